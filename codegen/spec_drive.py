"""The spec's drive sections, read and checked (called by `spec_loader`), and the
physics of the drive that the loader checks and the design uses.

Sections:

* `sensing`: the current-sensing topology (`dc_link_shunt` or `low_side_phase_shunts`),
  the ADC channels of the current shunt(s) and of the bus divider, the settling time of
  the shunt signal after a switching edge and the ADC sample time;
* `current_loop`: the bandwidth of the braking-current PI;
* `protection`: the over-current comparator's trip level on TIM1 BKIN and its polarity,
  the peak current the bridge may carry in an active short circuit, and the safe state
  where both all-off and the short circuit are valid;
* `firmware`: vector table or STM32Cube integration, the HSE start-up timeout, the
  independent watchdog's timeout and the budgets `make firmware` and `make bench` hold
  the image to.

The physics (one copy, used by the loader's checks and by codegen/control):

* `sense_window`: where in the PWM period the injected conversion samples the current
  and the largest duty whose OFF time still holds that sample away from every switching
  edge (RM0008 11.3.9 injected conversions, DS5319 Table 46 latency);
* `rectifying_speed`: above U_d / (lambda k_e) the bridge's diodes conduct with every
  switch off (lambda E is the peak line-to-line EMF: 2E for the 120 deg trapezoid),
  so all-off is no safe state there;
* `short_circuit_peak`: a bound on the phase current of an active short circuit
  (all lower switches on) at a speed, from the EMF's harmonics;
* `safe_state_corner`: the motor the safe state is chosen for, the worst one the spec
  declares: k_e at its upper tolerance, R and L at their lower ones, and a rotor up to
  `hall.sector_shortening` faster than the last Hall interval says;
* `braking_ripple` / `braking_current_peak`: the PWM ripple of the braking current
  and the largest instantaneous current steady braking makes above the current the
  loop samples, which the current sensing must read (ADC2's analog watchdog trips
  CURRENT_SENSOR on any conversion at a rail) and the comparator must let through.

Every error names the key path, the value, the unit and the allowed range.
"""

from __future__ import annotations

import bisect
import itertools
import math
from collections.abc import Mapping
from dataclasses import dataclass
from fractions import Fraction
from functools import lru_cache
from typing import Any, Protocol

from codegen import units
from codegen.errors import SpecError
from codegen.spec_model import (
    BackEmfShape,
    CurrentLoop,
    Firmware,
    Protection,
    Sensing,
)

SENSING_KEYS = (
    "topology",
    "current_channels",
    "bus_voltage_channel",
    "settling_time",
    "adc_sample_time",
)
CURRENT_LOOP_KEYS = ("bandwidth",)
PROTECTION_KEYS = ("over_current", "break_input", "short_circuit_current_max", "safe_state")
FIRMWARE_KEYS = (
    "integration",
    "hse_startup_timeout",
    "watchdog_timeout",
    "flash_budget",
    "ram_budget",
    "cpu_load_budget",
    "current_loop_budget",
)
#: PWM periods the watchdog's time-out must hold at least (main() refreshes it once a
#: period, after the current loop's run), on the slowest clock the PWM runs from.
WATCHDOG_PWM_PERIODS = 2
#: How much slower the PWM runs on the 8 MHz HSI than on the 72 MHz PLL: the clock the
#: firmware keeps where the HSE crystal never starts.
HSI_SLOWDOWN = 9
#: The HSE crystal's typical start-up time (DS5319 Table 22, t_SU(HSE)), seconds.
HSE_STARTUP_TYPICAL_S = 2e-3
SECTIONS = {
    "sensing": SENSING_KEYS,
    "current_loop": CURRENT_LOOP_KEYS,
    "protection": PROTECTION_KEYS,
    "firmware": FIRMWARE_KEYS,
}
TOPOLOGIES = ("dc_link_shunt", "low_side_phase_shunts")
#: ADC12_IN0..IN5 are PA0..PA5, IN9 is PB1. IN6, IN7 and IN8 (PA6, PA7, PB0) carry the
#: Hall inputs of TIM3 (DS5319 Table 5), so they cannot be analog inputs here.
ADC_CHANNELS = (0, 1, 2, 3, 4, 5, 9)
#: RM0008 ADC_SMPRx SMPx codes 000..111: sample time in ADC clock cycles.
ADC_SAMPLE_CYCLES: tuple[Fraction, ...] = tuple(
    Fraction(x) for x in ("1.5", "7.5", "13.5", "28.5", "41.5", "55.5", "71.5", "239.5")
)
#: The ADC clock: PCLK2 72 MHz / 6 (RCC_CFGR.ADCPRE = 10), within the 14 MHz maximum of
#: DS5319 Table 46. The port sets the prescaler.
ADC_CLOCK_HZ = Fraction(12_000_000)
ADC_PRESCALER = 6
#: RM0008 11.6: a conversion takes the sample time plus 12.5 ADC cycles.
ADC_CONVERSION_CYCLES = Fraction(25, 2)
#: DS5319 Table 46, t_latj: injected trigger to the start of sampling, at most 3 ADC cycles.
INJECTED_LATENCY_CYCLES = 3
#: DS5319 Table 47, ET: the ADC's total unadjusted error, +-2 LSB (typical): a steady
#: input may read this many codes either side of its own
ADC_ERROR_LSB = 2
#: The port converts four injected channels (JL = 3), so JSQx lands in JDRx (RM0008
#: 11.12.12): the current channel(s) first, the bus divider in the remaining slots.
INJECTED_CONVERSIONS = 4
BREAK_POLARITIES = ("active_low", "active_high")
#: The bus fault handler's path from its entry to MOE cleared, with its entry: 165
#: cycles on the paper motor's under-voltage path (`make bench`), 2.3 us at 72 MHz.
FAULT_PATH_ALLOWANCE_S = Fraction(5, 2_000_000)
SAFE_STATES = ("all_off", "short_circuit")
INTEGRATIONS = ("vector_table", "cube")
#: A loop delay of one PWM period costs 360 deg x f_c / f_pwm of phase margin: at
#: f_pwm / 10 the margin of the pole-zero cancelled loop is 90 - 36 = 54 deg.
BANDWIDTH_MAX_PER_PWM = Fraction(1, 10)
#: TIM1 and TIM3's clock in the generated clock tree (codegen/system_clock.py).
FIRMWARE_TIMER_CLOCK_HZ = Fraction(72_000_000)
#: Harmonics summed in the short-circuit bound (odd, not multiples of 3).
SHORT_CIRCUIT_HARMONICS = 999


class Reader(Protocol):
    """What `spec_loader._Reader` offers this module."""

    def section(self, data: Mapping[str, Any], key: str) -> Mapping[str, Any] | None: ...
    def only_keys(
        self,
        data: Mapping[Any, Any],
        allowed: tuple[str, ...],
        path: str,
        optional: tuple[str, ...] = (),
    ) -> None: ...
    def attempt(self, read: Any) -> Any: ...
    def raw(self, data: Mapping[str, Any], key: str, path: str, allowed: str = "") -> Any: ...
    def error(self, path: str, value: object, problem: str, allowed: str = "") -> SpecError: ...
    def report(self, path: str, value: object, problem: str, allowed: str = "") -> None: ...
    def warn(self, warning_id: str, path: str, value: object, message: str) -> None: ...
    def quantity(
        self, data: Mapping[str, Any], key: str, path: str, dim: units.Dimension, rng: Any
    ) -> Fraction: ...
    def number(self, data: Mapping[str, Any], key: str, path: str, rng: Any) -> Fraction: ...
    def integer(self, data: Mapping[str, Any], key: str, path: str, rng: Any) -> int: ...
    def choice(
        self, data: Mapping[str, Any], key: str, path: str, options: tuple[str, ...]
    ) -> str: ...


def _g(value: Fraction | float | int) -> str:
    return f"{float(value):g}"


# ------------------------------------------------------------------ readers


def read_sensing(r: Reader, data: Mapping[str, Any], rng: Any) -> Sensing | None:
    sec = r.section(data, "sensing")
    if sec is None:
        return None
    r.only_keys(sec, SENSING_KEYS, "sensing")
    topology = r.attempt(lambda: r.choice(sec, "topology", "sensing", TOPOLOGIES))
    channels_allowed = f"ADC12_IN channels {', '.join(map(str, ADC_CHANNELS))}"

    def channel(value: object, path: str) -> int:
        if isinstance(value, bool) or not isinstance(value, int) or value not in ADC_CHANNELS:
            raise r.error(
                path,
                value,
                "not an ADC input the port can use (IN6, IN7 and IN8 are the Hall pins"
                " PA6, PA7 and PB0)",
                channels_allowed,
            )
        return value

    def current_channels() -> tuple[int, ...]:
        wanted = {"dc_link_shunt": 1, "low_side_phase_shunts": 3}.get(str(topology), 0)
        allowed = (
            f"a list of {wanted} distinct channels ({channels_allowed})"
            if wanted
            else channels_allowed
        )
        raw = r.raw(sec, "current_channels", "sensing", allowed)
        if not isinstance(raw, list) or (wanted and len(raw) != wanted):
            raise r.error(
                "sensing.current_channels",
                raw,
                f"topology {topology} needs {wanted} current channel(s)"
                + (": phases A, B, C in that order" if wanted == 3 else ""),
                allowed,
            )
        out = tuple(channel(v, f"sensing.current_channels[{i}]") for i, v in enumerate(raw))
        if len(set(out)) != len(out):
            raise r.error("sensing.current_channels", raw, "channels repeat", allowed)
        return out

    currents = r.attempt(current_channels) if topology is not None else None
    bus = r.attempt(
        lambda: channel(
            r.raw(sec, "bus_voltage_channel", "sensing", channels_allowed),
            "sensing.bus_voltage_channel",
        )
    )
    if bus is not None and currents is not None and bus in currents:
        r.report(
            "sensing.bus_voltage_channel",
            bus,
            "is also a current channel",
            f"a channel other than {', '.join(map(str, currents))}",
        )
        bus = None
    settle = r.attempt(
        lambda: r.quantity(
            sec,
            "settling_time",
            "sensing",
            units.TIME,
            rng(0.0, 10e-6, "s", low_inclusive=False),
        )
    )

    def sample_time() -> Fraction:
        allowed = ", ".join(_g(c) for c in ADC_SAMPLE_CYCLES) + " ADC clock cycles"
        raw = r.raw(sec, "adc_sample_time", "sensing", allowed)
        exact = getattr(raw, "exact", None)
        value = exact if exact is not None else raw
        if isinstance(raw, bool) or not isinstance(raw, int | float):
            raise r.error("sensing.adc_sample_time", raw, "must be a plain number", allowed)
        if isinstance(value, float) and not math.isfinite(value):
            raise r.error("sensing.adc_sample_time", raw, "must be a finite number", allowed)
        if Fraction(value) not in ADC_SAMPLE_CYCLES:
            raise r.error(
                "sensing.adc_sample_time",
                raw,
                "not a sample time of RM0008 ADC_SMPRx",
                allowed,
            )
        return Fraction(value)

    cycles = r.attempt(sample_time)
    if None in (topology, currents, bus, settle, cycles):
        return None
    return Sensing(
        topology=topology,
        current_channels=currents,
        bus_voltage_channel=bus,
        settling_time_s=settle,
        adc_sample_cycles=cycles,
    )


def read_current_loop(r: Reader, data: Mapping[str, Any], rng: Any) -> CurrentLoop | None:
    sec = r.section(data, "current_loop")
    if sec is None:
        return None
    r.only_keys(sec, CURRENT_LOOP_KEYS, "current_loop")
    bandwidth = r.attempt(
        lambda: r.quantity(sec, "bandwidth", "current_loop", units.FREQUENCY, rng(1.0, 20e3, "Hz"))
    )
    return None if bandwidth is None else CurrentLoop(bandwidth_hz=bandwidth)


#: The largest current a protection entry may name (A): a bridge's pulsed rating beyond
#: 10 kA is no longer a board this firmware drives.
PROTECTION_AMPS_MAX = 10_000


def read_protection(r: Reader, data: Mapping[str, Any], rng: Any) -> Protection | None:
    sec = r.section(data, "protection")
    if sec is None:
        return None
    r.only_keys(sec, PROTECTION_KEYS, "protection")
    amps = rng(0.0, float(PROTECTION_AMPS_MAX), "A", low_inclusive=False)
    over = r.attempt(lambda: r.quantity(sec, "over_current", "protection", units.CURRENT, amps))
    polarity = r.attempt(lambda: r.choice(sec, "break_input", "protection", BREAK_POLARITIES))
    short = r.attempt(
        lambda: r.quantity(sec, "short_circuit_current_max", "protection", units.CURRENT, amps)
    )
    policy = r.attempt(lambda: r.choice(sec, "safe_state", "protection", SAFE_STATES))
    if None in (over, polarity, short, policy):
        return None
    return Protection(
        over_current_a=over,
        break_polarity=polarity,
        short_circuit_current_max_a=short,
        safe_state=policy,
    )


def read_firmware(r: Reader, data: Mapping[str, Any], rng: Any) -> Firmware | None:
    sec = r.section(data, "firmware")
    if sec is None:
        return None
    r.only_keys(sec, FIRMWARE_KEYS, "firmware")
    integration = r.attempt(lambda: r.choice(sec, "integration", "firmware", INTEGRATIONS))
    # The 8 MHz crystal starts in 2 ms typically (DS5319 Table 22, t_SU(HSE)): a shorter
    # timeout latches BLDC_FAULT_CLOCK at every start on a typical part, and the bridge
    # never arms (a 100 us timeout did, in `make pil`).
    hse = r.attempt(
        lambda: r.quantity(
            sec,
            "hse_startup_timeout",
            "firmware",
            units.TIME,
            rng(HSE_STARTUP_TYPICAL_S, 1.0, "s (at least the HSE crystal's typical start-up)"),
        )
    )
    # The IWDG counts the LSI (30..60 kHz, DS5319 Table 30) through a prescaler of 4..256
    # into a 12-bit reload: 4 / 60 kHz = 67 us at the shortest, 4096 x 256 / 30 kHz =
    # 35 s at the longest. The firmware refreshes it once per PWM period at most.
    wdg = r.attempt(
        lambda: r.quantity(sec, "watchdog_timeout", "firmware", units.TIME, rng(1e-3, 10.0, "s"))
    )
    flash = r.attempt(lambda: r.integer(sec, "flash_budget", "firmware", rng(1024, 65536, "bytes")))
    ram = r.attempt(lambda: r.integer(sec, "ram_budget", "firmware", rng(128, 20480, "bytes")))
    load = r.attempt(
        lambda: r.number(
            sec, "cpu_load_budget", "firmware", rng(0.0, 100.0, "percent", low_inclusive=False)
        )
    )
    loop = r.attempt(
        lambda: r.integer(sec, "current_loop_budget", "firmware", rng(40, 100_000, "cycles"))
    )
    if None in (integration, hse, wdg, flash, ram, load, loop):
        return None
    return Firmware(
        integration=integration,
        hse_startup_timeout_s=hse,
        watchdog_timeout_s=wdg,
        flash_budget_bytes=flash,
        ram_budget_bytes=ram,
        cpu_load_budget_percent=load,
        current_loop_budget_cycles=loop,
    )


# ------------------------------------------------------------------ physics


@dataclass(frozen=True)
class SenseWindow:
    """When the injected sequence samples the current, in TIM1 counts, and the largest
    steady duty that leaves that sample clear of every switching edge.

    Edge-aligned (PWM mode 1: a switch is ON while CNT < D): the period is P counts, OFF
    from D to P. The trigger (TIM1 OC4REF in PWM mode 2, rising at CNT = CCR4) is placed
    so that the last current sample ends one count before the next period's turn-on
    edge; D_max keeps `guard` counts between the turn-off edge and the trigger.

    Centre-aligned (the counter runs 0 -> P -> 0): OFF is centred on the peak, from D
    counting up to D counting down. The trigger is the peak itself: OC4REF in PWM mode 1
    with CCR4 = ARR - 1 is inactive at CNT = ARR - 1 counting up and at ARR, and rises
    one count after the peak, at ARR - 1 counting down (RM0008 14.4.7 OC1M: counting
    down, inactive while CNT > CCRx; CCR4 = ARR would hold OC4REF at 1, no trigger at
    all); D_max keeps `guard` counts between the turn-off edge and the peak and ends the
    samples one count before the turn-on edge.
    """

    alignment: str
    period_counts: int  # P: duty full scale
    trigger_counts: int  # CCR4
    trigger_time_counts: int  # timer counts from the period start to the trigger edge
    span_counts: int  # trigger to the end of the last current sample (latency included)
    guard_counts: int  # after a switching edge: dead time + settling time
    duty_max_counts: int
    current_samples: int  # current conversions before the bus ones
    #: each current channel's sampling interval, timer counts from the period start
    #: (exact: ADC cycles converted to timer counts)
    windows: tuple[tuple[Fraction, Fraction], ...]


def _ceil(x: Fraction) -> int:
    return -((-x.numerator) // x.denominator)


def sense_window(
    *,
    alignment: str,
    period_counts: int,
    timer_clock_hz: Fraction,
    dead_time_counts: int,
    settling_time_s: Fraction,
    adc_sample_cycles: Fraction,
    current_samples: int,
) -> SenseWindow:
    """The sample point and D_max (see SenseWindow). `dead_time_counts` is the dead time
    TIM1 is programmed with (the loader passes the requested one rounded up)."""
    per_adc_cycle = Fraction(timer_clock_hz) / ADC_CLOCK_HZ  # timer counts per ADC cycle
    conversion = adc_sample_cycles + ADC_CONVERSION_CYCLES
    windows = []
    for k in range(current_samples):
        start = (INJECTED_LATENCY_CYCLES + k * conversion) * per_adc_cycle
        windows.append((start, start + adc_sample_cycles * per_adc_cycle))
    span = _ceil(windows[-1][1])
    guard = dead_time_counts + _ceil(settling_time_s * timer_clock_hz)
    p = period_counts
    if alignment == "edge":
        trigger = p - 1 - span
        trigger_time = trigger
        duty_max = trigger - guard
    else:
        trigger = p - 1
        trigger_time = p + 1
        duty_max = min(p - 1 - span - 1, trigger_time - guard)
    shifted = tuple((trigger_time + a, trigger_time + b) for a, b in windows)
    return SenseWindow(
        alignment=alignment,
        period_counts=p,
        trigger_counts=trigger,
        trigger_time_counts=trigger_time,
        span_counts=span,
        guard_counts=guard,
        duty_max_counts=duty_max,
        current_samples=current_samples,
        windows=shifted,
    )


def injected_conversions_s(adc_sample_cycles: Fraction) -> Fraction:
    """Seconds the INJECTED_CONVERSIONS conversions of an injected sequence take: from
    its trigger to JEOC at the least (DS5319 gives only the largest injection latency)."""
    return (
        INJECTED_CONVERSIONS * (Fraction(adc_sample_cycles) + ADC_CONVERSION_CYCLES) / ADC_CLOCK_HZ
    )


def injected_sequence_s(adc_sample_cycles: Fraction) -> Fraction:
    """Seconds from an injected trigger to JEOC at the most: the latency and
    INJECTED_CONVERSIONS conversions."""
    return INJECTED_LATENCY_CYCLES / ADC_CLOCK_HZ + injected_conversions_s(adc_sample_cycles)


#: PWM periods the 60 deg sector at the top speed holds at the least for a braking the
#: current loop holds steady. The port computes the next edge's timing at the COM
#: events, from the loop's state before the previous edge; with few loop samples a
#: sector that state is stale and the braking locked into a two-sector cycle (make pil,
#: odd and even edges at 0.22-3.16 A and 1.41-3.34 A of a 3 A command). Measured with
#: the PWM frequency alone varied: a 1-pole-pair improved_r motor failed at 3.52
#: periods, passed at 3.76 with its duty moving 0.457 of the 0.485 allowed between
#: edges and at 4.23 with 0.224; an improved one failed at 2.81 and passed from 3.16
#: (0.176); conventional ones passed from 2.19. `init` derives no faster top speed; the
#: loader warns (few-pwm-periods-per-sector) where a spec's is.
STEADY_SECTOR_PWM_PERIODS = Fraction(9, 2)


#: The share of a sector init lets a commutation at braking_current_max take where
#: 4E <= U_d (`improved_commutation_share`): the rest of it, at least half, holds the
#: loop's samples of the held current.
INIT_COMMUTATION_SHARE = Fraction(1, 2)


def improved_commutation_share(
    current_a: Fraction, inductance_h: Fraction, pole_pairs: int, k_e_v_per_rpm: Fraction
) -> Fraction:
    """The share of a 60 deg sector an improved commutation of `current_a` lasts wherever
    4E <= U_d, the same at every such speed: Eq. 18's low-speed pair (D_on = 1,
    D_off = 1 - 4E/U_d) in Eq. 20 gives t_com = 3 I L / 6E = I L / (2E), and a sector
    lasts 10 / (p n) s, so t_com / T_s = I L p / (20 k_e). Above 4E = U_d the commutation
    is longer still (I L / (U_d - 2E)). The resistance-aware rule holds about the same pair
    (its R I terms shorten it a little). From 1 on, a commutation at this current never
    ends within its sector: it is cut at the end's guard (TIME_CLAMPED) with its outgoing
    current still flowing, at every speed."""
    return current_a * inductance_h * pole_pairs / (20 * k_e_v_per_rpm)


def end_sample_room_s(pwm_frequency_hz: Fraction, adc_sample_cycles: Fraction) -> Fraction:
    """Seconds a commutation's end leaves before the next Hall edge for one current
    sample (part of the end's guard, `codegen.dead_time.commutation_guard_ticks`): the
    end restarts the carrier, the loop's trigger comes within one PWM period whatever
    the alignment, and the injected sequence ends before JEOC runs the loop."""
    return 1 / Fraction(pwm_frequency_hz) + injected_sequence_s(adc_sample_cycles)


def bus_fault_detection_s(adc_sample_cycles: Fraction, current_samples: int) -> Fraction:
    """Seconds from a bus step to the analog watchdog's flag, at worst: the bus channel
    sampled just before the step, then either the injected sequence (its latency and
    INJECTED_CONVERSIONS conversions, the bus in its last slots) or the conversion in
    flight, the current channel(s) of a sequence that starts meanwhile and the next bus
    conversion (regular or injected; both are watched)."""
    conversions = max(INJECTED_CONVERSIONS, current_samples + 2)
    cycles = INJECTED_LATENCY_CYCLES + conversions * (
        Fraction(adc_sample_cycles) + ADC_CONVERSION_CYCLES
    )
    return cycles / ADC_CLOCK_HZ


def current_samples(topology: str) -> int:
    """Current conversions at the head of the injected sequence: the DC-link shunt, or
    the three phase shunts (A, B, C)."""
    return 1 if topology == "dc_link_shunt" else 3


@lru_cache(maxsize=64)
def _angles(shape: BackEmfShape) -> tuple[Fraction, ...]:
    return tuple(Fraction(a) for a, _ in shape.points)


def emf_at(shape: BackEmfShape, degrees: Fraction) -> Fraction:
    """e/E of one phase at an electrical angle from its rising zero crossing (the
    half-wave symmetric extension of the shape: e(theta + 180) = -e(theta)). The
    segment is found by bisection: the table's angles rise strictly from 0 to 180 (the
    loader's check), and a scan per angle made the whole-table evaluations quadratic (a
    3001-point measured table: `generate` took 150 s)."""
    angle = Fraction(degrees) % 360
    sign = 1
    if angle >= 180:
        angle -= 180
        sign = -1
    points = shape.points
    angles = _angles(shape)
    k = bisect.bisect_left(angles, angle)
    if k >= len(points):
        raise ValueError(f"angle {angle} outside the shape")
    if k == 0 or angles[k] == angle:
        return sign * points[k][1]
    (a0, e0), (a1, e1) = points[k - 1], points[k]
    return sign * (e0 + (e1 - e0) * (angle - a0) / (a1 - a0))


@lru_cache(maxsize=64)
def line_to_line_peak(shape: BackEmfShape) -> Fraction:
    """lambda: the peak line-to-line EMF e_a - e_b (b lags a by 120 deg) per unit of E,
    found exactly at the breakpoints of both (the difference is piecewise linear)."""
    breaks = {Fraction(a) for a, _ in shape.points} | {Fraction(a) + 180 for a, _ in shape.points}
    angles = breaks | {(b + 120) % 360 for b in breaks}
    return max(abs(emf_at(shape, a) - emf_at(shape, a - 120)) for a in angles)


@lru_cache(maxsize=64)
def conducting_line_mean(shape: BackEmfShape) -> Fraction:
    """The mean over a 60 deg sector of the conducting pair's line-to-line EMF, per unit
    of 2E: what the two phases in series oppose to the bus between commutations on the
    PWM average (phase a's sector [30, 90] deg from its rising zero crossing, with b
    lagging by 120 deg; every sector alike by symmetry). 1 for the 120 deg trapezoid and
    the paper's flat EMF; exact (the difference is piecewise linear, integrated between
    its breakpoints)."""
    low, high = Fraction(30), Fraction(90)
    breaks = {Fraction(a) for a, _ in shape.points}
    breaks |= {b + 180 for b in breaks} | {b - 180 for b in breaks}
    cuts = sorted(
        {low, high}
        | {b for b in breaks if low < b < high}
        | {b + 120 for b in breaks if low < b + 120 < high}
    )

    def line(angle: Fraction) -> Fraction:
        return emf_at(shape, angle) - emf_at(shape, angle - 120)

    area = sum((b - a) * (line(a) + line(b)) / 2 for a, b in itertools.pairwise(cuts))
    return Fraction(area) / (high - low) / 2


@dataclass(frozen=True)
class SafeStateCorner:
    """The worst motor of the spec's declared ranges for the safe state: the k_e that
    rectifies soonest, the R and L that make the short circuit's current largest, and
    the factor by which the rotor may be faster than its last Hall interval says (a
    sector up to `hall.sector_shortening` shorter: 1 / (1 - s)). Without a
    `tolerances` section, the nominal motor."""

    k_e: Fraction
    resistance_ohm: Fraction
    inductance_h: Fraction
    speed_factor: Fraction


def said_speed_factor(sector_shortening: Fraction) -> Fraction:
    """How much faster than its last Hall interval says a rotor may run: a sector up to
    `sector_shortening` shorter than the one measured, 1 / (1 - s)."""
    return 1 / (1 - sector_shortening)


def safe_state_corner(motor: Any, hall: Any, tolerances: Any) -> SafeStateCorner:
    """The safe state's worst corner (`SafeStateCorner`). The nominal boundary had let
    all-off be chosen 1.2 % below it on a 22.7 V bus while the paper motor with its k_e
    10 % high, inside its own tolerances, rectified 2.8 A into the bus (a hunt)."""
    k_e_high, r_low, l_low = Fraction(0), Fraction(0), Fraction(0)
    if tolerances is not None:
        k_e_high = max(Fraction(0), tolerances.back_emf_constant[1])
        r_low = min(Fraction(0), tolerances.phase_resistance[0])
        l_low = min(Fraction(0), tolerances.phase_inductance[0])
    return SafeStateCorner(
        k_e=motor.back_emf_constant_v_per_rpm * (1 + k_e_high),
        resistance_ohm=motor.phase_resistance_ohm * (1 + r_low),
        inductance_h=motor.phase_inductance_h * (1 + l_low),
        speed_factor=said_speed_factor(hall.sector_shortening),
    )


def corner_short_peak(motor: Any, corner: SafeStateCorner, entry_a: Fraction, rpm: float) -> float:
    """`short_circuit_peak` of the worst motor (`corner`) at `rpm`, entered with the
    over-current trip's `entry_a` flowing."""
    return short_circuit_peak(
        speed_rpm=rpm,
        k_e=float(corner.k_e),
        pole_pairs=motor.pole_pairs,
        resistance_ohm=float(corner.resistance_ohm),
        inductance_h=float(corner.inductance_h),
        shape=motor.back_emf_shape,
        current_at_entry_a=float(entry_a),
    )


def rectifying_speed(bus_voltage_v: Fraction, k_e: Fraction, shape: BackEmfShape) -> Fraction:
    """The speed (rpm) above which the bridge's diodes conduct with every switch off:
    the peak line-to-line EMF lambda k_e n reaches the bus voltage."""
    return Fraction(bus_voltage_v) / (line_to_line_peak(shape) * k_e)


@lru_cache(maxsize=64)
def _radian_points(shape: BackEmfShape) -> tuple[tuple[float, float], ...]:
    return tuple((math.radians(float(a)), float(e)) for a, e in shape.points)


@lru_cache(maxsize=4096)
def emf_harmonic(shape: BackEmfShape, h: int) -> float:
    """b_h of the per-unit phase EMF (odd h; half-wave symmetry makes the even ones 0):
    (2/pi) times the integral of e sin(h theta) over the half period, segment by segment
    in closed form. Kept per shape and h: the short-circuit bound sums hundreds of them
    at each speed it checks, for every spec loaded."""
    total = 0.0
    points = _radian_points(shape)
    for (t0, e0), (t1, e1) in itertools.pairwise(points):
        if t1 == t0:
            continue
        slope = (e1 - e0) / (t1 - t0)
        total += -(e1 * math.cos(h * t1) - e0 * math.cos(h * t0)) / h
        total += slope * (math.sin(h * t1) - math.sin(h * t0)) / (h * h)
    return 2.0 / math.pi * total


#: A ripple (peak to peak) above this fraction of braking_current_nominal is warned of
RIPPLE_WARN_FRACTION = Fraction(1, 2)
#: The comparator's trip is warned of where it leaves less than this fraction of
#: braking_current_max above the steady peak (the command plus the PWM ripple): the
#: loop's recovery from each commutation and the commutation itself carry the current
#: past the steady peak (a hunt's 48 V motor, 0.5 mH, 16 kHz, its commutations 75 % of
#: the sector at 3850 rpm: braking 9 A, whose steady peak is 9.9 A, it reached 11.0 A,
#: 12 % of the command above it, and tripped its 11 A comparator)
OVER_CURRENT_MARGIN_FRACTION = Fraction(1, 4)


@dataclass(frozen=True)
class BrakingRipple:
    """The braking current's PWM ripple at its worst and what it adds to the peak.

    Between commutations two phases conduct in series (2L, 2R) against their EMFs 2E.
    ON (the modulated switch closed) the bridge shorts them and the current rises at
    (2E - 2RI)/(2L); OFF it flows into the bus and falls at (U_d - 2E + 2RI)/(2L). In
    the steady state (1 - D) U_d = 2E - 2RI = y, so the peak-to-peak ripple is
    D (1 - D) U_d T / (2L) = y (U_d - y) T / (2 L U_d): largest at y = U_d/2 when the
    speed range reaches it, and growing with U_d (the largest bus voltage). The loop
    samples in the OFF time (codegen/control/sensing.py): at its end with edge-aligned
    PWM, the ripple's valley, so the current peaks a whole ripple above what the loop
    holds; at its centre with centre-aligned PWM, the mean, half a ripple below."""

    ripple_a: Fraction  # peak to peak, at the worst y in the speed range
    above_sample: Fraction  # the peak's rise above the sampled current
    bus_v: Fraction
    y_v: Fraction  # 2E - 2RI at the worst point


def braking_ripple(
    *,
    bus_voltage_max_v: Fraction,
    pwm_frequency_hz: Fraction,
    phase_inductance_h: Fraction,
    k_e_v_per_rpm: Fraction,
    phase_resistance_ohm: Fraction,
    speed_min_rpm: Fraction,
    speed_max_rpm: Fraction,
    current_max_a: Fraction,
    alignment: str,
) -> BrakingRipple:
    """The worst ripple over speed_min..speed_max and currents 0..current_max (exact)."""
    u = bus_voltage_max_v
    low = max(
        Fraction(0), 2 * (k_e_v_per_rpm * speed_min_rpm - phase_resistance_ohm * current_max_a)
    )
    high = min(u, 2 * k_e_v_per_rpm * speed_max_rpm)
    y = min(max(u / 2, low), high) if low <= high else high
    ripple = y * (u - y) / (pwm_frequency_hz * 2 * phase_inductance_h * u)
    above = ripple if alignment == "edge" else ripple / 2
    return BrakingRipple(ripple, above, u, y)


def braking_current_peak(current_a: Fraction, ripple: BrakingRipple) -> Fraction:
    """The largest instantaneous current while the loop holds `current_a`."""
    return current_a + ripple.above_sample


def short_circuit_peak(
    *,
    speed_rpm: float,
    k_e: float,
    pole_pairs: int,
    resistance_ohm: float,
    inductance_h: float,
    shape: BackEmfShape,
    current_at_entry_a: float,
) -> float:
    """A bound on the peak phase current after every lower switch closes at this speed.

    In steady state each harmonic h of the phase EMF (odd, not a multiple of 3: those
    are in phase in all three phases and drive no current with the star point open)
    drives b_h E / |R + j h w L|; their moduli summed bound the peak. Entering the short
    adds a transient that decays with L/R and starts from the difference between the
    current at entry and the steady current there: at most the steady peak plus
    `current_at_entry_a` (the over-current trip). Bound: 2 x steady + entry."""
    e = k_e * speed_rpm
    omega = 2 * math.pi * pole_pairs * speed_rpm / 60
    steady = 0.0
    for h in range(1, SHORT_CIRCUIT_HARMONICS + 1, 2):
        if h % 3 == 0:
            continue
        b = abs(emf_harmonic(shape, h))
        steady += b * e / math.hypot(resistance_ohm, h * omega * inductance_h)
    return 2 * steady + current_at_entry_a


# ------------------------------------------------------------------ checks


def check_drive(
    r: Reader,
    data: Mapping[str, Any],
    *,
    motor: Any,
    hall: Any,
    tolerances: Any,
    inverter: Any,
    adc: Any,
    controller: Any,
    points: Any,
    sensing: Sensing,
    current_loop: CurrentLoop,
    protection: Protection,
    firmware: Firmware,
) -> None:
    """Cross-key physics of the drive sections: exact arithmetic, floats in messages."""

    def raw(path: str) -> object:
        section, _, key = path.partition(".")
        return data[section][key]

    # The clock tree the firmware sets up: HSE 8 MHz x 9 = 72 MHz, APB2 / 1 (TIM1),
    # APB1 / 2 whose timers run at twice it (TIM3): both timers at 72 MHz.
    if inverter.timer_clock_hz != FIRMWARE_TIMER_CLOCK_HZ:
        r.report(
            "inverter.timer_clock",
            raw("inverter.timer_clock"),
            "the generated firmware's clock tree (HSE 8 MHz x 9 = 72 MHz, APB2 / 1) runs TIM1"
            " at 72 MHz",
            "72 MHz",
        )
        return
    # The current loop: a one-period delay must leave phase margin.
    f_pwm = inverter.pwm_frequency_hz
    if current_loop.bandwidth_hz > BANDWIDTH_MAX_PER_PWM * f_pwm:
        r.report(
            "current_loop.bandwidth",
            raw("current_loop.bandwidth"),
            f"above f_pwm / 10 = {_g(f_pwm / 10)} Hz: the duty computed from one period's"
            " sample applies in the next, a delay that costs 360 deg x f_c / f_pwm of phase"
            " margin",
            f"<= {_g(f_pwm / 10)} Hz",
        )
    # main() refreshes the watchdog after a current-loop run, once a PWM period: the
    # time-out (at the fastest LSI, as the firmware sets it) must hold two periods, the
    # period and the wait for main's turn, on the clock the PWM may run from: the HSI
    # where the crystal never starts (BLDC_FAULT_CLOCK), 9 times slower than the PLL
    # (a 1 ms time-out at 1125 Hz starved it in `make pil`, and 1.8 ms did on the HSI).
    hsi_period = HSI_SLOWDOWN / f_pwm
    shortest = WATCHDOG_PWM_PERIODS * hsi_period
    if firmware.watchdog_timeout_s < shortest:
        r.report(
            "firmware.watchdog_timeout",
            raw("firmware.watchdog_timeout"),
            "main() refreshes the watchdog once a PWM period, after the current loop's run;"
            " on the 8 MHz HSI, where a crystal that never starts leaves the clock"
            f" (BLDC_FAULT_CLOCK), a period takes {_g(hsi_period)} s: a time-out under"
            f" {WATCHDOG_PWM_PERIODS} of them starves the watchdog and the chip resets",
            f">= {_g(shortest)} s at {_g(f_pwm)} Hz",
        )
    # The sample window.
    centre = inverter.pwm_alignment == "center"
    period = inverter.timer_clock_hz / f_pwm / (2 if centre else 1)
    window = sense_window(
        alignment=inverter.pwm_alignment,
        period_counts=int(period),
        timer_clock_hz=inverter.timer_clock_hz,
        dead_time_counts=_ceil(inverter.dead_time_s * inverter.timer_clock_hz),
        settling_time_s=sensing.settling_time_s,
        adc_sample_cycles=sensing.adc_sample_cycles,
        current_samples=current_samples(sensing.topology),
    )
    # A bus fault's safe state within one PWM period: the watchdog's worst detection
    # (which also bounds the injected sequence: it must end before the next trigger, or
    # the ADC drops that trigger and the loop its period) and the handler's path to MOE;
    # where the sample window leaves too little duty (below), that names the sample time.
    samples = current_samples(sensing.topology)
    fault_s = bus_fault_detection_s(sensing.adc_sample_cycles, samples) + FAULT_PATH_ALLOWANCE_S
    if fault_s > 1 / f_pwm and window.duty_max_counts >= int(period) // 4:
        fitting = [
            c
            for c in ADC_SAMPLE_CYCLES
            if bus_fault_detection_s(c, samples) + FAULT_PATH_ALLOWANCE_S <= 1 / f_pwm
        ]
        problem = (
            f"a bus fault is seen at worst {_g(fault_s * 10**6)} us after it comes (the injected"
            f" sequence of {INJECTED_CONVERSIONS} conversions or the current sample(s) and two"
            f" bus conversions of {_g(sensing.adc_sample_cycles)} + 12.5 ADC cycles at"
            " 12 MHz, and the handler's path to MOE): beyond the PWM period of"
            f" {_g(10**6 / f_pwm)} us, within which the safe state must be reached"
        )
        if fitting:
            r.report(
                "sensing.adc_sample_time",
                raw("sensing.adc_sample_time"),
                problem,
                f"<= {_g(max(fitting))} ADC clock cycles at inverter.pwm_frequency {_g(f_pwm)} Hz",
            )
        else:
            fastest = 1 / (
                bus_fault_detection_s(ADC_SAMPLE_CYCLES[0], samples) + FAULT_PATH_ALLOWANCE_S
            )
            r.report(
                "inverter.pwm_frequency",
                raw("inverter.pwm_frequency"),
                problem,
                f"<= {_g(fastest)} Hz (the shortest sample time, 1.5 ADC cycles)",
            )
    if window.duty_max_counts < int(period) // 4:
        # the key to change: the ADC's sample time where a shorter one leaves the 25 %
        # (a 239.5-cycle sample was reported under the settling time), else the settling
        fitting = [
            c
            for c in ADC_SAMPLE_CYCLES
            if sense_window(
                alignment=inverter.pwm_alignment,
                period_counts=int(period),
                timer_clock_hz=inverter.timer_clock_hz,
                dead_time_counts=_ceil(inverter.dead_time_s * inverter.timer_clock_hz),
                settling_time_s=sensing.settling_time_s,
                adc_sample_cycles=c,
                current_samples=current_samples(sensing.topology),
            ).duty_max_counts
            >= int(period) // 4
        ]
        problem = (
            f"with the dead time and the ADC's {_g(sensing.adc_sample_cycles)}-cycle samples"
            f" the current sample needs {window.span_counts + window.guard_counts} of the"
            f" {int(period)} TIM1 counts of a period, leaving a largest braking duty of"
            f" {window.duty_max_counts} counts"
        )
        if fitting:
            r.report(
                "sensing.adc_sample_time",
                raw("sensing.adc_sample_time"),
                problem,
                f"<= {_g(max(fitting))} ADC clock cycles at sensing.settling_time"
                f" {_g(sensing.settling_time_s)} s (a sample window that leaves a duty of at"
                " least 25 %)",
            )
        else:
            r.report(
                "sensing.settling_time",
                raw("sensing.settling_time"),
                problem,
                "a sample window that leaves a duty of at least 25 %",
            )
    else:
        d_max = Fraction(window.duty_max_counts, int(period))
        u_d = inverter.bus_voltage_nominal_v
        r_ohm = motor.phase_resistance_ohm
        i_nom = controller.braking_current_nominal_a
        for index, point in enumerate(points):
            # Steady braking (averaged over a PWM period): (1 - D) U_d = 2E - 2 R I.
            needed = (
                1
                - (2 * motor.back_emf_constant_v_per_rpm * point.speed_rpm - 2 * r_ohm * i_nom)
                / u_d
            )
            if needed > d_max:
                r.warn(
                    "current-sense-window",
                    f"operating_points[{index}].speed",
                    data["operating_points"][index]["speed"],
                    f"holding braking_current_nominal = {_g(i_nom)} A here needs a duty of"
                    f" {float(needed):.3f}, above the {float(d_max):.3f} the current sample"
                    " window leaves: the loop saturates there",
                )

    # The PWM ripple: what the current reaches above the sample the loop holds.
    def ripple_up_to(current_a: Fraction) -> BrakingRipple:
        return braking_ripple(
            bus_voltage_max_v=inverter.bus_voltage_max_v,
            pwm_frequency_hz=f_pwm,
            phase_inductance_h=motor.phase_inductance_h,
            k_e_v_per_rpm=motor.back_emf_constant_v_per_rpm,
            phase_resistance_ohm=motor.phase_resistance_ohm,
            speed_min_rpm=controller.speed_min_rpm,
            speed_max_rpm=controller.speed_max_rpm,
            current_max_a=current_a,
            alignment=inverter.pwm_alignment,
        )

    ripple = ripple_up_to(controller.braking_current_max_a)
    peak = braking_current_peak(controller.braking_current_max_a, ripple)
    sampled = (
        "its mean, sampled at the centre of the OFF time"
        if centre
        else "its valley, sampled at the end of the OFF time"
    )
    why = (
        f"braking_current_max {_g(controller.braking_current_max_a)} A ({sampled}) +"
        f" {float(ripple.above_sample):.4g} A of PWM ripple ({float(ripple.ripple_a):.4g} A"
        f" peak to peak at {_g(f_pwm)} Hz through 2 x {_g(motor.phase_inductance_h)} H,"
        f" bus_voltage_max {_g(ripple.bus_v)} V) = {float(peak):.4g} A"
    )
    # The sensing chain must read every current steady braking makes: ADC2 watches the
    # current channel(s) continuously and a conversion at a rail is CURRENT_SENSOR.
    offset, reference = adc.current_offset_v, adc.reference_v
    if offset < reference and (reference - offset) / adc.current_gain_v_per_a < peak:
        r.report(
            "adc.current_gain",
            raw("adc.current_gain"),
            f"reads at most (reference - offset) / gain ="
            f" {float((reference - offset) / adc.current_gain_v_per_a):.4g} A, but braking"
            f" peaks at {why}: ADC2's watchdog would read the rail (CURRENT_SENSOR) in normal"
            " braking; lower the gain, or raise the PWM frequency or the inductance",
            f"<= {float((reference - offset) / peak * 1000):.4g} mV/A",
        )
    # The averaged model of Eqs. 13-20 takes I as constant over a PWM period.
    nominal = controller.braking_current_nominal_a
    at_nominal = ripple_up_to(nominal)
    if at_nominal.ripple_a > nominal * RIPPLE_WARN_FRACTION:
        r.warn(
            "pwm-ripple-large",
            "motor.phase_inductance",
            raw("motor.phase_inductance"),
            f"the braking current ripples by up to {float(at_nominal.ripple_a):.4g} A peak to"
            f" peak (D(1 - D) U_d T / (2L) at bus_voltage_max {_g(at_nominal.bus_v)} V),"
            f" {float(at_nominal.ripple_a / nominal) * 100:.0f} % of braking_current_nominal"
            f" {_g(nominal)} A: the duty-cycle model of Eqs. 13-20 takes I as constant over a"
            " PWM period, so expect the commutations to deviate from it; raise the PWM"
            " frequency or the inductance",
        )
    # Protection: the comparator must not trip in normal braking.
    if protection.over_current_a <= peak:
        r.report(
            "protection.over_current",
            raw("protection.over_current"),
            f"at or below the braking current's peak, {why}: normal braking would trip it",
            f"> {float(peak):.4g} A",
        )
        return
    margin = OVER_CURRENT_MARGIN_FRACTION * controller.braking_current_max_a
    if protection.over_current_a < peak + margin:
        r.warn(
            "over-current-margin-small",
            "protection.over_current",
            raw("protection.over_current"),
            f"{float(protection.over_current_a - peak):.4g} A above the braking current's"
            f" steady peak, {why}: the current loop's recovery from each commutation and"
            " the commutation itself carry the current past it (a 48 V motor braking 9 A"
            " reached 12 % of the command above its steady peak); give the comparator at"
            f" least {float(OVER_CURRENT_MARGIN_FRACTION) * 100:.0f} % of braking_current_max"
            f" above it: {float(peak + margin):.4g} A",
        )
    # Every current the comparator lets through must be readable: ADC2's watchdog takes
    # a conversion at a rail for a failed sensor (CURRENT_SENSOR), so a current between
    # the sensing's full scale and the trip (a commutation's overshoot above the steady
    # peak) would stop the drive as a sensor fault. Low-side phase shunts carry the
    # braking current both ways (in the ON state it circulates up one phase's lower leg
    # and down another's), so their range must reach the trip below the offset too.
    trip = protection.over_current_a
    gain = adc.current_gain_v_per_a
    if (
        offset < reference
        and (reference - offset) / gain < trip
        and (reference - offset) / gain >= peak
    ):
        r.report(
            "adc.current_gain",
            raw("adc.current_gain"),
            f"reads at most (reference - offset) / gain = {float((reference - offset) / gain):.4g}"
            f" A, below protection.over_current {_g(trip)} A: a current the comparator lets"
            " through would read as a failed sensor (ADC2's watchdog at the rail)",
            f"<= {float((reference - offset) / trip * 1000):.4g} mV/A",
        )
    if sensing.topology == "low_side_phase_shunts" and offset / gain < trip:
        r.report(
            "adc.current_offset",
            raw("adc.current_offset"),
            f"leaves offset / gain = {float(offset / gain):.4g} A below zero current, but each"
            " low-side phase shunt carries the braking current both ways (up one phase's lower"
            " leg, down another's) up to protection.over_current"
            f" {_g(trip)} A: ADC2's watchdog would read the low rail (CURRENT_SENSOR)",
            f">= {float(trip * gain):.4g} V (with the gain {float(gain * 1000):.4g} mV/A)",
        )
    # Safe state: above U_d/(lambda k_e) all-off rectifies, so the short circuit must be
    # within the bridge's rating wherever that can happen within the speed range (at the
    # lowest bus voltage it starts lowest), for the worst motor the spec declares (the
    # port chooses the short from the speed its last Hall interval says, at that corner)
    corner = safe_state_corner(motor, hall, tolerances)

    def short_peak(speed_rpm: Fraction) -> float:
        return corner_short_peak(motor, corner, protection.over_current_a, float(speed_rpm))

    n_rect = rectifying_speed(
        inverter.bus_voltage_min_v, corner.k_e * corner.speed_factor, motor.back_emf_shape
    )
    # Preferring the short, the port takes it only where it is rated for the fastest
    # the rotor may run at the interval it reads (c x the speed it says), all-off
    # elsewhere: read at speed_max, that is c x speed_max. Rated at speed_max alone
    # (init's rating, the bound there rounded up, with safe_state edited to the short),
    # the short was unrated from speed_max / c up, where all-off may rectify, and the
    # port chose all-off there, rectifying (a helper's hunt: 2 pole pairs, 48 V, 698 A,
    # 7 PIL scenarios at 18 058 rpm). Preferring all-off, the port takes the short
    # wherever all-off may rectify when it is rated up to speed_max (`short_while_unknown`
    # in codegen/control/safe_state.py): speed_max is the bound there.
    if controller.speed_max_rpm >= n_rect:
        short_preferred = protection.safe_state == "short_circuit"
        # preferring the short: where a rotor read at speed_max may run
        fastest = controller.speed_max_rpm * (corner.speed_factor if short_preferred else 1)
        peak = short_peak(fastest)
        at = f"c x speed_max = {float(fastest):.1f} rpm" if short_preferred else "speed_max"
        if peak > protection.short_circuit_current_max_a:
            r.report(
                "protection.short_circuit_current_max",
                raw("protection.short_circuit_current_max"),
                f"above {float(n_rect):.1f} rpm (U_d/(lambda k_e c) at bus_voltage_min, k_e"
                " at its upper tolerance, c = 1/(1 - hall.sector_shortening)) all-off may"
                " rectify into the bus, so the safe state there is the short circuit, whose"
                f" peak current at {at} is up to {peak:.1f} A (2 x the steady peak +"
                " over_current, R and L at their lowest): no safe state at the top of the"
                " speed range",
                # a rating the key cannot name is no way out: only the speed is
                (
                    f">= {math.ceil(peak)} A, or a controller.speed_max below"
                    if math.ceil(peak) <= PROTECTION_AMPS_MAX
                    else f"<= {PROTECTION_AMPS_MAX} A, with a controller.speed_max below"
                )
                + f" {float(n_rect):.1f} rpm, where all-off never rectifies"
                + (
                    ", or safe_state all_off"
                    if short_preferred
                    and short_peak(controller.speed_max_rpm)
                    <= protection.short_circuit_current_max_a
                    else ""
                ),
            )
    # The short circuit preferred, but within its rating at no speed of the range: the
    # firmware applies it nowhere there (all-off throughout, which the check above
    # requires not to rectify in the range), which the spec did not ask for (a hunt's
    # improved_r spec rated 40 A, short valid up to 904 rpm, speed_min above it).
    if protection.safe_state == "short_circuit":
        slowest = short_peak(controller.speed_min_rpm)
        if slowest > protection.short_circuit_current_max_a:
            r.warn(
                "short-circuit-never-rated",
                "protection.safe_state",
                raw("protection.safe_state"),
                f"the short circuit is preferred, but its peak current at speed_min"
                f" {_g(controller.speed_min_rpm)} rpm is up to {slowest:.1f} A (2 x the steady"
                " peak + over_current, k_e at its upper tolerance, R and L at their lower),"
                " above protection.short_circuit_current_max"
                f" {_g(protection.short_circuit_current_max_a)} A: the firmware applies it at no"
                " speed of the range (all-off throughout); rate the bridge for"
                f" >= {math.ceil(slowest)} A to have it, or write safe_state: all_off",
            )

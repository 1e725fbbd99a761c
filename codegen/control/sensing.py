"""Where the braking current I of Eqs. 15-20 is measured: per sector, which signal, and
when in the PWM period.

Between commutations one switch is modulated (the incoming switch of the last edge,
`switching.edge_into(...).modulated_on`) and the third phase returns the current
through a diode. From the paper's 60 deg example (T5 modulated, A returning through D1)
and its mirror image:

* upper switch modulated: ON, the current circulates through it and the returning
  phase's upper diode, inside the bridge; OFF, it flows from the negative rail up
  through the modulated phase's lower diode and back into the bus.
* lower switch modulated: ON, it circulates through it and the returning phase's lower
  diode; OFF, through the modulated phase's upper diode into the bus, and back from the
  negative rail through the returning phase's lower diode.

So a DC-link shunt carries I in the OFF time only, in both cases; a low-side phase
shunt carries it where a lower diode conducts: the modulated phase's in the OFF time
(upper modulated), the returning phase's all period (lower modulated). Every one of
these flows from the negative rail up into the bridge: the same sign on every shunt,
which the spec's sensing chain reads as offset + gain I. Sampling in the OFF time
serves every case, so the sample point is one per period (spec_drive.sense_window):
the trigger of the injected sequence is placed where the OFF time is, and D_max keeps
the turn-off edge, the dead time and the settling time clear of it.

During a commutation (from the Hall edge to its end) two switches are modulated at
D_on and D_off and no single signal is I: the port holds the last steady sample (the
I the commutation starts from, Eq. 20) and does not update the current loop.
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction
from functools import lru_cache

from codegen.dead_time import encode_dead_time
from codegen.derivation import derive
from codegen.fixedpoint.scaling import period_counts
from codegen.spec_drive import (
    ADC_CLOCK_HZ,
    ADC_CONVERSION_CYCLES,
    ADC_SAMPLE_CYCLES,
    INJECTED_CONVERSIONS,
    INJECTED_LATENCY_CYCLES,
    SenseWindow,
    current_samples,
    sense_window,
)
from codegen.spec_model import Spec

PHASES = "ABC"


@dataclass(frozen=True)
class SteadySignal:
    """What carries I in the steady state after one commutation edge."""

    edge: int  # the core's edge index
    direction: str
    sector: int
    modulated: str  # T1..T6
    returning_phase: str
    signal: str  # human-readable
    slot: int  # injected data register index 0..3 (JDR1..JDR4) holding I


@dataclass(frozen=True)
class SenseDesign:
    topology: str
    window: SenseWindow
    dead_time_counts: int
    #: ADC channel of each injected conversion JSQ1..JSQ4 (current channel(s) first)
    sequence: tuple[int, ...]
    bus_slot: int  # JDRx index 0..3 holding the bus voltage (the last conversion)
    sample_code: int  # RM0008 SMPx code of the sample time
    signals: tuple[SteadySignal, ...]
    #: the timer counts of the edges the proof checks against, for the report
    proof: tuple[str, ...]

    @property
    def conversion_time_s(self) -> Fraction:
        return (self.window_sample_cycles + ADC_CONVERSION_CYCLES) / ADC_CLOCK_HZ

    @property
    def window_sample_cycles(self) -> Fraction:
        return ADC_SAMPLE_CYCLES[self.sample_code]


def _phase_of(switch: str) -> int:
    return (int(switch[1:]) - 1) // 2


def steady_signals(spec: Spec) -> tuple[SteadySignal, ...]:
    from codegen.core.hall import edge_index

    switching = derive().switching
    out = []
    for direction in ("forward", "reverse"):
        for sector in range(6):
            edge = switching.edge_into(sector, direction)
            on, off = edge.modulated_on, edge.modulated_off
            returning = ({0, 1, 2} - {_phase_of(on), _phase_of(off)}).pop()
            upper = int(on[1:]) % 2 == 1
            if spec.sensing.topology == "dc_link_shunt":
                signal = "DC-link shunt, OFF time"
                slot = 0
            elif upper:
                signal = f"phase {PHASES[_phase_of(on)]} low-side shunt (its lower diode), OFF time"
                slot = _phase_of(on)
            else:
                signal = f"phase {PHASES[returning]} low-side shunt (its lower diode), all period"
                slot = returning
            out.append(
                SteadySignal(
                    edge=edge_index(direction, sector),
                    direction=direction,
                    sector=sector,
                    modulated=on,
                    returning_phase=PHASES[returning],
                    signal=signal,
                    slot=slot,
                )
            )
    return tuple(out)


def _proof(window: SenseWindow, dead_counts: int, settle_counts: int) -> tuple[str, ...]:
    """Check, for the extreme duties 0 and D_max (the edges move monotonically with D in
    between), that every current sample lies in the OFF time, at least the dead time plus
    the settling time after the turn-off edge and before the turn-on edge."""
    p = window.period_counts
    lines = []
    for duty in (0, window.duty_max_counts):
        if window.alignment == "edge":
            off_start, off_end = duty, p  # turn-off at CNT = D, turn-on at the next period
        else:
            off_start, off_end = duty, 2 * p - duty
        for k, (a, b) in enumerate(window.windows):
            after = a - off_start
            before = off_end - b
            clear = duty == 0 or after >= dead_counts + settle_counts
            if not (clear and before > 0 and a >= off_start):
                raise ValueError(
                    f"sample {k} [{float(a):.1f}, {float(b):.1f}] counts is not clear of the"
                    f" edges at D = {duty}: OFF time [{off_start}, {off_end}]"
                )
            lines.append(
                f"D = {duty}: sample {k} in [{float(a):.1f}, {float(b):.1f}] counts,"
                f" {float(after):.1f} after the turn-off edge (>= {dead_counts} dead +"
                f" {settle_counts} settling), {float(before):.1f} before the turn-on edge"
            )
    return tuple(lines)


@lru_cache(maxsize=16)
def sense_design(spec: Spec) -> SenseDesign:
    s = spec.sensing
    inv = spec.inverter
    dead = encode_dead_time(inv.dead_time_s, inv.timer_clock_hz)
    n = current_samples(s.topology)
    window = sense_window(
        alignment=inv.pwm_alignment,
        period_counts=period_counts(spec),
        timer_clock_hz=inv.timer_clock_hz,
        dead_time_counts=dead.dts_ticks,
        settling_time_s=s.settling_time_s,
        adc_sample_cycles=s.adc_sample_cycles,
        current_samples=n,
    )
    settle = window.guard_counts - dead.dts_ticks
    sequence = tuple(s.current_channels) + (s.bus_voltage_channel,) * (INJECTED_CONVERSIONS - n)
    return SenseDesign(
        topology=s.topology,
        window=window,
        dead_time_counts=dead.dts_ticks,
        sequence=sequence,
        bus_slot=INJECTED_CONVERSIONS - 1,
        sample_code=ADC_SAMPLE_CYCLES.index(s.adc_sample_cycles),
        signals=steady_signals(spec),
        proof=_proof(window, dead.dts_ticks, settle),
    )


def latency_text(spec: Spec) -> str:
    """When the sequence ends after its trigger (for the header)."""
    d = sense_design(spec)
    cycles = INJECTED_LATENCY_CYCLES + INJECTED_CONVERSIONS * (
        d.window_sample_cycles + ADC_CONVERSION_CYCLES
    )
    return f"{float(cycles / ADC_CLOCK_HZ) * 1e6:.2f} us"

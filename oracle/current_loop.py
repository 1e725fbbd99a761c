"""The braking-current PI's exact discrete-time model, from the spec alone.

Written from the physics and the documented contract (README, "The braking drive"),
not from the generator:

* Plant, averaged over a PWM period in PWM-OFF-PWM braking (two phases in series, ON
  shorted through a switch and a diode, OFF through the bus): 2 L dI/dt = 2E - 2RI -
  (1 - D) U_d, so the duty acts on I with the gain U_d / 2 over L s + R.
* Controller: zero on the plant's pole (K_i / K_p = R / L), crossover w_c = 2 pi f_c at
  the nominal bus: K_p = 2 L w_c / U_d, K_i = 2 R w_c / U_d; per PWM period T in TIM1
  counts per current code: k_p = K_p P a, k_i = K_i T P a (P counts per period, a
  amperes per code).
* One step, r and m the reference and measured codes clamped to the ADC range, x the
  integrator clamped to [0, D_max]:
      e = r - m, v = k_p e + x, D = clamp(v, 0, D_max),
      x' = x if (v > D_max and e > 0) or (v < 0 and e < 0), else clamp(x + k_i e, 0, D_max).
* D_max: the largest duty whose OFF time holds the current sample clear of the turn-off
  edge (dead time as TIM1 programs it, rounded up to its DTG grid, plus the settling
  time) and of the turn-on edge: the sample's span is the injected trigger latency
  (3 ADC cycles, DS5319 Table 46) and, for three phase shunts, two more conversions
  (sample time + 12.5 cycles each, RM0008 11.6) before the last sample, at 12 MHz.
* The reference: the nearest current code (ties up) of a command in mA, clamped to the
  spec's braking range.

Exact rationals (pi to 40 digits) for single values; float64 arrays for sweeps (the
tolerances are a sizeable fraction of a count, far above float64's error).
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction
from functools import cached_property

import numpy as np
import numpy.typing as npt

from codegen.spec_model import Spec
from oracle.units import units

Floats = npt.NDArray[np.float64]
Ints = npt.NDArray[np.int64]

PI = Fraction("3.1415926535897932384626433832795028841972")
#: The closed-loop time constants (1 / w_c each) a braking-current step response takes to
#: settle: the verifier's own statement of the requirement (README, "The braking
#: drive"), not the generator's (a generator that designed to a looser one had moved
#: the check's yardstick with it)
STEP_RESPONSE_TIME_CONSTANTS = 5


def step_response_periods(spec: Spec) -> Fraction:
    """PWM periods in a braking-current step response, 5 f_pwm / w_c (at least one):
    the integrator's error of each step accumulates over them."""
    periods = (
        STEP_RESPONSE_TIME_CONSTANTS
        * spec.inverter.pwm_frequency_hz
        / (2 * PI * spec.current_loop.bandwidth_hz)
    )
    return max(Fraction(1), periods)


ADC_HZ = Fraction(12_000_000)
LATENCY_CYCLES = 3
CONVERSION_EXTRA_CYCLES = Fraction(25, 2)
_ZERO = Fraction(0)


def _ceil(x: Fraction) -> int:
    return -((-x.numerator) // x.denominator)


def _floor(x: Fraction) -> int:
    return x.numerator // x.denominator


def programmed_dead_time_counts(dead_s: Fraction, clock_hz: Fraction) -> int:
    """The shortest dead time TIM1's DTG encodes that is not shorter than asked: steps of
    1 count up to 127, of 2 from 128 to 254, of 8 from 256 to 504, of 16 from 512 to
    1008 (RM0008 TIMx_BDTR)."""
    wanted = _ceil(dead_s * clock_hz)
    for low, high, step in ((0, 127, 1), (128, 254, 2), (256, 504, 8), (512, 1008, 16)):
        if wanted <= high:
            value = max(low, wanted)
            return low + _ceil(Fraction(value - low, step)) * step
    raise ValueError(f"dead time of {wanted} counts beyond TIM1's range")


def dtg_dead_time_counts(dtg: int) -> int:
    """The dead time a TIM1 BDTR.DTG code programs, in TIM1 clocks (t_DTS with CKD = 00),
    read from RM0008's TIMx_BDTR table: the top bits pick the segment, the rest count
    its steps above the segment's base."""
    for prefix, bits, base, step in ((0b0, 1, 0, 1), (0b10, 2, 64, 2), (0b110, 3, 32, 8)):
        if dtg >> (8 - bits) == prefix:
            return (base + (dtg & ((1 << (8 - bits)) - 1))) * step
    return (32 + (dtg & 0x1F)) * 16  # 111xxxxx


def duty_max(spec: Spec) -> int:
    inv = spec.inverter
    centre = inv.pwm_alignment == "center"
    p = units(spec).pwm_counts
    per_cycle = inv.timer_clock_hz / ADC_HZ
    phase_samples = 3 if spec.sensing.topology == "low_side_phase_shunts" else 1
    sample = spec.sensing.adc_sample_cycles
    last_sample_end = (
        LATENCY_CYCLES + (phase_samples - 1) * (sample + CONVERSION_EXTRA_CYCLES) + sample
    ) * per_cycle
    span = _ceil(last_sample_end)
    guard = programmed_dead_time_counts(inv.dead_time_s, inv.timer_clock_hz) + _ceil(
        spec.sensing.settling_time_s * inv.timer_clock_hz
    )
    if not centre:
        # OFF from D to P; the samples end one count before the next turn-on at P.
        trigger = p - 1 - span
        return trigger - guard
    # OFF from D (up) through the peak at P to D (down), at 2P - D; sampled from P + 1.
    return min(2 * p - (p + 1 + span) - 1, (p + 1) - guard)


@dataclass(frozen=True)
class LoopModel:
    kp: Fraction  # counts per code
    ki: Fraction  # counts per code per period
    duty_max: int
    code_max: int
    zero_code: Fraction
    codes_per_ma: Fraction
    ma_min: int
    ma_max: int
    # plant (per phase, averaged): for the step responses
    resistance: Fraction
    inductance: Fraction
    bus_nominal: Fraction
    period_s: Fraction
    amps_per_code: Fraction
    pwm_counts: int

    # ------------------------------------------------------------ exact, one value

    def held_current(self, emf_v: float, duty: float, bus_v: float | None = None) -> float:
        """The averaged plant's steady current at a constant duty (counts), >= 0."""
        u_d = float(self.bus_nominal if bus_v is None else bus_v)
        drive = (u_d * duty / self.pwm_counts / 2 + emf_v - u_d / 2) / float(self.resistance)
        return max(0.0, drive)

    def step(self, x: Fraction, reference: int, measured: int) -> tuple[Fraction, Fraction]:
        """(duty, next integrator), counts, exact."""
        r, m = min(reference, self.code_max), min(measured, self.code_max)
        e = r - m
        top = self._top
        x = min(max(Fraction(x), _ZERO), top)
        v = self.kp * e + x
        duty = min(max(v, _ZERO), top)
        if (v > self.duty_max and e > 0) or (v < 0 and e < 0):
            return duty, x
        return duty, min(max(x + self.ki * e, _ZERO), top)

    @cached_property
    def _top(self) -> Fraction:
        """D_max as a Fraction, the integrator's and the duty's upper clamp."""
        return Fraction(self.duty_max)

    def reference_code(self, milliamps: int) -> int:
        """floor(zero + held codes_per_ma + 1/2), on the integers of one common
        denominator (exact: the same floor as in Fractions, without a gcd per call;
        the verifier asks for every mA of the range)."""
        held = min(max(milliamps, self.ma_min), self.ma_max)
        zero_num, per_ma_num, half_num, denominator = self._reference_terms
        return (zero_num + held * per_ma_num + half_num) // denominator

    @cached_property
    def _reference_terms(self) -> tuple[int, int, int, int]:
        """zero_code, codes_per_ma and 1/2 over their common (positive) denominator."""
        z, c = Fraction(self.zero_code), Fraction(self.codes_per_ma)
        denominator = 2 * z.denominator * c.denominator
        return (
            z.numerator * 2 * c.denominator,
            c.numerator * 2 * z.denominator,
            z.denominator * c.denominator,
            denominator,
        )

    # ------------------------------------------------------------ float64 sweeps

    def step_array(self, x: Floats, reference: Ints, measured: Ints) -> tuple[Floats, Floats]:
        r = np.minimum(reference, self.code_max)
        m = np.minimum(measured, self.code_max)
        e = (r - m).astype(np.float64)
        top = float(self.duty_max)
        x = np.clip(x, 0.0, top)
        v = float(self.kp) * e + x
        duty = np.clip(v, 0.0, top)
        frozen = ((v > top) & (e > 0)) | ((v < 0) & (e < 0))
        nxt = np.where(frozen, x, np.clip(x + float(self.ki) * e, 0.0, top))
        return duty, nxt

    def near_decision(
        self, x: Floats, reference: Ints, measured: Ints, margin: float
    ) -> npt.NDArray[np.bool_]:
        """Points whose v lies within `margin` counts of a saturation bound, where a
        rounded gain may decide the anti-windup the other way."""
        e = (np.minimum(reference, self.code_max) - np.minimum(measured, self.code_max)).astype(
            np.float64
        )
        v = float(self.kp) * e + np.clip(x, 0.0, float(self.duty_max))
        return (np.abs(v - self.duty_max) <= margin) | (np.abs(v) <= margin)

    # ------------------------------------------------------------ closed loop

    def measured_code(self, amps: float) -> int:
        code = int(np.floor(float(self.zero_code) + amps / float(self.amps_per_code) + 0.5))
        return min(max(code, 0), self.code_max)

    def closed_loop(
        self,
        *,
        emf_v: float,
        references: list[int],
        bus_v: float | None = None,
        current_a: float = 0.0,
        state: Fraction = Fraction(0),
    ) -> tuple[list[int], list[float], list[float]]:
        """The exact controller on the averaged plant, the duty of period k applied in
        period k + 1 (the CCR preload): the measured codes, duties and currents per
        period. The plant is exact over a period for a constant duty:
        I' = a I + (1 - a) (U_d D / 2 + E - U_d / 2) / R, a = exp(-R T / L); the current
        cannot reverse through the diodes (I >= 0). `state`: the integrator (counts) it
        starts from, the duty it holds applied the period before."""
        u_d = float(self.bus_nominal if bus_v is None else bus_v)
        r_ohm, l_h, t = float(self.resistance), float(self.inductance), float(self.period_s)
        a = float(np.exp(-r_ohm * t / l_h))
        x = state
        applied = float(min(max(state, Fraction(0)), Fraction(self.duty_max)))
        current = current_a
        measured, duties, currents = [], [], []
        for reference in references:
            code = self.measured_code(current)
            duty, x = self.step(x, reference, code)
            measured.append(code)
            duties.append(float(duty))
            currents.append(current)
            d = applied / self.pwm_counts
            drive = (u_d * d / 2 + emf_v - u_d / 2) / r_ohm
            current = max(0.0, a * current + (1 - a) * drive)
            applied = float(duty)
        return measured, duties, currents


def loop_model(spec: Spec) -> LoopModel:
    u = units(spec)
    m, inv = spec.motor, spec.inverter
    omega = 2 * PI * spec.current_loop.bandwidth_hz
    u_d = inv.bus_voltage_nominal_v
    period = 1 / inv.pwm_frequency_hz
    kp_duty = 2 * m.phase_inductance_h * omega / u_d
    ki_duty = 2 * m.phase_resistance_ohm * omega / u_d
    c = spec.controller
    return LoopModel(
        kp=kp_duty * u.pwm_counts * u.amps_per_code,
        ki=ki_duty * period * u.pwm_counts * u.amps_per_code,
        duty_max=duty_max(spec),
        code_max=u.adc_max,
        zero_code=u.zero_current_code,
        codes_per_ma=1 / (1000 * u.amps_per_code),
        ma_min=_ceil(c.braking_current_min_a * 1000),
        ma_max=_floor(c.braking_current_max_a * 1000),
        resistance=m.phase_resistance_ohm,
        inductance=m.phase_inductance_h,
        bus_nominal=u_d,
        period_s=period,
        amps_per_code=u.amps_per_code,
        pwm_counts=u.pwm_counts,
    )

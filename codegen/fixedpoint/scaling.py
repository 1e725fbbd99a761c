"""From physical units to the integers the firmware sees, exactly.

The core's inputs are a Hall period T in Hall-timer ticks, a bus voltage code B and a
current code C in ADC counts, and a main duty M in TIM1 counts. Its outputs are compare
values in TIM1 counts and a commutation time in Hall ticks. This module states the
conversions (exact rationals from the spec) and derives, with SymPy, the two constants
the firmware needs from the paper's equations:

    X = P * 4E/U_d = K_X / (T * B)                      (Eq. 9: 4E/U_d = 2 - D_on)
    t_com * f_hall = K_G * I_code / (B * W),            (Eq. 20)
        W = 2P + 2 C_on - 4 C_off - X  (all in TIM1 counts)

so that the bus voltage enters through one reciprocal (K_X/B and K_G/B, recomputed when
the bus voltage is sampled) and the speed through one hardware divide per Hall edge.
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction

import sympy as sp

from codegen.dead_time import commutation_guard_ticks, sector_margin_shift
from codegen.derivation import symbols as s
from codegen.derivation.paper import Derivation
from codegen.errors import DerivationError
from codegen.spec_drive import end_sample_room_s
from codegen.spec_model import Spec

# Integer-domain symbols of the firmware.
T, B, C_i, M, P = sp.symbols("T B C_i M P", positive=True)
C_on, C_off, X = sp.symbols("C_on C_off X", real=True)


def _q(value: Fraction) -> sp.Rational:
    return sp.Rational(value.numerator, value.denominator)


@dataclass(frozen=True)
class Scaling:
    """Exact unit conversions of one spec (all SymPy rationals)."""

    period_counts: int  # P: TIM1 counts per PWM period (duty 1)
    hall_clock_hz: sp.Rational
    pole_pairs: int
    volts_per_bus_code: sp.Rational  # U_d = B * this
    amps_per_current_code: sp.Rational  # I = (C - offset) * this
    #: the code of zero current, exactly (V_offset / V_ref 2^bits: often not whole)
    current_offset_exact: sp.Rational
    #: the nearest whole code, for consumers that need one code per current (sim, bench)
    current_offset_code: int
    adc_full_scale: int
    k_x: sp.Rational  # X = k_x / (T B)
    k_g: sp.Rational  # t_ticks = k_g I_code / (B W)
    #: the shortest interval the Hall timer reads at speed_max: it counts whole ticks, so
    #: a sector of T ticks reads floor(T) or ceil(T) (rounded down)
    period_min_ticks: int
    #: the longest it reads at speed_min (rounded up, within the counter's range)
    period_max_ticks: int
    period_cap_ticks: int  # largest period the Hall counter can report (its full range)
    #: a commutation ends at least this many ticks before its sector's end (the bridge's
    #: dead time and the end's latency: `codegen.dead_time.commutation_guard_ticks`)
    commutation_guard_ticks: int
    #: k of the sector-shortening margin ceil(T / 2^k) beyond the guard
    #: (`codegen.dead_time.sector_margin_shift`; None: no margin)
    sector_margin_shift: int | None
    bus_code_min: int
    bus_code_max: int
    #: raw ADC codes of the braking-current range, decided exactly:
    #: I_min <= (C - offset) a <= I_max  <=>  low <= C <= high
    current_code_low: int
    current_code_high: int

    @property
    def current_code_min(self) -> int:
        """The range's low end relative to the whole offset code."""
        return self.current_code_low - self.current_offset_code

    @property
    def current_code_max(self) -> int:
        """The range's top relative to the whole offset code."""
        return self.current_code_high - self.current_offset_code

    def current_code(self, amps: sp.Rational) -> int:
        """The ADC code nearest to a current."""
        return int(
            sp.floor(
                self.current_offset_exact + amps / self.amps_per_current_code + sp.Rational(1, 2)
            )
        )

    def speed_rpm(self, period_ticks: sp.Expr) -> sp.Expr:
        """n = 60 f_hall / (6 p T): one Hall interval is 60 electrical degrees."""
        return 10 * self.hall_clock_hz / (self.pole_pairs * period_ticks)


def period_counts(spec: Spec) -> int:
    divisor = 2 if spec.inverter.pwm_alignment == "center" else 1
    counts = spec.inverter.timer_clock_hz / spec.inverter.pwm_frequency_hz / divisor
    if counts.denominator != 1:
        raise DerivationError(f"PWM period is not a whole number of counts: {counts}")
    return int(counts)


def scaling(spec: Spec, derivation: Derivation) -> Scaling:
    adc_full_scale = 2**spec.adc.bits
    volts_per_code = _q(spec.adc.reference_v * spec.adc.bus_voltage_divider) / adc_full_scale
    amps_per_code = _q(spec.adc.reference_v / spec.adc.current_gain_v_per_a) / adc_full_scale
    offset = _q(spec.adc.current_offset_v / spec.adc.reference_v) * adc_full_scale
    p = period_counts(spec)
    f_hall = _q(spec.hall.timer_clock_hz)
    pp = spec.motor.pole_pairs
    k_e = _q(spec.motor.back_emf_constant_v_per_rpm)
    emf = k_e * 10 * f_hall / (pp * T)  # E = k_e n, Eq. 3, n from the Hall period
    bus = B * volts_per_code
    # Eq. 9 rearranged: 4E/U_d = 2 - D_on(ripple-free). X is that ratio in TIM1 counts.
    four_e_over_ud = 2 - derivation["9"].row("")
    x_expr = sp.simplify(p * four_e_over_ud.subs({s.E: emf, s.U_d: bus}))
    k_x = sp.simplify(x_expr * T * B)
    if k_x.free_symbols:
        raise DerivationError(f"X is not k/(T B): {x_expr}")
    # Eq. 20 with duties as counts, 2E/U_d = X / (2P), I = C_i * amps_per_code.
    t_com = derivation["20"].row("")
    t_ticks = (
        t_com.subs(
            {
                s.D_on: C_on / p,
                s.D_off: C_off / p,
                s.E: X * bus / (4 * p),
                s.U_d: bus,
                s.I: C_i * amps_per_code,
                s.L: _q(spec.motor.phase_inductance_h),
            }
        )
        * f_hall
    )
    w = 2 * p + 2 * C_on - 4 * C_off - X
    k_g = sp.simplify(t_ticks * B * w / C_i)
    if k_g.free_symbols:
        raise DerivationError(f"Eq. 20 is not k I / (B W): {sp.simplify(t_ticks)}")
    n_max, n_min = _q(spec.controller.speed_max_rpm), _q(spec.controller.speed_min_rpm)
    ticks_per_rpm = 10 * f_hall / pp
    bus_min = _q(spec.inverter.bus_voltage_min_v) / volts_per_code
    bus_max = _q(spec.inverter.bus_voltage_max_v) / volts_per_code
    i_min = offset + _q(spec.controller.braking_current_min_a) / amps_per_code
    i_max = offset + _q(spec.controller.braking_current_max_a) / amps_per_code
    return Scaling(
        period_counts=p,
        hall_clock_hz=f_hall,
        pole_pairs=pp,
        volts_per_bus_code=volts_per_code,
        amps_per_current_code=amps_per_code,
        current_offset_exact=sp.Rational(offset),
        current_offset_code=int(sp.floor(offset + sp.Rational(1, 2))),
        adc_full_scale=adc_full_scale,
        k_x=sp.Rational(k_x),
        k_g=sp.Rational(k_g),
        period_min_ticks=int(sp.floor(ticks_per_rpm / n_max)),
        period_max_ticks=min(int(sp.ceiling(ticks_per_rpm / n_min)), 2**spec.hall.counter_bits - 1),
        period_cap_ticks=2**spec.hall.counter_bits - 1,
        commutation_guard_ticks=commutation_guard_ticks(
            spec.inverter.dead_time_s,
            spec.hall.timer_clock_hz,
            end_sample_room_s(spec.inverter.pwm_frequency_hz, spec.sensing.adc_sample_cycles),
        ),
        sector_margin_shift=sector_margin_shift(spec.hall.sector_shortening),
        bus_code_min=int(sp.ceiling(bus_min)),
        bus_code_max=int(sp.floor(bus_max)),
        current_code_low=int(sp.ceiling(i_min)),
        current_code_high=min(int(sp.floor(i_max)), adc_full_scale - 1),
    )

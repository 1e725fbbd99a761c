"""The rule's spec constants, exact, and the input box the firmware is proven over.

The firmware sees the Hall period T (ticks), the bus code B and the offset-removed
current i (in 1/m codes, `codegen.core.conditioning.CurrentFormat`). The rule's
quantities in duty counts (`derive_firmware_rule().counts`) are, with E = k_e n,
n = 10 f_hall/(p T) (Eq. 3) and U_d = B v, I = i a:

    X     = 4 P E / U_d             = K_X / (T B)
    Y     = 3 P R I / U_d           = K_Y i / B
    A     = 3 P L I / (U_d T_s)     = kappa i X   (E T_s = 10 k_e / p: no T, no B)
    rho   = R T_s / L               = K_rho T
    A rho = kappa K_rho K_X i / B   (no T)

The commutation ends on a carrier boundary: tau = f_hall / f_pwm ticks per PWM period,
the grid x_m = m tau / T, on which rho x_m = y_1 m with y_1 = K_rho tau and the decay
e^-rho x_m = D^m, D = e^-y_1: constants. The EMF shape enters through sigma(x) and phi(x)
(`codegen.derivation.shape_terms`), affine over the sector.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import sympy as sp

from codegen.core.conditioning import CurrentFormat, current_formats
from codegen.dead_time import latest_end_ticks
from codegen.derivation import derive
from codegen.derivation import symbols as s
from codegen.derivation.constant_pair import A_c, P, T_s, X_c, Y_c, derive_firmware_rule
from codegen.derivation.shape_terms import ShapeTerms, affine_terms
from codegen.errors import DerivationError
from codegen.fixedpoint.scaling import Scaling
from codegen.spec_model import Spec


def _q(value: object) -> sp.Rational:
    return sp.Rational(str(value)) if not isinstance(value, sp.Basic) else sp.Rational(value)


@dataclass(frozen=True)
class RuleConstants:
    """Exact constants (SymPy rationals) and integer input ranges of one spec."""

    period_counts: int  # P
    hall_clock_hz: sp.Rational
    k_x: sp.Rational  # X = k_x / (T B), duty counts
    k_y: sp.Rational  # Y = k_y i / B, i in 1/m codes
    kappa: sp.Rational  # A = kappa i X, i in 1/m codes
    k_rho: sp.Rational  # rho = k_rho T
    ramp_weight: sp.Expr  # theta (irrational: sqrt(2) - 1)
    period_low: int  # the core's shortest period (speed_max): shorter ones are the safe state
    period_high: int  # the core's longest period (speed_min): the rule clamps T to it
    bus_low: int
    bus_high: int
    #: the code of zero current (whole: the nearest code, for grids of inputs), and the
    #: current format i = m C - OFFSET_M in 1/m codes (see codegen.core.conditioning)
    current_offset: int
    current: CurrentFormat
    current_high: int  # largest i (ADC full scale), 1/m codes
    adc_max: int  # the ADC's full-scale code
    time_target_ticks: sp.Rational
    duty_target_counts: sp.Rational
    carrier_ticks: sp.Rational  # tau = f_hall / f_pwm: Hall ticks per PWM period
    #: a commutation ends at least this many ticks before its sector's end
    guard_ticks: int
    shape: ShapeTerms  # sigma(x), phi(x) of the spec's EMF over the sector
    #: k of the sector-shortening margin ceil(T / 2^k) beyond the guard (None: none)
    margin_shift: int | None = None

    def latest_end(self, period_ticks: Any) -> Any:
        """The latest end in a sector of `period_ticks` (an int or an int array): the
        guard and the margin before its end (`codegen.dead_time.latest_end_ticks`)."""
        return latest_end_ticks(period_ticks, self.guard_ticks, self.margin_shift)

    @property
    def rho_max(self) -> sp.Rational:
        return self.k_rho * self.period_high

    @property
    def step_decay(self) -> sp.Rational:
        """y_1 = K_rho tau: rho x over one carrier period (the grid's decay exponent)."""
        return self.k_rho * self.carrier_ticks

    @property
    def hold_slope(self) -> sp.Expr:
        """Sigma(x) - Sigma(0) per X per sector: -(sigma_1 / 4) theta."""
        return -sp.Rational(self.shape.sum1) / 4 * self.ramp_weight

    @property
    def ramp_per_x(self) -> sp.Rational:
        """q rho / X = -phi_1 / 4: the EMF ramp's forcing per X per sector."""
        return -sp.Rational(self.shape.force1) / 4

    def periods(self, period_ticks: int) -> int:
        """N: the whole carrier periods in a sector of `period_ticks`, less the guard at
        its end (a commutation ends at least the guard and the margin before the sector does)."""
        return int(sp.floor(self.latest_end(period_ticks) / self.carrier_ticks))


def rule_current_format(sc: Scaling) -> CurrentFormat:
    """The offset exactly when its denominator is small, else to 1/32 code."""
    candidates = current_formats(sc)
    exact = [c for c in candidates if c.is_exact]
    return exact[0] if exact else next(c for c in candidates if c.scale == 32)


def rule_constants(spec: Spec, sc: Scaling) -> RuleConstants:
    rule = derive_firmware_rule()
    T, B, i = sp.symbols("T B i", positive=True)
    n = 10 * sc.hall_clock_hz / (sc.pole_pairs * T)
    physical = {
        s.E: _q(spec.motor.back_emf_constant_v_per_rpm) * n,
        s.U_d: B * sc.volts_per_bus_code,
        s.I: i * sc.amps_per_current_code,
        s.R: _q(spec.motor.phase_resistance_ohm),
        s.L: _q(spec.motor.phase_inductance_h),
        T_s: T / sc.hall_clock_hz,
        P: sc.period_counts,
    }
    x_counts = sp.simplify(rule.counts[X_c].subs(physical))
    k_x = sp.simplify(x_counts * T * B)
    k_y = sp.simplify(rule.counts[Y_c].subs(physical) * B / i)
    kappa = sp.simplify(rule.counts[A_c].subs(physical) / (i * x_counts))
    k_rho = sp.simplify((s.R * T_s / s.L).subs(physical) / T)
    for name, value in (("K_X", k_x), ("K_Y", k_y), ("kappa", kappa), ("K_rho", k_rho)):
        if value.free_symbols or not value.is_positive:
            raise DerivationError(f"{name} is not a positive constant: {value}")
    if k_x != sc.k_x:
        raise DerivationError(f"K_X {k_x} differs from the core's {sc.k_x} (Eq. 9)")
    current = rule_current_format(sc)
    m = current.scale
    return RuleConstants(
        period_counts=sc.period_counts,
        hall_clock_hz=sc.hall_clock_hz,
        k_x=sp.Rational(k_x),
        k_y=sp.Rational(k_y) / m,
        kappa=sp.Rational(kappa) / m,
        k_rho=sp.Rational(k_rho),
        ramp_weight=rule.ramp_weight_minimax,
        period_low=sc.period_min_ticks,
        period_high=sc.period_max_ticks,
        bus_low=sc.bus_code_min,
        bus_high=sc.bus_code_max,
        current_offset=sc.current_offset_code,
        current=current,
        current_high=current.scale * (sc.adc_full_scale - 1) - current.offset_q.value,
        adc_max=sc.adc_full_scale - 1,
        time_target_ticks=_q(spec.accuracy.commutation_time_ticks),
        duty_target_counts=_q(spec.accuracy.duty_counts),
        carrier_ticks=sc.hall_clock_hz / _q(spec.inverter.pwm_frequency_hz),
        guard_ticks=sc.commutation_guard_ticks,
        margin_shift=sc.sector_margin_shift,
        shape=affine_terms(spec.motor.back_emf_shape, derive().switching),
    )

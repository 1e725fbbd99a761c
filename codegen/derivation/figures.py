"""The derivation evaluated at one motor spec: the numbers an engineer checks first.

All values are exact (SymPy rationals built from the spec's exact decimals) until
they are printed.
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction

import sympy as sp

from codegen.derivation import symbols as s
from codegen.derivation.paper import Derivation
from codegen.spec_model import Spec


def _q(value: Fraction) -> sp.Rational:
    return sp.Rational(value.numerator, value.denominator)


def spec_values(spec: Spec, bus_voltage: Fraction | None = None) -> dict[sp.Symbol, sp.Rational]:
    """Symbol -> exact value for the motor (speed in rpm, SI otherwise)."""
    return {
        s.U_d: _q(bus_voltage if bus_voltage is not None else spec.inverter.bus_voltage_nominal_v),
        s.k_e: _q(spec.motor.back_emf_constant_v_per_rpm),
        s.L: _q(spec.motor.phase_inductance_h),
        s.R: _q(spec.motor.phase_resistance_ohm),
        s.I: _q(spec.controller.braking_current_nominal_a),
    }


@dataclass(frozen=True)
class OperatingFigures:
    speed_rpm: sp.Rational
    main_duty: sp.Rational
    emf_v: sp.Expr
    region: str
    improved_on: sp.Expr
    improved_off: sp.Expr
    improved_t_com_s: sp.Expr
    sector_time_s: sp.Expr
    conventional_off: sp.Expr
    conventional_fails: bool


@dataclass(frozen=True)
class SpecFigures:
    boundary_speed_rpm: sp.Expr
    upper_speed_rpm: sp.Expr
    points: tuple[OperatingFigures, ...]


def region_of(derivation: Derivation, values: dict[sp.Symbol, sp.Rational], speed: sp.Expr) -> str:
    """Eq. 18's segment: "low" for 0 < n <= U_d/(4 k_e), "high" above it."""
    boundary = derivation["18"].row("boundary_speed").subs(values)
    return "low" if speed <= boundary else "high"


def operating_figures(
    derivation: Derivation, spec: Spec, speed_rpm: Fraction, main_duty: Fraction
) -> OperatingFigures:
    values = spec_values(spec)
    n = _q(speed_rpm)
    emf = sp.nsimplify(values[s.k_e] * n)
    at = {**values, s.E: emf, s.n: n, s.D: _q(main_duty)}
    rule = derivation["18"]
    region = region_of(derivation, values, n)
    on = rule.row(f"on_{region}").subs(at)
    off = rule.row(f"off_{region}").subs(at)
    t_com = derivation["20"].row(f"improved_{region}").subs(at)
    conventional_off = derivation["16"].row("").subs({**at, s.D_on: at[s.D]})
    electrical_hz = n * spec.motor.pole_pairs / 60
    return OperatingFigures(
        speed_rpm=n,
        main_duty=at[s.D],
        emf_v=emf,
        region=region,
        improved_on=on,
        improved_off=off,
        improved_t_com_s=t_com,
        sector_time_s=1 / (6 * electrical_hz),
        conventional_off=conventional_off,
        conventional_fails=not 0 <= conventional_off <= 1,
    )


def spec_figures(derivation: Derivation, spec: Spec) -> SpecFigures:
    values = spec_values(spec)
    rule = derivation["18"]
    return SpecFigures(
        boundary_speed_rpm=rule.row("boundary_speed").subs(values),
        upper_speed_rpm=rule.row("upper_speed").subs(values),
        points=tuple(
            operating_figures(derivation, spec, p.speed_rpm, p.main_duty)
            for p in spec.operating_points
        ),
    )

"""Tests of codegen.derivation: the paper's Eqs. 1-20 and the default motor's numbers.

The symbolic checks redo each step by other means than the derivation does (a hand
solve of Eq. 1, differentiation instead of integration, unit analysis), so that a wrong
step in codegen/derivation cannot make its own check pass.
"""

from __future__ import annotations

import time
from fractions import Fraction
from pathlib import Path

import pytest
import sympy as sp
from sympy.physics import units

from codegen.derivation import Derivation, derive
from codegen.derivation.figures import OperatingFigures, SpecFigures, spec_figures
from codegen.derivation.symbols import (
    D_off,
    D_on,
    E,
    I,
    L,
    R,
    U_d,
    i_a,
    i_b,
    i_c,
    k_e,
    n,
    t,
)
from codegen.spec_loader import load_spec
from codegen.spec_model import Spec

ROOT = Path(__file__).resolve().parents[1]
DEFAULT_SPEC = ROOT / "spec" / "paper_motor.yaml"

CURRENTS = (i_a, i_b, i_c)
ROWS = ("a", "b", "c")


@pytest.fixture(scope="module")
def derivation() -> Derivation:
    return derive()


@pytest.fixture(scope="module")
def spec() -> Spec:
    return load_spec(DEFAULT_SPEC)


@pytest.fixture(scope="module")
def figures(derivation: Derivation, spec: Spec) -> SpecFigures:
    return spec_figures(derivation, spec)


def _q(value: Fraction) -> sp.Rational:
    return sp.Rational(value.numerator, value.denominator)


def _point(figures: SpecFigures, speed_rpm: int) -> OperatingFigures:
    (point,) = [p for p in figures.points if p.speed_rpm == speed_rpm]
    return point


def _emf(spec: Spec, speed_rpm: int | sp.Expr) -> sp.Expr:
    """E = k_e n (Eq. 3), from the spec, not from the figures module."""
    return _q(spec.motor.back_emf_constant_v_per_rpm) * speed_rpm


def _bus(spec: Spec) -> sp.Rational:
    return _q(spec.inverter.bus_voltage_nominal_v)


def _is_zero(expr: sp.Expr) -> bool:
    return sp.simplify(expr) == 0


def _zero_on_star_point(expr: sp.Expr) -> bool:
    """expr vanishes once the floating star point's i_a + i_b + i_c = 0 is imposed."""
    return _is_zero(sp.expand(expr).subs(i_c, -i_a - i_b))


def _hand_solved_slopes(
    u: tuple[sp.Expr, sp.Expr, sp.Expr], e: tuple[sp.Expr, sp.Expr, sp.Expr]
) -> tuple[sp.Expr, ...]:
    """Eq. 1 solved by hand: u_x = R i_x + L di_x/dt + e_x + u_n with sum(di_x/dt) = 0."""
    slopes = sp.symbols("s_a s_b s_c")
    u_n = sp.Symbol("u_n")
    equations = [
        sp.Eq(u_x, R * i_x + L * s_x + e_x + u_n)
        for u_x, i_x, s_x, e_x in zip(u, CURRENTS, slopes, e, strict=True)
    ]
    equations.append(sp.Eq(sum(slopes), 0))
    solution = sp.solve(equations, [*slopes, u_n], dict=True)
    assert len(solution) == 1
    return tuple(solution[0][s_x] for s_x in slopes)


def _in_amperes_per_second(term: sp.Expr) -> bool:
    """True if `term` of a current slope has the unit A/s (duties are dimensionless)."""
    dims = {U_d: units.volt, E: units.volt, L: units.henry, R: units.ohm, D_on: 1, D_off: 1}
    dims.update({current: units.ampere for current in CURRENTS})
    value = units.convert_to(term.subs(dims), [units.ampere, units.second])
    ratio = sp.simplify(value / (units.ampere / units.second))
    return bool(ratio.is_number) and ratio != 0


# --- The default spec's numbers (paper Table 3 motor at 24 V) ---


def test_region_cut_off_speed_is_2542_rpm(figures: SpecFigures, spec: Spec) -> None:
    expected = _bus(spec) / (4 * _q(spec.motor.back_emf_constant_v_per_rpm))
    assert figures.boundary_speed_rpm == expected
    assert round(float(figures.boundary_speed_rpm)) == 2542


def test_upper_speed_limit_is_5085_rpm(figures: SpecFigures, spec: Spec) -> None:
    expected = _bus(spec) / (2 * _q(spec.motor.back_emf_constant_v_per_rpm))
    assert figures.upper_speed_rpm == expected
    assert round(float(figures.upper_speed_rpm)) == 5085


def test_high_speed_point_modulates_turn_on_phase_only(figures: SpecFigures, spec: Spec) -> None:
    point = _point(figures, 4600)
    assert point.region == "high"
    assert point.improved_on == 2 - 4 * _emf(spec, 4600) / _bus(spec)
    assert float(point.improved_on) == pytest.approx(0.191, abs=5e-4)
    assert point.improved_off == 0


def test_low_speed_point_modulates_turn_off_phase_only(figures: SpecFigures, spec: Spec) -> None:
    point = _point(figures, 1500)
    assert point.region == "low"
    assert point.improved_on == 1
    assert point.improved_off == 1 - 4 * _emf(spec, 1500) / _bus(spec)
    assert point.improved_off == sp.Rational(41, 100)


def test_conventional_overlap_fails_at_4600_rpm_but_not_at_1500_rpm(
    figures: SpecFigures, spec: Spec
) -> None:
    fast, slow = _point(figures, 4600), _point(figures, 1500)
    assert fast.main_duty == slow.main_duty == sp.Rational(42, 100)
    # Eq. 16: D_off = 2 - 4E/U_d - D_on, with D_on the main duty.
    assert fast.conventional_off == 2 - 4 * _emf(spec, 4600) / _bus(spec) - fast.main_duty
    assert fast.conventional_off < 0
    assert fast.conventional_fails
    assert slow.conventional_off == 2 - 4 * _emf(spec, 1500) / _bus(spec) - slow.main_duty
    assert 0 <= slow.conventional_off <= 1
    assert not slow.conventional_fails


# --- Independent symbolic checks ---


def test_overlap_slopes_match_a_hand_solve_of_eq_1(derivation: Derivation) -> None:
    derived = derivation["13"]
    hand = _hand_solved_slopes((U_d, D_off * U_d, D_on * U_d), (E, -E, -E))
    for name, expected in zip(ROWS, hand, strict=True):
        assert _zero_on_star_point(derived.row(name) - expected), name


def test_unsuppressed_slopes_match_a_hand_solve_of_eq_1(derivation: Derivation) -> None:
    derived = derivation["4"]
    hand = _hand_solved_slopes((U_d, sp.S.Zero, D_on * U_d), (E, -E, -E))
    for name, expected in zip(ROWS, hand, strict=True):
        assert _zero_on_star_point(derived.row(name) - expected), name


@pytest.mark.parametrize("key", ["4", "13"])
def test_slopes_sum_to_zero_only_through_the_star_point(derivation: Derivation, key: str) -> None:
    total = sum(derivation[key].row(name) for name in ROWS)
    # Each row keeps its own R i_x / L, so the sum is -R (i_a + i_b + i_c) / L exactly.
    assert _is_zero(total + R * (i_a + i_b + i_c) / L)
    assert _zero_on_star_point(total)


@pytest.mark.parametrize("key", ["4", "13"])
def test_turn_on_slope_has_plus_2e(derivation: Derivation, key: str) -> None:
    row_c = derivation[key].row("c")
    assert _is_zero(sp.diff(row_c, E) - 2 / (3 * L))


def test_printed_eq_4_row_c_minus_2e_is_a_misprint(derivation: Derivation) -> None:
    printed = {
        "a": ((2 - D_on) * U_d - 4 * E) / (3 * L),
        "b": (2 * E - (1 + D_on) * U_d) / (3 * L),
        "c": ((2 * D_on - 1) * U_d - 2 * E) / (3 * L),
    }
    derived = {name: derivation["4"].row(name).subs(R, 0) for name in ROWS}
    assert _is_zero(derived["a"] - printed["a"])
    assert _is_zero(derived["b"] - printed["b"])
    assert not _is_zero(derived["c"] - printed["c"])
    # The printed rows break the star-point balance; with +2E in row c they keep it.
    assert not _is_zero(sum(printed.values()))
    assert _is_zero(printed["a"] + printed["b"] + printed["c"].subs(E, -E))
    assert _is_zero(derived["c"] - printed["c"].subs(E, -E))


@pytest.mark.parametrize("key", ["4", "13"])
def test_resistance_enters_only_as_r_i_over_l(derivation: Derivation, key: str) -> None:
    for name, current in zip(ROWS, CURRENTS, strict=True):
        row = derivation[key].row(name)
        assert _is_zero(sp.diff(row, R) + current / L), name
        assert not row.subs(R, 0).has(R)


@pytest.mark.parametrize("key", ["4", "13"])
def test_every_slope_term_is_in_amperes_per_second(derivation: Derivation, key: str) -> None:
    for name in ROWS:
        for term in sp.Add.make_args(sp.expand(derivation[key].row(name))):
            assert _in_amperes_per_second(term), f"row {name}: {term}"
    # The paper's printed "- R i_a" would be in volts: the unit check must reject it.
    assert not _in_amperes_per_second(R * i_a)


@pytest.mark.parametrize(("currents_key", "slopes_key"), [("5", "4"), ("14", "13")])
def test_currents_integrate_lossless_slopes_from_the_pre_commutation_state(
    derivation: Derivation, currents_key: str, slopes_key: str
) -> None:
    currents = derivation[currents_key]
    assert currents.neglects_resistance
    for name, start in zip(ROWS, (-I, I, sp.S.Zero), strict=True):
        current = currents.row(name)
        assert _is_zero(current.subs(t, 0) - start), name
        slope = derivation[slopes_key].row(name).subs(R, 0)
        assert _is_zero(sp.diff(current, t) - slope), name


def test_improved_rule_holds_the_non_commutating_current_in_both_regions(
    derivation: Derivation,
) -> None:
    rule = derivation["18"]
    slope_a = derivation["13"].row("a").subs(R, 0)
    for region in ("low", "high"):
        duties = {D_on: rule.row(f"on_{region}"), D_off: rule.row(f"off_{region}")}
        assert _is_zero(slope_a.subs(duties)), region
    # Not a tautology: an arbitrary duty pair does move the non-commutating current.
    assert not _is_zero(slope_a.subs({D_on: 1, D_off: 0}))


def test_improved_rule_duties_are_duties_in_their_regions(derivation: Derivation) -> None:
    rule = derivation["18"]
    bus = sp.Integer(24)
    for fraction in (sp.Rational(1, 100), sp.Rational(1, 8), sp.Rational(1, 4)):
        off_low = rule.row("off_low").subs({E: fraction * bus, U_d: bus})
        assert 0 <= off_low <= 1
    for fraction in (sp.Rational(26, 100), sp.Rational(3, 8), sp.Rational(1, 2)):
        on_high = rule.row("on_high").subs({E: fraction * bus, U_d: bus})
        assert 0 <= on_high <= 1


def test_improved_rule_is_continuous_at_the_region_boundary(derivation: Derivation) -> None:
    rule = derivation["18"]
    boundary_emf = k_e * rule.row("boundary_speed")
    assert _is_zero(boundary_emf - U_d / 4)
    at = {E: boundary_emf}
    assert _is_zero(rule.row("on_low").subs(at) - rule.row("on_high").subs(at))
    assert _is_zero(rule.row("off_low").subs(at) - rule.row("off_high").subs(at))


def test_improved_commutation_times(derivation: Derivation) -> None:
    times = derivation["20"]
    assert _is_zero(times.row("improved_low") - I * L / (2 * E))
    assert _is_zero(times.row("improved_high") - I * L / (U_d - 2 * E))


def test_commutation_time_drives_the_turn_off_current_to_zero(derivation: Derivation) -> None:
    i_off = derivation["14"].row("b")
    t_com = derivation["20"].row("")
    assert _is_zero(i_off.subs(t, t_com))


def test_conventional_feasible_on_duty_is_the_unit_window_shifted_by_4e_over_ud(
    derivation: Derivation,
) -> None:
    feasible = derivation["16"].row("feasible_on_duty")
    assert isinstance(feasible, sp.Interval)
    assert _is_zero(feasible.start - (1 - 4 * E / U_d))
    assert _is_zero(feasible.end - (2 - 4 * E / U_d))
    assert not feasible.left_open
    assert not feasible.right_open


def test_ripple_free_speed_range_is_quarter_to_half_bus_over_ke(derivation: Derivation) -> None:
    speeds = derivation["11"].row("set")
    assert isinstance(speeds, sp.Interval)
    assert _is_zero(speeds.start - U_d / (4 * k_e))
    assert _is_zero(speeds.end - U_d / (2 * k_e))
    assert not speeds.left_open
    assert not speeds.right_open
    # The ends are where Eq. 9's duty hits 1 and 0 (Eq. 11 with E = k_e n).
    duty = derivation["11"].row("")
    assert _is_zero(duty.subs(n, speeds.start) - 1)
    assert _is_zero(duty.subs(n, speeds.end))


# --- Commutation time against the 60 deg sector at the default spec ---


def _t_com_and_sector(
    derivation: Derivation, spec: Spec, speed_rpm: int
) -> tuple[sp.Expr, sp.Expr]:
    values = {
        U_d: _bus(spec),
        E: _emf(spec, speed_rpm),
        L: _q(spec.motor.phase_inductance_h),
        I: _q(spec.controller.braking_current_nominal_a),
    }
    assert speed_rpm > derivation["18"].row("boundary_speed").subs(
        {U_d: values[U_d], k_e: _q(spec.motor.back_emf_constant_v_per_rpm)}
    )
    t_com = derivation["20"].row("improved_high").subs(values)
    electrical_hz = sp.Integer(speed_rpm) * spec.motor.pole_pairs / 60
    return t_com, 1 / (6 * electrical_hz)


def test_commutation_fits_in_the_sector_at_4600_rpm(derivation: Derivation, spec: Spec) -> None:
    t_com, sector = _t_com_and_sector(derivation, spec, 4600)
    assert float(sector) == pytest.approx(2.17e-3, abs=5e-6)
    assert t_com < sector
    assert t_com == _point(spec_figures(derivation, spec), 4600).improved_t_com_s


def test_commutation_outlasts_the_sector_near_5000_rpm(derivation: Derivation, spec: Spec) -> None:
    t_com, sector = _t_com_and_sector(derivation, spec, 5000)
    assert t_com > sector
    # So the top speed must be clamped: the crossing lies between the two speeds,
    # and below the spec's speed_max.
    speed = sp.Symbol("speed", positive=True)
    values = {
        U_d: _bus(spec),
        E: _emf(spec, speed),
        L: _q(spec.motor.phase_inductance_h),
        I: _q(spec.controller.braking_current_nominal_a),
    }
    t_com_n = derivation["20"].row("improved_high").subs(values)
    (crossing,) = sp.solve(sp.Eq(t_com_n, 10 / (speed * spec.motor.pole_pairs)), speed)
    assert 4600 < crossing < 5000
    assert crossing < _q(spec.controller.speed_max_rpm)


# --- Caching ---


def test_derive_is_cached() -> None:
    first = derive()
    hits = derive.cache_info().hits
    start = time.perf_counter()
    for _ in range(1000):
        again = derive()
        assert again is first
    elapsed = time.perf_counter() - start
    assert derive.cache_info().hits == hits + 1000
    # A real derivation takes on the order of a second; 1000 cached calls take microseconds.
    assert elapsed < 0.1

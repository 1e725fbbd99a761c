"""The firmware form of the resistance-aware rule: derivation, integer prototype, target."""

from __future__ import annotations

import random
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

from codegen.derivation import derive
from codegen.derivation import symbols as s
from codegen.derivation.constant_pair import derive_firmware_rule
from codegen.fixedpoint.scaling import scaling
from codegen.improved_r_rule.accuracy import point_bound
from codegen.improved_r_rule.constants import RuleConstants, rule_constants
from codegen.improved_r_rule.design import RuleDesign, design_grid, design_rule
from codegen.improved_r_rule.fixed import edge_state, loop_terms, run_fixed
from codegen.improved_r_rule.reference import (
    FLAG_CANNOT_HOLD,
    FLAG_NOT_FINISHED,
    FLAG_SPEED_CLAMPED,
    RuleInputs,
    psi_arrays,
    psi_values,
    reference_points,
)
from codegen.improved_r_rule.table import error_at, lookup
from codegen.spec_loader import load_spec
from codegen.spec_model import Spec
from sim.drive import Drive
from sim.runs import Controller, simulate
from sim.scenario import Case, paper_edge
from sim.sil import prepare_cores

ROOT = Path(__file__).resolve().parents[1]
SPECS = ("paper_motor.yaml", "example_maxon_ec45_flat_48v.yaml")


@pytest.fixture(scope="module", params=SPECS)
def spec(request: pytest.FixtureRequest) -> Spec:
    return load_spec(ROOT / "spec" / request.param)


@pytest.fixture(scope="module")
def design(spec: Spec) -> RuleDesign:
    sc = scaling(spec, derive())
    return design_rule(rule_constants(spec, sc), sc.current_code_max)


def test_ramp_weight_should_be_the_minimax_of_a_linear_ramp() -> None:
    rule = derive_firmware_rule()
    assert rule.ramp_weight_mean == sp.Rational(1, 2)
    assert sp.simplify(rule.ramp_weight_minimax - (sp.sqrt(2) - 1)) == 0
    # The held sum at the edge is the flat sum, Eq. 15 without resistance.
    flat = rule.duty_sum_held.subs(s.R, 0).subs(sp.Symbol("x", nonnegative=True), 0)
    assert sp.simplify(flat - (2 - 4 * s.E / s.U_d)) == 0


def test_table_should_stay_within_its_error_bound(design: RuleDesign) -> None:
    table = design.rule.table
    rng = random.Random(3)
    for _ in range(3000):
        y_q = rng.randint(0, table.y_limit)
        y_value = y_q / 2**table.y_frac_bits
        got = lookup(table, y_q)
        bound = error_at(table, y_value)
        for value, exact, limit in zip(got, psi_values(y_value), bound, strict=True):
            assert abs(value / 2**16 - exact) <= limit


def _grid(c: RuleConstants, braking_codes: int) -> list[RuleInputs]:
    rng = random.Random(7)
    extra = [
        RuleInputs(
            rng.randint(c.period_low, c.period_high),
            rng.randint(c.bus_low, c.bus_high),
            c.current_offset + rng.randint(0, braking_codes),
        )
        for _ in range(60)
    ]
    return design_grid(c, braking_codes)[::5] + extra


def test_integer_prototype_should_match_the_reference_within_its_bounds(
    spec: Spec, design: RuleDesign
) -> None:
    rule = design.rule
    c = rule.constants
    sc = scaling(spec, derive())
    grid = _grid(c, sc.current_code_max)
    for inputs, ref in zip(grid, reference_points(c, grid), strict=True):
        got = run_fixed(rule, inputs).outputs
        bound = point_bound(rule, inputs, ref)
        exact_ticks = min(ref.ticks_exact, inputs.period_ticks)
        assert abs(got.commutation_ticks - exact_ticks) <= bound.ticks, inputs
        assert abs(got.on_counts - ref.on_exact) <= bound.duty_counts, inputs
        assert abs(got.off_counts - ref.off_exact) <= bound.duty_counts, inputs
        if not ref.outputs.flags:
            assert bound.ticks <= bound.time_allowance(float(c.time_target_ticks)), inputs
            assert bound.duty_counts <= c.duty_target_counts, inputs


def test_design_should_prove_every_intermediate(design: RuleDesign) -> None:
    assert design.ranges
    assert all(r.headroom_bits >= 0 for r in design.ranges)
    assert design.time_ratio <= 1.0 and design.duty_bound <= 1.0
    assert design.rule.table.flash_bytes <= 2048


def test_rule_should_flag_what_it_cannot_do(design: RuleDesign) -> None:
    c = design.rule.constants
    nominal_bus = (c.bus_low + c.bus_high) // 2
    slow = run_fixed(design.rule, RuleInputs(c.period_high, nominal_bus, c.current_offset + 300))
    assert slow.outputs.flags & FLAG_CANNOT_HOLD
    assert slow.outputs.on_counts == slow.outputs.off_counts == c.period_counts
    fast = run_fixed(design.rule, RuleInputs(c.period_low - 1, nominal_bus, c.current_offset))
    assert fast.outputs.flags & FLAG_SPEED_CLAMPED


@pytest.mark.parametrize("speed", [500.0, 3000.0, 4600.0])
def test_firmware_rule_should_hold_the_current_within_3_percent(
    spec: Spec, design: RuleDesign, speed: float
) -> None:
    """The generated C core (`improved_r`, through sim's software in the loop) at the
    simulated edge: bit for bit the integer prototype, and on the paper's motor within
    3 % in the switched plant."""
    controller = Controller(spec, prepare_cores(spec, ("improved_r",)))
    drive = Drive.from_spec(spec)
    case = Case(drive, paper_edge(), speed, drive.braking_current_a, "spec")
    command = controller.command("improved_r", case, case.pre_edge_duty)
    raw = command.core_outputs
    inputs = RuleInputs(
        raw["in.hall_period_ticks"], raw["in.bus_voltage_adc"], raw["in.phase_current_adc"]
    )
    prototype = run_fixed(design.rule, inputs).outputs
    assert (raw["turn_on_compare"], raw["turn_off_compare"], raw["commutation_ticks"]) == (
        prototype.on_counts,
        prototype.off_counts,
        prototype.commutation_ticks,
    )
    assert command.constant_duties and not prototype.flags
    assert controller.flag_names(command) in ((), ("HIGH_SPEED",))
    if spec.name == "paper_motor":
        run = simulate(case, command, "switched")
        assert run.metrics.finished
        assert abs(run.metrics.deviation_worst_pct) <= 3.0


def test_loop_intermediates_should_stay_inside_their_proven_ranges(design: RuleDesign) -> None:
    rule = design.rule
    c = rule.constants
    proven = {r.name: r for r in design.ranges}

    def inside(value: int, *names: str) -> bool:
        low = min(proven[n].low for n in names)
        high = max(proven[n].high for n in names)
        return low <= value <= high

    rng = random.Random(11)
    for _ in range(400):
        st = edge_state(
            rule,
            rng.randint(c.period_low, c.period_high),
            rng.randint(c.bus_low, c.bus_high),
            rng.randint(0, c.current_high),
        )
        assert inside(st.x, "X") and inside(2 * st.a, "2 A") and inside(st.s1, "S1")
        assert inside(st.s0, "S0 low", "S0 high")
        for x_q in (0, 1, rng.randint(0, 1 << rule.steps), 1 << rule.steps):
            t = loop_terms(rule, st, x_q)
            assert inside(t.y, "y (inside the table)")
            assert 0 <= t.e <= 1 << rule.unit_frac_bits
            assert inside(t.u1, "x psi")
            assert inside(t.total, "S low", "S high")
            assert inside(t.f2, "F2 low", "F2 high")
            assert inside(t.twice_g, "2g low", "2g high")


def test_generated_twin_should_be_the_integer_rule_bit_for_bit() -> None:
    """The checked-in improved_r twin (which the verifier holds equal to the C) computes
    what the proven integer rule computes, inside and outside the input box."""
    from verify.run import load_twin

    spec = load_spec(ROOT / "spec" / "paper_motor_improved_r.yaml")
    sc = scaling(spec, derive())
    rule = design_rule(rule_constants(spec, sc), sc.current_code_max).rule
    c = rule.constants
    twin = load_twin(ROOT / "generated" / spec.name)
    rng = random.Random(11)
    for n in range(2000):
        period = rng.randint(c.period_low, 65535 if n % 4 == 0 else c.period_high)
        bus = rng.randint(c.bus_low - 50, c.bus_high)
        current = rng.randint(0, 4095)
        timing = twin.commutation_timing(twin.bus_condition(bus), period, current, 0)
        want = run_fixed(rule, RuleInputs(period, bus, current)).outputs
        got = (timing.on, timing.off, timing.ticks)
        assert got == (want.on_counts, want.off_counts, want.commutation_ticks), (
            period,
            bus,
            current,
        )
        assert bool(timing.flags & twin.FLAG_TIME_CLAMPED) == bool(want.flags & FLAG_NOT_FINISHED)


def test_scalar_psi_should_agree_with_the_array_form() -> None:
    """The error bounds use the scalar psi, the reference the array form: one function."""
    values = np.concatenate([np.linspace(0.0, 0.05, 501), np.geomspace(0.02, 40.0, 500)])
    q1, q2 = psi_arrays(values)
    for k, value in enumerate(values):
        s1, s2 = psi_values(float(value))
        assert abs(s1 - q1[k]) <= 1e-12 and abs(s2 - q2[k]) <= 1e-12, value

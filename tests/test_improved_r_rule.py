"""The firmware form of the resistance-aware rule: derivation, integer prototype, target."""

from __future__ import annotations

import random
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

from codegen.core.module import build_core, twin_module
from codegen.derivation import derive
from codegen.derivation import symbols as s
from codegen.derivation.constant_pair import derive_firmware_rule
from codegen.fixedpoint.scaling import scaling
from codegen.methods.improved_r.accuracy import point_bound
from codegen.methods.improved_r.constants import RuleConstants, rule_constants
from codegen.methods.improved_r.design import RuleDesign, design_grid, design_rule
from codegen.methods.improved_r.reference import (
    FLAG_CANNOT_HOLD,
    FLAG_SPEED_CLAMPED,
    RuleInputs,
    psi_arrays,
    psi_values,
    reference_points,
)
from codegen.methods.improved_r.table import error_at, lookup
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


def _improved_r(spec: Spec) -> Spec:
    from dataclasses import replace

    return replace(spec, controller=replace(spec.controller, method="improved_r"))


@pytest.fixture(scope="module")
def design(spec: Spec) -> RuleDesign:
    core = build_core(_improved_r(spec))
    sc = core.scaling
    return design_rule(rule_constants(spec, sc), sc.current_code_max, core.limits)


@pytest.fixture(scope="module")
def twin(spec: Spec) -> object:
    """The printed integer rule (the same IR as the C)."""
    return twin_module(build_core(_improved_r(spec)))


def run_twin(twin: object, inputs: RuleInputs) -> tuple[int, int, int, int]:
    """(on, off, ticks, flags) of the printed rule at one input."""
    t = twin.commutation_timing(
        twin.bus_condition(inputs.bus_code), inputs.period_ticks, inputs.current_code, 0
    )  # type: ignore[attr-defined]
    return t.turn_on_compare, t.turn_off_compare, t.commutation_ticks, t.flags


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


def test_printed_rule_should_match_the_reference_within_its_bounds(
    spec: Spec, design: RuleDesign, twin: object
) -> None:
    rule = design.rule
    c = rule.constants
    sc = scaling(spec, derive())
    grid = _grid(c, sc.current_code_max)
    for inputs, ref in zip(grid, reference_points(c, grid), strict=True):
        on, off, ticks, _ = run_twin(twin, inputs)
        bound = point_bound(rule, inputs, ref)
        exact_ticks = min(ref.ticks_exact, inputs.period_ticks)
        assert abs(ticks - exact_ticks) <= bound.ticks, inputs
        assert abs(on - ref.on_exact) <= bound.duty_counts, inputs
        assert abs(off - ref.off_exact) <= bound.duty_counts, inputs
        if not ref.outputs.flags:
            assert bound.ticks <= bound.time_allowance(float(c.time_target_ticks)), inputs
            assert bound.duty_counts <= c.duty_target_counts, inputs


def test_design_should_prove_every_intermediate(design: RuleDesign) -> None:
    assert design.ranges
    assert all(r.headroom_bits >= 0 for r in design.ranges)
    assert design.time_ratio <= 1.0 and design.duty_bound <= 1.0
    assert design.rule.table.flash_bytes <= 2048
    assert set(design.widths) == {"x_kappa_i", "x_theta", "rho_x", "y_psi1", "x_x_psi2", "s1_x"}


def test_rule_should_flag_what_it_cannot_do(design: RuleDesign, twin: object) -> None:
    c = design.rule.constants
    nominal_bus = (c.bus_low + c.bus_high) // 2
    ref = reference_points(c, [RuleInputs(c.period_high, nominal_bus, c.current_offset + 300)])[0]
    assert ref.outputs.flags & FLAG_CANNOT_HOLD
    on, off, _, flags = run_twin(
        twin, RuleInputs(c.period_high, nominal_bus, c.current_offset + 300)
    )
    assert flags & twin.FLAG_FAIL_AREA_CLAMPED  # type: ignore[attr-defined]
    assert on == off == c.period_counts
    ref = reference_points(c, [RuleInputs(c.period_low - 1, nominal_bus, c.current_offset)])[0]
    assert ref.outputs.flags & FLAG_SPEED_CLAMPED
    *_, flags = run_twin(twin, RuleInputs(c.period_low - 1, nominal_bus, c.current_offset))
    assert flags == twin.FLAG_INPUT_SATURATED  # type: ignore[attr-defined]  # the safe state


@pytest.mark.parametrize("speed", [500.0, 3000.0, 4600.0])
def test_firmware_rule_should_hold_the_current_within_3_percent(
    spec: Spec, twin: object, speed: float
) -> None:
    """The generated C core (`improved_r`, through sim's software in the loop) at the
    simulated edge: bit for bit the printed rule, and on the paper's motor within
    3 % in the switched plant."""
    controller = Controller(spec, prepare_cores(spec, ("improved_r",)))
    drive = Drive.from_spec(spec)
    case = Case(drive, paper_edge(), speed, drive.braking_current_a, "spec")
    command = controller.command("improved_r", case, case.pre_edge_duty)
    raw = command.core_outputs
    inputs = RuleInputs(
        raw["in.hall_period_ticks"], raw["in.bus_voltage_adc"], raw["in.phase_current_adc"]
    )
    on, off, ticks, flags = run_twin(twin, inputs)
    assert (raw["turn_on_compare"], raw["turn_off_compare"], raw["commutation_ticks"]) == (
        on,
        off,
        ticks,
    )
    assert command.constant_duties and not flags & ~twin.FLAG_HIGH_SPEED  # type: ignore[attr-defined]
    assert controller.flag_names(command) in ((), ("HIGH_SPEED",))
    if spec.name == "paper_motor":
        run = simulate(case, command, "switched")
        assert run.metrics.finished
        assert abs(run.metrics.deviation_worst_pct) <= 3.0


def test_scalar_psi_should_agree_with_the_array_form() -> None:
    """The error bounds use the scalar psi, the reference the array form: one function."""
    values = np.concatenate([np.linspace(0.0, 0.05, 501), np.geomspace(0.02, 40.0, 500)])
    q1, q2 = psi_arrays(values)
    for k, value in enumerate(values):
        s1, s2 = psi_values(float(value))
        assert abs(s1 - q1[k]) <= 1e-12 and abs(s2 - q2[k]) <= 1e-12, value

"""The resistance-aware rule: derivation, the +-3 % target met by the generated C core
(`improved_r` through software in the loop), and Ipopt agreeing with it."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import sympy as sp

from codegen.derivation import symbols as s
from codegen.spec_loader import load_spec
from codegen.spec_model import Spec
from oracle.units import units
from sim.clamp import scan
from sim.drive import Drive
from sim.limits import limits, paper_time_s
from sim.optimise import optimise
from sim.resistance import derive_resistance_rule
from sim.runs import Controller, simulate
from sim.scenario import Case, paper_edge
from sim.sil import CoreSet, prepare_cores

ROOT = Path(__file__).resolve().parents[1]
#: The target: R = 0.21 ohm, spec braking current, 20 kHz, switched plant, 500-4600 rpm.
TARGET_SPEEDS = (*np.arange(500.0, 4600.0, 250.0), 4600.0)


@pytest.fixture(scope="module")
def spec() -> Spec:
    return load_spec(ROOT / "spec" / "paper_motor.yaml")


@pytest.fixture(scope="module")
def controller(spec: Spec) -> Controller:
    return Controller(spec, prepare_cores(spec, ("improved", "improved_r")))


def test_rule_should_reduce_to_the_papers_equations_without_resistance() -> None:
    rule = derive_resistance_rule()
    assert sp.simplify(rule.duty_sum_flat.subs(s.R, 0) - (2 - 4 * s.E / s.U_d)) == 0
    assert sp.simplify(rule.boundary_emf - (s.U_d + 3 * s.R * s.I) / 4) == 0
    limit = sp.limit(rule.commutation_time_low, s.R, 0, "+")
    assert sp.simplify(limit - s.I * s.L / (2 * s.E)) == 0


def test_boundary_should_move_up_with_resistance(spec: Spec) -> None:
    bounds = limits(Drive.from_spec(spec))
    assert bounds.boundary_paper_rpm == pytest.approx(2542.4, abs=0.1)
    assert bounds.boundary_r_rpm == pytest.approx((24 + 3 * 0.21 * 5) / (4 * 2.36e-3), rel=1e-9)
    assert bounds.paper_time_fits_below_rpm == pytest.approx(4800.0, abs=0.5)


@pytest.mark.parametrize("shape", ["spec", "flat"])
def test_improved_r_should_hold_the_current_within_3_percent(
    spec: Spec, controller: Controller, shape: str
) -> None:
    """The C core generated for the EMF (the spec's 120 deg trapezoid, and the paper's
    flat EMF through `back_emf_shape: flat`), on the switched plant with the port's
    carrier restarts and the Hall edge on a carrier boundary (phase 0), and on the
    averaged one: within 3 % from 500 to 4600 rpm, and the commutation ends on a carrier
    boundary. Phase 0 is the edge at the ripple's valley: at the worst carrier phase the
    switched plant reaches +5.6 % at 4600 rpm (tests/test_sim_carrier_phase.py, and the
    report judges by that)."""
    drive = Drive.from_spec(spec)
    assert drive.resistance_ohm == 0.21 and drive.pwm_frequency_hz == 20e3
    assert {500.0, 1500.0, 3000.0, 4600.0} <= {float(s) for s in TARGET_SPEEDS}
    counts = controller.period_counts
    hall = float(controller.cores.scaling.hall_clock_hz)
    carrier = round(hall / drive.pwm_frequency_hz)
    expected_core = controller.cores.shaped["flat"] if shape == "flat" else None
    worst = {}
    for speed in TARGET_SPEEDS:
        case = Case(drive, paper_edge(), float(speed), drive.braking_current_a, shape)
        if expected_core is not None:
            assert controller.core_for("improved_r", case) is expected_core
        command = controller.command("improved_r", case, case.pre_edge_duty)
        raw = command.core_outputs
        # The gate command is the core's integers, nothing else.
        assert command.method == "improved_r"
        assert command.on_duties == (raw["turn_on_compare"] / counts,)
        assert command.off_duties == (raw["turn_off_compare"] / counts,)
        assert command.commutation_time_s == raw["commutation_ticks"] / hall
        assert raw["in.hall_period_ticks"] == round(case.sector_time_s * hall)
        assert raw["commutation_ticks"] % carrier == 0  # a whole number of PWM periods
        assert controller.flag_names(command) in ((), ("HIGH_SPEED",))
        averaged = simulate(case, command, "averaged").metrics
        switched = simulate(case, command, "switched").metrics
        assert averaged.finished and switched.finished
        worst[float(speed)] = (switched.deviation_worst_pct, averaged.deviation_worst_pct)
    assert max(abs(v) for pair in worst.values() for v in pair) <= 3.0, worst
    # Not a flat line: the rule's residual sags and swells are there.
    switched_values = [v[0] for v in worst.values()]
    assert max(switched_values) - min(switched_values) > 1.0, worst


def test_improved_r_should_be_whatever_core_is_loaded(spec: Spec, controller: Controller) -> None:
    """The method is routed to the compiled library: calling it directly gives the same
    outputs, and swapping the library swaps the command."""
    drive = Drive.from_spec(spec)
    case = Case(drive, paper_edge(), 3000.0, drive.braking_current_a, "spec")
    command = controller.command("improved_r", case, case.pre_edge_duty)
    core = controller.cores.cores["improved_r"]
    assert core.method == "improved_r" and core.path.suffix == ".so"
    inputs = {k[3:]: v for k, v in command.core_outputs.items() if k.startswith("in.")}
    outputs = {k: v for k, v in command.core_outputs.items() if not k.startswith("in.")}
    assert core.commutate(inputs) == outputs
    improved = controller.cores.cores["improved"]
    swapped = Controller(spec, CoreSet(spec, {**controller.cores.cores, "improved_r": improved}))
    other = swapped.command("improved_r", case, case.pre_edge_duty)
    assert (
        other.core_outputs == controller.command("improved", case, case.pre_edge_duty).core_outputs
    )
    assert other.core_outputs != command.core_outputs


def test_improved_r_core_should_never_clamp_the_time_where_eq_20_does(
    spec: Spec, controller: Controller
) -> None:
    """Every Hall period of the speed range through both cores (nominal bus and current):
    the paper's core clamps Eq. 20 where the derivation says it exceeds 60 deg, the
    resistance-aware core (R and the EMF ramp in its model) nowhere."""
    drive = Drive.from_spec(spec)
    bounds = limits(drive)
    paper = scan(controller, drive, "improved", drive.bus_voltage_v, drive.braking_current_a)
    assert len(paper.clamped_rpm) == 1
    low, high = paper.clamped_rpm[0]
    # where Eq. 20's time reaches the latest end L(T) = T - ceil(T / 16) - G (the
    # oracle's reading of the guard and the 5 % margin), a little below where it fills
    # the sector (bounds.paper_time_fits_below_rpm)
    u = units(spec)
    hall = float(u.hall_hz)

    def past_latest(n: float) -> bool:
        period = round(drive.sector_time_s(n) * hall)
        return paper_time_s(drive, n) * hall > u.latest_end(period)

    lo, hi = drive.boundary_speed_rpm, bounds.paper_time_fits_below_rpm
    for _ in range(40):
        lo, hi = (lo, (lo + hi) / 2) if past_latest((lo + hi) / 2) else ((lo + hi) / 2, hi)
    assert hi < bounds.paper_time_fits_below_rpm - 10.0
    assert low == pytest.approx(hi, abs=2.0)
    assert high == pytest.approx(drive.speed_max_rpm, abs=1.0)
    rule = scan(controller, drive, "improved_r", drive.bus_voltage_v, drive.braking_current_a)
    assert rule.clamped_rpm == ()
    assert rule.fastest_rpm == pytest.approx(drive.speed_max_rpm, abs=1.0)


def test_improved_r_core_should_sit_near_the_constant_ipopt_optimum(
    spec: Spec, controller: Controller
) -> None:
    """With the trapezoidal EMF the C core's held sum is within a hundredth of the best
    constant pair's Ipopt finds on the averaged plant (the split differs: the core
    eases it so the commutation ends on a carrier boundary, at most one PWM period after
    the optimum's)."""
    drive = Drive.from_spec(spec)
    for speed in (1500.0, 4000.0):
        case = Case(drive, paper_edge(), speed, drive.braking_current_a, "spec")
        rule = controller.command("improved_r", case, case.pre_edge_duty)
        best = optimise(case, rule.on_duty(0), rule.off_duty(0), rule.commutation_time_s)
        assert best.finishes
        assert best.on_duty + best.off_duty == pytest.approx(
            rule.on_duty(0) + rule.off_duty(0), abs=0.01
        )
        assert 0.0 <= rule.commutation_time_s - best.commutation_time_s <= 1.05 * drive.pwm_period_s


def test_paper_rule_should_miss_the_target_at_high_speed(
    spec: Spec, controller: Controller
) -> None:
    drive = Drive.from_spec(spec)
    case = Case(drive, paper_edge(), 4600.0, drive.braking_current_a, "spec")
    run = simulate(case, controller.command("improved", case, case.pre_edge_duty), "switched")
    assert run.metrics.deviation_worst_pct < -20.0


def test_ipopt_optimum_should_match_the_rule_with_flat_emf(
    spec: Spec, controller: Controller
) -> None:
    """The rule's flat-EMF sum (what the per-period ideal emits on a flat plant)."""
    drive = Drive.from_spec(spec)
    for speed in (1500.0, 4000.0):
        case = Case(drive, paper_edge(), speed, drive.braking_current_a, "flat")
        rule = controller.command("improved_r_pp", case, case.pre_edge_duty)
        assert rule.method == "improved_r_pp" and not rule.core_outputs
        best = optimise(case, 1.0, 0.0, 1e-3)
        assert best.finishes
        assert best.rms_deviation_pct < 0.01
        assert best.on_duty == pytest.approx(rule.on_duty(0), abs=2e-3)
        assert best.off_duty == pytest.approx(rule.off_duty(0), abs=2e-3)
        assert best.commutation_time_s == pytest.approx(rule.commutation_time_s, rel=0.02)


def test_ipopt_should_solve_every_speed_of_the_sweep_to_its_tolerance(
    spec: Spec, controller: Controller
) -> None:
    """The optimum column of the report: Ipopt with the exact Hessian (second-order
    sensitivities through CVODES) ran out of iterations here at 2250 rpm, and in the
    report's sweep stopped with Error_In_Step_Computation at 3500 rpm, where it gave a
    worse pair as the optimum (0.338 % rms where 0.311 % is reachable). With a
    quasi-Newton Hessian every speed solves, at least as well, in a fifth of the time."""
    drive = Drive.from_spec(spec)
    solved = ("Solve_Succeeded", "Solved_To_Acceptable_Level")
    for speed in (1250.0, 2250.0, 3000.0, 3500.0, 4000.0, 4600.0):
        case = Case(drive, paper_edge(), speed, drive.braking_current_a, "spec")
        rule = controller.command("improved", case, case.pre_edge_duty)
        best = optimise(case, rule.on_duty(0), rule.off_duty(0), rule.commutation_time_s)
        assert best.solver_status in solved, (speed, best)
        assert best.finishes

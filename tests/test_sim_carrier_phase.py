"""The carrier phase of the Hall edge: the pre-edge current the commutation starts from,
and the simulation's verdicts taken at the worst phase, not at phase 0 (the edge on a
carrier boundary, the best case of a commutation that swells)."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from codegen.spec_loader import load_spec
from codegen.spec_model import Spec
from sim import sweep
from sim.carrier_phase import phase_grid, rising_branch, worst_over_phase
from sim.current_loop import settle
from sim.drive import Drive
from sim.report import TARGET_PCT
from sim.runs import IMPROVED_R, METHODS, Controller, simulate
from sim.scenario import Case, paper_edge, plant, pre_edge_state, schedule_for
from sim.sil import prepare_cores

ROOT = Path(__file__).resolve().parents[1]
#: 2 poles, 30 000 rpm, improved_r, 20 kHz edge-aligned: at 27 500 rpm (7.3 PWM periods a
#: sector, main duty 0.238) +2.8 % with the edge on a carrier boundary, +19 % at the peak.
MOTOR = ROOT / "tests" / "fixtures" / "odd" / "ir_pp1_30k_carrier_phase.yaml"
SPEED = 27500.0


@pytest.fixture(scope="module")
def spec() -> Spec:
    return load_spec(MOTOR)


def _edge_current(case: Case) -> float:
    """|i_off| at the Hall edge, from the steady pre-edge state the run starts from."""
    trace = plant("switched")(
        case.drive,
        case.emf,
        schedule_for(case, None, 0.0),
        case.start_time,
        0.0,
        pre_edge_state(case, "switched"),
    )
    return abs(float(trace.current_at(0.0)[case.edge.turn_off]))


def test_an_edge_just_past_a_carrier_boundary_should_find_the_ripple_at_its_valley(
    spec: Spec,
) -> None:
    """The current loop holds I as a whole period's mean, so an edge 0.1 % of a period
    past the boundary finds the current where the ripple is then, next to its valley. The
    start state had made the period the edge cuts short average I: at phase 0+ the edge
    found I itself, half a ripple above phase 0's valley (8.00 A against 7.29 A)."""
    drive = Drive.from_spec(spec)
    current = drive.braking_current_a
    at = {
        phase: _edge_current(Case(drive, paper_edge(), SPEED, current, "spec", phase))
        for phase in (0.0, 1e-3, 0.5)
    }
    ripple = 2.0 * (current - at[0.0])
    assert ripple > 0.1 * current  # the valley lies well below the mean here
    assert at[1e-3] == pytest.approx(at[0.0], abs=0.01 * ripple), at
    assert at[0.5] > at[0.0] + 0.2 * ripple, at  # on the falling branch, above the valley


@pytest.fixture(scope="module")
def controller(spec: Spec) -> Controller:
    return Controller(spec, prepare_cores(spec, METHODS))


def _case(spec: Spec, controller: Controller) -> tuple[Case, float]:
    drive = Drive.from_spec(spec)
    loop = settle(drive, SPEED, drive.braking_current_a, controller.period_counts)
    return Case(drive, paper_edge(), SPEED, loop.current_a, "spec"), loop.duty


@pytest.mark.parametrize("method", [IMPROVED_R, "improved"])
def test_the_worst_phase_should_be_found_where_phase_zero_is_the_best_case(
    spec: Spec, controller: Controller, method: str
) -> None:
    """improved_r: +2.8 % at phase 0, +19 % with the edge at the ripple's peak (phase D,
    where the modulated transistor turns off); improved: -13 % at phase 0, +14 % there.
    The search (the rising branch's ends and middle) finds what a 32-phase scan finds."""
    case, duty = _case(spec, controller)
    command = controller.command(method, case, duty)
    scan = worst_over_phase(case, command)
    assert abs(scan.at_zero.deviation_worst_pct) < 15.0
    assert scan.worst.metrics.deviation_worst_pct > 14.0
    assert scan.phase == pytest.approx(case.pre_edge_duty, abs=1e-9)  # the ripple's peak
    assert len(scan.samples) <= 3
    fine = [
        simulate(replace(case, carrier_phase=float(p)), command, "switched").metrics
        for p in np.arange(32) / 32
    ]
    finest = max(abs(m.deviation_worst_pct) for m in fine)
    assert abs(scan.worst.metrics.deviation_worst_pct) >= finest - 0.05
    if method == IMPROVED_R:
        assert abs(scan.at_zero.deviation_worst_pct) <= TARGET_PCT  # phase 0 passes


def test_a_sweep_row_should_be_judged_at_its_worst_phase(
    spec: Spec, controller: Controller
) -> None:
    """The report's verdict on improved_r reads the row's metrics: they are the worst
    phase's (+19 %, outside +-3 %), and the row keeps phase 0's (+2.8 %, inside) beside
    them. The row had been phase 0's alone, and the motor had passed."""
    case, duty = _case(spec, controller)
    job = sweep._Job(
        SPEED, IMPROVED_R, "switched", "spec", sweep.STEADY, duty, case.current_a, False
    )
    assert job.judged
    row = sweep._row(controller, case.drive, job)
    assert abs(row.metrics.deviation_worst_pct) > TARGET_PCT
    assert abs(row.at_phase_zero.deviation_worst_pct) <= TARGET_PCT
    assert row.carrier_phase == pytest.approx(duty, abs=1e-9)
    averaged = sweep._row(controller, case.drive, replace(job, model="averaged"))
    assert averaged.phase_zero is None and averaged.carrier_phase == 0.0


def test_the_operating_point_should_name_the_worst_phase(
    spec: Spec, controller: Controller
) -> None:
    """Its metrics are the worst phase's, its figure runs and phase_zero metrics phase 0's."""
    drive = Drive.from_spec(spec)
    point = sweep.operating_point(controller, drive, SPEED, 0.42)
    key = (IMPROVED_R, "switched", sweep.STEADY)
    assert point.metrics[key].deviation_worst_pct > 14.0
    assert abs(point.phase_zero[key].deviation_worst_pct) <= TARGET_PCT
    assert point.phases[key] == pytest.approx(point.settled.duty, abs=1e-9)
    assert point.runs[key].case.carrier_phase == 0.0
    assert point.phase_zero[key] == point.runs[key].metrics


def test_the_phase_grid_should_span_the_rising_branch(spec: Spec) -> None:
    """Edge-aligned: from the turn-on (phase 0) to the turn-off (phase D); centre-aligned:
    the on-time centred in the period."""
    drive = Drive.from_spec(spec)
    case = Case(drive, paper_edge(), SPEED, drive.braking_current_a, "spec", pre_duty=0.3)
    assert rising_branch(case) == (0.0, 0.3)
    assert phase_grid(case) == pytest.approx((0.0, 0.15, 0.3))
    centre = replace(case, drive=replace(drive, pwm_alignment="centre"))
    assert rising_branch(centre) == pytest.approx((0.35, 0.65))


def test_the_paper_motor_rule_should_leave_the_band_at_its_worst_phase() -> None:
    """The default motor's improved_r at 4600 rpm: +2.6 % with the edge on a carrier
    boundary, the figure the target had been met by, +5.6 % with it at the ripple's peak
    (phase D = 0.18): on the switched plant the +-3 % target is met at phase 0 only."""
    paper = load_spec(ROOT / "spec" / "paper_motor.yaml")
    rule = Controller(paper, prepare_cores(paper, (IMPROVED_R,)))
    drive = Drive.from_spec(paper)
    loop = settle(drive, 4600.0, drive.braking_current_a, rule.period_counts)
    case = Case(drive, paper_edge(), 4600.0, loop.current_a, "spec")
    scan = worst_over_phase(case, rule.command(IMPROVED_R, case, loop.duty))
    assert abs(scan.at_zero.deviation_worst_pct) <= TARGET_PCT
    assert scan.worst.metrics.deviation_worst_pct == pytest.approx(5.6, abs=0.1)
    assert scan.phase == pytest.approx(loop.duty, abs=1e-9)

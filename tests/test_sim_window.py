"""The deviation window is defined from the physics: every carrier period that
overlaps the commutation, plus the one after it. Held to the closed form of the
averaged commutation (`sim.analytic`, slopes from the derivation, not the plant)."""

from __future__ import annotations

from itertools import pairwise
from pathlib import Path

import numpy as np
import pytest

from codegen.spec_loader import load_spec
from sim.analytic import commutation_dip
from sim.drive import Drive
from sim.metrics import window_periods
from sim.runs import Controller, Run, simulate
from sim.scenario import Case, paper_edge
from sim.sil import prepare_cores

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def drive_and_controller() -> tuple[Drive, Controller]:
    spec = load_spec(ROOT / "spec" / "paper_motor.yaml")
    return Drive.from_spec(spec), Controller(spec, prepare_cores(spec, ("none", "conventional")))


def _run(drive: Drive, controller: Controller, method: str, speed: float) -> Run:
    case = Case(drive, paper_edge(), speed, drive.braking_current_a, "spec")
    return simulate(case, controller.command(method, case, case.pre_edge_duty), "switched")


def _closed_form(drive: Drive, run: Run) -> float:
    case, command = run.case, run.command
    ramp = 2.0 * drive.emf_v(case.speed_rpm) / case.sector_time_s  # 120 deg trapezoid
    return commutation_dip(
        command.on_duty(0),
        command.off_duty(0),
        drive.emf_v(case.speed_rpm),
        ramp,
        drive.bus_voltage_v,
        drive.resistance_ohm,
        drive.inductance_h,
        case.current_a,
        case.sector_time_s,
    ).deviation_pct


def test_none_should_be_worse_than_conventional_at_1000_rpm_as_the_closed_form_says(
    drive_and_controller: tuple[Drive, Controller],
) -> None:
    drive, controller = drive_and_controller
    none = _run(drive, controller, "none", 1000.0)
    conventional = _run(drive, controller, "conventional", 1000.0)
    expected_none, expected_conventional = (
        _closed_form(drive, none),
        _closed_form(drive, conventional),
    )
    assert expected_none == pytest.approx(-46.4, abs=0.5)
    assert expected_conventional == pytest.approx(-34.2, abs=1.0)
    assert none.metrics.deviation_worst_pct == pytest.approx(expected_none, abs=2.0)
    assert conventional.metrics.deviation_worst_pct == pytest.approx(expected_conventional, abs=2.0)
    assert none.metrics.deviation_worst_pct < conventional.metrics.deviation_worst_pct - 10.0
    # The instantaneous extreme is at least as deep as the deepest period mean.
    assert none.metrics.deviation_peak_pct <= none.metrics.deviation_worst_pct + 1e-9


def test_window_should_hold_the_period_of_the_turn_off_zero_and_the_next(
    drive_and_controller: tuple[Drive, Controller],
) -> None:
    drive, controller = drive_and_controller
    run = _run(drive, controller, "none", 1000.0)
    zero = run.metrics.commutation_fraction * run.case.sector_time_s
    starts, ends = run.trace.period_starts, run.trace.period_ends
    containing = int(np.flatnonzero((starts <= zero) & (ends > zero))[0])
    first = int(np.flatnonzero(starts >= -1e-12)[0])
    assert run.metrics.periods == containing - first + 2
    assert len(run.metrics.period_deviations_pct) == run.metrics.periods


def test_none_should_follow_the_closed_form_not_a_sawtooth_in_t_c_mod_t(
    drive_and_controller: tuple[Drive, Controller],
) -> None:
    """600-1480 rpm moves t_c / T from 3.6 to 4.5 periods. A window that drops the
    period holding t_c makes a sawtooth of about 15 points; the physical window stays
    within the per-period averaging of the closed form's dip."""
    drive, controller = drive_and_controller
    errors, old_errors = [], []
    for speed in np.arange(600.0, 1500.0, 40.0):
        run = _run(drive, controller, "none", float(speed))
        expected = _closed_form(drive, run)
        errors.append(run.metrics.deviation_worst_pct - expected)
        old_errors.append(_old_window_worst(run) - expected)
    assert max(abs(e) for e in errors) < 3.0, errors
    assert max(abs(b - a) for a, b in pairwise(errors)) < 2.0, errors
    # The old window (periods whose middle lies before the turn-off zero) on the same
    # runs: the sawtooth this replaces.
    assert max(abs(e) for e in old_errors) > 8.0, old_errors


def _old_window_worst(run: Run) -> float:
    trace, case = run.trace, run.case
    period = case.drive.pwm_period_s
    end = run.metrics.commutation_end_s
    starts = trace.period_starts
    inside = (starts >= -1e-12) & (starts + 0.5 * period <= max(end, period) + 1e-12)
    nc = case.edge.non_commutating
    sign = case.edge.current_signs[nc]
    deviation = (sign * trace.period_currents[inside, nc] - case.current_a) / case.current_a * 100
    return float(deviation[np.argmax(np.abs(deviation))])


@pytest.mark.parametrize("model", ["switched", "averaged"])
def test_a_commutation_ended_inside_the_first_pwm_period_is_measured_over_the_periods_it_cuts(
    model: str,
) -> None:
    """The 16-pole 5 kHz fixture at its top speed, 5000 rpm: a 250 us sector against a
    200 us carrier period. (At 7000 rpm, as the fixture was, its 179 us sector was shorter
    than a period: the window was empty and `measure` failed, argmax of an empty
    sequence, when the commutation, commanded to the whole sector, did not restart the
    carrier; such a sector is now shorter than the end's guard and refused at load.) The
    commutation ends the guard (1 us dead time + 4 us + one current sample: a 200 us
    period and the ADC's sequence, 212 ticks at 1 MHz) and the margin (1/16 of the
    sector, 16 ticks) early, 22 us after the edge: its carrier restart cuts the period
    after the edge there. That cut period, averaged over its own length as every cut
    period is, and the whole period after it are the window; the period from there to
    the next edge, which that edge cuts, is kept as the trace's cut period."""
    spec = load_spec(ROOT / "tests" / "fixtures" / "odd" / "short_sector_5k_16p.yaml")
    drive = Drive.from_spec(spec)
    controller = Controller(spec, prepare_cores(spec, ("none",)))
    case = Case(drive, paper_edge(), 5000.0, drive.braking_current_a, "spec")
    early_s = 212e-6 + 16e-6  # the guard and the margin
    assert case.sector_time_s - early_s < drive.pwm_period_s
    command = controller.command("none", case, case.pre_edge_duty)
    assert command.commutation_time_s == pytest.approx(case.sector_time_s - early_s, abs=1e-9)
    run = simulate(case, command, model)
    trace = run.trace
    restart = case.sector_time_s - early_s
    cut = trace.cut_period
    assert cut is not None
    assert cut[0] == pytest.approx(restart + drive.pwm_period_s, abs=1e-9)
    assert cut[1] == pytest.approx(case.sector_time_s)
    window = window_periods(trace, case.sector_time_s)
    assert window.sum() == 2 and run.metrics.periods == 2
    first, second = (int(k) for k in np.flatnonzero(window))
    assert trace.period_starts[first] == pytest.approx(0.0, abs=1e-12)
    assert trace.period_ends[first] == pytest.approx(restart)  # the end's restart
    assert trace.period_starts[second] == pytest.approx(restart)
    assert trace.period_ends[second] == pytest.approx(cut[0])
    nc = case.edge.non_commutating
    mean = case.edge.current_signs[nc] * trace.period_currents[[first, second], nc]
    expected = (mean - case.current_a) / case.current_a * 100
    assert run.metrics.period_deviations_pct == pytest.approx(tuple(expected))

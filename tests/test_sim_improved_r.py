"""The resistance-aware rule: derivation, the +-3 % target, and Ipopt agreeing with it."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import sympy as sp

from codegen.derivation import symbols as s
from codegen.spec_loader import load_spec
from codegen.spec_model import Spec
from sim.drive import Drive
from sim.limits import limits
from sim.optimise import optimise
from sim.resistance import derive_resistance_rule
from sim.runs import Controller, simulate
from sim.scenario import Case, paper_edge
from sim.sil import prepare_cores

ROOT = Path(__file__).resolve().parents[1]
#: The brief's target: R = 0.21 ohm, spec braking current, 20 kHz, switched plant.
TARGET_SPEEDS = (*np.arange(500.0, 4600.0, 250.0), 4600.0)


@pytest.fixture(scope="module")
def spec() -> Spec:
    return load_spec(ROOT / "spec" / "paper_motor.yaml")


@pytest.fixture(scope="module")
def controller(spec: Spec) -> Controller:
    return Controller(spec, prepare_cores(spec, ("improved",)))


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


@pytest.mark.parametrize("shape", ["trapezoidal", "flat"])
def test_improved_r_should_hold_the_current_within_3_percent(
    spec: Spec, controller: Controller, shape: str
) -> None:
    drive = Drive.from_spec(spec)
    assert drive.resistance_ohm == 0.21 and drive.pwm_frequency_hz == 20e3
    worst = {}
    for speed in TARGET_SPEEDS:
        case = Case(drive, paper_edge(), float(speed), drive.braking_current_a, shape)
        command = controller.command("improved_r", case, case.pre_edge_duty)
        run = simulate(case, command, "switched")
        assert run.metrics.finished
        worst[float(speed)] = run.metrics.deviation_worst_pct
    assert max(abs(v) for v in worst.values()) <= 3.0, worst


def test_paper_rule_should_miss_the_target_at_high_speed(
    spec: Spec, controller: Controller
) -> None:
    drive = Drive.from_spec(spec)
    case = Case(drive, paper_edge(), 4600.0, drive.braking_current_a, "trapezoidal")
    run = simulate(case, controller.command("improved", case, case.pre_edge_duty), "switched")
    assert run.metrics.deviation_worst_pct < -20.0


def test_ipopt_optimum_should_match_the_rule_with_flat_emf(
    spec: Spec, controller: Controller
) -> None:
    drive = Drive.from_spec(spec)
    for speed in (1500.0, 4000.0):
        case = Case(drive, paper_edge(), speed, drive.braking_current_a, "flat")
        rule = controller.command("improved_r", case, case.pre_edge_duty)
        best = optimise(case, 1.0, 0.0, 1e-3)
        assert best.finishes
        assert best.rms_deviation_pct < 0.01
        assert best.on_duty == pytest.approx(rule.on_duty(0), abs=2e-3)
        assert best.off_duty == pytest.approx(rule.off_duty(0), abs=2e-3)
        assert best.commutation_time_s == pytest.approx(rule.commutation_time_s, rel=0.02)

"""Figures are byte-stable; the report renders under strict undefined checks and says
what is simulated: every method of the firmware through the generated C core."""

from __future__ import annotations

from pathlib import Path

import pytest

from codegen.spec_loader import load_spec
from sim import sweep
from sim.drive import Drive
from sim.figures import all_figures, currents_figure
from sim.limits import limits
from sim.report import TARGET_HIGH_RPM, TARGET_LOW_RPM, TARGET_PCT, render_report
from sim.runs import METHODS, Controller
from sim.sil import prepare_cores
from sim.sweep import STEADY, OperatingPoint, operating_point, run_all

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def point() -> OperatingPoint:
    spec = load_spec(ROOT / "spec" / "paper_motor.yaml")
    controller = Controller(spec, prepare_cores(spec, METHODS))
    return operating_point(controller, Drive.from_spec(spec), 4600.0, 0.42)


def test_currents_figure_should_be_byte_identical_on_rerun(
    point: OperatingPoint, tmp_path: Path
) -> None:
    first, second = tmp_path / "a", tmp_path / "b"
    first.mkdir()
    second.mkdir()
    name = currents_figure(point, "improved", STEADY, first)
    assert currents_figure(point, "improved", STEADY, second) == name
    assert (first / name).read_bytes() == (second / name).read_bytes()
    assert b"matplotlib" not in (first / name).read_bytes()


def test_operating_point_should_show_the_fail_area_and_improved_r(point: OperatingPoint) -> None:
    assert "FAIL_AREA_CLAMPED" in point.flags[("conventional", "point")]
    run = point.runs[("improved_r", "switched", STEADY)]
    assert run.command.method == "improved_r"
    assert {"in.hall_period_ticks", "turn_on_compare", "commutation_ticks"} <= set(
        run.command.core_outputs
    )
    assert abs(point.metrics[("improved_r", "switched", STEADY)].deviation_worst_pct) < 3.0
    assert point.metrics[("improved", "switched", STEADY)].deviation_worst_pct < -20.0


def test_report_should_present_improved_r_as_the_c_core(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A coarse run of the whole pipeline (500 rpm steps, one optimum speed)."""
    monkeypatch.setattr(sweep, "SWEEP_STEP_RPM", 500.0)
    monkeypatch.setattr(sweep, "OPTIMUM_SPEEDS_RPM", (4000.0,))
    spec = load_spec(ROOT / "spec" / "paper_motor.yaml")
    results = run_all(spec, progress=False)
    bounds = limits(results.drive)
    names = all_figures(
        results, bounds.boundary_r_rpm, (TARGET_LOW_RPM, TARGET_HIGH_RPM, TARGET_PCT), tmp_path
    )
    text = render_report(results, bounds, names)
    assert "pending" not in text and "improved_r_fw" not in text
    assert "| `improved_r` | generated C core |" in text
    assert "The ±3 % target is **met** by the C core" in text
    # The per-speed target table holds the core's own integers at 4600 rpm.
    row = results.rows(
        method="improved_r",
        speed_rpm=4600.0,
        model="switched",
        emf_shape="spec",
        duty_policy=STEADY,
    )[0]
    raw = row.core_outputs
    assert f"| {raw['turn_on_compare']} / {raw['turn_off_compare']} |" in text
    assert f"| {raw['commutation_ticks']} / {raw['in.hall_period_ticks']} |" in text
    assert "`improved` clamps 4801-5000 rpm and\n`improved_r` nowhere." in text
    assert (tmp_path / names["target"]).exists()
    optimum = results.optima[0].worst_pct
    assert set(optimum) == {"optimum", *METHODS, "improved_r_pp"}

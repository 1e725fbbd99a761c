"""Figures are byte-stable; the report template renders under strict undefined checks."""

from __future__ import annotations

from pathlib import Path

import pytest

from codegen.spec_loader import load_spec
from sim.drive import Drive
from sim.figures import currents_figure
from sim.runs import Controller
from sim.sil import prepare_cores
from sim.sweep import STEADY, OperatingPoint, operating_point

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def point() -> OperatingPoint:
    spec = load_spec(ROOT / "spec" / "paper_motor.yaml")
    controller = Controller(spec, prepare_cores(spec, ("none", "conventional", "improved")))
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


def testoperating_point_should_show_the_fail_area_and_improved_r(point: OperatingPoint) -> None:
    assert "FAIL_AREA_CLAMPED" in point.flags[("conventional", "point")]
    assert abs(point.metrics[("improved_r", "switched", STEADY)].deviation_worst_pct) < 3.0

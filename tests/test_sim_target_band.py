"""The speeds SIMULATION.md judges the resistance-aware method's target over: the
default motor's 500-4600 rpm band where a motor's range holds it, the part of it inside
the range, or the whole range where the band misses it (the report had printed
"500 to 4600 rpm" above a 2-120 rpm motor's figures)."""

from __future__ import annotations

from pathlib import Path

import pytest

from codegen.spec_loader import load_spec
from sim.drive import Drive
from sim.report import TARGET_HIGH_RPM, TARGET_LOW_RPM, judged_band

ROOT = Path(__file__).resolve().parents[1]


@pytest.mark.parametrize(
    ("path", "inside"),
    [
        ("spec/paper_motor.yaml", True),
        ("tests/fixtures/odd/pp30_5_to_120rpm.yaml", False),
        ("tests/fixtures/odd/pp1_150k_centre_conv.yaml", False),
        ("tests/fixtures/odd/narrow_speed_4k.yaml", True),
    ],
)
def test_the_target_should_be_judged_over_speeds_the_motor_runs_at(path: str, inside: bool) -> None:
    drive = Drive.from_spec(load_spec(ROOT / path))
    low, high = judged_band(drive)
    assert drive.speed_min_rpm <= low < high <= drive.speed_max_rpm
    if inside:
        assert (low, high) == (
            max(TARGET_LOW_RPM, drive.speed_min_rpm),
            min(TARGET_HIGH_RPM, drive.speed_max_rpm),
        )
    else:
        assert (low, high) == (drive.speed_min_rpm, drive.speed_max_rpm)
    if path == "spec/paper_motor.yaml":
        assert (low, high) == (TARGET_LOW_RPM, TARGET_HIGH_RPM)

"""The Hall time-out's design (`codegen/control/hall_timeout.py`) against the PIL's own
physics (`emulation/pil/hall_timeout.py`): where the port waits 4 intervals, a turning
rotor of the worst motor the spec declares makes its next edge before; and the port
does not give up that wait much before the physics does."""

from __future__ import annotations

from pathlib import Path

import pytest

from codegen.control.hall_timeout import hall_timeout_design
from codegen.errors import SpecError
from codegen.spec_loader import load_spec
from emulation.pil.hall_timeout import hardest_braking, latest_next_edge_s

ROOT = Path(__file__).resolve().parents[1]
SPECS = [
    ROOT / "spec" / "paper_motor.yaml",
    ROOT / "spec" / "example_maxon_ec45_flat_48v.yaml",
    *sorted((ROOT / "tests" / "fixtures" / "specs").glob("*.yaml")),
    *sorted((ROOT / "tests" / "fixtures" / "pil").glob("*.yaml")),
    # with motor.viscous_friction: its torque at the top speed adds to the braking's
    ROOT / "tests" / "fixtures" / "odd" / "hv560_10mh_150deg.yaml",
    ROOT / "tests" / "fixtures" / "odd" / "pp50_20mh_slow_loop.yaml",
    ROOT / "tests" / "fixtures" / "odd" / "hall1125_1rpm.yaml",
    ROOT / "tests" / "fixtures" / "odd" / "kv5000_2p_windup.yaml",
]


def _loadable(path: Path) -> bool:
    try:
        load_spec(str(path))
    except SpecError:
        return False  # a fixture the loader refuses on purpose
    return True


@pytest.mark.parametrize("path", [p for p in SPECS if _loadable(p)], ids=lambda p: p.stem)
def test_the_time_out_should_wait_for_every_turning_rotor_and_not_much_longer(
    path: Path,
) -> None:
    spec = load_spec(str(path))
    design = hall_timeout_design(spec)
    hz = float(spec.hall.timer_clock_hz)
    wait = 1 << design.shift
    if design.period_max:
        # at the longest interval the port bounds (read a tick short), the next edge of a
        # turning rotor comes within the wait; below it the bound only tightens
        for ticks in (design.period_max, design.period_max // 2, design.period_max // 4):
            if ticks * spec.motor.pole_pairs * float(spec.controller.speed_max_rpm) < 10 * hz:
                continue  # over speed: refused, never timed
            latest = latest_next_edge_s(spec, (ticks + 1) / hz)
            assert latest is not None and latest * hz <= wait * ticks, (ticks, latest)
    top = (2**spec.hall.counter_bits - 1) >> design.shift
    beyond = round(design.period_max * 1.01) + 3
    if beyond <= top:
        # 1 % longer, the physics no longer bounds the edge within the wait (the port's
        # counts' margins are a few ticks)
        latest = latest_next_edge_s(spec, beyond / hz)
        assert latest is None or latest * hz > wait * (beyond - 3), (beyond, latest)


def test_the_paper_motor_should_wait_4_intervals_from_1255_rpm() -> None:
    design = hall_timeout_design(load_spec(str(ROOT / "spec" / "paper_motor.yaml")))
    assert (design.shift, design.period_max) == (2, 7971)
    assert design.speed_min_rpm is not None and round(design.speed_min_rpm) == 1255
    assert round(design.deceleration) == 5000  # 2 x 2.36 V/krpm x 1.1 x 120 A / 1.19 g m^2


def test_a_rotor_that_may_stop_in_any_sector_should_keep_the_counters_range(
    tmp_path: Path,
) -> None:
    """A rotor of 0.01 g m^2 braking at the bridge's rating may stop within a sector at
    every speed of the range: no interval is bounded, and the PIL finds no hardest
    braking to run."""
    text = (ROOT / "spec" / "paper_motor.yaml").read_text(encoding="utf-8")
    path = tmp_path / "light.yaml"
    path.write_text(
        text.replace("rotor_inertia: 0.00119 kg*m^2", "rotor_inertia: 0.00001 kg*m^2"),
        encoding="utf-8",
    )
    spec = load_spec(str(path))
    assert hall_timeout_design(spec).period_max == 0
    assert hall_timeout_design(spec).speed_min_rpm is None
    assert hardest_braking(spec) is None

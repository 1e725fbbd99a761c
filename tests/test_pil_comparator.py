"""The board's over-current comparator with the motor in the loop
(emulation/pil/comparator.py): its output follows the plant's largest |phase current|
against protection.over_current, a scenario may force it active, and the pin changes at
the chip's tick when the plant reaches the crossing."""

from __future__ import annotations

import numpy as np
import pytest

from emulation.pil.comparator import OverCurrentComparator
from emulation.pil.rcc import TICK_HZ


class _Pin:
    def __init__(self) -> None:
        self.now = 0
        self.changes: list[tuple[bool, int]] = []

    def drive(self, active: bool, at: int) -> None:
        self.changes.append((active, at))


def _points(*samples: tuple[float, tuple[float, float, float]]) -> list[tuple[float, np.ndarray]]:
    return [(t, np.array(i)) for t, i in samples]


def test_the_output_should_go_active_at_the_first_point_at_the_trip_and_idle_below_it() -> None:
    pin = _Pin()
    comparator = OverCurrentComparator(10.0, pin.drive, lambda: pin.now)
    pin.now = round(3e-6 * TICK_HZ)
    comparator.observe(_points((1e-6, (9.9, -5.0, -4.9)), (2e-6, (5.0, -10.0, 5.0))))
    assert pin.changes == [(True, pin.now)]  # the chip is at 3 us: the pin changes now
    cause, at, peak = comparator.trips[0]
    assert cause == round(2e-6 * TICK_HZ) and at == pin.now and peak == 10.0
    assert comparator.worst_lag_ticks == pin.now - cause
    comparator.observe(_points((4e-6, (-11.0, 6.0, 5.0))))
    assert len(pin.changes) == 1  # still over: no change
    pin.now = round(6e-6 * TICK_HZ)
    comparator.observe(_points((5e-6, (9.99, -5.0, -4.99))))
    assert pin.changes[-1] == (False, pin.now)
    assert comparator.peak_a == 11.0


def test_a_forced_output_should_stay_active_whatever_the_currents() -> None:
    pin = _Pin()
    comparator = OverCurrentComparator(10.0, pin.drive, lambda: pin.now)
    comparator.force(True)
    assert pin.changes == [(True, 0)]
    comparator.observe(_points((1e-6, (20.0, -10.0, -10.0)), (2e-6, (0.0, 0.0, 0.0))))
    assert pin.changes == [(True, 0)]
    comparator.force(False)
    assert pin.changes[-1] == (False, 0)


@pytest.mark.parametrize("trip", [0.0, -1.0, float("nan")])
def test_a_trip_level_not_above_zero_should_be_refused(trip: float) -> None:
    with pytest.raises(ValueError, match="trip level"):
        OverCurrentComparator(trip, lambda _a, _t: None, lambda: 0)

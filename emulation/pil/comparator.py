"""The board's over-current comparator, driven by the simulated motor's phase currents.

The drive's hardware protection is an external comparator on TIM1's BKIN
(`protection.over_current`, `protection.break_input`: codegen/port_faults.py, "the
external comparator saw a phase current above protection.over_current"). With the motor
in the loop its input is the plant's phase currents: the output is active while the
largest |i_x| is at or above the trip level, idle below it, and the board's pin
follows at the spec's polarity. A scenario may also force the output active (a
comparator that fires on its own, `force`): the pin is then active whatever the
currents.

The plant is advanced lazily (emulation/pil/plant.py: at every ADC sample instant
converted, every PWM period start and every Hall crossing; ADC2's current conversions
are counted unconverted only while the plant's bound keeps every phase current under
the trip, emulation/pil/braking.py `ShuntSense`), and the comparator looks at every
point of every exact piece it integrates: the first point at or above the trip is the
crossing. The chip has run up to the plant's instant when it is advanced, so the pin
changes at the chip's tick then (`worst_lag_ticks` after the crossing): at most the time
between two advances, under one PWM period, which the report states. The real
comparator's own delay (a few hundred ns) is left out.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

import numpy as np

from emulation.pil.rcc import TICK_HZ


class OverCurrentComparator:
    """Watches the plant's pieces (`MotorPlant.current_watchers`); `drive(level, tick)`
    sets the comparator's output on the board's pin from `tick` on (active: True)."""

    def __init__(
        self, trip_a: float, drive: Callable[[bool, int], None], now: Callable[[], int]
    ) -> None:
        if not trip_a > 0.0:
            raise ValueError(f"the comparator's trip level must be above 0 A, not {trip_a!r}")
        self.trip_a = trip_a
        self._drive = drive
        self._now = now
        self.forced = False
        self.sees_over_current = False
        self.output = False
        #: (tick the currents crossed the trip level, tick the pin went active, peak A)
        self.trips: list[tuple[int, int, float]] = []
        #: the largest |phase current| seen, A
        self.peak_a = 0.0

    def force(self, active: bool) -> None:
        """The output held active (a comparator firing on its own), or let follow the currents."""
        self.forced = active
        self._update(self._now(), self._now())

    def observe(self, points: Sequence[tuple[float, np.ndarray]]) -> None:
        """One piece of the plant: (seconds, phase currents) at each of its steps."""
        for t, currents in points:
            # max(|i|) on Python floats: numpy's per-call overhead, at every step
            peak = max(abs(current) for current in currents.tolist())
            self.peak_a = max(self.peak_a, peak)
            over = peak >= self.trip_a
            if over != self.sees_over_current:
                self.sees_over_current = over
                tick = round(t * TICK_HZ)
                self._update(tick, self._now())

    def _update(self, cause: int, now: int) -> None:
        level = self.forced or self.sees_over_current
        if level == self.output:
            return
        self.output = level
        at = max(cause, now)
        if level:
            peak = self.peak_a if self.sees_over_current else 0.0
            self.trips.append((cause, at, peak))
        self._drive(level, at)

    @property
    def worst_lag_ticks(self) -> int:
        """The longest time from a crossing to the pin going active, ticks."""
        return max((at - cause for cause, at, _ in self.trips), default=0)

"""What a plant run returns: the current waveform, per-PWM-period averages, events.

Per-period averages are what the paper's comparisons are about (the non-commutating
current "remains constant" up to the PWM ripple), so both plants integrate the
currents and the electrical power sum e_x i_x exactly over each carrier period (a
period that a carrier restart cuts short is averaged over its own length).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from sim.schedule import Schedule


@dataclass(frozen=True)
class Event:
    time: float
    kind: str  # "zero": a current reached zero; "conducts": a floating phase started
    phase: int


def events_at(
    time: float, event: Event, carried: Sequence[float], left: Sequence[float]
) -> list[Event]:
    """`event` at `time`, and where it is a zero, one more for each other phase whose
    current went to zero with it (`carried` the currents at the start of the step that
    ends at the event, `left` after it and the balance): in a star winding the last two
    conducting phases reach zero together, the lone phase left cannot carry current.
    Recorded for the first only, a turn-off current that died with the non-commutating
    one had no zero (a measured EMF with a negative lobe: the two runs of one
    commutation tied which phase's zero came first, windows of 26 and 43 periods)."""
    events = [Event(time, event.kind, event.phase)]
    if event.kind == "zero":
        events += [
            Event(time, "zero", k)
            for k in range(3)
            if k != event.phase and carried[k] != 0.0 and left[k] == 0.0
        ]
    return events


@dataclass(frozen=True)
class Transition:
    time: float
    switch: int  # 0..5
    on: bool


@dataclass(frozen=True)
class Trace:
    model: str  # "switched" or "averaged"
    times: np.ndarray  # (N,)
    currents: np.ndarray  # (N, 3)
    #: Carrier periods fully inside the run: start and end time, mean currents, power.
    period_starts: np.ndarray  # (K,)
    period_ends: np.ndarray  # (K,)
    period_currents: np.ndarray  # (K, 3)
    period_power: np.ndarray  # (K,) mean of sum e_x i_x, W
    events: tuple[Event, ...]
    transitions: tuple[Transition, ...]
    #: The last carrier period the run covers in part (it ends inside it): start, end of
    #: the coverage, mean currents (3,) and power over the part covered; None if none.
    cut_period: tuple[float, float, np.ndarray, float] | None = None

    def current_at(self, t: float) -> np.ndarray:
        return np.array([np.interp(t, self.times, self.currents[:, k]) for k in range(3)])

    def first_zero(self, phase: int, after: float = 0.0) -> float | None:
        for event in self.events:
            if event.kind == "zero" and event.phase == phase and event.time >= after:
                return event.time
        return None

    def transitions_of(self, switch: int, start: float, end: float) -> int:
        return sum(1 for t in self.transitions if t.switch == switch and start <= t.time < end)

    def turn_ons_of(self, switch: int, start: float, end: float) -> int:
        return sum(
            1 for t in self.transitions if t.switch == switch and t.on and start <= t.time < end
        )


@dataclass
class TraceBuilder:
    """Accumulates a run; `finish` freezes it."""

    model: str
    schedule: Schedule
    times: list[float] = field(default_factory=list)
    currents: list[np.ndarray] = field(default_factory=list)
    events: list[Event] = field(default_factory=list)
    transitions: list[Transition] = field(default_factory=list)
    _charge: dict[int, np.ndarray] = field(default_factory=dict)
    _energy: dict[int, float] = field(default_factory=dict)
    _covered: dict[int, float] = field(default_factory=dict)

    def point(self, t: float, currents: np.ndarray) -> None:
        self.times.append(t)
        self.currents.append(np.array(currents, dtype=float))

    def accumulate(
        self, period: int, duration: float, charge: Sequence[float], energy: float
    ) -> None:
        """Add int i dt (3,) and int sum e i dt over `duration` seconds of `period`."""
        if period not in self._charge:
            self._charge[period] = np.zeros(3)
            self._energy[period] = 0.0
            self._covered[period] = 0.0
        self._charge[period] += charge
        self._energy[period] += energy
        self._covered[period] += duration

    def finish(self) -> Trace:
        bounds = {k: self.schedule.period_bounds(k) for k in self._covered}
        length = {k: hi - lo for k, (lo, hi) in bounds.items()}
        slack = 1e-9 * self.schedule.period
        full = sorted(
            k for k, d in self._covered.items() if length[k] > 0 and d >= length[k] - slack
        )
        starts = np.array([bounds[k][0] for k in full])
        ends = np.array([bounds[k][1] for k in full])
        mean_i = np.array([self._charge[k] / length[k] for k in full]).reshape(-1, 3)
        power = np.array([self._energy[k] / length[k] for k in full])
        cut = None
        part = [k for k, d in self._covered.items() if d > slack and k not in full]
        if part and max(part) > max(full, default=max(part) - 1):
            k = max(part)
            covered = self._covered[k]
            cut = (
                bounds[k][0],
                bounds[k][0] + covered,
                self._charge[k] / covered,
                self._energy[k] / covered,
            )
        return Trace(
            model=self.model,
            times=np.array(self.times),
            currents=np.array(self.currents).reshape(-1, 3),
            period_starts=starts,
            period_ends=ends,
            period_currents=mean_i,
            period_power=power,
            events=tuple(self.events),
            transitions=tuple(self.transitions),
            cut_period=cut,
        )

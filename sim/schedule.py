"""What each of the six transistors does over time: duties per interval and the carrier.

Both plants read the same schedule: the averaged plant uses the duties, the switched
plant expands them into gate edges on the PWM carrier. A compare value change takes
effect immediately.

Carrier: period T. The STM32 port raises TIM1's update event (EGR.UG) together with
every COM event, at the Hall edge and again at the end of the commutation, so the
counter restarts there: the carrier runs from each restart r_j in periods
[r_j + k T, r_j + (k + 1) T), and the period that a later restart cuts short ends at
that restart (`restarts`, the first is the Hall edge at t = 0; before it the carrier
is aligned to it). Edge-aligned, a duty d switches on at the period start for d T;
centre-aligned, the on-time is centred in the (nominal) period.
"""

from __future__ import annotations

import bisect
import math
from dataclasses import dataclass
from functools import cached_property

from codegen.spec_model import PwmAlignment

SWITCHES = 6
OFF: tuple[float, ...] = (0.0,) * SWITCHES
#: Relative slack on carrier-period arithmetic (times are sums of floats).
_EPS = 1e-9


def switch_name(index: int) -> str:
    """0..5 -> T1..T6 (T1/T2, T3/T4, T5/T6: upper/lower of phases A, B, C)."""
    return f"T{index + 1}"


def switch_index(name: str) -> int:
    return int(name[1:]) - 1


@dataclass(frozen=True)
class Segment:
    start: float
    end: float
    duties: tuple[float, ...]


@dataclass(frozen=True)
class Schedule:
    segments: tuple[Segment, ...]
    period: float
    alignment: PwmAlignment
    #: Carrier restarts (update events), ascending; the first is the carrier's origin.
    restarts: tuple[float, ...] = (0.0,)
    #: Centre-aligned only. False: the on-time is centred in the period. True: as TIM1
    #: runs PWM mode 1 centre-aligned from a counter restarted at 0 (the STM32 port): on
    #: while CNT < CCRx, so centred on the period's boundaries, half at each end.
    on_at_boundaries: bool = False

    @property
    def start(self) -> float:
        return self.segments[0].start

    @property
    def end(self) -> float:
        return self.segments[-1].end

    @property
    def origin(self) -> float:
        return self.restarts[0]

    @cached_property
    def _starts(self) -> tuple[float, ...]:
        return tuple(s.start for s in self.segments)

    def duties_at(self, t: float) -> tuple[float, ...]:
        index = max(bisect.bisect_right(self._starts, t) - 1, 0)
        return self.segments[index].duties

    @cached_property
    def _bases(self) -> tuple[int, ...]:
        """Index of the first carrier period after each restart (computed once: the
        schedule is immutable and the plants ask at every piece)."""
        bases = [0]
        for lo, hi in zip(self.restarts, self.restarts[1:], strict=False):
            bases.append(bases[-1] + max(math.ceil((hi - lo) / self.period - _EPS), 0))
        return tuple(bases)

    def period_index(self, t: float) -> int:
        """Global index of the carrier period that contains t (0: first after the edge)."""
        j = bisect.bisect_right(self.restarts, t + _EPS * self.period) - 1
        if j < 0:
            return math.floor((t - self.origin) / self.period + _EPS)
        return self._bases[j] + math.floor((t - self.restarts[j]) / self.period + _EPS)

    def period_bounds(self, index: int) -> tuple[float, float]:
        """(start, end) of carrier period `index`; the end is cut by a later restart."""
        if index < 0:
            start = self.origin + index * self.period
            return start, start + self.period
        bases = self._bases
        j = bisect.bisect_right(bases, index) - 1
        start = self.restarts[j] + (index - bases[j]) * self.period
        end = start + self.period
        if j + 1 < len(self.restarts):
            end = min(end, self.restarts[j + 1])
        return start, end

    def period_start(self, index: int) -> float:
        return self.period_bounds(index)[0]

    def _on_window(self, duty: float, index: int) -> tuple[float, float]:
        start = self.period_start(index)
        if self.alignment == "edge":
            return start, start + duty * self.period
        half = 0.5 * (1.0 - duty) * self.period
        return start + half, start + self.period - half

    def _split(self) -> bool:
        return self.alignment != "edge" and self.on_at_boundaries

    def gate(self, duty: float, t: float) -> bool:
        if duty >= 1.0:
            return True
        if duty <= 0.0:
            return False
        if self._split():
            start = self.period_start(self.period_index(t))
            half = 0.5 * duty * self.period
            return t < start + half or t >= start + self.period - half
        on, off = self._on_window(duty, self.period_index(t))
        return on <= t < off

    def gates_at(self, t: float) -> tuple[float, ...]:
        """Gate state (1.0 on, 0.0 off) of each switch at t."""
        return tuple(1.0 if self.gate(d, t) else 0.0 for d in self.duties_at(t))

    def breakpoints(self, t0: float, t1: float, gate_edges: bool) -> list[float]:
        """Sorted times in [t0, t1]: segment and carrier-period boundaries, and, for the
        switched plant, every gate edge."""
        times = {t0, t1}
        for segment in self.segments:
            for t in (segment.start, segment.end):
                if t0 < t < t1:
                    times.add(t)
        first = self.period_index(t0)
        last = self.period_index(t1)
        for k in range(first, last + 1):
            start = self.period_start(k)
            if t0 < start < t1:
                times.add(start)
        if gate_edges:
            for segment in self.segments:
                lo, hi = max(segment.start, t0), min(segment.end, t1)
                if hi <= lo:
                    continue
                for k in range(self.period_index(lo), self.period_index(hi) + 1):
                    period_end = self.period_bounds(k)[1]
                    for duty in set(segment.duties):
                        if 0.0 < duty < 1.0:
                            start = self.period_start(k)
                            half = 0.5 * duty * self.period
                            window = (
                                (start + half, start + self.period - half)
                                if self._split()
                                else self._on_window(duty, k)
                            )
                            for t in window:
                                if lo < t < hi and t < period_end:
                                    times.add(t)
        return sorted(times)

"""Back-EMF of the three phases around one commutation, at constant speed.

Time t = 0 is the Hall edge being simulated. Two shapes:

* spec: the motor's own waveform, `motor.back_emf_shape` of the spec (default the
  paper's ideal trapezoid with 120 deg flat tops and linear 60 deg transitions): a
  piecewise-linear half period per unit of E from the phase's rising zero crossing,
  negated for the other half. Each phase's zero crossing is placed 30 deg after the
  Hall edge at which that phase starts to ramp (the ramping phase of a sector is the
  one whose `Sector.emf_signs` entry is 0 in the derived switching table), so the
  shape and the Hall code agree by construction. For the 120 deg trapezoid the
  outgoing phase starts its ramp exactly at the edge, which the paper's analysis
  ignores; a wider flat top starts it later and steeper, a narrower one earlier.
* flat: the paper's idealisation (section 3.2, "e_a = E, e_b = -E, e_c = -E"): the
  EMFs are frozen at their values at the edge for the whole simulated window.

Both are affine in time between corners (the times at which a phase passes a point
of the table), which is what lets the switched plant integrate exactly.
"""

from __future__ import annotations

import math
from bisect import bisect_right
from dataclasses import dataclass
from functools import cached_property
from typing import Literal

import numpy as np

from codegen.derivation.switching import Edge, Sector

EmfShape = Literal["spec", "flat"]
EMF_SHAPES: tuple[EmfShape, ...] = ("spec", "flat")
#: The paper's ideal trapezoid as (angle deg, e/E) points of a half period.
TRAPEZOID_120: tuple[tuple[float, float], ...] = (
    (0.0, 0.0),
    (30.0, 1.0),
    (150.0, 1.0),
    (180.0, 0.0),
)


def rising_zero_deg(sectors: tuple[Sector, ...], phase: int) -> float:
    """Electrical angle of `phase`'s rising zero crossing (forward rotation): the middle
    of the sector in which it ramps from -E to +E."""
    for k in range(6):
        if (
            sectors[k].emf_signs[phase] == 0
            and sectors[(k - 1) % 6].emf_signs[phase] < 0
            and sectors[(k + 1) % 6].emf_signs[phase] > 0
        ):
            return 60.0 * k + 30.0
    raise ValueError(f"phase {phase} has no rising ramp in the switching table")


@dataclass(frozen=True)
class Waveform:
    """A half period of one phase's EMF per unit E, (angle deg, value) from 0 to 180."""

    points: tuple[tuple[float, float], ...] = TRAPEZOID_120

    def __call__(self, angle_deg: float) -> float:
        """Value at `angle_deg` from the rising zero crossing, any angle."""
        angle = angle_deg % 360.0
        sign = 1.0
        if angle >= 180.0:
            angle -= 180.0
            sign = -1.0
        return sign * _interp(angle, self._angles, self._values)

    @cached_property
    def _angles(self) -> tuple[float, ...]:
        return tuple(float(a) for a, _ in self.points)

    @cached_property
    def _values(self) -> tuple[float, ...]:
        return tuple(float(v) for _, v in self.points)

    def many(self, angles_deg: np.ndarray) -> np.ndarray:
        """`self(angle)` for each of `angles_deg`, the same arithmetic on arrays."""
        angle = np.mod(angles_deg, 360.0)
        upper = angle >= 180.0
        angle = np.where(upper, angle - 180.0, angle)
        sign = np.where(upper, -1.0, 1.0)
        angles = [a for a, _ in self.points]
        values = [v for _, v in self.points]
        return sign * np.interp(angle, angles, values)

    def corner_angles(self) -> tuple[float, ...]:
        """Angles in [0, 360) where the slope changes."""
        full = [(a, v) for a, v in self.points] + [(a + 180.0, -v) for a, v in self.points[1:]]
        out = set()
        for k, (angle, _) in enumerate(full):
            before = full[k - 1] if k > 0 else (full[-2][0] - 360.0, full[-2][1])
            after = full[k + 1] if k + 1 < len(full) else (full[1][0] + 360.0, full[1][1])
            left = (full[k][1] - before[1]) / (angle - before[0])
            right = (after[1] - full[k][1]) / (after[0] - angle)
            if abs(left - right) > 1e-12:
                out.add(angle % 360.0)
        return tuple(sorted(out))


def _interp(x: float, xs: tuple[float, ...], ys: tuple[float, ...]) -> float:
    """`np.interp(x, xs, ys)` for one x, in the same arithmetic (numpy's own per-call
    overhead was a large part of the switched plant's time)."""
    if x < xs[0]:
        return ys[0]
    if x >= xs[-1]:
        return ys[-1]
    j = bisect_right(xs, x) - 1
    if x == xs[j]:
        return ys[j]
    slope = (ys[j + 1] - ys[j]) / (xs[j + 1] - xs[j])
    return slope * (x - xs[j]) + ys[j]


def trapezoid(sectors: tuple[Sector, ...], phase: int, angle_deg: float) -> float:
    """Forward-rotation EMF of `phase` per unit E at electrical angle `angle_deg` for
    the paper's 120 deg trapezoid."""
    return Waveform()(angle_deg - rising_zero_deg(sectors, phase))


@dataclass(frozen=True)
class BackEmf:
    shape: EmfShape
    edge: Edge
    sectors: tuple[Sector, ...]
    #: Flat-top value E = k_e n in volts.
    amplitude_v: float
    sector_time_s: float
    waveform: Waveform = Waveform()
    #: The rotor passed the edge's angle this long before t = 0: the emulated drive's
    #: time 0 is the COM event its Hall edge's handler raises, after the Hall lines
    #: changed (TIM3's input filter, the EXTI's and the edge handler's entry).
    lead_s: float = 0.0

    @property
    def _direction(self) -> float:
        return 1.0 if self.edge.direction == "forward" else -1.0

    def _angle(self, t: float) -> float:
        return self.edge.angle_deg + self._direction * 60.0 * (t + self.lead_s) / self.sector_time_s

    @cached_property
    def _rising_zeros(self) -> tuple[float, ...]:
        return tuple(rising_zero_deg(self.sectors, p) for p in range(3))

    def values(self, t: float) -> np.ndarray:
        if self.shape == "flat":
            return self.amplitude_v * np.asarray(self.edge.emf_signs, dtype=float)
        # Forward: the angle grows through the edge; reverse: it falls and the EMF of
        # every phase is negated (paper 2.2).
        angle = self._angle(t)
        scale = self._direction * self.amplitude_v
        return np.array([scale * self.waveform(angle - zero) for zero in self._rising_zeros])

    def values_many(self, times: np.ndarray) -> np.ndarray:
        """`values(t)` for each of `times`, one row each, the same arithmetic on arrays."""
        if self.shape == "flat":
            return np.tile(self.values(0.0), (len(times), 1))
        angle = (
            self.edge.angle_deg
            + self._direction * 60.0 * (np.asarray(times) + self.lead_s) / self.sector_time_s
        )
        columns = [self.waveform.many(angle - rising_zero_deg(self.sectors, p)) for p in range(3)]
        return self._direction * self.amplitude_v * np.stack(columns, axis=1)

    def affine(self, t0: float, t1: float) -> tuple[np.ndarray, np.ndarray]:
        """(e0, e1) with e(t) = e0 + e1 t on [t0, t1], which must not contain a corner."""
        if self.shape == "flat" or t1 <= t0:
            return self.values(t0), np.zeros(3)
        # Sample inside the piece: exact for an affine piece, and at a corner on its
        # boundary it takes the piece's own side.
        a, b = t0 + 0.25 * (t1 - t0), t0 + 0.75 * (t1 - t0)
        start, end = self.values(a), self.values(b)
        slope = (end - start) / (b - a)
        return start - slope * a, slope

    def corners(self, t0: float, t1: float) -> list[float]:
        """Times in (t0, t1) where the EMF slope of some phase changes."""
        if self.shape == "flat":
            return []
        rate = self._direction * 60.0 / self.sector_time_s  # deg per second
        out: set[float] = set()
        for phase in range(3):
            zero = rising_zero_deg(self.sectors, phase)
            for corner in self.waveform.corner_angles():
                # angle(t) - zero = corner + 360 k, angle(t) = angle_deg + rate (t + lead)
                base = zero + corner - self.edge.angle_deg
                s0, s1 = (t0 + self.lead_s) * rate, (t1 + self.lead_s) * rate
                lo = (min(s0, s1) - base) / 360.0
                hi = (max(s0, s1) - base) / 360.0
                for k in range(math.floor(lo), math.ceil(hi) + 1):
                    t = (base + 360.0 * k) / rate - self.lead_s
                    if t0 < t < t1:
                        out.add(round(t, 15))
        return sorted(out)

"""Back-EMF of the three phases around one commutation, at constant speed.

Time t = 0 is the Hall edge being simulated. Two shapes:

* trapezoidal: each phase has 120 deg flat tops at +-E joined by 60 deg linear
  transitions. Which phase is flat or ramping in which sector comes from the derived
  switching table (`Sector.emf_signs`: 0 marks the ramping phase), so the shape and
  the Hall code agree by construction. The outgoing phase starts its ramp exactly at
  the edge, which the paper's analysis ignores.
* flat: the paper's idealisation (section 3.2, "e_a = E, e_b = -E, e_c = -E"): the
  EMFs are frozen at their values at the edge for the whole simulated window.

Both are affine in time between corners, which is what lets the switched plant
integrate exactly. Corners of the trapezoid fall on Hall edges (multiples of the
sector time from t = 0).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

import numpy as np

from codegen.derivation.switching import Edge, Sector

EmfShape = Literal["trapezoidal", "flat"]
EMF_SHAPES: tuple[EmfShape, ...] = ("trapezoidal", "flat")


def trapezoid(sectors: tuple[Sector, ...], phase: int, angle_deg: float) -> float:
    """Forward-rotation EMF of `phase` per unit E at electrical angle `angle_deg`."""
    position = (angle_deg % 360.0) / 60.0
    k = math.floor(position) % 6
    sign = sectors[k].emf_signs[phase]
    if sign != 0:
        return float(sign)
    before = sectors[(k - 1) % 6].emf_signs[phase]
    after = sectors[(k + 1) % 6].emf_signs[phase]
    fraction = position - math.floor(position)
    return before + (after - before) * fraction


@dataclass(frozen=True)
class BackEmf:
    shape: EmfShape
    edge: Edge
    sectors: tuple[Sector, ...]
    #: Flat-top value E = k_e n in volts.
    amplitude_v: float
    sector_time_s: float

    def values(self, t: float) -> np.ndarray:
        if self.shape == "flat":
            return self.amplitude_v * np.asarray(self.edge.emf_signs, dtype=float)
        # Forward: the angle grows through the edge; reverse: it falls and the EMF of
        # every phase is negated (paper 2.2).
        direction = 1.0 if self.edge.direction == "forward" else -1.0
        angle = self.edge.angle_deg + direction * 60.0 * t / self.sector_time_s
        return (
            direction
            * self.amplitude_v
            * np.array([trapezoid(self.sectors, phase, angle) for phase in range(3)])
        )

    def affine(self, t0: float, t1: float) -> tuple[np.ndarray, np.ndarray]:
        """(e0, e1) with e(t) = e0 + e1 t on [t0, t1], which must not contain a corner."""
        if self.shape == "flat" or t1 <= t0:
            return self.values(t0), np.zeros(3)
        start, end = self.values(t0), self.values(t1)
        slope = (end - start) / (t1 - t0)
        return start - slope * t0, slope

    def corners(self, t0: float, t1: float) -> list[float]:
        """Times in (t0, t1) where the EMF slope changes."""
        if self.shape == "flat":
            return []
        first = math.floor(t0 / self.sector_time_s) + 1
        out = []
        k = first
        while k * self.sector_time_s < t1:
            out.append(k * self.sector_time_s)
            k += 1
        return out

"""The spec's back-EMF around the paper's 60 deg edge, per unit of E, from the spec alone.

The edge is the forward one into sector 1 (`oracle.switching`: A non-commutating at
+E, B turned off, C turned on). Each phase's waveform is the spec's half period from
its rising zero crossing (negated for the other half), placed with that crossing in
the middle of the sector in which `FORWARD_EMF` has the phase at 0 between -1 and +1;
`back_emf_shape: flat` freezes the three EMFs at their values at the edge (+1, -1, -1).

The rule needs two combinations along the sector x = t / T_s in [0, 1]:
sigma = (2 e_a - e_b - e_c)/E (the duty sum's EMF part) and phi = (e_a - 2 e_b + e_c)/E
(the turn-off forcing's), both piecewise linear. `hold(x)` is the minimax constant of
sigma over [0, x] (the constant that makes the largest swell of the integral of
c - sigma equal its largest sag): sigma(theta x), theta = sqrt(2) - 1, where sigma is
affine, a numerical minimax elsewhere.
"""

from __future__ import annotations

import bisect
import math
from dataclasses import dataclass
from fractions import Fraction

import numpy as np
import numpy.typing as npt

from codegen.spec_model import BackEmfShape
from oracle.switching import FORWARD_EMF

Floats = npt.NDArray[np.float64]
THETA = math.sqrt(2.0) - 1.0
#: The paper's edge: forward, from sector 0 into sector 1, at 60 deg.
EDGE_ANGLE = 60.0
#: (non-commutating, turn-off, turn-on) of that edge.
ROLES = (0, 1, 2)
_HOLD_POINTS = 513
_HOLD_SAMPLES = 257


def _rising_zero(phase: int) -> float:
    for k in range(6):
        if (
            FORWARD_EMF[k][phase] == 0
            and FORWARD_EMF[(k - 1) % 6][phase] < 0
            and FORWARD_EMF[(k + 1) % 6][phase] > 0
        ):
            return 60.0 * k + 30.0
    raise ValueError(f"phase {phase} never rises")


def _wave(
    points: tuple[tuple[Fraction, Fraction], ...], angles: list[Fraction], angle: Fraction
) -> Fraction:
    """e/E at `angle` from the half-period table, exactly (linear between its points;
    `angles` its angles, for the bisection)."""
    angle %= 360
    sign = 1
    if angle >= 180:
        angle -= 180
        sign = -1
    k = bisect.bisect_left(angles, angle)
    if angles[k] == angle:
        return sign * points[k][1]
    (a0, e0), (a1, e1) = points[k - 1], points[k]
    return sign * (e0 + (e1 - e0) * (angle - a0) / (a1 - a0))


def line_to_line_peak(points: tuple[tuple[Fraction, Fraction], ...]) -> Fraction:
    """lambda: the peak line-to-line EMF e_a - e_b per unit of E, phase b lagging phase a
    by 120 electrical degrees, of the half-period table `points` (the other half its
    negative). Exact: e_a - e_b is piecewise linear, so its largest magnitude lies at a
    corner of e_a (a table angle, or one 180 deg on) or of e_b (those 120 deg later).
    2 for a flat top of 60 deg or more (+E and -E at once, the paper's Eq. 4)."""
    angles = [Fraction(a) for a, _ in points]
    table = tuple((Fraction(a), Fraction(e)) for a, e in points)
    corners = {a % 360 for a in angles} | {(a + 180) % 360 for a in angles}
    candidates = corners | {(c + 120) % 360 for c in corners}
    return max(abs(_wave(table, angles, t) - _wave(table, angles, t - 120)) for t in candidates)


@dataclass(frozen=True)
class EdgeEmf:
    """sigma and phi over the sector, as (x, value) breakpoints (linear between)."""

    breaks: Floats  # x of the breakpoints, 0 .. 1
    sigma: Floats
    phi: Floats
    frozen: bool
    #: mu(x) on a grid of x (None where sigma is affine and mu is sigma(theta x))
    hold_grid: tuple[Floats, Floats] | None = None

    def sigma_at(self, x: Floats) -> Floats:
        return np.interp(x, self.breaks, self.sigma)

    @property
    def affine(self) -> bool:
        return self.breaks.size == 2 and self.hold_grid is None

    def hold(self, x: Floats) -> Floats:
        """The minimax constant of sigma over [0, x] (x in [0, 1])."""
        if self.hold_grid is None:
            slope = self.sigma[1] - self.sigma[0]
            return self.sigma[0] + slope * THETA * x
        grid, values = self.hold_grid
        return np.interp(x, grid, values)

    def forcing_terms(self) -> tuple[float, float, tuple[tuple[float, float], ...]]:
        """phi(0), phi'(0+) and the slope changes (x_j, change) inside (0, 1)."""
        slopes = np.diff(self.phi) / np.diff(self.breaks)
        corners = tuple(
            (float(self.breaks[j]), float(slopes[j] - slopes[j - 1]))
            for j in range(1, slopes.size)
            if slopes[j] != slopes[j - 1]
        )
        return float(self.phi[0]), float(slopes[0]), corners


def edge_emf(shape: BackEmfShape) -> EdgeEmf:
    if shape.frozen:
        signs = (1.0, -1.0, -1.0)  # e_a = E, e_b = e_c = -E (paper section 3.2)
        sigma = 2 * signs[0] - signs[1] - signs[2]
        phi = signs[0] - 2 * signs[1] + signs[2]
        return EdgeEmf(np.array([0.0, 1.0]), np.full(2, sigma), np.full(2, phi), True)
    zeros = [_rising_zero(p) for p in ROLES]
    # the corners' places in exact arithmetic (the table's angles are exact fractions):
    # one corner reached from two phases had given two breaks 1e-15 apart, whose
    # spurious slopes (+-0.7) kept every one as a corner of the forcing (771 of them
    # on a 3001-point table, each a term of every evaluation of the rule: `verify` ran
    # for more than 10 minutes)
    corner_angles = {Fraction(a) for a, _ in shape.points} | {
        Fraction(a) + 180 for a, _ in shape.points
    }
    exact: set[Fraction] = {Fraction(0), Fraction(1)}
    for z in zeros:
        for c in corner_angles:
            offset = (Fraction(z) + c - Fraction(EDGE_ANGLE)) % 360
            if 0 < offset < 60:
                exact.add(offset / 60)
    xs = sorted(exact)
    points = tuple(shape.points)
    angles = [a for a, _ in points]
    edge = Fraction(EDGE_ANGLE)
    values = [
        [_wave(points, angles, edge + 60 * x - Fraction(zeros[p])) for p in ROLES] for x in xs
    ]
    sigma = [2 * a - b - c for a, b, c in values]
    phi = [a - 2 * b + c for a, b, c in values]
    # keep only real slope changes (a table point where no slope changes is no corner),
    # decided exactly: in floats, a 3001-point table's affine stretch kept 292 corners
    # of 1e-12 (its slopes' rounding), each a term of every evaluation of the rule
    keep = [0]
    for j in range(1, len(xs) - 1):
        s_left = (sigma[j] - sigma[j - 1]) / (xs[j] - xs[j - 1])
        s_right = (sigma[j + 1] - sigma[j]) / (xs[j + 1] - xs[j])
        p_left = (phi[j] - phi[j - 1]) / (xs[j] - xs[j - 1])
        p_right = (phi[j + 1] - phi[j]) / (xs[j + 1] - xs[j])
        if s_left != s_right or p_left != p_right:
            keep.append(j)
    keep.append(len(xs) - 1)
    out = EdgeEmf(
        np.array([float(xs[j]) for j in keep]),
        np.array([float(sigma[j]) for j in keep]),
        np.array([float(phi[j]) for j in keep]),
        False,
    )
    if out.affine:
        return out
    return EdgeEmf(out.breaks, out.sigma, out.phi, False, _hold_table(out))


def _hold_table(emf: EdgeEmf) -> tuple[Floats, Floats]:
    """mu(x) on a grid of x by bisection on the constant (general piecewise sigma)."""
    xs = np.linspace(0.0, 1.0, _HOLD_POINTS)
    out = np.empty_like(xs)
    out[0] = emf.sigma[0]
    for k, x in enumerate(xs[1:], start=1):
        tau = np.linspace(0.0, x, _HOLD_SAMPLES)
        s = emf.sigma_at(tau)
        integral = np.concatenate(([0.0], np.cumsum(0.5 * (s[1:] + s[:-1]) * np.diff(tau))))
        low, high = float(s.min()), float(s.max())
        for _ in range(50):
            c = 0.5 * (low + high)
            deviation = c * tau - integral
            if deviation.max() + deviation.min() > 0.0:
                high = c
            else:
                low = c
        out[k] = 0.5 * (low + high)
    return xs, out

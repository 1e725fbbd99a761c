"""The spec's back-EMF shape in the sector after the paper's edge, as the rule needs it.

The resistance-aware rule (`codegen.derivation.constant_pair`) uses the three EMFs only
through two combinations, per unit of E = k_e n (from `derive_resistance_rule`):

* the duty sum that holds the non-commutating current, S = 2 + 3 R I/U_d - (E/U_d) sigma,
  sigma = (2 e_a - e_b - e_c)/E;
* the EMF part of the turn-off forcing, 3 L d i_b/dt = ... + E phi, phi = (e_a - 2 e_b + e_c)/E,

with a the non-commutating, b the turn-off and c the turn-on phase of the paper's 60 deg
edge (`SwitchingTable.paper_example`). This module evaluates sigma and phi along the
sector x = t / T_s in [0, 1] for the spec's `motor.back_emf_shape`: each phase's
waveform (a half period from its rising zero crossing, negated for the other half)
placed with its rising zero crossing in the middle of the sector in which the switching
table has that phase ramp up (so the Hall edge at which it starts to rise lies 30 deg
before it), or, for `flat`, the EMFs frozen at their edge values.

The firmware rule holds one duty pair and searches the commutation end on the carrier
grid with exact exponentials per step, which needs sigma and phi affine in x over the
whole sector: that is the paper's frozen EMF (sigma = 4, phi = 2) and the 120 deg
trapezoid (sigma = 4 - 2x, phi = 2 - 4x, the turn-off phase ramping from the edge).
Any other shape has a corner inside the sector; `affine_terms` says so (ShapeError).
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction
from itertools import pairwise

from codegen.derivation.switching import SwitchingTable
from codegen.errors import DerivationError
from codegen.spec_model import BackEmfShape

#: Electrical degrees per sector.
SECTOR_DEG = Fraction(60)


class ShapeError(DerivationError):
    """The shape has a slope change inside the commutation sector."""


@dataclass(frozen=True)
class ShapeTerms:
    """sigma(x) = sum0 + sum1 x and phi(x) = force0 + force1 x over the sector, per unit
    E (exact). `frozen`: the paper's flat EMF."""

    sum0: Fraction
    sum1: Fraction
    force0: Fraction
    force1: Fraction
    frozen: bool
    description: str


def _waveform(points: tuple[tuple[Fraction, Fraction], ...], angle: Fraction) -> Fraction:
    """e/E at `angle` deg from the rising zero crossing (any angle), linear between points."""
    angle = angle % 360
    sign = 1
    if angle >= 180:
        angle -= 180
        sign = -1
    for (a0, v0), (a1, v1) in pairwise(points):
        if a0 <= angle <= a1:
            return sign * (v0 + (v1 - v0) * (angle - a0) / (a1 - a0))
    raise DerivationError(f"angle {angle} outside the waveform's half period")


def _corners(points: tuple[tuple[Fraction, Fraction], ...]) -> list[Fraction]:
    """Angles in [0, 360) where the full-period waveform changes slope."""
    full = list(points) + [(a + 180, -v) for a, v in points[1:]]
    out = []
    for k in range(len(full)):
        before = full[k - 1] if k > 0 else (full[-2][0] - 360, full[-2][1])
        after = full[k + 1] if k + 1 < len(full) else (full[1][0] + 360, full[1][1])
        left = (full[k][1] - before[1]) / (full[k][0] - before[0])
        right = (after[1] - full[k][1]) / (after[0] - full[k][0])
        if left != right:
            out.append(full[k][0] % 360)
    return sorted(set(out))


def rising_zero_deg(table: SwitchingTable, phase: int) -> Fraction:
    """Forward-rotation angle of `phase`'s rising zero crossing: the middle of the
    sector in which the switching table has it ramp from -E to +E."""
    sectors = table.sectors("forward")
    for k in range(6):
        if (
            sectors[k].emf_signs[phase] == 0
            and sectors[(k - 1) % 6].emf_signs[phase] < 0
            and sectors[(k + 1) % 6].emf_signs[phase] > 0
        ):
            return SECTOR_DEG * k + SECTOR_DEG / 2
    raise DerivationError(f"phase {phase} has no rising ramp in the switching table")


def edge_emfs(shape: BackEmfShape, table: SwitchingTable, x: Fraction) -> tuple[Fraction, ...]:
    """(e_a, e_b, e_c)/E (non-commutating, turn-off, turn-on) at x sectors after the
    paper's edge."""
    edge = table.paper_example()
    roles = (edge.non_commutating, edge.turn_off, edge.turn_on)
    if shape.frozen:
        return tuple(Fraction(edge.emf_signs[p]) for p in roles)
    angle = edge.angle_deg + SECTOR_DEG * x
    return tuple(_waveform(shape.points, angle - rising_zero_deg(table, p)) for p in roles)


def _corner_in_sector(shape: BackEmfShape, table: SwitchingTable) -> Fraction | None:
    """The first x in (0, 1) at which some phase's EMF changes slope, or None."""
    edge = table.paper_example()
    corners = _corners(shape.points)
    inside = []
    for p in (edge.non_commutating, edge.turn_off, edge.turn_on):
        zero = rising_zero_deg(table, p)
        for c in corners:
            # angle - zero = c (mod 360) for angle strictly inside the sector
            offset = (zero + c - edge.angle_deg) % 360
            if 0 < offset < SECTOR_DEG:
                inside.append(offset / SECTOR_DEG)
    return min(inside, default=None)


def affine_terms(shape: BackEmfShape, table: SwitchingTable) -> ShapeTerms:
    """sigma and phi of the shape over the sector, when both are affine in x."""
    if not shape.frozen:
        corner = _corner_in_sector(shape, table)
        if corner is not None:
            raise ShapeError(
                f"the back-EMF shape ({shape.describe()}) changes slope {float(corner):.3g}"
                " sectors after the edge"
            )
    values = {x: edge_emfs(shape, table, x) for x in (Fraction(0), Fraction(1))}

    def combination(weights: tuple[int, int, int]) -> tuple[Fraction, Fraction]:
        at = {x: sum(w * e for w, e in zip(weights, v, strict=True)) for x, v in values.items()}
        return at[Fraction(0)], at[Fraction(1)] - at[Fraction(0)]

    sum0, sum1 = combination((2, -1, -1))
    force0, force1 = combination((1, -2, 1))
    terms = (("2 e_a - e_b - e_c", Fraction(sum0)), ("e_a - 2 e_b + e_c", Fraction(force0)))
    failing = [(name, v) for name, v in terms if v.denominator != 1 or v < 0]
    if failing:
        # the firmware's rule takes X sigma_0 / 4 and X phi_0 / 4 in whole quarters (4
        # and 2 for a flat top at 1): a table scaled to 0.7 had reached the integer
        # design and failed there (an internal error in generate, simulate and bench);
        # the message names the term that is not whole (it had always named the first,
        # 3 E, for a table whose second was 1.5 E)
        edge = ", ".join(f"{float(e):+.3g}" for e in values[Fraction(0)])
        said = " and ".join(f"{name} = {float(v):.4g} E" for name, v in failing)
        raise ShapeError(
            f"the back-EMF shape ({shape.describe()}) has the EMFs ({edge}) E at the edge,"
            f" {said}, where the rule's integer form takes a whole number of E, 0 or more"
            " (a flat top at 1; scale motor.back_emf_constant instead of the table)"
        )
    return ShapeTerms(sum0, sum1, force0, force1, shape.frozen, shape.describe())

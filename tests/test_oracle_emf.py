"""The oracle's EMF around the edge (`oracle.emf_shape`) on long measured tables: the
corners of the forcing decided exactly."""

from __future__ import annotations

import math
from fractions import Fraction

import pytest

from codegen.spec_model import BackEmfShape
from oracle.emf_shape import edge_emf


def _trapezoid_table(points: int) -> BackEmfShape:
    """The paper's 120 deg trapezoid sampled at `points` angles, exactly."""

    def e(angle: Fraction) -> Fraction:
        return min(Fraction(1), angle / 30, (180 - angle) / 30)

    angles = [Fraction(180 * k, points - 1) for k in range(points)]
    return BackEmfShape(tuple((a, e(a)) for a in angles), None)


@pytest.mark.parametrize("points", [7, 181, 3001])
def test_a_sampled_trapezoid_should_be_as_affine_as_the_trapezoid(points: int) -> None:
    """Sampled every 0.06 deg, the 120 deg trapezoid is affine over the sector, as the
    improved_r design holds it: floats had kept 771 corners (breaks 1e-15 apart reached
    from two phases, and slopes' rounding of 1e-12), every one a term of each
    evaluation of the rule (`generate` 161 s, `verify` over 10 minutes)."""
    emf = edge_emf(_trapezoid_table(points))
    assert emf.affine
    assert emf.forcing_terms()[2] == ()
    reference = edge_emf(BackEmfShape.trapezoid(Fraction(120)))
    assert emf.sigma == pytest.approx(reference.sigma, abs=1e-15)
    assert emf.phi == pytest.approx(reference.phi, abs=1e-15)


def test_a_sine_should_keep_its_real_corners_only() -> None:
    """A coarse sine: the table's points inside the sector are real corners, kept."""
    angles = [Fraction(15 * k) for k in range(13)]
    table = tuple(
        (a, Fraction(round(math.sin(math.radians(float(a))) * 10**6), 10**6)) for a in angles
    )
    table = (*table[:-1], (Fraction(180), Fraction(0)))
    emf = edge_emf(BackEmfShape(table, None))
    corners = emf.forcing_terms()[2]
    assert 0 < len(corners) < len(emf.breaks)
    assert all(abs(change) > 1e-6 for _, change in corners)

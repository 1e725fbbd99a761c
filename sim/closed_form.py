"""Exact solution of di/dt = c0 + c1 t - a i, and its first zero.

Between two switching events every conducting phase obeys this scalar equation: all
phases share R and L, so after eliminating the neutral voltage (Eq. 1 with
i_a + i_b + i_c = 0) the system matrix is -R/L times the identity, and the forcing
(terminal voltage minus EMF minus neutral voltage, over L) is affine in time while the
EMFs are. No matrix exponential is needed, and R = 0 (a = 0) is the polynomial limit.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from itertools import pairwise

#: Below this a t the exponential terms are evaluated by their Taylor series.
_SERIES_LIMIT = 1e-4


def _phi(a: float, t: float) -> tuple[float, float]:
    """phi1 = int_0^t e^{-a(t-s)} ds and phi2 = int_0^t s e^{-a(t-s)} ds."""
    x = a * t
    if abs(x) < _SERIES_LIMIT:
        phi1 = t * (1.0 - x / 2.0 + x * x / 6.0)
        phi2 = t * t * (0.5 - x / 6.0 + x * x / 24.0)
        return phi1, phi2
    phi1 = -math.expm1(-x) / a
    return phi1, (t - phi1) / a


def current(i0: float, c0: float, c1: float, a: float, t: float) -> float:
    """i(t) from i(0) = i0 under di/dt = c0 + c1 t - a i."""
    phi1, phi2 = _phi(a, t)
    return i0 * math.exp(-a * t) + c0 * phi1 + c1 * phi2


def currents(
    i0: Sequence[float], c0: Sequence[float], c1: Sequence[float], a: float, t: float
) -> tuple[float, float, float]:
    """`current` of the three phases at one t: they share a, so the exponential and
    phi are evaluated once (the same arithmetic as three calls of `current`)."""
    phi1, phi2 = _phi(a, t)
    decay = math.exp(-a * t)
    return (
        i0[0] * decay + c0[0] * phi1 + c1[0] * phi2,
        i0[1] * decay + c0[1] * phi1 + c1[1] * phi2,
        i0[2] * decay + c0[2] * phi1 + c1[2] * phi2,
    )


def slope(i: float, c0: float, c1: float, a: float, t: float) -> float:
    return c0 + c1 * t - a * i


def _extremum(i0: float, c0: float, c1: float, a: float, horizon: float) -> float | None:
    """Time in (0, horizon) where di/dt = 0, if any (there is at most one)."""
    if a == 0.0:
        if c1 == 0.0:
            return None
        t = -c0 / c1
    else:
        # i = A e^{-at} + B + C t with C = c1/a, A = i0 - c0/a + c1/a^2.
        big_a = i0 - c0 / a + c1 / (a * a)
        big_c = c1 / a
        if big_a == 0.0 or big_c / (a * big_a) <= 0.0:
            return None
        t = -math.log(big_c / (a * big_a)) / a
    return t if 0.0 < t < horizon else None


def _root(i0: float, c0: float, c1: float, a: float, lo: float, hi: float, sign_lo: float) -> float:
    """Root in a monotone bracket [lo, hi]: safeguarded Newton (bisection fallback)."""
    t = 0.5 * (lo + hi)
    for _ in range(100):
        value = current(i0, c0, c1, a, t)
        if value == 0.0:
            return t
        if (value > 0.0) == (sign_lo > 0.0):
            lo = t
        else:
            hi = t
        d = slope(value, c0, c1, a, t)
        step = t - value / d if d != 0.0 else 0.5 * (lo + hi)
        t = step if lo < step < hi else 0.5 * (lo + hi)
        if hi - lo < 1e-15 * max(1.0, hi):
            break
    return 0.5 * (lo + hi)


def first_zero(i0: float, c0: float, c1: float, a: float, horizon: float) -> float | None:
    """First t in (0, horizon] where the current reaches zero, or None.

    A current that starts at zero (a phase that has just begun to conduct) is followed
    in the direction it leaves zero; its return to zero is the event.
    """
    direction = i0 if i0 != 0.0 else (c0 if c0 != 0.0 else c1)
    if direction == 0.0:
        return None
    sign = 1.0 if direction > 0.0 else -1.0
    pieces = [0.0]
    turn = _extremum(i0, c0, c1, a, horizon)
    if turn is not None:
        pieces.append(turn)
    pieces.append(horizon)
    for lo, hi in pairwise(pieces):
        end = current(i0, c0, c1, a, hi)
        if end * sign <= 0.0:
            if end == 0.0:
                return hi
            return _root(i0, c0, c1, a, lo, hi, sign)
    return None

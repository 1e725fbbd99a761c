"""The firmware rule in real arithmetic: what the integer prototype approximates.

From the integer inputs (Hall period T, bus code B, current code C) and the exact spec
constants, in duty counts and fractions x of the sector:

1. clamp T to the speed range and B to the bus range (flagged), i = C - offset
   clamped to [0, ADC full scale];
2. X = K_X/(T B), Y = K_Y i/B, A = kappa i X, rho = K_rho T;
3. the held duty sum for a commutation of x sectors, Sigma(x) = 2P + Y - X + theta X x/2
   (S at the EMFs of time theta t_com), split as the paper does:
   C_on = clamp(Sigma, 0, P), C_off = clamp(Sigma - P, 0, P);
4. the turn-off current in counts under that pair and the ramping EMF,
   g(x) = A e^{-rho x} + F x psi1(rho x) - X x^2/2 psi2(rho x),
   F = 2 C_off - C_on - P + X/2; x_c is its zero in (0, 1] (bisection: g(0) = A >= 0,
   and g changes sign once), or 1 when g(1) > 0 (the commutation does not finish
   within the sector: flagged, the time clamped to the sector);
5. outputs: round(C_on(x_c)), round(C_off(x_c)), round(x_c T) ticks.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import sympy as sp

from codegen.derivation.constant_pair import psi1, psi2, y
from codegen.improved_r_rule.constants import RuleConstants

FLAG_SPEED_CLAMPED = 0x01  # T outside the spec's speed range: the rule used the nearest end
FLAG_BUS_CLAMPED = 0x02  # B outside the spec's bus range
FLAG_NOT_FINISHED = 0x04  # the turn-off current does not reach zero within the sector
FLAG_CANNOT_HOLD = 0x08  # Sigma > 2P: even D_on = D_off = 1 lets the current sag
FLAG_ABOVE_BUS = 0x10  # Sigma < 0: even D_on = 0 lets the current swell (E near U_d/2)
FLAG_NAMES = {
    FLAG_SPEED_CLAMPED: "speed_clamped",
    FLAG_BUS_CLAMPED: "bus_clamped",
    FLAG_NOT_FINISHED: "not_finished",
    FLAG_CANNOT_HOLD: "cannot_hold",
    FLAG_ABOVE_BUS: "above_bus",
}
#: Below this y the psi functions are summed from their series (no cancellation).
SERIES_BELOW = 0.02
SERIES_TERMS = 10


@dataclass(frozen=True)
class RuleInputs:
    period_ticks: int  # T, Hall timer ticks of the last 60 deg
    bus_code: int  # B
    current_code: int  # C, with the sensor offset


@dataclass(frozen=True)
class RuleOutputs:
    on_counts: int
    off_counts: int
    commutation_ticks: int
    flags: int


@dataclass(frozen=True)
class Clamped:
    period: int
    bus: int
    current: int  # offset removed, >= 0
    flags: int


@dataclass(frozen=True)
class ReferenceResult:
    outputs: RuleOutputs
    fraction: float  # x_c
    on_exact: float  # C_on(x_c) before rounding
    off_exact: float
    ticks_exact: float  # x_c T'
    slope: float  # dg/dx at x_c (counts per sector), for error bounds
    x: float
    y: float
    a: float
    rho: float


def clamp_inputs(c: RuleConstants, inputs: RuleInputs) -> Clamped:
    flags = 0
    period = min(max(inputs.period_ticks, c.period_low), c.period_high)
    if period != inputs.period_ticks:
        flags |= FLAG_SPEED_CLAMPED
    bus = min(max(inputs.bus_code, c.bus_low), c.bus_high)
    if bus != inputs.bus_code:
        flags |= FLAG_BUS_CLAMPED
    current = min(max(inputs.current_code - c.current_offset, 0), c.current_high)
    return Clamped(period, bus, current, flags)


@lru_cache(maxsize=1)
def _series() -> tuple[tuple[float, ...], tuple[float, ...]]:
    """Taylor coefficients of psi1 and psi2 at y = 0, from their definitions."""
    out = []
    for psi in (psi1, psi2):
        poly = sp.series(psi, y, 0, SERIES_TERMS).removeO()
        out.append(tuple(float(poly.coeff(y, k)) for k in range(SERIES_TERMS)))
    return out[0], out[1]


def psi_values(value: float) -> tuple[float, float]:
    """(psi1, psi2) at y >= 0 in double precision."""
    if value < SERIES_BELOW:
        c1, c2 = _series()
        return (
            sum(c * value**k for k, c in enumerate(c1)),
            sum(c * value**k for k, c in enumerate(c2)),
        )
    return -math.expm1(-value) / value, 2.0 * (value - 1.0 + math.exp(-value)) / value**2


def _duties(period_counts: int, total: float) -> tuple[float, float]:
    on = min(max(total, 0.0), period_counts)
    off = min(max(total - period_counts, 0.0), period_counts)
    return on, off


def reference(c: RuleConstants, inputs: RuleInputs) -> ReferenceResult:
    clamped = clamp_inputs(c, inputs)
    p = c.period_counts
    t, b, i = clamped.period, clamped.bus, clamped.current
    x_counts = float(c.k_x / (t * b))
    y_counts = float(c.k_y * i / b)
    a = float(c.kappa * i) * x_counts
    rho = float(c.k_rho * t)
    theta = float(c.ramp_weight)
    base = 2 * p + y_counts - x_counts
    ramp = theta * x_counts / 2

    def g(frac: float) -> float:
        on, off = _duties(p, base + ramp * frac)
        forcing = 2 * off - on - p + x_counts / 2
        q1, q2 = psi_values(rho * frac)
        return a * math.exp(-rho * frac) + forcing * frac * q1 - x_counts * frac**2 / 2 * q2

    flags = clamped.flags
    if g(1.0) > 0.0:
        frac = 1.0
        flags |= FLAG_NOT_FINISHED
    else:
        lo, hi = 0.0, 1.0
        for _ in range(60):
            mid = 0.5 * (lo + hi)
            if g(mid) > 0.0:
                lo = mid
            else:
                hi = mid
        frac = 0.5 * (lo + hi)
    total = base + ramp * frac
    if total > 2 * p:
        flags |= FLAG_CANNOT_HOLD
    if total < 0:
        flags |= FLAG_ABOVE_BUS
    on, off = _duties(p, total)
    step = 1e-7
    slope = (g(min(frac + step, 1.0)) - g(max(frac - step, 0.0))) / (
        min(frac + step, 1.0) - max(frac - step, 0.0)
    )
    ticks = frac * t
    outputs = RuleOutputs(
        on_counts=round(on),
        off_counts=round(off),
        commutation_ticks=min(round(ticks), inputs.period_ticks),
        flags=flags,
    )
    return ReferenceResult(outputs, frac, on, off, ticks, slope, x_counts, y_counts, a, rho)

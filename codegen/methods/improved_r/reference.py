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
from collections.abc import Sequence
from dataclasses import dataclass
from functools import lru_cache

import numpy as np
import numpy.typing as npt
import sympy as sp

from codegen.derivation.constant_pair import psi1, psi2, y
from codegen.methods.improved_r.constants import RuleConstants

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
    current: float  # offset removed, >= 0, in 1/m codes
    flags: int


@dataclass(frozen=True)
class ReferenceResult:
    outputs: RuleOutputs
    fraction: float  # x_c
    on_exact: float  # C_on(x_c) before rounding
    off_exact: float
    ticks_exact: float  # x_c T'
    x: float
    y: float
    a: float
    rho: float


FloatArray = npt.NDArray[np.float64]
IntArray = npt.NDArray[np.int64]


@dataclass(frozen=True)
class ReferenceBatch:
    """`reference` over arrays of inputs (one element per input point)."""

    period: IntArray  # T after clamping
    bus: IntArray
    current: FloatArray  # offset removed, clamped, 1/m codes
    fraction: FloatArray
    total: FloatArray  # Sigma(x_c), counts
    on_exact: FloatArray
    off_exact: FloatArray
    ticks_exact: FloatArray
    flags: IntArray
    x: FloatArray
    y: FloatArray
    a: FloatArray
    rho: FloatArray

    def result(self, k: int, measured_period: int) -> ReferenceResult:
        outputs = RuleOutputs(
            on_counts=round(float(self.on_exact[k])),
            off_counts=round(float(self.off_exact[k])),
            commutation_ticks=min(round(float(self.ticks_exact[k])), measured_period),
            flags=int(self.flags[k]),
        )
        return ReferenceResult(
            outputs,
            float(self.fraction[k]),
            float(self.on_exact[k]),
            float(self.off_exact[k]),
            float(self.ticks_exact[k]),
            float(self.x[k]),
            float(self.y[k]),
            float(self.a[k]),
            float(self.rho[k]),
        )


def clamp_inputs(c: RuleConstants, inputs: RuleInputs) -> Clamped:
    flags = 0
    period = min(max(inputs.period_ticks, c.period_low), c.period_high)
    if period != inputs.period_ticks:
        flags |= FLAG_SPEED_CLAMPED
    bus = min(max(inputs.bus_code, c.bus_low), c.bus_high)
    if bus != inputs.bus_code:
        flags |= FLAG_BUS_CLAMPED
    exact = c.current.scale * (min(inputs.current_code, c.adc_max) - c.current.offset_exact)
    current = min(max(float(exact), 0.0), float(c.current_high))
    return Clamped(period, bus, current, flags)


@lru_cache(maxsize=1)
def _series() -> tuple[tuple[float, ...], tuple[float, ...]]:
    """Taylor coefficients of psi1 and psi2 at y = 0, from their definitions."""
    out = []
    for psi in (psi1, psi2):
        poly = sp.series(psi, y, 0, SERIES_TERMS).removeO()
        out.append(tuple(float(poly.coeff(y, k)) for k in range(SERIES_TERMS)))
    return out[0], out[1]


def psi_arrays(value: FloatArray) -> tuple[FloatArray, FloatArray]:
    """(psi1, psi2) at y >= 0, elementwise in double precision: the series near 0
    (no cancellation), the closed forms elsewhere."""
    c1, c2 = _series()
    small = value < SERIES_BELOW
    safe = np.where(small, 1.0, value)
    closed1 = -np.expm1(-safe) / safe
    closed2 = 2.0 * (safe - 1.0 + np.exp(-safe)) / safe**2
    return (
        np.where(small, np.polynomial.polynomial.polyval(value, c1), closed1),
        np.where(small, np.polynomial.polynomial.polyval(value, c2), closed2),
    )


def psi_values(value: float) -> tuple[float, float]:
    """(psi1, psi2) at one y >= 0: `psi_arrays` in scalar arithmetic (the error bounds
    evaluate it point by point, where array overhead would dominate)."""
    if value < SERIES_BELOW:
        c1, c2 = _series()
        return (
            sum(c * value**k for k, c in enumerate(c1)),
            sum(c * value**k for k, c in enumerate(c2)),
        )
    return -math.expm1(-value) / value, 2.0 * (value - 1.0 + math.exp(-value)) / value**2


def _duties(period_counts: int, total: FloatArray) -> tuple[FloatArray, FloatArray]:
    return np.clip(total, 0.0, period_counts), np.clip(total - period_counts, 0.0, period_counts)


def reference_batch(
    c: RuleConstants, periods: npt.ArrayLike, buses: npt.ArrayLike, current_codes: npt.ArrayLike
) -> ReferenceBatch:
    """The rule at every (T, B, C) given (broadcast), clamped as `clamp_inputs` does."""
    t_in, b_in, c_in = np.broadcast_arrays(
        *(np.atleast_1d(np.asarray(v, dtype=np.int64)) for v in (periods, buses, current_codes))
    )
    t = np.clip(t_in, c.period_low, c.period_high)
    b = np.clip(b_in, c.bus_low, c.bus_high)
    m, offset = c.current.scale, float(c.current.offset_exact)
    i = np.clip(m * (np.minimum(c_in, c.adc_max) - offset), 0.0, float(c.current_high))
    flags = np.where(t != t_in, FLAG_SPEED_CLAMPED, 0) | np.where(b != b_in, FLAG_BUS_CLAMPED, 0)
    p = c.period_counts
    x_counts = float(c.k_x) / (t.astype(np.float64) * b)
    y_counts = float(c.k_y) * i / b
    a = float(c.kappa) * i * x_counts
    rho = float(c.k_rho) * t
    base = 2 * p + y_counts - x_counts
    ramp = float(c.ramp_weight) * x_counts / 2

    def g(frac: FloatArray) -> FloatArray:
        on, off = _duties(p, base + ramp * frac)
        forcing = 2 * off - on - p + x_counts / 2
        q1, q2 = psi_arrays(rho * frac)
        return a * np.exp(-rho * frac) + forcing * frac * q1 - x_counts * frac**2 / 2 * q2

    unfinished = g(np.ones_like(x_counts)) > 0.0
    lo, hi = np.zeros_like(x_counts), np.ones_like(x_counts)
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        above = g(mid) > 0.0
        lo, hi = np.where(above, mid, lo), np.where(above, hi, mid)
    frac = np.where(unfinished, 1.0, 0.5 * (lo + hi))
    flags |= np.where(unfinished, FLAG_NOT_FINISHED, 0)
    total = base + ramp * frac
    flags |= np.where(total > 2 * p, FLAG_CANNOT_HOLD, 0) | np.where(total < 0, FLAG_ABOVE_BUS, 0)
    on, off = _duties(p, total)
    return ReferenceBatch(
        t, b, i, frac, total, on, off, frac * t, flags, x_counts, y_counts, a, rho
    )


def reference_points(c: RuleConstants, points: Sequence[RuleInputs]) -> list[ReferenceResult]:
    """`reference` at many points, evaluated as one batch."""
    periods = [q.period_ticks for q in points]
    batch = reference_batch(
        c, periods, [q.bus_code for q in points], [q.current_code for q in points]
    )
    return [batch.result(k, period) for k, period in enumerate(periods)]


def reference(c: RuleConstants, inputs: RuleInputs) -> ReferenceResult:
    return reference_points(c, [inputs])[0]

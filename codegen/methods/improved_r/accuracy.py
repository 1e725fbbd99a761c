"""Pointwise error bounds of the integer rule against the real-arithmetic reference.

For one input (T, B, C), every integer quantity is within a known distance of its exact
value (roundings of the constants, of the divides and shifts, the table's error):
delta X, delta Y, delta A, delta S, and at each x the error of psi1, psi2, e^{-y}, u1,
v2. Together they bound |2 g_int(x) - 2 g(x)| <= eps(x) (counts). The bisection keeps
hi with 2 g_int(hi) <= 0 and lo with 2 g_int(lo) > 0, so hi can be no earlier than the
first x where 2g <= eps and lo no later than the last x where 2g > -eps: the result
lies in [h_min - 2^-(K+1), l_max + 2^-(K+1)]. Time and duty bounds follow:

    |ticks - x_c T| <= T max(x_c - h_min, l_max - x_c) + T 2^-(K+1) + 1/2
    |C_on - C_on(x_c)| <= 1/2 + delta S + S1 |x - x_c|       (and C_off likewise)

No linearisation: where g is flat around its zero (a commutation that barely ends, a
current near zero) the bound grows as the real error can.

There the commutation time is ill-conditioned in the physics too: half a count of the
emitted duty (its own rounding) moves the true zero of the turn-off current by

    t_half = T x_c psi1(rho x_c) |dF/dS| / (2 |F(x_c) - X x_c|)

(dF/dS = 2 in the low segment, 1 in the high one), so the time target is asked of the
integer rule only as max(target, t_half): no rule that emits whole counts can be more
precise than that.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from codegen.methods.improved_r.fixed import THETA_FRAC_BITS, FixedRule
from codegen.methods.improved_r.reference import (
    FLAG_NOT_FINISHED,
    FloatArray,
    ReferenceBatch,
    ReferenceResult,
    RuleInputs,
    clamp_inputs,
    psi_arrays,
    psi_values,
    reference,
)
from codegen.methods.improved_r.table import error_at

#: The sign scan of g -/+ eps: g is unimodal in x (rises, then falls through its one
#: zero), so a coarse scan finds the crossing and bisection refines it.
_SCAN = 32
_REFINE = 40


@dataclass(frozen=True)
class PointBound:
    fraction_error: float  # |x_int - x_c| bound, sectors
    ticks: float  # |ticks_int - x_c T| bound
    duty_counts: float  # |C_int - C(x_c)| bound
    half_count_ticks: float  # t_half: the time shift of half a duty count (physics)

    def time_allowance(self, target_ticks: float) -> float:
        return max(target_ticks, self.half_count_ticks)


def _input_errors(
    rule: FixedRule, ref: ReferenceResult, t: int, b: int, i: int
) -> dict[str, float]:
    fc = 2.0**-rule.counts_frac_bits
    x_err = fc * (0.5 + (0.5 + 0.5 / b) / t)
    y_err = fc * (0.5 + (0.5 + 0.5 / b) * i / 2**rule.y_guard_bits)
    kappa = float(rule.constants.kappa)
    a_err = fc * 0.5 + x_err * kappa * i + ref.x * i * 0.5 / 2**rule.kappa_frac_bits
    theta = float(rule.constants.ramp_weight)
    s1_err = fc * 0.5 + theta / 2 * x_err + ref.x * 2.0 ** -(THETA_FRAC_BITS + 1)
    rho_err = t * 2.0 ** -(rule.rho_frac_bits + 1)
    return {"x": x_err, "y": y_err, "a": a_err, "s1": s1_err, "rho": rho_err, "fc": fc}


def _g_and_error(
    rule: FixedRule, ref: ReferenceResult, err: dict[str, float]
) -> Callable[[float], tuple[float, float]]:
    """x -> (2 g(x), eps(x)) at this input."""
    c = rule.constants
    p = c.period_counts
    theta = float(c.ramp_weight)
    fy = rule.table.y_frac_bits
    half_unit = 2.0 ** -(rule.unit_frac_bits + 1)
    base = 2 * p + ref.y - ref.x
    ramp = theta * ref.x / 2

    def at(frac: float) -> tuple[float, float]:
        y_value = ref.rho * frac
        dy = 2.0**-fy + frac * err["rho"]
        q1, q2 = psi_values(y_value)
        t1 = max(error_at(rule.table, max(y_value - dy, 0.0)), error_at(rule.table, y_value + dy))
        d1 = t1[0] + dy / 2
        d2 = t1[1] + dy / 3
        e = math.exp(-y_value)
        de = y_value * d1 + q1 * dy + dy * d1 + half_unit
        u1, du1 = frac * q1, frac * d1 + half_unit
        v2 = frac * frac * q2
        dv2 = frac * frac * d2 + half_unit
        total = base + ramp * frac
        on = min(max(total, 0.0), p)
        off = min(max(total - p, 0.0), p)
        f2 = 4 * off - 2 * on - 2 * p + ref.x
        d_total = err["y"] + err["x"] + err["s1"] * frac + err["fc"] / 2
        df2 = 4 * d_total + err["x"]
        g2 = 2 * ref.a * e + f2 * u1 - ref.x * v2
        eps = (
            2 * (err["a"] * (e + de) + ref.a * de)
            + df2 * (u1 + du1)
            + abs(f2) * du1
            + err["x"] * (v2 + dv2)
            + ref.x * dv2
        )
        return g2, 1.001 * eps

    return at


def _first(pred: Callable[[float], bool], lo: float, hi: float) -> float:
    """Smallest x in [lo, hi] with pred true (scan, then bisection; pred(hi) is true)."""
    previous = lo
    for m in range(_SCAN + 1):
        x = lo + (hi - lo) * m / _SCAN
        if pred(x):
            if m == 0:
                return lo
            a, b = previous, x
            for _ in range(_REFINE):
                mid = 0.5 * (a + b)
                a, b = (a, mid) if pred(mid) else (mid, b)
            return a
        previous = x
    return hi


def point_bound(
    rule: FixedRule, inputs: RuleInputs, ref: ReferenceResult | None = None
) -> PointBound:
    c = rule.constants
    ref = ref or reference(c, inputs)
    clamped = clamp_inputs(c, inputs)
    t, b, i = clamped.period, clamped.bus, clamped.current
    err = _input_errors(rule, ref, t, b, i)
    at = _g_and_error(rule, ref, err)
    x_c = ref.fraction
    h_min = _first(lambda x: at(x)[0] <= at(x)[1], 0.0, 1.0)
    # last x with 2g > -eps: first x (from the right) where it holds, scanning leftwards
    l_max = 1.0 - _first(lambda u: at(1.0 - u)[0] > -at(1.0 - u)[1], 0.0, 1.0)
    half_step = 2.0 ** -(rule.steps + 1)
    spread = max(x_c - h_min, l_max - x_c, 0.0) + half_step
    theta = float(c.ramp_weight)
    d_total = err["y"] + err["x"] + err["s1"] + err["fc"] / 2
    return PointBound(
        fraction_error=spread,
        ticks=t * spread + 0.5,
        duty_counts=0.5 + d_total + theta * ref.x / 2 * spread,
        half_count_ticks=half_count_ticks(rule, ref, t),
    )


def half_count_ticks_array(
    period_counts: int,
    on: FloatArray,
    off: FloatArray,
    x: FloatArray,
    fraction: FloatArray,
    rho: FloatArray,
    period: npt.ArrayLike,
    flags: npt.ArrayLike,
) -> FloatArray:
    """t_half (see the module docstring) elementwise; 0 where the commutation does not
    finish or the duty pair is clamped (no count of duty moves it there)."""
    p = period_counts
    total = on + off
    gain = np.where(total > p, 2.0, 1.0)
    slope = np.abs(2 * off - on - p + x / 2 - x * fraction)
    psi1, _ = psi_arrays(rho * fraction)
    with np.errstate(divide="ignore", invalid="ignore"):
        value = np.where(
            slope > 0, np.asarray(period) * fraction * psi1 * gain / (2 * slope), np.inf
        )
    decided = ((np.asarray(flags) & FLAG_NOT_FINISHED) == 0) & (total > 0) & (total < 2 * p)
    return np.where(decided, value, 0.0)


def half_count_ticks_batch(period_counts: int, batch: ReferenceBatch) -> FloatArray:
    return half_count_ticks_array(
        period_counts,
        batch.on_exact,
        batch.off_exact,
        batch.x,
        batch.fraction,
        batch.rho,
        batch.period,
        batch.flags,
    )


def half_count_ticks(rule: FixedRule, ref: ReferenceResult, period: int) -> float:
    values = half_count_ticks_array(
        rule.constants.period_counts,
        *(np.array([v]) for v in (ref.on_exact, ref.off_exact, ref.x, ref.fraction, ref.rho)),
        np.array([period]),
        np.array([ref.outputs.flags]),
    )
    return float(values[0])

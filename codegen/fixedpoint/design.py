"""Choose the integer formats of the core and prove them safe over the input domain.

Everything that depends on the bus voltage alone is computed once per bus code B
(`bldc_bus_condition`):

    x_numerator      = round(N_X / B),  N_X = round(K_X 2^f)        uint32, long division
    high_speed_period = ceil(C / B),    C = ceil(K_X / P)            uint32
    time_numerator   = round(N_G / B),  N_G = round(K_G 2^f)        uint32, long division

A long division splits N = hi 2^k + lo and divides twice in 32 bits, so no 64-bit divide
helper is needed. The speed-dependent part (`bldc_commutation_timing`, which the port
runs after each Hall edge for the next one) costs one divide for the speed and one for
Eq. 20:

    X_q  = round(x_numerator / T)                        uint32, X = P 4E/U_d in Q(f)
    X_c  = round(X_q / 2^f)                              TIM1 counts
    duties from Eq. 18 / 16 in counts, clamped to [0, P]
    W_q  = (2P + 2 C_on - 4 C_off) 2^f - X_q             int32 (t is unbounded when <= 0)
    i    = C_i - offset                                   int32, the whole ADC range
    t    = round(time_numerator i / W_q)                  int32, then saturated to [0, T]

Segment and fail-area decisions are exact integer comparisons: T < ceil(C/B) is
equivalent to T B < K_X / P, that is 4E > U_d (Eq. 18).

The period and the current are proven over their full representable range (the Hall
counter and the ADC), not only the spec's operating range, so the firmware needs no
clamp on them: below the minimum speed the equations still hold, and a current beyond
the braking range gives the true commutation time, which then saturates at the sector.
Every intermediate's range is bounded with SymPy's interval arithmetic (AccumBounds) and
must fit its type, or design() fails naming the quantity, its range and the type.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import sympy as sp

from codegen.fixedpoint.scaling import Scaling

UINT32_MAX = 2**32 - 1
INT32_MAX = 2**31 - 1
INT32_MIN = -(2**31)
UINT64_MAX = 2**64 - 1
LIMITS = {
    "uint32_t": (0, UINT32_MAX),
    "int32_t": (INT32_MIN, INT32_MAX),
    "uint64_t": (0, UINT64_MAX),
    "int64_t": (-(2**63), 2**63 - 1),
}
MAX_FRACTION_BITS = 12


class FixedPointError(ValueError):
    """The spec's ranges make a safe fixed-point design impossible."""


@dataclass(frozen=True)
class ProvenRange:
    """An intermediate, its interval over the input box, and the C type it must fit."""

    name: str
    c_type: str
    low: int
    high: int
    expression: str

    @property
    def headroom_bits(self) -> float:
        lo, hi = LIMITS[self.c_type]
        used = max(self.high / hi, self.low / lo if self.low < 0 else 0.0)
        return -math.log2(used) if used > 0 else float("inf")


@dataclass(frozen=True)
class LongDivision:
    """round(N / B) in two 32-bit divides: N = hi 2^shift + lo."""

    numerator: int  # N
    shift: int
    high: int
    low: int


@dataclass(frozen=True)
class FixedPointDesign:
    scaling: Scaling
    x_frac_bits: int  # f
    k_x: LongDivision  # N_X = round(K_X 2^f)
    k_g: LongDivision  # N_G = round(K_G 2^f)
    high_speed_tb: int  # C = ceil(K_X / P): 4E > U_d  <=>  T B < C
    ranges: tuple[ProvenRange, ...]
    x_q_error: sp.Rational  # |X_q - X 2^f| <= this
    time_numerator_error: sp.Rational  # |time_numerator - K_G 2^f / B| <= this
    duty_error_bound_counts: sp.Rational
    time_error_bound_ticks: sp.Rational
    #: the time bound holds wherever W = 2P + 2 D_on P - 4 D_off P - X >= this (counts);
    #: below it Eq. 20's sensitivity t/W dominates and the verifier checks the pointwise
    #: interval instead (see `time_interval`).
    time_bound_min_w_counts: sp.Rational


def _bounds(
    expr: sp.Expr, box: dict[sp.Symbol, tuple[int, int]]
) -> tuple[sp.Rational, sp.Rational]:
    """Interval of expr over the box, by interval arithmetic (sound, maybe loose)."""
    value = sp.sympify(expr).subs({sym: sp.AccumBounds(lo, hi) for sym, (lo, hi) in box.items()})
    if isinstance(value, sp.AccumBounds):
        return sp.Rational(value.min), sp.Rational(value.max)
    return sp.Rational(value), sp.Rational(value)


def _prove(
    name: str, c_type: str, expr: sp.Expr, box: dict[sp.Symbol, tuple[int, int]]
) -> ProvenRange:
    low, high = _bounds(expr, box)
    lo_ok, hi_ok = LIMITS[c_type]
    if low < lo_ok or high > hi_ok:
        raise FixedPointError(
            f"{name} = {expr} spans [{low}, {high}] over the spec's input ranges, "
            f"which does not fit {c_type} [{lo_ok}, {hi_ok}]; narrow the spec's ranges"
        )
    return ProvenRange(name, c_type, int(sp.floor(low)), int(sp.ceiling(high)), str(expr))


def _round(value: sp.Rational) -> int:
    return int(sp.floor(value + sp.Rational(1, 2)))


def long_division(numerator: int) -> LongDivision:
    shift = max(0, numerator.bit_length() - 32)
    return LongDivision(numerator, shift, numerator >> shift, numerator & ((1 << shift) - 1))


def _long_division_ranges(
    name: str, ld: LongDivision, box: dict[sp.Symbol, tuple[int, int]], bus: sp.Symbol
) -> tuple[ProvenRange, ...]:
    return (
        _prove(f"{name} high part", "uint32_t", sp.Integer(ld.high), box),
        _prove(f"{name} remainder + B/2", "uint32_t", bus * 2**ld.shift - 1 + bus / 2, box),
        _prove(f"{name} / B", "uint32_t", sp.Rational(ld.numerator) / bus + 1, box),
    )


def _time_bound(
    sc: Scaling, frac_bits: int, x_q_err: sp.Rational, g_err: sp.Rational, w_counts: sp.Rational
) -> sp.Rational:
    """|t - t*| where W >= w_counts: the final rounding plus t* times the relative
    errors of the numerator (time_numerator) and the denominator (W_q)."""
    scale = 2**frac_bits
    eps_g = g_err * sc.bus_code_max / (sc.k_g * scale)
    eps_w = x_q_err / (w_counts * scale)
    return sp.Rational(1, 2) + sc.period_cap_ticks * (eps_g + eps_w) / (1 - eps_w)


def design(
    sc: Scaling,
    duty_target_counts: sp.Rational,
    time_target_ticks: sp.Rational,
    method: str = "improved",
) -> FixedPointDesign:
    T, B, I_code = sp.symbols("T B I_code", integer=True)
    p = sc.period_counts
    current_low = -sc.current_offset_code
    current_high = sc.adc_full_scale - 1 - sc.current_offset_code
    box = {
        T: (sc.period_min_ticks, sc.period_cap_ticks),
        B: (sc.bus_code_min, sc.bus_code_max),
        I_code: (current_low, current_high),
    }
    high_speed_tb = int(sp.ceiling(sc.k_x / p))
    reasons: list[str] = []
    # Precision costs nothing at run time (a shift count), so take the most fraction
    # bits whose intermediates all fit.
    for frac_bits in range(MAX_FRACTION_BITS, -1, -1):
        scale = 2**frac_bits
        k_x = long_division(_round(sc.k_x * scale))
        k_g = long_division(_round(sc.k_g * scale))
        x_num = k_x.numerator / B + 1
        x_q = (x_num + T / 2) / T
        time_num = k_g.numerator / B + 1
        try:
            ranges = (
                *_long_division_ranges("N_X", k_x, box, B),
                *_long_division_ranges("N_G", k_g, box, B),
                _prove("C + B - 1", "uint32_t", high_speed_tb + B - 1, box),
                _prove("x_numerator + T/2", "uint32_t", x_num + T / 2, box),
                _prove("X_q", "uint32_t", x_q + 1, box),
                _prove("W_q", "int32_t", (4 * p) * scale + x_q + 1, box),
                _prove("W_q low", "int32_t", -(2 * p) * scale - x_q - 1, box),
                _prove(
                    "time_numerator i + W_q/2", "int32_t", time_num * I_code + (2 * p) * scale, box
                ),
                _prove(
                    "time_numerator i - W_q/2",
                    "int32_t",
                    time_num * I_code - (4 * p) * scale - x_q,
                    box,
                ),
            )
            if method == "conventional":  # the exact fail-area test
                ranges += (
                    _prove("T*B", "uint32_t", T * B, box),
                    _prove("T*B*K_X_den*2P", "uint64_t", 2 * p * T * B * sc.k_x.q, box),
                )
        except FixedPointError as exc:
            reasons.append(f"Q{frac_bits}: {exc}")
            continue
        # x_numerator: N_X rounds by 1/2, the division by B by 1/2 more.
        x_num_err = sp.Rational(1, 2) + sp.Rational(1, 2 * sc.bus_code_min)
        x_q_err = sp.Rational(1, 2) + x_num_err / sc.period_min_ticks
        duty_err = sp.Rational(1, 2) + x_q_err / scale
        g_err = x_num_err
        if duty_err > duty_target_counts:
            raise FixedPointError(
                f"the best format, Q{frac_bits}, gives a duty error of {float(duty_err):.3f}"
                f" counts, above the target {float(duty_target_counts)}: no format is accurate"
                " enough"
            )
        # Smallest W (in counts) where the time bound meets the target: bisect on the
        # monotone bound.
        lo, hi = sp.Rational(1, 2**20), sp.Rational(4 * p)
        if _time_bound(sc, frac_bits, x_q_err, g_err, hi) > time_target_ticks:
            raise FixedPointError(
                f"Q{frac_bits}: the commutation time error exceeds {float(time_target_ticks)}"
                " ticks even at the largest W: no format is accurate enough"
            )
        for _ in range(40):
            mid = (lo + hi) / 2
            if _time_bound(sc, frac_bits, x_q_err, g_err, mid) > time_target_ticks:
                lo = mid
            else:
                hi = mid
        w_ok = sp.Rational(sp.ceiling(hi * 1000), 1000)
        return FixedPointDesign(
            scaling=sc,
            x_frac_bits=frac_bits,
            k_x=k_x,
            k_g=k_g,
            high_speed_tb=high_speed_tb,
            ranges=ranges,
            x_q_error=x_q_err,
            time_numerator_error=g_err,
            duty_error_bound_counts=duty_err,
            time_error_bound_ticks=_time_bound(sc, frac_bits, x_q_err, g_err, w_ok),
            time_bound_min_w_counts=w_ok,
        )
    raise FixedPointError(
        f"no format from Q0 to Q{MAX_FRACTION_BITS} is safe: " + "; ".join(reversed(reasons))
    )

"""Choose the integer formats of the core and prove them safe over the input domain.

The firmware computes, per Hall edge (all unsigned unless noted):

    TB    = T * B                                   uint32
    X_q   = round(K_Xq / ((TB + 2^(s-1)) >> s))     uint32, X = P 4E/U_d in Q(f) counts
    X_c   = round(X_q / 2^f)                        TIM1 counts
    duties from Eq. 18 / 16 in counts               int32, then clamped to [0, P]
    W_q   = (2P + 2 C_on - 4 C_off) 2^f - X_q       int32 (> 0, else t is unbounded)
    num   = K_Gq * I_code                           uint64 (one UMULL)
    t     = round((num >> h) / ((B * W_q) >> h))    uint32, h = bits of num above 32

K_Xq = round(K_X 2^f / 2^s) and K_Gq = round(K_G 2^f) are the two constants, traced
to Eqs. 9 and 20 by codegen.fixedpoint.scaling. The fraction bits f are the smallest
that meet the spec's accuracy target; s is the smallest shift that keeps the numerator
of the X division in 32 bits. Every intermediate's range is bounded with SymPy's
interval arithmetic (AccumBounds) over the whole input box and must fit its type, or
design() fails naming the quantity, its range and the type.
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from codegen.fixedpoint.scaling import Scaling

UINT32_MAX = 2**32 - 1
INT32_MAX = 2**31 - 1
INT32_MIN = -(2**31)
UINT64_MAX = 2**64 - 1


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
        limit = {"uint32_t": UINT32_MAX, "int32_t": INT32_MAX, "uint64_t": UINT64_MAX}[self.c_type]
        return float(sp.log(sp.Rational(limit, max(abs(self.high), abs(self.low), 1)), 2))


@dataclass(frozen=True)
class FixedPointDesign:
    scaling: Scaling
    x_frac_bits: int  # f
    tb_shift: int  # s
    k_x_q: int
    k_g_q: int
    ranges: tuple[ProvenRange, ...]
    duty_error_bound_counts: sp.Rational
    time_error_bound_ticks: sp.Rational


def _bounds(
    expr: sp.Expr, box: dict[sp.Symbol, tuple[int, int]]
) -> tuple[sp.Rational, sp.Rational]:
    """Interval of expr over the box, by interval arithmetic (sound, maybe loose)."""
    value = expr.subs({sym: sp.AccumBounds(lo, hi) for sym, (lo, hi) in box.items()})
    if isinstance(value, sp.AccumBounds):
        return sp.Rational(value.min), sp.Rational(value.max)
    return sp.Rational(value), sp.Rational(value)


def _prove(
    name: str, c_type: str, expr: sp.Expr, box: dict[sp.Symbol, tuple[int, int]]
) -> ProvenRange:
    low, high = _bounds(expr, box)
    limits = {
        "uint32_t": (0, UINT32_MAX),
        "int32_t": (INT32_MIN, INT32_MAX),
        "uint64_t": (0, UINT64_MAX),
    }
    lo_ok, hi_ok = limits[c_type]
    if low < lo_ok or high > hi_ok:
        raise FixedPointError(
            f"{name} = {expr} spans [{low}, {high}] over the spec's input ranges, "
            f"which does not fit {c_type} [{lo_ok}, {hi_ok}]; narrow the spec's ranges"
        )
    return ProvenRange(name, c_type, int(sp.floor(low)), int(sp.ceiling(high)), str(expr))


def design(
    sc: Scaling, duty_target_counts: sp.Rational, time_target_ticks: sp.Rational
) -> FixedPointDesign:
    T, B, I_code = sp.symbols("T B I_code", positive=True)
    box = {
        T: (sc.period_min_ticks, sc.period_max_ticks),
        B: (sc.bus_code_min, sc.bus_code_max),
        I_code: (max(sc.current_code_min, 0), sc.current_code_max),
    }
    p = sc.period_counts
    tb_min = sc.period_min_ticks * sc.bus_code_min
    tb_max = sc.period_max_ticks * sc.bus_code_max
    x_max = sc.k_x / tb_min
    reasons: list[str] = []
    candidates: list[
        tuple[sp.Rational, int, int, int, int, sp.Rational, tuple[ProvenRange, ...]]
    ] = []
    for frac_bits in range(0, 9):
        scale = 2**frac_bits
        shift = 0
        while sc.k_x * scale / 2**shift + (tb_max >> shift) > UINT32_MAX:
            shift += 1
        k_x_q = int(sp.floor(sc.k_x * scale / 2**shift + sp.Rational(1, 2)))
        k_g_q = int(sp.floor(sc.k_g * scale + sp.Rational(1, 2)))
        x_q = k_x_q / ((T * B) / 2**shift)
        try:
            ranges = (
                _prove("T*B", "uint32_t", T * B, box),
                _prove("K_Xq + (T*B >> s)/2", "uint32_t", k_x_q + T * B / 2 ** (shift + 1), box),
                _prove("X_q", "uint32_t", x_q + 1, box),
                _prove("W_q", "int32_t", (6 * p) * scale + x_q, box),
                _prove("B*W_q", "uint32_t", B * ((6 * p) * scale + x_q), box),
                _prove("K_Gq*I", "uint64_t", k_g_q * I_code, box),
                _prove("P*T*B*K_X_den", "uint64_t", 2 * p * T * B * sp.Rational(sc.k_x).q, box),
                _prove("duty sums", "int32_t", 3 * p + x_q / scale, box),
            )
        except FixedPointError as exc:
            reasons.append(f"Q{frac_bits}: {exc}")
            continue
        den_min = (tb_min + 2 ** (shift - 1)) >> shift if shift else tb_min
        # |X_q - X 2^f|: rounding of K_Xq (1/2), of the shifted T B (1/2 of 2^s) and
        # of the division (1/2), each scaled by the quotient it perturbs.
        x_q_err = sp.Rational(1, 2) + (x_max * scale) * (
            sp.Rational(1, 2) / (sc.k_x * scale / 2**shift) + sp.Rational(1, 2) / den_min
        )
        x_err_counts = x_q_err / scale
        duty_err = sp.Rational(1, 2) + x_err_counts  # final rounding to counts
        if duty_err > duty_target_counts:
            reasons.append(
                f"Q{frac_bits}: duty error {float(duty_err):.3f} counts > {float(duty_target_counts)}"
            )
            continue
        t_max = sc.period_max_ticks  # t is clamped to the sector
        # The firmware's W uses X_q where the reference uses the exact X, so W is off
        # by x_err_counts; t = K_G I / (B W) moves by t x_err / W <= K_G I x_err /
        # (B W^2), largest at the smallest W (= 3 X_min, low speed). Plus the
        # normalising shift of the 64-bit numerator (t^2 / 2^31), K_Gq's rounding
        # and the final rounding.
        w_min = 3 * (sc.k_x / tb_max) - x_err_counts
        i_max = sc.current_code_max
        time_err = (
            sp.Rational(1, 2)
            + sc.k_g * i_max * x_err_counts / (sc.bus_code_min * w_min**2)
            + sp.Rational(t_max**2, 2**31)
            + t_max * sp.Rational(1, 2) / (sc.k_g * scale)
        )
        if time_err > time_target_ticks:
            reasons.append(
                f"Q{frac_bits}: t_com error {float(time_err):.2f} ticks > {float(time_target_ticks)}"
            )
            continue
        candidates.append((duty_err, frac_bits, shift, k_x_q, k_g_q, time_err, ranges))
    if not candidates:
        raise FixedPointError(
            "no format from Q0 to Q8 is both safe and accurate enough: " + "; ".join(reasons)
        )
    # Precision costs nothing at run time here, so take the most accurate format.
    duty_err, frac_bits, shift, k_x_q, k_g_q, time_err, ranges = min(candidates, key=lambda c: c[0])
    return FixedPointDesign(
        scaling=sc,
        x_frac_bits=frac_bits,
        tb_shift=shift,
        k_x_q=k_x_q,
        k_g_q=k_g_q,
        ranges=ranges,
        duty_error_bound_counts=duty_err,
        time_error_bound_ticks=time_err,
    )

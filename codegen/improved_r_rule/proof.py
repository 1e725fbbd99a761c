"""Interval proof that no intermediate of the integer rule overflows its C type.

Every quantity of `codegen.improved_r_rule.fixed` is bounded by interval arithmetic
(SymPy AccumBounds) over the box: T in the speed range, B in the bus range, i from 0 to
the ADC full scale, x in [0, 2^K], psi in [psi_min, 2^16] (Q16; psi is positive and
at most 1). Rounding adds at most one unit to a quotient, which the bounds include.
The integer operations are monotone in each variable, so the intervals are tight
enough; a quantity that does not fit its type raises `RuleFormatError` with its name,
expression and range.
"""

from __future__ import annotations

import sympy as sp

from codegen.fixedpoint.design import LIMITS, ProvenRange
from codegen.improved_r_rule.fixed import THETA_FRAC_BITS, FixedRule, LongDivision
from codegen.improved_r_rule.table import ONE_Q16, PsiTable, grid_point


class RuleFormatError(ValueError):
    """An intermediate of the integer rule does not fit its type over the input box."""


Box = dict[sp.Symbol, tuple[int, int]]


def _bounds(expr: sp.Expr, box: Box) -> tuple[sp.Rational, sp.Rational]:
    value = sp.sympify(expr).subs({sym: sp.AccumBounds(lo, hi) for sym, (lo, hi) in box.items()})
    if isinstance(value, sp.AccumBounds):
        return sp.Rational(value.min), sp.Rational(value.max)
    return sp.Rational(value), sp.Rational(value)


def prove(name: str, c_type: str, expr: sp.Expr, box: Box) -> ProvenRange:
    low, high = _bounds(expr, box)
    lo_ok, hi_ok = LIMITS[c_type]
    if low < lo_ok or high > hi_ok:
        raise RuleFormatError(
            f"{name} = {expr} spans [{low}, {high}] over the input box, "
            f"which does not fit {c_type} [{lo_ok}, {hi_ok}]"
        )
    return ProvenRange(name, c_type, int(sp.floor(low)), int(sp.ceiling(high)), str(expr))


def prove_narrowest(name: str, expr: sp.Expr, box: Box, signed: bool = False) -> ProvenRange:
    """The narrowest of (u)int32_t and (u)int64_t that holds expr over the box, so the
    C uses a 32-bit multiply wherever the proof allows it."""
    types = ("int32_t", "int64_t") if signed else ("uint32_t", "uint64_t")
    try:
        return prove(name, types[0], expr, box)
    except RuleFormatError:
        return prove(name, types[1], expr, box)


def _long_division(name: str, ld: LongDivision, bus: sp.Symbol, box: Box) -> list[ProvenRange]:
    return [
        prove(f"{name} high part", "uint32_t", sp.Integer(ld.high), box),
        prove(f"{name} remainder 2^shift + low + B/2", "uint32_t", bus * 2**ld.shift + bus, box),
        prove(f"{name} / B", "uint32_t", sp.Rational(ld.numerator) / bus + 1, box),
    ]


def interpolation_product_max(table: PsiTable) -> int:
    """Largest (c[k+1] - c[k]) r + 2^(sh-1) of any y the table covers (exact).

    Entry k lies in segment j = k // 2^n, whose fraction has sh = fy - n + max(j-1, 0)
    bits (see `table.locate`)."""
    worst = 0
    per = 1 << table.segment_bits
    for k in range(table.entries - 1):
        shift = table.y_frac_bits - table.segment_bits + max(k // per - 1, 0)
        diff = max(
            table.complement1[k + 1] - table.complement1[k],
            table.complement2[k + 1] - table.complement2[k],
        )
        worst = max(worst, diff * ((1 << shift) - 1) + (1 << (shift - 1)))
    return worst


def unit_product_max(table: PsiTable) -> int:
    """Largest y psi1 (Q(fy + 16)) of any y the table covers: y psi1 = 1 - e^{-y} <= 1
    in exact arithmetic, but not for the interpolated table at large y. On entry k's
    interval y <= y_(k+1) and psi1 <= psi1_k (it decreases), so their product bounds it."""
    worst = 0
    for k in range(table.entries - 1):
        y_next = int(grid_point(k + 1, table.segment_bits) * 2**table.y_frac_bits)
        worst = max(worst, y_next * (ONE_Q16 - table.complement1[k]))
    return worst


def prove_at_most(name: str, expr: sp.Expr, limit: int, box: Box) -> ProvenRange:
    low, high = _bounds(expr, box)
    if low < 0 or high > limit:
        raise RuleFormatError(f"{name} = {expr} spans [{low}, {high}], beyond [0, {limit}]")
    return ProvenRange(name, "uint32_t", int(sp.floor(low)), int(sp.ceiling(high)), str(expr))


def prove_rule(rule: FixedRule) -> tuple[ProvenRange, ...]:
    c = rule.constants
    T, B, i, x = sp.symbols("T B i x", integer=True, nonnegative=True)
    psi = sp.Symbol("psi", positive=True)
    k, fc, pq = rule.steps, rule.counts_frac_bits, rule.period_q
    fu = rule.unit_frac_bits
    unit = 2**fu  # e, u1, v2 <= 1 (they are e^{-y}, x psi1, x^2 psi2 with x <= 1)
    table = rule.table
    psi_min = ONE_Q16 - max(max(table.complement1), max(table.complement2)) - 1
    box: Box = {
        T: (c.period_low, c.period_high),
        B: (c.bus_low, c.bus_high),
        i: (0, c.current_high),
        x: (0, 1 << k),
        psi: (psi_min, ONE_Q16),
    }
    xn = rule.n_x.numerator / B + 1
    yn = rule.n_y.numerator / B + 1
    x_q = xn / T + 1
    y_c = yn * i / 2**rule.y_guard_bits + 1
    ki = rule.kappa_q * i
    a_q = x_q * ki / 2**rule.kappa_frac_bits + 1
    rho = rule.k_rho_q * T
    s1 = x_q * rule.theta_half_q / 2**THETA_FRAC_BITS + 1
    y_q = rho * x / 2**rule.y_shift
    total_low, total_high = 2 * pq - x_q, 2 * pq + y_c + s1
    f2_low, f2_high = -4 * pq, 4 * pq + x_q
    ranges = [
        *_long_division("N_X", rule.n_x, B, box),
        *_long_division("N_Y", rule.n_y, B, box),
        prove("xn + T/2", "uint32_t", xn + T / 2, box),
        prove("X", "int32_t", x_q, box),
        prove("yn i + 2^(gy-1)", "uint32_t", yn * i + 2 ** (rule.y_guard_bits - 1), box),
        prove("KAPPA i", "uint32_t", ki, box),
        prove_narrowest("X KAPPA i + half", x_q * ki + 2**rule.kappa_frac_bits, box),
        prove("2 A", "int32_t", 2 * a_q, box),
        prove("RHO = KRHO T", "uint32_t", rho, box),
        prove_narrowest("X THETA + half", x_q * rule.theta_half_q + 2**THETA_FRAC_BITS, box),
        prove("S1", "int32_t", s1, box),
        prove("S0 low", "int32_t", 2 * pq - x_q, box),
        prove("S0 high", "int32_t", 2 * pq + y_c, box),
        prove_narrowest("RHO x", rho * x, box),
        prove_at_most("y (inside the table)", y_q, table.y_limit, box),
        prove(
            "interpolation product",
            "uint32_t",
            sp.Integer(interpolation_product_max(table)),
            box,
        ),
        prove_narrowest("y psi1 + half", y_q * psi + 2**table.y_frac_bits, box),
        prove(
            "round(y psi1) in Q fu (e = max(2^fu - it, 0))",
            "uint32_t",
            sp.Integer(unit_product_max(table)) / 2 ** (table.y_frac_bits + 16 - fu) + 1,
            box,
        ),
        prove("x psi", "uint32_t", x * psi, box),
        prove_narrowest("x (x psi2) + half", x * x * psi + 2 ** (2 * k + 16 - fu), box),
        # the loop's S(x) (x in Q K) and the result's S(x_c) (x_c in Q(K + 1))
        prove_narrowest("S1 x + half", s1 * 2 * x + 2**k, box),
        prove("S low", "int32_t", total_low, box),
        prove("S high", "int32_t", total_high, box),
        prove("S - P 2^fc", "int32_t", total_low - pq, box),
        prove("F2 low", "int32_t", sp.Integer(f2_low), box),
        prove("F2 high", "int32_t", f2_high, box),
        prove_narrowest("2 A e", 2 * a_q * unit, box, signed=True),
        prove_narrowest("F2 u1 low", f2_low * unit, box, signed=True),
        prove_narrowest("F2 u1 high", f2_high * unit, box, signed=True),
        prove_narrowest("X v2", x_q * unit, box, signed=True),
        prove_narrowest("2g high", 2 * a_q * unit + f2_high * unit, box, signed=True),
        prove_narrowest("2g low", f2_low * unit - x_q * unit, box, signed=True),
        prove("x_c T + half", "uint32_t", 2 ** (k + 1) * T + 2**k, box),
        prove("S(x_c) rounding", "int32_t", pq + 2**fc, box),
    ]
    return tuple(ranges)

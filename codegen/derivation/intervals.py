"""Intervals with symbolic ends, decided from the symbols' sign assumptions.

SymPy's own set operations give up on ends such as U_d/4 vs U_d/2 even when every
symbol is declared positive; these helpers order the ends with Max/Min, which do use
the assumptions, and refuse to answer rather than guess.
"""

from __future__ import annotations

import sympy as sp

from codegen.errors import DerivationError


def intersect(intervals: list[sp.Set]) -> sp.Interval:
    """Intersection of intervals with symbolic ends that SymPy can order (positive symbols)."""
    for interval in intervals:
        if not isinstance(interval, sp.Interval):
            raise DerivationError(f"expected an interval, got {interval}")
    start = sp.Max(*(i.start for i in intervals))
    end = sp.Min(*(i.end for i in intervals))
    if start.has(sp.Max) or end.has(sp.Min):
        raise DerivationError(f"cannot order the interval ends of {intervals}")
    left_open = any(i.left_open for i in intervals if sp.simplify(i.start - start) == 0)
    right_open = any(i.right_open for i in intervals if sp.simplify(i.end - end) == 0)
    return sp.Interval(start, end, left_open, right_open)


def interval_where(expr: sp.Expr, low: sp.Expr, high: sp.Expr, var: sp.Symbol) -> sp.Interval:
    """Set of `var` (positive where its symbol says so) for which low <= expr <= high."""
    lower = sp.solve_univariate_inequality(expr >= low, var, relational=False)
    upper = sp.solve_univariate_inequality(expr <= high, var, relational=False)
    domain = sp.Interval.open(0, sp.oo) if var.is_positive else sp.Interval(-sp.oo, sp.oo)
    return intersect([lower, upper, domain])


def must_hold(condition: sp.Basic, var: sp.Symbol, region: sp.Set, what: str) -> None:
    """Prove that `condition` holds for every var in `region`."""
    holds = sp.solve_univariate_inequality(condition, var, relational=False)
    if not (isinstance(holds, sp.Interval) and contains(holds, region)):
        raise DerivationError(f"{what}: not true on {region} (holds on {holds})")


def contains(outer: sp.Interval, inner: sp.Interval) -> bool:
    """inner is a subset of outer, decided from the symbols' sign assumptions."""
    low = sp.simplify(inner.start - outer.start)
    high = sp.simplify(outer.end - inner.end)
    low_ok = bool(low.is_extended_positive) or (
        bool(low.is_zero) and (inner.left_open or not outer.left_open)
    )
    high_ok = bool(high.is_extended_positive) or (
        bool(high.is_zero) and (inner.right_open or not outer.right_open)
    )
    return low_ok and high_ok

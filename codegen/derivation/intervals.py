"""Intervals with symbolic ends, decided from the symbols' sign assumptions.

SymPy's own set operations give up on ends such as U_d/4 vs U_d/2 even when every
symbol is declared positive; these helpers order the ends with Max/Min, which do use
the assumptions, and refuse to answer rather than guess.

Every inequality of the paper is linear in its unknown. `solve_inequality` solves those
directly (the sign of the slope from the symbols' assumptions), which is what SymPy's
general solve_univariate_inequality also concludes, at a twentieth of its cost (it
first tries periodicity, singularities and so on); anything else goes to SymPy.
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


def _linear_solution(condition: sp.Rel, var: sp.Symbol) -> sp.Set | None:
    """The real solutions of `condition` if it is `a var + b (op) 0` with the sign of a
    known from the assumptions, else None."""
    if not isinstance(
        condition, (sp.GreaterThan, sp.StrictGreaterThan, sp.LessThan, sp.StrictLessThan)
    ):
        return None
    f = condition.lhs - condition.rhs
    slope = sp.cancel(sp.diff(f, var))
    if slope.has(var):
        return None
    if slope.is_positive:
        rising = True
    elif slope.is_negative:
        rising = False
    else:
        return None
    root = sp.expand(-f.subs(var, 0) / slope)
    strict = isinstance(condition, (sp.StrictGreaterThan, sp.StrictLessThan))
    above = isinstance(condition, (sp.GreaterThan, sp.StrictGreaterThan)) == rising
    if above:
        return sp.Interval(root, sp.oo, strict, True)
    return sp.Interval(-sp.oo, root, True, strict)


def solve_inequality(condition: sp.Basic, var: sp.Symbol) -> sp.Set:
    """The set of real `var` where `condition` holds (SymPy's relational=False form)."""
    solution = _linear_solution(condition, var)
    if solution is not None:
        return solution
    return sp.solve_univariate_inequality(condition, var, relational=False)


def interval_where(expr: sp.Expr, low: sp.Expr, high: sp.Expr, var: sp.Symbol) -> sp.Interval:
    """Set of `var` (positive where its symbol says so) for which low <= expr <= high."""
    lower = solve_inequality(expr >= low, var)
    upper = solve_inequality(expr <= high, var)
    domain = sp.Interval.open(0, sp.oo) if var.is_positive else sp.Interval(-sp.oo, sp.oo)
    return intersect([lower, upper, domain])


def must_hold(condition: sp.Basic, var: sp.Symbol, region: sp.Set, what: str) -> None:
    """Prove that `condition` holds for every var in `region`."""
    holds = solve_inequality(condition, var)
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

"""Error analysis of IR expressions: how far each computed integer is from its ideal.

The ideal of a node is the same expression evaluated in real arithmetic with every
constant at its exact value (`IConst.exact`) and no rounding: a rounding shift is a
division by 2^s, a rounding division a real quotient, a long division N*/B. The bound
is sound over the interval box the prover gives (first-order terms and their products
included, no linearisation):

    a + b, a - b   e_a + e_b
    a b            |a| e_b + |b| e_a + e_a e_b
    a >> s         e_a / 2^s + 1/2 (to nearest) or 1 - 2^-s (down)
    a / b          rounding + (e_a + |a/b| e_b) / (b_min - e_b),  b > e_b
    round(N / B)   1/2 + |N - N*| / B_min + N e_B / (B_min (B_min - e_B))
    min/max/clamp  max of the operands' errors (they are 1-Lipschitz)
    exact select   max of the branches' errors (the decision is the ideal one)

Variables take the errors the caller states (inputs are exact; a value that the check
of an output treats as given, such as the emitted duties of Eq. 20, has error 0).
"""

from __future__ import annotations

from fractions import Fraction

from codegen.ir.intervals import Env, Interval, Prover, refine
from codegen.ir.nodes import (
    Expr,
    IBin,
    ICast,
    ICmp,
    IConst,
    IDiv,
    IField,
    ILongDiv,
    ISelect,
    IShl,
    IShr,
    IVar,
)

Errors = dict[str, Fraction]


class ErrorAnalysisError(ValueError):
    """The expression has a node whose ideal the analysis cannot relate to it."""


def _magnitude(v: Interval) -> int:
    return max(abs(v.lo), abs(v.hi))


def _min_positive(v: Interval) -> int:
    if v.lo <= 0:
        raise ErrorAnalysisError(f"divisor spans {v}")
    return v.lo


def error(prover: Prover, e: Expr, env: Env, errs: Errors) -> Fraction:
    """max |computed - ideal| of e over env (intervals) with the variables' errors."""
    if isinstance(e, IConst):
        return e.error
    if isinstance(e, IVar):
        return errs.get(e.name, Fraction(0))
    if isinstance(e, IField):
        return errs.get(f"{e.base}.{e.field}", Fraction(0))
    if isinstance(e, ICast):
        return error(prover, e.a, env, errs)
    if isinstance(e, IBin):
        ea, eb = error(prover, e.a, env, errs), error(prover, e.b, env, errs)
        if e.op in "+-":
            return ea + eb
        if e.op == "*":
            a, b = _magnitude(prover.ev(e.a, env)), _magnitude(prover.ev(e.b, env))
            return a * eb + b * ea + ea * eb
        if ea == eb == 0:
            return Fraction(0)
        raise ErrorAnalysisError(f"bitwise {e.op} of inexact values")
    if isinstance(e, IShr):
        if not isinstance(e.shift, int):
            raise ErrorAnalysisError("variable shift")
        ea = error(prover, e.a, env, errs)
        rounding = Fraction(1, 2) if e.rounding == "nearest" else 1 - Fraction(1, 2**e.shift)
        return ea / 2**e.shift + rounding
    if isinstance(e, IShl):
        if not isinstance(e.shift, int):
            raise ErrorAnalysisError("variable shift")
        return error(prover, e.a, env, errs) * 2**e.shift
    if isinstance(e, IDiv):
        ea, eb = error(prover, e.a, env, errs), error(prover, e.b, env, errs)
        a, b = prover.ev(e.a, env), prover.ev(e.b, env)
        b_min = _min_positive(b)
        if eb >= b_min:
            raise ErrorAnalysisError(f"divisor error {eb} reaches the divisor {b_min}")
        quotient = Fraction(_magnitude(a), b_min)
        exact_part = (ea + quotient * eb) / (b_min - eb)
        nearest = e.rounding == "nearest" and (a.lo >= 0 or not e.ctype.signed)
        return exact_part + (Fraction(1, 2) if nearest else Fraction(1))
    if isinstance(e, ILongDiv):
        eb = error(prover, e.divisor, env, errs)
        b_min = _min_positive(prover.ev(e.divisor, env))
        n = e.numerator
        return Fraction(1, 2) + n.error / b_min + Fraction(n.value) * eb / (b_min * (b_min - eb))
    if isinstance(e, ISelect):
        branches = []
        cond = prover.ev(e.cond, env)
        for truth, branch in ((True, e.a), (False, e.b)):
            if (truth and cond.hi == 0) or (not truth and cond.lo == 1):
                continue
            narrowed = refine(prover, env, e.cond, truth)
            if narrowed is not None:
                branches.append(error(prover, branch, narrowed, errs))
        if not e.lipschitz and (cond.lo != cond.hi) and not _exact(e.cond):
            raise ErrorAnalysisError("a select decided by an inexact comparison")
        return max(branches)
    raise ErrorAnalysisError(f"no ideal for {type(e).__name__}")


def _exact(cond: Expr) -> bool:
    return isinstance(cond, ICmp) and cond.exact


def walk_errors(
    prover: Prover, stmts: tuple, env: Env, errs: Errors, ignore: frozenset[str] = frozenset()
) -> Errors:
    """Errors of every local through straight-line code and exactly decided branches.

    Variables in `ignore` keep the error the caller gave them (the check treats them as
    given). A local assigned under an inexact decision, or whose ideal the analysis
    cannot relate, gets no entry (unknown). Intervals follow the prover's rules."""
    from codegen.ir.nodes import SAssign, SComment, SIf, SLet, SOrAssign, SReturn, SStruct, SVar

    out = dict(errs)
    for s in stmts:
        if isinstance(s, SComment | SReturn | SOrAssign | SStruct):
            continue
        if isinstance(s, SLet | SVar | SAssign):
            expr = s.expr if not isinstance(s, SVar) else s.init
            if s.name not in ignore:
                try:
                    out[s.name] = error(prover, expr, env, out)
                except (ErrorAnalysisError, KeyError):
                    out.pop(s.name, None)
            env[s.name] = prover.ev(expr, env)
            continue
        if isinstance(s, SIf):
            cond = prover.ev(s.cond, env)
            branches = []
            for truth, block in ((True, s.then), (False, s.orelse)):
                if (truth and cond.hi == 0) or (not truth and cond.lo == 1):
                    continue
                narrowed = refine(prover, env, s.cond, truth)
                if narrowed is None:
                    continue
                returns = any(isinstance(b, SReturn) for b in block)
                result = walk_errors(prover, block, narrowed, out, ignore)
                if not returns:
                    branches.append((narrowed, result))
            if not branches:
                return out
            decided = cond.lo == cond.hi or _exact(s.cond)
            merged: Errors = {}
            for key in set.intersection(*(set(r) for _, r in branches)):
                values = [r[key] for _, r in branches]
                changed = any(r[key] != out.get(key) for _, r in branches)
                if decided or not changed:
                    merged[key] = max(values)
            env.clear()
            env.update(_join([e for e, _ in branches]))
            out = merged
            continue
        raise ErrorAnalysisError(f"unsupported statement {type(s).__name__}")
    return out


def _join(envs: list[Env]) -> Env:
    joined = dict(envs[0])
    for other in envs[1:]:
        joined = {k: v.union(other[k]) for k, v in joined.items() if k in other}
    return joined

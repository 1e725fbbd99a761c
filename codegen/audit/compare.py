"""Compare one printed equation row with the derived one, and explain a difference.

Equality is decided by simplifying the difference to zero. When SymPy cannot reduce a
non-zero-looking difference, both sides are evaluated at seeded random rational
points; a single point where they differ is a proof of difference.
"""

from __future__ import annotations

import random
from dataclasses import dataclass
from enum import StrEnum

import sympy as sp

from codegen.audit.dimensions import check_dimensions
from codegen.audit.transcription import PrintedRow, Transcription, parse_printed
from codegen.derivation import symbols as s
from codegen.derivation.intervals import interval_where

RANDOM_POINTS = 24


class Verdict(StrEnum):
    MATCH = "match"
    NOTATION = "match, notation differs"
    ENDPOINT = "endpoint differs"
    MISMATCH = "mismatch"
    MODEL = "model (taken as given)"

    @property
    def is_finding(self) -> bool:
        return self in (Verdict.ENDPOINT, Verdict.MISMATCH)

    @property
    def severity(self) -> int:
        order = [Verdict.MODEL, Verdict.MATCH, Verdict.NOTATION, Verdict.ENDPOINT, Verdict.MISMATCH]
        return order.index(self)


@dataclass(frozen=True)
class RowResult:
    name: str
    lhs: str
    printed_latex: str
    derived_latex: str
    verdict: Verdict
    method: str
    findings: tuple[str, ...]
    notes: tuple[str, ...]
    vanishes_without_r: bool


def _equal_at_random_points(a: sp.Expr, b: sp.Expr, seed: str) -> bool:
    rng = random.Random(seed)
    symbols = sorted(a.free_symbols | b.free_symbols, key=str)
    for _ in range(RANDOM_POINTS):
        point = {sym: sp.Rational(rng.randint(1, 997), rng.randint(1, 97)) for sym in symbols}
        if sp.simplify(a.subs(point) - b.subs(point)) != 0:
            return False
    return True


def _same(a: sp.Expr, b: sp.Expr, seed: str) -> tuple[bool, str]:
    if sp.simplify(sp.expand(a - b)) == 0:
        return True, "difference simplifies to 0"
    if _equal_at_random_points(a, b, seed):
        return True, f"equal at {RANDOM_POINTS} random rational points"
    return False, "non-zero at a random rational point"


def _sign_flips(printed: sp.Expr, derived: sp.Expr) -> list[str]:
    """Terms whose sign, flipped alone, turns the printed form into the derived one."""
    terms = sp.Add.make_args(sp.expand(printed))
    out = []
    for term in terms:
        if sp.simplify(sp.expand(printed - 2 * term - derived)) == 0:
            out.append(
                f"the term ${sp.latex(term)}$ has the wrong sign (derived: ${sp.latex(-term)}$)"
            )
    return out


def _explain(printed: sp.Expr, derived: sp.Expr) -> tuple[list[str], bool]:
    findings: list[str] = []
    clash = check_dimensions(printed)
    if clash is not None:
        by_dim: dict[str, list[str]] = {}
        for term, dim in clash.terms:
            by_dim.setdefault(dim, []).append(term)
        odd = min(by_dim.items(), key=lambda item: len(item[1]))
        rest = [d for d in by_dim if d != odd[0]]
        findings.append(
            "dimensionally inconsistent: "
            + ", ".join(f"${t}$" for t in odd[1])
            + f" is in {odd[0]} while the other terms are in {', '.join(rest)}"
        )
    printed_0, derived_0 = printed.subs(s.R, 0), derived.subs(s.R, 0)
    without_r_equal = sp.simplify(sp.expand(printed_0 - derived_0)) == 0
    if not without_r_equal:
        flips = _sign_flips(printed_0, derived_0)
        findings.extend(flips)
        if not flips:
            diff = sp.simplify(derived_0 - printed_0)
            findings.append(f"derived minus printed is ${sp.latex(diff)}$")
    r_part_printed = sp.simplify(printed - printed_0)
    r_part_derived = sp.simplify(derived - derived_0)
    if sp.simplify(r_part_printed - r_part_derived) != 0:
        findings.append(
            f"resistance term printed as ${sp.latex(r_part_printed)}$, derived "
            f"${sp.latex(r_part_derived)}$"
        )
        if without_r_equal:
            findings.append("with R = 0 the printed and derived forms agree")
    return findings, without_r_equal


def _interval_verdict(printed: sp.Interval, derived: sp.Interval) -> tuple[Verdict, list[str]]:
    ends_equal = (
        sp.simplify(printed.start - derived.start) == 0
        and sp.simplify(printed.end - derived.end) == 0
    )
    if not ends_equal:
        return Verdict.MISMATCH, [f"printed ${sp.latex(printed)}$, derived ${sp.latex(derived)}$"]
    findings = []
    if printed.left_open != derived.left_open:
        word = "excludes" if printed.left_open else "includes"
        findings.append(f"the printed form {word} the end point ${sp.latex(printed.start)}$")
    if printed.right_open != derived.right_open:
        word = "excludes" if printed.right_open else "includes"
        findings.append(f"the printed form {word} the end point ${sp.latex(printed.end)}$")
    return (Verdict.ENDPOINT, findings) if findings else (Verdict.MATCH, [])


def _solve(expr: sp.Basic, var: sp.Symbol) -> list[sp.Expr]:
    return sorted((sp.simplify(x) for x in sp.solve(expr, var)), key=sp.default_sort_key)


def compare_row(
    key: str,
    row: PrintedRow,
    derived: sp.Basic,
    transcription: Transcription,
    derived_note: str = "",
) -> RowResult:
    notes: list[str] = []
    if row.parse_note:
        notes.append(
            f"parsed as ${row.parse}$: {row.parse_note}"
            if row.parse != row.latex
            else row.parse_note
        )
    seed = f"{key}/{row.name}"
    vanishes = False
    if row.compare == "interval":
        low = parse_printed(row.low, transcription)
        high = parse_printed(row.high, transcription)
        printed_set = sp.Interval(low.expr, high.expr, row.low_open, row.high_open)
        verdict, findings = _interval_verdict(printed_set, derived)
        if findings and derived_note:
            findings.append(derived_note)
        notes.extend(low.notations + high.notations)
        printed_latex, method = sp.latex(printed_set), "interval ends and openness"
    else:
        parsed = parse_printed(row.parse, transcription)
        notes.extend(parsed.notations)
        printed_expr = parsed.expr
        findings = []
        if row.compare == "bounds":
            var = s.BY_NAME[row.var]
            printed_set = interval_where(
                printed_expr, sp.sympify(row.low), sp.sympify(row.high), var
            )
            verdict, findings = _interval_verdict(printed_set, derived)
            printed_latex, method = (
                sp.latex(printed_set),
                f"solved {row.low} <= . <= {row.high} for {row.var}",
            )
        elif row.compare in ("zero_set", "relation"):
            var = s.BY_NAME[row.solve_for]
            if row.compare == "relation":
                lhs = parse_printed(row.lhs, transcription).expr
                printed_rel: sp.Basic = sp.Eq(lhs, printed_expr)
            else:
                printed_rel = printed_expr
            derived_rel = derived.lhs - derived.rhs if isinstance(derived, sp.Equality) else derived
            printed_zero = (
                printed_rel.lhs - printed_rel.rhs
                if isinstance(printed_rel, sp.Equality)
                else printed_rel
            )
            a, b = _solve(printed_zero, var), _solve(derived_rel, var)
            same = len(a) == len(b) and all(
                sp.simplify(x - y) == 0 for x, y in zip(a, b, strict=True)
            )
            verdict = Verdict.MATCH if same else Verdict.MISMATCH
            if not same:
                findings.append(
                    f"solving for ${sp.latex(var)}$ gives ${sp.latex(a)}$, derived ${sp.latex(b)}$"
                )
            printed_latex, method = sp.latex(printed_rel), f"same solution for {row.solve_for}"
        else:
            same, method = _same(printed_expr, derived, seed)
            verdict = Verdict.MATCH if same else Verdict.MISMATCH
            if not same:
                findings, vanishes = _explain(printed_expr, derived)
            printed_latex = sp.latex(printed_expr)
    if verdict == Verdict.MATCH and notes:
        verdict = Verdict.NOTATION
    derived_latex = sp.latex(derived)
    return RowResult(
        name=row.name,
        lhs=row.lhs,
        printed_latex=printed_latex,
        derived_latex=derived_latex,
        verdict=verdict,
        method=method,
        findings=tuple(findings),
        notes=tuple(notes),
        vanishes_without_r=vanishes,
    )

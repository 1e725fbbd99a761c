"""Compare one printed equation row with the derived one, and explain a difference.

Equality is decided by simplifying the difference to zero. When SymPy cannot reduce a
non-zero-looking difference, both sides are evaluated at seeded random rational
points; a single point where they differ is a proof of difference.

Besides the verdict, each row carries what a reader needs to see the difference: the
printed and derived forms term by term with the differing terms marked
(`HIGHLIGHT`, a LaTeX colour group that code hosts and the HTML report both show), and
derived minus printed.
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


#: Marks a differing term or end point in the LaTeX of a row. Code hosts render the
#: colour; the HTML report restyles it as a highlighted background.
HIGHLIGHT = r"\color{red}"


@dataclass(frozen=True)
class Difference:
    """One way a printed row differs from the derived one.

    kind: dimension | sign | resistance | r_only | difference | interval | endpoint |
    solution | why. `text` is the full sentence; `short` a few words that do not name
    the row, so that rows with the same fault can share one line of the finding
    (empty for context that belongs in the evidence only).
    """

    kind: str
    short: str
    text: str


@dataclass(frozen=True)
class RowResult:
    name: str
    lhs: str
    printed_latex: str
    derived_latex: str
    verdict: Verdict
    method: str
    differences: tuple[Difference, ...]
    notes: tuple[str, ...]
    vanishes_without_r: bool
    #: Printed and derived forms for display, differing parts marked with HIGHLIGHT.
    printed_display: str
    derived_display: str
    #: derived minus printed (LaTeX), empty when they agree.
    difference_display: str

    @property
    def findings(self) -> tuple[str, ...]:
        return tuple(d.text for d in self.differences)


def marked(latex: str) -> str:
    return f"{{{HIGHLIGHT} {latex}}}"


def is_zero(expr: sp.Expr) -> bool:
    """Whether `expr` is zero. cancel() brings a rational function (all of the paper's)
    to canonical p/q form, which is 0 exactly when the function is: a decision either
    way. Anything else gets simplify(), where False means "not shown to be zero"."""
    if sp.cancel(expr) == 0:
        return True
    if expr.is_rational_function():
        return False
    return sp.simplify(expr) == 0


def _equal_at_random_points(a: sp.Expr, b: sp.Expr, seed: str) -> bool:
    rng = random.Random(seed)
    symbols = sorted(a.free_symbols | b.free_symbols, key=str)
    for _ in range(RANDOM_POINTS):
        point = {sym: sp.Rational(rng.randint(1, 997), rng.randint(1, 97)) for sym in symbols}
        if not is_zero(a.subs(point) - b.subs(point)):
            return False
    return True


def _same(a: sp.Expr, b: sp.Expr, seed: str) -> tuple[bool, str]:
    if is_zero(sp.expand(a - b)):
        return True, "difference simplifies to 0"
    if _equal_at_random_points(a, b, seed):
        return True, f"equal at {RANDOM_POINTS} random rational points"
    return False, "non-zero at a random rational point"


def _sign_flips(printed: sp.Expr, derived: sp.Expr) -> list[Difference]:
    """Terms whose sign, flipped alone, turns the printed form into the derived one."""
    terms = sp.Add.make_args(sp.expand(printed))
    out = []
    for term in terms:
        if is_zero(sp.expand(printed - 2 * term - derived)):
            out.append(
                Difference(
                    "sign",
                    f"wrong sign on ${sp.latex(term)}$",
                    f"the term ${sp.latex(term)}$ has the wrong sign (derived: ${sp.latex(-term)}$)",
                )
            )
    return out


def _resistance_short(printed_r: sp.Expr, derived_r: sp.Expr) -> str:
    """'lacks the factor 1/L' when the printed resistance term is off by a factor that
    does not depend on the row (the same fault in every row reads as one)."""
    if printed_r != 0 and derived_r != 0:
        factor = sp.simplify(derived_r / printed_r)
        if not factor.free_symbols & {s.i_a, s.i_b, s.i_c, s.R}:
            return f"resistance term lacks the factor ${sp.latex(factor)}$"
    return "resistance term differs"


def _explain(printed: sp.Expr, derived: sp.Expr) -> tuple[list[Difference], bool]:
    findings: list[Difference] = []
    clash = check_dimensions(printed)
    if clash is not None:
        by_dim: dict[str, list[str]] = {}
        for term, dim in clash.terms:
            by_dim.setdefault(dim, []).append(term)
        odd = min(by_dim.items(), key=lambda item: len(item[1]))
        rest = [d for d in by_dim if d != odd[0]]
        findings.append(
            Difference(
                "dimension",
                "dimensionally inconsistent",
                "dimensionally inconsistent: "
                + ", ".join(f"${t}$" for t in odd[1])
                + f" is in {odd[0]} while the other terms are in {', '.join(rest)}",
            )
        )
    printed_0, derived_0 = printed.subs(s.R, 0), derived.subs(s.R, 0)
    without_r_equal = is_zero(sp.expand(printed_0 - derived_0))
    if not without_r_equal:
        flips = _sign_flips(printed_0, derived_0)
        findings.extend(flips)
        if not flips:
            diff = sp.simplify(derived_0 - printed_0)
            findings.append(
                Difference(
                    "difference",
                    "differs from the derivation",
                    f"derived minus printed is ${sp.latex(diff)}$",
                )
            )
    r_part_printed = sp.cancel(printed - printed_0)
    r_part_derived = sp.cancel(derived - derived_0)
    if not is_zero(r_part_printed - r_part_derived):
        findings.append(
            Difference(
                "resistance",
                _resistance_short(r_part_printed, r_part_derived),
                f"resistance term printed as ${sp.latex(r_part_printed)}$, derived "
                f"${sp.latex(r_part_derived)}$",
            )
        )
        if without_r_equal:
            findings.append(
                Difference("r_only", "", "with R = 0 the printed and derived forms agree")
            )
    return findings, without_r_equal


def _interval_verdict(
    printed: sp.Interval, derived: sp.Interval
) -> tuple[Verdict, list[Difference]]:
    ends_equal = is_zero(printed.start - derived.start) and is_zero(printed.end - derived.end)
    if not ends_equal:
        return Verdict.MISMATCH, [
            Difference(
                "interval",
                "different interval",
                f"printed ${sp.latex(printed)}$, derived ${sp.latex(derived)}$",
            )
        ]
    findings = []
    for end, printed_open, derived_open in (
        (printed.start, printed.left_open, derived.left_open),
        (printed.end, printed.right_open, derived.right_open),
    ):
        if printed_open != derived_open:
            word = "excludes" if printed_open else "includes"
            findings.append(
                Difference(
                    "endpoint",
                    f"{word} the end point ${sp.latex(end)}$",
                    f"the printed form {word} the end point ${sp.latex(end)}$",
                )
            )
    return (Verdict.ENDPOINT, findings) if findings else (Verdict.MATCH, [])


def _solve(expr: sp.Basic, var: sp.Symbol) -> list[sp.Expr]:
    """The solutions of expr = 0 for var: directly where expr is linear in var (every
    row of the paper), else by sp.solve."""
    slope = sp.cancel(sp.diff(expr, var))
    if not slope.has(var) and slope != 0:
        return [sp.cancel(-expr.subs(var, 0) / slope)]
    return sorted((sp.simplify(x) for x in sp.solve(expr, var)), key=sp.default_sort_key)


def _terms_display(expr: sp.Expr, other: sp.Expr) -> str:
    """`expr` expanded into terms, marking each term the other side does not have."""
    theirs = list(sp.Add.make_args(sp.expand(other)))
    parts = []
    for index, term in enumerate(sp.expand(expr).as_ordered_terms()):
        tex = sp.latex(term)
        if index and not tex.startswith("-"):
            tex = f"+ {tex}"
        if term in theirs:
            theirs.remove(term)
            parts.append(tex)
        else:
            parts.append(marked(tex))
    return " ".join(parts)


def _interval_display(interval: sp.Interval, other: sp.Interval) -> str:
    """An interval with the brackets or end points that differ from `other` marked."""
    if not isinstance(other, sp.Interval):
        return sp.latex(interval)
    start, end = sp.latex(interval.start), sp.latex(interval.end)
    left = "(" if interval.left_open else "["
    right = ")" if interval.right_open else "]"
    if not is_zero(interval.start - other.start):
        start = marked(start)
    elif interval.left_open != other.left_open:
        left = marked(left)
    if not is_zero(interval.end - other.end):
        end = marked(end)
    elif interval.right_open != other.right_open:
        right = marked(right)
    return f"{left}{start}, {end}{right}"


def _displays(printed: sp.Basic, derived: sp.Basic, verdict: Verdict) -> tuple[str, str, str]:
    """(printed, derived, derived minus printed) for display."""
    if not verdict.is_finding:
        return sp.latex(printed), sp.latex(derived), ""
    if isinstance(printed, sp.Interval) and isinstance(derived, sp.Interval):
        return _interval_display(printed, derived), _interval_display(derived, printed), ""
    if isinstance(printed, sp.Expr) and isinstance(derived, sp.Expr):
        return (
            _terms_display(printed, derived),
            _terms_display(derived, printed),
            sp.latex(sp.expand(derived - printed)),
        )
    return sp.latex(printed), sp.latex(derived), ""


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
    findings: list[Difference] = []
    printed: sp.Basic
    if row.compare == "interval":
        low = parse_printed(row.low, transcription)
        high = parse_printed(row.high, transcription)
        printed = sp.Interval(low.expr, high.expr, row.low_open, row.high_open)
        verdict, findings = _interval_verdict(printed, derived)
        if findings and derived_note:
            findings.append(Difference("why", "", derived_note))
        notes.extend(low.notations + high.notations)
        method = "interval ends and openness"
    else:
        parsed = parse_printed(row.parse, transcription)
        notes.extend(parsed.notations)
        printed_expr = parsed.expr
        if row.compare == "bounds":
            var = s.BY_NAME[row.var]
            printed = interval_where(printed_expr, sp.sympify(row.low), sp.sympify(row.high), var)
            verdict, findings = _interval_verdict(printed, derived)
            method = f"solved {row.low} <= . <= {row.high} for {row.var}"
        elif row.compare in ("zero_set", "relation"):
            var = s.BY_NAME[row.solve_for]
            if row.compare == "relation":
                lhs = parse_printed(row.lhs, transcription).expr
                printed = sp.Eq(lhs, printed_expr)
            else:
                printed = printed_expr
            derived_rel = derived.lhs - derived.rhs if isinstance(derived, sp.Equality) else derived
            printed_zero = (
                printed.lhs - printed.rhs if isinstance(printed, sp.Equality) else printed
            )
            a, b = _solve(printed_zero, var), _solve(derived_rel, var)
            same = len(a) == len(b) and all(is_zero(x - y) for x, y in zip(a, b, strict=True))
            verdict = Verdict.MATCH if same else Verdict.MISMATCH
            if not same:
                findings.append(
                    Difference(
                        "solution",
                        f"different solution for ${sp.latex(var)}$",
                        f"solving for ${sp.latex(var)}$ gives ${sp.latex(a)}$, derived"
                        f" ${sp.latex(b)}$",
                    )
                )
            method = f"same solution for {row.solve_for}"
        else:
            printed = printed_expr
            same, method = _same(printed_expr, derived, seed)
            verdict = Verdict.MATCH if same else Verdict.MISMATCH
            if not same:
                findings, vanishes = _explain(printed_expr, derived)
    if verdict == Verdict.MATCH and notes:
        verdict = Verdict.NOTATION
    printed_display, derived_display, difference_display = _displays(printed, derived, verdict)
    return RowResult(
        name=row.name,
        lhs=row.lhs,
        printed_latex=sp.latex(printed),
        derived_latex=sp.latex(derived),
        verdict=verdict,
        method=method,
        differences=tuple(findings),
        notes=tuple(notes),
        vanishes_without_r=vanishes,
        printed_display=printed_display,
        derived_display=derived_display,
        difference_display=difference_display,
    )

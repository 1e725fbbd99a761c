"""ACSL, the specification language Frama-C reads, printed from Python.

Two jobs, both printed into the shipped C as `/*@ ... */` comments (compilers ignore
them; `make prove` reads them):

* Function contracts (`Contract`, `Predicate`): what the public API promises, laid out
  above each prototype. Their content is decided in `codegen/core/contracts.py`; this
  module only lays them out.
* Proof hints derived from the IR, so that Frama-C's EVA makes the case splits the IR's
  own interval proof makes (`codegen/ir/intervals.py`): a loop's declared invariants
  (`SFor.invariants`) become `loop invariant`/`loop assigns`/`loop variant`; a local the
  proof splits on (`SLet.split`) becomes `split`; a table step (`IStep`), which the proof
  bounds row by row, is analysed row by row between `split` and `merge`. A split only
  partitions the analysis, it assumes nothing: a wrong hint costs precision, never
  soundness.

`term` prints an IR expression as an ACSL term over mathematical integers (used to state
what a conditioned bus is); `//@` annotations attach to the next statement, so a hint
between declarations is anchored on an empty ghost statement (`/*@ ghost ; */`).
"""

from __future__ import annotations

from dataclasses import dataclass

from codegen.ir.nodes import (
    Expr,
    IAnd,
    IBin,
    ICast,
    ICmp,
    IConst,
    IDiv,
    IField,
    ILongDiv,
    IMod,
    INot,
    IOr,
    ISelect,
    IShl,
    IShr,
    IStep,
    IVar,
    SAssign,
    SFor,
    SLet,
    SOrAssign,
    Stmt,
)
from codegen.ir.walk import all_statements, expressions, statement_exprs

#: a hint that must sit between declarations: ACSL attaches it to the ghost statement
ANCHOR = "/*@ ghost ; */"


# ------------------------------------------------------------------ contracts


@dataclass(frozen=True)
class Clause:
    """One named ACSL clause: `<kind> <name>: <term>;`."""

    kind: str  # requires, ensures, assumes
    name: str
    term: str


@dataclass(frozen=True)
class Behavior:
    name: str
    assumes: str
    ensures: tuple[Clause, ...]


@dataclass(frozen=True)
class Contract:
    """An ACSL function contract. `assigns` lists the locations the function may
    write (empty: `\\nothing`)."""

    requires: tuple[Clause, ...] = ()
    assigns: tuple[str, ...] = ()
    ensures: tuple[Clause, ...] = ()
    behaviors: tuple[Behavior, ...] = ()
    #: the behaviors cover every case and never overlap (`complete`/`disjoint behaviors`)
    partition: bool = False

    def clauses(self) -> list[tuple[str, Clause]]:
        """Every named clause with the behavior it belongs to ("" for the default)."""
        out = [("", c) for c in (*self.requires, *self.ensures)]
        for b in self.behaviors:
            out += [(b.name, c) for c in b.ensures]
        return out


@dataclass(frozen=True)
class Predicate:
    """`predicate name(params) = body;` with a one-line description."""

    name: str
    params: tuple[tuple[str, str], ...]  # (ACSL type, name)
    body: tuple[str, ...]  # conjuncts or disjuncts, joined by `joiner`
    joiner: str
    doc: str


def _clause(c: Clause, pad: str) -> str:
    return f"{pad}{c.kind} {c.name}: {c.term};"


def contract(c: Contract) -> str:
    """The contract as an ACSL comment, one clause a line."""
    pad = "    "
    lines = [_clause(r, pad) for r in c.requires]
    lines.append(f"{pad}assigns {', '.join(c.assigns) if c.assigns else chr(92) + 'nothing'};")
    lines += [_clause(e, pad) for e in c.ensures]
    for b in c.behaviors:
        lines.append(f"{pad}behavior {b.name}:")
        lines.append(f"{pad}  assumes {b.assumes};")
        lines += [_clause(e, pad + "  ") for e in b.ensures]
    if c.partition:
        lines += [f"{pad}complete behaviors;", f"{pad}disjoint behaviors;"]
    lines[0] = "/*@" + lines[0][3:]
    return "\n".join([*lines, "*/"])


def predicate(p: Predicate) -> str:
    params = ", ".join(f"{t} {n}" for t, n in p.params)
    body = f"\n    {p.joiner} ".join(p.body)
    return f"/* {p.doc} */\n/*@ predicate {p.name}({params}) =\n       {body};\n*/"


# ------------------------------------------------------------------ IR terms


def term(e: Expr, names: dict[str, str], macros: frozenset[str] = frozenset()) -> str:
    """e as an ACSL term over mathematical integers. `names` maps the IR's variables
    (and `base.field`) to ACSL terms; constants print as their macro when it is in
    `macros` (visible where the term is printed), else as their value. Only operations
    whose integer meaning is the C one on the proven (non-negative) ranges are
    supported; anything else is a generator error."""
    if isinstance(e, IConst):
        return e.name if e.name in macros else str(e.value)
    if isinstance(e, IVar):
        return names[e.name]
    if isinstance(e, IField):
        return names[f"{e.base}.{e.field}"]
    if isinstance(e, ICast):
        return term(e.a, names, macros)  # the value fits (the IR proof's obligation)
    if isinstance(e, IBin) and e.op in "+-*":
        return f"({term(e.a, names, macros)} {e.op} {term(e.b, names, macros)})"
    if isinstance(e, IShr) and isinstance(e.shift, int) and e.rounding == "floor":
        return f"({term(e.a, names, macros)} / {1 << e.shift})"
    if isinstance(e, IShr) and isinstance(e.shift, int) and e.rounding == "nearest":
        half = 1 << (e.shift - 1) if e.shift > 0 else 0  # round half up (a >= 0)
        return f"(({term(e.a, names, macros)} + {half}) / {1 << e.shift})"
    if isinstance(e, IShl) and isinstance(e.shift, int):
        return f"({term(e.a, names, macros)} * {1 << e.shift})"
    if isinstance(e, IDiv):
        a, b = term(e.a, names, macros), term(e.b, names, macros)
        if e.rounding == "trunc":
            return f"({a} / {b})"
        if e.rounding == "ceil":
            return f"(({a} + {b} - 1) / {b})"
        return f"(({a} + {b} / 2) / {b})"
    if isinstance(e, ILongDiv):
        d = term(e.divisor, names, macros)
        return f"((2 * {e.numerator.value} + {d}) / (2 * {d}))"  # round half up, N, d > 0
    if isinstance(e, IMod):
        return f"({term(e.a, names, macros)} % {term(e.b, names, macros)})"
    if isinstance(e, ICmp):
        return f"({term(e.a, names, macros)} {e.op} {term(e.b, names, macros)})"
    if isinstance(e, IAnd | IOr):
        op = "&&" if isinstance(e, IAnd) else "||"
        return f"({term(e.a, names, macros)} {op} {term(e.b, names, macros)})"
    if isinstance(e, INot):
        return f"!{term(e.a, names, macros)}"
    if isinstance(e, ISelect):
        cond, a, b = (term(x, names, macros) for x in (e.cond, e.a, e.b))
        return f"({cond} ? {a} : {b})"
    raise TypeError(f"no ACSL term for {type(e).__name__}")


# ------------------------------------------------------------------ proof hints


def _assigned(stmts: tuple[Stmt, ...]) -> list[str]:
    out: list[str] = []
    for s in all_statements(stmts):
        if isinstance(s, SAssign | SOrAssign) and s.name not in out:
            out.append(s.name)
    return out


def loop_annotation(s: SFor) -> str:
    """The loop's declared invariants (the IR proof checks them by induction), each named
    `<variable>_kept` so that one EVA establishes can be left out of WP's goals, what it
    writes, and why it ends."""
    parts = [f"loop invariant {s.counter}_kept: 0 <= {s.counter} <= {s.count};"]
    parts += [
        f"loop invariant {name}_kept: {lo} <= {name} <= {hi};" for name, lo, hi in s.invariants
    ]
    parts.append(f"loop assigns {', '.join([*_assigned(s.body), s.counter])};")
    parts.append(f"loop variant {s.count} - {s.counter};")
    return "/*@ " + " ".join(parts) + " */"


def _stepped_index(s: Stmt) -> str | None:
    """The local indexing a table step in s (the IR proof bounds such a step row by row)."""
    if not isinstance(s, SLet):
        return None
    for top in statement_exprs((s,)):
        for e in expressions(top):
            if isinstance(e, IStep) and isinstance(e.index, IVar):
                return e.index.name
    return None


def block_hints(stmts: tuple[Stmt, ...]) -> list[tuple[list[str], list[str]]]:
    """Per statement of a block, the ACSL hints printed before and after it."""
    hints: list[tuple[list[str], list[str]]] = [([], []) for _ in stmts]
    stepped = [_stepped_index(s) for s in stmts]
    for k, s in enumerate(stmts):
        before, after = hints[k]
        if isinstance(s, SFor):
            before.append(loop_annotation(s))
        if isinstance(s, SLet) and s.split:
            after.append(f"/*@ split {s.name}; */ {ANCHOR}")
        index = stepped[k]
        if index is not None:
            if k == 0 or stepped[k - 1] != index:
                before.append(f"/*@ split {index}; */ {ANCHOR}")
            if k + 1 == len(stmts) or stepped[k + 1] != index:
                after.append(f"/*@ merge {index}; */ {ANCHOR}")
    return hints

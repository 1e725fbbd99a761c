"""Traversals shared by the printers and the analyses."""

from __future__ import annotations

from collections.abc import Iterator

from codegen.ir.nodes import (
    Expr,
    Function,
    IAnd,
    IBin,
    IBitLength,
    ICall,
    ICast,
    ICmp,
    IConst,
    IDiv,
    ILongDiv,
    ILookup,
    IMod,
    INot,
    IOr,
    ISelect,
    IShl,
    IShr,
    IStep,
    IVar,
    Module,
    SAssign,
    SFor,
    SIf,
    SLet,
    SLetStruct,
    SOrAssign,
    SReturn,
    SStore,
    SStruct,
    Stmt,
    SVar,
    Table,
)
from codegen.ir.types import U32


def children(e: Expr) -> tuple[Expr, ...]:
    if isinstance(e, IBin | IDiv | IMod | ICmp | IAnd | IOr):
        return (e.a, e.b)
    if isinstance(e, IShl) and not isinstance(e.shift, int):
        return (e.a, e.shift)
    if isinstance(e, IShr) and not isinstance(e.shift, int):
        return (e.a, e.shift)
    if isinstance(e, IShr | IShl | ICast | INot | IBitLength):
        return (e.a,)
    if isinstance(e, ISelect):
        return (e.cond, e.a, e.b)
    if isinstance(e, ILookup | IStep):
        return (e.index,)
    if isinstance(e, ILongDiv):
        return (e.divisor,)  # the numerator is printed as its _HIGH/_LOW/_SHIFT parts
    if isinstance(e, ICall):
        return e.args
    return ()


def expressions(e: Expr) -> Iterator[Expr]:
    """e and every sub-expression, depth first."""
    yield e
    for c in children(e):
        yield from expressions(c)


def statement_exprs(stmts: tuple[Stmt, ...]) -> Iterator[Expr]:
    """The top-level expressions of a statement list, nested blocks included."""
    for s in stmts:
        if isinstance(s, SLet | SAssign | SOrAssign | SStore):
            yield s.expr
        elif isinstance(s, SVar):
            yield s.init
        elif isinstance(s, SStruct):
            for _, value in s.values:
                yield value
        elif isinstance(s, SLetStruct):
            yield s.call
        elif isinstance(s, SReturn):
            if s.value is not None:
                yield s.value
        elif isinstance(s, SIf):
            yield s.cond
            yield from statement_exprs(s.then)
            yield from statement_exprs(s.orelse)
        elif isinstance(s, SFor):
            if s.start is not None:
                yield IVar(U32, s.start)
            yield from statement_exprs(s.body)


def all_exprs(stmts: tuple[Stmt, ...]) -> Iterator[Expr]:
    for top in statement_exprs(stmts):
        yield from expressions(top)


def called_functions(module: Module) -> list[Function]:
    """Every function of the module and every function they call, callees first."""
    order: list[Function] = []
    seen: set[int] = set()

    from codegen.ir.longdiv import DIVIDE_LONG

    def visit(fn: Function) -> None:
        if id(fn) in seen:
            return
        seen.add(id(fn))
        for e in all_exprs(fn.body):
            if isinstance(e, ICall):
                visit(e.function)
            elif isinstance(e, ILongDiv):
                visit(DIVIDE_LONG)
        order.append(fn)

    for fn in module.functions:
        visit(fn)
    return order


def long_division_parts(c: IConst) -> tuple[IConst, IConst, IConst]:
    """N = high 2^shift + low with high < 2^32: the named constants the helper takes."""
    from codegen.ir.types import U32

    shift = max(0, c.value.bit_length() - 32)
    base = c.name or "N"
    return (
        IConst(U32, c.value >> shift, f"{base}_HIGH", doc=f"{base} >> {shift}, {c.doc}".strip()),
        IConst(U32, c.value & ((1 << shift) - 1), f"{base}_LOW", doc=f"{base} mod 2^{shift}"),
        IConst(U32, shift, f"{base}_SHIFT"),
    )


def named_constants(module: Module) -> list[IConst]:
    """Named constants in first-use order (a name used twice must mean one value)."""
    out: dict[str, IConst] = {}

    def keep(c: IConst) -> None:
        if c.name is None:
            return
        known = out.get(c.name)
        if known is not None and (known.value != c.value or known.ctype != c.ctype):
            raise ValueError(f"constant {c.name} defined as {known.value} and {c.value}")
        out.setdefault(c.name, c)

    for fn in called_functions(module):
        for e in all_exprs(fn.body):
            if isinstance(e, ILongDiv):
                for part in long_division_parts(e.numerator):
                    keep(part)
            elif isinstance(e, IConst):
                keep(e)
    for c in module.extra_constants:
        keep(c)
    return list(out.values())


def tables(module: Module) -> list[Table]:
    out: dict[str, Table] = {t.name: t for t in module.tables}
    for fn in called_functions(module):
        for e in all_exprs(fn.body):
            if isinstance(e, ILookup | IStep):
                out.setdefault(e.table.name, e.table)
    return list(out.values())


def referenced_names(fn: Function) -> set[str]:
    """Names of parameters and locals the body reads (struct bases included)."""
    from codegen.ir.nodes import IAddr, IField, IVar

    out: set[str] = set()
    for e in all_exprs(fn.body):
        if isinstance(e, IVar | IAddr):
            out.add(e.name)
        elif isinstance(e, IField):
            out.add(e.base)
    for s in all_statements(fn.body):
        if isinstance(s, SStore):
            out.add(s.base)
    return out


def all_statements(stmts: tuple[Stmt, ...]) -> list[Stmt]:
    out: list[Stmt] = []
    for s in stmts:
        out.append(s)
        if isinstance(s, SIf):
            out += all_statements(s.then) + all_statements(s.orelse)
        elif isinstance(s, SFor):
            out += all_statements(s.body)
    return out

"""The overflow proof: interval analysis of the IR that is printed.

Every node's value is bounded over every input its function can receive: a public
function's scalar parameters range over their whole C type (a caller may pass any
value), a struct parameter over what the function that makes it can return (stated as
the function's precondition), a helper's parameters over each call site's arguments.
Each node must fit its C type (no wrap-around, no undefined behaviour), and the
operations whose C and Python meanings could differ are ruled out: a shift of a
negative value, a division by an interval that contains zero, a table index out of
range, CLZ of zero, an operand that a cast or an implicit conversion would change.

The analysis is path-sensitive where it matters for these cores: a branch condition
comparing a variable with a value narrows that variable inside the branch, and a
`return` ends its path. A loop's carried variables must keep the interval they declare
(checked after the body: an induction invariant). Intervals are exact integers; they
are sound and may be loose (non-relational).
"""

from __future__ import annotations

from dataclasses import dataclass, field

from codegen.ir.c_printer import printer_for
from codegen.ir.longdiv import DIVIDE_LONG
from codegen.ir.nodes import (
    Expr,
    Function,
    IAddr,
    IAnd,
    IBin,
    IBitLength,
    ICall,
    ICast,
    ICmp,
    IConst,
    IDiv,
    IField,
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
    SAssign,
    SComment,
    SFor,
    SIf,
    SLet,
    SLetStruct,
    SOrAssign,
    SReturn,
    SStore,
    SStruct,
    Stmt,
    StructType,
    SVar,
)
from codegen.ir.types import BOOL, CType
from codegen.ir.walk import long_division_parts


class ProofError(ValueError):
    """An operation of the IR can overflow or is undefined for some input."""


@dataclass(frozen=True)
class Interval:
    lo: int
    hi: int

    def __post_init__(self) -> None:
        if self.lo > self.hi:
            raise ValueError(f"empty interval [{self.lo}, {self.hi}]")

    def union(self, other: Interval) -> Interval:
        return Interval(min(self.lo, other.lo), max(self.hi, other.hi))

    def __str__(self) -> str:
        return f"[{self.lo}, {self.hi}]"


def full(ctype: CType) -> Interval:
    return Interval(ctype.low, ctype.high)


@dataclass(frozen=True)
class ProvenRange:
    """A named intermediate, the interval the proof found, and the type it fits."""

    function: str
    name: str
    c_type: str
    low: int
    high: int
    expression: str

    @property
    def headroom_bits(self) -> float:
        from math import log2

        from codegen.ir.types import BY_NAME

        t = BY_NAME[self.c_type]
        used = max(
            self.high / t.high if self.high > 0 else 0.0, self.low / t.low if self.low < 0 else 0.0
        )
        return -log2(used) if used > 0 else float("inf")


Env = dict[str, Interval]


def _c_div(n: int, d: int) -> int:
    q = abs(n) // abs(d)
    return q if (n >= 0) == (d > 0) else -q


@dataclass
class Analysis:
    """One function analysed at one calling context."""

    function: Function
    returns: Interval | None = None
    struct_returns: dict[str, Interval] = field(default_factory=dict)


class Prover:
    """Interval analysis of a module's functions; `ranges` collects every SLet/SVar/
    SStruct field it bounded (merged over calling contexts)."""

    def __init__(self) -> None:
        self._ranges: dict[tuple[str, str], ProvenRange] = {}
        self._stack: list[Function] = []

    @property
    def ranges(self) -> tuple[ProvenRange, ...]:
        return tuple(self._ranges.values())

    # ------------------------------------------------------------ reporting

    def _where(self) -> str:
        return self._stack[-1].c_name if self._stack else "?"

    def _fail(self, e: Expr | None, problem: str) -> ProofError:
        fn = self._stack[-1] if self._stack else None
        pointers = frozenset(p.name for p in fn.params if p.is_pointer) if fn else frozenset()
        text = printer_for(pointers).expr(e) if e is not None else ""
        return ProofError(
            f"{self._where()}: {text}: {problem}" if text else f"{self._where()}: {problem}"
        )

    def _fits(self, e: Expr, value: Interval, ctype: CType, what: str = "") -> Interval:
        if ctype != BOOL and not ctype.fits(value.lo, value.hi):
            raise self._fail(
                e, f"{what or 'value'} spans {value}, beyond {ctype.name} {full(ctype)}"
            )
        return value

    def _record(self, name: str, ctype: CType, value: Interval, e: Expr) -> None:
        fn = self._stack[-1]
        key = (fn.c_name, name)
        known = self._ranges.get(key)
        if known is not None:
            value = value.union(Interval(known.low, known.high))
        pointers = frozenset(p.name for p in fn.params if p.is_pointer)
        self._ranges[key] = ProvenRange(
            fn.c_name, name, ctype.name, value.lo, value.hi, printer_for(pointers).expr(e)
        )

    # ------------------------------------------------------------ expressions

    def ev(self, e: Expr, env: Env) -> Interval:
        narrowed = env.get(f"#{id(e)}")
        if narrowed is not None:
            return narrowed
        method = getattr(self, f"_ev_{type(e).__name__}")
        return method(e, env)  # type: ignore[no-any-return]

    def _operand(self, child: Expr, node: Expr, env: Env) -> Interval:
        """A child's interval, which C converts to the node's type: it must fit there."""
        value = self.ev(child, env)
        if child.ctype != node.ctype and node.ctype != BOOL:
            self._fits(child, value, node.ctype, f"operand converted to {node.ctype.name}")
        return value

    def _ev_IConst(self, e: IConst, env: Env) -> Interval:
        return self._fits(e, Interval(e.value, e.value), e.ctype)

    def _ev_IVar(self, e: IVar, env: Env) -> Interval:
        if e.name not in env:
            raise self._fail(e, "read before it has a value")
        return env[e.name]

    def _ev_IField(self, e: IField, env: Env) -> Interval:
        key = f"{e.base}.{e.field}"
        if key not in env:
            raise self._fail(e, "field read before it has a value")
        return env[key]

    def _ev_IBin(self, e: IBin, env: Env) -> Interval:
        if e.ctype.bits < 32:
            raise self._fail(
                e, f"arithmetic in {e.ctype.name} (C promotes it): use a 32/64-bit type"
            )
        a, b = self._operand(e.a, e, env), self._operand(e.b, e, env)
        if e.op == "+":
            r = Interval(a.lo + b.lo, a.hi + b.hi)
        elif e.op == "-":
            r = Interval(a.lo - b.hi, a.hi - b.lo)
        elif e.op == "*":
            corners = (a.lo * b.lo, a.lo * b.hi, a.hi * b.lo, a.hi * b.hi)
            r = Interval(min(corners), max(corners))
        else:
            if a.lo < 0 or b.lo < 0:
                raise self._fail(e, "bitwise operation on a possibly negative value")
            if e.op == "&":
                r = Interval(0, min(a.hi, b.hi))
            else:
                r = Interval(max(a.lo, b.lo), (1 << max(a.hi, b.hi).bit_length()) - 1)
        return self._fits(e, r, e.ctype)

    def _ev_IShr(self, e: IShr, env: Env) -> Interval:
        a = self._operand(e.a, e, env)
        if a.lo < 0:
            raise self._fail(e, f"right shift of a possibly negative value {a}")
        if not isinstance(e.shift, int):
            s = self.ev(e.shift, env)
            if s.lo < 0 or s.hi >= e.ctype.bits or e.rounding != "floor":
                raise self._fail(e, f"shift count {s} outside [0, {e.ctype.bits - 1}]")
            return Interval(a.lo >> s.hi, a.hi >> s.lo)
        if e.shift >= e.ctype.bits:
            raise self._fail(e, f"shift by {e.shift} in {e.ctype.name}")
        if e.rounding == "nearest":
            half = 1 << (e.shift - 1)
            self._fits(
                e, Interval(a.lo + half, a.hi + half), e.ctype, "value plus the rounding half"
            )
            return Interval((a.lo + half) >> e.shift, (a.hi + half) >> e.shift)
        return Interval(a.lo >> e.shift, a.hi >> e.shift)

    def _ev_IShl(self, e: IShl, env: Env) -> Interval:
        a = self._operand(e.a, e, env)
        s = Interval(e.shift, e.shift) if isinstance(e.shift, int) else self.ev(e.shift, env)
        if a.lo < 0:
            raise self._fail(e, f"left shift of a possibly negative value {a}")
        if s.lo < 0 or s.hi >= e.ctype.bits:
            raise self._fail(e, f"shift count {s} outside [0, {e.ctype.bits - 1}]")
        return self._fits(e, Interval(a.lo << s.lo, a.hi << s.hi), e.ctype)

    def _ev_IDiv(self, e: IDiv, env: Env) -> Interval:
        a, b = self._operand(e.a, e, env), self._operand(e.b, e, env)
        if b.lo <= 0:
            raise self._fail(e, f"divisor spans {b}: it must be positive")
        if e.rounding == "nearest":
            n = Interval(a.lo + (b.lo >> 1), a.hi + (b.hi >> 1))
        elif e.rounding == "ceil":
            if a.lo < 0:
                raise self._fail(e, "rounding up a possibly negative quotient")
            n = Interval(a.lo + b.lo - 1, a.hi + b.hi - 1)
        else:
            n = a
        self._fits(e, n, e.ctype, "rounded numerator")
        lo = _c_div(n.lo, b.lo if n.lo < 0 else b.hi)
        hi = _c_div(n.hi, b.lo if n.hi >= 0 else b.hi)
        return self._fits(e, Interval(lo, hi), e.ctype)

    def _ev_IMod(self, e: IMod, env: Env) -> Interval:
        a, b = self._operand(e.a, e, env), self._operand(e.b, e, env)
        if a.lo < 0 or b.lo <= 0:
            raise self._fail(e, f"remainder of {a} by {b}: both must be non-negative, divisor > 0")
        return Interval(0, min(a.hi, b.hi - 1))

    def _ev_ILongDiv(self, e: ILongDiv, env: Env) -> Interval:
        b = self._operand(e.divisor, e, env)
        if b.lo <= 0:
            raise self._fail(e, f"divisor spans {b}: it must be positive")
        high, low, shift = long_division_parts(e.numerator)
        self.call(
            DIVIDE_LONG,
            {
                "high": Interval(high.value, high.value),
                "low": Interval(low.value, low.value),
                "shift": Interval(shift.value, shift.value),
                "divisor": b,
            },
        )
        n = e.numerator.value
        return self._fits(
            e, Interval((2 * n + b.hi) // (2 * b.hi), (2 * n + b.lo) // (2 * b.lo)), e.ctype
        )

    def _decided(self, e: ICmp, a: Interval, b: Interval) -> Interval:
        op = e.op
        always = {
            "<": a.hi < b.lo,
            "<=": a.hi <= b.lo,
            ">": a.lo > b.hi,
            ">=": a.lo >= b.hi,
            "==": a.lo == a.hi == b.lo == b.hi,
            "!=": a.hi < b.lo or b.hi < a.lo,
        }[op]
        never = {
            "<": a.lo >= b.hi,
            "<=": a.lo > b.hi,
            ">": a.hi <= b.lo,
            ">=": a.hi < b.lo,
            "==": a.hi < b.lo or b.hi < a.lo,
            "!=": a.lo == a.hi == b.lo == b.hi,
        }[op]
        return Interval(1, 1) if always else Interval(0, 0) if never else Interval(0, 1)

    def _ev_ICmp(self, e: ICmp, env: Env) -> Interval:
        if e.a.ctype != e.b.ctype:
            raise self._fail(e, f"comparison of {e.a.ctype.name} with {e.b.ctype.name}")
        return self._decided(e, self.ev(e.a, env), self.ev(e.b, env))

    def _ev_IAnd(self, e: IAnd, env: Env) -> Interval:
        a = self.ev(e.a, env)
        if a.hi == 0:
            return a
        env_b = refine(self, env, e.a, True)
        b = self.ev(e.b, env_b) if env_b is not None else Interval(0, 0)
        return Interval(min(a.lo, b.lo), min(a.hi, b.hi))

    def _ev_IOr(self, e: IOr, env: Env) -> Interval:
        a = self.ev(e.a, env)
        if a.lo == 1:
            return a
        env_b = refine(self, env, e.a, False)
        b = self.ev(e.b, env_b) if env_b is not None else Interval(1, 1)
        return Interval(max(a.lo, b.lo), max(a.hi, b.hi))

    def _ev_INot(self, e: INot, env: Env) -> Interval:
        a = self.ev(e.a, env)
        return Interval(1 - a.hi, 1 - a.lo)

    def _ev_ISelect(self, e: ISelect, env: Env) -> Interval:
        cond = self.ev(e.cond, env)
        out: Interval | None = None
        for truth, branch in ((True, e.a), (False, e.b)):
            if (truth and cond.hi == 0) or (not truth and cond.lo == 1):
                continue
            narrowed = refine(self, env, e.cond, truth)
            if narrowed is None:
                continue
            value = self._operand(branch, e, narrowed)
            out = value if out is None else out.union(value)
        if out is None:
            raise self._fail(e, "neither branch is reachable")
        return self._fits(e, out, e.ctype)

    def _ev_ICast(self, e: ICast, env: Env) -> Interval:
        a = self.ev(e.a, env)
        return self._fits(e, a, e.ctype, f"value cast to {e.ctype.name}")

    def _rows(self, e: ILookup | IStep, env: Env, last: int) -> range:
        index = self.ev(e.index, env)
        if index.lo < 0 or index.hi > last:
            raise self._fail(e, f"table index spans {index}, beyond [0, {last}]")
        return range(index.lo, index.hi + 1)

    def _ev_ILookup(self, e: ILookup, env: Env) -> Interval:
        rows = self._rows(e, env, len(e.table.rows) - 1)
        values = [e.table.rows[k][e.column] for k in rows]
        return self._fits(e, Interval(min(values), max(values)), e.ctype)

    def _ev_IStep(self, e: IStep, env: Env) -> Interval:
        rows = self._rows(e, env, len(e.table.rows) - 2)
        steps = [e.table.rows[k + 1][e.column] - e.table.rows[k][e.column] for k in rows]
        return self._fits(e, Interval(min(steps), max(steps)), e.ctype, "table step")

    def _ev_IBitLength(self, e: IBitLength, env: Env) -> Interval:
        a = self.ev(e.a, env)
        if a.lo <= 0:
            raise self._fail(e, f"CLZ of a value spanning {a}: it must be positive")
        return Interval(a.lo.bit_length(), a.hi.bit_length())

    def _ev_IAddr(self, e: IAddr, env: Env) -> Interval:
        return Interval(0, 0)

    def _call_struct(self, e: ICall, env: Env) -> dict[str, Interval]:
        result = self.call(e.function, self._bind(e, env))
        if not isinstance(e.function.returns, StructType):
            raise self._fail(e, "the function does not return a struct")
        return result.struct_returns

    def _ev_ICall(self, e: ICall, env: Env) -> Interval:
        result = self.call(e.function, self._bind(e, env))
        if result.returns is None:
            raise self._fail(e, "the function returns no value")
        return result.returns

    def _bind(self, e: ICall, env: Env) -> Env:
        bound: Env = {}
        for param, arg in zip(e.function.params, e.args, strict=True):
            if param.struct is not None:
                if not isinstance(arg, IAddr):
                    raise self._fail(e, f"argument {param.name} must be &struct")
                for f in param.struct.fields:
                    bound[f"{param.name}.{f.name}"] = env[f"{arg.name}.{f.name}"]
            else:
                assert param.ctype is not None
                value = self.ev(arg, env)
                bound[param.name] = self._fits(arg, value, param.ctype, f"argument {param.name}")
        return bound

    # ------------------------------------------------------------ statements

    def call(self, fn: Function, params: Env) -> Analysis:
        self._stack.append(fn)
        try:
            result = Analysis(fn)
            env = dict(params)
            self.block(fn.body, env, result)
            return result
        finally:
            self._stack.pop()

    def block(self, stmts: tuple[Stmt, ...], env: Env, result: Analysis) -> bool:
        """Run the statements on env (updated in place); True if every path returned."""
        for k, s in enumerate(stmts):
            if isinstance(s, SLet) and s.split:
                return self._split(s, stmts[k + 1 :], env, result)
            if self.statement(s, env, result):
                return True
        return False

    def _split(self, s: SLet, rest: tuple[Stmt, ...], env: Env, result: Analysis) -> bool:
        """The rest of the block once per value of s (at most 64 values)."""
        value = self.ev(s.expr, env)
        self._record(s.name, s.expr.ctype, value, s.expr)
        if value.hi - value.lo >= 64:
            raise self._fail(s.expr, f"case split over {value}: too many cases")
        outcomes: list[Env] = []
        for v in range(value.lo, value.hi + 1):
            case = dict(env)
            case[s.name] = Interval(v, v)
            if not self.block(rest, case, result):
                outcomes.append(case)
        if not outcomes:
            return True
        env.clear()
        env.update(_join(outcomes))
        return False

    def statement(self, s: Stmt, env: Env, result: Analysis) -> bool:
        if isinstance(s, SComment):
            return False
        if isinstance(s, SLet):
            env[s.name] = self.ev(s.expr, env)
            self._record(s.name, s.expr.ctype, env[s.name], s.expr)
            return False
        if isinstance(s, SVar):
            value = self.ev(s.init, env)
            if s.init.ctype != s.ctype:
                self._fits(s.init, value, s.ctype, f"initial value of {s.name}")
            env[s.name] = value
            env[f"{s.name}:type"] = Interval(0, 0)  # marks a mutable local
            self._types[(self._where(), s.name)] = s.ctype
            self._record(s.name, s.ctype, value, s.init)
            return False
        if isinstance(s, SAssign | SOrAssign):
            ctype = self._types.get((self._where(), s.name))
            if ctype is None:
                raise self._fail(s.expr, f"assignment to {s.name}, which is not a mutable local")
            value = self.ev(s.expr, env)
            if isinstance(s, SOrAssign):
                old = env[s.name]
                if old.lo < 0 or value.lo < 0:
                    raise self._fail(s.expr, "bitwise or of a possibly negative value")
                value = Interval(
                    max(old.lo, value.lo), (1 << max(old.hi, value.hi).bit_length()) - 1
                )
            env[s.name] = self._fits(s.expr, value, ctype, f"value assigned to {s.name}")
            self._record(s.name, ctype, env[s.name], s.expr)
            return False
        if isinstance(s, SStruct):
            for name, value_expr in s.values:
                f = s.struct.field(name)
                value = self.ev(value_expr, env)
                self._fits(value_expr, value, f.ctype, f"{s.name}.{name}")
                env[f"{s.name}.{name}"] = value
                self._record(f"{s.name}.{name}", f.ctype, value, value_expr)
            return False
        if isinstance(s, SLetStruct):
            returned = self._call_struct(s.call, env)
            for name, value in returned.items():
                env[f"{s.name}.{name}"] = value
            return False
        if isinstance(s, SStore):
            struct = self._struct_of(s.base, env)
            f = struct.field(s.field)
            value = self.ev(s.expr, env)
            self._fits(s.expr, value, f.ctype, f"{s.base}.{s.field}")
            env[f"{s.base}.{s.field}"] = value
            self._record(f"{s.base}.{s.field}", f.ctype, value, s.expr)
            return False
        if isinstance(s, SReturn):
            self._return(s, env, result)
            return True
        if isinstance(s, SIf):
            return self._if(s, env, result)
        if isinstance(s, SFor):
            return self._for(s, env, result)
        raise TypeError(type(s).__name__)

    _types: dict[tuple[str, str], CType]

    def _struct_of(self, base: str, env: Env) -> StructType:
        fn = self._stack[-1]
        for p in fn.params:
            if p.name == base and p.struct is not None:
                return p.struct
        struct = self._struct_locals.get((fn.c_name, base))
        if struct is None:
            raise self._fail(None, f"{base} is not a struct")
        return struct

    _struct_locals: dict[tuple[str, str], StructType]

    def _return(self, s: SReturn, env: Env, result: Analysis) -> None:
        fn = result.function
        if s.value is None:
            return
        if isinstance(fn.returns, StructType):
            if not isinstance(s.value, IVar):
                raise self._fail(s.value, "a struct is returned by name")
            for f in fn.returns.fields:
                value = env[f"{s.value.name}.{f.name}"]
                known = result.struct_returns.get(f.name)
                result.struct_returns[f.name] = value if known is None else known.union(value)
            return
        assert isinstance(fn.returns, CType)
        value = self.ev(s.value, env)
        self._fits(s.value, value, fn.returns, "returned value")
        result.returns = value if result.returns is None else result.returns.union(value)

    def _if(self, s: SIf, env: Env, result: Analysis) -> bool:
        cond = self.ev(s.cond, env)
        outcomes: list[Env] = []
        for truth, branch in ((True, s.then), (False, s.orelse)):
            if (truth and cond.hi == 0) or (not truth and cond.lo == 1):
                continue
            narrowed = refine(self, env, s.cond, truth)
            if narrowed is None:
                continue
            if not self.block(branch, narrowed, result):
                outcomes.append(narrowed)
        if not outcomes:
            return True
        env.clear()
        env.update(_join(outcomes))
        return False

    def _for(self, s: SFor, env: Env, result: Analysis) -> bool:
        inner = dict(env)
        first = 0
        if s.start is not None:
            start = env.get(s.start)
            if start is None or start.lo < 0 or start.hi > s.count:
                raise self._fail(None, f"loop start {s.start} is {start}, outside [0, {s.count}]")
            if start.lo == s.count:
                return False  # the body never runs
            first = start.lo
        inner[s.counter] = Interval(first, s.count - 1)
        declared = {name: Interval(lo, hi) for name, lo, hi in s.invariants}
        for name, keep in declared.items():
            if name not in env or not (keep.lo <= env[name].lo and env[name].hi <= keep.hi):
                raise self._fail(
                    None,
                    f"loop variable {name} enters as {env.get(name)}, outside its invariant {keep}",
                )
            inner[name] = keep
        if self.block(s.body, inner, result):
            raise self._fail(None, "a loop body that always returns")
        for name, keep in declared.items():
            after = inner[name]
            if not (keep.lo <= after.lo and after.hi <= keep.hi):
                raise self._fail(
                    None,
                    f"loop variable {name} leaves the body as {after}, outside its invariant {keep}",
                )
        for stmt in _statements(s.body):
            target = stmt.name if isinstance(stmt, SAssign | SOrAssign) else None
            if target is not None and target in env and target not in declared:
                raise self._fail(None, f"{target} changes in the loop without a declared invariant")
        env.update(declared)
        return False


def _join(envs: list[Env]) -> Env:
    joined = dict(envs[0])
    for other in envs[1:]:
        joined = {k: v.union(other[k]) for k, v in joined.items() if k in other}
    return joined


def refine(prover: Prover, env: Env, cond: Expr, truth: bool) -> Env | None:
    """env narrowed by cond == truth, or None when that is impossible."""
    if isinstance(cond, INot):
        return refine(prover, env, cond.a, not truth)
    if (isinstance(cond, IAnd) and truth) or (isinstance(cond, IOr) and not truth):
        first = refine(prover, env, cond.a, truth)
        return refine(prover, first, cond.b, truth) if first is not None else None
    if not isinstance(cond, ICmp):
        return dict(env)
    op = cond.op
    if not truth:
        op = {"<": ">=", "<=": ">", ">": "<=", ">=": "<", "==": "!=", "!=": "=="}[op]
    out = dict(env)
    for left, right, relation in ((cond.a, cond.b, op), (cond.b, cond.a, _mirror(op))):
        key = _key(left)
        if key not in out:
            if not key.startswith("#"):
                continue
            out[key] = prover.ev(left, out)
        a, b = out[key], prover.ev(right, out)
        lo, hi = a.lo, a.hi
        if relation == "<":
            hi = min(hi, b.hi - 1)
        elif relation == "<=":
            hi = min(hi, b.hi)
        elif relation == ">":
            lo = max(lo, b.lo + 1)
        elif relation == ">=":
            lo = max(lo, b.lo)
        elif relation == "==":
            lo, hi = max(lo, b.lo), min(hi, b.hi)
        elif relation == "!=" and b.lo == b.hi:
            lo, hi = (lo + 1 if lo == b.lo else lo), (hi - 1 if hi == b.hi else hi)
        if lo > hi:
            return None
        out[key] = Interval(lo, hi)
    return out


def _mirror(op: str) -> str:
    return {"<": ">", "<=": ">=", ">": "<", ">=": "<=", "==": "==", "!=": "!="}[op]


def _key(e: Expr) -> str:
    """The env key a comparison narrows: a variable, a field, or (for any other
    expression) the node itself, so that a select's branch that reuses the compared
    node sees the narrowed interval."""
    if isinstance(e, IVar):
        return e.name
    if isinstance(e, IField):
        return f"{e.base}.{e.field}"
    return f"#{id(e)}"


def prove_function(prover: Prover, fn: Function, params: Env | None = None) -> Analysis:
    """Analyse fn with every scalar parameter over its whole type, struct parameters
    from `params` (their producer's postcondition)."""
    bound: Env = {}
    for p in fn.params:
        if p.struct is None:
            assert p.ctype is not None
            bound[p.name] = full(p.ctype)
    if params:
        bound.update(params)
    return prover.call(fn, bound)


def new_prover(functions: tuple[Function, ...]) -> Prover:
    """A prover that knows each function's struct locals and mutable locals."""
    prover = Prover()
    prover._types = {}
    prover._struct_locals = {}
    seen: set[int] = set()

    def visit(fn: Function) -> None:
        if id(fn) in seen:
            return
        seen.add(id(fn))
        for s in _statements(fn.body):
            if isinstance(s, SStruct):
                prover._struct_locals[(fn.c_name, s.name)] = s.struct
            elif isinstance(s, SLetStruct) and isinstance(s.call.function.returns, StructType):
                prover._struct_locals[(fn.c_name, s.name)] = s.call.function.returns
        from codegen.ir.walk import all_exprs

        for e in all_exprs(fn.body):
            if isinstance(e, ICall):
                visit(e.function)

    for fn in (*functions, DIVIDE_LONG):
        visit(fn)
    return prover


def _statements(stmts: tuple[Stmt, ...]) -> list[Stmt]:
    out: list[Stmt] = []
    for s in stmts:
        out.append(s)
        if isinstance(s, SIf):
            out += _statements(s.then) + _statements(s.orelse)
        elif isinstance(s, SFor):
            out += _statements(s.body)
    return out

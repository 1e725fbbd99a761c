"""Print the IR as bit-exact Python (SymPy's PythonCodePrinter, one `_print_<Node>` each).

Python integers do not overflow, and the proof guarantees that no C node does, so the
same operations give the same integers as long as the three places where C and Python
differ are printed explicitly: C's signed division truncates toward zero (`_c_div`),
casts are identities (the value fits, proven), and comparisons are 0/1.

A struct local that the C builds field by field (and an output pointer) becomes one
Python local per field, `name_field`; a struct passed around whole (a const local or a
struct parameter) is a NamedTuple.
"""

from __future__ import annotations

from sympy.printing.pycode import PythonCodePrinter

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
    Table,
)
from codegen.ir.walk import all_exprs, long_division_parts

# Python precedence, higher binds tighter.
ATOM, POWER, MULT, ADD, SHIFT, BAND, BOR, CMP, NOT, AND, OR, COND = (
    16,
    14,
    12,
    11,
    10,
    9,
    7,
    6,
    5,
    4,
    3,
    2,
)
_BIN = {"+": ADD, "-": ADD, "*": MULT, "&": BAND, "|": BOR}
INDENT = "    "

C_DIV = '''def _c_div(numerator: int, denominator: int) -> int:
    """C's integer division: truncates toward zero."""
    quotient = abs(numerator) // abs(denominator)
    return quotient if (numerator >= 0) == (denominator > 0) else -quotient
'''


def comment_text(text: str) -> str:
    return " ".join(text.split())


class IRPythonPrinter(PythonCodePrinter):  # type: ignore[misc]
    def __init__(self, tuples: frozenset[str] = frozenset()) -> None:
        super().__init__()
        #: names bound to a whole NamedTuple (fields read as name.field)
        self.tuples = set(tuples)

    def expr(self, e: Expr) -> str:
        return self._prec(e)[0]

    def _prec(self, e: Expr) -> tuple[str, int]:
        return self._print(e)  # type: ignore[no-any-return]

    def _op(self, e: Expr, level: int) -> str:
        text, prec = self._prec(e)
        return f"({text})" if prec < level else text

    def _print_IConst(self, e: IConst) -> tuple[str, int]:
        if e.name is not None:
            return e.name, ATOM
        return str(e.value), (ATOM if e.value >= 0 else ADD)

    def _print_IVar(self, e: IVar) -> tuple[str, int]:
        return e.name, ATOM

    def _print_IField(self, e: IField) -> tuple[str, int]:
        if e.base in self.tuples:
            return f"{e.base}.{e.field}", ATOM
        return f"{e.base}_{e.field}", ATOM

    def _print_IBin(self, e: IBin) -> tuple[str, int]:
        level = _BIN[e.op]
        return f"{self._op(e.a, level)} {e.op} {self._op(e.b, level + 1)}", level

    def _print_IShr(self, e: IShr) -> tuple[str, int]:
        if e.rounding == "nearest":
            assert isinstance(e.shift, int)
            return f"({self._op(e.a, ADD)} + {1 << (e.shift - 1)}) >> {e.shift}", SHIFT
        shift = str(e.shift) if isinstance(e.shift, int) else self._op(e.shift, SHIFT + 1)
        return f"{self._op(e.a, SHIFT)} >> {shift}", SHIFT

    def _print_IShl(self, e: IShl) -> tuple[str, int]:
        shift = str(e.shift) if isinstance(e.shift, int) else self._op(e.shift, SHIFT + 1)
        return f"{self._op(e.a, SHIFT)} << {shift}", SHIFT

    def _print_IDiv(self, e: IDiv) -> tuple[str, int]:
        if e.rounding == "trunc":
            numerator = self.expr(e.a)
        elif e.rounding == "nearest":
            numerator = f"{self._op(e.a, ADD)} + ({self._op(e.b, SHIFT)} >> 1)"
        else:
            numerator = f"{self._op(e.a, ADD)} + {self._op(e.b, ADD + 1)} - 1"
        if e.ctype.signed:
            return f"_c_div({numerator}, {self.expr(e.b)})", ATOM
        if e.rounding == "trunc":
            return f"{self._op(e.a, MULT)} // {self._op(e.b, MULT + 1)}", MULT
        return f"({numerator}) // {self._op(e.b, MULT + 1)}", MULT

    def _print_IMod(self, e: IMod) -> tuple[str, int]:
        return f"{self._op(e.a, MULT)} % {self._op(e.b, MULT + 1)}", MULT

    def _print_ILongDiv(self, e: ILongDiv) -> tuple[str, int]:
        high, low, shift = (p.name for p in long_division_parts(e.numerator))
        return f"{DIVIDE_LONG.py_name}({high}, {low}, {shift}, {self.expr(e.divisor)})", ATOM

    def _print_ICmp(self, e: ICmp) -> tuple[str, int]:
        return f"{self._op(e.a, CMP + 1)} {e.op} {self._op(e.b, CMP + 1)}", CMP

    def _print_IAnd(self, e: IAnd) -> tuple[str, int]:
        return f"{self._op(e.a, AND)} and {self._op(e.b, AND + 1)}", AND

    def _print_IOr(self, e: IOr) -> tuple[str, int]:
        return f"{self._op(e.a, OR)} or {self._op(e.b, OR + 1)}", OR

    def _print_INot(self, e: INot) -> tuple[str, int]:
        return f"not {self._op(e.a, NOT)}", NOT

    def _print_ISelect(self, e: ISelect) -> tuple[str, int]:
        return (
            f"{self._op(e.a, COND + 1)} if {self._op(e.cond, COND + 1)} else {self._op(e.b, COND)}",
            COND,
        )

    def _print_ICast(self, e: ICast) -> tuple[str, int]:
        return self._prec(e.a)

    def _row(self, e: ILookup | IStep, offset: str = "") -> str:
        index = self._op(e.index, ADD) + offset
        row = f"{e.table.py_name}[{index}]"
        return f"{row}[{e.column}]" if e.table.columns > 1 else row

    def _print_ILookup(self, e: ILookup) -> tuple[str, int]:
        return self._row(e), ATOM

    def _print_IStep(self, e: IStep) -> tuple[str, int]:
        return f"{self._row(e, ' + 1')} - {self._row(e)}", ADD

    def _print_IBitLength(self, e: IBitLength) -> tuple[str, int]:
        return f"{self._op(e.a, ATOM)}.bit_length()", ATOM

    def _print_IAddr(self, e: IAddr) -> tuple[str, int]:
        return e.name, ATOM

    def _print_ICall(self, e: ICall) -> tuple[str, int]:
        return f"{e.function.py_name}({', '.join(self.expr(a) for a in e.args)})", ATOM

    # ------------------------------------------------------------ statements

    def block(
        self, stmts: tuple[Stmt, ...], depth: int, out_struct: tuple[str, StructType] | None
    ) -> list[str]:
        lines: list[str] = []
        for s in stmts:
            lines.extend(self.statement(s, depth, out_struct))
        return lines or [f"{INDENT * depth}pass"]

    @staticmethod
    def _tail(comment: str) -> str:
        return f"  # {comment_text(comment)}" if comment else ""

    def _rebuild(self, name: str, struct: StructType) -> str:
        if name in self.tuples:
            return name
        return f"{struct.py_name}({', '.join(f'{name}_{f}' for f in struct.names)})"

    def statement(self, s: Stmt, depth: int, out: tuple[str, StructType] | None) -> list[str]:
        pad = INDENT * depth
        if isinstance(s, SComment):
            return [f"{pad}# {comment_text(s.text)}"]
        if isinstance(s, SLet | SAssign):
            return [f"{pad}{s.name} = {self.expr(s.expr)}{self._tail(s.comment)}"]
        if isinstance(s, SVar):
            return [f"{pad}{s.name} = {self.expr(s.init)}{self._tail(s.comment)}"]
        if isinstance(s, SLetStruct):
            self.tuples.add(s.name)
            return [f"{pad}{s.name} = {self.expr(s.call)}{self._tail(s.comment)}"]
        if isinstance(s, SOrAssign):
            return [f"{pad}{s.name} |= {self.expr(s.expr)}{self._tail(s.comment)}"]
        if isinstance(s, SStore):
            return [f"{pad}{s.base}_{s.field} = {self.expr(s.expr)}{self._tail(s.comment)}"]
        if isinstance(s, SStruct):
            if s.const:
                self.tuples.add(s.name)
                args = ", ".join(self.expr(v) for _, v in s.values)
                return [f"{pad}{s.name} = {s.struct.py_name}({args}){self._tail(s.comment)}"]
            return [f"{pad}{s.name}_{n} = {self.expr(v)}" for n, v in s.values]
        if isinstance(s, SReturn):
            if s.value is None:
                return [f"{pad}return {self._rebuild(*out)}" if out else f"{pad}return None"]
            if isinstance(s.value, IVar) and isinstance(self._struct_of(s.value.name), StructType):
                return [f"{pad}return {self._rebuild(s.value.name, self._struct_of(s.value.name))}"]
            return [f"{pad}return {self.expr(s.value)}"]
        if isinstance(s, SIf):
            lines = [f"{pad}if {self.expr(s.cond)}:{self._tail(s.comment)}"]
            lines += self.block(s.then, depth + 1, out)
            rest = s.orelse
            while len(rest) == 1 and isinstance(rest[0], SIf) and not rest[0].comment:
                lines.append(f"{pad}elif {self.expr(rest[0].cond)}:")
                lines += self.block(rest[0].then, depth + 1, out)
                rest = rest[0].orelse
            if rest:
                lines.append(f"{pad}else:")
                lines += self.block(rest, depth + 1, out)
            return lines
        if isinstance(s, SFor):
            return [
                f"{pad}for {s.counter} in range("
                f"{'' if s.start is None else s.start + ', '}{s.count}):{self._tail(s.comment)}",
                *self.block(s.body, depth + 1, out),
            ]
        raise TypeError(f"cannot print {type(s).__name__}")

    _structs: dict[str, StructType]

    def _struct_of(self, name: str) -> StructType | None:
        return self._structs.get(name)


def _struct_locals(stmts: tuple[Stmt, ...], into: dict[str, StructType]) -> None:
    for s in stmts:
        if isinstance(s, SStruct):
            into[s.name] = s.struct
        elif isinstance(s, SIf):
            _struct_locals(s.then, into)
            _struct_locals(s.orelse, into)
        elif isinstance(s, SFor):
            _struct_locals(s.body, into)


def function_definition(fn: Function) -> str:
    """def py_name(params) -> return: the body line for line. An output pointer
    parameter becomes the returned NamedTuple."""
    tuples = frozenset(p.name for p in fn.params if p.is_pointer and p.const)
    printer = IRPythonPrinter(tuples)
    structs: dict[str, StructType] = {}
    _struct_locals(fn.body, structs)
    out = next(((p.name, p.struct) for p in fn.params if p.struct and not p.const), None)
    printer._structs = structs
    params = [p.name for p in fn.params if not (p.struct and not p.const)]
    if out is not None:
        ret = out[1].py_name
    elif isinstance(fn.returns, StructType):
        ret = fn.returns.py_name
    else:
        ret = "int" if fn.returns is not None else "None"
    annotated = ", ".join(
        f"{p.name}: {p.struct.py_name if p.struct else 'int'}"
        for p in fn.params
        if p.name in params
    )
    lines = [f"def {fn.py_name}({annotated}) -> {ret}:"]
    if fn.doc:
        lines.append(f'{INDENT}"""{comment_text(fn.doc)} ({fn.c_name})."""')
    lines += printer.block(fn.body, 1, out)
    if out is not None and not isinstance(fn.body[-1], SReturn):
        lines.append(f"{INDENT}return {printer._rebuild(*out)}")
    return "\n".join(lines)


def named_tuple(s: StructType) -> str:
    lines = [
        f"class {s.py_name}(NamedTuple):",
        f'{INDENT}"""{s.c_name}: {comment_text(s.doc)}"""',
        "",
    ]
    lines += [f"{INDENT}{f.name}: int  # {comment_text(f.doc)}" for f in s.fields]
    return "\n".join(lines)


def table_definition(t: Table) -> str:
    lines = [f"# {comment_text(t.doc)}", f"{t.py_name} = ("]
    for row in t.rows:
        lines.append(
            f"{INDENT}({', '.join(map(str, row))})," if t.columns > 1 else f"{INDENT}{row[0]},"
        )
    lines.append(")")
    return "\n".join(lines)


def assignment(c: IConst) -> str:
    assert c.name is not None
    doc = f"  # {comment_text(c.doc)}" if c.doc else ""
    return f"{c.name} = {c.value}{doc}"


def helpers(functions: tuple[Function, ...] | list[Function], always: bool = False) -> list[str]:
    """The definitions a twin of `functions` needs beside them: `_c_div` where one of
    them divides signed integers (C truncates toward zero, Python floors), or `always`."""
    signed = any(
        isinstance(e, IDiv) and e.ctype.signed for fn in functions for e in all_exprs(fn.body)
    )
    return [C_DIV] if signed or always else []

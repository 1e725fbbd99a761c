"""Print the IR as C99 (SymPy's C99CodePrinter, one `_print_<Node>` per IR class).

Operands are cast to the node's type wherever C's usual conversions would pick another
one (integer promotion of uint8/uint16, signed/unsigned mixes), so the C computes in
exactly the type the proof checked. Constants carry their type's suffix. Parentheses
follow C precedence; rounding shows as the literal half it adds.
"""

from __future__ import annotations

from functools import lru_cache

from sympy.printing.c import C99CodePrinter

from codegen.ir import acsl
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
from codegen.ir.types import BOOL, CType
from codegen.ir.walk import long_division_parts, referenced_names

# C precedence, higher binds tighter.
PRIMARY, UNARY, MULTIPLICATIVE, ADDITIVE, SHIFT, RELATIONAL, EQUALITY = 15, 13, 12, 11, 10, 9, 8
BITAND, BITOR, LOGAND, LOGOR, CONDITIONAL = 7, 5, 4, 3, 2
_BIN = {"+": ADDITIVE, "-": ADDITIVE, "*": MULTIPLICATIVE, "&": BITAND, "|": BITOR}
_CMP = {"<": RELATIONAL, "<=": RELATIONAL, ">": RELATIONAL, ">=": RELATIONAL}
INDENT = "    "


def comment_text(text: str) -> str:
    """Text safe inside a C block comment: no comment terminator, one line."""
    return " ".join(text.replace("*/", "* /").replace("/*", "/ *").split())


def literal(value: int, ctype: CType) -> str:
    text = f"{value}{ctype.literal_suffix}"
    if ctype == BOOL:
        return str(value)
    return f"({text})" if value < 0 else text


class IRCPrinter(C99CodePrinter):  # type: ignore[misc]
    """Expressions and statements of one function at a time (`pointers` are its struct
    pointer parameters: their fields print with `->`)."""

    def __init__(self, pointers: frozenset[str] = frozenset()) -> None:
        super().__init__()
        self.pointers = pointers

    # ------------------------------------------------------------ expressions

    def expr(self, e: Expr) -> str:
        return self._prec(e)[0]

    def _prec(self, e: Expr) -> tuple[str, int]:
        return self._print(e)  # type: ignore[no-any-return]

    def _operand(self, e: Expr, ctype: CType, level: int) -> str:
        """e as an operand of a node of `ctype` whose precedence is `level`."""
        text, prec = self._prec(e)
        if e.ctype != ctype and ctype != BOOL:
            if isinstance(e, IConst) and e.name is None:
                return literal(e.value, ctype)
            if prec < UNARY:
                text = f"({text})"
            return f"({ctype.name}){text}"
        return f"({text})" if prec < level else text

    def _print_IConst(self, e: IConst) -> tuple[str, int]:
        if e.name is not None:
            return e.name, PRIMARY
        return literal(e.value, e.ctype), PRIMARY

    def _print_IVar(self, e: IVar) -> tuple[str, int]:
        return e.name, PRIMARY

    def _print_IField(self, e: IField) -> tuple[str, int]:
        arrow = "->" if e.base in self.pointers else "."
        return f"{e.base}{arrow}{e.field}", PRIMARY

    def _print_IBin(self, e: IBin) -> tuple[str, int]:
        level = _BIN[e.op]
        # bitwise operands in parentheses unless primary: C's precedence of & and | is
        # easy to misread
        inner = UNARY if e.op in "&|" else level
        left = self._operand(e.a, e.ctype, inner)
        right = self._operand(e.b, e.ctype, max(inner, level + 1))  # left-associative
        return f"{left} {e.op} {right}", level

    def _shift_count(self, shift: int | Expr) -> str:
        if isinstance(shift, int):
            return f"{shift}u"
        return self._operand(shift, shift.ctype, UNARY)

    def _print_IShr(self, e: IShr) -> tuple[str, int]:
        if e.rounding == "nearest":
            assert isinstance(e.shift, int)
            half = literal(1 << (e.shift - 1), e.ctype)
            inner = f"{self._operand(e.a, e.ctype, ADDITIVE)} + {half}"
            return f"({inner}) >> {e.shift}u", SHIFT
        return f"{self._operand(e.a, e.ctype, UNARY)} >> {self._shift_count(e.shift)}", SHIFT

    def _print_IShl(self, e: IShl) -> tuple[str, int]:
        return f"{self._operand(e.a, e.ctype, UNARY)} << {self._shift_count(e.shift)}", SHIFT

    def _print_IDiv(self, e: IDiv) -> tuple[str, int]:
        divisor = self._operand(e.b, e.ctype, MULTIPLICATIVE + 1)
        if e.rounding == "trunc":
            return f"{self._operand(e.a, e.ctype, MULTIPLICATIVE)} / {divisor}", MULTIPLICATIVE
        numerator = self._operand(e.a, e.ctype, ADDITIVE)
        if e.rounding == "nearest":
            half = f"({self._operand(e.b, e.ctype, SHIFT)} >> 1)"
            return f"({numerator} + {half}) / {divisor}", MULTIPLICATIVE
        one = literal(1, e.ctype)
        bump = self._operand(e.b, e.ctype, ADDITIVE + 1)
        return f"({numerator} + {bump} - {one}) / {divisor}", MULTIPLICATIVE

    def _print_IMod(self, e: IMod) -> tuple[str, int]:
        left = self._operand(e.a, e.ctype, MULTIPLICATIVE)
        return f"{left} % {self._operand(e.b, e.ctype, MULTIPLICATIVE + 1)}", MULTIPLICATIVE

    def _print_ILongDiv(self, e: ILongDiv) -> tuple[str, int]:
        high, low, shift = (p.name for p in long_division_parts(e.numerator))
        divisor = self._operand(e.divisor, e.ctype, CONDITIONAL)
        return f"{DIVIDE_LONG.c_name}({high}, {low}, {shift}, {divisor})", PRIMARY

    def _print_ICmp(self, e: ICmp) -> tuple[str, int]:
        if e.a.ctype != e.b.ctype:
            raise TypeError(f"comparison of {e.a.ctype} with {e.b.ctype}: cast one side")
        level = _CMP.get(e.op, EQUALITY)
        left = self._operand(e.a, e.a.ctype, level)
        return f"{left} {e.op} {self._operand(e.b, e.b.ctype, level + 1)}", level

    def _print_IAnd(self, e: IAnd) -> tuple[str, int]:
        return f"{self._operand(e.a, BOOL, LOGAND)} && {self._operand(e.b, BOOL, LOGAND)}", LOGAND

    def _print_IOr(self, e: IOr) -> tuple[str, int]:
        return f"{self._operand(e.a, BOOL, LOGOR)} || {self._operand(e.b, BOOL, LOGOR)}", LOGOR

    def _print_INot(self, e: INot) -> tuple[str, int]:
        return f"!{self._operand(e.a, BOOL, UNARY)}", UNARY

    def _print_ISelect(self, e: ISelect) -> tuple[str, int]:
        if e.a.ctype != e.b.ctype:
            raise TypeError(f"select of {e.a.ctype} and {e.b.ctype}: cast one side")
        cond = self._operand(e.cond, BOOL, LOGOR)
        a = self._operand(e.a, e.ctype, LOGOR)
        b = self._operand(e.b, e.ctype, CONDITIONAL)
        return f"({cond}) ? {a} : {b}", CONDITIONAL

    def _print_ICast(self, e: ICast) -> tuple[str, int]:
        return self._operand(e.a, e.ctype, UNARY), UNARY

    def _index(self, e: ILookup | IStep, offset: str = "") -> str:
        index = self._operand(e.index, e.index.ctype, ADDITIVE)
        row = f"{e.table.name}[{index}{offset}]"
        return f"{row}[{e.column}]" if e.table.columns > 1 else row

    def _print_ILookup(self, e: ILookup) -> tuple[str, int]:
        text = self._index(e)
        if e.table.ctype != e.ctype:
            return f"({e.ctype.name}){text}", UNARY
        return text, PRIMARY

    def _print_IStep(self, e: IStep) -> tuple[str, int]:
        return f"({e.ctype.name}){self._index(e, ' + 1u')} - {self._index(e)}", ADDITIVE

    def _print_IBitLength(self, e: IBitLength) -> tuple[str, int]:
        operand = self._operand(e.a, e.a.ctype, CONDITIONAL)
        return f"(32u - (uint32_t)__builtin_clz({operand}))", PRIMARY

    def _print_IAddr(self, e: IAddr) -> tuple[str, int]:
        return f"&{e.name}", UNARY

    def _print_ICall(self, e: ICall) -> tuple[str, int]:
        args = []
        for param, arg in zip(e.function.params, e.args, strict=True):
            want = param.ctype if param.ctype is not None else arg.ctype
            args.append(self._operand(arg, want, CONDITIONAL))
        return f"{e.function.c_name}({', '.join(args)})", PRIMARY

    # ------------------------------------------------------------ statements

    def block(self, stmts: tuple[Stmt, ...], depth: int) -> list[str]:
        out: list[str] = []
        pad = INDENT * depth
        for s, (before, after) in zip(stmts, acsl.block_hints(stmts), strict=True):
            out.extend(pad + hint for hint in before)  # ACSL proof hints (codegen/ir/acsl.py)
            out.extend(self.statement(s, depth))
            out.extend(pad + hint for hint in after)
        return out

    @staticmethod
    def _tail(comment: str) -> str:
        return f" /* {comment_text(comment)} */" if comment else ""

    def statement(self, s: Stmt, depth: int) -> list[str]:
        pad = INDENT * depth
        if isinstance(s, SComment):
            return [f"{pad}/* {comment_text(s.text)} */"]
        if isinstance(s, SLet):
            return [
                f"{pad}const {s.expr.ctype.name} {s.name} = {self.expr(s.expr)};{self._tail(s.comment)}"
            ]
        if isinstance(s, SLetStruct):
            returns = s.call.function.returns
            assert isinstance(returns, StructType)
            return [
                f"{pad}const {returns.c_name} {s.name} = {self.expr(s.call)};{self._tail(s.comment)}"
            ]
        if isinstance(s, SVar):
            init = self._operand(s.init, s.ctype, CONDITIONAL)
            return [f"{pad}{s.ctype.name} {s.name} = {init};{self._tail(s.comment)}"]
        if isinstance(s, SAssign):
            return [f"{pad}{s.name} = {self.expr(s.expr)};{self._tail(s.comment)}"]
        if isinstance(s, SOrAssign):
            return [f"{pad}{s.name} |= {self.expr(s.expr)};{self._tail(s.comment)}"]
        if isinstance(s, SStore):
            arrow = "->" if s.base in self.pointers else "."
            return [f"{pad}{s.base}{arrow}{s.field} = {self.expr(s.expr)};{self._tail(s.comment)}"]
        if isinstance(s, SReturn):
            return [f"{pad}return;" if s.value is None else f"{pad}return {self.expr(s.value)};"]
        if isinstance(s, SStruct):
            qualifier = "const " if s.const else ""
            lines = [f"{pad}{qualifier}{s.struct.c_name} {s.name} = {{{self._tail(s.comment)}"]
            for name, value in s.values:
                field = s.struct.field(name)
                text = self._operand(value, field.ctype, CONDITIONAL)
                lines.append(f"{pad}{INDENT}.{name} = {text},")
            lines.append(f"{pad}}};")
            return lines
        if isinstance(s, SIf):
            return self._if(s, depth, "if")
        if isinstance(s, SFor):
            first = s.start if s.start is not None else "0u"
            head = (
                f"{pad}for (uint32_t {s.counter} = {first}; {s.counter} < {s.count}u;"
                f" ++{s.counter}) {{{self._tail(s.comment)}"
            )
            return [head, *self.block(s.body, depth + 1), f"{pad}}}"]
        raise TypeError(f"cannot print {type(s).__name__}")

    def _if(self, s: SIf, depth: int, keyword: str) -> list[str]:
        pad = INDENT * depth
        lead = pad if keyword == "if" else ""
        lines = [f"{lead}{keyword} ({self.expr(s.cond)}) {{{self._tail(s.comment)}"]
        lines += self.block(s.then, depth + 1)
        if not s.orelse:
            return [*lines, f"{pad}}}"]
        if len(s.orelse) == 1 and isinstance(s.orelse[0], SIf) and not s.orelse[0].comment:
            chained = self._if(s.orelse[0], depth, "if")
            chained[0] = f"{pad}}} else {chained[0].lstrip()}"
            return [*lines, *chained]
        return [*lines, f"{pad}}} else {{", *self.block(s.orelse, depth + 1), f"{pad}}}"]


# ---------------------------------------------------------------- declarations


@lru_cache(maxsize=64)
def printer_for(pointers: frozenset[str] = frozenset()) -> IRCPrinter:
    """One printer per set of pointer parameters, built once: building a SymPy printer
    costs far more than printing one expression, and the interval proof prints the
    expression of every range it records. Printing reads only `pointers`."""
    return IRCPrinter(pointers)


def signature(fn: Function) -> str:
    params = []
    for p in fn.params:
        if p.struct is not None:
            qualifier = "const " if p.const else ""
            params.append(f"{qualifier}{p.struct.c_name} *{p.name}")
        else:
            assert p.ctype is not None
            params.append(f"{p.ctype.name} {p.name}")
    if fn.returns is None:
        ret = "void"
    elif isinstance(fn.returns, StructType):
        ret = fn.returns.c_name
    else:
        ret = fn.returns.name
    storage = "static inline " if fn.inline else ("static " if fn.static else "")
    return f"{storage}{ret} {fn.c_name}({', '.join(params) or 'void'})"


def function_definition(fn: Function, contract: str = "") -> str:
    """fn's definition, its ACSL contract (if any) between its comment and signature."""
    printer = IRCPrinter(frozenset(p.name for p in fn.params if p.is_pointer))
    lines = []
    if fn.doc:
        lines.append(f"/* {comment_text(fn.doc)} */")
    if contract:
        lines.append(contract)
    lines.append(signature(fn))
    lines.append("{")
    used = referenced_names(fn)
    for p in fn.params:
        if p.name not in used:
            lines.append(f"{INDENT}(void){p.name}; /* not used by this method */")
    lines.extend(printer.block(fn.body, 1))
    lines.append("}")
    return "\n".join(lines)


def prototype(fn: Function) -> str:
    return f"{signature(fn)};"


def struct_typedef(s: StructType) -> str:
    width = max(len(f"{f.ctype.name} {f.name};") for f in s.fields)
    lines = [f"/* {comment_text(s.doc)} */", "typedef struct {"]
    for f in s.fields:
        decl = f"{f.ctype.name} {f.name};"
        lines.append(f"    {decl:<{width}} /* {comment_text(f.doc)} */")
    lines.append(f"}} {s.c_name};")
    return "\n".join(lines)


def table_definition(t: Table) -> str:
    storage = "static const" if t.static else "const"
    shape = f"[{len(t.rows)}]" + (f"[{t.columns}]" if t.columns > 1 else "")
    lines = [f"/* {comment_text(t.doc)} */", f"{storage} {t.ctype.name} {t.name}{shape} = {{"]
    for row, note in zip(t.rows, t.comments, strict=True):
        cells = ", ".join(literal(v, t.ctype) for v in row)
        text = f"{{{cells}}}," if t.columns > 1 else f"{cells},"
        lines.append(f"    {text}" + (f" /* {comment_text(note)} */" if note else ""))
    lines.append("};")
    return "\n".join(lines)


def table_declaration(t: Table) -> str:
    shape = f"[{len(t.rows)}]" + (f"[{t.columns}]" if t.columns > 1 else "")
    return f"extern const {t.ctype.name} {t.name}{shape};"


def define(c: IConst) -> str:
    assert c.name is not None
    doc = f" /* {comment_text(c.doc)} */" if c.doc else ""
    return f"#define {c.name} {literal(c.value, c.ctype)}{doc}"

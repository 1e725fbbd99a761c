"""The integer IR: the core's arithmetic written once, as data.

Every node states its C type. The C printer (`c_printer`), the bit-exact Python printer
(`py_printer`), the overflow proof (`intervals`) and the error analysis (`errors`) all
walk these same objects, so what is proven is what is printed.

Semantics are C99's on the stated types, restricted so that Python integers reproduce
them exactly: the proof requires every node's value to fit its type (no wrap-around), a
shift's operand to be non-negative and a divisor to be non-zero. Rounding is explicit
in the node (`IShr.rounding`, `IDiv.rounding`), never implied by a printer.

Expressions
  IConst      integer constant; named ones become `#define NAME` in C and `NAME = ` in
              Python, with the exact value they approximate (for the error analysis)
  IVar        scalar parameter or local
  IField      field of a struct parameter or local
  IBin        + - * & | on operands cast to the node's type
  IShr/IShl   shifts by a constant; IShr rounds down or to nearest (half up)
  IDiv        division rounding toward zero, to nearest (half up) or up
  IMod        remainder of non-negative operands
  ILongDiv    round(N / divisor) for a constant N wider than 32 bits, in two 32-bit
              divides (a static helper); semantics exact rounding
  ICmp        comparison (0 or 1); `exact` says the integer decision is the ideal one
  IAnd/IOr/INot  logic on comparisons
  ISelect     cond ? a : b
  ICast       conversion to the node's type (the value must fit)
  ILookup     element of a constant table; IStep the difference of consecutive rows
  IBitLength  number of significant bits of a positive value (32 - CLZ on Cortex-M3)
  ICall       call of an IR function; IAddr passes a struct local by address

Statements
  SLet        const local;  SVar mutable local;  SAssign, SOrAssign
  SIf         branches; SFor a counted loop whose carried variables declare the
              interval they keep (checked by the proof: an induction invariant)
  SStruct     struct local with its fields; SLetStruct one a call returns; SStore writes a field of a struct local or
              of a pointer parameter; SReturn
  SComment    a comment line in C and Python
"""

from __future__ import annotations

from dataclasses import dataclass, field
from fractions import Fraction
from typing import Literal

from codegen.ir.types import BOOL, U32, CType

Rounding = Literal["floor", "nearest"]
DivRounding = Literal["trunc", "nearest", "ceil"]
BinOp = Literal["+", "-", "*", "&", "|"]
CmpOp = Literal["<", "<=", ">", ">=", "==", "!="]


# --------------------------------------------------------------------------- structs


@dataclass(frozen=True)
class StructField:
    name: str
    ctype: CType
    doc: str


@dataclass(frozen=True)
class StructType:
    """A C struct typedef and the Python NamedTuple that mirrors it."""

    c_name: str  # "bldc_timing_t"
    py_name: str  # "Timing"
    fields: tuple[StructField, ...]
    doc: str

    def field(self, name: str) -> StructField:
        for f in self.fields:
            if f.name == name:
                return f
        raise KeyError(f"{self.c_name} has no field {name!r}")

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(f.name for f in self.fields)


# --------------------------------------------------------------------------- tables


@dataclass(frozen=True)
class Table:
    """A constant table in flash: rows of one C type (one column or several)."""

    name: str  # C name; the Python name is its upper-case form
    ctype: CType
    rows: tuple[tuple[int, ...], ...]
    comments: tuple[str, ...]  # one per row
    doc: str
    static: bool = True

    @property
    def columns(self) -> int:
        return len(self.rows[0])

    @property
    def py_name(self) -> str:
        return self.name.upper()

    def column(self, k: int) -> tuple[int, ...]:
        return tuple(r[k] for r in self.rows)

    @property
    def flash_bytes(self) -> int:
        return len(self.rows) * self.columns * self.ctype.bits // 8


# --------------------------------------------------------------------------- expressions


@dataclass(frozen=True, eq=False)
class Expr:
    ctype: CType


@dataclass(frozen=True, eq=False)
class IConst(Expr):
    value: int
    name: str | None = None
    #: the real value this integer stands for, in the same units (None: exact)
    exact: Fraction | None = None
    doc: str = ""

    @property
    def error(self) -> Fraction:
        return abs(Fraction(self.value) - self.exact) if self.exact is not None else Fraction(0)


@dataclass(frozen=True, eq=False)
class IVar(Expr):
    name: str


@dataclass(frozen=True, eq=False)
class IField(Expr):
    base: str
    field: str


@dataclass(frozen=True, eq=False)
class IBin(Expr):
    op: BinOp
    a: Expr
    b: Expr


@dataclass(frozen=True, eq=False)
class IShr(Expr):
    a: Expr
    shift: int | Expr  # an expression only when rounding down (table interpolation)
    rounding: Rounding = "floor"


@dataclass(frozen=True, eq=False)
class IShl(Expr):
    a: Expr
    shift: int | Expr  # an expression only in the long-division helper


@dataclass(frozen=True, eq=False)
class IDiv(Expr):
    a: Expr
    b: Expr
    rounding: DivRounding = "trunc"


@dataclass(frozen=True, eq=False)
class IMod(Expr):
    a: Expr
    b: Expr


@dataclass(frozen=True, eq=False)
class ILongDiv(Expr):
    """round(numerator / divisor), numerator a named constant of up to 64 bits."""

    numerator: IConst
    divisor: Expr


@dataclass(frozen=True, eq=False)
class ICmp(Expr):
    op: CmpOp
    a: Expr
    b: Expr
    exact: bool = True


@dataclass(frozen=True, eq=False)
class IAnd(Expr):
    a: Expr
    b: Expr


@dataclass(frozen=True, eq=False)
class IOr(Expr):
    a: Expr
    b: Expr


@dataclass(frozen=True, eq=False)
class INot(Expr):
    a: Expr


@dataclass(frozen=True, eq=False)
class ISelect(Expr):
    cond: Expr
    a: Expr
    b: Expr
    #: a min, max or clamp: where rounding flips the decision the result still moves
    #: by no more than its operands' errors (the error analysis relies on it)
    lipschitz: bool = False


@dataclass(frozen=True, eq=False)
class ICast(Expr):
    a: Expr


@dataclass(frozen=True, eq=False)
class ILookup(Expr):
    table: Table
    index: Expr
    column: int = 0


@dataclass(frozen=True, eq=False)
class IStep(Expr):
    """table[index + 1][column] - table[index][column], proven non-negative per row."""

    table: Table
    index: Expr
    column: int = 0


@dataclass(frozen=True, eq=False)
class IBitLength(Expr):
    a: Expr


@dataclass(frozen=True, eq=False)
class IAddr(Expr):
    """&name of a struct local, as a call argument."""

    name: str


@dataclass(frozen=True, eq=False)
class ICall(Expr):
    function: Function
    args: tuple[Expr, ...]


# --------------------------------------------------------------------------- statements


@dataclass(frozen=True, eq=False)
class Stmt:
    pass


@dataclass(frozen=True, eq=False)
class SLet(Stmt):
    name: str
    expr: Expr
    comment: str = ""
    #: the proof analyses the rest of the block once per value of this local (a case
    #: split, as Frama-C's does): for a table segment whose row and shift go together
    split: bool = False


@dataclass(frozen=True, eq=False)
class SVar(Stmt):
    name: str
    ctype: CType
    init: Expr
    comment: str = ""


@dataclass(frozen=True, eq=False)
class SAssign(Stmt):
    name: str
    expr: Expr
    comment: str = ""


@dataclass(frozen=True, eq=False)
class SOrAssign(Stmt):
    name: str
    expr: Expr
    comment: str = ""


@dataclass(frozen=True, eq=False)
class SIf(Stmt):
    cond: Expr
    then: tuple[Stmt, ...]
    orelse: tuple[Stmt, ...] = ()
    comment: str = ""


@dataclass(frozen=True, eq=False)
class SFor(Stmt):
    counter: str
    count: int
    body: tuple[Stmt, ...]
    #: loop-carried variables and the interval each keeps (the proof checks it)
    invariants: tuple[tuple[str, int, int], ...] = ()
    comment: str = ""
    #: the counter's first value, a uint32 local within [0, count] (the proof checks it);
    #: None: 0
    start: str | None = None


@dataclass(frozen=True, eq=False)
class SStruct(Stmt):
    name: str
    struct: StructType
    values: tuple[tuple[str, Expr], ...]
    const: bool = True
    comment: str = ""


@dataclass(frozen=True, eq=False)
class SLetStruct(Stmt):
    """const struct local initialised by a call that returns the struct."""

    name: str
    call: ICall
    comment: str = ""


@dataclass(frozen=True, eq=False)
class SStore(Stmt):
    base: str
    field: str
    expr: Expr
    comment: str = ""


@dataclass(frozen=True, eq=False)
class SReturn(Stmt):
    value: Expr | None = None


@dataclass(frozen=True, eq=False)
class SComment(Stmt):
    text: str


# --------------------------------------------------------------------------- functions


@dataclass(frozen=True)
class Param:
    name: str
    ctype: CType | None = None  # scalar parameter
    struct: StructType | None = None  # pointer to a struct
    const: bool = True  # const pointer (input) or output pointer
    doc: str = ""

    @property
    def is_pointer(self) -> bool:
        return self.struct is not None


@dataclass(frozen=True, eq=False)
class Function:
    c_name: str
    py_name: str
    params: tuple[Param, ...]
    body: tuple[Stmt, ...]
    returns: CType | StructType | None = None
    doc: str = ""
    static: bool = False  # file-local helper
    inline: bool = False  # `static inline`, printed in the header

    def param(self, name: str) -> Param:
        for p in self.params:
            if p.name == name:
                return p
        raise KeyError(name)


@dataclass(frozen=True)
class Module:
    """Everything one generated core is made of."""

    functions: tuple[Function, ...]
    tables: tuple[Table, ...] = ()
    structs: tuple[StructType, ...] = ()
    #: named constants that no expression uses but the header documents
    extra_constants: tuple[IConst, ...] = field(default_factory=tuple)


# --------------------------------------------------------------------------- builders


def const(value: int, ctype: CType = U32, name: str | None = None, **kw: object) -> IConst:
    return IConst(ctype, int(value), name, **kw)  # type: ignore[arg-type]


def var(name: str, ctype: CType) -> IVar:
    return IVar(ctype, name)


def fld(base: str, name: str, ctype: CType) -> IField:
    return IField(ctype, base, name)


def cast(a: Expr, ctype: CType) -> Expr:
    return a if a.ctype == ctype else ICast(ctype, a)


def add(a: Expr, b: Expr, ctype: CType | None = None) -> IBin:
    return IBin(ctype or a.ctype, "+", a, b)


def sub(a: Expr, b: Expr, ctype: CType | None = None) -> IBin:
    return IBin(ctype or a.ctype, "-", a, b)


def mul(a: Expr, b: Expr, ctype: CType | None = None) -> IBin:
    return IBin(ctype or a.ctype, "*", a, b)


def shr(a: Expr, shift: int | Expr, rounding: Rounding = "floor") -> Expr:
    if isinstance(shift, int) and shift <= 0:
        return a
    return IShr(a.ctype, a, shift, rounding)


def round_shr(a: Expr, shift: int) -> Expr:
    return shr(a, shift, "nearest")


def shl(a: Expr, shift: int) -> Expr:
    return IShl(a.ctype, a, shift) if shift > 0 else a


def div(a: Expr, b: Expr, rounding: DivRounding = "trunc", ctype: CType | None = None) -> IDiv:
    return IDiv(ctype or a.ctype, a, b, rounding)


def cmp(op: CmpOp, a: Expr, b: Expr, exact: bool = True) -> ICmp:
    return ICmp(BOOL, op, a, b, exact)


def select(cond: Expr, a: Expr, b: Expr) -> ISelect:
    return ISelect(a.ctype, cond, a, b)


def clamp(a: Expr, low: Expr, high: Expr) -> Expr:
    """min(max(a, low), high) as nested selects (low <= high must hold)."""
    inner = ISelect(a.ctype, cmp(">", a, high, exact=False), high, a, lipschitz=True)
    return ISelect(a.ctype, cmp("<", a, low, exact=False), low, inner, lipschitz=True)


def minimum(a: Expr, b: Expr) -> Expr:
    return ISelect(a.ctype, cmp(">", a, b, exact=False), b, a, lipschitz=True)


def maximum(a: Expr, b: Expr) -> Expr:
    return ISelect(a.ctype, cmp("<", a, b, exact=False), b, a, lipschitz=True)


def lor(a: Expr, b: Expr) -> IOr:
    return IOr(BOOL, a, b)


def land(a: Expr, b: Expr) -> IAnd:
    return IAnd(BOOL, a, b)


def lnot(a: Expr) -> INot:
    return INot(BOOL, a)

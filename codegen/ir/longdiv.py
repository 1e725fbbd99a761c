"""round(N / B) for a constant N of up to 64 bits, in two 32-bit divides.

N = high 2^shift + low, high < 2^32. Then N / B = q_high 2^shift + (r 2^shift + low) / B
with q_high = high / B and r = high mod B, and r 2^shift + low < B 2^shift fits 32 bits
whenever B 2^shift does (the proof checks it at each call). No 64-bit divide helper
(__aeabi_uldivmod) is needed; a Cortex-M3 does each divide in one UDIV.
"""

from __future__ import annotations

from codegen.ir.nodes import (
    Expr,
    Function,
    IBin,
    IMod,
    IShl,
    Param,
    SLet,
    SReturn,
    Stmt,
    add,
    cast,
    const,
    div,
    minimum,
    shr,
    var,
)
from codegen.ir.types import U32, U64

_high, _low, _shift, _divisor = (var(n, U32) for n in ("high", "low", "shift", "divisor"))

DIVIDE_LONG = Function(
    c_name="bldc_divide_long",
    py_name="divide_long",
    params=tuple(Param(n, U32) for n in ("high", "low", "shift", "divisor")),
    returns=U32,
    static=True,
    doc="round(N / divisor) for N = high 2^shift + low: two 32-bit divides, no 64-bit "
    "helper. N / divisor = q_high 2^shift + (r 2^shift + low) / divisor, r = high mod "
    "divisor.",
    body=(
        SLet("q_high", div(_high, _divisor)),
        SLet("remainder", add(IShl(U32, IMod(U32, _high, _divisor), _shift), _low)),
        SReturn(
            add(
                IShl(U32, var("q_high", U32), _shift),
                div(var("remainder", U32), _divisor, "nearest"),
            )
        ),
    ),
)


def bytewise_quotient(
    name: str, numerator: str, divisor: Expr, top_cap: int, doc: str
) -> tuple[Stmt, ...]:
    """`name` = round(numerator / divisor) for a uint64_t local `numerator` below 2^48
    and a divisor below 2^24, in three 32-bit divides (16 + 8 + 8 bits): each remainder
    is below the divisor, so remainder 2^8 + the next byte fits 32 bits. The caller
    bounds the quotient: `top_cap` caps its first digit (the quotient / 2^16), the
    others are below 2^8 by construction; the caps let a non-relational proof see the
    shifts fit, and never bind."""
    wide = var(numerator, U64)
    upper, middle, lower = (var(f"{name}_{part}", U32) for part in ("upper", "middle", "lower"))

    def byte(shift: int) -> Expr:
        return cast(IBin(U64, "&", shr(wide, shift), const(255, U64)), U32)

    return (
        SLet(upper.name, cast(shr(wide, 16), U32), f"{numerator} / 2^16"),
        SLet(
            middle.name,
            add(IShl(U32, IMod(U32, upper, divisor), 8), byte(8)),
            "the remainder, then the next byte",
        ),
        SLet(
            lower.name,
            add(IShl(U32, IMod(U32, middle, divisor), 8), byte(0)),
            "the remainder, then the last byte",
        ),
        SLet(
            name,
            add(
                add(
                    IShl(U32, minimum(div(upper, divisor), const(top_cap)), 16),
                    IShl(U32, minimum(div(middle, divisor), const(255)), 8),
                ),
                minimum(div(lower, divisor, "nearest"), const(256)),
            ),
            doc,
        ),
    )

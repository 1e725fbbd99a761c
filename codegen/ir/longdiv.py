"""round(N / B) for a constant N of up to 64 bits, in two 32-bit divides.

N = high 2^shift + low, high < 2^32. Then N / B = q_high 2^shift + (r 2^shift + low) / B
with q_high = high / B and r = high mod B, and r 2^shift + low < B 2^shift fits 32 bits
whenever B 2^shift does (the proof checks it at each call). No 64-bit divide helper
(__aeabi_uldivmod) is needed; a Cortex-M3 does each divide in one UDIV.
"""

from __future__ import annotations

from codegen.ir.nodes import Function, IMod, IShl, Param, SLet, SReturn, add, div, var
from codegen.ir.types import U32

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

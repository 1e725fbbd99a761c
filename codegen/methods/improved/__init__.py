"""The paper's proposed method: Eq. 18's segmented duties.

Low speed (4E <= U_d): the turn-on phase fully on, the turn-off phase modulated at
D_off = 1 - 4E/U_d. High speed (4E > U_d): the turn-off phase off, the turn-on phase
modulated at D_on = 2 - 4E/U_d. The segment decision is exact (an integer comparison);
the main duty is not used: the rule holds the current by itself.
"""

from __future__ import annotations

from codegen.ir.nodes import SAssign, SIf, Stmt, cast, const, maximum, mul, sub
from codegen.ir.types import I32
from codegen.methods.paper_core import DutyContext, DutyRule
from codegen.methods.paper_method import PaperMethod


def _duties(ctx: DutyContext) -> tuple[Stmt, ...]:
    p = cast(ctx.limits.period_counts, I32)
    zero = const(0, I32)
    return (
        SIf(
            ctx.high_speed,
            (
                SAssign(
                    "on",
                    maximum(sub(mul(const(2, I32), p), ctx.x_c), zero),
                    "D_on = 2 - 4E/U_d; 0 above the upper speed limit 4E > 2 U_d",
                ),
                SAssign("off", zero, "the turn-off phase off"),
            ),
            (
                SAssign("on", p, "the turn-on phase fully on"),
                SAssign("off", maximum(sub(p, ctx.x_c), zero), "D_off = 1 - 4E/U_d"),
            ),
            comment="Eq. 18",
        ),
    )


METHOD = PaperMethod(
    DutyRule(
        method="improved",
        uses_main_duty=False,
        statements=_duties,
        doc=(
            "Eq. 18: low speed (4E <= U_d) C_on = P, C_off = P - X; high speed",
            "(4E > U_d) C_on = 2P - X, C_off = 0; clamped at 0. The main duty is not used.",
        ),
    )
)

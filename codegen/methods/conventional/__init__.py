"""Conventional overlapping commutation (Eqs. 15-16): the incoming switch runs the
controller's main duty D_on = M, the outgoing one D_off = 2 - 4E/U_d - D_on, clamped
to [0, 1]. Where the clamp acts (the control fail area, decided exactly) the flag says so.
"""

from __future__ import annotations

from codegen.core.conditioning import flag_if
from codegen.ir.nodes import SAssign, SLet, Stmt, cast, clamp, const, mul, sub, var
from codegen.ir.types import I32, U32
from codegen.methods.paper_core import (
    DutyContext,
    DutyRule,
    fail_area_condition,
    saturated_main_duty,
)
from codegen.methods.paper_method import PaperMethod


def _duties(ctx: DutyContext) -> tuple[Stmt, ...]:
    p = cast(ctx.limits.period_counts, I32)
    on = var("on", I32)
    return (
        *saturated_main_duty(ctx),
        flag_if(fail_area_condition(ctx), "FAIL_AREA_CLAMPED", "Eq. 16 outside [0, 1], exactly"),
        SAssign("on", cast(var("main_duty", U32), I32), "D_on = the main duty"),
        # a local of its own, so that a non-relational analysis (Frama-C's EVA) narrows
        # it in the clamp as the IR's proof does
        SLet("eq16_off", sub(sub(mul(const(2, I32), p), ctx.x_c), on), "Eq. 16: 2P - X - C_on"),
        SAssign("off", clamp(var("eq16_off", I32), const(0, I32), p), "D_off clamped to [0, 1]"),
    )


METHOD = PaperMethod(
    DutyRule(
        method="conventional",
        uses_main_duty=True,
        statements=_duties,
        doc=(
            "Eqs. 15-16: C_on = M (the main duty, saturated at P and flagged), C_off =",
            "2P - X - C_on clamped to [0, P]; BLDC_FLAG_FAIL_AREA_CLAMPED where the clamp",
            "acts, decided exactly from K_X = X T B (no rounding).",
        ),
    )
)

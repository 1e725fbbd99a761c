"""No suppression: the incoming switch runs the controller's main duty, the outgoing
one is off (D_off = 0), as a drive without commutation control does."""

from __future__ import annotations

from codegen.ir.nodes import SAssign, Stmt, cast, const, var
from codegen.ir.types import I32, U32
from codegen.methods.paper_core import DutyContext, DutyRule, saturated_main_duty
from codegen.methods.paper_method import PaperMethod


def _duties(ctx: DutyContext) -> tuple[Stmt, ...]:
    return (
        *saturated_main_duty(ctx),
        SAssign("on", cast(var("main_duty", U32), I32), "D_on = the main duty"),
        SAssign("off", const(0, I32), "the outgoing switch off"),
    )


METHOD = PaperMethod(
    DutyRule(
        method="none",
        uses_main_duty=True,
        statements=_duties,
        doc=("No suppression: C_on = M (the main duty, saturated at P and flagged), C_off = 0.",),
    )
)

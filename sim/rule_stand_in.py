"""improved_r in real arithmetic, standing in for its C core in a comparison.

The simulation compares every method on a motor whose firmware is one of them. The
resistance-aware rule's integer design refuses some motors its real-arithmetic rule
handles (at 5 kHz PWM its X numerator, duty counts x Hall ticks, needs more than 32
bits). Where the spec's own method is another, the comparison then runs the rule in
real arithmetic (`codegen.methods.improved_r.reference`: what the integer core
approximates within its proven bounds) rather than nothing, and the report says so.

The compare values, the commutation time and the flags are the reference's; the
switches, the sector and the safe state (over-speed, over-voltage, an invalid Hall
pair) are a sibling core's, whose edge tables and limits are the spec's as every
method's are.
"""

from __future__ import annotations

from pathlib import Path
from typing import Protocol

from codegen.methods.improved_r.constants import RuleConstants
from codegen.methods.improved_r.reference import (
    FLAG_ABOVE_BUS,
    FLAG_BUS_CLAMPED,
    FLAG_CANNOT_HOLD,
    FLAG_NOT_FINISHED,
    FLAG_SPEED_CLAMPED,
    RuleInputs,
    reference_points,
)

METHOD = "improved_r"
#: the reference's flags, as the core's flag bits of the same meaning
FLAG_BITS = (
    (FLAG_SPEED_CLAMPED | FLAG_BUS_CLAMPED, "INPUT_SATURATED"),
    (FLAG_NOT_FINISHED, "TIME_CLAMPED"),
    (FLAG_CANNOT_HOLD | FLAG_ABOVE_BUS, "FAIL_AREA_CLAMPED"),
)


class Constants(Protocol):
    no_switch: int
    flags: dict[str, int]


class Core(Protocol):
    constants: Constants

    def commutate(self, inputs: dict[str, int]) -> dict[str, int]: ...


class RuleStandIn:
    """`commutate` and `over_periods` as a compiled core has them (sim.sil.CoreLibrary),
    from the rule in real arithmetic; `path` is None: there is no library to load."""

    def __init__(self, sibling: Core, rule: RuleConstants, reason: str) -> None:
        self.method = METHOD
        self.constants = sibling.constants
        self.path: Path | None = None
        self.reason = reason
        self._sibling = sibling
        self._rule = rule

    def _flags(self, reference_flags: int) -> int:
        bits = self.constants.flags
        return sum(bits[name] for mask, name in FLAG_BITS if reference_flags & mask)

    def _many(self, inputs: dict[str, int], periods: list[int]) -> list[dict[str, int]]:
        outs = [self._sibling.commutate({**inputs, "hall_period_ticks": t}) for t in periods]
        switching = [
            k
            for k, out in enumerate(outs)
            if out["turn_on_switch"] != self.constants.no_switch
            or out["turn_off_switch"] != self.constants.no_switch
        ]
        if switching:
            batch = reference_points(
                self._rule,
                [
                    RuleInputs(periods[k], inputs["bus_voltage_adc"], inputs["phase_current_adc"])
                    for k in switching
                ],
            )
            for j, k in enumerate(switching):
                rule = batch.outputs(j, self._rule.latest_end(periods[k]))
                outs[k] = {
                    **outs[k],
                    "turn_on_compare": rule.on_counts,
                    "turn_off_compare": rule.off_counts,
                    "commutation_ticks": rule.commutation_ticks,
                    "flags": self._flags(rule.flags),
                }
        return outs

    def commutate(self, inputs: dict[str, int]) -> dict[str, int]:
        return self._many(inputs, [inputs["hall_period_ticks"]])[0]

    def over_periods(self, inputs: dict[str, int], periods: range) -> list[tuple[int, int]]:
        return [
            (out["commutation_ticks"], out["flags"]) for out in self._many(inputs, list(periods))
        ]

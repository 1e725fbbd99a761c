"""`improved_r_fw`: the firmware form of the resistance-aware rule as a controller.

It sees exactly the integers the port hands the core at a Hall edge (Hall period in
ticks, bus and current ADC codes) and runs the integer prototype of
`codegen.improved_r_rule.fixed`, bit for bit what the C will do: one constant duty
pair (TIM1 counts) and one commutation time (Hall ticks). `reference=True` runs the
real-arithmetic rule instead (same inputs, unrounded internals), to separate the
rule's error from the fixed-point error.
"""

from __future__ import annotations

from functools import lru_cache

from codegen.derivation import derive
from codegen.fixedpoint.scaling import Scaling, scaling
from codegen.improved_r_rule.constants import RuleConstants, rule_constants
from codegen.improved_r_rule.design import design_rule
from codegen.improved_r_rule.fixed import FixedRule, run_fixed
from codegen.improved_r_rule.reference import RuleInputs, RuleOutputs, reference
from codegen.spec_model import Spec
from sim.command import Command
from sim.scenario import Case
from sim.schedule import switch_index

METHOD = "improved_r_fw"


@lru_cache(maxsize=4)
def _rule(spec: Spec) -> tuple[Scaling, RuleConstants, FixedRule]:
    sc = scaling(spec, derive())
    constants = rule_constants(spec, sc)
    return sc, constants, design_rule(constants, sc.current_code_max).rule


def rule_inputs(sc: Scaling, case: Case, measured_current_a: float) -> RuleInputs:
    """The port's integers at this edge (as `sim.sil.core_inputs` forms them)."""
    ticks = round(case.sector_time_s * float(sc.hall_clock_hz))
    bus = round(case.drive.bus_voltage_v / float(sc.volts_per_bus_code))
    current = sc.current_offset_code + round(measured_current_a / float(sc.amps_per_current_code))
    return RuleInputs(
        period_ticks=min(max(ticks, 0), 2**16 - 1),
        bus_code=min(max(bus, 0), 2**16 - 1),
        current_code=min(max(current, 0), 2**16 - 1),
    )


def improved_r_fw_outputs(
    spec: Spec, case: Case, measured_current_a: float, exact: bool = False
) -> RuleOutputs:
    sc, constants, fixed = _rule(spec)
    inputs = rule_inputs(sc, case, measured_current_a)
    if exact:
        return reference(constants, inputs).outputs
    return run_fixed(fixed, inputs).outputs


def improved_r_fw_command(
    spec: Spec, case: Case, measured_current_a: float, main_duty: float, exact: bool = False
) -> Command:
    sc, _, _ = _rule(spec)
    out = improved_r_fw_outputs(spec, case, measured_current_a, exact)
    counts = sc.period_counts
    return Command(
        method=METHOD,
        turn_on_switch=switch_index(case.edge.modulated_on),
        turn_off_switch=switch_index(case.edge.modulated_off),
        on_duties=(out.on_counts / counts,),
        off_duties=(out.off_counts / counts,),
        commutation_time_s=out.commutation_ticks / float(sc.hall_clock_hz),
        main_duty=round(min(max(main_duty, 0.0), 1.0) * counts) / counts,
        flags=out.flags,
        core_outputs={
            "turn_on_compare": out.on_counts,
            "turn_off_compare": out.off_counts,
            "commutation_ticks": out.commutation_ticks,
        },
    )

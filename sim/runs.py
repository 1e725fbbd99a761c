"""One commutation from method to metrics: controller command, plant run, measurement.

The controller sees what the firmware sees: the measured current is the pre-edge
period average (what a PWM-centred ADC sample gives) rounded to ADC codes, the main
duty is rounded to TIM1 counts. Every method of `METHODS` is the generated C core:
the paper's three and the resistance-aware `improved_r` (one constant duty pair per
commutation, ended on the first PWM carrier boundary at which the turn-off current has
reached zero). `improved_r_pp`
(`sim.improved_r_pp`) is no firmware: the same rule re-solved every PWM period along the
EMF ramp in Python, the per-period ideal the constant pair is compared with.
"""

from __future__ import annotations

from dataclasses import dataclass

from codegen.spec_model import Spec
from sim.command import Command
from sim.improved_r_pp import METHOD as IMPROVED_R_PP
from sim.improved_r_pp import improved_r_pp_command
from sim.metrics import CommutationMetrics, commutation_end, measure
from sim.rule_stand_in import RuleStandIn
from sim.scenario import Case, PlantModel, run_case
from sim.sil import CoreLibrary, CoreSet, core_command
from sim.trace import Trace

#: The resistance-aware rule beyond the paper (`controller.method: improved_r`).
IMPROVED_R = "improved_r"
C_METHODS: tuple[str, ...] = ("none", "conventional", "improved", IMPROVED_R)
#: The methods the report simulates everywhere: the firmware's, all through the C core.
METHODS: tuple[str, ...] = C_METHODS
#: Comparison lines that are no firmware (the sweep and the optimum table only).
IDEAL_METHODS: tuple[str, ...] = (IMPROVED_R_PP,)
#: Carrier periods simulated after the commutation, so its end is inside the run.
TAIL_PERIODS = 3


@dataclass(frozen=True)
class Run:
    method: str
    model: PlantModel
    case: Case
    command: Command
    trace: Trace
    metrics: CommutationMetrics


class Controller:
    """Commands for every method at a Hall edge."""

    def __init__(self, spec: Spec, cores: CoreSet) -> None:
        self.spec = spec
        self.cores = cores

    @property
    def period_counts(self) -> int:
        return self.cores.scaling.period_counts

    def measured_current(self, case: Case) -> float:
        per_code = float(self.cores.scaling.amps_per_current_code)
        return round(case.current_a / per_code) * per_code

    def quantised_duty(self, duty: float) -> float:
        return round(min(max(duty, 0.0), 1.0) * self.period_counts) / self.period_counts

    def command(self, method: str, case: Case, main_duty: float) -> Command:
        if method == IMPROVED_R_PP:
            return improved_r_pp_command(
                case,
                self.measured_current(case),
                self.quantised_duty(main_duty),
                self.period_counts,
                float(self.cores.scaling.hall_clock_hz),
            )
        core = self.core_for(method, case)
        return core_command(
            core, self.spec, self.cores.scaling, case, self.measured_current(case), main_duty
        )

    def core_for(self, method: str, case: Case) -> CoreLibrary | RuleStandIn:
        """The method's core; for improved_r on a frozen (flat) EMF the one generated for
        that shape, when the spec's own shape is another."""
        frozen = case.emf_shape == "flat" or case.drive.emf_frozen
        if frozen and method == IMPROVED_R and "flat" in self.cores.shaped:
            return self.cores.shaped["flat"]
        return self.cores.cores[method]

    def flag_names(self, command: Command) -> tuple[str, ...]:
        any_core = next(iter(self.cores.cores.values()))
        return any_core.constants.flag_names(command.flags)


def simulate(case: Case, command: Command, model: PlantModel, end: float | None = None) -> Run:
    """Run to `end`, or (None) just past the end of the commutation."""
    sector = case.sector_time_s
    period = case.drive.pwm_period_s
    if end is not None:
        trace = run_case(case, command, model, min(end, sector))
    else:
        guess = min(sector, command.commutation_time_s + TAIL_PERIODS * period)
        trace = run_case(case, command, model, guess)
        end_s, zero = commutation_end(case, command, trace)
        # The window ends at most two carrier periods after the commutation.
        needed = sector if zero is None else min(sector, end_s + 2.0 * period)
        if needed > guess:
            trace = run_case(case, command, model, needed)
    return Run(command.method, model, case, command, trace, measure(case, command, trace))

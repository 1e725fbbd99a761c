"""The worst case over the carrier phase at the Hall edge (switched plant).

The Hall edge comes at any point of the PWM carrier. The port's update event restarts
the carrier there, so after the edge every run has the same schedule, and the phase
changes one thing: the currents the commutation starts from. Before the edge the
inactive phase carries none and the two conducting phases carry +-m, so they are one
number, m, and everything measured after the edge is a function of it. m is the steady
ripple of the modulated transistor, `phase` into its period: it rises from the valley
where that transistor turns on to the peak where it turns off (edge-aligned: phases 0
and D; centre-aligned: (1 - D) / 2 and (1 + D) / 2) and falls back. Both branches pass
every m from valley to peak, so the worst over the whole period is the worst over the
rising branch alone.

The plant is linear in m while no diode starts or stops conducting, so the deviation is
affine in m and its worst is at an end of the branch, the valley or the peak. An edge
on a carrier boundary (phase 0, the run the paper's figures are compared with) is the
edge-aligned valley: for a commutation that swells it is the best case (a 2-pole
30 000 rpm `improved_r` motor at 27 500 rpm: +2.8 % at phase 0, +19.4 % at the peak,
phase D = 0.24). Where m moves the turn-off current's zero across a carrier boundary
(the measured window gains a period) or the window's signed extreme changes sign
between two periods, the deviation bends inside the branch; so the search also runs
`GRID` - 1 evenly spaced phases inside it and, where one of them is the worst, halves
the step around it `REFINE` times.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

from sim.command import Command
from sim.metrics import CommutationMetrics
from sim.runs import Run, simulate
from sim.scenario import Case, PlantModel

#: Steps the rising branch is divided into (its two ends and GRID - 1 phases inside).
GRID = 2
#: Halvings of the step around an inside phase that is the worst.
REFINE = 3


@dataclass(frozen=True)
class PhaseScan:
    """One commutation over the carrier phase of its Hall edge."""

    #: the run at the worst phase (largest |deviation_worst_pct|)
    worst: Run
    #: its carrier phase, fraction of a PWM period
    phase: float
    #: the run at phase 0 (the edge on a carrier boundary)
    zero: Run
    #: (phase, worst per-period deviation %) of every phase run, ascending phase
    samples: tuple[tuple[float, float], ...]

    @property
    def at_zero(self) -> CommutationMetrics:
        return self.zero.metrics


def rising_branch(case: Case) -> tuple[float, float]:
    """Carrier phases where the modulated transistor turns on (the ripple's valley) and
    off (its peak) before the edge."""
    duty = min(max(case.pre_edge_duty, 0.0), 1.0)
    if case.drive.pwm_alignment == "edge":
        return 0.0, duty
    return (1.0 - duty) / 2.0, (1.0 + duty) / 2.0


def phase_grid(case: Case) -> tuple[float, ...]:
    """The rising branch's ends and `GRID` - 1 evenly spaced phases inside it."""
    low, high = rising_branch(case)
    return tuple(low + (high - low) * k / GRID for k in range(GRID + 1))


def worst_over_phase(case: Case, command: Command, model: PlantModel = "switched") -> PhaseScan:
    """`command` (decided from the case's inputs, which the phase does not change) over
    the carrier phase; the averaged plant has no carrier, so it runs at phase 0 only."""
    runs: dict[float, Run] = {}

    def run_at(phase: float) -> Run:
        phase = round(phase % 1.0, 12)
        if phase not in runs:
            runs[phase] = simulate(replace(case, carrier_phase=phase), command, model)
        return runs[phase]

    def size(phase: float) -> float:
        return abs(run_at(phase).metrics.deviation_worst_pct)

    zero = run_at(0.0)
    if model == "switched":
        grid = phase_grid(case)
        worst = max(grid, key=size)
        low, high = grid[0], grid[-1]
        if low < worst < high:
            step = (high - low) / GRID
            for _ in range(REFINE):
                step /= 2.0
                worst = max((worst - step, worst, worst + step), key=size)
    best = max(runs, key=lambda p: abs(runs[p].metrics.deviation_worst_pct))
    samples = tuple((p, runs[p].metrics.deviation_worst_pct) for p in sorted(runs))
    return PhaseScan(runs[best], best, zero, samples)

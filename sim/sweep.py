"""Everything the report shows, computed once: the speed sweep, the operating points,
Table 4's switching counts, the Ipopt optimum at sampled speeds, and where the cores
clamp the commutation time.

Operating points are run as the paper ran them: a current controller holds the
braking current and the main duty is what it settles at (`sim.current_loop`, a PI at
the PWM rate whose integer output the C core is handed). Below the speed where R I
reaches E the loop saturates at D = 1 and the drive holds only E / R: those points run
at that current and are marked. The spec's operating points also quote a main duty
(the paper's "approximately 42 %" at 4600 rpm): it is run at the current that duty
actually holds (`held_current`), never as a duty step at the edge, and skipped where
that duty cannot brake at all (it would hold a negative current).
"""

from __future__ import annotations

import time
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field

import numpy as np
from tqdm import tqdm

from codegen.audit.transcription import Table4Row, load_transcription
from codegen.spec_model import Spec
from sim.carrier_phase import worst_over_phase
from sim.clamp import ClampScan, clamp_scans
from sim.command import Command
from sim.current_loop import Settled, held_current, settle
from sim.drive import Drive
from sim.emf import TRAPEZOID_120, EmfShape
from sim.metrics import CommutationMetrics
from sim.optimise import Optimum, optimise
from sim.regions import Regions, regions
from sim.runs import IDEAL_METHODS, IMPROVED_R, METHODS, Controller, Run, simulate
from sim.scenario import Case, PlantModel, paper_edge
from sim.sil import prepare_cores
from sim.studies import Studies, shape_study, short_study, study_speeds
from sim.table4 import Table4Study, table4_study

DEFAULT_SHAPE: EmfShape = "spec"
#: About this many sweep points over the spec's speed range (plus the operating points).
SWEEP_POINTS = 19
#: Optimum rows: this many speeds spread over the sweep.
OPTIMUM_POINTS = 10
#: `--quick` (the end-to-end test, a first look at a new motor): this many sweep points,
#: optimum speeds and study speeds, instead of the report's full density.
QUICK_POINTS = 3
STEADY = "steady"
#: The resistance-aware rule's target range on the paper's motor (rpm); the EMF-shape
#: study runs over it (clipped to the spec's range).
TARGET_RANGE_RPM = (500.0, 4600.0)


@dataclass(frozen=True)
class SweepRow:
    speed_rpm: float
    method: str
    model: PlantModel
    emf_shape: EmfShape
    duty_policy: str  # "steady" (the current loop's settled duty) or a main duty, "0.42"
    main_duty: float
    #: The braking current before the edge: the one the main duty holds.
    current_a: float
    #: R I >= E: the loop saturated at D = 1 below the spec's braking current.
    current_limited: bool
    on_duty: float  # first carrier period of the commutation
    off_duty: float
    commanded_time_s: float
    flags: tuple[str, ...]
    #: Switched plant: at the carrier phase of the Hall edge where the worst per-period
    #: deviation is largest (`sim.carrier_phase`); averaged plant: the one run.
    metrics: CommutationMetrics
    #: The C core's inputs ("in." keys) and outputs; empty for the Python ideal.
    core_outputs: dict[str, int] = field(default_factory=dict)
    #: The carrier phase of `metrics` (fraction of a PWM period; 0: on a boundary).
    carrier_phase: float = 0.0
    #: The metrics with the edge on a carrier boundary (phase 0), what the paper's
    #: figures are compared with; None: `metrics` are those (averaged plant).
    phase_zero: CommutationMetrics | None = None

    @property
    def at_phase_zero(self) -> CommutationMetrics:
        return self.metrics if self.phase_zero is None else self.phase_zero


#: The point policy: the spec's quoted main duty at the current it holds.
POINT = "point"
POLICIES: tuple[str, ...] = (STEADY, POINT)


@dataclass(frozen=True)
class OperatingPoint:
    speed_rpm: float
    #: The spec's main duty at this point and the current it holds (A; <= 0: it cannot
    #: brake at this speed, and the "point" runs are absent).
    main_duty: float
    point_current_a: float
    #: The current loop at the spec's braking current ("steady" policy).
    settled: Settled
    #: (method, model, policy) -> run over the figure window.
    runs: dict[tuple[str, str, str], Run]
    #: (method, model, policy) -> metrics over the commutation.
    metrics: dict[tuple[str, str, str], CommutationMetrics]
    #: (method, policy) -> the controller's flags.
    flags: dict[tuple[str, str], tuple[str, ...]]
    #: (method, "switched", policy) -> the carrier phase of the Hall edge at which
    #: `metrics` (the worst over the phase) are measured; `runs` are at phase 0.
    phases: dict[tuple[str, str, str], float] = field(default_factory=dict)
    #: (method, "switched", policy) -> the metrics at phase 0 (the paper's figures).
    phase_zero: dict[tuple[str, str, str], CommutationMetrics] = field(default_factory=dict)

    @property
    def point_brakes(self) -> bool:
        return self.point_current_a > 0.0


@dataclass(frozen=True)
class OptimumRow:
    optimum: Optimum
    emf_shape: EmfShape
    #: Worst per-period deviation on the averaged plant: "optimum" and each method.
    worst_pct: dict[str, float]


@dataclass(frozen=True)
class Results:
    spec: Spec
    drive: Drive
    sweep: tuple[SweepRow, ...]
    operating: tuple[OperatingPoint, ...]
    optima: tuple[OptimumRow, ...]
    table4: tuple[Table4Row, ...]
    clamps: tuple[ClampScan, ...]
    table4_study: Table4Study
    regions: Regions
    studies: Studies
    seconds: dict[str, float] = field(default_factory=dict)
    quick: bool = False  # QUICK_POINTS speeds per study, not the report's density
    #: the duty target improved_r was held to, when the spec's is out of its reach
    rule_duty_target: str | None = None
    #: compared paper methods held to a looser time target (Hall ticks) than the spec's
    time_targets: dict[str, str] = field(default_factory=dict)
    #: why the rule's integer design refuses this motor: its rows are the rule in real
    #: arithmetic (sim/rule_stand_in.py), not a C core
    rule_refused: str | None = None
    #: the EMF shape improved_r's core was generated for, when its firmware refuses the
    #: spec's own (the rule holds the EMF affine over the commutation): the stand-in
    rule_shape_fallback: str | None = None

    def rows(self, **match: object) -> list[SweepRow]:
        return [r for r in self.sweep if all(getattr(r, k) == v for k, v in match.items())]


def nice_step(span: float, points: int) -> float:
    """The 1-2-2.5-5 x 10^k step nearest (in ratio) to dividing `span` into `points`."""
    raw = span / max(points, 1)
    decade = 10.0 ** np.floor(np.log10(raw))
    candidates = [f * decade for f in (1.0, 2.0, 2.5, 5.0, 10.0)]
    return float(min(candidates, key=lambda step: abs(np.log(step / raw))))


def sweep_speeds(
    drive: Drive, extra: Iterable[float], points: int = SWEEP_POINTS
) -> tuple[float, ...]:
    """The spec's whole speed range: its ends, the multiples of a round step between
    them, and the `extra` speeds (operating points) inside it."""
    low, high = drive.speed_min_rpm, drive.speed_max_rpm
    step = nice_step(high - low, points - 1)
    first = np.ceil(low / step) * step
    grid = {round(low, 6), round(high, 6)}
    grid |= {round(float(v), 6) for v in np.arange(first, high - 1e-9, step) if v > low + 1e-9}
    grid |= {round(float(s), 6) for s in extra if low <= s <= high}
    return tuple(sorted(grid))


def optimum_speeds(speeds: tuple[float, ...], points: int = OPTIMUM_POINTS) -> tuple[float, ...]:
    """About `points` speeds of the sweep, spread evenly, both ends included."""
    picks = np.linspace(0, len(speeds) - 1, min(points, len(speeds)))
    return tuple(sorted({speeds[int(np.rint(k))] for k in picks}))


@dataclass(frozen=True)
class _Job:
    speed_rpm: float
    method: str
    model: PlantModel
    emf_shape: EmfShape
    duty_policy: str
    main_duty: float
    current_a: float
    limited: bool

    @property
    def judged(self) -> bool:
        """A run the report judges (a verdict against a band or another method): every
        firmware method on the spec's EMF and `improved_r` on the flat one, switched
        plant. These are taken at their worst carrier phase; the comparison lines (the
        Python ideal, the paper methods on the flat EMF, the fixed duties) at phase 0."""
        if self.model != "switched" or self.duty_policy != STEADY:
            return False
        return self.method in METHODS and (
            self.emf_shape == DEFAULT_SHAPE or self.method == IMPROVED_R
        )


def _point_duties(spec: Spec) -> tuple[float, ...]:
    return tuple(sorted({float(p.main_duty) for p in spec.operating_points}))


def _jobs(
    drive: Drive, speeds: tuple[float, ...], duties: tuple[float, ...], counts: int, top_a: float
) -> list[_Job]:
    jobs: list[_Job] = []
    for speed in speeds:
        loop = settle(drive, speed, drive.braking_current_a, counts)
        for method in (*METHODS, *IDEAL_METHODS):
            for model, shape in (("switched", DEFAULT_SHAPE), ("averaged", DEFAULT_SHAPE)):
                jobs.append(
                    _Job(
                        speed, method, model, shape, STEADY, loop.duty, loop.current_a, loop.limited
                    )
                )
            flat_models = ("switched", "averaged") if method == IMPROVED_R else ("switched",)
            for model in flat_models:
                jobs.append(
                    _Job(
                        speed,
                        method,
                        model,
                        "flat",
                        STEADY,
                        loop.duty,
                        loop.current_a,
                        loop.limited,
                    )
                )
        for duty in duties:
            current = held_current(drive, speed, duty)
            if 0.0 < current <= top_a:
                jobs.append(
                    _Job(
                        speed,
                        "conventional",
                        "switched",
                        DEFAULT_SHAPE,
                        f"{duty:g}",
                        duty,
                        current,
                        False,
                    )
                )
    return jobs


def _row(controller: Controller, drive: Drive, job: _Job) -> SweepRow:
    case = Case(drive, paper_edge(), job.speed_rpm, job.current_a, job.emf_shape)
    command = controller.command(job.method, case, job.main_duty)
    phase, phase_zero = 0.0, None
    if job.judged:
        scan = worst_over_phase(case, command, job.model)
        run, phase, phase_zero = scan.worst, scan.phase, scan.at_zero
    else:
        run = simulate(case, command, job.model)
    return SweepRow(
        speed_rpm=job.speed_rpm,
        method=job.method,
        model=job.model,
        emf_shape=job.emf_shape,
        duty_policy=job.duty_policy,
        main_duty=command.main_duty,
        current_a=job.current_a,
        current_limited=job.limited,
        on_duty=command.on_duty(0),
        off_duty=command.off_duty(0),
        commanded_time_s=command.commutation_time_s,
        flags=controller.flag_names(command),
        metrics=run.metrics,
        core_outputs=command.core_outputs,
        carrier_phase=phase,
        phase_zero=phase_zero,
    )


#: Methods with a phase-current figure at the spec's main duty (Fig. 13 is conventional).
POINT_FIGURE_METHODS = ("none", "conventional")


def figure_keys(point: OperatingPoint) -> list[tuple[str, str]]:
    """(method, policy) pairs with a phase-current figure at this operating point."""
    keys = [(method, STEADY) for method in METHODS]
    if point.point_brakes:
        keys += [(method, POINT) for method in POINT_FIGURE_METHODS]
    return keys


def figure_end(case: Case, run: Run) -> float:
    """Figure window: the commutation twice over, at least 35 % of the sector."""
    fraction = run.metrics.commutation_fraction or 1.0
    span = max(fraction, run.metrics.commanded_fraction)
    return min(1.0, max(0.35, 2.0 * span)) * case.sector_time_s


def operating_point(
    controller: Controller, drive: Drive, speed: float, duty: float
) -> OperatingPoint:
    """Every method at the settled duty, and at the spec's duty with the current it holds."""
    runs: dict[tuple[str, str, str], Run] = {}
    metrics: dict[tuple[str, str, str], CommutationMetrics] = {}
    flags: dict[tuple[str, str], tuple[str, ...]] = {}
    phases: dict[tuple[str, str, str], float] = {}
    phase_zero: dict[tuple[str, str, str], CommutationMetrics] = {}
    loop = settle(drive, speed, drive.braking_current_a, controller.period_counts)
    point_current = held_current(drive, speed, duty)
    settings = [(STEADY, loop.duty, loop.current_a)]
    if point_current > 0.0:
        settings.append((POINT, duty, point_current))
    for policy, main, current in settings:
        case = Case(drive, paper_edge(), speed, current, DEFAULT_SHAPE)
        for method in METHODS:
            command = controller.command(method, case, main)
            flags[(method, policy)] = controller.flag_names(command)
            for model in ("switched", "averaged"):
                key = (method, model, policy)
                scan = worst_over_phase(case, command, model)
                metrics[key] = scan.worst.metrics
                if model == "switched":
                    phases[key] = scan.phase
                    phase_zero[key] = scan.at_zero
                # the figure: the edge on a carrier boundary, as the paper's are compared
                runs[key] = simulate(case, command, model, figure_end(case, scan.zero))
    return OperatingPoint(
        speed, duty, point_current, loop, runs, metrics, flags, phases, phase_zero
    )


def _optimum_row(
    controller: Controller, drive: Drive, speed: float, shape: EmfShape, loop: Settled
) -> OptimumRow:
    case = Case(drive, paper_edge(), speed, loop.current_a, shape)
    improved = controller.command("improved", case, loop.duty)
    optimum = optimise(case, improved.on_duty(0), improved.off_duty(0), improved.commutation_time_s)
    worst: dict[str, float] = {}
    hall = float(controller.cores.scaling.hall_clock_hz)
    best = Command(
        method="optimum",
        turn_on_switch=improved.turn_on_switch,
        turn_off_switch=improved.turn_off_switch,
        on_duties=(optimum.on_duty,),
        off_duties=(optimum.off_duty,),
        commutation_time_s=round(optimum.commutation_time_s * hall) / hall,
        main_duty=improved.main_duty,
    )
    worst["optimum"] = simulate(case, best, "averaged").metrics.deviation_worst_pct
    for method in (*METHODS, *IDEAL_METHODS):
        command = controller.command(method, case, loop.duty)
        worst[method] = simulate(case, command, "averaged").metrics.deviation_worst_pct
    return OptimumRow(optimum, shape, worst)


def optimum_shapes(drive: Drive) -> tuple[EmfShape, ...]:
    """The optimiser integrates one affine EMF over the sector: the spec's shape only
    when it is the 120 deg trapezoid (one ramp from the edge), and always the flat one."""
    trapezoid = drive.emf_points == TRAPEZOID_120
    return (DEFAULT_SHAPE, "flat") if trapezoid else ("flat",)


def run_all(spec: Spec, progress: bool = True, quick: bool = False) -> Results:
    """The whole simulation of one spec (the `python -m sim` workload). `quick` runs
    every study at QUICK_POINTS speeds (the report says so)."""
    seconds: dict[str, float] = {}
    clock = time.perf_counter()
    drive = Drive.from_spec(spec)
    cores = prepare_cores(spec, METHODS)
    controller = Controller(spec, cores)
    seconds["cores"] = time.perf_counter() - clock

    operating_speeds = [float(p.speed_rpm) for p in spec.operating_points]
    speeds = sweep_speeds(drive, operating_speeds, QUICK_POINTS if quick else SWEEP_POINTS)
    top_a = float(cores.scaling.amps_per_current_code) * (
        2**spec.adc.bits - 1 - cores.scaling.current_offset_code
    )
    jobs = _jobs(drive, speeds, _point_duties(spec), controller.period_counts, top_a)
    optimum_jobs = [
        (speed, shape)
        for shape in optimum_shapes(drive)
        for speed in optimum_speeds(speeds, QUICK_POINTS if quick else OPTIMUM_POINTS)
    ]
    total = len(jobs) + len(spec.operating_points) + len(optimum_jobs)
    bar = tqdm(total=total, desc=f"sim {spec.name}", unit="run", disable=not progress)

    def timed(name: str, work: Callable[[], object]) -> object:
        start = time.perf_counter()
        out = work()
        seconds[name] = time.perf_counter() - start
        return out

    def do_sweep() -> list[SweepRow]:
        rows = []
        for job in jobs:
            rows.append(_row(controller, drive, job))
            bar.update()
        return rows

    def do_operating() -> list[OperatingPoint]:
        points = []
        for point in spec.operating_points:
            points.append(
                operating_point(controller, drive, float(point.speed_rpm), float(point.main_duty))
            )
            bar.update()
        return points

    def do_optima() -> list[OptimumRow]:
        rows = []
        for speed, shape in optimum_jobs:
            loop = settle(drive, speed, drive.braking_current_a, controller.period_counts)
            rows.append(_optimum_row(controller, drive, speed, shape, loop))
            bar.update()
        return rows

    sweep = timed("sweep", do_sweep)
    operating = timed("operating points", do_operating)
    optima = timed("optimiser", do_optima)
    clamps = timed("clamp scan", lambda: clamp_scans(controller, drive, spec))
    table4 = load_transcription().table4
    counts = timed("table 4", lambda: table4_study(controller, drive, table4))
    found = regions(drive)
    target_low, target_high = TARGET_RANGE_RPM
    shape_speeds = study_speeds(drive, target_low, target_high)
    if quick:
        shape_speeds = optimum_speeds(shape_speeds, QUICK_POINTS)
    shapes = timed("EMF shapes", lambda: shape_study(controller, drive, shape_speeds))
    short = timed("short commutations", lambda: short_study(controller, drive, found))
    bar.close()
    seconds["total"] = time.perf_counter() - clock
    return Results(
        spec=spec,
        drive=drive,
        sweep=tuple(sweep),  # type: ignore[arg-type]
        operating=tuple(operating),  # type: ignore[arg-type]
        optima=tuple(optima),  # type: ignore[arg-type]
        table4=table4,
        clamps=clamps,  # type: ignore[arg-type]
        table4_study=counts,  # type: ignore[arg-type]
        regions=found,
        studies=Studies(shapes, shape_speeds, short),  # type: ignore[arg-type]
        seconds=seconds,
        quick=quick,
        rule_duty_target=cores.rule_duty_target,
        time_targets=dict(cores.time_targets),
        rule_refused=cores.rule_refused,
        rule_shape_fallback=cores.shape_fallback,
    )

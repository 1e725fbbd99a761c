"""Everything the report shows, computed once: the speed sweep, the operating points,
Table 4's switching counts, the Ipopt optimum at sampled speeds, and where the cores
clamp the commutation time.

Main duty: in the sweep the main duty is the one that holds the braking current
between commutations (`Drive.steady_duty`, what a settled current loop outputs). The
spec's operating points carry their own main duty (the paper's "approximately 42 %"
at 4600 rpm), which the operating-point figures use, and the conventional method is
also swept at each such fixed duty to show where its control fail area lies.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field

import numpy as np
from tqdm import tqdm

from codegen.audit.transcription import Table4Row, load_transcription
from codegen.spec_model import Spec
from sim.clamp import ClampScan, clamp_scans
from sim.command import Command
from sim.drive import Drive
from sim.emf import EmfShape
from sim.metrics import CommutationMetrics
from sim.optimise import Optimum, optimise
from sim.runs import IDEAL_METHODS, METHODS, Controller, Run, simulate
from sim.scenario import Case, PlantModel, paper_edge
from sim.sil import prepare_cores

DEFAULT_SHAPE: EmfShape = "spec"
SWEEP_LOW_RPM = 500.0
SWEEP_HIGH_RPM = 5000.0
SWEEP_STEP_RPM = 250.0
OPTIMUM_SPEEDS_RPM = (500.0, 1000.0, 1500.0, 2000.0, 2500.0, 3000.0, 3500.0, 4000.0, 4600.0, 5000.0)
STEADY = "steady"


@dataclass(frozen=True)
class SweepRow:
    speed_rpm: float
    method: str
    model: PlantModel
    emf_shape: EmfShape
    duty_policy: str  # "steady" or the fixed main duty, e.g. "0.42"
    main_duty: float
    on_duty: float  # first carrier period of the commutation
    off_duty: float
    commanded_time_s: float
    flags: tuple[str, ...]
    metrics: CommutationMetrics
    #: The C core's inputs ("in." keys) and outputs; empty for the Python ideal.
    core_outputs: dict[str, int] = field(default_factory=dict)


#: Operating-point runs: at the steady-state main duty every method; at the spec's
#: main duty the methods whose commutation duties depend on it.
POINT_POLICIES: dict[str, tuple[str, ...]] = {
    STEADY: METHODS,
    "point": ("none", "conventional"),
}


@dataclass(frozen=True)
class OperatingPoint:
    speed_rpm: float
    #: The spec's main duty at this point ("point" policy).
    main_duty: float
    #: (method, model, policy) -> run over the figure window.
    runs: dict[tuple[str, str, str], Run]
    #: (method, model, policy) -> metrics over the commutation.
    metrics: dict[tuple[str, str, str], CommutationMetrics]
    #: (method, policy) -> the controller's flags.
    flags: dict[tuple[str, str], tuple[str, ...]]


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
    seconds: dict[str, float] = field(default_factory=dict)

    def rows(self, **match: object) -> list[SweepRow]:
        return [r for r in self.sweep if all(getattr(r, k) == v for k, v in match.items())]


def sweep_speeds(drive: Drive, extra: Iterable[float]) -> tuple[float, ...]:
    low = max(SWEEP_LOW_RPM, drive.speed_min_rpm)
    high = min(max(SWEEP_HIGH_RPM, low), drive.speed_max_rpm)
    grid = set(np.arange(low, high + 1e-9, SWEEP_STEP_RPM).round(6).tolist())
    grid |= {s for s in extra if low <= s <= high}
    return tuple(sorted(grid))


@dataclass(frozen=True)
class _Job:
    speed_rpm: float
    method: str
    model: PlantModel
    emf_shape: EmfShape
    duty_policy: str


def _jobs(speeds: tuple[float, ...], fixed_duties: tuple[float, ...]) -> list[_Job]:
    jobs: list[_Job] = []
    for speed in speeds:
        for method in (*METHODS, *IDEAL_METHODS):
            jobs.append(_Job(speed, method, "switched", DEFAULT_SHAPE, STEADY))
            jobs.append(_Job(speed, method, "averaged", DEFAULT_SHAPE, STEADY))
            jobs.append(_Job(speed, method, "switched", "flat", STEADY))
        for duty in fixed_duties:
            jobs.append(_Job(speed, "conventional", "switched", DEFAULT_SHAPE, f"{duty:g}"))
    return jobs


def _row(controller: Controller, drive: Drive, job: _Job) -> SweepRow:
    case = Case(drive, paper_edge(), job.speed_rpm, drive.braking_current_a, job.emf_shape)
    main = case.pre_edge_duty if job.duty_policy == STEADY else float(job.duty_policy)
    command = controller.command(job.method, case, main)
    run = simulate(case, command, job.model)
    return SweepRow(
        speed_rpm=job.speed_rpm,
        method=job.method,
        model=job.model,
        emf_shape=job.emf_shape,
        duty_policy=job.duty_policy,
        main_duty=command.main_duty,
        on_duty=command.on_duty(0),
        off_duty=command.off_duty(0),
        commanded_time_s=command.commutation_time_s,
        flags=controller.flag_names(command),
        metrics=run.metrics,
        core_outputs=command.core_outputs,
    )


def figure_end(case: Case, run: Run) -> float:
    """Figure window: the commutation twice over, at least 35 % of the sector."""
    fraction = run.metrics.commutation_fraction or 1.0
    span = max(fraction, run.metrics.commanded_fraction)
    return min(1.0, max(0.35, 2.0 * span)) * case.sector_time_s


def operating_point(
    controller: Controller, drive: Drive, speed: float, duty: float
) -> OperatingPoint:
    runs: dict[tuple[str, str, str], Run] = {}
    metrics: dict[tuple[str, str, str], CommutationMetrics] = {}
    flags: dict[tuple[str, str], tuple[str, ...]] = {}
    case = Case(drive, paper_edge(), speed, drive.braking_current_a, DEFAULT_SHAPE)
    for policy, methods in POINT_POLICIES.items():
        main = case.pre_edge_duty if policy == STEADY else duty
        for method in methods:
            command = controller.command(method, case, main)
            flags[(method, policy)] = controller.flag_names(command)
            for model in ("switched", "averaged"):
                measured = simulate(case, command, model)
                metrics[(method, model, policy)] = measured.metrics
                runs[(method, model, policy)] = simulate(
                    case, command, model, figure_end(case, measured)
                )
    return OperatingPoint(speed, duty, runs, metrics, flags)


def _optimum_row(controller: Controller, drive: Drive, speed: float, shape: EmfShape) -> OptimumRow:
    case = Case(drive, paper_edge(), speed, drive.braking_current_a, shape)
    improved = controller.command("improved", case, case.pre_edge_duty)
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
        command = controller.command(method, case, case.pre_edge_duty)
        worst[method] = simulate(case, command, "averaged").metrics.deviation_worst_pct
    return OptimumRow(optimum, shape, worst)


def run_all(spec: Spec, progress: bool = True) -> Results:
    """The whole simulation of one spec (the `python -m sim` workload)."""
    seconds: dict[str, float] = {}
    clock = time.perf_counter()
    drive = Drive.from_spec(spec)
    cores = prepare_cores(spec, METHODS)
    controller = Controller(spec, cores)
    seconds["cores"] = time.perf_counter() - clock

    operating_speeds = [float(p.speed_rpm) for p in spec.operating_points]
    fixed_duties = tuple(sorted({float(p.main_duty) for p in spec.operating_points}))
    speeds = sweep_speeds(drive, operating_speeds)
    jobs = _jobs(speeds, fixed_duties)
    optimum_jobs = [
        (speed, shape)
        for shape in (DEFAULT_SHAPE, "flat")
        for speed in OPTIMUM_SPEEDS_RPM
        if speeds[0] <= speed <= speeds[-1]
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
            rows.append(_optimum_row(controller, drive, speed, shape))
            bar.update()
        return rows

    sweep = timed("sweep", do_sweep)
    operating = timed("operating points", do_operating)
    optima = timed("optimiser", do_optima)
    clamps = timed("clamp scan", lambda: clamp_scans(controller, drive, spec))
    bar.close()
    seconds["total"] = time.perf_counter() - clock
    return Results(
        spec=spec,
        drive=drive,
        sweep=tuple(sweep),  # type: ignore[arg-type]
        operating=tuple(operating),  # type: ignore[arg-type]
        optima=tuple(optima),  # type: ignore[arg-type]
        table4=load_transcription().table4,
        clamps=clamps,  # type: ignore[arg-type]
        seconds=seconds,
    )

"""`python -m sim.robustness SPEC`: the firmware core against a drive that is not the spec.

Motor parameters drift: the winding's R rises by up to 40 % hot, L and k_e sit
10-20 % from the datasheet, the bus moves. The firmware keeps the nominal constants
it was generated with; the plant gets the sampled ones. For each sample, speed and
method this runs what `python -m sim` runs for one commutation: the current loop
settles on the sampled drive (`sim.current_loop`), the generated C core is called
through ctypes with the integers the port would read (the sampled bus in ADC codes,
the Hall period, the measured current, the settled duty), and the plant (averaged
by default, switched on request) measures the deviation of the non-commutating
current over the physical window (`sim.metrics`).

Sampling: a Latin hypercube over the spec's `tolerances` (uniform in each relative
range; the spec's defaults below when the section is absent), seeded, plus the carrier
phase at the Hall edge (uniform over a period) for the switched plant, where the
port's carrier restart makes it matter. Distribution of the worst per-period
deviation per method and speed (median, p95 of |deviation|, worst), and the
sensitivities: Spearman rank correlation of the deviation with each parameter.

Runs on Dask: a `dask.distributed.LocalCluster` of `--workers` processes, or an
existing scheduler (`--scheduler tcp://host:8786`) whose workers see the same checkout
and build/ folder (the compiled cores are loaded from there by path).

Exit status: 0 success, 2 bad spec or arguments, 3 the generator refuses the spec (its
own method's design, as `generate SPEC` says), 4 the cores cannot be built.
"""

from __future__ import annotations

import argparse
import sys
import time
from collections.abc import Sequence
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from codegen.errors import ExitCode, SpecError
from codegen.publish import os_error_line, require_folder_path
from codegen.shown import shown
from codegen.spec_loader import load_spec
from codegen.spec_model import Spec, Tolerances
from sim.drive import Drive
from sim.robustness_args import add_campaign_arguments

EXIT_SPEC = 2
EXIT_REFUSED = 3
EXIT_SIL = 4
REPORT_NAME = "ROBUSTNESS.md"
#: Relative (low, high) used when the spec declares no `tolerances` section.
DEFAULT_TOLERANCES = {
    "phase_resistance": (-0.10, 0.40),
    "phase_inductance": (-0.15, 0.15),
    "back_emf_constant": (-0.10, 0.10),
    "bus_voltage": None,  # the inverter's [bus_voltage_min, bus_voltage_max]
}
PARAMETERS = ("phase_resistance", "phase_inductance", "back_emf_constant", "bus_voltage")
CARRIER_PHASE = "carrier_phase"


@dataclass(frozen=True)
class Campaign:
    """What to run: relative ranges, the sample matrix and the speeds."""

    spec_path: str
    ranges: dict[str, tuple[float, float]]
    declared: bool  # the ranges come from the spec's `tolerances` section
    samples: np.ndarray  # (N, P) relative deviations, P = len(parameters)
    parameters: tuple[str, ...]
    speeds_rpm: tuple[float, ...]
    methods: tuple[str, ...]
    plant: str  # "averaged" or "switched"
    seed: int


def tolerance_ranges(spec: Spec) -> tuple[dict[str, tuple[float, float]], bool]:
    """Relative (low, high) per parameter, and whether the spec declared them."""
    declared: Tolerances | None = spec.tolerances
    if declared is not None:
        return {name: tuple(float(v) for v in getattr(declared, name)) for name in PARAMETERS}, True  # type: ignore[misc]
    nominal = float(spec.inverter.bus_voltage_nominal_v)
    out: dict[str, tuple[float, float]] = {}
    for name in PARAMETERS:
        default = DEFAULT_TOLERANCES[name]
        if default is None:
            default = (
                float(spec.inverter.bus_voltage_min_v) / nominal - 1.0,
                float(spec.inverter.bus_voltage_max_v) / nominal - 1.0,
            )
        out[name] = default
    return out, False


def latin_hypercube(count: int, dimensions: int, seed: int) -> np.ndarray:
    """(count, dimensions) points in [0, 1): one in each of `count` strata per axis."""
    rng = np.random.default_rng(seed)
    strata = np.stack([rng.permutation(count) for _ in range(dimensions)], axis=1)
    return (strata + rng.random((count, dimensions))) / count


def campaign_speeds(drive: Drive, count: int) -> tuple[float, ...]:
    """`count` speeds evenly over the spec's range, whole rpm, both ends inside it."""
    low, high = drive.speed_min_rpm, drive.speed_max_rpm
    speeds = np.linspace(low, high, count)
    return tuple(float(min(max(round(s), low), high)) for s in speeds)


def build_campaign(
    spec: Spec, samples: int, speeds: int, methods: tuple[str, ...], plant: str, seed: int
) -> Campaign:
    ranges, declared = tolerance_ranges(spec)
    parameters = PARAMETERS + ((CARRIER_PHASE,) if plant == "switched" else ())
    unit = latin_hypercube(samples, len(parameters), seed)
    matrix = np.empty_like(unit)
    for k, name in enumerate(parameters):
        low, high = ranges[name] if name != CARRIER_PHASE else (0.0, 1.0)
        matrix[:, k] = low + (high - low) * unit[:, k]
    return Campaign(
        spec_path=spec.source_path,
        ranges=ranges,
        declared=declared,
        samples=matrix,
        parameters=parameters,
        speeds_rpm=campaign_speeds(Drive.from_spec(spec), speeds),
        methods=methods,
        plant=plant,
        seed=seed,
    )


@dataclass(frozen=True)
class CoreHandle:
    """Enough to load a compiled core in another process: library path and constants."""

    method: str
    library: str
    constants: object  # sim.sil.CoreConstants


#: Per worker process: (spec path, library paths) -> (spec, controller).
_CONTROLLERS: dict[tuple[str, tuple[str, ...]], tuple[Spec, object]] = {}


def _worker_controller(spec_path: str, handles: tuple[CoreHandle, ...], scaling: object):  # type: ignore[no-untyped-def]
    """The worker's controller: cores loaded by path, once per process."""
    from sim.runs import Controller
    from sim.sil import CoreLibrary, CoreSet

    key = (spec_path, tuple(h.library for h in handles))
    if key not in _CONTROLLERS:
        spec = load_spec(spec_path)
        cores = {h.method: CoreLibrary(Path(h.library), h.constants, h.method) for h in handles}  # type: ignore[arg-type]
        core_set = CoreSet(spec, cores)
        core_set.__dict__["scaling"] = scaling  # computed once by the client
        _CONTROLLERS[key] = (spec, Controller(spec, core_set))
    return _CONTROLLERS[key]


def perturbed(drive: Drive, parameters: tuple[str, ...], row: np.ndarray) -> tuple[Drive, float]:
    """The sampled drive, and the carrier phase (0 when not sampled)."""
    values = dict(zip(parameters, row, strict=True))
    return (
        replace(
            drive,
            resistance_ohm=drive.resistance_ohm * (1.0 + values["phase_resistance"]),
            inductance_h=drive.inductance_h * (1.0 + values["phase_inductance"]),
            emf_v_per_rpm=drive.emf_v_per_rpm * (1.0 + values["back_emf_constant"]),
            bus_voltage_v=drive.bus_voltage_v * (1.0 + values["bus_voltage"]),
        ),
        float(values.get(CARRIER_PHASE, 0.0)),
    )


def evaluate_chunk(
    spec_path: str,
    handles: tuple[CoreHandle, ...],
    scaling: object,
    parameters: tuple[str, ...],
    rows: np.ndarray,
    speeds: tuple[float, ...],
    methods: tuple[str, ...],
    plant: str,
) -> np.ndarray:
    """(len(rows), len(speeds), len(methods), 3): worst period deviation %, peak %,
    1 where the current loop could not hold the braking current (R I >= E)."""
    from sim.current_loop import settle
    from sim.runs import simulate
    from sim.scenario import Case, paper_edge

    spec, controller = _worker_controller(spec_path, handles, scaling)
    nominal = Drive.from_spec(spec)
    out = np.empty((len(rows), len(speeds), len(methods), 3))
    for i, row in enumerate(rows):
        drive, phase = perturbed(nominal, parameters, row)
        for j, speed in enumerate(speeds):
            loop = settle(drive, speed, nominal.braking_current_a, controller.period_counts)
            case = Case(drive, paper_edge(), speed, loop.current_a, "spec", phase)
            for k, method in enumerate(methods):
                command = controller.command(method, case, loop.duty)
                metrics = simulate(case, command, plant).metrics  # type: ignore[arg-type]
                out[i, j, k] = (
                    metrics.deviation_worst_pct,
                    metrics.deviation_peak_pct,
                    float(loop.limited),
                )
    return out


@dataclass(frozen=True)
class CampaignResult:
    campaign: Campaign
    #: (N, S, M, 3) as `evaluate_chunk` returns, all samples.
    values: np.ndarray
    seconds: float
    workers: int


def run_campaign(
    spec: Spec,
    campaign: Campaign,
    scheduler: str | None,
    workers: int,
    chunk: int,
    progress: bool,
) -> CampaignResult:
    from dask.distributed import Client, LocalCluster, as_completed
    from tqdm import tqdm

    from sim.sil import SilError, prepare_cores

    core_set = prepare_cores(spec, campaign.methods)
    left_out = [m for m in campaign.methods if core_set.cores[m].path is None]
    if left_out:  # the rule in real arithmetic, where its integer design refuses the motor
        kept = tuple(m for m in campaign.methods if m not in left_out)
        if not kept:
            raise SilError(
                f"--methods {','.join(left_out)}: no C core on this motor ({core_set.rule_refused})"
            )
        print(
            f"robustness: {', '.join(left_out)} left out: no C core on this motor"
            f" ({core_set.rule_refused})",
            file=sys.stderr,
        )
        campaign = replace(campaign, methods=kept)
    handles = tuple(
        CoreHandle(m, str(core_set.cores[m].path), core_set.cores[m].constants)
        for m in campaign.methods
    )
    scaling = core_set.scaling
    start = time.perf_counter()
    cluster = None
    if scheduler:
        client = Client(scheduler)
    else:
        cluster = LocalCluster(
            n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=None
        )
        client = Client(cluster)
    try:
        blocks = [
            (k, campaign.samples[k : k + chunk]) for k in range(0, len(campaign.samples), chunk)
        ]
        futures = {
            client.submit(
                evaluate_chunk,
                campaign.spec_path,
                handles,
                scaling,
                campaign.parameters,
                rows,
                campaign.speeds_rpm,
                campaign.methods,
                campaign.plant,
                pure=False,
            ): k
            for k, rows in blocks
        }
        total = len(campaign.samples) * len(campaign.speeds_rpm) * len(campaign.methods)
        bar = tqdm(total=total, desc=f"robustness {spec.name}", unit="run", disable=not progress)
        pieces: dict[int, np.ndarray] = {}
        for future in as_completed(futures):
            block = future.result()
            pieces[futures[future]] = block
            bar.update(block.shape[0] * block.shape[1] * block.shape[2])
        bar.close()
        used = len(client.scheduler_info().get("workers", {})) or workers
    finally:
        client.close()
        if cluster is not None:
            cluster.close()
    values = np.concatenate([pieces[k] for k in sorted(pieces)], axis=0)
    return CampaignResult(campaign, values, time.perf_counter() - start, used)


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(
        prog="python -m sim.robustness", description=__doc__.splitlines()[0]
    )
    parser.add_argument("spec", help="motor spec YAML, e.g. spec/paper_motor.yaml")
    add_campaign_arguments(parser)
    parser.add_argument(
        "-o",
        "--output",
        help="output folder (default: generated/<spec name>/robustness in the current folder)",
    )
    parser.add_argument("--no-progress", action="store_true", help="no progress bar")
    return run(parser.parse_args(argv))


def run(args: argparse.Namespace) -> int:
    """The campaign for parsed arguments (`add_campaign_arguments` plus spec, output
    and no_progress), its report written; the exit status."""
    from sim.robustness_report import write_report
    from sim.runs import METHODS
    from sim.sil import SilError, SpecRefusedError

    methods = tuple(m for m in args.methods.split(",") if m)
    bad = [m for m in methods if m not in METHODS]
    if bad or not methods:
        print(f"error: --methods {args.methods!r}: allowed {', '.join(METHODS)}", file=sys.stderr)
        return EXIT_SPEC
    try:
        spec = load_spec(args.spec)
        out = Path(args.output) if args.output else Path("generated") / spec.name / "robustness"
        require_folder_path(out)  # before the campaign, not after it
        campaign = build_campaign(spec, args.samples, args.speeds, methods, args.plant, args.seed)
        result = run_campaign(
            spec, campaign, args.scheduler, args.workers, args.chunk, not args.no_progress
        )
        names = write_report(spec, result, out)
    except SpecError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return EXIT_SPEC
    except SpecRefusedError as exc:  # what `generate SPEC` says of it
        for line in str(exc).splitlines():
            print(f"error: {line}", file=sys.stderr)
        return EXIT_REFUSED
    except SilError as exc:
        print(f"software in the loop failed: {exc}", file=sys.stderr)
        return EXIT_SIL
    except OSError as exc:  # the output folder
        print(os_error_line(exc), file=sys.stderr)
        return int(ExitCode.ENVIRONMENT)
    runs = result.values.shape[0] * result.values.shape[1] * result.values.shape[2]
    print(
        f"robustness: {runs} runs ({args.samples} samples x {len(campaign.speeds_rpm)} speeds x"
        f" {len(result.campaign.methods)} methods, {args.plant} plant) on {result.workers} workers in"
        f" {result.seconds:.1f} s -> {shown(out)}: {', '.join(names)}"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())

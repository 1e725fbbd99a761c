"""`verify SPEC`: the generated C core against the exact symbolic model.

Builds the core for the host, runs it over the exhaustive, random and boundary sets,
compares each point with codegen.reference (the derivation's expressions, exactly or in
float64 far below one LSB) and with the generated bit-exact Python twin, and writes a
terminal table, a JSON report and a PNG of the error against speed beside the
generated code.
"""

from __future__ import annotations

import functools
import importlib.util
import json
import sys
import time
from dataclasses import asdict, dataclass
from pathlib import Path
from types import ModuleType

import numpy as np
from tqdm import tqdm

from codegen.derivation import derive
from codegen.fixedpoint.design import FixedPointDesign
from codegen.fixedpoint.scaling import Scaling, scaling
from codegen.generate import fixed_point_design
from codegen.improved_r_rule.context import rule_design
from codegen.improved_r_rule.design import RuleDesign
from codegen.reference import build_model
from codegen.render import project_relative
from codegen.spec_loader import load_spec
from codegen.spec_model import Spec
from verify import points
from verify.check import Evaluated, OutputCheck, check_set, new_checks
from verify.check_rule import check_rule_set, new_rule_checks
from verify.host_core import OUTPUT_DTYPE, build_host_core

DEFAULT_RANDOM_POINTS = 20_000
SHORT = {
    "hall_code": "hall",
    "previous_hall_code": "prev",
    "hall_period_ticks": "T",
    "bus_voltage_adc": "B",
    "phase_current_adc": "I",
    "main_duty_counts": "M",
}


@dataclass(frozen=True)
class DesignBounds:
    """The generator's headline bounds, for the report and its plot."""

    duty_counts: float
    time_ticks: float
    summary: dict[str, float | int | str]


def design_bounds(spec: Spec, fx: FixedPointDesign, rule: RuleDesign | None) -> DesignBounds:
    if rule is not None:
        target = float(spec.accuracy.commutation_time_ticks)
        return DesignBounds(
            rule.duty_bound,
            target,
            {
                "method": "improved_r",
                "counts_frac_bits": rule.rule.counts_frac_bits,
                "bisection_steps": rule.rule.steps,
                "table_rows": rule.rule.table.entries,
                "duty_error_bound_counts": rule.duty_bound,
                "time_target_ticks": target,
                "time_bound_over_allowance": rule.time_ratio,
            },
        )
    return DesignBounds(
        float(fx.duty_error_bound_counts),
        float(fx.time_error_bound_ticks),
        {
            "method": spec.controller.method,
            "x_frac_bits": fx.x_frac_bits,
            "duty_error_bound_counts": float(fx.duty_error_bound_counts),
            "time_error_bound_ticks": float(fx.time_error_bound_ticks),
            "time_bound_min_w_counts": float(fx.time_bound_min_w_counts),
        },
    )


@dataclass(frozen=True)
class VerifyResult:
    spec: str
    generated: str
    seed: int
    sets: dict[str, int]
    checks: dict[str, OutputCheck]
    seconds: float

    @property
    def passed(self) -> bool:
        return all(c.verdict == "PASS" for c in self.checks.values())


def load_twin(generated: Path) -> ModuleType:
    path = generated / "python" / "bldc_fixed.py"
    spec = importlib.util.spec_from_file_location(f"bldc_fixed_{abs(hash(path))}", path)
    if spec is None or spec.loader is None:
        raise FileNotFoundError(path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def run_twin(twin: ModuleType, inputs: np.ndarray, progress: tqdm | None) -> np.ndarray:
    """The twin on every point; bus states and timings cached (the twin's commutate()
    is bus_condition() then commutate_edge(), as in C, and its timing is a pure
    function that the 12 edges of a point share)."""
    if not hasattr(twin.commutation_timing, "cache_info"):
        twin.commutation_timing = functools.lru_cache(maxsize=None)(twin.commutation_timing)
    buses: dict[int, object] = {}
    columns = [inputs[n].tolist() for n in inputs.dtype.names or ()]
    rows = []
    for k, (hall, previous, period, bus, current, duty) in enumerate(zip(*columns, strict=True)):
        if hall > 7 or previous > 7:
            rows.append(tuple(twin.commutate(hall, previous, period, bus, current, duty)))
            continue
        state = buses.get(bus)
        if state is None:
            state = buses[bus] = twin.bus_condition(bus)
        on, off, ticks, edge, flags = twin.commutate_edge(
            state, previous, hall, period, current, duty
        )
        on_sw, off_sw = twin.EDGE_SWITCH[edge] if edge != twin.EDGE_NONE else (0xFF, 0xFF)
        rows.append((on, off, ticks, on_sw, off_sw, twin.SECTOR_OF_HALL[hall], flags))
        if progress is not None and k % 50_000 == 49_999:
            progress.update(50_000)
    if progress is not None:
        progress.update(len(rows) % 50_000)
    return np.array(rows, dtype=OUTPUT_DTYPE)


def verify(
    spec_path: str | Path,
    generated: Path,
    build_dir: Path,
    *,
    seed: int | None = None,
    random_count: int = DEFAULT_RANDOM_POINTS,
    exhaustive_stride: int = 1,
    show_progress: bool = True,
) -> tuple[VerifyResult, dict[str, Evaluated], DesignBounds, Scaling]:
    started = time.perf_counter()
    spec = load_spec(spec_path)
    derivation = derive()
    sc = scaling(spec, derivation)
    fx = fixed_point_design(spec)
    model = build_model(spec, derivation, sc)
    core = build_host_core(generated / "c", build_dir)
    twin = load_twin(generated)
    if seed is None:
        seed = int(np.random.default_rng().integers(0, 2**31))
    exhaustive = points.exhaustive(spec, sc, model)
    if exhaustive_stride > 1:
        exhaustive = exhaustive[::exhaustive_stride]
    sets = {
        "exhaustive": exhaustive,
        "random": points.random_points(sc, model, seed, random_count),
        "boundary": points.boundaries(spec, sc, model),
    }
    rule = rule_design(spec, sc) if spec.controller.method == "improved_r" else None
    bounds = design_bounds(spec, fx, rule)
    if rule is not None:
        designed: RuleDesign = rule  # narrowed for the closure
        checks = new_rule_checks(designed, bounds.time_ticks)

        def check(inputs: np.ndarray, c_out: np.ndarray, twin_out: np.ndarray) -> Evaluated:
            return check_rule_set(
                model, designed, bounds.time_ticks, inputs, c_out, twin_out, checks
            )
    else:
        checks = new_checks(fx)

        def check(inputs: np.ndarray, c_out: np.ndarray, twin_out: np.ndarray) -> Evaluated:
            return check_set(model, fx, inputs, c_out, twin_out, checks)

    evaluated: dict[str, Evaluated] = {}
    total = sum(s.size for s in sets.values())
    with tqdm(
        total=total, unit="pt", unit_scale=True, disable=not show_progress, file=sys.stderr
    ) as bar:
        for name, inputs in sets.items():
            bar.set_description(name)
            c_out = core.run(inputs)
            twin_out = run_twin(twin, inputs, bar)
            evaluated[name] = check(inputs, c_out, twin_out)
    result = VerifyResult(
        spec=project_relative(spec_path),
        generated=project_relative(generated),
        seed=seed,
        sets={name: int(s.size) for name, s in sets.items()},
        checks=checks,
        seconds=time.perf_counter() - started,
    )
    return result, evaluated, bounds, sc


def table(result: VerifyResult) -> str:
    lines = [
        f"verify {result.spec} ({result.generated}), seed {result.seed}: "
        + ", ".join(f"{n} {c:,}" for n, c in result.sets.items())
        + " points",
        f"{'output':<52} {'points':>9} {'max err':>9} {'bound':>9}  verdict  worst at",
    ]
    for check in result.checks.values():
        bound = "exact" if check.bound is None else f"{check.bound:.3f}"
        where = " ".join(f"{SHORT[k]}={v}" for k, v in check.worst_inputs.items())
        lines.append(
            f"{check.name:<52} {check.points:>9,} {check.max_error:>9.3f} {bound:>9}  "
            f"{check.verdict:<7}  {where if check.max_error else ''}"
        )
    lines.append(
        f"{'PASS' if result.passed else 'FAIL'} in {result.seconds:.1f} s"
        f" (replay: --seed {result.seed})"
    )
    return "\n".join(lines)


def write_json(result: VerifyResult, bounds: DesignBounds, path: Path) -> None:
    data = {
        "spec": result.spec,
        "generated": result.generated,
        "seed": result.seed,
        "points": result.sets,
        "passed": result.passed,
        "design": bounds.summary,
        "outputs": {
            key: {
                **asdict(c),
                "verdict": c.verdict,
                "bound": c.bound if c.bound != float("inf") else None,
            }
            for key, c in result.checks.items()
        },
    }
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(data, indent=2) + "\n", encoding="utf-8")


def plot(evaluated: dict[str, Evaluated], bounds: DesignBounds, sc: Scaling, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    ex = evaluated["exhaustive"]
    speed = np.asarray(
        [float(sc.speed_rpm(int(t))) for t in ex.period[:: max(1, ex.period.size // 20000)]]
    )
    step = max(1, ex.period.size // 20000)
    fig, axes = plt.subplots(3, 1, figsize=(8, 8), sharex=True)
    for ax, values, bound, label in (
        (axes[0], ex.on_error, bounds.duty_counts, "|D_on error| (counts)"),
        (axes[1], ex.off_error, bounds.duty_counts, "|D_off error| (counts)"),
        (axes[2], ex.time_error, bounds.time_ticks, "|t_com error| (ticks)"),
    ):
        ax.plot(speed, values[::step], ".", markersize=1)
        ax.axhline(float(bound), color="red", linewidth=0.8, label="design bound")
        ax.set_ylabel(label)
        ax.legend(loc="upper right")
    axes[2].set_xlabel("speed (rpm), exhaustive set")
    fig.suptitle("generated core against the exact symbolic model")
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=100, metadata={"Software": None})
    plt.close(fig)

"""`verify SPEC`: the generated C core against the independent oracle.

What is checked is read from generated/<name>/ (the C, the Python twin, the manifest's
ABI and claims) and the spec; the expected values and the tolerances come from the
oracle (`oracle/`) and the spec's `accuracy:` section. Nothing is taken from the
generator's Python objects, and the loader's converted quantities only once they are
shown equal to the oracle's own reading of the spec file (`oracle.quantities`, the first
check). A manifest whose spec hash differs from the spec given is stale: verify stops
and says how to regenerate.
"""

from __future__ import annotations

import json
import sys
import time
from dataclasses import asdict, dataclass
from pathlib import Path
from types import ModuleType

import numpy as np
from tqdm import tqdm

from codegen.freshness import another_spec, regenerate_command
from codegen.manifest_check import shape_problem
from codegen.render import save_figure_atomically, write_atomically
from codegen.spec_loader import load_spec
from codegen.spec_model import Spec
from oracle.model import Oracle, oracle
from oracle.quantities import Agreement, cross_check
from verify import points
from verify.check import (
    Evaluated,
    OutputCheck,
    Tolerances,
    check_set,
    claims_check,
    new_checks,
    tolerances,
)
from verify.current_loop import verify_loop
from verify.host_core import HostCore, build_host_core, dtype_of, load_twin

DEFAULT_RANDOM_POINTS = 20_000
TWIN_SAMPLE = 8_000  # points per set run through the Python twin (it is printed from the same IR)
SHORT = {
    "hall_code": "hall",
    "previous_hall_code": "prev",
    "hall_period_ticks": "T",
    "bus_voltage_adc": "B",
    "phase_current_adc": "C",
    "main_duty_counts": "M",
}


class StaleOutputError(RuntimeError):
    """generated/<name> was made from another version of the spec."""


@dataclass(frozen=True)
class VerifyResult:
    spec: str
    motor: str
    generated: str
    seed: int
    sets: dict[str, int]
    checks: dict[str, OutputCheck]
    seconds: float

    @property
    def passed(self) -> bool:
        return all(c.verdict == "PASS" for c in self.checks.values())


def read_manifest(generated: Path, spec: Spec, spec_arg: str) -> dict[str, object]:
    # the command that regenerates this very folder (it named `make generate`, which
    # outside the project has no Makefile, and not the -o of a folder elsewhere)
    fix = regenerate_command(spec, generated)
    path = generated / "manifest.json"
    if not path.is_file():
        raise FileNotFoundError(f"no manifest in {generated}: run `{fix}`")
    try:
        manifest = json.loads(path.read_text(encoding="utf-8"))
    except ValueError as exc:
        raise StaleOutputError(f"{path} is unreadable ({exc}): regenerate with `{fix}`") from None
    if not isinstance(manifest, dict):
        raise StaleOutputError(
            f"{path} is not as bldc-codegen wrote it (edited?): {shape_problem(manifest)}:"
            f" regenerate with `{fix}`"
        )
    other = another_spec(spec, generated, manifest)
    if other is not None:
        raise StaleOutputError(other)
    if manifest.get("spec_sha256") != spec.sha256:
        raise StaleOutputError(
            f"{generated} was generated from another version of {spec_arg} "
            f"(spec hash {str(manifest.get('spec_sha256'))[:12]}, now {spec.sha256[:12]}): "
            f"regenerate with `{fix}`"
        )
    if "core" not in manifest:
        raise StaleOutputError(
            f"{generated} predates the manifest's core section: regenerate with `{fix}`"
        )
    # "core": null had been an AssertionError below (exit 70)
    problem = shape_problem(manifest)
    if problem is not None:
        raise StaleOutputError(
            f"{path} is not as bldc-codegen wrote it (edited?): {problem}: regenerate with `{fix}`"
        )
    return manifest


def quantity_checks(rows: tuple[Agreement, ...]) -> dict[str, OutputCheck]:
    """The oracle's own reading of the spec's quantities against the loader's
    (`oracle.quantities`): one row for every key compared, and one FAIL row per key
    that disagrees, its note the key, the raw text, the oracle's value and the loader's."""
    bad = [row for row in rows if not row.agrees]
    checks = {
        "quantities": OutputCheck(
            "spec quantities: oracle's reading == loader's",
            "keys off",
            None,
            points=len(rows),
            failures=len(bad),
            max_error=float(len(bad)),
            note=(
                f"{len(rows)} keys converted from the YAML by oracle/quantities.py: exact,"
                " within 1e-12 relative where the unit holds pi"
                if not bad
                else f"{len(bad)} of {len(rows)} keys disagree (below)"
            ),
        )
    }
    for row in bad:
        checks[f"quantity {row.key}"] = OutputCheck(
            f"spec {row.key}",
            "rel. diff",
            None,
            points=1,
            failures=1,
            max_error=row.relative_difference,
            note=row.line(),
        )
    return checks


def _sample(n: int, count: int) -> np.ndarray:
    if n <= count:
        return np.arange(n)
    return np.unique(np.linspace(0, n - 1, count).astype(np.int64))


#: Points of the check of bldc_commutation_timing() beyond the Hall counter's range
WIDE_POINTS = 4096


def wide_period_check(core: HostCore, o: Oracle, inputs: np.ndarray, seed: int) -> OutputCheck:
    """bldc_commutation_timing() takes any uint32_t period, but bldc_commutate() (the
    points above) passes the struct's 16 bits: a period beyond what the Hall counter can
    read (the oracle's hall_counter_max) must give what the counter's full count gives.
    A core whose clamp to the counter's range was dropped passed every other check (a
    hunt's mutant): its periods above 65535 computed a speed below the range's."""
    rng = np.random.default_rng(seed)
    pick = inputs[rng.integers(0, inputs.size, WIDE_POINTS)]
    top = o.u.hall_counter_max
    wide = rng.integers(top + 1, 2**32, WIDE_POINTS, dtype=np.uint64)
    wide[:2] = (top + 1, 2**32 - 1)
    columns = (pick["bus_voltage_adc"], np.full(WIDE_POINTS, top), pick["phase_current_adc"])
    at_top = np.stack([*columns, pick["main_duty_counts"]], axis=1).astype(np.uint32)
    beyond = at_top.copy()
    beyond[:, 1] = wide.astype(np.uint32)
    expected, got = core.timing(at_top), core.timing(beyond)
    bad = np.zeros(WIDE_POINTS, dtype=bool)
    for name in expected.dtype.names or ():
        bad |= expected[name] != got[name]
    check = OutputCheck(
        "bldc_commutation_timing beyond the Hall counter == at its full count", "mismatches", None
    )
    check.add(bad.astype(np.float64), bad, pick)
    check.note = (
        f"periods {top + 1}..2^32-1 against {top} ticks, the counter's largest"
        f" ({WIDE_POINTS} points of the random set)"
        + (f"; first differing period {int(wide[np.argmax(bad)])}" if bad.any() else "")
    )
    return check


def twin_check(twin: ModuleType, inputs: np.ndarray, c_out: np.ndarray, check: OutputCheck) -> None:
    """C == the bit-exact Python twin on a deterministic sample of the set."""
    index = _sample(inputs.size, TWIN_SAMPLE)
    names = list(c_out.dtype.names or ())
    bad = np.zeros(index.size, dtype=bool)
    # the sampled rows as Python ints, fields in order (indexing a structured array a
    # field and a row at a time was most of this check's time)
    rows = inputs[index][list(points.FIELDS)].tolist()
    expected = c_out[index][names].tolist()
    for j, (row, want) in enumerate(zip(rows, expected, strict=True)):
        out = twin.commutate(twin.Inputs(*(int(v) for v in row)))
        bad[j] = any(int(getattr(out, n)) != int(w) for n, w in zip(names, want, strict=True))
    check.add(bad.astype(np.float64), bad, inputs[index])


def _time_model(o: Oracle):  # type: ignore[no-untyped-def]
    """(period, bus, current) -> exact t_com in ticks, for locating the time clamp."""

    def paper(period: np.ndarray, bus: np.ndarray, current: np.ndarray) -> np.ndarray:
        main = np.zeros_like(period)
        on, off, _, _ = o.duties(period, bus, main)
        t, _ = o.eq20(period, bus, current, on, off)
        return t

    def rule(period: np.ndarray, bus: np.ndarray, current: np.ndarray) -> np.ndarray:
        # the end the rule gives: the carrier boundary after the zero, beyond the
        # period exactly when the sector's last whole PWM period comes first
        com = o.rule(period, bus, current)
        x, _ = com.zero()
        return com.end_after(x * period) * float(o.u.carrier_ticks)

    return rule if o.method == "improved_r" else paper


def verify(
    spec_arg: str | Path,
    generated: Path,
    build_dir: Path,
    *,
    seed: int | None = None,
    random_count: int = DEFAULT_RANDOM_POINTS,
    exhaustive_stride: int = 1,
    show_progress: bool = True,
) -> tuple[VerifyResult, dict[str, Evaluated], Tolerances, Oracle]:
    started = time.perf_counter()
    spec = load_spec(spec_arg)
    # first: every quantity the oracle takes from the loader's Spec, as the oracle reads
    # it from the YAML with its own units (a factor wrong in the loader would otherwise
    # move the C and its yardstick together)
    quantities = quantity_checks(cross_check(spec_arg, spec))
    manifest = read_manifest(generated, spec, str(spec_arg))
    core_info = manifest["core"]
    assert isinstance(core_info, dict)
    abi = core_info["abi"]
    in_dtype = dtype_of(abi["structs"]["bldc_inputs_t"])
    out_dtype = dtype_of(abi["structs"]["bldc_outputs_t"])
    timing_dtype = dtype_of(abi["structs"]["bldc_timing_t"])
    core = build_host_core(generated / "c", build_dir, in_dtype, out_dtype, timing_dtype)
    twin = load_twin(generated)
    o = oracle(spec)
    tol = tolerances(spec)
    if seed is None:
        seed = int(np.random.default_rng().integers(0, 2**31))
    exhaustive = points.exhaustive(o, in_dtype)
    if exhaustive_stride > 1:
        exhaustive = exhaustive[::exhaustive_stride]
    sets = {
        "exhaustive": exhaustive,
        "random": points.random_points(o, in_dtype, seed, random_count),
        "thresholds": points.thresholds(o, in_dtype),
        "time clamp": points.time_clamp_points(o, in_dtype, _time_model(o)),
        "conditioning": points.conditioning_points(o, in_dtype),
    }
    checks = {**quantities, **new_checks(tol)}
    checks["twin"] = OutputCheck("C == bit-exact Python twin (sample)", "mismatches", None)
    evaluated: dict[str, Evaluated] = {}
    flag_bits = {k: int(v) for k, v in abi["flags"].items()}
    total = sum(s.size for s in sets.values())
    with tqdm(
        total=total, unit="pt", unit_scale=True, disable=not show_progress, file=sys.stderr
    ) as bar:
        for name, inputs in sets.items():
            bar.set_description(name)
            c_out = core.run(inputs)
            evaluated[name] = check_set(o, tol, flag_bits, inputs, c_out, checks)
            twin_check(twin, inputs, c_out, checks["twin"])
            bar.update(inputs.size)
    checks["wide_period"] = wide_period_check(core, o, sets["random"], seed)
    measured_duty = max(checks["turn_on"].max_error, checks["turn_off"].max_error)
    checks["claims"] = claims_check(core_info["claims"], tol, measured_duty)  # type: ignore[arg-type]
    # The braking-current PI (oracle/current_loop.py).
    checks.update(verify_loop(spec, generated, build_dir, manifest, seed))
    result = VerifyResult(
        spec=str(spec_arg),
        motor=spec.name,
        generated=str(generated),
        seed=seed,
        sets={name: int(s.size) for name, s in sets.items()},
        checks=checks,
        seconds=time.perf_counter() - started,
    )
    return result, evaluated, tol, o


def physical(o: Oracle, inputs: dict[str, int]) -> str:
    """A point in engineering units."""
    if not inputs:
        return ""
    t = max(inputs["hall_period_ticks"], 1)
    parts = [
        f"{float(o.u.rpm(t)):.1f} rpm (T={t})",
        f"{float(o.u.volts(inputs['bus_voltage_adc'])):.2f} V",
        f"{float(o.u.amps(inputs['phase_current_adc'])):.3f} A",
    ]
    if o.uses_main_duty:
        parts.append(f"duty {inputs['main_duty_counts'] / o.u.pwm_counts:.3f}")
    parts.append(f"Hall {inputs['previous_hall_code']:03b}->{inputs['hall_code']:03b}")
    return ", ".join(parts)


def table(result: VerifyResult, o: Oracle) -> str:
    lines = [
        f"verify {result.motor} ({result.generated}), seed {result.seed}: "
        + ", ".join(f"{n} {c:,}" for n, c in result.sets.items())
        + " points",
        f"{'output':<46} {'points':>10} {'max err':>9} {'bound':>9}  {'unit':<10} verdict  worst at",
    ]
    for check in result.checks.values():
        bound = "exact" if check.bound is None else f"{check.bound:.3f}"
        where = physical(o, check.worst_inputs) if check.max_error else ""
        lines.append(
            f"{check.name:<46} {check.points:>10,} {check.max_error:>9.3f} {bound:>9}  "
            f"{check.unit:<10} {check.verdict:<7}  {where}"
        )
        if check.note:
            lines.append(f"{'':<46}   {check.note}")
    lines.append(
        f"{'PASS' if result.passed else 'FAIL'} in {result.seconds:.1f} s (replay: --seed {result.seed})"
    )
    return "\n".join(lines)


def write_json(result: VerifyResult, tol: Tolerances, o: Oracle, path: Path) -> None:
    """report.json, written beside and renamed (a run stopped mid-write left it cut),
    with the spec's hash: `generate` keeps the report across a regeneration (a file it
    did not write), and the hash says which version of the spec it verified."""
    data = {
        "spec": result.spec,
        "spec_sha256": o.spec.sha256,
        "motor": result.motor,
        "generated": result.generated,
        "seed": result.seed,
        "points": result.sets,
        "passed": result.passed,
        "tolerances": asdict(tol),
        "outputs": {
            key: {
                **asdict(c),
                "verdict": c.verdict,
                "worst_at": physical(o, c.worst_inputs),
            }
            for key, c in result.checks.items()
        },
    }
    write_atomically(path, json.dumps(data, indent=2) + "\n")


def plot(evaluated: dict[str, Evaluated], tol: Tolerances, motor: str, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(3, 1, figsize=(8, 8), sharex=True)
    styles = {"exhaustive": ".", "random": "x", "thresholds": "+", "time clamp": "^"}
    for name, ev in evaluated.items():
        step = max(1, ev.speed_rpm.size // 20000)
        speed = ev.speed_rpm[::step]
        for ax, values in zip(axes, (ev.on_error, ev.off_error, ev.time_error), strict=True):
            ax.plot(speed, values[::step], styles.get(name, "."), markersize=2, label=name)
    for ax, bound, label in (
        (axes[0], tol.duty_counts, "|D_on error| (counts)"),
        (axes[1], tol.duty_counts, "|D_off error| (counts)"),
        (axes[2], tol.time_ticks, "|t_com error| (ticks)"),
    ):
        ax.axhline(bound, color="red", linewidth=0.8, label="spec tolerance")
        ax.set_ylabel(label)
    axes[0].legend(loc="upper right", fontsize=7)
    axes[2].set_xlabel("speed (rpm)")
    axes[2].set_xscale("log")
    fig.suptitle(
        f"{motor}: generated core against the oracle (ill-conditioned points excluded from t_com)"
    )
    fig.tight_layout()
    try:
        save_figure_atomically(fig, path, dpi=100)
    finally:
        plt.close(fig)

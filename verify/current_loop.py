"""The generated braking-current PI against its exact discrete-time model.

Reads generated/<name>/c/bldc_current_loop.{h,c} and python/bldc_current_loop.py and the
manifest's claims; the expected values come from oracle/current_loop.py and the
tolerance from the spec's `accuracy.current_loop_duty_counts` alone.

Checks:

* one step, from the integrator state the C is given (the exact model steps from the
  same state): every error r - m of the ADC range, each at states spread over the whole
  int32 type (below 0, inside, above D_max); every state within 4 counts of 0 and of
  D_max at a grid of errors; every pair of 12-bit codes at the rails and ADC codes
  beyond 12 bits (the inputs are uint32: they saturate); random points over the whole
  types. The duty within the tolerance; the integrator within the tolerance divided by
  the periods of a step response (5 / w_c in PWM periods: its error accumulates over
  them), except where the exact v is within the tolerance of a saturation bound, where
  either anti-windup decision is accepted (the rounded gain may take the other one);
* step responses: the exact controller closed on the averaged plant (oracle) at speeds
  across the range, references stepping up, down and to an unreachable current; the C
  and the exact controller fed the same measured codes from zero state: every duty
  within the tolerance;
* anti-windup: after a long saturation, the C leaves it in the same period as the exact
  model, and no integrator ever leaves [0, D_max];
* the reference: every mA from 0 to twice the braking range, and the uint32 extremes:
  the exact nearest code (ties up) of the clamped command;
* the C against the bit-exact Python twin on a sample; the design's claims against the
  spec's tolerance, and the measured error against the claims;
* the port's dead time (its BDTR.DTG code, decoded by the oracle) is the one D_max's
  guard counts.
"""

from __future__ import annotations

import ctypes
import re
from dataclasses import dataclass
from fractions import Fraction
from pathlib import Path
from types import ModuleType

import numpy as np
import numpy.typing as npt

from codegen.spec_model import Spec
from oracle.current_loop import (
    LoopModel,
    dtg_dead_time_counts,
    loop_model,
    programmed_dead_time_counts,
    step_response_periods,
)
from verify.check import SLACK, OutputCheck
from verify.host_core import compile_with_shim, load_twin

SHIM = """\
/* Batch entry for the verifier: not part of the firmware. */
#include <stddef.h>
#include "bldc_current_loop.h"
void loop_batch(const int32_t *x, const uint32_t *r, const uint32_t *m, uint32_t *duty,
                int32_t *next, size_t n)
{
    size_t k;
    for (k = 0; k < n; k++) {
        duty[k] = bldc_current_loop_duty(x[k], r[k], m[k]);
        next[k] = bldc_current_loop_integrate(x[k], r[k], m[k]);
    }
}
void loop_run(const uint32_t *r, const uint32_t *m, uint32_t *duty, int32_t *state, size_t n,
              int32_t x0)
{
    int32_t x = x0;
    size_t k;
    for (k = 0; k < n; k++) {
        duty[k] = bldc_current_loop_duty(x, r[k], m[k]);
        x = bldc_current_loop_integrate(x, r[k], m[k]);
        state[k] = x;
    }
}
void loop_reference(const uint32_t *ma, uint32_t *code, size_t n)
{
    size_t k;
    for (k = 0; k < n; k++) {
        code[k] = bldc_current_reference(ma[k]);
    }
}
"""
RANDOM_POINTS = 200_000
STATES_PER_ERROR = 41
TWIN_SAMPLE = 4_000
STEP_PERIODS = 200
#: periods at D_max the windup scenario holds before the drop; the longest it may ask
#: for the unreachable current (see windup_periods)
WINDUP_HELD = 20
WINDUP_PERIODS_MAX = 20 * STEP_PERIODS
SPEED_FRACTIONS = (Fraction(1, 5), Fraction(1, 2), Fraction(3, 4), Fraction(19, 20))
U32 = np.uint32
I32 = np.int32
Ints = npt.NDArray[np.int64]


@dataclass(frozen=True)
class HostLoop:
    library: ctypes.CDLL
    fraction_bits: int

    def step(self, x: Ints, r: Ints, m: Ints) -> tuple[Ints, Ints]:
        x32 = np.ascontiguousarray(x, dtype=I32)
        r32 = np.ascontiguousarray(r, dtype=U32)
        m32 = np.ascontiguousarray(m, dtype=U32)
        duty = np.zeros(x32.size, dtype=U32)
        nxt = np.zeros(x32.size, dtype=I32)
        self.library.loop_batch(
            *(a.ctypes.data_as(ctypes.c_void_p) for a in (x32, r32, m32, duty, nxt)),
            ctypes.c_size_t(x32.size),
        )
        return duty.astype(np.int64), nxt.astype(np.int64)

    def run(self, r: Ints, m: Ints, x0: int = 0) -> tuple[Ints, Ints]:
        """The C loop over a trajectory of references and measured codes, from the
        integrator `x0` (the C's own format)."""
        r32 = np.ascontiguousarray(r, dtype=U32)
        m32 = np.ascontiguousarray(m, dtype=U32)
        duty = np.zeros(r32.size, dtype=U32)
        state = np.zeros(r32.size, dtype=I32)
        self.library.loop_run(
            *(a.ctypes.data_as(ctypes.c_void_p) for a in (r32, m32, duty, state)),
            ctypes.c_size_t(r32.size),
            ctypes.c_int32(x0),
        )
        return duty.astype(np.int64), state.astype(np.int64)

    def reference(self, ma: Ints) -> Ints:
        ma32 = np.ascontiguousarray(ma, dtype=U32)
        code = np.zeros(ma32.size, dtype=U32)
        self.library.loop_reference(
            ma32.ctypes.data_as(ctypes.c_void_p),
            code.ctypes.data_as(ctypes.c_void_p),
            ctypes.c_size_t(ma32.size),
        )
        return code.astype(np.int64)


def build_host_loop(c_dir: Path, build_dir: Path, fraction_bits: int) -> HostLoop:
    dll, _ = compile_with_shim(c_dir / "bldc_current_loop.c", SHIM, build_dir, "verify_loop")
    for name in ("loop_batch", "loop_run", "loop_reference"):
        getattr(dll, name).restype = None
    return HostLoop(dll, fraction_bits)


# ------------------------------------------------------------------ input sets


def _step_points(model: LoopModel, scale: int, seed: int) -> dict[str, tuple[Ints, Ints, Ints]]:
    """(integrator in Q, reference, measured) per set."""
    top = model.duty_max * scale
    code_max = model.code_max
    i32 = np.iinfo(np.int32)
    errors = np.arange(-code_max, code_max + 1, dtype=np.int64)
    spread = np.unique(
        np.concatenate(
            [
                np.linspace(0, top, STATES_PER_ERROR - 8).round().astype(np.int64),
                np.array([i32.min, -scale, -1, top + 1, top + scale, i32.max, 1, top - 1]),
            ]
        )
    )
    ref = np.where(errors >= 0, errors, 0)
    meas = np.where(errors >= 0, 0, -errors)
    every_error = (
        np.repeat(spread, errors.size),
        np.tile(ref, spread.size),
        np.tile(meas, spread.size),
    )
    near = np.concatenate(
        [np.arange(-4 * scale, 4 * scale + 1), np.arange(top - 4 * scale, top + 4 * scale + 1)]
    )
    near = near[:: max(1, near.size // 4000)]
    grid = np.concatenate(
        [np.arange(-64, 65), np.array([-code_max, -1000, -300, 300, 1000, code_max])]
    )
    gref = np.where(grid >= 0, grid, 0)
    gmeas = np.where(grid >= 0, 0, -grid)
    near_bounds = (np.repeat(near, grid.size), np.tile(gref, near.size), np.tile(gmeas, near.size))
    wide = np.array([code_max, code_max + 1, 65535, 2**31, 2**32 - 1], dtype=np.int64)
    pairs = np.array(
        np.meshgrid(np.concatenate([[0, 1, 2048], wide]), np.concatenate([[0, 1, 2048], wide]))
    ).reshape(2, -1)
    states = np.array([0, top // 2, top], dtype=np.int64)
    beyond = (
        np.repeat(states, pairs.shape[1]),
        np.tile(pairs[0], states.size),
        np.tile(pairs[1], states.size),
    )
    rng = np.random.default_rng(seed)
    small = rng.random(RANDOM_POINTS) < 0.75
    r_rand = np.where(
        small, rng.integers(0, code_max + 1, RANDOM_POINTS), rng.integers(0, 2**32, RANDOM_POINTS)
    )
    m_rand = np.where(
        small, rng.integers(0, code_max + 1, RANDOM_POINTS), rng.integers(0, 2**32, RANDOM_POINTS)
    )
    x_rand = np.where(
        small,
        rng.integers(0, top + 1, RANDOM_POINTS),
        rng.integers(i32.min, i32.max, RANDOM_POINTS, endpoint=True),
    )
    return {
        "every error": every_error,
        "states at the bounds": near_bounds,
        "inputs beyond the ADC": beyond,
        "random": (x_rand.astype(np.int64), r_rand.astype(np.int64), m_rand.astype(np.int64)),
    }


# ------------------------------------------------------------------ checks


def _record(
    check: OutputCheck,
    errors: npt.NDArray[np.float64],
    failed: npt.NDArray[np.bool_],
    where: list[str],
) -> None:
    check.points += int(errors.size)
    if errors.size == 0:
        return
    new = int(np.count_nonzero(failed))
    k = int(np.argmax(np.where(failed, errors, -np.inf) if new else errors))
    if float(errors[k]) >= check.max_error or (new and not check.failures):
        check.note = where[k] if k < len(where) else ""
    check.failures += new
    check.max_error = max(check.max_error, float(errors.max()))


def _describe(x: int, r: int, m: int, scale: int) -> str:
    return f"x = {x} (Q: {x / scale:.3f} counts), r = {r}, m = {m}"


def step_checks(
    model: LoopModel, host: HostLoop, tol: float, integrator_tol: float, seed: int
) -> dict[str, OutputCheck]:
    scale = 2**host.fraction_bits
    duty_check = OutputCheck("current loop: duty, one step", "counts", tol)
    state_check = OutputCheck("current loop: integrator, one step", "counts", integrator_tol)
    for _name, (x, r, m) in _step_points(model, scale, seed).items():
        duty_c, next_c = host.step(x, r, m)
        exact_x = x.astype(np.float64) / scale
        duty_e, next_e = model.step_array(exact_x, r, m)
        duty_err = np.abs(duty_c - duty_e)
        # either anti-windup decision where the exact v is within the tolerance of a bound
        near = model.near_decision(exact_x, r, m, tol)
        held = np.clip(exact_x, 0.0, float(model.duty_max))
        integrated = np.clip(
            held
            + float(model.ki) * (np.minimum(r, model.code_max) - np.minimum(m, model.code_max)),
            0.0,
            float(model.duty_max),
        )
        state_err = np.abs(next_c / scale - next_e)
        alternative = np.minimum(np.abs(next_c / scale - held), np.abs(next_c / scale - integrated))
        state_err = np.where(near, np.minimum(state_err, alternative), state_err)
        worst_d = int(np.argmax(duty_err))
        worst_s = int(np.argmax(state_err))
        notes_d = [""] * duty_err.size
        notes_d[worst_d] = _describe(int(x[worst_d]), int(r[worst_d]), int(m[worst_d]), scale)
        notes_s = [""] * state_err.size
        notes_s[worst_s] = _describe(int(x[worst_s]), int(r[worst_s]), int(m[worst_s]), scale)
        _record(duty_check, duty_err, duty_err > tol + SLACK, notes_d)
        _record(state_check, state_err, state_err > integrator_tol + SLACK, notes_s)
        # the integrator never leaves [0, D_max]
        outside = (next_c < 0) | (next_c > model.duty_max * scale)
        if outside.any():
            state_check.failures += int(np.count_nonzero(outside))
            state_check.note = "integrator outside [0, D_max]"
    return {"loop_duty": duty_check, "loop_integrator": state_check}


@dataclass(frozen=True)
class Scenario:
    """A step response: references per period at an EMF, from an integrator state and
    the plant current it holds (rest, or a loop already saturated at D_max)."""

    name: str
    emf_v: float
    references: list[int]
    state: Fraction = Fraction(0)  # counts
    current_a: float = 0.0


def scenarios(spec: Spec, model: LoopModel) -> list[Scenario]:
    """The step responses: speeds across the range, and the windup scenario last."""
    c = spec.controller
    code = model.reference_code
    nominal = code(int(c.braking_current_nominal_a * 1000))
    top = code(int(c.braking_current_max_a * 1000))
    bottom = code(int(c.braking_current_min_a * 1000))
    out = []
    k_e = spec.motor.back_emf_constant_v_per_rpm
    for fraction in SPEED_FRACTIONS:
        speed = c.speed_min_rpm + fraction * (c.speed_max_rpm - c.speed_min_rpm)
        emf = float(k_e * speed)
        half = STEP_PERIODS // 2
        out.append(
            Scenario(
                f"{float(speed):.0f} rpm: 0 -> nominal -> max", emf, [nominal] * half + [top] * half
            )
        )
        out.append(
            Scenario(
                f"{float(speed):.0f} rpm: nominal -> min", emf, [nominal] * half + [bottom] * half
            )
        )
    # saturation: at the EMF where the averaged plant's steady current at D_max,
    # (E - U_d (1 - D_max) / 2) / R, is midway between the smallest and the largest
    # braking current, the largest is unreachable (the duty saturates) and the smallest
    # is reachable (it must leave saturation). speed_min's EMF may hold both (a narrow
    # speed range of a fast motor) or neither (E/R below the smallest current)
    u_d, r_ohm = float(model.bus_nominal), float(model.resistance)
    floor_v = u_d * (1 - float(model.duty_max) / model.pwm_counts) / 2
    middle_a = float(c.braking_current_min_a + c.braking_current_max_a) / 2
    slow = floor_v + r_ohm * middle_a
    where = f"{slow / float(k_e):.0f} rpm (D_max holds {middle_a:g} A)"
    held = windup_periods(model, slow, top)
    if held is not None:
        out.append(
            Scenario(
                f"windup: max at {where}, then min", slow, [top] * held + [bottom] * STEP_PERIODS
            )
        )
        return out
    # The exact loop does not reach D_max from rest within WINDUP_PERIODS_MAX (a motor
    # of tiny R and L: K_i = 2 R w_c / U_d leaves the integrator crawling): both loops
    # start saturated, as the port preloads the integrator from a duty, at the current
    # D_max holds, and hold the unreachable current 2 x WINDUP_HELD periods
    out.append(
        Scenario(
            f"windup: max at {where} from D_max (not reached from rest in"
            f" {WINDUP_PERIODS_MAX} periods), then min",
            slow,
            [top] * (2 * WINDUP_HELD) + [bottom] * STEP_PERIODS,
            state=Fraction(model.duty_max),
            current_a=model.held_current(slow, float(model.duty_max)),
        )
    )
    return out


def windup_periods(model: LoopModel, emf_v: float, top: int) -> int | None:
    """How long the windup scenario asks for the unreachable current: 2 x STEP_PERIODS,
    or longer where the exact loop needs longer to saturate, so that it has been at D_max
    for WINDUP_HELD periods before the drop. From rest the current stays at zero until
    the duty passes 1 - 2E/U_d, and a motor of small R has a small K_i (2 R w_c / U_d):
    a 2-pole 15 mohm 5 uH motor at 50 kHz took 555 periods to saturate and the check,
    asserting saturation at period 400, failed on a loop the C met exactly (and once
    at D_max the duty dips below it while the current rises and the integrator catches
    up: held right up to the drop, not first reached; a 0.3 A fan motor, saturated on
    and off from period 26, dipped at period 397 of 400)."""
    periods = 2 * STEP_PERIODS
    _, duties, _ = model.closed_loop(emf_v=emf_v, references=[top] * WINDUP_PERIODS_MAX)
    held = next(
        (
            k
            for k in range(periods, len(duties) + 1)
            if all(d >= model.duty_max for d in duties[k - WINDUP_HELD : k])
        ),
        None,
    )
    return held  # None: it never saturates from rest (the scenario starts saturated)


def _admissible_state(
    model: LoopModel,
    x: Fraction,
    x_next: Fraction,
    reference: int,
    measured: int,
    tol: float,
    state_c: float,
) -> Fraction:
    """The exact loop's next integrator along a trajectory the C runs too. Where the
    exact v lies within `tol` of a saturation bound the rounded gains may take the other
    anti-windup decision (hold, or integrate), as the one-step check allows; the model
    then follows the decision the C took, so one admissible flip is not counted again
    at every later period (a 400 V motor whose integrator steps 9 counts a period was
    3.4 counts apart after the C integrated one period before the exact loop)."""
    near = model.near_decision(
        np.array([float(x)]), np.array([reference]), np.array([measured]), tol
    )
    if not near[0]:
        return x_next
    e = min(reference, model.code_max) - min(measured, model.code_max)
    held = min(max(Fraction(x), Fraction(0)), Fraction(model.duty_max))
    integrated = min(max(held + model.ki * e, Fraction(0)), Fraction(model.duty_max))
    return min((held, integrated), key=lambda v: abs(float(v) - state_c))


def trajectory_checks(
    spec: Spec, model: LoopModel, host: HostLoop, tol: float
) -> dict[str, OutputCheck]:
    scale = 2**host.fraction_bits
    steps = OutputCheck("current loop: step responses (same measured codes)", "counts", tol)
    windup = OutputCheck(
        "current loop: anti-windup (leaves saturation with the model)", "periods", None
    )
    windup.points = 0
    for scenario in scenarios(spec, model):
        name, refs = scenario.name, scenario.references
        measured, _, _ = model.closed_loop(
            emf_v=scenario.emf_v,
            references=refs,
            current_a=scenario.current_a,
            state=scenario.state,
        )
        r = np.array(refs, dtype=np.int64)
        m = np.array(measured, dtype=np.int64)
        # the same state in the C's format (D_max is a whole count: exact)
        duty_c, state_c = host.run(r, m, int(scenario.state * scale))
        x = scenario.state
        duty_e = []
        for k in range(len(refs)):
            d, x_next = model.step(x, refs[k], measured[k])
            duty_e.append(float(d))
            x = _admissible_state(model, x, x_next, refs[k], measured[k], tol, state_c[k] / scale)
        err = np.abs(duty_c - np.array(duty_e))
        notes = [""] * err.size
        worst = int(np.argmax(err))
        notes[worst] = f"{name}, period {worst}"
        _record(steps, err, err > tol + SLACK, notes)
        if name.startswith("windup"):
            drop = len(refs) - STEP_PERIODS
            leave_c = next((k for k in range(drop, len(refs)) if duty_c[k] < model.duty_max), None)
            leave_e = next(
                (k for k in range(drop, len(refs)) if duty_e[k] < model.duty_max - 1e-9), None
            )
            saturated = bool(np.all(duty_c[drop - WINDUP_HELD // 2 : drop] == model.duty_max))
            windup.points += 1
            ok = saturated and leave_c == leave_e and leave_c is not None
            lag = 0 if leave_c == leave_e else abs((leave_c or len(refs)) - (leave_e or len(refs)))
            windup.max_error = max(windup.max_error, float(lag))
            windup.note = (
                f"{name}: saturated before the drop {saturated}, leaves at period"
                f" {leave_c} (model {leave_e}); integrator within [0, D_max]"
                f" {bool(np.all((state_c >= 0) & (state_c <= model.duty_max * scale)))}"
            )
            if not ok or not np.all((state_c >= 0) & (state_c <= model.duty_max * scale)):
                windup.failures += 1
    return {"loop_steps": steps, "loop_windup": windup}


def reference_check(model: LoopModel, host: HostLoop) -> OutputCheck:
    check = OutputCheck("current loop: reference mA -> code (nearest, ties up)", "mismatches", None)
    ma = np.concatenate(
        [np.arange(0, 2 * model.ma_max + 2, dtype=np.int64), np.array([2**31, 2**32 - 1])]
    )
    code_c = host.reference(ma)
    expected = np.array([model.reference_code(int(v)) for v in ma], dtype=np.int64)
    bad = code_c != expected
    notes = [""] * bad.size
    if bad.any():
        k = int(np.argmax(bad))
        notes[k] = f"{int(ma[k])} mA: C {int(code_c[k])}, exact {int(expected[k])}"
    _record(check, bad.astype(np.float64), bad, notes)
    return check


def twin_check(twin: ModuleType, model: LoopModel, host: HostLoop, seed: int) -> OutputCheck:
    check = OutputCheck("current loop: C == bit-exact Python twin (sample)", "mismatches", None)
    scale = 2**host.fraction_bits
    x, r, m = _step_points(model, scale, seed)["random"]
    index = np.unique(np.linspace(0, x.size - 1, TWIN_SAMPLE).astype(np.int64))
    duty_c, next_c = host.step(x[index], r[index], m[index])
    bad = np.zeros(index.size, dtype=bool)
    for j, k in enumerate(index):
        args = (int(x[k]), int(r[k]), int(m[k]))
        bad[j] = (
            twin.current_loop_duty(*args) != duty_c[j]
            or twin.current_loop_integrate(*args) != next_c[j]
        )
    ma = np.arange(0, model.ma_max + 1, max(1, model.ma_max // 500), dtype=np.int64)
    ref_c = host.reference(ma)
    ref_bad = np.array(
        [twin.current_reference(int(v)) != int(c) for v, c in zip(ma, ref_c, strict=True)]
    )
    all_bad = np.concatenate([bad, ref_bad])
    _record(check, all_bad.astype(np.float64), all_bad, [""] * all_bad.size)
    return check


def claims_check(
    claims: dict[str, float], tol: float, integrator_tol: float, measured: dict[str, OutputCheck]
) -> OutputCheck:
    check = OutputCheck("current loop: design claims within the spec", "violations", None)
    problems = []
    duty, state = float(claims["duty_counts"]), float(claims["integrator_counts"])
    if duty > tol + SLACK:
        problems.append(f"duty bound {duty:g} > accuracy.current_loop_duty_counts {tol:g}")
    if state > integrator_tol + SLACK:
        problems.append(f"integrator bound {state:g} > {integrator_tol:.4g}")
    if measured["loop_duty"].max_error > duty + SLACK:
        problems.append(
            f"measured duty error {measured['loop_duty'].max_error:.4f} > claimed {duty:g}"
        )
    check.points = 3
    check.failures = len(problems)
    check.max_error = float(len(problems))
    check.note = (
        "; ".join(problems)
        if problems
        else f"claims duty {duty:.4f}, integrator {state:.4f} counts per step"
    )
    return check


def integrator_tolerance(spec: Spec, tol: float) -> float:
    """The duty tolerance `tol` spread over the PWM periods of a step response
    (`oracle.current_loop.step_response_periods`, the oracle's own): the integrator's
    error per step accumulates."""
    return tol / float(step_response_periods(spec))


def verify_loop(
    spec: Spec, generated: Path, build_dir: Path, manifest: dict[str, object], seed: int
) -> dict[str, OutputCheck]:
    info = manifest.get("current_loop")
    if not isinstance(info, dict):
        raise FileNotFoundError(
            f"{generated}/manifest.json has no current_loop section: regenerate"
        )
    model = loop_model(spec)
    host = build_host_loop(generated / "c", build_dir / "loop", int(info["fraction_bits"]))
    tol = float(spec.accuracy.current_loop_duty_counts)
    integrator_tol = integrator_tolerance(spec, tol)
    checks = step_checks(model, host, tol, integrator_tol, seed)
    checks.update(trajectory_checks(spec, model, host, tol))
    checks["loop_reference"] = reference_check(model, host)
    checks["loop_twin"] = twin_check(load_twin(generated, "bldc_current_loop"), model, host, seed)
    checks["loop_claims"] = claims_check(info["claims"], tol, integrator_tol, checks)  # type: ignore[arg-type]
    dmax = OutputCheck("current loop: D_max (the sample window's)", "counts", None)
    dmax.points = 1
    if int(info["duty_max_counts"]) != model.duty_max:
        dmax.failures = 1
        dmax.max_error = abs(int(info["duty_max_counts"]) - model.duty_max)
    dmax.note = f"generated {info['duty_max_counts']}, model {model.duty_max}"
    checks["loop_duty_max"] = dmax
    checks["dead_time"] = dead_time_check(spec, generated)
    return checks


_DTG = re.compile(r"^#define BLDC_PORT_TIM1_DTG\s+(0x[0-9a-fA-F]+|[0-9]+)u\b", re.M)


def dead_time_check(spec: Spec, generated: Path) -> OutputCheck:
    """The dead time the port programs (BLDC_PORT_TIM1_DTG, decoded by RM0008's table)
    is the shortest TIM1 can encode that is not shorter than `inverter.dead_time`: the
    one D_max's guard counts. Nothing had read it: a port that encoded it at half the
    clock (250 ns for 500 ns) verified (a helper's hunt)."""
    check = OutputCheck("port: TIM1 dead time (BDTR.DTG)", "TIM1 clocks", None)
    check.points = 1
    inv = spec.inverter
    expected = programmed_dead_time_counts(inv.dead_time_s, inv.timer_clock_hz)
    header = generated / "c" / "stm32f103_port.h"
    found = _DTG.search(header.read_text(encoding="utf-8")) if header.is_file() else None
    if found is None:
        check.failures = 1
        check.note = f"no BLDC_PORT_TIM1_DTG in {header.name}; expected {expected} clocks"
        return check
    dtg = int(found.group(1), 0)
    programmed = dtg_dead_time_counts(dtg) if 0 <= dtg <= 0xFF else -1
    if programmed != expected:
        check.failures = 1
        check.max_error = abs(programmed - expected)
    check.note = (
        f"DTG {dtg:#04x} programs {programmed} clocks, the spec's"
        f" {float(inv.dead_time_s) * 1e9:g} ns takes {expected}"
    )
    return check

"""Checks of an `improved_r` core against the resistance-aware rule in real arithmetic.

The reference (`codegen.improved_r_rule.reference`, evaluated by the exact model) gives
at each input the commutation fraction x_c, the held duty sum S(x_c) and its split.
Its constants are the spec's exact rationals, not the generator's integers. Per output:

* duties: |C - C(x_c)| in counts. The design states a headline bound over its grid;
  every point must lie within its own pointwise bound
  (`codegen.improved_r_rule.accuracy.point_bound`: every rounding, the table's error and
  the bisection's last bracket), which is evaluated for the points above the headline;
* commutation time: |ticks - min(x_c T, T)|. Where the time is well-conditioned
  (t_half <= the spec's target: half a count of duty moves the true zero by less than
  the target) and the inputs are inside the spec's ranges, the error must be within the
  target or its pointwise bound; elsewhere within the pointwise bound, reported
  separately;
* flags: HIGH_SPEED (S < P), FAIL_AREA_CLAMPED (S outside [0, 2P]) and TIME_CLAMPED
  (x_c = 1) exactly, except where the reference lies within the pointwise error of the
  threshold; INPUT_SATURATED and the Hall flags exactly.
"""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt

from codegen.improved_r_rule.accuracy import half_count_ticks_batch, point_bound
from codegen.improved_r_rule.design import RuleDesign
from codegen.improved_r_rule.reference import (
    FLAG_NOT_FINISHED,
    ReferenceBatch,
    RuleInputs,
)
from codegen.reference import (
    FLAG_FAIL_AREA_CLAMPED,
    FLAG_HIGH_SPEED,
    FLAG_INPUT_SATURATED,
    FLAG_TIME_CLAMPED,
    SLACK,
    ExactModel,
)
from verify.check import Evaluated, OutputCheck, column, expected_and_exact_checks

#: A broken core puts most points beyond their bounds: stop evaluating them after this
#: many. The verdict is FAIL then; the remaining points above the headline are judged
#: against the headline alone, and the checks' notes say how many.
MAX_POINTWISE_FAILURES = 200
#: Flags whose threshold the reference may sit on: decided within the pointwise error.
THRESHOLD_FLAGS = FLAG_HIGH_SPEED | FLAG_FAIL_AREA_CLAMPED | FLAG_TIME_CLAMPED


def new_rule_checks(design: RuleDesign, time_target_ticks: float) -> dict[str, OutputCheck]:
    duty = design.duty_bound
    return {
        "turn_on": OutputCheck(
            "D_on (turn_on_compare)", "counts", duty, note="else within its pointwise bound"
        ),
        "turn_off": OutputCheck(
            "D_off (turn_off_compare)", "counts", duty, note="else within its pointwise bound"
        ),
        "commutation_time": OutputCheck(
            f"t_com, t_half <= {time_target_ticks:g} ticks, inputs in range",
            "ticks",
            time_target_ticks,
            note="else within its pointwise bound",
        ),
        "commutation_time_ill": OutputCheck(
            "t_com, ill-conditioned or inputs saturated",
            "ticks",
            math.inf,
            note="pointwise bound",
        ),
        "pattern": OutputCheck("switch pattern and sector", "mismatches", None),
        "flags": OutputCheck("flags", "mismatches", None),
        "twin": OutputCheck("C == bit-exact Python twin", "mismatches", None),
    }


def _pointwise(
    design: RuleDesign,
    batch: ReferenceBatch,
    inputs: np.ndarray,
    points: npt.NDArray[np.int64],
    on_err: npt.NDArray[np.float64],
    off_err: npt.NDArray[np.float64],
    time_err: npt.NDArray[np.float64],
) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64], npt.NDArray[np.float64]]:
    """(duty bound, time bound, fraction bound) at the given point indices, in order,
    stopping after MAX_POINTWISE_FAILURES points beyond their bound."""
    duty, ticks, fraction = (np.zeros(points.size) for _ in range(3))
    cache: dict[tuple[int, int, int], tuple[float, float, float]] = {}
    failures = 0
    for n, k in enumerate(points):
        if failures >= MAX_POINTWISE_FAILURES:
            return duty[:n], ticks[:n], fraction[:n]
        key = (
            int(inputs["hall_period_ticks"][k]),
            int(inputs["bus_voltage_adc"][k]),
            int(inputs["phase_current_adc"][k]),
        )
        if key not in cache:
            ref = batch.result(int(k), key[0])
            bound = point_bound(design.rule, RuleInputs(*key), ref)
            cache[key] = (bound.duty_counts, bound.ticks, bound.fraction_error)
        duty[n], ticks[n], fraction[n] = cache[key]
        if max(on_err[k], off_err[k]) > duty[n] + SLACK or time_err[k] > ticks[n] + SLACK:
            failures += 1
    return duty, ticks, fraction


def check_rule_set(
    model: ExactModel,
    design: RuleDesign,
    time_target_ticks: float,
    inputs: np.ndarray,
    c_out: np.ndarray,
    twin_out: np.ndarray,
    checks: dict[str, OutputCheck],
) -> Evaluated:
    exp = expected_and_exact_checks(model, inputs, c_out, twin_out, checks)
    period = column(inputs, "hall_period_ticks")
    active = exp.active
    batch = exp.rule
    if batch is None:
        raise ValueError(f"the model of method {model.method!r} has no resistance-aware rule")
    on_c, off_c = column(c_out, "turn_on_compare"), column(c_out, "turn_off_compare")
    ticks_c, flags_c = column(c_out, "commutation_ticks"), column(c_out, "flags")

    # The safe state (inactive points) must emit zeros: bound 0 there.
    on_err = np.abs(on_c - exp.turn_on)
    off_err = np.abs(off_c - exp.turn_off)
    t_exact = np.where(active, np.minimum(batch.ticks_exact, period), 0.0)
    time_err = np.abs(ticks_c - t_exact)
    half = half_count_ticks_batch(model.period_counts, batch)
    p = model.period_counts
    thresholds = np.stack([batch.total - p, batch.total, batch.total - 2 * p])
    expected_flags = exp.flags | np.where(
        active & ((batch.flags & FLAG_NOT_FINISHED) != 0), FLAG_TIME_CLAMPED, 0
    )
    flag_diff = flags_c ^ expected_flags
    suspect = active & (
        (on_err > design.duty_bound + SLACK)
        | (off_err > design.duty_bound + SLACK)
        | (time_err > time_target_ticks + SLACK)
        | (flag_diff != 0)
    )
    # Worst first, so a broken core fails fast: after MAX_POINTWISE_FAILURES points
    # beyond their bound the rest of the suspects are counted as not evaluated.
    ratio = np.maximum(
        np.maximum(on_err, off_err) / design.duty_bound, time_err / time_target_ticks
    )
    k = np.flatnonzero(suspect)
    k = k[np.argsort(-ratio[k], kind="stable")]
    duty_b, time_b, frac_b = _pointwise(design, batch, inputs, k, on_err, off_err, time_err)
    k = k[: duty_b.size]
    duty_bound = np.zeros(inputs.size)
    time_bound = np.zeros(inputs.size)
    duty_bound[active] = design.duty_bound
    time_bound[active] = time_target_ticks
    skipped = np.zeros(inputs.size, dtype=bool)
    skipped[np.flatnonzero(suspect)] = True
    skipped[k] = False  # evaluated
    if skipped.any():
        for key in ("turn_on", "turn_off", "commutation_time", "commutation_time_ill", "flags"):
            checks[key].note = (
                f"stopped after {MAX_POINTWISE_FAILURES} points beyond their pointwise bound;"
                f" {int(skipped.sum())} more judged against the headline only"
            )
    duty_bound[k] = np.maximum(duty_b, design.duty_bound)
    time_bound[k] = np.maximum(time_b, np.where(half[k] <= time_target_ticks, time_target_ticks, 0))

    checks["turn_on"].add(on_err, on_err > duty_bound + SLACK, inputs)
    checks["turn_off"].add(off_err, off_err > duty_bound + SLACK, inputs)
    in_range = (flags_c & FLAG_INPUT_SATURATED) == 0
    good = ~active | ((half <= time_target_ticks) & in_range)
    ill = ~good
    time_failed = time_err > time_bound + SLACK
    checks["commutation_time"].add(time_err[good], time_failed[good], inputs[good])
    checks["commutation_time_ill"].add(time_err[ill], time_failed[ill], inputs[ill])

    # A threshold flag may differ only where the reference is within the error of it.
    near = np.zeros(inputs.size, dtype=np.int64)
    if k.size:
        margin = duty_b + SLACK
        on_edge = np.abs(thresholds[:, k]) <= margin
        near[k] |= np.where(on_edge[0], FLAG_HIGH_SPEED, 0)
        near[k] |= np.where(on_edge[1] | on_edge[2], FLAG_FAIL_AREA_CLAMPED, 0)
        near[k] |= np.where(batch.fraction[k] + frac_b >= 1.0, FLAG_TIME_CLAMPED, 0)
    flags_wrong = (flag_diff & ~(near & THRESHOLD_FLAGS)) != 0
    checks["flags"].add(flags_wrong.astype(np.float64), flags_wrong, inputs)
    return Evaluated(period, on_err, off_err, time_err)

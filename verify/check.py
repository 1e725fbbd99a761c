"""Compare the generated core's outputs with the exact symbolic model.

Per output the verifier keeps the points checked, the largest error in LSB and where it
happened, the bound the generator promised, and a verdict:

* duties: |C - exact| <= the design's duty bound, at every point;
* commutation time: Eq. 20 evaluated exactly at the duties the core emitted, saturated
  to [0, T] as the firmware must. Every point must lie in the interval that the design's
  stated error components (the quantisation of X_q and of the bus reciprocal) allow
  there, and where W >= the design's W_ok the error must be within its headline bound;
* switch pattern (both switches and the sector) and flags: exact. BLDC_FLAG_TIME_CLAMPED
  may differ only where the allowed interval of the unsaturated time straddles T.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import numpy.typing as npt

from codegen.fixedpoint.design import FixedPointDesign
from codegen.reference import (
    FLAG_TIME_CLAMPED,
    SLACK,
    ExactModel,
    Expected,
    expected,
    time_interval,
)
from verify.host_core import INPUT_DTYPE


@dataclass
class OutputCheck:
    name: str
    unit: str
    bound: float | None  # None: must match exactly
    points: int = 0
    failures: int = 0
    max_error: float = 0.0
    worst_inputs: dict[str, int] = field(default_factory=dict)
    note: str = ""

    @property
    def verdict(self) -> str:
        return "PASS" if self.failures == 0 else "FAIL"

    def add(
        self, errors: npt.NDArray[np.float64], failed: npt.NDArray[np.bool_], inputs: np.ndarray
    ) -> None:
        self.points += int(errors.size)
        self.failures += int(np.count_nonzero(failed))
        if errors.size == 0:
            return
        k = int(np.argmax(errors))
        if errors[k] > self.max_error or not self.worst_inputs:
            self.max_error = float(errors[k])
            self.worst_inputs = {n: int(inputs[n][k]) for n in inputs.dtype.names or ()}


@dataclass(frozen=True)
class Evaluated:
    """Per-point results of one input set, for the report's plot."""

    period: npt.NDArray[np.int64]
    on_error: npt.NDArray[np.float64]
    off_error: npt.NDArray[np.float64]
    time_error: npt.NDArray[np.float64]


def column(array: np.ndarray, name: str) -> npt.NDArray[np.int64]:
    return np.asarray(array[name], dtype=np.int64)


def expected_and_exact_checks(
    model: ExactModel,
    inputs: np.ndarray,
    c_out: np.ndarray,
    twin_out: np.ndarray,
    checks: dict[str, OutputCheck],
) -> Expected:
    """The model's expectation at every input; checks the C against its bit-exact twin
    (every field, every point) and the switch pattern and sector against the model."""
    exp = expected(
        model,
        *(column(inputs, name) for name in INPUT_DTYPE.names or ()),
    )
    differs = np.zeros(inputs.size, dtype=bool)
    for name in c_out.dtype.names or ():
        differs |= column(c_out, name) != column(twin_out, name)
    checks["twin"].add(differs.astype(np.float64), differs, inputs)
    pattern = (
        (column(c_out, "turn_on_switch") != exp.turn_on_switch)
        | (column(c_out, "turn_off_switch") != exp.turn_off_switch)
        | (column(c_out, "sector") != exp.sector)
    )
    checks["pattern"].add(pattern.astype(np.float64), pattern, inputs)
    return exp


def check_set(
    model: ExactModel,
    fx: FixedPointDesign,
    inputs: np.ndarray,
    c_out: np.ndarray,
    twin_out: np.ndarray,
    checks: dict[str, OutputCheck],
) -> Evaluated:
    exp = expected_and_exact_checks(model, inputs, c_out, twin_out, checks)
    period, current = column(inputs, "hall_period_ticks"), column(inputs, "phase_current_adc")
    on_c, off_c = column(c_out, "turn_on_compare"), column(c_out, "turn_off_compare")
    ticks_c, flags_c = column(c_out, "commutation_ticks"), column(c_out, "flags")

    on_err = np.abs(on_c - exp.turn_on)
    off_err = np.abs(off_c - exp.turn_off)
    duty_bound = float(fx.duty_error_bound_counts)
    checks["turn_on"].add(on_err, on_err > duty_bound + SLACK, inputs)
    checks["turn_off"].add(off_err, off_err > duty_bound + SLACK, inputs)

    # Commutation time at the emitted duties.
    active = exp.active
    t_exact, w = model.commutation_time(np.maximum(period, 1), exp.bus, current, on_c, off_c)
    i_code = current - model.current_offset
    positive = i_code > 0
    t_sat = np.where(positive, np.minimum(t_exact, period), 0.0)
    time_err = np.where(active, np.abs(ticks_c - t_sat), 0.0)
    lo, hi = time_interval(model, fx, np.maximum(period, 1), exp.bus, current, w)
    lo_sat = np.where(positive, np.minimum(np.maximum(lo, 0), period), 0)
    hi_sat = np.where(positive, np.minimum(hi, period), 0)
    outside = active & ((ticks_c < lo_sat - SLACK) | (ticks_c > hi_sat + SLACK))
    well_conditioned = w >= float(fx.time_bound_min_w_counts)
    over_bound = active & well_conditioned & (time_err > float(fx.time_error_bound_ticks) + SLACK)
    good = active & well_conditioned
    checks["commutation_time"].add(time_err[good], (outside | over_bound)[good], inputs[good])
    ill = active & ~well_conditioned
    checks["commutation_time_ill"].add(time_err[ill], outside[ill], inputs[ill])

    # Flags: exact, but TIME_CLAMPED only where the allowed interval decides it.
    must_clamp = active & positive & (lo > period)
    must_not = active & (~positive | (hi <= period))
    clamped_c = (flags_c & FLAG_TIME_CLAMPED) != 0
    time_flag_wrong = (must_clamp & ~clamped_c) | (must_not & clamped_c) | (~active & clamped_c)
    other_wrong = (flags_c & ~FLAG_TIME_CLAMPED) != exp.flags
    flags_wrong = time_flag_wrong | other_wrong
    checks["flags"].add(flags_wrong.astype(np.float64), flags_wrong, inputs)
    return Evaluated(
        period, np.where(active, on_err, 0.0), np.where(active, off_err, 0.0), time_err
    )


def new_checks(fx: FixedPointDesign) -> dict[str, OutputCheck]:
    duty = float(fx.duty_error_bound_counts)
    w_ok = float(fx.time_bound_min_w_counts)
    return {
        "turn_on": OutputCheck("D_on (turn_on_compare)", "counts", duty),
        "turn_off": OutputCheck("D_off (turn_off_compare)", "counts", duty),
        "commutation_time": OutputCheck(
            f"t_com, W >= {w_ok:g} counts",
            "ticks",
            float(fx.time_error_bound_ticks),
            note="and every point inside its allowed interval",
        ),
        "commutation_time_ill": OutputCheck(
            f"t_com, W < {w_ok:g} counts (near the top-speed limit)",
            "ticks",
            math.inf,
            note="pointwise interval from the design's error components",
        ),
        "pattern": OutputCheck("switch pattern and sector", "mismatches", None),
        "flags": OutputCheck("flags", "mismatches", None),
        "twin": OutputCheck("C == bit-exact Python twin", "mismatches", None),
    }

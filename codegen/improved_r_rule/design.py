"""Choose the integer rule's formats and table size for one spec, and prove them.

* K (bisection steps): `fixed.steps_for`, from the time and duty targets.
* fc (fraction bits of duty counts): the most that fit; the binding constraint is
  xn = N_X / B in uint32 (precision costs nothing at run time).
* the table: the fewest entries per octave (2^n) whose pointwise bounds meet the
  spec's accuracy targets (time: max(target, t_half), see `accuracy`) over the grid (speeds across the range, bus min,
  nominal and max, braking currents up to the spec's maximum, commutations that finish
  unflagged); fy (y's fraction bits) the most for which the interpolation product
  stays in uint32.
* every intermediate's range is proven by `proof.prove_rule` over the full input box.
"""

from __future__ import annotations

import random
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from codegen.improved_r_rule.accuracy import PointBound, point_bound
from codegen.improved_r_rule.constants import RuleConstants
from codegen.improved_r_rule.fixed import FixedRule, build_fixed_rule, steps_for
from codegen.improved_r_rule.proof import (
    ProvenRange,
    RuleFormatError,
    interpolation_product_max,
    prove_rule,
)
from codegen.improved_r_rule.reference import RuleInputs, reference_points
from codegen.improved_r_rule.table import PsiTable, design_psi_table

MAX_COUNTS_FRAC_BITS = 12
MAX_Y_FRAC_BITS = 24
SEGMENT_BITS = range(3, 9)
GRID_SPEEDS = 40
GRID_CURRENT_EIGHTHS = (1, 2, 3, 4, 6, 8)  # braking currents in eighths of the maximum
GRID_RANDOM = 200


@dataclass(frozen=True)
class RuleDesign:
    rule: FixedRule
    ranges: tuple[ProvenRange, ...]
    #: Worst pointwise bounds over the design grid (unflagged points): ticks, the
    #: largest ratio of the time bound to its allowance max(target, t_half), counts.
    ticks_bound: float
    time_ratio: float
    duty_bound: float
    grid_points: int


def design_grid(c: RuleConstants, braking_current_codes: int) -> list[RuleInputs]:
    """Speeds (geometric), bus min/mid/max, braking currents from 1 code to the spec's
    maximum, and seeded random points of the same box."""
    # Slowest first: the ill-conditioned points (long commutations) come early, so a
    # table that is too small fails fast.
    spaced = np.geomspace(c.period_low, c.period_high, GRID_SPEEDS).round().astype(int)
    periods = sorted(set(spaced.tolist()), reverse=True)
    buses = sorted({c.bus_low, (c.bus_low + c.bus_high) // 2, c.bus_high})
    currents = sorted({1, *(braking_current_codes * k // 8 for k in GRID_CURRENT_EIGHTHS)})
    grid = [
        RuleInputs(t, b, c.current_offset + i) for t in periods for b in buses for i in currents
    ]
    rng = random.Random(0)
    grid += [
        RuleInputs(
            rng.randint(c.period_low, c.period_high),
            rng.randint(c.bus_low, c.bus_high),
            c.current_offset + rng.randint(1, braking_current_codes),
        )
        for _ in range(GRID_RANDOM)
    ]
    return grid


def _table(c: RuleConstants, segment_bits: int) -> PsiTable:
    for fy in range(MAX_Y_FRAC_BITS, segment_bits, -1):
        table = design_psi_table(c.rho_max, segment_bits, fy)
        if interpolation_product_max(table) < 2**32 and table.y_limit < 2**31:
            return table
    raise RuleFormatError(f"no y format fits a table of 2^{segment_bits} entries per octave")


def _formats(
    c: RuleConstants, table: PsiTable, steps: int
) -> tuple[FixedRule, tuple[ProvenRange, ...]]:
    reasons = []
    for fc in range(MAX_COUNTS_FRAC_BITS, -1, -1):
        rule = build_fixed_rule(c, fc, table, steps)
        try:
            return rule, prove_rule(rule)
        except RuleFormatError as exc:
            reasons.append(f"Q{fc}: {exc}")
    raise RuleFormatError("no counts format fits: " + "; ".join(reasons))


def worst_bounds(
    rule: FixedRule, grid: list[RuleInputs], stop_above: float = float("inf")
) -> tuple[float, float, float, int]:
    """(worst time bound, worst bound/allowance ratio, worst duty bound, points used);
    stops early once the ratio exceeds stop_above."""
    target = float(rule.constants.time_target_ticks)
    ticks = ratio = duty = 0.0
    used = 0
    for inputs, ref in zip(grid, reference_points(rule.constants, grid), strict=True):
        if ref.outputs.flags:
            continue
        bound: PointBound = point_bound(rule, inputs, ref)
        ticks = max(ticks, bound.ticks)
        ratio = max(ratio, bound.ticks / bound.time_allowance(target))
        duty = max(duty, bound.duty_counts)
        used += 1
        if ratio > stop_above or duty > stop_above * float(rule.constants.duty_target_counts):
            break
    return ticks, ratio, duty, used


@lru_cache(maxsize=8)
def design_rule(c: RuleConstants, braking_current_codes: int) -> RuleDesign:
    steps = steps_for(c)
    grid = design_grid(c, braking_current_codes)
    last = ""
    for n in SEGMENT_BITS:
        rule, ranges = _formats(c, _table(c, n), steps)
        ticks, ratio, duty, used = worst_bounds(rule, grid, stop_above=1.0)
        if ratio <= 1.0 and duty <= c.duty_target_counts:
            return RuleDesign(rule, ranges, ticks, ratio, duty, used)
        last = f"2^{n} entries per octave: time bound/allowance {ratio:.2f}, {duty:.2f} counts"
    raise RuleFormatError(f"no table size meets the accuracy targets; largest tried: {last}")

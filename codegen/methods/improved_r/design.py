"""Choose the integer rule's formats and table size for one spec, and prove them.

* K (bisection steps): `fixed.steps_for`, from the time and duty targets.
* fc (fraction bits of duty counts): the most that fit; the binding constraint is
  xn = N_X / B in uint32 (precision costs nothing at run time).
* the table: the fewest entries per octave (2^n) whose pointwise bounds meet the
  spec's accuracy targets (time: max(target, t_half), see `accuracy`) over the grid (speeds across the range, bus min,
  nominal and max, braking currents up to the spec's maximum, commutations that finish
  unflagged); fy (y's fraction bits) the most for which the interpolation product
  stays in uint32.
* every intermediate's range is proven on the printed IR (`ir.py`, `codegen.ir.intervals`)
  over every input value.
"""

from __future__ import annotations

import random
from dataclasses import dataclass

import numpy as np

from codegen.core.conditioning import CoreLimits
from codegen.ir.intervals import ProofError, ProvenRange, new_prover, prove_function
from codegen.ir.types import U64, CType, narrowest
from codegen.methods.improved_r.accuracy import PointBound, point_bound
from codegen.methods.improved_r.constants import RuleConstants
from codegen.methods.improved_r.fixed import THETA_FRAC_BITS, FixedRule, build_fixed_rule, steps_for
from codegen.methods.improved_r.ir import ALL_WIDE, WIDE_PRODUCTS, functions
from codegen.methods.improved_r.reference import RuleInputs, reference_points
from codegen.methods.improved_r.table import PsiTable, design_psi_table, interpolation_product_max

MAX_COUNTS_FRAC_BITS = 12


class RuleFormatError(ValueError):
    """No integer format of the rule meets the spec's ranges and accuracy targets."""


MAX_Y_FRAC_BITS = 24
SEGMENT_BITS = range(3, 9)
GRID_SPEEDS = 40
GRID_CURRENT_EIGHTHS = (1, 2, 3, 4, 6, 8)  # braking currents in eighths of the maximum
GRID_RANDOM = 200


@dataclass(frozen=True)
class RuleDesign:
    rule: FixedRule
    widths: dict[str, CType]  # the wide products' proven types
    ranges: tuple[ProvenRange, ...]
    #: Worst pointwise bounds over the design grid (unflagged points): ticks, the
    #: largest ratio of the time bound to its allowance max(target, t_half), counts.
    ticks_bound: float  # where t_half <= the target
    time_ratio: float
    duty_bound: float
    grid_points: int


def design_grid(c: RuleConstants, braking_current_codes: int) -> list[RuleInputs]:
    """Speeds (geometric), bus min/mid/max, braking currents from 1 code to the spec's
    maximum and on to the ADC's full scale (the core computes any current it is given),
    and seeded random points of the same box."""
    # Slowest first: the ill-conditioned points (long commutations) come early, so a
    # table that is too small fails fast.
    spaced = np.geomspace(c.period_low, c.period_high, GRID_SPEEDS).round().astype(int)
    periods = sorted(set(spaced.tolist()), reverse=True)
    buses = sorted({c.bus_low, (c.bus_low + c.bus_high) // 2, c.bus_high})
    full_scale = c.adc_max - c.current_offset
    currents = sorted(
        {
            1,
            *(
                codes * k // 8
                for codes in (braking_current_codes, full_scale)
                for k in GRID_CURRENT_EIGHTHS
            ),
        }
    )
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


#: the rounding half each wide product gets before its shift (C: product + half)
def _halves(rule: FixedRule) -> dict[str, int]:
    def half(shift: int) -> int:
        return 1 << (shift - 1) if shift > 0 else 0

    k, fu, fy = rule.steps, rule.unit_frac_bits, rule.table.y_frac_bits
    return {
        "x_kappa_i": half(rule.kappa_frac_bits),
        "x_theta": half(THETA_FRAC_BITS),
        "rho_x": 0,
        "y_psi1": half(fy + 16 - fu),
        "x_x_psi2": half(2 * k + 16 - fu),
        "s1_x": half(k + 1),
    }


def prove_formats(
    rule: FixedRule, limits: CoreLimits
) -> tuple[dict[str, CType], tuple[ProvenRange, ...]]:
    """Prove the printed IR of these formats; each wide product in the narrowest type
    its proven range (plus its rounding half) allows. Raises ProofError."""

    def prove(widths: dict[str, CType]) -> tuple[ProvenRange, ...]:
        bus_fn, timing, _ = functions(rule, limits, rule.constants.current, widths)
        prover = new_prover((bus_fn, timing))
        bus = prove_function(prover, bus_fn)
        prove_function(prover, timing, {f"bus.{k}": v for k, v in bus.struct_returns.items()})
        return prover.ranges

    wide = prove(ALL_WIDE)
    halves = _halves(rule)
    widths: dict[str, CType] = {}
    for name, signed in WIDE_PRODUCTS.items():
        found = [r for r in wide if r.name == name]
        low = min((r.low for r in found), default=0)
        high = max((r.high for r in found), default=0) + halves[name]
        widths[name] = narrowest(low, high, signed) if found else U64
    return widths, prove(widths)


def _formats(
    c: RuleConstants, table: PsiTable, steps: int, limits: CoreLimits
) -> tuple[FixedRule, dict[str, CType], tuple[ProvenRange, ...]]:
    reasons = []
    for fc in range(MAX_COUNTS_FRAC_BITS, -1, -1):
        rule = build_fixed_rule(c, fc, table, steps)
        try:
            widths, ranges = prove_formats(rule, limits)
            return rule, widths, ranges
        except ProofError as exc:
            reasons.append(f"Q{fc}: {exc}")
    raise RuleFormatError("no counts format fits: " + "; ".join(reasons))


def worst_bounds(
    rule: FixedRule, grid: list[RuleInputs], stop_above: float = float("inf")
) -> tuple[float, float, float, int]:
    """(worst time bound where well conditioned (t_half <= target), worst
    bound/allowance ratio, worst duty bound, points used); stops early once the ratio
    exceeds stop_above."""
    target = float(rule.constants.time_target_ticks)
    ticks = ratio = duty = 0.0
    used = 0
    for inputs, ref in zip(grid, reference_points(rule.constants, grid), strict=True):
        if ref.outputs.flags:
            continue
        bound: PointBound = point_bound(rule, inputs, ref)
        if bound.half_count_ticks <= target:  # well conditioned: the target itself holds
            ticks = max(ticks, bound.ticks)
        ratio = max(ratio, bound.ticks / bound.time_allowance(target))
        duty = max(duty, bound.duty_counts)
        used += 1
        if ratio > stop_above or duty > stop_above * float(rule.constants.duty_target_counts):
            break
    return ticks, ratio, duty, used


def design_rule(c: RuleConstants, braking_current_codes: int, limits: CoreLimits) -> RuleDesign:
    steps = steps_for(c)
    grid = design_grid(c, braking_current_codes)
    last = ""
    for n in SEGMENT_BITS:
        rule, widths, ranges = _formats(c, _table(c, n), steps, limits)
        ticks, ratio, duty, used = worst_bounds(rule, grid, stop_above=1.0)
        if ratio <= 1.0 and duty <= c.duty_target_counts:
            return RuleDesign(rule, widths, ranges, ticks, ratio, duty, used)
        last = f"2^{n} entries per octave: time bound/allowance {ratio:.2f}, {duty:.2f} counts"
    raise RuleFormatError(f"no table size meets the accuracy targets; largest tried: {last}")

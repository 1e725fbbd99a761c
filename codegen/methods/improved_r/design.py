"""Choose the integer rule's formats for one spec, and prove them.

* fc (fraction bits of duty counts): the most that fit, down to whole counts; the
  binding constraint is xn = N_X / B in uint32 (precision costs nothing at run time;
  where few bits fit, as at low PWM frequencies, the accuracy bounds below decide).
* fq (the ramp term's extra bits): the fewest that keep y_1 N, rho x at the sector's last
  carrier boundary, in uint32 (Y1 is y_1 in Q(32 - fq)): the most bits for the decay's
  exponent.
* fs (the held sum's growth per PWM period): the most the proof accepts.
* every intermediate's range is proven on the printed IR (`ir.py`, `codegen.ir.intervals`)
  over every input value; the accuracy bounds (`accuracy.py`) are evaluated over a
  design grid (speeds across the range, bus min/nominal/max, braking currents up to the
  ADC's full scale) and must meet the spec's duty target where the end is decided.
"""

from __future__ import annotations

import math
import random
import re
from collections.abc import Iterable
from dataclasses import dataclass
from fractions import Fraction

import numpy as np

from codegen.core.conditioning import CoreLimits
from codegen.ir.intervals import ProofError, ProvenRange, new_prover, prove_function
from codegen.methods.improved_r.accuracy import bounds
from codegen.methods.improved_r.constants import RuleConstants
from codegen.methods.improved_r.fixed import FixedRule, build_fixed_rule
from codegen.methods.improved_r.ir import functions
from codegen.methods.improved_r.reference import (
    FLAG_NOT_FINISHED,
    RuleInputs,
    reference_points,
)

MAX_COUNTS_FRAC_BITS = 12
#: whole counts: the accuracy bounds decide whether so few bits meet the spec's targets
MIN_COUNTS_FRAC_BITS = 0
MAX_GROWTH_FRAC_BITS = 12
GRID_SPEEDS = 40
GRID_CURRENT_EIGHTHS = (1, 2, 3, 4, 6, 8)  # braking currents in eighths of the maximum
GRID_RANDOM = 200


class RuleFormatError(ValueError):
    """No integer format of the rule meets the spec's ranges and accuracy targets."""


class SectorTooShortError(RuleFormatError):
    """The shortest sector, less the end's guard and margin, holds no PWM period: the
    commutation cannot end on a carrier boundary. `period_needed`: the shortest Hall
    period (ticks) that holds one."""

    def __init__(self, message: str, period_needed: int) -> None:
        super().__init__(message)
        self.period_needed = period_needed


#: How a refusal for the duty target begins; `refused_duty_bound` reads the bound back.
DUTY_REFUSAL = "duty bound"
_DUTY_REFUSED = re.compile(
    re.escape(DUTY_REFUSAL) + r" (\d+\.\d{3}) counts over the design grid exceeds the target"
)


def refused_duty_bound(message: str) -> Fraction | None:
    """The rule's duty bound (counts) a refusal for the spec's duty target names, or None
    for any other message."""
    found = _DUTY_REFUSED.search(message)
    return Fraction(found.group(1)) if found else None


def reachable_duty_target(messages: Iterable[str]) -> str | None:
    """The duty target (counts, as a spec value) the simulation and the bench hold the
    rule to when they compare it on a motor whose own method is another and its design
    refused the spec's: the largest bound the refusals name, to 0.01 counts up; None if
    none of them is such a refusal."""
    bounds = [b for m in messages if (b := refused_duty_bound(m)) is not None]
    return f"{math.ceil(max(bounds) * 100) / 100:.2f}" if bounds else None


@dataclass(frozen=True)
class RuleDesign:
    rule: FixedRule
    ranges: tuple[ProvenRange, ...]
    #: Worst bounds over the design grid where the end is decided: duty counts, ticks
    duty_bound: float
    ticks_bound: float
    grid_points: int
    decided_points: int


#: ADC code 0: at or below the offset, where the core reads zero current (it clamps i at
#: 0). The current starts at zero and the end is the first carrier boundary, where the
#: easing -rho g / (3 (1 - e)) divides a near-cancelling sum of terms of order
#: q = (-phi_1/4) X / rho by 3 (1 - e) ~ 3 y_1: on a motor of L/R = 7.8 s at 2.5 kHz
#: (q 1.6e7 counts, 3 y_1 1.5e-4) the integer rule was 36.7 counts off there and its bound
#: is 681 counts, while at the grid's lowest current, 1 code, the commutation does not
#: finish (no easing) and the design had claimed 0.576 counts.
ZERO_CURRENT_CODE = 0


def design_grid(c: RuleConstants, braking_current_codes: int) -> list[RuleInputs]:
    """Speeds (geometric), bus min/mid/max, zero current and braking currents from 1 code
    to the spec's maximum and on to the ADC's full scale (the core computes any current
    it is given), and seeded random points of the same box."""
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
    codes = [ZERO_CURRENT_CODE, *(c.current_offset + i for i in currents)]
    grid = [RuleInputs(t, b, code) for t in periods for b in buses for code in codes]
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


def prove_formats(rule: FixedRule, limits: CoreLimits) -> tuple[ProvenRange, ...]:
    """Prove the printed IR of these formats. Raises ProofError."""
    bus_fn, timing, _ = functions(rule, limits, rule.constants.current)
    prover = new_prover((bus_fn, timing))
    bus = prove_function(prover, bus_fn)
    prove_function(prover, timing, {f"bus.{k}": v for k, v in bus.struct_returns.items()})
    return prover.ranges


def _ramp_bits(c: RuleConstants) -> int:
    """fq: Y1 N = y_1 N < 2^(32 - fq) must hold for the largest N."""
    top = c.step_decay * c.periods(c.period_high)
    fq = 1
    while top * 2 ** (32 - fq) >= 2**32:
        fq += 1
    return fq


def _formats(c: RuleConstants, limits: CoreLimits) -> tuple[FixedRule, tuple[ProvenRange, ...]]:
    if c.periods(c.period_low) < 1:
        needed = next(t for t in range(c.period_low, 2**20) if c.periods(t) >= 1)
        raise SectorTooShortError(
            f"the shortest sector ({c.period_low} ticks), less the {c.guard_ticks}-tick guard"
            " and the hall.sector_shortening margin a commutation ends by before the sector"
            " does, is shorter than one PWM period"
            f" ({float(c.carrier_ticks):g} ticks): the commutation cannot end on a carrier"
            " boundary",
            needed,
        )
    fq = _ramp_bits(c)
    reasons = []
    for fc in range(MAX_COUNTS_FRAC_BITS, MIN_COUNTS_FRAC_BITS - 1, -1):
        if c.k_x * 2**fc / c.bus_low >= 2**32:
            continue
        for fs in range(MAX_GROWTH_FRAC_BITS, -1, -1):
            rule = build_fixed_rule(c, fc, fq, fs)
            try:
                return rule, prove_formats(rule, limits)
            except ProofError as exc:
                reasons.append(f"Q{fc}, growth Q{fc + fs}: {exc}")
    if not reasons:  # every format's X numerator overflowed before any was tried
        raise RuleFormatError(
            "no counts format fits: X's numerator K_X 2^fc / B at the lowest bus code"
            f" ({float(c.k_x / c.bus_low):.4g} duty counts x Hall ticks, the same at every"
            f" speed) needs more than 32 bits even in whole counts (Q{MIN_COUNTS_FRAC_BITS}; a"
            " higher PWM frequency or a slower Hall clock shrinks it)"
        )
    raise RuleFormatError("no counts format fits: " + "; ".join(reasons[-3:]))


def worst_bounds(rule: FixedRule, grid: list[RuleInputs]) -> tuple[float, float, int]:
    """(worst duty bound over every grid point, worst time bound where the end is
    decided and the commutation ends within the sector, those points). `verify` checks
    the duties everywhere, at the end the core chose; only the time is relaxed where the
    end is not decided. (Both bounds had been taken where the end is decided alone: a
    motor of L/R = 5 s, whose core decides the end at no finished point, claimed 0
    counts and 0 ticks over an empty set, and `verify` found its duties 507 counts off.)
    A bound the analysis cannot evaluate counts as unbounded."""
    ref = reference_points(rule.constants, grid)
    b = bounds(rule, ref)
    duty = np.where(np.isnan(b.duty_counts), np.inf, b.duty_counts)
    use = b.decided & ((ref.flags & FLAG_NOT_FINISHED) == 0)
    ticks = float(np.where(np.isnan(b.ticks), np.inf, b.ticks)[use].max()) if use.any() else 0.0
    return float(duty.max()), ticks, int(use.sum())


def design_rule(c: RuleConstants, braking_current_codes: int, limits: CoreLimits) -> RuleDesign:
    rule, ranges = _formats(c, limits)
    grid = design_grid(c, braking_current_codes)
    duty, ticks, used = worst_bounds(rule, grid)
    if duty > c.duty_target_counts:
        # printed rounded up: a target read back from it must meet the bound (3.2300x
        # printed 3.230 made init write 3.23, which the design refused again)
        shown = math.ceil(duty * 1000) / 1000 if math.isfinite(duty) else duty
        raise RuleFormatError(
            f"{DUTY_REFUSAL} {shown:.3f} counts over the design grid exceeds the target"
            f" {float(c.duty_target_counts):g}"
        )
    if ticks > c.time_target_ticks:
        raise RuleFormatError(f"time bound {ticks:.2f} ticks exceeds the target")
    return RuleDesign(rule, ranges, duty, ticks, len(grid), used)

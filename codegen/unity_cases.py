"""Test vectors for the generated Unity tests, one per behaviour.

A case is a set of core inputs and the outputs the exact symbolic model expects, with
the tolerance the fixed-point design promises for each numeric output. Switch patterns,
the sector and the flags have no tolerance: they must match exactly.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from fractions import Fraction

import numpy as np

from codegen.derivation.paper import Derivation
from codegen.fixedpoint.design import FixedPointDesign
from codegen.fixedpoint.scaling import Scaling
from codegen.improved_r_rule.accuracy import point_bound
from codegen.improved_r_rule.context import rule_design
from codegen.improved_r_rule.design import RuleDesign
from codegen.improved_r_rule.reference import FLAG_NOT_FINISHED as RULE_NOT_FINISHED
from codegen.improved_r_rule.reference import RuleInputs
from codegen.reference import (
    FLAG_TIME_CLAMPED,
    ExactModel,
    Expected,
    build_model,
    expected,
    operating_codes,
    time_interval,
)
from codegen.spec_model import Spec


@dataclass(frozen=True)
class UnityCase:
    name: str  # C identifier fragment: test_bldc_commutate_should_<name>
    group: str  # "sector", "boundary", "saturation", "invalid"
    comment: str  # where the expected values come from (equation, physical point)
    hall_code: int
    previous_hall_code: int
    hall_period_ticks: int
    bus_voltage_adc: int
    phase_current_adc: int
    main_duty_counts: int
    turn_on_compare: int  # exact model, rounded to the nearest count
    turn_off_compare: int
    commutation_ticks: int
    turn_on_tolerance: int  # counts / ticks the design promises (ceil of its bound)
    turn_off_tolerance: int
    commutation_tolerance: int
    turn_on_switch: int
    turn_off_switch: int
    sector: int
    flags: int


def _ticks_at(sc: Scaling, speed_rpm: Fraction) -> int:
    ticks = Fraction(10) * Fraction(str(sc.hall_clock_hz)) / (sc.pole_pairs * speed_rpm)
    return math.floor(ticks + Fraction(1, 2))


def _unity_case(
    name: str,
    group: str,
    comment: str,
    inputs: tuple[int, int, int, int, int, int],
    exp: Expected,
    ticks: int,
    tolerance: int,
    flags: int,
) -> UnityCase:
    """A case from the model's expectation at one input vector: duties rounded to the
    nearest count, tolerance 1 (every design's duty bound is below 1)."""
    hall, previous, period, bus, current, duty = inputs
    return UnityCase(
        name=name,
        group=group,
        comment=comment,
        hall_code=hall,
        previous_hall_code=previous,
        hall_period_ticks=period,
        bus_voltage_adc=bus,
        phase_current_adc=current,
        main_duty_counts=duty,
        turn_on_compare=math.floor(float(exp.turn_on[0]) + 0.5),
        turn_off_compare=math.floor(float(exp.turn_off[0]) + 0.5),
        commutation_ticks=ticks,
        turn_on_tolerance=1 if exp.active[0] else 0,
        turn_off_tolerance=1 if exp.active[0] else 0,
        commutation_tolerance=tolerance,
        turn_on_switch=int(exp.turn_on_switch[0]),
        turn_off_switch=int(exp.turn_off_switch[0]),
        sector=int(exp.sector[0]),
        flags=flags,
    )


def _case(
    model: ExactModel,
    fx: FixedPointDesign,
    name: str,
    group: str,
    comment: str,
    inputs: tuple[int, int, int, int, int, int],
) -> UnityCase:
    """Expected outputs of one input vector from the exact model.

    Duties: the exact value rounded, tolerance 1 (the design's bound is below 1/2 plus
    the quantisation, so the emitted count is the rounded value or its neighbour). The
    commutation time is Eq. 20 at the emitted duties, so its tolerance covers every
    duty pair the core may emit and, for each, the interval the design allows.
    """
    period, current = inputs[2], inputs[4]
    col = [np.array([v], dtype=np.int64) for v in inputs]
    exp = expected(model, col[0], col[1], col[2], col[3], col[4], col[5])
    on_exact, off_exact = float(exp.turn_on[0]), float(exp.turn_off[0])
    flags = int(exp.flags[0])
    ticks, tolerance = 0, 0
    if bool(exp.active[0]):
        bound = float(fx.duty_error_bound_counts)
        candidates = [
            (on, off)
            for on in range(math.floor(on_exact - bound), math.ceil(on_exact + bound) + 1)
            for off in range(math.floor(off_exact - bound), math.ceil(off_exact + bound) + 1)
            if abs(on - on_exact) <= bound and abs(off - off_exact) <= bound
        ]
        lows, highs, clamped = [], [], set()
        for on, off in candidates:
            a = np.array([on], dtype=np.int64)
            b = np.array([off], dtype=np.int64)
            _, w = model.commutation_time(col[2], exp.bus, col[4], a, b)
            lo, hi = time_interval(model, fx, col[2], exp.bus, col[4], w)
            if current <= model.current_offset:
                lows.append(0.0)
                highs.append(0.0)
                clamped.add(False)
                continue
            lows.append(min(max(float(lo[0]), 0.0), period))
            highs.append(min(float(hi[0]), period))
            if float(lo[0]) > period:
                clamped.add(True)
            elif float(hi[0]) <= period:
                clamped.add(False)
            else:
                clamped.update((True, False))
        if len(clamped) != 1:
            raise ValueError(f"unity case {name}: TIME_CLAMPED is not decided at {inputs}")
        low, high = math.ceil(min(lows) - 1e-6), math.floor(max(highs) + 1e-6)
        ticks = (low + high) // 2
        tolerance = max(ticks - low, high - ticks)
        if clamped.pop():
            flags |= FLAG_TIME_CLAMPED
    return _unity_case(name, group, comment, inputs, exp, ticks, tolerance, flags)


def _rule_case(
    model: ExactModel,
    design: RuleDesign,
    name: str,
    group: str,
    comment: str,
    inputs: tuple[int, int, int, int, int, int],
) -> UnityCase:
    """Expected outputs of one input vector from the resistance-aware rule (improved_r).

    Duties: the exact C(x_c) rounded, tolerance 1 (the design's bound is below 1). The
    time: min(x_c T, T) rounded, tolerance the point's own proven bound. The threshold
    flags must be decided at the vector: the reference farther from each threshold
    than the error bound."""
    period, bus, current = inputs[2], inputs[3], inputs[4]
    col = [np.array([v], dtype=np.int64) for v in inputs]
    exp = expected(model, col[0], col[1], col[2], col[3], col[4], col[5])
    flags = int(exp.flags[0])
    ticks, tolerance = 0, 0
    if bool(exp.active[0]) and exp.rule is not None:
        ref = exp.rule.result(0, period)
        bound = point_bound(design.rule, RuleInputs(period, bus, current), ref)
        total = float(exp.rule.total[0])
        p = model.period_counts
        margin = bound.duty_counts
        undecided = [abs(total - edge) <= margin for edge in (0.0, float(p), 2.0 * p)]
        finished = not ref.outputs.flags & RULE_NOT_FINISHED
        if any(undecided) or (finished and ref.fraction + bound.fraction_error >= 1.0):
            raise ValueError(f"unity case {name}: a flag is not decided at {inputs}")
        if not finished:
            flags |= FLAG_TIME_CLAMPED
        exact = min(ref.ticks_exact, period)
        ticks = math.floor(exact + 0.5)
        tolerance = math.ceil(abs(exact - ticks) + bound.ticks)
    return _unity_case(name, group, comment, inputs, exp, ticks, tolerance, flags)


def unity_cases(spec: Spec, derivation: Derivation, fx: FixedPointDesign) -> tuple[UnityCase, ...]:
    """Sector transitions at both test speeds, the segment boundary, saturation and
    invalid codes, with expectations from codegen.reference."""
    sc = fx.scaling
    model = build_model(spec, derivation, sc)
    bus, current, duty = operating_codes(spec, sc)
    cases: list[UnityCase] = []
    if spec.controller.method == "improved_r":
        design = rule_design(spec, sc)

        def case(
            name: str, group: str, comment: str, inputs: tuple[int, int, int, int, int, int]
        ) -> UnityCase:
            return _rule_case(model, design, name, group, comment, inputs)

        rule = "resistance-aware pair and t_com (improved_r)"
    else:

        def case(
            name: str, group: str, comment: str, inputs: tuple[int, int, int, int, int, int]
        ) -> UnityCase:
            return _case(model, fx, name, group, comment, inputs)

        rule = "Eq. 18 duties, Eq. 20 time"
    sequence = spec.hall.sequence
    for point in spec.operating_points:
        period = _ticks_at(sc, point.speed_rpm)
        rpm = f"{float(point.speed_rpm):g} rpm"
        for direction, step in (("forward", 1), ("reverse", -1)):
            for sector in range(6):
                previous = sequence[(sector - step) % 6]
                edge = derivation.switching.edge_into(sector, direction)
                cases.append(
                    case(
                        f"commutate_{direction}_into_sector_{sector}_at_{int(point.speed_rpm)}_rpm",
                        "sector",
                        f"{edge.describe()} at {rpm}: {rule}",
                        (sequence[sector], previous, period, bus, current, duty),
                    )
                )
    cut = -(-model.boundary_lhs // (model.boundary_rhs * bus))
    # The rule's segment follows S(x_c) = P, not Eq. 18's cut: no exact boundary case.
    eq18_cuts = () if spec.controller.method == "improved_r" else (cut - 1, cut)
    for period, what in zip(eq18_cuts, ("last_high_speed", "first_low_speed"), strict=False):
        cases.append(
            _case(
                model,
                fx,
                f"take_the_{what}_segment_at_period_{period}",
                "boundary",
                f"Eq. 18 cut-off 4E = U_d falls between periods {cut - 1} and {cut}",
                (sequence[1], sequence[0], period, bus, current, duty),
            )
        )
    forward = (sequence[1], sequence[0])
    mid = (sc.period_min_ticks + sc.period_max_ticks) // 2
    for name, comment, inputs in (
        (
            "saturate_a_low_bus",
            "bus below its minimum: saturated and flagged",
            (*forward, mid, sc.bus_code_min - 100, current, duty),
        ),
        (
            "switch_off_over_voltage",
            "bus above its maximum: every switch off",
            (*forward, mid, sc.bus_code_max + 1, current, duty),
        ),
        (
            "switch_off_over_speed",
            "period below the top speed's: every switch off",
            (*forward, sc.period_min_ticks - 1, bus, current, duty),
        ),
        (
            "flag_a_speed_below_the_minimum",
            "period above the slowest speed's: flagged"
            + (
                ", the rule uses the slowest"
                if spec.controller.method == "improved_r"
                else ", exact"
            ),
            (*forward, sc.period_max_ticks + 1000, bus, current, duty),
        ),
        (
            "give_no_commutation_time_without_current",
            "zero current: t_com = 0",
            (*forward, mid, bus, sc.current_offset_code, duty),
        ),
        (
            "give_no_commutation_time_for_a_negative_current",
            "current below the offset",
            (*forward, mid, bus, sc.current_offset_code - 50, duty),
        ),
        (
            "flag_a_current_above_the_range",
            "current above the braking range: exact, flagged",
            (*forward, mid, bus, sc.current_offset_code + sc.current_code_max + 10, duty),
        ),
    ):
        cases.append(case(name, "saturation", comment, inputs))
    for name, comment, inputs in (
        ("switch_off_on_hall_000", "Hall code 000", (0, sequence[0], mid, bus, current, duty)),
        ("switch_off_on_hall_111", "Hall code 111", (7, sequence[0], mid, bus, current, duty)),
        (
            "switch_off_after_hall_000",
            "previous code 000",
            (sequence[1], 0, mid, bus, current, duty),
        ),
        (
            "switch_off_on_a_skipped_sector",
            "a jump of two sectors",
            (sequence[2], sequence[0], mid, bus, current, duty),
        ),
        (
            "switch_off_on_a_repeated_code",
            "no sector change",
            (sequence[0], sequence[0], mid, bus, current, duty),
        ),
        (
            "switch_off_on_a_code_above_7",
            "not a 3-bit code",
            (9, sequence[0], mid, bus, current, duty),
        ),
    ):
        cases.append(case(name, "invalid", comment, inputs))
    return tuple(cases)

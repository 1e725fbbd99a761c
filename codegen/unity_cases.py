"""Test vectors for the generated Unity tests, one per behaviour.

A case is a set of core inputs and what the independent oracle (`oracle/`) expects of
them, with tolerances from the spec's `accuracy:` section alone (never the design's own
bounds): a duty within accuracy.duty_counts of the exact one, the commutation time within
the time target of the exact value at any duty pair the core may emit (or, where the
spec declares the time ill-conditioned, of its window); for improved_r, any carrier
boundary that a time within that target of the turn-off current's zero gives, with
the eased pair there. Switches and sector must match
exactly, and so must every flag the oracle decides; a flag that depends on a value
within its tolerance of a threshold is masked out of the comparison.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from fractions import Fraction

import numpy as np

from codegen.abi import FLAG
from codegen.spec_model import Spec
from oracle.model import Oracle, oracle


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
    turn_on_compare: int
    turn_off_compare: int
    commutation_ticks: int
    turn_on_tolerance: int
    turn_off_tolerance: int
    commutation_tolerance: int
    turn_on_switch: int
    turn_off_switch: int
    sector: int
    flags: int
    flags_mask: int  # the decided flag bits (0xFF: every bit)


Inputs = tuple[int, int, int, int, int, int]


def _mid_range(low: float, high: float) -> tuple[int, int]:
    """(expected, tolerance) of an integer that must lie in [low, high]."""
    lo, hi = math.ceil(low - 1e-9), math.floor(high + 1e-9)
    if hi < lo:
        lo = hi = round((low + high) / 2)
    expected = (lo + hi) // 2
    return expected, max(expected - lo, hi - expected)


class _CaseMaker:
    def __init__(self, o: Oracle) -> None:
        self.o = o
        a = o.spec.accuracy
        self.duty = float(a.duty_counts)
        self.time = float(a.commutation_time_ticks)
        self.above = None if a.ill_conditioned_above is None else float(a.ill_conditioned_above)
        self.counts = None if a.ill_conditioned_counts is None else float(a.ill_conditioned_counts)

    def case(self, name: str, group: str, comment: str, inputs: Inputs) -> UnityCase:
        o = self.o
        hall, previous, period, bus, current, main = (np.array([v], dtype=np.int64) for v in inputs)
        dec = o.decide(hall, previous, period, bus, current, main)
        base = {
            "name": name,
            "group": group,
            "comment": comment,
            "hall_code": inputs[0],
            "previous_hall_code": inputs[1],
            "hall_period_ticks": inputs[2],
            "bus_voltage_adc": inputs[3],
            "phase_current_adc": inputs[4],
            "main_duty_counts": inputs[5],
            "turn_on_switch": int(dec.on_switch[0]),
            "turn_off_switch": int(dec.off_switch[0]),
            "sector": int(dec.sector[0]),
        }
        if not dec.active[0]:
            flags = FLAG["INPUT_SATURATED"] if dec.valid[0] else FLAG["INVALID_HALL"]
            return UnityCase(
                **base,
                turn_on_compare=0,
                turn_off_compare=0,
                commutation_ticks=0,
                turn_on_tolerance=0,
                turn_off_tolerance=0,
                commutation_tolerance=0,
                flags=flags,
                flags_mask=0xFF,
            )
        saturated = FLAG["INPUT_SATURATED"] if dec.saturated[0] else 0
        measured = min(inputs[2], o.u.hall_counter_max)
        if o.method == "improved_r":
            values = self._rule(dec.period, dec.bus, current, measured)
        else:
            values = self._paper(dec.period, dec.bus, current, main, measured)
        (on, on_tol), (off, off_tol), (ticks, t_tol), flags, mask = values
        return UnityCase(
            **base,
            turn_on_compare=on,
            turn_off_compare=off,
            commutation_ticks=ticks,
            turn_on_tolerance=on_tol,
            turn_off_tolerance=off_tol,
            commutation_tolerance=t_tol,
            flags=flags | saturated,
            flags_mask=mask,
        )

    def _time_window(
        self, t: float, sensitivity: float, edges: tuple[float, float]
    ) -> tuple[float, float]:
        if self.above is not None and sensitivity > self.above:
            return min(edges[0], t) - self.time, max(edges[1], t) + self.time
        return t - self.time, t + self.time

    def _paper(self, period, bus, current, main, measured):  # type: ignore[no-untyped-def]
        o = self.o
        on, off, high, fail = o.duties(period, bus, main)
        p = o.u.pwm_counts
        ons = range(max(math.ceil(on[0] - self.duty), 0), min(math.floor(on[0] + self.duty), p) + 1)
        offs = range(
            max(math.ceil(off[0] - self.duty), 0), min(math.floor(off[0] + self.duty), p) + 1
        )
        limit = float(o.u.latest_end(int(period[0])))  # the latest end
        lows, highs = [], []
        for a in ons:
            for b in offs:
                on_c, off_c = np.array([float(a)]), np.array([float(b)])
                t, w = o.eq20(period, bus, current, on_c, off_c)
                sens = float(t[0] / w[0]) if w[0] > 0 else math.inf
                edges = (0.0, 0.0)
                if self.counts is not None:
                    fast, _ = o.eq20(period, bus, current, on_c, off_c, w_shift=self.counts)
                    slow, _ = o.eq20(period, bus, current, on_c, off_c, w_shift=-self.counts)
                    edges = (float(fast[0]), float(slow[0]))
                lo, hi = self._time_window(float(t[0]), sens, edges)
                lows.append(lo)
                highs.append(hi)
        amps = float(o.amps(current)[0])
        flags = (FLAG["HIGH_SPEED"] if high[0] else 0) | (
            FLAG["FAIL_AREA_CLAMPED"] if fail[0] else 0
        )
        mask = 0xFF
        if amps <= 0:
            ticks = (0, 0)
        else:
            low, high_t = min(lows), max(highs)
            if low > limit:
                flags |= FLAG["TIME_CLAMPED"]
            elif high_t >= limit:
                mask &= ~FLAG["TIME_CLAMPED"]
            ticks = _mid_range(max(min(low, limit), 0.0), min(high_t, limit))
        duty_tol = math.floor(self.duty + 0.5)
        return (round(on[0]), duty_tol), (round(off[0]), duty_tol), ticks, flags, mask

    def _rule(self, period, bus, current, measured):  # type: ignore[no-untyped-def]
        """The rule ends on a carrier boundary after the zero of the turn-off current:
        every boundary a time within the target of that zero (or of the declared
        window) gives is allowed, and the duties are the eased pair at any of them."""
        o = self.o
        com = o.rule(period, bus, current)
        x0, _ = com.zero()
        probe = max(self.counts or 0.0, 0.01)
        xm, _ = com.zero(-probe)
        xp, _ = com.zero(+probe)
        t_used = float(period[0])
        sens = t_used * abs(float(xp[0] - xm[0])) / (2 * probe)
        t0 = float(x0[0]) * t_used
        edges = (min(float(xm[0]), float(xp[0])) * t_used, max(float(xm[0]), float(xp[0])) * t_used)
        lo, hi = self._time_window(t0, sens, edges)
        first = int(com.end_after(np.array([max(lo, 0.0)]))[0])
        last = int(com.end_after(np.array([hi]))[0])
        periods = int(com.periods[0])
        limit = float(o.u.latest_end(int(measured)))  # the latest end
        ends = list(range(first, last + 1))
        # round(m tau) half up, as the core rounds it: a carrier of 62.5 ticks ends the
        # first period at 63 (Python's round() would give the even 62)
        carrier = Fraction(o.u.carrier_ticks)
        times = [
            limit if m > periods else min(math.floor(m * carrier + Fraction(1, 2)), limit)
            for m in ends
        ]
        ticks = _mid_range(min(times), max(times))
        pairs = com.pair_at(np.array(ends, dtype=np.int64))
        p = o.u.pwm_counts
        on = _mid_range(float(pairs.on.min()) - self.duty, float(pairs.on.max()) + self.duty)
        off = _mid_range(float(pairs.off.min()) - self.duty, float(pairs.off.max()) + self.duty)
        s_min = float(pairs.total.min()) - self.duty
        s_max = float(pairs.total.max()) + self.duty
        flags, mask = 0, 0xFF
        for bit, must, must_not in (
            (FLAG["HIGH_SPEED"], s_max < p, s_min > p),
            (FLAG["FAIL_AREA_CLAMPED"], s_min > 2 * p or s_max < 0, s_max < 2 * p and s_min > 0),
            (FLAG["TIME_CLAMPED"], first > periods, last <= periods),
        ):
            if must:
                flags |= bit
            elif not must_not:
                mask &= ~bit
        return on, off, ticks, flags, mask


def unity_cases(spec: Spec) -> tuple[UnityCase, ...]:
    """Sector transitions at both test speeds, Eq. 18's cut-off, saturation and invalid
    codes, with expectations from the oracle."""
    o = oracle(spec)
    maker = _CaseMaker(o)
    case = maker.case
    bus = o.u.bus_code(spec.inverter.bus_voltage_nominal_v)
    current = o.u.current_code(spec.controller.braking_current_nominal_a)
    duty = math.floor(spec.operating_points[0].main_duty * o.u.pwm_counts + Fraction(1, 2))
    method = spec.controller.method
    rule = (
        "resistance-aware pair and t_com (improved_r)"
        if method == "improved_r"
        else "Eqs. 16/18 duties, Eq. 20 time"
    )
    sequence = spec.hall.sequence
    cases: list[UnityCase] = []
    for point in spec.operating_points:
        period = math.floor(o.u.ticks_at(point.speed_rpm) + Fraction(1, 2))
        rpm = f"{float(point.speed_rpm):g} rpm"
        for direction, step in (("forward", 1), ("reverse", -1)):
            for sector in range(6):
                previous = sequence[(sector - step) % 6]
                cases.append(
                    case(
                        f"commutate_{direction}_into_sector_{sector}_at_{int(point.speed_rpm)}_rpm",
                        "sector",
                        f"{direction} edge into sector {sector} at {rpm}: {rule}",
                        (sequence[sector], previous, period, bus, current, duty),
                    )
                )
    forward = (sequence[1], sequence[0])
    if method != "improved_r":
        limit = 4 * o.motor.k_e * 60 * o.u.hall_hz / (6 * o.u.pole_pairs * o.u.volts(bus))
        cut = -((-limit.numerator) // limit.denominator)
        for period, what in ((cut - 1, "last_high_speed"), (cut, "first_low_speed")):
            cases.append(
                case(
                    f"take_the_{what}_segment_at_period_{period}",
                    "boundary",
                    f"Eq. 18 cut-off 4E = U_d falls between periods {cut - 1} and {cut}",
                    (*forward, period, bus, current, duty),
                )
            )
    lim = o.lim
    mid = (lim.period_min + lim.period_max) // 2
    zero = o.u.current_code(Fraction(0))
    for name, comment, inputs in (
        (
            "saturate_a_low_bus",
            "bus below its minimum: saturated and flagged",
            (*forward, mid, max(lim.bus_min - 100, 0), current, duty),
        ),
        (
            "switch_off_over_voltage",
            "bus above its maximum: every switch off",
            (*forward, mid, lim.bus_max + 1, current, duty),
        ),
        (
            "switch_off_over_speed",
            "period below the top speed's: every switch off",
            (*forward, lim.period_min - 1, bus, current, duty),
        ),
        (
            "flag_a_speed_below_the_minimum",
            "period above the slowest speed's: flagged",
            (*forward, min(lim.period_max + 1000, o.u.hall_counter_max), bus, current, duty),
        ),
        (
            "give_no_commutation_time_without_current",
            "zero current: t_com = 0",
            (*forward, mid, bus, max(zero - 1, 0), duty),  # the offset's code, at code 0
        ),
        (
            "flag_a_current_above_the_range",
            "current above the braking range: flagged",
            (*forward, mid, bus, min(lim.current_high + 1, o.u.adc_max), duty),
        ),
        (
            "saturate_a_current_above_the_adc",
            "current code above the ADC's full scale: saturated, flagged",
            (*forward, mid, bus, 0xFFFF, duty),
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
        (
            "switch_off_on_codes_above_7_that_alias_a_valid_pair",
            "8 + a valid code, both fields",
            (sequence[1] + 8, sequence[0] + 8, mid, bus, current, duty),
        ),
    ):
        cases.append(case(name, "invalid", comment, inputs))
    return tuple(cases)

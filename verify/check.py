"""Compare the generated core's outputs with the oracle, within the spec's tolerances.

Every tolerance comes from the spec's `accuracy:` section (`Tolerances`), never from the
generator. Per output the verifier keeps the points checked, the largest error and
where it happened, the bound, and a verdict; a point outside its bound is a failure.

* switch pattern, sector, the safe state's zero outputs, and every flag that is decided
  exactly (invalid Hall, input saturation, Eq. 18's segment, the fail area of Eq. 16):
  exact;
* duties: |C - exact| <= accuracy.duty_counts;
* commutation time, against the exact value at the duties the core emitted (Eq. 20 for
  the paper's methods, the rule's zero for improved_r), saturated to the sector less the
  end guard (`oracle.units`) as the contract says: within
  accuracy.commutation_time_ticks; where the spec declares a
  relaxation and the time is ill-conditioned there (one count of duty moves it by more
  than `ill_conditioned_above` ticks), within the target of the exact value for some
  duty error up to `ill_conditioned_counts` counts (its window), reported as the share
  of that window used;
* TIME_CLAMPED (and, for improved_r, HIGH_SPEED and FAIL_AREA_CLAMPED, which depend on
  the computed time): wherever the window decides them.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from fractions import Fraction

import numpy as np
import numpy.typing as npt

from codegen.spec_model import Spec
from oracle.model import Oracle
from verify.points import FIELDS

Floats = npt.NDArray[np.float64]
Ints = npt.NDArray[np.int64]
Bools = npt.NDArray[np.bool_]
SLACK = 1e-6  # float64 evaluation of the oracle, far below one LSB


@dataclass(frozen=True)
class Tolerances:
    """The spec's error budget (accuracy:)."""

    duty_counts: float
    time_ticks: float
    ill_conditioned_above: float | None
    ill_conditioned_counts: float | None

    @property
    def relaxed(self) -> bool:
        return self.ill_conditioned_above is not None


def tolerances(spec: Spec) -> Tolerances:
    a = spec.accuracy
    return Tolerances(
        float(a.duty_counts),
        float(a.commutation_time_ticks),
        None if a.ill_conditioned_above is None else float(a.ill_conditioned_above),
        None if a.ill_conditioned_counts is None else float(a.ill_conditioned_counts),
    )


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

    def add(self, errors: Floats, failed: Bools, inputs: np.ndarray) -> None:
        """Count the points; keep the largest error, and where it is: the worst failing
        point once any point has failed, else the worst point."""
        self.points += int(errors.size)
        new_failures = int(np.count_nonzero(failed))
        if errors.size == 0:
            return
        candidates = np.where(failed, errors, -np.inf) if new_failures else errors
        k = int(np.argmax(candidates))
        first_failure = new_failures > 0 and self.failures == 0
        keeps_a_failure = self.failures > 0 and new_failures == 0
        self.failures += new_failures
        larger = float(errors[k]) >= self.max_error and not keeps_a_failure
        if first_failure or larger or not self.worst_inputs:
            self.worst_inputs = {n: int(inputs[n][k]) for n in FIELDS}
        self.max_error = max(self.max_error, float(errors.max()))


@dataclass(frozen=True)
class Evaluated:
    """Per-point results of one input set, for the report's plot."""

    speed_rpm: Floats
    on_error: Floats
    off_error: Floats
    time_error: Floats
    relaxed: Bools


def new_checks(tol: Tolerances) -> dict[str, OutputCheck]:
    checks = {
        "turn_on": OutputCheck("D_on (turn_on_compare)", "counts", tol.duty_counts),
        "turn_off": OutputCheck("D_off (turn_off_compare)", "counts", tol.duty_counts),
        "commutation_time": OutputCheck(
            "t_com" + (", well-conditioned" if tol.relaxed else ""), "ticks", tol.time_ticks
        ),
    }
    if tol.relaxed:
        checks["commutation_time_relaxed"] = OutputCheck(
            f"t_com, ill-conditioned (> {tol.ill_conditioned_above:g} ticks/count)",
            "of window",
            1.0,
            note=f"declared relaxation: exact for a duty error up to {tol.ill_conditioned_counts:g} counts, "
            f"then within {tol.time_ticks:g} ticks",
        )
    checks.update(
        {
            "end_guard": OutputCheck(
                "t_com ends the guard and the margin before the sector does",
                "ticks over",
                None,
                note="t_com <= L(min(T, counter)) exactly, L(T) = T - ceil(T / 2^k) - G,"
                " G = ceil((dead time + 4 us) f_hall), 2^-k >= hall.sector_shortening:"
                " the next edge, up to that much early, switches on the other switch of the"
                " leg the end switched off",
            ),
            "pattern": OutputCheck("switch pattern and sector", "mismatches", None),
            "safe_state": OutputCheck("safe state: zero duties and time", "mismatches", None),
            "flags": OutputCheck("flags", "mismatches", None),
        }
    )
    return checks


def column(array: np.ndarray, name: str) -> Ints:
    return np.asarray(array[name], dtype=np.int64)


def _mismatch(checks: dict[str, OutputCheck], key: str, bad: Bools, inputs: np.ndarray) -> None:
    checks[key].add(bad.astype(np.float64), bad, inputs)


def check_set(
    o: Oracle,
    tol: Tolerances,
    flag_bits: dict[str, int],
    inputs: np.ndarray,
    c_out: np.ndarray,
    checks: dict[str, OutputCheck],
) -> Evaluated:
    cols = {n: column(inputs, n) for n in FIELDS}
    hall, previous = cols["hall_code"], cols["previous_hall_code"]
    period, bus, current, main = (
        cols["hall_period_ticks"],
        cols["bus_voltage_adc"],
        cols["phase_current_adc"],
        cols["main_duty_counts"],
    )
    dec = o.decide(hall, previous, period, bus, current, main)
    on_c, off_c = column(c_out, "turn_on_compare"), column(c_out, "turn_off_compare")
    ticks_c, flags_c = column(c_out, "commutation_ticks"), column(c_out, "flags")
    f = flag_bits

    pattern = (
        (column(c_out, "turn_on_switch") != dec.on_switch)
        | (column(c_out, "turn_off_switch") != dec.off_switch)
        | (column(c_out, "sector") != dec.sector)
    )
    _mismatch(checks, "pattern", pattern, inputs)
    inactive = ~dec.active
    nonzero = inactive & ((on_c != 0) | (off_c != 0) | (ticks_c != 0))
    _mismatch(checks, "safe_state", nonzero[inactive], inputs[inactive])

    expected_inactive = np.where(dec.valid, f["INPUT_SATURATED"], f["INVALID_HALL"])
    flags_wrong = inactive & (flags_c != expected_inactive)

    act = np.flatnonzero(dec.active)
    n = act.size
    on_err = np.zeros(inputs.size)
    off_err = np.zeros(inputs.size)
    t_err = np.zeros(inputs.size)
    relaxed_mask = np.zeros(inputs.size, dtype=bool)
    if n:
        # exact, not within the time target: a safety bound of the bridge, not an accuracy
        latest = o.u.latest_end(np.minimum(period[act], o.u.hall_counter_max).astype(np.int64))
        over = np.maximum(ticks_c[act] - latest, 0).astype(np.float64)
        checks["end_guard"].add(over, over > 0, inputs[act])
        sub = _ActiveSet(o, tol, f, dec, act, cols, on_c, off_c, ticks_c, flags_c)
        result = sub.evaluate()
        on_err[act], off_err[act], t_err[act] = result.on_err, result.off_err, result.t_forward
        relaxed_mask[act] = result.relaxed
        pts = inputs[act]
        checks["turn_on"].add(result.on_err, result.on_err > tol.duty_counts + SLACK, pts)
        checks["turn_off"].add(result.off_err, result.off_err > tol.duty_counts + SLACK, pts)
        well = ~result.relaxed
        checks["commutation_time"].add(
            result.t_forward[well], result.t_forward[well] > tol.time_ticks + SLACK, pts[well]
        )
        if tol.relaxed:
            r = result.relaxed
            checks["commutation_time_relaxed"].add(
                result.window_use[r], result.window_use[r] > 1 + SLACK, pts[r]
            )
        flags_wrong[act] |= result.flags_wrong
    _mismatch(checks, "flags", flags_wrong, inputs)
    speed = (
        _exact_speeds(o, period)
        if period.size < 50_000
        else (float(60 * o.u.hall_hz / (6 * o.u.pole_pairs)) / np.maximum(period, 1))
    )
    return Evaluated(speed, on_err, off_err, t_err, relaxed_mask)


def _exact_speeds(o: Oracle, period: Ints) -> Floats:
    """float(o.u.rpm(max(T, 1))) of each period: 60 f_hall / (6 p T) is a ratio of two
    integers, which Python's integer division rounds to the nearest float exactly as
    float() of that Fraction does (without a Fraction a point)."""
    hall_hz = Fraction(o.u.hall_hz)
    numerator = 60 * hall_hz.numerator
    per_tick = 6 * o.u.pole_pairs * hall_hz.denominator
    return np.array([numerator / (per_tick * max(int(t), 1)) for t in period], dtype=np.float64)


@dataclass(frozen=True)
class _Result:
    on_err: Floats
    off_err: Floats
    t_forward: Floats  # |t_C - t*| (exact time saturated to the sector)
    window_use: Floats  # relaxed points: share of the window used (<= 1 passes)
    relaxed: Bools
    flags_wrong: Bools


class _ActiveSet:
    """The active points of a set, evaluated once per distinct (T, B, C, M)."""

    def __init__(
        self,
        o: Oracle,
        tol: Tolerances,
        flag_bits: dict[str, int],
        dec: object,
        act: Ints,
        cols: dict[str, Ints],
        on_c: Ints,
        off_c: Ints,
        ticks_c: Ints,
        flags_c: Ints,
    ) -> None:
        self.o, self.tol, self.f = o, tol, flag_bits
        self.period = dec.period[act]  # type: ignore[attr-defined]
        self.measured = np.minimum(cols["hall_period_ticks"][act], o.u.hall_counter_max)
        self.bus = dec.bus[act]  # type: ignore[attr-defined]
        self.current = cols["phase_current_adc"][act]
        self.main = cols["main_duty_counts"][act]
        self.saturated = dec.saturated[act]  # type: ignore[attr-defined]
        self.on_c, self.off_c = on_c[act].astype(np.float64), off_c[act].astype(np.float64)
        self.ticks_c = ticks_c[act].astype(np.float64)
        self.flags_c = flags_c[act]

    def evaluate(self) -> _Result:
        if self.o.method == "improved_r":
            return self._rule()
        return self._paper()

    # ------------------------------------------------------------ paper methods

    def _paper(self) -> _Result:
        o, tol, f = self.o, self.tol, self.f
        on, off, high, fail = o.duties(self.period, self.bus, self.main)
        on_err, off_err = np.abs(self.on_c - on), np.abs(self.off_c - off)
        t, w = o.eq20(self.period, self.bus, self.current, self.on_c, self.off_c)
        limit = o.u.latest_end(self.period.astype(np.int64)).astype(np.float64)  # the latest end
        t_sat = np.minimum(t, limit)
        forward = np.abs(self.ticks_c - t_sat)
        lo, hi = t - tol.time_ticks, t + tol.time_ticks
        relaxed = np.zeros(t.size, dtype=bool)
        use = np.zeros(t.size)
        if tol.relaxed:
            assert tol.ill_conditioned_above is not None and tol.ill_conditioned_counts is not None
            with np.errstate(divide="ignore", invalid="ignore"):
                sensitivity = np.where(w > 0, t / w, np.inf)
            relaxed = (sensitivity > tol.ill_conditioned_above) & (t > 0)
            d = tol.ill_conditioned_counts
            t_fast, _ = o.eq20(
                self.period, self.bus, self.current, self.on_c, self.off_c, w_shift=+d
            )
            t_slow, _ = o.eq20(
                self.period, self.bus, self.current, self.on_c, self.off_c, w_shift=-d
            )
            lo = np.where(relaxed, t_fast - tol.time_ticks, lo)
            hi = np.where(relaxed, t_slow + tol.time_ticks, hi)
            use = _window_use(self.ticks_c, t_sat, np.minimum(lo, limit), np.minimum(hi, limit))
        amps_positive = t > 0
        must_clamp = amps_positive & (lo > limit)
        must_not = ~amps_positive | (hi < limit)
        clamped = (self.flags_c & f["TIME_CLAMPED"]) != 0
        expected = (
            np.where(self.saturated, f["INPUT_SATURATED"], 0)
            | np.where(high, f["HIGH_SPEED"], 0)
            | np.where(fail, f["FAIL_AREA_CLAMPED"], 0)
        )
        wrong = (
            ((self.flags_c & ~f["TIME_CLAMPED"]) != expected)
            | (must_clamp & ~clamped)
            | (must_not & clamped)
        )
        forward = np.where(relaxed, 0.0, forward)
        return _Result(on_err, off_err, forward, use, relaxed, wrong)

    # ------------------------------------------------------------ improved_r

    def _rule(self) -> _Result:
        """The rule ends on a carrier boundary: the first one after the zero of the
        turn-off current (N + 1 when the current remains at the sector's last whole
        period). The time check asks which boundaries a time within the target of that
        zero (or, where declared, within the relaxation's window) would give; the
        duties are checked at the boundary the core chose, eased as the rule eases them
        there."""
        o, tol, f = self.o, self.tol, self.f
        # one evaluation per distinct (T, B, C): the 12 edges of a point share it
        current = np.minimum(self.current, o.u.adc_max)
        key = (self.period << 32) | (self.bus << 16) | current  # each field < 2^16
        uniq_key, inverse = np.unique(key, return_inverse=True)
        inverse = inverse.ravel()
        uniq = np.stack([uniq_key >> 32, (uniq_key >> 16) & 0xFFFF, uniq_key & 0xFFFF], axis=1)
        com = o.rule(uniq[:, 0], uniq[:, 1], uniq[:, 2])
        d = tol.ill_conditioned_counts if tol.relaxed else 0.0
        probe = max(d or 0.0, 0.01)
        x0, _ = com.zero()
        x_minus, _ = com.zero(-probe)
        x_plus, _ = com.zero(+probe)
        t_used = uniq[:, 0].astype(np.float64)
        sensitivity = t_used * np.abs(x_plus - x_minus) / (2 * probe)
        t0 = x0 * t_used
        lo, hi = t0 - tol.time_ticks, t0 + tol.time_ticks
        relaxed_u = np.zeros(t0.size, dtype=bool)
        if tol.relaxed:
            assert tol.ill_conditioned_above is not None
            relaxed_u = sensitivity > tol.ill_conditioned_above
            edge_lo = np.minimum(x_minus, x_plus) * t_used
            edge_hi = np.maximum(x_minus, x_plus) * t_used
            lo = np.where(relaxed_u, np.minimum(edge_lo, t0) - tol.time_ticks, lo)
            hi = np.where(relaxed_u, np.maximum(edge_hi, t0) + tol.time_ticks, hi)
        exact_end = com.end_after(t0)
        end_lo, end_hi = com.end_after(np.maximum(lo, 0.0)), com.end_after(hi)
        periods = com.periods
        tau = float(o.u.carrier_ticks)
        # the core's end: a carrier boundary, or the whole sector (TIME_CLAMPED)
        flag = self.flags_c
        clamped = (flag & f["TIME_CLAMPED"]) != 0
        rows = inverse
        n_rows = periods[rows]
        core_end = np.where(clamped, n_rows + 1, np.rint(self.ticks_c / tau).astype(np.int64))
        on_grid = np.abs(self.ticks_c - core_end * tau) <= 0.5 + SLACK
        limit = o.u.latest_end(self.measured.astype(np.int64)).astype(np.float64)  # the latest end
        core_time = np.where(clamped, limit, self.ticks_c)
        expected_time = np.where(
            exact_end[rows] > n_rows, limit, np.minimum(exact_end[rows] * tau, limit)
        )
        allowed = (core_end >= end_lo[rows]) & (core_end <= end_hi[rows])
        relaxed = relaxed_u[rows]
        forward = np.abs(core_time - expected_time)
        # a boundary outside the allowed ones, or a time that is no boundary, fails
        bad_end = ~allowed | (~clamped & ~on_grid) | (clamped & (self.ticks_c != limit))
        forward = np.where(bad_end, np.maximum(forward, tol.time_ticks + 1.0), 0.0)
        # relaxed points: the share of the allowed boundaries the core's end uses
        ex = exact_end[rows]
        above = core_end >= ex
        span = np.where(above, end_hi[rows] - ex, ex - end_lo[rows]).astype(np.float64)
        gap = np.abs(core_end - ex).astype(np.float64)
        with np.errstate(divide="ignore", invalid="ignore"):
            use = np.where(gap == 0, 0.0, np.where(span > 0, gap / span, np.inf))
        use = np.where(bad_end, np.maximum(use, 1.0 + 2 * SLACK), use)
        # duties at the core's own end (N + 1: the pair at x_N, uneased): evaluated once
        # per distinct (point, end)
        row_key = rows.astype(np.int64) * (1 << 20) + np.clip(core_end, 0, (1 << 20) - 1)
        row_uniq, row_inv = np.unique(row_key, return_inverse=True)
        row_inv = row_inv.ravel()
        point = (row_uniq >> 20).astype(np.int64)
        end = (row_uniq & ((1 << 20) - 1)).astype(np.int64)
        sub = com.take(point)
        at = sub.pair_at(np.maximum(end, 1))
        on_exp, off_exp = at.on[row_inv], at.off[row_inv]
        on_err = np.abs(self.on_c - on_exp)
        off_err = np.abs(self.off_c - off_exp)
        margin = tol.duty_counts
        p = o.u.pwm_counts
        total = at.total[row_inv]
        high_set = (flag & f["HIGH_SPEED"]) != 0
        fail_set = (flag & f["FAIL_AREA_CLAMPED"]) != 0
        wrong = ((flag & f["INPUT_SATURATED"]) != 0) != self.saturated
        wrong |= (total < p - margin) & ~high_set
        wrong |= (total > p + margin) & high_set
        outside = (total > 2 * p + margin) | (total < -margin)
        inside = (total < 2 * p - margin) & (total > margin)
        wrong |= (outside & ~fail_set) | (inside & fail_set)
        # TIME_CLAMPED: where every allowed end is past the sector, or none is
        wrong |= ((end_lo[rows] > n_rows) & ~clamped) | ((end_hi[rows] <= n_rows) & clamped)
        forward = np.where(relaxed, 0.0, forward)
        return _Result(on_err, off_err, forward, use, relaxed, wrong)


def _distance(value: Floats, lo: Floats, hi: Floats) -> Floats:
    return np.where(value < lo, lo - value, np.where(value > hi, value - hi, 0.0))


def _window_use(value: Floats, center: Floats, lo: Floats, hi: Floats) -> Floats:
    """How much of the window [lo, hi] around center the value uses (<= 1 inside)."""
    above = value >= center
    span = np.where(above, hi - center, center - lo)
    gap = np.abs(value - center)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(gap == 0, 0.0, np.where(span > 0, gap / span, np.inf))


def claims_check(claims: dict[str, object], tol: Tolerances, measured_duty: float) -> OutputCheck:
    """The design's claimed bounds may not exceed the spec's targets, and the measured
    duty error may not exceed the claim."""
    check = OutputCheck("design claims within the spec", "violations", None)
    duty = float(claims.get("duty_counts", 0.0))  # type: ignore[arg-type]
    time = float(claims.get("commutation_time_ticks", 0.0))  # type: ignore[arg-type]
    problems = []
    if duty > tol.duty_counts + SLACK:
        problems.append(f"duty bound {duty:g} > accuracy.duty_counts {tol.duty_counts:g}")
    if time > tol.time_ticks + SLACK:
        problems.append(f"time bound {time:g} > accuracy.commutation_time_ticks {tol.time_ticks:g}")
    if measured_duty > duty + SLACK:
        problems.append(f"measured duty error {measured_duty:.3f} > claimed {duty:g}")
    check.points = 3
    check.failures = len(problems)
    check.max_error = float(len(problems))
    check.note = (
        "; ".join(problems)
        if problems
        else (
            f"claims duty {duty:g} counts, t_com {time:g} ticks ({claims.get('commutation_time_region', '')})"
        )
    )
    return check


def as_fraction(value: float) -> Fraction:
    return Fraction(value).limit_denominator(10**9)

"""Input sets of the verifier: exhaustive, random (seeded) and thresholds.

Every limit comes from the oracle (`oracle.units.limits`), never from the generator.
The threshold set puts points on both sides of every decision the core makes, at
every bus code: Eq. 18's cut-off, the over-speed period, the over-voltage and
under-voltage codes, every current code of the 16-bit field, the conventional
method's fail area (D_off = 0 and D_off = 1), Eq. 20's denominator W = 0 (with the
currents at zero and at the range's ends), the exact ties where X is a whole count,
and every pair of 8-bit Hall codes; the time-clamp set those of t_com = T and, for
the resistance-aware rule, the steps of the sector's whole PWM periods where the
current remains through it; the conditioning set (the paper's methods) the smallest
positive W at currents just below the one whose Eq. 20 time reaches the latest end.
"""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np
import numpy.typing as npt

from oracle.model import Oracle

Inputs = npt.NDArray[np.void]
FIELDS = (
    "hall_code",
    "previous_hall_code",
    "hall_period_ticks",
    "bus_voltage_adc",
    "phase_current_adc",
    "main_duty_counts",
)


def make(dtype: np.dtype, *columns: npt.ArrayLike) -> Inputs:
    arrays = np.broadcast_arrays(*(np.asarray(c, dtype=np.int64) for c in columns))
    out = np.zeros(arrays[0].size, dtype=dtype)
    for name, values in zip(FIELDS, arrays, strict=True):
        out[name] = values.ravel()
    return out


def valid_edges(o: Oracle) -> list[tuple[int, int]]:
    """(previous code, code) of the 12 commutations: 6 forward, 6 reverse."""
    return sorted(o.edges)


def operating_codes(o: Oracle) -> tuple[int, int, int]:
    """Bus code at the nominal voltage, current code at the nominal braking current and
    the first operating point's main duty in counts."""
    spec = o.spec
    bus = o.u.bus_code(spec.inverter.bus_voltage_nominal_v)
    current = o.u.current_code(spec.controller.braking_current_nominal_a)
    duty = math.floor(spec.operating_points[0].main_duty * o.u.pwm_counts + Fraction(1, 2))
    return bus, current, duty


def exhaustive(o: Oracle, dtype: np.dtype) -> Inputs:
    """Every period code of the speed range, at the bus minimum, nominal and maximum,
    for every valid Hall transition (both directions)."""
    bus_nominal, current, duty = operating_codes(o)
    periods = np.arange(o.lim.period_min, o.lim.period_max + 1)
    buses = np.array([o.lim.bus_min, bus_nominal, o.lim.bus_max])
    edges = np.array(valid_edges(o))
    e, b, t = np.meshgrid(np.arange(len(edges)), buses, periods, indexing="ij")
    return make(dtype, edges[e, 1], edges[e, 0], t, b, current, duty)


def random_points(o: Oracle, dtype: np.dtype, seed: int, count: int) -> Inputs:
    """The whole input space: mostly valid transitions, some invalid codes; periods
    log-uniform from half the minimum to the counter's top; braking and any currents."""
    rng = np.random.default_rng(seed)
    edges = np.array(valid_edges(o))
    pick = edges[rng.integers(0, len(edges), count)]
    wild = rng.random(count) < 0.1
    hall = np.where(wild, rng.integers(0, 8, count), pick[:, 1])
    previous = np.where(wild, rng.integers(0, 8, count), pick[:, 0])
    low, high = np.log(max(o.lim.period_min / 2, 1)), np.log(o.u.hall_counter_max)
    period = np.exp(rng.uniform(low, high, count)).astype(np.int64)
    top = o.u.adc_max + 1
    bus = np.where(
        rng.random(count) < 0.8,
        rng.integers(o.lim.bus_min, o.lim.bus_max + 1, count),
        rng.integers(0, top, count),
    )
    current = np.where(
        rng.random(count) < 0.8,
        rng.integers(o.lim.current_low, o.lim.current_high + 1, count),
        rng.integers(0, top, count),
    )
    duty = rng.integers(0, 2 * o.u.pwm_counts, count)
    return make(dtype, hall, previous, period, bus, current, duty)


def _first_low_speed_period(o: Oracle, bus: int) -> int:
    """Smallest T with 4E <= U_d at this bus code (Eq. 18's cut-off), exactly."""
    # 4 k_e n(T) <= U_d  <=>  T >= 4 k_e 60 f / (6 p U_d)
    u_d = o.u.volts(bus)
    limit = 4 * o.motor.k_e * 60 * o.u.hall_hz / (6 * o.u.pole_pairs * u_d)
    return -((-limit.numerator) // limit.denominator)


def _fail_area_periods(o: Oracle, bus: int, duty: int) -> list[int]:
    """Periods where Eq. 16's D_off crosses 0 and 1 at this bus code and main duty."""
    p = o.u.pwm_counts
    d_on = Fraction(min(duty, p), p)
    u_d = o.u.volts(bus)
    out = []
    for d_off in (Fraction(0), Fraction(1)):
        ratio = 2 - d_on - d_off  # 4E/U_d at the crossing
        if ratio > 0:
            t = 4 * o.motor.k_e * 60 * o.u.hall_hz / (6 * o.u.pole_pairs * u_d * ratio)
            out.append(t.numerator // t.denominator)
    return out


def _currents_at_the_ends(o: Oracle) -> list[int]:
    """Current codes on both sides of zero current and of the braking range's ends, and
    the ADC's full scale (a code above it saturates there)."""
    zero = o.u.zero_current_code
    codes = {
        math.floor(zero),
        math.ceil(zero),
        o.lim.current_low - 1,
        o.lim.current_low,
        o.lim.current_high,
        o.lim.current_high + 1,
        o.u.adc_max,
    }
    return sorted(c for c in codes if 0 <= c <= 0xFFFF)


def _denominator_zero_rows(
    o: Oracle, forward: tuple[int, int], duty: int
) -> list[tuple[int, int, int, int, int, int]]:
    """At every bus code of the range: the top speed's periods, and (the paper's
    methods) the periods on both sides of W = 0, where Eq. 20's denominator at the exact
    duties changes sign (found by bisection on the oracle's own Eq. 16/18 and 20; for
    the methods that take a main duty, at none and at the operating point's), each at
    the currents of `_currents_at_the_ends`. Beyond W = 0 the turn-off current never
    reaches zero: the whole sector where there is current, nothing where there is
    none; and at W = 0 exactly the core must not divide by it. The resistance-aware
    rule has no W: its top speed's periods, where the current remains through the
    sector, are the ones it shares."""
    buses = np.arange(o.lim.bus_min, o.lim.bus_max + 1)
    currents = _currents_at_the_ends(o)
    periods: list[npt.NDArray[np.int64]] = [
        np.full(buses.size, o.lim.period_min),
        np.full(buses.size, o.lim.period_min + 1),
    ]
    if o.method != "improved_r":
        amps = np.full(buses.size, o.lim.current_high)

        def w_positive(period: npt.NDArray[np.int64], main: int) -> npt.NDArray[np.bool_]:
            m = np.full(buses.size, main)
            on, off, _, _ = o.duties(period, buses, m)
            _, w = o.eq20(period, buses, amps, on, off)
            return w > 0

        for main in sorted({0, duty} if o.uses_main_duty else {duty}):
            lo = np.full(buses.size, o.lim.period_min, dtype=np.int64)
            hi = np.full(buses.size, o.lim.period_max, dtype=np.int64)
            at_lo = w_positive(lo, main)
            crosses = at_lo != w_positive(hi, main)
            for _ in range(int(o.lim.period_max - o.lim.period_min).bit_length()):
                mid = (lo + hi) // 2
                same = w_positive(mid, main) == at_lo
                lo = np.where(same, mid, lo)
                hi = np.where(same, hi, mid)
            for shift in (-2, -1, 0, 1):
                periods.append(np.where(crosses, hi + shift, o.lim.period_min))
    mains = sorted({0, duty} if o.uses_main_duty else {duty})
    rows = []
    for column in periods:
        for b, t in sorted({(int(b), int(t)) for b, t in zip(buses, column, strict=True)}):
            if o.lim.period_min <= t <= o.u.hall_counter_max:
                for c in currents:
                    for main in mains:
                        rows.append((forward[1], forward[0], t, b, c, main))
    return rows


def _exact_tie_rows(
    o: Oracle, forward: tuple[int, int]
) -> list[tuple[int, int, int, int, int, int]]:
    """Where X = P 4E/U_d = c / (T B) is a whole number of counts (c a rational of the
    spec), the duties' decisions can tie exactly: Eq. 16's D_off exactly 0 or 1 at the
    main duty 2P - X or P - X, W = 0 at the main duty (X - 2P) / 2, Eq. 18's segments at
    X = P and 2P. Every such period and bus code of the range, at those main duties and
    the braking range's currents. (A motor whose c has a large numerator has none.)"""
    p = o.u.pwm_counts
    c = 4 * p * o.motor.k_e * o.u.rpm(1) / o.u.volts(1)
    num, den = c.numerator, c.denominator
    periods = np.arange(o.lim.period_min, o.lim.period_max + 1, dtype=np.int64)
    _, current, duty = operating_codes(o)
    rows = []
    if den * int(periods[-1]) >= 2**62:
        return rows
    for bus in range(o.lim.bus_min, o.lim.bus_max + 1):
        if num % bus or num // bus >= 2**62:
            continue
        per_bus = num // bus
        tie = periods[per_bus % (den * periods) == 0]
        for t in tie:
            x = per_bus // (den * int(t))
            mains = {2 * p - x, p - x, duty}
            if (x - 2 * p) % 2 == 0:
                mains.add((x - 2 * p) // 2)
            for m in sorted(mains):
                if 0 <= m <= p:
                    for amps in (current, o.lim.current_low, o.lim.current_high):
                        rows.append((forward[1], forward[0], int(t), bus, amps, m))
    return rows


def thresholds(o: Oracle, dtype: np.dtype) -> Inputs:
    bus_nominal, current, duty = operating_codes(o)
    forward = valid_edges(o)[0]
    reverse = valid_edges(o)[-1]
    mid = (o.lim.period_min + o.lim.period_max) // 2
    rows: list[tuple[int, int, int, int, int, int]] = []
    cap = o.u.hall_counter_max
    for bus in range(0, o.u.adc_max + 1):
        b = min(max(bus, o.lim.bus_min), o.lim.bus_max)
        cut = _first_low_speed_period(o, b)
        periods = {cut - 2, cut - 1, cut, cut + 1, o.lim.period_min - 1, o.lim.period_min, mid}
        for period in periods:
            if 0 < period <= cap:
                for previous, code in (forward, reverse):
                    rows.append((code, previous, period, bus, current, duty))
        if o.method == "conventional" and o.lim.bus_min <= bus <= o.lim.bus_max and bus % 3 == 0:
            p = o.u.pwm_counts
            for m in (0, p // 4, p // 2, 3 * p // 4, p - 1):
                for t in _fail_area_periods(o, bus, m):
                    for period in (t - 1, t, t + 1, t + 2):
                        if o.lim.period_min <= period <= cap:
                            rows.append((forward[1], forward[0], period, bus, current, m))
    rows.extend(_denominator_zero_rows(o, forward, duty))
    rows.extend(_exact_tie_rows(o, forward))
    sweeps = _threshold_sweeps(o, forward, mid, bus_nominal, current, duty)
    listed = np.array(rows, dtype=np.int64).reshape(-1, len(FIELDS))
    return make(dtype, *np.concatenate([listed, sweeps]).T)


def _rows(*columns: npt.ArrayLike) -> npt.NDArray[np.int64]:
    """Rows (code, previous, period, bus, current, main duty) of the columns broadcast
    together (each a value or a sweep)."""
    arrays = np.broadcast_arrays(*(np.asarray(c, dtype=np.int64) for c in columns))
    return np.stack(arrays, axis=1).reshape(-1, len(FIELDS))


def _threshold_sweeps(
    o: Oracle, forward: tuple[int, int], mid: int, bus: int, current: int, duty: int
) -> npt.NDArray[np.int64]:
    """The threshold set's sweeps at the nominal bus, as rows (built as arrays: a
    Python list of their 200 000 tuples was most of the set's time): every current
    code, every 7th period, the main duty's ends, then every pair of Hall codes."""
    previous, code = forward
    ends = [0, o.u.pwm_counts - 1, o.u.pwm_counts, o.u.pwm_counts + 1, 0xFFFF]
    pairs = np.arange(256 * 256)
    return np.concatenate(
        [
            _rows(code, previous, mid, bus, np.arange(65536), duty),
            _rows(code, previous, np.arange(0, 65536, 7), bus, current, duty),
            _rows(code, previous, mid, bus, current, ends),
            _rows(pairs // 256, pairs % 256, mid, bus, current, duty),
        ]
    )


def _carrier_step_periods(o: Oracle) -> list[int]:
    """The resistance-aware rule's periods on both sides of each step of N, the whole
    PWM periods before the latest end, where the current remains through the sector
    (TIME_CLAMPED) at the ADC's full-scale current at some bus code of a sample (every
    16th and the range's ends; the oracle's rule decides)."""
    t = np.arange(o.lim.period_min, o.lim.period_max + 1, dtype=np.int64)
    n = np.floor(_over_carrier(o, o.u.latest_end(t)) + 1e-9).astype(np.int64)
    steps = t[1:][np.diff(n) != 0]
    candidates = np.unique(np.concatenate([steps - 1, steps]))
    sample = np.unique(np.r_[np.arange(o.lim.bus_min, o.lim.bus_max + 1, 16), o.lim.bus_max])
    period = np.repeat(candidates, sample.size)
    bus = np.tile(sample, candidates.size)
    com = o.rule(period, bus, np.full(period.size, o.u.adc_max))
    x, _ = com.zero()
    clamped = com.end_after(x * period) > com.periods
    return sorted({int(p) for p in period[clamped]})


def _over_carrier(o: Oracle, ticks: npt.NDArray[np.int64]) -> npt.NDArray[np.float64]:
    """float(T / carrier_ticks) of each of `ticks`: the ratio of two integers, which
    Python's integer division rounds to the nearest float exactly as float() of the
    Fraction does (dividing the array by the Fraction made one Fraction an element)."""
    carrier = Fraction(o.u.carrier_ticks)
    num, den = carrier.numerator, carrier.denominator
    return np.array([int(t) * den / num for t in ticks], dtype=np.float64)


#: periods of the conditioning set, spread geometrically over the counter's range
CONDITIONING_PERIODS = 48
#: main duties swept per (T, B) for a method that takes one, and the refinement's steps
MAIN_SWEEP = 64


def conditioning_points(o: Oracle, dtype: np.dtype) -> Inputs:
    """The paper's methods, where Eq. 20 is worst conditioned and still below the latest
    end: the core's error in W moves t by t delta / W, largest where W is small and t
    just below the latest end L(T), so at a current just below the code where Eq. 20
    reaches L(T) (linear in the current: found from the full-scale code's time). At
    `CONDITIONING_PERIODS` periods over the counter's range and every 4th bus code (the
    range's ends too), at the operating main duty or, for a method that takes one, the
    two of a sweep (refined) that give the smallest positive W; the current codes on
    both sides of that crossing and the lowest code above zero current. (offset_
    conventional broke its 16 ticks by up to 33 in range at such points, which no other
    set held: a current 0.58 A, W 5.6 counts, a 49 888-tick sector.)"""
    if o.method == "improved_r":
        return make(dtype, *np.zeros((6, 0), dtype=np.int64))
    forward = valid_edges(o)[0]
    _, _, duty = operating_codes(o)
    cap = o.u.hall_counter_max
    periods = np.unique(np.geomspace(o.lim.period_min, cap, CONDITIONING_PERIODS).astype(np.int64))
    buses = np.unique(np.r_[np.arange(o.lim.bus_min, o.lim.bus_max + 1, 4), o.lim.bus_max])
    grid_t, grid_b = (a.ravel() for a in np.meshgrid(periods, buses))
    p = o.u.pwm_counts
    top = np.full(grid_t.size, o.u.adc_max)

    def w_at(main: npt.NDArray[np.int64]) -> npt.NDArray[np.float64]:
        on, off, _, _ = o.duties(grid_t, grid_b, main)
        _, w = o.eq20(grid_t, grid_b, top, on, off)
        return np.where(w > 0, w, np.inf)

    if o.uses_main_duty:
        sweep = np.linspace(0, p, MAIN_SWEEP + 1).round().astype(np.int64)
        ws = np.stack([w_at(np.full(grid_t.size, m)) for m in sweep])
        chosen = []
        for rank in range(2):
            best = sweep[np.argsort(ws, axis=0)[rank]]
            step = -(-p // MAIN_SWEEP)
            fine = np.stack(
                [np.clip(best + d, 0, p) for d in range(-step, step + 1, max(1, step // 8))]
            )
            fine_w = np.stack([w_at(m) for m in fine])
            chosen.append(fine[np.argmin(fine_w, axis=0), np.arange(grid_t.size)])
        mains = np.concatenate(chosen)
        grid_t, grid_b = np.tile(grid_t, 2), np.tile(grid_b, 2)
        top = np.tile(top, 2)
    else:
        mains = np.full(grid_t.size, duty)
    on, off, _, _ = o.duties(grid_t, grid_b, mains)
    t_top, w = o.eq20(grid_t, grid_b, top, on, off)
    zero = float(o.u.zero_current_code)
    span = o.u.adc_max - zero
    usable = (w > 0) & np.isfinite(t_top) & (t_top > 0) & (span > 0)
    per_code = np.where(usable, t_top / max(span, 1e-30), 1.0)
    latest = o.u.latest_end(grid_t).astype(np.float64)
    crossing = zero + latest / per_code
    lowest = math.floor(zero) + 1
    rows = []
    for k in np.flatnonzero(usable):
        c = crossing[k]
        codes = {lowest, *(math.floor(c) + d for d in (-2, -1, 0, 1))}
        for code in sorted(codes):
            if lowest <= code <= o.u.adc_max:
                rows.append(
                    (forward[1], forward[0], int(grid_t[k]), int(grid_b[k]), code, int(mains[k]))
                )
    if not rows:
        return make(dtype, *np.zeros((6, 0), dtype=np.int64))
    return make(dtype, *np.array(rows, dtype=np.int64).T)


def time_clamp_points(o: Oracle, dtype: np.dtype, duties: object) -> Inputs:
    """Periods on both sides of t_com = T at every bus code of the range, three
    braking currents and the ADC's full scale (found by bisection on the oracle's own
    Eq. 20 or rule); for the resistance-aware rule also `_carrier_step_periods`."""
    _, current, duty = operating_codes(o)
    forward = valid_edges(o)[0]
    buses = np.arange(o.lim.bus_min, o.lim.bus_max + 1)
    rows = []
    for amps_code in (
        current,
        (current + o.lim.current_high) // 2,
        o.lim.current_high,
        o.u.adc_max,
    ):
        lo = np.full(buses.size, o.lim.period_min, dtype=np.int64)
        hi = np.full(buses.size, o.lim.period_max, dtype=np.int64)
        f = duties  # callable (period, bus, current) -> (t_ticks) from the verifier's model
        clamped_lo = f(lo, buses, np.full(buses.size, amps_code)) > lo  # type: ignore[operator]
        for _ in range(20):
            midp = (lo + hi) // 2
            over = f(midp, buses, np.full(buses.size, amps_code)) > midp  # type: ignore[operator]
            same = over == clamped_lo
            lo = np.where(same, midp, lo)
            hi = np.where(same, hi, midp)
        for b, t in zip(buses, hi, strict=True):
            for period in (t - 2, t - 1, t, t + 1):
                if o.lim.period_min <= period <= o.lim.period_max:
                    rows.append((forward[1], forward[0], int(period), int(b), amps_code, duty))
    if o.method == "improved_r":
        # where the current remains through the sector, the pair is the one at its last
        # whole PWM period N: both sides of every step of N where that happens, at every
        # 8th bus code and the range's ends, at the braking range's top and the ADC's
        # full scale
        every_8th = np.unique(np.r_[buses[::8], o.lim.bus_max])
        for period in _carrier_step_periods(o):
            for b in every_8th:
                for amps_code in (o.lim.current_high, o.u.adc_max):
                    rows.append((forward[1], forward[0], period, int(b), amps_code, duty))
    if not rows:
        return make(dtype, *np.zeros((6, 0), dtype=np.int64))
    return make(dtype, *np.array(rows).T)

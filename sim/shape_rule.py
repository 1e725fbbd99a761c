"""`improved_r_shape`: the resistance-aware constant pair for any back-EMF shape (Python
prototype for the generated core; no firmware runs this yet).

The generated `improved_r` core assumes the paper's 120 deg trapezoid: the outgoing
phase ramps from -E at the edge at 2E per sector, so it holds the duty sum S at the
EMFs of theta t_com (theta = sqrt(2) - 1, the minimax weight of a linear ramp) and
finds t_com as the zero of the turn-off current under that ramp. On another shape
both steps are wrong: on the paper's flat EMF S never ramps, and a 100 deg flat top
has the turn-on phase still ramping at the edge. This rule takes the shape as data
(the spec's `motor.back_emf_shape`, or the paper's frozen flat EMF) and generalises
the two steps, keeping the firmware's structure (one constant pair, t_com at the zero
of the turn-off current):

1. hold: S(t) = duty_sum(e_nc(t), e_off(t), e_on(t)) along the shape (affine in the
   EMFs, so S(t) - S(0) = (E / U_d) s(t / T_s) with s a function of the shape alone).
   For a commutation of t_c the held sum is the minimax constant of S over [0, t_c]:
   the c that makes the largest swell of int_0^tau (c - S) equal the largest sag.
   For a linear ramp from the edge this is S(theta t_c); for the flat EMF it is S(0);
   for a trapezoid of flat-top width w >= 120 deg, whose outgoing phase starts to ramp
   x0 = (w - 120) / 120 sectors after the edge, it is S(0) + slope * p with
   p = sqrt((x0 + x_c)^2 + (x_c - x0)^2) - (x0 + x_c) (x_c > x0, in sectors).
2. time: the turn-off current under that pair with the shape's EMFs, each affine
   piece integrated exactly (di_b/dt = alpha + beta t - (R/L) i_b per piece); t_c is
   the zero of i_b(t_c; pair(t_c)), found by bisection (the firmware instead takes the
   first PWM carrier boundary past it, as `improved_r_aligned` does).

The firmware (codegen/methods/improved_r/) implements the shapes whose EMFs are affine
over the commutation sector, flat and the 120 deg trapezoid, in the aligned form: the
end on the carrier grid, where the decay is a constant to the power m (a table of
D^(2^k) and a binary search over m, no exponential). A trapezoid of another width has
a slope change inside the sector (a second (x - x_j)+ term in g); the generator refuses
it for improved_r, and these prototypes remain its model.
"""

from __future__ import annotations

import math
from itertools import pairwise

import numpy as np

from sim import closed_form
from sim.command import Command
from sim.emf import BackEmf
from sim.resistance import numeric_rule
from sim.scenario import Case
from sim.schedule import switch_index

METHOD = "improved_r_shape"
#: Samples of S over [0, t_c] for the minimax constant.
_SAMPLES = 257
_BISECTIONS = 40


def _canonical(case: Case, emf: BackEmf, t: float) -> tuple[float, float, float]:
    """EMFs of (non-commutating, turn-off, turn-on) in the paper's edge frame."""
    values = emf.values(t)
    mirror = 1.0 if case.edge.kind == "upper" else -1.0
    nc, off, on = case.roles()
    return mirror * values[nc], mirror * values[off], mirror * values[on]


def duty_sum_along(case: Case, current_a: float, times: np.ndarray) -> np.ndarray:
    """S(t): the duty sum that holds the non-commutating current, along the shape."""
    rule = numeric_rule()
    drive = case.drive
    mirror = 1.0 if case.edge.kind == "upper" else -1.0
    values = case.emf.values_many(times)
    return np.array(
        [
            rule.duty_sum(
                *(mirror * float(values[k, phase]) for phase in case.roles()),
                drive.resistance_ohm,
                current_a,
                drive.bus_voltage_v,
            )
            for k in range(len(times))
        ]
    )


def minimax_sum(case: Case, current_a: float, t_c: float) -> float:
    """The constant c minimising max over tau in [0, t_c] of |int_0^tau (c - S)|."""
    times = np.linspace(0.0, t_c, _SAMPLES)
    s = duty_sum_along(case, current_a, times)
    integral = np.concatenate(([0.0], np.cumsum(0.5 * (s[1:] + s[:-1]) * np.diff(times))))

    def spread(c: float) -> float:
        deviation = c * times - integral
        return float(deviation.max() + deviation.min())  # zero at the minimax c

    low, high = float(s.min()), float(s.max())
    if high - low < 1e-12:
        return low
    for _ in range(60):
        middle = 0.5 * (low + high)
        if spread(middle) > 0.0:
            high = middle
        else:
            low = middle
    return 0.5 * (low + high)


def _pair(total: float, period_counts: int) -> tuple[float, float]:
    def quantised(duty: float) -> float:
        return round(min(max(duty, 0.0), 1.0) * period_counts) / period_counts

    return quantised(min(total, 1.0)), quantised(max(total - 1.0, 0.0))


def turn_off_current(case: Case, current_a: float, on: float, off: float, t: float) -> float:
    """i_b(t) from I at the edge under a constant pair, the shape's EMFs piecewise exact."""
    rule = numeric_rule()
    drive = case.drive
    emf = case.emf
    bus, ell = drive.bus_voltage_v, drive.inductance_h
    pieces = [0.0, *emf.corners(0.0, t), t]
    value = current_a
    for lo, hi in pairwise(pieces):
        if hi <= lo:
            continue
        start = rule.off_forcing(on, off, *_canonical(case, emf, lo + 1e-12 * (hi - lo)), bus, ell)
        stop = rule.off_forcing(on, off, *_canonical(case, emf, hi - 1e-12 * (hi - lo)), bus, ell)
        ramp = (stop - start) / (hi - lo)
        value = closed_form.current(value, start, ramp, drive.decay_rate, hi - lo)
    return value


def shape_rule_command(
    case: Case,
    measured_current_a: float,
    main_duty: float,
    period_counts: int,
    hall_clock_hz: float,
) -> Command:
    """One constant pair and t_com for this case's EMF shape (see the module doc)."""
    sector = case.sector_time_s

    def g(t: float) -> tuple[float, tuple[float, float]]:
        pair = _pair(minimax_sum(case, measured_current_a, t), period_counts)
        return turn_off_current(case, measured_current_a, *pair, t), pair

    end, pair = g(sector)
    commutation = sector
    if end <= 0.0:
        low, high = 0.0, sector
        for _ in range(_BISECTIONS):
            middle = 0.5 * (low + high)
            value, _ = g(middle)
            if value > 0.0:
                low = middle
            else:
                high = middle
        commutation = high
        _, pair = g(commutation)
    ticks = max(round(commutation * hall_clock_hz), 1)
    return Command(
        method=METHOD,
        turn_on_switch=switch_index(case.edge.modulated_on),
        turn_off_switch=switch_index(case.edge.modulated_off),
        on_duties=(pair[0],),
        off_duties=(pair[1],),
        commutation_time_s=ticks / hall_clock_hz,
        main_duty=main_duty,
    )


def trapezoid_hold_point(flat_top_deg: float, x_c: float) -> float:
    """Closed form of step 1 for a trapezoid of width >= 120 deg: sectors after the
    ramp's start at which S is held (0 while the commutation ends before the ramp)."""
    x0 = (flat_top_deg - 120.0) / 120.0
    if x_c <= x0:
        return 0.0
    return math.hypot(x0 + x_c, x_c - x0) - (x0 + x_c)


ALIGNED_METHOD = "improved_r_aligned"


def aligned_command(
    case: Case,
    measured_current_a: float,
    main_duty: float,
    period_counts: int,
    hall_clock_hz: float,
) -> Command:
    """The shape rule with the commutation stretched to a whole number of carrier periods.

    The port restarts the carrier at the commutation end (COM with an update): ending
    mid-period moves the PWM ripple's phase, a DC step of up to half the ripple that
    lasts L/R, and a commutation of one to three periods ends mid-period by nature.
    Here the commutation lasts n = ceil(t_c / T) periods: the held sum is the minimax
    constant over n T, and the saturated split is eased by delta (D_on - delta,
    D_off + delta, the sum unchanged) so that the turn-off current reaches zero exactly
    at n T: 3 L di_b/dt grows by 3 delta U_d, so i_b(n T) rises monotonically in delta.
    The price is that both transistors switch during the commutation.
    """
    fastest = shape_rule_command(case, measured_current_a, main_duty, period_counts, hall_clock_hz)
    period = case.drive.pwm_period_s
    sector = case.sector_time_s
    periods = max(1, math.ceil(fastest.commutation_time_s / period - 1e-6))
    end = periods * period
    if end > sector:
        return fastest
    total = minimax_sum(case, measured_current_a, end)
    on0, off0 = min(total, 1.0), max(total - 1.0, 0.0)
    room = min(on0, 1.0 - off0)

    def at(delta: float) -> float:
        return turn_off_current(case, measured_current_a, on0 - delta, off0 + delta, end)

    low, high = 0.0, room
    if at(low) < 0.0 < at(high):
        for _ in range(_BISECTIONS):
            middle = 0.5 * (low + high)
            if at(middle) < 0.0:
                low = middle
            else:
                high = middle
    delta = high if at(low) < 0.0 else 0.0
    on, off = on0 - delta, off0 + delta

    def quantised(duty: float) -> float:
        return round(min(max(duty, 0.0), 1.0) * period_counts) / period_counts

    ticks = round(end * hall_clock_hz)
    return Command(
        method=ALIGNED_METHOD,
        turn_on_switch=fastest.turn_on_switch,
        turn_off_switch=fastest.turn_off_switch,
        on_duties=(quantised(on),),
        off_duties=(quantised(off),),
        commutation_time_s=ticks / hall_clock_hz,
        main_duty=main_duty,
    )

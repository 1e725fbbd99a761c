"""`improved_r_pp`: the resistance-aware rule re-solved every PWM period (Python only).

No firmware runs this: the shipped `improved_r` is the generated C core, which holds
one constant duty pair per commutation. This is its per-period ideal, the comparison
line that shows what the constant pair gives away.

At the Hall edge it knows what the C core knows (speed from the Hall period, bus
voltage, the measured current I) plus R, L and the EMF shape of the motor model. For
each carrier period of the commutation it evaluates the derived duty sum S at the
period's mid-point EMFs and splits it as the paper does (one transistor saturated):
D_on = min(S, 1), D_off = max(S - 1, 0). With the paper's flat EMFs S is constant;
with a trapezoidal EMF the outgoing phase's ramp makes S grow through the commutation
and the split may move from the high to the low segment on the way.

The commutation time is the rule's own prediction: the turn-off current under the
emitted (quantised) duties, di_b/dt = alpha + beta t - (R/L) i_b in each period,
stepped exactly with the closed form until it reaches zero, then rounded to Hall
ticks. Duties are rounded to TIM1 counts like the core's.
"""

from __future__ import annotations

import math

from sim import closed_form
from sim.command import Command
from sim.emf import BackEmf
from sim.resistance import numeric_rule
from sim.scenario import Case
from sim.schedule import switch_index

METHOD = "improved_r_pp"


def _canonical(case: Case, emf: BackEmf, t: float) -> tuple[float, float, float]:
    """EMFs of (non-commutating, turn-off, turn-on) in the paper's edge frame.

    At the mirror-image ("lower") edges u -> U_d - u, i -> -i, e -> -e maps the circuit
    onto the paper's, so the derived rule applies to the negated EMFs.
    """
    values = emf.values(t)
    mirror = 1.0 if case.edge.kind == "upper" else -1.0
    nc, off, on = case.roles()
    return mirror * values[nc], mirror * values[off], mirror * values[on]


def _quantised(duty: float, period_counts: int) -> float:
    return round(min(max(duty, 0.0), 1.0) * period_counts) / period_counts


def improved_r_pp_command(
    case: Case,
    measured_current_a: float,
    main_duty: float,
    period_counts: int,
    hall_clock_hz: float,
) -> Command:
    """Duties per carrier period and the commutation time, from the derived rule."""
    rule = numeric_rule()
    drive = case.drive
    emf = case.emf
    period = drive.pwm_period_s
    sector = case.sector_time_s
    r, ell, bus = drive.resistance_ohm, drive.inductance_h, drive.bus_voltage_v
    current = measured_current_a
    on_duties: list[float] = []
    off_duties: list[float] = []
    commutation_time = sector
    remaining = current
    for k in range(math.ceil(sector / period)):
        lo, hi = k * period, min((k + 1) * period, sector)
        e_nc, e_off, e_on = _canonical(case, emf, 0.5 * (lo + hi))
        total = rule.duty_sum(e_nc, e_off, e_on, r, current, bus)
        d_on = _quantised(min(total, 1.0), period_counts)
        d_off = _quantised(max(total - 1.0, 0.0), period_counts)
        on_duties.append(d_on)
        off_duties.append(d_off)
        start = rule.off_forcing(d_on, d_off, *_canonical(case, emf, lo), bus, ell)
        stop = rule.off_forcing(d_on, d_off, *_canonical(case, emf, hi), bus, ell)
        ramp = (stop - start) / (hi - lo)
        zero = closed_form.first_zero(remaining, start, ramp, drive.decay_rate, hi - lo)
        if zero is not None:
            commutation_time = lo + zero
            break
        remaining = closed_form.current(remaining, start, ramp, drive.decay_rate, hi - lo)
    ticks = round(commutation_time * hall_clock_hz)
    return Command(
        method=METHOD,
        turn_on_switch=switch_index(case.edge.modulated_on),
        turn_off_switch=switch_index(case.edge.modulated_off),
        on_duties=tuple(on_duties),
        off_duties=tuple(off_duties),
        commutation_time_s=ticks / hall_clock_hz,
        main_duty=main_duty,
    )

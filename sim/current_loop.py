"""The braking current controller, as the paper ran its operating points.

Between commutations two phases conduct in series behind the modulated transistor
(PWM-OFF-PWM): 2 L di/dt = 2E - (1 - D) U_d - 2 R i on the PWM average, where i is the
braking current and D the main duty. The paper's main controller holds the braking
current; the main duty is whatever it settles at. This module is that controller: a
discrete PI at the PWM rate on the period-mean current (what an ADC sample centred
in the PWM period returns), its output rounded to TIM1 counts and saturated to
[0, 1] with anti-windup, acting on the exact discretisation of the averaged circuit.

Its fixed point is the exact steady duty (1 - D) U_d = 2E - 2 R I (`Drive.steady_duty`)
up to one count, which the tests check; the duty the simulation hands the C core is
the PI's settled integer output. Where even D = 1 cannot hold I (R I >= E, the
winding's own resistance limits a short-circuit brake to E / R), the PI saturates at
D = 1 and the current it settles at is E / R: `Settled.limited` says so. Where one count
moves the held current by more than the loop's settling band (U_d / (2 R P): 8.7 A on a
0.2 mohm winding at 5 V and 1440 counts), no count holds I; the loop alternates between
the two counts around the steady duty, the winding's L/R smoothing the current, and its
mean duty is the steady one (`Settled.dithering`).

`held_current` answers the converse question: which braking current does a given
main duty hold (the paper quotes a main duty, not a current, for Fig. 13).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from sim.drive import Drive

#: Crossover of the current loop as a fraction of the PWM frequency.
CROSSOVER_FRACTION = 1.0 / 20.0
#: Periods the loop runs from rest at least; settled when the duty stays within one
#: count. A winding slower than that (L/R of hundreds of PWM periods) gets
#: TIME_CONSTANTS of its L/R, up to MAX_PERIODS_SLOW.
MAX_PERIODS = 4000
TIME_CONSTANTS = 30
MAX_PERIODS_SLOW = 200_000
#: How close the period-mean current must be to the steady one of the applied duty for a
#: saturated duty to count as settled (of the larger of the two currents).
SATURATED_TOLERANCE = 0.005
#: The settling band: the loop rests on a count whose held current is this close to I
#: (of I); else it alternates between two counts (`Settled.dithering`)
SETTLED_TOLERANCE = 0.005


@dataclass(frozen=True)
class Settled:
    duty: float  # the PI's output, rounded to counts (dithering: the mean, steady duty)
    counts: int
    current_a: float  # the period-mean current it settles at
    limited: bool  # D = 1 and the current below the request: R I >= E
    periods: int  # PWM periods until the duty stayed within one count for 50 periods
    #: no count holds I within SETTLED_TOLERANCE: the loop alternates between the two
    #: around the steady duty, whose mean `duty` is (`counts` the nearer), holding I
    dithering: bool = False


def held_current(drive: Drive, speed_rpm: float, duty: float) -> float:
    """Braking current a main duty holds at this speed (period mean, steady state)."""
    emf = drive.hold_emf_v(speed_rpm)
    return (2.0 * emf - (1.0 - duty) * drive.bus_voltage_v) / (2.0 * drive.resistance_ohm)


def settle(drive: Drive, speed_rpm: float, current_a: float, period_counts: int) -> Settled:
    """Run the PI from D = 0 and i = 0 until the duty settles; return where it settled."""
    period = drive.pwm_period_s
    bus = drive.bus_voltage_v
    decay = drive.resistance_ohm / drive.inductance_h
    factor = math.exp(-decay * period)
    emf = drive.hold_emf_v(speed_rpm)
    # Plant per period on the mean: i+ = f i + (1 - f) (2E - (1 - D) U) / (2 R).
    crossover = 2.0 * math.pi * CROSSOVER_FRACTION * drive.pwm_frequency_hz
    gain = 2.0 * drive.inductance_h * crossover / bus  # duty per ampere
    integral_gain = gain * decay * period  # zero on the winding's pole
    current, integral, counts = 0.0, 0.0, 0
    stable, last = 0, -10
    periods = 0
    budget = min(MAX_PERIODS_SLOW, max(MAX_PERIODS, math.ceil(TIME_CONSTANTS / (decay * period))))
    while periods < budget:
        periods += 1
        error = current_a - current
        # Braking: more duty, more current (a longer short through the bridge).
        unclamped = integral + integral_gain * error + gain * error
        duty = min(max(unclamped, 0.0), 1.0)
        if duty == unclamped:
            integral += integral_gain * error  # anti-windup: integrate only unsaturated
        counts = round(duty * period_counts)
        applied = counts / period_counts
        target = (2.0 * emf - (1.0 - applied) * bus) / (2.0 * drive.resistance_ohm)
        current = factor * current + (1.0 - factor) * target
        # A saturated duty is where the loop rests only once the current has reached the
        # steady value of that duty and it still cannot hold I (D = 1: R I >= E). A slow
        # winding (L/R of 200 PWM periods) saturates at once, its current still rising:
        # the loop had "settled" at D = 1 after 50 periods and reported 2 A for 1 A.
        steady = abs(current - target) <= SATURATED_TOLERANCE * max(abs(target), current_a)
        beyond = (counts == period_counts and target < current_a) or (
            counts == 0 and target > current_a
        )
        settled_error = abs(error) < SETTLED_TOLERANCE * current_a or (steady and beyond)
        stable = stable + 1 if abs(counts - last) <= 1 and settled_error else 0
        last = counts
        if stable >= 50:
            break
    applied = counts / period_counts
    held = held_current(drive, speed_rpm, applied)
    exact = drive.steady_duty(speed_rpm, current_a)
    if 0.0 < exact < 1.0 and abs(held - current_a) > SETTLED_TOLERANCE * current_a:
        # no count holds I (a 0.2 mohm winding: 8.7 A a count, and the loop had rested
        # on a count that holds 0 A, which the deviation is a fraction of)
        return Settled(
            duty=exact,
            counts=round(exact * period_counts),
            current_a=current_a,
            limited=False,
            periods=periods,
            dithering=True,
        )
    return Settled(
        duty=applied,
        counts=counts,
        current_a=held,
        limited=counts == period_counts and held < current_a,
        periods=periods,
    )

"""Where the resistance-aware rule cannot hold the current, from the physics.

At the spec's nominal bus and braking current, over the speed range:

* current limited: below n = R I / k_e even a short-circuit brake (D = 1) drives only
  E / R < I through the winding, so the braking current itself cannot be held and the
  operating point is at E / R (`sim.current_loop` saturates there);
* cannot hold through the commutation: below E = `ResistanceRule.lowest_emf` the duty
  sum S exceeds 2, so even both transistors fully on let the non-commutating current
  sag (the core flags CANNOT_HOLD);
* short commutation: the rule's commutation time (flat EMF, R kept: the derived
  logarithm) lasts less than one, or less than three, PWM periods; a per-period duty
  cannot shape the current inside one period, and the commutation's end falls inside
  a period (`sim.short_schedule` is the prototype for it);
* the turn-off current does not reach zero within the sector (above the finish limit).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from sim.drive import Drive
from sim.limits import limits
from sim.resistance import numeric_rule

#: Speeds evaluated across the range.
GRID = 2001


@dataclass(frozen=True)
class Regions:
    current_limited_below_rpm: float  # R I / k_e (0: nowhere in the range)
    cannot_hold_below_rpm: float
    #: Speed intervals (low, high) where the rule's t_com < 1 and < 3 PWM periods.
    under_one_period: tuple[tuple[float, float], ...]
    under_three_periods: tuple[tuple[float, float], ...]
    #: Speed above which the flat-EMF t_com does not fit in the sector.
    time_fits_below_rpm: float
    #: Fewest PWM periods a commutation lasts over the range, and where.
    fewest_periods: float
    fewest_at_rpm: float


def commutation_periods(drive: Drive, speed: float) -> float:
    """The rule's commutation time (flat EMF, R kept) in PWM periods; inf if it does not
    finish."""
    rule = numeric_rule()
    emf = drive.emf_v(speed)
    args = (drive.resistance_ohm, drive.braking_current_a, drive.bus_voltage_v)
    total = rule.duty_sum(emf, -emf, -emf, *args)
    time_of = rule.commutation_time_low if total >= 1.0 else rule.commutation_time_high
    try:
        t = time_of(emf, *args, drive.inductance_h)
    except (ValueError, ZeroDivisionError):
        return math.inf
    if isinstance(t, complex) or not math.isfinite(t) or t <= 0.0:
        return math.inf
    return t * drive.pwm_frequency_hz


def _intervals(speeds: np.ndarray, mask: np.ndarray) -> tuple[tuple[float, float], ...]:
    out = []
    start: float | None = None
    for k, inside in enumerate(mask):
        if inside and start is None:
            start = float(speeds[k])
        if not inside and start is not None:
            out.append((start, float(speeds[k - 1])))
            start = None
    if start is not None:
        out.append((start, float(speeds[-1])))
    return tuple(out)


def regions(drive: Drive) -> Regions:
    bounds = limits(drive)
    speeds = np.linspace(drive.speed_min_rpm, drive.speed_max_rpm, GRID)
    periods = np.array([commutation_periods(drive, float(s)) for s in speeds])
    finite = np.isfinite(periods)
    fewest = int(np.argmin(np.where(finite, periods, np.inf)))
    limited = drive.resistance_ohm * drive.braking_current_a / drive.hold_emf_v(1.0)
    return Regions(
        current_limited_below_rpm=limited if limited > drive.speed_min_rpm else 0.0,
        cannot_hold_below_rpm=max(bounds.lowest_hold_rpm, 0.0),
        under_one_period=_intervals(speeds, finite & (periods < 1.0)),
        under_three_periods=_intervals(speeds, finite & (periods < 3.0)),
        time_fits_below_rpm=bounds.r_time_fits_below_rpm,
        fewest_periods=float(periods[fewest]),
        fewest_at_rpm=float(speeds[fewest]),
    )

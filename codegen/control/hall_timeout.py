"""The Hall time-out: how long the port waits for the next Hall edge, from the physics.

Hall lines that freeze at a valid code (a connector pulled with its lines held, a
sensor board that stops updating) give the port no edge and no invalid code: the bridge
goes on braking with the pattern of one sector while the rotor turns through the
others. The port had caught that only when TIM3 wrapped, its whole range after the last
edge (65 ms on the paper motor, 30 sectors at 4600 rpm). A turning rotor cannot be that
late: its deceleration is bounded by the torque the machine can brake with.

The bound. Let the rotor brake at most alpha (mechanical rad/s^2), the previous sector
be theta_p long (mechanical rad) and have taken T, the next be theta_n long. The
slowest the rotor can leave the previous sector is at

    w0 = theta_p / T - alpha T / 2          (braking at alpha all through it)

(its mean speed is theta_p / T, and at a deceleration up to alpha its speed at the end
is at most alpha T / 2 below the mean). The next sector takes longest when the rotor
brakes at alpha all through it: pointwise the slowest speed profile. If w0^2 > 2 alpha
theta_n it still reaches the edge, after at most

    T_next = (w0 - sqrt(w0^2 - 2 alpha theta_n)) / alpha = 2 theta_n / (w0 + sqrt(...))

and otherwise it may stop within the sector (where the edge may never come, and the
wrap stays the time-out: a stopped rotor and frozen lines look alike, and both end in
the safe state). Braking at the edge of stopping gives T_next / T = 1 / (sqrt(1 + r) - 1)
with r = theta_p / theta_n: 2.41 for equal sectors, 3.77 at the largest sector
shortening the loader allows (25 %: r = 0.75 / 1.25). So the port waits 4 T
(`SHIFT`: T << 2, one instruction), wherever the bound holds for every interval up to
T (`HallTimeout.period_max`), and the counter's whole range above it.

The worst motor the spec declares (as `spec_drive.safe_state_corner`):
* alpha = (lambda k_e I + B w_top) / J: the braking torque sum(e_i i_i) / w is at most the peak
  line-to-line EMF per unit of speed (lambda k_e, k_e at its upper tolerance) times the
  largest phase current; that current is taken as the bridge's rating
  (protection.short_circuit_current_max, which the safe state keeps every current
  within), and J as the rotor's own inertia (a load adds inertia: it only slows the
  deceleration); B w_top the viscous friction (motor.viscous_friction) at the top speed
  read up to 1 / (1 - s) fast. A load that brakes by torque of its own beyond these is not
  covered: the time-out may then end a braking near the stop early, in the safe state.
* theta_p = (1 - s) 60 deg / p and theta_n = (1 + s) 60 deg / p (s the sector
  shortening: an edge displaced by s x 30 deg shortens one sector and lengthens its
  neighbour).
* The counts: the interval T read one tick short of the rotor's (the counter's
  resolution) and the time-out matching `MARGIN_TICKS` before the bound's ticks.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

from codegen.spec_drive import line_to_line_peak, safe_state_corner
from codegen.spec_model import Spec

#: The time-out is T << SHIFT: 4 T, above the bound's 3.77 T at 25 % sector shortening.
SHIFT = 2
#: Ticks the time-out keeps before the latest edge of a turning rotor: the interval's
#: resolution (1 tick) and the compare's (1 tick).
MARGIN_TICKS = 2


@dataclass(frozen=True)
class HallTimeout:
    shift: int
    #: T in [1, period_max]: the time-out is T << shift; above it (and at T = 0, which no
    #: edge captures) the counter's whole range. 0: the whole range at every interval.
    period_max: int
    deceleration: float  # alpha, mechanical rad/s^2
    #: the mean speed over a sector of period_max (rpm), the slowest with the short time-out
    speed_min_rpm: float | None


def latest_next_interval(
    interval_s: float, theta_prev: float, theta_next: float, alpha: float
) -> float | None:
    """The longest the next sector can take (s) after one of `interval_s`, braking at
    up to `alpha`; None where the rotor may stop within it."""
    w0 = theta_prev / interval_s - alpha * interval_s / 2
    if w0 <= 0:
        return None
    margin = w0 * w0 - 2 * alpha * theta_next
    if margin <= 0:
        return None
    return 2 * theta_next / (w0 + math.sqrt(margin))


@lru_cache(maxsize=16)
def hall_timeout_design(spec: Spec) -> HallTimeout:
    m, hall = spec.motor, spec.hall
    corner = safe_state_corner(m, hall, spec.tolerances)
    k_e = float(corner.k_e) * 60 / (2 * math.pi)  # V s/rad, mechanical
    s = float(hall.sector_shortening)
    # the viscous friction's torque at the fastest a rotor of the speed range turns (the
    # top speed, up to 1 / (1 - s) faster than its interval says): a bound at every
    # speed below
    fastest = float(spec.controller.speed_max_rpm) * 2 * math.pi / 60 / (1 - s)
    torque = (
        float(line_to_line_peak(m.back_emf_shape))
        * k_e
        * float(spec.protection.short_circuit_current_max_a)
        + float(m.viscous_friction_n_m_s) * fastest
    )
    alpha = torque / float(m.rotor_inertia_kg_m2)
    sector = math.pi / 3 / m.pole_pairs
    theta_prev, theta_next = (1 - s) * sector, (1 + s) * sector
    hz = float(hall.timer_clock_hz)
    top = (2**hall.counter_bits - 1) >> SHIFT
    # from the shortest interval the port accepts (a shorter one is over-speed: refused,
    # no commutation and no time-out); below it the counts' margins do not fit
    first = max(1, math.floor(10 * hz / (m.pole_pairs * float(spec.controller.speed_max_rpm))))
    period_max = 0
    for period in range(first, top + 1):
        latest = latest_next_interval((period + 1) / hz, theta_prev, theta_next, alpha)
        if latest is None or latest * hz > (period << SHIFT) - MARGIN_TICKS:
            break
        period_max = period
    speed = 10 * hz / (m.pole_pairs * period_max) if period_max else None
    return HallTimeout(SHIFT, period_max, alpha, speed)

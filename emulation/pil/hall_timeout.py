"""The PIL's yardstick for the Hall time-out: when a turning rotor must make its next edge.

Computed here from the spec, apart from the port's design
(`codegen/control/hall_timeout.py`), so a wrong design constant fails the scenarios:

* The hardest a rotor can brake, alpha = tau_max / J: the machine's torque
  sum(e_i i_i) / w is at most the worst motor's peak line EMF per unit of speed
  (`safe_state.worst_line_emf_v`) times the largest current, the bridge's rating
  (protection.short_circuit_current_max), plus the viscous friction at the fastest the
  rotor turns; J is the rotor's own inertia.
* Sectors: each Hall edge up to s x 30 electrical degrees off its place (s the sector
  shortening), so the interval measured may belong to a sector (1 - s) 60 deg long and
  the next be (1 + s) 60 deg.
* The next edge's latest time: the rotor braking at alpha through the previous sector
  (the slowest it can leave it after its interval) and through the next (the slowest
  speed profile there), found as the roots of the motion's quadratic (numpy); where the
  rotor may stop within the next sector there is none (`None`).

Requirement (`TIMEOUT_INTERVALS`): frozen Hall lines, the rotor turning, trip within 4 of
the last interval where a turning rotor is bound to make its next edge by then, and by
the Hall counter's wrap elsewhere; a rotor braking at alpha all the way never trips.
"""

from __future__ import annotations

import math

import numpy as np

from codegen.spec_model import Spec
from emulation.pil.safe_state import worst_line_emf_v

#: The time-out the PIL requires where the physics bounds the next edge: 4 intervals.
TIMEOUT_INTERVALS = 4
#: Around the speed where the bound stops holding, either the 4 intervals or the wrap:
#: the bound with the interval this much longer must still fit this much inside them.
BOUNDARY_GUARD = 0.05


def deceleration(spec: Spec) -> float:
    """alpha, mechanical rad/s^2: the rated current through the worst motor's EMF, and
    the viscous friction at the fastest the speed range's rotor turns (speed_max, up to
    1 / (1 - s) faster than its interval says)."""
    rpm = 1000.0
    volts_per_rad_s = worst_line_emf_v(spec, rpm) / (rpm * 2 * math.pi / 60)
    torque = volts_per_rad_s * float(spec.protection.short_circuit_current_max_a)
    fastest = float(spec.controller.speed_max_rpm) / (1 - float(spec.hall.sector_shortening))
    torque += float(spec.motor.viscous_friction_n_m_s) * fastest * 2 * math.pi / 60
    return torque / float(spec.motor.rotor_inertia_kg_m2)


def _sectors(spec: Spec) -> tuple[float, float]:
    """(shortest, longest) sector, mechanical rad."""
    s = float(spec.hall.sector_shortening)
    nominal = 2 * math.pi / (6 * spec.motor.pole_pairs)
    return (1 - s) * nominal, (1 + s) * nominal


def latest_next_edge_s(spec: Spec, interval_s: float) -> float | None:
    """The longest the sector after one of `interval_s` can last for a rotor that
    reaches its end (s), or None where the rotor may stop within it."""
    alpha = deceleration(spec)
    shortest, longest = _sectors(spec)
    # through the previous sector at alpha: shortest = w_in t - alpha t^2 / 2, and the
    # speed out of it w_in - alpha t
    w_out = shortest / interval_s - alpha * interval_s / 2
    if w_out <= 0:
        return None
    # through the next: longest = w_out t - alpha t^2 / 2; the first positive real root
    roots = np.roots([alpha / 2, -w_out, longest])
    real = [float(r.real) for r in roots if abs(r.imag) < 1e-12 * abs(r) and r.real > 0]
    return min(real) if real else None


def timeout_bound_s(
    spec: Spec, interval_s: float, *, guard: float = BOUNDARY_GUARD
) -> float | None:
    """Where the PIL requires the time-out of TIMEOUT_INTERVALS intervals (s after the
    last edge); None where it accepts the counter's wrap (the rotor may stop within the
    sector, or the bound is within `guard` of the requirement; 0: where the time-out
    of TIMEOUT_INTERVALS is right at all)."""
    latest = latest_next_edge_s(spec, interval_s * (1 + guard))
    limit = TIMEOUT_INTERVALS * interval_s
    if latest is None or latest > limit * (1 - guard):
        return None
    return limit


#: The hardest braking scenario's interval: this far below the longest one after which
#: a turning rotor is still bound to make its next edge (there the next sector may last
#: up to 2.4 of it at equal sectors, 3.8 at 25 % sector shortening; 0.5 % below, 2.35
#: on the paper motor: a time-out of 2 intervals trips)
HARDEST_BELOW = 0.005
#: ... and its next sector this far inside the Hall counter's range (past the range the
#: counter's wrap is the time-out whatever the physics)
RANGE_INSIDE = 0.05
#: ... and its interval this far above the one at controller.speed_max (shorter is over
#: speed: the edge refused)
OVER_SPEED_INSIDE = 0.03
_BISECTION_STEPS = 60


def hardest_braking(spec: Spec) -> tuple[float, float] | None:
    """(interval, next) in s: a shortest sector braked through at alpha in `interval`,
    then the longest sector it can be followed by, braked through at alpha in `next`,
    the latest edge of a turning rotor; near the slowest speed where that edge is bound
    to come, with `next` inside the Hall counter's range. None where there is none."""
    hz = float(spec.hall.timer_clock_hz)
    counter_s = (2**spec.hall.counter_bits - 1) / hz
    fastest = 10 * hz / (spec.motor.pole_pairs * float(spec.controller.speed_max_rpm)) / hz
    if latest_next_edge_s(spec, fastest) is None:
        return None
    low, high = fastest, counter_s
    if latest_next_edge_s(spec, high) is not None:
        low = high  # bound up to the counter's range (and the room below cuts it)
    else:
        for _ in range(_BISECTION_STEPS):
            mid = (low + high) / 2
            if latest_next_edge_s(spec, mid) is None:
                high = mid
            else:
                low = mid
    interval = low * (1 - HARDEST_BELOW)
    room = counter_s * (1 - RANGE_INSIDE)
    following = latest_next_edge_s(spec, interval)
    if following is None or following > room:
        # the longest interval whose next sector fits the counter, down to one inside
        # the over-speed limit (a shorter interval is refused, not braked)
        least = fastest * (1 + OVER_SPEED_INSIDE)
        bounded = latest_next_edge_s(spec, least)
        if least >= interval or bounded is None or bounded > room:
            return None
        low, high = least, interval
        for _ in range(_BISECTION_STEPS):
            mid = (low + high) / 2
            edge = latest_next_edge_s(spec, mid)
            if edge is not None and edge <= room:
                low = mid
            else:
                high = mid
        interval = low
        following = latest_next_edge_s(spec, interval)
        assert following is not None
    # The rotor enters the braked sector at speed_into(interval), which under a hard
    # braking is well above the sector's mean: kept OVER_SPEED_INSIDE below
    # controller.speed_max (a 1-pole-pair spindle braking at 2.1e7 rad/s^2 had been
    # started at 90 382 rpm, over its 90 000, and tripped OVER_SPEED: a helper's hunt).
    # speed_into(t) <= w_max exactly for t in [t1, t2], the roots of
    # alpha t^2 / 2 - w_max t + shortest; shorter intervals than the one chosen stay
    # bounded (the rotor only leaves its sector faster).
    alpha = deceleration(spec)
    shortest, _ = _sectors(spec)
    w_max = float(spec.controller.speed_max_rpm) * (1 - OVER_SPEED_INSIDE) * 2 * math.pi / 60
    discriminant = w_max**2 - 2 * alpha * shortest
    if discriminant < 0:
        return None
    t1 = (w_max - math.sqrt(discriminant)) / alpha
    t2 = (w_max + math.sqrt(discriminant)) / alpha
    if interval > t2:
        interval = t2
        following = latest_next_edge_s(spec, interval)
        if following is None or following > room:
            return None
    if interval < t1:
        return None
    return interval, following


def speed_into(spec: Spec, interval_s: float) -> float:
    """The speed (rpm) a rotor braking at alpha enters a shortest sector with, to cross
    it in `interval_s`."""
    shortest, _ = _sectors(spec)
    w_in = shortest / interval_s + deceleration(spec) * interval_s / 2
    return w_in * 60 / (2 * math.pi)

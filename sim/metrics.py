"""The numbers the paper argues with, measured on one simulated commutation.

* Non-commutating current deviation: per carrier period, (|mean i_nc| - I) / I in %,
  over the commutation (the periods that lie mostly between the edge and the turn-off
  current reaching zero, or the commanded end if later and the command differs from
  the main duty). Per-period means remove the PWM ripple, which no
  duty rule can suppress; the worst period (largest magnitude, signed) is reported.
  Negative: the non-commutating current sags (paper Fig. 4 b), positive: it swells
  (Fig. 4 c).
* Torque ripple: (max - min) / |mean| of the per-period torque sum e_x i_x / omega_m
  over the last pre-edge period and the commutation periods.
* Commutation time: when the turn-off current reaches zero, as a fraction of the
  60 deg interval; None when it does not within the interval.
* Gate transitions (both edges) and pulses (turn-ons) of the turn-on and turn-off
  transistors while the commutation command is active (switched plant only).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from sim.command import Command
from sim.scenario import Case
from sim.trace import Trace


@dataclass(frozen=True)
class CommutationMetrics:
    deviation_worst_pct: float
    deviation_mean_pct: float
    torque_ripple_pct: float
    #: Turn-off current zero time over the sector time; None: not within the sector.
    commutation_fraction: float | None
    commanded_fraction: float
    on_transitions: int | None
    off_transitions: int | None
    on_pulses: int | None
    off_pulses: int | None
    periods: int
    #: Peak-to-peak current ripple of the last pre-edge period, % of I (switched plant):
    #: the scale below which per-period deviations are carrier-phase effects.
    pre_edge_ripple_pct: float

    @property
    def finished(self) -> bool:
        return self.commutation_fraction is not None


def acts_like_main_duty(command: Command) -> bool:
    """The commutation command changes nothing against the main duty (no suppression,
    or a conventional command clamped to D_off = 0 at the main duty): its commanded
    end is then not an event in the plant."""
    return (
        command.constant_duties
        and command.off_duty(0) == 0.0
        and command.on_duty(0) == command.main_duty
    )


def commutation_end(case: Case, command: Command, trace: Trace) -> tuple[float, float | None]:
    """(end of the measured window, turn-off zero time or None).

    The window ends when the turn-off current reaches zero, or at the commanded end
    if that is later and the command differs from the main duty (its duties then keep
    acting on the non-commutating current).
    """
    zero = trace.first_zero(case.edge.turn_off, after=0.0)
    if zero is not None and zero > case.sector_time_s:
        zero = None
    physical = zero if zero is not None else case.sector_time_s
    commanded = 0.0 if acts_like_main_duty(command) else command.commutation_time_s
    return min(max(commanded, physical), case.sector_time_s), zero


def measure(case: Case, command: Command, trace: Trace) -> CommutationMetrics:
    end, zero = commutation_end(case, command, trace)
    period = case.drive.pwm_period_s
    starts = trace.period_starts
    # Periods mostly inside the commutation: a period straddling its end would mix in
    # the main current loop's duty, which is not what the commutation rule controls.
    inside = (starts >= -1e-12) & (starts + 0.5 * period <= max(end, period) + 1e-12)
    if not inside.any():
        inside = starts >= -1e-12
        inside &= starts <= starts[inside].min()
    nc = case.edge.non_commutating
    sign = case.edge.current_signs[nc]
    deviation = (sign * trace.period_currents[inside, nc] - case.current_a) / case.current_a * 100
    worst = float(deviation[np.argmax(np.abs(deviation))])
    omega = case.drive.mechanical_speed_rad_s(case.speed_rpm)
    with_reference = inside | ((starts < 0.0) & (starts >= -period - 1e-12))
    torque = trace.period_power[with_reference] / omega
    ripple = float((torque.max() - torque.min()) / abs(torque.mean()) * 100)
    counts: list[int | None] = [None, None, None, None]
    if trace.model == "switched" and command.turn_on_switch is not None:
        window = (0.0, command.commutation_time_s)
        on, off = command.turn_on_switch, command.turn_off_switch
        assert off is not None
        counts = [
            trace.transitions_of(on, *window),
            trace.transitions_of(off, *window),
            trace.turn_ons_of(on, *window),
            trace.turn_ons_of(off, *window),
        ]
    sector = case.sector_time_s
    last = (trace.times >= -period - 1e-12) & (trace.times <= 0.0)
    off_current = trace.currents[last, case.edge.turn_off]
    ripple_before = float(off_current.max() - off_current.min()) / case.current_a * 100
    return CommutationMetrics(
        deviation_worst_pct=worst,
        deviation_mean_pct=float(deviation.mean()),
        torque_ripple_pct=ripple,
        commutation_fraction=None if zero is None else zero / sector,
        commanded_fraction=command.commutation_time_s / sector,
        on_transitions=counts[0],
        off_transitions=counts[1],
        on_pulses=counts[2],
        off_pulses=counts[3],
        periods=int(inside.sum()),
        pre_edge_ripple_pct=ripple_before,
    )

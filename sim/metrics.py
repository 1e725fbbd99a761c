"""The numbers the paper argues with, measured on one simulated commutation.

The commutation lasts from the Hall edge until the turn-off current reaches zero, or
until the commanded end if that is later and the command differs from the main duty
(its duties then keep acting on the non-commutating current). The measured window is
defined from that physics: every carrier period that overlaps the commutation, plus
the one after it, where the non-commutating current settles from what the
commutation did to it (a dip that the commutation digs is deepest when the turn-off
current has just reached zero, which is inside the period that contains that instant
or at the start of the next).

* Non-commutating current deviation, (|i_nc| - I) / I in %, two ways:
  - per carrier period: the mean over each period of the window; the largest
    magnitude (signed) is `deviation_worst_pct`. Period means remove the PWM ripple,
    which no duty rule can suppress;
  - instantaneous: the extreme of the current itself over the window
    (`deviation_peak_pct`, signed), ripple included.
  Negative: the non-commutating current sags (paper Fig. 4 b), positive: it swells
  (Fig. 4 c).
* Torque ripple: (max - min) / |mean| of the per-period torque sum e_x i_x / omega_m
  over the last pre-edge period and the window's periods.
* Commutation time: when the turn-off current reaches zero, as a fraction of the
  60 deg interval; None when it does not within the interval.
* Gate transitions (both edges) and pulses (turn-ons) of the turn-on and turn-off
  transistors while the commutation command is active, and pulses while the
  turn-off current still flows (switched plant only).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from sim.command import Command
from sim.scenario import Case
from sim.trace import Trace

#: Seconds of slack on period-boundary comparisons.
_SLACK = 1e-12


@dataclass(frozen=True)
class CommutationMetrics:
    #: Extreme per-period mean deviation over the window, % of I (signed).
    deviation_worst_pct: float
    deviation_mean_pct: float
    #: Extreme instantaneous deviation over the window, % of I (signed, ripple included).
    deviation_peak_pct: float
    torque_ripple_pct: float
    #: Turn-off current zero time over the sector time; None: not within the sector.
    commutation_fraction: float | None
    commanded_fraction: float
    on_transitions: int | None
    off_transitions: int | None
    on_pulses: int | None
    off_pulses: int | None
    #: Pulses (turn-ons) of the turn-on / turn-off transistor while the turn-off
    #: current flows (the physical commutation; what a scope shows). Switched only.
    on_pulses_flowing: int | None
    off_pulses_flowing: int | None
    #: Carrier periods in the window (those overlapping the commutation, plus one).
    periods: int
    #: End of the commutation the window is built on, s from the edge.
    commutation_end_s: float
    #: Per-period mean deviations over the window, % of I, in time order.
    period_deviations_pct: tuple[float, ...]
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
    """(end of the commutation, turn-off zero time or None).

    The commutation ends when the turn-off current reaches zero, or at the commanded
    end if that is later and the command differs from the main duty.
    """
    zero = trace.first_zero(case.edge.turn_off, after=0.0)
    if zero is not None and zero > case.sector_time_s:
        zero = None
    physical = zero if zero is not None else case.sector_time_s
    commanded = 0.0 if acts_like_main_duty(command) else command.commutation_time_s
    return min(max(commanded, physical), case.sector_time_s), zero


def window_periods(trace: Trace, end: float) -> np.ndarray:
    """Mask of the trace's periods in the window: those overlapping (0, end), plus the
    next one (when the run holds it)."""
    starts, ends = trace.period_starts, trace.period_ends
    overlapping = (starts < end - _SLACK) & (ends > _SLACK)
    if not overlapping.any():
        overlapping = (starts >= -_SLACK) & (starts <= end + _SLACK)
        if not overlapping.any():
            return overlapping
        overlapping &= starts <= starts[overlapping].min()
    last_end = ends[overlapping].max()
    later = np.flatnonzero(starts >= last_end - _SLACK)
    window = overlapping.copy()
    if later.size:
        window[later[np.argmin(starts[later])]] = True
    return window


def window_end(trace: Trace, end: float) -> float:
    """End time of the measured window (the end of its last period)."""
    mask = window_periods(trace, end)
    return float(trace.period_ends[mask].max()) if mask.any() else end


def _signed_extreme(values: np.ndarray) -> float:
    return float(values[np.argmax(np.abs(values))])


def _periods(
    trace: Trace, end: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(starts, ends, mean currents, mean power, window mask) of the periods measured.
    Where the sector ends inside the first carrier period after the edge (a sector
    shorter than a PWM period), no whole period lies in the window: the period the next
    Hall edge's carrier restart cuts short, averaged over its own length as every cut
    period is, is the window then."""
    starts, ends = trace.period_starts, trace.period_ends
    currents, power = trace.period_currents, trace.period_power
    window = window_periods(trace, end)
    cut = trace.cut_period
    if not window.any() and cut is not None and cut[0] < end - _SLACK and cut[1] > _SLACK:
        starts, ends = np.append(starts, cut[0]), np.append(ends, cut[1])
        currents = np.vstack([currents.reshape(-1, 3), cut[2]])
        power = np.append(power, cut[3])
        window = np.append(np.zeros(trace.period_starts.shape, dtype=bool), True)
    return starts, ends, currents, power, window


def measure(case: Case, command: Command, trace: Trace) -> CommutationMetrics:
    end, zero = commutation_end(case, command, trace)
    period = case.drive.pwm_period_s
    starts, ends, currents, power, window = _periods(trace, end)
    nc = case.edge.non_commutating
    sign = case.edge.current_signs[nc]
    current = case.current_a
    deviation = (sign * currents[window, nc] - current) / current * 100
    stop = float(ends[window].max()) if window.any() else end
    during = (trace.times >= 0.0) & (trace.times <= stop + _SLACK)
    instantaneous = (sign * trace.currents[during, nc] - current) / current * 100
    omega = case.drive.mechanical_speed_rad_s(case.speed_rpm)
    full = np.abs(ends - starts - period) < 1e-9 * period
    before = np.flatnonzero(full & (ends <= _SLACK))
    with_reference = window.copy()
    if before.size:
        with_reference[before[-1]] = True
    torque = power[with_reference] / omega
    ripple = float((torque.max() - torque.min()) / abs(torque.mean()) * 100)
    counts: list[int | None] = [None] * 6
    if trace.model == "switched" and command.turn_on_switch is not None:
        active = (0.0, command.commutation_time_s)
        flowing = (0.0, min(zero if zero is not None else end, command.commutation_time_s))
        on, off = command.turn_on_switch, command.turn_off_switch
        assert off is not None
        counts = [
            trace.transitions_of(on, *active),
            trace.transitions_of(off, *active),
            trace.turn_ons_of(on, *active),
            trace.turn_ons_of(off, *active),
            trace.turn_ons_of(on, *flowing),
            trace.turn_ons_of(off, *flowing),
        ]
    sector = case.sector_time_s
    last = (trace.times >= -period - _SLACK) & (trace.times <= 0.0)
    off_current = trace.currents[last, case.edge.turn_off]
    ripple_before = float(off_current.max() - off_current.min()) / current * 100
    return CommutationMetrics(
        deviation_worst_pct=_signed_extreme(deviation),
        deviation_mean_pct=float(deviation.mean()),
        deviation_peak_pct=_signed_extreme(instantaneous),
        torque_ripple_pct=ripple,
        commutation_fraction=None if zero is None else zero / sector,
        commanded_fraction=command.commutation_time_s / sector,
        on_transitions=counts[0],
        off_transitions=counts[1],
        on_pulses=counts[2],
        off_pulses=counts[3],
        on_pulses_flowing=counts[4],
        off_pulses_flowing=counts[5],
        periods=int(window.sum()),
        commutation_end_s=end,
        period_deviations_pct=tuple(float(v) for v in deviation),
        pre_edge_ripple_pct=ripple_before,
    )

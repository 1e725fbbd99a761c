"""A duty schedule over the PWM periods of a short commutation (Python prototype).

When the commutation lasts one to three carrier periods a constant duty pair cannot
hold the per-period mean of the non-commutating current: the duty only sets a
period's average voltage, and within a period the on- and off-intervals move the
current by about the ripple, so where in the period the turn-off current reaches
zero decides the mean. This prototype asks what a schedule of one pair per period
can do there: the commutation is stretched to n = max(2, ceil(t_c / T)) whole periods
(so the port's carrier restart at its end falls on a period boundary), and the n
pairs (D_on,k, D_off,k) are solved so that

* each period's mean of |i_nc| equals I, and the period after the commutation too
  (its mean is set by the current left at n T);
* the turn-off current is zero at n T;

by Gauss-Newton with finite differences on the switched plant itself. That is a
perfect-model bound: it shows what a per-period schedule can reach, not a firmware
rule. The firmware would need the same conditions in closed form, which the
switched plant's pieces give (each on/off interval is an exact exponential).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from sim.command import Command
from sim.runs import simulate
from sim.scenario import Case
from sim.schedule import switch_index

METHOD = "short_schedule"
_STEP = 1e-3  # finite-difference step in duty
_ITERATIONS = 12


@dataclass(frozen=True)
class Schedule:
    command: Command
    residual_pct: float  # the largest remaining condition error, % of I
    iterations: int


def _residuals(case: Case, command: Command) -> np.ndarray:
    """Period-mean deviations of the n commutation periods and the next, and i_b(n T)."""
    run = simulate(case, command, "switched")
    wanted = len(command.on_duties) + 1
    deviations = np.array(run.metrics.period_deviations_pct[:wanted])
    if deviations.size < wanted:
        deviations = np.pad(deviations, (0, wanted - deviations.size), constant_values=100.0)
    off = case.edge.turn_off
    sign = case.edge.current_signs[off]
    end = command.commutation_time_s
    left = sign * float(run.trace.current_at(end)[off])
    return np.concatenate((deviations, [left / case.current_a * 100.0]))


def short_schedule(
    case: Case, start: Command, period_counts: int, hall_clock_hz: float
) -> Schedule:
    """Per-period pairs from `start` (a constant-pair command) over whole periods."""
    period = case.drive.pwm_period_s
    periods = max(2, math.ceil(start.commutation_time_s / period - 1e-6))
    end = round(periods * period * hall_clock_hz) / hall_clock_hz
    x = np.array([start.on_duty(0)] * periods + [start.off_duty(0)] * periods)

    def command(values: np.ndarray) -> Command:
        clipped = np.clip(values, 0.0, 1.0)
        return Command(
            method=METHOD,
            turn_on_switch=switch_index(case.edge.modulated_on),
            turn_off_switch=switch_index(case.edge.modulated_off),
            on_duties=tuple(float(v) for v in clipped[:periods]),
            off_duties=tuple(float(v) for v in clipped[periods:]),
            commutation_time_s=end,
            main_duty=start.main_duty,
        )

    residual = _residuals(case, command(x))
    iterations = 0
    while iterations < _ITERATIONS and np.max(np.abs(residual)) >= 0.2:
        iterations += 1
        jacobian = np.empty((residual.size, x.size))
        for k in range(x.size):
            probe = x.copy()
            probe[k] += _STEP if probe[k] + _STEP <= 1.0 else -_STEP
            jacobian[:, k] = (_residuals(case, command(probe)) - residual) / (probe[k] - x[k])
        step, *_ = np.linalg.lstsq(jacobian, -residual, rcond=None)
        scale = 1.0
        for _ in range(8):
            trial = np.clip(x + scale * step, 0.0, 1.0)
            trial_residual = _residuals(case, command(trial))
            if np.max(np.abs(trial_residual)) < np.max(np.abs(residual)):
                x, residual = trial, trial_residual
                break
            scale *= 0.5
        else:
            break
    quantised = np.round(np.clip(x, 0.0, 1.0) * period_counts) / period_counts
    final = command(quantised)
    return Schedule(final, float(np.max(np.abs(_residuals(case, final)))), iterations)

"""The report's studies beyond the sweep: EMF shape, short commutations, Table 4.

* EMF shape: the generated `improved_r` core (which assumes the 120 deg trapezoid)
  against the paper's flat EMF and trapezoids of other flat-top widths, next to the
  shape-aware prototype (`sim.shape_rule`) and its carrier-aligned form, on the
  averaged and the switched plant.
* Short commutations: where the rule's commutation lasts under three PWM periods
  (`sim.regions`), the core's constant pair next to the per-period schedule bound
  (`sim.short_schedule`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from sim.command import Command
from sim.current_loop import settle
from sim.drive import Drive
from sim.emf import TRAPEZOID_120, EmfShape
from sim.regions import Regions
from sim.runs import IMPROVED_R, Controller, simulate
from sim.scenario import Case, paper_edge
from sim.shape_rule import aligned_command, shape_rule_command
from sim.short_schedule import short_schedule

#: EMF shapes of the study: label -> (flat-top width in deg, or None for the paper's
#: frozen flat EMF, or 0 for the spec's own shape).
SHAPES: tuple[tuple[str, float | None], ...] = (
    ("spec", 0.0),
    ("flat (paper)", None),
    ("trapezoid 150 deg", 150.0),
    ("trapezoid 135 deg", 135.0),
    ("trapezoid 120 deg", 120.0),
    ("trapezoid 100 deg", 100.0),
)
RULES = ("improved_r (C core)", "improved_r_shape", "improved_r_aligned")
#: Speeds of the study: about this many over the rule's target range within the spec's.
STUDY_POINTS = 9


@dataclass(frozen=True)
class ShapeRow:
    shape: str
    speed_rpm: float
    rule: str
    averaged_pct: float
    switched_pct: float
    on_duty: float
    off_duty: float
    periods: float  # commanded commutation in PWM periods


@dataclass(frozen=True)
class ShortRow:
    speed_rpm: float
    periods: float  # the core's commanded commutation, PWM periods
    core_pct: float  # switched plant, the C core's constant pair
    aligned_pct: float
    schedule_pct: float  # per-period schedule (perfect-model bound)
    schedule_peak_pct: float  # its instantaneous extreme (ripple)
    pre_edge_ripple_pct: float
    on_duties: tuple[float, ...]
    off_duties: tuple[float, ...]


@dataclass(frozen=True)
class Studies:
    shapes: tuple[ShapeRow, ...]
    shape_speeds: tuple[float, ...]
    short: tuple[ShortRow, ...]


def study_speeds(drive: Drive, low: float, high: float) -> tuple[float, ...]:
    """STUDY_POINTS speeds over [low, high] clipped to the spec's range, whole rpm."""
    lo = max(low, drive.speed_min_rpm)
    hi = min(high, drive.speed_max_rpm)
    if hi <= lo:
        lo, hi = drive.speed_min_rpm, drive.speed_max_rpm
    return tuple(sorted({float(round(s)) for s in np.linspace(lo, hi, STUDY_POINTS)}))


def _shape_drive(drive: Drive, width: float | None) -> tuple[Drive, EmfShape]:
    if width is None:
        return drive, "flat"
    if width == 0.0:
        return drive, "spec"
    return drive.with_flat_top(width), "spec"


def shape_study(
    controller: Controller, drive: Drive, speeds: tuple[float, ...]
) -> tuple[ShapeRow, ...]:
    hall = float(controller.cores.scaling.hall_clock_hz)
    counts = controller.period_counts
    rows = []
    shapes = [s for s in SHAPES if not (s[1] == 120.0 and drive.emf_points == TRAPEZOID_120)]
    for label, width in shapes:
        shaped, emf = _shape_drive(drive, width)
        for speed in speeds:
            loop = settle(shaped, speed, drive.braking_current_a, counts)
            case = Case(shaped, paper_edge(), speed, loop.current_a, emf)
            measured = controller.measured_current(case)
            commands: dict[str, Command] = {
                RULES[0]: controller.command(IMPROVED_R, case, loop.duty),
                RULES[1]: shape_rule_command(case, measured, loop.duty, counts, hall),
                RULES[2]: aligned_command(case, measured, loop.duty, counts, hall),
            }
            for rule, command in commands.items():
                rows.append(
                    ShapeRow(
                        shape=label,
                        speed_rpm=speed,
                        rule=rule,
                        averaged_pct=simulate(
                            case, command, "averaged"
                        ).metrics.deviation_worst_pct,
                        switched_pct=simulate(
                            case, command, "switched"
                        ).metrics.deviation_worst_pct,
                        on_duty=command.on_duty(0),
                        off_duty=command.off_duty(0),
                        periods=command.commutation_time_s / drive.pwm_period_s,
                    )
                )
    return tuple(rows)


def short_study(
    controller: Controller, drive: Drive, found: Regions, points: int = 5
) -> tuple[ShortRow, ...]:
    """The core and the per-period schedule where the commutation is under 3 periods."""
    if not found.under_three_periods:
        return ()
    hall = float(controller.cores.scaling.hall_clock_hz)
    counts = controller.period_counts
    speeds: set[float] = set()
    for low, high in found.under_three_periods:
        speeds |= {float(round(s)) for s in np.linspace(low, high, points)}
    rows = []
    for speed in sorted(speeds):
        loop = settle(drive, speed, drive.braking_current_a, counts)
        case = Case(drive, paper_edge(), speed, loop.current_a, "spec")
        core = controller.command(IMPROVED_R, case, loop.duty)
        if core.commutation_time_s <= 0.0:
            continue  # the core refused the input (INPUT_SATURATED): nothing to shape
        measured = controller.measured_current(case)
        start = shape_rule_command(case, measured, loop.duty, counts, hall)
        aligned = aligned_command(case, measured, loop.duty, counts, hall)
        schedule = short_schedule(case, start, counts, hall)
        core_metrics = simulate(case, core, "switched").metrics
        schedule_metrics = simulate(case, schedule.command, "switched").metrics
        rows.append(
            ShortRow(
                speed_rpm=speed,
                periods=core.commutation_time_s / drive.pwm_period_s,
                core_pct=core_metrics.deviation_worst_pct,
                aligned_pct=simulate(case, aligned, "switched").metrics.deviation_worst_pct,
                schedule_pct=schedule_metrics.deviation_worst_pct,
                schedule_peak_pct=schedule_metrics.deviation_peak_pct,
                pre_edge_ripple_pct=core_metrics.pre_edge_ripple_pct,
                on_duties=schedule.command.on_duties,
                off_duties=schedule.command.off_duties,
            )
        )
    return tuple(rows)

"""Table 4's switching counts: the conditions that reproduce the paper, and the spec's.

A modulated transistor is switched on once per carrier period that starts inside the
commutation, so its pulse count is about f t_com, and t_com (Eq. 20) is proportional
to the current: the count scales with I f. The paper states neither its current nor
its PWM frequency, so the counts are compared along I at the spec's frequency (the
generated core is built for it), through the C core and the switched plant:

* improved: the braking current whose counts equal the paper's at every Table 4
  speed of the low segment (the paper's 2500 rpm row shows the high-segment pattern
  below its own 2542 rpm cut-off, which the audit reports);
* conventional: its commanded time is Eq. 20 with D_on = the main duty, which a
  current loop settles at (1 - D) U_d = 2E - 2RI, where Eq. 20 is L / (2R) at every
  speed and current; so no current loop on this motor gives the paper's falling
  counts. The main duty that would is listed per speed, from Eq. 20 solved for D.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from codegen.audit.transcription import Table4Row
from sim.current_loop import settle
from sim.drive import Drive
from sim.runs import Controller, simulate
from sim.scenario import Case, paper_edge

#: Braking currents tried, A.
CURRENTS_A = (1.0, 2.0, 3.0, 4.0, 5.0, 6.0)


@dataclass(frozen=True)
class CountRow:
    speed_rpm: float
    current_a: float
    #: Pulses while the turn-off current flows (the physical commutation, as a scope
    #: counts them); the commanded window can be longer (Eq. 20 without R).
    on_pulses: int
    off_pulses: int
    commanded_us: float


@dataclass(frozen=True)
class Table4Study:
    pwm_frequency_hz: float
    #: current -> improved counts per Table 4 speed (C core, switched plant).
    improved: dict[float, tuple[CountRow, ...]]
    #: Currents at which improved reproduces every low-segment row of the paper.
    reproducing_a: tuple[float, ...]
    #: Conventional at the reproducing current (or the spec's), the loop's settled duty.
    conventional_at_reproducing: tuple[CountRow, ...]
    #: The spec's braking current: both methods at the loop's settled duty.
    spec_improved: tuple[CountRow, ...]
    spec_conventional: tuple[CountRow, ...]
    #: Per Table 4 speed: main duty range for which Eq. 20 gives the paper's
    #: conventional count at the reproducing current (low, high), or None.
    conventional_duty: tuple[tuple[float, float] | None, ...]


def _counts(
    controller: Controller, drive: Drive, method: str, speed: float, current: float
) -> CountRow:
    loop = settle(drive, speed, current, controller.period_counts)
    case = Case(drive, paper_edge(), speed, loop.current_a, "spec")
    command = controller.command(method, case, loop.duty)
    metrics = simulate(case, command, "switched").metrics
    return CountRow(
        speed,
        loop.current_a,
        metrics.on_pulses_flowing or 0,
        metrics.off_pulses_flowing or 0,
        command.commutation_time_s * 1e6,
    )


def _duty_for_count(drive: Drive, speed: float, current: float, count: int) -> tuple[float, float]:
    """Main duties for which Eq. 20 (conventional, D_on = D) lasts count periods:
    t = I L / (2E - (1 - D) U_d) in ((count - 1) T, count T]."""
    period = drive.pwm_period_s
    emf, bus = drive.emf_v(speed), drive.bus_voltage_v
    charge = current * drive.inductance_h

    def duty(time: float) -> float:
        return 1.0 - (2.0 * emf - charge / time) / bus

    return duty(count * period), duty(max(count - 1, 1e-9) * period)


def table4_study(controller: Controller, drive: Drive, rows: tuple[Table4Row, ...]) -> Table4Study:
    speeds = [float(r.speed_rpm) for r in rows]
    # The rows the paper prints with the low-segment pattern (turn-on phase static).
    low = [r for r in rows if r.improved_on == 1]
    inside = [s for s in speeds if drive.speed_min_rpm <= s <= drive.speed_max_rpm]
    improved = {
        current: tuple(_counts(controller, drive, "improved", s, current) for s in inside)
        for current in CURRENTS_A
    }
    reproducing = tuple(
        current
        for current, counts in improved.items()
        if low
        and all(
            any(
                c.speed_rpm == float(r.speed_rpm)
                and (c.on_pulses, c.off_pulses) == (r.improved_on, r.improved_off)
                for c in counts
            )
            for r in low
        )
    )
    nominal = drive.braking_current_a
    reference = reproducing[0] if reproducing else nominal
    duties: list[tuple[float, float] | None] = []
    for r in rows:
        window = _duty_for_count(drive, float(r.speed_rpm), reference, r.conventional_on)
        duties.append(window if all(0.0 <= d <= 1.0 for d in window) else None)
    return Table4Study(
        pwm_frequency_hz=drive.pwm_frequency_hz,
        improved=improved,
        reproducing_a=reproducing,
        conventional_at_reproducing=tuple(
            _counts(controller, drive, "conventional", s, reference) for s in inside
        ),
        spec_improved=tuple(_counts(controller, drive, "improved", s, nominal) for s in inside),
        spec_conventional=tuple(
            _counts(controller, drive, "conventional", s, nominal) for s in inside
        ),
        conventional_duty=tuple(duties),
    )


def periods_started(time_s: float, frequency_hz: float) -> int:
    """Carrier periods that start inside a commutation of time_s (from the edge)."""
    return math.ceil(time_s * frequency_hz - 1e-9)

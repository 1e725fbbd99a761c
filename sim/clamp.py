"""Where a core clamps the commutation time to the Hall period: every period, through the C.

The core sets `BLDC_FLAG_TIME_CLAMPED` when its commutation time does not fit in the
60 deg interval: for `improved` when Eq. 20 exceeds the Hall period, for `improved_r`
when its search finds the turn-off current still positive at the sector's last whole
PWM period.
It then commands the whole sector (`commutation_ticks` = the Hall period). Neither
method reads the main duty for its timing, so the scan holds the edge, the bus and the
current and calls the compiled core at every Hall period (in ticks) of the spec's speed
range: the flagged speeds are the C's own decision, not a model of it.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

from codegen.spec_model import Spec
from sim.drive import Drive
from sim.runs import Controller
from sim.scenario import Case, paper_edge
from sim.sil import core_inputs

#: The methods whose commutation time can be clamped.
TIMED_METHODS = ("improved", "improved_r")
TIME_CLAMPED = "TIME_CLAMPED"


@dataclass(frozen=True)
class ClampScan:
    method: str
    bus_voltage_v: float
    current_a: float
    #: Flagged speed intervals (rpm, low to high), one per run of consecutive periods.
    clamped_rpm: tuple[tuple[float, float], ...]
    #: Hall periods scanned (every tick from the top speed down to the lowest speed).
    periods: int
    #: Speed of the shortest Hall period the core still commutates by rule (a shorter one
    #: is above its top speed: INPUT_SATURATED, no commutation time); None: none.
    fastest_rpm: float | None


def _rpm(drive: Drive, ticks: int, hall_clock_hz: float) -> float:
    return 10.0 / (ticks / hall_clock_hz * drive.pole_pairs)


def scan(
    controller: Controller, drive: Drive, method: str, bus_v: float, current_a: float
) -> ClampScan:
    """Call `method`'s core at every Hall period of [speed_min, speed_max]."""
    spec = controller.spec
    scale = controller.cores.scaling
    core = controller.cores.cores[method]
    hall = float(scale.hall_clock_hz)
    at_bus = replace(drive, bus_voltage_v=bus_v)
    case = Case(at_bus, paper_edge(), drive.speed_max_rpm, current_a, "spec")
    inputs = core_inputs(spec, scale, case, controller.measured_current(case), 0.0)
    shortest = inputs["hall_period_ticks"]
    longest = min(round(drive.sector_time_s(drive.speed_min_rpm) * hall), 2**16 - 1)
    bit = core.constants.flags[TIME_CLAMPED]
    runs: list[tuple[int, int]] = []
    fastest: int | None = None
    periods = range(shortest, longest + 1)
    for ticks, (commutation_ticks, flags) in zip(
        periods, core.over_periods(inputs, periods), strict=True
    ):
        if fastest is None and commutation_ticks > 0:
            fastest = ticks
        if flags & bit:
            if runs and runs[-1][1] == ticks - 1:
                runs[-1] = (runs[-1][0], ticks)
            else:
                runs.append((ticks, ticks))
    intervals = tuple(
        (_rpm(drive, high, hall), _rpm(drive, low, hall)) for low, high in reversed(runs)
    )
    top = None if fastest is None else _rpm(drive, fastest, hall)
    return ClampScan(method, bus_v, current_a, intervals, longest - shortest + 1, top)


def clamp_scans(controller: Controller, drive: Drive, spec: Spec) -> tuple[ClampScan, ...]:
    """Both timed methods at the spec's bus voltages (min, nominal, max) and braking
    currents (nominal, max)."""
    buses = (
        float(spec.inverter.bus_voltage_min_v),
        float(spec.inverter.bus_voltage_nominal_v),
        float(spec.inverter.bus_voltage_max_v),
    )
    currents = (
        float(spec.controller.braking_current_nominal_a),
        float(spec.controller.braking_current_max_a),
    )
    return tuple(
        scan(controller, drive, method, bus, current)
        for method in TIMED_METHODS
        for current in currents
        for bus in buses
    )

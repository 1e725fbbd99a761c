"""`init`'s estimate of the drive's CPU load at the top speed, before anything is built.

`make bench` measures the load from the generated firmware's own cycles
(`emulation.bench._cpu_load`); `init` has no firmware yet, so it prices the same events
with the worst handler cycles the bench measured on the checked-in motors (2 flash wait
states, entry and exit included). A sector at the top speed holds the Hall edge, its
EXTI, the commutation end, two timing runs and the bus changes the port's gate lets a
noisy bus pend (one per `bus_min_periods` PWM periods: one, or two where the sector is
not a whole number of periods), each timing run priced as a bus change (the bus handler
and the timing run it pends), and one current-loop run per PWM period it starts. The
estimate errs high for `improved_r`, whose search is shorter in a short sector; it is a
warning that the motor needs measuring, not a figure to hold the firmware to."""

from __future__ import annotations

import math
from dataclasses import dataclass
from fractions import Fraction

from codegen.port import bus_min_periods
from codegen.spec_model import Spec

CPU_HZ = 72_000_000

#: Hall edge 119 + its EXTI 57 + commutation end 129 (the worst of the checked-in
#: motors' `make bench` figures, cycles)
EDGE_EVENTS_CYCLES = 305
#: one timing run priced as a bus change (TIM1_UP, then the timing run it pends): 412
#: on the paper's methods, 1483 on `improved_r` (spec/paper_motor*.yaml's bench, since
#: the bus-change handler waits while the Hall interval is unknown: 398 and 1478 before)
TIMING_CYCLES = {"improved_r": 1490}
TIMING_CYCLES_DEFAULT = 415
#: the current loop's JEOC handler, once per PWM period (146-148 on the checked-in motors)
LOOP_CYCLES = 148


@dataclass(frozen=True)
class LoadEstimate:
    percent: float
    commutation_percent: float
    loop_percent: float
    sector_us: float


def estimate(spec: Spec) -> LoadEstimate:
    """The load over one sector at `controller.speed_max`."""
    sector_s = Fraction(60) / (spec.controller.speed_max_rpm * spec.motor.pole_pairs * 6)
    sector_cycles = sector_s * CPU_HZ
    timing = TIMING_CYCLES.get(str(spec.controller.method), TIMING_CYCLES_DEFAULT)
    # a current-loop run for each PWM period the sector starts, whole ones counted up,
    # as the bench counts them (the mean rate had put a 274 us sector under its 28.3 %)
    periods = math.ceil(spec.inverter.pwm_frequency_hz * sector_s)
    changes = -(-periods // bus_min_periods(sector_s, spec.inverter.pwm_frequency_hz))
    commutation = Fraction(EDGE_EVENTS_CYCLES + (2 + changes) * timing) / sector_cycles
    loop = Fraction(LOOP_CYCLES * periods) / sector_cycles
    return LoadEstimate(
        percent=float(100 * (commutation + loop)),
        commutation_percent=float(100 * commutation),
        loop_percent=float(100 * loop),
        sector_us=float(sector_s * 1_000_000),
    )


def _percent(value: float, budget: float) -> str:
    """`value` with as many decimals as show it above `budget` (25.008 over 25: 25.01,
    where a whole number had printed 25, "over its 25 %")."""
    for decimals in range(0, 6):
        shown = f"{value:.{decimals}f}"
        if float(shown) > budget:
            return shown
    return repr(value)


def over_budget(spec: Spec) -> str | None:
    """A warning when the estimate passes `firmware.cpu_load_budget`, else None."""
    load = estimate(spec)
    budget = float(spec.firmware.cpu_load_budget_percent)
    if load.percent <= budget:
        return None
    return (
        f"firmware.cpu_load_budget: the drive may take up to about {_percent(load.percent, budget)} % of"
        f" the CPU at controller.speed_max ({float(spec.controller.speed_max_rpm):g} rpm,"
        f" a {load.sector_us:.0f} us sector: the commutation's handlers"
        f" {load.commutation_percent:.0f} %, the current loop at"
        f" {float(spec.inverter.pwm_frequency_hz) / 1000:g} kHz {load.loop_percent:.0f} %),"
        f" over its {budget:g} % (an estimate from the checked-in motors' handler cycles;"
        " `bldc-codegen bench` measures this motor's): a lower PWM frequency or top speed"
        " lowers it"
    )

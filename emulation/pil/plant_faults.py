"""The fault scenarios with the motor in the loop: the firmware brakes the simulated
motor (emulation/pil/braking.py) and, once the loop and the commutations have settled,
one cause is applied; the latency is measured from the cause to TIM1's MOE cleared,
against the limits of emulation/pil/scenarios.py, with every invariant of the braking
run watched throughout and the motor still turning behind the bridge (its diodes
conduct into the bus after the trip, or the three lower switches short it).

* over-voltage: the bus itself steps to 10 % above inverter.bus_voltage_max (the bridge
  and the divider both see it) at the start of a PWM period;
* BKIN over-current: the comparator goes active mid-sector;
* Hall unplugged: the two low lines are pulled up together (code 7), the rotor turns on;
* bus ADC stuck at 0: the divider's input reads 0 V, the bridge still sees the bus;
* rotor stops: the rotor is blocked (speed 0): the Hall code stops changing while the
  bridge switches; latency from TIM3's wrap.

Where the fault leaves the short circuit, the motor runs on shorted for an electrical
period (at least three L/R, at most SHORT_FOLLOW_MAX_S) and the peak phase current the
plant integrates must stay within protection.short_circuit_current_max and within the
bound the safe state is chosen by (`safe_state.short_circuit_bound_a`): the physics of
the choice, not only the gates.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from codegen.spec_model import Spec
from emulation.pil.braking import SETTLING_EDGES, BrakingLoop, braking_setup
from emulation.pil.bus import PilError
from emulation.pil.iwdg import WatchdogResetError
from emulation.pil.rcc import TICK_HZ
from emulation.pil.safe_state import SHORT_CIRCUIT, short_circuit_bound_a
from emulation.pil.scenarios import (
    FAULT,
    Outcome,
    counter_range_end,
    shorten_quiet_wait,
    timeout_window,
)

#: Hall edges braked before the cause: the loop, the timing and the commutations run
EDGES_BEFORE = SETTLING_EDGES + 2
#: The longest the shorted motor is followed after a trip (s of motor time)
SHORT_FOLLOW_MAX_S = 0.05
#: Samples of the phase currents per electrical period while following the short
SHORT_SAMPLES_PER_PERIOD = 200


@dataclass(frozen=True)
class PlantFault:
    key: str
    run: Callable[[BrakingLoop], Outcome]


def _settle(loop: BrakingLoop) -> None:
    """Brake until EDGES_BEFORE Hall edges have passed: each sector lasts at most the
    stop speed's (the braking run takes many more edges to get there), so the wait is
    bounded; a rotor that slows below it first ends the fault's run."""
    stop = loop.setup.stop_rpm
    while len(loop.edges) < EDGES_BEFORE:
        # a rotor at rest brings no more edges: waiting for them never ended
        if loop.plant.next_sector_tick() is None:
            raise PilError(
                f"the rotor stopped ({loop.plant.speed_rpm:g} rpm) after {len(loop.edges)}"
                f" Hall edges, before the {EDGES_BEFORE} the fault waits for"
            )
        if loop.plant.speed_rpm < stop:
            raise PilError(
                f"the rotor slowed to {loop.plant.speed_rpm:.3g} rpm, below the braking run's"
                f" stop speed {stop:.3g} rpm, after {len(loop.edges)} Hall edges, before the"
                f" {EDGES_BEFORE} the fault waits for"
            )
        loop.advance_to(loop.machine.now + loop.run.board.pwm_period_ticks())


def _third_of_sector(loop: BrakingLoop) -> int:
    return round(loop.plant.drive.sector_time_s(loop.plant.speed_rpm) * TICK_HZ / 3)


def _until_tripped(loop: BrakingLoop, limit: int) -> None:
    """Run with the motor until MOE clears or `limit` ticks pass; then until main has
    published app_faults, as the scenarios do (`Run.run_until_tripped`)."""
    loop.run.run_until_tripped(limit, lambda ticks: loop.advance_to(loop.machine.now + ticks))


def follow_short_circuit(loop: BrakingLoop) -> tuple[float | None, list[str]]:
    """After a trip that left the short circuit: the motor shorted for an electrical
    period (three L/R at least), its peak phase current (A, None where the fault did
    not leave the short) and what it breaks: the bridge's rating, and the bound of the
    safe state's choice. The faults the shorted current raises later (the current
    sensor past its range, the comparator) are its consequence: the outcome is taken
    before."""
    machine, plant, spec = loop.machine, loop.plant, loop.spec
    if machine.tim1.moe or machine.tim1.gates() != SHORT_CIRCUIT or plant.speed_rpm <= 0:
        return None, []
    rpm = plant.speed_rpm  # the bound at the speed of entry (the rotor only slows)
    motor = spec.motor
    electrical_s = 60.0 / (motor.pole_pairs * rpm)
    tau_s = float(motor.phase_inductance_h / motor.phase_resistance_ohm)
    follow_s = min(max(electrical_s, 3 * tau_s), SHORT_FOLLOW_MAX_S)
    step = max(1, round(min(electrical_s, follow_s) * TICK_HZ / SHORT_SAMPLES_PER_PERIOD))
    end = machine.now + round(follow_s * TICK_HZ)
    peak = float(np.abs(plant.currents).max())
    while machine.now < end and machine.tim1.gates() == SHORT_CIRCUIT:
        loop.advance_to(min(machine.now + step, end))
        peak = max(peak, float(np.abs(plant.currents).max()))
    rating = float(spec.protection.short_circuit_current_max_a)
    bound = short_circuit_bound_a(spec, rpm)
    where = f"the short circuit from {rpm:.0f} rpm, followed {follow_s * 1e3:.2f} ms"
    problems = []
    if peak > rating:
        problems.append(
            f"{where}: peak phase current {peak:.1f} A over"
            f" protection.short_circuit_current_max {rating:g} A"
        )
    if peak > bound:
        problems.append(f"{where}: peak phase current {peak:.1f} A over its bound {bound:.1f} A")
    return peak, problems


def _over_voltage(loop: BrakingLoop) -> Outcome:
    _settle(loop)
    loop.advance_to(loop.run.next_update())
    high = 1.1 * float(loop.spec.inverter.bus_voltage_max_v)
    cause = loop.machine.now
    loop.plant.bus_voltage_v = high
    loop.run.board.set_bus_voltage(high)
    _until_tripped(loop, 2 * loop.run.board.pwm_period_ticks())
    return loop.run.outcome(
        "over-voltage step (motor in the loop)",
        "OVER_VOLTAGE",
        cause,
        loop.run.board.pwm_period_ticks(),
        "the bus steps 10 % above inverter.bus_voltage_max at a PWM period start",
    )


def _break_input(loop: BrakingLoop) -> Outcome:
    _settle(loop)
    loop.advance_to(loop.machine.now + _third_of_sector(loop))
    cause = loop.machine.now
    loop.comparator.force(True)  # fires whatever the currents: the pin goes active now
    _until_tripped(loop, loop.run.board.pwm_period_ticks())
    return loop.run.outcome(
        "BKIN over-current (motor in the loop)",
        "OVER_CURRENT",
        cause,
        loop.run.board.pwm_period_ticks(),
        "the comparator on BKIN goes active mid-sector; MOE clears in hardware",
    )


def _hall_unplugged(loop: BrakingLoop) -> Outcome:
    _settle(loop)
    loop.advance_to(loop.machine.now + _third_of_sector(loop))
    cause = loop.machine.now
    loop.hall_override = 7
    loop.run.board.set_hall(7)
    _until_tripped(loop, 2 * loop.run.board.pwm_period_ticks())
    return loop.run.outcome(
        "Hall unplugged, code 7 (motor in the loop)",
        "HALL_INVALID",
        cause,
        loop.run.board.pwm_period_ticks(),
        "two Hall lines pulled up together while the rotor turns (the Hall lines' EXTI)",
    )


def _bus_stuck_at_zero(loop: BrakingLoop) -> Outcome:
    _settle(loop)
    loop.advance_to(loop.machine.now + _third_of_sector(loop))
    cause = loop.machine.now
    loop.run.board.set_bus_voltage(0.0)
    _until_tripped(loop, 2 * loop.run.board.pwm_period_ticks())
    return loop.run.outcome(
        "bus ADC stuck at 0 (motor in the loop)",
        "UNDER_VOLTAGE",
        cause,
        loop.run.board.pwm_period_ticks(),
        "the divider's ADC input reads 0 V from mid-sector on; the bridge still sees the bus",
    )


def _rotor_stops(loop: BrakingLoop) -> Outcome:
    """As the scenario without the motor (`scenarios._rotor_stops`): the time-out within
    `scenarios.timeout_window` of the last edge where a turning rotor is bound to make
    its next edge, else the counter's range, whose wait is emulated in full up to
    QUIET_WAIT_TICKS (`shorten_quiet_wait`; at the slowest Hall clock the counter's
    range is 60 s of motor time, hours of emulation with the plant, and the report never
    finished). The rotor is blocked within a PWM period of a Hall edge, while that
    edge's commutation runs: the chip runs on for the last Hall interval, past the
    commutation end it scheduled (within its sector), first."""
    _settle(loop)
    last_edge, previous = loop.edges[-1][0], loop.edges[-2][0]
    loop.plant.speed_rpm = 0.0  # blocked
    loop.advance_to(max(loop.machine.now, 2 * last_edge - previous))
    period = loop.run.board.pwm_period_ticks()
    window = timeout_window(loop.run, last_edge, last_edge - previous)
    if window is not None:
        _until_tripped(loop, window.cause + window.limit - loop.machine.now + period)
        return loop.run.outcome(
            "rotor stops (motor in the loop)",
            "HALL_TIMEOUT",
            window.cause,
            window.limit,
            f"the rotor is blocked after a Hall edge; {window.note}",
        )
    band = timeout_window(loop.run, last_edge, last_edge - previous, guard=0.0)
    if band is not None:  # near the bound's end either time-out is right (_rotor_stops)
        _until_tripped(loop, band.cause + band.limit - loop.machine.now + period)
        if not loop.machine.tim1.moe:
            return loop.run.outcome(
                "rotor stops (motor in the loop)",
                "HALL_TIMEOUT",
                band.cause,
                band.limit,
                "the rotor is blocked after a Hall edge, near the slowest speed whose next"
                f" edge is bound (either time-out is right); {band.note}",
            )
    wrap, shortened = shorten_quiet_wait(loop.machine, counter_range_end(loop.machine, last_edge))
    _until_tripped(loop, wrap - loop.machine.now + 2 * period)
    return loop.run.outcome(
        "rotor stops (motor in the loop)",
        "HALL_TIMEOUT",
        wrap,
        period,
        "the rotor is blocked after a Hall edge; latency from TIM3's counter range" + shortened,
    )


PLANT_FAULTS = (
    PlantFault("over_voltage", _over_voltage),
    PlantFault("break_input", _break_input),
    PlantFault("hall_unplugged", _hall_unplugged),
    PlantFault("bus_stuck_at_zero", _bus_stuck_at_zero),
    PlantFault("rotor_stops", _rotor_stops),
)


def run_plant_fault(elf: Path, port_source: Path, spec: Spec, fault: PlantFault) -> Outcome:
    """One fault with the motor in the loop, braking from the braking scenario's start."""
    loop = BrakingLoop(elf, port_source, spec, braking_setup(spec, short=True))
    try:
        outcome = fault.run(loop)
        peak, problems = follow_short_circuit(loop)
    except (PilError, WatchdogResetError) as error:
        loop.run.violations.append(f"{type(error).__name__}: {error}")
        return loop.run.outcome(fault.key, "never", None, None, "aborted")
    if peak is None:
        return outcome
    note = f"{outcome.note}; shorted after the trip, peak phase current {peak:.1f} A"
    faults = outcome.faults
    over = FAULT["OVER_CURRENT"]
    tripped = loop.machine.tim1.moe_cleared_at
    crossed = [cross for cross, _, _ in loop.comparator.trips]
    if (
        outcome.expected != "OVER_CURRENT"
        and faults & over
        and tripped is not None
        and crossed
        and min(crossed) > tripped
    ):
        # The short's own current over the comparator's level, after the trip: latched
        # as the break interrupt now latches every over-current while another fault is
        # (a helper's hunt: it had stayed off, and one was lost), a consequence of the
        # safe state, not of the cause.
        faults &= ~over
        note += (
            f"; OVER_CURRENT latched as well, the short circuit's current over the"
            f" comparator's {loop.comparator.trip_a:g} A after the trip (its consequence)"
        )
    return replace(
        outcome,
        faults=faults,
        violations=(*outcome.violations, *problems),
        note=note,
    )

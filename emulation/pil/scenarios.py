"""Fault scenarios on the emulated drive: each boots the firmware, brakes with the Hall
code stepping at a constant speed, applies one cause at a known tick and measures the
fault latency (the cause to TIM1's MOE cleared), with the bridge's invariants checked
over the whole run:

* no shoot-through and no dead time shorter than the spec's (`tim1.gate_violations`
  on every gate edge);
* every compare value in force within the PWM period, checked at every step of the
  machine: CCRx <= ARR + 1 edge-aligned (ARR + 1: active all period, RM0008 14.3.10),
  CCRx <= ARR centre-aligned;
* the compare values in force change only at an update event (CCRx preloaded, OCxPE,
  RM0008 14.3.9: a duty written mid-period waits for the next period);
* the timing handler (TIM1_TRG_COM) never runs above the Hall edge (TIM3), the Hall
  lines' EXTI (EXTI0, EXTI9_5) or the current loop (ADC1_2): it is never active while a
  later-entered one of those is below it (the port's priority plan: those preempt the
  timing); and none of the Hall edge, the Hall lines' EXTI, the current loop and the
  break interrupt preempts another of them (they share one level, so none interrupts
  another half way through a TIM1 update);
* with a bus or current fault latched and its cause still there, nothing trips again:
  the timing handler stays idle for ten PWM periods;
* every Hall edge of the turning rotor commutates: the enables in force (TIM1 CCER)
  change within the sector that follows it, while the bridge is armed;
* the timers as the spec sets them, read from the booted machine: TIM1 counting at
  inverter.timer_clock, P counts a PWM period (the oracle's `units`: duty 1) in the
  spec's alignment, so one PWM period at inverter.pwm_frequency; TIM3 ticking at
  hall.timer_clock over hall.counter_bits; each current channel sampled for
  sensing.adc_sample_time ADC cycles (`configuration_problems`);
* every current sample the current loop closes on is taken in a clean window: no gate
  edge inside its sampling window (the ADC's SMPRx, plus the datasheet's injection
  latency) and none less than sensing.settling_time before it (`sample_window`);
* no hard fault (the machine raises `PilError`) and no watchdog reset (`Iwdg` raises
  `WatchdogResetError`), the longest gap between refreshes (from the run's start, or
  the last refresh before it, to now) reported against the watchdog's time-out at the
  fastest LSI (60 kHz, where it is shortest);
* a fault's safe state is the spec's at the run's speed and bus: the short circuit
  where the peak line EMF (sim's waveform of the spec's EMF) reaches the bus, all-off
  where it does not and protection.safe_state prefers it (the break input after the
  dead time, the under-voltage near the top speed one PWM period on), and either side
  of the speed where all-off starts to rectify (the break input 3 % below and 3 %
  above it, at a bus voltage of the spec's range that puts it in the speed range): the
  port's rule for that speed, found from the bus code and the Hall interval, is
  checked against the physics where it changes; where the spec prefers the short
  circuit, the short within protection.short_circuit_current_max and all-off above it
  (the bound of `safe_state.short_circuit_bound_a`), and the break 3 % either side of
  the speed where that bound meets the rating; where the port cannot know the speed
  (no Hall interval yet after start-up: an under-voltage before the first edge, the
  break in the first sector) or the bus (its ADC stuck at 0 with the bus in fact at
  nominal), a state safe at the rotor's speed and the real bus, whatever the spec
  prefers.

The inputs are set by the scenario (Hall code, comparator, bus and current through the
spec's sensing chain, `runner.DriveBoard`), not yet by a motor model: the current read
is a constant half the nominal braking current, so the loop keeps the bridge switching.
The yardsticks are the spec's (PWM period, dead time, the fault API's codes), never the
firmware's constants.
"""

from __future__ import annotations

import math
import random
import time
from collections.abc import Callable
from dataclasses import dataclass, replace
from fractions import Fraction
from itertools import pairwise
from pathlib import Path

from unicorn import UC_HOOK_CODE, UC_HOOK_MEM_WRITE

from codegen.port_faults import FAULTS
from codegen.spec_model import Spec
from emulation.pil.bus import PilError, svd_interrupt
from emulation.pil.hall_timeout import (
    BOUNDARY_GUARD,
    TIMEOUT_INTERVALS,
    deceleration,
    hardest_braking,
    latest_next_edge_s,
    speed_into,
    timeout_bound_s,
)
from emulation.pil.iwdg import WatchdogResetError
from emulation.pil.machine import Machine, MachineOptions
from emulation.pil.rcc import TICK_HZ
from emulation.pil.runner import DriveBoard
from emulation.pil.safe_state import (
    ALL_OFF,
    SHORT_CIRCUIT,
    corner,
    peak_line_emf_v,
    required_idle_state,
    required_safe_state,
    said_line_emf_v,
    short_circuit_bound_a,
    short_rated_speed,
    worst_line_emf_v,
)
from emulation.pil.sample_window import LoopSampleWatch, sample_window_lines
from emulation.pil.scs import IRQ_BASE
from emulation.pil.tim1 import gate_violations
from oracle.units import units

FAULT = {f.name: f.value for f in FAULTS}
#: The fastest LSI of the datasheet's range: the watchdog's time-out is shortest there
LSI_FASTEST_HZ = 60_000
#: Sectors turned before the cause: the loop and the commutations are running
SETTLE_SECTORS = 8
#: PWM periods after start-up before the first Hall edge of the start-up scenarios:
#: the bus sampled and the bridge armed
START_WAIT_PERIODS = 20
#: PWM periods main's loop gets to publish a latched fault in app_faults
MAIN_WAIT_PERIODS = 10
#: PWM periods a scenario waits for an instant it places its cause at (the CPU asleep,
#: an injected sequence's end), each due within a period or two
WAIT_PERIODS = 10


def sector_ticks_at(spec: Spec, rpm: float) -> float:
    """A 60 electrical degree sector at `rpm`, in ticks of 72 MHz."""
    return TICK_HZ * 60 / (rpm * spec.motor.pole_pairs * 6)


@dataclass(frozen=True)
class Outcome:
    """What one scenario measured on one spec."""

    name: str
    expected: str | None  # the fault the cause must latch alone; None: no fault at all
    faults: int  # app_faults at the end
    latency_ticks: int | None  # cause to MOE cleared; None where MOE stayed set
    limit_ticks: int | None  # the latency allowed; None: MOE must stay set (or never set)
    violations: tuple[str, ...]
    refresh_gap_ticks: int  # longest gap between watchdog refreshes
    watchdog_ticks: int  # the watchdog's time-out at the fastest LSI
    cpu_load: float  # handler time / emulated time, over the whole run after boot
    emulated_s: float
    wall_s: float
    note: str
    published_ticks: int | None = None  # MOE cleared to app_faults set by main
    #: the current samples the loop closed on whose sampling window was checked
    samples_checked: int = 0
    #: MOE cleared this long before the cause (the latency is None then): a trip too
    #: early, which had been reported as "MOE was never cleared"
    early_ticks: int | None = None

    @property
    def fault_names(self) -> list[str]:
        return [name for name, value in FAULT.items() if self.faults & value]

    @property
    def problems(self) -> list[str]:
        """Every way this outcome breaks its scenario's requirement (empty: it passes)."""
        out = list(self.violations)
        # "A+B": every one of those faults latched, and no other
        wanted = (
            sum(FAULT.get(name, -1 << 32) for name in self.expected.split("+"))
            if self.expected
            else 0
        )
        if self.faults != wanted:
            out.append(f"faults {self.fault_names or ['none']}, expected {self.expected or 'none'}")
        if self.limit_ticks is not None:
            if self.latency_ticks is None and self.early_ticks is not None:
                out.append(f"MOE cleared {self.early_ticks} ticks before the cause")
            elif self.latency_ticks is None:
                out.append("MOE was never cleared")
            elif not 0 <= self.latency_ticks <= self.limit_ticks:
                out.append(f"latency {self.latency_ticks} ticks > {self.limit_ticks}")
        elif self.latency_ticks is not None and self.expected is None:
            out.append("MOE cleared with no fault expected")
        if self.refresh_gap_ticks >= self.watchdog_ticks:
            out.append("the watchdog starved")
        return out


def configuration_problems(machine: Machine, spec: Spec) -> list[str]:
    """The booted machine's timers against the spec (the yardsticks: the spec and the
    oracle's own unit conversions, never the port's constants): TIM1 counts at
    inverter.timer_clock, P of its counts make duty 1 (ARR = P centre-aligned, P - 1
    edge-aligned) in the spec's alignment, and so one PWM period lasts 1 / pwm_frequency;
    TIM3 ticks at hall.timer_clock and counts over hall.counter_bits; ADC1 and ADC2
    sample each current channel for sensing.adc_sample_time. A prescaler off by
    one (a 1.4 % slow Hall clock: every speed and commutation time off by as much, the
    over-speed threshold too) kept every other invariant."""
    u = units(spec)
    tim1, tim3 = machine.tim1, machine.tim3
    out = []
    timer_ticks = Fraction(TICK_HZ) / spec.inverter.timer_clock_hz
    if tim1.ticks_per_count() != timer_ticks:
        out.append(
            f"TIM1 counts every {tim1.ticks_per_count()} ticks of 72 MHz (PSC = {tim1.psc}):"
            f" inverter.timer_clock {float(spec.inverter.timer_clock_hz):g} Hz is every"
            f" {float(timer_ticks):g}"
        )
    centre = spec.inverter.pwm_alignment == "center"
    if bool(tim1.centre_aligned) != centre:
        out.append(
            f"TIM1 counts {'up and down' if tim1.centre_aligned else 'up'} (CR1.CMS ="
            f" {tim1.centre_aligned}): inverter.pwm_alignment is {spec.inverter.pwm_alignment!r}"
        )
    full = tim1.arr if centre else tim1.arr + 1
    if full != u.pwm_counts:
        out.append(
            f"TIM1 ARR = {tim1.arr}: duty 1 is {full} counts, the spec's PWM period"
            f" {u.pwm_counts} (inverter.pwm_frequency {float(spec.inverter.pwm_frequency_hz):g} Hz)"
        )
    period = tim1.cycle_counts() * tim1.ticks_per_count()
    if period != Fraction(TICK_HZ) / spec.inverter.pwm_frequency_hz:
        out.append(
            f"one PWM period lasts {period} ticks of 72 MHz: inverter.pwm_frequency"
            f" {float(spec.inverter.pwm_frequency_hz):g} Hz is"
            f" {float(Fraction(TICK_HZ) / spec.inverter.pwm_frequency_hz):g}"
        )
    hall_ticks = Fraction(TICK_HZ) / u.hall_hz
    if tim3.ticks_per_count() != hall_ticks:
        out.append(
            f"TIM3 ticks every {tim3.ticks_per_count()} ticks of 72 MHz (PSC = {tim3.psc}):"
            f" hall.timer_clock {float(u.hall_hz):g} Hz is every {float(hall_ticks):g}"
        )
    out += _sample_time_problems(machine, spec)
    if tim3.arr != u.hall_counter_max:
        out.append(
            f"TIM3 ARR = {tim3.arr}: hall.counter_bits {spec.hall.counter_bits} count to"
            f" {u.hall_counter_max}"
        )
    return out


def _sample_time_problems(machine: Machine, spec: Spec) -> list[str]:
    """Each current channel sampled for sensing.adc_sample_time ADC cycles (SMPRx) on
    ADC1, which the loop reads, and ADC2: a longer sample runs into the next switching
    edge (the sample-window invariant sees that), a shorter one leaves the amplifier's
    settling of the sample capacitor to chance and no other invariant sees it."""
    out = []
    wanted = spec.sensing.adc_sample_cycles
    for adc in (machine.adc1, machine.adc2):
        for channel in spec.sensing.current_channels:
            cycles = adc.sample_ticks(channel) * machine.rcc.adc_hz / TICK_HZ
            if cycles != wanted:
                out.append(
                    f"{adc.svd_name} samples channel {channel} for {float(cycles):g} ADC cycles"
                    f" (SMPRx): sensing.adc_sample_time is {float(wanted):g}"
                )
    return out


class Run:
    """A booted board braking at `rpm`, with the invariants watched at every step."""

    def __init__(self, elf: Path, spec: Spec, *, hse_fails: bool = False) -> None:
        self.spec = spec
        self.board = DriveBoard(
            elf,
            spec,
            MachineOptions(
                vref=float(spec.adc.reference_v), lsi_hz=LSI_FASTEST_HZ, hse_fails=hse_fails
            ),
        )
        self.machine = self.board.machine
        self.violations: list[str] = []
        # what _check_nesting reads, set before it listens (the boot may nest handlers)
        self._timing = IRQ_BASE + svd_interrupt("TIM1", "TIM1_TRG_COM_TIM11")
        self._urgent = {
            IRQ_BASE + svd_interrupt("TIM3", "TIM3"),
            IRQ_BASE + svd_interrupt("ADC1", "ADC"),
            IRQ_BASE + svd_interrupt("EXTI", "EXTI0"),
            IRQ_BASE + svd_interrupt("EXTI", "EXTI9_5"),
        }
        # the one level none of which may interrupt another half way through a TIM1 update
        # (README, Braking current and fault API: the priority plan)
        self._one_level = self._urgent | {IRQ_BASE + svd_interrupt("TIM1", "TIM1_BRK_TIM9")}
        self.machine.listeners.append(self._check_duties)
        self.machine.listeners.append(self._check_preload)
        self.machine.listeners.append(self._check_nesting)
        self._compares: tuple[int, ...] = ()
        self._updates = -1
        for channel in (1, 2, 3):
            self._watch_compare_writes(channel)
        self._watch_publication()
        self.wall = time.perf_counter()
        self.board.boot()
        if not hse_fails:  # on the HSI every rate is the crystal's / 9: the bridge never arms
            self.violations += configuration_problems(self.machine, spec)
        self.start = self.machine.now
        self.handler_start = self.machine.handler_ticks
        self.board.set_current(float(spec.controller.braking_current_nominal_a) / 2)
        self.machine.tim1.record_gates()
        self.samples = LoopSampleWatch(self.machine, spec)
        self.sector = 0
        self.rpm = default_rpm(spec)
        self.published_after: int | None = None
        self._armed_edges = 0  # the first edge after boot only arms the measurement
        self._due: int | None = None  # where the sector entered last ends at `rpm`

    def _watch_publication(self) -> None:
        """The timing handler fills the slot the Hall edge is not reading, then publishes
        it (`port.timing`, the state's first word): it must never write the slot
        published at that moment, which a Hall edge preempting it may be applying (a
        torn timing: some fields new, some old). Watched on every write the timing
        handler makes to the two slots (`port_slots`, PORT_SLOT_BYTES each)."""
        machine = self.machine
        if "port_slots" not in machine.image.symbols:
            raise PilError(f"{machine.image.path}: no symbol 'port_slots' (the timing slots)")
        slots, state = machine.symbol("port_slots"), machine.symbol("port")

        def written(_uc: object, _access: int, address: int, size: int, *_: object) -> None:
            active = machine.nvic.active
            if not active or active[-1] != self._timing:
                return
            published = machine.read_u32(state)
            if published not in (slots, slots + PORT_SLOT_BYTES):
                raise PilError(
                    f"port.timing = 0x{published:08x} is neither timing slot (0x{slots:08x},"
                    f" {PORT_SLOT_BYTES} bytes each): the port's layout is not the one watched"
                )
            if published <= address < published + PORT_SLOT_BYTES and len(self.violations) < 20:
                self.violations.append(
                    f"tick {machine.now}: the timing handler wrote {size} bytes at"
                    f" 0x{address:08x}, in the slot published then (0x{published:08x}): a Hall"
                    " edge preempting it would apply a torn timing"
                )

        machine.uc.hook_add(
            UC_HOOK_MEM_WRITE, written, None, slots, slots + 2 * PORT_SLOT_BYTES - 1
        )

    def _check_duties(self, machine: object) -> None:
        tim1 = self.machine.tim1
        top = tim1.arr if tim1.centre_aligned else tim1.arr + 1
        for channel in (1, 2, 3):
            if tim1.ccr[channel] > top and len(self.violations) < 10:
                self.violations.append(
                    f"CCR{channel} = {tim1.ccr[channel]} > {top} (ARR = {tim1.arr}) at tick"
                    f" {self.machine.now}"
                )

    def _note(self, text: str) -> None:
        if len(self.violations) < 20:
            self.violations.append(text)

    def _watch_compare_writes(self, channel: int) -> None:
        """A CCRx write must not change the compare value in force (OCxPE: it waits for
        the update event); the commutation's EGR.UG that follows is that event."""
        tim1 = self.machine.tim1
        write = tim1.writers[f"CCR{channel}"]

        def checked(value: int) -> None:
            before = tim1.ccr[channel]
            write(value)
            if tim1.ccr[channel] != before and tim1.moe:
                self._note(
                    f"CCR{channel} write took effect at once ({before} -> {tim1.ccr[channel]})"
                    f" at {self.machine.now}: no preload"
                )

        tim1.writers[f"CCR{channel}"] = checked

    def _check_preload(self, _machine: object) -> None:
        tim1 = self.machine.tim1
        compares = tuple(tim1.ccr[1:4])
        if compares != self._compares and tim1.update_count == self._updates:
            self._note(
                f"CCR {self._compares} -> {compares} with no update event at {self.machine.now}"
            )
        self._compares, self._updates = compares, tim1.update_count

    def _check_nesting(self, _machine: object) -> None:
        active = self.machine.nvic.active
        if len(active) < 2:
            return
        for below, above in pairwise(active):
            if above == self._timing and below in self._urgent:
                self._note(f"the timing handler preempted exception {below} at {self.machine.now}")
            elif above in self._one_level and below in self._one_level:
                self._note(
                    f"exception {above} preempted exception {below} at {self.machine.now}: the"
                    " Hall edge, the Hall lines, the current loop and the break share one level"
                )

    def turn_until(self, reached: Callable[[], bool], sectors: int) -> bool:
        """Turn up to `sectors` sectors, stopping at the first 0.5 us step where
        `reached()` holds; whether it did."""
        for _ in range(sectors):
            self._finish_sector()
            self.sector = (self.sector + 1) % 6
            self.board.set_hall(self.spec.hall.sequence[self.sector])
            end = self.machine.now + self.sector_ticks()
            self._due = end
            while self.machine.now < end:
                if reached():
                    return True
                self.machine.run_for(TICK_HZ // 2_000_000)
        return False

    def wait_for(self, reached: Callable[[], bool], step: int, what: str) -> None:
        """Run in steps of `step` ticks until `reached()` holds; where it does not within
        WAIT_PERIODS PWM periods, the scenario ends there (PilError, `what` its reason)
        instead of running on for ever."""
        end = self.machine.now + WAIT_PERIODS * self.board.pwm_period_ticks()
        while not reached():
            if self.machine.now >= end:
                raise PilError(f"{what} within {WAIT_PERIODS} PWM periods")
            self.machine.run_for(step)

    def turn(self, sectors: int) -> None:
        """`sectors` Hall steps at `rpm`; each must change the enables in force."""
        for _ in range(sectors):
            self.step(self.sector_ticks())

    def step(self, ticks: int, *, sector: int | None = None) -> None:
        """One Hall step (once the sector entered last has ended), then `ticks` in the
        new sector, which lasts `sector` ticks (default: `ticks`); the edge must change
        the enables in force."""
        self._finish_sector()
        before = self.machine.tim1.ccer
        self.sector = (self.sector + 1) % 6
        self.board.set_hall(self.spec.hall.sequence[self.sector])
        self._due = self.machine.now + (ticks if sector is None else sector)
        self.machine.run_for(ticks)
        if self.machine.tim1.moe and self.machine.tim1.ccer == before and self._armed_edges:
            self._note(
                f"a Hall edge to code {self.spec.hall.sequence[self.sector]} did not commutate"
            )
        self._armed_edges += 1

    def edge_now(self) -> tuple[int, int]:
        """The sector entered last held to its end, then the next sector's Hall edge now
        (the caller schedules what follows it): (the code left, the code entered)."""
        self._finish_sector()
        sequence = self.spec.hall.sequence
        before = sequence[self.sector]
        self.sector = (self.sector + 1) % 6
        self.board.set_hall(sequence[self.sector])
        return before, sequence[self.sector]

    def _finish_sector(self) -> None:
        """Hold the Hall code to the end of the sector entered last: a cause placed
        inside it (`into_sector`) leaves the rest for the next step."""
        if self._due is not None and self.machine.now < self._due:
            self.machine.run_for(self._due - self.machine.now)

    def into_sector(self, fraction: float) -> None:
        """One Hall step at `rpm`, then `fraction` of the sector: a cause placed there
        comes inside a sector of the rotor's speed, and a later step waits for its end.
        Running on for the fraction after a whole sector held that code for 1 +
        `fraction` sectors instead: beyond TIM3's range where a sector nears it (a 72 MHz
        Hall clock near controller.speed_min), so the Hall timed out before the cause."""
        sector = self.sector_ticks()
        self.step(round(sector * fraction), sector=sector)

    def sector_ticks(self) -> int:
        return round(sector_ticks_at(self.spec, self.rpm))

    def next_update(self) -> int:
        tim1 = self.machine.tim1
        counts = tim1.cycle_counts() - tim1.position(self.machine.now) % tim1.cycle_counts()
        return self.machine.now + counts * tim1.ticks_per_count()

    def main_wait_ticks(self) -> int:
        """One PWM period at the clock the chip runs on now, the step of the wait for
        main to publish a fault: after the clock security system's switch to the 8 MHz
        HSI the timers and main run nine times slower, and ten design periods (120 us at
        100 kHz) had ended the wait before main's next wake (a helper's hunt: CLOCK
        published 286 us after the trip)."""
        hclk = self.machine.rcc.hclk_hz
        return -(-self.board.pwm_period_ticks() * TICK_HZ // hclk)

    def run_until_tripped(self, limit: int, advance: Callable[[int], None] | None = None) -> None:
        """Run until MOE clears or `limit` ticks pass, then two PWM periods more: main
        refreshes app_faults after an interrupt, and one that came while main was past
        that line but before its WFI waits for the next period's. `advance(ticks)` runs
        the chip on (default: alone; the plant faults pass one that moves the motor
        too)."""
        step = advance or self.machine.run_for
        end = self.machine.now + limit
        while self.machine.tim1.moe and self.machine.now < end:
            step(TICK_HZ // 1_000_000)
        step(2 * self.board.pwm_period_ticks())
        # main's loop publishes app_faults; it runs below every handler, so give it up
        # to MAIN_WAIT_PERIODS periods (the time it took is reported)
        tripped = self.machine.tim1.moe_cleared_at
        for _ in range(MAIN_WAIT_PERIODS):
            if self.board.symbol("app_faults") or tripped is None:
                break
            step(self.main_wait_ticks())
        published = tripped is not None and self.board.symbol("app_faults") != 0
        self.published_after = self.machine.now - tripped if published else None

    def outcome(
        self, name: str, expected: str | None, cause: int | None, limit: int | None, note: str
    ) -> Outcome:
        machine = self.machine
        dead = round(self.spec.inverter.dead_time_s * TICK_HZ)
        log = machine.tim1.gate_log or []
        violations = self.violations + [str(v) for v in gate_violations(log, dead)[:10]]
        violations += sample_window_lines(self.samples.violations(log))
        cleared = machine.tim1.moe_cleared_at
        latency = early = None
        if cleared is not None and cause is not None and cleared >= cause:
            latency = cleared - cause
        elif cleared is not None and cause is not None:
            early = cause - cleared
        # from the last refresh before the run (or the run's start) to now: a firmware that
        # stops refreshing shows a gap up to now, not none
        before = [t for t in machine.iwdg.refresh_log if t < self.start]
        refreshes = (
            [before[-1] if before else self.start]
            + [t for t in machine.iwdg.refresh_log if t >= self.start]
            + [machine.now]
        )
        gap = max((b - a for a, b in pairwise(refreshes)), default=0)
        return Outcome(
            name=name,
            expected=expected,
            faults=self.board.symbol("app_faults"),
            latency_ticks=latency,
            limit_ticks=limit,
            violations=tuple(violations),
            refresh_gap_ticks=gap,
            watchdog_ticks=machine.iwdg.timeout_ticks(),
            cpu_load=(machine.handler_ticks - self.handler_start)
            / max(1, machine.now - self.start),
            emulated_s=(machine.now - self.start) / TICK_HZ,
            wall_s=time.perf_counter() - self.wall,
            note=note,
            published_ticks=self.published_after,
            samples_checked=len(self.samples.used),
            early_ticks=early,
        )


def _check_safe_state(
    run: Run,
    at: int,
    bus_v: float,
    what: str,
    *,
    inputs_known: bool = True,
    complete_by: int | None = None,
    idle: bool = False,
) -> None:
    """The gates at `at` are a safe state, the one the spec requires at the run's speed
    (`inputs_known` False: the port has no Hall interval yet, or reads no bus voltage;
    one safe at that speed and bus). With `complete_by`, at `at` (the break's dead time,
    in hardware) no switch is on that the safe state has off, and at `complete_by` the
    safe state is whole: the idle levels reach only the channels the sector left
    enabled, and the port's trip handler enables the others (a floating phase's pair
    stays off until then)."""
    required = (
        required_idle_state(run.spec, run.rpm, bus_v)
        if idle
        else required_safe_state(run.spec, run.rpm, bus_v, inputs_known=inputs_known)
    )
    if complete_by is not None:
        allowed = required if required is not None else SHORT_CIRCUIT  # ALL_OFF within it
        on = _gates_in_force(run, at)
        if any(g and not a for g, a in zip(on, allowed, strict=True)):
            run.violations.append(f"gates {on} {what}: a switch on that the safe state has off")
        at = complete_by
        what = f"{what}, whole by one PWM period on"
    gates = _gates_in_force(run, at)
    if gates not in (ALL_OFF, SHORT_CIRCUIT):
        run.violations.append(f"gates {gates} {what}: no safe state")
    elif required is not None and gates != required:
        name = "the short circuit" if required == SHORT_CIRCUIT else "all off"
        run.violations.append(
            f"gates {gates} {what}: not {name}, the {'idle' if idle else 'spec' + chr(39) + 's safe'}"
            f" state at {run.rpm:.0f} rpm and"
            f" {bus_v:g} V (peak line EMF {peak_line_emf_v(run.spec, run.rpm):.1f} V, the short"
            f" circuit's bound {short_circuit_bound_a(run.spec, run.rpm):.1f} A against"
            f" protection.short_circuit_current_max"
            f" {float(run.spec.protection.short_circuit_current_max_a):g} A)"
        )


def _gates_in_force(run: Run, at: int) -> tuple[bool, ...]:
    """The six gates in force at tick `at` (the run is taken there first if it is not
    yet): from TIM1's gate record, not from its registers now, which may hold a state
    set after `at` (an under-voltage's short, set 57 us after the cause, had been read
    as in force at 50 us). A pin TIM1 does not drive is off, as the plant takes it (the
    gate driver's pull-down)."""
    if run.machine.now < at:
        run.machine.run_until(at)
    log = run.machine.tim1.gate_log
    if log is not None and log and at < log[0][0]:
        # before the scenario began recording: the bridge was off from before its cause
        # (a fault latched at boot: a hunt's bus_voltage_max at the ADC's full scale,
        # whose report had ended in a traceback); judged by the record's first state
        run.violations.append(
            f"MOE cleared at tick {at}, before the scenario's record began at {log[0][0]}:"
            f" the drive was faulted before the cause (app_faults {run.board.symbol('app_faults'):#x})"
        )
        at = log[0][0]
    return tuple(g is True for g in run.machine.tim1.gates_at(at))


def default_rpm(spec: Spec) -> float:
    """Braking half-way between the controller's lowest and highest speed."""
    return float(spec.controller.speed_min_rpm + spec.controller.speed_max_rpm) / 2


def _over_voltage(run: Run) -> Outcome:
    run.turn(SETTLE_SECTORS - 1)
    run.into_sector(1 / 3)
    step = run.next_update()
    nominal = float(run.spec.inverter.bus_voltage_nominal_v)
    high = 1.1 * float(run.spec.inverter.bus_voltage_max_v)
    run.board.set_bus_voltage(lambda tick: high if tick >= step else nominal)
    run.run_until_tripped(2 * run.board.pwm_period_ticks())
    return run.outcome(
        "over-voltage step",
        "OVER_VOLTAGE",
        step,
        run.board.pwm_period_ticks(),
        "bus 10 % above inverter.bus_voltage_max at a PWM period start (the injected trigger)",
    )


def _bus_step_after_a_sample(run: Run, volts: float) -> int:
    """The bus steps to `volts` just after an injected sequence: the instant a bus the
    sampled path alone would see waits longest (a whole PWM period) for the next
    sample, so only the analog watchdog on every conversion meets the limit. The cause."""
    run.turn(SETTLE_SECTORS - 1)
    run.into_sector(1 / 3)
    _after_a_sample(run)
    cause = run.machine.now
    run.board.set_bus_voltage(volts)
    run.run_until_tripped(2 * run.board.pwm_period_ticks())
    return cause


def _over_voltage_between_samples(run: Run) -> Outcome:
    high = 1.1 * float(run.spec.inverter.bus_voltage_max_v)
    cause = _bus_step_after_a_sample(run, high)
    return run.outcome(
        "over-voltage between samples",
        "OVER_VOLTAGE",
        cause,
        run.board.pwm_period_ticks(),
        "bus 10 % above inverter.bus_voltage_max from just after an injected sample (the"
        " sampled path's worst instant): the analog watchdog's next bus conversion",
    )


def _under_voltage_at(run: Run, *, at_start: bool) -> Outcome:
    """The bus 10 % below inverter.bus_voltage_min, the rotor at 98 % of
    controller.speed_max, where all-off rectifies into a bus this low: from just after
    an injected sample while braking (the spec's safe state one PWM period on), or
    right after start-up, before the first Hall edge (`at_start`: the speed unknown to
    the port, so one safe at the rotor's speed, whatever the spec prefers)."""
    low = 0.9 * float(run.spec.inverter.bus_voltage_min_v)
    run.rpm = 0.98 * float(run.spec.controller.speed_max_rpm)
    period = run.board.pwm_period_ticks()
    if at_start:
        cause = run.machine.now
        run.board.set_bus_voltage(low)
        run.run_until_tripped(2 * period)
    else:
        cause = _bus_step_after_a_sample(run, low)
    _check_safe_state(run, cause + period, low, "one PWM period on", inputs_known=not at_start)
    if at_start:
        name = "under-voltage before the first Hall edge"
        note = (
            "bus 10 % below inverter.bus_voltage_min right after start-up, no Hall edge"
            " yet, the rotor at 98 % of controller.speed_max: the speed unknown to the port"
        )
    else:
        name = "under-voltage near the top speed"
        note = (
            "bus 10 % below inverter.bus_voltage_min from just after an injected sample, at"
            " 98 % of controller.speed_max; the safe state one period on is the spec's at"
            " that bus"
        )
    return run.outcome(name, "UNDER_VOLTAGE", cause, period, note)


def _under_voltage(run: Run) -> Outcome:
    return _under_voltage_at(run, at_start=False)


def _under_voltage_at_start(run: Run) -> Outcome:
    return _under_voltage_at(run, at_start=True)


def _break_after_the_first_edge(run: Run) -> Outcome:
    """The break input half-way into the first sector after start-up, above the speed
    from which all-off rectifies (3 % above it, at the bus of `rectifying_boundary`;
    else 98 % of controller.speed_max at the nominal bus): the first edge after arming
    reads TIM3's preset wrap, so the port has no interval yet and the safe state after
    the dead time must be safe at the rotor's speed whatever the spec prefers."""
    boundary = rectifying_boundary(run.spec)
    if boundary is None:
        bus_v = float(run.spec.inverter.bus_voltage_nominal_v)
        run.rpm = 0.98 * float(run.spec.controller.speed_max_rpm)
    else:
        bus_v, rpm = boundary
        run.rpm = rpm * (1 + RECTIFYING_MARGIN)
    run.board.set_bus_voltage(bus_v)
    run.machine.run_for(START_WAIT_PERIODS * run.board.pwm_period_ticks())
    run.into_sector(1 / 2)
    cause = run.machine.now
    run.board.set_break(True)
    run.run_until_tripped(run.board.pwm_period_ticks())
    tim1 = run.machine.tim1
    _check_safe_state(
        run,
        cause + tim1.dead_time_ticks(),
        bus_v,
        "after the dead time",
        inputs_known=False,
        complete_by=cause + run.board.pwm_period_ticks(),
    )
    return run.outcome(
        "BKIN in the first sector after start-up",
        "OVER_CURRENT",
        cause,
        run.board.pwm_period_ticks(),
        f"bus {bus_v:.2f} V, the rotor at {run.rpm:.0f} rpm: the break half-way into the"
        " first sector, the port with no Hall interval yet",
    )


def _break_input(run: Run) -> Outcome:
    nominal = float(run.spec.inverter.bus_voltage_nominal_v)
    return _break_at(
        run,
        nominal,
        "BKIN over-current",
        "the comparator on BKIN goes active mid-sector; MOE clears in hardware",
    )


def _break_at(run: Run, bus_v: float, name: str, note: str) -> Outcome:
    """The break input mid-sector at the run's speed and the bus `bus_v` (set from the
    start, so the port's bus change has run at it): MOE clears in hardware and the
    outputs take the idle levels the port chose for that speed and bus (from the last
    Hall interval, a whole sector at the run's speed: `into_sector`)."""
    run.board.set_bus_voltage(bus_v)
    run.turn(SETTLE_SECTORS - 1)
    run.into_sector(1 / 3)
    # the break while an upper switch conducts, if one does within the sector: the hand-
    # over to the lower switches (the short circuit) then needs the dead time
    tim1 = run.machine.tim1
    if not run.turn_until(lambda: any(tim1.gates()[0::2]), 6):
        run.into_sector(1 / 3)  # no upper switch conducts: mid-sector
    cause = run.machine.now
    run.board.set_break(True)
    run.run_until_tripped(run.board.pwm_period_ticks())
    tim1 = run.machine.tim1
    # the safe state after the dead time: every switch off, or the three lower switches
    # on (the short circuit, where all-off would rectify into the bus); gates are
    # (CH1, CH1N, CH2, CH2N, CH3, CH3N), the upper switches on CHx
    period = run.board.pwm_period_ticks()
    after = cause + tim1.dead_time_ticks()
    _check_safe_state(run, after, bus_v, "after the dead time", complete_by=cause + period)
    return run.outcome(name, "OVER_CURRENT", cause, period, note)


#: How far either side of the rectifying speed the boundary scenarios brake: wide enough
#: for the Hall interval's and the bus code's quantisation (well under 0.1 % each) and
#: the hysteresis of the bus change, narrow enough that a rule off by a few percent is seen
RECTIFYING_MARGIN = 0.03
#: ... and how far inside the controller's speed range it stays: at its very ends the
#: Hall interval, rounded, may fall on the over-speed side (a fault of its own)
SPEED_RANGE_INSIDE = 0.01


def rectifying_boundary(spec: Spec, *, said: bool = False) -> tuple[float, float] | None:
    """A bus voltage of the spec's range, as near the nominal one as can be, and the
    speed from which all-off may rectify into it (the worst motor's peak line EMF, sim's
    waveform of the spec's EMF at k_e's upper tolerance, reaches the bus), with
    RECTIFYING_MARGIN either side of that speed 1 % inside the controller's range; None
    if no bus voltage of the range has one. `said`: instead the speed from which the
    port may take the rotor to be there (`Corner.said` slower): below it all-off is
    required where the spec prefers it."""
    per_rpm = worst_line_emf_v(spec, 1.0) * (corner(spec).said if said else 1.0)
    lowest = (
        float(spec.controller.speed_min_rpm) * (1 + SPEED_RANGE_INSIDE) / (1 - RECTIFYING_MARGIN)
    )
    highest = (
        float(spec.controller.speed_max_rpm) * (1 - SPEED_RANGE_INSIDE) / (1 + RECTIFYING_MARGIN)
    )
    inverter = spec.inverter
    nominal = float(inverter.bus_voltage_nominal_v) / per_rpm
    rpm = min(
        max(nominal, lowest, float(inverter.bus_voltage_min_v) / per_rpm),
        highest,
        float(inverter.bus_voltage_max_v) / per_rpm,
    )
    bus_v = rpm * per_rpm
    if not (
        lowest <= rpm <= highest
        and inverter.bus_voltage_min_v <= bus_v <= inverter.bus_voltage_max_v
    ):
        return None
    return bus_v, rpm


def _boundary_side(
    run: Run,
    side: int,
    name: str,
    boundary: tuple[float, float] | None,
    missing: str,
    note: Callable[[float, float], str],
) -> Outcome:
    """The break input RECTIFYING_MARGIN below (`side` -1) or above (+1) a boundary
    speed at its bus (`boundary`: bus V, rpm), noted by `note(bus, rpm)`; where there is
    none, the break at the default speed and nominal bus, noted `missing`."""
    if boundary is None:
        nominal = float(run.spec.inverter.bus_voltage_nominal_v)
        return _break_at(run, nominal, name, f"{missing}: the break at the default speed")
    bus_v, rpm = boundary
    run.rpm = rpm * (1 + side * RECTIFYING_MARGIN)
    return _break_at(
        run,
        bus_v,
        name,
        f"{note(bus_v, rpm)}; the break at {run.rpm:.0f} rpm ({side * RECTIFYING_MARGIN:+.0%})",
    )


def _rectifying_side(run: Run, side: int) -> Outcome:
    """The break input just below (`side` -1) or just above (+1) the speed from which
    all-off rectifies into the bus: all-off below it where protection.safe_state prefers
    it, the short circuit above it. Where no bus voltage of the spec's range puts that
    speed in the controller's range, the break at the default speed and nominal bus."""
    return _boundary_side(
        run,
        side,
        f"BKIN {'below' if side < 0 else 'above'} the rectifying speed",
        rectifying_boundary(run.spec, said=side < 0),
        "no bus voltage of the spec's range rectifies within the controller's speed range",
        lambda bus_v, rpm: (
            f"bus {bus_v:.2f} V, where all-off may rectify from {rpm:.0f} rpm"
            + (" (said by the last Hall interval)" if side < 0 else "")
            + " (the safe state after the dead time is the spec's there)"
        ),
    )


def short_rating_boundary(spec: Spec) -> tuple[float, float] | None:
    """Where the spec prefers the short circuit: a bus voltage of the spec's range at
    which all-off does not rectify up to RECTIFYING_MARGIN above the speed where the
    short circuit's bound meets protection.short_circuit_current_max, and that speed,
    with RECTIFYING_MARGIN either side of it 1 % inside the controller's range; None
    where the spec prefers all-off, or no such speed and bus exist."""
    if spec.protection.safe_state != "short_circuit":
        return None
    rpm = short_rated_speed(spec)
    controller, inverter = spec.controller, spec.inverter
    if (
        not rpm
        or rpm * (1 - RECTIFYING_MARGIN)
        < float(controller.speed_min_rpm) * (1 + SPEED_RANGE_INSIDE)
        or rpm * (1 + RECTIFYING_MARGIN)
        > float(controller.speed_max_rpm) * (1 - SPEED_RANGE_INSIDE)
    ):
        return None
    if rpm / corner(spec).said * (1 - RECTIFYING_MARGIN) < float(controller.speed_min_rpm) * (
        1 + SPEED_RANGE_INSIDE
    ):
        return None
    # all-off may not rectify even at the speed the port may read the rotor at
    line = said_line_emf_v(spec, rpm * (1 + RECTIFYING_MARGIN) * (1 + SPEED_RANGE_INSIDE))
    for bus in (inverter.bus_voltage_nominal_v, inverter.bus_voltage_max_v):
        if line < float(bus):
            return float(bus), rpm
    return None


def _short_rating_side(run: Run, side: int) -> Outcome:
    """The break input just below (`side` -1) or just above (+1) the speed where the
    short circuit's bound meets its rating, where the spec prefers the short: the short
    below it, all-off above it. Where the spec prefers all-off, or that speed is out of
    the controller's range, the break at the default speed and nominal bus."""
    boundary = short_rating_boundary(run.spec)
    if boundary is not None and side < 0:
        # the rated speed as the port may read it: the rotor up to Corner.said faster
        boundary = (boundary[0], boundary[1] / corner(run.spec).said)
    return _boundary_side(
        run,
        side,
        f"BKIN {'below' if side < 0 else 'above'} the short circuit's rated speed",
        boundary,
        "the spec prefers all-off, or its short circuit is within its rating at every"
        " speed of the controller's range (or at none)",
        lambda bus_v, rpm: (
            "the short circuit's bound meets"
            f" protection.short_circuit_current_max at {rpm:.0f} rpm, bus {bus_v:g} V (all-off"
            " does not rectify): the short below, all-off above"
        ),
    )


def _below_short_rating(run: Run) -> Outcome:
    return _short_rating_side(run, -1)


def _above_short_rating(run: Run) -> Outcome:
    return _short_rating_side(run, +1)


def _below_rectifying(run: Run) -> Outcome:
    return _rectifying_side(run, -1)


def _above_rectifying(run: Run) -> Outcome:
    return _rectifying_side(run, +1)


#: The bus falls from FALL_FROM x to FALL_TO x the peak line EMF of the run's speed
#: (at least to FALL_NEAREST x where the bus range ends above FALL_TO x): all-off is the
#: safe state before (where the spec prefers it), the short circuit after; either side
#: clear of the bus code's and the Hall interval's quantisation (under 0.1 % and 0.3 %
#: on the fixtures) and of the firmware's hysteresis (8 codes, 0.2 % of full scale)
FALL_FROM, FALL_TO, FALL_NEAREST = 1.03, 0.97, 0.99
#: ... and the bus stays this far inside the spec's range, so no bus fault latches
BUS_RANGE_INSIDE = 0.01


def bus_fall_while_faulted(spec: Spec) -> tuple[float, float, float] | None:
    """A speed 1 % inside the controller's range, as low as the bus range allows (the
    short circuit's current is then the least), and two bus voltages 1 % inside the
    inverter's either side of the peak line EMF at that speed: (rpm, from V, to V);
    None where no speed and bus of the ranges have both."""
    per_rpm = worst_line_emf_v(spec, 1.0)
    said = corner(spec).said
    inverter, controller = spec.inverter, spec.controller
    floor_v = float(inverter.bus_voltage_min_v) * (1 + BUS_RANGE_INSIDE)
    ceiling_v = float(inverter.bus_voltage_max_v) * (1 - BUS_RANGE_INSIDE)
    bottom = float(controller.speed_min_rpm) * (1 + SPEED_RANGE_INSIDE)
    top = float(controller.speed_max_rpm) * (1 - SPEED_RANGE_INSIDE)
    rpm = min(max(floor_v / (FALL_TO * per_rpm), bottom), top)
    line = rpm * per_rpm
    # from above the line EMF the port may read (all-off required where preferred) to
    # below the worst motor's (all-off may rectify: the short)
    low, high = max(line * FALL_TO, floor_v), line * said * FALL_FROM
    if rpm < bottom or low > line * FALL_NEAREST or high > ceiling_v:
        return None
    return rpm, high, low


def _bus_falls_while_faulted(run: Run) -> Outcome:
    """The break input latches a fault with the bus above the rotor's peak line EMF
    (all-off does not rectify: the spec's preference holds), then the bus falls, within
    its range, below that EMF just after an injected sample (the sampled path's worst
    instant): the safe state one PWM period on is the spec's at the new bus (the short
    circuit where all-off now rectifies). The firmware had waited for the next injected
    sample's bus change, 53.5-56.7 us on a 50 us period (a helper's hunt)."""
    name = "bus falls while faulted"
    chosen = bus_fall_while_faulted(run.spec)
    if chosen is None:
        nominal = float(run.spec.inverter.bus_voltage_nominal_v)
        return _break_at(
            run,
            nominal,
            name,
            "no speed of the controller's range has a peak line EMF the bus range can fall"
            " across: the break at the default speed",
        )
    run.rpm, high, low = chosen
    period = run.board.pwm_period_ticks()
    run.board.set_bus_voltage(high)
    run.turn(SETTLE_SECTORS - 1)
    run.into_sector(1 / 3)
    cause = run.machine.now
    run.board.set_break(True)
    run.run_until_tripped(period)
    _check_safe_state(run, cause + period, high, "one PWM period after the break")
    # two whole sectors: the first edge ends the sector the trip's wait ran on in (a
    # longer interval: a slower rotor to the port), the second measures the speed
    run.turn(2)
    _after_a_sample(run)
    fall = run.machine.now
    run.board.set_bus_voltage(low)
    _check_safe_state(run, fall + period, low, "one PWM period after the bus fell")
    moved = [t for t, gates in run.machine.tim1.gate_log or [] if t >= fall]
    after = f", the gates changed {(moved[0] - fall) / TICK_HZ * 1e6:.1f} us on" if moved else ""
    return run.outcome(
        name,
        "OVER_CURRENT",
        cause,
        period,
        f"the break at {run.rpm:.0f} rpm (peak line EMF"
        f" {peak_line_emf_v(run.spec, run.rpm):.2f} V) with the bus at {high:.2f} V, then"
        f" the bus at {low:.2f} V from just after an injected sample, two sectors later{after}",
    )


def _hall_unplugged(run: Run) -> Outcome:
    run.turn(SETTLE_SECTORS - 1)
    # into a sector whose code has one line high (7 then raises two together)
    while bin(run.spec.hall.sequence[(run.sector + 1) % 6]).count("1") != 1:
        run.turn(1)
    run.into_sector(1 / 3)
    cause = run.machine.now
    run.board.set_hall(7)  # the two low lines pulled up at once: no TI1 edge
    run.run_until_tripped(2 * run.board.pwm_period_ticks())
    return run.outcome(
        "Hall unplugged (code 7)",
        "HALL_INVALID",
        cause,
        run.board.pwm_period_ticks(),
        "two Hall lines rise together (pull-ups of an unplugged connector): no TIM3 edge;"
        " the EXTI on the Hall lines sees the code 7 at once and confirms it",
    )


def _hall_pulse(run: Run, during: int, width: int, what: str) -> int:
    """The Hall pins at `during` for `width` ticks, then back at the sector's code (the
    end scheduled on the pins); then one PWM period and four sectors, which must bring
    no TIM3 edge and leave the bridge switching. Returns the pulse's start."""
    code = run.spec.hall.sequence[run.sector]
    captures = run.machine.tim3.captures
    began = run.machine.now
    run.board.set_hall(during)
    run.board.set_hall(code, at=began + width)
    run.machine.run_for(run.board.pwm_period_ticks())
    if run.machine.tim3.captures != captures:
        run.violations.append(f"the {what} made a TIM3 edge")
    run.turn(4)
    if not run.machine.tim1.moe:
        run.violations.append(f"the bridge stopped after the {what}")
    return began


def _hall_glitch(run: Run) -> Outcome:
    run.turn(SETTLE_SECTORS - 1)
    run.into_sector(1 / 3)
    code = run.spec.hall.sequence[run.sector]
    width = max(1, run.machine.tim3._filter_ticks() // 2)
    # one line flips for half the input filter's time, to a valid code (the EXTI wakes
    # the CPU at its start)
    flipped = next(code ^ (1 << b) for b in range(3) if (code ^ (1 << b)) not in (0, 7))
    # placed while the CPU sleeps: time is exact then
    run.wait_for(lambda: run.machine.sleep_pc is not None, 1, "the CPU did not sleep")
    _hall_pulse(run, flipped, width, "glitch")
    return run.outcome(
        "Hall glitch",
        None,
        None,
        None,
        f"one Hall line flips for {width} ticks, half TIM3's input filter: no edge, no fault",
    )


#: Steps of the sector shortening the Hall scenario below sweeps, 0 to the spec's bound
SHORTENING_STEPS = 12


def _hall_off_marks(run: Run) -> Outcome:
    """A rotor speeding up (or Hall sensors off their marks): runs of six sectors, each
    shorter than the one two before it, the one its commutation's timing was computed
    from (the timing handler runs after an edge on the interval that edge ends, for the
    next edge), by 1/12 to 12/12 of hall.sector_shortening in turn (every sector
    position: both switches of every leg), then one sector back at the start; near the
    top speed, where commutations last longest (up to their whole sector). Where a
    commutation fills its sector it ends the guard and the margin before the sector
    measured does; the next edge then still comes at least the guard after it and
    switches the other switch of that leg on no sooner than the dead time (the gate
    invariant). Without the margin, a 2 us bridge's edges came within the dead time of
    the end (tests/fixtures/pil/fast40k_dead2us.yaml)."""
    shortening = float(run.spec.hall.sector_shortening)
    # each sector (1 - d) of the one before: (1 - d)^2 >= 1 - 2 d of the one two before
    halves = [shortening * step / SHORTENING_STEPS / 2 for step in range(1, SHORTENING_STEPS + 1)]
    # the shortest sector of a run still inside the speed range
    top = 0.98 * float(run.spec.controller.speed_max_rpm)
    run.rpm = (1.0 - halves[-1]) ** 6 * top
    shortest = 0
    if run.rpm < float(run.spec.controller.speed_min_rpm):
        # a range narrower than the run's 1/(1 - d)^6 (11 000 to 12 000 rpm on a 72 MHz
        # Hall clock): below it the sectors outlasted TIM3's range (the Hall timed out),
        # so the run starts at the lowest speed and its sectors stop at the top speed's
        run.rpm = float(run.spec.controller.speed_min_rpm)
        shortest = round(sector_ticks_at(run.spec, top))
    run.turn(SETTLE_SECTORS)
    base = run.sector_ticks()
    for half in halves:
        factors = [(1.0 - half) ** k for k in range(1, 7)]
        for factor in (*factors, 1.0):
            run.step(max(shortest, round(base * factor)))
    return run.outcome(
        "Hall sensors off their marks",
        None,
        None,
        None,
        f"runs of six sectors each up to {100 * shortening:g} % (hall.sector_shortening)"
        " shorter than the one two before it (its timing's), near the top speed: no fault,"
        " the dead time kept at every edge",
    )


#: Bus ADC noise of the bus_noise scenario: uniform, this many LSB either side, drawn
#: afresh at each conversion (an STM32F103's ADC is specified to about +-2 LSB)
BUS_NOISE_LSB = 2.0
BUS_NOISE_SECTORS = 24


def _bus_noise(run: Run) -> Outcome:
    """The bus at its nominal voltage with +-2 LSB of noise at every conversion, near
    the top speed: the noise leaves the bus change's one-code band at almost every
    sample, and each change costs the bus state and a timing run. The drive must take
    at most one bus change per top-speed sector, the rate the CPU-load budget prices
    (`make bench` judges the budget; the loads, noisy and quiet, are in the note): a bus
    change every PWM period had doubled the load on a 100 kHz fixture, 21 -> 42 %. No
    fault may result."""
    spec = run.spec
    top = float(spec.controller.speed_max_rpm)
    run.rpm = float(spec.controller.speed_min_rpm) + 0.98 * (
        top - float(spec.controller.speed_min_rpm)
    )
    run.turn(1)
    machine = run.machine
    quiet_from, quiet_busy = machine.now, machine.handler_ticks
    run.turn(SETTLE_SECTORS - 1)
    quiet = (machine.handler_ticks - quiet_busy) / max(1, machine.now - quiet_from)
    lsb = float(spec.adc.reference_v) / 2**spec.adc.bits * float(spec.adc.bus_voltage_divider)
    nominal = float(spec.inverter.bus_voltage_nominal_v)
    noise = random.Random(1)
    run.board.set_bus_voltage(lambda tick: nominal + noise.uniform(-1.0, 1.0) * BUS_NOISE_LSB * lsb)
    begun, busy = machine.now, machine.handler_ticks
    changes_before = len(run.board.entries_of("TIM1", "TIM1_UP_TIM10"))
    run.turn(BUS_NOISE_SECTORS)
    elapsed = machine.now - begun
    load = (machine.handler_ticks - busy) / max(1, elapsed)
    changes = len(run.board.entries_of("TIM1", "TIM1_UP_TIM10")) - changes_before
    shortest = sector_ticks_at(spec, top)
    allowed = -(-elapsed // int(shortest)) + 1
    budget = float(spec.firmware.cpu_load_budget_percent) / 100
    if changes > allowed:
        run.violations.append(
            f"{changes} bus changes in {elapsed / TICK_HZ * 1e3:.2f} ms, more than one per"
            f" top-speed sector ({allowed})"
        )
    return run.outcome(
        "bus ADC noise",
        None,
        None,
        None,
        f"+-{BUS_NOISE_LSB:g} LSB at every conversion near the top speed: CPU load"
        f" {100 * load:.1f} % ({100 * quiet:.1f} % on a quiet bus; budget {100 * budget:g} %),"
        f" {changes} bus changes in"
        f" {BUS_NOISE_SECTORS} sectors (at most {allowed})",
    )


#: The spike on two Hall lines the EXTI path must ignore: shorter than its confirmation
#: (codegen/port.py HALL_CONFIRM_NS, 1 us), longer than TIM3's input filter
HALL_SPIKE_NS = 500


def _hall_spike(run: Run) -> Outcome:
    run.turn(SETTLE_SECTORS - 1)
    # into a sector whose code has one line high (7 then raises two together)
    while bin(run.spec.hall.sequence[(run.sector + 1) % 6]).count("1") != 1:
        run.turn(1)
    run.into_sector(1 / 3)
    width = HALL_SPIKE_NS * TICK_HZ // 1_000_000_000
    # the two low lines together: no TI1 edge, the EXTI sees 7
    began = _hall_pulse(run, 7, width, "spike")
    if not any(began <= t <= began + width for _, t in run.machine.exti.edge_log):
        run.violations.append("the spike reached no EXTI line")
    return run.outcome(
        "Hall spike to code 7",
        None,
        None,
        None,
        f"two Hall lines rise together for {HALL_SPIKE_NS} ns (half the EXTI path's 1 us"
        " confirmation): no TIM3 edge, the EXTI reads 7 once, no fault",
    )


#: The longest quiet wait for the Hall time-out emulated in full (ticks, 0.2 s): beyond
#: it TIM3's counter is moved on to that far before its wrap
QUIET_WAIT_TICKS = TICK_HZ // 5


def shorten_quiet_wait(machine: Machine, wrap: int) -> tuple[int, str]:
    """Where TIM3's wrap (the Hall time-out, at tick `wrap`) is more than QUIET_WAIT_TICKS
    away, move its counter on to QUIET_WAIT_TICKS before it: the wrap's tick then, and a
    note for the outcome saying so ("" where nothing was skipped). Only counts in which
    TIM3 has nothing to do are skipped: a compare of an output channel inside them (the
    commutation end the last Hall edge scheduled, TIM3 CCR2) would never match, so the
    caller runs past it first, and a skip over one raises PilError."""
    tim3, now = machine.tim3, machine.now
    if wrap - now <= QUIET_WAIT_TICKS:
        return wrap, ""
    per_count = tim3.ticks_per_count()
    skipped = (wrap - now - QUIET_WAIT_TICKS) // per_count
    position = tim3.position(now)
    counter = tim3.cnt_of_position(position)
    for channel in (1, 2, 3, 4):
        if not tim3.is_input(channel) and counter < tim3.ccr[channel] <= counter + skipped:
            raise PilError(
                f"TIM3's counter is to skip {skipped} counts from {counter} to the quiet wait"
                f" before its wrap, over CCR{channel} = {tim3.ccr[channel]}: a compare due"
                " (the commutation end) would never match"
            )
    tim3.reanchor(position + skipped)
    note = (
        f"; the quiet wait shortened by {skipped * per_count / TICK_HZ:.3g} s"
        f" (TIM3's counter moved on to {QUIET_WAIT_TICKS / TICK_HZ:g} s before its wrap)"
    )
    return wrap - skipped * per_count, note


@dataclass(frozen=True)
class TimeoutWindow:
    """When a Hall time-out after an edge at `last_edge` must act: not before `cause`
    (the latest edge of a turning rotor, or the counter's range), and within `limit`
    ticks of it."""

    cause: int
    limit: int
    note: str


def timeout_window(
    run: Run, last_edge: int, interval: int, *, guard: float = BOUNDARY_GUARD
) -> TimeoutWindow | None:
    """Where a turning rotor is bound to make its next edge within TIMEOUT_INTERVALS of
    its last `interval` (ticks; the yardstick, `hall_timeout.timeout_bound_s`): the trip
    after the latest such edge and by then + one PWM period. None where the counter's
    range is the time-out (the rotor may stop within the sector)."""
    bound = timeout_bound_s(run.spec, interval / TICK_HZ, guard=guard)
    if bound is None:
        return None
    earliest = latest_next_edge_s(run.spec, interval / TICK_HZ)
    assert earliest is not None  # bounded: the rotor cannot stop within the sector
    cause = last_edge + math.ceil(earliest * TICK_HZ)
    due = last_edge + round(bound * TICK_HZ)
    return TimeoutWindow(
        cause,
        due + run.board.pwm_period_ticks() - cause,
        f"a turning rotor braking at up to {deceleration(run.spec):.4g} rad/s^2 makes its"
        f" next edge within {earliest * 1e3:.3g} ms of the last: the trip after that and by"
        f" {TIMEOUT_INTERVALS} intervals ({bound * 1e3:.3g} ms) + one PWM period",
    )


def counter_range_end(machine: Machine, last_edge: int) -> int:
    """The Hall counter's range after an edge: CC3 matches at ARR, a count before the
    wrap's UIF, where the counter's range is the time-out."""
    tim3 = machine.tim3
    return last_edge + tim3.arr * tim3.ticks_per_count()


def _rotor_stops(run: Run) -> Outcome:
    """The Hall code stops changing while the bridge switches: the rotor stopped, or the
    Hall lines froze at a valid code while it turns. Where a turning rotor is bound to
    make its next edge within TIMEOUT_INTERVALS of its last interval (`timeout_window`)
    the trip must come after the latest such edge and by then: frozen lines had braked
    with one sector's pattern for the Hall counter's whole range, 65 ms on the paper
    motor, 17 sectors at 2600 rpm (a hunt). Elsewhere the latency runs from TIM3's
    counter range after the last edge. A sector after the last edge its commutation has
    ended, and until the time-out nothing else happens but the current loop's periods:
    where that wait is longer than QUIET_WAIT_TICKS (the counter's range at a slow Hall
    clock: 58 s at 1125 Hz) TIM3's counter is moved on to QUIET_WAIT_TICKS before its
    wrap, and the wait from there and the way to the safe state are emulated in full."""
    run.turn(SETTLE_SECTORS)
    sector = run.sector_ticks()
    last_edge = run.machine.now - sector
    period = run.board.pwm_period_ticks()
    # Within BOUNDARY_GUARD of the speed where the bound stops holding (guard 0: the
    # band) the time-out of TIMEOUT_INTERVALS is right too, if it comes after a turning
    # rotor's latest edge: a 1-pole-pair spindle at 82 800 rpm had tripped there and been
    # reported as never tripping, its cause taken at the wrap (a helper's hunt).
    for guard in (BOUNDARY_GUARD, 0.0):
        window = timeout_window(run, last_edge, sector, guard=guard)
        if window is None:
            continue
        run.run_until_tripped(window.cause + window.limit - run.machine.now + period)
        if guard == 0.0 and run.machine.tim1.moe:
            break  # in the band, not tripped by then: the counter's wrap is the time-out
        _check_timeout_source(run, window.cause)
        band = (
            ""
            if guard
            else f", within {BOUNDARY_GUARD:.0%} of the slowest speed whose next edge is"
            " bound (either time-out is right)"
        )
        return run.outcome(
            "rotor stops",
            "HALL_TIMEOUT",
            window.cause,
            window.limit,
            "the Hall code stops changing while the bridge switches, the rotor at"
            f" {run.rpm:.0f} rpm{band}; {window.note}",
        )
    wrap, note = shorten_quiet_wait(run.machine, counter_range_end(run.machine, last_edge))
    run.run_until_tripped(wrap - run.machine.now + 2 * period)
    _check_timeout_source(run, wrap)
    return run.outcome(
        "rotor stops",
        "HALL_TIMEOUT",
        wrap,
        period,
        "the Hall code stops changing while the bridge switches; latency from TIM3's"
        " counter range after the last edge (the Hall time-out where a rotor this slow may"
        " stop within a sector)" + note,
    )


#: PWM periods the hardest-braking scenario runs on after the late edge
AFTER_LATE_EDGE_PERIODS = 10


def _hardest_braking(run: Run) -> Outcome:
    """A rotor braking as hard as the machine can (the yardstick's alpha, the bridge's
    rated current through the worst motor) through a shortest sector and then a longest
    one, near the slowest speed where a turning rotor is still bound to make its next
    edge (`hall_timeout.hardest_braking`): that edge comes as late as a turning rotor's
    can, 2.35 intervals on at equal sectors, and the Hall time-out must not trip before
    it (one of 2 intervals would). Where no speed bounds the next edge, plain braking
    sectors at the default speed (the time-out is the counter's wrap)."""
    chosen = hardest_braking(run.spec)
    if chosen is None:
        run.turn(SETTLE_SECTORS)
        note = "no speed of the spec's range bounds a turning rotor's next edge (or its rotor enters the braked sector over speed_max): braking at the default speed"
    else:
        interval, following = chosen
        run.rpm = speed_into(run.spec, interval)
        run.turn(SETTLE_SECTORS)
        run.step(round(interval * TICK_HZ))  # the shortest sector, braked through at alpha
        run.step(math.floor(following * TICK_HZ))  # the longest, its edge as late as can be
        note = (
            f"from {run.rpm:.0f} rpm braking at {deceleration(run.spec):.4g} rad/s^2: a"
            f" {interval * 1e3:.4g} ms interval, then the next edge"
            f" {following * 1e3:.4g} ms on ({following / interval:.3g} intervals)"
        )
    run.step(AFTER_LATE_EDGE_PERIODS * run.board.pwm_period_ticks())
    return run.outcome("hardest braking", None, None, None, note)


def _check_timeout_source(run: Run, wrap: int) -> None:
    """The Hall time-out must be TIM3's own event: the current loop, which looks at the
    wrap once a PWM period, finds it up to a whole period after it and then needs its
    path to MOE, so it misses the one-period limit at the worst phase of the wrap (which
    is fixed per motor: the carrier restarts at each COM event, so a scenario cannot
    steer it there)."""
    cleared = run.machine.tim1.moe_cleared_at
    if cleared is None or cleared < wrap:
        return
    # the handler that cleared MOE: the last one entered by then
    entries = [(t, e) for t, e in run.machine.entry_log if wrap <= t <= cleared]
    loop = IRQ_BASE + svd_interrupt("ADC1", "ADC")
    if entries and entries[-1][1] == loop:
        run.violations.append(
            f"the Hall time-out was found by the current loop {entries[-1][0] - wrap} ticks"
            " after TIM3 wrapped, not by TIM3's own interrupt: at the worst phase a whole"
            f" PWM period ({run.board.pwm_period_ticks()} ticks) and its path to MOE"
        )


#: Bytes of one timing slot of the port (`PORT_SLOT_BYTES`, port_slots[0] and [1])
PORT_SLOT_BYTES = 16

#: PWM periods watched after a latched fault with its cause still present
QUIET_PERIODS = 10


def _check_quiet_while_faulted(run: Run) -> None:
    """With the fault latched and its cause present, nothing re-trips: the timing handler
    (raised by each trip's COM event) stays idle over QUIET_PERIODS PWM periods."""
    before = len(run.board.entries_of("TIM1", "TIM1_TRG_COM_TIM11"))
    run.machine.run_for(QUIET_PERIODS * run.board.pwm_period_ticks())
    runs = len(run.board.entries_of("TIM1", "TIM1_TRG_COM_TIM11")) - before
    if runs:
        run.violations.append(
            f"the timing handler ran {runs} times in {QUIET_PERIODS} PWM periods while faulted"
        )


def _bus_stuck_at_zero(run: Run) -> Outcome:
    run.turn(SETTLE_SECTORS - 1)
    run.into_sector(1 / 3)
    cause = run.machine.now
    run.board.set_bus_voltage(0.0)
    run.run_until_tripped(2 * run.board.pwm_period_ticks())
    # the bus is in fact at its nominal voltage: the safe state must be one safe there
    # (the port reads no bus: a collapsed one or a stuck ADC look alike to it)
    nominal = float(run.spec.inverter.bus_voltage_nominal_v)
    _check_safe_state(
        run, cause + run.board.pwm_period_ticks(), nominal, "one PWM period on", inputs_known=False
    )
    _check_quiet_while_faulted(run)
    return run.outcome(
        "bus ADC stuck at 0",
        "UNDER_VOLTAGE",
        cause,
        run.board.pwm_period_ticks(),
        "the bus divider's ADC input reads 0 V from mid-sector on",
    )


def _no_rectifying_speed(run: Run, instead: str) -> tuple[float, str]:
    """The nominal bus and the note of a scenario that needs all-off to rectify inside
    the controller's speed range where no bus of the spec's range makes it."""
    return float(run.spec.inverter.bus_voltage_nominal_v), (
        f"no bus voltage of the spec's range rectifies inside the controller's speed range:"
        f" {instead}"
    )


def _bus_stuck_at_full_scale(run: Run) -> Outcome:
    """The bus divider's ADC input stuck at the reference (its lower resistor open)
    while the bus is in fact at a voltage of the spec's range, the rotor RECTIFYING_MARGIN
    above the speed from which all-off rectifies into it: OVER_VOLTAGE, and one PWM period
    on a state safe at that speed and the real bus (the short circuit there), since the
    port cannot tell a bus that is over from an ADC stuck high. The firmware had chosen
    the region from the reading: all-off, rectifying (a hunt)."""
    boundary = rectifying_boundary(run.spec)
    if boundary is None:
        bus_v, note = _no_rectifying_speed(run, "at the default speed and the nominal bus")
    else:
        bus_v, rpm = boundary
        run.rpm = rpm * (1 + RECTIFYING_MARGIN)
        note = (
            f"the bus in fact at {bus_v:.2f} V, where all-off rectifies from {rpm:.0f} rpm;"
            f" the rotor at {run.rpm:.0f} rpm"
        )
    run.board.set_bus_voltage(bus_v)
    run.turn(SETTLE_SECTORS - 1)
    run.into_sector(1 / 3)
    cause = run.machine.now
    adc = run.spec.adc
    run.board.set_bus_voltage(1.05 * float(adc.reference_v * adc.bus_voltage_divider))
    period = run.board.pwm_period_ticks()
    run.run_until_tripped(2 * period)
    _check_safe_state(run, cause + period, bus_v, "one PWM period on", inputs_known=False)
    _check_quiet_while_faulted(run)
    return run.outcome(
        "bus ADC stuck at full scale",
        "OVER_VOLTAGE",
        cause,
        period,
        f"the bus divider's ADC input at the reference from mid-sector on; {note}",
    )


def _after_a_sample(run: Run) -> None:
    """Run on to just after an injected sequence's end: the instant a cause that only
    the sampled current would show waits longest (a whole PWM period) for the next."""
    adc = run.machine.adc1
    seen = adc.injected_sequences
    run.wait_for(
        lambda: adc.injected_sequences != seen and not adc.queue,
        TICK_HZ // 2_000_000,
        "no injected sequence ended",
    )


def zero_current_reads_on(spec: Spec, rail_v: float) -> bool:
    """Whether the current sense reads zero current on this rail: its offset converts
    to code 0 (below one LSB) or to full scale. Such a rail is what a braking current of
    0 reads (and any current beyond the sense's range on that side), not a fault."""
    full = 2**spec.adc.bits
    zero = Fraction(spec.adc.current_offset_v) / Fraction(spec.adc.reference_v) * full
    return zero < 1 if rail_v == 0.0 else zero >= full - 1


def _current_sensor(run: Run, rail_v: float, which: str) -> Outcome:
    run.turn(SETTLE_SECTORS - 1)
    run.into_sector(1 / 3)
    _after_a_sample(run)
    cause = run.machine.now
    channel = run.spec.sensing.current_channels[0]
    run.machine.adc1.set_input(channel, rail_v)  # ADC1 and ADC2 share the pin
    if zero_current_reads_on(run.spec, rail_v):
        run.machine.run_for(4 * run.board.pwm_period_ticks())
        return run.outcome(
            f"current sensor at {which}",
            None,
            None,
            None,
            f"the first current channel (IN{channel}) reads {which} ({rail_v:g} V), where"
            f" zero current reads (adc.current_offset = {float(run.spec.adc.current_offset_v):g}"
            " V): a current of 0, no fault for four PWM periods",
        )
    run.run_until_tripped(2 * run.board.pwm_period_ticks())
    _check_quiet_while_faulted(run)
    return run.outcome(
        f"current sensor at {which}",
        "CURRENT_SENSOR",
        cause,
        run.board.pwm_period_ticks(),
        f"the first current channel (IN{channel}) reads {which} ({rail_v:g} V) from just after"
        " an injected sample (the sampled path's worst instant); ADC2's analog watchdog sees"
        " it at the end of its next conversion",
    )


def _current_sensor_low(run: Run) -> Outcome:
    return _current_sensor(run, 0.0, "the low rail")


def _current_sensor_high(run: Run) -> Outcome:
    return _current_sensor(run, float(run.spec.adc.reference_v), "the high rail")


#: How far apart the two lines of a skipped sector change: beyond TIM3's input filter
#: (111 ns), so the first change makes a Hall edge, and before its handler reads the pins
SKIP_GAP_NS = 200


def _hall_sequence(run: Run) -> Outcome:
    run.turn(SETTLE_SECTORS - 1)
    run.into_sector(1 / 2)
    sequence = run.spec.hall.sequence
    now_code = sequence[run.sector]
    middle = sequence[(run.sector + 1) % 6]
    skipped_to = sequence[(run.sector + 2) % 6]
    # placed while the CPU sleeps: time is exact then
    run.wait_for(lambda: run.machine.sleep_pc is not None, 1, "the CPU did not sleep")
    cause = run.machine.now
    run.board.set_hall(middle)
    run.board.set_hall(skipped_to, at=cause + SKIP_GAP_NS * TICK_HZ // 1_000_000_000)
    if bin(now_code ^ skipped_to).count("1") != 2:
        run.violations.append("the skipped sector is not two line changes away")
    run.run_until_tripped(2 * run.board.pwm_period_ticks())
    return run.outcome(
        "Hall sector skipped",
        "HALL_SEQUENCE",
        cause,
        run.board.pwm_period_ticks(),
        f"two Hall lines change {SKIP_GAP_NS} ns apart (a sector skipped): the Hall edge of the"
        " first reads the pins after the second, a code two sectors on",
    )


#: How far above the speed from which all-off rectifies the stuck-line scenario brakes
#: (at most 1 % inside speed_max): a two-sector interval then reads as a speed well
#: below it
STUCK_ABOVE = 1.3
#: ... and how many sectors it turns with the line stuck
STUCK_SECTORS = 8


def hall_stuck_speed(spec: Spec) -> tuple[float, float] | None:
    """A bus voltage of the spec's range and a speed inside the controller's, at least
    RECTIFYING_MARGIN above the one from which all-off rectifies into that bus (up to
    STUCK_ABOVE x it): (bus V, rpm); None where there is none."""
    boundary = rectifying_boundary(spec)
    if boundary is None:
        return None
    bus_v, rpm = boundary
    fast = min(rpm * STUCK_ABOVE, float(spec.controller.speed_max_rpm) * (1 - SPEED_RANGE_INSIDE))
    if fast < rpm * (1 + RECTIFYING_MARGIN):
        return None
    return bus_v, fast


def _rectifying_note(run: Run, bus_v: float) -> str:
    """The speed and bus a scenario placed above the rectifying speed, for its note."""
    rectifying = bus_v / worst_line_emf_v(run.spec, 1.0)
    return (
        f"the rotor at {run.rpm:.0f} rpm, bus {bus_v:.2f} V (all-off may rectify from"
        f" {rectifying:.0f} rpm)"
    )


def _hall_line_stuck(run: Run) -> Outcome:
    """A Hall line stops changing while the rotor brakes faster than the speed from
    which all-off rectifies: the next code with it stuck is 000 or 111 (HALL_INVALID),
    and the other two lines go on changing, every other interval two sectors long. From
    one PWM period after the trip to STUCK_SECTORS sectors on, the gates are a state
    safe at the rotor's speed and bus, which the port no longer knows (the short
    circuit there). The firmware had taken the two-sector intervals as the rotor's and
    chosen all-off, rectifying, 17.6 ms after the trip on the paper motor (a hunt)."""
    name = "Hall line stuck above the rectifying speed"
    bus_v, note = _placed_above_rectifying(run, "the line stuck")
    run.board.set_bus_voltage(bus_v)
    run.turn(SETTLE_SECTORS)
    sequence = run.spec.hall.sequence
    now, following = sequence[run.sector], sequence[(run.sector + 1) % 6]
    stuck = (now ^ following).bit_length() - 1  # the line the next edge would change
    level = now >> stuck & 1
    cause = run.machine.now
    for _ in range(STUCK_SECTORS):
        run._finish_sector()
        run.sector = (run.sector + 1) % 6
        code = sequence[run.sector] & ~(1 << stuck) | level << stuck
        run.board.set_hall(code)
        run._due = run.machine.now + run.sector_ticks()
        run.machine.run_for(run.sector_ticks())
    run.run_until_tripped(run.board.pwm_period_ticks())
    cleared = run.machine.tim1.moe_cleared_at
    period = run.board.pwm_period_ticks()
    if cleared is not None:
        start = cleared + period
        changes = [t for t, _ in run.machine.tim1.gate_log or [] if t > start]
        for at in [start, *changes]:
            _check_safe_state(
                run, at, bus_v, "with the Hall line stuck, the speed unknown", inputs_known=False
            )
    # two sectors beyond TIM3's range (a narrow range near the counter's, 20 000 rpm on
    # a 72 MHz Hall clock): the counter wraps first, HALL_TIMEOUT, and the stuck line's
    # code latches HALL_INVALID as well (a hunt: the scenario had wanted it alone)
    hall_ticks = 2 * run.sector_ticks() * run.spec.hall.timer_clock_hz / TICK_HZ
    wraps = hall_ticks > 2**run.spec.hall.counter_bits
    return run.outcome(
        name,
        "HALL_TIMEOUT+HALL_INVALID" if wraps else "HALL_INVALID",
        cause,
        2 * run.sector_ticks(),
        f"{note}; line {stuck} stuck from the next edge on, {STUCK_SECTORS} sectors;"
        " the trip comes with the first code of the stuck line (000 or 111), a sector on",
    )


#: A Hall line's bounce: each level held this long (longer than TIM3's input filter)
BOUNCE_NS = 3000
#: ... and this many changes of the line before the connector's pull-ups win (code 7)
BOUNCE_CHANGES = 5
#: Sectors after a bounce at which the gates are checked
BOUNCE_CHECKS = (1, 5, 10)


def _bounce_ticks() -> int:
    return round(BOUNCE_NS * TICK_HZ / 1e9)


def _placed_above_rectifying(run: Run, what: str) -> tuple[float, str]:
    """The rotor (set) and bus (returned, with the note) of a scenario just above the
    speed from which all-off rectifies (`hall_stuck_speed`), where the short is due and
    a rotor read too fast may be taken beyond a rated short; else the default speed and
    the nominal bus."""
    chosen = hall_stuck_speed(run.spec)
    if chosen is None:
        return _no_rectifying_speed(run, f"{what} at the default speed")
    bus_v, run.rpm = chosen
    return bus_v, _rectifying_note(run, bus_v)


def _over_speed_or_read_back(run: Run) -> str:
    """The fault a spurious Hall edge must latch: OVER_SPEED, or with or instead of it
    HALL_SEQUENCE where the edge's handler, entered late, reads the pins back at the old
    code (a repeated code): whichever of the two latched, and nothing else."""
    latched = run.board.symbol("app_faults")
    either = {FAULT["OVER_SPEED"], FAULT["HALL_SEQUENCE"]}
    return (
        "+".join(name for name in ("OVER_SPEED", "HALL_SEQUENCE") if latched & FAULT[name])
        if latched and latched & ~sum(either) == 0
        else "OVER_SPEED"
    )


def _hall_bounce(run: Run) -> Outcome:
    """A real Hall edge whose line bounces (the new code, the old one BOUNCE_NS later,
    the new one again after as long: longer than TIM3's input filter): OVER_SPEED
    latches at the second edge (a microseconds' interval), and the safe state is the
    one at the rotor's speed, which the last right interval tells: the bounce's
    interval says nothing of it. A spec that prefers the short had read the 3 us as a
    rotor beyond the short's rating and held all-off, rectifying, to the next edge (a
    hunt: the paper motor preferring the short, 4400 rpm on 20.5 V)."""
    bus_v, note = _placed_above_rectifying(run, "the bounce")
    run.board.set_bus_voltage(bus_v)
    run.turn(SETTLE_SECTORS)
    before, code = run.edge_now()
    sector = run.sector_ticks()
    edge = run.machine.now
    bounce = _bounce_ticks()
    run.board.set_hall(before, at=edge + bounce)
    run.board.set_hall(code, at=edge + 2 * bounce)
    run._due = edge + sector
    run.machine.run_until(edge + sector - 1)
    cleared = run.machine.tim1.moe_cleared_at
    period = run.board.pwm_period_ticks()
    if cleared is not None:
        for at in (cleared + period, edge + sector - 2):
            _check_safe_state(run, at, bus_v, "after the bounce")
    run.turn(max(BOUNCE_CHECKS))
    for k in BOUNCE_CHECKS:
        at = edge + k * sector + sector // 2
        _check_safe_state(run, at, bus_v, f"{k} sectors after the bounce")
    # the edge's handler, entered late (a handler ahead of it), may read the pins back at
    # the old code: a repeated code, HALL_SEQUENCE, as much at once
    expected = _over_speed_or_read_back(run)
    return run.outcome(
        "Hall edge bounces",
        expected,
        edge + bounce,
        bounce + period,
        f"{note}; the edge's line back to the old code {BOUNCE_NS} ns on and forward again"
        " as long after: OVER_SPEED at the second edge (or HALL_SEQUENCE where the edge's"
        " handler reads the pins back at the old code)",
    )


#: A Hall line's glitch late in a sector: where in it (a fraction of the sector) and how
#: long (longer than TIM3's input filter and than the edge's handler takes to trip)
GLITCH_LATE_AT = 0.6
GLITCH_LATE_NS = 2000
#: Checks of the gates after a late glitch, in sectors from it
GLITCH_LATE_CHECKS = (0.2, 0.7, 1.2, 1.7)


def _hall_glitch_late(run: Run) -> Outcome:
    """One Hall line flips to the next sector's code for GLITCH_LATE_NS at GLITCH_LATE_AT
    of a sector, the rotor just above the speed from which all-off rectifies: the part
    sector up to the glitch reads as a rotor 1/GLITCH_LATE_AT x as fast, over the top
    speed (OVER_SPEED), and the line's return is a bounce. The safe state is the one at
    the rotor's speed from one PWM period after the trip to two sectors on: a rotor
    shortens its interval by hall.sector_shortening at most, so the part sector is no
    rotor's. It had been read as the rotor's: on the paper motor preferring the short,
    rated to 5359 rpm, a rotor beyond the rating, all-off, rectifying, for up to 1.4
    sectors (a hunt: 4900 rpm on 20.2 V)."""
    assert max(GLITCH_LATE_CHECKS) > 1 + GLITCH_LATE_AT  # one check after a whole interval
    bus_v, note = _placed_above_rectifying(run, "the glitch")
    run.board.set_bus_voltage(bus_v)
    run.turn(SETTLE_SECTORS)
    sector = run.sector_ticks()
    run.step(round(GLITCH_LATE_AT * sector), sector=sector)
    sequence = run.spec.hall.sequence
    code, following = sequence[run.sector], sequence[(run.sector + 1) % 6]
    cause = run.machine.now
    width = round(GLITCH_LATE_NS * TICK_HZ / 1e9)
    run.board.set_hall(following)
    run.board.set_hall(code, at=cause + width)
    run.machine.run_until(run._due)
    run.turn(2)
    period = run.board.pwm_period_ticks()
    cleared = run.machine.tim1.moe_cleared_at
    # Until a whole interval after the glitch is measured (the edge at 1.4 sectors) the
    # port may hold a state safe at the speed a part sector reads, its preference aside
    # (all-off preferred, the short rated: the short), since that one is safe at the
    # rotor's speed too; it must be safe at the rotor's, and from then on the spec's.
    if cleared is not None:
        _check_safe_state(
            run,
            cleared + period,
            bus_v,
            "one PWM period after the glitch's trip",
            inputs_known=False,
        )
    for k in GLITCH_LATE_CHECKS:
        _check_safe_state(
            run,
            cause + round(k * sector),
            bus_v,
            f"{k:g} sectors after the glitch",
            inputs_known=k > 1 + GLITCH_LATE_AT,
        )
    expected = _over_speed_or_read_back(run)
    return run.outcome(
        "Hall glitch late in a sector",
        expected,
        cause,
        width + period,
        f"{note}; one line to the next code for {GLITCH_LATE_NS} ns at {GLITCH_LATE_AT:g} of a"
        " sector: OVER_SPEED (or HALL_SEQUENCE where the edge's handler reads the pins back),"
        " and the safe state at the rotor's speed, not at the part sector's",
    )


def _hall_unplugged_bouncing(run: Run) -> Outcome:
    """The Hall connector comes off half-way into a sector, one line bouncing
    (BOUNCE_CHANGES levels BOUNCE_NS each) before the pull-ups hold code 7: OVER_SPEED
    at the bounce's microseconds' interval, HALL_INVALID at the code 7, and from one PWM
    period on a state safe at the rotor's speed and bus, which the port no longer knows
    (the short circuit where all-off rectifies). The faulted port took the shortest
    interval as the rotor's while a Hall line's fault lasts, the first bounce edge's
    half sector among them: on a spec that prefers the short, a rotor read at twice its
    speed, beyond the short's rating, got all-off, rectifying, for as long as the fault
    lasted (a hunt: 4700 rpm on 20.5 V, the short rated to 5359 rpm)."""
    bus_v, note = _placed_above_rectifying(run, "the unplugged connector")
    run.board.set_bus_voltage(bus_v)
    run.turn(SETTLE_SECTORS)
    sector = run.sector_ticks()
    run.step(sector // 2, sector=sector)
    code = run.spec.hall.sequence[run.sector]
    line = next(b for b in range(3) if (code ^ (1 << b)) not in (0, 7))
    start = run.machine.now
    bounce = _bounce_ticks()
    at = start
    for change in range(BOUNCE_CHANGES):
        run.board.set_hall(code ^ (1 << line) if change % 2 == 0 else code, at=at)
        at += bounce
    run.board.set_hall(7, at=at)
    run._due = None
    run.machine.run_until(start + max(BOUNCE_CHECKS) * sector + sector // 2)
    for k in BOUNCE_CHECKS:
        _check_safe_state(
            run,
            start + k * sector,
            bus_v,
            f"{k} sectors after the connector came off",
            inputs_known=False,
        )
    return run.outcome(
        "Hall connector off, a line bouncing",
        "HALL_INVALID+OVER_SPEED",
        start,
        at - start + run.board.pwm_period_ticks(),
        f"{note}; half-way into a sector line {line} changes {BOUNCE_CHANGES} times"
        f" {BOUNCE_NS} ns apart, then code 7",
    )


#: Top-speed sectors each step of the early step back lasts (1.05: no over-speed) ...
ROCK_STEP = 1.05
#: ... in a sector this many times a top-speed one: the forward edge 2.1 of them on,
#: and 4 x 1.05 after it, a time-out from the step's interval, well inside it
ROCK_SLOWER = 10
#: Sectors turned before the steps: fewer than SETTLE_SECTORS, slow ones are long to
#: emulate (the timing and the commutations run from the second edge on)
ROCK_SETTLE_SECTORS = 3


def _hall_rocks_early(run: Run) -> Outcome:
    """The Hall code steps back early in a slow sector and forward again (a rotor rocking
    over a Hall boundary, or a line's glitch longer than a top-speed sector), each step
    ROCK_STEP top-speed sectors long, in a sector ROCK_SLOWER times a top-speed one; the
    rotor's next edge comes a whole sector after the first. No fault may result: the
    forward edge's interval is part of a sector and bounds no next edge. The Hall
    time-out had been set to 4 of it and tripped 7 ms before the rotor's next edge (a
    hunt: the paper motor at 500 rpm)."""
    per_rpm = sector_ticks_at(run.spec, 1.0)  # a sector's ticks x rpm
    top = per_rpm / float(run.spec.controller.speed_max_rpm)
    tim3 = run.machine.tim3
    counter = (tim3.arr + 1) * tim3.ticks_per_count()
    # at most half the Hall counter's range a sector
    rpm = max(float(run.spec.controller.speed_max_rpm) / ROCK_SLOWER, per_rpm / (counter / 2))
    held = round(ROCK_STEP * top)
    if per_rpm / rpm < 3 * held:
        run.turn(SETTLE_SECTORS + 4)
        return run.outcome(
            "Hall code rocks early in a slow sector",
            None,
            None,
            None,
            "no sector within half the Hall counter's range has room for the steps: braking"
            " at the default speed",
        )
    run.rpm = rpm
    note = f"at {rpm:.0f} rpm"
    run.turn(ROCK_SETTLE_SECTORS)
    before, code = run.edge_now()
    sector = run.sector_ticks()
    edge = run.machine.now
    run.board.set_hall(before, at=edge + held)
    run.board.set_hall(code, at=edge + 2 * held)
    run._due = edge + sector
    run.turn(2)  # the rotor's next edge, and one more sector
    return run.outcome(
        "Hall code rocks early in a slow sector",
        None,
        None,
        None,
        f"{note}: back {held / TICK_HZ * 1e3:.3g} ms after an edge, forward as long after,"
        f" the next edge {sector / TICK_HZ * 1e3:.3g} ms after the first",
    )


#: An overhauling load: the rotor's speed step a sector (x), the speed it is driven to
#: (x speed_max) and the sectors it holds there, the last OVERHAUL_CHECKS of them checked
OVERHAUL_STEP = 0.02
OVERHAUL_TOP = 3.0
OVERHAUL_HOLD = 6
OVERHAUL_CHECKS = 3


def _overhauling(run: Run) -> Outcome:
    """An overhauling load drives the rotor from 0.95 x speed_max up to OVERHAUL_TOP x,
    OVERHAUL_STEP a sector, and holds it there, on a bus of the spec's range where
    all-off rectifies at the held speed and not at twice the top one: OVER_SPEED at the
    first sector shorter than the top speed's, and from then on the safe state follows
    the rotor (the faulted port reads each interval): at the held speed the one the
    physics requires there. The port had taken every interval past twice the top
    speed's for a bounce and held the state of 2 x: all-off, rectifying, up to 3 x (a
    hunt: short_sector_5k_16p on 29.5 V)."""
    top = float(run.spec.controller.speed_max_rpm)
    # a bus where all-off rectifies at the held speed but not at twice the top one (the
    # old port's reading), within the spec's range where it allows, BUS_RANGE_INSIDE
    # inside it: a bus at bus_voltage_min exactly reads a code below the port's least
    # (its threshold is rounded up, so every code it takes is in the range) and latched
    # UNDER_VOLTAGE before the rotor had moved (dmax_above_start_2k25 and
    # outrunner20_3mh_5a, an odd-motor sweep of the scenarios)
    inv = run.spec.inverter
    bus_v = min(
        max(
            worst_line_emf_v(run.spec, 0.5 * (2 + OVERHAUL_TOP) * top),
            float(inv.bus_voltage_min_v) * (1 + BUS_RANGE_INSIDE),
        ),
        float(inv.bus_voltage_max_v) * (1 - BUS_RANGE_INSIDE),
    )
    run.board.set_bus_voltage(bus_v)
    run.rpm = 0.95 * top
    run.turn(SETTLE_SECTORS)
    cause = None
    while run.rpm < OVERHAUL_TOP * top:
        run.rpm = min(run.rpm * (1 + OVERHAUL_STEP), OVERHAUL_TOP * top)
        run.turn(1)
        if cause is None and run.rpm > top:
            cause = run.machine.now  # the edge that ends the first sector over speed
    run.turn(OVERHAUL_HOLD - OVERHAUL_CHECKS)
    for k in range(OVERHAUL_CHECKS):
        sector = run.sector_ticks()
        run.step(sector // 2, sector=sector)
        _check_safe_state(run, run.machine.now, bus_v, f"held at {run.rpm:.0f} rpm ({k + 1})")
    return run.outcome(
        "overhauling load past the top speed",
        "OVER_SPEED",
        cause,
        run.board.pwm_period_ticks(),
        f"from {0.95 * top:.0f} to {run.rpm:.0f} rpm ({OVERHAUL_TOP:g} x speed_max), "
        f"{OVERHAUL_STEP:.0%} a sector, bus {bus_v:g} V; the safe state checked at the held"
        " speed",
    )


def _over_speed(run: Run) -> Outcome:
    run.turn(SETTLE_SECTORS)
    run.rpm = 1.25 * float(run.spec.controller.speed_max_rpm)
    edges = []
    for _ in range(6):
        run.sector = (run.sector + 1) % 6
        run.board.set_hall(run.spec.hall.sequence[run.sector])
        edges.append(run.machine.now)
        run.machine.run_for(run.sector_ticks())
        if not run.machine.tim1.moe:
            break
    # the first edge ends the last sector at the old speed; the second the first short one
    cause = edges[1] if len(edges) > 1 else None
    run.run_until_tripped(2 * run.board.pwm_period_ticks())
    return run.outcome(
        "over-speed",
        "OVER_SPEED",
        cause,
        run.board.pwm_period_ticks(),
        "the rotor steps at 1.25 x controller.speed_max from one Hall edge on; latency from the"
        " first edge that ends a sector shorter than at speed_max",
    )


def clear_faults(run: Run) -> int:
    """main's clear (app_clear_request), run until main has answered; its answer (the
    faults left latched)."""
    machine = run.machine
    machine.write_symbol_u32("app_clear_request", 1)
    run.wait_for(
        lambda: machine.read_symbol_u32("app_clear_request") == 0,
        TICK_HZ // 1_000_000,
        "main did not answer the clear",
    )
    return machine.read_symbol_u32("app_clear_result")


def _kept_safe_since(run: Run, since: int, what: str) -> None:
    """A violation if any gate state since `since` is no safe state, or MOE is set now:
    a clear that re-armed into a cause."""
    tim1 = run.machine.tim1
    tim1.gates_at(run.machine.now)  # the record up to now
    for at, gates in tim1.gate_log or []:
        on = tuple(g is True for g in gates)
        if at >= since and on not in (ALL_OFF, SHORT_CIRCUIT):
            run.violations.append(f"gates {on} {(at - since) / TICK_HZ * 1e6:.2f} us {what}")
            return
    if tim1.moe:
        run.violations.append(f"MOE set {what}")


#: Ticks (72 MHz) after the clear's entry (port_clear_masked) at which a short
#: comparator pulse comes, one clear each: between the break pin's read and the arming
BREAK_IN_CLEAR_TICKS = (40, 100, 160)
#: ... and its width
BREAK_IN_CLEAR_NS = 100


def _break_during_clear(run: Run) -> Outcome:
    """A 5 us comparator pulse latches OVER_CURRENT; main clears it, and a
    BREAK_IN_CLEAR_NS pulse comes during the clear, BREAK_IN_CLEAR_TICKS after its entry
    (three clears in turn). Each pulse must be latched and the bridge stay off: the clear
    had cleared the break flag after it read the pin, erasing a pulse between, and armed
    the bridge into it (a hunt: the paper motor, +100 ticks)."""
    machine = run.machine
    period = run.board.pwm_period_ticks()
    run.board.set_bus_voltage(float(run.spec.inverter.bus_voltage_nominal_v))
    run.turn(SETTLE_SECTORS)
    run.into_sector(1 / 4)
    start = machine.now + 10
    run.board.set_break(True, at=start)
    run.board.set_break(False, at=start + round(5e-6 * TICK_HZ))
    run.run_until_tripped(period)
    machine.run_for(4 * period)
    entry = machine.symbol("port_clear_masked") & ~1
    width = round(BREAK_IN_CLEAR_NS * TICK_HZ / 1e9)
    for offset in BREAK_IN_CLEAR_TICKS:

        def pulse(_uc: object, _address: int, _size: int, _data: object, k: int = offset) -> None:
            at = machine._block_end + k
            run.board.set_break(True, at=at)
            run.board.set_break(False, at=at + width)

        hook = machine.uc.hook_add(UC_HOOK_CODE, pulse, None, entry, entry)
        try:
            clear_faults(run)
        finally:
            machine.uc.hook_del(hook)
        machine.run_for(3 * period)
        if machine.tim1.moe or not run.board.symbol("app_faults") & FAULT["OVER_CURRENT"]:
            run.violations.append(
                f"a {BREAK_IN_CLEAR_NS} ns comparator pulse {offset} ticks into the clear was"
                f" lost: MOE {int(machine.tim1.moe)}, faults"
                f" {run.board.symbol('app_faults'):#x}"
            )
            break
    return run.outcome(
        "comparator pulse during the clear",
        "OVER_CURRENT",
        None,
        None,
        f"OVER_CURRENT latched, then {len(BREAK_IN_CLEAR_TICKS)} clears, each with a"
        f" {BREAK_IN_CLEAR_NS} ns pulse {', '.join(map(str, BREAK_IN_CLEAR_TICKS))} ticks into it",
    )


def _break_while_faulted(run: Run) -> Outcome:
    """An over-current while another fault is latched: an over-voltage trips the drive,
    the bus comes back, then the comparator goes active and stays; main asks for the
    clear. The over-current must be latched as it comes (one PWM period), and the clear
    must keep the bridge off and answer OVER_CURRENT alone (the bus is back). The break
    interrupt had stayed off after the over-voltage's own break request: the over-current
    was latched by nobody, the clear answered 0 and armed the bridge into it (its
    re-armed break caught it 3 us later, all-off meanwhile where the short was due; a
    helper's hunt)."""
    nominal = float(run.spec.inverter.bus_voltage_nominal_v)
    period = run.board.pwm_period_ticks()
    run.board.set_bus_voltage(nominal)
    run.turn(SETTLE_SECTORS)
    run.into_sector(1 / 3)
    run.board.set_bus_voltage(1.1 * float(run.spec.inverter.bus_voltage_max_v))
    run.run_until_tripped(period)
    run.board.set_bus_voltage(nominal)
    run.machine.run_for(2 * period)
    cause = run.machine.now
    run.board.set_break(True)
    run.machine.run_for(period)
    over = FAULT["OVER_CURRENT"]
    run.wait_for(  # main publishes what the break handler latched at once
        lambda: (run.board.symbol("app_faults") & over) != 0,
        TICK_HZ // 1_000_000,
        "OVER_CURRENT was not latched",
    )
    answer = clear_faults(run)
    if answer != over:
        run.violations.append(f"the clear answered {answer:#x}, not OVER_CURRENT alone")
    run.machine.run_for(2 * period)
    _kept_safe_since(run, cause, "after the break, with a fault latched")
    return run.outcome(
        "over-current while faulted",
        "OVER_CURRENT",
        None,
        None,
        "an over-voltage latched, the bus back, then BKIN active and held; main clears: the"
        " over-current latched and the clear refused, the bridge off throughout",
    )


def _break_pulse(run: Run) -> Outcome:
    """A comparator pulse shorter than the break interrupt's entry (200 ns mid-sector):
    TIM1 clears MOE in hardware, and the handler found the input inactive by then and
    latched nothing, so the drive stopped with no fault and no clear re-armed it (a
    helper's hunt: up to 1.5 us at a Hall edge). A break no request explains is an
    over-current."""
    nominal = float(run.spec.inverter.bus_voltage_nominal_v)
    run.board.set_bus_voltage(nominal)
    run.turn(SETTLE_SECTORS)
    run.into_sector(1 / 3)
    cause = run.machine.now + 10
    width = round(200e-9 * TICK_HZ)
    run.board.set_break(True, at=cause)
    run.board.set_break(False, at=cause + width)
    period = run.board.pwm_period_ticks()
    run.run_until_tripped(period)
    return run.outcome(
        "BKIN pulse of 200 ns",
        "OVER_CURRENT",
        cause,
        period,
        "the comparator active for 200 ns mid-sector, shorter than the break interrupt's"
        " entry: MOE clears in hardware and the handler reads the input inactive",
    )


def _clear_where_all_off_rectifies(run: Run) -> Outcome:
    """A 5 us comparator pulse at a speed from which all-off rectifies (as the Hall back
    step's: the bus 1 % inside the range's bottom, the rotor 3 % above that speed), then
    main clears: the drive re-arms, and from the moment MOE is set again to the next Hall
    edge the gates are the idle state there, the short circuit, with no gap: MOE comes up
    into it. Arming had turned every switch off with MOE set until the next
    edge, rectifying (1.66 ms on the paper motor; a hunt), then for 2.7 us before the
    short (a 400 V motor; a hunt). Where no bus of the range rectifies at such a speed: at the default
    speed and nominal bus, all-off."""
    name = "clear where all-off rectifies"
    chosen = hall_back_step_speed(run.spec)
    if chosen is None:
        bus_v = float(run.spec.inverter.bus_voltage_nominal_v)
    else:
        bus_v, run.rpm = chosen
    run.board.set_bus_voltage(bus_v)
    run.turn(SETTLE_SECTORS)
    run.into_sector(1 / 4)
    cause = run.machine.now + 10
    run.board.set_break(True, at=cause)
    run.board.set_break(False, at=cause + round(5e-6 * TICK_HZ))
    period = run.board.pwm_period_ticks()
    run.run_until_tripped(period)
    run.machine.run_for(2 * period)
    if run.board.symbol("app_faults") != FAULT["OVER_CURRENT"]:
        return run.outcome(name, "OVER_CURRENT", cause, period, "the pulse latched no fault")
    # from the moment the clear sets MOE to the next edge: the idle state, no gap (main
    # wakes at its next interrupt, up to a PWM period after the request; the window had
    # begun a period after the request, and a clear that ran 51 us after it, all-off
    # with MOE set for 2.7 us before the short, fell inside only by that phase; before
    # MOE the fault's own state holds, which may be another: the hub prefers the short)
    requested = run.machine.now
    answer = clear_faults(run)
    if answer != 0:
        run.violations.append(f"the clear answered {answer:#x}, not 0")
    armed = run.machine.tim1.moe_set_at
    if armed is None or armed < requested:
        run.violations.append("the clear did not set MOE")
        armed = run.machine.now
    edge = run._due  # the sector's end: the next Hall edge
    start = armed
    if edge > start:
        run.machine.run_until(edge - 1)
        changes = [t for t, _ in run.machine.tim1.gate_log or [] if start < t < edge]
        for at in [start, *changes]:
            _check_safe_state(run, at, bus_v, "after the clear, before the next edge", idle=True)
    run.turn(3)  # braking again: each edge commutates
    return run.outcome(
        name,
        None,
        None,
        None,
        f"the comparator active for 5 us at {run.rpm:.0f} rpm on {bus_v:.2f} V, main's clear:"
        " the idle state from MOE set to the next edge, then braking",
    )


def _clear_over_speed(run: Run) -> Outcome:
    """main clears an over-speed while the rotor is still over speed: the clear must
    refuse (the interval the faulted drive keeps measuring is still short) and the safe
    state hold. It had re-armed: all-off with MOE set, which at 1.25 x speed_max
    rectifies into the bus, until the second edge tripped again (about 1.5 sectors; a
    helper's hunt)."""
    outcome = _over_speed(run)
    if outcome.faults != FAULT["OVER_SPEED"]:
        return replace(outcome, name="clear while over speed")
    since = run.machine.now
    answer = clear_faults(run)
    if answer != FAULT["OVER_SPEED"]:
        run.violations.append(f"the clear answered {answer:#x}, not OVER_SPEED")
    for _ in range(3):  # sectors on at the same speed, the faulted drive measuring them
        run.sector = (run.sector + 1) % 6
        run.board.set_hall(run.spec.hall.sequence[run.sector])
        run.machine.run_for(run.sector_ticks())
    _kept_safe_since(run, since, "after the clear at over-speed")
    bus = float(run.spec.inverter.bus_voltage_nominal_v)
    _check_safe_state(run, run.machine.now, bus, "three sectors after the clear")
    return run.outcome(
        "clear while over speed",
        "OVER_SPEED",
        None,
        None,
        "the over-speed scenario, then main clears with the rotor still at 1.25 x"
        " controller.speed_max: refused, the safe state kept for three sectors",
    )


#: the IWDG's 12-bit down counter: reload values 0..4095, so 4096 counts at most (RM0008 19.3.1)
IWDG_COUNTS = 4096


def _current_loop_stalls(run: Run) -> Outcome:
    """The watchdog guards the current loop: braking for longer than
    firmware.watchdog_timeout, it must not reset (the firmware refreshes it); then the
    ADC's injected trigger is lost (TIM1's TRGO no longer reaches ADC1: the current
    loop's interrupt stops), and it must reset within firmware.watchdog_timeout (the LSI
    runs at its fastest here, so the firmware's time-out is the spec's, rounded up to
    the IWDG's count: one count of the finest prescaler whose 12-bit reload reaches the
    time-out, 0.53 ms for 1.1 s, where the check had allowed one PWM period; a hunt)."""
    timeout = round(float(run.spec.firmware.watchdog_timeout_s) * TICK_HZ)
    lsi = run.machine.iwdg.lsi_hz
    divider = 4
    while Fraction(run.spec.firmware.watchdog_timeout_s) * lsi / divider > IWDG_COUNTS:
        divider *= 2
    count = -(-divider * TICK_HZ // lsi)
    run.turn(SETTLE_SECTORS)
    while run.machine.now - run.start < 1.2 * timeout:
        run.turn(1)
    alive = run.outcome(
        "current loop stalls",
        None,
        None,
        None,
        "braking for 1.2 x firmware.watchdog_timeout, then the ADC's injected trigger lost:"
        " the watchdog resets the chip within firmware.watchdog_timeout",
    )
    adc1 = run.machine.adc1
    run.machine.tim1.trgo_listeners.remove(adc1._tim1_trgo)
    stalled = run.machine.now
    reset = None
    try:
        while run.machine.now - stalled <= timeout + count + run.board.pwm_period_ticks():
            run.turn(1)
    except WatchdogResetError:
        reset = run.machine.now
    extra = []
    if reset is None:
        extra.append(
            f"no watchdog reset within {timeout} ticks (firmware.watchdog_timeout) and one"
            f" IWDG count ({count} ticks) of the current loop's stall"
        )
    else:
        # and not sooner than the spec's time-out after the last refresh, even at the
        # fastest LSI: a watchdog sized at the slowest (30 kHz) reset after half of it
        last = max((t for t in run.machine.iwdg.refresh_log if t <= reset), default=stalled)
        if reset - last < timeout:
            extra.append(
                f"the watchdog reset {reset - last} ticks after its last refresh, sooner than"
                f" firmware.watchdog_timeout ({timeout} ticks) at the fastest LSI"
            )
    return replace(alive, violations=alive.violations + tuple(extra))


#: A second reversal at this fraction of the speed range: where the rule's turn-off
#: switch is modulated (D_off > 0, the paper's low-speed segment), a reverse edge that
#: hands a leg over from its PWM switch to the other in one COM event is a shoot-through
REVERSAL_LOW_FRACTION = 0.2


def _reversal(run: Run) -> Outcome:
    """The rotor turns back (it oscillates as it stops, or is driven backwards): after
    the settling sectors it turns back half-way into a sector (its code steps back a
    sector's time after the last edge), then on backwards. A reverse edge is valid (no
    fault), but a phase whose other switch is on
    now must not hand over from one switch to the other in one COM event: TIM1 inserts
    no dead time between the two outputs of a channel enabled one at a time (RM0008
    Table 83), so the gate invariant sees it. The refused edge leaves the idle state of
    the speed and bus (`required_idle_state`: all-off where it does not rectify, whatever
    the spec prefers)."""
    low = float(run.spec.controller.speed_min_rpm)
    high = float(run.spec.controller.speed_max_rpm)
    bus_v = float(run.spec.inverter.bus_voltage_nominal_v)
    for rpm in (run.rpm, low + REVERSAL_LOW_FRACTION * (high - low)):
        run.rpm = rpm
        # half a sector on and back again: the reverse edge a sector after the last one
        # (held for half a sector more, a narrow speed range's slowest sectors reached
        # TIM3's wrap, and the Hall timed out)
        run.turn(SETTLE_SECTORS)
        for step in range(6):
            run.sector = (run.sector - 1) % 6
            run.board.set_hall(run.spec.hall.sequence[run.sector])
            back = run.machine.now
            run.machine.run_for(run.sector_ticks())
            if step == 0:  # refused: the safe state of the speed and bus, MOE set
                _check_safe_state(
                    run,
                    back + run.board.pwm_period_ticks(),
                    bus_v,
                    "one PWM period after the code stepped back",
                    idle=True,
                )
    return run.outcome(
        "direction reversal",
        None,
        None,
        None,
        "the rotor turns back half-way into a sector and on backwards for six"
        f" sectors, at the scenarios' speed and at {REVERSAL_LOW_FRACTION:g} of the speed"
        " range, each after turning forwards again: no fault, the idle state one PWM"
        " period after the first reverse edge, no switch-over within a leg without the dead"
        " time",
    )


#: The Hall code steps back one sector and forward again (below): each of its two
#: intervals this much longer than a sector at controller.speed_max, so that neither edge
#: is an over-speed (a glitch shorter than that sector trips OVER_SPEED at its forward
#: edge: a fault of its own, as a bounce does)
BACK_STEP_MARGIN = 0.02
#: The bus over the first half of the step back: this much above the one the scenario
#: brakes on, above the rectifying bound at its speed (RECTIFYING_MARGIN above it), as
#: the port may read that speed (`back_step_bus_rise`)


def back_step_bus_rise(spec: Spec) -> float:
    """How far the bus is above the back step's for its first half: RECTIFYING_MARGIN
    above the worst motor's line EMF at the speed the port may read (`Corner.said` x the
    rotor's, itself RECTIFYING_MARGIN above the bus's rectifying speed)."""
    return corner(spec).said * (1 + RECTIFYING_MARGIN) ** 2 - 1


def hall_back_step_speed(spec: Spec) -> tuple[float, float] | None:
    """A bus voltage BUS_RANGE_INSIDE above the bottom of the spec's range (where all-off
    rectifies from the lowest speed) and a speed RECTIFYING_MARGIN above the one from
    which it does: (bus V, rpm), where that speed is inside the controller's range with
    a sector 2 x BACK_STEP_MARGIN longer than one at speed_max (room for the step back
    late in it); None where there is none."""
    bus_v = float(spec.inverter.bus_voltage_min_v) * (1 + BUS_RANGE_INSIDE)
    rpm = bus_v / worst_line_emf_v(spec, 1.0) * (1 + RECTIFYING_MARGIN)
    lowest = float(spec.controller.speed_min_rpm) * (1 + SPEED_RANGE_INSIDE)
    if not lowest <= rpm <= float(spec.controller.speed_max_rpm) / (1 + 2 * BACK_STEP_MARGIN):
        return None
    return bus_v, rpm


def _hall_back_step(run: Run) -> Outcome:
    """The Hall code steps back one sector late in a sector and, an interval later,
    forward again (a line's glitch, or a rotor that cannot reverse at this speed), at a
    speed from which all-off rectifies into the bus. The port refuses the back step
    (a phase would hand over from one switch to the other in one COM event): no fault,
    MOE stays set, and from one PWM period after the back step to the forward edge the
    gates are the idle state at the rotor's speed and bus (`required_idle_state`: the
    short circuit where all-off rectifies, else all-off, whatever the spec prefers;
    where no bus of the range rectifies at a speed with room for the step, the glitch
    comes at the default speed and nominal bus: all-off there); the
    forward edge commutates and braking goes on, no fault, the dead time kept at every
    gate change. The firmware had turned every switch off (a hunt: the paper motor at
    4600 rpm on 20.5 V, rectifying until the forward edge). Each interval is
    BACK_STEP_MARGIN longer than a sector at speed_max, at least two PWM periods."""
    name = "Hall code steps back and forward again"
    chosen = hall_back_step_speed(run.spec)
    if chosen is None:
        bus_v = float(run.spec.inverter.bus_voltage_nominal_v)
        note = (
            "no bus voltage of the spec's range rectifies at a speed with room for the step"
            " back: at the default speed and the nominal bus"
        )
    else:
        bus_v, run.rpm = chosen
        note = _rectifying_note(run, bus_v)
    run.board.set_bus_voltage(bus_v)
    run.turn(SETTLE_SECTORS)
    machine, tim1 = run.machine, run.machine.tim1
    period = run.board.pwm_period_ticks()
    top = sector_ticks_at(run.spec, float(run.spec.controller.speed_max_rpm))
    held = round((1 + BACK_STEP_MARGIN) * top)
    before, code = run.edge_now()
    sector = run.sector_ticks()
    back = machine.now + max(held, sector // 2)
    forward = back + max(held, 2 * period)
    run.board.set_hall(before, at=back)
    run.board.set_hall(code, at=forward)
    run._due = forward + sector  # the forward edge starts the sector again
    # a bus above the rectifying bound until half-way through the step, then at bus_v
    # (all-off rectifies): the idle state follows it (a hunt: all-off, chosen once at
    # the back step, had rectified until the forward edge)
    high = bus_v * (1 + back_step_bus_rise(run.spec))
    falls = chosen is not None and high <= float(run.spec.inverter.bus_voltage_max_v)
    fall = (back + forward) // 2 if falls else back
    if falls:
        run.board.set_bus_voltage(lambda tick: high if tick < fall else bus_v)
    machine.run_until(forward)
    # the idle state follows the bus at the current loop's samples: the first one after
    # the fall ends at most a PWM period and its conversions later (2 periods allowed)
    for start, end, volts in ((back + period, fall, high), (fall + 2 * period, forward, bus_v)):
        if start >= end:
            continue
        changes = [t for t, _ in tim1.gate_log or [] if start < t < end]
        for at in [start, *changes]:
            _check_safe_state(run, at, volts, "after the Hall code stepped back", idle=True)
    # what the gates held up to the forward edge, and since when
    kept = _gates_in_force(run, forward - 1)
    since, previous = back, None
    for at, gates in tim1.gate_log or []:
        on = tuple(g is True for g in gates)
        if back <= at < forward and on == kept and previous != kept:
            since = at
        previous = on
    refused = tim1.ccer
    run._finish_sector()
    if not tim1.moe or tim1.ccer == refused:
        run.violations.append("the forward edge did not commutate: the bridge no longer brakes")
    run.turn(4)  # each edge must commutate (`step`)
    held_name = {SHORT_CIRCUIT: "the short circuit", ALL_OFF: "all-off"}.get(kept, "switching")
    return run.outcome(
        name,
        None,
        back,
        None,
        f"{note}; the code back one sector {max(held, sector // 2) / TICK_HZ * 1e6:.0f}"
        f" us into a {sector / TICK_HZ * 1e6:.0f} us sector, forward again"
        f" {(forward - back) / TICK_HZ * 1e6:.0f} us later: {held_name} from"
        f" {(since - back) / TICK_HZ * 1e6:.2f} us after the back step to the forward edge",
    )


def _hse_fails(run: Run) -> Outcome:
    run.machine.run_for(run.board.pwm_period_ticks() * 20)
    if run.machine.tim1.moe or run.machine.tim1.moe_cleared_at is not None:
        run.violations.append("the bridge was armed on the HSI")
    return run.outcome(
        "HSE fails to start",
        "CLOCK",
        None,
        None,
        "the crystal never starts: the bridge is never armed (no latency: MOE never set)",
    )


def _hse_fails_running(run: Run) -> Outcome:
    """The crystal stops while the bridge brakes: the clock security system switches
    SYSCLK to the HSI (8 MHz, a ninth of the PLL's 72 MHz: every timer slows as much)
    and raises the NMI, whose handler must reach the safe state within one PWM period
    of the failure, the spec's safe state at the run's speed and bus."""
    run.turn(SETTLE_SECTORS - 1)
    run.into_sector(1 / 3)
    cause = run.next_update() + run.board.pwm_period_ticks() // 3
    run.machine.rcc.fail_hse(cause)
    run.run_until_tripped(20 * run.board.pwm_period_ticks())
    cleared = run.machine.tim1.moe_cleared_at
    if cleared is not None:  # TIM1's break takes the clock failure (RM0008 7.2.7)
        # the dead time at the clock TIM1 runs on now: the HSI's 8 MHz, a ninth of the
        # PLL's, so the lower switches close nine dead times (at 72 MHz) after the break
        dead = run.machine.tim1.dead_time_ticks()
        bus = float(run.spec.inverter.bus_voltage_nominal_v)
        whole = cleared + run.board.pwm_period_ticks()
        _check_safe_state(run, cleared + dead + 1, bus, "after the dead time", complete_by=whole)
    return run.outcome(
        "HSE fails while braking",
        "CLOCK",
        cause,
        run.board.pwm_period_ticks(),
        "the crystal stops a third of a PWM period after an update while the bridge"
        " brakes: the CSS moves SYSCLK to the HSI and raises the NMI",
    )


@dataclass(frozen=True)
class Scenario:
    key: str
    run: Callable[[Run], Outcome]
    hse_fails: bool = False
    #: the cause comes before the bridge switches (no current sample to check)
    before_switching: bool = False


SCENARIOS = (
    Scenario("over_voltage", _over_voltage),
    Scenario("over_voltage_between_samples", _over_voltage_between_samples),
    Scenario("under_voltage", _under_voltage),
    Scenario("under_voltage_at_start", _under_voltage_at_start, before_switching=True),
    Scenario("break_after_the_first_edge", _break_after_the_first_edge),
    Scenario("break_input", _break_input),
    Scenario("below_rectifying", _below_rectifying),
    Scenario("above_rectifying", _above_rectifying),
    Scenario("below_short_rating", _below_short_rating),
    Scenario("above_short_rating", _above_short_rating),
    Scenario("bus_falls_while_faulted", _bus_falls_while_faulted),
    Scenario("hall_unplugged", _hall_unplugged),
    Scenario("hall_glitch", _hall_glitch),
    Scenario("hall_spike", _hall_spike),
    Scenario("hall_off_marks", _hall_off_marks),
    Scenario("current_sensor_low", _current_sensor_low),
    Scenario("current_sensor_high", _current_sensor_high),
    Scenario("hall_sequence", _hall_sequence),
    Scenario("hall_line_stuck", _hall_line_stuck),
    Scenario("hall_bounce", _hall_bounce),
    Scenario("hall_glitch_late", _hall_glitch_late),
    Scenario("hall_unplugged_bouncing", _hall_unplugged_bouncing),
    Scenario("hall_rocks_early", _hall_rocks_early),
    Scenario("over_speed", _over_speed),
    Scenario("overhauling", _overhauling),
    Scenario("clear_over_speed", _clear_over_speed),
    Scenario("break_while_faulted", _break_while_faulted),
    Scenario("break_during_clear", _break_during_clear),
    Scenario("break_pulse", _break_pulse),
    Scenario("rotor_stops", _rotor_stops),
    Scenario("hardest_braking", _hardest_braking),
    Scenario("bus_stuck_at_zero", _bus_stuck_at_zero),
    Scenario("bus_stuck_at_full_scale", _bus_stuck_at_full_scale),
    Scenario("reversal", _reversal),
    Scenario("hall_back_step", _hall_back_step),
    Scenario("clear_where_all_off_rectifies", _clear_where_all_off_rectifies),
    Scenario("bus_noise", _bus_noise),
    Scenario("current_loop_stalls", _current_loop_stalls),
    Scenario("hse_fails", _hse_fails, hse_fails=True),
    Scenario("hse_fails_running", _hse_fails_running),
)


def run_scenario(elf: Path, spec: Spec, scenario: Scenario) -> Outcome:
    """One scenario; a hard fault or a watchdog reset is an outcome, not an exception."""
    try:
        run = Run(elf, spec, hse_fails=scenario.hse_fails)
    except (PilError, WatchdogResetError, TimeoutError) as error:
        return _broken(scenario, spec, f"boot: {error}")
    try:
        return scenario.run(run)
    except (PilError, WatchdogResetError) as error:
        run.violations.append(f"{type(error).__name__}: {error}")
        return run.outcome(scenario.key, "never", None, None, "aborted")


def _broken(scenario: Scenario, spec: Spec, why: str) -> Outcome:
    return Outcome(scenario.key, "never", 0, None, None, (why,), 0, 1, 0.0, 0.0, 0.0, "aborted")

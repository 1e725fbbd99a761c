"""The drive firmware for spec/paper_motor.yaml, as `make firmware` links it, runs on the
emulated STM32F103 from its reset vector: clock tree, port init, then the interrupts.

The yardsticks come from the spec (PWM frequency, clock, sensing chain, break polarity)
and the fault API (codegen/port_faults.py), never from the firmware's own constants."""

from __future__ import annotations

import subprocess
import sys
from itertools import pairwise
from pathlib import Path

import pytest

from codegen.port_faults import FAULTS
from codegen.spec_loader import load_spec
from codegen.spec_model import Spec
from emulation.pil.machine import MachineOptions
from emulation.pil.rcc import TICK_HZ
from emulation.pil.runner import DriveBoard
from emulation.pil.safe_state import short_rated_speed
from emulation.pil.tim1 import gate_violations

ROOT = Path(__file__).resolve().parents[1]
SPEC = ROOT / "spec" / "paper_motor.yaml"
FAULT = {f.name: f.value for f in FAULTS}


@pytest.fixture(scope="module")
def spec() -> Spec:
    return load_spec(str(SPEC))


@pytest.fixture(scope="module")
def elf(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """`make firmware SPEC=spec/paper_motor.yaml`'s command, into a temporary build folder."""
    build = tmp_path_factory.mktemp("firmware")
    subprocess.run(
        [sys.executable, "-m", "codegen", "firmware", str(SPEC), "--build", str(build)],
        check=True,
        cwd=ROOT,
        capture_output=True,
    )
    return build / "firmware.elf"


def booted(elf: Path, spec: Spec, **options: object) -> DriveBoard:
    board = DriveBoard(
        elf,
        spec,
        MachineOptions(vref=float(spec.adc.reference_v), **options),  # type: ignore[arg-type]
    )
    board.boot()
    return board


def test_the_clock_should_reach_72mhz_with_two_flash_wait_states(elf: Path, spec: Spec) -> None:
    board = booted(elf, spec)
    machine = board.machine
    assert machine.rcc.sysclk_hz == 72_000_000 == machine.rcc.timer_hz(2)
    assert machine.flash.latency == 2 and machine.flash.acr & 0x10  # prefetch on
    assert machine.rcc.cr & (1 << 19)  # CSS on once the PLL runs
    assert board.symbol("app_faults") == 0 and machine.tim1.moe  # armed, no fault
    # booted within the HSE start-up, the PLL lock and a few ms of set-up
    assert machine.now < 5 * TICK_HZ // 1000


def test_tim1_should_run_at_the_spec_pwm_frequency(elf: Path, spec: Spec) -> None:
    board = booted(elf, spec)
    tim1 = board.machine.tim1
    period_ticks = tim1.cycle_counts() * tim1.ticks_per_count()
    assert period_ticks == TICK_HZ / spec.inverter.pwm_frequency_hz
    updates = tim1.update_count
    board.run_seconds(0.005)
    per_period = 2 if tim1.centre_aligned else 1
    assert tim1.update_count - updates == pytest.approx(
        0.005 * float(spec.inverter.pwm_frequency_hz) * per_period, abs=1
    )


def test_the_current_loop_should_run_once_per_pwm_period(elf: Path, spec: Spec) -> None:
    board = booted(elf, spec)
    start = board.machine.now
    board.run_seconds(0.01)
    entries = [t for t in board.entries_of("ADC1", "ADC") if t >= start]
    gaps = {b - a for a, b in pairwise(entries)}
    assert gaps == {board.pwm_period_ticks()}
    assert len(entries) == pytest.approx(0.01 * float(spec.inverter.pwm_frequency_hz), abs=1)


def test_the_break_input_should_clear_moe_and_latch_over_current(elf: Path, spec: Spec) -> None:
    board = booted(elf, spec)
    machine = board.machine
    board.run_seconds(0.001)
    board.set_break(True)
    tripped = machine.now
    assert not machine.tim1.moe and machine.tim1.moe_cleared_at == tripped  # hardware, at once
    board.run_seconds(0.001)
    assert board.symbol("app_faults") == FAULT["OVER_CURRENT"]
    dead = machine.tim1.dead_time_ticks()
    # no Hall edge since start-up: the speed unknown to the port, the short circuit, which
    # the paper motor's bridge is rated for at every speed of its range, for the worst
    # motor its tolerances declare (all-off would rectify into the bus if the rotor
    # turned fast); the PIL's own bound, not the port's constant
    rated = short_rated_speed(spec)
    assert rated is None or rated >= float(spec.controller.speed_max_rpm)
    assert machine.tim1.gates(tripped + dead) == (False, True) * 3
    board.set_break(False)
    board.run_seconds(0.001)
    assert board.symbol("app_faults") == FAULT["OVER_CURRENT"] and not machine.tim1.moe  # latched
    machine.write_symbol_u32("app_clear_request", 1)
    board.run_seconds(0.001)
    assert board.symbol("app_clear_result") == 0 and board.symbol("app_faults") == 0
    assert machine.tim1.moe


def _next_update(board: DriveBoard) -> int:
    tim1 = board.machine.tim1
    counts = tim1.cycle_counts() - tim1.position(board.machine.now) % tim1.cycle_counts()
    return board.machine.now + counts * tim1.ticks_per_count()


def _over_voltage_step(board: DriveBoard, spec: Spec) -> int:
    """The bus steps 10 % above inverter.bus_voltage_max at the next PWM period start."""
    step = _next_update(board)
    nominal = float(spec.inverter.bus_voltage_nominal_v)
    high = 1.1 * float(spec.inverter.bus_voltage_max_v)
    board.set_bus_voltage(lambda tick: high if tick >= step else nominal)
    return step


def test_an_over_voltage_should_reach_the_safe_state_within_a_pwm_period(
    elf: Path, spec: Spec
) -> None:
    board = booted(elf, spec)
    machine = board.machine
    board.run_seconds(0.001)
    step = _over_voltage_step(board, spec)
    board.run_seconds(0.0005)
    assert not machine.tim1.moe
    latency = machine.tim1.moe_cleared_at - step
    assert 0 < latency <= board.pwm_period_ticks()
    assert machine.adc1.sr & 1 or board.symbol("app_faults") & FAULT["OVER_VOLTAGE"]
    assert board.symbol("app_faults") & FAULT["OVER_VOLTAGE"]


def test_an_over_voltage_should_latch_over_voltage_alone(elf: Path, spec: Spec) -> None:
    """Once a port bug: the bus steps at the period start, where TIM1 also triggers the
    injected sequence, which resets the regular conversion (RM0008 11.3.9); the
    watchdog flags the first injected bus conversion (JSQ2) before JDR4 is written, and
    the classification read DR and JDR4 only, both from before the step: UNDER_VOLTAGE
    was latched for an over-voltage. It now reads every JDRx of the bus."""
    board = booted(elf, spec)
    machine = board.machine
    board.run_seconds(0.001)
    _over_voltage_step(board, spec)
    while machine.tim1.moe:
        machine.run_for(10)
    # the handlers end (the trip's, the bus change's and its backstop's), main refreshes
    # app_faults: within a few PWM periods
    for _ in range(4):
        machine.run_for(board.pwm_period_ticks())
        if board.symbol("app_faults"):
            break
    assert board.symbol("app_faults") == FAULT["OVER_VOLTAGE"]


def test_the_watchdog_should_never_starve(elf: Path, spec: Spec) -> None:
    """The fastest LSI (60 kHz) starves first; 1000 PWM periods with the loop running."""
    board = booted(elf, spec, lsi_hz=60_000)
    machine = board.machine
    start = machine.now
    board.run_seconds(1000 / float(spec.inverter.pwm_frequency_hz))
    refreshes = [t for t in machine.iwdg.refresh_log if t >= start]
    gaps = [b - a for a, b in pairwise(refreshes)]
    assert len(refreshes) >= 999
    assert max(gaps) < machine.iwdg.timeout_ticks() / 4


def test_the_watchdog_should_count_the_specs_timeout_from_its_start(elf: Path, spec: Spec) -> None:
    """From the firmware's first sleep on, the running count is the one of the spec's
    firmware.watchdog_timeout: at most the time-out at the fastest LSI and at least it
    (RM0008 19.4.4: a reload issued while RVU is set loads the reset value, 4096 x 4 LSI
    cycles, 273 ms: the firmware reloaded before the new RLR had arrived until this was
    found, so a hang before main's first refresh after the update took 273 ms, not 20)."""
    for lsi_hz in (30_000, 60_000):
        board = booted(elf, spec, lsi_hz=lsi_hz)
        iwdg = board.machine.iwdg
        assert iwdg.running and iwdg.expires_at is not None and iwdg.last_reload is not None
        counting = (iwdg.expires_at - iwdg.last_reload) / TICK_HZ
        timeout = float(spec.firmware.watchdog_timeout_s)
        assert timeout <= counting * lsi_hz / 60_000 <= timeout * 1.01, (lsi_hz, counting)


def test_a_hse_that_never_starts_should_latch_the_clock_fault(elf: Path, spec: Spec) -> None:
    board = booted(elf, spec, hse_fails=True)
    machine = board.machine
    board.run_seconds(0.001)
    assert machine.rcc.sysclk_hz == 8_000_000  # stayed on the HSI
    assert board.symbol("app_faults") & FAULT["CLOCK"] and not machine.tim1.moe
    # it waited the spec's HSE time-out before giving up
    assert machine.now > spec.firmware.hse_startup_timeout_s * TICK_HZ


def test_an_invalid_hall_code_on_one_edge_should_reach_the_safe_state(
    elf: Path, spec: Spec
) -> None:
    board = booted(elf, spec)
    sector = board.turn(3000, 7)
    while bin(spec.hall.sequence[sector]).count("1") != 2:
        sector = board.turn(3000, 1, sector)
    board.set_hall(7)  # one line rises: a TI1 edge
    unplugged = board.machine.now
    board.run_seconds(0.0005)
    assert board.symbol("app_faults") & FAULT["HALL_INVALID"]
    assert board.machine.tim1.moe_cleared_at - unplugged <= board.pwm_period_ticks()


def test_two_hall_lines_rising_together_should_reach_the_safe_state(elf: Path, spec: Spec) -> None:
    """Once a port bug: TIM3 sees the Hall lines only through TI1 = CH1 xor CH2 xor CH3;
    two lines changing within the input filter (an unplugged connector pulling two
    lines up) make no TI1 edge, so code 7 went unseen until HALL_TIMEOUT. The current
    loop's interrupt now tests the pins for 0 and 7 every PWM period."""
    board = booted(elf, spec)
    sector = board.turn(3000, 7)
    while bin(spec.hall.sequence[sector]).count("1") != 1:
        sector = board.turn(3000, 1, sector)
    board.set_hall(7)
    unplugged = board.machine.now
    board.run_seconds(0.001)
    assert board.symbol("app_faults") & FAULT["HALL_INVALID"]
    assert board.machine.tim1.moe_cleared_at - unplugged <= board.pwm_period_ticks()


def test_the_bridge_should_never_shoot_through_nor_cut_the_dead_time(elf: Path, spec: Spec) -> None:
    """Braking at 3000 rpm, then a break: every gate edge logged. The current read stays
    below the reference (no plant yet), so the loop drives the duty up and switches."""
    board = booted(elf, spec)
    board.set_current(float(spec.controller.braking_current_nominal_a) / 2)
    machine = board.machine
    machine.tim1.record_gates()
    sector = board.turn(3000, 12)
    board.set_break(True)
    board.turn(3000, 2, sector)
    log = machine.tim1.gate_log
    assert log is not None and len(log) > 1000  # it switched
    dead = round(spec.inverter.dead_time_s * TICK_HZ)
    assert gate_violations(log, dead) == []
    assert not machine.tim1.moe


def test_a_lasting_over_voltage_should_not_starve_the_watchdog(elf: Path, spec: Spec) -> None:
    """Once a port bug (the ADC interrupt returned before ++heartbeat on the watchdog
    path, so main stopped refreshing the IWDG): the final port counts first, and turns
    the analog watchdog's interrupt off from the trip until the fault is cleared."""
    board = booted(elf, spec, lsi_hz=60_000)
    board.set_current(float(spec.controller.braking_current_nominal_a) / 2)
    board.turn(3000, 6)
    board.set_bus_voltage(1.1 * float(spec.inverter.bus_voltage_max_v))
    board.run_seconds(3 * float(spec.firmware.watchdog_timeout_s))
    assert board.symbol("app_faults") & FAULT["OVER_VOLTAGE"]


def test_a_50khz_firmware_should_be_found_asleep_after_its_boot(tmp_path: Path) -> None:
    """The boot runs until main's first WFI. It used to look for a sleep at the end of
    each 100 us step: on a 50 kHz PWM every step ended just after the current loop's
    interrupt, with main awake, and this 100 000 rpm fixture timed out its boot (every
    PIL scenario and the braking run failed). The first WFI is counted now, and the
    firmware then sleeps most of a PWM period."""
    from emulation.pil.build import build_firmware, generate

    fixture = ROOT / "tests" / "fixtures" / "pil" / "pp1_100k_ir_centre.yaml"
    elf = build_firmware(fixture, tmp_path, generate(fixture, tmp_path / "generated"))
    board = booted(elf, load_spec(str(fixture)))
    machine = board.machine
    assert machine.sleeps >= 1
    period = TICK_HZ // 50_000
    asleep = 0
    for _ in range(200):  # 200 samples a fifth of a period apart: main mostly asleep
        machine.run_for(period // 5 + 1)
        asleep += machine.sleep_pc is not None
    assert asleep > 100, asleep

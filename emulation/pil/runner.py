"""The drive firmware on the emulated chip, with the board's inputs set by the caller.

`DriveBoard` wires what the spec says the board has to the emulated pins and ADC
channels: the Hall sensors on TIM3's CH1..CH3 pins (PA6, PA7, PB0 carry Hall A, B, C,
code bits 2, 1, 0: the port's pin table, codegen/port.py), the over-current comparator
on BKIN (PB12) with the spec's polarity, the DC-link current and the bus voltage on the
spec's ADC channels through its sensing chain (adc.current_offset + current_gain x I;
U / bus_voltage_divider). The plant coupling (gate signals into the motor model,
rotor angle into the Hall pins) is a later layer; here the caller sets each input.

The machine records the tick of every handler entry (`Machine.entry_log`) and of every
watchdog refresh (`Iwdg.refresh_log`).
"""

from __future__ import annotations

from collections.abc import Callable
from fractions import Fraction
from pathlib import Path

from codegen.spec_model import Spec
from emulation.pil.bus import svd_interrupt
from emulation.pil.machine import Machine, MachineOptions, load_firmware
from emulation.pil.rcc import TICK_HZ
from emulation.pil.scs import IRQ_BASE

HALL_PINS = (("gpioa", 6, 2), ("gpioa", 7, 1), ("gpiob", 0, 0))  # port, pin, code bit
BREAK_PIN = ("gpiob", 12)
#: Boot time allowed beyond firmware.hse_startup_timeout, which the firmware waits out in
#: full for a crystal that never starts (up to 1 s: a limit of 1/10 s alone failed the
#: HSE-fails scenario of a spec with the longest time-out it may have)
BOOT_LIMIT_S = Fraction(1, 10)


class DriveBoard:
    def __init__(self, elf: str | Path, spec: Spec, options: MachineOptions | None = None) -> None:
        self.spec = spec
        self.options = options or MachineOptions(vref=float(spec.adc.reference_v))
        self.machine = Machine(load_firmware(elf), self.options)
        self.set_hall(spec.hall.sequence[0])
        self.set_break(False)
        self.set_bus_voltage(float(spec.inverter.bus_voltage_nominal_v))
        self.set_current(0.0)

    def entries_of(self, peripheral: str, interrupt: str) -> list[int]:
        """Ticks at which the handler of an SVD interrupt was entered."""
        exception = IRQ_BASE + svd_interrupt(peripheral, interrupt)
        return [tick for tick, e in self.machine.entry_log if e == exception]

    # ------------------------------------------------------------------ inputs
    def set_hall(self, code: int, at: int | None = None) -> None:
        """The Hall code now, or from tick `at` exactly (`Gpio.drive_at`)."""
        for port, pin, bit in HALL_PINS:
            gpio = getattr(self.machine, port)
            if at is None:
                gpio.drive(pin, bool(code >> bit & 1))
            else:
                gpio.drive_at(pin, bool(code >> bit & 1), at)

    def set_break(self, over_current: bool, at: int | None = None) -> None:
        """The comparator's output: active (over-current) or idle, at the spec's polarity;
        now, or from tick `at` exactly (`Gpio.drive_at`)."""
        active_level = self.spec.protection.break_polarity == "active_high"
        port, pin = BREAK_PIN
        level = active_level if over_current else not active_level
        if at is None:
            getattr(self.machine, port).drive(pin, level)
        else:
            getattr(self.machine, port).drive_at(pin, level, at)

    def set_bus_voltage(self, volts: float | Callable[[int], float]) -> None:
        divider = float(self.spec.adc.bus_voltage_divider)
        channel = self.spec.sensing.bus_voltage_channel
        if callable(volts):
            source = volts
            self.machine.adc1.set_input(channel, lambda tick: source(tick) / divider)
        else:
            self.machine.adc1.set_input(channel, volts / divider)

    def set_current(self, amps: float | Callable[[int], float]) -> None:
        offset = float(self.spec.adc.current_offset_v)
        gain = float(self.spec.adc.current_gain_v_per_a)
        if callable(amps):
            source = amps

            def volts(tick: int) -> float:
                return offset + gain * source(tick)

            for channel in self.spec.sensing.current_channels:
                self.machine.adc1.set_input(channel, volts)
        else:
            for channel in self.spec.sensing.current_channels:
                self.machine.adc1.set_input(channel, offset + gain * amps)

    # ------------------------------------------------------------------ running
    def boot(self) -> int:
        """Run from reset until main's loop first sleeps (WFI); the tick it did."""
        allowed = BOOT_LIMIT_S + self.spec.firmware.hse_startup_timeout_s
        limit = self.machine.now + int(allowed * TICK_HZ)
        step = TICK_HZ // 10_000
        # the first WFI counted, not a sleep seen at a step's end: with a 50 kHz PWM the
        # 100 us steps fell each time just after the current loop's interrupt, with main
        # awake, and a booted 100 000 rpm motor timed out its boot
        while self.machine.sleeps == 0:
            if self.machine.now >= limit:
                raise TimeoutError(
                    f"the firmware did not reach its WFI within {float(allowed):g} s"
                    f" ({float(BOOT_LIMIT_S):g} s after firmware.hse_startup_timeout)"
                )
            self.machine.run_for(step)
        return self.machine.now

    def run_seconds(self, seconds: float) -> None:
        self.machine.run_for(round(seconds * TICK_HZ))

    def turn(self, rpm: float, sectors: int, start_sector: int = 0) -> int:
        """Step the Hall code through `sectors` 60-degree sectors forward (hall.sequence)
        at a constant `rpm`, one pin changing per edge; returns the sector reached (the
        code is held for a whole sector after each step)."""
        pole_pairs = self.spec.motor.poles // 2
        sector_ticks = round(TICK_HZ * 60 / (rpm * pole_pairs * 6))
        sector = start_sector
        for _ in range(sectors):
            sector = (sector + 1) % 6
            self.set_hall(self.spec.hall.sequence[sector])
            self.machine.run_for(sector_ticks)
        return sector

    def pwm_period_ticks(self) -> int:
        return round(TICK_HZ / self.spec.inverter.pwm_frequency_hz)

    def symbol(self, name: str) -> int:
        return self.machine.read_symbol_u32(name)

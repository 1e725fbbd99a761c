"""GPIO ports (RM0008 section 9).

* 9.2.1/9.2.2 CRL, CRH: four bits per pin, MODE[1:0] (00 input, else output speed) and
  CNF[1:0] (input: 00 analog, 01 floating, 10 pull-up/down; output: 00/01 general
  purpose push-pull/open-drain, 10/11 alternate function push-pull/open-drain).
* 9.1.1/9.1.4 input: IDR reads the pin. An input pin takes the level driven on it from
  outside (`drive`); with CNF = 10 and nothing driving it, ODR selects the pull (9.2.4:
  1 pull-up, 0 pull-down). A floating input nobody drives reads 0 here (noise on the
  chip) and is noted in `floating_reads`. An analog pin reads 0 in IDR (9.1.11).
* 9.1.8 output: a general-purpose output drives ODR; 9.1.4 alternate function: the
  peripheral drives the pin (`alternate`: TIM1's outputs, no remap, RM0008 9.3.7).
* 9.2.5 BSRR: BSy sets, BRy resets ODR bit y, BSy wins when both are written; 9.2.6 BRR.
* LCKR is not modelled.
Pins driven by the board are kept as levels with the time they changed; a peripheral
that watches an input (TIM3's Hall channels, TIM1's BKIN, the EXTI) is told at once
(`watchers`). The board may also schedule a level for a later tick (`drive_at`): it
takes effect at that exact tick, whatever the CPU is doing then (an exception entry
advances time in one step), so a pulse shorter than an interrupt's entry stays exact.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING

from emulation.pil.bus import Peripheral, PilError

if TYPE_CHECKING:
    from emulation.pil.machine import Machine

MODE_INPUT = 0
CNF_ANALOG, CNF_FLOATING, CNF_PULL = 0, 1, 2
CNF_AF_PUSH_PULL, CNF_AF_OPEN_DRAIN = 2, 3


class Gpio(Peripheral):
    def __init__(self, machine: Machine, name: str) -> None:
        super().__init__(machine, name)
        self.port = name[-1]
        self.config = [0x4] * 16  # reset: floating input (CNF = 01, MODE = 00)
        self.odr = 0
        self.external: list[bool | None] = [None] * 16
        #: input pins read through IDR while nothing drove them (they read 0 here)
        self.floating_reads: set[int] = set()
        #: pin -> callbacks(level, tick) when the pin's input level changes
        self.watchers: dict[int, list[Callable[[bool, int], None]]] = {}
        #: pin -> the alternate-function output driving it: () -> level or None (not driven)
        self.alternate: dict[int, Callable[[], bool | None]] = {}
        #: levels the board scheduled: (tick, pin, level), in tick order
        self.scheduled: list[tuple[int, int, bool | None]] = []
        self.readers = {
            "CRL": lambda: self._cr(0),
            "CRH": lambda: self._cr(8),
            "IDR": self._read_idr,
            "ODR": lambda: self.odr,
        }
        self.writers = {
            "CRL": lambda v: self._write_cr(0, v),
            "CRH": lambda v: self._write_cr(8, v),
            "ODR": self._write_odr,
            "BSRR": self._write_bsrr,
            "BRR": lambda v: self._write_odr(self.odr & ~(v & 0xFFFF)),
        }

    def pin_name(self, pin: int) -> str:
        return f"P{self.port}{pin}"

    def _cr(self, first: int) -> int:
        return sum(self.config[first + k] << (4 * k) for k in range(8))

    def _write_cr(self, first: int, value: int) -> None:
        before = self._input_levels()
        for k in range(8):
            self.config[first + k] = (value >> (4 * k)) & 0xF
        self._notify(before)

    def _write_odr(self, value: int) -> None:
        before = self._input_levels()
        self.odr = value & 0xFFFF
        self._notify(before)

    def _write_bsrr(self, value: int) -> None:
        reset = (value >> 16) & ~value & 0xFFFF
        self._write_odr((self.odr | (value & 0xFFFF)) & ~reset)

    def mode(self, pin: int) -> int:
        return self.config[pin] & 3

    def cnf(self, pin: int) -> int:
        return self.config[pin] >> 2

    def is_alternate_output(self, pin: int) -> bool:
        return self.mode(pin) != MODE_INPUT and self.cnf(pin) >= CNF_AF_PUSH_PULL

    def level(self, pin: int) -> bool | None:
        """The pin's level now: None when nothing drives it (a floating input, an
        alternate-function output its peripheral does not drive)."""
        if self.mode(pin) == MODE_INPUT:
            if self.cnf(pin) == CNF_ANALOG:
                return None
            if self.external[pin] is not None:
                return self.external[pin]
            if self.cnf(pin) == CNF_PULL:
                return bool(self.odr >> pin & 1)
            return None
        if self.cnf(pin) >= CNF_AF_PUSH_PULL:
            source = self.alternate.get(pin)
            if source is None:
                raise PilError(
                    f"{self.pin_name(pin)} is an alternate-function output but no modelled"
                    " peripheral drives it"
                )
            return source()
        return bool(self.odr >> pin & 1)

    def _read_idr(self) -> int:
        value = 0
        for pin in range(16):
            if self.mode(pin) == MODE_INPUT and self.cnf(pin) == CNF_ANALOG:
                continue  # RM0008 9.1.11: the Schmitt trigger is off, IDR reads 0
            level = self.level(pin)
            if level is None:
                # Noise on the chip; 0 here, and noted: a check can refuse a firmware
                # whose decision rests on a floating pin.
                if self.mode(pin) == MODE_INPUT:
                    self.floating_reads.add(pin)
                level = False
            value |= int(level) << pin
        return value

    def drive(self, pin: int, level: bool | None) -> None:
        """The board drives (or releases, None) pin `pin` from now on."""
        before = self._input_levels()
        self.external[pin] = level
        after = self.level(pin) if self.mode(pin) == MODE_INPUT else None
        if after != before[pin]:
            for callback in self.watchers.get(pin, ()):
                callback(bool(after), self.machine.now)

    def drive_at(self, pin: int, level: bool | None, at: int) -> None:
        """The board drives `pin` to `level` from tick `at` on (not before now)."""
        if at < self.machine.now:
            raise PilError(
                f"{self.pin_name(pin)} scheduled at tick {at}, before now ({self.machine.now})"
            )
        self.scheduled.append((at, pin, level))
        self.scheduled.sort(key=lambda event: event[0])

    def next_event(self) -> int | None:
        return self.scheduled[0][0] if self.scheduled else None

    def on_event(self, now: int) -> None:
        while self.scheduled and self.scheduled[0][0] <= now:
            at, pin, level = self.scheduled.pop(0)
            saved = self.machine.now
            self.machine.now = at  # the watchers see the change at its own tick
            try:
                self.drive(pin, level)
            finally:
                self.machine.now = saved

    def _input_levels(self) -> list[bool | None]:
        return [self.level(p) if self.mode(p) == MODE_INPUT else None for p in range(16)]

    def _notify(self, before: list[bool | None]) -> None:
        for pin, callbacks in self.watchers.items():
            after = self.level(pin) if self.mode(pin) == MODE_INPUT else None
            if after != before[pin]:
                for callback in callbacks:
                    callback(bool(after), self.machine.now)

    def watch(self, pin: int, callback: Callable[[bool, int], None]) -> None:
        self.watchers.setdefault(pin, []).append(callback)

    def input_level(self, pin: int) -> bool:
        """What a peripheral input on this pin sees (a floating pin reads low)."""
        level = self.level(pin) if self.mode(pin) == MODE_INPUT else None
        return bool(level)

"""TIM3 as the Hall sensor interface (RM0008 section 15, on top of `timer.Timer`).

Behaviours beyond the shared time base, with their RM0008 sections:
* 15.4.2 CR2.TI1S = 1: TI1 is the XOR of the CH1, CH2 and CH3 pins (PA6, PA7, PB0,
  RM0008 9.3.7 without remap); TI1S = 0: the CH1 pin alone.
* 15.4.7 CCMR1.IC1F: the digital filter; a new TI1 level is taken after N consecutive
  equal samples at f_SAMPLING (the table of IC1F codes below), so it lags the pin by
  N samples and a pulse shorter than that never passes. IC1PSC must be 0 (every edge).
* 15.3.4 / 15.4.3 the edge detector TI1F_ED (both edges) is the trigger TRGI with
  SMCR.TS = 100; TI1FP1 (TS = 101, and CC1S = 01) takes the edge of CC1P's polarity.
* 15.3.5 capture: CC1S = 11 maps IC1 on TRC (= TI1F_ED here), CC1S = 01 on TI1FP1; on
  the edge CCR1 takes CNT and CC1IF is set, CC1OF when CC1IF was already set.
* 15.3.14 slave reset mode (SMS = 100): the same edge re-initialises the counter after
  the capture; TIF is set; UIF only with URS = 0.
* One interrupt vector (TIM3) for every flag, its number from the SVD.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from emulation.pil.bus import PilError, bits, svd_interrupt
from emulation.pil.timer import SR_TIF, Timer

if TYPE_CHECKING:
    from emulation.pil.machine import Machine

#: IC1F -> (f_SAMPLING divider of f_DTS (0: f_CK_INT), N samples) (RM0008 15.4.7)
FILTERS = {
    0: (0, 1),
    1: (0, 2),
    2: (0, 4),
    3: (0, 8),
    4: (2, 6),
    5: (2, 8),
    6: (4, 6),
    7: (4, 8),
    8: (8, 6),
    9: (8, 8),
    10: (16, 5),
    11: (16, 6),
    12: (16, 8),
    13: (32, 5),
    14: (32, 6),
    15: (32, 8),
}
HALL_PINS = (("gpioa", 6), ("gpioa", 7), ("gpiob", 0))


class HallTimer(Timer):
    APB = 1

    def __init__(self, machine: Machine) -> None:
        super().__init__(machine, "TIM3")
        self.VECTORS = ((0x1FFF, svd_interrupt("TIM3", "TIM3")),)
        self.ti1_filtered = False
        self.pending_edge: tuple[int, bool] | None = None  # (tick, new filtered level)
        self.captures = 0
        for port, pin in HALL_PINS:
            getattr(machine, port).watch(pin, lambda _level, _at: self._input_changed())

    def _ti1_raw(self) -> bool:
        machine = self.machine
        levels = [getattr(machine, port).input_level(pin) for port, pin in HALL_PINS]
        if self.cr2 & (1 << 7):  # TI1S
            return levels[0] ^ levels[1] ^ levels[2]
        return levels[0]

    def _filter_ticks(self) -> int:
        divider, samples = FILTERS[bits(self.ccmr[0], 4, 4)]
        rcc = self.machine.rcc
        ck_int = rcc.ticks_of(rcc.timer_hz(self.APB), "TIM3CLK")
        return ck_int * max(divider, 1) * samples if divider or samples > 1 else 0

    def _input_changed(self) -> None:
        raw = self._ti1_raw()
        if raw == self.ti1_filtered:
            self.pending_edge = None  # back before the filter took it: a glitch
            return
        self.pending_edge = (self.machine.now + self._filter_ticks(), raw)

    def _write_cr2(self, value: int) -> None:
        super()._write_cr2(value)
        self.ti1_filtered = self._ti1_raw()
        self.pending_edge = None

    def check_slave_mode(self) -> None:
        super().check_slave_mode()
        if self.smcr & 7 and bits(self.smcr, 4, 3) not in (4, 5):
            raise PilError(f"TIM3.SMCR.TS = {bits(self.smcr, 4, 3):03b} is not modelled (100, 101)")

    def write_ccmr(self, index: int, value: int) -> None:
        if index == 0 and bits(value, 0, 2) and bits(value, 2, 2):
            raise PilError("TIM3.CCMR1.IC1PSC != 0 is not modelled")
        super().write_ccmr(index, value)

    def next_event(self) -> int | None:
        base = self._next if self._next_valid else self.counter_event()
        if self.pending_edge is None:
            return base
        return self.pending_edge[0] if base is None else min(base, self.pending_edge[0])

    def on_event(self, now: int) -> None:
        while self.pending_edge is not None and self.pending_edge[0] <= now:
            at, level = self.pending_edge
            super().on_event(at)  # the counter up to the edge first
            self.pending_edge = None
            saved = self.machine.now
            self.machine.now = at
            try:
                self._edge(level)
            finally:
                self.machine.now = saved
        super().on_event(now)

    def _edge(self, level: bool) -> None:
        """TI1F changed to `level` (after the filter)."""
        self.ti1_filtered = level
        polarity_falling = bool(self.ccer & (1 << 1))
        fp1_edge = level != polarity_falling  # TI1FP1: rising, or falling with CC1P
        capture = {3: True, 1: fp1_edge}.get(self.cc_select(1), False)
        if capture and self.ccer & 1:
            self.ccr[1] = self.cnt(self.machine.now)
            self.set_cc_flag(1)
            self.captures += 1
        ts = bits(self.smcr, 4, 3)
        trigger = ts == 4 or (ts == 5 and fp1_edge)
        if trigger:
            self.sr |= SR_TIF
            if self.smcr & 7 == 4:
                self.reinitialise(from_software=False)
        self.update_lines()

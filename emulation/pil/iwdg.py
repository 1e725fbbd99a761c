"""Independent watchdog (RM0008 section 19).

* 19.3 KR keys: 0xCCCC starts the watchdog (and the LSI), 0xAAAA reloads the counter
  with RLR, 0x5555 unlocks PR and RLR for writing (any other key locks them again).
* 19.4.2/19.4.3 PR (divider 4 x 2^PR, at most 256) and RLR (12 bits): a write needs the
  unlock key; while the new value crosses into the LSI domain (up to 5 LSI cycles, 19.4.4)
  SR.PVU / SR.RVU read 1 and a reload still uses the previous value.
* 19.3.1 the 12-bit down counter at LSI / divider: reaching 0 resets the chip. Here that
  reset is a `PilError` naming the time of the last refresh: the firmware starved it.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from emulation.pil.bus import Peripheral, PilError
from emulation.pil.rcc import TICK_HZ

if TYPE_CHECKING:
    from emulation.pil.machine import Machine

KEY_START, KEY_RELOAD, KEY_UNLOCK = 0xCCCC, 0xAAAA, 0x5555
UPDATE_LSI_CYCLES = 5


class WatchdogResetError(PilError):
    """The IWDG counted down to 0: on the chip, a reset."""


class Iwdg(Peripheral):
    def __init__(self, machine: Machine, *, lsi_hz: int) -> None:
        super().__init__(machine, "IWDG")
        self.lsi_hz = lsi_hz
        self.running = False
        self.unlocked = False
        self.pr = 0
        self.rlr = 0xFFF
        self.pr_pending: tuple[int, int] | None = None  # (value, effective tick)
        self.rlr_pending: tuple[int, int] | None = None
        self.expires_at: int | None = None
        self.last_reload: int | None = None
        self.refresh_log: list[int] = []  # ticks of every reload (start included)
        self.readers = {"SR": self._read_sr, "PR": self._read_pr, "RLR": self._read_rlr}
        self.writers = {"KR": self._write_kr, "PR": self._write_pr, "RLR": self._write_rlr}

    def _lsi_ticks(self, cycles: int) -> int:
        return -(-cycles * TICK_HZ // self.lsi_hz)

    def _settle(self) -> None:
        now = self.machine.now
        if self.pr_pending is not None and self.pr_pending[1] <= now:
            self.pr, self.pr_pending = self.pr_pending[0], None
        if self.rlr_pending is not None and self.rlr_pending[1] <= now:
            self.rlr, self.rlr_pending = self.rlr_pending[0], None

    def _read_sr(self) -> int:
        self._settle()
        return (self.pr_pending is not None) | ((self.rlr_pending is not None) << 1)

    def _read_pr(self) -> int:
        self._settle()
        return self.pr

    def _read_rlr(self) -> int:
        self._settle()
        return self.rlr

    def timeout_ticks(self) -> int:
        divider = min(4 << self.pr, 256)
        return self._lsi_ticks(divider * (self.rlr + 1))

    def _reload(self) -> None:
        self._settle()
        self.expires_at = self.machine.now + self.timeout_ticks()
        self.last_reload = self.machine.now
        self.refresh_log.append(self.machine.now)

    def _write_kr(self, value: int) -> None:
        key = value & 0xFFFF
        self.unlocked = key == KEY_UNLOCK
        if key == KEY_START:
            self.running = True
            self.machine.rcc.csr |= 0b11  # LSION, LSIRDY: the IWDG forces the LSI on
            self._reload()
        elif key == KEY_RELOAD and self.running:
            self._reload()

    def _write_pr(self, value: int) -> None:
        if self.unlocked:
            self.pr_pending = (value & 7, self.machine.now + self._lsi_ticks(UPDATE_LSI_CYCLES))

    def _write_rlr(self, value: int) -> None:
        if self.unlocked:
            self.rlr_pending = (
                value & 0xFFF,
                self.machine.now + self._lsi_ticks(UPDATE_LSI_CYCLES),
            )

    def next_event(self) -> int | None:
        return self.expires_at if self.running else None

    def on_event(self, now: int) -> None:
        last = (
            "never" if self.last_reload is None else f"at {self.last_reload / TICK_HZ * 1e3:.3f} ms"
        )
        raise WatchdogResetError(
            f"IWDG reset at {now / TICK_HZ * 1e3:.3f} ms: the watchdog was starved (last refresh"
            f" {last}, timeout {self.timeout_ticks() / TICK_HZ * 1e3:.2f} ms at LSI {self.lsi_hz} Hz)"
        )

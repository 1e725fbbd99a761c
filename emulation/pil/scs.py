"""The Cortex-M3 system control space: NVIC, SCB, SysTick and the DWT's cycle counter
(PM0056 4.3, 4.4, 4.5;
ARMv7-M ARM B1.5 for the exception model the machine runs on top of them).

NVIC (PM0056 4.3): ISER/ICER set and clear enables, ISPR/ICPR pending, IABR reads the
active bits, IPR holds one priority byte per interrupt of which the STM32F103
implements the upper 4 bits (PM0056 4.3.7). A peripheral's interrupt request is a level
(`set_line`): it pends the interrupt when it rises, and an interrupt whose line is still
high when its handler returns, or when software clears its pending bit, is pending again
(PM0056 4.3.9 "level-sensitive interrupts"). The NMI is an edge (`set_nmi`).

Priorities (PM0056 2.3.6, 4.4.5): AIRCR.PRIGROUP splits each priority into group priority
and subpriority; only the group priority preempts. Among pending exceptions the lowest
priority value wins, then the lowest exception number. Reset, NMI and HardFault are
fixed at -3, -2, -1; SysTick, PendSV and SVCall take theirs from SHPR3/SHPR2.

SCB (PM0056 4.4): VTOR (TBLOFF), AIRCR (VECTKEY, PRIGROUP; SYSRESETREQ is an error here),
SHPR1-3 (byte access), ICSR (VECTACTIVE, VECTPENDING, ISRPENDING; PENDSTSET/PENDSTCLR,
NMIPENDSET), SCR (SLEEPONEXIT and SLEEPDEEP are errors: not modelled), CCR (STKALIGN = 1,
PM0056 4.4.7), CPUID.

SysTick (PM0056 4.5): a 24-bit down counter clocked by HCLK (CLKSOURCE = 1) or HCLK / 8;
writing CVR clears it and COUNTFLAG; the first count after that loads RVR; COUNTFLAG is
set when the counter goes from 1 to 0 and cleared by reading CSR; with TICKINT the same
transition pends the SysTick exception. Its value is computed from the time when read.

Cycle counter (ARMv7-M ARM C1.8.7, C1.6.5): DWT_CYCCNT counts processor clock cycles
while DWT_CTRL.CYCCNTENA and CoreDebug DEMCR.TRCENA are both set, wrapping at 2^32;
writable. Its value is computed from the time when read, as SysTick's. The rest of the
DWT (comparators, the other profiling counters) and of CoreDebug (halting debug) is not
modelled: an access to it is an error.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from emulation.pil.bus import Peripheral, PilError, UnmodelledAccessError, bits

if TYPE_CHECKING:
    from emulation.pil.machine import Machine

NMI, HARD_FAULT, SVCALL, PENDSV, SYSTICK = 2, 3, 11, 14, 15
IRQ_BASE = 16
IRQ_COUNT = 60  # the SVD's IPR0..IPR14; the F103 uses 0..42
PRIORITY_MASK = 0xF0  # __NVIC_PRIO_BITS = 4
CPUID_CORTEX_M3_R1P1 = 0x411FC231  # PM0056 4.4.1 for the STM32F10xxx
AIRCR_VECTKEY = 0x05FA
CCR_STKALIGN = 1 << 9


class Nvic(Peripheral):
    def __init__(self, machine: Machine) -> None:
        super().__init__(machine, "NVIC")
        self.enabled = [False] * IRQ_COUNT
        self.line = [False] * IRQ_COUNT
        self.priority = [0] * IRQ_COUNT
        #: pending exception numbers (system exceptions and IRQ_BASE + n)
        self.pending: set[int] = set()
        #: active exceptions, innermost last
        self.active: list[int] = []
        self.prigroup = 0
        self.system_priority = {SVCALL: 0, PENDSV: 0, SYSTICK: 0}
        self.nmi_line = False
        self.readers = {}
        self.writers = {}
        for word in range(2):
            self.readers[f"ISER{word}"] = lambda w=word: self._mask(self.enabled, w)
            self.readers[f"ICER{word}"] = lambda w=word: self._mask(self.enabled, w)
            self.readers[f"ISPR{word}"] = lambda w=word: self._pending_mask(w)
            self.readers[f"ICPR{word}"] = lambda w=word: self._pending_mask(w)
            self.readers[f"IABR{word}"] = lambda w=word: self._active_mask(w)
            self.writers[f"ISER{word}"] = lambda v, w=word: self._set_enable(v, w, True)
            self.writers[f"ICER{word}"] = lambda v, w=word: self._set_enable(v, w, False)
            self.writers[f"ISPR{word}"] = lambda v, w=word: self._set_pending(v, w, True)
            self.writers[f"ICPR{word}"] = lambda v, w=word: self._set_pending(v, w, False)
        for index in range(IRQ_COUNT // 4):
            self.readers[f"IPR{index}"] = lambda i=index: self._ipr(i)
            self.writers[f"IPR{index}"] = lambda v, i=index: self._write_ipr(i, v)
        self.writers["STIR"] = self._write_stir
        self.byte_access = frozenset(f"IPR{index}" for index in range(IRQ_COUNT // 4))

    # ------------------------------------------------------------ registers
    @staticmethod
    def _mask(flags: list[bool], word: int) -> int:
        return sum(1 << n for n in range(32) if 32 * word + n < IRQ_COUNT and flags[32 * word + n])

    def _pending_mask(self, word: int) -> int:
        return sum(1 << n for n in range(32) if IRQ_BASE + 32 * word + n in self.pending)

    def _active_mask(self, word: int) -> int:
        return sum(1 << n for n in range(32) if IRQ_BASE + 32 * word + n in self.active)

    def _irqs(self, value: int, word: int) -> list[int]:
        return [32 * word + n for n in range(32) if value >> n & 1 and 32 * word + n < IRQ_COUNT]

    def _set_enable(self, value: int, word: int, enable: bool) -> None:
        for irq in self._irqs(value, word):
            self.enabled[irq] = enable
        self.machine.interrupts_changed()

    def _set_pending(self, value: int, word: int, pend: bool) -> None:
        for irq in self._irqs(value, word):
            if pend or self.line[irq]:
                self.pending.add(IRQ_BASE + irq)
            else:
                self.pending.discard(IRQ_BASE + irq)
        self.machine.interrupts_changed()

    def _write_stir(self, value: int) -> None:
        self._set_pending(1 << (value & 0x1F), (value & 0x1FF) >> 5, True)

    def _ipr(self, index: int) -> int:
        return sum(self.priority[4 * index + k] << (8 * k) for k in range(4))

    def _write_ipr(self, index: int, value: int) -> None:
        for k in range(4):
            self.priority[4 * index + k] = (value >> (8 * k)) & PRIORITY_MASK
        self.machine.interrupts_changed()

    def write_part(self, name: str, byte: int, size: int, value: int) -> None:
        index = int(name[3:])
        for k in range(size):
            self.priority[4 * index + byte + k] = (value >> (8 * k)) & PRIORITY_MASK
        self.machine.interrupts_changed()

    # ------------------------------------------------------------ lines
    def set_line(self, irq: int, level: bool) -> None:
        """A peripheral's interrupt request: a rising level pends the interrupt."""
        if level and not self.line[irq]:
            self.pending.add(IRQ_BASE + irq)
            self.machine.interrupts_changed()
        self.line[irq] = level

    def set_nmi(self, level: bool) -> None:
        if level and not self.nmi_line:
            self.pending.add(NMI)
            self.machine.interrupts_changed()
        self.nmi_line = level

    def pend(self, exception: int) -> None:
        self.pending.add(exception)
        self.machine.interrupts_changed()

    # ------------------------------------------------------------ priorities
    def priority_of(self, exception: int) -> int:
        if exception == NMI:
            return -2
        if exception == HARD_FAULT:
            return -1
        if exception >= IRQ_BASE:
            return self.priority[exception - IRQ_BASE]
        return self.system_priority.get(exception, 0)

    def group_priority(self, exception: int) -> int:
        priority = self.priority_of(exception)
        if priority < 0:
            return priority
        return priority & ~((2 << self.prigroup) - 1)

    def execution_priority(self, primask: bool) -> int:
        """ARMv7-M B1.5.4: the highest (lowest valued) group priority of the active
        exceptions, boosted to 0 by PRIMASK; 256 in thread mode with nothing masked."""
        current = min((self.group_priority(e) for e in self.active), default=256)
        return min(current, 0) if primask else current

    def _is_enabled(self, exception: int) -> bool:
        if exception >= IRQ_BASE:
            return self.enabled[exception - IRQ_BASE]
        return True

    def highest_pending(self) -> int | None:
        candidates = [e for e in self.pending if self._is_enabled(e)]
        if not candidates:
            return None
        return min(candidates, key=lambda e: (self.priority_of(e), e))

    def preempting(self, execution_priority: int) -> int | None:
        """The pending exception that would be taken now, if any."""
        best = self.highest_pending()
        if best is None or self.group_priority(best) >= execution_priority:
            return None
        return best

    def activate(self, exception: int) -> None:
        self.pending.discard(exception)
        self.active.append(exception)

    def deactivate(self) -> int:
        """Return from the innermost active exception; a line still high pends it again."""
        if not self.active:
            raise PilError("exception return with no exception active")
        exception = self.active.pop()
        if exception >= IRQ_BASE and self.line[exception - IRQ_BASE]:
            self.pending.add(exception)
        return exception


class Scb(Peripheral):
    def __init__(self, machine: Machine) -> None:
        super().__init__(machine, "SCB")
        self.vtor = 0
        self.ccr = CCR_STKALIGN
        self.readers = {
            "CPUID": lambda: CPUID_CORTEX_M3_R1P1,
            "ICSR": self._read_icsr,
            "VTOR": lambda: self.vtor,
            "AIRCR": lambda: (0xFA05 << 16) | (self.machine.nvic.prigroup << 8),
            "SCR": lambda: 0,
            "CCR": lambda: self.ccr,
            "SHPR2": lambda: self.machine.nvic.system_priority[SVCALL] << 24,
            "SHPR3": lambda: (
                self.machine.nvic.system_priority[SYSTICK] << 24
                | self.machine.nvic.system_priority[PENDSV] << 16
            ),
        }
        self.writers = {
            "ICSR": self._write_icsr,
            "VTOR": self._write_vtor,
            "AIRCR": self._write_aircr,
            "SCR": self._write_scr,
            "SHPR2": lambda v: self._write_shpr(2, 0, 4, v),
            "SHPR3": lambda v: self._write_shpr(3, 0, 4, v),
        }
        self.byte_access = frozenset({"SHPR2", "SHPR3"})

    def _read_icsr(self) -> int:
        nvic = self.machine.nvic
        active = nvic.active[-1] if nvic.active else 0
        pending = nvic.highest_pending() or 0
        isr_pending = any(e >= IRQ_BASE for e in nvic.pending)
        systick = SYSTICK in nvic.pending
        return active | (pending << 12) | (isr_pending << 22) | (systick << 26)

    def _write_icsr(self, value: int) -> None:
        nvic = self.machine.nvic
        if value & (1 << 31):
            nvic.pend(NMI)
        if value & (1 << 28):
            nvic.pend(PENDSV)
        if value & (1 << 27):
            nvic.pending.discard(PENDSV)
        if value & (1 << 26):
            nvic.pend(SYSTICK)
        if value & (1 << 25):
            nvic.pending.discard(SYSTICK)

    def _write_vtor(self, value: int) -> None:
        self.vtor = value & 0x3FFFFF80

    def _write_aircr(self, value: int) -> None:
        if value >> 16 != AIRCR_VECTKEY:
            return  # PM0056 4.4.5: a write without the key is ignored
        if value & (1 << 2):
            raise PilError("AIRCR.SYSRESETREQ: the firmware asked for a system reset")
        if value & 1:
            raise PilError("AIRCR.VECTRESET is for debug only (PM0056 4.4.5)")
        self.machine.nvic.prigroup = bits(value, 8, 3)
        self.machine.interrupts_changed()

    def _write_scr(self, value: int) -> None:
        if value & 0b10110:
            raise PilError(
                f"SCB.SCR = 0x{value:x}: SLEEPONEXIT, SLEEPDEEP and SEVONPEND are not modelled"
            )

    def _write_shpr(self, register: int, byte: int, size: int, value: int) -> None:
        nvic = self.machine.nvic
        for k in range(size):
            slot = byte + k
            level = (value >> (8 * k)) & PRIORITY_MASK
            if register == 2 and slot == 3:
                nvic.system_priority[SVCALL] = level
            elif register == 3 and slot == 2:
                nvic.system_priority[PENDSV] = level
            elif register == 3 and slot == 3:
                nvic.system_priority[SYSTICK] = level
            elif level:
                raise UnmodelledAccessError(f"SCB.SHPR{register} byte {slot}: not modelled")
        self.machine.interrupts_changed()

    def write_part(self, name: str, byte: int, size: int, value: int) -> None:
        self._write_shpr(int(name[-1]), byte, size, value)


CSR_ENABLE, CSR_TICKINT, CSR_CLKSOURCE, CSR_COUNTFLAG = 1, 2, 4, 1 << 16


class SysTick(Peripheral):
    def __init__(self, machine: Machine) -> None:
        super().__init__(machine, "SysTick")
        self.csr = 0
        self.rvr = 0
        self.countflag = False
        self.anchor_time = 0
        self.anchor_value = 0
        self.checked_until = 0  # wraps up to this tick are in `countflag`
        self.readers = {
            "CSR": self._read_csr,
            "RVR": lambda: self.rvr,
            "CVR": lambda: self.value(self.machine.now),
            "CALIB": lambda: 9000,  # PM0056 4.5.4: 1 ms at HCLK / 8 = 9 MHz
        }
        self.writers = {"CSR": self._write_csr, "RVR": self._write_rvr, "CVR": self._write_cvr}

    def _ticks_per_count(self) -> int:
        rcc = self.machine.rcc
        hz = rcc.hclk_hz if self.csr & CSR_CLKSOURCE else rcc.hclk_hz // 8
        return rcc.ticks_of(hz, "the SysTick clock")

    def _zero_time(self) -> int:
        return self.anchor_time + self.anchor_value * self._ticks_per_count()

    def value(self, now: int) -> int:
        if not self.csr & CSR_ENABLE:
            return self.anchor_value
        tpc = self._ticks_per_count()
        zero = self._zero_time()
        if now < zero:
            return self.anchor_value - (now - self.anchor_time) // tpc
        if self.rvr == 0:
            return 0
        m = ((now - zero) // tpc) % (self.rvr + 1)
        return 0 if m == 0 else self.rvr + 1 - m

    def _wraps_between(self, start: int, end: int) -> bool:
        """A 1 -> 0 transition in (start, end]."""
        if not self.csr & CSR_ENABLE or end <= start:
            return False
        wrap = self._next_wrap(start)
        return wrap is not None and wrap <= end

    def _next_wrap(self, after: int) -> int | None:
        """The first 1 -> 0 transition strictly after `after`."""
        if not self.csr & CSR_ENABLE:
            return None
        zero = self._zero_time()
        if zero > after and self.anchor_value > 0:
            return zero
        if self.rvr == 0:
            return None
        period = (self.rvr + 1) * self._ticks_per_count()
        base = zero if zero > after else zero + ((after - zero) // period + 1) * period
        return base if base > after else base + period

    def _catch_up(self) -> None:
        now = self.machine.now
        if self._wraps_between(self.checked_until, now):
            self.countflag = True
        self.checked_until = max(self.checked_until, now)

    def _reanchor(self) -> None:
        now = self.machine.now
        self._catch_up()
        self.anchor_value = self.value(now)
        self.anchor_time = now

    def _read_csr(self) -> int:
        self._catch_up()
        value = self.csr | (CSR_COUNTFLAG if self.countflag else 0)
        self.countflag = False
        return value

    def _write_csr(self, value: int) -> None:
        self._reanchor()
        self.csr = value & (CSR_ENABLE | CSR_TICKINT | CSR_CLKSOURCE)
        self.anchor_time = self.machine.now

    def _write_rvr(self, value: int) -> None:
        self._reanchor()
        self.rvr = value & 0xFFFFFF

    def _write_cvr(self, _value: int) -> None:
        self._catch_up()
        self.anchor_value = 0
        self.anchor_time = self.machine.now
        self.countflag = False

    def clock_changed(self, now: int) -> None:
        self._reanchor()

    def next_event(self) -> int | None:
        if not self.csr & CSR_TICKINT:
            return None
        return self._next_wrap(self.checked_until)

    def on_event(self, now: int) -> None:
        self._catch_up()
        self.machine.nvic.pend(SYSTICK)


CYCCNTENA = 1
#: DWT_CTRL's read-only fields as the Cortex-M3 has them: NUMCOMP = 4 comparators (bits
#: 31:28; ARMv7-M ARM C1.8.7); a read-modify-write writes them back, which they ignore
DWT_CTRL_READ_ONLY = 4 << 28
DWT_CTRL_WRITABLE = (1 << 23) - 1  # bits 22:0; 27:24 and NUMCOMP are read-only
DEMCR_TRCENA = 1 << 24


class CycleCounter(Peripheral):
    """DWT_CTRL and DWT_CYCCNT; CoreDebug's DEMCR (its TRCENA gates the DWT) is the
    `CoreDebug` model's, which tells this one when it changes."""

    size = 0x8

    def __init__(self, machine: Machine) -> None:
        super().__init__(machine, "DWT")
        self.ctrl = 0
        self.trcena = False
        self.anchor_time = 0
        self.anchor_value = 0
        self.anchor_ticks = machine.cycle_ticks  # ticks per cycle since the anchor
        self.readers = {
            "CTRL": lambda: DWT_CTRL_READ_ONLY | self.ctrl,
            "CYCCNT": lambda: self.value(self.machine.now),
        }
        self.writers = {"CTRL": self._write_ctrl, "CYCCNT": self._write_cyccnt}

    def counting(self) -> bool:
        return self.trcena and bool(self.ctrl & CYCCNTENA)

    def value(self, now: int) -> int:
        if not self.counting():
            return self.anchor_value
        cycles = (now - self.anchor_time) // self.anchor_ticks
        return (self.anchor_value + cycles) & 0xFFFFFFFF

    def _reanchor(self) -> None:
        """From now on, at the processor clock now (`clock_changed` comes after the
        machine took the new one: the cycles so far are counted at the old)."""
        now = self.machine.now
        self.anchor_value = self.value(now)
        self.anchor_time = now
        self.anchor_ticks = self.machine.cycle_ticks

    def _write_ctrl(self, value: int) -> None:
        if value & DWT_CTRL_WRITABLE & ~CYCCNTENA:
            raise UnmodelledAccessError(
                f"DWT.CTRL = 0x{value:08x}: of its writable bits only CYCCNTENA (bit 0) is modelled"
            )
        self._reanchor()
        self.ctrl = value & CYCCNTENA

    def _write_cyccnt(self, value: int) -> None:
        self.anchor_time = self.machine.now
        self.anchor_value = value
        self.anchor_ticks = self.machine.cycle_ticks

    def set_trcena(self, on: bool) -> None:
        self._reanchor()
        self.trcena = on

    def clock_changed(self, now: int) -> None:
        self._reanchor()


class CoreDebug(Peripheral):
    """DEMCR's TRCENA only (the DWT's enable); halting debug is not modelled."""

    size = 0x10

    def __init__(self, machine: Machine, dwt: CycleCounter) -> None:
        super().__init__(machine, "CoreDebug")
        self.dwt = dwt
        self.demcr = 0
        self.readers = {"DEMCR": lambda: self.demcr}
        self.writers = {"DEMCR": self._write_demcr}

    def _write_demcr(self, value: int) -> None:
        if value & ~DEMCR_TRCENA:
            raise UnmodelledAccessError(
                f"CoreDebug.DEMCR = 0x{value:08x}: only TRCENA (bit 24) is modelled"
            )
        self.demcr = value
        self.dwt.set_trcena(bool(value & DEMCR_TRCENA))

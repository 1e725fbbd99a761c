"""An emulated STM32F103 that runs a linked firmware ELF from its reset vector.

The CPU is unicorn's Cortex-M3 (Thumb, M-class). Unicorn runs instructions only; the
exception model, the peripherals and time are this module's:

* Memory (RM0008 3.3, 3.4): 128 KiB flash at 0x08000000, aliased at 0 (BOOT0 = 0), read
  and execute only; 20 KiB SRAM at 0x20000000, filled with `ram_fill` (not zeros, so
  code that reads uninitialised RAM does not pass by luck); the peripheral region and the
  private peripheral bus are memory-mapped I/O dispatched to the models of
  `emulation.pil`. The ELF's loadable bytes are written at their load (physical)
  addresses, exactly as a programmer would flash them; nothing else is prepared: the
  firmware's own start-up code copies .data and clears .bss.
* Reset (PM0056 2.3.7 / ARMv7-M B1.5.5): SP from word 0, PC from word 1 of the table at 0.
* Exceptions (ARMv7-M B1.5.6-B1.5.8): taken between translation blocks when the NVIC has
  one whose group priority beats the execution priority (PRIMASK counted). Entry pushes
  the 8-word frame (r0-r3, r12, lr, return address, xPSR) on the main stack, aligned to
  8 bytes (CCR.STKALIGN, xPSR bit 9 records it), sets LR to EXC_RETURN (0xFFFFFFF9 from
  thread mode, 0xFFFFFFF1 nested) and jumps to the vector at VTOR. Return is detected
  when the PC reaches 0xFFFFFFxx (unicorn reports it as an exception-exit interrupt); a
  pending exception that beats what the return would go back to is tail-chained (no
  unstacking), otherwise the frame is popped. The process stack is not modelled.
* WFI (ARMv7-M B1.5.19): the CPU stops at the instruction; time jumps to the next
  peripheral event until an interrupt that would preempt (PRIMASK ignored) is pending.
* Time: ticks of 1/72 MHz. The CPU runs in slices up to the next peripheral event; each
  translation block costs its instructions' TRM cycles (`emulation.cycles.decode`, a
  taken branch's refill at its end) plus FLASH_ACR.LATENCY wait cycles for its first
  flash line and for each literal load (an estimate: the bench's `emulation.memory`
  prices the prefetch buffer exactly on traces), times the ticks of one HCLK cycle; an
  exception entry and return cost `emulation.memory`'s figures at the latency in force.
  A peripheral access happens at its own instruction's tick within its block (the
  block's start plus the cycles before it), and the peripherals' events due by then
  happen first: two accesses a few cycles apart in one block see the timers move
  between them (the commutation end's counter read and its COM event).

Anything the chip would not survive (a hard fault, a fetch from nowhere, a write to
flash, the watchdog's reset) and anything not modelled raises `PilError`.
"""

from __future__ import annotations

import struct
from collections.abc import Callable
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path

import capstone  # type: ignore[import-untyped]
from capstone import arm_const as cs_arm
from elftools.elf.elffile import ELFFile
from unicorn import (
    UC_ARCH_ARM,
    UC_HOOK_BLOCK,
    UC_HOOK_CODE,
    UC_HOOK_INTR,
    UC_HOOK_MEM_INVALID,
    UC_MODE_MCLASS,
    UC_MODE_THUMB,
    UC_PROT_ALL,
    UC_PROT_EXEC,
    UC_PROT_READ,
    Uc,
    UcError,
)
from unicorn import arm_const as uc_arm

from codegen.interrupts import interrupts_noted, raise_noted
from emulation.cycles import decode, disassemble, thumb_instruction_size
from emulation.memory import (
    STM32F103_72MHZ,
    MemoryTiming,
    exception_entry_cycles,
    exception_exit_cycles,
)
from emulation.pil.adc import Adc
from emulation.pil.bus import Peripheral, PilError, describe_address
from emulation.pil.exti import Afio, Exti
from emulation.pil.gpio import Gpio
from emulation.pil.iwdg import Iwdg
from emulation.pil.rcc import TICK_HZ, Flash, Rcc
from emulation.pil.scs import HARD_FAULT, CoreDebug, CycleCounter, Nvic, Scb, SysTick
from emulation.pil.tim1 import AdvancedTimer
from emulation.pil.tim3 import HallTimer

FLASH_BASE = 0x0800_0000
FLASH_SIZE = 128 * 1024
SRAM_BASE = 0x2000_0000
SRAM_SIZE = 20 * 1024
PERIPHERAL_REGION = (0x4000_0000, 0x4003_0000)
PRIVATE_PERIPHERAL_BUS = (0xE000_0000, 0xE010_0000)
EXC_RETURN_HANDLER, EXC_RETURN_THREAD_MSP, EXC_RETURN_THREAD_PSP = (
    0xFFFFFFF1,
    0xFFFFFFF9,
    0xFFFFFFFD,
)
_EXCP_EXCEPTION_EXIT = 8  # QEMU's EXCP_EXCEPTION_EXIT, reported through UC_HOOK_INTR
_WFI = b"\x30\xbf"
_TAKEN_REFILL = 3  # TRM pipeline refill P, worst case (emulation.cycles)
#: xPSR's IT/ICI bits (ARMv7-M B1.4.2): IT[1:0] at 26:25, IT[7:2] at 15:10
_ITSTATE = (3 << 25) | (0x3F << 10)
_FRAME = (
    uc_arm.UC_ARM_REG_R0,
    uc_arm.UC_ARM_REG_R1,
    uc_arm.UC_ARM_REG_R2,
    uc_arm.UC_ARM_REG_R3,
    uc_arm.UC_ARM_REG_R12,
    uc_arm.UC_ARM_REG_LR,
    uc_arm.UC_ARM_REG_PC,
    uc_arm.UC_ARM_REG_XPSR,
)


_STORES = capstone.Cs(capstone.CS_ARCH_ARM, capstone.CS_MODE_THUMB | capstone.CS_MODE_MCLASS)
_STORES.detail = True
#: capstone register id -> unicorn register id (r0-r12, sp, lr, pc)
_REGISTER = {
    **{getattr(cs_arm, f"ARM_REG_R{n}"): getattr(uc_arm, f"UC_ARM_REG_R{n}") for n in range(13)},
    cs_arm.ARM_REG_SP: uc_arm.UC_ARM_REG_SP,
    cs_arm.ARM_REG_LR: uc_arm.UC_ARM_REG_LR,
    cs_arm.ARM_REG_PC: uc_arm.UC_ARM_REG_PC,
}


_LOADS_AND_STORES = {
    "ldr": None, "ldrh": None, "ldrb": None, "ldrsh": None, "ldrsb": None,
    "str": 0xFFFFFFFF, "strh": 0xFFFF, "strb": 0xFF,
}  # fmt: skip


@dataclass(frozen=True)
class _Access:
    """A single load or store of a block (no writeback, one register): where its
    address comes from, and how many of the block's cycles come before it."""

    cycles_before: int
    store: bool
    base: int  # unicorn register ids
    disp: int
    index: int | None
    shift: int
    source: int  # the stored register (stores)
    mask: int  # the stored width's bits


def _access_of(code: bytes, address: int, cycles_before: int) -> _Access | None:
    instruction = next(_STORES.disasm(code, address), None)
    if instruction is None:
        return None
    mnemonic = instruction.mnemonic.split(".")[0]
    if mnemonic not in _LOADS_AND_STORES or len(instruction.operands) != 2:
        return None
    source, target = instruction.operands
    memory = target.mem
    if target.type != cs_arm.ARM_OP_MEM or memory.base not in _REGISTER:
        return None
    if memory.base == cs_arm.ARM_REG_PC or instruction.writeback:
        return None
    mask = _LOADS_AND_STORES[mnemonic]
    index = _REGISTER.get(memory.index) if memory.index else None
    if memory.index and index is None:
        return None
    return _Access(
        cycles_before,
        mask is not None,
        _REGISTER[memory.base],
        memory.disp,
        index,
        memory.lshift if memory.index else 0,
        _REGISTER.get(source.reg, uc_arm.UC_ARM_REG_R0),
        mask or 0,
    )


@lru_cache(maxsize=16384)
def block_cost(code: bytes, address: int) -> tuple[tuple[int, int], tuple[_Access, ...]]:
    """The block of Thumb instructions `code` at `address`: (TRM cycles, flash reads
    that wait), and its loads and stores. A block entered from elsewhere waits for its
    first flash line, and each literal load reads the flash over D-Code (RM0008 3.3.3;
    `emulation.memory` models this in full for the bench). A function of the bytes and
    the address alone: every machine running the same image shares it."""
    cycles = 0
    literal_loads = 0
    offset = 0
    last = None
    accesses = []
    while offset < len(code):
        length = thumb_instruction_size(code[offset : offset + 2])
        instruction = code[offset : offset + length]
        access = _access_of(instruction, address + offset, cycles)
        if access is not None:
            accesses.append(access)
        last = decode(instruction)
        cycles += last.cycles
        if "[pc" in disassemble(instruction, address + offset):
            literal_loads += 1
        offset += length
    if last is not None and last.refill != "never":
        cycles += _TAKEN_REFILL
    waits = (1 + literal_loads) if address < SRAM_BASE else 0
    return (cycles, waits), tuple(accesses)


@dataclass(frozen=True)
class MachineOptions:
    """What the board around the chip does (defaults: a healthy board)."""

    hse_fails: bool = False
    #: datasheet t_SU(HSE) for an 8 MHz crystal: 2 ms typical
    hse_startup_ticks: int = 2 * TICK_HZ // 1000
    #: datasheet t_LOCK: 200 us maximum
    pll_lock_ticks: int = 200 * TICK_HZ // 1_000_000
    #: the LSI's frequency; the datasheet gives 30 to 60 kHz: the fastest starves first
    lsi_hz: int = 60_000
    #: analog reference, volts
    vref: float = 3.3
    ram_fill: int = 0xCD


@dataclass(frozen=True)
class FirmwareImage:
    """The loadable bytes of an ELF at their load addresses, and its symbols."""

    path: Path
    chunks: tuple[tuple[int, bytes], ...]
    symbols: dict[str, int]
    #: every WFI instruction address in the code (Thumb mapping symbols)
    wfi_addresses: tuple[int, ...]
    #: end of the RAM the image uses (.data, .bss): the stack must stay above it
    static_ram_end: int


def load_firmware(path: str | Path) -> FirmwareImage:
    """Read an ARM ELF the way a programmer flashes it: PT_LOAD file bytes at p_paddr."""
    path = Path(path)
    with path.open("rb") as stream:
        elf = ELFFile(stream)
        if elf["e_machine"] != "EM_ARM" or elf.elfclass != 32 or not elf.little_endian:
            raise PilError(f"{path}: not a 32-bit little-endian ARM ELF")
        chunks = []
        static_end = SRAM_BASE
        for segment in elf.iter_segments():
            if segment["p_type"] != "PT_LOAD":
                continue
            vaddr, memsz = segment["p_vaddr"], segment["p_memsz"]
            if SRAM_BASE <= vaddr < SRAM_BASE + SRAM_SIZE:
                static_end = max(static_end, vaddr + memsz)
            if segment["p_filesz"] == 0:
                continue
            paddr = segment["p_paddr"]
            data = segment.data()
            if not FLASH_BASE <= paddr <= paddr + len(data) <= FLASH_BASE + FLASH_SIZE:
                raise PilError(
                    f"{path}: a loadable segment at 0x{paddr:08x} ({len(data)} bytes) is not in flash"
                )
            chunks.append((paddr, data))
        symbols: dict[str, int] = {}
        thumb_code: list[tuple[int, str]] = []
        symtab = elf.get_section_by_name(".symtab")
        if symtab is not None:
            for symbol in symtab.iter_symbols():
                name = symbol.name
                if name[:2] in ("$t", "$d", "$a") and (len(name) == 2 or name[2] == "."):
                    thumb_code.append((symbol["st_value"] & ~1, name[1]))
                elif name and symbol["st_shndx"] != "SHN_UNDEF":
                    symbols.setdefault(name, symbol["st_value"])
    wfi = _find_wfi(chunks, sorted(thumb_code))
    return FirmwareImage(path, tuple(chunks), symbols, wfi, static_end)


def _find_wfi(chunks: list[tuple[int, bytes]], marks: list[tuple[int, str]]) -> tuple[int, ...]:
    """Addresses of 0xBF30 half-words in Thumb code (not in $d literal data). One inside
    a 32-bit instruction is harmless: a code hook only fires at instruction starts."""
    found = []
    for base, data in chunks:
        for offset in range(0, len(data) - 1, 2):
            if data[offset : offset + 2] != _WFI:
                continue
            address = base + offset
            kind = "t"
            for mark_address, mark in marks:
                if mark_address > address:
                    break
                kind = mark
            if kind == "t":
                found.append(address)
    return tuple(found)


class Machine:
    """The chip: CPU, memories, peripherals and time."""

    def __init__(self, image: FirmwareImage, options: MachineOptions | None = None) -> None:
        self.image = image
        self.options = options or MachineOptions()
        self.now = 0
        #: set while a peripheral looks ahead at its inputs (the ADC's watchdog): a
        #: causal source (the motor in the loop) answers only what it already knows
        self.looking_ahead = False
        self.cycle_ticks = TICK_HZ // 8_000_000  # the HSI out of reset
        self.error: BaseException | None = None
        self.sleep_pc: int | None = None
        #: WFI instructions executed so far (a sleep an interrupt ends before anyone
        #: looks still counts)
        self.sleeps = 0
        self.exceptions_taken = 0
        self.handler_entries: dict[int, int] = {}
        #: (tick, exception number) of every exception entry, tail-chained ones included
        self.entry_log: list[tuple[int, int]] = []
        #: ticks spent out of thread mode (entry, handlers, exit): the CPU load's numerator
        self.handler_ticks = 0
        self._busy_since = 0
        self._deadline = 0
        self._block_end = 0
        self._block_cost: dict[tuple[int, int], tuple[int, int]] = {}
        #: each block's loads and stores: (cycles before it in the block, its operands)
        self._block_accesses: dict[tuple[int, int], tuple[_Access, ...]] = {}
        self._block_start = 0  # the running block's first tick
        self._accesses: tuple[_Access, ...] = ()  # the running block's loads and stores
        self._next_access = 0  # the first of them no peripheral access has matched yet
        self._returning = False
        self._after_store: tuple[int, int] | None = None  # (address, value) of that store
        self._fault: str | None = None

        self.rcc = Rcc(
            self,
            hse_startup_ticks=self.options.hse_startup_ticks,
            pll_lock_ticks=self.options.pll_lock_ticks,
            hse_fails=self.options.hse_fails,
        )
        self.flash = Flash(self)
        self.nvic = Nvic(self)
        self.scb = Scb(self)
        self.systick = SysTick(self)
        self.dwt = CycleCounter(self)
        self.coredebug = CoreDebug(self, self.dwt)
        self.gpioa = Gpio(self, "GPIOA")
        self.gpiob = Gpio(self, "GPIOB")
        self.iwdg = Iwdg(self, lsi_hz=self.options.lsi_hz)
        self.tim1 = AdvancedTimer(self)
        self.tim3 = HallTimer(self)
        self.adc1 = Adc(self, vref=self.options.vref)
        self.adc2 = Adc(self, vref=self.options.vref, name="ADC2", shares_pins_with=self.adc1)
        self.afio = Afio(self)
        self.exti = Exti(self, self.afio, (self.gpioa, self.gpiob))
        self.peripherals: tuple[Peripheral, ...] = (
            self.rcc,
            self.flash,
            self.nvic,
            self.scb,
            self.systick,
            self.dwt,
            self.coredebug,
            self.gpioa,
            self.gpiob,
            self.iwdg,
            self.tim1,
            self.tim3,
            self.adc1,
            self.adc2,
            self.afio,
            self.exti,
        )
        #: the peripherals that schedule events of their own, in the same order (the
        #: others keep the bus's `next_event`, which is always None): the machine asks
        #: them for their next event at every step
        self._timed = tuple(
            p for p in self.peripherals if type(p).next_event is not Peripheral.next_event
        )
        self._ranges: list[tuple[int, int, Peripheral]] = []
        for p in self.peripherals:
            if p is self.nvic:
                self._ranges.append((p.base + 0x100, p.base + 0x4F0, p))
                self._ranges.append((p.base + 0xF00, p.base + 0xF04, p))
            elif p is self.scb:
                self._ranges.append((p.base, p.base + 0x40, p))
            elif p is self.systick:
                self._ranges.append((p.base, p.base + 0x10, p))
            else:
                self._ranges.append((p.base, p.base + p.size, p))
        self._dispatch: dict[int, tuple[Peripheral, int]] = {}
        self.listeners: list[Callable[[Machine], None]] = []
        self._build_cpu()
        self.reset()

    # ------------------------------------------------------------------ set-up
    def _build_cpu(self) -> None:
        uc = Uc(UC_ARCH_ARM, UC_MODE_THUMB | UC_MODE_MCLASS)
        uc.ctl_set_cpu_model(uc_arm.UC_CPU_ARM_CORTEX_M3)
        flash = bytearray(b"\xff" * FLASH_SIZE)  # erased flash reads all ones
        for address, data in self.image.chunks:
            flash[address - FLASH_BASE : address - FLASH_BASE + len(data)] = data
        for base in (0, FLASH_BASE):
            uc.mem_map(base, FLASH_SIZE, UC_PROT_READ | UC_PROT_EXEC)
            uc.mem_write(base, bytes(flash))
        uc.mem_map(SRAM_BASE, SRAM_SIZE, UC_PROT_ALL)
        uc.mem_write(SRAM_BASE, bytes([self.options.ram_fill]) * SRAM_SIZE)
        for start, end in (PERIPHERAL_REGION, PRIVATE_PERIPHERAL_BUS):
            uc.mmio_map(
                start,
                end - start,
                self._mmio_read,
                start,
                self._mmio_write,
                start,
            )
        uc.hook_add(UC_HOOK_BLOCK, self._on_block)
        uc.hook_add(UC_HOOK_INTR, self._on_interrupt)
        uc.hook_add(UC_HOOK_MEM_INVALID, self._on_invalid)
        for address in self.image.wfi_addresses:
            uc.hook_add(UC_HOOK_CODE, self._on_wfi, None, address, address)
        self.uc = uc

    def reset(self) -> None:
        """Power-on reset: SP and PC from the vector table at address 0 (the flash alias)."""
        sp = self.read_u32(0)
        pc = self.read_u32(4)
        if not pc & 1:
            raise PilError(f"reset vector 0x{pc:08x} has no Thumb bit: the core would lock up")
        self.uc.reg_write(uc_arm.UC_ARM_REG_MSP, sp)
        self.uc.reg_write(uc_arm.UC_ARM_REG_SP, sp)
        self.pc = pc & ~1

    # ------------------------------------------------------------------ memory
    def read_u32(self, address: int) -> int:
        return int.from_bytes(self.uc.mem_read(address, 4), "little")

    def write_u32(self, address: int, value: int) -> None:
        self.uc.mem_write(address, (value & 0xFFFFFFFF).to_bytes(4, "little"))

    def symbol(self, name: str) -> int:
        if name not in self.image.symbols:
            raise PilError(f"{self.image.path}: no symbol {name!r}")
        return self.image.symbols[name]

    def read_symbol_u32(self, name: str) -> int:
        return self.read_u32(self.symbol(name))

    def write_symbol_u32(self, name: str, value: int) -> None:
        self.write_u32(self.symbol(name), value)

    def _peripheral_at(self, address: int) -> tuple[Peripheral, int]:
        hit = self._dispatch.get(address)
        if hit is None:
            for start, end, p in self._ranges:
                if start <= address < end:
                    hit = (p, address - p.base)
                    break
            else:
                raise PilError(f"access to {describe_address(address)}: no peripheral model there")
            self._dispatch[address] = hit
        peripheral = hit[0]
        if not self.rcc.clock_enabled(peripheral.svd_name):
            raise PilError(
                f"access to {describe_address(address)} with the {peripheral.svd_name} clock"
                " off in RCC (RM0008 7.3.7/7.3.8: the register would not respond)"
            )
        return hit

    def _mmio_read(self, uc: Uc, offset: int, size: int, base: int) -> int:
        if self.error is not None:
            return 0
        try:
            self._at_access(base + offset, None)
            peripheral, register = self._peripheral_at(base + offset)
            return peripheral.read(register, size)
        except Exception as error:
            self._stop_with(error)
            return 0

    def _mmio_write(self, uc: Uc, offset: int, size: int, value: int, base: int) -> None:
        if self.error is not None:
            return
        try:
            self._at_access(base + offset, value & ((1 << (8 * size)) - 1))
            peripheral, register = self._peripheral_at(base + offset)
            peripheral.write(register, size, value)
            if self.nvic.pending and self._preemption_due():
                # Take it after this store, not at the end of the block (see
                # `_step_over_store`).
                self._after_store = (base + offset, value & ((1 << (8 * size)) - 1))
                uc.emu_stop()
        except Exception as error:
            self._stop_with(error)

    def _stop_with(self, error: BaseException) -> None:
        if self.error is None:
            self.error = error
        self.uc.emu_stop()

    # ------------------------------------------------------------------ hooks
    def _on_block(self, uc: Uc, address: int, size: int, _data: object) -> None:
        start = self._block_end
        if start >= self._deadline or (self.nvic.pending and self._preemption_due()):
            uc.emu_stop()  # before the block runs: it runs again on resume
            return
        self.now = start
        cost = self._block_cost.get((address, size))
        if cost is None:
            cost = self._cost_of_block(address, size)
        cycles = cost[0] + self.flash.latency * cost[1]
        self._block_end = start + cycles * self.cycle_ticks
        self._block_start = start
        self._accesses = self._block_accesses[(address, size)]
        self._next_access = 0

    def _access_tick(self, address: int, value: int | None) -> int:
        """The tick of the running block's load (`value` None) or store of `value` at
        `address`: the block's start plus the cycles of the instructions before it (its
        first flash wait aside), so that a peripheral sees the accesses of one block at
        their own ticks (a trigger between the commutation end's read of TIM1's counter
        and its COM event, a few cycles apart in one block, fires between them). The
        instruction is found as `_step_over_store` finds one: the next load or store of
        the block, from the last one matched, whose address (and stored value) the
        registers give; unicorn's PC in a peripheral callback is the block's. None
        found: the block's start."""
        register = self.uc.reg_read
        for k in range(self._next_access, len(self._accesses)):
            access = self._accesses[k]
            if access.store != (value is not None):
                continue
            target = register(access.base) + access.disp
            if access.index is not None:
                target += register(access.index) << access.shift
            if target & 0xFFFFFFFF != address:
                continue
            if value is not None and register(access.source) & access.mask != value & access.mask:
                continue
            self._next_access = k + 1
            return self._block_start + access.cycles_before * self.cycle_ticks
        return self._block_start

    def _at_access(self, address: int, value: int | None) -> None:
        """Time moves to the access's own tick, and the peripherals' events due by then
        happen first."""
        tick = self._access_tick(address, value)
        if tick > self.now:
            self.now = tick
            self._process_events()

    def _cost_of_block(self, address: int, size: int) -> tuple[int, int]:
        """(TRM cycles, flash reads that wait) of the block at `address` (`block_cost`),
        and its loads and stores for `_access_tick`."""
        code = bytes(self.uc.mem_read(address, size))
        cost, accesses = block_cost(code, address)
        self._block_cost[(address, size)] = cost
        self._block_accesses[(address, size)] = accesses
        return cost

    def _on_wfi(self, uc: Uc, address: int, _size: int, _data: object) -> None:
        self.sleep_pc = address
        self.sleeps += 1
        uc.emu_stop()

    def _on_interrupt(self, uc: Uc, number: int, _data: object) -> None:
        pc = uc.reg_read(uc_arm.UC_ARM_REG_PC)
        if number == _EXCP_EXCEPTION_EXIT or pc >= 0xFFFFFF00:
            self._returning = True
        else:
            self._fault = (
                f"CPU exception {number} at pc 0x{pc:08x} (an undefined instruction, a"
                " breakpoint or a bad state): a HardFault on the chip"
            )
        uc.emu_stop()

    def _on_invalid(
        self, uc: Uc, access: int, address: int, size: int, value: int, _data: object
    ) -> bool:
        pc = uc.reg_read(uc_arm.UC_ARM_REG_PC)
        self._fault = (
            f"invalid memory access (unicorn access type {access}) of {size} bytes at"
            f" 0x{address:08x} from pc 0x{pc:08x}: a bus fault on the chip"
        )
        return False

    # ------------------------------------------------------------------ exceptions
    def _primask(self) -> bool:
        return bool(self.uc.reg_read(uc_arm.UC_ARM_REG_PRIMASK) & 1)

    def _preemption_due(self) -> bool:
        priority = self.nvic.execution_priority(self._primask())
        return self.nvic.preempting(priority) is not None

    def interrupts_changed(self) -> None:
        """A pending, enable or priority change: the block hook looks at the next block."""

    def _memory_timing(self) -> MemoryTiming:
        latency = self.flash.latency
        if latency == STM32F103_72MHZ.flash_wait_states:
            return STM32F103_72MHZ
        return MemoryTiming(f"FLASH_ACR.LATENCY = {latency}", latency)

    def clocks_changed(self) -> None:
        self.cycle_ticks = self.rcc.ticks_of(self.rcc.hclk_hz, "HCLK")
        for p in self.peripherals:
            p.clock_changed(self.now)

    def _enter(self, exception: int, return_address: int, exc_return: int | None) -> None:
        """Exception entry (ARMv7-M B1.5.6); `exc_return` None pushes a new frame, else
        tail-chains into `exception` with the frame already on the stack."""
        uc = self.uc
        frame_pushed = exc_return is None
        if exc_return is None:
            if not self.nvic.active:
                self._busy_since = self.now
            sp = uc.reg_read(uc_arm.UC_ARM_REG_SP)
            xpsr = uc.reg_read(uc_arm.UC_ARM_REG_XPSR) | (1 << 24)
            frame_sp = sp - 32
            aligned = bool(self.scb.ccr & (1 << 9)) and frame_sp & 4
            if aligned:
                frame_sp -= 4
                xpsr |= 1 << 9
            if frame_sp < self.image.static_ram_end:
                raise PilError(
                    f"stack overflow: the exception frame at 0x{frame_sp:08x} would overwrite"
                    f" static data ending at 0x{self.image.static_ram_end:08x}"
                )
            values = [*uc.reg_read_batch(_FRAME[:6]), return_address, xpsr]
            uc.mem_write(frame_sp, b"".join((v & 0xFFFFFFFF).to_bytes(4, "little") for v in values))
            uc.reg_write(uc_arm.UC_ARM_REG_SP, frame_sp)
            exc_return = EXC_RETURN_HANDLER if self.nvic.active else EXC_RETURN_THREAD_MSP
        self.nvic.activate(exception)
        self.exceptions_taken += 1
        self.handler_entries[exception] = self.handler_entries.get(exception, 0) + 1
        self.entry_log.append((self.now, exception))
        vector = self.read_u32(self.scb.vtor + 4 * exception)
        # a tail-chain takes 6 cycles (Cortex-M3 TRM 5.5.2)
        entry = exception_entry_cycles(self._memory_timing(), vector & ~1) if frame_pushed else 6
        if not vector & 1:
            raise PilError(
                f"vector {exception} is 0x{vector:08x} without the Thumb bit: a HardFault (INVSTATE)"
            )
        if exception == HARD_FAULT:
            raise PilError("HardFault taken")
        uc.reg_write(uc_arm.UC_ARM_REG_LR, exc_return)
        # The handler starts outside any IT block (ExceptionTaken: ITSTATE = 0): the
        # interrupted block's state is in the stacked xPSR, for the return. Left in
        # place, the handler's first instructions ran under the interrupted block's
        # conditions (a false one skipped them: a handler entered between an IT's
        # instructions read its state base from another handler's register).
        uc.reg_write(uc_arm.UC_ARM_REG_XPSR, uc.reg_read(uc_arm.UC_ARM_REG_XPSR) & ~_ITSTATE)
        self.pc = vector & ~1
        self.now += entry * self.cycle_ticks

    def _exception_return(self) -> None:
        """PC reached EXC_RETURN (ARMv7-M B1.5.8): tail-chain or unstack."""
        uc = self.uc
        exc_return = uc.reg_read(uc_arm.UC_ARM_REG_PC) | 1
        if exc_return not in (EXC_RETURN_HANDLER, EXC_RETURN_THREAD_MSP):
            raise PilError(f"exception return 0x{exc_return:08x}: only the main stack is modelled")
        self.nvic.deactivate()
        priority = self.nvic.execution_priority(self._primask())
        chained = self.nvic.preempting(priority)
        if chained is not None:
            frame_sp = uc.reg_read(uc_arm.UC_ARM_REG_SP)
            self._enter(chained, self.read_u32(frame_sp + 24), exc_return)
            return
        frame_sp = uc.reg_read(uc_arm.UC_ARM_REG_SP)
        # the frame in one read and its six core registers in one write (each unicorn
        # call costs microseconds of Python: this runs at every exception return)
        words = struct.unpack("<8I", uc.mem_read(frame_sp, 32))
        uc.reg_write_batch(list(zip(_FRAME[:6], words[:6], strict=True)))
        xpsr = words[7]
        uc.reg_write(uc_arm.UC_ARM_REG_XPSR, xpsr & ~(1 << 9))
        uc.reg_write(uc_arm.UC_ARM_REG_SP, frame_sp + 32 + (4 if xpsr & (1 << 9) else 0))
        self.pc = words[6] & ~1
        self.now += exception_exit_cycles(self._memory_timing()) * self.cycle_ticks
        if exc_return == EXC_RETURN_THREAD_MSP:
            self.handler_ticks += self.now - self._busy_since

    def _take_exception(self) -> bool:
        if not self.nvic.pending:
            return False
        primask = self._primask()
        exception = self.nvic.preempting(self.nvic.execution_priority(primask))
        if exception is None:
            return False
        return_address = self.pc
        if self.sleep_pc is not None:
            return_address = self.sleep_pc + 2
            self.sleep_pc = None
        self._enter(exception, return_address, None)
        return True

    # ------------------------------------------------------------------ time
    def next_event(self) -> int | None:
        first = None
        for p in self._timed:
            t = p.next_event()
            if t is not None and (first is None or t < first):
                first = t
        return first

    def _process_events(self) -> None:
        """The peripherals' events due by now, in time order: the earliest first, at its
        own tick (the CPU may have run past several in one block or exception entry, and
        one event can undo another's cause: a pin change back before TIM3's filter took
        the first one)."""
        timed = self._timed
        for _ in range(10_000):
            now = self.now
            first: int | None = None
            hits: list[Peripheral] = []  # those due at `first`, asked before any runs
            for p in timed:
                t = p.next_event()
                if t is None or t > now:
                    continue
                if first is None or t < first:
                    first, hits = t, [p]
                elif t == first:
                    hits.append(p)
            if first is None:
                return
            self.now = first
            try:
                for p in hits:
                    p.on_event(first)
            finally:
                self.now = now
        raise PilError(f"peripheral events do not settle at tick {self.now}")

    def _raise_error(self) -> None:
        if self.error is not None:
            error, self.error = self.error, None
            raise error
        if self._fault is not None:
            fault, self._fault = self._fault, None
            raise PilError(fault)

    def run_until(self, until: int) -> None:
        """Run the firmware and the peripherals until tick `until`. A Ctrl-C while the
        firmware runs (in a hook: unicorn drops an exception raised there) is raised
        once its block returns (`codegen.interrupts`)."""
        with interrupts_noted():
            self._run_until(until)

    def _run_until(self, until: int) -> None:
        while True:
            self._process_events()
            for listener in self.listeners:
                listener(self)
            if self.now >= until:
                return
            if self._take_exception():
                continue
            upcoming = self.next_event()
            horizon = until if upcoming is None else min(upcoming, until)
            if self.sleep_pc is not None:
                priority = self.nvic.execution_priority(False)
                if self.nvic.pending and self.nvic.preempting(priority) is not None:
                    self.pc = self.sleep_pc + 2  # woken with PRIMASK set: not taken
                    self.sleep_pc = None
                    continue
                self.now = max(self.now, horizon)
                continue
            self._execute(horizon)

    def run_for(self, ticks: int) -> None:
        self.run_until(self.now + ticks)

    def _execute(self, deadline: int) -> None:
        self._deadline = max(deadline, self.now + 1)
        self._block_end = self.now
        try:
            self.uc.emu_start(self.pc | 1, 0xFFFFFFFF)
        except UcError as error:
            if self.error is None and self._fault is None:
                pc = self.uc.reg_read(uc_arm.UC_ARM_REG_PC)
                self._fault = f"unicorn stopped at pc 0x{pc:08x}: {error}: a HardFault on the chip"
        raise_noted()
        self.now = max(self.now, self._block_end)
        self._raise_error()
        if self._returning:
            self._returning = False
            self._exception_return()
            return
        if self.sleep_pc is not None:
            return
        self.pc = self.uc.reg_read(uc_arm.UC_ARM_REG_PC)
        if self._after_store is not None:
            store, self._after_store = self._after_store, None
            self._step_over_store(*store)

    def _step_over_store(self, address: int, value: int) -> None:
        """A stop asked for in a peripheral write callback lands in one of two places
        (as unicorn 2.1 behaves): on the store itself, whose write has happened but
        which has not retired (resuming there would write again), or, for a store in
        an IT block, after the end of the IT block. The first case is told by the
        instruction at the PC: a store of `value` to `address`. It is retired here;
        only a single store without writeback can be; inside an IT block the IT state
        advances as ITAdvance() does (ARMv7-M A7.3.2)."""
        code = bytes(self.uc.mem_read(self.pc, 4))
        size = thumb_instruction_size(code[:2])
        instruction = next(_STORES.disasm(code[:size], self.pc), None)
        if instruction is None or instruction.mnemonic.split(".")[0] not in (
            "str",
            "strh",
            "strb",
        ):
            return  # not on a store: the block went on to the end of its IT block
        source, target = instruction.operands
        memory = target.mem
        register = self.uc.reg_read
        target_address = register(_REGISTER[memory.base]) + memory.disp
        if memory.index:
            target_address += register(_REGISTER[memory.index]) << memory.lshift
        width = {"str": 32, "strh": 16, "strb": 8}[instruction.mnemonic.split(".")[0]]
        stored = register(_REGISTER[source.reg]) & ((1 << width) - 1)
        if (target_address & 0xFFFFFFFF, stored) != (address, value):
            return  # a later store, not the one that wrote
        if instruction.writeback or len(instruction.operands) != 2:
            raise PilError(
                f"an interrupt pended by `{instruction.mnemonic} {instruction.op_str}` at"
                f" 0x{self.pc:08x}: preemption right after a store with writeback is not modelled"
            )
        xpsr = self.uc.reg_read(uc_arm.UC_ARM_REG_XPSR)
        it = ((xpsr >> 25) & 3) | (((xpsr >> 10) & 0x3F) << 2)
        if it:
            it = 0 if it & 7 == 0 else (it & 0xE0) | ((it << 1) & 0x1F)
            it = 0 if it & 0xF == 0 else it
            xpsr = (xpsr & ~((3 << 25) | (0x3F << 10))) | ((it & 3) << 25) | ((it >> 2) << 10)
            self.uc.reg_write(uc_arm.UC_ARM_REG_XPSR, xpsr)
        self.pc += size


def bare_image(
    code: bytes = b"\xfe\xe7", *, handlers: dict[int, bytes] | None = None, stack: int = 0x2000_5000
) -> FirmwareImage:
    """A flash image with no ELF behind it, for model tests: a 64-entry vector table,
    `code` at the reset vector (default `b .`), and per exception number a handler's code.
    WFI instructions in `code` and the handlers are found as in an ELF's Thumb code."""
    table_words = 64
    blobs = [code, *(handlers or {}).values()]
    addresses = []
    cursor = FLASH_BASE + 4 * table_words
    for blob in blobs:
        addresses.append(cursor)
        cursor += (len(blob) + 7) // 8 * 8
    vectors = [0] * table_words
    vectors[0] = stack
    vectors[1] = addresses[0] | 1
    for (exception, _), address in zip((handlers or {}).items(), addresses[1:], strict=True):
        vectors[exception] = address | 1
    image = bytearray(b"".join(v.to_bytes(4, "little") for v in vectors))
    for blob, address in zip(blobs, addresses, strict=True):
        image.extend(b"\x00" * (address - FLASH_BASE - len(image)))
        image.extend(blob)
    chunks = [(FLASH_BASE, bytes(image))]
    marks = [(FLASH_BASE, "d"), *((a, "t") for a in addresses)]
    return FirmwareImage(
        Path("<bare image>"), tuple(chunks), {}, _find_wfi(chunks, marks), SRAM_BASE
    )

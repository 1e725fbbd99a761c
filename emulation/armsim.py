"""Run functions of a Cortex-M3 ELF in the unicorn emulator and record what executed.

Why an emulator: instruction counts and cycle estimates of the interrupt handlers come from
the very Thumb-2 code arm-none-eabi-gcc produced, run on many inputs, without a board.
The image is loaded as the startup code would leave it (.data at its run address, .bss
zeroed); no startup code runs. Peripheral space is plain read/write memory, so handler
register writes land and a test can pre-load what a handler reads (a capture register).
One register is not plain memory: the DWT's cycle counter (DWT_CYCCNT, ARMv7-M ARM
C1.8.7) reads as the cycles the call has taken so far, as `emulation.cycles` estimates
them, so a wait on it (the Hall lines' confirmation) runs for as long as on the chip.

A call runs one function under the AAPCS: arguments in r0-r3, the stack at the top of
RAM, LR pointing at a return address outside the image where emulation stops. Anything
else, an unmapped or forbidden access, an undefined instruction or a runaway loop,
raises `SimulationError` naming the PC and the address.

Each executed instruction is recorded with the data accesses it made (address, size,
read or write), because what they cost depends on where they go: a load from flash
waits for the flash, one from SRAM does not (`emulation.cycles`). The lowest stack
address a call wrote is its measured stack depth.

One defect of unicorn 2.1 is worked around: the IT state of an IT block can outlive the
block when its last instructions are conditional stores seen by the memory hooks, so the
instructions after it ran as if still inside the block, some of them skipped
(unicorn-engine/unicorn#2309; GCC gives the improved_r search such a block). The
emulator knows every IT block of the image and clears stale IT bits of the CPSR at the
first instruction that runs outside the block.
"""

from __future__ import annotations

import difflib
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from enum import Enum
from pathlib import Path
from typing import NamedTuple

from elftools.elf.constants import P_FLAGS
from elftools.elf.elffile import ELFFile
from elftools.elf.sections import SymbolTableSection
from unicorn import (
    UC_ARCH_ARM,
    UC_HOOK_CODE,
    UC_HOOK_MEM_INVALID,
    UC_HOOK_MEM_READ,
    UC_HOOK_MEM_WRITE,
    UC_MEM_FETCH_PROT,
    UC_MEM_FETCH_UNMAPPED,
    UC_MEM_READ,
    UC_MEM_READ_PROT,
    UC_MEM_READ_UNMAPPED,
    UC_MEM_WRITE_PROT,
    UC_MEM_WRITE_UNMAPPED,
    UC_MODE_MCLASS,
    UC_MODE_THUMB,
    UC_PROT_EXEC,
    UC_PROT_READ,
    UC_PROT_WRITE,
    Uc,
    UcError,
)
from unicorn import arm_const as uc_arm

from codegen.interrupts import interrupts_noted
from emulation.cycles import disassemble, estimate_cycles

PAGE = 0x1000  # unicorn maps whole 4 KiB pages
STM32F103_RAM_BASE = 0x2000_0000
STM32F103_RAM_SIZE = 20 * 1024  # STM32F103x8/xB
PERIPHERAL_REGIONS = (
    (0x4000_0000, 0x4003_0000),  # APB1, APB2, AHB (TIM1 at 0x40012C00, GPIO, ADC, ...)
    (0xE000_0000, 0xE010_0000),  # private peripheral bus: NVIC, SCB, SysTick
)
#: DWT_CYCCNT: reads as the call's cycles so far (see the module's docstring)
CYCLE_COUNTER = 0xE000_1004
# LR holds this (| 1 for Thumb) during a call; it lies outside every mapping, and
# emulation stops when the PC reaches it, before anything is fetched there.
RETURN_ADDRESS = 0x0FFF_FFF0
_CORE_REGISTERS = (
    *(getattr(uc_arm, f"UC_ARM_REG_R{n}") for n in range(13)),
    uc_arm.UC_ARM_REG_SP,
    uc_arm.UC_ARM_REG_LR,
    uc_arm.UC_ARM_REG_PC,
)
_SYMBOL_TYPES = ("STT_FUNC", "STT_OBJECT", "STT_NOTYPE")
_ACCESS_NAMES = {
    UC_MEM_READ_UNMAPPED: "read from unmapped address",
    UC_MEM_WRITE_UNMAPPED: "write to unmapped address",
    UC_MEM_FETCH_UNMAPPED: "instruction fetch from unmapped address",
    UC_MEM_READ_PROT: "read from non-readable address",
    UC_MEM_WRITE_PROT: "write to read-only address",
    UC_MEM_FETCH_PROT: "instruction fetch from non-executable address",
}


class WriteRule(Enum):
    """How a store to a register combines with the word there (`combine_on_write`)."""

    SET = "write 1 to set"
    CLEAR = "rc_w0"


SET, CLEAR = WriteRule.SET, WriteRule.CLEAR


class SimulationError(RuntimeError):
    """The emulated code did something a correct handler never does, or the call was bad."""


@dataclass(frozen=True)
class Segment:
    """A PT_LOAD program header's contents at its run address, .bss zeros included."""

    address: int
    data: bytes
    writable: bool
    executable: bool


@dataclass(frozen=True)
class Symbol:
    name: str
    address: int  # the Thumb bit of a function is cleared
    size: int
    is_function: bool


@dataclass(frozen=True)
class ArmImage:
    path: Path
    segments: tuple[Segment, ...]
    symbols: dict[str, Symbol]
    ambiguous: frozenset[str] = field(default_factory=frozenset)
    #: ARM ELF mapping symbols, sorted: (address, "t" for Thumb code or "d" for data such
    #: as a literal pool inside a function).
    mapping: tuple[tuple[int, str], ...] = ()

    def symbol(self, name: str) -> Symbol:
        if name in self.ambiguous:
            raise SimulationError(f"{self.path}: symbol {name!r} is defined more than once")
        if name not in self.symbols:
            near = difflib.get_close_matches(name, self.symbols, n=3)
            hint = f" (did you mean {', '.join(near)}?)" if near else ""
            raise SimulationError(f"{self.path}: no symbol {name!r}{hint}")
        return self.symbols[name]


class Access(NamedTuple):
    """One data transfer of an instruction, as the bus sees it."""

    address: int
    size: int  # bytes
    write: bool


class Step(NamedTuple):
    """One executed instruction. A UDIV/SDIV also records (Rn, Rm) as read before it ran,
    because its cycle count depends on the values; every instruction records its data
    accesses in program order (an LDM or PUSH one per register)."""

    address: int
    size: int
    divide_operands: tuple[int, int] | None = None
    accesses: tuple[Access, ...] = ()


@dataclass(frozen=True)
class CallResult:
    instructions: int  # executed; condition-failed IT-block instructions are not counted
    trace: tuple[Step, ...]
    return_value: int  # r0
    stack_bytes: int  # below the SP at the call: the deepest stack write it made
    memory: CortexM3Sim = field(repr=False, compare=False)

    @property
    def cycles(self) -> int:
        """`emulation.cycles.estimate_cycles` with its defaults (computed when asked)."""
        return estimate_cycles(self.trace, self.memory).cycles


def _read_mapping(elf: ELFFile) -> tuple[tuple[int, str], ...]:
    """$t / $a / $d mapping symbols (AAELF 5.5.5): where code and data start."""
    marks = set()
    for table in elf.iter_sections():
        if not isinstance(table, SymbolTableSection):
            continue
        for entry in table.iter_symbols():
            name = entry.name
            if name[:2] in ("$t", "$a", "$d") and (len(name) == 2 or name[2] == "."):
                marks.add((entry["st_value"] & ~1, "d" if name[1] == "d" else "t"))
    return tuple(sorted(marks))


def _read_symbols(elf: ELFFile) -> tuple[dict[str, Symbol], frozenset[str]]:
    """Defined functions, objects and labels by name, and the names that are not unique.

    A global definition wins over local ones (a static of the same name elsewhere); two
    different definitions of equal binding make the name ambiguous.
    """
    symbols: dict[str, Symbol] = {}
    is_global: dict[str, bool] = {}
    ambiguous: set[str] = set()
    for table in elf.iter_sections():
        if not isinstance(table, SymbolTableSection):
            continue
        for entry in table.iter_symbols():
            kind = entry["st_info"]["type"]
            # "$t", "$d" and "$a" are mapping symbols marking code and data, not names.
            named = bool(entry.name) and not entry.name.startswith("$")
            if not named or kind not in _SYMBOL_TYPES or entry["st_shndx"] == "SHN_UNDEF":
                continue
            is_function = kind == "STT_FUNC"
            value = entry["st_value"] & ~1 if is_function else entry["st_value"]
            symbol = Symbol(entry.name, value, entry["st_size"], is_function)
            binds_global = entry["st_info"]["bind"] != "STB_LOCAL"
            previous = symbols.get(entry.name)
            if previous is None or (binds_global and not is_global[entry.name]):
                symbols[entry.name] = symbol
                is_global[entry.name] = binds_global
                ambiguous.discard(entry.name)
            elif previous.address != value and binds_global == is_global[entry.name]:
                ambiguous.add(entry.name)
    return symbols, frozenset(ambiguous)


def load_elf(path: str | Path) -> ArmImage:
    """Loadable segments and named symbols of a 32-bit little-endian ARM executable."""
    path = Path(path)
    with path.open("rb") as stream:
        elf = ELFFile(stream)
        if elf["e_machine"] != "EM_ARM" or elf.elfclass != 32 or not elf.little_endian:
            raise SimulationError(f"{path}: not a 32-bit little-endian ARM ELF")
        segments = tuple(
            Segment(
                address=segment["p_vaddr"],
                data=segment.data().ljust(segment["p_memsz"], b"\0"),
                writable=bool(segment["p_flags"] & P_FLAGS.PF_W),
                executable=bool(segment["p_flags"] & P_FLAGS.PF_X),
            )
            for segment in elf.iter_segments()
            if segment["p_type"] == "PT_LOAD" and segment["p_memsz"] > 0
        )
        symbols, ambiguous = _read_symbols(elf)
        mapping = _read_mapping(elf)
    return ArmImage(path, segments, symbols, ambiguous, mapping)


def _divide_sites(segments: Sequence[Segment]) -> dict[int, tuple[int, int]]:
    """Address -> (Rn, Rm) register ids of every UDIV/SDIV encoding in executable code.

    T1 encodings: 0xFBB0|Rn (UDIV) or 0xFB90|Rn (SDIV), then 0xF0F0|Rd<<8|Rm. A match in a
    literal pool is harmless: only executed addresses are ever looked up.
    """
    sites: dict[int, tuple[int, int]] = {}
    for segment in segments:
        if not segment.executable:
            continue
        code = segment.data
        for offset in range(0, len(code) - 3, 2):
            first = int.from_bytes(code[offset : offset + 2], "little")
            second = int.from_bytes(code[offset + 2 : offset + 4], "little")
            if first & 0xFFF0 in (0xFBB0, 0xFB90) and second & 0xF0F0 == 0xF0F0:
                sites[segment.address + offset] = (
                    _CORE_REGISTERS[first & 0xF],
                    _CORE_REGISTERS[second & 0xF],
                )
    return sites


#: The IT state in the CPSR: IT[7:2] in bits 15:10, IT[1:0] in bits 26:25.
_CPSR_IT_BITS = (0x3F << 10) | (0x3 << 25)


def _thumb_size(halfword: int) -> int:
    """Bytes of the Thumb instruction whose first halfword is `halfword`."""
    return 4 if halfword >> 11 in (0b11101, 0b11110, 0b11111) else 2


def _it_blocks(segments: Sequence[Segment]) -> dict[int, int]:
    """Address of every IT instruction (0xBF00 | firstcond << 4 | mask, mask != 0) in
    executable code -> the address just past the last instruction of its block. A match
    in a literal pool or in the second half of a 32-bit instruction is harmless: only
    executed instruction addresses are ever looked up."""
    blocks: dict[int, int] = {}
    for segment in segments:
        if not segment.executable:
            continue
        code = segment.data
        for offset in range(0, len(code) - 1, 2):
            halfword = int.from_bytes(code[offset : offset + 2], "little")
            mask = halfword & 0xF
            if halfword & 0xFF00 != 0xBF00 or mask == 0:
                continue
            length = 4 - ((mask & -mask).bit_length() - 1)  # the lowest set bit ends it
            end = offset + 2
            for _ in range(length):
                if end + 2 > len(code):
                    break
                end += _thumb_size(int.from_bytes(code[end : end + 2], "little"))
            blocks[segment.address + offset] = segment.address + end
    return blocks


def _page_permissions(image: ArmImage, ram_base: int, ram_size: int) -> dict[int, int]:
    """Page number -> unicorn protection, the union over everything that page holds."""
    pages: dict[int, int] = {}

    def cover(start: int, end: int, protection: int) -> None:
        for page in range(start // PAGE, (end + PAGE - 1) // PAGE):
            pages[page] = pages.get(page, 0) | protection

    for segment in image.segments:
        protection = UC_PROT_READ
        protection |= UC_PROT_WRITE if segment.writable else 0
        protection |= UC_PROT_EXEC if segment.executable else 0
        cover(segment.address, segment.address + len(segment.data), protection)
    # RAM may hold code copied there (.ramfunc), so it is executable too.
    cover(ram_base, ram_base + ram_size, UC_PROT_READ | UC_PROT_WRITE | UC_PROT_EXEC)
    for start, end in PERIPHERAL_REGIONS:
        cover(start, end, UC_PROT_READ | UC_PROT_WRITE)
    return pages


class CortexM3Sim:
    """An emulated Cortex-M3 holding one image; `call` runs one function of it."""

    def __init__(
        self,
        image: ArmImage,
        *,
        ram_base: int = STM32F103_RAM_BASE,
        ram_size: int = STM32F103_RAM_SIZE,
    ) -> None:
        self.image = image
        self.stack_top = ram_base + ram_size
        # Static data (.data, .bss) ends here; the stack grows down towards it.
        self.stack_limit = max(
            (
                s.address + len(s.data)
                for s in image.segments
                if s.writable and ram_base <= s.address < self.stack_top
            ),
            default=ram_base,
        )
        for segment in image.segments:
            end = segment.address + len(segment.data)
            if segment.writable and ram_base <= segment.address < self.stack_top < end:
                raise SimulationError(
                    f"{image.path}: RAM segment at 0x{segment.address:08x} ends at 0x{end:08x}, "
                    f"past the end of the {ram_size} bytes of RAM"
                )
        self._uc = Uc(UC_ARCH_ARM, UC_MODE_THUMB | UC_MODE_MCLASS)
        if hasattr(uc_arm, "UC_CPU_ARM_CORTEX_M3"):
            self._uc.ctl_set_cpu_model(uc_arm.UC_CPU_ARM_CORTEX_M3)
        self._map(_page_permissions(image, ram_base, ram_size))
        for segment in image.segments:
            self._uc.mem_write(segment.address, segment.data)
        self._divides = _divide_sites(image.segments)
        self._it_blocks = _it_blocks(image.segments)
        self._it_span: tuple[int, int] | None = None  # the IT block running now
        self._steps: list[Step] = []
        self._accesses: list[Access] = []  # of the instruction running now
        self._fault: tuple[int, int, int, int] | None = None  # access, address, size, pc
        self._done_on_read: dict[int, int] = {}  # register -> bits that read as done
        self._write_rules: dict[int, WriteRule] = {}  # register -> how a write acts
        self._written: list[tuple[int, int]] = []  # (register, word before the write)
        #: register -> its value from the call's steps so far (`count_on_read`)
        self._counting: dict[int, Callable[[Sequence[Step]], int]] = {}
        self._uc.hook_add(UC_HOOK_CODE, self._on_instruction)
        self._uc.hook_add(UC_HOOK_MEM_READ | UC_HOOK_MEM_WRITE, self._on_access)
        self._uc.hook_add(UC_HOOK_MEM_INVALID, self._on_invalid_access)

    def _map(self, pages: dict[int, int]) -> None:
        """Map runs of consecutive pages with equal protection as one region each."""
        run_start: int | None = None
        ordered = sorted(pages)
        for index, page in enumerate(ordered):
            if run_start is None:
                run_start = page
            following = ordered[index + 1] if index + 1 < len(ordered) else None
            if following != page + 1 or pages[following] != pages[page]:
                size = (page + 1 - run_start) * PAGE
                self._uc.mem_map(run_start * PAGE, size, pages[page])
                run_start = None

    def _on_instruction(self, uc: Uc, address: int, size: int, _data: object) -> None:
        self._close_step()
        self._apply_write_rules()
        span = self._it_span
        if span is not None and not span[0] <= address < span[1]:
            # the first instruction outside the block: no IT state may remain (#2309)
            self._it_span = None
            cpsr = uc.reg_read(uc_arm.UC_ARM_REG_CPSR)
            if cpsr & _CPSR_IT_BITS:
                uc.reg_write(uc_arm.UC_ARM_REG_CPSR, cpsr & ~_CPSR_IT_BITS)
        end = self._it_blocks.get(address)
        if end is not None:
            self._it_span = (address, end)
        registers = self._divides.get(address)
        if registers is None:
            self._steps.append(Step(address, size))
        else:
            operands = (uc.reg_read(registers[0]), uc.reg_read(registers[1]))
            self._steps.append(Step(address, size, operands))

    def _on_access(
        self, uc: Uc, access: int, address: int, size: int, _value: int, _data: object
    ) -> None:
        self._accesses.append(Access(address, size, access != UC_MEM_READ))
        if access == UC_MEM_READ and address == CYCLE_COUNTER:
            cycles = estimate_cycles(self._steps, self).cycles & 0xFFFF_FFFF
            uc.mem_write(address, cycles.to_bytes(4, "little"))
            return
        if access == UC_MEM_READ and address in self._counting:
            value = self._counting[address](self._steps) & 0xFFFF_FFFF
            uc.mem_write(address, value.to_bytes(4, "little"))
            return
        if access != UC_MEM_READ and address in self._write_rules:
            # the hook runs before the store: the word it replaces, for the rule after it
            self._written.append((address, int.from_bytes(uc.mem_read(address, 4), "little")))
        mask = self._done_on_read.get(address) if access == UC_MEM_READ else None
        if mask:
            word = int.from_bytes(uc.mem_read(address, 4), "little")
            uc.mem_write(address, (word & ~mask).to_bytes(4, "little"))

    def finish_on_read(self, address: int, mask: int) -> None:
        """Bits of a register that read back as 0: an operation the hardware finishes by
        the time software polls it (such as ADC_CR2.CAL, the calibration), which plain
        memory would otherwise hold set forever."""
        self._done_on_read[address] = self._done_on_read.get(address, 0) | mask

    def count_on_read(self, address: int, value_of: Callable[[Sequence[Step]], int] | None) -> None:
        """A register that moves while the call runs (a timer's counter): each read takes
        `value_of` the call's steps so far (what the caller prices them at); None makes it
        plain memory again."""
        if value_of is None:
            self._counting.pop(address, None)
        else:
            self._counting[address] = value_of

    def combine_on_write(self, address: int, rule: WriteRule) -> None:
        """A register whose bits a store does not simply replace: `SET` for write 1 to
        set (an NVIC ISPR word: a 0 bit leaves its interrupt's pending state, PM0056
        4.3.4), `CLEAR` for rc_w0 (a status register: a 0 bit clears its flag, a 1 bit
        leaves it, RM0008). Plain memory would take a store's word as the register's."""
        self._write_rules[address] = rule

    def _apply_write_rules(self) -> None:
        """Combine each word stored to a ruled register since the last instruction began
        with the word it replaced."""
        for address, before in self._written:
            stored = self.read_u32(address)
            combined = before | stored if self._write_rules[address] is SET else before & stored
            self.write_u32(address, combined)
        self._written = []

    def _close_step(self) -> None:
        """Attach the accesses made since the last instruction began to that instruction."""
        if self._accesses:
            self._steps[-1] = self._steps[-1]._replace(accesses=tuple(self._accesses))
            self._accesses = []

    def _on_invalid_access(
        self, uc: Uc, access: int, address: int, size: int, _value: int, _data: object
    ) -> bool:
        self._fault = (access, address, size, uc.reg_read(uc_arm.UC_ARM_REG_PC))
        return False  # do not recover: emu_start raises

    def read_code(self, address: int, size: int) -> bytes:
        return self.read_bytes(address, size)

    def read_bytes(self, address: int, size: int) -> bytes:
        try:
            return bytes(self._uc.mem_read(address, size))
        except UcError as error:
            raise SimulationError(f"cannot read {size} bytes at 0x{address:08x}: {error}") from None

    def write_bytes(self, address: int, data: bytes) -> None:
        try:
            self._uc.mem_write(address, data)
        except UcError as error:
            raise SimulationError(
                f"cannot write {len(data)} bytes at 0x{address:08x}: {error}"
            ) from None

    def read_u16(self, address: int) -> int:
        return int.from_bytes(self.read_bytes(address, 2), "little")

    def read_u32(self, address: int) -> int:
        return int.from_bytes(self.read_bytes(address, 4), "little")

    def write_u16(self, address: int, value: int) -> None:
        self.write_bytes(address, (value & 0xFFFF).to_bytes(2, "little"))

    def write_u32(self, address: int, value: int) -> None:
        self.write_bytes(address, (value & 0xFFFF_FFFF).to_bytes(4, "little"))

    def call(
        self,
        function: str | int,
        args: Sequence[int] = (),
        *,
        max_instructions: int = 100_000,
    ) -> CallResult:
        """Run `function` (a symbol name or an address) with up to four word arguments."""
        if len(args) > 4:
            raise SimulationError(f"at most 4 register arguments (r0-r3), got {len(args)}")
        if isinstance(function, str):
            entry, name = self.image.symbol(function).address, function
        else:
            entry, name = function & ~1, f"0x{function:08x}"
        uc = self._uc
        for index, register in enumerate(_CORE_REGISTERS[:13]):
            uc.reg_write(register, args[index] & 0xFFFF_FFFF if index < len(args) else 0)
        uc.reg_write(uc_arm.UC_ARM_REG_SP, self.stack_top)
        uc.reg_write(uc_arm.UC_ARM_REG_LR, RETURN_ADDRESS | 1)
        self._steps = []
        self._accesses = []
        self._fault = None
        self._it_span = None
        try:
            with interrupts_noted():  # a Ctrl-C in a hook is raised after the call
                uc.emu_start(entry | 1, RETURN_ADDRESS, count=max_instructions)
        except UcError as error:
            raise SimulationError(self._failure(name, str(error))) from None
        finally:
            self._close_step()
            self._apply_write_rules()
        pc = uc.reg_read(uc_arm.UC_ARM_REG_PC)
        if pc != RETURN_ADDRESS:
            raise SimulationError(
                self._failure(name, f"no return after {max_instructions} instructions")
            )
        trace = tuple(self._steps)
        deepest = min(
            (
                a.address
                for step in trace
                for a in step.accesses
                if a.write and self.stack_limit <= a.address < self.stack_top
            ),
            default=self.stack_top,
        )
        return CallResult(
            instructions=len(trace),
            memory=self,
            trace=trace,
            return_value=uc.reg_read(uc_arm.UC_ARM_REG_R0),
            stack_bytes=self.stack_top - deepest,
        )

    def _describe(self, address: int) -> str:
        try:
            return disassemble(self.read_bytes(address, 4), address)
        except SimulationError:
            return "unreadable"

    def _failure(self, name: str, problem: str) -> str:
        pc = self._uc.reg_read(uc_arm.UC_ARM_REG_PC)
        text = f"emulating {name}: {problem}"
        if self._fault is not None:
            access, address, size, pc = self._fault
            what = _ACCESS_NAMES.get(access, f"invalid access {access}")
            text += f"; {what} 0x{address:08x} ({size} bytes)"
        text += f"; PC=0x{pc:08x}"
        if self._steps:
            last = self._steps[-1].address
            text += f", last executed 0x{last:08x} ({self._describe(last)})"
        return f"{text} [{self.image.path.name}]"

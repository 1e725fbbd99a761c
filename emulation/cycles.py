"""Cortex-M3 cycle estimate of an executed instruction trace.

The emulator (`emulation.armsim`) says *which* instructions ran and what memory they
touched; this module says what they cost: first by the Cortex-M3 Technical Reference
Manual r2p1 (ARM DDI 0337I), Table 3-1 "Cortex-M3 instruction set summary" and section
"Load/store timings", which assume zero wait states; then what the STM32F103's flash
wait states, prefetch buffer and System bus add (`emulation.memory`, whose `ASSUMPTIONS`
the bench prints), unless `timing` is `ZERO_WAIT`.

Choices where the TRM gives a range or depends on operand values (P is the pipeline
refill, 1 to 3 cycles by the TRM; `pipeline_refill` sets it, default 3, the worst case):

* data processing, MOVW/MOVT, bit field, saturate, extend, CLZ, IT, NOP: 1 (+P when the
  destination is the PC). IT may fold into the previous 16-bit instruction for 0 cycles;
  not modelled (counted as 1).
* instructions of an IT block whose condition fails: 1 each (issued as a NOP). The
  emulator does not report them, so they are found by walking the IT block statically.
* MUL 1, MLA/MLS 2. UMULL/SMULL "3 to 5" and UMLAL/SMLAL "4 to 7" terminate early on
  small operands by rules ARM does not publish: always charged the worst, 5 and 7.
* UDIV/SDIV "2 to 12", early termination by an unpublished rule. ``udiv_mode="estimate"``
  charges ``2 + ceil(b / 4)`` with b the number of significant bits of the quotient
  magnitude (so 2..10 for 32-bit operands): an estimate, not a datasheet figure.
  ``udiv_mode="worst"`` charges 12.
* single loads (LDR, LDRB, LDRH, LDRSB, LDRSH, LDREX, literal loads): 2, +P into the PC.
  Pipelining of neighbouring loads (which can save one cycle each) is not modelled.
* single stores: 1 with an immediate offset ("STR Rx,[Ry,#imm] is always one cycle"),
  2 with a register offset (nothing pipelines after it); STREX 2 (timed like a load).
* LDRD/STRD, LDM/STM, PUSH/POP: 1 + N registers, +P when the PC is loaded.
* branches B, B<cond>, BL, BX, BLX, CBZ, CBNZ: 1 + P taken, 1 not taken; taken-ness is
  read from the trace (the next executed address is not the fall-through address).
  TBB/TBH 2 + P. The call's final return is a taken branch.
* MRS/MSR/CPS 2 (the TRM's upper figure); DMB/DSB 1 (barrier time B has minimum 0),
  ISB 1 + P.

`isr_cycles` adds the exception entry and exit of `emulation.memory` (12 and 10 with
zero wait states). The handler's own return instruction is still charged 1 + P, an
overlap with the exit sequence that this model leaves in, so ISR totals err high by at
most P.
"""

from __future__ import annotations

import math
from collections import Counter
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from enum import StrEnum
from functools import lru_cache
from typing import TYPE_CHECKING, Literal, Protocol

import capstone  # type: ignore[import-untyped]
from capstone import arm_const as arm

from emulation.memory import (
    STM32F103_72MHZ,
    Executed,
    MemoryTiming,
    exception_entry_cycles,
    exception_exit_cycles,
    memory_stalls,
)

if TYPE_CHECKING:
    from emulation.armsim import Step

UdivMode = Literal["estimate", "worst"]

DIVIDE_WORST_CYCLES = 12  # UDIV/SDIV, TRM Table 3-1 "2 to 12"
LONG_MULTIPLY_WORST_CYCLES = 5  # UMULL/SMULL "3 to 5"
LONG_MULTIPLY_ACCUMULATE_WORST_CYCLES = 7  # UMLAL/SMLAL "4 to 7"


class InstructionClass(StrEnum):
    ALU = "alu"
    MULTIPLY = "mul"
    MULTIPLY_ACCUMULATE = "mla"
    LONG_MULTIPLY = "long_mul"
    LONG_MULTIPLY_ACCUMULATE = "long_mla"
    DIVIDE = "divide"
    LOAD = "load"
    STORE = "store"
    LOAD_MULTIPLE = "load_multiple"
    STORE_MULTIPLE = "store_multiple"
    BRANCH = "branch"
    TABLE_BRANCH = "table_branch"
    IT = "it"
    IT_SKIPPED = "it_skipped"
    SYSTEM = "system"
    BARRIER = "barrier"
    HINT = "hint"
    MEMORY_STALL = "memory_stall"  # wait states and bus contention (emulation.memory)


class CodeMemory(Protocol):
    """Where the executed instruction bytes are read back from (a `CortexM3Sim`)."""

    def read_code(self, address: int, size: int) -> bytes: ...


@dataclass(frozen=True)
class Decoded:
    """The cost-relevant facts of one instruction, independent of its operand values.

    `cycles` excludes the refill P; `refill` says when P is added: never, always (the
    instruction writes the PC unconditionally) or when the trace shows the branch taken.
    """

    mnemonic: str
    kind: InstructionClass
    cycles: int
    refill: Literal["never", "always", "if_taken"]
    signed_divide: bool = False
    it_length: int = 0  # instructions an IT covers (1 to 4), 0 for every other instruction
    #: B, B<cond>, BL, CBZ, CBNZ: the target relative to the instruction's address, which
    #: the prefetch unit knows at decode (TRM 1.4); None for every other instruction.
    target_offset: int | None = None
    conditional: bool = False


@dataclass(frozen=True)
class CycleBreakdown:
    """Estimated cycles of one executed trace, split by instruction class.

    `instructions` counts executed instructions per class, plus the condition-failed
    instructions of IT blocks under `InstructionClass.IT_SKIPPED` (which the emulator's
    instruction count does not include). What the memory system added is under
    `InstructionClass.MEMORY_STALL` (no instructions), split in `fetch_stall` (waiting
    for code) and `data_stall` (waiting for flash data or the System bus).
    """

    cycles: int
    instructions: Mapping[InstructionClass, int]
    cycles_by_class: Mapping[InstructionClass, int]
    taken_branches: int
    not_taken_branches: int
    udiv_mode: UdivMode
    pipeline_refill: int
    timing: MemoryTiming = STM32F103_72MHZ
    fetch_stall: int = 0
    data_stall: int = 0
    flash_data_reads: int = 0
    peripheral_accesses: int = 0

    def lines(self) -> list[str]:
        """One line per class, `class  count  cycles`, in the enum's order, for reports."""
        rows = [
            f"{kind.value:<15} {self.instructions.get(kind, 0):>6} {self.cycles_by_class[kind]:>7}"
            for kind in InstructionClass
            if self.instructions.get(kind) or self.cycles_by_class.get(kind)
        ]
        rows.append(f"{'total':<15} {sum(self.instructions.values()):>6} {self.cycles:>7}")
        return rows


_BRANCHES = {
    arm.ARM_INS_B,
    arm.ARM_INS_BL,
    arm.ARM_INS_BLX,
    arm.ARM_INS_BX,
    arm.ARM_INS_CBZ,
    arm.ARM_INS_CBNZ,
}
_LOADS = {
    arm.ARM_INS_LDR,
    arm.ARM_INS_LDRB,
    arm.ARM_INS_LDRH,
    arm.ARM_INS_LDRSB,
    arm.ARM_INS_LDRSH,
    arm.ARM_INS_LDRT,
    arm.ARM_INS_LDRBT,
    arm.ARM_INS_LDRHT,
    arm.ARM_INS_LDRSBT,
    arm.ARM_INS_LDRSHT,
    arm.ARM_INS_LDREX,
    arm.ARM_INS_LDREXB,
    arm.ARM_INS_LDREXH,
    arm.ARM_INS_PLD,
}
_STORES = {
    arm.ARM_INS_STR,
    arm.ARM_INS_STRB,
    arm.ARM_INS_STRH,
    arm.ARM_INS_STRT,
    arm.ARM_INS_STRBT,
    arm.ARM_INS_STRHT,
}
_STORE_EXCLUSIVES = {arm.ARM_INS_STREX, arm.ARM_INS_STREXB, arm.ARM_INS_STREXH}
_LOAD_MULTIPLES = {arm.ARM_INS_LDM, arm.ARM_INS_LDMDB, arm.ARM_INS_POP}
_STORE_MULTIPLES = {arm.ARM_INS_STM, arm.ARM_INS_STMDB, arm.ARM_INS_PUSH}
_FIXED: dict[int, tuple[InstructionClass, int]] = {
    arm.ARM_INS_MUL: (InstructionClass.MULTIPLY, 1),
    arm.ARM_INS_MLA: (InstructionClass.MULTIPLY_ACCUMULATE, 2),
    arm.ARM_INS_MLS: (InstructionClass.MULTIPLY_ACCUMULATE, 2),
    arm.ARM_INS_UMULL: (InstructionClass.LONG_MULTIPLY, LONG_MULTIPLY_WORST_CYCLES),
    arm.ARM_INS_SMULL: (InstructionClass.LONG_MULTIPLY, LONG_MULTIPLY_WORST_CYCLES),
    arm.ARM_INS_UMLAL: (
        InstructionClass.LONG_MULTIPLY_ACCUMULATE,
        LONG_MULTIPLY_ACCUMULATE_WORST_CYCLES,
    ),
    arm.ARM_INS_SMLAL: (
        InstructionClass.LONG_MULTIPLY_ACCUMULATE,
        LONG_MULTIPLY_ACCUMULATE_WORST_CYCLES,
    ),
    arm.ARM_INS_LDRD: (InstructionClass.LOAD_MULTIPLE, 3),  # 1 + N, N = 2
    arm.ARM_INS_STRD: (InstructionClass.STORE_MULTIPLE, 3),
    arm.ARM_INS_MRS: (InstructionClass.SYSTEM, 2),
    arm.ARM_INS_MSR: (InstructionClass.SYSTEM, 2),
    arm.ARM_INS_CPS: (InstructionClass.SYSTEM, 2),
    arm.ARM_INS_DMB: (InstructionClass.BARRIER, 1),
    arm.ARM_INS_DSB: (InstructionClass.BARRIER, 1),
    arm.ARM_INS_NOP: (InstructionClass.HINT, 1),
    arm.ARM_INS_YIELD: (InstructionClass.HINT, 1),
    arm.ARM_INS_SEV: (InstructionClass.HINT, 1),
    arm.ARM_INS_WFE: (InstructionClass.HINT, 1),
    arm.ARM_INS_WFI: (InstructionClass.HINT, 1),
}


@lru_cache(maxsize=1)
def _disassembler() -> capstone.Cs:
    engine = capstone.Cs(capstone.CS_ARCH_ARM, capstone.CS_MODE_THUMB | capstone.CS_MODE_MCLASS)
    engine.detail = True
    return engine


def _first_instruction(code: bytes, address: int = 0) -> capstone.CsInsn:
    for instruction in _disassembler().disasm(code, address, count=1):
        return instruction
    raise ValueError(f"capstone cannot decode Thumb instruction bytes {code.hex()}")


def disassemble(code: bytes, address: int) -> str:
    """`mnemonic operands` of the instruction in `code`, for error messages."""
    try:
        instruction = _first_instruction(code, address)
    except ValueError:
        return f"undecodable {code.hex()}"
    return f"{instruction.mnemonic} {instruction.op_str}".strip()


def thumb_instruction_size(first_halfword: bytes) -> int:
    """2 or 4: a Thumb-2 instruction is 32-bit when bits 15:11 are 0b11101, 0b11110 or 0b11111."""
    return 4 if int.from_bytes(first_halfword, "little") >> 11 in (0x1D, 0x1E, 0x1F) else 2


def _register_operands(instruction: capstone.CsInsn) -> list[int]:
    return [op.reg for op in instruction.operands if op.type == arm.ARM_OP_REG]


@lru_cache(maxsize=4096)
def decode(code: bytes) -> Decoded:
    """Classify one Thumb instruction (its exact bytes) for the cycle model."""
    instruction = _first_instruction(code)
    ident = instruction.id
    mnemonic = instruction.mnemonic
    registers = _register_operands(instruction)
    writes_pc = bool(registers) and registers[0] == arm.ARM_REG_PC

    if ident in _BRANCHES:
        conditional = ident in (arm.ARM_INS_CBZ, arm.ARM_INS_CBNZ) or (
            ident == arm.ARM_INS_B and instruction.cc not in (arm.ARM_CC_AL, arm.ARM_CC_INVALID)
        )
        immediates = [op.imm for op in instruction.operands if op.type == arm.ARM_OP_IMM]
        return Decoded(
            mnemonic,
            InstructionClass.BRANCH,
            1,
            "if_taken" if conditional else "always",
            target_offset=immediates[-1] if immediates else None,  # decoded at address 0
            conditional=conditional,
        )
    if ident in (arm.ARM_INS_TBB, arm.ARM_INS_TBH):
        return Decoded(mnemonic, InstructionClass.TABLE_BRANCH, 2, "always")
    if ident == arm.ARM_INS_IT:
        # "itte" covers three instructions: the mnemonic is "it" plus one letter per extra.
        return Decoded(mnemonic, InstructionClass.IT, 1, "never", it_length=len(mnemonic) - 1)
    if ident in (arm.ARM_INS_UDIV, arm.ARM_INS_SDIV):
        return Decoded(
            mnemonic,
            InstructionClass.DIVIDE,
            DIVIDE_WORST_CYCLES,
            "never",
            signed_divide=ident == arm.ARM_INS_SDIV,
        )
    if ident in _LOADS:
        return Decoded(mnemonic, InstructionClass.LOAD, 2, "always" if writes_pc else "never")
    if ident in _STORES:
        register_offset = any(
            op.type == arm.ARM_OP_MEM and op.mem.index != 0 for op in instruction.operands
        )
        return Decoded(mnemonic, InstructionClass.STORE, 2 if register_offset else 1, "never")
    if ident in _STORE_EXCLUSIVES:
        return Decoded(mnemonic, InstructionClass.STORE, 2, "never")
    if ident in _LOAD_MULTIPLES or ident in _STORE_MULTIPLES:
        # LDM/STM list the base register first; PUSH/POP list only the transferred ones.
        count = len(registers) - (0 if ident in (arm.ARM_INS_POP, arm.ARM_INS_PUSH) else 1)
        if ident in _STORE_MULTIPLES:
            return Decoded(mnemonic, InstructionClass.STORE_MULTIPLE, 1 + count, "never")
        loads_pc = arm.ARM_REG_PC in registers
        return Decoded(
            mnemonic,
            InstructionClass.LOAD_MULTIPLE,
            1 + count,
            "always" if loads_pc else "never",
        )
    if ident == arm.ARM_INS_ISB:
        return Decoded(mnemonic, InstructionClass.BARRIER, 1, "always")
    if ident in _FIXED:
        kind, cycles = _FIXED[ident]
        return Decoded(mnemonic, kind, cycles, "never")
    return Decoded(mnemonic, InstructionClass.ALU, 1, "always" if writes_pc else "never")


def divide_cycles(
    dividend: int, divisor: int, *, signed: bool, udiv_mode: UdivMode = "estimate"
) -> int:
    """UDIV/SDIV cycles: 12 in "worst" mode, else 2 + ceil(quotient bits / 4) (an estimate).

    Operands are the raw 32-bit register values. Division by zero (result 0 on a
    Cortex-M3 with CCR.DIV_0_TRP clear) is charged the minimum, 2.
    """
    if udiv_mode == "worst":
        return DIVIDE_WORST_CYCLES
    if signed:
        dividend = abs(dividend - (1 << 32) if dividend & 0x8000_0000 else dividend)
        divisor = abs(divisor - (1 << 32) if divisor & 0x8000_0000 else divisor)
    quotient = dividend // divisor if divisor else 0
    return min(DIVIDE_WORST_CYCLES, 2 + math.ceil(quotient.bit_length() / 4))


def _skipped_in_it_block(
    trace: Sequence[Step], it_index: int, it_length: int, memory: CodeMemory
) -> int:
    """How many instructions of the IT block at trace[it_index] failed their condition.

    The block's instructions follow the IT statically; those the trace does not show next,
    in order, were skipped. Only the last one of a block may branch, so no executed one
    can lead the trace away before the walk ends.
    """
    address = trace[it_index].address + 2
    following = it_index + 1
    skipped = 0
    for _ in range(it_length):
        if following < len(trace) and trace[following].address == address:
            following += 1
        else:
            skipped += 1
        address += thumb_instruction_size(memory.read_code(address, 2))
    return skipped


def estimate_cycles(
    trace: Sequence[Step],
    memory: CodeMemory,
    *,
    udiv_mode: UdivMode = "estimate",
    pipeline_refill: int = 3,
    timing: MemoryTiming = STM32F103_72MHZ,
    after_exception: bool = False,
) -> CycleBreakdown:
    """Cycles of an executed trace (one `CortexM3Sim.call`), by the model in the module doc.

    The last step is the call's return, so a conditional branch there counts as taken.
    `after_exception`: the trace is a handler entered by an exception, whose entry
    already fetched its first instructions (see `isr_cycles`).
    """
    if udiv_mode not in ("estimate", "worst"):
        raise ValueError(f"udiv_mode must be 'estimate' or 'worst', not {udiv_mode!r}")
    if not 1 <= pipeline_refill <= 3:
        raise ValueError(f"pipeline_refill must be 1..3 cycles (TRM), not {pipeline_refill}")
    instructions: Counter[InstructionClass] = Counter()
    cycles: Counter[InstructionClass] = Counter()
    taken = not_taken = 0
    decoded: dict[int, Decoded] = {}  # code does not change during one call
    executed: list[Executed] = []
    for index, step in enumerate(trace):
        info = decoded.get(step.address)
        if info is None:
            info = decoded[step.address] = decode(memory.read_code(step.address, step.size))
        cost = info.cycles
        if info.kind is InstructionClass.DIVIDE:
            if step.divide_operands is None:
                raise ValueError(f"divide at 0x{step.address:08x} has no recorded operands")
            dividend, divisor = step.divide_operands
            cost = divide_cycles(dividend, divisor, signed=info.signed_divide, udiv_mode=udiv_mode)
        jumps = False
        if info.refill != "never":
            following = trace[index + 1].address if index + 1 < len(trace) else None
            if info.refill == "always" or following != step.address + step.size:
                cost += pipeline_refill
                taken += 1
                jumps = True
            else:
                not_taken += 1
        instructions[info.kind] += 1
        cycles[info.kind] += cost
        if info.it_length:
            skipped = _skipped_in_it_block(trace, index, info.it_length, memory)
            instructions[InstructionClass.IT_SKIPPED] += skipped
            cycles[InstructionClass.IT_SKIPPED] += skipped
            cost += skipped
        executed.append(
            Executed(
                address=step.address,
                size=step.size,
                accesses=tuple(step.accesses),  # (address, size, write) each
                cycles=cost,
                jumps=jumps,
                target=None
                if info.target_offset is None
                else (step.address + info.target_offset) & 0xFFFF_FFFF,
                conditional=info.conditional,
                pc_known_after=cost - (pipeline_refill if jumps else 0),
            )
        )
    stalls = memory_stalls(timing, executed, after_exception=after_exception)
    if stalls.total:
        cycles[InstructionClass.MEMORY_STALL] += stalls.total
    return CycleBreakdown(
        cycles=sum(cycles.values()),
        instructions=dict(instructions),
        cycles_by_class=dict(cycles),
        taken_branches=taken,
        not_taken_branches=not_taken,
        udiv_mode=udiv_mode,
        pipeline_refill=pipeline_refill,
        timing=timing,
        fetch_stall=stalls.fetch,
        data_stall=stalls.data,
        flash_data_reads=stalls.flash_data_reads,
        peripheral_accesses=stalls.peripheral_accesses,
    )


def entry_cycles(body: CycleBreakdown, handler_address: int) -> int:
    return exception_entry_cycles(body.timing, handler_address)


def exit_cycles(body: CycleBreakdown) -> int:
    return exception_exit_cycles(body.timing)


def isr_cycles(body: CycleBreakdown, handler_address: int) -> int:
    """Cycles from interrupt request to the interrupted code: entry + handler body + exit,
    with the handler at `handler_address` and the body priced `after_exception`."""
    return entry_cycles(body, handler_address) + body.cycles + exit_cycles(body)

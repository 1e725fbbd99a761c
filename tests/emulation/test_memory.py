"""The STM32F103 memory model (emulation/memory.py) on hand-built traces whose stalls
follow from its stated rules: flash reads of LATENCY + 1 cycles, the two-block
direct-mapped prefetch buffer, D-Code reads with priority over a queued prefetch, the
Cortex-M3 prefetch unit (three words, branch targets at decode), and the System bus for
code in SRAM."""

from __future__ import annotations

from dataclasses import replace

from emulation.memory import (
    STM32F103_72MHZ,
    ZERO_WAIT,
    Executed,
    MemoryTiming,
    exception_entry_cycles,
    exception_exit_cycles,
    memory_stalls,
)

FLASH = 0x0800_0000
SRAM = 0x2000_0000
PERIPHERAL = 0x4001_2C34  # TIM1 CCR1
WAIT = STM32F103_72MHZ.flash_wait_states
assert WAIT == 2
REFILL = 3  # the TRM's P that the traces' branch costs include


def op(
    address: int,
    *,
    size: int = 2,
    cycles: int = 1,
    accesses: tuple[tuple[int, int, bool], ...] = (),
    jumps: bool = False,
    target: int | None = None,
    conditional: bool = False,
    pc_known_after: int = 1,
) -> Executed:
    return Executed(address, size, accesses, cycles, jumps, target, conditional, pc_known_after)


def straight(start: int, count: int, cycles: int = 1) -> list[Executed]:
    """`count` 16-bit instructions from `start`, each `cycles` long."""
    return [op(start + 2 * k, cycles=cycles) for k in range(count)]


def stalls(trace: list[Executed], timing: MemoryTiming = STM32F103_72MHZ) -> list[int]:
    return memory_stalls(timing, trace, after_exception=True).per_step


def test_zero_wait_timing_should_add_nothing() -> None:
    trace = [*straight(FLASH, 4), op(FLASH + 8, accesses=((FLASH + 0x100, 4, False),))]
    assert memory_stalls(ZERO_WAIT, trace, after_exception=False).total == 0


def test_sequential_16_bit_code_should_outrun_nothing() -> None:
    # 8 bytes (four single-cycle instructions) take 4 cycles, a read 3: the prefetch
    # buffer keeps ahead once the block after the entry's has arrived.
    result = stalls(straight(FLASH, 32))
    assert sum(result[4:]) == 0


def test_sequential_32_bit_code_should_wait_for_the_flash() -> None:
    # 8 bytes of 32-bit single-cycle instructions take 2 cycles, a read 3: one stall per
    # block in the long run.
    trace = [op(FLASH + 4 * k, size=4) for k in range(64)]
    result = stalls(trace)
    blocks = 64 * 4 // 8
    assert blocks - 4 <= sum(result) <= blocks + 4


def test_literal_load_from_flash_should_cost_the_wait_states() -> None:
    # Long instructions let the prefetch finish: the flash is idle at the load.
    lead = straight(FLASH, 12, cycles=6)
    load = op(FLASH + 24, cycles=2, accesses=((FLASH + 0x400, 4, False),))
    from_sram = replace(load, accesses=((SRAM + 0x10, 4, False),))
    assert stalls([*lead, load])[-1] == WAIT
    assert stalls([*lead, from_sram])[-1] == 0
    # an LDRD from flash is two D-Code reads, one after the other
    double = replace(
        load, cycles=3, accesses=((FLASH + 0x400, 4, False), (FLASH + 0x404, 4, False))
    )
    assert stalls([*lead, double])[-1] == 2 * WAIT


def test_branch_targets_should_be_fetched_early_only_when_immediate() -> None:
    lead = straight(FLASH, 12, cycles=6)
    far = FLASH + 0x800
    # B to a block outside the buffer: its target is known at decode, so the TRM's refill
    # P = 3 covers the 3-cycle read.
    b = op(FLASH + 24, cycles=1 + REFILL, jumps=True, target=far)
    assert stalls([*lead, b, op(far)])[-1] == 0
    # BX: the target is known after it executes: 1 + LATENCY + 1 cycles to decode > 1 + P
    bx = op(FLASH + 24, cycles=1 + REFILL, jumps=True, pc_known_after=1)
    assert stalls([*lead, bx, op(far)])[-1] == 1 + (WAIT + 1) + 1 - (1 + REFILL)
    # a target already in the prefetch buffer (the block being executed) costs nothing
    near = op(FLASH + 24, cycles=1 + REFILL, jumps=True, pc_known_after=1)
    assert stalls([*lead, near, op(FLASH + 26)])[-1] == 0


def test_a_conditional_branch_not_taken_should_still_fetch_its_target() -> None:
    # The target's block has the parity of the block after the branch: the speculative
    # read replaces it in the direct-mapped buffer, so it is read again.
    lead = straight(FLASH, 12, cycles=6)
    far = FLASH + 0x800
    branch = op(FLASH + 24, target=far, conditional=True)
    after = straight(FLASH + 26, 8)
    quiet = replace(STM32F103_72MHZ, speculative_branch_fetch=False)
    assert sum(stalls([*lead, branch, *after], quiet)[12:]) == 0
    assert sum(stalls([*lead, branch, *after])[12:]) > 0
    # a target in the prefetch buffer costs nothing
    near = replace(branch, target=FLASH + 30)
    assert sum(stalls([*lead, near, *after])[12:]) == 0


def test_code_in_sram_should_share_the_system_bus_with_its_data() -> None:
    lead = straight(SRAM, 8)
    assert sum(stalls(lead)) == 0  # one word per two instructions, the bus is free
    # a store every cycle keeps the System bus busy with data: the fetch starves
    stores = [op(SRAM + 16 + 2 * k, accesses=((PERIPHERAL, 4, True),)) for k in range(16)]
    assert sum(stalls([*lead, *stores])) > 0
    # the same stores from flash code leave the (separate) I-Code fetch alone
    from_flash = [replace(s, address=s.address - SRAM + FLASH) for s in stores]
    assert sum(stalls([*straight(FLASH, 8), *from_flash])[8:]) == 0
    # a jump in SRAM costs the System bus's extra fetch cycle
    bx = op(SRAM + 16, cycles=1 + REFILL, jumps=True, pc_known_after=1)
    assert stalls([*lead, bx, op(SRAM + 0x100)])[-1] == max(
        0, 1 + 1 + STM32F103_72MHZ.system_bus_fetch_penalty + 1 - (1 + REFILL)
    )


def test_exception_entry_and_exit_should_follow_the_stated_formulas() -> None:
    assert exception_entry_cycles(ZERO_WAIT, FLASH) == 12
    assert exception_exit_cycles(ZERO_WAIT) == 10
    # 3 + max(9, 6 + 3 LATENCY): vector and handler reads, a prefetch in flight
    assert exception_entry_cycles(STM32F103_72MHZ, FLASH) == 3 + 6 + 3 * WAIT
    # from SRAM the handler's fetch waits for the push on the System bus
    assert exception_entry_cycles(STM32F103_72MHZ, SRAM) == 3 + 9 + 3 + 1
    assert exception_exit_cycles(STM32F103_72MHZ) == 10 + WAIT

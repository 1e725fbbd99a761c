"""The emulated chip's core: reset, memory map, the exception model (PM0056 2.3, ARMv7-M
B1.5) and WFI, on small hand-written Thumb programs."""

from __future__ import annotations

import subprocess
from pathlib import Path

import pytest
from unicorn import arm_const as uc_arm

from emulation.pil.bus import PilError
from emulation.pil.machine import (
    EXC_RETURN_HANDLER,
    EXC_RETURN_THREAD_MSP,
    SRAM_BASE,
    Machine,
    bare_image,
)
from emulation.pil.scs import IRQ_BASE, SYSTICK

STACK = 0x2000_5000


def assemble(source: str, tmp_path: Path, name: str = "code") -> bytes:
    """Thumb-2 source -> its bytes (arm-none-eabi-as, position-independent snippets)."""
    asm = tmp_path / f"{name}.s"
    asm.write_text(".syntax unified\n.thumb\n.cpu cortex-m3\n" + source + "\n.ltorg\n")
    obj = tmp_path / f"{name}.o"
    subprocess.run(["arm-none-eabi-as", str(asm), "-o", str(obj)], check=True)
    binary = tmp_path / f"{name}.bin"
    subprocess.run(["arm-none-eabi-objcopy", "-O", "binary", str(obj), str(binary)], check=True)
    return binary.read_bytes()


def reg(machine: Machine, name: str) -> int:
    return machine.uc.reg_read(getattr(uc_arm, f"UC_ARM_REG_{name}"))


def test_reset_should_load_sp_and_pc_from_the_vector_table() -> None:
    image = bare_image(stack=0x2000_4FF0)
    machine = Machine(image)
    assert reg(machine, "SP") == 0x2000_4FF0
    assert machine.pc == machine.read_u32(4) & ~1 == machine.read_u32(0x0800_0004) & ~1


def test_sram_should_start_filled_not_zeroed() -> None:
    machine = Machine(bare_image())
    assert machine.read_u32(SRAM_BASE) == 0xCDCDCDCD


def test_an_unmodelled_peripheral_access_should_name_the_register(tmp_path: Path) -> None:
    code = assemble("ldr r0, =0x40013800\nldr r1, [r0]\nb .", tmp_path)
    machine = Machine(bare_image(code))
    with pytest.raises(PilError, match=r"USART1\.SR \(0x40013800\)"):
        machine.run_for(1000)


def test_an_unmodelled_register_of_a_modelled_peripheral_should_be_an_error(tmp_path: Path) -> None:
    code = assemble("ldr r0, =0x40021010\nmovs r1, #1\nstr r1, [r0]\nb .", tmp_path)
    machine = Machine(bare_image(code))
    with pytest.raises(PilError, match=r"RCC\.APB1RSTR .*not modelled"):
        machine.run_for(1000)


def test_a_peripheral_with_its_clock_off_should_not_answer(tmp_path: Path) -> None:
    code = assemble("ldr r0, =0x40012C24\nldr r1, [r0]\nb .", tmp_path)
    machine = Machine(bare_image(code))
    with pytest.raises(PilError, match=r"TIM1\.CNT .*clock off"):
        machine.run_for(1000)


def test_a_write_to_flash_should_be_a_bus_fault(tmp_path: Path) -> None:
    code = assemble("ldr r0, =0x08001000\nstr r0, [r0]\nb .", tmp_path)
    machine = Machine(bare_image(code))
    with pytest.raises(PilError, match="0x08001000"):
        machine.run_for(1000)


def test_an_undefined_instruction_should_be_a_hard_fault(tmp_path: Path) -> None:
    machine = Machine(bare_image(assemble("udf #0", tmp_path)))
    with pytest.raises(PilError, match="HardFault"):
        machine.run_for(1000)


def _enable(machine: Machine, irq: int, priority: int) -> None:
    machine.nvic.enabled[irq] = True
    machine.nvic.priority[irq] = priority


def test_entry_should_push_the_eight_word_frame_and_set_exc_return(tmp_path: Path) -> None:
    main = assemble("movs r0, #5\nmovs r1, #6\nmovs r2, #7\nmovs r3, #8\nloop: b loop", tmp_path)
    handler = assemble("b .", tmp_path, "handler")
    machine = Machine(bare_image(main, handlers={IRQ_BASE + 3: handler}))
    machine.run_for(100)
    loop = machine.pc
    _enable(machine, 3, 0x10)
    machine.nvic.set_line(3, True)
    machine.run_for(200)
    sp = reg(machine, "SP")
    frame = [machine.read_u32(sp + 4 * k) for k in range(8)]
    assert frame[:4] == [5, 6, 7, 8]
    assert frame[6] == loop  # the return address: the loop it interrupted
    assert frame[7] & (1 << 24)  # Thumb bit of the stacked xPSR
    assert sp % 8 == 0 and STACK - sp == 32  # CCR.STKALIGN: already 8-byte aligned
    assert reg(machine, "LR") == EXC_RETURN_THREAD_MSP
    assert machine.nvic.active == [IRQ_BASE + 3]


def test_return_should_restore_the_interrupted_registers(tmp_path: Path) -> None:
    main = assemble("movs r0, #5\nmovs r1, #6\nmovs r2, #7\nmovs r3, #8\nloop: b loop", tmp_path)
    handler = assemble("movs r0, #0\nmovs r1, #0\nmovs r2, #0\nmovs r3, #0\nbx lr", tmp_path, "h")
    machine = Machine(bare_image(main, handlers={IRQ_BASE + 3: handler}))
    machine.run_for(100)
    _enable(machine, 3, 0x10)
    machine.nvic.set_line(3, True)
    machine.nvic.set_line(3, False)  # a pulse: pending latched, nothing re-pends it
    machine.run_for(500)
    assert [reg(machine, f"R{n}") for n in range(4)] == [5, 6, 7, 8]
    assert reg(machine, "SP") == STACK and machine.nvic.active == []
    assert [e for _, e in machine.entry_log] == [IRQ_BASE + 3]


# A handler that pends IRQ 2 (NVIC ISPR0 bit 2) and notes the order in RAM.
_PEND_IRQ2 = """
ldr r0, =0xE000E200
movs r1, #4
str r1, [r0]
ldr r0, =0x20000000
movs r1, #1
str r1, [r0]
bx lr
"""
_NOTE_IRQ2 = """
ldr r0, =0x20000004
ldr r1, =0x20000000
ldr r1, [r1]
str r1, [r0]
bx lr
"""


def test_a_higher_priority_interrupt_should_preempt(tmp_path: Path) -> None:
    handlers = {
        IRQ_BASE + 1: assemble(_PEND_IRQ2, tmp_path, "a"),
        IRQ_BASE + 2: assemble("mov r3, lr\nb .", tmp_path, "b"),
    }
    machine = Machine(bare_image(handlers=handlers))
    _enable(machine, 1, 0x40)
    _enable(machine, 2, 0x10)
    machine.nvic.pend(IRQ_BASE + 1)
    machine.run_for(2000)
    assert machine.nvic.active == [IRQ_BASE + 1, IRQ_BASE + 2]  # nested
    assert reg(machine, "R3") == EXC_RETURN_HANDLER


def test_equal_priority_should_wait_and_then_tail_chain(tmp_path: Path) -> None:
    handlers = {
        IRQ_BASE + 1: assemble(_PEND_IRQ2, tmp_path, "a"),
        IRQ_BASE + 2: assemble(_NOTE_IRQ2, tmp_path, "b"),
    }
    machine = Machine(bare_image(handlers=handlers))
    _enable(machine, 1, 0x20)
    _enable(machine, 2, 0x20)  # same group priority: no preemption
    machine.nvic.pend(IRQ_BASE + 1)
    machine.run_for(2000)
    # IRQ 2 ran after IRQ 1 had finished its last store
    assert machine.read_u32(0x2000_0004) == 1
    entries = [e for _, e in machine.entry_log]
    assert entries == [IRQ_BASE + 1, IRQ_BASE + 2]
    assert machine.nvic.active == [] and reg(machine, "SP") == STACK


def test_subpriority_should_not_preempt_under_priority_grouping(tmp_path: Path) -> None:
    handlers = {
        IRQ_BASE + 1: assemble(_PEND_IRQ2, tmp_path, "a"),
        IRQ_BASE + 2: assemble(_NOTE_IRQ2, tmp_path, "b"),
    }
    machine = Machine(bare_image(handlers=handlers))
    machine.scb.write(0x0C, 4, (0x05FA << 16) | (6 << 8))  # PRIGROUP 6: 1 group bit
    _enable(machine, 1, 0x40)
    _enable(machine, 2, 0x10)  # same group (bit 7 = 0), better subpriority
    machine.nvic.pend(IRQ_BASE + 1)
    machine.run_for(2000)
    assert machine.read_u32(0x2000_0004) == 1  # waited for IRQ 1 to finish


def test_primask_should_hold_an_interrupt_until_cleared(tmp_path: Path) -> None:
    main = assemble(
        "cpsid i\nmovs r0, #0\nspin: adds r0, #1\ncmp r0, #200\nbne spin\ncpsie i\nloop: b loop",
        tmp_path,
    )
    handlers = {IRQ_BASE + 1: assemble("mov r4, r0\nb .", tmp_path, "h")}
    machine = Machine(bare_image(main, handlers=handlers))
    _enable(machine, 1, 0x10)
    machine.run_for(50)
    machine.nvic.pend(IRQ_BASE + 1)
    machine.run_for(20_000)
    assert machine.nvic.active == [IRQ_BASE + 1]
    assert reg(machine, "R4") == 200  # taken only after CPSIE


def test_a_line_still_high_should_pend_again_after_return(tmp_path: Path) -> None:
    handlers = {IRQ_BASE + 1: assemble("bx lr", tmp_path, "h")}
    machine = Machine(bare_image(handlers=handlers))
    _enable(machine, 1, 0x10)
    machine.nvic.set_line(1, True)
    machine.run_for(300)
    assert len([e for _, e in machine.entry_log if e == IRQ_BASE + 1]) > 2


def test_wfi_should_sleep_until_the_next_event(tmp_path: Path) -> None:
    main = assemble(
        """
        ldr r0, =0xE000E010
        ldr r1, =7999
        str r1, [r0, #4]      @ RVR: 1 ms at 8 MHz
        movs r1, #0
        str r1, [r0, #8]      @ CVR
        movs r1, #7
        str r1, [r0]          @ ENABLE | TICKINT | CLKSOURCE
        loop: wfi
        b loop
        """,
        tmp_path,
    )
    handler = assemble(
        "ldr r0, =0x20000000\nldr r1, [r0]\nadds r1, #1\nstr r1, [r0]\nbx lr", tmp_path, "h"
    )
    machine = Machine(bare_image(main, handlers={SYSTICK: handler}))
    machine.write_u32(0x2000_0000, 0)
    machine.run_for(72_000 * 10 + 20_000)  # 10 ms
    assert machine.read_u32(0x2000_0000) == 10
    assert machine.sleep_pc is not None
    # Asleep between ticks: a few hundred cycles of code, not 80000 per millisecond.
    assert len(machine._block_cost) < 20


def test_preemption_inside_an_it_block_should_resume_the_block(tmp_path: Path) -> None:
    """The store that pends the interrupt is retired by hand, the IT state advanced
    (ARMv7-M A7.3.2 ITAdvance): the rest of the block runs with its conditions."""
    main = assemble(
        """
        movs r3, #0
        ldr r0, =0xE000E200
        movs r1, #2
        movs r2, #1
        cmp r2, #1
        itte eq
        streq r1, [r0]
        moveq r3, #5
        movne r3, #9
        loop: b loop
        """,
        tmp_path,
    )
    handler = assemble("movs r4, #1\nmovs r3, #7\nbx lr", tmp_path, "h")
    machine = Machine(bare_image(main, handlers={IRQ_BASE + 1: handler}))
    _enable(machine, 1, 0x10)
    machine.run_for(2000)
    assert [e for _, e in machine.entry_log] == [IRQ_BASE + 1]
    assert reg(machine, "R4") == 1 and reg(machine, "R3") == 5


def test_a_handler_entered_inside_an_it_block_should_run_unconditionally(
    tmp_path: Path,
) -> None:
    """Exception entry clears ITSTATE (ARMv7-M B1.5.6): the handler runs whatever the
    interrupted IT block's condition, and the block's rest resumes with it on return.
    The block here straddles a 1 KiB page, where the emulator's translation blocks end,
    so the machine stops between its instructions, its condition left false (NE after
    an equal compare): the emulator once entered the handler with that state, and the
    handler's first instruction was skipped (found by a PIL scenario on a real port)."""
    # main starts at 0x0800_0100 (after 64 vectors): the IT at 0x0800_03FC, its second
    # instruction at 0x0800_0400, the page boundary
    main = assemble(
        """
        movs r3, #0
        movs r2, #1
        cmp r2, #1
        .rept 379
        nop
        .endr
        itt ne
        movne r3, #9
        movne r3, #7
        loop: b loop
        """,
        tmp_path,
    )
    assert main[0x2FC:0x2FE] == bytes.fromhex("1cbf")  # itt ne, at 0x0800_03FC
    handler = assemble("movs r4, #1\nmovs r5, #2\nbx lr", tmp_path, "h")
    machine = Machine(bare_image(main, handlers={IRQ_BASE + 1: handler}))
    _enable(machine, 1, 0x10)
    machine.run_for(1)  # the first block runs whole: the machine stops at the page
    assert machine.pc == 0x0800_0400
    machine.nvic.set_line(1, True)
    machine.nvic.set_line(1, False)
    machine.run_for(2000)
    assert [e for _, e in machine.entry_log] == [IRQ_BASE + 1]
    assert (reg(machine, "R4"), reg(machine, "R5")) == (1, 2)
    assert reg(machine, "R3") == 0  # both movne false, the second one after the return


def test_wfi_with_primask_set_should_wake_without_taking_the_interrupt(tmp_path: Path) -> None:
    """ARMv7-M B1.5.19: a pending interrupt that would preempt but for PRIMASK wakes WFI."""
    main = assemble("cpsid i\nwfi\nmovs r5, #3\nloop: b loop", tmp_path)
    handler = assemble("b .", tmp_path, "h")
    machine = Machine(bare_image(main, handlers={IRQ_BASE + 1: handler}))
    _enable(machine, 1, 0x10)
    machine.run_for(1000)
    assert machine.sleep_pc is not None
    machine.nvic.pend(IRQ_BASE + 1)
    machine.run_for(1000)
    assert reg(machine, "R5") == 3 and machine.nvic.active == []

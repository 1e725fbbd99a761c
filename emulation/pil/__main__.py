"""`python -m emulation.pil SPEC [--elf ELF] [--ms N] [--rpm R] [--amps I] [--gates]`: boot the
drive firmware on the emulated STM32F103, run it with the Hall code stepping at a
constant speed and a constant measured current, and print what it did and how fast
the emulation ran (emulated ms per wall-clock second). A measurement, not a test."""

from __future__ import annotations

import argparse
import sys
import time
from collections import Counter
from pathlib import Path

from elftools.common.exceptions import ELFError

from codegen.argtypes import decimal_number
from codegen.errors import ExitCode, SpecError
from codegen.publish import os_error_line
from codegen.spec_loader import load_spec
from emulation.pil.bus import PilError
from emulation.pil.rcc import TICK_HZ
from emulation.pil.runner import DriveBoard
from emulation.pil.tim1 import gate_violations


def _unloadable(error: OSError | PilError | ELFError) -> str:
    """Why a firmware image does not load, in a few words."""
    if isinstance(error, OSError):
        return os_error_line(error).removeprefix("error: ")
    if isinstance(error, ELFError):
        return f"not an ELF image ({error})"
    return str(error)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m emulation.pil", description=__doc__)
    parser.add_argument("spec")
    parser.add_argument("--elf", help="default: build/<spec name>/firmware.elf (make firmware)")
    parser.add_argument(
        "--ms", type=decimal_number(0.001, 60000), default=100.0, help="emulated time after boot"
    )
    parser.add_argument(
        "--rpm", type=decimal_number(0, 1e6), default=4600.0, help="0: the rotor stands still"
    )
    parser.add_argument(
        "--amps", type=decimal_number(-1e4, 1e4), default=5.0, help="the DC-link current read"
    )
    parser.add_argument(
        "--gates", action="store_true", help="record every gate edge and check the bridge"
    )
    args = parser.parse_args(argv)
    try:
        spec = load_spec(args.spec)
    except SpecError as error:  # every error of the spec, one line each
        for line in str(error).splitlines():
            print(f"error: {line}", file=sys.stderr)
        return int(ExitCode.SPEC)
    elf = Path(args.elf) if args.elf else Path("build") / spec.name / "firmware.elf"
    if not elf.is_file():  # a traceback had said FileNotFoundError
        hint = "" if args.elf else f" (build it: bldc-codegen firmware {args.spec})"
        print(f"error: pil: {elf} is no firmware image{hint}", file=sys.stderr)
        return int(ExitCode.ENVIRONMENT)
    try:
        board = DriveBoard(elf, spec)
    except (OSError, PilError, ELFError) as error:
        print(f"error: pil: {elf}: {_unloadable(error)}", file=sys.stderr)
        return int(ExitCode.ENVIRONMENT)
    board.set_current(args.amps)
    machine = board.machine
    wall = time.perf_counter()
    boot = board.boot()
    boot_wall = time.perf_counter() - wall
    pole_pairs = spec.motor.poles // 2
    sector_ticks = round(TICK_HZ * 60 / (args.rpm * pole_pairs * 6)) if args.rpm > 0 else None
    if args.gates:
        machine.tim1.record_gates()
    start, handler_start = machine.now, machine.handler_ticks
    end = start + round(args.ms * TICK_HZ / 1000)
    sector = 0
    wall = time.perf_counter()
    while machine.now < end:
        step = end - machine.now if sector_ticks is None else min(sector_ticks, end - machine.now)
        machine.run_for(step)
        if sector_ticks is not None:
            sector = (sector + 1) % 6
            board.set_hall(spec.hall.sequence[sector])
    elapsed = time.perf_counter() - wall
    emulated_ms = (machine.now - start) * 1000 / TICK_HZ
    entries = Counter(e for t, e in machine.entry_log if t >= start)
    load = (machine.handler_ticks - handler_start) / (machine.now - start)
    print(f"{elf}: booted to main's WFI at {boot * 1000 / TICK_HZ:.3f} ms ({boot_wall:.2f} s wall)")
    print(
        f"ran {emulated_ms:.1f} ms at {args.rpm:g} rpm, {args.amps:g} A in {elapsed:.2f} s wall:"
        f" {emulated_ms / elapsed:.1f} emulated ms per second"
    )
    print(f"exception entries by number: {dict(sorted(entries.items()))}")
    print(
        f"CPU load (handlers, entry and exit; TRM cycles plus estimated flash waits): {100 * load:.1f} %"
    )
    print(f"app_faults = 0x{board.symbol('app_faults'):04x}, MOE = {int(machine.tim1.moe)}")
    log = machine.tim1.gate_log
    if log is not None:
        dead = round(spec.inverter.dead_time_s * TICK_HZ)
        violations = gate_violations(log, dead)
        print(f"gate edges: {len(log) - 1}; bridge invariant violations: {len(violations)}")
        for line in violations[:10]:
            print(f"  {line}")
    return 0


if __name__ == "__main__":
    from codegen.interrupts import exit_status

    raise SystemExit(exit_status(main))

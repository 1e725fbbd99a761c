"""`make firmware`: cross-compile the generated firmware for the Cortex-M3, link it, and
hold it to the spec's budgets.

Builds the core, the current loop, the port, the clock tree, the start-up code and
main() (and, for `firmware.integration: cube`, the stm32f1xx_it.c a Cube project would
hold) with arm-none-eabi-gcc -Werror, links `firmware.elf` with a map, and writes
`firmware.bin` and `firmware.hex`. It reports flash and RAM by section, the worst stack
depth from the compiler's call graph (-fcallgraph-info, codegen/stack_usage.py) and
exits non-zero when flash exceeds `firmware.flash_budget` or RAM, stack included,
`firmware.ram_budget`.
"""

from __future__ import annotations

import contextlib
import os
import re
import signal
import subprocess
import sys
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from codegen.port_drive import HANDLERS
from codegen.report_folder import staged_build
from codegen.stack_usage import StackReport, read_call_graph, stack_report

CFLAGS = [
    "-std=c99",
    "-mcpu=cortex-m3",
    "-mthumb",
    "-O2",
    "-Wall",
    "-Wextra",
    "-Wconversion",
    "-Wpedantic",
    "-Werror",
    "-ffunction-sections",
    "-fdata-sections",
    "-fno-tree-loop-distribute-patterns",  # start-up loops must not become memcpy calls
    # At 72 MHz a load from flash waits two cycles (RM0008 3.3.3): constants are built by
    # MOVW/MOVT in the instruction stream instead of loaded from literal pools.
    "-mslow-flash-data",
]
SOURCES = {
    "core": "c/bldc_commutation.c",
    "loop": "c/bldc_current_loop.c",
    "port": "c/stm32f103_port.c",
    "system": "firmware/system_stm32f103.c",
    "startup": "firmware/startup_stm32f103.c",
    "main": "firmware/main.c",
}
CUBE_SOURCE = ("it", "firmware/stm32f1xx_it.c")
#: .RamFunc holds code and tables that run from SRAM: in flash as the load image, copied
#: to RAM by the start-up code, so it counts for both.
FLASH_SECTIONS = (".isr_vector", ".text", ".rodata", ".data", ".RamFunc")
RAM_SECTIONS = (".data", ".bss", ".RamFunc")
ELF = "firmware.elf"
MAP = "firmware.map"
#: what the build writes beside the objects
IMAGE_FILES = (ELF, "firmware.bin", "firmware.hex", MAP)
#: text the head of a map this build wrote holds (its first object's discarded
#: sections): a build folder from before the ledger counts as the tool's by it
MAP_MARKER = "core.o"


@dataclass(frozen=True)
class Sizes:
    sections: dict[str, int]

    @property
    def flash(self) -> int:
        return sum(v for k, v in self.sections.items() if k.startswith(FLASH_SECTIONS))

    @property
    def ram(self) -> int:
        return sum(v for k, v in self.sections.items() if k.startswith(RAM_SECTIONS))

    @property
    def ram_code(self) -> int:
        """Of `ram`, the code and tables copied to SRAM to run there (.RamFunc)."""
        return sum(v for k, v in self.sections.items() if k.startswith(".RamFunc"))

    @property
    def ram_state(self) -> int:
        """Of `ram`, the variables (.data, .bss)."""
        return self.ram - self.ram_code


def section_sizes(path: Path) -> Sizes:
    out = subprocess.run(
        ["arm-none-eabi-size", "-A", str(path)], check=True, capture_output=True, text=True
    )
    sections: dict[str, int] = {}
    for line in out.stdout.splitlines():
        parts = line.split()
        if len(parts) >= 2 and parts[0].startswith(".") and parts[1].isdigit() and int(parts[1]):
            sections[parts[0]] = sections.get(parts[0], 0) + int(parts[1])
    return Sizes(sections)


_MAP_OUTPUT = re.compile(r"^(\.\S+)\s+0x[0-9a-f]+\s+0x[0-9a-f]+")
_MAP_INPUT = re.compile(r"\s0x[0-9a-f]+\s+(0x[0-9a-f]+)\s+(\S+)\.o$")


def linked_flash(build_dir: Path) -> dict[str, int]:
    """Flash bytes each object contributes to the linked image (from the link map: what
    --gc-sections kept), by part name. Unlike the objects' own sizes, a function or
    table the linker dropped does not count: the port compiles the core's text in as
    well (templates/c/stm32f103_port.c.j2) and keeps only what its handler inlined."""
    out: dict[str, int] = {}
    output = ""
    started = False
    for line in (build_dir / "firmware.map").read_text(encoding="utf-8").splitlines():
        if line.startswith("Linker script and memory map"):
            started = True
            continue
        if not started:
            continue
        head = _MAP_OUTPUT.match(line)
        if head:
            output = head.group(1)
            continue
        found = _MAP_INPUT.search(line)
        if found and output.startswith(FLASH_SECTIONS):
            part = Path(found.group(2)).name
            out[part] = out.get(part, 0) + int(found.group(1), 16)
    return out


def sources(generated: Path) -> dict[str, str]:
    """The sources of this generated tree (the Cube-style handlers where present)."""
    out = dict(SOURCES)
    if (generated / CUBE_SOURCE[1]).is_file():
        out[CUBE_SOURCE[0]] = CUBE_SOURCE[1]
    return out


def build(generated: Path, build_dir: Path, *, defines: Sequence[str] = ()) -> dict[str, Sizes]:
    """Compile and link; `defines` are NAME=VALUE macros for every source (the bench
    builds the port's alternatives with them). Each object's stack frames and call graph
    are written beside it (-fstack-usage `<name>.su`, -fcallgraph-info `<name>.ci`); the
    image as ELF, binary, Intel hex and a link map. All are built in a staging folder
    and moved into `build_dir` at the end (codegen.report_folder.staged_build)."""
    # a file of the build's names that bldc-codegen did not write (its ledger does not
    # list it with its content's hash) stops it before it starts: `firmware --build DIR`
    # had overwritten a user's firmware.map and main.o
    written = [
        *(f"{name}{ext}" for name in (*SOURCES, CUBE_SOURCE[0]) for ext in (".o", ".su", ".ci")),
        *IMAGE_FILES,
    ]
    with staged_build(build_dir, written, MAP, MAP_MARKER) as staging:
        return _build_in(generated, staging, defines)


def _run_tool(argv: Sequence[str], cwd: Path | None = None) -> None:
    """Run a toolchain step as subprocess.run(check=True) would, in a process group of its
    own: interrupted (Ctrl-C), the whole group is killed and waited for before the
    staging folder is removed. gcc's driver forks cc1 and as, which a kill of the driver
    alone leaves running: a `make bench` interrupted in its build printed cc1's "cannot
    open ... startup.su for writing" after its "interrupted" line (CI on a slow
    machine)."""
    process = subprocess.Popen(list(argv), cwd=cwd, start_new_session=True)
    try:
        status = process.wait()
    except BaseException:
        with contextlib.suppress(ProcessLookupError, PermissionError):
            os.killpg(process.pid, signal.SIGKILL)
        process.wait()
        raise
    if status != 0:
        raise subprocess.CalledProcessError(status, list(argv))


def _build_in(generated: Path, build_dir: Path, defines: Sequence[str]) -> dict[str, Sizes]:
    """`build` into the empty folder `build_dir`."""
    objects = {}
    for name, source in sources(generated).items():
        obj = build_dir / f"{name}.o"
        _run_tool(
            [
                "arm-none-eabi-gcc",
                *CFLAGS,
                "-fstack-usage",
                "-fcallgraph-info=su",
                *(f"-D{d}" for d in defines),
                f"-I{generated / 'c'}",
                f"-I{generated / 'firmware'}",
                "-c",
                str(generated / source),
                "-o",
                str(obj),
            ]
        )
        objects[name] = obj
    elf = build_dir / ELF
    # linked in the folder, so the map names the objects as they are there once moved
    # (core.o), not by the staging folder's path
    _run_tool(
        [
            "arm-none-eabi-gcc",
            "-mcpu=cortex-m3",
            "-mthumb",
            "-nostdlib",
            "-Wl,--gc-sections",
            "-T",
            os.path.abspath(generated / "firmware" / "stm32f103.ld"),
            *(obj.name for obj in objects.values()),
            "-o",
            ELF,
            f"-Wl,-Map={MAP}",
        ],
        cwd=build_dir,
    )
    for kind, suffix in (("binary", "bin"), ("ihex", "hex")):
        _run_tool(
            ["arm-none-eabi-objcopy", "-O", kind, str(elf), str(build_dir / f"firmware.{suffix}")]
        )
    sizes = {name: section_sizes(obj) for name, obj in objects.items()}
    sizes[ELF] = section_sizes(elf)
    return sizes


#: Functions thread mode calls with interrupts masked (PRIMASK) from start to end: no
#: handler stacks on them, so they count apart (`make firmware` prints both).
MASKED = ("bldc_port_init", "port_clear_masked")


def stack(build_dir: Path, cube: bool) -> StackReport:
    """Worst stack over the preemption levels of the port's NVIC plan (thread mode, the
    timing handler, the Hall edge's level, the NMI and HardFault). Each level's roots
    are the vector table's handlers, in either integration: the port's own or, for the
    vectors the port leaves to a Cube project (`cube`), stm32f1xx_it.c's, whose call
    into the port the graph follows."""
    vectors = {role: h.vector for role, h in HANDLERS.items()}
    levels = [
        ("thread mode (interrupts open)", ["main"]),
        ("timing and bus change (priority 2)", [vectors["timing"], vectors["bus"]]),
        (
            "Hall edge, Hall lines, current loop, break (priority 1)",
            [vectors[r] for r in ("hall", "adc", "brk", "hall_line0", "hall_lines9_5")],
        ),
        ("NMI, HardFault", ["NMI_Handler", "HardFault_Handler"]),
    ]
    return stack_report(read_call_graph(build_dir), levels, masked=MASKED)


@dataclass(frozen=True)
class Budget:
    name: str
    value: int | None
    limit: int

    @property
    def meets(self) -> bool:
        return self.value is not None and self.value <= self.limit

    def line(self) -> str:
        shown = "unknown" if self.value is None else f"{self.value} B"
        return f"{self.name}: {shown} of {self.limit} B {'(meets)' if self.meets else '(EXCEEDED)'}"


def budgets(
    sizes: dict[str, Sizes], report: StackReport, flash_limit: int, ram_limit: int
) -> list[Budget]:
    image = sizes[ELF]
    worst = report.worst
    return [
        Budget("flash", image.flash, flash_limit),
        Budget(
            "RAM (variables, code run from SRAM, worst stack)",
            None if worst is None else image.ram + worst,
            ram_limit,
        ),
    ]


def main(argv: list[str]) -> int:
    """argv: generated folder, build folder, spec path. Exit 1 when a budget is exceeded."""
    from codegen.spec_loader import load_spec

    generated, build_dir, spec_path = Path(argv[0]), Path(argv[1]), argv[2]
    spec = load_spec(spec_path)
    sizes = build(generated, build_dir)
    report = stack(build_dir, spec.firmware.integration == "cube")
    print(f"firmware: {build_dir / ELF} (+ .bin, .hex, .map)")
    linked = linked_flash(build_dir)
    for name, size in sizes.items():
        detail = ", ".join(f"{k} {v}" for k, v in sorted(size.sections.items()))
        kept = f"  linked {linked.get(name, 0):5d} B" if name != ELF else ""
        print(f"  {name:13s} flash {size.flash:5d} B{kept}  RAM {size.ram:4d} B  ({detail})")
    print("  worst stack, every preemption level stacked (-fcallgraph-info):")
    for line in report.lines():
        print(f"    {line}")
    print(f"    total {report.worst if report.worst is not None else 'unknown'} B")
    results = budgets(
        sizes, report, spec.firmware.flash_budget_bytes, spec.firmware.ram_budget_bytes
    )
    for b in results:
        print(f"  {b.line()}")
    for b in results:
        hint = budget_hint(b, spec.controller.method)
        if hint:
            print(f"  {hint}")
    return 0 if all(b.meets for b in results) else 1


def budget_hint(budget: Budget, method: str) -> str | None:
    """What to change where a budget is exceeded: the spec key, its value and what the
    image needs."""
    if budget.meets or budget.value is None:
        return None
    key = "firmware.flash_budget" if budget.name == "flash" else "firmware.ram_budget"
    why = (
        " (the resistance-aware rule's search runs deeper than the paper method's;"
        " `init --method improved_r` writes 640 B)"
        if key == "firmware.ram_budget" and method == "improved_r"
        else ""
    )
    return f"{key} = {budget.limit} B is below what this image needs, {budget.value} B{why}"


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))

"""`make firmware`: cross-compile the generated core and port for the Cortex-M3 and
report flash and RAM by section, for the whole image and for the commutation code
alone (core + port), which carries the 2 KiB flash / 64 B RAM budget.
"""

from __future__ import annotations

import subprocess
import sys
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

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
]
SOURCES = {
    "core": "c/bldc_commutation.c",
    "port": "c/stm32f103_port.c",
    "startup": "firmware/startup_stm32f103.c",
    "main": "firmware/main.c",
}
#: .RamFunc holds code and tables that run from SRAM: in flash as the load image, copied
#: to RAM by the start-up code, so it counts for both.
FLASH_SECTIONS = (".isr_vector", ".text", ".rodata", ".data", ".RamFunc")
RAM_SECTIONS = (".data", ".bss", ".RamFunc")


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


def build(generated: Path, build_dir: Path, *, defines: Sequence[str] = ()) -> dict[str, Sizes]:
    """Compile and link; `defines` are NAME=VALUE macros for every source (the bench
    builds the port's alternatives with them). Each object's stack frames are written
    beside it (-fstack-usage, `<name>.su`)."""
    build_dir.mkdir(parents=True, exist_ok=True)
    objects = {}
    for name, source in SOURCES.items():
        obj = build_dir / f"{name}.o"
        subprocess.run(
            [
                "arm-none-eabi-gcc",
                *CFLAGS,
                "-fstack-usage",
                *(f"-D{d}" for d in defines),
                f"-I{generated / 'c'}",
                "-c",
                str(generated / source),
                "-o",
                str(obj),
            ],
            check=True,
        )
        objects[name] = obj
    elf = build_dir / "firmware.elf"
    subprocess.run(
        [
            "arm-none-eabi-gcc",
            "-mcpu=cortex-m3",
            "-mthumb",
            "-nostdlib",
            "-Wl,--gc-sections",
            "-T",
            str(generated / "firmware" / "stm32f103.ld"),
            *map(str, objects.values()),
            "-o",
            str(elf),
            f"-Wl,-Map={build_dir / 'firmware.map'}",
        ],
        check=True,
    )
    sizes = {name: section_sizes(obj) for name, obj in objects.items()}
    sizes["firmware.elf"] = section_sizes(elf)
    return sizes


def main(argv: list[str]) -> int:
    generated, build_dir = Path(argv[0]), Path(argv[1])
    sizes = build(generated, build_dir)
    print(f"firmware: {build_dir / 'firmware.elf'}")
    for name, size in sizes.items():
        detail = ", ".join(f"{k} {v}" for k, v in sorted(size.sections.items()))
        print(f"  {name:13s} flash {size.flash:5d} B  RAM {size.ram:4d} B  ({detail})")
    code = sizes["core"].flash + sizes["port"].flash
    state = sizes["core"].ram_state + sizes["port"].ram_state
    ram_code = sizes["core"].ram_code + sizes["port"].ram_code
    print(
        f"  commutation code (core + port): flash {code} B of 2048, RAM {state} B of"
        f" variables and {ram_code} B of code and tables run from SRAM (.RamFunc)"
    )
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))

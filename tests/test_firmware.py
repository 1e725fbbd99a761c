"""`make firmware`: the generated core and port link into a Cortex-M3 image."""

from __future__ import annotations

import shutil
import subprocess
from pathlib import Path

import pytest

from codegen.build_firmware import build
from codegen.firmware import tim3_irq_number, vector_table

ROOT = Path(__file__).resolve().parents[1]

pytestmark = pytest.mark.skipif(shutil.which("arm-none-eabi-gcc") is None, reason="no arm gcc")


def test_tim3_vector_should_sit_at_its_svd_interrupt_number() -> None:
    table = vector_table()
    assert tim3_irq_number() == 29
    assert table[0] == "Reset_Handler"  # vector 1; vector 0 is the initial stack pointer
    assert table[15 + 29] == "TIM3_IRQHandler"  # vector 16 + 29
    assert table.count("TIM3_IRQHandler") == 1 and len(table) == 15 + 43


@pytest.mark.parametrize("name", ["paper_motor", "maxon_ec45_flat_48v"])
def test_firmware_should_link_with_the_handler_in_the_vector_table(
    name: str, tmp_path: Path
) -> None:
    sizes = build(ROOT / "generated" / name, tmp_path)
    elf = tmp_path / "firmware.elf"
    symbols = subprocess.run(
        ["arm-none-eabi-nm", str(elf)], check=True, capture_output=True, text=True
    ).stdout
    handler = next(
        int(line.split()[0], 16)
        for line in symbols.splitlines()
        if line.endswith(" TIM3_IRQHandler")
    )
    image = subprocess.run(
        [
            "arm-none-eabi-objcopy",
            "-O",
            "binary",
            "-j",
            ".isr_vector",
            str(elf),
            str(tmp_path / "v.bin"),
        ],
        check=True,
    )
    assert image.returncode == 0
    vectors = (tmp_path / "v.bin").read_bytes()
    entry = int.from_bytes(vectors[4 * (16 + 29) : 4 * (16 + 30)], "little")
    assert entry == handler | 1  # Thumb bit set
    assert sizes["firmware.elf"].flash > 0 and "__aeabi" not in symbols

"""Stack usage (emulation/stack.py): -fstack-usage frames summed along the deepest static
call path, checked on a sample whose frames the test sets, and against the stack the
emulated run really wrote."""

from __future__ import annotations

import subprocess
from pathlib import Path

from emulation.armsim import CortexM3Sim, load_elf
from emulation.stack import EXCEPTION_FRAME_BYTES, read_frames, static_depth

SAMPLE = r"""
#include <stdint.h>
volatile uint32_t sink;

__attribute__((noinline)) static uint32_t leaf(uint32_t n)
{
    volatile uint32_t buffer[16]; /* 64 bytes of frame */
    for (uint32_t i = 0u; i < 16u; i++) {
        buffer[i] = n + i;
    }
    return buffer[n & 15u];
}

__attribute__((noinline)) static uint32_t shallow(uint32_t n)
{
    return n * 3u;
}

__attribute__((noinline)) uint32_t middle(uint32_t n)
{
    volatile uint32_t pad[4];
    pad[0] = n;
    return leaf(pad[0]) + shallow(n);
}

uint32_t root(uint32_t n)
{
    sink = n;
    return middle(n) + shallow(n);
}
"""


def _build(tmp_path: Path) -> Path:
    (tmp_path / "sample.c").write_text(SAMPLE, encoding="utf-8")
    subprocess.run(
        [
            "arm-none-eabi-gcc",
            "-mcpu=cortex-m3",
            "-mthumb",
            "-O2",
            "-fstack-usage",
            "-c",
            "sample.c",
            "-o",
            "sample.o",
        ],
        cwd=tmp_path,
        check=True,
    )
    subprocess.run(
        [
            "arm-none-eabi-gcc",
            "-mcpu=cortex-m3",
            "-mthumb",
            "-nostdlib",
            "-Wl,-Ttext=0x08000000",
            "-Wl,--section-start=.bss=0x20000000",
            "-Wl,-e,root",
            "sample.o",
            "-o",
            "sample.elf",
        ],
        cwd=tmp_path,
        check=True,
    )
    return tmp_path / "sample.elf"


def test_static_depth_should_sum_the_deepest_path_and_bound_the_measured_run(
    tmp_path: Path,
) -> None:
    elf = _build(tmp_path)
    frames = read_frames(tmp_path)
    assert {"leaf", "shallow", "middle", "root"} <= set(frames)
    assert frames["leaf"].bytes >= 64 and frames["leaf"].bounded
    image = load_elf(elf)
    depth = static_depth(image, frames, "root")
    assert depth.path == ("root", "middle", "leaf")
    assert depth.bytes == frames["root"].bytes + frames["middle"].bytes + frames["leaf"].bytes
    assert depth.missing == ()
    assert depth.with_frame() == depth.bytes + EXCEPTION_FRAME_BYTES == depth.bytes + 36
    measured = CortexM3Sim(image).call("root", args=(5,)).stack_bytes
    assert 64 < measured <= depth.bytes


def test_a_function_without_a_frame_should_make_the_bound_unknown(tmp_path: Path) -> None:
    elf = _build(tmp_path)
    frames = read_frames(tmp_path)
    del frames["leaf"]
    depth = static_depth(load_elf(elf), frames, "root")
    assert depth.bytes is None and depth.missing == ("leaf",)


def test_a_skipped_call_should_leave_the_depth_without_its_path(tmp_path: Path) -> None:
    """Thread mode's interrupts-masked calls stack alone: the depth under preemption
    skips them (the bench had put main's masked start-up under every handler level, 424 B
    where make firmware's nesting gives 380 B)."""
    elf = _build(tmp_path)
    frames = read_frames(tmp_path)
    image = load_elf(elf)
    depth = static_depth(image, frames, "root", skip=frozenset({"middle"}))
    assert depth.path == ("root", "shallow")
    assert depth.bytes == frames["root"].bytes + frames["shallow"].bytes

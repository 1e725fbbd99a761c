"""Stack usage of the interrupt handlers, two ways.

* Static: the compiler's frame of each function (-fstack-usage, the `.su` files the
  firmware build writes beside its objects) summed along the deepest path of the
  handler's static call graph (`emulation.callgraph`). A frame the compiler marks
  `dynamic` (alloca, variable-length arrays) makes the bound unknown.
* Measured: the deepest stack write of any emulated run of the handler.

Both add the exception frame the Cortex-M3 pushes on entry: eight words, plus one word
of padding when the stack pointer is not 8-byte aligned (CCR.STKALIGN, PM0056 4.4.7):
36 bytes at most. A handler preempted by a more urgent one adds that one's total.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

from emulation.armsim import ArmImage
from emulation.callgraph import call_graph

#: r0-r3, r12, lr, pc, xPSR, and the alignment word.
EXCEPTION_FRAME_BYTES = 8 * 4 + 4

_SU_LINE = re.compile(r"^(?P<where>.+):(?P<function>[^:\s]+)\s+(?P<bytes>\d+)\s+(?P<kind>\S+)$")


@dataclass(frozen=True)
class Frame:
    bytes: int
    bounded: bool  # static or bounded, not dynamic


def read_frames(build_dir: Path) -> dict[str, Frame]:
    """Function -> its frame, from every `.su` file in `build_dir`."""
    frames: dict[str, Frame] = {}
    for path in sorted(build_dir.glob("*.su")):
        for line in path.read_text(encoding="utf-8").splitlines():
            match = _SU_LINE.match(line.strip())
            if match is None:
                continue
            name = match["function"]
            frame = Frame(int(match["bytes"]), "dynamic" not in match["kind"].split(","))
            previous = frames.get(name)
            if previous is None or frame.bytes > previous.bytes:
                frames[name] = frame
    return frames


@dataclass(frozen=True)
class StaticDepth:
    handler: str
    bytes: int | None  # None when a frame on the path is unknown or dynamic
    path: tuple[str, ...]
    missing: tuple[str, ...]  # reached functions without a known, bounded frame

    def with_frame(self) -> int | None:
        return None if self.bytes is None else self.bytes + EXCEPTION_FRAME_BYTES


_CLONE_NUMBER = re.compile(r"^(?P<name>.+\.(?:constprop|isra|part|cold))\.\d+$")


def frame_of(frames: dict[str, Frame], symbol: str) -> Frame | None:
    """The frame of an ELF symbol. GCC's clones (`f.constprop.0`, `f.isra.0`) are
    named in the `.su` file without their number (`f.constprop`)."""
    if symbol in frames:
        return frames[symbol]
    clone = _CLONE_NUMBER.match(symbol)
    return frames.get(clone["name"]) if clone else None


def static_depth(
    image: ArmImage, frames: dict[str, Frame], handler: str, skip: frozenset[str] = frozenset()
) -> StaticDepth:
    """The deepest frame sum over the handler's static call paths (no recursion), not
    through the functions in `skip` (thread mode's interrupts-masked ones, which no
    handler stacks on)."""
    graph = call_graph(image, handler)
    known = {f: frame_of(frames, f) for f in graph.functions}
    missing = tuple(sorted(f for f, frame in known.items() if frame is None or not frame.bounded))

    def deepest(function: str, above: tuple[str, ...]) -> tuple[int, tuple[str, ...]]:
        if function in above:
            raise ValueError(f"{handler}: recursion through {function}: no static bound")
        frame = frame_of(frames, function)
        own = frame.bytes if frame is not None else 0
        below = [
            deepest(c, (*above, function)) for c in sorted(graph.calls[function]) if c not in skip
        ]
        best = max(below, default=(0, ()))
        return own + best[0], (function, *best[1])

    total, path = deepest(handler, ())
    return StaticDepth(handler, None if missing else total, path, missing)

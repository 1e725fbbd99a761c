"""Worst stack depth of the firmware from the compiler's own call graph.

GCC writes, per object, the functions it compiled with their frames and the calls
between them (`-fcallgraph-info=su`, a VCG graph in `<object>.ci`). Summed along the
deepest call path from each entry point, and stacked over the interrupts that can
preempt one another, that bounds the stack. (`make bench` measures the same depth a
second way, from the disassembled image and the emulator: emulation/stack.py.)

Preemption: main (thread mode) can be interrupted by the timing handler, which can be
interrupted by one of the handlers at the Hall edge's priority (they share a level, so
never each other), which can be interrupted by the NMI or a HardFault. Every interrupt
pushes an exception frame of eight words, plus one of alignment (PM0056 2.3.7):
36 bytes.

A function that calls through a pointer, or that no graph defines, makes the bound
unknown: the report names it.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

EXCEPTION_FRAME_BYTES = 9 * 4

_NODE = re.compile(r'node:\s*\{\s*title:\s*"(?P<title>[^"]+)"\s*label:\s*"(?P<label>[^"]*)"')
_EDGE = re.compile(
    r'edge:\s*\{\s*sourcename:\s*"(?P<source>[^"]+)"\s*targetname:\s*"(?P<target>[^"]+)"'
)
_BYTES = re.compile(r"\\n(?P<bytes>\d+) bytes \((?P<kind>[^)]*)\)")
INDIRECT = "__indirect_call"


@dataclass(frozen=True)
class Depth:
    root: str
    bytes: int | None  # None: a frame on some path is unknown or dynamic
    path: tuple[str, ...]
    unknown: tuple[str, ...]


@dataclass(frozen=True)
class CallGraph:
    frames: dict[str, int]  # function -> frame bytes (static or bounded)
    calls: dict[str, set[str]]
    unbounded: frozenset[str]  # dynamic frames, or calls through a pointer

    def without(self, names: tuple[str, ...]) -> CallGraph:
        """The graph with the calls to `names` removed (they are counted apart)."""
        calls = {f: {c for c in cs if _short(c) not in names} for f, cs in self.calls.items()}
        return CallGraph(self.frames, calls, self.unbounded)

    def depth(self, root: str) -> Depth:
        unknown: set[str] = set()

        def deepest(function: str, above: tuple[str, ...]) -> tuple[int, tuple[str, ...]]:
            if function in above:
                unknown.add(f"recursion through {function}")
                return 0, (function,)
            if function not in self.frames:
                unknown.add(function)
                return 0, (function,)
            if function in self.unbounded:
                unknown.add(function)
            below = [deepest(c, (*above, function)) for c in sorted(self.calls.get(function, ()))]
            best = max(below, default=(0, ()))
            return self.frames[function] + best[0], (function, *best[1])

        total, path = deepest(root, ())
        names = tuple(sorted(unknown))
        return Depth(root, None if names else total, tuple(_short(p) for p in path), names)


def _short(title: str) -> str:
    return title.rsplit(":", 1)[-1]


def read_call_graph(build_dir: Path) -> CallGraph:
    """Every `.ci` file of the build folder, merged; a static function keeps its
    `file:name` title, an external one resolves to the global definition."""
    frames: dict[str, int] = {}
    calls: dict[str, set[str]] = {}
    unbounded: set[str] = set()
    edges: list[tuple[str, str]] = []
    for path in sorted(build_dir.glob("*.ci")):
        text = path.read_text(encoding="utf-8")
        for match in _NODE.finditer(text):
            size = _BYTES.search(match["label"])
            if size is None:
                continue  # a declaration: defined in another object
            frames[match["title"]] = int(size["bytes"])
            if "dynamic" in size["kind"] and "bounded" not in size["kind"]:
                unbounded.add(match["title"])
        edges += [(m["source"], m["target"]) for m in _EDGE.finditer(text)]
    for source, target in edges:
        if target == INDIRECT:
            unbounded.add(source)
            continue
        calls.setdefault(source, set()).add(target)
    return CallGraph(frames, calls, frozenset(unbounded))


@dataclass(frozen=True)
class StackReport:
    levels: tuple[tuple[str, Depth], ...]  # (level, its deepest entry point)
    #: thread mode through the calls made with interrupts masked: alone, nothing on top
    masked: Depth | None = None

    @property
    def nested(self) -> int | None:
        total = 0
        for index, (_, depth) in enumerate(self.levels):
            if depth.bytes is None:
                return None
            total += depth.bytes + (EXCEPTION_FRAME_BYTES if index else 0)
        return total

    @property
    def worst(self) -> int | None:
        nested = self.nested
        if self.masked is None or nested is None:
            return nested
        if self.masked.bytes is None:
            return None
        return max(nested, self.masked.bytes)

    def lines(self) -> list[str]:
        out = []
        if self.masked is not None:
            shown = "unknown" if self.masked.bytes is None else f"{self.masked.bytes} B"
            out.append(
                f"thread mode with interrupts masked (alone): {shown}"
                f" ({' > '.join(self.masked.path)})"
            )
        for index, (level, depth) in enumerate(self.levels):
            frame = f" + {EXCEPTION_FRAME_BYTES} B exception frame" if index else ""
            if depth.bytes is None:
                out.append(f"{level}: {depth.root}: unknown ({', '.join(depth.unknown)})")
            else:
                out.append(
                    f"{level}: {depth.root} {depth.bytes} B{frame} ({' > '.join(depth.path)})"
                )
        return out


def stack_report(
    graph: CallGraph, levels: list[tuple[str, list[str]]], masked: tuple[str, ...] = ()
) -> StackReport:
    """The deepest entry point of each preemption level, in nesting order (thread mode
    first). Calls to `masked` functions (which run with interrupts masked) are left out
    of the nesting and counted alone, from the first level's root."""
    chosen = []
    open_graph = graph.without(masked) if masked else graph
    for index, (level, roots) in enumerate(levels):
        depths = [(open_graph if index == 0 else graph).depth(r) for r in roots]
        known = [d for d in depths if d.bytes is not None]
        unknown = [d for d in depths if d.bytes is None]
        chosen.append((level, unknown[0] if unknown else max(known, key=lambda d: d.bytes or 0)))
    alone = graph.depth(levels[0][1][0]) if masked else None
    return StackReport(tuple(chosen), alone)

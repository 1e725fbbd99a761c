"""The static call graph of a linked image: which functions a handler can reach.

Each function's code is disassembled where the ELF's mapping symbols say there is code
(`$t`); literal pools and tables inside a function (`$d`) are skipped, so their words are
never read as branches. A direct branch or call (B, BL, CBZ, CBNZ) names its target; a
BX or BLX through a register other than LR is an indirect branch, which the graph cannot
follow and reports. A function symbol without a size (hand-written library assembly)
extends to the next function symbol.
"""

from __future__ import annotations

import bisect
from collections.abc import Iterator
from dataclasses import dataclass

import capstone  # type: ignore[import-untyped]
from capstone import arm_const as arm

from emulation.armsim import ArmImage, Symbol


class CallGraphError(ValueError):
    """The image's code branches somewhere no function covers."""


@dataclass(frozen=True)
class CallGraph:
    root: str
    calls: dict[str, frozenset[str]]  # function -> the functions it branches to
    indirect: frozenset[str]  # functions that branch through a register

    @property
    def functions(self) -> frozenset[str]:
        return frozenset(self.calls)


def _engine() -> capstone.Cs:
    engine = capstone.Cs(capstone.CS_ARCH_ARM, capstone.CS_MODE_THUMB | capstone.CS_MODE_MCLASS)
    engine.detail = True
    return engine


class _Image:
    def __init__(self, image: ArmImage) -> None:
        self.image = image
        self.functions: list[Symbol] = sorted(
            (s for s in image.symbols.values() if s.is_function), key=lambda s: s.address
        )
        self.starts = [s.address for s in self.functions]
        self.marks = [address for address, _ in image.mapping]

    def extent(self, index: int) -> int:
        symbol = self.functions[index]
        if symbol.size:
            return symbol.size
        following = self.starts[index + 1] if index + 1 < len(self.starts) else symbol.address
        return following - symbol.address

    def owner(self, address: int) -> int:
        index = bisect.bisect_right(self.starts, address) - 1
        if index < 0 or address >= self.starts[index] + self.extent(index):
            raise CallGraphError(f"a branch to 0x{address:08x} lies outside every function")
        return index

    def read(self, address: int, size: int) -> bytes:
        for segment in self.image.segments:
            offset = address - segment.address
            if offset >= 0 and offset + size <= len(segment.data):
                return segment.data[offset : offset + size]
        raise CallGraphError(f"0x{address:08x}..+{size} is not in a loaded segment")

    def code_runs(self, index: int) -> Iterator[tuple[int, int]]:
        """(start, end) of the function's code, literal pools cut out."""
        start = self.starts[index]
        end = start + self.extent(index)
        kind = "t"
        at = bisect.bisect_right(self.marks, start) - 1
        if at >= 0:
            kind = self.image.mapping[at][1]
        position = start
        for address, mark in self.image.mapping[at + 1 :]:
            if address >= end:
                break
            if kind == "t" and address > position:
                yield position, address
            kind, position = mark, address
        if kind == "t" and end > position:
            yield position, end


def _targets(code: bytes, address: int) -> tuple[set[int], bool]:
    targets: set[int] = set()
    indirect = False
    for insn in _engine().disasm(code, address):
        if insn.id in (arm.ARM_INS_BL, arm.ARM_INS_B, arm.ARM_INS_CBZ, arm.ARM_INS_CBNZ):
            targets.update(op.imm for op in insn.operands if op.type == arm.ARM_OP_IMM)
        elif insn.id in (arm.ARM_INS_BLX, arm.ARM_INS_BX):
            registers = [op.reg for op in insn.operands if op.type == arm.ARM_OP_REG]
            indirect |= registers != [arm.ARM_REG_LR]
    return targets, indirect


def call_graph(image: ArmImage, root: str) -> CallGraph:
    """Every function reachable from `root` through direct branches, with its edges."""
    view = _Image(image)
    calls: dict[str, frozenset[str]] = {}
    indirect: set[str] = set()
    pending = [view.owner(image.symbol(root).address)]
    while pending:
        index = pending.pop()
        name = view.functions[index].name
        if name in calls:
            continue
        targets: set[int] = set()
        for start, end in view.code_runs(index):
            found, through_register = _targets(view.read(start, end - start), start)
            targets |= found
            if through_register:
                indirect.add(name)
        owners = {view.owner(t) for t in targets}
        calls[name] = frozenset(view.functions[o].name for o in owners if o != index)
        pending.extend(owners)
    return CallGraph(root, calls, frozenset(indirect))


def reached_functions(image: ArmImage, root: str) -> tuple[frozenset[str], bool]:
    """Functions reachable from `root`, and whether any of them branches indirectly."""
    graph = call_graph(image, root)
    return graph.functions, bool(graph.indirect)

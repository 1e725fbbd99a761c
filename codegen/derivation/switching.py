"""PWM-OFF-PWM switching table, derived from the paper's 60 deg example and Table 1.

Switch numbering follows the paper: T1/T2 are phase A's upper/lower transistors, T3/T4
phase B's and T5/T6 phase C's, each with its antiparallel diode D1..D6 (section 3.2
names D1 as A's upper diode, D4 as B's lower and D6 as C's lower diode).

The anchor (section 3.2): at the 60 deg edge in forward rotation the conduction moves
from BA to CA; A is non-commutating with e_a = +E and its current -I returning through
D1, B (e_b = -E) is turned off with T3 off, and C (e_c = -E) is turned on with T5
modulated. From the anchor alone:

* A is mid flat-top at 60 deg, so its +E flat spans sectors 0-1; B's -E flat ends at
  the edge (sectors 5, 0); C's -E flat starts there (sectors 1, 2). Each flat-top is
  120 deg wide and the opposite flat follows 180 deg later. The three phases come out
  120 deg apart, which the code checks.
* Braking: a conducting phase's current opposes its EMF.
* At an edge, the phase in both sectors is non-commutating, the one leaving is the
  turn-off phase and the one arriving the turn-on phase.
* "Upper" edges (non-commutating current negative, back to the bus through its upper
  diode, as in the anchor) modulate the upper transistors of the turn-on and turn-off
  phases. At the other three edges of each direction the non-commutating current is
  positive and returns through its lower diode; only the lower transistors of the
  (negative-current) turn-on and turn-off phases can then steer the commutation.
  These "lower" edges are the exact mirror image of the paper's case
  (u -> U_d - u, i -> -i, e -> -e), so Eqs. 13-20 hold for them with D the duty of
  the lower transistor; the derivation proves this edge by edge.
* Reverse rotation negates every EMF and runs the sectors the other way (paper 2.2).
"""

from __future__ import annotations

from dataclasses import dataclass
from itertools import pairwise
from typing import Literal

import sympy as sp

from codegen.derivation import symbols as s
from codegen.derivation.circuit import averaged_terminal_voltage, solve_slopes
from codegen.errors import DerivationError

PHASE_NAMES = ("A", "B", "C")
#: The paper's Table 1: Hall code (A B C as bits 2 1 0) of sectors 0..5.
PAPER_HALL_SEQUENCE = (5, 4, 6, 2, 3, 1)

Direction = Literal["forward", "reverse"]
EdgeKind = Literal["upper", "lower"]


def upper_switch(phase: int) -> str:
    return f"T{2 * phase + 1}"


def lower_switch(phase: int) -> str:
    return f"T{2 * phase + 2}"


def upper_diode(phase: int) -> str:
    return f"D{2 * phase + 1}"


def lower_diode(phase: int) -> str:
    return f"D{2 * phase + 2}"


@dataclass(frozen=True)
class Anchor:
    """The paper's worked commutation, as indices: sectors 0 -> 1, forward."""

    sector_before: int = 0
    non_commutating: int = 0  # A, e = +E, current -I through D1
    turn_off: int = 1  # B, e = -E, T3 switched off
    turn_on: int = 2  # C, e = -E, T5 modulated
    non_commutating_emf_sign: int = 1


@dataclass(frozen=True)
class Sector:
    index: int
    #: EMF sign of phases A, B, C in this sector (+1, -1, or 0 while ramping).
    emf_signs: tuple[int, int, int]

    def current_signs(self) -> tuple[int, int, int]:
        """Braking: current opposes EMF; the ramping phase carries none."""
        return tuple(-sign for sign in self.emf_signs)  # type: ignore[return-value]

    def pair_name(self) -> str:
        signs = self.current_signs()
        into = PHASE_NAMES[signs.index(1)]
        out_of = PHASE_NAMES[signs.index(-1)]
        return f"{into}{out_of}"


@dataclass(frozen=True)
class Edge:
    """One commutation: entering `sector_to` from `sector_from` in `direction`."""

    direction: Direction
    sector_from: int
    sector_to: int
    angle_deg: int
    kind: EdgeKind
    non_commutating: int
    turn_off: int
    turn_on: int
    #: EMF signs of A, B, C during the commutation (both commutating phases sit on the
    #: same flat value, the paper's e_b = e_c = -E assumption).
    emf_signs: tuple[int, int, int]
    #: Current signs of A, B, C as they are before and after the commutation.
    current_signs: tuple[int, int, int]

    @property
    def modulated_on(self) -> str:
        return upper_switch(self.turn_on) if self.kind == "upper" else lower_switch(self.turn_on)

    @property
    def modulated_off(self) -> str:
        return upper_switch(self.turn_off) if self.kind == "upper" else lower_switch(self.turn_off)

    @property
    def freewheel_diode(self) -> str:
        """Path of the non-commutating current: upper diode for negative current."""
        nc = self.non_commutating
        return upper_diode(nc) if self.kind == "upper" else lower_diode(nc)

    def terminal_voltages(self, d_on: sp.Expr, d_off: sp.Expr) -> tuple[sp.Expr, ...]:
        """PWM-averaged u_a, u_b, u_c with the two commutating transistors at d_on, d_off."""
        out: list[sp.Expr] = []
        for phase in range(3):
            sign = self.current_signs[phase]
            if phase == self.non_commutating:
                out.append(averaged_terminal_voltage("off", sp.S.Zero, sign))
            elif phase == self.turn_on:
                out.append(averaged_terminal_voltage(self.kind, d_on, sign))
            else:
                out.append(averaged_terminal_voltage(self.kind, d_off, sign))
        return tuple(sp.expand(u) for u in out)

    def back_emfs(self) -> tuple[sp.Expr, ...]:
        return tuple(sign * s.E for sign in self.emf_signs)

    def initial_currents(self) -> tuple[sp.Expr, ...]:
        """i_nc = -+I and i_off = +-I carry the pre-commutation current; i_on = 0."""
        return tuple(
            sp.S.Zero if phase == self.turn_on else self.current_signs[phase] * s.I
            for phase in range(3)
        )

    def describe(self) -> str:
        return (
            f"{self.direction} {self.angle_deg} deg: non-commutating {PHASE_NAMES[self.non_commutating]}"
            f" via {self.freewheel_diode}, off {PHASE_NAMES[self.turn_off]} ({self.modulated_off}),"
            f" on {PHASE_NAMES[self.turn_on]} ({self.modulated_on})"
        )


@dataclass(frozen=True)
class SwitchingTable:
    forward_sectors: tuple[Sector, ...]
    edges: tuple[Edge, ...]

    def sectors(self, direction: Direction) -> tuple[Sector, ...]:
        if direction == "forward":
            return self.forward_sectors
        return tuple(
            Sector(sec.index, tuple(-x for x in sec.emf_signs))  # type: ignore[arg-type]
            for sec in self.forward_sectors
        )

    def edge_into(self, sector: int, direction: Direction) -> Edge:
        for edge in self.edges:
            if edge.sector_to == sector and edge.direction == direction:
                return edge
        raise KeyError((sector, direction))

    def paper_example(self) -> Edge:
        anchor = Anchor()
        return self.edge_into((anchor.sector_before + 1) % 6, "forward")


def _emf_signs_from_anchor(anchor: Anchor) -> tuple[Sector, ...]:
    """Forward EMF sign of each phase in each sector, from the anchor alone."""
    edge_sector = (anchor.sector_before + 1) % 6
    flat_start = {
        # first sector of the flat-top whose sign is given by the anchor
        anchor.non_commutating: (anchor.sector_before, anchor.non_commutating_emf_sign),
        anchor.turn_off: ((anchor.sector_before - 1) % 6, -anchor.non_commutating_emf_sign),
        anchor.turn_on: (edge_sector, -anchor.non_commutating_emf_sign),
    }
    signs = [[0, 0, 0] for _ in range(6)]
    for phase, (start, sign) in flat_start.items():
        for offset in range(2):
            signs[(start + offset) % 6][phase] = sign
            signs[(start + 3 + offset) % 6][phase] = -sign
    positive_starts = sorted(
        (start if sign > 0 else (start + 3) % 6, phase)
        for phase, (start, sign) in flat_start.items()
    )
    gaps = {(b[0] - a[0]) % 6 for a, b in pairwise(positive_starts)}
    if gaps != {2}:
        raise DerivationError(f"anchor does not give a balanced three-phase EMF: {positive_starts}")
    return tuple(Sector(k, tuple(signs[k])) for k in range(6))  # type: ignore[arg-type]


def _edge(direction: Direction, before: Sector, after: Sector, angle: int) -> Edge:
    cur_before, cur_after = before.current_signs(), after.current_signs()
    common = [p for p in range(3) if cur_before[p] and cur_after[p]]
    if len(common) != 1:
        raise DerivationError(
            f"sectors {before.index}->{after.index} share {common}, not one phase"
        )
    nc = common[0]
    off = next(p for p in range(3) if cur_before[p] and not cur_after[p])
    on = next(p for p in range(3) if cur_after[p] and not cur_before[p])
    if cur_before[off] != cur_after[on]:
        raise DerivationError("the turn-on phase must take over the turn-off phase's current")
    emf = [after.emf_signs[p] or before.emf_signs[p] for p in range(3)]
    currents = [cur_before[p] or cur_after[p] for p in range(3)]
    kind: EdgeKind = "upper" if currents[nc] < 0 else "lower"
    return Edge(
        direction=direction,
        sector_from=before.index,
        sector_to=after.index,
        angle_deg=angle,
        kind=kind,
        non_commutating=nc,
        turn_off=off,
        turn_on=on,
        emf_signs=tuple(emf),  # type: ignore[arg-type]
        current_signs=tuple(currents),  # type: ignore[arg-type]
    )


def _check_mirror(edge: Edge, canonical: tuple[sp.Expr, ...]) -> None:
    """Prove the edge obeys Eq. 13 (upper) or its mirror image (lower).

    canonical: Eq. 13 slopes of (non-commutating, off, on) for the paper's edge, as
    functions of that edge's currents (i_nc, i_off, i_on) = (i_a, i_b, i_c).
    """
    u = edge.terminal_voltages(d_on=s.D_on, d_off=s.D_off)
    slopes = solve_slopes(u, edge.back_emfs())
    order = (edge.non_commutating, edge.turn_off, edge.turn_on)
    mirror = 1 if edge.kind == "upper" else -1
    rename = {
        s.i_a: mirror * s.CURRENTS[order[0]],
        s.i_b: mirror * s.CURRENTS[order[1]],
        s.i_c: mirror * s.CURRENTS[order[2]],
    }
    for role, phase, reference in zip(("nc", "off", "on"), order, canonical, strict=True):
        expected = mirror * reference.xreplace(rename)
        if sp.cancel(slopes[phase] - expected) != 0:
            raise DerivationError(f"{edge.describe()}: {role} slope {slopes[phase]} != {expected}")


def derive_switching_table(anchor: Anchor | None = None) -> SwitchingTable:
    anchor = anchor or Anchor()
    forward = _emf_signs_from_anchor(anchor)
    reverse = tuple(Sector(sec.index, tuple(-x for x in sec.emf_signs)) for sec in forward)  # type: ignore[arg-type]
    edges: list[Edge] = []
    for k in range(6):
        nxt = (k + 1) % 6
        boundary = 60 * nxt
        edges.append(_edge("forward", forward[k], forward[nxt], boundary))
        edges.append(_edge("reverse", reverse[nxt], reverse[k], boundary))
    table = SwitchingTable(forward_sectors=forward, edges=tuple(edges))
    example = table.paper_example()
    if (example.non_commutating, example.turn_off, example.turn_on, example.kind) != (
        anchor.non_commutating,
        anchor.turn_off,
        anchor.turn_on,
        "upper",
    ) or (example.modulated_on, example.freewheel_diode) != ("T5", "D1"):
        raise DerivationError(f"table does not reproduce the anchor: {example.describe()}")
    canonical = solve_slopes(example.terminal_voltages(s.D_on, s.D_off), example.back_emfs())
    for edge in table.edges:
        _check_mirror(edge, canonical)
    return table

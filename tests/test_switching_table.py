"""Tests of codegen.derivation.switching: the PWM-OFF-PWM table derived from the paper.

The physics checks rebuild each edge's averaged terminal voltages from the switch names
and the current directions alone, and solve Eq. 1 by hand, so they do not reuse the
table's own `terminal_voltages` or `circuit.solve_slopes`.
"""

from __future__ import annotations

import pytest
import sympy as sp

from codegen.derivation import derive
from codegen.derivation.switching import Direction, Edge, SwitchingTable
from codegen.derivation.symbols import D_off, D_on, E, I, L, U_d

PAIRS = ("BA", "CA", "CB", "AB", "AC", "BC")
DIRECTIONS: tuple[Direction, ...] = ("forward", "reverse")


@pytest.fixture(scope="module")
def table() -> SwitchingTable:
    return derive().switching


def _edge_id(edge: Edge) -> str:
    return f"{edge.direction}-{edge.angle_deg}"


EDGES = derive().switching.edges


def _switch(name: str) -> tuple[int, str]:
    """'T5' -> (phase 2, 'upper'): T1/T2 are A, T3/T4 B, T5/T6 C; odd numbers are upper."""
    number = int(name.removeprefix("T"))
    assert 1 <= number <= 6
    return (number - 1) // 2, "upper" if number % 2 else "lower"


def _averaged_voltage(current_sign: int, modulated: str | None, duty: sp.Expr) -> sp.Expr:
    """Terminal voltage averaged over a PWM period, from first principles.

    A transistor conducts only in its forward direction: the upper one carries current
    into the winding (sign +1), the lower one out of it (sign -1). Whenever the current
    is not in a conducting transistor it freewheels through a diode: into the winding
    from the lower diode (0 V), out of it through the upper diode (U_d).
    """
    diode_voltage = sp.S.Zero if current_sign > 0 else U_d
    if modulated == "upper" and current_sign > 0:
        return duty * U_d + (1 - duty) * diode_voltage
    if modulated == "lower" and current_sign < 0:
        return duty * 0 + (1 - duty) * diode_voltage
    return diode_voltage


def _independent_voltages(edge: Edge) -> list[sp.Expr]:
    on_phase, on_side = _switch(edge.modulated_on)
    off_phase, off_side = _switch(edge.modulated_off)
    assert (on_phase, off_phase) == (edge.turn_on, edge.turn_off)
    out = []
    for phase in range(3):
        sign = edge.current_signs[phase]
        if phase == on_phase:
            out.append(_averaged_voltage(sign, on_side, D_on))
        elif phase == off_phase:
            out.append(_averaged_voltage(sign, off_side, D_off))
        else:
            out.append(_averaged_voltage(sign, None, sp.S.Zero))
    return out


def _lossless_slopes(u: list[sp.Expr], e: list[sp.Expr]) -> list[sp.Expr]:
    """Eq. 1 at R = 0 by hand: the floating star point gives u_n = (sum u - sum e) / 3."""
    u_n = (sum(u) - sum(e)) / 3
    return [(u_x - e_x - u_n) / L for u_x, e_x in zip(u, e, strict=True)]


# --- Sectors ---


def test_forward_sectors_conduct_ba_ca_cb_ab_ac_bc(table: SwitchingTable) -> None:
    sectors = table.forward_sectors
    assert [sector.index for sector in sectors] == list(range(6))
    assert tuple(sector.pair_name() for sector in sectors) == PAIRS


def test_forward_emf_is_a_balanced_trapezoid(table: SwitchingTable) -> None:
    for sector in table.forward_sectors:
        assert sorted(sector.emf_signs) == [-1, 0, 1]
    for phase in range(3):
        signs = [sector.emf_signs[phase] for sector in table.forward_sectors]
        # 120 deg flat-tops, opposite flat 180 deg later.
        assert signs.count(1) == signs.count(-1) == 2
        assert all(signs[k] == -signs[(k + 3) % 6] for k in range(6))


# --- The paper's worked example (section 3.2) ---


def test_paper_example_is_forward_60_deg_ba_to_ca(table: SwitchingTable) -> None:
    edge = table.paper_example()
    assert edge is table.edge_into(1, "forward")
    assert (edge.direction, edge.sector_from, edge.sector_to, edge.angle_deg) == (
        "forward",
        0,
        1,
        60,
    )
    assert (edge.non_commutating, edge.turn_off, edge.turn_on) == (0, 1, 2)
    assert edge.freewheel_diode == "D1"
    assert edge.modulated_on == "T5"
    assert edge.modulated_off == "T3"
    assert edge.kind == "upper"
    assert edge.back_emfs() == (E, -E, -E)
    assert edge.initial_currents() == (-I, I, 0)


# --- Structure of every edge ---


def test_table_has_six_edges_per_direction_one_into_each_sector(table: SwitchingTable) -> None:
    assert len(table.edges) == 12
    for direction in DIRECTIONS:
        edges = [edge for edge in table.edges if edge.direction == direction]
        assert sorted(edge.sector_to for edge in edges) == list(range(6))
        step = 1 if direction == "forward" else -1
        for edge in edges:
            assert edge.sector_to == (edge.sector_from + step) % 6
            # The edge sits at the far end of the lower-numbered sector, mod 360 deg.
            earlier = edge.sector_from if direction == "forward" else edge.sector_to
            assert edge.angle_deg == 60 * ((earlier + 1) % 6)


@pytest.mark.parametrize("edge", EDGES, ids=_edge_id)
def test_edge_has_one_non_commutating_and_distinct_on_off_phases(
    table: SwitchingTable, edge: Edge
) -> None:
    before = table.sectors(edge.direction)[edge.sector_from].current_signs()
    after = table.sectors(edge.direction)[edge.sector_to].current_signs()
    in_both = [p for p in range(3) if before[p] and after[p]]
    assert in_both == [edge.non_commutating]
    assert len({edge.non_commutating, edge.turn_off, edge.turn_on}) == 3
    assert before[edge.turn_off] != 0 and after[edge.turn_off] == 0
    assert before[edge.turn_on] == 0 and after[edge.turn_on] != 0


@pytest.mark.parametrize("edge", EDGES, ids=_edge_id)
def test_turn_on_phase_takes_over_the_turn_off_current(table: SwitchingTable, edge: Edge) -> None:
    before = table.sectors(edge.direction)[edge.sector_from].current_signs()
    after = table.sectors(edge.direction)[edge.sector_to].current_signs()
    assert after[edge.turn_on] == before[edge.turn_off]
    assert after[edge.non_commutating] == before[edge.non_commutating]
    # And the edge's own record of the currents agrees with the sectors.
    assert edge.current_signs[edge.turn_on] == before[edge.turn_off]
    assert edge.current_signs[edge.non_commutating] == -before[edge.turn_off]


@pytest.mark.parametrize("direction", DIRECTIONS)
def test_edge_kinds_alternate_around_the_cycle(table: SwitchingTable, direction: Direction) -> None:
    step = 1 if direction == "forward" else -1
    kinds = [table.edge_into((step * k) % 6, direction).kind for k in range(6)]
    assert all(kinds[k] != kinds[(k + 1) % 6] for k in range(6))
    assert kinds.count("upper") == kinds.count("lower") == 3


@pytest.mark.parametrize("edge", EDGES, ids=_edge_id)
def test_kind_follows_the_non_commutating_current(edge: Edge) -> None:
    nc_current = edge.current_signs[edge.non_commutating]
    assert edge.kind == ("upper" if nc_current < 0 else "lower")
    nc_diode = int(edge.freewheel_diode.removeprefix("D"))
    assert (nc_diode - 1) // 2 == edge.non_commutating
    assert (nc_diode % 2 == 1) == (edge.kind == "upper")


def test_reverse_edge_swaps_turn_on_and_turn_off_of_the_forward_edge(
    table: SwitchingTable,
) -> None:
    for angle in range(0, 360, 60):
        (forward,) = [e for e in table.edges if e.angle_deg == angle and e.direction == "forward"]
        (reverse,) = [e for e in table.edges if e.angle_deg == angle and e.direction == "reverse"]
        assert (reverse.sector_from, reverse.sector_to) == (forward.sector_to, forward.sector_from)
        assert reverse.non_commutating == forward.non_commutating
        assert reverse.turn_on == forward.turn_off
        assert reverse.turn_off == forward.turn_on
        assert reverse.kind != forward.kind


@pytest.mark.parametrize("edge", EDGES, ids=_edge_id)
def test_upper_edges_modulate_odd_switches_and_lower_edges_even(edge: Edge) -> None:
    numbers = [int(name.removeprefix("T")) for name in (edge.modulated_on, edge.modulated_off)]
    parity = 1 if edge.kind == "upper" else 0
    assert [number % 2 for number in numbers] == [parity, parity]
    assert [(number - 1) // 2 for number in numbers] == [edge.turn_on, edge.turn_off]
    # The modulated transistors must be able to carry the commutating currents.
    for phase in (edge.turn_on, edge.turn_off):
        assert edge.current_signs[phase] == (1 if edge.kind == "upper" else -1)


# --- Eq. 15 at every edge ---


@pytest.mark.parametrize("edge", EDGES, ids=_edge_id)
def test_table_voltages_match_the_switch_level_average(edge: Edge) -> None:
    table_u = edge.terminal_voltages(d_on=D_on, d_off=D_off)
    for mine, theirs in zip(_independent_voltages(edge), table_u, strict=True):
        assert sp.simplify(mine - theirs) == 0


@pytest.mark.parametrize("edge", EDGES, ids=_edge_id)
def test_eq_15_holds_at_every_edge(edge: Edge) -> None:
    slopes = _lossless_slopes(_independent_voltages(edge), list(edge.back_emfs()))
    mirror = 1 if edge.kind == "upper" else -1
    eq_15_slope = ((2 - D_on - D_off) * U_d - 4 * E) / (3 * L)
    assert sp.simplify(slopes[edge.non_commutating] - mirror * eq_15_slope) == 0
    # Floating star point: the turn-on and turn-off slopes cancel the held phase's.
    assert sp.simplify(sum(slopes)) == 0
    # With Eq. 15's duty sum the non-commutating current is held.
    held = {D_off: 2 - 4 * E / U_d - D_on}
    assert sp.simplify(slopes[edge.non_commutating].subs(held)) == 0


@pytest.mark.parametrize("edge", EDGES, ids=_edge_id)
def test_commutating_emfs_sit_on_the_same_flat_opposite_the_held_phase(edge: Edge) -> None:
    signs = edge.emf_signs
    assert signs[edge.turn_on] == signs[edge.turn_off] == -signs[edge.non_commutating]
    # Braking: every conducting current opposes its EMF.
    for phase in range(3):
        assert edge.current_signs[phase] == -signs[phase]


# --- Reverse rotation ---


def test_reverse_emf_is_the_negated_forward_emf(table: SwitchingTable) -> None:
    forward = table.sectors("forward")
    reverse = table.sectors("reverse")
    assert forward == table.forward_sectors
    for fwd, rev in zip(forward, reverse, strict=True):
        assert rev.index == fwd.index
        assert rev.emf_signs == tuple(-sign for sign in fwd.emf_signs)
        assert rev.emf_signs != fwd.emf_signs


def test_reverse_edges_see_negated_emf(table: SwitchingTable) -> None:
    for angle in range(0, 360, 60):
        (forward,) = [e for e in table.edges if e.angle_deg == angle and e.direction == "forward"]
        (reverse,) = [e for e in table.edges if e.angle_deg == angle and e.direction == "reverse"]
        assert reverse.emf_signs == tuple(-sign for sign in forward.emf_signs)
        assert reverse.back_emfs() == tuple(-emf for emf in forward.back_emfs())

"""The method-independent part of the core: Hall decoding and the composed decision.

Tables (from the derived switching table and the spec's Hall sequence):
  bldc_sector_of_hall[8]        Hall code -> sector, 0xFF for 000 and 111
  bldc_edge_of_hall_pair[64]    previous code << 3 | code -> edge 0..11 or EDGE_NONE
  bldc_edge_switch[12][2]       edge -> {switch at D_on, switch at D_off}
Functions:
  bldc_edge_of()    the Hall edge's part (inline): one table lookup
  bldc_commutate()  all of it on plain inputs: the reference API of tests and verifier
"""

from __future__ import annotations

from codegen.abi import (
    EDGE_NONE,
    INPUTS,
    INVALID_SECTOR,
    OUTPUTS,
    flag_const,
    value_const,
)
from codegen.derivation.paper import Derivation
from codegen.ir.nodes import (
    Expr,
    Function,
    IAddr,
    IBin,
    ICall,
    ILookup,
    Param,
    SAssign,
    SIf,
    SLet,
    SLetStruct,
    SReturn,
    SStore,
    SVar,
    Table,
    cast,
    cmp,
    const,
    fld,
    lor,
    select,
    shl,
    var,
)
from codegen.ir.types import U8, U16, U32
from codegen.spec_model import Spec


def _switch_index(name: str) -> int:
    return int(name[1:]) - 1  # "T5" -> 4


def edge_index(direction: str, sector: int) -> int:
    """The core's edge numbering: forward edges 0..5, reverse 6..11, by sector entered."""
    return (0 if direction == "forward" else 6) + sector


def edge_of_hall_pair(sequence: tuple[int, ...]) -> list[int]:
    """(previous code << 3 | code) -> edge index, EDGE_NONE for an invalid pair."""
    sector_of = {code: sector for sector, code in enumerate(sequence)}
    table = [EDGE_NONE] * 64
    for previous, before in sector_of.items():
        for code, after in sector_of.items():
            if after == (before + 1) % 6:
                table[(previous << 3) | code] = edge_index("forward", after)
            elif before == (after + 1) % 6:
                table[(previous << 3) | code] = edge_index("reverse", after)
    return table


def hall_tables(spec: Spec, derivation: Derivation) -> tuple[Table, Table, Table]:
    sector_of_hall = [INVALID_SECTOR] * 8
    for sector, code in enumerate(spec.hall.sequence):
        sector_of_hall[code] = sector
    sectors = Table(
        "bldc_sector_of_hall",
        U8,
        tuple((s,) for s in sector_of_hall),
        tuple(
            f"{code:03b}: " + ("invalid" if s == INVALID_SECTOR else f"sector {s}")
            for code, s in enumerate(sector_of_hall)
        ),
        "Hall code -> sector (Table 1 order), 0xFF for 000 and 111",
        static=False,
    )
    pairs = []
    notes = []
    for index, edge in enumerate(edge_of_hall_pair(spec.hall.sequence)):
        previous, code = index >> 3, index & 7
        if edge == EDGE_NONE:
            what = "invalid: every switch off"
        else:
            direction = "forward" if edge < 6 else "reverse"
            what = f"{direction} into sector {edge % 6}"
        pairs.append((edge,))
        notes.append(f"{previous:03b} -> {code:03b}: {what}")
    edges = Table(
        "bldc_edge_of_hall_pair",
        U8,
        tuple(pairs),
        tuple(notes),
        "(previous Hall code << 3 | Hall code) -> edge, BLDC_EDGE_NONE when invalid",
        static=False,
    )
    rows = []
    comments = []
    for direction in ("forward", "reverse"):
        for sector in range(6):
            e = derivation.switching.edge_into(sector, direction)
            rows.append((_switch_index(e.modulated_on), _switch_index(e.modulated_off)))
            comments.append(
                f"edge {edge_index(direction, sector)}: into sector {sector} "
                f"({60 * sector}-{60 * sector + 60} deg), {e.describe()}"
            )
    switches = Table(
        "bldc_edge_switch",
        U8,
        tuple(rows),
        tuple(comments),
        "edge -> {switch at D_on, switch at D_off} (codegen/derivation/switching.py)",
        static=False,
    )
    return sectors, edges, switches


def edge_of_function(edges: Table) -> Function:
    previous, code = var("previous_hall_code", U32), var("hall_code", U32)
    index = IBin(U32, "|", shl(previous, 3), code)
    invalid = lor(cmp(">", previous, const(7)), cmp(">", code, const(7)))
    return Function(
        c_name="bldc_edge_of",
        py_name="edge_of",
        params=(Param("previous_hall_code", U32), Param("hall_code", U32)),
        returns=U32,
        inline=True,
        doc="The commutation of a Hall edge (pure): 0..11 (see bldc_edge_switch), or "
        "BLDC_EDGE_NONE for 000, 111, a code above 7 or a jump that is not one sector",
        body=(
            SReturn(
                select(invalid, value_const("EDGE_NONE"), cast(ILookup(U8, edges, index), U32))
            ),
        ),
    )


def commutate_function(
    sectors: Table,
    switches: Table,
    edge_of: Function,
    bus_condition: Function,
    timing: Function,
) -> Function:
    """bldc_commutate(): the edge, the bus state and the timing on plain inputs."""

    def field(name: str) -> Expr:
        return cast(fld("inputs", name, INPUTS.field(name).ctype), U32)

    hall, previous = var("hall_code", U32), var("previous_hall_code", U32)
    period = var("period", U32)
    edge, sector = var("edge", U32), var("sector", U32)
    valid_codes = SIf(
        cmp("<=", hall, const(7)),
        (
            SAssign("sector", cast(ILookup(U8, sectors, hall), U32), "the sector of the new code"),
            SAssign("edge", ICall(U32, edge_of, (previous, hall))),
        ),
    )
    outputs = [
        SStore("out", "turn_on_compare", const(0, U16)),
        SStore("out", "turn_off_compare", const(0, U16)),
        SStore("out", "commutation_ticks", const(0, U16)),
        SStore("out", "turn_on_switch", cast(value_const("NO_SWITCH"), U8)),
        SStore("out", "turn_off_switch", cast(value_const("NO_SWITCH"), U8)),
        SStore("out", "sector", cast(sector, U8)),
        SStore("out", "flags", cast(flag_const("INVALID_HALL"), U8)),
    ]
    t = "timing"
    apply = (
        SLetStruct(
            "bus", ICall(U32, bus_condition, (field("bus_voltage_adc"),)), "bldc_bus_condition()"
        ),
        SLetStruct(
            t,
            ICall(
                U32,
                timing,
                (
                    IAddr(U32, "bus"),
                    period,
                    field("phase_current_adc"),
                    field("main_duty_counts"),
                ),
            ),
        ),
        SStore("out", "turn_on_compare", fld(t, "turn_on_compare", U16)),
        SStore("out", "turn_off_compare", fld(t, "turn_off_compare", U16)),
        SStore("out", "commutation_ticks", fld(t, "commutation_ticks", U16)),
        SStore("out", "flags", cast(fld(t, "flags", U16), U8)),
        SIf(
            cmp(">=", period, fld(t, "period_min", U32)),
            (
                SStore("out", "turn_on_switch", ILookup(U8, switches, edge, 0)),
                SStore("out", "turn_off_switch", ILookup(U8, switches, edge, 1)),
            ),
            comment="a shorter interval (over-speed) or over-voltage: the safe state",
        ),
    )
    return Function(
        c_name="bldc_commutate",
        py_name="commutate",
        params=(
            Param("inputs", struct=INPUTS, const=True),
            Param("out", struct=OUTPUTS, const=False),
        ),
        doc="Commutation decision on plain inputs: bldc_edge_of(), bldc_bus_condition() and "
        "bldc_commutation_timing() for the same inputs (pure, reentrant)",
        body=(
            SLet("hall_code", field("hall_code")),
            SLet("previous_hall_code", field("previous_hall_code")),
            SLet("period", field("hall_period_ticks")),
            SVar("edge", U32, value_const("EDGE_NONE")),
            SVar("sector", U32, value_const("INVALID_SECTOR")),
            valid_codes,
            *outputs,
            SIf(cmp("<", edge, value_const("EDGE_COUNT")), apply),
        ),
    )

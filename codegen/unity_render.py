"""Unity tests of the generated core: one C test function per `UnityCase`.

The cases come from the exact symbolic model; this module only prints them. Every C
literal, name and comment is made here, so the templates lay out ready strings and do no
arithmetic (STYLE: print in Python, lay out in templates). Only the core's public API
(`bldc_commutate`, its structures and the BLDC_* constants) appears in the output, so
the tests survive any rewrite of the core's internals.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

from codegen import abi
from codegen.render import render
from codegen.unity_cases import UnityCase

#: output path (relative to generated/<spec>/) -> template (relative to templates/)
TEMPLATES = {
    "tests/test_bldc_commutation.c": "unity/test_bldc_commutation.c.j2",
    "tests/test_runner.c": "unity/test_runner.c.j2",
}
TEST_PREFIX = "test_bldc_commutate_should_"
NO_SWITCH = abi.NO_SWITCH  # also the sector of an invalid Hall code
#: BLDC_FLAG_* of bldc_commutation.h (the ABI), lowest bit first
FLAG_NAMES = {f.value: f"BLDC_FLAG_{f.name}" for f in abi.FLAGS}
#: Written into the outputs before the call: a field the core forgets to set then shows
#: up as a failure, the same on host and target, instead of as an uninitialised read.
POISON_U16 = 0xA5A5
POISON_U8 = 0xA5


@dataclass(frozen=True)
class Field:
    """One `.name = value,` line of a structure initialiser; comment is "" or " /* */"."""

    name: str
    value: str
    comment: str


@dataclass(frozen=True)
class Check:
    """One assertion on `actual` (out.<name>, or a masked form); tolerance is empty
    for exact checks."""

    name: str
    expected: str
    tolerance: str
    comment: str
    actual: str = ""


@dataclass(frozen=True)
class CaseContext:
    function: str
    comment: str
    inputs: tuple[Field, ...]
    within: tuple[Check, ...]
    exact: tuple[Check, ...]


def c_comment(text: str) -> str:
    """Text that cannot end the C comment it is placed in, on one line."""
    return " ".join(text.replace("*/", "* /").split())


def trailing(text: str) -> str:
    return f" /* {c_comment(text)} */" if text else ""


def unsigned(value: int) -> str:
    return f"{value}u"


def hex8(value: int) -> str:
    return f"0x{value:02X}u"


def hall_field(name: str, code: int) -> Field:
    return Field(name, unsigned(code), trailing(f"Hall {code:03b}" if 0 <= code <= 7 else ""))


def switch_literal(switch: int) -> tuple[str, str]:
    """T1..T6 are switch indices 0..5 (bldc_commutation.h)."""
    if switch == NO_SWITCH:
        return "BLDC_NO_SWITCH", trailing("all off")
    return hex8(switch), trailing(f"T{switch + 1}")


def flags_literal(flags: int) -> str:
    names = [name for bit, name in FLAG_NAMES.items() if flags & bit]
    unknown = flags & ~sum(FLAG_NAMES)
    if unknown:
        names.append(hex8(unknown))
    return " | ".join(names) if names else hex8(0)


def sector_literal(sector: int) -> tuple[str, str]:
    return hex8(sector), trailing("invalid Hall code" if sector == NO_SWITCH else "")


def case_context(case: UnityCase) -> CaseContext:
    on_value, on_comment = switch_literal(case.turn_on_switch)
    off_value, off_comment = switch_literal(case.turn_off_switch)
    sector_value, sector_comment = sector_literal(case.sector)
    return CaseContext(
        function=TEST_PREFIX + case.name,
        comment=c_comment(case.comment),
        inputs=(
            hall_field("hall_code", case.hall_code),
            hall_field("previous_hall_code", case.previous_hall_code),
            Field("hall_period_ticks", unsigned(case.hall_period_ticks), ""),
            Field("bus_voltage_adc", unsigned(case.bus_voltage_adc), ""),
            Field("phase_current_adc", unsigned(case.phase_current_adc), ""),
            Field("main_duty_counts", unsigned(case.main_duty_counts), ""),
        ),
        within=(
            Check(
                "turn_on_compare",
                unsigned(case.turn_on_compare),
                unsigned(case.turn_on_tolerance),
                "",
            ),
            Check(
                "turn_off_compare",
                unsigned(case.turn_off_compare),
                unsigned(case.turn_off_tolerance),
                "",
            ),
            Check(
                "commutation_ticks",
                unsigned(case.commutation_ticks),
                unsigned(case.commutation_tolerance),
                "",
            ),
        ),
        exact=(
            Check("turn_on_switch", on_value, "", on_comment),
            Check("turn_off_switch", off_value, "", off_comment),
            Check("sector", sector_value, "", sector_comment),
            Check(
                "flags",
                flags_literal(case.flags & case.flags_mask),
                "",
                ""
                if case.flags_mask == 0xFF
                else trailing("flags within tolerance of a threshold masked"),
                "out.flags"
                if case.flags_mask == 0xFF
                else f"(uint8_t)(out.flags & {hex8(case.flags_mask)})",
            ),
        ),
    )


def poison_fields() -> tuple[Field, ...]:
    marker = ""
    return (
        Field("turn_on_compare", f"0x{POISON_U16:04X}u", marker),
        Field("turn_off_compare", f"0x{POISON_U16:04X}u", marker),
        Field("commutation_ticks", f"0x{POISON_U16:04X}u", marker),
        Field("turn_on_switch", hex8(POISON_U8), marker),
        Field("turn_off_switch", hex8(POISON_U8), marker),
        Field("sector", hex8(POISON_U8), marker),
        Field("flags", hex8(POISON_U8), marker),
    )


def render_unity_tests(
    cases: Sequence[UnityCase], provenance: Callable[[str], str]
) -> dict[str, str]:
    """{path relative to generated/<spec>/: text} for the test file and its runner.

    `provenance` maps a template path ("templates/unity/...") to the first-line
    provenance text, as `codegen.render.provenance` does for a spec.
    """
    contexts = [case_context(case) for case in cases]
    context = {
        "cases": contexts,
        "functions": [c.function for c in contexts],
        "poison": poison_fields(),
    }
    return {
        out: render(template, provenance=provenance(f"templates/{template}"), **context)
        for out, template in TEMPLATES.items()
    }

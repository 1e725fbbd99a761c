"""Regression tests of the scaling defects an independent check found (issue 19).

The motor is tests/fixtures/specs/offset_conventional.yaml: a 3.0 V ADC reference with
a 0.5 V current-sense offset puts zero current at 2048/3 = 682.667 codes, and its range
edges fall between codes. Every expected value below is worked out by hand in this file
from the spec's numbers, without codegen's or the oracle's conversions.
"""

from __future__ import annotations

import ctypes
from fractions import Fraction
from pathlib import Path

import pytest

from codegen.generate import render_all, write_tree
from sim.sil import CoreInputs, CoreOutputs, compile_core

ROOT = Path(__file__).resolve().parents[1]
SPEC = ROOT / "tests" / "fixtures" / "specs" / "offset_conventional.yaml"

# The spec's numbers, typed in again.
V_REF, BITS, V_OFFSET, GAIN = Fraction(3), 12, Fraction(1, 2), Fraction(1, 10)  # V, -, V, V/A
DIVIDER = 16
K_E = Fraction(4, 1000) / 2  # 4 V/krpm line to line -> per phase, V/rpm
POLE_PAIRS, HALL_HZ, L_H = 4, 2_000_000, Fraction(4, 10000)
P = 72_000_000 // (16_000 * 2)  # centre-aligned 16 kHz: 2250 counts
I_MIN, I_MAX = Fraction(1, 2), Fraction(15)
ZERO_CODE = V_OFFSET / V_REF * 2**BITS  # 682.667
AMPS_PER_CODE = V_REF / (GAIN * 2**BITS)
VOLTS_PER_CODE = V_REF * DIVIDER / 2**BITS
FORWARD = (5, 1)  # Hall codes (code, previous): sector 0 -> 1 of [1, 5, 4, 6, 2, 3]
INPUT_SATURATED, TIME_CLAMPED = 0x04, 0x10
DEAD_TIME = Fraction(400, 10**9)
#: the current loop's sample after a commutation's end: a 16 kHz PWM period, then the
#: ADC's injected sequence, 3 + 4 x (1.5 + 12.5) cycles of its 12 MHz clock
SAMPLE_ROOM = Fraction(1, 16_000) + Fraction(3 + 4 * 14, 12_000_000)
#: a commutation ends (dead time + 4 us + the sample) f_hall, rounded up, before its
#: sector does
END_GUARD = -(-(DEAD_TIME + Fraction(4, 10**6) + SAMPLE_ROOM) * HALL_HZ // 1)


def amps(code: int, zero: Fraction = ZERO_CODE) -> Fraction:
    return (code - zero) * AMPS_PER_CODE


def rpm(ticks: int) -> Fraction:
    return Fraction(60 * HALL_HZ, 6 * POLE_PAIRS * ticks)


def eq20_ticks(
    ticks: int, bus: int, code: int, on: int, off: int, zero: Fraction = ZERO_CODE
) -> Fraction:
    """t_com = 3 I L / (U_d (1 + D_on - 2 D_off) - 2E), in Hall ticks."""
    u_d, e = bus * VOLTS_PER_CODE, K_E * rpm(ticks)
    w = u_d * (1 + Fraction(on, P) - 2 * Fraction(off, P)) - 2 * e
    return 3 * amps(code, zero) * L_H / w * HALL_HZ


@pytest.fixture(scope="module")
def core(tmp_path_factory: pytest.TempPathFactory) -> ctypes.CDLL:
    out = tmp_path_factory.mktemp("gen") / "offset_conventional"
    write_tree(render_all(SPEC).files, out)
    dll = ctypes.CDLL(str(compile_core(out / "c", out / "build")))
    dll.bldc_commutate.argtypes = [ctypes.POINTER(CoreInputs), ctypes.POINTER(CoreOutputs)]
    return dll


def run(core: ctypes.CDLL, ticks: int, bus: int, code: int, duty: int) -> CoreOutputs:
    out = CoreOutputs()
    core.bldc_commutate(
        ctypes.byref(CoreInputs(*FORWARD, ticks, bus, code, duty)), ctypes.byref(out)
    )
    return out


def test_offset_should_be_carried_exactly_through_eq_20(core: ctypes.CDLL) -> None:
    """Defect 1: 1/3 code of offset error is 20 ticks here (a small current, a long
    commutation: t_com = 1052 of 2074 ticks); the budget is 16 ticks."""
    ticks, bus, code, duty = 2074, 2048, 700, 1355  # 2411 rpm, 24 V, 0.127 A, D_on 0.602
    out = run(core, ticks, bus, code, duty)
    exact = eq20_ticks(ticks, bus, code, out.turn_on_compare, out.turn_off_compare)
    rounded = eq20_ticks(ticks, bus, code, out.turn_on_compare, out.turn_off_compare, Fraction(683))
    assert abs(out.commutation_ticks - exact) <= 16, (out.commutation_ticks, float(exact))
    assert exact < ticks and abs(rounded - exact) > 16  # what the whole-code offset gave


def test_a_current_just_above_zero_should_take_the_whole_sector_where_w_is_negative(
    core: ctypes.CDLL,
) -> None:
    """Defect 1: code 683 is +2.4 mA; at 1500 rpm and D_on 0.6 Eq. 20's denominator is
    negative, so the current never reaches zero: t_com is the sector (less the end
    guard and the sector-shortening margin), not 0."""
    assert amps(683) > 0 and abs(amps(683) - Fraction(244, 100000)) < Fraction(1, 10000)
    ticks = 3333  # 1500 rpm
    out = run(core, ticks, 2048, 683, 1350)
    u_d, e = 2048 * VOLTS_PER_CODE, K_E * rpm(ticks)
    d_off = Fraction(out.turn_off_compare, P)
    assert u_d * (1 + Fraction(out.turn_on_compare, P) - 2 * d_off) - 2 * e < 0
    assert END_GUARD == 144  # 143.6 ticks at 2 MHz
    margin = -(-ticks // 16)  # hall.sector_shortening 5 % (the default): 1/16, rounded up
    assert out.commutation_ticks == ticks - margin - END_GUARD and out.flags & TIME_CLAMPED


def test_the_range_edges_should_be_decided_exactly(core: ctypes.CDLL) -> None:
    """Defects 2 and 3: the last in-range code at 15 A is 2730, the first at 0.5 A 751."""
    assert amps(2730) <= I_MAX < amps(2731)
    assert amps(750) < I_MIN <= amps(751)
    nominal = (3333, 2048, 1350)

    def flagged(code: int) -> bool:
        ticks, bus, duty = nominal
        return bool(run(core, ticks, bus, code, duty).flags & INPUT_SATURATED)

    assert [flagged(c) for c in (750, 751, 2730, 2731)] == [True, False, False, True]


def test_headers_should_not_claim_what_the_core_does_not_do() -> None:
    """Defect 4: the improved rule ignores the main duty, so its header must not claim
    to saturate or flag it; the conventional method does both."""
    improved = (ROOT / "generated" / "paper_motor" / "c" / "bldc_commutation.h").read_text()
    assert "main duty is not used" in improved.lower() or "the main duty is not used" in improved
    assert "main duty, saturated at P and flagged" not in improved
    conventional = render_all(SPEC).files["c/bldc_commutation.h"]
    assert "saturated at P and flagged" in conventional


def test_printed_bounds_should_be_rounded_up() -> None:
    from codegen.methods.paper_method import round_up

    assert round_up(Fraction(5003, 10000)) == 0.501
    assert round_up(Fraction(1, 2)) == 0.5
    header = (ROOT / "generated" / "paper_motor" / "c" / "bldc_commutation.h").read_text()
    assert "duties <= 0.508 counts" in header  # 0.5078125, rounded up

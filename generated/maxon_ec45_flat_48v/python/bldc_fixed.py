# Generated from template templates/python/bldc_fixed.py.j2 with spec spec/example_maxon_ec45_flat_48v.yaml (sha256 88a70eb72b9494810aaa1248e2beb874e1bc6578ac98fdca4370be1ee72c27cc). Do not edit: regenerate with `make`.
"""Bit-exact integer model of bldc_commutation.c (method "improved").

Same formats, rounding and saturation as the C: a drop-in reference for test benches.
Standalone: the standard library only.
"""

from __future__ import annotations

from typing import NamedTuple

PERIOD_COUNTS = 3600
NO_SWITCH = 0xFF
INVALID = 0xFF
FLAG_HIGH_SPEED = 0x01
FLAG_FAIL_AREA_CLAMPED = 0x02
FLAG_INPUT_SATURATED = 0x04
FLAG_INVALID_HALL = 0x08
FLAG_TIME_CLAMPED = 0x10

X_FRAC_BITS = 2
X_SCALE = 4
X_ROUND = 2
TB_SHIFT = 3
TB_ROUND = 4
K_XQ = 2196945455
K_X_NUM = 48332800000
K_X_DEN = 11
K_GQ = 8897143
PERIOD_MIN_TICKS = 228
PERIOD_MAX_TICKS = 8333
BUS_CODE_MIN = 2306
BUS_CODE_MAX = 3546
CURRENT_OFFSET_CODE = 2048
CURRENT_CODE_MAX = 1191
METHOD = "improved"

SECTOR_OF_HALL = (255, 5, 3, 4, 1, 0, 2, 255, )
EDGE_SWITCH = (
    ((1, 5), (4, 2), (3, 1), (0, 4), (5, 3), (2, 0), ),  # forward
    ((3, 5), (0, 2), (5, 1), (2, 4), (1, 3), (4, 0), ),  # reverse
)


class Outputs(NamedTuple):
    turn_on_compare: int
    turn_off_compare: int
    commutation_ticks: int
    turn_on_switch: int
    turn_off_switch: int
    sector: int
    flags: int


def _divide_rounded(numerator: int, denominator: int) -> int:
    quotient = numerator // denominator
    remainder = numerator - quotient * denominator
    return quotient + 1 if remainder >= denominator - remainder else quotient


def _clamp_duty(counts: int) -> int:
    return min(max(counts, 0), PERIOD_COUNTS)


def _safe(sector: int, flags: int) -> Outputs:
    return Outputs(0, 0, 0, NO_SWITCH, NO_SWITCH, sector, flags)


def commutate(
    hall_code: int,
    previous_hall_code: int,
    hall_period_ticks: int,
    bus_voltage_adc: int,
    phase_current_adc: int,
    main_duty_counts: int,
) -> Outputs:
    """bldc_commutate() for uint8/uint16 inputs."""
    flags = 0
    sector = SECTOR_OF_HALL[hall_code & 7]
    previous = SECTOR_OF_HALL[previous_hall_code & 7]
    if hall_code > 7 or previous_hall_code > 7 or sector == INVALID or previous == INVALID:
        return _safe(INVALID, FLAG_INVALID_HALL)
    if sector == (previous + 1) % 6:
        direction = 0
    elif previous == (sector + 1) % 6:
        direction = 1
    else:
        return _safe(sector, FLAG_INVALID_HALL)
    period, bus = hall_period_ticks, bus_voltage_adc
    if period < PERIOD_MIN_TICKS or bus > BUS_CODE_MAX:
        return _safe(sector, FLAG_INPUT_SATURATED)
    if period > PERIOD_MAX_TICKS:
        period = PERIOD_MAX_TICKS
        flags |= FLAG_INPUT_SATURATED
    if bus < BUS_CODE_MIN:
        bus = BUS_CODE_MIN
        flags |= FLAG_INPUT_SATURATED
    current = 0
    if phase_current_adc < CURRENT_OFFSET_CODE:
        flags |= FLAG_INPUT_SATURATED
    else:
        current = phase_current_adc - CURRENT_OFFSET_CODE
        if current > CURRENT_CODE_MAX:
            current = CURRENT_CODE_MAX
            flags |= FLAG_INPUT_SATURATED
    main_duty = main_duty_counts
    if main_duty > PERIOD_COUNTS:
        main_duty = PERIOD_COUNTS
        flags |= FLAG_INPUT_SATURATED

    tb = period * bus
    tb_shifted = (tb + TB_ROUND) >> TB_SHIFT
    x_q = _divide_rounded(K_XQ, tb_shifted)
    x_c = (x_q + X_ROUND) >> X_FRAC_BITS
    ptb = tb * K_X_DEN
    high_speed = K_X_NUM > ptb * PERIOD_COUNTS
    if high_speed:
        flags |= FLAG_HIGH_SPEED
    if METHOD == "improved":
        if high_speed:
            on, off = _clamp_duty(2 * PERIOD_COUNTS - x_c), 0
        else:
            on, off = PERIOD_COUNTS, _clamp_duty(PERIOD_COUNTS - x_c)
    elif METHOD == "conventional":
        on = main_duty
        off = 2 * PERIOD_COUNTS - x_c - main_duty
        below = ptb * (2 * PERIOD_COUNTS - main_duty)
        above = ptb * (PERIOD_COUNTS - main_duty)
        if K_X_NUM > below or K_X_NUM < above:
            flags |= FLAG_FAIL_AREA_CLAMPED
        off = _clamp_duty(off)
    else:
        on, off = main_duty, 0

    ticks = period
    w_q = (2 * PERIOD_COUNTS + 2 * on - 4 * off) * X_SCALE - x_q
    if current == 0:
        ticks = 0
    elif w_q <= 0:
        flags |= FLAG_TIME_CLAMPED
    else:
        numerator = K_GQ * current
        denominator = bus * w_q
        high = numerator >> 32
        shift = high.bit_length()
        den32 = denominator >> shift
        if den32 == 0:
            flags |= FLAG_TIME_CLAMPED
        else:
            ticks = _divide_rounded(numerator >> shift, den32)
            if ticks > period:
                ticks = period
                flags |= FLAG_TIME_CLAMPED
    return Outputs(on, off, ticks, EDGE_SWITCH[direction][sector][0], EDGE_SWITCH[direction][sector][1], sector, flags)

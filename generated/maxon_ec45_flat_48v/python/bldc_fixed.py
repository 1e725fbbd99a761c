# Generated from template templates/python/bldc_fixed.py.j2 with spec spec/example_maxon_ec45_flat_48v.yaml (sha256 dece2274d408914f53e74b84728750ad8d9e2a754cdc79404df2f8daae1a20d5). Do not edit: regenerate with `make`.
"""Bit-exact integer model of bldc_commutation.c (method "improved").

Same formats, rounding and saturation as the C: a drop-in reference for test benches.
Standalone: the standard library only.
"""

from __future__ import annotations

from typing import NamedTuple

PERIOD_COUNTS = 3600
NO_SWITCH = 0xFF
EDGE_NONE = 0xFF
INVALID_SECTOR = 0xFF
FLAG_HIGH_SPEED = 0x01
FLAG_FAIL_AREA_CLAMPED = 0x02
FLAG_INPUT_SATURATED = 0x04
FLAG_INVALID_HALL = 0x08
FLAG_TIME_CLAMPED = 0x10

X_FRAC_BITS = 10
X_SCALE = 1024
X_ROUND = 512
K_X_HIGH, K_X_LOW, K_X_SHIFT = 2196945454, 1117, 11
K_G_HIGH, K_G_LOW, K_G_SHIFT = 2277668571, 0, 0
HIGH_SPEED_TB = 1220526
K_X_NUM = 48332800000
K_X_DEN = 11
PERIOD_MIN_TICKS = 228
PERIOD_MAX_TICKS = 8333
PERIOD_CAP_TICKS = 65535
PERIOD_NEVER = 0x10000
BUS_CODE_MIN = 2306
BUS_CODE_MAX = 3546
CURRENT_OFFSET_CODE = 2048
CURRENT_CODE_MAX = 1191
METHOD = "improved"

SECTOR_OF_HALL = (255, 5, 3, 4, 1, 0, 2, 255, )
EDGE_OF_HALL_PAIR = (255, 255, 255, 255, 255, 255, 255, 255, 255, 255, 255, 10, 255, 0, 255, 255, 255, 255, 255, 4, 255, 255, 8, 255, 255, 5, 9, 255, 255, 255, 255, 255, 255, 255, 255, 255, 255, 6, 2, 255, 255, 11, 255, 255, 1, 255, 255, 255, 255, 255, 3, 255, 7, 255, 255, 255, 255, 255, 255, 255, 255, 255, 255, 255, )
EDGE_SWITCH = ((1, 5), (4, 2), (3, 1), (0, 4), (5, 3), (2, 0), (3, 5), (0, 2), (5, 1), (2, 4), (1, 3), (4, 0), )


class Outputs(NamedTuple):
    turn_on_compare: int
    turn_off_compare: int
    commutation_ticks: int
    turn_on_switch: int
    turn_off_switch: int
    sector: int
    flags: int


class Timing(NamedTuple):
    """bldc_timing_t."""

    period_min: int
    on: int
    off: int
    ticks: int
    flags: int


class Bus(NamedTuple):
    x_numerator: int
    high_speed_period: int
    time_numerator: int
    period_min: int
    bus_code: int
    flags: int


def _divide_long(high: int, low: int, shift: int, divisor: int) -> int:
    q_high = high // divisor
    remainder = ((high - q_high * divisor) << shift) | low
    return (q_high << shift) + (remainder + (divisor >> 1)) // divisor


def bus_condition(bus_code: int) -> Bus:
    """bldc_bus_condition()."""
    code, period_min, flags = bus_code, PERIOD_MIN_TICKS, 0
    if code > BUS_CODE_MAX:
        code, period_min, flags = BUS_CODE_MAX, PERIOD_NEVER, FLAG_INPUT_SATURATED
    elif code < BUS_CODE_MIN:
        code, flags = BUS_CODE_MIN, FLAG_INPUT_SATURATED
    return Bus(
        _divide_long(K_X_HIGH, K_X_LOW, K_X_SHIFT, code),
        (HIGH_SPEED_TB + code - 1) // code,
        _divide_long(K_G_HIGH, K_G_LOW, K_G_SHIFT, code),
        period_min,
        code,
        flags,
    )


def _c_divide(numerator: int, denominator: int) -> int:
    """C's signed division: truncates toward zero."""
    quotient = abs(numerator) // abs(denominator)
    return quotient if (numerator >= 0) == (denominator > 0) else -quotient


def edge_of(previous_hall_code: int, hall_code: int) -> int:
    """bldc_edge_of(): 0..11, or EDGE_NONE."""
    return EDGE_OF_HALL_PAIR[(previous_hall_code << 3) | hall_code]


def commutation_timing(bus: Bus, period: int, current_adc: int, main_duty: int) -> Timing:
    """bldc_commutation_timing()."""
    flags = bus.flags
    period = min(period, PERIOD_CAP_TICKS)
    if period < bus.period_min:
        return Timing(PERIOD_NEVER, 0, 0, 0, flags | FLAG_INPUT_SATURATED)
    if period > PERIOD_MAX_TICKS:
        flags |= FLAG_INPUT_SATURATED
    current = current_adc - CURRENT_OFFSET_CODE
    if current < 0 or current > CURRENT_CODE_MAX:
        flags |= FLAG_INPUT_SATURATED
    x_q = (bus.x_numerator + (period >> 1)) // period
    x_c = (x_q + X_ROUND) >> X_FRAC_BITS
    high_speed = period < bus.high_speed_period
    if high_speed:
        flags |= FLAG_HIGH_SPEED
    if METHOD == "improved":
        if high_speed:
            on, off = max(2 * PERIOD_COUNTS - x_c, 0), 0
        else:
            on, off = PERIOD_COUNTS, max(PERIOD_COUNTS - x_c, 0)
    else:
        if main_duty > PERIOD_COUNTS:
            main_duty = PERIOD_COUNTS
            flags |= FLAG_INPUT_SATURATED
        on = main_duty
        if METHOD == "conventional":
            ptb = period * bus.bus_code * K_X_DEN
            if K_X_NUM > ptb * (2 * PERIOD_COUNTS - main_duty) or K_X_NUM < ptb * (
                PERIOD_COUNTS - main_duty
            ):
                flags |= FLAG_FAIL_AREA_CLAMPED
            off = min(max(2 * PERIOD_COUNTS - x_c - on, 0), PERIOD_COUNTS)
        else:
            off = 0
    w_q = (2 * PERIOD_COUNTS + 2 * on - 4 * off) * X_SCALE - x_q
    if w_q <= 0:
        ticks = 0
        if current > 0:
            ticks = period
            flags |= FLAG_TIME_CLAMPED
    else:
        ticks = max(_c_divide(bus.time_numerator * current + (w_q >> 1), w_q), 0)
        if ticks > period:
            ticks = period
            flags |= FLAG_TIME_CLAMPED
    return Timing(bus.period_min, on, off, ticks, flags)




def commutate_edge(
    bus: Bus, previous_hall_code: int, hall_code: int, period: int, current_adc: int, main_duty: int
) -> tuple[int, int, int, int, int]:
    """bldc_commutate() after the Hall codes' range check: (on, off, ticks, edge, flags)."""
    edge = edge_of(previous_hall_code, hall_code)
    if edge == EDGE_NONE:
        return 0, 0, 0, EDGE_NONE, FLAG_INVALID_HALL
    timing = commutation_timing(bus, period, current_adc, main_duty)
    if period < timing.period_min:
        edge = EDGE_NONE
    return timing.on, timing.off, timing.ticks, edge, timing.flags


def commutate(
    hall_code: int,
    previous_hall_code: int,
    hall_period_ticks: int,
    bus_voltage_adc: int,
    phase_current_adc: int,
    main_duty_counts: int,
) -> Outputs:
    """bldc_commutate() for uint8/uint16 inputs."""
    if hall_code > 7 or previous_hall_code > 7:
        return Outputs(0, 0, 0, NO_SWITCH, NO_SWITCH, INVALID_SECTOR, FLAG_INVALID_HALL)
    on, off, ticks, edge, flags = commutate_edge(
        bus_condition(bus_voltage_adc),
        previous_hall_code,
        hall_code,
        hall_period_ticks,
        phase_current_adc,
        main_duty_counts,
    )
    on_switch, off_switch = EDGE_SWITCH[edge] if edge != EDGE_NONE else (NO_SWITCH, NO_SWITCH)
    return Outputs(on, off, ticks, on_switch, off_switch, SECTOR_OF_HALL[hall_code], flags)

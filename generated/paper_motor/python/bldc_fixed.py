# Generated from template templates/python/bldc_fixed.py.j2 with spec spec/paper_motor.yaml (sha256 6e149e81b56aaf0ac5791d1ff3459c01b1ba7fdb119982156e9fd60cd3b42049). Do not edit: regenerate with `bldc-codegen generate spec/paper_motor.yaml`.
"""Bit-exact integer model of bldc_commutation.c (method "improved").

Printed from the same IR as the C (codegen/ir/py_printer.py): the same operations,
rounding and saturation, on Python integers (the IR proof rules out every overflow, so
they give the C's results). Standalone: the standard library only.
"""

from __future__ import annotations

from typing import NamedTuple

METHOD = "improved"
BLDC_PERIOD_MIN_TICKS = 2000  # 5000 rpm reads 2000 or more (whole ticks): a shorter period is over-speed
BLDC_BUS_CODE_MAX = 3385  # 30 V (30 V): above it over-voltage
BLDC_PERIOD_NEVER = 65536  # above every 16-bit period: the safe state
BLDC_FLAG_INPUT_SATURATED = 4  # an input was outside the spec's range
BLDC_BUS_CODE_MIN = 2257  # 20 V (20 V)
N_X_HIGH = 2396667768  # N_X >> 10, round(K_X 2^6), K_X = 3.834668e+10 (Eqs. 3, 9)
N_X_LOW = 609  # N_X mod 2^10
N_X_SHIFT = 10
HIGH_SPEED_TB = 10651857  # ceil(K_X / P): 4E > U_d <=> T B < it (Eq. 18)
N_G_HIGH = 1407534545  # N_G >> 0, round(K_G 2^6 / 1), K_G = 2.199273e+07 (Eq. 20)
N_G_LOW = 0  # N_G mod 2^0
N_G_SHIFT = 0
BLDC_PERIOD_CAP_TICKS = 65535  # the Hall counter's range: longer periods saturate
BLDC_PERIOD_MAX_TICKS = 50000  # 200 rpm reads 50000 or less (whole ticks): a longer period is flagged
BLDC_ADC_CODE_MAX = 4095  # 12-bit ADC full scale
BLDC_CURRENT_CODE_LOW = 2048  # first code at or above 0 A (0 A)
BLDC_CURRENT_CODE_HIGH = 2668  # last code at or below 10 A (9.99 A)
CURRENT_OFFSET_Q = 2048  # zero current: 2048 codes x 1
BLDC_COMMUTATION_GUARD_TICKS = 62  # a commutation ends at least this long before its sector does: dead time 0.5 us + 4 us of the end's latency (the next edge switches on the other switch of the leg the end switched off) + one current sample (a PWM period and the ADC's injected sequence: the braking-current loop samples between commutations)
BLDC_FLAG_HIGH_SPEED = 1  # Eq. 18 high-speed segment: 4E > U_d (the turn-off phase is off)
BLDC_PWM_PERIOD_COUNTS = 3600  # TIM1 counts per PWM period: duty 1
BLDC_FLAG_TIME_CLAMPED = 16  # the commutation does not finish within the sector: clamped to it
BLDC_EDGE_NONE = 255  # no valid commutation: every switch off
BLDC_INVALID_SECTOR = 255  # the sector of Hall code 000 or 111
BLDC_NO_SWITCH = 255  # no switch: every transistor of that role off
BLDC_FLAG_INVALID_HALL = 8  # Hall code 000/111 or an impossible jump: every switch off
BLDC_EDGE_COUNT = 12  # edge = 6 x direction + sector entered (0 forward, 1 reverse)
BLDC_X_FRAC_BITS = 6  # fraction bits of X_q
FLAG_HIGH_SPEED = 1  # Eq. 18 high-speed segment: 4E > U_d (the turn-off phase is off)
FLAG_FAIL_AREA_CLAMPED = 2  # no duty pair in [0, 1] holds the current: clamped
FLAG_INPUT_SATURATED = 4  # an input was outside the spec's range
FLAG_INVALID_HALL = 8  # Hall code 000/111 or an impossible jump: every switch off
FLAG_TIME_CLAMPED = 16  # the commutation does not finish within the sector: clamped to it


# Hall code -> sector (Table 1 order), 0xFF for 000 and 111
BLDC_SECTOR_OF_HALL = (
    255,
    5,
    3,
    4,
    1,
    0,
    2,
    255,
)


# (previous Hall code << 3 | Hall code) -> edge, BLDC_EDGE_NONE when invalid
BLDC_EDGE_OF_HALL_PAIR = (
    255,
    255,
    255,
    255,
    255,
    255,
    255,
    255,
    255,
    255,
    255,
    10,
    255,
    0,
    255,
    255,
    255,
    255,
    255,
    4,
    255,
    255,
    8,
    255,
    255,
    5,
    9,
    255,
    255,
    255,
    255,
    255,
    255,
    255,
    255,
    255,
    255,
    6,
    2,
    255,
    255,
    11,
    255,
    255,
    1,
    255,
    255,
    255,
    255,
    255,
    3,
    255,
    7,
    255,
    255,
    255,
    255,
    255,
    255,
    255,
    255,
    255,
    255,
    255,
)


# edge -> {switch at D_on, switch at D_off} (codegen/derivation/switching.py)
BLDC_EDGE_SWITCH = (
    (1, 5),
    (4, 2),
    (3, 1),
    (0, 4),
    (5, 3),
    (2, 0),
    (3, 5),
    (0, 2),
    (5, 1),
    (2, 4),
    (1, 3),
    (4, 0),
)


class Inputs(NamedTuple):
    """bldc_inputs_t: Inputs of one commutation decision (bldc_commutate)"""

    hall_code: int  # A B C as bits 2 1 0
    previous_hall_code: int  # code of the sector being left: gives the direction
    hall_period_ticks: int  # last 60 degree interval, Hall ticks
    bus_voltage_adc: int  # bus code
    phase_current_adc: int  # current code of the commutated current I
    main_duty_counts: int  # current controller output, TIM1 counts


class Outputs(NamedTuple):
    """bldc_outputs_t: Result of one commutation decision"""

    turn_on_compare: int  # D_on: ON time of turn_on_switch in TIM1 counts
    turn_off_compare: int  # D_off: ON time of turn_off_switch in TIM1 counts
    commutation_ticks: int  # Eq. 20 in Hall ticks, at most the Hall period
    turn_on_switch: int  # 0..5 (T1..T6) or BLDC_NO_SWITCH
    turn_off_switch: int  # 0..5 (T1..T6) or BLDC_NO_SWITCH
    sector: int  # sector entered, 0..5 in Table 1 order; 0xFF if invalid
    flags: int  # BLDC_FLAG_*


class Timing(NamedTuple):
    """bldc_timing_t: Duties and commutation time for one speed, current and main duty: what the next Hall edge applies"""

    period_min: int  # an edge with a shorter interval goes to the safe state: BLDC_PERIOD_MIN_TICKS, or BLDC_PERIOD_NEVER when these values must not be applied
    turn_on_compare: int  # D_on in TIM1 counts, 0..P
    turn_off_compare: int  # D_off in TIM1 counts, 0..P
    commutation_ticks: int  # Eq. 20 in Hall ticks, 0..T
    flags: int  # BLDC_FLAG_*


class Bus(NamedTuple):
    """bldc_bus_t: What the Hall-edge step needs of the bus voltage (see the formats above)"""

    x_numerator: int  # round(N_X / B): X = x_numerator / T in Q(f) counts
    high_speed_period: int  # ceil(C / B): Eq. 18's high-speed segment below it
    time_numerator: int  # round(N_G / B): Eq. 20's numerator per unit current
    period_min: int  # BLDC_PERIOD_MIN_TICKS, or BLDC_PERIOD_NEVER when over-voltage
    bus_code: int  # the saturated bus code B
    flags: int  # BLDC_FLAG_INPUT_SATURATED when the code was saturated


def _c_div(numerator: int, denominator: int) -> int:
    """C's integer division: truncates toward zero."""
    quotient = abs(numerator) // abs(denominator)
    return quotient if (numerator >= 0) == (denominator > 0) else -quotient


def divide_long(high: int, low: int, shift: int, divisor: int) -> int:
    """round(N / divisor) for N = high 2^shift + low: two 32-bit divides, no 64-bit helper. N / divisor = q_high 2^shift + (r 2^shift + low) / divisor, r = high mod divisor. (bldc_divide_long)."""
    q_high = high // divisor
    remainder = (high % divisor << shift) + low
    return (q_high << shift) + (remainder + (divisor >> 1)) // divisor


def bus_condition(bus_code: int) -> Bus:
    """Saturate a bus code and precompute its reciprocals (pure, reentrant) (bldc_bus_condition)."""
    code = bus_code
    period_min = BLDC_PERIOD_MIN_TICKS
    flags = 0
    if code > BLDC_BUS_CODE_MAX:
        code = BLDC_BUS_CODE_MAX
        period_min = BLDC_PERIOD_NEVER  # over-voltage: every edge goes to the safe state
        flags = BLDC_FLAG_INPUT_SATURATED
    elif code < BLDC_BUS_CODE_MIN:
        code = BLDC_BUS_CODE_MIN
        flags = BLDC_FLAG_INPUT_SATURATED
    bus = Bus(divide_long(N_X_HIGH, N_X_LOW, N_X_SHIFT, code), (HIGH_SPEED_TB + code - 1) // code, divide_long(N_G_HIGH, N_G_LOW, N_G_SHIFT, code), period_min, code, flags)
    return bus


def commutation_timing(bus: Bus, period_ticks: int, current_adc: int, main_duty_counts: int) -> Timing:
    """Duties and commutation time (pure, reentrant): period in Hall ticks, current as its ADC code, main duty in TIM1 counts; any uint32_t value of each is allowed (bldc_commutation_timing)."""
    flags = bus.flags
    period = BLDC_PERIOD_CAP_TICKS if period_ticks > BLDC_PERIOD_CAP_TICKS else period_ticks  # the proven range: the full Hall counter
    if period < bus.period_min:  # above the top speed or over-voltage: braking is no longer controlled
        safe = Timing(BLDC_PERIOD_NEVER, 0, 0, 0, flags | BLDC_FLAG_INPUT_SATURATED)
        return safe
    if period > BLDC_PERIOD_MAX_TICKS:  # below the minimum speed: still exact
        flags |= BLDC_FLAG_INPUT_SATURATED
    current_code = BLDC_ADC_CODE_MAX if current_adc > BLDC_ADC_CODE_MAX else current_adc  # above the ADC's range: full scale
    if current_adc < BLDC_CURRENT_CODE_LOW or current_adc > BLDC_CURRENT_CODE_HIGH:  # outside the braking-current range
        flags |= BLDC_FLAG_INPUT_SATURATED
    current = current_code - CURRENT_OFFSET_Q  # I in codes, offset removed
    latest = period * 15 // 16 - BLDC_COMMUTATION_GUARD_TICKS  # the latest end: the guard and the sector-shortening margin before the sector's end (positive from the minimum period on), so the next edge, up to hall.sector_shortening early, switches the other switch of the leg on at least the dead time after this end switched its partner off
    x_q = (bus.x_numerator + (period >> 1)) // period  # X = P 4E/U_d in Q6 counts (Eqs. 3, 9)
    x_c = (x_q + 32) >> 6  # X in counts
    high_speed = 1 if period < bus.high_speed_period else 0  # Eq. 18: 4E > U_d, exactly
    if high_speed != 0:
        flags |= BLDC_FLAG_HIGH_SPEED
    on = 0
    off = 0
    if high_speed != 0:  # Eq. 18
        on = 0 if 2 * BLDC_PWM_PERIOD_COUNTS - x_c < 0 else 2 * BLDC_PWM_PERIOD_COUNTS - x_c  # D_on = 2 - 4E/U_d; 0 above the upper speed limit 4E > 2 U_d
        off = 0  # the turn-off phase off
    else:
        on = BLDC_PWM_PERIOD_COUNTS  # the turn-on phase fully on
        off = 0 if BLDC_PWM_PERIOD_COUNTS - x_c < 0 else BLDC_PWM_PERIOD_COUNTS - x_c  # D_off = 1 - 4E/U_d
    w_q = (2 * BLDC_PWM_PERIOD_COUNTS + 2 * on - 4 * off) * 64 - x_q  # Eq. 20's denominator at the emitted duties, Q6
    ticks = 0
    if w_q <= 0:  # the turn-off current never reaches zero: the whole sector
        if current > 0:  # unless there is no current to commutate
            ticks = latest
            flags |= BLDC_FLAG_TIME_CLAMPED
    else:
        t = _c_div(bus.time_numerator * current + (w_q >> 1), w_q)  # Eq. 20
        ticks = 0 if t < 0 else t  # a negative current: nothing to commutate
        if ticks > latest:
            flags |= BLDC_FLAG_TIME_CLAMPED
        ticks = latest if ticks > latest else ticks  # at most the sector, less the guard
    timing = Timing(bus.period_min, on, off, ticks, flags)
    return timing


def edge_of(previous_hall_code: int, hall_code: int) -> int:
    """The commutation of a Hall edge (pure): 0..11 (see bldc_edge_switch), or BLDC_EDGE_NONE for 000, 111, a code above 7 or a jump that is not one sector (bldc_edge_of)."""
    return BLDC_EDGE_NONE if previous_hall_code > 7 or hall_code > 7 else BLDC_EDGE_OF_HALL_PAIR[(previous_hall_code << 3 | hall_code)]


def commutate(inputs: Inputs) -> Outputs:
    """Commutation decision on plain inputs: bldc_edge_of(), bldc_bus_condition() and bldc_commutation_timing() for the same inputs (pure, reentrant) (bldc_commutate)."""
    hall_code = inputs.hall_code
    previous_hall_code = inputs.previous_hall_code
    period = inputs.hall_period_ticks
    edge = BLDC_EDGE_NONE
    sector = BLDC_INVALID_SECTOR
    if hall_code <= 7:
        sector = BLDC_SECTOR_OF_HALL[hall_code]  # the sector of the new code
        edge = edge_of(previous_hall_code, hall_code)
    out_turn_on_compare = 0
    out_turn_off_compare = 0
    out_commutation_ticks = 0
    out_turn_on_switch = BLDC_NO_SWITCH
    out_turn_off_switch = BLDC_NO_SWITCH
    out_sector = sector
    out_flags = BLDC_FLAG_INVALID_HALL
    if edge < BLDC_EDGE_COUNT:
        bus = bus_condition(inputs.bus_voltage_adc)  # bldc_bus_condition()
        timing = commutation_timing(bus, period, inputs.phase_current_adc, inputs.main_duty_counts)
        out_turn_on_compare = timing.turn_on_compare
        out_turn_off_compare = timing.turn_off_compare
        out_commutation_ticks = timing.commutation_ticks
        out_flags = timing.flags
        if period >= timing.period_min:  # a shorter interval (over-speed) or over-voltage: the safe state
            out_turn_on_switch = BLDC_EDGE_SWITCH[edge][0]
            out_turn_off_switch = BLDC_EDGE_SWITCH[edge][1]
    return Outputs(out_turn_on_compare, out_turn_off_compare, out_commutation_ticks, out_turn_on_switch, out_turn_off_switch, out_sector, out_flags)

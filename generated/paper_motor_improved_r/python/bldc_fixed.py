# Generated from template templates/python/bldc_fixed.py.j2 with spec spec/paper_motor_improved_r.yaml (sha256 9f5d9c8963649549b4e129e1bd9cd35baa3c8e343f67f4b67f06c6141ed1f434). Do not edit: regenerate with `bldc-codegen generate spec/paper_motor_improved_r.yaml`.
"""Bit-exact integer model of bldc_commutation.c (method "improved_r").

Printed from the same IR as the C (codegen/ir/py_printer.py): the same operations,
rounding and saturation, on Python integers (the IR proof rules out every overflow, so
they give the C's results). Standalone: the standard library only.
"""

from __future__ import annotations

from typing import NamedTuple

METHOD = "improved_r"
BLDC_PERIOD_MIN_TICKS = 2000  # 5000 rpm reads 2000 or more (whole ticks): a shorter period is over-speed
BLDC_BUS_CODE_MAX = 3385  # 30 V (30 V): above it over-voltage
BLDC_PERIOD_NEVER = 65536  # above every 16-bit period: the safe state
BLDC_FLAG_INPUT_SATURATED = 4  # an input was outside the spec's range
BLDC_BUS_CODE_MIN = 2257  # 20 V (20 V)
N_X_HIGH = 2396667768  # N_X >> 11, round(K_X 2^7), K_X = 3.834668e+10
N_X_LOW = 1219  # N_X mod 2^11
N_X_SHIFT = 11
KYX_Q = 1891788  # K_Y / K_X in Q44: Y per unit = x_numerator K_Y/K_X
BLDC_PERIOD_CAP_TICKS = 65535  # the Hall counter's range: longer periods saturate
BLDC_PERIOD_MAX_TICKS = 50000  # 200 rpm reads 50000 or less (whole ticks): a longer period is flagged
BLDC_COMMUTATION_GUARD_TICKS = 62  # a commutation ends at least this long before its sector does: dead time 0.5 us + 4 us of the end's latency (the next edge switches on the other switch of the leg the end switched off) + one current sample (a PWM period and the ADC's injected sequence: the braking-current loop samples between commutations)
BLDC_ADC_CODE_MAX = 4095  # 12-bit ADC full scale
BLDC_CURRENT_CODE_LOW = 2048  # first code at or above 0 A (0 A)
BLDC_CURRENT_CODE_HIGH = 2668  # last code at or below 10 A (9.99 A)
CURRENT_OFFSET_Q = 2048  # zero current: 2048 codes x 1
CARRIER_DEN = 1  # N = floor(T CARRIER_DEN / CARRIER_NUM)
CARRIER_NUM = 50  # tau = CARRIER_NUM / CARRIER_DEN = 50 Hall ticks per PWM period
PERIOD_Q = 460800  # P in Q7 counts
RAMP_Q = 2796202667  # (-phi_1/4) / K_rho: the EMF ramp's forcing over rho, per X per tick
GROWTH_Q = 694935041  # hold slope x tau: the held duty sum's growth per carrier period, per X per tick
PHI0 = 2  # phi_0 of the spec's EMF at the edge (X phi_0/4)
STEP_DECAY_Q = 2516582  # y_1 = K_rho tau = 1.875000e-02 in Q27: rho x over one PWM period
BLDC_FLAG_TIME_CLAMPED = 16  # the commutation does not finish within the sector: clamped to it
BLDC_FLAG_FAIL_AREA_CLAMPED = 2  # no duty pair in [0, 1] holds the current: clamped
BLDC_FLAG_HIGH_SPEED = 1  # Eq. 18 high-speed segment: 4E > U_d (the turn-off phase is off)
BLDC_EDGE_NONE = 255  # no valid commutation: every switch off
BLDC_INVALID_SECTOR = 255  # the sector of Hall code 000 or 111
BLDC_NO_SWITCH = 255  # no switch: every transistor of that role off
BLDC_FLAG_INVALID_HALL = 8  # Hall code 000/111 or an impossible jump: every switch off
BLDC_EDGE_COUNT = 12  # edge = 6 x direction + sector entered (0 forward, 1 reverse)
BLDC_PWM_PERIOD_COUNTS = 3600  # TIM1 counts per PWM period: duty 1
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


# D^(2^k) in Q32 for k = 9 .. 0 (row step: 2^k = 2^9 >> step), D = e^-y_1, y_1 = R tau / (L f_hall) = 1.875000e-02: the turn-off current's decay over 2^k PWM periods
BLDC_DECAY = (
    290893,
    35346494,
    389630643,
    1293619290,
    2357128029,
    3181790030,
    3696712610,
    3984627933,
    4136888524,
    4215186937,
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
    """bldc_bus_t: What the timing step needs of the bus voltage (see the formats above)"""

    x_numerator: int  # round(N_X / B): X = x_numerator / T in Q(fc) counts
    y_numerator: int  # Y per unit of current, Q(fc + gy): Y = 3 P R I / U_d
    a_numerator: int  # A rho per unit of current, Q(fc + ga)
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
    xn = divide_long(N_X_HIGH, N_X_LOW, N_X_SHIFT, code)  # round(N_X / B)
    yn = (xn * KYX_Q + 1073741824) >> 31  # Y per unit of current
    bus = Bus(xn, yn, yn, period_min, code, flags)
    return bus


def commutation_timing(bus: Bus, period_ticks: int, current_adc: int, main_duty_counts: int) -> Timing:
    """Duties and commutation time of the resistance-aware rule (pure, reentrant); any uint32_t value of each parameter is allowed. The rule holds the current by itself: the main duty is not used (bldc_commutation_timing)."""
    flags = bus.flags
    measured = BLDC_PERIOD_CAP_TICKS if period_ticks > BLDC_PERIOD_CAP_TICKS else period_ticks  # the Hall counter's range
    if measured < bus.period_min:  # above the top speed or over-voltage: braking is no longer controlled
        safe = Timing(BLDC_PERIOD_NEVER, 0, 0, 0, flags | BLDC_FLAG_INPUT_SATURATED)
        return safe
    if measured > BLDC_PERIOD_MAX_TICKS:  # below the minimum speed
        flags |= BLDC_FLAG_INPUT_SATURATED
    period = BLDC_PERIOD_MAX_TICKS if measured > BLDC_PERIOD_MAX_TICKS else measured  # the rule's constants cover the speed range
    latest = measured * 15 // 16 - BLDC_COMMUTATION_GUARD_TICKS  # the latest end: the guard and the sector-shortening margin before the sector's end (positive from the minimum period on), so the next edge, up to hall.sector_shortening early, switches the other switch of the leg on at least the dead time after this end switched its partner off
    current_code = BLDC_ADC_CODE_MAX if current_adc > BLDC_ADC_CODE_MAX else current_adc  # above the ADC's range: full scale
    if current_adc < BLDC_CURRENT_CODE_LOW or current_adc > BLDC_CURRENT_CODE_HIGH:  # outside the braking-current range
        flags |= BLDC_FLAG_INPUT_SATURATED
    current = current_code - CURRENT_OFFSET_Q  # I in codes, offset removed
    i = 0 if current < 0 else current  # negative currents count as 0
    x = (bus.x_numerator + (period >> 1)) // period  # X in Q7 counts
    y = (bus.y_numerator * i + 4096) >> 13  # Y = 3 P R I / U_d, Q7
    a_rho = y  # A rho = 3 P R I / U_d x (L / (R T_s)) rho: the current at the edge, Q7 (= Y: the same constant and format)
    periods = (period * 15 // 16 - BLDC_COMMUTATION_GUARD_TICKS) * CARRIER_DEN // CARRIER_NUM  # N: whole PWM periods in the sector, less the guard and the margin at its end
    sigma0 = 2 * PERIOD_Q + y - x  # Sigma(0) = 2P + Y - (sigma_0/4) X: the held duty sum at the edge's EMFs
    per_tick = divide_long(x, 0, 15, period)  # X / T in Q22
    q = per_tick * RAMP_Q >> 30  # q = (-phi_1/4) X / rho: the EMF ramp's forcing, Q12
    growth = per_tick * GROWTH_Q >> 32  # the held sum's growth per PWM period, Q16
    ca2 = 2 * (a_rho - ((q + 16) >> 5) - ((x * PHI0 + 2) >> 2))  # 2 (A rho - q - (phi_0/4) X)
    cb = ((x * PHI0 + 2) >> 2) + ((q + 16) >> 5)  # (phi_0/4) X + q
    skipped = 10 - (1 if periods < 1 else periods).bit_length()  # the steps whose 2^k is past the sector
    first = 0 if skipped < 0 else skipped  # the first step whose 2^k fits in the sector: 2^9 >> step <= N (a larger candidate is past the sector, from n = 0: the same result, fewer steps)
    n = 0
    e = 2147483648
    end_h = -1
    end_e = 0
    for step in range(first, 10):  # binary lifting: n = the last carrier boundary at which the current remains
        m = n + (512 >> step)  # the next candidate: n + 2^k, 2^k = 2^9 >> step
        if m <= periods:
            em = e * BLDC_DECAY[step] >> 32  # e^-rho x_m in Q31
            total = sigma0 + (growth * m >> 9)  # Sigma at m: the held duty sum
            held = 0 if total < 0 else 2 * PERIOD_Q if total > 2 * PERIOD_Q else total  # the duties' range: C_on + C_off in [0, 2P]
            fd = 3 * (0 if held - PERIOD_Q < 0 else held - PERIOD_Q) - held - PERIOD_Q  # F_d = 2 C_off - C_on - P = 3 C_off - (C_on + C_off) - P of the split
            h = (ca2 - 2 * fd) * em + (fd + cb) * 4294967296 - q * (STEP_DECAY_Q * m)  # 2^(32+fc) rho g at m
            if h >= 0:  # the turn-off current has not reached zero at m (else: the last candidate refused is n + 1, the end)
                n = m
                e = em
            else:
                end_h = h
                end_e = em
    end = periods if n + 1 > periods else n + 1  # the first carrier boundary with the current at zero (or the sector's last)
    end_total = sigma0 + (growth * end >> 9)  # Sigma at the end: the held duty sum
    end_held = 0 if end_total < 0 else 2 * PERIOD_Q if end_total > 2 * PERIOD_Q else end_total  # C_on + C_off in [0, 2P]
    end_on = PERIOD_Q if end_held > PERIOD_Q else end_held
    end_off = 0 if end_held - PERIOD_Q < 0 else end_held - PERIOD_Q
    room = PERIOD_Q - end_off if end_on > PERIOD_Q - end_off else end_on  # what the split can give: C_on down to 0, C_off up to P
    shortfall = 3 * (2147483648 - end_e >> 9)  # 3 (1 - e) in Q22
    overshoot = 0 - end_h >> 11  # -rho g / 3 in Q28, > 0
    cap = ((room >> 1) + 1) * shortfall  # (room + 1) 3 (1 - e): a larger easing is cut to the room below
    numerator = cap if overshoot > cap else overshoot  # the overshoot, at most the cap (it never binds sooner than the room)
    eased_upper = numerator >> 16  # numerator / 2^16
    eased_middle = (eased_upper % shortfall << 8) + (numerator >> 8 & 255)  # the remainder, then the next byte
    eased_lower = (eased_middle % shortfall << 8) + (numerator & 255)  # the remainder, then the last byte
    eased = ((3 if eased_upper // shortfall > 3 else eased_upper // shortfall) << 16) + ((255 if eased_middle // shortfall > 255 else eased_middle // shortfall) << 8) + (256 if (eased_lower + (shortfall >> 1)) // shortfall > 256 else (eased_lower + (shortfall >> 1)) // shortfall)  # delta = -rho g / (3 (1 - e)) in Q6: ends the current at the boundary (at most room + 1: the numerator's cap)
    delta = (room >> 1 if (1073741823 if eased > 1073741823 else eased) > room >> 1 else 1073741823 if eased > 1073741823 else eased) << 1  # the easing in Q7, at most the room
    eased_on = end_on - delta  # C_on - delta
    eased_off = end_off + delta  # C_off + delta
    on = 0 if eased_on < 0 else eased_on  # delta <= the room: never below 0
    off = PERIOD_Q if eased_off > PERIOD_Q else eased_off  # never above P
    if n >= periods:  # the current remains at every carrier boundary
        flags |= BLDC_FLAG_TIME_CLAMPED
    if end_total > 2 * PERIOD_Q or end_total < 0:  # no duty pair in [0, 1] holds the current
        flags |= BLDC_FLAG_FAIL_AREA_CLAMPED
    if end_total < PERIOD_Q:  # the upper segment: the turn-off phase at most eased, the turn-on one modulated
        flags |= BLDC_FLAG_HIGH_SPEED
    ticks = latest if n >= periods else (end * CARRIER_NUM + 0) // CARRIER_DEN  # round(end tau), a carrier boundary; the whole sector less the guard when the current remains
    timing = Timing(bus.period_min, (on + 64) >> 7, (off + 64) >> 7, latest if ticks > latest else ticks, flags)
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

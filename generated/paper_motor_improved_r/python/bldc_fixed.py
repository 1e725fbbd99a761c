# Generated from template templates/python/bldc_fixed.py.j2 with spec spec/paper_motor_improved_r.yaml (sha256 313dd61f95b5018d390bb349cd716e3ca5c6158c512536194e3b94687b277ff1). Do not edit: regenerate with `make`.
"""Bit-exact integer model of bldc_commutation.c (method "improved_r").

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

# Resistance-aware rule (codegen/improved_r_rule): see bldc_commutation.h.
N_X_HIGH, N_X_LOW, N_X_SHIFT = 2396667768, 1219, 11
N_Y_HIGH, N_Y_LOW, N_Y_SHIFT = 1080986531, 0, 0
KAPPA_Q = 615816
K_RHO_Q = 50332
THETA_HALF_Q = 217167
PERIOD_Q = 460800
UNIT_Q = 1073741824
STEPS = 14
CURRENT_HIGH = 2047
Y_FRAC_BITS = 24
SEGMENT_BITS = 6
ONE_Q16 = 65536
PSI_COMPLEMENT = (
    (0, 0),
    (509, 340),
    (1013, 677),
    (1512, 1012),
    (2006, 1344),
    (2495, 1674),
    (2978, 2001),
    (3457, 2325),
    (3931, 2647),
    (4399, 2967),
    (4863, 3284),
    (5323, 3599),
    (5777, 3911),
    (6227, 4221),
    (6673, 4528),
    (7114, 4834),
    (7550, 5136),
    (7982, 5437),
    (8409, 5735),
    (8833, 6031),
    (9252, 6325),
    (9666, 6617),
    (10077, 6906),
    (10483, 7193),
    (10886, 7478),
    (11284, 7761),
    (11678, 8042),
    (12069, 8321),
    (12455, 8597),
    (12838, 8872),
    (13217, 9144),
    (13592, 9415),
    (13963, 9683),
    (14331, 9950),
    (14695, 10214),
    (15055, 10477),
    (15412, 10738),
    (15765, 10996),
    (16115, 11253),
    (16462, 11508),
    (16805, 11761),
    (17144, 12012),
    (17481, 12262),
    (17814, 12509),
    (18143, 12755),
    (18470, 12999),
    (18793, 13242),
    (19114, 13482),
    (19431, 13721),
    (19745, 13958),
    (20056, 14193),
    (20364, 14427),
    (20669, 14659),
    (20971, 14889),
    (21270, 15118),
    (21566, 15345),
    (21860, 15570),
    (22151, 15794),
    (22439, 16016),
    (22724, 16237),
    (23006, 16456),
    (23286, 16674),
    (23563, 16890),
    (23837, 17104),
    (24109, 17317),
    (24379, 17529),
    (24645, 17739),
    (24910, 17947),
    (25171, 18155),
    (25431, 18360),
    (25688, 18564),
    (25942, 18767),
    (26194, 18969),
    (26444, 19169),
    (26691, 19367),
    (26936, 19565),
    (27179, 19760),
    (27420, 19955),
    (27658, 20148),
    (27894, 20340),
    (28128, 20531),
    (28360, 20720),
    (28590, 20908),
    (28817, 21095),
    (29043, 21280),
    (29266, 21464),
    (29488, 21647),
    (29707, 21829),
    (29924, 22010),
    (30140, 22189),
    (30353, 22367),
    (30565, 22544),
    (30774, 22719),
    (30982, 22894),
    (31188, 23067),
    (31392, 23240),
    (31594, 23411),
    (31794, 23581),
    (31993, 23749),
    (32190, 23917),
    (32385, 24084),
    (32578, 24249),
    (32770, 24413),
    (32959, 24577),
    (33148, 24739),
    (33334, 24900),
    (33519, 25060),
    (33702, 25219),
    (33884, 25377),
    (34064, 25534),
    (34242, 25690),
    (34419, 25845),
    (34595, 25999),
    (34768, 26152),
    (34941, 26304),
    (35111, 26455),
    (35281, 26605),
    (35449, 26755),
    (35615, 26903),
    (35780, 27050),
    (35944, 27196),
    (36106, 27341),
    (36267, 27486),
    (36426, 27629),
    (36584, 27772),
    (36741, 27914),
    (36896, 28054),
    (37050, 28194),
    (37203, 28333),
    (37504, 28609),
    (37801, 28881),
    (38092, 29149),
    (38379, 29415),
    (38661, 29677),
    (38938, 29936),
    (39211, 30191),
    (39479, 30444),
    (39743, 30693),
    (40002, 30940),
    (40257, 31183),
    (40509, 31424),
    (40756, 31661),
    (40999, 31896),
    (41238, 32128),
    (41473, 32357),
    (41705, 32584),
    (41933, 32808),
    (42158, 33029),
    (42378, 33248),
    (42596, 33464),
    (42810, 33677),
    (43021, 33889),
    (43228, 34097),
    (43433, 34304),
    (43634, 34508),
    (43832, 34709),
    (44027, 34909),
    (44219, 35106),
    (44408, 35301),
    (44595, 35493),
    (44778, 35684),
    (44959, 35872),
    (45137, 36059),
    (45313, 36243),
    (45486, 36425),
    (45656, 36605),
    (45824, 36783),
    (45990, 36960),
    (46153, 37134),
    (46314, 37307),
    (46472, 37477),
    (46628, 37646),
    (46782, 37813),
    (46934, 37978),
    (47084, 38142),
    (47231, 38303),
    (47377, 38464),
    (47520, 38622),
    (47662, 38779),
    (47801, 38934),
    (47939, 39087),
    (48075, 39239),
    (48208, 39389),
    (48340, 39538),
    (48471, 39685),
    (48599, 39831),
    (48726, 39975),
    (48851, 40118),
    (48974, 40259),
    (49096, 40399),
    (49216, 40537),
    (49335, 40674),
    (49452, 40810),
    (49682, 41077),
    (49905, 41339),
    (50123, 41597),
    (50336, 41849),
    (50543, 42096),
    (50745, 42338),
    (50942, 42576),
    (51134, 42810),
    (51322, 43039),
    (51505, 43264),
    (51684, 43484),
    (51858, 43701),
    (52029, 43914),
    (52195, 44123),
    (52358, 44328),
    (52517, 44529),
    (52673, 44727),
    (52825, 44922),
    (52973, 45113),
    (53118, 45300),
    (53261, 45485),
    (53400, 45666),
    (53536, 45845),
    (53669, 46020),
    (53799, 46192),
    (53927, 46362),
    (54052, 46529),
    (54175, 46693),
    (54295, 46854),
    (54412, 47013),
    (54527, 47169),
    (54640, 47323),
    (54751, 47474),
    (54860, 47623),
    (54966, 47769),
    (55070, 47913),
    (55173, 48055),
    (55273, 48195),
    (55372, 48333),
    (55469, 48469),
    (55564, 48602),
    (55657, 48734),
    (55748, 48864),
    (55838, 48991),
    (55927, 49117),
    (56013, 49241),
    (56099, 49363),
    (56182, 49484),
    (56265, 49603),
    (56345, 49720),
    (56425, 49835),
    (56503, 49949),
    (56580, 50061),
    (56655, 50172),
    (56730, 50281),
    (56803, 50389),
    (56875, 50495),
    (56945, 50600),
    (57015, 50703),
    (57083, 50805),
    (57151, 50905),
    (57217, 51005),
    (57282, 51103),
    (57347, 51199),
    (57472, 51389),
    (57594, 51574),
    (57713, 51754),
    (57827, 51930),
    (57939, 52101),
    (58047, 52268),
    (58153, 52431),
    (58255, 52590),
    (58355, 52746),
    (58452, 52898),
    (58546, 53046),
    (58638, 53191),
    (58728, 53333),
    (58815, 53471),
    (58900, 53607),
    (58983, 53739),
    (59064, 53869),
    (59142, 53996),
    (59219, 54120),
    (59295, 54242),
    (59368, 54361),
    (59440, 54477),
    (59510, 54592),
    (59578, 54704),
    (59645, 54813),
    (59711, 54921),
    (59775, 55026),
    (59837, 55130),
    (59899, 55231),
    (59959, 55330),
    (60017, 55428),
    (60075, 55524),
    (60131, 55617),
    (60186, 55710),
    (60240, 55800),
    (60293, 55889),
    (60345, 55976),
    (60396, 56062),
    (60446, 56146),
    (60495, 56229),
    (60543, 56310),
    (60590, 56390),
    (60636, 56469),
    (60681, 56546),
    (60726, 56622),
    (60770, 56697),
    (60813, 56770),
    (60855, 56842),
    (60896, 56914),
    (60937, 56983),
    (60977, 57052),
    (61016, 57120),
    (61055, 57187),
    (61093, 57252),
    (61130, 57317),
    (61167, 57380),
    (61203, 57443),
    (61239, 57505),
    (61273, 57565),
    (61308, 57625),
    (61342, 57684),
    (61375, 57742),
    (61408, 57800),
    (61440, 57856),
    (61503, 57966),
    (61564, 58074),
    (61623, 58178),
    (61681, 58279),
    (61737, 58378),
    (61791, 58474),
    (61844, 58568),
    (61895, 58659),
    (61945, 58748),
    (61994, 58834),
    (62041, 58918),
    (62087, 59001),
    (62132, 59081),
    (62175, 59159),
    (62218, 59235),
    (62259, 59310),
    (62300, 59383),
    (62339, 59454),
    (62378, 59524),
    (62415, 59592),
    (62452, 59658),
    (62488, 59723),
    (62523, 59787),
    (62557, 59849),
    (62591, 59910),
    (62623, 59969),
    (62655, 60028),
    (62687, 60085),
    (62717, 60141),
    (62747, 60196),
    (62777, 60250),
    (62805, 60302),
    (62833, 60354),
    (62861, 60404),
    (62888, 60454),
    (62915, 60503),
    (62941, 60551),
    (62966, 60597),
    (62991, 60644),
    (63015, 60689),
    (63039, 60733),
    (63063, 60777),
    (63086, 60819),
    (63109, 60861),
    (63131, 60903),
    (63153, 60943),
    (63174, 60983),
    (63195, 61022),
    (63216, 61061),
    (63236, 61098),
    (63256, 61136),
    (63276, 61172),
    (63295, 61208),
    (63314, 61243),
    (63333, 61278),
    (63351, 61313),
    (63370, 61346),
    (63387, 61379),
    (63405, 61412),
    (63422, 61444),
    (63439, 61476),
    (63455, 61507),
    (63472, 61538),
    (63488, 61568),
)
PERIOD_MIN_TICKS = 2000
PERIOD_MAX_TICKS = 50000
PERIOD_CAP_TICKS = 65535
PERIOD_NEVER = 0x10000
BUS_CODE_MIN = 2257
BUS_CODE_MAX = 3385
CURRENT_OFFSET_CODE = 2048
CURRENT_CODE_MAX = 620
METHOD = "improved_r"

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
    y_numerator: int
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
        _divide_long(N_X_HIGH, N_X_LOW, N_X_SHIFT, code),
        _divide_long(N_Y_HIGH, N_Y_LOW, N_Y_SHIFT, code),
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


class RuleEdge(NamedTuple):
    """bldc_rule_edge_t (Q7 counts; rho Q27)."""

    x: int
    a2: int
    rho: int
    s0: int
    s1: int


def psi(y: int) -> tuple[int, int]:
    """bldc_psi(): psi1 and psi2 in Q16 at y in Q24."""
    whole = y >> Y_FRAC_BITS
    shift = Y_FRAC_BITS - SEGMENT_BITS
    if whole == 0:
        row = y >> shift
    else:
        octave = whole.bit_length()
        shift += octave - 1
        row = ((octave - 1) << SEGMENT_BITS) + (y >> shift)
    r = y & ((1 << shift) - 1)
    half = 1 << (shift - 1)
    low, high = PSI_COMPLEMENT[row], PSI_COMPLEMENT[row + 1]
    return (
        ONE_Q16 - (low[0] + (((high[0] - low[0]) * r + half) >> shift)),
        ONE_Q16 - (low[1] + (((high[1] - low[1]) * r + half) >> shift)),
    )


def rule_sum(st: RuleEdge, x: int, frac_bits: int) -> int:
    """bldc_rule_sum(): S0 + S1 x, x in Q(frac_bits)."""
    return st.s0 + ((st.s1 * x + (1 << (frac_bits - 1))) >> frac_bits)


def _split(total: int) -> tuple[int, int]:
    return min(max(total, 0), PERIOD_Q), min(max(total - PERIOD_Q, 0), PERIOD_Q)


def current_remains(st: RuleEdge, x: int) -> bool:
    """bldc_current_remains(): 2 g(x) > 0."""
    y = (st.rho * x) >> 17
    psi1, psi2 = psi(y)
    e = UNIT_Q - min((y * psi1 + 512) >> 10, UNIT_Q)
    u1 = (x * psi1 + 0) >> 0
    v2 = (x * (x * psi2) + 8192) >> 14
    on, off = _split(rule_sum(st, x, STEPS))
    f2 = 4 * off - 2 * on - 2 * PERIOD_Q + st.x
    return st.a2 * e + f2 * u1 - st.x * v2 > 0


def commutation_timing(bus: Bus, period: int, current_adc: int, main_duty: int) -> Timing:
    """bldc_commutation_timing()."""
    del main_duty  # the rule does not use it
    flags = bus.flags
    period = min(period, PERIOD_CAP_TICKS)
    if period < bus.period_min:
        return Timing(PERIOD_NEVER, 0, 0, 0, flags | FLAG_INPUT_SATURATED)
    measured = period
    if period > PERIOD_MAX_TICKS:
        period = PERIOD_MAX_TICKS
        flags |= FLAG_INPUT_SATURATED
    current = current_adc - CURRENT_OFFSET_CODE
    if current < 0 or current > CURRENT_CODE_MAX:
        flags |= FLAG_INPUT_SATURATED
    i = min(max(current, 0), CURRENT_HIGH)
    x = (bus.x_numerator + (period >> 1)) // period
    y = (bus.y_numerator * i + 1024) >> 11
    a = (x * (KAPPA_Q * i) + 1073741824) >> 31
    st = RuleEdge(
        x=x,
        a2=2 * a,
        rho=K_RHO_Q * period,
        s0=2 * PERIOD_Q + y - x,
        s1=(x * THETA_HALF_Q + 524288) >> 20,
    )
    lo, hi = 0, 1 << STEPS
    for _ in range(STEPS):
        mid = (lo + hi) >> 1
        if current_remains(st, mid):
            lo = mid
        else:
            hi = mid
    fraction = lo + hi
    if hi == 1 << STEPS and current_remains(st, hi):
        fraction = 2 << STEPS
        flags |= FLAG_TIME_CLAMPED
    total = rule_sum(st, fraction, STEPS + 1)
    if total > 2 * PERIOD_Q or total < 0:
        flags |= FLAG_FAIL_AREA_CLAMPED
    if total < PERIOD_Q:
        flags |= FLAG_HIGH_SPEED
    on, off = _split(total)
    ticks = min((fraction * period + 16384) >> 15, measured)
    return Timing(
        bus.period_min,
        (on + 64) >> 7,
        (off + 64) >> 7,
        ticks,
        flags,
    )




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

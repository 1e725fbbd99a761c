# Generated from template templates/python/bldc_fixed.py.j2 with spec spec/paper_motor_improved_r.yaml (sha256 9f5d9c8963649549b4e129e1bd9cd35baa3c8e343f67f4b67f06c6141ed1f434). Do not edit: regenerate with `make`.
"""Bit-exact integer model of bldc_commutation.c (method "improved_r").

Printed from the same IR as the C (codegen/ir/py_printer.py): the same operations,
rounding and saturation, on Python integers (the IR proof rules out every overflow, so
they give the C's results). Standalone: the standard library only.
"""

from __future__ import annotations

from typing import NamedTuple

METHOD = "improved_r"
BLDC_PERIOD_MIN_TICKS = 2000  # 5000 rpm: a shorter period is over-speed
BLDC_BUS_CODE_MAX = 3385  # 30 V (30 V): above it over-voltage
BLDC_PERIOD_NEVER = 65536  # above every 16-bit period: the safe state
BLDC_FLAG_INPUT_SATURATED = 4  # an input was outside the spec's range
BLDC_BUS_CODE_MIN = 2257  # 20 V (20 V)
N_X_HIGH = 2396667768  # N_X >> 11, round(K_X 2^7), K_X = 3.834668e+10
N_X_LOW = 1219  # N_X mod 2^11
N_X_SHIFT = 11
N_Y_HIGH = 1080986531  # N_Y >> 0, round(K_Y 2^18 / 1), K_Y = 4.123636e+03
N_Y_LOW = 0  # N_Y mod 2^0
N_Y_SHIFT = 0
UNIT_Q = 1073741824  # 1 in Q30 (e, u1, v2)
PERIOD_Q = 460800  # P in Q7 counts
BLDC_PERIOD_CAP_TICKS = 65535  # the Hall counter's range: longer periods saturate
BLDC_PERIOD_MAX_TICKS = 50000  # 200 rpm: a longer period is flagged
BLDC_ADC_CODE_MAX = 4095  # 12-bit ADC full scale
BLDC_CURRENT_CODE_LOW = 2048  # first code at or above 0 A (0 A)
BLDC_CURRENT_CODE_HIGH = 2668  # last code at or below 10 A (9.99 A)
CURRENT_OFFSET_Q = 2048  # zero current: 2048 codes x 1
KAPPA_Q = 615816  # kappa = 2.867618e-04 in Q31 / 1: A = kappa i X
THETA_HALF_Q = 217167  # theta/2 in Q20, theta = sqrt(2) - 1 = 0.414213562
K_RHO_Q = 50332  # K_rho = R/(L f_hall) = 3.750000e-04 in Q27: rho = K_rho T
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


# Complements round((1 - psi) 2^16) of psi1(y) = (1 - e^-y)/y and psi2(y) = 2(y - 1 + e^-y)/y^2 on octave segments: rows 0..63 cover [0, 1) in steps of 2^-6, octave j >= 1 covers [2^(j-1), 2^j) in steps of 2^(j-1-6); one closing row. Linear interpolation error <= 2.69e-05 (psi1), 2.55e-05 (psi2). 1540 bytes.
BLDC_PSI_COMPLEMENT = (
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
    y_numerator: int  # round(N_Y / B): Y = y_numerator i / 2^gy
    period_min: int  # BLDC_PERIOD_MIN_TICKS, or BLDC_PERIOD_NEVER when over-voltage
    bus_code: int  # the saturated bus code B
    flags: int  # BLDC_FLAG_INPUT_SATURATED when the code was saturated


class RuleEdge(NamedTuple):
    """bldc_rule_edge_t: Per-edge quantities of the rule (Q(fc) duty counts unless noted)"""

    x: int  # X = 4 P E / U_d, Q(fc) counts
    a2: int  # 2 A, A = 3 P L I / (U_d T_s): the turn-off current at the edge
    rho: int  # rho = R T_s / L, Q(frho)
    s0: int  # 2P + Y - X: the held duty sum at the edge's EMFs
    s1: int  # theta X / 2: its growth per sector of commutation


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
    bus = Bus(divide_long(N_X_HIGH, N_X_LOW, N_X_SHIFT, code), divide_long(N_Y_HIGH, N_Y_LOW, N_Y_SHIFT, code), period_min, code, flags)
    return bus


def current_remains(st: RuleEdge, x: int) -> int:
    """Sign of 2 g(x): the turn-off current after x sectors (Q K) under the pair held at S(x), g = A e^-rho x + F x psi1(rho x) - X x^2/2 psi2(rho x), F = 2 C_off - C_on - P + X/2. 1 while the current has not yet reached zero (bldc_current_remains)."""
    rho_x = st.rho * x
    y = rho_x >> 17  # y = rho x in Q24
    whole = y >> 24
    octave = 0 if whole == 0 else whole.bit_length()  # table segment: 0 for y < 1, else 32 - CLZ(integer part)
    shift = 18 if octave == 0 else 17 + octave  # fraction bits of y within its row
    row = (octave << 6) + (y >> shift & 63)
    r = y & (1 << shift) - 1
    half = 1 << shift - 1
    psi1 = 65536 - (BLDC_PSI_COMPLEMENT[row][0] + ((BLDC_PSI_COMPLEMENT[row + 1][0] - BLDC_PSI_COMPLEMENT[row][0]) * r + half >> shift))  # psi1(y) in Q16, linear interpolation
    psi2 = 65536 - (BLDC_PSI_COMPLEMENT[row][1] + ((BLDC_PSI_COMPLEMENT[row + 1][1] - BLDC_PSI_COMPLEMENT[row][1]) * r + half >> shift))  # psi2(y) in Q16, linear interpolation
    y_psi1 = y * psi1
    one_minus_e = (y_psi1 + 512) >> 10  # 1 - e^-y in Q30
    e = UNIT_Q - (UNIT_Q if one_minus_e > UNIT_Q else one_minus_e)  # e^-y = 1 - y psi1 in Q30, kept >= 0 against the table's error
    u1 = x * psi1  # x psi1
    x_x_psi2 = x * (x * psi2)
    v2 = (x_x_psi2 + 8192) >> 14  # x^2 psi2
    s1_x = st.s1 * x
    total = st.s0 + ((s1_x + 8192) >> 14)  # S(x)
    on = 0 if total < 0 else PERIOD_Q if total > PERIOD_Q else total
    off = 0 if total - PERIOD_Q < 0 else PERIOD_Q if total - PERIOD_Q > PERIOD_Q else total - PERIOD_Q
    f2 = 4 * off - 2 * on - 2 * PERIOD_Q + st.x  # 2F
    twice_g = st.a2 * e + f2 * u1 - st.x * v2  # 2 g(x)
    return 1 if twice_g > 0 else 0


def commutation_timing(bus: Bus, period_ticks: int, current_adc: int, main_duty_counts: int) -> Timing:
    """Duties and commutation time of the resistance-aware rule (pure, reentrant); any uint32_t value of each parameter is allowed. The rule holds the current by itself: the main duty is not used (bldc_commutation_timing)."""
    flags = bus.flags
    measured = BLDC_PERIOD_CAP_TICKS if period_ticks > BLDC_PERIOD_CAP_TICKS else period_ticks  # the Hall counter's range
    if measured < bus.period_min:  # above the top speed or over-voltage: braking is no longer controlled
        safe = Timing(BLDC_PERIOD_NEVER, 0, 0, 0, flags | BLDC_FLAG_INPUT_SATURATED)
        return safe
    if measured > BLDC_PERIOD_MAX_TICKS:  # below the minimum speed
        flags |= BLDC_FLAG_INPUT_SATURATED
    period = BLDC_PERIOD_MAX_TICKS if measured > BLDC_PERIOD_MAX_TICKS else measured  # the table covers rho up to the slowest speed
    current_code = BLDC_ADC_CODE_MAX if current_adc > BLDC_ADC_CODE_MAX else current_adc  # above the ADC's range: full scale
    if current_adc < BLDC_CURRENT_CODE_LOW or current_adc > BLDC_CURRENT_CODE_HIGH:  # outside the braking-current range
        flags |= BLDC_FLAG_INPUT_SATURATED
    current = current_code - CURRENT_OFFSET_Q  # I in codes, offset removed
    i = 0 if current < 0 else current  # negative currents count as 0
    x = (bus.x_numerator + (period >> 1)) // period  # X in Q7 counts
    y = (bus.y_numerator * i + 1024) >> 11  # Y = 3 P R I / U_d, Q7
    x_kappa_i = x * (KAPPA_Q * i)
    a = (x_kappa_i + 1073741824) >> 31  # A = kappa i X
    x_theta = x * THETA_HALF_Q
    st = RuleEdge(x, 2 * a, K_RHO_Q * period, 2 * PERIOD_Q + y - x, (x_theta + 524288) >> 20)
    lo = 0
    hi = 16384
    for step in range(14):  # t_com: bisection over x in (0, 1] sectors; g(0) = A >= 0 changes sign once
        mid = lo + hi >> 1
        if current_remains(st, mid) != 0:
            lo = mid
        else:
            hi = mid
    fraction = lo + hi  # Q15: the middle of the last bracket
    if hi == 16384 and current_remains(st, hi) != 0:
        fraction = 2 << 14  # does not finish within the sector: the whole sector
        flags |= BLDC_FLAG_TIME_CLAMPED
    s1_x = st.s1 * fraction
    total = st.s0 + ((s1_x + 16384) >> 15)  # S(x_c)
    if total > 2 * PERIOD_Q or total < 0:  # no duty pair in [0, 1] holds the current
        flags |= BLDC_FLAG_FAIL_AREA_CLAMPED
    if total < PERIOD_Q:  # the turn-off phase off, the turn-on one modulated
        flags |= BLDC_FLAG_HIGH_SPEED
    on = 0 if total < 0 else PERIOD_Q if total > PERIOD_Q else total
    off = 0 if total - PERIOD_Q < 0 else PERIOD_Q if total - PERIOD_Q > PERIOD_Q else total - PERIOD_Q
    scaled = (fraction * period + 16384) >> 15  # x_c T
    ticks = measured if scaled > measured else scaled  # at most the measured period
    timing = Timing(bus.period_min, (on + 64) >> 7, (off + 64) >> 7, ticks, flags)
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

/* Generated from template templates/c/bldc_commutation.h.j2 with spec spec/paper_motor_improved_r.yaml (sha256 313dd61f95b5018d390bb349cd716e3ca5c6158c512536194e3b94687b277ff1). Do not edit: regenerate with `make`. */
#ifndef BLDC_COMMUTATION_H
#define BLDC_COMMUTATION_H

/*
 * Portable commutation core: PWM-OFF-PWM braking, method "improved_r".
 * Pure functions of their inputs: no register access, no floating point, no library
 * division helpers (32-bit hardware UDIV/SDIV only), no dynamic memory.
 *
 * Three steps, split by how fast their inputs change and by how little time the Hall
 * edge has:
 *   bldc_bus_condition()       saturates the bus code and computes everything that
 *                              depends on it alone (five 32-bit divides).
 *   bldc_commutation_timing()  everything that depends on speed, current and main duty:
 *                              duties (Eq. 16/18) and commutation time (Eq. 20), one
 *                              divide for the speed and one for Eq. 20. The port runs it
 *                              at low priority right after each Hall edge, with the
 *                              interval just measured, for the next edge.
 *   bldc_edge_of()             at the Hall edge (inline): which of the 12 commutations
 *                              the Hall code pair is, or none. One table lookup.
 *   bldc_commutate()           all three in one call, on plain inputs: the reference API
 *                              that tests and the verifier call.
 *
 * Units
 *   TIM1 counts      BLDC_PWM_PERIOD_COUNTS = duty 1 (20000 Hz PWM)
 *   Hall ticks       1e+06 Hz Hall timer; one Hall interval is 60 electrical degrees
 *   bus code         U_d = code * 0.0088623 V
 *   current code     I = (code - 2048) * 0.0161133 A
 *
 * Resistance-aware rule (codegen/improved_r_rule; beyond the paper, which sets R = 0 in
 * Eqs. 14-20). One constant duty pair per commutation, held at the EMFs of time
 * theta t_com (theta = sqrt(2) - 1, the minimax weight of the ramping EMF), and t_com
 * the zero of the turn-off current with R and the trapezoidal EMF's ramp:
 *   S(x) = 2P + Y - X + theta X x / 2, C_on = clamp(S, 0, P), C_off = clamp(S - P, 0, P)
 *   g(x) = A e^-rho x + F x psi1(rho x) - X x^2/2 psi2(rho x), F = 2 C_off - C_on - P + X/2
 *   x_c: g(x_c) = 0 in (0, 1] sectors; t_com = x_c T
 * with, in duty counts, X = 4 P E / U_d = K_X / (T B), K_X = 3.834668e+10;
 * Y = 3 P R I / U_d = K_Y i / B, K_Y = 4.123636e+03; A = 3 P L I / (U_d T_s) = kappa i X,
 * kappa = 2.867618e-04; rho = R T_s / L = K_rho T, K_rho = 3.750000e-04.
 *
 * Fixed-point formats and rounding (chosen and proven by codegen/improved_r_rule/design.py)
 *   per bus code B: x_numerator = round(N_X / B), y_numerator = round(N_Y / B) (two-step
 *     32-bit long divisions), N_X = 4908375590083, N_Y = 1080986531
 *   per speed: T clamped to [2000, 50000], i = current code - offset clamped to
 *     [0, 2047]; X = round(x_numerator / T) in Q7 counts (one divide),
 *     Y = round(y_numerator i / 2^11), 2A = 2 round(X KAPPA i / 2^31), RHO = K_RHO T (Q27),
 *     S0 = 2P + Y - X, S1 = round(X theta/2)
 *   bisection: 14 steps over x in Q14 on the sign of 2g (int64), e^-y, x psi1 and
 *     x^2 psi2 in Q30, y = rho x in Q24, psi from a 385-row octave table
 *     (1540 bytes, linear interpolation, one CLZ per lookup); x_c = the middle of
 *     the last bracket, or 1 (flagged) when the current does not reach zero in the sector
 *   outputs: round(C_on(x_c)), round(C_off(x_c)) counts, round(x_c T) ticks <= T
 *   rounding is half up everywhere; no floating point, no library division helpers.
 *   Error bounds against the real-arithmetic rule over the design grid (835 points):
 *   duties <= 0.640 counts; t_com <= 62.68 ticks, at most 0.645 of the
 *   allowance max(target, t_half) (t_half: the shift of the true zero that half a count
 *   of duty causes, where the commutation time is ill-conditioned in the physics too).
 *   The verifier checks every point against its own pointwise bound.
 *
 * Intermediate ranges proven over the whole input box (codegen/improved_r_rule/proof.py)
 *   N_X high part: uint32_t in [2396667768, 2396667768] (0.8 bits spare)
 *   N_X remainder 2^shift + low + B/2: uint32_t in [4624593, 6935865] (9.3 bits spare)
 *   N_X / B: uint32_t in [1450037102, 2174734423] (1.0 bits spare)
 *   N_Y high part: uint32_t in [1080986531, 1080986531] (2.0 bits spare)
 *   N_Y remainder 2^shift + low + B/2: uint32_t in [4514, 6770] (19.3 bits spare)
 *   N_Y / B: uint32_t in [319347, 478950] (13.1 bits spare)
 *   xn + T/2: uint32_t in [1450038102, 2174759423] (1.0 bits spare)
 *   X: int32_t in [29001, 1087369] (10.9 bits spare)
 *   yn i + 2^(gy-1): uint32_t in [1024, 980410439] (2.1 bits spare)
 *   KAPPA i: uint32_t in [0, 1260575352] (1.8 bits spare)
 *   X KAPPA i + half: uint64_t in [2147483648, 1370711713345266] (13.7 bits spare)
 *   2 A: int32_t in [2, 1276575] (10.7 bits spare)
 *   RHO = KRHO T: uint32_t in [100664000, 2516600000] (0.8 bits spare)
 *   X THETA + half: uint64_t in [6299269893, 236141540945] (26.2 bits spare)
 *   S1: int32_t in [6007, 225203] (13.2 bits spare)
 *   S0 low: int32_t in [-165769, 892599] (11.2 bits spare)
 *   S0 high: int32_t in [921601, 1400317] (10.6 bits spare)
 *   RHO x: uint64_t in [0, 41231974400000] (18.8 bits spare)
 *   y (inside the table): uint32_t in [0, 314575000] (3.8 bits spare)
 *   interpolation product: uint32_t in [463470482, 463470482] (3.2 bits spare)
 *   y psi1 + half: uint64_t in [16777216, 20616003977216] (19.8 bits spare)
 *   round(y psi1) in Q fu (e = max(2^fu - it, 0)): uint32_t in [1090519041, 1090519041] (2.0 bits spare)
 *   x psi: uint32_t in [0, 1073741824] (2.0 bits spare)
 *   x (x psi2) + half: uint64_t in [16384, 17592186060800] (20.0 bits spare)
 *   S1 x + half: uint64_t in [16384, 7379439539] (31.2 bits spare)
 *   S low: int32_t in [-165769, 892599] (11.2 bits spare)
 *   S high: int32_t in [927608, 1625519] (10.4 bits spare)
 *   S - P 2^fc: int32_t in [-626569, 431799] (11.7 bits spare)
 *   F2 low: int32_t in [-1843200, -1843200] (10.2 bits spare)
 *   F2 high: int32_t in [1872201, 2930569] (9.5 bits spare)
 *   2 A e: int64_t in [2147483648, 1370711713345266] (12.7 bits spare)
 *   F2 u1 low: int64_t in [-1979120929996800, -1979120929996800] (12.2 bits spare)
 *   F2 u1 high: int64_t in [2010261313414295, 3146673656684179] (11.5 bits spare)
 *   X v2: int64_t in [31140383417495, 1167552726687379] (12.9 bits spare)
 *   2g high: int64_t in [2010263460897943, 4517385370029445] (11.0 bits spare)
 *   2g low: int64_t in [-3146673656684179, -2010261313414295] (11.5 bits spare)
 *   x_c T + half: uint32_t in [65552384, 1638416384] (1.4 bits spare)
 *   S(x_c) rounding: int32_t in [460928, 460928] (12.2 bits spare)
 *
 * Flags: BLDC_FLAG_HIGH_SPEED when C_off = 0 (S < P); BLDC_FLAG_FAIL_AREA_CLAMPED when no
 * pair in [0, 1] holds the current (S > 2P or S < 0); BLDC_FLAG_TIME_CLAMPED when the
 * turn-off current does not reach zero within the sector.
 *
 * Safety
 *   Hall code 000 or 111, or a jump that is not one sector forward or back: every
 *   switch off (edge BLDC_EDGE_NONE, BLDC_NO_SWITCH), BLDC_FLAG_INVALID_HALL.
 *   Hall period below 2000 ticks (speed above 5000 rpm) or bus
 *   code above 3385 (30 V): every switch off, BLDC_FLAG_INPUT_SATURATED.
 *   Bus code below 2257 (20 V): saturated, flagged.
 *   Period above 50000 ticks (below 200 rpm): the rule uses 50000 (its table
 *   covers rho up to there), flagged; the commutation time stays within the measured
 *   period. Current outside [0, 10] A: flagged; negative currents count as 0 and
 *   codes above the ADC range as its full scale.
 */

#include <stdint.h>

#define BLDC_PWM_PERIOD_COUNTS 3600u /* TIM1 counts per PWM period */
#define BLDC_NO_SWITCH 0xFFu
#define BLDC_EDGE_NONE 0xFFu   /* no valid commutation: every switch off */
#define BLDC_EDGE_COUNT 12u    /* edge = 6 direction + sector entered (0 forward, 1 reverse) */

/* Switch index 0..5 = T1..T6: T1/T2, T3/T4, T5/T6 are the upper/lower transistors of
 * phases A, B, C (TIM1 CH1/CH1N, CH2/CH2N, CH3/CH3N). */
#define BLDC_FLAG_HIGH_SPEED 0x01u        /* Eq. 18 high-speed segment: 4E > U_d */
#define BLDC_FLAG_FAIL_AREA_CLAMPED 0x02u /* conventional: Eq. 16 D_off outside [0, 1] */
#define BLDC_FLAG_INPUT_SATURATED 0x04u   /* an input was outside the spec's range */
#define BLDC_FLAG_INVALID_HALL 0x08u      /* all switches off */
#define BLDC_FLAG_TIME_CLAMPED 0x10u      /* Eq. 20 exceeds the sector: clamped to it */

#define BLDC_X_FRAC_BITS 6u
#define BLDC_X_SCALE 64 /* 2^BLDC_X_FRAC_BITS */
#define BLDC_PERIOD_MIN_TICKS 2000u  /* 5000 rpm */
#define BLDC_PERIOD_MAX_TICKS 50000u /* 200 rpm */
#define BLDC_PERIOD_CAP_TICKS 65535u /* the Hall counter's range: longer periods saturate */
#define BLDC_PERIOD_NEVER 0x10000u   /* above every 16-bit period: the safe state */
#define BLDC_CURRENT_OFFSET_CODE 2048 /* 0 A */
#define BLDC_CURRENT_CODE_MAX 620     /* 10 A above the offset */

typedef struct {
    uint8_t hall_code;          /* A B C as bits 2 1 0 */
    uint8_t previous_hall_code; /* code of the sector being left: gives the direction */
    uint16_t hall_period_ticks; /* last 60 degree interval, Hall ticks */
    uint16_t bus_voltage_adc;   /* bus code */
    uint16_t phase_current_adc; /* current code of the commutated current I */
    uint16_t main_duty_counts;  /* current controller output, 0..BLDC_PWM_PERIOD_COUNTS */
} bldc_inputs_t;

typedef struct {
    uint16_t turn_on_compare;   /* D_on: ON time of turn_on_switch in TIM1 counts */
    uint16_t turn_off_compare;  /* D_off: ON time of turn_off_switch in TIM1 counts */
    uint16_t commutation_ticks; /* Eq. 20 in Hall ticks, clamped to the Hall period */
    uint8_t turn_on_switch;     /* 0..5 or BLDC_NO_SWITCH */
    uint8_t turn_off_switch;    /* 0..5 or BLDC_NO_SWITCH */
    uint8_t sector;             /* sector entered, 0..5 in Table 1 order; 0xFF if invalid */
    uint8_t flags;              /* BLDC_FLAG_* */
} bldc_outputs_t;

/* What the Hall-edge step needs of the bus voltage (see the formats above). */
typedef struct {
    uint32_t x_numerator;       /* round(N_X / B): X = K_X / (T B) in Q7 after / T */
    uint32_t y_numerator;       /* round(N_Y / B): Y = K_Y i / B */
    uint32_t period_min;        /* BLDC_PERIOD_MIN_TICKS, or BLDC_PERIOD_NEVER when over-voltage */
    uint32_t bus_code;          /* the saturated bus code B */
    uint32_t flags;             /* BLDC_FLAG_INPUT_SATURATED when the code was saturated */
} bldc_bus_t;

/* Duties and commutation time for one speed, current and main duty: what the next
 * Hall edge applies. */
typedef struct {
    uint32_t period_min;        /* an edge with a shorter interval goes to the safe state:
                                   BLDC_PERIOD_MIN_TICKS, or BLDC_PERIOD_NEVER when these
                                   values are not valid (over-speed, over-voltage) */
    uint16_t turn_on_compare;   /* D_on in TIM1 counts, 0..P */
    uint16_t turn_off_compare;  /* D_off in TIM1 counts, 0..P */
    uint16_t commutation_ticks; /* Eq. 20 in Hall ticks, 0..T */
    uint16_t flags;             /* BLDC_FLAG_* */
} bldc_timing_t;

/* (previous Hall code << 3 | Hall code) -> edge, BLDC_EDGE_NONE when invalid. */
extern const uint8_t bldc_edge_of_hall_pair[64];
/* edge -> {switch at D_on, switch at D_off} (codegen/derivation/switching.py). */
extern const uint8_t bldc_edge_switch[BLDC_EDGE_COUNT][2];
/* Hall code -> sector (Table 1 order), 0xFF for 000 and 111. */
extern const uint8_t bldc_sector_of_hall[8];

/* Saturate a bus code and precompute its reciprocals (pure, reentrant). */
bldc_bus_t bldc_bus_condition(uint32_t bus_code);

/* Duties and commutation time (pure, reentrant): period in Hall ticks (16-bit counter,
 * longer periods saturate), current as its ADC code, main duty in TIM1 counts. Below the
 * bus state's minimum period (above the top speed, or over-voltage) the result is the
 * safe state: period_min = BLDC_PERIOD_NEVER, every value 0. */
bldc_timing_t bldc_commutation_timing(const bldc_bus_t *bus, uint32_t period_ticks,
                                      uint32_t current_adc, uint32_t main_duty_counts);

/* The commutation of a Hall edge (pure): 0..11 (see bldc_edge_switch), or
 * BLDC_EDGE_NONE for 000, 111 or a jump that is not one sector. Codes must be 0..7. */
static inline uint32_t bldc_edge_of(uint32_t previous_hall_code, uint32_t hall_code)
{
    return bldc_edge_of_hall_pair[(previous_hall_code << 3) | hall_code];
}

/* Commutation decision on plain inputs: bldc_edge_of(), bldc_bus_condition() and
 * bldc_commutation_timing() for the same inputs (pure, reentrant). */
void bldc_commutate(const bldc_inputs_t *in, bldc_outputs_t *out);

#endif /* BLDC_COMMUTATION_H */

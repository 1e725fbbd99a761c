/* Generated from template templates/c/bldc_commutation.h.j2 with spec spec/paper_motor_improved_r.yaml (sha256 9f5d9c8963649549b4e129e1bd9cd35baa3c8e343f67f4b67f06c6141ed1f434). Do not edit: regenerate with `bldc-codegen generate spec/paper_motor_improved_r.yaml`. */
#ifndef BLDC_COMMUTATION_H
#define BLDC_COMMUTATION_H

/*
 * Portable commutation core: PWM-OFF-PWM braking. Printed from the integer IR
 * (codegen/ir) of codegen/methods/improved_r; every function is proven free of
 * overflow and undefined behaviour for every value of its parameters' types.
 * Pure functions of their inputs: no register access, no floating point, no library
 * division helpers (32-bit hardware UDIV/SDIV only), no dynamic memory.
 *
 *   bldc_bus_condition()       saturates the bus code and computes everything that
 *                              depends on it alone (at the bus-voltage rate).
 *   bldc_commutation_timing()  duties and commutation time for a speed, current and
 *                              main duty: what the next Hall edge applies. Its bus
 *                              argument must come from bldc_bus_condition().
 *   bldc_edge_of()             at the Hall edge (inline): which of the 12 commutations
 *                              a Hall code pair is, or none. One table lookup.
 *   bldc_commutate()           all three on plain inputs: the reference API of the
 *                              tests and the verifier.
 *
 * Method "improved_r": the resistance-aware rule (codegen/methods/improved_r).
 * EMF: trapezoid, 120 deg flat top; per unit E over the sector after the edge,
 * sigma = (2e_a - e_b - e_c)/E = 4 + -2 x, phi = (e_a - 2e_b + e_c)/E = 2 + -4 x.
 * One constant duty pair per commutation, held at the minimax duty sum over it, and
 * the end on a carrier boundary (the port restarts the PWM carrier there):
 *   Sigma(x) = 2P + Y - (X/4)(sigma_0 + sigma_1 theta x), theta = sqrt(2) - 1,
 *   C_on = clamp(Sigma, 0, P), C_off = clamp(Sigma - P, 0, P), F_d = 2 C_off - C_on - P,
 *   g(x) = A e^-rho x + (F_d + (X/4) phi_0) x psi1(rho x) + (X/4) phi_1 x^2/2 psi2(rho x):
 *   the turn-off current under that pair (psi1 = (1 - e^-y)/y, psi2 = 2(y - 1 + e^-y)/y^2);
 *   the end: the first x_m = m tau / T (tau = 50 ticks, m >= 1) with g(x_m) < 0;
 *   the pair eased there: C_on - delta, C_off + delta, delta = -g / (3 x psi1), at most
 *   min(C_on, P - C_off), so the current reaches zero exactly on the boundary.
 * with, in duty counts, X = 4 P E / U_d = K_X / (T B), K_X = 3.834668e+10;
 * Y = 3 P R I / U_d = K_Y i / B, K_Y = 4.123636e+03; A = kappa i X, kappa = 2.867618e-04;
 * rho = R T_s / L = K_rho T, K_rho = 3.750000e-04; i in 1/1 codes.
 *
 * Formats (codegen/methods/improved_r/design.py chose them; the IR proof checked them):
 *   counts in Q7; on the grid rho x_m = y_1 m, e^-rho x_m = D^m from a
 *   10-entry table of D^(2^k) (Q32): a 10-step binary lifting over m,
 *   each step one table product and the sign of 2^(32+fc) rho g in int64; the easing
 *   by two 32-bit divides. No exponential, no psi table, no divide in the loop.
 *   Period clamped to [BLDC_PERIOD_MIN_TICKS, BLDC_PERIOD_MAX_TICKS]; current clamped at 0.
 * Claimed bounds over the design grid (1880 points, the end decided at 1619):
 *   duties <= 0.641 counts at every point, t_com <= 0.0 ticks of the rule's carrier boundary where the end is decided.
 * Flags: HIGH_SPEED when Sigma < P; FAIL_AREA_CLAMPED when no pair in [0, 1] holds the
 * current (Sigma > 2P or Sigma < 0); TIME_CLAMPED when the turn-off current does not
 * reach zero by the sector's last whole PWM period (then the pair is held over the
 * whole sector, uneased, and the time is the sector). The main duty is not used.
 *
 * Safety
 *   Hall code 000 or 111, a code above 7, or a jump that is not one sector forward or
 *   back: every switch off (BLDC_NO_SWITCH), BLDC_FLAG_INVALID_HALL.
 *   Hall period below BLDC_PERIOD_MIN_TICKS (over-speed) or bus code above
 *   BLDC_BUS_CODE_MAX (over-voltage): every switch off, BLDC_FLAG_INPUT_SATURATED.
 *   Bus code below BLDC_BUS_CODE_MIN: saturated, flagged. Hall period above
 *   BLDC_PERIOD_CAP_TICKS: saturated. Current code above BLDC_ADC_CODE_MAX: saturated;
 *   outside [BLDC_CURRENT_CODE_LOW, BLDC_CURRENT_CODE_HIGH]: flagged.
 *
 * Intermediate ranges, proven by interval analysis of the printed IR over every input
 * (bits of headroom left in each type):
 *   bldc_bus_condition: code: uint32_t in [0, 4294967295] (-0.0 bits spare)
 *   bldc_bus_condition: period_min: uint32_t in [2000, 65536] (16.0 bits spare)
 *   bldc_bus_condition: flags: uint32_t in [0, 4] (30.0 bits spare)
 *   bldc_divide_long: q_high: uint32_t in [0, 1061882] (12.0 bits spare)
 *   bldc_divide_long: remainder: uint32_t in [0, 1638367232] (1.4 bits spare)
 *   bldc_bus_condition: xn: uint32_t in [1450037102, 2174734422] (1.0 bits spare)
 *   bldc_bus_condition: yn: uint32_t in [1277385, 1915794] (11.1 bits spare)
 *   bldc_bus_condition: bus.x_numerator: uint32_t in [1450037102, 2174734422] (1.0 bits spare)
 *   bldc_bus_condition: bus.y_numerator: uint32_t in [1277385, 1915794] (11.1 bits spare)
 *   bldc_bus_condition: bus.a_numerator: uint32_t in [1277385, 1915794] (11.1 bits spare)
 *   bldc_bus_condition: bus.period_min: uint32_t in [2000, 65536] (16.0 bits spare)
 *   bldc_bus_condition: bus.bus_code: uint32_t in [2257, 3385] (20.3 bits spare)
 *   bldc_bus_condition: bus.flags: uint32_t in [0, 4] (30.0 bits spare)
 *   bldc_commutation_timing: flags: uint32_t in [0, 31] (27.0 bits spare)
 *   bldc_commutation_timing: measured: uint32_t in [0, 65535] (16.0 bits spare)
 *   bldc_commutation_timing: safe.period_min: uint32_t in [65536, 65536] (16.0 bits spare)
 *   bldc_commutation_timing: safe.turn_on_compare: uint16_t in [0, 0] (inf bits spare)
 *   bldc_commutation_timing: safe.turn_off_compare: uint16_t in [0, 0] (inf bits spare)
 *   bldc_commutation_timing: safe.commutation_ticks: uint16_t in [0, 0] (inf bits spare)
 *   bldc_commutation_timing: safe.flags: uint16_t in [4, 7] (13.2 bits spare)
 *   bldc_commutation_timing: period: uint32_t in [2000, 50000] (16.4 bits spare)
 *   bldc_commutation_timing: latest: uint32_t in [1813, 61377] (16.1 bits spare)
 *   bldc_commutation_timing: current_code: uint32_t in [0, 4095] (20.0 bits spare)
 *   bldc_commutation_timing: current: int32_t in [-2048, 2047] (20.0 bits spare)
 *   bldc_commutation_timing: i: uint32_t in [0, 2047] (21.0 bits spare)
 *   bldc_commutation_timing: x: uint32_t in [29000, 1087379] (11.9 bits spare)
 *   bldc_commutation_timing: y: uint32_t in [0, 478715] (13.1 bits spare)
 *   bldc_commutation_timing: a_rho: uint32_t in [0, 478715] (13.1 bits spare)
 *   bldc_commutation_timing: periods: uint32_t in [36, 936] (22.1 bits spare)
 *   bldc_commutation_timing: sigma0: int32_t in [-165779, 1371315] (10.6 bits spare)
 *   bldc_commutation_timing: per_tick: uint32_t in [0, 18612220] (7.9 bits spare)
 *   bldc_commutation_timing: q: uint32_t in [0, 48469322] (6.5 bits spare)
 *   bldc_commutation_timing: growth: uint32_t in [0, 3011497] (10.5 bits spare)
 *   bldc_commutation_timing: ca2: int32_t in [-4116712, 928430] (9.0 bits spare)
 *   bldc_commutation_timing: cb: int32_t in [14500, 2058356] (10.0 bits spare)
 *   bldc_commutation_timing: skipped: int32_t in [0, 4] (29.0 bits spare)
 *   bldc_commutation_timing: first: uint32_t in [0, 4] (30.0 bits spare)
 *   bldc_commutation_timing: n: uint32_t in [0, 936] (22.1 bits spare)
 *   bldc_commutation_timing: e: uint32_t in [0, 2147483648] (1.0 bits spare)
 *   bldc_commutation_timing: end_h: int64_t in [-132606651171623360, -1] (6.1 bits spare)
 *   bldc_commutation_timing: end_e: uint32_t in [0, 2107593468] (1.0 bits spare)
 *   bldc_commutation_timing: m: uint32_t in [1, 1448] (21.5 bits spare)
 *   bldc_commutation_timing: em: uint32_t in [0, 2107593468] (1.0 bits spare)
 *   bldc_commutation_timing: total: int32_t in [-165779, 6876707] (8.3 bits spare)
 *   bldc_commutation_timing: held: int32_t in [0, 921600] (11.2 bits spare)
 *   bldc_commutation_timing: fd: int32_t in [-1382400, 921600] (10.6 bits spare)
 *   bldc_commutation_timing: h: int64_t in [-132606651171623360, 20582640987340616] (6.1 bits spare)
 *   bldc_commutation_timing: end: uint32_t in [1, 936] (22.1 bits spare)
 *   bldc_commutation_timing: end_total: int32_t in [-165779, 6876707] (8.3 bits spare)
 *   bldc_commutation_timing: end_held: int32_t in [0, 921600] (11.2 bits spare)
 *   bldc_commutation_timing: end_on: int32_t in [0, 460800] (12.2 bits spare)
 *   bldc_commutation_timing: end_off: int32_t in [0, 460800] (12.2 bits spare)
 *   bldc_commutation_timing: room: int32_t in [0, 460800] (12.2 bits spare)
 *   bldc_commutation_timing: shortfall: uint32_t in [233730, 12582912] (8.4 bits spare)
 *   bldc_commutation_timing: overshoot: uint64_t in [0, 4503599627370495] (12.0 bits spare)
 *   bldc_commutation_timing: cap: uint64_t in [233730, 2899115507712] (22.6 bits spare)
 *   bldc_commutation_timing: numerator: uint64_t in [0, 2899115507712] (22.6 bits spare)
 *   bldc_commutation_timing: eased_upper: uint32_t in [0, 44236992] (6.6 bits spare)
 *   bldc_commutation_timing: eased_middle: uint32_t in [0, 3221225471] (0.4 bits spare)
 *   bldc_commutation_timing: eased_lower: uint32_t in [0, 3221225471] (0.4 bits spare)
 *   bldc_commutation_timing: eased: uint32_t in [0, 262144] (14.0 bits spare)
 *   bldc_commutation_timing: delta: int32_t in [0, 460800] (12.2 bits spare)
 *   bldc_commutation_timing: eased_on: int32_t in [-460800, 460800] (12.2 bits spare)
 *   bldc_commutation_timing: eased_off: int32_t in [0, 921600] (11.2 bits spare)
 *   bldc_commutation_timing: on: uint32_t in [0, 460800] (13.2 bits spare)
 *   bldc_commutation_timing: off: uint32_t in [0, 460800] (13.2 bits spare)
 *   bldc_commutation_timing: ticks: uint32_t in [50, 61377] (16.1 bits spare)
 *   bldc_commutation_timing: timing.period_min: uint32_t in [2000, 65535] (16.0 bits spare)
 *   bldc_commutation_timing: timing.turn_on_compare: uint16_t in [0, 3600] (4.2 bits spare)
 *   bldc_commutation_timing: timing.turn_off_compare: uint16_t in [0, 3600] (4.2 bits spare)
 *   bldc_commutation_timing: timing.commutation_ticks: uint16_t in [50, 61377] (0.1 bits spare)
 *   bldc_commutation_timing: timing.flags: uint16_t in [0, 31] (11.0 bits spare)
 *   bldc_commutate: hall_code: uint32_t in [0, 255] (24.0 bits spare)
 *   bldc_commutate: previous_hall_code: uint32_t in [0, 255] (24.0 bits spare)
 *   bldc_commutate: period: uint32_t in [0, 65535] (16.0 bits spare)
 *   bldc_commutate: edge: uint32_t in [0, 255] (24.0 bits spare)
 *   bldc_commutate: sector: uint32_t in [0, 255] (24.0 bits spare)
 *   bldc_commutate: out.turn_on_compare: uint16_t in [0, 3600] (4.2 bits spare)
 *   bldc_commutate: out.turn_off_compare: uint16_t in [0, 3600] (4.2 bits spare)
 *   bldc_commutate: out.commutation_ticks: uint16_t in [0, 61377] (0.1 bits spare)
 *   bldc_commutate: out.turn_on_switch: uint8_t in [0, 255] (-0.0 bits spare)
 *   bldc_commutate: out.turn_off_switch: uint8_t in [0, 255] (-0.0 bits spare)
 *   bldc_commutate: out.sector: uint8_t in [0, 255] (-0.0 bits spare)
 *   bldc_commutate: out.flags: uint8_t in [0, 31] (3.0 bits spare)
 */

#include <stdint.h>

#define BLDC_NO_SWITCH 255u /* no switch: every transistor of that role off */
#define BLDC_EDGE_NONE 255u /* no valid commutation: every switch off */
#define BLDC_EDGE_COUNT 12u /* edge = 6 x direction + sector entered (0 forward, 1 reverse) */
#define BLDC_INVALID_SECTOR 255u /* the sector of Hall code 000 or 111 */
#define BLDC_PERIOD_NEVER 65536u /* above every 16-bit period: the safe state */
#define BLDC_FLAG_HIGH_SPEED 0x01u /* Eq. 18 high-speed segment: 4E > U_d (the turn-off phase is off) */
#define BLDC_FLAG_FAIL_AREA_CLAMPED 0x02u /* no duty pair in [0, 1] holds the current: clamped */
#define BLDC_FLAG_INPUT_SATURATED 0x04u /* an input was outside the spec's range */
#define BLDC_FLAG_INVALID_HALL 0x08u /* Hall code 000/111 or an impossible jump: every switch off */
#define BLDC_FLAG_TIME_CLAMPED 0x10u /* the commutation does not finish within the sector: clamped to it */
#define BLDC_PWM_PERIOD_COUNTS 3600u /* TIM1 counts per PWM period: duty 1 */
#define BLDC_PERIOD_MIN_TICKS 2000u /* 5000 rpm reads 2000 or more (whole ticks): a shorter period is over-speed */
#define BLDC_PERIOD_MAX_TICKS 50000u /* 200 rpm reads 50000 or less (whole ticks): a longer period is flagged */
#define BLDC_PERIOD_CAP_TICKS 65535u /* the Hall counter's range: longer periods saturate */
#define BLDC_COMMUTATION_GUARD_TICKS 62u /* a commutation ends at least this long before its sector does: dead time 0.5 us + 4 us of the end's latency (the next edge switches on the other switch of the leg the end switched off) + one current sample (a PWM period and the ADC's injected sequence: the braking-current loop samples between commutations) */
#define BLDC_BUS_CODE_MIN 2257u /* 20 V (20 V) */
#define BLDC_BUS_CODE_MAX 3385u /* 30 V (30 V): above it over-voltage */
#define BLDC_ADC_CODE_MAX 4095u /* 12-bit ADC full scale */
#define BLDC_CURRENT_CODE_LOW 2048u /* first code at or above 0 A (0 A) */
#define BLDC_CURRENT_CODE_HIGH 2668u /* last code at or below 10 A (9.99 A) */

/* Switch index 0..5 = T1..T6: T1/T2, T3/T4, T5/T6 are the upper/lower transistors of
 * phases A, B, C (TIM1 CH1/CH1N, CH2/CH2N, CH3/CH3N). */

/* Inputs of one commutation decision (bldc_commutate) */
typedef struct {
    uint8_t hall_code;          /* A B C as bits 2 1 0 */
    uint8_t previous_hall_code; /* code of the sector being left: gives the direction */
    uint16_t hall_period_ticks; /* last 60 degree interval, Hall ticks */
    uint16_t bus_voltage_adc;   /* bus code */
    uint16_t phase_current_adc; /* current code of the commutated current I */
    uint16_t main_duty_counts;  /* current controller output, TIM1 counts */
} bldc_inputs_t;

/* Result of one commutation decision */
typedef struct {
    uint16_t turn_on_compare;   /* D_on: ON time of turn_on_switch in TIM1 counts */
    uint16_t turn_off_compare;  /* D_off: ON time of turn_off_switch in TIM1 counts */
    uint16_t commutation_ticks; /* Eq. 20 in Hall ticks, at most the Hall period */
    uint8_t turn_on_switch;     /* 0..5 (T1..T6) or BLDC_NO_SWITCH */
    uint8_t turn_off_switch;    /* 0..5 (T1..T6) or BLDC_NO_SWITCH */
    uint8_t sector;             /* sector entered, 0..5 in Table 1 order; 0xFF if invalid */
    uint8_t flags;              /* BLDC_FLAG_* */
} bldc_outputs_t;

/* Duties and commutation time for one speed, current and main duty: what the next Hall edge applies */
typedef struct {
    uint32_t period_min;        /* an edge with a shorter interval goes to the safe state: BLDC_PERIOD_MIN_TICKS, or BLDC_PERIOD_NEVER when these values must not be applied */
    uint16_t turn_on_compare;   /* D_on in TIM1 counts, 0..P */
    uint16_t turn_off_compare;  /* D_off in TIM1 counts, 0..P */
    uint16_t commutation_ticks; /* Eq. 20 in Hall ticks, 0..T */
    uint16_t flags;             /* BLDC_FLAG_* */
} bldc_timing_t;

/* What the timing step needs of the bus voltage (see the formats above) */
typedef struct {
    uint32_t x_numerator; /* round(N_X / B): X = x_numerator / T in Q(fc) counts */
    uint32_t y_numerator; /* Y per unit of current, Q(fc + gy): Y = 3 P R I / U_d */
    uint32_t a_numerator; /* A rho per unit of current, Q(fc + ga) */
    uint32_t period_min;  /* BLDC_PERIOD_MIN_TICKS, or BLDC_PERIOD_NEVER when over-voltage */
    uint32_t bus_code;    /* the saturated bus code B */
    uint32_t flags;       /* BLDC_FLAG_INPUT_SATURATED when the code was saturated */
} bldc_bus_t;

extern const uint8_t bldc_sector_of_hall[8];
extern const uint8_t bldc_edge_of_hall_pair[64];
extern const uint8_t bldc_edge_switch[12][2];

/* The contracts below are ACSL, Frama-C's specification language (compilers see
 * comments). `make prove` proves each with Frama-C's WP or checks it with EVA over
 * every input, and writes which into generated/<spec>/PROOF.md; the `split`, `merge`
 * and `loop` annotations in the .c file are hints of the same proof. */

/* a Hall edge of the spec's sequence (hall.sequence), forward or reverse */
/*@ predicate bldc_valid_hall_pair(integer previous, integer code) =
       (previous == 5 && code == 4)
    || (previous == 4 && code == 6)
    || (previous == 6 && code == 2)
    || (previous == 2 && code == 3)
    || (previous == 3 && code == 1)
    || (previous == 1 && code == 5)
    || (previous == 4 && code == 5)
    || (previous == 6 && code == 4)
    || (previous == 2 && code == 6)
    || (previous == 3 && code == 2)
    || (previous == 1 && code == 3)
    || (previous == 5 && code == 1);
*/

/* a bus state bldc_bus_condition() returns: its precondition for bldc_commutation_timing(), restated from its IR over mathematical integers */
/*@ predicate bldc_bus_conditioned(bldc_bus_t b) =
       BLDC_BUS_CODE_MIN <= b.bus_code <= BLDC_BUS_CODE_MAX
    && b.x_numerator == ((2 * 4908375590083 + b.bus_code) / (2 * b.bus_code))
    && b.y_numerator == (((((2 * 4908375590083 + b.bus_code) / (2 * b.bus_code)) * 1891788) + 1073741824) / 2147483648)
    && b.a_numerator == (((((2 * 4908375590083 + b.bus_code) / (2 * b.bus_code)) * 1891788) + 1073741824) / 2147483648)
    && (b.period_min == BLDC_PERIOD_MIN_TICKS || b.period_min == BLDC_PERIOD_NEVER)
    && (b.flags == 0 || b.flags == BLDC_FLAG_INPUT_SATURATED);
*/

/* Saturate a bus code and precompute its reciprocals (pure, reentrant) */
/*@ assigns \nothing;
    ensures conditioned: bldc_bus_conditioned(\result);
    ensures over_voltage_never_applies: bus_code > BLDC_BUS_CODE_MAX ==> \result.period_min == BLDC_PERIOD_NEVER;
*/
bldc_bus_t bldc_bus_condition(uint32_t bus_code);

/* Duties and commutation time of the resistance-aware rule (pure, reentrant); any uint32_t value of each parameter is allowed. The rule holds the current by itself: the main duty is not used */
/*@ requires readable: \valid_read(bus);
    requires conditioned: bldc_bus_conditioned(*bus);
    assigns \nothing;
    ensures turn_on_compare_in_period: \result.turn_on_compare <= BLDC_PWM_PERIOD_COUNTS;
    ensures turn_off_compare_in_period: \result.turn_off_compare <= BLDC_PWM_PERIOD_COUNTS;
    ensures commutation_ends_the_guard_early: \result.commutation_ticks == 0 || \result.commutation_ticks + BLDC_COMMUTATION_GUARD_TICKS <= period_ticks * 15 / 16;
    ensures applies_at_most_from_bus_minimum: \result.period_min >= bus->period_min;
*/
bldc_timing_t bldc_commutation_timing(const bldc_bus_t *bus, uint32_t period_ticks, uint32_t current_adc, uint32_t main_duty_counts);

/* Commutation decision on plain inputs: bldc_edge_of(), bldc_bus_condition() and bldc_commutation_timing() for the same inputs (pure, reentrant) */
/*@ requires readable: \valid_read(inputs);
    requires writable: \valid(out);
    requires separated: \separated(inputs, out);
    assigns *out;
    ensures turn_on_compare_in_period: out->turn_on_compare <= BLDC_PWM_PERIOD_COUNTS;
    ensures turn_off_compare_in_period: out->turn_off_compare <= BLDC_PWM_PERIOD_COUNTS;
    ensures commutation_ends_the_guard_early: out->commutation_ticks == 0 || out->commutation_ticks + BLDC_COMMUTATION_GUARD_TICKS <= \old(inputs->hall_period_ticks) * 15 / 16;
    ensures over_speed_or_voltage_no_switch: \old(inputs->hall_period_ticks) < BLDC_PERIOD_MIN_TICKS || \old(inputs->bus_voltage_adc) > BLDC_BUS_CODE_MAX ==> out->turn_on_switch == BLDC_NO_SWITCH && out->turn_off_switch == BLDC_NO_SWITCH;
    behavior invalid_hall:
      assumes !bldc_valid_hall_pair(inputs->previous_hall_code, inputs->hall_code);
      ensures no_switch: out->turn_on_switch == BLDC_NO_SWITCH && out->turn_off_switch == BLDC_NO_SWITCH;
      ensures invalid_flag: (out->flags & BLDC_FLAG_INVALID_HALL) != 0;
*/
void bldc_commutate(const bldc_inputs_t *inputs, bldc_outputs_t *out);

/* The commutation of a Hall edge (pure): 0..11 (see bldc_edge_switch), or BLDC_EDGE_NONE for 000, 111, a code above 7 or a jump that is not one sector */
/*@ assigns \nothing;
    behavior invalid_pair:
      assumes !bldc_valid_hall_pair(previous_hall_code, hall_code);
      ensures no_edge: \result == BLDC_EDGE_NONE;
    behavior valid_pair:
      assumes bldc_valid_hall_pair(previous_hall_code, hall_code);
      ensures an_edge: \result < BLDC_EDGE_COUNT;
    complete behaviors;
    disjoint behaviors;
*/
static inline uint32_t bldc_edge_of(uint32_t previous_hall_code, uint32_t hall_code)
{
    return (previous_hall_code > 7u || hall_code > 7u) ? BLDC_EDGE_NONE : (uint32_t)bldc_edge_of_hall_pair[((previous_hall_code << 3u) | hall_code)];
}

#endif /* BLDC_COMMUTATION_H */

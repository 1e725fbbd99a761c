/* Generated from template templates/c/bldc_current_loop.h.j2 with spec spec/paper_motor_improved_r.yaml (sha256 9f5d9c8963649549b4e129e1bd9cd35baa3c8e343f67f4b67f06c6141ed1f434). Do not edit: regenerate with `bldc-codegen generate spec/paper_motor_improved_r.yaml`. */
#ifndef BLDC_CURRENT_LOOP_H
#define BLDC_CURRENT_LOOP_H

/*
 * The braking-current PI, printed from the integer IR of codegen/control/current_loop.py:
 * every function is proven free of overflow and undefined behaviour for every value of
 * its parameters' types, and checked by `verify` against the exact discrete-time model
 * of oracle/current_loop.py.
 *
 * Plant (averaged PWM-OFF-PWM braking, per phase): L dI/dt = -R I + (U_d/2) D + (E - U_d/2).
 * PI with its zero on the plant's pole (pole-zero cancellation), open-loop crossover at
 * the spec's bandwidth, discretised at the PWM period (forward Euler; the sample of
 * period k sets the duty of period k + 1):
 *   K_p = 2 L w_c / U_d = 0.293215 per A (L = 0.56 mH, w_c = 2 pi 1000 Hz, U_d = 24 V nominal)
 *   K_i = 2 R w_c / U_d = 109.956 per A s (R = 0.21 ohm): zero at R/L, the plant's pole
 *   per period T = 1/20000 Hz in counts per code (P = 3600, a = 16.1133 mA per code): k_p = 17.0088, k_i = 0.318915
 *   Q14: KP = 278672 (+0.6 ppm), KI = 5225 (-18.5 ppm)
 *   claimed, one step from a given state (IR error analysis): duty <= 0.5020 counts, integrator <= 0.0012 counts a step, 0.0636 over a ramp from 0 to D_max
 *   reference: code = round((mA x 8329634 + 274877906944) / 2^27), exact nearest code for every mA in [0, 10000]
 *
 *   e = r - m (codes), v = k_p e + x, D = clamp(v, 0, D_max) rounded to counts,
 *   x' = x where v > D_max and e > 0 or v < 0 and e < 0 (clamping anti-windup),
 *   else clamp(x + k_i e, 0, D_max). x and v in Q14 counts.
 *
 * bldc_current_loop_duty() and bldc_current_loop_integrate() run in the injected
 * end-of-conversion interrupt (inline: no call, and the compiler shares their common
 * part); bldc_current_reference() converts a command in mA, in thread mode.
 *
 * Intermediate ranges, proven by interval analysis of the printed IR over every input
 * (bits of headroom left in each type):
 *   bldc_current_loop_duty: reference: uint32_t in [0, 4095] (20.0 bits spare)
 *   bldc_current_loop_duty: measured: uint32_t in [0, 4095] (20.0 bits spare)
 *   bldc_current_loop_duty: error: int32_t in [-4095, 4095] (19.0 bits spare)
 *   bldc_current_loop_duty: state: int32_t in [0, 56164352] (5.3 bits spare)
 *   bldc_current_loop_duty: demand: int32_t in [-1141161840, 1197326192] (0.8 bits spare)
 *   bldc_current_loop_duty: limited: int32_t in [0, 56164352] (5.3 bits spare)
 *   bldc_current_loop_integrate: reference: uint32_t in [0, 4095] (20.0 bits spare)
 *   bldc_current_loop_integrate: measured: uint32_t in [0, 4095] (20.0 bits spare)
 *   bldc_current_loop_integrate: error: int32_t in [-4095, 4095] (19.0 bits spare)
 *   bldc_current_loop_integrate: state: int32_t in [0, 56164352] (5.3 bits spare)
 *   bldc_current_loop_integrate: demand: int32_t in [-1141161840, 1197326192] (0.8 bits spare)
 *   bldc_current_loop_integrate: total: int32_t in [-21396375, 77560727] (4.8 bits spare)
 *   bldc_current_reference: held: uint32_t in [0, 10000] (18.7 bits spare)
 *   bldc_current_reference: scaled: uint64_t in [274877906944, 358174246944] (25.6 bits spare)
 */

#include <stdint.h>

#define BLDC_LOOP_CODE_MAX 4095u /* ADC full scale: inputs saturate here */
#define BLDC_LOOP_STATE_MAX 56164352 /* D_max = 3428 counts in Q14 */
#define BLDC_LOOP_KP 278672 /* k_p = 17.0088 counts per code, Q14 */
#define BLDC_LOOP_KI 5225 /* k_i = 0.318915 counts per code per PWM period, Q14 */
#define BLDC_LOOP_MA_MAX 10000u /* braking_current_max, mA */
#define BLDC_LOOP_REF_SCALE 8329634ull /* codes per mA, Q27, rounded up */
#define BLDC_LOOP_REF_OFFSET 274877906944ull /* zero-current code, Q27, rounded up */
#define BLDC_LOOP_FRAC_BITS 14u /* fraction bits of x and v */
#define BLDC_LOOP_DUTY_MAX 3428u /* D_max, TIM1 counts: the OFF time holds the current sample */

/* main duty in TIM1 counts, 0..D_max, for this period's sample */
/*@ assigns \nothing;
    ensures within_d_max: \result <= BLDC_LOOP_DUTY_MAX;
*/
static inline uint32_t bldc_current_loop_duty(int32_t integrator, uint32_t reference_code, uint32_t measured_code)
{
    const uint32_t reference = (reference_code > BLDC_LOOP_CODE_MAX) ? BLDC_LOOP_CODE_MAX : reference_code;
    const uint32_t measured = (measured_code > BLDC_LOOP_CODE_MAX) ? BLDC_LOOP_CODE_MAX : measured_code;
    const int32_t error = (int32_t)reference - (int32_t)measured; /* codes: reference - measured */
    const int32_t state = (integrator < 0) ? 0 : (integrator > BLDC_LOOP_STATE_MAX) ? BLDC_LOOP_STATE_MAX : integrator; /* Q14 counts */
    const int32_t demand = BLDC_LOOP_KP * error + state; /* k_p e + x */
    const int32_t limited = (demand < 0) ? 0 : (demand > BLDC_LOOP_STATE_MAX) ? BLDC_LOOP_STATE_MAX : demand;
    return (uint32_t)((limited + 8192) >> 14u);
}

/* the integrator for the next period (clamping anti-windup) */
/*@ assigns \nothing;
    ensures in_range: 0 <= \result <= BLDC_LOOP_STATE_MAX;
    ensures holds_where_saturated: \let r = (reference_code > BLDC_LOOP_CODE_MAX ? BLDC_LOOP_CODE_MAX : reference_code); \let m = (measured_code > BLDC_LOOP_CODE_MAX ? BLDC_LOOP_CODE_MAX : measured_code); \let x = (integrator < 0 ? 0 : (integrator > BLDC_LOOP_STATE_MAX ? BLDC_LOOP_STATE_MAX : integrator)); \let e = r - m; \let v = BLDC_LOOP_KP * e + x; ((v > BLDC_LOOP_STATE_MAX && e > 0) || (v < 0 && e < 0)) ==> \result == x;
    ensures integrates_elsewhere: \let r = (reference_code > BLDC_LOOP_CODE_MAX ? BLDC_LOOP_CODE_MAX : reference_code); \let m = (measured_code > BLDC_LOOP_CODE_MAX ? BLDC_LOOP_CODE_MAX : measured_code); \let x = (integrator < 0 ? 0 : (integrator > BLDC_LOOP_STATE_MAX ? BLDC_LOOP_STATE_MAX : integrator)); \let e = r - m; \let v = BLDC_LOOP_KP * e + x; !((v > BLDC_LOOP_STATE_MAX && e > 0) || (v < 0 && e < 0)) ==> \result == ((x + BLDC_LOOP_KI * e) < 0 ? 0 : ((x + BLDC_LOOP_KI * e) > BLDC_LOOP_STATE_MAX ? BLDC_LOOP_STATE_MAX : (x + BLDC_LOOP_KI * e)));
*/
static inline int32_t bldc_current_loop_integrate(int32_t integrator, uint32_t reference_code, uint32_t measured_code)
{
    const uint32_t reference = (reference_code > BLDC_LOOP_CODE_MAX) ? BLDC_LOOP_CODE_MAX : reference_code;
    const uint32_t measured = (measured_code > BLDC_LOOP_CODE_MAX) ? BLDC_LOOP_CODE_MAX : measured_code;
    const int32_t error = (int32_t)reference - (int32_t)measured; /* codes: reference - measured */
    const int32_t state = (integrator < 0) ? 0 : (integrator > BLDC_LOOP_STATE_MAX) ? BLDC_LOOP_STATE_MAX : integrator; /* Q14 counts */
    const int32_t demand = BLDC_LOOP_KP * error + state; /* k_p e + x */
    const int32_t total = state + BLDC_LOOP_KI * error; /* x + k_i e */
    return (demand > BLDC_LOOP_STATE_MAX || demand < 0) ? state : total;
}

/* the nearest ADC code of a braking current in mA, clamped to the spec's braking range */
/*@ assigns \nothing;
    ensures an_adc_code: \result <= BLDC_LOOP_CODE_MAX;
*/
uint32_t bldc_current_reference(uint32_t milliamps);

#endif /* BLDC_CURRENT_LOOP_H */

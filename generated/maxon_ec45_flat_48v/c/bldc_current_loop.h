/* Generated from template templates/c/bldc_current_loop.h.j2 with spec spec/example_maxon_ec45_flat_48v.yaml (sha256 4e4bc402b3ee91505838c88f91659557d0005f5a8b56d60c19ecc3e2f665b3c6). Do not edit: regenerate with `bldc-codegen generate spec/example_maxon_ec45_flat_48v.yaml`. */
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
 *   K_p = 2 L w_c / U_d = 0.226456 per A (L = 0.865 mH, w_c = 2 pi 1000 Hz, U_d = 48 V nominal)
 *   K_i = 2 R w_c / U_d = 472.548 per A s (R = 1.805 ohm): zero at R/L, the plant's pole
 *   per period T = 1/20000 Hz in counts per code (P = 3600, a = 2.01416 mA per code): k_p = 1.64203, k_i = 0.171322
 *   Q17: KP = 215224 (-1.1 ppm), KI = 22455 (-21.2 ppm)
 *   claimed, one step from a given state (IR error analysis): duty <= 0.5034 counts, integrator <= 0.0070 counts a step, 0.0676 over a ramp from 0 to D_max
 *   reference: code = round((mA x 16659268 + 68719476736) / 2^25), exact nearest code for every mA in [0, 2400]
 *
 *   e = r - m (codes), v = k_p e + x, D = clamp(v, 0, D_max) rounded to counts,
 *   x' = x where v > D_max and e > 0 or v < 0 and e < 0 (clamping anti-windup),
 *   else clamp(x + k_i e, 0, D_max). x and v in Q17 counts.
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
 *   bldc_current_loop_duty: state: int32_t in [0, 417857536] (2.4 bits spare)
 *   bldc_current_loop_duty: demand: int32_t in [-881342280, 1299199816] (0.7 bits spare)
 *   bldc_current_loop_duty: limited: int32_t in [0, 417857536] (2.4 bits spare)
 *   bldc_current_loop_integrate: reference: uint32_t in [0, 4095] (20.0 bits spare)
 *   bldc_current_loop_integrate: measured: uint32_t in [0, 4095] (20.0 bits spare)
 *   bldc_current_loop_integrate: error: int32_t in [-4095, 4095] (19.0 bits spare)
 *   bldc_current_loop_integrate: state: int32_t in [0, 417857536] (2.4 bits spare)
 *   bldc_current_loop_integrate: demand: int32_t in [-881342280, 1299199816] (0.7 bits spare)
 *   bldc_current_loop_integrate: total: int32_t in [-91953225, 509810761] (2.1 bits spare)
 *   bldc_current_reference: held: uint32_t in [0, 2400] (20.8 bits spare)
 *   bldc_current_reference: scaled: uint64_t in [68719476736, 108701719936] (27.3 bits spare)
 */

#include <stdint.h>

#define BLDC_LOOP_CODE_MAX 4095u /* ADC full scale: inputs saturate here */
#define BLDC_LOOP_STATE_MAX 417857536 /* D_max = 3188 counts in Q17 */
#define BLDC_LOOP_KP 215224 /* k_p = 1.64203 counts per code, Q17 */
#define BLDC_LOOP_KI 22455 /* k_i = 0.171322 counts per code per PWM period, Q17 */
#define BLDC_LOOP_MA_MAX 2400u /* braking_current_max, mA */
#define BLDC_LOOP_REF_SCALE 16659268ull /* codes per mA, Q25, rounded up */
#define BLDC_LOOP_REF_OFFSET 68719476736ull /* zero-current code, Q25, rounded up */
#define BLDC_LOOP_FRAC_BITS 17u /* fraction bits of x and v */
#define BLDC_LOOP_DUTY_MAX 3188u /* D_max, TIM1 counts: the OFF time holds the current sample */

/* main duty in TIM1 counts, 0..D_max, for this period's sample */
/*@ assigns \nothing;
    ensures within_d_max: \result <= BLDC_LOOP_DUTY_MAX;
*/
static inline uint32_t bldc_current_loop_duty(int32_t integrator, uint32_t reference_code, uint32_t measured_code)
{
    const uint32_t reference = (reference_code > BLDC_LOOP_CODE_MAX) ? BLDC_LOOP_CODE_MAX : reference_code;
    const uint32_t measured = (measured_code > BLDC_LOOP_CODE_MAX) ? BLDC_LOOP_CODE_MAX : measured_code;
    const int32_t error = (int32_t)reference - (int32_t)measured; /* codes: reference - measured */
    const int32_t state = (integrator < 0) ? 0 : (integrator > BLDC_LOOP_STATE_MAX) ? BLDC_LOOP_STATE_MAX : integrator; /* Q17 counts */
    const int32_t demand = BLDC_LOOP_KP * error + state; /* k_p e + x */
    const int32_t limited = (demand < 0) ? 0 : (demand > BLDC_LOOP_STATE_MAX) ? BLDC_LOOP_STATE_MAX : demand;
    return (uint32_t)((limited + 65536) >> 17u);
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
    const int32_t state = (integrator < 0) ? 0 : (integrator > BLDC_LOOP_STATE_MAX) ? BLDC_LOOP_STATE_MAX : integrator; /* Q17 counts */
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

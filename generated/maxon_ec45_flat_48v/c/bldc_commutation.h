/* Generated from template templates/c/bldc_commutation.h.j2 with spec spec/example_maxon_ec45_flat_48v.yaml (sha256 88a70eb72b9494810aaa1248e2beb874e1bc6578ac98fdca4370be1ee72c27cc). Do not edit: regenerate with `make`. */
#ifndef BLDC_COMMUTATION_H
#define BLDC_COMMUTATION_H

/*
 * Portable commutation core: PWM-OFF-PWM braking, method "improved".
 * A pure function of its inputs: no register access, no floating point, no division
 * helpers (one 32-bit hardware UDIV for the speed, one for Eq. 20), no dynamic memory.
 *
 * Units
 *   TIM1 counts      BLDC_PWM_PERIOD_COUNTS = duty 1 (20000 Hz PWM)
 *   Hall ticks       1e+06 Hz Hall timer; one Hall interval is 60 electrical degrees
 *   bus code         U_d = code * 0.0169189 V
 *   current code     I = (code - 2048) * 0.00201416 A
 *
 * Fixed-point formats and rounding (chosen and proven by codegen/fixedpoint/design.py)
 *   X = P * 4E/U_d = K_X / (T B), K_X = 4.393891e+09 (Eqs. 3, 9)
 *   X_q, Q2: round(K_Xq / round(T B / 2^3)), K_Xq = 2196945455
 *   duties: Eq. 18 / 16 in counts from X_c = round(X_q / 2^2), clamped to [0, P]
 *   t_com (Eq. 20 at the emitted duties): round(K_Gq I / (B W_q)),
 *       W_q = (2P + 2 C_on - 4 C_off) 2^2 - X_q, K_Gq = 8897143 (K_G = 2.224286e+06 in Q2)
 *   all divisions round to nearest; segment and fail-area flags use exact integer
 *   comparisons against K_X = 48332800000 / 11.
 *   Error bounds against the exact symbolic model: duties <= 0.689 counts,
 *   t_com <= 1.622 ticks.
 *
 * Intermediate ranges proven over the whole input domain (bits of headroom)
 *   T*B: uint32_t in [525768, 29548818] (7.2 bits spare)
 *   K_Xq + (T*B >> s)/2: uint32_t in [2196978315, 2198792257] (1.0 bits spare)
 *   X_q: uint32_t in [595, 33430] (17.0 bits spare)
 *   W_q: int32_t in [86994, 119829] (14.1 bits spare)
 *   B*W_q: uint32_t in [200610003, 424911376] (3.3 bits spare)
 *   K_Gq*I: uint64_t in [0, 10596497313] (30.7 bits spare)
 *   P*T*B*K_X_den: uint64_t in [41640825600, 2340266385600] (22.9 bits spare)
 *   duty sums: int32_t in [10948, 19158] (16.8 bits spare)
 *
 * Safety
 *   Hall code 000 or 111, or a jump that is not one sector forward or back: every
 *   switch off (turn_on_switch = turn_off_switch = BLDC_NO_SWITCH), FLAG_INVALID_HALL.
 *   Hall period below 228 ticks (speed above 5500 rpm) or bus
 *   code above 3546 (60 V): every switch off, FLAG_INPUT_SATURATED.
 *   Period above 8333 ticks (below 150 rpm), bus below 2306
 *   (39 V), current outside [0, 2.4] A, main duty above P: saturated
 *   to the range, FLAG_INPUT_SATURATED.
 */

#include <stdint.h>

#define BLDC_PWM_PERIOD_COUNTS 3600u /* TIM1 counts per PWM period */
#define BLDC_NO_SWITCH 0xFFu

/* Switch index 0..5 = T1..T6: T1/T2, T3/T4, T5/T6 are the upper/lower transistors of
 * phases A, B, C (TIM1 CH1/CH1N, CH2/CH2N, CH3/CH3N). */
#define BLDC_FLAG_HIGH_SPEED 0x01u        /* Eq. 18 high-speed segment: 4E > U_d */
#define BLDC_FLAG_FAIL_AREA_CLAMPED 0x02u /* conventional: Eq. 16 D_off outside [0, 1] */
#define BLDC_FLAG_INPUT_SATURATED 0x04u   /* an input was outside the spec's range */
#define BLDC_FLAG_INVALID_HALL 0x08u      /* all switches off */
#define BLDC_FLAG_TIME_CLAMPED 0x10u      /* Eq. 20 exceeds the sector: clamped to it */

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

/* Commutation decision at a Hall edge (pure, reentrant). */
void bldc_commutate(const bldc_inputs_t *in, bldc_outputs_t *out);

#endif /* BLDC_COMMUTATION_H */

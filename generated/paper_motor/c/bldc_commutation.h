/* Generated from template templates/c/bldc_commutation.h.j2 with spec spec/paper_motor.yaml (sha256 088d04b5d93e1db022c5058e8b28c79f09dd6712853062822d3652a8919f775d). Do not edit: regenerate with `make`. */
#ifndef BLDC_COMMUTATION_H
#define BLDC_COMMUTATION_H

/*
 * Portable commutation core: PWM-OFF-PWM braking, method "improved".
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
 * Fixed-point formats and rounding (chosen and proven by codegen/fixedpoint/design.py)
 *   X = P 4E/U_d = K_X / (T B), K_X = 3.834668e+10 counts ticks codes (Eqs. 3, 9)
 *   per bus code B, rounded to nearest by a two-step 32-bit long division:
 *     x_numerator       = round(N_X / B), N_X = round(K_X 2^6) = 2454187795041
 *     time_numerator    = round(N_G / B), N_G = round(K_G 2^6) = 1407534545,
 *                         K_G = 2.199273e+07 (Eq. 20: t_com f_hall = K_G I_code / (B W))
 *     high_speed_period = ceil(C / B), C = ceil(K_X / P) = 10651857: T < it <=> 4E > U_d
 *   per speed (bldc_commutation_timing()), period T in ticks:
 *     X_q = round(x_numerator / T), Q6 counts; X_c = round(X_q / 2^6)
 *     duties: Eq. 18 / 16 in counts from X_c, clamped to [0, P]
 *     W_q = (2P + 2 C_on - 4 C_off) 2^6 - X_q, Eq. 20's denominator at the emitted duties
 *     t_com = round(time_numerator i / W_q), i = current code - offset, saturated to
 *     [0, T] (Eq. 20 at the emitted duties; W_q <= 0: the turn-off current never
 *     reaches zero, t_com = T)
 *   rounding is half up everywhere; the segment and fail-area decisions are exact
 *   integer comparisons (K_X = 4639948800000 / 121).
 *   Error bounds against the exact symbolic model: duties <= 0.508 counts
 *   (1/2 for the final rounding plus the quantisation of X); t_com <= 8.000 ticks
 *   wherever W >= 69.034 counts. Closer to the top-speed limit (W -> 0) Eq. 20's
 *   sensitivity t/W dominates; the verifier checks those points against their interval.
 *
 * Intermediate ranges proven over the whole input domain: bus codes
 * [2257, 3385], periods [2000, 65535] ticks (up to the full Hall counter),
 * current codes over the whole ADC range (bits of headroom)
 *   N_X high part: uint32_t in [2396667768, 2396667768] (0.8 bits spare)
 *   N_X remainder + B/2: uint32_t in [2312295, 3467932] (10.3 bits spare)
 *   N_X / B: uint32_t in [725018551, 1087367212] (2.0 bits spare)
 *   N_G high part: uint32_t in [1407534545, 1407534545] (1.6 bits spare)
 *   N_G remainder + B/2: uint32_t in [3384, 5077] (19.7 bits spare)
 *   N_G / B: uint32_t in [415816, 623632] (12.7 bits spare)
 *   C + B - 1: uint32_t in [10654113, 10655241] (8.7 bits spare)
 *   x_numerator + T/2: uint32_t in [725019551, 1087399980] (2.0 bits spare)
 *   X_q: uint32_t in [11064, 543701] (12.9 bits spare)
 *   W_q: int32_t in [932664, 1465301] (10.5 bits spare)
 *   W_q low: int32_t in [-1004501, -471864] (11.1 bits spare)
 *   time_numerator i + W_q/2: int32_t in [-1276736972, 1277034940] (0.7 bits spare)
 *   time_numerator i - W_q/2: int32_t in [-1278663072, 1275641477] (0.7 bits spare)
 *
 * Safety
 *   Hall code 000 or 111, or a jump that is not one sector forward or back: every
 *   switch off (edge BLDC_EDGE_NONE, BLDC_NO_SWITCH), BLDC_FLAG_INVALID_HALL.
 *   Hall period below 2000 ticks (speed above 5000 rpm) or bus
 *   code above 3385 (30 V): every switch off, BLDC_FLAG_INPUT_SATURATED.
 *   Bus code below 2257 (20 V) and main duty above P: saturated, flagged.
 *   Period above 50000 ticks (below 200 rpm) and current outside
 *   [0, 10] A: flagged but not clamped, because the equations are proven
 *   over the whole counter and ADC range and the true values give the right answer; a
 *   negative current gives t_com = 0 and the commutation time saturates at the sector.
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
    uint32_t x_numerator;       /* round(K_X 2^f / B) */
    uint32_t high_speed_period; /* ceil(C / B): Eq. 18 high-speed segment below it */
    int32_t time_numerator;     /* round(K_G 2^f / B) */
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

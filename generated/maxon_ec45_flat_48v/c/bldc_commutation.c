/* Generated from template templates/c/bldc_commutation.c.j2 with spec spec/example_maxon_ec45_flat_48v.yaml (sha256 4e4bc402b3ee91505838c88f91659557d0005f5a8b56d60c19ecc3e2f665b3c6). Do not edit: regenerate with `bldc-codegen generate spec/example_maxon_ec45_flat_48v.yaml`. */
#include "bldc_commutation.h"

#define N_X_HIGH 2196945454u /* N_X >> 11, round(K_X 2^10), K_X = 4.393891e+09 (Eqs. 3, 9) */
#define N_X_LOW 1117u /* N_X mod 2^11 */
#define N_X_SHIFT 11u
#define HIGH_SPEED_TB 1220526u /* ceil(K_X / P): 4E > U_d <=> T B < it (Eq. 18) */
#define N_G_HIGH 2277668571u /* N_G >> 0, round(K_G 2^10 / 1), K_G = 2.224286e+06 (Eq. 20) */
#define N_G_LOW 0u /* N_G mod 2^0 */
#define N_G_SHIFT 0u
#define CURRENT_OFFSET_Q 2048 /* zero current: 2048 codes x 1 */

/* Hall code -> sector (Table 1 order), 0xFF for 000 and 111 */
const uint8_t bldc_sector_of_hall[8] = {
    255u, /* 000: invalid */
    5u, /* 001: sector 5 */
    3u, /* 010: sector 3 */
    4u, /* 011: sector 4 */
    1u, /* 100: sector 1 */
    0u, /* 101: sector 0 */
    2u, /* 110: sector 2 */
    255u, /* 111: invalid */
};

/* (previous Hall code << 3 | Hall code) -> edge, BLDC_EDGE_NONE when invalid */
const uint8_t bldc_edge_of_hall_pair[64] = {
    255u, /* 000 -> 000: invalid: every switch off */
    255u, /* 000 -> 001: invalid: every switch off */
    255u, /* 000 -> 010: invalid: every switch off */
    255u, /* 000 -> 011: invalid: every switch off */
    255u, /* 000 -> 100: invalid: every switch off */
    255u, /* 000 -> 101: invalid: every switch off */
    255u, /* 000 -> 110: invalid: every switch off */
    255u, /* 000 -> 111: invalid: every switch off */
    255u, /* 001 -> 000: invalid: every switch off */
    255u, /* 001 -> 001: invalid: every switch off */
    255u, /* 001 -> 010: invalid: every switch off */
    10u, /* 001 -> 011: reverse into sector 4 */
    255u, /* 001 -> 100: invalid: every switch off */
    0u, /* 001 -> 101: forward into sector 0 */
    255u, /* 001 -> 110: invalid: every switch off */
    255u, /* 001 -> 111: invalid: every switch off */
    255u, /* 010 -> 000: invalid: every switch off */
    255u, /* 010 -> 001: invalid: every switch off */
    255u, /* 010 -> 010: invalid: every switch off */
    4u, /* 010 -> 011: forward into sector 4 */
    255u, /* 010 -> 100: invalid: every switch off */
    255u, /* 010 -> 101: invalid: every switch off */
    8u, /* 010 -> 110: reverse into sector 2 */
    255u, /* 010 -> 111: invalid: every switch off */
    255u, /* 011 -> 000: invalid: every switch off */
    5u, /* 011 -> 001: forward into sector 5 */
    9u, /* 011 -> 010: reverse into sector 3 */
    255u, /* 011 -> 011: invalid: every switch off */
    255u, /* 011 -> 100: invalid: every switch off */
    255u, /* 011 -> 101: invalid: every switch off */
    255u, /* 011 -> 110: invalid: every switch off */
    255u, /* 011 -> 111: invalid: every switch off */
    255u, /* 100 -> 000: invalid: every switch off */
    255u, /* 100 -> 001: invalid: every switch off */
    255u, /* 100 -> 010: invalid: every switch off */
    255u, /* 100 -> 011: invalid: every switch off */
    255u, /* 100 -> 100: invalid: every switch off */
    6u, /* 100 -> 101: reverse into sector 0 */
    2u, /* 100 -> 110: forward into sector 2 */
    255u, /* 100 -> 111: invalid: every switch off */
    255u, /* 101 -> 000: invalid: every switch off */
    11u, /* 101 -> 001: reverse into sector 5 */
    255u, /* 101 -> 010: invalid: every switch off */
    255u, /* 101 -> 011: invalid: every switch off */
    1u, /* 101 -> 100: forward into sector 1 */
    255u, /* 101 -> 101: invalid: every switch off */
    255u, /* 101 -> 110: invalid: every switch off */
    255u, /* 101 -> 111: invalid: every switch off */
    255u, /* 110 -> 000: invalid: every switch off */
    255u, /* 110 -> 001: invalid: every switch off */
    3u, /* 110 -> 010: forward into sector 3 */
    255u, /* 110 -> 011: invalid: every switch off */
    7u, /* 110 -> 100: reverse into sector 1 */
    255u, /* 110 -> 101: invalid: every switch off */
    255u, /* 110 -> 110: invalid: every switch off */
    255u, /* 110 -> 111: invalid: every switch off */
    255u, /* 111 -> 000: invalid: every switch off */
    255u, /* 111 -> 001: invalid: every switch off */
    255u, /* 111 -> 010: invalid: every switch off */
    255u, /* 111 -> 011: invalid: every switch off */
    255u, /* 111 -> 100: invalid: every switch off */
    255u, /* 111 -> 101: invalid: every switch off */
    255u, /* 111 -> 110: invalid: every switch off */
    255u, /* 111 -> 111: invalid: every switch off */
};

/* edge -> {switch at D_on, switch at D_off} (codegen/derivation/switching.py) */
const uint8_t bldc_edge_switch[12][2] = {
    {1u, 5u}, /* edge 0: into sector 0 (0-60 deg), forward 0 deg: non-commutating B via D4, off C (T6), on A (T2) */
    {4u, 2u}, /* edge 1: into sector 1 (60-120 deg), forward 60 deg: non-commutating A via D1, off B (T3), on C (T5) */
    {3u, 1u}, /* edge 2: into sector 2 (120-180 deg), forward 120 deg: non-commutating C via D6, off A (T2), on B (T4) */
    {0u, 4u}, /* edge 3: into sector 3 (180-240 deg), forward 180 deg: non-commutating B via D3, off C (T5), on A (T1) */
    {5u, 3u}, /* edge 4: into sector 4 (240-300 deg), forward 240 deg: non-commutating A via D2, off B (T4), on C (T6) */
    {2u, 0u}, /* edge 5: into sector 5 (300-360 deg), forward 300 deg: non-commutating C via D5, off A (T1), on B (T3) */
    {3u, 5u}, /* edge 6: into sector 0 (0-60 deg), reverse 60 deg: non-commutating A via D2, off C (T6), on B (T4) */
    {0u, 2u}, /* edge 7: into sector 1 (60-120 deg), reverse 120 deg: non-commutating C via D5, off B (T3), on A (T1) */
    {5u, 1u}, /* edge 8: into sector 2 (120-180 deg), reverse 180 deg: non-commutating B via D4, off A (T2), on C (T6) */
    {2u, 4u}, /* edge 9: into sector 3 (180-240 deg), reverse 240 deg: non-commutating A via D1, off C (T5), on B (T3) */
    {1u, 3u}, /* edge 10: into sector 4 (240-300 deg), reverse 300 deg: non-commutating C via D6, off B (T4), on A (T2) */
    {4u, 0u}, /* edge 11: into sector 5 (300-360 deg), reverse 0 deg: non-commutating B via D3, off A (T1), on C (T5) */
};

/* round(N / divisor) for N = high 2^shift + low: two 32-bit divides, no 64-bit helper. N / divisor = q_high 2^shift + (r 2^shift + low) / divisor, r = high mod divisor. */
/*@ assigns \nothing;
*/
static uint32_t bldc_divide_long(uint32_t high, uint32_t low, uint32_t shift, uint32_t divisor)
{
    const uint32_t q_high = high / divisor;
    const uint32_t remainder = ((high % divisor) << shift) + low;
    return (q_high << shift) + (remainder + (divisor >> 1)) / divisor;
}

/* Saturate a bus code and precompute its reciprocals (pure, reentrant) */
bldc_bus_t bldc_bus_condition(uint32_t bus_code)
{
    uint32_t code = bus_code;
    uint32_t period_min = BLDC_PERIOD_MIN_TICKS;
    uint32_t flags = 0u;
    if (code > BLDC_BUS_CODE_MAX) {
        code = BLDC_BUS_CODE_MAX;
        period_min = BLDC_PERIOD_NEVER; /* over-voltage: every edge goes to the safe state */
        flags = BLDC_FLAG_INPUT_SATURATED;
    } else if (code < BLDC_BUS_CODE_MIN) {
        code = BLDC_BUS_CODE_MIN;
        flags = BLDC_FLAG_INPUT_SATURATED;
    }
    const bldc_bus_t bus = {
        .x_numerator = bldc_divide_long(N_X_HIGH, N_X_LOW, N_X_SHIFT, code),
        .high_speed_period = (HIGH_SPEED_TB + code - 1u) / code,
        .time_numerator = (int32_t)bldc_divide_long(N_G_HIGH, N_G_LOW, N_G_SHIFT, code),
        .period_min = period_min,
        .bus_code = code,
        .flags = flags,
    };
    return bus;
}

/* Duties and commutation time (pure, reentrant): period in Hall ticks, current as its ADC code, main duty in TIM1 counts; any uint32_t value of each is allowed */
bldc_timing_t bldc_commutation_timing(const bldc_bus_t *bus, uint32_t period_ticks, uint32_t current_adc, uint32_t main_duty_counts)
{
    (void)main_duty_counts; /* not used by this method */
    uint32_t flags = bus->flags;
    const uint32_t period = (period_ticks > BLDC_PERIOD_CAP_TICKS) ? BLDC_PERIOD_CAP_TICKS : period_ticks; /* the proven range: the full Hall counter */
    if (period < bus->period_min) { /* above the top speed or over-voltage: braking is no longer controlled */
        const bldc_timing_t safe = {
            .period_min = BLDC_PERIOD_NEVER,
            .turn_on_compare = 0u,
            .turn_off_compare = 0u,
            .commutation_ticks = 0u,
            .flags = (uint16_t)(flags | BLDC_FLAG_INPUT_SATURATED),
        };
        return safe;
    }
    if (period > BLDC_PERIOD_MAX_TICKS) { /* below the minimum speed: still exact */
        flags |= BLDC_FLAG_INPUT_SATURATED;
    }
    const uint32_t current_code = (current_adc > BLDC_ADC_CODE_MAX) ? BLDC_ADC_CODE_MAX : current_adc; /* above the ADC's range: full scale */
    if (current_adc < BLDC_CURRENT_CODE_LOW || current_adc > BLDC_CURRENT_CODE_HIGH) { /* outside the braking-current range */
        flags |= BLDC_FLAG_INPUT_SATURATED;
    }
    const int32_t current = (int32_t)current_code - CURRENT_OFFSET_Q; /* I in codes, offset removed */
    const uint32_t latest = period * 15u / 16u - BLDC_COMMUTATION_GUARD_TICKS; /* the latest end: the guard and the sector-shortening margin before the sector's end (positive from the minimum period on), so the next edge, up to hall.sector_shortening early, switches the other switch of the leg on at least the dead time after this end switched its partner off */
    const uint32_t x_q = (bus->x_numerator + (period >> 1)) / period; /* X = P 4E/U_d in Q10 counts (Eqs. 3, 9) */
    const int32_t x_c = (int32_t)((x_q + 512u) >> 10u); /* X in counts */
    const uint32_t high_speed = (period < bus->high_speed_period) ? 1u : 0u; /* Eq. 18: 4E > U_d, exactly */
    if (high_speed != 0u) {
        flags |= BLDC_FLAG_HIGH_SPEED;
    }
    int32_t on = 0;
    int32_t off = 0;
    if (high_speed != 0u) { /* Eq. 18 */
        on = (2 * (int32_t)BLDC_PWM_PERIOD_COUNTS - x_c < 0) ? 0 : 2 * (int32_t)BLDC_PWM_PERIOD_COUNTS - x_c; /* D_on = 2 - 4E/U_d; 0 above the upper speed limit 4E > 2 U_d */
        off = 0; /* the turn-off phase off */
    } else {
        on = (int32_t)BLDC_PWM_PERIOD_COUNTS; /* the turn-on phase fully on */
        off = ((int32_t)BLDC_PWM_PERIOD_COUNTS - x_c < 0) ? 0 : (int32_t)BLDC_PWM_PERIOD_COUNTS - x_c; /* D_off = 1 - 4E/U_d */
    }
    const int32_t w_q = (2 * (int32_t)BLDC_PWM_PERIOD_COUNTS + 2 * on - 4 * off) * 1024 - (int32_t)x_q; /* Eq. 20's denominator at the emitted duties, Q10 */
    uint32_t ticks = 0u;
    if (w_q <= 0) { /* the turn-off current never reaches zero: the whole sector */
        if (current > 0) { /* unless there is no current to commutate */
            ticks = latest;
            flags |= BLDC_FLAG_TIME_CLAMPED;
        }
    } else {
        const int32_t t = (bus->time_numerator * current + (w_q >> 1)) / w_q; /* Eq. 20 */
        ticks = (uint32_t)((t < 0) ? 0 : t); /* a negative current: nothing to commutate */
        if (ticks > latest) {
            flags |= BLDC_FLAG_TIME_CLAMPED;
        }
        ticks = (ticks > latest) ? latest : ticks; /* at most the sector, less the guard */
    }
    const bldc_timing_t timing = {
        .period_min = bus->period_min,
        .turn_on_compare = (uint16_t)on,
        .turn_off_compare = (uint16_t)off,
        .commutation_ticks = (uint16_t)ticks,
        .flags = (uint16_t)flags,
    };
    return timing;
}

/* Commutation decision on plain inputs: bldc_edge_of(), bldc_bus_condition() and bldc_commutation_timing() for the same inputs (pure, reentrant) */
void bldc_commutate(const bldc_inputs_t *inputs, bldc_outputs_t *out)
{
    const uint32_t hall_code = (uint32_t)inputs->hall_code;
    const uint32_t previous_hall_code = (uint32_t)inputs->previous_hall_code;
    const uint32_t period = (uint32_t)inputs->hall_period_ticks;
    uint32_t edge = BLDC_EDGE_NONE;
    uint32_t sector = BLDC_INVALID_SECTOR;
    if (hall_code <= 7u) {
        sector = (uint32_t)bldc_sector_of_hall[hall_code]; /* the sector of the new code */
        edge = bldc_edge_of(previous_hall_code, hall_code);
    }
    out->turn_on_compare = 0u;
    out->turn_off_compare = 0u;
    out->commutation_ticks = 0u;
    out->turn_on_switch = (uint8_t)BLDC_NO_SWITCH;
    out->turn_off_switch = (uint8_t)BLDC_NO_SWITCH;
    out->sector = (uint8_t)sector;
    out->flags = (uint8_t)BLDC_FLAG_INVALID_HALL;
    if (edge < BLDC_EDGE_COUNT) {
        const bldc_bus_t bus = bldc_bus_condition((uint32_t)inputs->bus_voltage_adc); /* bldc_bus_condition() */
        const bldc_timing_t timing = bldc_commutation_timing(&bus, period, (uint32_t)inputs->phase_current_adc, (uint32_t)inputs->main_duty_counts);
        out->turn_on_compare = timing.turn_on_compare;
        out->turn_off_compare = timing.turn_off_compare;
        out->commutation_ticks = timing.commutation_ticks;
        out->flags = (uint8_t)timing.flags;
        if (period >= timing.period_min) { /* a shorter interval (over-speed) or over-voltage: the safe state */
            out->turn_on_switch = bldc_edge_switch[edge][0];
            out->turn_off_switch = bldc_edge_switch[edge][1];
        }
    }
}

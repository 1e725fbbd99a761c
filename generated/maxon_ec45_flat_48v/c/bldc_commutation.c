/* Generated from template templates/c/bldc_commutation.c.j2 with spec spec/example_maxon_ec45_flat_48v.yaml (sha256 dece2274d408914f53e74b84728750ad8d9e2a754cdc79404df2f8daae1a20d5). Do not edit: regenerate with `make`. */
#include "bldc_commutation.h"

#define BUS_CODE_MIN 2306u /* 39 V */
#define BUS_CODE_MAX 3546u /* 60 V */
#define INVALID_SECTOR 0xFFu
#define K_X_HIGH 2196945454u /* N_X >> 11, N_X = round(K_X 2^10) = 4499344290909 (Eqs. 3, 9) */
#define K_X_LOW 1117u  /* N_X mod 2^11 */
#define K_X_SHIFT 11u
#define K_G_HIGH 2277668571u /* N_G >> 0, N_G = round(K_G 2^10) = 2277668571 (Eq. 20) */
#define K_G_LOW 0u  /* N_G mod 2^0 */
#define K_G_SHIFT 0u
#define HIGH_SPEED_TB 1220526u /* C = ceil(K_X / P): 4E > U_d <=> T B < C (Eq. 18) */

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

const uint8_t bldc_edge_switch[BLDC_EDGE_COUNT][2] = {
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

/* round(N / divisor) for N = high 2^shift + low: two 32-bit divides, no 64-bit helper.
 * N / divisor = q_high 2^shift + (r 2^shift + low) / divisor, r = high mod divisor. */
static uint32_t bldc_divide_long(uint32_t high, uint32_t low, uint32_t shift, uint32_t divisor)
{
    const uint32_t q_high = high / divisor;
    const uint32_t remainder = ((high - q_high * divisor) << shift) | low;
    return (q_high << shift) + (remainder + (divisor >> 1u)) / divisor;
}

bldc_bus_t bldc_bus_condition(uint32_t bus_code)
{
    bldc_bus_t bus;
    uint32_t code = bus_code;

    bus.flags = 0u;
    bus.period_min = BLDC_PERIOD_MIN_TICKS;
    if (code > BUS_CODE_MAX) {
        code = BUS_CODE_MAX;
        bus.period_min = BLDC_PERIOD_NEVER; /* over-voltage: every edge goes to the safe state */
        bus.flags = BLDC_FLAG_INPUT_SATURATED;
    } else if (code < BUS_CODE_MIN) {
        code = BUS_CODE_MIN;
        bus.flags = BLDC_FLAG_INPUT_SATURATED;
    }
    bus.bus_code = code;
    bus.x_numerator = bldc_divide_long(K_X_HIGH, K_X_LOW, K_X_SHIFT, code);
    bus.high_speed_period = (HIGH_SPEED_TB + code - 1u) / code;
    bus.time_numerator = (int32_t)bldc_divide_long(K_G_HIGH, K_G_LOW, K_G_SHIFT, code);
    return bus;
}

bldc_timing_t bldc_commutation_timing(const bldc_bus_t *bus, uint32_t period_ticks,
                                      uint32_t current_adc, uint32_t main_duty_counts)
{
    bldc_timing_t timing = {BLDC_PERIOD_NEVER, 0u, 0u, 0u, 0u};
    const int32_t period_counts = (int32_t)BLDC_PWM_PERIOD_COUNTS;
    uint32_t flags = bus->flags;
    int32_t on;
    int32_t off;

    (void)main_duty_counts; /* the improved rule does not use the main duty (Eq. 18) */
    if (period_ticks > BLDC_PERIOD_CAP_TICKS) {
        period_ticks = BLDC_PERIOD_CAP_TICKS; /* the proven range: the full Hall counter */
    }
    if (period_ticks < bus->period_min) {
        /* Above the top speed or over-voltage: braking is no longer controlled. */
        timing.flags = (uint16_t)(flags | BLDC_FLAG_INPUT_SATURATED);
        return timing;
    }
    if (period_ticks > BLDC_PERIOD_MAX_TICKS) {
        flags |= BLDC_FLAG_INPUT_SATURATED; /* below the minimum speed: still exact */
    }
    const int32_t current = (int32_t)current_adc - BLDC_CURRENT_OFFSET_CODE;
    if (current < 0 || current > BLDC_CURRENT_CODE_MAX) {
        flags |= BLDC_FLAG_INPUT_SATURATED;
    }

    /* X = P 4E/U_d (Eqs. 3, 9) in Q10 counts, then in counts. */
    const uint32_t x_q = (bus->x_numerator + (period_ticks >> 1)) / period_ticks;
    const int32_t x_c = (int32_t)((x_q + 512u) >> BLDC_X_FRAC_BITS);
    const uint32_t high_speed = (period_ticks < bus->high_speed_period) ? 1u : 0u;
    if (high_speed != 0u) {
        flags |= BLDC_FLAG_HIGH_SPEED;
    }
    /* Eq. 18: low speed, turn-on phase fully on and turn-off phase modulated; high
     * speed, turn-off phase off and turn-on phase modulated. */
    if (high_speed != 0u) {
        on = 2 * period_counts - x_c; /* D_on = 2 - 4E/U_d */
        if (on < 0) {
            on = 0; /* above the upper speed limit 4E > 2 U_d */
        }
        off = 0;
    } else {
        on = period_counts;
        off = period_counts - x_c; /* D_off = 1 - 4E/U_d */
        if (off < 0) {
            off = 0;
        }
    }

    /* Eq. 20 at the emitted duties: t = time_numerator i / W_q. */
    const int32_t w_q = (2 * period_counts + 2 * on - 4 * off) * BLDC_X_SCALE - (int32_t)x_q;
    uint32_t ticks;
    if (w_q <= 0) {
        /* The turn-off current never reaches zero: the whole sector, unless there is
         * no current to commutate. */
        ticks = 0u;
        if (current > 0) {
            ticks = period_ticks;
            flags |= BLDC_FLAG_TIME_CLAMPED;
        }
    } else {
        int32_t t = (bus->time_numerator * current + (w_q >> 1)) / w_q;
        if (t < 0) {
            t = 0; /* negative braking current: nothing to commutate */
        }
        ticks = (uint32_t)t;
        if (ticks > period_ticks) {
            ticks = period_ticks;
            flags |= BLDC_FLAG_TIME_CLAMPED;
        }
    }

    timing.turn_on_compare = (uint16_t)on;
    timing.turn_off_compare = (uint16_t)off;
    timing.commutation_ticks = (uint16_t)ticks;
    timing.flags = (uint16_t)flags;
    timing.period_min = bus->period_min;
    return timing;
}

void bldc_commutate(const bldc_inputs_t *in, bldc_outputs_t *out)
{
    bldc_timing_t timing = {BLDC_PERIOD_NEVER, 0u, 0u, 0u, BLDC_FLAG_INVALID_HALL};
    uint32_t edge = BLDC_EDGE_NONE;
    uint8_t sector = INVALID_SECTOR;

    if (in->hall_code <= 7u && in->previous_hall_code <= 7u) {
        sector = bldc_sector_of_hall[in->hall_code];
        edge = bldc_edge_of(in->previous_hall_code, in->hall_code);
    }
    if (edge < BLDC_EDGE_COUNT) {
        const bldc_bus_t bus = bldc_bus_condition(in->bus_voltage_adc);
        timing = bldc_commutation_timing(&bus, in->hall_period_ticks, in->phase_current_adc,
                                         in->main_duty_counts);
        if (in->hall_period_ticks < timing.period_min) {
            edge = BLDC_EDGE_NONE; /* the safe state */
        }
    }
    out->turn_on_compare = timing.turn_on_compare;
    out->turn_off_compare = timing.turn_off_compare;
    out->commutation_ticks = timing.commutation_ticks;
    if (edge < BLDC_EDGE_COUNT) {
        out->turn_on_switch = bldc_edge_switch[edge][0];
        out->turn_off_switch = bldc_edge_switch[edge][1];
    } else {
        out->turn_on_switch = BLDC_NO_SWITCH;
        out->turn_off_switch = BLDC_NO_SWITCH;
    }
    out->sector = sector;
    out->flags = (uint8_t)timing.flags;
}

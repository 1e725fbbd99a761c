/* Generated from template templates/c/bldc_commutation.c.j2 with spec spec/example_maxon_ec45_flat_48v.yaml (sha256 88a70eb72b9494810aaa1248e2beb874e1bc6578ac98fdca4370be1ee72c27cc). Do not edit: regenerate with `make`. */
#include "bldc_commutation.h"

#define P_COUNTS ((int32_t)BLDC_PWM_PERIOD_COUNTS)
#define X_FRAC_BITS 2u
#define TB_SHIFT 3u
#define K_XQ 2196945455u              /* round(K_X 2^2 / 2^3), Eqs. 3, 9 */
#define K_X_NUM 48332800000ull /* K_X = X T B exactly, numerator */
#define K_X_DEN 11ull /* K_X denominator */
#define K_GQ 8897143u              /* round(K_G 2^2), Eq. 20 */
#define PERIOD_MIN_TICKS 228u /* 5500 rpm */
#define PERIOD_MAX_TICKS 8333u /* 150 rpm */
#define BUS_CODE_MIN 2306u  /* 39 V */
#define BUS_CODE_MAX 3546u  /* 60 V */
#define CURRENT_OFFSET_CODE 2048u /* 0 A */
#define CURRENT_CODE_MAX 1191u /* 2.4 A above the offset */
#define INVALID 0xFFu

/* Table 1 (this spec's Hall sequence): Hall code -> sector, 0xFF for 000/111. */
static const uint8_t bldc_sector_of_hall[8] = {
    255u, /* 000: code 0, invalid */
    5u, /* 001: code 1, sector 5 */
    3u, /* 002: code 2, sector 3 */
    4u, /* 003: code 3, sector 4 */
    1u, /* 004: code 4, sector 1 */
    0u, /* 005: code 5, sector 0 */
    2u, /* 006: code 6, sector 2 */
    255u, /* 007: code 7, invalid */
};

/* Switching table (codegen/derivation/switching.py): transistor at D_on and at D_off
 * for the edge entering each sector, [direction][sector][on, off]. */
static const uint8_t bldc_edge_switch[2][6][2] = {
    { /* forward */
        {1u, 5u}, /* sector 0 (0-60 deg), forward 0 deg: non-commutating B via D4, off C (T6), on A (T2) */
        {4u, 2u}, /* sector 1 (60-120 deg), forward 60 deg: non-commutating A via D1, off B (T3), on C (T5) */
        {3u, 1u}, /* sector 2 (120-180 deg), forward 120 deg: non-commutating C via D6, off A (T2), on B (T4) */
        {0u, 4u}, /* sector 3 (180-240 deg), forward 180 deg: non-commutating B via D3, off C (T5), on A (T1) */
        {5u, 3u}, /* sector 4 (240-300 deg), forward 240 deg: non-commutating A via D2, off B (T4), on C (T6) */
        {2u, 0u}, /* sector 5 (300-360 deg), forward 300 deg: non-commutating C via D5, off A (T1), on B (T3) */
    },
    { /* reverse */
        {3u, 5u}, /* sector 0 (0-60 deg), reverse 60 deg: non-commutating A via D2, off C (T6), on B (T4) */
        {0u, 2u}, /* sector 1 (60-120 deg), reverse 120 deg: non-commutating C via D5, off B (T3), on A (T1) */
        {5u, 1u}, /* sector 2 (120-180 deg), reverse 180 deg: non-commutating B via D4, off A (T2), on C (T6) */
        {2u, 4u}, /* sector 3 (180-240 deg), reverse 240 deg: non-commutating A via D1, off C (T5), on B (T3) */
        {1u, 3u}, /* sector 4 (240-300 deg), reverse 300 deg: non-commutating C via D6, off B (T4), on A (T2) */
        {4u, 0u}, /* sector 5 (300-360 deg), reverse 0 deg: non-commutating B via D3, off A (T1), on C (T5) */
    },
};

static uint32_t divide_rounded(uint32_t numerator, uint32_t denominator)
{
    /* Round to nearest without overflowing numerator + denominator / 2. */
    uint32_t quotient = numerator / denominator;
    uint32_t remainder = numerator - quotient * denominator;
    if (remainder >= denominator - remainder) {
        quotient++;
    }
    return quotient;
}

static void bldc_safe_state(bldc_outputs_t *out, uint8_t sector, uint8_t flags)
{
    out->turn_on_compare = 0u;
    out->turn_off_compare = 0u;
    out->commutation_ticks = 0u;
    out->turn_on_switch = BLDC_NO_SWITCH;
    out->turn_off_switch = BLDC_NO_SWITCH;
    out->sector = sector;
    out->flags = flags;
}

static int32_t clamp_duty(int32_t counts)
{
    if (counts < 0) {
        return 0;
    }
    if (counts > P_COUNTS) {
        return P_COUNTS;
    }
    return counts;
}

void bldc_commutate(const bldc_inputs_t *in, bldc_outputs_t *out)
{
    uint8_t flags = 0u;
    const uint8_t sector = bldc_sector_of_hall[in->hall_code & 7u];
    const uint8_t previous = bldc_sector_of_hall[in->previous_hall_code & 7u];
    uint32_t direction;

    if (in->hall_code > 7u || in->previous_hall_code > 7u || sector == INVALID || previous == INVALID) {
        bldc_safe_state(out, INVALID, BLDC_FLAG_INVALID_HALL);
        return;
    }
    if (sector == (uint8_t)((previous + 1u) % 6u)) {
        direction = 0u; /* forward: Table 1 order */
    } else if (previous == (uint8_t)((sector + 1u) % 6u)) {
        direction = 1u; /* reverse */
    } else {
        bldc_safe_state(out, sector, BLDC_FLAG_INVALID_HALL);
        return;
    }

    uint32_t period = in->hall_period_ticks;
    uint32_t bus = in->bus_voltage_adc;
    if (period < PERIOD_MIN_TICKS || bus > BUS_CODE_MAX) {
        /* Above the top speed or over-voltage: braking is no longer controlled. */
        bldc_safe_state(out, sector, BLDC_FLAG_INPUT_SATURATED);
        return;
    }
    if (period > PERIOD_MAX_TICKS) {
        period = PERIOD_MAX_TICKS;
        flags |= BLDC_FLAG_INPUT_SATURATED;
    }
    if (bus < BUS_CODE_MIN) {
        bus = BUS_CODE_MIN;
        flags |= BLDC_FLAG_INPUT_SATURATED;
    }
    uint32_t current = 0u;
    if (in->phase_current_adc < CURRENT_OFFSET_CODE) {
        flags |= BLDC_FLAG_INPUT_SATURATED;
    } else {
        current = (uint32_t)in->phase_current_adc - CURRENT_OFFSET_CODE;
        if (current > CURRENT_CODE_MAX) {
            current = CURRENT_CODE_MAX;
            flags |= BLDC_FLAG_INPUT_SATURATED;
        }
    }
    int32_t main_duty = (int32_t)in->main_duty_counts;
    if (main_duty > P_COUNTS) {
        main_duty = P_COUNTS;
        flags |= BLDC_FLAG_INPUT_SATURATED;
    }

    /* X = P 4E/U_d (Eqs. 3, 9), in Q2 counts. */
    const uint32_t tb = period * bus;
    const uint32_t tb_shifted = (tb + 4u) >> TB_SHIFT;
    const uint32_t x_q = divide_rounded(K_XQ, tb_shifted);
    const int32_t x_c = (int32_t)((x_q + 2u) >> X_FRAC_BITS);
    /* P T B K_X_DEN, compared exactly with K_X_NUM: X > P  <=>  4E > U_d. */
    const uint64_t ptb = (uint64_t)tb * K_X_DEN;
    int32_t on;
    int32_t off;
    /* Eq. 18: low speed, turn-on phase fully on and turn-off phase modulated; high
     * speed, turn-off phase off and turn-on phase modulated. */
    if (K_X_NUM > ptb * (uint64_t)P_COUNTS) {
        flags |= BLDC_FLAG_HIGH_SPEED;
        on = clamp_duty(2 * P_COUNTS - x_c);
        off = 0;
    } else {
        on = P_COUNTS;
        off = clamp_duty(P_COUNTS - x_c);
    }

    /* Eq. 20 at the emitted duties: t = K_G I / (B W). */
    uint32_t ticks = period;
    const int32_t w_q = (2 * P_COUNTS + 2 * on - 4 * off) * 4 - (int32_t)x_q;
    if (current == 0u) {
        ticks = 0u;
    } else if (w_q <= 0) {
        flags |= BLDC_FLAG_TIME_CLAMPED; /* the turn-off current never reaches zero */
    } else {
        const uint64_t numerator = (uint64_t)K_GQ * current;
        const uint32_t denominator = bus * (uint32_t)w_q;
        const uint32_t high = (uint32_t)(numerator >> 32);
        const uint32_t shift = (high == 0u) ? 0u : 32u - (uint32_t)__builtin_clz(high);
        const uint32_t low = (uint32_t)numerator;
        const uint32_t num32 = (shift == 0u) ? low : ((low >> shift) | (high << (32u - shift)));
        const uint32_t den32 = denominator >> shift;
        if (den32 == 0u) {
            flags |= BLDC_FLAG_TIME_CLAMPED;
        } else {
            ticks = divide_rounded(num32, den32);
            if (ticks > period) {
                ticks = period;
                flags |= BLDC_FLAG_TIME_CLAMPED;
            }
        }
    }

    out->turn_on_compare = (uint16_t)on;
    out->turn_off_compare = (uint16_t)off;
    out->commutation_ticks = (uint16_t)ticks;
    out->turn_on_switch = bldc_edge_switch[direction][sector][0];
    out->turn_off_switch = bldc_edge_switch[direction][sector][1];
    out->sector = sector;
    out->flags = flags;
}

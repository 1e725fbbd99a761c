/* Generated from template templates/c/bldc_commutation.c.j2 with spec spec/paper_motor_improved_r.yaml (sha256 9f5d9c8963649549b4e129e1bd9cd35baa3c8e343f67f4b67f06c6141ed1f434). Do not edit: regenerate with `bldc-codegen generate spec/paper_motor_improved_r.yaml`. */
#include "bldc_commutation.h"

#define N_X_HIGH 2396667768u /* N_X >> 11, round(K_X 2^7), K_X = 3.834668e+10 */
#define N_X_LOW 1219u /* N_X mod 2^11 */
#define N_X_SHIFT 11u
#define KYX_Q 1891788u /* K_Y / K_X in Q44: Y per unit = x_numerator K_Y/K_X */
#define CURRENT_OFFSET_Q 2048 /* zero current: 2048 codes x 1 */
#define CARRIER_DEN 1u /* N = floor(T CARRIER_DEN / CARRIER_NUM) */
#define CARRIER_NUM 50u /* tau = CARRIER_NUM / CARRIER_DEN = 50 Hall ticks per PWM period */
#define PERIOD_Q 460800 /* P in Q7 counts */
#define RAMP_Q 2796202667u /* (-phi_1/4) / K_rho: the EMF ramp's forcing over rho, per X per tick */
#define GROWTH_Q 694935041u /* hold slope x tau: the held duty sum's growth per carrier period, per X per tick */
#define PHI0 2u /* phi_0 of the spec's EMF at the edge (X phi_0/4) */
#define STEP_DECAY_Q 2516582u /* y_1 = K_rho tau = 1.875000e-02 in Q27: rho x over one PWM period */

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

/* D^(2^k) in Q32 for k = 9 .. 0 (row step: 2^k = 2^9 >> step), D = e^-y_1, y_1 = R tau / (L f_hall) = 1.875000e-02: the turn-off current's decay over 2^k PWM periods */
static const uint32_t bldc_decay[10] = {
    290893u, /* D^512: 512 PWM periods */
    35346494u, /* D^256: 256 PWM periods */
    389630643u, /* D^128: 128 PWM periods */
    1293619290u, /* D^64: 64 PWM periods */
    2357128029u, /* D^32: 32 PWM periods */
    3181790030u, /* D^16: 16 PWM periods */
    3696712610u, /* D^8: 8 PWM periods */
    3984627933u, /* D^4: 4 PWM periods */
    4136888524u, /* D^2: 2 PWM periods */
    4215186937u, /* D^1: 1 PWM periods */
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
    const uint32_t xn = bldc_divide_long(N_X_HIGH, N_X_LOW, N_X_SHIFT, code); /* round(N_X / B) */
    const uint32_t yn = (uint32_t)(((uint64_t)xn * (uint64_t)KYX_Q + 1073741824ull) >> 31u); /* Y per unit of current */
    const bldc_bus_t bus = {
        .x_numerator = xn,
        .y_numerator = yn,
        .a_numerator = yn,
        .period_min = period_min,
        .bus_code = code,
        .flags = flags,
    };
    return bus;
}

/* Duties and commutation time of the resistance-aware rule (pure, reentrant); any uint32_t value of each parameter is allowed. The rule holds the current by itself: the main duty is not used */
bldc_timing_t bldc_commutation_timing(const bldc_bus_t *bus, uint32_t period_ticks, uint32_t current_adc, uint32_t main_duty_counts)
{
    (void)main_duty_counts; /* not used by this method */
    uint32_t flags = bus->flags;
    const uint32_t measured = (period_ticks > BLDC_PERIOD_CAP_TICKS) ? BLDC_PERIOD_CAP_TICKS : period_ticks; /* the Hall counter's range */
    if (measured < bus->period_min) { /* above the top speed or over-voltage: braking is no longer controlled */
        const bldc_timing_t safe = {
            .period_min = BLDC_PERIOD_NEVER,
            .turn_on_compare = 0u,
            .turn_off_compare = 0u,
            .commutation_ticks = 0u,
            .flags = (uint16_t)(flags | BLDC_FLAG_INPUT_SATURATED),
        };
        return safe;
    }
    if (measured > BLDC_PERIOD_MAX_TICKS) { /* below the minimum speed */
        flags |= BLDC_FLAG_INPUT_SATURATED;
    }
    const uint32_t period = (measured > BLDC_PERIOD_MAX_TICKS) ? BLDC_PERIOD_MAX_TICKS : measured; /* the rule's constants cover the speed range */
    const uint32_t latest = measured * 15u / 16u - BLDC_COMMUTATION_GUARD_TICKS; /* the latest end: the guard and the sector-shortening margin before the sector's end (positive from the minimum period on), so the next edge, up to hall.sector_shortening early, switches the other switch of the leg on at least the dead time after this end switched its partner off */
    const uint32_t current_code = (current_adc > BLDC_ADC_CODE_MAX) ? BLDC_ADC_CODE_MAX : current_adc; /* above the ADC's range: full scale */
    if (current_adc < BLDC_CURRENT_CODE_LOW || current_adc > BLDC_CURRENT_CODE_HIGH) { /* outside the braking-current range */
        flags |= BLDC_FLAG_INPUT_SATURATED;
    }
    const int32_t current = (int32_t)current_code - CURRENT_OFFSET_Q; /* I in codes, offset removed */
    const uint32_t i = (uint32_t)((current < 0) ? 0 : current); /* negative currents count as 0 */
    const uint32_t x = (bus->x_numerator + (period >> 1)) / period; /* X in Q7 counts */
    const uint32_t y = (bus->y_numerator * i + 4096u) >> 13u; /* Y = 3 P R I / U_d, Q7 */
    const uint32_t a_rho = y; /* A rho = 3 P R I / U_d x (L / (R T_s)) rho: the current at the edge, Q7 (= Y: the same constant and format) */
    const uint32_t periods = (period * 15u / 16u - BLDC_COMMUTATION_GUARD_TICKS) * CARRIER_DEN / CARRIER_NUM; /* N: whole PWM periods in the sector, less the guard and the margin at its end */
    const int32_t sigma0 = 2 * PERIOD_Q + (int32_t)y - (int32_t)x; /* Sigma(0) = 2P + Y - (sigma_0/4) X: the held duty sum at the edge's EMFs */
    const uint32_t per_tick = bldc_divide_long(x, 0u, 15u, period); /* X / T in Q22 */
    const uint32_t q = (uint32_t)(((uint64_t)per_tick * (uint64_t)RAMP_Q) >> 30u); /* q = (-phi_1/4) X / rho: the EMF ramp's forcing, Q12 */
    const uint32_t growth = (uint32_t)(((uint64_t)per_tick * (uint64_t)GROWTH_Q) >> 32u); /* the held sum's growth per PWM period, Q16 */
    const int32_t ca2 = 2 * ((int32_t)a_rho - (int32_t)((q + 16u) >> 5u) - (int32_t)((x * PHI0 + 2u) >> 2u)); /* 2 (A rho - q - (phi_0/4) X) */
    const int32_t cb = (int32_t)((x * PHI0 + 2u) >> 2u) + (int32_t)((q + 16u) >> 5u); /* (phi_0/4) X + q */
    const int32_t skipped = 10 - (int32_t)(32u - (uint32_t)__builtin_clz((periods < 1u) ? 1u : periods)); /* the steps whose 2^k is past the sector */
    const uint32_t first = (uint32_t)((skipped < 0) ? 0 : skipped); /* the first step whose 2^k fits in the sector: 2^9 >> step <= N (a larger candidate is past the sector, from n = 0: the same result, fewer steps) */
    uint32_t n = 0u;
    uint32_t e = 2147483648u;
    int64_t end_h = (-1ll);
    uint32_t end_e = 0u;
    /*@ loop invariant step_kept: 0 <= step <= 10; loop invariant n_kept: 0 <= n <= 936; loop invariant e_kept: 0 <= e <= 2147483648; loop invariant end_h_kept: -9223372036854775807 <= end_h <= -1; loop invariant end_e_kept: 0 <= end_e <= 2107593468; loop assigns n, e, end_h, end_e, step; loop variant 10 - step; */
    for (uint32_t step = first; step < 10u; ++step) { /* binary lifting: n = the last carrier boundary at which the current remains */
        const uint32_t m = n + (512u >> step); /* the next candidate: n + 2^k, 2^k = 2^9 >> step */
        if (m <= periods) {
            const uint32_t em = (uint32_t)(((uint64_t)e * (uint64_t)bldc_decay[step]) >> 32u); /* e^-rho x_m in Q31 */
            const int32_t total = sigma0 + (int32_t)((growth * m) >> 9u); /* Sigma at m: the held duty sum */
            const int32_t held = (total < 0) ? 0 : (total > 2 * PERIOD_Q) ? 2 * PERIOD_Q : total; /* the duties' range: C_on + C_off in [0, 2P] */
            const int32_t fd = 3 * ((held - PERIOD_Q < 0) ? 0 : held - PERIOD_Q) - held - PERIOD_Q; /* F_d = 2 C_off - C_on - P = 3 C_off - (C_on + C_off) - P of the split */
            const int64_t h = (int64_t)(ca2 - 2 * fd) * (int64_t)(int32_t)em + (int64_t)(fd + cb) * 4294967296ll - (int64_t)((uint64_t)q * (uint64_t)(STEP_DECAY_Q * m)); /* 2^(32+fc) rho g at m */
            if (h >= 0ll) { /* the turn-off current has not reached zero at m (else: the last candidate refused is n + 1, the end) */
                n = m;
                e = em;
            } else {
                end_h = h;
                end_e = em;
            }
        }
    }
    const uint32_t end = (n + 1u > periods) ? periods : n + 1u; /* the first carrier boundary with the current at zero (or the sector's last) */
    const int32_t end_total = sigma0 + (int32_t)((growth * end) >> 9u); /* Sigma at the end: the held duty sum */
    const int32_t end_held = (end_total < 0) ? 0 : (end_total > 2 * PERIOD_Q) ? 2 * PERIOD_Q : end_total; /* C_on + C_off in [0, 2P] */
    const int32_t end_on = (end_held > PERIOD_Q) ? PERIOD_Q : end_held;
    const int32_t end_off = (end_held - PERIOD_Q < 0) ? 0 : end_held - PERIOD_Q;
    const int32_t room = (end_on > PERIOD_Q - end_off) ? PERIOD_Q - end_off : end_on; /* what the split can give: C_on down to 0, C_off up to P */
    const uint32_t shortfall = 3u * ((2147483648u - end_e) >> 9u); /* 3 (1 - e) in Q22 */
    const uint64_t overshoot = (uint64_t)(0ll - end_h) >> 11u; /* -rho g / 3 in Q28, > 0 */
    const uint64_t cap = (uint64_t)((uint32_t)(room >> 1u) + 1u) * (uint64_t)shortfall; /* (room + 1) 3 (1 - e): a larger easing is cut to the room below */
    const uint64_t numerator = (overshoot > cap) ? cap : overshoot; /* the overshoot, at most the cap (it never binds sooner than the room) */
    const uint32_t eased_upper = (uint32_t)(numerator >> 16u); /* numerator / 2^16 */
    const uint32_t eased_middle = ((eased_upper % shortfall) << 8u) + (uint32_t)((numerator >> 8u) & 255ull); /* the remainder, then the next byte */
    const uint32_t eased_lower = ((eased_middle % shortfall) << 8u) + (uint32_t)(numerator & 255ull); /* the remainder, then the last byte */
    const uint32_t eased = (((eased_upper / shortfall > 3u) ? 3u : eased_upper / shortfall) << 16u) + (((eased_middle / shortfall > 255u) ? 255u : eased_middle / shortfall) << 8u) + (((eased_lower + (shortfall >> 1)) / shortfall > 256u) ? 256u : (eased_lower + (shortfall >> 1)) / shortfall); /* delta = -rho g / (3 (1 - e)) in Q6: ends the current at the boundary (at most room + 1: the numerator's cap) */
    const int32_t delta = (((int32_t)((eased > 1073741823u) ? 1073741823u : eased) > room >> 1u) ? room >> 1u : (int32_t)((eased > 1073741823u) ? 1073741823u : eased)) << 1u; /* the easing in Q7, at most the room */
    const int32_t eased_on = end_on - delta; /* C_on - delta */
    const int32_t eased_off = end_off + delta; /* C_off + delta */
    const uint32_t on = (uint32_t)((eased_on < 0) ? 0 : eased_on); /* delta <= the room: never below 0 */
    const uint32_t off = (uint32_t)((eased_off > PERIOD_Q) ? PERIOD_Q : eased_off); /* never above P */
    if (n >= periods) { /* the current remains at every carrier boundary */
        flags |= BLDC_FLAG_TIME_CLAMPED;
    }
    if (end_total > 2 * PERIOD_Q || end_total < 0) { /* no duty pair in [0, 1] holds the current */
        flags |= BLDC_FLAG_FAIL_AREA_CLAMPED;
    }
    if (end_total < PERIOD_Q) { /* the upper segment: the turn-off phase at most eased, the turn-on one modulated */
        flags |= BLDC_FLAG_HIGH_SPEED;
    }
    const uint32_t ticks = (n >= periods) ? latest : (end * CARRIER_NUM + 0u) / CARRIER_DEN; /* round(end tau), a carrier boundary; the whole sector less the guard when the current remains */
    const bldc_timing_t timing = {
        .period_min = bus->period_min,
        .turn_on_compare = (uint16_t)((on + 64u) >> 7u),
        .turn_off_compare = (uint16_t)((off + 64u) >> 7u),
        .commutation_ticks = (uint16_t)((ticks > latest) ? latest : ticks),
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

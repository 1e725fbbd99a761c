/* Generated from template templates/c/bldc_current_loop.c.j2 with spec spec/example_maxon_ec45_flat_48v.yaml (sha256 4e4bc402b3ee91505838c88f91659557d0005f5a8b56d60c19ecc3e2f665b3c6). Do not edit: regenerate with `bldc-codegen generate spec/example_maxon_ec45_flat_48v.yaml`. */
#include "bldc_current_loop.h"

/* the nearest ADC code of a braking current in mA, clamped to the spec's braking range */
uint32_t bldc_current_reference(uint32_t milliamps)
{
    const uint32_t held = (milliamps > BLDC_LOOP_MA_MAX) ? BLDC_LOOP_MA_MAX : milliamps; /* the spec's braking range */
    const uint64_t scaled = (uint64_t)held * BLDC_LOOP_REF_SCALE + BLDC_LOOP_REF_OFFSET;
    return (uint32_t)((scaled + 16777216ull) >> 25u);
}

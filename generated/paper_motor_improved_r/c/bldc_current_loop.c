/* Generated from template templates/c/bldc_current_loop.c.j2 with spec spec/paper_motor_improved_r.yaml (sha256 9f5d9c8963649549b4e129e1bd9cd35baa3c8e343f67f4b67f06c6141ed1f434). Do not edit: regenerate with `bldc-codegen generate spec/paper_motor_improved_r.yaml`. */
#include "bldc_current_loop.h"

/* the nearest ADC code of a braking current in mA, clamped to the spec's braking range */
uint32_t bldc_current_reference(uint32_t milliamps)
{
    const uint32_t held = (milliamps > BLDC_LOOP_MA_MAX) ? BLDC_LOOP_MA_MAX : milliamps; /* the spec's braking range */
    const uint64_t scaled = (uint64_t)held * BLDC_LOOP_REF_SCALE + BLDC_LOOP_REF_OFFSET;
    return (uint32_t)((scaled + 67108864ull) >> 27u);
}

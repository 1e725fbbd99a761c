/* Generated from template templates/proof/harness.c.j2 with spec spec/paper_motor_improved_r.yaml (sha256 9f5d9c8963649549b4e129e1bd9cd35baa3c8e343f67f4b67f06c6141ed1f434). Do not edit: regenerate with `bldc-codegen generate spec/paper_motor_improved_r.yaml`. */
/*
 * Frama-C EVA harness of this core and the current loop (`make prove`;
 * codegen/proof/harness.py explains it).
 * Each prove_<function>() gives every parameter, or every field of an input struct,
 * every value of its C type: nothing is assumed away. The `split` annotations only
 * partition that input space so EVA keeps the partitions apart; they cover it whole.
 * Partitioning: the IR's interval proof keeps every compare value within the PWM period.
 * Analysed only by Frama-C: not part of the firmware.
 */
#include <stdint.h>

#include "__fc_builtin.h"
#include "bldc_commutation.h"
#include "bldc_current_loop.h"

/* __builtin_clz as the Cortex-M3's CLZ computes it for a non-zero argument (GCC
 * leaves 0 undefined: required). Frama-C's declaration only bounds the result to
 * [0, 31]; this definition gives EVA the exact count. */
/*@ requires nonzero: x != 0;
    assigns \nothing;
    ensures leading_zeros: x >> (31 - \result) == 1;
*/
int __builtin_clz(unsigned int x)
{
    if (x >= 2147483648u) {
        return 0;
    }
    if (x >= 1073741824u) {
        return 1;
    }
    if (x >= 536870912u) {
        return 2;
    }
    if (x >= 268435456u) {
        return 3;
    }
    if (x >= 134217728u) {
        return 4;
    }
    if (x >= 67108864u) {
        return 5;
    }
    if (x >= 33554432u) {
        return 6;
    }
    if (x >= 16777216u) {
        return 7;
    }
    if (x >= 8388608u) {
        return 8;
    }
    if (x >= 4194304u) {
        return 9;
    }
    if (x >= 2097152u) {
        return 10;
    }
    if (x >= 1048576u) {
        return 11;
    }
    if (x >= 524288u) {
        return 12;
    }
    if (x >= 262144u) {
        return 13;
    }
    if (x >= 131072u) {
        return 14;
    }
    if (x >= 65536u) {
        return 15;
    }
    if (x >= 32768u) {
        return 16;
    }
    if (x >= 16384u) {
        return 17;
    }
    if (x >= 8192u) {
        return 18;
    }
    if (x >= 4096u) {
        return 19;
    }
    if (x >= 2048u) {
        return 20;
    }
    if (x >= 1024u) {
        return 21;
    }
    if (x >= 512u) {
        return 22;
    }
    if (x >= 256u) {
        return 23;
    }
    if (x >= 128u) {
        return 24;
    }
    if (x >= 64u) {
        return 25;
    }
    if (x >= 32u) {
        return 26;
    }
    if (x >= 16u) {
        return 27;
    }
    if (x >= 8u) {
        return 28;
    }
    if (x >= 4u) {
        return 29;
    }
    if (x >= 2u) {
        return 30;
    }
    return 31;
}

/* bldc_bus_condition() for every uint32_t bus code, code by code */
void prove_bldc_bus_condition(void)
{
    uint32_t bus_code = Frama_C_unsigned_int_interval(0u, 4294967295u);
    /* one partition below BLDC_BUS_CODE_MIN, one above BLDC_BUS_CODE_MAX, one per code between */
    //@ split bus_code < BLDC_BUS_CODE_MIN;
    //@ split bus_code > BLDC_BUS_CODE_MAX;
    if (bus_code >= BLDC_BUS_CODE_MIN) {
        if (bus_code <= BLDC_BUS_CODE_MAX) {
            /*@ split bus_code; */ /*@ ghost ; */
        }
    }
    const bldc_bus_t bus = bldc_bus_condition(bus_code);
    (void)bus;
}

/* bldc_commutation_timing() for a bus state of every uint32_t code and every uint32_t period, current and duty */
void prove_bldc_commutation_timing(void)
{
    uint32_t period_ticks = Frama_C_unsigned_int_interval(0u, 4294967295u);
    uint32_t current_adc = Frama_C_unsigned_int_interval(0u, 4294967295u);
    uint32_t main_duty_counts = Frama_C_unsigned_int_interval(0u, 4294967295u);
    uint32_t bus_code = Frama_C_unsigned_int_interval(0u, 4294967295u);
    const bldc_bus_t bus = bldc_bus_condition(bus_code);
    const bldc_timing_t timing = bldc_commutation_timing(&bus, period_ticks, current_adc, main_duty_counts);
    (void)timing;
}

/* bldc_edge_of() for every pair of arguments */
void prove_bldc_edge_of(void)
{
    uint32_t previous_hall_code = Frama_C_unsigned_int_interval(0u, 4294967295u);
    /* one partition per value of [0, 7], one for the rest */
    //@ split previous_hall_code <= 7u;
    if (previous_hall_code <= 7u) {
        /*@ split previous_hall_code; */ /*@ ghost ; */
    }
    uint32_t hall_code = Frama_C_unsigned_int_interval(0u, 4294967295u);
    /* one partition per value of [0, 7], one for the rest */
    //@ split hall_code <= 7u;
    if (hall_code <= 7u) {
        /*@ split hall_code; */ /*@ ghost ; */
    }
    const uint32_t result = bldc_edge_of(previous_hall_code, hall_code);
    (void)result;
}

/* bldc_commutate() for every value of every input field */
void prove_bldc_commutate(void)
{
    bldc_inputs_t inputs;
    inputs.hall_code = Frama_C_unsigned_char_interval(0u, 255u);
    inputs.previous_hall_code = Frama_C_unsigned_char_interval(0u, 255u);
    inputs.hall_period_ticks = Frama_C_unsigned_short_interval(0u, 65535u);
    inputs.bus_voltage_adc = Frama_C_unsigned_short_interval(0u, 65535u);
    inputs.phase_current_adc = Frama_C_unsigned_short_interval(0u, 65535u);
    inputs.main_duty_counts = Frama_C_unsigned_short_interval(0u, 65535u);
    bldc_outputs_t out;
    bldc_commutate(&inputs, &out);
}

/* bldc_current_loop_duty() for every value of its arguments */
void prove_bldc_current_loop_duty(void)
{
    int32_t integrator = Frama_C_int_interval(-2147483647 - 1, 2147483647);
    uint32_t reference_code = Frama_C_unsigned_int_interval(0u, 4294967295u);
    uint32_t measured_code = Frama_C_unsigned_int_interval(0u, 4294967295u);
    const uint32_t result = bldc_current_loop_duty(integrator, reference_code, measured_code);
    (void)result;
}

/* bldc_current_loop_integrate() for every value of its arguments */
void prove_bldc_current_loop_integrate(void)
{
    int32_t integrator = Frama_C_int_interval(-2147483647 - 1, 2147483647);
    uint32_t reference_code = Frama_C_unsigned_int_interval(0u, 4294967295u);
    uint32_t measured_code = Frama_C_unsigned_int_interval(0u, 4294967295u);
    const int32_t result = bldc_current_loop_integrate(integrator, reference_code, measured_code);
    (void)result;
}

/* bldc_current_reference() for every value of its arguments */
void prove_bldc_current_reference(void)
{
    uint32_t milliamps = Frama_C_unsigned_int_interval(0u, 4294967295u);
    const uint32_t result = bldc_current_reference(milliamps);
    (void)result;
}

/* Generated from template templates/proof/harness.c.j2 with spec spec/paper_motor.yaml (sha256 6e149e81b56aaf0ac5791d1ff3459c01b1ba7fdb119982156e9fd60cd3b42049). Do not edit: regenerate with `bldc-codegen generate spec/paper_motor.yaml`. */
/*
 * Frama-C EVA harness of this core and the current loop (`make prove`;
 * codegen/proof/harness.py explains it).
 * Each prove_<function>() gives every parameter, or every field of an input struct,
 * every value of its C type: nothing is assumed away. The `split` annotations only
 * partition that input space so EVA keeps the partitions apart; they cover it whole.
 * Partitioning: the IR's interval proof leaves timing.turn_on_compare in [0, 7027], above the PWM period 3600: a relational contract, so one partition per bus code and the period split at bus.high_speed_period.
 * Analysed only by Frama-C: not part of the firmware.
 */
#include <stdint.h>

#include "__fc_builtin.h"
#include "bldc_commutation.h"
#include "bldc_current_loop.h"

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
    /* one partition below BLDC_BUS_CODE_MIN, one above BLDC_BUS_CODE_MAX, one per code between */
    //@ split bus_code < BLDC_BUS_CODE_MIN;
    //@ split bus_code > BLDC_BUS_CODE_MAX;
    if (bus_code >= BLDC_BUS_CODE_MIN) {
        if (bus_code <= BLDC_BUS_CODE_MAX) {
            /*@ split bus_code; */ /*@ ghost ; */
        }
    }
    const bldc_bus_t bus = bldc_bus_condition(bus_code);
    bldc_timing_t timing;
    //@ split period_ticks < bus.high_speed_period;
    timing = bldc_commutation_timing(&bus, period_ticks, current_adc, main_duty_counts);
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

/* Generated from template templates/unity/test_bldc_commutation.c.j2 with spec spec/paper_motor.yaml (sha256 6e149e81b56aaf0ac5791d1ff3459c01b1ba7fdb119982156e9fd60cd3b42049). Do not edit: regenerate with `bldc-codegen generate spec/paper_motor.yaml`. */
/*
 * Unity tests of bldc_commutate(), one per vector of the independent oracle
 * (codegen/unity_cases.py, oracle/). The compare values and the commutation time may
 * differ from the exact values by the spec's accuracy targets (never the design's own
 * bounds); the transistors, the sector and every decided flag must match exactly. Only the public API of bldc_commutation.h is
 * used, so the tests hold for any implementation of the core.
 */
#include "bldc_commutation.h"
#include "unity.h"

void setUp(void)
{
}

void tearDown(void)
{
}

/* forward edge into sector 0 at 1500 rpm: Eqs. 16/18 duties, Eq. 20 time */
void test_bldc_commutate_should_commutate_forward_into_sector_0_at_1500_rpm(void)
{
    const bldc_inputs_t in = {
        .hall_code = 5u, /* Hall 101 */
        .previous_hall_code = 1u, /* Hall 001 */
        .hall_period_ticks = 6667u,
        .bus_voltage_adc = 2708u,
        .phase_current_adc = 2358u,
        .main_duty_counts = 1512u,
    };
    bldc_outputs_t out = { /* poison: every field must be overwritten by the core */
        .turn_on_compare = 0xA5A5u,
        .turn_off_compare = 0xA5A5u,
        .commutation_ticks = 0xA5A5u,
        .turn_on_switch = 0xA5u,
        .turn_off_switch = 0xA5u,
        .sector = 0xA5u,
        .flags = 0xA5u,
    };

    bldc_commutate(&in, &out);

    TEST_ASSERT_UINT16_WITHIN(1u, 3600u, out.turn_on_compare);
    TEST_ASSERT_UINT16_WITHIN(1u, 1476u, out.turn_off_compare);
    TEST_ASSERT_UINT16_WITHIN(8u, 395u, out.commutation_ticks);
    TEST_ASSERT_EQUAL_HEX8(0x01u, out.turn_on_switch); /* T2 */
    TEST_ASSERT_EQUAL_HEX8(0x05u, out.turn_off_switch); /* T6 */
    TEST_ASSERT_EQUAL_HEX8(0x00u, out.sector);
    TEST_ASSERT_EQUAL_HEX8(0x00u, out.flags);
}

/* forward edge into sector 1 at 1500 rpm: Eqs. 16/18 duties, Eq. 20 time */
void test_bldc_commutate_should_commutate_forward_into_sector_1_at_1500_rpm(void)
{
    const bldc_inputs_t in = {
        .hall_code = 4u, /* Hall 100 */
        .previous_hall_code = 5u, /* Hall 101 */
        .hall_period_ticks = 6667u,
        .bus_voltage_adc = 2708u,
        .phase_current_adc = 2358u,
        .main_duty_counts = 1512u,
    };
    bldc_outputs_t out = { /* poison: every field must be overwritten by the core */
        .turn_on_compare = 0xA5A5u,
        .turn_off_compare = 0xA5A5u,
        .commutation_ticks = 0xA5A5u,
        .turn_on_switch = 0xA5u,
        .turn_off_switch = 0xA5u,
        .sector = 0xA5u,
        .flags = 0xA5u,
    };

    bldc_commutate(&in, &out);

    TEST_ASSERT_UINT16_WITHIN(1u, 3600u, out.turn_on_compare);
    TEST_ASSERT_UINT16_WITHIN(1u, 1476u, out.turn_off_compare);
    TEST_ASSERT_UINT16_WITHIN(8u, 395u, out.commutation_ticks);
    TEST_ASSERT_EQUAL_HEX8(0x04u, out.turn_on_switch); /* T5 */
    TEST_ASSERT_EQUAL_HEX8(0x02u, out.turn_off_switch); /* T3 */
    TEST_ASSERT_EQUAL_HEX8(0x01u, out.sector);
    TEST_ASSERT_EQUAL_HEX8(0x00u, out.flags);
}

/* forward edge into sector 2 at 1500 rpm: Eqs. 16/18 duties, Eq. 20 time */
void test_bldc_commutate_should_commutate_forward_into_sector_2_at_1500_rpm(void)
{
    const bldc_inputs_t in = {
        .hall_code = 6u, /* Hall 110 */
        .previous_hall_code = 4u, /* Hall 100 */
        .hall_period_ticks = 6667u,
        .bus_voltage_adc = 2708u,
        .phase_current_adc = 2358u,
        .main_duty_counts = 1512u,
    };
    bldc_outputs_t out = { /* poison: every field must be overwritten by the core */
        .turn_on_compare = 0xA5A5u,
        .turn_off_compare = 0xA5A5u,
        .commutation_ticks = 0xA5A5u,
        .turn_on_switch = 0xA5u,
        .turn_off_switch = 0xA5u,
        .sector = 0xA5u,
        .flags = 0xA5u,
    };

    bldc_commutate(&in, &out);

    TEST_ASSERT_UINT16_WITHIN(1u, 3600u, out.turn_on_compare);
    TEST_ASSERT_UINT16_WITHIN(1u, 1476u, out.turn_off_compare);
    TEST_ASSERT_UINT16_WITHIN(8u, 395u, out.commutation_ticks);
    TEST_ASSERT_EQUAL_HEX8(0x03u, out.turn_on_switch); /* T4 */
    TEST_ASSERT_EQUAL_HEX8(0x01u, out.turn_off_switch); /* T2 */
    TEST_ASSERT_EQUAL_HEX8(0x02u, out.sector);
    TEST_ASSERT_EQUAL_HEX8(0x00u, out.flags);
}

/* forward edge into sector 3 at 1500 rpm: Eqs. 16/18 duties, Eq. 20 time */
void test_bldc_commutate_should_commutate_forward_into_sector_3_at_1500_rpm(void)
{
    const bldc_inputs_t in = {
        .hall_code = 2u, /* Hall 010 */
        .previous_hall_code = 6u, /* Hall 110 */
        .hall_period_ticks = 6667u,
        .bus_voltage_adc = 2708u,
        .phase_current_adc = 2358u,
        .main_duty_counts = 1512u,
    };
    bldc_outputs_t out = { /* poison: every field must be overwritten by the core */
        .turn_on_compare = 0xA5A5u,
        .turn_off_compare = 0xA5A5u,
        .commutation_ticks = 0xA5A5u,
        .turn_on_switch = 0xA5u,
        .turn_off_switch = 0xA5u,
        .sector = 0xA5u,
        .flags = 0xA5u,
    };

    bldc_commutate(&in, &out);

    TEST_ASSERT_UINT16_WITHIN(1u, 3600u, out.turn_on_compare);
    TEST_ASSERT_UINT16_WITHIN(1u, 1476u, out.turn_off_compare);
    TEST_ASSERT_UINT16_WITHIN(8u, 395u, out.commutation_ticks);
    TEST_ASSERT_EQUAL_HEX8(0x00u, out.turn_on_switch); /* T1 */
    TEST_ASSERT_EQUAL_HEX8(0x04u, out.turn_off_switch); /* T5 */
    TEST_ASSERT_EQUAL_HEX8(0x03u, out.sector);
    TEST_ASSERT_EQUAL_HEX8(0x00u, out.flags);
}

/* forward edge into sector 4 at 1500 rpm: Eqs. 16/18 duties, Eq. 20 time */
void test_bldc_commutate_should_commutate_forward_into_sector_4_at_1500_rpm(void)
{
    const bldc_inputs_t in = {
        .hall_code = 3u, /* Hall 011 */
        .previous_hall_code = 2u, /* Hall 010 */
        .hall_period_ticks = 6667u,
        .bus_voltage_adc = 2708u,
        .phase_current_adc = 2358u,
        .main_duty_counts = 1512u,
    };
    bldc_outputs_t out = { /* poison: every field must be overwritten by the core */
        .turn_on_compare = 0xA5A5u,
        .turn_off_compare = 0xA5A5u,
        .commutation_ticks = 0xA5A5u,
        .turn_on_switch = 0xA5u,
        .turn_off_switch = 0xA5u,
        .sector = 0xA5u,
        .flags = 0xA5u,
    };

    bldc_commutate(&in, &out);

    TEST_ASSERT_UINT16_WITHIN(1u, 3600u, out.turn_on_compare);
    TEST_ASSERT_UINT16_WITHIN(1u, 1476u, out.turn_off_compare);
    TEST_ASSERT_UINT16_WITHIN(8u, 395u, out.commutation_ticks);
    TEST_ASSERT_EQUAL_HEX8(0x05u, out.turn_on_switch); /* T6 */
    TEST_ASSERT_EQUAL_HEX8(0x03u, out.turn_off_switch); /* T4 */
    TEST_ASSERT_EQUAL_HEX8(0x04u, out.sector);
    TEST_ASSERT_EQUAL_HEX8(0x00u, out.flags);
}

/* forward edge into sector 5 at 1500 rpm: Eqs. 16/18 duties, Eq. 20 time */
void test_bldc_commutate_should_commutate_forward_into_sector_5_at_1500_rpm(void)
{
    const bldc_inputs_t in = {
        .hall_code = 1u, /* Hall 001 */
        .previous_hall_code = 3u, /* Hall 011 */
        .hall_period_ticks = 6667u,
        .bus_voltage_adc = 2708u,
        .phase_current_adc = 2358u,
        .main_duty_counts = 1512u,
    };
    bldc_outputs_t out = { /* poison: every field must be overwritten by the core */
        .turn_on_compare = 0xA5A5u,
        .turn_off_compare = 0xA5A5u,
        .commutation_ticks = 0xA5A5u,
        .turn_on_switch = 0xA5u,
        .turn_off_switch = 0xA5u,
        .sector = 0xA5u,
        .flags = 0xA5u,
    };

    bldc_commutate(&in, &out);

    TEST_ASSERT_UINT16_WITHIN(1u, 3600u, out.turn_on_compare);
    TEST_ASSERT_UINT16_WITHIN(1u, 1476u, out.turn_off_compare);
    TEST_ASSERT_UINT16_WITHIN(8u, 395u, out.commutation_ticks);
    TEST_ASSERT_EQUAL_HEX8(0x02u, out.turn_on_switch); /* T3 */
    TEST_ASSERT_EQUAL_HEX8(0x00u, out.turn_off_switch); /* T1 */
    TEST_ASSERT_EQUAL_HEX8(0x05u, out.sector);
    TEST_ASSERT_EQUAL_HEX8(0x00u, out.flags);
}

/* reverse edge into sector 0 at 1500 rpm: Eqs. 16/18 duties, Eq. 20 time */
void test_bldc_commutate_should_commutate_reverse_into_sector_0_at_1500_rpm(void)
{
    const bldc_inputs_t in = {
        .hall_code = 5u, /* Hall 101 */
        .previous_hall_code = 4u, /* Hall 100 */
        .hall_period_ticks = 6667u,
        .bus_voltage_adc = 2708u,
        .phase_current_adc = 2358u,
        .main_duty_counts = 1512u,
    };
    bldc_outputs_t out = { /* poison: every field must be overwritten by the core */
        .turn_on_compare = 0xA5A5u,
        .turn_off_compare = 0xA5A5u,
        .commutation_ticks = 0xA5A5u,
        .turn_on_switch = 0xA5u,
        .turn_off_switch = 0xA5u,
        .sector = 0xA5u,
        .flags = 0xA5u,
    };

    bldc_commutate(&in, &out);

    TEST_ASSERT_UINT16_WITHIN(1u, 3600u, out.turn_on_compare);
    TEST_ASSERT_UINT16_WITHIN(1u, 1476u, out.turn_off_compare);
    TEST_ASSERT_UINT16_WITHIN(8u, 395u, out.commutation_ticks);
    TEST_ASSERT_EQUAL_HEX8(0x03u, out.turn_on_switch); /* T4 */
    TEST_ASSERT_EQUAL_HEX8(0x05u, out.turn_off_switch); /* T6 */
    TEST_ASSERT_EQUAL_HEX8(0x00u, out.sector);
    TEST_ASSERT_EQUAL_HEX8(0x00u, out.flags);
}

/* reverse edge into sector 1 at 1500 rpm: Eqs. 16/18 duties, Eq. 20 time */
void test_bldc_commutate_should_commutate_reverse_into_sector_1_at_1500_rpm(void)
{
    const bldc_inputs_t in = {
        .hall_code = 4u, /* Hall 100 */
        .previous_hall_code = 6u, /* Hall 110 */
        .hall_period_ticks = 6667u,
        .bus_voltage_adc = 2708u,
        .phase_current_adc = 2358u,
        .main_duty_counts = 1512u,
    };
    bldc_outputs_t out = { /* poison: every field must be overwritten by the core */
        .turn_on_compare = 0xA5A5u,
        .turn_off_compare = 0xA5A5u,
        .commutation_ticks = 0xA5A5u,
        .turn_on_switch = 0xA5u,
        .turn_off_switch = 0xA5u,
        .sector = 0xA5u,
        .flags = 0xA5u,
    };

    bldc_commutate(&in, &out);

    TEST_ASSERT_UINT16_WITHIN(1u, 3600u, out.turn_on_compare);
    TEST_ASSERT_UINT16_WITHIN(1u, 1476u, out.turn_off_compare);
    TEST_ASSERT_UINT16_WITHIN(8u, 395u, out.commutation_ticks);
    TEST_ASSERT_EQUAL_HEX8(0x00u, out.turn_on_switch); /* T1 */
    TEST_ASSERT_EQUAL_HEX8(0x02u, out.turn_off_switch); /* T3 */
    TEST_ASSERT_EQUAL_HEX8(0x01u, out.sector);
    TEST_ASSERT_EQUAL_HEX8(0x00u, out.flags);
}

/* reverse edge into sector 2 at 1500 rpm: Eqs. 16/18 duties, Eq. 20 time */
void test_bldc_commutate_should_commutate_reverse_into_sector_2_at_1500_rpm(void)
{
    const bldc_inputs_t in = {
        .hall_code = 6u, /* Hall 110 */
        .previous_hall_code = 2u, /* Hall 010 */
        .hall_period_ticks = 6667u,
        .bus_voltage_adc = 2708u,
        .phase_current_adc = 2358u,
        .main_duty_counts = 1512u,
    };
    bldc_outputs_t out = { /* poison: every field must be overwritten by the core */
        .turn_on_compare = 0xA5A5u,
        .turn_off_compare = 0xA5A5u,
        .commutation_ticks = 0xA5A5u,
        .turn_on_switch = 0xA5u,
        .turn_off_switch = 0xA5u,
        .sector = 0xA5u,
        .flags = 0xA5u,
    };

    bldc_commutate(&in, &out);

    TEST_ASSERT_UINT16_WITHIN(1u, 3600u, out.turn_on_compare);
    TEST_ASSERT_UINT16_WITHIN(1u, 1476u, out.turn_off_compare);
    TEST_ASSERT_UINT16_WITHIN(8u, 395u, out.commutation_ticks);
    TEST_ASSERT_EQUAL_HEX8(0x05u, out.turn_on_switch); /* T6 */
    TEST_ASSERT_EQUAL_HEX8(0x01u, out.turn_off_switch); /* T2 */
    TEST_ASSERT_EQUAL_HEX8(0x02u, out.sector);
    TEST_ASSERT_EQUAL_HEX8(0x00u, out.flags);
}

/* reverse edge into sector 3 at 1500 rpm: Eqs. 16/18 duties, Eq. 20 time */
void test_bldc_commutate_should_commutate_reverse_into_sector_3_at_1500_rpm(void)
{
    const bldc_inputs_t in = {
        .hall_code = 2u, /* Hall 010 */
        .previous_hall_code = 3u, /* Hall 011 */
        .hall_period_ticks = 6667u,
        .bus_voltage_adc = 2708u,
        .phase_current_adc = 2358u,
        .main_duty_counts = 1512u,
    };
    bldc_outputs_t out = { /* poison: every field must be overwritten by the core */
        .turn_on_compare = 0xA5A5u,
        .turn_off_compare = 0xA5A5u,
        .commutation_ticks = 0xA5A5u,
        .turn_on_switch = 0xA5u,
        .turn_off_switch = 0xA5u,
        .sector = 0xA5u,
        .flags = 0xA5u,
    };

    bldc_commutate(&in, &out);

    TEST_ASSERT_UINT16_WITHIN(1u, 3600u, out.turn_on_compare);
    TEST_ASSERT_UINT16_WITHIN(1u, 1476u, out.turn_off_compare);
    TEST_ASSERT_UINT16_WITHIN(8u, 395u, out.commutation_ticks);
    TEST_ASSERT_EQUAL_HEX8(0x02u, out.turn_on_switch); /* T3 */
    TEST_ASSERT_EQUAL_HEX8(0x04u, out.turn_off_switch); /* T5 */
    TEST_ASSERT_EQUAL_HEX8(0x03u, out.sector);
    TEST_ASSERT_EQUAL_HEX8(0x00u, out.flags);
}

/* reverse edge into sector 4 at 1500 rpm: Eqs. 16/18 duties, Eq. 20 time */
void test_bldc_commutate_should_commutate_reverse_into_sector_4_at_1500_rpm(void)
{
    const bldc_inputs_t in = {
        .hall_code = 3u, /* Hall 011 */
        .previous_hall_code = 1u, /* Hall 001 */
        .hall_period_ticks = 6667u,
        .bus_voltage_adc = 2708u,
        .phase_current_adc = 2358u,
        .main_duty_counts = 1512u,
    };
    bldc_outputs_t out = { /* poison: every field must be overwritten by the core */
        .turn_on_compare = 0xA5A5u,
        .turn_off_compare = 0xA5A5u,
        .commutation_ticks = 0xA5A5u,
        .turn_on_switch = 0xA5u,
        .turn_off_switch = 0xA5u,
        .sector = 0xA5u,
        .flags = 0xA5u,
    };

    bldc_commutate(&in, &out);

    TEST_ASSERT_UINT16_WITHIN(1u, 3600u, out.turn_on_compare);
    TEST_ASSERT_UINT16_WITHIN(1u, 1476u, out.turn_off_compare);
    TEST_ASSERT_UINT16_WITHIN(8u, 395u, out.commutation_ticks);
    TEST_ASSERT_EQUAL_HEX8(0x01u, out.turn_on_switch); /* T2 */
    TEST_ASSERT_EQUAL_HEX8(0x03u, out.turn_off_switch); /* T4 */
    TEST_ASSERT_EQUAL_HEX8(0x04u, out.sector);
    TEST_ASSERT_EQUAL_HEX8(0x00u, out.flags);
}

/* reverse edge into sector 5 at 1500 rpm: Eqs. 16/18 duties, Eq. 20 time */
void test_bldc_commutate_should_commutate_reverse_into_sector_5_at_1500_rpm(void)
{
    const bldc_inputs_t in = {
        .hall_code = 1u, /* Hall 001 */
        .previous_hall_code = 5u, /* Hall 101 */
        .hall_period_ticks = 6667u,
        .bus_voltage_adc = 2708u,
        .phase_current_adc = 2358u,
        .main_duty_counts = 1512u,
    };
    bldc_outputs_t out = { /* poison: every field must be overwritten by the core */
        .turn_on_compare = 0xA5A5u,
        .turn_off_compare = 0xA5A5u,
        .commutation_ticks = 0xA5A5u,
        .turn_on_switch = 0xA5u,
        .turn_off_switch = 0xA5u,
        .sector = 0xA5u,
        .flags = 0xA5u,
    };

    bldc_commutate(&in, &out);

    TEST_ASSERT_UINT16_WITHIN(1u, 3600u, out.turn_on_compare);
    TEST_ASSERT_UINT16_WITHIN(1u, 1476u, out.turn_off_compare);
    TEST_ASSERT_UINT16_WITHIN(8u, 395u, out.commutation_ticks);
    TEST_ASSERT_EQUAL_HEX8(0x04u, out.turn_on_switch); /* T5 */
    TEST_ASSERT_EQUAL_HEX8(0x00u, out.turn_off_switch); /* T1 */
    TEST_ASSERT_EQUAL_HEX8(0x05u, out.sector);
    TEST_ASSERT_EQUAL_HEX8(0x00u, out.flags);
}

/* forward edge into sector 0 at 4600 rpm: Eqs. 16/18 duties, Eq. 20 time */
void test_bldc_commutate_should_commutate_forward_into_sector_0_at_4600_rpm(void)
{
    const bldc_inputs_t in = {
        .hall_code = 5u, /* Hall 101 */
        .previous_hall_code = 1u, /* Hall 001 */
        .hall_period_ticks = 2174u,
        .bus_voltage_adc = 2708u,
        .phase_current_adc = 2358u,
        .main_duty_counts = 1512u,
    };
    bldc_outputs_t out = { /* poison: every field must be overwritten by the core */
        .turn_on_compare = 0xA5A5u,
        .turn_off_compare = 0xA5A5u,
        .commutation_ticks = 0xA5A5u,
        .turn_on_switch = 0xA5u,
        .turn_off_switch = 0xA5u,
        .sector = 0xA5u,
        .flags = 0xA5u,
    };

    bldc_commutate(&in, &out);

    TEST_ASSERT_UINT16_WITHIN(1u, 686u, out.turn_on_compare);
    TEST_ASSERT_UINT16_WITHIN(1u, 0u, out.turn_off_compare);
    TEST_ASSERT_UINT16_WITHIN(9u, 1222u, out.commutation_ticks);
    TEST_ASSERT_EQUAL_HEX8(0x01u, out.turn_on_switch); /* T2 */
    TEST_ASSERT_EQUAL_HEX8(0x05u, out.turn_off_switch); /* T6 */
    TEST_ASSERT_EQUAL_HEX8(0x00u, out.sector);
    TEST_ASSERT_EQUAL_HEX8(BLDC_FLAG_HIGH_SPEED, out.flags);
}

/* forward edge into sector 1 at 4600 rpm: Eqs. 16/18 duties, Eq. 20 time */
void test_bldc_commutate_should_commutate_forward_into_sector_1_at_4600_rpm(void)
{
    const bldc_inputs_t in = {
        .hall_code = 4u, /* Hall 100 */
        .previous_hall_code = 5u, /* Hall 101 */
        .hall_period_ticks = 2174u,
        .bus_voltage_adc = 2708u,
        .phase_current_adc = 2358u,
        .main_duty_counts = 1512u,
    };
    bldc_outputs_t out = { /* poison: every field must be overwritten by the core */
        .turn_on_compare = 0xA5A5u,
        .turn_off_compare = 0xA5A5u,
        .commutation_ticks = 0xA5A5u,
        .turn_on_switch = 0xA5u,
        .turn_off_switch = 0xA5u,
        .sector = 0xA5u,
        .flags = 0xA5u,
    };

    bldc_commutate(&in, &out);

    TEST_ASSERT_UINT16_WITHIN(1u, 686u, out.turn_on_compare);
    TEST_ASSERT_UINT16_WITHIN(1u, 0u, out.turn_off_compare);
    TEST_ASSERT_UINT16_WITHIN(9u, 1222u, out.commutation_ticks);
    TEST_ASSERT_EQUAL_HEX8(0x04u, out.turn_on_switch); /* T5 */
    TEST_ASSERT_EQUAL_HEX8(0x02u, out.turn_off_switch); /* T3 */
    TEST_ASSERT_EQUAL_HEX8(0x01u, out.sector);
    TEST_ASSERT_EQUAL_HEX8(BLDC_FLAG_HIGH_SPEED, out.flags);
}

/* forward edge into sector 2 at 4600 rpm: Eqs. 16/18 duties, Eq. 20 time */
void test_bldc_commutate_should_commutate_forward_into_sector_2_at_4600_rpm(void)
{
    const bldc_inputs_t in = {
        .hall_code = 6u, /* Hall 110 */
        .previous_hall_code = 4u, /* Hall 100 */
        .hall_period_ticks = 2174u,
        .bus_voltage_adc = 2708u,
        .phase_current_adc = 2358u,
        .main_duty_counts = 1512u,
    };
    bldc_outputs_t out = { /* poison: every field must be overwritten by the core */
        .turn_on_compare = 0xA5A5u,
        .turn_off_compare = 0xA5A5u,
        .commutation_ticks = 0xA5A5u,
        .turn_on_switch = 0xA5u,
        .turn_off_switch = 0xA5u,
        .sector = 0xA5u,
        .flags = 0xA5u,
    };

    bldc_commutate(&in, &out);

    TEST_ASSERT_UINT16_WITHIN(1u, 686u, out.turn_on_compare);
    TEST_ASSERT_UINT16_WITHIN(1u, 0u, out.turn_off_compare);
    TEST_ASSERT_UINT16_WITHIN(9u, 1222u, out.commutation_ticks);
    TEST_ASSERT_EQUAL_HEX8(0x03u, out.turn_on_switch); /* T4 */
    TEST_ASSERT_EQUAL_HEX8(0x01u, out.turn_off_switch); /* T2 */
    TEST_ASSERT_EQUAL_HEX8(0x02u, out.sector);
    TEST_ASSERT_EQUAL_HEX8(BLDC_FLAG_HIGH_SPEED, out.flags);
}

/* forward edge into sector 3 at 4600 rpm: Eqs. 16/18 duties, Eq. 20 time */
void test_bldc_commutate_should_commutate_forward_into_sector_3_at_4600_rpm(void)
{
    const bldc_inputs_t in = {
        .hall_code = 2u, /* Hall 010 */
        .previous_hall_code = 6u, /* Hall 110 */
        .hall_period_ticks = 2174u,
        .bus_voltage_adc = 2708u,
        .phase_current_adc = 2358u,
        .main_duty_counts = 1512u,
    };
    bldc_outputs_t out = { /* poison: every field must be overwritten by the core */
        .turn_on_compare = 0xA5A5u,
        .turn_off_compare = 0xA5A5u,
        .commutation_ticks = 0xA5A5u,
        .turn_on_switch = 0xA5u,
        .turn_off_switch = 0xA5u,
        .sector = 0xA5u,
        .flags = 0xA5u,
    };

    bldc_commutate(&in, &out);

    TEST_ASSERT_UINT16_WITHIN(1u, 686u, out.turn_on_compare);
    TEST_ASSERT_UINT16_WITHIN(1u, 0u, out.turn_off_compare);
    TEST_ASSERT_UINT16_WITHIN(9u, 1222u, out.commutation_ticks);
    TEST_ASSERT_EQUAL_HEX8(0x00u, out.turn_on_switch); /* T1 */
    TEST_ASSERT_EQUAL_HEX8(0x04u, out.turn_off_switch); /* T5 */
    TEST_ASSERT_EQUAL_HEX8(0x03u, out.sector);
    TEST_ASSERT_EQUAL_HEX8(BLDC_FLAG_HIGH_SPEED, out.flags);
}

/* forward edge into sector 4 at 4600 rpm: Eqs. 16/18 duties, Eq. 20 time */
void test_bldc_commutate_should_commutate_forward_into_sector_4_at_4600_rpm(void)
{
    const bldc_inputs_t in = {
        .hall_code = 3u, /* Hall 011 */
        .previous_hall_code = 2u, /* Hall 010 */
        .hall_period_ticks = 2174u,
        .bus_voltage_adc = 2708u,
        .phase_current_adc = 2358u,
        .main_duty_counts = 1512u,
    };
    bldc_outputs_t out = { /* poison: every field must be overwritten by the core */
        .turn_on_compare = 0xA5A5u,
        .turn_off_compare = 0xA5A5u,
        .commutation_ticks = 0xA5A5u,
        .turn_on_switch = 0xA5u,
        .turn_off_switch = 0xA5u,
        .sector = 0xA5u,
        .flags = 0xA5u,
    };

    bldc_commutate(&in, &out);

    TEST_ASSERT_UINT16_WITHIN(1u, 686u, out.turn_on_compare);
    TEST_ASSERT_UINT16_WITHIN(1u, 0u, out.turn_off_compare);
    TEST_ASSERT_UINT16_WITHIN(9u, 1222u, out.commutation_ticks);
    TEST_ASSERT_EQUAL_HEX8(0x05u, out.turn_on_switch); /* T6 */
    TEST_ASSERT_EQUAL_HEX8(0x03u, out.turn_off_switch); /* T4 */
    TEST_ASSERT_EQUAL_HEX8(0x04u, out.sector);
    TEST_ASSERT_EQUAL_HEX8(BLDC_FLAG_HIGH_SPEED, out.flags);
}

/* forward edge into sector 5 at 4600 rpm: Eqs. 16/18 duties, Eq. 20 time */
void test_bldc_commutate_should_commutate_forward_into_sector_5_at_4600_rpm(void)
{
    const bldc_inputs_t in = {
        .hall_code = 1u, /* Hall 001 */
        .previous_hall_code = 3u, /* Hall 011 */
        .hall_period_ticks = 2174u,
        .bus_voltage_adc = 2708u,
        .phase_current_adc = 2358u,
        .main_duty_counts = 1512u,
    };
    bldc_outputs_t out = { /* poison: every field must be overwritten by the core */
        .turn_on_compare = 0xA5A5u,
        .turn_off_compare = 0xA5A5u,
        .commutation_ticks = 0xA5A5u,
        .turn_on_switch = 0xA5u,
        .turn_off_switch = 0xA5u,
        .sector = 0xA5u,
        .flags = 0xA5u,
    };

    bldc_commutate(&in, &out);

    TEST_ASSERT_UINT16_WITHIN(1u, 686u, out.turn_on_compare);
    TEST_ASSERT_UINT16_WITHIN(1u, 0u, out.turn_off_compare);
    TEST_ASSERT_UINT16_WITHIN(9u, 1222u, out.commutation_ticks);
    TEST_ASSERT_EQUAL_HEX8(0x02u, out.turn_on_switch); /* T3 */
    TEST_ASSERT_EQUAL_HEX8(0x00u, out.turn_off_switch); /* T1 */
    TEST_ASSERT_EQUAL_HEX8(0x05u, out.sector);
    TEST_ASSERT_EQUAL_HEX8(BLDC_FLAG_HIGH_SPEED, out.flags);
}

/* reverse edge into sector 0 at 4600 rpm: Eqs. 16/18 duties, Eq. 20 time */
void test_bldc_commutate_should_commutate_reverse_into_sector_0_at_4600_rpm(void)
{
    const bldc_inputs_t in = {
        .hall_code = 5u, /* Hall 101 */
        .previous_hall_code = 4u, /* Hall 100 */
        .hall_period_ticks = 2174u,
        .bus_voltage_adc = 2708u,
        .phase_current_adc = 2358u,
        .main_duty_counts = 1512u,
    };
    bldc_outputs_t out = { /* poison: every field must be overwritten by the core */
        .turn_on_compare = 0xA5A5u,
        .turn_off_compare = 0xA5A5u,
        .commutation_ticks = 0xA5A5u,
        .turn_on_switch = 0xA5u,
        .turn_off_switch = 0xA5u,
        .sector = 0xA5u,
        .flags = 0xA5u,
    };

    bldc_commutate(&in, &out);

    TEST_ASSERT_UINT16_WITHIN(1u, 686u, out.turn_on_compare);
    TEST_ASSERT_UINT16_WITHIN(1u, 0u, out.turn_off_compare);
    TEST_ASSERT_UINT16_WITHIN(9u, 1222u, out.commutation_ticks);
    TEST_ASSERT_EQUAL_HEX8(0x03u, out.turn_on_switch); /* T4 */
    TEST_ASSERT_EQUAL_HEX8(0x05u, out.turn_off_switch); /* T6 */
    TEST_ASSERT_EQUAL_HEX8(0x00u, out.sector);
    TEST_ASSERT_EQUAL_HEX8(BLDC_FLAG_HIGH_SPEED, out.flags);
}

/* reverse edge into sector 1 at 4600 rpm: Eqs. 16/18 duties, Eq. 20 time */
void test_bldc_commutate_should_commutate_reverse_into_sector_1_at_4600_rpm(void)
{
    const bldc_inputs_t in = {
        .hall_code = 4u, /* Hall 100 */
        .previous_hall_code = 6u, /* Hall 110 */
        .hall_period_ticks = 2174u,
        .bus_voltage_adc = 2708u,
        .phase_current_adc = 2358u,
        .main_duty_counts = 1512u,
    };
    bldc_outputs_t out = { /* poison: every field must be overwritten by the core */
        .turn_on_compare = 0xA5A5u,
        .turn_off_compare = 0xA5A5u,
        .commutation_ticks = 0xA5A5u,
        .turn_on_switch = 0xA5u,
        .turn_off_switch = 0xA5u,
        .sector = 0xA5u,
        .flags = 0xA5u,
    };

    bldc_commutate(&in, &out);

    TEST_ASSERT_UINT16_WITHIN(1u, 686u, out.turn_on_compare);
    TEST_ASSERT_UINT16_WITHIN(1u, 0u, out.turn_off_compare);
    TEST_ASSERT_UINT16_WITHIN(9u, 1222u, out.commutation_ticks);
    TEST_ASSERT_EQUAL_HEX8(0x00u, out.turn_on_switch); /* T1 */
    TEST_ASSERT_EQUAL_HEX8(0x02u, out.turn_off_switch); /* T3 */
    TEST_ASSERT_EQUAL_HEX8(0x01u, out.sector);
    TEST_ASSERT_EQUAL_HEX8(BLDC_FLAG_HIGH_SPEED, out.flags);
}

/* reverse edge into sector 2 at 4600 rpm: Eqs. 16/18 duties, Eq. 20 time */
void test_bldc_commutate_should_commutate_reverse_into_sector_2_at_4600_rpm(void)
{
    const bldc_inputs_t in = {
        .hall_code = 6u, /* Hall 110 */
        .previous_hall_code = 2u, /* Hall 010 */
        .hall_period_ticks = 2174u,
        .bus_voltage_adc = 2708u,
        .phase_current_adc = 2358u,
        .main_duty_counts = 1512u,
    };
    bldc_outputs_t out = { /* poison: every field must be overwritten by the core */
        .turn_on_compare = 0xA5A5u,
        .turn_off_compare = 0xA5A5u,
        .commutation_ticks = 0xA5A5u,
        .turn_on_switch = 0xA5u,
        .turn_off_switch = 0xA5u,
        .sector = 0xA5u,
        .flags = 0xA5u,
    };

    bldc_commutate(&in, &out);

    TEST_ASSERT_UINT16_WITHIN(1u, 686u, out.turn_on_compare);
    TEST_ASSERT_UINT16_WITHIN(1u, 0u, out.turn_off_compare);
    TEST_ASSERT_UINT16_WITHIN(9u, 1222u, out.commutation_ticks);
    TEST_ASSERT_EQUAL_HEX8(0x05u, out.turn_on_switch); /* T6 */
    TEST_ASSERT_EQUAL_HEX8(0x01u, out.turn_off_switch); /* T2 */
    TEST_ASSERT_EQUAL_HEX8(0x02u, out.sector);
    TEST_ASSERT_EQUAL_HEX8(BLDC_FLAG_HIGH_SPEED, out.flags);
}

/* reverse edge into sector 3 at 4600 rpm: Eqs. 16/18 duties, Eq. 20 time */
void test_bldc_commutate_should_commutate_reverse_into_sector_3_at_4600_rpm(void)
{
    const bldc_inputs_t in = {
        .hall_code = 2u, /* Hall 010 */
        .previous_hall_code = 3u, /* Hall 011 */
        .hall_period_ticks = 2174u,
        .bus_voltage_adc = 2708u,
        .phase_current_adc = 2358u,
        .main_duty_counts = 1512u,
    };
    bldc_outputs_t out = { /* poison: every field must be overwritten by the core */
        .turn_on_compare = 0xA5A5u,
        .turn_off_compare = 0xA5A5u,
        .commutation_ticks = 0xA5A5u,
        .turn_on_switch = 0xA5u,
        .turn_off_switch = 0xA5u,
        .sector = 0xA5u,
        .flags = 0xA5u,
    };

    bldc_commutate(&in, &out);

    TEST_ASSERT_UINT16_WITHIN(1u, 686u, out.turn_on_compare);
    TEST_ASSERT_UINT16_WITHIN(1u, 0u, out.turn_off_compare);
    TEST_ASSERT_UINT16_WITHIN(9u, 1222u, out.commutation_ticks);
    TEST_ASSERT_EQUAL_HEX8(0x02u, out.turn_on_switch); /* T3 */
    TEST_ASSERT_EQUAL_HEX8(0x04u, out.turn_off_switch); /* T5 */
    TEST_ASSERT_EQUAL_HEX8(0x03u, out.sector);
    TEST_ASSERT_EQUAL_HEX8(BLDC_FLAG_HIGH_SPEED, out.flags);
}

/* reverse edge into sector 4 at 4600 rpm: Eqs. 16/18 duties, Eq. 20 time */
void test_bldc_commutate_should_commutate_reverse_into_sector_4_at_4600_rpm(void)
{
    const bldc_inputs_t in = {
        .hall_code = 3u, /* Hall 011 */
        .previous_hall_code = 1u, /* Hall 001 */
        .hall_period_ticks = 2174u,
        .bus_voltage_adc = 2708u,
        .phase_current_adc = 2358u,
        .main_duty_counts = 1512u,
    };
    bldc_outputs_t out = { /* poison: every field must be overwritten by the core */
        .turn_on_compare = 0xA5A5u,
        .turn_off_compare = 0xA5A5u,
        .commutation_ticks = 0xA5A5u,
        .turn_on_switch = 0xA5u,
        .turn_off_switch = 0xA5u,
        .sector = 0xA5u,
        .flags = 0xA5u,
    };

    bldc_commutate(&in, &out);

    TEST_ASSERT_UINT16_WITHIN(1u, 686u, out.turn_on_compare);
    TEST_ASSERT_UINT16_WITHIN(1u, 0u, out.turn_off_compare);
    TEST_ASSERT_UINT16_WITHIN(9u, 1222u, out.commutation_ticks);
    TEST_ASSERT_EQUAL_HEX8(0x01u, out.turn_on_switch); /* T2 */
    TEST_ASSERT_EQUAL_HEX8(0x03u, out.turn_off_switch); /* T4 */
    TEST_ASSERT_EQUAL_HEX8(0x04u, out.sector);
    TEST_ASSERT_EQUAL_HEX8(BLDC_FLAG_HIGH_SPEED, out.flags);
}

/* reverse edge into sector 5 at 4600 rpm: Eqs. 16/18 duties, Eq. 20 time */
void test_bldc_commutate_should_commutate_reverse_into_sector_5_at_4600_rpm(void)
{
    const bldc_inputs_t in = {
        .hall_code = 1u, /* Hall 001 */
        .previous_hall_code = 5u, /* Hall 101 */
        .hall_period_ticks = 2174u,
        .bus_voltage_adc = 2708u,
        .phase_current_adc = 2358u,
        .main_duty_counts = 1512u,
    };
    bldc_outputs_t out = { /* poison: every field must be overwritten by the core */
        .turn_on_compare = 0xA5A5u,
        .turn_off_compare = 0xA5A5u,
        .commutation_ticks = 0xA5A5u,
        .turn_on_switch = 0xA5u,
        .turn_off_switch = 0xA5u,
        .sector = 0xA5u,
        .flags = 0xA5u,
    };

    bldc_commutate(&in, &out);

    TEST_ASSERT_UINT16_WITHIN(1u, 686u, out.turn_on_compare);
    TEST_ASSERT_UINT16_WITHIN(1u, 0u, out.turn_off_compare);
    TEST_ASSERT_UINT16_WITHIN(9u, 1222u, out.commutation_ticks);
    TEST_ASSERT_EQUAL_HEX8(0x04u, out.turn_on_switch); /* T5 */
    TEST_ASSERT_EQUAL_HEX8(0x00u, out.turn_off_switch); /* T1 */
    TEST_ASSERT_EQUAL_HEX8(0x05u, out.sector);
    TEST_ASSERT_EQUAL_HEX8(BLDC_FLAG_HIGH_SPEED, out.flags);
}

/* Eq. 18 cut-off 4E = U_d falls between periods 3933 and 3934 */
void test_bldc_commutate_should_take_the_last_high_speed_segment_at_period_3933(void)
{
    const bldc_inputs_t in = {
        .hall_code = 4u, /* Hall 100 */
        .previous_hall_code = 5u, /* Hall 101 */
        .hall_period_ticks = 3933u,
        .bus_voltage_adc = 2708u,
        .phase_current_adc = 2358u,
        .main_duty_counts = 1512u,
    };
    bldc_outputs_t out = { /* poison: every field must be overwritten by the core */
        .turn_on_compare = 0xA5A5u,
        .turn_off_compare = 0xA5A5u,
        .commutation_ticks = 0xA5A5u,
        .turn_on_switch = 0xA5u,
        .turn_off_switch = 0xA5u,
        .sector = 0xA5u,
        .flags = 0xA5u,
    };

    bldc_commutate(&in, &out);

    TEST_ASSERT_UINT16_WITHIN(1u, 3600u, out.turn_on_compare);
    TEST_ASSERT_UINT16_WITHIN(1u, 0u, out.turn_off_compare);
    TEST_ASSERT_UINT16_WITHIN(8u, 233u, out.commutation_ticks);
    TEST_ASSERT_EQUAL_HEX8(0x04u, out.turn_on_switch); /* T5 */
    TEST_ASSERT_EQUAL_HEX8(0x02u, out.turn_off_switch); /* T3 */
    TEST_ASSERT_EQUAL_HEX8(0x01u, out.sector);
    TEST_ASSERT_EQUAL_HEX8(BLDC_FLAG_HIGH_SPEED, out.flags);
}

/* Eq. 18 cut-off 4E = U_d falls between periods 3933 and 3934 */
void test_bldc_commutate_should_take_the_first_low_speed_segment_at_period_3934(void)
{
    const bldc_inputs_t in = {
        .hall_code = 4u, /* Hall 100 */
        .previous_hall_code = 5u, /* Hall 101 */
        .hall_period_ticks = 3934u,
        .bus_voltage_adc = 2708u,
        .phase_current_adc = 2358u,
        .main_duty_counts = 1512u,
    };
    bldc_outputs_t out = { /* poison: every field must be overwritten by the core */
        .turn_on_compare = 0xA5A5u,
        .turn_off_compare = 0xA5A5u,
        .commutation_ticks = 0xA5A5u,
        .turn_on_switch = 0xA5u,
        .turn_off_switch = 0xA5u,
        .sector = 0xA5u,
        .flags = 0xA5u,
    };

    bldc_commutate(&in, &out);

    TEST_ASSERT_UINT16_WITHIN(1u, 3600u, out.turn_on_compare);
    TEST_ASSERT_UINT16_WITHIN(1u, 0u, out.turn_off_compare);
    TEST_ASSERT_UINT16_WITHIN(8u, 233u, out.commutation_ticks);
    TEST_ASSERT_EQUAL_HEX8(0x04u, out.turn_on_switch); /* T5 */
    TEST_ASSERT_EQUAL_HEX8(0x02u, out.turn_off_switch); /* T3 */
    TEST_ASSERT_EQUAL_HEX8(0x01u, out.sector);
    TEST_ASSERT_EQUAL_HEX8(0x00u, out.flags);
}

/* bus below its minimum: saturated and flagged */
void test_bldc_commutate_should_saturate_a_low_bus(void)
{
    const bldc_inputs_t in = {
        .hall_code = 4u, /* Hall 100 */
        .previous_hall_code = 5u, /* Hall 101 */
        .hall_period_ticks = 26000u,
        .bus_voltage_adc = 2157u,
        .phase_current_adc = 2358u,
        .main_duty_counts = 1512u,
    };
    bldc_outputs_t out = { /* poison: every field must be overwritten by the core */
        .turn_on_compare = 0xA5A5u,
        .turn_off_compare = 0xA5A5u,
        .commutation_ticks = 0xA5A5u,
        .turn_on_switch = 0xA5u,
        .turn_off_switch = 0xA5u,
        .sector = 0xA5u,
        .flags = 0xA5u,
    };

    bldc_commutate(&in, &out);

    TEST_ASSERT_UINT16_WITHIN(1u, 3600u, out.turn_on_compare);
    TEST_ASSERT_UINT16_WITHIN(1u, 2947u, out.turn_off_compare);
    TEST_ASSERT_UINT16_WITHIN(9u, 1541u, out.commutation_ticks);
    TEST_ASSERT_EQUAL_HEX8(0x04u, out.turn_on_switch); /* T5 */
    TEST_ASSERT_EQUAL_HEX8(0x02u, out.turn_off_switch); /* T3 */
    TEST_ASSERT_EQUAL_HEX8(0x01u, out.sector);
    TEST_ASSERT_EQUAL_HEX8(BLDC_FLAG_INPUT_SATURATED, out.flags);
}

/* bus above its maximum: every switch off */
void test_bldc_commutate_should_switch_off_over_voltage(void)
{
    const bldc_inputs_t in = {
        .hall_code = 4u, /* Hall 100 */
        .previous_hall_code = 5u, /* Hall 101 */
        .hall_period_ticks = 26000u,
        .bus_voltage_adc = 3386u,
        .phase_current_adc = 2358u,
        .main_duty_counts = 1512u,
    };
    bldc_outputs_t out = { /* poison: every field must be overwritten by the core */
        .turn_on_compare = 0xA5A5u,
        .turn_off_compare = 0xA5A5u,
        .commutation_ticks = 0xA5A5u,
        .turn_on_switch = 0xA5u,
        .turn_off_switch = 0xA5u,
        .sector = 0xA5u,
        .flags = 0xA5u,
    };

    bldc_commutate(&in, &out);

    TEST_ASSERT_UINT16_WITHIN(0u, 0u, out.turn_on_compare);
    TEST_ASSERT_UINT16_WITHIN(0u, 0u, out.turn_off_compare);
    TEST_ASSERT_UINT16_WITHIN(0u, 0u, out.commutation_ticks);
    TEST_ASSERT_EQUAL_HEX8(BLDC_NO_SWITCH, out.turn_on_switch); /* all off */
    TEST_ASSERT_EQUAL_HEX8(BLDC_NO_SWITCH, out.turn_off_switch); /* all off */
    TEST_ASSERT_EQUAL_HEX8(0x01u, out.sector);
    TEST_ASSERT_EQUAL_HEX8(BLDC_FLAG_INPUT_SATURATED, out.flags);
}

/* period below the top speed's: every switch off */
void test_bldc_commutate_should_switch_off_over_speed(void)
{
    const bldc_inputs_t in = {
        .hall_code = 4u, /* Hall 100 */
        .previous_hall_code = 5u, /* Hall 101 */
        .hall_period_ticks = 1999u,
        .bus_voltage_adc = 2708u,
        .phase_current_adc = 2358u,
        .main_duty_counts = 1512u,
    };
    bldc_outputs_t out = { /* poison: every field must be overwritten by the core */
        .turn_on_compare = 0xA5A5u,
        .turn_off_compare = 0xA5A5u,
        .commutation_ticks = 0xA5A5u,
        .turn_on_switch = 0xA5u,
        .turn_off_switch = 0xA5u,
        .sector = 0xA5u,
        .flags = 0xA5u,
    };

    bldc_commutate(&in, &out);

    TEST_ASSERT_UINT16_WITHIN(0u, 0u, out.turn_on_compare);
    TEST_ASSERT_UINT16_WITHIN(0u, 0u, out.turn_off_compare);
    TEST_ASSERT_UINT16_WITHIN(0u, 0u, out.commutation_ticks);
    TEST_ASSERT_EQUAL_HEX8(BLDC_NO_SWITCH, out.turn_on_switch); /* all off */
    TEST_ASSERT_EQUAL_HEX8(BLDC_NO_SWITCH, out.turn_off_switch); /* all off */
    TEST_ASSERT_EQUAL_HEX8(0x01u, out.sector);
    TEST_ASSERT_EQUAL_HEX8(BLDC_FLAG_INPUT_SATURATED, out.flags);
}

/* period above the slowest speed's: flagged */
void test_bldc_commutate_should_flag_a_speed_below_the_minimum(void)
{
    const bldc_inputs_t in = {
        .hall_code = 4u, /* Hall 100 */
        .previous_hall_code = 5u, /* Hall 101 */
        .hall_period_ticks = 51000u,
        .bus_voltage_adc = 2708u,
        .phase_current_adc = 2358u,
        .main_duty_counts = 1512u,
    };
    bldc_outputs_t out = { /* poison: every field must be overwritten by the core */
        .turn_on_compare = 0xA5A5u,
        .turn_off_compare = 0xA5A5u,
        .commutation_ticks = 0xA5A5u,
        .turn_on_switch = 0xA5u,
        .turn_off_switch = 0xA5u,
        .sector = 0xA5u,
        .flags = 0xA5u,
    };

    bldc_commutate(&in, &out);

    TEST_ASSERT_UINT16_WITHIN(1u, 3600u, out.turn_on_compare);
    TEST_ASSERT_UINT16_WITHIN(1u, 3322u, out.turn_off_compare);
    TEST_ASSERT_UINT16_WITHIN(15u, 3025u, out.commutation_ticks);
    TEST_ASSERT_EQUAL_HEX8(0x04u, out.turn_on_switch); /* T5 */
    TEST_ASSERT_EQUAL_HEX8(0x02u, out.turn_off_switch); /* T3 */
    TEST_ASSERT_EQUAL_HEX8(0x01u, out.sector);
    TEST_ASSERT_EQUAL_HEX8(BLDC_FLAG_INPUT_SATURATED, out.flags);
}

/* zero current: t_com = 0 */
void test_bldc_commutate_should_give_no_commutation_time_without_current(void)
{
    const bldc_inputs_t in = {
        .hall_code = 4u, /* Hall 100 */
        .previous_hall_code = 5u, /* Hall 101 */
        .hall_period_ticks = 26000u,
        .bus_voltage_adc = 2708u,
        .phase_current_adc = 2047u,
        .main_duty_counts = 1512u,
    };
    bldc_outputs_t out = { /* poison: every field must be overwritten by the core */
        .turn_on_compare = 0xA5A5u,
        .turn_off_compare = 0xA5A5u,
        .commutation_ticks = 0xA5A5u,
        .turn_on_switch = 0xA5u,
        .turn_off_switch = 0xA5u,
        .sector = 0xA5u,
        .flags = 0xA5u,
    };

    bldc_commutate(&in, &out);

    TEST_ASSERT_UINT16_WITHIN(1u, 3600u, out.turn_on_compare);
    TEST_ASSERT_UINT16_WITHIN(1u, 3055u, out.turn_off_compare);
    TEST_ASSERT_UINT16_WITHIN(0u, 0u, out.commutation_ticks);
    TEST_ASSERT_EQUAL_HEX8(0x04u, out.turn_on_switch); /* T5 */
    TEST_ASSERT_EQUAL_HEX8(0x02u, out.turn_off_switch); /* T3 */
    TEST_ASSERT_EQUAL_HEX8(0x01u, out.sector);
    TEST_ASSERT_EQUAL_HEX8(BLDC_FLAG_INPUT_SATURATED, out.flags);
}

/* current above the braking range: flagged */
void test_bldc_commutate_should_flag_a_current_above_the_range(void)
{
    const bldc_inputs_t in = {
        .hall_code = 4u, /* Hall 100 */
        .previous_hall_code = 5u, /* Hall 101 */
        .hall_period_ticks = 26000u,
        .bus_voltage_adc = 2708u,
        .phase_current_adc = 2669u,
        .main_duty_counts = 1512u,
    };
    bldc_outputs_t out = { /* poison: every field must be overwritten by the core */
        .turn_on_compare = 0xA5A5u,
        .turn_off_compare = 0xA5A5u,
        .commutation_ticks = 0xA5A5u,
        .turn_on_switch = 0xA5u,
        .turn_off_switch = 0xA5u,
        .sector = 0xA5u,
        .flags = 0xA5u,
    };

    bldc_commutate(&in, &out);

    TEST_ASSERT_UINT16_WITHIN(1u, 3600u, out.turn_on_compare);
    TEST_ASSERT_UINT16_WITHIN(1u, 3055u, out.turn_off_compare);
    TEST_ASSERT_UINT16_WITHIN(12u, 3087u, out.commutation_ticks);
    TEST_ASSERT_EQUAL_HEX8(0x04u, out.turn_on_switch); /* T5 */
    TEST_ASSERT_EQUAL_HEX8(0x02u, out.turn_off_switch); /* T3 */
    TEST_ASSERT_EQUAL_HEX8(0x01u, out.sector);
    TEST_ASSERT_EQUAL_HEX8(BLDC_FLAG_INPUT_SATURATED, out.flags);
}

/* current code above the ADC's full scale: saturated, flagged */
void test_bldc_commutate_should_saturate_a_current_above_the_adc(void)
{
    const bldc_inputs_t in = {
        .hall_code = 4u, /* Hall 100 */
        .previous_hall_code = 5u, /* Hall 101 */
        .hall_period_ticks = 26000u,
        .bus_voltage_adc = 2708u,
        .phase_current_adc = 65535u,
        .main_duty_counts = 1512u,
    };
    bldc_outputs_t out = { /* poison: every field must be overwritten by the core */
        .turn_on_compare = 0xA5A5u,
        .turn_off_compare = 0xA5A5u,
        .commutation_ticks = 0xA5A5u,
        .turn_on_switch = 0xA5u,
        .turn_off_switch = 0xA5u,
        .sector = 0xA5u,
        .flags = 0xA5u,
    };

    bldc_commutate(&in, &out);

    TEST_ASSERT_UINT16_WITHIN(1u, 3600u, out.turn_on_compare);
    TEST_ASSERT_UINT16_WITHIN(1u, 3055u, out.turn_off_compare);
    TEST_ASSERT_UINT16_WITHIN(20u, 10178u, out.commutation_ticks);
    TEST_ASSERT_EQUAL_HEX8(0x04u, out.turn_on_switch); /* T5 */
    TEST_ASSERT_EQUAL_HEX8(0x02u, out.turn_off_switch); /* T3 */
    TEST_ASSERT_EQUAL_HEX8(0x01u, out.sector);
    TEST_ASSERT_EQUAL_HEX8(BLDC_FLAG_INPUT_SATURATED, out.flags);
}

/* Hall code 000 */
void test_bldc_commutate_should_switch_off_on_hall_000(void)
{
    const bldc_inputs_t in = {
        .hall_code = 0u, /* Hall 000 */
        .previous_hall_code = 5u, /* Hall 101 */
        .hall_period_ticks = 26000u,
        .bus_voltage_adc = 2708u,
        .phase_current_adc = 2358u,
        .main_duty_counts = 1512u,
    };
    bldc_outputs_t out = { /* poison: every field must be overwritten by the core */
        .turn_on_compare = 0xA5A5u,
        .turn_off_compare = 0xA5A5u,
        .commutation_ticks = 0xA5A5u,
        .turn_on_switch = 0xA5u,
        .turn_off_switch = 0xA5u,
        .sector = 0xA5u,
        .flags = 0xA5u,
    };

    bldc_commutate(&in, &out);

    TEST_ASSERT_UINT16_WITHIN(0u, 0u, out.turn_on_compare);
    TEST_ASSERT_UINT16_WITHIN(0u, 0u, out.turn_off_compare);
    TEST_ASSERT_UINT16_WITHIN(0u, 0u, out.commutation_ticks);
    TEST_ASSERT_EQUAL_HEX8(BLDC_NO_SWITCH, out.turn_on_switch); /* all off */
    TEST_ASSERT_EQUAL_HEX8(BLDC_NO_SWITCH, out.turn_off_switch); /* all off */
    TEST_ASSERT_EQUAL_HEX8(0xFFu, out.sector); /* invalid Hall code */
    TEST_ASSERT_EQUAL_HEX8(BLDC_FLAG_INVALID_HALL, out.flags);
}

/* Hall code 111 */
void test_bldc_commutate_should_switch_off_on_hall_111(void)
{
    const bldc_inputs_t in = {
        .hall_code = 7u, /* Hall 111 */
        .previous_hall_code = 5u, /* Hall 101 */
        .hall_period_ticks = 26000u,
        .bus_voltage_adc = 2708u,
        .phase_current_adc = 2358u,
        .main_duty_counts = 1512u,
    };
    bldc_outputs_t out = { /* poison: every field must be overwritten by the core */
        .turn_on_compare = 0xA5A5u,
        .turn_off_compare = 0xA5A5u,
        .commutation_ticks = 0xA5A5u,
        .turn_on_switch = 0xA5u,
        .turn_off_switch = 0xA5u,
        .sector = 0xA5u,
        .flags = 0xA5u,
    };

    bldc_commutate(&in, &out);

    TEST_ASSERT_UINT16_WITHIN(0u, 0u, out.turn_on_compare);
    TEST_ASSERT_UINT16_WITHIN(0u, 0u, out.turn_off_compare);
    TEST_ASSERT_UINT16_WITHIN(0u, 0u, out.commutation_ticks);
    TEST_ASSERT_EQUAL_HEX8(BLDC_NO_SWITCH, out.turn_on_switch); /* all off */
    TEST_ASSERT_EQUAL_HEX8(BLDC_NO_SWITCH, out.turn_off_switch); /* all off */
    TEST_ASSERT_EQUAL_HEX8(0xFFu, out.sector); /* invalid Hall code */
    TEST_ASSERT_EQUAL_HEX8(BLDC_FLAG_INVALID_HALL, out.flags);
}

/* previous code 000 */
void test_bldc_commutate_should_switch_off_after_hall_000(void)
{
    const bldc_inputs_t in = {
        .hall_code = 4u, /* Hall 100 */
        .previous_hall_code = 0u, /* Hall 000 */
        .hall_period_ticks = 26000u,
        .bus_voltage_adc = 2708u,
        .phase_current_adc = 2358u,
        .main_duty_counts = 1512u,
    };
    bldc_outputs_t out = { /* poison: every field must be overwritten by the core */
        .turn_on_compare = 0xA5A5u,
        .turn_off_compare = 0xA5A5u,
        .commutation_ticks = 0xA5A5u,
        .turn_on_switch = 0xA5u,
        .turn_off_switch = 0xA5u,
        .sector = 0xA5u,
        .flags = 0xA5u,
    };

    bldc_commutate(&in, &out);

    TEST_ASSERT_UINT16_WITHIN(0u, 0u, out.turn_on_compare);
    TEST_ASSERT_UINT16_WITHIN(0u, 0u, out.turn_off_compare);
    TEST_ASSERT_UINT16_WITHIN(0u, 0u, out.commutation_ticks);
    TEST_ASSERT_EQUAL_HEX8(BLDC_NO_SWITCH, out.turn_on_switch); /* all off */
    TEST_ASSERT_EQUAL_HEX8(BLDC_NO_SWITCH, out.turn_off_switch); /* all off */
    TEST_ASSERT_EQUAL_HEX8(0x01u, out.sector);
    TEST_ASSERT_EQUAL_HEX8(BLDC_FLAG_INVALID_HALL, out.flags);
}

/* a jump of two sectors */
void test_bldc_commutate_should_switch_off_on_a_skipped_sector(void)
{
    const bldc_inputs_t in = {
        .hall_code = 6u, /* Hall 110 */
        .previous_hall_code = 5u, /* Hall 101 */
        .hall_period_ticks = 26000u,
        .bus_voltage_adc = 2708u,
        .phase_current_adc = 2358u,
        .main_duty_counts = 1512u,
    };
    bldc_outputs_t out = { /* poison: every field must be overwritten by the core */
        .turn_on_compare = 0xA5A5u,
        .turn_off_compare = 0xA5A5u,
        .commutation_ticks = 0xA5A5u,
        .turn_on_switch = 0xA5u,
        .turn_off_switch = 0xA5u,
        .sector = 0xA5u,
        .flags = 0xA5u,
    };

    bldc_commutate(&in, &out);

    TEST_ASSERT_UINT16_WITHIN(0u, 0u, out.turn_on_compare);
    TEST_ASSERT_UINT16_WITHIN(0u, 0u, out.turn_off_compare);
    TEST_ASSERT_UINT16_WITHIN(0u, 0u, out.commutation_ticks);
    TEST_ASSERT_EQUAL_HEX8(BLDC_NO_SWITCH, out.turn_on_switch); /* all off */
    TEST_ASSERT_EQUAL_HEX8(BLDC_NO_SWITCH, out.turn_off_switch); /* all off */
    TEST_ASSERT_EQUAL_HEX8(0x02u, out.sector);
    TEST_ASSERT_EQUAL_HEX8(BLDC_FLAG_INVALID_HALL, out.flags);
}

/* no sector change */
void test_bldc_commutate_should_switch_off_on_a_repeated_code(void)
{
    const bldc_inputs_t in = {
        .hall_code = 5u, /* Hall 101 */
        .previous_hall_code = 5u, /* Hall 101 */
        .hall_period_ticks = 26000u,
        .bus_voltage_adc = 2708u,
        .phase_current_adc = 2358u,
        .main_duty_counts = 1512u,
    };
    bldc_outputs_t out = { /* poison: every field must be overwritten by the core */
        .turn_on_compare = 0xA5A5u,
        .turn_off_compare = 0xA5A5u,
        .commutation_ticks = 0xA5A5u,
        .turn_on_switch = 0xA5u,
        .turn_off_switch = 0xA5u,
        .sector = 0xA5u,
        .flags = 0xA5u,
    };

    bldc_commutate(&in, &out);

    TEST_ASSERT_UINT16_WITHIN(0u, 0u, out.turn_on_compare);
    TEST_ASSERT_UINT16_WITHIN(0u, 0u, out.turn_off_compare);
    TEST_ASSERT_UINT16_WITHIN(0u, 0u, out.commutation_ticks);
    TEST_ASSERT_EQUAL_HEX8(BLDC_NO_SWITCH, out.turn_on_switch); /* all off */
    TEST_ASSERT_EQUAL_HEX8(BLDC_NO_SWITCH, out.turn_off_switch); /* all off */
    TEST_ASSERT_EQUAL_HEX8(0x00u, out.sector);
    TEST_ASSERT_EQUAL_HEX8(BLDC_FLAG_INVALID_HALL, out.flags);
}

/* not a 3-bit code */
void test_bldc_commutate_should_switch_off_on_a_code_above_7(void)
{
    const bldc_inputs_t in = {
        .hall_code = 9u,
        .previous_hall_code = 5u, /* Hall 101 */
        .hall_period_ticks = 26000u,
        .bus_voltage_adc = 2708u,
        .phase_current_adc = 2358u,
        .main_duty_counts = 1512u,
    };
    bldc_outputs_t out = { /* poison: every field must be overwritten by the core */
        .turn_on_compare = 0xA5A5u,
        .turn_off_compare = 0xA5A5u,
        .commutation_ticks = 0xA5A5u,
        .turn_on_switch = 0xA5u,
        .turn_off_switch = 0xA5u,
        .sector = 0xA5u,
        .flags = 0xA5u,
    };

    bldc_commutate(&in, &out);

    TEST_ASSERT_UINT16_WITHIN(0u, 0u, out.turn_on_compare);
    TEST_ASSERT_UINT16_WITHIN(0u, 0u, out.turn_off_compare);
    TEST_ASSERT_UINT16_WITHIN(0u, 0u, out.commutation_ticks);
    TEST_ASSERT_EQUAL_HEX8(BLDC_NO_SWITCH, out.turn_on_switch); /* all off */
    TEST_ASSERT_EQUAL_HEX8(BLDC_NO_SWITCH, out.turn_off_switch); /* all off */
    TEST_ASSERT_EQUAL_HEX8(0xFFu, out.sector); /* invalid Hall code */
    TEST_ASSERT_EQUAL_HEX8(BLDC_FLAG_INVALID_HALL, out.flags);
}

/* 8 + a valid code, both fields */
void test_bldc_commutate_should_switch_off_on_codes_above_7_that_alias_a_valid_pair(void)
{
    const bldc_inputs_t in = {
        .hall_code = 12u,
        .previous_hall_code = 13u,
        .hall_period_ticks = 26000u,
        .bus_voltage_adc = 2708u,
        .phase_current_adc = 2358u,
        .main_duty_counts = 1512u,
    };
    bldc_outputs_t out = { /* poison: every field must be overwritten by the core */
        .turn_on_compare = 0xA5A5u,
        .turn_off_compare = 0xA5A5u,
        .commutation_ticks = 0xA5A5u,
        .turn_on_switch = 0xA5u,
        .turn_off_switch = 0xA5u,
        .sector = 0xA5u,
        .flags = 0xA5u,
    };

    bldc_commutate(&in, &out);

    TEST_ASSERT_UINT16_WITHIN(0u, 0u, out.turn_on_compare);
    TEST_ASSERT_UINT16_WITHIN(0u, 0u, out.turn_off_compare);
    TEST_ASSERT_UINT16_WITHIN(0u, 0u, out.commutation_ticks);
    TEST_ASSERT_EQUAL_HEX8(BLDC_NO_SWITCH, out.turn_on_switch); /* all off */
    TEST_ASSERT_EQUAL_HEX8(BLDC_NO_SWITCH, out.turn_off_switch); /* all off */
    TEST_ASSERT_EQUAL_HEX8(0xFFu, out.sector); /* invalid Hall code */
    TEST_ASSERT_EQUAL_HEX8(BLDC_FLAG_INVALID_HALL, out.flags);
}

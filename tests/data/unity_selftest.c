/* Self-test of the Unity stand-in (verify/unity_standin), or of real Unity when
 * UNITY_DIR is set: every assertion the generated tests may use, passing once and
 * failing once, so tests/test_unity.py can check the printed format, the per-test
 * verdicts and the exit status (the number of failed tests) on host and target. */
#include <stdint.h>

#include "unity.h"

static uint16_t set_up_calls;

void setUp(void)
{
    set_up_calls++;
}

void tearDown(void)
{
}

static void test_every_assertion_should_pass(void)
{
    const uint16_t reading = 102u;
    TEST_ASSERT_UINT16_WITHIN(2u, 100u, reading);
    TEST_ASSERT_UINT16_WITHIN(2u, 104u, reading);
    TEST_ASSERT_EQUAL_UINT16(65535u, 65535u);
    TEST_ASSERT_EQUAL_HEX8(0xA5u, 0xA5u);
    TEST_ASSERT_EQUAL_INT(-7, -7);
    TEST_ASSERT_TRUE(reading == 102u);
    TEST_ASSERT_FALSE(reading == 0u);
    TEST_ASSERT_EQUAL_UINT16(1u, set_up_calls); /* setUp ran before this test */
}

static void test_within_should_fail_above(void)
{
    TEST_ASSERT_UINT16_WITHIN(2u, 100u, 103u);
    TEST_FAIL_MESSAGE("not reached: a failed assertion leaves the test");
}

static void test_within_should_fail_below(void)
{
    TEST_ASSERT_UINT16_WITHIN(0u, 65535u, 0u);
}

static void test_equal_uint16_should_fail(void)
{
    TEST_ASSERT_EQUAL_UINT16(1u, 65535u);
}

static void test_equal_hex8_should_fail(void)
{
    TEST_ASSERT_EQUAL_HEX8(0x0Fu, 0xF0u);
}

static void test_equal_int_should_fail(void)
{
    TEST_ASSERT_EQUAL_INT(-2147483647 - 1, 5);
}

static void test_true_should_fail(void)
{
    TEST_ASSERT_TRUE(set_up_calls == 0u);
}

static void test_fail_message_should_fail(void)
{
    TEST_FAIL_MESSAGE("explicit failure");
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_every_assertion_should_pass);
    RUN_TEST(test_within_should_fail_above);
    RUN_TEST(test_within_should_fail_below);
    RUN_TEST(test_equal_uint16_should_fail);
    RUN_TEST(test_equal_hex8_should_fail);
    RUN_TEST(test_equal_int_should_fail);
    RUN_TEST(test_true_should_fail);
    RUN_TEST(test_fail_message_should_fail);
    return UNITY_END();
}

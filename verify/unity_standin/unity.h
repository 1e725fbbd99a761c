/*
 * STAND-IN, NOT ThrowTheSwitch Unity.
 *
 * A small, independent implementation of the subset of Unity's public test API that the
 * generated tests (generated/<spec>/tests/) use, written for this project from Unity's
 * documented macros and output format. It contains no Unity source code. When the
 * environment variable UNITY_DIR points to a Unity checkout, verify/unity_run.py builds
 * against the real Unity (UNITY_DIR/src/unity.c) instead of this folder.
 *
 * Why a stand-in: the verifier must run on a fresh machine that reaches no source host,
 * on the host (with sanitizers) and on a Cortex-M3 under qemu, without libc on target.
 *
 * Supported: UNITY_BEGIN, UNITY_END, RUN_TEST, TEST_ASSERT_UINT16_WITHIN,
 * TEST_ASSERT_EQUAL_HEX8, TEST_ASSERT_EQUAL_UINT16, TEST_ASSERT_EQUAL_INT,
 * TEST_ASSERT_TRUE, TEST_ASSERT_FALSE, TEST_FAIL_MESSAGE, TEST_FAIL.
 *
 * Output, as Unity prints it: one line per test, `file:line:test_name:PASS` or
 * `file:line:test_name:FAIL: message`, then a line of dashes,
 * `N Tests M Failures 0 Ignored ` and `OK` or `FAIL`. As in Unity without setjmp, a
 * failed assertion returns from the test function; the first failure is reported.
 *
 * Characters go out through one hook, Unity's own configuration macro:
 * UNITY_OUTPUT_CHAR(c) (default: putchar from <stdio.h>). For a bare-metal target define
 * UNITY_OUTPUT_CHAR=my_putchar and UNITY_OUTPUT_CHAR_HEADER_DECLARATION=my_putchar(int),
 * with `void my_putchar(int)`: then this runner needs no libc at all.
 * No dynamic memory, no floating point, C99.
 */
#ifndef UNITY_STANDIN_H
#define UNITY_STANDIN_H

#include <stdint.h>

/* Provided by the test file: run around every test. */
void setUp(void);
void tearDown(void);

typedef void (*unity_standin_test_t)(void);

void unity_standin_begin(const char *file);
int unity_standin_end(void);
void unity_standin_run(unity_standin_test_t test, const char *name, int line);

/* Each check returns 1 (and reports) when it fails, so the macro can leave the test. */
int unity_standin_check_within(uint32_t delta, uint32_t expected, uint32_t actual, int line);
int unity_standin_check_equal_unsigned(uint32_t expected, uint32_t actual, int line);
int unity_standin_check_equal_signed(int32_t expected, int32_t actual, int line);
int unity_standin_check_equal_hex(uint32_t expected, uint32_t actual, unsigned hex_digits,
                                  int line);
int unity_standin_check_true(int condition, const char *expectation, int line);
void unity_standin_fail(const char *message, int line);

#define UNITY_STANDIN_LEAVE_IF(failed) \
    do {                               \
        if (failed) {                  \
            return;                    \
        }                              \
    } while (0)

#define UNITY_BEGIN() unity_standin_begin(__FILE__)
#define UNITY_END() unity_standin_end()
#define RUN_TEST(func) unity_standin_run(func, #func, __LINE__)

/* |expected - actual| <= delta, both taken as uint16 (Unity's semantics). */
#define TEST_ASSERT_UINT16_WITHIN(delta, expected, actual)                                 \
    UNITY_STANDIN_LEAVE_IF(unity_standin_check_within((uint32_t)(uint16_t)(delta),         \
                                                      (uint32_t)(uint16_t)(expected),      \
                                                      (uint32_t)(uint16_t)(actual), __LINE__))
#define TEST_ASSERT_EQUAL_UINT16(expected, actual)                                         \
    UNITY_STANDIN_LEAVE_IF(unity_standin_check_equal_unsigned(                             \
        (uint32_t)(uint16_t)(expected), (uint32_t)(uint16_t)(actual), __LINE__))
#define TEST_ASSERT_EQUAL_HEX8(expected, actual)                                           \
    UNITY_STANDIN_LEAVE_IF(unity_standin_check_equal_hex(                                  \
        (uint32_t)(uint8_t)(expected), (uint32_t)(uint8_t)(actual), 2u, __LINE__))
#define TEST_ASSERT_EQUAL_INT(expected, actual)                                            \
    UNITY_STANDIN_LEAVE_IF(                                                                \
        unity_standin_check_equal_signed((int32_t)(expected), (int32_t)(actual), __LINE__))
#define TEST_ASSERT_TRUE(condition) \
    UNITY_STANDIN_LEAVE_IF(unity_standin_check_true((condition) ? 1 : 0, "TRUE", __LINE__))
#define TEST_ASSERT_FALSE(condition) \
    UNITY_STANDIN_LEAVE_IF(unity_standin_check_true((condition) ? 0 : 1, "FALSE", __LINE__))
#define TEST_FAIL_MESSAGE(message)               \
    do {                                         \
        unity_standin_fail((message), __LINE__); \
        return;                                  \
    } while (0)
#define TEST_FAIL() TEST_FAIL_MESSAGE("")

#endif /* UNITY_STANDIN_H */

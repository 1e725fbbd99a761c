/*
 * STAND-IN, NOT ThrowTheSwitch Unity: see unity.h. Written for this project from Unity's
 * documented behaviour; it contains no Unity source code.
 */
#include "unity.h"

#ifndef UNITY_OUTPUT_CHAR
#include <stdio.h>
#define UNITY_OUTPUT_CHAR(c) ((void)putchar(c))
#ifndef UNITY_OUTPUT_FLUSH
#define UNITY_OUTPUT_FLUSH() ((void)fflush(stdout))
#endif
#elif defined(UNITY_OUTPUT_CHAR_HEADER_DECLARATION)
extern void UNITY_OUTPUT_CHAR_HEADER_DECLARATION;
#endif
#ifndef UNITY_OUTPUT_FLUSH
#define UNITY_OUTPUT_FLUSH() ((void)0)
#endif

/* All runner state: one static record, no dynamic memory. */
static struct {
    const char *file;      /* UNITY_BEGIN's __FILE__, as Unity reports it */
    const char *test_name; /* test being run */
    int test_line;         /* RUN_TEST's line: where a passing test is reported */
    uint32_t tests;
    uint32_t failures;
    int current_failed;
} unity_standin;

static void print_char(char c)
{
    UNITY_OUTPUT_CHAR((int)(unsigned char)c);
}

static void print_text(const char *text)
{
    while (*text != '\0') {
        print_char(*text++);
    }
}

static void print_unsigned(uint32_t value)
{
    char digits[10]; /* 4294967295 */
    unsigned count = 0u;
    do {
        digits[count++] = (char)('0' + (char)(value % 10u));
        value /= 10u;
    } while (value != 0u);
    while (count > 0u) {
        print_char(digits[--count]);
    }
}

static void print_signed(int32_t value)
{
    if (value < 0) {
        print_char('-');
        /* two's complement magnitude, also right for INT32_MIN */
        print_unsigned(0u - (uint32_t)value);
    } else {
        print_unsigned((uint32_t)value);
    }
}

static void print_hex(uint32_t value, unsigned hex_digits)
{
    static const char nibble_char[16] = {'0', '1', '2', '3', '4', '5', '6', '7',
                                         '8', '9', 'A', 'B', 'C', 'D', 'E', 'F'};
    print_text("0x");
    while (hex_digits > 0u) {
        --hex_digits;
        print_char(nibble_char[(value >> (4u * hex_digits)) & 0xFu]);
    }
}

static void print_location(int line)
{
    print_text(unity_standin.file);
    print_char(':');
    print_signed((int32_t)line);
    print_char(':');
    print_text(unity_standin.test_name);
    print_char(':');
}

/* "file:line:test:FAIL" — the caller prints ": reason" and ends the line. */
static void begin_failure(int line)
{
    unity_standin.current_failed = 1;
    print_location(line);
    print_text("FAIL");
}

static void end_line(void)
{
    print_char('\n');
    UNITY_OUTPUT_FLUSH();
}

void unity_standin_begin(const char *file)
{
    unity_standin.file = file;
    unity_standin.test_name = "";
    unity_standin.test_line = 0;
    unity_standin.tests = 0u;
    unity_standin.failures = 0u;
    unity_standin.current_failed = 0;
}

void unity_standin_run(unity_standin_test_t test, const char *name, int line)
{
    unity_standin.test_name = name;
    unity_standin.test_line = line;
    unity_standin.current_failed = 0;
    unity_standin.tests++;
    setUp();
    if (!unity_standin.current_failed) {
        test();
    }
    tearDown();
    if (unity_standin.current_failed) {
        unity_standin.failures++;
    } else {
        print_location(line);
        print_text("PASS");
        end_line();
    }
}

int unity_standin_end(void)
{
    print_text("\n-----------------------\n");
    print_unsigned(unity_standin.tests);
    print_text(" Tests ");
    print_unsigned(unity_standin.failures);
    print_text(" Failures 0 Ignored \n");
    print_text(unity_standin.failures == 0u ? "OK" : "FAIL");
    end_line();
    return (int)unity_standin.failures;
}

int unity_standin_check_within(uint32_t delta, uint32_t expected, uint32_t actual, int line)
{
    const uint32_t difference = expected > actual ? expected - actual : actual - expected;
    if (difference <= delta) {
        return 0;
    }
    begin_failure(line);
    print_text(": Values Not Within Delta ");
    print_unsigned(delta);
    print_text(" Expected ");
    print_unsigned(expected);
    print_text(" Was ");
    print_unsigned(actual);
    end_line();
    return 1;
}

int unity_standin_check_equal_unsigned(uint32_t expected, uint32_t actual, int line)
{
    if (expected == actual) {
        return 0;
    }
    begin_failure(line);
    print_text(": Expected ");
    print_unsigned(expected);
    print_text(" Was ");
    print_unsigned(actual);
    end_line();
    return 1;
}

int unity_standin_check_equal_signed(int32_t expected, int32_t actual, int line)
{
    if (expected == actual) {
        return 0;
    }
    begin_failure(line);
    print_text(": Expected ");
    print_signed(expected);
    print_text(" Was ");
    print_signed(actual);
    end_line();
    return 1;
}

int unity_standin_check_equal_hex(uint32_t expected, uint32_t actual, unsigned hex_digits,
                                  int line)
{
    if (expected == actual) {
        return 0;
    }
    begin_failure(line);
    print_text(": Expected ");
    print_hex(expected, hex_digits);
    print_text(" Was ");
    print_hex(actual, hex_digits);
    end_line();
    return 1;
}

int unity_standin_check_true(int condition, const char *expectation, int line)
{
    if (condition) {
        return 0;
    }
    begin_failure(line);
    print_text(": Expected ");
    print_text(expectation);
    print_text(" Was ");
    print_text(expectation[0] == 'T' ? "FALSE" : "TRUE");
    end_line();
    return 1;
}

void unity_standin_fail(const char *message, int line)
{
    begin_failure(line);
    if (message[0] != '\0') {
        print_text(": ");
        print_text(message);
    }
    end_line();
}

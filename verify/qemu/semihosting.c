/*
 * ARM semihosting calls (ARM "Semihosting for AArch32 and AArch64", version 2): on
 * M-profile the call is `bkpt 0xab` with the operation in r0 and its argument in r1.
 */
#include "semihosting.h"

#define SYS_WRITE0 0x04u
#define SYS_EXIT 0x18u
#define SYS_EXIT_EXTENDED 0x20u
#define ADP_STOPPED_APPLICATION_EXIT 0x20026u
#define ADP_STOPPED_RUN_TIME_ERROR 0x20023u
#define LINE_CAPACITY 160u

static char line_buffer[LINE_CAPACITY + 1u]; /* + NUL for SYS_WRITE0 */
static uint32_t line_length;

static uint32_t semihosting_call(uint32_t operation, const void *argument)
{
    uint32_t result;
    __asm__ volatile("mov r0, %1\n\t"
                     "mov r1, %2\n\t"
                     "bkpt 0xab\n\t"
                     "mov %0, r0"
                     : "=r"(result)
                     : "r"(operation), "r"(argument)
                     : "r0", "r1", "memory");
    return result;
}

void semihosting_flush(void)
{
    if (line_length > 0u) {
        line_buffer[line_length] = '\0';
        (void)semihosting_call(SYS_WRITE0, line_buffer);
        line_length = 0u;
    }
}

void semihosting_putchar(int c)
{
    if (c == '\0') {
        return; /* SYS_WRITE0 would stop there */
    }
    line_buffer[line_length++] = (char)c;
    if (c == '\n' || line_length == LINE_CAPACITY) {
        semihosting_flush();
    }
}

void semihosting_exit(uint32_t status)
{
    /* SYS_EXIT_EXTENDED carries the status; qemu ends with it. */
    const uint32_t block[2] = {ADP_STOPPED_APPLICATION_EXIT, status};
    semihosting_flush();
    (void)semihosting_call(SYS_EXIT_EXTENDED, block);
    /* A host without the extension: SYS_EXIT passes only success or failure. */
    (void)semihosting_call(SYS_EXIT, (const void *)(uintptr_t)(status == 0u
                                                                   ? ADP_STOPPED_APPLICATION_EXIT
                                                                   : ADP_STOPPED_RUN_TIME_ERROR));
    for (;;) {
    }
}

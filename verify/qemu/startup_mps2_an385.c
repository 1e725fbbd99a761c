/*
 * Start-up for the Unity runs on qemu-system-arm -machine mps2-an385 (Cortex-M3):
 * vector table, .data copy, .bss clear, main(), then main's return value as the
 * emulator's exit status through semihosting. Any fault ends the run with status 255
 * and a message, so a crash in the code under test cannot pass as a hang or a success.
 */
#include <stddef.h>
#include <stdint.h>

#include "semihosting.h"

#define FAULT_EXIT_STATUS 255u
#define STARTUP_EXIT_STATUS 254u
#define DATA_CANARY 0x5EED1234u

extern uint32_t __stack_top, __data_load, __data_start, __data_end, __bss_start, __bss_end;
int main(void);
void Reset_Handler(void);
void Fault_Handler(void);

/* Proof that start-up ran: one word that must come from .data, one from .bss. */
static volatile uint32_t data_canary = DATA_CANARY;
static volatile uint32_t bss_canary;

static void report(const char *text)
{
    while (*text != '\0') {
        semihosting_putchar(*text++);
    }
    semihosting_flush();
}

void Fault_Handler(void)
{
    report("\nmps2-an385: fault exception in the code under test\n");
    semihosting_exit(FAULT_EXIT_STATUS);
}

void Reset_Handler(void)
{
    const uint32_t *src = &__data_load;
    for (uint32_t *dst = &__data_start; dst < &__data_end; ++dst) {
        *dst = *src++;
    }
    for (uint32_t *dst = &__bss_start; dst < &__bss_end; ++dst) {
        *dst = 0u;
    }
    if (data_canary != DATA_CANARY || bss_canary != 0u) {
        report("mps2-an385: .data or .bss not initialised\n");
        semihosting_exit(STARTUP_EXIT_STATUS);
    }
    semihosting_exit((uint32_t)main());
}

/* The freestanding compiler may call these for structure copies and clears. */
void *memcpy(void *restrict destination, const void *restrict source, size_t size);
void *memset(void *destination, int value, size_t size);

void *memcpy(void *restrict destination, const void *restrict source, size_t size)
{
    unsigned char *d = destination;
    const unsigned char *s = source;
    while (size-- > 0u) {
        *d++ = *s++;
    }
    return destination;
}

void *memset(void *destination, int value, size_t size)
{
    unsigned char *d = destination;
    while (size-- > 0u) {
        *d++ = (unsigned char)value;
    }
    return destination;
}

/* Initial stack pointer, reset, then the Cortex-M3 system exceptions (NMI to SysTick):
 * all of them end the run; the tests use no interrupts. */
typedef void (*vector_t)(void);
typedef union {
    vector_t handler;
    uint32_t *stack;
} vector_entry_t;
__attribute__((section(".isr_vector"), used)) static const vector_entry_t vectors[16] = {
    {.stack = &__stack_top},      {.handler = Reset_Handler},   {.handler = Fault_Handler},
    {.handler = Fault_Handler},   {.handler = Fault_Handler},   {.handler = Fault_Handler},
    {.handler = Fault_Handler},   {.handler = Fault_Handler},   {.handler = Fault_Handler},
    {.handler = Fault_Handler},   {.handler = Fault_Handler},   {.handler = Fault_Handler},
    {.handler = Fault_Handler},   {.handler = Fault_Handler},   {.handler = Fault_Handler},
    {.handler = Fault_Handler},
};

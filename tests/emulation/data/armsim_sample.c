/* Sample for tests/test_armsim.py: small functions with known results, instruction
 * counts and cycle costs, compiled for a Cortex-M3 by the test itself. The naked
 * functions fix their instruction sequences so exact cycle counts can be asserted. */
#include <stdint.h>

#define TIM1_CCR1 (*(volatile uint32_t *)0x40012C34u)
#define NVIC_ISER0 (*(volatile uint32_t *)0xE000E100u)

uint32_t sample_counter = 5u; /* .data: initialised by the image */
uint32_t sample_calls;        /* .bss: zero */

uint32_t add3(uint32_t a, uint32_t b, uint32_t c)
{
    return a + b + c;
}

uint32_t sum_to(uint32_t n)
{
    uint32_t sum = 0u;
    for (uint32_t i = 1u; i <= n; i++) {
        sum += i;
    }
    return sum;
}

uint32_t div(uint32_t a, uint32_t b)
{
    return a / b;
}

void poke(void)
{
    TIM1_CCR1 = 123u;
}

uint32_t read_capture(void)
{
    return TIM1_CCR1;
}

void enable_irq25(void)
{
    NVIC_ISER0 = 1u << 25;
}

uint32_t count_call(void)
{
    sample_calls += 1u;
    return sample_counter + sample_calls;
}

uint32_t read_nowhere(void)
{
    return *(volatile uint32_t *)0x50000000u;
}

void write_flash(void)
{
    *(volatile uint32_t *)0x08000000u = 1u;
}

void jump_nowhere(void)
{
    ((void (*)(void))0x30000001u)();
}

void spin(void)
{
    for (;;) {
    }
}

/* cmp 1, ite 1, one of moveq/addne 1 and the other skipped 1, bx lr 1 + P. */
__attribute__((naked)) uint32_t it_select(uint32_t a, uint32_t b)
{
    __asm__ volatile("cmp r0, r1\n"
                     "ite eq\n"
                     "moveq r0, #7\n"
                     "addne r0, r0, r1\n"
                     "bx lr\n");
}

/* push {r4, lr} 1 + 2, umull 5, pop {r4, pc} 1 + 2 + P. */
__attribute__((naked)) uint32_t multiply_high(uint32_t a, uint32_t b)
{
    __asm__ volatile("push {r4, lr}\n"
                     "umull r4, r0, r0, r1\n"
                     "pop {r4, pc}\n");
}

/* Two stores to one register: the second replaces the first in plain memory, not in a
 * set-pending or an rc_w0 register. */
void store_twice(volatile uint32_t *reg, uint32_t first, uint32_t second)
{
    *reg = first;
    *reg = second;
}

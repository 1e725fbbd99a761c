/* Generated from template templates/firmware/startup_stm32f103.c.j2 with spec spec/example_maxon_ec45_flat_48v.yaml (sha256 8b5f5d50b8448d3cbaa1fb633cc60b872c18290557700779debfaeb46d86d548). Do not edit: regenerate with `make`. */
/* Minimal start-up for the project's own firmware build: vector table with the
 * CMSIS handler names, .data copy, .bss clear, then main(). A Cube project uses its
 * own start-up file instead; the port's handlers drop into it by name. */
#include <stdint.h>

extern uint32_t _estack, _etext, _sdata, _edata, _sbss, _ebss;
int main(void);
void Reset_Handler(void);
void Default_Handler(void);
void TIM1_TRG_COM_IRQHandler(void);
void TIM3_IRQHandler(void);

void Default_Handler(void)
{
    for (;;) {
    }
}

void Reset_Handler(void)
{
    const uint32_t *src = &_etext;
    for (uint32_t *dst = &_sdata; dst < &_edata; ++dst) {
        *dst = *src++;
    }
    for (uint32_t *dst = &_sbss; dst < &_ebss; ++dst) {
        *dst = 0u;
    }
    (void)main();
    for (;;) {
    }
}

/* 16 system exceptions, then the STM32F103xB's 43 peripheral interrupts (RM0008
 * Table 63); the port's: TIM1_TRG_COM_IRQHandler at IRQ 26 (SVD TIM1_TRG_COM_TIM11), TIM3_IRQHandler at IRQ 29 (SVD TIM3). */
typedef void (*vector_t)(void);
typedef union {
    vector_t handler;
    uint32_t *stack;
} vector_entry_t;
__attribute__((section(".isr_vector"), used)) static const vector_entry_t vectors[59] = {
    {.stack = &_estack},
    {.handler = Reset_Handler},
    {.handler = Default_Handler},
    {.handler = Default_Handler},
    {.handler = Default_Handler},
    {.handler = Default_Handler},
    {.handler = Default_Handler},
    {.handler = Default_Handler},
    {.handler = Default_Handler},
    {.handler = Default_Handler},
    {.handler = Default_Handler},
    {.handler = Default_Handler},
    {.handler = Default_Handler},
    {.handler = Default_Handler},
    {.handler = Default_Handler},
    {.handler = Default_Handler},
    {.handler = Default_Handler},
    {.handler = Default_Handler},
    {.handler = Default_Handler},
    {.handler = Default_Handler},
    {.handler = Default_Handler},
    {.handler = Default_Handler},
    {.handler = Default_Handler},
    {.handler = Default_Handler},
    {.handler = Default_Handler},
    {.handler = Default_Handler},
    {.handler = Default_Handler},
    {.handler = Default_Handler},
    {.handler = Default_Handler},
    {.handler = Default_Handler},
    {.handler = Default_Handler},
    {.handler = Default_Handler},
    {.handler = Default_Handler},
    {.handler = Default_Handler},
    {.handler = Default_Handler},
    {.handler = Default_Handler},
    {.handler = Default_Handler},
    {.handler = Default_Handler},
    {.handler = Default_Handler},
    {.handler = Default_Handler},
    {.handler = Default_Handler},
    {.handler = Default_Handler},
    {.handler = TIM1_TRG_COM_IRQHandler},
    {.handler = Default_Handler},
    {.handler = Default_Handler},
    {.handler = TIM3_IRQHandler},
    {.handler = Default_Handler},
    {.handler = Default_Handler},
    {.handler = Default_Handler},
    {.handler = Default_Handler},
    {.handler = Default_Handler},
    {.handler = Default_Handler},
    {.handler = Default_Handler},
    {.handler = Default_Handler},
    {.handler = Default_Handler},
    {.handler = Default_Handler},
    {.handler = Default_Handler},
    {.handler = Default_Handler},
    {.handler = Default_Handler},
};

/* Generated from template templates/firmware/startup_stm32f103.c.j2 with spec spec/paper_motor_improved_r.yaml (sha256 9f5d9c8963649549b4e129e1bd9cd35baa3c8e343f67f4b67f06c6141ed1f434). Do not edit: regenerate with `bldc-codegen generate spec/paper_motor_improved_r.yaml`. */
/* Minimal start-up for the project's own firmware build: vector table with the
 * CMSIS handler names, .data copy, .bss clear, then main(). A Cube project uses its
 * own start-up file instead; the port's handlers drop into it by name. */
#include <stdint.h>

#include "stm32f103_port.h"
#include "stm32f103_regs.h"

extern uint32_t _estack, _etext, _sdata, _edata, _sbss, _ebss;
int main(void);
void Reset_Handler(void);
void Default_Handler(void);
void NMI_Handler(void);
void HardFault_Handler(void);
void TIM1_TRG_COM_IRQHandler(void);
void TIM1_UP_IRQHandler(void);
void TIM3_IRQHandler(void);
void ADC1_2_IRQHandler(void);
void TIM1_BRK_IRQHandler(void);
void EXTI0_IRQHandler(void);
void EXTI9_5_IRQHandler(void);

void Default_Handler(void)
{
    for (;;) {
    }
}

/* The clock security system reports an HSE failure by the NMI (RM0008 7.2.7). */
void NMI_Handler(void)
{
    if ((RCC->CIR & RCC_CIR_CSSF) != 0u) {
        RCC->CIR = RCC_CIR_CSSC;
        bldc_port_clock_failure();
    }
}

/* Nothing can go on: the bridge's outputs to their idle level, then the watchdog. */
void HardFault_Handler(void)
{
    bldc_port_emergency_off();
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
 * Table 63); the port's: TIM1_TRG_COM_IRQHandler at IRQ 26 (SVD TIM1_TRG_COM_TIM11), TIM1_UP_IRQHandler at IRQ 25 (SVD TIM1_UP_TIM10), TIM3_IRQHandler at IRQ 29 (SVD TIM3), ADC1_2_IRQHandler at IRQ 18 (SVD ADC), TIM1_BRK_IRQHandler at IRQ 24 (SVD TIM1_BRK_TIM9), EXTI0_IRQHandler at IRQ 6 (SVD EXTI0), EXTI9_5_IRQHandler at IRQ 23 (SVD EXTI9_5). */
typedef void (*vector_t)(void);
typedef union {
    vector_t handler;
    uint32_t *stack;
} vector_entry_t;
__attribute__((section(".isr_vector"), used)) static const vector_entry_t vectors[59] = {
    {.stack = &_estack},
    {.handler = Reset_Handler},
    {.handler = NMI_Handler},
    {.handler = HardFault_Handler},
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
    {.handler = EXTI0_IRQHandler},
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
    {.handler = ADC1_2_IRQHandler},
    {.handler = Default_Handler},
    {.handler = Default_Handler},
    {.handler = Default_Handler},
    {.handler = Default_Handler},
    {.handler = EXTI9_5_IRQHandler},
    {.handler = TIM1_BRK_IRQHandler},
    {.handler = TIM1_UP_IRQHandler},
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

/* Generated from template c/stm32f103_port.h.j2 with spec spec/paper_motor.yaml (sha256 07b8685d3a2684e5f837564446d9717554545097976668f5f4050212bf8dcce5). Do not edit: regenerate with `make`. */
#ifndef STM32F103_PORT_H
#define STM32F103_PORT_H

/*
 * STM32F103 port of the braking commutation core: reads the Hall timer and the
 * latest ADC values, calls bldc_commutate_edge() and writes TIM1. No floating point, no
 * division, no dynamic memory.
 *
 * Resources (default pin mapping, no AFIO remap)
 *   TIM1  20 kHz edge-aligned PWM, complementary outputs, commutation by COM event
 *         PA8  TIM1_CH1  T1, phase A upper
 *         PA9  TIM1_CH2  T3, phase B upper
 *         PA10  TIM1_CH3  T5, phase C upper
 *         PB13  TIM1_CH1N  T2, phase A lower
 *         PB14  TIM1_CH2N  T4, phase B lower
 *         PB15  TIM1_CH3N  T6, phase C lower
 *   TIM3  Hall-sensor interface: CH1..CH3 XOR (CR2.TI1S), 1 MHz ticks,
 *         counter reset and CC1 capture at each Hall edge (the 60 degree interval),
 *         CC2 compare for the end of the commutation (paper Eq. 20)
 *         PA6  TIM3_CH1  Hall A, code bit 2 (input, pull-up)
 *         PA7  TIM3_CH2  Hall B, code bit 1 (input, pull-up)
 *         PB0  TIM3_CH3  Hall C, code bit 0 (input, pull-up)
 *   TIM3_IRQHandler: Hall edge (CC1), commutation end (CC2); a Hall timeout (update
 *         flag, no interrupt) is read by the next edge
 *
 * The port never drives both switches of one phase: each phase has at most one of
 * CCxE / CCxNE set, and a request that would move a phase from its upper to its lower
 * switch (or back) in one COM event turns every output off instead (no dead time is
 * inserted between the two in single-output mode, RM0008 Table 83).
 *
 * Clocks assumed: TIM1 at 72 MHz (APB2 timer clock), TIM3 at
 * 72 MHz (APB1 timer clock, which RM0008 7.2 doubles when APB1 is
 * prescaled). Set up the RCC clock tree before calling bldc_port_init().
 */

#include <stdint.h>

#include "bldc_commutation.h"

#define BLDC_PORT_TIM1_PSC 0u /* TIM1 counts at the full 72 MHz timer clock */
#define BLDC_PORT_TIM1_ARR 3599u /* 20 kHz edge-aligned at 72 MHz */
#define BLDC_PORT_TIM1_CMS 0u /* CR1.CMS: edge-aligned */
#define BLDC_PORT_DUTY_FULL_SCALE 3600u /* CCRx for 100 % duty = ARR + 1: PWM mode 1 upcounting is active while CNT < CCRx */
#define BLDC_PORT_TIM1_DTG 0x24u /* dead time 500 ns requested, 36 t_DTS = 500 ns programmed (t_DTS = 1 / 72 MHz) */
#define BLDC_PORT_TIM3_PSC 71u /* Hall timer ticks at 1 MHz from 72 MHz */
#define BLDC_PORT_TIM3_ARR 65535u /* 16-bit Hall counter: overflows 65.54 ms after the last edge, and a longer interval reads as this value */
#define BLDC_PORT_TIM3_IC1F 3u /* Hall input filter: 8 equal samples at 72 MHz, ignores glitches shorter than 111.1 ns and delays each edge as much */

/*
 * Inputs from outside the port.
 *
 * bldc_port_set_bus_voltage(): the latest bus-voltage ADC result in counts. It
 * saturates the code and computes the bus voltage's reciprocals (bldc_bus_condition(),
 * three hardware divides), so the Hall edge only multiplies and divides by the speed.
 * Call it whenever the bus voltage is sampled (a few hundred Hz is plenty: the bus
 * changes slowly), from thread mode or any interrupt that cannot preempt
 * TIM3_IRQHandler. Until the first call the bridge stays off (treated as over-voltage).
 *
 * bldc_adc_phase_current: latest ADC result of the commutated phase current I in
 * counts, written by the user's ADC conversion-complete interrupt or as the destination
 * of a circular DMA (16-bit half-word transfers). The Hall edge reads it once.
 *
 * bldc_port_set_main_duty(): output of the braking current controller, in TIM1
 * counts 0..BLDC_PWM_PERIOD_COUNTS (larger values are clamped). It takes effect from the
 * next PWM period when no commutation is running, and at the end of each commutation.
 * Callable from thread mode or any interrupt: it masks interrupts (PRIMASK) for the
 * few instructions that touch the port's state.
 */
void bldc_port_set_bus_voltage(uint16_t adc_code);
void bldc_port_set_main_duty(uint16_t duty_counts);
extern volatile uint16_t bldc_adc_phase_current;

/* Enable the clocks of GPIOA, GPIOB, TIM1 and TIM3, configure TIM1 (PWM, dead time,
 * all outputs off, MOE set) and TIM3 (Hall interface), set up the pins and enable
 * TIM3_IRQn. The bridge stays off until the first Hall edge. */
void bldc_port_init(void);

/* Vector table entry (CMSIS/Cube name): Hall edge, commutation end, Hall timeout. */
void TIM3_IRQHandler(void);

#endif /* STM32F103_PORT_H */

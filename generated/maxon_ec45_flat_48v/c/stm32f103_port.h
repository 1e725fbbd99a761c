/* Generated from template c/stm32f103_port.h.j2 with spec spec/example_maxon_ec45_flat_48v.yaml (sha256 8b5f5d50b8448d3cbaa1fb633cc60b872c18290557700779debfaeb46d86d548). Do not edit: regenerate with `make`. */
#ifndef STM32F103_PORT_H
#define STM32F103_PORT_H

/*
 * STM32F103 port of the braking commutation core: reads the Hall timer and the
 * latest ADC values, runs the core and writes TIM1. No floating point, no library
 * division helpers, no dynamic memory.
 *
 * Compute ahead. The Hall edge has no time for divides, so it applies duties and a
 * commutation time computed before it: right after each Hall edge, at a lower
 * priority, TIM1_TRG_COM_IRQHandler runs bldc_commutation_timing() on the interval
 * just measured, the latest current and main duty, for the next edge. The speed the
 * next commutation is computed for is therefore one 60 degree interval old; at a
 * constant speed (the paper's assumption through a commutation) it is the same, and
 * while braking decelerates the drive the relative error is the relative speed change
 * over one sector. The edge itself still checks, with what it has just measured: the
 * Hall code pair (invalid code or sequence) and the interval (over-speed) put every
 * switch off at once.
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
 *         flag, no interrupt) is read by the next edge. Priority BLDC_PORT_HALL_PRIORITY.
 *         Runs from SRAM with its pin table: section .RamFunc, which the linker script
 *         must place in .data for the start-up code to copy (STM32Cube's scripts do;
 *         define BLDC_PORT_HALL_EDGE_IN_FLASH to 1 to keep it in flash instead).
 *   TIM1_TRG_COM_IRQHandler: the next edge's duties and commutation time, raised by
 *         every COM event (DIER.COMIE: each Hall edge and each commutation end) and
 *         pended by software (NVIC set-pending) when the bus voltage or main duty changes.
 *         Priority BLDC_PORT_TIMING_PRIORITY, lower than the Hall edge's.
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
#define BLDC_PORT_BUS_CODE_MAX 3546u /* the core's over-voltage threshold, 59.99 V: crossing it always recomputes, whatever the hysteresis */
#define BLDC_PORT_TIM3_IC1F 3u /* Hall input filter: 8 equal samples at 72 MHz, ignores glitches shorter than 111.1 ns and delays each edge as much */

/* NVIC priorities (0 is the most urgent; the STM32F103 implements 4 bits). Define them
 * before including this header to fit another interrupt plan; the Hall edge must stay
 * more urgent than the timing. */
#ifndef BLDC_PORT_HALL_PRIORITY
#define BLDC_PORT_HALL_PRIORITY 1u
#endif
#ifndef BLDC_PORT_TIMING_PRIORITY
#define BLDC_PORT_TIMING_PRIORITY 2u
#endif
#if BLDC_PORT_HALL_PRIORITY >= BLDC_PORT_TIMING_PRIORITY
#error "the Hall edge must preempt the timing computation"
#endif

/* Bus codes a new bus-voltage sample may differ from the code the timing uses before
 * the port recomputes the bus state (bldc_bus_condition(), five divides): the default
 * 1 code = 16.92 mV keeps one code of ADC noise from costing a recomputation.
 * The price: the duties are computed for a bus voltage up to that much off the latest
 * sample, which moves them by up to 3.62 counts at the top speed and
 * the lowest bus voltage (X = 4PE/U_d); define 0 to recompute on every change. Crossing
 * the over-voltage threshold BLDC_PORT_BUS_CODE_MAX recomputes whatever the value. */
#ifndef BLDC_PORT_BUS_HYSTERESIS_CODES
#define BLDC_PORT_BUS_HYSTERESIS_CODES 1u
#endif

/*
 * Inputs from outside the port.
 *
 * bldc_port_set_bus_voltage(): the latest bus-voltage ADC result in counts. When it
 * differs from the code in use by more than BLDC_PORT_BUS_HYSTERESIS_CODES, or crosses
 * the over-voltage threshold, it stores the code and pends the timing computation, which
 * then saturates it and computes the bus voltage's reciprocals once
 * (bldc_bus_condition()); otherwise it does nothing. Call it whenever the bus voltage
 * is sampled (a few hundred Hz is plenty: the bus changes slowly), from thread mode or
 * any interrupt. Until the first call the bridge stays off (treated as over-voltage);
 * an over-voltage code turns it off from the next edge on.
 *
 * bldc_adc_phase_current: latest ADC result of the commutated phase current I in
 * counts, written by the user's ADC conversion-complete interrupt or as the destination
 * of a circular DMA (16-bit half-word transfers). The timing computation after each
 * Hall edge reads it once.
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
 * all outputs off, MOE set) and TIM3 (Hall interface), set up the pins, and set the
 * priorities of and enable TIM3_IRQn and TIM1_TRG_COM_IRQn. The bridge stays off until
 * the first Hall edge after a bus voltage is known. */
void bldc_port_init(void);

/* Vector table entries (CMSIS/Cube names). A Cube project that already uses the TIM1
 * trigger/commutation interrupt must hand it over to the port. */
void TIM3_IRQHandler(void);          /* Hall edge, commutation end, Hall timeout */
void TIM1_TRG_COM_IRQHandler(void);  /* the next edge's duties and commutation time */

#endif /* STM32F103_PORT_H */

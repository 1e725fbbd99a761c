/* Generated from template templates/firmware/system_stm32f103.h.j2 with spec spec/example_maxon_ec45_flat_48v.yaml (sha256 4e4bc402b3ee91505838c88f91659557d0005f5a8b56d60c19ecc3e2f665b3c6). Do not edit: regenerate with `bldc-codegen generate spec/example_maxon_ec45_flat_48v.yaml`. */
#ifndef SYSTEM_STM32F103_H
#define SYSTEM_STM32F103_H

/* The firmware's clock tree and independent watchdog (see system_stm32f103.c). A Cube
 * project uses its own SystemClock_Config() and IWDG set-up instead. */

#include <stdint.h>

/* HSE 8 MHz -> PLL 72 MHz, flash at 2 wait states with prefetch, APB1 / 2, APB2 / 1,
 * ADC / 6, the clock security system on. Returns 0, or BLDC_FAULT_CLOCK when the HSE
 * did not start within 10 ms or the PLL did not lock: the chip then
 * stays on its 8 MHz HSI, and bldc_port_init(BLDC_FAULT_CLOCK) never arms the bridge. */
uint32_t bldc_system_clock_init(void);

/* The independent watchdog: prescaler 4, reload 299: 20.0 ms at 60 kHz, 40.0 ms at 30 kHz (firmware.watchdog_timeout = 20 ms). Once started it cannot be stopped. */
void bldc_system_watchdog_start(void);
void bldc_system_watchdog_refresh(void);

#endif /* SYSTEM_STM32F103_H */

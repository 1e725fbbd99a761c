/* Generated from template templates/firmware/main.c.j2 with spec spec/paper_motor.yaml (sha256 353cb73b28c0b827ba0524490cb9ff1397c10b6f2cbe203a67af9ae2661c890c). Do not edit: regenerate with `make`. */
/* Firmware entry for the project's own build: bring up the port, then sleep. The
 * Hall-edge and commutation-end work happens in TIM3_IRQHandler, the next edge's timing
 * in TIM1_TRG_COM_IRQHandler; thread mode hands the latest bus-voltage sample and main
 * duty to the port after every wake-up (the port recomputes only when they change). */
#include "stm32f103_port.h"

/* Bus-voltage ADC result, written by the application's ADC (e.g. a circular DMA), and
 * the braking current controller's output in TIM1 counts. */
volatile uint16_t app_bus_voltage_adc;
volatile uint16_t app_main_duty;

int main(void)
{
    bldc_port_init();
    for (;;) {
        __asm__ volatile("wfi");
        bldc_port_set_bus_voltage(app_bus_voltage_adc);
        bldc_port_set_main_duty(app_main_duty);
    }
}

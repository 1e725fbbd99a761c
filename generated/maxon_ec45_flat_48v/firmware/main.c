/* Generated from template templates/firmware/main.c.j2 with spec spec/example_maxon_ec45_flat_48v.yaml (sha256 8b5f5d50b8448d3cbaa1fb633cc60b872c18290557700779debfaeb46d86d548). Do not edit: regenerate with `make`. */
/* Firmware entry for the project's own build: bring up the port, then sleep. The
 * Hall-edge and commutation-end work happens in TIM3_IRQHandler, the next edge's timing
 * in TIM1_TRG_COM_IRQHandler; thread mode hands a new bus-voltage sample or main duty
 * to the port when one arrived (the port itself recomputes only for a bus change beyond
 * its hysteresis). */
#include "stm32f103_port.h"

/* Bus-voltage ADC result, written by the application's ADC (e.g. a circular DMA), and
 * the braking current controller's output in TIM1 counts. */
volatile uint16_t app_bus_voltage_adc;
volatile uint16_t app_main_duty;

int main(void)
{
    /* No sample has been handed over yet: a value no 12-bit ADC produces. */
    uint32_t bus_handed = UINT32_MAX;
    uint32_t duty_handed = UINT32_MAX;

    bldc_port_init();
    for (;;) {
        __asm__ volatile("wfi");
        const uint16_t bus = app_bus_voltage_adc;
        const uint16_t duty = app_main_duty;
        if (bus != bus_handed) {
            bus_handed = bus;
            bldc_port_set_bus_voltage(bus);
        }
        if (duty != duty_handed) {
            duty_handed = duty;
            bldc_port_set_main_duty(duty);
        }
    }
}

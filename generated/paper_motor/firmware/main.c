/* Generated from template templates/firmware/main.c.j2 with spec spec/paper_motor.yaml (sha256 07b8685d3a2684e5f837564446d9717554545097976668f5f4050212bf8dcce5). Do not edit: regenerate with `make`. */
/* Firmware entry for the project's own build: bring up the port and sleep; the
 * Hall-edge and commutation-end work happens in TIM3_IRQHandler. */
#include "stm32f103_port.h"

int main(void)
{
    bldc_port_init();
    for (;;) {
        __asm__ volatile("wfi");
    }
}

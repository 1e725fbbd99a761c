/* Generated from template templates/firmware/main.c.j2 with spec spec/example_maxon_ec45_flat_48v.yaml (sha256 88a70eb72b9494810aaa1248e2beb874e1bc6578ac98fdca4370be1ee72c27cc). Do not edit: regenerate with `make`. */
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

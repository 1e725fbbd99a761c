/* Generated from template templates/firmware/main.c.j2 with spec spec/paper_motor_improved_r.yaml (sha256 9f5d9c8963649549b4e129e1bd9cd35baa3c8e343f67f4b67f06c6141ed1f434). Do not edit: regenerate with `bldc-codegen generate spec/paper_motor_improved_r.yaml`. */
/* Firmware entry for the project's own build: the clock tree, the port, the watchdog,
 * then sleep. The Hall edge and the commutation end run in the TIM3 interrupt, the
 * current loop in the ADC's, the next edge's timing in TIM1_TRG_COM. Thread mode hands
 * a new braking-current command to the port, clears faults only when asked, and
 * refreshes the watchdog only while the current loop runs.
 *
 * The application's interface (plain variables, so a debugger or an emulator can
 * drive it):
 *   app_braking_current_ma  the braking current to hold, mA (the spec's nominal at reset)
 *   app_open_loop_duty      a main duty in TIM1 counts to run open loop instead (bring-up),
 *                           0xFFFFFFFF for none; a new braking current closes the loop
 *   app_clear_request       set nonzero to ask for bldc_port_clear_faults(); main
 *                           answers in app_clear_result and sets it back to 0
 *   app_faults              bldc_port_faults(), refreshed after every interrupt
 */
#include "stm32f103_port.h"
#include "system_stm32f103.h"

volatile uint32_t app_braking_current_ma = 5000u;
volatile uint32_t app_open_loop_duty = UINT32_MAX;
volatile uint32_t app_clear_request;
volatile uint32_t app_clear_result;
volatile uint32_t app_faults;

int main(void)
{
    bldc_port_init(bldc_system_clock_init());
    bldc_system_watchdog_start();
    /* No command has been handed over yet: a value no command equals. */
    uint32_t handed = UINT32_MAX;
    uint32_t handed_duty = UINT32_MAX;
    for (;;) {
        /* Sleep only with nothing left to do, the look and the WFI with interrupts
         * masked (an interrupt pending wakes WFI all the same, and is taken at the
         * unmask; ARMv7-M B1.5.19): a current-loop run between the watchdog's test
         * below and the WFI waited for the next interrupt, up to a Hall sector later,
         * and its refresh put the reset after a stalled current loop that much past
         * firmware.watchdog_timeout (make pil, a 100 kHz fixture: 4.8 ms). */
        __asm__ volatile("cpsid i" ::: "memory");
        if (bldc_port_alive_pending() == 0u) {
            __asm__ volatile("wfi");
        }
        __asm__ volatile("cpsie i" ::: "memory");
        const uint32_t command = app_braking_current_ma;
        if (command != handed) {
            handed = command;
            handed_duty = UINT32_MAX;
            bldc_set_braking_current(command);
        }
        const uint32_t duty = app_open_loop_duty;
        if ((duty != handed_duty) && (duty <= UINT16_MAX)) {
            handed_duty = duty;
            bldc_port_set_main_duty((uint16_t)duty);
        }
        if (app_clear_request != 0u) {
            app_clear_result = bldc_port_clear_faults();
            app_clear_request = 0u;
        }
        app_faults = bldc_port_faults();
        if (bldc_port_alive() != 0u) {
            bldc_system_watchdog_refresh();
        }
    }
}

/* Generated from template templates/firmware/system_stm32f103.c.j2 with spec spec/paper_motor_improved_r.yaml (sha256 9f5d9c8963649549b4e129e1bd9cd35baa3c8e343f67f4b67f06c6141ed1f434). Do not edit: regenerate with `bldc-codegen generate spec/paper_motor_improved_r.yaml`. */
/*
 * Clock tree (RM0008 7.2): HSE 8 MHz -> PLL x 9 = 72 MHz SYSCLK; AHB / 1, APB2 / 1
 * (TIM1, ADC1 at 72 MHz), APB1 / 2 (36 MHz, its timers at 72 MHz: TIM3), ADC / 6 =
 * 12 MHz; flash LATENCY = 2 with the prefetch buffer (RM0008 3.3.3). Every wait is
 * bounded: the HSE and the PLL by SysTick counting milliseconds on the 8 MHz HSI the
 * chip resets to, the switch by a loop count.
 */
#include "system_stm32f103.h"
#include "stm32f103_port.h"
#include "stm32f103_regs.h"

#define BLDC_SYSTEM_HSE_TIMEOUT_MS 10u /* firmware.hse_startup_timeout */
#define BLDC_SYSTEM_SYSTICK_MS 8000u        /* HSI counts per millisecond */
#define BLDC_SYSTEM_PLLMUL 7u            /* RCC_CFGR.PLLMUL = 0111: x9 */
#define BLDC_SYSTEM_PPRE1 4u              /* RCC_CFGR.PPRE1 = 100: HCLK / 2 */
#define BLDC_SYSTEM_SW_PLL 2u                 /* RCC_CFGR.SW = 10: PLL */
#define BLDC_SYSTEM_FLASH_LATENCY 2u   /* FLASH_ACR.LATENCY: 2 wait states */
#define BLDC_SYSTEM_SWITCH_WAIT_LOOPS 100000u
#define BLDC_SYSTEM_IWDG_PR 0u   /* prescaler 4, reload 299: 20.0 ms at 60 kHz, 40.0 ms at 30 kHz (firmware.watchdog_timeout = 20 ms) */
#define BLDC_SYSTEM_IWDG_RLR 299u
#define BLDC_SYSTEM_IWDG_WAIT_LOOPS 7200u
#define BLDC_SYSTEM_IWDG_UNLOCK 0x5555u  /* RM0008 19.4.1 IWDG_KR keys */
#define BLDC_SYSTEM_IWDG_RELOAD 0xAAAAu
#define BLDC_SYSTEM_IWDG_START 0xCCCCu

/* Wait until `mask` is set in RCC->CR, for at most `ms` milliseconds of SysTick. */
static uint32_t system_wait_ready(uint32_t mask, uint32_t ms)
{
    SysTick->LOAD = BLDC_SYSTEM_SYSTICK_MS - 1u;
    SysTick->VAL = 0u;
    SysTick->CTRL = SysTick_CTRL_CLKSOURCE_Msk | SysTick_CTRL_ENABLE_Msk;
    uint32_t elapsed = 0u;
    while (((RCC->CR & mask) == 0u) && (elapsed < ms)) {
        if ((SysTick->CTRL & SysTick_CTRL_COUNTFLAG_Msk) != 0u) {
            ++elapsed;
        }
    }
    SysTick->CTRL = 0u;
    return ((RCC->CR & mask) != 0u) ? 1u : 0u;
}

uint32_t bldc_system_clock_init(void)
{
    RCC->CR |= RCC_CR_HSEON;
    if (system_wait_ready(RCC_CR_HSERDY, BLDC_SYSTEM_HSE_TIMEOUT_MS) == 0u) {
        RCC->CR &= ~RCC_CR_HSEON; /* stay on the HSI: the drive must not start */
        return BLDC_FAULT_CLOCK;
    }
    /* Two wait states before the clock rises above 48 MHz. */
    FLASH->ACR = FLASH_ACR_PRFTBE | (BLDC_SYSTEM_FLASH_LATENCY << FLASH_ACR_LATENCY_Pos);
    RCC->CFGR = (BLDC_SYSTEM_PLLMUL << RCC_CFGR_PLLMUL_Pos) | RCC_CFGR_PLLSRC |
                (BLDC_PORT_ADC_PRESCALER << RCC_CFGR_ADCPRE_Pos) |
                (BLDC_SYSTEM_PPRE1 << RCC_CFGR_PPRE1_Pos);
    RCC->CR |= RCC_CR_PLLON;
    if (system_wait_ready(RCC_CR_PLLRDY, BLDC_SYSTEM_HSE_TIMEOUT_MS) == 0u) {
        return BLDC_FAULT_CLOCK;
    }
    RCC->CFGR |= BLDC_SYSTEM_SW_PLL << RCC_CFGR_SW_Pos;
    uint32_t spins = 0u;
    while ((((RCC->CFGR & RCC_CFGR_SWS_Msk) >> RCC_CFGR_SWS_Pos) != BLDC_SYSTEM_SW_PLL) &&
           (spins < BLDC_SYSTEM_SWITCH_WAIT_LOOPS)) {
        ++spins;
    }
    if (((RCC->CFGR & RCC_CFGR_SWS_Msk) >> RCC_CFGR_SWS_Pos) != BLDC_SYSTEM_SW_PLL) {
        return BLDC_FAULT_CLOCK;
    }
    RCC->CR |= RCC_CR_CSSON; /* an HSE failure from now on raises the NMI */
    return 0u;
}

/* PR and RLR reach the watchdog's LSI domain up to 5 LSI cycles after they are written
 * (SR.PVU, SR.RVU read 1 meanwhile), and a reload before that loads the value already
 * there (RM0008 19.4.4): reloaded at once, the first time-out would be the reset
 * value's (4096 x 4 LSI cycles, 273 ms at 60 kHz). So the watchdog is started first
 * (the start key turns the LSI on, counting from the reset value), then PR and RLR are
 * written and the reload waits for both to arrive, at most
 * BLDC_SYSTEM_IWDG_WAIT_LOOPS polls (twice 6 LSI cycles at 30 kHz, at 4 SYSCLK cycles a poll or more). */
void bldc_system_watchdog_start(void)
{
    IWDG->KR = BLDC_SYSTEM_IWDG_START;
    IWDG->KR = BLDC_SYSTEM_IWDG_UNLOCK;
    IWDG->PR = BLDC_SYSTEM_IWDG_PR;
    IWDG->RLR = BLDC_SYSTEM_IWDG_RLR;
    uint32_t spins = 0u;
    while (((IWDG->SR & (IWDG_SR_PVU | IWDG_SR_RVU)) != 0u) &&
           (spins < BLDC_SYSTEM_IWDG_WAIT_LOOPS)) {
        ++spins;
    }
    IWDG->KR = BLDC_SYSTEM_IWDG_RELOAD;
}

void bldc_system_watchdog_refresh(void)
{
    IWDG->KR = BLDC_SYSTEM_IWDG_RELOAD;
}

"""Render context of the firmware's clock tree and independent watchdog.

Clock tree (RM0008 7.2, DS5319 Table 13 limits): HSE 8 MHz -> PLL x 9 = 72 MHz SYSCLK,
AHB / 1 = 72 MHz, APB2 / 1 = 72 MHz (TIM1, ADC1, GPIO), APB1 / 2 = 36 MHz (its timers
run at twice that: TIM3 at 72 MHz), ADC / 6 = 12 MHz; the flash at 2 wait states with
the prefetch buffer (RM0008 3.3.3: 48 < SYSCLK <= 72 MHz). The HSE gets
`firmware.hse_startup_timeout`, counted by SysTick on the 8 MHz HSI the chip resets
to; if it does not start (or the PLL does not lock) the chip stays on the HSI, the
bridge is never armed and BLDC_FAULT_CLOCK is latched. The clock security system is
on: an HSE failure later raises the NMI.

Independent watchdog (RM0008 19): the LSI is 30..60 kHz (DS5319 Table 30); the
prescaler and reload are chosen so that even at 60 kHz the timeout is at least
`firmware.watchdog_timeout` (at 30 kHz it is twice that). They reach the LSI domain up
to 5 LSI cycles after they are written (19.4.4): the firmware starts the watchdog first,
writes them, and reloads once SR.PVU and SR.RVU have cleared (a bounded wait).
"""

from __future__ import annotations

from fractions import Fraction

from codegen.spec_model import Spec

HSE_HZ = Fraction(8_000_000)
HSI_HZ = Fraction(8_000_000)
SYSCLK_HZ = Fraction(72_000_000)
PLL_MULTIPLIER = 9
#: RCC_CFGR.PLLMUL: 0111 = x9 (the code is the multiplier - 2).
PLLMUL_CODE = PLL_MULTIPLIER - 2
#: RCC_CFGR.PPRE1 = 100: HCLK / 2 (APB1 at most 36 MHz).
PPRE1_DIV2 = 4
#: RCC_CFGR.SW / SWS = 10: PLL.
SW_PLL = 2
#: FLASH_ACR.LATENCY = 010: two wait states for 48 < SYSCLK <= 72 MHz.
FLASH_LATENCY = 2
#: SysTick counts of one millisecond on the HSI.
SYSTICK_MS = int(HSI_HZ / 1000)
LSI_MAX_HZ = Fraction(60_000)
LSI_MIN_HZ = Fraction(30_000)
IWDG_RELOAD_MAX = 4095
#: Bound of the wait for the switch to the PLL (SWS), in loop iterations.
SWITCH_WAIT_LOOPS = 100_000
#: LSI cycles PR and RLR take into the watchdog's domain (RM0008 19.4.4: up to 5), one more
IWDG_UPDATE_LSI_CYCLES = 6
#: Cycles of one poll of IWDG_SR at the fewest: a load, a test, a compare, a branch
POLL_CYCLES_MIN = 4


def iwdg_wait_loops() -> int:
    """Polls of IWDG_SR that last at least twice IWDG_UPDATE_LSI_CYCLES at the slowest LSI
    on the 72 MHz SYSCLK (on the 8 MHz HSI, after a clock fault, each lasts longer)."""
    cycles = 2 * IWDG_UPDATE_LSI_CYCLES * SYSCLK_HZ / LSI_MIN_HZ
    return int(-(-cycles // POLL_CYCLES_MIN))


def watchdog_setting(timeout_s: Fraction) -> tuple[int, int]:
    """(PR code, RLR): the smallest prescaler 4 x 2^PR whose reload reaches the timeout
    at the fastest LSI."""
    for code in range(7):
        divider = 4 << code
        reload = -((-timeout_s * LSI_MAX_HZ) // divider) - 1  # ceil - 1
        if 0 <= reload <= IWDG_RELOAD_MAX:
            return code, int(reload)
    raise ValueError(f"watchdog timeout {float(timeout_s)} s beyond the IWDG's range")


def system_context(spec: Spec) -> dict[str, object]:
    fw = spec.firmware
    timeout_ms = max(1, -((-fw.hse_startup_timeout_s * 1000) // 1))
    code, reload = watchdog_setting(fw.watchdog_timeout_s)
    divider = 4 << code
    shortest = Fraction(divider * (reload + 1)) / LSI_MAX_HZ
    longest = Fraction(divider * (reload + 1)) / LSI_MIN_HZ
    return {
        "hse_timeout_ms": int(timeout_ms),
        "systick_ms": SYSTICK_MS,
        "pllmul_code": PLLMUL_CODE,
        "ppre1_code": PPRE1_DIV2,
        "sw_pll": SW_PLL,
        "flash_latency": FLASH_LATENCY,
        "switch_wait_loops": SWITCH_WAIT_LOOPS,
        "iwdg_pr": code,
        "iwdg_rlr": reload,
        "iwdg_wait_loops": iwdg_wait_loops(),
        "iwdg_wait_text": f"twice {IWDG_UPDATE_LSI_CYCLES} LSI cycles at 30 kHz, at"
        f" {POLL_CYCLES_MIN} SYSCLK cycles a poll or more",
        "iwdg_text": f"prescaler {divider}, reload {reload}: {float(shortest) * 1e3:.1f} ms at 60 kHz,"
        f" {float(longest) * 1e3:.1f} ms at 30 kHz (firmware.watchdog_timeout ="
        f" {float(fw.watchdog_timeout_s) * 1e3:g} ms)",
        "braking_current_ma": int(spec.controller.braking_current_nominal_a * 1000),
    }

"""Each peripheral behaviour the emulated STM32F103 models, one test each, with its
RM0008 (or PM0056) section. Registers are written as the firmware would, by SVD name;
the CPU sleeps in a WFI loop meanwhile, so time is the peripherals' alone."""

from __future__ import annotations

import pytest

from emulation.pil.bus import Peripheral, PilError, UnmodelledAccessError, svd_offsets
from emulation.pil.iwdg import WatchdogResetError
from emulation.pil.machine import Machine, MachineOptions, bare_image
from emulation.pil.rcc import TICK_HZ
from emulation.pil.scs import IRQ_BASE, NMI, SYSTICK
from emulation.pil.tim1 import dead_time_counts, gate_violations

WFI_LOOP = b"\x30\xbf\xfd\xe7"  # loop: wfi; b loop
US = TICK_HZ // 1_000_000
TIM1_UP, TIM1_BRK, TIM1_COM, TIM1_CC, TIM3_IRQ, ADC_IRQ = 25, 24, 26, 27, 29, 18


def machine(**options: object) -> Machine:
    return Machine(bare_image(WFI_LOOP), MachineOptions(**options))  # type: ignore[arg-type]


def write(p: Peripheral, name: str, value: int) -> None:
    p.write(svd_offsets(p.svd_name)[name], 4, value)


def read(p: Peripheral, name: str) -> int:
    return p.read(svd_offsets(p.svd_name)[name], 4)


def at(m: Machine, tick: int) -> None:
    m.run_until(tick)


def clocks_72mhz(m: Machine) -> None:
    """HSE -> PLL x9, latency 2, APB1 / 2: the drive's clock tree, set directly."""
    write(m.rcc, "CR", read(m.rcc, "CR") | 1 << 16)
    at(m, m.now + m.rcc.hse_startup_ticks)
    write(m.flash, "ACR", 0x12)
    write(m.rcc, "CFGR", (7 << 18) | (1 << 16) | (4 << 8) | (2 << 14))
    write(m.rcc, "CR", read(m.rcc, "CR") | 1 << 24)
    at(m, m.now + m.rcc.pll_lock_ticks)
    write(m.rcc, "CFGR", read(m.rcc, "CFGR") | 2)
    write(m.rcc, "APB2ENR", 0xFFFF)
    write(m.rcc, "APB1ENR", 0x3)


# ---------------------------------------------------------------------- RCC and FLASH


def test_rcc_hse_should_be_ready_after_its_startup_time() -> None:
    """RM0008 7.2.1: HSERDY follows HSEON after the oscillator starts."""
    m = machine()
    write(m.rcc, "CR", read(m.rcc, "CR") | 1 << 16)
    at(m, m.rcc.hse_startup_ticks - 10)
    assert not read(m.rcc, "CR") & (1 << 17)
    at(m, m.rcc.hse_startup_ticks + 10)
    assert read(m.rcc, "CR") & (1 << 17)


def test_rcc_a_failing_hse_should_never_be_ready() -> None:
    m = machine(hse_fails=True)
    write(m.rcc, "CR", read(m.rcc, "CR") | 1 << 16)
    at(m, 50 * m.rcc.hse_startup_ticks)
    assert not read(m.rcc, "CR") & (1 << 17)


def test_rcc_pll_should_lock_and_the_switch_follow_only_when_ready() -> None:
    """RM0008 7.2.3 PLLRDY after t_LOCK; 7.2.6 SWS follows SW once the source is ready."""
    m = machine()
    write(m.rcc, "CR", read(m.rcc, "CR") | 1 << 16)
    at(m, m.rcc.hse_startup_ticks)
    write(m.flash, "ACR", 2)
    write(m.rcc, "CFGR", (7 << 18) | (1 << 16))
    write(m.rcc, "CR", read(m.rcc, "CR") | 1 << 24)
    write(m.rcc, "CFGR", read(m.rcc, "CFGR") | 2)  # SW = PLL before it locks
    assert (read(m.rcc, "CFGR") >> 2) & 3 == 0 and m.rcc.sysclk_hz == 8_000_000
    at(m, m.now + m.rcc.pll_lock_ticks)
    assert read(m.rcc, "CR") & (1 << 25)
    assert (read(m.rcc, "CFGR") >> 2) & 3 == 2 and m.rcc.sysclk_hz == 72_000_000
    assert m.cycle_ticks == 1


def test_rcc_pll_configuration_should_be_locked_while_the_pll_runs() -> None:
    """RM0008 7.3.2: PLLMUL/PLLSRC "can be written only when PLL is disabled"."""
    m = machine()
    write(m.rcc, "CFGR", 7 << 18)
    write(m.rcc, "CR", read(m.rcc, "CR") | 1 << 24)
    with pytest.raises(PilError, match="PLL"):
        write(m.rcc, "CFGR", 6 << 18)


def test_flash_latency_should_match_the_clock_switched_to() -> None:
    """RM0008 3.3.3: two wait states above 48 MHz; switching with fewer is an error."""
    m = machine()
    write(m.rcc, "CFGR", 7 << 18)  # HSI / 2 x 9 = 36 MHz: one wait state
    write(m.rcc, "CR", read(m.rcc, "CR") | 1 << 24)
    at(m, m.rcc.pll_lock_ticks)
    with pytest.raises(PilError, match="LATENCY"):
        write(m.rcc, "CFGR", read(m.rcc, "CFGR") | 2)
    write(m.flash, "ACR", 0x11)
    assert read(m.flash, "ACR") == 0x31  # LATENCY 1, PRFTBE, PRFTBS
    write(m.rcc, "CFGR", read(m.rcc, "CFGR") | 2)
    assert m.rcc.sysclk_hz == 36_000_000


def test_rcc_timer_clocks_should_double_behind_a_divided_apb() -> None:
    """RM0008 7.2 Figure 8: TIMxCLK = 2 x PCLKx when the APB prescaler is not 1."""
    m = machine()
    clocks_72mhz(m)
    assert m.rcc.pclk1_hz == 36_000_000 and m.rcc.timer_hz(1) == 72_000_000
    assert m.rcc.timer_hz(2) == 72_000_000 and m.rcc.adc_hz == 12_000_000


def test_css_should_raise_the_nmi_break_tim1_and_fall_back_to_the_hsi() -> None:
    """RM0008 7.2.7: HSE failure with CSSON: CSSF, NMI, TIM1 break, SYSCLK = HSI."""
    m = machine()
    clocks_72mhz(m)
    write(m.rcc, "CR", read(m.rcc, "CR") | 1 << 19)
    m.gpiob.drive(12, True)
    write(m.tim1, "BDTR", (1 << 12) | (1 << 15))  # BKE, active low, MOE
    m.rcc.fail_hse(m.now + 100)
    m.nvic.active.append(NMI)  # hold the NMI handler off: look at the pending state
    at(m, m.now + 200)
    assert read(m.rcc, "CIR") & (1 << 7)
    assert NMI in m.nvic.pending
    assert m.rcc.sysclk_hz == 8_000_000 and not m.tim1.moe and read(m.tim1, "SR") & (1 << 7)
    write(m.rcc, "CIR", 1 << 23)
    assert not read(m.rcc, "CIR") & (1 << 7)


def test_rcc_reset_flags_should_clear_with_rmvf() -> None:
    """RM0008 7.3.10: PORRSTF/PINRSTF after power-on, RMVF clears them."""
    m = machine()
    assert read(m.rcc, "CSR") & (3 << 26) == 3 << 26
    write(m.rcc, "CSR", 1 << 24)
    assert read(m.rcc, "CSR") & 0xFC000000 == 0


# ---------------------------------------------------------------------- GPIO


def test_gpio_input_with_pull_up_should_read_odr_unless_driven() -> None:
    """RM0008 9.1.1 / 9.2.4: CNF = 10 input, ODR picks the pull; a driven pin wins."""
    m = machine()
    write(m.gpioa, "CRL", 0x8 << 24)  # PA6: input pull-up/down
    write(m.gpioa, "BSRR", 1 << 6)
    assert read(m.gpioa, "IDR") >> 6 & 1
    m.gpioa.drive(6, False)
    assert not read(m.gpioa, "IDR") >> 6 & 1


def test_gpio_bsrr_set_should_win_over_reset() -> None:
    """RM0008 9.2.5: with BSy and BRy both written, BSy acts."""
    m = machine()
    write(m.gpiob, "BSRR", (1 << 3) | (1 << (16 + 3)) | (1 << (16 + 4)))
    assert read(m.gpiob, "ODR") == 1 << 3
    write(m.gpiob, "BRR", 1 << 3)
    assert read(m.gpiob, "ODR") == 0


def test_gpio_alternate_function_output_should_show_the_timer() -> None:
    """RM0008 9.1.4: an AF push-pull pin carries the peripheral's output (TIM1 CH1 on PA8)."""
    m = machine()
    clocks_72mhz(m)
    write(m.gpioa, "CRH", 0xB)  # PA8: AF push-pull 50 MHz
    write(m.tim1, "CCMR1", 5 << 4)  # OC1M force active
    write(m.tim1, "CCER", 1)
    write(m.tim1, "BDTR", 1 << 15)
    assert read(m.gpioa, "IDR") >> 8 & 1
    write(m.tim1, "CCMR1", 4 << 4)  # force inactive
    assert not read(m.gpioa, "IDR") >> 8 & 1


def test_gpio_a_floating_input_nobody_drives_should_be_noted() -> None:
    m = machine()
    m.gpioa.drive(6, True)
    m.gpioa.drive(6, None)
    assert not read(m.gpioa, "IDR") >> 6 & 1
    assert 6 in m.gpioa.floating_reads


# ---------------------------------------------------------------------- TIM1


def tim1_pwm(m: Machine, *, arr: int = 99, cms: int = 0, dtg: int = 0) -> None:
    clocks_72mhz(m)
    write(m.tim1, "ARR", arr)
    write(m.tim1, "CCMR1", (6 << 4) | (1 << 3) | (6 << 12) | (1 << 11))
    write(m.tim1, "CCMR2", (6 << 4) | (1 << 3) | (7 << 12) | (1 << 11))
    write(m.tim1, "BDTR", dtg | (1 << 11) | (1 << 10))
    write(m.tim1, "CR1", (cms << 5) | (1 << 7) | 1)


def test_tim1_up_counter_should_count_from_the_time() -> None:
    """RM0008 14.3.2: CNT counts 0..ARR at CK_CNT and wraps with an update (UIF)."""
    m = machine()
    tim1_pwm(m)
    start = m.now
    at(m, start + 42)
    assert read(m.tim1, "CNT") == 42
    write(m.tim1, "SR", 0)
    at(m, start + 100 + 5)
    assert read(m.tim1, "CNT") == 5 and read(m.tim1, "SR") & 1


def test_tim1_centre_aligned_should_count_up_and_down() -> None:
    """RM0008 14.3.4: 0..ARR..0, DIR reads the direction, an UEV at each end."""
    m = machine()
    tim1_pwm(m, cms=3)
    start = m.now
    at(m, start + 60)
    assert read(m.tim1, "CNT") == 60 and not read(m.tim1, "CR1") & (1 << 4)
    at(m, start + 130)
    assert read(m.tim1, "CNT") == 2 * 99 - 130 and read(m.tim1, "CR1") & (1 << 4)
    assert m.tim1.update_count >= 1


def test_tim1_ccr_preload_should_wait_for_the_update() -> None:
    """RM0008 14.3.9 / 14.4.7: with OCxPE the new CCRx acts from the next UEV."""
    m = machine()
    tim1_pwm(m)
    start = m.now
    write(m.tim1, "CCR1", 30)
    at(m, start + 10)
    assert m.tim1.ccr[1] == 0 and read(m.tim1, "CCR1") == 30
    at(m, start + 101)
    assert m.tim1.ccr[1] == 30


def test_tim1_ccer_should_be_preloaded_until_a_com_event() -> None:
    """RM0008 14.4.2 CCPC: CCxE/CCxNE/OCxM change at COM (EGR.COMG), which sets COMIF."""
    m = machine()
    tim1_pwm(m)
    write(m.tim1, "CR2", 1)  # CCPC
    write(m.tim1, "CCER", 0b0101)
    assert m.tim1.ccer == 0 and read(m.tim1, "CCER") == 0b0101
    write(m.tim1, "DIER", 1 << 5)
    write(m.tim1, "CCMR1", (4 << 4) | (1 << 3) | (6 << 12) | (1 << 11))  # OC1M: force inactive
    assert m.tim1.oc_mode(1) == 6 and m.tim1.oc_preload(1)  # OC1M preloaded, OC1PE not
    write(m.tim1, "EGR", 1 << 5)
    assert m.tim1.ccer == 0b0101 and read(m.tim1, "SR") & (1 << 5)
    assert m.tim1.oc_mode(1) == 4
    assert IRQ_BASE + TIM1_COM in m.nvic.pending


@pytest.mark.parametrize(
    ("dtg", "counts"),
    [
        (0x24, 36),
        (0x7F, 127),
        (0x80, 128),
        (0xBF, 254),
        (0xC0, 256),
        (0xDF, 504),
        (0xE0, 512),
        (0xFF, 1008),
    ],
)
def test_tim1_dead_time_generator_should_decode_dtg(dtg: int, counts: int) -> None:
    """RM0008 14.4.18 DTG[7:0]: four ranges of step 1, 2, 8 and 16 t_DTS."""
    assert dead_time_counts(dtg) == counts


def test_tim1_complementary_outputs_should_keep_the_dead_time() -> None:
    """RM0008 14.3.11: each rising edge is delayed by DT; OCx and OCxN never overlap."""
    m = machine()
    tim1_pwm(m, arr=199, dtg=10)
    write(m.tim1, "CCR1", 100)
    write(m.tim1, "CCER", 0b0101)  # CC1E, CC1NE
    write(m.tim1, "BDTR", read(m.tim1, "BDTR") | 1 << 15)
    write(m.tim1, "EGR", 1)
    start = m.now
    levels = [m.tim1.gates(start + t)[:2] for t in range(400)]
    # OC1: high from 10 (dead time after the period start) to 100; OC1N from 110 to 200
    assert [t for t in range(200) if levels[t][0]] == list(range(10, 100))
    assert [t for t in range(200) if levels[t][1]] == list(range(110, 200))
    assert not any(a and b for a, b in levels)


def test_tim1_gate_record_should_log_each_edge_and_check_the_dead_time() -> None:
    """The outputs' edges as they happen (`record_gates`), and the bridge invariants."""
    for dtg, expected in ((10, []), (0, ["phase A"])):
        m = machine()
        tim1_pwm(m, arr=199, dtg=dtg)
        write(m.tim1, "CCR1", 100)
        write(m.tim1, "CCER", 0b0101)
        write(m.tim1, "BDTR", read(m.tim1, "BDTR") | 1 << 15)
        write(m.tim1, "EGR", 1)
        start = m.now
        m.tim1.record_gates()
        at(m, start + 3 * 200)
        log = m.tim1.gate_log
        assert log is not None
        edges = [(t - start, g[:2]) for t, g in log[1:]]
        if dtg:
            assert edges[:4] == [
                (10, (True, False)),
                (100, (False, False)),
                (110, (False, True)),
                (200, (False, False)),
            ]
        violations = gate_violations(log, 10)
        assert all(any(e in v for e in expected) for v in violations) and bool(violations) == bool(
            expected
        )


def test_a_switch_over_at_one_instant_should_break_the_dead_time_either_way() -> None:
    """One output of a phase off and the other on in the same record (a COM event that
    hands a leg over in single-output mode): a turn-on 0 ticks after its partner, whichever
    of the two is the upper. The check once took the upper's turn-on before the lower's
    turn-off and missed the lower-to-upper switch-over."""
    for before, after in (((True, False), (False, True)), ((False, True), (True, False))):
        idle = (None, None, None, None)
        log = [(0, (False, False, *idle)), (50, (*before, *idle)), (100, (*after, *idle))]
        (violation,) = gate_violations(log, 10)
        assert "switch on 0 ticks after its partner turned off" in violation, violation


def test_tim1_single_output_should_follow_ocxref_and_ossr_should_hold_the_other() -> None:
    """RM0008 Table 83: CCxE = 1, CCxNE = 0: OCx = OCxREF (no dead time); OSSR = 1
    drives the disabled OCxN at its inactive level, OSSR = 0 leaves it undriven."""
    m = machine()
    tim1_pwm(m, dtg=10)
    write(m.tim1, "CCR1", 50)
    write(m.tim1, "CCER", 0b0001)
    write(m.tim1, "BDTR", read(m.tim1, "BDTR") | 1 << 15)
    write(m.tim1, "EGR", 1)
    start = m.now
    assert m.tim1.gates(start + 1)[:2] == (True, False)
    assert m.tim1.gates(start + 60)[:2] == (False, False)
    write(m.tim1, "BDTR", read(m.tim1, "BDTR") & ~(1 << 11))
    assert m.tim1.gates(start + 1)[1] is None
    assert m.tim1.gates(start + 1)[2:] == (None, None, None, None)  # CH2, CH3 disabled


def test_tim1_complementary_output_alone_should_follow_ocxref_not_its_complement() -> None:
    """RM0008 Table 83: CCxE = 0, CCxNE = 1: OCxN = OCxREF xor CCxNP (active while
    CNT < CCRx in PWM mode 1, like OCx alone); the complement only with both enabled."""
    m = machine()
    tim1_pwm(m, dtg=10)
    write(m.tim1, "CCR1", 50)
    write(m.tim1, "CCER", 0b0100)  # CC1NE alone
    write(m.tim1, "BDTR", read(m.tim1, "BDTR") | 1 << 15 | 1 << 11)  # MOE, OSSR
    write(m.tim1, "EGR", 1)
    start = m.now
    assert m.tim1.gates(start + 1)[:2] == (False, True)
    assert m.tim1.gates(start + 60)[:2] == (False, False)
    write(m.tim1, "CCER", 0b1100)  # CC1NP: active low
    write(m.tim1, "EGR", 1)
    assert m.tim1.gates(m.now + 1)[1] is False
    assert m.tim1.gates(m.now + 60)[1] is True


def test_tim1_break_input_should_clear_moe_and_idle_after_the_dead_time() -> None:
    """RM0008 14.3.12: BKIN active clears MOE at once and sets BIF; with OSSI the outputs
    go to CCxP/CCxNP at once and to OISx/OISxN after a dead time."""
    m = machine()
    tim1_pwm(m, dtg=20)
    write(m.tim1, "CR2", (1 << 9) | (1 << 11) | (1 << 13))  # OIS1N..3N: lower switches on
    write(m.tim1, "CCER", 0x555)
    m.gpiob.drive(12, True)
    write(m.tim1, "BDTR", read(m.tim1, "BDTR") | (1 << 12) | (1 << 15))  # BKE low, MOE
    write(m.tim1, "DIER", 1 << 7)
    assert m.tim1.moe
    m.gpiob.drive(12, False)
    broke = m.now
    assert not m.tim1.moe and read(m.tim1, "SR") & (1 << 7)
    assert IRQ_BASE + TIM1_BRK in m.nvic.pending
    assert m.tim1.gates(broke + 5) == (False,) * 6
    assert m.tim1.gates(broke + 25) == (False, True) * 3


def test_tim1_break_should_hold_bif_and_moe_while_the_input_is_active() -> None:
    """RM0008 14.3.12: the break acts on the level: BIF cannot be cleared, MOE not set."""
    m = machine()
    tim1_pwm(m)
    m.gpiob.drive(12, False)
    write(m.tim1, "BDTR", (1 << 12) | (1 << 15))
    write(m.tim1, "SR", 0)
    write(m.tim1, "BDTR", (1 << 12) | (1 << 15))
    assert read(m.tim1, "SR") & (1 << 7) and not m.tim1.moe
    m.gpiob.drive(12, True)
    write(m.tim1, "SR", 0)
    write(m.tim1, "BDTR", (1 << 12) | (1 << 15))
    assert not read(m.tim1, "SR") & (1 << 7) and m.tim1.moe


def test_tim1_software_break_and_automatic_output_enable() -> None:
    """RM0008 14.4.6 EGR.BG clears MOE; 14.4.18 AOE sets it again at the next UEV."""
    m = machine()
    tim1_pwm(m)
    write(m.tim1, "BDTR", (1 << 14) | (1 << 15))
    write(m.tim1, "EGR", 1 << 7)
    assert not m.tim1.moe and read(m.tim1, "SR") & (1 << 7)
    at(m, m.now + 101)
    assert m.tim1.moe


def test_tim1_interrupt_vectors_should_follow_flags_and_enables() -> None:
    """TIM1_UP (UIF), TIM1_CC (CCxIF) with their DIER enables (RM0008 14.4.4)."""
    m = machine()
    tim1_pwm(m)
    write(m.tim1, "CCR2", 40)
    write(m.tim1, "DIER", (1 << 0) | (1 << 2))
    m.nvic.active.append(2)  # hold every handler off (NMI active): look at pending
    at(m, m.now + 150)
    assert {IRQ_BASE + TIM1_UP, IRQ_BASE + TIM1_CC} <= m.nvic.pending


def test_tim1_trgo_should_fire_on_the_oc4ref_rising_edge() -> None:
    """RM0008 14.4.2 MMS = 111: TRGO = OC4REF; PWM mode 2 rises at CNT = CCR4."""
    m = machine()
    tim1_pwm(m)
    write(m.tim1, "CCR4", 80)
    write(m.tim1, "CR2", 7 << 4)
    edges: list[int] = []
    m.tim1.trgo_listeners.append(edges.append)
    start = m.now
    at(m, start + 450)
    # CCR4 is preloaded (OC4PE): the new compare acts from the first update, at 100
    assert [e - start for e in edges] == [180, 280, 380]


def test_tim1_centre_aligned_trgo_should_rise_one_count_after_the_peak() -> None:
    """RM0008 14.4.7 OC1M, PWM mode 1: counting down, inactive while CNT > CCRx. So
    OC4REF with CCR4 = ARR - 1 (the port's centre-aligned current-sample trigger) is
    inactive at ARR - 1 counting up and at ARR, and rises one count after the peak, at
    CNT = ARR - 1 counting down; not at the next compare match of another channel (the
    model once raised it at CCR3's match, late by ARR - CCR3 counts)."""
    m = machine()
    tim1_pwm(m, cms=1)
    write(m.tim1, "CCMR2", (6 << 4) | (1 << 3) | (6 << 12) | (1 << 11))  # OC3, OC4: PWM 1
    write(m.tim1, "CCR3", 60)
    write(m.tim1, "CCR4", 98)
    write(m.tim1, "CR2", 7 << 4)  # TRGO = OC4REF
    edges: list[tuple[int, bool]] = []  # (CNT, counting down) at each rising edge
    m.tim1.trgo_listeners.append(lambda t: edges.append((m.tim1.cnt(t), m.tim1.counting_down(t))))
    at(m, m.now + 1000)
    assert len(edges) >= 4
    assert set(edges) == {(98, True)}


def test_tim1_centre_aligned_ccr_at_arr_should_hold_ocxref_active() -> None:
    """RM0008 14.3.10, Figure "Center-aligned PWM waveforms (ARR=8)": CCRx = ARR holds
    OCxREF at 1 in PWM mode 1 (active while CNT < ARR counting up, and counting down
    from CNT = ARR on), so an OC4REF trigger with CCR4 = ARR never rises."""
    m = machine()
    tim1_pwm(m, cms=1)
    write(m.tim1, "CCMR2", (6 << 4) | (1 << 3) | (6 << 12) | (1 << 11))
    write(m.tim1, "CCR4", 99)
    write(m.tim1, "CR2", 7 << 4)
    edges: list[int] = []
    m.tim1.trgo_listeners.append(edges.append)
    start = m.now
    at(m, start + 110)  # CCR4 preloaded: in force from the overflow at 99
    edges.clear()
    at(m, start + 1000)
    assert edges == []
    assert all(m.tim1.ref_level(4, t) for t in range(start + 110, start + 1000))


def test_tim1_centre_aligned_pwm_should_be_on_for_twice_ccr_counts() -> None:
    """RM0008 14.4.7 OC1M, PWM mode 1: active while CNT < CCRx counting up (0..ARR-1),
    and from CNT = CCRx on counting down (ARR..1): 2 CCRx counts of the 2 ARR, centred on
    the underflow, so the duty is CCRx / ARR (CCRx = 0: never on)."""
    for ccr in (0, 1, 37, 98, 99):
        m = machine()
        tim1_pwm(m, cms=1)
        write(m.tim1, "CCR1", ccr)
        start = m.now
        at(m, start + 2 * 99)  # CCR1 preloaded: in force from the overflow
        first = m.now - m.now % (2 * 99) + 2 * 99  # the next underflow's start of a period
        on = [m.tim1.ref_level(1, t) for t in range(first, first + 2 * 99)]
        assert sum(on) == 2 * ccr, ccr
        if 0 < ccr < 99:  # on at both ends: up to CCRx - 1, and down from CCRx
            assert on[ccr - 1] and not on[ccr] and on[2 * 99 - ccr] and not on[2 * 99 - ccr - 1]


def test_tim1_centre_aligned_should_load_a_compare_at_the_overflow() -> None:
    """RM0008 14.3.4 with RCR = 0: an UEV at the overflow as well as the underflow, so a
    preloaded CCRx written in a period's first half acts in its second half."""
    m = machine()
    tim1_pwm(m, cms=1)
    start = m.now
    at(m, start + 2 * 99 + 10)  # a period started at 198; counting up
    write(m.tim1, "CCR1", 40)
    at(m, start + 2 * 99 + 98)
    assert m.tim1.ccr[1] == 0
    at(m, start + 2 * 99 + 100)  # past the overflow at 297
    assert m.tim1.ccr[1] == 40


def test_tim1_gate_log_should_hold_every_centre_aligned_edge() -> None:
    """The plant reads the gates from the log: at every tick it must equal the outputs
    evaluated afresh, the turn-on counting down (at CNT = CCRx) included."""
    m = machine()
    tim1_pwm(m, cms=1)
    write(m.tim1, "CCR3", 60)
    write(m.tim1, "CCER", 1 << 8)  # CH3 alone
    write(m.tim1, "BDTR", (1 << 15) | (1 << 11) | (1 << 10))  # MOE, OSSR, OSSI
    m.tim1.record_gates()
    start = m.now
    at(m, start + 1000)
    log = m.tim1.gate_log
    assert log is not None
    changes = 0
    for tick in range(start + 200, start + 990):
        logged = [g for t, g in log if t <= tick][-1]
        assert logged == m.tim1.gates(tick), tick
        changes += int(logged != [g for t, g in log if t <= tick - 1][-1])
    assert changes >= 6


# ---------------------------------------------------------------------- TIM3


def tim3_hall(m: Machine, *, filter_code: int = 0) -> None:
    clocks_72mhz(m)
    for port, pin in (("gpioa", 6), ("gpioa", 7), ("gpiob", 0)):
        getattr(m, port).drive(pin, False)
    write(m.tim3, "CR1", 1 << 2)
    write(m.tim3, "CR2", 1 << 7)  # TI1S
    write(m.tim3, "PSC", 71)
    write(m.tim3, "ARR", 0xFFFF)
    write(m.tim3, "CCMR1", 3 | (filter_code << 4))  # CC1S = TRC
    write(m.tim3, "SMCR", 4 << 4)
    write(m.tim3, "SMCR", (4 << 4) | 4)  # TI1F_ED, reset mode
    write(m.tim3, "CCER", 1)
    write(m.tim3, "EGR", 1)
    write(m.tim3, "SR", 0)
    write(m.tim3, "CR1", (1 << 2) | 1)


def test_tim3_hall_edge_should_capture_and_reset_the_counter() -> None:
    """RM0008 15.3.5 capture into CCR1 and 15.3.14 reset mode on TI1F_ED; with URS the
    reset sets no UIF; reading CCR1 clears CC1IF."""
    m = machine()
    tim3_hall(m)
    at(m, m.now + 1234 * US)
    m.gpioa.drive(7, True)  # any one Hall pin toggles TI1 (XOR)
    at(m, m.now + 10 * US)
    assert read(m.tim3, "SR") & 0b10 and not read(m.tim3, "SR") & 1
    assert read(m.tim3, "CCR1") in (1233, 1234)
    assert not read(m.tim3, "SR") & 0b10
    assert read(m.tim3, "CNT") in (9, 10)
    assert read(m.tim3, "SR") & (1 << 6)  # TIF


def test_tim3_xor_should_see_every_pin() -> None:
    """RM0008 15.4.2 TI1S: TI1 = CH1 xor CH2 xor CH3: every pin change is an edge."""
    m = machine()
    tim3_hall(m)
    for port, pin in (("gpioa", 6), ("gpiob", 0), ("gpioa", 7)):
        at(m, m.now + 100 * US)
        getattr(m, port).drive(pin, True)
    at(m, m.now + 10 * US)
    assert m.tim3.captures == 3


def test_tim3_filter_should_delay_edges_and_drop_glitches() -> None:
    """RM0008 15.4.7 IC1F = 0011: N = 8 samples at f_CK_INT."""
    m = machine()
    tim3_hall(m, filter_code=3)
    at(m, m.now + 100)
    m.gpioa.drive(6, True)
    at(m, m.now + 5)
    m.gpioa.drive(6, False)  # a 5-tick glitch
    at(m, m.now + 100)
    assert m.tim3.captures == 0
    m.gpioa.drive(6, True)
    changed = m.now
    at(m, changed + 7)
    assert m.tim3.captures == 0
    at(m, changed + 8)
    assert m.tim3.captures == 1


def test_tim3_overflow_should_set_uif_and_capture_overrun_cc1of() -> None:
    """RM0008 15.3.2: overflow sets UIF even with URS; 15.4.5 a second capture before
    CCR1 is read sets CC1OF."""
    m = machine()
    tim3_hall(m)
    at(m, m.now + 65_537 * US)
    assert read(m.tim3, "SR") & 1
    m.gpioa.drive(6, True)
    at(m, m.now + 100 * US)
    m.gpioa.drive(6, False)
    at(m, m.now + 10 * US)
    assert read(m.tim3, "SR") & (1 << 9)


def test_tim3_update_interrupt_should_come_at_the_wrap_and_not_at_a_hall_reset() -> None:
    """RM0008 15.4.4 DIER.UIE: the TIM3 interrupt at the overflow (UIF); with URS = 1 the
    slave-mode reset of a Hall edge sets no UIF (15.4.1), so it raises none."""
    m = machine()
    tim3_hall(m)
    write(m.tim3, "DIER", 1)  # UIE
    m.nvic.active.append(2)  # hold the interrupt pending: the WFI loop has no handler
    start = m.now
    at(m, start + 30_000 * US)
    m.gpioa.drive(6, True)  # a Hall edge resets the counter: no update interrupt
    at(m, m.now + 10 * US)
    assert IRQ_BASE + TIM3_IRQ not in m.nvic.pending
    reset = m.now - 10 * US
    at(m, reset + 65_535 * US)
    assert IRQ_BASE + TIM3_IRQ not in m.nvic.pending
    at(m, reset + 65_537 * US)
    assert IRQ_BASE + TIM3_IRQ in m.nvic.pending and read(m.tim3, "SR") & 1


def test_tim3_cc2_compare_should_flag_at_the_match_and_by_software() -> None:
    """RM0008 15.3.8 output compare (frozen): CC2IF at CNT = CCR2; 15.4.6 CC2G."""
    m = machine()
    tim3_hall(m)
    write(m.tim3, "CCR2", 500)
    write(m.tim3, "DIER", 1 << 2)
    m.nvic.active.append(2)
    start = m.now
    at(m, start + 499 * US)
    assert not read(m.tim3, "SR") & 0b100
    at(m, start + 501 * US)
    assert read(m.tim3, "SR") & 0b100 and IRQ_BASE + TIM3_IRQ in m.nvic.pending
    write(m.tim3, "SR", ~0b100)
    write(m.tim3, "EGR", 1 << 2)
    assert read(m.tim3, "SR") & 0b100


# ---------------------------------------------------------------------- ADC1


def adc_ready(m: Machine) -> None:
    clocks_72mhz(m)
    write(m.adc1, "CR2", 1)
    at(m, m.now + 2 * US)
    write(m.adc1, "CR2", 1 | 4)
    at(m, m.now + 100 * US)


def test_adc_calibration_should_take_83_adc_cycles() -> None:
    """RM0008 11.4: CAL reads 1 until the calibration ends (t_CAL)."""
    m = machine()
    clocks_72mhz(m)
    write(m.adc1, "CR2", 1)
    at(m, m.now + 2 * US)
    write(m.adc1, "CR2", 5)
    start = m.now
    at(m, start + 83 * 6 - 1)
    assert read(m.adc1, "CR2") & 4
    at(m, start + 83 * 6)
    assert not read(m.adc1, "CR2") & 4


def test_adc_calibration_before_power_up_settles_should_be_an_error() -> None:
    m = machine()
    clocks_72mhz(m)
    write(m.adc1, "CR2", 1)
    with pytest.raises(PilError, match="t_STAB"):
        write(m.adc1, "CR2", 5)


def test_adc_injected_sequence_should_follow_jsqr_with_offsets_and_timing() -> None:
    """RM0008 11.3.4, JSQR with JL = 3 into JDR1..4, JOFRx subtracted (signed), each
    conversion SMP + 12.5 ADC cycles (11.6), JEOC at the end with its interrupt."""
    m = machine(vref=3.3)
    adc_ready(m)
    for channel, volts in ((0, 1.65), (1, 2.2), (2, 0.0)):
        m.adc1.set_input(channel, volts)
    write(m.adc1, "SMPR2", 1 | (1 << 3))  # 7.5 cycles on IN0, IN1; 1.5 on IN2
    write(m.adc1, "JSQR", (3 << 20) | (0 << 0) | (1 << 5) | (2 << 10) | (1 << 15))
    write(m.adc1, "JOFR1", 2048)
    write(m.adc1, "CR1", (1 << 8) | (1 << 7))  # SCAN, JEOCIE
    write(m.adc1, "CR2", 1 | (1 << 15) | (7 << 12))
    m.nvic.active.append(2)
    write(m.adc1, "CR2", 1 | (1 << 15) | (7 << 12) | (1 << 21))  # JSWSTART
    start = m.now
    half = 3  # ticks per half ADC cycle at 12 MHz
    end = start + (20 + 20 + 14 + 20) * 2 * half
    at(m, end - 1)
    assert not read(m.adc1, "SR") & 4
    at(m, end)
    assert read(m.adc1, "SR") & 0b1100 == 0b1100  # JEOC, JSTRT
    assert [read(m.adc1, f"JDR{k}") for k in (1, 2, 3, 4)] == [0, 2730, 0, 2730]
    assert IRQ_BASE + ADC_IRQ in m.nvic.pending
    m.adc1.set_input(0, 1.0)
    write(m.adc1, "CR2", 1 | (1 << 15) | (7 << 12) | (1 << 21))
    at(m, m.now + 200)
    assert read(m.adc1, "JDR1") == (1241 - 2048) & 0xFFFF


def test_adc_analog_watchdog_should_flag_the_guarded_channel_only() -> None:
    """RM0008 11.3.7: JAWDEN with AWDSGL on AWDCH: a result above HTR sets AWD."""
    m = machine()
    adc_ready(m)
    m.adc1.set_input(0, 3.0)
    m.adc1.set_input(1, 1.0)
    write(m.adc1, "JSQR", (1 << 20) | (0 << 10) | (1 << 15))
    write(m.adc1, "HTR", 2000)
    write(m.adc1, "LTR", 1000)
    write(m.adc1, "CR1", (1 << 8) | (1 << 22) | (1 << 9) | 1)  # SCAN, JAWDEN, AWDSGL, CH1
    write(m.adc1, "CR2", 1 | (1 << 15) | (7 << 12) | (1 << 21))
    at(m, m.now + 300)
    assert not read(m.adc1, "SR") & 1  # IN0 at 3 V is not watched
    m.adc1.set_input(1, 2.0)  # 2482 > HTR
    write(m.adc1, "CR1", (1 << 8) | (1 << 22) | (1 << 9) | (1 << 6) | 1)
    m.nvic.active.append(2)
    write(m.adc1, "CR2", 1 | (1 << 15) | (7 << 12) | (1 << 21))
    at(m, m.now + 300)
    assert read(m.adc1, "SR") & 1 and IRQ_BASE + ADC_IRQ in m.nvic.pending


def test_adc_tim1_trgo_should_trigger_and_a_busy_adc_ignore_it() -> None:
    """RM0008 11.12.2 JEXTSEL = 000: TIM1 TRGO starts the injected sequence; a trigger
    during a conversion is ignored."""
    m = machine()
    adc_ready(m)
    m.adc1.set_input(0, 1.0)
    write(m.adc1, "SMPR2", 7)  # 239.5 cycles: longer than the 100-count PWM period
    write(m.adc1, "JSQR", 0)
    write(m.adc1, "CR2", 1 | (1 << 15))
    tim1_pwm(m)
    write(m.tim1, "CCR4", 50)
    write(m.tim1, "CR2", 7 << 4)
    at(m, m.now + 4000)
    # 252 ADC cycles = 1512 ticks per conversion, a trigger every 100 ticks
    assert m.adc1.injected_sequences == 3 and m.adc1.ignored_triggers >= 30


def test_adc_regular_conversion_should_start_on_adon_rewrite() -> None:
    """RM0008 11.3.1 / 11.12.3: ADON written again alone starts a conversion; DR read
    clears EOC; a write that changes another bit starts nothing."""
    m = machine()
    adc_ready(m)
    m.adc1.set_input(5, 1.65)
    write(m.adc1, "SQR3", 5)
    write(m.adc1, "CR2", 1)
    at(m, m.now + 200)
    assert read(m.adc1, "SR") & 2
    assert read(m.adc1, "DR") == 2048 and not read(m.adc1, "SR") & 2
    write(m.adc1, "CR2", 1 | (1 << 15))
    at(m, m.now + 200)
    assert not read(m.adc1, "SR") & 2


def test_adc_unmodelled_modes_should_be_errors() -> None:
    m = machine()
    adc_ready(m)
    with pytest.raises(PilError, match="RSTCAL"):
        write(m.adc1, "CR2", 1 | 8)
    with pytest.raises(PilError, match="discontinuous"):
        write(m.adc1, "CR1", 1 << 11)


def continuous_bus(m: Machine, channel: int, cr1: int) -> None:
    """The drive's regular group: one channel, IN0..IN3 at 7.5 cycles (20 ADC cycles = 120 ticks
    per conversion at 12 MHz), continuous, started by SWSTART (EXTSEL = 111)."""
    write(m.adc1, "SMPR2", 0o1111)  # IN0..IN3
    write(m.adc1, "SQR3", channel)
    write(m.adc1, "CR1", cr1)
    cr2 = 1 | 2 | (1 << 20) | (7 << 17) | (1 << 15) | (7 << 12)  # ADON CONT EXTTRIG JEXTTRIG
    write(m.adc1, "CR2", cr2)
    write(m.adc1, "CR2", cr2 | (1 << 22))  # SWSTART


def test_adc_continuous_mode_should_convert_the_regular_group_back_to_back() -> None:
    """RM0008 11.3.5: with CONT the regular sequence starts again as soon as it ends;
    DR holds the latest result, taken at the end of its sampling window."""
    m = machine(vref=3.3)
    adc_ready(m)
    start_input = m.now
    m.adc1.set_input(3, lambda tick: 1.0 if tick < start_input + 1000 else 2.0)
    continuous_bus(m, 3, 0)
    start = m.now
    at(m, start + 119)
    assert read(m.adc1, "SR") & 2 == 0 and m.adc1.regular_conversions == 0
    at(m, start + 120)
    assert read(m.adc1, "DR") == 1241 and m.adc1.regular_conversions == 1
    at(m, start + 10 * 120)
    # the 9th conversion sampled at start + 8 x 120 + 45 (7.5 cycles) > 1000 ticks
    assert read(m.adc1, "DR") == 2482 and m.adc1.regular_conversions == 10
    m.adc1.set_input(3, 0.5)  # a constant input: whole sequences at once
    at(m, start + 1_000_000 * 120)
    assert read(m.adc1, "DR") == 620 and m.adc1.regular_conversions == 1_000_000


def test_adc_an_injected_trigger_should_reset_and_then_resume_the_regular_conversion() -> None:
    """RM0008 11.3.9: the regular conversion under way is reset, the injected sequence
    converted, then the regular sequence resumes with the interrupted conversion."""
    m = machine(vref=3.3)
    adc_ready(m)
    m.adc1.set_input(3, 1.0)
    m.adc1.set_input(0, 2.0)
    write(m.adc1, "JSQR", 0)  # JL = 0: JSQ4 = IN0
    continuous_bus(m, 3, 1 << 8)
    m.adc1.keep_sample_log = True
    start = m.now
    at(m, start + 60)  # half-way through the first regular conversion
    write(m.adc1, "CR2", read(m.adc1, "CR2") | (7 << 12) | (1 << 21))  # JSWSTART
    at(m, start + 60 + 119)
    assert not read(m.adc1, "SR") & 4 and m.adc1.regular_conversions == 0
    at(m, start + 60 + 120)
    assert read(m.adc1, "SR") & 4 and read(m.adc1, "JDR4") == 2482
    assert m.adc1.regular_conversions == 0  # the interrupted one was lost
    at(m, start + 60 + 240)
    assert read(m.adc1, "SR") & 2 and m.adc1.regular_conversions == 1 and read(m.adc1, "DR") == 1241
    ticks = [tick for tick, _channel, _raw in m.adc1.sample_log]
    assert ticks == [start + 60 + 45, start + 180 + 45]  # injected, then the regular again


def test_adc_a_regular_start_during_an_injected_sequence_should_wait_for_its_end() -> None:
    """RM0008 11.3.9: a regular event during an injected conversion does not interrupt it."""
    m = machine(vref=3.3)
    adc_ready(m)
    m.adc1.set_input(3, 1.0)
    m.adc1.set_input(0, 2.0)
    write(m.adc1, "SMPR2", (1 << 9) | 1)
    write(m.adc1, "JSQR", 0)
    write(m.adc1, "SQR3", 3)
    cr2 = 1 | 2 | (1 << 20) | (7 << 17) | (1 << 15) | (7 << 12)
    write(m.adc1, "CR2", cr2)
    write(m.adc1, "CR2", cr2 | (1 << 21))  # JSWSTART
    start = m.now
    at(m, start + 30)
    write(m.adc1, "CR2", cr2 | (1 << 22))  # SWSTART
    at(m, start + 120 + 119)
    assert not read(m.adc1, "SR") & 2 and m.adc1.regular_conversions == 0
    at(m, start + 240)
    assert read(m.adc1, "SR") & 2 and m.adc1.regular_conversions == 1


def test_adc_regular_analog_watchdog_should_interrupt_at_the_first_conversion_outside() -> None:
    """RM0008 11.3.7: AWDEN with AWDSGL on AWDCH guards the regular conversions: AWD and
    its interrupt at the end of the first regular conversion above HTR; none with
    AWDEN clear (JAWDEN alone guards the injected ones only)."""
    m = machine(vref=3.3)
    adc_ready(m)
    step = m.now + 5000
    m.adc1.set_input(3, lambda tick: 3.0 if tick >= step else 1.0)
    write(m.adc1, "HTR", 3000)
    write(m.adc1, "LTR", 100)
    m.nvic.active.append(2)
    continuous_bus(m, 3, (1 << 23) | (1 << 9) | (1 << 6) | 3)  # AWDEN AWDSGL AWDIE CH3
    start = m.now
    at(m, step)
    assert not read(m.adc1, "SR") & 1
    first = start + 120 * ((step - start - 45) // 120 + 1)  # first sampled at or after step
    first += 120 if first - 120 + 45 < step else 0
    at(m, first - 1)
    assert IRQ_BASE + ADC_IRQ not in m.nvic.pending
    at(m, first)
    assert IRQ_BASE + ADC_IRQ in m.nvic.pending and read(m.adc1, "SR") & 1
    m2 = machine(vref=3.3)
    adc_ready(m2)
    m2.adc1.set_input(3, 3.0)
    write(m2.adc1, "HTR", 3000)
    continuous_bus(m2, 3, (1 << 22) | (1 << 9) | (1 << 6) | 3)  # JAWDEN only
    at(m2, m2.now + 10_000)
    assert not read(m2.adc1, "SR") & 1


class _StepInput:
    """1 V, then 3 V from `step`; it bounds itself as the motor's current sense does
    (emulation/pil/adc.py `BoundedInput`): honestly, or, `lying`, inside the window
    whatever the tick (a bound the ADC then believes)."""

    def __init__(self, step: int, lying: bool = False) -> None:
        self.step = step
        self.lying = lying
        self.calls: list[int] = []

    def __call__(self, tick: int) -> float:
        self.calls.append(tick)
        return 3.0 if tick >= self.step else 1.0

    def volts_range(self, lo: int, hi: int) -> tuple[float, float] | None:
        if self.lying or hi < self.step:
            return 0.9, 1.1
        return None  # may be 3 V: no bound


@pytest.mark.parametrize("bounded", [False, True])
def test_adc_a_bounded_input_should_set_awd_at_the_same_conversion_converting_fewer(
    bounded: bool,
) -> None:
    """A watched regular conversion whose input's bound lies inside [LTR, HTR] cannot
    set AWD: it is counted unconverted, and DR converted when read; the first
    conversion sampled at or after the step interrupts at the same tick as with a plain
    function input, which is converted at every conversion. A bound that lies hides the
    step (so the check is the bound's, as the plant's is held to the switched plant:
    tests/test_pil_current_bound.py)."""
    m = machine(vref=3.3)
    adc_ready(m)
    step = m.now + 5000
    source = _StepInput(step)
    m.adc1.set_input(3, source if bounded else lambda tick: source(tick))
    write(m.adc1, "HTR", 3000)
    write(m.adc1, "LTR", 100)
    m.nvic.active.append(2)
    continuous_bus(m, 3, (1 << 23) | (1 << 9) | (1 << 6) | 3)  # AWDEN AWDSGL AWDIE CH3
    start = m.now
    first = start + 120 * ((step - start - 45) // 120 + 1)
    first += 120 if first - 120 + 45 < step else 0
    at(m, first - 1)
    assert IRQ_BASE + ADC_IRQ not in m.nvic.pending and not read(m.adc1, "SR") & 1
    converted = len(source.calls)
    counted = m.adc1.regular_conversions
    assert counted == (first - start) // 120 - 1 >= 30
    before = [tick for tick in source.calls if tick < step]
    # plain: each conversion looked at ahead, then converted; bounded: only the one
    # sampled after the step, looked at ahead for the alarm
    assert len(before) >= counted if not bounded else before == []
    assert read(m.adc1, "DR") == 1241  # the latest conversion, converted now if not yet
    assert len(source.calls) == converted + (1 if bounded else 0)
    at(m, first)
    assert IRQ_BASE + ADC_IRQ in m.nvic.pending and read(m.adc1, "SR") & 1

    m2 = machine(vref=3.3)
    adc_ready(m2)
    m2.adc1.set_input(3, _StepInput(step - start + m2.now, lying=True))
    write(m2.adc1, "HTR", 3000)
    continuous_bus(m2, 3, (1 << 23) | (1 << 9) | (1 << 6) | 3)
    at(m2, m2.now + 20_000)
    assert not read(m2.adc1, "SR") & 1 and read(m2.adc1, "DR") == 3723


# ---------------------------------------------------------------------- NVIC, SCB, SysTick, IWDG


def test_nvic_priority_bytes_should_keep_four_bits() -> None:
    """PM0056 4.3.7: IPR is byte-accessible; the STM32F103 implements bits 7:4."""
    m = machine()
    m.nvic.write(0x400 + 18, 1, 0x1F)
    assert m.nvic.priority[18] == 0x10
    assert m.nvic.read(0x400 + 16, 4) == 0x10 << 16


def test_nvic_enable_and_pending_registers() -> None:
    """PM0056 4.3.2-4.3.5: ISER/ICER and ISPR/ICPR set and clear; IABR reads active."""
    m = machine()
    m.nvic.write(0x100, 4, 1 << 29)
    assert m.nvic.read(0x180, 4) == 1 << 29
    m.nvic.write(0x180, 4, 1 << 29)
    assert m.nvic.read(0x100, 4) == 0
    m.nvic.write(0x200, 4, 1 << 29)
    assert m.nvic.read(0x280, 4) == 1 << 29
    m.nvic.write(0x280, 4, 1 << 29)
    assert m.nvic.read(0x200, 4) == 0


def test_nvic_clearing_a_pending_level_interrupt_should_not_stick() -> None:
    """PM0056 4.3.9: an interrupt whose request is still asserted stays pending."""
    m = machine()
    m.nvic.set_line(29, True)
    m.nvic.write(0x280, 4, 1 << 29)
    assert IRQ_BASE + 29 in m.nvic.pending
    m.nvic.set_line(29, False)
    m.nvic.write(0x280, 4, 1 << 29)
    assert IRQ_BASE + 29 not in m.nvic.pending


def test_scb_aircr_needs_its_key_and_sets_the_grouping() -> None:
    """PM0056 4.4.5: writes without VECTKEY 0x05FA are ignored."""
    m = machine()
    m.scb.write(0x0C, 4, 5 << 8)
    assert m.nvic.prigroup == 0
    m.scb.write(0x0C, 4, (0x05FA << 16) | (5 << 8))
    assert m.nvic.prigroup == 5 and m.scb.read(0x0C, 4) >> 8 & 7 == 5


def test_scb_shpr3_should_set_the_systick_priority() -> None:
    """PM0056 4.4.8: SHPR3 bits 31:24 are SysTick's priority."""
    m = machine()
    m.scb.write(0x23, 1, 0xF0)
    assert m.nvic.priority_of(SYSTICK) == 0xF0


def test_systick_should_reload_and_flag_each_wrap() -> None:
    """PM0056 4.5: CVR write clears; RVR loads on the next count; COUNTFLAG at 1 -> 0,
    cleared by reading CSR; the clock is HCLK with CLKSOURCE = 1."""
    m = machine()
    m.systick.write(0x4, 4, 99)
    m.systick.write(0x8, 4, 0)
    m.systick.write(0x0, 4, 0b101)
    start = m.now
    tick = TICK_HZ // 8_000_000
    at(m, start + 1 * tick)
    assert m.systick.read(0x8, 4) == 99
    at(m, start + 99 * tick)
    assert not m.systick.read(0x0, 4) & (1 << 16)
    at(m, start + 100 * tick)
    assert m.systick.read(0x0, 4) & (1 << 16)
    assert not m.systick.read(0x0, 4) & (1 << 16)


def test_cycle_counter_should_count_processor_cycles_once_both_enables_are_set() -> None:
    """ARMv7-M ARM C1.8.7: DWT_CYCCNT counts the processor clock while DWT_CTRL.CYCCNTENA
    and DEMCR.TRCENA are set, wraps at 2^32 and takes writes; other bits are errors."""
    m = machine()
    tick = TICK_HZ // 8_000_000  # HCLK out of reset: the 8 MHz HSI
    assert m.dwt.read(0x0, 4) == 4 << 28  # NUMCOMP: the M3's 4 comparators, read-only
    m.dwt.write(0x0, 4, m.dwt.read(0x0, 4) | 1)  # the port's read-modify-write
    at(m, m.now + 50 * tick)
    assert m.dwt.read(0x4, 4) == 0  # TRCENA still 0: the DWT is off
    m.coredebug.write(0xC, 4, 1 << 24)
    start = m.now
    at(m, start + 40 * tick)
    assert m.dwt.read(0x4, 4) == 40
    m.dwt.write(0x4, 4, 0xFFFF_FFF0)
    at(m, m.now + 20 * tick)
    assert m.dwt.read(0x4, 4) == 4  # wrapped
    m.dwt.write(0x0, 4, 0)
    held = m.dwt.read(0x4, 4)
    at(m, m.now + 30 * tick)
    assert m.dwt.read(0x4, 4) == held  # CYCCNTENA cleared: it holds
    with pytest.raises(UnmodelledAccessError):
        m.dwt.write(0x0, 4, 1 << 22)  # a profiling counter's enable: not modelled
    with pytest.raises(UnmodelledAccessError):
        m.coredebug.write(0xC, 4, 1 << 16)  # MON_EN: halting debug is not modelled


def test_systick_tickint_should_pend_the_exception() -> None:
    m = machine()
    m.nvic.active.append(2)
    m.systick.write(0x4, 4, 9)
    m.systick.write(0x0, 4, 0b111)
    at(m, m.now + 20 * 9)
    assert SYSTICK in m.nvic.pending


def test_iwdg_should_reset_the_chip_when_starved() -> None:
    """RM0008 19.3: 0xCCCC starts it; without 0xAAAA it reaches 0 after
    4 x 2^PR x (RLR + 1) LSI periods: a reset, reported as an error."""
    m = machine(lsi_hz=40_000)
    write(m.iwdg, "KR", 0x5555)
    write(m.iwdg, "PR", 0)
    write(m.iwdg, "RLR", 99)
    at(m, m.now + TICK_HZ // 1000)  # let the update reach the LSI domain
    assert read(m.iwdg, "SR") == 0
    write(m.iwdg, "KR", 0xCCCC)
    start = m.now
    assert m.iwdg.timeout_ticks() == 4 * 100 * TICK_HZ // 40_000
    at(m, start + m.iwdg.timeout_ticks() - 100)
    write(m.iwdg, "KR", 0xAAAA)
    with pytest.raises(WatchdogResetError, match="starved"):
        at(m, m.now + m.iwdg.timeout_ticks() + 1)


def test_iwdg_prescaler_should_need_the_unlock_key() -> None:
    """RM0008 19.4.2: PR and RLR are write-protected until 0x5555."""
    m = machine()
    write(m.iwdg, "PR", 3)
    at(m, m.now + TICK_HZ // 1000)
    assert read(m.iwdg, "PR") == 0
    write(m.iwdg, "KR", 0x5555)
    write(m.iwdg, "PR", 3)
    assert read(m.iwdg, "SR") & 1  # PVU while it crosses into the LSI domain
    at(m, m.now + TICK_HZ // 1000)
    assert read(m.iwdg, "PR") == 3 and not read(m.iwdg, "SR") & 1


def test_an_unmodelled_register_should_raise_with_its_name() -> None:
    m = machine()
    with pytest.raises(UnmodelledAccessError, match=r"TIM1\.DCR"):
        read(m.tim1, "DCR")


# ---------------------------------------------------------------------- AFIO, EXTI

EXTI0_IRQ, EXTI9_5_IRQ = 6, 23


def exti_on_hall_pins(m: Machine, *, rising: bool = True, falling: bool = True) -> None:
    """PA6, PA7 and PB0 inputs with pull-up, driven low; EXTI0 <- PB0, EXTI6/7 <- PA6/7."""
    clocks_72mhz(m)
    write(m.gpioa, "CRL", (0x88 << 24) | 0x8)  # PA0 too (input with pull)
    write(m.gpiob, "CRL", 0x8)
    for port, pin in (("gpioa", 6), ("gpioa", 7), ("gpiob", 0), ("gpioa", 0)):
        getattr(m, port).drive(pin, False)
    write(m.afio, "EXTICR1", 0x1)  # EXTI0: PB
    write(m.afio, "EXTICR2", 0x0)  # EXTI4..7: PA
    lines = (1 << 0) | (1 << 6) | (1 << 7)
    write(m.exti, "RTSR", lines if rising else 0)
    write(m.exti, "FTSR", lines if falling else 0)
    write(m.exti, "IMR", lines)


def test_afio_exticr_should_pick_the_port_of_each_line() -> None:
    """RM0008 9.4.3: EXTICR1 bits 3:0 route EXTI0 to PA (0000) or PB (0001): only the
    selected port's pin 0 sets PR0."""
    m = machine()
    exti_on_hall_pins(m)
    m.gpioa.drive(0, True)  # PA0 is not EXTI0's port
    assert not read(m.exti, "PR") & 1
    m.gpiob.drive(0, True)
    assert read(m.exti, "PR") & 1
    write(m.afio, "EXTICR1", 0x0)  # EXTI0 <- PA0 now
    write(m.exti, "PR", 1)
    m.gpiob.drive(0, False)
    assert not read(m.exti, "PR") & 1
    m.gpioa.drive(0, False)
    assert read(m.exti, "PR") & 1
    assert read(m.afio, "EXTICR1") == 0


def test_afio_exticr_should_need_its_clock_and_refuse_other_ports() -> None:
    """RM0008 7.3.7: AFIO's registers need APB2ENR.AFIOEN; ports C..G are not modelled."""
    m = machine()
    with pytest.raises(PilError, match="clock"):
        m._peripheral_at(m.afio.base + 8)
    clocks_72mhz(m)
    with pytest.raises(PilError, match="only PA and PB"):
        write(m.afio, "EXTICR2", 0x2 << 8)


@pytest.mark.parametrize(("rising", "falling"), [(True, False), (False, True), (True, True)])
def test_exti_should_pend_on_the_selected_edges(rising: bool, falling: bool) -> None:
    """RM0008 10.3.3 RTSR, 10.3.4 FTSR: the selected edges set PR (both with both)."""
    m = machine()
    exti_on_hall_pins(m, rising=rising, falling=falling)
    m.gpioa.drive(6, True)
    assert bool(read(m.exti, "PR") & (1 << 6)) == rising
    write(m.exti, "PR", 1 << 6)
    m.gpioa.drive(6, False)
    assert bool(read(m.exti, "PR") & (1 << 6)) == falling


def test_exti_pending_lines_should_raise_their_shared_vectors_until_cleared() -> None:
    """RM0008 10.2.4 and the vector table: PR0 with IMR0 raises EXTI0; lines 5..9 share EXTI9_5,
    whose request stays while any of its lines is pending; PR is rc_w1 (10.3.6)."""
    m = machine()
    exti_on_hall_pins(m)
    m.nvic.active.append(2)  # nothing is taken: the pending state is what is checked
    m.gpioa.drive(6, True)
    m.gpioa.drive(7, True)
    assert m.nvic.line[EXTI9_5_IRQ] and not m.nvic.line[EXTI0_IRQ]
    assert IRQ_BASE + EXTI9_5_IRQ in m.nvic.pending
    write(m.exti, "PR", 1 << 6)
    assert m.nvic.line[EXTI9_5_IRQ]  # line 7 still pending
    write(m.exti, "PR", 0)  # writing 0 clears nothing
    assert read(m.exti, "PR") == 1 << 7
    write(m.exti, "PR", 1 << 7)
    assert not m.nvic.line[EXTI9_5_IRQ]
    m.gpiob.drive(0, True)
    assert m.nvic.line[EXTI0_IRQ]


def test_exti_masked_line_should_pend_but_not_interrupt() -> None:
    """RM0008 10.2.2 (the block diagram): the edge sets PR; IMR gates the request."""
    m = machine()
    exti_on_hall_pins(m)
    write(m.exti, "IMR", 0)
    m.gpiob.drive(0, True)
    assert read(m.exti, "PR") & 1 and not m.nvic.line[EXTI0_IRQ]
    write(m.exti, "IMR", 1)
    assert m.nvic.line[EXTI0_IRQ]


def test_exti_software_interrupt_should_pend_an_unmasked_line() -> None:
    """RM0008 10.3.5: SWIER bit x at 0 written 1 with IMR x set sets PR x; clearing PR x
    clears SWIER x; with IMR x clear it sets nothing."""
    m = machine()
    exti_on_hall_pins(m)
    write(m.exti, "SWIER", 1 << 7)
    assert read(m.exti, "PR") & (1 << 7) and read(m.exti, "SWIER") & (1 << 7)
    write(m.exti, "PR", 1 << 7)
    assert not read(m.exti, "SWIER") & (1 << 7)
    write(m.exti, "IMR", 0)
    write(m.exti, "SWIER", 1 << 6)
    assert not read(m.exti, "PR") & (1 << 6)


def test_exti_lines_16_to_18_and_events_should_not_be_modelled() -> None:
    m = machine()
    with pytest.raises(PilError, match=r"lines 16\.\.18"):
        write(m.exti, "IMR", 1 << 16)
    with pytest.raises(UnmodelledAccessError, match="EMR"):
        write(m.exti, "EMR", 1)


# ---------------------------------------------------------------------- ADC2


def test_adc2_should_sit_at_its_own_base_and_share_adc1s_pins_and_interrupt() -> None:
    """RM0008 11.1 / the SVD: ADC2 at 0x40012800, its own registers; the analog inputs
    ADC12_INx are the same pins for both; ADC1_2 is one NVIC line for both (high while
    either requests)."""
    m = machine(vref=3.3)
    assert m.adc2.base == 0x40012800 and m.adc1.base == 0x40012400
    clocks_72mhz(m)
    m.adc1.set_input(2, 3.3)  # set once, on the pin
    m.adc2.set_input(3, 1.65)
    for adc in (m.adc1, m.adc2):
        write(adc, "CR2", 1)
    at(m, m.now + 2 * US)
    m.nvic.active.append(2)
    write(m.adc2, "HTR", 4000)
    write(m.adc2, "LTR", 1)
    write(m.adc2, "SMPR2", 1 << 6)  # IN2: 7.5 cycles
    write(m.adc2, "SQR3", 2)
    cr2 = 1 | 2 | (1 << 20) | (7 << 17)  # ADON CONT EXTTRIG, EXTSEL = SWSTART
    write(m.adc2, "CR1", (1 << 23) | (1 << 6))  # AWDEN, AWDIE (every regular channel)
    write(m.adc2, "CR2", cr2)
    write(m.adc2, "CR2", cr2 | (1 << 22))
    at(m, m.now + 120)  # one conversion: 20 ADC cycles at 12 MHz
    assert read(m.adc2, "DR") == 4095 and read(m.adc2, "SR") & 1  # AWD above HTR
    assert not read(m.adc1, "SR") & 1
    assert m.nvic.line[ADC_IRQ]
    m.adc1.set_input(2, 1.0)
    write(m.adc2, "CR1", 1 << 23)  # AWDIE off
    write(m.adc2, "SR", 0)
    assert not m.nvic.line[ADC_IRQ]
    write(m.adc1, "CR1", 1 << 5)  # ADC1's EOCIE: the same line for ADC1's request
    write(m.adc1, "SQR3", 3)
    write(m.adc1, "SMPR2", 1 << 9)
    write(m.adc1, "CR2", cr2)
    write(m.adc1, "CR2", cr2 | (1 << 22))
    at(m, m.now + 240)
    assert read(m.adc2, "DR") == 1241  # the new level on the shared pin
    assert m.nvic.line[ADC_IRQ] and read(m.adc1, "SR") & 2


# ---------------------------------------------------------------------- the board's pins and event order


def test_a_scheduled_pin_level_should_take_effect_at_its_exact_tick() -> None:
    """`Gpio.drive_at`: the level changes at its tick even while the CPU is busy (a pulse
    shorter than TIM3's input filter stays a glitch: RM0008 15.4.7, N = 8)."""
    m = machine()
    tim3_hall(m, filter_code=3)
    at(m, m.now + 100)
    start = m.now
    m.gpioa.drive(6, True)
    m.gpioa.drive_at(6, False, start + 5)
    m.run_for(40)  # one step well past both the pulse and the filter
    assert m.tim3.captures == 0
    assert not read(m.gpioa, "IDR") & (1 << 6)
    m.gpioa.drive_at(6, True, m.now + 3)
    m.run_for(30)
    assert m.tim3.captures == 1
    with pytest.raises(PilError, match="before now"):
        m.gpioa.drive_at(6, False, m.now - 1)


def test_events_run_past_at_once_should_be_processed_in_time_order() -> None:
    """The machine may pass several events in one step (a block, an exception entry):
    TIM3's filtered edge (due 8 ticks after the pin change) comes before the pin's
    scheduled return 14 ticks after it, though GPIOA is listed before TIM3."""
    m = machine()
    tim3_hall(m, filter_code=3)
    at(m, m.now + 100)
    start = m.now
    m.gpioa.drive(6, True)
    m.gpioa.drive_at(6, False, start + 14)
    m.now = start + 40  # as if the CPU had run past both
    m._process_events()
    # the change at +0 captured at +8, then the return at +14 captured at +22: two
    # edges (out of order, the return would have read as a glitch and cancelled both)
    assert m.tim3.captures == 2

"""RCC (RM0008 section 7) and the flash interface's access control (section 3.3.3).

Time is counted in ticks of 1/72 MHz (`TICK_HZ`), the fastest clock of the chip; every
clock the drive uses divides it (HSI and HSE 8 MHz: 9 ticks, ADC 12 MHz: 6 ticks).

Behaviours modelled, each with its RM0008 section:
* 7.2.1 HSE: HSEON starts the oscillator, HSERDY rises after `hse_startup_ticks`
  (datasheet t_SU(HSE), 2 ms typical for 8 MHz); `hse_fails=True` makes it never start
  (the HSE-timeout scenario). 7.2.2 HSI: on and ready out of reset.
* 7.2.3 PLL: PLLON locks after `pll_lock_ticks` (datasheet t_LOCK, 200 us max), PLLRDY;
  PLLSRC, PLLXTPRE and PLLMUL "can be written only when PLL is disabled" (7.3.2): a write
  that changes them with PLLON set is an error here.
* 7.2.6 system clock switch: SW selects, SWS follows once the source is ready (a source
  that is not ready is not switched to). 3.3.3: SYSCLK above 48 MHz needs
  FLASH_ACR.LATENCY = 2 (above 24 MHz 1): switching to a clock too fast for the
  latency set is an error, since the chip would read the flash wrongly.
* 7.3.2 prescalers HPRE, PPRE1, PPRE2, ADCPRE; the timer clocks are PCLKx, times 2 when
  the APB prescaler is not 1 (7.2, Figure 8).
* 7.2.7 clock security system: with CSSON, an HSE failure (`fail_hse(at)`) sets CSSF,
  raises the NMI, sends the clock failure event to TIM1's break input and, if the HSE
  fed SYSCLK (directly or by the PLL), switches SYSCLK to the HSI. CIR.CSSC clears CSSF.
* 7.3.7, 7.3.8 APB2ENR, APB1ENR: a model whose clock is off refuses register accesses
  (on the chip they would read 0 and be ignored).
* 7.3.10 CSR: reset flags (PORRSTF and PINRSTF after power-on, IWDGRSTF after a watchdog
  reset), RMVF clears them; LSION/LSIRDY (the IWDG turns the LSI on itself).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from emulation.pil.bus import Peripheral, PilError, bits

if TYPE_CHECKING:
    from emulation.pil.machine import Machine

TICK_HZ = 72_000_000
HSI_HZ = 8_000_000
HSE_HZ = 8_000_000  # the drive's crystal (spec: firmware clock tree)

CR_HSION, CR_HSIRDY, CR_HSEON, CR_HSERDY, CR_HSEBYP, CR_CSSON, CR_PLLON, CR_PLLRDY = (
    1 << 0,
    1 << 1,
    1 << 16,
    1 << 17,
    1 << 18,
    1 << 19,
    1 << 24,
    1 << 25,
)
CFGR_PLL_CONFIG = (1 << 16) | (1 << 17) | (0xF << 18)  # PLLSRC, PLLXTPRE, PLLMUL
CIR_CSSF, CIR_CSSC = 1 << 7, 1 << 23
CIR_WRITABLE = 0x1F00  # LSIRDYIE..PLLRDYIE; the *RDYC clear bits are write-only
CSR_LSION, CSR_LSIRDY, CSR_RMVF = 1 << 0, 1 << 1, 1 << 24
CSR_PINRSTF, CSR_PORRSTF, CSR_IWDGRSTF = 1 << 26, 1 << 27, 1 << 29
CSR_RESET_FLAGS = 0xFC000000

APB2_CLOCKS = {"AFIO": 0, "GPIOA": 2, "GPIOB": 3, "GPIOC": 4, "ADC1": 9, "ADC2": 10, "TIM1": 11}
APB1_CLOCKS = {"TIM3": 1}
_AHB_DIVIDERS = {8: 2, 9: 4, 10: 8, 11: 16, 12: 64, 13: 128, 14: 256, 15: 512}
_APB_DIVIDERS = {4: 2, 5: 4, 6: 8, 7: 16}


def _ahb_divider(hpre: int) -> int:
    return _AHB_DIVIDERS.get(hpre, 1)


def _apb_divider(ppre: int) -> int:
    return _APB_DIVIDERS.get(ppre, 1)


class Flash(Peripheral):
    """FLASH_ACR (RM0008 3.3.3): LATENCY and PRFTBE read back; HLFCYA must stay 0.
    PRFTBS (the prefetch buffer status) follows PRFTBE."""

    def __init__(self, machine: Machine) -> None:
        super().__init__(machine, "FLASH")
        self.acr = 0x30  # reset: prefetch enabled and on, zero wait states
        self.readers = {"ACR": lambda: self.acr}
        self.writers = {"ACR": self._write_acr}

    @property
    def latency(self) -> int:
        return self.acr & 7

    def _write_acr(self, value: int) -> None:
        latency = value & 7
        if latency > 2:
            raise PilError(f"FLASH.ACR.LATENCY = {latency}: RM0008 3.3.3 allows 0, 1 or 2")
        if value & (1 << 3):
            raise PilError("FLASH.ACR.HLFCYA = 1: half-cycle access is not modelled")
        if (
            latency < self.machine.rcc.latency_needed(self.machine.rcc.sysclk_hz)
            and self.machine.rcc.sysclk_hz
        ):
            raise PilError(
                f"FLASH.ACR.LATENCY = {latency} with SYSCLK at {self.machine.rcc.sysclk_hz} Hz:"
                " RM0008 3.3.3 needs more wait states"
            )
        prefetch = value & (1 << 4)
        self.acr = latency | prefetch | (prefetch << 1)


class Rcc(Peripheral):
    def __init__(
        self,
        machine: Machine,
        *,
        hse_startup_ticks: int = 2 * TICK_HZ // 1000,
        pll_lock_ticks: int = 200 * TICK_HZ // 1_000_000,
        hse_fails: bool = False,
    ) -> None:
        super().__init__(machine, "RCC")
        self.hse_startup_ticks = hse_startup_ticks
        self.pll_lock_ticks = pll_lock_ticks
        self.hse_fails = hse_fails
        self.cr = CR_HSION | CR_HSIRDY | (16 << 3)  # HSITRIM reset value 16
        self.cfgr = 0
        self.cir = 0
        self.apb2enr = 0
        self.apb1enr = 0
        self.ahbenr = 0x14  # SRAM and FLITF clocks on in Sleep mode (reset value)
        self.csr = CSR_PORRSTF | CSR_PINRSTF
        self.hse_ready_at: int | None = None
        self.pll_ready_at: int | None = None
        self.hse_failure_at: int | None = None
        self.sysclk_source = 0  # SWS: 0 HSI, 1 HSE, 2 PLL
        self._derived_key: tuple[int, int] | None = None
        self._derived_hz = (0, 0, 0)
        self.readers = {
            "CR": self._read_cr,
            "CFGR": lambda: self.cfgr,
            "CIR": lambda: self.cir,
            "APB2ENR": lambda: self.apb2enr,
            "APB1ENR": lambda: self.apb1enr,
            "AHBENR": lambda: self.ahbenr,
            "CSR": self._read_csr,
        }
        self.writers = {
            "CR": self._write_cr,
            "CFGR": self._write_cfgr,
            "CIR": self._write_cir,
            "APB2ENR": self._write_apb2enr,
            "APB1ENR": self._write_apb1enr,
            "CSR": self._write_csr,
        }

    # ----------------------------------------------------------------- clocks
    def _hse_on(self) -> bool:
        return bool(self.cr & CR_HSERDY)

    @property
    def pll_hz(self) -> int:
        source = (
            HSE_HZ // (2 if self.cfgr & (1 << 17) else 1) if self.cfgr & (1 << 16) else HSI_HZ // 2
        )
        multiplier = min(bits(self.cfgr, 18, 4) + 2, 16)
        return source * multiplier

    @property
    def sysclk_hz(self) -> int:
        return (HSI_HZ, HSE_HZ, self.pll_hz)[self.sysclk_source]

    @property
    def hclk_hz(self) -> int:
        return self.sysclk_hz // _ahb_divider(bits(self.cfgr, 4, 4))

    @property
    def pclk1_hz(self) -> int:
        return self.hclk_hz // _apb_divider(bits(self.cfgr, 8, 3))

    @property
    def pclk2_hz(self) -> int:
        return self.hclk_hz // _apb_divider(bits(self.cfgr, 11, 3))

    def timer_hz(self, apb: int) -> int:
        """RM0008 7.2 Figure 8: TIMxCLK = PCLKx, x2 when the APB prescaler is not 1."""
        return self._derived()[0 if apb == 1 else 1]

    @property
    def adc_hz(self) -> int:
        return self._derived()[2]

    def _derived(self) -> tuple[int, int, int]:
        """TIM on APB1, TIM on APB2 and ADCCLK, recomputed only when CFGR or the system
        clock's source has changed (the peripherals ask at every event)."""
        key = (self.cfgr, self.sysclk_source)
        if key != self._derived_key:
            timers = []
            for ppre, pclk in (
                (bits(self.cfgr, 8, 3), self.pclk1_hz),
                (bits(self.cfgr, 11, 3), self.pclk2_hz),
            ):
                timers.append(pclk * (2 if _apb_divider(ppre) > 1 else 1))
            adc = self.pclk2_hz // (2 * (bits(self.cfgr, 14, 2) + 1))
            self._derived_key, self._derived_hz = key, (timers[0], timers[1], adc)
        return self._derived_hz

    @staticmethod
    def latency_needed(sysclk_hz: int) -> int:
        """RM0008 3.3.3: 0 wait states up to 24 MHz, 1 up to 48 MHz, 2 up to 72 MHz."""
        return 0 if sysclk_hz <= 24_000_000 else 1 if sysclk_hz <= 48_000_000 else 2

    @staticmethod
    def ticks_of(hz: int, what: str) -> int:
        """Ticks of one period of a clock at `hz` (it must divide 72 MHz)."""
        if hz <= 0 or TICK_HZ % hz:
            raise PilError(f"{what} runs at {hz} Hz, which does not divide the 72 MHz time base")
        return TICK_HZ // hz

    def clock_enabled(self, peripheral: str) -> bool:
        if peripheral in APB2_CLOCKS:
            return bool(self.apb2enr >> APB2_CLOCKS[peripheral] & 1)
        if peripheral in APB1_CLOCKS:
            return bool(self.apb1enr >> APB1_CLOCKS[peripheral] & 1)
        return True

    # ----------------------------------------------------------------- registers
    def _read_cr(self) -> int:
        return self.cr

    def _read_csr(self) -> int:
        return self.csr

    def _write_cr(self, value: int) -> None:
        now = self.machine.now
        writable = 0xFD | CR_HSEON | CR_HSEBYP | CR_CSSON | CR_PLLON  # HSION, HSITRIM
        if not value & CR_HSION and self.sysclk_source == 0:
            value |= CR_HSION  # 7.3.1: HSION cannot be reset while the HSI is SYSCLK
        if value & CR_HSEBYP:
            raise PilError("RCC.CR.HSEBYP = 1: an external clock bypass is not modelled")
        old = self.cr
        self.cr = (old & ~writable) | (value & writable)
        if value & CR_HSEON and not old & CR_HSEON:
            self.hse_ready_at = None if self.hse_fails else now + self.hse_startup_ticks
        if not value & CR_HSEON and old & CR_HSEON:
            if self.sysclk_source == 1 or (self.sysclk_source == 2 and self.cfgr & (1 << 16)):
                raise PilError("RCC.CR.HSEON cleared while the HSE feeds SYSCLK (RM0008 7.3.1)")
            self.cr &= ~CR_HSERDY
            self.hse_ready_at = None
        if value & CR_PLLON and not old & CR_PLLON:
            if self.cfgr & (1 << 16) and not self.cr & CR_HSERDY:
                raise PilError("RCC.CR.PLLON set with PLLSRC = HSE before HSERDY")
            self.pll_ready_at = now + self.pll_lock_ticks
        if not value & CR_PLLON and old & CR_PLLON:
            if self.sysclk_source == 2:
                raise PilError("RCC.CR.PLLON cleared while the PLL is SYSCLK (RM0008 7.3.1)")
            self.cr &= ~CR_PLLRDY
            self.pll_ready_at = None

    def _write_cfgr(self, value: int) -> None:
        if (value ^ self.cfgr) & CFGR_PLL_CONFIG and self.cr & CR_PLLON:
            raise PilError(
                "RCC.CFGR PLLSRC/PLLXTPRE/PLLMUL changed with the PLL on (RM0008 7.3.2:"
                " written only when the PLL is disabled)"
            )
        if bits(value, 24, 3):
            raise PilError("RCC.CFGR.MCO: the clock output is not modelled")
        self.cfgr = (value & ~0xC) | (self.sysclk_source << 2)
        self._switch()
        self.machine.clocks_changed()

    def _switch(self) -> None:
        """7.2.6: SWS follows SW once the selected source is ready."""
        wanted = self.cfgr & 3
        if wanted == 3:
            raise PilError("RCC.CFGR.SW = 11 is not allowed (RM0008 7.3.2)")
        ready = {0: True, 1: bool(self.cr & CR_HSERDY), 2: bool(self.cr & CR_PLLRDY)}[wanted]
        if not ready or wanted == self.sysclk_source:
            return
        new_hz = (HSI_HZ, HSE_HZ, self.pll_hz)[wanted]
        if self.machine.flash.latency < self.latency_needed(new_hz):
            raise PilError(
                f"SYSCLK switched to {new_hz} Hz with FLASH.ACR.LATENCY ="
                f" {self.machine.flash.latency}: RM0008 3.3.3 needs"
                f" {self.latency_needed(new_hz)} wait states"
            )
        self.sysclk_source = wanted
        self.cfgr = (self.cfgr & ~0xC) | (wanted << 2)

    def _write_cir(self, value: int) -> None:
        if value & 0x1F00:
            raise PilError("RCC.CIR ready interrupts are not modelled")
        if value & CIR_CSSC:
            self.cir &= ~CIR_CSSF
            self.machine.nvic.set_nmi(False)

    def _write_apb2enr(self, value: int) -> None:
        self.apb2enr = value & 0xFFFF

    def _write_apb1enr(self, value: int) -> None:
        self.apb1enr = value & 0x3EFEC9FF

    def _write_csr(self, value: int) -> None:
        if value & CSR_RMVF:
            self.csr &= ~CSR_RESET_FLAGS
        if value & CSR_LSION:
            self.csr |= CSR_LSION | CSR_LSIRDY

    # ----------------------------------------------------------------- events
    def fail_hse(self, at: int) -> None:
        """The crystal stops at tick `at` (7.2.7)."""
        self.hse_failure_at = at

    def next_event(self) -> int | None:
        first = None  # asked at every step of the machine: no lists
        for t in (self.hse_ready_at, self.pll_ready_at, self.hse_failure_at):
            if t is not None and (first is None or t < first):
                first = t
        return first

    def on_event(self, now: int) -> None:
        if self.hse_ready_at is not None and self.hse_ready_at <= now:
            self.hse_ready_at = None
            self.cr |= CR_HSERDY
        if self.pll_ready_at is not None and self.pll_ready_at <= now:
            self.pll_ready_at = None
            self.cr |= CR_PLLRDY
            if (self.cfgr & 3) == 2:
                self._switch()
                self.machine.clocks_changed()
        if self.hse_failure_at is not None and self.hse_failure_at <= now:
            self.hse_failure_at = None
            self._hse_failed()

    def _hse_failed(self) -> None:
        hse_fed = self.sysclk_source == 1 or (self.sysclk_source == 2 and self.cfgr & (1 << 16))
        self.cr &= ~(CR_HSERDY | CR_HSEON)
        self.hse_ready_at = None
        if not self.cr & CR_CSSON:
            if hse_fed:
                raise PilError(
                    "the HSE failed while it fed SYSCLK and CSSON = 0: the chip would stop"
                )
            return
        self.cir |= CIR_CSSF
        if hse_fed:
            if self.sysclk_source == 2:
                self.cr &= ~(CR_PLLON | CR_PLLRDY)
                self.pll_ready_at = None
            self.sysclk_source = 0
            self.cfgr &= ~0xF  # SW and SWS: HSI
            self.machine.clocks_changed()
        self.machine.nvic.set_nmi(True)
        self.machine.tim1.clock_failure()

"""The time base, compare and capture channels shared by TIM1 and TIM3 (RM0008 14.3 and
15.3; the general-purpose timer's behaviour is a subset of the advanced one's).

Behaviours, with their RM0008 sections (TIM1 numbering, 14.x; TIM3's are 15.x):
* 14.3.1 time base: CNT counts at CK_CNT = TIMxCLK / (PSC + 1); PSC and (with
  CR1.ARPE) ARR are preloaded and take effect at the update event (UEV).
* 14.3.2 up-counting (CMS = 00, DIR = 0): 0..ARR, overflow and UEV when ARR -> 0.
* 14.3.4 centre-aligned (CMS = 01..11): 0 up to ARR, overflow (UEV) at ARR, down to 0,
  underflow (UEV) at 0; DIR reads the direction. Down-counting edge-aligned (DIR = 1) is
  not modelled.
* 14.3.3 repetition counter: RCR = 0 only (an UEV at every overflow/underflow).
* 14.4.1 CR1.URS: with URS = 1 only an overflow/underflow sets UIF, not UG or a slave
  reset; CR1.UDIS is not modelled.
* 14.4.6 EGR: UG re-initialises the counter and generates an UEV (preloads transferred);
  CCxG sets CCxIF; TG sets TIF (COMG and BG in `tim1`).
* 14.3.9 / 14.4.7 output compare: CCxIF is set when the counter matches CCRx (in
  centre-aligned mode on the way up for CMS = 10, down for CMS = 01, both for 11);
  CCRx is preloaded when CCMRx.OCxPE = 1 (loaded at the UEV), immediate otherwise.
* 14.3.10 / 14.4.7 OCxM, PWM mode 1 (110): OCxREF active while CNT < CCRx counting up,
  inactive while CNT > CCRx counting down (active from CNT = CCRx on the way down:
  centre-aligned, a pulse of 2 CCRx counts, centred on the underflow); PWM mode 2
  (111): the inverse; CCRx > ARR: always active (mode 1). Force inactive/active (100/101);
  frozen (000) holds OCxREF. Active/inactive-on-match and toggle are not modelled.
* 14.4.2 CR2.MMS: TRGO from the UEV (010) or OCxREF (100..111); its rising edges reach
  the listeners (`trgo_listeners`, the ADC's external trigger).
* 14.3.5 input capture: on the selected edge CCRx takes CNT and CCxIF is set (CCxOF if
  it was set already); reading CCRx clears CCxIF (14.4.5).
* 14.3.14 slave reset mode (SMS = 100): the trigger re-initialises the counter and
  generates an UEV (UIF only with URS = 0), after the capture of the same edge.
Flags are rc_w0 (writing 0 clears, 1 leaves), and each interrupt vector's request is the
OR of its flags and DIER enables (`VECTORS`).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING

from emulation.pil.bus import Peripheral, PilError, bits

if TYPE_CHECKING:
    from emulation.pil.machine import Machine

SR_UIF, SR_COMIF, SR_TIF, SR_BIF = 1 << 0, 1 << 5, 1 << 6, 1 << 7
CR1_CEN, CR1_UDIS, CR1_URS, CR1_OPM, CR1_DIR, CR1_ARPE = 1, 2, 4, 8, 16, 128
OC_FROZEN, OC_FORCE_INACTIVE, OC_FORCE_ACTIVE, OC_PWM1, OC_PWM2 = 0, 4, 5, 6, 7


#: (channel, CCMRx index, CCxS shift) of channels 1..4
_CC_FIELDS = tuple(
    (channel, (channel - 1) // 2, 8 * ((channel - 1) % 2)) for channel in range(1, 5)
)


def cc_flag(channel: int) -> int:
    """CCxIF bit of channel 1..4."""
    return 1 << channel


class Timer(Peripheral):
    #: flag mask -> IRQ number, per interrupt vector (filled by the subclass)
    VECTORS: tuple[tuple[int, int], ...] = ()
    APB = 1

    def __init__(self, machine: Machine, svd_name: str) -> None:
        super().__init__(machine, svd_name)
        self.cr1 = 0
        #: CR1.CEN and CR1.CMS, kept beside CR1 (`_set_cr1`): asked at every event
        self.running = False
        self.centre_aligned = 0
        self.cr2 = 0
        self.smcr = 0
        self.dier = 0
        self.sr = 0
        self.ccmr = [0, 0]  # in force
        self.ccer = 0  # in force
        self.psc = 0  # in force; `psc_preload` is the register
        self.psc_preload = 0
        self.arr = 0xFFFF
        self.arr_preload = 0xFFFF
        self.ccr = [0, 0, 0, 0, 0]  # index 1..4, in force
        self.ccr_preload = [0, 0, 0, 0, 0]
        self.anchor_time = 0
        self.anchor_pos = 0
        self.stopped_cnt = 0
        self.processed_until = 0
        self.ref = [False] * 5  # OCxREF, index 1..4
        self.trgo = False
        self.trgo_listeners: list[Callable[[int], None]] = []
        #: called with the tick at which the counter starts a PWM period from 0: an
        #: overflow (edge-aligned), an underflow (centre-aligned), UG or a slave reset
        self.period_listeners: list[Callable[[int], None]] = []
        #: called with the tick of a centre-aligned counter's overflow (at ARR), the
        #: update event in the middle of its PWM period (RCR = 0, 14.3.4): preloaded
        #: CCRx written in the first half take effect there
        self.half_period_listeners: list[Callable[[int], None]] = []
        self.update_count = 0
        self._tpc: int | None = None  # ticks per count, cached until PSC or a clock changes
        self._next: int | None = None  # counter_event(), cached until the state changes
        self._next_valid = False
        self.readers = {
            "CR1": self._read_cr1,
            "CR2": lambda: self.cr2,
            "SMCR": lambda: self.smcr,
            "DIER": lambda: self.dier,
            "SR": lambda: self.sr,
            "CCMR1": lambda: self.ccmr_register(0),
            "CCMR2": lambda: self.ccmr_register(1),
            "CCER": lambda: self.ccer_register(),
            "CNT": lambda: self.cnt(self.machine.now),
            "PSC": lambda: self.psc_preload,
            "ARR": lambda: self.arr_preload,
            "CCR1": lambda: self.read_ccr(1),
            "CCR2": lambda: self.read_ccr(2),
            "CCR3": lambda: self.read_ccr(3),
            "CCR4": lambda: self.read_ccr(4),
        }
        self.writers = {
            "CR1": self._write_cr1,
            "CR2": self._write_cr2,
            "SMCR": self._write_smcr,
            "DIER": self._write_dier,
            "SR": self._write_sr,
            "EGR": self.write_egr,
            "CCMR1": lambda v: self.write_ccmr(0, v),
            "CCMR2": lambda v: self.write_ccmr(1, v),
            "CCER": self.write_ccer,
            "CNT": self._write_cnt,
            "PSC": self._write_psc,
            "ARR": self._write_arr,
            "CCR1": lambda v: self._write_ccr(1, v),
            "CCR2": lambda v: self._write_ccr(2, v),
            "CCR3": lambda v: self._write_ccr(3, v),
            "CCR4": lambda v: self._write_ccr(4, v),
        }

    # ------------------------------------------------------------- register views
    def ccmr_register(self, index: int) -> int:
        return self.ccmr[index]

    def ccer_register(self) -> int:
        return self.ccer

    def read_ccr(self, channel: int) -> int:
        if self.is_input(channel):
            self.sr &= ~cc_flag(channel)  # 14.4.5: reading CCRx clears CCxIF
            self.update_lines()
            return self.ccr[channel]
        return self.ccr_preload[channel]

    # ------------------------------------------------------------- configuration
    def _set_cr1(self, value: int) -> None:
        """CR1 and what is read from it at every event: `running` (CEN) and
        `centre_aligned` (CMS, 0 for edge-aligned)."""
        self.cr1 = value
        self.running = bool(value & CR1_CEN)
        self.centre_aligned = (value >> 5) & 3

    def cc_select(self, channel: int) -> int:
        return (self.ccmr[(channel - 1) // 2] >> (8 * ((channel - 1) % 2))) & 3

    def is_input(self, channel: int) -> bool:
        return self.cc_select(channel) != 0

    def oc_mode(self, channel: int) -> int:
        return (self.ccmr[(channel - 1) // 2] >> (8 * ((channel - 1) % 2) + 4)) & 7

    def oc_preload(self, channel: int) -> bool:
        return bool(bits(self.ccmr[(channel - 1) // 2], 8 * ((channel - 1) % 2) + 3))

    def ticks_per_count(self) -> int:
        if self._tpc is None:
            rcc = self.machine.rcc
            self._tpc = rcc.ticks_of(rcc.timer_hz(self.APB), f"{self.svd_name}CLK") * (self.psc + 1)
        return self._tpc

    def write(self, offset: int, size: int, value: int) -> None:
        self._next_valid = False
        super().write(offset, size, value)

    def cycle_counts(self) -> int:
        """Counts from one UEV of the same kind to the next: a PWM period."""
        return 2 * self.arr if self.centre_aligned else self.arr + 1

    # ------------------------------------------------------------- the counter
    def position(self, now: int) -> int:
        if not self.running:
            return self.anchor_pos
        return self.anchor_pos + (now - self.anchor_time) // (self._tpc or self.ticks_per_count())

    def cnt_of_position(self, pos: int) -> int:
        if self.centre_aligned:
            pos %= 2 * self.arr if self.arr else 1
            return pos if pos <= self.arr else 2 * self.arr - pos
        return pos % (self.arr + 1)

    def cnt(self, now: int) -> int:
        return self.cnt_of_position(self.position(now))

    def counting_down(self, now: int) -> bool:
        pos = self.position(now)
        return bool(self.centre_aligned) and pos >= self.arr

    def _read_cr1(self) -> int:
        down = self.counting_down(self.machine.now) if self.running else bool(self.cr1 & CR1_DIR)
        return (self.cr1 & ~CR1_DIR) | (CR1_DIR if down else 0)

    def reanchor(self, pos: int | None = None) -> None:
        self._next_valid = False
        now = self.machine.now
        self.anchor_pos = self.position(now) if pos is None else pos
        self.anchor_time = now
        self.processed_until = now

    def time_of_position(self, pos: int) -> int:
        return self.anchor_time + (pos - self.anchor_pos) * self.ticks_per_count()

    # ------------------------------------------------------------- writes
    def _write_cr1(self, value: int) -> None:
        if value & CR1_UDIS:
            raise PilError(f"{self.svd_name}.CR1.UDIS = 1 is not modelled")
        if value & CR1_OPM:
            raise PilError(f"{self.svd_name}.CR1.OPM = 1 is not modelled")
        if bits(value, 8, 2):
            raise PilError(f"{self.svd_name}.CR1.CKD = {bits(value, 8, 2)} is not modelled")
        if value & CR1_DIR and not bits(value, 5, 2):
            raise PilError(f"{self.svd_name}.CR1.DIR = 1: down-counting is not modelled")
        if self.running and bits(value ^ self.cr1, 5, 2):
            raise PilError(
                f"{self.svd_name}.CR1.CMS changed while the counter runs (RM0008 14.4.1 forbids"
                " switching from edge- to centre-aligned with CEN = 1)"
            )
        was_running = self.running
        if was_running:
            self.reanchor()
        self._set_cr1(value & 0x3FF)
        if self.running and not was_running:
            self.anchor_time = self.machine.now
            self.processed_until = self.machine.now
        self.refresh_refs()

    def _write_cr2(self, value: int) -> None:
        self.cr2 = value & 0xFFFF
        self.refresh_refs()

    def _write_smcr(self, value: int) -> None:
        self.smcr = value & 0xFFFF
        self.check_slave_mode()

    def check_slave_mode(self) -> None:
        sms = self.smcr & 7
        if sms not in (0, 4):
            raise PilError(f"{self.svd_name}.SMCR.SMS = {sms} is not modelled (0 or 4: reset mode)")

    def _write_dier(self, value: int) -> None:
        self.dier = value & 0x7FFF
        self.update_lines()

    def _write_sr(self, value: int) -> None:
        self.sr &= value | ~0x1FFF
        self.keep_flags()
        self.update_lines()

    def keep_flags(self) -> None:
        """Flags hardware holds while their cause lasts (TIM1's BIF)."""

    def write_egr(self, value: int) -> None:
        for channel in range(1, 5):
            if value >> channel & 1:
                self.set_cc_flag(channel)
        if value & (1 << 6):
            self.sr |= SR_TIF
        if value & 1:
            self.reinitialise(from_software=True)
        self.update_lines()

    def write_ccmr(self, index: int, value: int) -> None:
        self.ccmr[index] = value & 0xFFFF
        self.refresh_refs()

    def write_ccer(self, value: int) -> None:
        self.ccer = value & 0xFFFF
        self.refresh_refs()

    def _write_cnt(self, value: int) -> None:
        count = value & 0xFFFF
        if self.centre_aligned and self.counting_down(self.machine.now):
            pos = 2 * self.arr - count
        else:
            pos = count
        self.reanchor(pos)
        self.refresh_refs()

    def _write_psc(self, value: int) -> None:
        self.psc_preload = value & 0xFFFF  # 14.4.11: taken at the next UEV

    def _write_arr(self, value: int) -> None:
        self.arr_preload = value & 0xFFFF
        if not self.cr1 & CR1_ARPE:
            self.reanchor()
            self.arr = self.arr_preload
            self.refresh_refs()

    def _write_ccr(self, channel: int, value: int) -> None:
        if self.is_input(channel):
            raise PilError(
                f"{self.svd_name}.CCR{channel} written while channel {channel} is an input"
            )
        self.ccr_preload[channel] = value & 0xFFFF
        if not self.oc_preload(channel):
            self.ccr[channel] = self.ccr_preload[channel]
            self.refresh_refs()

    # ------------------------------------------------------------- events
    def set_cc_flag(self, channel: int) -> None:
        flag = cc_flag(channel)
        if self.sr & flag and self.is_input(channel):
            self.sr |= 1 << (channel + 8)  # CCxOF
        self.sr |= flag

    def update_event(self, *, from_counter: bool) -> None:
        """UEV: transfer the preloads (14.3.1); UIF unless URS filters it."""
        self._next_valid = False
        if self.psc != self.psc_preload:
            self.psc = self.psc_preload
            self._tpc = None
        self.arr = self.arr_preload
        for channel in range(1, 5):
            if not self.is_input(channel):
                self.ccr[channel] = self.ccr_preload[channel]
        if from_counter or not self.cr1 & CR1_URS:
            self.sr |= SR_UIF
        self.update_count += 1
        self.on_update()

    def on_update(self) -> None:
        """Subclass hook: what else an UEV does (TIM1's AOE)."""

    def reinitialise(self, *, from_software: bool) -> None:
        """UG or a slave reset: counter to 0 (14.3.1) and an UEV."""
        self.update_event(from_counter=False)
        self.reanchor(0)
        self._period_started()
        self.trgo_update_pulse()
        self.refresh_refs()

    def _period_started(self) -> None:
        for listener in self.period_listeners:
            listener(self.machine.now)

    def _channel_events(self, start: int, end: int) -> list[tuple[int, int]]:
        """(position, channel) compare matches with start < position <= end."""
        found = []
        arr, centre, ccmr = self.arr, self.centre_aligned, self.ccmr
        for channel, index, shift in _CC_FIELDS:
            if (ccmr[index] >> shift) & 3:  # `is_input`, inline: asked at every event
                continue
            value = self.ccr[channel]
            if value > arr:
                continue
            if centre:
                cycle = 2 * arr
                base = (start // cycle) * cycle
                for offset in (value, 2 * arr - value):
                    for pos in (base + offset, base + cycle + offset):
                        if start < pos <= end and self._centre_flags(pos, cycle):
                            found.append((pos, channel))
            else:
                cycle = arr + 1
                base = (start // cycle) * cycle
                for pos in (base + value, base + cycle + value):
                    if start < pos <= end:
                        found.append((pos, channel))
        return sorted(set(found))

    def pwm_active(self, pos: int, value: int) -> bool:
        """PWM mode 1's OCxREF at counter position `pos` for CCRx = `value` (14.4.7
        OC1M): counting up active while CNT < CCRx, counting down inactive while
        CNT > CCRx, so active from CNT = CCRx on (the counter goes 0..ARR-1 up, ARR..1
        down: a pulse of 2 CCRx counts, CCRx / ARR of the period; CCRx = 0 never)."""
        arr = self.arr
        if not self.centre_aligned:
            return pos % (arr + 1) < value
        # `cnt_of_position` inline (asked for every output at every gate change)
        phase = pos % (2 * arr if arr else 1)
        if phase >= arr:
            return (phase if phase <= arr else 2 * arr - phase) <= value
        return phase < value

    def down_count_edges(self, start: int, end: int) -> list[int]:
        """Positions in (start, end] where a PWM-mode OCxREF of a centre-aligned counter
        changes level counting down: at the compare match, CNT going from CCRx + 1 to
        CCRx (14.4.7: inactive while CNT > CCRx), whichever matches set CCxIF (CMS)."""
        if not self.centre_aligned:
            return []
        cycle = 2 * self.arr
        found = []
        for channel in range(1, 5):
            if self.is_input(channel) or self.oc_mode(channel) not in (OC_PWM1, OC_PWM2):
                continue
            value = self.ccr[channel]
            if not 0 < value <= self.arr:
                continue
            base = (start // cycle) * cycle
            for pos in (base + 2 * self.arr - value, base + cycle + 2 * self.arr - value):
                if start < pos <= end:
                    found.append(pos)
        return sorted(set(found))

    def _centre_flags(self, pos: int, cycle: int) -> bool:
        up = pos % cycle < self.arr
        return {1: not up, 2: up, 3: True}[self.centre_aligned]

    def _next_update_position(self, after: int) -> int:
        step = self.arr if self.centre_aligned else self.arr + 1
        return (after // step + 1) * step

    def next_event(self) -> int | None:
        return self._next if self._next_valid else self.counter_event()

    def counter_event(self) -> int | None:
        """The next compare match or UEV of the counter."""
        if not self._next_valid:
            self._next = self._counter_event()
            self._next_valid = True
        return self._next

    def _counter_event(self) -> int | None:
        if not self.running:
            return None
        done = self.position(self.processed_until)
        update = self._next_update_position(done)
        matches = self._channel_events(done, update)
        target = min(
            [update, *(pos for pos, _ in matches[:1]), *self.down_count_edges(done, update)[:1]]
        )
        return self.time_of_position(target)

    def on_event(self, now: int) -> None:
        """Each due match and UEV at its own tick, so OCxREF edges (TRGO) carry their time."""
        saved = self.machine.now
        try:
            while (at := self.counter_event()) is not None and at <= now:
                self.machine.now = at
                self._next_valid = False
                done = self.position(self.processed_until)
                update = self._next_update_position(done)
                target = self.position(at)
                for pos, channel in self._channel_events(done, target):
                    if pos == target:
                        self.set_cc_flag(channel)
                self.processed_until = at
                if target >= update:
                    at_top = bool(self.centre_aligned) and (update // self.arr) % 2 == 1
                    self.update_event(from_counter=True)
                    self.reanchor(self.arr if at_top else 0)
                    if not at_top:
                        self._period_started()
                    else:
                        for listener in self.half_period_listeners:
                            listener(at)
                    self.trgo_update_pulse()
                self.refresh_refs()
                self.update_lines()
        finally:
            self.machine.now = saved

    # ------------------------------------------------------------- OCxREF and TRGO
    def ref_level(self, channel: int, now: int) -> bool:
        mode = self.oc_mode(channel)
        if mode == OC_FROZEN:
            return self.ref[channel]
        if mode == OC_FORCE_INACTIVE:
            return False
        if mode == OC_FORCE_ACTIVE:
            return True
        if mode in (OC_PWM1, OC_PWM2):
            active = self.pwm_active(self.position(now), self.ccr[channel])
            return active if mode == OC_PWM1 else not active
        raise PilError(
            f"{self.svd_name} channel {channel}: OC{channel}M = {mode:03b} is not modelled"
        )

    def refresh_refs(self) -> None:
        now = self.machine.now
        for channel in range(1, 5):
            if self.is_input(channel):
                continue
            self.ref[channel] = self.ref_level(channel, now)
        mms = bits(self.cr2, 4, 3)
        if mms >= 4:
            level = self.ref[mms - 3]
            if level and not self.trgo:
                for listener in self.trgo_listeners:
                    listener(now)
            self.trgo = level

    def trgo_update_pulse(self) -> None:
        if bits(self.cr2, 4, 3) == 2:
            for listener in self.trgo_listeners:
                listener(self.machine.now)

    def update_lines(self) -> None:
        nvic = self.machine.nvic
        for mask, irq in self.VECTORS:
            nvic.set_line(irq, bool(self.sr & self.dier & mask))

    def clock_changed(self, now: int) -> None:
        if self.running:
            self.reanchor()
        self._tpc = None
        self._next_valid = False

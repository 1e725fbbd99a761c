"""TIM1, the advanced-control timer (RM0008 section 14), on top of `timer.Timer`.

Behaviours beyond the shared time base, with their RM0008 sections:
* 14.4.2 CR2.CCPC = 1: CCxE, CCxNE (CCER) and OCxM (CCMRx) of the channels with a
  complementary output (1..3) are preloaded; a COM event (EGR.COMG, 14.4.6) transfers
  them and sets COMIF (14.3.16). CR2.CCUS (COM on TRGI) is not modelled. CCER reads back
  what was written.
* 14.4.18 BDTR: DTG (dead time), OSSI, OSSR, BKE, BKP, AOE, MOE; LOCK must stay 0.
* 14.3.11 dead time: with CCxE = CCxNE = 1 each output's rising edge is delayed by
  DT = DTG decoded (14.4.18: 0xx: DTG x t_DTS; 10x: (64 + DTG[5:0]) x 2 t_DTS; 110:
  (32 + DTG[4:0]) x 8 t_DTS; 111: (32 + DTG[4:0]) x 16 t_DTS) with t_DTS = 1 / CK_INT
  (CR1.CKD = 00); a pulse shorter than DT never shows.
* 14.4.9 Table 83, the output states, for channels 1..3 (`outputs`):
  MOE = 1: CCxE/CCxNE 00: not driven; 10: OCx = OCxREF xor CCxP, OCxN = CCxNP (OSSR = 1)
  or not driven (OSSR = 0); 01: the mirror image, OCxN = OCxREF xor CCxNP (not the
  complement of OCxREF) and OCx = CCxP or not driven; 11: complementary with dead time.
  MOE = 0: OSSI = 0 or both enables 0: not driven; OSSI = 1: OCx = CCxP and OCxN =
  CCxNP at once, then OCx = OISx and OCxN = OISxN (CR2) after a dead time.
* 14.3.12 break: the break input (BKIN, PB12, RM0008 9.3.7 with no remap) active at level
  BKP with BKE = 1, the CSS clock failure event (7.2.7), or EGR.BG: MOE is cleared at
  once, BIF is set (interrupt with BIE). The input acts on its level: while it is
  active MOE cannot be set and BIF cannot be cleared. With AOE = 1 MOE is set again at
  the next UEV once the break is gone.
* Interrupt vectors: TIM1_BRK (BIF), TIM1_UP (UIF), TIM1_TRG_COM (COMIF, TIF), TIM1_CC
  (CC1IF..CC4IF), numbers from the SVD.
The outputs are a function of time computed from the register state in force: the last
OCxREF edge is found from the counter, assuming the compare values and mode in force now
also held through the previous PWM period.
"""

from __future__ import annotations

import bisect
from typing import TYPE_CHECKING

from emulation.pil.bus import PilError, bits, svd_interrupt
from emulation.pil.timer import SR_BIF, SR_COMIF, SR_TIF, SR_UIF, Timer

if TYPE_CHECKING:
    from emulation.pil.machine import Machine

BDTR_OSSI, BDTR_OSSR, BDTR_BKE, BDTR_BKP, BDTR_AOE, BDTR_MOE = (
    1 << 10,
    1 << 11,
    1 << 12,
    1 << 13,
    1 << 14,
    1 << 15,
)
CR2_CCPC, CR2_CCUS = 1, 4
EGR_COMG, EGR_BG = 1 << 5, 1 << 7
#: pins of CH1, CH2, CH3 (GPIOA) and CH1N, CH2N, CH3N (GPIOB), and BKIN (GPIOB), no remap
CHANNEL_PINS = (8, 9, 10)
COMPLEMENTARY_PINS = (13, 14, 15)
BREAK_PIN = 12
#: CCMRx bits of OCxM for channels 1..3 (the preloaded part with CCPC)
_OCM_MASK = (0x0070 | 0x7000, 0x0070)
#: CCER bits preloaded with CCPC: CCxE, CCxNE of channels 1..3
_CCER_PRELOADED = 0b0101_0101_0101
#: entries the per-compare-value caches keep (a braking run moves CCRx every period)
_CACHE_LIMIT = 4096


def dead_time_counts(dtg: int) -> int:
    """RM0008 14.4.18 DTG[7:0] -> dead time in t_DTS."""
    if dtg >> 7 == 0:
        return dtg
    if dtg >> 6 == 0b10:
        return (64 + (dtg & 0x3F)) * 2
    if dtg >> 5 == 0b110:
        return (32 + (dtg & 0x1F)) * 8
    return (32 + (dtg & 0x1F)) * 16


class AdvancedTimer(Timer):
    APB = 2

    def __init__(self, machine: Machine) -> None:
        super().__init__(machine, "TIM1")
        self.VECTORS = (
            (SR_BIF, svd_interrupt("TIM1", "TIM1_BRK_TIM9")),
            (SR_UIF, svd_interrupt("TIM1", "TIM1_UP_TIM10")),
            (SR_COMIF | SR_TIF, svd_interrupt("TIM1", "TIM1_TRG_COM_TIM11")),
            (0b11110, svd_interrupt("TIM1", "TIM1_CC")),
        )
        self.bdtr = 0
        self.rcr = 0
        self.ccer_written = 0
        self.ccmr_written = [0, 0]
        self.moe_cleared_at: int | None = None
        self.moe_set_at: int | None = None  # the latest write that set MOE
        self.breaks = 0
        self.com_events = 0
        #: (tick, gates) at every change of the six outputs, once `record_gates()` ran
        self.gate_log: list[tuple[int, tuple[bool | None, ...]]] | None = None
        self._flushed = 0
        #: the dead time in ticks, cached until BDTR is written or a clock changes
        self._dead: int | None = None
        #: per (OCxM, CCRx, ARR, CMS): the positions within a PWM period where OCxREF
        #: turns inactive and active (`_ref_turns`)
        self._turns: dict[tuple[int, int, int, int], tuple[tuple[int, ...], tuple[int, ...]]] = {}
        #: per (CMS, ARR, CCR1..3): the positions within a PWM period where an output may
        #: change (`_candidates`)
        self._changes: dict[tuple[int, int, int, int, int], tuple[int, ...]] = {}
        self.readers |= {"BDTR": lambda: self.bdtr, "RCR": lambda: self.rcr}
        self.writers |= {"BDTR": self._write_bdtr, "RCR": self._write_rcr}
        for index, pin in enumerate(CHANNEL_PINS):
            machine.gpioa.alternate[pin] = lambda c=index + 1: self.output(c, False)
        for index, pin in enumerate(COMPLEMENTARY_PINS):
            machine.gpiob.alternate[pin] = lambda c=index + 1: self.output(c, True)
        machine.gpiob.watch(BREAK_PIN, lambda _level, _at: self._check_break_input())

    # ------------------------------------------------------------- preloaded control bits
    def ccmr_register(self, index: int) -> int:
        return self.ccmr_written[index]

    def ccer_register(self) -> int:
        return self.ccer_written

    def _preloading(self) -> bool:
        return bool(self.cr2 & CR2_CCPC)

    def write_ccmr(self, index: int, value: int) -> None:
        self.ccmr_written[index] = value & 0xFFFF
        if self._preloading():
            kept = self.ccmr[index] & _OCM_MASK[index]
            value = (value & ~_OCM_MASK[index]) | kept
        super().write_ccmr(index, value)

    def write_ccer(self, value: int) -> None:
        self.ccer_written = value & 0xFFFF
        if self._preloading():
            value = (value & ~_CCER_PRELOADED) | (self.ccer & _CCER_PRELOADED)
        super().write_ccer(value)

    def commutate(self) -> None:
        """COM event (14.3.16): the preloaded enables and modes take effect, COMIF."""
        for index in range(2):
            self.ccmr[index] = (self.ccmr[index] & ~_OCM_MASK[index]) | (
                self.ccmr_written[index] & _OCM_MASK[index]
            )
        self.ccer = (self.ccer & ~_CCER_PRELOADED) | (self.ccer_written & _CCER_PRELOADED)
        self.sr |= SR_COMIF
        self.com_events += 1
        self.refresh_refs()

    def _write_cr2(self, value: int) -> None:
        if value & CR2_CCUS:
            raise PilError("TIM1.CR2.CCUS = 1 (COM on TRGI) is not modelled")
        super()._write_cr2(value)

    def _write_rcr(self, value: int) -> None:
        if value & 0xFF:
            raise PilError("TIM1.RCR != 0: the repetition counter is not modelled")
        self.rcr = 0

    def write_egr(self, value: int) -> None:
        if value & EGR_COMG:
            self.commutate()
        if value & EGR_BG:
            self._break(software=True)
        super().write_egr(value & ~(EGR_COMG | EGR_BG))

    # ------------------------------------------------------------- BDTR and the break
    def _write_bdtr(self, value: int) -> None:
        if bits(value, 8, 2):
            raise PilError("TIM1.BDTR.LOCK != 0 is not modelled")
        was_on = self.moe
        self.bdtr = value & 0xFFFF
        self._dead = None
        if self.moe and self.break_input_active():
            self.bdtr &= ~BDTR_MOE  # 14.3.12: MOE cannot be set while the break is active
        if was_on and not self.moe:
            self.moe_cleared_at = self.machine.now
        if self.moe and not was_on:
            self.moe_set_at = self.machine.now
        self._check_break_input()

    @property
    def moe(self) -> bool:
        return bool(self.bdtr & BDTR_MOE)

    def break_input_active(self) -> bool:
        if not self.bdtr & BDTR_BKE:
            return False
        level = self.machine.gpiob.input_level(BREAK_PIN)
        return level == bool(self.bdtr & BDTR_BKP)

    def _check_break_input(self) -> None:
        if self.break_input_active():
            self._break(software=False)

    def _break(self, *, software: bool) -> None:
        self._flush(self.machine.now)
        if self.moe:
            self.moe_cleared_at = self.machine.now
        self.bdtr &= ~BDTR_MOE
        if not self.sr & SR_BIF:
            self.breaks += 1
        self.sr |= SR_BIF
        self.update_lines()
        self._mark(self.machine.now)

    def clock_failure(self) -> None:
        """7.2.7: the CSS sends the clock failure event to the break input."""
        if self.bdtr & BDTR_BKE:
            self._break(software=False)

    def keep_flags(self) -> None:
        if self.break_input_active():
            self.sr |= SR_BIF  # 14.3.12: BIF cannot be cleared while the input is active

    def on_update(self) -> None:
        if self.bdtr & BDTR_AOE and not self.moe and not self.break_input_active():
            self.bdtr |= BDTR_MOE

    # ------------------------------------------------------------- outputs
    def dead_time_ticks(self) -> int:
        if self._dead is None:
            rcc = self.machine.rcc
            t_dts = rcc.ticks_of(rcc.timer_hz(self.APB), "TIM1CLK")
            self._dead = dead_time_counts(self.bdtr & 0xFF) * t_dts
        return self._dead

    def clock_changed(self, now: int) -> None:
        self._dead = None
        super().clock_changed(now)

    def _ref_edges(self, channel: int, now: int) -> tuple[bool, int]:
        """OCxREF at `now` and the tick it took that level (register state in force):
        the latest of its turns to that level at a compare match or an update in this
        PWM period or the one before, else two periods back."""
        mode = self.oc_mode(channel)
        if not self.running or mode not in (6, 7):
            return self.ref_level(channel, now), -(10**12)
        pos = self.position(now)
        active = self.pwm_active(pos, self.ccr[channel])  # `ref_level`, the position known
        level = active if mode == 6 else not active
        cycle = self.cycle_counts()
        base = (pos // cycle) * cycle
        latest = None
        for offset in self._ref_turns(channel, mode)[level]:
            for candidate in (base + offset, base - cycle + offset):
                if candidate <= pos and (latest is None or candidate > latest):
                    latest = candidate
        if latest is not None:
            return level, self.time_of_position(latest)
        return level, now - 2 * cycle * self.ticks_per_count()

    def _ref_turns(self, channel: int, mode: int) -> tuple[tuple[int, ...], tuple[int, ...]]:
        """(turns inactive, turns active): the positions of a compare match or an
        update, relative to a period's start, where OCxREF changes level. OCxREF at a
        position depends only on it modulo the period, so these hold for every period
        while OCxM, CCRx, ARR and CMS stay (kept per those)."""
        value, arr, centre = self.ccr[channel], self.arr, self.centre_aligned
        key = (mode, value, arr, centre)
        turns = self._turns.get(key)
        if turns is None:
            offsets = (value, 2 * arr - value, 0) if centre else (value, 0)
            found: tuple[list[int], list[int]] = ([], [])
            for offset in offsets:
                after = self._ref_at_position(channel, offset)
                if self._ref_at_position(channel, offset - 1) != after:
                    found[after].append(offset)
            if len(self._turns) >= _CACHE_LIMIT:
                self._turns.clear()
            turns = self._turns[key] = (tuple(found[0]), tuple(found[1]))
        return turns

    def _ref_at_position(self, channel: int, pos: int) -> bool:
        active = self.pwm_active(pos, self.ccr[channel])
        return active if self.oc_mode(channel) == 6 else not active

    def output(self, channel: int, complementary: bool, now: int | None = None) -> bool | None:
        """Level of OCx (or OCxN) at `now` (default: the machine's time); None where
        the timer does not drive the pin (Table 83 "output disabled")."""
        now = self.machine.now if now is None else now
        return self._channel(channel, now)[1 if complementary else 0]

    def _channel(self, channel: int, now: int) -> tuple[bool | None, bool | None]:
        """(OCx, OCxN) of `channel` at `now` (14.4.9 Table 83), from one look at its
        CCER bits and at most one at its OCxREF (`_ref_edges`)."""
        enables = self.ccer >> 4 * (channel - 1)
        enabled, polarity = bool(enables & 1), bool(enables & 2)
        enabled_n, polarity_n = bool(enables & 4), bool(enables & 8)
        if not enabled and not enabled_n:
            return None, None
        dead = self.dead_time_ticks()
        bdtr = self.bdtr
        if not bdtr & BDTR_MOE:
            if not bdtr & BDTR_OSSI:
                return None, None
            cleared = self.moe_cleared_at if self.moe_cleared_at is not None else -(10**12)
            if now - cleared < dead:
                return polarity, polarity_n
            idle = self.cr2 >> (8 + 2 * (channel - 1))
            return bool(idle & 1), bool(idle & 2)
        level, since = self._ref_edges(channel, now)
        if enabled and enabled_n:
            # complementary with dead time: each output's rising edge delayed by DT
            after_dead = now - since >= dead
            return (level and after_dead) != polarity, (not level and after_dead) != polarity_n
        # one output enabled: OCx = OCxREF xor CCxP or OCxN = OCxREF xor CCxNP (not the
        # complement of OCxREF), the other at its polarity (OSSR = 1) or not driven
        idle_level = bool(bdtr & BDTR_OSSR)
        if enabled:
            return level != polarity, polarity_n if idle_level else None
        return polarity if idle_level else None, level != polarity_n

    def gates(self, now: int | None = None) -> tuple[bool | None, ...]:
        """(CH1, CH1N, CH2, CH2N, CH3, CH3N) at `now`."""
        now = self.machine.now if now is None else now
        return self._channel(1, now) + self._channel(2, now) + self._channel(3, now)

    def gates_at(self, at: int) -> tuple[bool | None, ...]:
        """The outputs in force at tick `at`, now or earlier, from the gate record.
        `gates(at)` evaluates the registers as they are now at `at`: for a past tick it
        judged that instant by a state set after it (a scenario checking the safe state
        one period after an under-voltage saw the short the firmware set at 57 us, not
        the all-off in force at 50 us)."""
        now = self.machine.now
        if at >= now:
            return self.gates(at)
        log = self.gate_log
        if log is None or at < log[0][0]:
            raise ValueError(f"no gate record at tick {at}: record_gates() first")
        self._flush(now)
        index = bisect.bisect_right(log, at, key=lambda entry: entry[0]) - 1
        return log[index][1]

    # ------------------------------------------------------------- the gate record
    def record_gates(self) -> None:
        """Start recording every change of the six outputs (`gate_log`)."""
        now = self.machine.now
        self.gate_log = [(now, self.gates(now))]
        self._flushed = now

    def _candidates(self, start: int, end: int) -> list[int]:
        """Ticks in (start, end] where an output may change with the state in force:
        each OCxREF edge (a compare match, an update) and a dead time after it."""
        ticks: set[int] = set()
        if self.moe_cleared_at is not None:
            ticks.add(self.moe_cleared_at + self.dead_time_ticks())
        if self.running:
            dead = self.dead_time_ticks()
            cycle = self.cycle_counts()
            first = (self.position(start) // cycle - 1) * cycle
            last = self.position(end) + cycle
            offsets = self._change_offsets()
            # time_of_position, with the anchor and the count's length taken once
            anchor_time, anchor_pos, tpc = self.anchor_time, self.anchor_pos, self.ticks_per_count()
            for base in range(first, last + 1, cycle):
                base_tick = anchor_time + (base - anchor_pos) * tpc
                for offset in offsets:
                    tick = base_tick + offset * tpc
                    if tick + dead > start and tick <= end:
                        ticks.add(tick)
                        ticks.add(tick + dead)
        return sorted([t for t in ticks if start < t <= end])

    def _change_offsets(self) -> tuple[int, ...]:
        """The positions, relative to a period's start, of its update events and of
        channels 1..3's compare matches (counting down too, CNT = CCRx, centre-aligned),
        kept per CMS, ARR and CCR1..3."""
        centre, arr, ccr = self.centre_aligned, self.arr, self.ccr
        key = (centre, arr, ccr[1], ccr[2], ccr[3])
        offsets = self._changes.get(key)
        if offsets is None:
            found = {0, arr} if centre else {0}
            for channel in (1, 2, 3):
                found.add(ccr[channel])
                if centre:
                    found.add(2 * arr - ccr[channel])
            if len(self._changes) >= _CACHE_LIMIT:
                self._changes.clear()
            offsets = self._changes[key] = tuple(sorted(found))
        return offsets

    def _flush(self, until: int) -> None:
        """Log the changes up to `until` that the state in force makes by itself."""
        log = self.gate_log
        if log is None or until <= self._flushed:
            return
        for tick in self._candidates(self._flushed, until):
            gates = self.gates(tick)
            if gates != log[-1][1]:
                log.append((tick, gates))
        self._flushed = until

    def _mark(self, tick: int) -> None:
        """Log the outputs right after a state change at `tick`."""
        log = self.gate_log
        if log is None:
            return
        gates = self.gates(tick)
        if gates != log[-1][1]:
            log.append((tick, gates))
        self._flushed = max(self._flushed, tick)

    def write(self, offset: int, size: int, value: int) -> None:
        now = self.machine.now
        self._flush(now)
        super().write(offset, size, value)
        self._mark(now)

    def on_event(self, now: int) -> None:
        while (at := self.counter_event()) is not None and at <= now:
            self._flush(at)
            super().on_event(at)
            self._mark(at)
        self._flush(now)


def gate_violations(
    log: list[tuple[int, tuple[bool | None, ...]]], dead_time_ticks: int
) -> list[str]:
    """The bridge invariants on a gate record: both switches of a phase never on at
    once, and a switch turns on no sooner than `dead_time_ticks` after the other switch
    of its phase turned off. An undriven output (None) counts as off."""
    violations: list[str] = []
    if not log:
        return violations
    off_since: list[list[int | None]] = [[None, None] for _ in range(3)]
    previous = log[0][1]
    for tick, gates in log[1:]:
        for phase in range(3):
            upper, lower = gates[2 * phase] is True, gates[2 * phase + 1] is True
            if upper and lower:
                violations.append(f"tick {tick}: phase {'ABC'[phase]} has both switches on")
            # turn-offs first: a switch-over at one instant (one output off, the other
            # on, in either order of the two) is a turn-on 0 ticks after its partner
            for switch in (0, 1):
                was = previous[2 * phase + switch] is True
                now = gates[2 * phase + switch] is True
                if was and not now:
                    off_since[phase][switch] = tick
            for switch in (0, 1):
                was = previous[2 * phase + switch] is True
                now = gates[2 * phase + switch] is True
                if now and not was:
                    other = off_since[phase][1 - switch]
                    if other is not None and tick - other < dead_time_ticks:
                        violations.append(
                            f"tick {tick}: phase {'ABC'[phase]} {('upper', 'lower')[switch]}"
                            f" switch on {tick - other} ticks after its partner turned off"
                            f" (dead time {dead_time_ticks})"
                        )
        previous = gates
    return violations

"""ADC1 and ADC2 (RM0008 section 11), one class at either base (the SVD's ADC1 and ADC2).

The two are independent (ADC1's CR1.DUALMOD = 0; the dual modes are not modelled) but
share the analog pins (ADC12_INx: one set of inputs, `shares_pins_with`), the external
triggers (11.7: both take TIM1 TRGO as JEXTSEL = 000) and one interrupt, ADC1_2 (the
SVD's ADC): the NVIC line is high while either ADC requests it.

Behaviours, with their RM0008 sections:
* 11.3.1 CR2.ADON: writing 1 to a powered-down ADC powers it up (t_STAB, datasheet 1 us);
  writing ADON = 1 again with no other CR2 bit changed starts a regular conversion
  (11.12.3: a write that also changes another bit starts nothing).
* 11.4 calibration: CR2.CAL = 1 starts it, CAL reads 1 until it ends (t_CAL = 83 ADC
  cycles, datasheet); it must start at least 2 ADC cycles after power-up.
* 11.3.3 / 11.12.2 CR1.SCAN: every channel of a sequence is converted; without it only
  the first. 11.3.4 injected sequence, 11.12.12 JSQR: JL + 1 conversions taken from
  JSQ(4 - JL) .. JSQ4, each result in the JDRx of its JSQx slot (for JL = 3: JSQ1..JSQ4
  into JDR1..JDR4).
* 11.12.2 / 11.7 external trigger: CR2.JEXTTRIG with JEXTSEL = 000 starts the injected
  sequence on TIM1 TRGO's rising edge (Table 71); JEXTSEL = 111 with JSWSTART starts it
  by software. A trigger during an injected sequence is ignored.
* 11.6 timing: each conversion takes SMPx + 12.5 ADC cycles (SMPR1/SMPR2, 11.12.4/5),
  the input being sampled over the first SMPx cycles (taken at the end of that window);
  ADCCLK = PCLK2 / ADCPRE (RCC).
* 11.3.7 analog watchdog: with JAWDEN (injected) or AWDEN (regular), and AWDSGL for the
  single channel AWDCH, a raw conversion result above HTR or below LTR sets SR.AWD at
  the end of that conversion (interrupt with AWDIE).
* 11.5 / 11.12.13 data: JDRx = raw - JOFRx, a signed 16-bit right-aligned value
  (ALIGN = 1 is not modelled); DR the last regular result, read clears EOC.
* 11.3.5 continuous conversion (CR2.CONT = 1): the regular sequence starts again as
  soon as it ends, from the first rank, until CONT or ADON is cleared.
* 11.3.9 triggered injection: an injected trigger during a regular conversion resets
  that conversion (its result is lost), the injected sequence is converted, and the
  regular sequence resumes with the interrupted rank converted again from the start;
  a regular start during an injected sequence waits for its end. (The datasheet's
  injection latency of a few ADC cycles is not modelled: the injected sampling starts
  at the trigger.)
* 11.3.7 the analog watchdog on regular conversions (AWDEN) as on injected ones
  (JAWDEN): AWD is set at the end of each regular conversion of the guarded channel
  whose result is outside [LTR, HTR].
* 11.12.1 SR flags AWD, EOC, JEOC, JSTRT, STRT (rc_w0); JEOC at the end of the injected
  sequence, EOC at the end of the regular one; ADC1_2 interrupt on EOC/JEOC/AWD with
  their enables.
Regular conversions run continuously, every couple of microseconds, so they are worked
out when something could see them (a read of SR or DR, an injected trigger), not one
event each: the machine gets an event only for a regular conversion that changes the
interrupt line (AWD with AWDIE, EOC with EOCIE), found by looking ahead at the inputs.
Inputs that are functions of the tick must not depend on state the caller changes
meanwhile without calling `set_input` again.
Not modelled (an error if set): discontinuous and dual modes, JAUTO, DMA, RSTCAL, left
alignment, the temperature sensor; SWSTART while the regular group already converts.
A conversion under way when ADCCLK changes ends as first scheduled.
Inputs are voltages set per channel (`set_input`, a number or a function of the tick),
converted as an ideal 12-bit ADC: floor(V / VREF x 4096), clamped to 0..4095.
A function input may also say how far its voltage can go (`BoundedInput.volts_range`:
the motor's current sense, from the plant's largest possible current). A watched regular
conversion whose whole range is inside [LTR, HTR] cannot set AWD, so it is counted
without being converted; the last regular conversion's result is converted when DR is
read (or before the input changes). The outcome is the same as converting each one; the
plant is no longer advanced at each of ADC2's conversions, a few microseconds apart.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from dataclasses import dataclass
from fractions import Fraction
from typing import TYPE_CHECKING, Protocol

from emulation.pil.bus import NotYetKnownError, Peripheral, PilError, bits, svd_interrupt
from emulation.pil.rcc import TICK_HZ

if TYPE_CHECKING:
    from emulation.pil.machine import Machine

SR_AWD, SR_EOC, SR_JEOC, SR_JSTRT, SR_STRT = 1, 2, 4, 8, 16
CR2_ADON, CR2_CONT, CR2_CAL, CR2_RSTCAL, CR2_DMA, CR2_ALIGN = 1, 2, 4, 8, 1 << 8, 1 << 11
CR2_JEXTTRIG, CR2_EXTTRIG, CR2_JSWSTART, CR2_SWSTART, CR2_TSVREFE = (
    1 << 15,
    1 << 20,
    1 << 21,
    1 << 22,
    1 << 23,
)
CR1_EOCIE, CR1_AWDIE, CR1_JEOCIE, CR1_SCAN, CR1_AWDSGL = 1 << 5, 1 << 6, 1 << 7, 1 << 8, 1 << 9
CR1_JAUTO, CR1_DISCEN, CR1_JDISCEN, CR1_JAWDEN, CR1_AWDEN = (
    1 << 10,
    1 << 11,
    1 << 12,
    1 << 22,
    1 << 23,
)
#: SMPx code -> sampling time in half ADC cycles (1.5, 7.5, ... 239.5 cycles)
SAMPLE_HALF_CYCLES = (3, 15, 27, 57, 83, 111, 143, 479)
CONVERSION_HALF_CYCLES = 25  # 12.5 cycles
CALIBRATION_CYCLES = 83
STABILISATION_TICKS = TICK_HZ // 1_000_000  # t_STAB = 1 us
FULL_SCALE = 4095


@dataclass(frozen=True)
class Conversion:
    """One scheduled conversion: ends at `end`, its input taken at `sampled`."""

    end: int
    sampled: int
    channel: int
    injected: bool
    slot: int  # JDR index 1..4, or the rank in the regular sequence
    last: bool


@dataclass
class RegularRun:
    """The regular sequence under way: the conversion of `rank` (1-based) started at
    `start`; `paused` while an injected sequence runs (RM0008 11.3.9)."""

    channels: list[tuple[int, int]]  # (rank, channel)
    rank: int
    start: int
    paused: bool = False


#: Regular conversions looked at ahead of time for an AWD alarm before a checkpoint event
LOOKAHEAD = 64


class BoundedInput(Protocol):
    """A function input that also bounds itself: `volts_range(lo, hi)` is (lowest,
    highest) voltage the pin can have at any tick in [lo, hi], or None where it cannot
    say (the caller then converts the sample itself)."""

    def __call__(self, tick: int) -> float: ...

    def volts_range(self, lo: int, hi: int) -> tuple[float, float] | None: ...


class Adc(Peripheral):
    def __init__(
        self,
        machine: Machine,
        *,
        vref: float,
        name: str = "ADC1",
        shares_pins_with: Adc | None = None,
    ) -> None:
        super().__init__(machine, name)
        self.vref = vref
        self.irq = svd_interrupt(name, "ADC")
        #: the ADCs on the same pins and interrupt line (this one included)
        self.group: list[Adc] = shares_pins_with.group if shares_pins_with else []
        self.group.append(self)
        self.request = False
        self.sr = 0
        self.cr1 = 0
        self.cr2 = 0
        self.smpr = [0, 0]  # SMPR1 (channels 10..17), SMPR2 (0..9)
        self.jofr = [0, 0, 0, 0]
        self.htr = 0xFFF
        self.ltr = 0
        self.sqr = [0, 0, 0]
        self.jsqr = 0
        self.jdr = [0, 0, 0, 0]
        self.dr = 0
        self.powered_at: int | None = None
        self.calibration_end: int | None = None
        self.queue: list[Conversion] = []
        self.regular: RegularRun | None = None
        self.regular_requested = False  # a regular start during an injected sequence
        self.regular_conversions = 0
        self._alarm: int | None = None
        self._alarm_known = False
        self.inputs: dict[int, float | Callable[[int], float] | BoundedInput] = (
            shares_pins_with.inputs if shares_pins_with else {}
        )
        self.injected_sequences = 0
        #: the tick the latest injected sequence was triggered (JSTRT set): the one in
        #: flight while its conversions end
        self.injected_started: int | None = None
        self.ignored_triggers = 0
        self.sample_log: list[tuple[int, int, int]] = []  # (tick sampled, channel, raw)
        #: called at the end of every injected conversion: (tick sampled, channel, JDRx)
        self.injected_listeners: list[Callable[[int, int, int], None]] = []
        self.keep_sample_log = False
        #: the latest regular conversion not converted yet (channel, tick sampled): DR's
        self._dr_pending: tuple[int, int] | None = None
        self.readers = {
            "SR": self._read_sr,
            "CR1": lambda: self.cr1,
            "CR2": lambda: self.cr2,
            "SMPR1": lambda: self.smpr[0],
            "SMPR2": lambda: self.smpr[1],
            "HTR": lambda: self.htr,
            "LTR": lambda: self.ltr,
            "SQR1": lambda: self.sqr[0],
            "SQR2": lambda: self.sqr[1],
            "SQR3": lambda: self.sqr[2],
            "JSQR": lambda: self.jsqr,
            "DR": self._read_dr,
        }
        self.writers = {
            "SR": self._write_sr,
            "CR1": self._write_cr1,
            "CR2": self._write_cr2,
            "SMPR1": lambda v: self._set_smpr(0, v),
            "SMPR2": lambda v: self._set_smpr(1, v),
            "HTR": lambda v: self._set_threshold("htr", v),
            "LTR": lambda v: self._set_threshold("ltr", v),
            "SQR1": lambda v: self._set_sqr(0, v),
            "SQR2": lambda v: self._set_sqr(1, v),
            "SQR3": lambda v: self._set_sqr(2, v),
            "JSQR": self._write_jsqr,
        }
        for k in range(4):
            self.readers[f"JOFR{k + 1}"] = lambda k=k: self.jofr[k]
            self.writers[f"JOFR{k + 1}"] = lambda v, k=k: self._set_jofr(k, v)
            self.readers[f"JDR{k + 1}"] = lambda k=k: self.jdr[k]
        machine.tim1.trgo_listeners.append(self._tim1_trgo)

    # ------------------------------------------------------------- inputs
    def set_input(self, channel: int, volts: float | Callable[[int], float]) -> None:
        """The pin's voltage from now on, for every ADC on the pin."""
        for adc in self.group:
            adc._catch_up(self.machine.now)  # what was converted so far saw the old input
            adc._resolve_dr()
        self.inputs[channel] = volts
        for adc in self.group:
            adc._alarm_known = False

    def raw(self, channel: int, at: int) -> int:
        if channel not in self.inputs:
            raise PilError(
                f"{self.svd_name} converts channel {channel}, which the board model does not drive"
            )
        source = self.inputs[channel]
        volts = source(at) if callable(source) else source
        return self._code(volts)

    def _code(self, volts: float) -> int:
        return max(0, min(FULL_SCALE, int(volts / self.vref * 4096)))

    def _inside_window(self, channel: int, sampled: int) -> bool:
        """True where the input's bound keeps the conversion sampled at `sampled` within
        [LTR, HTR] whatever its value (the code is monotonic in the voltage)."""
        # (getattr, not isinstance: a Protocol's check costs microseconds a conversion)
        volts_range = getattr(self.inputs.get(channel), "volts_range", None)
        if volts_range is None:
            return False
        bound = volts_range(sampled, sampled)
        if bound is None:
            return False
        return self.ltr <= self._code(bound[0]) and self._code(bound[1]) <= self.htr

    def _resolve_dr(self) -> None:
        """DR from the latest regular conversion, where it was counted unconverted."""
        pending = self._dr_pending
        if pending is not None:
            self._dr_pending = None
            self.dr = self.raw(*pending)

    # ------------------------------------------------------------- registers
    def _set_smpr(self, index: int, value: int) -> None:
        self.smpr[index] = value & 0x3FFFFFFF

    def _set_sqr(self, index: int, value: int) -> None:
        self.sqr[index] = value & 0xFFFFFF

    def _set_jofr(self, index: int, value: int) -> None:
        self.jofr[index] = value & 0xFFF

    def _write_jsqr(self, value: int) -> None:
        if any(c.injected for c in self.queue):
            raise PilError(
                f"{self.svd_name}.JSQR written during an injected sequence (RM0008 11.12.12)"
            )
        self.jsqr = value & 0x3FFFFF

    def _set_threshold(self, name: str, value: int) -> None:
        self._catch_up(self.machine.now)
        setattr(self, name, value & 0xFFF)
        self._alarm_known = False

    def _read_sr(self) -> int:
        self._catch_up(self.machine.now)
        self._update_line()
        return self.sr

    def _write_sr(self, value: int) -> None:
        self._catch_up(self.machine.now)
        self.sr &= value | ~0x1F
        self._alarm_known = False
        self._update_line()

    def _read_dr(self) -> int:
        self._catch_up(self.machine.now)
        self._resolve_dr()
        self.sr &= ~SR_EOC
        self._update_line()
        return self.dr

    def _write_cr1(self, value: int) -> None:
        unsupported = value & (CR1_JAUTO | CR1_DISCEN | CR1_JDISCEN | (0xF << 16))
        if unsupported:
            raise PilError(
                f"{self.svd_name}.CR1 = 0x{value:08x}: JAUTO, discontinuous and dual modes are not modelled"
            )
        self._catch_up(self.machine.now)
        self.cr1 = value & 0xCFFFFF
        self._alarm_known = False
        self._update_line()

    def _write_cr2(self, value: int) -> None:
        unsupported = value & (CR2_RSTCAL | CR2_DMA | CR2_ALIGN | CR2_TSVREFE)
        if unsupported:
            raise PilError(
                f"{self.svd_name}.CR2 = 0x{value:08x}: RSTCAL, DMA, left alignment and"
                " the temperature sensor are not modelled"
            )
        now = self.machine.now
        self._catch_up(now)
        self._resolve_dr()
        self._alarm_known = False
        old = self.cr2
        self.cr2 = value & 0xFEF90F & ~(CR2_JSWSTART | CR2_SWSTART)  # RM0008 11.12.3
        if not value & CR2_ADON:
            self.powered_at = None
            self.queue = []
            self.regular = None
            self.regular_requested = False
            self.cr2 &= ~CR2_CAL
            return
        if not old & CR2_ADON:
            self.powered_at = now  # 11.3.1: power-up; t_STAB before converting
            return
        if value & CR2_CAL and not old & CR2_CAL:
            self._start_calibration()
        elif (value ^ old) & ~CR2_ADON & 0xFFFFFF == 0 and not value & (CR2_SWSTART | CR2_JSWSTART):
            self._start_regular()  # 11.12.3: ADON written again alone
        if value & CR2_SWSTART and value & CR2_EXTTRIG and bits(value, 17, 3) == 7:
            self._start_regular()
        if value & CR2_JSWSTART and value & CR2_JEXTTRIG and bits(value, 12, 3) == 7:
            self._start_injected()

    def _after(self, half_cycles: int) -> int:
        """The tick `half_cycles` ADC half-cycles from now, rounded up (ADCCLK need not
        divide the 72 MHz time base: 8 MHz HSI / 6 does not)."""
        hz = self.machine.rcc.adc_hz
        return self.machine.now + -(-half_cycles * TICK_HZ // (2 * hz))

    def _check_ready(self, what: str) -> None:
        if self.powered_at is None:
            raise PilError(f"{self.svd_name} {what} while powered down (CR2.ADON = 0)")
        if self.machine.now < self.powered_at + STABILISATION_TICKS:
            raise PilError(
                f"{self.svd_name} {what} before t_STAB (1 us) after power-up (RM0008 11.3.1)"
            )

    def _start_calibration(self) -> None:
        self._check_ready("calibration")
        self.calibration_end = self._after(2 * CALIBRATION_CYCLES)

    # ------------------------------------------------------------- conversions
    def _sample_half_cycles(self, channel: int) -> int:
        register, index = (0, channel - 10) if channel >= 10 else (1, channel)
        return SAMPLE_HALF_CYCLES[bits(self.smpr[register], 3 * index, 3)]

    def sample_ticks(self, channel: int) -> Fraction:
        """The channel's sampling time (SMPRx, 11.12.4/5) at the ADCCLK in force, in
        72 MHz ticks, exact."""
        return Fraction(self._sample_half_cycles(channel) * TICK_HZ, 2 * self.machine.rcc.adc_hz)

    def _schedule(self, channels: list[tuple[int, int]], injected: bool) -> None:
        elapsed = 0  # half ADC cycles
        conversions = []
        for index, (slot, channel) in enumerate(channels):
            sample = self._sample_half_cycles(channel)
            sampled = self._after(elapsed + sample)
            elapsed += sample + CONVERSION_HALF_CYCLES
            conversions.append(
                Conversion(
                    self._after(elapsed),
                    sampled,
                    channel,
                    injected,
                    slot,
                    index == len(channels) - 1,
                )
            )
        self.queue.extend(conversions)
        self.queue.sort(key=lambda c: c.end)

    def injected_channels(self) -> list[tuple[int, int]]:
        length = bits(self.jsqr, 20, 2) + 1
        slots = list(range(5 - length, 5))
        if not self.cr1 & CR1_SCAN:
            slots = slots[:1]
        return [(slot, bits(self.jsqr, 5 * (slot - 1), 5)) for slot in slots]

    def _start_injected(self) -> None:
        self._check_ready("injected conversion")
        if self.calibration_end is not None:
            raise PilError(f"{self.svd_name} injected conversion during calibration")
        if any(c.injected for c in self.queue):
            self.ignored_triggers += 1
            return
        self._catch_up(self.machine.now)
        if self.regular is not None:
            # 11.3.9: the regular conversion under way is reset; its rank is converted
            # again once the injected sequence has ended
            self.regular.paused = True
            self._alarm_known = False
        self.sr |= SR_JSTRT
        self.injected_sequences += 1
        self.injected_started = self.machine.now
        self._schedule(self.injected_channels(), injected=True)

    def regular_channels(self) -> list[tuple[int, int]]:
        length = bits(self.sqr[0], 20, 4) + 1
        if not self.cr1 & CR1_SCAN:
            length = 1
        channels = []
        for rank in range(1, length + 1):
            register = 2 - (rank - 1) // 6
            channels.append((rank, bits(self.sqr[register], 5 * ((rank - 1) % 6), 5)))
        return channels

    def _start_regular(self) -> None:
        self._check_ready("regular conversion")
        if self.regular is not None:
            raise PilError(
                f"{self.svd_name}: a regular start while the regular group converts is not modelled"
            )
        self.sr |= SR_STRT
        self._alarm_known = False
        if any(c.injected for c in self.queue):
            self.regular_requested = True  # 11.3.9: after the injected sequence
            return
        self.regular = RegularRun(self.regular_channels(), 1, self.machine.now)

    def _ticks(self, half_cycles: int) -> int:
        hz = self.machine.rcc.adc_hz
        return -(-half_cycles * TICK_HZ // (2 * hz))

    def _regular_steps(self, run: RegularRun) -> Iterator[tuple[int, int, int, int, bool]]:
        """The regular conversions from `run`'s state on, without changing it:
        (end, sampled, rank, channel, last of the sequence)."""
        channels, rank, start = run.channels, run.rank, run.start
        # (sampling, whole conversion) ticks per rank: SMPRx and ADCCLK cannot change
        # while the caller walks the steps
        timing = []
        for _, channel in channels:
            sample = self._sample_half_cycles(channel)
            timing.append((self._ticks(sample), self._ticks(sample + CONVERSION_HALF_CYCLES)))
        while True:
            channel = channels[rank - 1][1]
            sample_ticks, conversion_ticks = timing[rank - 1]
            end = start + conversion_ticks
            last = rank == len(channels)
            yield end, start + sample_ticks, rank, channel, last
            if last and not self.cr2 & CR2_CONT:
                return
            rank = 1 if last else rank + 1
            start = end

    def _constant_inputs(self, run: RegularRun) -> bool:
        return not self.keep_sample_log and not any(
            callable(self.inputs.get(channel)) for _, channel in run.channels
        )

    def _catch_up(self, until: int) -> None:
        """Complete the regular conversions that ended by `until` (11.3.5)."""
        run = self.regular
        if run is None or run.paused:
            return
        if self._constant_inputs(run) and self.cr2 & CR2_CONT and run.rank == 1:
            cycle = sum(
                self._ticks(self._sample_half_cycles(c) + CONVERSION_HALF_CYCLES)
                for _, c in run.channels
            )
            whole = (until - run.start) // cycle - 1
            if whole > 0:  # identical sequences: the last one stands for them all
                run.start += whole * cycle
                self.regular_conversions += whole * len(run.channels)
        for end, sampled, rank, channel, last in self._regular_steps(run):
            if end > until:
                run.rank, run.start = (
                    rank,
                    end - self._ticks(self._sample_half_cycles(channel) + CONVERSION_HALF_CYCLES),
                )
                return
            self._finish_regular(channel, sampled, last)
        self.regular = None  # single mode: the sequence has ended
        self._resolve_dr()
        self._alarm_known = False

    def _finish_regular(self, channel: int, sampled: int, last: bool) -> None:
        self.regular_conversions += 1
        if last:
            self.sr |= SR_EOC
        watched = self._watched(channel, injected=False)
        if not self.keep_sample_log and (
            not watched or self.sr & SR_AWD or self._inside_window(channel, sampled)
        ):
            self._dr_pending = (channel, sampled)  # it sets no AWD: converted if DR is read
            return
        self._dr_pending = None
        raw = self.raw(channel, sampled)
        if self.keep_sample_log:
            self.sample_log.append((sampled, channel, raw))
        self.dr = raw
        if watched and not self.ltr <= raw <= self.htr:
            self.sr |= SR_AWD

    def _regular_alarm(self) -> int | None:
        """The end of the next regular conversion that changes the interrupt line, or a
        checkpoint LOOKAHEAD conversions ahead; None if none ever will."""
        if self._alarm_known:
            return self._alarm
        self._alarm_known = True
        self._alarm = None
        run = self.regular
        if run is None or run.paused:
            return None
        eoc = bool(self.cr1 & CR1_EOCIE) and not self.sr & SR_EOC
        awd = (
            bool(self.cr1 & CR1_AWDIE)
            and not self.sr & SR_AWD
            and any(self._watched(c, injected=False) for _, c in run.channels)
        )
        if not eoc and not awd:
            return None
        constant = self._constant_inputs(run)
        for count, (end, sampled, _rank, channel, last) in enumerate(self._regular_steps(run)):
            self.machine.looking_ahead = True
            try:
                outside = (
                    awd
                    and self._watched(channel, injected=False)
                    and not self._inside_window(channel, sampled)
                    and not self.ltr <= self.raw(channel, sampled) <= self.htr
                )
            except NotYetKnownError:  # a causal input: look again when this one ends
                self._alarm = end
                return end
            finally:
                self.machine.looking_ahead = False
            if (eoc and last) or outside:
                self._alarm = end
                return end
            if count >= LOOKAHEAD or (constant and count >= len(run.channels)):
                self._alarm = None if constant else end
                return self._alarm
        return None

    def _tim1_trgo(self, at: int) -> None:
        if self.cr2 & CR2_JEXTTRIG and bits(self.cr2, 12, 3) == 0 and self.cr2 & CR2_ADON:
            saved = self.machine.now
            self.machine.now = at
            try:
                self._start_injected()
            finally:
                self.machine.now = saved

    def next_event(self) -> int | None:
        """The earliest of the injected conversion's end, the regular alarm and the
        calibration's end (asked at every step of the machine: no lists)."""
        first = self.queue[0].end if self.queue else None
        alarm = self._alarm if self._alarm_known else self._regular_alarm()
        if alarm is not None and (first is None or alarm < first):
            first = alarm
        calibration = self.calibration_end
        if calibration is not None and (first is None or calibration < first):
            first = calibration
        return first

    def on_event(self, now: int) -> None:
        if self.calibration_end is not None and self.calibration_end <= now:
            self.calibration_end = None
            self.cr2 &= ~CR2_CAL
        while self.queue and self.queue[0].end <= now:
            self._finish(self.queue.pop(0))
        self._catch_up(now)
        self._alarm_known = False
        self._update_line()

    def _watched(self, channel: int, injected: bool) -> bool:
        enabled = self.cr1 & (CR1_JAWDEN if injected else CR1_AWDEN)
        if not enabled:
            return False
        return not self.cr1 & CR1_AWDSGL or channel == bits(self.cr1, 0, 5)

    def _finish(self, conversion: Conversion) -> None:
        raw = self.raw(conversion.channel, conversion.sampled)
        if self.keep_sample_log:
            self.sample_log.append((conversion.sampled, conversion.channel, raw))
        if conversion.injected:
            self.jdr[conversion.slot - 1] = (raw - self.jofr[conversion.slot - 1]) & 0xFFFF
            for listener in self.injected_listeners:
                listener(conversion.sampled, conversion.channel, self.jdr[conversion.slot - 1])
            if conversion.last:
                self.sr |= SR_JEOC
                self._alarm_known = False
                if self.regular is not None:  # 11.3.9: the regular sequence resumes
                    self.regular.paused = False
                    self.regular.start = conversion.end
                elif self.regular_requested:
                    self.regular_requested = False
                    self.regular = RegularRun(self.regular_channels(), 1, conversion.end)
        if self._watched(conversion.channel, conversion.injected) and not (
            self.ltr <= raw <= self.htr
        ):
            self.sr |= SR_AWD

    def _update_line(self) -> None:
        request = (
            (self.sr & SR_EOC and self.cr1 & CR1_EOCIE)
            or (self.sr & SR_JEOC and self.cr1 & CR1_JEOCIE)
            or (self.sr & SR_AWD and self.cr1 & CR1_AWDIE)
        )
        self.request = bool(request)
        self.machine.nvic.set_line(self.irq, any(adc.request for adc in self.group))

    def clock_changed(self, now: int) -> None:
        """A conversion under way when ADCCLK changes (the CSS falling back to the HSI)
        keeps the end it was given: the emulated sequence is not stretched."""
        self._alarm_known = False

"""Every current sample the current loop closes on is taken in a clean window.

The shunt's signal rings after each switching edge of the bridge. A current sample
reads the braking current only if its sampling window (the SMPx ADC cycles before the
conversion's `sampled` tick, RM0008 11.6) holds no gate edge and starts at least
`sensing.settling_time` after the last one. The generator places the trigger so that
it does (codegen/spec_drive.py `sense_window`); this checks the instant the emulated
chip samples against the gate edges the emulated TIM1 puts out.

Yardsticks, none of them the port's: `sensing.settling_time` from the spec, the sample
time from the emulated ADC's SMPRx and ADCCLK at the conversion, the gate edges from
TIM1's outputs (`AdvancedTimer.gate_log`), and the injection latency from the
datasheet: the emulated ADC starts sampling at the trigger, the chip up to t_latj = 3
ADC cycles later, plus one PCLK2 cycle for an external trigger (DS5319 Table 46 and its
note), so the window may end up to that much later than emulated.

The samples checked are those the port uses: a current channel's JDRx read by the
current loop's handler (ADC1_2) in an entry that then writes a duty (TIM1 CCR1..CCR3)
while the bridge is armed. A sequence the port discards (the commutation's, marked by
`port.stale` / JSTRT or `port.pending`) writes no duty and is not checked; a port that
closed its loop on one would be.

Which gate edges: all six. With a DC-link shunt every switch's transition moves the
current the shunt carries (the modulated switch's, its complement's after the dead
time, and a commutation's); with low-side phase shunts a phase's own lower switch
switches its shunt, its upper switch commutates the phase current into or out of the
lower diode, and any other leg's dv/dt couples into the amplifier through the common
ground. So the physically conservative rule takes every edge of the six outputs. In the
steady state only the steady switch (and its complement) switches, so the rule costs
no margin there.
"""

from __future__ import annotations

import bisect
from collections.abc import Callable
from dataclasses import dataclass
from fractions import Fraction
from functools import lru_cache
from itertools import pairwise
from typing import TYPE_CHECKING

from emulation.pil.bus import svd_interrupt
from emulation.pil.rcc import TICK_HZ
from emulation.pil.scs import IRQ_BASE

if TYPE_CHECKING:
    from codegen.spec_model import Spec
    from emulation.pil.machine import Machine

#: DS5319 Table 46: t_latj, the injected trigger to the start of sampling, at most 3
#: ADC cycles; its note adds one PCLK2 cycle for an external trigger (TIM1 TRGO)
INJECTION_LATENCY_ADC_CYCLES = 3
GATE_NAMES = tuple(
    f"phase {phase} {side} ({output})"
    for phase, channel in zip("ABC", (1, 2, 3), strict=True)
    for side, output in (("upper", f"CH{channel}"), ("lower", f"CH{channel}N"))
)


@dataclass(frozen=True)
class SampleWindow:
    """One injected conversion's sampling window, 72 MHz ticks: from `start` to
    `sampled` as emulated; the chip may take it up to `latency` later."""

    sampled: int
    start: Fraction
    latency: Fraction
    channel: int

    @property
    def latest_end(self) -> Fraction:
        return self.sampled + self.latency


@dataclass(frozen=True)
class GateEdge:
    tick: int
    gate: int  # index into GATE_NAMES
    on: bool  # the switch turned on (else off)


def gate_edges(log: list[tuple[int, tuple[bool | None, ...]]]) -> list[GateEdge]:
    """Every switch's turn-on and turn-off in a gate record (an undriven output is off:
    a change between undriven and driven low is no edge)."""
    edges: list[GateEdge] = []
    for (_, before), (tick, after) in pairwise(log):
        for gate, (was, now) in enumerate(zip(before, after, strict=True)):
            if (was is True) != (now is True):
                edges.append(GateEdge(tick, gate, now is True))
    return edges


def window_violation(
    window: SampleWindow, edges: list[GateEdge], ticks: list[int], settling: Fraction
) -> str | None:
    """The line for `window` if a gate edge lies inside it (at any latency) or less than
    `settling` ticks before its start; `ticks` are the edges' ticks, sorted. An edge at
    the latest end itself is after the hold: clean."""
    low = window.start - settling  # an edge after this is too close or inside
    first = bisect.bisect_right(ticks, low)
    last = bisect.bisect_left(ticks, window.latest_end)
    if first >= last:
        return None
    edge = edges[last - 1]  # the latest offending edge
    if edge.tick < window.start:
        where = (
            f"{_t(window.start - edge.tick)} ticks before the window starts, under"
            f" sensing.settling_time ({_t(settling)} ticks)"
        )
    elif edge.tick < window.sampled:
        where = "inside the window"
    else:
        where = (
            f"inside the window as the chip may take it (up to {_t(window.latency)} ticks"
            " later: the injection latency)"
        )
    margin = min(edge.tick - low, window.latest_end - edge.tick)
    return (
        f"tick {window.sampled}: the current loop's sample of channel {window.channel}"
        f" (window {_t(window.start)}..{window.sampled} ticks) has {GATE_NAMES[edge.gate]}"
        f" turning {'on' if edge.on else 'off'} at tick {edge.tick}, {where}: margin"
        f" -{_t(margin)} ticks ({float(margin) / TICK_HZ * 1e9:.0f} ns)"
    )


def _t(value: Fraction | int) -> str:
    return f"{float(value):g}"


@lru_cache(maxsize=16)
def _injection_latency(adc_hz: int, pclk2_hz: int) -> Fraction:
    """Ticks from an injected trigger to its sampling's start: the ADC's injection
    latency and one APB2 clock (kept per clock setting: asked at every conversion)."""
    return Fraction(INJECTION_LATENCY_ADC_CYCLES * TICK_HZ, adc_hz) + Fraction(TICK_HZ, pclk2_hz)


class LoopSampleWatch:
    """The sampling windows of the current samples the current loop uses (see the
    module's docstring), collected as the firmware runs."""

    def __init__(self, machine: Machine, spec: Spec) -> None:
        self.machine = machine
        self.settling = Fraction(spec.sensing.settling_time_s) * TICK_HZ
        self._currents = frozenset(spec.sensing.current_channels)
        self._adc = IRQ_BASE + svd_interrupt("ADC1", "ADC")
        #: the latest injected conversion's window of each current channel
        self._latest: dict[int, SampleWindow] = {}
        #: windows read by the current loop's handler: (its entry count, window)
        self._read: list[tuple[int, SampleWindow]] = []
        #: the windows of samples the loop closed on, by (sampled, channel)
        self.used: dict[tuple[int, int], SampleWindow] = {}
        adc1 = machine.adc1
        adc1.injected_listeners.append(self._converted)
        for slot in (1, 2, 3, 4):
            adc1.readers[f"JDR{slot}"] = self._reading(slot, adc1.readers[f"JDR{slot}"])
        for channel in (1, 2, 3):
            name = f"CCR{channel}"
            machine.tim1.writers[name] = self._writing(machine.tim1.writers[name])

    def _in_loop(self) -> bool:
        active = self.machine.nvic.active
        return bool(active) and active[-1] == self._adc

    def _entries(self) -> int:
        return self.machine.handler_entries.get(self._adc, 0)

    def _converted(self, sampled: int, channel: int, _code: int) -> None:
        if channel not in self._currents:
            return
        adc = self.machine.adc1
        latency = _injection_latency(self.machine.rcc.adc_hz, self.machine.rcc.pclk2_hz)
        start = sampled - adc.sample_ticks(channel)
        self._latest[channel] = SampleWindow(sampled, start, latency, channel)

    def _reading(self, slot: int, read: Callable[[], int]) -> Callable[[], int]:
        def reader() -> int:
            if self._in_loop():
                channels = dict(self.machine.adc1.injected_channels())
                window = self._latest.get(channels.get(slot, -1))
                if window is not None:
                    self._read.append((self._entries(), window))
            return read()

        return reader

    def _writing(self, write: Callable[[int], None]) -> Callable[[int], None]:
        def writer(value: int) -> None:
            if self._in_loop() and self.machine.tim1.moe:
                entry = self._entries()
                for seen, window in self._read:
                    if seen == entry:
                        self.used[(window.sampled, window.channel)] = window
                self._read = [(seen, w) for seen, w in self._read if seen == entry]
            write(value)

        return writer

    def violations(self, log: list[tuple[int, tuple[bool | None, ...]]]) -> list[str]:
        """One line per used sample taken in a dirty window. A window that starts
        within the settling time of the gate record's start (no edges known before it)
        is not judged."""
        if not log:
            return []
        edges = gate_edges(log)
        ticks = [e.tick for e in edges]
        out = []
        for window in sorted(self.used.values(), key=lambda w: w.sampled):
            if window.start - self.settling < log[0][0]:
                continue
            line = window_violation(window, edges, ticks, self.settling)
            if line is not None:
                out.append(line)
        return out


#: Dirty windows reported one a line; the rest counted
REPORTED_WINDOWS = 10


def sample_window_lines(lines: list[str]) -> list[str]:
    """The first REPORTED_WINDOWS lines, and how many more there were."""
    more = len(lines) - REPORTED_WINDOWS
    return lines[:REPORTED_WINDOWS] + (
        [f"... and {more} more dirty current samples"] if more > 0 else []
    )

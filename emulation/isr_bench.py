"""Instructions and estimated Cortex-M3 cycles of the port's interrupt handlers.

The firmware image that `make firmware` links is run in unicorn (emulation.armsim). Each
Hall edge is staged the way the hardware presents it: the Hall pins in GPIO IDR, the
captured 60 degree interval in TIM3 CCR1, TIM3 SR.CC1IF set, and the ADC and duty
inputs filled (bldc_port_set_bus_voltage(), bldc_port_set_main_duty()); the commutation
end is SR.CC2IF. The timer and the NVIC are played by this module (`PortRig`): when the
Hall edge writes TIM1 EGR.COMG with DIER.COMIE set (the COM event raises TIM1_TRG_COM),
or a setter sets the TIM1_TRG_COM pending bit in NVIC_ISPR0, the bench runs
TIM1_TRG_COM_IRQHandler (the next edge's timing, at the lower priority) before the
commutation end. Register addresses and bit positions come from the vendor SVD, as in
the generated header.

`bench` runs edges through all six Hall codes in both directions over a sweep of speed,
bus voltage, current and duty (`Sweep`). `timing_sweep` runs the timing handler alone,
once per input point, over a denser sweep of the Hall period, and reads back what the
next edge applies; it is how the bench measures a rule whose cost varies with the inputs
(the resistance-aware rule's bisection and table lookups). `reached_functions` walks the
image's static call graph from a handler, to show which functions (library helpers
included) it can reach.
"""

from __future__ import annotations

import statistics
from collections import Counter, OrderedDict
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass
from pathlib import Path

from codegen.build_firmware import build
from codegen.derivation import derive
from codegen.fixedpoint.scaling import Scaling, scaling
from codegen.port import port_context
from codegen.port_drive import current_watch, wait_counts
from codegen.spec_loader import load_spec
from codegen.spec_model import Spec
from codegen.svd import load_device
from codegen.system_clock import SYSCLK_HZ
from emulation.armsim import (
    CLEAR,
    SET,
    ArmImage,
    CallResult,
    CortexM3Sim,
    Step,
    Symbol,
    load_elf,
)
from emulation.cycles import CycleBreakdown, UdivMode, entry_cycles, estimate_cycles, isr_cycles
from emulation.memory import STM32F103_72MHZ, MemoryTiming
from emulation.progress import progress

TARGET_HALL_INSTRUCTIONS = 64
TARGET_HALL_CYCLES = 120
TARGET_END_INSTRUCTIONS = 24
#: TIM1 trigger/COM: IRQ 26 on the STM32F103 (SVD TIM1_TRG_COM_TIM11).
TIMING_HANDLER = "TIM1_TRG_COM_IRQHandler"
#: TIM1 update: IRQ 25, which TIM1 never raises; the current loop pends it when the bus
#: moved, and it pends the timing once the bus state is new.
BUS_HANDLER = "TIM1_UP_IRQHandler"
#: A bus change as one event: the bus-change handler and the timing run it pends.
BUS_CHANGE = f"bus change ({BUS_HANDLER}, then {TIMING_HANDLER})"
HALL_HANDLER = "TIM3_IRQHandler"
#: ADC1_2: the current loop (JEOC) and the bus watchdog (AWD).
ADC_HANDLER = "ADC1_2_IRQHandler"
#: TIM1_BRK: the break input (over-current).
BREAK_HANDLER = "TIM1_BRK_IRQHandler"
#: EXTI9_5 (Hall A, B on PA6, PA7) and EXTI0 (Hall C on PB0) run the same body: a Hall
#: line changed (every Hall edge), the code 0 or 7 tripped.
HALL_LINES_HANDLER = "EXTI9_5_IRQHandler"
BUS_FUNCTION = "bldc_bus_condition"
TIMING_FUNCTION = "bldc_commutation_timing"
CPU_HZ = 72_000_000
#: Log-spaced Hall periods from the top speed to the slowest one in `bench`'s sweep.
BENCH_PERIOD_POINTS = 12
#: The bench's firmware takes a bus change at any sample: it steps the bus code from
#: point to point, where the port's gate (BLDC_PORT_BUS_MIN_PERIODS PWM periods from one
#: change to the next) would leave most of them waiting. The gate spaces the changes and
#: does not change what one costs (its compare takes an immediate either way); the CPU
#: load prices the default gate's spacing (`emulation.bench.bus_min_periods`).
BUS_GATE_OPEN = ("BLDC_PORT_BUS_MIN_PERIODS=1u",)
#: A value no TIM1 compare register takes (duties are 0..P): marks "not written".
UNWRITTEN = 0xFFFF


@dataclass(frozen=True)
class HandlerStats:
    name: str
    calls: int
    instructions_worst: int
    instructions_mean: float
    cycles_worst: int  # UDIV at 12 cycles, taken branches with a 3-cycle refill
    cycles_mean: float  # UDIV early-termination estimate
    stack_bytes: int = 0  # deepest below the entry SP, exception frame not included
    peripheral_accesses: int = 0  # worst per call


@dataclass(frozen=True)
class Sample:
    """The cost of one call: instructions, cycles with UDIV at its worst, cycles with the
    UDIV estimate (both with exception entry and exit for a handler), the stack it used
    below its entry SP (the exception frame not included) and its accesses to
    peripheral registers (whose APB wait states the model does not price)."""

    instructions: int
    cycles_worst: int
    cycles_typical: int
    stack_bytes: int = 0
    peripheral_accesses: int = 0


def _register(peripheral: str, register: str) -> int:
    p = load_device().peripheral(peripheral)
    (reg,) = [r for r in p.registers if r.name == register]
    return p.base_address + reg.address_offset


def _bit(peripheral: str, register: str, field: str) -> int:
    p = load_device().peripheral(peripheral)
    (reg,) = [r for r in p.registers if r.name == register]
    (f,) = [x for x in reg.fields if x.name == field]
    return 1 << f.bit_offset


def _stats(name: str, samples: Sequence[Sample]) -> HandlerStats:
    return HandlerStats(
        name=name,
        calls=len(samples),
        instructions_worst=max(s.instructions for s in samples),
        instructions_mean=statistics.fmean(s.instructions for s in samples),
        cycles_worst=max(s.cycles_worst for s in samples),
        cycles_mean=statistics.fmean(s.cycles_typical for s in samples),
        stack_bytes=max(s.stack_bytes for s in samples),
        peripheral_accesses=max(s.peripheral_accesses for s in samples),
    )


class NvicError(AssertionError):
    """The Hall edge did not raise the timing interrupt."""


@dataclass(frozen=True)
class Sweep:
    """The inputs a bench runs through: Hall periods (ticks), bus and current ADC codes,
    main duties (TIM1 counts)."""

    periods: tuple[int, ...]
    buses: tuple[int, ...]
    currents: tuple[int, ...]
    duties: tuple[int, ...]

    def __len__(self) -> int:
        return len(self.periods) * len(self.buses) * len(self.currents) * len(self.duties)

    def describe(self) -> str:
        def count(values: tuple[int, ...], one: str, many: str) -> str:
            return f"{len(values)} {one if len(values) == 1 else many}"

        return (
            f"{count(self.periods, 'period', 'periods')} {self.periods[0]}..{self.periods[-1]}"
            f" ticks x {count(self.buses, 'bus', 'buses')} x"
            f" {count(self.currents, 'current', 'currents')} x"
            f" {count(self.duties, 'duty', 'duties')}"
        )


def sweep(spec: Spec, sc: Scaling, period_points: int = BENCH_PERIOD_POINTS) -> Sweep:
    """Periods log-spaced from the top speed to the slowest one; bus min, middle, max;
    braking current 0, nominal and max; main duty 0, half, full."""
    low, high = sc.period_min_ticks, sc.period_max_ticks
    last = period_points - 1
    periods = sorted({low, high, *(round(low * (high / low) ** (k / last)) for k in range(last))})
    nominal = round(float(spec.controller.braking_current_nominal_a / sc.amps_per_current_code))
    currents = (
        sc.current_offset_code,
        sc.current_offset_code + min(int(nominal), sc.current_code_max),
        sc.current_offset_code + sc.current_code_max,
    )
    return Sweep(
        periods=tuple(periods),
        buses=(sc.bus_code_min, (sc.bus_code_min + sc.bus_code_max) // 2, sc.bus_code_max),
        currents=currents,
        duties=(0, sc.period_counts // 2, sc.period_counts),
    )


#: traces a rig keeps priced (`PortRig._price`)
PRICED_TRACES = 256


class PortRig:
    """The linked image in unicorn, with the timers, the ADC and the NVIC played around
    it. Peripheral registers are plain memory here, so the rig writes each status
    register (TIM3 SR, ADC SR) as the hardware would present it before every handler
    call; the Hall pins and the break input (inactive) are staged before the port's
    init reads them."""

    def __init__(self, spec: Spec, elf: Path, timing: MemoryTiming = STM32F103_72MHZ) -> None:
        self.spec = spec
        self.memory_timing = timing
        self.sim = CortexM3Sim(load_elf(elf))
        #: the last PRICED_TRACES traces priced (`_price`), by trace and mode
        self._priced: OrderedDict[tuple[tuple[Step, ...], UdivMode, bool], CycleBreakdown] = (
            OrderedDict()
        )
        context = port_context(spec)
        self.pins = context["hall_pins"]
        bkin = context["bkin"]
        self.break_inactive = (
            str(bkin["port"]),
            0 if spec.protection.break_polarity == "active_high" else 1 << int(str(bkin["n"])),
        )
        self.tim3_sr, self.tim3_ccr1, self.tim3_ccr2, self.tim3_cnt = (
            _register("TIM3", r) for r in ("SR", "CCR1", "CCR2", "CNT")
        )
        self.tim1_ccr = tuple(_register("TIM1", f"CCR{n}") for n in (1, 2, 3))
        self.tim1_cnt, self.tim1_ccr4 = _register("TIM1", "CNT"), _register("TIM1", "CCR4")
        self.tim1_arr, self.tim1_cr1 = _register("TIM1", "ARR"), _register("TIM1", "CR1")
        self.dir_bit = _bit("TIM1", "CR1", "DIR")
        #: the counts before the next trigger from which the end waits it out
        self.wait_counts = wait_counts(spec)  # BLDC_PORT_WAIT_COUNTS
        self.cc1if, self.cc2if = _bit("TIM3", "SR", "CC1IF"), _bit("TIM3", "SR", "CC2IF")
        self.uif = _bit("TIM3", "SR", "UIF")
        self.cc3if = _bit("TIM3", "SR", "CC3IF")
        self.ispr0 = _register("NVIC", "ISPR0")
        self.tim1_egr, self.tim1_dier = _register("TIM1", "EGR"), _register("TIM1", "DIER")
        self.tim1_bdtr, self.tim1_sr = _register("TIM1", "BDTR"), _register("TIM1", "SR")
        self.comg, self.comie = _bit("TIM1", "EGR", "COMG"), _bit("TIM1", "DIER", "COMIE")
        self.bif = _bit("TIM1", "SR", "BIF")
        self.adc_sr = _register("ADC1", "SR")
        self.adc_jdr = tuple(_register("ADC1", f"JDR{n}") for n in (1, 2, 3, 4))
        self.adc_dr = _register("ADC1", "DR")
        self.adc2_sr, self.adc2_dr = _register("ADC2", "SR"), _register("ADC2", "DR")
        self.jeoc, self.awd = _bit("ADC1", "SR", "JEOC"), _bit("ADC1", "SR", "AWD")
        # Stores that do not replace the word: the NVIC's set-pending words (a 0 bit
        # leaves its interrupt; the port's pend writes rely on it) and the status
        # registers the port clears by writing 0 to a flag and 1 to the rest.
        self.sim.combine_on_write(self.ispr0, SET)
        for peripheral in ("TIM1", "TIM3", "ADC1", "ADC2"):
            self.sim.combine_on_write(_register(peripheral, "SR"), CLEAR)
        tim1_irqs = load_device().peripheral("TIM1").interrupts
        (self.timing_irq,) = [i.value for i in tim1_irqs if i.name.startswith("TIM1_TRG_COM")]
        (self.bus_irq,) = [i.value for i in tim1_irqs if i.name.startswith("TIM1_UP")]
        self.bus_symbol = self.sim.image.symbol(BUS_FUNCTION)
        self.function_at = {
            s.address: s.name for s in self.sim.image.symbols.values() if s.is_function
        }
        self.stage_hall(spec.hall.sequence[0])
        # The ADC's calibration is over by the time the port polls it.
        self.sim.finish_on_read(_register("ADC1", "CR2"), _bit("ADC1", "CR2", "CAL"))
        self.sim.finish_on_read(_register("ADC2", "CR2"), _bit("ADC2", "CR2", "CAL"))
        self.sim.call("bldc_port_init", args=(0,))
        self.sim.write_u32(self.ispr0, 0)
        #: CR1 as init left it (the counter running), without DIR
        self.tim1_cr1_running = self.sim.read_u32(self.tim1_cr1) & ~self.dir_bit

    def prime(self, bus: int, current: int, period: int) -> None:
        """From init to the steady state: a bus sample (its bus change and timing), one
        Hall edge forward and its commutation end."""
        self.adc_sample(bus, current)
        self.serve(self.pended())
        self.timing()
        self.hall_edge(self.spec.hall.sequence[1], period)
        self.timing()
        self.commutation_end()
        self.timing()

    @property
    def image(self) -> ArmImage:
        return self.sim.image

    def stage_hall(self, code: int) -> None:
        levels = {"GPIOA": 0, "GPIOB": 0}
        port, inactive = self.break_inactive
        levels[port] |= inactive
        for pin in self.pins:
            if code & int(str(pin["code_bit"]).rstrip("u"), 16):
                levels[str(pin["port"])] |= 1 << int(str(pin["n"]))
        for gpio, value in levels.items():
            self.sim.write_u32(_register(gpio, "IDR"), value)

    def pended(self) -> frozenset[str]:
        """The port's handlers pended by software since the last look (then cleared):
        the timing and the bus change."""
        word = self.sim.read_u32(self.ispr0)
        self.sim.write_u32(self.ispr0, 0)
        irqs = ((TIMING_HANDLER, self.timing_irq), (BUS_HANDLER, self.bus_irq))
        return frozenset(name for name, irq in irqs if word & (1 << irq))

    def serve(self, pended: frozenset[str]) -> dict[str, CallResult]:
        """Run what is pending as the NVIC would: the bus change first (the same priority
        as the timing and a lower IRQ number), which pends the timing; then the timing.
        Each run by its handler's name, in that order."""
        runs = {}
        if BUS_HANDLER in pended:
            runs[BUS_HANDLER] = self.sim.call(BUS_HANDLER)
            pended = pended | self.pended()
        if TIMING_HANDLER in pended:
            runs[TIMING_HANDLER] = self.sim.call(TIMING_HANDLER)
        return runs

    def com_event(self) -> bool:
        """Whether the last handler raised a COM event with its interrupt on (then cleared)."""
        com = bool(self.sim.read_u32(self.tim1_egr) & self.comg) and bool(
            self.sim.read_u32(self.tim1_dier) & self.comie
        )
        self.sim.write_u32(self.tim1_egr, 0)
        return com

    def adc_sample(
        self, bus: int, current: int, *, status: int | None = None, capture: int | None = None
    ) -> CallResult:
        """The injected conversions end (JEOC): every current channel reads `current`,
        the bus `bus`; no Hall counter overflow pending, and with `capture` a Hall
        interval TIM3 captured (what a faulted drive's tick takes). The current-loop
        handler."""
        for address in self.adc_jdr[:3]:
            self.sim.write_u32(address, current)
        self.sim.write_u32(self.adc_jdr[3], bus)
        self.sim.write_u32(self.adc_dr, bus)  # the regular group's latest, the same bus
        self.sim.write_u32(self.adc2_dr, current)  # ADC2's latest conversion of the current
        self.sim.write_u32(self.adc_sr, self.jeoc if status is None else status)
        if capture is not None:
            self.sim.write_u32(self.tim3_ccr1, capture)
        self.sim.write_u32(self.tim3_sr, 0 if capture is None else self.cc1if)
        return self.sim.call(ADC_HANDLER)

    def current_rail(self, raw: int) -> CallResult:
        """ADC2's analog watchdog: a continuous conversion of the current read `raw`;
        ADC1 has nothing. The ADC1_2 handler (ADC2's entry)."""
        self.sim.write_u32(self.adc2_dr, raw)
        self.sim.write_u32(self.adc2_sr, self.awd)
        self.sim.write_u32(self.adc_sr, 0)
        self.sim.write_u32(self.tim3_sr, 0)
        result = self.sim.call(ADC_HANDLER)
        self.sim.write_u32(self.adc2_sr, 0)
        return result

    def hall_lines(self, code: int) -> CallResult:
        """A Hall line changed to `code`: the EXTI handler."""
        self.stage_hall(code)
        return self.sim.call(HALL_LINES_HANDLER)

    def set_inputs(self, bus: int, current: int, duty: int) -> dict[str, CallResult]:
        """The open-loop duty, then a sample of the bus and the current (which the port
        takes as I in the steady state); the runs they pended (`serve`), if any."""
        self.sim.call("bldc_port_set_main_duty", args=(duty,))
        pended = self.pended()
        self.adc_sample(bus, current)
        return self.serve(pended | self.pended())

    def hall_edge(self, code: int, period: int, *, timeout: bool = False) -> CallResult:
        """A Hall edge to `code` after `period` ticks (with the counter wrapped if
        `timeout`); it must raise the COM event that runs the timing handler."""
        self.stage_hall(code)
        self.sim.write_u32(self.tim3_ccr1, period)
        self.sim.write_u32(self.tim3_cnt, 0)
        self.sim.write_u32(self.tim3_sr, self.cc1if | (self.uif if timeout else 0))
        self.sim.write_u32(self.tim1_egr, 0)
        result = self.sim.call(HALL_HANDLER)
        if not self.com_event():
            raise NvicError("the Hall edge raised no COM event")
        return result

    def timing(self) -> CallResult:
        return self.sim.call(TIMING_HANDLER)

    def commutation_end(self, *, trigger_in: int | None = None) -> CallResult:
        """The commutation end mid-period, long after the last injected trigger (its
        sequence taken) and long before the next: the port holds the loop through a
        sequence a trigger younger than the sequence began (BLDC_PORT_TRIGGER_AGE), which
        a counter left at 0 would be, and through one a trigger about to fire before the
        COM event begins (BLDC_PORT_IMMINENT_AGE), which a counter one short of CCR4
        would be. `trigger_in`: the end's first read of TIM1's counter finds the next
        injected trigger that many counts ahead, and the counter counts with the cycles
        the call's steps take (and CR1's DIR, centre-aligned); BLDC_PORT_WAIT_COUNTS is
        the end's longest wait."""
        self.sim.write_u32(self.tim3_sr, self.cc2if)
        self.sim.write_u32(self.tim1_egr, 0)
        ccr4 = self.sim.read_u32(self.tim1_ccr4)
        if trigger_in is None:
            self.sim.write_u32(self.tim1_cnt, ccr4 // 2)
            return self.sim.call(HALL_HANDLER)
        arr = self.sim.read_u32(self.tim1_arr)
        centre = self.spec.inverter.pwm_alignment != "edge"
        clock = float(self.spec.inverter.timer_clock_hz / SYSCLK_HZ)  # counts per cycle
        # at the first read: WAIT_COUNTS before CCR4 (edge-aligned), before the peak
        # counting up (centre-aligned: the trigger one count after it)
        start = (arr + 1 if centre else ccr4) - trigger_in
        first: list[int] = []  # the cycles at the first read

        def position(steps: Sequence[Step]) -> int:
            cycles = estimate_cycles(steps, self.sim, timing=self.memory_timing).cycles
            first[:] = first or [cycles]
            return start + int((cycles - first[0]) * clock)

        def counter(steps: Sequence[Step]) -> int:
            at = position(steps)
            if not centre:
                return at % (arr + 1)
            phase = at % (2 * arr)
            return phase if phase < arr else 2 * arr - phase

        def control(steps: Sequence[Step]) -> int:
            down = centre and position(steps) % (2 * arr) >= arr
            return self.tim1_cr1_running | (self.dir_bit if down else 0)

        self.sim.count_on_read(self.tim1_cnt, counter)
        self.sim.count_on_read(self.tim1_cr1, control)
        try:
            return self.sim.call(HALL_HANDLER)
        finally:
            self.sim.count_on_read(self.tim1_cnt, None)
            self.sim.count_on_read(self.tim1_cr1, None)

    def mark_unwritten(self) -> None:
        """Fill the TIM1 compare registers and TIM3 CCR2 with a value no edge writes."""
        for address in (*self.tim1_ccr, self.tim3_ccr2):
            self.sim.write_u32(address, UNWRITTEN)

    def applied(self) -> tuple[int, tuple[int, ...]] | None:
        """What the last edge applied since `mark_unwritten`: the commutation end (TIM3
        CCR2, Hall ticks) and the TIM1 compares it wrote, sorted; None if it applied
        nothing (the safe state)."""
        ticks = self.sim.read_u32(self.tim3_ccr2)
        if ticks == UNWRITTEN:
            return None
        written = (self.sim.read_u32(a) for a in self.tim1_ccr)
        return ticks, tuple(sorted(v for v in written if v != UNWRITTEN))

    def cost(self, result: CallResult) -> Sample:
        """Instructions and cycles of a handler call, exception entry and exit included."""
        entry = result.trace[0].address

        worst = self._price(result.trace, "worst", after_exception=True)
        return Sample(
            result.instructions,
            isr_cycles(worst, entry),
            isr_cycles(self._price(result.trace, "estimate", after_exception=True), entry),
            result.stack_bytes,
            worst.peripheral_accesses,
        )

    def _price(
        self, trace: Sequence[Step], mode: UdivMode, *, after_exception: bool = False
    ) -> CycleBreakdown:
        """`estimate_cycles` of a trace on this rig's image and memory timing, kept for
        the last PRICED_TRACES traces: a sweep runs the same path with the same divide
        operands again and again (two thirds of a rule sweep's traces), and the same
        steps on the same code cost the same."""
        key = (tuple(trace), mode, after_exception)
        known = self._priced.get(key)
        if known is not None:
            self._priced.move_to_end(key)
            return known
        priced = estimate_cycles(
            trace,
            self.sim,
            udiv_mode=mode,
            timing=self.memory_timing,
            after_exception=after_exception,
        )
        self._priced[key] = priced
        if len(self._priced) > PRICED_TRACES:
            self._priced.popitem(last=False)
        return priced

    def total(self, runs: Iterable[CallResult]) -> Sample:
        """The cost of handler runs one after the other (each with its entry and exit):
        the whole work of one event; the deepest stack of any of them."""
        costs = [self.cost(r) for r in runs]
        return Sample(
            sum(c.instructions for c in costs),
            sum(c.cycles_worst for c in costs),
            sum(c.cycles_typical for c in costs),
            max(c.stack_bytes for c in costs),
            sum(c.peripheral_accesses for c in costs),
        )

    def part(self, result: CallResult, symbol: Symbol) -> Sample:
        """The cost of the steps of a call that ran inside `symbol` (no entry or exit)."""
        inside = [
            s for s in result.trace if symbol.address <= s.address < symbol.address + symbol.size
        ]
        return Sample(
            len(inside),
            self._price(inside, "worst").cycles,
            self._price(inside, "estimate").cycles,
        )

    def entries(self, trace: Iterable[Step]) -> Counter[str]:
        """How often a call entered each function (executed its first instruction)."""
        return Counter(self.function_at[s.address] for s in trace if s.address in self.function_at)


@dataclass(frozen=True)
class Stats:
    """The port's handlers over a bench run. The timing handler's runs on the cached
    bus state apart from the bus changes (a new bus code beyond the hysteresis: the
    bus-change handler and the timing run it pends, one event); `core_*` are the core's
    functions inside those runs (no entry or exit)."""

    hall: HandlerStats  # edges that commutate
    hall_refused: HandlerStats | None  # refused, no fault: the region's safe state
    end: HandlerStats
    timing: HandlerStats | None  # runs on the cached bus state
    timing_bus: HandlerStats | None  # bus changes: the bus-change handler + the timing it pends
    core_bus: HandlerStats | None  # bldc_bus_condition() inside them
    #: bldc_commutation_timing() inside every run; None where the port inlines it into
    #: the handler (no function of that name in the image: the handler's figure is all)
    core_timing: HandlerStats | None
    current_loop: HandlerStats  # the ADC handler in the closed loop (JEOC), every path
    hall_lines: HandlerStats  # the EXTI handler on a valid code (every Hall edge)
    fault_paths: dict[str, Sample]  # the handler that detects each fault, one run
    fault_to_moe: dict[str, int]  # cycles from its entry to the store that clears MOE
    #: cycles from entry to the COM event (TIM1 EGR) that switches the outputs: the
    #: Hall edge's shortest run, and the commutation end's longest
    edge_switch_best: int = 0
    end_switch_worst: int = 0
    #: (Hall period in ticks, worst timing run at it, either path), by period: each run
    #: counts at the period of the last Hall edge, the one the handler computes with
    timing_by_period: tuple[tuple[int, int], ...] = ()

    @property
    def timing_worst(self) -> HandlerStats:
        """The slower of the two timing paths (the worst case a budget must take)."""
        paths = [t for t in (self.timing, self.timing_bus) if t is not None]
        return max(paths, key=lambda t: t.cycles_worst)


def bench(
    spec_path: str | Path,
    generated: Path,
    build_dir: Path,
    inputs: Sweep | None = None,
    *,
    defines: Sequence[str] = (),
    timing: MemoryTiming = STM32F103_72MHZ,
) -> Stats:
    """All three handlers in their order (edge, timing, end, timing) over `inputs`
    (default `sweep`), all six Hall codes in both directions, plus the safe-state paths;
    the timing runs a bus change pends included."""
    spec = load_spec(spec_path)
    if inputs is None:
        inputs = sweep(spec, scaling(spec, derive()))
    build(generated, build_dir, defines=(*BUS_GATE_OPEN, *defines))
    rig = PortRig(spec, build_dir / "firmware.elf", timing)
    timing_symbol = rig.image.symbols.get(TIMING_FUNCTION)
    hall_edge: list[Sample] = []
    refused: list[Sample] = []
    cached: list[Sample] = []
    recomputed: list[Sample] = []
    bus_part: list[Sample] = []
    timing_part: list[Sample] = []
    commutation_end: list[Sample] = []
    switches_on: list[int] = []  # Hall edge: entry to its COM event
    switches_off: list[int] = []  # commutation end: entry to its COM event
    worst_at: dict[int, int] = {}
    at_period = [inputs.periods[0]]  # the last Hall edge's period (rig.prime's first)

    def worst_here(cost: Sample) -> None:
        worst_at[at_period[0]] = max(worst_at.get(at_period[0], 0), cost.cycles_worst)

    def measure_timing(result: CallResult) -> None:
        cost = rig.cost(result)
        worst_here(cost)
        if timing_symbol is not None:
            timing_part.append(rig.part(result, timing_symbol))
        cached.append(cost)

    def set_inputs(bus: int, current: int, duty: int) -> None:
        runs = rig.set_inputs(bus, current, duty)
        if BUS_HANDLER in runs:
            # a bus change: its handler and the timing run it pends, one event
            bus_part.append(rig.part(runs[BUS_HANDLER], rig.bus_symbol))
            if timing_symbol is not None and TIMING_HANDLER in runs:
                timing_part.append(rig.part(runs[TIMING_HANDLER], timing_symbol))
            cost = rig.total(runs.values())
            worst_here(cost)
            recomputed.append(cost)
        elif TIMING_HANDLER in runs:
            measure_timing(runs[TIMING_HANDLER])

    periods = inputs.periods
    rig.prime(inputs.buses[0], inputs.currents[0], periods[0])
    runs = [(d, p) for d in (1, -1) for p in periods]
    for direction, period in progress(runs, f"bench {spec.name} handlers"):
        # backwards from the code the forward runs end on (their last, the sequence's
        # last): a first edge to that code again is a repeated code, HALL_SEQUENCE, and
        # the rest of the sweep had measured a faulted drive (a bus change's faulted path)
        back = tuple(reversed(spec.hall.sequence))
        sequence = spec.hall.sequence if direction > 0 else back[1:] + back[:1]
        for bus in inputs.buses:
            for current in inputs.currents:
                for duty in inputs.duties:
                    set_inputs(bus, current, duty)
                    for index, code in enumerate(sequence):
                        # The slowest period also as a Hall timeout (the counter wrapped).
                        edge = rig.hall_edge(code, period, timeout=period == periods[-1])
                        at_period[0] = period
                        if "port_refuse" in rig.entries(edge.trace):
                            refused.append(rig.cost(edge))
                        else:
                            hall_edge.append(rig.cost(edge))
                            switches_on.append(_cycles_to_store(rig, edge, rig.tim1_egr))
                        # The timing depends on the period, bus, current and duty only,
                        # the same for every edge of this loop: after the first edge
                        # (and its commutation end) a rerun would publish the same
                        # values, so it is skipped.
                        if index == 0:
                            measure_timing(rig.timing())
                        # the first end of each run of edges waits out an imminent
                        # trigger, its longest wait (the rest: mid-period)
                        end = rig.commutation_end(
                            trigger_in=rig.wait_counts if index == 0 else None
                        )
                        commutation_end.append(rig.cost(end))
                        if _stores_to(end, rig.tim1_egr):  # it ended a commutation
                            switches_off.append(_cycles_to_store(rig, end, rig.tim1_egr))
                        if rig.com_event() and index == 0:
                            measure_timing(rig.timing())
    latched = rig.sim.call("bldc_port_faults").return_value
    if latched != 0:
        raise AssertionError(f"the handler sweep latched faults {latched:#x}: a faulted drive")
    lines = [rig.cost(rig.hall_lines(code)) for code in spec.hall.sequence]
    loop, faults, to_moe = current_loop_runs(rig, inputs)
    return Stats(
        hall=_stats("Hall edge (TIM3 CC1)", hall_edge),
        hall_refused=_stats("Hall edge refused (safe state)", refused) if refused else None,
        end=_stats("commutation end (TIM3 CC2)", commutation_end),
        timing=_stats(f"{TIMING_HANDLER}, bus state cached", cached) if cached else None,
        timing_bus=_stats(BUS_CHANGE, recomputed) if recomputed else None,
        core_bus=_stats(f"{BUS_FUNCTION}()", bus_part) if bus_part else None,
        core_timing=_stats(f"{TIMING_FUNCTION}()", timing_part) if timing_part else None,
        current_loop=_stats(f"{ADC_HANDLER} (current loop)", loop),
        hall_lines=_stats(f"{HALL_LINES_HANDLER} (a valid code)", lines),
        fault_paths=faults,
        fault_to_moe=to_moe,
        edge_switch_best=min(switches_on),
        end_switch_worst=max(switches_off),
        timing_by_period=tuple(sorted(worst_at.items())),
    )


def _stores_to(result: CallResult, address: int) -> bool:
    return any(a.write and a.address == address for step in result.trace for a in step.accesses)


def _cycles_to_store(rig: PortRig, result: CallResult, address: int) -> int:
    """Cycles from the handler's entry (exception entry included) to the end of the
    first instruction that stores to `address`."""
    for k, step in enumerate(result.trace):
        if any(a.write and a.address == address for a in step.accesses):
            part = estimate_cycles(
                result.trace[: k + 1],
                rig.sim,
                udiv_mode="worst",
                timing=rig.memory_timing,
                after_exception=True,
            )
            return entry_cycles(part, result.trace[0].address) + part.cycles
    raise AssertionError(f"the handler never stored to 0x{address:08x}")


def current_loop_runs(
    rig: PortRig, inputs: Sweep
) -> tuple[list[Sample], dict[str, Sample], dict[str, int]]:
    """The current-loop handler in the closed loop, in the steady state, over the sweep's
    buses and currents (a moved bus takes its slower path); then each fault path once,
    from the state the drive is in, with the cycles until MOE is cleared."""
    spec = rig.spec
    sc = scaling(spec, derive())
    milliamps = int(spec.controller.braking_current_nominal_a * 1000)
    rig.sim.call("bldc_set_braking_current", args=(milliamps,))
    samples = []
    for bus in inputs.buses:
        for current in inputs.currents:
            samples.append(rig.cost(rig.adc_sample(bus, current)))
            rig.serve(rig.pended())
            samples.append(rig.cost(rig.adc_sample(bus, current)))
    faults: dict[str, Sample] = {}
    to_moe: dict[str, int] = {}

    def rearm(after: str) -> None:
        """The drive armed afresh through its own API, the rotor in the sequence's first
        sector, and primed: each fault path is measured from the armed drive, as it trips
        from there. A clear re-arms (reads the pins) only with a fault latched, so one is
        raised first (the clear had left the pins of the last edge, and prime's edge
        from them latched HALL_SEQUENCE: every fault path after the first had been
        measured with it latched, which a bus fault now only adds its bit to)."""
        rig.com_event()
        if rig.sim.call("bldc_port_faults").return_value != 0:
            # the faulted drive measures the rotor at the sweep's first interval (before
            # the Hall lines' trip below, whose intervals it lets only shorten): an
            # over-speed's own short one is a cause the clear keeps
            rig.adc_sample(sc.bus_code_min, sc.current_offset_code, capture=inputs.periods[0])
        rig.hall_lines(7)  # HALL_INVALID: a Hall code 0/7 on the lines, the EXTI's trip
        rig.pended()
        rig.stage_hall(spec.hall.sequence[0])
        rig.adc_sample(sc.bus_code_min, sc.current_offset_code)
        left = rig.sim.call("bldc_port_clear_faults").return_value
        if left != 0:
            raise AssertionError(f"{after}: the fault did not clear ({left:#x})")
        rig.prime(sc.bus_code_min, sc.current_offset_code, inputs.periods[0])
        latched = rig.sim.call("bldc_port_faults").return_value
        if latched != 0:
            raise AssertionError(f"{after}: re-armed and primed with faults {latched:#x}")

    def fault(name: str, run: Callable[[], CallResult]) -> None:
        result = run()
        faults[name] = rig.cost(result)
        try:
            to_moe[name] = _cycles_to_store(rig, result, rig.tim1_bdtr)
        except AssertionError as error:
            raise AssertionError(f"{name}: {error}") from error
        rearm(name)

    rearm("the current loop's runs")

    offset = sc.current_offset_code
    fault(
        "over-voltage (analog watchdog)",
        lambda: rig.adc_sample(sc.bus_code_max + 1, offset, status=rig.jeoc | rig.awd),
    )
    fault(
        "under-voltage (analog watchdog)",
        lambda: rig.adc_sample(0, offset, status=rig.jeoc | rig.awd),
    )
    # ADC2's watchdog sees each rail zero current does not read on, at every conversion
    rail = 0 if current_watch(spec).ltr > 0 else 2**spec.adc.bits - 1
    fault("current sensor at a rail (ADC2 watchdog)", lambda: rig.current_rail(rail))

    def timeout() -> CallResult:
        # the Hall counter wraps while the bridge switches: TIM3's update interrupt
        rig.sim.write_u32(rig.tim3_sr, rig.uif)
        return rig.sim.call(HALL_HANDLER)

    fault("Hall timeout (TIM3 wrap)", timeout)

    def late_edge() -> CallResult:
        # no edge by 4 intervals while the bridge switches: TIM3's CC3 match
        rig.sim.write_u32(rig.tim3_sr, rig.cc3if)
        return rig.sim.call(HALL_HANDLER)

    fault("Hall timeout (TIM3 CC3, 4 intervals)", late_edge)
    fault("invalid Hall code", lambda: rig.hall_edge(7, inputs.periods[0]))
    fault("Hall code 0/7 without an edge (EXTI, 1 us confirmation)", lambda: rig.hall_lines(7))
    fault("over-speed", lambda: rig.hall_edge(spec.hall.sequence[2], sc.period_min_ticks - 1))

    def break_input() -> CallResult:
        rig.sim.write_u32(rig.tim1_sr, rig.bif)
        port, inactive = rig.break_inactive
        active = 0 if inactive else 1 << int(str(port_context(spec)["bkin"]["n"]))
        rig.sim.write_u32(_register(port, "IDR"), active)
        return rig.sim.call(BREAK_HANDLER)

    fault("over-current (break input)", break_input)
    return samples, faults, to_moe


@dataclass(frozen=True)
class TimingPoint:
    """One run of the timing handler: its inputs, its cost, the functions it entered (with
    how often) and what the next Hall edge applied from it."""

    period: int
    bus: int
    current: int
    duty: int
    cost: Sample
    bus_part: Sample
    entries: Counter[str]
    applied: tuple[int, tuple[int, ...]] | None


@dataclass(frozen=True)
class TimingSweep:
    inputs: Sweep
    points: tuple[TimingPoint, ...]
    bus_changes: tuple[Sample, ...] = ()  # the runs a new bus code pended (cost only)

    @property
    def bus_change_stats(self) -> HandlerStats | None:
        if not self.bus_changes:
            return None
        return _stats(BUS_CHANGE, self.bus_changes)

    @property
    def stats(self) -> HandlerStats:
        return _stats(f"{TIMING_HANDLER} (timing sweep)", [p.cost for p in self.points])

    @property
    def bus_stats(self) -> HandlerStats:
        return _stats(f"{BUS_FUNCTION}() inside it", [p.bus_part for p in self.points])

    @property
    def worst(self) -> TimingPoint:
        return max(self.points, key=lambda p: (p.cost.cycles_worst, p.cost.instructions))

    def functions(self) -> frozenset[str]:
        """Every function the handler entered over the sweep."""
        return frozenset(name for p in self.points for name in p.entries)


def timing_sweep(spec: Spec, elf: Path, inputs: Sweep) -> TimingSweep:
    """The timing handler once per input point: a Hall edge measures `period` and raises
    it, then the next edge (same period) applies its result, read back from the timers."""
    rig = PortRig(spec, elf)
    rig.prime(inputs.buses[0], inputs.currents[0], inputs.periods[0])
    sequence = spec.hall.sequence
    wrapped = (1 << spec.hall.counter_bits) - 1  # TIM3's ARR: a wrap reads as it
    step = 0
    points = []
    bus_changes = []
    for period in progress(inputs.periods, f"bench {spec.name} timing sweep"):
        for bus in inputs.buses:
            for current in inputs.currents:
                for duty in inputs.duties:
                    if period == wrapped:
                        # the port holds a bus change (and an open-loop duty's run) while
                        # the last interval reads as the counter's wrap, the speed unknown
                        # (`port_timing_may_run`): an edge at the sweep's first period
                        # first, as the rotor's next one would give, so that the point's
                        # inputs reach its timing
                        rig.hall_edge(sequence[step % 6], inputs.periods[0])
                        rig.commutation_end()
                        step += 1
                    runs = rig.set_inputs(bus, current, duty)
                    if BUS_HANDLER in runs:
                        bus_changes.append(rig.total(runs.values()))
                    rig.hall_edge(sequence[step % 6], period)
                    result = rig.timing()
                    rig.commutation_end()
                    rig.mark_unwritten()
                    rig.hall_edge(sequence[(step + 1) % 6], period)
                    applied = rig.applied()
                    # The timing this edge raised has the same inputs: its value is already
                    # in place, so it is not run again; the commutation end is.
                    rig.commutation_end()
                    step += 2
                    points.append(
                        TimingPoint(
                            period,
                            bus,
                            current,
                            duty,
                            rig.cost(result),
                            rig.part(result, rig.bus_symbol),
                            rig.entries(result.trace),
                            applied,
                        )
                    )
    return TimingSweep(inputs, tuple(points), tuple(bus_changes))


def shortest_sector_cycles(spec_path: str | Path) -> int:
    """CPU cycles (72 MHz) in the shortest 60 degree interval the spec allows."""
    spec = load_spec(spec_path)
    sc = scaling(spec, derive())
    return int(sc.period_min_ticks * CPU_HZ / spec.hall.timer_clock_hz)


def sector_share(cycles: int, sector_cycles: int | None) -> str:
    if not sector_cycles:
        return ""
    return (
        f", {100.0 * cycles / sector_cycles:.1f} % of the shortest 60 degree"
        f" interval ({sector_cycles} cycles)"
    )

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

import bisect
import statistics
from collections import Counter
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from pathlib import Path

import capstone  # type: ignore[import-untyped]
from capstone import arm_const as arm

from codegen.build_firmware import build
from codegen.derivation import derive
from codegen.fixedpoint.scaling import Scaling, scaling
from codegen.port import port_context
from codegen.spec_loader import load_spec
from codegen.spec_model import Spec
from codegen.svd import load_device
from emulation.armsim import ArmImage, CallResult, CortexM3Sim, Step, Symbol, load_elf
from emulation.cycles import UdivMode, estimate_cycles, isr_cycles
from emulation.memory import STM32F103_72MHZ, MemoryTiming

TARGET_HALL_INSTRUCTIONS = 64
TARGET_HALL_CYCLES = 120
TARGET_END_INSTRUCTIONS = 24
#: TIM1 trigger/COM: IRQ 26 on the STM32F103 (SVD TIM1_TRG_COM_TIM11).
TIMING_HANDLER = "TIM1_TRG_COM_IRQHandler"
HALL_HANDLER = "TIM3_IRQHandler"
BUS_FUNCTION = "bldc_bus_condition"
CPU_HZ = 72_000_000
#: Log-spaced Hall periods from the top speed to the slowest one in `bench`'s sweep.
BENCH_PERIOD_POINTS = 12
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


@dataclass(frozen=True)
class Sample:
    """The cost of one call: instructions, cycles with UDIV at its worst, cycles with the
    UDIV estimate (both with exception entry and exit for a handler)."""

    instructions: int
    cycles_worst: int
    cycles_typical: int


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


class PortRig:
    """The linked image in unicorn, with the timers and the NVIC played around it."""

    def __init__(self, spec: Spec, elf: Path, timing: MemoryTiming = STM32F103_72MHZ) -> None:
        self.spec = spec
        self.memory_timing = timing
        self.sim = CortexM3Sim(load_elf(elf))
        self.sim.call("bldc_port_init")
        self.pins = port_context(spec)["hall_pins"]
        self.tim3_sr, self.tim3_ccr1, self.tim3_ccr2, self.tim3_cnt = (
            _register("TIM3", r) for r in ("SR", "CCR1", "CCR2", "CNT")
        )
        self.tim1_ccr = tuple(_register("TIM1", f"CCR{n}") for n in (1, 2, 3))
        self.cc1if, self.cc2if = _bit("TIM3", "SR", "CC1IF"), _bit("TIM3", "SR", "CC2IF")
        self.uif = _bit("TIM3", "SR", "UIF")
        self.ispr0 = _register("NVIC", "ISPR0")
        self.tim1_egr, self.tim1_dier = _register("TIM1", "EGR"), _register("TIM1", "DIER")
        self.comg, self.comie = _bit("TIM1", "EGR", "COMG"), _bit("TIM1", "DIER", "COMIE")
        (self.timing_irq,) = [
            i.value
            for i in load_device().peripheral("TIM1").interrupts
            if i.name.startswith("TIM1_TRG_COM")
        ]
        self.current_adc = self.sim.image.symbol("bldc_adc_phase_current").address
        self.bus_symbol = self.sim.image.symbol(BUS_FUNCTION)
        self.function_at = {
            s.address: s.name for s in self.sim.image.symbols.values() if s.is_function
        }

    @property
    def image(self) -> ArmImage:
        return self.sim.image

    def stage_hall(self, code: int) -> None:
        levels = {"GPIOA": 0, "GPIOB": 0}
        for pin in self.pins:
            if code & int(str(pin["code_bit"]).rstrip("u"), 16):
                levels[str(pin["port"])] |= 1 << int(str(pin["n"]))
        for port, value in levels.items():
            self.sim.write_u32(_register(port, "IDR"), value)

    def nvic_pending(self) -> bool:
        """Whether TIM1_TRG_COM was pended by software (then cleared)."""
        pending = bool(self.sim.read_u32(self.ispr0) & (1 << self.timing_irq))
        self.sim.write_u32(self.ispr0, 0)
        return pending

    def com_event(self) -> bool:
        """Whether the last handler raised a COM event with its interrupt on (then cleared)."""
        com = bool(self.sim.read_u32(self.tim1_egr) & self.comg) and bool(
            self.sim.read_u32(self.tim1_dier) & self.comie
        )
        self.sim.write_u32(self.tim1_egr, 0)
        return com

    def set_inputs(self, bus: int, current: int, duty: int) -> None:
        """The application's setters and the current ADC; a pended timing runs (unmeasured)."""
        self.sim.call("bldc_port_set_bus_voltage", args=(bus,))
        self.sim.write_u16(self.current_adc, current)
        self.sim.call("bldc_port_set_main_duty", args=(duty,))
        if self.nvic_pending():
            self.sim.call(TIMING_HANDLER)

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

    def commutation_end(self) -> CallResult:
        self.sim.write_u32(self.tim3_sr, self.cc2if)
        return self.sim.call(HALL_HANDLER)

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

        def cycles(mode: UdivMode) -> int:
            body = estimate_cycles(
                result.trace, self.sim, udiv_mode=mode, timing=self.memory_timing, after_exception=True
            )
            return isr_cycles(body, entry)

        return Sample(result.instructions, cycles("worst"), cycles("estimate"))

    def part(self, result: CallResult, symbol: Symbol) -> Sample:
        """The cost of the steps of a call that ran inside `symbol` (no entry or exit)."""
        inside = [
            s for s in result.trace if symbol.address <= s.address < symbol.address + symbol.size
        ]
        return Sample(
            len(inside),
            estimate_cycles(inside, self.sim, udiv_mode="worst", timing=self.memory_timing).cycles,
            estimate_cycles(inside, self.sim, udiv_mode="estimate", timing=self.memory_timing).cycles,
        )

    def entries(self, trace: Iterable[Step]) -> Counter[str]:
        """How often a call entered each function (executed its first instruction)."""
        return Counter(self.function_at[s.address] for s in trace if s.address in self.function_at)


Stats = tuple[HandlerStats, HandlerStats, HandlerStats, HandlerStats]


def bench(
    spec_path: str | Path, generated: Path, build_dir: Path, inputs: Sweep | None = None
) -> Stats:
    """All three handlers in their order (edge, timing, end) over `inputs` (default
    `sweep`), all six Hall codes in both directions, plus the safe-state paths."""
    spec = load_spec(spec_path)
    if inputs is None:
        inputs = sweep(spec, scaling(spec, derive()))
    build(generated, build_dir)
    rig = PortRig(spec, build_dir / "firmware.elf")
    hall_edge: list[Sample] = []
    timing: list[Sample] = []
    bus_part: list[Sample] = []
    commutation_end: list[Sample] = []

    def run_timing() -> None:
        result = rig.timing()
        bus_part.append(rig.part(result, rig.bus_symbol))
        timing.append(rig.cost(result))

    periods = inputs.periods
    for direction in (1, -1):
        sequence = spec.hall.sequence if direction > 0 else tuple(reversed(spec.hall.sequence))
        for period in periods:
            for bus in inputs.buses:
                for current in inputs.currents:
                    for duty in inputs.duties:
                        rig.set_inputs(bus, current, duty)
                        for code in sequence:
                            # The slowest period also as a Hall timeout (the counter wrapped).
                            edge = rig.hall_edge(code, period, timeout=period == periods[-1])
                            hall_edge.append(rig.cost(edge))
                            run_timing()
                            commutation_end.append(rig.cost(rig.commutation_end()))
    # The safe-state paths: an invalid code (000, 111) from a valid one, and back.
    for code in (7, spec.hall.sequence[0], 0, spec.hall.sequence[0]):
        hall_edge.append(rig.cost(rig.hall_edge(code, periods[0])))
        run_timing()
    return (
        _stats("Hall edge (TIM3 CC1)", hall_edge),
        _stats("commutation end (TIM3 CC2)", commutation_end),
        _stats("next edge's timing (TIM1_TRG_COM, low priority)", timing),
        _stats(f"{BUS_FUNCTION}() inside it", bus_part),
    )


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
    sequence = spec.hall.sequence
    step = 0
    points = []
    for period in inputs.periods:
        for bus in inputs.buses:
            for current in inputs.currents:
                for duty in inputs.duties:
                    rig.set_inputs(bus, current, duty)
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
    return TimingSweep(inputs, tuple(points))


def _direct_targets(code: bytes, address: int) -> tuple[set[int], bool]:
    """Branch and call targets of a function's code, and whether it branches indirectly
    (other than returning)."""
    engine = capstone.Cs(capstone.CS_ARCH_ARM, capstone.CS_MODE_THUMB | capstone.CS_MODE_MCLASS)
    engine.detail = True
    targets: set[int] = set()
    indirect = False
    for insn in engine.disasm(code, address):
        if insn.id in (arm.ARM_INS_BL, arm.ARM_INS_B, arm.ARM_INS_CBZ, arm.ARM_INS_CBNZ):
            immediates = [op.imm for op in insn.operands if op.type == arm.ARM_OP_IMM]
            targets.update(immediates)
        elif insn.id in (arm.ARM_INS_BLX, arm.ARM_INS_BX):
            registers = [op.reg for op in insn.operands if op.type == arm.ARM_OP_REG]
            indirect |= registers != [arm.ARM_REG_LR]
    return targets, indirect


def reached_functions(image: ArmImage, root: str) -> tuple[frozenset[str], bool]:
    """Functions reachable from `root` through direct calls and branches in the linked
    image (its static call graph), and whether any of them branches indirectly.

    A function symbol without a size (hand-written library assembly) extends to the next
    function symbol; a branch target belongs to the function whose extent holds it."""
    functions = sorted(
        (s for s in image.symbols.values() if s.is_function), key=lambda s: s.address
    )
    starts = [s.address for s in functions]

    def extent(index: int) -> int:
        symbol = functions[index]
        if symbol.size:
            return symbol.size
        following = starts[index + 1] if index + 1 < len(starts) else symbol.address
        return following - symbol.address

    def owner(address: int) -> int:
        index = bisect.bisect_right(starts, address) - 1
        if index < 0 or address >= starts[index] + extent(index):
            raise ValueError(f"a branch to 0x{address:08x} lies outside every function")
        return index

    def read(index: int) -> bytes:
        symbol = functions[index]
        for segment in image.segments:
            start = symbol.address - segment.address
            if start >= 0 and start + extent(index) <= len(segment.data):
                return segment.data[start : start + extent(index)]
        raise ValueError(f"{symbol.name} is not in a loaded segment")

    seen: set[int] = set()
    indirect = False
    pending = [owner(image.symbol(root).address)]
    while pending:
        index = pending.pop()
        if index in seen:
            continue
        seen.add(index)
        targets, branches_indirectly = _direct_targets(read(index), starts[index])
        indirect |= branches_indirectly
        pending.extend(owner(target) for target in targets)
    return frozenset(functions[i].name for i in seen), indirect


def shortest_sector_cycles(spec_path: str | Path) -> int:
    """CPU cycles (72 MHz) in the shortest 60 degree interval the spec allows."""
    spec = load_spec(spec_path)
    sc = scaling(spec, derive())
    return int(sc.period_min_ticks * CPU_HZ / spec.hall.timer_clock_hz)


def report(stats: Stats, sector_cycles: int | None = None) -> list[str]:
    hall, end, timing, _ = stats
    lines = []
    for s, target_i, target_c in (
        (hall, TARGET_HALL_INSTRUCTIONS, TARGET_HALL_CYCLES),
        (end, TARGET_END_INSTRUCTIONS, None),
    ):
        lines.append(
            f"{s.name}: {s.calls} calls; instructions worst {s.instructions_worst} mean"
            f" {s.instructions_mean:.1f} (target <= {target_i}); cycles worst {s.cycles_worst}"
            f" mean {s.cycles_mean:.1f} incl. 12 entry + 10 exit"
            + (f" (target <= {target_c})" if target_c else "")
        )
    lines.append(timing_line(timing, sector_cycles))
    return lines


def sector_share(cycles: int, sector_cycles: int | None) -> str:
    if not sector_cycles:
        return ""
    return (
        f", {100.0 * cycles / sector_cycles:.1f} % of the shortest 60 degree"
        f" interval ({sector_cycles} cycles)"
    )


def timing_line(timing: HandlerStats, sector_cycles: int | None = None) -> str:
    return (
        f"{timing.name}: {timing.calls} calls; instructions worst {timing.instructions_worst}"
        f" mean {timing.instructions_mean:.1f}; cycles worst {timing.cycles_worst} mean"
        f" {timing.cycles_mean:.1f}{sector_share(timing.cycles_worst, sector_cycles)}"
        " (no target: off the edge, preempted by it)"
    )


def meets_hall_targets(hall: HandlerStats) -> bool:
    return (
        hall.instructions_worst <= TARGET_HALL_INSTRUCTIONS
        and hall.cycles_worst <= TARGET_HALL_CYCLES
    )

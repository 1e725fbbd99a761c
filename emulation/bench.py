"""`make bench`: speed and size figures, measured, each printed with its target.

    python -m emulation [SPEC ...] [--only SECTIONS] [--quick] [--report-only] [--work DIR]

Every SPEC (default spec/paper_motor.yaml) is generated afresh into WORK/<name>/
(default build/bench/), built for the STM32F103 and measured:

* size: the whole image's flash against `firmware.flash_budget` and its RAM with the
  worst stack (-fcallgraph-info, every preemption level) against `firmware.ram_budget`
  (issue 12: 8 KiB and 512 B for the paper method), and flash by part;
* handlers: the port's interrupt handlers in unicorn over all Hall codes, both
  directions and a sweep of speed, bus voltage, current and duty
  (emulation/isr_bench.py), priced by the cycle model of emulation/cycles.py and
  emulation/memory.py (flash wait states, prefetch buffer; its assumptions are
  printed): the Hall edge (120 cycles, entry and exit included), the commutation end,
  the timing handler on the cached bus state (150) and a bus change (the bus-change
  handler and the timing run it pends), the core's
  arithmetic inside it, the current-loop interrupt (`firmware.current_loop_budget`,
  150), the CPU load at the worst swept speed with every interrupt in it (the Hall
  edge, the commutation end, three timing runs at their worst path at that speed and a
  current-loop run every PWM period: `firmware.cpu_load_budget`, 25 %), the cycles from each fault
  handler's entry to the store that clears MOE, and the stack per handler (static from
  -fstack-usage, and measured);
* placement: the Hall edge handler built in SRAM instead of flash (faster, but its
  code and table do not fit the RAM budget);
* peers: the same outputs computed by sympy.ccode in float and double and by plain
  32-bit fixed point, on the same inputs, as cycle ratios, with their errors against
  the exact model (emulation/peers.py);
* rule: the spec with the resistance-aware rule (emulation/rule_bench.py);
* reciprocal: the bus reciprocal by divide or by table (emulation/reciprocal_bench.py);
* times: derive + audit from a cold start, regeneration, verify, the Unity tests under
  qemu and the simulation, wall time;
* pil: the linked firmware on the emulated STM32F103 braking the simulated motor
  (emulation/pil/braking.py, plant in the loop): wall time of 100 ms of motor time
  from the spec's braking start (issue 13: under 60 s); --quick runs 10 ms and scales.

Exit status: 0 when every figure meets its target, 1 when one misses (0 with
--report-only), 2 for a bad spec or usage. --quick shrinks the sweeps (the bench's own
tests use it); its figures are not the headline ones.
"""

from __future__ import annotations

import argparse
import re
import statistics
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path

from codegen.argtypes import path_text
from codegen.build_firmware import ELF, MASKED, Sizes, budgets, build, linked_flash
from codegen.build_firmware import stack as stack_report
from codegen.core.module import build_core
from codegen.dead_time import COMMUTATION_END_ALLOWANCE_S, encode_dead_time
from codegen.derivation import derive
from codegen.errors import ExitCode, SpecError
from codegen.fixedpoint.scaling import scaling
from codegen.generate import generate
from codegen.methods.base import FixedPointError
from codegen.methods.paper_method import refused_time_bound
from codegen.publish import os_error_line
from codegen.render import PROJECT_ROOT
from codegen.spec_loader import load_spec
from codegen.spec_model import Spec
from codegen.spec_variant import spec_with_method, spec_with_time_target
from emulation import peers, progress, rule_bench
from emulation.armsim import load_elf
from emulation.figures import Figure, misses
from emulation.isr_bench import (
    ADC_HANDLER,
    BUS_CHANGE,
    BUS_HANDLER,
    CPU_HZ,
    HALL_HANDLER,
    TIMING_HANDLER,
    Stats,
    Sweep,
    bench,
    shortest_sector_cycles,
    sweep,
)
from emulation.memory import ASSUMPTIONS, STM32F103_72MHZ
from emulation.reciprocal_bench import ReciprocalChoice, table_option
from emulation.sections import SECTIONS, unknown_sections
from emulation.stack import EXCEPTION_FRAME_BYTES, read_frames, static_depth

DEFAULT_SPEC = "spec/paper_motor.yaml"
DEFAULT_WORK = Path("build") / "bench"

HALL_TARGET_CYCLES = 120
HALL_TARGET_INSTRUCTIONS = 64
TIMING_TARGET_CYCLES = 150
#: Issue 17: the arithmetic of a commutation at most as costly as plain fixed point.
PEER_RATIO_TARGET = 1.0
RUNS = 5
TARGET_DERIVE_AUDIT_S = 3.0
TARGET_REGENERATE_WARM_S = 2.0
TARGET_VERIFY_S = 10.0
TARGET_QEMU_S = 60.0
TARGET_SIMULATE_S = 60.0
#: Issue 13: 100 ms of motor time with the plant in the loop in under 60 s (2 cores)
PIL_MOTOR_S = 0.1
TARGET_PIL_S = 60.0
#: Defines that build the Hall edge handler in SRAM (the placement comparison).
IN_SRAM = ("BLDC_PORT_HALL_EDGE_IN_SRAM=1",)


@dataclass
class Report:
    """What one spec's bench printed: figures with targets, and lines of context."""

    spec: Spec
    figures: list[Figure] = field(default_factory=list)
    lines: list[str] = field(default_factory=list)

    def add(self, *figures: Figure) -> None:
        self.figures.extend(figures)
        for figure in figures:
            print(f"bench: {figure.line()}", flush=True)

    def say(self, *lines: str) -> None:
        self.lines.extend(lines)
        for line in lines:
            print(f"bench: {line}", flush=True)


@dataclass(frozen=True)
class Bench:
    """One spec prepared for measuring: generated and built under `work`."""

    spec_path: Path
    spec: Spec
    work: Path
    quick: bool

    @property
    def generated(self) -> Path:
        return self.work / "generated"

    @property
    def build_dir(self) -> Path:
        return self.work / "firmware"

    def inputs(self) -> Sweep:
        full = sweep(self.spec, scaling(self.spec, derive()))
        if not self.quick:
            return full
        return replace(
            full,
            periods=(full.periods[0], full.periods[-1]),
            buses=(full.buses[0], full.buses[-1]),
            currents=(full.currents[-1],),
            duties=(full.duties[1],),
        )


def prepare(spec_path: Path, work_root: Path, quick: bool) -> Bench:
    spec = load_spec(spec_path)
    work = work_root / spec.name
    generate(spec_path, work / "generated", PROJECT_ROOT)
    return Bench(spec_path, spec, work, quick)


# ------------------------------------------------------------------ sections


def section_size(b: Bench, report: Report) -> dict[str, Sizes]:
    sizes = build(b.generated, b.build_dir)
    fw = b.spec.firmware
    stack = stack_report(b.build_dir, fw.integration == "cube")
    flash, ram = budgets(sizes, stack, fw.flash_budget_bytes, fw.ram_budget_bytes)
    image = sizes[ELF]
    # The link script places .RamFunc inside .data: the objects name it.
    ram_code = sum(sizes[name].ram_code for name in sizes if name != ELF)
    linked = linked_flash(b.build_dir)
    parts = ", ".join(f"{name} {linked.get(name, 0)}" for name in sizes if name != ELF)
    report.add(
        Figure(
            "image flash",
            float(flash.value or 0),
            "B",
            flash.limit,
            f"by part, as linked: {parts} (alignment padding apart)",
        ),
        Figure(
            "image RAM with the worst stack",
            float("nan") if ram.value is None else ram.value,
            "B",
            ram.limit,
            f"variables {image.ram - ram_code}, code and tables run from SRAM {ram_code},"
            f" stack {stack.worst} ({'; '.join(stack.lines())})",
        ),
        Figure(
            "core + port flash",
            linked.get("core", 0) + linked.get("port", 0),
            "B",
            detail="as linked (what --gc-sections kept; the port compiles the core's text in"
            " where it inlines the timing)",
        ),
        Figure(
            "current loop flash",
            sizes["loop"].flash,
            "B",
            detail="bldc_current_reference(); the PI is inline",
        ),
    )
    return sizes


def _share(cycles: int, sector: int) -> str:
    return f"{100.0 * cycles / sector:.2f} % of the shortest 60 degree interval ({sector} cycles)"


def _stack_figures(b: Bench, stats: Stats) -> list[Figure]:
    image = load_elf(b.build_dir / "firmware.elf")
    frames = read_frames(b.build_dir)
    measured = {
        HALL_HANDLER: max(stats.hall.stack_bytes, stats.end.stack_bytes),
        ADC_HANDLER: stats.current_loop.stack_bytes,
        TIMING_HANDLER: stats.timing.stack_bytes if stats.timing is not None else 0,
        # a bus change: the deeper of its two handlers, the bus-change one
        BUS_HANDLER: stats.timing_bus.stack_bytes if stats.timing_bus is not None else 0,
    }
    figures = []
    totals: dict[str, int] = {}
    for handler in (HALL_HANDLER, ADC_HANDLER, TIMING_HANDLER, BUS_HANDLER, "main"):
        depth = static_depth(image, frames, handler)
        frame = 0 if handler == "main" else EXCEPTION_FRAME_BYTES
        if depth.bytes is None:
            figures.append(
                Figure(
                    f"stack {handler} (static)",
                    float("nan"),
                    "B",
                    detail=f"unknown: no bounded frame for {', '.join(depth.missing)}",
                )
            )
            continue
        totals[handler] = depth.bytes + frame
        detail = f"{' > '.join(depth.path)}"
        if handler != "main":
            over = (
                " over the whole bus change (the timing run it pends, after it, included)"
                if handler == BUS_HANDLER
                else ""
            )
            detail = (
                f"{detail} + {EXCEPTION_FRAME_BYTES} B exception frame; measured"
                f" {measured[handler] + EXCEPTION_FRAME_BYTES} B{over}"
            )
        figures.append(Figure(f"stack {handler} (static)", depth.bytes + frame, "B", detail=detail))
    open_main = static_depth(image, frames, "main", skip=frozenset(MASKED))
    faults = [static_depth(image, frames, h) for h in ("NMI_Handler", "HardFault_Handler")]
    fault_level = max(
        (d.bytes + EXCEPTION_FRAME_BYTES for d in faults if d.bytes is not None), default=0
    )
    if len(totals) == 5 and open_main.bytes is not None:
        # thread mode's interrupts-masked calls (the port's start-up) stack alone: no
        # handler preempts them (the figure had added them under the handlers: 424 B
        # where make firmware's -fcallgraph-info nesting gives 380 B)
        nested = (
            open_main.bytes
            + max(totals[TIMING_HANDLER], totals[BUS_HANDLER])
            + max(totals[HALL_HANDLER], totals[ADC_HANDLER])
            + fault_level
        )
        worst = max(nested, totals["main"])
        figures.append(
            Figure(
                "stack worst case (main, preempted by the timing or the bus change, preempted by the Hall edge or"
                " the current loop, preempted by the NMI or a HardFault), from the disassembly",
                worst,
                "B",
                detail=f"{' > '.join(open_main.path)} {open_main.bytes} B with interrupts open +"
                f" {max(totals[TIMING_HANDLER], totals[BUS_HANDLER])} +"
                f" {max(totals[HALL_HANDLER], totals[ADC_HANDLER])} + {fault_level} B, or main's"
                f" interrupts-masked start-up alone, {totals['main']} B: the same nesting as"
                " make firmware's -fcallgraph-info figure, found from the image instead of the"
                " compiler's graph",
            )
        )
    return figures


def _end_guard_figure(b: Bench, stats: Stats, wait: int) -> Figure:
    """The allowance in the commutation end guard (`codegen.dead_time`): how much later
    the end's switch-off can follow its TIM3 match than the next Hall edge's switch-on
    follows that edge, both at their COM event (the TIM1 EGR write), with a handler of
    the same priority ahead of the end; plus what the DTG code adds to the dead time."""
    sc = scaling(b.spec, derive())
    dead = encode_dead_time(b.spec.inverter.dead_time_s, b.spec.inverter.timer_clock_hz)
    rounding_us = float(dead.programmed_s - dead.requested_s) * 1e6
    lag = wait + stats.end_switch_worst - stats.edge_switch_best
    lag_us = lag / 72.0 + rounding_us
    return Figure(
        "commutation end's switch-off lag past the Hall edge's switch-on lag, worst",
        lag_us,
        "us",
        target=float(COMMUTATION_END_ALLOWANCE_S) * 1e6,
        decimals=2,
        detail=f"a handler of the same priority ahead ({wait} cycles) + the end's entry to its"
        f" COM event ({stats.end_switch_worst}) - the edge's shortest ({stats.edge_switch_best})"
        f" + the DTG code's rounding up ({rounding_us:.3f} us): the allowance a commutation"
        f" ends by, with the dead time, before its sector does"
        f" (BLDC_COMMUTATION_GUARD_TICKS = {sc.commutation_guard_ticks} Hall ticks)",
    )


def _fault_figures(b: Bench, stats: Stats) -> list[Figure]:
    """Each fault path's handler from its entry to the store that clears MOE, and the
    time from the fault to that store derived from how each is detected."""
    period_us = 1e6 / float(b.spec.inverter.pwm_frequency_hz)
    sample = float(b.spec.sensing.adc_sample_cycles)
    regular_us = (sample + 12.5) / 12.0  # one regular conversion of the bus at 12 MHz
    # a handler of the same priority ahead: the Hall edge, the current loop, or the Hall
    # lines' EXTI waiting out its confirmation (rare: a glitch or an unplug)
    wait_end = max(
        stats.hall.cycles_worst,
        stats.current_loop.cycles_worst,
        *(s.cycles_worst for n, s in stats.fault_paths.items() if "EXTI" in n),
    )
    # ... and ahead of a fault's handler, a refused Hall edge too (rare: a reversal), the
    # longest of them once the refusal's short circuit waits out the dead time (250
    # cycles on the paper motor). Not ahead of a commutation end: the TIM3 handler takes
    # a pending end first, and a refusal drops the commutation running or starts its own.
    refused = stats.hall_refused.cycles_worst if stats.hall_refused is not None else 0
    wait = max(wait_end, refused)
    figures = []
    worst: tuple[float, str, str] | None = None  # (us, fault, how it adds up)
    for name, cycles in stats.fault_to_moe.items():
        if "watchdog" in name and "ADC2" not in name:
            detect, how = 2 * regular_us, f"two regular bus conversions ({2 * regular_us:.1f} us)"
        elif name.startswith("current sensor") and "ADC2" in name:
            detect = len(b.spec.sensing.current_channels) * regular_us
            how = (
                f"ADC2's next conversion of the channel(s), continuously ({detect:.1f} us: the"
                " sequence of current channels)"
            )
        elif "EXTI" in name:
            detect, how = (
                0.0,
                "at the line's edge (the EXTI); the handler waits out the confirmation",
            )
        elif name.startswith("Hall timeout") and "CC3" in name:
            detect, how = 0.0, "at the time-out's compare match itself (TIM3's CC3 interrupt)"
        elif name.startswith("Hall timeout"):
            detect, how = 0.0, "at the wrap itself (TIM3's update interrupt)"
        elif name.startswith("over-current"):
            detect, how = 0.0, "none: BKIN clears MOE in hardware; this completes the third phase"
        else:
            detect, how = 0.0, "at the Hall edge itself (after the 8-sample input filter)"
        total_us = detect + (wait + cycles) / 72.0
        if worst is None or total_us > worst[0]:
            worst = (
                total_us,
                name,
                f"detection {detect:.2f} us + a handler of the same priority ahead"
                f" ({wait} cycles) + its own path to MOE = 0 ({cycles} cycles)",
            )
        figures.append(
            Figure(
                f"fault {name}: handler entry to MOE cleared",
                cycles,
                "cycles",
                detail=f"detection: {how}; worst to the safe state {total_us:.2f} us with a"
                f" handler of the same priority ({wait} cycles) ahead of it; the PWM period is"
                f" {period_us:.1f} us",
            )
        )
    figures.append(_end_guard_figure(b, stats, wait_end))
    if worst is not None:
        figures.append(
            Figure(
                "fault to the safe state, worst of every fault",
                worst[0],
                "us",
                target=period_us,
                decimals=2,
                detail=f"{worst[1]}: {worst[2]}; the target is one PWM period"
                f" ({float(b.spec.inverter.pwm_frequency_hz) / 1000:g} kHz)",
            )
        )
    return figures


def section_handlers(b: Bench, report: Report) -> Stats:
    report.say(f"cycle model: {STM32F103_72MHZ.describe()}")
    report.say(*(f"  assumes: {a}" for a in ASSUMPTIONS))
    inputs = b.inputs()
    stats = bench(b.spec_path, b.generated, b.build_dir, inputs)
    sector = shortest_sector_cycles(b.spec_path)
    report.say(f"inputs: {inputs.describe()}, all Hall codes both ways, safe-state paths")
    hall, end = stats.hall, stats.end
    lines = stats.hall_lines
    report.add(
        Figure(
            "Hall edge (TIM3 CC1) worst",
            hall.cycles_worst,
            "cycles",
            HALL_TARGET_CYCLES,
            f"entry and exit included; mean {hall.cycles_mean:.1f}; {hall.calls} edges that"
            " commutate; handler in flash",
        ),
        Figure(
            "Hall edge instructions worst",
            hall.instructions_worst,
            "",
            HALL_TARGET_INSTRUCTIONS,
        ),
        Figure(
            "commutation end (TIM3 CC2) worst",
            end.cycles_worst,
            "cycles",
            detail=f"{end.instructions_worst} instructions",
        ),
    )
    if stats.hall_refused is not None:
        report.add(
            Figure(
                "Hall edge refused (a reversal: all-off or the short, no fault) worst",
                stats.hall_refused.cycles_worst,
                "cycles",
                detail=f"{stats.hall_refused.calls} edges; rare (the rotor reverses at standstill)",
            )
        )
    report.add(
        Figure(
            "Hall lines' EXTI (every Hall edge, a valid code) worst",
            lines.cycles_worst,
            "cycles",
            detail=f"{lines.instructions_worst} instructions; runs at the Hall edge's level"
            " just before it, so it delays the Hall edge's handler by as much",
        )
    )
    loop = stats.current_loop
    loop_budget = b.spec.firmware.current_loop_budget_cycles
    report.add(
        Figure(
            "current loop (ADC1_2 JEOC) worst",
            loop.cycles_worst,
            "cycles",
            loop_budget,
            f"entry and exit included; mean {loop.cycles_mean:.1f}; {loop.calls} runs in the"
            f" closed loop, the bus-moved path included; {loop.instructions_worst} instructions",
        )
    )
    timing_target = (
        rule_bench.TIMING_TARGET_CYCLES
        if b.spec.controller.method == rule_bench.METHOD
        else TIMING_TARGET_CYCLES
    )
    if stats.timing is not None:
        report.add(
            Figure(
                f"{TIMING_HANDLER} worst, bus state cached",
                stats.timing.cycles_worst,
                "cycles",
                timing_target,
                f"mean {stats.timing.cycles_mean:.1f}; {stats.timing.calls} runs",
            )
        )
    if stats.timing_bus is not None:
        report.add(
            Figure(
                f"{BUS_CHANGE} worst",
                stats.timing_bus.cycles_worst,
                "cycles",
                detail=f"{stats.timing_bus.calls} changes, both handlers' entry and exit"
                " included; in the CPU-load budget below",
            )
        )
    bus_text = f"{stats.core_bus.cycles_worst}" if stats.core_bus else "not run"
    if stats.core_timing is not None:
        core = stats.core_timing.cycles_worst + (
            stats.core_bus.cycles_worst if stats.core_bus else 0
        )
        report.add(
            Figure(
                "core arithmetic of one commutation worst (bldc_bus_condition +"
                " bldc_commutation_timing, no entry or exit)",
                core,
                "cycles",
                detail=f"bldc_commutation_timing {stats.core_timing.cycles_worst},"
                f" bldc_bus_condition {bus_text}",
            )
        )
    else:
        report.say(
            "core arithmetic: bldc_commutation_timing() is inlined into the timing handler"
            f" (its figure above includes it); bldc_bus_condition {bus_text} cycles on a bus"
            " change"
        )
    report.add(_cpu_load(b, stats, sector))
    if stats.timing is not None:
        cached = (
            hall.cycles_worst
            + lines.cycles_worst
            + end.cycles_worst
            + 3 * stats.timing.cycles_worst
        )
        report.add(
            Figure(
                "CPU load of the commutation alone, bus state cached",
                100.0 * cached / sector,
                "%",
                detail=f"the Hall edge, its EXTI, the end and three timing runs on the cached bus state:"
                f" {cached} cycles",
                decimals=2,
            )
        )
    report.add(*_fault_figures(b, stats))
    report.add(*_stack_figures(b, stats))
    report.say(
        "peripheral register accesses per run (APB wait states not priced): Hall edge"
        f" {hall.peripheral_accesses}, commutation end {end.peripheral_accesses}, timing"
        f" {stats.timing_worst.peripheral_accesses}"
    )
    return stats


def bus_min_periods(generated: Path) -> int:
    """The port's gate on bus changes as built: PWM periods from one to the next."""
    header = (generated / "c" / "stm32f103_port.h").read_text(encoding="utf-8")
    found = re.search(r"^#define BLDC_PORT_BUS_MIN_PERIODS (\d+)u$", header, re.M)
    if found is None:
        raise ValueError(f"{generated}: the port header defines no BLDC_PORT_BUS_MIN_PERIODS")
    return int(found.group(1))


def _cpu_load(b: Bench, stats: Stats, sector: int) -> Figure:
    """The CPU load of every interrupt over one sector, at the worst speed of the sweep.

    At each swept period T_i the sector holds the Hall edge, its EXTI, the commutation
    end, two timing runs (after the edge, after the end), the bus changes a bus sample
    may pend through the bus-change handler (one per BLDC_PORT_BUS_MIN_PERIODS PWM
    periods at most, the port's gate, which a noisy or rippling bus reaches; rounded
    up, so at least one) and one current-loop run per PWM period. The timing runs are
    priced at the worst of a cached run and a whole bus change (both handlers) measured
    at T_i or at the next swept period, and the sector at T_i:
    an upper bound for every speed between the two, as far as the sweep's runs are the
    worst. The improved_r search runs more steps the longer the sector, so pricing its
    slowest run against the shortest sector, as the bound over all speeds at once does,
    overstates the load at every speed.
    """
    hall, lines, end, loop = stats.hall, stats.hall_lines, stats.end, stats.current_loop
    gate = bus_min_periods(b.generated)
    fixed = hall.cycles_worst + lines.cycles_worst + end.cycles_worst
    pwm_hz = int(b.spec.inverter.pwm_frequency_hz)
    clock = int(b.spec.hall.timer_clock_hz)
    by_period = list(stats.timing_by_period)
    shortest_ticks = sector * clock // CPU_HZ
    if not by_period or by_period[0][0] > shortest_ticks + 1:
        # no run at the top speed: every speed priced at the slowest run
        by_period = [(shortest_ticks, stats.timing_worst.cycles_worst)]
    worst: tuple[float, int, int, int, int, int] | None = None
    for index, (ticks, cycles) in enumerate(by_period):
        timing = max(cycles, by_period[index + 1][1]) if index + 1 < len(by_period) else cycles
        cycles_in_sector = sector if index == 0 else ticks * CPU_HZ // clock
        periods = -(-pwm_hz * cycles_in_sector // CPU_HZ)  # PWM periods per sector, up
        changes = -(-periods // gate)
        load = fixed + (2 + changes) * timing + periods * loop.cycles_worst
        share = 100.0 * load / cycles_in_sector
        if worst is None or share > worst[0]:
            worst = (share, ticks, cycles_in_sector, timing, periods, load, changes)
    assert worst is not None
    share, ticks, cycles_in_sector, timing, periods, load, changes = worst
    rpm = 60.0 * clock / (6 * ticks * b.spec.motor.pole_pairs)
    return Figure(
        "CPU load at the worst speed, every interrupt",
        share,
        "%",
        float(b.spec.firmware.cpu_load_budget_percent),
        detail=f"at {rpm:.0f} rpm (a {ticks}-tick sector; the worst of {len(by_period)} swept"
        f" speeds, the top one {by_period[0][0]} ticks): Hall edge {hall.cycles_worst} + its"
        f" EXTI {lines.cycles_worst} + end {end.cycles_worst} + {2 + changes} timing runs"
        f" (after the edge, after the end, {changes} a bus sample pends: one per {gate} PWM"
        " periods at most) at the worst of a cached run and a"
        f" bus change (both handlers) at this speed or the next swept one, {timing} + {periods} current-loop runs (one per"
        f" PWM period) at {loop.cycles_worst} = {load} cycles of {cycles_in_sector}",
        decimals=2,
    )


def section_placement(b: Bench, report: Report, in_flash: Stats | None) -> None:
    inputs = b.inputs()
    if not b.quick:
        inputs = replace(inputs, periods=(inputs.periods[0], inputs.periods[-1]))
    sram_dir = b.work / "firmware-hall-in-sram"
    in_sram = bench(b.spec_path, b.generated, sram_dir, inputs, defines=IN_SRAM)
    flash = in_flash or bench(b.spec_path, b.generated, b.build_dir, inputs)
    sizes = build(b.generated, sram_dir, defines=IN_SRAM)
    ram_code = sum(sizes[name].ram_code for name in sizes if name != ELF)
    report.add(
        Figure(
            "Hall edge from flash (the port's default) minus from SRAM",
            flash.hall.cycles_worst - in_sram.hall.cycles_worst,
            "cycles",
            detail=f"worst {flash.hall.cycles_worst} in flash, {in_sram.hall.cycles_worst} in"
            f" SRAM (BLDC_PORT_HALL_EDGE_IN_SRAM=1), which puts {ram_code} B of code"
            f" and table in RAM; commutation end {flash.end.cycles_worst} vs"
            f" {in_sram.end.cycles_worst}",
        )
    )


def _closed_form_spec(b: Bench) -> tuple[Spec, Path, str | None]:
    """The spec the peers run on, its generated core, and the time target (Hall ticks)
    it was generated for where the spec's own is out of its reach: the spec itself, or
    the same motor with the paper's improved rule for improved_r (at the spec's Hall
    clock its X may keep too few bits for the spec's time target where the time is well
    conditioned: then the bound it meets, as `simulate` does)."""
    if b.spec.controller.method in peers.CLOSED_FORM:
        return b.spec, b.generated, None
    folder = b.work / "peers-spec"
    folder.mkdir(parents=True, exist_ok=True)
    name = f"{b.spec.name}_improved"[:64]
    path = folder / f"{name}.yaml"
    text = spec_with_method(b.spec_path.read_text(encoding="utf-8"), "improved", name)
    path.write_text(text, encoding="utf-8")
    held = None
    try:
        generate(path, folder / "generated", PROJECT_ROOT)
    except FixedPointError as error:
        bound = refused_time_bound(str(error))
        if bound is None:
            raise
        held = f"{float(bound):.2f}"
        path.write_text(spec_with_time_target(text, held), encoding="utf-8")
        generate(path, folder / "generated", PROJECT_ROOT)
    return load_spec(path), folder / "generated", held


def section_peers(b: Bench, report: Report) -> None:
    spec, generated, held = _closed_form_spec(b)
    full = sweep(spec, scaling(spec, derive()), 2 if b.quick else 6)
    duties = full.duties if spec.controller.method != "improved" else full.duties[1:2]
    if b.quick:
        full = replace(full, buses=full.buses[::2], currents=full.currents[1:])
        duties = duties[-1:]
    points = peers.points(full.buses, full.periods, full.currents, duties)
    if spec is not b.spec:
        report.say(
            f"peers on {spec.name} (the paper's improved rule: {b.spec.name} has no closed form)"
            + (
                ""
                if held is None
                else f", generated for {held} Hall ticks of commutation time, the bound its"
                " design meets at this Hall clock"
            )
        )
    results = peers.run(spec, generated, b.work / "peers", points)
    ours = results[0]
    plain = next(r for r in results if r.name == "plain fixed point")
    report.say(f"peers: {len(points)} points, same emulator and cycle model, functions in flash")
    for r in results:
        ratio = r.cycles_worst / ours.cycles_worst
        bus = f", of which bldc_bus_condition {r.bus_part_worst}" if r.bus_part_worst else ""
        report.add(
            Figure(
                f"arithmetic {r.name} worst",
                r.cycles_worst,
                "cycles",
                detail=f"{ratio:.2f} x ours; mean {r.cycles_mean:.0f}{bus}; {r.flash_bytes} B of"
                f" code; error vs the exact model: duties {r.duty_error:.3f} counts, t_com"
                f" {r.time_error:.3f} ticks (where Eq. 20 ends by the latest end L(T))",
            )
        )
    cached = ours.cached
    assert cached is not None  # peers.run measures ours both ways
    report.add(
        Figure(
            "arithmetic ours worst, bus state cached",
            cached.cycles_worst,
            "cycles",
            detail="bldc_commutation_timing() alone per point, inlined into its caller as in"
            " the port's timing handler; bldc_bus_condition() run beforehand and not counted"
            f" (the port runs it on a bus change only); mean {cached.cycles_mean:.0f}; the"
            " same outputs as computed afresh",
        ),
        Figure(
            "ours (bus state cached) / plain fixed point (all its work every run)",
            cached.cycles_worst / plain.cycles_worst,
            "x",
            PEER_RATIO_TARGET,
            f"ours {cached.cycles_worst} cycles on the cached bus state, plain"
            f" {plain.cycles_worst} (its two bus divides included, every run); ours computed"
            f" afresh {ours.cycles_worst} (bus part {ours.bus_part_worst}) is"
            f" {ours.cycles_worst / plain.cycles_worst:.2f} x",
            decimals=2,
        ),
    )


def section_rule(b: Bench, report: Report) -> None:
    started = time.perf_counter()
    try:
        rule = rule_bench.run(b.spec_path, b.work / "rule", quick=b.quick)
    except (FixedPointError, SpecError) as error:
        if b.spec.controller.method == rule_bench.METHOD:
            raise  # the spec's own firmware: the design refusal is the spec's error
        # a copy for comparison, which the rule's integer design (or the loader, for a
        # value only the rule's copy is held to) cannot take on this motor: nothing to
        # measure, and the spec's own firmware is unaffected
        report.say(
            f"{rule_bench.METHOD}: not measured: its copy of this motor cannot be designed"
            f" ({' '.join(str(error).split())})"
        )
        return
    report.add(*rule.figures())
    report.say(*rule.lines())
    report.say(
        f"{rule_bench.METHOD} generate + build + measure {time.perf_counter() - started:.1f} s"
    )


def section_reciprocal(b: Bench, report: Report, sizes: dict[str, Sizes], stats: Stats) -> None:
    bus = stats.core_bus
    if bus is None:
        report.say("bus reciprocal: no bldc_bus_condition run measured")
        return
    core = build_core(b.spec)
    needed = ("x_frac_bits", "n_x", "n_g", "time_bound_min_w_counts")
    if any(key not in core.design.formats for key in needed):
        report.say(
            f"bus reciprocal: no table option for method {core.design.method}"
            " (only the paper's methods' X and Eq. 20 numerators are tabulated)"
        )
        return
    choice = ReciprocalChoice(
        table=table_option(b.spec, core),
        divide_instructions=bus.instructions_worst,
        divide_cycles=bus.cycles_worst,
        flash_in_use=sum(linked_flash(b.build_dir).get(part, 0) for part in ("core", "port")),
    )
    report.say(*choice.lines())


@dataclass(frozen=True)
class Timed:
    """A command's wall time, or why it failed: a failed run is a miss (infinite
    seconds) with its exit status and last line of stderr, never a traceback."""

    seconds: float
    failure: str = ""


def _seconds(command: Sequence[str]) -> Timed:
    started = time.perf_counter()
    run = subprocess.run(command, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    if run.returncode != 0:
        lines = run.stderr.strip().splitlines()
        last = lines[-1] if lines else "no output"
        return Timed(float("inf"), f"FAILED (exit {run.returncode}): {last}")
    return Timed(time.perf_counter() - started)


def section_times(b: Bench, report: Report) -> None:
    python = sys.executable
    spec = str(b.spec_path)
    with tempfile.TemporaryDirectory() as out:
        runs = [_seconds([python, "-m", "codegen", "audit", spec, "-o", out]) for _ in range(RUNS)]
    cold = [r.seconds for r in runs]
    failed = next((r.failure for r in runs if r.failure), "")
    report.add(
        Figure(
            "derive + audit, cold start, median",
            float("inf") if failed else statistics.median(cold),
            "s",
            TARGET_DERIVE_AUDIT_S,
            failed or f"{RUNS} runs, min {min(cold):.2f} s",
            decimals=2,
        )
    )
    from codegen.generate import render_all

    render_all(spec)
    warm = []
    for _ in range(RUNS):
        started = time.perf_counter()
        render_all(spec)
        warm.append(time.perf_counter() - started)
    report.add(
        Figure(
            "regenerate, warm, median",
            statistics.median(warm),
            "s",
            TARGET_REGENERATE_WARM_S,
            decimals=2,
        )
    )
    verified = _seconds(
        [python, "-m", "verify", spec, "--generated", str(b.generated), "--no-progress"]
    )
    report.add(
        Figure(
            "verify (exhaustive + random + boundary, host)",
            verified.seconds,
            "s",
            TARGET_VERIFY_S,
            verified.failure,
            decimals=1,
        )
    )
    from verify.unity_run import run_qemu

    started = time.perf_counter()
    with tempfile.TemporaryDirectory() as qemu_build:
        run = run_qemu(b.generated, Path(qemu_build))
    seconds = time.perf_counter() - started
    report.add(
        Figure(
            "Unity tests on the emulated Cortex-M3 (build + qemu run)",
            seconds if run.passed else float("inf"),
            "s",
            TARGET_QEMU_S,
            f"{len(run.results)} tests, {'pass' if run.passed else 'FAIL'}",
            decimals=1,
        )
    )
    with tempfile.TemporaryDirectory() as sim_out:
        simulated = _seconds([python, "-m", "sim", spec, "-o", sim_out, "--no-progress"])
    report.add(
        Figure(
            "simulate (sweep, optimum, figures, report)",
            simulated.seconds,
            "s",
            TARGET_SIMULATE_S,
            simulated.failure,
            decimals=1,
        )
    )


def section_pil(b: Bench, report: Report) -> None:
    from emulation.pil.braking import BrakingLoop, braking_setup
    from emulation.pil.build import ToolError, build_firmware
    from emulation.pil.bus import PilError
    from emulation.pil.iwdg import WatchdogResetError

    motor_s = PIL_MOTOR_S / 10 if b.quick else PIL_MOTOR_S
    name = f"PIL: {PIL_MOTOR_S * 1e3:.0f} ms of motor time, plant in the loop"
    try:
        # the bench's folders are relative to the working directory, and pil.build
        # reads a relative path from the project root (as `make pil` runs)
        elf = build_firmware(
            b.spec_path.resolve(), (b.work / "pil").resolve(), b.generated.resolve()
        )
    except ToolError as error:  # e.g. the image over its RAM budget: a miss, its reason
        report.add(Figure(name, float("inf"), "s", TARGET_PIL_S, f"not run: {error}", 1))
        return
    setup = replace(
        braking_setup(b.spec, short=False), max_seconds=motor_s, stop_rpm=0.0, trace_seconds=0.0
    )
    started = time.perf_counter()
    try:
        loop = BrakingLoop(elf, b.generated / "c" / "stm32f103_port.c", b.spec, setup)
        result = loop.run_braking()
    except (PilError, WatchdogResetError, TimeoutError) as error:  # a miss, with its reason
        report.add(Figure(name, float("inf"), "s", TARGET_PIL_S, f"not run: {error}", 1))
        return
    seconds = time.perf_counter() - started
    emulated = result.emulated_s
    report.add(
        Figure(
            name,
            seconds * PIL_MOTOR_S / emulated,
            "s",
            TARGET_PIL_S,
            f"{emulated * 1e3:.1f} ms emulated in {seconds:.1f} s wall"
            f" ({emulated * 1e3 / seconds:.1f} ms per second, boot excluded)"
            + ("; --quick: scaled from the shorter run" if b.quick else "")
            + f"; from {setup.start_rpm:.0f} rpm at {setup.current_a:g} A,"
            f" {result.edges} Hall edges, invariants"
            f" {'kept' if not result.outcome.violations else 'BROKEN'}",
            decimals=1,
        )
    )


# ------------------------------------------------------------------ driver


def run_spec(b: Bench, sections: Sequence[str]) -> Report:
    report = Report(b.spec)
    report.say(
        f"spec {b.spec_path} ({b.spec.name}, method {b.spec.controller.method}), work {b.work}"
    )
    sizes = section_size(b, report) if "size" in sections or "reciprocal" in sections else None
    stats = None
    if "handlers" in sections or "reciprocal" in sections:
        stats = section_handlers(b, report)
    steps: dict[str, Callable[[], None]] = {
        "placement": lambda: section_placement(b, report, stats if not b.quick else None),
        "peers": lambda: section_peers(b, report),
        "rule": lambda: section_rule(b, report),
        "times": lambda: section_times(b, report),
    }
    for name in ("placement", "peers", "rule"):
        if name in sections:
            steps[name]()
    if "reciprocal" in sections and sizes is not None and stats is not None:
        section_reciprocal(b, report, sizes, stats)
    if "times" in sections:
        steps["times"]()
    if "pil" in sections:
        section_pil(b, report)
    return report


def parse(argv: Sequence[str]) -> argparse.Namespace:
    parser = argparse.ArgumentParser(
        prog="python -m emulation",
        description="Speed and size figures of the generated firmware, each with its target.",
    )
    parser.add_argument("specs", nargs="*", type=Path, help=f"spec files (default {DEFAULT_SPEC})")
    parser.add_argument(
        "--only",
        default=",".join(SECTIONS),
        help=f"comma-separated sections to run, of {', '.join(SECTIONS)} (default all)",
    )
    parser.add_argument(
        "--report-only",
        action="store_true",
        help="print the figures and exit 0 even when one misses its target",
    )
    parser.add_argument(
        "--quick",
        action="store_true",
        help="small sweeps: checks that the bench runs, not headline figures",
    )
    parser.add_argument(
        "--no-progress",
        action="store_true",
        help="no progress bars on stderr (they show only when stderr is a terminal)",
    )
    parser.add_argument(
        "--work",
        type=lambda text: Path(path_text(text)),
        default=DEFAULT_WORK,
        help=f"where each spec is generated and built (default {DEFAULT_WORK})",
    )
    args = parser.parse_args(argv)
    unknown = unknown_sections(args.only)
    if unknown:
        named = ", ".join(repr(s) if s else "'' (an empty name)" for s in sorted(unknown))
        parser.error(
            f"--only {args.only!r}: unknown section {named} (allowed: {', '.join(SECTIONS)})"
        )
    return args


def main(argv: Sequence[str] | None = None) -> int:
    args = parse(sys.argv[1:] if argv is None else argv)
    progress.enabled = sys.stderr.isatty() and not args.no_progress
    sections = args.only.split(",")
    missed: list[tuple[str, Figure]] = []
    for spec_path in args.specs or [Path(DEFAULT_SPEC)]:
        try:
            b = prepare(spec_path, args.work, args.quick)
        except SpecError as error:
            print(f"bench: {error}", file=sys.stderr)
            return int(ExitCode.SPEC)
        except FixedPointError as error:  # no design meets the spec: the key to change
            print(
                f"bench: {spec_path}: {error.key}: fixed-point design: {' '.join(str(error).split())}",
                file=sys.stderr,
            )
            return int(ExitCode.SPEC)
        except OSError as error:
            # the spec, or the work folder the firmware is generated and built under
            # (which had been blamed on the spec: "cannot read spec ...: Read-only")
            spec_file = error.filename is not None and Path(error.filename) == Path(spec_path)
            line = (
                f"cannot read spec {spec_path}: {error.strerror}"
                if spec_file
                else os_error_line(error).removeprefix("error: ")
            )
            print(f"bench: {line}", file=sys.stderr)
            return int(ExitCode.ENVIRONMENT)
        report = run_spec(b, sections)
        missed += [(b.spec.name, f) for f in misses(report.figures)]
    if missed:
        print(f"bench: {len(missed)} figure(s) MISS their targets:")
        for name, figure in missed:
            print(f"bench:   {name}: {figure.line()}")
        return 0 if args.report_only else 1
    print("bench: every figure meets its target")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

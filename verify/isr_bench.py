"""Instructions and estimated Cortex-M3 cycles of the port's interrupt handlers.

The firmware image that `make firmware` links is run in unicorn (verify.armsim). Each
Hall edge is staged the way the hardware presents it: the Hall pins in GPIO IDR, the
captured 60 degree interval in TIM3 CCR1, TIM3 SR.CC1IF set, and the ADC and duty
inputs filled (bldc_port_set_bus_voltage(), bldc_port_set_main_duty()); the commutation
end is SR.CC2IF. The timer and the NVIC are played by this module: when the Hall edge
writes TIM1 EGR.COMG with DIER.COMIE set (the COM event raises TIM1_TRG_COM), or a setter
sets the TIM1_TRG_COM pending bit in NVIC_ISPR0, the bench runs TIM1_TRG_COM_IRQHandler
(the next edge's timing, at the lower priority) before the commutation end. Register addresses and bit positions come from the vendor SVD, as in
the generated header. Edges run through all six Hall codes in both directions over a
sweep of speed, bus voltage, current and duty.
"""

from __future__ import annotations

import statistics
from dataclasses import dataclass
from pathlib import Path

from codegen.build_firmware import build
from codegen.derivation import derive
from codegen.fixedpoint.scaling import scaling
from codegen.port import port_context
from codegen.spec_loader import load_spec
from codegen.svd import load_device
from verify.armsim import CortexM3Sim, load_elf
from verify.cycles import estimate_cycles, isr_cycles

TARGET_HALL_INSTRUCTIONS = 64
TARGET_HALL_CYCLES = 120
TARGET_END_INSTRUCTIONS = 24
#: TIM1 trigger/COM: IRQ 26 on the STM32F103 (SVD TIM1_TRG_COM_TIM11).
TIMING_HANDLER = "TIM1_TRG_COM_IRQHandler"
CPU_HZ = 72_000_000


@dataclass(frozen=True)
class HandlerStats:
    name: str
    calls: int
    instructions_worst: int
    instructions_mean: float
    cycles_worst: int  # UDIV at 12 cycles, taken branches with a 3-cycle refill
    cycles_mean: float  # UDIV early-termination estimate


def _register(peripheral: str, register: str) -> int:
    p = load_device().peripheral(peripheral)
    (reg,) = [r for r in p.registers if r.name == register]
    return p.base_address + reg.address_offset


def _bit(peripheral: str, register: str, field: str) -> int:
    p = load_device().peripheral(peripheral)
    (reg,) = [r for r in p.registers if r.name == register]
    (f,) = [x for x in reg.fields if x.name == field]
    return 1 << f.bit_offset


def _stats(name: str, samples: list[tuple[int, int, int]]) -> HandlerStats:
    return HandlerStats(
        name=name,
        calls=len(samples),
        instructions_worst=max(s[0] for s in samples),
        instructions_mean=statistics.fmean(s[0] for s in samples),
        cycles_worst=max(s[1] for s in samples),
        cycles_mean=statistics.fmean(s[2] for s in samples),
    )


class NvicError(AssertionError):
    """The Hall edge did not raise the timing interrupt."""


Stats = tuple[HandlerStats, HandlerStats, HandlerStats, HandlerStats]


def bench(spec_path: str | Path, generated: Path, build_dir: Path) -> Stats:
    spec = load_spec(spec_path)
    sc = scaling(spec, derive())
    build(generated, build_dir)
    sim = CortexM3Sim(load_elf(build_dir / "firmware.elf"))
    sim.call("bldc_port_init")
    pins = port_context(spec)["hall_pins"]
    tim3_sr, tim3_ccr1, tim3_cnt = (_register("TIM3", r) for r in ("SR", "CCR1", "CNT"))
    cc1if, cc2if = _bit("TIM3", "SR", "CC1IF"), _bit("TIM3", "SR", "CC2IF")
    uif = _bit("TIM3", "SR", "UIF")
    ispr0 = _register("NVIC", "ISPR0")
    tim1_egr, tim1_dier = _register("TIM1", "EGR"), _register("TIM1", "DIER")
    comg, comie = _bit("TIM1", "EGR", "COMG"), _bit("TIM1", "DIER", "COMIE")
    (timing_irq,) = [
        i.value
        for i in load_device().peripheral("TIM1").interrupts
        if i.name.startswith("TIM1_TRG_COM")
    ]
    globals_ = {
        n: sim_symbol
        for n in ("bldc_adc_phase_current",)
        for sim_symbol in [sim.image.symbol(n).address]
    }
    periods = sorted(
        {
            sc.period_min_ticks,
            sc.period_max_ticks,
            *(
                round(sc.period_min_ticks * (sc.period_max_ticks / sc.period_min_ticks) ** (k / 11))
                for k in range(12)
            ),
        }
    )
    buses = (sc.bus_code_min, (sc.bus_code_min + sc.bus_code_max) // 2, sc.bus_code_max)
    currents = (
        sc.current_offset_code,
        sc.current_offset_code + sc.current_code_max // 2,
        sc.current_offset_code + sc.current_code_max,
    )
    duties = (0, sc.period_counts // 2, sc.period_counts)
    hall_edge: list[tuple[int, int, int]] = []
    timing: list[tuple[int, int, int]] = []
    bus_part: list[tuple[int, int, int]] = []
    bus_symbol = sim.image.symbol("bldc_bus_condition")
    commutation_end: list[tuple[int, int, int]] = []

    def stage_hall(code: int) -> None:
        levels = {"GPIOA": 0, "GPIOB": 0}
        for pin in pins:
            if code & int(str(pin["code_bit"]).rstrip("u"), 16):
                levels[str(pin["port"])] |= 1 << int(str(pin["n"]))
        for port, value in levels.items():
            sim.write_u32(_register(port, "IDR"), value)

    def nvic_pending() -> bool:
        pending = bool(sim.read_u32(ispr0) & (1 << timing_irq))
        sim.write_u32(ispr0, 0)
        return pending

    def com_event() -> bool:
        com = bool(sim.read_u32(tim1_egr) & comg) and bool(sim.read_u32(tim1_dier) & comie)
        sim.write_u32(tim1_egr, 0)
        return com

    def run(samples: list[tuple[int, int, int]], handler: str = "TIM3_IRQHandler") -> None:
        result = sim.call(handler)
        if handler == TIMING_HANDLER:
            inside = [
                s
                for s in result.trace
                if bus_symbol.address <= s.address < bus_symbol.address + bus_symbol.size
            ]
            bus_part.append(
                (
                    len(inside),
                    estimate_cycles(inside, sim, udiv_mode="worst").cycles,
                    estimate_cycles(inside, sim, udiv_mode="estimate").cycles,
                )
            )
        worst = isr_cycles(estimate_cycles(result.trace, sim, udiv_mode="worst"))
        typical = isr_cycles(estimate_cycles(result.trace, sim, udiv_mode="estimate"))
        samples.append((result.instructions, worst, typical))

    for direction in (1, -1):
        sequence = spec.hall.sequence if direction > 0 else tuple(reversed(spec.hall.sequence))
        for period in periods:
            for bus in buses:
                for current in currents:
                    for duty in duties:
                        sim.call("bldc_port_set_bus_voltage", args=(bus,))
                        sim.write_u16(globals_["bldc_adc_phase_current"], current)
                        sim.call("bldc_port_set_main_duty", args=(duty,))
                        if nvic_pending():
                            sim.call(TIMING_HANDLER)
                        for code in sequence:
                            stage_hall(code)
                            sim.write_u32(tim3_ccr1, period)
                            sim.write_u32(tim3_cnt, 0)
                            # The slowest period also as a Hall timeout (the counter wrapped).
                            timeout = uif if period == periods[-1] else 0
                            sim.write_u32(tim3_sr, cc1if | timeout)
                            sim.write_u32(tim1_egr, 0)
                            run(hall_edge)
                            if not com_event():
                                raise NvicError("the Hall edge raised no COM event")
                            run(timing, TIMING_HANDLER)
                            sim.write_u32(tim3_sr, cc2if)
                            run(commutation_end)
    # The safe-state paths: an invalid code (000, 111) from a valid one, and back.
    for code in (7, spec.hall.sequence[0], 0, spec.hall.sequence[0]):
        stage_hall(code)
        sim.write_u32(tim3_ccr1, periods[0])
        sim.write_u32(tim3_sr, cc1if)
        sim.write_u32(tim1_egr, 0)
        run(hall_edge)
        if not com_event():
            raise NvicError("the Hall edge raised no COM event")
        run(timing, TIMING_HANDLER)
    return (
        _stats("Hall edge (TIM3 CC1)", hall_edge),
        _stats("commutation end (TIM3 CC2)", commutation_end),
        _stats("next edge's timing (TIM1_TRG_COM, low priority)", timing),
        _stats("bldc_bus_condition() inside it", bus_part),
    )


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
    share = (
        f", {100.0 * timing.cycles_worst / sector_cycles:.1f} % of the shortest 60 degree"
        f" interval ({sector_cycles} cycles)"
        if sector_cycles
        else ""
    )
    lines.append(
        f"{timing.name}: {timing.calls} calls; instructions worst {timing.instructions_worst}"
        f" mean {timing.instructions_mean:.1f}; cycles worst {timing.cycles_worst} mean"
        f" {timing.cycles_mean:.1f}{share} (no target: off the edge, preempted by it)"
    )
    return lines

"""Instructions and estimated Cortex-M3 cycles of the two interrupt handlers.

The firmware image that `make firmware` links is run in unicorn (verify.armsim). Each
Hall edge is staged the way the hardware presents it: the Hall pins in GPIO IDR, the
captured 60 degree interval in TIM3 CCR1, TIM3 SR.CC1IF set, and the ADC and duty
globals filled (the bus voltage through bldc_port_set_bus_voltage(), whose cost is
reported separately: it runs when the bus is sampled, not at the edge); the
commutation end is SR.CC2IF. Register addresses and bit positions
come from the vendor SVD, as in the generated header. Edges run through all six Hall
codes in both directions over a sweep of speed, bus voltage, current and duty.
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


def bench(
    spec_path: str | Path, generated: Path, build_dir: Path
) -> tuple[HandlerStats, HandlerStats]:
    spec = load_spec(spec_path)
    sc = scaling(spec, derive())
    build(generated, build_dir)
    sim = CortexM3Sim(load_elf(build_dir / "firmware.elf"))
    sim.call("bldc_port_init")
    pins = port_context(spec)["hall_pins"]
    tim3_sr, tim3_ccr1, tim3_cnt = (_register("TIM3", r) for r in ("SR", "CCR1", "CNT"))
    cc1if, cc2if = _bit("TIM3", "SR", "CC1IF"), _bit("TIM3", "SR", "CC2IF")
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
    commutation_end: list[tuple[int, int, int]] = []

    def stage_hall(code: int) -> None:
        levels = {"GPIOA": 0, "GPIOB": 0}
        for pin in pins:
            if code & int(str(pin["code_bit"]).rstrip("u"), 16):
                levels[str(pin["port"])] |= 1 << int(str(pin["n"]))
        for port, value in levels.items():
            sim.write_u32(_register(port, "IDR"), value)

    def run(samples: list[tuple[int, int, int]]) -> None:
        result = sim.call("TIM3_IRQHandler")
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
                        for code in sequence:
                            stage_hall(code)
                            sim.write_u32(tim3_ccr1, period)
                            sim.write_u32(tim3_cnt, 0)
                            sim.write_u32(tim3_sr, cc1if)
                            run(hall_edge)
                            sim.write_u32(tim3_sr, cc2if)
                            run(commutation_end)
    return _stats("Hall edge (TIM3 CC1)", hall_edge), _stats(
        "commutation end (TIM3 CC2)", commutation_end
    )


def report(stats: tuple[HandlerStats, HandlerStats]) -> list[str]:
    hall, end = stats
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
    return lines

"""The commutation end reads TIM1's counter once to wait out an imminent trigger
(BLDC_PORT_WAIT_COUNTS, within END_WAIT_GAP_CYCLES of its second read), reads it again,
stores the COM event, then reads ADC1's SR: the port's bound for an injected sequence to have ended
(BLDC_PORT_SEQUENCE_MIN_COUNTS) is short of the conversions by END_READ_GAP_CYCLES,
the cycles between those two loads at the most, and a trigger the counter puts within
END_COM_GAP_CYCLES of its read fires before the COM event (BLDC_PORT_IMMINENT_AGE).
Measured here on the compiled handler, flash wait states included (the bench's cycle
model), for an edge-aligned and a centre-aligned carrier (which reads CR1 between)."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from codegen.build_firmware import build
from codegen.port_drive import END_COM_GAP_CYCLES, END_READ_GAP_CYCLES, END_WAIT_GAP_CYCLES
from codegen.render import PROJECT_ROOT
from codegen.spec_loader import load_spec
from codegen.spec_model import Spec
from codegen.system_clock import SYSCLK_HZ
from emulation.cycles import estimate_cycles
from emulation.isr_bench import PortRig, _register
from emulation.pil.build import generate

SPECS = ("spec/paper_motor.yaml", "tests/fixtures/pil/conv_cen_ps.yaml")


def _access_indices(trace: tuple, address: int, write: bool = False) -> list[int]:
    return [
        k
        for k, step in enumerate(trace)
        if any(a.address == address and a.write == write for a in step.accesses)
    ]


def _access_index(trace: tuple, address: int, write: bool = False) -> int:
    (index,) = _access_indices(trace, address, write)
    return index


def _built(relative: str, tmp_path: Path) -> tuple[Spec, Path, Path]:
    """The spec, its generated folder and its firmware ELF."""
    path = PROJECT_ROOT / relative
    generated = generate(path, tmp_path / "generated")
    build(generated, tmp_path / "build")
    return load_spec(path), generated, tmp_path / "build" / "firmware.elf"


def _rig_before_an_end(spec: Spec, elf: Path) -> PortRig:
    """The drive running, a Hall edge's commutation pending its end."""
    rig = PortRig(spec, elf)
    rig.prime(2800, 2100, 2000)
    rig.hall_edge(spec.hall.sequence[2], 2000)
    return rig


@pytest.mark.parametrize("relative", SPECS, ids=lambda p: Path(p).stem)
def test_the_end_should_store_the_com_and_read_adc_sr_within_their_gaps_after_tim1_cnt(
    relative: str, tmp_path: Path
) -> None:
    spec, _, elf = _built(relative, tmp_path)
    rig = _rig_before_an_end(spec, elf)
    end = rig.commutation_end()
    # the usual end (mid-period): the wait's read, then the age's
    first, counter = _access_indices(end.trace, _register("TIM1", "CNT"))
    com = _access_index(end.trace, _register("TIM1", "EGR"), write=True)
    status = _access_index(end.trace, _register("ADC1", "SR"))
    assert counter < com < status

    def cycles(first: int, last: int) -> int:
        return estimate_cycles(
            end.trace[first + 1 : last + 1], rig.sim, udiv_mode="worst", timing=rig.memory_timing
        ).cycles

    assert 0 < cycles(first, counter) <= END_WAIT_GAP_CYCLES, cycles(first, counter)
    assert 0 < cycles(counter, status) <= END_READ_GAP_CYCLES, cycles(counter, status)
    assert 0 < cycles(counter, com) <= END_COM_GAP_CYCLES, cycles(counter, com)


@pytest.mark.parametrize("relative", SPECS, ids=lambda p: Path(p).stem)
def test_an_end_before_an_imminent_trigger_should_wait_it_out_before_its_com(
    relative: str, tmp_path: Path
) -> None:
    """An end whose first counter read finds the next injected trigger
    BLDC_PORT_WAIT_COUNTS ahead (TIM1's counter counting with the modelled cycles): it
    reads the counter again until the trigger has fired, so that it fires before the
    COM event for certain and the end counts its sequence (one stale sequence, by its
    age). An end that took the next trigger for fired when the COM event came first had
    dropped the one clean sample after it, sector after sector (`make pil`, a
    conventional motor whose ends kept landing a few counts before a trigger)."""
    from codegen.port_drive import wait_counts

    spec, _, elf = _built(relative, tmp_path)
    rig = _rig_before_an_end(spec, elf)
    end = rig.commutation_end(trigger_in=rig.wait_counts)
    reads = _access_indices(end.trace, _register("TIM1", "CNT"))
    com = _access_index(end.trace, _register("TIM1", "EGR"), write=True)
    assert len(reads) > 2 and reads[-1] < com  # it waited
    ccr4 = rig.sim.read_u32(rig.tim1_ccr4)
    arr = rig.sim.read_u32(rig.tim1_arr)
    last = rig.sim.read_u32(rig.tim1_cnt)  # what the last read gave
    if spec.inverter.pwm_alignment == "edge":
        assert ccr4 <= last < ccr4 + 200, (ccr4, last)  # the trigger has fired
    else:
        down = rig.sim.read_u32(rig.tim1_cr1) & rig.dir_bit
        assert down and arr - 200 < last < arr, (arr, last)  # past the peak: fired
    # the wait is about WAIT_COUNTS long, not its cap of reads
    wait = estimate_cycles(
        end.trace[reads[0] + 1 : reads[-1] + 1],
        rig.sim,
        udiv_mode="worst",
        timing=rig.memory_timing,
    ).cycles
    assert wait_counts(spec) <= wait <= wait_counts(spec) + 2 * END_WAIT_GAP_CYCLES, wait


def _port_current(rig: PortRig, generated: Path) -> int:
    """port.current, the loop's latest sample of I (ADC code)."""
    from emulation.pil.braking import port_layout

    offset, size = port_layout(generated / "c" / "stm32f103_port.c")["current"]
    word = rig.sim.read_u32(rig.sim.image.symbol("port").address + offset)
    return word & ((1 << (8 * size)) - 1)


def _end_then_samples(elf: Path, spec: Spec, generated: Path, ahead: int | None) -> int:
    """An end whose first counter read finds the next trigger `ahead` counts away (None:
    far), the sequence that trigger begins if it fires before the end's COM event (the
    carrier's restart), then one sequence begun after the end: the current the loop
    holds after them (each sequence its own code)."""
    rig = _rig_before_an_end(spec, elf)
    end = rig.commutation_end(trigger_in=ahead if ahead is not None else 1000)
    first = _access_indices(end.trace, _register("TIM1", "CNT"))[0]
    com = _access_index(end.trace, _register("TIM1", "EGR"), write=True)
    cycles = estimate_cycles(end.trace[first + 1 : com + 1], rig.sim, timing=rig.memory_timing)
    counts = cycles.cycles * float(spec.inverter.timer_clock_hz / SYSCLK_HZ)
    if ahead is not None and counts >= ahead:  # it fired before the COM event
        rig.adc_sample(2800, 2301)  # sampled the commutating bridge: not I
    rig.adc_sample(2800, 2302)  # begun after the end: I
    return _port_current(rig, generated)


@pytest.mark.parametrize("relative", SPECS, ids=lambda p: Path(p).stem)
def test_an_end_a_few_counts_before_a_trigger_should_leave_the_next_sample_to_the_loop(
    relative: str, tmp_path: Path
) -> None:
    """An end whose COM event comes a couple of counts before an injected trigger: the
    restart leaves that trigger unfired, yet the end, its counter read within the COM
    event's gap of it, counted its sequence stale and dropped the one clean sample
    after it (a commutation of constant length, ending at the same carrier phase
    sector after sector, read a current three sectors old: `make pil`, a hunt's
    conventional motor, tests/fixtures/pil/conv_ltl_end_before_trigger.yaml). The end
    now waits such a trigger out: it fires, its sequence is dropped, the next is I. The
    port without the wait (a mutant) drops the clean one."""
    from emulation.pil.build import link_mutant

    spec, generated, elf = _built(relative, tmp_path)

    def no_wait(copy: Path) -> None:
        source = copy / "c" / "stm32f103_port.c"
        text = source.read_text(encoding="utf-8")
        wait = "if (BLDC_PORT_RARE(BLDC_PORT_TRIGGER_WITHIN("
        assert text.count(wait) == 1, "the wait's pattern no longer matches the port"
        source.write_text(text.replace(wait, "if (BLDC_PORT_RARE(0 && BLDC_PORT_TRIGGER_WITHIN("))

    mutant = link_mutant(generated, tmp_path / "mutant", no_wait)
    # where the mutant's COM event lands 2 counts before the trigger: its reads' gap
    rig = _rig_before_an_end(spec, mutant)
    end = rig.commutation_end(trigger_in=1000)
    first = _access_indices(end.trace, _register("TIM1", "CNT"))[0]
    com = _access_index(end.trace, _register("TIM1", "EGR"), write=True)
    to_com = estimate_cycles(end.trace[first + 1 : com + 1], rig.sim, timing=rig.memory_timing)
    ahead = math.ceil(to_com.cycles * float(spec.inverter.timer_clock_hz / SYSCLK_HZ)) + 2
    assert _end_then_samples(elf, spec, generated, ahead) == 2302
    assert _end_then_samples(mutant, spec, tmp_path / "mutant" / "generated", ahead) != 2302
    assert _end_then_samples(elf, spec, generated, None) == 2302  # far: no wait, no stale

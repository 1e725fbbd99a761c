"""The commutation end reads TIM1's counter, stores the COM event, then reads ADC1's
SR: the port's bound for an injected sequence to have ended
(BLDC_PORT_SEQUENCE_MIN_COUNTS) is short of the conversions by END_READ_GAP_CYCLES,
the cycles between those two loads at the most, and a trigger the counter puts within
END_COM_GAP_CYCLES of its read fires before the COM event (BLDC_PORT_IMMINENT_AGE).
Measured here on the compiled handler, flash wait states included (the bench's cycle
model), for an edge-aligned and a centre-aligned carrier (which reads CR1 between)."""

from __future__ import annotations

from pathlib import Path

import pytest

from codegen.build_firmware import build
from codegen.port_drive import END_COM_GAP_CYCLES, END_READ_GAP_CYCLES
from codegen.render import PROJECT_ROOT
from codegen.spec_loader import load_spec
from emulation.cycles import estimate_cycles
from emulation.isr_bench import PortRig, _register
from emulation.pil.build import generate

SPECS = ("spec/paper_motor.yaml", "tests/fixtures/pil/conv_cen_ps.yaml")


def _access_index(trace: tuple, address: int, write: bool = False) -> int:
    (index,) = [
        k
        for k, step in enumerate(trace)
        if any(a.address == address and a.write == write for a in step.accesses)
    ]
    return index


@pytest.mark.parametrize("relative", SPECS, ids=lambda p: Path(p).stem)
def test_the_end_should_store_the_com_and_read_adc_sr_within_their_gaps_after_tim1_cnt(
    relative: str, tmp_path: Path
) -> None:
    path = PROJECT_ROOT / relative
    spec = load_spec(path)
    generated = generate(path, tmp_path / "generated")
    build(generated, tmp_path / "build")
    rig = PortRig(spec, tmp_path / "build" / "firmware.elf")
    rig.prime(2800, 2100, 2000)
    rig.hall_edge(spec.hall.sequence[2], 2000)
    end = rig.commutation_end()
    counter = _access_index(end.trace, _register("TIM1", "CNT"))
    com = _access_index(end.trace, _register("TIM1", "EGR"), write=True)
    status = _access_index(end.trace, _register("ADC1", "SR"))
    assert counter < com < status

    def cycles(first: int, last: int) -> int:
        return estimate_cycles(
            end.trace[first + 1 : last + 1], rig.sim, udiv_mode="worst", timing=rig.memory_timing
        ).cycles

    assert 0 < cycles(counter, status) <= END_READ_GAP_CYCLES, cycles(counter, status)
    assert 0 < cycles(counter, com) <= END_COM_GAP_CYCLES, cycles(counter, com)

"""The commutation end reads TIM1's counter, then ADC1's SR: the port's bound for an
injected sequence to have ended (BLDC_PORT_SEQUENCE_MIN_COUNTS) is short of the
conversions by END_READ_GAP_CYCLES, the cycles between those two loads at the most.
Measured here on the compiled handler, flash wait states included (the bench's cycle
model), for an edge-aligned and a centre-aligned carrier (which reads CR1 between)."""

from __future__ import annotations

from pathlib import Path

import pytest

from codegen.build_firmware import build
from codegen.port_drive import END_READ_GAP_CYCLES
from codegen.render import PROJECT_ROOT
from codegen.spec_loader import load_spec
from emulation.cycles import estimate_cycles
from emulation.isr_bench import PortRig, _register
from emulation.pil.build import generate

SPECS = ("spec/paper_motor.yaml", "tests/fixtures/pil/conv_cen_ps.yaml")


def _load_index(trace: tuple, address: int) -> int:
    (index,) = [
        k
        for k, step in enumerate(trace)
        if any(a.address == address and not a.write for a in step.accesses)
    ]
    return index


@pytest.mark.parametrize("relative", SPECS, ids=lambda p: Path(p).stem)
def test_the_end_should_read_adc_sr_within_the_gap_after_tim1_cnt(
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
    counter = _load_index(end.trace, _register("TIM1", "CNT"))
    status = _load_index(end.trace, _register("ADC1", "SR"))
    assert counter < status
    gap = estimate_cycles(
        end.trace[counter + 1 : status + 1],
        rig.sim,
        udiv_mode="worst",
        timing=rig.memory_timing,
    ).cycles
    assert 0 < gap <= END_READ_GAP_CYCLES, gap

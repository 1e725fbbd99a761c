"""The carrier phase of the Hall edge: the pre-edge current the commutation starts from,
and the simulation's verdicts taken at the worst phase, not at phase 0 (the edge on a
carrier boundary, the best case of a commutation that swells)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from codegen.spec_loader import load_spec
from codegen.spec_model import Spec
from sim.drive import Drive
from sim.scenario import Case, paper_edge, plant, pre_edge_state, schedule_for

ROOT = Path(__file__).resolve().parents[1]
#: 2 poles, 30 000 rpm, improved_r, 20 kHz edge-aligned: at 27 500 rpm (7.3 PWM periods a
#: sector, main duty 0.238) +2.8 % with the edge on a carrier boundary, +19 % at the peak.
MOTOR = ROOT / "tests" / "fixtures" / "odd" / "ir_pp1_30k_carrier_phase.yaml"
SPEED = 27500.0


@pytest.fixture(scope="module")
def spec() -> Spec:
    return load_spec(MOTOR)


def _edge_current(case: Case) -> float:
    """|i_off| at the Hall edge, from the steady pre-edge state the run starts from."""
    trace = plant("switched")(
        case.drive,
        case.emf,
        schedule_for(case, None, 0.0),
        case.start_time,
        0.0,
        pre_edge_state(case, "switched"),
    )
    return abs(float(trace.current_at(0.0)[case.edge.turn_off]))


def test_an_edge_just_past_a_carrier_boundary_should_find_the_ripple_at_its_valley(
    spec: Spec,
) -> None:
    """The current loop holds I as a whole period's mean, so an edge 0.1 % of a period
    past the boundary finds the current where the ripple is then, next to its valley. The
    start state had made the period the edge cuts short average I: at phase 0+ the edge
    found I itself, half a ripple above phase 0's valley (8.00 A against 7.29 A)."""
    drive = Drive.from_spec(spec)
    current = drive.braking_current_a
    at = {
        phase: _edge_current(Case(drive, paper_edge(), SPEED, current, "spec", phase))
        for phase in (0.0, 1e-3, 0.5)
    }
    ripple = 2.0 * (current - at[0.0])
    assert ripple > 0.1 * current  # the valley lies well below the mean here
    assert at[1e-3] == pytest.approx(at[0.0], abs=0.01 * ripple), at
    assert at[0.5] > at[0.0] + 0.2 * ripple, at  # on the falling branch, above the valley

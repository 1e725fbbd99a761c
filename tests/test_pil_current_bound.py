"""The plant's bound on the phase currents (emulation/pil/plant.py `phase_current_bound`)
held to the switched plant it bounds (sim/switched.py, the same pieces the emulated
motor runs): the ADC counts a current conversion unconverted where the bound keeps it
inside the watchdog's window (emulation/pil/adc.py `BoundedInput`), so a bound that is
too tight would hide a conversion at a rail.

Each case runs a motor under fixed gates from a start and checks, from every point of
the trace, every later and earlier point within 300 us: the largest |i| there is within
the bound from the first point's largest |i|. Each term of U + 2 E_peak is needed: a
bound without the EMF misses the short circuit at 3 x the rectifying speed, one without
the bus misses a phase pair driven at a low speed."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from codegen.spec_loader import load_spec
from emulation.pil.plant import phase_current_bound
from sim.drive import Drive
from sim.scenario import Case, switching_table
from sim.schedule import OFF, Schedule, Segment
from sim.switched import simulate_switched

ROOT = Path(__file__).resolve().parents[1]
MOTORS = {
    "paper": ROOT / "spec" / "paper_motor.yaml",
    # 14 poles, 12 V: a low inductance, the steepest currents of the fixtures
    "fast_14p_12v": ROOT / "tests" / "fixtures" / "specs" / "fast_14p_12v.yaml",
    "hub_motor_46p": ROOT / "tests" / "fixtures" / "specs" / "hub_motor_46p.yaml",
}
WINDOW_S = 300e-6
SHORT = (0.0, 1.0, 0.0, 1.0, 0.0, 1.0)  # every lower switch on
A_TO_B = (1.0, 0.0, 0.0, 1.0, 0.0, 0.0)  # upper A and lower B on: the bus across A-B


def _trace(motor: str, gates: tuple[float, ...], speed_share: float) -> tuple[Drive, float, object]:
    spec = load_spec(str(MOTORS[motor]))
    drive = Drive.from_spec(spec).rotating()
    speed = speed_share * drive.upper_speed_rpm
    edge = switching_table().edge_into(1, "forward")
    case = Case(drive, edge, speed, 1.0, "spec")
    duration = 2.0 * drive.sector_time_s(speed)
    schedule = Schedule((Segment(0.0, duration, gates),), drive.pwm_period_s, drive.pwm_alignment)
    trace = simulate_switched(drive, case.emf, schedule, 0.0, duration, np.zeros(3))
    emf_peak = max(abs(v) for _, v in drive.emf_points) * drive.emf_v(speed)
    return drive, emf_peak, trace


def _worst_ratio(drive: Drive, volts: float, trace: object) -> float:
    """The largest (|i| at a point) / (the bound from another point within the window)."""
    times = np.asarray(trace.times)  # type: ignore[attr-defined]
    peaks = np.abs(np.asarray(trace.currents)).max(axis=1)  # type: ignore[attr-defined]
    worst = 0.0
    for j in range(len(times)):
        near = np.abs(times - times[j]) <= WINDOW_S
        bounds = np.array(
            [
                phase_current_bound(
                    float(peaks[j]),
                    float(abs(t - times[j])),
                    volts,
                    drive.inductance_h,
                    drive.resistance_ohm,
                )
                for t in times[near]
            ]
        )
        worst = max(worst, float(np.max(peaks[near] / np.maximum(bounds, 1e-12))))
    return worst


CASES = [
    # (gates, speed as a share of the speed from which all-off rectifies)
    pytest.param(OFF, 1.3, id="all-off-rectifying"),
    pytest.param(SHORT, 1.3, id="short-above-rectifying"),
    pytest.param(SHORT, 0.5, id="short-below-rectifying"),
    pytest.param(A_TO_B, 0.1, id="bus-across-a-pair-slow"),
]


@pytest.mark.parametrize("motor", sorted(MOTORS))
@pytest.mark.parametrize(("gates", "share"), CASES)
def test_the_bound_should_hold_the_switched_plant_from_every_point(
    motor: str, gates: tuple[float, ...], share: float
) -> None:
    drive, emf_peak, trace = _trace(motor, gates, share)
    peaks = np.abs(np.asarray(trace.currents)).max(axis=1)  # type: ignore[attr-defined]
    assert peaks.max() > 0.5, "the case drives no current: it would check nothing"
    ratio = _worst_ratio(drive, drive.bus_voltage_v + 2.0 * emf_peak, trace)
    assert ratio <= 1.0 + 1e-9, f"a current {ratio:.4f} x its bound"


@pytest.mark.parametrize("motor", sorted(MOTORS))
def test_each_term_of_the_bound_should_be_needed(motor: str) -> None:
    drive, emf_peak, short = _trace(motor, SHORT, 3.0)  # line EMF 3 x the bus
    assert _worst_ratio(drive, drive.bus_voltage_v, short) > 1.0, "the EMF's term is slack"
    drive, emf_peak, driven = _trace(motor, A_TO_B, 0.1)
    assert _worst_ratio(drive, 2.0 * emf_peak, driven) > 1.0, "the bus's term is slack"

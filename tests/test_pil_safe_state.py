"""The PIL's own yardstick for the safe state (emulation/pil/safe_state.py): the short
circuit's bound from the FFT of sim's waveform, against closed forms, and the regions it
gives on a motor whose short circuit is within its rating only in part of its range."""

from __future__ import annotations

import math
from dataclasses import replace
from fractions import Fraction
from pathlib import Path

import pytest
from conftest import without_tolerances

from codegen.spec_loader import load_spec
from codegen.spec_model import BackEmfShape
from emulation.pil.build import build_firmware, generate
from emulation.pil.safe_state import (
    ALL_OFF,
    RATING_BAND,
    SHORT_CIRCUIT,
    _harmonics,
    corner,
    peak_line_emf_v,
    required_safe_state,
    short_circuit_bound_a,
    short_rated_speed,
)
from emulation.pil.scenarios import (
    RECTIFYING_MARGIN,
    SCENARIOS,
    run_scenario,
    short_rating_boundary,
)

ROOT = Path(__file__).resolve().parents[1]
SHORT_RATED = ROOT / "tests" / "fixtures" / "pil" / "short_rated_mid_range.yaml"
PAPER = ROOT / "spec" / "paper_motor.yaml"
HUB = ROOT / "tests" / "fixtures" / "specs" / "hub_motor_46p.yaml"


@pytest.mark.parametrize("flat_top_deg", [120, 150, 90])
def test_the_harmonics_should_be_the_trapezoids_fourier_series(flat_top_deg: int) -> None:
    """A trapezoid rising linearly over a = (180 - flat top) / 2 degrees from its zero
    crossing: b_h = 4 sin(h a) / (pi h^2 a), a in radians, odd h only."""
    shape = BackEmfShape.trapezoid(Fraction(flat_top_deg))
    orders, amplitudes = _harmonics(tuple((float(a), float(v)) for a, v in shape.points))
    rise = math.radians((180 - flat_top_deg) / 2)
    by_order = dict(zip(orders.tolist(), amplitudes.tolist(), strict=True))
    for h in (1, 5, 7, 11, 13):
        expected = abs(4 * math.sin(h * rise) / (math.pi * h * h * rise))
        assert by_order[h] == pytest.approx(expected, abs=1e-6)
    assert all(by_order[h] < 1e-9 for h in (2, 4, 8, 10))  # half-wave symmetry
    assert 3 not in by_order and 9 not in by_order  # no current with the star open


def test_the_bound_should_be_twice_the_steady_peak_plus_the_entry_current() -> None:
    """At a low speed (w L << R) the steady peak is E / R times the sum of the EMF's
    harmonic amplitudes; the bound adds the entry transient and the trip current."""
    spec = load_spec(str(SHORT_RATED))
    motor = spec.motor
    _, amplitudes = _harmonics(tuple((float(a), float(v)) for a, v in motor.back_emf_shape.points))
    rpm = 1.0
    e = float(motor.back_emf_constant_v_per_rpm) * rpm
    steady = e / float(motor.phase_resistance_ohm) * float(amplitudes.sum())
    assert short_circuit_bound_a(spec, rpm) == pytest.approx(
        2 * steady + float(spec.protection.over_current_a), rel=1e-4
    )


def test_the_regions_should_follow_the_rating_where_the_short_is_preferred() -> None:
    spec = load_spec(str(SHORT_RATED))
    rated = short_rated_speed(spec)
    assert rated is not None and 2000 < rated < 2400
    rating = float(spec.protection.short_circuit_current_max_a)
    assert short_circuit_bound_a(spec, rated) == pytest.approx(rating, rel=1e-6)  # 1e-3 rpm
    bus = float(spec.inverter.bus_voltage_nominal_v)
    assert peak_line_emf_v(spec, 1.1 * rated) < bus
    # the port reads the rotor up to 1 / (1 - sector_shortening) faster than it is: the
    # short below the rated speed as it may be read, all-off above the rated speed,
    # either between
    said = corner(spec).said
    assert said == pytest.approx(1 / (1 - float(spec.hall.sector_shortening)))
    assert required_safe_state(spec, 0.97 * rated / said, bus) == SHORT_CIRCUIT
    assert required_safe_state(spec, 0.99 * rated, bus) is None
    assert required_safe_state(spec, 1.03 * rated, bus) == ALL_OFF
    assert required_safe_state(spec, rated * (1 + RATING_BAND / 10), bus) is None
    # where all-off rectifies and the short exceeds its rating (above the speed range
    # here) no state is safe: either is accepted; the hub motor's short is rated at every
    # speed, so where all-off rectifies it is the short
    top = float(spec.inverter.bus_voltage_min_v) / peak_line_emf_v(spec, 1.0)
    assert required_safe_state(spec, 1.01 * top, float(spec.inverter.bus_voltage_min_v)) is None
    hub = load_spec(str(HUB))
    hub_top = float(hub.inverter.bus_voltage_min_v) / peak_line_emf_v(hub, 1.0)
    assert required_safe_state(hub, 1.01 * hub_top, float(hub.inverter.bus_voltage_min_v)) == (
        SHORT_CIRCUIT
    )
    # the port cannot know the speed or the bus: no preference, only the physics
    assert required_safe_state(spec, 0.97 * rated / said, bus, inputs_known=False) is None
    assert required_safe_state(spec, 1.03 * rated, bus, inputs_known=False) == ALL_OFF
    # a spec that prefers all-off: all-off below the rectifying speed, at any current
    all_off = replace(spec, protection=replace(spec.protection, safe_state="all_off"))
    assert required_safe_state(all_off, 0.5 * rated, bus) == ALL_OFF


SAID_BAND = ROOT / "tests" / "fixtures" / "pil" / "pp1_95krpm_said_band.yaml"


def test_where_no_state_is_safe_at_every_speed_the_reading_allows_either_is_accepted() -> None:
    """`init` with 1 pole pair at 95 000 rpm (a hunt): at 1.25 x speed_max on the nominal
    bus all-off rectifies nothing at the rotor's speed but would at the speed the port
    may read (Corner.said above it), and the short exceeds its rating at the rotor's
    own. The check had required all-off, which the port cannot tell from the short's
    side of the reading. Either is accepted there, and nowhere else around it: above
    the rectifying speed the short is over its rating (either, no state safe), below
    the band all-off (the spec's preference)."""
    spec = load_spec(str(SAID_BAND))
    said = corner(spec).said
    bus = float(spec.inverter.bus_voltage_nominal_v)
    rating = float(spec.protection.short_circuit_current_max_a)
    rpm = 1.25 * float(spec.controller.speed_max_rpm)
    assert peak_line_emf_v(spec, rpm) < bus <= peak_line_emf_v(spec, said * rpm)
    assert short_circuit_bound_a(spec, rpm, worst=True) > rating * (1 + RATING_BAND)
    assert required_safe_state(spec, rpm, bus) is None
    # no state is known at the port: the physics alone, all-off rectifies nothing
    assert required_safe_state(spec, rpm, bus, inputs_known=False) == ALL_OFF
    # below the band (all-off rectifies at neither speed): the spec's all-off
    below = 0.98 * bus / (said * peak_line_emf_v(spec, 1.0))
    assert required_safe_state(spec, below, bus) == ALL_OFF


@pytest.mark.parametrize(("path", "reachable"), [(SHORT_RATED, True), (PAPER, False), (HUB, False)])
def test_the_rating_boundary_should_lie_inside_the_speed_range_below_rectifying(
    path: Path, reachable: bool
) -> None:
    """Only where the spec prefers the short and its rated speed is in the range (the
    paper motor prefers all-off; the hub motor's short is within its rating at every
    speed)."""
    spec = load_spec(str(path))
    boundary = short_rating_boundary(spec)
    assert (boundary is not None) == reachable
    if boundary is None:
        return
    bus_v, rpm = boundary
    assert float(spec.controller.speed_min_rpm) < rpm * (1 - RECTIFYING_MARGIN)
    assert rpm * (1 + RECTIFYING_MARGIN) < float(spec.controller.speed_max_rpm)
    assert peak_line_emf_v(spec, rpm * (1 + RECTIFYING_MARGIN)) < bus_v


def test_the_port_should_short_below_the_rated_speed_and_switch_off_above(
    tmp_path: Path,
) -> None:
    """The break input 3 % either side of the rated speed on the fixture: the short
    circuit after the dead time below it, all-off above it, every invariant kept (port
    mutants moving the port's rated interval: tests/test_pil_mutants.py)."""
    spec = load_spec(str(SHORT_RATED))
    elf = build_firmware(SHORT_RATED, tmp_path, generate(SHORT_RATED, tmp_path / "g"))
    for key in ("below_short_rating", "above_short_rating"):
        scenario = next(s for s in SCENARIOS if s.key == key)
        outcome = run_scenario(elf, spec, scenario)
        assert outcome.problems == [], (key, outcome.note)
        assert "meets protection.short_circuit_current_max" in outcome.note


def _trip_with_k_e_high(elf: Path, generated: Path, scale: Fraction) -> tuple[str, float]:
    """The paper motor's firmware `elf` braking a plant whose k_e is `scale` x the spec's,
    on a 22.7 V bus, the rotor near 4752 rpm; the comparator trips: the gates chosen,
    and the largest phase current over the last 10 of 30 ms after the trip (the diodes
    rectifying into the bus where all-off is chosen above the real motor's boundary)."""
    from emulation.pil.braking import BrakingLoop, braking_setup
    from emulation.pil.plant_faults import _until_tripped
    from emulation.pil.rcc import TICK_HZ

    spec = load_spec(str(PAPER))
    motor = replace(
        spec.motor, back_emf_constant_v_per_rpm=spec.motor.back_emf_constant_v_per_rpm * scale
    )
    real = replace(spec, motor=motor)
    loop = BrakingLoop(
        elf,
        generated / "c" / "stm32f103_port.c",
        real,
        replace(braking_setup(spec, short=True), start_rpm=4800.0),
    )
    loop.plant.bus_voltage_v = 22.7
    loop.run.board.set_bus_voltage(22.7)
    period = loop.run.board.pwm_period_ticks()
    while len(loop.edges) < 14:
        loop.advance_to(loop.machine.now + period)
    sector = loop.plant.drive.sector_time_s(loop.plant.speed_rpm)
    loop.advance_to(loop.machine.now + round(sector * TICK_HZ / 3))
    loop.comparator.force(True)
    _until_tripped(loop, period)
    gates = loop.machine.tim1.gates()
    state = "short" if gates == SHORT_CIRCUIT else "all-off" if gates == ALL_OFF else str(gates)
    end = loop.machine.now + round(0.03 * TICK_HZ)
    late = end - round(0.01 * TICK_HZ)
    largest = 0.0
    while loop.machine.now < end:
        loop.advance_to(loop.machine.now + 720)
        if loop.machine.now >= late:
            largest = max(largest, float(abs(loop.plant.currents).max()))
    return state, largest


@pytest.mark.heavy(seconds=14)
def test_a_motor_at_the_top_of_its_k_e_tolerance_should_get_the_short_where_it_rectifies(
    tmp_path: Path,
) -> None:
    """A hunt: the paper motor's firmware braking a plant with k_e 10 % high (inside its
    tolerances.back_emf_constant [-10, 10]) at about 4750 rpm on 22.7 V, 1.2 % below the
    nominal motor's rectifying speed (4809 rpm) but above the real one's (4372 rpm). The
    port had chosen all-off from the nominal motor, and the diodes drove 2.8 A into the
    bus for as long as the rotor turned. Now the short, and no current after it has
    decayed; the same firmware for the nominal motor alone (no tolerances, no sector
    shortening: the old boundary) still chooses all-off there, and rectifies."""
    generated = ROOT / "generated" / "paper_motor"
    elf = build_firmware(PAPER, tmp_path / "worst", generated)
    state, _ = _trip_with_k_e_high(elf, generated, Fraction(11, 10))
    assert state == "short", state
    nominal_text = without_tolerances(PAPER.read_text(encoding="utf-8"))
    nominal_text = nominal_text.replace(
        "  counter_bits: 16\n", "  counter_bits: 16\n  sector_shortening: 0\n", 1
    )
    nominal = tmp_path / "paper_motor.yaml"
    nominal.write_text(nominal_text, encoding="utf-8")
    old = generate(nominal, tmp_path / "nominal")
    old_elf = build_firmware(nominal, tmp_path / "old", old)
    old_state, old_current = _trip_with_k_e_high(old_elf, old, Fraction(11, 10))
    assert old_state == "all-off", old_state
    assert old_current > 1.0  # rectifying into the bus, 30 ms on

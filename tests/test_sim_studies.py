"""The studies beyond the sweep: the current loop, Table 4's conditions, the EMF-shape
prototype, the short-commutation schedule and the failure regions."""

from __future__ import annotations

import math
from fractions import Fraction
from pathlib import Path

import numpy as np
import pytest

from codegen.audit.transcription import load_transcription
from codegen.spec_loader import load_spec
from sim.current_loop import held_current, settle
from sim.drive import MAX_SECTOR_PERIODS, Drive
from sim.regions import regions
from sim.runs import Controller, simulate
from sim.scenario import Case, paper_edge
from sim.shape_rule import (
    aligned_command,
    minimax_sum,
    shape_rule_command,
    trapezoid_hold_point,
)
from sim.short_schedule import short_schedule
from sim.sil import prepare_cores
from sim.sweep import sweep_speeds
from sim.table4 import table4_study

ROOT = Path(__file__).resolve().parents[1]
SPECS = (
    "spec/paper_motor.yaml",
    "spec/example_maxon_ec45_flat_48v.yaml",
    "tests/fixtures/specs/hub_motor_46p.yaml",
    "tests/fixtures/specs/fast_14p_12v.yaml",
    "tests/fixtures/specs/offset_conventional.yaml",
)


@pytest.fixture(scope="module")
def paper() -> tuple[Drive, Controller]:
    spec = load_spec(ROOT / "spec" / "paper_motor.yaml")
    methods = ("none", "conventional", "improved", "improved_r")
    return Drive.from_spec(spec), Controller(spec, prepare_cores(spec, methods))


#: L/R of 200 PWM periods: the PI saturates at once from rest, the current still rising
#: (`settle` had stopped there after 50 periods, "settled" at D = 1 with 2 A for 1 A)
SLOW_LOOP = "tests/fixtures/odd/pp50_20mh_slow_loop.yaml"


@pytest.mark.parametrize("path", [*SPECS, SLOW_LOOP])
def test_current_loop_should_settle_at_the_steady_duty_or_saturate(path: str) -> None:
    drive = Drive.from_spec(load_spec(ROOT / path))
    counts = round(72e6 / drive.pwm_frequency_hz / (2 if drive.pwm_alignment == "center" else 1))
    limit = drive.resistance_ohm * drive.braking_current_a / drive.emf_v_per_rpm
    for speed in np.linspace(drive.speed_min_rpm, drive.speed_max_rpm * 0.98, 5):
        loop = settle(drive, float(speed), drive.braking_current_a, counts)
        if speed < limit:
            # R I >= E: D = 1 holds only E / R.
            assert loop.limited and loop.counts == counts
            assert loop.current_a == pytest.approx(drive.emf_v(speed) / drive.resistance_ohm)
        else:
            exact = drive.steady_duty(float(speed), drive.braking_current_a) * counts
            assert abs(loop.counts - exact) <= 1.0, (speed, loop, exact)
            assert not loop.limited
        assert held_current(drive, float(speed), loop.duty) == pytest.approx(loop.current_a)


def test_a_count_coarser_than_the_settling_band_should_hold_the_current_on_the_mean() -> None:
    """0.2 mohm at 5 V and 1440 counts: a count moves the held current by 8.7 A, and at
    2500 rpm the PI rested on the count that holds 0 A (`simulate` then divided by it).
    The loop alternates between the two counts around the steady duty; the mean holds I."""
    drive = Drive.from_spec(load_spec(ROOT / "tests/fixtures/odd/lv5v_200a_coarse_counts.yaml"))
    counts = round(72e6 / drive.pwm_frequency_hz)
    step = drive.bus_voltage_v / (2 * drive.resistance_ohm * counts)
    assert step > 8.0
    dithered = 0
    for speed in (2500.0, *np.linspace(drive.speed_min_rpm, drive.speed_max_rpm * 0.98, 7)):
        loop = settle(drive, float(speed), drive.braking_current_a, counts)
        exact = drive.steady_duty(float(speed), drive.braking_current_a)
        if loop.limited:
            continue
        assert loop.current_a > 0.0
        assert abs(loop.counts - exact * counts) <= 0.5 + 1e-9
        assert abs(loop.current_a - drive.braking_current_a) <= 0.005 * drive.braking_current_a
        dithered += loop.dithering
        if loop.dithering:
            assert loop.duty == exact
    assert dithered >= 1


@pytest.mark.parametrize("path", SPECS)
def test_sweep_should_span_the_specs_own_speed_range(path: str) -> None:
    drive = Drive.from_spec(load_spec(ROOT / path))
    speeds = sweep_speeds(drive, ())
    assert speeds[0] == drive.speed_min_rpm and speeds[-1] == drive.speed_max_rpm
    assert 10 <= len(speeds) <= 30


def test_a_sector_of_more_periods_than_the_plants_simulate_should_raise_the_lowest_speed() -> None:
    """At 1 rpm on one pole pair a sector spans 200 000 periods of the 20 kHz PWM, each
    simulated: the simulation starts where a sector spans MAX_SECTOR_PERIODS (10 rpm),
    and the report keeps the spec's own speed_min. A spec whose slowest sector is within
    it (the paper motor's 1000 periods) keeps its range."""
    spec = load_spec(ROOT / "tests" / "fixtures" / "odd" / "hall1125_1rpm.yaml")
    drive = Drive.from_spec(spec)
    assert drive.spec_speed_min_rpm == 1.0 and drive.speed_min_rpm == 10.0
    periods = drive.sector_time_s(drive.speed_min_rpm) / drive.pwm_period_s
    assert periods == pytest.approx(MAX_SECTOR_PERIODS)
    assert sweep_speeds(drive, ())[0] == 10.0
    paper = Drive.from_spec(load_spec(ROOT / "spec" / "paper_motor.yaml"))
    assert paper.speed_min_rpm == paper.spec_speed_min_rpm == 200.0


def test_table4_should_be_reproduced_at_3_amperes_and_20_khz(
    paper: tuple[Drive, Controller],
) -> None:
    drive, controller = paper
    study = table4_study(controller, drive, load_transcription().table4)
    assert study.reproducing_a == (3.0,)
    counts = {c.speed_rpm: (c.on_pulses, c.off_pulses) for c in study.improved[3.0]}
    assert counts[1000.0] == (1, 7) and counts[1500.0] == (1, 5) and counts[2000.0] == (1, 4)
    # The count scales with I: twice the current, about twice the pulses.
    assert study.improved[6.0][0].off_pulses in (13, 14, 15)
    # A settled loop gives the conventional method L/(2R) at every speed.
    for count in study.spec_conventional:  # Hall ticks of 1 us
        assert count.commanded_us == pytest.approx(0.56e-3 / (2 * 0.21) * 1e6, abs=1.5)


def test_aligned_prototype_should_be_the_c_core_on_the_trapezoid_and_on_the_flat_emf(
    paper: tuple[Drive, Controller],
) -> None:
    """The carrier-aligned prototype (`sim.shape_rule`, Python, any shape) and the C core
    generated for the shape agree on the two shapes the firmware takes: the same
    carrier boundary and the pair within a count (the prototype quantises its pair
    before easing it)."""
    drive, controller = paper
    hall = float(controller.cores.scaling.hall_clock_hz)
    counts = controller.period_counts
    for shape in ("spec", "flat"):
        for speed in (1000.0, 3000.0, 4600.0):
            loop = settle(drive, speed, drive.braking_current_a, counts)
            case = Case(drive, paper_edge(), speed, loop.current_a, shape)
            measured = controller.measured_current(case)
            core = controller.command("improved_r", case, loop.duty)
            mine = aligned_command(case, measured, loop.duty, counts, hall)
            assert mine.commutation_time_s == pytest.approx(core.commutation_time_s, abs=1e-9)
            assert abs(mine.on_duty(0) - core.on_duty(0)) * counts <= 1.0
            assert abs(mine.off_duty(0) - core.off_duty(0)) * counts <= 1.0
            assert abs(simulate(case, core, "switched").metrics.deviation_worst_pct) < 3.0
        # the unaligned prototype (the rule before the carrier alignment) ends mid-period
        shaped = shape_rule_command(case, measured, loop.duty, counts, hall)
        periods = shaped.commutation_time_s / drive.pwm_period_s
        assert abs(periods - round(periods)) > 0.01


def test_trapezoid_hold_point_should_be_the_numeric_minimax(
    paper: tuple[Drive, Controller],
) -> None:
    """The closed form for a flat top >= 120 deg against the numeric minimax constant."""
    drive, _ = paper
    wide = drive.with_flat_top(150.0)
    case = Case(wide, paper_edge(), 2000.0, 5.0, "spec")
    sector = case.sector_time_s
    e, bus = wide.emf_v(2000.0), wide.bus_voltage_v
    flat_sum = minimax_sum(case, 5.0, 0.2 * sector)  # before the ramp: S(0)
    for x_c in (0.5, 0.7):
        held = minimax_sum(case, 5.0, x_c * sector) - flat_sum
        slope = (2 * e / bus) / 0.5  # S ramps by 2E/U_d over the 0.5-sector ramp
        assert held == pytest.approx(slope * trapezoid_hold_point(150.0, x_c), rel=0.02)
    assert trapezoid_hold_point(120.0, 1.0) == pytest.approx(np.sqrt(2) - 1)


def test_aligned_rule_should_end_on_a_carrier_boundary(paper: tuple[Drive, Controller]) -> None:
    """At 3500 rpm the unaligned rule ends mid-period and the port's carrier restart
    there swells the current past 3 % on the switched plant; the C core ends on a
    carrier boundary and stays within."""
    drive, controller = paper
    hall = float(controller.cores.scaling.hall_clock_hz)
    loop = settle(drive, 3500.0, drive.braking_current_a, controller.period_counts)
    case = Case(drive, paper_edge(), 3500.0, loop.current_a, "spec")
    measured = controller.measured_current(case)
    core = controller.command("improved_r", case, loop.duty)
    unaligned = shape_rule_command(case, measured, loop.duty, controller.period_counts, hall)
    periods = core.commutation_time_s / drive.pwm_period_s
    assert periods == pytest.approx(round(periods), abs=1e-9)
    core_dev = simulate(case, core, "switched").metrics.deviation_worst_pct
    unaligned_dev = simulate(case, unaligned, "switched").metrics.deviation_worst_pct
    assert abs(unaligned_dev) > 3.0 > abs(core_dev)


def test_short_schedule_should_hold_the_period_means_of_a_two_period_commutation() -> None:
    spec = load_spec(ROOT / "spec" / "example_maxon_ec45_flat_48v.yaml")
    drive = Drive.from_spec(spec)
    controller = Controller(spec, prepare_cores(spec, ("improved_r",)))
    hall = float(controller.cores.scaling.hall_clock_hz)
    loop = settle(drive, 3500.0, drive.braking_current_a, controller.period_counts)
    case = Case(drive, paper_edge(), 3500.0, loop.current_a, "spec")
    core = controller.command("improved_r", case, loop.duty)
    # the zero of the turn-off current comes within one period: the core ends on the
    # first carrier boundary, with the PWM ripple of one period on top of its pair
    assert core.commutation_time_s == pytest.approx(drive.pwm_period_s)
    start = shape_rule_command(
        case, controller.measured_current(case), loop.duty, controller.period_counts, hall
    )
    schedule = short_schedule(case, start, controller.period_counts, hall)
    metrics = simulate(case, schedule.command, "switched").metrics
    assert abs(metrics.deviation_worst_pct) < 1.0
    assert abs(simulate(case, core, "switched").metrics.deviation_worst_pct) > 5.0
    assert len(schedule.command.on_duties) == 2


def test_regions_should_follow_from_the_physics() -> None:
    paper = Drive.from_spec(load_spec(ROOT / "spec" / "paper_motor.yaml"))
    found = regions(paper)
    assert found.current_limited_below_rpm == pytest.approx(0.21 * 5 / 2.36e-3)
    assert found.under_three_periods == ()
    maxon = regions(Drive.from_spec(load_spec(ROOT / "spec" / "example_maxon_ec45_flat_48v.yaml")))
    assert maxon.under_one_period and maxon.fewest_periods < 1.0
    low, high = maxon.under_three_periods[0]
    assert low < 2500.0 and high > 4250.0


def test_the_main_duty_loop_should_balance_the_conducting_pairs_mean_emf(tmp_path: Path) -> None:
    """The averaged circuit between commutations opposes the bus with the conducting
    pair's line-to-line EMF. The loop took 2 k_e n for every shape: a table whose flat
    top is 2 (k_e halved: the same motor) settled at 0.891 against 0.748 and held another
    current than the switched plant carried (a helper's hunt). A sine's mean over a
    sector is 3 sqrt(3) / pi of its peak, not 2."""
    from codegen.spec_drive import conducting_line_mean
    from codegen.spec_model import BackEmfShape

    text = (ROOT / "spec" / "paper_motor.yaml").read_text(encoding="utf-8")
    assert "  back_emf_constant: 2.36 V/krpm\n" in text
    doubled = text.replace(
        "  back_emf_constant: 2.36 V/krpm\n",
        "  back_emf_constant: 1.18 V/krpm\n"
        "  back_emf_shape: [[0, 0], [30, 2], [150, 2], [180, 0]]\n",
    )
    (tmp_path / "doubled.yaml").write_text(doubled, encoding="utf-8")
    reference = Drive.from_spec(load_spec(ROOT / "spec" / "paper_motor.yaml"))
    table = Drive.from_spec(load_spec(tmp_path / "doubled.yaml"))
    assert (reference.hold_emf_factor, table.hold_emf_factor) == (1.0, 2.0)
    for speed in (300.0, 1500.0, 4000.0):
        assert table.hold_emf_v(speed) == pytest.approx(reference.hold_emf_v(speed))
        a = settle(reference, speed, reference.braking_current_a, 3600)
        b = settle(table, speed, table.braking_current_a, 3600)
        assert (a.counts, a.limited) == (b.counts, b.limited)
    sine = tuple(
        (Fraction(a), Fraction(math.sin(math.radians(a))).limit_denominator(10**9))
        for a in range(181)
    )
    mean = float(conducting_line_mean(BackEmfShape(sine, None)))
    assert mean == pytest.approx(3 * math.sqrt(3) / math.pi / 2, rel=1e-4)
    assert conducting_line_mean(BackEmfShape.trapezoid(Fraction(150))) == 1

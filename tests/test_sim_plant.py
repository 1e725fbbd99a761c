"""The simulated plant: exact pieces, diode blocking, and switched -> averaged as f rises."""

from __future__ import annotations

import dataclasses
import math
import random
from itertools import pairwise
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

from codegen.spec_loader import load_spec
from sim import closed_form
from sim.circuit import LegVoltages, resolve
from sim.command import Command
from sim.drive import Drive
from sim.emf import TRAPEZOID_120, BackEmf, Waveform
from sim.resistance import alpha, beta, decay, derive_resistance_rule, i0
from sim.scenario import Case, paper_edge, run_case, switching_table
from sim.schedule import switch_index

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def drive() -> Drive:
    return Drive.from_spec(load_spec(ROOT / "spec" / "paper_motor.yaml"))


def _improved_command(case: Case, t_com: float) -> Command:
    """The paper's low-segment duties (Eq. 18) as a fixed command, no quantisation."""
    emf = case.drive.emf_v(case.speed_rpm)
    off = 1.0 - 4.0 * emf / case.drive.bus_voltage_v
    return Command(
        method="improved",
        turn_on_switch=switch_index(case.edge.modulated_on),
        turn_off_switch=switch_index(case.edge.modulated_off),
        on_duties=(1.0,),
        off_duties=(off,),
        commutation_time_s=t_com,
        main_duty=case.pre_edge_duty,
    )


def test_closed_form_should_match_the_sympy_solution() -> None:
    """closed_form.current is the dsolve solution the R-aware rule is derived from."""
    solution = derive_resistance_rule().current_solution
    rng = random.Random(7)
    for _ in range(20):
        values = {
            i0: rng.uniform(-5, 5),
            alpha: rng.uniform(-2e4, 2e4),
            beta: rng.uniform(-1e7, 1e7),
            decay: rng.choice([1e-3, 375.0, 2000.0]),
            sp.Symbol("t", nonnegative=True): rng.uniform(0, 2e-3),
        }
        t = values[sp.Symbol("t", nonnegative=True)]
        exact = {k: sp.Rational(repr(v)) for k, v in values.items()}  # no float cancellation
        expected = float(solution.subs(exact).evalf(40))
        got = closed_form.current(values[i0], values[alpha], values[beta], values[decay], t)
        assert got == pytest.approx(expected, rel=1e-9, abs=1e-9)


def test_first_zero_should_find_the_earliest_root() -> None:
    # i = 5 - 1e4 t (a = 0) reaches zero at 0.5 ms; a horizon before it finds nothing.
    assert closed_form.first_zero(5.0, -1e4, 0.0, 0.0, 1e-3) == pytest.approx(5e-4, rel=1e-12)
    assert closed_form.first_zero(5.0, -1e4, 0.0, 0.0, 4e-4) is None
    # A current that starts at zero and turns back: the return to zero is the event.
    t = closed_form.first_zero(0.0, 1e4, -4e7, 100.0, 1e-3)
    assert t is not None and 4e-4 < t < 6e-4
    assert closed_form.current(0.0, 1e4, -4e7, 100.0, t) == pytest.approx(0.0, abs=1e-9)


def test_floating_phase_should_start_conducting_only_past_a_rail() -> None:
    legs = LegVoltages.from_duties((0, 0, 0, 0, 1, 0), 24.0)  # T5 on, C at U_d
    emf = np.array([10.0, -10.0, -10.0])
    # A through D1 (U_d) and B through D4 (0 V) conduct; C has T5 on: it joins.
    topology = resolve(legs, np.array([-5.0, 5.0, 0.0]), emf)
    assert topology.conducting.tolist() == [True, True, True]
    # All switches off: C floats at u_n + e_c = 12 - 10 = 2 V, inside the rails.
    topology = resolve(LegVoltages.from_duties((0,) * 6, 24.0), np.array([-5.0, 5.0, 0.0]), emf)
    assert topology.conducting.tolist() == [True, True, False]
    v0, v1 = topology.floating_voltage(emf, np.zeros(3), 2)
    assert v0 == pytest.approx(2.0) and v1 == 0.0


def test_turn_off_current_should_stay_blocked_after_reaching_zero(drive: Drive) -> None:
    case = Case(drive, paper_edge(), 1500.0, 5.0, "spec")
    trace = run_case(case, _improved_command(case, 2e-4), "switched", 2e-3)
    zero = trace.first_zero(case.edge.turn_off, after=0.0)
    assert zero is not None and 2e-4 < zero < 5e-4
    after = trace.times > zero
    assert np.all(trace.currents[after, case.edge.turn_off] == 0.0)
    assert np.allclose(trace.currents.sum(axis=1), 0.0, atol=1e-9)


def test_averaged_plant_should_hold_the_current_under_the_exact_rule(drive: Drive) -> None:
    """R = 0 and flat EMFs: Eq. 18 keeps i_nc exactly constant on the averaged plant."""
    ideal = dataclasses.replace(drive, resistance_ohm=0.0)
    case = Case(ideal, paper_edge(), 1500.0, 5.0, "flat")
    t_com = 5.0 * ideal.inductance_h / (2 * ideal.emf_v(1500.0))  # Eq. 20, low segment
    trace = run_case(case, _improved_command(case, t_com), "averaged", t_com + 2e-4)
    nc = case.edge.non_commutating
    assert np.allclose(trace.currents[:, nc], -5.0, atol=1e-6)
    assert trace.first_zero(case.edge.turn_off) == pytest.approx(t_com, rel=1e-6)


def _switched_error(drive: Drive, frequency: float) -> float:
    """Largest current difference switched vs averaged at 41 common instants."""
    faster = drive.with_pwm_frequency(frequency)
    case = Case(faster, paper_edge(), 1500.0, 5.0, "spec")
    command = _improved_command(case, 4e-4)
    end = 1e-3
    switched = run_case(case, command, "switched", end)
    averaged = run_case(case, command, "averaged", end)
    return max(
        float(np.max(np.abs(switched.current_at(t) - averaged.current_at(t))))
        for t in np.linspace(0.0, end, 41)
    )


def test_switched_plant_should_converge_to_the_averaged_one(drive: Drive) -> None:
    frequencies = [20e3, 40e3, 80e3, 160e3]
    errors = [_switched_error(drive, f) for f in frequencies]
    assert all(b < a for a, b in pairwise(errors)), errors
    # Roughly proportional to 1/f: error x f stays within a factor of 3.
    scaled = [e * f for e, f in zip(errors, frequencies, strict=True)]
    assert max(scaled) / min(scaled) < 3.0, scaled
    slope = math.log(errors[-1] / errors[0]) / math.log(frequencies[-1] / frequencies[0])
    assert -1.5 < slope < -0.7, slope


def test_exact_averaged_plant_should_agree_with_cvodes(drive: Drive) -> None:
    """The averaged model solved by exact pieces and integrated by CVODES: two
    independent solutions of the same equations, per-period means within 1e-5 A."""
    for speed, t_com in ((1500.0, 4e-4), (4600.0, 9e-4)):
        case = Case(drive, paper_edge(), speed, 5.0, "spec")
        command = _improved_command(case, t_com)
        exact = run_case(case, command, "averaged", 1.5e-3)
        cvodes = run_case(case, command, "averaged_cvodes", 1.5e-3)
        assert exact.period_starts.tolist() == cvodes.period_starts.tolist()
        assert np.allclose(exact.period_currents, cvodes.period_currents, atol=1e-5)
        zero = exact.first_zero(case.edge.turn_off)
        assert zero is not None
        assert zero == pytest.approx(cvodes.first_zero(case.edge.turn_off), abs=1e-9)


@pytest.mark.parametrize(
    "points",
    [TRAPEZOID_120, ((0.0, 0.0), (20.0, 0.7), (75.0, 1.0), (150.0, 0.9), (180.0, 0.0))],
    ids=["trapezoid", "uneven"],
)
def test_emf_values_on_arrays_should_equal_them_one_by_one(
    points: tuple[tuple[float, float], ...],
) -> None:
    """`values_many` (the shaped rule's vector form) gives each instant exactly what
    `values` gives it, every edge of both directions, before, in and past the sector."""
    table = switching_table()
    for edge in table.edges:
        for shape in ("spec", "flat"):
            emf = BackEmf(shape, edge, table.sectors("forward"), 37.5, 1.3e-3, Waveform(points))
            times = np.linspace(-2.0e-3, 4.0e-3, 401)
            one_by_one = np.array([emf.values(float(t)) for t in times])
            assert np.array_equal(emf.values_many(times), one_by_one), (edge, shape)


def test_an_emf_lead_should_shift_the_waveform_and_its_corners_in_time() -> None:
    """`BackEmf.lead_s`: the rotor passed the edge's angle `lead_s` before t = 0, so the
    EMF at t is the unshifted one's at t + lead_s, corners included (the emulated
    drive's time 0 is its COM event, after the Hall lines changed)."""
    edge = paper_edge()
    sectors = switching_table().sectors("forward")
    sector_s, lead = 1e-3, 37e-6
    plain = BackEmf("spec", edge, sectors, 10.0, sector_s)
    ahead = dataclasses.replace(plain, lead_s=lead)
    times = np.linspace(-2e-3, 2e-3, 97)
    for t in times:
        assert np.allclose(ahead.values(float(t)), plain.values(float(t) + lead), atol=1e-12)
    assert np.allclose(ahead.values_many(times), plain.values_many(times + lead), atol=1e-12)
    assert np.allclose(
        ahead.corners(-2e-3, 2e-3), [c - lead for c in plain.corners(-2e-3 + lead, 2e-3 + lead)]
    )
    e0, e1 = ahead.affine(0.0, 1e-5)
    assert np.allclose(e0 + e1 * 5e-6, plain.values(5e-6 + lead), atol=1e-9)


class _Emf:
    """Constant phase EMFs (V): the one piece `run_piece` asks for."""

    def __init__(self, values: tuple[float, float, float]) -> None:
        self._values = np.array(values)

    def affine(self, _t0: float, _t1: float) -> tuple[np.ndarray, np.ndarray]:
        return self._values, np.zeros(3)


class _Schedule:
    def period_index(self, _t: float) -> int:
        return 0


class _Recorder:
    def __init__(self) -> None:
        self.events: list = []

    def accumulate(self, *_args: object) -> None:
        pass

    def point(self, *_args: object) -> None:
        pass


@pytest.mark.parametrize("model", ["switched", "averaged"])
def test_two_phases_whose_current_dies_should_both_record_its_zero(
    drive: Drive, model: str
) -> None:
    """Two phases carrying one current through the diodes (every switch off) into the
    bus: it decays to zero in both at the same instant. Only the phase found first had
    its zero recorded, the other set to zero by the balance, silently; a turn-off
    current that died with the non-commutating one so had no zero, and the PIL and SIL
    runs of one commutation (a measured EMF with a negative lobe: a hunt) tied the
    other way round, windows of 26 and 43 PWM periods. Each phase now records it."""
    from sim import averaged, switched

    legs = LegVoltages.from_duties((0.0,) * 6, drive.bus_voltage_v)
    for order in ((2.0, -2.0, 0.0), (0.0, 2.0, -2.0), (-2.0, 0.0, 2.0)):
        recorder = _Recorder()
        run_piece = switched.run_piece if model == "switched" else averaged._run_piece
        left = run_piece(
            drive, _Emf((0.0, 0.0, 0.0)), _Schedule(), legs, 0.0, 0.01, np.array(order), recorder
        )
        assert list(left) == [0.0, 0.0, 0.0]
        zeros = [e for e in recorder.events if e.kind == "zero"]
        carried = [k for k in range(3) if order[k] != 0.0]
        assert sorted(e.phase for e in zeros) == carried, (model, order, zeros)
        assert zeros[0].time == zeros[1].time > 0.0

"""The independent oracle against values worked out by hand, and against the
generator's own derivation (two independent routes that must agree)."""

from __future__ import annotations

import math
import random
from fractions import Fraction
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

from codegen import spec_model
from codegen.derivation import derive
from codegen.derivation import symbols as s
from codegen.spec_loader import load_spec
from oracle.model import oracle
from verify.current_loop import integrator_tolerance

ROOT = Path(__file__).resolve().parents[1]

#: spec -> (P counts, volts per bus code, amps per current code, zero-current code,
#: period_min, period_max, bus_min, bus_max, current_low, current_high), by hand:
#: P = f_timer / f_pwm (/2 centre); V/code = V_ref k / 4096; A/code = V_ref / (G 4096);
#: C0 = V_off / V_ref 4096; T = 60 f_hall / (6 p n); codes of the ranges, exactly; the
#: Hall timer counts whole ticks, so a sector of T ticks reads floor(T) or ceil(T): the
#: period range is [floor(T(speed_max)), ceil(T(speed_min))].
HAND = {
    "paper_motor.yaml": (
        3600,
        Fraction(33, 10) * 11 / 4096,
        Fraction(33, 10) / (Fraction(5, 100) * 4096),
        Fraction(2048),
        2000,  # 5000 rpm, 1 MHz, 1 pole pair: 10^6 / (5000 / 10) = 2000 exactly
        50000,  # 200 rpm
        2257,  # ceil(20 / (36.3 / 4096)) = ceil(2256.75)
        3385,  # floor(30 / 0.0088623) = floor(3385.12)
        2048,
        2668,  # floor(2048 + 10 / 0.0161133) = floor(2668.6)
    ),
    "example_maxon_ec45_flat_48v.yaml": (
        3600,
        Fraction(33, 10) * 21 / 4096,
        Fraction(33, 10) / (Fraction(4, 10) * 4096),
        Fraction(2048),
        227,  # floor(10^6 / (8 * 5500 / 10)) = floor(227.27): 5500 rpm reads 227 or 228
        8334,  # ceil(10^6 / (8 * 150 / 10)) = ceil(8333.3)
        2306,  # ceil(39 / (69.3 / 4096)) = ceil(2305.1)
        3546,  # floor(60 / 0.0169189) = floor(3546.3)
        2048,
        3239,  # floor(2048 + 2.4 / 0.00201416) = floor(3239.6)
    ),
    "offset_conventional.yaml": (
        2250,  # 72 MHz / 16 kHz / 2
        Fraction(3) * 16 / 4096,
        Fraction(3) / (Fraction(1, 10) * 4096),
        Fraction(2048, 3),
        909,  # floor(2e6 * 10 / (4 * 5500)) = floor(909.09)
        50000,  # floor(2e6 * 10 / (4 * 100))
        1536,  # ceil(18 / 0.01171875) = 1536 exactly
        2560,  # 30 / 0.01171875 = 2560 exactly
        751,  # ceil(682.667 + 0.5 / 0.00732422) = ceil(750.93)
        2730,  # floor(682.667 + 15 / 0.00732422) = floor(2730.67)
    ),
}


def _spec(name: str) -> Path:
    for folder in (ROOT / "spec", ROOT / "tests" / "fixtures" / "specs"):
        if (folder / name).is_file():
            return folder / name
    raise FileNotFoundError(name)


def test_maxon_hand_values() -> None:
    """The maxon's limits worked out in full (48 V bus, divider 21, 400 mV/A)."""
    volts = Fraction(33, 10) * 21 / 4096  # 0.0169189 V per code
    assert -(-Fraction(39) // volts) == 2306  # ceil(2305.1)
    assert Fraction(60) // volts == 3546  # floor(3546.3)
    amps = Fraction(33, 10) / (Fraction(4, 10) * 4096)  # 2.0142 mA per code
    assert (2048 + Fraction(24, 10) / amps) // 1 == 3239  # floor(3239.6)


@pytest.mark.parametrize("name", sorted(HAND))
def test_units_and_limits_should_match_the_hand_values(name: str) -> None:
    o = oracle(load_spec(_spec(name)))
    p, volts, amps, zero, t_min, t_max, b_min, b_max, c_low, c_high = HAND[name]
    assert o.u.pwm_counts == p
    assert o.u.volts_per_code == volts and o.u.amps_per_code == amps
    assert o.u.zero_current_code == zero
    lim = o.lim
    assert (lim.period_min, lim.period_max) == (t_min, t_max)
    assert (lim.bus_min, lim.bus_max) == (b_min, b_max)
    assert (lim.current_low, lim.current_high) == (c_low, c_high)


def test_speed_and_current_conversions_by_hand() -> None:
    o = oracle(load_spec(_spec("offset_conventional.yaml")))
    assert o.u.rpm(3333) == Fraction(60 * 2_000_000, 6 * 4 * 3333)  # 1500.15 rpm
    assert o.u.amps(700) == (700 - Fraction(2048, 3)) * Fraction(3) / (Fraction(1, 10) * 4096)
    assert o.u.current_code(Fraction(0)) == 683  # nearest to 682.667


@pytest.mark.parametrize(
    "name", ["paper_motor.yaml", "offset_conventional.yaml", "hub_motor_46p.yaml"]
)
def test_switching_table_should_agree_with_the_derivation(name: str) -> None:
    """The oracle's table, from the paper's 60 deg example alone, against the
    generator's circuit-analysis derivation: every edge, both directions."""
    spec = load_spec(_spec(name))
    o = oracle(spec)
    table = derive().switching
    seq = spec.hall.sequence
    assert len(o.edges) == 12
    for (previous, code), switches in o.edges.items():
        k0, k1 = seq.index(previous), seq.index(code)
        direction = "forward" if k1 == (k0 + 1) % 6 else "reverse"
        edge = table.edge_into(k1, direction)
        assert switches == (int(edge.modulated_on[1:]) - 1, int(edge.modulated_off[1:]) - 1)
    # the paper's own edge: BA -> CA, T5 modulated at D_on, T3 at D_off
    assert o.edges[(5, 4)] == (4, 2) if seq[:2] == (5, 4) else True


def test_equations_should_agree_with_the_derivation() -> None:
    """Eqs. 16, 18 and 20 as the oracle writes them, against SymPy's derivation."""
    d = derive()
    rng = random.Random(4)
    rule, eq16, eq20 = d["18"], d["16"].row(""), d["20"].row("")
    for _ in range(200):
        e, u_d = Fraction(rng.randint(1, 140), 10), Fraction(rng.randint(150, 600), 10)
        current, inductance = Fraction(rng.randint(1, 100), 10), Fraction(rng.randint(1, 50), 10000)
        on = Fraction(rng.randint(0, 100), 100)
        sub = {s.E: sp.Rational(e), s.U_d: sp.Rational(u_d), s.D_on: sp.Rational(on)}
        x = 4 * e / u_d
        if 4 * e > u_d:  # Eq. 18 high
            assert sp.Rational(2 - x) == rule.row("on_high").subs(sub)
        else:
            assert sp.Rational(1 - x) == rule.row("off_low").subs(sub)
        assert sp.Rational(2 - on - x) == eq16.subs(sub)
        off = Fraction(rng.randint(0, 100), 100)
        w = u_d * (1 + on - 2 * off) - 2 * e
        if w > 0:
            hand = 3 * current * inductance / w
            derived = eq20.subs(
                {
                    **sub,
                    s.D_off: sp.Rational(off),
                    s.I: sp.Rational(current),
                    s.L: sp.Rational(inductance),
                }
            )
            assert sp.simplify(sp.Rational(hand) - derived) == 0


@pytest.mark.parametrize("shape", ["120 deg", "flat"])
def test_rule_should_agree_with_the_generators_reference(tmp_path: Path, shape: str) -> None:
    """The resistance-aware rule: the oracle's implementation (its own EMF shape from
    its switching table, a continuous zero, then the carrier boundary after it) and the
    generator's design reference (the derivation's terms, a search on the grid) are
    written independently; both give the same end and the same eased pair."""
    from codegen.core.module import build_core
    from codegen.methods.improved_r.constants import rule_constants
    from codegen.methods.improved_r.reference import FLAG_NOT_FINISHED, reference_batch

    text = (ROOT / "spec" / "paper_motor_improved_r.yaml").read_text(encoding="utf-8")
    path = tmp_path / "rule.yaml"
    marker = "  back_emf_convention: phase\n"
    path.write_text(text.replace(marker, marker + f"  back_emf_shape: {shape}\n"))
    spec = load_spec(path)
    o = oracle(spec)
    c = rule_constants(spec, build_core(spec).scaling)
    rng = np.random.default_rng(2)
    period = rng.integers(o.lim.period_min, o.lim.period_max, 400)
    bus = rng.integers(o.lim.bus_min, o.lim.bus_max, 400)
    current = rng.integers(o.lim.current_low, o.lim.current_high, 400)
    ref = reference_batch(c, period, bus, current)
    com = o.rule(period, bus, current)
    x, _ = com.zero()
    end = com.end_after(x * period)
    finished = (ref.flags & FLAG_NOT_FINISHED) == 0
    clear = np.minimum(np.abs(ref.h_end), np.abs(ref.h_before)) > 1e-6
    same = (end == np.where(finished, ref.end, ref.periods + 1)) | ~clear
    assert same.all()
    pair = com.pair_at(end)
    assert np.max(np.abs(pair.on - ref.on_exact)[clear]) < 1e-6
    assert np.max(np.abs(pair.off - ref.off_exact)[clear]) < 1e-6


@pytest.mark.parametrize(
    "path",
    [
        "spec/example_maxon_ec45_flat_48v.yaml",
        "tests/fixtures/odd/hallmin_asym.yaml",
        "tests/fixtures/odd/pp40_2rpm.yaml",
    ],
)
def test_the_period_range_should_be_every_interval_the_timer_reads_in_the_speed_range(
    path: str,
) -> None:
    """The Hall timer counts whole ticks: a sector of T ticks reads floor(T) or ceil(T).
    The generator's range and the oracle's own are [floor(T(speed_max)),
    ceil(T(speed_min))] (within the counter), T = f_hall x 10 / (p n), worked out here from
    the spec's values (a 1098.6 Hz Hall clock; 40 pole pairs from 2 rpm)."""
    import math

    from codegen.fixedpoint.scaling import scaling

    spec = load_spec(ROOT / path)
    ticks_60deg = spec.hall.timer_clock_hz * 10 / spec.motor.pole_pairs
    fastest = ticks_60deg / spec.controller.speed_max_rpm
    slowest = ticks_60deg / spec.controller.speed_min_rpm
    expected = (math.floor(fastest), min(math.ceil(slowest), 2**spec.hall.counter_bits - 1))
    lim = oracle(spec).lim
    assert (lim.period_min, lim.period_max) == expected
    sc = scaling(spec, derive())
    assert (sc.period_min_ticks, sc.period_max_ticks) == expected


@pytest.mark.parametrize(
    "path",
    [
        "spec/paper_motor_improved_r.yaml",
        "tests/fixtures/odd/pp24_flat_ir.yaml",
        "tests/fixtures/specs/short_sector_2k5_ir.yaml",
    ],
)
def test_the_rules_zero_should_be_the_bisections_within_its_width(path: str) -> None:
    """`Commutation.zero` narrows its brackets by false position (Illinois) and stops at
    ZERO_WIDTH_TICKS: against 56 plain bisection steps of the same g, written here, over
    the whole input box (zero currents, whose g(0) = 0, included) and the verifier's
    shifts, every zero within two widths and every carrier-boundary end the same but
    where the zero lies within that of a boundary."""
    from oracle.rule import ZERO_WIDTH_TICKS

    o = oracle(load_spec(ROOT / path))
    rng = np.random.default_rng(11)
    period = rng.integers(o.lim.period_min, o.lim.period_max + 1, 4000)
    bus = rng.integers(o.lim.bus_min, o.lim.bus_max + 1, 4000)
    current = rng.integers(0, o.u.adc_max + 1, 4000)
    com = o.rule(period, bus, current)
    for shift in (0.0, -0.01, 0.01, -1.0, 1.0):
        unfinished = com.current(np.ones_like(com.x), shift) > 0
        lo, hi = np.zeros_like(com.x), np.ones_like(com.x)
        for _ in range(56):
            mid = 0.5 * (lo + hi)
            above = com.current(mid, shift) > 0
            lo, hi = np.where(above, mid, lo), np.where(above, hi, mid)
        bisected = np.where(unfinished, 1.0, 0.5 * (lo + hi))
        z, flag = com.zero(shift)
        assert np.array_equal(flag, unfinished)
        ticks = com.sector_ticks
        assert np.max(np.abs(z - bisected) * ticks) <= 2 * ZERO_WIDTH_TICKS
        periods = bisected * ticks / com.carrier_ticks
        on_a_boundary = np.abs(periods - np.rint(periods)) * com.carrier_ticks <= 4e-9
        differ = com.end_after(z * ticks) != com.end_after(bisected * ticks)
        assert not (differ & ~on_a_boundary).any()


def test_the_integrators_tolerance_should_be_the_verifiers_own(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """A generator held to a looser step response must not move verify's yardstick: a
    hunt's mutant (codegen.spec_model's 5 time constants made 1) had made the integrator
    check five times looser, as verify took the constant from the generator."""
    spec = load_spec(_spec("paper_motor.yaml"))
    # 1 count spread over 5 f_pwm / (2 pi f_c) = 5 x 20 kHz / (2 pi x 1 kHz) = 15.92
    # PWM periods: 0.0628 counts a step
    by_hand = 2 * math.pi * 1000 / (5 * 20_000)
    assert integrator_tolerance(spec, 1.0) == pytest.approx(by_hand, rel=1e-12)
    assert spec_model.integrator_step_tolerance_counts(spec) == pytest.approx(by_hand, rel=1e-12)
    monkeypatch.setattr(spec_model, "STEP_RESPONSE_TIME_CONSTANTS", 1)
    assert spec_model.integrator_step_tolerance_counts(spec) == pytest.approx(5 * by_hand)
    assert integrator_tolerance(spec, 1.0) == pytest.approx(by_hand, rel=1e-12)

"""Unusual motors every command was run on (generate, firmware, verify, unity, prove on
two, simulate, the PIL's fault scenarios): here each is generated twice (byte-identical)
and verified against the oracle; and one test for each bug the later ones exposed."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace
from fractions import Fraction
from pathlib import Path
from types import SimpleNamespace

import pytest

from codegen.audit.transcription import load_transcription
from codegen.core.module import build_core
from codegen.generate import render_all, write_tree
from codegen.methods.base import FixedPointError
from codegen.spec_loader import load_spec
from emulation.pil.report import summary_line
from sim import report
from sim.drive import Drive
from sim.table4 import table4_study
from verify.run import VerifyResult, verify

ROOT = Path(__file__).resolve().parents[1]
ODD = ROOT / "tests" / "fixtures" / "odd"


@pytest.mark.parametrize(
    "name",
    [
        "pp1_60krpm_20k",
        "pp30_5_to_120rpm",
        "rev_hall_centre_shunts_sc",
        "heavy_l_finer_integrator",
        "hv600_20mh_integrator_q4",
    ],
)
def test_an_unusual_motor_should_regenerate_identically_and_verify(
    tmp_path: Path, name: str
) -> None:
    spec = ODD / f"{name}.yaml"
    first, second = render_all(spec).files, render_all(spec).files
    assert first == second
    generated = tmp_path / "generated"
    write_tree(first, generated)
    result, _, _, _ = verify(
        spec,
        generated,
        tmp_path / "build",
        seed=20261129,
        random_count=500,
        exhaustive_stride=7,
        show_progress=False,
    )
    failed = [f"{k}: {c.note}" for k, c in result.checks.items() if c.verdict != "PASS"]
    assert result.passed, failed


def test_claims_on_table4_speeds_outside_the_range_should_say_not_tested() -> None:
    """A motor whose speed range holds none of Table 4's speeds (1000-2500 rpm): claims
    4 and 5 are neither reproduced nor refuted, and the section says why (`simulate`
    reported both 'refuted' with an empty evidence and printed empty tables)."""
    spec = load_spec(ODD / "pp1_150k_centre_conv.yaml")
    drive = Drive.from_spec(spec)
    rows = load_transcription().table4
    # no Table 4 speed inside: no commutation is simulated, so no controller is needed
    study = table4_study(None, drive, rows)  # type: ignore[arg-type]
    assert study.spec_improved == () and study.spec_conventional == ()
    results = SimpleNamespace(table4_study=study, table4=rows, drive=drive)
    claims = report._table4_claims(results)  # type: ignore[arg-type]
    assert [c["verdict"] for c in claims] == [report.NOT_TESTED, report.NOT_TESTED]
    for claim in claims:
        assert "1000-2500 rpm" in claim["evidence"], claim
        assert "10000-150000 rpm" in claim["evidence"], claim
    assert "outside the simulated speed range" in report._table4(results)["outside"]  # type: ignore[arg-type,operator]


def test_pil_summary_should_count_the_braking_run() -> None:
    """`make pil` printed '22/22 scenarios pass' for a spec whose braking run failed
    (and exited 1): the summary names the braking run's verdict too."""
    failed = summary_line("m", 22, 22, object(), ["the rotor did not reach 15000 rpm"])  # type: ignore[arg-type]
    assert failed == "pil: m: 22/22 fault scenarios pass, braking run FAILS"
    assert summary_line("m", 22, 22, object(), []).endswith("braking run passes")  # type: ignore[arg-type]
    assert summary_line("m", 21, 22, None, []).endswith(
        "21/22 fault scenarios pass, braking run off"
    )


def _hall_clock_refusal(path: Path) -> str:
    """The core's refusal of the spec at `path`, which must name hall.timer_clock."""
    with pytest.raises(FixedPointError) as caught:
        build_core(load_spec(path))
    assert caught.value.key == "hall.timer_clock"
    return str(caught.value)


def test_a_hall_clock_that_overflows_every_format_should_be_named(tmp_path: Path) -> None:
    """A 72 MHz Hall clock against a 2.25 kHz PWM: Eq. 20's product overflows int32_t
    in every format, Q0 included. The refusal named accuracy.commutation_time_ticks,
    which no value could meet; it names hall.timer_clock and a clock that designs."""
    path = ROOT / "tests" / "fixtures" / "refused" / "hall72m_pwm2k25_centre.yaml"
    message = _hall_clock_refusal(path)
    assert message.startswith("hall.timer_clock = 72000000 Hz: no format from Q0 to Q12 is safe")
    # Q0 would fit up to 27.5 MHz; X needs 3 bits where the spec holds t_com to 8 ticks
    assert message.endswith(
        "(allowed: <= 3.43605e+06 Hz, 72000000 Hz / N for N >= 21: 3428571.429 Hz)"
    )
    text = path.read_text(encoding="utf-8")
    assert text.count("  timer_clock: 72 MHz\n") == 2  # TIM1's and TIM3's
    named = tmp_path / "named.yaml"
    named.write_text(
        text.replace(
            "  timer_clock: 72 MHz\n  counter_bits", "  timer_clock: 3 MHz\n  counter_bits"
        )
    )
    assert "  timer_clock: 3 MHz\n" in named.read_text()
    build_core(load_spec(named))  # the clock named does design


def test_a_core_that_misses_the_target_where_verify_holds_it_should_be_refused(
    tmp_path: Path, generate_and_verify: Callable[..., tuple[VerifyResult, object, Path]]
) -> None:
    """50 mH on 24 V with a 1 MHz Hall clock: Eq. 20's numerator times the current code
    leaves X no fraction bit, so W errs by half a count, and where the spec holds t_com
    to 8 ticks (one count of W moves it by up to 80) that is up to 40 ticks. The design
    claimed 8 ticks only where W >= 4405 counts; `generate` wrote it and `verify` failed
    it (35.5 ticks at 164 rpm). It is refused, naming the Hall clock that designs, and
    that clock's firmware verifies."""
    path = ROOT / "tests" / "fixtures" / "refused" / "l50mh_wide_sense.yaml"
    message = _hall_clock_refusal(path)
    assert message.startswith("hall.timer_clock = 1000000 Hz: X's widest safe format, Q0 ")
    assert "by 40.82 Hall ticks where the spec holds it to" in message  # 40.813, up
    assert message.endswith("(allowed: <= 125000 Hz, 72000000 Hz / N for N >= 576: 125000 Hz)")
    text = path.read_text(encoding="utf-8")
    assert text.count("  timer_clock: 1 MHz\n") == 1
    named = tmp_path / "named.yaml"
    named.write_text(text.replace("  timer_clock: 1 MHz\n", "  timer_clock: 125 kHz\n"))
    result, _, _ = generate_and_verify(named, seed=20261129, stride=3)
    failed = [f"{k}: {c.note}" for k, c in result.checks.items() if c.verdict != "PASS"]
    assert result.passed, failed


def test_a_flat_emf_spec_should_rotate_the_plant_and_the_sil_alike() -> None:
    """The spec's `flat` freezes the EMFs at an edge, which no rotating motor does: the
    emulated drive's plant turns the 120 deg trapezoid it idealises, and the SIL it holds
    each commutation to must turn the same one (`Drive.rotating`)."""
    drive = Drive.from_spec(load_spec(ODD / "pp24_flat_ir.yaml"))
    assert drive.emf_frozen
    rotating = drive.rotating()
    assert not rotating.emf_frozen
    assert rotating.emf_points == drive.with_flat_top(120.0).emf_points
    other = Drive.from_spec(load_spec(ROOT / "spec" / "paper_motor.yaml"))
    assert other.rotating() == other  # every other shape is its own


@pytest.mark.heavy(seconds=6)
def test_a_flat_emf_motor_should_brake_in_the_pil_as_in_the_sil(tmp_path: Path) -> None:
    """24 pole pairs, flat EMF, improved_r: the first Hall edges of `make pil`'s braking
    run. The SIL froze the EMFs at the edge while the chip's plant turned them: every
    commutation read 3 to 9 pp apart (required: 1 pp)."""
    _brakes_its_first_edges(ODD / "pp24_flat_ir.yaml", tmp_path)


def _brakes_its_first_edges(path: Path, tmp_path: Path) -> None:
    """The first Hall edges of `make pil`'s braking run past its settling ones: at least
    three commutations measured, no problem found."""
    from emulation.pil.braking import SETTLING_EDGES, brake, braking_setup
    from emulation.pil.braking_report import problems
    from emulation.pil.build import build_firmware, generate

    spec = load_spec(path)
    generated = generate(path, tmp_path / "generated")
    elf = build_firmware(path, tmp_path, generated)
    setup = replace(braking_setup(spec, short=True), max_edges=SETTLING_EDGES + 4)
    result = brake(elf, generated / "c" / "stm32f103_port.c", spec, setup)
    assert len(result.commutations) >= 3
    assert problems(result) == []


def test_a_braking_run_should_stop_above_where_the_saturated_loop_holds_no_current() -> None:
    """An 80 kHz motor whose sample window leaves its loop a D_max of 0.84: below 2573 rpm
    the loop saturates and its current, (2E - (1 - D_max) U_d) / 2R, is gone at 1933 rpm.
    `make pil` braked towards a tenth of its top speed, 1140 rpm, which the rotor never
    reaches (over half an hour of emulation): the run stops where the saturated loop still
    drives half the current, 2253 rpm."""
    from codegen.control.sensing import sense_design
    from emulation.pil.braking import HELD_SHARE, braking_setup, held_down_to_rpm

    spec = load_spec(ODD / "lv12_3uh_80k.yaml")
    window = sense_design(spec).window
    d_max = window.duty_max_counts / window.period_counts
    assert d_max < 0.84
    bus = float(spec.inverter.bus_voltage_nominal_v)
    k_e = float(spec.motor.back_emf_constant_v_per_rpm)
    gone = (1.0 - d_max) * bus / (2.0 * k_e)  # no current left at all
    held = held_down_to_rpm(spec, 40.0)
    assert 1900 < gone < held < 2600
    setup = braking_setup(spec, short=False)
    assert setup.stop_rpm == pytest.approx(gone + HELD_SHARE * (held - gone))
    assert held > setup.stop_rpm > gone > 0.1 * float(spec.controller.speed_max_rpm)


def test_a_commutation_longer_than_its_sector_should_be_warned_of(tmp_path: Path) -> None:
    """A 20-pole-pair 3 mH outrunner on the paper motor's k_e, braking 5 A (10 A at most),
    as an earlier `init` wrote it: an improved commutation lasts I L/(2E) wherever
    4E <= U_d, I L p/(20 k_e) of a sector at every such speed, 12.7 sectors at 10 A.
    `make pil` braked it from 1159 to 923 rpm in 2011 Hall edges with no commutation
    measured; the spec had loaded without a warning. Below 20 k_e/(p L) = 0.787 A it
    does not warn."""
    path = ODD / "outrunner20_3mh_5a.yaml"
    (warning,) = [w for w in load_spec(path).warnings if w.id == "commutation-fills-sectors"]
    assert "12.7119 sectors" in warning.message
    assert "20 k_e/(p L) = 0.786667 A" in warning.message
    assert warning.path == "controller.braking_current_max"
    text = path.read_text()
    for key, before, after in [
        ("braking_current_nominal", "5 A", "0.39 A"),
        ("braking_current_max", "10 A", "0.78 A"),
    ]:
        assert f"  {key}: {before}\n" in text
        text = text.replace(f"  {key}: {before}\n", f"  {key}: {after}\n")
    below = tmp_path / "below.yaml"
    below.write_text(text)
    assert "commutation-fills-sectors" not in [w.id for w in load_spec(below).warnings]


@pytest.mark.heavy(seconds=8)
def test_init_should_brake_a_many_pole_high_inductance_outrunner_with_commutations(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """`init` now takes the braking current whose commutation at braking_current_max lasts
    half a sector where 4E <= U_d, 20 k_e/(4 p L) = 0.197 A here (0.19 A), and the PIL's
    braking run measures its commutations from the first edges on."""
    from bldc import cli

    monkeypatch.chdir(tmp_path)
    argv = ["init", "outrunner20", "--pole-pairs", "20", "--inductance-line-to-line", "6 mH"]
    argv += ["--pwm-frequency", "12 kHz", "--method", "improved_r", "-o", "o.yaml"]
    assert cli.main(argv) == 0
    path = tmp_path / "o.yaml"
    spec = load_spec(path)
    assert spec.controller.braking_current_nominal_a == Fraction(19, 100)
    assert "commutation-fills-sectors" not in [w.id for w in spec.warnings]
    _brakes_its_first_edges(path, tmp_path / "run")


def test_a_preferred_short_circuit_rated_below_the_speed_range_should_be_warned_of(
    tmp_path: Path,
) -> None:
    """A hunt's improved_r spec prefers the short circuit, rated 40 A: its peak is within
    that only up to 904 rpm (725 rpm for the worst motor the spec's tolerances declare),
    below speed_min (1300 rpm), so the firmware applies all-off throughout the range,
    which the spec did not ask for, and nothing said so. Rated for the worst corner's
    peak at speed_min (57.5 A), the warning goes."""
    path = ODD / "ir_table_short_unrated.yaml"
    (warning,) = [w for w in load_spec(path).warnings if w.id == "short-circuit-never-rated"]
    assert warning.path == "protection.safe_state"
    assert "at speed_min 1300 rpm is up to 57.5 A" in warning.message
    assert ">= 58 A" in warning.message
    rated = tmp_path / "rated.yaml"
    text = path.read_text(encoding="utf-8")
    assert text.count("  short_circuit_current_max: 40 A\n") == 1
    rated.write_text(
        text.replace("short_circuit_current_max: 40 A", "short_circuit_current_max: 58 A")
    )
    assert "short-circuit-never-rated" not in [w.id for w in load_spec(rated).warnings]

"""The oracle's own reading of the spec's quantities (oracle/quantities.py).

* on every checked-in spec and every fixture the loader accepts, the oracle's conversion
  from the YAML agrees with the loader's, key by key;
* two generator mutants that verify did not see (its yardstick took the loader's values)
  are caught by the cross-check, on the key they move: S1, a phase k_e halved as if it
  were line to line; S2, rpm per rad/s written 60/pi (a k_e in V*s/rad off by 2);
* a hand-worked spec: R in mohm, L in uH, k_e in V*s/rad, mV/rpm, V/krpm and line to
  line on a 30 deg flat top, against values worked out here.
"""

from __future__ import annotations

import sys
import types
from fractions import Fraction
from pathlib import Path

import pytest

import codegen.spec_loader as spec_loader
from codegen.errors import SpecError
from codegen.spec_loader import load_spec
from codegen.spec_model import BackEmfShape
from oracle.emf_shape import line_to_line_peak
from oracle.quantities import (
    EMF_CONSTANT,
    INDUCTANCE,
    PI,
    RESISTANCE,
    cross_check,
    quantity,
)
from verify.run import quantity_checks

ROOT = Path(__file__).resolve().parents[1]
PAPER = ROOT / "spec" / "paper_motor.yaml"
K_E_LINE = "  back_emf_constant: 2.36 V/krpm\n  back_emf_convention: phase\n"


def _accepted() -> list[Path]:
    """Every checked-in spec and YAML fixture the loader accepts (the others are refusal
    fixtures: there is no Spec to compare with)."""
    out = []
    for path in sorted(ROOT.glob("spec/*.yaml")) + sorted(ROOT.glob("tests/fixtures/**/*.yaml")):
        try:
            load_spec(path)
        except SpecError:
            continue
        out.append(path)
    return out


ACCEPTED = _accepted()


def _disagreeing(path: Path, spec: object) -> dict[str, str]:
    return {row.key: row.line() for row in cross_check(path, spec) if not row.agrees}  # type: ignore[arg-type]


def test_the_list_of_specs_should_hold_the_checked_in_ones() -> None:
    names = {p.name for p in ACCEPTED}
    assert {
        "paper_motor.yaml",
        "paper_motor_improved_r.yaml",
        "example_maxon_ec45_flat_48v.yaml",
    } <= names
    assert len(ACCEPTED) > 50


@pytest.mark.parametrize("path", ACCEPTED, ids=[str(p.relative_to(ROOT)) for p in ACCEPTED])
def test_the_oracle_should_read_every_quantity_as_the_loader_does(path: Path) -> None:
    spec = load_spec(path)
    rows = cross_check(path, spec)
    assert {r.key for r in rows} >= {
        "motor.back_emf_constant",
        "motor.phase_resistance",
        "motor.phase_inductance",
        "motor.poles",
        "inverter.pwm_frequency",
        "inverter.timer_clock",
        "inverter.dead_time",
        "hall.timer_clock",
        "adc.reference",
        "adc.bus_voltage_divider",
        "adc.current_gain",
        "adc.current_offset",
        "controller.braking_current_max",
        "controller.speed_max",
        "accuracy.duty_counts",
    }
    assert not [r.line() for r in rows if not r.agrees]


# ------------------------------------------------------------------ generator mutants


def _patched_module(
    monkeypatch: pytest.MonkeyPatch, source: Path, name: str, original: str, mutant: str
) -> types.ModuleType:
    """A copy of a generator module with one line changed, loaded under its own name."""
    text = source.read_text(encoding="utf-8")
    assert text.count(original) == 1, f"the mutant's line is no longer in {source.name}"
    module = types.ModuleType(name)
    module.__file__ = str(source)
    monkeypatch.setitem(sys.modules, name, module)
    exec(compile(text.replace(original, mutant), str(source), "exec"), module.__dict__)
    return module


def _s1_loader(monkeypatch: pytest.MonkeyPatch) -> types.ModuleType:
    """Mutant S1: the loader halves a phase constant as if it were line to line."""
    return _patched_module(
        monkeypatch,
        ROOT / "codegen" / "spec_loader.py",
        "codegen._spec_loader_s1",
        'if convention == "line_to_line":\n        # The datasheet',
        'if convention in ("line_to_line", "phase"):\n        # The datasheet',
    )


def test_s1_a_phase_constant_halved_as_line_to_line_should_fail_on_k_e(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    mutant = _s1_loader(monkeypatch)
    wrong = mutant.load_spec(PAPER)
    right = load_spec(PAPER)
    assert wrong.motor.back_emf_constant_v_per_rpm * 2 == right.motor.back_emf_constant_v_per_rpm
    bad = _disagreeing(PAPER, wrong)
    assert list(bad) == ["motor.back_emf_constant"], bad
    assert bad["motor.back_emf_constant"] == (
        "motor.back_emf_constant: '2.36 V/krpm (phase)' -> oracle 0.00236 V/rpm,"
        " loader 0.00118 V/rpm"
    )
    checks = quantity_checks(cross_check(PAPER, wrong))
    assert checks["quantities"].verdict == "FAIL"
    row = checks["quantity motor.back_emf_constant"]
    assert row.verdict == "FAIL" and row.max_error == pytest.approx(0.5)
    assert [k for k, c in checks.items() if c.verdict == "FAIL"] == [
        "quantities",
        "quantity motor.back_emf_constant",
    ]


def test_s2_rpm_per_rad_s_written_60_over_pi_should_fail_on_k_e(
    monkeypatch: pytest.MonkeyPatch, tmp_path: Path
) -> None:
    spec = tmp_path / "paper_motor.yaml"
    text = PAPER.read_text(encoding="utf-8")
    assert text.count("back_emf_constant: 2.36 V/krpm") == 1
    spec.write_text(
        text.replace("back_emf_constant: 2.36 V/krpm", "back_emf_constant: 0.0225364 V*s/rad"),
        encoding="utf-8",
    )
    assert not _disagreeing(spec, load_spec(spec))  # unmutated: within 1e-12
    mutant = _patched_module(
        monkeypatch,
        ROOT / "codegen" / "units.py",
        "codegen._units_s2",
        "_RPM_PER_RAD_S = 60.0 / (2.0 * math.pi)",
        "_RPM_PER_RAD_S = 60.0 / math.pi",
    )
    monkeypatch.setattr(spec_loader, "units", mutant)
    wrong = spec_loader.load_spec(spec)
    monkeypatch.undo()
    assert wrong.motor.back_emf_constant_v_per_rpm == pytest.approx(
        float(load_spec(spec).motor.back_emf_constant_v_per_rpm) / 2, rel=1e-12
    )
    bad = _disagreeing(spec, wrong)
    assert list(bad) == ["motor.back_emf_constant"], bad
    assert bad["motor.back_emf_constant"].startswith(
        "motor.back_emf_constant: '0.0225364 V*s/rad (phase)' -> oracle 0.00236000628928"
    )
    checks = quantity_checks(cross_check(spec, wrong))
    assert checks["quantity motor.back_emf_constant"].verdict == "FAIL"


def test_verify_should_run_the_cross_check_first_and_fail_on_s1(
    monkeypatch: pytest.MonkeyPatch, tmp_path: Path
) -> None:
    """verify itself: the loader it calls is S1's; the cross-check is its first row, and
    the run fails on motor.back_emf_constant (the checked-in core, a few points)."""
    import verify.run as run

    mutant = _s1_loader(monkeypatch)
    monkeypatch.setattr(run, "load_spec", mutant.load_spec)
    result, _, _, _ = run.verify(
        PAPER,
        ROOT / "generated" / "paper_motor",
        tmp_path / "build",
        seed=20261121,
        random_count=500,
        exhaustive_stride=97,
        show_progress=False,
    )
    assert not result.passed
    assert list(result.checks)[:2] == ["quantities", "quantity motor.back_emf_constant"]
    assert result.checks["quantity motor.back_emf_constant"].verdict == "FAIL"
    assert "loader 0.00118 V/rpm" in result.checks["quantity motor.back_emf_constant"].note


# ------------------------------------------------------------------ worked by hand


def test_units_should_convert_as_worked_by_hand() -> None:
    # 210 mohm = 210 / 1000 ohm = 21/100; 560 uH = 560 / 10^6 H = 7/12500
    assert quantity("210 mohm", RESISTANCE) == (Fraction(21, 100), True)
    assert quantity("560 uH", INDUCTANCE) == (Fraction(7, 12500), True)
    # 2.36 mV/rpm = 2.36 / 1000 V/rpm; 2.36 V/krpm = 2.36 V per 1000 rpm: both 59/25000
    assert quantity("2.36 mV/rpm", EMF_CONSTANT) == (Fraction(59, 25000), True)
    assert quantity("2.36 V/krpm", EMF_CONSTANT) == (Fraction(59, 25000), True)
    # 0.0225364 V*s/rad: one rpm is 2 pi / 60 rad/s = 0.10471975511965977 rad/s, so
    # 0.0225364 x 0.10471975511965977 = 0.0023600062892787 V/rpm (pi enters: not exact)
    value, exact = quantity("0.0225364 V*s/rad", EMF_CONSTANT)
    assert not exact and float(value) == pytest.approx(0.0023600062892787, rel=1e-14)
    assert value == Fraction("0.0225364") * 2 * PI / 60


def test_line_to_line_peak_should_be_worked_by_hand() -> None:
    # 120 deg flat top (rise 30 deg): a at +1 over [30, 150] deg; b(t) = e(t - 120) at
    # -1 where t - 120 lies in [210, 330], t in [330, 450] = [330, 360) + [0, 90]: both
    # at once over [30, 90], where e_a - e_b = 1 - (-1) = 2
    assert line_to_line_peak(BackEmfShape.trapezoid(Fraction(120)).points) == 2
    # 30 deg flat top, rise 75 deg: at 60 deg, a = 60/75 = 0.8, b = e(-60) = -e(120)
    # = -(180 - 120)/75 = -0.8; from 60 to 75 deg a rises and b falls by as much, so
    # e_a - e_b = 1.6 there, its peak (at 90 deg: 1 + 30/75 = 1.4)
    assert line_to_line_peak(BackEmfShape.trapezoid(Fraction(30)).points) == Fraction(8, 5)


#: (k_e as written, its convention, EMF shape, the phase k_e in V/rpm worked by hand)
HAND_K_E = [
    # 2.36 mV/rpm = 0.00236 V/rpm = 59/25000
    ("2.36 mV/rpm", "phase", None, Fraction(59, 25000)),
    # 4.72 V/krpm line to line, 120 deg trapezoid (lambda 2): 4.72 / 1000 / 2 = 0.00236
    ("4.72 V/krpm", "line_to_line", None, Fraction(59, 25000)),
    # 3.776 V/krpm line to line, 30 deg flat top (lambda 8/5): 0.003776 / 1.6 = 0.00236
    ("3.776 V/krpm", "line_to_line", "30 deg", Fraction(59, 25000)),
    # 0.0225364 V*s/rad x 2 pi / 60 = 0.0023600062892787 V/rpm (see above)
    ("0.0225364 V*s/rad", "phase", None, Fraction("0.0023600062892787")),
    # 0.0450728 V*s/rad line to line (lambda 2): half of 0.0450728 x pi / 30, the same
    ("0.0450728 V*s/rad", "line_to_line", None, Fraction("0.0023600062892787")),
]


@pytest.mark.parametrize(("written", "convention", "shape", "phase_k_e"), HAND_K_E)
def test_a_hand_worked_spec_should_read_as_worked_out(
    tmp_path: Path, written: str, convention: str, shape: str | None, phase_k_e: Fraction
) -> None:
    text = PAPER.read_text(encoding="utf-8")
    assert text.count(K_E_LINE) == 1
    motor = f"  back_emf_constant: {written}\n  back_emf_convention: {convention}\n"
    if shape is not None:
        motor += f"  back_emf_shape: {shape}\n"
    text = text.replace(K_E_LINE, motor)
    text = text.replace("phase_resistance: 0.21 ohm", "phase_resistance: 210 mohm")
    text = text.replace("phase_inductance: 0.56 mH", "phase_inductance: 560 uH")
    path = tmp_path / "hand.yaml"
    path.write_text(text, encoding="utf-8")
    spec = load_spec(path)
    rows = {r.key: r for r in cross_check(path, spec)}
    assert not [r.line() for r in rows.values() if not r.agrees]
    assert rows["motor.phase_resistance"].oracle == Fraction(21, 100)
    assert rows["motor.phase_inductance"].oracle == Fraction(7, 12500)
    k_e = rows["motor.back_emf_constant"]
    assert k_e.raw == f"{written} ({convention})"
    assert isinstance(k_e.oracle, Fraction)
    if "V*s/rad" in written:
        assert not k_e.exact
        assert float(k_e.oracle) == pytest.approx(float(phase_k_e), rel=1e-14)
    else:
        assert k_e.exact and k_e.oracle == phase_k_e


def test_a_unit_the_oracle_does_not_know_should_be_a_disagreement(tmp_path: Path) -> None:
    """A loader that accepted a spelling the oracle's table lacks is named, not passed."""
    spec = load_spec(PAPER)
    from oracle.quantities import convert, read_raw

    data = read_raw(PAPER.read_bytes())
    data["motor"]["phase_inductance"] = "0.56 millihenry"
    bad = {r.key: r for r in convert(data, spec) if not r.agrees}
    assert list(bad) == ["motor.phase_inductance"]
    assert "not in the oracle's table" in bad["motor.phase_inductance"].line()


@pytest.mark.parametrize(
    ("old", "new"),
    [
        # YAML 1.2 octal integers, which the spec's reader takes and PyYAML leaves strings
        ("  poles: 2\n", "  poles: 0o2\n"),
        ("  bits: 12\n", "  bits: 0o14\n"),
        ("  bus_voltage_divider: 11\n", "  bus_voltage_divider: 0o13\n"),
        # a line break after the value: a quoted "...\n" and a literal block
        ("  phase_inductance: 0.56 mH\n", '  phase_inductance: "0.56 mH\\n"\n'),
        ("  phase_inductance: 0.56 mH\n", "  phase_inductance: |\n    0.56 mH\n"),
        # a table entry of 17 digits: the loader had rounded it to a double
        (
            "  back_emf_convention: phase\n",
            "  back_emf_convention: phase\n"
            "  back_emf_shape: [[0, 0], [30, 0.99999999999999999], [150, 1], [180, 0]]\n",
        ),
    ],
    ids=["octal-poles", "octal-bits", "octal-divider", "quoted-newline", "literal", "table-17"],
)
def test_a_value_the_loader_takes_should_read_the_same_to_the_oracle(
    tmp_path: Path, old: str, new: str
) -> None:
    """A hunt's valid specs on which verify failed at its first check: the oracle's
    PyYAML reading and the loader's YAML 1.2 one parted on octal integers and on a line
    break after a value, and the loader rounded a measured table's long entries."""
    text = PAPER.read_text(encoding="utf-8")
    assert text.count(old) == 1
    path = tmp_path / "variant.yaml"
    path.write_text(text.replace(old, new), encoding="utf-8")
    spec = load_spec(path)
    assert _disagreeing(path, spec) == {}
    if "0.99999999999999999" in new:
        assert spec.motor.back_emf_shape.points[1][1] == Fraction(99999999999999999, 10**17)

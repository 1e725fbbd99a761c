"""Each motor's DERIVATION.md: its own numbers, checked against closed forms typed here
from the paper (not read from the derivation), and nothing of the paper audit."""

from __future__ import annotations

from fractions import Fraction
from pathlib import Path

import pytest

from codegen.audit.motor_report import DUTY_GRID, render_derivation
from codegen.derivation import derive
from codegen.spec_loader import load_spec
from codegen.spec_model import Spec

ROOT = Path(__file__).resolve().parents[1]
SPECS = [
    ROOT / "spec" / "paper_motor.yaml",
    ROOT / "spec" / "paper_motor_improved_r.yaml",
    ROOT / "spec" / "example_maxon_ec45_flat_48v.yaml",
    *sorted((ROOT / "tests" / "fixtures" / "specs").glob("*.yaml")),
]


def _rpm(value: Fraction) -> str:
    return f"{float(value):.1f} rpm"


def _duty(value: Fraction) -> str:
    return f"{float(value):.4g}"


@pytest.fixture(scope="module", params=SPECS, ids=[p.stem for p in SPECS])
def motor(request: pytest.FixtureRequest) -> tuple[Spec, str]:
    spec = load_spec(request.param)
    return spec, render_derivation(derive(), spec)


def test_limits_should_be_the_cut_off_and_upper_limit_at_each_bus_voltage(
    motor: tuple[Spec, str],
) -> None:
    spec, text = motor
    k_e = spec.motor.back_emf_constant_v_per_rpm
    inverter = spec.inverter
    for volts in (
        inverter.bus_voltage_min_v,
        inverter.bus_voltage_nominal_v,
        inverter.bus_voltage_max_v,
    ):
        row = f"V | {_rpm(volts / (4 * k_e))} | {_rpm(volts / (2 * k_e))} |"
        assert row in text, row


def test_operating_points_should_carry_the_duties_and_commutation_time(
    motor: tuple[Spec, str],
) -> None:
    spec, text = motor
    bus = spec.inverter.bus_voltage_nominal_v
    k_e = spec.motor.back_emf_constant_v_per_rpm
    current = spec.controller.braking_current_nominal_a
    inductance = spec.motor.phase_inductance_h
    for point in spec.operating_points:
        emf = k_e * point.speed_rpm
        if point.speed_rpm <= bus / (4 * k_e):  # Eq. 18, low-speed segment
            segment, on, off = "low", Fraction(1), 1 - 4 * emf / bus
            t_com = current * inductance / (2 * emf)  # Eq. 20 with those duties
        else:
            segment, on, off = "high", 2 - 4 * emf / bus, Fraction(0)
            t_com = current * inductance / (bus - 2 * emf)
        conventional = 2 - 4 * emf / bus - point.main_duty  # Eq. 16
        sector = Fraction(60) / (6 * point.speed_rpm * spec.motor.pole_pairs)
        row = (
            f"| {segment} | {_duty(on)} | {_duty(off)} | {float(t_com) * 1e6:.1f} us |"
            f" {float(sector) * 1e6:.1f} us | {_duty(point.main_duty)} |"
            f" {_duty(conventional)} | {'no' if 0 <= conventional <= 1 else 'yes'} |"
        )
        assert row in text, row


def test_fail_area_should_bound_the_conventional_duty(motor: tuple[Spec, str]) -> None:
    spec, text = motor
    bus = spec.inverter.bus_voltage_nominal_v
    k_e = spec.motor.back_emf_constant_v_per_rpm
    controller = spec.controller
    for duty in sorted(set(DUTY_GRID) | {p.main_duty for p in spec.operating_points}):
        # D_off = 2 - 4 k_e n / U_d - D leaves [0, 1] outside these speeds.
        slow, fast = (1 - duty) * bus / (4 * k_e), (2 - duty) * bus / (4 * k_e)
        fails = []
        if slow > controller.speed_min_rpm:
            fails.append(f"below {_rpm(slow)} ($D_{{off}} > 1$)")
        if fast < controller.speed_max_rpm:
            fails.append(f"above {_rpm(fast)} ($D_{{off}} < 0$)")
        row = (
            f"| {_duty(duty)} | {_rpm(max(slow, Fraction(0)))} to {_rpm(fast)} |"
            f" {', '.join(fails) or 'nowhere in the speed range'} |"
        )
        assert row in text, row


def test_switching_table_should_use_the_spec_hall_codes(motor: tuple[Spec, str]) -> None:
    spec, text = motor
    rows = [line for line in text.splitlines() if line.startswith(("| forward", "| reverse"))]
    assert len(rows) == 12
    for k, code in enumerate(spec.hall.sequence):
        assert f"| forward | {code} ({code:03b}) | {60 * k}-{60 * (k + 1)} |" in text


def test_derivation_should_not_repeat_the_paper_audit(motor: tuple[Spec, str]) -> None:
    spec, text = motor
    assert len(text) < 8000
    for paper_only in ("Table 2", "Table 4", "citation", "caption", "mismatch", "Finding"):
        assert paper_only not in text
    assert "(../paper/AUDIT.md)" in text
    first = text.splitlines()[0]
    assert "templates/audit/DERIVATION.md.j2" in first and spec.sha256 in first


def test_a_description_should_stay_plain_text_in_the_report(tmp_path: Path) -> None:
    """A spec's description opens DERIVATION.md's first paragraph: a heading, a script
    and a list item written into it had been printed as such."""
    text = (ROOT / "spec" / "paper_motor.yaml").read_text(encoding="utf-8")
    line = next(x for x in text.splitlines() if x.startswith("description: "))
    hostile = 'description: "- x\\n\\n# Injected heading\\n<script>alert(1)</script> [a](b)"'
    path = tmp_path / "hostile.yaml"
    path.write_text(text.replace(line, hostile), encoding="utf-8")
    report = render_derivation(derive(), load_spec(path))
    first = next(p for p in report.split("\n\n") if "Commutation method" in p)
    assert first.startswith(
        "\\- x \\# Injected heading &lt;script&gt;alert(1)&lt;/script&gt; \\[a\\](b). "
    ), first
    assert "\n# Injected" not in report and "<script>" not in report


@pytest.mark.parametrize("char", ["\u202e", "\u200f", "\u2066"])
def test_an_invisible_character_in_the_spec_text_should_be_refused(
    tmp_path: Path, char: str
) -> None:
    """A right-to-left override, a right-to-left mark or a left-to-right isolate in the
    description or a source: the text reads in another order than it is stored
    (accepted before; raw control characters the YAML reader refuses)."""
    from codegen.errors import SpecError

    text = (ROOT / "spec" / "paper_motor.yaml").read_text(encoding="utf-8")
    for old in ("description: Table 3", 'motor.poles: "'):
        path = tmp_path / "hidden.yaml"
        path.write_text(text.replace(old, old + char, 1), encoding="utf-8")
        with pytest.raises(SpecError, match=f"invisible or control character U\\+{ord(char):04X}"):
            load_spec(path)


@pytest.mark.parametrize(
    "text", ["Motör 24 V – 3 kW", "👩\u200d🔧 fitter's motor", "می\u200cخواهم", "hub\u00admotor"]
)
def test_text_with_joiners_and_soft_hyphens_should_load(tmp_path: Path, text: str) -> None:
    """A zero-width joiner (an emoji sequence, a Persian word) and a soft hyphen are
    text, not hidden controls (the first check refused every format character)."""
    source = (ROOT / "spec" / "paper_motor.yaml").read_text(encoding="utf-8")
    line = next(x for x in source.splitlines() if x.startswith("description: "))
    path = tmp_path / "text.yaml"
    path.write_text(source.replace(line, f'description: "{text}"'), encoding="utf-8")
    assert load_spec(path).description == text


@pytest.mark.parametrize(
    ("description", "shown"),
    [
        ("1.5 kW hub motor", "1.5 kW hub motor. "),
        ("3. phase motor", "3\\. phase motor. "),
        ("2) second", "2\\) second. "),
        ("-5 V rail", "-5 V rail. "),
    ],
)
def test_a_leading_number_should_be_escaped_only_where_it_would_start_a_list(
    tmp_path: Path, description: str, shown: str
) -> None:
    """`1.5 kW` starts no list: the first escape had put a backslash before its digits,
    shown in the text."""
    source = (ROOT / "spec" / "paper_motor.yaml").read_text(encoding="utf-8")
    line = next(x for x in source.splitlines() if x.startswith("description: "))
    path = tmp_path / "number.yaml"
    path.write_text(source.replace(line, f'description: "{description}"'), encoding="utf-8")
    report = render_derivation(derive(), load_spec(path))
    first = next(p for p in report.split("\n\n") if "Commutation method" in p)
    assert first.startswith(shown), first

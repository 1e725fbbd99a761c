"""The second example spec: a real datasheet motor (maxon EC 45 flat, 48 V winding).

It must pass the same loader as the paper's motor, differ from it where it matters
(voltage, inductance, pole count), feed the derivation, and say where every number
comes from: the datasheet, or an explicit assumption.
"""

from __future__ import annotations

from fractions import Fraction
from pathlib import Path
from typing import Any

import sympy as sp
import yaml

from bldc import cli
from codegen.derivation import derive
from codegen.derivation.figures import spec_figures
from codegen.spec_loader import load_spec

ROOT = Path(__file__).resolve().parents[1]
PAPER_SPEC = ROOT / "spec" / "paper_motor.yaml"
SECOND_SPEC = ROOT / "spec" / "example_maxon_ec45_flat_48v.yaml"
DATASHEET = "datasheet maxon EC 45 flat 50 W 48 V:"


def _raw() -> dict[str, Any]:
    return yaml.safe_load(SECOND_SPEC.read_text(encoding="utf-8"))


def _number(quantity: str, unit: str) -> Fraction:
    """The exact number of a "<number> <unit>" string written in `unit`."""
    number, written_unit = quantity.split()
    assert written_unit == unit, f"{quantity!r} is not in {unit}"
    return Fraction(number)


def test_second_spec_should_validate() -> None:
    spec = load_spec(SECOND_SPEC)
    assert spec.name == "maxon_ec45_flat_48v"
    assert spec.motor.back_emf_convention == "line_to_line"


def test_second_spec_should_differ_from_the_paper_motor() -> None:
    paper = load_spec(PAPER_SPEC)
    second = load_spec(SECOND_SPEC)
    assert second.motor.rated_voltage_v != paper.motor.rated_voltage_v
    assert second.motor.phase_inductance_h != paper.motor.phase_inductance_h
    assert second.motor.poles != paper.motor.poles


def test_second_spec_should_halve_the_terminal_datasheet_values() -> None:
    # maxon line 10/11: 3.610 ohm and 1.730 mH phase to phase; line 13: 121 rpm/V.
    motor = load_spec(SECOND_SPEC).motor
    assert motor.phase_resistance_ohm == Fraction("3.610") / 2
    assert motor.phase_inductance_h == Fraction("1.730e-3") / 2
    assert motor.poles == 2 * 8
    assert motor.pole_pairs == 8
    line_to_line_v_per_rpm = Fraction("8.26") / 1000
    assert motor.back_emf_constant_v_per_rpm == line_to_line_v_per_rpm / 2
    # 8.26 V/krpm is 1/k_n = 1/121 V/rpm to three significant figures.
    assert abs(line_to_line_v_per_rpm * 121 - 1) < Fraction(1, 1000)


def test_boundary_speed_should_be_u_d_over_4_k_e_from_the_yaml_numbers() -> None:
    raw = _raw()
    u_d = _number(raw["inverter"]["bus_voltage_nominal"], "V")
    k_e = _number(raw["motor"]["back_emf_constant"], "V/krpm") / 1000  # V/rpm
    if raw["motor"]["back_emf_convention"] == "line_to_line":
        k_e /= 2  # the flat-top line EMF of the two conducting phases is 2E
    expected = u_d / (4 * k_e)

    figures = spec_figures(derive(), load_spec(SECOND_SPEC))

    assert figures.boundary_speed_rpm == sp.Rational(expected.numerator, expected.denominator)
    assert figures.upper_speed_rpm == sp.Rational(2 * expected.numerator, expected.denominator)
    assert round(float(expected), 1) == 2905.6
    assert [p.region for p in figures.points] == ["low", "high"]


def test_every_value_should_cite_the_datasheet_or_an_assumption() -> None:
    raw = _raw()
    sources: dict[str, str] = raw["sources"]
    keys = {
        f"{section}.{key}"
        for section in (
            "motor",
            "inverter",
            "hall",
            "adc",
            "controller",
            "accuracy",
            "sensing",
            "current_loop",
            "protection",
            "firmware",
        )
        for key in raw[section]
    } | {"operating_points"}
    keys |= {"tolerances"} & set(raw)  # the optional robustness ranges
    assert set(sources) == keys
    for key, text in sources.items():
        # the firmware's budgets are requirements (issue 12), not properties of the motor
        cited = (
            DATASHEET,
            "assumption",
            *(("requirement",) if key.startswith("firmware.") else ()),
        )
        assert text.startswith(cited), key
    assert all(sources[f"motor.{key}"].startswith(DATASHEET) for key in raw["motor"])


def test_audit_should_accept_the_second_spec(tmp_path: Path) -> None:
    assert cli.main(["audit", str(SECOND_SPEC), "-o", str(tmp_path)]) == 0
    report = (tmp_path / "DERIVATION.md").read_text(encoding="utf-8")
    assert "spec/example_maxon_ec45_flat_48v.yaml" in report.splitlines()[0]
    assert "2905.6 rpm" in report

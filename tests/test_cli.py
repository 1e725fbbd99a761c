"""The command line: outputs, exit codes, determinism and atomic writes."""

from __future__ import annotations

import hashlib
import subprocess
import sys
from pathlib import Path

import pytest

from codegen import cli
from codegen.errors import DerivationError

ROOT = Path(__file__).resolve().parents[1]
SPEC = ROOT / "spec" / "paper_motor.yaml"


TRANSCRIPTION = ROOT / "spec" / "paper_printed.yaml"
FIXTURES = sorted((ROOT / "tests" / "fixtures" / "specs").glob("*.yaml"))


def test_audit_should_write_the_paper_report_that_states_its_provenance(tmp_path: Path) -> None:
    assert cli.main(["audit", "-o", str(tmp_path)]) == 0
    assert sorted(p.name for p in tmp_path.iterdir()) == ["AUDIT.html", "AUDIT.md"]
    digest = hashlib.sha256(TRANSCRIPTION.read_bytes()).hexdigest()
    for name, template in (
        ("AUDIT.md", "audit/AUDIT.md.j2"),
        ("AUDIT.html", "audit/AUDIT.html.j2"),
    ):
        report = (tmp_path / name).read_text(encoding="utf-8")
        provenance = next(line for line in report.splitlines() if "Generated from" in line)
        assert f"templates/{template}" in provenance
        assert "spec/paper_printed.yaml" in provenance
        assert digest in provenance
        assert "Do not edit" in provenance
        assert str(ROOT) not in report  # no absolute paths


def test_the_paper_audit_should_not_depend_on_the_motor(tmp_path: Path) -> None:
    assert cli.main(["audit", "-o", str(tmp_path / "none")]) == 0
    for spec in (SPEC, *FIXTURES):
        out = tmp_path / spec.stem
        assert cli.main(["audit", str(spec), "-o", str(out)]) == 0
        for name in ("AUDIT.md", "AUDIT.html"):
            assert (out / name).read_bytes() == (tmp_path / "none" / name).read_bytes()
        assert (out / "DERIVATION.md").exists()


def test_audit_with_a_spec_should_write_the_same_derivation_as_generate(tmp_path: Path) -> None:
    from codegen.generate import render_all

    spec = FIXTURES[0]
    assert cli.main(["audit", str(spec), "-o", str(tmp_path)]) == 0
    generated = render_all(spec).files
    assert "AUDIT.md" not in generated
    assert (tmp_path / "DERIVATION.md").read_text(encoding="utf-8") == generated["DERIVATION.md"]


def test_two_audits_should_be_byte_identical(tmp_path: Path) -> None:
    for out in ("one", "two"):
        assert cli.main(["audit", "-o", str(tmp_path / out)]) == 0
    for name in ("AUDIT.md", "AUDIT.html"):
        assert (tmp_path / "one" / name).read_bytes() == (tmp_path / "two" / name).read_bytes()


def test_checked_in_paper_audit_should_match_a_fresh_one(tmp_path: Path) -> None:
    assert cli.main(["audit", "-o", str(tmp_path)]) == 0
    for name in ("AUDIT.md", "AUDIT.html"):
        checked_in = ROOT / "generated" / "paper" / name
        assert checked_in.read_bytes() == (tmp_path / name).read_bytes(), name


def test_derive_should_print_the_default_spec_numbers(capsys: pytest.CaptureFixture[str]) -> None:
    assert cli.main(["derive", str(SPEC)]) == 0
    out = capsys.readouterr().out
    assert "U_d/(4 k_e) = 2542.4 rpm" in out
    assert "U_d/(2 k_e) = 5084.7 rpm" in out
    assert "D_on = 0.1907" in out
    assert "control fail area" in out


def test_a_bad_spec_should_exit_2_naming_the_key(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    bad = tmp_path / "bad.yaml"
    bad.write_text(SPEC.read_text().replace("speed_max: 5000 rpm", "speed_max: 5100 rpm"))
    # A bad spec named to `audit` stops it before it writes the paper audit too.
    assert cli.main(["audit", str(bad), "-o", str(tmp_path / "out")]) == cli.EXIT_SPEC
    err = capsys.readouterr().err
    assert "controller.speed_max" in err and "5084.7" in err
    assert not (tmp_path / "out").exists()


def test_a_failing_derivation_should_exit_3_and_keep_the_old_reports(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    assert cli.main(["audit", str(SPEC), "-o", str(tmp_path)]) == 0
    names = ["AUDIT.html", "AUDIT.md", "DERIVATION.md"]
    before = {name: (tmp_path / name).read_bytes() for name in names}

    def broken() -> None:
        raise DerivationError("planted")

    monkeypatch.setattr("codegen.derivation.derive", broken)
    assert cli.main(["audit", str(SPEC), "-o", str(tmp_path)]) == cli.EXIT_DERIVATION
    assert {name: (tmp_path / name).read_bytes() for name in names} == before
    assert sorted(p.name for p in tmp_path.iterdir()) == names


def test_module_and_console_entry_points_should_run() -> None:
    result = subprocess.run(
        [sys.executable, "-m", "codegen", "--help"], capture_output=True, text=True, check=False
    )
    assert result.returncode == 0 and "audit" in result.stdout


def test_an_improved_r_spec_the_formats_cannot_meet_should_exit_2_writing_nothing(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    from codegen.core.module import build_core
    from codegen.methods.improved_r.design import RuleFormatError

    def unmeetable(*_: object) -> None:
        raise RuleFormatError("no table size meets the accuracy targets")

    monkeypatch.setattr("codegen.methods.improved_r.design_rule", unmeetable)
    build_core.cache_clear()
    spec = ROOT / "spec" / "paper_motor_improved_r.yaml"
    out = tmp_path / "out"
    assert cli.main(["generate", str(spec), "-o", str(out)]) == cli.EXIT_SPEC
    err = capsys.readouterr().err
    assert "controller.method = 'improved_r'" in err and "accuracy targets" in err
    assert not out.exists() and list(tmp_path.iterdir()) == []

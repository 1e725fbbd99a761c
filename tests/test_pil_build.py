"""emulation/pil/build.py: the firmware of any spec, through `bldc-codegen generate` and
`bldc-codegen firmware` run in this process."""

from __future__ import annotations

from pathlib import Path

import pytest

from emulation.pil.build import ROOT, build_firmware

HUB = Path("tests") / "fixtures" / "specs" / "hub_motor_46p.yaml"  # from the project root


def test_a_failing_command_should_raise_its_own_message_and_print_nothing(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """`firmware` refuses another spec's generated folder; a missing spec is refused by
    `generate`: each a RuntimeError with the command's one line, nothing printed."""
    paper = ROOT / "generated" / "paper_motor"
    with pytest.raises(RuntimeError) as refused:
        build_firmware(HUB, tmp_path / "a", paper)
    assert str(refused.value).startswith(f"bldc-codegen firmware {HUB}: error: ")
    assert "holds the output of another spec, 'paper_motor'" in str(refused.value)
    with pytest.raises(RuntimeError) as missing:
        build_firmware(HUB.with_name("no_such_motor.yaml"), tmp_path / "b")
    assert "bldc-codegen generate" in str(missing.value)
    assert "cannot read spec" in str(missing.value)
    assert capsys.readouterr() == ("", "")
    assert not (tmp_path / "a" / "build" / "firmware.elf").exists()


def test_a_relative_spec_should_resolve_from_the_project_root(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """As the command ran from the project root before: the working directory does not
    matter; the ELF is linked from the spec's own generation."""
    monkeypatch.chdir(tmp_path)
    elf = build_firmware(HUB, tmp_path / "hub")
    assert elf == tmp_path / "hub" / "build" / "firmware.elf" and elf.is_file()
    assert (tmp_path / "hub" / "generated" / "manifest.json").is_file()
    assert capsys.readouterr() == ("", "")


def test_a_failed_step_should_report_why_not_the_specs_warnings() -> None:
    """A spec that loads with a warning (a large PWM ripple) and whose image is over its
    RAM budget: `firmware` warns on stderr and reports the budget on stdout. The error
    names the budget; the warning is not the reason (make pil once printed only it)."""
    from codegen.build_firmware import Budget, budget_hint
    from emulation.pil.build import ToolError

    warning = "warning: spec/m.yaml:18: motor.phase_inductance = '0.05 mH': ripple"
    budget = Budget("RAM (variables, worst stack)", 532, 512)
    hint = budget_hint(budget, "improved_r")
    assert hint is not None
    stdout = f"firmware: build/m/firmware.elf\n  {budget.line()}\n  {hint}\n"
    error = ToolError("firmware spec/m.yaml", 1, warning + "\n", stdout)
    # the budget and the key to change (the budget alone named none: a helper's hunt)
    assert error.lines == ["RAM (variables, worst stack): 532 B of 512 B (EXCEEDED)", hint]
    assert hint.startswith("firmware.ram_budget = 512 B") and "640 B" in hint
    assert error.returncode == 1
    failed = ToolError("generate spec/m.yaml", 3, f"{warning}\nerror: no design meets\n", "")
    assert failed.lines == ["error: no design meets"]


@pytest.mark.parametrize(
    ("option", "value", "said"),
    [
        ("--ms", "-5", "-5 is out of range"),
        ("--amps", "nan", "'nan' is not a number (ASCII digits, no '_')"),
    ],
)
def test_pil_main_should_refuse_a_bad_number_in_one_usage_line(
    capsys: pytest.CaptureFixture[str], option: str, value: str, said: str
) -> None:
    """`python -m emulation.pil --ms -5` once divided by zero (a traceback)."""
    from emulation.pil.__main__ import main

    with pytest.raises(SystemExit) as caught:
        main([str(ROOT / "spec" / "paper_motor.yaml"), option, value])
    assert caught.value.code == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert f"argument {option}: {said}" in err[-1]


def test_an_exceeded_budget_should_name_its_key_and_what_the_image_needs() -> None:
    from codegen.build_firmware import Budget, budget_hint

    ram = Budget("RAM (variables, code run from SRAM, worst stack)", 532, 512)
    assert budget_hint(ram, "improved_r") == (
        "firmware.ram_budget = 512 B is below what this image needs, 532 B (the"
        " resistance-aware rule's search runs deeper than the paper method's;"
        " `init --method improved_r` writes 640 B)"
    )
    assert budget_hint(ram, "improved") == (
        "firmware.ram_budget = 512 B is below what this image needs, 532 B"
    )
    assert budget_hint(Budget("flash", 9000, 8192), "improved_r") == (
        "firmware.flash_budget = 8192 B is below what this image needs, 9000 B"
    )
    assert budget_hint(Budget("flash", 4000, 8192), "improved") is None


def test_a_braking_run_that_cannot_start_should_be_one_line_not_a_traceback(
    monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    """`make pil`: the motor is attached to an idle bridge; where the firmware holds a
    switch on when it is attached (a fault latched at boot, the short circuit its safe
    state) the plant refuses with PilError. The report says so in one line and exits 1
    (a 10-bit ADC spec once ended in a traceback there). The firmware, scenarios and
    run are stand-ins: this is the report's handling of the refusal."""
    from emulation.pil import report
    from emulation.pil.bus import PilError

    def refuse(*_: object) -> None:
        raise PilError("the plant is attached with switches on ((False, True)): attach it idle")

    monkeypatch.setattr(report, "build_firmware", lambda *_: tmp_path / "firmware.elf")
    monkeypatch.setattr(report, "SCENARIOS", ())
    monkeypatch.setattr(report, "brake", refuse)
    assert report.main([str(ROOT / "spec" / "paper_motor.yaml"), "--braking", "short"]) == 1
    err = capsys.readouterr().err
    assert err.splitlines() == [
        "error: pil: paper_motor: braking: the plant is attached with switches on"
        " ((False, True)): attach it idle"
    ]

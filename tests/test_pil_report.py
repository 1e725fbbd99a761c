"""`emulation.pil.report`'s publication of PIL.md and the braking run's CSV."""

from __future__ import annotations

import stat
from pathlib import Path

import pytest

from emulation.pil.report import publish

ROOT = Path(__file__).resolve().parents[1]


def test_published_outputs_should_get_the_permissions_of_any_new_file(tmp_path: Path) -> None:
    """PIL.md and braking_commutations.csv are written beside and renamed; a temporary
    file from `tempfile` is its owner's alone (0600), and renamed so the CSV was, while
    the figures beside it were 0644."""
    plain = tmp_path / "plain.txt"
    plain.write_text("x", encoding="utf-8")  # the umask's permissions
    target = tmp_path / "pil" / "braking_commutations.csv"
    publish("a,b\n1,2\n", target)
    assert target.read_text(encoding="utf-8") == "a,b\n1,2\n"
    assert stat.S_IMODE(target.stat().st_mode) == stat.S_IMODE(plain.stat().st_mode)
    assert [p.name for p in target.parent.iterdir()] == [target.name]  # nothing left beside


def test_the_report_should_go_under_the_current_folder_or_to_o(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """`python -m emulation.pil.report SPEC` run from a user's folder wrote PIL.md into the
    project's own generated/<name>/pil/ (over the checked-in motor's report, for a spec
    of the same name). It goes under the current folder, as every command's output, or
    to -o. The firmware and scenarios are stand-ins: this is where the report goes."""
    from emulation.pil import report

    spec = ROOT / "spec" / "paper_motor.yaml"
    monkeypatch.setattr(report, "build_firmware", lambda *_: tmp_path / "firmware.elf")
    monkeypatch.setattr(report, "SCENARIOS", ())
    monkeypatch.setattr(report, "render", lambda *_: "# PIL: a stand-in\n")
    project = ROOT / "generated" / "paper_motor" / "pil" / "PIL.md"
    before = project.stat().st_mtime_ns if project.exists() else None
    monkeypatch.chdir(tmp_path)
    assert report.main([str(spec), "--braking", "off", "--no-progress"]) == 0
    written = tmp_path / "generated" / "paper_motor" / "pil" / "PIL.md"
    assert written.read_text(encoding="utf-8").startswith("# ")
    assert capsys.readouterr().out.rstrip().endswith("-> generated/paper_motor/pil/PIL.md")
    assert report.main([str(spec), "--braking", "off", "--no-progress", "-o", "mine"]) == 0
    assert (tmp_path / "mine" / "PIL.md").is_file()
    assert (project.stat().st_mtime_ns if project.exists() else None) == before
    with pytest.raises(SystemExit) as usage:
        report.main([str(spec), str(spec), "-o", "mine"])
    assert usage.value.code == 2


def test_the_report_folder_should_hold_one_run_and_keep_a_strangers_files(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """The CSV and figures were written into the folder as they came and PIL.md at the
    end: a run stopped between left new figures beside the former report, and a run
    without braking left a former run's CSV beside its own report. They are staged and
    moved in together (codegen/report_folder.py), a former run's own files go, a
    stranger's stay, and a hand-written PIL.md stops the run before it starts."""
    from codegen.report_folder import LEDGER, staged_report
    from emulation.pil import report

    spec = ROOT / "spec" / "paper_motor.yaml"
    built: list[Path] = []
    monkeypatch.setattr(report, "build_firmware", lambda *_: built.append(spec) or spec)
    monkeypatch.setattr(report, "SCENARIOS", ())
    monkeypatch.setattr(report, "render", lambda *_: f"# PIL\n{report.REPORT_MARKER}\n")
    out = tmp_path / "pil"
    with staged_report(out, report.REPORT_NAME, report.REPORT_MARKER) as staging:
        (staging / report.REPORT_NAME).write_text(f"# former\n{report.REPORT_MARKER}\n")
        (staging / "braking_commutations.csv").write_text("index\n")
        (staging / "braking_speed.png").write_bytes(b"png")
    (out / "notes.txt").write_text("mine")
    args = [str(spec), "--braking", "off", "--no-progress", "-o", str(out)]
    assert report.main(args) == 0
    assert sorted(p.name for p in out.iterdir()) == [LEDGER, "PIL.md", "notes.txt"]
    assert [line.split("\t")[0] for line in (out / LEDGER).read_text().splitlines()] == ["PIL.md"]
    stranger = tmp_path / "theirs"
    stranger.mkdir()
    (stranger / "PIL.md").write_text("# my own notes\n")
    built.clear()
    assert report.main([*args[:-1], str(stranger)]) == 5
    assert built == [] and (stranger / "PIL.md").read_text() == "# my own notes\n"
    assert capsys.readouterr().err.startswith("error: pil: ")
    # a file where the folder goes: one line, one prefix (it had said "error: pil: error:")
    afile = tmp_path / "afile"
    afile.write_text("x")
    assert report.main([*args[:-1], str(afile)]) == 5
    said = capsys.readouterr().err
    assert said.startswith(f"error: pil: {afile}: ") and said.count("\n") == 1, said
    assert afile.read_text() == "x"

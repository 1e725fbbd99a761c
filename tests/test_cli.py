"""The command line: outputs, exit codes, determinism and atomic writes."""

from __future__ import annotations

import hashlib
import subprocess
import sys
from pathlib import Path

import pytest

from bldc import cli
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
        assert "Do not edit: regenerate with `bldc-codegen audit`." in provenance  # not `make`
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


def test_generate_should_take_over_the_derivation_an_audit_wrote_first(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """`audit SPEC` writes generated/<name>/DERIVATION.md; `generate SPEC` then refused
    the folder ("DERIVATION.md is in the way and was not written by bldc-codegen"), and
    `all` stopped at its first step. The audit now records the file as its own."""
    monkeypatch.chdir(tmp_path)
    spec = str(FIXTURES[0])
    name = FIXTURES[0].stem
    folder = tmp_path / "generated" / name
    (folder / "notes.txt").parent.mkdir(parents=True)
    (folder / "notes.txt").write_text("the user's own\n", encoding="utf-8")
    assert cli.main(["audit", spec]) == 0
    assert cli.main(["verify", spec, "--no-progress"]) == 4
    assert "holds only the audit's DERIVATION.md" in capsys.readouterr().err
    assert cli.main(["generate", spec]) == 0
    assert (folder / "c" / "bldc_commutation.c").is_file()
    assert (folder / "notes.txt").read_text(encoding="utf-8") == "the user's own\n"
    before = (folder / "manifest.json").read_bytes()
    assert cli.main(["audit", spec]) == 0  # into the generated tree: its own file, in place
    assert (folder / "manifest.json").read_bytes() == before
    assert cli.main(["generate", spec]) == 0


def test_audit_should_not_rewrite_another_specs_generated_derivation(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """`audit maxon.yaml -o DIR` with DIR holding paper_motor's generated tree rewrote
    DIR/DERIVATION.md with the Maxon's derivation (publish_derivation rewrote it wherever
    the manifest recorded a spec): refused in one line, before the work, nothing written.
    The tree of the same spec keeps its copy rewritten in place (the test above)."""
    import shutil

    tree = tmp_path / "paper_motor"
    shutil.copytree(ROOT / "generated" / "paper_motor", tree)
    before = {p: p.read_bytes() for p in tree.rglob("*") if p.is_file()}
    maxon = ROOT / "spec" / "example_maxon_ec45_flat_48v.yaml"
    assert cli.main(["audit", str(maxon), "-o", str(tree)]) == 5
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1, err
    assert "holds the generated output of another spec, 'paper_motor', not of" in err[0], err
    assert {p: p.read_bytes() for p in tree.rglob("*") if p.is_file()} == before


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


def test_a_bad_spec_should_exit_with_the_spec_code_naming_the_key(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    bad = tmp_path / "bad.yaml"
    bad.write_text(SPEC.read_text().replace("speed_max: 5000 rpm", "speed_max: 5100 rpm"))
    # A bad spec named to `audit` stops it before it writes the paper audit too.
    assert cli.main(["audit", str(bad), "-o", str(tmp_path / "out")]) == cli.EXIT_SPEC
    err = capsys.readouterr().err
    assert "controller.speed_max" in err and "5084.7" in err
    assert not (tmp_path / "out").exists()


def test_a_failing_derivation_should_exit_as_an_internal_error_and_keep_the_old_report(
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
    # and the manifest that records DERIVATION.md as bldc-codegen's own
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted([*names, "manifest.json"])


@pytest.mark.parametrize("module", ["codegen", "bldc", "bldc.cli"])
def test_module_and_console_entry_points_should_run(module: str) -> None:
    """Each module a user may run with -m prints the commands (`python -m bldc.cli
    init --help` printed nothing and exited 0: the module had no main block)."""
    result = subprocess.run(
        [sys.executable, "-m", module, "init", "--help"],
        capture_output=True,
        text=True,
        check=False,
    )
    assert result.returncode == 0 and "--pole-pairs" in result.stdout, result


def test_an_improved_r_spec_the_formats_cannot_meet_should_exit_3_writing_nothing(
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


def test_generate_keeps_reports_and_foreign_files_in_its_output_folder(tmp_path: Path) -> None:
    out = tmp_path / "project"
    (out / "verify").mkdir(parents=True)
    (out / "verify" / "report.json").write_text('{"passed": true}\n')
    (out / "simulation").mkdir()
    (out / "simulation" / "SIMULATION.md").write_text("# sim\n")
    (out / "Makefile").write_text("all:\n")
    assert cli.main(["generate", str(SPEC), "-o", str(out)]) == 0
    assert (out / "c" / "bldc_commutation.c").is_file()
    (out / "c" / "my_app.c").write_text("/* mine */\n")
    assert cli.main(["generate", str(SPEC), "-o", str(out)]) == 0
    assert (out / "verify" / "report.json").read_text() == '{"passed": true}\n'
    assert (out / "simulation" / "SIMULATION.md").read_text() == "# sim\n"
    assert (out / "Makefile").read_text() == "all:\n"
    assert (out / "c" / "my_app.c").read_text() == "/* mine */\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == [".project.bldc-codegen.lock", "project"]


def test_generate_refuses_to_overwrite_a_file_it_did_not_write(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "project"
    out.mkdir()
    (out / "DERIVATION.md").write_text("my notes\n")
    assert cli.main(["generate", str(SPEC), "-o", str(out)]) == int(cli.ExitCode.ENVIRONMENT)
    assert "DERIVATION.md is in the way" in capsys.readouterr().err
    assert sorted(p.name for p in out.iterdir()) == ["DERIVATION.md"]
    # every file in the way in the one line (a user had learnt of them one run at a time)
    (out / "c").mkdir()
    (out / "c" / "bldc_commutation.c").write_text("/* mine */\n")
    assert cli.main(["generate", str(SPEC), "-o", str(out)]) == int(cli.ExitCode.ENVIRONMENT)
    (line,) = capsys.readouterr().err.strip().splitlines()
    assert "DERIVATION.md and 1 more there (c/bldc_commutation.c) are in the way" in line, line
    assert (out / "c" / "bldc_commutation.c").read_text() == "/* mine */\n"


def test_a_spec_path_cannot_inject_code_into_generated_files(tmp_path: Path) -> None:
    """A newline, `*/` and `-->` in the spec's path would end the comment that carries
    the provenance; the generated C must still compile and the Python still import."""
    evil = tmp_path / 'm *\n#"--> y.yaml'
    evil.write_text(SPEC.read_text(encoding="utf-8"), encoding="utf-8")
    out = tmp_path / "out"
    assert cli.main(["generate", str(evil), "-o", str(out)]) == 0
    first_lines = {
        path.relative_to(out).as_posix(): path.read_text(encoding="utf-8").splitlines()[0]
        for path in out.rglob("*")
        if path.is_file() and path.suffix in (".c", ".h", ".py", ".md", ".ld")
    }
    for name, line in first_lines.items():
        assert "<the spec named paper_motor, path withheld: unsafe characters>" in line, name
        assert "generate <" not in line, name  # a shell would read a redirect there
        assert "*/" not in line[2:-2] and "-->" not in line[4:-3], name
    for source in sorted((out / "c").glob("*.c")):
        subprocess.run(
            ["gcc", "-std=c99", "-fsyntax-only", "-Wall", "-Werror", f"-I{out / 'c'}", str(source)],
            check=True,
        )
    for module in sorted((out / "python").glob("*.py")):
        compile(module.read_text(encoding="utf-8"), str(module), "exec")


def test_the_provenance_line_never_carries_comment_terminators() -> None:
    import dataclasses

    from codegen.render import project_relative, provenance
    from codegen.spec_loader import load_spec

    spec = load_spec(SPEC)
    assert "with spec spec/paper_motor.yaml (sha256" in provenance("t.j2", spec)
    for evil in ("spec/a */b.yaml", "spec/a\nb.yaml", "spec/a-->b.yaml", "spec/a??/b.yaml"):
        text = provenance("t.j2", dataclasses.replace(spec, source_path=str(ROOT / evil)))
        assert "<the spec named paper_motor, path withheld: unsafe characters>" in text, evil
        assert spec.sha256 in text
        # Other reports (sim's SIMULATION.md, verify's JSON) show paths the same way.
        assert project_relative(ROOT / evil) == "<path withheld: unsafe characters>"
    assert project_relative(ROOT / "spec" / "my motor+v2.yaml") == "spec/my motor+v2.yaml"
    # letters and digits beyond ASCII are shown (`motör.yaml` had been withheld and its
    # spec named `paper_motor.yaml`, another file); an invisible character is not
    for shown in ("spec/motör.yaml", "spec/モーター٣.yaml", "spec/mo\u0308tor.yaml"):
        assert project_relative(ROOT / shown) == shown
    for hidden in ("spec/mot\u202eor.yaml", "spec/mo\u200btor.yaml", "spec/mo\u00a0tor.yaml"):
        assert project_relative(ROOT / hidden) == "<path withheld: unsafe characters>", hidden


def test_every_generated_header_cites_its_template_from_the_root_and_its_command(
    tmp_path: Path,
) -> None:
    """The port's files cited `c/stm32f103_port.c.j2` where the others cite
    `templates/c/...`, and every header said "regenerate with `make`", which generates
    the default spec only (and nothing for a spec outside the project). Each cites its
    template from the project root now, and the command for its own spec."""
    import re
    import shutil

    from codegen.generate import render_all

    inside = render_all(SPEC).files
    outside = tmp_path / "my motor.yaml"
    shutil.copyfile(SPEC, outside)
    elsewhere = render_all(outside).files
    cited = re.compile(r"Generated from template (\S+) with spec (.+?) \(sha256 [0-9a-f]{64}\)")
    for files, spec, command in (
        (inside, "spec/paper_motor.yaml", "bldc-codegen generate spec/paper_motor.yaml"),
        (elsewhere, "my motor.yaml", "bldc-codegen generate 'my motor.yaml'"),
    ):
        headed = 0
        for name, text in files.items():
            if "regenerate with" not in text[:600]:
                continue
            headed += 1
            first = text[:600].splitlines()[1 if name.endswith(".json") else 0]
            assert "`make`" not in first, name
            assert f"Do not edit: regenerate with `{command}`." in first, (name, first)
            match = cited.search(first)
            if name.endswith(".json"):  # the proof plan names its generator, not a template
                assert match is None and "codegen/proof/harness.py" in first, name
                continue
            assert match is not None, (name, first)
            template, shown = match.groups()
            assert template.startswith("templates/"), (name, template)
            assert (ROOT / template).is_file(), (name, template)
            assert shown == spec, name
        assert headed == len(files) - 1, sorted(files)  # all but manifest.json


def test_generate_killed_after_its_atomic_exchange_leaves_a_complete_tree(tmp_path: Path) -> None:
    """The generate command, SIGKILLed at its first rename after the exchange: the new tree
    is in place and whole; the old one and the verify report are beside it until the
    next run, which moves the report back in and removes the rest."""
    import json
    import os
    import signal

    out = tmp_path / "motor"
    assert cli.main(["generate", str(SPEC), "-o", str(out)]) == 0
    (out / "verify").mkdir()
    (out / "verify" / "report.json").write_text("{}\n")
    other = tmp_path / "other.yaml"
    other.write_text(SPEC.read_text().replace("dead_time: 500 ns", "dead_time: 400 ns"))
    # A forked child keeps this process's warm derivation: the same command, seconds faster.
    pid = os.fork()
    if pid == 0:  # pragma: no cover - the child
        os.environ["BLDC_CODEGEN_TEST_KILL_AT_LABEL"] = "rename "
        try:
            cli.main(["generate", str(other), "-o", str(out)])
        finally:
            os._exit(0)
    _, status = os.waitpid(pid, 0)
    assert os.WIFSIGNALED(status) and os.WTERMSIG(status) == signal.SIGKILL
    manifest = json.loads((out / "manifest.json").read_text())
    assert manifest["spec_sha256"] == hashlib.sha256(other.read_bytes()).hexdigest()
    for name, digest in manifest["files"].items():
        assert hashlib.sha256((out / name).read_bytes()).hexdigest() == digest, name
    assert cli.main(["generate", str(other), "-o", str(out)]) == 0
    assert (out / "verify" / "report.json").read_text() == "{}\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == [
        ".motor.bldc-codegen.lock",
        "motor",
        "other.yaml",
    ]


@pytest.mark.parametrize("command", ["verify", "unity", "firmware"])
def test_a_file_given_as_the_generated_folder_should_be_named_not_offered_as_an_output(
    command: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """`--generated README.md` had said `regenerate with bldc-codegen generate ... -o
    README.md`: advice to write a generated tree over a file the tool did not write."""
    note = tmp_path / "notes.md"
    note.write_text("mine\n")
    assert cli.main([command, str(SPEC), "--generated", str(note)]) == 4
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "is a file, not a generated folder" in err[0], err
    assert " -o " not in err[0] and note.read_text() == "mine\n"


def test_an_interrupt_while_the_command_line_loads_should_say_interrupted_in_one_line(
    monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """Ctrl-C in the first 0.2 s (Jinja2, SymPy loading; the parser importing every
    command) had printed a 20-50 line traceback; now the one line a running command's
    interrupt prints, status 130."""
    import builtins

    import bldc.cli
    import bldc.entry

    real = builtins.__import__

    def interrupted(name: str, *args: object, **kwargs: object) -> object:
        if name == "bldc.cli":
            raise KeyboardInterrupt
        return real(name, *args, **kwargs)  # type: ignore[arg-type]

    with monkeypatch.context() as patch:
        patch.setattr(builtins, "__import__", interrupted)
        assert bldc.entry.main(["--help"]) == 130
    assert capsys.readouterr().err == "interrupted\n"

    def parser() -> None:
        raise KeyboardInterrupt

    monkeypatch.setattr(bldc.cli, "build_parser", parser)
    assert bldc.cli.main(["derive", "x.yaml"]) == 130
    assert capsys.readouterr().err == "interrupted\n"

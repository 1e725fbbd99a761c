"""`bldc-codegen`: every subcommand, its help, exit codes, stale output, the working
directory, `init`'s datasheet conversions, and a new user's own motors end to end."""

from __future__ import annotations

import argparse
import hashlib
import json
import os
import shutil
import signal
import subprocess
import sys
from fractions import Fraction
from pathlib import Path

import pytest

from bldc import cli
from codegen import __version__
from codegen.errors import ExitCode
from codegen.spec_loader import load_spec

ROOT = Path(__file__).resolve().parents[1]
SPEC = ROOT / "spec" / "paper_motor.yaml"
EXPECTED = ["init", "derive", "audit", "generate", "firmware", "verify", "unity", "simulate"]
EXPECTED += ["robustness", "bench", "all"]


def _subparsers(parser: argparse.ArgumentParser) -> dict[str, argparse.ArgumentParser]:
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            return dict(action.choices)
    raise AssertionError("no subcommands")


def test_every_command_is_there_and_documents_every_option() -> None:
    parser = cli.build_parser()
    assert parser.prog == "bldc-codegen"
    commands = _subparsers(parser)
    assert list(commands) == EXPECTED
    for name, sub in commands.items():
        assert sub.prog == f"bldc-codegen {name}"
        assert sub.description, name
        for action in sub._actions:
            if isinstance(action, argparse._HelpAction):
                continue
            assert action.help, f"{name} {action.option_strings or action.dest} has no help"


def test_version_and_help(capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit) as caught:
        cli.main(["--version"])
    assert caught.value.code == 0
    assert capsys.readouterr().out.strip() == f"bldc-codegen {__version__}"
    for name in EXPECTED:
        with pytest.raises(SystemExit) as caught:
            cli.main([name, "--help"])
        assert caught.value.code == 0
        out = capsys.readouterr().out
        assert out.startswith(f"usage: bldc-codegen {name}"), name


def test_a_usage_error_exits_2_and_a_bad_spec_3(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    with pytest.raises(SystemExit) as caught:
        cli.main(["generate"])
    assert caught.value.code == ExitCode.USAGE
    assert "the following arguments are required: SPEC" in capsys.readouterr().err
    bad = tmp_path / "bad.yaml"
    bad.write_text(SPEC.read_text().replace("0.56 mH", "0.56 mh"))
    assert cli.main(["derive", str(bad)]) == ExitCode.SPEC
    err = capsys.readouterr().err
    assert err.startswith(f"error: {bad}:") and "did you mean 'mH'?" in err


def test_an_internal_error_is_one_line_saying_where(
    monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    def broken(*_: object) -> None:
        raise ZeroDivisionError("planted")

    monkeypatch.setattr("codegen.derivation.figures.spec_figures", broken)
    assert cli.main(["derive", str(SPEC)]) == ExitCode.INTERNAL
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1
    assert err[0].startswith("internal error (a bug in bldc-codegen, not in your spec):")
    assert "ZeroDivisionError: planted at tests/test_cli_commands.py:" in err[0]
    with pytest.raises(ZeroDivisionError):
        cli.main(["--traceback", "derive", str(SPEC)])


def test_traceback_is_accepted_before_and_after_every_command(
    monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """The internal-error line says "run with --traceback"; `generate SPEC --traceback`
    was a usage error (exit 2), only `--traceback generate SPEC` worked."""
    parser = cli.build_parser()
    for name in EXPECTED:
        words = ["new_motor"] if name == "init" else [str(SPEC)]
        assert parser.parse_args([name, *words]).traceback is False, name
        assert parser.parse_args(["--traceback", name, *words]).traceback is True, name
        assert parser.parse_args([name, *words, "--traceback"]).traceback is True, name

    def broken(*_: object) -> None:
        raise ZeroDivisionError("planted")

    monkeypatch.setattr("codegen.derivation.figures.spec_figures", broken)
    with pytest.raises(ZeroDivisionError):
        cli.main(["derive", str(SPEC), "--traceback"])
    assert cli.main(["derive", str(SPEC)]) == ExitCode.INTERNAL
    assert "run with --traceback" in capsys.readouterr().err


def test_traceback_should_leave_a_users_error_its_line_and_status(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """--traceback shows an internal error whole; a bad spec or stale output keeps its
    one line and its status (the flag had re-raised every error: a refused spec exited
    1, not 3, and stale output 1, not 4)."""
    bad = tmp_path / "bad.yaml"
    bad.write_text(SPEC.read_text(encoding="utf-8").replace("poles: 2", "poles: 3"), "utf-8")
    for argv in (["--traceback", "generate", str(bad)], ["derive", str(bad), "--traceback"]):
        assert cli.main(argv) == ExitCode.SPEC, argv
        err = capsys.readouterr().err
        assert "Traceback" not in err and err.startswith("error: "), err
    empty = tmp_path / "empty"
    empty.mkdir()
    assert cli.main(["verify", str(SPEC), "--generated", str(empty), "--traceback"]) == (
        ExitCode.STALE
    )
    assert "Traceback" not in capsys.readouterr().err


def test_a_command_is_one_registration(capsys: pytest.CaptureFixture[str]) -> None:
    def run(args: argparse.Namespace) -> int:
        print(f"pil {args.spec}")
        return 0

    def arguments(parser: argparse.ArgumentParser) -> None:
        parser.add_argument("spec", help="motor spec")

    cli.register(
        cli.Command("pil-test", "processor in the loop", "A test command.", arguments, run)
    )
    try:
        assert cli.main(["pil-test", "x.yaml"]) == 0
        assert capsys.readouterr().out == "pil x.yaml\n"
    finally:
        del cli.COMMANDS["pil-test"]


def _copy_generated(tmp_path: Path, name: str = "paper_motor") -> Path:
    target = tmp_path / "generated" / name
    shutil.copytree(ROOT / "generated" / name, target)
    return target


def test_a_folder_of_another_specs_output_should_not_be_offered_for_regeneration(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """`verify B.yaml --generated DIR` with DIR holding motor A's output said "DIR was
    generated from another version of the spec: regenerate with `bldc-codegen generate
    B.yaml -o DIR`", and that command replaced A's output (a helper's hunt). Every
    command that reads a generated folder now names the spec whose output it holds and
    does not offer to overwrite it; another version of the same spec still gets the
    regenerate line."""
    monkeypatch.chdir(tmp_path)
    generated = _copy_generated(tmp_path)  # paper_motor's
    other = tmp_path / "mine.yaml"
    other.write_text(SPEC.read_text().replace("name: paper_motor", "name: mine_motor"))
    for command in ("firmware", "verify", "unity"):
        argv = [command, str(other), "--generated", str(generated)]
        assert cli.main(argv) == ExitCode.STALE, command
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1, err
        assert (
            "holds the output of another spec, 'paper_motor' (from spec/paper_motor.yaml)"
            in (err[0])
        ), err
        assert "regenerate with" not in err[0] and f"-o {generated}" not in err[0], err
        assert "writes mine_motor's into generated/mine_motor" in err[0], err
    # the folder named after the spec, holding another's: no command to run into it
    os.rename(generated, tmp_path / "generated" / "mine_motor")
    assert cli.main(["verify", str(other)]) == ExitCode.STALE
    err = capsys.readouterr().err
    assert "holds the output of another spec" in err and "give -o a folder of its own" in err
    assert (tmp_path / "generated" / "mine_motor" / "c").is_dir()  # untouched


def test_commands_that_read_generated_output_refuse_stale_output(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    monkeypatch.chdir(tmp_path)
    spec = tmp_path / "paper_motor.yaml"
    spec.write_text(SPEC.read_text())
    assert cli.main(["firmware", str(spec)]) == ExitCode.STALE
    assert "has no generated output" in capsys.readouterr().err
    generated = _copy_generated(tmp_path)
    assert cli.main(["firmware", str(spec), "--json"]) == 0  # fresh: the copy is this spec's
    assert json.loads(capsys.readouterr().out)["sizes"]["core"]["flash"] > 0
    spec.write_text(SPEC.read_text().replace("dead_time: 500 ns", "dead_time: 400 ns"))
    # (bench is not here: it generates the spec afresh under build/bench/)
    for command in ("firmware", "verify", "unity"):
        assert cli.main([command, str(spec)]) == ExitCode.STALE, command
        err = capsys.readouterr().err
        assert "was generated from another version of the spec" in err, command
        assert f"regenerate with `bldc-codegen generate {spec}`" in err, command
    spec.write_text(SPEC.read_text())
    (generated / "c" / "bldc_commutation.c").write_text("/* edited */\n")
    assert cli.main(["unity", str(spec)]) == ExitCode.STALE
    assert "c/bldc_commutation.c differs from what bldc-codegen wrote" in capsys.readouterr().err
    manifest = json.loads((ROOT / "generated/paper_motor/manifest.json").read_text())
    manifest["generator_version"] = "0.0.1"
    shutil.copy(ROOT / "generated/paper_motor/c/bldc_commutation.c", generated / "c")
    (generated / "manifest.json").write_text(json.dumps(manifest))
    assert cli.main(["verify", str(spec)]) == ExitCode.STALE
    assert f"bldc-codegen 0.0.1, this is {__version__}" in capsys.readouterr().err


@pytest.mark.parametrize(
    ("edit", "said"),
    [
        (lambda m: [], "it is a list, expected an object"),
        (lambda m: dict(m, files=5), "files is an integer (5), expected an object"),
        (lambda m: dict(m, files=["DERIVATION.md"]), "files is a list"),
        (lambda m: dict(m, core=None), "core is an empty value (null), expected an object"),
        (lambda m: dict(m, core=dict(m["core"], limits="x")), "core.limits is a string ('x')"),
        (lambda m: dict(m, folders="c"), "folders is a string ('c'), expected a list"),
        (lambda m: dict(m, spec_name=3), "spec_name is an integer (3), expected a string"),
        (lambda m: dict(m, files={k: 1 for k in m["files"]}), "expected a SHA-256 in hex"),
        (
            lambda m: dict(m, files=dict(m["files"], **{"../victim.txt": "0" * 64})),
            "files lists '../victim.txt', expected a relative path inside the folder",
        ),
        (
            lambda m: dict(m, files=dict(m["files"], **{"/tmp/victim.txt": "0" * 64})),
            "files lists '/tmp/victim.txt', expected a relative path inside the folder",
        ),
    ],
)
def test_an_edited_manifest_should_be_refused_in_one_line_naming_its_key(
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
    capsys: pytest.CaptureFixture[str],
    edit: object,
    said: str,
) -> None:
    """`"files": 5` had been an AttributeError in check_fresh and `"core": null` an
    AssertionError in verify (exit 70), and entries outside the folder were hashed: an
    edited manifest is stale output, one line naming the key and what was expected."""
    monkeypatch.chdir(tmp_path)
    generated = _copy_generated(tmp_path)
    manifest = json.loads((generated / "manifest.json").read_text())
    (generated / "manifest.json").write_text(json.dumps(edit(manifest)))  # type: ignore[operator]
    assert cli.main(["verify", str(SPEC), "--generated", str(generated)]) == ExitCode.STALE
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and said in err[0] and "regenerate with" in err[0], err
    assert "is not as bldc-codegen wrote it (edited?)" in err[0], err


def test_python_m_verify_should_refuse_a_manifest_with_a_null_core(tmp_path: Path) -> None:
    """verify.run read the manifest itself: `"core": null` was an AssertionError."""
    from verify.run import StaleOutputError as VerifyStale
    from verify.run import read_manifest

    generated = _copy_generated(tmp_path)
    manifest = json.loads((generated / "manifest.json").read_text())
    (generated / "manifest.json").write_text(json.dumps(dict(manifest, core=None)))
    with pytest.raises(VerifyStale, match=r"core is an empty value \(null\), expected an"):
        read_manifest(generated, load_spec(SPEC), str(SPEC))


@pytest.mark.parametrize("kind", ["fifo", "link out", "folder link out"])
def test_a_listed_file_that_is_no_regular_file_inside_the_folder_should_not_be_read(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], kind: str
) -> None:
    """A manifest's entry naming a FIFO had blocked verify for ever (read_bytes), and a
    symbolic link was followed out of the folder: only regular files inside are read."""
    generated = _copy_generated(tmp_path)
    outside = tmp_path / "victim.txt"
    outside.write_text("victim")
    name = {"fifo": "a_fifo", "link out": "link", "folder link out": "ldir/victim.txt"}[kind]
    if kind == "fifo":
        os.mkfifo(generated / name)
    elif kind == "link out":
        (generated / name).symlink_to(outside)
    else:
        (generated / "ldir").symlink_to(tmp_path)
    manifest = json.loads((generated / "manifest.json").read_text())
    manifest["files"][name] = hashlib.sha256(b"victim").hexdigest()
    (generated / "manifest.json").write_text(json.dumps(manifest))

    def hung(signum: int, frame: object) -> None:
        raise TimeoutError(f"verify blocked on {name}")

    previous = signal.signal(signal.SIGALRM, hung)
    signal.alarm(30)  # a regression blocks in open() for ever: fail instead
    try:
        status = cli.main(["verify", str(SPEC), "--generated", str(generated)])
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, previous)
    assert status == ExitCode.STALE
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and f"/{name} is not a file bldc-codegen wrote (" in err[0], err
    assert "it was not read" in err[0], err
    assert outside.read_text() == "victim"


def test_paths_resolve_against_the_working_directory_outside_the_repo(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    before = (ROOT / "generated" / "paper_motor" / "manifest.json").read_bytes()
    monkeypatch.chdir(tmp_path)
    (tmp_path / "specs").mkdir()
    (tmp_path / "specs" / "mine.yaml").write_text(
        SPEC.read_text().replace("name: paper_motor", "name: mine")
    )
    assert cli.main(["generate", "specs/mine.yaml", "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["output"] == "generated/mine"
    assert (tmp_path / "generated" / "mine" / "manifest.json").is_file()
    assert cli.main(["generate", str(tmp_path / "specs" / "mine.yaml"), "-o", "out/x"]) == 0
    assert "-> out/x" in capsys.readouterr().out
    assert (tmp_path / "out" / "x" / "c" / "bldc_commutation.c").is_file()
    assert not (ROOT / "generated" / "mine").exists()
    assert (ROOT / "generated" / "paper_motor" / "manifest.json").read_bytes() == before


def test_init_converts_datasheet_values_and_records_each_conversion(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    from codegen.spec_loader import load_spec

    monkeypatch.chdir(tmp_path)
    argv = ["init", "drone", "--pole-pairs", "7", "--kv", "625"]
    argv += ["--resistance-line-to-line", "0.1 ohm", "--inductance-line-to-line", "30 uH"]
    argv += ["--bus-voltage", "12 V", "--pwm-frequency", "16 kHz"]
    assert cli.main(argv) == 0
    assert capsys.readouterr().out == "init: wrote spec/drone.yaml\n"
    spec = load_spec(tmp_path / "spec" / "drone.yaml")
    assert spec.motor.poles == 14
    assert float(spec.motor.phase_resistance_ohm) == pytest.approx(0.05)
    assert float(spec.motor.phase_inductance_h) == pytest.approx(15e-6)
    assert spec.motor.back_emf_convention == "line_to_line"
    assert float(spec.motor.back_emf_constant_v_per_rpm) == pytest.approx(1 / 625 / 2)
    sources = dict(spec.sources)
    assert "7 pole pairs, poles = 2 x pole pairs" in sources["motor.poles"]
    assert "Kv = 625 rpm/V" in sources["motor.back_emf_constant"]
    assert "1/Kv = 1.6 V/krpm" in sources["motor.back_emf_constant"]
    assert "line-to-line / 2" in sources["motor.phase_resistance"]
    assert "line-to-line / 2" in sources["motor.phase_inductance"]
    assert sources["motor.rotor_inertia"].startswith("assumption:")
    assert cli.main(["init", "drone"]) == ExitCode.USAGE  # never overwrites by surprise
    assert "exists" in capsys.readouterr().err


def test_init_should_write_what_loads_when_the_current_sits_exactly_at_e_over_r(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """Kv 30 rpm/V at 300 rpm is E = 5 V a phase, and 10 ohm x 0.5 A is 5 V: the nominal
    current sits exactly at E(speed_max)/R, which the loader allows. init wrote 1/Kv as
    33.3333 V/krpm, 1 ppm small, and its own spec was refused ("allowed: <= 0.499999 A").
    A constant with no finite decimal is now written rounded up at the 9th digit, and one
    with a short decimal exactly (a line-to-line 123.4567 mH is 61.72835 mH)."""
    monkeypatch.chdir(tmp_path)
    argv = ["init", "edge", "--kv", "30", "--speed-max", "300 rpm", "--resistance", "10 ohm"]
    argv += ["--braking-current", "0.5 A", "--inductance-line-to-line", "123.4567 mH"]
    assert cli.main(argv) == 0, capsys.readouterr().err
    captured = capsys.readouterr()
    assert "does not load" not in captured.out + captured.err
    spec = load_spec(tmp_path / "spec" / "edge.yaml")
    k_e = spec.motor.back_emf_constant_v_per_rpm
    assert Fraction(1, 60) < k_e < Fraction(1, 60) * (1 + Fraction(1, 10**8))
    assert spec.motor.phase_inductance_h == Fraction(6172835, 10**8)
    text = (tmp_path / "spec" / "edge.yaml").read_text()
    assert "back_emf_constant: 33.3333334 V/krpm" in text
    assert "1/Kv = 33.3333334 V/krpm (rounded up" in text


def test_init_should_round_a_very_slow_motors_speeds_to_two_digits(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """50 pole pairs, 1000 V/krpm on 8 V: U_d/(2 k_e) is 4 rpm. init rounded its speeds
    to 10 rpm with a 10 rpm floor: speed_max 10 rpm (above the limit its own source
    named), a 0 rpm operating point. Below 100 rpm a speed now keeps two digits."""
    monkeypatch.chdir(tmp_path)
    argv = ["init", "slow", "--pole-pairs", "50", "--ke", "1000 V/krpm"]
    argv += ["--resistance", "1 ohm", "--inductance", "50 mH", "--bus-voltage", "8 V"]
    argv += ["--braking-current", "100 mA", "--pwm-frequency", "20 kHz"]
    assert cli.main(argv) == 0, capsys.readouterr().err
    captured = capsys.readouterr()
    assert "does not load" not in captured.out + captured.err
    spec = load_spec(tmp_path / "spec" / "slow.yaml")
    assert spec.controller.speed_max_rpm == Fraction(38, 10)
    assert [p.speed_rpm for p in spec.operating_points] == [Fraction(11, 10), Fraction(34, 10)]
    assert spec.controller.speed_min_rpm <= Fraction(11, 10)


def test_init_should_keep_a_stiff_motors_top_speed_where_all_off_is_safe(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """2 uH and 10 mohm on 600 V: above 12000 rpm (U_d/(lambda k_e) at the 480 V bus
    minimum) all-off rectifies, so the safe state is the short circuit, whose peak at
    init's 95 % top speed is 61.8 kA, past the 10 kA a spec may name. init wrote 10 kA,
    which the loader refused, asking for ">= 61799 A" the key cannot hold. Without
    --speed-max init now keeps the top speed below where all-off may rectify: 12000 rpm
    for a rotor 5 % faster than its last Hall interval says (the default sector
    shortening), 11400 rpm said, 99 % of it rounded down to 11280; with one, the refusal
    names the way out the key has: a speed_max below 11400 rpm."""
    monkeypatch.chdir(tmp_path)
    argv = ["init", "stiff", "--pole-pairs", "2", "--ke", "20 V/krpm", "--resistance", "0.01 ohm"]
    argv += ["--inductance", "2 uH", "--bus-voltage", "600 V", "--braking-current", "50 A"]
    argv += ["--pwm-frequency", "80 kHz"]
    assert cli.main(argv) == 0, capsys.readouterr().err
    captured = capsys.readouterr()
    assert "does not load" not in captured.out + captured.err
    spec = load_spec(tmp_path / "spec" / "stiff.yaml")
    assert spec.controller.speed_max_rpm == 11280
    # 1 % of the 12.5 us period, 125 ns, rounded down to 10 ns; the source says so (it
    # had said 500 ns)
    assert spec.inverter.dead_time_s == Fraction(120, 10**9)
    assert "1 % of the PWM period" in dict(spec.sources)["inverter.dead_time"]
    assert (
        "below the speed where every switch off may rectify"
        in dict(spec.sources)["controller.speed_max"]
    )
    assert cli.main([*argv, "--force", "--speed-max", "14000 rpm"]) == ExitCode.SPEC
    err = capsys.readouterr().err
    assert "protection.short_circuit_current_max = '10000 A'" in err
    assert "(allowed: <= 10000 A, with a controller.speed_max below 11400.0 rpm, where" in err


@pytest.mark.parametrize("method", ["improved", "improved_r", "conventional", "none"])
def test_init_should_write_the_method_asked_for_with_its_ram_budget(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str], method: str
) -> None:
    """`init --method`: the spec loads with that method, says where it came from, and
    the resistance-aware rule gets the RAM budget its deeper stack needs (640 B, as the
    checked-in improved_r spec); without the option the paper's Eq. 18."""
    from codegen.spec_loader import load_spec

    monkeypatch.chdir(tmp_path)
    argv = ["init", "m", "--pole-pairs", "6", "--kv", "400", "--bus-voltage", "24 V"]
    argv += ["--resistance-line-to-line", "0.2 ohm", "--inductance-line-to-line", "100 uH"]
    argv += ["--speed-max", "8000 rpm", "--pwm-frequency", "20 kHz"]
    assert cli.main([*argv, "--method", method]) == 0
    capsys.readouterr()
    spec = load_spec(tmp_path / "spec" / "m.yaml")
    assert spec.controller.method == method
    assert spec.firmware.ram_budget_bytes == (640 if method == "improved_r" else 512)
    sources = dict(spec.sources)
    if method != "improved":
        assert f"--method {method}" in sources["controller.method"]
    assert ("640 B" in sources["firmware"]) == (method == "improved_r")
    assert cli.main(["init", "d", *argv[2:]]) == 0
    assert load_spec(tmp_path / "spec" / "d.yaml").controller.method == "improved"
    capsys.readouterr()
    with pytest.raises(SystemExit) as caught:
        cli.main([*argv, "--force", "--method", "improved-r"])
    assert caught.value.code == ExitCode.USAGE
    assert "argument --method: invalid choice: 'improved-r'" in capsys.readouterr().err


@pytest.mark.parametrize(
    ("option", "value"),
    [("--speed-max", "0 rpm"), ("--resistance", "0 ohm"), ("--bus-voltage", "-5 V")],
)
def test_init_should_refuse_a_quantity_not_above_zero_in_one_line(
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
    capsys: pytest.CaptureFixture[str],
    option: str,
    value: str,
) -> None:
    """A zero top speed or resistance once divided by zero inside init (an internal
    error); every datasheet quantity must be above zero, said at the argument."""
    monkeypatch.chdir(tmp_path)
    with pytest.raises(SystemExit) as caught:
        cli.main(["init", "m", option, value])
    assert caught.value.code == ExitCode.USAGE
    err = capsys.readouterr().err.strip().splitlines()
    assert err[-1].startswith(
        f"bldc-codegen init: error: argument {option}: {value!r} is out of range (allowed: > 0"
    )
    assert "Traceback" not in "\n".join(err)
    assert not (tmp_path / "spec").exists()


@pytest.mark.parametrize(
    ("option", "value", "line"),
    [
        # 1/Kv is line to line: the phase k_e, half of it, is held to the range
        ("--kv", "1e400", "motor.back_emf_constant = 5e-401 V/rpm is out of range"),
        ("--kv", "1e-400", "motor.back_emf_constant = 5e+399 V/rpm is out of range"),
        ("--resistance", "1e400 ohm", "motor.phase_resistance = 1e+400 ohm is out of range"),
        (
            "--resistance-line-to-line",
            "1e-400 ohm",
            "halved to the phase value: motor.phase_resistance = 5e-401 ohm is out of range",
        ),
        ("--rated-voltage", "1e400 V", "motor.rated_voltage = 1e+400 V is out of range"),
        ("--pwm-frequency", "1e-400 Hz", "inverter.pwm_frequency = 1e-400 Hz is out of range"),
        ("--ke", "1e-9 V/krpm", "motor.back_emf_constant = 1e-12 V/rpm is out of range"),
        ("--poles", "1000", "'1000' is not an even whole number from 2 to 128"),
        ("--poles", "3", "'3' is not an even whole number from 2 to 128"),
        # init wrote 0.1 A under the source 'nominal braking current 1e-3 A'
        ("--braking-current", "1e-3 A", "'1e-3 A' is below 0.1 A, the smallest nominal"),
        # init wrote braking_current_max = 1200 A, which the loader refused (<= 1000 A)
        ("--braking-current", "600 A", "'600 A' is above 500 A, the largest whose"),
    ],
)
def test_init_should_refuse_a_value_no_spec_can_hold_at_its_argument(
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
    capsys: pytest.CaptureFixture[str],
    option: str,
    value: str,
    line: str,
) -> None:
    """`--kv 1e400` (or 1e400 ohm, 1e-400 Hz) was an internal error, a float overflow in
    init (exit 70); `--ke 1e-9 V/krpm` wrote a spec refused for a top speed of 1e13 rpm
    derived from it; `--poles 1000` said 'from 1 to 64'. A datasheet value is held to
    the loader's range of the key it becomes, at its argument, in one line."""
    monkeypatch.chdir(tmp_path)
    with pytest.raises(SystemExit) as caught:
        cli.main(["init", "m", option, value])
    assert caught.value.code == ExitCode.USAGE
    err = capsys.readouterr().err.strip().splitlines()
    assert err[-1].startswith(f"bldc-codegen init: error: argument {option}: "), err[-1]
    assert line in err[-1]
    assert "(allowed: " in err[-1] or "whole number" in err[-1]
    assert not (tmp_path / "spec").exists()


@pytest.mark.parametrize(
    ("argv", "line"),
    [
        (["verify", "SPEC", "--seed", "-1"], "argument --seed: -1 is out of range"),
        (["verify", "SPEC", "--random", "-5"], "argument --random: -5 is out of range"),
        (["all", "SPEC", "--random", "-5"], "argument --random: -5 is out of range"),
        (["robustness", "SPEC", "--seed", "x"], "argument --seed: 'x' is not a whole number"),
        # distributed's own parser had raised ValueError (an internal error), and a
        # port of 99999 waited 30 s for a connection
        (
            ["robustness", "SPEC", "--scheduler", "not a url"],
            "argument --scheduler: 'not a url' is not a scheduler address: no host:port"
            " (allowed: [tcp|tls|ws|wss|ucx://]host:port, port 1-65535)",
        ),
        (["robustness", "SPEC", "--scheduler", "bogus://x:1"], "unknown scheme 'bogus'"),
        (["robustness", "SPEC", "--scheduler", "tcp://h:99999"], "port '99999' is not a port"),
        (["robustness", "SPEC", "--scheduler", ""], "'' is not a scheduler address"),
        # int() and Fraction() take other scripts' digits and digit groups; a spec does not
        (["verify", "SPEC", "--seed", "\u0661\u0662"], "is not a whole number (ASCII digits"),
        (["verify", "SPEC", "--seed", "1_2"], "'1_2' is not a whole number (ASCII digits"),
        (["init", "x", "--kv", "\u0666\u0662\u0665"], "is not a number (ASCII digits, no '_')"),
        (["init", "x", "--kv", "1_000"], "argument --kv: '1_000' is not a number (ASCII"),
    ],
)
def test_a_numeric_option_out_of_range_should_be_one_usage_line(
    capsys: pytest.CaptureFixture[str], argv: list[str], line: str
) -> None:
    """A negative seed or point count once reached NumPy (an internal error)."""
    with pytest.raises(SystemExit) as caught:
        cli.main([str(SPEC) if a == "SPEC" else a for a in argv])
    assert caught.value.code == ExitCode.USAGE
    err = capsys.readouterr().err.strip().splitlines()
    assert line in err[-1] and "Traceback" not in "\n".join(err)


_MANY_DIGITS = "1" * 5000


@pytest.mark.parametrize(
    ("argv", "line"),
    [
        # an exponent of 7 digits ran init's exact Fraction arithmetic for ever
        (["init", "x", "--kv", "1e9999999"], "argument --kv: '1e9999999' is not a number (ASCII"),
        # more than 4300 digits were int()'s ValueError: "invalid _kv value: '1111...'"
        (["init", "x", "--kv", _MANY_DIGITS], "argument --kv: '111"),
        (["verify", "SPEC", "--seed", _MANY_DIGITS], "(allowed: [0, 4294967295])"),
        (["verify", "SPEC", "--random", _MANY_DIGITS], "(allowed: [0, 100000000])"),
        (["robustness", "SPEC", "--seed", _MANY_DIGITS], "argument --seed: 111"),
        (["init", "x", "--pole-pairs", _MANY_DIGITS], "is not a whole number from 1 to 64"),
        (["init", "x", "--poles", _MANY_DIGITS], "is not an even whole number from 2 to 128"),
    ],
)
def test_a_numeric_option_of_many_digits_should_be_one_clipped_line_at_once(
    capsys: pytest.CaptureFixture[str], argv: list[str], line: str
) -> None:
    """A number is held to the digits a spec quantity takes before it is converted:
    refused in one usage line that clips the value, not a hang nor argparse's generic
    'invalid ... value' echoing 5000 digits."""
    with pytest.raises(SystemExit) as caught:
        cli.main([str(SPEC) if a == "SPEC" else a for a in argv])
    assert caught.value.code == ExitCode.USAGE
    err = capsys.readouterr().err.strip().splitlines()
    assert line in err[-1] and "invalid" not in err[-1], err[-1]
    assert len(err[-1]) < 300, err[-1]


def test_init_should_size_the_current_sensing_and_the_trip_above_the_pwm_ripple(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """A small high-speed motor (2 x 5 uH at 20 kHz, 30 V bus_voltage_max): its braking
    current ripples by 37.5 A peak to peak above the sample the loop holds, so 40 A of
    braking_current_max peaks at 77.5 A. init sizes the sensing's full scale and the
    comparator's trip to 1.25 x that (17 mV/A: 97 A; 97 A), and the spec loads."""
    from codegen.spec_loader import load_spec

    monkeypatch.chdir(tmp_path)
    argv = ["init", "tiny4p", "--pole-pairs", "2", "--kv", "1000"]
    argv += ["--resistance-line-to-line", "0.05 ohm", "--inductance-line-to-line", "0.01 mH"]
    argv += ["--bus-voltage", "24 V", "--braking-current", "20 A", "--pwm-frequency", "20 kHz"]
    assert cli.main(argv) == 0
    capsys.readouterr()
    spec = load_spec(tmp_path / "spec" / "tiny4p.yaml")
    assert spec.adc.current_gain_v_per_a == Fraction(17, 1000)
    assert spec.protection.over_current_a == 97
    span = (spec.adc.reference_v - spec.adc.current_offset_v) / spec.adc.current_gain_v_per_a
    assert span >= Fraction(5, 4) * Fraction(155, 2)  # 40 A + 37.5 A of ripple
    sources = dict(spec.sources)
    assert "braking_current_max + 37.5 A of PWM ripple" in sources["adc.current_gain"]


def test_init_should_write_a_short_circuit_rating_a_spec_can_name(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """A tiny, stiff motor (0.1 mohm, 0.1 uH): its short-circuit bound at the paper's top
    speed is about 256 kA, 212.4 kA at the top speed init now keeps below the speed where
    all-off may rectify (99 % of it, for a rotor 5 % faster than its last Hall interval
    says: the test below). init had written the bound, and the loader refused the number it
    wrote (out of (0, 10000] A) instead of the values the user has to change; it writes
    the 10 kA a spec may name, says so in the source, and the loader's lines name the
    motor's real problems, not the rating."""
    from codegen.spec_drive import PROTECTION_AMPS_MAX
    from codegen.yaml12 import read_yaml

    monkeypatch.chdir(tmp_path)
    argv = ["init", "tiny", "--resistance", "0.1 mohm", "--inductance", "0.1 uH"]
    assert cli.main(argv) == ExitCode.SPEC  # written, but not loadable yet: edit it
    err = capsys.readouterr().err
    assert "short_circuit_current_max" not in err
    assert "does not load yet" in err
    data, _ = read_yaml((tmp_path / "spec" / "tiny.yaml").read_bytes())
    assert data["protection"]["short_circuit_current_max"] == f"{PROTECTION_AMPS_MAX} A"
    note = data["sources"]["protection.short_circuit_current_max"]
    # the bound at c x speed_max, where the port rates a preferred short (c = 1/(1 - s))
    assert "is 221547 A, beyond the 10000 A a spec may name" in note


@pytest.mark.parametrize(("bus", "low", "high"), [("800 V", 640, 1000), ("1.25 V", 1, "1.57")])
def test_init_should_keep_the_bus_range_within_the_voltages_a_spec_holds(
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
    capsys: pytest.CaptureFixture[str],
    bus: str,
    low: object,
    high: object,
) -> None:
    """--bus-voltage takes 1.25 to 800 V, and init writes 0.8 and 1.25 x it: a 1000 V
    bus had written a 1250 V bus_voltage_max and a 1 V one a 0.8 V minimum, which the
    spec then refused. Each is held to the loader's voltages, and its source says so;
    1 V and 1000 V are refused at the option (held to the loader's 1 V, the minimum was
    the nominal bus, which the drive reads as under-voltage)."""
    from codegen.spec_loader import load_spec

    monkeypatch.chdir(tmp_path)
    argv = ["init", "bus_end", "--kv", "100", "--bus-voltage", bus, "--rated-voltage", bus]
    assert cli.main(argv) == 0, capsys.readouterr().err
    capsys.readouterr()
    spec = load_spec(tmp_path / "spec" / "bus_end.yaml")
    assert spec.inverter.bus_voltage_min_v == Fraction(str(low))
    assert spec.inverter.bus_voltage_max_v == Fraction(str(high))
    sources = dict(spec.sources)
    held = sources["inverter.bus_voltage_max" if bus == "800 V" else "inverter.bus_voltage_min"]
    assert ("at most 1000 V" if bus == "800 V" else "at least 1 V") in held
    for refused in ("1 V", "1000 V"):
        with pytest.raises(SystemExit) as caught:
            cli.main(["init", "bus_out", "--bus-voltage", refused])
        assert caught.value.code == ExitCode.USAGE
        assert f"argument --bus-voltage: '{refused}' is" in capsys.readouterr().err


def test_init_should_put_the_lower_operating_point_where_the_current_can_be_held(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """A 60-pole hub motor braking 20 A through 0.3 ohm: the back-EMF drives at most E/R,
    which reaches 20 A at 96 rpm. init's usual lower point, 30 % of 300 rpm, is below it;
    init moves the point to where E = 1.5 x R x I (144 rpm, rounded up to 150) and the
    spec loads without the loader's warning that the current cannot be held there."""
    from codegen.spec_loader import load_spec

    monkeypatch.chdir(tmp_path)
    argv = ["init", "hub30pp", "--pole-pairs", "30", "--kv", "8", "--resistance", "0.3 ohm"]
    argv += ["--inductance", "400 uH", "--bus-voltage", "48 V", "--braking-current", "20 A"]
    argv += ["--speed-max", "300 rpm", "--pwm-frequency", "20 kHz"]
    assert cli.main(argv) == 0
    captured = capsys.readouterr()
    assert "warning" not in captured.err + captured.out
    spec = load_spec(tmp_path / "spec" / "hub30pp.yaml")
    assert [float(p.speed_rpm) for p in spec.operating_points] == [150.0, 270.0]


def test_init_should_keep_a_many_pole_motors_top_speed_inside_the_sampled_sectors(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """50 pole pairs on the paper motor's k_e and 24 V: 95 % of U_d/(2 k_e) is 4830 rpm,
    whose 41.4 us sector ends before the current loop's first sample after the Hall edge
    (52.7 us at 20 kHz, edge-aligned), and init wrote a spec its own loader refused
    (exit 3). init now takes 95 % of the fastest speed whose sector, less its 1/16
    margin, outlasts the commutation end's guard (0.5 us dead time + 4 us + one current
    sample, a 50 us period and 6.9 us of the ADC's sequence: 3053 rpm), and now below
    that 95 % of the speed whose sector holds STEADY_SECTOR_PWM_PERIODS (4.5 at 20 kHz:
    889 rpm; with fewer loop samples a sector the braking locked into a two-sector
    cycle): 840 rpm, says why in `sources`, and the spec loads without the warning the
    loader gives a faster one."""
    from codegen.spec_loader import load_spec

    monkeypatch.chdir(tmp_path)
    assert cli.main(["init", "hub50pp", "--pole-pairs", "50"]) == 0
    captured = capsys.readouterr()
    assert "error" not in captured.err
    spec = load_spec(tmp_path / "spec" / "hub50pp.yaml")
    assert spec.controller.speed_max_rpm == 840
    assert "holds 4.5 PWM periods" in dict(spec.sources)["controller.speed_max"]
    assert "few-pwm-periods-per-sector" not in [w.id for w in spec.warnings]
    # a motor the sector does not limit keeps 95 % of U_d/(2 k_e)
    assert cli.main(["init", "pp7", "--pole-pairs", "7", "-o", "pp7.yaml"]) == 0
    capsys.readouterr()
    assert load_spec(tmp_path / "pp7.yaml").controller.speed_max_rpm == 4830


def test_init_should_write_a_centre_aligned_carrier_when_asked(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """init wrote edge-aligned PWM only, so a centre-aligned board's spec was edited by
    hand after it, its source still saying "init default, edge-aligned", and what init
    checks (the ripple above the sample, the current gain) was an edge-aligned carrier's
    (a helper's 23-pole-pair 60 kHz motor: a sample-window warning init never gave).
    `--pwm-alignment center` writes it and says where it came from; a frequency whose
    half period is no whole number of TIM1 counts is refused in one line, before
    anything is written."""
    from codegen.spec_loader import load_spec

    monkeypatch.chdir(tmp_path)
    argv = ["init", "cen", "-o", "cen.yaml", "--pole-pairs", "4", "--pwm-frequency", "40 kHz"]
    assert cli.main([*argv, "--pwm-alignment", "center"]) == 0, capsys.readouterr().err
    capsys.readouterr()
    spec = load_spec(tmp_path / "cen.yaml")
    assert spec.inverter.pwm_alignment == "center"
    assert "init --pwm-alignment" in dict(spec.sources)["inverter.pwm_alignment"]
    edge = ["init", "edge", "-o", "edge.yaml", "--pole-pairs", "4", "--pwm-frequency", "40 kHz"]
    assert cli.main(edge) == 0
    capsys.readouterr()
    gain = dict(load_spec(tmp_path / "edge.yaml").sources)["adc.current_gain"]
    assert "edge-aligned" in gain and "center-aligned" in dict(spec.sources)["adc.current_gain"]
    odd = ["init", "odd", "-o", "odd.yaml", "--pwm-frequency", "64 kHz", "--pwm-alignment"]
    assert cli.main([*odd, "center"]) == 2
    err = capsys.readouterr().err.splitlines()
    assert len(err) == 1, err
    assert err[0].startswith("error: argument --pwm-frequency: '64 kHz' gives 562.5 TIM1 counts")
    assert "(allowed: 36 MHz / N" in err[0] and "62500 Hz (576 counts)" in err[0], err
    assert not (tmp_path / "odd.yaml").exists()
    assert cli.main([*odd, "edge"]) == 0  # 1125 counts: a whole edge-aligned period


@pytest.mark.parametrize(
    ("frequency", "alignment", "line"),
    [
        # a spec the loader refused (10285.7 counts, not whole): its exact neighbours
        ("7 kHz", "edge", "e.g. 7031.25 Hz (10240 counts) or 6400 Hz (11250 counts)"),
        ("2 kHz", "edge", "36000 TIM1 counts per period at 72 MHz (edge-aligned)"),
        ("1 kHz", "center", "36000 TIM1 counts per half period at 72 MHz (center-aligned)"),
    ],
)
def test_init_should_judge_the_pwm_period_at_the_alignment_asked_for(
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
    capsys: pytest.CaptureFixture[str],
    frequency: str,
    alignment: str,
    line: str,
) -> None:
    """The option's own check was the edge-aligned period's, made before argparse knew
    the alignment: `--pwm-frequency "2 kHz" --pwm-alignment center` (a half period of
    18000 counts, which the loader takes) was refused for the 36000-count whole period,
    the line saying edge-aligned (a helper's hunt: every centre-aligned frequency from
    1098.7 to 2197 Hz). The period is judged at the alignment asked for, edge by default,
    in one line before anything is written."""
    from codegen.spec_loader import load_spec

    monkeypatch.chdir(tmp_path)
    argv = ["init", "m", "-o", "m.yaml", "--pwm-frequency", frequency]
    argv += [] if alignment == "edge" else ["--pwm-alignment", alignment]
    assert cli.main(argv) == ExitCode.USAGE
    err = capsys.readouterr().err.splitlines()
    assert len(err) == 1 and err[0].startswith("error: argument --pwm-frequency: "), err
    assert line in err[0] and "(allowed: " in err[0], err
    assert not (tmp_path / "m.yaml").exists()
    if frequency == "2 kHz":  # its half period is whole: centre-aligned it is written
        argv += ["--pwm-alignment", "center"]
        assert cli.main(argv) == 0, capsys.readouterr().err
        spec = load_spec(tmp_path / "m.yaml")
        assert (spec.inverter.pwm_frequency_hz, spec.inverter.pwm_alignment) == (2000, "center")


def test_init_should_never_replace_a_folder_or_a_fifo_even_with_force(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """`init -o FOLDER --force` failed on its temporary file ('.specs.tmp-123: Is a
    directory'), and with --force the atomic rename put a spec in place of a FIFO (or,
    as root, of /dev/null). Only a regular file is ever replaced: anything else is
    refused in one line (exit 5) and left as it was."""
    import os
    import stat

    monkeypatch.chdir(tmp_path)
    folder = tmp_path / "specs"
    folder.mkdir()
    fifo = tmp_path / "pipe"
    os.mkfifo(fifo)
    for target, kind in ((folder, "is a folder"), (fifo, "is not a regular file")):
        assert cli.main(["init", "m", "-o", str(target), "--force"]) == ExitCode.ENVIRONMENT
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and kind in err[0] and "-o takes the spec FILE" in err[0], err
    assert list(folder.iterdir()) == []
    assert stat.S_ISFIFO(os.stat(fifo).st_mode)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["pipe", "specs"]


HEAVY_L = [
    *("init", "heavy_l", "--pole-pairs", "2", "--resistance", "1.5 ohm", "--inductance"),
    *("2 mH", "--ke", "0.05 V/rpm", "--bus-voltage", "24 V", "--braking-current", "3 A"),
    *("--speed-max", "200 rpm", "--pwm-frequency", "8 kHz"),
]


def test_init_should_write_a_current_loop_accuracy_its_pi_meets(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """A 2 mH motor at 8 kHz with an 800 Hz loop: its PI's widest format (Q13, the
    proportional product fills int32) claimed k_i's rounding times every error of the ADC
    range, 1.002 counts over a step response, and init wrote 1.01 counts. Over the errors
    that can leave the output unsaturated it meets init's 1 count; the spec says 1 and
    its PI designs."""
    from codegen.control.current_loop import accuracy_needed, design
    from codegen.spec_loader import load_spec

    monkeypatch.chdir(tmp_path)
    assert cli.main(HEAVY_L) == 0
    capsys.readouterr()
    spec = load_spec(tmp_path / "spec" / "heavy_l.yaml")
    assert spec.accuracy.current_loop_duty_counts == 1
    assert accuracy_needed(design(spec)) <= 1


def test_init_should_take_the_hall_clock_a_long_commutation_needs(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """1 H and 80 ohm a phase on 310 V: init's 4 MHz Hall clock leaves Eq. 20's X no
    fraction bit, and half a count of W at up to 80 ticks a count (the points `verify`
    holds to 8 ticks) is 41 ticks. `generate` wrote it and `verify` failed it (38.6
    ticks); init now takes the Hall clock the design names (500 kHz, with a note), and
    the spec generates and verifies."""
    from codegen.spec_loader import load_spec

    argv = [
        *("init", "hv_1h", "--inductance", "1 H", "--resistance", "80 ohm"),
        *("--bus-voltage", "310 V", "--braking-current", "0.2 A"),
    ]
    monkeypatch.chdir(tmp_path)
    assert cli.main(argv) == 0
    said = capsys.readouterr()
    assert "init: note: hall.timer_clock = 500000 Hz: " in said.out + said.err, said
    path = tmp_path / "spec" / "hv_1h.yaml"
    spec = load_spec(path)
    assert spec.hall.timer_clock_hz == 500_000
    assert "commutation core" in dict(spec.sources)["hall.timer_clock"]
    assert cli.main(["generate", str(path), "-o", "out"]) == 0
    assert cli.main(["verify", str(path), "--generated", "out", "--no-progress"]) == 0
    capsys.readouterr()


def test_init_should_write_a_large_inductance_motor_that_generates_and_verifies(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """A 1 H, 100 ohm motor on 48 V: its PI's claims over every error of the ADC range
    came to 35.5 counts, and init refused it (naming a current-sense gain). k_p of
    thousands of counts a code saturates the output beyond a code of error, exactly and
    as printed: over the errors that can leave it unsaturated the PI meets 1 count, and
    the spec init writes generates and passes `verify`."""
    argv = [
        *("init", "big_l", "--pole-pairs", "4", "--ke", "50 V/krpm"),
        *("--resistance", "100 ohm", "--inductance", "1 H", "--bus-voltage", "48 V"),
    ]
    monkeypatch.chdir(tmp_path)
    assert cli.main(argv) == 0, capsys.readouterr().err
    path = tmp_path / "spec" / "big_l.yaml"
    assert "current_loop_duty_counts: 1.0\n" in path.read_text()
    assert cli.main(["generate", str(path), "-o", "out"]) == 0
    assert cli.main(["verify", str(path), "--generated", "out", "--no-progress"]) == 0
    capsys.readouterr()


#: a 4-pole-pair Kv-30 motor on 6 V: 10 mohm and 2.5 uH a phase, 40 kHz, method none
KV30_NONE = [
    *("--pole-pairs", "4", "--kv", "30", "--resistance-line-to-line", "0.02 ohm"),
    *("--inductance-line-to-line", "5 uH", "--bus-voltage", "6 V", "--method", "none"),
    *("--pwm-frequency", "40 kHz"),
]


@pytest.mark.parametrize(
    ("argv", "key", "written"),
    [
        (KV30_NONE, "accuracy.commutation_time_ticks", Fraction(15075, 1000)),
        (
            [
                *("--pole-pairs", "1", "--kv", "100", "--resistance-line-to-line", "0.1 ohm"),
                *("--inductance-line-to-line", "5 mH", "--bus-voltage", "48 V"),
                *("--method", "improved_r", "--pwm-frequency", "16 kHz"),
            ],
            "accuracy.duty_counts",
            Fraction(14, 10),
        ),
    ],
    ids=["none-time", "improved_r-duty"],
)
def test_init_should_write_the_commutation_accuracy_its_core_can_meet(
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
    capsys: pytest.CaptureFixture[str],
    argv: list[str],
    key: str,
    written: Fraction,
) -> None:
    """init ran the current loop's design but not the commutation core's: on these
    motors it said "next: generate", and `generate` refused (the none core's best
    format bounds t_com by 15.07 ticks against init's 8; the improved_r rule's duty bound
    is 1.39 counts against 1). init now runs the core's design too, writes the target it
    meets, says so in `sources` and in a note, and `generate`'s design accepts the spec."""
    from codegen.core.module import build_core
    from codegen.spec_loader import load_spec

    monkeypatch.chdir(tmp_path)
    assert cli.main(["init", "own", *argv]) == 0
    err = capsys.readouterr().err.splitlines()
    notes = [line for line in err if line.startswith("init: note:")]
    assert len(notes) == 1 and key in notes[0] and "out of its reach" in notes[0], err
    assert err[-1].startswith("init: next: edit it, then"), err
    spec = load_spec(tmp_path / "spec" / "own.yaml")
    attribute = key.removeprefix("accuracy.")
    assert getattr(spec.accuracy, attribute) == written
    assert "out of reach" in dict(spec.sources)[key]
    build_core(spec)  # the design `generate` runs: no refusal


def test_init_should_refuse_in_one_line_a_motor_whose_core_meets_no_spec_target(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """The improved_r rule's duty bound on a 2.5 mH, 10 mohm motor is 55.85 counts over
    every design point (with init's 1/Kv rounded up at the 9th digit; 56.09 with it
    rounded at the 6th, which moved the top speed and the design grid), beyond the 16 a
    spec may ask:
    init keeps the target it wrote and reports `generate`'s refusal (exit 3), which names
    the bound and another method, instead of writing a spec its own loader refuses."""
    argv = [
        *("init", "slow_l", "--pole-pairs", "4", "--kv", "300"),
        *("--resistance-line-to-line", "0.02 ohm", "--inductance-line-to-line", "5 mH"),
        *("--bus-voltage", "24 V", "--method", "improved_r"),
    ]
    monkeypatch.chdir(tmp_path)
    assert cli.main(argv) == ExitCode.SPEC
    err = capsys.readouterr().err.splitlines()
    assert err[0].startswith("error: spec/slow_l.yaml: accuracy.duty_counts: fixed-point"), err
    assert "duty bound 55.8" in err[0] and "exceeds the target 1" in err[0], err[0]
    # more than any spec may ask (accuracy.duty_counts <= 16): the method is to change
    assert "(allowed: <= 16 counts, which this motor's rule does not reach" in err[0], err[0]
    assert "duty_counts: 1.0\n" in (tmp_path / "spec" / "slow_l.yaml").read_text()


def test_init_should_keep_the_rules_shortest_sector_longer_than_a_pwm_period(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """A 15-pole-pair Kv-700 motor on 60 V at 8 kHz with `--method improved_r`: init wrote
    4780 rpm, whose 539-tick sector less the 18-tick guard and the 1/16 margin (487
    ticks) holds no 500-tick PWM period, and the rule's design refused it (exit 3). init
    now caps the top speed where that sector, less the guard with its room for a
    current sample (a PWM period and the ADC's sequence), holds one period more (95 % of
    2391 rpm: 2270), and now where it holds STEADY_SECTOR_PWM_PERIODS (4.5 at 8 kHz: 95 %
    of 1185 rpm, 1120), and says why in `sources`; the rule's design takes it."""
    from codegen.spec_loader import load_spec

    argv = [
        *("init", "pp15", "--pole-pairs", "15", "--kv", "700", "--method", "improved_r"),
        *("--resistance-line-to-line", "0.6 ohm", "--inductance-line-to-line", "12 mH"),
        *("--bus-voltage", "60 V", "--pwm-frequency", "8 kHz"),
    ]
    monkeypatch.chdir(tmp_path)
    assert cli.main(argv) == 0, capsys.readouterr().err
    spec = load_spec(tmp_path / "spec" / "pp15.yaml")
    assert spec.controller.speed_max_rpm == 1120
    assert "holds 4.5 PWM periods" in dict(spec.sources)["controller.speed_max"]
    assert "few-pwm-periods-per-sector" not in [w.id for w in spec.warnings]


REFUSED = ROOT / "tests" / "fixtures" / "refused" / "heavy_l_pi_one_count.yaml"


@pytest.mark.parametrize(
    "command",
    [
        ["simulate", "--quick", "--no-progress"],
        ["robustness", "--samples", "2", "--speeds", "2", "--no-progress"],
        ["bench", "--quick", "--report-only"],
    ],
    ids=["simulate", "robustness", "bench"],
)
def test_a_spec_no_design_meets_is_a_bad_spec_for_every_command(
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
    capsys: pytest.CaptureFixture[str],
    command: list[str],
) -> None:
    """A valid spec whose current loop no fixed-point format meets: `generate` refuses
    it (exit 3, one line naming the key). `simulate` and `robustness` said 'software in
    the loop failed' about a variant in build/sim/specs/ and exited 5 (the environment),
    `bench` exited 2 (a usage error); each says what `generate` says, exit 3."""
    monkeypatch.chdir(tmp_path)
    code = cli.main([command[0], str(REFUSED), *command[1:]])
    err = [line for line in capsys.readouterr().err.splitlines() if not line.startswith("warn")]
    assert code == ExitCode.SPEC, err
    assert len(err) == 1, err
    assert f"{REFUSED}: accuracy.current_loop_duty_counts: fixed-point design: " in err[0]
    assert "(allowed: >= 2.991 counts)" in err[0]
    assert "build/sim" not in err[0]
    assert not (tmp_path / "generated").exists()


@pytest.mark.parametrize(
    ("name", "datasheet", "edit"),
    [
        pytest.param(
            "hub46",
            [
                *("--pole-pairs", "23", "--ke", "60 V/krpm"),
                *("--resistance-line-to-line", "0.24 ohm", "--inductance", "0.25 mH"),
                *("--bus-voltage", "48 V", "--speed-max", "360 rpm", "--braking-current", "8 A"),
            ],
            ("sequence: [5, 4, 6, 2, 3, 1]", "sequence: [3, 2, 6, 4, 5, 1]"),
            id="46-pole-hub-cut-off-200-rpm-reversed-hall-order",
            marks=pytest.mark.heavy(seconds=16),
        ),
        pytest.param(
            "drone14",
            [
                *("--poles", "14", "--kv", "625", "--resistance-line-to-line", "0.1 ohm"),
                *("--inductance-line-to-line", "30 uH", "--bus-voltage", "12 V"),
                *("--speed-max", "7000 rpm", "--pwm-frequency", "16 kHz"),
            ],
            ("pwm_alignment: edge", "pwm_alignment: center"),
            id="14-pole-7000-rpm-line-to-line-centre-aligned-16-kHz",
            marks=pytest.mark.heavy(seconds=9),
        ),
        pytest.param(
            "conventional",
            [
                *("--ke-line-to-line", "8 V/krpm", "--resistance", "0.3 ohm"),
                *("--inductance", "0.4 mH", "--bus-voltage", "24 V", "--braking-current", "6 A"),
            ],
            ("method: improved", "method: conventional"),
            id="conventional-method",
            marks=pytest.mark.heavy(seconds=13),
        ),
    ],
)
def test_a_new_users_motor_goes_through_every_step_outside_the_repo(
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
    name: str,
    datasheet: list[str],
    edit: tuple[str, str],
    capsys: pytest.CaptureFixture[str],
) -> None:
    """init, edit, generate, firmware, unity, verify, simulate and bench from an empty
    folder outside the repo (simulate and bench in their quick forms: every study at a
    few speeds, the bench's size and handler sections, and for one motor its PIL run)."""
    monkeypatch.chdir(tmp_path)
    assert cli.main(["init", name, *datasheet]) == 0
    spec = Path("spec") / f"{name}.yaml"
    spec.write_text(spec.read_text().replace(*edit))
    assert cli.main(["generate", str(spec)]) == 0
    assert cli.main(["firmware", str(spec)]) == 0
    assert (tmp_path / "build" / name / "firmware.elf").is_file()
    assert cli.main(["unity", str(spec)]) == 0
    if name == "hub46":
        assert cli.main(["verify", str(spec), "--no-progress", "--random", "2000"]) == 0
        assert (tmp_path / "generated" / name / "verify" / "report.json").is_file()
        assert cli.main(["generate", str(spec)]) == 0  # the report survives a regenerate
        assert (tmp_path / "generated" / name / "verify" / "report.json").is_file()
    assert cli.main(["simulate", str(spec), "--quick", "--no-progress"]) == 0
    report = tmp_path / "generated" / name / "simulation" / "SIMULATION.md"
    assert "quick run" in report.read_text()
    # the PIL section links the firmware through emulation/pil/build.py, which reads a
    # relative folder from the project root: the bench's own folder is relative to here
    sections = "size,handlers,pil" if name == "conventional" else "size,handlers"
    bench = ["bench", str(spec), "--quick", "--report-only", "--only", sections]
    capsys.readouterr()
    assert cli.main(bench) == 0
    said = capsys.readouterr().out
    assert "not run" not in said, said  # --report-only exits 0 on a miss: read the lines
    if "pil" in sections:
        assert "bench: PIL: 100 ms of motor time, plant in the loop:" in said, said
    assert (tmp_path / "build" / "bench" / name).is_dir()


def test_the_module_entry_points_stay_and_unity_run_has_help() -> None:
    for module in ("codegen", "verify.unity_run"):
        result = subprocess.run(
            [sys.executable, "-m", module, "--help"],
            cwd=ROOT,
            capture_output=True,
            text=True,
            check=False,
        )
        assert result.returncode == 0, result.stderr
        assert "Traceback" not in result.stderr and result.stdout.startswith("usage:")


def test_make_targets_honour_spec(tmp_path: Path) -> None:
    def dry_run(*args: str) -> str:
        return subprocess.run(
            ["make", "-n", "--no-print-directory", *args],
            cwd=ROOT,
            capture_output=True,
            text=True,
            check=True,
        ).stdout

    # each spec reaches the shell single-quoted (a '(' or a quote in a path)
    for target in ("derive", "generate", "firmware"):
        out = dry_run(target, "SPEC=my/motor.yaml")
        assert f"-m codegen {target} 'my/motor.yaml'" in out, (target, out)
        assert "spec/paper_motor.yaml" not in out, (target, out)
    assert "-m emulation 'my/motor.yaml'" in dry_run("bench", "SPEC=my/motor.yaml")
    for target in ("verify", "unity", "simulate"):
        out = dry_run(target, "SPEC=my/motor.yaml")
        assert "for spec in 'my/motor.yaml'; do" in out, (target, out)
        assert f'-m codegen {target} "$spec"' in out, (target, out)
    assert "-m codegen audit 'my/motor.yaml'" in dry_run("audit", "SPEC=my/motor.yaml")
    assert dry_run("audit").rstrip().endswith("-m codegen audit")  # the paper's audit alone
    assert "-m verify.prove 'my/motor.yaml'" in dry_run("prove", "SPEC=my/motor.yaml")
    assert "-m emulation.pil.report 'my/motor.yaml'" in dry_run("pil", "SPEC=my/motor.yaml")
    assert "for spec in 'my/motor.yaml'; do" in dry_run("robustness", "SPEC=my/motor.yaml")
    assert "spec/paper_motor_improved_r.yaml" in dry_run("verify")
    assert "spec/example_maxon_ec45_flat_48v.yaml" in dry_run("simulate")
    assert "-m codegen firmware 'spec/paper_motor.yaml'" in dry_run("firmware")


def test_a_bad_spec_is_reported_without_loading_the_derivation(tmp_path: Path) -> None:
    """The spec-error path needs no SymPy: the loader runs before any heavy import."""
    bad = tmp_path / "bad.yaml"
    bad.write_text(SPEC.read_text().replace("0.56 mH", "0.56 mh"))
    code = (
        "import sys; from bldc import cli;"
        f"status = cli.main(['generate', {str(bad)!r}, '-o', {str(tmp_path / 'out')!r}]);"
        "print(status, 'sympy' in sys.modules)"
    )
    result = subprocess.run(
        [sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True, check=True
    )
    assert result.stdout.split() == [str(int(ExitCode.SPEC)), "False"], result.stderr


def test_bench_help_names_every_section_the_bench_has() -> None:
    import bldc.commands  # noqa: F401  (registers the commands)
    from emulation.bench import SECTIONS

    parser = argparse.ArgumentParser()
    cli.COMMANDS["bench"].arguments(parser)
    only = next(a for a in parser._actions if a.dest == "only")
    assert only.help is not None
    assert only.help.rsplit(": ", 1)[1].split(", ") == list(SECTIONS)


def test_robustness_runs_from_the_cli_outside_the_repo(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """`bldc-codegen robustness`: the campaign on a local Dask cluster, its report where
    the user is, the path shown as the user would type it."""
    monkeypatch.chdir(tmp_path)
    spec = tmp_path / "motor.yaml"
    shutil.copy(ROOT / "tests" / "fixtures" / "specs" / "hub_motor_46p.yaml", spec)
    argv = ["robustness", "motor.yaml", "--samples", "4", "--speeds", "2"]
    argv += ["--methods", "improved", "--workers", "1", "--chunk", "2", "--no-progress"]
    assert cli.main(argv) == 0
    name = load_spec(spec).name
    report = tmp_path / "generated" / name / "robustness" / "ROBUSTNESS.md"
    assert report.is_file() and "improved" in report.read_text()
    assert f"-> generated/{name}/robustness:" in capsys.readouterr().out
    with pytest.raises(SystemExit) as caught:
        cli.main([*argv[:2], "--samples", "0"])
    assert caught.value.code == ExitCode.USAGE
    assert "argument --samples: 0: at least 2" in capsys.readouterr().err


def test_init_should_write_a_duty_target_the_rule_meets_when_its_bound_is_printed(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """improved_r on a 50 mH, 0.5 ohm, 300 V motor: the rule's duty bound was 3.2300x
    counts; its refusal printed 3.230, init wrote 3.23 and the design refused that too
    ("loads, but its fixed-point design does not fit"). The refusal prints the bound
    rounded up, and init wrote 3.24; with zero current in the design grid the bound is
    3.24699 counts, printed 3.247, and init writes 3.25."""
    argv = [
        *("init", "lrhl", "--pole-pairs", "2", "--resistance", "0.5 ohm"),
        *("--inductance", "50 mH", "--ke", "50 V/krpm", "--bus-voltage", "300 V"),
        *("--braking-current", "2 A", "--method", "improved_r"),
    ]
    monkeypatch.chdir(tmp_path)
    assert cli.main(argv) == 0, capsys.readouterr().err
    said = capsys.readouterr()
    assert "init: note: accuracy.duty_counts = 3.25 counts: " in said.out + said.err, said


def test_a_path_with_a_line_break_should_stay_on_one_line_in_every_message(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """init's and generate's lines printed the path raw: `init -o $'new\\nline.yaml'`
    split "init: wrote ..." over two lines; now it is quoted with its escapes."""
    monkeypatch.chdir(tmp_path)
    spec = "new\nline.yaml"
    assert cli.main(["init", "m1", "-o", spec]) == 0
    assert cli.main(["generate", spec, "-o", "o\nut"]) == 0
    said = capsys.readouterr()
    lines = (said.out + said.err).splitlines()
    assert "init: wrote 'new\\nline.yaml'" in lines
    assert any(line.startswith("generate: 21 files -> 'o\\nut' [") for line in lines), lines
    assert cli.main(["init", "m1", "-o", spec]) == ExitCode.USAGE
    err = capsys.readouterr().err.splitlines()
    assert err == ["error: 'new\\nline.yaml' exists; choose another -o FILE or pass --force"]


def test_init_should_write_a_loadable_spec_for_a_top_speed_of_a_few_rpm(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """`--speed-max 3 rpm` on a 46-pole hub motor: the 16-bit Hall counter at init's
    slowest 100 kHz fills above 3 rpm for a 2-pole motor (speed_min 16.8 rpm, a spec its
    loader refused), so init takes a slower clock there; its two operating points came
    within 1 rpm of each other (2.3 and 2.7 rpm), one is kept; `--speed-max 1 rpm` is
    refused at the option (its 90 % point, 0.9 rpm, is below a spec's 1 rpm)."""
    from codegen.spec_loader import load_spec

    monkeypatch.chdir(tmp_path)
    argv = ["init", "hub", "--pole-pairs", "23", "--ke", "600 V/krpm", "--resistance", "0.5 ohm"]
    assert cli.main([*argv, "--speed-max", "3 rpm", "--bus-voltage", "48 V"]) == 0
    spec = load_spec(tmp_path / "spec" / "hub.yaml")
    assert spec.controller.speed_max_rpm == 3 and len(spec.operating_points) == 1
    assert cli.main(["init", "two", "--pole-pairs", "1", "--speed-max", "5 rpm"]) in (0, 3)
    text = (tmp_path / "spec" / "two.yaml").read_text()
    assert "  timer_clock: 18 kHz\n" in text and "  speed_min: 3.05 rpm\n" in text
    capsys.readouterr()
    with pytest.raises(SystemExit) as caught:
        cli.main(["init", "one", "--speed-max", "1 rpm"])
    assert caught.value.code == ExitCode.USAGE
    assert "argument --speed-max: '1 rpm' is below 1.2 rpm" in capsys.readouterr().err


@pytest.mark.parametrize(
    "datasheet",
    [
        pytest.param(["--speed-max", "300 rpm"], id="paper-motor-at-300-rpm"),
        pytest.param(
            [
                *("--pole-pairs", "40", "--speed-max", "25 rpm", "--kv", "10"),
                *("--resistance-line-to-line", "3 ohm", "--inductance-line-to-line", "8 mH"),
                *("--bus-voltage", "36 V", "--method", "improved_r"),
            ],
            id="40-pole-pairs-at-25-rpm",
        ),
    ],
)
def test_init_should_choose_a_braking_current_the_loop_can_hold_at_its_upper_point(
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
    capsys: pytest.CaptureFixture[str],
    datasheet: list[str],
) -> None:
    """With no braking current given, init took 5 A or half of E(speed_max)/R: on a
    slow motor more than the loop can hold at its upper operating point, 90 % of the
    top speed (the paper motor at 300 rpm: 1.6 A needs a duty of 0.975 there, D_max
    0.952), and the loader warned of init's own spec (a hunt). It now takes at most
    (2E - (1 - D_max) U_d) / (2R) there, and says so."""
    from codegen.spec_loader import load_spec

    monkeypatch.chdir(tmp_path)
    assert cli.main(["init", "slow", "-o", "slow.yaml", *datasheet]) == 0, capsys.readouterr().err
    spec = load_spec(tmp_path / "slow.yaml")
    assert "current-sense-window" not in [w.id for w in spec.warnings], spec.warnings
    text = (tmp_path / "slow.yaml").read_text()
    assert "what the current loop can hold at" in text


def test_init_should_place_its_lower_point_where_the_loop_can_hold_the_current(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """init's lower operating point sat where E = 1.5 R I, whatever the current sample's
    window left of the duty: at 100 kHz centre-aligned its 1440 rpm point needed a duty
    of 0.804 where D_max is 0.781, and the loader warned of init's own spec
    (`current-sense-window`; a helper's hunt). It now sits where the nominal current
    needs at most D_max."""
    from codegen.spec_loader import load_spec

    monkeypatch.chdir(tmp_path)
    argv = ["init", "c1", "-o", "c1.yaml", "--pwm-frequency", "100 kHz"]
    assert cli.main([*argv, "--pwm-alignment", "center"]) == 0, capsys.readouterr().err
    assert "current-sense-window" not in capsys.readouterr().err
    spec = load_spec(tmp_path / "c1.yaml")
    assert "current-sense-window" not in [w.id for w in spec.warnings]
    assert len(spec.operating_points) == 2


def test_init_should_keep_the_braking_current_within_what_a_slow_top_speed_drives(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """--speed-max 5 rpm on the paper motor: the back-EMF drives at most E/R = 56 mA
    there. init's least braking current, 0.1 A, had been written past it, a spec the
    loader refused (a hunt: 1.2 to 10 rpm); now half of E/R, to two digits (0.028 A),
    which loads (warning that the loop saturates where it would hold it)."""
    from codegen.spec_loader import load_spec

    monkeypatch.chdir(tmp_path)
    assert cli.main(["init", "slow", "--speed-max", "5 rpm", "-o", "slow.yaml"]) == 0
    capsys.readouterr()
    spec = load_spec(tmp_path / "slow.yaml")
    e_over_r = (
        spec.motor.back_emf_constant_v_per_rpm * spec.controller.speed_max_rpm
    ) / spec.motor.phase_resistance_ohm
    assert spec.controller.braking_current_nominal_a == Fraction(28, 1000)
    assert spec.controller.braking_current_nominal_a <= e_over_r / 2


@pytest.mark.parametrize("speed", ["1.2 rpm", "2 rpm"])
def test_init_at_its_least_top_speed_should_write_a_gain_that_resolves_the_current(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str], speed: str
) -> None:
    """--speed-max 1.2 rpm (init's least) on the paper motor: half of E/R is 0.0134 A,
    8 codes at init's usual 500 mV/A, and the loader refused the range as narrower than
    its 16 codes (a hunt). The gain now rises to span 20 codes (1203 mV/A at 1.2 rpm),
    within the 1.65 V/A the 1 A trip leaves, and the spec loads."""
    from codegen.spec_loader import CURRENT_RANGE_CODES, load_spec

    monkeypatch.chdir(tmp_path)
    assert cli.main(["init", "slow", "--speed-max", speed, "-o", "slow.yaml"]) == 0
    out = capsys.readouterr()
    assert "does not load" not in out.out + out.err
    spec = load_spec(tmp_path / "slow.yaml")
    adc, controller = spec.adc, spec.controller
    amps_per_code = adc.reference_v / 2**adc.bits / adc.current_gain_v_per_a
    span = controller.braking_current_max_a - controller.braking_current_min_a
    assert span >= CURRENT_RANGE_CODES * amps_per_code
    assert adc.current_gain_v_per_a > Fraction(1, 2)  # above the usual 500 mV/A
    # every current up to the trip still reads: 1.65 V of headroom
    assert spec.protection.over_current_a * adc.current_gain_v_per_a <= Fraction(165, 100)
    assert "above init's usual 500 mV/A" in dict(spec.sources)["adc.current_gain"]


def test_init_should_say_why_its_braking_current_is_below_its_sensing(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """60 pole pairs, 5 V/krpm, 5 ohm and a 3 rpm top speed: the back-EMF there drives
    E/R = 3 mA, and init writes half of it, under the 0.1 A it sizes the current sensing
    for. The loader then refuses braking_current_max, a value init derived, and the source
    had said '0.1 A at least' (a helper's hunt). The source says what happened and what
    to change; the console points to the sources."""
    from codegen.yaml12 import read_yaml

    monkeypatch.chdir(tmp_path)
    argv = [
        *("init", "slow", "--pole-pairs", "60", "--ke", "5 V/krpm", "--resistance", "5 ohm"),
        *("--inductance", "50 mH", "--bus-voltage", "300 V", "--speed-max", "3 rpm"),
    ]
    assert cli.main(argv) == ExitCode.SPEC
    err = capsys.readouterr().err
    assert "does not load yet" in err and "`sources` entry says what init derived" in err
    data, _ = read_yaml((tmp_path / "spec" / "slow.yaml").read_bytes())
    source = data["sources"]["controller.braking_current_nominal"]
    assert "0.1 A at least" not in source, source
    assert "below the 0.1 A init sizes the current sensing for" in source, source
    assert "raise --speed-max or give --braking-current" in source, source

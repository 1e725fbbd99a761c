"""Hostile file-system and command-line conditions around the output folder.

Each case was seen to fail before its fix: a traceback-like internal error, a
published tree followed by exit 5, the user's files stranded in the hidden `-old`
folder, a staged tree left behind, or a stranger's file overwritten. Root does not
stop at chmod, so the cases that need a file-system refusal inject it (monkeypatch) or
use a file where a folder is expected; the one case that needs root says so.
"""

from __future__ import annotations

import errno
import os
import signal
import subprocess
import sys
from pathlib import Path

import pytest
from test_publish import FOREIGN, NEW, OLD, _forked, leftovers, owned_part, read_tree
from test_publish import write_foreign as _write_foreign

from codegen import publish as publish_module
from codegen.errors import ExitCode
from codegen.publish import PublishError, publish

ROOT = Path(__file__).resolve().parents[1]
SPEC = ROOT / "spec" / "paper_motor.yaml"


def cli(*args: str, cwd: Path = ROOT) -> subprocess.CompletedProcess[str]:
    return _module("codegen", *args, cwd=cwd)


def one_error_line(proc: subprocess.CompletedProcess[str]) -> str:
    assert "Traceback" not in proc.stderr, proc.stderr
    lines = [line for line in proc.stderr.splitlines() if line.strip()]
    assert len(lines) == 1, proc.stderr
    assert lines[0].startswith("error: "), lines[0]
    return lines[0]


def test_an_output_path_that_is_a_symlink_loop_is_one_line_exit_5(tmp_path: Path) -> None:
    """Was: exit 70, `internal error ... RuntimeError: Symlink loop from ...`."""
    loop = tmp_path / "loop"
    loop.symlink_to("loop")
    for output in (loop, loop / "below"):
        proc = cli("generate", str(SPEC), "-o", str(output))
        assert proc.returncode == ExitCode.ENVIRONMENT, proc.stderr
        assert "link loop" in one_error_line(proc)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["loop"]


@pytest.mark.parametrize("output", [".", ".."], ids=["dot", "dot-dot"])
def test_the_working_folder_as_output_is_refused_and_left_as_it_was(
    tmp_path: Path, output: str
) -> None:
    """Was: `-o .` exchanged the working folder for the new tree, removed the old one
    and then failed with `error: No such file or directory` (exit 5 after publishing)."""
    here = tmp_path / "work"
    here.mkdir()
    (here / "notes.txt").write_text("mine\n")
    inode = here.stat().st_ino
    proc = cli("generate", str(SPEC), "-o", output, cwd=here)
    assert proc.returncode == ExitCode.ENVIRONMENT, proc.stderr
    assert "the current" in one_error_line(proc)
    assert here.stat().st_ino == inode
    assert sorted(p.name for p in here.iterdir()) == ["notes.txt"]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["work"]


def test_the_paper_audits_folder_as_output_is_refused_in_one_line(tmp_path: Path) -> None:
    """Was: `generate spec/paper_motor.yaml -o generated/paper` published the motor's
    tree into the paper audit's folder (a spec named paper is refused for it); a link to
    that folder too."""
    (tmp_path / "generated" / "paper").mkdir(parents=True)
    (tmp_path / "link").symlink_to(tmp_path / "generated" / "paper")
    for output in ("generated/paper", "generated/paper/", "link"):
        proc = cli("generate", str(SPEC), "-o", output, cwd=tmp_path)
        assert proc.returncode == ExitCode.ENVIRONMENT, proc.stderr
        line = one_error_line(proc)
        assert "error: output: generated/paper is the paper audit's folder" in line, line
        assert "generated/paper/" in line and "choose another output folder" in line, line
    assert sorted(p.name for p in tmp_path.iterdir()) == ["generated", "link"]
    assert list((tmp_path / "generated").iterdir()) == [tmp_path / "generated" / "paper"]
    assert list((tmp_path / "generated" / "paper").iterdir()) == []


@pytest.mark.parametrize(
    "argv",
    [
        ["generate", str(SPEC), "-o", "LINK"],
        ["generate", str(SPEC), "-o", "LINK/below"],
        ["audit", "-o", "LINK"],
        ["audit", str(SPEC), "-o", "LINK"],
        ["firmware", str(SPEC), "--generated", str(ROOT / "generated" / "paper_motor"),
         "--build", "LINK"],
        ["simulate", str(SPEC), "--quick", "--no-progress", "-o", "LINK/below"],
        ["robustness", str(SPEC), "--no-progress", "-o", "LINK/below"],
    ],
    ids=["generate", "generate-below", "audit", "audit-spec", "firmware", "simulate", "robustness"],
)  # fmt: skip
def test_a_dangling_link_as_output_folder_is_refused_and_nothing_made(
    tmp_path: Path, argv: list[str]
) -> None:
    """Was: `generate -o LINK`, LINK a symbolic link to /nonexistent/x, created
    /nonexistent/x and published there (exit 0); audit and firmware said only
    "LINK: File exists". One line naming the link and where it points, exit 5."""
    link = tmp_path / "link"
    link.symlink_to(tmp_path / "nowhere" / "x")
    proc = cli(*[a.replace("LINK", str(link)) for a in argv], cwd=tmp_path)
    assert proc.returncode == ExitCode.ENVIRONMENT, proc.stderr
    line = one_error_line(proc)
    assert f"{link} is a symbolic link to nothing" in line, line
    assert f"{tmp_path / 'nowhere' / 'x'} does not exist" in line, line
    assert sorted(p.name for p in tmp_path.iterdir()) == ["link"]


def test_an_unreadable_manifest_is_named_as_such_and_the_tree_kept(tmp_path: Path) -> None:
    """Was: a corrupt manifest.json in the output folder made `generate -o DIR` say the
    tree's own files "were not written by bldc-codegen" without a word about the
    manifest; a FIFO in its place blocked the run for good (SIGTERM held back). One line
    naming the manifest and why it cannot be read, exit 5, the folder as it was."""
    out = tmp_path / "out"
    assert cli("generate", str(SPEC), "-o", str(out)).returncode == 0
    manifest = out / "manifest.json"
    cases = {"it is not JSON: ": b'{"broken', "it is not UTF-8 text": b"\xff\xfe"}
    for why, data in cases.items():
        manifest.write_bytes(data)
        proc = cli("generate", str(SPEC), "-o", str(out))
        assert proc.returncode == ExitCode.ENVIRONMENT, proc.stderr
        line = one_error_line(proc)
        assert line.startswith(f"error: output: {manifest} is unreadable ({why}"), line
        assert "cannot tell its own files" in line, line
        assert manifest.read_bytes() == data
    manifest.unlink()
    os.mkfifo(manifest)
    proc = cli("generate", str(SPEC), "-o", str(out))  # had blocked: TimeoutExpired
    assert f"{manifest} is unreadable (it is a named pipe (FIFO))" in one_error_line(proc)
    assert (out / "c" / "bldc_commutation.c").is_file()
    assert sorted(p.name for p in tmp_path.iterdir()) == [".out.bldc-codegen.lock", "out"]


def test_an_unreadable_manifest_is_refused_before_the_design(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """Was: `generate -o` designed and rendered the whole tree (seconds) before it read
    the output folder's manifest and refused it. The design is made to fail here: the
    refusal must come first, the same line, the folder as it was."""
    import codegen.generate
    from bldc import cli as bldc_cli

    out = tmp_path / "out"
    out.mkdir()
    (out / "manifest.json").write_bytes(b'{"broken')

    def no_design(*args: object, **kwargs: object) -> object:
        raise AssertionError("the design ran before the output folder was checked")

    monkeypatch.setattr(codegen.generate, "render_all", no_design)
    assert bldc_cli.main(["generate", str(SPEC), "-o", str(out)]) == ExitCode.ENVIRONMENT
    err = capsys.readouterr().err
    assert err.startswith(
        f"error: output: {out / 'manifest.json'} is unreadable (it is not JSON"
    ), err
    assert "cannot tell its own files" in err and err.count("\n") == 1, err
    assert sorted(p.name for p in out.iterdir()) == ["manifest.json"]


def _publish_with_default_signals(target: Path, env: dict[str, str]) -> int:
    """The publish in a forked child whose SIGINT, SIGTERM and SIGHUP have their default
    actions, whatever the test runner's are (a background or xdist run starts with SIGINT
    ignored, which the publish rightly keeps: the child then ran to its end, exit 0)."""

    def work() -> None:
        signal.signal(signal.SIGINT, signal.default_int_handler)
        signal.signal(signal.SIGTERM, signal.SIG_DFL)
        signal.signal(signal.SIGHUP, signal.SIG_DFL)
        publish(NEW, target)

    return _forked(env, work)


@pytest.mark.parametrize("name", ["INT", "TERM", "HUP"])
@pytest.mark.parametrize("label", ["write bldc_commutation.c", "exchange", "rename ", "unlink "])
def test_a_polite_signal_mid_publish_ends_with_the_new_tree_and_the_users_files_in_place(
    tmp_path: Path, name: str, label: str
) -> None:
    """Was: SIGTERM or Ctrl-C after the exchange left the user's files in the hidden
    `.motor.bldc-codegen-old` until the next run. Now the signal waits for the publish."""
    target = tmp_path / "motor"
    publish(OLD, target)
    _write_foreign(target)
    env = {"BLDC_CODEGEN_TEST_KILL_AT_LABEL": label, "BLDC_CODEGEN_TEST_KILL_SIGNAL": name}
    code = _publish_with_default_signals(target, env)
    # SIGINT is KeyboardInterrupt in Python (the forked child exits 1); the others end it
    assert code == (1 if name == "INT" else -getattr(signal, f"SIG{name}")), code
    content = read_tree(target)
    assert owned_part(content) == NEW
    assert {k: content.get(k) for k in FOREIGN} == FOREIGN
    assert leftovers(tmp_path, target) == []


def _refuse_renaming(monkeypatch: pytest.MonkeyPatch, name: str) -> None:
    real = publish_module._rename

    def rename(src: Path, dst: Path) -> None:
        if src.name == name:
            raise PermissionError(errno.EPERM, os.strerror(errno.EPERM), str(src))
        real(src, dst)

    monkeypatch.setattr(publish_module, "_rename", rename)


def test_a_users_file_that_cannot_be_moved_back_strands_no_other_and_is_named(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """Was (chattr +i on one file of the -o folder): exit 5 naming the hidden folder,
    with that file and every one after it left in `.motor.bldc-codegen-old`."""
    target = tmp_path / "motor"
    publish(OLD, target)
    _write_foreign(target)
    (target / "a_first.txt").write_text("a\n")
    (target / "z_last.txt").write_text("z\n")
    _refuse_renaming(monkeypatch, "NOTES.txt")
    result = publish(NEW, target)
    content = read_tree(target)
    moved = {k: v for k, v in FOREIGN.items() if k != "NOTES.txt"}
    expected = {**NEW, **moved, "a_first.txt": "a\n", "z_last.txt": "z\n"}
    assert content == expected
    retired = tmp_path / ".motor.bldc-codegen-old"
    assert (retired / "NOTES.txt").read_text() == FOREIGN["NOTES.txt"]
    assert sorted(p.name for p in retired.iterdir()) == ["NOTES.txt"]
    assert str(retired / "NOTES.txt") in result.left_behind
    err = capsys.readouterr().err
    assert f"warning: {retired / 'NOTES.txt'} could not be moved back" in err
    # The next run does not exchange over the leftover: it stops first, in one line.
    with pytest.raises(PublishError, match="left from an earlier run"):
        publish(OLD, target)
    assert read_tree(target) == expected


def test_a_target_that_cannot_be_replaced_leaves_no_staged_tree(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Was (chattr +i on the -o folder): exit 5, and `.motor.bldc-codegen-new` stayed."""
    target = tmp_path / "motor"
    publish(OLD, target)
    _write_foreign(target)

    def refuse(a: Path, b: Path) -> bool:
        raise PermissionError(errno.EPERM, os.strerror(errno.EPERM), str(b))

    monkeypatch.setattr(publish_module, "_exchange", refuse)
    with pytest.raises(PermissionError):
        publish(NEW, target)
    assert owned_part(read_tree(target)) == OLD
    assert leftovers(tmp_path, target) == []


def test_a_republished_folder_keeps_its_mode_and_as_root_its_owner(tmp_path: Path) -> None:
    """Was: `sudo ... generate -o ~/motor` replaced ~/motor by a folder owned by root,
    its user unable to add a file to it. Not root: the owner cannot be given away, so
    the mode (kept before too) and the runner's own ownership are what is checked."""
    target = tmp_path / "motor"
    publish(OLD, target)
    os.chmod(target, 0o750)
    owner = (4242, 4343) if os.geteuid() == 0 else (os.getuid(), os.getgid())
    if os.geteuid() == 0:
        os.chown(target, *owner)
    publish(NEW, target)
    info = target.stat()
    assert (info.st_uid, info.st_gid) == owner
    assert info.st_mode & 0o7777 == 0o750
    assert owned_part(read_tree(target)) == NEW


def test_audit_into_a_folder_with_a_hand_written_report_writes_nothing(tmp_path: Path) -> None:
    """Was: `audit -o DIR` replaced a hand-written AUDIT.md (exit 0); with a SPEC and a
    hand-written DERIVATION.md it wrote AUDIT.md and AUDIT.html, then refused (exit 5)."""
    mine = tmp_path / "mine"
    mine.mkdir()
    (mine / "AUDIT.md").write_text("my notes\n")
    proc = cli("audit", "-o", str(mine))
    assert proc.returncode == ExitCode.ENVIRONMENT, proc.stderr
    assert f"{mine / 'AUDIT.md'} is in the way" in one_error_line(proc)
    assert [(p.name, p.read_text()) for p in mine.iterdir()] == [("AUDIT.md", "my notes\n")]

    other = tmp_path / "other"
    other.mkdir()
    (other / "DERIVATION.md").write_text("my derivation\n")
    proc = cli("audit", str(SPEC), "-o", str(other))
    assert proc.returncode == ExitCode.ENVIRONMENT, proc.stderr
    assert f"{other / 'DERIVATION.md'} is in the way" in one_error_line(proc)
    assert [(p.name, p.read_text()) for p in other.iterdir()] == [
        ("DERIVATION.md", "my derivation\n")
    ]


def test_audit_replaces_its_own_reports_and_keeps_the_users_files(tmp_path: Path) -> None:
    out = tmp_path / "out"
    out.mkdir()
    (out / "notes.txt").write_text("mine\n")
    for _ in range(2):
        proc = cli("audit", str(SPEC), "-o", str(out))
        assert proc.returncode == 0, proc.stderr
    names = sorted(p.name for p in out.iterdir())
    assert names == ["AUDIT.html", "AUDIT.md", "DERIVATION.md", "manifest.json", "notes.txt"]
    assert (out / "notes.txt").read_text() == "mine\n"


@pytest.mark.parametrize(
    "argv",
    [
        ["generate", str(SPEC), "-o", ""],
        ["generate", ""],
        ["verify", str(SPEC), "--generated", ""],
        ["firmware", str(SPEC), "--build", ""],
        ["simulate", str(SPEC), "-o", ""],
        ["init", "x_motor", "-o", ""],
    ],
    ids=["generate-o", "spec", "generated", "build", "simulate-o", "init-o"],
)
def test_an_empty_path_is_a_usage_error_not_the_default_folder(
    tmp_path: Path, argv: list[str]
) -> None:
    """Was: `generate SPEC -o "$OUT"` with OUT unset wrote generated/<name> in the
    current folder (exit 0), as if -o had not been given."""
    proc = cli(*argv, cwd=tmp_path)
    assert proc.returncode == ExitCode.USAGE, proc.stderr
    assert "is an empty path" in proc.stderr.splitlines()[-1]
    assert "Traceback" not in proc.stderr
    assert list(tmp_path.iterdir()) == []


def _make(*args: str, timeout: float = 30) -> subprocess.CompletedProcess[str]:
    """make in the project, unchecked."""
    return subprocess.run(
        ["make", "--no-print-directory", "-C", str(ROOT), *args],
        capture_output=True,
        text=True,
        timeout=timeout,
        check=False,
    )


def test_make_refuses_a_spec_path_with_a_space_in_one_line(tmp_path: Path) -> None:
    """Was: `make generate SPEC="my motors/m.yaml"` ran `generate my motors/m.yaml`, a
    usage error about an unrecognized argument. make cannot quote it: it says so."""
    folder = tmp_path / "my motors"
    folder.mkdir()
    spec = folder / "m.yaml"
    spec.write_bytes(SPEC.read_bytes())
    proc = _make("-n", "generate", f"SPEC={spec}")
    assert proc.returncode == 2, proc.stdout + proc.stderr
    assert f'no file "{tmp_path / "my"}": make splits SPEC at spaces' in proc.stderr
    assert "-m codegen generate" not in proc.stdout
    # several specs, each a file, still go through
    proc = _make(
        "-n", "verify", f"SPEC={SPEC} {ROOT / 'spec' / 'example_maxon_ec45_flat_48v.yaml'}"
    )
    assert proc.returncode == 0, proc.stderr
    assert "example_maxon_ec45_flat_48v.yaml'; do" in proc.stdout


def test_make_should_pass_a_spec_path_with_shell_characters_quoted(tmp_path: Path) -> None:
    """Was: `make derive SPEC='m(1).yaml'` and `SPEC="it's.yaml"` were shell syntax
    errors, and SPEC='$HOME.yaml' read "OME.yaml" (make expands '$' itself): a path
    reaches the shell single-quoted, and a '$' is refused in one line."""
    for name in ("m(1).yaml", "it's.yaml"):
        spec = tmp_path / name
        spec.write_bytes(SPEC.read_bytes())
        proc = _make("derive", f"SPEC={spec}", timeout=120)
        assert proc.returncode == 0, proc.stdout + proc.stderr
        assert "Eq. 18" in proc.stdout or "t_com" in proc.stdout, proc.stdout
    proc = _make("-n", "derive", f"SPEC={tmp_path}/$HOME.yaml")
    assert proc.returncode == 2
    (line,) = [x for x in proc.stderr.splitlines() if "SPEC contains" in x]
    assert "'$'" in line and "-m codegen derive" not in proc.stdout


def _module(module: str, *args: str, cwd: Path) -> subprocess.CompletedProcess[str]:
    """`python -m module args` with the project on the path, in `cwd`."""
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    return subprocess.run(
        [sys.executable, "-m", module, *args],
        cwd=cwd,
        env=env,
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
    )


def _one_line(proc: subprocess.CompletedProcess[str]) -> str:
    """The one line on stderr, with no traceback (the tools prefix it with their name)."""
    assert "Traceback" not in proc.stderr, proc.stderr
    lines = [line for line in proc.stderr.splitlines() if line.strip()]
    assert len(lines) == 1, proc.stderr
    return lines[0]


def test_the_module_tools_should_refuse_a_file_in_the_way_in_one_line(tmp_path: Path) -> None:
    """Was (a hunt): `python -m emulation.pil` printed a traceback for a missing spec or
    firmware image; `python -m verify.prove --build FILE` a FileExistsError traceback
    (and a read-only --generated one after the whole proof, the folder now checked
    first); `python -m emulation --work FILE` blamed the readable spec ("cannot read
    spec ...: Not a directory")."""
    blocker = tmp_path / "afile"
    blocker.write_text("not a folder\n", encoding="utf-8")
    proc = _module("emulation.pil", str(tmp_path / "missing.yaml"), cwd=tmp_path)
    assert proc.returncode == ExitCode.SPEC
    assert "cannot read spec: No such file" in _one_line(proc)
    proc = _module("emulation.pil", str(SPEC), "--elf", str(tmp_path / "none.elf"), cwd=tmp_path)
    assert proc.returncode == ExitCode.ENVIRONMENT
    assert "none.elf is no firmware image" in _one_line(proc)
    proc = _module("emulation.pil", str(SPEC), "--elf", str(blocker), cwd=tmp_path)
    assert proc.returncode == ExitCode.ENVIRONMENT
    assert "not an ELF image" in _one_line(proc)
    proc = _module("verify.prove", "--build", str(blocker), str(SPEC), cwd=tmp_path)
    assert proc.returncode == ExitCode.ENVIRONMENT
    assert f"{blocker} is a file, not a folder" in _one_line(proc)
    proc = _module("emulation", "--only", "size", "--work", str(blocker), str(SPEC), cwd=tmp_path)
    assert proc.returncode == ExitCode.ENVIRONMENT
    line = _one_line(proc)
    assert f"{blocker} is a file, not a folder" in line and "cannot read spec" not in line
    assert blocker.read_text(encoding="utf-8") == "not a folder\n"


@pytest.mark.parametrize(
    ("module", "option"),
    [("emulation.pil.report", "-o"), ("verify", "--generated"), ("verify.prove", "--build")],
)
def test_an_empty_path_option_should_be_refused_not_taken_as_the_current_folder(
    tmp_path: Path, module: str, option: str
) -> None:
    """Was (a hunt): `python -m emulation.pil.report -o ''` wrote PIL.md into the current
    folder (Path('') is '.'), as `bldc-codegen` refuses."""
    proc = _module(module, option, "", str(SPEC), cwd=tmp_path)
    assert proc.returncode == ExitCode.USAGE, proc.stderr
    assert "is an empty path" in proc.stderr
    assert list(tmp_path.iterdir()) == []


def test_init_should_write_through_a_link_and_refuse_a_link_to_nothing(tmp_path: Path) -> None:
    """Was (a hunt): `init -o LINK`, LINK a symbolic link to nothing or a loop, wrote a
    regular file in its place without --force (exists() follows the link); with --force
    a link to a spec was replaced by a file. A link to nothing or a loop is refused in
    one line and left as it was; --force writes through a link to its file."""
    dangling = tmp_path / "dangling.yaml"
    dangling.symlink_to(tmp_path / "nowhere" / "target.yaml")
    loop = tmp_path / "loop"
    loop.symlink_to("loop")
    for link in (dangling, loop):
        proc = cli("init", "m", "-o", str(link))
        assert proc.returncode == ExitCode.ENVIRONMENT, proc.stderr
        assert "is a symbolic link to nothing" in one_error_line(proc)
        assert link.is_symlink()
    real = tmp_path / "real.yaml"
    real.write_text("mine\n", encoding="utf-8")
    linked = tmp_path / "linked.yaml"
    linked.symlink_to(real)
    assert cli("init", "m", "-o", str(linked)).returncode == ExitCode.USAGE
    assert real.read_text(encoding="utf-8") == "mine\n"
    assert cli("init", "m", "-o", str(linked), "--force").returncode == 0
    assert linked.is_symlink() and linked.resolve() == real
    assert "name: m\n" in real.read_text(encoding="utf-8")

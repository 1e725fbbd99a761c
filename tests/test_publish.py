"""codegen.publish: output is replaced in one atomic step, survives kill -9 at every
file-system step, keeps what bldc-codegen did not write, and serialises concurrent runs.

The kill tests run `publish` in a subprocess that SIGKILLs itself at its k-th step
(BLDC_CODEGEN_TEST_KILL_AT_STEP) for every k until a run completes, once with the atomic
exchange and once with the two-rename fallback. After each kill the target must hold
the complete old or the complete new tree; after the next run's recovery, the complete
new one, every foreign file in place and no leftovers.
"""

from __future__ import annotations

import contextlib
import errno
import json
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable, Iterator
from pathlib import Path

import pytest

from codegen import publish as publish_module
from codegen.publish import MANIFEST, PublishError, manifest_record, publish, recover

ROOT = Path(__file__).resolve().parents[1]
SPEC = ROOT / "spec" / "paper_motor.yaml"

#: Whatever another command or the user put into the output folder.
FOREIGN = {
    "verify/report.json": '{"passed": true}\n',
    "verify/error_vs_speed.png": "png\n",
    "simulation/SIMULATION.md": "# simulation\n",
    "NOTES.txt": "my own notes\n",
    "c/my_driver.c": "/* mine */\n",
}


@pytest.fixture
def fast_tmp(tmp_path: Path) -> Iterator[Path]:
    """A scratch folder on tmpfs when the machine has one: the kill tests publish a few
    hundred trees, and on a busy disk their fsyncs, not the code, would set the pace."""
    shm = Path("/dev/shm")
    if not (shm.is_dir() and os.access(shm, os.W_OK)):
        yield tmp_path
        return
    folder = Path(tempfile.mkdtemp(prefix="bldc-publish-", dir=shm))
    try:
        yield folder
    finally:
        shutil.rmtree(folder, ignore_errors=True)


def tree(version: str, extra: dict[str, str] | None = None) -> dict[str, str]:
    files = {
        "AUDIT.md": f"audit {version}\n",
        "c/bldc_commutation.c": f"core {version}\n",
        "c/bldc_commutation.h": f"header {version}\n",
        "python/bldc_fixed.py": f"twin {version}\n",
        "tests/unity/test_runner.c": f"runner {version}\n",
        **(extra or {}),
    }
    files[MANIFEST] = json.dumps({"version": version, **manifest_record(files)}, indent=2)
    return files


OLD = tree("old", {"firmware/main.c": "main old\n"})  # a folder the new tree drops
NEW = tree("new", {"python/bldc_float.py": "float new\n"})


def read_tree(folder: Path) -> dict[str, str]:
    return {
        path.relative_to(folder).as_posix(): path.read_text(encoding="utf-8")
        for path in sorted(folder.rglob("*"))
        if path.is_file()
    }


def owned_part(content: dict[str, str]) -> dict[str, str]:
    return {name: text for name, text in content.items() if name not in FOREIGN}


def write_foreign(folder: Path) -> None:
    for name, text in FOREIGN.items():
        (folder / name).parent.mkdir(parents=True, exist_ok=True)
        (folder / name).write_text(text, encoding="utf-8")


def leftovers(parent: Path, target: Path) -> list[str]:
    lock = f".{target.name}.bldc-codegen.lock"
    return sorted(p.name for p in parent.iterdir() if p != target and p.name != lock)


def test_a_first_publish_writes_the_tree_and_nothing_else(tmp_path: Path) -> None:
    target = tmp_path / "out" / "motor"
    result = publish(NEW, target)
    assert read_tree(target) == NEW
    assert leftovers(target.parent, target) == []
    assert result.carried_over == [] and result.left_behind == []


def test_a_republish_replaces_its_own_files_and_keeps_every_other(tmp_path: Path) -> None:
    target = tmp_path / "motor"
    publish(OLD, target)
    write_foreign(target)
    result = publish(NEW, target)
    content = read_tree(target)
    assert owned_part(content) == NEW  # firmware/main.c, no longer generated, is gone
    assert {k: v for k, v in content.items() if k in FOREIGN} == FOREIGN
    assert not (target / "firmware").exists()
    assert sorted(result.carried_over) == sorted(
        ["NOTES.txt", "c/my_driver.c", "simulation", "verify"]
    )
    assert result.atomic_exchange is sys.platform.startswith("linux")
    assert leftovers(tmp_path, target) == []


def test_output_into_a_folder_of_foreign_files_keeps_them(tmp_path: Path) -> None:
    target = tmp_path / "project"
    write_foreign(target)
    (target / "src").mkdir()
    (target / "src" / "app.c").write_text("int main(void) { return 0; }\n")
    before = read_tree(target)
    publish(NEW, target)
    after = read_tree(target)
    assert {k: after[k] for k in before} == before
    assert {k: after[k] for k in NEW} == NEW


def test_a_foreign_file_in_the_way_stops_the_publish_before_anything_is_written(
    tmp_path: Path,
) -> None:
    target = tmp_path / "project"
    target.mkdir()
    (target / "AUDIT.md").write_text("hand written\n")
    with pytest.raises(PublishError, match=r"AUDIT\.md is in the way"):
        publish(NEW, target)
    assert read_tree(target) == {"AUDIT.md": "hand written\n"}
    assert leftovers(tmp_path, target) == []


@pytest.mark.parametrize("bad", ["/", "file"])
def test_a_target_that_cannot_be_a_folder_is_refused(tmp_path: Path, bad: str) -> None:
    if bad == "file":
        (tmp_path / "file").write_text("x")
    target = Path("/") if bad == "/" else tmp_path / bad
    with pytest.raises(PublishError):
        publish(NEW, target)


def test_a_symlinked_target_publishes_into_the_folder_it_points_to(tmp_path: Path) -> None:
    real = tmp_path / "real"
    publish(OLD, real)
    link = tmp_path / "link"
    link.symlink_to(real)
    publish(NEW, link)
    assert link.is_symlink() and read_tree(real) == NEW


def _publish_script(files_json: Path, target: Path) -> list[str]:
    code = (
        "import json, sys; from pathlib import Path; from codegen.publish import publish;"
        "publish(json.loads(Path(sys.argv[1]).read_text()), Path(sys.argv[2]))"
    )
    return [sys.executable, "-c", code, str(files_json), str(target)]


def _forked(env: dict[str, str], work: Callable[[], object]) -> int:
    """Run `work` in a forked child with `env` and a fresh step counter; its wait
    status as subprocess reports it (0, or -signal). A fork costs a millisecond where a
    new interpreter costs a hundred, and the kill tests start a hundred and fifty."""
    pid = os.fork()
    if pid == 0:  # pragma: no cover - the child
        code = 1
        try:
            os.environ.update(env)
            publish_module._steps = 0
            work()
            code = 0
        finally:
            os._exit(code)
    _, status = os.waitpid(pid, 0)
    return -os.WTERMSIG(status) if os.WIFSIGNALED(status) else os.WEXITSTATUS(status)


def _run_publish(files: dict[str, str], target: Path, env: dict[str, str]) -> int:
    return _forked(env, lambda: publish(files, target))


@pytest.mark.parametrize("exchange", [True, False], ids=["exchange", "two-renames"])
def test_kill_9_at_every_step_leaves_the_old_or_the_new_tree_complete(
    fast_tmp: Path, exchange: bool
) -> None:
    tmp_path = fast_tmp
    env = {} if exchange else {"BLDC_CODEGEN_NO_EXCHANGE": "1"}
    step = 0
    kills = 0
    while True:
        step += 1
        assert step < 400, "publish never completed"
        case = tmp_path / f"k{step}"
        case.mkdir()
        target = case / "out" / "motor"
        publish(OLD, target)
        write_foreign(target)
        code = _run_publish(NEW, target, {**env, "BLDC_CODEGEN_TEST_KILL_AT_STEP": str(step)})
        if code == 0:
            assert owned_part(read_tree(target)) == NEW
            break
        assert code == -signal.SIGKILL, code
        kills += 1
        # Right after the kill: the old or the new tree, whole, at the target path (the
        # two-rename fallback may have neither there between its renames).
        if target.exists():
            owned = owned_part(read_tree(target))
            assert owned in (OLD, NEW), f"step {step}: a mixed tree {sorted(owned)}"
        else:
            assert not exchange, f"step {step}: the target vanished"
        # Every foreign file is somewhere under the case folder, never lost.
        everywhere = [p.read_text() for p in case.rglob("*") if p.is_file()]
        for text in FOREIGN.values():
            assert text in everywhere, f"step {step}: lost {text!r}"
        # The next run recovers: target whole, foreign files in place, no leftovers.
        recovered = recover(target)
        content = read_tree(target)
        assert owned_part(content) in (OLD, NEW), f"step {step}: {recovered}"
        assert {k: content.get(k) for k in FOREIGN} == FOREIGN, f"step {step}: {recovered}"
        assert leftovers(target.parent, target) == [], f"step {step}"
        publish(NEW, target)
        assert owned_part(read_tree(target)) == NEW
    assert kills >= 2 * len(NEW)  # every write and fsync of every file was a kill point


def test_concurrent_runs_take_turns(tmp_path: Path) -> None:
    target = tmp_path / "motor"
    publish(OLD, target)
    write_foreign(target)
    trees = [tree(f"v{i}") for i in range(6)]
    procs = []
    for i, files in enumerate(trees):
        scratch = tmp_path / f"p{i}"
        scratch.mkdir()
        (scratch / "files.json").write_text(json.dumps(files))
        procs.append(
            subprocess.Popen(
                _publish_script(scratch / "files.json", target),
                cwd=ROOT,
                stdout=subprocess.PIPE,
                stderr=subprocess.PIPE,
                text=True,
            )
        )
    results = [(p.wait(timeout=120), p.stderr.read() if p.stderr else "") for p in procs]
    for p in procs:
        for stream in (p.stdout, p.stderr):
            if stream:
                stream.close()
    assert [code for code, _ in results] == [0] * len(trees), results
    content = read_tree(target)
    assert owned_part(content) in trees
    assert {k: content[k] for k in FOREIGN} == FOREIGN
    assert leftovers(tmp_path, target) == sorted(f"p{i}" for i in range(len(trees)))


def test_a_recovery_killed_at_every_step_still_recovers(fast_tmp: Path) -> None:
    tmp_path = fast_tmp
    """Recovery is itself made of steps a kill can interrupt: it must be restartable."""
    step = 0
    while True:
        step += 1
        assert step < 100, "recovery never completed"
        case = tmp_path / f"k{step}"
        case.mkdir()
        target = case / "out" / "motor"
        publish(OLD, target)
        write_foreign(target)
        # Killed just after the exchange: the old tree, holding the reports, is beside.
        code = _run_publish(NEW, target, {"BLDC_CODEGEN_TEST_KILL_AT_LABEL": "rename "})
        assert code == -signal.SIGKILL
        assert leftovers(target.parent, target) == [".motor.bldc-codegen-new"]
        killed = _forked(
            {"BLDC_CODEGEN_TEST_KILL_AT_STEP": str(step)}, lambda target=target: recover(target)
        )
        recover(target)
        content = read_tree(target)
        assert owned_part(content) == NEW, f"step {step}"
        assert {k: content.get(k) for k in FOREIGN} == FOREIGN, f"step {step}"
        assert leftovers(target.parent, target) == [], f"step {step}"
        if killed == 0:
            break
        assert killed == -signal.SIGKILL
    assert step > 5


def test_a_lock_that_cannot_be_made_should_name_the_output_folder(tmp_path: Path) -> None:
    """`generate -o /proc/x` said only `/proc/.x.bldc-codegen.lock: No such file...`."""
    from codegen.publish import os_error_line

    lock = tmp_path / "gone" / ".out.bldc-codegen.lock"
    line = os_error_line(FileNotFoundError(2, "No such file or directory", str(lock)))
    assert line.startswith(f"error: {tmp_path / 'gone' / 'out'}: cannot publish there:"), line
    assert "\n" not in line and ".out.bldc-codegen.lock" in line


def test_an_os_error_without_a_file_is_one_plain_line() -> None:
    """A Dask scheduler that cannot be reached (`robustness --scheduler ...`) raises an
    OSError with no file name: its line read 'error:: Timed out trying to connect'."""
    from codegen.publish import os_error_line

    line = os_error_line(OSError("Timed out trying to connect to tcp://127.0.0.1:1 after 30 s"))
    assert line == "error: Timed out trying to connect to tcp://127.0.0.1:1 after 30 s"
    named = os_error_line(PermissionError(13, "Permission denied", "/x/y"))
    assert named == "error: /x/y: Permission denied"


def test_a_manifest_naming_files_outside_its_tree_should_delete_none_of_them(
    tmp_path: Path,
) -> None:
    """A manifest is the list of what bldc-codegen wrote; one edited (or not ours) to
    name "../victim", an absolute path, or a file behind a linked sub-folder had the next
    publish delete those files outside the output folder."""
    target = tmp_path / "out" / "motor"
    publish(OLD, target)
    victims = [tmp_path / "out" / "victim.txt", tmp_path / "abs_victim.txt"]
    outside = tmp_path / "elsewhere"
    outside.mkdir()
    victims.append(outside / "linked.txt")
    for victim in victims:
        victim.write_text("user data")
    (target / "link").symlink_to(outside)
    manifest = json.loads((target / MANIFEST).read_text())
    manifest["files"]["../victim.txt"] = "0" * 64
    manifest["files"][str(victims[1])] = "0" * 64
    manifest["files"]["link/linked.txt"] = "0" * 64
    manifest["folders"] = ["..", "/tmp"]
    (target / MANIFEST).write_text(json.dumps(manifest))
    publish(NEW, target)
    assert all(victim.read_text() == "user data" for victim in victims)
    assert (target / "link").is_symlink()  # a foreign entry: carried over
    content = read_tree(target)
    assert {name: content[name] for name in NEW} == NEW


def test_a_run_waiting_for_the_lock_should_name_the_folder_it_waits_to_write(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """The lock `.<name>.bldc-codegen.lock` sits beside the folder: the wait's line had
    named the folder above the one being written."""
    import threading

    lock = tmp_path / ".out.bldc-codegen.lock"
    entered = threading.Event()

    def wait() -> None:
        with publish_module._locked(lock):
            entered.set()

    said = ""
    with publish_module._locked(lock):
        waiter = threading.Thread(target=wait)
        waiter.start()
        # until it says it waits (a fixed half second had let a slow start reach the
        # lock after its release, on a loaded machine: no wait, no line)
        deadline = time.monotonic() + 30
        while "waiting for" not in said and time.monotonic() < deadline:
            waiter.join(timeout=0.05)
            said += capsys.readouterr().err
        assert waiter.is_alive() and not entered.is_set()  # it waits
    waiter.join(timeout=30)
    assert entered.is_set()
    said += capsys.readouterr().err
    assert f"waiting for another bldc-codegen run writing {tmp_path / 'out'}" in said


@contextlib.contextmanager
def read_only_folder(folder: Path, monkeypatch: pytest.MonkeyPatch) -> Iterator[None]:
    """`folder` at mode 555 for the block, and unwritable through `os.access` too (root,
    whom the mode does not stop, is what the tests run as)."""
    real_access = os.access

    def access(path: object, mode: int, **kwargs: object) -> bool:
        if Path(str(path)) == folder and mode & os.W_OK:
            return False
        return real_access(path, mode, **kwargs)  # type: ignore[arg-type]

    monkeypatch.setattr(publish_module.os, "access", access)
    folder.chmod(0o555)
    try:
        yield
    finally:
        folder.chmod(0o755)
        monkeypatch.undo()


@pytest.mark.parametrize("read_only", ["", "c"])
def test_a_read_only_folder_of_the_tree_is_refused_before_anything_moves(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, read_only: str
) -> None:
    """A folder of the old tree this user cannot write (the target, or a subfolder)
    would keep the user's files in the hidden old tree: refused first (as root, which
    `os.access` lets write anything, the mode is simulated through `os.access`)."""
    target = tmp_path / "motor"
    publish(OLD, target)
    write_foreign(target)
    locked = target / read_only if read_only else target
    before = read_tree(target)
    refused = pytest.raises(PublishError, match=f"{locked} is not writable by this user")
    with read_only_folder(locked, monkeypatch), refused:
        publish(NEW, target)
    assert read_tree(target) == before
    assert leftovers(tmp_path, target) == []


def test_a_read_only_folder_of_the_users_own_should_move_whole(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A folder the user made inside the output, read-only: it moves by one rename in
    its (writable) parent, and is carried over (the first refusal had walked every
    folder and refused it)."""
    target = tmp_path / "motor"
    publish(OLD, target)
    archive = target / "mydata" / "archive"
    archive.mkdir(parents=True)
    (archive / "run1.csv").write_text("1,2\n", encoding="utf-8")
    with read_only_folder(archive, monkeypatch):
        result = publish(NEW, target)
    assert "mydata" in result.carried_over
    assert (target / "mydata" / "archive" / "run1.csv").read_text(encoding="utf-8") == "1,2\n"
    assert owned_part(read_tree(target)) == {**NEW, "mydata/archive/run1.csv": "1,2\n"}


def test_a_full_disk_names_the_file_of_the_target_and_publishes_nothing(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A write's ENOSPC carries no file name: the error names the target's file (not
    the hidden staging folder's, nor nothing: "error: No space left on device")."""
    target = tmp_path / "motor"
    publish(OLD, target)
    before = read_tree(target)

    def full(fd: int) -> None:
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    monkeypatch.setattr(publish_module.os, "fsync", full)
    with pytest.raises(OSError) as raised:
        publish(NEW, target)
    monkeypatch.undo()
    assert raised.value.errno == errno.ENOSPC
    assert Path(str(raised.value.filename)) == target / MANIFEST
    line = publish_module.os_error_line(raised.value)
    assert line == f"error: {target / MANIFEST}: No space left on device"
    assert read_tree(target) == before
    assert leftovers(tmp_path, target) == []


def test_a_target_inside_another_generated_tree_should_be_refused(tmp_path: Path) -> None:
    """`generate -o out/motor/c`, inside the tree of `generate -o out/motor`: the two
    trees' files interleaved there, each run moving the other's aside. A folder the
    manifest does not list (the user's own, or a new one below a listed folder) stays a
    place to publish: the outer tree carries it over as it carries the user's files."""
    outer = tmp_path / "motor"
    publish(OLD, outer)
    before = read_tree(outer)
    for inner in (outer / "c", outer / "firmware"):
        with pytest.raises(PublishError, match="is inside the generated tree"):
            publish(NEW, inner)
    assert read_tree(outer) == before
    for mine in (outer / "mine", outer / "c" / "deeper"):
        publish(NEW, mine)
        assert read_tree(mine) == NEW

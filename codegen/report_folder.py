"""A report's files into its output folder, never over a file the tool did not write.

`simulate` and `robustness` write a report and its figures into a folder a user may
name with `-o`. The files are written into a staging folder beside it first (hidden,
on the same file system); only when all of them are there is each moved in by rename,
and only if no file of the same name in the folder is a stranger's: a hand-written
SIMULATION.md in the folder given with -o stops the run, in one line, before anything
in the folder changes (it had been overwritten).

Which files are the tool's: those its ledger in the folder lists (`LEDGER`). The
ledger is written before the moves, listing the new report's names too, so that a run
stopped between two moves (SIGKILL) leaves no file of its own unlisted (the next run had
refused its own figure as a stranger's); SIGINT, SIGTERM and SIGHUP wait for the moves
(`signals_deferred`). After them the tool's files of an earlier report that the new one
does not have (a figure of a speed no longer simulated) are removed, and the ledger
lists what is there. A folder from before the ledger counts as the tool's when its
report carries the tool's own header (`marker`); then every file of the new report is
taken to be one the tool wrote before, and nothing else is removed.

The staging folder's name carries the process id: one left by a process that no longer
runs (killed while rendering) is removed by the next run into the same folder.
"""

from __future__ import annotations

import os
import shutil
import tempfile
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

from codegen.publish import PublishError, in_the_way, refuse_root, signals_deferred
from codegen.render import write_atomically

#: the names of the files bldc-codegen wrote into a report folder, one per line
LEDGER = ".bldc-codegen-report"
#: the same for a firmware build folder: its own, so that a report written into the
#: folder never takes the image for a former report's files (and deletes it)
BUILD_LEDGER = ".bldc-codegen-build"


def owned_names(
    out: Path, report: str, marker: str, ledger_name: str = LEDGER
) -> frozenset[str] | None:
    """The names of `out`'s files the tool wrote; None when every name counts as the
    tool's (a report folder from before the ledger, its report carrying `marker`)."""
    ledger = out / ledger_name
    if ledger.is_file():
        # plain names only (a report folder is flat): a ledger line "/tmp/x" or "../x"
        # had the next run delete that file outside the folder
        names = ledger.read_text(encoding="utf-8", errors="replace").splitlines()
        return frozenset(n for n in names if n not in ("", ".", "..") and _plain_name(n))
    try:
        head = (out / report).read_text(encoding="utf-8", errors="replace")[:2000]
    except OSError:
        return frozenset()
    return None if marker in head else frozenset()


def _plain_name(name: str) -> bool:
    return not any(c in name for c in "/\\\0")


def strangers(
    out: Path, names: list[str], report: str, marker: str, ledger_name: str = LEDGER
) -> list[Path]:
    """The files of `out` that `names` would replace and the tool did not write."""
    if not out.is_dir():
        return []
    owned = owned_names(out, report, marker, ledger_name)
    found = []
    for name in names:
        path = out / name
        if not (path.exists() or path.is_symlink()):
            continue
        if path.is_symlink() or not path.is_file() or (owned is not None and name not in owned):
            found.append(path)
    return found


def refuse_strangers(
    out: Path, names: list[str], report: str, marker: str, ledger_name: str = LEDGER
) -> None:
    """Raise PublishError when a file of `names` in `out` is a stranger's, or `out` is
    a file-system root (`simulate -o /` had written its report into /)."""
    refuse_root(out)
    paths = strangers(out, names, report, marker, ledger_name)
    if paths:
        raise PublishError(
            f"{in_the_way(paths, out)} not written by bldc-codegen (the folder's"
            f" {ledger_name} does not list it): move it away or choose another output folder"
        )


@contextmanager
def staged_report(out: Path, report: str, marker: str) -> Iterator[Path]:
    """A staging folder to write the report into; on leaving without an error its files
    are moved into `out` (refused, leaving `out` as it was, when one would replace a
    file the tool did not write). `report` is the report's file name, `marker` a text
    its header holds."""
    refuse_strangers(out, [report], report, marker)
    out.parent.mkdir(parents=True, exist_ok=True)
    _remove_abandoned_staging(out)
    prefix = f".{out.name}.staging-{os.getpid()}-"
    staging = Path(tempfile.mkdtemp(prefix=prefix, dir=out.parent))
    try:
        yield staging
        names = sorted(p.name for p in staging.iterdir())
        refuse_strangers(out, names, report, marker)
        owned = owned_names(out, report, marker) if out.is_dir() else frozenset()
        out.mkdir(parents=True, exist_ok=True)
        earlier = set(owned) if owned is not None else set()
        with signals_deferred():
            _write_ledger(out, earlier | set(names))
            for name in names:
                os.replace(staging / name, out / name)
            for name in sorted(earlier - set(names)):
                path = out / name
                if path.is_file() and not path.is_symlink():
                    path.unlink()
            _write_ledger(out, {n for n in names if (out / n).is_file()})
    finally:
        shutil.rmtree(staging, ignore_errors=True)


def claim_build_names(out: Path, names: list[str], report: str, marker: str) -> None:
    """Refuse a stranger's file of `names` in `out`, then list `names` in its build
    ledger before any is written in place (a firmware build's objects and image): a
    build interrupted or failed half-way leaves files the next one knows as its own."""
    refuse_strangers(out, names, report, marker, BUILD_LEDGER)
    owned = owned_names(out, report, marker, BUILD_LEDGER)
    out.mkdir(parents=True, exist_ok=True)
    _write_ledger(out, set(owned or ()) | set(names), BUILD_LEDGER)


def _write_ledger(out: Path, names: set[str], ledger_name: str = LEDGER) -> None:
    write_atomically(out / ledger_name, "".join(f"{n}\n" for n in sorted(names)))


def _remove_abandoned_staging(out: Path) -> None:
    """Staging folders of `out` whose process no longer runs (killed while rendering)."""
    for folder in out.parent.glob(f".{out.name}.staging-*-*"):
        pid = folder.name.removeprefix(f".{out.name}.staging-").split("-", 1)[0]
        if not pid.isdigit() or not folder.is_dir() or folder.is_symlink():
            continue
        try:
            os.kill(int(pid), 0)
        except ProcessLookupError:
            shutil.rmtree(folder, ignore_errors=True)
        except OSError:
            continue  # another user's process: it runs

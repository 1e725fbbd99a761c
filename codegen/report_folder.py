"""A report's files into its output folder, never over a file the tool did not write.

`simulate` and `robustness` write a report and its figures into a folder a user may
name with `-o`. The files are written into a staging folder beside it first (hidden,
on the same file system); only when all of them are there is each moved in by rename,
and only if no file of the same name in the folder is a stranger's: a hand-written
SIMULATION.md in the folder given with -o stops the run, in one line, before anything
in the folder changes (it had been overwritten).

Which files are the tool's: those its ledger in the folder lists (`LEDGER`, rewritten
after each report with every name it has written there). A folder from before the
ledger counts as the tool's when its report carries the tool's own header (`marker`);
then every file of the new report is taken to be one the tool wrote before.
"""

from __future__ import annotations

import os
import shutil
import tempfile
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

from codegen.publish import PublishError
from codegen.render import write_atomically

#: the names of the files bldc-codegen wrote into a report folder, one per line
LEDGER = ".bldc-codegen-report"


def owned_names(out: Path, report: str, marker: str) -> frozenset[str] | None:
    """The names of `out`'s files the tool wrote; None when every name counts as the
    tool's (a report folder from before the ledger, its report carrying `marker`)."""
    ledger = out / LEDGER
    if ledger.is_file():
        return frozenset(n for n in ledger.read_text(encoding="utf-8").splitlines() if n)
    try:
        head = (out / report).read_text(encoding="utf-8", errors="replace")[:2000]
    except OSError:
        return frozenset()
    return None if marker in head else frozenset()


def strangers(out: Path, names: list[str], report: str, marker: str) -> list[Path]:
    """The files of `out` that `names` would replace and the tool did not write."""
    if not out.is_dir():
        return []
    owned = owned_names(out, report, marker)
    found = []
    for name in names:
        path = out / name
        if not (path.exists() or path.is_symlink()):
            continue
        if path.is_symlink() or not path.is_file() or (owned is not None and name not in owned):
            found.append(path)
    return found


def refuse_strangers(out: Path, names: list[str], report: str, marker: str) -> None:
    """Raise PublishError when a file of `names` in `out` is a stranger's."""
    paths = strangers(out, names, report, marker)
    if paths:
        raise PublishError(
            f"{paths[0]} is in the way and was not written by bldc-codegen (the report"
            f" folder's {LEDGER} does not list it): move it away or choose another output"
            " folder"
        )


@contextmanager
def staged_report(out: Path, report: str, marker: str) -> Iterator[Path]:
    """A staging folder to write the report into; on leaving without an error its files
    are moved into `out` (refused, leaving `out` as it was, when one would replace a
    file the tool did not write). `report` is the report's file name, `marker` a text
    its header holds."""
    refuse_strangers(out, [report], report, marker)
    out.parent.mkdir(parents=True, exist_ok=True)
    staging = Path(tempfile.mkdtemp(prefix=f".{out.name}.staging-", dir=out.parent))
    try:
        yield staging
        names = sorted(p.name for p in staging.iterdir())
        refuse_strangers(out, names, report, marker)
        owned = owned_names(out, report, marker) if out.is_dir() else frozenset()
        out.mkdir(parents=True, exist_ok=True)
        for name in names:
            os.replace(staging / name, out / name)
        kept = set(names) | (set(owned) if owned is not None else set())
        kept = {n for n in kept if (out / n).is_file()}
        write_atomically(out / LEDGER, "".join(f"{n}\n" for n in sorted(kept)))
    finally:
        shutil.rmtree(staging, ignore_errors=True)

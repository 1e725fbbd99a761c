"""A report's files into its output folder, never over a file the tool did not write.

`simulate` and `robustness` write a report and its figures into a folder a user may
name with `-o`. The files are written into a staging folder beside it first (hidden,
on the same file system); only when all of them are there is each moved in by rename,
and only if no file of the same name in the folder is a stranger's: a hand-written
SIMULATION.md in the folder given with -o stops the run, in one line, before anything
in the folder changes (it had been overwritten).

Which files are the tool's: those its ledger in the folder lists (`LEDGER`, a line
`name<TAB>sha256` for each) whose content still has the SHA-256 recorded, read only
where the name is a regular file inside the folder. A line without a hash, a file since
changed, a link, a FIFO or a name leading outside the folder is a stranger's: never
removed, and never replaced (a forged line "mine.txt" had the next run delete the
user's mine.txt). The ledger is written before the moves, listing the new report's
files with the hashes of what was staged, beside the earlier entries' own, so that a
run stopped between two moves (SIGKILL) leaves no file of its own unlisted (the next
run had refused its own figure as a stranger's); SIGINT, SIGTERM and SIGHUP wait for
the moves (`signals_deferred`). After them the tool's files of an earlier report that
the new one does not have (a figure of a speed no longer simulated) are removed, each
only while its hash still matches, and the ledger lists what is there. A folder from
before the ledger, or whose ledger holds no hash at all (an earlier version's), counts
as the tool's when its report carries the tool's own header (`marker`); then every
file of the new report is taken to be one the tool wrote before, and nothing else is
removed.

The firmware build (`staged_build`) keeps its own ledger (`BUILD_LEDGER`) by the same
rules: it refuses a stranger's file of any name it may write before it compiles, then
compiles and links into a staging folder inside the build folder and moves its files in
as a report's are, its ledger written first with their hashes. A forged names-only line
"main.o" had let `firmware --build` overwrite the user's main.o; a build interrupted
half-way leaves the folder as it was. A build folder from before the build ledger, or
with an earlier version's (names, no hashes), counts as the tool's when its map carries
the build's `marker`: the new build's files are replaced, nothing else is removed.

The staging folder's name carries the process id: one left by a process that no longer
runs (killed while rendering) is removed by the next run into the same folder. A
report's is beside its folder; a build's is inside it (`firmware --build .` and a build
folder that is a link to another file system move their files within the folder).
"""

from __future__ import annotations

import glob
import hashlib
import os
import shutil
import tempfile
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

from codegen.manifest_check import SHA256, read_listed
from codegen.publish import PublishError, in_the_way, refuse_root, signals_deferred
from codegen.render import write_atomically

#: the files bldc-codegen wrote into a report folder, a line `name<TAB>sha256` each
LEDGER = ".bldc-codegen-report"
#: the same for a firmware build folder: its own, so that a report written into the
#: folder never takes the image for a former report's files (and deletes it)
BUILD_LEDGER = ".bldc-codegen-build"


def owned_names(
    out: Path, report: str, marker: str, ledger_name: str = LEDGER
) -> frozenset[str] | None:
    """The names of `out`'s files the tool wrote; None when every name counts as the
    tool's (a folder from before the ledger, its report carrying `marker`)."""
    owned = owned_hashes(out, report, marker, ledger_name)
    return None if owned is None else frozenset(owned)


def owned_hashes(
    out: Path, report: str, marker: str, ledger_name: str = LEDGER
) -> dict[str, str] | None:
    """The files of `out` the ledger lists whose content still has a recorded SHA-256:
    name -> that hash. None when every name counts as the tool's (no ledger, or one
    without hashes, and a report carrying `marker`)."""
    lines = _ledger_lines(out, ledger_name)
    recorded = _recorded(lines or [])
    if not recorded:
        return None if _by_marker(out, report, marker) is None and _legacy(lines) else {}
    owned = {}
    for name, digests in recorded.items():
        current = digest_of(out, name)
        if current is not None and current in digests:
            owned[name] = current
    return owned


def _legacy(lines: list[str] | None) -> bool:
    """Whether `out` has no ledger, or one of an earlier version (names, no hashes)."""
    return lines is None or not any("\t" in line for line in lines)


def _by_marker(out: Path, report: str, marker: str) -> frozenset[str] | None:
    """None (every name the tool's) when `out`'s report carries `marker`, else none."""
    try:
        head = read_listed(out, report)[:8000].decode("utf-8", errors="replace")
    except OSError:
        return frozenset()
    return None if marker in head else frozenset()


def _ledger_lines(out: Path, ledger_name: str) -> list[str] | None:
    """The ledger's lines; None where there is none, no line where it is no regular
    file (a FIFO had blocked the run, a link is read as listing nothing)."""
    try:
        data = read_listed(out, ledger_name)
    except FileNotFoundError:
        return None
    except OSError:
        return []
    return data.decode("utf-8", errors="replace").splitlines()


def _recorded(lines: list[str]) -> dict[str, set[str]]:
    """The ledger's `name<TAB>sha256` lines: name -> the hashes recorded for it (two
    while a run moves a new file over an earlier one). A line without a well-formed
    hash, or naming anything but a plain file name, records nothing."""
    recorded: dict[str, set[str]] = {}
    for line in lines:
        name, tab, digest = line.partition("\t")
        if tab and _plain_name(name) and SHA256.fullmatch(digest):
            recorded.setdefault(name, set()).add(digest)
    return recorded


def digest_of(folder: Path, name: str) -> str | None:
    """The SHA-256 of `folder`/`name` where it is a regular file inside `folder`
    (read without following a link or opening a FIFO); None otherwise."""
    if not _plain_name(name):
        return None
    try:
        return hashlib.sha256(read_listed(folder, name)).hexdigest()
    except OSError:
        return None


def _plain_name(name: str) -> bool:
    """A file name of the flat folder: a ledger line "/tmp/x" or "../x" had the next
    run delete that file outside it."""
    return name not in ("", ".", "..") and not any(c in name for c in "/\\\0")


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
            f" {ledger_name} does not list it with its content's SHA-256): move it away or"
            " choose another output folder"
        )


@contextmanager
def staged_report(out: Path, report: str, marker: str) -> Iterator[Path]:
    """A staging folder to write the report into; on leaving without an error its files
    are moved into `out` (refused, leaving `out` as it was, when one would replace a
    file the tool did not write). `report` is the report's file name, `marker` a text
    its header holds."""
    refuse_strangers(out, [report], report, marker)
    out.parent.mkdir(parents=True, exist_ok=True)
    prefix = f".{out.name}.staging-"
    _remove_abandoned_staging(out.parent, prefix)
    staging = Path(tempfile.mkdtemp(prefix=f"{prefix}{os.getpid()}-", dir=out.parent))
    try:
        yield staging
        _move_in(out, staging, report, marker, LEDGER)
    finally:
        shutil.rmtree(staging, ignore_errors=True)


@contextmanager
def staged_build(out: Path, names: list[str], report: str, marker: str) -> Iterator[Path]:
    """A staging folder inside `out` to build into, after refusing a stranger's file of
    `names` (every file the build may write) in `out`; on leaving without an error its
    files are moved into `out` as a report's are, listed in `out`'s build ledger with
    their hashes. `report` is the build's map, `marker` a text its head holds."""
    refuse_strangers(out, names, report, marker, BUILD_LEDGER)
    out.mkdir(parents=True, exist_ok=True)
    prefix = f"{BUILD_LEDGER}.staging-"
    _remove_abandoned_staging(out, prefix)
    staging = Path(tempfile.mkdtemp(prefix=f"{prefix}{os.getpid()}-", dir=out))
    try:
        yield staging
        _move_in(out, staging, report, marker, BUILD_LEDGER)
    finally:
        shutil.rmtree(staging, ignore_errors=True)


def _move_in(out: Path, staging: Path, report: str, marker: str, ledger_name: str) -> None:
    """Move the files of `staging` into `out`, refused (`out` left as it was) when one
    would replace a file the tool did not write; the ledger lists them with their hashes
    before the moves, and the earlier files of the tool the new ones do not replace are
    removed after them."""
    names = sorted(p.name for p in staging.iterdir())
    refuse_strangers(out, names, report, marker, ledger_name)
    earlier = owned_hashes(out, report, marker, ledger_name) or {}
    staged = {name: digest_of(staging, name) for name in names}
    out.mkdir(parents=True, exist_ok=True)
    with signals_deferred():
        _write_hashed_ledger(out, [*earlier.items(), *staged.items()], ledger_name)
        for name in names:
            os.replace(staging / name, out / name)
        kept = _remove_earlier(out, {n: d for n, d in earlier.items() if n not in staged})
        listed = [(n, d) for n, d in staged.items() if (out / n).is_file()]
        _write_hashed_ledger(out, [*listed, *kept.items()], ledger_name)


def _remove_earlier(out: Path, earlier: dict[str, str]) -> dict[str, str]:
    """Remove the earlier report's files the new one does not have, each only while its
    content has the hash recorded; those that could not go (still the tool's)."""
    kept = {}
    for name, digest in sorted(earlier.items()):
        if digest_of(out, name) != digest:
            continue  # changed since: a stranger's now
        try:
            (out / name).unlink()
        except OSError:
            kept[name] = digest
    return kept


def _write_hashed_ledger(
    out: Path, entries: list[tuple[str, str | None]], ledger_name: str = LEDGER
) -> None:
    """The ledger: a line `name<TAB>sha256` for each entry with a hash."""
    lines = sorted({f"{name}\t{digest}\n" for name, digest in entries if digest is not None})
    write_atomically(out / ledger_name, "".join(lines))


def _remove_abandoned_staging(folder: Path, prefix: str) -> None:
    """The staging folders in `folder` named `prefix`<pid>-... whose process no longer
    runs (killed while rendering or compiling)."""
    for staging in folder.glob(f"{glob.escape(prefix)}*-*"):
        pid = staging.name.removeprefix(prefix).split("-", 1)[0]
        if not pid.isdigit() or not staging.is_dir() or staging.is_symlink():
            continue
        try:
            os.kill(int(pid), 0)
        except ProcessLookupError:
            shutil.rmtree(staging, ignore_errors=True)
        except OSError:
            continue  # another user's process: it runs

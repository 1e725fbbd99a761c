"""Publish a generated tree into a folder so that it cannot be lost or half-written.

`publish(files, target)` replaces the files bldc-codegen wrote in `target` by `files`:

1. Lock: `.<name>.bldc-codegen.lock` beside the target (flock), so concurrent runs into
   the same folder take turns instead of renaming over each other.
2. Recover: leftovers of a killed run (the hidden siblings `.<name>.bldc-codegen-new`
   and `.<name>.bldc-codegen-old`) are finished or undone before anything else.
3. Stage: every file is written (manifest first, then the files, each fsynced) into
   `.<name>.bldc-codegen-new`, a sibling on the same file system.
4. Publish, in ONE step: renameat2(RENAME_EXCHANGE) swaps the staged folder and the
   target atomically (Linux 3.15+ on ext4, btrfs, xfs, tmpfs...). A reader or a kill
   at any instant sees the complete old tree or the complete new one. Where the
   exchange is unavailable (other systems, some file systems) two renames do it, and a
   kill between them leaves the target missing until the next run, whose recovery puts
   the complete new tree (verified against its manifest) or else the old one in place.
5. Carry over: everything in the old tree that bldc-codegen did not write (reports of
   `verify` and `sim` in verify/ and simulation/, a user's own files) is moved, by
   rename, into the new tree. Then the old tree's own files are deleted, and its
   folders if they are empty. Nothing else is ever deleted.

What bldc-codegen wrote is what the target's manifest.json lists ("files" and
"folders", with "generator": "bldc-codegen"). The target keeps its place and its name:
it is a real folder, not a symlink, so git, `make check-generated`, diff and Windows
see the same layout as always. Its inode changes at each publish: a shell whose working
directory is the target must `cd` into it again.

Before staging, a file the new tree would put where a foreign file already is (say a
hand-written AUDIT.md in a folder given with -o) stops the publish with PublishError:
nothing is overwritten that the tool did not write.

Fault injection for tests: with BLDC_CODEGEN_TEST_KILL_AT_STEP=k in the environment the
process SIGKILLs itself at its k-th file-system step (every write, fsync, mkdir, rename,
exchange, unlink and rmdir here is one); BLDC_CODEGEN_TEST_STEP_LOG=FILE appends each
step's label to FILE; BLDC_CODEGEN_TEST_KILL_AT_LABEL=PREFIX kills at the first step whose
label starts with PREFIX ("exchange", "write AUDIT.md"); BLDC_CODEGEN_TEST_KILL_SIGNAL=
INT, TERM or HUP sends that signal there instead of SIGKILL. BLDC_CODEGEN_NO_EXCHANGE=1
forces the two-rename fallback.

SIGINT, SIGTERM and SIGHUP (Ctrl-C, `kill`, a closed terminal) are held back while the
lock is held and delivered when the publish is done (`signals_deferred`): one arriving
mid-publish ends the run with the new tree whole and the user's files in place, instead
of leaving them in the hidden `-old` folder until the next run. Only SIGKILL (and a
power cut) can stop a publish half-way, and the next run's recovery handles those.
"""

from __future__ import annotations

import contextlib
import ctypes
import errno
import hashlib
import json
import os
import signal
import sys
import tempfile
from collections.abc import Iterable, Iterator, Mapping
from dataclasses import dataclass, field
from pathlib import Path

from codegen.manifest_check import NotRegularFileError, inside, read_listed
from codegen.shown import on_one_line

GENERATOR = "bldc-codegen"
MANIFEST = "manifest.json"
_TAG = "bldc-codegen"


class PublishError(OSError):
    """The output cannot be published (a foreign file in the way, an unusable target)."""


@dataclass
class PublishResult:
    target: Path
    atomic_exchange: bool
    recovered: list[str] = field(default_factory=list)
    carried_over: list[str] = field(default_factory=list)
    left_behind: list[str] = field(default_factory=list)
    #: one line for each thing the user must know: a file left in a hidden folder
    notes: list[str] = field(default_factory=list)


# --------------------------------------------------------------------- fault injection

_steps = 0


def _step(label: str) -> None:
    """Count one file-system step; the fault-injection hook for the kill -9 tests."""
    global _steps
    _steps += 1
    log = os.environ.get("BLDC_CODEGEN_TEST_STEP_LOG")
    if log:
        with open(log, "a", encoding="utf-8") as stream:
            stream.write(f"{_steps} {label}\n")
    kill_at = os.environ.get("BLDC_CODEGEN_TEST_KILL_AT_STEP")
    kill_label = os.environ.get("BLDC_CODEGEN_TEST_KILL_AT_LABEL")
    if (kill_at and int(kill_at) == _steps) or (kill_label and label.startswith(kill_label)):
        name = os.environ.get("BLDC_CODEGEN_TEST_KILL_SIGNAL", "KILL")
        os.kill(os.getpid(), getattr(signal, f"SIG{name}"))


# --------------------------------------------------------------------- file system steps


def _write(path: Path, text: str) -> None:
    _step(f"write {path.name}")
    data = text.encode("utf-8")
    try:
        with open(path, "wb") as stream:
            stream.write(data)
            stream.flush()
            _step(f"fsync {path.name}")
            os.fsync(stream.fileno())
    except OSError as exc:  # a write's ENOSPC names no file
        raise OSError(exc.errno, exc.strerror, str(exc.filename or path)) from None


def _fsync_dir(path: Path) -> None:
    if os.name != "posix":
        return
    fd = os.open(path, os.O_RDONLY)
    try:
        os.fsync(fd)
    finally:
        os.close(fd)


def _mkdir(path: Path) -> None:
    _step(f"mkdir {path.name}")
    path.mkdir()


def _rename(src: Path, dst: Path) -> None:
    _step(f"rename {src.name} -> {dst.name}")
    os.rename(src, dst)


def _unlink(path: Path) -> None:
    _step(f"unlink {path.name}")
    path.unlink()


def _rmdir(path: Path) -> None:
    _step(f"rmdir {path.name}")
    path.rmdir()


_RENAME_EXCHANGE = 2
_AT_FDCWD = -100


def _exchange(a: Path, b: Path) -> bool:
    """Swap two directory entries atomically; False if this system cannot."""
    if os.environ.get("BLDC_CODEGEN_NO_EXCHANGE") or not sys.platform.startswith("linux"):
        return False
    try:
        libc = ctypes.CDLL(None, use_errno=True)
        renameat2 = libc.renameat2
    except (OSError, AttributeError):
        return False
    renameat2.argtypes = (
        ctypes.c_int,
        ctypes.c_char_p,
        ctypes.c_int,
        ctypes.c_char_p,
        ctypes.c_uint,
    )
    _step(f"exchange {a.name} <-> {b.name}")
    if renameat2(_AT_FDCWD, os.fsencode(a), _AT_FDCWD, os.fsencode(b), _RENAME_EXCHANGE) == 0:
        return True
    code = ctypes.get_errno()
    if code in (errno.EINVAL, errno.ENOSYS, errno.ENOTSUP, errno.EOPNOTSUPP):
        return False
    raise OSError(code, os.strerror(code), str(b))


# --------------------------------------------------------------------- ownership


@dataclass(frozen=True)
class _Owned:
    files: frozenset[str]
    folders: frozenset[str]
    hashes: Mapping[str, str]


def manifest_record(files: Mapping[str, str]) -> dict[str, object]:
    """The manifest's ownership part for a tree of `files` (path -> text): every file
    with its SHA-256 and every folder the tree creates. manifest.json itself is owned."""
    folders = sorted(
        {"/".join(name.split("/")[:i]) for name in files for i in range(1, name.count("/") + 1)}
    )
    return {
        "generator": GENERATOR,
        "folders": folders,
        "files": {
            name: hashlib.sha256(text.encode()).hexdigest() for name, text in sorted(files.items())
        },
    }


def _manifest_data(tree: Path) -> object:
    """The JSON of `tree`'s manifest, read only where it is a regular file (a FIFO in
    its place had blocked `generate -o` for good, SIGTERM held back by the lock);
    OSError or ValueError where it cannot be read or parsed."""
    return json.loads(read_listed(tree, MANIFEST).decode("utf-8"))


def manifest_unreadable(tree: Path) -> str | None:
    """Why `tree`'s manifest.json cannot be read, in a few words, where one is there
    (not JSON, a FIFO, no permission); None where there is none or it reads as JSON."""
    try:
        _manifest_data(tree)
    except FileNotFoundError:
        return None
    except NotRegularFileError as exc:
        return f"it is {exc}"
    except UnicodeDecodeError:
        return "it is not UTF-8 text"
    except ValueError as exc:
        return f"it is not JSON: {exc}"
    except OSError as exc:
        return exc.strerror or str(exc)
    return None


def _owned(tree: Path) -> _Owned | None:
    """What bldc-codegen wrote in `tree`, from its manifest; None if it has none."""
    try:
        data = _manifest_data(tree)
    except (OSError, ValueError):
        return None
    if not isinstance(data, dict) or not isinstance(data.get("files"), dict):
        return None
    # Manifests written before "generator" existed have spec_sha256 and files.
    if data.get("generator") != GENERATOR and "spec_sha256" not in data:
        return None
    # only names inside the tree: a manifest listing "../x" or "/tmp/x" (edited, or
    # not ours) had its generate delete those files outside the output folder
    files = {str(name) for name in data["files"] if inside(str(name))}
    folders = {"/".join(n.split("/")[:i]) for n in files for i in range(1, n.count("/") + 1)}
    folders |= {f for f in data.get("folders", []) if isinstance(f, str) and inside(f)}
    hashes = {str(k): str(v) for k, v in data["files"].items() if str(k) in files}
    return _Owned(frozenset(files | {MANIFEST}), frozenset(folders), hashes)


def _complete(tree: Path) -> bool:
    """Whether every file the tree's manifest lists is there with its hash."""
    owned = _owned(tree)
    if owned is None:
        return False
    for name, digest in owned.hashes.items():
        try:
            if hashlib.sha256(read_listed(tree, name)).hexdigest() != digest:
                return False
        except OSError:
            return False
    return True


# --------------------------------------------------------------------- lock


@contextlib.contextmanager
def _locked(lock_path: Path) -> Iterator[None]:
    fd = os.open(lock_path, os.O_RDWR | os.O_CREAT, 0o644)
    try:
        if os.name == "posix":
            import fcntl

            try:
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except BlockingIOError:
                # the lock `.<name>.bldc-codegen.lock` sits beside the folder it guards
                target = lock_path.parent / lock_path.name[1 : -len(f".{_TAG}.lock")]
                print(
                    f"waiting for another bldc-codegen run writing {on_one_line(str(target))}",
                    file=sys.stderr,
                )
                fcntl.flock(fd, fcntl.LOCK_EX)
        else:  # pragma: no cover - Windows
            import msvcrt

            while True:
                try:
                    msvcrt.locking(fd, msvcrt.LK_LOCK, 1)
                    break
                except OSError:
                    continue
        yield
    finally:
        os.close(fd)  # releases the lock


#: the signals that end a run politely; held back while a publish is under way
_DEFERRED_SIGNALS = tuple(
    getattr(signal, name) for name in ("SIGINT", "SIGTERM", "SIGHUP") if hasattr(signal, name)
)


@contextlib.contextmanager
def signals_deferred() -> Iterator[None]:
    """Hold back SIGINT, SIGTERM and SIGHUP until the block is done, then deliver the
    first that came (its own handler runs: KeyboardInterrupt, or the process ends). In a
    thread other than the main one handlers cannot be set and nothing is deferred."""
    import threading

    if threading.current_thread() is not threading.main_thread():
        yield
        return
    arrived: list[int] = []

    def hold(signum: int, _frame: object) -> None:
        arrived.append(signum)

    previous = {}
    try:
        for signum in _DEFERRED_SIGNALS:
            previous[signum] = signal.signal(signum, hold)
        yield
    finally:
        for signum, handler in previous.items():
            signal.signal(signum, handler)
        if arrived:
            os.kill(os.getpid(), arrived[0])


# --------------------------------------------------------------------- paths


@dataclass(frozen=True)
class _Paths:
    target: Path
    staging: Path
    retired: Path
    lock: Path


def refuse_dangling_link(target: Path) -> None:
    """PublishError where `target`, or a folder above it, is a symbolic link to nothing:
    the output would go where the link points, made on the way (`generate -o LINK`, LINK
    pointing to /nonexistent/x, had created /nonexistent/x)."""
    target = Path(os.path.abspath(target))
    for path in (target, *target.parents):
        points_to = _dangling(path)
        if points_to is not None:
            raise PublishError(
                f"{on_one_line(str(path))} is a symbolic link to nothing"
                f" ({_clipped_path(on_one_line(points_to))} does not exist): give a folder, or"
                " make the one it points to first"
            )


def _dangling(path: Path) -> str | None:
    """Where `path` points when it is a symbolic link to nothing; None otherwise (a link
    loop too: left to the write, which says so)."""
    try:
        if not path.is_symlink():
            return None
        os.stat(path)
    except FileNotFoundError:
        return os.readlink(path)
    except OSError:
        return None
    return None


def _clipped_path(text: str, limit: int = 200) -> str:
    """A path the user did not type, cut to `limit` characters in a one-line message."""
    return text if len(text) <= limit else f"{text[: limit - 3]}..."


def refuse_root(target: Path) -> None:
    """PublishError where `target`, or the link it is, names a file-system root: no
    command writes its output there (`simulate -o /` had put its report into /); and
    where it or a folder above it is a symbolic link to nothing (`refuse_dangling_link`).
    A link loop is left to the write, which says so."""
    refuse_dangling_link(target)
    target = Path(os.path.abspath(target))
    try:
        if target.is_symlink():
            target = target.resolve()
    except (RuntimeError, OSError):
        return
    if target.parent == target:
        raise PublishError(f"{target} is a file-system root: choose a folder inside it")


def _paths(target: Path) -> _Paths:
    target = Path(os.path.abspath(target))
    try:
        refuse_root(target)  # and a link to nothing, before it is followed
        if target.is_symlink():
            target = target.resolve()  # publish into the folder the link points to
        parent = target.parent.resolve()
    except (RuntimeError, OSError) as exc:  # RuntimeError: Python < 3.13's symlink loop
        if isinstance(exc, PublishError):
            raise
        raise PublishError(
            f"{target}: a symbolic link on the way points back to itself (a link loop):"
            " give a real folder"
        ) from None
    name = target.name
    return _Paths(
        parent / name,
        parent / f".{name}.{_TAG}-new",
        parent / f".{name}.{_TAG}-old",
        parent / f".{name}.{_TAG}.lock",
    )


def file_in_the_way(path: Path) -> Path | None:
    """The file standing where `path`, or a folder above it, must be a folder: the first
    existing path from `path` upwards when that is not a folder, else None. Checked
    before long work whose output goes there, so that it fails at once."""
    for candidate in (path, *path.parents):
        if candidate.exists():
            return None if candidate.is_dir() else candidate
    return None


def require_folder_path(path: Path) -> None:
    """Raise NotADirectoryError (for `os_error_line`) when a file stands where `path` or
    a folder above it must be: before long work whose output goes there."""
    if file_in_the_way(path) is not None:
        raise NotADirectoryError(errno.ENOTDIR, os.strerror(errno.ENOTDIR), str(path))


def require_writable_folder(path: Path) -> None:
    """`require_folder_path`, and a folder can be made where `path` goes (probed by
    making and removing one in the nearest folder that exists): before long work whose
    output goes there. Raises OSError naming `path` (`simulate -o /proc/x` had simulated
    for 9 s, then named its hidden staging folder)."""
    require_folder_path(path)
    if path.is_symlink() and not path.exists():  # the staging's rename fails there, late
        raise FileExistsError(
            errno.EEXIST, "a symbolic link to nothing is there (give a folder)", str(path)
        )
    existing = next((p for p in (path, *path.parents) if p.is_dir()), None)
    if existing is None:
        return
    try:
        probe = tempfile.mkdtemp(prefix=f".{path.name or 'out'}.probe-", dir=existing)
    except OSError as exc:
        raise OSError(exc.errno, exc.strerror, str(path)) from None
    with contextlib.suppress(OSError):
        os.rmdir(probe)


def os_error_line(exc: OSError) -> str:
    """The one `error:` line for a file-system error: the file that stands where a
    folder had to be made (mkdir's "File exists", or "Not a directory" below it) named
    as such; else the path and the system's words."""
    blocker = (
        file_in_the_way(Path(str(exc.filename)))
        if isinstance(exc, FileExistsError | NotADirectoryError) and exc.filename
        else None
    )
    if blocker is not None:
        return (
            f"error: {on_one_line(str(exc.filename))}: {on_one_line(str(blocker))} is a file,"
            " not a folder (a folder is needed"
            " there: give another path, or move the file)"
        )
    words = exc.strerror or str(exc).splitlines()[0]
    lock = Path(str(exc.filename)) if exc.filename else None
    if lock is not None and lock.name.startswith(".") and lock.name.endswith(f".{_TAG}.lock"):
        target = lock.parent / lock.name[1 : -len(f".{_TAG}.lock")]
        return (
            f"error: {on_one_line(str(target))}: cannot publish there: {words} when creating"
            f" its lock file {on_one_line(lock.name)} beside it (give a folder in a writable"
            " place)"
        )
    if not exc.filename:
        return f"error: {words}"
    return f"error: {on_one_line(str(exc.filename))}: {words}"


def _refuse_the_working_folder(target: Path) -> None:
    """PublishError when `target` is the current folder or one above it: the publish
    puts a new folder in the target's place and removes the old one once emptied, so
    `-o .` pulled the working folder out from under the run (and the user's shell)."""
    try:
        here = Path.cwd().resolve()
    except OSError:
        return
    if target == here or target in here.parents:
        which = "the current folder" if target == here else "a folder above the current one"
        raise PublishError(
            f"{target} is {which}: the output folder is replaced by a new one at each run,"
            " which would pull it out from under this shell; give a folder below it"
            " (e.g. generated/NAME) or run from elsewhere"
        )


def check_target(target: Path) -> Path:
    """The absolute target folder, or PublishError if it can never hold the output (a
    file-system root, a file, the working folder): cheap, so a command can fail before
    it does any work."""
    p = _paths(target)
    _refuse_the_working_folder(p.target)
    _refuse_inside_another_tree(p.target)
    if p.target.exists() and not p.target.is_dir():
        raise PublishError(f"{p.target} exists and is not a folder")
    blocker = file_in_the_way(p.target)
    if blocker is not None:  # a file above it: the folder can never be made
        raise PublishError(f"{p.target}: {blocker} is a file, not a folder")
    return p.target


# --------------------------------------------------------------------- recovery


def _carry_over(old: Path, new: Path, result: PublishResult) -> bool:
    """Move what bldc-codegen did not write from `old` into `new` (merging folders that
    exist on both sides), then delete what it did write and the folders this emptied.
    True if `old` is gone; a foreign entry whose place in `new` is taken stays in `old`."""
    owned = _owned(old) or _Owned(frozenset(), frozenset(), {})
    merged: list[Path] = []

    def visit(rel: str) -> None:
        here = old / rel if rel else old
        for entry in sorted(here.iterdir(), key=lambda path: path.name):
            name = f"{rel}/{entry.name}" if rel else entry.name
            real_dir = entry.is_dir() and not entry.is_symlink()
            if name in owned.files and not real_dir:
                continue  # deleted below, once everything foreign is safe
            destination = new / name
            if real_dir and (
                name in owned.folders or (destination.is_dir() and not destination.is_symlink())
            ):
                merged.append(entry)
                visit(name)
                continue
            if destination.exists() or destination.is_symlink():
                result.left_behind.append(str(entry))
                continue
            missing = [folder for folder in destination.parents if not folder.exists()]
            try:
                for folder in reversed(missing):
                    _mkdir(folder)
                _rename(entry, destination)
            except OSError as exc:
                # One entry that cannot move (immutable, a mount point) must not strand
                # every entry after it in the hidden folder: it stays, and is named.
                result.left_behind.append(str(entry))
                result.notes.append(
                    f"{entry} could not be moved back into {new / name}"
                    f" ({exc.strerror or exc}): it is still there, move it yourself"
                )
                continue
            result.carried_over.append(name)

    visit("")
    with contextlib.suppress(OSError):  # what cannot go stays, and `old` with it
        for name in sorted(owned.files - {MANIFEST}):
            path = old / name
            # not through a link: a linked sub-folder leads out of the tree
            through_link = any((old / parent).is_symlink() for parent in Path(name).parents)
            if not through_link and (path.is_symlink() or path.is_file()):
                _unlink(path)
        for folder in sorted(merged, key=lambda path: -len(path.parts)):
            if folder.is_dir() and not any(folder.iterdir()):
                _rmdir(folder)
        manifest = old / MANIFEST
        if MANIFEST in owned.files and manifest.is_file():
            _unlink(manifest)
    if any(old.iterdir()):
        return False
    _rmdir(old)
    return True


def _only_a_partial_manifest(tree: Path) -> bool:
    return {p.name for p in tree.iterdir()} <= {MANIFEST} and _owned(tree) is None


def _recover(p: _Paths, result: PublishResult) -> None:
    """Finish or undo a killed run: afterwards no staging or retired folder is left
    (unless it holds something bldc-codegen may not delete) and the target is whole."""
    if not p.target.exists():
        if p.staging.is_dir() and _complete(p.staging) and p.retired.is_dir():
            # Killed between the two renames of the fallback: the new tree is whole.
            _rename(p.staging, p.target)
            result.recovered.append(f"published the complete {p.staging.name}")
        elif p.retired.is_dir():
            _rename(p.retired, p.target)
            result.recovered.append(f"restored {p.retired.name}")
    for leftover in (p.staging, p.retired):
        if not leftover.is_dir():
            continue
        if _owned(leftover) is None and _only_a_partial_manifest(leftover):
            for entry in leftover.iterdir():
                _unlink(entry)
            _rmdir(leftover)
            result.recovered.append(f"removed the empty {leftover.name}")
            continue
        if _carry_over(leftover, p.target, result):
            result.recovered.append(f"cleaned up {leftover.name}")


def recover(target: Path) -> PublishResult:
    """Recover the leftovers of a killed publish into `target`, under the lock."""
    p = _paths(target)
    result = PublishResult(p.target, atomic_exchange=False)
    if not p.target.parent.is_dir():
        return result
    with _locked(p.lock), signals_deferred():
        _recover(p, result)
    return result


# --------------------------------------------------------------------- publish


def _check_target(p: _Paths, files: Mapping[str, str]) -> None:
    """Refuse, before writing anything, to put a file where a foreign one is."""
    if p.target.is_symlink() or (p.target.exists() and not p.target.is_dir()):
        raise PublishError(f"{p.target} exists and is not a folder")
    if not p.target.exists():
        return
    owned = _owned(p.target)
    _require_writable_tree(p.target, owned, files)
    mine = owned.files if owned else frozenset()
    found: list[Path] = []
    for name in files:
        parts = name.split("/")
        for depth in range(1, len(parts) + 1):
            rel = "/".join(parts[:depth])
            path = p.target / rel
            if not (path.exists() or path.is_symlink()):
                break
            real_dir = path.is_dir() and not path.is_symlink()
            if depth < len(parts) and real_dir:
                continue
            if depth == len(parts) and not real_dir and not path.is_symlink() and rel in mine:
                break
            if path not in found:
                found.append(path)
            break
    unreadable = manifest_unreadable(p.target) if found and owned is None else None
    if unreadable is not None:  # it had said only that the tree's files were not the tool's
        raise _unreadable_manifest(p.target, unreadable, f" ({len(found)} in the way)")
    if found:
        raise PublishError(
            f"{in_the_way(found, p.target)} not written by bldc-codegen (its manifest does"
            " not list it): move it away or choose another output folder"
        )


def _unreadable_manifest(target: Path, why: str, count: str = "") -> PublishError:
    return PublishError(
        f"{target / MANIFEST} is unreadable ({on_one_line(why)}): bldc-codegen cannot tell"
        f" its own files in {target} from a stranger's{count}: move that folder away or"
        " choose another output folder"
    )


def refuse_unreadable_manifest(target: Path) -> None:
    """PublishError where `target` is a folder whose manifest.json cannot be read (not
    JSON, a FIFO, no permission): for a command to check before its long work (publish
    refuses it again, under its lock, where the tree's files are in the way)."""
    folder = _paths(target).target  # a link to a folder: the folder
    if folder.is_dir() and not folder.is_symlink():
        unreadable = manifest_unreadable(folder)
        if unreadable is not None:
            raise _unreadable_manifest(folder, unreadable)


def in_the_way(paths: list[Path], folder: Path) -> str:
    """The start of the one line that names every file in the way (the first in full,
    the others in `folder`'s terms; a user had learnt of them one run at a time)."""
    if len(paths) == 1:
        return f"{paths[0]} is in the way and was"
    others = [str(path.relative_to(folder)) for path in paths[1:]]
    shown = ", ".join(others[:5]) + (f" and {len(others) - 5} more" if len(others) > 5 else "")
    return f"{paths[0]} and {len(others)} more there ({shown}) are in the way and were"


def _refuse_inside_another_tree(target: Path) -> None:
    """PublishError when `target` is a folder of another generated tree (a folder above
    it holds a manifest of ours that lists a folder or file at or below it): the two
    trees' files interleave there and each run moves the other's aside (`generate -o
    out/motor/c` had been accepted)."""
    for above in target.parents:
        owned = _owned(above)
        if owned is None:
            continue
        rel = target.relative_to(above).as_posix()
        if rel in owned.folders or any(name.startswith(f"{rel}/") for name in owned.files):
            raise PublishError(
                f"{target} is inside the generated tree {above} (its manifest lists"
                f" {rel}/): each run would move the other's files aside; choose a folder"
                " outside it"
            )


def _require_writable_tree(target: Path, owned: _Owned | None, files: Mapping[str, str]) -> None:
    """PublishError naming the first folder whose entries the publish moves one by one
    and this user cannot move: the target and each of its folders the old or the new
    tree has (not through a link; a folder of the user's own moves whole, by one rename
    in its parent). A read-only one kept the user's files in the hidden old tree
    (`generate -o` a mode-555 folder: exit 0, the user's file moved aside, and every
    later run stopped on the leftover)."""
    new = {"/".join(n.split("/")[:i]) for n in files for i in range(1, n.count("/") + 1)}
    listed = new | (set(owned.folders) if owned else set())
    for rel in ["", *sorted(listed)]:
        here = target / rel if rel else target
        through_link = any((target / parent).is_symlink() for parent in Path(rel).parents)
        if not here.is_dir() or here.is_symlink() or through_link:
            continue
        if not os.access(here, os.W_OK | os.X_OK):
            raise PublishError(
                f"{here} is not writable by this user: the files bldc-codegen did not write"
                " there could not be carried into the new tree (make it writable, e.g."
                " chmod u+w, or choose another output folder)"
            )


def refuse_foreign(target: Path, names: Iterable[str]) -> None:
    """PublishError when publishing `names` into `target` would replace a file
    bldc-codegen did not write: for a command to check before its long work."""
    _check_target(_paths(target), dict.fromkeys(names, ""))


def publish(files: Mapping[str, str], target: Path) -> PublishResult:
    """Replace bldc-codegen's files in `target` by `files` (path -> text, '/'-separated,
    including manifest.json), atomically, keeping everything else in `target`."""
    if MANIFEST not in files:
        raise ValueError("publish() needs the tree's manifest.json")
    for name in files:
        if name.startswith("/") or ".." in name.split("/") or name.endswith("/"):
            raise ValueError(f"unsafe output path {name!r}")
    p = _paths(target)
    _refuse_the_working_folder(p.target)
    _refuse_inside_another_tree(p.target)  # before its lock file is made there
    p.target.parent.mkdir(parents=True, exist_ok=True)
    result = PublishResult(p.target, atomic_exchange=False)
    with _locked(p.lock), signals_deferred():
        _recover(p, result)
        for leftover in (p.staging, p.retired):
            if leftover.exists() or leftover.is_symlink():
                raise PublishError(
                    f"{leftover} is left from an earlier run and holds files that could not"
                    f" be moved back into {p.target}: move them where they belong, delete"
                    " it and run again"
                )
        _check_target(p, files)
        _mkdir(p.staging)  # fails on a leftover recovery had to keep: never discarded
        try:
            _stage(p.staging, files)
            if p.target.exists():
                _take_over_metadata(p.staging, p.target)
                result.atomic_exchange = _exchange(p.staging, p.target)
        except OSError as exc:
            # Nothing is published (a full disk, a target that cannot be replaced): the
            # staged tree, all of it ours, goes, instead of waiting for the next run.
            _discard(p.staging)
            raise _named_in_target(exc, p) from None
        if p.target.exists():
            if result.atomic_exchange:
                _rename(p.staging, p.retired)
            else:
                _rename(p.target, p.retired)
                _rename(p.staging, p.target)
            _fsync_dir(p.target.parent)
            if not _carry_over(p.retired, p.target, result):
                result.left_behind.append(str(p.retired))
                if not result.notes:
                    result.notes.append(
                        f"{p.retired} keeps what could not be moved back into {p.target}"
                    )
        else:
            _rename(p.staging, p.target)
            _fsync_dir(p.target.parent)
    for note in result.notes:
        print(f"warning: {note}", file=sys.stderr)
    return result


def _named_in_target(exc: OSError, p: _Paths) -> OSError:
    """`exc` naming the file of the target it was writing, not the hidden staging
    folder's (a full disk had said "error: No space left on device" and no path)."""
    where = Path(str(exc.filename)) if exc.filename else p.staging
    if where == p.staging or p.staging in where.parents:
        where = p.target / where.relative_to(p.staging)
    return OSError(exc.errno, exc.strerror, str(where))


def _take_over_metadata(staging: Path, target: Path) -> None:
    """Give the staged folder the target's mode and, where allowed (as root), its owner:
    `sudo bldc-codegen generate -o ~/motor` left ~/motor owned by root, its user unable
    to add a file to it."""
    info = target.stat()
    with contextlib.suppress(OSError):
        os.chmod(staging, info.st_mode & 0o7777)
    if hasattr(os, "chown") and (info.st_uid, info.st_gid) != (os.getuid(), os.getgid()):
        with contextlib.suppress(OSError):
            os.chown(staging, info.st_uid, info.st_gid)


def _discard(staging: Path) -> None:
    """Remove a staging folder this run made (every entry in it is this run's)."""
    if not staging.is_dir() or staging.is_symlink():
        return
    for entry in sorted(staging.rglob("*"), key=lambda path: -len(path.parts)):
        with contextlib.suppress(OSError):
            if entry.is_dir() and not entry.is_symlink():
                entry.rmdir()
            else:
                entry.unlink()
    with contextlib.suppress(OSError):
        staging.rmdir()


def _stage(staging: Path, files: Mapping[str, str]) -> None:
    """Write `files` into the (new, empty) folder `staging`."""
    ordered = [MANIFEST, *sorted(name for name in files if name != MANIFEST)]
    made: set[Path] = {staging}
    for name in ordered:
        path = staging / name
        for folder in reversed(path.parents):
            if folder in made or staging not in (folder, *folder.parents):
                continue
            _mkdir(folder)
            made.add(folder)
        _write(path, files[name])
    for folder in sorted(made, key=lambda f: -len(f.parts)):
        _fsync_dir(folder)

"""A generated folder's manifest.json as the commands that read it rely on it.

The manifest is not itself hashed: an edited one ("files": 5, "core": null) had been an
AttributeError in check_fresh and an AssertionError in verify (exit 70), and a "files"
entry naming a FIFO, '/tmp/x' or '../x' was opened (for ever, or outside the folder).
`shape_problem` says which key is not what `generate` writes; `read_listed` reads a
listed file only where it is a regular file inside the folder.
"""

from __future__ import annotations

import os
import re
import stat
from collections.abc import Mapping
from pathlib import Path

from codegen.errors import show_value
from codegen.yaml12 import type_name

#: a SHA-256 in lower-case hex, as generate and the report ledger record it
SHA256 = re.compile(r"[0-9a-f]{64}", re.ASCII)
#: a struct field of the core's ABI, as verify turns it into a NumPy dtype
_FIELD_BITS = (8, 16, 32, 64)

#: Shape = a type (the value is one), a dict (an object with at least these keys, each
#: of its shape) or a one-item list (a list of values of that shape)
_FIELD = {"name": str, "bits": int, "signed": bool}
_CORE = {
    "formats": dict,
    "claims": dict,
    "limits": dict,
    "abi": {
        "flags": dict,
        "structs": {"bldc_inputs_t": [_FIELD], "bldc_outputs_t": [_FIELD]},
    },
}
_TOP = {
    "generator_version": str,
    "spec_name": str,
    "spec_sha256": str,
    "core": _CORE,
    "folders": [str],
    "files": dict,
}
_CURRENT_LOOP = {"claims": dict, "functions": dict}


def _expected(shape: object) -> str:
    if isinstance(shape, dict):
        return "an object"
    if isinstance(shape, list):
        return "a list"
    return {str: "a string", int: "an integer", bool: "a boolean"}.get(shape, "an object")  # type: ignore[call-overload]


def _fits(value: object, shape: object) -> bool:
    """Whether `value` is of `shape`'s own type (its members are checked apart)."""
    if isinstance(shape, dict):
        return isinstance(value, dict)
    if isinstance(shape, list):
        return isinstance(value, list)
    if shape is int:
        return isinstance(value, int) and not isinstance(value, bool)
    return isinstance(value, shape)  # type: ignore[arg-type]


def _problem(value: object, shape: object, key: str) -> str | None:
    """Where `value` (at `key`) is not of `shape`: the key, what it is, what was expected."""
    if not _fits(value, shape):
        shown = "" if value is None else f" ({show_value(value)})"
        return f"{key} is {type_name(value)}{shown}, expected {_expected(shape)}"
    if isinstance(shape, dict):
        assert isinstance(value, dict)
        for member, inner in shape.items():
            if member not in value:
                return f"{key}.{member} is missing, expected {_expected(inner)}"
            found = _problem(value[member], inner, f"{key}.{member}")
            if found is not None:
                return found
    if isinstance(shape, list):
        assert isinstance(value, list)
        for index, item in enumerate(value):
            found = _problem(item, shape[0], f"{key}[{index}]")
            if found is not None:
                return found
    return None


def _fields_problem(core: Mapping[str, object]) -> str | None:
    abi = core["abi"]
    assert isinstance(abi, dict)
    for struct, fields in abi["structs"].items():
        for index, field in enumerate(fields if isinstance(fields, list) else []):
            if field.get("bits") not in _FIELD_BITS:
                return (
                    f"core.abi.structs.{struct}[{index}].bits = {show_value(field.get('bits'))},"
                    f" expected one of {', '.join(map(str, _FIELD_BITS))}"
                )
    for flag, bit in abi["flags"].items():
        if isinstance(bit, bool) or not isinstance(bit, int):
            return f"core.abi.flags.{flag} is {type_name(bit)}, expected an integer"
    return None


def _files_problem(files: Mapping[object, object]) -> str | None:
    for name, digest in files.items():
        if not isinstance(name, str) or not inside(name):
            return (
                f"files lists {show_value(name)}, expected a relative path inside the folder"
                " (no '..', '.', empty part, leading '/' or backslash)"
            )
        if not isinstance(digest, str) or SHA256.fullmatch(digest) is None:
            return f"files[{show_value(name)}] = {show_value(digest)}, expected a SHA-256 in hex"
    return None


def shape_problem(manifest: object) -> str | None:
    """Which key of a generated folder's manifest is not what `generate` writes, and what
    was expected; None if every key the commands read is of its shape."""
    if not isinstance(manifest, dict):
        return f"it is {type_name(manifest)}, expected an object"
    found = _problem(manifest, _TOP, "manifest")
    if found is None and "current_loop" in manifest:
        found = _problem(manifest["current_loop"], _CURRENT_LOOP, "manifest.current_loop")
    if found is not None:
        return found.removeprefix("manifest.")
    return _fields_problem(manifest["core"]) or _files_problem(manifest["files"])


def inside(name: str) -> bool:
    """Whether a manifest's entry names a place inside its tree: a relative POSIX path
    of plain components (no "..", ".", empty part, backslash or NUL)."""
    parts = name.split("/")
    return bool(name) and all(
        part not in ("", ".", "..") and "\\" not in part and "\0" not in part for part in parts
    )


class NotRegularFileError(OSError):
    """A manifest's entry that is no regular file inside its folder (a FIFO, a device, a
    folder, a symbolic link): not opened."""


def read_listed(tree: Path, name: str) -> bytes:
    """The bytes of the file `name` a manifest lists, read only where it is a regular
    file inside `tree`: never a FIFO or a device (opening one had blocked for ever), nor
    through a symbolic link. Raises FileNotFoundError where it is missing and
    NotRegularFileError where it is something else."""
    if not inside(name):
        raise NotRegularFileError(f"{name!r} is not a path inside the folder")
    path = tree / name
    mode = os.lstat(path).st_mode
    if not stat.S_ISREG(mode):
        raise NotRegularFileError(_kind(mode))
    if not Path(os.path.realpath(path)).is_relative_to(os.path.realpath(tree)):
        raise NotRegularFileError("reached through a symbolic link leaving the folder")
    # O_NONBLOCK: a FIFO put in its place after lstat() opens at once, then fstat refuses it
    fd = os.open(path, os.O_RDONLY | os.O_NOFOLLOW | os.O_NONBLOCK | getattr(os, "O_CLOEXEC", 0))
    with os.fdopen(fd, "rb") as stream:
        mode = os.fstat(stream.fileno()).st_mode
        if not stat.S_ISREG(mode):
            raise NotRegularFileError(_kind(mode))
        return stream.read()


def _kind(mode: int) -> str:
    """What a file of `mode` is, in words, where it is no regular file."""
    kinds = (
        (stat.S_ISLNK, "a symbolic link"),
        (stat.S_ISFIFO, "a named pipe (FIFO)"),
        (stat.S_ISDIR, "a folder"),
        (stat.S_ISCHR, "a device"),
        (stat.S_ISBLK, "a device"),
        (stat.S_ISSOCK, "a socket"),
    )
    return next((word for test, word in kinds if test(mode)), "not a regular file")

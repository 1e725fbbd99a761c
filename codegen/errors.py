"""Errors the toolchain reports to its user.

A SpecError always names the key path, the offending value, the unit and the allowed
range, so that a user can fix the YAML without reading the loader. Its text is one line;
MultiSpecError carries every error of one spec, one line each.
"""

from __future__ import annotations

import traceback
from collections.abc import Sequence
from enum import IntEnum
from pathlib import Path

#: Longest rendering of an offending value in a message: a value is quoted so the user
#: can find it, not echoed whole (a 4 kB string or a 2000-item list would bury the line).
_MAX_VALUE_CHARS = 60


def show_value(value: object) -> str:
    """repr() of a value, on one line and at most _MAX_VALUE_CHARS characters; YAML's
    own words for its null and booleans (`poles: ~` had read `= None`)."""
    if value is None:
        return "null"
    if isinstance(value, bool):
        return "true" if value else "false"
    return clipped(repr(value))


def clipped(text: str) -> str:
    """A value's text cut to _MAX_VALUE_CHARS characters (a warning's YAML list too)."""
    if len(text) > _MAX_VALUE_CHARS:
        text = text[: _MAX_VALUE_CHARS - 3] + "..."
    return text


class NoValue:
    """The value of an error about no value at all, shown as `(label)`: a key that is
    missing, or a place where the document does not read as YAML (None there had read as
    if the user had written null)."""

    def __init__(self, label: str) -> None:
        self.label = label

    def __repr__(self) -> str:
        return f"({self.label})"


#: a required key or section that is not there
MISSING = NoValue("missing")
#: where the document does not read as YAML (malformed, duplicate key, not UTF-8, ...)
NOT_READ = NoValue("not read")


class SpecError(ValueError):
    """A spec that is malformed or physically impossible."""

    def __init__(
        self,
        path: str,
        value: object,
        problem: str,
        allowed: str = "",
        source: str = "",
        line: int | None = None,
    ) -> None:
        self.path = path
        self.value = value
        self.problem = " ".join(problem.split())
        self.allowed = " ".join(allowed.split())
        self.source = source
        self.line = line
        where = source
        if line is not None:
            where = f"{source}:{line}" if source else f"line {line}"
        head = f"{where}: " if where else ""
        text = f"{head}{path} = {show_value(value)}: {self.problem}"
        if self.allowed:
            text += f" (allowed: {self.allowed})"
        super().__init__(text)


class MultiSpecError(SpecError):
    """Every error found in one spec. Behaves as its first error (path, value, ...) for
    callers that handle one; its text is one line per error, in the order found (the
    spec's sections top down, then the sources)."""

    def __init__(self, errors: Sequence[SpecError]) -> None:
        if not errors:
            raise ValueError("MultiSpecError needs at least one error")
        ordered = list(errors)
        first = ordered[0]
        super().__init__(
            first.path, first.value, first.problem, first.allowed, first.source, first.line
        )
        self.errors: tuple[SpecError, ...] = tuple(ordered)
        self.args = ("\n".join(str(e) for e in ordered),)

    def __str__(self) -> str:
        return str(self.args[0])


class DerivationError(RuntimeError):
    """The symbolic derivation failed to reach a result it must reach."""


class ExitCode(IntEnum):
    """Exit status of every bldc-codegen command (README, `bldc-codegen --help`)."""

    OK = 0
    #: A check ran and failed: verify or Unity found a wrong output, a bench target missed.
    CHECK_FAILED = 1
    #: The command line is wrong (argparse's own convention).
    USAGE = 2
    #: The spec is invalid (every error listed, one per line), or no design meets it.
    SPEC = 3
    #: generated/<name> was not generated from this spec: regenerate first.
    STALE = 4
    #: Something outside the spec is in the way: an output folder that cannot be written,
    #: a missing or failing external tool (compiler, qemu).
    ENVIRONMENT = 5
    #: A bug in bldc-codegen (an unexpected exception); the message says where.
    INTERNAL = 70
    #: Ctrl-C: one line, `interrupted` (the shell's 128 + SIGINT).
    INTERRUPTED = 130


def internal_error_line(exc: BaseException, root: Path) -> str:
    """One line for an unexpected exception: what it is and where in our code it was
    raised (the innermost frame under `root`), never a bare traceback."""
    where = ""
    for frame in reversed(traceback.extract_tb(exc.__traceback__)):
        try:
            rel = Path(frame.filename).resolve().relative_to(root)
        except ValueError:
            continue
        where = f" at {rel.as_posix()}:{frame.lineno} in {frame.name}()"
        break
    text = " ".join(str(exc).split())
    if len(text) > 200:
        text = text[:197] + "..."
    detail = f"{type(exc).__name__}: {text}" if text else type(exc).__name__
    return (
        f"internal error (a bug in bldc-codegen, not in your spec): {detail}{where};"
        " run with --traceback for the full traceback"
    )

"""Errors the toolchain reports to its user.

A SpecError always names the key path, the offending value, the unit and the allowed
range, so that a user can fix the YAML without reading the loader.
"""

from __future__ import annotations


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
        self.problem = problem
        self.allowed = allowed
        self.source = source
        self.line = line
        where = source
        if line is not None:
            where = f"{source}:{line}" if source else f"line {line}"
        head = f"{where}: " if where else ""
        text = f"{head}{path} = {value!r}: {problem}"
        if allowed:
            text += f" (allowed: {allowed})"
        super().__init__(text)


class DerivationError(RuntimeError):
    """The symbolic derivation failed to reach a result it must reach."""

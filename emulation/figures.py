"""One measured figure of `make bench`, with its target and verdict.

A figure without a target is reported as such ("no target"), never as met. The bench
exits non-zero when any figure misses its target (unless asked only to report).
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass


@dataclass(frozen=True)
class Figure:
    name: str
    value: float
    unit: str
    target: float | None = None  # an upper bound, inclusive
    detail: str = ""
    decimals: int = 0

    @property
    def meets(self) -> bool | None:
        return None if self.target is None else self.value <= self.target

    def _number(self, value: float) -> str:
        return f"{value:.{self.decimals}f}"

    def line(self) -> str:
        if self.target is None:
            verdict = "(no target)"
        else:
            verdict = (
                f"(target <= {self._number(self.target)}) -> {'meets' if self.meets else 'MISSES'}"
            )
        detail = f"; {self.detail}" if self.detail else ""
        return f"{self.name}: {self._number(self.value)} {self.unit} {verdict}{detail}"


def misses(figures: Iterable[Figure]) -> list[Figure]:
    return [f for f in figures if f.meets is False]

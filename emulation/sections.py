"""The sections `make bench` (`python -m emulation`, `bldc-codegen bench`) can run: a
module of its own, so that the CLI checks `--only` without importing the bench."""

from __future__ import annotations

SECTIONS = ("size", "handlers", "placement", "peers", "rule", "reciprocal", "times", "pil")


def unknown_sections(only: str) -> list[str]:
    """The names of a comma-separated `--only` that are no section (an empty one too)."""
    return sorted(set(only.split(",")) - set(SECTIONS))

"""Session-wide reporting: the spec fuzzer's outcome counts (tests/test_spec_fuzz.py)."""

from __future__ import annotations

import sys

import pytest


def pytest_terminal_summary(terminalreporter: pytest.TerminalReporter) -> None:
    fuzz = sys.modules.get("test_spec_fuzz")
    counts = getattr(fuzz, "COUNTS", None)
    if not counts:
        return
    terminalreporter.section("spec fuzzing")
    for name, count in sorted(counts.items()):
        terminalreporter.write_line(f"{name}: {count}")

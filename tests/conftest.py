"""Session-wide: green means it ran, the spec fuzzer's outcome counts, and the long
tests first.

A skipped test fails the session unless it is on the allow-list below, with its reason:
a missing tool (a compiler, qemu, chromium, the paper) must make `make test` fail, never
pass quietly.
"""

from __future__ import annotations

import sys

import pytest

#: nodeid prefix -> why a skip there is acceptable
ALLOWED_SKIPS: dict[str, str] = {}

_skipped: list[tuple[str, str]] = []


def pytest_collection_modifyitems(items: list[pytest.Item]) -> None:
    """The tests marked `heavy` (a Frama-C proof, a user's whole journey, a motor braking
    in the loop: 10-50 s each) are queued first, in their order, so none of them starts
    when the rest of the suite is done and leaves the other core idle."""
    items.sort(key=lambda item: item.get_closest_marker("heavy") is None)


def pytest_runtest_logreport(report: pytest.TestReport) -> None:
    if report.skipped and not hasattr(report, "wasxfail"):
        reason = (
            str(report.longrepr[-1]) if isinstance(report.longrepr, tuple) else str(report.longrepr)
        )
        if not any(report.nodeid.startswith(prefix) for prefix in ALLOWED_SKIPS):
            _skipped.append((report.nodeid, reason))


def pytest_sessionfinish(session: pytest.Session, exitstatus: int) -> None:
    if _skipped and exitstatus == 0:
        session.exitstatus = pytest.ExitCode.TESTS_FAILED


def pytest_terminal_summary(terminalreporter: pytest.TerminalReporter) -> None:
    if _skipped:
        terminalreporter.section("skipped tests fail the run (tests/conftest.py)", red=True)
        for nodeid, reason in _skipped:
            terminalreporter.write_line(f"{nodeid}: {reason}")
    fuzz = sys.modules.get("test_spec_fuzz")
    counts = getattr(fuzz, "COUNTS", None)
    if counts:
        terminalreporter.section("spec fuzzing")
        for name, count in sorted(counts.items()):
            terminalreporter.write_line(f"{name}: {count}")

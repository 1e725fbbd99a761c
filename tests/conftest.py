"""Session-wide: green means it ran, the spec fuzzer's outcome counts, and the long
tests first, spread so the workers finish together.

A skipped test fails the session unless it is on the allow-list below, with its reason:
a missing tool (a compiler, qemu, chromium, the paper) must make `make test` fail, never
pass quietly.
"""

from __future__ import annotations

import itertools
import os
import sys
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import TypeVar

import pytest

T = TypeVar("T")
#: pytester, for the tests of the queue order (test_scheduling.py)
pytest_plugins = ["pytester"]

#: nodeid prefix -> why a skip there is acceptable
ALLOWED_SKIPS: dict[str, str] = {}

_skipped: list[tuple[str, str]] = []


def heavy_unit(item: pytest.Item) -> tuple[str, float] | None:
    """The unit a `heavy(seconds=N)` test is queued in, and its cost: the test alone,
    or its whole module when the module carries the mark (its tests share module-scoped
    fixtures, so they stay together on one worker)."""
    for node, mark in item.iter_markers_with_node("heavy"):
        seconds = mark.kwargs.get("seconds")
        if not isinstance(seconds, int | float) or seconds <= 0:
            raise pytest.UsageError(
                f"{item.nodeid}: heavy needs seconds=N (its CPU seconds on 2 cores), "
                f"got {seconds!r}"
            )
        key = node.nodeid if isinstance(node, pytest.Module) else item.nodeid
        return key, float(seconds)
    return None


def chunk_sizes(count: int, workers: int) -> list[int]:
    """How pytest-xdist's work stealing first deals `count` tests to `workers` idle
    workers: each takes the next len(pending) // (workers left) from the front."""
    sizes = []
    left = count
    for remaining in range(workers, 0, -1):
        sizes.append(left // remaining)
        left -= sizes[-1]
    return sizes


def deal(
    items: Sequence[T], unit_of: Callable[[T], tuple[str, float] | None], workers: int
) -> list[T]:
    """`items` reordered for `workers` workers: the long units (`unit_of` gives an
    item's unit and the unit's cost, None for a short test) longest first, each onto the
    worker with the least so far; each worker's chunk of the queue begins with its long
    units, and the short tests fill the chunks in their order."""
    units: dict[str, list[T]] = {}
    cost: dict[str, float] = {}
    light: list[T] = []
    for item in items:
        unit = unit_of(item)
        if unit is None:
            light.append(item)
            continue
        units.setdefault(unit[0], []).append(item)
        cost[unit[0]] = unit[1]
    sizes = chunk_sizes(len(items), max(1, workers))
    shares: list[list[T]] = [[] for _ in sizes]
    loads = [0.0 for _ in sizes]
    for key in sorted(units, key=lambda k: -cost[k]):  # stable: ties in collection order
        k = loads.index(min(loads))
        shares[k].extend(units[key])
        loads[k] += cost[key]
    if any(len(share) > size for share, size in zip(shares, sizes, strict=True)):
        shares = [[i for share in shares for i in share]]  # too few tests to deal out
        sizes = [len(items)]
    ordered: list[T] = []
    rest = iter(light)
    for share, size in zip(shares, sizes, strict=True):
        ordered.extend(share)
        ordered.extend(itertools.islice(rest, size - len(share)))
    ordered.extend(rest)
    return ordered


def pytest_collection_modifyitems(items: list[pytest.Item]) -> None:
    """The tests marked `heavy(seconds=N)` (a Frama-C proof, a user's whole journey, a
    motor braking in the loop: 5-45 s each) start first, longest first, spread over the
    workers so that each gets the same total (`deal`); every other test follows in
    collection order. Work stealing deals the queue out in contiguous chunks, one per
    worker (`chunk_sizes`), so each chunk begins with its worker's share of the long
    tests; a worker that runs out takes the tail of another's queue, short tests, and
    no long test is left to start when the rest of the suite is done. The order is the
    same in every worker (xdist requires it); without xdist it is the long tests,
    longest first, then the rest."""
    items[:] = deal(items, heavy_unit, int(os.environ.get("PYTEST_XDIST_WORKER_COUNT", "1")))


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


@pytest.fixture
def generate_and_verify(tmp_path: Path) -> Callable[..., tuple[object, object, Path]]:
    """`generate` a spec into tmp_path/<folder> and `verify` it there (no progress bars):
    (VerifyResult, Oracle, the generated folder). Small point counts by default: the
    tests that call it each hold one motor to the spec's targets."""

    def run(
        spec: Path,
        *,
        seed: int,
        random_count: int = 500,
        stride: int = 9,
        folder: str = "generated",
    ) -> tuple[object, object, Path]:
        from codegen.generate import render_all, write_tree
        from verify.run import verify

        generated = tmp_path / folder
        write_tree(render_all(spec).files, generated)
        result, _, _, o = verify(
            spec,
            generated,
            tmp_path / f"build-{folder}",
            seed=seed,
            random_count=random_count,
            exhaustive_stride=stride,
            show_progress=False,
        )
        return result, o, generated

    return run


@pytest.fixture
def gone_pid() -> str:
    """The process id of a process that has ended (a run killed with its staging
    folder left behind)."""
    import subprocess

    done = subprocess.run(
        [sys.executable, "-c", "import os; print(os.getpid())"],
        capture_output=True,
        text=True,
        check=True,
    )
    return done.stdout.strip()


def without_tolerances(text: str) -> str:
    """A spec's YAML text with its `tolerances` section (and that key's source) taken out:
    the nominal motor alone."""
    start = text.index("\ntolerances:\n")
    end = text.index("\n\n", start + 1)
    text = text[:start] + text[end:]
    return "".join(line for line in text.splitlines(keepends=True) if "  tolerances:" not in line)

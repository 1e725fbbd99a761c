"""What the two fuzzers share (tests/test_spec_fuzz.py, tests/fuzz_hostile.py): a wall-clock
limit on one case, so that a hang fails instead of stalling the run. Imported from tests/
(pytest puts the folder on sys.path; the fuzzer run as a script has it there too)."""

from __future__ import annotations

import contextlib
import signal
from collections.abc import Iterator


@contextlib.contextmanager
def time_limit(seconds: float) -> Iterator[None]:
    """Raise TimeoutError in the case if it runs longer than `seconds` (a hang fails)."""

    def expire(*_: object) -> None:
        raise TimeoutError(f"case ran longer than {seconds} s")

    previous = signal.signal(signal.SIGALRM, expire)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)

"""Ctrl-C across native code that calls back into Python.

Unicorn runs its hooks as ctypes callbacks and CasADi checks for signals inside its
solvers: a KeyboardInterrupt raised there is printed and dropped ("Exception ignored on
calling ctypes callback function", "rhsQB failed: KeyboardInterrupt") and the native
call goes on, so `bench` and `simulate` ran to their end after a Ctrl-C and exited 0,
`simulate` once publishing an integration the interrupt had cut short. Inside
`interrupts_noted()` SIGINT is noted instead of raised; `raise_noted()`, called once the
native call has returned, raises it, and so does the block's end if nothing did.

Pure Python can drop one too: distributed's garbage-collector callback (in every process
with a Dask client) runs at any allocation, and a KeyboardInterrupt raised while it runs
is printed ("Exception ignored in: <bound method GCDiagnosis._gc_callback ...>") and
lost; `robustness` then ran its campaign to the end, published its report and exited 0.
Inside `interrupts_kept()` SIGINT raises as Python's default does and is noted too: a
dropped one is raised again at the next `raise_noted()`, and at the block's end.
"""

from __future__ import annotations

import contextlib
import signal
import sys
import threading
from collections.abc import Callable, Iterator

from codegen.errors import ExitCode

#: SIGINTs noted inside `interrupts_noted` and not yet raised
_noted: list[int] = []


def _note(signum: int, _frame: object) -> None:
    _noted.append(signum)


def _note_and_raise(signum: int, _frame: object) -> None:
    _noted.append(signum)
    raise KeyboardInterrupt


def raise_noted() -> None:
    """Raise KeyboardInterrupt if a SIGINT was noted (then forget it); cheap otherwise."""
    if _noted:
        _noted.clear()
        raise KeyboardInterrupt


@contextlib.contextmanager
def _sigint_handled_by(handler: Callable[[int, object], None]) -> Iterator[None]:
    """`handler` takes SIGINT in the block; a KeyboardInterrupt that leaves the block
    forgets what was noted (it got through), and one noted and not raised is raised at
    the block's end. Outside the main thread handlers cannot be set and the block runs
    as it is."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = signal.signal(signal.SIGINT, handler)
    try:
        yield
    except KeyboardInterrupt:
        _noted.clear()
        raise
    finally:
        signal.signal(signal.SIGINT, previous)
    raise_noted()


def interrupts_noted() -> contextlib.AbstractContextManager[None]:
    """SIGINT noted, not raised, in the block (see the module's doc)."""
    return _sigint_handled_by(_note)


def interrupts_kept() -> contextlib.AbstractContextManager[None]:
    """SIGINT raised and noted in the block (see the module's doc): a KeyboardInterrupt
    that something swallowed is raised again at `raise_noted()` or the block's end."""
    return _sigint_handled_by(_note_and_raise)


def exit_status(main: Callable[[], int]) -> int:
    """`main()`'s status, or 130 after one line on stderr if Ctrl-C ended it: what
    `bldc-codegen` gives, for the modules make runs directly (`python -m emulation`
    printed a traceback ending in unicorn's mem_read)."""
    try:
        return main()
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return int(ExitCode.INTERRUPTED)

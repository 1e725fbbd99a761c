"""Progress bars for the bench's long loops, on stderr (results go to stdout).

`make bench` turns them on when stderr is a terminal; `--no-progress` or a pipe keeps
them off, so logs and tests stay clean.
"""

from __future__ import annotations

import sys
from collections.abc import Iterable, Iterator
from typing import TypeVar

from tqdm import tqdm

T = TypeVar("T")

enabled = False


def progress(items: Iterable[T], label: str, total: int | None = None) -> Iterator[T]:
    yield from tqdm(
        items, desc=label, total=total, file=sys.stderr, leave=False, disable=not enabled
    )

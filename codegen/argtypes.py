"""argparse types for the command lines' numeric options: a bad value is one usage line
naming the option, the value and the allowed range, never a traceback further in."""

from __future__ import annotations

import argparse
import re
from collections.abc import Callable

#: a decimal number as the spec writes one: ASCII digits, no digit groups (Python's
#: int() and float() also take '1_000' and other scripts' digits, '١٢', which the spec
#: refuses)
_WHOLE = re.compile(r"[+-]?[0-9]+")
_DECIMAL = re.compile(r"[+-]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]+)?")


def plain_decimal(text: str) -> bool:
    """Whether `text` is a decimal number in ASCII, as a spec writes one."""
    return _DECIMAL.fullmatch(text.strip()) is not None


def whole_number(low: int, high: int) -> Callable[[str], int]:
    """A whole number in [low, high]."""

    def parse(text: str) -> int:
        if _WHOLE.fullmatch(text.strip()) is None:
            raise argparse.ArgumentTypeError(
                f"{text!r} is not a whole number (ASCII digits, no '_')"
            )
        value = int(text, 10)
        if not low <= value <= high:
            raise argparse.ArgumentTypeError(f"{value} is out of range (allowed: [{low}, {high}])")
        return value

    parse.__name__ = "whole number"
    return parse


#: a random generator's seed (NumPy takes any non-negative integer; 32 bits replays)
SEED = whole_number(0, 2**32 - 1)
#: a count of random points
POINTS = whole_number(0, 10**8)


def decimal_number(low: float, high: float) -> Callable[[str], float]:
    """A finite number in [low, high]."""

    def parse(text: str) -> float:
        if not plain_decimal(text):
            raise argparse.ArgumentTypeError(f"{text!r} is not a number (ASCII digits, no '_')")
        value = float(text)
        if not low <= value <= high:  # NaN fails both comparisons
            raise argparse.ArgumentTypeError(
                f"{text} is out of range (allowed: [{low:g}, {high:g}])"
            )
        return value

    parse.__name__ = "number"
    return parse


def path_text(text: str) -> str:
    """A path given on the command line: not empty. `-o "$OUT"` with OUT unset passed
    '' and the command wrote to its default folder instead, as if -o had not been given."""
    if not text:
        raise argparse.ArgumentTypeError(
            f"{text!r} is an empty path (an unset shell variable?): give a path or leave"
            " the option out"
        )
    return text


path_text.__name__ = "path"

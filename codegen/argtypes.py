"""argparse types for the command lines' numeric options: a bad value is one usage line
naming the option, the value and the allowed range, never a traceback further in."""

from __future__ import annotations

import argparse
import re
from collections.abc import Callable

from codegen.errors import clipped, show_value

#: a decimal number as the spec writes one: ASCII digits, no digit groups (Python's
#: int() and float() also take '1_000' and other scripts' digits, '١٢', which the spec
#: refuses), and as many digits as a spec quantity takes (codegen.units): an exponent of
#: unbounded digits, '1e9999999', had init's exact Fraction arithmetic run for ever, and
#: more than 4300 digits were int()'s ValueError, argparse's 'invalid _kv value: ...'
#: echoing every digit
_WHOLE = re.compile(r"[+-]?[0-9]+", re.ASCII)
_DECIMAL = re.compile(
    r"[+-]?(?:[0-9]{1,30}\.?[0-9]{0,30}|\.[0-9]{1,30})(?:[eE][+-]?[0-9]{1,3})?", re.ASCII
)
#: how a number given on the command line is written, for the refusal of one that is not
DECIMAL_FORM = (
    "ASCII digits, no '_') of at most 30 digits before and after the point and an"
    " exponent of at most 3 digits"
)


def plain_decimal(text: str) -> bool:
    """Whether `text` is a decimal number in ASCII, as a spec writes one."""
    return _DECIMAL.fullmatch(text.strip()) is not None


def not_a_number(text: str, unit: str = "") -> argparse.ArgumentTypeError:
    """The refusal of `text` where a decimal number (of `unit`) was expected, the value
    clipped."""
    of_unit = f", in {unit}" if unit else ""
    return argparse.ArgumentTypeError(
        f"{show_value(text)} is not a number ({DECIMAL_FORM}{of_unit}"
    )


def _whole_in(text: str, low: int, high: int) -> int | None:
    """`text` as a whole number in [low, high], or None where it is out of range.
    Counts the digits before int() converts them: a value of more than 4300 digits is
    int()'s ValueError, and one beyond the bounds' digits is out of range anyway."""
    digits = text.strip().lstrip("+-").lstrip("0")
    if len(digits) > max(len(str(abs(low))), len(str(abs(high)))):
        return None
    value = int(text, 10)
    return value if low <= value <= high else None


def whole_number(low: int, high: int) -> Callable[[str], int]:
    """A whole number in [low, high]."""

    def parse(text: str) -> int:
        if _WHOLE.fullmatch(text.strip()) is None:
            raise argparse.ArgumentTypeError(
                f"{show_value(text)} is not a whole number (ASCII digits, no '_')"
                f" (allowed: [{low}, {high}])"
            )
        value = _whole_in(text, low, high)
        if value is None:
            raise argparse.ArgumentTypeError(
                f"{clipped(text.strip())} is out of range (allowed: [{low}, {high}])"
            )
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
            raise not_a_number(text)
        value = float(text)
        if not low <= value <= high:  # NaN fails both comparisons
            raise argparse.ArgumentTypeError(
                f"{text.strip()} is out of range (allowed: [{low:g}, {high:g}])"
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

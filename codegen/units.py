"""Physical quantities in the spec: "<number> <unit>" strings converted to SI.

The spec is written by motor engineers in datasheet units (mH, V/krpm, kHz), so the
loader accepts a short, explicit list of units per dimension and converts once to SI.
Anything else is an error that lists what is accepted; nothing is guessed.
"""

from __future__ import annotations

import difflib
import math
import re
from dataclasses import dataclass
from fractions import Fraction

from codegen.yaml12 import type_name

# ASCII digits only: Python's \d and int() also accept other scripts' digits, and a
# spec that reads "٢٤ V" as 24 V is not what its author can see at a glance.
_NUMBER = r"[-+]?(?:[0-9]{1,30}\.?[0-9]{0,30}|\.[0-9]{1,30})(?:[eE][-+]?[0-9]{1,3})?"
#: What reads as the number: every character a number could continue with (no unit
#: starts with one), so that '1e999999 V' or '2_4 V' is a bad number, not a bad unit.
_TOKEN = r"[-+]?[0-9.][0-9._/eE+-]*"
_QUANTITY = re.compile(rf"^[ \t]*(?P<number>{_TOKEN})[ \t]*(?P<unit>\S.*?)?[ \t]*$", re.ASCII)
_NUMBER_ONLY = re.compile(rf"{_NUMBER}\Z", re.ASCII)
_MAX_QUANTITY_CHARS = 80

_RPM_PER_RAD_S = 60.0 / (2.0 * math.pi)

#: Numbers as people write them that the pattern above splits into a number and a
#: "unit" (`0,56 mH` read as 0 and the unit ',56 mH'), and what to write instead.
_DECIMAL_COMMA = re.compile(
    r"[ \t]*(?P<int>[-+]?[0-9][0-9.]*),(?P<frac>[0-9]+)(?P<exp>[eE][-+]?[0-9]+)?[ \t]*"
    r"(?P<unit>.*)\Z"
)
_GROUPED = re.compile(r"[ \t]*[-+]?[0-9]{1,3}(?:[,' \u00a0\u2009\u202f][0-9]{3})+(?:[.,][0-9]+)?")
_NOT_ASCII_MINUS = "\u2212\u2010\u2011\u2012\u2013\u2014\ufe63\uff0d"
_RADIX = re.compile(r"[ \t]*[-+]?0[xXoObB][0-9a-fA-F]")


def misread_number(raw: str) -> str | None:
    """Why `raw` does not start with a number its author meant, if it is one of the
    usual ways (decimal comma, digit groups, a typographic minus, hex); else None."""
    if match := _DECIMAL_COMMA.match(raw):
        whole, fraction = match.group("int"), match.group("frac")
        exponent = match.group("exp") or ""  # 2,4e1 V: the exponent stays with the number
        unit = f"{exponent} {match.group('unit').strip()}".rstrip()
        if "." in whole:
            return "a comma in the number: write it with a decimal point and no separators"
        if len(fraction) == 3:  # 1,000: a thousand, or one with a decimal comma
            return (
                f"a comma in the number: write '{whole}{fraction}{unit}' (thousands)"
                f" or '{whole}.{fraction}{unit}' (decimal comma)"
            )
        return f"a decimal comma: write '{whole}.{fraction}{unit}'"
    if _GROUPED.match(raw):
        return "digits in groups: write the number without separators, e.g. '1000'"
    first = raw.lstrip(" \t")[:1]
    if first and first in _NOT_ASCII_MINUS:
        return f"'{first}' (U+{ord(first):04X}) is not a minus sign: use '-'"
    if _RADIX.match(raw):
        return "a number in another base: write it in decimal"
    return None


@dataclass(frozen=True)
class Dimension:
    """A physical dimension: its SI unit and the spellings the spec may use."""

    name: str
    si_unit: str
    #: (spelling, exact factor to the SI unit as a decimal string)
    scales: tuple[tuple[str, str], ...]

    @property
    def a_name(self) -> str:
        """The name with its indefinite article: 'an inductance', 'a voltage'."""
        return f"{'an' if self.name[0] in 'aeiou' else 'a'} {self.name}"

    def accepted(self) -> str:
        return ", ".join(unit for unit, _ in self.scales)

    def scale(self, unit: str) -> Fraction | None:
        for known, factor in self.scales:
            if known == unit:
                return Fraction(factor)
        return None

    def suggest(self, unit: str) -> str | None:
        """The accepted spelling a typo most likely meant: the ASCII spelling of the
        same unit (`µH` -> `uH`, `mΩ` -> `mohm`, `kg·m²` -> `kg*m^2`), the same letters
        in another case (`mh` -> `mH`, never guessing between mV and MV), else the
        closest one."""
        spellings = [known for known, _ in self.scales]
        ascii_unit = "".join(_ASCII_SPELLING.get(char, char) for char in unit).strip()
        if ascii_unit != unit and ascii_unit in spellings:
            return ascii_unit
        unit = ascii_unit
        # a prefix the spec does not take (`kohm`, `Mohm`, `nH`, `MV`) names a scale: a
        # spelling of another scale is no typo of it (`kohm` was answered 'ohm', a
        # factor of 1000; `MV` 'mV', of 1e9)
        meant = self._prefixed_scales(unit)
        if meant:
            spellings = [k for k in spellings if self.scale(k) in meant]
        same_letters = [known for known in spellings if known.lower() == unit.lower()]
        if len(same_letters) == 1:
            return same_letters[0]
        close = difflib.get_close_matches(unit, spellings, n=1, cutoff=0.6)
        return close[0] if close else None

    def _prefixed_scales(self, unit: str) -> set[Fraction]:
        """The scales `unit` reads as, an SI prefix (case as written) on a spelling of
        scale 1 (its letters in any case); empty where it reads as none."""
        bases = [known for known, factor in self.scales if Fraction(factor) == 1]
        # `K` is no SI prefix, but a datasheet's `Kohm` means kilo: read as no prefix it
        # was answered 'ohm', a factor of 1000 (a helper's hunt)
        prefixes = {**_SI_PREFIXES, "K": _SI_PREFIXES["k"]}
        return {
            Fraction(factor)
            for prefix, factor in prefixes.items()
            for base in bases
            if unit.startswith(prefix) and unit[len(prefix) :].lower() == base.lower()
        }


#: SI prefixes as a unit is written with them (micro as `u`), and their factors
_SI_PREFIXES = {
    "": "1",
    "p": "1e-12",
    "n": "1e-9",
    "u": "1e-6",
    "m": "1e-3",
    "k": "1e3",
    "M": "1e6",
    "G": "1e9",
}


#: Unicode spellings of unit symbols and their ASCII ones in the spec's units (a
#: datasheet's `µH` or `Ω` was answered "did you mean 'H'?", or nothing).
_ASCII_SPELLING = {
    "\u00b5": "u",  # MICRO SIGN
    "\u03bc": "u",  # GREEK SMALL LETTER MU
    "\u2126": "ohm",  # OHM SIGN
    "\u03a9": "ohm",  # GREEK CAPITAL LETTER OMEGA
    "\u00b7": "*",  # MIDDLE DOT
    "\u22c5": "*",  # DOT OPERATOR
    "\u00d7": "*",  # MULTIPLICATION SIGN
    "\u00b2": "^2",  # SUPERSCRIPT TWO
    "\u2215": "/",  # DIVISION SLASH
    "\u00a0": " ",  # NO-BREAK SPACE
    "\u2009": " ",  # THIN SPACE
    "\u202f": " ",  # NARROW NO-BREAK SPACE
}

VOLTAGE = Dimension("voltage", "V", (("V", "1.0"), ("mV", "1e-3"), ("kV", "1e3")))
RESISTANCE = Dimension(
    "resistance", "ohm", (("ohm", "1.0"), ("Ohm", "1.0"), ("mohm", "1e-3"), ("mOhm", "1e-3"))
)
INDUCTANCE = Dimension("inductance", "H", (("H", "1.0"), ("mH", "1e-3"), ("uH", "1e-6")))
# Back-EMF constant in SI is V per (mechanical) rpm here, because the paper writes
# E = k_e n with n in rpm.
EMF_CONSTANT = Dimension(
    "back-EMF constant",
    "V/rpm",
    (
        ("V/krpm", "1e-3"),
        ("V/rpm", "1.0"),
        ("mV/rpm", "1e-3"),
        ("V*s/rad", repr(1.0 / _RPM_PER_RAD_S)),
    ),
)
INERTIA = Dimension(
    "moment of inertia",
    "kg*m^2",
    (("kg*m^2", "1.0"), ("kg*cm^2", "1e-4"), ("g*cm^2", "1e-7")),
)
#: Viscous friction torque per mechanical angular speed.
VISCOUS_FRICTION = Dimension(
    "viscous friction",
    "N*m*s/rad",
    (("N*m*s/rad", "1.0"), ("mN*m*s/rad", "1e-3"), ("uN*m*s/rad", "1e-6")),
)
FREQUENCY = Dimension("frequency", "Hz", (("Hz", "1.0"), ("kHz", "1e3"), ("MHz", "1e6")))
TIME = Dimension("time", "s", (("s", "1.0"), ("ms", "1e-3"), ("us", "1e-6"), ("ns", "1e-9")))
CURRENT = Dimension("current", "A", (("A", "1.0"), ("mA", "1e-3")))
SPEED = Dimension("speed", "rpm", (("rpm", "1.0"), ("krpm", "1e3")))
TRANSRESISTANCE = Dimension("current-sense gain", "V/A", (("V/A", "1.0"), ("mV/A", "1e-3")))


@dataclass(frozen=True)
class ParsedQuantity:
    #: Exact SI value: decimal spec numbers stay exact, so the symbolic model sees
    #: 0.56 mH as 7/12500 H, not as the nearest binary double.
    si_value: Fraction
    unit: str


class QuantityError(ValueError):
    """A quantity string that cannot be read; the loader adds the key path."""


def parse_quantity(raw: object, dimension: Dimension) -> ParsedQuantity:
    """Read "<number> <unit>" and convert it to the dimension's SI unit."""
    if isinstance(raw, bool) or not isinstance(raw, (str, int, float)):
        raise QuantityError(
            f"expected {dimension.a_name} such as '1.5 {dimension.scales[0][0]}', "
            f"got {type_name(raw)}"
        )
    if isinstance(raw, float) and not math.isfinite(raw):
        # not "write e.g. 'nan Hz'"
        raise QuantityError(
            f"expected {dimension.a_name}: a finite number and a unit such as"
            f" '1.5 {dimension.scales[0][0]}' (units: {dimension.accepted()})"
        )
    if isinstance(raw, (int, float)):
        raise QuantityError(
            f"missing unit for {dimension.a_name}; write e.g. '{raw} {dimension.scales[0][0]}' "
            f"(units: {dimension.accepted()})"
        )
    if len(raw) > _MAX_QUANTITY_CHARS:
        raise QuantityError(
            f"{dimension.a_name} of {len(raw)} characters is not a number and a unit"
        )
    match = _QUANTITY.match(raw)
    misread = misread_number(raw)
    if misread is not None and (
        match is None or dimension.scale(match.group("unit") or "") is None
    ):
        raise QuantityError(f"{misread} (units: {dimension.accepted()})")
    if match is None:
        raise QuantityError(
            f"not a number (ASCII digits) followed by a unit (units: {dimension.accepted()})"
        )
    if _NUMBER_ONLY.match(match.group("number")) is None:
        raise QuantityError(
            f"'{match.group('number')}' is not a decimal number (ASCII digits, at most 30"
            f" before and after the point, an exponent of at most 3 digits; no '_' or '/')"
            f" (units: {dimension.accepted()})"
        )
    unit = match.group("unit")
    if unit is None:
        raise QuantityError(f"missing unit for {dimension.a_name} (units: {dimension.accepted()})")
    factor = dimension.scale(unit)
    if factor is None:
        guess = dimension.suggest(unit)
        hint = f"; did you mean '{guess}'?" if guess else ""
        raise QuantityError(
            f"unit '{unit}' is not {dimension.a_name} unit{hint} (units: {dimension.accepted()})"
        )
    number = Fraction(match.group("number"))
    return ParsedQuantity(si_value=number * factor, unit=unit)

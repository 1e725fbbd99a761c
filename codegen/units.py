"""Physical quantities in the spec: "<number> <unit>" strings converted to SI.

The spec is written by motor engineers in datasheet units (mH, V/krpm, kHz), so the
loader accepts a short, explicit list of units per dimension and converts once to SI.
Anything else is an error that lists what is accepted; nothing is guessed.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from fractions import Fraction

_NUMBER = r"[-+]?(?:\d{1,30}\.?\d{0,30}|\.\d{1,30})(?:[eE][-+]?\d{1,3})?"
_QUANTITY = re.compile(rf"^\s*(?P<number>{_NUMBER})\s*(?P<unit>\S.*?)?\s*$")

_RPM_PER_RAD_S = 60.0 / (2.0 * math.pi)


@dataclass(frozen=True)
class Dimension:
    """A physical dimension: its SI unit and the spellings the spec may use."""

    name: str
    si_unit: str
    #: (spelling, exact factor to the SI unit as a decimal string)
    scales: tuple[tuple[str, str], ...]

    def accepted(self) -> str:
        return ", ".join(unit for unit, _ in self.scales)

    def scale(self, unit: str) -> Fraction | None:
        for known, factor in self.scales:
            if known == unit:
                return Fraction(factor)
        return None


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
            f"expected a {dimension.name} such as '1.5 {dimension.scales[0][0]}', "
            f"got a {type(raw).__name__}"
        )
    if isinstance(raw, (int, float)):
        raise QuantityError(
            f"missing unit for a {dimension.name}; write e.g. '{raw} {dimension.scales[0][0]}' "
            f"(units: {dimension.accepted()})"
        )
    match = _QUANTITY.match(raw)
    if match is None:
        raise QuantityError(f"not a number followed by a unit (units: {dimension.accepted()})")
    unit = match.group("unit")
    if unit is None:
        raise QuantityError(f"missing unit for a {dimension.name} (units: {dimension.accepted()})")
    factor = dimension.scale(unit)
    if factor is None:
        raise QuantityError(
            f"unit '{unit}' is not a {dimension.name} unit (units: {dimension.accepted()})"
        )
    number = Fraction(match.group("number"))
    return ParsedQuantity(si_value=number * factor, unit=unit)

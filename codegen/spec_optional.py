"""The spec's two optional entries, parsed and checked (called by `spec_loader`).

* `motor.back_emf_shape`: the phase back-EMF waveform. Either `flat`, the paper's
  idealisation (section 3.2: the EMFs keep their edge values +E, -E, -E through the
  commutation), or a flat-top width,
  `"<w> deg"` in electrical degrees with 0 < w < 180 (120 deg is the paper's ideal
  trapezoid, the default), or a measured table: a list of `[angle_deg, e_per_unit]`
  pairs over the half period from the phase's rising zero crossing, angles rising
  from 0 to 180, e = 0 at both ends, e in units of E = k_e n (the spec's constant is
  the flat-top value, so a measured table's flat part sits at 1).
* `tolerances`: how far the real drive may sit from the nominal values, each a pair
  `[low %, high %]` of plain numbers (for example `phase_resistance: [-10, 40]` for
  a winding that is up to 40 % hotter), for `phase_resistance`, `phase_inductance`,
  `back_emf_constant` and `bus_voltage`. The bus pair must keep the bus inside
  [inverter.bus_voltage_min, inverter.bus_voltage_max].

Every error names the key path, the value, the unit and the allowed range.
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable, Mapping
from decimal import Decimal, localcontext
from fractions import Fraction
from functools import lru_cache
from typing import Any, Protocol, TypeVar

from codegen import spec_drive
from codegen.errors import SpecError
from codegen.spec_model import BackEmfShape, Inverter, Tolerances
from codegen.yaml12 import ExactFloat

EMF_SHAPE_KEY = "back_emf_shape"
TOLERANCES_KEY = "tolerances"
TOLERANCE_KEYS = ("phase_resistance", "phase_inductance", "back_emf_constant", "bus_voltage")
#: ASCII digits only (\d also took '١٢٠ deg'), at most 30 before and after the point as
#: in a quantity (codegen.units)
_WIDTH = re.compile(
    r"^\s*(?P<number>[-+]?(?:[0-9]{1,30}\.?[0-9]{0,30}|\.[0-9]{1,30}))\s*(?:deg|°)\s*$", re.ASCII
)
_WIDTH_ALLOWED = (
    "'flat', '<w> deg' with 0 < w < 180 electrical degrees, or a table of [angle_deg, e/E]"
)
#: The most points a measured EMF table may hold (0.05 deg apart over the half period).
TABLE_POINTS_MAX = 3601
_TABLE_ALLOWED = "[[0, 0], ..., [180, 0]]: angles rising from 0 to 180 deg, |e/E| <= 2"
_PERCENT_LOW, _PERCENT_HIGH = -90.0, 400.0
T = TypeVar("T")


class _Errors(Protocol):
    def error(self, path: str, value: object, problem: str, allowed: str = "") -> SpecError: ...

    def attempt(self, read: Callable[[], T]) -> T | None: ...


def _exact(value: object) -> Fraction:
    """A plain number as the exact decimal the spec wrote (a YAML float's ExactFloat.exact:
    a table entry of 17 digits had been rounded to a double, which verify's own reading
    of the spec then told apart)."""
    if isinstance(value, ExactFloat) and value.exact is not None:
        return value.exact
    return Fraction(str(value))


def _digits(value: Fraction, digits: int) -> str:
    """`value` to `digits` significant digits, exactly (a float rounds 24 x (1 -
    0.16666666666666668) to 20)."""
    with localcontext() as context:
        context.prec = digits
        shown = +(Decimal(value.numerator) / Decimal(value.denominator))
    return f"{shown.normalize():f}"


def _apart(value: Fraction, limit: Fraction) -> int:
    """The fewest significant digits, from 4, that show `value` apart from `limit`."""
    for digits in range(4, 40):
        if _digits(value, digits) != _digits(limit, digits):
            return digits
    return 40


def _inward(value: Fraction, up: bool) -> str:
    """`value` with 4 decimals, rounded up (a lower bound) or down (an upper one)."""
    scaled = value * 10_000
    whole = math.ceil(scaled) if up else math.floor(scaled)
    sign = "-" if whole < 0 else ""
    units, tenths = divmod(abs(whole), 10_000)  # exactly: :g kept 6 digits (123.457)
    return f"{sign}{units}.{tenths:04d}".rstrip("0").rstrip(".")


def _plain(value: object) -> bool:
    return (
        not isinstance(value, bool)
        and isinstance(value, (int, float))
        and (not isinstance(value, float) or math.isfinite(value))
    )


@lru_cache(maxsize=64)
def _interned(shape: BackEmfShape) -> BackEmfShape:
    """The first loaded table equal to `shape`: the caches keyed by a shape then meet
    the same object again, not an equal one compared point by point (a spec loaded
    twice: 666 comparisons of a 3001-point table, 7 s)."""
    return shape


def back_emf_shape(r: _Errors, raw: object) -> BackEmfShape:
    """`motor.back_emf_shape` (raw YAML value) -> the checked waveform."""
    path = f"motor.{EMF_SHAPE_KEY}"
    if isinstance(raw, str):
        if raw.strip() == "flat":
            return BackEmfShape.flat()
        match = _WIDTH.match(raw)
        if match is None:
            raise r.error(path, raw, "not a flat-top width in electrical degrees", _WIDTH_ALLOWED)
        width = Fraction(match.group("number"))
        if not 0 < width < 180:
            raise r.error(path, raw, "flat-top width out of range", "0 < w < 180 deg")
        return BackEmfShape.trapezoid(width)
    if not isinstance(raw, list):
        raise r.error(path, raw, "must be a flat-top width or a table", _WIDTH_ALLOWED)
    if len(raw) > TABLE_POINTS_MAX:
        raise r.error(
            path,
            raw,
            f"a table of {len(raw)} points: every command evaluates it at each breakpoint",
            f"3 to {TABLE_POINTS_MAX} points, one every 0.05 deg at the finest (resample a"
            " finer capture)",
        )
    points: list[tuple[Fraction, Fraction]] = []
    for index, item in enumerate(raw):
        where = f"{path}[{index}]"
        if not (isinstance(item, list) and len(item) == 2 and all(_plain(v) for v in item)):
            raise r.error(where, item, "must be a pair [angle_deg, e/E] of numbers", _TABLE_ALLOWED)
        angle, value = _exact(item[0]), _exact(item[1])
        if not 0 <= angle <= 180:
            raise r.error(where, item, "angle outside the half period", "0 <= angle <= 180 deg")
        if abs(value) > 2:
            raise r.error(where, item, "e/E beyond twice the flat-top value", "-2 <= e/E <= 2")
        if points and angle <= points[-1][0]:
            raise r.error(
                where,
                item,
                f"angle not above the previous {float(points[-1][0]):g} deg",
                _TABLE_ALLOWED,
            )
        points.append((angle, value))
    if len(points) < 3 or points[0][0] != 0 or points[-1][0] != 180:
        raise r.error(path, raw, "the table must run from 0 deg to 180 deg", _TABLE_ALLOWED)
    if points[0][1] != 0 or points[-1][1] != 0:
        raise r.error(
            path, raw, "e/E must be 0 at 0 deg and 180 deg (the zero crossings)", _TABLE_ALLOWED
        )
    if max(value for _, value in points) <= 0:
        raise r.error(
            path, raw, "a rising zero crossing needs a positive half period", _TABLE_ALLOWED
        )
    shape = _interned(BackEmfShape(tuple(points), None))
    # a pure triplen shape (e(theta) = e(theta - 120)) has no line-to-line EMF at all:
    # every command divided by its peak (ZeroDivisionError); and a pair whose mean over
    # its conducting sector is not positive drives no braking current
    if spec_drive.line_to_line_peak(shape) == 0 or spec_drive.conducting_line_mean(shape) <= 0:
        raise r.error(
            path,
            raw,
            "no line-to-line EMF to brake with: e_a - e_b (b 120 deg behind) is"
            f" {float(spec_drive.line_to_line_peak(shape)):g} E at its peak and"
            f" {float(2 * spec_drive.conducting_line_mean(shape)):g} E on the conducting"
            " sector's mean",
            f"{_TABLE_ALLOWED}, whose line-to-line EMF is positive on the conducting sector",
        )
    return shape


def tolerances(r: _Errors, raw: object, inverter: Inverter | None) -> Tolerances | None:
    """`tolerances` (raw YAML value) -> relative (low, high) per parameter; None once
    every bad key's error is recorded through `r.attempt`. Each pair is read even when
    the inverter is refused (None), so a bad one is named with its allowed range; only
    the bus pair's check against the inverter's range then waits for a valid inverter."""
    allowed = f"[low %, high %] with {_PERCENT_LOW:g} < low <= high <= {_PERCENT_HIGH:g}"
    if not isinstance(raw, Mapping):
        raise r.error(TOLERANCES_KEY, raw, "must map parameters to [low %, high %]", allowed)
    for key in raw:
        if key not in TOLERANCE_KEYS:
            raise r.error(
                f"{TOLERANCES_KEY}.{key}", raw[key], "unknown key", ", ".join(TOLERANCE_KEYS)
            )

    def pair(key: str) -> tuple[Fraction, Fraction]:
        path = f"{TOLERANCES_KEY}.{key}"
        if key not in raw:
            raise r.error(path, None, "missing required key", allowed)
        item: Any = raw[key]
        if not (isinstance(item, list) and len(item) == 2 and all(_plain(v) for v in item)):
            raise r.error(path, item, "must be a pair [low %, high %] of numbers", allowed)
        low, high = float(item[0]), float(item[1])
        if not _PERCENT_LOW < low <= high <= _PERCENT_HIGH:
            raise r.error(path, item, "percent range empty, inverted or out of range", allowed)
        return (_exact(item[0]) / 100, _exact(item[1]) / 100)

    # every key is read (and every bad one reported) before the section is given up
    read = {key: r.attempt(lambda key=key: pair(key)) for key in TOLERANCE_KEYS}
    pairs = {key: value for key, value in read.items() if value is not None}
    if len(pairs) < len(TOLERANCE_KEYS):
        return None  # each error is recorded
    if inverter is None:
        return None  # the inverter's own error is recorded
    nominal = inverter.bus_voltage_nominal_v
    low_v, high_v = (nominal * (1 + p) for p in pairs["bus_voltage"])
    if low_v < inverter.bus_voltage_min_v or high_v > inverter.bus_voltage_max_v:
        lowest = (inverter.bus_voltage_min_v / nominal - 1) * 100
        highest = (inverter.bus_voltage_max_v / nominal - 1) * 100
        low_at, high_at = (
            _apart(low_v, inverter.bus_voltage_min_v),
            _apart(high_v, inverter.bus_voltage_max_v),
        )
        raise r.error(
            f"{TOLERANCES_KEY}.bus_voltage",
            raw["bus_voltage"],
            f"puts the bus at {_digits(low_v, low_at)}-{_digits(high_v, high_at)} V, outside"
            f" the inverter's {_digits(inverter.bus_voltage_min_v, low_at)}-"
            f"{_digits(inverter.bus_voltage_max_v, high_at)} V",
            # rounded inwards: a bound copied from here is accepted (-16.67 % of 24 V is
            # below a 20 V minimum, and the message had said "20-30 V, outside 20-30 V")
            f"[{_inward(lowest, up=True)}, {_inward(highest, up=False)}] %",
        )
    return Tolerances(**pairs)

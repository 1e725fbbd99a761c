"""The spec's quantities as the oracle reads them: from the YAML text, with its own units.

The oracle's model (`oracle.units`, `oracle.model`, `oracle.current_loop`) takes the
loader's validated Spec, whose quantities the generator's own code converted
(codegen/units.py, the line-to-line factor of codegen/spec_drive.py). A wrong factor
there moves the generated C and its yardstick together, and verify passes (a phase k_e
halved as if line to line; rpm per rad/s written 60/pi). So this module reads the spec
file again with PyYAML, converts every quantity the oracle and verify use with a unit
table written here from the units' definitions, and `cross_check` compares each with the
loader's value: verify runs it first and fails on any disagreement, one row per key.

Units (the spellings the spec format accepts; the factor to the SI unit the Spec keeps):

  voltage        V = 1, mV = 10^-3, kV = 10^3                                  (V)
  resistance     ohm = Ohm = 1, mohm = mOhm = 10^-3                           (ohm)
  inductance     H = 1, mH = 10^-3, uH = 10^-6                                 (H)
  back-EMF k_e   per mechanical rpm, the paper's E = k_e n (V/rpm):
                 V/rpm = 1, V/krpm = 10^-3 (volts per 1000 rpm), mV/rpm = 10^-3,
                 V*s/rad = 2 pi / 60: E = k omega with omega = 2 pi n / 60 rad/s
  inertia        kg*m^2 = 1, kg*cm^2 = 10^-4 (1 cm^2 = 10^-4 m^2), g*cm^2 = 10^-7
  friction       N*m*s/rad = 1, mN*m*s/rad = 10^-3, uN*m*s/rad = 10^-6
  frequency      Hz = 1, kHz = 10^3, MHz = 10^6                                (Hz)
  time           s = 1, ms = 10^-3, us = 10^-6, ns = 10^-9                     (s)
  current        A = 1, mA = 10^-3                                             (A)
  speed          rpm = 1, krpm = 10^3                                          (rpm)
  sense gain     V/A = 1, mV/A = 10^-3                                         (V/A)

Numbers stay exact: "0.56 mH" is 7/12500 H. pi enters one factor (V*s/rad); it is taken
to 40 digits here, and such a value agrees with the loader's within a relative
PI_TOLERANCE (1e-12: the loader holds 2 pi / 60 as a double's 17 digits, far finer; a
wrong factor is off by a sizeable fraction). Every other value must agree exactly.

`motor.back_emf_convention: line_to_line` divides the datasheet's constant by the peak
line-to-line EMF per unit of E, lambda, of the spec's EMF shape, computed by the
oracle's own `oracle.emf_shape.line_to_line_peak` (2 for the paper's 120 deg trapezoid
and for `flat`, whose EMFs at the edge are +E, -E, -E). The shape itself (`flat`,
`<w> deg` or a table of [angle, e/E]; absent: the 120 deg trapezoid) is read here too
and compared with the loader's, point by point.

Compared: motor (rated voltage, R, L, poles, k_e with its convention and shape, rotor
inertia, viscous friction), inverter (the three bus voltages, PWM frequency, timer
clock, dead time), hall (timer clock, counter bits, sector shortening in percent), adc
(bits, reference, bus divider, current gain, current offset), controller (braking
currents, speeds), accuracy (every number of the error budget verify's tolerances come
from), operating_points (speed, main duty), sensing (settling time, ADC sample time),
current_loop (bandwidth), protection (over-current, short-circuit current) and firmware
(HSE start-up and watchdog timeouts). Left out: the `tolerances` section (percent pairs
of the robustness campaign, which neither the oracle nor verify reads), the firmware's
plain budgets (bytes, cycles, CPU load) and the choices and channel numbers (no unit to
convert). The EMF table's entries are compared as part of `motor.back_emf_shape`, not
one key each. An optional key the YAML leaves out is skipped: its value is the spec
model's default, not a conversion.

PyYAML reads the file (the safe loader), with two changes to its YAML 1.1 scalars so that
a number means what the spec's YAML 1.2 reader makes of it: a float is kept as the exact
decimal it is written as (not the nearest double), and a decimal integer with a leading
zero is decimal (YAML 1.1 reads 010 as octal). Nothing is imported from the generator:
only the Spec, whose values are what is checked.
"""

from __future__ import annotations

import hashlib
import re
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from fractions import Fraction
from operator import attrgetter
from pathlib import Path
from typing import Any

import yaml

from codegen.spec_model import Spec
from oracle.emf_shape import line_to_line_peak

#: pi to 40 digits (as oracle.current_loop takes it)
PI = Fraction("3.1415926535897932384626433832795028841972")
#: the relative agreement asked of a value whose unit's factor holds pi (V*s/rad)
PI_TOLERANCE = Fraction(1, 10**12)

_MILLI, _MICRO, _NANO = Fraction(1, 10**3), Fraction(1, 10**6), Fraction(1, 10**9)


@dataclass(frozen=True)
class Unit:
    factor: Fraction
    exact: bool = True  # False: the factor holds pi, exact only to PI_TOLERANCE


@dataclass(frozen=True)
class Dimension:
    si_unit: str
    units: Mapping[str, Unit]


def _dimension(si_unit: str, table: dict[str, Fraction | Unit]) -> Dimension:
    return Dimension(
        si_unit, {k: v if isinstance(v, Unit) else Unit(Fraction(v)) for k, v in table.items()}
    )


ONE = Fraction(1)
VOLTAGE = _dimension("V", {"V": ONE, "mV": _MILLI, "kV": Fraction(1000)})
RESISTANCE = _dimension("ohm", {"ohm": ONE, "Ohm": ONE, "mohm": _MILLI, "mOhm": _MILLI})
INDUCTANCE = _dimension("H", {"H": ONE, "mH": _MILLI, "uH": _MICRO})
#: E = k_e n with n in mechanical rpm (the paper's Eq. 3). One rpm is 2 pi rad per 60 s,
#: so a constant of k V*s/rad gives E = k (2 pi / 60) n: k * 2 pi / 60 V per rpm.
EMF_CONSTANT = _dimension(
    "V/rpm",
    {
        "V/rpm": ONE,
        "V/krpm": _MILLI,
        "mV/rpm": _MILLI,
        "V*s/rad": Unit(2 * PI / 60, exact=False),
    },
)
INERTIA = _dimension(
    "kg*m^2",
    {"kg*m^2": ONE, "kg*cm^2": Fraction(1, 10**4), "g*cm^2": _MILLI * Fraction(1, 10**4)},
)
FRICTION = _dimension("N*m*s/rad", {"N*m*s/rad": ONE, "mN*m*s/rad": _MILLI, "uN*m*s/rad": _MICRO})
FREQUENCY = _dimension("Hz", {"Hz": ONE, "kHz": Fraction(10**3), "MHz": Fraction(10**6)})
TIME = _dimension("s", {"s": ONE, "ms": _MILLI, "us": _MICRO, "ns": _NANO})
CURRENT = _dimension("A", {"A": ONE, "mA": _MILLI})
SPEED = _dimension("rpm", {"rpm": ONE, "krpm": Fraction(1000)})
SENSE_GAIN = _dimension("V/A", {"V/A": ONE, "mV/A": _MILLI})

#: what may stand around a value: blanks, and the line breaks of a literal block or of a
#: quoted "...\n"
_SPACE = " \t\r\n"
_QUANTITY = re.compile(
    r"[ \t]*(?P<number>[-+]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][-+]?[0-9]+)?)[ \t]*"
    r"(?P<unit>\S(?:.*\S)?)?[ \t]*\Z",
    re.ASCII,
)
_WIDTH = re.compile(
    r"[ \t]*(?P<number>[-+]?(?:[0-9]+\.?[0-9]*|\.[0-9]+))[ \t]*(?:deg|\u00b0)[ \t]*\Z", re.ASCII
)
#: the paper's trapezoid, 120 deg flat tops (Fig. 2): 0 at 0, E from 30 to 150, 0 at 180
_TRAPEZOID_120 = (
    (Fraction(0), Fraction(0)),
    (Fraction(30), Fraction(1)),
    (Fraction(150), Fraction(1)),
    (Fraction(180), Fraction(0)),
)


class UnreadableError(ValueError):
    """A raw value the oracle cannot read (the row says why)."""


Shape = tuple[bool, tuple[tuple[Fraction, Fraction], ...]]  # (frozen, points)
Value = Fraction | int | Shape


@dataclass(frozen=True)
class Agreement:
    """One key: what the YAML says, the oracle's value and the loader's."""

    key: str
    raw: str
    oracle: Value | None  # None: the oracle could not read the raw text (`problem`)
    loader: Value | None  # None: the loader's Spec has no such value
    si_unit: str = ""
    exact: bool = True
    problem: str = ""

    @property
    def agrees(self) -> bool:
        if self.oracle is None or self.loader is None:
            return False
        if self.exact or not isinstance(self.oracle, Fraction):
            return self.oracle == self.loader
        assert isinstance(self.loader, Fraction | int)
        return abs(self.oracle - self.loader) <= PI_TOLERANCE * abs(self.oracle)

    @property
    def relative_difference(self) -> float:
        """|oracle - loader| / |oracle| (1 where either is missing or not a number)."""
        o, lo = self.oracle, self.loader
        if not isinstance(o, Fraction | int) or not isinstance(lo, Fraction | int):
            return 0.0 if self.agrees else 1.0
        if o == 0:
            return 0.0 if lo == 0 else 1.0
        return float(abs(Fraction(o) - Fraction(lo)) / abs(Fraction(o)))

    def line(self) -> str:
        """'key: raw -> oracle X, loader Y' in one line."""
        oracle = self.problem if self.oracle is None else _shown(self.oracle, self.si_unit)
        loader = "none" if self.loader is None else _shown(self.loader, self.si_unit)
        return f"{self.key}: '{self.raw}' -> oracle {oracle}, loader {loader}"


def _shown(value: Value, unit: str) -> str:
    if isinstance(value, tuple):
        frozen, points = value
        table = ", ".join(f"[{float(a):g}, {float(e):g}]" for a, e in points[:6])
        more = ", ..." if len(points) > 6 else ""
        return f"{'frozen ' if frozen else ''}[{table}{more}] ({len(points)} points)"
    return f"{float(value):.12g}{' ' + unit if unit else ''}"


# ---------------------------------------------------------------------------- reading


class _ExactLoader(yaml.SafeLoader):
    """PyYAML's safe loader, a float kept as its exact decimal, a decimal int as decimal."""


def _exact_float(loader: yaml.SafeLoader, node: yaml.ScalarNode) -> object:
    text = str(loader.construct_scalar(node)).replace("_", "")
    try:
        return Fraction(text)
    except ValueError:  # .inf, .nan, base 60: as PyYAML reads them (the loader refuses them)
        return loader.construct_yaml_float(node)


def _decimal_int(loader: yaml.SafeLoader, node: yaml.ScalarNode) -> object:
    text = str(loader.construct_scalar(node))
    if re.fullmatch(r"[-+]?[0-9]+", text, re.ASCII):
        return int(text, 10)
    return loader.construct_yaml_int(node)


def _octal(text: str) -> int | None:
    """A YAML 1.2 octal integer, 0o17, which YAML 1.1 (PyYAML) leaves a string; None for
    anything else (the spec's reader takes 0o14 as 12: `motor.poles: 0o2` had failed
    verify against a spec that generated)."""
    if re.fullmatch(r"0o[0-7]+", text.strip(), re.ASCII):
        return int(text.strip()[2:], 8)
    return None


_ExactLoader.add_constructor("tag:yaml.org,2002:float", _exact_float)
_ExactLoader.add_constructor("tag:yaml.org,2002:int", _decimal_int)


def read_raw(data: bytes) -> Any:
    """The spec's YAML as PyYAML's safe loader reads it (floats exact)."""
    return yaml.load(data, Loader=_ExactLoader)  # a SafeLoader subclass


def quantity(raw: object, dim: Dimension) -> tuple[Fraction, bool]:
    """'<number> <unit>' -> (the value in the dimension's SI unit, exact?)."""
    if not isinstance(raw, str):
        raise UnreadableError(f"not a '<number> <unit>' string ({type(raw).__name__})")
    # the spec's reader takes a value with a line break after it (a literal block, a
    # quoted "0.56 mH\n") or around it: white space is no part of a quantity
    match = _QUANTITY.match(raw.strip(_SPACE))
    if match is None or match.group("unit") is None:
        raise UnreadableError("not a number and a unit")
    unit = dim.units.get(match.group("unit"))
    if unit is None:
        raise UnreadableError(f"unit '{match.group('unit')}' not in the oracle's table")
    return Fraction(match.group("number")) * unit.factor, unit.exact


def number(raw: object) -> Fraction:
    """A plain number, exact (a YAML 1.2 float PyYAML leaves a string, such as 1e3, too)."""
    if isinstance(raw, bool):
        raise UnreadableError("a boolean, not a number")
    if isinstance(raw, Fraction | int):
        return Fraction(raw)
    if isinstance(raw, str):
        octal = _octal(raw)
        if octal is not None:
            return Fraction(octal)
        try:
            return Fraction(raw.strip())
        except ValueError:
            pass
    raise UnreadableError(f"not a number ({type(raw).__name__})")


def integer(raw: object) -> int:
    octal = _octal(raw) if isinstance(raw, str) else None
    if octal is not None:
        return octal
    if isinstance(raw, bool) or not isinstance(raw, int):
        raise UnreadableError(f"not an integer ({type(raw).__name__})")
    return raw


def emf_shape(raw: object) -> Shape:
    """`motor.back_emf_shape` -> (frozen, half-period points)."""
    if isinstance(raw, str):
        if raw.strip() == "flat":
            return True, _TRAPEZOID_120
        match = _WIDTH.match(raw.strip(_SPACE))
        if match is None:
            raise UnreadableError("neither 'flat' nor '<w> deg'")
        rise = (180 - Fraction(match.group("number"))) / 2
        return False, (
            (Fraction(0), Fraction(0)),
            (rise, ONE),
            (180 - rise, ONE),
            (Fraction(180), Fraction(0)),
        )
    if isinstance(raw, list) and all(isinstance(p, list) and len(p) == 2 for p in raw):
        return False, tuple((number(a), number(e)) for a, e in raw)
    raise UnreadableError("not an EMF shape")


# ---------------------------------------------------------------------------- the keys


#: (section, key, dimension, the Spec's field for it in the section, optional)
QUANTITIES: tuple[tuple[str, str, Dimension, str, bool], ...] = (
    ("motor", "rated_voltage", VOLTAGE, "rated_voltage_v", False),
    ("motor", "phase_resistance", RESISTANCE, "phase_resistance_ohm", False),
    ("motor", "phase_inductance", INDUCTANCE, "phase_inductance_h", False),
    ("motor", "rotor_inertia", INERTIA, "rotor_inertia_kg_m2", False),
    ("motor", "viscous_friction", FRICTION, "viscous_friction_n_m_s", True),
    ("inverter", "bus_voltage_nominal", VOLTAGE, "bus_voltage_nominal_v", False),
    ("inverter", "bus_voltage_min", VOLTAGE, "bus_voltage_min_v", False),
    ("inverter", "bus_voltage_max", VOLTAGE, "bus_voltage_max_v", False),
    ("inverter", "pwm_frequency", FREQUENCY, "pwm_frequency_hz", False),
    ("inverter", "timer_clock", FREQUENCY, "timer_clock_hz", False),
    ("inverter", "dead_time", TIME, "dead_time_s", False),
    ("hall", "timer_clock", FREQUENCY, "timer_clock_hz", False),
    ("adc", "reference", VOLTAGE, "reference_v", False),
    ("adc", "current_gain", SENSE_GAIN, "current_gain_v_per_a", False),
    ("adc", "current_offset", VOLTAGE, "current_offset_v", False),
    ("controller", "braking_current_min", CURRENT, "braking_current_min_a", False),
    ("controller", "braking_current_nominal", CURRENT, "braking_current_nominal_a", False),
    ("controller", "braking_current_max", CURRENT, "braking_current_max_a", False),
    ("controller", "speed_min", SPEED, "speed_min_rpm", False),
    ("controller", "speed_max", SPEED, "speed_max_rpm", False),
    ("sensing", "settling_time", TIME, "settling_time_s", False),
    ("current_loop", "bandwidth", FREQUENCY, "bandwidth_hz", False),
    ("protection", "over_current", CURRENT, "over_current_a", False),
    ("protection", "short_circuit_current_max", CURRENT, "short_circuit_current_max_a", False),
    ("firmware", "hse_startup_timeout", TIME, "hse_startup_timeout_s", False),
    ("firmware", "watchdog_timeout", TIME, "watchdog_timeout_s", False),
)

#: (section, key, reader, scale to the Spec's value, the Spec's field, optional)
NUMBERS: tuple[tuple[str, str, Callable[[object], Fraction | int], Fraction, str, bool], ...] = (
    ("motor", "poles", integer, ONE, "poles", False),
    ("hall", "counter_bits", integer, ONE, "counter_bits", False),
    # percent of the sector -> a fraction of it
    ("hall", "sector_shortening", number, Fraction(1, 100), "sector_shortening", True),
    ("adc", "bits", integer, ONE, "bits", False),
    ("adc", "bus_voltage_divider", number, ONE, "bus_voltage_divider", False),
    ("sensing", "adc_sample_time", number, ONE, "adc_sample_cycles", False),
    ("accuracy", "duty_counts", number, ONE, "duty_counts", False),
    ("accuracy", "commutation_time_ticks", number, ONE, "commutation_time_ticks", False),
    ("accuracy", "current_loop_duty_counts", number, ONE, "current_loop_duty_counts", False),
    ("accuracy", "ill_conditioned_above", number, ONE, "ill_conditioned_above", True),
    ("accuracy", "ill_conditioned_counts", number, ONE, "ill_conditioned_counts", True),
)


def _text(raw: object) -> str:
    if isinstance(raw, Fraction):
        return f"{float(raw):g}" if float(raw) == raw else str(raw)
    if isinstance(raw, list):
        return f"table of {len(raw)} points"
    # on one line: a line break in the value had broken verify's table row
    return str(raw).replace("\r", "\\r").replace("\n", "\\n")


def _row(
    key: str, raw: object, read: Callable[[], tuple[Value, bool]], loader: Value | None, unit: str
) -> Agreement:
    try:
        value, exact = read()
    except UnreadableError as exc:
        return Agreement(key, _text(raw), None, loader, unit, True, str(exc))
    return Agreement(key, _text(raw), value, loader, unit, exact)


def _section(data: Mapping[str, Any], name: str) -> Mapping[str, Any]:
    sec = data.get(name)
    return sec if isinstance(sec, Mapping) else {}


_ABSENT = object()


def convert(data: Mapping[str, Any], spec: Spec) -> tuple[Agreement, ...]:
    """Every key's row: the raw YAML (`read_raw`) against the loader's Spec."""
    rows: list[Agreement] = []

    def absent(key: str, loader: Value | None, unit: str, optional: bool) -> None:
        if not optional:  # the loader accepted a spec without it: say so
            rows.append(Agreement(key, "", None, loader, unit, True, "absent from the YAML"))

    for section, key, dim, field, optional in QUANTITIES:
        get = attrgetter(f"{section}.{field}")
        path, raw = f"{section}.{key}", _section(data, section).get(key, _ABSENT)
        if raw is _ABSENT:
            absent(path, get(spec), dim.si_unit, optional)
            continue
        rows.append(
            _row(path, raw, lambda raw=raw, dim=dim: quantity(raw, dim), get(spec), dim.si_unit)
        )
    for section, key, reader, scale, field, optional in NUMBERS:
        get = attrgetter(f"{section}.{field}")
        path, raw = f"{section}.{key}", _section(data, section).get(key, _ABSENT)
        if raw is _ABSENT:
            absent(path, get(spec), "", optional)
            continue

        def read(
            raw: object = raw, reader: Any = reader, scale: Fraction = scale
        ) -> tuple[Value, bool]:
            value = reader(raw)
            return (value if scale == 1 and isinstance(value, int) else value * scale), True

        rows.append(_row(path, raw, read, get(spec), ""))
    rows.extend(_motor_emf(_section(data, "motor"), spec))
    rows.extend(_operating_points(data.get("operating_points"), spec))
    return tuple(rows)


def _motor_emf(motor: Mapping[str, Any], spec: Spec) -> list[Agreement]:
    """motor.back_emf_shape and motor.back_emf_constant (with its convention)."""
    loaded = spec.motor.back_emf_shape
    raw_shape = motor.get("back_emf_shape", _ABSENT)
    shape: Shape | None = (False, _TRAPEZOID_120)
    rows = []
    if raw_shape is not _ABSENT:
        row = _row(
            "motor.back_emf_shape",
            raw_shape,
            lambda: (emf_shape(raw_shape), True),
            (loaded.frozen, tuple(loaded.points)),
            "",
        )
        rows.append(row)
        shape = row.oracle  # type: ignore[assignment]
    raw = motor.get("back_emf_constant", _ABSENT)
    convention = motor.get("back_emf_convention")
    loader = spec.motor.back_emf_constant_v_per_rpm

    def read() -> tuple[Value, bool]:
        value, exact = quantity(raw, EMF_CONSTANT)
        if convention == "line_to_line":
            if shape is None:
                raise UnreadableError("line to line, and the EMF shape unreadable")
            value /= line_to_line_peak(shape[1])
        elif convention != "phase":
            raise UnreadableError(
                f"back_emf_convention {convention!r} is neither phase nor line_to_line"
            )
        return value, exact

    if raw is _ABSENT:
        rows.append(
            Agreement(
                "motor.back_emf_constant", "", None, loader, "V/rpm", True, "absent from the YAML"
            )
        )
        return rows
    row = _row("motor.back_emf_constant", raw, read, loader, "V/rpm")
    rows.append(
        Agreement(
            row.key,
            f"{row.raw} ({convention})",
            row.oracle,
            row.loader,
            row.si_unit,
            row.exact,
            row.problem,
        )
    )
    return rows


def _operating_points(raw: object, spec: Spec) -> list[Agreement]:
    points = raw if isinstance(raw, list) else []
    rows = []
    for k, item in enumerate(points):
        item = item if isinstance(item, Mapping) else {}
        loaded = spec.operating_points[k] if k < len(spec.operating_points) else None
        speed, duty = item.get("speed"), item.get("main_duty")
        rows.append(
            _row(
                f"operating_points[{k}].speed",
                speed,
                lambda speed=speed: quantity(speed, SPEED),
                None if loaded is None else loaded.speed_rpm,
                "rpm",
            )
        )
        rows.append(
            _row(
                f"operating_points[{k}].main_duty",
                duty,
                lambda duty=duty: (number(duty), True),
                None if loaded is None else loaded.main_duty,
                "",
            )
        )
    if len(points) != len(spec.operating_points):
        rows.append(
            Agreement(
                "operating_points",
                f"{len(points)} points",
                Fraction(len(points)),
                Fraction(len(spec.operating_points)),
            )
        )
    return rows


def cross_check(path: str | Path, spec: Spec) -> tuple[Agreement, ...]:
    """The spec file at `path`, which the loader read into `spec`, read and converted by
    the oracle: one row per key (`Agreement.agrees` False where the two disagree)."""
    data = Path(path).read_bytes()
    if hashlib.sha256(data).hexdigest() != spec.sha256:
        return (
            Agreement(
                "<file>", str(path), None, None, problem="the file changed since the loader read it"
            ),
        )
    raw = read_raw(data)
    if not isinstance(raw, Mapping):
        return (Agreement("<document>", str(path), None, None, problem="not a YAML mapping"),)
    return convert(raw, spec)

"""The one place where a spec is checked.

load_spec() reads the file through codegen.yaml12 (bounded, YAML 1.2 core schema),
rejects unknown keys, converts every quantity to SI, checks each value against its
allowed range, then checks the physics that ties the values together and whether the
values are plausible for a real drive. It returns a frozen codegen.spec_model.Spec or
raises codegen.errors.MultiSpecError: every error of the spec, one line each, naming the key
path, the value, the unit, the allowed range and the YAML line.

Legal but unusual values give SpecWarnings (in Spec.warnings); a spec silences one by
listing its id under `warnings: {silence: [...]}` (see WARNINGS below).

Arithmetic on spec values is exact (Fractions); floats appear only in messages.
"""

from __future__ import annotations

import difflib
import hashlib
import math
import os
import re
import unicodedata
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from decimal import Context, Decimal
from fractions import Fraction
from pathlib import Path
from typing import Any, TypeVar

from codegen import spec_drive, spec_optional, units
from codegen.dead_time import (
    COMMUTATION_END_ALLOWANCE_S,
    SECTOR_SHORTENING_DEFAULT_PERCENT,
    SECTOR_SHORTENING_MAX_PERCENT,
    commutation_guard_ticks,
    latest_end_ticks,
    sector_margin_shift,
)
from codegen.errors import MISSING, NOT_READ, MultiSpecError, SpecError
from codegen.shown import on_one_line
from codegen.spec_model import (
    COMMUTATION_METHODS,
    COMMUTATION_TICKS_MAX,
    LOOP_DUTY_COUNTS_MAX,
    Accuracy,
    Adc,
    BackEmfShape,
    Controller,
    HallSensor,
    Inverter,
    Motor,
    OperatingPoint,
    Sensing,
    Spec,
    SpecWarning,
)
from codegen.yaml12 import (
    DEFAULT_LIMITS,
    ExactFloat,
    YamlError,
    child_path,
    read_yaml,
    type_name,
    unreadable_values,
)

_NAME = re.compile(r"[a-z][a-z0-9_]{0,63}\Z")
#: generated/<this>/ is the paper audit's folder (codegen.audit), never a motor's.
PAPER_AUDIT_NAME = "paper"
_MAX_DESCRIPTION_CHARS = 500
_MAX_SOURCE_CHARS = 500
#: Operating points are the paper's experiment speeds: each one is printed in the audit,
#: becomes Unity cases and is simulated in full, so a spec lists a few, not a sweep.
MAX_OPERATING_POINTS = 16

#: The share of the sector a none or conventional commutation (L/(2R) at the loop's
#: steady duty) may fill at speed_max before it is warned of: the loop samples only
#: after the commutation's end, and braking runs failed at 73-87 % and 79-80 % and
#: passed at 62 % (hunts; `make pil` judges each spec).
FILL_WARNED = Fraction(7, 10)
#: Plausibility warnings a spec may silence, by id: what each one means.
WARNINGS: dict[str, str] = {
    "braking-current-max-unreachable": "R * braking_current_max exceeds E at speed_max",
    "braking-current-at-operating-point": "R * braking_current_nominal exceeds E at an operating point",
    "braking-current-min-at-speed-min": "R * braking_current_min exceeds E at speed_min",
    "current-resolution": "braking_current_nominal is fewer than 16 current-ADC codes",
    "time-constant-short": "L/R is less than 4 PWM periods",
    "dead-time-short": "dead time under 50 ns",
    "dead-time-long": "two dead times take more than 4 % of the PWM period",
    "duty-budget-large": "accuracy.duty_counts above 4 TIM1 counts",
    "time-budget-large": "accuracy.commutation_time_ticks above 2 % of the shortest 60 deg sector",
    "current-sense-window": "an operating point's nominal braking current needs a duty above"
    " the current sample window's maximum",
    "pwm-ripple-large": "the braking current's PWM ripple is more than half of"
    " braking_current_nominal",
    "short-circuit-never-rated": "protection.safe_state short_circuit whose peak at"
    " speed_min is above protection.short_circuit_current_max: applied at no speed of the range",
    "over-current-margin-small": "protection.over_current less than a quarter of"
    " braking_current_max above the braking current's steady peak",
    "improved-r-time-not-relaxed": "controller.method improved_r, a PWM period longer than"
    " accuracy.commutation_time_ticks and no declared relaxation",
    "conventional-fills-sectors": "controller.method conventional above 14 R/(p L) rpm, where"
    " its commutation, L/(2R) with the loop's steady duty, fills 70 % of the sector or more",
    "none-fills-sectors": "controller.method none above 14 R/(p L) rpm, where its natural"
    " commutation, L/(2R) with the loop's steady duty, fills 70 % of the sector or more",
    "commutation-fills-sectors": "controller.method improved or improved_r with"
    " braking_current_max L p / (20 k_e) >= 1: its commutation, I L/(2E) where 4E <= U_d,"
    " lasts a whole sector at every such speed",
    "emf-shape-not-paper": "controller.method improved or conventional with a back-EMF shape"
    " whose EMFs at the Hall edge are not the paper's (+E, -E, -E)",
    "few-pwm-periods-per-sector": "the 60 deg sector at speed_max holds fewer than"
    " STEADY_SECTOR_PWM_PERIODS (4.5) PWM periods, too few loop samples for a steady braking",
}

#: Electrical angles, from each phase's rising zero crossing, of the non-commutating,
#: turn-off and turn-on phases at the paper's Hall edge (Hall sensors placed for 120 deg
#: conduction: a phase starts to rise 30 deg before its zero crossing). The 120 deg
#: trapezoid gives (+1, -1, -1) there, the EMFs the paper's Eqs. 14-20 hold through the
#: commutation; tests/test_spec_loader.py checks them against the switching table.
EDGE_ANGLES_DEG = (Fraction(90), Fraction(-30), Fraction(210))
#: The paper's EMFs at the edge, per unit of E.
PAPER_EDGE_EMFS = (Fraction(1), Fraction(-1), Fraction(-1))
#: How far (per unit of E) an EMF at the edge may be from the paper's before the
#: paper's methods are warned about the shape.
EDGE_EMF_SLACK = Fraction(1, 100)

T = TypeVar("T")


@dataclass(frozen=True)
class _Range:
    """Allowed interval of a value in SI, shown to the user in `unit`."""

    low: float | None
    high: float | None
    unit: str
    low_inclusive: bool = True
    high_inclusive: bool = True

    def contains(self, value: float | Fraction) -> bool:
        """Against the bounds as the decimals they print as: a spec's exact 1 ms is
        inside [0.001, 10] s, although the double 1e-3 is a little above 1/1000."""
        low, high = _decimal(self.low), _decimal(self.high)
        if low is not None and (value < low or (value == low and not self.low_inclusive)):
            return False
        return not (
            high is not None and (value > high or (value == high and not self.high_inclusive))
        )

    def describe(self) -> str:
        left = "[" if self.low_inclusive else "("
        right = "]" if self.high_inclusive else ")"
        low = "-inf" if self.low is None else _g(self.low)
        high = "inf" if self.high is None else _g(self.high)
        return f"{left}{low}, {high}{right} {self.unit}".rstrip()


def _decimal(bound: float | None) -> Fraction | None:
    """A range's bound as the shortest decimal that reads back as its double (what
    the code says and what the message shows), exactly; None stays None."""
    if bound is None:
        return None
    if isinstance(bound, float) and math.isfinite(bound):
        return Fraction(repr(bound))
    return Fraction(bound)


def _g(value: float | Fraction | int) -> str:
    """%g of an int, float or Fraction; exact values beyond a double (1e400 overflows,
    1e-403 underflows to 0.0) print their own digits."""
    try:
        as_float = float(value)
        if as_float != 0 or value == 0:
            return f"{as_float:g}"
    except OverflowError:
        pass
    exact = Fraction(value)
    decimal = Context(prec=6).divide(Decimal(exact.numerator), Decimal(exact.denominator))
    return f"{decimal.normalize():g}"


def _f1(value: Fraction) -> str:
    return f"{float(value):.1f}"


def _got(raw: object) -> str:
    """What a value that should be a number is: its type, and for a string that is a
    number written the usual wrong way ('0,75'), how to write it."""
    misread = units.misread_number(raw) if isinstance(raw, str) else None
    return f"{type_name(raw)} ({misread})" if misread else type_name(raw)


class _Reader:
    """Reads one parsed document, collecting every error and warning with its YAML line."""

    def __init__(self, source: str, lines: Mapping[str, int]) -> None:
        self.source = source
        self.lines = lines
        self.errors: list[SpecError] = []
        self.warnings: list[SpecWarning] = []

    def error(self, path: str, value: object, problem: str, allowed: str = "") -> SpecError:
        return SpecError(path, value, problem, allowed, self.source, self._line(path))

    def _line(self, path: str) -> int | None:
        # A missing key has no line: cite its section, the nearest place to add it.
        while path:
            if path in self.lines:
                return self.lines[path]
            path = path.rpartition(".")[0] if "." in path else ""
        return None

    def report(self, path: str, value: object, problem: str, allowed: str = "") -> None:
        self.errors.append(self.error(path, value, problem, allowed))

    def warn(self, warning_id: str, path: str, value: object, message: str) -> None:
        assert warning_id in WARNINGS, warning_id
        self.warnings.append(
            SpecWarning(warning_id, path, value, message, self.source, self._line(path))
        )

    def attempt(self, read: Callable[[], T]) -> T | None:
        """The value, or None after recording its SpecError (so reading goes on)."""
        try:
            return read()
        except SpecError as exc:
            self.errors.append(exc)
            return None

    def section(self, data: Mapping[str, Any], key: str) -> Mapping[str, Any] | None:
        if key not in data:
            self.report(key, MISSING, "missing required section", "a mapping")
            return None
        value = data[key]
        if not isinstance(value, Mapping):
            keys = _SECTIONS.get(key, ())
            optional = _SECTION_OPTIONAL.get(key, ())
            also = f"; optionally {', '.join(optional)}" if optional else ""
            self.report(
                key,
                value,
                f"must be a mapping of keys, got {type_name(value)}",
                f"a mapping of {', '.join(keys)}{also}" if keys else "a mapping",
            )
            return None
        return value

    def only_keys(
        self,
        data: Mapping[Any, Any],
        allowed: tuple[str, ...],
        path: str,
        optional: tuple[str, ...] = (),
    ) -> None:
        """Report every unknown key (suggesting the nearest known one); missing keys are
        reported by the readers, each under its own path."""
        known = (*allowed, *optional)
        for key in data:
            if key in known:
                continue
            where = child_path(path, key)
            guess = difflib.get_close_matches(str(key), known, n=1, cutoff=0.6)
            hint = f"; did you mean '{guess[0]}'?" if guess else ""
            self.report(where, data[key], f"unknown key{hint}", ", ".join(known))

    def raw(self, data: Mapping[str, Any], key: str, path: str, allowed: str = "") -> Any:
        """The key's value; a missing key is an error that says what the key takes
        (its range and unit where the caller knows them: a user's spec folder need not
        hold an example to look it up in)."""
        where = f"{path}.{key}" if path else key
        if key not in data:
            raise self.error(where, MISSING, "missing required key", allowed)
        return data[key]

    def quantity(
        self, data: Mapping[str, Any], key: str, path: str, dim: units.Dimension, rng: _Range
    ) -> Fraction:
        where = f"{path}.{key}"
        raw = self.raw(data, key, path, f"{rng.describe()}; units: {dim.accepted()}")
        try:
            parsed = units.parse_quantity(raw, dim)
        except units.QuantityError as exc:
            raise self.error(where, raw, str(exc), rng.describe()) from None
        if not rng.contains(parsed.si_value):
            raise self.error(
                where, raw, f"{_g(parsed.si_value)} {dim.si_unit} is out of range", rng.describe()
            )
        return parsed.si_value

    def number(self, data: Mapping[str, Any], key: str, path: str, rng: _Range) -> Fraction:
        where = f"{path}.{key}" if path else key
        raw = self.raw(data, key, path, f"a plain number in {rng.describe()}")
        if isinstance(raw, bool) or not isinstance(raw, (int, float)):
            raise self.error(where, raw, f"must be a plain number, got {_got(raw)}", rng.describe())
        if isinstance(raw, float) and not math.isfinite(raw):
            raise self.error(where, raw, "must be a finite number", rng.describe())
        exact = raw.exact if isinstance(raw, ExactFloat) else None
        value = Fraction(raw) if exact is None else exact
        if not rng.contains(value):
            raise self.error(where, raw, "out of range", rng.describe())
        return value

    def integer(self, data: Mapping[str, Any], key: str, path: str, rng: _Range) -> int:
        where = f"{path}.{key}"
        raw = self.raw(data, key, path, f"an integer in {rng.describe()}")
        if isinstance(raw, bool) or not isinstance(raw, int):
            raise self.error(where, raw, f"must be an integer, got {_got(raw)}", rng.describe())
        if not rng.contains(raw):
            raise self.error(where, raw, "out of range", rng.describe())
        return raw

    def choice(self, data: Mapping[str, Any], key: str, path: str, options: tuple[str, ...]) -> str:
        raw = self.raw(data, key, path, ", ".join(options))
        if not isinstance(raw, str) or raw not in options:
            guess = (
                difflib.get_close_matches(raw, options, n=1, cutoff=0.6)
                if isinstance(raw, str)
                else []
            )
            hint = f"; did you mean '{guess[0]}'?" if guess else ""
            raise self.error(f"{path}.{key}", raw, f"not a known option{hint}", ", ".join(options))
        return raw


def _positive(low: float, high: float, unit: str) -> _Range:
    return _Range(low, high, unit)


_TOP_KEYS = (
    "name",
    "description",
    "motor",
    "inverter",
    "hall",
    "adc",
    "controller",
    "accuracy",
    "operating_points",
    *spec_drive.SECTIONS,
    "sources",
)
_OPTIONAL_TOP_KEYS = ("warnings",)

_MOTOR_KEYS = (
    "rated_voltage",
    "phase_resistance",
    "phase_inductance",
    "poles",
    "back_emf_constant",
    "back_emf_convention",
    "rotor_inertia",
)
_INVERTER_KEYS = (
    "bus_voltage_nominal",
    "bus_voltage_min",
    "bus_voltage_max",
    "pwm_frequency",
    "pwm_alignment",
    "timer_clock",
    "dead_time",
)
_HALL_KEYS = ("sequence", "timer_clock", "counter_bits")
#: the narrowest braking-current range, in current-ADC codes
CURRENT_RANGE_CODES = 16
#: the narrowest speed range, in Hall timer ticks of the 60 deg period
SPEED_RANGE_TICKS = 16
_ADC_KEYS = ("bits", "reference", "bus_voltage_divider", "current_gain", "current_offset")
_CONTROLLER_KEYS = (
    "method",
    "braking_current_min",
    "braking_current_nominal",
    "braking_current_max",
    "speed_min",
    "speed_max",
)
_ACCURACY_KEYS = ("duty_counts", "commutation_time_ticks", "current_loop_duty_counts")
#: The largest accuracy.duty_counts a spec may ask (see `_accuracy`)
DUTY_COUNTS_MAX = 16
_SECTIONS = {
    "motor": _MOTOR_KEYS,
    "inverter": _INVERTER_KEYS,
    "hall": _HALL_KEYS,
    "adc": _ADC_KEYS,
    "controller": _CONTROLLER_KEYS,
    "accuracy": _ACCURACY_KEYS,
    **spec_drive.SECTIONS,
}

# Ranges: what any real drive of this kind can have, so that no value can reach the
# arithmetic below as zero, infinity or beyond a double (1e-400 V/krpm is 0.0 in float).
_VOLTS = _positive(1, 1000, "V")
_POLES = _Range(2, 128, "poles")
_EMF = _positive(1e-5, 1, "V/rpm")
_RESISTANCE = _positive(1e-4, 100, "ohm")
_INDUCTANCE = _positive(1e-7, 1, "H")
_INERTIA = _positive(1e-9, 100, "kg*m^2")
_PWM_FREQUENCY = _Range(1e3, 100e3, "Hz")
_AMPS = _Range(0.0, 1000.0, "A")
_SPEEDS = _positive(1, 1e6, "rpm")
#: The ranges of the values a datasheet gives (`bldc-codegen init` holds its arguments
#: to them: `out_of_range`), by key path; the unit is the SI one the loader converts to.
DATASHEET_RANGES = {
    "motor.poles": _POLES,
    "motor.back_emf_constant": _EMF,
    "motor.rated_voltage": _VOLTS,
    "motor.phase_resistance": _RESISTANCE,
    "motor.phase_inductance": _INDUCTANCE,
    "motor.rotor_inertia": _INERTIA,
    "inverter.bus_voltage_nominal": _VOLTS,
    "inverter.pwm_frequency": _PWM_FREQUENCY,
    "controller.braking_current_nominal": _AMPS,
    "controller.speed_max": _SPEEDS,
}


def out_of_range(key: str, value: Fraction | int) -> str | None:
    """Why `value` (in the SI unit) cannot be the spec's `key` of DATASHEET_RANGES, in
    the loader's words, or None where it can."""
    rng = DATASHEET_RANGES[key]
    if rng.contains(value):
        return None
    return f"{key} = {_g(value)} {rng.unit} is out of range (allowed: {rng.describe()})"


#: Optional motor.viscous_friction: 0 (none) up to what would stop a large hub motor
#: within milliseconds.
_FRICTION_KEY = "viscous_friction"
_FRICTION = _Range(0, 10, "N*m*s/rad")


def _motor(r: _Reader, data: Mapping[str, Any]) -> Motor | None:
    sec = r.section(data, "motor")
    if sec is None:
        return None
    r.only_keys(sec, _MOTOR_KEYS, "motor", _SECTION_OPTIONAL["motor"])
    shape = BackEmfShape()
    if spec_optional.EMF_SHAPE_KEY in sec:
        read = r.attempt(lambda: spec_optional.back_emf_shape(r, sec[spec_optional.EMF_SHAPE_KEY]))
        shape = read if read is not None else shape
    friction: Fraction | None = Fraction(0)
    if _FRICTION_KEY in sec:
        friction = r.attempt(
            lambda: r.quantity(sec, _FRICTION_KEY, "motor", units.VISCOUS_FRICTION, _FRICTION)
        )

    def poles() -> int:
        count = r.integer(sec, "poles", "motor", _POLES)
        if count % 2:
            raise r.error(
                "motor.poles", count, "a rotor has an even number of poles", "2, 4, 6, ... 128"
            )
        return count

    convention = r.attempt(
        lambda: r.choice(sec, "back_emf_convention", "motor", ("phase", "line_to_line"))
    )
    # the range is the phase k_e's; a line-to-line constant is lambda times it (the
    # same motor was accepted as 0.75 V/rpm phase and refused as 1.5 line to line, and
    # a table of nearly no line-to-line EMF turned 1 V/rpm into a phase k_e of 1e297)
    emf_range = _EMF
    if convention == "line_to_line":
        ltl = float(spec_drive.line_to_line_peak(shape))
        emf_range = _Range(
            _EMF.low * ltl if _EMF.low is not None else None,
            _EMF.high * ltl if _EMF.high is not None else None,
            f"V/rpm line to line (the phase k_e in {_EMF.describe()}, x {ltl:.4g} for this"
            " EMF shape)",
        )
    k_e = r.attempt(
        lambda: r.quantity(sec, "back_emf_constant", "motor", units.EMF_CONSTANT, emf_range)
    )
    values = (
        r.attempt(lambda: r.quantity(sec, "rated_voltage", "motor", units.VOLTAGE, _VOLTS)),
        r.attempt(
            lambda: r.quantity(sec, "phase_resistance", "motor", units.RESISTANCE, _RESISTANCE)
        ),
        r.attempt(
            lambda: r.quantity(sec, "phase_inductance", "motor", units.INDUCTANCE, _INDUCTANCE)
        ),
        r.attempt(poles),
        r.attempt(lambda: r.quantity(sec, "rotor_inertia", "motor", units.INERTIA, _INERTIA)),
    )
    if convention is None or k_e is None or friction is None or any(v is None for v in values):
        return None
    rated, resistance, inductance, pole_count, inertia = values
    if convention == "line_to_line":
        # The datasheet's constant is the peak line-to-line EMF per rpm, lambda E with
        # lambda the shape's (spec_drive.line_to_line_peak): 2 for a flat top of 60 deg
        # or more (the paper's Eq. 4: the two conducting phases at +E and -E), less for a
        # narrower top or a sine-like table (sqrt 3), where halving read E too low.
        k_e /= spec_drive.line_to_line_peak(shape)
    return Motor(
        rated_voltage_v=rated,  # type: ignore[arg-type]
        phase_resistance_ohm=resistance,  # type: ignore[arg-type]
        phase_inductance_h=inductance,  # type: ignore[arg-type]
        poles=pole_count,  # type: ignore[arg-type]
        back_emf_constant_v_per_rpm=k_e,
        back_emf_convention=convention,  # type: ignore[arg-type]
        rotor_inertia_kg_m2=inertia,  # type: ignore[arg-type]
        back_emf_shape=shape,
        viscous_friction_n_m_s=friction,
    )


#: The longest PWM period in TIM1 counts: twice it fits the core's 16-bit compare values.
PERIOD_COUNTS_MAX = 32767


def _inverter(r: _Reader, data: Mapping[str, Any]) -> Inverter | None:
    sec = r.section(data, "inverter")
    if sec is None:
        return None
    r.only_keys(sec, _INVERTER_KEYS, "inverter")
    v_nom = r.attempt(
        lambda: r.quantity(sec, "bus_voltage_nominal", "inverter", units.VOLTAGE, _VOLTS)
    )
    v_min = r.attempt(lambda: r.quantity(sec, "bus_voltage_min", "inverter", units.VOLTAGE, _VOLTS))
    v_max = r.attempt(lambda: r.quantity(sec, "bus_voltage_max", "inverter", units.VOLTAGE, _VOLTS))
    timer_clock = r.attempt(
        lambda: r.quantity(sec, "timer_clock", "inverter", units.FREQUENCY, _Range(1e6, 72e6, "Hz"))
    )
    f_pwm = r.attempt(
        lambda: r.quantity(sec, "pwm_frequency", "inverter", units.FREQUENCY, _PWM_FREQUENCY)
    )
    alignment = r.attempt(lambda: r.choice(sec, "pwm_alignment", "inverter", ("edge", "center")))
    # Both switches of a leg conducting at once short the bus: a bridge needs a dead time.
    dead = r.attempt(
        lambda: r.quantity(
            sec, "dead_time", "inverter", units.TIME, _Range(0.0, 5e-6, "s", low_inclusive=False)
        )
    )
    if v_min is not None and v_max is not None and not v_min < v_max:
        r.report(
            "inverter.bus_voltage_max",
            sec["bus_voltage_max"],
            "bus voltage range is empty or inverted",
            f"> bus_voltage_min = {_g(v_min)} V",
        )
    elif None not in (v_min, v_max, v_nom) and not v_min <= v_nom <= v_max:  # type: ignore[operator]
        r.report(
            "inverter.bus_voltage_nominal",
            sec["bus_voltage_nominal"],
            "nominal bus voltage outside the operating range",
            f"[{_g(v_min)}, {_g(v_max)}] V",  # type: ignore[arg-type]
        )
    if timer_clock is not None and f_pwm is not None and alignment is not None:
        period_counts = timer_clock / f_pwm / (2 if alignment == "center" else 1)
        # Eq. 18's D_on = 2 - 4E/U_d reaches twice the period's counts before its clamp,
        # and the core's compare values are 16 bits: 2 P <= 65535
        if not 256 <= period_counts <= PERIOD_COUNTS_MAX or period_counts.denominator != 1:
            halves = 2 if alignment == "center" else 1
            lowest = timer_clock / PERIOD_COUNTS_MAX / halves
            highest = timer_clock / 256 / halves
            r.report(
                "inverter.pwm_frequency",
                sec["pwm_frequency"],
                f"gives {_g(period_counts)} TIM1 counts per period at {_g(timer_clock)} Hz"
                f" ({alignment}); the duties reach twice the period's counts in 16-bit"
                " compare values",
                f"a whole number of counts in [256, {PERIOD_COUNTS_MAX}]: {_g(lowest)} to"
                f" {_g(highest)} Hz at this timer_clock, dividing it into whole counts",
            )
    if dead is not None and f_pwm is not None and dead * f_pwm * 2 >= Fraction(1, 10):
        r.report(
            "inverter.dead_time",
            sec["dead_time"],
            "two dead times per period eat more than 10 % of the PWM period, distorting"
            " every duty by as much",
            f"< {_g(Fraction(1, 20) / f_pwm)} s at {_g(f_pwm)} Hz",
        )
    values = (v_nom, v_min, v_max, f_pwm, alignment, timer_clock, dead)
    if any(v is None for v in values) or _any_under(r, "inverter"):
        return None
    return Inverter(
        bus_voltage_nominal_v=v_nom,  # type: ignore[arg-type]
        bus_voltage_min_v=v_min,  # type: ignore[arg-type]
        bus_voltage_max_v=v_max,  # type: ignore[arg-type]
        pwm_frequency_hz=f_pwm,  # type: ignore[arg-type]
        pwm_alignment=alignment,  # type: ignore[arg-type]
        timer_clock_hz=timer_clock,  # type: ignore[arg-type]
        dead_time_s=dead,  # type: ignore[arg-type]
    )


def _any_under(r: _Reader, section: str) -> bool:
    return any(e.path == section or e.path.startswith(f"{section}.") for e in r.errors)


_HALL_SEQUENCE_ALLOWED = "six distinct codes 1..6, consecutive codes differing in exactly one bit"


def _hall_sequence(r: _Reader, raw: object) -> tuple[int, ...]:
    path = "hall.sequence"
    allowed = _HALL_SEQUENCE_ALLOWED
    if not isinstance(raw, list) or len(raw) != 6:
        raise r.error(path, raw, "must list the six Hall codes of Table 1", allowed)
    for index, code in enumerate(raw):
        if isinstance(code, bool) or not isinstance(code, int):
            raise r.error(f"{path}[{index}]", code, "Hall code must be an integer", allowed)
        if code in (0, 7):
            raise r.error(
                f"{path}[{index}]", code, "000 and 111 are the invalid (fault) Hall codes", allowed
            )
        if not 1 <= code <= 6:
            raise r.error(f"{path}[{index}]", code, "Hall code out of range", allowed)
    if len(set(raw)) != 6:
        raise r.error(path, raw, "Hall codes repeat", allowed)
    for index, code in enumerate(raw):
        following = raw[(index + 1) % 6]
        if bin(code ^ following).count("1") != 1:
            raise r.error(
                f"{path}[{(index + 1) % 6}]",
                following,
                f"not a Gray step from {code:03b} to {following:03b}",
                allowed,
            )
    return tuple(raw)


def _hall(r: _Reader, data: Mapping[str, Any]) -> HallSensor | None:
    sec = r.section(data, "hall")
    if sec is None:
        return None
    r.only_keys(sec, _HALL_KEYS, "hall", _SECTION_OPTIONAL["hall"])
    bits = r.attempt(lambda: r.integer(sec, "counter_bits", "hall", _Range(16, 16, "bits")))
    shortening: Fraction | None = Fraction(SECTOR_SHORTENING_DEFAULT_PERCENT, 100)
    if "sector_shortening" in sec:
        percent = r.attempt(
            lambda: r.number(
                sec,
                "sector_shortening",
                "hall",
                _Range(0, SECTOR_SHORTENING_MAX_PERCENT, "percent of the sector measured"),
            )
        )
        shortening = None if percent is None else Fraction(percent) / 100
    sequence = r.attempt(
        lambda: _hall_sequence(r, r.raw(sec, "sequence", "hall", _HALL_SEQUENCE_ALLOWED))
    )
    clock = r.attempt(
        lambda: r.quantity(sec, "timer_clock", "hall", units.FREQUENCY, _Range(1e3, 72e6, "Hz"))
    )
    if bits is None or sequence is None or clock is None or shortening is None:
        return None
    return HallSensor(
        sequence=sequence, timer_clock_hz=clock, counter_bits=bits, sector_shortening=shortening
    )


def _adc(r: _Reader, data: Mapping[str, Any]) -> Adc | None:
    sec = r.section(data, "adc")
    if sec is None:
        return None
    r.only_keys(sec, _ADC_KEYS, "adc")
    # The generated port reads the STM32F103's ADC as it converts: 12-bit codes, right
    # aligned, against VREF+ (DS5319: 2.4 V to VDDA, which is at most 3.6 V). Another
    # width would make the firmware read every code 2^(12 - bits) times off, and trip.
    reference = r.attempt(
        lambda: r.quantity(
            sec, "reference", "adc", units.VOLTAGE, _Range(2.4, 3.6, "V (the STM32F103's VREF+)")
        )
    )
    bits = r.attempt(
        lambda: r.integer(sec, "bits", "adc", _Range(12, 12, "bits (the STM32F103's ADC)"))
    )
    divider = r.attempt(
        lambda: r.number(sec, "bus_voltage_divider", "adc", _Range(1, 1000, "(V/V)"))
    )
    gain = r.attempt(
        lambda: r.quantity(
            sec, "current_gain", "adc", units.TRANSRESISTANCE, _positive(1e-4, 10.0, "V/A")
        )
    )
    offset = (
        None
        if reference is None
        else r.attempt(
            lambda: r.quantity(
                sec, "current_offset", "adc", units.VOLTAGE, _Range(0.0, float(reference), "V")
            )
        )
    )
    if None in (reference, bits, divider, gain, offset):
        return None
    return Adc(
        bits=bits,  # type: ignore[arg-type]
        reference_v=reference,  # type: ignore[arg-type]
        bus_voltage_divider=divider,  # type: ignore[arg-type]
        current_gain_v_per_a=gain,  # type: ignore[arg-type]
        current_offset_v=offset,  # type: ignore[arg-type]
    )


def _controller(r: _Reader, data: Mapping[str, Any]) -> Controller | None:
    sec = r.section(data, "controller")
    if sec is None:
        return None
    r.only_keys(sec, _CONTROLLER_KEYS, "controller")
    amps = _AMPS
    method = r.attempt(lambda: r.choice(sec, "method", "controller", COMMUTATION_METHODS))
    i_min = r.attempt(
        lambda: r.quantity(sec, "braking_current_min", "controller", units.CURRENT, amps)
    )
    i_nom = r.attempt(
        lambda: r.quantity(sec, "braking_current_nominal", "controller", units.CURRENT, amps)
    )
    i_max = r.attempt(
        lambda: r.quantity(sec, "braking_current_max", "controller", units.CURRENT, amps)
    )
    speeds = _SPEEDS
    n_min = r.attempt(lambda: r.quantity(sec, "speed_min", "controller", units.SPEED, speeds))
    n_max = r.attempt(lambda: r.quantity(sec, "speed_max", "controller", units.SPEED, speeds))
    if i_min is not None and i_max is not None and not i_min < i_max:
        r.report(
            "controller.braking_current_max",
            sec["braking_current_max"],
            "braking current range is empty or inverted",
            f"> braking_current_min = {_g(i_min)} A",
        )
    elif None not in (i_min, i_nom, i_max) and not i_min <= i_nom <= i_max:  # type: ignore[operator]
        r.report(
            "controller.braking_current_nominal",
            sec["braking_current_nominal"],
            "nominal braking current outside its range",
            f"[{_g(i_min)}, {_g(i_max)}] A",  # type: ignore[arg-type]
        )
    elif i_nom is not None and i_nom <= 0:
        r.report(
            "controller.braking_current_nominal",
            sec["braking_current_nominal"],
            "braking needs a current",
            f"(0, {_g(i_max)}] A" if i_max is not None else "> 0 A",
        )
    if n_min is not None and n_max is not None and not n_min < n_max:
        r.report(
            "controller.speed_max",
            sec["speed_max"],
            "speed range is empty or inverted",
            f"> speed_min = {_g(n_min)} rpm",
        )
    if None in (method, i_min, i_nom, i_max, n_min, n_max) or _any_under(r, "controller"):
        return None
    return Controller(
        method=method,  # type: ignore[arg-type]
        braking_current_min_a=i_min,  # type: ignore[arg-type]
        braking_current_nominal_a=i_nom,  # type: ignore[arg-type]
        braking_current_max_a=i_max,  # type: ignore[arg-type]
        speed_min_rpm=n_min,  # type: ignore[arg-type]
        speed_max_rpm=n_max,  # type: ignore[arg-type]
    )


def _accuracy(r: _Reader, data: Mapping[str, Any]) -> Accuracy | None:
    sec = r.section(data, "accuracy")
    if sec is None:
        return None
    r.only_keys(sec, _ACCURACY_KEYS, "accuracy", _SECTION_OPTIONAL["accuracy"])
    # An error budget is a few LSBs: the final rounding alone costs half of one, so the
    # budget must exceed 1/2; past 16 counts (0.4 % of a 3600-count period) or 64 ticks
    # it no longer describes an accurate implementation.
    duty = r.attempt(
        lambda: r.number(
            sec,
            "duty_counts",
            "accuracy",
            _Range(0.5, DUTY_COUNTS_MAX, "TIM1 counts", low_inclusive=False),
        )
    )
    ticks = r.attempt(
        lambda: r.number(
            sec,
            "commutation_time_ticks",
            "accuracy",
            _Range(0.5, COMMUTATION_TICKS_MAX, "Hall timer ticks", low_inclusive=False),
        )
    )
    loop = r.attempt(
        lambda: r.number(
            sec,
            "current_loop_duty_counts",
            "accuracy",
            _Range(0.5, LOOP_DUTY_COUNTS_MAX, "TIM1 counts", low_inclusive=False),
        )
    )
    present = tuple(k for k in _RELAXATION if k in sec)
    if len(present) == 1:
        missing = next(k for k in _RELAXATION if k not in present)
        r.report(
            f"accuracy.{missing}",
            None,
            f"missing: accuracy.{present[0]} declares a relaxation, which needs both keys",
            "both ill_conditioned_above (ticks per count) and ill_conditioned_counts (counts), or neither",
        )
        return None
    above = counts = None
    if present:
        # Where one count of error moves t_com by more than `above` ticks, t_com need only
        # be exact for an error of `counts` (checked by verify, never claimed by a design).
        above = r.attempt(
            lambda: r.number(
                sec,
                "ill_conditioned_above",
                "accuracy",
                _Range(1, 1e6, "Hall ticks per TIM1 count"),
            )
        )
        counts = r.attempt(
            lambda: r.number(
                sec, "ill_conditioned_counts", "accuracy", _Range(0.001, 4, "TIM1 counts")
            )
        )
        if above is None or counts is None:
            return None
    if duty is None or ticks is None or loop is None:
        return None
    return Accuracy(
        duty_counts=duty,
        commutation_time_ticks=ticks,
        ill_conditioned_above=above,
        ill_conditioned_counts=counts,
        current_loop_duty_counts=loop,
    )


#: The optional declared relaxation of accuracy: (threshold, backward tolerance).
_RELAXATION = ("ill_conditioned_above", "ill_conditioned_counts")
#: The optional keys of a section, which its `only_keys` takes beside the required ones
_SECTION_OPTIONAL = {
    "motor": (spec_optional.EMF_SHAPE_KEY, _FRICTION_KEY),
    "hall": ("sector_shortening",),
    "accuracy": _RELAXATION,
}


def _operating_points(r: _Reader, data: Mapping[str, Any]) -> tuple[OperatingPoint, ...] | None:
    allowed = f"1 to {MAX_OPERATING_POINTS} mappings {{speed, main_duty}}"
    raw = r.attempt(lambda: r.raw(data, "operating_points", "", allowed))
    if raw is None and "operating_points" not in data:  # reported as missing
        return None
    if not isinstance(raw, list):  # a null value included (it had reached the physics: a TypeError)
        r.report("operating_points", raw, f"must be a list, got {type_name(raw)}", allowed)
        return None
    if not raw:
        r.report(
            "operating_points",
            raw,
            "is empty: the audit, the Unity tests and the simulation work at these speeds"
            " (the paper's experiment), so there must be at least one",
            allowed,
        )
        return None
    if len(raw) > MAX_OPERATING_POINTS:
        r.report(
            "operating_points",
            raw,
            f"lists {len(raw)} points: each is printed in the audit, becomes Unity cases and"
            " is simulated in full, so list the few speeds that matter, not a sweep",
            allowed,
        )
        return None
    points: list[OperatingPoint] = []
    for index, item in enumerate(raw):
        path = f"operating_points[{index}]"
        if not isinstance(item, Mapping):
            r.report(path, item, f"must be a mapping {{speed, main_duty}}, got {type_name(item)}")
            continue
        r.only_keys(item, ("speed", "main_duty"), path)
        speed = r.attempt(
            lambda item=item, path=path: r.quantity(
                item, "speed", path, units.SPEED, _positive(1, 1e6, "rpm")
            )
        )
        duty = r.attempt(
            lambda item=item, path=path: r.number(item, "main_duty", path, _Range(0.0, 1.0, ""))
        )
        if speed is not None and duty is not None:
            points.append(OperatingPoint(speed_rpm=speed, main_duty=duty))
    if len(points) != len(raw):
        return None
    # the Unity tests, the audit and the simulation name each point by its speed in whole
    # rpm: two points at one speed (another main duty) wrote two Unity tests of one name
    # (the suite did not compile) and one figure over the other
    for j, later in enumerate(points):
        for i, earlier in enumerate(points[:j]):
            if abs(later.speed_rpm - earlier.speed_rpm) < 1:
                r.report(
                    f"operating_points[{j}].speed",
                    raw[j].get("speed"),
                    f"within 1 rpm of operating_points[{i}].speed"
                    f" ({_g(earlier.speed_rpm)} rpm): the Unity tests, the audit and the"
                    " simulation name each point by its speed in whole rpm",
                    "a speed at least 1 rpm from every other operating point's",
                )
                break
    return tuple(points)


def _value_paths(data: Mapping[str, Any]) -> list[str]:
    """Every value that must say where it comes from: each key of each section and
    each operating point's fields."""
    paths = [f"{section}.{key}" for section, keys in _SECTIONS.items() for key in keys]
    points = data.get("operating_points")
    if isinstance(points, list):
        paths += [
            f"operating_points[{i}].{key}"
            for i in range(len(points))
            for key in ("speed", "main_duty")
        ]
    return paths


def _covered(path: str, named: set[str]) -> bool:
    """A source for a value or for any section or item that contains it covers it."""
    while path:
        if path in named:
            return True
        cut = max(path.rfind("."), path.rfind("["))
        path = path[:cut] if cut > 0 else ""
    return False


#: The bidirectional embeddings, overrides, isolates and marks: the "Trojan Source"
#: characters that make text read in another order than it is stored. Other format
#: characters are text (a zero-width joiner in an emoji or a Persian word, a soft
#: hyphen), and are kept.
_BIDI_CONTROLS = frozenset(
    "\u061c\u200e\u200f\u202a\u202b\u202c\u202d\u202e\u2066\u2067\u2068\u2069"
)


def _hidden_character(text: str) -> str | None:
    """The first character of `text` a reader cannot see for what it is, named (U+202E),
    else None: a control character other than a line break or a tab, or a bidirectional
    control."""
    for char in text:
        if char in "\n\r\t":
            continue
        if unicodedata.category(char) == "Cc" or char in _BIDI_CONTROLS:
            name = unicodedata.name(char, "")
            return f"U+{ord(char):04X}" + (f" ({name})" if name else "")
    return None


def _sources(r: _Reader, data: Mapping[str, Any]) -> tuple[tuple[str, str], ...] | None:
    raw = r.attempt(lambda: r.raw(data, "sources", "", "a mapping of key paths to descriptions"))
    if raw is None and "sources" not in data:  # reported as missing
        return None
    if not isinstance(raw, Mapping):  # `sources: ~` included (it had skipped the check)
        r.report(
            "sources",
            raw,
            f"must map key paths to where each value comes from, got {type_name(raw)}",
        )
        return None
    out: list[tuple[str, str]] = []
    required = _value_paths(data)
    schema = set(required)
    for key, text in raw.items():
        path = child_path("sources", key)
        if not isinstance(text, str) or not text.strip():
            r.report(path, text, "must be a non-empty description")
            continue
        if len(text) > _MAX_SOURCE_CHARS:
            r.report(path, text, f"a source of {len(text)} characters", f"<= {_MAX_SOURCE_CHARS}")
            continue
        if (hidden := _hidden_character(text)) is not None:
            r.report(
                path, text, f"holds the invisible or control character {hidden}", "printable text"
            )
            continue
        key_text = str(key)
        # A key of the schema that the spec lacks is reported where it is missing.
        in_schema = key_text in schema or key_text in _SECTIONS or key_text == "operating_points"
        if key_text.startswith(("sources", "warnings")) or (
            key_text not in r.lines and not in_schema
        ):
            known = [p for p in r.lines if not p.startswith(("sources", "warnings"))]
            guess = difflib.get_close_matches(key_text, known, n=1, cutoff=0.6)
            hint = f"; did you mean '{guess[0]}'?" if guess else ""
            r.report(path, text, f"names a key that the spec does not have{hint}")
            continue
        out.append((key_text, text))
    named = {key for key, _ in out} | {str(key) for key in raw}
    missing = [path for path in required if not _covered(path, named)]
    allowed = (
        "a datasheet, the paper, a measurement or 'assumption: why', for the key or its section"
    )
    if len(missing) > 3:  # one line, not thirty, for a spec with no sources yet
        listed = ", ".join(missing[:4])
        r.report(
            "sources",
            raw,
            f"{len(missing)} values do not say where they come from: {listed}, ...",
            allowed,
        )
        return tuple(out)
    for path in missing:
        r.report(f"sources.{path}", None, "missing: say where this value comes from", allowed)
    return tuple(out)


def _silenced(r: _Reader, data: Mapping[str, Any]) -> tuple[str, ...]:
    if "warnings" not in data:
        return ()
    sec = data["warnings"]
    if not isinstance(sec, Mapping):
        r.report("warnings", sec, f"must be a mapping {{silence: [...]}}, got {type_name(sec)}")
        return ()
    r.only_keys(sec, ("silence",), "warnings")
    ids = sec.get("silence", [])
    allowed = ", ".join(WARNINGS)
    if not isinstance(ids, list):
        r.report(
            "warnings.silence", ids, f"must be a list of warning ids, got {type_name(ids)}", allowed
        )
        return ()
    out: list[str] = []
    for index, warning_id in enumerate(ids):
        if not isinstance(warning_id, str) or warning_id not in WARNINGS:
            guess = (
                difflib.get_close_matches(warning_id, list(WARNINGS), n=1, cutoff=0.6)
                if isinstance(warning_id, str)
                else []
            )
            hint = f"; did you mean '{guess[0]}'?" if guess else ""
            r.report(f"warnings.silence[{index}]", warning_id, f"not a warning id{hint}", allowed)
            continue
        out.append(warning_id)
    return tuple(out)


@dataclass(frozen=True)
class _Parts:
    motor: Motor
    inverter: Inverter
    hall: HallSensor
    adc: Adc
    controller: Controller
    accuracy: Accuracy
    points: tuple[OperatingPoint, ...]


def _raw(data: Mapping[str, Any], path: str) -> object:
    section, _, key = path.partition(".")
    return data[section][key]


def _check_physics(r: _Reader, data: Mapping[str, Any], p: _Parts, sensing: Sensing) -> None:
    """Cross-key consistency: what makes a spec physically impossible. Exact arithmetic."""
    motor, inverter, hall, adc, controller = p.motor, p.inverter, p.hall, p.adc, p.controller
    k_e = motor.back_emf_constant_v_per_rpm
    # Above U_d / (2 k_e) the line EMF 2E exceeds the bus and the bridge diodes
    # rectify uncontrolled: PWM-OFF-PWM braking no longer controls the current
    # (paper Eq. 11 upper bound, section 4.2).
    n_limit = inverter.bus_voltage_nominal_v / (2 * k_e)
    if controller.speed_max_rpm >= n_limit:
        r.report(
            "controller.speed_max",
            _raw(data, "controller.speed_max"),
            f"at or above U_d/(2 k_e) = {_f1(n_limit)} rpm, where 2E reaches the bus voltage",
            f"< {_f1(n_limit)} rpm",
        )
    ticks_per_rpm_60deg = hall.timer_clock_hz * 60 / (6 * motor.pole_pairs)
    counter_max = 2**hall.counter_bits - 1
    slowest = ticks_per_rpm_60deg / controller.speed_min_rpm
    if slowest > counter_max:
        r.report(
            "controller.speed_min",
            _raw(data, "controller.speed_min"),
            f"its 60 deg Hall period is {float(slowest):.0f} ticks, beyond the"
            f" {hall.counter_bits}-bit counter",
            f">= {_f1(ticks_per_rpm_60deg / counter_max)} rpm at {_g(hall.timer_clock_hz)} Hz",
        )
    fastest = ticks_per_rpm_60deg / controller.speed_max_rpm
    if fastest < 64:
        r.report(
            "controller.speed_max",
            _raw(data, "controller.speed_max"),
            f"its 60 deg Hall period is only {_f1(fastest)} ticks: speed resolution worse than"
            " 1.6 %",
            f"<= {_f1(ticks_per_rpm_60deg / 64)} rpm at {_g(hall.timer_clock_hz)} Hz",
        )
    # A commutation ends at least the guard before its sector does (the next edge switches
    # on the other switch of the leg the end switched off, and the current loop takes one
    # sample in between): a sector no longer than the guard leaves no commutation at all.
    # The guard's sample (a whole PWM period and four conversions) outlasts the loop's
    # first sample after the edge, which the edge's carrier restart sets: a sector shorter
    # than that was never sampled, so the loop never ran, did not brake and starved the
    # watchdog (make pil: a 16-pole 5 kHz edge-aligned motor at 6440 rpm coasted until
    # the watchdog reset the chip; a 128-pole 1125 Hz one did not slow).
    room_s = spec_drive.end_sample_room_s(inverter.pwm_frequency_hz, sensing.adc_sample_cycles)
    guard = commutation_guard_ticks(inverter.dead_time_s, hall.timer_clock_hz, room_s)
    shift = sector_margin_shift(hall.sector_shortening)
    shortest = math.floor(fastest)  # the timer reads floor(T) or ceil(T) ticks
    if fastest >= 64 and latest_end_ticks(shortest, guard, shift) <= 0:
        guard_s = inverter.dead_time_s + COMMUTATION_END_ALLOWANCE_S + room_s
        lasting = next(t for t in range(shortest, 2**20) if latest_end_ticks(t, guard, shift) > 0)
        margin = "" if shift is None else f" and its 1/{2**shift} margin (hall.sector_shortening)"
        r.report(
            "controller.speed_max",
            _raw(data, "controller.speed_max"),
            f"its 60 deg sector ({_f1(fastest)} Hall ticks) is not longer than the {guard}-tick"
            f" guard a commutation ends by before its sector does (inverter.dead_time"
            f" {_g(inverter.dead_time_s)} s + {_g(COMMUTATION_END_ALLOWANCE_S)} s of the end's"
            f" latency + {_g(room_s)} s for one current sample: a PWM period and the ADC's"
            f" injected sequence){margin}: no commutation could last",
            f"<= {_f1(ticks_per_rpm_60deg / lasting)} rpm, or a higher PWM frequency or a"
            f" shorter dead time (the guard: {_g(guard_s)} s)",
        )
    # The Hall timer measures the speed to a tick, and a rotor at a steady speed reads
    # intervals a tick apart: a range of a few ticks reads as over-speed (an interval
    # below the one at speed_max, the safe state) at speeds inside it.
    span_ticks = slowest - fastest
    if fastest >= 64 and slowest <= counter_max and span_ticks < SPEED_RANGE_TICKS:
        r.report(
            "controller.speed_max",
            _raw(data, "controller.speed_max"),
            f"the speed range spans only {_f1(span_ticks)} Hall timer ticks of 60 deg period"
            f" ({_f1(fastest)} to {_f1(slowest)}): a rotor inside it reads outside it on a"
            " tick's jitter",
            f">= {_f1(ticks_per_rpm_60deg / (slowest - SPEED_RANGE_TICKS))} rpm, a range of"
            f" {SPEED_RANGE_TICKS} ticks at least",
        )
    # The port clocks TIM3 (the Hall timer) from the timer clock through a 16-bit prescaler.
    prescale = inverter.timer_clock_hz / hall.timer_clock_hz
    if prescale.denominator != 1 or not 1 <= prescale <= 65536:
        r.report(
            "hall.timer_clock",
            _raw(data, "hall.timer_clock"),
            f"is not the timer clock {_g(inverter.timer_clock_hz)} Hz divided by a whole"
            " prescaler (TIM3 counts the timer clock through a 16-bit prescaler)",
            f"{_g(inverter.timer_clock_hz)} Hz / N for a whole N in [1, 65536]",
        )
    bus_full_scale = adc.reference_v * adc.bus_voltage_divider
    # The over-voltage watchdog trips on a code above bus_voltage_max's (ADC1 HTR, 12
    # bits): a code must be left above it. At the full scale itself HTR would be 4096,
    # which the register cannot hold (it held 0, and the watchdog tripped at every
    # conversion: under-voltage latched at boot, the drive never armed; a hunt).
    top_code_v = bus_full_scale * (2**adc.bits - 1) / 2**adc.bits
    if inverter.bus_voltage_max_v > bus_full_scale:
        r.report(
            "inverter.bus_voltage_max",
            _raw(data, "inverter.bus_voltage_max"),
            f"beyond the ADC full scale reference x divider = {_g(bus_full_scale)} V",
            f"< {_g(top_code_v)} V",
        )
    elif inverter.bus_voltage_max_v >= top_code_v:
        r.report(
            "inverter.bus_voltage_max",
            _raw(data, "inverter.bus_voltage_max"),
            f"leaves no ADC code above it for the over-voltage watchdog (the top code,"
            f" {2**adc.bits - 1}, reads {_g(top_code_v)} V at reference x divider ="
            f" {_g(bus_full_scale)} V)",
            f"< {_g(top_code_v)} V",
        )
    # The core divides by the bus code: at the lowest bus voltage it must still resolve
    # the voltage to about 3 % (32 codes), or the duties are as coarse.
    volts_per_code = bus_full_scale / 2**adc.bits
    bus_code_min = inverter.bus_voltage_min_v / volts_per_code
    if bus_code_min < 32:
        r.report(
            "inverter.bus_voltage_min",
            _raw(data, "inverter.bus_voltage_min"),
            f"reads as only {_f1(bus_code_min)} ADC codes ({_g(volts_per_code)} V per code):"
            " the duties are computed from it, so they would be as coarse",
            f">= {_g(32 * volts_per_code)} V (32 codes)",
        )
    i_span = (adc.reference_v - adc.current_offset_v) / adc.current_gain_v_per_a
    if controller.braking_current_max_a > i_span:
        r.report(
            "controller.braking_current_max",
            _raw(data, "controller.braking_current_max"),
            f"beyond the current-sense range (reference - offset) / gain = {_g(i_span)} A",
            f"<= {_g(i_span)} A",
        )
    amps_per_code = adc.reference_v / 2**adc.bits / adc.current_gain_v_per_a
    if controller.braking_current_nominal_a < amps_per_code:
        r.report(
            "controller.braking_current_nominal",
            _raw(data, "controller.braking_current_nominal"),
            f"below one current-ADC code ({_g(amps_per_code)} A = reference / 2^bits / gain):"
            " the controller cannot tell it from zero",
            f">= {_g(amps_per_code)} A",
        )
    current_span = controller.braking_current_max_a - controller.braking_current_min_a
    # the current loop's range: its anti-windup is exercised (and needed) where the
    # largest current is codes above what D_max holds and the smallest codes below it
    if 0 < current_span < CURRENT_RANGE_CODES * amps_per_code:
        r.report(
            "controller.braking_current_max",
            _raw(data, "controller.braking_current_max"),
            f"is only {_g(current_span)} A above braking_current_min, less than"
            f" {CURRENT_RANGE_CODES} current-ADC codes ({_g(amps_per_code)} A each): too"
            " narrow a range for the current loop to resolve",
            f">= braking_current_min + {_g(CURRENT_RANGE_CODES * amps_per_code)} A",
        )
    bus_span = inverter.bus_voltage_max_v - inverter.bus_voltage_min_v
    if 0 < bus_span < volts_per_code:
        r.report(
            "inverter.bus_voltage_max",
            _raw(data, "inverter.bus_voltage_max"),
            f"is only {_g(bus_span)} V above bus_voltage_min, less than one bus-ADC code"
            f" ({_g(volts_per_code)} V): the range may hold no code",
            f">= bus_voltage_min + {_g(volts_per_code)} V",
        )
    # the analog watchdog trips below bus_voltage_min's code (rounded up) and above
    # bus_voltage_max's: a nominal bus within a code of either, or within the ADC's own
    # error beyond that, reads as a fault (a spec with bus_voltage_min = nominal latched
    # UNDER_VOLTAGE in every PIL scenario; one 1.1 codes above it, in the PIL's bus
    # noise of +-2 LSB: a hunt)
    margin = (1 + spec_drive.ADC_ERROR_LSB) * volts_per_code
    for edge, value, side in (
        ("bus_voltage_min", inverter.bus_voltage_min_v, "above"),
        ("bus_voltage_max", inverter.bus_voltage_max_v, "below"),
    ):
        if bus_span > 0 and abs(inverter.bus_voltage_nominal_v - value) < margin:
            sign = "+" if side == "above" else "-"
            r.report(
                "inverter.bus_voltage_nominal",
                _raw(data, "inverter.bus_voltage_nominal"),
                f"is within {1 + spec_drive.ADC_ERROR_LSB} bus-ADC codes ({_g(margin)} V: one"
                f" code and the ADC's +-{spec_drive.ADC_ERROR_LSB} LSB error) of {edge} ="
                f" {_g(value)} V, where the analog watchdog trips: the drive would read its"
                " nominal bus as a fault",
                f"{'>=' if side == 'above' else '<='} {edge} {sign} {_g(margin)} V",
            )
    if inverter.bus_voltage_nominal_v > Fraction(3, 2) * motor.rated_voltage_v:
        r.report(
            "inverter.bus_voltage_nominal",
            _raw(data, "inverter.bus_voltage_nominal"),
            f"more than 1.5 x the motor's rated {_g(motor.rated_voltage_v)} V",
            f"<= {_g(Fraction(3, 2) * motor.rated_voltage_v)} V",
        )
    # In braking the back-EMF drives the current: with both switches of the loop closed
    # the two conducting phases see 2E across 2R, so the largest current braking can
    # hold at speed n is I = E(n) / R = k_e n / R, whatever the bus (which only takes
    # the current back during the OFF part of the PWM). E is at most U_d/2 in the speed
    # range (checked above), so R I must stay below E(speed_max) < U_d/2.
    r_ohm = motor.phase_resistance_ohm
    e_top = k_e * controller.speed_max_rpm
    drop_nominal = r_ohm * controller.braking_current_nominal_a
    if drop_nominal > e_top:
        r.report(
            "controller.braking_current_nominal",
            _raw(data, "controller.braking_current_nominal"),
            f"R x I = {_g(r_ohm)} ohm x {_g(controller.braking_current_nominal_a)} A ="
            f" {_g(drop_nominal)} V, but in braking only the back-EMF drives the current and"
            f" E at speed_max is {_g(e_top)} V (E < U_d/2 = {_g(inverter.bus_voltage_nominal_v / 2)} V"
            " in the speed range): no speed can hold this current",
            f"<= E(speed_max)/R = {_g(e_top / r_ohm)} A",
        )
    # The averaged duty-cycle model of Eqs. 13-20 treats the current as a straight line
    # over a PWM period; an RL circuit with L/R below one period relaxes almost fully
    # within it (1 - e^-1 = 63 %), so the model, and the commutation times, do not hold.
    tau = motor.phase_inductance_h / r_ohm
    # Eq. 20 (conventional), t_com = I L / (D U_d + 2E - U_d), at the loop's steady
    # braking duty D = 1 - (2E - 2RI)/U_d: L / (2R) at every speed and current; a sector
    # lasts 10 / (p n) s, so commutations fill the sectors above n = 20 R / (p L), and
    # FILL_WARNED of them from FILL_WARNED x that speed: the loop, which samples only
    # after the commutation's end, no longer holds the current there (a 560 V 30 mH
    # motor failed its braking run at 73-87 %, a 6 V 3 mH one at 79-80 % and passed at
    # 62 %; hunts)
    filled_above = 20 / (motor.pole_pairs * tau)
    warned_above = FILL_WARNED * filled_above
    fill = controller.speed_max_rpm / filled_above
    fills = (
        f"{_g(100 * fill)} % of the sector at speed_max ({_g(100 * FILL_WARNED)} % from"
        f" {_g(warned_above)} rpm, a whole sector from 20 R/(p L) = {_g(filled_above)} rpm)"
    )
    if controller.method == "conventional" and controller.speed_max_rpm > warned_above:
        r.warn(
            "conventional-fills-sectors",
            "controller.speed_max",
            _raw(data, "controller.speed_max"),
            f"with the braking-current loop's steady duty D = 1 - (2E - 2RI)/U_d, Eq. 20"
            f" gives the conventional commutation t_com = L/(2R) = {_g(tau / 2)} s at every"
            f" speed, {fills}: each commutation runs late into its sector or to the end's"
            " guard and is cut there (TIME_CLAMPED), its outgoing current still flowing,"
            " and the loop, which samples only after the commutation, may not hold the"
            " braking current steady there (`make pil` judges it: a 380 V 25 mH motor held"
            " 0.29 A of its 1.5 A command at some edges, its main duty swinging 0.28 to"
            " 0.97; a 6 V 3 mH one at 80-93 % failed its braking run);"
            " controller.method improved ends its commutations within the sector",
        )
    if controller.method == "none" and controller.speed_max_rpm > warned_above:
        r.warn(
            "none-fills-sectors",
            "controller.speed_max",
            _raw(data, "controller.speed_max"),
            f"controller.method none keeps the loop's steady duty D = 1 - (2E - 2RI)/U_d"
            f" through the commutation, whose natural length (Eq. 20 at that duty) is"
            f" L/(2R) = {_g(tau / 2)} s at every speed, {fills}: the outgoing current"
            " flows late into the sector and the loop, which samples only after it, may"
            " not hold the braking current steady (`make pil` judges it: a 560 V 30 mH"
            " 3 ohm motor on 5 kHz centre-aligned PWM, its commutations 73-87 % of the"
            " sector, its main duty swinging 0.03 to 0.99, failed its braking run, and a"
            " 6 V 1.2 ohm 3 mH one at 79-80 %; at 62 % it passed);"
            " controller.method improved ends its commutations within the sector",
        )
    if controller.method in ("improved", "improved_r"):
        _warn_commutation_fills(r, data, motor, controller)
    periods = inverter.pwm_frequency_hz * 10 / (motor.pole_pairs * controller.speed_max_rpm)
    if periods < spec_drive.STEADY_SECTOR_PWM_PERIODS:
        steady_rpm = (
            inverter.pwm_frequency_hz
            * 10
            / (motor.pole_pairs * spec_drive.STEADY_SECTOR_PWM_PERIODS)
        )
        r.warn(
            "few-pwm-periods-per-sector",
            "controller.speed_max",
            _raw(data, "controller.speed_max"),
            f"the 60 deg sector at speed_max holds {_g(periods)} PWM periods, fewer than"
            f" {_g(spec_drive.STEADY_SECTOR_PWM_PERIODS)}: the port computes each edge's"
            " timing from the current loop's state before the previous edge, and with so"
            " few loop samples a sector the braking may lock into a two-sector cycle, or"
            " brake not at all, there (`make pil` judges it: a 1-pole-pair motor at 2.35"
            " periods held 0.21 A of its 3 A command at some edges; a 2-pole-pair one at"
            " 1.33 held 0.5 A of 5 A and slowed by 28 rpm in 0.8 s); steady up to about"
            f" {_g(steady_rpm)} rpm at this PWM frequency, or raise it",
        )
    if controller.method in ("improved", "conventional"):
        _warn_edge_emfs(r, data, motor, inverter, controller)
    period = 1 / inverter.pwm_frequency_hz
    if tau <= period:
        r.report(
            "motor.phase_inductance",
            _raw(data, "motor.phase_inductance"),
            f"gives L/R = {_g(tau)} s, not longer than the PWM period {_g(period)} s: the current"
            " relaxes within one period, so the duty-cycle model of Eqs. 13-20 does not hold",
            f"> R x T_pwm = {_g(r_ohm * period)} H",
        )
    ticks_fastest = fastest
    budget = p.accuracy.commutation_time_ticks
    if budget > ticks_fastest / 10:
        r.report(
            "accuracy.commutation_time_ticks",
            _raw(data, "accuracy.commutation_time_ticks"),
            f"is more than 10 % of the shortest 60 deg sector ({_f1(ticks_fastest)} ticks at"
            " speed_max): not an accuracy target for the commutation time",
            f"<= {_g(ticks_fastest / 10)} ticks",
        )
    for index, point in enumerate(p.points):
        if not controller.speed_min_rpm <= point.speed_rpm <= controller.speed_max_rpm:
            r.report(
                f"operating_points[{index}].speed",
                data["operating_points"][index]["speed"],
                "outside the controller speed range",
                f"[{_g(controller.speed_min_rpm)}, {_g(controller.speed_max_rpm)}] rpm",
            )


def _check_plausible(r: _Reader, data: Mapping[str, Any], p: _Parts) -> None:
    """Legal but unusual values: each a warning that the spec may silence."""
    motor, inverter, hall, adc, controller = p.motor, p.inverter, p.hall, p.adc, p.controller
    k_e = motor.back_emf_constant_v_per_rpm
    r_ohm = motor.phase_resistance_ohm
    emf_note = "in braking only the back-EMF drives the current, at most E/R"

    def speed_for(current: Fraction) -> str:
        return f"{_g(r_ohm * current / k_e)} rpm"

    e_top = k_e * controller.speed_max_rpm
    i_max = controller.braking_current_max_a
    if r_ohm * i_max > e_top:
        r.warn(
            "braking-current-max-unreachable",
            "controller.braking_current_max",
            _raw(data, "controller.braking_current_max"),
            f"R x I = {_g(r_ohm * i_max)} V exceeds E(speed_max) = {_g(e_top)} V ({emf_note}):"
            f" no speed in the range reaches {_g(i_max)} A, so the design covers currents that"
            " cannot occur",
        )
    i_nom = controller.braking_current_nominal_a
    for index, point in enumerate(p.points):
        e_point = k_e * point.speed_rpm
        if r_ohm * i_nom > e_point:
            r.warn(
                "braking-current-at-operating-point",
                f"operating_points[{index}].speed",
                data["operating_points"][index]["speed"],
                f"E = {_g(e_point)} V here, below R x braking_current_nominal ="
                f" {_g(r_ohm * i_nom)} V ({emf_note}): {_g(i_nom)} A needs at least"
                f" {speed_for(i_nom)}",
            )
    i_min = controller.braking_current_min_a
    e_bottom = k_e * controller.speed_min_rpm
    if r_ohm * i_min > e_bottom:
        r.warn(
            "braking-current-min-at-speed-min",
            "controller.braking_current_min",
            _raw(data, "controller.braking_current_min"),
            f"R x I = {_g(r_ohm * i_min)} V exceeds E(speed_min) = {_g(e_bottom)} V ({emf_note}):"
            f" below {speed_for(i_min)} no current in the designed range can be held",
        )
    amps_per_code = adc.reference_v / 2**adc.bits / adc.current_gain_v_per_a
    if i_nom < 16 * amps_per_code:
        r.warn(
            "current-resolution",
            "controller.braking_current_nominal",
            _raw(data, "controller.braking_current_nominal"),
            f"only {_f1(i_nom / amps_per_code)} current-ADC codes ({_g(amps_per_code)} A per"
            " code): the current the commutation time is computed from is quantised by more"
            " than 6 %",
        )
    tau = motor.phase_inductance_h / r_ohm
    period = 1 / inverter.pwm_frequency_hz
    if tau < 4 * period:
        r.warn(
            "time-constant-short",
            "motor.phase_inductance",
            _raw(data, "motor.phase_inductance"),
            f"L/R = {_g(tau)} s is only {_f1(tau / period)} PWM periods: the current departs"
            f" from the straight line the duty-cycle model assumes by about T/(2 L/R) ="
            f" {float(period / (2 * tau)) * 100:.0f} % within a period",
        )
    dead = inverter.dead_time_s
    if dead < Fraction(50, 10**9):
        r.warn(
            "dead-time-short",
            "inverter.dead_time",
            _raw(data, "inverter.dead_time"),
            f"{_g(dead)} s is shorter than silicon MOSFETs and their gate drivers switch off"
            " (typically 100 ns or more): risk of shoot-through",
        )
    if 2 * dead * inverter.pwm_frequency_hz > Fraction(4, 100):
        r.warn(
            "dead-time-long",
            "inverter.dead_time",
            _raw(data, "inverter.dead_time"),
            f"two dead times take {float(2 * dead * inverter.pwm_frequency_hz) * 100:.1f} % of"
            " the PWM period: every duty is distorted by as much",
        )
    if p.accuracy.duty_counts > 4:
        r.warn(
            "duty-budget-large",
            "accuracy.duty_counts",
            _raw(data, "accuracy.duty_counts"),
            "an error budget of more than 4 TIM1 counts: the rounding alone needs 1/2",
        )
    fastest = hall.timer_clock_hz * 10 / (motor.pole_pairs * controller.speed_max_rpm)
    budget = p.accuracy.commutation_time_ticks
    carrier = hall.timer_clock_hz / inverter.pwm_frequency_hz
    if (
        controller.method == "improved_r"
        and p.accuracy.ill_conditioned_above is None
        and carrier > budget
    ):
        r.warn(
            "improved-r-time-not-relaxed",
            "accuracy.commutation_time_ticks",
            _raw(data, "accuracy.commutation_time_ticks"),
            "the improved_r commutation ends on a carrier boundary, and where the turn-off"
            " current is within the core's error of zero at a boundary the end may move by"
            f" one PWM period ({_f1(carrier)} Hall ticks, more than this target): `verify`"
            " fails there. Declare accuracy.ill_conditioned_above and"
            " accuracy.ill_conditioned_counts (spec/paper_motor_improved_r.yaml: 80 and 0.1)",
        )
    if budget > fastest / 50:
        r.warn(
            "time-budget-large",
            "accuracy.commutation_time_ticks",
            _raw(data, "accuracy.commutation_time_ticks"),
            f"{float(budget / fastest) * 100:.1f} % of the shortest 60 deg sector"
            f" ({_f1(fastest)} ticks at speed_max)",
        )


def _warn_commutation_fills(
    r: _Reader, data: Mapping[str, Any], motor: Motor, controller: Controller
) -> None:
    """`commutation-fills-sectors`: an improved commutation at braking_current_max lasts a
    sector or more wherever 4E <= U_d (`spec_drive.improved_commutation_share`)."""
    k_e = motor.back_emf_constant_v_per_rpm
    share = spec_drive.improved_commutation_share(
        controller.braking_current_max_a, motor.phase_inductance_h, motor.pole_pairs, k_e
    )
    if share < 1:
        return
    fits = 20 * k_e / (motor.phase_inductance_h * motor.pole_pairs)
    r.warn(
        "commutation-fills-sectors",
        "controller.braking_current_max",
        _raw(data, "controller.braking_current_max"),
        f"an improved commutation at this current lasts t_com = I L/(2E) wherever 4E <= U_d"
        f" (Eqs. 18 and 20), I L p/(20 k_e) = {_g(share)} sectors at every such speed: it"
        " never ends within its sector, is cut at the end's guard (TIME_CLAMPED) with its"
        " outgoing current still flowing, and leaves the loop no sample of the held current"
        " (`make pil` judges it: a 20-pole-pair 3 mH 2.36 V/krpm motor with 5 A nominal,"
        " 6.4 sectors, braked with no commutation measured); a commutation within the sector needs I < 20 k_e/(p L)"
        f" = {_g(fits)} A, one within half of it (`init`'s choice) half that",
    )


def _warn_edge_emfs(
    r: _Reader, data: Mapping[str, Any], motor: Motor, inverter: Inverter, controller: Controller
) -> None:
    """The paper's methods take the EMFs at the Hall edge as (+E, -E, -E) (Eqs. 14-20);
    a shape that is not there (a sine, a flat top under 120 deg) moves the duty sum
    that holds the non-commutating current, (E/U_d)(2 e_a - e_b - e_c)/E of a PWM period."""
    shape = motor.back_emf_shape
    if shape.frozen:
        return
    edge = tuple(spec_drive.emf_at(shape, angle) for angle in EDGE_ANGLES_DEG)
    if all(abs(e - p) <= EDGE_EMF_SLACK for e, p in zip(edge, PAPER_EDGE_EMFS, strict=True)):
        return
    sigma = 2 * edge[0] - edge[1] - edge[2]
    e_top = motor.back_emf_constant_v_per_rpm * controller.speed_max_rpm
    counts = inverter.timer_clock_hz / inverter.pwm_frequency_hz
    if inverter.pwm_alignment == "center":
        counts /= 2
    moved = e_top / inverter.bus_voltage_min_v * abs(4 - sigma) * counts
    r.warn(
        "emf-shape-not-paper",
        f"motor.{spec_optional.EMF_SHAPE_KEY}",
        _raw(data, f"motor.{spec_optional.EMF_SHAPE_KEY}"),
        f"{shape.describe()}: at the Hall edge its EMFs (non-commutating, turn-off, turn-on)"
        f" are ({', '.join(f'{float(e):+.3g}' for e in edge)}) E, where the paper's Eqs."
        f" 14-20, which controller.method {controller.method} applies, take (+1, -1, -1) E:"
        f" the duty sum that holds the non-commutating current moves by (E/U_d) x"
        f" {float(abs(4 - sigma)):.3g}, {float(moved):.4g} TIM1 counts at speed_max and"
        f" bus_voltage_min, and the commutation time with it; controller.method improved_r"
        " follows a shape that is affine over the sector (the 120 deg trapezoid, flat)",
    )


def _read_bytes(file: Path, source: str) -> bytes:
    """Up to one byte past the size limit. The file is opened without blocking: a named
    pipe nothing writes to had held open() for ever; it now reads as empty (a pipe with
    a writer, `cat spec.yaml | bldc-codegen generate /dev/stdin`, reads as before)."""
    try:
        descriptor = os.open(file, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0))
        try:
            if hasattr(os, "set_blocking"):
                os.set_blocking(descriptor, True)
            stream = os.fdopen(descriptor, "rb")
        except BaseException:
            os.close(descriptor)
            raise
        with stream:
            raw = stream.read(DEFAULT_LIMITS.max_bytes + 1)
    except OSError as exc:
        reason = exc.strerror or type(exc).__name__
        raise MultiSpecError([SpecError("<file>", source, f"cannot read spec: {reason}")]) from None
    return raw


def load_spec(path: str | Path) -> Spec:
    """Load, validate and freeze a spec file; MultiSpecError lists every problem found."""
    file = Path(path)
    # every error starts with the file, on the one line that is the error's: a name
    # with a line break in it ('bad\nspec.yaml') is quoted, as Python writes it
    source = on_one_line(str(path))
    raw_bytes = _read_bytes(file, source)
    try:
        data, lines = read_yaml(raw_bytes)
    except YamlError as exc:
        raise MultiSpecError(
            [
                SpecError(
                    exc.path or "<document>", NOT_READ, exc.problem, exc.allowed, source, exc.line
                )
            ]
        ) from None
    if not isinstance(data, Mapping):
        raise MultiSpecError(
            [
                SpecError(
                    "<document>",
                    data,
                    f"the spec must be a YAML mapping of sections, got {type_name(data)}",
                    "",
                    source,
                    1,
                )
            ]
        )
    r = _Reader(source, lines)
    r.only_keys(data, _TOP_KEYS, "", (*_OPTIONAL_TOP_KEYS, spec_optional.TOLERANCES_KEY))
    name = r.attempt(lambda: r.raw(data, "name", "", "[a-z][a-z0-9_]{0,63}"))
    if "name" in data and (not isinstance(name, str) or not _NAME.match(name)):
        r.report("name", name, "must be a lower-case identifier", "[a-z][a-z0-9_]{0,63}")
    elif name == PAPER_AUDIT_NAME:
        r.report(
            "name",
            name,
            "is reserved: generated/paper/ holds the paper's audit",
            "any other lower-case identifier",
        )
    description = r.attempt(
        lambda: r.raw(
            data, "description", "", f"a string of <= {_MAX_DESCRIPTION_CHARS} characters"
        )
    )
    if "description" in data:
        if not isinstance(description, str):
            r.report(
                "description",
                description,
                f"must be a string, got {type_name(description)}",
                f"a string of <= {_MAX_DESCRIPTION_CHARS} characters",
            )
        elif len(description) > _MAX_DESCRIPTION_CHARS:
            r.report(
                "description",
                description,
                f"a description of {len(description)} characters",
                f"<= {_MAX_DESCRIPTION_CHARS}",
            )
        elif (hidden := _hidden_character(description)) is not None:
            r.report(
                "description",
                description,
                f"holds the invisible or control character {hidden}",
                "printable text (a right-to-left override had been accepted and printed into"
                " DERIVATION.md)",
            )
    motor = _motor(r, data)
    inverter = _inverter(r, data)
    hall = _hall(r, data)
    adc = _adc(r, data)
    controller = _controller(r, data)
    accuracy = _accuracy(r, data)
    points = _operating_points(r, data)
    sensing = spec_drive.read_sensing(r, data, _Range)
    current_loop = spec_drive.read_current_loop(r, data, _Range)
    protection = spec_drive.read_protection(r, data, _Range)
    firmware = spec_drive.read_firmware(r, data, _Range)
    sources = _sources(r, data)
    silenced = _silenced(r, data)
    tolerances = None
    if spec_optional.TOLERANCES_KEY in data:
        # read without a valid inverter too: each bad pair is named with its range
        tolerances = r.attempt(
            lambda: spec_optional.tolerances(r, data[spec_optional.TOLERANCES_KEY], inverter)
        )
    reported = {error.path for error in r.errors}
    for where, value in unreadable_values(data):
        # a value too long to read that no reader refused under its own key
        if not any(
            where == path or where.startswith((f"{path}.", f"{path}[")) for path in reported
        ):
            r.report(where, value, f"is {value.problem}")
    if r.errors:
        raise MultiSpecError(r.errors)
    parts = _Parts(motor, inverter, hall, adc, controller, accuracy, points)  # type: ignore[arg-type]
    assert sensing and current_loop and protection and firmware  # else r.errors
    _check_physics(r, data, parts, sensing)
    if r.errors:
        raise MultiSpecError(r.errors)
    spec_drive.check_drive(
        r,
        data,
        motor=parts.motor,
        hall=parts.hall,
        tolerances=tolerances,
        inverter=parts.inverter,
        adc=parts.adc,
        controller=parts.controller,
        points=parts.points,
        sensing=sensing,
        current_loop=current_loop,
        protection=protection,
        firmware=firmware,
    )
    if r.errors:
        raise MultiSpecError(r.errors)
    _check_plausible(r, data, parts)
    return Spec(
        name=name,  # type: ignore[arg-type]
        description=description,  # type: ignore[arg-type]
        source_path=str(path),
        sha256=hashlib.sha256(raw_bytes).hexdigest(),
        motor=parts.motor,
        inverter=parts.inverter,
        hall=parts.hall,
        adc=parts.adc,
        controller=parts.controller,
        accuracy=parts.accuracy,
        operating_points=parts.points,
        sensing=sensing,
        current_loop=current_loop,
        protection=protection,
        firmware=firmware,
        sources=sources,  # type: ignore[arg-type]
        tolerances=tolerances,
        warnings=tuple(w for w in r.warnings if w.id not in silenced),
        silenced_warnings=silenced,
    )


__all__ = ["MAX_OPERATING_POINTS", "PAPER_AUDIT_NAME", "WARNINGS", "load_spec"]

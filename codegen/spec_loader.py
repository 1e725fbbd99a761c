"""The one place where a spec is checked.

load_spec() reads YAML with yaml.safe_load semantics (plus duplicate-key rejection),
rejects unknown keys, converts every quantity to SI, checks each value against its
allowed range, then checks the physics that ties the values together. It returns a
frozen codegen.spec_model.Spec or raises codegen.errors.SpecError naming the key path,
the value, the unit and the allowed range (and the YAML line where known).
"""

from __future__ import annotations

import hashlib
import math
import re
from collections.abc import Mapping
from dataclasses import dataclass
from decimal import Context, Decimal
from fractions import Fraction
from pathlib import Path
from typing import Any

import yaml

from codegen import spec_optional, units
from codegen.errors import SpecError
from codegen.spec_model import (
    COMMUTATION_METHODS,
    Accuracy,
    Adc,
    BackEmfShape,
    Controller,
    HallSensor,
    Inverter,
    Motor,
    OperatingPoint,
    Spec,
)

_NAME = re.compile(r"^[a-z][a-z0-9_]{0,63}$")
#: generated/<this>/ is the paper audit's folder (codegen.audit), never a motor's.
PAPER_AUDIT_NAME = "paper"


class _StrictLoader(yaml.SafeLoader):
    """safe_load that refuses duplicate keys instead of keeping the last one."""


def _construct_mapping(loader: _StrictLoader, node: yaml.MappingNode) -> dict[Any, Any]:
    seen: dict[Any, int] = {}
    for key_node, _ in node.value:
        key = loader.construct_object(key_node)
        try:
            duplicate = key in seen
        except TypeError:
            raise yaml.constructor.ConstructorError(
                None, None, "found unhashable key", key_node.start_mark
            ) from None
        if duplicate:
            raise yaml.constructor.ConstructorError(
                None,
                None,
                f"duplicate key {key!r} (first defined on line {seen[key]})",
                key_node.start_mark,
            )
        seen[key] = key_node.start_mark.line + 1
    return loader.construct_mapping(node)


_StrictLoader.add_constructor(yaml.resolver.BaseResolver.DEFAULT_MAPPING_TAG, _construct_mapping)


@dataclass(frozen=True)
class _Range:
    """Allowed interval of a value in SI, shown to the user in `unit`."""

    low: float | None
    high: float | None
    unit: str
    low_inclusive: bool = True
    high_inclusive: bool = True

    def contains(self, value: float) -> bool:
        if self.low is not None and (
            value < self.low or (value == self.low and not self.low_inclusive)
        ):
            return False
        return not (
            self.high is not None
            and (value > self.high or (value == self.high and not self.high_inclusive))
        )

    def describe(self) -> str:
        left = "[" if self.low_inclusive else "("
        right = "]" if self.high_inclusive else ")"
        low = "-inf" if self.low is None else _g(self.low)
        high = "inf" if self.high is None else _g(self.high)
        return f"{left}{low}, {high}{right} {self.unit}".rstrip()


def _g(value: float | Fraction) -> str:
    """%g of an int, float or Fraction; exact Fractions too large for a float still print."""
    try:
        return f"{float(value):g}"
    except OverflowError:
        exact = Context(prec=6).divide(Decimal(value.numerator), Decimal(value.denominator))
        return f"{exact.normalize():g}"


def _positive(high: float, unit: str) -> _Range:
    return _Range(0.0, high, unit, low_inclusive=False)


class _Reader:
    """Walks one parsed document, remembering YAML lines so errors can cite them."""

    def __init__(self, source: str, lines: Mapping[str, int]) -> None:
        self.source = source
        self.lines = lines

    def error(self, path: str, value: object, problem: str, allowed: str = "") -> SpecError:
        return SpecError(path, value, problem, allowed, self.source, self.lines.get(path))

    def section(self, data: Mapping[str, Any], key: str, parent: str = "") -> Mapping[str, Any]:
        path = f"{parent}.{key}" if parent else key
        if key not in data:
            raise self.error(path, None, "missing required section", "a mapping")
        value = data[key]
        if not isinstance(value, Mapping):
            raise self.error(path, value, f"must be a mapping, got {type(value).__name__}")
        return value

    def only_keys(self, data: Mapping[str, Any], allowed: tuple[str, ...], path: str) -> None:
        for key in data:
            if key not in allowed:
                where = f"{path}.{key}" if path else str(key)
                raise self.error(where, data[key], "unknown key", ", ".join(allowed))
        for key in allowed:
            if key not in data:
                where = f"{path}.{key}" if path else key
                raise self.error(where, None, "missing required key", "see spec/paper_motor.yaml")

    def quantity(
        self, data: Mapping[str, Any], key: str, path: str, dim: units.Dimension, rng: _Range
    ) -> Fraction:
        where = f"{path}.{key}"
        raw = data[key]
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
        raw = data[key]
        if (
            isinstance(raw, bool)
            or not isinstance(raw, (int, float))
            or (isinstance(raw, float) and not math.isfinite(raw))
        ):
            raise self.error(where, raw, "must be a plain number", rng.describe())
        if not rng.contains(raw):
            raise self.error(where, raw, "out of range", rng.describe())
        return Fraction(str(raw))

    def integer(self, data: Mapping[str, Any], key: str, path: str, rng: _Range) -> int:
        where = f"{path}.{key}"
        raw = data[key]
        if isinstance(raw, bool) or not isinstance(raw, int):
            raise self.error(where, raw, "must be an integer", rng.describe())
        if not rng.contains(raw):
            raise self.error(where, raw, "out of range", rng.describe())
        return raw

    def choice(self, data: Mapping[str, Any], key: str, path: str, options: tuple[str, ...]) -> str:
        raw = data[key]
        if raw not in options:
            raise self.error(f"{path}.{key}", raw, "not a known option", ", ".join(options))
        return str(raw)


def _yaml_lines(text: str) -> dict[str, int]:
    """Key path -> 1-based line of the value, for error messages."""
    lines: dict[str, int] = {}
    try:
        root = yaml.compose(text, Loader=_StrictLoader)
    except yaml.YAMLError:
        return lines

    def walk(node: yaml.Node, path: str, ancestors: frozenset[int]) -> None:
        if path:
            lines[path] = node.start_mark.line + 1
        if id(node) in ancestors:  # a recursive alias such as `&x [*x]`
            return
        inner = ancestors | {id(node)}
        if isinstance(node, yaml.MappingNode):
            for key_node, value_node in node.value:
                key = str(key_node.value)
                walk(value_node, f"{path}.{key}" if path else key, inner)
        elif isinstance(node, yaml.SequenceNode):
            for index, item in enumerate(node.value):
                walk(item, f"{path}[{index}]", inner)

    if root is not None:
        walk(root, "", frozenset())
    return lines


def _parse_yaml(text: str, source: str) -> Mapping[str, Any]:
    try:
        data = yaml.load(text, Loader=_StrictLoader)
    except yaml.MarkedYAMLError as exc:
        mark = exc.problem_mark or exc.context_mark
        line = mark.line + 1 if mark is not None else None
        problem = exc.problem or str(exc)
        raise SpecError(
            "<document>", None, f"malformed YAML: {problem}", "", source, line
        ) from None
    except yaml.YAMLError as exc:
        raise SpecError("<document>", None, f"malformed YAML: {exc}", "", source) from None
    if not isinstance(data, Mapping):
        raise SpecError("<document>", data, "the spec must be a YAML mapping", "", source, 1)
    return data


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
    "sources",
)


def _motor(r: _Reader, data: Mapping[str, Any]) -> Motor:
    sec = r.section(data, "motor")
    keys = (
        "rated_voltage",
        "phase_resistance",
        "phase_inductance",
        "poles",
        "back_emf_constant",
        "back_emf_convention",
        "rotor_inertia",
    )
    r.only_keys({k: v for k, v in sec.items() if k != spec_optional.EMF_SHAPE_KEY}, keys, "motor")
    poles = r.integer(sec, "poles", "motor", _Range(2, 128, "poles"))
    if poles % 2:
        raise r.error(
            "motor.poles", poles, "a rotor has an even number of poles", "2, 4, 6, ... 128"
        )
    convention = r.choice(sec, "back_emf_convention", "motor", ("phase", "line_to_line"))
    k_e = r.quantity(sec, "back_emf_constant", "motor", units.EMF_CONSTANT, _positive(1.0, "V/rpm"))
    if convention == "line_to_line":
        # Flat-top line-to-line EMF of the two conducting phases is 2E (paper Eq. 4).
        k_e /= 2
    return Motor(
        rated_voltage_v=r.quantity(
            sec, "rated_voltage", "motor", units.VOLTAGE, _positive(1000, "V")
        ),
        phase_resistance_ohm=r.quantity(
            sec, "phase_resistance", "motor", units.RESISTANCE, _positive(100, "ohm")
        ),
        phase_inductance_h=r.quantity(
            sec, "phase_inductance", "motor", units.INDUCTANCE, _positive(1.0, "H")
        ),
        poles=poles,
        back_emf_constant_v_per_rpm=k_e,
        back_emf_convention=convention,  # type: ignore[arg-type]
        rotor_inertia_kg_m2=r.quantity(
            sec, "rotor_inertia", "motor", units.INERTIA, _positive(100, "kg*m^2")
        ),
        back_emf_shape=spec_optional.back_emf_shape(r, sec[spec_optional.EMF_SHAPE_KEY])
        if spec_optional.EMF_SHAPE_KEY in sec
        else BackEmfShape(),
    )


def _inverter(r: _Reader, data: Mapping[str, Any]) -> Inverter:
    sec = r.section(data, "inverter")
    keys = (
        "bus_voltage_nominal",
        "bus_voltage_min",
        "bus_voltage_max",
        "pwm_frequency",
        "pwm_alignment",
        "timer_clock",
        "dead_time",
    )
    r.only_keys(sec, keys, "inverter")
    volts = _positive(1000, "V")
    v_nom = r.quantity(sec, "bus_voltage_nominal", "inverter", units.VOLTAGE, volts)
    v_min = r.quantity(sec, "bus_voltage_min", "inverter", units.VOLTAGE, volts)
    v_max = r.quantity(sec, "bus_voltage_max", "inverter", units.VOLTAGE, volts)
    if not v_min < v_max:
        raise r.error(
            "inverter.bus_voltage_max",
            sec["bus_voltage_max"],
            "bus voltage range is empty or inverted",
            f"> bus_voltage_min = {float(v_min):g} V",
        )
    if not v_min <= v_nom <= v_max:
        raise r.error(
            "inverter.bus_voltage_nominal",
            sec["bus_voltage_nominal"],
            "nominal bus voltage outside the operating range",
            f"[{float(v_min):g}, {float(v_max):g}] V",
        )
    timer_clock = r.quantity(
        sec, "timer_clock", "inverter", units.FREQUENCY, _Range(1e6, 72e6, "Hz")
    )
    f_pwm = r.quantity(sec, "pwm_frequency", "inverter", units.FREQUENCY, _Range(1e3, 100e3, "Hz"))
    alignment = r.choice(sec, "pwm_alignment", "inverter", ("edge", "center"))
    period_counts = timer_clock / f_pwm / (2 if alignment == "center" else 1)
    if not 256 <= period_counts <= 65536 or period_counts.denominator != 1:
        raise r.error(
            "inverter.pwm_frequency",
            sec["pwm_frequency"],
            f"gives {float(period_counts):g} TIM1 counts per period at {float(timer_clock):g} Hz"
            f" ({alignment})",
            "a whole number of counts in [256, 65536]",
        )
    dead = r.quantity(sec, "dead_time", "inverter", units.TIME, _Range(0.0, 5e-6, "s"))
    if dead * f_pwm * 2 >= Fraction(1, 10):
        raise r.error(
            "inverter.dead_time",
            sec["dead_time"],
            "dead time eats more than 10 % of the PWM period",
            f"< {0.05 / float(f_pwm):g} s at {float(f_pwm):g} Hz",
        )
    return Inverter(
        bus_voltage_nominal_v=v_nom,
        bus_voltage_min_v=v_min,
        bus_voltage_max_v=v_max,
        pwm_frequency_hz=f_pwm,
        pwm_alignment=alignment,  # type: ignore[arg-type]
        timer_clock_hz=timer_clock,
        dead_time_s=dead,
    )


def _hall_sequence(r: _Reader, raw: object) -> tuple[int, ...]:
    path = "hall.sequence"
    allowed = "six distinct codes 1..6, consecutive codes differing in exactly one bit"
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


def _hall(r: _Reader, data: Mapping[str, Any]) -> HallSensor:
    sec = r.section(data, "hall")
    r.only_keys(sec, ("sequence", "timer_clock", "counter_bits"), "hall")
    bits = r.integer(sec, "counter_bits", "hall", _Range(16, 16, "bits"))
    return HallSensor(
        sequence=_hall_sequence(r, sec["sequence"]),
        timer_clock_hz=r.quantity(
            sec, "timer_clock", "hall", units.FREQUENCY, _Range(1e3, 72e6, "Hz")
        ),
        counter_bits=bits,
    )


def _adc(r: _Reader, data: Mapping[str, Any]) -> Adc:
    sec = r.section(data, "adc")
    keys = ("bits", "reference", "bus_voltage_divider", "current_gain", "current_offset")
    r.only_keys(sec, keys, "adc")
    reference = r.quantity(sec, "reference", "adc", units.VOLTAGE, _positive(5.0, "V"))
    return Adc(
        bits=r.integer(sec, "bits", "adc", _Range(8, 16, "bits")),
        reference_v=reference,
        bus_voltage_divider=r.number(sec, "bus_voltage_divider", "adc", _Range(1, 1000, "(V/V)")),
        current_gain_v_per_a=r.quantity(
            sec, "current_gain", "adc", units.TRANSRESISTANCE, _positive(10.0, "V/A")
        ),
        current_offset_v=r.quantity(
            sec, "current_offset", "adc", units.VOLTAGE, _Range(0.0, reference, "V")
        ),
    )


def _controller(r: _Reader, data: Mapping[str, Any]) -> Controller:
    sec = r.section(data, "controller")
    keys = (
        "method",
        "braking_current_min",
        "braking_current_nominal",
        "braking_current_max",
        "speed_min",
        "speed_max",
    )
    r.only_keys(sec, keys, "controller")
    amps = _Range(0.0, 1000.0, "A")
    i_min = r.quantity(sec, "braking_current_min", "controller", units.CURRENT, amps)
    i_nom = r.quantity(sec, "braking_current_nominal", "controller", units.CURRENT, amps)
    i_max = r.quantity(sec, "braking_current_max", "controller", units.CURRENT, amps)
    if not i_min < i_max:
        raise r.error(
            "controller.braking_current_max",
            sec["braking_current_max"],
            "braking current range is empty or inverted",
            f"> braking_current_min = {float(i_min):g} A",
        )
    if not i_min <= i_nom <= i_max:
        raise r.error(
            "controller.braking_current_nominal",
            sec["braking_current_nominal"],
            "nominal braking current outside its range",
            f"[{float(i_min):g}, {float(i_max):g}] A",
        )
    if i_nom <= 0.0:
        raise r.error(
            "controller.braking_current_nominal",
            sec["braking_current_nominal"],
            "braking needs a current",
            f"(0, {float(i_max):g}] A",
        )
    speeds = _positive(1e6, "rpm")
    n_min = r.quantity(sec, "speed_min", "controller", units.SPEED, speeds)
    n_max = r.quantity(sec, "speed_max", "controller", units.SPEED, speeds)
    if not n_min < n_max:
        raise r.error(
            "controller.speed_max",
            sec["speed_max"],
            "speed range is empty or inverted",
            f"> speed_min = {float(n_min):g} rpm",
        )
    return Controller(
        method=r.choice(sec, "method", "controller", COMMUTATION_METHODS),  # type: ignore[arg-type]
        braking_current_min_a=i_min,
        braking_current_nominal_a=i_nom,
        braking_current_max_a=i_max,
        speed_min_rpm=n_min,
        speed_max_rpm=n_max,
    )


_RELAXATION = ("ill_conditioned_above", "ill_conditioned_counts")


def _accuracy(r: _Reader, data: Mapping[str, Any]) -> Accuracy:
    sec = r.section(data, "accuracy")
    present = tuple(k for k in _RELAXATION if k in sec)
    r.only_keys(sec, ("duty_counts", "commutation_time_ticks", *present), "accuracy")
    if len(present) == 1:
        missing = next(k for k in _RELAXATION if k not in present)
        raise r.error(
            f"accuracy.{missing}",
            None,
            f"missing: accuracy.{present[0]} declares a relaxation, which needs both keys",
            "both ill_conditioned_above (ticks per count) and ill_conditioned_counts (counts), or neither",
        )
    above = counts = None
    if present:
        above = r.number(
            sec, "ill_conditioned_above", "accuracy", _Range(1, 1e6, "Hall ticks per TIM1 count")
        )
        counts = r.number(
            sec, "ill_conditioned_counts", "accuracy", _Range(0.001, 4, "TIM1 counts")
        )
    return Accuracy(
        duty_counts=r.number(sec, "duty_counts", "accuracy", _Range(0.5, 64, "TIM1 counts")),
        commutation_time_ticks=r.number(
            sec, "commutation_time_ticks", "accuracy", _Range(0.5, 1024, "Hall timer ticks")
        ),
        ill_conditioned_above=above,
        ill_conditioned_counts=counts,
    )


def _operating_points(r: _Reader, data: Mapping[str, Any]) -> tuple[OperatingPoint, ...]:
    raw = data["operating_points"]
    if not isinstance(raw, list):
        raise r.error("operating_points", raw, "must be a list of {speed, main_duty}")
    points = []
    for index, item in enumerate(raw):
        path = f"operating_points[{index}]"
        if not isinstance(item, Mapping):
            raise r.error(path, item, "must be a mapping {speed, main_duty}")
        r.only_keys(item, ("speed", "main_duty"), path)
        points.append(
            OperatingPoint(
                speed_rpm=r.quantity(item, "speed", path, units.SPEED, _positive(1e6, "rpm")),
                main_duty=r.number(item, "main_duty", path, _Range(0.0, 1.0, "")),
            )
        )
    return tuple(points)


def _sources(
    r: _Reader, data: Mapping[str, Any], lines: Mapping[str, int]
) -> tuple[tuple[str, str], ...]:
    raw = data["sources"]
    if not isinstance(raw, Mapping):
        raise r.error("sources", raw, "must map key paths to where each value comes from")
    out = []
    for key, text in raw.items():
        if not isinstance(text, str) or not text.strip():
            raise r.error(f"sources.{key}", text, "must be a non-empty description")
        if key not in lines or key.startswith("sources"):
            raise r.error(f"sources.{key}", text, "names a key that the spec does not have")
        out.append((str(key), text))
    return tuple(out)


def _check_physics(
    r: _Reader,
    data: Mapping[str, Any],
    motor: Motor,
    inverter: Inverter,
    hall: HallSensor,
    adc: Adc,
    controller: Controller,
    points: tuple[OperatingPoint, ...],
) -> None:
    """Cross-key consistency: what makes a spec physically impossible."""
    k_e = float(motor.back_emf_constant_v_per_rpm)
    # Above U_d / (2 k_e) the line EMF 2E exceeds the bus and the bridge diodes
    # rectify uncontrolled: PWM-OFF-PWM braking no longer controls the current
    # (paper Eq. 11 upper bound, section 4.2).
    n_limit = float(inverter.bus_voltage_nominal_v) / (2.0 * k_e)
    if controller.speed_max_rpm >= n_limit:
        raise r.error(
            "controller.speed_max",
            data["controller"]["speed_max"],
            f"at or above U_d/(2 k_e) = {n_limit:.1f} rpm, where 2E reaches the bus voltage",
            f"< {n_limit:.1f} rpm",
        )
    pole_pairs = motor.pole_pairs
    ticks_per_rpm_60deg = float(hall.timer_clock_hz) * 60.0 / (6.0 * pole_pairs)
    slowest = ticks_per_rpm_60deg / controller.speed_min_rpm
    counter_max = 2**hall.counter_bits - 1
    if slowest > counter_max:
        raise r.error(
            "controller.speed_min",
            data["controller"]["speed_min"],
            f"its 60 deg Hall period is {slowest:.0f} ticks, beyond the {hall.counter_bits}-bit counter",
            f">= {ticks_per_rpm_60deg / counter_max:.1f} rpm at {_g(hall.timer_clock_hz)} Hz",
        )
    fastest = ticks_per_rpm_60deg / controller.speed_max_rpm
    if fastest < 64:
        raise r.error(
            "controller.speed_max",
            data["controller"]["speed_max"],
            f"its 60 deg Hall period is only {fastest:.1f} ticks: speed resolution worse than 1.6 %",
            f"<= {ticks_per_rpm_60deg / 64:.1f} rpm at {_g(hall.timer_clock_hz)} Hz",
        )
    bus_full_scale = float(adc.reference_v * adc.bus_voltage_divider)
    if inverter.bus_voltage_max_v > bus_full_scale:
        raise r.error(
            "inverter.bus_voltage_max",
            data["inverter"]["bus_voltage_max"],
            f"beyond the ADC full scale reference x divider = {bus_full_scale:g} V",
            f"<= {bus_full_scale:g} V",
        )
    i_span = float((adc.reference_v - adc.current_offset_v) / adc.current_gain_v_per_a)
    if controller.braking_current_max_a > i_span:
        raise r.error(
            "controller.braking_current_max",
            data["controller"]["braking_current_max"],
            f"beyond the current-sense range (reference - offset) / gain = {i_span:g} A",
            f"<= {i_span:g} A",
        )
    if inverter.bus_voltage_nominal_v > 1.5 * motor.rated_voltage_v:
        raise r.error(
            "inverter.bus_voltage_nominal",
            data["inverter"]["bus_voltage_nominal"],
            f"more than 1.5 x the motor's rated {float(motor.rated_voltage_v):g} V",
            f"<= {1.5 * float(motor.rated_voltage_v):g} V",
        )
    for index, point in enumerate(points):
        if not controller.speed_min_rpm <= point.speed_rpm <= controller.speed_max_rpm:
            raise r.error(
                f"operating_points[{index}].speed",
                data["operating_points"][index]["speed"],
                "outside the controller speed range",
                f"[{float(controller.speed_min_rpm):g}, {float(controller.speed_max_rpm):g}] rpm",
            )


def load_spec(path: str | Path) -> Spec:
    """Load, validate and freeze a spec file."""
    file = Path(path)
    source = str(path)
    try:
        raw_bytes = file.read_bytes()
    except OSError as exc:
        raise SpecError("<file>", source, f"cannot read spec: {exc.strerror}") from None
    try:
        text = raw_bytes.decode("utf-8")
    except UnicodeDecodeError:
        raise SpecError("<file>", source, "spec is not UTF-8 text") from None
    data = _parse_yaml(text, source)
    lines = _yaml_lines(text)
    r = _Reader(source, lines)
    r.only_keys({k: v for k, v in data.items() if k != spec_optional.TOLERANCES_KEY}, _TOP_KEYS, "")
    name = data["name"]
    if not isinstance(name, str) or not _NAME.fullmatch(name):
        raise r.error("name", name, "must be a lower-case identifier", "[a-z][a-z0-9_]{0,63}")
    if name == PAPER_AUDIT_NAME:
        raise r.error(
            "name",
            name,
            "is reserved: generated/paper/ holds the paper's audit",
            "any other lower-case identifier",
        )
    description = data["description"]
    if not isinstance(description, str):
        raise r.error("description", description, "must be a string")
    motor = _motor(r, data)
    inverter = _inverter(r, data)
    hall = _hall(r, data)
    adc = _adc(r, data)
    controller = _controller(r, data)
    accuracy = _accuracy(r, data)
    points = _operating_points(r, data)
    sources = _sources(r, data, lines)
    _check_physics(r, data, motor, inverter, hall, adc, controller, points)
    tolerances = (
        spec_optional.tolerances(r, data[spec_optional.TOLERANCES_KEY], inverter)
        if spec_optional.TOLERANCES_KEY in data
        else None
    )
    return Spec(
        name=name,
        description=description,
        source_path=source,
        sha256=hashlib.sha256(raw_bytes).hexdigest(),
        motor=motor,
        inverter=inverter,
        hall=hall,
        adc=adc,
        controller=controller,
        accuracy=accuracy,
        operating_points=points,
        sources=sources,
        tolerances=tolerances,
    )

"""`bldc-codegen init`: a commented spec for a new motor, from datasheet values.

Datasheets quote what is easy to measure at the terminals; the spec wants what the
paper's equations use. The conversions (a star-connected winding is assumed, as the
paper's Eq. 1 does):

* resistance and inductance measured line to line are two phases in series, so the
  phase value is half;
* a line-to-line back-EMF constant is 2 k_e (two conducting phases, Eq. 4, on the
  default 120 deg trapezoid); the spec keeps the datasheet's number with
  `back_emf_convention: line_to_line` and the loader divides it by the shape's peak
  line-to-line factor (2 here);
* a speed constant Kv in rpm/V gives the line-to-line constant 1/Kv (the no-load speed
  per volt of the six-step bus is the speed per volt of line-to-line flat-top EMF);
* pole pairs are poles / 2.

Every conversion and every value not given is recorded in `sources`; values not given
are the paper motor's or derived from the ones given (speed range, Hall timer clock,
ADC scaling), marked 'assumption:'. The written spec is loaded once to report at once
what still does not fit.
"""

from __future__ import annotations

import argparse
import math
import re
from collections.abc import Callable
from dataclasses import dataclass, replace
from fractions import Fraction
from pathlib import Path

from codegen import units
from codegen.argtypes import not_a_number, plain_decimal
from codegen.dead_time import (
    COMMUTATION_END_ALLOWANCE_S,
    SECTOR_SHORTENING_DEFAULT_PERCENT,
    sector_margin_shift,
)
from codegen.errors import SpecError, show_value
from codegen.render import write_atomically
from codegen.spec_drive import (
    INIT_COMMUTATION_SHARE,
    PROTECTION_AMPS_MAX,
    STEADY_SECTOR_PWM_PERIODS,
    braking_current_peak,
    braking_ripple,
    end_sample_room_s,
    improved_commutation_share,
    rectifying_speed,
    said_speed_factor,
    sense_window,
    short_circuit_peak,
)
from codegen.spec_loader import (
    CURRENT_RANGE_CODES,
    DATASHEET_RANGES,
    PAPER_AUDIT_NAME,
    PERIOD_COUNTS_MAX,
    load_spec,
    out_of_range,
)
from codegen.spec_model import (
    COMMUTATION_METHODS,
    LOOP_DUTY_COUNTS_MAX,
    BackEmfShape,
    Spec,
    SpecWarning,
)

TIMER_CLOCK_HZ = 72_000_000
#: --speed-max at least: init's upper operating point, 90 % of it rounded down to 0.1
#: rpm, must be the 1 rpm a spec's speeds start at (1 rpm wrote a point at 0.9 rpm)
SPEED_MAX_LOWEST_RPM = Fraction(12, 10)
#: Slower Hall timer clocks, fastest first (72 MHz / N, N up to 64000 in TIM3's 16-bit
#: prescaler): for a top speed of a few rpm, where the counter fills at 100 kHz
SLOW_HALL_CLOCKS_HZ = (72_000, 36_000, 18_000, 9_000, 4_500, 2_250, 1_125)
#: Hall timer clocks that divide the 72 MHz timer clock, slowest first.
HALL_CLOCKS_HZ = (
    100_000,
    250_000,
    500_000,
    1_000_000,
    2_000_000,
    4_000_000,
    6_000_000,
    8_000_000,
    12_000_000,
    18_000_000,
    24_000_000,
    36_000_000,
    72_000_000,
)
ADC_REFERENCE_V = Fraction(33, 10)
#: the smallest braking_current_nominal init writes (its sensing: at most 500 mV/A)
BRAKING_CURRENT_MIN_A = Fraction(1, 10)
#: the largest: init writes braking_current_max as twice it, within the loader's range
BRAKING_CURRENT_MAX_A = (
    Fraction(str(DATASHEET_RANGES["controller.braking_current_nominal"].high)) / 2
)
#: the ADC sample time written (sensing.adc_sample_time), ADC clock cycles
SAMPLE_CYCLES = Fraction(15, 2)
#: the settling time written (sensing.settling_time)
SETTLING_TIME_S = Fraction(1, 10**6)
COUNTER_MAX = 65535


#: where `controller.method` comes from, per method `init --method` can write
METHOD_SOURCES = {
    "improved": "paper Eq. 18 (the proposed method)",
    "improved_r": "bldc-codegen init --method improved_r: the resistance-aware rule",
    "conventional": "bldc-codegen init --method conventional: the paper's conventional"
    " PWM-OFF-PWM commutation (its baseline)",
    "none": "bldc-codegen init --method none: no commutation compensation",
}


def _quantity(
    dimension: units.Dimension,
    key: str,
    per_phase: bool = False,
    minimum: tuple[Fraction, str, str] | None = None,
    maximum: tuple[Fraction, str, str] | None = None,
) -> Callable[[str], tuple[Fraction, str]]:
    """argparse type: a positive quantity whose spec value (the phase value, half of it,
    where `per_phase` converts a line-to-line one) is within the loader's range for `key`:
    a value no spec can hold (1e400 ohm) is said at its argument, not met later as a
    float overflow inside init or as an error about a value derived from it. `minimum`
    (SI value, as shown, why) is init's own lower bound, where it would write another
    value than the one given; `maximum` its upper bound, where a value init derives from
    this one would leave the loader's range."""

    def parse(text: str) -> tuple[Fraction, str]:
        try:
            value = units.parse_quantity(text, dimension).si_value
        except units.QuantityError as exc:
            raise argparse.ArgumentTypeError(str(exc)) from None
        if value <= 0:  # every datasheet value init takes is a positive quantity
            raise argparse.ArgumentTypeError(
                f"{text!r} is out of range (allowed: > 0, a quantity of {dimension.name})"
            )
        if minimum is not None and value < minimum[0]:
            raise argparse.ArgumentTypeError(
                f"{text!r} is below {minimum[1]}, {minimum[2]} (allowed: >= {minimum[1]})"
            )
        if maximum is not None and value > maximum[0]:
            raise argparse.ArgumentTypeError(
                f"{text!r} is above {maximum[1]}, {maximum[2]} (allowed: <= {maximum[1]})"
            )
        why = out_of_range(key, value / 2 if per_phase else value)
        if why is not None:
            half = ", halved to the phase value" if per_phase else ""
            raise argparse.ArgumentTypeError(f"{text!r}{half}: {why}")
        return value, text

    parse.__name__ = dimension.name  # argparse names the type in its error
    return parse


def _terminating(value: Fraction) -> bool:
    """Whether `value` has a finite decimal expansion (a spec can write it exactly)."""
    d = value.denominator
    for p in (2, 5):
        while d % p == 0:
            d //= p
    return d == 1


_PWM_QUANTITY = _quantity(units.FREQUENCY, "inverter.pwm_frequency")


def _pwm_frequency(text: str) -> tuple[Fraction, str]:
    """argparse type: a PWM frequency within the loader's range. Whether TIM1 can count
    its period depends on the alignment, which argparse does not know here: that is
    `pwm_frequency_error`'s (the edge-aligned check made here had refused 2 kHz
    centre-aligned, a half period of 18000 counts, for its 36000-count whole period)."""
    return _PWM_QUANTITY(text)


def _period_problem(text: str, value: Fraction, alignment: str) -> str | None:
    """Why a PWM frequency gives no period TIM1 can count at 72 MHz with this alignment
    (edge: the period, centre: half of it, a whole number of counts in [256,
    PERIOD_COUNTS_MAX]), with the nearest frequencies that do; None if it does."""
    clock = Fraction(TIMER_CLOCK_HZ) / (2 if alignment == "center" else 1)
    counts = clock / value
    low, high = 256, PERIOD_COUNTS_MAX
    if low <= counts <= high and counts.denominator == 1:
        return None
    # the nearest periods either side whose frequency a spec can write exactly (a
    # terminating decimal: 72 MHz / 10285 counts is 7000.486... Hz and has none)
    exact = [n for n in range(low, high + 1) if _terminating(clock / n)]
    below = [n for n in exact if n <= counts]
    above = [n for n in exact if n >= counts]
    near = sorted({*below[-1:], *above[:1]})
    options = " or ".join(f"{_num(clock / n, 12)} Hz ({n} counts)" for n in near)
    part, whole = ("half period", "36 MHz") if alignment == "center" else ("period", "72 MHz")
    return (
        f"{text!r} gives {_num(counts)} TIM1 counts per {part} at 72 MHz ({alignment}-aligned);"
        f" the {part} must be a whole number of counts in [{low}, {high}]"
        f" (allowed: {whole} / N for a whole N in [{low}, {high}], e.g. {options})"
    )


def pwm_frequency_error(sheet: Datasheet) -> str | None:
    """The one line `init` refuses a PWM frequency with, before it writes anything: at
    the alignment asked for (edge by default) its period, centre-aligned its half
    period, is no whole number of TIM1 counts in the loader's range; with the nearest
    frequencies that are."""
    if sheet.pwm_frequency is None:
        return None
    value, text = sheet.pwm_frequency
    problem = _period_problem(text, value, sheet.pwm_alignment or "edge")
    return None if problem is None else f"argument --pwm-frequency: {problem}"


def _kv(text: str) -> Fraction:
    """argparse type: a speed constant in rpm/V whose line-to-line constant 1/Kv, halved
    to the phase k_e (init writes the 120 deg trapezoid), is within the loader's range
    of motor.back_emf_constant (a phase constant; line to line it is twice that)."""
    if not plain_decimal(text):  # Fraction() takes '1_000' and '٦٢٥'; a spec does not
        raise not_a_number(text, "rpm/V")
    value = Fraction(text.strip())
    if value <= 0:
        raise argparse.ArgumentTypeError(f"{text} must be positive")
    why = out_of_range("motor.back_emf_constant", 1 / value / 2)
    if why is not None:
        raise argparse.ArgumentTypeError(
            f"{text} rpm/V gives 1/Kv, line to line, halved to the phase value: {why}"
        )
    return value


def spec_name(text: str) -> str:
    """argparse type: a spec name the loader accepts."""
    if not re.fullmatch(r"[a-z][a-z0-9_]{0,63}", text):
        raise argparse.ArgumentTypeError(
            f"{text!r} is not a lower-case identifier ([a-z][a-z0-9_]{{0,63}}), e.g. my_motor"
        )
    if text == PAPER_AUDIT_NAME:
        # the loader refuses it: init wrote a spec that did not load (exit 3)
        raise argparse.ArgumentTypeError(
            f"{text!r} is reserved: generated/{text}/ holds the paper's audit; choose another name"
        )
    return text


def _count(low: int, high: int, step: int = 1) -> object:
    """argparse type: a whole number from `low` to `high` in steps of `step`."""

    def parse(text: str) -> int:
        if (
            not text.isascii()
            or not text.isdigit()
            # more than 4300 digits: int() raised ValueError, argparse's "invalid count
            # value: '1111...'" echoing every digit
            or len(text.lstrip("0")) > len(str(high))
            or not low <= int(text) <= high
            or (int(text) - low) % step
        ):
            even = "an even" if step == 2 else "a"
            raise argparse.ArgumentTypeError(
                f"{show_value(text)} is not {even} whole number from {low} to {high}"
            )
        return int(text)

    parse.__name__ = "count"
    return parse


def add_datasheet_arguments(parser: argparse.ArgumentParser) -> None:
    group = parser.add_argument_group(
        "datasheet values (quantities with their unit, e.g. '0.42 ohm'; defaults: the"
        " paper's motor, marked as assumptions)"
    )
    poles = group.add_mutually_exclusive_group()
    poles.add_argument("--poles", type=_count(2, 128, 2), metavar="N", help="number of rotor poles")
    poles.add_argument(
        "--pole-pairs",
        type=_count(1, 64),
        metavar="N",
        help="number of pole pairs (poles = 2 N)",
    )
    r = group.add_mutually_exclusive_group()
    r.add_argument(
        "--resistance",
        type=_quantity(units.RESISTANCE, "motor.phase_resistance"),
        metavar="Q",
        help="phase resistance",
    )
    r.add_argument(
        "--resistance-line-to-line",
        type=_quantity(units.RESISTANCE, "motor.phase_resistance", per_phase=True),
        metavar="Q",
        help="terminal (line-to-line) resistance; the phase value is half",
    )
    inductance = group.add_mutually_exclusive_group()
    inductance.add_argument(
        "--inductance",
        type=_quantity(units.INDUCTANCE, "motor.phase_inductance"),
        metavar="Q",
        help="phase inductance",
    )
    inductance.add_argument(
        "--inductance-line-to-line",
        type=_quantity(units.INDUCTANCE, "motor.phase_inductance", per_phase=True),
        metavar="Q",
        help="terminal (line-to-line) inductance; the phase value is half",
    )
    emf = group.add_mutually_exclusive_group()
    emf.add_argument(
        "--ke",
        type=_quantity(units.EMF_CONSTANT, "motor.back_emf_constant"),
        metavar="Q",
        help="phase back-EMF constant k_e (E = k_e n, flat top), e.g. '2.36 V/krpm'",
    )
    emf.add_argument(
        "--ke-line-to-line",
        type=_quantity(units.EMF_CONSTANT, "motor.back_emf_constant", per_phase=True),
        metavar="Q",
        help="line-to-line back-EMF constant (= 2 k_e)",
    )
    emf.add_argument(
        "--kv",
        type=_kv,
        metavar="RPM_PER_V",
        help="speed constant in rpm/V; line-to-line k_e = 1/Kv",
    )
    group.add_argument(
        "--rated-voltage",
        type=_quantity(units.VOLTAGE, "motor.rated_voltage"),
        metavar="Q",
        help="motor rated voltage",
    )
    group.add_argument(
        "--inertia",
        type=_quantity(units.INERTIA, "motor.rotor_inertia"),
        metavar="Q",
        help="rotor inertia",
    )
    group.add_argument(
        "--bus-voltage",
        type=_quantity(
            units.VOLTAGE,
            "inverter.bus_voltage_nominal",
            # init writes 0.8 and 1.25 times it as bus_voltage_min and max, within the
            # loader's [1, 1000] V: at 1 V both min and nominal were 1 V, a nominal bus
            # the drive reads as under-voltage
            minimum=(Fraction(5, 4), "1.25 V", "whose 0.8 x is the 1 V a spec's bus starts at"),
            maximum=(Fraction(800), "800 V", "whose 1.25 x is the 1000 V a spec's bus ends at"),
        ),
        metavar="Q",
        help="nominal DC bus voltage (range: 0.8 to 1.25 times it)",
    )
    group.add_argument(
        "--braking-current",
        type=_quantity(
            units.CURRENT,
            "controller.braking_current_nominal",
            minimum=(
                BRAKING_CURRENT_MIN_A,
                f"{_num(BRAKING_CURRENT_MIN_A)} A",
                "the smallest nominal braking current init sizes the current sensing for",
            ),
            maximum=(
                BRAKING_CURRENT_MAX_A,
                f"{_num(BRAKING_CURRENT_MAX_A)} A",
                "the largest whose braking_current_max, twice it, a spec holds",
            ),
        ),
        metavar="Q",
        help="nominal braking current (range: 0 to twice it)",
    )
    group.add_argument(
        "--speed-max",
        type=_quantity(
            units.SPEED,
            "controller.speed_max",
            minimum=(
                SPEED_MAX_LOWEST_RPM,
                f"{_num(SPEED_MAX_LOWEST_RPM)} rpm",
                "the lowest top speed whose operating point, at 90 % of it, is at least"
                " the 1 rpm a spec's speeds start at",
            ),
        ),
        metavar="Q",
        help="top speed (default: 95 %% of U_d/(2 k_e), where 2E reaches the bus)",
    )
    group.add_argument(
        "--pwm-frequency",
        type=_pwm_frequency,
        metavar="Q",
        help="PWM frequency",
    )
    group.add_argument(
        "--pwm-alignment",
        choices=("edge", "center"),
        help="TIM1's carrier: edge-aligned (default) or centre-aligned (the current sample"
        " at the counter's peak, half the PWM ripple)",
    )
    parser.add_argument(
        "--method",
        choices=COMMUTATION_METHODS,
        help="commutation method (default: improved, the paper's Eq. 18); improved_r, the"
        " resistance-aware rule, gets a 640 B RAM budget for its deeper stack",
    )


@dataclass(frozen=True)
class Datasheet:
    """The values given to `init`: (SI value, text as typed) or None."""

    poles: int | None = None
    pole_pairs: int | None = None
    resistance: tuple[Fraction, str] | None = None
    resistance_line_to_line: tuple[Fraction, str] | None = None
    inductance: tuple[Fraction, str] | None = None
    inductance_line_to_line: tuple[Fraction, str] | None = None
    ke: tuple[Fraction, str] | None = None
    ke_line_to_line: tuple[Fraction, str] | None = None
    kv: Fraction | None = None
    rated_voltage: tuple[Fraction, str] | None = None
    inertia: tuple[Fraction, str] | None = None
    bus_voltage: tuple[Fraction, str] | None = None
    braking_current: tuple[Fraction, str] | None = None
    speed_max: tuple[Fraction, str] | None = None
    pwm_frequency: tuple[Fraction, str] | None = None
    pwm_alignment: str | None = None
    method: str | None = None

    @classmethod
    def from_arguments(cls, args: argparse.Namespace) -> Datasheet:
        return cls(**{name: getattr(args, name, None) for name in cls.__dataclass_fields__})


@dataclass(frozen=True)
class DesignRefusal:
    """The fixed-point design refused a spec that loads: the one line `generate` prints."""

    source: str
    key: str
    problem: str

    def __str__(self) -> str:
        return f"{self.source}: {self.key}: fixed-point design: {self.problem}"


@dataclass(frozen=True)
class Written:
    path: Path
    error: SpecError | DesignRefusal | None
    warnings: tuple[SpecWarning, ...]
    #: targets raised to what a design meets (`codegen.init_design`)
    notes: tuple[str, ...] = ()


#: The most significant digits a value is written with exactly (a datasheet's 0.123457
#: ohm line to line is 0.0617285 ohm a phase, not a rounding of it).
EXACT_DIGITS = 15


def _exact_decimal(value: Fraction) -> str | None:
    """`value` as a plain decimal when it has a finite one of at most EXACT_DIGITS
    significant digits (its denominator is 2^a 5^b), else None."""
    den = value.denominator
    twos = fives = 0
    while den % 2 == 0:
        den //= 2
        twos += 1
    while den % 5 == 0:
        den //= 5
        fives += 1
    if den != 1:
        return None
    places = max(twos, fives)
    scaled = abs(value.numerator) * 10**places // value.denominator
    if len(str(scaled).strip("0")) > EXACT_DIGITS:
        return None
    sign = "-" if value < 0 else ""
    whole, frac = divmod(scaled, 10**places)
    text = f"{whole}.{frac:0{places}d}".rstrip("0").rstrip(".") if places else str(whole)
    return sign + text


def _num(value: Fraction, digits: int = 6) -> str:
    """A decimal for a spec value, no exponent: exact when it has a short one (see
    EXACT_DIGITS), else rounded to `digits` significant digits."""
    exact = _exact_decimal(value)
    if exact is not None:
        return exact
    text = f"{float(value):.{digits}g}"
    if "e" in text:
        text = f"{float(value):.{digits + 6}f}".rstrip("0").rstrip(".")
    return text


#: Significant digits of a back-EMF constant with no finite decimal (1/Kv).
KE_DIGITS = 9


def _num_up(value: Fraction, digits: int = KE_DIGITS) -> str:
    """`value` exactly when it has a short decimal, else rounded up at `digits`
    significant digits: a k_e of 1/Kv written a hair large, never small, so that a
    braking current the user put exactly at E(speed_max)/R still loads (the loader's
    R I <= E(speed_max)); 1e-9 of k_e is far inside any datasheet's tolerance."""
    exact = _exact_decimal(value)
    if exact is not None or value <= 0:
        return exact if exact is not None else _num(value, digits)
    exponent = len(str(value.numerator)) - len(str(value.denominator))
    while Fraction(10) ** (exponent + 1) <= value:
        exponent += 1
    while Fraction(10) ** exponent > value:
        exponent -= 1
    unit = Fraction(10) ** (exponent - digits + 1)
    up = math.ceil(value / unit) * unit
    exact_up = _exact_decimal(up)
    assert exact_up is not None  # a whole number of a power of ten
    return exact_up


_DEFAULT = "assumption: bldc-codegen init default (the paper's motor, Table 3); replace"


def _motor(sheet: Datasheet) -> tuple[dict[str, str], dict[str, str], dict[str, Fraction]]:
    values: dict[str, str] = {}
    sources: dict[str, str] = {}
    si: dict[str, Fraction] = {}
    if sheet.poles is not None:
        values["poles"], sources["poles"] = str(sheet.poles), "datasheet: number of poles"
    elif sheet.pole_pairs is not None:
        values["poles"] = str(2 * sheet.pole_pairs)
        sources["poles"] = (
            f"datasheet: {sheet.pole_pairs} pole pairs, poles = 2 x pole pairs (bldc-codegen init)"
        )
    else:
        values["poles"], sources["poles"] = "2", f"{_DEFAULT} with your motor's poles"
    si["pole_pairs"] = Fraction(int(values["poles"]) // 2)
    if sheet.resistance is not None:
        si["r"] = sheet.resistance[0]
        values["phase_resistance"] = f"{_num(si['r'])} ohm"
        sources["phase_resistance"] = f"datasheet: phase resistance {sheet.resistance[1]}"
    elif sheet.resistance_line_to_line is not None:
        si["r"] = sheet.resistance_line_to_line[0] / 2
        values["phase_resistance"] = f"{_num(si['r'])} ohm"
        sources["phase_resistance"] = (
            f"datasheet: {sheet.resistance_line_to_line[1]} line to line; star winding, so"
            " phase = line-to-line / 2 (bldc-codegen init)"
        )
    else:
        si["r"] = Fraction(21, 100)
        values["phase_resistance"] = "0.21 ohm"
        sources["phase_resistance"] = f"{_DEFAULT} with your motor's phase resistance"
    if sheet.inductance is not None:
        si["l"] = sheet.inductance[0]
        sources["phase_inductance"] = f"datasheet: phase inductance {sheet.inductance[1]}"
    elif sheet.inductance_line_to_line is not None:
        si["l"] = sheet.inductance_line_to_line[0] / 2
        sources["phase_inductance"] = (
            f"datasheet: {sheet.inductance_line_to_line[1]} line to line; star winding, so"
            " phase = line-to-line / 2 (bldc-codegen init)"
        )
    else:
        si["l"] = Fraction(56, 100_000)
        sources["phase_inductance"] = f"{_DEFAULT} with your motor's phase inductance"
    values["phase_inductance"] = f"{_num(si['l'] * 1000)} mH"
    if sheet.ke is not None:
        si["ke"] = sheet.ke[0]
        values["back_emf_constant"] = f"{_num(si['ke'] * 1000)} V/krpm"
        values["back_emf_convention"] = "phase"
        sources["back_emf_constant"] = f"datasheet: phase back-EMF constant {sheet.ke[1]}"
        sources["back_emf_convention"] = "datasheet value is per phase (bldc-codegen init --ke)"
    elif sheet.ke_line_to_line is not None or sheet.kv is not None:
        if sheet.kv is not None:
            line_to_line = 1 / sheet.kv  # V per rpm
            sources["back_emf_constant"] = (
                f"datasheet: Kv = {_num(sheet.kv)} rpm/V, so the line-to-line constant is"
                f" 1/Kv = {_num_up(line_to_line * 1000)} V/krpm ("
                + (
                    ""
                    if _exact_decimal(line_to_line * 1000) is not None
                    else f"rounded up at the {KE_DIGITS}th digit; "
                )
                + "bldc-codegen init)"
            )
        else:
            assert sheet.ke_line_to_line is not None
            line_to_line = sheet.ke_line_to_line[0]
            sources["back_emf_constant"] = (
                f"datasheet: line-to-line back-EMF constant {sheet.ke_line_to_line[1]}"
            )
        written = _num_up(line_to_line * 1000)
        # what the loader reads: every value init derives from k_e (the default top
        # speed, the hold speed) is derived from the written one
        line_to_line = Fraction(written) / 1000
        si["ke"] = line_to_line / 2
        values["back_emf_constant"] = f"{written} V/krpm"
        values["back_emf_convention"] = "line_to_line"
        sources["back_emf_convention"] = (
            "the datasheet's constant is line to line (2E of two conducting phases, Eq. 4);"
            " the loader divides it by the EMF shape's peak line-to-line factor (2 for the"
            " 120 deg trapezoid) to the phase k_e"
        )
    else:
        si["ke"] = Fraction(236, 100_000)
        values["back_emf_constant"] = "2.36 V/krpm"
        values["back_emf_convention"] = "phase"
        sources["back_emf_constant"] = f"{_DEFAULT} with your motor's back-EMF constant"
        sources["back_emf_convention"] = f"{_DEFAULT}: phase or line_to_line, as the datasheet"
    if sheet.rated_voltage is not None:
        si["rated"] = sheet.rated_voltage[0]
        sources["rated_voltage"] = f"datasheet: rated voltage {sheet.rated_voltage[1]}"
    elif sheet.bus_voltage is not None:
        si["rated"] = sheet.bus_voltage[0]
        sources["rated_voltage"] = "assumption: bldc-codegen init, the nominal bus voltage"
    else:
        si["rated"] = Fraction(24)
        sources["rated_voltage"] = f"{_DEFAULT} with your motor's rated voltage"
    values["rated_voltage"] = f"{_num(si['rated'])} V"
    if sheet.inertia is not None:
        values["rotor_inertia"] = f"{_num(sheet.inertia[0])} kg*m^2"
        sources["rotor_inertia"] = f"datasheet: rotor inertia {sheet.inertia[1]}"
    else:
        values["rotor_inertia"] = "0.00119 kg*m^2"
        sources["rotor_inertia"] = f"{_DEFAULT} with your motor's rotor inertia"
    return values, sources, si


def _round_down(value: Fraction, step: int | Fraction) -> Fraction:
    return Fraction(math.floor(value / step) * step)


def _round_down_digits(value: Fraction, digits: int) -> Fraction:
    """A positive value rounded down to `digits` significant digits (never to 0)."""
    step = Fraction(10) ** (math.floor(math.log10(value)) - digits + 1)
    return max(_round_down(value, step), step)


def _round_up(value: Fraction, step: int | Fraction) -> Fraction:
    return Fraction(math.ceil(value / step) * step)


def _speed_step(speed_rpm: Fraction) -> Fraction:
    """The step init rounds a speed to: 10 rpm from 100 rpm up, else two significant
    digits (a 2 rpm cut-off motor's 95 % top speed is 3.8 rpm: rounded to 10 rpm, with
    a 10 rpm floor, init had written 10 rpm, above the limit, and a 0 rpm point)."""
    if speed_rpm >= 100:
        return Fraction(10)
    step = Fraction(1)
    while step > Fraction(1, 10**6) and speed_rpm < 10 * step:
        step /= 10
    return step


def _lowest_speed(
    hall_clock: Fraction | int, pole_pairs: Fraction | int, n_max: Fraction
) -> Fraction:
    """speed_min init writes: 1.1 x the speed whose 60 deg sector fills the 16-bit Hall
    counter at `hall_clock`, 1 rpm at least."""
    slowest_rpm = Fraction(hall_clock * 10) / (pole_pairs * COUNTER_MAX)
    return max(Fraction(1), _round_up(slowest_rpm * Fraction(11, 10), _speed_step(n_max) / 2))


def _speed_down(speed_rpm: Fraction) -> Fraction:
    return _round_down(speed_rpm, _speed_step(speed_rpm))


def _speed_up(speed_rpm: Fraction) -> Fraction:
    return _round_up(speed_rpm, _speed_step(speed_rpm))


@dataclass(frozen=True)
class Targets:
    """The accuracy targets init writes: its defaults, or what a fixed-point design meets
    where the default is out of its reach (`codegen.init_design` raises them)."""

    loop_counts: Fraction = Fraction(1)  # accuracy.current_loop_duty_counts
    duty_counts: Fraction = Fraction(1)  # accuracy.duty_counts
    time_ticks: Fraction | None = None  # accuracy.commutation_time_ticks; None: the budget
    hall_clock_hz: Fraction | None = None  # hall.timer_clock; None: from the top speed


def _guarded_sector_s(pwm_hz: Fraction, dead_ns: Fraction, method: str) -> Fraction:
    """The shortest sector, in seconds, that outlasts the commutation end's guard (the
    loader refuses a shorter one) and, for the resistance-aware rule, which ends a
    commutation on a carrier boundary, holds one PWM period more: T (2^k - 1)/2^k - G
    >= 0 (or one period), G the guard (`codegen.dead_time.commutation_guard_ticks`, with
    its current sample) and 2^-k the default sector-shortening margin."""
    shift = sector_margin_shift(Fraction(SECTOR_SHORTENING_DEFAULT_PERCENT, 100))
    keep = Fraction(1) if shift is None else Fraction(2**shift - 1, 2**shift)
    guard = dead_ns / 10**9 + COMMUTATION_END_ALLOWANCE_S + end_sample_room_s(pwm_hz, SAMPLE_CYCLES)
    carrier = 1 / pwm_hz if method == "improved_r" else Fraction(0)
    return (carrier + guard) / keep


def _short_peak(speed_rpm: Fraction, si: dict[str, Fraction], entry_a: Fraction | int) -> float:
    """The loader's bound on the short circuit's peak current at this speed (init's
    120 deg EMF), entered with `entry_a` flowing."""
    return short_circuit_peak(
        speed_rpm=float(speed_rpm),
        k_e=float(si["ke"]),
        pole_pairs=int(si["pole_pairs"]),
        resistance_ohm=float(si["r"]),
        inductance_h=float(si["l"]),
        shape=BackEmfShape(),
        current_at_entry_a=float(entry_a),
    )


def render_spec(name: str, sheet: Datasheet, targets: Targets = Targets()) -> str:
    """The spec text for `name` from the datasheet values (see the module docstring),
    with `targets` as its accuracy targets."""
    loop_counts = targets.loop_counts
    motor, motor_sources, si = _motor(sheet)
    method = sheet.method or "improved"
    derived = "assumption: bldc-codegen init, derived:"
    bus = sheet.bus_voltage[0] if sheet.bus_voltage else si["rated"]
    bus_source = (
        f"datasheet/board: nominal bus {sheet.bus_voltage[1]}"
        if sheet.bus_voltage
        else "assumption: bldc-codegen init, the motor's rated voltage"
    )
    # 0.8 and 1.25 x nominal, within the loader's voltages: a 1000 V bus (which the
    # option takes) had written a 1250 V maximum the spec then refused, a 1 V one 0.8 V
    volts = DATASHEET_RANGES["inverter.bus_voltage_nominal"]
    lowest, highest = Fraction(str(volts.low)), Fraction(str(volts.high))
    v_min = max(lowest, _round_down(bus * 8, 1) / 10)
    v_max = min(highest, _round_up(bus * 125, 1) / 100)
    divider = max(1, math.ceil(v_max * Fraction(11, 10) / ADC_REFERENCE_V))
    n_limit = bus / (2 * si["ke"])
    pole_pairs = si["pole_pairs"]
    pwm = sheet.pwm_frequency[0] if sheet.pwm_frequency else Fraction(20_000)
    alignment = sheet.pwm_alignment or "edge"
    dead_ns = min(Fraction(500), _round_down(Fraction(10**9, 100) / pwm, 10))
    if sheet.speed_max is not None:
        n_max = sheet.speed_max[0]
        n_max_source = f"datasheet/application: top speed {sheet.speed_max[1]}"
    else:
        n_max = max(Fraction(1), _speed_down(n_limit * Fraction(95, 100)))
        n_max_source = f"{derived} 95 % of U_d/(2 k_e) = {_num(n_limit)} rpm, rounded down"
        # the shortest sector must outlast the commutation end's guard, which holds one
        # current sample (the loader refuses a speed_max whose sector does not, and the
        # loop's first sample after an edge comes within it), so a many-pole motor's top
        # speed may sit below 95 %
        guarded_s = _guarded_sector_s(pwm, dead_ns, method)
        steady_s = STEADY_SECTOR_PWM_PERIODS / pwm
        n_guarded = 60 / (max(guarded_s, steady_s) * pole_pairs * 6)
        n_cap = max(Fraction(1), _speed_down(n_guarded * Fraction(95, 100)))
        if n_cap < n_max:
            n_max = n_cap
            why = (
                f" 60 deg sector holds {_num(STEADY_SECTOR_PWM_PERIODS)} PWM periods (the"
                " timing takes the loop's state from before the previous edge: with fewer"
                " loop samples a sector the braking locked into a two-sector cycle, make pil)"
                if steady_s >= guarded_s
                else " 60 deg sector outlasts the commutation end's guard and margin (the end"
                " leaves room for one current sample before the next edge)"
                + (
                    " by one PWM period (the resistance-aware rule ends a commutation on a"
                    " carrier boundary)"
                    if method == "improved_r"
                    else ""
                )
            )
            n_max_source = (
                f"{derived} 95 % of {_num(n_guarded)} rpm, rounded down, the speed whose"
                + why
                + f"; below 95 % of U_d/(2 k_e) = {_num(n_limit)} rpm; raise the PWM"
                " frequency for more"
            )
        # above the speed where all-off rectifies (at the lowest bus) the safe state is
        # the short circuit; where its peak is past any rating a spec may name (a stiff
        # 2 uH, 10 mohm motor: 61.8 kA), the top speed stays below that speed, or the
        # spec would name no safe state there (the loader refuses it); the speed the last
        # Hall interval says, which may be the default sector shortening slow
        # (`spec_drive.safe_state_corner`: init writes no tolerances)
        said = said_speed_factor(Fraction(SECTOR_SHORTENING_DEFAULT_PERCENT, 100))
        n_rect = rectifying_speed(v_min, si["ke"] * said, BackEmfShape())
        if n_max >= n_rect and _short_peak(n_max, si, 0) > PROTECTION_AMPS_MAX:
            n_max = max(Fraction(1), _speed_down(n_rect * Fraction(99, 100)))
            n_max_source = (
                f"{derived} 99 % of {_num(n_rect)} rpm, rounded down, below the speed where"
                " every switch off may rectify into the bus at bus_voltage_min (with a"
                f" rotor {SECTOR_SHORTENING_DEFAULT_PERCENT} % faster than its last Hall"
                " interval says): above it the"
                " safe state is the short circuit, whose peak current there is beyond the"
                f" {PROTECTION_AMPS_MAX} A a spec may name"
            )
    hall_clock: Fraction | int = next(
        (clock for clock in HALL_CLOCKS_HZ if clock * 10 / (pole_pairs * n_max) >= 500),
        HALL_CLOCKS_HZ[-1],
    )
    slow_clock = False
    if targets.hall_clock_hz is not None:
        hall_clock = targets.hall_clock_hz
    elif _lowest_speed(hall_clock, pole_pairs, n_max) >= _speed_down(n_max * 9 / 10):
        # a top speed of a few rpm: the 16-bit counter at 100 kHz fills above it (a 2-pole
        # motor's --speed-max 5 rpm got speed_min 16.8 rpm, a spec its loader refused);
        # the fastest slower clock whose counter holds a sector below 90 % of it
        slow = [
            c for c in SLOW_HALL_CLOCKS_HZ if _lowest_speed(c, pole_pairs, n_max) < n_max * 9 / 10
        ]
        hall_clock, slow_clock = (slow[0], True) if slow else (hall_clock, False)
    fastest = Fraction(hall_clock * 10) / (pole_pairs * n_max)
    n_min = _lowest_speed(hall_clock, pole_pairs, n_max)
    e_top = si["ke"] * n_max
    # the largest duty the current sample leaves (the loader's check of each operating
    # point: holding I at speed n needs 1 - (2E - 2RI)/U_d within it)
    period_counts = TIMER_CLOCK_HZ // int(pwm) // (2 if alignment == "center" else 1)
    window = sense_window(
        alignment=alignment,
        period_counts=period_counts,
        timer_clock_hz=Fraction(TIMER_CLOCK_HZ),
        dead_time_counts=math.ceil(dead_ns * TIMER_CLOCK_HZ / 10**9),
        settling_time_s=SETTLING_TIME_S,
        adc_sample_cycles=SAMPLE_CYCLES,
        current_samples=1,  # the DC-link shunt init writes
    )
    d_max = Fraction(window.duty_max_counts, period_counts)
    high = _speed_down(n_max * 9 / 10)
    if sheet.braking_current is not None:
        i_nom = sheet.braking_current[0]
        i_source = f"datasheet/application: nominal braking current {sheet.braking_current[1]}"
    else:
        # what the loop can hold at the upper operating point, (2E - (1 - D_max) U_d)/(2R):
        # half of E(speed_max)/R alone had written 1.6 A on a 300 rpm paper motor, which
        # needs a duty of 0.975 of a 0.952 D_max there, and the loader warned of init's
        # own spec (a hunt)
        held = (2 * si["ke"] * high - (1 - d_max) * bus) / (2 * si["r"])
        # and where a commutation at braking_current_max (twice it) lasts at most
        # INIT_COMMUTATION_SHARE of a sector where 4E <= U_d, I L p / (20 k_e) (the loader's
        # commutation-fills-sectors): 5 A on a 20-pole-pair 3 mH 2.36 V/krpm outrunner
        # lasted 6.4 sectors and no commutation ended (make pil, a hunt)
        one_sector = 1 / improved_commutation_share(Fraction(1), si["l"], pole_pairs, si["ke"])
        shared = INIT_COMMUTATION_SHARE * one_sector / 2
        improved = method in ("improved", "improved_r")
        i_nom = max(
            BRAKING_CURRENT_MIN_A,
            min(
                Fraction(5),
                _round_down(e_top / si["r"] * 5, 1) / 10,
                _round_down(held, 1 / 10),
                _round_down(shared, 1 / 100) if improved else Fraction(5),
            ),
        )
        # the least init writes, never past what the back-EMF can drive (the loader
        # refuses R I > E(speed_max): --speed-max 2 rpm on the paper motor, E/R 22 mA,
        # had written 0.1 A, a hunt): half of it, to two digits
        if i_nom > e_top / si["r"] / 2:
            i_nom = _round_down_digits(e_top / si["r"] / 2, 2)
        i_source = (
            f"{derived} 5 A, or half of what the back-EMF can drive in braking,"
            f" E(speed_max)/R = {_num(e_top / si['r'])} A, or what the current loop can hold at"
            f" {_num(high)} rpm within its D_max {float(d_max):.3f},"
            f" {_num(max(held, Fraction(0)))} A"
            + (
                ", or the current whose improved commutation at twice it lasts half a sector"
                f" where 4E <= U_d, 20 k_e/(4 p L) = {_num(shared)} A"
                if improved
                else ""
            )
            + (
                f", if less; {_num(BRAKING_CURRENT_MIN_A)} A at least"
                if i_nom >= BRAKING_CURRENT_MIN_A
                else f"; below the {_num(BRAKING_CURRENT_MIN_A)} A init sizes the current"
                " sensing for, as the back-EMF at speed_max drives no more: raise --speed-max"
                " or give --braking-current and your sensing's gain"
            )
        )
    i_max = 2 * i_nom
    # the current the sensing must read and the comparator let through: braking_current_max
    # plus the PWM ripple above the loop's sample (edge-aligned, the default: a whole
    # ripple; centre-aligned the sample sits at the ripple's middle)
    ripple = braking_ripple(
        bus_voltage_max_v=v_max,
        pwm_frequency_hz=pwm,
        phase_inductance_h=si["l"],
        k_e_v_per_rpm=si["ke"],
        phase_resistance_ohm=si["r"],
        speed_min_rpm=n_min,
        speed_max_rpm=n_max,
        current_max_a=i_max,
        alignment=alignment,
    )
    peak = braking_current_peak(i_max, ripple)
    default_budget = min(Fraction(8), _round_down(fastest / 20, 1))
    budget = default_budget if targets.time_ticks is None else targets.time_ticks
    # In braking only the back-EMF drives the current, at most E/R: the lower point sits
    # where E is 1.5 x R x braking_current_nominal (a duty near 2/3), if 30 % is below it.
    n_hold = _speed_up(si["r"] * i_nom / si["ke"] * Fraction(3, 2))
    # ... and where the loop can hold it: the duty it needs there, 1 - (2E - 2RI) / U_d,
    # within the largest the current sample leaves (the loader's own check; a 100 kHz
    # centre-aligned spec init wrote had its lower point at 1440 rpm needing 0.804 of a
    # 0.781 D_max, and warned of it: a helper's hunt)
    n_hold = max(n_hold, _speed_up(((1 - d_max) * bus + 2 * si["r"] * i_nom) / (2 * si["ke"])))
    low = max(n_min, _speed_down(n_max * Fraction(3, 10)))
    points = sorted({min(max(low, n_hold), high), high})
    if points[-1] - points[0] < 1:  # the reports name a point by its speed in whole rpm
        points = [high]
    bandwidth_hz = min(Fraction(1000), pwm / 10)
    over_current = _round_up(max(i_max * Fraction(3, 2), peak * Fraction(5, 4)), 1)
    # the sensing reads every current below the trip: 1.65 V of mid-rail headroom at it;
    # at most 500 mV/A, unless the braking range (from 0 A) needs more to span the
    # loader's CURRENT_RANGE_CODES codes of the 12-bit, 3.3 V ADC, with a quarter to spare
    # (`init --speed-max 1.2 rpm` wrote 0.0134 A at 500 mV/A, 8 codes, which the loader
    # refused; the 1 A trip leaves room for 1650 mV/A, 27 codes)
    headroom_mv = _round_down(Fraction(1650) / over_current, 1)
    resolving_mv = _round_up(CURRENT_RANGE_CODES * Fraction(5, 4) * 3300 / (4096 * i_max), 1)
    gain_mv = max(Fraction(1, 10), min(max(Fraction(500), resolving_mv), headroom_mv))
    # at the fastest a rotor read at speed_max may run (the loader's and the port's c x
    # speed_max, c = 1/(1 - sector_shortening)): at speed_max alone the short was unrated
    # at the top of the range, where all-off may rectify (a helper's hunt)
    fastest = n_max * said_speed_factor(Fraction(SECTOR_SHORTENING_DEFAULT_PERCENT, 100))
    short_bound = _round_up(Fraction(math.ceil(_short_peak(fastest, si, over_current))), 1)
    # a bound past what a protection entry may name (a tiny, stiff motor's E/R at the
    # top speed): the entry's limit, noted, so that the loader judges the physics (does
    # the short circuit have to hold at speed_max?) rather than the number's range
    short_max = min(short_bound, Fraction(PROTECTION_AMPS_MAX))

    def steady_duty(rpm: Fraction) -> str:
        """The duty the braking-current loop settles at there, at braking_current_nominal
        (1 - (2E - 2RI) / U_d on the nominal bus, within [0, D_max]): a fixed 0.42 had
        been written for every motor, a duty that cannot brake a 24-pole robot joint at
        its low point and puts a 400 V servo's conventional D_off into the fail area
        (a helper's hunt)."""
        duty = 1 - (2 * si["ke"] * rpm - 2 * si["r"] * i_nom) / bus
        return f"{math.floor(float(min(max(duty, Fraction(0)), d_max)) * 1000) / 1000:.3f}"

    point_lines = "\n".join(
        f"  - {{speed: {_num(p)} rpm, main_duty: {steady_duty(p)}}}" for p in points
    )
    sources = {f"motor.{k}": v for k, v in motor_sources.items()} | {
        "inverter.bus_voltage_nominal": bus_source,
        "inverter.bus_voltage_min": f"{derived} 0.8 x nominal"
        + (f", at least {_num(lowest)} V" if v_min == lowest else "")
        + "; set your undervoltage trip",
        "inverter.bus_voltage_max": f"{derived} 1.25 x nominal"
        + (f", at most {_num(highest)} V" if v_max == highest else "")
        + "; set your overvoltage trip",
        "inverter.pwm_frequency": (
            f"datasheet/board: {sheet.pwm_frequency[1]}"
            if sheet.pwm_frequency
            else "assumption: bldc-codegen init default, 20 kHz (above the audible range)"
        ),
        "inverter.pwm_alignment": (
            f"datasheet/board: {alignment}-aligned TIM1 (init --pwm-alignment)"
            if sheet.pwm_alignment
            else "assumption: bldc-codegen init default, edge-aligned TIM1"
        ),
        "inverter.timer_clock": "STM32F103 TIM1 clock (APB2 at 72 MHz)",
        "inverter.dead_time": (
            (
                f"{derived} 500 ns, at most 1 % of the PWM period"
                if dead_ns == 500
                else f"{derived} 1 % of the PWM period (rounded down to 10 ns), less than the"
                " 500 ns init takes at most"
            )
            + "; check your gate driver"
        ),
        "hall.sequence": "assumption: the paper's Table 1 order; check your motor's wiring",
        "hall.timer_clock": (
            f"{derived} the fastest 72 MHz / N whose 16-bit counter holds a 60 deg sector"
            " below 90 % of speed_max (a slower clock than the 100 kHz init takes at least)"
            if slow_clock
            else f"{derived} the slowest 72 MHz / N giving >= 500 ticks per 60 deg at speed_max"
            if targets.hall_clock_hz is None
            else f"{derived} what the commutation core's fixed-point design takes (a faster"
            " clock leaves Eq. 20's X too few fraction bits on this motor)"
        ),
        "hall.counter_bits": "STM32F103 general-purpose timers are 16 bit",
        "hall.sector_shortening": (
            "assumption: bldc-codegen init default, a sector up to 5 % shorter than the one"
            " its timing was measured on (a Hall sensor 0.75 electrical degrees off its mark,"
            " or acceleration); measure your motor's six sector lengths"
        ),
        "adc.bits": "STM32F103 ADC resolution",
        "adc.reference": "assumption: VREF+ = 3.3 V",
        "adc.bus_voltage_divider": f"{derived} full scale at least 1.1 x bus_voltage_max",
        "adc.current_gain": (
            f"{derived} full scale (3.3 V - offset) / gain at least protection.over_current,"
            " so that every current below the trip reads (that is at least 1.25 x the braking"
            f" current's peak, braking_current_max + {_num(_round_up(ripple.above_sample * 10, 1) / 10)} A"
            f" of PWM ripple, {alignment}-aligned)"
            + (
                f", above init's usual 500 mV/A so that the braking range spans"
                f" {CURRENT_RANGE_CODES} x 1.25 ADC codes"
                if gain_mv > 500
                else ""
            )
            + "; set your shunt x amplifier gain"
        ),
        "adc.current_offset": "assumption: bipolar current sense biased at mid-rail",
        "controller.method": METHOD_SOURCES[method],
        "controller.braking_current_min": "assumption: bldc-codegen init default",
        "controller.braking_current_nominal": i_source,
        "controller.braking_current_max": f"{derived} twice nominal",
        "controller.speed_min": (
            f"{derived} 1.1 x the speed whose 60 deg Hall period fills the 16-bit counter"
        ),
        "controller.speed_max": n_max_source,
        "accuracy.duty_counts": (
            "assumption: 1 TIM1 count error budget for D_on and D_off"
            if targets.duty_counts == 1
            else f"{derived} {_num(targets.duty_counts)} TIM1 counts, what the {method}"
            " commutation core's integer design meets on this motor (1 count is out of reach)"
        ),
        "accuracy.commutation_time_ticks": (
            f"{derived} {_num(budget)} Hall ticks, at most 8 and 5 % of the shortest sector"
            if targets.time_ticks is None
            else f"{derived} {_num(budget)} Hall ticks, what the {method} commutation core's"
            f" integer design meets on this motor ({_num(default_budget)} is out of reach)"
        ),
        "operating_points": (
            f"{derived} 90 % of speed_max, and 30 % or where E = 1.5 x R x"
            " braking_current_nominal if faster, each at the duty the braking-current loop"
            " settles at there, 1 - (2E - 2RI) / U_d at braking_current_nominal on the"
            " nominal bus; set your test speeds"
        ),
        "accuracy.current_loop_duty_counts": (
            "assumption: 1 TIM1 count for the braking-current PI"
            if loop_counts == 1
            else f"{derived} {_num(loop_counts)} TIM1 counts, what the braking-current PI's"
            " widest fixed-point format meets over a step response (1 count is out of reach)"
        ),
        "accuracy.ill_conditioned_above": (
            f"{derived} the time target per 0.1 count, as spec/paper_motor.yaml declares"
        ),
        "accuracy.ill_conditioned_counts": "assumption: 0.1 count, as spec/paper_motor.yaml",
        "sensing": "assumption: bldc-codegen init default, a DC-link shunt on ADC12_IN0 (PA0), the"
        " bus divider on ADC12_IN1 (PA1); set your board's topology, channels and settling time",
        "current_loop.bandwidth": f"{derived} 1 kHz or a tenth of the PWM frequency if less",
        "protection.over_current": (
            f"{derived} 1.5 x braking_current_max, or 1.25 x the braking current's peak"
            " (with the PWM ripple) if more; set your comparator's trip"
        ),
        "protection.break_input": "assumption: open-drain comparator output, low on over-current",
        "protection.short_circuit_current_max": (
            f"{derived} the short-circuit bound at speed_max / (1 - hall.sector_shortening),"
            " rounded up (the fastest a rotor read at speed_max may run); set your bridge's"
            " pulsed rating"
            if short_max == short_bound
            else f"{derived} the short-circuit bound at speed_max / (1 - hall.sector_shortening)"
            f" is {_num(short_bound)} A,"
            f" beyond the {PROTECTION_AMPS_MAX} A a spec may name: written as that; set your"
            " bridge's pulsed rating"
        ),
        "protection.safe_state": "assumption: all-off where both are valid",
        "firmware": "assumption: bldc-codegen init defaults; the budgets of issue 12"
        + (
            ", but ram_budget 640 B, stack included (the resistance-aware rule's search"
            " runs deeper than the 512 B of the paper method)"
            if method == "improved_r"
            else ""
        ),
    }
    source_lines = "\n".join(f"  {key}: {_yaml_string(text)}" for key, text in sources.items())
    return f"""\
# Motor spec written by `bldc-codegen init {name}`. Edit every value marked
# 'assumption:' in `sources` for your motor and board, then run
#   bldc-codegen generate <this file>
#
# Conventions (checked by codegen/spec_loader.py):
#   * Quantities are "<number> <unit>" strings; plain numbers are dimensionless.
#   * Speeds are mechanical rpm; poles counts poles (pole pairs = poles / 2).
#   * back_emf_constant is k_e in E = k_e n (paper Eq. 3), the flat-top EMF of one phase;
#     with back_emf_convention: line_to_line it is the datasheet's (peak) line-to-line
#     value and the loader divides it by the shape's line-to-line factor (2 at 120 deg).
#   * Every value says where it comes from in `sources`.
name: {name}
description: {name} (written by bldc-codegen init; describe your drive here)

motor:
  rated_voltage: {motor["rated_voltage"]}
  phase_resistance: {motor["phase_resistance"]}
  phase_inductance: {motor["phase_inductance"]}
  poles: {motor["poles"]}
  back_emf_constant: {motor["back_emf_constant"]}
  back_emf_convention: {motor["back_emf_convention"]}
  rotor_inertia: {motor["rotor_inertia"]}

inverter:
  # The braking speed limit is U_d/(2 k_e) = {_num(n_limit)} rpm at the nominal bus.
  bus_voltage_nominal: {_num(bus)} V
  bus_voltage_min: {_num(v_min)} V
  bus_voltage_max: {_num(v_max)} V
  pwm_frequency: {_num(pwm / 1000)} kHz
  pwm_alignment: {alignment}
  timer_clock: 72 MHz
  dead_time: {_num(dead_ns)} ns

hall:
  # Code (A B C as bits 2 1 0) of each 60 deg sector in forward rotation (Table 1).
  sequence: [5, 4, 6, 2, 3, 1]
  timer_clock: {_num(Fraction(hall_clock) / 1000)} kHz
  counter_bits: 16
  # percent: how much shorter a sector may be than the one its commutation timing was
  # computed from; a commutation ends that much (rounded up to 1/2^k) before its sector
  sector_shortening: {SECTOR_SHORTENING_DEFAULT_PERCENT}

adc:
  bits: 12
  reference: 3.3 V
  bus_voltage_divider: {divider}
  current_gain: {_num(gain_mv)} mV/A
  current_offset: 1.65 V

controller:
  method: {method}
  braking_current_min: 0 A
  braking_current_nominal: {_num(i_nom)} A
  braking_current_max: {_num(i_max)} A
  speed_min: {_num(n_min)} rpm
  speed_max: {_num(n_max)} rpm

accuracy:
  duty_counts: {_num(targets.duty_counts) if targets.duty_counts != 1 else "1.0"}
  commutation_time_ticks: {_num(budget)}
  current_loop_duty_counts: {_num(loop_counts) if loop_counts != 1 else "1.0"}
  # Declared relaxation (as in spec/paper_motor.yaml): where the commutation time is
  # ill-conditioned (an error of one count in Eq. 20's denominator, or in the
  # resistance-aware rule's turn-off current, moves t_com by more than
  # ill_conditioned_above ticks), t_com need only be within the target of the exact time
  # for an error of up to ill_conditioned_counts there; their product is the target, so
  # outside that region the plain target is the stricter one.
  ill_conditioned_above: {_num(budget * 10)}
  ill_conditioned_counts: 0.1

# The speeds (and the current controller's main duty there) the audit, the Unity tests
# and the simulation report on.
operating_points:
{point_lines}

# The braking drive around the core: current sensing, the braking-current PI, the
# protection and the firmware build (see spec/paper_motor.yaml).
sensing:
  topology: dc_link_shunt
  current_channels: [0]
  bus_voltage_channel: 1
  settling_time: {_num(SETTLING_TIME_S * 10**6)} us
  adc_sample_time: {_num(SAMPLE_CYCLES)}

current_loop:
  bandwidth: {_num(bandwidth_hz)} Hz

protection:
  over_current: {_num(over_current)} A
  break_input: active_low
  short_circuit_current_max: {_num(short_max)} A
  safe_state: all_off

firmware:
  integration: vector_table
  hse_startup_timeout: 10 ms
  watchdog_timeout: 20 ms
  flash_budget: 8192
  ram_budget: {640 if method == "improved_r" else 512}
  cpu_load_budget: 25
  current_loop_budget: 150

sources:
{source_lines}
"""


def _yaml_string(text: str) -> str:
    return '"' + text.replace("\\", "\\\\").replace('"', '\\"') + '"'


def write_new_spec(name: str, sheet: Datasheet, path: Path) -> Written:
    """Write the spec and run `generate`'s fixed-point designs on it (the current loop's,
    then the commutation core's): a target a design cannot meet becomes the one it meets
    (`codegen.init_design`), with a note; the caller reports what still does not fit."""
    targets = Targets()
    write_atomically(path, render_spec(name, sheet, targets))
    try:
        spec = load_spec(path)
    except SpecError as exc:
        return Written(path, exc, ())
    # the designs import the IR and its prover: only once the spec loads
    from codegen.control.current_loop import accuracy_needed, design, widest_design
    from codegen.init_design import meet_core_targets
    from codegen.methods.base import FixedPointError

    notes: tuple[str, ...] = ()

    def rewrite(raised: Targets) -> Spec:
        write_atomically(path, render_spec(name, sheet, raised))
        return load_spec(path)

    try:
        loop_refusal: FixedPointError | None = None
        try:
            needed = accuracy_needed(widest_design(spec))
            if spec.accuracy.current_loop_duty_counts < needed <= LOOP_DUTY_COUNTS_MAX:
                # the PI's widest format cannot meet 1 count: the spec says what it does
                # meet (beyond what a spec may ask, the design's refusal below names what
                # builds: a 1 H, 100 ohm motor's 35.5 counts had been written, and refused
                # by the loader)
                targets = replace(targets, loop_counts=_round_up(needed * 100, 1) / 100)
                spec = rewrite(targets)
            design(spec)
        except FixedPointError as exc:
            loop_refusal = exc
        checked = meet_core_targets(spec, targets, rewrite)
        spec, notes = checked.spec, checked.notes
        # the refusal `generate` gives: it designs the core before the loop (init had
        # named the PI's bandwidth where generate named the Hall clock)
        if checked.refusal is not None:
            raise checked.refusal
        if loop_refusal is not None:
            raise loop_refusal
    except SpecError as exc:
        return Written(path, exc, (), notes)
    except FixedPointError as exc:
        # no format at all (a k_i below one LSB, a core no target rescues): said now, not
        # by `generate` after "init: next: ... generate" (a 1 mohm, 500 mH motor)
        return Written(path, DesignRefusal(str(path), exc.key, str(exc)), (), notes)
    from codegen.init_load import over_budget

    load = over_budget(spec)
    if load is not None:
        # the bench flags it after a build; said here, where the PWM frequency and the
        # top speed are still being chosen (an 80 kHz motor: 32 % in the bench)
        notes = (*notes, load)
    return Written(path, None, spec.warnings, notes)

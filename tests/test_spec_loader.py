"""Tests of codegen.spec_loader: the default spec loads exactly, and bad specs are refused.

Every bad spec is the default spec with one mutation. Each case checks that the SpecError
message names the key path, a fragment of the problem or the allowed range and, for
quantities, the unit, so a user can fix the YAML from the message alone.
"""

from __future__ import annotations

import hashlib
import re
from collections.abc import Callable
from fractions import Fraction
from pathlib import Path
from typing import Any

import pytest
import yaml

from codegen.errors import SpecError
from codegen.spec_loader import load_spec

ROOT = Path(__file__).resolve().parents[1]
DEFAULT_SPEC = ROOT / "spec" / "paper_motor.yaml"
DEFAULT_TEXT = DEFAULT_SPEC.read_text(encoding="utf-8")

Mutation = Callable[[str], str]


def _line_of(fragment: str) -> int:
    """1-based line of the one line of the default spec that contains `fragment`."""
    hits = [n for n, line in enumerate(DEFAULT_TEXT.splitlines(), start=1) if fragment in line]
    assert len(hits) == 1, f"{fragment!r} is not on exactly one line of {DEFAULT_SPEC}"
    return hits[0]


INDUCTANCE_LINE = _line_of("phase_inductance: 0.56 mH")
POLES_LINE = _line_of("  poles: 2")


def _replace(old: str, new: str) -> Mutation:
    """Text mutation: replace the one occurrence of `old` (keeps comments and lines)."""

    def mutate(text: str) -> str:
        assert text.count(old) == 1, f"{old!r} is not unique in the default spec"
        return text.replace(old, new)

    return mutate


def _edit_line(start: str, new: str) -> Mutation:
    """Text mutation: replace the whole line that starts with `start`."""

    def mutate(text: str) -> str:
        lines = text.splitlines(keepends=True)
        hits = [n for n, line in enumerate(lines) if line.startswith(start)]
        assert len(hits) == 1, f"{start!r} does not start exactly one line of the default spec"
        lines[hits[0]] = new + "\n"
        return "".join(lines)

    return mutate


def _edit(change: Callable[[dict[str, Any]], object]) -> Mutation:
    """Data mutation: load the YAML, change the parsed mapping in place, dump it again."""

    def mutate(text: str) -> str:
        data = yaml.safe_load(text)
        change(data)
        return yaml.safe_dump(data, sort_keys=False)

    return mutate


def _as_list(text: str) -> str:
    return yaml.safe_dump([yaml.safe_load(text)], sort_keys=False)


def _write(tmp_path: Path, text: str, name: str = "bad.yaml") -> Path:
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


# --------------------------------------------------------------------------- good specs


def test_default_spec_loads_in_exact_si() -> None:
    spec = load_spec(DEFAULT_SPEC)

    assert spec.name == "paper_motor"
    assert spec.source_path == str(DEFAULT_SPEC)
    assert spec.sha256 == hashlib.sha256(DEFAULT_SPEC.read_bytes()).hexdigest()

    motor = spec.motor
    assert motor.rated_voltage_v == Fraction(24)
    assert motor.phase_resistance_ohm == Fraction(21, 100)
    assert motor.phase_inductance_h == Fraction(7, 12500)
    assert motor.back_emf_constant_v_per_rpm == Fraction(236, 100000)
    assert motor.back_emf_convention == "phase"
    assert motor.rotor_inertia_kg_m2 == Fraction(119, 100000)
    assert motor.poles == 2
    assert motor.pole_pairs == 1

    inverter = spec.inverter
    assert inverter.bus_voltage_nominal_v == 24
    assert (inverter.bus_voltage_min_v, inverter.bus_voltage_max_v) == (20, 30)
    assert inverter.pwm_frequency_hz == 20_000
    assert inverter.timer_clock_hz == 72_000_000
    assert inverter.pwm_alignment == "edge"
    assert inverter.dead_time_s == Fraction(1, 2_000_000)

    assert spec.hall.sequence == (5, 4, 6, 2, 3, 1)
    assert spec.hall.timer_clock_hz == 1_000_000
    assert spec.hall.counter_bits == 16

    assert spec.adc.bits == 12
    assert spec.adc.reference_v == Fraction(33, 10)
    assert spec.adc.bus_voltage_divider == 11
    assert spec.adc.current_gain_v_per_a == Fraction(1, 20)
    assert spec.adc.current_offset_v == Fraction(33, 20)

    controller = spec.controller
    assert controller.method == "improved"
    assert controller.braking_current_min_a == 0
    assert controller.braking_current_nominal_a == 5
    assert controller.braking_current_max_a == 10
    assert (controller.speed_min_rpm, controller.speed_max_rpm) == (200, 5000)

    assert spec.accuracy.duty_counts == Fraction(3, 4)
    assert (spec.accuracy.ill_conditioned_above, spec.accuracy.ill_conditioned_counts) == (
        80,
        Fraction(1, 10),
    )
    assert spec.accuracy.commutation_time_ticks == 8

    assert [(p.speed_rpm, p.main_duty) for p in spec.operating_points] == [
        (1500, Fraction(21, 50)),
        (4600, Fraction(21, 50)),
    ]

    # Every SI value is an exact Fraction, never a binary float.
    exact = [
        motor.rated_voltage_v,
        motor.phase_resistance_ohm,
        motor.phase_inductance_h,
        motor.back_emf_constant_v_per_rpm,
        motor.rotor_inertia_kg_m2,
        inverter.bus_voltage_nominal_v,
        inverter.pwm_frequency_hz,
        inverter.dead_time_s,
        spec.adc.current_gain_v_per_a,
        controller.speed_max_rpm,
        spec.accuracy.duty_counts,
        *(p.main_duty for p in spec.operating_points),
    ]
    assert all(type(value) is Fraction for value in exact)

    sources = dict(spec.sources)
    assert sources["motor.phase_inductance"] == "paper Table 3"
    assert ("inverter.dead_time", sources["inverter.dead_time"]) in spec.assumptions


def test_line_to_line_convention_halves_back_emf_constant(tmp_path: Path) -> None:
    text = _replace("back_emf_convention: phase", "back_emf_convention: line_to_line")(DEFAULT_TEXT)
    spec = load_spec(_write(tmp_path, text, "line_to_line.yaml"))

    assert spec.motor.back_emf_convention == "line_to_line"
    assert spec.motor.back_emf_constant_v_per_rpm == Fraction(118, 100000)
    assert type(spec.motor.back_emf_constant_v_per_rpm) is Fraction


@pytest.mark.parametrize("shape", ["30 deg", "90 deg", "120 deg", "150 deg"])
def test_a_line_to_line_constant_should_be_the_peak_line_emf_of_the_spec_shape(
    tmp_path: Path, shape: str
) -> None:
    """A datasheet's line-to-line constant is its peak line-to-line EMF per rpm: E is that
    over the shape's lambda, which is 2 only for a flat top of 60 deg or more (halving
    read a 30 deg motor's E 20 % low). Checked with the PIL's own peak of e_a - e_b,
    taken numerically from sim's waveform of the shape."""
    from emulation.pil.scenarios import peak_line_emf_v

    text = _replace("back_emf_convention: phase", "back_emf_convention: line_to_line")(DEFAULT_TEXT)
    text = text.replace(
        "\n  back_emf_convention: line_to_line\n",
        f"\n  back_emf_convention: line_to_line\n  back_emf_shape: {shape}\n",
    )
    spec = load_spec(_write(tmp_path, text, "line_to_line_shape.yaml"))
    datasheet = Fraction(236, 100000)  # the paper motor's 2.36 V/krpm, read as line to line
    assert peak_line_emf_v(spec, 1000.0) == pytest.approx(float(datasheet * 1000), rel=1e-3)
    if shape in ("90 deg", "120 deg", "150 deg"):
        assert spec.motor.back_emf_constant_v_per_rpm == datasheet / 2


# --------------------------------------------------------------------------- bad specs

BAD_SPECS = [
    # ---- YAML structure
    pytest.param(
        _replace("phase_inductance: 0.56 mH", "phase_inductance: 0.56 mH: oops"),
        "motor.phase_inductance",
        ("malformed YAML", "mapping values are not allowed", f"bad.yaml:{INDUCTANCE_LINE}"),
        id="malformed-yaml-cites-line-and-key",
    ),
    pytest.param(
        lambda text: f"{text}---\nname: other\n",
        "<document>",
        (
            "the file holds more than one YAML document",
            f"second one starts at line {DEFAULT_TEXT.count(chr(10)) + 1}",
            f"bad.yaml:{DEFAULT_TEXT.count(chr(10)) + 1}:",
        ),
        id="a-second-document-is-named-at-its-line",  # was: the last key, "malformed YAML"
    ),
    pytest.param(
        _replace("  poles: 2\n", "\tpoles: 2\n"),
        "motor.poles",
        ("malformed YAML", "found character '\\t'", f"bad.yaml:{POLES_LINE}"),
        id="tab-indent-names-its-key",  # was: motor.phase_inductance, the line above
    ),
    pytest.param(
        _replace("  poles: 2\n", "  poles: 2\n  poles: 4\n"),
        "motor.poles",
        (
            "duplicate key 'poles'",
            f"first defined on line {POLES_LINE}",
            f"bad.yaml:{POLES_LINE + 1}",
        ),
        id="duplicate-key",
    ),
    pytest.param(
        _replace("name: paper_motor\n", "name: paper_motor\n? [a, b]\n: 1\n"),
        "<document>",
        ("a mapping key must be a plain value",),
        id="unhashable-key",
    ),
    pytest.param(_as_list, "<document>", ("must be a YAML mapping",), id="top-level-is-list"),
    pytest.param(lambda _: "", "<document>", ("must be a YAML mapping",), id="empty-document"),
    pytest.param(
        _replace("name: paper_motor\n", "name: paper_motor\ncolour: red\n"),
        "colour",
        ("unknown key", "name, description, motor"),
        id="unknown-top-level-key",
    ),
    pytest.param(
        _replace("  poles: 2\n", "  poles: 2\n  colour: red\n"),
        "motor.colour",
        ("unknown key", "rated_voltage, phase_resistance"),
        id="unknown-nested-key",
    ),
    pytest.param(
        _edit(lambda d: d.pop("hall")), "hall", ("missing required section",), id="missing-section"
    ),
    pytest.param(
        _edit(lambda d: d.update(motor=5)),
        "motor",
        ("must be a mapping of keys, got an integer",),
        id="section-not-a-mapping",
    ),
    pytest.param(
        # the allowed keys named whole: the optional ones too (a hunt: 3 of 5 were named)
        _edit(lambda d: d.update(accuracy=1)),
        "accuracy",
        (
            "(allowed: a mapping of duty_counts, commutation_time_ticks,"
            " current_loop_duty_counts; optionally ill_conditioned_above,"
            " ill_conditioned_counts)",
        ),
        id="section-not-a-mapping-with-optional-keys",
    ),
    pytest.param(
        _edit(lambda d: d["motor"].pop("phase_inductance")),
        "motor.phase_inductance",
        ("missing required key", "(allowed: [1e-07, 1] H; units: H, mH, uH)"),
        id="missing-key",
    ),
    pytest.param(
        _edit_line("description:", "description: &x [*x]"),
        "description",
        ("recursive alias *x",),
        id="recursive-alias",
    ),
    pytest.param(
        _replace("hse_startup_timeout: 10 ms", "hse_startup_timeout: 1 ms"),
        "firmware.hse_startup_timeout",
        ("0.001 s is out of range", "(allowed: [0.002, 1] s (at least the HSE crystal's typical"),
        id="hse-timeout-below-the-crystals-start-up",  # latched CLOCK at every start (PIL)
    ),
    pytest.param(
        lambda t: _replace("watchdog_timeout: 20 ms", "watchdog_timeout: 10 ms")(
            _replace("pwm_frequency: 20 kHz", "pwm_frequency: 1.5 kHz")(
                _replace("pwm_alignment: edge", "pwm_alignment: center")(
                    _replace("  bandwidth: 1 kHz", "  bandwidth: 100 Hz")(t)
                )
            )
        ),
        "firmware.watchdog_timeout",
        ("a period takes 0.006 s", "(allowed: >= 0.012 s at 1500 Hz)"),
        id="watchdog-shorter-than-two-pwm-periods-on-the-hsi",  # starved in `make pil`
    ),
    pytest.param(
        lambda t: _replace("  poles: 2\n", "  poles: 32\n")(
            _replace("pwm_frequency: 20 kHz", "pwm_frequency: 5 kHz")(
                _replace("  bandwidth: 1 kHz", "  bandwidth: 400 Hz")(t)
            )
        ),
        "controller.speed_max",
        (
            "its 60 deg sector (125.0 Hall ticks) is not longer than the 212-tick guard a"
            " commutation ends by before its sector does",
            "for one current sample: a PWM period and the ADC's injected sequence",
            "(allowed: <= 2741.2 rpm, or a higher PWM frequency or a shorter dead time",
        ),
        # the guard keeps a current sample after each commutation's end, and so covers
        # the loop's first sample after the edge: never sampled, no braking (PIL)
        id="sector-shorter-than-the-end-guard-and-its-current-sample",
    ),
    # ---- quantities and units
    pytest.param(
        _replace("0.56 mH", "0.56 mF"),
        "motor.phase_inductance",
        ("unit 'mF' is not an inductance unit", "H, mH, uH", f"bad.yaml:{INDUCTANCE_LINE}"),
        id="wrong-unit",
    ),
    pytest.param(
        _replace("0.56 mH", "0.56"),
        "motor.phase_inductance",
        ("missing unit for an inductance", "H, mH, uH", "[1e-07, 1] H"),
        id="missing-unit-bare-number",
    ),
    pytest.param(
        _replace("rated_voltage: 24 V", "rated_voltage: '24'"),
        "motor.rated_voltage",
        ("missing unit for a voltage", "V, mV, kV"),
        id="missing-unit-in-string",
    ),
    pytest.param(
        _replace("0.56 mH", "lots mH"),
        "motor.phase_inductance",
        ("not a number (ASCII digits) followed by a unit", "H, mH, uH"),
        id="non-numeric-quantity",
    ),
    pytest.param(
        _replace("0.56 mH", "[0.56, mH]"),
        "motor.phase_inductance",
        ("got a list", "H"),
        id="quantity-is-a-list",
    ),
    pytest.param(
        _replace("0.21 ohm", "-0.21 ohm"),
        "motor.phase_resistance",
        ("-0.21 ohm is out of range", "[0.0001, 100] ohm"),
        id="negative-resistance",
    ),
    pytest.param(
        _replace("0.56 mH", "0 mH"),
        "motor.phase_inductance",
        ("0 H is out of range", "[1e-07, 1] H"),
        id="zero-inductance",
    ),
    pytest.param(
        _replace("0.56 mH", "1e400 mH"),
        "motor.phase_inductance",
        ("1e+397 H is out of range", "[1e-07, 1] H"),
        id="inductance-beyond-float-range",
    ),
    pytest.param(
        _replace("timer_clock: 72 MHz", "timer_clock: 100 MHz"),
        "inverter.timer_clock",
        ("1e+08 Hz is out of range", "[1e+06, 7.2e+07] Hz"),
        id="timer-clock-too-fast",
    ),
    pytest.param(
        _replace("current_offset: 1.65 V", "current_offset: 4 V"),
        "adc.current_offset",
        ("4 V is out of range", "[0, 3.3] V"),
        id="current-offset-above-reference",
    ),
    # ---- integers, numbers and choices
    pytest.param(
        _replace("  poles: 2\n", "  poles: 3\n"),
        "motor.poles",
        ("even number of poles", "2, 4, 6"),
        id="odd-pole-count",
    ),
    pytest.param(
        _replace("  poles: 2\n", "  poles: 2.5\n"),
        "motor.poles",
        ("must be an integer", "[2, 128] poles"),
        id="pole-count-not-integer",
    ),
    pytest.param(
        _replace("  poles: 2\n", f"  poles: {'9' * 400}\n"),
        "motor.poles",
        ("a number of 400 characters (at most 64)",),
        id="pole-count-huge-integer",
    ),
    pytest.param(
        # the generated port reads the F103's 12-bit codes as they are: a 10-bit spec
        # read every code 4x high and tripped over-voltage at boot (its PIL run, with
        # the short circuit as the safe state, could not even attach the motor)
        _replace("  bits: 12\n", "  bits: 10\n"),
        "adc.bits",
        ("out of range", "[12, 12] bits (the STM32F103's ADC)"),
        id="adc-not-12-bit",
    ),
    pytest.param(
        _replace("  reference: 3.3 V\n", "  reference: 5 V\n"),
        "adc.reference",
        ("out of range", "[2.4, 3.6] V (the STM32F103's VREF+)"),
        id="adc-reference-above-vdda",
    ),
    pytest.param(
        _replace("counter_bits: 16", "counter_bits: 32"),
        "hall.counter_bits",
        ("out of range", "[16, 16] bits"),
        id="hall-counter-not-16-bit",
    ),
    pytest.param(
        _replace("duty_counts: 0.75", "duty_counts: .nan"),
        "accuracy.duty_counts",
        ("must be a finite number", "(0.5, 16] TIM1 counts"),
        id="duty-accuracy-nan",
    ),
    pytest.param(
        _replace("duty_counts: 0.75", f"duty_counts: {'9' * 400}"),
        "accuracy.duty_counts",
        ("a number of 400 characters (at most 64)",),
        id="duty-accuracy-huge-integer",
    ),
    pytest.param(
        _replace("back_emf_convention: phase", "back_emf_convention: line"),
        "motor.back_emf_convention",
        ("not a known option", "phase, line_to_line"),
        id="emf-convention-unknown",
    ),
    pytest.param(
        _replace("method: improved", "method: magic"),
        "controller.method",
        ("not a known option", "improved, conventional, none"),
        id="method-magic",
    ),
    # ---- inverter
    pytest.param(
        _edit(lambda d: d["inverter"].update(bus_voltage_min="30 V", bus_voltage_max="20 V")),
        "inverter.bus_voltage_max",
        ("bus voltage range is empty or inverted", "> bus_voltage_min = 30 V"),
        id="bus-voltage-range-inverted",
    ),
    pytest.param(
        _replace("bus_voltage_nominal: 24 V", "bus_voltage_nominal: 35 V"),
        "inverter.bus_voltage_nominal",
        ("outside the operating range", "[20, 30] V"),
        id="bus-voltage-nominal-outside-range",
    ),
    pytest.param(
        _replace("rated_voltage: 24 V", "rated_voltage: 12 V"),
        "inverter.bus_voltage_nominal",
        ("more than 1.5 x the motor's rated 12 V", "<= 18 V"),
        id="bus-voltage-far-above-motor-rating",
    ),
    pytest.param(
        _replace("pwm_frequency: 20 kHz", "pwm_frequency: 7 kHz"),
        "inverter.pwm_frequency",
        ("10285.7 TIM1 counts", "a whole number of counts in [256, 32767]"),
        id="pwm-period-not-integer",
    ),
    pytest.param(
        # 36000 counts: Eq. 18's D_on reaches 2 x that in the core's 16-bit compares (it
        # used to be refused by the fixed-point design, naming the time accuracy)
        _replace("pwm_frequency: 20 kHz", "pwm_frequency: 2 kHz"),
        "inverter.pwm_frequency",
        ("36000 TIM1 counts", "twice the period's counts", "2197.33 to 281250 Hz"),
        id="pwm-period-beyond-16-bit-duties",
    ),
    pytest.param(
        # a 1 MHz timer clock leaves 50 counts at 20 kHz: the allowed range had read
        # "at least 30.5185 Hz", which 20 kHz is (a helper's hunt); the top is the bound
        _replace("timer_clock: 72 MHz", "timer_clock: 1 MHz"),
        "inverter.pwm_frequency",
        ("50 TIM1 counts", "30.5185 to 3906.25 Hz at this timer_clock"),
        id="pwm-period-too-few-counts",
    ),
    pytest.param(
        _replace("dead_time: 500 ns", "dead_time: 3 us"),
        "inverter.dead_time",
        ("more than 10 % of the PWM period", "< 2.5e-06 s at 20000 Hz"),
        id="dead-time-too-long",
    ),
    pytest.param(
        _replace("bus_voltage_max: 30 V", "bus_voltage_max: 40 V"),
        "inverter.bus_voltage_max",
        ("beyond the ADC full scale", "< 36.2911 V"),
        id="bus-voltage-beyond-adc-full-scale",
    ),
    pytest.param(
        # HTR would be 4096, which ADC1's 12-bit field holds as 0 (a hunt: under-voltage
        # latched at boot, the drive never armed)
        _replace("bus_voltage_max: 30 V", "bus_voltage_max: 36.3 V"),
        "inverter.bus_voltage_max",
        ("no ADC code above it for the over-voltage watchdog", "< 36.2911 V"),
        id="bus-voltage-at-adc-full-scale",
    ),
    # ---- Hall sensor
    pytest.param(
        _replace("[5, 4, 6, 2, 3, 1]", "[5, 4, 6, 2, 3, 0]"),
        "hall.sequence[5]",
        ("000 and 111 are the invalid", "six distinct codes 1..6"),
        id="hall-code-0",
    ),
    pytest.param(
        _replace("[5, 4, 6, 2, 3, 1]", "[5, 4, 7, 2, 3, 1]"),
        "hall.sequence[2]",
        ("000 and 111 are the invalid", "six distinct codes 1..6"),
        id="hall-code-7",
    ),
    pytest.param(
        _replace("[5, 4, 6, 2, 3, 1]", "[5, 4, 6, 2, 3, 3]"),
        "hall.sequence",
        ("Hall codes repeat", "six distinct codes 1..6"),
        id="hall-code-repeated",
    ),
    pytest.param(
        _replace("[5, 4, 6, 2, 3, 1]", "[5, 4, 6, 2, 1, 3]"),
        "hall.sequence[4]",
        ("not a Gray step from 010 to 001", "differing in exactly one bit"),
        id="hall-sequence-not-gray",
    ),
    pytest.param(
        _replace("[5, 4, 6, 2, 3, 1]", "[5, 4, 6, 2, 3]"),
        "hall.sequence",
        ("must list the six Hall codes", "six distinct codes 1..6"),
        id="hall-sequence-wrong-length",
    ),
    pytest.param(
        _replace("[5, 4, 6, 2, 3, 1]", "[5, 4, 6, 2, 3, '1']"),
        "hall.sequence[5]",
        ("Hall code must be an integer",),
        id="hall-code-not-integer",
    ),
    # ---- controller
    pytest.param(
        _replace("speed_max: 5000 rpm", "speed_max: 5100 rpm"),
        "controller.speed_max",
        ("U_d/(2 k_e) = 5084.7 rpm", "< 5084.7 rpm"),
        id="speed-max-above-emf-limit",
    ),
    pytest.param(
        _edit(lambda d: d["controller"].update(speed_min="3000 rpm", speed_max="2000 rpm")),
        "controller.speed_max",
        ("speed range is empty or inverted", "> speed_min = 3000 rpm"),
        id="speed-range-inverted",
    ),
    pytest.param(
        _replace("speed_min: 200 rpm", "speed_min: 100 rpm"),
        "controller.speed_min",
        ("beyond the 16-bit counter", ">= 152.6 rpm at 1e+06 Hz"),
        id="speed-min-overflows-hall-counter",
    ),
    pytest.param(
        _edit(
            lambda d: d["controller"].update(braking_current_min="10 A", braking_current_max="5 A")
        ),
        "controller.braking_current_max",
        ("braking current range is empty or inverted", "> braking_current_min = 10 A"),
        id="braking-current-range-inverted",
    ),
    pytest.param(
        # 4000-4001 rpm: 0.6 Hall ticks; a rotor at 4000.5 rpm read 2499 and tripped
        # OVER_SPEED (the PIL's fault scenarios failed 11 of 17 on it)
        _edit(
            lambda d: (
                d["controller"].update(speed_min="4000 rpm", speed_max="4001 rpm"),
                d.update(
                    operating_points=[
                        {"speed": "4000 rpm", "main_duty": 0.42},
                        {"speed": "4001 rpm", "main_duty": 0.42},
                    ]
                ),
            )
        ),
        "controller.speed_max",
        ("spans only 0.6 Hall timer ticks", "(allowed: >= 4025.8 rpm, a range of 16 ticks"),
        id="speed-range-narrower-than-16-hall-ticks",
    ),
    pytest.param(
        # 0.25 A over 16 mA codes: 15.5 codes, too few for the loop to saturate and leave
        _edit(
            lambda d: d["controller"].update(
                braking_current_min="5 A",
                braking_current_nominal="5.1 A",
                braking_current_max="5.25 A",
            )
        ),
        "controller.braking_current_max",
        (
            "only 0.25 A above braking_current_min",
            "16 current-ADC codes",
            ">= braking_current_min + 0.257812 A",
        ),
        id="braking-current-range-narrower-than-16-codes",
    ),
    pytest.param(
        # 5 mV over 8.9 mV codes, with the tolerances narrowed to fit
        _edit(
            lambda d: (
                d["inverter"].update(
                    bus_voltage_min="23.998 V",
                    bus_voltage_nominal="24 V",
                    bus_voltage_max="24.003 V",
                ),
                d["tolerances"].update(bus_voltage=[-0.001, 0.001]),
            )
        ),
        "inverter.bus_voltage_max",
        ("only 0.005 V above bus_voltage_min", "less than one bus-ADC code"),
        id="bus-range-narrower-than-one-code",
    ),
    pytest.param(
        _replace("braking_current_nominal: 5 A", "braking_current_nominal: 15 A"),
        "controller.braking_current_nominal",
        ("outside its range", "[0, 10] A"),
        id="braking-current-nominal-outside-range",
    ),
    pytest.param(
        _replace("braking_current_nominal: 5 A", "braking_current_nominal: 0 A"),
        "controller.braking_current_nominal",
        ("braking needs a current", "(0, 10] A"),
        id="braking-current-nominal-zero",
    ),
    pytest.param(
        _replace("braking_current_max: 10 A", "braking_current_max: 40 A"),
        "controller.braking_current_max",
        ("beyond the current-sense range", "<= 33 A"),
        id="braking-current-beyond-current-sense",
    ),
    pytest.param(
        # above braking_current_max (10 A) but not above its PWM ripple's peak (10.33 A)
        _replace("over_current: 15 A", "over_current: 10.2 A"),
        "protection.over_current",
        (
            "at or below the braking current's peak",
            "its valley, sampled at the end of the OFF time",
            "0.3348 A of PWM ripple",
            "normal braking would trip it",
            "(allowed: > 10.33 A)",
        ),
        id="over-current-within-the-pwm-ripple",
    ),
    pytest.param(
        # reads 10.25 A: braking_current_max (10 A) but not its ripple's peak (10.33 A)
        _replace("current_gain: 50 mV/A", "current_gain: 161 mV/A"),
        "adc.current_gain",
        ("reads at most", "10.25 A", "10.33 A", "CURRENT_SENSOR", "(allowed: <= 159.7 mV/A)"),
        id="current-sense-below-the-pwm-ripples-peak",
    ),
    pytest.param(
        # reads 13.75 A: above the ripple's peak (10.33 A), below the 15 A trip
        _replace("current_gain: 50 mV/A", "current_gain: 120 mV/A"),
        "adc.current_gain",
        (
            "reads at most",
            "13.75 A",
            "below protection.over_current 15 A",
            "failed sensor",
            "(allowed: <= 110 mV/A)",
        ),
        id="current-sense-below-the-over-current-trip",
    ),
    # ---- operating points
    pytest.param(
        _replace("{speed: 4600 rpm", "{speed: 6000 rpm"),
        "operating_points[1].speed",
        ("outside the controller speed range", "[200, 5000] rpm"),
        id="operating-point-speed-outside-range",
    ),
    pytest.param(
        # a second duty at one speed: two Unity tests of one name (the suite did not
        # compile) and one simulation figure over the other
        _replace("{speed: 4600 rpm, main_duty: 0.42}", "{speed: 1500.5 rpm, main_duty: 0.6}"),
        "operating_points[1].speed",
        ("within 1 rpm of operating_points[0].speed (1500 rpm)", "at least 1 rpm from every"),
        id="operating-points-at-one-speed",
    ),
    pytest.param(
        _replace("{speed: 1500 rpm, main_duty: 0.42}", "{speed: 1500 rpm, main_duty: 1.5}"),
        "operating_points[0].main_duty",
        ("out of range", "[0, 1]"),
        id="main-duty-above-one",
    ),
    pytest.param(
        _replace("{speed: 1500 rpm, main_duty: 0.42}", "{speed: 1500 rpm, duty: 0.42}"),
        "operating_points[0].duty",
        ("unknown key", "speed, main_duty"),
        id="operating-point-unknown-key",
    ),
    # ---- sources and identity
    pytest.param(
        _replace("sources:\n", 'sources:\n  motor.colour: "paper Table 3"\n'),
        "sources.motor.colour",
        ("names a key that the spec does not have",),
        id="source-for-missing-key",
    ),
    pytest.param(
        _replace('hall.sequence: "paper Table 1"', 'hall.sequence: ""'),
        "sources.hall.sequence",
        ("must be a non-empty description",),
        id="source-empty",
    ),
    pytest.param(
        _replace("name: paper_motor", "name: Paper Motor"),
        "name",
        ("must be a lower-case identifier", "[a-z][a-z0-9_]{0,63}"),
        id="name-not-identifier",
    ),
    pytest.param(
        _replace("name: paper_motor", 'name: "paper_motor\\n"'),
        "name",
        ("must be a lower-case identifier",),
        id="name-with-trailing-newline",
    ),
    pytest.param(
        _replace("name: paper_motor", "name: paper"),
        "name",
        ("reserved", "generated/paper/ holds the paper's audit", "any other"),
        id="name-of-the-paper-audit-folder",
    ),
    pytest.param(
        _edit(lambda d: d.update(operating_points=None)),
        "operating_points",
        ("operating_points = null: must be a list, got an empty value (null)",),
        id="operating-points-null",  # had reached the physics checks: a TypeError
    ),
    pytest.param(
        _edit(lambda d: d.update(sources=None)),
        "sources",
        ("sources = null: must map key paths", "got an empty value (null)"),
        id="sources-null",  # had skipped the provenance check: exit 0
    ),
    pytest.param(
        _edit(lambda d: d["motor"].update(poles=True)),
        "motor.poles",
        ("motor.poles = true: ",),
        id="poles-boolean-in-yamls-words",
    ),
]


@pytest.mark.parametrize(("mutate", "key_path", "fragments"), BAD_SPECS)
def test_bad_spec_is_refused(
    tmp_path: Path, mutate: Mutation, key_path: str, fragments: tuple[str, ...]
) -> None:
    path = _write(tmp_path, mutate(DEFAULT_TEXT))

    with pytest.raises(SpecError) as caught:
        load_spec(path)

    error = caught.value
    message = str(error)
    assert error.path == key_path
    assert f"{key_path} = " in message
    assert message.startswith(str(path))
    for fragment in fragments:
        assert fragment in message, f"{fragment!r} not in {message!r}"


def _required_leaves() -> list[str]:
    """Every required key path of the default spec below a section (not the sources,
    the optional tolerances or the optional relaxation pair)."""
    data = yaml.safe_load(DEFAULT_TEXT)
    return [
        f"{section}.{key}"
        for section, body in data.items()
        if isinstance(body, dict) and section not in ("sources", "tolerances")
        for key in body
        if not key.startswith("ill_conditioned_")
    ]


@pytest.mark.parametrize("key_path", _required_leaves())
def test_a_missing_key_says_what_it_takes(tmp_path: Path, key_path: str) -> None:
    """A missing key once said only "see spec/paper_motor.yaml", a file a user's own
    spec folder need not hold: the message states what the key takes (its range and
    unit, its options, its form) in the same line."""
    section, key = key_path.split(".")
    path = _write(tmp_path, _edit(lambda d: d[section].pop(key))(DEFAULT_TEXT))

    with pytest.raises(SpecError) as caught:
        load_spec(path)

    message = str(caught.value).splitlines()[0]
    assert f"{key_path} = (missing): missing required key (allowed: " in message, message
    assert "paper_motor.yaml" not in message, message


def test_out_of_range_quantity_states_value_and_allowed_range(tmp_path: Path) -> None:
    path = _write(tmp_path, _replace("0.56 mH", "2 H")(DEFAULT_TEXT))

    with pytest.raises(SpecError) as caught:
        load_spec(path)

    error = caught.value
    assert error.path == "motor.phase_inductance"
    assert error.value == "2 H"
    assert error.problem == "2 H is out of range"
    assert error.allowed == "[1e-07, 1] H"
    assert error.line == INDUCTANCE_LINE
    assert str(error) == (
        f"{path}:{INDUCTANCE_LINE}: motor.phase_inductance = '2 H': 2 H is out of range"
        " (allowed: [1e-07, 1] H)"
    )


@pytest.mark.parametrize("timeout", ["1 ms", "10 s"])
def test_a_quantity_at_an_inclusive_bound_should_be_accepted(tmp_path: Path, timeout: str) -> None:
    """The bounds are compared as the decimals the message prints: 1 ms is the exact
    1/1000 s, which the double 1e-3 lies a little above, and was refused with
    "0.001 s is out of range (allowed: [0.001, 10] s)"."""
    path = _write(
        tmp_path, _replace("watchdog_timeout: 20 ms", f"watchdog_timeout: {timeout}")(DEFAULT_TEXT)
    )
    spec = load_spec(path)
    assert spec.firmware.watchdog_timeout_s == {"1 ms": Fraction(1, 1000), "10 s": 10}[timeout]


def test_a_range_should_hold_both_of_its_decimal_bounds() -> None:
    """0.1 and 0.3 as doubles lie above 1/10 and below 3/10: each end still holds its
    exact decimal, and an open end still refuses it."""
    from codegen.spec_loader import _Range

    closed = _Range(0.1, 0.3, "s")
    assert closed.contains(Fraction(1, 10)) and closed.contains(Fraction(3, 10))
    assert not closed.contains(Fraction(99, 1000)) and not closed.contains(Fraction(301, 1000))
    opened = _Range(0.1, 0.3, "s", low_inclusive=False, high_inclusive=False)
    assert not opened.contains(Fraction(1, 10)) and not opened.contains(Fraction(3, 10))
    assert opened.contains(Fraction(2, 10))
    assert _Range(None, None, "").contains(Fraction(10) ** 400)


def test_unreadable_file_is_a_spec_error(tmp_path: Path) -> None:
    missing = tmp_path / "missing.yaml"
    with pytest.raises(SpecError, match="cannot read spec") as caught:
        load_spec(missing)
    assert caught.value.path == "<file>"

    latin1 = tmp_path / "latin1.yaml"
    latin1.write_bytes(DEFAULT_TEXT.replace("Table 3", "Tabl\xe9 3").encode("latin-1"))
    with pytest.raises(SpecError, match="not UTF-8"):
        load_spec(latin1)


TINY4P = ROOT / "tests" / "fixtures" / "pil" / "tiny4p_init_before_ripple.yaml"


def test_a_small_inductance_should_need_sensing_and_a_trip_above_its_pwm_ripple() -> None:
    """A new user's motor as `bldc-codegen init` wrote it before the ripple was counted
    (2 x 5 uH at 20 kHz, 30 V bus_voltage_max: 37.5 A of ripple peak to peak, sampled at
    its valley): its 50 A current sensing and 60 A trip sit below the 77.5 A braking at
    40 A reaches, and the firmware latched CURRENT_SENSOR in its first commutations."""
    from codegen.errors import MultiSpecError

    with pytest.raises(MultiSpecError) as caught:
        load_spec(TINY4P)
    found = {e.path: e for e in caught.value.errors}
    assert set(found) == {"adc.current_gain", "protection.over_current"}
    assert found["adc.current_gain"].value == "33 mV/A"
    assert found["adc.current_gain"].allowed == "<= 21.29 mV/A"
    assert "37.5 A of PWM ripple" in found["adc.current_gain"].problem
    assert found["protection.over_current"].allowed == "> 77.5 A"


def test_braking_ripple_should_be_worst_at_half_the_bus_within_the_speed_range() -> None:
    from codegen.spec_drive import braking_current_peak, braking_ripple

    tiny = {
        "bus_voltage_max_v": Fraction(30),
        "pwm_frequency_hz": Fraction(20_000),
        "phase_inductance_h": Fraction(5, 10**6),
        "k_e_v_per_rpm": Fraction(1, 2000),
        "phase_resistance_ohm": Fraction(1, 40),
        "speed_min_rpm": Fraction(340),
        "speed_max_rpm": Fraction(22_800),
        "current_max_a": Fraction(40),
    }
    edge = braking_ripple(**tiny, alignment="edge")
    # y = 2E - 2RI = U/2 = 15 V is in range: D(1 - D) U T / (2L) = 30 / 4 x 50 us / 10 uH
    assert edge.y_v == 15 and edge.ripple_a == Fraction(75, 2) == edge.above_sample
    assert braking_current_peak(Fraction(40), edge) == Fraction(155, 2)
    centre = braking_ripple(**tiny, alignment="center")
    assert centre.ripple_a == edge.ripple_a and centre.above_sample == Fraction(75, 4)
    # a speed range whose largest 2E is below U/2: the worst is at speed_max, no current
    slow = braking_ripple(**(tiny | {"speed_max_rpm": Fraction(6000)}), alignment="edge")
    assert slow.y_v == 6 and slow.ripple_a == Fraction(6 * 24, 20_000 * 10 * 30) * 10**6


def test_a_pwm_ripple_above_half_the_nominal_current_should_be_warned_of(tmp_path: Path) -> None:
    """0.06 mH: the paper motor's 0.335 A of ripple grows to 3.125 A peak to peak, 62.5 %
    of its 5 A braking_current_nominal (still under its 15 A trip and 33 A sensing)."""
    text = _replace("phase_inductance: 0.56 mH", "phase_inductance: 0.06 mH")(DEFAULT_TEXT)
    # less inductance: a larger short-circuit peak at the top speed (158 A; 190 A with k_e
    # at its upper tolerance, R and L at their lower)
    text = _replace("short_circuit_current_max: 120 A", "short_circuit_current_max: 200 A")(text)
    path = _write(tmp_path, text)
    warnings = load_spec(path).warnings
    # and the 15 A trip is now within a quarter of braking_current_max of the peak
    assert [w.id for w in warnings] == ["pwm-ripple-large", "over-current-margin-small"]
    line = str(warnings[0])
    assert "motor.phase_inductance = '0.06 mH'" in line
    assert "3.125 A peak to peak" in line and "62 % of braking_current_nominal 5 A" in line
    assert load_spec(DEFAULT_SPEC).warnings == ()


def test_a_comparator_trip_just_above_the_steady_peak_should_be_warned_of(
    tmp_path: Path,
) -> None:
    """The paper motor's steady peak is braking_current_max 10 A + 0.3348 A of ripple;
    a 48 V motor whose trip sat 0.06 A above its own tripped in normal braking (a hunt:
    12 % of its 9 A command above the steady peak, after its long commutations). A trip
    less than a quarter of braking_current_max above the peak is warned of, naming the
    key, its value and the level that leaves the margin; from that level on, not."""
    thin = _write(tmp_path, _replace("over_current: 15 A", "over_current: 11 A")(DEFAULT_TEXT))
    warnings = load_spec(thin).warnings
    assert [w.id for w in warnings] == ["over-current-margin-small"]
    line = str(warnings[0])
    assert "protection.over_current = '11 A'" in line and "\n" not in line
    assert "0.6652 A above the braking current's steady peak" in line
    assert "at least 25 % of braking_current_max above it: 12.83 A" in line
    enough = _replace("over_current: 15 A", "over_current: 12.84 A")(DEFAULT_TEXT)
    assert load_spec(_write(tmp_path, enough)).warnings == ()
    assert load_spec(DEFAULT_SPEC).warnings == ()


def test_low_side_phase_shunts_should_read_the_trip_below_their_offset(tmp_path: Path) -> None:
    """Each low-side phase shunt carries the braking current both ways: the Maxon's 3.6 A
    trip needs 1.44 V of offset at 400 mV/A; 1.2 V reads only 3 A below zero (the
    offset_conventional fixture's 0.5 V on such shunts latched CURRENT_SENSOR in the
    loop at -7 A)."""
    from codegen.errors import MultiSpecError

    maxon = ROOT / "spec" / "example_maxon_ec45_flat_48v.yaml"
    text = maxon.read_text(encoding="utf-8")
    assert "  current_offset: 1.65 V\n" in text and "topology: low_side_phase_shunts" in text
    path = _write(tmp_path, text.replace("  current_offset: 1.65 V\n", "  current_offset: 1.2 V\n"))
    with pytest.raises(MultiSpecError) as caught:
        load_spec(path)
    found = {e.path: e for e in caught.value.errors}
    assert set(found) == {"adc.current_offset"}
    assert found["adc.current_offset"].allowed == ">= 1.44 V (with the gain 400 mV/A)"
    assert "3 A below zero current" in found["adc.current_offset"].problem


def test_a_too_long_adc_sample_should_name_the_sample_time_and_the_longest_that_fits(
    tmp_path: Path,
) -> None:
    """Phase shunts at 239.5 ADC cycles a sample: the window leaves no duty. The refusal
    named sensing.settling_time, which no value could fix; it names the sample time and
    the longest that leaves 25 %, and that one loads."""
    hub = ROOT / "tests" / "fixtures" / "specs" / "hub_motor_46p.yaml"
    text = hub.read_text(encoding="utf-8")
    assert text.count("adc_sample_time: 13.5") == 1
    path = _write(tmp_path, text.replace("adc_sample_time: 13.5", "adc_sample_time: 239.5"))
    with pytest.raises(SpecError) as caught:
        load_spec(path)
    lines = str(caught.value).splitlines()
    assert len(lines) == 1 and "sensing.adc_sample_time = 239.5" in lines[0], lines
    assert "(allowed: <= 71.5 ADC clock cycles" in lines[0], lines
    fits = _write(tmp_path, text.replace("adc_sample_time: 13.5", "adc_sample_time: 71.5"))
    assert load_spec(fits).sensing.adc_sample_cycles == Fraction(143, 2)


@pytest.mark.parametrize(
    ("sample", "pwm", "key", "allowed"),
    [
        # the paper motor's DC-link shunt: 239.5 cycles leave the window its duty, but four
        # injected conversions take 84 us of a 50 us period (the PIL's bus faults took 60 us)
        ("239.5", "20 kHz", "sensing.adc_sample_time", "<= 71.5 ADC clock cycles"),
        # phase shunts at 100 kHz, the loader's fastest PWM: three current conversions
        # come before the bus's; at 7.5 cycles that is 8.6 us, with the path 11.1 us
        ("7.5", "100 kHz", "sensing.adc_sample_time", "<= 1.5 ADC clock cycles"),
    ],
    ids=["long-sample", "phase-shunts-100k"],
)
def test_a_bus_fault_seen_later_than_a_pwm_period_should_be_refused_in_one_line(
    tmp_path: Path, sample: str, pwm: str, key: str, allowed: str
) -> None:
    """The analog watchdog sees a bus step within the injected sequence or the current
    sample(s) and two bus conversions; with the handler's path to MOE that must fit a
    PWM period (the safe state within one period), which also keeps the sequence from
    running into the next trigger. The longest sample that fits loads."""
    name = "paper_motor.yaml" if pwm == "20 kHz" else "example_maxon_ec45_flat_48v.yaml"
    text = (ROOT / "spec" / name).read_text(encoding="utf-8")
    edited = re.sub(r"adc_sample_time: [0-9.]+", f"adc_sample_time: {sample}", text)
    edited = re.sub(r"pwm_frequency: [0-9.]+ kHz", f"pwm_frequency: {pwm}", edited)
    edited = re.sub(r"dead_time: [0-9.]+ ns", "dead_time: 200 ns", edited)  # < 10 % at 100 kHz
    with pytest.raises(SpecError) as caught:
        load_spec(_write(tmp_path, edited))
    lines = [line for line in str(caught.value).splitlines() if "a bus fault is seen" in line]
    assert len(lines) == 1 and f"{key} = " in lines[0], str(caught.value)
    assert f"(allowed: {allowed}" in lines[0], lines
    longest = allowed.split()[1]
    fits = _write(
        tmp_path, edited.replace(f"adc_sample_time: {sample}", f"adc_sample_time: {longest}")
    )
    assert load_spec(fits).sensing.adc_sample_cycles == Fraction(longest)


def test_a_top_speed_sector_of_few_pwm_periods_should_be_warned_of(tmp_path: Path) -> None:
    """init's 1-pole-pair improved_r motor at 34 060 rpm on 8 kHz: 2.35 PWM periods a
    sector at speed_max, where make pil locked into a two-sector cycle. The loader warns,
    with the speed that keeps 4.5 periods at this PWM frequency (10 f / (p x 4.5) rpm);
    a sector of 4.52 periods (17 700 rpm) is not warned of."""
    path = Path(__file__).resolve().parent / "fixtures" / "odd" / "ir_2p_34k_few_periods.yaml"
    (warning,) = [w for w in load_spec(path).warnings if w.id == "few-pwm-periods-per-sector"]
    line = str(warning)
    assert "controller.speed_max = '34060 rpm'" in line, line
    assert "holds 2.3488 PWM periods, fewer than 4.5" in line, line
    assert "steady up to about 17777.8 rpm at this PWM frequency" in line, line
    text = path.read_text(encoding="utf-8")
    slower = text.replace("speed_max: 34060 rpm", "speed_max: 17700 rpm")
    at_limit = _write(tmp_path, slower.replace("speed: 30650 rpm", "speed: 15930 rpm"))
    assert "few-pwm-periods-per-sector" not in [w.id for w in load_spec(at_limit).warnings]


def test_a_conventional_drive_whose_commutations_fill_the_sectors_should_be_warned_of() -> None:
    """Eq. 20 (conventional) at the loop's steady braking duty is L/(2R) at every speed:
    the 0.3 A fan motor's 2.5 ms fills its sectors above 20 R/(p L) = 1000 rpm, far below
    its 27 360 rpm top (its commutations are cut at the end's guard there); a conventional
    motor whose top speed stays below that line, and the paper's improved rule, are not
    warned."""
    odd = Path(__file__).resolve().parent / "fixtures" / "odd"
    warnings = load_spec(odd / "fan8p_windup_dips.yaml").warnings
    assert [w.id for w in warnings][:1] == ["conventional-fills-sectors"]
    line = str(warnings[0])
    assert "controller.speed_max = '27360 rpm'" in line
    assert "t_com = L/(2R) = 0.0025 s" in line and "20 R/(p L) = 1000 rpm" in line
    below = load_spec(odd / "rev_hall_centre_shunts_sc.yaml")
    assert below.controller.method == "conventional" and below.warnings == ()
    assert load_spec(DEFAULT_SPEC).warnings == ()


@pytest.mark.parametrize(
    ("dimension", "typed", "meant"),
    [
        ("RESISTANCE", "kohm", None),  # was 'ohm': 1000 times off
        ("RESISTANCE", "\u00b5ohm", None),  # was 'ohm'
        ("RESISTANCE", "Mohm", None),  # was 'mohm': 1e9 times off
        ("VOLTAGE", "MV", None),  # was 'mV'
        ("INDUCTANCE", "nH", None),  # was 'H'
        ("INDUCTANCE", "MH", None),  # was 'mH'
        ("INDUCTANCE", "mh", "mH"),
        ("INDUCTANCE", "\u00b5H", "uH"),
        ("VOLTAGE", "mv", "mV"),
        ("RESISTANCE", "m\u03a9", "mohm"),
        ("RESISTANCE", "mohms", "mohm"),
        ("EMF_CONSTANT", "V/Krpm", "V/krpm"),
    ],
)
def test_a_unit_suggestion_should_never_cross_an_si_prefix(
    dimension: str, typed: str, meant: str | None
) -> None:
    """A prefix the spec does not take names a scale: no spelling of another scale is
    offered as its typo ("'0.00021 kohm' ... did you mean 'ohm'?")."""
    from codegen import units

    assert getattr(units, dimension).suggest(typed) == meant


@pytest.mark.parametrize(
    ("old", "new", "edge", "allowed"),
    [
        ("bus_voltage_min: 20 V", "bus_voltage_min: 24 V", "min", ">= bus_voltage_min +"),
        ("bus_voltage_max: 30 V", "bus_voltage_max: 24 V", "max", "<= bus_voltage_max -"),
    ],
)
def test_a_nominal_bus_within_a_code_of_a_trip_should_be_refused(
    tmp_path: Path, old: str, new: str, edge: str, allowed: str
) -> None:
    """The analog watchdog trips below bus_voltage_min's code and above
    bus_voltage_max's: a nominal bus at the minimum latched UNDER_VOLTAGE in every PIL
    scenario (init wrote one for a 1 V bus)."""
    untoleranced = _replace("  bus_voltage: [-16, 25]", "  bus_voltage: [0, 0]")(DEFAULT_TEXT)
    path = _write(tmp_path, _replace(old, new)(untoleranced))
    with pytest.raises(SpecError) as caught:
        load_spec(path)
    lines = [line for line in str(caught.value).splitlines() if "within 3 bus-ADC codes" in line]
    assert len(lines) == 1
    assert "inverter.bus_voltage_nominal = '24 V'" in lines[0]
    assert f"of bus_voltage_{edge} = 24 V" in lines[0] and f"(allowed: {allowed}" in lines[0]


@pytest.mark.parametrize(("codes", "refused"), [(1.1, True), (2.9, True), (3.05, False)])
def test_a_nominal_bus_within_the_adcs_error_of_a_trip_should_be_refused(
    tmp_path: Path, codes: float, refused: bool
) -> None:
    """A nominal bus 1.1 codes above bus_voltage_min's passed the one-code rule, and the
    PIL's bus noise (+-2 LSB, the ADC's specified error) latched UNDER_VOLTAGE (a hunt):
    the nominal bus must lie a code and the ADC's error inside the watchdog's window."""
    volts_per_code = 3.3 * 11 / 4096  # the paper motor's reference x divider / 2^12
    low = f"{24 - codes * volts_per_code:.6f}"
    untoleranced = _replace("  bus_voltage: [-16, 25]", "  bus_voltage: [0, 0]")(DEFAULT_TEXT)
    text = _replace("bus_voltage_min: 20 V", f"bus_voltage_min: {low} V")(untoleranced)
    path = _write(tmp_path, text)
    if not refused:
        assert load_spec(path).inverter.bus_voltage_min_v < 24
        return
    with pytest.raises(SpecError) as caught:
        load_spec(path)
    (line,) = [x for x in str(caught.value).splitlines() if "within 3 bus-ADC codes" in x]
    assert "and the ADC's +-2 LSB error) of bus_voltage_min" in line
    assert "(allowed: >= bus_voltage_min + 0.0265869 V)" in line, line


def test_a_none_drive_whose_natural_commutations_fill_the_sectors_should_be_warned_of(
    tmp_path: Path,
) -> None:
    """controller.method none keeps the loop's duty through the commutation, whose
    natural length is Eq. 20's L/(2R) at every speed, as the conventional one: `init
    --method none` at 560 V, 30 mH, 3 ohm on 5 kHz centre-aligned PWM had its
    commutations fill 73-87 % of the sector and failed its braking run with no warning,
    where the same motor with method conventional was warned (a helper's hunt). Below
    20 R/(p L) it is not warned."""
    text = DEFAULT_SPEC.read_text(encoding="utf-8")
    for old, new in (
        ("method: improved", "method: none"),
        ("phase_inductance: 0.56 mH", "phase_inductance: 30 mH"),
    ):
        assert old in text, old
        text = text.replace(old, new)
    spec = load_spec(_write(tmp_path, text))
    (warning,) = [w for w in spec.warnings if w.id == "none-fills-sectors"]
    line = str(warning)
    assert "L/(2R) = " in line and "controller.method improved ends" in line, line
    fast = float(str(line).split("20 R/(p L) = ")[1].split(" rpm")[0])
    assert fast < float(spec.controller.speed_max_rpm)
    slow = text.replace("phase_inductance: 30 mH", "phase_inductance: 0.56 mH")
    assert "none-fills-sectors" not in [w.id for w in load_spec(_write(tmp_path, slow)).warnings]


def test_a_preferred_short_should_be_rated_where_a_rotor_read_at_speed_max_may_run(
    tmp_path: Path,
) -> None:
    """Preferring the short, the port takes it only where it is rated for the fastest a
    rotor may run at the interval it reads, c = 1/(1 - sector_shortening) above what it
    says; rated at speed_max alone (init's rating, 698 A, safe_state edited to the
    short), it got all-off from speed_max / c up, where all-off may rectify (a helper's
    hunt: 7 PIL scenarios at 18 058 rpm). The loader asks for the bound at c x
    speed_max, naming both ways out; the same spec preferring all-off loads (the port
    takes the short wherever all-off may rectify, rated up to speed_max)."""
    path = ROOT / "tests" / "fixtures" / "refused" / "drone_short_preferred_rated_at_speed_max.yaml"
    with pytest.raises(SpecError) as caught:
        load_spec(path)
    message = str(caught.value)
    assert "protection.short_circuit_current_max = '698 A'" in message, message
    assert "c x speed_max = 19200.0 rpm" in message, message
    assert "allowed: >= 705 A" in message and "or safe_state all_off)" in message
    # within the hostile fuzzer's 600 characters a line, its 40-character path aside
    assert len(message.splitlines()[0]) - len(str(path)) <= 560
    text = path.read_text().replace("safe_state: short_circuit", "safe_state: all_off")
    preferring_off = tmp_path / "off.yaml"
    preferring_off.write_text(text)
    assert load_spec(preferring_off).protection.safe_state == "all_off"
    rated = tmp_path / "rated.yaml"
    rated.write_text(path.read_text().replace("current_max: 698 A", "current_max: 705 A"))
    assert load_spec(rated).protection.short_circuit_current_max_a == 705


@pytest.mark.parametrize("method", ["none", "conventional"])
def test_commutations_filling_most_of_the_sector_should_be_warned_of(
    tmp_path: Path, method: str
) -> None:
    """none and conventional commutations last L/(2R) at the loop's steady duty, a
    share n p L / (20 R) of the sector. The warning came only at a whole sector, but
    braking runs failed from about 73 % (`init --method none` on a 6 V 1.2 ohm 3 mH
    motor: 79-80 % at speed_max, no warning; a helper's hunt; at 62 % it passed): it
    comes from 70 %, and says the share."""
    spec = load_spec(DEFAULT_SPEC)
    r_ohm = spec.motor.phase_resistance_ohm
    pole_pairs = spec.motor.pole_pairs
    top = spec.controller.speed_max_rpm
    text = DEFAULT_SPEC.read_text(encoding="utf-8").replace("method: improved", f"method: {method}")

    def warned(share: Fraction) -> list[str]:
        henry = share * 20 * r_ohm / (pole_pairs * top)
        mh = f"{float(henry * 1000):.6f} mH"
        edited = text.replace("phase_inductance: 0.56 mH", f"phase_inductance: {mh}")
        return [str(w) for w in load_spec(_write(tmp_path, edited)).warnings if "fills" in w.id]

    (line,) = warned(Fraction(3, 4))
    assert "75 % of the sector at speed_max (70 % from" in line, line
    assert warned(Fraction(65, 100)) == []

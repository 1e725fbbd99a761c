"""Regressions found by the seeded hostile-input fuzzer (tests/fuzz_hostile.py).

One case per class of bug; each replays in-process or in one short CLI run. The fuzzer's
case that found it is named beside it (`python tests/fuzz_hostile.py load --seed S --only N`).
"""

from __future__ import annotations

import json
import re
import subprocess
import sys
import time
from collections.abc import Callable
from pathlib import Path

import pytest
import yaml

from bldc.cli import main
from codegen.errors import ExitCode, MultiSpecError, SpecError
from codegen.spec_loader import load_spec
from codegen.spec_variant import spec_with_duty_target, spec_with_emf_shape, spec_with_method
from codegen.yaml12 import read_yaml

ROOT = Path(__file__).resolve().parents[1]
TEXT = (ROOT / "spec" / "paper_motor.yaml").read_text(encoding="utf-8")


def refusal(tmp_path: Path, text: str) -> list[str]:
    spec = tmp_path / "fuzz.yaml"
    spec.write_text(text, encoding="utf-8")
    with pytest.raises(SpecError) as caught:
        load_spec(spec)
    error = caught.value
    lines = [str(one) for one in (error.errors if isinstance(error, MultiSpecError) else [error])]
    for line in lines:
        assert "\n" not in line and len(line) < 600, line
        assert line.startswith(str(spec)), line
    return lines


@pytest.mark.parametrize(
    ("old", "new", "fragments"),
    [
        # [1:960]: `= None: number 9e-1000 has an exponent beyond +-999`, no range
        (
            "commutation_time_ticks: 8",
            "commutation_time_ticks: 9e-1000",
            (
                "accuracy.commutation_time_ticks = '9e-1000'",
                "exponent beyond +-999",
                "(allowed: (0.5, 64] Hall timer ticks)",
            ),
        ),
        # [1:885]: `adc.bits = None: a number of 3003 characters (at most 64)`, no range
        (
            "  poles: 2\n",
            "  poles: 0." + "0" * 3000 + "1\n",
            ("motor.poles = '0.000", "a number of 3003 characters (at most 64)", "[2, 128] poles"),
        ),
        # [1:164]: `motor.phase_inductance = None: a value of 5000 characters`, no unit or range
        (
            "phase_inductance: 0.56 mH",
            "phase_inductance: " + "x" * 5000,
            (
                "motor.phase_inductance = 'xxx",
                "an inductance",
                "5000 characters (too long to read)",
                "(allowed: [1e-07, 1] H)",
            ),
        ),
        # the same value under a key no reader takes a number at
        (
            "\nmotor:\n",
            "\nmotor:\n  colour: 1e99999\n",
            ("motor.colour = '1e99999': unknown key", "rated_voltage"),
        ),
    ],
    ids=["exponent", "many-digits", "long-string", "unknown-key"],
)
def test_a_value_too_long_to_read_is_named_with_its_key_value_and_range(
    tmp_path: Path, old: str, new: str, fragments: tuple[str, ...]
) -> None:
    assert TEXT.count(old) == 1
    lines = refusal(tmp_path, TEXT.replace(old, new))
    assert len(lines) == 1, lines
    for fragment in fragments:
        assert fragment in lines[0], lines[0]


def test_a_100_000_character_key_is_cut_in_the_message(tmp_path: Path) -> None:
    # [1:286]: the key path was echoed whole, a message line of 100 kB
    lines = refusal(tmp_path, TEXT.replace("\nmotor:\n", f"\nmotor:\n  {'k' * 100_000}: 1\n", 1))
    assert any(f"motor.{'k' * 61}..." in line for line in lines), lines


def test_init_refuses_the_reserved_name_at_the_argument(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    # `init paper` wrote a spec the loader then refused (name 'paper' is reserved), exit 3
    with pytest.raises(SystemExit) as caught:
        main(["init", "paper", "-o", str(tmp_path / "paper.yaml")])
    assert caught.value.code == ExitCode.USAGE
    assert "argument NAME: 'paper' is reserved" in capsys.readouterr().err
    assert not (tmp_path / "paper.yaml").exists()


def test_a_spec_file_that_cannot_be_written_is_named_not_its_temporary_file(
    capsys: pytest.CaptureFixture[str],
) -> None:
    # `init m -o /proc/x.yaml` said "error: /proc/.x.yaml.tmp-29017: No such file ..."
    assert main(["init", "m", "-o", "/proc/x.yaml"]) == ExitCode.ENVIRONMENT
    err = capsys.readouterr().err
    assert err.startswith("error: /proc/x.yaml: "), err
    assert ".tmp-" not in err and len(err.splitlines()) == 1, err


@pytest.mark.parametrize(
    ("old", "new", "fragment"),
    [
        # the number read as 0 and the "unit" ',56 mH'
        ("0.56 mH", "0,56 mH", "a decimal comma: write '0.56 mH'"),
        # the exponent had gone to the unit: "write '2.4 e1 V'" (a helper's hunt)
        ("0.56 mH", "5,6e-1 mH", "a decimal comma: write '5.6e-1 mH'"),
        ("0.56 mH", "1,000 mH", "write '1000 mH' (thousands) or '1.000 mH' (decimal comma)"),
        ("0.56 mH", "1 000 uH", "digits in groups"),
        ("0.56 mH", "0x10 uH", "a number in another base"),
        ("0.56 mH", "\u22120.56 mH", "(U+2212) is not a minus sign: use '-'"),
        # µH was answered "did you mean 'H'?", Ω with no suggestion
        ("0.56 mH", "560 \u00b5H", "did you mean 'uH'?"),
        ("0.56 mH", "560 \u03bcH", "did you mean 'uH'?"),
        ("0.21 ohm", "210 m\u2126", "did you mean 'mohm'?"),
        ("0.21 ohm", "0.21 \u03a9", "did you mean 'ohm'?"),
        ("0.00119 kg*m^2", "0.00119 kg\u00b7m\u00b2", "did you mean 'kg*m^2'?"),
        ("duty_counts: 0.75", "duty_counts: 0,75", "got a string (a decimal comma: write '0.75')"),
        # the fuzzer's [7:1396]: an empty string crashed the typographic-minus check
        ("0.56 mH", '""', "not a number (ASCII digits) followed by a unit"),
        ("0.56 mH", '"  "', "not a number (ASCII digits) followed by a unit"),
    ],
)
def test_a_number_or_unit_written_the_usual_wrong_way_says_how_to_write_it(
    tmp_path: Path, old: str, new: str, fragment: str
) -> None:
    assert TEXT.count(old) == 1
    lines = refusal(tmp_path, TEXT.replace(old, new))
    assert len(lines) == 1 and fragment in lines[0], lines
    assert "(allowed: " in lines[0], lines[0]


def _quoted_keys(text: str) -> str:
    return re.sub(r"^(\s*)([a-z_]+):", r'\1"\2":', text, flags=re.M)


@pytest.mark.parametrize(
    "layout",
    [
        # [5:21]: simulate refused a valid spec with quoted keys, "controller.method =
        # None: no line to replace" (a line pattern found the method to rewrite)
        _quoted_keys,
        lambda text: text.replace("method: improved", 'method: "improved"'),
        lambda text: text.replace("method: improved", "method: !!str improved # paper"),
        lambda text: json.dumps(yaml.safe_load(text)),
        lambda text: yaml.safe_dump(yaml.safe_load(text), default_flow_style=True),
        lambda text: text.replace("description: Table", "description: &m improved #").replace(
            "method: improved", "method: *m"
        ),
    ],
    ids=["quoted-keys", "quoted-value", "tagged-value", "json", "flow", "alias"],
)
def test_the_methods_variants_of_a_valid_spec_in_any_layout_load(
    tmp_path: Path, layout: Callable[[str], str]
) -> None:
    text = layout(TEXT)
    variant = spec_with_method(text, "none", "variant")
    variant = spec_with_emf_shape(variant, "[[0, 0], [30, 1], [150, 1], [180, 0]]")
    variant = spec_with_duty_target(variant, "2")
    path = tmp_path / "variant.yaml"
    path.write_text(variant, encoding="utf-8")
    spec = load_spec(path)
    original = tmp_path / "original.yaml"
    original.write_text(text, encoding="utf-8")
    base = load_spec(original)
    assert (spec.name, spec.controller.method, spec.accuracy.duty_counts) == ("variant", "none", 2)
    assert spec.motor.back_emf_shape != base.motor.back_emf_shape
    assert (spec.motor.phase_inductance_h, spec.operating_points) == (
        base.motor.phase_inductance_h,
        base.operating_points,
    )


@pytest.mark.parametrize("indent", ["  ", "    "])
def test_a_block_emf_table_at_its_keys_indent_is_rewritten_for_a_variant(indent: str) -> None:
    """A measured EMF table in block style, its items at the key's own indent (as
    yaml.safe_dump writes it): the flow value written at the first item's place read as
    a key ('could not find expected :'), so `simulate` refused the spec and `bench`
    failed with a traceback. The variant now has the new shape and nothing else new."""
    rows = "".join(
        f"  {indent[2:]}- - {a}\n  {indent[2:]}  - {e}\n"
        for a, e in ((0, 0), (30, 1), (150, 1), (180, 0))
    )
    text = TEXT.replace("  back_emf_convention: phase\n", f"  back_emf_shape:\n{rows}", 1)
    text = text.replace("  back_emf_shape:", "  back_emf_convention: phase\n  back_emf_shape:")
    for shape in ("flat", "[[0, 0], [60, 1], [120, 1], [180, 0]]"):
        variant = spec_with_emf_shape(text, shape)
        data, _ = read_yaml(variant.encode("utf-8"))
        before, _ = read_yaml(text.encode("utf-8"))
        assert data["motor"].pop("back_emf_shape") != before["motor"].pop("back_emf_shape")
        assert data == before


def test_a_variant_that_would_change_another_key_through_an_anchor_is_refused() -> None:
    text = TEXT.replace("name: paper_motor", "name: &n paper_motor", 1)
    text = re.sub(r"(?m)^description: .*$", "description: *n", text)
    with pytest.raises(SpecError, match="other keys take its value through an alias"):
        spec_with_method(text, "none", "renamed")


@pytest.mark.parametrize("value", [".nan", ".inf", "-.inf"])
def test_a_non_finite_quantity_is_not_told_to_add_a_unit(tmp_path: Path, value: str) -> None:
    # `hall.timer_clock = nan: missing unit for a frequency; write e.g. 'nan Hz'`
    lines = refusal(tmp_path, TEXT.replace("timer_clock: 1 MHz", f"timer_clock: {value}"))
    assert len(lines) == 1 and "a finite number and a unit" in lines[0], lines
    assert "(allowed: " in lines[0] and f"{value.lstrip('-.')} Hz" not in lines[0], lines


def test_an_alias_is_cited_at_the_key_that_uses_it(tmp_path: Path) -> None:
    # the unknown key `copy: *m` at the end was cited at the anchor's line, 17
    text = TEXT.replace("\nmotor:", "\nmotor: &m", 1) + "copy: *m\n"
    lines = refusal(tmp_path, text)
    assert lines == [line for line in lines if f":{text.count(chr(10))}: copy = " in line], lines


def test_init_says_when_the_pi_it_writes_cannot_integrate(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    # [init 1:22]: a 1 mohm, 500 mH motor: init exited 0 ("next: generate"), and generate
    # refused it with "k_i = 0.00069 ... below one LSB ... (Q6)": no value, no range. Its
    # PI now designs (the integrator in a finer format than the output); its Eq. 20 needs
    # a Hall clock of at most 31 kHz, which leaves the top speed too few ticks: init says
    # so in one line with the value, and that the design does not fit.
    spec = tmp_path / "m.yaml"
    argv = ["init", "m", "-o", str(spec), "--resistance", "0.001 ohm", "--inductance", "500 mH"]
    # the 5 A init then derived (it now derives 0.1 A for so long a commutation)
    argv += ["--braking-current", "5 A"]
    assert main(argv) == ExitCode.SPEC
    err = capsys.readouterr().err.splitlines()
    assert err[0].startswith(f"error: {spec}: hall.timer_clock: fixed-point design: "), err
    assert "(allowed: <= 31250 Hz, " in err[0], err
    assert "fixed-point design does not fit" in err[1], err


def test_a_k_i_below_one_lsb_is_refused_at_once_at_any_bandwidth(tmp_path: Path) -> None:
    # the search for a bandwidth that fits ran its own search in each trial: at 50 Hz,
    # generate ran for minutes
    from codegen.control.current_loop import widest_design
    from codegen.methods.base import FixedPointError

    spec = tmp_path / "m.yaml"
    argv = ["init", "m", "-o", str(spec), "--resistance", "0.001 ohm", "--inductance", "500 mH"]
    main(argv)
    # (at 50 Hz its integrator now takes Q19, where k_i is 18 LSB; at 1 Hz, 0.36)
    spec.write_text(spec.read_text().replace("bandwidth: 1000 Hz", "bandwidth: 1 Hz"))
    start = time.monotonic()
    with pytest.raises(FixedPointError, match=r"bandwidth = 1 Hz: .*\(allowed: "):
        widest_design(load_spec(spec))
    assert time.monotonic() - start < 20


def test_an_unreachable_commutation_time_target_names_the_target_that_is_reached(
    tmp_path: Path,
) -> None:
    # [init 2:182]: "no format from Q0 to Q12 is both safe and accurate enough for
    # accuracy.commutation_time_ticks = 8.0: Q7, current x256: bldc_divide_long: q_high
    # << shift: value spans [...]": internal overflows, no range (64 ticks designed)
    from codegen.core.module import build_core
    from codegen.methods.base import FixedPointError

    spec = tmp_path / "m.yaml"
    datasheet = ["--inductance", "20 uH", "--kv", "30", "--resistance-line-to-line", "0.02 ohm"]
    drive = ["--braking-current", "0.1 A", "--bus-voltage", "6 V"]
    assert main(["init", "m", "-o", str(spec), *datasheet, *drive]) == 0
    # init now writes the target the core meets (tests/test_cli_commands.py); the spec
    # asks for init's default 8 ticks again
    text = spec.read_text(encoding="utf-8")
    assert "  commutation_time_ticks: 45.993\n" in text
    strict = tmp_path / "strict.yaml"
    strict.write_text(
        text.replace("  commutation_time_ticks: 45.993\n", "  commutation_time_ticks: 8\n")
    )
    with pytest.raises(FixedPointError) as caught:
        build_core(load_spec(strict))
    assert caught.value.key == "accuracy.commutation_time_ticks"
    message = str(caught.value)
    assert message.startswith("accuracy.commutation_time_ticks = 8 ticks: "), message
    assert message.endswith("(allowed: >= 45.993 ticks)"), message
    assert "bldc_divide_long" not in message, message


@pytest.mark.parametrize(
    ("option", "value", "fragment"),
    [
        # MemoryError (exit 70, "internal error") allocating 7.28 TiB
        ("--samples", "999999999999", "(allowed: [2, 100000])"),
        ("--speeds", "999999999999", "(allowed: [1, 100])"),
        # started LocalCluster worker processes until it was killed
        ("--workers", "100000", "4 per core"),
    ],
)
def test_a_robustness_campaign_too_large_to_run_is_a_usage_error(
    capsys: pytest.CaptureFixture[str], option: str, value: str, fragment: str
) -> None:
    spec = str(ROOT / "spec" / "paper_motor.yaml")
    with pytest.raises(SystemExit) as caught:
        main(["robustness", spec, option, value])
    assert caught.value.code == ExitCode.USAGE
    err = capsys.readouterr().err.splitlines()[-1]
    assert f"argument {option}: {value} is out of range" in err and fragment in err, err


def test_a_spec_path_with_a_line_break_stays_on_the_errors_one_line(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    # `generate $'bad\nspec.yaml'` printed "error: bad" and "error: spec.yaml:59: ..."
    spec = tmp_path / "bad\nspec.yaml"
    spec.write_text(TEXT.replace("commutation_time_ticks: 8", "commutation_time_ticks: 99"))
    assert main(["generate", str(spec), "-o", str(tmp_path / "out")]) == ExitCode.SPEC
    err = capsys.readouterr().err.splitlines()
    assert len(err) == 1 and err[0].startswith(f"error: {str(spec)!r}:"), err
    assert "accuracy.commutation_time_ticks = 99" in err[0], err


def test_an_output_path_with_a_line_break_stays_on_the_errors_one_line(
    capsys: pytest.CaptureFixture[str],
) -> None:
    spec = str(ROOT / "spec" / "paper_motor.yaml")
    assert main(["generate", spec, "-o", "/proc/a\nb"]) == ExitCode.ENVIRONMENT
    err = capsys.readouterr().err.splitlines()
    assert len(err) == 1 and err[0].startswith("error: '/proc/a\\nb': cannot publish"), err


def test_a_reader_that_stops_reading_is_no_error() -> None:
    # `derive SPEC | head -1` printed "error: Broken pipe"
    command = [sys.executable, "-m", "codegen", "derive", str(ROOT / "spec" / "paper_motor.yaml")]
    process = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    assert process.stdout is not None and process.stderr is not None
    process.stdout.close()  # before it writes
    err = process.stderr.read().decode()
    assert process.wait(timeout=60) == 141
    assert err == "", err


@pytest.mark.parametrize(
    ("old", "new", "fragment"),
    [
        ("\nhall:\n", "\nhall: ~\nhall_was:\n", "(allowed: a mapping of sequence, timer_clock,"),
        ("description: Table", "description: [Table] #", "(allowed: a string of <= 500 char"),
    ],
    ids=["section-null", "description-list"],
)
def test_a_section_or_description_of_the_wrong_type_names_what_it_takes(
    tmp_path: Path, old: str, new: str, fragment: str
) -> None:
    lines = refusal(tmp_path, TEXT.replace(old, new, 1))
    assert any(fragment in line for line in lines), lines


@pytest.mark.heavy(seconds=5)
def test_the_hostile_fuzzers_seeded_sample_finds_nothing(
    capsys: pytest.CaptureFixture[str],
) -> None:
    # tests/fuzz_hostile.py's `load` phase, without the design: 250 text mutations of the
    # checked-in specs (a few seconds); every refusal one clear line, no crash, no hang
    import importlib.util

    spec = importlib.util.spec_from_file_location(
        "fuzz_hostile", ROOT / "tests" / "fuzz_hostile.py"
    )
    assert spec is not None and spec.loader is not None
    fuzzer = importlib.util.module_from_spec(spec)
    sys.modules.setdefault("fuzz_hostile", fuzzer)  # its dataclass looks itself up there
    spec.loader.exec_module(fuzzer)
    status = fuzzer.load_phase(seed=1, count=250, only=None, limit=10.0, do_design=False)
    out = capsys.readouterr().out
    assert status == 0, out


def test_a_pi_no_bandwidth_fits_should_name_the_motor_values_behind_it(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    # a hunt: init --resistance 0.0001 ohm (the loader's least) wrote a spec whose PI
    # fits at no bandwidth, and the one line named current_loop.bandwidth alone, which
    # no value fixes: it now names R and L, whose ratio sets k_i
    spec = tmp_path / "m.yaml"
    assert main(["init", "m", "-o", str(spec), "--resistance", "0.0001 ohm"]) == ExitCode.SPEC
    err = capsys.readouterr().err.splitlines()
    (line,) = [x for x in err if x.startswith("error: ")]
    assert "current_loop.bandwidth" in line
    assert "L/R = 5.6 s" in line and "motor.phase_resistance = 0.0001 ohm" in line, line


def test_a_capital_k_prefix_should_not_be_answered_with_the_unprefixed_unit(
    tmp_path: Path,
) -> None:
    """'1 Kohm' (a datasheet's kilo, capitalised) was answered "did you mean 'ohm'?":
    taken, the value is 1000 times too small (a helper's hunt). A kilo the spec does not
    take gets no suggestion; one it takes gets its spelling ('1.2 KV': 'kV')."""
    (line,) = refusal(tmp_path, TEXT.replace("0.21 ohm", "1 Kohm"))
    assert "unit 'Kohm'" in line and "did you mean" not in line, line
    (line,) = refusal(tmp_path, TEXT.replace("bus_voltage_max: 30 V", "bus_voltage_max: 0.03 KV"))
    assert "did you mean 'kV'?" in line, line

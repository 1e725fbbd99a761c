"""Fuzzing the spec loader and the design behind it with Hypothesis.

Each case is one of the checked-in or fixture specs with up to three mutations of its
data (wrong types, hostile numbers, unit typos, deleted and unknown keys, broken
structure) and, often, one of its YAML text (1.1 literals such as `1:00` and `yes`,
tags, anchors and alias bombs, duplicate keys, control characters, deep nesting,
truncation, binary). Every case must end in one of two ways, within its time limit:

* accepted: load_spec returns a Spec and the fixed-point design and everything else
  `generate` derives from the spec (port, firmware, Unity cases, core context) is
  computed without an exception, or the design refuses the spec with its own error
  (FixedPointError, which the CLI reports as a bad spec);
* refused: SpecError, each of its lines one line that starts with the file and names a
  key path (or `<document>` for a document that is not a spec at all).

Anything else (another exception, a hang) fails. The default is 1000 cases, derandomized
so CI sees the same ones every run; BLDC_FUZZ_EXAMPLES=N and BLDC_FUZZ_RANDOM=1 explore
further. A smaller sample of refused specs goes through the real CLI in a subprocess, where it
must exit 3 with `error:` lines, print nothing on stdout and write nothing. The counts are printed in the
test session's summary (tests/conftest.py).

The resistance-aware rule's design (improved_r, 2-7 s per spec) is not fuzzed: `method`
mutates among the other three methods.
"""

from __future__ import annotations

import atexit
import contextlib
import copy
import functools
import os
import re
import shutil
import subprocess
import sys
import tempfile
from collections import Counter
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest
import yaml
from fuzz_limits import time_limit
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

from codegen.errors import MultiSpecError, SpecError
from codegen.methods.base import FixedPointError
from codegen.spec_loader import WARNINGS, load_spec
from codegen.spec_model import Spec
from codegen.spec_variant import spec_with_method

ROOT = Path(__file__).resolve().parents[1]
BASE_FILES = {
    "paper_motor": ROOT / "spec" / "paper_motor.yaml",
    "maxon": ROOT / "spec" / "example_maxon_ec45_flat_48v.yaml",
    "hub_46p": ROOT / "tests" / "fixtures" / "specs" / "hub_motor_46p.yaml",
    "offset_conventional": ROOT / "tests" / "fixtures" / "specs" / "offset_conventional.yaml",
    "fast_14p": ROOT / "tests" / "fixtures" / "specs" / "fast_14p_12v.yaml",
}
#: Base spec texts; improved_r bases run the improved rule here (see the docstring).
BASE_TEXTS = {
    name: spec_with_method(path.read_text(encoding="utf-8"), "improved")
    if "method: improved_r" in path.read_text(encoding="utf-8")
    else path.read_text(encoding="utf-8")
    for name, path in BASE_FILES.items()
}
BASE_DATA = {name: yaml.safe_load(text) for name, text in BASE_TEXTS.items()}

#: libyaml's emitter when PyYAML has it (six times faster than the pure-Python one).
DUMPER = getattr(yaml, "CSafeDumper", yaml.SafeDumper)
EXAMPLES = int(os.environ.get("BLDC_FUZZ_EXAMPLES", "1000"))
CLI_EXAMPLES = int(os.environ.get("BLDC_FUZZ_CLI_EXAMPLES", "25"))
RANDOM = bool(os.environ.get("BLDC_FUZZ_RANDOM"))
CASE_SECONDS = 10
CLI_CASE_SECONDS = 120

#: Outcome counts, printed by tests/conftest.py at the end of the session.
COUNTS: Counter[str] = Counter()

# --------------------------------------------------------------------- strategies

UNITS = [
    "V", "mV", "kV", "ohm", "Ohm", "mohm", "mOhm", "H", "mH", "uH", "V/krpm", "V/rpm",
    "mV/rpm", "V*s/rad", "kg*m^2", "kg*cm^2", "g*cm^2", "Hz", "kHz", "MHz", "s", "ms",
    "us", "ns", "A", "mA", "rpm", "krpm", "V/A", "mV/A",
]  # fmt: skip
UNIT_TYPOS = [
    "mh", "MH", "kv", "v", "ohms", "Ω", "µH", "uh", "V/KRPM", "krpm ", "khz", "KHz",
    "mhz", "µs", "usec", "nS", "a", "ma", "RPM", "v/a", "mv/A", "kg m^2", "kgm2", "",
    "V/krpm/", "H H", "%", "°C",
]  # fmt: skip
NUMBER_TEXTS = [
    "0", "-0", "1", "-1", "0.5", ".5", "5.", "1e-400", "1e400", "1e-9", "1e9", "1e-30",
    "9" * 40, "0.0000001", "1e+3", "1E3", "+2", "٢٤", "２４", "1_000", "1,5", "0x10",
    "0o17", "1:00", "inf", "nan", "1e", "e5", "--1", "1e-999", "1e999",
]  # fmt: skip
RAW_TOKENS = [
    "1:00", "yes", "No", "on", "OFF", "y", "n", "0o17", "010", "0x1F", "1_000", ".inf",
    "-.Inf", ".NaN", "~", "null", "", "true", "False", "!!python/object:os.system echo",
    "!!binary aGVsbG8=", "!!set {a, b}", "!!float 1", "!!int 1.5", "!!str 12", "!!bool yes",
    "!!timestamp 2001-12-14", "!!omap [a: 1]", "!custom x", "&anchor 1", "*undefined",
    "[1, [2, [3]]]", "{a: 1}", "'quoted'", '"\\u0662\\u0664 V"', "٢٤ V", "24 V # comment",
    '"24 V"', "0.56 mh", "1e-400 V/krpm", "2001-12-14", "=", "<<: {a: 1}", "? complex",
    "- item", ">-\n  folded", "|\n  literal", "@reserved", "`backtick`", "%directive",
]  # fmt: skip


def leaf_paths(data: Any, prefix: tuple[Any, ...] = ()) -> list[tuple[Any, ...]]:
    paths: list[tuple[Any, ...]] = []
    if isinstance(data, dict):
        for key, value in data.items():
            paths.append((*prefix, key))
            paths += leaf_paths(value, (*prefix, key))
    elif isinstance(data, list):
        for index, value in enumerate(data):
            paths.append((*prefix, index))
            paths += leaf_paths(value, (*prefix, index))
    return paths


def _parent(data: Any, path: tuple[Any, ...]) -> Any:
    for key in path[:-1]:
        data = data[key]
    return data


hostile_scalars = st.one_of(
    st.none(),
    st.booleans(),
    st.integers(min_value=-(10**40), max_value=10**40),
    st.floats(allow_nan=True, allow_infinity=True),
    st.text(max_size=30),
    st.sampled_from(NUMBER_TEXTS),
    st.builds(
        lambda n, sep, u: f"{n}{sep}{u}",
        st.sampled_from(NUMBER_TEXTS),
        st.sampled_from([" ", "", "  ", "\t", "\u00a0"]),
        st.sampled_from(UNITS + UNIT_TYPOS),
    ),
)
hostile_values = st.recursive(
    hostile_scalars,
    lambda inner: st.one_of(
        st.lists(inner, max_size=4), st.dictionaries(st.text(max_size=8), inner, max_size=4)
    ),
    max_leaves=8,
)


def _set_leaf(draw: Callable[..., Any], data: dict[str, Any]) -> str:
    path = draw(st.sampled_from(leaf_paths(data)))
    _parent(data, path)[path[-1]] = draw(hostile_values)
    return f"set {path}"


_QUANTITY = re.compile(
    r"^(?P<number>[-+]?[0-9]*\.?[0-9]+(?:[eE][-+]?[0-9]+)?) (?P<unit>[A-Za-z].*)$"
)


def _scale_quantity(draw: Callable[..., Any], data: dict[str, Any]) -> str:
    """Keep the unit, change the number: the physics checks' territory."""
    candidates = [
        path
        for path in leaf_paths(data)
        if isinstance(_parent(data, path)[path[-1]], str)
        and _QUANTITY.match(_parent(data, path)[path[-1]])
    ]
    if not candidates:
        return "no quantity"
    path = draw(st.sampled_from(candidates))
    match = _QUANTITY.match(_parent(data, path)[path[-1]])
    assert match is not None
    number = float(match.group("number"))
    factor = draw(
        st.one_of(
            st.sampled_from(
                [0.0, -1.0, 1e-12, 1e-6, 1e-3, 0.1, 0.5, 0.9, 1.1, 2.0, 10.0, 1e3, 1e6]
            ),
            st.floats(min_value=0.01, max_value=100.0),
        )
    )
    _parent(data, path)[path[-1]] = f"{number * factor:.6g} {match.group('unit')}"
    return f"scale {path} x{factor}"


def _scale_number(draw: Callable[..., Any], data: dict[str, Any]) -> str:
    candidates = [
        path
        for path in leaf_paths(data)
        if isinstance(_parent(data, path)[path[-1]], (int, float))
        and not isinstance(_parent(data, path)[path[-1]], bool)
    ]
    path = draw(st.sampled_from(candidates))
    value = _parent(data, path)[path[-1]]
    new = draw(
        st.one_of(
            st.sampled_from([0, -1, 1, 2, 7, 8, 9, 16, 17, 64, 128, 1024, 10**9]),
            st.floats(min_value=-1e6, max_value=1e6, allow_nan=False),
            st.just(value * 2),
        )
    )
    _parent(data, path)[path[-1]] = new
    return f"number {path} = {new}"


def _retype_unit(draw: Callable[..., Any], data: dict[str, Any]) -> str:
    candidates = [
        path
        for path in leaf_paths(data)
        if isinstance(_parent(data, path)[path[-1]], str)
        and _QUANTITY.match(_parent(data, path)[path[-1]])
    ]
    path = draw(st.sampled_from(candidates))
    match = _QUANTITY.match(_parent(data, path)[path[-1]])
    assert match is not None
    unit = draw(st.sampled_from(UNITS + UNIT_TYPOS))
    _parent(data, path)[path[-1]] = f"{match.group('number')} {unit}"
    return f"unit {path} {unit!r}"


def _delete(draw: Callable[..., Any], data: dict[str, Any]) -> str:
    path = draw(st.sampled_from(leaf_paths(data)))
    del _parent(data, path)[path[-1]]
    return f"delete {path}"


def _add_key(draw: Callable[..., Any], data: dict[str, Any]) -> str:
    maps = [()] + [p for p in leaf_paths(data) if isinstance(_parent(data, p)[p[-1]], dict)]
    path = draw(st.sampled_from(maps))
    target = data if not path else _parent(data, path)[path[-1]]
    key = draw(st.one_of(st.text(max_size=12), st.sampled_from(["colour", "pole", "motr", "x"])))
    target[key] = draw(hostile_scalars)
    return f"add {path}.{key!r}"


def _operating_points(draw: Callable[..., Any], data: dict[str, Any]) -> str:
    count = draw(st.sampled_from([0, 1, 2, 16, 17, 40]))
    speed = draw(st.sampled_from(["100 rpm", "1000 rpm", "300 rpm", "5000 rpm", "1 rpm"]))
    data["operating_points"] = [{"speed": speed, "main_duty": 0.5} for _ in range(count)]
    return f"{count} operating points"


def _sources(draw: Callable[..., Any], data: dict[str, Any]) -> str:
    sources = data.get("sources")
    choice = draw(st.sampled_from(["empty", "drop", "blank", "unknown"]))
    if not isinstance(sources, dict):
        return "sources not a mapping"
    if choice == "empty":
        data["sources"] = {}
    elif choice == "drop" and sources:
        del sources[draw(st.sampled_from(sorted(sources)))]
    elif choice == "blank" and sources:
        sources[draw(st.sampled_from(sorted(sources)))] = ""
    else:
        sources["motor.colour"] = "datasheet"
    return f"sources {choice}"


def _silence(draw: Callable[..., Any], data: dict[str, Any]) -> str:
    ids = draw(
        st.lists(st.one_of(st.sampled_from(sorted(WARNINGS)), st.text(max_size=20)), max_size=3)
    )
    data["warnings"] = draw(st.sampled_from([{"silence": ids}, ids, {"mute": ids}]))
    return f"warnings {data['warnings']!r}"


DATA_MUTATIONS = [
    _set_leaf,
    _scale_quantity,
    _scale_quantity,
    _scale_number,
    _retype_unit,
    _delete,
    _add_key,
    _operating_points,
    _sources,
    _silence,
]

_VALUE_LINE = re.compile(r"^(?P<head>\s*-?\s*[A-Za-z_][\w.]*:)[ \t]+(?P<value>\S.*)$")


@st.composite
def text_mutation(draw: Callable[..., Any], text: str) -> str | bytes:
    lines = text.splitlines(keepends=True)
    kind = draw(
        st.sampled_from(
            [
                "raw-token",
                "raw-token",
                "raw-token",
                "bom",
                "control",
                "tab",
                "duplicate-line",
                "second-document",
                "truncate",
                "alias-bomb",
                "deep-nesting",
                "long-line",
                "binary",
                "anchor-alias",
            ]
        )
    )
    value_lines = [i for i, line in enumerate(lines) if _VALUE_LINE.match(line.rstrip("\n"))]
    if kind == "raw-token" and value_lines:
        index = draw(st.sampled_from(value_lines))
        match = _VALUE_LINE.match(lines[index].rstrip("\n"))
        assert match is not None
        token = draw(st.sampled_from(RAW_TOKENS))
        lines[index] = f"{match.group('head')} {token}\n"
        return "".join(lines)
    if kind == "bom":
        return "\ufeff" + text
    if kind == "control":
        at = draw(st.integers(0, len(text)))
        char = draw(st.sampled_from(["\x00", "\x07", "\x1b[31m", "\x7f", "\ufffe", "\u2028"]))
        return text[:at] + char + text[at:]
    if kind == "tab" and value_lines:
        index = draw(st.sampled_from(value_lines))
        lines[index] = "\t" + lines[index].lstrip(" ")
        return "".join(lines)
    if kind == "duplicate-line" and value_lines:
        index = draw(st.sampled_from(value_lines))
        lines.insert(index, lines[index])
        return "".join(lines)
    if kind == "second-document":
        return text + "---\nname: other\n"
    if kind == "truncate":
        return text[: draw(st.integers(0, len(text)))]
    if kind == "alias-bomb":
        bomb = "lol0: &l0 [x, x, x, x, x, x, x, x, x]\n" + "".join(
            f"lol{i}: &l{i} [{', '.join([f'*l{i - 1}'] * 9)}]\n" for i in range(1, 9)
        )
        return bomb + text
    if kind == "deep-nesting":
        depth = draw(st.sampled_from([17, 100, 3000]))
        return text.replace("description:", f"description: {'[' * depth}{']' * depth} #", 1)
    if kind == "long-line":
        return text.replace("description:", f"description: {'x' * 300_000} #", 1)
    if kind == "binary":
        data = bytearray(text.encode())
        for _ in range(draw(st.integers(1, 5))):
            data[draw(st.integers(0, len(data) - 1))] = draw(st.integers(128, 255))
        return bytes(data)
    if kind == "anchor-alias" and value_lines:
        first, second = sorted(draw(st.lists(st.sampled_from(value_lines), min_size=2, max_size=2)))
        match = _VALUE_LINE.match(lines[first].rstrip("\n"))
        other = _VALUE_LINE.match(lines[second].rstrip("\n"))
        if match is None or other is None or first == second:
            return text
        lines[first] = f"{match.group('head')} &a {match.group('value')}\n"
        lines[second] = f"{other.group('head')} *a\n"
        return "".join(lines)
    return text


@st.composite
def spec_case(draw: Callable[..., Any]) -> tuple[str, bytes]:
    base = draw(st.sampled_from(sorted(BASE_DATA)))
    data = copy.deepcopy(BASE_DATA[base])
    steps = [base]
    for mutate in draw(st.lists(st.sampled_from(DATA_MUTATIONS), max_size=3)):
        with contextlib.suppress(IndexError, KeyError, TypeError):
            steps.append(mutate(draw, data))
    text: str | bytes = yaml.dump(
        data, Dumper=DUMPER, sort_keys=False, allow_unicode=True, width=10**6
    )
    if draw(st.booleans()):
        text = draw(text_mutation(text))
        steps.append("text")
    raw = text if isinstance(text, bytes) else text.encode("utf-8", "surrogatepass")
    return " | ".join(steps), raw


# --------------------------------------------------------------------- checks


def check_refusal(error: SpecError, source: str) -> bool:
    """Each error is one line that starts with the file and names a key path; True if
    one of them is about the document as a whole (`<document>`)."""
    errors = error.errors if isinstance(error, MultiSpecError) else (error,)
    assert errors
    for one in errors:
        line = str(one)
        assert "\n" not in line, line
        assert line.startswith(source), line
        assert one.path, line
        assert f"{one.path} = " in line, line
    return any(one.path == "<document>" for one in errors)


@functools.cache
def _audit_free_design(spec_key: tuple[Any, ...], spec: Spec) -> str:
    """Everything `generate` computes from a spec except the spec-independent audit."""
    from codegen.core.float_model import float_model_context
    from codegen.core.module import build_core, core_context
    from codegen.derivation import derive
    from codegen.firmware import render_firmware_files
    from codegen.port import render_port_files
    from codegen.unity_cases import unity_cases

    derivation = derive()
    try:
        core = build_core(spec)
        core_context(core)
        float_model_context(spec, derivation)
        # the current loop's fixed-point design, in the port, refuses a spec its widest
        # format cannot meet as the core's does (the CLI: one `error:` line, exit 3)
        render_port_files(spec)
    except FixedPointError:
        return "design refused"
    render_firmware_files(spec)
    unity_cases(spec)
    return "designed"


@functools.cache
def _scratch() -> Path:
    folder = Path(tempfile.mkdtemp(prefix="bldc-fuzz-"))
    atexit.register(shutil.rmtree, folder, ignore_errors=True)
    return folder


def run_case(raw: bytes, design: bool = True) -> str:
    path = _scratch() / "fuzz.yaml"
    path.write_bytes(raw)
    try:
        with time_limit(CASE_SECONDS):
            spec = load_spec(path)
    except SpecError as error:
        if check_refusal(error, str(path)) and design:
            COUNTS["refused: about the whole document"] += 1
        return "refused"
    if not design:
        return "accepted"
    key = (
        spec.motor,
        spec.inverter,
        spec.hall,
        spec.adc,
        spec.controller,
        spec.accuracy,
        spec.operating_points,
    )
    with time_limit(CASE_SECONDS):
        outcome = _audit_free_design(key, spec)
    if spec.warnings:
        COUNTS["accepted with warnings"] += 1
        COUNTS["warnings"] += len(spec.warnings)
    return f"accepted, {outcome}"


@settings(
    max_examples=EXAMPLES,
    derandomize=not RANDOM,
    database=None,
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
)
@given(spec_case())
@pytest.mark.heavy(seconds=21)
def test_a_malformed_spec_is_refused_cleanly_or_designed(case: tuple[str, bytes]) -> None:
    _, raw = case
    outcome = run_case(raw)
    COUNTS["tried"] += 1
    COUNTS[outcome] += 1


# --------------------------------------------------------------------- the CLI


def run_cli(spec: Path, output: Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "codegen", "generate", str(spec), "-o", str(output)],
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=CLI_CASE_SECONDS,
        check=False,
    )


def check_cli(result: subprocess.CompletedProcess[str], spec: Path, output: Path) -> str:
    assert "Traceback" not in result.stderr, result.stderr
    lines = result.stderr.splitlines()
    if result.returncode == 0:
        assert (output / "manifest.json").is_file()
        assert all(line.startswith(("warning: ", "waiting for")) for line in lines), lines
        return "accepted"
    assert result.returncode == 3, (result.returncode, result.stderr)
    assert lines, "a refused spec must say why"
    for line in lines:
        assert line.startswith(("error: ", "warning: ")), line
    assert any(line.startswith(f"error: {spec}") for line in lines), lines
    assert not output.exists(), "a refused spec wrote output"
    assert result.stdout == ""
    return "refused"


@settings(
    max_examples=CLI_EXAMPLES,
    derandomize=not RANDOM,
    database=None,
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
)
@given(spec_case())
@pytest.mark.heavy(seconds=6)
def test_the_cli_refuses_a_malformed_spec_in_one_line_per_error_and_writes_nothing(
    case: tuple[str, bytes],
) -> None:
    _, raw = case
    # Specs the loader accepts are generated in full by other tests (seconds each).
    assume(run_case(raw, design=False) == "refused")
    with tempfile.TemporaryDirectory() as scratch:
        spec = Path(scratch) / "fuzz.yaml"
        spec.write_bytes(raw)
        output = Path(scratch) / "out"
        outcome = check_cli(run_cli(spec, output), spec, output)
    COUNTS[f"cli {outcome}"] += 1

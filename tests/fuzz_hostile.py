"""A seeded hostile-input fuzzer for specs and the command line (not a test: run it).

    .venv/bin/python tests/fuzz_hostile.py load  --seed 1 --count 3000
    .venv/bin/python tests/fuzz_hostile.py cli   --seed 1 --count 40 --commands derive,generate
    .venv/bin/python tests/fuzz_hostile.py layout --commands generate,simulate --layouts json

`load` mutates the checked-in specs (spec/*.yaml, tests/fixtures/**/*.yaml) in their text,
line by line, so comments and layout stay real: every value replaced by wrong types,
units (wrong, none, typos, SI prefixes, unicode minus/micro/ohm, comma decimals),
extreme magnitudes, deleted, unknown and duplicate keys, and YAML features (anchors,
aliases, tags, merge keys, several documents, BOMs, CRLF, tabs, deep nesting, long
strings, binary junk). Each case goes through load_spec in this process and, when
accepted, through everything `generate` derives from it. Outcomes are classified:

* refused: one line per error, naming the key path and the value, with the allowed
  range where the problem is a value (`refused-unclear` when the range is missing);
* accepted (and designed, or refused by the fixed-point design);
* crash (another exception) and slow (over the case's time limit).

`cli` runs the real CLI in subprocesses on a sample of the same cases (`--accepted-only`:
the ones the loader accepts, for the later commands); `layout` runs every command on
valid specs written another way (CRLF, BOM, JSON, flow style, quoted keys, ...). Each
finding is printed with the seed and case number that replays it (`--only N`).

tests/test_spec_fuzz.py is the Hypothesis fuzzer the suite runs; the regressions this
fuzzer found are in tests/test_fuzz_regressions.py.
"""

from __future__ import annotations

import argparse
import contextlib
import os
import random
import re
import shutil
import subprocess
import sys
import tempfile
import time
import traceback
from collections import Counter
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

from fuzz_limits import time_limit

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

BASES = sorted(
    p
    for p in [*ROOT.glob("spec/*.yaml"), *ROOT.glob("tests/fixtures/**/*.yaml")]
    if p.name != "paper_printed.yaml"
)

WRONG_TYPES = [
    "[1, 2]", "{a: 1}", "true", "false", "null", "~", '""', "''", "[]", "{}", "5", '"5"',
    "-5", "0", "yes", "no", "on", "0x10", "0o17", "1:30", "2001-12-14", ".inf", "-.inf",
    ".nan", "!!binary aGVsbG8=", "!!python/object/apply:os.system ['echo pwned']",
    "!!python/name:os.system", "!!float '1'", "!!int '7'", "!!str 5", "!custom 3",
    "!!set {a, b}", "!!map {a: 1}", "!!seq [1]", "!!null ''", "'\\x00'", '"\\0"',
    '"\\u202e24 V"', "|\n    24 V", ">-\n    24 V", "&x 24 V", "*nope",
]  # fmt: skip
SI = ["", "k", "M", "G", "T", "m", "u", "µ", "μ", "n", "p", "f", "a", "E", "P", "c", "d", "da", "h"]
UNIT_WORDS = [
    "V", "A", "ohm", "Ohm", "OHM", "Ω", "Ω", "H", "Hz", "hz", "s", "sec", "rpm", "RPM",
    "rad/s", "V/rpm", "V/krpm", "V/(rad/s)", "V*s/rad", "kg*m^2", "kg·m²", "kg*m**2",
    "g*cm^2", "N*m*s/rad", "%", "deg", "°", "counts", "ticks", "W", "F", "K", "°C", "1",
    "V/A", "mV/A", "ohm*ohm", "V V", "V/", "/V", "*", "^2", "m^2", "",
]  # fmt: skip
NUMBERS = [
    "0", "-0", "-1", "1", "0.0", "00", "007", "1e308", "1e309", "-1e308", "4.9e-324",
    "2.2250738585072014e-308", "1e-320", "nan", "NaN", "inf", "-inf", "Infinity",
    "1" + "0" * 400, "9" * 5000, "0." + "0" * 3000 + "1", "1." + "3" * 2000,
    "1e99999", "1e-99999", "1e+", "1e", "e1", ".", "-", "+", "+-1", "1.2.3", "1,5", "1.5,",
    "0,56", "2.36e", "−1", "−0.5", "–3", "１２", "٢٤", "½", "1/2", "3/4", "2**10",
    "0x1p3", "1_0", "1 000", "1\u00a0000", "1\u2009000", "( 1 )", "1e-30", "1e30", "1e-9",
    "1e9", "123456789012345678901234567890", "0.1e1000", "9e-1000",
]  # fmt: skip
SEPARATORS = [" ", "", "  ", "\u00a0", "\u2009", "\u202f", "\u3000", "\t", " \u200b"]


@dataclass(frozen=True)
class Case:
    number: int
    base: str
    steps: tuple[str, ...]
    raw: bytes


_VALUE = re.compile(r"^(?P<head>\s*(?:-\s+)?[A-Za-z_][\w.]*:)[ \t]+(?P<value>[^#\n]*?)\s*(?:#.*)?$")
_KEY = re.compile(r"^(?P<indent>\s*)(?P<key>[A-Za-z_][\w.]*):")
_QUANTITY = re.compile(r"^(?P<number>[-+]?[0-9.eE+-]+)\s*(?P<unit>\S.*)?$")


def _typo(unit: str, rng: random.Random) -> str:
    if not unit:
        return "V"
    choice = rng.randrange(6)
    i = rng.randrange(len(unit))
    if choice == 0:
        return unit[:i] + unit[i + 1 :]
    if choice == 1:
        return unit[:i] + unit[i] + unit[i:]
    if choice == 2:
        return unit.swapcase()
    if choice == 3:
        return unit.replace("u", "µ").replace("ohm", "Ω").replace("-", "−")
    if choice == 4:
        return unit + "s"
    return unit[:i] + " " + unit[i:]


def hostile_value(value: str, rng: random.Random) -> tuple[str, str]:
    """A replacement for one scalar `value` and a label saying what it is."""
    match = _QUANTITY.match(value.strip().strip("'\""))
    number, unit = (match.group("number"), match.group("unit") or "") if match else (value, "")
    kind = rng.choice(
        ["type", "unit", "unit", "typo", "prefix", "number", "number", "number", "sep",
         "comma", "unicode", "long", "scale"]
    )  # fmt: skip
    if kind == "type":
        return rng.choice(WRONG_TYPES), kind
    if kind == "unit":
        return f"{number} {rng.choice(UNIT_WORDS)}".rstrip(), kind
    if kind == "typo":
        return f"{number} {_typo(unit, rng)}", kind
    if kind == "prefix":
        base = unit.lstrip("kMGTmuµμnp") or unit
        return f"{number} {rng.choice(SI)}{base}", kind
    if kind == "number":
        return f"{rng.choice(NUMBERS)} {unit}".rstrip(), kind
    if kind == "sep":
        return f"{number}{rng.choice(SEPARATORS)}{unit}", kind
    if kind == "comma":
        return f"{number.replace('.', ',')} {unit}".rstrip(), kind
    if kind == "unicode":
        text = f"{number} {unit}".rstrip()
        return text.replace("-", "−").replace("u", "µ").replace("ohm", "Ω") or "−1", kind
    if kind == "long":
        return '"' + "x" * rng.choice([501, 5000, 200_000]) + '"', kind
    try:
        scaled = float(number) * rng.choice([0.0, -1.0, 1e-12, 1e-3, 0.5, 0.99, 1.01, 2, 1e3, 1e12])
    except ValueError:
        scaled = -1.0
    return f"{scaled:.17g} {unit}".rstrip(), kind


def _line_mutation(lines: list[str], rng: random.Random) -> str:
    sources = next((i for i, line in enumerate(lines) if line.startswith("sources:")), len(lines))
    values = [
        i
        for i, line in enumerate(lines)
        if _VALUE.match(line.rstrip("\r\n")) and (i < sources or rng.random() < 0.1)
    ]
    keys = [i for i, line in enumerate(lines) if _KEY.match(line)]
    kind = rng.choice(["value"] * 8 + ["delete", "duplicate", "unknown", "rename", "section"])
    if kind == "value" and values:
        i = rng.choice(values)
        m = _VALUE.match(lines[i].rstrip("\r\n"))
        assert m
        new, label = hostile_value(m.group("value"), rng)
        lines[i] = f"{m.group('head')} {new}\n"
        return f"{m.group('head').strip()} {label} {new[:40]!r}"
    if kind == "delete" and keys:
        i = rng.choice(keys)
        lines[i] = ""
        return f"delete line {i}"
    if kind == "duplicate" and keys:
        i = rng.choice(keys)
        lines.insert(i + 1, lines[i])
        return f"duplicate line {i}"
    if kind == "unknown" and keys:
        i = rng.choice(keys)
        m = _KEY.match(lines[i])
        assert m
        word = rng.choice(
            ["colour", "pole", "motr", "x", "Poles", "speed-max", "ünit", "__class__"]
        )
        lines.insert(i, f"{m.group('indent')}{word}: 1\n")
        return f"unknown key {word!r} at line {i}"
    if kind == "rename" and keys:
        i = rng.choice(keys)
        m = _KEY.match(lines[i])
        assert m
        key = m.group("key")
        new = rng.choice([key.upper(), key + "_", key.replace("_", "-"), key[:-1], " " + key])
        lines[i] = lines[i].replace(key, new, 1)
        return f"rename {key} -> {new}"
    if kind == "section" and keys:
        tops = [i for i in keys if not lines[i].startswith((" ", "\t"))]
        i = rng.choice(tops)
        m = _KEY.match(lines[i])
        assert m
        new = rng.choice(["", " null", " []", " 5", " [a, b]", " 'text'", " {}"])
        lines[i] = f"{m.group('key')}:{new}\n"
        return f"section {m.group('key')}:{new}"
    return "no-op"


def _alias_bomb(depth: int) -> str:
    return "lol0: &l0 [x, x, x, x, x, x, x, x, x]\n" + "".join(
        f"lol{i}: &l{i} [{', '.join([f'*l{i - 1}'] * 9)}]\n" for i in range(1, depth)
    )


def _text_mutation(text: str, rng: random.Random) -> tuple[str | bytes, str]:
    kind = rng.choice(
        ["crlf", "cr", "bom", "bom16", "utf16", "tabs", "multi-doc", "doc-end", "merge",
         "anchor", "alias-bomb", "deep", "binary", "truncate", "empty", "comment-only",
         "scalar-doc", "list-doc", "null-doc", "long-key", "many-keys", "nul", "directive",
         "json", "flow", "quoted-keys", "complex-key", "surrogate", "lone-cr-in-value"]
    )  # fmt: skip
    if kind == "crlf":
        return text.replace("\n", "\r\n"), kind
    if kind == "cr":
        return text.replace("\n", "\r"), kind
    if kind == "bom":
        return "\ufeff" + text, kind
    if kind == "bom16":
        return ("\ufeff" + text).encode("utf-16-le"), kind
    if kind == "utf16":
        return text.encode("utf-16"), kind
    if kind == "tabs":
        return re.sub(r"^(  )+", lambda m: "\t" * (len(m.group(0)) // 2), text, flags=re.M), kind
    if kind == "multi-doc":
        return rng.choice(
            ["---\n" + text, text + "---\n" + text, text + "\n---\n", "--- \n" + text + "...\n"]
        ), kind
    if kind == "doc-end":
        return text.replace("\nhall:", "\n...\nhall:", 1), kind
    if kind == "merge":
        return text.replace(
            "\nmotor:\n", "\nbase: &base {poles: 2}\nmotor:\n  <<: *base\n", 1
        ), kind
    if kind == "anchor":
        return text.replace("\nmotor:", "\nmotor: &m", 1) + "copy: *m\n", kind
    if kind == "alias-bomb":
        return _alias_bomb(rng.choice([3, 5, 9])) + text, kind
    if kind == "deep":
        depth = rng.choice([15, 16, 17, 200, 20000])
        return text.replace("description:", f"description: {'[' * depth}{']' * depth} #", 1), kind
    if kind == "binary":
        data = bytearray(text.encode())
        for _ in range(rng.randint(1, 8)):
            data[rng.randrange(len(data))] = rng.randrange(256)
        return bytes(data), kind
    if kind == "truncate":
        return text[: rng.randrange(len(text) + 1)], kind
    if kind == "empty":
        return rng.choice(["", " ", "\n", "\ufeff", "---", "...", "\n\n\n"]), kind
    if kind == "comment-only":
        return "# nothing here\n", kind
    if kind == "scalar-doc":
        return rng.choice(["42\n", "'text'\n", "!!binary aGVsbG8=\n", "name\n"]), kind
    if kind == "list-doc":
        return "- " + text.replace("\n", "\n  "), kind
    if kind == "null-doc":
        return "~\n", kind
    if kind == "long-key":
        return text.replace("\nmotor:\n", f"\nmotor:\n  {'k' * 100_000}: 1\n", 1), kind
    if kind == "many-keys":
        return text + "".join(f"extra_{i}: {i}\n" for i in range(rng.choice([50, 5000]))), kind
    if kind == "nul":
        return text.replace("\n", "\x00\n", 1), kind
    if kind == "directive":
        return rng.choice(
            [
                "%YAML 1.1\n---\n",
                "%YAML 1.2\n---\n",
                "%TAG ! tag:x,2000:\n---\n",
                "%YAML 9.9\n---\n",
            ]
        ) + text, kind
    if kind == "json":
        import json

        import yaml

        with contextlib.suppress(Exception):
            return json.dumps(yaml.safe_load(text)), kind
        return text, kind
    if kind == "flow":
        import yaml

        with contextlib.suppress(Exception):
            return yaml.safe_dump(yaml.safe_load(text), default_flow_style=True, width=10**6), kind
        return text, kind
    if kind == "quoted-keys":
        return re.sub(r"^(\s*)([a-z_]+):", r'\1"\2":', text, flags=re.M), kind
    if kind == "complex-key":
        return text + "? [a, b]\n: 1\n", kind
    if kind == "surrogate":
        return text.encode() + b"\xed\xa0\x80\n", kind
    return text.replace(" V\n", " V\r5\n", 1), kind


_PREFIXED = {"mH": ("uH", 1000), "ohm": ("mohm", 1000), "V": ("mV", 1000), "A": ("mA", 1000),
             "kHz": ("Hz", 1000), "MHz": ("kHz", 1000), "ns": ("us", 0.001), "us": ("ns", 1000),
             "ms": ("us", 1000), "rpm": ("krpm", 0.001), "V/krpm": ("V/rpm", 0.001),
             "mV/A": ("V/A", 0.001), "uH": ("mH", 0.001)}  # fmt: skip


def _drift(lines: list[str], rng: random.Random) -> str:
    """A change that may well keep the spec valid: a quantity scaled near its value, or
    the same value in another prefix (the accepted-then-crashes territory)."""
    sources = next((i for i, line in enumerate(lines) if line.startswith("sources:")), len(lines))
    values = []
    for i, line in enumerate(lines[:sources]):
        m = _VALUE.match(line.rstrip("\r\n"))
        if m and _QUANTITY.match(m.group("value")):
            values.append(i)
    if not values:
        return "no quantity"
    i = rng.choice(values)
    m = _VALUE.match(lines[i].rstrip("\r\n"))
    assert m
    q = _QUANTITY.match(m.group("value"))
    assert q
    try:
        number = float(q.group("number"))
    except ValueError:
        return "no number"
    unit = (q.group("unit") or "").strip()
    if rng.random() < 0.3 and unit in _PREFIXED:
        new_unit, factor = _PREFIXED[unit]
        new = f"{number * factor:.12g} {new_unit}"
    else:
        factor = rng.choice([0.25, 0.5, 0.8, 0.9, 0.99, 1.01, 1.1, 1.25, 1.5, 2, 4])
        new = f"{number * factor:.6g} {unit}".rstrip()
        if isinstance(number, float) and number.is_integer() and not unit:
            new = str(max(1, round(number * factor)))
    lines[i] = f"{m.group('head')} {new}\n"
    return f"drift {m.group('head').strip()} {new!r}"


def make_case(number: int, seed: int) -> Case:
    rng = random.Random(f"{seed}:{number}")
    base = rng.choice(BASES)
    text = base.read_text(encoding="utf-8")
    lines = text.splitlines(keepends=True)
    steps = [str(base.relative_to(ROOT))]
    drift = rng.random() < 0.4
    for _ in range(rng.choice([1, 1, 1, 2, 3])):
        steps.append(_drift(lines, rng) if drift else _line_mutation(lines, rng))
    out: str | bytes = "".join(lines)
    if rng.random() < (0.1 if drift else 0.25):
        out, label = _text_mutation(out, rng)
        steps.append(label)
    raw = out if isinstance(out, bytes) else out.encode("utf-8", "surrogatepass")
    return Case(number, str(base.relative_to(ROOT)), tuple(steps), raw)


# ------------------------------------------------------------------------ load phase


#: Problems about the document's syntax, not a value: no range to name.
_NOT_A_VALUE = (
    "malformed YAML", "duplicate key", "YAML tag", "not UTF-8", "expands to", "nested deeper",
    "not allowed in a spec", "unknown key", "missing", "did you mean",
)  # fmt: skip


def refusal_problems(error: Exception, source: str) -> list[str]:
    """What is unclear about a refusal: each line must start with the file, name a key
    path and its value; a value problem names the allowed range."""
    from codegen.errors import MultiSpecError

    errors = error.errors if isinstance(error, MultiSpecError) else (error,)
    problems = []
    for one in errors:
        line = str(one)
        if "\n" in line or "\r" in line:
            problems.append(f"multi-line: {line!r}")
        elif not line.startswith(source):
            problems.append(f"no file: {line}")
        elif not one.path or f"{one.path} = " not in line:
            problems.append(f"no key: {line}")
        elif len(line) > 600:
            problems.append(f"long ({len(line)}): {line[:200]}")
        elif (
            not one.allowed
            and not one.path.startswith(("<document>", "sources", "warnings"))
            and not any(word in one.problem for word in _NOT_A_VALUE)
        ):
            problems.append(f"no range: {line}")
    return problems


def design(spec: object) -> str:
    from codegen.core.float_model import float_model_context
    from codegen.core.module import build_core, core_context
    from codegen.derivation import derive
    from codegen.derivation.figures import spec_figures
    from codegen.firmware import render_firmware_files
    from codegen.methods.base import FixedPointError
    from codegen.port import render_port_files
    from codegen.unity_cases import unity_cases

    derivation = derive()
    spec_figures(derivation, spec)  # type: ignore[arg-type]
    try:
        core = build_core(spec)  # type: ignore[arg-type]
        core_context(core)
        float_model_context(spec, derivation)  # type: ignore[arg-type]
        render_port_files(spec)  # type: ignore[arg-type]
    except FixedPointError:
        return "design refused"
    render_firmware_files(spec)  # type: ignore[arg-type]
    unity_cases(spec)  # type: ignore[arg-type]
    return "designed"


def load_phase(seed: int, count: int, only: int | None, limit: float, do_design: bool) -> int:
    scratch = Path(tempfile.mkdtemp(prefix="bldc-hostile-"))
    try:
        return _load_cases(scratch / "fuzz.yaml", seed, count, only, limit, do_design)
    finally:  # a run left its scratch folder in /tmp
        shutil.rmtree(scratch, ignore_errors=True)


def _load_cases(
    path: Path, seed: int, count: int, only: int | None, limit: float, do_design: bool
) -> int:
    from codegen.errors import SpecError
    from codegen.spec_loader import load_spec

    counts: Counter[str] = Counter()
    findings: Counter[str] = Counter()
    numbers = [only] if only is not None else range(count)
    for number in numbers:
        case = make_case(number, seed)
        path.write_bytes(case.raw)
        start = time.monotonic()
        outcome = ""
        try:
            with time_limit(limit):
                spec = load_spec(path)
                if do_design and "improved_r" not in case.raw.decode("utf-8", "replace"):
                    outcome = "accepted, " + design(spec)
                else:
                    outcome = "accepted"
        except SpecError as error:
            problems = refusal_problems(error, str(path))
            outcome = "refused-unclear" if problems else "refused"
            for problem in problems:
                key = re.sub(r"'.*?'|\d+(\.\d+)?", "_", problem)[:90]
                if findings[key] == 0 or only is not None:
                    print(f"[{seed}:{number}] {' | '.join(case.steps)}\n    {problem[:400]}")
                findings[key] += 1
        except TimeoutError:
            outcome = "slow"
            print(f"[{seed}:{number}] SLOW {' | '.join(case.steps)}")
        except Exception as error:
            outcome = "crash"
            where = traceback.extract_tb(error.__traceback__)[-1]
            key = f"{type(error).__name__} {Path(where.filename).name}:{where.lineno}"
            if findings[key] == 0 or only is not None:
                print(
                    f"[{seed}:{number}] CRASH {key}: {str(error)[:200]!r}\n    {' | '.join(case.steps)}"
                )
                if only is not None:
                    traceback.print_exc()
            findings[key] += 1
        elapsed = time.monotonic() - start
        if elapsed > limit / 2 and outcome != "slow":
            print(f"[{seed}:{number}] {elapsed:.1f}s {outcome} {' | '.join(case.steps)}")
        counts[outcome] += 1
    print("outcomes:", dict(counts))
    print("findings:", dict(findings))
    return 1 if counts["crash"] or counts["slow"] or counts["refused-unclear"] else 0


# ------------------------------------------------------------------------- CLI phase


def run(argv: list[str], cwd: Path, timeout: float = 300) -> tuple[int, str, str, float]:
    start = time.monotonic()
    try:
        result = subprocess.run(
            [sys.executable, "-m", "codegen", *argv],
            cwd=cwd,
            capture_output=True,
            text=True,
            errors="replace",
            timeout=timeout,
            check=False,
        )
    except subprocess.TimeoutExpired:
        return -1, "", "TIMEOUT", time.monotonic() - start
    return result.returncode, result.stdout, result.stderr, time.monotonic() - start


def cli_verdict(rc: int, err: str) -> str:
    if rc == -1:
        return "hang"
    if "Traceback" in err or rc == 70 or rc < 0:
        return "crash"
    if rc == 0:
        return "ok"
    lines = [line for line in err.splitlines() if not line.startswith(("warning:", "waiting"))]
    if not lines:
        return "silent-failure"
    if not all(
        line.startswith(("error:", "usage:", "bldc-codegen")) or line.startswith(" ")
        for line in lines
    ):
        return "unclear"
    return f"exit {rc}"


def cli_phase(
    seed: int, count: int, commands: list[str], only: int | None, accepted_only: bool
) -> int:
    from codegen.errors import SpecError
    from codegen.spec_loader import load_spec

    bad = 0
    counts: Counter[str] = Counter()
    numbers = [only] if only is not None else range(count)
    for number in numbers:
        case = make_case(number, seed)
        with tempfile.TemporaryDirectory(prefix="bldc cli ü ") as scratch:
            folder = Path(scratch)
            spec = folder / "my spec ü.yaml"
            spec.write_bytes(case.raw)
            try:
                load_spec(spec)
                accepted = True
            except SpecError:
                accepted = False
            except Exception:
                accepted = False
            if accepted_only and not accepted:
                continue
            for command in commands:
                rc, _, err, seconds = run_command(command, spec, folder)
                verdict = cli_verdict(rc, err)
                counts[f"{command} {'accepted' if accepted else 'refused'}: {verdict}"] += 1
                suspicious = (
                    verdict in ("hang", "crash", "unclear", "silent-failure")
                    or (accepted and rc not in (0,))
                    or (not accepted and rc not in (3,))
                )
                if command == "generate" and not accepted and (folder / "out").exists():
                    suspicious = True
                    err += "\n(wrote output for a refused spec)"
                if suspicious:
                    bad += 1
                    print(
                        f"[{seed}:{number}] {command} rc={rc} {seconds:.1f}s {' | '.join(case.steps)}"
                    )
                    print("    " + err.strip().replace("\n", "\n    ")[-1500:])
    print("outcomes:", dict(counts))
    return 1 if bad else 0


def _layouts() -> dict[str, Callable[[str], str | bytes]]:
    import json

    import yaml

    return {
        "crlf": lambda t: t.replace("\n", "\r\n"),
        "bom": lambda t: "\ufeff" + t,
        "doc-markers": lambda t: "%YAML 1.2\n---\n" + t + "...\n",
        "quoted-keys": lambda t: re.sub(r"^(\s*)([a-z_]+):", r'\1"\2":', t, flags=re.M),
        "json": lambda t: json.dumps(yaml.safe_load(t), indent=1),
        "flow": lambda t: yaml.safe_dump(yaml.safe_load(t), default_flow_style=True),
        "no-comments": lambda t: re.sub(r"(?m)^\s*#.*\n", "", t),
        "indent-4": lambda t: re.sub(r"(?m)^( +)", lambda m: m.group(1) * 2, t),
    }


def layout_phase(commands: list[str], bases: list[str], only: list[str] | None) -> int:
    """Valid specs in other layouts (same values): every command must take them."""
    from codegen.spec_loader import load_spec

    bad = 0
    for base in bases:
        text = (ROOT / base).read_text(encoding="utf-8")
        for label, layout in _layouts().items():
            if only and label not in only:
                continue
            raw = layout(text)
            with tempfile.TemporaryDirectory(prefix="bldc layout ") as scratch:
                folder = Path(scratch)
                spec = folder / "spec.yaml"
                spec.write_bytes(raw if isinstance(raw, bytes) else raw.encode())
                try:
                    load_spec(spec)
                except Exception as error:  # the layout must not matter
                    bad += 1
                    print(f"{base} {label}: refused: {str(error)[:300]}")
                    continue
                for command in commands:
                    rc, _, err, seconds = run_command(command, spec, folder)
                    verdict = cli_verdict(rc, err)
                    print(f"{base} {label} {command}: {verdict} ({seconds:.1f} s)")
                    if rc != 0:
                        bad += 1
                        print("    " + err.strip().replace("\n", "\n    ")[-1500:])
    return 1 if bad else 0


def run_command(command: str, spec: Path, folder: Path) -> tuple[int, str, str, float]:
    """One CLI command on `spec` in `folder` (`run`), the tree it reads generated first
    where it reads one (firmware, verify, unity)."""
    if command in ("firmware", "verify", "unity"):
        run(["generate", str(spec), "-o", str(folder / "gen")], folder)
    return run(_argv(command, spec, folder), folder)


def _argv(command: str, spec: Path, folder: Path) -> list[str]:
    argv = [command, str(spec)]
    if command in ("generate", "audit", "simulate"):
        argv += ["-o", str(folder / "out")]
    if command == "simulate":
        argv += ["--quick", "--no-progress"]
    if command in ("firmware", "verify", "unity"):
        argv += ["--generated", str(folder / "gen")]
    if command == "verify":
        argv += ["--random", "200", "--no-progress"]
    if command == "bench":
        argv += ["--quick"]
    return argv


_INIT_OPTIONS = {
    "--pole-pairs": ["1", "2", "4", "7", "23", "64", "0", "65", "2.5", "-1", "x"],
    "--poles": ["2", "3", "14", "46", "128", "130"],
    "--resistance": ["0.001 ohm", "0.21 ohm", "5 ohm", "50 ohm", "100 ohm", "0 ohm", "1e-9 ohm"],
    "--resistance-line-to-line": ["0.2 ohm", "0.02 ohm", "12 ohm"],
    "--inductance": ["1 uH", "20 uH", "0.56 mH", "10 mH", "500 mH", "0.1 uH"],
    "--inductance-line-to-line": ["30 uH", "2 mH", "0.3 uH"],
    "--ke": ["0.01 V/krpm", "2.36 V/krpm", "100 V/krpm", "1 V/rpm", "1e-6 V/rpm"],
    "--kv": ["1", "30", "625", "5000", "20000", "0.001", "1e6"],
    "--rated-voltage": ["3 V", "12 V", "48 V", "400 V", "1000 V"],
    "--inertia": ["1e-9 kg*m^2", "1e-6 kg*m^2", "0.01 kg*m^2", "10 kg*m^2"],
    "--bus-voltage": ["1 V", "6 V", "12 V", "48 V", "100 V", "400 V", "800 V", "1000 V"],
    "--braking-current": ["0.1 A", "1 A", "5 A", "100 A", "500 A", "1000 A"],
    "--speed-max": ["1 rpm", "100 rpm", "3000 rpm", "60000 rpm", "1e6 rpm"],
    "--pwm-frequency": ["1 kHz", "2 kHz", "5 kHz", "7031.25 Hz", "20 kHz", "40 kHz", "100 kHz"],
    "--method": ["improved", "conventional", "none"],
}


def init_phase(seed: int, count: int, only: int | None) -> int:
    """`init` on random datasheet values; a spec it writes that loads must design."""
    import contextlib as _c
    import io

    from bldc.cli import main as cli_main
    from codegen.errors import SpecError
    from codegen.spec_loader import load_spec

    counts: Counter[str] = Counter()
    bad = 0
    scratch = Path(tempfile.mkdtemp(prefix="bldc-init-"))
    for number in [only] if only is not None else range(count):
        rng = random.Random(f"init:{seed}:{number}")
        options = rng.sample(sorted(_INIT_OPTIONS), rng.randint(1, 6))
        argv = ["init", "m", "-o", str(scratch / f"m{number}.yaml"), "--force"]
        for option in options:
            argv += [option, rng.choice(_INIT_OPTIONS[option])]
        err = io.StringIO()
        try:
            with _c.redirect_stderr(err), _c.redirect_stdout(io.StringIO()):
                rc = cli_main(argv)
        except SystemExit as exit_:
            rc = exit_.code if isinstance(exit_.code, int) else 2
        except Exception as error:
            rc = -1
            err.write(f"CRASH {type(error).__name__}: {error}")
        text = err.getvalue()
        verdict = f"exit {rc}"
        if rc in (-1, 70) or "Traceback" in text:
            verdict = "crash"
        elif rc == 0:
            try:
                with time_limit(60):
                    verdict = "written, " + design(load_spec(scratch / f"m{number}.yaml"))
            except SpecError as error:
                verdict = "written but refused"
                text += str(error)
            except Exception as error:
                verdict = "crash after init"
                text += f"{type(error).__name__}: {error}"
        counts[verdict] += 1
        if verdict.startswith(("crash", "written but", "written, design refused")) or (
            rc not in (0, 2, 3) and verdict != "crash"
        ):
            bad += 1
            print(f"[init {seed}:{number}] {verdict}: {' '.join(argv[4:])}\n    {text[-800:]}")
    print("outcomes:", dict(counts))
    return 1 if bad else 0


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("phase", choices=["load", "cli", "layout", "init"])
    parser.add_argument("--bases", default="spec/paper_motor.yaml", help="layout: specs")
    parser.add_argument("--layouts", default="", help="layout: which (default all)")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--count", type=int, default=500)
    parser.add_argument("--only", type=int, default=None, help="replay one case number")
    parser.add_argument("--limit", type=float, default=20.0, help="seconds per case (load)")
    parser.add_argument("--no-design", action="store_true")
    parser.add_argument("--commands", default="derive,generate")
    parser.add_argument("--dump", type=Path, help="write case --only to this file")
    parser.add_argument("--accepted-only", action="store_true", help="cli: skip refused specs")
    args = parser.parse_args(argv)
    if args.dump is not None and args.only is not None:
        args.dump.write_bytes(make_case(args.only, args.seed).raw)
        return 0
    if args.phase == "init":
        return init_phase(args.seed, args.count, args.only)
    if args.phase == "layout":
        layouts = args.layouts.split(",") if args.layouts else None
        return layout_phase(args.commands.split(","), args.bases.split(","), layouts)
    if args.phase == "load":
        return load_phase(args.seed, args.count, args.only, args.limit, not args.no_design)
    return cli_phase(args.seed, args.count, args.commands.split(","), args.only, args.accepted_only)


if __name__ == "__main__":
    os.environ.setdefault("PYTHONHASHSEED", "0")
    raise SystemExit(main())

"""codegen.yaml12: YAML 1.2 core-schema values, and hostile documents stopped early."""

from __future__ import annotations

from fractions import Fraction

import pytest

from codegen.yaml12 import (
    ExactFloat,
    Limits,
    Unreadable,
    YamlError,
    child_path,
    read_yaml,
    type_name,
    unreadable_values,
)


def value(text: str) -> object:
    data, _ = read_yaml(f"v: {text}\n".encode())
    assert isinstance(data, dict)
    return data["v"]


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        # YAML 1.1 literals that 1.2's core schema reads as strings
        ("1:00", "1:00"),
        ("yes", "yes"),
        ("No", "No"),
        ("on", "on"),
        ("OFF", "OFF"),
        ("y", "y"),
        ("1_000", "1_000"),
        ("2001-12-14", "2001-12-14"),
        ("0b101", "0b101"),
        ("٢٤", "٢٤"),  # Arabic-Indic digits are not a number
        ("２４", "２４"),  # nor are full-width ones
        # the core schema's own values
        ("010", 10),  # decimal in 1.2, octal 8 in 1.1
        ("0o17", 15),
        ("0x1F", 31),
        ("-12", -12),
        ("+7", 7),
        ("true", True),
        ("FALSE", False),
        ("~", None),
        ("null", None),
        ("", None),
        ("'12'", "12"),
        ("!!str 12", "12"),
        ("!!float 1", 1.0),
    ],
)
def test_plain_scalars_follow_the_yaml_1_2_core_schema(text: str, expected: object) -> None:
    got = value(text)
    assert got == expected
    if isinstance(expected, bool) or expected is None:
        assert got is expected
    else:  # an ExactFloat is a float; 1 is not True
        assert isinstance(got, type(expected)) and not isinstance(got, bool)


def test_floats_keep_their_exact_decimal_value() -> None:
    got = value("0.42")
    assert isinstance(got, ExactFloat) and got.exact == Fraction(21, 50)
    tiny = value("1e-400")
    assert isinstance(tiny, ExactFloat) and tiny == 0.0 and tiny.exact == Fraction(1, 10**400)
    assert value(".inf") == float("inf") and value("-.Inf") == float("-inf")
    nan = value(".NaN")
    assert isinstance(nan, float) and nan != nan


@pytest.mark.parametrize(
    ("document", "fragment", "path"),
    [
        (b"a: &x [*x]\n", "recursive alias *x", "a"),
        (b"a: &x {b: *x}\n", "recursive alias *x", "a"),
        (b"a: *nope\n", "found undefined alias 'nope'", "a"),
        (b"a: " + b"[" * 40 + b"]" * 40 + b"\n", "nested deeper than 16 levels", "a"),
        (b"a: !!python/object:os.system x\n", "YAML tag !!python/object:os.system", "a"),
        (b"a: !!binary aGk=\n", "YAML tag !!binary is not allowed", "a"),
        (b"a: !!int 1.5\n", "'1.5' is not a valid int", "a"),
        (b"a: 1\nb: 2\na: 3\n", "duplicate key 'a' (first defined on line 1)", "a"),
        (b"? [a, b]\n: 1\n", "a mapping key must be a plain value", ""),
        (b"? " + b"k" * 5000 + b"\n: 1\n", "a mapping key that is a value of 5000 char", ""),
        (b"a: 1\nb: \x07\n", "character U+0007 is not allowed", "b"),
        (b"a: 1\n---\nb: 2\n", "more than one YAML document: a second one starts at line 2", ""),
        (b"m:\n  x: 1\n  y: 2: 3\n", "mapping values are not allowed here", "m.y"),
        (b"a: \xff\n", "not UTF-8 text (byte 0xff at offset 3)", "a"),
        (b"x" * 300_000, "a spec has at most 262144", ""),
    ],
)
def test_hostile_documents_are_refused_in_one_line(
    document: bytes, fragment: str, path: str
) -> None:
    with pytest.raises(YamlError) as caught:
        read_yaml(document)
    assert fragment in caught.value.problem
    assert "\n" not in caught.value.problem
    assert caught.value.path == path


def test_a_control_character_in_a_file_of_carriage_returns_is_placed_on_its_line() -> None:
    """A file whose lines end in carriage returns alone had every refusal of a character
    on line 1, at `<document>`: lines are counted by YAML's line breaks."""
    with pytest.raises(YamlError) as caught:
        read_yaml(b"m:\r  a: 1\r  b: x\x07y\r")
    assert caught.value.line == 3
    assert caught.value.path == "m.b"


@pytest.mark.parametrize("character", ["\x00", "\x17", "\x7f", "\x9f", "\ufffe"])
def test_a_character_outside_yamls_printable_set_is_refused_with_the_set_it_may_hold(
    character: str,
) -> None:
    """The refusal named the character and the key but no allowed range (the hostile
    fuzzer's seeds 5-7: U+0017 in a value, U+0000 in the name): it names YAML's
    printable set, which every listed character is outside of."""
    with pytest.raises(YamlError) as caught:
        read_yaml(f"a: 1\nb: x{character}y\n".encode("utf-8", "surrogatepass"))
    assert f"character U+{ord(character):04X} is not allowed" in caught.value.problem
    assert caught.value.path == "b"
    assert caught.value.allowed.startswith("YAML's printable characters: tab, line feed")


@pytest.mark.parametrize(
    ("document", "line", "path"),
    [
        ("a: 1\n# a note \x85 more: x: y\nb: 2\n", 2, "a"),
        ("a: 1\nb: 2  # \u2029 - z\nc: 3\n", 2, "b"),
        ('a: 1\nb: "x\u2028y"\nc: 3\n', 2, "b"),
        # inside a key, its indentation or a quoted key: that key, not the one before
        ("m:\n  a: 1\n  phase_\u2028resistance: 2\n", 3, "m.phase_resistance"),
        ("m:\n  a: 1\n  \u2029b: 2\n", 3, "m.b"),
        ('m:\n  a: 1\n  "b\x85": 2\n', 3, "m.b"),
        # carriage returns alone end the lines, as PyYAML reads them
        ("m:\r  a: 1\r  b: x\u2028\r", 3, "m.b"),
        ("m:\r\n  a: 1\r\n  b\u2028: x\r\n", 3, "m.b"),
    ],
)
def test_a_raw_character_yaml_versions_read_apart_is_refused_on_its_own_line(
    document: str, line: int, path: str
) -> None:
    """U+0085 in a comment was a line break to PyYAML and text to YAML 1.2: the rest of
    the comment's line was read as a key ("malformed YAML" on line 3, at `a.more`), and
    U+2028 in a quoted value moved every later line's number by one. Raw, they are
    refused on their own line; as escapes in a double-quoted string they are text."""
    with pytest.raises(YamlError) as caught:
        read_yaml(document.encode())
    assert "is not allowed raw in a spec" in caught.value.problem
    assert "remove it" in caught.value.problem
    assert caught.value.line == line
    assert caught.value.path == path
    assert "less U+0085, U+2028 and U+2029" in caught.value.allowed
    values, lines = read_yaml(b'a: 1\nb: "x\\u2028y\\x85"\nc: 3\n')
    assert values == {"a": 1, "b": "x\u2028y\x85", "c": 3}
    assert lines["c"] == 3


@pytest.mark.parametrize(
    ("text", "shown", "problem"),
    [
        ("9" * 100, "9" * 80, "a number of 100 characters (at most 64)"),
        ("1e99999", "1e99999", "a number with an exponent beyond +-999"),
        ("x" * 5000, "x" * 80, "a value of 5000 characters (too long to read)"),
    ],
)
def test_a_value_too_long_to_read_stays_in_place_for_the_spec_reader(
    text: str, shown: str, problem: str
) -> None:
    # the spec's reader refuses it under its key, with the range the key allows
    got = value(text)
    assert got == Unreadable(shown, problem)
    assert repr(got) == repr(shown)
    assert type_name(got) == problem
    assert unreadable_values({"a": [1, got]}) == [("a[1]", got)]


def test_a_long_key_is_cut_in_its_key_path() -> None:
    assert child_path("motor", "k" * 100) == f"motor[{'k' * 61 + '...'!r}]"


def test_an_alias_bomb_is_stopped_by_the_expansion_limit() -> None:
    bomb = "a0: &a0 [x, x, x, x, x, x, x, x, x]\n" + "".join(
        f"a{i}: &a{i} [{', '.join([f'*a{i - 1}'] * 9)}]\n" for i in range(1, 12)
    )
    with pytest.raises(YamlError, match="expands to more than 12000 values"):
        read_yaml(bomb.encode())
    small = "a: &a [1, 2]\nb: [*a, *a]\n"
    data, _ = read_yaml(small.encode())
    assert data == {"a": [1, 2], "b": [[1, 2], [1, 2]]}


def test_limits_are_configurable_and_lines_are_recorded() -> None:
    with pytest.raises(YamlError, match="nested deeper than 2 levels"):
        read_yaml(b"a:\n  b:\n    c: 1\n", Limits(max_depth=2))
    data, lines = read_yaml(b"a:\n  b: 1\n  c: [1, 2]\n'': 3\n")
    assert data == {"a": {"b": 1, "c": [1, 2]}, "": 3}
    assert lines == {"a": 2, "a.b": 2, "a.c": 3, "a.c[0]": 3, "a.c[1]": 3, "['']": 4}


@pytest.mark.parametrize(
    ("text", "shown", "code"),
    [
        ('"bad \\ud800 x"', "bad \ud800 x", "U+D800"),
        ('"a \\x07 b"', "a \x07 b", "U+0007"),
        ('"nul \\0"', "nul \x00", "U+0000"),
        ('"\\x85 is fine"', None, None),
        ('"tab\\there"', None, None),
    ],
)
def test_an_escape_for_a_character_yaml_text_may_not_hold_should_be_unreadable(
    text: str, shown: str | None, code: str | None
) -> None:
    """Escapes in a double-quoted string are valid YAML, but write characters the
    document's own text may not hold: a lone surrogate passed the loader and failed
    every writer (UnicodeEncodeError), a NUL reached DERIVATION.md."""
    got = value(text)
    if shown is None:
        assert isinstance(got, str)
        return
    assert isinstance(got, Unreadable) and got.text == shown
    assert got.problem.startswith(f"text with {code}, a character YAML's printable set")

"""A bounded YAML 1.2 reader for specs: core schema, no surprises, no blow-ups.

PyYAML's own loaders implement YAML 1.1, where `1:00` is the base-60 number 60, `yes`,
`on` and `off` are booleans, `010` is octal and `1_000` is a thousand. A motor spec must
not change meaning that way, so this module uses PyYAML only to scan and parse, and
builds the Python values itself with the YAML 1.2 core schema (YAML 1.2.2, section
10.3.2):

    null   ~ null Null NULL (and an empty value)
    bool   true True TRUE false False FALSE
    int    [-+]?[0-9]+   0o[0-7]+   0x[0-9a-fA-F]+
    float  [-+]?(.[0-9]+|[0-9]+(.[0-9]*)?)([eE][-+]?[0-9]+)?   [-+]?.inf   .nan
    str    everything else, and every quoted or block scalar

Only ASCII digits count (`[0-9]`, never Python's Unicode-aware `\\d`). A float keeps its
exact decimal value beside the binary double (ExactFloat.exact), so 0.42 stays 21/50.

Hostile input is stopped before it can cost time or memory, in this order: the size of
the document, its characters (YAML's printable set), the nesting depth while composing,
recursive aliases, and the number of values after alias expansion while building.
Every failure is a YamlError with one line of text, the YAML line and, where known, the
key path it concerns. A value too long to convert (a string past max_scalar_chars, a
number past max_number_chars or max_exponent) is the one exception: it stays in place as
an Unreadable, which says what it is, so that the spec's reader names it under its key
with the value and the range the key allows (a YamlError knows neither); a string's
own length limit is the key's, so the reading limit is not quoted beside it.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from fractions import Fraction
from typing import Any

import yaml
from yaml.composer import Composer
from yaml.nodes import MappingNode, Node, ScalarNode, SequenceNode
from yaml.parser import Parser
from yaml.reader import Reader
from yaml.resolver import BaseResolver
from yaml.scanner import Scanner


@dataclass(frozen=True)
class Limits:
    """What a spec may cost to read. A real spec is about 6 kB, 3 levels deep, with
    about 120 values; these leave an order of magnitude of room and no more."""

    max_bytes: int = 256 * 1024
    max_depth: int = 16
    max_values: int = 12_000  # a 3601-point EMF table is 10 803 of them
    max_nodes: int = 50_000
    max_scalar_chars: int = 4096
    max_number_chars: int = 64
    max_exponent: int = 999


DEFAULT_LIMITS = Limits()

#: What the value limit means for a spec (a 4901-point EMF table was refused as "more
#: than 10000 values", which named neither the table nor what it may hold).
_VALUES_HINT = "a spec holds about 120, and a motor.back_emf_shape table at most 3601 points"


class YamlError(ValueError):
    """A document this reader refuses. `path` is the key path ('' if unknown)."""

    def __init__(
        self, problem: str, line: int | None = None, path: str = "", allowed: str = ""
    ) -> None:
        self.problem = " ".join(problem.split())  # always one line
        self.line = line
        self.path = path
        self.allowed = allowed  # what the document may hold there, where it is a rule
        super().__init__(self.problem)


@dataclass(frozen=True)
class Unreadable:
    """A scalar the reader would not convert: `text` is its start, `problem` what it is
    ("a number of 3003 characters (at most 64)"). Shown as its text, so a message quotes
    the value the user wrote."""

    text: str
    problem: str

    def __repr__(self) -> str:
        return repr(self.text)


def unreadable_values(data: Any, path: str = "") -> list[tuple[str, Unreadable]]:
    """Every Unreadable in a built document, with its key path."""
    if isinstance(data, Unreadable):
        return [(path, data)]
    if isinstance(data, dict):
        return [
            found
            for key, value in data.items()
            for found in unreadable_values(value, child_path(path, key))
        ]
    if isinstance(data, list):
        return [
            found
            for index, value in enumerate(data)
            for found in unreadable_values(value, f"{path}[{index}]")
        ]
    return []


class ExactFloat(float):
    """A YAML float that remembers its exact decimal value (None for inf and nan)."""

    exact: Fraction | None

    def __new__(cls, text: str, exact: Fraction | None) -> ExactFloat:
        value = super().__new__(cls, text)
        value.exact = exact
        return value


def type_name(value: object) -> str:
    """What a value is, in the spec author's (YAML's) words."""
    if value is None:
        return "an empty value (null)"
    if isinstance(value, Unreadable):
        return value.problem
    if isinstance(value, bool):
        return "a boolean"
    if isinstance(value, int):
        return "an integer"
    if isinstance(value, float):
        return "a number"
    if isinstance(value, str):
        return "a string"
    if isinstance(value, list):
        return "a list"
    if isinstance(value, dict):
        return "a mapping"
    return f"a {type(value).__name__}"


_PLAIN_KEY = re.compile(r"[A-Za-z_][A-Za-z0-9_.\-]*\Z")


#: Longest key shown whole in a key path; a longer one is cut (a 100 000-character key
#: made a message line of 100 kB).
_MAX_KEY_CHARS = 64


def _short_key(key: str) -> str:
    return key if len(key) <= _MAX_KEY_CHARS else key[: _MAX_KEY_CHARS - 3] + "..."


def child_path(parent: str, key: object) -> str:
    """The key path of `key` under `parent`: `motor.poles`; a key that is not a plain
    name (empty, a number, spaces, quotes) is shown as `motor['']`, `[1]`, a key longer
    than _MAX_KEY_CHARS cut to them ending in `...`."""
    if isinstance(key, str) and len(key) > _MAX_KEY_CHARS:
        return f"{parent}[{_short_key(key)!r}]"
    if isinstance(key, str) and _PLAIN_KEY.match(key):
        return f"{parent}.{key}" if parent else key
    return f"{parent}[{key!r}]"


_STR = "tag:yaml.org,2002:str"
_INT = "tag:yaml.org,2002:int"
_FLOAT = "tag:yaml.org,2002:float"
_BOOL = "tag:yaml.org,2002:bool"
_NULL = "tag:yaml.org,2002:null"
_SEQ = "tag:yaml.org,2002:seq"
_MAP = "tag:yaml.org,2002:map"
#: Tag of a plain (unquoted, untagged) scalar, resolved below by the core schema.
_PLAIN = "?plain"

_NULL_RE = re.compile(r"(?:~|null|Null|NULL|)\Z")
_TRUE_RE = re.compile(r"(?:true|True|TRUE)\Z")
_FALSE_RE = re.compile(r"(?:false|False|FALSE)\Z")
_INT10_RE = re.compile(r"[-+]?[0-9]+\Z")
_INT8_RE = re.compile(r"0o[0-7]+\Z")
_INT16_RE = re.compile(r"0x[0-9a-fA-F]+\Z")
_FLOAT_RE = re.compile(r"[-+]?(?:\.[0-9]+|[0-9]+(?:\.[0-9]*)?)(?:[eE](?P<exp>[-+]?[0-9]+))?\Z")
_INF_RE = re.compile(r"[-+]?(?:\.inf|\.Inf|\.INF)\Z")
_NAN_RE = re.compile(r"(?:\.nan|\.NaN|\.NAN)\Z")
#: YAML 1.2 c-printable, minus the byte-order mark inside the text.
_NOT_PRINTABLE = re.compile(
    "[^\x09\x0a\x0d\x20-\x7e\x85\xa0-\ud7ff\ue000-\ufefe\uff00-\ufffd\U00010000-\U0010ffff]"
)
_ABOVE_LATIN1 = "U+00A0 upward, less the surrogates, U+FEFF inside the text, U+FFFE and U+FFFF"
#: `_NOT_PRINTABLE`'s complement in words, for the refusal of a document that holds one
PRINTABLE = (
    "YAML's printable characters: tab, line feed, carriage return, U+0020-U+007E, U+0085"
    f" and {_ABOVE_LATIN1}"
)
#: the printable characters YAML 1.1 takes for line breaks and YAML 1.2 for text
_AMBIGUOUS_BREAK = re.compile("[\x85\u2028\u2029]")
#: what a spec's raw text may hold: the printable set less those three
PRINTABLE_UNAMBIGUOUS = (
    "YAML's printable characters less U+0085, U+2028 and U+2029: tab, line feed, carriage"
    f" return, U+0020-U+007E and {_ABOVE_LATIN1}"
)


class _Composer(Reader, Scanner, Parser, Composer, BaseResolver):
    """PyYAML's scanner and parser; composing with a depth limit, recursive
    aliases refused, and scalars left unresolved for the core schema."""

    def __init__(self, text: str, limits: Limits) -> None:
        Reader.__init__(self, text)
        Scanner.__init__(self)
        Parser.__init__(self)
        Composer.__init__(self)
        BaseResolver.__init__(self)
        self.limits = limits
        self.depth = 0
        self.open_nodes: set[int] = set()
        self.events = 0

    def resolve(self, kind: type, value: str | None, implicit: Any) -> str:
        if kind is ScalarNode:
            return _PLAIN if implicit[0] else _STR
        return _SEQ if kind is SequenceNode else _MAP

    def compose_node(self, parent: Node | None, index: object) -> Node:
        self.events += 1
        if self.events > self.limits.max_nodes:
            mark = self.peek_event().start_mark
            raise YamlError(f"more than {self.limits.max_nodes} YAML nodes", mark.line + 1)
        if self.check_event(yaml.AliasEvent):
            event = self.peek_event()
            target = self.anchors.get(event.anchor)
            if target is not None and id(target) in self.open_nodes:
                raise YamlError(
                    f"recursive alias *{event.anchor}: an anchor cannot contain itself",
                    event.start_mark.line + 1,
                )
            return super().compose_node(parent, index)
        event = self.peek_event()
        if self.depth >= self.limits.max_depth:
            raise YamlError(
                f"nested deeper than {self.limits.max_depth} levels", event.start_mark.line + 1
            )
        self.depth += 1
        try:
            return super().compose_node(parent, index)
        finally:
            self.depth -= 1

    def compose_sequence_node(self, anchor: str | None) -> Node:
        # As PyYAML's, but the node stays in open_nodes while its children are
        # composed: an alias to it from inside is a recursive alias.
        start = self.get_event()
        node = SequenceNode(
            _SEQ if start.tag in (None, "!") else start.tag,
            [],
            start.start_mark,
            None,
            flow_style=start.flow_style,
        )
        return self._children(node, anchor, self._sequence_items)

    def compose_mapping_node(self, anchor: str | None) -> Node:
        start = self.get_event()
        node = MappingNode(
            _MAP if start.tag in (None, "!") else start.tag,
            [],
            start.start_mark,
            None,
            flow_style=start.flow_style,
        )
        return self._children(node, anchor, self._mapping_items)

    def _children(self, node: Node, anchor: str | None, compose: Any) -> Node:
        if anchor is not None:
            self.anchors[anchor] = node
        self.open_nodes.add(id(node))
        try:
            compose(node)
        finally:
            self.open_nodes.discard(id(node))
        node.end_mark = self.get_event().end_mark
        return node

    def _sequence_items(self, node: SequenceNode) -> None:
        index = 0
        while not self.check_event(yaml.SequenceEndEvent):
            node.value.append(self.compose_node(node, index))
            index += 1

    def _mapping_items(self, node: MappingNode) -> None:
        while not self.check_event(yaml.MappingEndEvent):
            key = self.compose_node(node, None)
            node.value.append((key, self.compose_node(node, key)))


@dataclass
class _Builder:
    limits: Limits
    lines: dict[str, int]
    values: int = 0

    def build(self, node: Node, path: str, depth: int) -> Any:
        self.values += 1
        if self.values > self.limits.max_values:
            raise YamlError(
                f"the document expands to more than {self.limits.max_values} values"
                f" (aliases are expanded; {_VALUES_HINT})",
                node.start_mark.line + 1,
                path,
            )
        if depth > self.limits.max_depth:
            raise YamlError(
                f"nested deeper than {self.limits.max_depth} levels (through aliases)",
                node.start_mark.line + 1,
                path,
            )
        if path and path not in self.lines:
            self.lines[path] = node.start_mark.line + 1
        if isinstance(node, ScalarNode):
            return self.scalar(node, path)
        if isinstance(node, SequenceNode):
            if node.tag != _SEQ:
                raise self._tag_error(node, path)
            return [
                self.build(item, f"{path}[{index}]", depth + 1)
                for index, item in enumerate(node.value)
            ]
        if isinstance(node, MappingNode):
            if node.tag != _MAP:
                raise self._tag_error(node, path)
            out: dict[Any, Any] = {}
            first_line: dict[Any, int] = {}
            for key_node, value_node in node.value:
                if not isinstance(key_node, ScalarNode):
                    raise YamlError(
                        "a mapping key must be a plain value, not a list or a mapping",
                        key_node.start_mark.line + 1,
                        path,
                    )
                key = self.scalar(key_node, path)
                if isinstance(key, Unreadable):
                    raise YamlError(
                        f"a mapping key that is {key.problem}", key_node.start_mark.line + 1, path
                    )
                if isinstance(key, float) and key != key:
                    raise YamlError("a mapping key cannot be .nan", key_node.start_mark.line + 1)
                child = child_path(path, key)
                if key in first_line:
                    raise YamlError(
                        f"duplicate key {key!r} (first defined on line {first_line[key]})",
                        key_node.start_mark.line + 1,
                        child,
                    )
                first_line[key] = key_node.start_mark.line + 1
                if value_node.start_mark.index < key_node.end_mark.index:
                    # an alias: its node is the anchor's; cite the key that uses it
                    self.lines.setdefault(child, key_node.start_mark.line + 1)
                out[key] = self.build(value_node, child, depth + 1)
            return out
        raise YamlError(f"unexpected YAML node {type(node).__name__}", None, path)

    def _tag_error(self, node: Node, path: str) -> YamlError:
        tag = node.tag.replace("tag:yaml.org,2002:", "!!")
        return YamlError(
            f"YAML tag {tag} is not allowed in a spec (only the core schema's"
            " !!str, !!int, !!float, !!bool, !!null, !!seq and !!map)",
            node.start_mark.line + 1,
            path,
        )

    def scalar(self, node: ScalarNode, path: str) -> Any:
        text: str = node.value
        line = node.start_mark.line + 1
        if len(text) > self.limits.max_scalar_chars:
            # the reading limit is not quoted: the key's own (a description's 500
            # characters) follows as what it allows, and two limits had read as a riddle
            return Unreadable(text[:80], f"a value of {len(text)} characters (too long to read)")
        tag = node.tag
        bad = _NOT_PRINTABLE.search(text)
        if bad is not None:
            # an escape in a quoted string ("\ud800", "\x07", "\0") writes what the
            # document's text may not hold: a lone surrogate passed the loader and failed
            # every writer (UnicodeEncodeError), a NUL reached DERIVATION.md
            return Unreadable(
                text[:80],
                f"text with U+{ord(bad.group()):04X}, a character YAML's printable set"
                " leaves out (a control character or a lone surrogate, from an escape)",
            )
        if tag == _STR:
            return text
        if tag == _PLAIN:
            return self.core(text, line, path, strict=None)
        if tag in (_INT, _FLOAT, _BOOL, _NULL):
            return self.core(text, line, path, strict=tag)
        raise self._tag_error(node, path)

    def core(self, text: str, line: int, path: str, strict: str | None) -> Any:
        """Resolve a plain scalar by the YAML 1.2 core schema; with `strict` (an explicit
        !!int, !!float, !!bool or !!null tag) the text must be of that type."""
        if _NULL_RE.match(text):
            value: Any = None
            kind = _NULL
        elif _TRUE_RE.match(text) or _FALSE_RE.match(text):
            value, kind = bool(_TRUE_RE.match(text)), _BOOL
        elif _INT10_RE.match(text) or _INT8_RE.match(text) or _INT16_RE.match(text):
            if len(text) > self.limits.max_number_chars:
                return self._too_long(text)
            if text.startswith("0o"):
                value = int(text[2:], 8)
            elif text.startswith("0x"):
                value = int(text[2:], 16)
            else:
                value = int(text, 10)
            kind = _INT
        elif match := _FLOAT_RE.match(text):
            if len(text) > self.limits.max_number_chars:
                return self._too_long(text)
            exponent = match.group("exp")
            if exponent is not None and abs(int(exponent)) > self.limits.max_exponent:
                return Unreadable(
                    text, f"a number with an exponent beyond +-{self.limits.max_exponent}"
                )
            value, kind = ExactFloat(text, Fraction(text)), _FLOAT
        elif _INF_RE.match(text):
            value, kind = ExactFloat(text.replace(".", "").lower(), None), _FLOAT
        elif _NAN_RE.match(text):
            value, kind = ExactFloat("nan", None), _FLOAT
        else:
            value, kind = text, _STR
        if strict is None or strict == kind or (strict == _FLOAT and kind == _INT):
            if strict == _FLOAT and kind == _INT:
                return ExactFloat(str(value), Fraction(value))
            return value
        raise YamlError(
            f"{text!r} is not a valid {strict.rsplit(':', 1)[-1]} for its explicit tag", line, path
        )

    def _too_long(self, text: str) -> Unreadable:
        return Unreadable(
            text[:80],
            f"a number of {len(text)} characters (at most {self.limits.max_number_chars})",
        )


#: YAML's line breaks (PyYAML's too, once U+0085, U+2028 and U+2029 are refused)
_LINE_BREAK = re.compile(r"\r\n|\r|\n")


def _line_at(text: str, index: int) -> int:
    """The 1-based line of `text[index]`, counted by YAML's line breaks (a file with
    carriage returns alone had every refusal of a character on line 1)."""
    return len(_LINE_BREAK.findall(text, 0, index)) + 1


def _key_near(text: str, line: int) -> str:
    """The block-mapping key path in force at `line` (1-based), read from indentation:
    a best guess for naming the key of a syntax error, '' if none is found. Characters
    a spec may not hold are left out first, so that one inside a key or its indentation
    names that key, not the one before it."""
    stack: list[tuple[int, str]] = []
    # a tab in the indentation is what PyYAML refuses there: count it as one column
    key_line = re.compile(
        r"^(?P<indent>[ \t]*)"
        r"(?:\"(?P<double>[^\"]*)\"|'(?P<single>[^']*)'|(?P<key>[A-Za-z_][A-Za-z0-9_.\[\]]*))"
        r"\s*:(?:\s|$)"
    )
    clean = _AMBIGUOUS_BREAK.sub("", _NOT_PRINTABLE.sub("", text))
    for content in _LINE_BREAK.split(clean)[:line]:
        match = key_line.match(content)
        if match is None:
            continue
        indent = len(match.group("indent"))
        while stack and stack[-1][0] >= indent:
            stack.pop()
        key = next(k for k in match.group("double", "single", "key") if k is not None)
        stack.append((indent, _short_key(key)))
    return ".".join(key for _, key in stack)


def read_yaml(raw: bytes, limits: Limits = DEFAULT_LIMITS) -> tuple[Any, dict[str, int]]:
    """The document's value and, for each key path, the 1-based line of its value."""
    if len(raw) > limits.max_bytes:
        raise YamlError(
            # the loader reads one byte past the limit, never the whole of a huge file
            f"the file has more than {limits.max_bytes} bytes; a spec has at most"
            f" {limits.max_bytes}",
            None,
        )
    try:
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        before = raw[: exc.start].decode("utf-8", "replace")
        line = _line_at(before, len(before))
        raise YamlError(
            f"not UTF-8 text (byte 0x{raw[exc.start]:02x} at offset {exc.start})",
            line,
            _key_near(before + "\n", line),
        ) from None
    bad = _NOT_PRINTABLE.search(text)
    if bad is not None:
        line = _line_at(text, bad.start())
        raise YamlError(
            f"character U+{ord(bad.group()):04X} is not allowed in YAML (binary or"
            " control characters)",
            line,
            _key_near(text, line),
            PRINTABLE,
        )
    ambiguous = _AMBIGUOUS_BREAK.search(text)
    if ambiguous is not None:
        # YAML 1.2 reads U+0085, U+2028 and U+2029 as text, PyYAML (YAML 1.1) as line
        # breaks: one in a comment ended the comment there and the rest of its line was
        # read as a key (a "malformed YAML" line that pointed at the wrong line)
        line = _line_at(text, ambiguous.start())
        char = ambiguous.group()
        instead = (
            "remove it (a C1 control character, which no spec value may hold)"
            if char == "\x85"
            else f"remove it, or write it as the escape \\u{ord(char):04X} in a double-quoted string"
        )
        raise YamlError(
            f"character U+{ord(char):04X} is not allowed raw in a spec: a line break to YAML"
            f" 1.1 readers and text to YAML 1.2; {instead}",
            line,
            _key_near(text, line),
            PRINTABLE_UNAMBIGUOUS,
        )
    composer = _Composer(text, limits)
    try:
        _check_flow_depth(text, limits)
        root = composer.get_single_node()
    except YamlError as exc:
        if not exc.path and exc.line is not None:
            exc.path = _key_near(text, exc.line)
        raise
    except yaml.MarkedYAMLError as exc:
        mark = exc.problem_mark or exc.context_mark
        line = mark.line + 1 if mark is not None else None
        if _second_document(exc):
            # it had read as malformed YAML at the last key of the first document
            raise YamlError(
                f"the file holds more than one YAML document: a second one starts at line"
                f" {line} ('---'); remove that line and what follows it",
                line,
                "",  # the whole file's, not the last key's
                "one YAML document per spec file",
            ) from None
        parts = [part for part in (exc.context, exc.problem) if part]
        problem = ": ".join(parts) or "malformed YAML"
        raise YamlError(
            f"malformed YAML: {problem}", line, _key_near(text, line) if line else ""
        ) from None
    except yaml.YAMLError as exc:
        raise YamlError(f"malformed YAML: {exc}", None) from None
    finally:
        composer.dispose()
    lines: dict[str, int] = {}
    if root is None:
        return None, lines
    try:
        _check_expansion(root, limits)
    except YamlError as exc:
        exc.path = _key_near(text, exc.line) if exc.line else ""
        raise
    return _Builder(limits, lines).build(root, "", 0), lines


def _second_document(exc: yaml.MarkedYAMLError) -> bool:
    """Whether PyYAML's error is a second document after the first (`---` and more)."""
    return isinstance(exc, yaml.composer.ComposerError) and "another document" in str(exc.problem)


def _check_flow_depth(text: str, limits: Limits) -> None:
    """Refuse deeply nested flow collections (`[[[[...`) before PyYAML scans them: its
    scanner keeps a possible simple key per open bracket and rescans them all at each
    token, quadratic in the depth. Brackets inside quoted scalars and comments do not
    count; a quote opens only where a YAML node can start, and no quote outlives its line
    here, so a stray apostrophe cannot hide brackets. Four times the composer's limit, so
    this never refuses what the composer would accept."""
    limit = 4 * limits.max_depth
    depth = 0
    line = 1
    for text_line in text.split("\n"):
        quote = ""
        last = "\n"  # the previous non-blank character on the line
        index = 0
        length = len(text_line)
        while index < length:
            char = text_line[index]
            if quote:
                if char == "\\" and quote == '"':
                    index += 1
                elif char == quote:
                    quote = ""
            elif char == "#" and (index == 0 or text_line[index - 1] in " \t"):
                break
            elif char in "'\"" and last in "\n:[{,-?":
                quote = char
            elif char in "[{":
                depth += 1
                if depth > limit:
                    raise YamlError(f"nested deeper than {limits.max_depth} levels", line)
            elif char in "]}" and depth:
                depth -= 1
            if char not in " \t":
                last = char
            index += 1
        line += 1


def _check_expansion(root: Node, limits: Limits) -> None:
    """Refuse a document whose aliases expand it past max_values, counting on the node
    graph (each anchored node once, memoised) before a single value is built."""
    sizes: dict[int, int] = {}

    def size(node: Node, depth: int) -> int:
        known = sizes.get(id(node))
        if known is not None:
            return known
        if depth > limits.max_depth:
            raise YamlError(
                f"nested deeper than {limits.max_depth} levels (through aliases)",
                node.start_mark.line + 1,
            )
        total = 1
        if isinstance(node, SequenceNode):
            total += sum(size(item, depth + 1) for item in node.value)
        elif isinstance(node, MappingNode):
            total += sum(size(value, depth + 1) for _, value in node.value)
        if total > limits.max_values:
            raise YamlError(
                f"the document expands to more than {limits.max_values} values (aliases"
                f" are expanded; {_VALUES_HINT})",
                node.start_mark.line + 1,
            )
        sizes[id(node)] = total
        return total

    size(root, 0)

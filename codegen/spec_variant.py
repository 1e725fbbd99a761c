"""A spec's YAML with the commutation method (and optionally the name) replaced, its
duty accuracy target, or its back-EMF shape.

The simulation and the bench measure a motor under every method; they derive each
variant from the user's spec text, so comments and layout are kept and every other
value is the user's. The value is found by the YAML parser's marks, not by a pattern
over lines: a line pattern missed a valid spec's quoted key ("method": improved), a
quoted value, a flow mapping or a JSON spec, and `simulate` refused the spec with
"controller.method = None: no line to replace".
"""

from __future__ import annotations

import re

import yaml
from yaml.nodes import MappingNode, Node, ScalarNode

from codegen.errors import MISSING, NOT_READ, SpecError
from codegen.spec_model import COMMUTATION_METHODS
from codegen.yaml12 import YamlError, read_yaml

_ANCHOR = re.compile(r"&[^\s,\[\]{}]+\s*")
_ALIAS = re.compile(r"[\"']?\s*:\s*(\*[^\s,\[\]{}]+)")


def _mapping_entry(
    spec_text: str, root: Node | None, path: tuple[str, ...]
) -> tuple[MappingNode, tuple[int, int] | None]:
    """The mapping that holds the last key of `path`, and the span of that key's value
    in `spec_text` (None where the key is missing)."""
    node = root
    for depth, key in enumerate(path):
        if not isinstance(node, MappingNode):
            raise SpecError(".".join(path[: depth + 1]), NOT_READ, "no mapping to find it in")
        holder = node
        entry = next(
            ((k, v) for k, v in node.value if isinstance(k, ScalarNode) and k.value == key),
            None,
        )
        if entry is None:
            if depth == len(path) - 1:
                return holder, None
            raise SpecError(".".join(path[: depth + 1]), MISSING, "missing")
        key_node, node = entry
    assert isinstance(holder, MappingNode)
    if node.start_mark.index < key_node.end_mark.index:
        # an alias (*name): its node is the anchor's, written before this key; the
        # alias itself is replaced, the anchor and every other key that uses it kept
        alias = _ALIAS.match(spec_text, key_node.end_mark.index)
        assert alias is not None, spec_text[key_node.end_mark.index :][:40]
        return holder, alias.span(1)
    start, end = node.start_mark.index, node.end_mark.index
    if anchor := _ANCHOR.match(spec_text, start):
        start = anchor.end()  # keep `&name` (a key that shares it is caught later)
    colon = spec_text.index(":", key_node.end_mark.index)
    if "\n" in spec_text[colon:start] and not spec_text[colon + 1 : start].strip(" \t\r\n"):
        # a block collection on the lines below its key (`back_emf_shape:` then `- - 0`
        # at the key's indent): the flow value replaces it from the colon on, where the
        # value written at the collection's place had been read as a key
        start = colon + 1
    # a block collection's span runs to the next key: keep its line break and indent
    return holder, (start, start + len(spec_text[start:end].rstrip()))


def _compose(spec_text: str) -> Node | None:
    try:
        return yaml.compose(spec_text, Loader=yaml.SafeLoader)
    except yaml.YAMLError as exc:
        raise SpecError("<document>", NOT_READ, f"not YAML: {' '.join(str(exc).split())}") from None


def _replaced(spec_text: str, path: tuple[str, ...], value: str, allowed: str) -> str:
    """`spec_text` with the value at `path` replaced by the YAML text `value` (a plain
    scalar or a flow collection), found by the YAML parser's marks, so a quoted key or
    value, a flow mapping or a JSON spec is rewritten as well as a block one. Every
    other character stays the user's."""
    where = ".".join(path)
    _, span = _mapping_entry(spec_text, _compose(spec_text), path)
    if span is None:
        raise SpecError(where, MISSING, "missing: no value to replace", allowed)
    start, end = span
    gap = " " if spec_text[start - 1 : start] == ":" else ""
    new = spec_text[:start] + gap + value + spec_text[end:]
    _check_only(spec_text, new, path, where, allowed)
    return new


def _check_only(old: str, new: str, path: tuple[str, ...], where: str, allowed: str) -> None:
    """The rewrite changed `path` and nothing else (an anchored value that other keys
    take through aliases is refused, not rewritten behind their back)."""
    try:
        before, _ = read_yaml(old.encode("utf-8"))
        after, _ = read_yaml(new.encode("utf-8"))
    except YamlError as exc:
        raise SpecError(
            where, NOT_READ, f"the rewritten spec does not read: {exc.problem}"
        ) from None
    for data in (before, after):
        holder = data
        for key in path[:-1]:
            holder = holder[key]
        holder.pop(path[-1], None)
    if before != after:
        raise SpecError(
            where,
            None,
            "cannot be rewritten for a variant of the spec: other keys take its value"
            " through an alias (*name); write the value itself there",
            allowed,
        )


def spec_with_method(spec_text: str, method: str, name: str | None = None) -> str:
    """The spec YAML with controller.method (and the top-level name) replaced."""
    new = _replaced(spec_text, ("controller", "method"), method, f"one of {COMMUTATION_METHODS}")
    if name is not None:
        new = _replaced(new, ("name",), name, "a spec name")
    return new


def spec_with_duty_target(spec_text: str, counts: str) -> str:
    """The spec YAML with accuracy.duty_counts replaced by `counts`."""
    return _replaced(spec_text, ("accuracy", "duty_counts"), counts, "a number of counts")


def spec_with_time_target(spec_text: str, ticks: str) -> str:
    """The spec YAML with accuracy.commutation_time_ticks replaced by `ticks`."""
    return _replaced(
        spec_text, ("accuracy", "commutation_time_ticks"), ticks, "a number of Hall ticks"
    )


#: The EMF shape the improved_r firmware takes where it refuses the spec's own (a shape
#: that is not affine over the commutation): the paper's trapezoid.
FALLBACK_SHAPE = "120 deg"


def spec_with_emf_shape(spec_text: str, shape: str) -> str:
    """The spec YAML with motor.back_emf_shape set to `shape` (a scalar or a flow list):
    the entry replaced (a block list under it too), or added as the motor section's
    first key, in the section's own style (block or flow)."""
    allowed = "a motor section"
    motor, span = _mapping_entry(spec_text, _compose(spec_text), ("motor", "back_emf_shape"))
    if span is not None:
        return _replaced(spec_text, ("motor", "back_emf_shape"), shape, allowed)
    if not motor.value:
        raise SpecError("motor", MISSING, "no keys to put back_emf_shape beside", allowed)
    first = motor.value[0][0]
    at = first.start_mark.index
    if motor.flow_style:
        entry = f"back_emf_shape: {shape}, "
    else:
        entry = f"back_emf_shape: {shape}\n{' ' * first.start_mark.column}"
    new = spec_text[:at] + entry + spec_text[at:]
    _check_only(spec_text, new, ("motor", "back_emf_shape"), "motor.back_emf_shape", allowed)
    return new


def shape_refused(output: str) -> bool:
    """The improved_r design refused the spec's EMF shape (not affine over the
    commutation)."""
    return "motor.back_emf_shape" in output

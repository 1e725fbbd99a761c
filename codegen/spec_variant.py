"""A spec's YAML with the commutation method (and optionally the name) replaced, its
duty accuracy target, or its back-EMF shape.

The simulation and the bench measure a motor under every method; they derive each
variant from the user's spec text, so comments and layout are kept and every other
value is the user's.
"""

from __future__ import annotations

import re

from codegen.errors import SpecError
from codegen.spec_model import COMMUTATION_METHODS


def spec_with_method(spec_text: str, method: str, name: str | None = None) -> str:
    """The spec YAML with controller.method (and the top-level name) replaced."""
    new, count = re.subn(r"(?m)^(\s+method:\s*)[A-Za-z_]+", rf"\g<1>{method}", spec_text, count=1)
    if count != 1:
        raise SpecError(
            "controller.method", None, "no line to replace", f"one of {COMMUTATION_METHODS}"
        )
    if name is not None:
        new, count = re.subn(r"(?m)^(name:\s*)\S+", rf"\g<1>{name}", new, count=1)
        if count != 1:
            raise SpecError("name", None, "no top-level line to replace", "a spec name")
    return new


def spec_with_duty_target(spec_text: str, counts: str) -> str:
    """The spec YAML with accuracy.duty_counts replaced by `counts`."""
    new, count = re.subn(r"(?m)^(\s+duty_counts:\s*)[^\s#]+", rf"\g<1>{counts}", spec_text, count=1)
    if count != 1:
        raise SpecError("accuracy.duty_counts", None, "no line to replace", "a number of counts")
    return new


#: The EMF shape the improved_r firmware takes where it refuses the spec's own (a shape
#: that is not affine over the commutation): the paper's trapezoid.
FALLBACK_SHAPE = "120 deg"


def spec_with_emf_shape(spec_text: str, shape: str) -> str:
    """The spec YAML with motor.back_emf_shape set to `shape` (a scalar or a flow list):
    the entry replaced (with any block-list lines under it), or added under `motor:`."""
    lines = spec_text.splitlines(keepends=True)
    out: list[str] = []
    skip_indent: int | None = None
    # an entry of the spec's own is replaced where it is; only without one is it added
    placed = any(re.match(r"^\s+back_emf_shape:", line) for line in lines)
    for line in lines:
        indent = len(line) - len(line.lstrip(" "))
        if skip_indent is not None:
            if line.strip() and indent > skip_indent:
                continue
            skip_indent = None
        match = re.match(r"^(\s+)back_emf_shape:", line)
        if match:
            out.append(f"{match.group(1)}back_emf_shape: {shape}\n")
            skip_indent = len(match.group(1))
            placed = True
            continue
        out.append(line)
        if not placed and re.match(r"^motor:\s*(#.*)?$", line):
            out.append(f"  back_emf_shape: {shape}\n")
            placed = True
    if not placed:
        raise SpecError(
            "motor", None, "no motor: section to put back_emf_shape in", "a motor section"
        )
    return "".join(out)


def shape_refused(output: str) -> bool:
    """The improved_r design refused the spec's EMF shape (not affine over the
    commutation)."""
    return "motor.back_emf_shape" in output

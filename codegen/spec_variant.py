"""A spec's YAML with the commutation method (and optionally the name) replaced, or
its duty accuracy target.

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

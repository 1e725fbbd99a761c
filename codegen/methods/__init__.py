"""Commutation methods, one folder each, behind `codegen.methods.base.Method`.

Adding a method: a folder with an `__init__.py` exposing METHOD, its name in
`codegen.spec_model.COMMUTATION_METHODS`, and its tests.
"""

from __future__ import annotations

from importlib import import_module

from codegen.methods.base import Method


def method(name: str) -> Method:
    """The method of that name (one of COMMUTATION_METHODS)."""
    module = import_module(f"codegen.methods.{name}")
    return module.METHOD  # type: ignore[no-any-return]

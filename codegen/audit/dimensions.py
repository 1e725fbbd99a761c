"""Dimensional analysis of printed expressions (SymPy's SI dimension system).

A sum whose terms have different dimensions cannot be right whatever the numbers;
this finds, for example, "- R i_a" added to a slope in A/s.
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy as sp
from sympy.physics import units as u
from sympy.physics.units.systems.si import dimsys_SI

from codegen.derivation import symbols as s

_ONE = u.Dimension(1)

SYMBOL_DIMENSIONS: dict[sp.Symbol, u.Dimension] = {
    s.U_d: u.voltage,
    s.E: u.voltage,
    s.L: u.inductance,
    s.R: u.impedance,
    s.I: u.current,
    s.i_a: u.current,
    s.i_b: u.current,
    s.i_c: u.current,
    s.t: u.time,
    s.D_on: _ONE,
    s.D_off: _ONE,
    s.D: _ONE,
    s.omega_m: 1 / u.time,
    s.n: 1 / u.time,
    s.k_e: u.voltage * u.time,
}

_NAMED: tuple[tuple[str, u.Dimension], ...] = (
    ("1", _ONE),
    ("V", u.voltage),
    ("A", u.current),
    ("A/s", u.current / u.time),
    ("s", u.time),
    ("N m", u.energy),
    ("V A", u.power),
    ("H", u.inductance),
    ("ohm", u.impedance),
)


def dimension_name(dim: u.Dimension) -> str:
    for name, named in _NAMED:
        if dimsys_SI.equivalent_dims(dim, named):
            return name
    deps = dimsys_SI.get_dimensional_dependencies(dim)
    return " ".join(f"{base.name}^{power}" for base, power in deps.items()) or "1"


@dataclass(frozen=True)
class DimensionClash:
    """Terms of one sum with different dimensions."""

    terms: tuple[tuple[str, str], ...]  # (term LaTeX, dimension)


class _ClashError(Exception):
    def __init__(self, clash: DimensionClash) -> None:
        super().__init__(str(clash))
        self.clash = clash


def _dimension(expr: sp.Basic) -> u.Dimension:
    if expr.is_Number:
        return _ONE
    if isinstance(expr, sp.Symbol):
        return SYMBOL_DIMENSIONS[expr]
    if isinstance(expr, sp.Mul):
        out = _ONE
        for factor in expr.args:
            out = out * _dimension(factor)
        return out
    if isinstance(expr, sp.Pow) and expr.exp.is_Number:
        return _dimension(expr.base) ** expr.exp
    if isinstance(expr, sp.Add):
        dims = [(term, _dimension(term)) for term in expr.args]
        first = dims[0][1]
        if all(dimsys_SI.equivalent_dims(first, d) for _, d in dims[1:]):
            return first
        raise _ClashError(DimensionClash(tuple((sp.latex(t), dimension_name(d)) for t, d in dims)))
    raise TypeError(f"no dimension rule for {type(expr).__name__}")


def check_dimensions(expr: sp.Basic) -> DimensionClash | None:
    """The first clash in `expr` (outermost sum first), or None if consistent."""
    try:
        _dimension(sp.expand(expr))
    except _ClashError as clash:
        return clash.clash
    return None


def dimension_of(expr: sp.Basic) -> str:
    return dimension_name(_dimension(expr))

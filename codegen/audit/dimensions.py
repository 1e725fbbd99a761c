"""Dimensional analysis of printed expressions, in SI base dimensions.

A sum whose terms have different dimensions cannot be right whatever the numbers;
this finds, for example, "- R i_a" added to a slope in A/s.

A dimension is its vector of exponents over the SI base dimensions the paper's
quantities need (mass, length, time, current). That is all `sympy.physics.units`
would do here, and importing it costs a fifth of a second of every audit.
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction

import sympy as sp

from codegen.derivation import symbols as s

_BASE = ("kg", "m", "s", "A")


@dataclass(frozen=True)
class Dimension:
    """Exponents of kg, m, s and A."""

    exponents: tuple[Fraction, Fraction, Fraction, Fraction]

    def __mul__(self, other: Dimension) -> Dimension:
        return Dimension(tuple(a + b for a, b in zip(self.exponents, other.exponents, strict=True)))  # type: ignore[arg-type]

    def __pow__(self, power: Fraction) -> Dimension:
        return Dimension(tuple(a * power for a in self.exponents))  # type: ignore[arg-type]

    def __truediv__(self, other: Dimension) -> Dimension:
        return self * other ** Fraction(-1)


def _dim(kg: int = 0, m: int = 0, sec: int = 0, amp: int = 0) -> Dimension:
    return Dimension((Fraction(kg), Fraction(m), Fraction(sec), Fraction(amp)))


ONE = _dim()
CURRENT = _dim(amp=1)
TIME = _dim(sec=1)
VOLTAGE = _dim(kg=1, m=2, sec=-3, amp=-1)  # W/A
INDUCTANCE = _dim(kg=1, m=2, sec=-2, amp=-2)  # V s/A
RESISTANCE = _dim(kg=1, m=2, sec=-3, amp=-2)  # V/A

SYMBOL_DIMENSIONS: dict[sp.Symbol, Dimension] = {
    s.U_d: VOLTAGE,
    s.E: VOLTAGE,
    s.L: INDUCTANCE,
    s.R: RESISTANCE,
    s.I: CURRENT,
    s.i_a: CURRENT,
    s.i_b: CURRENT,
    s.i_c: CURRENT,
    s.t: TIME,
    s.D_on: ONE,
    s.D_off: ONE,
    s.D: ONE,
    s.omega_m: ONE / TIME,
    s.n: ONE / TIME,
    s.k_e: VOLTAGE * TIME,
}

_NAMED: tuple[tuple[str, Dimension], ...] = (
    ("1", ONE),
    ("V", VOLTAGE),
    ("A", CURRENT),
    ("A/s", CURRENT / TIME),
    ("s", TIME),
    ("N m", VOLTAGE * CURRENT * TIME),
    ("V A", VOLTAGE * CURRENT),
    ("H", INDUCTANCE),
    ("ohm", RESISTANCE),
)


def dimension_name(dim: Dimension) -> str:
    for name, named in _NAMED:
        if dim == named:
            return name
    return (
        " ".join(
            f"{base}^{power}" for base, power in zip(_BASE, dim.exponents, strict=True) if power
        )
        or "1"
    )


@dataclass(frozen=True)
class DimensionClash:
    """Terms of one sum with different dimensions."""

    terms: tuple[tuple[str, str], ...]  # (term LaTeX, dimension)


class _ClashError(Exception):
    def __init__(self, clash: DimensionClash) -> None:
        super().__init__(str(clash))
        self.clash = clash


def _dimension(expr: sp.Basic) -> Dimension:
    if expr.is_Number:
        return ONE
    if isinstance(expr, sp.Symbol):
        return SYMBOL_DIMENSIONS[expr]
    if isinstance(expr, sp.Mul):
        out = ONE
        for factor in expr.args:
            out = out * _dimension(factor)
        return out
    if isinstance(expr, sp.Pow) and expr.exp.is_Rational:
        return _dimension(expr.base) ** Fraction(int(expr.exp.p), int(expr.exp.q))
    if isinstance(expr, sp.Add):
        dims = [(term, _dimension(term)) for term in expr.args]
        first = dims[0][1]
        if all(d == first for _, d in dims[1:]):
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

"""The psi1/psi2 table: octave segments, linear interpolation, proven error.

psi1(y) = (1 - e^{-y})/y and psi2(y) = 2 (y - 1 + e^{-y})/y^2 are completely monotone
(integrals of e^{-y s} against positive kernels, checked in the derivation), so on
every interval |psi''| is largest at its left end and decays like 1/y^3. Equal steps
would waste entries at large y; the table uses octaves instead:

    segment 0 covers [0, 1) in steps of 2^-n, segment j >= 1 covers [2^(j-1), 2^j) in
    steps of 2^(j-1-n); each has N = 2^n entries, plus one closing entry at 2^J.

The segment of y (Q(fy) in an integer) is its integer part's bit length (one CLZ on a
Cortex-M3), so the index is a shift and an add. Entries are complements
c = round((1 - psi) 2^16) in uint16 (psi is in (0, 1], 1 - psi in [0, 1)).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import mpmath
import sympy as sp

from codegen.derivation.constant_pair import derive_firmware_rule, psi1, psi2, y

ONE_Q16 = 1 << 16
_DIGITS = 40


@dataclass(frozen=True)
class PsiTable:
    segment_bits: int  # n: 2^n entries per segment
    segments: int  # J + 1
    y_frac_bits: int  # fy: y = y_q / 2^fy
    complement1: tuple[int, ...]  # round((1 - psi1(y_k)) 2^16)
    complement2: tuple[int, ...]
    #: max |psi - table interpolation| over [0, 2^J) with exact y (interpolation
    #: remainder + entry rounding + the interpolation's own rounding), per function.
    error1: float
    error2: float

    @property
    def entries(self) -> int:
        return len(self.complement1)

    @property
    def y_limit(self) -> int:
        """Largest y_q the table covers (y < 2^J)."""
        return (1 << (self.segments - 1 + self.y_frac_bits)) - 1

    @property
    def flash_bytes(self) -> int:
        return 4 * self.entries


def grid_point(k: int, segment_bits: int) -> sp.Rational:
    """y of entry k."""
    per = 1 << segment_bits
    if k < per:
        return sp.Rational(k, per)
    j, offset = divmod(k, per)  # segment j >= 1 starts at 2^(j-1)
    return sp.Rational(2 ** (j - 1)) * (1 + sp.Rational(offset, per))


def _value(expr: sp.Expr, at: sp.Rational) -> mpmath.mpf:
    if at == 0:
        return mpmath.mpf(1)
    with mpmath.workdps(_DIGITS):
        return mpmath.mpf(sp.N(expr.subs(y, at), _DIGITS))


def _complement(expr: sp.Expr, at: sp.Rational) -> int:
    with mpmath.workdps(_DIGITS):
        return int(mpmath.nint((1 - _value(expr, at)) * ONE_Q16))


@lru_cache(maxsize=8)
def _second_derivative_bounds(segment_bits: int, segments: int) -> tuple[tuple[float, float], ...]:
    """max |psi1''|, |psi2''| per segment: their values at the segment's left end."""
    rule = derive_firmware_rule()
    d1, d2 = psi1.diff(y, 2), psi2.diff(y, 2)
    out = [(float(rule.psi1_second_derivative_max), float(rule.psi2_second_derivative_max))]
    for j in range(1, segments):
        left = sp.Integer(2 ** (j - 1))
        out.append((float(sp.N(d1.subs(y, left))), float(sp.N(d2.subs(y, left)))))
    return tuple(out)


def step(segment: int, segment_bits: int) -> float:
    return 2.0 ** (max(segment - 1, 0) - segment_bits)


def design_psi_table(y_max: sp.Rational, segment_bits: int, y_frac_bits: int) -> PsiTable:
    top = 0  # J: the table covers y < 2^J
    while 2**top <= y_max:
        top += 1
    segments = top + 1
    per = 1 << segment_bits
    count = per * segments + 1
    points = [grid_point(k, segment_bits) for k in range(count)]
    c1 = tuple(_complement(psi1, p) for p in points)
    c2 = tuple(_complement(psi2, p) for p in points)
    rounding = 2 * 0.5 / ONE_Q16  # entry rounding (interpolated, <= 1/2 ULP) + product rounding
    err1 = err2 = 0.0
    for j, (m1, m2) in enumerate(_second_derivative_bounds(segment_bits, segments)):
        h = step(j, segment_bits)
        err1 = max(err1, h * h / 8 * m1)
        err2 = max(err2, h * h / 8 * m2)
    return PsiTable(segment_bits, segments, y_frac_bits, c1, c2, err1 + rounding, err2 + rounding)


def locate(table: PsiTable, y_q: int) -> tuple[int, int, int]:
    """(index k, fraction r, shift sh): y = y_k + r 2^-sh ... exactly as the C does it."""
    n, fy = table.segment_bits, table.y_frac_bits
    whole = y_q >> fy
    if whole == 0:
        shift = fy - n
        return y_q >> shift, y_q & ((1 << shift) - 1), shift
    segment = whole.bit_length()  # 32 - CLZ(whole)
    shift = fy - n + segment - 1
    return ((segment - 1) << n) + (y_q >> shift), y_q & ((1 << shift) - 1), shift


def lookup(table: PsiTable, y_q: int) -> tuple[int, int]:
    """(psi1, psi2) in Q16 at y_q (Q fy): linear interpolation, rounded."""
    k, r, shift = locate(table, y_q)
    half = 1 << (shift - 1)
    out = []
    for column in (table.complement1, table.complement2):
        low, high = column[k], column[k + 1]
        out.append(ONE_Q16 - (low + (((high - low) * r + half) >> shift)))
    return out[0], out[1]


def error_at(table: PsiTable, y_value: float) -> tuple[float, float]:
    """Bound on |psi - interpolated table| at y (exact y), for psi1 and psi2.

    Interpolation remainder h^2/8 max|psi''| of y's segment (|psi''| is largest at the
    segment's left end) plus one Q16 unit for the entry and product roundings."""
    bounds = _second_derivative_bounds(table.segment_bits, table.segments)
    whole = int(y_value)
    segment = min(whole.bit_length(), table.segments - 1)
    h = step(segment, table.segment_bits)
    rounding = 1.0 / ONE_Q16
    m1, m2 = bounds[segment]
    return h * h / 8 * m1 + rounding, h * h / 8 * m2 + rounding


def interpolation_product_max(table: PsiTable) -> int:
    """Largest (c[k+1] - c[k]) r + 2^(sh-1) of any y the table covers (exact).

    Entry k lies in segment j = k // 2^n, whose fraction has sh = fy - n + max(j-1, 0)
    bits (see `locate`). The design keeps it in uint32 when it picks fy; the IR proof
    checks the printed arithmetic itself."""
    worst = 0
    per = 1 << table.segment_bits
    for k in range(table.entries - 1):
        shift = table.y_frac_bits - table.segment_bits + max(k // per - 1, 0)
        diff = max(
            table.complement1[k + 1] - table.complement1[k],
            table.complement2[k + 1] - table.complement2[k],
        )
        worst = max(worst, diff * ((1 << shift) - 1) + (1 << (shift - 1)))
    return worst

"""The integer rule's formats and constants (the arithmetic itself is the IR, `ir.py`).

Formats (Qf: value = integer / 2^f; all shifts of
non-negative values unless noted):

  bus rate, B clamped to [B_lo, B_hi]:
    xn = round(N_X / B)            uint32  N_X = round(K_X 2^fc), long division
    yn = round(N_Y / B)            uint32  N_Y = round(K_Y 2^(fc+gy)), long division
  edge, T clamped to [T_lo, T_hi], i = C - offset clamped to [0, i_max]:
    X   = round(xn / T)            Q fc    one UDIV
    Y   = round(yn i / 2^gy)       Q fc
    A   = round(X (KAPPA i) / 2^fk)           Q fc   (32x32->64 product)
    RHO = KRHO T                   Q frho  = rho
    S0  = 2P 2^fc + Y - X          Q fc    int32
    S1  = round(X THETA / 2^ft)    Q fc    theta X / 2
  bisection over x in Q K (x = 1 is 2^K), K steps, on the sign of 2 g(x); the unit
  functions are kept in Q fu, fu = min(K + 16, 30):
    y   = (RHO x) >> (frho + K - fy)          Q fy   (64-bit product)
    psi1, psi2 = 2^16 - interpolated complements          Q16 (table.lookup)
    e   = max(2^fu - round(y psi1 / 2^(fy+16-fu)), 0)   Q fu   e^{-y} = 1 - y psi1
          (64-bit product; the table's error can make y psi1 exceed 1 at large y, and
          e^{-y} > 0, hence the clamp: e stays in uint32 [0, 2^fu])
    u1  = x psi1 >> (K + 16 - fu)            Q fu   x psi1 (exact for K <= 14)
    v2  = round(x (x psi2) / 2^(2K+16-fu))   Q fu   x^2 psi2 (64-bit product)
    S   = S0 + round(S1 x / 2^K)             Q fc   int32
    C_on = clamp(S, 0, P 2^fc), C_off = clamp(S - P 2^fc, 0, P 2^fc)
    F2  = 4 C_off - 2 C_on - 2 P 2^fc + X    Q fc   int32 (2F)
    2g  = 2 A e + F2 u1 - X v2               Q(fc+fu) int64 (three 32x32->64 products)
  result: the last bracket [lo, hi], hi - lo = 1; x_c = (lo + hi) / 2^(K+1); if hi never
  moved and 2g(1) > 0 the commutation does not finish: x_c = 1, flagged.
    on  = round(clamp(S(x_c), 0, P 2^fc) / 2^fc), off likewise   TIM1 counts
    ticks = round(x_c T), at most the measured T                 Hall ticks
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from codegen.methods.improved_r.constants import RuleConstants
from codegen.methods.improved_r.table import PsiTable

UNIT_FRAC_BITS_MAX = 30
#: The ramp weight's fraction bits (theta/2 < 1/2): its rounding moves S1 by X 2^-ft.
THETA_FRAC_BITS = 20


@dataclass(frozen=True)
class LongDivision:
    """round(N / B) in two 32-bit divides: N = high 2^shift + low."""

    numerator: int
    shift: int
    high: int
    low: int


def long_division(numerator: int) -> LongDivision:
    shift = max(0, numerator.bit_length() - 32)
    return LongDivision(numerator, shift, numerator >> shift, numerator & ((1 << shift) - 1))


@dataclass(frozen=True)
class FixedRule:
    """Integer constants and formats of one spec's firmware rule."""

    constants: RuleConstants
    counts_frac_bits: int  # fc
    y_guard_bits: int  # gy
    kappa_frac_bits: int  # fk
    rho_frac_bits: int  # frho
    steps: int  # K: bisection steps, x in Q K
    n_x: LongDivision
    n_y: LongDivision
    kappa_q: int
    k_rho_q: int
    theta_half_q: int  # round(theta/2 2^ft)
    table: PsiTable

    @property
    def period_q(self) -> int:
        return self.constants.period_counts << self.counts_frac_bits

    @property
    def y_shift(self) -> int:
        return self.rho_frac_bits + self.steps - self.table.y_frac_bits

    @property
    def unit_frac_bits(self) -> int:
        """fu: e^{-y}, x psi1 and x^2 psi2 in Q fu."""
        return min(self.steps + 16, UNIT_FRAC_BITS_MAX)


def _round(value: sp.Expr) -> int:
    return int(sp.floor(value + sp.Rational(1, 2)))


def steps_for(c: RuleConstants) -> int:
    """K: the bisection's last bracket (2^-(K+1) of the sector) costs at most a quarter
    of the time target at the slowest speed and of the duty target through S1."""
    x_max = c.k_x / (c.period_low * c.bus_low)
    s1_max = c.ramp_weight * x_max / 2
    k = 1
    while (
        sp.Rational(c.period_high, 2 ** (k + 1)) > c.time_target_ticks / 4
        or s1_max / 2 ** (k + 1) > c.duty_target_counts / 4
    ):
        k += 1
    return k


def build_fixed_rule(
    c: RuleConstants, counts_frac_bits: int, table: PsiTable, steps: int
) -> FixedRule:
    """Integer constants for given formats; `design.design_rule` picks the formats."""
    fc = counts_frac_bits
    i_max = c.current_high
    y_guard = max(1, i_max.bit_length())
    kappa_bits = 0
    while _round(c.kappa * 2 ** (kappa_bits + 1)) * i_max < 2**31:
        kappa_bits += 1
    rho_bits = 0
    while _round(c.k_rho * 2 ** (rho_bits + 1)) * c.period_high < 2**32:
        rho_bits += 1
    return FixedRule(
        constants=c,
        counts_frac_bits=fc,
        y_guard_bits=y_guard,
        kappa_frac_bits=kappa_bits,
        rho_frac_bits=rho_bits,
        steps=steps,
        n_x=long_division(_round(c.k_x * 2**fc)),
        n_y=long_division(_round(c.k_y * 2 ** (fc + y_guard))),
        kappa_q=_round(c.kappa * 2**kappa_bits),
        k_rho_q=_round(c.k_rho * 2**rho_bits),
        theta_half_q=_round(c.ramp_weight / 2 * 2**THETA_FRAC_BITS),
        table=table,
    )

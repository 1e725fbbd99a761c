"""The integer rule in Python integers: the operations the generated improved_r core does.

The design and its proofs run on it; tests check that the generated C (and its twin)
agree with it bit for bit. Formats (Qf: value = integer / 2^f; all shifts of
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

from codegen.improved_r_rule.constants import RuleConstants
from codegen.improved_r_rule.reference import (
    FLAG_ABOVE_BUS,
    FLAG_CANNOT_HOLD,
    FLAG_NOT_FINISHED,
    RuleInputs,
    RuleOutputs,
    clamp_inputs,
)
from codegen.improved_r_rule.table import PsiTable, lookup

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


def divide_long(ld: LongDivision, divisor: int) -> int:
    """round(N / divisor) as the C does it: q_hi = high / B, then (r_hi 2^shift + low)/B."""
    q_high, r_high = divmod(ld.high, divisor)
    remainder = (r_high << ld.shift) | ld.low
    return (q_high << ld.shift) + (remainder + (divisor >> 1)) // divisor


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


@dataclass(frozen=True)
class EdgeState:
    """Per-edge quantities (all Q fc except rho)."""

    x: int
    y: int
    a: int
    rho: int
    s0: int
    s1: int


@dataclass(frozen=True)
class FixedResult:
    outputs: RuleOutputs
    state: EdgeState
    fraction_q: int  # x_c in Q(K + 1)
    total_q: int  # S(x_c) in Q fc


def _round_shift(value: int, shift: int) -> int:
    """round(value / 2^shift), halves up (add half, arithmetic shift); shift <= 0: exact."""
    return (value + (1 << (shift - 1))) >> shift if shift > 0 else value << -shift


def edge_state(rule: FixedRule, period: int, bus: int, current: int) -> EdgeState:
    fc = rule.counts_frac_bits
    xn = divide_long(rule.n_x, bus)
    yn = divide_long(rule.n_y, bus)
    x = (xn + (period >> 1)) // period
    y = _round_shift(yn * current, rule.y_guard_bits)
    a = _round_shift(x * (rule.kappa_q * current), rule.kappa_frac_bits)
    rho = rule.k_rho_q * period
    s0 = (2 * rule.constants.period_counts << fc) + y - x
    s1 = _round_shift(x * rule.theta_half_q, THETA_FRAC_BITS)
    return EdgeState(x, y, a, rho, s0, s1)


def duty_sum(rule: FixedRule, st: EdgeState, x_q: int, frac_bits: int) -> int:
    return st.s0 + _round_shift(st.s1 * x_q, frac_bits)


@dataclass(frozen=True)
class LoopTerms:
    """One evaluation of the bisection's test, every intermediate (for the range tests)."""

    y: int
    psi1: int
    psi2: int
    e: int
    u1: int
    v2: int
    total: int
    f2: int
    twice_g: int


def loop_terms(rule: FixedRule, st: EdgeState, x_q: int) -> LoopTerms:
    """2 g(x) in Q(fc + fu), the sign the bisection tests, and what it is made of."""
    k, fu = rule.steps, rule.unit_frac_bits
    y_q = (st.rho * x_q) >> rule.y_shift
    psi1, psi2 = lookup(rule.table, y_q)
    e = max((1 << fu) - _round_shift(y_q * psi1, rule.table.y_frac_bits + 16 - fu), 0)
    u1 = _round_shift(x_q * psi1, k + 16 - fu)
    v2 = _round_shift(x_q * (x_q * psi2), 2 * k + 16 - fu)
    total = duty_sum(rule, st, x_q, k)
    pq = rule.period_q
    on = min(max(total, 0), pq)
    off = min(max(total - pq, 0), pq)
    f2 = 4 * off - 2 * on - 2 * pq + st.x
    g2 = 2 * st.a * e + f2 * u1 - st.x * v2
    return LoopTerms(y_q, psi1, psi2, e, u1, v2, total, f2, g2)


def twice_g(rule: FixedRule, st: EdgeState, x_q: int) -> int:
    return loop_terms(rule, st, x_q).twice_g


def run_fixed(rule: FixedRule, inputs: RuleInputs) -> FixedResult:
    c = rule.constants
    clamped = clamp_inputs(c, inputs)
    st = edge_state(rule, clamped.period, clamped.bus, clamped.current)
    k = rule.steps
    lo, hi = 0, 1 << k
    for _ in range(k):
        mid = (lo + hi) >> 1
        if twice_g(rule, st, mid) > 0:
            lo = mid
        else:
            hi = mid
    flags = clamped.flags
    fraction = lo + hi  # Q(K + 1): the middle of the last bracket
    if hi == 1 << k and twice_g(rule, st, hi) > 0:
        fraction = 1 << (k + 1)
        flags |= FLAG_NOT_FINISHED
    total = duty_sum(rule, st, fraction, k + 1)
    pq = rule.period_q
    if total > 2 * pq:
        flags |= FLAG_CANNOT_HOLD
    if total < 0:
        flags |= FLAG_ABOVE_BUS
    fc = rule.counts_frac_bits
    on = _round_shift(min(max(total, 0), pq), fc)
    off = _round_shift(min(max(total - pq, 0), pq), fc)
    ticks = _round_shift(fraction * clamped.period, k + 1)
    outputs = RuleOutputs(on, off, min(ticks, inputs.period_ticks), flags)
    return FixedResult(outputs, st, fraction, total)


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

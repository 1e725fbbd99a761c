"""The integer rule's formats and constants (the arithmetic itself is the IR, `ir.py`).

Qf: value = integer / 2^f. fc is the counts' fraction bits; every quantity below is in
duty counts unless it says otherwise.

  bus rate, B clamped to [B_lo, B_hi]:
    xn = round(N_X / B)              N_X = round(K_X 2^fc)          long division
    yn = round(xn KYX / 2^sy)        Y per current unit, Q(fc + gy)
    ar = round(xn KAR / 2^sr)        A rho per current unit, Q(fc + ga)
  edge, T clamped to [T_lo, T_hi], i the offset-removed current clamped at 0:
    X   = round(xn / T)                          one UDIV
    W   = round(X 2^fw / T)                      X per tick, Q(fc + fw), two UDIVs
    Y   = round(yn i / 2^gy),  A rho = round(ar i / 2^ga)
    q   = round(W QC / 2^sq)     Q(fc + fq)      the EMF ramp's forcing over rho: -(phi_1/4) X / rho
    s   = round(W HS / 2^ss)     Q(fc + fs)      Sigma's growth per carrier period
    N   = floor(T / tau)                         whole carrier periods in the sector
    Sigma_0 = 2P + Y - (sigma_0/4) X,  cA = A rho - q - (phi_0/4) X,  cB = (phi_0/4) X + q
  search (binary lifting over m in [0, N], K = bit length of the largest N):
    e_m = e_n DECAY[k] >> 32        Q31, DECAY[k] = D^(2^k) in Q32
    Sigma_m = Sigma_0 + round(s m / 2^fs),  C_on, C_off the split, F_d = 2 C_off - C_on - P
    H_m = 2 (cA - F_d) e_m + (F_d + cB) 2^32 - q (Y1 m)      = 2^(32 + fc) rho g(x_m)
          Y1 = y_1 in Q(32 - fq); int64
    n = the largest m with H_m >= 0 (H_0 = A rho >= 0); the commutation ends at m = n + 1,
    or does not end within the sector's whole periods (n = N: TIME_CLAMPED)
  result: at m = n + 1, delta = -H / (3 (1 - e) 2^(32+fc)) in Q(min(6, fc)) (three UDIVs), at most the
  room min(C_on, P - C_off); C_on - delta, C_off + delta rounded to counts; ticks = round(m tau).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import mpmath
import sympy as sp

from codegen.methods.improved_r.constants import RuleConstants

#: delta's fraction bits (fewer where the counts have fewer: `FixedRule.delta_frac_bits`),
#: and the shift that brings 3 (1 - e) (Q31) under 2^24 (the divisor of the easing's
#: byte-wise long division: remainder 2^8 + a byte stays in 32 bits).
DELTA_FRAC_BITS = 6
E1_SHIFT = 9
#: W = X per tick: fraction bits beyond the counts' (W = round(X 2^fw / T), T 2^fw < 2^32).
PER_TICK_BITS = 15
_DIGITS = 50


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


def _round(value: sp.Expr) -> int:
    """round(value), half up: exact in integers where the value is a ratio of integers
    (never through `nsimplify`, which may trade a rational for a nearby simpler one:
    333333333333333333/10^18 becomes 1/3), else from 50 significant digits."""
    numerator, denominator = sp.fraction(sp.together(value))
    if numerator.is_Integer and denominator.is_Integer:
        n, d = int(numerator), int(denominator)
        if d < 0:
            n, d = -n, -d
        return (2 * n + d) // (2 * d)
    return int(sp.floor(sp.N(value, _DIGITS) + sp.Rational(1, 2)))


def _bits_for(value: sp.Expr, limit: int) -> int:
    """The most fraction bits f with round(value 2^f) < limit (value > 0)."""
    f = 0
    while _round(value * 2 ** (f + 1)) < limit:
        f += 1
    return f


@dataclass(frozen=True)
class FixedRule:
    """Integer constants and formats of one spec's firmware rule."""

    constants: RuleConstants
    counts_frac_bits: int  # fc
    y_guard_bits: int  # gy: yn = Y per current unit in Q(fc + gy)
    a_guard_bits: int  # ga: ar = A rho per current unit in Q(fc + ga)
    ramp_frac_bits: int  # fq: q in Q(fc + fq), Y1 = y_1 in Q(32 - fq)
    growth_frac_bits: int  # fs: s in Q(fc + fs)
    steps: int  # K: bits of the largest N
    n_x: LongDivision
    kyx: int  # yn = round(xn KYX / 2^sy)
    kyx_shift: int
    kar: int  # ar = round(xn KAR / 2^sr)
    kar_shift: int
    qc: int  # q = round(W QC / 2^sq)
    qc_shift: int
    hs: int  # s = round(W HS / 2^ss)
    hs_shift: int
    y1: int  # y_1 in Q(32 - fq)
    decay: tuple[int, ...]  # D^(2^k) in Q32, k = 0..K-1
    periods_num: int  # N = floor(T periods_num / periods_den)
    periods_den: int

    @property
    def period_q(self) -> int:
        return self.constants.period_counts << self.counts_frac_bits

    @property
    def delta_frac_bits(self) -> int:
        """The easing's fraction bits: Q6, or the counts' own where they have fewer (a
        motor whose X numerator leaves fewer than 6 bits, such as one at 5 kHz PWM)."""
        return min(DELTA_FRAC_BITS, self.counts_frac_bits)

    @property
    def periods_max(self) -> int:
        return self.constants.periods(self.constants.period_high)


def _decay_table(y1: sp.Rational, steps: int) -> tuple[int, ...]:
    with mpmath.workdps(_DIGITS):
        d = mpmath.exp(-mpmath.mpf(sp.N(y1, _DIGITS)))
        return tuple(int(mpmath.nint(d ** (2**k) * 2**32)) for k in range(steps))


def build_fixed_rule(
    c: RuleConstants, counts_frac_bits: int, ramp_frac_bits: int, growth_frac_bits: int
) -> FixedRule:
    """Integer constants for given formats; `design.design_rule` picks the formats."""
    fc = counts_frac_bits
    fq, fs = ramp_frac_bits, growth_frac_bits
    fw = PER_TICK_BITS
    m = c.current.scale
    i_max = max(c.current_high, 1)
    b_lo = c.bus_low
    # xn's largest value: K_X 2^fc / B_lo; the products below keep 64 bits
    xn_max = c.k_x * 2**fc / b_lo
    # yn: Y per current unit, Q(fc + gy), with yn i < 2^32
    y_per = c.k_y / b_lo * 2**fc  # counts Q fc per unit at the lowest bus
    gy = _bits_for(y_per, 2**32 // i_max) if y_per > 0 else 0
    # Y = K_Y i / B = (K_Y / K_X) i xn / 2^fc: yn = xn (K_Y/K_X) 2^gy
    kyx_shift = 64 - max(1, int(sp.ceiling(sp.log(xn_max, 2)))) - 1
    kyx = _round(c.k_y / c.k_x * 2 ** (gy + kyx_shift))
    while kyx >= 2**32:
        kyx_shift -= 1
        kyx = _round(c.k_y / c.k_x * 2 ** (gy + kyx_shift))
    # ar: A rho per unit, Q(fc + ga): A rho = kappa K_rho K_X i / B = kappa K_rho i xn / 2^fc
    ar_per = c.kappa * c.k_rho * c.k_x / b_lo * 2**fc
    ga = _bits_for(ar_per, 2**32 // i_max)
    kar_shift = kyx_shift
    kar = _round(c.kappa * c.k_rho * 2 ** (ga + kar_shift))
    while kar >= 2**32:
        kar_shift -= 1
        kar = _round(c.kappa * c.k_rho * 2 ** (ga + kar_shift))
    # q = (-phi_1/4) X / (K_rho T) = qc W 2^-fw with W = X 2^fw / T, Q(fc + fw)
    qc_value = c.ramp_per_x / c.k_rho
    qc_shift = 32
    qc = _round(qc_value * 2 ** (fq - fw + qc_shift)) if qc_value else 0
    while qc >= 2**32:
        qc_shift -= 1
        qc = _round(qc_value * 2 ** (fq - fw + qc_shift))
    # s = hold_slope X tau / T = hold_slope tau W 2^-fw, Q(fc + fs)
    hs_value = c.hold_slope * c.carrier_ticks
    hs_shift = 32
    hs = _round(hs_value * 2 ** (fs - fw + hs_shift)) if hs_value != 0 else 0
    while hs >= 2**32:
        hs_shift -= 1
        hs = _round(hs_value * 2 ** (fs - fw + hs_shift))
    y1 = _round(c.step_decay * 2 ** (32 - fq))
    n_max = c.periods(c.period_high)
    steps = max(1, n_max.bit_length())
    tau = sp.Rational(c.carrier_ticks)
    del xn_max, m
    return FixedRule(
        constants=c,
        counts_frac_bits=fc,
        y_guard_bits=gy,
        a_guard_bits=ga,
        ramp_frac_bits=fq,
        growth_frac_bits=fs,
        steps=steps,
        n_x=long_division(_round(c.k_x * 2**fc)),
        kyx=kyx,
        kyx_shift=kyx_shift,
        kar=kar,
        kar_shift=kar_shift,
        qc=qc,
        qc_shift=qc_shift,
        hs=hs,
        hs_shift=hs_shift,
        y1=y1,
        decay=_decay_table(c.step_decay, steps),
        periods_num=int(tau.q),
        periods_den=int(tau.p),
    )


def exact_decay(c: RuleConstants, periods: int) -> float:
    """e^-y_1 m in double precision (the reference's)."""
    return math.exp(-float(c.step_decay) * periods)

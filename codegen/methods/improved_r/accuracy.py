"""Pointwise error bounds of the integer rule against the real-arithmetic reference.

For one input (T, B, C) every integer quantity is within a known distance of its exact
value (roundings of the constants, of the divides and shifts, and of the decay table's
products): X, Y, A rho, q, the held sum's growth, e^-y_1 m. Together they bound
|h_int - rho g| <= eps_h (counts) at any grid point of the commutation. The binary
lifting keeps every m with h_int >= 0, so it finds the reference's end exactly where
the current is clearly on either side of zero at the two boundaries around it:

    rho g(end - 1) > eps_h  and  rho g(end) < -eps_h       (the end is decided)

Elsewhere the core may end one PWM period earlier or later (there the current is
within eps_h / rho counts of zero at a boundary: the time is ill-conditioned and the
verifier's declared relaxation applies). Where the end is decided, the time is
round(end tau) exactly, and the duties are within

    |C - C_exact| <= 1/2 + eps_Sigma + eps_delta,
    eps_delta = eps_h / (3 (1 - e)) + |delta| eps_rel(1 - e) + 2^-min(6, fc) (the easing's format)

(1/2 the final rounding; the clamps move a duty by no more than their operand).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from codegen.methods.improved_r.fixed import (
    E1_SHIFT,
    PER_TICK_BITS,
    FixedRule,
)
from codegen.methods.improved_r.reference import FLAG_NOT_FINISHED, ReferenceBatch

FloatArray = npt.NDArray[np.float64]


@dataclass(frozen=True)
class Bounds:
    """Per point: the bound on |h_int - rho g| (counts), whether the end is decided,
    and the duty and time bounds there."""

    eps_h: FloatArray
    decided: npt.NDArray[np.bool_]
    duty_counts: FloatArray
    ticks: FloatArray


def bounds(rule: FixedRule, ref: ReferenceBatch) -> Bounds:
    c = rule.constants
    fc = rule.counts_frac_bits
    lsb = 2.0**-fc
    t = ref.period.astype(np.float64)
    i = ref.current
    xn = float(c.k_x) * 2**fc / ref.bus
    x = ref.x
    # X = round(xn / T), xn = round(N_X / B): 1/2 + (1 LSB of xn) / T
    eps_x = lsb * (0.5 + 1.0 / t)
    rel_xn = 1.0 / xn
    eps_y = ref.y * (rel_xn + 0.5 / max(rule.kyx, 1)) + lsb * (0.5 + 0.5 * i / 2**rule.y_guard_bits)
    eps_a = ref.a_rho * (rel_xn + 0.5 / max(rule.kar, 1)) + lsb * (
        0.5 + 0.5 * i / 2**rule.a_guard_bits
    )
    per_tick = x / t * 2 ** (fc + PER_TICK_BITS)
    rel_w = eps_x / np.maximum(x, lsb) + 0.5 / np.maximum(per_tick, 1.0)
    q = float(c.ramp_per_x) * x / ref.rho
    eps_q = q * (rel_w + (0.5 / rule.qc if rule.qc else 0.0)) + 2.0 ** -(fc + rule.ramp_frac_bits)
    growth = float(c.hold_slope * c.carrier_ticks) * x / t
    eps_growth = growth * (rel_w + (0.5 / rule.hs if rule.hs else 0.0)) + 2.0 ** -(
        fc + rule.growth_frac_bits
    )  # floored
    m = ref.end.astype(np.float64)
    sum0, force0 = float(c.shape.sum0), float(c.shape.force0)
    eps_sigma = eps_y + sum0 / 4 * eps_x + m * eps_growth + lsb  # the growth is floored
    eps_fd = 2 * eps_sigma
    eps_force0 = force0 / 4 * eps_x + 0.5 * lsb
    eps_q_counts = eps_q + 0.5 * lsb  # q rounded to counts in the coefficients
    steps = rule.steps
    eps_e = steps * 1.25 * 2.0**-31
    y1 = float(c.step_decay)
    ym = y1 * m
    eps_ym = m * 0.5 * 2.0 ** -(32 - rule.ramp_frac_bits)
    e = np.exp(-ym)
    # h = A rho e + (F_d + (phi_0/4) X + q)(1 - e) - q y_1 m: the integer coefficients
    # 2 (A rho - q - F_0) and F_0 + q share F_d, phi_0 X/4 and q, so their errors enter
    # multiplied by 1 - e; |A rho - q - F_0| multiplies the decay's error
    c_abs = ref.a_rho + q + force0 / 4 * x + 2 * c.period_counts
    eps_h = (
        eps_a * e
        + (eps_fd + eps_force0 + eps_q_counts) * (1 - e)
        + c_abs * eps_e
        + eps_q * ym
        + q * eps_ym
    )
    eps_h = 1.001 * eps_h + 2.0 ** -(32 + fc)  # the sign test's unit
    finished = (ref.flags & FLAG_NOT_FINISHED) == 0
    decided = np.where(
        finished,
        (ref.h_before > eps_h) & (ref.h_end < -eps_h),
        ref.h_end > eps_h,  # not finished: the current clearly remains at the last boundary
    )
    shortfall = ref.shortfall
    e1 = shortfall / 3
    with np.errstate(divide="ignore", invalid="ignore"):
        rel_shortfall = (2.0 ** (E1_SHIFT - 31) + eps_e) / np.maximum(e1, 1e-300)
        eps_delta = np.where(
            finished,
            eps_h / np.maximum(shortfall, 1e-300)
            + np.abs(ref.delta) * rel_shortfall
            + 2.0**-rule.delta_frac_bits,
            0.0,
        )
    duty = 0.5 + eps_sigma + eps_delta
    tau = c.carrier_ticks
    rounding = 0.0 if tau.q == 1 else 0.5
    ticks = np.where(finished, rounding, 0.0)
    return Bounds(eps_h, decided, duty, ticks)

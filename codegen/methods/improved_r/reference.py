"""The firmware rule in real arithmetic: what the integer rule approximates.

From the integer inputs (Hall period T, bus code B, current code C) and the exact spec
constants, in duty counts and fractions x of the sector:

1. clamp T to the speed range and B to the bus range (flagged), i = C - offset
   clamped to [0, ADC full scale];
2. X = K_X/(T B), Y = K_Y i/B, A = kappa i X, rho = K_rho T; the carrier grid
   x_m = m tau / T, m = 0..N, N = floor(L(T) / tau), L(T) = floor(T (2^k - 1) / 2^k) - G
   the latest end: the guard G and the sector-shortening margin a commutation ends by
   before its sector does (`codegen.dead_time`);
3. the held duty sum for a commutation of x sectors, Sigma(x) = 2P + Y - (X/4) mu(x),
   mu(x) = sigma_0 + sigma_1 theta x (the minimax constant of the EMF's sigma over
   [0, x]); split as the paper does: C_on = clamp(Sigma, 0, P), C_off = clamp(Sigma - P, 0, P);
4. the turn-off current in counts under that pair and the spec's EMF,
   g(x) = A e^{-rho x} + F_0 x psi1(rho x) + (X/4) phi_1 x^2/2 psi2(rho x),
   F_0 = 2 C_off - C_on - P + (X/4) phi_0;
5. the end: the first grid point m >= 1 with g(x_m) < 0 (the current has reached zero),
   or none by m = N (flagged; the pair held at x_N, uneased, the time the whole sector
   less G);
6. the easing delta = -g / (3 x psi1(rho x)) at the end, at most min(C_on, P - C_off):
   C_on - delta, C_off + delta end the current exactly on the boundary;
7. outputs: the eased pair rounded to counts, round(m tau) ticks.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from codegen.methods.improved_r.constants import RuleConstants

FLAG_SPEED_CLAMPED = 0x01  # T outside the spec's speed range: the rule used the nearest end
FLAG_BUS_CLAMPED = 0x02  # B outside the spec's bus range
FLAG_NOT_FINISHED = 0x04  # the current does not reach zero by the sector's last whole period
FLAG_CANNOT_HOLD = 0x08  # Sigma > 2P: even D_on = D_off = 1 lets the current sag
FLAG_ABOVE_BUS = 0x10  # Sigma < 0: even D_on = 0 lets the current swell (E near U_d/2)
FLAG_NAMES = {
    FLAG_SPEED_CLAMPED: "speed_clamped",
    FLAG_BUS_CLAMPED: "bus_clamped",
    FLAG_NOT_FINISHED: "not_finished",
    FLAG_CANNOT_HOLD: "cannot_hold",
    FLAG_ABOVE_BUS: "above_bus",
}
#: Below this y the psi-free forms are summed from their series (no cancellation).
SERIES_BELOW = 1e-3

FloatArray = npt.NDArray[np.float64]
IntArray = npt.NDArray[np.int64]


@dataclass(frozen=True)
class RuleInputs:
    period_ticks: int  # T, Hall timer ticks of the last 60 deg
    bus_code: int  # B
    current_code: int  # C, with the sensor offset


@dataclass(frozen=True)
class RuleOutputs:
    on_counts: int
    off_counts: int
    commutation_ticks: int
    flags: int


@dataclass(frozen=True)
class ReferenceBatch:
    """The rule over arrays of inputs (one element per input point)."""

    period: IntArray  # T after clamping
    bus: IntArray
    current: FloatArray  # offset removed, clamped, 1/m codes
    periods: IntArray  # N
    end: IntArray  # m of the end (N when not finished)
    total: FloatArray  # Sigma at the end (at x_N when the current remains)
    on_held: FloatArray  # the split of Sigma before the easing
    off_held: FloatArray
    delta: FloatArray  # the easing (0 when not finished)
    on_exact: FloatArray  # the eased pair, counts
    off_exact: FloatArray
    ticks_exact: FloatArray  # end tau (the sector when not finished)
    flags: IntArray
    #: rho g at the end and one carrier period before it (how clearly the end is decided)
    h_end: FloatArray
    h_before: FloatArray
    shortfall: FloatArray  # 3 (1 - e^-rho x) at the end: delta = -h_end / shortfall
    x: FloatArray
    y: FloatArray
    a_rho: FloatArray
    rho: FloatArray

    def outputs(self, k: int, latest: int) -> RuleOutputs:
        """Point k's outputs, the time at most `latest` (the measured period less the
        guard)."""
        return RuleOutputs(
            on_counts=round(float(self.on_exact[k])),
            off_counts=round(float(self.off_exact[k])),
            commutation_ticks=min(math.floor(float(self.ticks_exact[k]) + 0.5), latest),
            flags=int(self.flags[k]),
        )


def _split(p: int, total: FloatArray) -> tuple[FloatArray, FloatArray]:
    return np.clip(total, 0.0, p), np.clip(total - p, 0.0, p)


def decay_terms(y: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
    """(e^-y, 1 - e^-y, y - 1 + e^-y) without cancellation at small y."""
    e1 = -np.expm1(-y)
    small = y < SERIES_BELOW
    e2 = np.where(small, y * y / 2 - y**3 / 6 + y**4 / 24, y - e1)
    return 1.0 - e1, e1, e2


@dataclass(frozen=True)
class _Edge:
    c: RuleConstants
    x: FloatArray
    y: FloatArray
    a_rho: FloatArray
    rho: FloatArray
    period: IntArray

    def total(self, fraction: FloatArray) -> FloatArray:
        c = self.c
        mu = float(c.shape.sum0) + float(c.shape.sum1) * float(c.ramp_weight) * fraction
        return 2 * c.period_counts + self.y - self.x / 4 * mu

    def current(self, m: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
        """(rho g, the held sum, 3 (1 - e)) at grid point m (whole PWM periods)."""
        c = self.c
        yy = float(c.step_decay) * m
        e, e1, e2 = decay_terms(yy)
        total = self.total(m * float(c.carrier_ticks) / self.period)
        on, off = _split(c.period_counts, total)
        f0 = 2 * off - on - c.period_counts + self.x / 4 * float(c.shape.force0)
        ramp = self.x / 4 * float(c.shape.force1) / self.rho
        return self.a_rho * e + f0 * e1 + ramp * e2, total, 3 * e1


def reference_batch(
    c: RuleConstants, periods: npt.ArrayLike, buses: npt.ArrayLike, current_codes: npt.ArrayLike
) -> ReferenceBatch:
    """The rule at every (T, B, C) given (broadcast), clamped as the core does."""
    t_in, b_in, c_in = np.broadcast_arrays(
        *(np.atleast_1d(np.asarray(v, dtype=np.int64)) for v in (periods, buses, current_codes))
    )
    t = np.clip(t_in, c.period_low, c.period_high)
    b = np.clip(b_in, c.bus_low, c.bus_high)
    m_scale, offset = c.current.scale, float(c.current.offset_exact)
    i = np.clip(m_scale * (np.minimum(c_in, c.adc_max) - offset), 0.0, float(c.current_high))
    flags = np.where(t != t_in, FLAG_SPEED_CLAMPED, 0) | np.where(b != b_in, FLAG_BUS_CLAMPED, 0)
    p = c.period_counts
    x = float(c.k_x) / (t.astype(np.float64) * b)
    y = float(c.k_y) * i / b
    a_rho = float(c.kappa) * float(c.k_rho) * float(c.k_x) * i / b
    rho = float(c.k_rho) * t
    edge = _Edge(c, x, y, a_rho, rho, t)
    tau = c.carrier_ticks
    periods = np.floor(c.latest_end(t) * int(tau.q) / int(tau.p)).astype(np.int64)
    # binary lifting over the grid: n = the last m with rho g >= 0
    n = np.zeros_like(periods)
    steps = int(periods.max()).bit_length()
    for k in range(steps - 1, -1, -1):
        m = n + (1 << k)
        ok = m <= periods
        h, _, _ = edge.current(np.minimum(m, periods).astype(np.float64))
        n = np.where(ok & (h >= 0), m, n)
    finished = n < periods
    end = np.where(finished, n + 1, periods)
    h_end, total_end, shortfall = edge.current(end.astype(np.float64))
    h_before, _, _ = edge.current(np.maximum(end - 1, 0).astype(np.float64))
    total = total_end
    on0, off0 = _split(p, total)
    room = np.minimum(on0, p - off0)
    with np.errstate(divide="ignore", invalid="ignore"):
        eased = np.where(shortfall > 0, -h_end / shortfall, 0.0)
    delta = np.where(finished, np.clip(eased, 0.0, room), 0.0)
    ticks = np.where(finished, end * float(tau), c.latest_end(t).astype(np.float64))
    flags |= np.where(finished, 0, FLAG_NOT_FINISHED)
    flags |= np.where(total > 2 * p, FLAG_CANNOT_HOLD, 0) | np.where(total < 0, FLAG_ABOVE_BUS, 0)
    return ReferenceBatch(
        period=t,
        bus=b,
        current=i,
        periods=periods,
        end=end,
        total=total,
        on_held=on0,
        off_held=off0,
        delta=delta,
        on_exact=on0 - delta,
        off_exact=off0 + delta,
        ticks_exact=ticks,
        flags=flags,
        h_end=h_end,
        h_before=h_before,
        shortfall=shortfall,
        x=x,
        y=y,
        a_rho=a_rho,
        rho=rho,
    )


def reference_points(c: RuleConstants, points: Sequence[RuleInputs]) -> ReferenceBatch:
    return reference_batch(
        c,
        [q.period_ticks for q in points],
        [q.bus_code for q in points],
        [q.current_code for q in points],
    )


def reference(c: RuleConstants, inputs: RuleInputs) -> RuleOutputs:
    batch = reference_points(c, [inputs])
    return batch.outputs(0, c.latest_end(min(inputs.period_ticks, 2**31)))


def decay(c: RuleConstants, periods: int) -> float:
    return math.exp(-float(c.step_decay) * periods)

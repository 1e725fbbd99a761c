"""The resistance-aware rule (method improved_r) in real arithmetic, written from its
definition (README, "The resistance-aware core"), not from the generator.

For one commutation, with T_s the sector time, E = k_e n, U_d, I >= 0, R, L, P the PWM
period in counts, and the spec's EMF per unit E along the sector x = t / T_s as
sigma(x) = (2 e_a - e_b - e_c)/E and phi(x) = (e_a - 2 e_b + e_c)/E (`oracle.emf_shape`):

  X = 4 P E / U_d,  Y = 3 P R I / U_d,  A = 3 P L I / (U_d T_s),  rho = R T_s / L
  Sigma(x) = 2P + Y - (X/4) mu(x)        mu(x): the minimax constant of sigma over [0, x]
  C_on = clamp(Sigma, 0, P), C_off = clamp(Sigma - P, 0, P)
  g(x) = A e^{-rho x} + (2 C_off - C_on - P) x psi1(rho x) + (X/4) int_0^x phi(s) e^{-rho (x - s)} ds
  psi1(y) = (1 - e^{-y})/y,  psi2(y) = 2 (y - 1 + e^{-y})/y^2

g is the turn-off phase's current (in counts) after x sectors under the pair held at
Sigma(x). Its zero z (g(0) = A >= 0, one sign change) is where the current reaches zero.
The commutation ends on a carrier boundary x_m = m tau / T_s (tau = one PWM period,
where the port restarts the carrier): the first one after z, m = floor(z T_s / tau) + 1,
if m <= N = floor((T_s - G) / tau), G the guard a commutation ends by before its sector
does (`oracle.units`); there the pair is eased so the current ends exactly on it,
C_on - delta, C_off + delta with delta = -g(x_m) / (3 x_m psi1(rho x_m)) clamped to
[0, min(C_on, P - C_off)]. If the current remains at x_N the commutation does not end
within the sector: the pair at Sigma(x_N), uneased, for the whole sector less G.

`shift` adds a number of counts to g (the change a duty error of that many counts held
over one sector makes): the verifier asks which ends an error of that size would give.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np
import numpy.typing as npt

from oracle.emf_shape import EdgeEmf

Floats = npt.NDArray[np.float64]
Ints = npt.NDArray[np.int64]
Bools = npt.NDArray[np.bool_]

THETA = math.sqrt(2.0) - 1.0
#: `zero` narrows each bracket to this width in Hall ticks (the verifier's time
#: tolerances are whole ticks; 56 bisection steps had narrowed it to 2^-56 of a sector,
#: about 1e-12 ticks at the counter's longest period)
ZERO_WIDTH_TICKS = 1e-9
#: a bound on `zero`'s steps: a bisection at least every other step halves the bracket,
#: so about 2 x 46 steps reach ZERO_WIDTH_TICKS at the 16-bit counter's longest period
ZERO_STEPS_MAX = 200
SERIES_BELOW = 1e-2


def psi(y: Floats) -> tuple[Floats, Floats]:
    """(psi1, psi2) elementwise; Taylor series below 0.01 (no cancellation), evaluated
    on those elements only (the bisection of `zero` calls this dozens of times a point)."""
    y = np.asarray(y)
    small = y < SERIES_BELOW
    z = np.where(small, 1.0, y)
    em1 = np.expm1(-z)  # e^{-y} - 1
    psi1 = -em1 / z
    psi2 = 2.0 * (z + em1) / (z * z)
    if np.ndim(psi1) == 0:  # one value: as an array, so that the series can go in
        psi1, psi2 = np.asarray(psi1), np.asarray(psi2)
    if small.any():
        s = y[small]
        psi1[small] = 1 - s / 2 + s**2 / 6 - s**3 / 24 + s**4 / 120
        psi2[small] = 1 - s / 3 + s**2 / 12 - s**3 / 60 + s**4 / 360
    return psi1, psi2


@dataclass(frozen=True)
class Pair:
    """A commutation's outcome at a given end: the held sum, the pair before and after
    the easing, and the current there."""

    total: Floats
    on_held: Floats
    off_held: Floats
    on: Floats
    off: Floats
    current: Floats  # g at the end, counts


@dataclass(frozen=True)
class Commutation:
    """The rule's quantities at each point (counts, sectors)."""

    x: Floats  # X
    y: Floats  # Y
    a: Floats  # A
    rho: Floats
    p: int
    emf: EdgeEmf
    sector_ticks: Floats  # T_s in Hall ticks
    carrier_ticks: float  # tau
    #: L(T): the latest end, the guard and the sector-shortening margin before the
    #: sector's end (`oracle.units.Units.latest_end`), Hall ticks
    latest_ticks: Floats

    def duty_sum(self, fraction: Floats) -> Floats:
        return 2 * self.p + self.y - self.x / 4 * self.emf.hold(fraction)

    def split(self, total: Floats) -> tuple[Floats, Floats]:
        return np.clip(total, 0, self.p), np.clip(total - self.p, 0, self.p)

    def current(self, fraction: Floats, shift: float = 0.0, total: Floats | None = None) -> Floats:
        """g at x = fraction under the pair held at Sigma(fraction) (or at `total`)."""
        on, off = self.split(self.duty_sum(fraction) if total is None else total)
        f0, slope, corners = self.emf.forcing_terms()
        y = self.rho * fraction
        p1, p2 = psi(y)
        ramp = f0 * fraction * p1 + slope * fraction**2 / 2 * p2
        for at, change in corners:
            late = np.maximum(fraction - at, 0.0)
            _, q2 = psi(self.rho * late)
            ramp = ramp + change * late**2 / 2 * q2
        driven = (2 * off - on - self.p) * fraction * p1
        return self.a * np.exp(-y) + driven + self.x / 4 * ramp + shift

    def take(self, index: Ints) -> Commutation:
        """The quantities of a subset of the points (repeated as indexed)."""
        return replace(
            self,
            x=self.x[index],
            y=self.y[index],
            a=self.a[index],
            rho=self.rho[index],
            sector_ticks=self.sector_ticks[index],
            latest_ticks=self.latest_ticks[index],
        )

    def zero(self, shift: float = 0.0) -> tuple[Floats, Bools]:
        """z, the zero of g in (0, 1] (1 where the current does not reach zero), and
        that flag.

        The bracket [lo, hi] starts at [0, 1] with g(hi) <= 0 and, once g(lo) > 0, is
        narrowed by false position with the Illinois halving (superlinear on a smooth
        g), by bisection where the bracket did not halve over the last two steps or g(lo)
        is not yet above zero (g(0) = A may be 0: the bisection then finds where the
        EMF's forcing lifts g, as before); each point stops when its bracket is
        ZERO_WIDTH_TICKS wide, and only the points still open are evaluated: 12 to 30
        evaluations a point (the most where a zero current leaves g(0) = 0) where 56
        bisection steps took 56. Only the sign of g moves the bracket, so the false
        position picks points but never decides the zero (on 200 000 random points of
        each of seven improved_r motors at six shifts: within 2.2e-9 ticks of the
        bisection's zero; a carrier-boundary end differs only where the zero lies that
        close to a boundary, 22 of 100 000 points on a 40 kHz motor, inside the window
        of ends the verifier allows)."""
        ones = np.ones_like(self.x)
        g_one = self.current(ones, shift)
        unfinished = g_one > 0
        g_zero = self.current(np.zeros_like(self.x), shift)
        z = np.ones_like(self.x)
        index = np.flatnonzero(~unfinished)
        n = index.size
        # the open points' state, filtered together as points close
        st = {
            "lo": np.zeros(n),
            "hi": np.ones(n),
            "g_lo": g_zero[index],
            "g_hi": g_one[index],
            "side": np.zeros(n, dtype=np.int8),  # the end the last step moved: +1 lo, -1 hi
            "width_back": np.full(n, 2.0),  # the bracket's width two steps back
            "width_last": np.full(n, 2.0),  # and one step back
            "tolerance": ZERO_WIDTH_TICKS / np.maximum(self.sector_ticks[index], 1.0),
        }
        open_ = self.take(index)
        for _ in range(ZERO_STEPS_MAX):
            if index.size == 0:
                break
            lo, hi, g_lo, g_hi = st["lo"], st["hi"], st["g_lo"], st["g_hi"]
            width = hi - lo
            with np.errstate(divide="ignore", invalid="ignore"):
                secant = (lo * g_hi - hi * g_lo) / (g_hi - g_lo)
            # g(lo) > 0 >= g(hi) once lo has moved (or g(0) > 0): false position may step
            step = (g_lo > 0) & (width <= 0.5 * st["width_back"]) & (secant > lo) & (secant < hi)
            c = np.where(step, secant, 0.5 * (lo + hi))
            stuck = (c == lo) | (c == hi)  # the bracket is as narrow as floats make it
            g = open_.current(c, shift)
            above = g > 0
            # Illinois: the end kept twice running has its value halved
            g_hi = np.where(above & (st["side"] > 0), 0.5 * g_hi, g_hi)
            g_lo = np.where(~above & (st["side"] < 0), 0.5 * g_lo, g_lo)
            st.update(
                lo=np.where(above, c, lo),
                g_lo=np.where(above, g, g_lo),
                hi=np.where(above, hi, c),
                g_hi=np.where(above, g_hi, g),
                side=np.where(above, 1, -1).astype(np.int8),
                width_back=st["width_last"],
                width_last=width,
            )
            done = ((st["hi"] - st["lo"]) <= st["tolerance"]) | stuck
            if done.any():
                z[index[done]] = 0.5 * (st["lo"][done] + st["hi"][done])
                keep = np.flatnonzero(~done)
                index, open_ = index[keep], open_.take(keep)
                st = {key: value[keep] for key, value in st.items()}
        z[index] = 0.5 * (st["lo"] + st["hi"])
        return z, unfinished

    @property
    def periods(self) -> Ints:
        """N: whole carrier periods in the sector, less the guard and the margin at its end."""
        usable = self.latest_ticks
        return np.floor(usable / self.carrier_ticks + 1e-9).astype(np.int64)

    def end_after(self, ticks: Floats) -> Ints:
        """The carrier boundary m that ends a commutation whose current reaches zero at
        `ticks`: the first one after it (N + 1: none within the sector)."""
        m = np.floor(ticks / self.carrier_ticks).astype(np.int64) + 1
        return np.minimum(np.maximum(m, 1), self.periods + 1)

    def pair_at(self, end: Ints) -> Pair:
        """The outcome when the commutation ends at boundary `end` (N + 1: it does not
        end within the sector; the pair at x_N, uneased)."""
        n = self.periods
        finished = end <= n
        m = np.minimum(end, n).astype(np.float64)
        fraction = m * self.carrier_ticks / self.sector_ticks
        total = self.duty_sum(fraction)
        on0, off0 = self.split(total)
        g = self.current(fraction, total=total)
        p1, _ = psi(self.rho * fraction)
        with np.errstate(divide="ignore", invalid="ignore"):
            eased = np.where(fraction > 0, -g / (3 * fraction * p1), 0.0)
        room = np.minimum(on0, self.p - off0)
        delta = np.where(finished, np.clip(eased, 0.0, room), 0.0)
        return Pair(total, on0, off0, on0 - delta, off0 + delta, g)


def commutation(
    p: int,
    emf_volts: Floats,
    u_d: Floats,
    amps: Floats,
    sector_s: Floats,
    resistance: float,
    inductance: float,
    shape: EdgeEmf,
    hall_hz: float,
    carrier_ticks: float,
    latest_ticks: Floats,
) -> Commutation:
    x = 4 * p * emf_volts / u_d
    y = 3 * p * resistance * amps / u_d
    a = 3 * p * inductance * amps / (u_d * sector_s)
    rho = resistance * sector_s / inductance
    return Commutation(x, y, a, rho, p, shape, sector_s * hall_hz, carrier_ticks, latest_ticks)

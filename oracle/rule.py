"""The resistance-aware rule (method improved_r) in real arithmetic, written from its
definition (README, "The resistance-aware core"), not from the generator.

For one commutation, with T_s the sector time, E = k_e n, U_d, I >= 0, R, L, and P the
PWM period in counts:

  X = 4 P E / U_d,  Y = 3 P R I / U_d,  A = 3 P L I / (U_d T_s),  rho = R T_s / L
  S(x) = 2P + Y - X + theta X x / 2           theta = sqrt(2) - 1, x in sectors
  C_on = clamp(S, 0, P), C_off = clamp(S - P, 0, P), F = 2 C_off - C_on - P + X/2
  g(x) = A e^{-rho x} + F x psi1(rho x) - X x^2/2 psi2(rho x)
  psi1(y) = (1 - e^{-y})/y,  psi2(y) = 2 (y - 1 + e^{-y})/y^2

g is the turn-off phase's current (in counts) under the pair held at S(x); the
commutation time is its zero x_c in (0, 1] (g(0) = A >= 0 and g falls through zero
once), or the whole sector when g(1) > 0. `shift` adds a number of counts to g (the
change a duty error of that many counts held over one sector makes): the verifier asks
which commutation times an error of that size would give, and how far one count
moves the zero (the conditioning of t_com).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

Floats = npt.NDArray[np.float64]

THETA = math.sqrt(2.0) - 1.0
BISECTION_STEPS = 56
SERIES_BELOW = 1e-2


def psi(y: Floats) -> tuple[Floats, Floats]:
    """(psi1, psi2) elementwise; Taylor series below 0.01 (no cancellation)."""
    small = y < SERIES_BELOW
    z = np.where(small, 1.0, y)
    em1 = np.expm1(-z)  # e^{-y} - 1
    closed1 = -em1 / z
    closed2 = 2.0 * (z + em1) / (z * z)
    s1 = 1 - y / 2 + y**2 / 6 - y**3 / 24 + y**4 / 120
    s2 = 1 - y / 3 + y**2 / 12 - y**3 / 60 + y**4 / 360
    return np.where(small, s1, closed1), np.where(small, s2, closed2)


@dataclass(frozen=True)
class Commutation:
    """The rule's quantities at each point (counts, sectors)."""

    x: Floats  # X
    base: Floats  # 2P + Y - X
    a: Floats  # A
    rho: Floats
    p: int

    def duty_sum(self, fraction: Floats) -> Floats:
        return self.base + THETA * self.x * fraction / 2

    def split(self, total: Floats) -> tuple[Floats, Floats]:
        return np.clip(total, 0, self.p), np.clip(total - self.p, 0, self.p)

    def current(self, fraction: Floats, shift: float = 0.0) -> Floats:
        on, off = self.split(self.duty_sum(fraction))
        forcing = 2 * off - on - self.p + self.x / 2
        y = self.rho * fraction
        p1, p2 = psi(y)
        return self.a * np.exp(-y) + forcing * fraction * p1 - self.x * fraction**2 / 2 * p2 + shift

    def zero(self, shift: float = 0.0) -> tuple[Floats, npt.NDArray[np.bool_]]:
        """x_c (1 where the current does not reach zero) and that flag."""
        ones = np.ones_like(self.x)
        unfinished = self.current(ones, shift) > 0
        lo, hi = np.zeros_like(self.x), ones
        for _ in range(BISECTION_STEPS):
            mid = 0.5 * (lo + hi)
            above = self.current(mid, shift) > 0
            lo, hi = np.where(above, mid, lo), np.where(above, hi, mid)
        return np.where(unfinished, 1.0, 0.5 * (lo + hi)), unfinished


def commutation(
    p: int,
    emf: Floats,
    u_d: Floats,
    amps: Floats,
    sector_s: Floats,
    resistance: float,
    inductance: float,
) -> Commutation:
    x = 4 * p * emf / u_d
    y = 3 * p * resistance * amps / u_d
    a = 3 * p * inductance * amps / (u_d * sector_s)
    rho = resistance * sector_s / inductance
    return Commutation(x, 2 * p + y - x, a, rho, p)

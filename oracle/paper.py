"""The paper's equations at the firmware's inputs, written out by hand.

With E = k_e n (Eq. 3, per-phase flat-top EMF) and U_d the bus voltage:

  Eq. 18 (improved)   4E <= U_d: D_on = 1, D_off = 1 - 4E/U_d
                      4E >  U_d: D_on = 2 - 4E/U_d, D_off = 0
  Eq. 16 (conventional) D_on = M, D_off = 2 - M - 4E/U_d  (fail area: outside [0, 1])
  none                D_on = M, D_off = 0
  Eq. 20              t_com = 3 I L / (U_d (1 + D_on - 2 D_off) - 2E)

(Eq. 20 as derived from Eq. 19 with the corrected signs; the audit shows the printed
one.) Duties are clamped to [0, 1] as a duty must be. Values are float64 arrays, far
below one LSB of error; the two decisions (segment, fail area) are exact: float first,
then exact rationals wherever the float margin is within 1e-9 of the threshold.
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction

import numpy as np
import numpy.typing as npt

from oracle.units import Units

Floats = npt.NDArray[np.float64]
Ints = npt.NDArray[np.int64]
Bools = npt.NDArray[np.bool_]

TIE = 1e-9


@dataclass(frozen=True)
class Motor:
    k_e: Fraction  # V per rpm, per-phase flat top
    inductance: Fraction  # H, per phase


def emf(u: Units, m: Motor, period: Ints) -> Floats:
    return float(m.k_e * 60 * u.hall_hz / (6 * u.pole_pairs)) / period.astype(np.float64)


def bus_volts(u: Units, bus: Ints) -> Floats:
    return float(u.volts_per_code) * bus.astype(np.float64)


def _exact_fix(ratio: Floats, exact: object, *args: Ints) -> Bools:
    """ratio > 1, with ties (|ratio - 1| < TIE) decided by exact(*scalars)."""
    out = ratio > 1.0
    for k in np.flatnonzero(np.abs(ratio - 1.0) < TIE):
        out[k] = exact(*(int(a[k]) for a in args))  # type: ignore[operator]
    return out


def high_speed(u: Units, m: Motor, period: Ints, bus: Ints) -> Bools:
    """Eq. 18's high-speed segment: 4E > U_d."""
    ratio = 4 * emf(u, m, period) / bus_volts(u, bus)

    def exact(t: int, b: int) -> bool:
        return 4 * m.k_e * u.rpm(t) > u.volts(b)

    return _exact_fix(ratio, exact, period, bus)


def improved_duties(u: Units, m: Motor, period: Ints, bus: Ints) -> tuple[Floats, Floats, Bools]:
    """Eq. 18 in counts, clamped to [0, P], and the segment."""
    x = 4 * emf(u, m, period) / bus_volts(u, bus)
    high = high_speed(u, m, period, bus)
    on = np.where(high, 2 - x, 1.0)
    off = np.where(high, 0.0, 1 - x)
    p = u.pwm_counts
    return np.clip(on, 0, 1) * p, np.clip(off, 0, 1) * p, high


def conventional_duties(
    u: Units, m: Motor, period: Ints, bus: Ints, main: Ints
) -> tuple[Floats, Floats, Bools]:
    """Eq. 16 in counts (D_on = M saturated at 1), clamped, and the fail area."""
    p = u.pwm_counts
    on = np.minimum(main, p).astype(np.float64) / p
    x = 4 * emf(u, m, period) / bus_volts(u, bus)
    off = 2 - on - x
    fail = (off < -TIE) | (off > 1 + TIE)

    def outside(t: int, b: int, duty: int) -> bool:
        d_off = 2 - Fraction(min(duty, p), p) - 4 * m.k_e * u.rpm(t) / u.volts(b)
        return not (0 <= d_off <= 1)

    near = (np.abs(off) < TIE) | (np.abs(off - 1) < TIE)
    for k in np.flatnonzero(near):
        fail[k] = outside(int(period[k]), int(bus[k]), int(main[k]))
    return on * p, np.clip(off, 0, 1) * p, fail


def commutation_seconds(
    u: Units, m: Motor, period: Ints, bus: Ints, amps: Floats, on_counts: Floats, off_counts: Floats
) -> tuple[Floats, Floats]:
    """Eq. 20 in seconds (inf where the current never reaches zero) and its denominator
    W in volts, at the given duties."""
    p = u.pwm_counts
    u_d = bus_volts(u, bus)
    w = u_d * (1 + on_counts / p - 2 * off_counts / p) - 2 * emf(u, m, period)
    with np.errstate(divide="ignore", invalid="ignore"):
        t = np.where(w > 0, 3 * amps * float(m.inductance) / w, np.inf)
    return t, w

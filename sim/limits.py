"""Speeds where a rule stops working, from the derived expressions at the spec's values.

* the paper's segment boundary U_d/(4 k_e) and the R-aware one (U_d + 3 R I)/(4 k_e);
* the lowest speed at which the R-aware rule can hold I at all (S <= 2) and the speeds
  between which its turn-off current reaches zero (flat EMFs);
* the speed above which each rule's commutation time (paper's Eq. 20, or the R-aware
  logarithm) no longer fits in the 60 deg interval (flat EMFs, found by bisection).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import sympy as sp

from codegen.derivation import derive
from codegen.derivation import symbols as s
from sim.drive import Drive
from sim.resistance import derive_resistance_rule


@dataclass(frozen=True)
class Limits:
    boundary_paper_rpm: float
    boundary_r_rpm: float
    lowest_hold_rpm: float
    finish_low_rpm: float
    finish_high_rpm: float
    #: Speed above which the commanded commutation time exceeds the 60 deg interval.
    paper_time_fits_below_rpm: float
    r_time_fits_below_rpm: float


def _values(drive: Drive) -> dict[sp.Symbol, float]:
    return {
        s.U_d: drive.bus_voltage_v,
        s.R: drive.resistance_ohm,
        s.I: drive.braking_current_a,
        s.L: drive.inductance_h,
        s.k_e: drive.emf_v_per_rpm,
    }


def _speed(emf: sp.Expr, drive: Drive) -> float:
    return float(emf.subs(_values(drive))) / drive.emf_v_per_rpm


def _first_misfit(
    time_of: Callable[[float], float], drive: Drive, low: float, high: float
) -> float:
    """Lowest speed in [low, high] where time_of(n) >= sector time (bisection)."""

    def misfit(n: float) -> bool:
        t = time_of(n)
        return not math.isfinite(t) or t <= 0.0 or t >= drive.sector_time_s(n)

    if not misfit(high):
        return high
    for _ in range(60):
        middle = 0.5 * (low + high)
        if misfit(middle):
            high = middle
        else:
            low = middle
    return high


def _evaluate(drive: Drive, expr: sp.Expr, n: float) -> float:
    result = complex(expr.subs(_values(drive)).subs(s.E, drive.emf_v(n)).evalf())
    return result.real if abs(result.imag) < 1e-12 else math.nan


def paper_time_s(drive: Drive, n: float) -> float:
    """Eq. 20 at speed `n` under the paper's improved duties (its low or high row),
    seconds (R = 0, as printed)."""
    row = "improved_low" if n <= drive.boundary_speed_rpm else "improved_high"
    return _evaluate(drive, derive()["20"].row(row), n)


def limits(drive: Drive) -> Limits:
    rule = derive_resistance_rule()
    boundary = drive.boundary_speed_rpm
    upper = drive.upper_speed_rpm

    def evaluate(expr: sp.Expr, n: float) -> float:
        return _evaluate(drive, expr, n)

    def paper_time(n: float) -> float:
        return paper_time_s(drive, n)

    boundary_r = _speed(rule.boundary_emf, drive)

    def r_time(n: float) -> float:
        expr = rule.commutation_time_low if n <= boundary_r else rule.commutation_time_high
        return evaluate(expr, n)

    return Limits(
        boundary_paper_rpm=boundary,
        boundary_r_rpm=boundary_r,
        lowest_hold_rpm=_speed(rule.lowest_emf, drive),
        finish_low_rpm=_speed(rule.finish_emf_low, drive),
        finish_high_rpm=_speed(rule.finish_emf_high, drive),
        paper_time_fits_below_rpm=_first_misfit(paper_time, drive, boundary, upper * 0.9999),
        r_time_fits_below_rpm=_first_misfit(
            r_time, drive, boundary_r, _speed(rule.finish_emf_high, drive) * 0.9999
        ),
    )

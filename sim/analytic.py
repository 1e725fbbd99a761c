"""The commutation in closed form: the yardstick the simulated metrics are held to.

Constant duties through the commutation, PWM-averaged terminal voltages, R kept, at
the paper's 60 deg edge. The slopes come from the derivation
(`codegen.derivation.circuit.solve_slopes` on the switching table's terminal
voltages), not from the plant's diode logic (`sim.circuit`): with equal R and L in
every phase each slope is f_x(D_on, D_off, e) - (R/L) i_x, and with the EMFs affine
in time (flat, or the outgoing phase's trapezoid ramp e_b = -E + 2E t / T_s) every
current is the exact solution of di/dt = c0 + c1 t - (R/L) i (`sim.closed_form`).

`commutation_dip` is the non-commutating current's deviation at the instant the
turn-off current reaches zero: for a monotone sag or swell the extreme of the
commutation, which is what the paper's Fig. 4 b/c sketches.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from functools import lru_cache

import sympy as sp

from codegen.derivation import derive
from codegen.derivation import symbols as s
from codegen.derivation.circuit import solve_slopes
from sim import closed_form


@dataclass(frozen=True)
class Dip:
    #: Turn-off current zero, s from the edge; None: not within the horizon.
    commutation_time_s: float | None
    #: (|i_nc| - I) / I in % at that instant (or at the horizon).
    deviation_pct: float


@lru_cache(maxsize=1)
def _forcing() -> tuple[Callable[..., float], Callable[..., float]]:
    """f_a, f_b of the paper's edge: slope + (R/L) i, a function of duties and EMFs."""
    edge = derive().switching.paper_example()
    slopes = solve_slopes(edge.terminal_voltages(s.D_on, s.D_off), s.BACK_EMFS)
    args = (s.D_on, s.D_off, s.e_a, s.e_b, s.e_c, s.U_d, s.L)
    out = []
    for slope, current in ((slopes[0], s.i_a), (slopes[1], s.i_b)):
        forcing = sp.simplify(slope + s.R / s.L * current)
        if forcing.has(s.i_a, s.i_b, s.i_c, s.R):
            raise ValueError(f"slope is not f(D, e) - (R/L) i: {forcing}")
        out.append(sp.lambdify(args, forcing, "math"))
    return out[0], out[1]


def commutation_dip(
    on_duty: float,
    off_duty: float,
    emf_v: float,
    ramp_v_per_s: float,
    bus_v: float,
    resistance_ohm: float,
    inductance_h: float,
    current_a: float,
    horizon_s: float,
) -> Dip:
    """Deviation of the non-commutating current when the turn-off current is zero.

    emf_v: E; ramp_v_per_s: slope of the turn-off phase's EMF from -E (0 for flat).
    """
    f_a, f_b = _forcing()
    consts = (bus_v, inductance_h)
    e_flat = (emf_v, -emf_v, -emf_v)
    c0_a = f_a(on_duty, off_duty, *e_flat, *consts)
    c0_b = f_b(on_duty, off_duty, *e_flat, *consts)
    # The forcing is affine in the EMFs: its slope in time is the ramp's share.
    c1_a = f_a(on_duty, off_duty, emf_v, -emf_v + ramp_v_per_s, -emf_v, *consts) - c0_a
    c1_b = f_b(on_duty, off_duty, emf_v, -emf_v + ramp_v_per_s, -emf_v, *consts) - c0_b
    decay = resistance_ohm / inductance_h
    zero = closed_form.first_zero(current_a, c0_b, c1_b, decay, horizon_s)
    at = horizon_s if zero is None else zero
    i_a = closed_form.current(-current_a, c0_a, c1_a, decay, at)
    return Dip(zero, (-i_a - current_a) / current_a * 100.0)

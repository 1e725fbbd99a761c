"""Eq. 1, the star-connected winding, solved for the phase-current slopes.

    u_x = R i_x + L di_x/dt + e_x + u_n        x in {a, b, c}        (Eq. 1)

The star point is floating, so i_a + i_b + i_c = 0 and hence the slopes also sum to
zero. Summing the three rows then fixes the neutral voltage
u_n = (sum u - sum e) / 3, which is eliminated here. Terminal voltages are PWM
averages over one period (the paper's D U_d), built from the switch state of each
leg and the sign of its current.
"""

from __future__ import annotations

from collections.abc import Sequence

import sympy as sp

from codegen.derivation import symbols as s


def solve_slopes(
    terminal_voltages: Sequence[sp.Expr],
    back_emfs: Sequence[sp.Expr],
    currents: Sequence[sp.Expr] = s.CURRENTS,
) -> tuple[sp.Expr, sp.Expr, sp.Expr]:
    """di_x/dt of Eq. 1 for given averaged terminal voltages and back-EMFs, R kept."""
    unknowns = (*s.SLOPES, s.u_n)
    equations = [
        sp.Eq(u, s.R * i + s.L * di + e + s.u_n)
        for u, i, di, e in zip(terminal_voltages, currents, s.SLOPES, back_emfs, strict=True)
    ]
    equations.append(sp.Eq(sum(s.SLOPES), 0))
    (solution,) = sp.linsolve(equations, unknowns)
    slopes = []
    for index, slope in enumerate(solution[:3]):
        # Use i_a + i_b + i_c = 0 to leave each slope with its own phase current only.
        others = [c for k, c in enumerate(currents) if k != index]
        eliminated = slope.subs(others[0], -currents[index] - others[1])
        # cancel() puts the rational function in canonical p/q form, which is all
        # the later equality tests need, at a fraction of simplify()'s cost.
        slopes.append(sp.cancel(sp.expand(eliminated)))
    return slopes[0], slopes[1], slopes[2]


def averaged_terminal_voltage(switch: str, duty: sp.Expr, current_sign: int) -> sp.Expr:
    """PWM-period average of one leg's terminal voltage (ideal switch plus diode).

    switch: "upper" or "lower" (the transistor that is modulated at `duty`), or "off".
    current_sign: +1 for current into the winding from the terminal, -1 out of it.
    A positive current with its upper switch off returns through the lower diode
    (0 V); a negative current with its lower switch off returns through the upper
    diode (U_d). A switch only conducts the current direction it can carry.
    """
    if current_sign not in (1, -1):
        raise ValueError("a conducting leg carries a current of sign +1 or -1")
    rail_when_off = 0 if current_sign > 0 else s.U_d
    if switch == "off":
        return sp.sympify(rail_when_off)
    if switch == "upper":
        return duty * s.U_d + (1 - duty) * rail_when_off if current_sign > 0 else s.U_d
    if switch == "lower":
        return (1 - duty) * rail_when_off if current_sign < 0 else sp.S.Zero
    raise ValueError(f"unknown switch state {switch!r}")


def integrate_constant_slopes(
    slopes: Sequence[sp.Expr], initial: Sequence[sp.Expr]
) -> tuple[sp.Expr, sp.Expr, sp.Expr]:
    """Currents over time for slopes that do not depend on the currents (R = 0)."""
    out = []
    for slope, start in zip(slopes, initial, strict=True):
        if slope.has(*s.CURRENTS):
            raise ValueError("slope depends on the currents; set R = 0 first")
        out.append(start + sp.integrate(slope, (s.t, 0, s.t)))
    return out[0], out[1], out[2]

"""The segmented duty rule with the winding resistance kept (SymPy, from Eq. 1).

(Moved here from sim/: the generator needs these expressions for the firmware form of
the rule, `codegen.derivation.constant_pair`.)

The paper drops R from Eq. 14 on ("ignoring phase resistance"). With the default
motor (R = 0.21 ohm, L = 0.56 mH, L/R = 2.7 ms) a commutation of about 1 ms at high
speed then loses a third of the non-commutating current to the R i drop alone. This
module repeats the paper's steps on the same circuit (the switching table's 60 deg
edge, `solve_slopes` with R kept) without that approximation, and with the three
EMFs as free symbols so a ramping outgoing EMF can be handled as well:

* hold condition: d i_a/dt = 0 at i_a = -I (the measured current) gives the duty sum
  D_on + D_off = S(e_a, e_b, e_c, R I); with the paper's flat EMFs
  S = 2 - (4E - 3 R I)/U_d, which is Eq. 15 when R = 0;
* segments: the paper's choice (saturate one duty, solve for the other) gives
  D_on = min(S, 1), D_off = max(S - 1, 0); the boundary S = 1 moves from
  E = U_d/4 to E = (U_d + 3 R I)/4;
* commutation time: the turn-off current under the rule obeys
  di_b/dt = alpha + beta t - (R/L) i_b (beta from a ramping EMF); its solution is
  exponential, so the time to zero is a logarithm for flat EMFs (Eq. 20 in the limit
  R -> 0) and is found numerically otherwise.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from functools import lru_cache

import sympy as sp

from codegen.derivation import derive
from codegen.derivation import symbols as s
from codegen.derivation.circuit import solve_slopes
from codegen.errors import DerivationError

#: Time and the slope of a linearly ramping forcing (from a ramping EMF).
alpha, beta = sp.symbols("alpha beta", real=True)
decay = sp.Symbol("a", positive=True)  # R / L
i0 = sp.Symbol("i_0", real=True)


@dataclass(frozen=True)
class ResistanceRule:
    """The rule's expressions, each in the paper's symbols (canonical 60 deg edge)."""

    duty_sum: sp.Expr  # S(e_a, e_b, e_c, R, I, U_d)
    duty_sum_flat: sp.Expr  # S with e_a = E, e_b = e_c = -E
    boundary_emf: sp.Expr  # S_flat = 1
    lowest_emf: sp.Expr  # S_flat = 2: below it even D_on = D_off = 1 cannot hold I
    #: Flat EMFs: the turn-off current reaches zero under the rule only for
    #: finish_emf_low < E (low segment) and E < finish_emf_high (high segment).
    finish_emf_low: sp.Expr
    finish_emf_high: sp.Expr
    off_slope: sp.Expr  # d i_b/dt for any D_on, D_off (Eq. 13 row b, R and i_b kept)
    off_slope_low: sp.Expr  # d i_b/dt with D_on = 1, D_off = S - 1 (i_b kept)
    off_slope_high: sp.Expr  # d i_b/dt with D_on = S, D_off = 0
    current_solution: sp.Expr  # i(t) of di/dt = alpha + beta t - a i, i(0) = i_0
    commutation_time_low: sp.Expr  # flat EMFs, time for i_b: I -> 0
    commutation_time_high: sp.Expr


def _one(solutions: list[sp.Expr], what: str) -> sp.Expr:
    if len(solutions) != 1:
        raise DerivationError(f"{what}: expected one solution, got {solutions}")
    return sp.simplify(solutions[0])


@lru_cache(maxsize=1)
def derive_resistance_rule() -> ResistanceRule:
    derivation = derive()
    edge = derivation.switching.paper_example()
    voltages = edge.terminal_voltages(s.D_on, s.D_off)
    slopes = solve_slopes(voltages, s.BACK_EMFS)  # Eq. 13 with R kept and general EMFs
    hold = slopes[0].subs(s.i_a, -s.I)
    duty_sum = sp.expand(_one(sp.solve(hold, s.D_off), "hold condition") + s.D_on)
    flat = {s.e_a: s.E, s.e_b: -s.E, s.e_c: -s.E}
    duty_sum_flat = sp.expand(duty_sum.subs(flat))
    paper_sum = derivation["15"].row("").rhs
    if sp.simplify(duty_sum_flat.subs(s.R, 0) - paper_sum) != 0:
        raise DerivationError(f"R -> 0 does not give Eq. 15: {duty_sum_flat} vs {paper_sum}")
    boundary_emf = _one(sp.solve(sp.Eq(duty_sum_flat, 1), s.E), "segment boundary")
    lowest_emf = _one(sp.solve(sp.Eq(duty_sum_flat, 2), s.E), "lowest EMF")
    off_low = sp.simplify(slopes[1].subs({s.D_on: 1, s.D_off: duty_sum - 1}))
    off_high = sp.simplify(slopes[1].subs({s.D_on: duty_sum, s.D_off: 0}))
    finish_low = _one(sp.solve(off_low.subs(flat).subs(s.i_b, 0), s.E), "low finish")
    finish_high = _one(sp.solve(off_high.subs(flat).subs(s.i_b, 0), s.E), "high finish")

    t = s.t
    current = sp.Function("i")
    ode = sp.Eq(current(t).diff(t), alpha + beta * t - decay * current(t))
    solution = sp.dsolve(ode, current(t), ics={current(0): i0}).rhs
    solution = sp.simplify(solution)

    def time_to_zero(off_slope: sp.Expr) -> sp.Expr:
        # Flat EMFs: the forcing is constant, alpha = slope at i_b = 0, beta = 0.
        forcing = sp.simplify(off_slope.subs(flat).subs(s.i_b, 0))
        flat_solution = solution.subs({beta: 0, alpha: forcing, i0: s.I, decay: s.R / s.L})
        roots = [r for r in sp.solve(sp.Eq(flat_solution, 0), t) if not r.has(sp.I)]
        return _one(roots, "commutation time")

    t_low = time_to_zero(off_low)
    t_high = time_to_zero(off_high)
    paper_low = derivation["20"].row("improved_low")
    paper_high = derivation["20"].row("improved_high")
    for mine, paper in ((t_low, paper_low), (t_high, paper_high)):
        limit = sp.limit(mine, s.R, 0, "+")
        if sp.simplify(limit - paper) != 0:
            raise DerivationError(f"R -> 0 does not give Eq. 20: {limit} vs {paper}")
    return ResistanceRule(
        duty_sum=duty_sum,
        duty_sum_flat=duty_sum_flat,
        boundary_emf=boundary_emf,
        lowest_emf=lowest_emf,
        finish_emf_low=finish_low,
        finish_emf_high=finish_high,
        off_slope=sp.expand(slopes[1]),
        off_slope_low=off_low,
        off_slope_high=off_high,
        current_solution=solution,
        commutation_time_low=t_low,
        commutation_time_high=t_high,
    )


@dataclass(frozen=True)
class NumericRule:
    """The rule's expressions as float functions, for the simulation loop."""

    duty_sum: Callable[..., float]  # (e_a, e_b, e_c, R, I, U_d)
    off_forcing: Callable[..., float]  # (D_on, D_off, e_a, e_b, e_c, U_d, L) at i_b = 0
    off_forcing_low: Callable[..., float]  # (e_a, e_b, e_c, R, I, U_d, L) at i_b = 0
    off_forcing_high: Callable[..., float]
    commutation_time_low: Callable[..., float]  # (E, R, I, U_d, L)
    commutation_time_high: Callable[..., float]


@lru_cache(maxsize=1)
def numeric_rule() -> NumericRule:
    rule = derive_resistance_rule()
    emfs = (s.e_a, s.e_b, s.e_c)
    args = (*emfs, s.R, s.I, s.U_d)
    flat_args = (s.E, s.R, s.I, s.U_d, s.L)
    return NumericRule(
        duty_sum=sp.lambdify(args, rule.duty_sum, "math"),
        off_forcing=sp.lambdify(
            (s.D_on, s.D_off, *emfs, s.U_d, s.L), rule.off_slope.subs(s.i_b, 0), "math"
        ),
        off_forcing_low=sp.lambdify((*args, s.L), rule.off_slope_low.subs(s.i_b, 0), "math"),
        off_forcing_high=sp.lambdify((*args, s.L), rule.off_slope_high.subs(s.i_b, 0), "math"),
        commutation_time_low=sp.lambdify(flat_args, rule.commutation_time_low, "math"),
        commutation_time_high=sp.lambdify(flat_args, rule.commutation_time_high, "math"),
    )

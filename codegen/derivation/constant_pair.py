"""The resistance-aware rule in firmware form: one constant duty pair per commutation.

The firmware emits one (D_on, D_off) and one commutation time per Hall edge, but the
trapezoidal EMF of the outgoing phase ramps from the edge on (e_b = -E + 2E x over the
sector, x = t / T_s), so the duty sum S that holds the non-commutating current grows
linearly through the commutation. This module derives, from `derive_resistance_rule`
and the switching table, what a constant pair needs:

* the ramp: S(x) = S_flat + (2E/U_d) x, affine in x because S is affine in the EMFs;
* the ramp weight theta: holding S(theta x_c) makes d i_a/dt proportional to
  theta - x/x_c, so the non-commutating deviation is int_0^tau (theta - s) ds in units
  of x_c. theta = 1/2 zeroes it at the end (the mean-slope condition); the minimax
  weight theta = sqrt(2) - 1 makes the peak of the swell equal the final sag, the
  smallest worst case (R -> 0; with the decay R t_com / L = 1.4 of 500 rpm the optimum
  moves only to 0.47, so the firmware keeps the constant);
* the turn-off current under the constant pair and the ramping EMF:
  L di_b/dt = alpha L + beta L t - R i_b, and its value in duty counts
  g(x) = A e^{-y} + F x psi1(y) - X x^2/2 psi2(y), y = rho x, rho = R T_s / L,
  with psi1 = (1 - e^{-y})/y and psi2 = 2 (y - 1 + e^{-y})/y^2: bounded, completely
  monotone, free of cancellation at y -> 0 (the R -> 0 limit), so they can be tabulated;
* the commutation time: the zero of g, found by the firmware by bisection.

Every expression is checked against the paper's R -> 0 / flat-EMF limits (Eqs. 15
and 20) or against the exact solution of the current ODE, or DerivationError is raised.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import sympy as sp

from codegen.derivation import derive
from codegen.derivation import symbols as s
from codegen.derivation.resistance import alpha, beta, decay, derive_resistance_rule, i0
from codegen.errors import DerivationError

#: Sector time, time as a fraction of the sector, the ramp weight.
T_s = sp.Symbol("T_s", positive=True)
x = sp.Symbol("x", nonnegative=True)
theta = sp.Symbol("theta", positive=True)
#: TIM1 counts per PWM period (duty 1), decay over one sector, normalised decay time.
P = sp.Symbol("P", positive=True)
rho = sp.Symbol("rho", positive=True)
y = sp.Symbol("y", nonnegative=True)
#: The rule's quantities in duty counts (see `FirmwareRule`).
A_c, X_c, Y_c, F_c = sp.symbols("A X Y F", real=True)

psi1 = (1 - sp.exp(-y)) / y
psi2 = 2 * (y - 1 + sp.exp(-y)) / y**2


@dataclass(frozen=True)
class FirmwareRule:
    """Expressions of the constant-pair rule at the paper's 60 deg edge."""

    ramp_emfs: dict[sp.Symbol, sp.Expr]  # e_a, e_b, e_c over x in [0, 1]
    duty_sum_ramp: sp.Expr  # S(x) with the ramping EMF
    ramp_weight_mean: sp.Expr  # theta that zeroes the deviation at the end: 1/2
    ramp_weight_minimax: sp.Expr  # theta of the smallest worst deviation: sqrt(2) - 1
    duty_sum_held: sp.Expr  # S(theta x): the constant sum for a commutation of x sectors
    off_alpha: sp.Expr  # d i_b/dt at t = 0, i_b = 0, any constant D_on, D_off
    off_beta: sp.Expr  # its slope in time (the EMF ramp)
    #: Counts: Sigma = P S_held, X = 4 P E/U_d, Y = 3 P R I/U_d, A = 3 P L I/(U_d T_s),
    #: F = 3 P L alpha/U_d = P (2 D_off - D_on - 1) + X/2, and beta in counts is -X.
    counts: dict[sp.Symbol, sp.Expr]
    duty_sum_counts: sp.Expr  # 2P + Y - X + theta X x / 2
    forcing_counts: sp.Expr  # F in terms of D_on, D_off, X
    #: g(x) = 3 P L/(U_d T_s) i_b(T_s x), in A, F, X, rho, x.
    off_current_counts: sp.Expr
    off_current_slope: sp.Expr  # dg/dx at constant duties
    off_current_no_r: sp.Expr  # R -> 0: A + F x - X x^2 / 2
    psi1_second_derivative_max: sp.Expr  # 1/3, at y = 0
    psi2_second_derivative_max: sp.Expr  # 1/6


def _check(condition: sp.Expr, what: str) -> None:
    if sp.simplify(condition) != 0:
        raise DerivationError(f"{what}: residual {sp.simplify(condition)}")


def _ramp_emfs() -> dict[sp.Symbol, sp.Expr]:
    """EMFs over the sector after the paper's edge, from the switching table.

    The turn-off phase ramps (its sector sign is 0) from its sign before the edge to its
    sign one sector later; the other two phases sit on their flat tops.
    """
    table = derive().switching
    edge = table.paper_example()
    sectors = table.sectors(edge.direction)
    during = sectors[edge.sector_to].emf_signs
    if during[edge.turn_off] != 0 or any(
        during[p] != edge.emf_signs[p] for p in (edge.non_commutating, edge.turn_on)
    ):
        raise DerivationError(f"sector {edge.sector_to} is not the turn-off phase's ramp")
    before = sectors[edge.sector_from].emf_signs[edge.turn_off]
    after = sectors[(edge.sector_to + 1) % 6].emf_signs[edge.turn_off]
    out = {s.BACK_EMFS[p]: edge.emf_signs[p] * s.E for p in (edge.non_commutating, edge.turn_on)}
    out[s.BACK_EMFS[edge.turn_off]] = s.E * (before + (after - before) * x)
    return out


def _ramp_weights() -> tuple[sp.Expr, sp.Expr]:
    """theta for a linear ramp: mean-zero and minimax deviation (R -> 0).

    With S held at S(theta x_c), L d i_a/dt is proportional to theta - tau (tau = t/t_c)
    and the deviation to delta(tau) = int_0^tau (theta - s) ds, peaking at tau = theta.
    """
    tau, sigma = sp.symbols("tau sigma", nonnegative=True)
    deviation = sp.integrate(theta - sigma, (sigma, 0, tau))
    (mean,) = sp.solve(deviation.subs(tau, 1), theta)
    roots = sp.solve(sp.Eq(deviation.subs(tau, theta), -deviation.subs(tau, 1)), theta)
    minimax = [r for r in roots if r.is_positive and (r < 1) is sp.true]
    if len(minimax) != 1:
        raise DerivationError(f"minimax ramp weight: expected one root in (0, 1), got {roots}")
    return sp.nsimplify(mean), sp.radsimp(minimax[0])


@lru_cache(maxsize=1)
def derive_firmware_rule() -> FirmwareRule:
    derivation = derive()
    rule = derive_resistance_rule()
    emfs = _ramp_emfs()
    flat = {k: v.subs(x, 0) for k, v in emfs.items()}
    duty_sum_ramp = sp.expand(rule.duty_sum.subs(emfs))
    _check(duty_sum_ramp.subs(x, 0) - rule.duty_sum_flat, "S(x = 0) is not the flat S")
    _check(duty_sum_ramp.diff(x) - 2 * s.E / s.U_d, "S does not ramp by 2E/U_d per sector")
    _check(
        duty_sum_ramp.subs({x: 0, s.R: 0}) - derivation["15"].row("").rhs, "R -> 0 is not Eq. 15"
    )
    weight_mean, weight_minimax = _ramp_weights()
    duty_sum_held = sp.expand(duty_sum_ramp.subs(x, theta * x))

    forcing = sp.expand(rule.off_slope.subs(s.i_b, 0).subs(emfs).subs(x, s.t / T_s))
    off_alpha = sp.expand(forcing.subs(s.t, 0))
    off_beta = sp.expand(forcing.diff(s.t))
    if forcing.diff(s.t, 2) != 0:
        raise DerivationError("the turn-off forcing is not affine in time")
    _check(off_beta + 4 * s.E / (3 * s.L * T_s), "EMF ramp forcing")
    low_flat = {s.D_on: 1, s.D_off: rule.duty_sum_flat - 1}
    _check(
        off_alpha.subs(low_flat) - rule.off_slope_low.subs(flat).subs(s.i_b, 0),
        "alpha with the flat low-segment duties is not the flat forcing",
    )

    scale = 3 * P * s.L / s.U_d  # volts * L -> duty counts: F = scale * alpha
    counts = {
        X_c: 4 * P * s.E / s.U_d,
        Y_c: 3 * P * s.R * s.I / s.U_d,
        A_c: scale * s.I / T_s,
        F_c: scale * off_alpha,
    }
    duty_sum_counts = 2 * P + Y_c - X_c + theta * X_c * x / 2
    _check(
        (P * duty_sum_held - duty_sum_counts).subs(counts),
        "P S_held is not 2P + Y - X + theta X x / 2",
    )
    forcing_counts = P * (2 * s.D_off - s.D_on - 1) + X_c / 2
    _check((scale * off_alpha - forcing_counts).subs(counts), "forcing in counts")
    _check((scale * off_beta * T_s + X_c).subs(counts), "ramp forcing in counts is not -X")

    off_current_counts = (
        A_c * sp.exp(-rho * x)
        + F_c * x * psi1.subs(y, rho * x)
        - X_c * x**2 / 2 * psi2.subs(y, rho * x)
    )
    exact = rule.current_solution.subs(
        {alpha: off_alpha, beta: off_beta, decay: s.R / s.L, i0: s.I, s.t: T_s * x}
    )
    physical = off_current_counts.subs(counts).subs(rho, s.R * T_s / s.L)
    _check(physical - scale / T_s * exact, "g(x) is not the exact turn-off current in counts")
    off_current_slope = sp.simplify(off_current_counts.diff(x))
    _check(
        off_current_slope - (F_c - X_c * x - rho * off_current_counts),
        "dg/dx is not F - X x - rho g (the circuit equation)",
    )
    no_r = sp.expand(sp.limit(off_current_counts, rho, 0, "+"))
    _check(no_r - (A_c + F_c * x - X_c * x**2 / 2), "R -> 0 limit of g")
    # Flat EMF (no ramp term), low segment, R -> 0: the zero of A + F x is Eq. 20.
    flat_low = no_r.subs(X_c * x**2 / 2, 0).subs(F_c, forcing_counts)
    flat_low = flat_low.subs({s.D_on: 1, s.D_off: rule.duty_sum_flat - 1}).subs(counts)
    (root,) = sp.solve(flat_low.subs(s.R, 0), x)
    _check(
        T_s * root - derivation["20"].row("improved_low"),
        "R -> 0 flat low-segment time is not Eq. 20",
    )
    sigma = sp.Symbol("sigma", nonnegative=True)
    y_pos = sp.Symbol("y_pos", positive=True)  # the integral forms also hold at y = 0
    for name, psi, kernel in (
        ("psi1", psi1, sp.exp(-y_pos * sigma)),
        ("psi2", psi2, 2 * (1 - sigma) * sp.exp(-y_pos * sigma)),
    ):
        residual = psi.subs(y, y_pos) - sp.integrate(kernel, (sigma, 0, 1))
        _check(residual, f"{name} is not its integral form")
    # Completely monotone (integral of e^{-y sigma} with a positive kernel): |psi''| is
    # largest at y = 0, where it is the kernel's second moment.
    second_1 = sp.integrate(sigma**2, (sigma, 0, 1))
    second_2 = sp.integrate(2 * (1 - sigma) * sigma**2, (sigma, 0, 1))
    _check(sp.limit(psi1.diff(y, 2), y, 0) - second_1, "psi1''(0)")
    _check(sp.limit(psi2.diff(y, 2), y, 0) - second_2, "psi2''(0)")
    return FirmwareRule(
        ramp_emfs=emfs,
        duty_sum_ramp=duty_sum_ramp,
        ramp_weight_mean=weight_mean,
        ramp_weight_minimax=weight_minimax,
        duty_sum_held=duty_sum_held,
        off_alpha=off_alpha,
        off_beta=off_beta,
        counts=counts,
        duty_sum_counts=duty_sum_counts,
        forcing_counts=forcing_counts,
        off_current_counts=off_current_counts,
        off_current_slope=off_current_slope,
        off_current_no_r=no_r,
        psi1_second_derivative_max=second_1,
        psi2_second_derivative_max=second_2,
    )


# --------------------------------------------------------------------------- any EMF shape

#: Coefficients of sigma(x) = (2 e_a - e_b - e_c)/E and phi(x) = (e_a - 2 e_b + e_c)/E
#: over the sector, for an EMF affine in x (`codegen.derivation.shape_terms`).
sigma0, sigma1, phi0, phi1 = sp.symbols("sigma_0 sigma_1 phi_0 phi_1", real=True)
#: The easing of the split (counts): D_on - delta, D_off + delta, the sum unchanged.
delta = sp.Symbol("delta", real=True)
#: e^{-rho x}, the decay over the commutation.
decay_factor = sp.Symbol("e", positive=True)


@dataclass(frozen=True)
class AlignedRule:
    """The rule for an EMF affine over the sector, ending on a carrier boundary.

    All in duty counts, with the EMFs per unit E as sigma(x), phi(x) (coefficients
    sigma_0, sigma_1, phi_0, phi_1):

    * hold: Sigma(x) = 2P + Y - (X/4) mu(x), mu(x) = sigma_0 + sigma_1 theta x (the
      minimax constant of an affine sigma over [0, x], theta = sqrt(2) - 1);
    * turn-off current: g(x) = A e^-rho x + F_0 x psi1(rho x) + (X/4) phi_1 x^2 psi2(rho x)/2,
      F_0 = 2 C_off - C_on - P + (X/4) phi_0, the exact solution under a constant pair;
    * on the carrier grid the firmware searches h = rho g = A rho e + F_0 E_1 + (X/4)(phi_1/rho) E_2,
      e = e^-y, E_1 = 1 - e, E_2 = y - 1 + e, y = rho x: no psi, and e on the grid
      x_m = m tau/T is e^-(K_rho tau) m, a constant to the power m;
    * easing: C_on - delta, C_off + delta moves F_0 by 3 delta and g by 3 delta x psi1,
      so the pair that ends the commutation exactly at x is delta = -g(x)/(3 x psi1(rho x))
      = -h / (3 E_1).
    """

    duty_sum_counts: sp.Expr  # Sigma(x)
    forcing_counts: sp.Expr  # F_0 in D_on, D_off, X
    off_current_counts: sp.Expr  # g(x)
    grid_current: sp.Expr  # h in e, y
    easing: sp.Expr  # delta that zeroes g at x


@lru_cache(maxsize=1)
def derive_aligned_rule() -> AlignedRule:
    firmware = derive_firmware_rule()
    rule = derive_resistance_rule()
    a0, a1, b0, b1, c0, c1 = sp.symbols("a_0 a_1 b_0 b_1 c_0 c_1", real=True)
    emfs = {s.e_a: s.E * (a0 + a1 * x), s.e_b: s.E * (b0 + b1 * x), s.e_c: s.E * (c0 + c1 * x)}
    sigma_x = 2 * (a0 + a1 * x) - (b0 + b1 * x) - (c0 + c1 * x)
    phi_x = (a0 + a1 * x) - 2 * (b0 + b1 * x) + (c0 + c1 * x)
    counts = firmware.counts
    # the hold condition along the shape, in counts
    sum_along = P * rule.duty_sum.subs(emfs)
    _check(
        (sum_along - (2 * P + Y_c - X_c / 4 * sigma_x)).subs(counts),
        "P S is not 2P + Y - (X/4) sigma along the shape",
    )
    # the forcing on the turn-off current (i_b = 0), in counts
    scale = 3 * P * s.L / s.U_d
    forcing = scale * rule.off_slope.subs(s.i_b, 0).subs(emfs)
    _check(
        (forcing - (P * (2 * s.D_off - s.D_on - 1) + X_c / 4 * phi_x)).subs(counts),
        "the turn-off forcing is not P (2 D_off - D_on - 1) + (X/4) phi",
    )
    mu = sigma0 + sigma1 * firmware.ramp_weight_minimax * x
    duty_sum_counts = 2 * P + Y_c - X_c / 4 * mu
    forcing_counts = P * (2 * s.D_off - s.D_on - 1) + X_c / 4 * phi0
    g = (
        A_c * sp.exp(-rho * x)
        + F_c * x * psi1.subs(y, rho * x)
        + X_c / 4 * phi1 * x**2 / 2 * psi2.subs(y, rho * x)
    )
    # exact: L di_b/dt = alpha + beta t - R i_b with the forcing at t = 0 and its slope
    t_phys = s.t
    alpha_counts = forcing.subs(x, 0)
    beta_counts = sp.diff(forcing, x)
    solution = rule.current_solution.subs(
        {
            alpha: alpha_counts / scale,
            beta: beta_counts / (scale * T_s),
            decay: s.R / s.L,
            i0: s.I,
            t_phys: T_s * x,
        }
    )
    physical = g.subs({F_c: alpha_counts, phi1: beta_counts / (X_c / 4)}).subs(counts)
    physical = physical.subs(rho, s.R * T_s / s.L)
    _check(physical - scale / T_s * solution, "g(x) is not the turn-off current for any shape")
    # the 120 deg trapezoid is the firmware rule of the paper's ramp
    trapezoid = {sigma0: 4, sigma1: -2, phi0: 2, phi1: -4}
    _check(
        duty_sum_counts.subs(trapezoid)
        - firmware.duty_sum_counts.subs(theta, firmware.ramp_weight_minimax),
        "the 120 deg hold is not the firmware rule's",
    )
    _check(
        g.subs(trapezoid) - firmware.off_current_counts,
        "the 120 deg turn-off current is not the firmware rule's",
    )
    # the grid form
    e_sym, yy = decay_factor, sp.Symbol("y_g", positive=True)
    h = A_c * rho * e_sym + F_c * (1 - e_sym) + X_c / 4 * phi1 / rho * (yy - 1 + e_sym)
    _check(
        (rho * g).subs(x, yy / rho).rewrite(sp.exp).subs(sp.exp(-yy), e_sym) - h,
        "rho g is not the grid form",
    )
    # easing
    eased = g.subs(
        F_c, forcing_counts.subs({s.D_on: s.D_on - delta / P, s.D_off: s.D_off + delta / P})
    )
    _check(sp.diff(eased, delta) - 3 * x * psi1.subs(y, rho * x), "dg/d delta is not 3 x psi1")
    (solved,) = sp.solve(sp.Eq(eased.subs(F_c, forcing_counts), 0), delta) or (None,)
    easing = -g / (3 * x * psi1.subs(y, rho * x))
    if solved is not None:
        _check(
            solved - easing.subs(F_c, forcing_counts),
            "the easing is not -g / (3 x psi1)",
        )
    return AlignedRule(duty_sum_counts, forcing_counts, g, h, easing)

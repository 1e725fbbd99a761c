"""The best constant duty pair for one commutation, by Ipopt on the averaged model.

Question answered: if the duties of the turn-on and turn-off transistors are held
constant through the commutation (as all three of the paper's methods do), how close
can the non-commutating current stay to I, and how far is each rule from that?

Decision variables: D_on, D_off in [0, 1] and the commutation length tau. The
averaged commutation circuit (non-commutating current back through its diode at the
rail, turn-off and turn-on legs at D U_d, R kept, the case's EMF shape) is integrated
by CVODES with tau as a time scale, so Ipopt gets exact gradients through the
integrator (the Hessian by L-BFGS). Objective: mean over the commutation of
((|i_nc| - I) / I)^2; constraint: the turn-off current is zero at tau (the commutation
is complete). A tiny weight on tau picks, among equally good pairs (with flat EMFs every
pair on the line D_on + D_off = S holds the current exactly), the one that commutates
fastest: that is the paper's saturated split, which the optimum therefore rediscovers.

When even D_on = 1, D_off = 0 cannot bring the turn-off current to zero within the
60 deg interval, tau is fixed to the interval and the constraint dropped.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import casadi as ca
import numpy as np

from codegen.interrupts import interrupts_noted
from sim.scenario import Case

#: Weight of tau / T_sector against the mean squared relative deviation.
TIME_WEIGHT = 1e-6


@dataclass(frozen=True)
class Optimum:
    speed_rpm: float
    on_duty: float
    off_duty: float
    commutation_time_s: float
    rms_deviation_pct: float
    finishes: bool  # the turn-off current reaches zero within the sector
    solver_status: str


def _canonical_emf(case: Case) -> tuple[np.ndarray, np.ndarray]:
    """EMF coefficients of (nc, off, on) on [0, T_sector] in the paper's edge frame."""
    e0, e1 = case.emf.affine(0.0, case.sector_time_s)
    mirror = 1.0 if case.edge.kind == "upper" else -1.0
    order = list(case.roles())
    return mirror * e0[order], mirror * e1[order]


@lru_cache(maxsize=1)
def _evaluator() -> ca.Function:
    """(D_on, D_off, tau), case data -> objective, i_off(tau)/I, mean squared deviation."""
    x = ca.SX.sym("x", 4)
    p = ca.SX.sym("p", 13)
    s = ca.SX.sym("s")
    on_duty, off_duty, length = p[0], p[1], p[2]
    emf0, emf1 = p[3:6], p[6:9]
    bus, decay, inductance, current = p[9], p[10], p[11], p[12]
    emf = emf0 + emf1 * (s * length)
    voltages = ca.vertcat(bus, off_duty * bus, on_duty * bus)
    neutral = ca.sum1(voltages - emf) / 3
    di = (voltages - emf - neutral) / inductance - decay * x[0:3]
    deviation = (-x[0] - current) / current
    rhs = ca.vertcat(di * length, deviation**2)
    dae = {"x": x, "p": p, "t": s, "ode": rhs}
    integrator = ca.integrator(
        "commutation", "cvodes", dae, 0.0, 1.0, {"abstol": 1e-10, "reltol": 1e-9}
    )
    w = ca.MX.sym("w", 3)
    fixed = ca.MX.sym("fixed", 11)  # emf0, emf1, bus, decay, L, I, sector time
    x0 = ca.vertcat(-fixed[9], fixed[9], 0, 0)
    params = ca.vertcat(w, fixed[0:10])
    final = integrator(x0=x0, p=params)["xf"]
    objective = final[3] + TIME_WEIGHT * w[2] / fixed[10]
    evaluate = ca.Function("evaluate", [w, fixed], [objective, final[1] / fixed[9], final[3]])
    return evaluate


@lru_cache(maxsize=2)
def _solver(constrained: bool) -> ca.Function:
    """Ipopt over w = (D_on, D_off, tau) with the case data as NLP parameters."""
    evaluate = _evaluator()
    w = ca.MX.sym("w", 3)
    fixed = ca.MX.sym("fixed", 11)
    objective, off_end, _ = evaluate(w, fixed)
    problem = {"x": w, "p": fixed, "f": objective, "g": off_end if constrained else ca.MX(0)}
    options = {
        "ipopt.print_level": 0,
        "ipopt.sb": "yes",
        "ipopt.tol": 1e-10,
        "ipopt.max_iter": 200,
        # L-BFGS: the exact Hessian needs CVODES's second-order sensitivities, which
        # left Ipopt failing (Error_In_Step_Computation, Restoration_Failed, out of
        # iterations) at some speeds with a worse pair; the quasi-Newton one solves
        # each speed, as well or better, in a fifth of the time
        "ipopt.hessian_approximation": "limited-memory",
        "print_time": False,
    }
    return ca.nlpsol("duty_pair", "ipopt", problem, options)


def optimise(case: Case, guess_on: float, guess_off: float, guess_time: float) -> Optimum:
    """Best constant (D_on, D_off) and commutation length at this case's speed."""
    drive = case.drive
    emf0, emf1 = _canonical_emf(case)
    sector = case.sector_time_s
    fixed = np.concatenate(
        (
            emf0,
            emf1,
            [drive.bus_voltage_v, drive.decay_rate, drive.inductance_h, case.current_a, sector],
        )
    )
    evaluate = _evaluator()
    with interrupts_noted():  # CasADi drops a KeyboardInterrupt raised in its solver
        _, fastest_end, _ = evaluate([1.0, 0.0, sector], fixed)
    finishes = float(fastest_end) <= 0.0
    guess_time = min(max(guess_time, 1e-6), sector)
    guess = [min(max(guess_on, 0.0), 1.0), min(max(guess_off, 0.0), 1.0), guess_time]
    if finishes:
        bounds = ([0.0, 0.0, 1e-7], [1.0, 1.0, sector])
    else:
        bounds = ([0.0, 0.0, sector], [1.0, 1.0, sector])
        guess[2] = sector
    solver = _solver(finishes)
    with interrupts_noted():
        result = solver(x0=guess, p=fixed, lbx=bounds[0], ubx=bounds[1], lbg=0, ubg=0)
        solution = np.array(result["x"]).ravel()
        status = str(solver.stats()["return_status"])
        _, _, mean_square = evaluate(solution, fixed)
    return Optimum(
        speed_rpm=case.speed_rpm,
        # Ipopt may end a hair outside the bounds (bound_relax_factor, 1e-8): a duty is
        # within [0, 1]
        on_duty=min(max(float(solution[0]), 0.0), 1.0),
        off_duty=min(max(float(solution[1]), 0.0), 1.0),
        commutation_time_s=float(solution[2]),
        rms_deviation_pct=100.0 * math.sqrt(max(float(mean_square), 0.0)),
        finishes=finishes,
        solver_status=status,
    )

"""The symbols of the paper, with the assumptions SymPy needs to simplify.

Names follow the paper: U_d bus voltage, E phase back-EMF flat-top, L and R phase
inductance and resistance, I current before commutation, D_on and D_off the turn-on
and turn-off phase duty cycles, k_e the EMF constant (E = k_e n, Eq. 3), n speed.
"""

from __future__ import annotations

import sympy as sp

U_d, E, L, I, k_e, n, omega_m = sp.symbols("U_d E L I k_e n omega_m", positive=True)
R = sp.Symbol("R", nonnegative=True)
t = sp.Symbol("t", nonnegative=True)
D_on, D_off = sp.symbols("D_on D_off", real=True)
#: Main braking duty of the current controller (conventional method: D_on = D).
D = sp.Symbol("D", real=True)

i_a, i_b, i_c = sp.symbols("i_a i_b i_c", real=True)
u_a, u_b, u_c, u_n = sp.symbols("u_a u_b u_c u_n", real=True)
e_a, e_b, e_c = sp.symbols("e_a e_b e_c", real=True)
di_a, di_b, di_c = sp.symbols("di_a/dt di_b/dt di_c/dt", real=True)
T_e = sp.Symbol("T_e", real=True)

PHASES: tuple[str, str, str] = ("a", "b", "c")
CURRENTS = (i_a, i_b, i_c)
TERMINAL_VOLTAGES = (u_a, u_b, u_c)
BACK_EMFS = (e_a, e_b, e_c)
SLOPES = (di_a, di_b, di_c)

#: Spec parameter -> symbol, for evaluating expressions at a motor's values.
BY_NAME: dict[str, sp.Symbol] = {
    str(s): s for s in (U_d, E, L, R, I, k_e, n, omega_m, t, D_on, D_off, D, i_a, i_b, i_c)
}

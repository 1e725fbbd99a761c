# Generated from template templates/python/bldc_float.py.j2 with spec spec/paper_motor_improved_r.yaml (sha256 9f5d9c8963649549b4e129e1bd9cd35baa3c8e343f67f4b67f06c6141ed1f434). Do not edit: regenerate with `bldc-codegen generate spec/paper_motor_improved_r.yaml`.
"""Floating-point physics of the commutation rule (method "improved_r").

Each function is printed by SymPy from the derivation (codegen/derivation), so this is
the paper's mathematics with R = 0 as in Eqs. 14-20, not a re-typed copy.
Standalone: the standard library only.
"""

from __future__ import annotations

import math

K_E_V_PER_RPM = 0.00236  # E = k_e n, Eq. 3 (phase flat-top EMF)
INDUCTANCE_H = 0.00056
METHOD = "improved_r"


def back_emf(speed_rpm: float) -> float:
    """Eq. 3."""
    return K_E_V_PER_RPM * speed_rpm


def is_high_speed(E: float, U_d: float) -> bool:
    """Eq. 18 segment: high speed when n > U_d / (4 k_e), i.e. 4E > U_d."""
    return ((1/4)*U_d < E)


def improved_duties(E: float, U_d: float) -> tuple[float, float]:
    """Eq. 18: (D_on, D_off)."""
    if is_high_speed(E, U_d):
        return (-4*E/U_d + 2, 0)
    return (1, (-4*E + U_d)/U_d)


def conventional_off_duty(E: float, U_d: float, D_on: float) -> float:
    """Eq. 16, unclamped: outside [0, 1] is the control fail area."""
    return -D_on - 4*E/U_d + 2


def commutation_time(I: float, E: float, U_d: float, D_on: float, D_off: float) -> float:
    """Eq. 20 in seconds (R = 0); math.inf where the turn-off current never reaches zero."""
    denominator = 2*D_off*U_d - D_on*U_d + 2*E - U_d
    if denominator >= 0:
        return math.inf
    return -3*I*INDUCTANCE_H / denominator


def duties(E: float, U_d: float, main_duty: float) -> tuple[float, float]:
    """(D_on, D_off) of this spec's method, clamped to [0, 1] as the firmware does."""
    if METHOD == "improved":
        on, off = improved_duties(E, U_d)
    elif METHOD == "conventional":
        on, off = main_duty, conventional_off_duty(E, U_d, main_duty)
    else:
        on, off = main_duty, 0.0
    return min(max(on, 0.0), 1.0), min(max(off, 0.0), 1.0)

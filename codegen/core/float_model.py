"""Render context of the floating-point physics model (python/bldc_float.py).

SymPy prints the derivation's own expressions (Eqs. 16, 18, 20) to Python, so the float
model is the paper's equations at the spec's constants, not a fixed-point design.
"""

from __future__ import annotations

import sympy as sp

from codegen.derivation.paper import Derivation
from codegen.spec_model import Spec


def float_model_context(spec: Spec, derivation: Derivation) -> dict[str, object]:
    """SymPy-printed expressions for the floating-point physics model."""
    from sympy.printing.pycode import pycode

    from codegen.derivation import symbols as s

    rule = derivation["18"]
    t_com = sp.together(derivation["20"].row(""))
    numerator, denominator = sp.fraction(t_com)
    boundary_emf = sp.solve(sp.Eq(rule.row("boundary_speed") * s.k_e, s.E), s.E)[0]
    return {
        "method": spec.controller.method,
        "k_e": repr(float(spec.motor.back_emf_constant_v_per_rpm)),
        "inductance": repr(float(spec.motor.phase_inductance_h)),
        "high_condition": pycode(boundary_emf < s.E),
        "on_high": pycode(rule.row("on_high")),
        "off_high": pycode(rule.row("off_high")),
        "on_low": pycode(rule.row("on_low")),
        "off_low": pycode(rule.row("off_low")),
        "off_conventional": pycode(derivation["16"].row("")),
        "t_numerator": pycode(numerator.subs(s.L, sp.Symbol("INDUCTANCE_H"))),
        "t_denominator": pycode(denominator),
    }

"""Render context of the portable core and its bit-exact Python twin.

Prints every constant (with its physical meaning and equation) and the switching
tables into plain strings and integers; the templates only lay them out.
"""

from __future__ import annotations

import sympy as sp

from codegen.derivation.paper import Derivation
from codegen.fixedpoint.design import FixedPointDesign
from codegen.spec_model import Spec

NO_SWITCH = 0xFF
INVALID_SECTOR = 0xFF


def _switch_index(name: str) -> int:
    return int(name[1:]) - 1  # "T5" -> 4


def core_context(spec: Spec, derivation: Derivation, fx: FixedPointDesign) -> dict[str, object]:
    sc = fx.scaling
    k_x = sp.Rational(sc.k_x)
    sector_of_hall = [INVALID_SECTOR] * 8
    for sector, code in enumerate(spec.hall.sequence):
        sector_of_hall[code] = sector
    edges = []
    for direction in ("forward", "reverse"):
        rows = []
        for sector in range(6):
            edge = derivation.switching.edge_into(sector, direction)
            rows.append(
                {
                    "on": _switch_index(edge.modulated_on),
                    "off": _switch_index(edge.modulated_off),
                    "comment": f"sector {sector} ({60 * sector}-{60 * sector + 60} deg), {edge.describe()}",
                }
            )
        edges.append({"direction": direction, "rows": rows})
    p = sc.period_counts
    return {
        "method": spec.controller.method,
        "period_counts": p,
        "pwm_hz": f"{float(spec.inverter.pwm_frequency_hz):g}",
        "hall_hz": f"{float(sc.hall_clock_hz):g}",
        "period_min_ticks": sc.period_min_ticks,
        "period_max_ticks": sc.period_max_ticks,
        "speed_max_rpm": f"{float(spec.controller.speed_max_rpm):g}",
        "speed_min_rpm": f"{float(spec.controller.speed_min_rpm):g}",
        "bus_code_min": sc.bus_code_min,
        "bus_code_max": sc.bus_code_max,
        "bus_min_v": f"{float(spec.inverter.bus_voltage_min_v):g}",
        "bus_max_v": f"{float(spec.inverter.bus_voltage_max_v):g}",
        "volts_per_code": f"{float(sc.volts_per_bus_code):.6g}",
        "current_offset_code": sc.current_offset_code,
        "current_code_max": sc.current_code_max,
        "current_max_a": f"{float(spec.controller.braking_current_max_a):g}",
        "amps_per_code": f"{float(sc.amps_per_current_code):.6g}",
        "x_frac_bits": fx.x_frac_bits,
        "x_scale": 2**fx.x_frac_bits,
        "x_round": 2 ** (fx.x_frac_bits - 1) if fx.x_frac_bits else 0,
        "tb_shift": fx.tb_shift,
        "tb_round": 2 ** (fx.tb_shift - 1) if fx.tb_shift else 0,
        "k_x_q": fx.k_x_q,
        "k_x_num": int(k_x.p),
        "k_x_den": int(k_x.q),
        "k_x": f"{float(k_x):.6e}",
        "k_g_q": fx.k_g_q,
        "k_g": f"{float(sc.k_g):.6e}",
        "duty_bound": f"{float(fx.duty_error_bound_counts):.3f}",
        "time_bound": f"{float(fx.time_error_bound_ticks):.3f}",
        "sector_of_hall": [
            {
                "code": code,
                "sector": sector,
                "comment": "invalid" if sector == INVALID_SECTOR else f"sector {sector}",
            }
            for code, sector in enumerate(sector_of_hall)
        ],
        "edges": edges,
        "ranges": [
            {
                "name": r.name,
                "type": r.c_type,
                "low": r.low,
                "high": r.high,
                "headroom": f"{r.headroom_bits:.1f}",
            }
            for r in fx.ranges
        ],
    }


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

"""Render context of the portable core and its bit-exact Python twin.

Prints every constant (with its physical meaning and equation) and the switching
tables into plain strings and integers; the templates only lay them out.
"""

from __future__ import annotations

import sympy as sp

from codegen.derivation.paper import Derivation
from codegen.fixedpoint.design import FixedPointDesign
from codegen.improved_r_rule.context import rule_context
from codegen.spec_model import Spec, uses_main_duty

NO_SWITCH = 0xFF
INVALID_SECTOR = 0xFF


def _switch_index(name: str) -> int:
    return int(name[1:]) - 1  # "T5" -> 4


def edge_index(direction: str, sector: int) -> int:
    """The core's edge numbering: forward edges 0..5, reverse 6..11, by sector entered."""
    return (0 if direction == "forward" else 6) + sector


def edge_of_hall_pair(sequence: tuple[int, ...]) -> list[int]:
    """(previous code << 3 | code) -> edge index, NO_SWITCH for an invalid pair."""
    sector_of = {code: sector for sector, code in enumerate(sequence)}
    table = [NO_SWITCH] * 64
    for previous, before in sector_of.items():
        for code, after in sector_of.items():
            if after == (before + 1) % 6:
                table[(previous << 3) | code] = edge_index("forward", after)
            elif before == (after + 1) % 6:
                table[(previous << 3) | code] = edge_index("reverse", after)
    return table


def core_context(spec: Spec, derivation: Derivation, fx: FixedPointDesign) -> dict[str, object]:
    sc = fx.scaling
    k_x = sp.Rational(sc.k_x)
    sector_of_hall = [INVALID_SECTOR] * 8
    for sector, code in enumerate(spec.hall.sequence):
        sector_of_hall[code] = sector
    edges = []
    for direction in ("forward", "reverse"):
        for sector in range(6):
            edge = derivation.switching.edge_into(sector, direction)
            edges.append(
                {
                    "index": edge_index(direction, sector),
                    "on": _switch_index(edge.modulated_on),
                    "off": _switch_index(edge.modulated_off),
                    "comment": f"into sector {sector} ({60 * sector}-{60 * sector + 60} deg), "
                    f"{edge.describe()}",
                }
            )
    pairs = []
    for index, edge_number in enumerate(edge_of_hall_pair(spec.hall.sequence)):
        previous, code = index >> 3, index & 7
        if edge_number == NO_SWITCH:
            what = "invalid: every switch off"
        else:
            direction = "forward" if edge_number < 6 else "reverse"
            what = f"{direction} into sector {edge_number % 6}"
        pairs.append({"value": edge_number, "comment": f"{previous:03b} -> {code:03b}: {what}"})
    p = sc.period_counts
    method = spec.controller.method
    rule = rule_context(spec, sc) if method == "improved_r" else {}
    return {
        **rule,
        "method": method,
        "uses_main_duty": uses_main_duty(method),
        "period_counts": p,
        "pwm_hz": f"{float(spec.inverter.pwm_frequency_hz):g}",
        "hall_hz": f"{float(sc.hall_clock_hz):g}",
        "period_min_ticks": sc.period_min_ticks,
        "period_max_ticks": sc.period_max_ticks,
        "period_cap_ticks": sc.period_cap_ticks,
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
        "k_x_numerator": fx.k_x.numerator,
        "k_x_high": fx.k_x.high,
        "k_x_low": fx.k_x.low,
        "k_x_shift": fx.k_x.shift,
        "k_g_numerator": fx.k_g.numerator,
        "k_g_high": fx.k_g.high,
        "k_g_low": fx.k_g.low,
        "k_g_shift": fx.k_g.shift,
        "high_speed_tb": fx.high_speed_tb,
        "k_x_num": int(k_x.p),
        "k_x_den": int(k_x.q),
        "k_x": f"{float(k_x):.6e}",
        "k_g": f"{float(sc.k_g):.6e}",
        "duty_bound": f"{float(fx.duty_error_bound_counts):.3f}",
        "time_bound": f"{float(fx.time_error_bound_ticks):.3f}",
        "time_bound_min_w": f"{float(fx.time_bound_min_w_counts):g}",
        "x_q_error": f"{fx.x_q_error}",
        "time_numerator_error": f"{fx.time_numerator_error}",
        "sector_of_hall": [
            {
                "code": code,
                "bits": f"{code:03b}",
                "sector": sector,
                "comment": "invalid" if sector == INVALID_SECTOR else f"sector {sector}",
            }
            for code, sector in enumerate(sector_of_hall)
        ],
        "edges": edges,
        "edge_of_hall_pair": pairs,
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

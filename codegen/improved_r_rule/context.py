"""Render context of the `improved_r` core: the designed rule's integers, printed.

Every value comes from `design.design_rule` (formats, constants and table, each
proven by `proof.prove_rule`); the templates only lay them out. The C types of the
products whose width depends on the spec (32-bit where the proof allows it, 64-bit
otherwise) are taken from the proof, so a spec that needs a wider product gets one.
"""

from __future__ import annotations

from codegen.fixedpoint.scaling import Scaling
from codegen.improved_r_rule.constants import rule_constants
from codegen.improved_r_rule.design import RuleDesign, design_rule
from codegen.improved_r_rule.fixed import THETA_FRAC_BITS, LongDivision
from codegen.improved_r_rule.table import ONE_Q16, grid_point
from codegen.spec_model import Spec

#: proof name -> template key of the products whose type the proof chooses.
PRODUCT_TYPES = {
    "X KAPPA i + half": "type_x_kappa_i",
    "X THETA + half": "type_x_theta",
    "RHO x": "type_rho_x",
    "y psi1 + half": "type_y_psi1",
    "x (x psi2) + half": "type_x_x_psi2",
    "S1 x + half": "type_s1_x",
}


def rule_design(spec: Spec, sc: Scaling) -> RuleDesign:
    return design_rule(rule_constants(spec, sc), sc.current_code_max)


def _long(prefix: str, ld: LongDivision) -> dict[str, int]:
    return {
        f"{prefix}_numerator": ld.numerator,
        f"{prefix}_high": ld.high,
        f"{prefix}_low": ld.low,
        f"{prefix}_shift": ld.shift,
    }


def _half(shift: int) -> int:
    return 1 << (shift - 1) if shift > 0 else 0


def rule_context(spec: Spec, sc: Scaling) -> dict[str, object]:
    design = rule_design(spec, sc)
    r = design.rule
    c = r.constants
    t = r.table
    types = {r.name: r.c_type for r in design.ranges}
    k, fc, fu, fy = r.steps, r.counts_frac_bits, r.unit_frac_bits, t.y_frac_bits
    shifts = {
        "y_guard": r.y_guard_bits,
        "kappa": r.kappa_frac_bits,
        "theta": THETA_FRAC_BITS,
        "y": r.y_shift,
        "e": fy + 16 - fu,
        "u1": k + 16 - fu,
        "v2": 2 * k + 16 - fu,
        "s1_x": k,
        "fraction": k + 1,
        "counts": fc,
    }
    per = 1 << t.segment_bits
    rows = [
        {
            "c1": c1,
            "c2": c2,
            "comment": f"y = {float(grid_point(n, t.segment_bits)):.6g}"
            + (f", octave {n // per}" if n % per == 0 else ""),
        }
        for n, (c1, c2) in enumerate(zip(t.complement1, t.complement2, strict=True))
    ]
    return {
        "rule": {
            **_long("n_x", r.n_x),
            **_long("n_y", r.n_y),
            "k_x": f"{float(c.k_x):.6e}",
            "k_y": f"{float(c.k_y):.6e}",
            "kappa": f"{float(c.kappa):.6e}",
            "k_rho": f"{float(c.k_rho):.6e}",
            "theta": f"{float(c.ramp_weight):.9f}",
            "counts_frac_bits": fc,
            "kappa_q": r.kappa_q,
            "k_rho_q": r.k_rho_q,
            "rho_frac_bits": r.rho_frac_bits,
            "theta_half_q": r.theta_half_q,
            "steps": k,
            "unit_frac_bits": fu,
            "y_frac_bits": fy,
            "segment_bits": t.segment_bits,
            "segments": t.segments,
            "entries": t.entries,
            "table_bytes": t.flash_bytes,
            "error1": f"{t.error1:.2e}",
            "error2": f"{t.error2:.2e}",
            "one_q16": ONE_Q16,
            "period_q": r.period_q,
            "current_high": c.current_high,
            "shifts": shifts,
            "halves": {name: _half(s) for name, s in shifts.items()},
            "types": {key: types[name] for name, key in PRODUCT_TYPES.items()},
            "rows": rows,
            "ticks_bound": f"{design.ticks_bound:.2f}",
            "time_ratio": f"{design.time_ratio:.3f}",
            "duty_bound": f"{design.duty_bound:.3f}",
            "grid_points": design.grid_points,
            "ranges": [
                {
                    "name": p.name,
                    "type": p.c_type,
                    "low": p.low,
                    "high": p.high,
                    "headroom": f"{p.headroom_bits:.1f}",
                }
                for p in design.ranges
            ],
        }
    }

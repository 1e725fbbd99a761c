"""The resistance-aware rule (beyond the paper, which sets R = 0 in Eqs. 14-20).

One constant duty pair per commutation, held at the EMFs of time theta t_com (theta =
sqrt(2) - 1, the minimax weight of the ramping EMF), and t_com the zero of the
turn-off current with R and the trapezoidal EMF's ramp, found by integer bisection
with an octave table of psi1, psi2. `design.py` picks the formats and table against
the spec's targets; `ir.py` is the arithmetic; `accuracy.py` its pointwise bounds.
"""

from __future__ import annotations

from codegen.core.conditioning import CoreLimits
from codegen.fixedpoint.scaling import Scaling
from codegen.methods.base import Claims, CoreDesign, FixedPointError
from codegen.methods.improved_r.constants import rule_constants
from codegen.methods.improved_r.design import RuleFormatError, design_rule
from codegen.methods.improved_r.ir import BUS, EDGE, functions
from codegen.methods.paper_method import round_up
from codegen.spec_model import Spec


class ImprovedR:
    name = "improved_r"
    uses_main_duty = False

    def design(self, spec: Spec, sc: Scaling, limits: CoreLimits) -> CoreDesign:
        c = rule_constants(spec, sc)
        try:
            design = design_rule(c, sc.current_code_max, limits)
        except RuleFormatError as exc:
            raise FixedPointError(
                f"controller.method = 'improved_r': {exc} (allowed: a spec whose accuracy targets "
                "and ranges the rule's integer formats can meet)",
                "controller.method",
            ) from None
        r = design.rule
        t = r.table
        bus_fn, timing, table = functions(r, limits, c.current, design.widths)
        m = c.current.scale
        doc = (
            'Method "improved_r": the resistance-aware rule (codegen/methods/improved_r).',
            "One constant duty pair per commutation, held at the EMFs of time theta t_com",
            "(theta = sqrt(2) - 1), and t_com the zero of the turn-off current with R and the",
            "trapezoidal EMF's ramp:",
            "  S(x) = 2P + Y - X + theta X x / 2, C_on = clamp(S, 0, P), C_off = clamp(S - P, 0, P)",
            "  g(x) = A e^-rho x + F x psi1(rho x) - X x^2/2 psi2(rho x), F = 2 C_off - C_on - P + X/2",
            "  x_c: g(x_c) = 0 in (0, 1] sectors; t_com = x_c T",
            f"with, in duty counts, X = 4 P E / U_d = K_X / (T B), K_X = {float(c.k_x):.6e};",
            f"Y = 3 P R I / U_d = K_Y i / B, K_Y = {float(c.k_y):.6e}; A = kappa i X, kappa = {float(c.kappa):.6e};",
            f"rho = R T_s / L = K_rho T, K_rho = {float(c.k_rho):.6e}; i in 1/{m} codes.",
            "",
            "Formats (codegen/methods/improved_r/design.py chose them; the IR proof checked them):",
            f"  counts in Q{r.counts_frac_bits}; {r.steps}-step bisection, x in Q{r.steps}; e^-y, x psi1, x^2 psi2 in Q{r.unit_frac_bits};",
            f"  y = rho x in Q{t.y_frac_bits}; psi from a {t.entries}-row octave table ({t.flash_bytes} bytes, linear",
            "  interpolation, one CLZ per lookup); x_c = the middle of the last bracket, or 1",
            "  (flagged) when the current does not reach zero in the sector.",
            "  Period clamped to [BLDC_PERIOD_MIN_TICKS, BLDC_PERIOD_MAX_TICKS] (the table covers rho up",
            "  to the slowest speed; t_com stays within the measured period); current clamped at 0.",
            f"Claimed bounds over the design grid ({design.grid_points} points): duties <= {round_up_f(design.duty_bound)}",
            f"  counts; t_com <= {round_up_f(design.ticks_bound)} ticks where t_half <= the target, and everywhere",
            f"  at most {round_up_f(design.time_ratio)} of max(target, t_half) (t_half: the shift of the true zero",
            "  that half a count of duty causes, where t_com is ill-conditioned in the physics too).",
            "Flags: HIGH_SPEED when C_off = 0 (S < P); FAIL_AREA_CLAMPED when no pair in [0, 1]",
            "holds the current (S > 2P or S < 0); TIME_CLAMPED when the turn-off current does not",
            "reach zero within the sector. The main duty is not used.",
        )
        formats: dict[str, int | float | str] = {
            "counts_frac_bits": r.counts_frac_bits,
            "bisection_steps": r.steps,
            "unit_frac_bits": r.unit_frac_bits,
            "y_frac_bits": t.y_frac_bits,
            "rho_frac_bits": r.rho_frac_bits,
            "y_shift": r.y_shift,
            "table_rows": t.entries,
            "table_bytes": t.flash_bytes,
            "current_scale": m,
            **{f"width_{k}": v.name for k, v in design.widths.items()},
        }
        return CoreDesign(
            method=self.name,
            uses_main_duty=False,
            bus_struct=BUS,
            bus_condition=bus_fn,
            commutation_timing=timing,
            tables=(table,),
            doc=doc,
            extra_constants=(),
            ranges=design.ranges,
            claims=Claims(
                duty_counts=round_up_f(design.duty_bound),
                time_ticks=round_up_f(design.ticks_bound),
                time_region="where half a count of duty moves t_com by at most the target (design grid)",
            ),
            formats=formats,
            summary=(
                f"improved_r, counts in Q{r.counts_frac_bits}, {r.steps}-step bisection, psi table "
                f"{t.entries} rows ({t.flash_bytes} B); bounds over the design grid: duties "
                f"{round_up_f(design.duty_bound)} counts, t_com {round_up_f(design.ticks_bound)} ticks"
            ),
        )


def round_up_f(value: float) -> float:
    from fractions import Fraction

    return round_up(Fraction(value))


METHOD = ImprovedR()
__all__ = ["EDGE", "METHOD"]

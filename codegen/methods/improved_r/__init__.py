"""The resistance-aware rule (beyond the paper, which sets R = 0 in Eqs. 14-20).

One constant duty pair per commutation, held at the minimax duty sum of the spec's EMF
over the commutation (theta = sqrt(2) - 1 for the 120 deg trapezoid's ramp, the edge's
sum for the paper's flat EMF); the commutation ends on the first carrier boundary at
which the turn-off current, with R and the EMF's ramp, has reached zero, and the split
is eased so that it reaches zero exactly there (the port restarts the PWM carrier at
the commutation end: ending on a boundary leaves the ripple's phase alone).
`design.py` picks the formats against the spec's targets; `ir.py` is the arithmetic;
`accuracy.py` its pointwise bounds; `reference.py` the rule in real arithmetic.
"""

from __future__ import annotations

import math
from fractions import Fraction

from codegen.core.conditioning import CoreLimits
from codegen.derivation.shape_terms import ShapeError
from codegen.fixedpoint.scaling import Scaling
from codegen.methods.base import Claims, CoreDesign, FixedPointError
from codegen.methods.improved_r.constants import rule_constants
from codegen.methods.improved_r.design import (
    RuleFormatError,
    SectorTooShortError,
    design_rule,
    reachable_duty_target,
)
from codegen.methods.improved_r.ir import BUS, functions
from codegen.methods.paper_method import round_up
from codegen.spec_loader import DUTY_COUNTS_MAX
from codegen.spec_model import Spec


class ImprovedR:
    name = "improved_r"
    uses_main_duty = False

    def design(self, spec: Spec, sc: Scaling, limits: CoreLimits) -> CoreDesign:
        try:
            c = rule_constants(spec, sc)
        except ShapeError as exc:
            raise FixedPointError(
                f"motor.back_emf_shape = {spec.motor.back_emf_shape.describe()!r}: {exc};"
                " the improved_r firmware holds the EMF affine over the commutation sector"
                " (allowed: 'flat', '120 deg', or a table with no corner inside the"
                " commutation sector and whole EMFs at the edge, as the 120 deg trapezoid's"
                " [[0, 0], [30, 1], [150, 1], [180, 0]])",
                "motor.back_emf_shape",
            ) from None
        try:
            design = design_rule(c, sc.current_code_max, limits)
        except SectorTooShortError as exc:
            # the top speed's sector is the cause: named with the speed that holds one
            # period (this had named controller.method, with no value to change to)
            top = float(sc.speed_rpm(exc.period_needed))
            raise FixedPointError(
                f"controller.speed_max = {float(spec.controller.speed_max_rpm):g} rpm: {exc}"
                f" (allowed: <= {math.floor(top * 10) / 10:g} rpm for controller.method"
                " improved_r, or a higher PWM frequency or a shorter dead time)",
                "controller.speed_max",
            ) from None
        except RuleFormatError as exc:
            # a target the formats miss is named as such, with the value they do meet
            # (the "duty bound ... exceeds the target" wording stays: the simulation and
            # the bench read the bound back from it)
            reachable = reachable_duty_target([str(exc)])
            if reachable is not None and float(reachable) > DUTY_COUNTS_MAX:
                raise FixedPointError(  # no target a spec may ask is met: the method is
                    f"accuracy.duty_counts = {float(spec.accuracy.duty_counts):g} counts: the"
                    f" improved_r rule's {exc}: its integer formats meet no less (allowed:"
                    f" <= {DUTY_COUNTS_MAX} counts, which this motor's rule does not reach:"
                    " choose another controller.method)",
                    "accuracy.duty_counts",
                ) from None
            if reachable is not None:
                raise FixedPointError(
                    f"accuracy.duty_counts = {float(spec.accuracy.duty_counts):g} counts: the"
                    f" improved_r rule's {exc}: its integer formats meet no less (allowed:"
                    f" >= {reachable} counts for controller.method improved_r, or another"
                    " method)",
                    "accuracy.duty_counts",
                ) from None
            raise FixedPointError(
                f"controller.method = 'improved_r': {exc} (allowed: a spec whose accuracy targets "
                "and ranges the rule's integer formats can meet)",
                "controller.method",
            ) from None
        r = design.rule
        bus_fn, timing, table = functions(r, limits, c.current)
        m = c.current.scale
        shape = c.shape
        tau = c.carrier_ticks
        doc = (
            'Method "improved_r": the resistance-aware rule (codegen/methods/improved_r).',
            f"EMF: {shape.description}; per unit E over the sector after the edge,",
            f"sigma = (2e_a - e_b - e_c)/E = {shape.sum0} + {shape.sum1} x,"
            f" phi = (e_a - 2e_b + e_c)/E = {shape.force0} + {shape.force1} x.",
            "One constant duty pair per commutation, held at the minimax duty sum over it, and",
            "the end on a carrier boundary (the port restarts the PWM carrier there):",
            "  Sigma(x) = 2P + Y - (X/4)(sigma_0 + sigma_1 theta x), theta = sqrt(2) - 1,",
            "  C_on = clamp(Sigma, 0, P), C_off = clamp(Sigma - P, 0, P), F_d = 2 C_off - C_on - P,",
            "  g(x) = A e^-rho x + (F_d + (X/4) phi_0) x psi1(rho x) + (X/4) phi_1 x^2/2 psi2(rho x):",
            "  the turn-off current under that pair (psi1 = (1 - e^-y)/y, psi2 = 2(y - 1 + e^-y)/y^2);",
            f"  the end: the first x_m = m tau / T (tau = {float(tau):g} ticks, m >= 1) with g(x_m) < 0;",
            "  the pair eased there: C_on - delta, C_off + delta, delta = -g / (3 x psi1), at most",
            "  min(C_on, P - C_off), so the current reaches zero exactly on the boundary.",
            f"with, in duty counts, X = 4 P E / U_d = K_X / (T B), K_X = {float(c.k_x):.6e};",
            f"Y = 3 P R I / U_d = K_Y i / B, K_Y = {float(c.k_y):.6e}; A = kappa i X,"
            f" kappa = {float(c.kappa):.6e};",
            f"rho = R T_s / L = K_rho T, K_rho = {float(c.k_rho):.6e}; i in 1/{m} codes.",
            "",
            "Formats (codegen/methods/improved_r/design.py chose them; the IR proof checked them):",
            f"  counts in Q{r.counts_frac_bits}; on the grid rho x_m = y_1 m, e^-rho x_m = D^m from a",
            f"  {len(r.decay)}-entry table of D^(2^k) (Q32): a {r.steps}-step binary lifting over m,",
            "  each step one table product and the sign of 2^(32+fc) rho g in int64; the easing",
            "  by two 32-bit divides. No exponential, no psi table, no divide in the loop.",
            "  Period clamped to [BLDC_PERIOD_MIN_TICKS, BLDC_PERIOD_MAX_TICKS]; current clamped at 0.",
            f"Claimed bounds over the design grid ({design.grid_points} points, the end decided at"
            f" {design.decided_points}):",
            f"  duties <= {round_up_f(design.duty_bound)} counts at every point, t_com <= "
            f"{round_up_f(design.ticks_bound)} ticks of the rule's carrier boundary where the"
            " end is decided.",
            "Flags: HIGH_SPEED when Sigma < P; FAIL_AREA_CLAMPED when no pair in [0, 1] holds the",
            "current (Sigma > 2P or Sigma < 0); TIME_CLAMPED when the turn-off current does not",
            "reach zero by the sector's last whole PWM period (then the pair is held over the",
            "whole sector, uneased, and the time is the sector). The main duty is not used.",
        )
        formats: dict[str, int | float | str] = {
            "counts_frac_bits": r.counts_frac_bits,
            "search_steps": r.steps,
            "ramp_frac_bits": r.ramp_frac_bits,
            "growth_frac_bits": r.growth_frac_bits,
            "decay_table_rows": len(r.decay),
            "decay_table_bytes": 4 * len(r.decay),  # D^(2^k) as one uint32_t (2^k is a shift)
            "carrier_ticks": str(Fraction(int(tau.p), int(tau.q))),
            "emf_shape": shape.description,
            "current_scale": m,
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
                time_region="where the turn-off current is clearly on either side of zero at "
                "the carrier boundaries around the end (design grid)",
            ),
            formats=formats,
            summary=(
                f"improved_r, counts in Q{r.counts_frac_bits}, {r.steps}-step carrier-grid search,"
                f" decay table {len(r.decay)} rows ({4 * len(r.decay)} B), EMF {shape.description};"
                f" bounds over the design grid: duties {round_up_f(design.duty_bound)} counts,"
                f" t_com {round_up_f(design.ticks_bound)} ticks"
            ),
        )


def round_up_f(value: float) -> float:
    return round_up(Fraction(value))


METHOD = ImprovedR()
__all__ = ["METHOD"]

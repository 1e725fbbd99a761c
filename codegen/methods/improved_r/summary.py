"""`python -m codegen.methods.improved_r SPEC`: the firmware rule's design as Markdown.

Constants with their equations, formats, the table, every proven range, and the integer
prototype's measured error against the real-arithmetic reference over a grid (the
design grid plus random points of the braking range), next to its pointwise bounds.
"""

from __future__ import annotations

import random
import sys
from dataclasses import dataclass

from codegen.core.module import build_core, twin_module
from codegen.methods.improved_r.accuracy import point_bound
from codegen.methods.improved_r.constants import rule_constants
from codegen.methods.improved_r.design import RuleDesign, design_grid, design_rule
from codegen.methods.improved_r.fixed import THETA_FRAC_BITS
from codegen.methods.improved_r.reference import RuleInputs, reference_points
from codegen.spec_loader import load_spec

RANDOM_POINTS = 400


@dataclass(frozen=True)
class ErrorStats:
    points: int
    unflagged: int
    ticks_max: float  # measured |ticks - x_c T|, unflagged points
    ticks_max_conditioned: float  # the same where t_half <= the time target
    counts_max: float  # measured |C - C(x_c)|, unflagged points
    ticks_max_flagged: float  # measured, all points
    counts_max_flagged: float
    bound_ratio_max: float  # time bound / max(target, t_half), unflagged


def error_stats(design: RuleDesign, braking_codes: int, twin: object, seed: int = 1) -> ErrorStats:
    """The printed rule (the twin of the C) against the reference over the grid."""
    rule = design.rule
    c = rule.constants
    rng = random.Random(seed)
    grid = design_grid(c, braking_codes) + [
        RuleInputs(
            rng.randint(c.period_low, c.period_high),
            rng.randint(c.bus_low, c.bus_high),
            c.current_offset + rng.randint(0, braking_codes),
        )
        for _ in range(RANDOM_POINTS)
    ]
    target = float(c.time_target_ticks)
    ticks = conditioned = counts = ticks_all = counts_all = ratio = 0.0
    unflagged = 0
    for inputs, ref in zip(grid, reference_points(c, grid), strict=True):
        out = twin.commutation_timing(
            twin.bus_condition(inputs.bus_code), inputs.period_ticks, inputs.current_code, 0
        )  # type: ignore[attr-defined]
        dt = abs(out.commutation_ticks - min(ref.ticks_exact, inputs.period_ticks))
        dc = max(abs(out.turn_on_compare - ref.on_exact), abs(out.turn_off_compare - ref.off_exact))
        ticks_all, counts_all = max(ticks_all, dt), max(counts_all, dc)
        if ref.outputs.flags:
            continue
        unflagged += 1
        ticks, counts = max(ticks, dt), max(counts, dc)
        bound = point_bound(rule, inputs, ref)
        ratio = max(ratio, bound.ticks / bound.time_allowance(target))
        if bound.half_count_ticks <= target:
            conditioned = max(conditioned, dt)
    return ErrorStats(
        len(grid), unflagged, ticks, conditioned, counts, ticks_all, counts_all, ratio
    )


def summary_lines(spec_path: str) -> list[str]:
    spec = load_spec(spec_path)
    core = build_core(spec)
    sc = core.scaling
    c = rule_constants(spec, sc)
    design = design_rule(c, sc.current_code_max, core.limits)
    r = design.rule
    t = r.table
    stats = error_stats(design, sc.current_code_max, twin_module(core))
    lines = [
        f"# improved_r design: {spec.name}",
        "",
        "## Constants",
        "",
        f"* P = {c.period_counts} counts, f_hall = {c.hall_clock_hz} Hz",
        f"* K_X = 4 P 10 k_e f_hall / (p v_bus) = {c.k_x} ({float(c.k_x):.6g}); X = K_X/(T B)",
        f"* K_Y = 3 P R a_i / v_bus = {c.k_y} ({float(c.k_y):.6g}); Y = K_Y i / B",
        f"* kappa = 3 L p a_i / (40 k_e) = {c.kappa} ({float(c.kappa):.6g}); A = kappa i X",
        f"* K_rho = R / (L f_hall) = {c.k_rho} ({float(c.k_rho):.6g}); rho = K_rho T",
        f"* theta = {c.ramp_weight} ({float(c.ramp_weight):.6f}), stored as theta/2 in "
        f"Q{THETA_FRAC_BITS}: {r.theta_half_q}",
        f"* T in [{c.period_low}, {c.period_high}] ticks, B in [{c.bus_low}, {c.bus_high}],"
        f" i in [0, {c.current_high}] (offset {c.current_offset})",
        "",
        "## Formats",
        "",
        f"* counts Q{r.counts_frac_bits}; N_X = {r.n_x.numerator} (shift {r.n_x.shift}),"
        f" N_Y = {r.n_y.numerator} (Q{r.counts_frac_bits + r.y_guard_bits}, shift {r.n_y.shift})",
        f"* KAPPA = {r.kappa_q} (Q{r.kappa_frac_bits}), KRHO = {r.k_rho_q} (Q{r.rho_frac_bits})",
        f"* bisection K = {r.steps} steps, x in Q{r.steps}; units (e, u1, v2) Q{r.unit_frac_bits};"
        f" y Q{t.y_frac_bits}, y = (RHO x) >> {r.y_shift}",
        "",
        "## Table",
        "",
        f"* {t.entries} rows x 2 uint16 ({t.flash_bytes} bytes): {t.segments} octave segments"
        f" of 2^{t.segment_bits} entries, y < 2^{t.segments - 1}",
        f"* error bound psi1 {t.error1:.2e}, psi2 {t.error2:.2e}",
        "",
        "## Accuracy (integer prototype against the real-arithmetic reference)",
        "",
        f"* design grid: worst time bound {design.ticks_bound:.2f} ticks, bound/allowance"
        f" {design.time_ratio:.3f}, duty bound {design.duty_bound:.3f} counts"
        f" ({design.grid_points} unflagged points)",
        f"* measured over {stats.points} points ({stats.unflagged} unflagged):"
        f" |ticks| <= {stats.ticks_max:.2f} ({stats.ticks_max_conditioned:.2f} where"
        f" t_half <= target), |counts| <= {stats.counts_max:.3f}"
        f" (with flagged points: {stats.ticks_max_flagged:.2f} ticks,"
        f" {stats.counts_max_flagged:.3f} counts); bound/allowance <= {stats.bound_ratio_max:.3f}",
        f"* targets: {float(c.time_target_ticks)} ticks (or t_half), "
        f"{float(c.duty_target_counts)} counts",
        "",
        "## Proven ranges",
        "",
        "| quantity | C type | range | headroom bits |",
        "|---|---|---|---|",
    ]
    lines += [
        f"| {p.name} | {p.c_type} | [{p.low}, {p.high}] | {p.headroom_bits:.1f} |"
        for p in design.ranges
    ]
    return lines


def main(argv: list[str] | None = None) -> int:
    args = sys.argv[1:] if argv is None else argv
    if len(args) != 1:
        print("usage: python -m codegen.methods.improved_r SPEC.yaml", file=sys.stderr)
        return 2
    print("\n".join(summary_lines(args[0])))
    return 0

"""`python -m codegen.methods.improved_r SPEC`: the firmware rule's design as Markdown.

Constants with their equations, formats, the decay table, every proven range, and the
integer prototype's measured error against the real-arithmetic reference over a grid
(the design grid plus random points of the braking range), next to the design's bounds.
"""

from __future__ import annotations

import random
import sys
from dataclasses import dataclass

from codegen.core.module import build_core, twin_module
from codegen.methods.improved_r.constants import rule_constants
from codegen.methods.improved_r.design import RuleDesign, design_grid, design_rule
from codegen.methods.improved_r.reference import FLAG_NOT_FINISHED, RuleInputs, reference_points
from codegen.spec_loader import load_spec

RANDOM_POINTS = 400


@dataclass(frozen=True)
class ErrorStats:
    points: int
    finished: int  # points whose commutation ends within the sector
    end_mismatches: int  # finished points whose carrier boundary differs from the reference's
    ticks_max: float  # measured |ticks - end tau|, finished points
    counts_max: float  # measured |C - C_exact| (eased pair), finished points
    counts_max_all: float  # the same over every point


def error_stats(design: RuleDesign, braking_codes: int, twin: object, seed: int = 1) -> ErrorStats:
    """The printed rule (the twin of the C) against the real-arithmetic reference over
    the design grid plus random points of the braking range."""
    c = design.rule.constants
    rng = random.Random(seed)
    grid = design_grid(c, braking_codes) + [
        RuleInputs(
            rng.randint(c.period_low, c.period_high),
            rng.randint(c.bus_low, c.bus_high),
            c.current_offset + rng.randint(0, braking_codes),
        )
        for _ in range(RANDOM_POINTS)
    ]
    ref = reference_points(c, grid)
    tau = float(c.carrier_ticks)
    finished = mismatches = 0
    ticks = counts = counts_all = 0.0
    for k, inputs in enumerate(grid):
        out = twin.commutation_timing(  # type: ignore[attr-defined]
            twin.bus_condition(inputs.bus_code), inputs.period_ticks, inputs.current_code, 0
        )
        dc = max(
            abs(out.turn_on_compare - float(ref.on_exact[k])),
            abs(out.turn_off_compare - float(ref.off_exact[k])),
        )
        counts_all = max(counts_all, dc)
        if ref.flags[k] & FLAG_NOT_FINISHED:
            continue
        finished += 1
        dt = abs(out.commutation_ticks - float(ref.ticks_exact[k]))
        ticks, counts = max(ticks, dt), max(counts, dc)
        mismatches += round(out.commutation_ticks / tau) != int(ref.end[k])
    return ErrorStats(len(grid), finished, mismatches, ticks, counts, counts_all)


def summary_lines(spec_path: str) -> list[str]:
    spec = load_spec(spec_path)
    core = build_core(spec)
    sc = core.scaling
    c = rule_constants(spec, sc)
    design = design_rule(c, sc.current_code_max, core.limits)
    r = design.rule
    fc = r.counts_frac_bits
    stats = error_stats(design, sc.current_code_max, twin_module(core))
    lines = [
        f"# improved_r design: {spec.name}",
        "",
        "## Constants",
        "",
        f"* P = {c.period_counts} counts, f_hall = {c.hall_clock_hz} Hz,"
        f" tau = {c.carrier_ticks} Hall ticks per PWM period",
        f"* K_X = 4 P 10 k_e f_hall / (p v_bus) = {float(c.k_x):.6g}; X = K_X/(T B)",
        f"* K_Y = 3 P R a_i / v_bus = {float(c.k_y):.6g}; Y = K_Y i / B",
        f"* kappa = 3 L p a_i / (40 k_e) = {float(c.kappa):.6g}; A = kappa i X",
        f"* K_rho = R / (L f_hall) = {float(c.k_rho):.6g}; rho = K_rho T;"
        f" y_1 = K_rho tau = {float(c.step_decay):.6g}",
        f"* EMF shape: {c.shape.description}; theta = {float(c.ramp_weight):.6f};"
        f" hold slope {float(c.hold_slope):.6g} X per sector,"
        f" ramp forcing {float(c.ramp_per_x):.6g} X per sector",
        f"* T in [{c.period_low}, {c.period_high}] ticks, B in [{c.bus_low}, {c.bus_high}],"
        f" i in [0, {c.current_high}] (offset {c.current_offset})",
        "",
        "## Formats",
        "",
        f"* counts Q{fc}; N_X = {r.n_x.numerator} (shift {r.n_x.shift});"
        f" KYX = {r.kyx} (shift {r.kyx_shift}), KAR = {r.kar} (shift {r.kar_shift})",
        f"* ramp q in Q{fc + r.ramp_frac_bits} (QC = {r.qc}, shift {r.qc_shift});"
        f" growth in Q{fc + r.growth_frac_bits} (HS = {r.hs}, shift {r.hs_shift});"
        f" y_1 = {r.y1} (Q{32 - r.ramp_frac_bits})",
        f"* search: {r.steps} steps of binary lifting over N <= {r.periods_max} whole PWM"
        f" periods; N = floor(T {r.periods_num} / {r.periods_den})",
        "",
        "## Decay table",
        "",
        f"* {len(r.decay)} rows x D^(2^k) Q32 uint32 ({4 * len(r.decay)} bytes), D = e^-y_1; the"
        " row's 2^k is a shift of the step",
        "",
        "## Accuracy (integer prototype against the real-arithmetic reference)",
        "",
        f"* design grid: duty bound {design.duty_bound:.3f} counts at all {design.grid_points}"
        f" points, time bound {design.ticks_bound:.2f} ticks where the end is decided"
        f" ({design.decided_points} of them)",
        f"* measured over {stats.points} points ({stats.finished} ending within the sector):"
        f" the carrier boundary differs from the reference's at {stats.end_mismatches},"
        f" |ticks| <= {stats.ticks_max:.2f}, |counts| <= {stats.counts_max:.3f}"
        f" ({stats.counts_max_all:.3f} with the points that do not end)",
        f"* targets: {float(c.time_target_ticks)} ticks, {float(c.duty_target_counts)} counts",
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

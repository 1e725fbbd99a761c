"""The simulation report: numbers printed here, laid out by a strict Jinja template.

Everything in the context is a ready string, a number already formatted, a boolean
or a list of those (the project's "print in Python, lay out in templates"). No
timings or versions go into the report, so reruns are byte-identical.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from pathlib import Path

import jinja2
import sympy as sp

from codegen.derivation import derive
from codegen.fixedpoint.scaling import scaling
from codegen.render import PROJECT_ROOT, environment, project_relative
from codegen.spec_loader import load_spec
from sim.clamp import ClampScan
from sim.drive import Drive
from sim.limits import Limits
from sim.metrics import CommutationMetrics, acts_like_main_duty
from sim.resistance import derive_resistance_rule
from sim.runs import IDEAL_METHODS, IMPROVED_R, METHODS, Run
from sim.sweep import DEFAULT_SHAPE, POINT_POLICIES, STEADY, Results, SweepRow

TEMPLATE_DIR = Path(__file__).resolve().parent / "templates"
TEMPLATE = "SIMULATION.md.j2"
#: The resistance-aware method's target: on the default motor (R = 0.21 ohm), at the
#: spec's braking current and 20 kHz, in the switched model, the non-commutating current
#: deviation stays within +-3 % from 500 to 4600 rpm.
TARGET_LOW_RPM, TARGET_HIGH_RPM, TARGET_PCT = 500.0, 4600.0, 3.0
TARGET_SPEC = PROJECT_ROOT / "spec" / "paper_motor.yaml"
#: The paper's figure numbers for (operating point index, method, main-duty policy), by
#: the text: only Fig. 13 states the main duty (about 42 %), the others are taken at
#: the duty that holds the current.
PAPER_FIGURES = {
    (0, "none", STEADY): 10,
    (0, "improved", STEADY): 11,
    (1, "none", STEADY): 12,
    (1, "conventional", "point"): 13,
    (1, "improved", STEADY): 14,
}


def _environment() -> jinja2.Environment:
    return environment(TEMPLATE_DIR)


def pct(value: float | None) -> str:
    return "n/a" if value is None else f"{value:+.1f} %"


def frac(value: float | None) -> str:
    return "not within 60 deg" if value is None else f"{value:.2f}"


def flags(names: tuple[str, ...]) -> str:
    return ", ".join(names) if names else "-"


@dataclass(frozen=True)
class _Lookup:
    results: Results

    def row(
        self,
        method: str,
        speed: float,
        model: str = "switched",
        shape: str = DEFAULT_SHAPE,
        policy: str = STEADY,
    ) -> SweepRow:
        rows = self.results.rows(
            method=method, speed_rpm=speed, model=model, emf_shape=shape, duty_policy=policy
        )
        return rows[0]


def _metrics_cells(m: CommutationMetrics) -> dict[str, str]:
    return {
        "worst": pct(m.deviation_worst_pct),
        "mean": pct(m.deviation_mean_pct),
        "ripple": f"{m.torque_ripple_pct:.1f} %",
        "fraction": frac(m.commutation_fraction),
        "commanded": f"{m.commanded_fraction:.2f}",
        "transitions": "-"
        if m.on_transitions is None
        else f"{m.on_transitions} / {m.off_transitions}",
        "pulses": "-" if m.on_pulses is None else f"{m.on_pulses} / {m.off_pulses}",
    }


def _operating_rows(results: Results) -> list[dict[str, object]]:
    out: list[dict[str, object]] = []
    for point in results.operating:
        for method in METHODS:
            steady = point.runs[(method, "switched", STEADY)]
            at_point = point.metrics.get((method, "switched", "point"))
            point_run = point.runs.get((method, "switched", "point"))
            out.append(
                {
                    "speed": f"{point.speed_rpm:g}",
                    "method": method,
                    "steady_duty": f"{steady.command.main_duty:.3f}",
                    "duties": f"{steady.command.on_duty(0):.3f} / {steady.command.off_duty(0):.3f}",
                    "flags": flags(point.flags[(method, STEADY)]),
                    "steady": _metrics_cells(point.metrics[(method, "switched", STEADY)]),
                    "averaged_worst": pct(
                        point.metrics[(method, "averaged", STEADY)].deviation_worst_pct
                    ),
                    "has_point": at_point is not None,
                    "point_duty": f"{point.main_duty:g}",
                    "point_duties": "-"
                    if point_run is None
                    else f"{point_run.command.on_duty(0):.3f} / {point_run.command.off_duty(0):.3f}",
                    "point_flags": flags(point.flags.get((method, "point"), ())),
                    "point": _metrics_cells(at_point) if at_point is not None else {},
                }
            )
    return out


def _sweep_rows(results: Results, lookup: _Lookup) -> list[dict[str, str]]:
    speeds = sorted({r.speed_rpm for r in results.sweep})
    policies = sorted({r.duty_policy for r in results.sweep} - {STEADY})
    out = []
    for speed in speeds:
        cells = {"speed": f"{speed:g}"}
        for method in (*METHODS, *IDEAL_METHODS):
            row = lookup.row(method, speed)
            cells[method] = pct(row.metrics.deviation_worst_pct)
            cells[f"{method}_flat"] = pct(
                lookup.row(method, speed, shape="flat").metrics.deviation_worst_pct
            )
            cells[f"{method}_averaged"] = pct(
                lookup.row(method, speed, model="averaged").metrics.deviation_worst_pct
            )
            cells[f"{method}_ripple"] = f"{row.metrics.torque_ripple_pct:.0f}"
            cells[f"{method}_fraction"] = frac(row.metrics.commutation_fraction)
        fixed = []
        for policy in policies:
            row = lookup.row("conventional", speed, policy=policy)
            mark = " (fail area)" if "FAIL_AREA_CLAMPED" in row.flags else ""
            fixed.append(f"{pct(row.metrics.deviation_worst_pct)}{mark}")
        cells["fixed"] = "; ".join(fixed)
        out.append(cells)
    return out


def _claims(results: Results, lookup: _Lookup) -> dict[str, object]:
    """The paper's qualitative claims (brief item 7), each with its evidence."""
    beats = []
    for point in results.operating:
        improved = point.metrics[("improved", "switched", STEADY)]
        for policy_name, none in (
            ("steady-state main duty", point.metrics[("none", "switched", STEADY)]),
            (f"spec main duty {point.main_duty:g}", point.metrics[("none", "switched", "point")]),
        ):
            beats.append(
                {
                    "speed": f"{point.speed_rpm:g}",
                    "policy": policy_name,
                    "improved": pct(improved.deviation_worst_pct),
                    "none": pct(none.deviation_worst_pct),
                    "improved_ripple": f"{improved.torque_ripple_pct:.1f} %",
                    "none_ripple": f"{none.torque_ripple_pct:.1f} %",
                    "holds": abs(improved.deviation_worst_pct) < abs(none.deviation_worst_pct),
                }
            )
    single = []
    for point in results.operating:
        rule = point.runs[(IMPROVED_R, "switched", STEADY)].command
        total = rule.on_duty(0) + rule.off_duty(0)
        single.append(
            {
                "speed": f"{point.speed_rpm:g}",
                "sum": f"{total:.3f}",
                "duty": f"{point.main_duty:g}",
                "close": abs(total - point.main_duty) < 0.15,
            }
        )
    fail = [
        {
            "speed": f"{p.speed_rpm:g}",
            "duty": f"{p.main_duty:g}",
            "flags": flags(p.flags[("conventional", "point")]),
            "in_fail_area": "FAIL_AREA_CLAMPED" in p.flags[("conventional", "point")],
            "off_duty": f"{p.runs[('conventional', 'switched', 'point')].command.off_duty(0):.3f}",
        }
        for p in results.operating
    ]
    low = [
        r
        for r in results.rows(
            method="improved", model="switched", emf_shape=DEFAULT_SHAPE, duty_policy=STEADY
        )
        if r.speed_rpm <= results.drive.boundary_speed_rpm
    ]
    static = all(
        r.on_duty == 1.0 and r.metrics.on_transitions is not None and r.metrics.on_transitions <= 1
        for r in low
    )
    fewer = []
    for paper_row in results.table4:
        speed = float(paper_row.speed_rpm)
        improved = lookup.row("improved", speed).metrics
        conventional = lookup.row("conventional", speed).metrics
        total_i = (improved.on_transitions or 0) + (improved.off_transitions or 0)
        total_c = (conventional.on_transitions or 0) + (conventional.off_transitions or 0)
        fewer.append(
            {
                "speed": f"{speed:g}",
                "improved": total_i,
                "conventional": total_c,
                "holds": total_i < total_c,
            }
        )
    return {
        "beats": beats,
        "beats_all": all(b["holds"] for b in beats),
        "single": single,
        "fail": fail,
        "fail_any": any(f["in_fail_area"] for f in fail),
        "static": static,
        "static_speeds": f"{low[0].speed_rpm:g}-{low[-1].speed_rpm:g}" if low else "-",
        "fewer": fewer,
        "fewer_all": all(f["holds"] for f in fewer),
    }


def _table4(results: Results, lookup: _Lookup) -> list[dict[str, str]]:
    out = []
    for row in results.table4:
        speed = float(row.speed_rpm)
        conventional = lookup.row("conventional", speed).metrics
        improved = lookup.row("improved", speed).metrics
        out.append(
            {
                "speed": f"{speed:g}",
                "region": "low" if speed <= results.drive.boundary_speed_rpm else "high",
                "paper_conventional": f"{row.conventional_on} / {row.conventional_off}",
                "paper_improved": f"{row.improved_on} / {row.improved_off}",
                "sim_conventional": _metrics_cells(conventional)["pulses"],
                "sim_improved": _metrics_cells(improved)["pulses"],
                "sim_conventional_tr": _metrics_cells(conventional)["transitions"],
                "sim_improved_tr": _metrics_cells(improved)["transitions"],
                "conventional_time": f"{lookup.row('conventional', speed).commanded_time_s * 1e6:.0f}",
                "improved_time": f"{lookup.row('improved', speed).commanded_time_s * 1e6:.0f}",
            }
        )
    return out


def _optimum_rows(results: Results) -> list[dict[str, str]]:
    out = []
    for row in results.optima:
        o = row.optimum
        out.append(
            {
                "shape": row.emf_shape,
                "speed": f"{o.speed_rpm:g}",
                "duties": f"{o.on_duty:.3f} / {o.off_duty:.3f}",
                "time": f"{o.commutation_time_s * 1e6:.0f}",
                "rms": f"{o.rms_deviation_pct:.2f} %",
                "status": o.solver_status,
                **{key: pct(value) for key, value in row.worst_pct.items()},
            }
        )
    return out


def _target(results: Results, lookup: _Lookup) -> dict[str, object]:
    """The resistance-aware method (C core) against its target, speed by speed, next to
    the paper's rule and the per-period ideal."""
    speeds = sorted({r.speed_rpm for r in results.sweep})
    in_target = [s for s in speeds if TARGET_LOW_RPM <= s <= TARGET_HIGH_RPM]
    rows = []
    for speed in speeds:
        rule = lookup.row(IMPROVED_R, speed)
        raw = rule.core_outputs
        rows.append(
            {
                "speed": f"{speed:g}",
                "in_target": TARGET_LOW_RPM <= speed <= TARGET_HIGH_RPM,
                "improved": pct(lookup.row("improved", speed).metrics.deviation_worst_pct),
                "improved_r": pct(rule.metrics.deviation_worst_pct),
                "within": abs(rule.metrics.deviation_worst_pct) <= TARGET_PCT,
                "compares": f"{raw['turn_on_compare']} / {raw['turn_off_compare']}",
                "ticks": f"{raw['commutation_ticks']} / {raw['in.hall_period_ticks']}",
                "measured": frac(rule.metrics.commutation_fraction),
                "flags": flags(rule.flags),
                "flat": pct(
                    lookup.row(IMPROVED_R, speed, shape="flat").metrics.deviation_worst_pct
                ),
                "averaged": pct(
                    lookup.row(IMPROVED_R, speed, model="averaged").metrics.deviation_worst_pct
                ),
                "per_period": pct(lookup.row(IDEAL_METHODS[0], speed).metrics.deviation_worst_pct),
            }
        )

    def worst(method: str, shape: str = DEFAULT_SHAPE, model: str = "switched") -> SweepRow:
        picked = [lookup.row(method, s, model=model, shape=shape) for s in in_target]
        return max(picked, key=lambda r: abs(r.metrics.deviation_worst_pct))

    main, flat, averaged = (
        worst(IMPROVED_R),
        worst(IMPROVED_R, "flat"),
        worst(IMPROVED_R, model="averaged"),
    )
    paper = worst("improved")
    ideal = worst(IDEAL_METHODS[0])
    covers = speeds[0] <= TARGET_LOW_RPM and speeds[-1] >= TARGET_HIGH_RPM
    lengths = [
        lookup.row(IMPROVED_R, s).commanded_time_s / results.drive.pwm_period_s for s in in_target
    ]
    ripples = [lookup.row(IMPROVED_R, s).metrics.pre_edge_ripple_pct for s in in_target]
    return {
        "low": f"{TARGET_LOW_RPM:g}",
        "high": f"{TARGET_HIGH_RPM:g}",
        "tolerance": f"{TARGET_PCT:g}",
        "is_target_spec": _is_target_motor(results.drive),
        "target_spec": project_relative(TARGET_SPEC),
        "rows": rows,
        "worst": pct(main.metrics.deviation_worst_pct),
        "worst_speed": f"{main.speed_rpm:g}",
        "flat_worst": pct(flat.metrics.deviation_worst_pct),
        "flat_speed": f"{flat.speed_rpm:g}",
        "averaged_worst": pct(averaged.metrics.deviation_worst_pct),
        "averaged_speed": f"{averaged.speed_rpm:g}",
        "paper_worst": pct(paper.metrics.deviation_worst_pct),
        "paper_speed": f"{paper.speed_rpm:g}",
        "ideal_worst": pct(ideal.metrics.deviation_worst_pct),
        "ideal_speed": f"{ideal.speed_rpm:g}",
        "met": abs(main.metrics.deviation_worst_pct) <= TARGET_PCT,
        "outside": ", ".join(
            f"{s:g}"
            for s in in_target
            if abs(lookup.row(IMPROVED_R, s).metrics.deviation_worst_pct) > TARGET_PCT
        ),
        "covers_range": covers,
        "periods_low": f"{min(lengths):.1f}" if lengths else "-",
        "periods_high": f"{max(lengths):.1f}" if lengths else "-",
        "ripple_low": f"{min(ripples):.0f}" if ripples else "-",
        "ripple_high": f"{max(ripples):.0f}" if ripples else "-",
    }


def _is_target_motor(drive: Drive) -> bool:
    """The drive is the default motor's (any controller method, any spec name)."""
    default = Drive.from_spec(load_spec(TARGET_SPEC))
    return replace(default, name=drive.name) == drive


def _speed_ranges(ranges: tuple[tuple[float, float], ...]) -> str:
    return ", ".join(f"{low:.0f}-{high:.0f} rpm" for low, high in ranges) or "nowhere"


def _clamps(results: Results) -> dict[str, object]:
    """Where each timed core flags TIME_CLAMPED (every Hall period of the speed range)."""
    scans: list[ClampScan] = list(results.clamps)
    rows = []
    for current in sorted({s.current_a for s in scans}):
        for bus in sorted({s.bus_voltage_v for s in scans}):
            cells: dict[str, object] = {"current": f"{current:g}", "bus": f"{bus:g}"}
            for scan in scans:
                if scan.current_a == current and scan.bus_voltage_v == bus:
                    cells[scan.method] = _speed_ranges(scan.clamped_rpm)
            rows.append(cells)

    def nominal(method: str) -> ClampScan:
        drive = results.drive
        return next(
            s
            for s in scans
            if s.method == method
            and s.bus_voltage_v == drive.bus_voltage_v
            and s.current_a == drive.braking_current_a
        )

    top = _top_row(results)
    return {
        "rows": rows,
        "periods": f"{scans[0].periods}" if scans else "0",
        "improved_nominal": _speed_ranges(nominal("improved").clamped_rpm),
        "improved_r_nominal": _speed_ranges(nominal(IMPROVED_R).clamped_rpm),
        "improved_r_any": any(s.clamped_rpm for s in scans if s.method == IMPROVED_R),
        "top_speed": f"{top.speed_rpm:g}",
        "top_fraction": f"{top.metrics.commanded_fraction:.2f}",
        "top_measured": frac(top.metrics.commutation_fraction),
        "fastest": "-"
        if nominal(IMPROVED_R).fastest_rpm is None
        else f"{nominal(IMPROVED_R).fastest_rpm:.0f}",
    }


def _top_row(results: Results) -> SweepRow:
    """improved_r at the highest swept speed (switched, trapezoidal, steady duty)."""
    rows = results.rows(
        method=IMPROVED_R, model="switched", emf_shape=DEFAULT_SHAPE, duty_policy=STEADY
    )
    return max(rows, key=lambda r: r.speed_rpm)


def _latex(expr: sp.Basic) -> str:
    return sp.latex(expr)


def _rule_context(limits: Limits) -> dict[str, str]:
    rule = derive_resistance_rule()
    return {
        "duty_sum": _latex(rule.duty_sum),
        "duty_sum_flat": _latex(rule.duty_sum_flat),
        "boundary_emf": _latex(rule.boundary_emf),
        "lowest_emf": _latex(rule.lowest_emf),
        "finish_low": _latex(rule.finish_emf_low),
        "finish_high": _latex(rule.finish_emf_high),
        "off_low": _latex(rule.off_slope_low),
        "off_high": _latex(rule.off_slope_high),
        "t_low": _latex(rule.commutation_time_low),
        "t_high": _latex(rule.commutation_time_high),
        "boundary_paper": f"{limits.boundary_paper_rpm:.0f}",
        "boundary_r": f"{limits.boundary_r_rpm:.0f}",
        "lowest_hold": f"{limits.lowest_hold_rpm:.0f}",
        "finish_low_rpm": f"{limits.finish_low_rpm:.0f}",
        "finish_high_rpm": f"{limits.finish_high_rpm:.0f}",
        "paper_fits": f"{limits.paper_time_fits_below_rpm:.0f}",
        "r_fits": f"{limits.r_time_fits_below_rpm:.0f}",
    }


def _unfinished(results: Results) -> list[dict[str, str]]:
    """Sweep points where the commutation is clamped or does not finish within 60 deg."""
    out = []
    for row in results.rows(model="switched", emf_shape=DEFAULT_SHAPE, duty_policy=STEADY):
        clamped = "TIME_CLAMPED" in row.flags
        if clamped or not row.metrics.finished:
            out.append(
                {
                    "speed": f"{row.speed_rpm:g}",
                    "method": row.method,
                    "commanded": f"{row.metrics.commanded_fraction:.2f}",
                    "measured": frac(row.metrics.commutation_fraction),
                    "flags": flags(row.flags),
                }
            )
    return out


def _figure_note(run: Run, metrics: CommutationMetrics, names: tuple[str, ...]) -> str:
    """One sentence on what the figure shows, from the run's own numbers."""
    parts = []
    if "FAIL_AREA_CLAMPED" in names:
        parts.append(
            "Eq. 16 asks for a turn-off duty outside [0, 1] and the core clamps it: the"
            " control fail area, so the method acts like another duty pair than it intends."
        )
    if metrics.commutation_fraction is None:
        parts.append(
            "The turn-off current does not reach zero within the 60 deg interval: the"
            " turn-on phase is not driven hard enough to take over."
        )
    elif "TIME_CLAMPED" in names:
        parts.append("Eq. 20 exceeds the Hall period and is clamped to it.")
    worst = metrics.deviation_worst_pct
    if abs(worst) <= TARGET_PCT:
        parts.append("The non-commutating current stays within the ripple band.")
    elif worst < 0:
        parts.append(
            "The non-commutating current sags (paper Fig. 4 b): the turn-off current falls"
            " faster than the turn-on current rises, or R drains it."
        )
    else:
        parts.append(
            "The non-commutating current swells (paper Fig. 4 c): the turn-on current rises"
            " faster than the turn-off current falls."
        )
    if metrics.commutation_fraction is not None and not acts_like_main_duty(run.command):
        ratio = metrics.commanded_fraction / metrics.commutation_fraction
        if ratio > 1.2:
            parts.append(
                f"The commanded commutation lasts {ratio:.1f} times as long as the turn-off"
                " current needs, and the commutation duties keep acting after it is zero."
            )
        elif ratio < 0.8:
            parts.append(
                "The commanded commutation ends before the turn-off current is zero; it"
                " then decays through its diode."
            )
    return " ".join(parts)


def _figures(results: Results, names: dict[str, str]) -> list[dict[str, str]]:
    out = []
    for index, point in enumerate(results.operating):
        for policy, methods in POINT_POLICIES.items():
            for method in methods:
                figure = PAPER_FIGURES.get((index, method, policy))
                run = point.runs[(method, "switched", policy)]
                metrics = point.metrics[(method, "switched", policy)]
                duty = "steady-state" if policy == STEADY else "the spec's"
                out.append(
                    {
                        "file": names[f"currents:{point.speed_rpm:g}:{method}:{policy}"],
                        "speed": f"{point.speed_rpm:g}",
                        "method": method,
                        "duty": f"{duty} main duty {run.command.main_duty:.3f}",
                        "paper": f"analogue of the paper's Fig. {figure}"
                        if figure
                        else "no counterpart in the paper",
                        "worst": pct(metrics.deviation_worst_pct),
                        "note": _figure_note(run, metrics, point.flags[(method, policy)]),
                    }
                )
    return out


def render_report(results: Results, limits: Limits, figure_names: dict[str, str]) -> str:
    spec = results.spec
    drive = results.drive
    lookup = _Lookup(results)
    context = {
        "spec_path": project_relative(spec.source_path),
        "spec_sha256": spec.sha256,
        "spec_name": spec.name,
        "template": f"sim/templates/{TEMPLATE}",
        "drive": {
            "resistance": f"{drive.resistance_ohm:g}",
            "inductance_mh": f"{drive.inductance_h * 1e3:g}",
            "time_constant_ms": f"{drive.inductance_h / drive.resistance_ohm * 1e3:.2f}",
            "k_e": f"{drive.emf_v_per_rpm * 1e3:g}",
            "pole_pairs": str(drive.pole_pairs),
            "bus": f"{drive.bus_voltage_v:g}",
            "current": f"{drive.braking_current_a:g}",
            "pwm_khz": f"{drive.pwm_frequency_hz / 1e3:g}",
            "alignment": drive.pwm_alignment,
            "upper": f"{drive.upper_speed_rpm:.0f}",
            "speed_max": f"{drive.speed_max_rpm:g}",
        },
        "sweep_low": f"{min(r.speed_rpm for r in results.sweep):g}",
        "sweep_high": f"{max(r.speed_rpm for r in results.sweep):g}",
        "fixed_policies": ", ".join(sorted({r.duty_policy for r in results.sweep} - {STEADY})),
        "operating": _operating_rows(results),
        "operating_speeds": " and ".join(f"{p.speed_rpm:g}" for p in results.operating),
        "sweep": _sweep_rows(results, lookup),
        "claims": _claims(results, lookup),
        "table4": _table4(results, lookup),
        "optima": _optimum_rows(results),
        "target": _target(results, lookup),
        "clamps": _clamps(results),
        "rule": _rule_context(limits),
        "unfinished": _unfinished(results),
        "figures": _figures(results, figure_names),
        "figure_names": figure_names,
        "methods": list(METHODS),
        "ideal": IDEAL_METHODS[0],
        "period_counts": str(scaling(spec, derive()).period_counts),
    }
    return _environment().get_template(TEMPLATE).render(**context)

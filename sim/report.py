"""The simulation report: numbers printed here, laid out by a strict Jinja template.

Everything in the context is a ready string, a number already formatted, a boolean
or a list of those (the project's "print in Python, lay out in templates"). No
timings or versions go into the report, so reruns are byte-identical.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import jinja2
import sympy as sp

from codegen.render import environment, project_relative
from sim.improved_r import METHOD as IMPROVED_R
from sim.limits import Limits
from sim.metrics import CommutationMetrics, acts_like_main_duty
from sim.resistance import derive_resistance_rule
from sim.runs import METHODS, Run
from sim.sweep import DEFAULT_SHAPE, POINT_POLICIES, STEADY, Results, SweepRow

TEMPLATE_DIR = Path(__file__).resolve().parent / "templates"
TEMPLATE = "SIMULATION.md.j2"
#: The speed range of the brief's improved_r target, and its tolerance in %.
TARGET_LOW_RPM, TARGET_HIGH_RPM, TARGET_PCT = 500.0, 4600.0, 3.0
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
        for method in METHODS:
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
    def worst(shape: str, model: str = "switched") -> tuple[float, float]:
        rows = [
            lookup.row(IMPROVED_R, s, model=model, shape=shape)
            for s in sorted({r.speed_rpm for r in results.sweep})
            if TARGET_LOW_RPM <= s <= TARGET_HIGH_RPM
        ]
        pick = max(rows, key=lambda r: abs(r.metrics.deviation_worst_pct))
        return pick.metrics.deviation_worst_pct, pick.speed_rpm

    value, speed = worst(DEFAULT_SHAPE)
    flat_value, flat_speed = worst("flat")
    averaged_value, averaged_speed = worst(DEFAULT_SHAPE, "averaged")
    swept = [r.speed_rpm for r in results.sweep]
    in_range = min(swept) <= TARGET_LOW_RPM and max(swept) >= TARGET_HIGH_RPM
    in_target = [
        lookup.row(IMPROVED_R, s)
        for s in sorted(set(swept))
        if TARGET_LOW_RPM <= s <= TARGET_HIGH_RPM
    ]
    ripples = [r.metrics.pre_edge_ripple_pct for r in in_target]
    period = results.drive.pwm_period_s
    lengths = [r.commanded_time_s / period for r in in_target]
    return {
        "low": f"{TARGET_LOW_RPM:g}",
        "high": f"{TARGET_HIGH_RPM:g}",
        "tolerance": f"{TARGET_PCT:g}",
        "worst": pct(value),
        "worst_speed": f"{speed:g}",
        "flat_worst": pct(flat_value),
        "flat_speed": f"{flat_speed:g}",
        "averaged_worst": pct(averaged_value),
        "averaged_speed": f"{averaged_speed:g}",
        "met": abs(value) <= TARGET_PCT and abs(flat_value) <= TARGET_PCT,
        "periods_low": f"{min(lengths):.1f}",
        "periods_high": f"{max(lengths):.1f}",
        "ripple_low": f"{min(ripples):.0f}",
        "ripple_high": f"{max(ripples):.0f}",
        "covers_range": in_range,
    }


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
        "rule": _rule_context(limits),
        "unfinished": _unfinished(results),
        "figures": _figures(results, figure_names),
        "figure_names": figure_names,
        "methods": list(METHODS),
    }
    return _environment().get_template(TEMPLATE).render(**context)

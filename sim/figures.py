"""PNG figures of the simulation (matplotlib, Agg backend, byte-stable output).

Byte stability: the Agg backend, a fixed size and dpi, no timestamps, and PNG metadata
without the "Software" entry that would carry the matplotlib version.
"""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt
import numpy as np

from sim.runs import IDEAL_METHODS, IMPROVED_R, METHODS
from sim.scenario import Case
from sim.studies import RULES
from sim.sweep import DEFAULT_SHAPE, STEADY, OperatingPoint, Results, figure_keys

DPI = 110
METHOD_COLOURS = {
    "none": "tab:gray",
    "conventional": "tab:orange",
    "improved": "tab:blue",
    "improved_r": "tab:green",
    "improved_r_pp": "tab:cyan",
    "optimum": "black",
}
PHASE_COLOURS = ("tab:red", "tab:olive", "tab:purple")
PHASE_NAMES = ("A", "B", "C")


def _save(fig: plt.Figure, path: Path) -> None:
    try:
        fig.savefig(path, dpi=DPI, metadata={"Software": None})
    except OSError as exc:  # matplotlib's has no file name: "No space left on device" alone
        raise OSError(exc.errno, exc.strerror or str(exc), str(path)) from exc
    finally:
        plt.close(fig)


def _role_label(case: Case, phase: int) -> str:
    roles = {case.edge.non_commutating: "non-commutating", case.edge.turn_off: "turn-off"}
    roles[case.edge.turn_on] = "turn-on"
    return f"i_{PHASE_NAMES[phase].lower()} ({roles[phase]})"


def currents_figure(point: OperatingPoint, method: str, policy: str, out: Path) -> str:
    """Three phase currents through one commutation (analogue of Figs. 10-14)."""
    switched = point.runs[(method, "switched", policy)]
    averaged = point.runs[(method, "averaged", policy)]
    case = switched.case
    fig, ax = plt.subplots(figsize=(7.0, 3.8))
    for phase in range(3):
        colour = PHASE_COLOURS[phase]
        ax.plot(
            switched.trace.times * 1e3,
            switched.trace.currents[:, phase],
            color=colour,
            lw=0.8,
            label=_role_label(case, phase),
        )
        ax.plot(
            averaged.trace.times * 1e3,
            averaged.trace.currents[:, phase],
            color=colour,
            lw=1.2,
            ls="--",
        )
    ax.axvline(0.0, color="k", lw=0.6)
    t_com = switched.command.commutation_time_s * 1e3
    ax.axvline(t_com, color="k", lw=0.6, ls=":")
    ax.text(t_com, ax.get_ylim()[1] * 0.95, " commanded end", fontsize=7, va="top")
    ax.axhline(-case.current_a, color="0.6", lw=0.5)
    ax.axhline(case.current_a, color="0.6", lw=0.5)
    metrics = switched.metrics
    window = (
        switched.trace.period_starts >= -1e-12
    )  # the measured window: from the edge over metrics.periods periods
    starts = switched.trace.period_starts[window][: metrics.periods]
    ends = switched.trace.period_ends[window][: metrics.periods]
    if starts.size:
        ax.axvspan(starts[0] * 1e3, ends[-1] * 1e3, color="0.85", alpha=0.5, lw=0)
    ax.set_title(
        f"{case.drive.name}: {method} at {point.speed_rpm:g} rpm, main duty"
        f" {switched.command.main_duty:.3f}, I = {case.current_a:.1f} A: worst period"
        f" {metrics.deviation_worst_pct:+.1f} %",
        fontsize=9,
    )
    ax.set_xlabel("time from the Hall edge (ms)")
    ax.set_ylabel("phase current (A)")
    ax.legend(
        fontsize=7, loc="center right", title="solid switched, dashed averaged", title_fontsize=7
    )
    ax.grid(alpha=0.3)
    fig.tight_layout()
    suffix = "" if policy == STEADY else "_spec_duty_held_current"
    name = f"currents_{point.speed_rpm:g}rpm_{method}{suffix}.png"
    _save(fig, out / name)
    return name


def _series(
    results: Results, method: str, attribute: str, phase_zero: bool = False, **match: object
) -> tuple[np.ndarray, np.ndarray]:
    """`attribute` of the rows' metrics: at the worst carrier phase of the Hall edge where
    the row is judged so, or (`phase_zero`) with the edge on a carrier boundary."""
    rows = results.rows(method=method, **match)
    speeds = np.array([r.speed_rpm for r in rows])
    picked = [r.at_phase_zero if phase_zero else r.metrics for r in rows]
    values = np.array(
        [np.nan if getattr(m, attribute) is None else getattr(m, attribute) for m in picked],
        dtype=float,
    )
    return speeds, values


def _speed_marks(ax: plt.Axes, results: Results, boundary_r_rpm: float) -> None:
    ax.axvline(results.drive.boundary_speed_rpm, color="0.5", lw=0.6, ls="--")
    ax.axvline(boundary_r_rpm, color="tab:green", lw=0.6, ls="--")


def deviation_figure(results: Results, boundary_r_rpm: float, out: Path) -> str:
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(7.0, 6.4), sharex=True)
    for method in (*METHODS, *IDEAL_METHODS):
        colour = METHOD_COLOURS[method]
        speeds, worst = _series(
            results,
            method,
            "deviation_worst_pct",
            model="switched",
            emf_shape=DEFAULT_SHAPE,
            duty_policy=STEADY,
        )
        top.plot(speeds, worst, color=colour, marker="o", ms=3, label=f"{method}")
        speeds, flat = _series(
            results,
            method,
            "deviation_worst_pct",
            model="switched",
            emf_shape="flat",
            duty_policy=STEADY,
        )
        top.plot(speeds, flat, color=colour, ls=":", lw=1.0)
        speeds, ripple = _series(
            results,
            method,
            "torque_ripple_pct",
            model="switched",
            emf_shape=DEFAULT_SHAPE,
            duty_policy=STEADY,
        )
        bottom.plot(speeds, ripple, color=colour, marker="o", ms=3, label=method)
    for policy in sorted({r.duty_policy for r in results.sweep} - {STEADY}):
        speeds, worst = _series(results, "conventional", "deviation_worst_pct", duty_policy=policy)
        rows = results.rows(method="conventional", duty_policy=policy)
        if not rows:
            continue
        fail = np.array(["FAIL_AREA_CLAMPED" in r.flags for r in rows])
        top.plot(
            speeds,
            worst,
            color="tab:brown",
            lw=1.0,
            label=f"conventional, main duty {policy} (at the current it holds)",
        )
        top.plot(
            speeds[fail], worst[fail], "x", color="tab:brown", label="control fail area (core flag)"
        )
    top.axhspan(-3, 3, color="tab:green", alpha=0.12)
    top.set_ylabel("worst per-period deviation of |i_nc| (% of I)")
    top.set_title(
        f"{results.spec.name}: solid the spec's EMF, dotted the paper's flat EMF; switched"
        " plant, the firmware methods on the spec's EMF at their worst carrier phase",
        fontsize=9,
    )
    top.legend(fontsize=7, ncol=2)
    top.grid(alpha=0.3)
    bottom.set_ylabel("torque ripple (max-min)/mean (%)")
    bottom.set_xlabel("speed (rpm); dashed: U_d/(4 k_e) grey, R-aware boundary green")
    bottom.grid(alpha=0.3)
    for ax in (top, bottom):
        _speed_marks(ax, results, boundary_r_rpm)
    fig.tight_layout()
    name = "deviation_vs_speed.png"
    _save(fig, out / name)
    return name


def target_figure(
    results: Results, low_rpm: float, high_rpm: float, tolerance_pct: float, out: Path
) -> str:
    """The paper's rule and the resistance-aware C core on one axis, against the target;
    the lower panel is the same axis zoomed to twice the tolerance."""
    fig, axes = plt.subplots(2, 1, figsize=(7.0, 6.0), sharex=True)
    match = {"model": "switched", "emf_shape": DEFAULT_SHAPE, "duty_policy": STEADY}
    for ax in axes:
        for method, style in (("improved", "-o"), (IMPROVED_R, "-^"), (IDEAL_METHODS[0], ":")):
            speeds, worst = _series(results, method, "deviation_worst_pct", **match)
            ax.plot(speeds, worst, style, color=METHOD_COLOURS[method], ms=4, label=method)
            rows = results.rows(method=method, **match)
            clamped = np.array(["TIME_CLAMPED" in r.flags for r in rows], dtype=bool)
            if clamped.any():
                ax.plot(speeds[clamped], worst[clamped], "x", color="k", ms=7)
        ax.axhspan(-tolerance_pct, tolerance_pct, color="tab:green", alpha=0.12)
        ax.axvspan(low_rpm, high_rpm, color="0.85", alpha=0.35, lw=0)
        ax.grid(alpha=0.3)
    top, zoom = axes
    zoom.set_ylim(-2.0 * tolerance_pct, 2.0 * tolerance_pct)
    top.set_ylabel("worst per-period deviation\nof |i_nc| (% of I)")
    zoom.set_ylabel("zoom to +-2x the tolerance (%)")
    zoom.set_xlabel("speed (rpm); grey: the target's speed range; x: core flag TIME_CLAMPED")
    top.set_title(
        f"{results.spec.name}: switched plant, the spec's EMF, I = {results.drive.braking_current_a:g} A, "
        f"{results.drive.pwm_frequency_hz / 1e3:g} kHz; green band: +-{tolerance_pct:g} %\n"
        f"{IMPROVED_R} and improved at the worst carrier phase of the Hall edge,"
        f" {IDEAL_METHODS[0]} at phase 0",
        fontsize=9,
    )
    top.legend(fontsize=7)
    fig.tight_layout()
    name = "target_vs_speed.png"
    _save(fig, out / name)
    return name


def commutation_time_figure(results: Results, out: Path) -> str:
    fig, ax = plt.subplots(figsize=(7.0, 3.8))
    for method in METHODS:
        colour = METHOD_COLOURS[method]
        match = {"model": "switched", "emf_shape": DEFAULT_SHAPE, "duty_policy": STEADY}
        # the edge on a carrier boundary: Eq. 20's time against the plant, as the paper
        speeds, actual = _series(results, method, "commutation_fraction", True, **match)
        ax.plot(
            speeds,
            actual,
            color=colour,
            marker="o",
            ms=3,
            label=f"{method}: turn-off current at zero",
        )
        speeds, commanded = _series(results, method, "commanded_fraction", **match)
        ax.plot(speeds, commanded, color=colour, ls=":", lw=1.0)
    ax.axhline(1.0, color="k", lw=0.6)
    ax.set_ylim(0, 1.05)
    ax.set_xlabel("speed (rpm)")
    ax.set_ylabel("fraction of the 60 deg interval")
    ax.set_title(
        f"{results.spec.name}: commutation time, solid measured in the plant, dotted commanded",
        fontsize=9,
    )
    ax.legend(fontsize=7)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    name = "commutation_time_vs_speed.png"
    _save(fig, out / name)
    return name


def _count(value: int | None) -> float:
    return np.nan if value is None else float(value)


def switching_figure(results: Results, out: Path) -> str:
    fig, axes = plt.subplots(1, 2, figsize=(8.0, 3.6), sharey=True)
    width = 0.2
    for ax, method in zip(axes, ("conventional", "improved"), strict=True):
        speeds = [row.speed_rpm for row in results.table4]
        x = np.arange(len(speeds))
        paper_on = [getattr(r, f"{method}_on") for r in results.table4]
        paper_off = [getattr(r, f"{method}_off") for r in results.table4]
        sim_rows = [
            results.rows(
                method=method,
                model="switched",
                emf_shape=DEFAULT_SHAPE,
                duty_policy=STEADY,
                speed_rpm=float(s),
            )
            for s in speeds
        ]
        # no bar where the sweep has no such row, or the core switched nothing (a Table 4
        # speed outside the spec's range: the safe state has no pulses to count)
        # the edge on a carrier boundary, as the paper's counts are compared throughout
        sim_on = [_count(r[0].at_phase_zero.on_pulses_flowing) if r else np.nan for r in sim_rows]
        sim_off = [_count(r[0].at_phase_zero.off_pulses_flowing) if r else np.nan for r in sim_rows]
        ax.bar(
            x - 1.5 * width, paper_on, width, color="tab:blue", alpha=0.5, label="paper, on phase"
        )
        ax.bar(x - 0.5 * width, sim_on, width, color="tab:blue", label="simulated pulses, on")
        ax.bar(
            x + 0.5 * width, paper_off, width, color="tab:red", alpha=0.5, label="paper, off phase"
        )
        ax.bar(x + 1.5 * width, sim_off, width, color="tab:red", label="simulated pulses, off")
        ax.set_xticks(x, [f"{s:g}" for s in speeds])
        ax.set_title(f"{results.spec.name}: {method}", fontsize=9)
        ax.set_xlabel("speed (rpm)")
        ax.grid(alpha=0.3, axis="y")
    axes[0].set_ylabel("switchings in one commutation")
    axes[1].legend(fontsize=7)
    fig.tight_layout()
    name = "switching_counts.png"
    _save(fig, out / name)
    return name


def optimum_figure(results: Results, out: Path) -> str:
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(7.0, 6.0), sharex=True)
    rows = [r for r in results.optima if r.emf_shape == DEFAULT_SHAPE]
    speeds = np.array([r.optimum.speed_rpm for r in rows])
    top.plot(speeds, [r.optimum.on_duty for r in rows], "k-o", ms=3, label="Ipopt optimum D_on")
    top.plot(speeds, [r.optimum.off_duty for r in rows], "k--s", ms=3, label="Ipopt optimum D_off")
    for method, marker in (("improved", "o"), (IMPROVED_R, "^")):
        match = {"model": "averaged", "emf_shape": DEFAULT_SHAPE, "duty_policy": STEADY}
        sweep_rows = [
            r for r in results.rows(method=method, **match) if r.speed_rpm in set(speeds.tolist())
        ]
        colour = METHOD_COLOURS[method]
        top.plot(
            [r.speed_rpm for r in sweep_rows],
            [r.on_duty for r in sweep_rows],
            marker,
            color=colour,
            ms=4,
            ls="none",
            label=f"{method} D_on (first period)",
        )
        top.plot(
            [r.speed_rpm for r in sweep_rows],
            [r.off_duty for r in sweep_rows],
            marker,
            color=colour,
            ms=4,
            ls="none",
            mfc="none",
            label=f"{method} D_off",
        )
    top.set_ylabel("duty")
    top.set_title(f"{results.spec.name}: Ipopt's best constant pair against the rules", fontsize=9)
    top.legend(fontsize=7, ncol=2)
    top.grid(alpha=0.3)
    for key in ("optimum", *METHODS, *IDEAL_METHODS):
        values = [abs(r.worst_pct[key]) for r in rows]
        bottom.semilogy(
            speeds, np.maximum(values, 1e-3), "-o", ms=3, color=METHOD_COLOURS[key], label=key
        )
    bottom.set_ylabel("|worst per-period deviation| (%), averaged plant")
    bottom.set_xlabel("speed (rpm)")
    bottom.legend(fontsize=7, ncol=3)
    bottom.grid(alpha=0.3, which="both")
    fig.tight_layout()
    name = "optimum_vs_rules.png"
    _save(fig, out / name)
    return name


def shapes_figure(results: Results, out: Path) -> str:
    """The rules on each EMF shape: worst per-period deviation against speed."""
    rows = results.studies.shapes
    shapes = list(dict.fromkeys(r.shape for r in rows))
    fig, axes = plt.subplots(1, len(RULES), figsize=(10.0, 3.8), sharey=True)
    for ax, rule in zip(np.atleast_1d(axes), RULES, strict=True):
        for k, shape in enumerate(shapes):
            mine = [r for r in rows if r.rule == rule and r.shape == shape]
            colour = f"C{k}"
            ax.plot(
                [r.speed_rpm for r in mine],
                [r.averaged_pct for r in mine],
                "-o",
                ms=3,
                color=colour,
                label=shape,
            )
            ax.plot([r.speed_rpm for r in mine], [r.switched_pct for r in mine], ":", color=colour)
        ax.axhspan(-3, 3, color="tab:green", alpha=0.12)
        ax.set_title(f"{results.spec.name}: {rule}", fontsize=8)
        ax.set_xlabel("speed (rpm)")
        ax.grid(alpha=0.3)
    np.atleast_1d(axes)[0].set_ylabel("worst period deviation (%)\nsolid averaged, dotted switched")
    np.atleast_1d(axes)[0].legend(fontsize=6)
    fig.tight_layout()
    name = "emf_shapes.png"
    _save(fig, out / name)
    return name


def all_figures(
    results: Results,
    boundary_r_rpm: float,
    target: tuple[float, float, float],
    out: Path,
) -> dict[str, str]:
    """Write every figure into `out`; returns key -> file name.

    target: (low rpm, high rpm, tolerance %) of the resistance-aware method's target.
    """
    out.mkdir(parents=True, exist_ok=True)
    names: dict[str, str] = {}
    for point in results.operating:
        for method, policy in figure_keys(point):
            key = f"currents:{point.speed_rpm:g}:{method}:{policy}"
            names[key] = currents_figure(point, method, policy, out)
    names["deviation"] = deviation_figure(results, boundary_r_rpm, out)
    names["target"] = target_figure(results, *target, out)
    names["commutation_time"] = commutation_time_figure(results, out)
    names["switching"] = switching_figure(results, out)
    names["optimum"] = optimum_figure(results, out)
    names["shapes"] = shapes_figure(results, out)
    return names

"""The robustness campaign's report: distributions, sensitivities, one figure.

Per method and speed: median and 95th percentile of |worst per-period deviation|, the
worst sample (signed), the share of samples outside +-3 %, and the Spearman rank
correlation of the deviation with each sampled parameter (which one drives it). The
report holds no timing, so a rerun with the same seed is byte-identical.
"""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt
import numpy as np

from codegen.render import environment, project_relative, write_atomically
from codegen.spec_model import Spec
from sim.drive import MAX_SECTOR_PERIODS, Drive
from sim.robustness import CARRIER_PHASE, REPORT_NAME, Campaign, CampaignResult
from sim.robustness_args import METHOD_NAMES

TEMPLATE_DIR = Path(__file__).resolve().parent / "templates"
TEMPLATE = "ROBUSTNESS.md.j2"
FIGURE = "robustness.png"
BAND_PCT = 3.0
#: the driver where no parameter's rank correlation differs from 0 (nothing varies)
NO_DRIVER = "none"
LABELS = {
    "phase_resistance": "R",
    "phase_inductance": "L",
    "back_emf_constant": "k_e",
    "bus_voltage": "U_d",
    CARRIER_PHASE: "carrier phase",
    NO_DRIVER: "none",
}


def _ranks(values: np.ndarray) -> np.ndarray:
    """Ranks from 0, tied values sharing their mean rank (a parameter whose tolerance is
    [0, 0] is one value: ranked by index, its ties had correlated +1 with a deviation
    that did not vary either, and named it the driver)."""
    order = np.argsort(values, kind="stable")
    ranks = np.empty(len(values))
    ranks[order] = np.arange(len(values))
    _, inverse, counts = np.unique(values, return_inverse=True, return_counts=True)
    sums = np.bincount(inverse, weights=ranks)
    return (sums / counts)[inverse]


def spearman(x: np.ndarray, y: np.ndarray) -> float:
    """Rank correlation, ties at their mean rank; 0 where either does not vary."""
    rx, ry = _ranks(x), _ranks(y)
    if np.std(ry) == 0.0 or np.std(rx) == 0.0:
        return 0.0
    return float(np.corrcoef(rx, ry)[0, 1])


def statistics(result: CampaignResult) -> list[dict[str, object]]:
    campaign = result.campaign
    rows: list[dict[str, object]] = []
    for k, method in enumerate(campaign.methods):
        for j, speed in enumerate(campaign.speeds_rpm):
            worst = result.values[:, j, k, 0]
            peak = result.values[:, j, k, 1]
            limited = result.values[:, j, k, 2]
            magnitude = np.abs(worst)
            correlations = {
                name: spearman(campaign.samples[:, p], worst)
                for p, name in enumerate(campaign.parameters)
            }
            driver = max(correlations, key=lambda n: abs(correlations[n]))
            if correlations[driver] == 0.0:
                driver = NO_DRIVER
            rows.append(
                {
                    "method": method,
                    "speed": speed,
                    "median": float(np.median(magnitude)),
                    "p95": float(np.percentile(magnitude, 95)),
                    "worst": float(worst[np.argmax(magnitude)]),
                    "peak": float(peak[np.argmax(np.abs(peak))]),
                    "outside": float(np.mean(magnitude > BAND_PCT)),
                    "limited": float(np.mean(limited)),
                    "correlations": correlations,
                    "driver": driver,
                }
            )
    return rows


def report_command(spec: Spec, campaign: Campaign) -> str:
    """The command that writes this report again: every option that changes it (the
    methods too, unless all four in their order; not the output folder, the workers or
    the chunk size, which change nothing in it)."""
    words = [
        "python -m sim.robustness",
        project_relative(spec.source_path),
        f"--samples {len(campaign.samples)}",
        f"--speeds {len(campaign.speeds_rpm)}",
    ]
    if campaign.methods != tuple(METHOD_NAMES.split(",")):
        words.append(f"--methods {','.join(campaign.methods)}")
    words += [f"--plant {campaign.plant}", f"--seed {campaign.seed}"]
    return " ".join(words)


def figure(spec: Spec, result: CampaignResult, stats: list[dict[str, object]], out: Path) -> str:
    campaign = result.campaign
    fig, axes = plt.subplots(
        len(campaign.methods), 1, figsize=(7.0, 2.2 * len(campaign.methods)), sharex=True
    )
    axes = np.atleast_1d(axes)
    speeds = np.array(campaign.speeds_rpm)
    for ax, method in zip(axes, campaign.methods, strict=True):
        k = campaign.methods.index(method)
        values = result.values[:, :, k, 0]
        ax.fill_between(
            speeds,
            np.percentile(values, 2.5, axis=0),
            np.percentile(values, 97.5, axis=0),
            color="tab:blue",
            alpha=0.25,
            label="95 % of samples",
        )
        ax.plot(speeds, np.median(values, axis=0), "-o", color="tab:blue", ms=3, label="median")
        ax.plot(speeds, values.min(axis=0), ":", color="k", lw=0.8, label="min / max")
        ax.plot(speeds, values.max(axis=0), ":", color="k", lw=0.8)
        ax.axhspan(-BAND_PCT, BAND_PCT, color="tab:green", alpha=0.12)
        ax.set_ylabel(f"{method}\n(% of I)", fontsize=8)
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=7, ncol=3)
    axes[0].set_title(
        f"{spec.name}: worst per-period deviation of |i_nc| over {len(campaign.samples)} samples"
        f" ({campaign.plant} plant)",
        fontsize=9,
    )
    axes[-1].set_xlabel("speed (rpm)")
    fig.tight_layout()
    fig.savefig(out / FIGURE, dpi=110, metadata={"Software": None})
    plt.close(fig)
    return FIGURE


def _pct(value: float) -> str:
    return f"{value:+.1f} %"


def write_report(spec: Spec, result: CampaignResult, out: Path) -> list[str]:
    out.mkdir(parents=True, exist_ok=True)
    stats = statistics(result)
    name = figure(spec, result, stats, out)
    campaign = result.campaign
    parameters = list(campaign.parameters)
    rows = [
        {
            "method": s["method"],
            "speed": f"{s['speed']:g}",
            "median": f"{s['median']:.1f} %",
            "p95": f"{s['p95']:.1f} %",
            "worst": _pct(float(s["worst"])),  # type: ignore[arg-type]
            "peak": _pct(float(s["peak"])),  # type: ignore[arg-type]
            "outside": f"{100 * float(s['outside']):.0f} %",  # type: ignore[arg-type]
            "limited": f"{100 * float(s['limited']):.0f} %",  # type: ignore[arg-type]
            "correlations": [f"{s['correlations'][p]:+.2f}" for p in parameters],  # type: ignore[index]
            "driver": LABELS[str(s["driver"])],
        }
        for s in stats
    ]
    summary = []
    for method in campaign.methods:
        mine = [s for s in stats if s["method"] == method]
        worst = max(mine, key=lambda s: abs(float(s["worst"])))  # type: ignore[arg-type]
        p95 = max(mine, key=lambda s: float(s["p95"]))  # type: ignore[arg-type]
        drivers = [str(s["driver"]) for s in mine]
        summary.append(
            {
                "method": method,
                "worst": _pct(float(worst["worst"])),  # type: ignore[arg-type]
                "worst_speed": f"{worst['speed']:g}",
                "p95": f"{float(p95['p95']):.1f} %",  # type: ignore[arg-type]
                "p95_speed": f"{p95['speed']:g}",
                "driver": LABELS[max(set(drivers), key=drivers.count)],
            }
        )
    ranges = [
        {
            "name": LABELS[p],
            "key": p,
            "low": f"{100 * campaign.ranges[p][0]:+.1f} %" if p in campaign.ranges else "0",
            "high": f"{100 * campaign.ranges[p][1]:+.1f} %" if p in campaign.ranges else "1 period",
        }
        for p in parameters
    ]
    drive = Drive.from_spec(spec)
    floor_note = (
        ""
        if drive.speed_min_rpm <= drive.spec_speed_min_rpm
        else f" (from {drive.speed_min_rpm:g} rpm, above controller.speed_min"
        f" {drive.spec_speed_min_rpm:g} rpm: below it a sector spans more than"
        f" {MAX_SECTOR_PERIODS} PWM periods, which the plant simulates one by one)"
    )
    text = (
        environment(TEMPLATE_DIR)
        .get_template(TEMPLATE)
        .render(
            spec_name=spec.name,
            spec_path=project_relative(spec.source_path),
            spec_sha256=spec.sha256,
            template=f"sim/templates/{TEMPLATE}",
            samples=len(campaign.samples),
            speeds=", ".join(f"{s:g}" for s in campaign.speeds_rpm),
            floor_note=floor_note,
            methods=", ".join(campaign.methods),
            plant=campaign.plant,
            seed=campaign.seed,
            declared=campaign.declared,
            ranges=ranges,
            parameter_labels=[LABELS[p] for p in parameters],
            rows=rows,
            summary=summary,
            figure=name,
            band=f"{BAND_PCT:g}",
            command=report_command(spec, campaign),
        )
    )
    write_atomically(out / REPORT_NAME, text)
    return [REPORT_NAME, name]

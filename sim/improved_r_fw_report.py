"""`python -m sim.improved_r_fw_report SPEC [RPM,RPM,...]`: the firmware rule's target table.

Switched plant, trapezoidal EMF, the spec's nominal braking current and bus voltage:
the worst per-period deviation of the non-commutating current for `improved_r_fw` (the
integer prototype, one constant pair), next to `improved_r` (the per-period Python rule)
and the same resistance-aware sum frozen at the edge's flat EMFs (one constant pair,
no ramp), which is what the firmware form improves on.
"""

from __future__ import annotations

import sys

import numpy as np

from codegen.derivation import derive
from codegen.fixedpoint.scaling import scaling
from codegen.improved_r_rule.reference import FLAG_NAMES
from codegen.spec_loader import load_spec
from codegen.spec_model import Spec
from sim.drive import Drive
from sim.emf import BackEmf
from sim.improved_r import improved_r_command
from sim.improved_r_fw import improved_r_fw_command
from sim.runs import simulate
from sim.scenario import Case, paper_edge


def _speeds(spec: Spec, count: int = 12) -> list[float]:
    low, high = float(spec.controller.speed_min_rpm), float(spec.controller.speed_max_rpm)
    return [float(round(v)) for v in np.linspace(low, high, count)]


def rows(spec: Spec, speeds: list[float]) -> list[str]:
    drive = Drive.from_spec(spec)
    sc = scaling(spec, derive())
    per_code = float(sc.amps_per_current_code)
    f_hall = float(sc.hall_clock_hz)
    out = [
        "| rpm | improved_r_fw | D_on / D_off counts | t_com ticks | flags |"
        " improved_r (per period) | flat-EMF constant pair |",
        "|---|---|---|---|---|---|---|",
    ]
    for speed in speeds:
        case = Case(drive, paper_edge(), speed, drive.braking_current_a, "trapezoidal")
        measured = round(case.current_a / per_code) * per_code
        main = round(case.pre_edge_duty * sc.period_counts) / sc.period_counts
        fw = improved_r_fw_command(spec, case, measured, main)
        flat_emf = BackEmf(
            "flat", case.edge, case.emf.sectors, case.emf.amplitude_v, case.sector_time_s
        )
        per_period = improved_r_command(case, measured, main, sc.period_counts, f_hall)
        flat = improved_r_command(case, measured, main, sc.period_counts, f_hall, flat_emf)
        worst = [simulate(case, c, "switched").metrics for c in (fw, per_period, flat)]
        flags = ", ".join(name for bit, name in FLAG_NAMES.items() if fw.flags & bit) or "-"
        cells = [
            f"{m.deviation_worst_pct:+.1f} %" + ("" if m.finished else " (not finished)")
            for m in worst
        ]
        out.append(
            f"| {speed:.0f} | {cells[0]} | {fw.core_outputs['turn_on_compare']} / "
            f"{fw.core_outputs['turn_off_compare']} | {fw.core_outputs['commutation_ticks']} |"
            f" {flags} | {cells[1]} | {cells[2]} |"
        )
    return out


def main(argv: list[str] | None = None) -> int:
    args = sys.argv[1:] if argv is None else argv
    if not 1 <= len(args) <= 2:
        print("usage: python -m sim.improved_r_fw_report SPEC [RPM,RPM,...]", file=sys.stderr)
        return 2
    spec = load_spec(args[0])
    speeds = [float(v) for v in args[1].split(",")] if len(args) == 2 else _speeds(spec)
    print("\n".join(rows(spec, speeds)))
    return 0


if __name__ == "__main__":
    sys.exit(main())

"""`python -m sim SPEC [-o DIR]`: simulate the spec's drive and write the report.

Writes DIR/SIMULATION.md and its PNG figures (default generated/<spec name>/simulation/).
Exit status: 0 on success, 2 for a bad spec, 3 if the derivation fails, 4 if the C
core cannot be generated, compiled or loaded.
"""

from __future__ import annotations

import argparse
import sys
import time
from collections.abc import Sequence
from pathlib import Path

from codegen.errors import DerivationError, ExitCode, SpecError
from codegen.publish import os_error_line, require_folder_path
from codegen.render import write_atomically
from codegen.shown import shown
from codegen.spec_loader import load_spec

EXIT_SPEC = 2
EXIT_DERIVATION = 3
EXIT_SIL = 4
REPORT_NAME = "SIMULATION.md"


def simulate_spec(spec_path: str, output: str | None, progress: bool, quick: bool = False) -> int:
    from sim.figures import all_figures
    from sim.limits import limits
    from sim.report import TARGET_HIGH_RPM, TARGET_LOW_RPM, TARGET_PCT, render_report
    from sim.sweep import run_all

    start = time.perf_counter()
    spec = load_spec(spec_path)
    out = Path(output) if output else Path("generated") / spec.name / "simulation"
    require_folder_path(out)  # before the run, not after it
    results = run_all(spec, progress=progress, quick=quick)
    bounds = limits(results.drive)
    figure_start = time.perf_counter()
    target = (TARGET_LOW_RPM, TARGET_HIGH_RPM, TARGET_PCT)
    names = all_figures(results, bounds.boundary_r_rpm, target, out)
    write_atomically(out / REPORT_NAME, render_report(results, bounds, names))
    results.seconds["figures and report"] = time.perf_counter() - figure_start
    total = time.perf_counter() - start
    timing = ", ".join(f"{k} {v:.1f} s" for k, v in results.seconds.items() if k != "total")
    print(f"sim: {len(names)} figures + {REPORT_NAME} -> {shown(out)} [{total:.1f} s: {timing}]")
    for point in results.operating:
        cells = []
        for (method, model, policy), metrics in sorted(point.metrics.items()):
            if model == "switched":
                run = point.runs[(method, model, policy)]
                label = f"D {run.command.main_duty:.3f}, {run.case.current_a:.1f} A"
                cells.append(f"{method} ({label}) {metrics.deviation_worst_pct:+.1f} %")
        print(f"sim: {point.speed_rpm:g} rpm: " + ", ".join(cells))
    return 0


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m sim", description=__doc__.splitlines()[0])
    parser.add_argument("spec", help="motor spec YAML, e.g. spec/paper_motor.yaml")
    parser.add_argument(
        "-o", "--output", help="output folder (default generated/<spec name>/simulation)"
    )
    parser.add_argument("--no-progress", action="store_true", help="no progress bar")
    parser.add_argument(
        "--quick",
        action="store_true",
        help="every study at a few speeds (a first look; the report says so)",
    )
    args = parser.parse_args(argv)
    from sim.sil import SilError, SpecRefusedError

    try:
        return simulate_spec(
            args.spec, args.output, progress=not args.no_progress, quick=args.quick
        )
    except SpecError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return EXIT_SPEC
    except DerivationError as exc:
        print(f"derivation failed: {exc}", file=sys.stderr)
        return EXIT_DERIVATION
    except SpecRefusedError as exc:  # what `generate SPEC` says of it
        for line in str(exc).splitlines():
            print(f"error: {line}", file=sys.stderr)
        return EXIT_SPEC
    except SilError as exc:
        print(f"software in the loop failed: {exc}", file=sys.stderr)
        return EXIT_SIL
    except OSError as exc:  # the output folder
        print(os_error_line(exc), file=sys.stderr)
        return int(ExitCode.ENVIRONMENT)

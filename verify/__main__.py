"""python -m verify SPEC [--generated DIR] [--seed N] [--random N]."""

from __future__ import annotations

import argparse
import sys
import tempfile
from pathlib import Path

from codegen.argtypes import POINTS, SEED, path_text
from codegen.errors import ExitCode, SpecError
from codegen.freshness import regenerate_command
from codegen.publish import PublishError
from codegen.report_folder import staged_report
from codegen.spec_loader import load_spec
from verify.run import DEFAULT_RANDOM_POINTS, StaleOutputError, plot, table, verify, write_json

#: the exit statuses of bldc-codegen (codegen.errors.ExitCode): a point out of tolerance,
#: the spec refused, no generated core or not this spec's (regenerate)
EXIT_FAILED, EXIT_SPEC, EXIT_STALE = (
    int(ExitCode.CHECK_FAILED),
    int(ExitCode.SPEC),
    int(ExitCode.STALE),
)


#: what verify writes into generated/<name>/verify/, and the text its report holds that
#: says it is the tool's (`codegen.report_folder`: a folder from before its ledger)
REPORT_NAME, FIGURE_NAME = "report.json", "error_vs_speed.png"
REPORT_MARKER = '"spec_sha256"'


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(
        prog="verify", description="The generated C core against the independent oracle."
    )
    parser.add_argument("spec", help="motor spec YAML")
    parser.add_argument(
        "--generated",
        type=lambda text: Path(path_text(text)),
        help="generated folder (default: generated/<spec name> in the current folder)",
    )
    parser.add_argument("--seed", type=SEED, help="replay a random set")
    parser.add_argument(
        "--random", type=POINTS, default=DEFAULT_RANDOM_POINTS, help="random points"
    )
    parser.add_argument(
        "--no-progress",
        action="store_true",
        help="no progress bar (there is none unless stderr is a terminal)",
    )
    args = parser.parse_args(argv)
    try:
        spec = load_spec(args.spec)
    except SpecError as exc:
        print(f"verify: {exc}", file=sys.stderr)
        return EXIT_SPEC
    # Like bldc-codegen: generated/<name> under the current folder.
    generated = args.generated or Path("generated") / spec.name
    if not (generated / "c" / "bldc_commutation.c").is_file():
        print(
            f"verify: no generated core in {generated}: run"
            f" `{regenerate_command(spec, generated)}`",
            file=sys.stderr,
        )
        return EXIT_STALE
    try:
        with tempfile.TemporaryDirectory() as build:
            result, evaluated, tol, o = verify(
                args.spec,
                generated,
                Path(build),
                seed=args.seed,
                random_count=args.random,
                show_progress=sys.stderr.isatty() and not args.no_progress,
            )
    except (StaleOutputError, FileNotFoundError) as exc:
        print(f"verify: {exc}", file=sys.stderr)
        return EXIT_STALE
    print(table(result, o))
    out = generated / "verify"
    # the report and its figure staged and moved in together (a Ctrl-C between the two
    # writes had left a new report.json beside the former run's figure)
    try:
        with staged_report(out, REPORT_NAME, REPORT_MARKER) as staging:
            write_json(result, tol, o, staging / REPORT_NAME)
            plot(evaluated, tol, result.motor, staging / FIGURE_NAME)
    except PublishError as exc:  # a file in the folder the tool did not write
        print(f"verify: {exc}", file=sys.stderr)
        return int(ExitCode.ENVIRONMENT)
    print(f"verify: wrote {out / REPORT_NAME} and {out / FIGURE_NAME}")
    return 0 if result.passed else EXIT_FAILED


if __name__ == "__main__":
    from codegen.interrupts import exit_status

    raise SystemExit(exit_status(main))

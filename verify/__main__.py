"""python -m verify SPEC [--generated DIR] [--seed N] [--random N]."""

from __future__ import annotations

import argparse
import sys
import tempfile
from pathlib import Path

from codegen.argtypes import POINTS, SEED
from codegen.errors import ExitCode, SpecError
from codegen.freshness import regenerate_command
from codegen.spec_loader import load_spec
from verify.run import DEFAULT_RANDOM_POINTS, StaleOutputError, plot, table, verify, write_json

#: the exit statuses of bldc-codegen (codegen.errors.ExitCode): a point out of tolerance,
#: the spec refused, no generated core or not this spec's (regenerate)
EXIT_FAILED, EXIT_SPEC, EXIT_STALE = (
    int(ExitCode.CHECK_FAILED),
    int(ExitCode.SPEC),
    int(ExitCode.STALE),
)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(
        prog="verify", description="The generated C core against the independent oracle."
    )
    parser.add_argument("spec", help="motor spec YAML")
    parser.add_argument(
        "--generated",
        type=Path,
        help="generated folder (default: generated/<spec name> in the current folder)",
    )
    parser.add_argument("--seed", type=SEED, help="replay a random set")
    parser.add_argument(
        "--random", type=POINTS, default=DEFAULT_RANDOM_POINTS, help="random points"
    )
    parser.add_argument("--no-progress", action="store_true", help="no progress bar")
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
                show_progress=not args.no_progress,
            )
    except (StaleOutputError, FileNotFoundError) as exc:
        print(f"verify: {exc}", file=sys.stderr)
        return EXIT_STALE
    print(table(result, o))
    out = generated / "verify"
    write_json(result, tol, o, out / "report.json")
    plot(evaluated, tol, result.motor, out / "error_vs_speed.png")
    print(f"verify: wrote {out / 'report.json'} and {out / 'error_vs_speed.png'}")
    return 0 if result.passed else EXIT_FAILED


if __name__ == "__main__":
    raise SystemExit(main())

"""What the subcommands share: the spec argument, output folders, freshness, --json."""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from codegen.argtypes import path_text
from codegen.freshness import check_fresh
from codegen.spec_loader import load_spec
from codegen.spec_model import Spec


def add_spec(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "spec",
        metavar="SPEC",
        type=path_text,
        help="motor spec YAML (relative to the current folder), e.g. spec/paper_motor.yaml",
    )


def add_generated(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "--generated",
        metavar="DIR",
        type=path_text,
        help="the spec's generated output to use (default: generated/<spec name> in the"
        " current folder); it must be from this spec and tool version, else exit 4",
    )


def add_output(parser: argparse.ArgumentParser, what: str) -> None:
    parser.add_argument(
        "-o",
        "--output",
        metavar="DIR",
        type=path_text,
        help=f"{what} (default: generated/<spec name> in the current folder)",
    )


def add_json(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "--json",
        action="store_true",
        help="print the result as one JSON object on stdout instead of text",
    )


def add_progress(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "--no-progress", action="store_true", help="no progress bar on stderr (for logs and CI)"
    )


def load(spec_path: str) -> Spec:
    """The spec, its plausibility warnings printed on stderr, one line each."""
    spec = load_spec(spec_path)
    for warning in spec.warnings:
        print(f"warning: {warning}", file=sys.stderr)
    return spec


def output_dir(spec: Spec, override: str | None) -> Path:
    """Where a command writes: -o DIR, else generated/<name>, both against the cwd."""
    return Path(override) if override else Path("generated") / spec.name


def fresh_generated(spec: Spec, override: str | None) -> Path:
    """The generated folder a command reads, after checking that it is this spec's."""
    generated = Path(override) if override else Path("generated") / spec.name
    check_fresh(spec, generated)
    return generated


def emit_json(payload: object) -> None:
    print(json.dumps(payload, indent=2, sort_keys=True, default=str))

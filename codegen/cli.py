"""Command line: `python -m codegen <command> SPEC` (also installed as `bldc-codegen`).

Commands:
  derive SPEC             print the derived equations and the spec's key numbers
  audit [SPEC] [-o DIR]   write the paper audit, AUDIT.md and AUDIT.html (default
                          generated/paper/); it is the same for every motor. With SPEC,
                          also that motor's DERIVATION.md (default generated/<name>/)
  generate SPEC [-o DIR]  write everything for a motor: DERIVATION.md, fixed-point C,
                          Python models, firmware, tests (atomically)

One process derives once (codegen.derivation.derive is cached) and every command reuses
that result. Exit status: 0 on success (also when the paper has errors: finding them
is the audit's job), 2 for a bad spec, 3 if the derivation itself fails.
"""

from __future__ import annotations

import argparse
import sys
import time
from collections.abc import Sequence
from pathlib import Path

import sympy as sp

from codegen.errors import DerivationError, SpecError
from codegen.render import PROJECT_ROOT, project_relative, write_atomically
from codegen.spec_loader import PAPER_AUDIT_NAME, load_spec

EXIT_SPEC = 2
EXIT_DERIVATION = 3


def _output_dir(spec_name: str, override: str | None) -> Path:
    return Path(override) if override else PROJECT_ROOT / "generated" / spec_name


def cmd_derive(args: argparse.Namespace) -> int:
    from codegen.derivation import derive
    from codegen.derivation.figures import spec_figures

    spec = load_spec(args.spec)
    derivation = derive()
    for result in derivation:
        r_note = " (R = 0)" if result.neglects_resistance else ""
        print(f"Eq. ({result.key}) {result.title}{r_note}")
        for name, value in result.rows:
            label = f"  {name}: " if name else "  "
            print(f"{label}{sp.sstr(value)}")
    figures = spec_figures(derivation, spec)
    print(f"\nAt spec {spec.name}:")
    print(f"  segment cut-off U_d/(4 k_e) = {float(figures.boundary_speed_rpm):.1f} rpm")
    print(f"  upper limit     U_d/(2 k_e) = {float(figures.upper_speed_rpm):.1f} rpm")
    for p in figures.points:
        fail = "  <- control fail area" if p.conventional_fails else ""
        print(
            f"  {float(p.speed_rpm):6.0f} rpm ({p.region}): improved D_on = {float(p.improved_on):.4f},"
            f" D_off = {float(p.improved_off):.4f}, t_com = {float(p.improved_t_com_s) * 1e6:.0f} us"
            f" of {float(p.sector_time_s) * 1e6:.0f} us;"
            f" conventional D_off at D_on = {float(p.main_duty):g}: {float(p.conventional_off):.4f}{fail}"
        )
    return 0


def cmd_audit(args: argparse.Namespace) -> int:
    from codegen.audit.latex_cache import shared_cache
    from codegen.audit.motor_report import render_derivation
    from codegen.audit.report import counts, render_reports
    from codegen.audit.run import run_audit
    from codegen.audit.transcription import load_transcription
    from codegen.derivation import derive

    started = time.perf_counter()
    spec = load_spec(args.spec) if args.spec else None  # a bad spec writes nothing
    derivation = derive()
    transcription = load_transcription()
    result = run_audit(transcription, derivation)
    files = render_reports(result, transcription)
    motor = render_derivation(derivation, spec) if spec else ""
    shared_cache().save()
    paper_dir = _output_dir(PAPER_AUDIT_NAME, args.output)
    for name, text in files.items():
        write_atomically(paper_dir / name, text)
    if spec:
        write_atomically(_output_dir(spec.name, args.output) / "DERIVATION.md", motor)
    c = counts(result)
    elapsed = time.perf_counter() - started
    out = paper_dir / "AUDIT.md"
    print(
        f"audit: {c.rows} equation rows: {c.match} match, {c.notation} match (notation),"
        f" {c.endpoint} end point, {c.mismatch} mismatch"
    )
    print(
        f"audit: {c.findings} findings ({c.errors} errors, {c.inconsistencies} inconsistencies,"
        f" {c.minor} minor) -> {project_relative(out)}, AUDIT.html [{elapsed:.2f} s]"
    )
    if spec:
        print(
            f"audit: the derivation at {spec.name} ->"
            f" {project_relative(_output_dir(spec.name, args.output) / 'DERIVATION.md')}"
        )
    return 0


def cmd_generate(args: argparse.Namespace) -> int:
    from codegen.generate import generate
    from codegen.methods.base import FixedPointError

    started = time.perf_counter()
    try:
        result = generate(args.spec, args.output, PROJECT_ROOT)
    except FixedPointError as exc:
        print(f"error: {args.spec}: {exc.key}: {exc}", file=sys.stderr)
        return EXIT_SPEC
    out = Path(args.output) if args.output else PROJECT_ROOT / "generated" / result.spec.name
    print(
        f"generate: {len(result.files)} files -> {project_relative(out)}"
        f" [{time.perf_counter() - started:.2f} s]"
    )
    print(f"generate: {result.core.design.summary}")
    return 0


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="codegen", description=__doc__.split("\n")[0])
    sub = parser.add_subparsers(dest="command", required=True)
    derive_p = sub.add_parser("derive", help="print the derived equations and key numbers")
    derive_p.add_argument("spec", help="motor spec YAML, e.g. spec/paper_motor.yaml")
    derive_p.set_defaults(func=cmd_derive)
    audit_p = sub.add_parser(
        "audit", help="audit the paper (the same for every motor); with SPEC, its DERIVATION.md"
    )
    audit_p.add_argument(
        "spec",
        nargs="?",
        help="optional motor spec YAML: also write its DERIVATION.md (generated/<spec name>/)",
    )
    audit_p.add_argument(
        "-o", "--output", help="one output folder for everything (default generated/paper/)"
    )
    audit_p.set_defaults(func=cmd_audit)
    gen_p = sub.add_parser("generate", help="generate C, Python models and DERIVATION.md")
    gen_p.add_argument("spec", help="motor spec YAML, e.g. spec/paper_motor.yaml")
    gen_p.add_argument("-o", "--output", help="output folder (default generated/<spec name>)")
    gen_p.set_defaults(func=cmd_generate)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    try:
        return int(args.func(args))
    except SpecError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return EXIT_SPEC
    except DerivationError as exc:
        print(f"derivation failed: {exc}", file=sys.stderr)
        return EXIT_DERIVATION

"""Command line: `python -m codegen <command> SPEC` (also installed as `bldc-codegen`).

Commands:
  derive SPEC             print the derived equations and the spec's key numbers
  audit SPEC [-o DIR]     write the derivation audit, DIR/AUDIT.md (default generated/<name>/)
  generate SPEC [-o DIR]  write everything: audit, fixed-point C, Python models (atomically)

One process derives once (codegen.derivation.derive is cached) and every command reuses
that result. Exit status (codegen.errors.ExitCode): 0 on success (also when the paper
has errors: finding them is the audit's job), 1 a check failed, 2 usage error, 3 bad
spec, 4 stale output, 5 environment (output folder, external tool), 70 internal error.
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from collections.abc import Sequence
from pathlib import Path

from codegen.errors import DerivationError, ExitCode, SpecError, internal_error_line
from codegen.publish import PublishError, check_target
from codegen.render import PROJECT_ROOT, project_relative, write_atomically
from codegen.spec_loader import load_spec as _load_spec
from codegen.spec_model import Spec

EXIT_SPEC = int(ExitCode.SPEC)
EXIT_DERIVATION = int(ExitCode.INTERNAL)


def load_spec(path: str) -> Spec:
    """The spec, with its plausibility warnings printed on stderr, one line each."""
    spec = _load_spec(path)
    for warning in spec.warnings:
        print(f"warning: {warning}", file=sys.stderr)
    return spec


def _one_line(text: object) -> str:
    return " ".join(str(text).split())


def _output_dir(spec_name: str, override: str | None) -> Path:
    return Path(override) if override else PROJECT_ROOT / "generated" / spec_name


def cmd_derive(args: argparse.Namespace) -> int:
    import sympy as sp

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
    from codegen.audit.report import counts, render_report
    from codegen.audit.run import run_audit
    from codegen.audit.transcription import load_transcription
    from codegen.derivation import derive

    started = time.perf_counter()
    spec = load_spec(args.spec)
    derivation = derive()
    transcription = load_transcription()
    result = run_audit(transcription, derivation)
    text = render_report(result, derivation, transcription, spec)
    shared_cache().save()
    out = _output_dir(spec.name, args.output) / "AUDIT.md"
    write_atomically(out, text)
    c = counts(result)
    elapsed = time.perf_counter() - started
    print(
        f"audit: {c.rows} equation rows: {c.match} match, {c.notation} match (notation),"
        f" {c.endpoint} end point, {c.mismatch} mismatch"
    )
    print(
        f"audit: {c.findings} findings ({c.errors} errors, {c.inconsistencies} inconsistencies,"
        f" {c.minor} minor) -> {project_relative(out)} [{elapsed:.2f} s]"
    )
    return 0


def cmd_generate(args: argparse.Namespace) -> int:
    started = time.perf_counter()
    spec = load_spec(args.spec)  # errors and warnings before the heavy imports
    check_target(_output_dir(spec.name, args.output))

    from codegen.fixedpoint.design import FixedPointError
    from codegen.generate import generate
    from codegen.improved_r_rule.proof import RuleFormatError

    try:
        result = generate(args.spec, args.output, PROJECT_ROOT)
    except FixedPointError as exc:
        print(f"error: {args.spec}: fixed-point design: {_one_line(exc)}", file=sys.stderr)
        return EXIT_SPEC
    except RuleFormatError as exc:
        print(
            f"error: {args.spec}: controller.method = 'improved_r': {_one_line(exc)} (allowed:"
            " a spec whose accuracy targets and ranges the rule's integer formats can meet)",
            file=sys.stderr,
        )
        return EXIT_SPEC
    fx = result.design
    out = Path(args.output) if args.output else PROJECT_ROOT / "generated" / result.spec.name
    print(
        f"generate: {len(result.files)} files -> {project_relative(out)}"
        f" [{time.perf_counter() - started:.2f} s]"
    )
    if result.spec.controller.method == "improved_r":
        from codegen.improved_r_rule.context import rule_design

        rule = rule_design(result.spec, fx.scaling)
        print(
            f"generate: improved_r, counts in Q{rule.rule.counts_frac_bits},"
            f" {rule.rule.steps}-step bisection, psi table {rule.rule.table.entries} rows"
            f" ({rule.rule.table.flash_bytes} B); error bounds over the design grid: duties"
            f" {rule.duty_bound:.3f} counts, t_com {rule.ticks_bound:.2f} ticks"
            f" ({rule.time_ratio:.2f} of max(target, t_half))"
        )
        return 0
    print(
        f"generate: X in Q{fx.x_frac_bits}; error bounds: duties"
        f" {float(fx.duty_error_bound_counts):.3f} counts, t_com"
        f" {float(fx.time_error_bound_ticks):.2f} ticks where W >="
        f" {float(fx.time_bound_min_w_counts):g} counts"
    )
    return 0


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="codegen", description=__doc__.split("\n")[0])
    parser.add_argument(
        "--traceback",
        action="store_true",
        help="on an internal error, print the full Python traceback",
    )
    sub = parser.add_subparsers(dest="command", required=True)
    derive_p = sub.add_parser("derive", help="print the derived equations and key numbers")
    derive_p.add_argument("spec", help="motor spec YAML, e.g. spec/paper_motor.yaml")
    derive_p.set_defaults(func=cmd_derive)
    audit_p = sub.add_parser("audit", help="audit the paper's printed equations")
    audit_p.add_argument("spec", help="motor spec YAML, e.g. spec/paper_motor.yaml")
    audit_p.add_argument("-o", "--output", help="output folder (default generated/<spec name>)")
    audit_p.set_defaults(func=cmd_audit)
    gen_p = sub.add_parser("generate", help="generate C, Python models and the audit")
    gen_p.add_argument("spec", help="motor spec YAML, e.g. spec/paper_motor.yaml")
    gen_p.add_argument("-o", "--output", help="output folder (default generated/<spec name>)")
    gen_p.set_defaults(func=cmd_generate)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    try:
        return int(args.func(args))
    except SpecError as exc:
        for line in str(exc).splitlines():
            print(f"error: {line}", file=sys.stderr)
        return EXIT_SPEC
    except PublishError as exc:
        print(f"error: output: {_one_line(exc)}", file=sys.stderr)
        return int(ExitCode.ENVIRONMENT)
    except DerivationError as exc:
        print(f"derivation failed (a bug in bldc-codegen): {_one_line(exc)}", file=sys.stderr)
        return EXIT_DERIVATION
    except OSError as exc:
        name = f" {exc.filename}" if exc.filename else ""
        print(f"error: cannot write{name}: {exc.strerror or exc}", file=sys.stderr)
        return int(ExitCode.ENVIRONMENT)
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return 130
    except Exception as exc:
        if args.traceback or os.environ.get("BLDC_CODEGEN_TRACEBACK"):
            raise
        print(internal_error_line(exc, PROJECT_ROOT), file=sys.stderr)
        return int(ExitCode.INTERNAL)

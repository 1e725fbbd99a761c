"""Subcommands that turn a spec into output: init, derive, audit, generate."""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

from bldc.cli import Command, register
from bldc.commands.common import (
    add_json,
    add_output,
    add_spec,
    emit_json,
    load,
    output_dir,
)
from codegen.argtypes import path_text
from codegen.errors import ExitCode, SpecError
from codegen.publish import check_target
from codegen.render import PROJECT_ROOT, write_atomically
from codegen.shown import on_one_line, said, shown


def _init(args: argparse.Namespace) -> int:
    from codegen.spec_init import Datasheet, pwm_frequency_error, write_new_spec

    path = Path(args.output) if args.output else Path("spec") / f"{args.name}.yaml"
    if path.is_symlink():
        # the spec goes through a link to its file (the atomic rename had put a regular
        # file in place of the link); a link to nothing, or a loop, is refused: exists()
        # follows links and had said "nothing there", so init replaced it unasked
        try:
            path = path.resolve(strict=True)
        except (OSError, RuntimeError):  # RuntimeError: a loop, before Python 3.13
            print(  # the link as given: said() resolves it
                f"error: {on_one_line(str(path))} is a symbolic link to nothing (or a loop of"
                " links): -o takes the spec FILE to write",
                file=sys.stderr,
            )
            return int(ExitCode.ENVIRONMENT)
    if path.exists() and not path.is_file():
        # --force replaces a file; a folder, a device (/dev/null) or a FIFO is never
        # replaced (the atomic rename would put a spec in place of /dev/null as root)
        kind = "a folder" if path.is_dir() else "not a regular file"
        print(
            f"error: {said(path)} is {kind}: -o takes the spec FILE to write",
            file=sys.stderr,
        )
        return int(ExitCode.ENVIRONMENT)
    if path.exists() and not args.force:
        print(
            f"error: {said(path)} exists; choose another -o FILE or pass --force",
            file=sys.stderr,
        )
        return int(ExitCode.USAGE)
    sheet = Datasheet.from_arguments(args)
    refused = pwm_frequency_error(sheet)
    if refused is not None:
        print(f"error: {refused}", file=sys.stderr)
        return int(ExitCode.USAGE)
    written = write_new_spec(args.name, sheet, path)
    if args.json:
        emit_json({"spec": shown(written.path), "valid": written.error is None})
    else:
        print(f"init: wrote {said(written.path)}")
    for note in written.notes:
        print(f"init: note: {note}", file=sys.stderr)
    if written.error is not None:
        for line in str(written.error).splitlines():
            print(f"error: {line}", file=sys.stderr)
        state = "does not load yet" if isinstance(written.error, SpecError) else "loads, but"
        if not isinstance(written.error, SpecError):
            state += " its fixed-point design does not fit"
        print(
            f"init: {said(written.path)} {state}: edit the values above (each one's"
            " `sources` entry says what init derived it from)",
            file=sys.stderr,
        )
        return int(ExitCode.SPEC)
    for warning in written.warnings:
        print(f"warning: {warning}", file=sys.stderr)
    print(
        f"init: next: edit it, then `bldc-codegen generate {said(written.path)}`",
        file=sys.stderr,
    )
    return 0


def _init_arguments(parser: argparse.ArgumentParser) -> None:
    from codegen.spec_init import add_datasheet_arguments, spec_name

    parser.add_argument(
        "name",
        metavar="NAME",
        type=spec_name,
        help="the motor's name: a lower-case identifier, e.g. my_motor",
    )
    parser.add_argument(
        "-o",
        "--output",
        metavar="FILE",
        type=path_text,
        help="where to write the spec (default: spec/NAME.yaml)",
    )
    parser.add_argument("--force", action="store_true", help="overwrite FILE if it exists")
    add_json(parser)
    add_datasheet_arguments(parser)


register(
    Command(
        "init",
        "write a commented spec for a new motor, converting datasheet values",
        "Write a spec for a new motor from datasheet values. Line-to-line resistance and"
        " inductance are halved to phase values, a line-to-line back-EMF constant or a Kv"
        " in rpm/V becomes the paper's k_e, pole pairs become poles; each conversion is"
        " recorded in `sources`. Values you do not give are the paper motor's, marked"
        " 'assumption:' for you to replace. The spec is checked once written.",
        _init_arguments,
        _init,
    )
)


def _derive(args: argparse.Namespace) -> int:
    import sympy as sp

    from codegen.derivation import derive
    from codegen.derivation.figures import spec_figures

    spec = load(args.spec)
    derivation = derive()
    figures = spec_figures(derivation, spec)
    if args.json:
        emit_json(
            {
                "spec": spec.name,
                "spec_sha256": spec.sha256,
                "segment_cut_off_rpm": float(figures.boundary_speed_rpm),
                "upper_limit_rpm": float(figures.upper_speed_rpm),
                "operating_points": [
                    {
                        "speed_rpm": float(p.speed_rpm),
                        "region": p.region,
                        "improved_on": float(p.improved_on),
                        "improved_off": float(p.improved_off),
                        "improved_t_com_s": float(p.improved_t_com_s),
                        "sector_time_s": float(p.sector_time_s),
                        "main_duty": float(p.main_duty),
                        "conventional_off": float(p.conventional_off),
                        "conventional_fails": bool(p.conventional_fails),
                    }
                    for p in figures.points
                ],
            }
        )
        return 0
    for result in derivation:
        r_note = " (R = 0)" if result.neglects_resistance else ""
        print(f"Eq. ({result.key}) {result.title}{r_note}")
        for name, value in result.rows:
            label = f"  {name}: " if name else "  "
            print(f"{label}{sp.sstr(value)}")
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


def _derive_arguments(parser: argparse.ArgumentParser) -> None:
    add_spec(parser)
    add_json(parser)


register(
    Command(
        "derive",
        "print the derived equations and the spec's key numbers",
        "Derive Eqs. 3b-20 from Eq. 1 (SymPy) and print them, then the spec's segment"
        " cut-off, upper speed limit and the duties at its operating points.",
        _derive_arguments,
        _derive,
    )
)


def _audit(args: argparse.Namespace) -> int:
    started = time.perf_counter()
    spec = load(args.spec) if args.spec else None  # a bad spec writes nothing

    from codegen.audit.latex_cache import shared_cache
    from codegen.audit.motor_report import (
        publish_derivation,
        refuse_foreign_reports,
        render_derivation,
    )
    from codegen.audit.report import counts, render_reports
    from codegen.audit.run import run_audit
    from codegen.audit.transcription import load_transcription
    from codegen.derivation import derive
    from codegen.spec_loader import PAPER_AUDIT_NAME

    paper_dir = Path(args.output) if args.output else Path.cwd() / "generated" / PAPER_AUDIT_NAME
    folder = None  # where DERIVATION.md goes, with a spec
    if spec is not None:
        folder = Path(args.output) if args.output else output_dir(spec, None)
    reports = ("AUDIT.md", "AUDIT.html")

    def refuse_foreign() -> None:  # before the work, and again just before writing
        name = spec.name if spec is not None else None
        refuse_foreign_reports(paper_dir, reports, derivation=folder == paper_dir, spec_name=name)
        if folder is not None and folder != paper_dir:
            refuse_foreign_reports(folder, (), derivation=True, spec_name=name)

    refuse_foreign()
    derivation = derive()
    transcription = load_transcription()
    result = run_audit(transcription, derivation)
    files = render_reports(result, transcription)
    motor = render_derivation(derivation, spec) if spec else ""
    shared_cache().save()
    refuse_foreign()
    for name, text in files.items():
        write_atomically(paper_dir / name, text)
    motor_out = None
    if spec and folder is not None:
        publish_derivation(motor, folder, spec.name)
        motor_out = folder / "DERIVATION.md"
    c = counts(result)
    elapsed = time.perf_counter() - started
    print(
        f"audit: {c.rows} equation rows: {c.match} match, {c.notation} match (notation),"
        f" {c.endpoint} end point, {c.mismatch} mismatch"
    )
    print(
        f"audit: {c.findings} findings ({c.errors} errors, {c.inconsistencies} inconsistencies,"
        f" {c.minor} minor) -> {said(paper_dir / 'AUDIT.md')}, AUDIT.html [{elapsed:.2f} s]"
    )
    if motor_out is not None and spec is not None:
        print(f"audit: the derivation at {spec.name} -> {said(motor_out)}")
    return 0


def _audit_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "spec",
        nargs="?",
        type=path_text,
        help="optional motor spec YAML: also write its DERIVATION.md (generated/<name>/)",
    )
    add_output(parser, "one folder for everything (default generated/paper/)")


register(
    Command(
        "audit",
        "audit the paper (AUDIT.md, AUDIT.html); with SPEC, also its DERIVATION.md",
        "Compare every equation, table and checkable statement the paper prints with the"
        " derivation and write the findings to generated/paper/AUDIT.md and AUDIT.html"
        " (math as MathML, no network). The audit is the same for every motor; with SPEC,"
        " also write that motor's numbers to generated/<name>/DERIVATION.md.",
        _audit_arguments,
        _audit,
    )
)


def _generate(args: argparse.Namespace) -> int:
    started = time.perf_counter()
    spec = load(args.spec)  # errors and warnings before the heavy imports
    target = check_target(output_dir(spec, args.output))

    from codegen.generate import generate, refuse_audit_folder
    from codegen.publish import refuse_unreadable_manifest

    refuse_audit_folder(target)
    refuse_unreadable_manifest(target)  # now, not after the design's seconds
    result = generate(args.spec, target, PROJECT_ROOT)
    design = result.core.design
    seconds = time.perf_counter() - started
    summary: dict[str, object] = {
        "output": shown(target),
        "files": sorted(result.files),
        "spec": spec.source_path,
        "spec_sha256": spec.sha256,
        "method": spec.controller.method,
        "seconds": round(seconds, 3),
    }
    lines = [
        f"generate: {len(result.files)} files -> {said(target)} [{seconds:.2f} s]",
        f"generate: {design.summary}",
    ]
    summary["formats"] = design.formats
    summary["duty_error_bound_counts"] = design.claims.duty_counts
    summary["time_error_bound_ticks"] = design.claims.time_ticks
    if args.json:
        emit_json(summary)
    else:
        print("\n".join(lines))
    return 0


def _generate_arguments(parser: argparse.ArgumentParser) -> None:
    add_spec(parser)
    add_output(
        parser,
        "output folder; replaced atomically, keeping files bldc-codegen did not write",
    )
    add_json(parser)


register(
    Command(
        "generate",
        "generate the C core, STM32F103 port, firmware files, Python models, Unity tests",
        "Render everything for the spec in memory, then publish it into the output folder"
        " in one atomic step. Files bldc-codegen did not write (verify/ and simulation/"
        " reports, your own files) are kept; manifest.json lists what it wrote.",
        _generate_arguments,
        _generate,
    )
)

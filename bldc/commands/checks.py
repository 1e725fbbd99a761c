"""Subcommands that build, check and measure a spec's generated output: firmware, verify,
unity, simulate, bench, all. Each delegates to the module that owns the work
(codegen.build_firmware, verify, verify.unity_run, sim, emulation) after checking
that the generated folder is this spec's (codegen.freshness)."""

from __future__ import annotations

import argparse
import json
import shutil
import subprocess
import sys
from pathlib import Path

from bldc.cli import COMMANDS, Command, register
from bldc.commands.common import (
    add_generated,
    add_json,
    add_progress,
    add_spec,
    emit_json,
    fresh_generated,
    load,
)
from codegen.argtypes import POINTS, SEED, path_text
from codegen.errors import ExitCode
from codegen.shown import shown
from emulation.sections import SECTIONS, unknown_sections
from sim.robustness_args import add_campaign_arguments


def _require_tools(*tools: str) -> None:
    missing = [tool for tool in tools if shutil.which(tool) is None]
    if missing:
        raise FileNotFoundError(
            2, f"{', '.join(missing)} not found on PATH (install with `make sysdeps`)"
        )


# --------------------------------------------------------------------- firmware


def _firmware(args: argparse.Namespace) -> int:
    from codegen import build_firmware

    spec = load(args.spec)
    generated = fresh_generated(spec, args.generated)
    build_dir = Path(args.build) if args.build else Path("build") / spec.name
    _require_tools("arm-none-eabi-gcc", "arm-none-eabi-size", "arm-none-eabi-objcopy")
    try:
        if not args.json:
            code = build_firmware.main([str(generated), str(build_dir), args.spec])
            return int(ExitCode.CHECK_FAILED) if code else 0
        sizes = build_firmware.build(generated, build_dir)
    except subprocess.CalledProcessError as exc:
        print(f"error: the generated firmware does not build ({exc.cmd[0]})", file=sys.stderr)
        return int(ExitCode.CHECK_FAILED)
    report = build_firmware.stack(build_dir, spec.firmware.integration == "cube")
    budgets = build_firmware.budgets(
        sizes, report, spec.firmware.flash_budget_bytes, spec.firmware.ram_budget_bytes
    )
    emit_json(
        {
            "elf": shown(build_dir / build_firmware.ELF),
            "bin": shown(build_dir / "firmware.bin"),
            "hex": shown(build_dir / "firmware.hex"),
            "map": shown(build_dir / "firmware.map"),
            "sizes": {
                name: {"flash": size.flash, "ram": size.ram, "sections": size.sections}
                for name, size in sizes.items()
            },
            "stack_bytes": report.worst,
            "stack": report.lines(),
            "budgets": [
                {"name": b.name, "value": b.value, "limit": b.limit, "meets": b.meets}
                for b in budgets
            ],
        }
    )
    return 0 if all(b.meets for b in budgets) else int(ExitCode.CHECK_FAILED)


def _firmware_arguments(parser: argparse.ArgumentParser) -> None:
    add_spec(parser)
    add_generated(parser)
    parser.add_argument(
        "--build", metavar="DIR", type=path_text, help="build folder (default: build/<spec name>)"
    )
    add_json(parser)


register(
    Command(
        "firmware",
        "cross-compile the generated firmware; .elf, .bin, .hex, map; flash, RAM and stack"
        " against the spec's budgets",
        "Build the core, the current loop, the port, the clock tree, start-up and main (and"
        " the Cube-style stm32f1xx_it.c for firmware.integration: cube) with arm-none-eabi-gcc"
        " (-Wall -Wextra -Wconversion -Werror), link firmware.elf with a map and write"
        " firmware.bin and firmware.hex; report flash and RAM by section and the worst stack"
        " depth (-fcallgraph-info), and exit 1 when flash exceeds firmware.flash_budget or"
        " RAM with the stack firmware.ram_budget.",
        _firmware_arguments,
        _firmware,
    )
)


# --------------------------------------------------------------------- verify


def _verify(args: argparse.Namespace) -> int:
    from verify.__main__ import main as verify_main

    spec = load(args.spec)
    generated = fresh_generated(spec, args.generated)
    argv = [args.spec, "--generated", str(generated)]
    if args.random is not None:
        argv += ["--random", str(args.random)]
    if args.seed is not None:
        argv += ["--seed", str(args.seed)]
    if args.no_progress or args.json:
        argv.append("--no-progress")
    if args.json:
        import contextlib
        import io

        with contextlib.redirect_stdout(io.StringIO()):
            code = verify_main(argv)
        report = generated / "verify" / "report.json"
        emit_json(json.loads(report.read_text(encoding="utf-8")) if report.is_file() else {})
    else:
        code = verify_main(argv)
    return int(ExitCode.CHECK_FAILED) if code == 1 else code


def _verify_arguments(parser: argparse.ArgumentParser) -> None:
    add_spec(parser)
    add_generated(parser)
    parser.add_argument(
        "--seed", type=SEED, metavar="N", help="seed of the random set, to replay a run"
    )
    parser.add_argument(
        "--random",
        type=POINTS,
        metavar="N",
        help="number of random points over the whole input space (default: verify's, 20000)",
    )
    add_progress(parser)
    add_json(parser)


register(
    Command(
        "verify",
        "check the generated C against the exact symbolic model (exit 1 on a failure)",
        "Build the generated core for the host and run it over every Hall period code of"
        " the speed range, random points and the boundaries; compare each output with the"
        " derivation's exact model and the bit-exact Python twin. Writes"
        " DIR/verify/report.json and error_vs_speed.png.",
        _verify_arguments,
        _verify,
    )
)


# --------------------------------------------------------------------- unity


def _unity(args: argparse.Namespace) -> int:
    from verify import unity_run

    spec = load(args.spec)
    generated = fresh_generated(spec, args.generated)
    argv = [str(generated)] + ([args.build] if args.build else [])
    code = unity_run.main(argv)
    return int(ExitCode.CHECK_FAILED) if code == 1 else code


def _unity_arguments(parser: argparse.ArgumentParser) -> None:
    add_spec(parser)
    add_generated(parser)
    parser.add_argument(
        "--build", metavar="DIR", type=path_text, help="build folder (default: a temporary folder)"
    )


register(
    Command(
        "unity",
        "run the generated Unity tests on the host (ASan/UBSan) and on a Cortex-M3 (qemu)",
        "Build and run the generated Unity tests on the host under AddressSanitizer and"
        " UBSan and on an emulated Cortex-M3 (qemu mps2-an385); the per-test results must"
        " be identical. Real Unity when UNITY_DIR points to a checkout, else the stand-in"
        " runner.",
        _unity_arguments,
        _unity,
    )
)


# --------------------------------------------------------------------- simulate


def _simulate(args: argparse.Namespace) -> int:
    from sim.cli import main as sim_main

    spec = load(args.spec)
    out = Path(args.output) if args.output else Path("generated") / spec.name / "simulation"
    argv = [args.spec, "-o", str(out)] + (["--no-progress"] if args.no_progress else [])
    argv += ["--quick"] if getattr(args, "quick", False) else []
    # sim.cli exits with these statuses: 3 a bad spec (already refused above), 70 the
    # derivation, 5 software in the loop or the output folder
    return sim_main(argv)


def _simulate_arguments(parser: argparse.ArgumentParser) -> None:
    add_spec(parser)
    parser.add_argument(
        "-o",
        "--output",
        metavar="DIR",
        type=path_text,
        help="report folder (default: generated/<spec name>/simulation in the current folder)",
    )
    parser.add_argument(
        "--quick",
        action="store_true",
        help="every study at a few speeds: a first look at a new motor (the report says so)",
    )
    add_progress(parser)


register(
    Command(
        "simulate",
        "simulate commutations with the generated C core in the loop; write SIMULATION.md",
        "Generate the spec's core for each method, compile it for the host and drive it"
        " from switched and averaged plants of Eq. 1 over the speed range; write the"
        " figures and SIMULATION.md.",
        _simulate_arguments,
        _simulate,
    )
)


# --------------------------------------------------------------------- robustness


def _robustness(args: argparse.Namespace) -> int:
    from sim.robustness import run as robustness_run

    spec = load(args.spec)  # one line for a bad spec, before Dask starts
    if not args.output:
        args.output = str(Path("generated") / spec.name / "robustness")
    # sim.robustness exits with these statuses: 2 a bad argument, 3 a spec the generator
    # refuses (a bad one was refused above), 5 software in the loop or the output folder
    return robustness_run(args)


def _robustness_arguments(parser: argparse.ArgumentParser) -> None:
    add_spec(parser)
    add_campaign_arguments(parser)
    parser.add_argument(
        "-o",
        "--output",
        metavar="DIR",
        type=path_text,
        help="report folder (default: generated/<spec name>/robustness in the current folder)",
    )
    add_progress(parser)


register(
    Command(
        "robustness",
        "the deviation under the spec's parameter tolerances, on Dask; write ROBUSTNESS.md",
        "Sample the tolerances the spec declares (R hot, L, k_e, the bus) on a Latin"
        " hypercube, run each method's generated C core (software in the loop) at each"
        " speed over the spec's range on a Dask cluster, and write the deviation's"
        " distribution (median, p95, worst) and each parameter's sensitivity to"
        " ROBUSTNESS.md.",
        _robustness_arguments,
        _robustness,
    )
)


# --------------------------------------------------------------------- bench


def _bench(args: argparse.Namespace) -> int:
    from emulation.bench import main as bench_main

    load(args.spec)  # one line for a bad spec, before the heavy imports
    flags = ["--report-only"] if args.report_only else []
    flags += ["--quick"] if args.quick else []
    flags += ["--only", args.only] if args.only is not None else []  # "" is refused there
    return bench_main([args.spec, *flags])  # 3 when the design refuses the spec, as generate


def _bench_arguments(parser: argparse.ArgumentParser) -> None:
    add_spec(parser)
    parser.add_argument(
        "--report-only",
        action="store_true",
        help="print the figures; do not fail on a missed target",
    )
    parser.add_argument("--quick", action="store_true", help="small sweeps (what the tests run)")
    parser.add_argument(
        "--only",
        metavar="SECTIONS",
        type=_sections,
        help="comma-separated sections to run (default: all; an unknown one is refused with"
        f" the list): {', '.join(SECTIONS)}",
    )


def _sections(only: str) -> str:
    """`--only`, checked here so that an unknown section is refused under this command's
    name and usage (it was refused under `python -m emulation`'s)."""
    unknown = unknown_sections(only)
    if unknown:
        named = ", ".join(repr(s) if s else "'' (an empty name)" for s in unknown)
        raise argparse.ArgumentTypeError(
            f"unknown section {named} (allowed: {', '.join(SECTIONS)})"
        )
    return only


register(
    Command(
        "bench",
        "measure speed, size and interrupt cost of the generated code",
        "Generate the spec afresh under build/bench/ and measure, each with its target:"
        " flash and RAM, stack per handler, the interrupt handlers' cycles in an emulated"
        " Cortex-M3 with the STM32F103's flash wait states, the peers (sympy.ccode float and"
        " double, plain fixed point), CPU load, and the run times of derive + audit, verify,"
        " the qemu Unity tests and the simulation. Exit 1 on a missed target.",
        _bench_arguments,
        _bench,
    )
)


# --------------------------------------------------------------------- all


def _all(args: argparse.Namespace) -> int:
    steps = ["generate", "firmware", "verify", "unity", "simulate"] + (
        ["bench"] if args.bench else []
    )
    for step in steps:
        print(f"all: {step} {args.spec}", file=sys.stderr)
        step_args = argparse.Namespace(
            spec=args.spec,
            output=None,
            generated=None,
            build=None,
            json=False,
            seed=None,
            random=args.random,
            no_progress=args.no_progress,
            bench=False,
        )
        code = COMMANDS[step].run(step_args)
        if code != 0:
            print(f"all: stopped at {step} (exit {code})", file=sys.stderr)
            return code
    return 0


def _all_arguments(parser: argparse.ArgumentParser) -> None:
    add_spec(parser)
    parser.add_argument(
        "--random", type=POINTS, metavar="N", help="random points for verify (default: 20000)"
    )
    parser.add_argument("--bench", action="store_true", help="run the bench as the last step")
    add_progress(parser)


register(
    Command(
        "all",
        "generate, then firmware, verify, unity and simulate (and bench with --bench)",
        "Run every step for one spec in the current folder, in order, stopping at the"
        " first that fails; the exit status is that step's.",
        _all_arguments,
        _all,
    )
)

"""`make pil` (`python -m emulation.pil.report SPEC...`): build each spec's firmware,
run every fault scenario (emulation/pil/scenarios.py) on the emulated chip and write
generated/<name>/pil/PIL.md: per scenario the fault latched, the latency from the cause
to MOE cleared against its limit, the invariants, the CPU load from emulated cycles and
the emulation's speed. Exit 1 if any scenario breaks its requirement.

PIL.md is published atomically (written beside, then renamed); it states the spec and
its hash, no timestamps or absolute paths."""

from __future__ import annotations

import argparse
import hashlib
import sys
import tempfile
from pathlib import Path

from codegen.argtypes import path_text
from codegen.errors import ExitCode, SpecError
from codegen.publish import PublishError, os_error_line, require_writable_folder
from codegen.render import write_atomically
from codegen.report_folder import refuse_strangers, staged_report
from codegen.shown import said
from codegen.spec_loader import load_spec
from emulation import progress
from emulation.pil import braking_report
from emulation.pil.braking import BrakingResult, brake, braking_setup
from emulation.pil.build import ROOT, ToolError, build_firmware, checked_in, generate
from emulation.pil.bus import PilError
from emulation.pil.iwdg import WatchdogResetError
from emulation.pil.plant_faults import PLANT_FAULTS, run_plant_fault
from emulation.pil.rcc import TICK_HZ
from emulation.pil.scenarios import SCENARIOS, Outcome, run_scenario


def _us(ticks: int | None) -> str:
    return "-" if ticks is None else f"{ticks * 1e6 / TICK_HZ:.2f} us"


def render(
    spec_path: str,
    name: str,
    outcomes: list[Outcome],
    pwm_hz: float,
    braking: list[str] | None = None,
) -> str:
    digest = hashlib.sha256(Path(spec_path).read_bytes()).hexdigest()[:16]
    shown = Path(spec_path).resolve()
    shown = shown.relative_to(ROOT) if shown.is_relative_to(ROOT) else Path(shown.name)
    emulated = sum(o.emulated_s for o in outcomes)
    wall = sum(o.wall_s for o in outcomes)
    lines = [
        f"# PIL: {name}",
        "",
        f"Spec `{shown.as_posix()}` (sha256 {digest}); written by"
        " `emulation/pil/report.py` (`make pil`). The drive firmware on the emulated"
        " STM32F103 (emulation/pil), the inputs set by each scenario; the braking run and"
        " the scenarios marked 'motor in the loop' drive the simulated motor"
        " (emulation/pil/plant.py).",
        "",
        f"PWM period {1e6 / pwm_hz:.2f} us. Latency: the cause to TIM1's MOE cleared (the"
        " bridge in its safe state), limit one PWM period unless stated.",
        "",
        "| scenario | fault latched | latency | limit | invariants | CPU load | result |",
        "|---|---|---|---|---|---|---|",
    ]
    for o in outcomes:
        problems = o.problems
        lines.append(
            f"| {o.name} | {', '.join(o.fault_names) or 'none'} | {_us(o.latency_ticks)} |"
            f" {_us(o.limit_ticks)} | {'kept' if not o.violations else len(o.violations)} |"
            f" {100 * o.cpu_load:.2f} % | {'PASS' if not problems else 'FAIL: ' + '; '.join(problems)} |"
        )
    lines += ["", "Scenarios:", ""]
    for o in outcomes:
        gap = o.refresh_gap_ticks * 1e3 / TICK_HZ
        limit = o.watchdog_ticks * 1e3 / TICK_HZ
        lines.append(
            f"* **{o.name}**: {o.note}. Longest gap between watchdog refreshes {gap:.2f} ms"
            f" (time-out {limit:.1f} ms at the fastest LSI); {o.samples_checked} current"
            " samples the loop closed on, each window checked."
            + (
                f" app_faults published by main within {_us(o.published_ticks)} of MOE cleared"
                " (looked at two periods after, then once a period)."
                if o.published_ticks is not None
                else ""
            )
        )
    lines += [
        "",
        "Invariants checked at every step: no shoot-through and no dead time shorter than"
        " the spec's (every gate edge), CCR1..CCR3 within the PWM period and changed only"
        " at an update event (preload), the timing handler never above the Hall edge or"
        " the current loop, every Hall edge commutating, every current sample the loop"
        " closes on taken in a clean window (no gate edge inside its sampling window, with"
        " the datasheet's injection latency, nor within sensing.settling_time before it),"
        " no hard fault, no watchdog reset. CPU load: time in handlers (entry and exit included, the emulator's"
        " cycle model) over emulated time, from boot's end.",
        "",
        f"Emulation: {emulated * 1e3:.1f} ms emulated in {wall:.1f} s wall"
        f" ({emulated * 1e3 / wall:.1f} emulated ms per second, boot and build excluded).",
        "",
    ]
    if braking:
        lines += braking
    return "\n".join(lines)


def _plant_faults_section(outcomes: list[Outcome]) -> list[str]:
    lines = [
        "## Fault scenarios with the motor in the loop",
        "",
        "The firmware brakes the simulated motor from the braking scenario's start; after"
        " a few commutations the cause is applied (emulation/pil/plant_faults.py). The"
        " invariants are watched throughout; these outcomes count in the table above.",
        "",
        "| scenario | fault latched | latency | limit | invariants | result |",
        "|---|---|---|---|---|---|",
    ]
    for o in outcomes:
        problems = o.problems
        lines.append(
            f"| {o.name} | {', '.join(o.fault_names) or 'none'} | {_us(o.latency_ticks)} |"
            f" {_us(o.limit_ticks)} | {'kept' if not o.violations else len(o.violations)} |"
            f" {'PASS' if not problems else 'FAIL: ' + '; '.join(problems)} |"
        )
    lines.append("")
    return lines


#: the report's name, and what its header says in every version (codegen/report_folder.py)
REPORT_NAME = "PIL.md"
REPORT_MARKER = "written by `emulation/pil/report.py`"


def publish(text: str, target: Path) -> None:
    """Written beside `target` and renamed (`write_atomically`), with the permissions
    any new file gets: a NamedTemporaryFile renamed left PIL.md and the commutations'
    CSV readable by their owner alone (0600), the figures beside them 0644."""
    write_atomically(target, text)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m emulation.pil.report", description=__doc__)
    parser.add_argument("specs", nargs="+")
    parser.add_argument(
        "--braking",
        choices=("full", "short", "off"),
        default="full",
        help="the braking scenario: to its stop speed (default), its first Hall edges, or none",
    )
    parser.add_argument(
        "--no-progress",
        action="store_true",
        help="no progress bars on stderr (they show only when stderr is a terminal)",
    )
    parser.add_argument(
        "-o",
        "--output",
        type=lambda text: Path(path_text(text)),
        default=None,
        help="the folder of PIL.md, its CSV and figures (one spec only; default"
        " generated/<name>/pil/ under the current folder)",
    )
    args = parser.parse_args(argv)
    if args.output is not None and len(args.specs) > 1:
        parser.error(f"-o {args.output}: one spec only (got {len(args.specs)})")
    progress.enabled = sys.stderr.isatty() and not args.no_progress
    failed = False
    for spec_path in args.specs:
        try:
            spec = load_spec(spec_path)
        except SpecError as error:  # every error of the spec, one line each
            for line in str(error).splitlines():
                print(f"error: {line}", file=sys.stderr)
            return int(ExitCode.SPEC)
        # under the current folder, as every command's output (the package's own folder
        # was used: a run from elsewhere wrote into the project's generated/, over the
        # report of a checked-in motor of the same name)
        out = Path.cwd() / (args.output or Path("generated") / spec.name / "pil")
        target = out / REPORT_NAME
        try:  # a stranger's PIL.md stops the run before it starts, not after it
            require_writable_folder(out)
            refuse_strangers(out, [REPORT_NAME], REPORT_NAME, REPORT_MARKER)
        except (PublishError, OSError) as error:
            return _cannot_write(error)
        with tempfile.TemporaryDirectory() as folder:
            try:
                path = Path(spec_path).resolve()
                generated = checked_in(path) or generate(path, Path(folder) / "generated")
                elf = build_firmware(path, Path(folder), generated)
            except ToolError as error:  # the tool's own lines and status (3: no design)
                for line in error.lines or [str(error)]:
                    print(line, file=sys.stderr)
                return error.returncode
            except RuntimeError as error:
                print(f"error: {error}", file=sys.stderr)
                return 1
            outcomes = [
                run_scenario(elf, spec, s)
                for s in progress.progress(SCENARIOS, f"pil {spec.name} fault scenarios")
            ]
            result: BrakingResult | None = None
            plant_outcomes: list[Outcome] = []
            if args.braking != "off":
                setup = braking_setup(spec, short=args.braking == "short")
                try:
                    result = brake(elf, generated / "c" / "stm32f103_port.c", spec, setup)
                except (PilError, WatchdogResetError, TimeoutError) as error:
                    # e.g. a fault latched at boot, or no boot at all: no motor to brake
                    print(f"error: pil: {spec.name}: braking: {error}", file=sys.stderr)
                    return 1
                plant_outcomes = [
                    run_plant_fault(elf, generated / "c" / "stm32f103_port.c", spec, f)
                    for f in progress.progress(
                        PLANT_FAULTS, f"pil {spec.name} faults with the motor in the loop"
                    )
                ]
                outcomes += plant_outcomes
        # the report, its CSV and figures staged and moved in together, the ledger first
        # (codegen/report_folder.py): they were written into the folder as they came, so
        # a run stopped half-way left new figures beside the former PIL.md, and a run
        # without braking left a former run's CSV and figures beside its own
        try:
            with staged_report(out, REPORT_NAME, REPORT_MARKER) as staging:
                section: list[str] | None = None
                if result is not None:
                    names = braking_report.write_figures(result, staging)
                    csv = staging / "braking_commutations.csv"
                    publish(braking_report.csv_text(result), csv)
                    section = braking_report.section(result, names)
                    section += _plant_faults_section(plant_outcomes)
                pwm_hz = float(spec.inverter.pwm_frequency_hz)
                text = render(spec_path, spec.name, outcomes, pwm_hz, section)
                publish(text, staging / REPORT_NAME)
        except (PublishError, OSError) as error:
            return _cannot_write(error)
        bad = [o for o in outcomes if o.problems]
        failed |= bool(bad)
        braking_problems = [] if result is None else braking_report.problems(result)
        failed |= bool(braking_problems)
        if result is not None:
            print(
                f"pil:   braking: {result.emulated_s * 1e3:.1f} ms, {result.setup.start_rpm:.0f}"
                f" -> {result.end_rpm:.0f} rpm, {len(result.commutations)} commutations;"
                f" {'; '.join(braking_problems[:3]) or 'pass'}"
                + "".join(
                    f"; {check} not judged: {why}"
                    for check, why in braking_report.not_judged(result)
                )
            )
        print(
            summary_line(
                spec.name, len(outcomes) - len(bad), len(outcomes), result, braking_problems
            )
            + f" -> {said(target)}"
        )
        for o in outcomes:
            print(
                f"pil:   {o.name}: latency {_us(o.latency_ticks)} (limit {_us(o.limit_ticks)}); {'; '.join(o.problems) or 'pass'}"
            )
    return 1 if failed else 0


def _cannot_write(error: OSError | PublishError) -> int:
    """One line for an output folder the report cannot go into; the environment's status."""
    line = str(error) if isinstance(error, PublishError) else os_error_line(error)
    print(f"error: pil: {line.removeprefix('error: ')}", file=sys.stderr)
    return int(ExitCode.ENVIRONMENT)


def summary_line(
    name: str, passed: int, total: int, braking: BrakingResult | None, braking_problems: list[str]
) -> str:
    """The run's one-line verdict: the fault scenarios and the braking run, which is no
    scenario of the table (a spec whose braking failed read '22/22 scenarios pass' and
    exited 1)."""
    if braking is None:
        run = "braking run off"
    elif braking_problems:
        run = "braking run FAILS"
    else:
        run = "braking run passes"
    return f"pil: {name}: {passed}/{total} fault scenarios pass, {run}"


if __name__ == "__main__":
    from codegen.interrupts import exit_status

    raise SystemExit(exit_status(main))

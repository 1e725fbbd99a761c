"""`bldc-codegen`: one command line for every step, on any spec.

    bldc-codegen init NAME            a commented spec for a new motor
    bldc-codegen derive SPEC          the derived equations and the spec's key numbers
    bldc-codegen audit SPEC           the paper audit (AUDIT.md)
    bldc-codegen generate SPEC        C, Python models, firmware files, Unity tests, audit
    bldc-codegen firmware SPEC        cross-compile for the Cortex-M3, flash/RAM by section
    bldc-codegen verify SPEC          the generated C against the exact symbolic model
    bldc-codegen unity SPEC           the Unity tests on the host and under qemu
    bldc-codegen simulate SPEC        the commutation simulation and its report
    bldc-codegen robustness SPEC      the deviation under parameter tolerances (Dask)
    bldc-codegen bench SPEC           speed, size and interrupt-cost figures
    bldc-codegen all SPEC             generate, firmware, verify, unity, simulate

`python -m codegen` is the same; `python -m verify`, `python -m sim` and
`python -m verify.unity_run` remain as the modules' own entry points.

Each command is one `Command` registered with `register()` (bldc/commands/); adding
one is a function, its options, and one `register(...)` call. Paths on the command line
resolve against the current directory; output goes to `generated/<name>/` under it
unless `-o` says otherwise. Messages go to stderr, results to stdout (`--json` where a
script wants them).

Exit status (codegen.errors.ExitCode): 0 success (also when the paper has errors:
finding them is the audit's job), 1 a check failed, 2 usage error, 3 bad spec, 4 stale
or missing generated output, 5 environment (an output folder that cannot be written, a
missing or failing external tool), 70 internal error (a bug; the message says where).
"""

from __future__ import annotations

import argparse
import contextlib
import os
import subprocess
import sys
import textwrap
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path

from codegen import __version__
from codegen.errors import DerivationError, ExitCode, SpecError, internal_error_line
from codegen.freshness import StaleOutputError
from codegen.publish import PublishError, os_error_line
from codegen.render import PROJECT_ROOT
from codegen.shown import on_one_line

PROG = "bldc-codegen"
EXIT_SPEC = int(ExitCode.SPEC)
EXIT_DERIVATION = int(ExitCode.INTERNAL)


@dataclass(frozen=True)
class Command:
    """One subcommand: its name, a one-line summary, a longer description for --help,
    a function adding its options, and the function that runs it (returns the exit
    status)."""

    name: str
    summary: str
    description: str
    arguments: Callable[[argparse.ArgumentParser], None]
    run: Callable[[argparse.Namespace], int]


COMMANDS: dict[str, Command] = {}


def register(command: Command) -> Command:
    """Add a subcommand to `bldc-codegen` (in the order registered)."""
    if command.name in COMMANDS:
        raise ValueError(f"command {command.name!r} registered twice")
    COMMANDS[command.name] = command
    return command


class _Formatter(argparse.RawDescriptionHelpFormatter):
    """Keeps descriptions as written and shows each option's default."""

    def _get_help_string(self, action: argparse.Action) -> str:
        text = action.help or ""
        if (
            action.default not in (None, False, argparse.SUPPRESS)
            and "%(default)" not in text
            and action.option_strings
        ):
            text += " (default: %(default)s)"
        return text


def _add_traceback(parser: argparse.ArgumentParser, default: object) -> None:
    parser.add_argument(
        "--traceback",
        action="store_true",
        default=default,
        help="on an internal error, print the full Python traceback instead of one line",
    )


def build_parser() -> argparse.ArgumentParser:
    import bldc.commands  # noqa: F401  (registers the commands)

    parser = argparse.ArgumentParser(
        prog=PROG,
        description=__doc__.split("\n\n")[0] if __doc__ else PROG,
        epilog=__doc__.split("\n\n", 1)[1] if __doc__ else None,
        formatter_class=_Formatter,
    )
    parser.add_argument("--version", action="version", version=f"{PROG} {__version__}")
    _add_traceback(parser, default=False)
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    for command in COMMANDS.values():
        child = sub.add_parser(
            command.name,
            help=command.summary,
            description=textwrap.fill(command.description, 88),
            formatter_class=_Formatter,
        )
        command.arguments(child)
        # after the command too (`generate SPEC --traceback`), as the internal-error line
        # says; SUPPRESS leaves a --traceback given before the command in place
        _add_traceback(child, default=argparse.SUPPRESS)
        child.set_defaults(func=command.run)
    return parser


def _one_line(text: object) -> str:
    return " ".join(str(text).split())


def _internal(exc: BaseException) -> bool:
    """Whether `_report` calls `exc` an internal error (a bug), the one --traceback
    shows whole."""
    base = sys.modules.get("codegen.methods.base")
    design = getattr(base, "FixedPointError", None) if base else None
    known: tuple[type[BaseException], ...] = (
        SpecError,
        StaleOutputError,
        PublishError,
        subprocess.CalledProcessError,
        OSError,
    )
    if design is not None:
        known = (*known, design)
    return not isinstance(exc, known)


def _report(exc: BaseException, args: argparse.Namespace) -> int:
    """The exit status for an exception, after printing it on stderr as error lines."""
    # The design's errors come from modules that import SymPy: look them up only if
    # they are loaded (an exception of theirs was raised), so a bad spec stays fast.
    base = sys.modules.get("codegen.methods.base")
    FixedPointError = getattr(base, "FixedPointError", ()) if base else ()
    spec = on_one_line(str(getattr(args, "spec", "") or ""))
    if isinstance(exc, SpecError):
        for line in str(exc).splitlines():
            print(f"error: {line}", file=sys.stderr)
        return EXIT_SPEC
    if isinstance(exc, FixedPointError):
        # names the spec key the user would change, e.g. accuracy.duty_counts
        print(f"error: {spec}: {exc.key}: fixed-point design: {_one_line(exc)}", file=sys.stderr)
        return EXIT_SPEC
    if isinstance(exc, StaleOutputError):
        print(f"error: {_one_line(exc)}", file=sys.stderr)
        return int(ExitCode.STALE)
    if isinstance(exc, PublishError):
        print(f"error: output: {_one_line(exc)}", file=sys.stderr)
        return int(ExitCode.ENVIRONMENT)
    if isinstance(exc, DerivationError):
        print(f"derivation failed (a bug in bldc-codegen): {_one_line(exc)}", file=sys.stderr)
        return EXIT_DERIVATION
    if isinstance(exc, subprocess.CalledProcessError):
        words = [str(w) for w in exc.cmd] if isinstance(exc.cmd, (list, tuple)) else [str(exc.cmd)]
        if words and Path(words[0]).name.startswith("python"):
            words[0] = "python"
        command = " ".join(words)
        command = command if len(command) <= 120 else command[:117] + "..."
        print(f"error: `{command}` failed with exit status {exc.returncode}", file=sys.stderr)
        return int(ExitCode.ENVIRONMENT)
    if isinstance(exc, OSError):
        print(os_error_line(exc), file=sys.stderr)
        return int(ExitCode.ENVIRONMENT)
    print(internal_error_line(exc, PROJECT_ROOT), file=sys.stderr)
    return int(ExitCode.INTERNAL)


def main(argv: Sequence[str] | None = None) -> int:
    try:
        # the parser imports every command: an interrupt there (Ctrl-C at once) had
        # printed a 50-line traceback
        args = build_parser().parse_args(argv)
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return int(ExitCode.INTERRUPTED)
    try:
        return int(args.func(args))
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return int(ExitCode.INTERRUPTED)
    except BrokenPipeError:
        # whoever read stdout has gone (`derive SPEC | head -2`): nothing to tell, and
        # no "error: Broken pipe"; the status a shell gives a command SIGPIPE ended
        with contextlib.suppress(OSError, ValueError):
            os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 128 + 13
    except Exception as exc:
        wanted = args.traceback or os.environ.get("BLDC_CODEGEN_TRACEBACK")
        if wanted and _internal(exc):
            raise
        # a bad spec, stale output, the environment: the same line and status with the
        # flag (it had re-raised every error: a refused spec exited 1, not 3)
        return _report(exc, args)


__all__ = ["COMMANDS", "EXIT_DERIVATION", "EXIT_SPEC", "Command", "ExitCode", "main", "register"]

if __name__ == "__main__":
    # `python -m bldc.cli` as `python -m bldc`: through the entry point, which imports
    # this module by its name (run as __main__ it would be a second copy, with no
    # commands registered in it), so it does not exit 0 having done nothing
    from bldc.entry import main as entry

    raise SystemExit(entry())

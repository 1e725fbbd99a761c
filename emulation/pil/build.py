"""The firmware of any spec for the emulated chip: `bldc-codegen generate` into a
folder of its own, then `bldc-codegen firmware` (the `make firmware` command) from it,
so a spec with no checked-in generated/ output (a test fixture) builds too. A port
mutant is linked from an edited copy of a generated folder (`link_mutant`).

The commands run in this process (`bldc.cli.main`, the same code as the command line,
with the paths resolved from the project root as the command would resolve them
there): a second interpreter would only start Python and import SymPy again, and derive
again what this process has derived already (2.5 s a generate). Their messages are
captured, so callers run them one at a time (stdout and stderr are the process's)."""

from __future__ import annotations

import contextlib
import io
import shutil
import subprocess
from collections.abc import Callable
from pathlib import Path

from codegen.build_firmware import build as build_sources
from codegen.freshness import StaleOutputError, check_fresh
from codegen.spec_loader import load_spec

ROOT = Path(__file__).resolve().parents[2]


class ToolError(RuntimeError):
    """A bldc-codegen step failed: its exit status (a spec no design meets is
    ExitCode.SPEC) and its own error lines."""

    def __init__(self, step: str, returncode: int, stderr: str, stdout: str = "") -> None:
        self.returncode = returncode
        # the spec's warnings are not why it failed (a spec that loads warns on stderr too)
        self.lines = [
            line
            for line in stderr.strip().splitlines()
            if line.strip() and not line.startswith("warning:")
        ]
        if not self.lines:  # `firmware` reports an exceeded budget on stdout
            said = [line.strip() for line in stdout.strip().splitlines() if line.strip()]
            # the exceeded budget, and the hint naming its spec key (`budget_hint`): the
            # budget's line alone named no key (a helper's hunt: "RAM ... 584 B of 512 B")
            self.lines = [
                line for line in said if "EXCEEDED" in line or line.startswith("firmware.")
            ] or said[-1:]
        super().__init__(f"bldc-codegen {step}: {' / '.join(self.lines) or 'no output'}")


def _codegen(command: str, spec: Path, *options: str | Path) -> None:
    """`bldc-codegen command spec options` as if run from the project root; raises
    ToolError with the command's status and its own messages when it fails."""
    from bldc import cli  # the command line sits above emulation; imported when used

    argv = [command, str(ROOT / spec)]
    argv += [str(ROOT / o) if isinstance(o, Path) else o for o in options]
    messages, said = io.StringIO(), io.StringIO()
    try:
        with contextlib.redirect_stderr(messages), contextlib.redirect_stdout(said):
            status = cli.main(argv)
    except SystemExit as stop:  # argparse's usage error
        status = stop.code if isinstance(stop.code, int) else 2
    if status != 0:
        raise ToolError(f"{command} {spec}", status, messages.getvalue(), said.getvalue())


def generate(spec: Path, generated: Path) -> Path:
    """`bldc-codegen generate spec -o generated`; the folder."""
    _codegen("generate", spec, "-o", generated)
    return generated


def checked_in(spec: Path) -> Path | None:
    """The spec's checked-in generated folder (kept fresh by `make check-generated`),
    where it holds this spec's current output: a user's motor may share its name with a
    checked-in one (a copy of spec/paper_motor.yaml, edited), or the spec may have been
    edited since; then None, and the caller generates it (`make pil` stopped instead,
    asking to regenerate it over the checked-in folder)."""
    loaded = load_spec(str(spec))
    folder = ROOT / "generated" / loaded.name
    try:
        check_fresh(loaded, folder)
    except StaleOutputError:
        return None
    return folder


def build_firmware(spec: Path, folder: Path, generated: Path | None = None) -> Path:
    """Link `spec` under `folder` from `generated`, or from its own generation there;
    the ELF's path. Raises RuntimeError with the tool's own message when a step fails
    (`firmware` refuses a generated folder that is not this spec's, fresh)."""
    generated = generated or generate(spec, folder / "generated")
    build = ROOT / folder / "build"  # where `firmware` puts it (a relative folder is the root's)
    _codegen("firmware", spec, "--generated", generated, "--build", build)
    return build / "firmware.elf"


def link_mutant(generated: Path, folder: Path, mutate: Callable[[Path], None]) -> Path:
    """Copy `generated` into `folder`, let `mutate` edit the copy, link it (`firmware`
    refuses an edited generated folder, so the sources are linked directly); the ELF."""
    copy, build = folder / "generated", folder / "build"
    shutil.copytree(generated, copy)
    mutate(copy)
    try:
        build_sources(copy, build)
    except subprocess.CalledProcessError as error:
        raise RuntimeError(f"the mutant does not build: {error.stderr or error}") from error
    return build / "firmware.elf"

"""The firmware of any spec for the emulated chip: `bldc-codegen generate` into a
folder of its own, then `bldc-codegen firmware` (the `make firmware` command) from it,
so a spec with no checked-in generated/ output (a test fixture) builds too."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def build_firmware(spec: Path, folder: Path) -> Path:
    """Generate and link `spec` under `folder`; the ELF's path. Raises RuntimeError with
    the tool's own message when either step fails."""
    generated, build = folder / "generated", folder / "build"
    for command in (
        ["generate", str(spec), "-o", str(generated)],
        ["firmware", str(spec), "--generated", str(generated), "--build", str(build)],
    ):
        done = subprocess.run(
            [sys.executable, "-m", "codegen", *command], cwd=ROOT, capture_output=True, text=True
        )
        if done.returncode != 0:
            raise RuntimeError(f"bldc-codegen {command[0]} {spec}: {done.stderr.strip()}")
    return build / "firmware.elf"

"""Jinja2 rendering: one strict environment, and the provenance every output carries.

Templates receive ready-made strings and integers (SymForce's "print in Python, lay out
in templates"); a missing variable is an error, never an empty string.
"""

from __future__ import annotations

import os
import re
import shlex
import unicodedata
from functools import lru_cache
from pathlib import Path
from typing import Any

import jinja2

from codegen.spec_model import Spec

PROJECT_ROOT = Path(__file__).resolve().parents[1]
TEMPLATE_DIR = PROJECT_ROOT / "templates"


def markdown_cell(text: object) -> str:
    """Text safe inside a Markdown table cell: pipes escaped, one line."""
    return str(text).replace("|", "\\|").replace("\n", " ")


def environment(template_dir: Path = TEMPLATE_DIR) -> jinja2.Environment:
    env = jinja2.Environment(
        loader=jinja2.FileSystemLoader(str(template_dir)),
        undefined=jinja2.StrictUndefined,
        trim_blocks=True,
        lstrip_blocks=True,
        keep_trailing_newline=True,
        autoescape=False,
    )
    env.filters["cell"] = markdown_cell
    return env


#: Characters a path may show in a generated file. None of them can end a C or linker
#: comment (`*/`), a Python comment (a newline) or a Markdown/HTML comment (`-->`), start
#: a trigraph (`??`), continue a line (a backslash) or reach a terminal as a control code.
_SAFE_PATH = re.compile(r"[A-Za-z0-9 _.,+=@%/-]{1,200}\Z", re.ASCII)
WITHHELD = "path withheld: unsafe characters"


def project_relative(path: str | Path) -> str:
    """A path as it should appear in generated files: relative to the project when
    inside it, else just the file name, so output never depends on the checkout; and
    `<path withheld: unsafe characters>` when it holds anything that could end the
    comment or string it is printed in (see _SAFE_PATH)."""
    resolved = Path(path).resolve()
    try:
        shown = resolved.relative_to(PROJECT_ROOT).as_posix()
    except ValueError:
        shown = resolved.name
    if _safe_path(shown):
        return shown
    return f"<{WITHHELD}>"


def _safe_path(shown: str) -> bool:
    """_SAFE_PATH's characters, and letters and digits beyond ASCII (`motör.yaml` had
    been withheld: none of them ends a comment, and UTF-8 is what every file is
    written in); never a control, format (bidirectional) or other invisible one."""
    if "--" in shown or not 0 < len(shown) <= 200:
        return False
    plain = "".join(c if c.isascii() or not _letter_or_digit(c) else "a" for c in shown)
    return bool(_SAFE_PATH.match(plain))


def _letter_or_digit(char: str) -> bool:
    return unicodedata.category(char)[0] in "LNM"


def spec_label(spec: Spec) -> str:
    """The spec's path as generated files may show it (project_relative), or, when that
    is withheld, `<the spec named NAME, path withheld: ...>` after its own name, a checked
    identifier. The hash beside it identifies the file either way."""
    shown = project_relative(spec.source_path)
    # the spec's name, not a file name: `<paper_motor.yaml, ...>` had named another file
    return shown if shown != f"<{WITHHELD}>" else f"<the spec named {spec.name}, {WITHHELD}>"


def regenerate_hint(spec: Spec) -> str:
    """The command that writes a spec's generated files again, as their first line says
    it: `bldc-codegen generate` on the spec as the line shows it (spec_label), quoted for
    a shell. It had said `make`, which generates the default spec only."""
    label = spec_label(spec)
    if label.startswith("<"):  # withheld: `generate <the spec named ...>` reads as a redirect
        return "bldc-codegen generate SPEC"
    return f"bldc-codegen generate {shlex.quote(label)}"


def provenance(template: str, spec: Spec) -> str:
    """One line naming the template (its path from the project root: templates/...),
    the spec and its hash, and the command that regenerates it; no time, no version.
    Safe inside a C, Python or Markdown comment whatever the spec's path (spec_label)."""
    return (
        f"Generated from template {template} with spec {spec_label(spec)}"
        f" (sha256 {spec.sha256}). Do not edit: regenerate with `{regenerate_hint(spec)}`."
    )


@lru_cache(maxsize=8)
def shared_environment(template_dir: Path = TEMPLATE_DIR) -> jinja2.Environment:
    """`environment(template_dir)`, one per process: Jinja2 compiles each template once
    per environment (and again when its file changes), where a new environment per
    render compiled every template at every use. Not to be changed: `environment()`
    gives one to adapt."""
    return environment(template_dir)


def render(template: str, **context: object) -> str:
    return shared_environment().get_template(template).render(**context)


def save_figure_atomically(figure: Any, path: Path, dpi: int) -> None:
    """A matplotlib figure as PNG, drawn beside the target and renamed, as
    `write_atomically`: a run stopped while it was drawn left an empty or cut PNG."""
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(f".{path.name}.tmp-{os.getpid()}")
    try:
        figure.savefig(tmp, dpi=dpi, format="png", metadata={"Software": None})
        os.replace(tmp, path)
    finally:
        tmp.unlink(missing_ok=True)


def write_atomically(path: Path, text: str) -> None:
    """Write beside the target and rename, so a reader never sees half a file."""
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(f".{path.name}.tmp-{os.getpid()}")
    try:
        tmp.write_text(text, encoding="utf-8", newline="\n")
        os.replace(tmp, path)
    except OSError as exc:
        # name the file the user asked for, not the temporary one beside it
        # (`init -o /proc/x.yaml` said "/proc/.x.yaml.tmp-29017: No such file ...")
        raise OSError(exc.errno, exc.strerror, str(path)) from None
    finally:
        if tmp.exists():
            tmp.unlink()

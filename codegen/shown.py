"""How a path is shown on the console: as the user would type it from here."""

from __future__ import annotations

from pathlib import Path


def shown(path: str | Path) -> str:
    """Relative to the current folder when inside it, else absolute. (Generated files
    use `codegen.render.project_relative` instead: their text must not depend on where
    the tool ran.)"""
    resolved = Path(path).resolve()
    try:
        return resolved.relative_to(Path.cwd().resolve()).as_posix() or "."
    except ValueError:
        return str(resolved)


def on_one_line(text: str) -> str:
    """`text` as it is when every character prints, else quoted with Python's escapes
    (a path with a line break or an escape sequence in it, in a one-line message)."""
    return text if text.isprintable() else repr(text)


def said(path: str | Path) -> str:
    """`shown(path)` for a message line: quoted with Python's escapes where it holds a
    line break or another character that does not print (`bldc-codegen init -o
    $'new\\nline.yaml'` had split "init: wrote ..." over two lines)."""
    return on_one_line(shown(path))

"""codegen sits above everything else: it imports neither verify, sim nor emulation (the
benchmark moved out of it into emulation/)."""

from __future__ import annotations

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
BELOW = ("verify", "sim", "emulation")


def _imported(path: Path) -> set[str]:
    names: set[str] = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import):
            names.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            names.add(node.module)
    return names


def test_codegen_should_import_nothing_below_it() -> None:
    sources = sorted((ROOT / "codegen").rglob("*.py"))
    assert len(sources) > 20  # the walk really sees the package
    offending = {
        str(path.relative_to(ROOT)): sorted(n for n in _imported(path) if n.split(".")[0] in BELOW)
        for path in sources
    }
    assert {k: v for k, v in offending.items() if v} == {}
    # and the check does see an import when there is one
    assert "emulation.bench" in _imported(ROOT / "emulation" / "__main__.py")

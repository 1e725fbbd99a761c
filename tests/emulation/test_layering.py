"""codegen sits above everything else: it imports neither verify, sim nor emulation (the
benchmark moved out of it into emulation/). The oracle and the verifier take from the
generator only what an allow-list names (pyproject.toml's import contracts hold the same
as lists of what is forbidden, which a new module of codegen would slip past)."""

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
            if node.module == "codegen":  # from codegen import spec_model
                names.update(f"codegen.{alias.name}" for alias in node.names)
    return names


#: what the oracle may take from the generator: the validated spec's types
ORACLE_MAY_IMPORT = frozenset({"codegen.spec_model", "codegen.errors"})
#: what the verifier may: the spec, and the plumbing of a command (arguments, exit
#: codes, publishing a report, naming a stale tree); nothing of the design
VERIFY_MAY_IMPORT = ORACLE_MAY_IMPORT | {
    "codegen.spec_loader",
    "codegen.argtypes",
    "codegen.interrupts",
    "codegen.freshness",
    "codegen.manifest_check",
    "codegen.publish",
    "codegen.render",
    "codegen.report_folder",
    "codegen.shown",
}
#: verify.prove proves the generator's own output: it generates it
PROVE_MAY_IMPORT = VERIFY_MAY_IMPORT | {"codegen.generate", "codegen.methods.base"}


def _from_codegen(path: Path) -> set[str]:
    return {n for n in _imported(path) if n.split(".")[0] == "codegen" and n != "codegen"}


def test_the_oracle_and_the_verifier_should_import_only_their_allow_lists() -> None:
    """A hunt added `from codegen.dead_time import latest_end_ticks` to verify/check.py
    and `from codegen.units import *` to oracle/units.py, and the blocklists passed."""
    allowed = {"oracle": ORACLE_MAY_IMPORT, "verify": VERIFY_MAY_IMPORT}
    offending: dict[str, list[str]] = {}
    seen = 0
    for package, may in allowed.items():
        for path in sorted((ROOT / package).rglob("*.py")):
            seen += 1
            ok = PROVE_MAY_IMPORT if path == ROOT / "verify" / "prove.py" else may
            extra = sorted(_from_codegen(path) - ok)
            if extra:
                offending[str(path.relative_to(ROOT))] = extra
    assert seen > 10
    assert offending == {}
    # and the walk sees an import of codegen when there is one, in either form
    assert "codegen.spec_model" in _from_codegen(ROOT / "oracle" / "model.py")
    assert "codegen.spec_drive" in _from_codegen(ROOT / "codegen" / "spec_loader.py")


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

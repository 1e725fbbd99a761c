"""The ACSL contracts printed into the header: their yardsticks come from the spec.

The valid Hall pairs of the contract are spelled from `hall.sequence`; the edge table
they judge comes from the derivation's switching table. The two must agree pair by
pair, and the printed contract must name every public function.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from codegen.core.contracts import PUBLIC, valid_hall_pair
from codegen.core.module import build_core, core_context
from codegen.spec_loader import load_spec

ROOT = Path(__file__).resolve().parents[1]
SPECS = [
    *sorted((ROOT / "spec").glob("*motor*.yaml")),
    ROOT / "spec" / "example_maxon_ec45_flat_48v.yaml",
    *sorted((ROOT / "tests" / "fixtures" / "specs").glob("*.yaml")),
]


def _pairs(predicate_body: tuple[str, ...]) -> set[tuple[int, int]]:
    out = set()
    for disjunct in predicate_body:
        previous, code = (int(part.split("==")[1].strip(" ()")) for part in disjunct.split("&&"))
        out.add((previous, code))
    return out


@pytest.mark.parametrize("spec", SPECS, ids=lambda p: Path(p).stem)
def test_valid_hall_pairs_should_be_the_edges_of_the_table(spec: Path) -> None:
    loaded = load_spec(spec)
    core = build_core(loaded)
    table = next(t for t in core.module.tables if t.name == "bldc_edge_of_hall_pair")
    edges = {(k >> 3, k & 7) for k, (edge,) in enumerate(table.rows) if edge != 0xFF}
    assert _pairs(valid_hall_pair(loaded.hall.sequence).body) == edges
    assert len(edges) == 12


@pytest.mark.parametrize("spec", SPECS, ids=lambda p: Path(p).stem)
def test_every_public_function_should_carry_its_contract(spec: Path) -> None:
    context = core_context(build_core(load_spec(spec)))
    entries = [*context["h_prototypes"], *context["h_inline"]]  # type: ignore[misc]
    found = set()
    for entry in entries:
        lines = entry.splitlines()
        signature = next(
            k for k, line in enumerate(lines) if not line.startswith(("/*", " ", "*/"))
        )
        name = re.search(r"(\w+)\(", lines[signature]).group(1)  # type: ignore[union-attr]
        assert any(line.startswith("/*@") for line in lines[:signature]), name
        found.add(name)
    assert found == set(PUBLIC)

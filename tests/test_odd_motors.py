"""Unusual motors every command was run on (generate, firmware, verify, unity, prove on
two, simulate, the PIL's fault scenarios): here each is generated twice (byte-identical)
and verified against the oracle."""

from __future__ import annotations

from pathlib import Path

import pytest

from codegen.generate import render_all, write_tree
from verify.run import verify

ROOT = Path(__file__).resolve().parents[1]
ODD = ROOT / "tests" / "fixtures" / "odd"


@pytest.mark.parametrize(
    "name", ["pp1_60krpm_20k", "pp30_5_to_120rpm", "rev_hall_centre_shunts_sc"]
)
def test_an_unusual_motor_should_regenerate_identically_and_verify(
    tmp_path: Path, name: str
) -> None:
    spec = ODD / f"{name}.yaml"
    first, second = render_all(spec).files, render_all(spec).files
    assert first == second
    generated = tmp_path / "generated"
    write_tree(first, generated)
    result, _, _, _ = verify(
        spec,
        generated,
        tmp_path / "build",
        seed=20261129,
        random_count=500,
        exhaustive_stride=7,
        show_progress=False,
    )
    failed = [f"{k}: {c.note}" for k, c in result.checks.items() if c.verdict != "PASS"]
    assert result.passed, failed

"""The verifier: green on the generated core, red on every deliberately broken one.

A green verify proves nothing unless it goes red when the C is wrong, so each mutant
below plants one classic fault in a copy of the generated core and the verifier must
reject it through a symbolic check, not only through the twin comparison (the twin is
left unmutated, so it disagrees with every mutant by construction).
"""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from verify.run import VerifyResult, verify

ROOT = Path(__file__).resolve().parents[1]
SPECS = {
    "paper_motor": ROOT / "spec" / "paper_motor.yaml",
    "paper_motor_improved_r": ROOT / "spec" / "paper_motor_improved_r.yaml",
    "maxon_ec45_flat_48v": ROOT / "spec" / "example_maxon_ec45_flat_48v.yaml",
}


def _verify(name: str, generated: Path, tmp_path: Path) -> VerifyResult:
    result, _, _, _ = verify(
        SPECS[name],
        generated,
        tmp_path / "build",
        seed=20261121,
        random_count=4000,
        exhaustive_stride=5,
        show_progress=False,
    )
    return result


@pytest.mark.parametrize("name", sorted(SPECS))
def test_verify_should_pass_on_the_checked_in_core(name: str, tmp_path: Path) -> None:
    result = _verify(name, ROOT / "generated" / name, tmp_path)
    assert result.passed, {k: (c.failures, c.max_error) for k, c in result.checks.items()}
    assert result.sets["random"] == 4000 and result.sets["boundary"] > 1000
    assert result.checks["turn_on"].max_error <= result.checks["turn_on"].bound  # type: ignore[operator]


#: (mutant, file, original text, replacement, the symbolic check that must fail), on
#: the paper motor's core
MUTANTS = [
    (
        "flipped_sign_of_2E",
        "bldc_commutation.c",
        "* BLDC_X_SCALE - (int32_t)x_q;",
        "* BLDC_X_SCALE + (int32_t)x_q;",
        "commutation_time",
    ),
    (
        "region_boundary_one_code_off",
        "bldc_commutation.c",
        "(period_ticks < bus->high_speed_period)",
        "(period_ticks <= bus->high_speed_period)",
        "flags",
    ),
    (
        "truncation_instead_of_rounding",
        "bldc_commutation.c",
        "((x_q + 32u) >> BLDC_X_FRAC_BITS)",
        "(x_q >> BLDC_X_FRAC_BITS)",
        "turn_on",
    ),
    (
        "swapped_turn_on_and_turn_off",
        "bldc_commutation.c",
        "timing.turn_on_compare = (uint16_t)on;\n    timing.turn_off_compare = (uint16_t)off;",
        "timing.turn_on_compare = (uint16_t)off;\n    timing.turn_off_compare = (uint16_t)on;",
        "turn_on",
    ),
    (
        "overflowing_intermediate",
        "bldc_commutation.c",
        "(bus->x_numerator + (period_ticks >> 1)) / period_ticks",
        "(bus->x_numerator * 4u + (period_ticks << 1)) / (period_ticks << 2)",
        "turn_on",
    ),
    (
        "wrong_hall_table_entry",
        "bldc_commutation.c",
        "1u, /* 101 -> 100: forward into sector 1 */",
        "2u, /* 101 -> 100: forward into sector 1 */",
        "pattern",
    ),
]


#: The same for the resistance-aware core (method improved_r), against the rule's
#: real-arithmetic reference and each point's own error bound.
RULE_MUTANTS = [
    (
        "flipped_sign_of_the_resistive_drop",
        "bldc_commutation.c",
        "st.s0 = 2 * PERIOD_Q + (int32_t)y - (int32_t)x;",
        "st.s0 = 2 * PERIOD_Q - (int32_t)y - (int32_t)x;",
        "turn_off",
    ),
    (
        "resistance_left_out_of_the_decay",
        "bldc_commutation.c",
        "#define K_RHO_Q 50332u",
        "#define K_RHO_Q 0u",
        "commutation_time",
    ),
    (
        "inductive_current_ten_percent_low",
        "bldc_commutation.c",
        "#define KAPPA_Q 615816u",
        "#define KAPPA_Q 554234u",
        "commutation_time",
    ),
    (
        "ramp_weight_doubled",
        "bldc_commutation.c",
        "#define THETA_HALF_Q 217167u",
        "#define THETA_HALF_Q 434334u",
        "turn_off",
    ),
]


@pytest.mark.parametrize(
    ("spec", "mutant", "file", "original", "replacement", "caught_by"),
    [("paper_motor", *m) for m in MUTANTS] + [("paper_motor_improved_r", *m) for m in RULE_MUTANTS],
    ids=[m[0] for m in MUTANTS] + [f"improved_r_{m[0]}" for m in RULE_MUTANTS],
)
def test_verify_should_catch_every_mutant(
    tmp_path: Path,
    spec: str,
    mutant: str,
    file: str,
    original: str,
    replacement: str,
    caught_by: str,
) -> None:
    generated = tmp_path / "generated"
    shutil.copytree(ROOT / "generated" / spec, generated)
    source = generated / "c" / file
    text = source.read_text(encoding="utf-8")
    assert text.count(original) == 1, f"{mutant}: the pattern no longer matches the template"
    source.write_text(text.replace(original, replacement), encoding="utf-8")
    result = _verify(spec, generated, tmp_path)
    assert not result.passed
    assert result.checks[caught_by].verdict == "FAIL", {
        k: c.failures for k, c in result.checks.items()
    }


def test_verify_should_refuse_a_missing_spec_or_core_clearly(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    from verify.__main__ import main

    assert main([str(tmp_path / "absent.yaml")]) == 2
    assert "cannot read spec" in capsys.readouterr().err
    assert main([str(SPECS["paper_motor"]), "--generated", str(tmp_path)]) == 2
    assert "no generated core" in capsys.readouterr().err

"""The bus-reciprocal table sizing that `make bench` sets against the hardware divide."""

from __future__ import annotations

from fractions import Fraction
from pathlib import Path

import sympy as sp

from codegen.core.module import build_core
from codegen.spec_loader import load_spec
from emulation.reciprocal_bench import FLASH_BUDGET_BYTES, _step, table_option

ROOT = Path(__file__).resolve().parents[2]


def _worst_interpolation_error(numerator: int, b_min: int, step: int) -> Fraction:
    """Largest |N/B - linear interpolation| over the first (steepest) interval."""
    left, right = Fraction(numerator, b_min), Fraction(numerator, b_min + step)
    return max(
        abs(Fraction(numerator, b_min + k) - (left + (right - left) * Fraction(k, step)))
        for k in range(step + 1)
    )


def test_interpolation_step_should_keep_the_error_within_its_budget() -> None:
    numerator, b_min = 123_456_789, 2000
    for budget in (Fraction(1, 2), Fraction(5), Fraction(300)):
        step = _step(numerator, b_min, sp.Rational(budget.numerator, budget.denominator))
        assert _worst_interpolation_error(numerator, b_min, step) <= budget
        # and it is not needlessly fine: twice the step breaks the budget
        assert _worst_interpolation_error(numerator, b_min, 2 * step + 2) > budget


def test_default_spec_table_should_not_fit_the_flash_budget() -> None:
    spec = load_spec(ROOT / "spec" / "paper_motor.yaml")
    option = table_option(spec, build_core(spec))
    assert option.step_g == 1  # t_com's bound already sits at its target: exact entries
    assert option.step_x > 1  # the duties leave room for interpolation
    assert option.flash_bytes > FLASH_BUDGET_BYTES

"""The commutation's latest end beyond the dead-time guard: the sector-shortening margin
(`hall.sector_shortening`, codegen/dead_time.py), the oracle's own reading of it
(oracle/units.py), the generated C and the loader's key."""

from __future__ import annotations

from fractions import Fraction
from pathlib import Path

import numpy as np
import pytest

from codegen.dead_time import SECTOR_MARGIN_SHIFT_MAX, latest_end_ticks, sector_margin_shift
from codegen.errors import SpecError
from codegen.generate import render_all
from codegen.spec_loader import load_spec
from oracle.units import _halvings, units

ROOT = Path(__file__).resolve().parents[1]
PAPER = ROOT / "spec" / "paper_motor.yaml"
HALL = "  counter_bits: 16\n"


def _with_shortening(tmp_path: Path, value: str) -> Path:
    text = PAPER.read_text(encoding="utf-8")
    assert text.count(HALL) == 1
    spec = tmp_path / "spec.yaml"
    spec.write_text(
        text.replace(HALL, f"{HALL}  sector_shortening: {value}\n").replace(
            "sources:\n", 'sources:\n  hall.sector_shortening: "assumption: a test"\n'
        ),
        encoding="utf-8",
    )
    return spec


@pytest.mark.parametrize(
    "percent", [Fraction(5), Fraction(1), Fraction(25), Fraction(1, 10**4), Fraction(625, 100)]
)
def test_the_margin_should_be_the_largest_power_of_two_fraction_not_below_the_shortening(
    percent: Fraction,
) -> None:
    shortening = percent / 100
    k = sector_margin_shift(shortening)
    assert k is not None and k == _halvings(shortening)  # the oracle's own reading agrees
    assert Fraction(1, 2**k) >= shortening
    assert k == SECTOR_MARGIN_SHIFT_MAX or Fraction(1, 2 ** (k + 1)) < shortening
    assert sector_margin_shift(Fraction(0)) is None and _halvings(Fraction(0)) is None


@pytest.mark.parametrize("k", [None, 2, 4, 7, 16])
def test_the_cores_latest_end_should_be_the_oracles_at_every_16_bit_period(k: int | None) -> None:
    """floor(T (2^k - 1) / 2^k) - G (the core's form, an interval proof keeps its range)
    against T - ceil(T / 2^k) - G (the oracle's), and the margin at least 2^-k T."""
    periods = np.arange(1, 2**16, dtype=np.int64)
    core = np.array([latest_end_ticks(int(t), 24, k) for t in periods[::97]])
    u = units(load_spec(str(PAPER)))
    oracle = type(u)(**{**u.__dict__, "end_guard_ticks": 24, "end_margin_shift": k})
    assert np.array_equal(core, oracle.latest_end(periods[::97]))
    if k is not None:
        assert np.all(periods - 24 - oracle.latest_end(periods) >= periods / 2**k)


def test_the_default_shortening_should_give_a_sixteenth_and_zero_none(tmp_path: Path) -> None:
    assert load_spec(str(PAPER)).hall.sector_shortening == Fraction(5, 100)
    spec = load_spec(str(_with_shortening(tmp_path, "0")))
    assert spec.hall.sector_shortening == 0
    default = render_all(PAPER).files
    none = render_all(_with_shortening(tmp_path, "0")).files
    key = next(k for k in default if str(k).endswith("c/bldc_commutation.c"))
    assert "period * 15u / 16u - BLDC_COMMUTATION_GUARD_TICKS;" in str(default[key])
    assert "latest = period - BLDC_COMMUTATION_GUARD_TICKS;" in str(none[key])


@pytest.mark.parametrize("value", ["30", "-1", "'5 %'", "true"])
def test_a_shortening_out_of_range_should_be_refused_in_one_line(
    tmp_path: Path, value: str
) -> None:
    with pytest.raises(SpecError) as caught:
        load_spec(str(_with_shortening(tmp_path, value)))
    lines = str(caught.value).splitlines()
    assert len(lines) == 1 and "hall.sector_shortening" in lines[0], lines
    assert "[0, 25] percent of the sector measured" in lines[0], lines

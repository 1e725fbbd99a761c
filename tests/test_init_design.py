"""`init`'s design check (codegen/init_design.py): what it writes when a refusal stands."""

from __future__ import annotations

from fractions import Fraction
from pathlib import Path

import pytest

from codegen import init_design
from codegen.methods.base import FixedPointError
from codegen.spec_init import Targets
from codegen.spec_loader import load_spec
from codegen.spec_model import Spec

ROOT = Path(__file__).resolve().parents[1]
CLOCK_REFUSAL = (
    "hall.timer_clock = 1e+06 Hz: Eq. 20's product leaves X too few bits (allowed: <= 12000 Hz,"
    " or a motor with a shorter L/R)"
)
DUTY_REFUSAL = "accuracy.duty_counts = 1 counts: beyond every format (allowed: another method)"


def _scripted(monkeypatch: pytest.MonkeyPatch, refusals: list[FixedPointError | None]) -> None:
    left = list(refusals)
    monkeypatch.setattr(init_design, "core_refusal", lambda spec: left.pop(0))


def test_a_slower_hall_clock_that_does_not_fit_should_not_be_written(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """The core refuses the Hall clock (it names <= 12 kHz); init lowers it to 10 kHz,
    and the design refuses again for another reason. The spec had stayed at 10 kHz, a
    tenfold rise of the slowest speed the timer measures, bought for nothing, with the
    second refusal. Now it is written back with the clock it had and reports the refusal
    `generate` gives that spec (the clock's), with a note naming what comes after it."""
    spec = load_spec(ROOT / "spec" / "paper_motor.yaml")
    written: list[Targets] = []

    def rewrite(targets: Targets) -> Spec:
        written.append(targets)
        return spec

    clock = FixedPointError(CLOCK_REFUSAL, "hall.timer_clock")
    duty = FixedPointError(DUTY_REFUSAL, "accuracy.duty_counts")
    _scripted(monkeypatch, [clock, duty])
    checked = init_design.meet_core_targets(spec, Targets(), rewrite)
    assert [t.hall_clock_hz for t in written] == [Fraction(10_000), None]
    assert checked.refusal is clock
    assert len(checked.notes) == 1
    assert checked.notes[0].startswith("at hall.timer_clock = 10000 Hz, what the refusal")
    assert DUTY_REFUSAL in checked.notes[0]


def test_a_slower_hall_clock_that_fits_should_be_kept_with_its_note(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    spec = load_spec(ROOT / "spec" / "paper_motor.yaml")
    written: list[Targets] = []

    def rewrite(targets: Targets) -> Spec:
        written.append(targets)
        return spec

    _scripted(monkeypatch, [FixedPointError(CLOCK_REFUSAL, "hall.timer_clock"), None])
    checked = init_design.meet_core_targets(spec, Targets(), rewrite)
    assert [t.hall_clock_hz for t in written] == [Fraction(10_000)]
    assert checked.refusal is None
    assert checked.notes[0].startswith("hall.timer_clock = 10000 Hz: what the improved")

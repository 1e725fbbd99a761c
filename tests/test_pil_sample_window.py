"""The clean-window rule of emulation/pil/sample_window.py on hand-made gate records:
a current sample is dirty when a gate edge lies inside its sampling window (as the
chip may take it, up to the injection latency later) or less than the settling time
before it; an output going from undriven to driven low is no edge."""

from __future__ import annotations

from fractions import Fraction

import pytest

from emulation.pil.sample_window import (
    REPORTED_WINDOWS,
    SampleWindow,
    gate_edges,
    sample_window_lines,
    window_violation,
)

OFF = (False,) * 6
SETTLING = Fraction(72)  # 1 us
#: sampled at 1045 after 45 ticks of sampling (7.5 cycles at 12 MHz), up to 19 later
WINDOW = SampleWindow(sampled=1045, start=Fraction(1000), latency=Fraction(19), channel=0)


def record(*edges: tuple[int, int, bool]) -> list[tuple[int, tuple[bool | None, ...]]]:
    """A gate record from (tick, gate, on) changes, all off at tick 0."""
    log: list[tuple[int, tuple[bool | None, ...]]] = [(0, OFF)]
    for tick, gate, on in edges:
        gates = list(log[-1][1])
        gates[gate] = on
        log.append((tick, tuple(gates)))
    return log


def violation(log: list[tuple[int, tuple[bool | None, ...]]]) -> str | None:
    edges = gate_edges(log)
    return window_violation(WINDOW, edges, [e.tick for e in edges], SETTLING)


def test_a_window_after_the_settling_time_and_before_the_next_edge_should_be_clean() -> None:
    # the turn-off 72 ticks before the window, the next turn-on at its latest end (after
    # the hold: clean)
    assert violation(record((500, 1, True), (928, 1, False), (1064, 1, True))) is None


@pytest.mark.parametrize(
    ("tick", "where", "margin"),
    [
        (929, "71 ticks before the window starts, under sensing.settling_time (72 ticks)", 1),
        (1020, "inside the window", 44),
        (1063, "inside the window as the chip may take it (up to 19 ticks later", 1),
    ],
)
def test_an_edge_too_close_before_or_inside_the_window_should_be_reported(
    tick: int, where: str, margin: int
) -> None:
    line = violation(record((tick, 3, True)))
    assert line is not None
    assert line.startswith("tick 1045: the current loop's sample of channel 0")
    assert f"phase B lower (CH2N) turning on at tick {tick}, {where}" in line
    assert f"margin -{margin} ticks" in line


def test_an_output_driven_low_from_undriven_should_be_no_edge() -> None:
    undriven = (None,) * 6
    log: list[tuple[int, tuple[bool | None, ...]]] = [(0, undriven), (1020, OFF)]
    assert gate_edges(log) == []
    assert violation(log) is None


def test_many_dirty_windows_should_be_reported_up_to_a_limit_and_counted() -> None:
    lines = [f"line {k}" for k in range(REPORTED_WINDOWS + 3)]
    out = sample_window_lines(lines)
    assert out[:-1] == lines[:REPORTED_WINDOWS]
    assert out[-1] == "... and 3 more dirty current samples"
    assert sample_window_lines(lines[:2]) == lines[:2]

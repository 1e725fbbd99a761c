"""`init`'s design check: a new spec gets through `generate`'s fixed-point designs.

`init` writes default accuracy targets (1 count for the duties and the PI, the Hall-tick
budget of its sector). A design that cannot meet one names what it does meet ("allowed:
>= V counts"); `init` then writes that target, says so in the spec's `sources` and in a
note, and checks again, so that "next: generate" is never followed by a refusal. Any
other refusal is the one line `generate` would print.
"""

from __future__ import annotations

import re
from collections.abc import Callable
from dataclasses import dataclass, replace
from fractions import Fraction

from codegen.errors import SpecError
from codegen.methods.base import FixedPointError
from codegen.spec_init import HALL_CLOCKS_HZ, Targets
from codegen.spec_model import Spec

#: how a design refusal names the target it meets (`paper_method`, `improved_r`)
_REACHABLE = re.compile(r"\(allowed: >= ([0-9]+(?:\.[0-9]+)?) (counts|ticks)\b")
#: the targets a commutation core's refusal may raise, by the key it names
CORE_TARGETS = {"accuracy.duty_counts": "counts", "accuracy.commutation_time_ticks": "ticks"}
#: Hall clocks below init's own choices (72 MHz / 7200, / 2880, / 1440), for a motor
#: whose Eq. 20 needs them (600 mH on 0.21 ohm: a 2.9 s time constant)
SLOW_HALL_CLOCKS_HZ = (10_000, 25_000, 50_000)
#: how a core's refusal of the Hall clock bounds the clocks that design (`paper_method`)
_HALL_CLOCK = re.compile(r"\(allowed: <= ([0-9.e+]+) Hz, ")


@dataclass(frozen=True)
class Adopted:
    """A target raised to what a design meets."""

    targets: Targets
    note: str


def reachable(error: FixedPointError) -> Fraction | None:
    """The target a core refusal of one of `CORE_TARGETS` says its design meets."""
    unit = CORE_TARGETS.get(error.key)
    found = _REACHABLE.search(str(error))
    if unit is None or found is None or found.group(2) != unit:
        return None
    return Fraction(found.group(1))


def _amount(value: Fraction, unit: str) -> str:
    return f"{float(value):g} {unit}{'' if value == 1 else 's'}"


def _adopt_hall_clock(targets: Targets, spec: Spec, error: FixedPointError) -> Adopted | None:
    """`targets` with the fastest of init's Hall clocks (72 MHz / N, each a whole number
    of Hz) within the bound the core's refusal names, where it is slower than the spec's;
    None otherwise."""
    found = _HALL_CLOCK.search(str(error))
    if found is None:
        return None
    bound = Fraction(found.group(1))
    fitting = [Fraction(c) for c in (*SLOW_HALL_CLOCKS_HZ, *HALL_CLOCKS_HZ) if c <= bound]
    if not fitting or fitting[-1] >= spec.hall.timer_clock_hz:
        return None
    clock = fitting[-1]
    return Adopted(
        replace(targets, hall_clock_hz=clock),
        f"hall.timer_clock = {float(clock):g} Hz: what the {spec.controller.method}"
        f" commutation core's integer design takes on this motor"
        f" ({float(spec.hall.timer_clock_hz):g} Hz leaves Eq. 20 too few bits; the slowest"
        " speed the Hall timer measures rises with it)",
    )


def adopt_core_target(targets: Targets, spec: Spec, error: FixedPointError) -> Adopted | None:
    """`targets` with the one the core's refusal names raised to what it meets (or the
    Hall clock lowered to one it takes); None when the refusal names no such target, or
    one no looser than the spec's (no progress)."""
    if error.key == "hall.timer_clock":
        return _adopt_hall_clock(targets, spec, error)
    value = reachable(error)
    if value is None:
        return None
    method = spec.controller.method
    if error.key == "accuracy.duty_counts":
        if value <= spec.accuracy.duty_counts:
            return None
        old = _amount(spec.accuracy.duty_counts, "count")
        raised = replace(targets, duty_counts=value)
        unit = "counts"
    else:
        if value <= spec.accuracy.commutation_time_ticks:
            return None
        old = _amount(spec.accuracy.commutation_time_ticks, "tick")
        raised = replace(targets, time_ticks=value)
        unit = "ticks"
    return Adopted(
        raised,
        f"{error.key} = {float(value):g} {unit}: what the {method} commutation core's"
        f" integer design meets on this motor ({old} is out of its reach; another"
        " --method may meet more)",
    )


def core_refusal(spec: Spec) -> FixedPointError | None:
    """The refusal `generate`'s commutation-core design gives this spec, or None."""
    from codegen.core.module import build_core  # the design imports the IR and its prover

    try:
        build_core(spec)
    except FixedPointError as exc:
        return exc
    return None


@dataclass(frozen=True)
class CoreCheck:
    """Where `meet_core_targets` left the spec."""

    spec: Spec
    notes: tuple[str, ...]
    refusal: FixedPointError | None  # what `generate` would still refuse, if anything


def meet_core_targets(
    spec: Spec, targets: Targets, rewrite: Callable[[Targets], Spec]
) -> CoreCheck:
    """Run the core's design on `spec` (written with `targets`), raising each target it
    names to what it meets through `rewrite` (write the spec with these targets, load
    it), until it designs or refuses for another reason."""
    notes: list[str] = []
    #: the targets, notes and refusal before init first lowered the Hall clock
    before_clock: tuple[Targets, int, FixedPointError] | None = None
    for _ in range(len(CORE_TARGETS) + 2):  # each target, the Hall clock, the last check
        refusal = core_refusal(spec)
        if refusal is None:
            break
        adopted = adopt_core_target(targets, spec, refusal)
        if adopted is None:
            break
        try:
            spec = rewrite(adopted.targets)
        except SpecError:
            # what the design meets is beyond what a spec may ask (46.68 counts of duty
            # error): the spec keeps the target, and the refusal stands
            spec = rewrite(targets)
            break
        if before_clock is None and adopted.targets.hall_clock_hz != targets.hall_clock_hz:
            before_clock = (targets, len(notes), refusal)
        targets = adopted.targets
        notes.append(adopted.note)
    if refusal is not None and before_clock is not None:
        # a slower Hall clock did not make the design fit: the spec keeps the clock it
        # had (a 10 kHz clock raises the slowest speed the timer measures tenfold, for
        # nothing) and the refusal `generate` gives it; a note says what comes next
        kept, count, first = before_clock
        tried = targets.hall_clock_hz
        spec = rewrite(kept)
        notes = notes[:count]
        notes.append(
            f"at hall.timer_clock = {float(tried or 0):g} Hz, what the refusal below"
            f" asks, the design still refuses: {refusal}"
        )
        refusal = first
    return CoreCheck(spec, tuple(notes), refusal)

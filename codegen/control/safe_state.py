"""The safe state by speed region: all-off or the active short circuit, from the physics.

All switches off: the bridge's diodes form a three-phase rectifier. While the peak
line-to-line EMF lambda k_e n stays below the bus voltage U_d the diodes block: the
inductive current returns to the bus within a few L/R and then no current flows. Above
U_d / (lambda k_e) they conduct: the machine brakes uncontrolled into the bus and pumps
it, the very hazard of an over-voltage fault. All-off is no safe state there.

Active short circuit (every lower switch on, every upper off): the terminals are
shorted together, so nothing flows into the bus at any speed; the phase current is the
short-circuit current, bounded by `spec_drive.short_circuit_peak` (each EMF harmonic
over its impedance, doubled for the entry transient, plus the current at entry). It is
a safe state wherever that bound is within the bridge's rating
(`protection.short_circuit_current_max`).

Regions, at the bus voltage U_d measured now:

    n >= U_d / (lambda k_e)                    short circuit (all-off rectifies)
    n <  U_d / (lambda k_e), short within rating   both valid: `protection.safe_state`
    n <  U_d / (lambda k_e), short over rating     all-off

Both boundaries are those of the worst motor the spec declares
(`spec_drive.safe_state_corner`): k_e at its upper tolerance (all-off rectifies soonest),
R and L at their lower ones (the short's current is largest), and a rotor up to
`hall.sector_shortening` faster than its last Hall interval says (the factor
c = 1 / (1 - s)). The nominal boundary had let the port choose all-off 1.2 % below it
while the paper motor with its k_e 10 % high, inside its own tolerances, rectified into
the bus (a hunt). The loader has already checked that the short is within the rating
wherever all-off can rectify in the speed range, at the same corner. In the port both
conditions are one integer comparison each on the last Hall interval T (ticks) and bus
code B:

    rectifying  <=>  T B <= K_RECT = floor(10 f_hall lambda k_e_max c / (p V_code))
    short valid <=>  T >= T_SHORT (c x the interval of the speed where the worst
                                   corner's bound meets the rating)

A bus code that reads low (a collapsed bus, or its ADC stuck at 0) makes T B small:
the short circuit where the spec prefers all-off; where it prefers the short, the port
takes it wherever it is rated and all-off elsewhere, whatever the bus reads (the loader
keeps the short rated wherever all-off rectifies in the ranges). A Hall interval that
fills the counter (the speed unknown before the first edges, or below the range) takes
the short where it is rated at every speed up to speed_max (`short_while_unknown`),
else all-off.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from fractions import Fraction
from functools import lru_cache

from codegen.spec_drive import (
    corner_short_peak,
    line_to_line_peak,
    rectifying_speed,
    safe_state_corner,
)
from codegen.spec_model import Spec

#: Bisection steps for the speed where the short-circuit bound meets the rating.
BISECTION_STEPS = 60


@dataclass(frozen=True)
class SafeStateDesign:
    policy: str  # where both are valid: all_off or short_circuit
    line_to_line_peak: Fraction  # lambda
    k_rect: int  # T B <= k_rect: rectifying
    short_valid_period: int  # T >= it: the short is within the rating (0: always)
    short_valid_speed_rpm: float | None  # None: within the rating at every speed
    regions: tuple[str, ...]  # one line per bus voltage of the spec, for the header
    #: The state for a Hall interval that fills the counter (it wrapped): the speed is
    #: unknown (before the first edge, and at the first edge after the bridge is armed,
    #: which reads TIM3's preset wrap) or below the counter's range. The short circuit
    #: where it is within the rating at every speed up to speed_max (then valid whatever
    #: the rotor does: all-off is not where it rectifies); else all-off (the loader then
    #: keeps speed_max below the speed from which all-off rectifies at bus_voltage_min).
    short_while_unknown: bool = False


def _speed_of_period(spec: Spec, ticks: Fraction) -> Fraction:
    return 10 * spec.hall.timer_clock_hz / (spec.motor.pole_pairs * ticks)


def _peak(spec: Spec, rpm: float) -> float:
    corner = safe_state_corner(spec.motor, spec.hall, spec.tolerances)
    return corner_short_peak(spec.motor, corner, spec.protection.over_current_a, rpm)


def short_valid_speed(spec: Spec) -> float | None:
    """The highest speed at which the short-circuit bound of the worst corner is within
    the rating (rpm), or None when it is at every speed up to 100 x speed_max."""
    rating = float(spec.protection.short_circuit_current_max_a)
    high = 100 * float(spec.controller.speed_max_rpm)
    if _peak(spec, high) <= rating:
        return None
    low = 0.0
    if _peak(spec, low) > rating:
        return 0.0
    for _ in range(BISECTION_STEPS):
        mid = (low + high) / 2
        if _peak(spec, mid) <= rating:
            low = mid
        else:
            high = mid
    return low


@lru_cache(maxsize=16)
def safe_state_design(spec: Spec) -> SafeStateDesign:
    m, inv = spec.motor, spec.inverter
    corner = safe_state_corner(m, spec.hall, spec.tolerances)
    lam = line_to_line_peak(m.back_emf_shape)
    volts_per_code = spec.adc.reference_v * spec.adc.bus_voltage_divider / 2**spec.adc.bits
    k = (
        10
        * spec.hall.timer_clock_hz
        * lam
        * corner.k_e
        * corner.speed_factor
        / (m.pole_pairs * volts_per_code)
    )
    k_rect = k.numerator // k.denominator
    n_short = short_valid_speed(spec)
    if n_short is None:
        period = 0
    elif n_short == 0.0:
        period = 1 << 32  # never
    else:
        # T >= this <=> the rotor, up to c faster than T says, is at most n_short
        # (rounded up: the short is never used above it)
        period = math.ceil(
            float(10 * spec.hall.timer_clock_hz * corner.speed_factor / m.pole_pairs) / n_short
        )
    regions = []
    for label, volts in (
        ("bus_voltage_min", inv.bus_voltage_min_v),
        ("bus_voltage_nominal", inv.bus_voltage_nominal_v),
        ("bus_voltage_max", inv.bus_voltage_max_v),
    ):
        # the speed the last interval says from which all-off may rectify
        n_rect = float(rectifying_speed(volts, corner.k_e * corner.speed_factor, m.back_emf_shape))
        said_short = None if n_short is None else n_short / float(corner.speed_factor)
        both = (
            f"below {n_rect:.0f} rpm both are valid: {spec.protection.safe_state.replace('_', ' ')}"
            if said_short is None or said_short >= n_rect
            else f"below {said_short:.0f} rpm both are valid: {spec.protection.safe_state.replace('_', ' ')};"
            f" {said_short:.0f}..{n_rect:.0f} rpm all-off (the short may exceed the rating)"
        )
        regions.append(
            f"{label} {float(volts):g} V: from {n_rect:.0f} rpm (the speed the last Hall"
            f" interval says) short circuit (all-off may rectify); {both}"
        )
    return SafeStateDesign(
        policy=spec.protection.safe_state,
        line_to_line_peak=lam,
        k_rect=k_rect,
        short_valid_period=period,
        short_valid_speed_rpm=n_short,
        regions=tuple(regions),
        short_while_unknown=n_short is None or n_short >= float(spec.controller.speed_max_rpm),
    )

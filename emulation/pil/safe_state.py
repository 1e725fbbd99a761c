"""The safe state a fault must leave, from the physics at the run's speed and bus: the
PIL's own yardstick, from the spec and sim's EMF waveform, never the generator's.

* All switches off: the six diodes rectify into the bus once the peak line-to-line EMF
  reaches it (`peak_line_emf_v`): no safe state there.
* The active short circuit (the three lower switches on): nothing flows into the bus,
  but the phases carry the short-circuit current. The spec's requirement
  (protection.short_circuit_current_max) is on its bound: each harmonic of the phase
  EMF (every one but the multiples of 3, which drive no current with the star point
  open) over its impedance |R + j h w L|, their moduli summed (the steady peak), twice
  that for the entry transient, plus the current at entry (the over-current trip). The
  harmonics here are the FFT of sim's waveform (`short_circuit_bound_a`), not the
  generator's series.

Where all-off rectifies the short is required; elsewhere all-off where the spec prefers
it, and where it prefers the short, the short within its rating and all-off above it
(within RATING_BAND of the rating either is accepted: the port decides on a Hall
interval of whole ticks).

Both for the worst motor the spec declares (`Corner`): k_e at its upper tolerance
(`tolerances.back_emf_constant`), R and L at their lower ones; the drive cannot tell
which motor it has. And the port reads the speed from the last Hall interval, which a
rotor may outrun by `hall.sector_shortening` (a sector up to s shorter): where the worst
motor at up to 1/(1 - s) times the rotor's speed would rectify, or exceed the short's
rating, while at the rotor's own speed it does not, either state is accepted. A hunt
ran the paper motor's firmware on a plant with k_e 10 % high, inside its tolerances: the
port, deciding on the nominal motor, chose all-off 1.2 % below the nominal boundary,
and the plant rectified 2.8 A into the bus.
"""

from __future__ import annotations

import bisect
import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from codegen.spec_model import Spec
from sim.emf import Waveform

#: The gates of each safe state, (CH1, CH1N, CH2, CH2N, CH3, CH3N), upper switches on CHx
ALL_OFF, SHORT_CIRCUIT = (False,) * 6, (False, True) * 3
#: Samples of one electrical period for the EMF's harmonics (harmonics up to half of it)
FFT_SAMPLES = 36_000
#: Either side of the rating, either safe state is accepted: the port reads the speed as
#: a Hall interval of whole ticks (well under 0.1 % at every speed of a valid spec)
RATING_BAND = 0.005
#: The rated speed is found to 1/RPM_STEPS rpm
RPM_STEPS = 1000
#: The bound is searched up to this multiple of controller.speed_max
SEARCH_SPAN = 100


@dataclass(frozen=True)
class Corner:
    """The worst motor of the spec's declared ranges, as factors of the nominal one, and
    how much faster than its last Hall interval says the rotor may run."""

    k_e: float  # 1 + the upper k_e tolerance: the EMF is largest
    resistance: float  # 1 + the lower R tolerance: the short's current is largest
    inductance: float  # 1 + the lower L tolerance
    said: float  # 1 / (1 - hall.sector_shortening)


def corner(spec: Spec) -> Corner:
    """The spec's worst corner (`Corner`); the nominal motor where it declares no
    tolerances."""
    tol = spec.tolerances
    k_e = 1.0 + max(0.0, float(tol.back_emf_constant[1])) if tol else 1.0
    r = 1.0 + min(0.0, float(tol.phase_resistance[0])) if tol else 1.0
    inductance = 1.0 + min(0.0, float(tol.phase_inductance[0])) if tol else 1.0
    return Corner(k_e, r, inductance, 1.0 / (1.0 - float(spec.hall.sector_shortening)))


def _wave(spec: Spec) -> Waveform:
    return Waveform(tuple((float(a), float(v)) for a, v in spec.motor.back_emf_shape.points))


def peak_line_emf_v(spec: Spec, rpm: float) -> float:
    """The peak line-to-line EMF at `rpm` from the spec's phase EMF (sim's waveform of
    motor.back_emf_shape, E = k_e n at its flat top): e_a - e_b at its largest."""
    wave = _wave(spec)
    angles = np.linspace(0.0, 360.0, 3601)
    line = np.abs(wave.many(angles) - wave.many(angles - 120.0)).max()
    return float(spec.motor.back_emf_constant_v_per_rpm) * rpm * float(line)


def worst_line_emf_v(spec: Spec, rpm: float) -> float:
    """The peak line EMF of the worst motor (`Corner.k_e`) at `rpm`: all-off may rectify
    where it reaches the bus."""
    return peak_line_emf_v(spec, rpm) * corner(spec).k_e


def said_line_emf_v(spec: Spec, rpm: float) -> float:
    """The worst motor's peak line EMF at the fastest speed a rotor at `rpm` may be
    taken to run at from its last Hall interval (`Corner.said` x `rpm`): where it
    reaches the bus the port may choose the short."""
    return worst_line_emf_v(spec, rpm * corner(spec).said)


@lru_cache(maxsize=32)
def _harmonics(points: tuple[tuple[float, float], ...]) -> tuple[np.ndarray, np.ndarray]:
    """(orders, amplitudes per unit E) of the phase EMF's harmonics that drive current
    in a star winding: every order >= 1 but the multiples of 3."""
    wave = Waveform(points)
    samples = wave.many(np.arange(FFT_SAMPLES) * 360.0 / FFT_SAMPLES)
    amplitudes = 2.0 * np.abs(np.fft.rfft(samples)) / FFT_SAMPLES
    orders = np.arange(amplitudes.size)
    keep = (orders >= 1) & (orders % 3 != 0) & (orders < FFT_SAMPLES // 2)
    return orders[keep], amplitudes[keep]


def short_circuit_bound_a(spec: Spec, rpm: float, *, worst: bool = False) -> float:
    """The spec's bound on the short circuit's peak phase current at `rpm` (A): of the
    nominal motor, or of the worst one the spec declares (`worst`, `Corner`)."""
    motor = spec.motor
    c = corner(spec) if worst else Corner(1.0, 1.0, 1.0, 1.0)
    orders, amplitudes = _harmonics(_wave(spec).points)
    e = float(motor.back_emf_constant_v_per_rpm) * c.k_e * rpm
    omega = 2.0 * math.pi * motor.pole_pairs * rpm / 60.0
    impedance = np.hypot(
        float(motor.phase_resistance_ohm) * c.resistance,
        orders * omega * float(motor.phase_inductance_h) * c.inductance,
    )
    steady = float((amplitudes * e / impedance).sum())
    return 2.0 * steady + float(spec.protection.over_current_a)


def short_rated_speed(spec: Spec) -> float | None:
    """The speed (rpm, to 1/RPM_STEPS) up to which the worst motor's short-circuit bound
    is within protection.short_circuit_current_max; None when it is at every speed up to
    SEARCH_SPAN x controller.speed_max, 0.0 when at none. The bound grows with the
    speed: the standard library's bisection over a grid of speeds finds the last."""
    rating = float(spec.protection.short_circuit_current_max_a)
    grid = range(round(SEARCH_SPAN * float(spec.controller.speed_max_rpm) * RPM_STEPS) + 1)

    def bound(step: int) -> float:
        return short_circuit_bound_a(spec, step / RPM_STEPS, worst=True)

    if bound(grid[-1]) <= rating:
        return None
    within = bisect.bisect_right(grid, rating, key=bound)
    return (within - 1) / RPM_STEPS if within else 0.0


def required_idle_state(spec: Spec, rpm: float, bus_v: float) -> tuple[bool, ...] | None:
    """The state a drive without a fault must hold with no sector's switch on (a refused
    Hall edge, or armed before its first edge): the short circuit where all-off may
    rectify (the worst motor's line EMF reaches the bus) and the short is within its
    rating (None within RATING_BAND of it, or where neither is safe); else all-off,
    except where the port, reading the speed up to `Corner.said` high, may take the
    short (either). Not the spec's preference, as a fault's state is: the short brakes
    the rotor with its short-circuit current, which may trip the comparator, and a
    refusal is no fault."""
    bound = short_circuit_bound_a(spec, rpm, worst=True)
    rating = float(spec.protection.short_circuit_current_max_a)
    if worst_line_emf_v(spec, rpm) < bus_v:
        if said_line_emf_v(spec, rpm) >= bus_v and bound <= rating * (1 + RATING_BAND):
            return None
        return ALL_OFF
    if bound > rating * (1 + RATING_BAND):
        return None
    return SHORT_CIRCUIT if bound <= rating * (1 - RATING_BAND) else None


def required_safe_state(
    spec: Spec, rpm: float, bus_v: float, *, inputs_known: bool = True
) -> tuple[bool, ...] | None:
    """The safe state the spec requires at `rpm` and the bus `bus_v`, for the worst
    motor it declares (`Corner`): the short circuit where all-off may rectify (the six
    diodes conduct into the bus); else all-off where protection.safe_state prefers it;
    else the short within its rating, all-off above it; None within RATING_BAND of the
    rating (either is accepted), where no state is safe (all-off rectifies and the short
    exceeds its rating: a bus below the spec's range), and where the port, reading the
    speed up to `Corner.said` above the rotor's, may take the other side of a boundary.
    That includes all-off rectifying at the faster speed and not at the rotor's while the
    short exceeds its rating at the rotor's: no state is safe at every speed the reading
    allows (a hunt: a 1-pole-pair 95 000 rpm init motor at 1.25 x its top speed, on its
    nominal bus, held the short, 247 A on 240 A, where all-off rectifies from 1.05 x
    that speed; the check had required all-off).
    Where the port cannot know the speed or the bus (`inputs_known` False: no Hall
    interval yet, or the bus ADC stuck), only the physics: the preference decides
    nothing, so either state that is safe at `rpm` and `bus_v` is."""
    rating = float(spec.protection.short_circuit_current_max_a)
    bound = short_circuit_bound_a(spec, rpm, worst=True)
    over = bound > rating * (1 + RATING_BAND)
    if worst_line_emf_v(spec, rpm) >= bus_v:
        return None if over else SHORT_CIRCUIT
    if said_line_emf_v(spec, rpm) >= bus_v and inputs_known:
        # the port may read the rotor as where all-off rectifies: the short (rated), or,
        # the short beyond its rating at the rotor's speed, no state safe at every speed
        # the rotor may have at the interval it reads (the short over its rating at the
        # slowest, all-off rectifying at the fastest): either
        return None
    if inputs_known and spec.protection.safe_state == "all_off":
        return ALL_OFF
    if over:
        return ALL_OFF
    if not inputs_known:
        return None
    said = short_circuit_bound_a(spec, rpm * corner(spec).said, worst=True)
    if said <= rating * (1 - RATING_BAND):
        return SHORT_CIRCUIT
    return None  # rated at the rotor's speed, maybe not at the one the port reads

"""Switched plant: every PWM edge and every diode event, integrated exactly.

Between breakpoints (gate edges, carrier-period boundaries, EMF corners) the gates are
constant; the conducting set then only changes at events, which are found exactly:

* a current through a diode reaches zero (`closed_form.first_zero`): the diode blocks
  and the phase floats, its terminal voltage following from the other two;
* a floating phase's terminal voltage u_n + e_x (affine in time) reaches the voltage
  of a conducting path (a transistor that is on, or a rail through a diode).

Each piece in between is the closed-form solution of di/dt = c0 + c1 t - (R/L) i.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from itertools import pairwise

import numpy as np

from sim import closed_form
from sim.circuit import (
    LegVoltages,
    balanced_floats,
    floating_voltage_of,
    forcing_of,
    resolve_floats,
    threshold_crossing,
)
from sim.drive import Drive
from sim.emf import BackEmf
from sim.schedule import Schedule
from sim.trace import Event, Trace, TraceBuilder, Transition, events_at

#: Gauss-Legendre nodes and weights on [0, 1], exact for the period averages up to
#: terms of order (a h)^6 with h at most one PWM period.
_GL_NODES = (0.5 - math.sqrt(0.15), 0.5, 0.5 + math.sqrt(0.15))
_GL_WEIGHTS = (5.0 / 18.0, 8.0 / 18.0, 5.0 / 18.0)
_MAX_EVENTS_PER_PIECE = 64


def simulate_switched(
    drive: Drive,
    emf: BackEmf,
    schedule: Schedule,
    start: float,
    end: float,
    initial_currents: np.ndarray,
) -> Trace:
    return _simulate(drive, emf, schedule, start, end, initial_currents, averaged=False)


def simulate_averaged_exact(
    drive: Drive,
    emf: BackEmf,
    schedule: Schedule,
    start: float,
    end: float,
    initial_currents: np.ndarray,
) -> Trace:
    """The averaged plant (each leg at its PWM-period average D U_d, the paper's model)
    solved by the same exact pieces: between breakpoints the averaged voltages are
    constant too, so the closed form applies unchanged. `sim.averaged` integrates the
    same model with CVODES; the tests hold the two together."""
    return _simulate(drive, emf, schedule, start, end, initial_currents, averaged=True)


def _simulate(
    drive: Drive,
    emf: BackEmf,
    schedule: Schedule,
    start: float,
    end: float,
    initial_currents: np.ndarray,
    averaged: bool,
) -> Trace:
    builder = TraceBuilder("averaged" if averaged else "switched", schedule)
    currents = np.array(initial_currents, dtype=float)
    builder.point(start, currents)
    times = sorted(
        set(schedule.breakpoints(start, end, gate_edges=not averaged))
        | set(emf.corners(start, end))
    )
    previous_gates: tuple[float, ...] | None = None
    for lo, hi in pairwise(times):
        if hi - lo <= 1e-15:
            continue
        middle = 0.5 * (lo + hi)
        gates = schedule.duties_at(middle) if averaged else schedule.gates_at(middle)
        if previous_gates is not None and not averaged:
            for switch, (was, now) in enumerate(zip(previous_gates, gates, strict=True)):
                if was != now:
                    builder.transitions.append(Transition(lo, switch, now > 0.5))
        previous_gates = gates
        legs = LegVoltages.from_duties(gates, drive.bus_voltage_v)
        currents = run_piece(drive, emf, schedule, legs, lo, hi, currents, builder)
    return builder.finish()


def run_piece(
    drive: Drive,
    emf: BackEmf,
    schedule: Schedule,
    legs: LegVoltages,
    lo: float,
    hi: float,
    currents: np.ndarray,
    builder: TraceBuilder,
) -> np.ndarray:
    """The currents at `hi` from `currents` at `lo`, the gates (`legs`) constant and the
    EMFs affine in between (no corner of `emf.affine` inside): every diode event found
    exactly, each stretch recorded in `builder` (points, events, the carrier period's
    charge and energy from `schedule.period_index`). The emulated drive's plant
    (emulation/pil/plant.py) advances its motor with this same function.

    Within the piece the three-element vectors are Python floats (numpy's per-call
    overhead on them was most of the plant's time), each element computed as numpy
    computed it; `builder` gets each point as an array and each charge as a tuple."""
    emf0, emf1 = emf.affine(lo, hi)
    period = schedule.period_index(0.5 * (lo + hi))
    e0, e1 = emf0.tolist(), emf1.tolist()
    legs_at = _LegFloats(*legs.floats)
    inductance, decay = drive.inductance_h, drive.decay_rate
    i = currents.tolist()
    t = lo
    for _ in range(_MAX_EVENTS_PER_PIECE):
        if t >= hi:
            break
        emf_now = [e0[0] + e1[0] * t, e0[1] + e1[1] * t, e0[2] + e1[2] * t]
        conducting, voltages = resolve_floats(legs_at.positive, legs_at.negative, i, emf_now)
        c0, c1 = forcing_of(conducting, voltages, e0, e1, inductance)
        local_c0 = [c0[0] + c1[0] * t, c0[1] + c1[1] * t, c0[2] + c1[2] * t]
        step, event = _next_event(
            decay, conducting, voltages, legs_at, e0, e1, i, local_c0, c1, t, hi - t
        )
        new = list(closed_form.currents(i, local_c0, c1, decay, step))
        charge, energy = _quadrature(decay, i, local_c0, c1, e0, e1, t, step)
        builder.accumulate(period, step, charge, energy)
        t += step
        if event is not None and event.kind == "zero":
            new[event.phase] = 0.0
        carried = i
        i = balanced_floats(new)
        if event is not None:
            builder.events += events_at(t, event, carried, i)
        currents = np.array(i)
        builder.point(t, currents)
    return currents


@dataclass(frozen=True)
class _LegFloats:
    """`LegVoltages` of one piece as Python floats, and which legs are reversible."""

    positive: list[float]
    negative: list[float]
    reversible: list[bool]


def _next_event(
    decay_rate: float,
    conducting: list[bool],
    voltages: list[float],
    legs: _LegFloats,
    emf0: list[float],
    emf1: list[float],
    currents: list[float],
    c0: list[float],
    c1: list[float],
    t: float,
    horizon: float,
) -> tuple[float, Event | None]:
    best, event = horizon, None
    count = sum(conducting)
    for phase in range(3):
        if conducting[phase]:
            if not legs.reversible[phase]:
                continue
            zero = closed_form.first_zero(
                currents[phase], c0[phase], c1[phase], decay_rate, horizon
            )
            if zero is not None and zero < best:
                best, event = zero, Event(0.0, "zero", phase)
        elif count >= 2:
            v0, v1 = floating_voltage_of(conducting, voltages, emf0, emf1, phase)
            now = v0 + v1 * t
            for threshold, falling in ((legs.positive[phase], True), (legs.negative[phase], False)):
                crossing = threshold_crossing(now, v1, threshold, falling)
                if crossing is not None and crossing < best:
                    best, event = crossing, Event(0.0, "conducts", phase)
    return best, event


def _quadrature(
    decay_rate: float,
    i0: list[float],
    k0: list[float],
    k1: list[float],
    emf0: list[float],
    emf1: list[float],
    t: float,
    step: float,
) -> tuple[tuple[float, float, float], float]:
    """int i dt and int sum e_x i_x dt over [t, t + step]."""
    (ea, eb, ec), (sa, sb, sc) = emf0, emf1
    qa = qb = qc = 0.0
    energy = 0.0
    for node, weight in zip(_GL_NODES, _GL_WEIGHTS, strict=True):
        tau = node * step
        ia, ib, ic = closed_form.currents(i0, k0, k1, decay_rate, tau)
        now = t + tau
        scale = weight * step
        qa += scale * ia
        qb += scale * ib
        qc += scale * ic
        energy += scale * ((ea + sa * now) * ia + (eb + sb * now) * ib + (ec + sc * now) * ic)
    return (qa, qb, qc), energy

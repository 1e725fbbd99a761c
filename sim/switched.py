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
from itertools import pairwise

import numpy as np

from sim import closed_form
from sim.circuit import LegVoltages, Topology, balanced, resolve, threshold_crossing
from sim.drive import Drive
from sim.emf import BackEmf
from sim.schedule import Schedule
from sim.trace import Event, Trace, TraceBuilder, Transition

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
    (emulation/pil/plant.py) advances its motor with this same function."""
    emf0, emf1 = emf.affine(lo, hi)
    period = schedule.period_index(0.5 * (lo + hi))
    reversible = legs.reversible()
    t = lo
    for _ in range(_MAX_EVENTS_PER_PIECE):
        if t >= hi:
            break
        topology = resolve(legs, currents, emf0 + emf1 * t)
        c0, c1 = topology.forcing(emf0, emf1, drive.inductance_h)
        local_c0 = c0 + c1 * t
        step, event = _next_event(
            drive, topology, legs, reversible, emf0, emf1, currents, local_c0, c1, t, hi - t
        )
        new = np.array(
            closed_form.currents(
                currents.tolist(), local_c0.tolist(), c1.tolist(), drive.decay_rate, step
            )
        )
        charge, energy = _quadrature(drive, currents, local_c0, c1, emf0, emf1, t, step)
        builder.accumulate(period, step, charge, energy)
        t += step
        if event is not None:
            if event.kind == "zero":
                new[event.phase] = 0.0
            builder.events.append(Event(t, event.kind, event.phase))
        new = balanced(new)
        currents = new
        builder.point(t, currents)
    return currents


def _next_event(
    drive: Drive,
    topology: Topology,
    legs: LegVoltages,
    reversible: np.ndarray,
    emf0: np.ndarray,
    emf1: np.ndarray,
    currents: np.ndarray,
    c0: np.ndarray,
    c1: np.ndarray,
    t: float,
    horizon: float,
) -> tuple[float, Event | None]:
    best, event = horizon, None
    for phase in range(3):
        if topology.conducting[phase]:
            if not reversible[phase]:
                continue
            zero = closed_form.first_zero(
                currents[phase], c0[phase], c1[phase], drive.decay_rate, horizon
            )
            if zero is not None and zero < best:
                best, event = zero, Event(0.0, "zero", phase)
        elif topology.count >= 2:
            v0, v1 = topology.floating_voltage(emf0, emf1, phase)
            now = v0 + v1 * t
            for threshold, falling in ((legs.positive[phase], True), (legs.negative[phase], False)):
                crossing = threshold_crossing(now, v1, threshold, falling)
                if crossing is not None and crossing < best:
                    best, event = crossing, Event(0.0, "conducts", phase)
    return best, event


def _quadrature(
    drive: Drive,
    currents: np.ndarray,
    c0: np.ndarray,
    c1: np.ndarray,
    emf0: np.ndarray,
    emf1: np.ndarray,
    t: float,
    step: float,
) -> tuple[np.ndarray, float]:
    """int i dt and int sum e_x i_x dt over [t, t + step] (on Python floats: numpy's
    per-call overhead on three-element vectors was most of the plant's time)."""
    i0, k0, k1 = currents.tolist(), c0.tolist(), c1.tolist()
    (ea, eb, ec), (sa, sb, sc) = emf0.tolist(), emf1.tolist()
    qa = qb = qc = 0.0
    energy = 0.0
    for node, weight in zip(_GL_NODES, _GL_WEIGHTS, strict=True):
        tau = node * step
        ia, ib, ic = closed_form.currents(i0, k0, k1, drive.decay_rate, tau)
        now = t + tau
        scale = weight * step
        qa += scale * ia
        qb += scale * ib
        qc += scale * ic
        energy += scale * ((ea + sa * now) * ia + (eb + sb * now) * ib + (ec + sc * now) * ic)
    return np.array((qa, qb, qc)), energy

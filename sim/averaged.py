"""Averaged plant: Eq. 1 over PWM-averaged terminal voltages, integrated with CVODES.

Each leg's voltage is its period average (the paper's D U_d, `sim.circuit`), so the
ripple disappears and the states are the three phase currents plus the integrals the
metrics need (int i dt, int sum e_x i_x dt). One casadi integrator, built once, serves
every piece: the conducting mask, terminal voltages, EMF coefficients and the piece
length are parameters, and time is scaled to s in [0, 1] so the length can vary.

The diode logic is the same as the switched plant's with fractional duties (a leg
starts to conduct when its floating voltage passes the averaged path voltage). A
current that reaches zero is located by the secant method on the piece length, which
converges in a few integrator calls because the averaged currents are smooth.
"""

from __future__ import annotations

from functools import lru_cache
from itertools import pairwise

import casadi as ca
import numpy as np

from codegen.interrupts import interrupts_noted
from sim.circuit import LegVoltages, Topology, balanced, resolve, threshold_crossing
from sim.drive import Drive
from sim.emf import BackEmf
from sim.schedule import Schedule
from sim.trace import Event, Trace, TraceBuilder, events_at

_STATES = 7  # i_a, i_b, i_c, int i_a, int i_b, int i_c, int sum e i
_TIME_TOLERANCE = 1e-10  # s, zero-crossing location


@lru_cache(maxsize=1)
def _integrator() -> ca.Function:
    x = ca.SX.sym("x", _STATES)
    p = ca.SX.sym("p", 16)
    s = ca.SX.sym("s")
    length, start = p[0], p[1]
    mask, voltages, emf0, emf1 = p[2:5], p[5:8], p[8:11], p[11:14]
    decay, inverse_inductance = p[14], p[15]
    t = start + s * length
    emf = emf0 + emf1 * t
    i = x[0:3]
    count = ca.fmax(ca.sum1(mask), 1)
    neutral = ca.sum1(mask * (voltages - emf)) / count
    di = mask * ((voltages - emf - neutral) * inverse_inductance - decay * i)
    rhs = ca.vertcat(di, i, ca.dot(emf, i)) * length
    dae = {"x": x, "p": p, "t": s, "ode": rhs}
    options = {"abstol": 1e-11, "reltol": 1e-10}
    return ca.integrator("averaged_plant", "cvodes", dae, 0.0, 1.0, options)


def _step(
    state: np.ndarray,
    length: float,
    start: float,
    conducting: np.ndarray,
    voltages: np.ndarray,
    emf0: np.ndarray,
    emf1: np.ndarray,
    drive: Drive,
) -> np.ndarray:
    params = np.concatenate(
        (
            [length, start],
            conducting.astype(float),
            voltages,
            emf0,
            emf1,
            [drive.decay_rate, 1.0 / drive.inductance_h],
        )
    )
    with interrupts_noted():  # CasADi drops a KeyboardInterrupt raised in CVODES
        final = _integrator()(x0=state, p=params)["xf"]
    return np.array(final).ravel()


def simulate_averaged(
    drive: Drive,
    emf: BackEmf,
    schedule: Schedule,
    start: float,
    end: float,
    initial_currents: np.ndarray,
) -> Trace:
    builder = TraceBuilder("averaged", schedule)
    currents = np.array(initial_currents, dtype=float)
    builder.point(start, currents)
    times = sorted(
        set(schedule.breakpoints(start, end, gate_edges=False)) | set(emf.corners(start, end))
    )
    for lo, hi in pairwise(times):
        if hi - lo <= 1e-15:
            continue
        legs = LegVoltages.from_duties(schedule.duties_at(0.5 * (lo + hi)), drive.bus_voltage_v)
        currents = _run_piece(drive, emf, schedule, legs, lo, hi, currents, builder)
    return builder.finish()


def _run_piece(
    drive: Drive,
    emf: BackEmf,
    schedule: Schedule,
    legs: LegVoltages,
    lo: float,
    hi: float,
    currents: np.ndarray,
    builder: TraceBuilder,
) -> np.ndarray:
    emf0, emf1 = emf.affine(lo, hi)
    period = schedule.period_index(0.5 * (lo + hi))
    reversible = legs.reversible()
    t = lo
    for _ in range(64):
        if t >= hi:
            break
        topology = resolve(legs, currents, emf0 + emf1 * t)
        horizon, event = hi - t, None
        if topology.count >= 2:
            for phase in np.flatnonzero(~topology.conducting):
                v0, v1 = topology.floating_voltage(emf0, emf1, phase)
                now = v0 + v1 * t
                for threshold, falling in (
                    (legs.positive[phase], True),
                    (legs.negative[phase], False),
                ):
                    crossing = threshold_crossing(now, v1, threshold, falling)
                    if crossing is not None and crossing < horizon:
                        horizon, event = crossing, Event(0.0, "conducts", int(phase))
        state = np.concatenate((currents, np.zeros(4)))
        args = (topology.conducting, topology.voltages, emf0, emf1, drive)
        new = _step(state, horizon, t, *args)
        watched = topology.conducting & reversible
        direction = _directions(currents, topology, emf0 + emf1 * t, drive)
        crossed = [int(k) for k in np.flatnonzero(watched) if direction[k] * new[k] <= 0.0]
        if crossed:
            horizon, phase = _locate_zero(state, t, horizon, crossed, direction, args)
            new = _step(state, horizon, t, *args)
            new[phase] = 0.0
            event = Event(0.0, "zero", phase)
        builder.accumulate(period, horizon, new[3:6], float(new[6]))
        t += horizon
        # A floating phase's current is exactly zero, not the integrator's 1e-50.
        carried = currents
        currents = balanced(np.where(topology.conducting, new[:3], 0.0))
        if event is not None:
            builder.events += events_at(t, event, carried.tolist(), currents.tolist())
        builder.point(t, currents)
    return currents


def _directions(
    currents: np.ndarray, topology: Topology, emf: np.ndarray, drive: Drive
) -> np.ndarray:
    """Sign each conducting current moves in: its own sign, or its slope's at zero."""
    out = np.sign(currents)
    if np.any((currents == 0.0) & topology.conducting):
        neutral = topology.neutral(emf)
        slope = topology.voltages - emf - neutral
        out = np.where(currents == 0.0, np.sign(slope), out)
    return out


def _locate_zero(
    state: np.ndarray,
    t: float,
    horizon: float,
    phases: list[int],
    direction: np.ndarray,
    args: tuple,
) -> tuple[float, int]:
    """Earliest zero among `phases` in (0, horizon]."""
    zeros = [
        (_zero_of(state, t, horizon, phase, direction[phase], args), phase) for phase in phases
    ]
    return min(zeros)


def _zero_of(
    state: np.ndarray, t: float, horizon: float, phase: int, direction: float, args: tuple
) -> float:
    """Bracketed secant (Illinois) on the piece length for one phase current."""
    lo, hi = 0.0, horizon
    f_lo = direction * state[phase]
    f_hi = direction * _step(state, hi, t, *args)[phase]
    side = 0
    for _ in range(60):
        if hi - lo < _TIME_TOLERANCE:
            break
        guess = hi - f_hi * (hi - lo) / (f_hi - f_lo) if f_hi != f_lo else 0.5 * (lo + hi)
        if not lo < guess < hi:
            guess = 0.5 * (lo + hi)
        value = direction * _step(state, guess, t, *args)[phase]
        if value > 0.0:
            lo, f_lo = guess, value
            if side == -1:
                f_hi *= 0.5
            side = -1
        else:
            hi, f_hi = guess, value
            if side == 1:
                f_lo *= 0.5
            side = 1
    return hi

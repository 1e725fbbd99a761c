"""Which phases conduct, and at what terminal voltage: the bridge's diode logic.

Shared by the switched plant (duties 0 or 1: the gate states) and the averaged plant
(duties in [0, 1]: PWM averages, the paper's D U_d). For each leg, with d_up and d_low
the duties of its upper and lower transistor:

* a current into the winding (i > 0) flows through the upper transistor while it is on
  and through the lower diode otherwise: u+ = d_up U_d;
* a current out of the winding (i < 0) flows through the lower transistor while it is
  on and through the upper diode otherwise: u- = (1 - d_low) U_d.

This is `codegen.derivation.circuit.averaged_terminal_voltage` written for both current
signs at once. A leg with zero current floats: its terminal sits at u_n + e_x, fixed by
the conducting phases (Eq. 1 with i_x = 0 and di_x/dt = 0). It starts to conduct when
that voltage passes u+ (current flows in) or u- (current flows out), which covers both
a transistor turning on and a diode clamping to a rail.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from functools import cached_property

import numpy as np

#: Volts: a floating voltage within this of a threshold does not start conduction.
VOLTAGE_TOLERANCE = 1e-9


@dataclass(frozen=True)
class LegVoltages:
    """Terminal voltage each leg would have for a positive or a negative current."""

    positive: np.ndarray
    negative: np.ndarray

    @staticmethod
    def from_duties(duties: tuple[float, ...], bus_voltage: float) -> LegVoltages:
        """duties: six switch duties, index 2 k (upper) and 2 k + 1 (lower) of phase k."""
        upper = np.array(duties[0::2], dtype=float)
        lower = np.array(duties[1::2], dtype=float)
        return LegVoltages(upper * bus_voltage, (1.0 - lower) * bus_voltage)

    def reversible(self) -> np.ndarray:
        """Legs whose voltage depends on the current sign: a zero crossing is an event."""
        return np.abs(self.positive - self.negative) > VOLTAGE_TOLERANCE

    @cached_property
    def floats(self) -> tuple[list[float], list[float], list[bool]]:
        """(positive, negative, reversible) as Python lists, made once per legs (the
        emulated drive's plant keeps one per gate state and asks at every piece)."""
        return self.positive.tolist(), self.negative.tolist(), self.reversible().tolist()


@dataclass(frozen=True)
class Topology:
    conducting: np.ndarray  # bool, per phase
    voltages: np.ndarray  # terminal voltage of conducting phases (0 where floating)

    @property
    def count(self) -> int:
        return int(self.conducting.sum())

    def neutral(self, emf: np.ndarray) -> float:
        """u_n = mean over conducting phases of (u - e): R and L terms cancel (sum i = 0)."""
        if self.count == 0:
            return 0.0
        mask = self.conducting
        return float(np.mean(self.voltages[mask] - emf[mask]))

    def forcing(
        self, emf0: np.ndarray, emf1: np.ndarray, inductance: float
    ) -> tuple[np.ndarray, np.ndarray]:
        """(c0, c1) of di/dt = c0 + c1 t - (R/L) i for every phase (0 where floating)."""
        c0, c1 = forcing_of(
            self.conducting.tolist(),
            self.voltages.tolist(),
            emf0.tolist(),
            emf1.tolist(),
            inductance,
        )
        return np.array(c0), np.array(c1)

    def floating_voltage(
        self, emf0: np.ndarray, emf1: np.ndarray, phase: int
    ) -> tuple[float, float]:
        """(v0, v1) of the floating phase's terminal voltage v = v0 + v1 t = u_n + e_x."""
        return floating_voltage_of(
            self.conducting.tolist(), self.voltages.tolist(), emf0.tolist(), emf1.tolist(), phase
        )


def forcing_of(
    conducting: Sequence[bool],
    u: Sequence[float],
    e0: Sequence[float],
    e1: Sequence[float],
    inductance: float,
) -> tuple[list[float], list[float]]:
    """`Topology.forcing` on Python floats (the switched plant's pieces): the conducting
    set, the terminal voltages `u` and the EMF's (e0, e1)."""
    phases = [k for k, on in enumerate(conducting) if on]
    c0 = [0.0, 0.0, 0.0]
    c1 = [0.0, 0.0, 0.0]
    if len(phases) < 2:
        return c0, c1
    neutral0 = sum(u[k] - e0[k] for k in phases) / len(phases)
    neutral1 = -(sum(e1[k] for k in phases) / len(phases))
    for k in phases:
        c0[k] = (u[k] - e0[k] - neutral0) / inductance
        c1[k] = (-e1[k] - neutral1) / inductance
    return c0, c1


def floating_voltage_of(
    conducting: Sequence[bool],
    u: Sequence[float],
    e0: Sequence[float],
    e1: Sequence[float],
    phase: int,
) -> tuple[float, float]:
    """`Topology.floating_voltage` on Python floats."""
    phases = [k for k, on in enumerate(conducting) if on]
    neutral0 = sum(u[k] - e0[k] for k in phases) / len(phases)
    neutral1 = -(sum(e1[k] for k in phases) / len(phases))
    return neutral0 + e0[phase], neutral1 + e1[phase]


def resolve(legs: LegVoltages, currents: np.ndarray, emf: np.ndarray) -> Topology:
    """Conducting set and terminal voltages for the present currents and EMFs."""
    conducting, voltages = resolve_floats(
        legs.positive.tolist(), legs.negative.tolist(), currents.tolist(), emf.tolist()
    )
    return Topology(np.array(conducting, dtype=bool), np.array(voltages, dtype=float))


def resolve_floats(
    positive: Sequence[float], negative: Sequence[float], i: Sequence[float], e: Sequence[float]
) -> tuple[list[bool], list[float]]:
    """`resolve` on Python floats (it runs once a piece of the switched plant, where
    numpy's per-call overhead on three-element vectors was most of the time): the legs'
    `positive` and `negative` voltages, the currents `i` and the EMFs `e`; the
    conducting set and the terminal voltages."""
    conducting = [value != 0.0 for value in i]
    voltages = [
        (positive[k] if i[k] > 0.0 else negative[k]) if conducting[k] else 0.0 for k in range(3)
    ]
    if sum(conducting) < 2:
        conducting, voltages = _start_pair(positive, negative, e)
    while sum(conducting) >= 2:
        on = [k for k in range(3) if conducting[k]]
        neutral = sum(voltages[k] - e[k] for k in on) / len(on)
        best, best_margin, best_voltage = -1, VOLTAGE_TOLERANCE, 0.0
        for phase in range(3):
            if conducting[phase]:
                continue
            floating = neutral + e[phase]
            into = positive[phase] - floating
            out_of = floating - negative[phase]
            if into > best_margin:
                best, best_margin, best_voltage = phase, into, positive[phase]
            if out_of > best_margin:
                best, best_margin, best_voltage = phase, out_of, negative[phase]
        if best < 0:
            break
        conducting[best] = True
        voltages[best] = best_voltage
    return conducting, voltages


def _start_pair(
    positive: Sequence[float], negative: Sequence[float], emf: Sequence[float]
) -> tuple[list[bool], list[float]]:
    """With no current anywhere, the pair (in, out) whose loop voltage drives a current."""
    best, margin = None, VOLTAGE_TOLERANCE
    for into in range(3):
        for out_of in range(3):
            if into == out_of:
                continue
            drive = positive[into] - negative[out_of] - (emf[into] - emf[out_of])
            if drive > margin:
                best, margin = (into, out_of), drive
    conducting = [False, False, False]
    voltages = [0.0, 0.0, 0.0]
    if best is not None:
        conducting[best[0]] = conducting[best[1]] = True
        voltages[best[0]] = positive[best[0]]
        voltages[best[1]] = negative[best[1]]
    return conducting, voltages


def threshold_crossing(now: float, rate: float, threshold: float, falling: bool) -> float | None:
    """Time until v = now + rate t passes `threshold` downwards (falling) or upwards.

    The crossing is placed just past the threshold so that `resolve` sees it.
    """
    if falling and rate < 0.0 and now > threshold + VOLTAGE_TOLERANCE:
        return (threshold - VOLTAGE_TOLERANCE - now) / rate
    if not falling and rate > 0.0 and now < threshold - VOLTAGE_TOLERANCE:
        return (threshold + VOLTAGE_TOLERANCE - now) / rate
    return None


def balanced(currents: np.ndarray) -> np.ndarray:
    """Remove the rounding residue of sum i = 0 from the phases that carry current."""
    i = currents.tolist()
    out = balanced_floats(i)
    return currents if out is i else np.array(out)


def balanced_floats(i: list[float]) -> list[float]:
    """`balanced` on Python floats: a new list, or `i` itself where nothing changes."""
    carriers = [k for k in range(3) if i[k] != 0.0]
    count = len(carriers)
    if count == 1:
        return [0.0, 0.0, 0.0]  # a lone phase cannot carry current in a star winding
    if count >= 2:
        residue = (i[0] + i[1] + i[2]) / count
        out = list(i)
        for k in carriers:
            out[k] -= residue
        return out
    return i

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

from dataclasses import dataclass

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
        c0 = np.zeros(3)
        c1 = np.zeros(3)
        if self.count < 2:
            return c0, c1
        mask = self.conducting
        neutral0 = np.mean(self.voltages[mask] - emf0[mask])
        neutral1 = -np.mean(emf1[mask])
        c0[mask] = (self.voltages[mask] - emf0[mask] - neutral0) / inductance
        c1[mask] = (-emf1[mask] - neutral1) / inductance
        return c0, c1

    def floating_voltage(
        self, emf0: np.ndarray, emf1: np.ndarray, phase: int
    ) -> tuple[float, float]:
        """(v0, v1) of the floating phase's terminal voltage v = v0 + v1 t = u_n + e_x."""
        mask = self.conducting
        neutral0 = float(np.mean(self.voltages[mask] - emf0[mask]))
        neutral1 = float(-np.mean(emf1[mask]))
        return neutral0 + float(emf0[phase]), neutral1 + float(emf1[phase])


def resolve(legs: LegVoltages, currents: np.ndarray, emf: np.ndarray) -> Topology:
    """Conducting set and terminal voltages for the present currents and EMFs."""
    conducting = currents != 0.0
    voltages = np.where(currents > 0.0, legs.positive, legs.negative)
    voltages = np.where(conducting, voltages, 0.0)
    if conducting.sum() < 2:
        conducting, voltages = _start_pair(legs, emf)
    while conducting.sum() >= 2:
        neutral = float(np.mean(voltages[conducting] - emf[conducting]))
        best, best_margin, best_voltage = -1, VOLTAGE_TOLERANCE, 0.0
        for phase in np.flatnonzero(~conducting):
            floating = neutral + emf[phase]
            into = legs.positive[phase] - floating
            out_of = floating - legs.negative[phase]
            if into > best_margin:
                best, best_margin, best_voltage = phase, into, legs.positive[phase]
            if out_of > best_margin:
                best, best_margin, best_voltage = phase, out_of, legs.negative[phase]
        if best < 0:
            break
        conducting = conducting.copy()
        voltages = voltages.copy()
        conducting[best] = True
        voltages[best] = best_voltage
    return Topology(conducting, voltages)


def _start_pair(legs: LegVoltages, emf: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """With no current anywhere, the pair (in, out) whose loop voltage drives a current."""
    best, margin = None, VOLTAGE_TOLERANCE
    for into in range(3):
        for out_of in range(3):
            if into == out_of:
                continue
            drive = legs.positive[into] - legs.negative[out_of] - (emf[into] - emf[out_of])
            if drive > margin:
                best, margin = (into, out_of), drive
    conducting = np.zeros(3, dtype=bool)
    voltages = np.zeros(3)
    if best is not None:
        conducting[list(best)] = True
        voltages[best[0]] = legs.positive[best[0]]
        voltages[best[1]] = legs.negative[best[1]]
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
    carriers = currents != 0.0
    count = int(carriers.sum())
    if count == 1:
        return np.zeros(3)  # a lone phase cannot carry current in a star winding
    if count >= 2:
        currents = currents.copy()
        currents[carriers] -= currents.sum() / count
    return currents

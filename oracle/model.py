"""What the core must do at given inputs, from the spec and this package alone.

The documented contract of `bldc_commutate()` (README, "The generated C"):

* Hall codes: a code outside the spec's sequence (000, 111, > 7) or a jump that is not
  one sector forward or back: every switch off, sector 0xFF for an invalid code,
  flag INVALID_HALL.
* Safe state: a Hall period below the top speed's, or a bus above its maximum: every
  switch off, zero duties and time, flag INPUT_SATURATED.
* Otherwise the edge's two switches, the duties and the commutation time of the
  method; INPUT_SATURATED when the period is above the slowest speed's, the bus below
  its minimum (it saturates there), the current code outside the braking range, or (for
  the methods that take one) the main duty above one period; HIGH_SPEED in Eq. 18's
  upper segment; FAIL_AREA_CLAMPED where no duty pair in [0, 1] holds the current.

Flag bits are read from the generated manifest by the verifier; here flags are names.
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction

import numpy as np
import numpy.typing as npt

from codegen.spec_model import Spec
from oracle import paper, rule, switching
from oracle.emf_shape import EdgeEmf, edge_emf
from oracle.units import Limits, Units, limits, units

Ints = npt.NDArray[np.int64]
Bools = npt.NDArray[np.bool_]
Floats = npt.NDArray[np.float64]

NONE = 0xFF


@dataclass(frozen=True)
class Decisions:
    """The exact, discrete part of the expectation, per point."""

    valid: Bools  # a valid edge
    active: Bools  # valid and not in the safe state
    on_switch: Ints
    off_switch: Ints
    sector: Ints
    saturated: Bools  # INPUT_SATURATED expected (active points and safe-state points)
    bus: Ints  # the bus code the core computes with (saturated to its range)
    period: Ints  # the period the duties and time are computed at


@dataclass(frozen=True)
class Oracle:
    spec: Spec
    u: Units
    lim: Limits
    motor: paper.Motor
    method: str
    edges: dict[tuple[int, int], tuple[int, int]]
    emf: EdgeEmf  # the spec's EMF around the paper's edge (the rule's shape)

    @property
    def uses_main_duty(self) -> bool:
        return self.method in ("none", "conventional")

    # -------------------------------------------------------------- decisions

    def decide(
        self, hall: Ints, previous: Ints, period: Ints, bus: Ints, current: Ints, main: Ints
    ) -> Decisions:
        n = hall.size
        on_sw = np.full(n, NONE, dtype=np.int64)
        off_sw = np.full(n, NONE, dtype=np.int64)
        for (a, b), (s_on, s_off) in self.edges.items():
            hit = (previous == a) & (hall == b)
            on_sw[hit], off_sw[hit] = s_on, s_off
        valid = on_sw != NONE
        sector_of = np.full(256, NONE, dtype=np.int64)
        for k, code in enumerate(self.spec.hall.sequence):
            sector_of[code] = k
        sector = sector_of[np.clip(hall, 0, 255)]
        capped = np.minimum(period, self.u.hall_counter_max)
        unsafe = (capped < self.lim.period_min) | (bus > self.lim.bus_max)
        active = valid & ~unsafe
        out_of_range = (
            (capped > self.lim.period_max)
            | (bus < self.lim.bus_min)
            | (current < self.lim.current_low)
            | (current > self.lim.current_high)
        )
        if self.uses_main_duty:
            out_of_range |= main > self.u.pwm_counts
        saturated = valid & (unsafe | out_of_range)
        used_period = capped
        if self.method == "improved_r":
            used_period = np.minimum(capped, self.lim.period_max)
        return Decisions(
            valid=valid,
            active=active,
            on_switch=np.where(active, on_sw, NONE),
            off_switch=np.where(active, off_sw, NONE),
            sector=sector,
            saturated=saturated,
            bus=np.clip(bus, self.lim.bus_min, self.lim.bus_max),
            period=np.maximum(used_period, 1),
        )

    # -------------------------------------------------------------- physics

    def amps(self, current: Ints) -> Floats:
        """I at a current code, the code saturated at the ADC's full scale."""
        code = np.minimum(current, self.u.adc_max).astype(np.float64)
        return (code - float(self.u.zero_current_code)) * float(self.u.amps_per_code)

    def duties(self, period: Ints, bus: Ints, main: Ints) -> tuple[Floats, Floats, Bools, Bools]:
        """(D_on, D_off) in counts, the high-speed segment and the fail area."""
        if self.method == "improved":
            on, off, high = paper.improved_duties(self.u, self.motor, period, bus)
            return on, off, high, np.zeros(on.shape, dtype=bool)
        high = paper.high_speed(self.u, self.motor, period, bus)
        if self.method == "conventional":
            on, off, fail = paper.conventional_duties(self.u, self.motor, period, bus, main)
            return on, off, high, fail
        on = np.minimum(main, self.u.pwm_counts).astype(np.float64)
        return on, np.zeros_like(on), high, np.zeros(on.shape, dtype=bool)

    def eq20(
        self, period: Ints, bus: Ints, current: Ints, on: Floats, off: Floats, w_shift: float = 0.0
    ) -> tuple[Floats, Floats]:
        """Eq. 20 in Hall ticks at the given duties (inf where W <= 0; 0 for I <= 0),
        and W in counts (W_volts 2P / U_d), with W moved by w_shift counts."""
        amps = self.amps(current)
        u_d = paper.bus_volts(self.u, bus)
        p = self.u.pwm_counts
        _, w_volts = paper.commutation_seconds(self.u, self.motor, period, bus, amps, on, off)
        w = w_volts * 2 * p / u_d + w_shift
        with np.errstate(divide="ignore", invalid="ignore"):
            seconds = 6 * p * amps * float(self.motor.inductance) / (u_d * w)
        ticks = np.where(w > 0, seconds * float(self.u.hall_hz), np.inf)
        return np.where(amps > 0, ticks, 0.0), w

    def rule(self, period: Ints, bus: Ints, current: Ints) -> rule.Commutation:
        """The resistance-aware rule's quantities (period already clamped to the range)."""
        amps = np.maximum(self.amps(current), 0.0)
        return rule.commutation(
            self.u.pwm_counts,
            paper.emf(self.u, self.motor, period),
            paper.bus_volts(self.u, bus),
            amps,
            period.astype(np.float64) / float(self.u.hall_hz),
            float(self.spec.motor.phase_resistance_ohm),
            float(self.motor.inductance),
            self.emf,
            float(self.u.hall_hz),
            float(self.u.carrier_ticks),
            self.u.latest_end(np.asarray(period, dtype=np.int64)).astype(np.float64),
        )


def oracle(spec: Spec) -> Oracle:
    u = units(spec)
    return Oracle(
        spec=spec,
        u=u,
        lim=limits(spec, u),
        motor=paper.Motor(
            Fraction(spec.motor.back_emf_constant_v_per_rpm),
            Fraction(spec.motor.phase_inductance_h),
        ),
        method=spec.controller.method,
        edges=switching.switches(tuple(spec.hall.sequence)),
        emf=edge_emf(spec.motor.back_emf_shape),
    )

"""The spec's drive as floats in SI units, and the speed-dependent quantities.

The spec keeps exact fractions for the symbolic chain; the simulation needs floats,
converted once here so no other module touches `Spec` fields directly.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

from codegen.spec_drive import conducting_line_mean
from codegen.spec_model import PwmAlignment, Spec
from sim.emf import TRAPEZOID_120

#: The plant is simulated one PWM period after another, so a sector's cost grows with its
#: carrier periods: the simulation starts no lower than the speed whose 60 deg sector
#: spans this many (a whole second at 20 kHz; the paper motor's slowest sector spans 1000)
MAX_SECTOR_PERIODS = 20_000


def simulated_speed_min_rpm(spec_min_rpm: float, pole_pairs: int, pwm_frequency_hz: float) -> float:
    """The lowest speed the simulation runs at: the spec's speed_min, or the speed whose
    sector spans MAX_SECTOR_PERIODS carrier periods where that is higher (rounded up to
    a whole rpm)."""
    floor = 10.0 * pwm_frequency_hz / (MAX_SECTOR_PERIODS * pole_pairs)
    return spec_min_rpm if floor <= spec_min_rpm else float(math.ceil(floor))


@dataclass(frozen=True)
class Drive:
    name: str
    resistance_ohm: float
    inductance_h: float
    #: Phase flat-top EMF per mechanical rpm (paper Eq. 3, E = k_e n).
    emf_v_per_rpm: float
    pole_pairs: int
    bus_voltage_v: float
    pwm_frequency_hz: float
    pwm_alignment: PwmAlignment
    braking_current_a: float
    #: the lowest speed simulated: the spec's speed_min, or higher where a sector there
    #: spans more than MAX_SECTOR_PERIODS carrier periods (`spec_speed_min_rpm` keeps it)
    speed_min_rpm: float
    speed_max_rpm: float
    #: The phase EMF's half period, (deg from the rising zero crossing, e/E) points.
    emf_points: tuple[tuple[float, float], ...] = TRAPEZOID_120
    #: How the spec gave it ("trapezoid, 120 deg flat top" or "measured table, ...").
    emf_description: str = "trapezoid, 120 deg flat top"
    #: The spec's `back_emf_shape: flat`: the paper's EMFs, frozen at their edge values
    #: through the commutation (the plant's "spec" shape is then the "flat" one).
    emf_frozen: bool = False
    #: the spec's controller.speed_min (0: the same as speed_min_rpm)
    spec_speed_min_rpm: float = 0.0
    #: The conducting pair's mean line-to-line EMF over a sector per unit of 2E
    #: (`codegen.spec_drive.conducting_line_mean`): 1 for the 120 deg trapezoid, 2 for a
    #: table whose flat top is 2 (the loader's k_e is then half the trapezoid's)
    hold_emf_factor: float = 1.0

    @staticmethod
    def from_spec(spec: Spec) -> Drive:
        return Drive(
            name=spec.name,
            resistance_ohm=float(spec.motor.phase_resistance_ohm),
            inductance_h=float(spec.motor.phase_inductance_h),
            emf_v_per_rpm=float(spec.motor.back_emf_constant_v_per_rpm),
            pole_pairs=spec.motor.pole_pairs,
            bus_voltage_v=float(spec.inverter.bus_voltage_nominal_v),
            pwm_frequency_hz=float(spec.inverter.pwm_frequency_hz),
            pwm_alignment=spec.inverter.pwm_alignment,
            braking_current_a=float(spec.controller.braking_current_nominal_a),
            speed_min_rpm=min(
                simulated_speed_min_rpm(
                    float(spec.controller.speed_min_rpm),
                    spec.motor.pole_pairs,
                    float(spec.inverter.pwm_frequency_hz),
                ),
                float(spec.controller.speed_max_rpm),
            ),
            speed_max_rpm=float(spec.controller.speed_max_rpm),
            emf_points=tuple((float(a), float(v)) for a, v in spec.motor.back_emf_shape.points),
            emf_description=spec.motor.back_emf_shape.describe(),
            emf_frozen=spec.motor.back_emf_shape.frozen,
            spec_speed_min_rpm=float(spec.controller.speed_min_rpm),
            hold_emf_factor=float(conducting_line_mean(spec.motor.back_emf_shape)),
        )

    def with_pwm_frequency(self, frequency_hz: float) -> Drive:
        return replace(self, pwm_frequency_hz=frequency_hz)

    def with_flat_top(self, width_deg: float) -> Drive:
        """The same drive with a trapezoidal EMF of another flat-top width."""
        rise = (180.0 - width_deg) / 2.0
        points = ((0.0, 0.0), (rise, 1.0), (180.0 - rise, 1.0), (180.0, 0.0))
        return replace(
            self,
            emf_points=points,
            emf_description=f"trapezoid, {width_deg:g} deg flat top",
            emf_frozen=False,
        )

    def rotating(self) -> Drive:
        """The drive whose EMFs turn with the rotor, as a motor's do over many sectors
        (the emulated drive's plant, emulation/pil/plant.py, and the SIL commutations it
        is held to): the spec's `flat` is the paper's idealisation of one commutation
        (the EMFs frozen at their edge values), which no rotating motor has; the motor
        it idealises is the 120 deg trapezoid whose edge values they are. Every other
        shape is its own."""
        return self.with_flat_top(120.0) if self.emf_frozen else self

    def with_frozen_emf(self) -> Drive:
        """The same drive with the paper's frozen (flat) EMF as its own shape."""
        return replace(
            self,
            emf_points=TRAPEZOID_120,
            emf_description="flat (the paper's EMFs frozen at the edge)",
            emf_frozen=True,
        )

    @property
    def pwm_period_s(self) -> float:
        return 1.0 / self.pwm_frequency_hz

    @property
    def decay_rate(self) -> float:
        """R/L in 1/s: the only dynamics of the winding (all phases share R and L)."""
        return self.resistance_ohm / self.inductance_h

    def emf_v(self, speed_rpm: float) -> float:
        """k_e n: the amplitude the shape's per-unit points scale (the plant's EMF)."""
        return self.emf_v_per_rpm * speed_rpm

    def hold_emf_v(self, speed_rpm: float) -> float:
        """Half the conducting pair's mean line-to-line EMF over a sector: the E of the
        averaged circuit between commutations, (1 - D) U_d = 2E - 2 R I, which the main
        duty balances. k_e n for the 120 deg trapezoid; the main-duty loop had taken k_e n
        for every shape, so a table whose flat top is 2 got a duty that held another
        current than the switched plant then carried."""
        return self.emf_v(speed_rpm) * self.hold_emf_factor

    def sector_time_s(self, speed_rpm: float) -> float:
        """One Hall interval, 60 electrical degrees: 10 / (n p) seconds for n in rpm."""
        return 10.0 / (speed_rpm * self.pole_pairs)

    def mechanical_speed_rad_s(self, speed_rpm: float) -> float:
        return 2.0 * math.pi * speed_rpm / 60.0

    def steady_duty(self, speed_rpm: float, current_a: float) -> float:
        """Main duty that holds `current_a` between commutations (an ideal current loop).

        Two phases in series: (1 - D) U_d = 2E - 2 R I, the duty of the modulated
        transistor at which the averaged voltage balances EMF and resistive drop. The
        periodic steady state of a linear RL circuit has exactly this average current.
        """
        emf = self.hold_emf_v(speed_rpm)
        duty = 1.0 - (2.0 * emf - 2.0 * self.resistance_ohm * current_a) / self.bus_voltage_v
        return min(max(duty, 0.0), 1.0)

    @property
    def boundary_speed_rpm(self) -> float:
        """Eq. 18's segment cut-off U_d / (4 k_e)."""
        return self.bus_voltage_v / (4.0 * self.emf_v_per_rpm)

    @property
    def upper_speed_rpm(self) -> float:
        """U_d / (2 k_e): above it the EMF alone exceeds the bus."""
        return self.bus_voltage_v / (2.0 * self.emf_v_per_rpm)

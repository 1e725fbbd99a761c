"""Validated spec data: frozen dataclasses in SI units, as exact fractions.

Only codegen.spec_loader builds these. Everything downstream trusts them: a Spec that
exists has passed every range, unit and physical-consistency check.
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction
from typing import Literal

CommutationMethod = Literal["improved", "conventional", "none", "improved_r"]
PwmAlignment = Literal["edge", "center"]
EmfConvention = Literal["phase", "line_to_line"]

COMMUTATION_METHODS: tuple[str, ...] = ("improved", "conventional", "none", "improved_r")


def uses_main_duty(method: str) -> bool:
    """Whether the method's commutation duties follow the current controller's main duty
    (the improved rules hold the current by themselves)."""
    return method in ("none", "conventional")


@dataclass(frozen=True)
class Motor:
    rated_voltage_v: Fraction
    phase_resistance_ohm: Fraction
    phase_inductance_h: Fraction
    poles: int
    #: Phase flat-top back-EMF per mechanical rpm (paper Eq. 3, E = k_e n), already
    #: converted from a line-to-line datasheet value when the spec said so.
    back_emf_constant_v_per_rpm: Fraction
    back_emf_convention: EmfConvention
    rotor_inertia_kg_m2: Fraction

    @property
    def pole_pairs(self) -> int:
        return self.poles // 2


@dataclass(frozen=True)
class Inverter:
    bus_voltage_nominal_v: Fraction
    bus_voltage_min_v: Fraction
    bus_voltage_max_v: Fraction
    pwm_frequency_hz: Fraction
    pwm_alignment: PwmAlignment
    timer_clock_hz: Fraction
    dead_time_s: Fraction


@dataclass(frozen=True)
class HallSensor:
    #: Hall codes (A B C as bits 2 1 0) of sectors 0..5 in forward rotation.
    sequence: tuple[int, ...]
    timer_clock_hz: Fraction
    counter_bits: int


@dataclass(frozen=True)
class Adc:
    bits: int
    reference_v: Fraction
    bus_voltage_divider: Fraction
    current_gain_v_per_a: Fraction
    current_offset_v: Fraction


@dataclass(frozen=True)
class Controller:
    method: CommutationMethod
    braking_current_min_a: Fraction
    braking_current_nominal_a: Fraction
    braking_current_max_a: Fraction
    speed_min_rpm: Fraction
    speed_max_rpm: Fraction


@dataclass(frozen=True)
class Accuracy:
    duty_counts: Fraction
    commutation_time_ticks: Fraction


@dataclass(frozen=True)
class OperatingPoint:
    speed_rpm: Fraction
    main_duty: Fraction


@dataclass(frozen=True)
class SpecWarning:
    """A legal but unusual value: printed on stderr, one line, unless the spec lists
    its `id` under `warnings.silence`."""

    id: str
    path: str
    value: object
    message: str
    source: str = ""
    line: int | None = None

    def __str__(self) -> str:
        where = f"{self.source}:{self.line}" if self.line is not None else self.source
        return (
            f"{where}: {self.path} = {self.value!r}: {self.message}"
            f" [silence with `warnings: {{silence: [{self.id}]}}`]"
        )


@dataclass(frozen=True)
class Spec:
    name: str
    description: str
    #: Path of the YAML file as given by the user, and the SHA-256 of its bytes.
    source_path: str
    sha256: str
    motor: Motor
    inverter: Inverter
    hall: HallSensor
    adc: Adc
    controller: Controller
    accuracy: Accuracy
    operating_points: tuple[OperatingPoint, ...]
    #: Key path -> where the value comes from ("paper Table 3", "assumption: ...").
    sources: tuple[tuple[str, str], ...]
    #: Plausibility warnings the spec did not silence, and the ids it silenced.
    warnings: tuple[SpecWarning, ...] = ()
    silenced_warnings: tuple[str, ...] = ()

    @property
    def assumptions(self) -> tuple[tuple[str, str], ...]:
        return tuple((k, v) for k, v in self.sources if v.startswith("assumption"))

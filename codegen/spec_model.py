"""Validated spec data: frozen dataclasses in SI units, as exact fractions.

Only codegen.spec_loader builds these. Everything downstream trusts them: a Spec that
exists has passed every range, unit and physical-consistency check.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from decimal import Decimal, localcontext
from fractions import Fraction
from typing import Literal

from codegen.errors import clipped

CommutationMethod = Literal["improved", "conventional", "none", "improved_r"]
PwmAlignment = Literal["edge", "center"]
EmfConvention = Literal["phase", "line_to_line"]
SensingTopology = Literal["dc_link_shunt", "low_side_phase_shunts"]
BreakPolarity = Literal["active_low", "active_high"]
SafeStatePolicy = Literal["all_off", "short_circuit"]
Integration = Literal["vector_table", "cube"]

COMMUTATION_METHODS: tuple[str, ...] = ("improved", "conventional", "none", "improved_r")


def uses_main_duty(method: str) -> bool:
    """Whether the method's commutation duties follow the current controller's main duty
    (the improved rules hold the current by themselves)."""
    return method in ("none", "conventional")


#: The paper's ideal trapezoid: flat tops of 120 electrical degrees (Fig. 2).
TRAPEZOID_120: tuple[tuple[Fraction, Fraction], ...] = (
    (Fraction(0), Fraction(0)),
    (Fraction(30), Fraction(1)),
    (Fraction(150), Fraction(1)),
    (Fraction(180), Fraction(0)),
)


@dataclass(frozen=True)
class BackEmfShape:
    """One phase's back-EMF over a half period, per unit of E = k_e n.

    Points (electrical degrees from the phase's rising zero crossing, e / E), linear
    in between, from 0 deg to 180 deg with e = 0 at both ends; the other half period
    is the negative (e(theta + 180) = -e(theta)). The Hall edge at which a phase
    starts its rise lies 30 deg before that zero crossing (Hall sensors placed for
    120 deg conduction). `flat_top_deg` is the width it was given as, or None for a
    measured table. `frozen` is the paper's idealisation instead (section 3.2,
    `back_emf_shape: flat`): every EMF keeps its value at the Hall edge (+E, -E, -E)
    through the commutation, the shape the paper's Eqs. 14-20 assume; `points` then
    holds the 120 deg trapezoid whose values at the edge those are.
    """

    points: tuple[tuple[Fraction, Fraction], ...] = TRAPEZOID_120
    flat_top_deg: Fraction | None = Fraction(120)
    frozen: bool = False

    def __hash__(self) -> int:
        """Computed once: the loader's and the drive's checks key their caches by the
        shape, and a measured table's thousands of Fractions (each hash a modular
        inverse) made every lookup cost milliseconds (a 3001-point table: 200 s)."""
        cached = self.__dict__.get("_hash")
        if cached is None:
            cached = hash((self.points, self.flat_top_deg, self.frozen))
            object.__setattr__(self, "_hash", cached)
        return cached

    @staticmethod
    def trapezoid(flat_top_deg: Fraction) -> BackEmfShape:
        rise = (180 - flat_top_deg) / 2
        points = ((Fraction(0), Fraction(0)), (rise, Fraction(1)))
        points += ((180 - rise, Fraction(1)), (Fraction(180), Fraction(0)))
        return BackEmfShape(points, flat_top_deg)

    @staticmethod
    def flat() -> BackEmfShape:
        """The paper's frozen EMFs (section 3.2: e_a = E, e_b = e_c = -E)."""
        return BackEmfShape(TRAPEZOID_120, None, frozen=True)

    def describe(self) -> str:
        if self.frozen:
            return "flat (the paper's EMFs frozen at the edge)"
        if self.flat_top_deg is not None:
            return f"trapezoid, {_width_text(self.flat_top_deg)} deg flat top"
        return f"measured table, {len(self.points)} points"


def _width_text(value: Fraction, digits: int = 12) -> str:
    """A flat-top width as the spec wrote it: its exact decimal (`:g` had shown
    '119.9999999 deg' as 120, in a refusal whose allowed value was '120 deg'), or
    `digits` significant digits where it has no finite decimal expansion."""
    denominator = value.denominator
    for p in (2, 5):
        while denominator % p == 0:
            denominator //= p
    with localcontext() as context:
        context.prec = 100 if denominator == 1 else digits
        shown = Decimal(value.numerator) / Decimal(value.denominator)
    return f"{shown.normalize():f}"


@dataclass(frozen=True)
class Tolerances:
    """Relative deviation of the real drive from the spec's nominal values, as
    (low, high) fractions (-0.1 = 10 % below nominal): what a robustness campaign
    samples. The firmware keeps the nominal values; the plant gets the sampled ones."""

    phase_resistance: tuple[Fraction, Fraction]
    phase_inductance: tuple[Fraction, Fraction]
    back_emf_constant: tuple[Fraction, Fraction]
    bus_voltage: tuple[Fraction, Fraction]


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
    #: Optional `motor.back_emf_shape`; default the paper's 120 deg trapezoid.
    back_emf_shape: BackEmfShape = BackEmfShape()
    #: Optional `motor.viscous_friction` (bearings, windage), N m s/rad; default 0: the
    #: braking torque alone decelerates the rotor (the emulated drive's plant).
    viscous_friction_n_m_s: Fraction = Fraction(0)

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
    #: the most a 60 deg sector may be shorter than the one its commutation's timing was
    #: computed from (two sectors before it), as a fraction (`hall.sector_shortening`,
    #: percent in the spec: a Hall sensor off its mark, 6.7 % per electrical degree,
    #: and acceleration)
    sector_shortening: Fraction


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
    """The user's error budget; the verifier's tolerances come from here alone."""

    duty_counts: Fraction
    commutation_time_ticks: Fraction
    #: Declared relaxation where the commutation time is ill-conditioned: where one TIM1
    #: count of duty moves t_com by more than `ill_conditioned_above` ticks, t_com need
    #: only be within the time target of the exact value for a duty error of up to
    #: `ill_conditioned_counts` counts (Eq. 20's denominator, or the rule's held duty
    #: sum). None: no relaxation, the time target holds everywhere.
    ill_conditioned_above: Fraction | None = None
    ill_conditioned_counts: Fraction | None = None
    #: |duty - exact| of the braking-current PI, TIM1 counts: one step from any state,
    #: and along step responses and saturation from the same measured codes.
    current_loop_duty_counts: Fraction = Fraction(1)


@dataclass(frozen=True)
class Sensing:
    """Where the braking current I of Eqs. 15-20 and the bus voltage are measured.

    `dc_link_shunt`: one shunt in the bridge's negative rail (one ADC channel);
    `low_side_phase_shunts`: one shunt under each lower switch (channels of phases A, B,
    C). Every channel's chain reads I as `adc.current_offset + adc.current_gain I`.
    Which signal is I in each sector, and when in the PWM period it is sampled, is
    derived from the switching table (codegen/control/sensing.py)."""

    topology: SensingTopology
    current_channels: tuple[int, ...]  # ADC12_INx: one (DC link) or three (A, B, C)
    bus_voltage_channel: int
    #: ringing after a switching edge before the shunt signal is valid
    settling_time_s: Fraction
    #: ADC sample time in ADC clock cycles (RM0008 ADC_SMPRx: 1.5 ... 239.5)
    adc_sample_cycles: Fraction


@dataclass(frozen=True)
class CurrentLoop:
    """The braking-current PI: crossover of the open loop (pole-zero cancellation)."""

    bandwidth_hz: Fraction


@dataclass(frozen=True)
class Protection:
    #: trip level of the external over-current comparator on TIM1 BKIN (phase current)
    over_current_a: Fraction
    break_polarity: BreakPolarity
    #: peak phase current the bridge may carry in an active short circuit
    short_circuit_current_max_a: Fraction
    #: the safe state where both all-off and the short circuit are valid
    safe_state: SafeStatePolicy


@dataclass(frozen=True)
class Firmware:
    """How the firmware is built and integrated, and its budgets (`make firmware`)."""

    integration: Integration
    hse_startup_timeout_s: Fraction
    watchdog_timeout_s: Fraction
    flash_budget_bytes: int
    ram_budget_bytes: int  # stack included
    cpu_load_budget_percent: Fraction
    current_loop_budget_cycles: int


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

    def __post_init__(self) -> None:
        # a frozen Spec is hashed (the core's build is cached by it): a raw YAML list (a
        # measured EMF table) is kept as a tuple of tuples
        object.__setattr__(self, "value", _frozen(self.value))

    def __str__(self) -> str:
        where = f"{self.source}:{self.line}" if self.line is not None else self.source
        return (
            f"{where}: {self.path} = {clipped(_as_yaml_text(self.value))}: {self.message}"
            f" [silence with `warnings: {{silence: [{self.id}]}}`]"
        )


def _frozen(value: object) -> object:
    if isinstance(value, list | tuple):
        return tuple(_frozen(item) for item in value)
    return value


def _as_yaml_text(value: object) -> str:
    """repr, with a tuple shown as the YAML list it was read from."""
    if isinstance(value, tuple):
        return "[" + ", ".join(_as_yaml_text(item) for item in value) + "]"
    return repr(value)


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
    sensing: Sensing
    current_loop: CurrentLoop
    protection: Protection
    firmware: Firmware
    #: Key path -> where the value comes from ("paper Table 3", "assumption: ...").
    sources: tuple[tuple[str, str], ...]
    #: Optional `tolerances` section (robustness campaign); None when absent.
    tolerances: Tolerances | None = None
    #: Plausibility warnings the spec did not silence, and the ids it silenced.
    warnings: tuple[SpecWarning, ...] = ()
    silenced_warnings: tuple[str, ...] = ()

    @property
    def assumptions(self) -> tuple[tuple[str, str], ...]:
        return tuple((k, v) for k, v in self.sources if v.startswith("assumption"))


#: The closed-loop time constants a braking-current step response takes to settle.
STEP_RESPONSE_TIME_CONSTANTS = 5
#: The largest accuracy.current_loop_duty_counts a spec may ask for (the loader's range):
#: an error budget of a few counts, not a description of an inaccurate loop.
LOOP_DUTY_COUNTS_MAX = 16
#: The loosest accuracy.commutation_time_ticks a spec may ask for.
COMMUTATION_TICKS_MAX = 64


def loop_periods_per_step_response(spec: Spec) -> float:
    """PWM periods in a braking-current step response: 5 closed-loop time constants,
    5 f_pwm / w_c (at least one)."""
    periods = (
        STEP_RESPONSE_TIME_CONSTANTS
        * float(spec.inverter.pwm_frequency_hz)
        / (2 * math.pi * float(spec.current_loop.bandwidth_hz))
    )
    return max(1.0, periods)


def integrator_step_tolerance_counts(spec: Spec) -> float:
    """What the spec allows the braking-current PI's integrator to be off by in one PWM
    period, in TIM1 counts: accuracy.current_loop_duty_counts spread over the periods of
    a step response, over which the error of each step accumulates: the requirement the
    loop's design is held to (verify states its own, oracle.current_loop)."""
    return float(spec.accuracy.current_loop_duty_counts) / loop_periods_per_step_response(spec)

"""The exact symbolic model at the firmware's integer inputs: what the core should return.

This is the reference of the verifier and of the generated Unity tests. It evaluates the
derivation's own expressions (Eq. 18's rows and boundary, Eq. 16, Eq. 20) at the
physical values the spec's conversions give for each input code: speed from the Hall
period, U_d from the bus code, I from the current code. It never uses the fixed-point
design's constants (K_X, K_G, the Q format), so a wrong constant in the generator shows
up as a disagreement.

Decisions (segment, fail area, safe state) are exact rational comparisons. Duties and
the commutation time are lambdified to float64 numpy functions: their rounding error is
below 1e-9 counts or ticks for the values involved (a handful of operations on numbers
below 1e5 at 2^-53 relative precision), negligible against one LSB. Where Eq. 20's
denominator is within 1e-6 counts of zero, `commutation_time` switches to exact rational
arithmetic.
"""

from __future__ import annotations

from dataclasses import dataclass, fields
from fractions import Fraction

import numpy as np
import numpy.typing as npt
import sympy as sp

from codegen.derivation import symbols as s
from codegen.derivation.paper import Derivation
from codegen.fixedpoint.design import FixedPointDesign
from codegen.fixedpoint.scaling import Scaling
from codegen.improved_r_rule.constants import RuleConstants, rule_constants
from codegen.improved_r_rule.reference import FLAG_ABOVE_BUS as RULE_ABOVE_BUS
from codegen.improved_r_rule.reference import FLAG_CANNOT_HOLD as RULE_CANNOT_HOLD
from codegen.improved_r_rule.reference import ReferenceBatch, reference_batch
from codegen.spec_model import Spec, uses_main_duty

FLAG_HIGH_SPEED = 0x01
FLAG_FAIL_AREA_CLAMPED = 0x02
FLAG_INPUT_SATURATED = 0x04
FLAG_INVALID_HALL = 0x08
FLAG_TIME_CLAMPED = 0x10
NO_SWITCH = 0xFF
INVALID_SECTOR = 0xFF

SLACK = 1e-6  # float64 evaluation of the reference, far below one LSB
Floats = npt.NDArray[np.float64]
Ints = npt.NDArray[np.int64]


def _fraction(value: sp.Rational | Fraction | int) -> Fraction:
    r = sp.Rational(value)
    return Fraction(int(r.p), int(r.q))


@dataclass(frozen=True)
class ExactModel:
    """One spec's reference. Built once; evaluates arrays of input codes."""

    method: str
    period_counts: int  # P
    hall_sequence: tuple[int, ...]
    edge_switches: dict[tuple[str, int], tuple[int, int]]  # (direction, sector) -> (on, off)
    period_min: int
    period_max: int
    bus_min: int
    bus_max: int
    current_offset: int
    current_code_max: int
    #: 4E > U_d  <=>  boundary_lhs > boundary_rhs * T * B (integers, from Eq. 18's row)
    boundary_lhs: int
    boundary_rhs: int
    speed_per_tick: Fraction  # n = speed_per_tick / T (rpm)
    volts_per_code: Fraction
    amps_per_code: Fraction
    k_e: Fraction
    inductance: Fraction
    hall_clock_hz: Fraction
    on_high: object  # numpy functions of (E, U_d)
    off_high: object
    on_low: object
    off_low: object
    off_conventional: object  # (E, U_d, D_on)
    time_denominator: object  # W in volts: Eq. 20 = 3 I L / W, (E, U_d, D_on, D_off)
    #: improved_r: the resistance-aware rule's exact constants (None for the paper's methods)
    rule: RuleConstants | None = None

    # ------------------------------------------------------------------ decisions

    def sector_of(self, code: int) -> int:
        return self.hall_sequence.index(code) if code in self.hall_sequence else INVALID_SECTOR

    def edge(self, previous: int, code: int) -> tuple[str, int] | None:
        """(direction, sector entered) of a Hall transition, None when invalid."""
        before, after = self.sector_of(previous), self.sector_of(code)
        if INVALID_SECTOR in (before, after):
            return None
        if after == (before + 1) % 6:
            return ("forward", after)
        if before == (after + 1) % 6:
            return ("reverse", after)
        return None

    def high_speed(self, period: Ints, bus: Ints) -> npt.NDArray[np.bool_]:
        """Eq. 18's segment, exactly: n > U_d / (4 k_e) as an integer comparison."""
        return self.boundary_lhs > self.boundary_rhs * period.astype(object) * bus.astype(object)

    def fail_area(self, period: Ints, bus: Ints, main: Ints) -> npt.NDArray[np.bool_]:
        """Eq. 16's D_off outside [0, 1], exactly (conventional method)."""
        out = np.zeros(period.shape, dtype=bool)
        for k in range(period.size):
            emf = self.k_e * self.speed_per_tick / int(period.flat[k])
            u_d = self.volts_per_code * int(bus.flat[k])
            d_off = 2 - Fraction(int(main.flat[k]), self.period_counts) - 4 * emf / u_d
            out.flat[k] = not (0 <= d_off <= 1)
        return out

    # ------------------------------------------------------------------ values

    def emf_and_bus(self, period: Ints, bus: Ints) -> tuple[Floats, Floats]:
        emf = float(self.k_e * self.speed_per_tick) / period.astype(np.float64)
        return emf, float(self.volts_per_code) * bus.astype(np.float64)

    def rule_batch(self, period: Ints, bus: Ints, current: Ints) -> ReferenceBatch:
        """The resistance-aware rule in real arithmetic at every point (evaluated once per
        distinct (T, B, C): the verifier's sets repeat them across the 12 edges)."""
        if self.rule is None:
            raise ValueError(f"method {self.method!r} has no resistance-aware rule")
        mask = 0xFFFF  # the core's inputs are 16-bit: one int64 key per point
        keys = (period.ravel() & mask) << 32 | (bus.ravel() & mask) << 16 | (current.ravel() & mask)
        unique, inverse = np.unique(keys, return_inverse=True)
        batch = reference_batch(self.rule, unique >> 32, (unique >> 16) & mask, unique & mask)
        return ReferenceBatch(
            *(getattr(batch, f.name)[inverse.ravel()] for f in fields(ReferenceBatch))
        )

    def duties(
        self, period: Ints, bus: Ints, main: Ints
    ) -> tuple[Floats, Floats, npt.NDArray[np.bool_]]:
        """Exact (D_on, D_off) in counts of the paper's methods, clamped to [0, P] as a
        duty must be, and the high-speed segment. `bus` is the saturated bus code."""
        emf, u_d = self.emf_and_bus(period, bus)
        high = self.high_speed(period, bus).astype(bool)
        p = float(self.period_counts)
        if self.method == "improved":
            on = np.where(high, self.on_high(emf, u_d), self.on_low(emf, u_d))  # type: ignore[operator]
            off = np.where(high, self.off_high(emf, u_d), self.off_low(emf, u_d))  # type: ignore[operator]
            on, off = on * p, off * p
        else:
            on = np.minimum(main, self.period_counts).astype(np.float64)
            if self.method == "conventional":
                off = self.off_conventional(emf, u_d, on / p) * p  # type: ignore[operator]
            else:
                off = np.zeros_like(on)
        return np.clip(on, 0.0, p), np.clip(off, 0.0, p), high

    def commutation_time(
        self, period: Ints, bus: Ints, current: Ints, on_counts: Ints, off_counts: Ints
    ) -> tuple[Floats, Floats]:
        """Eq. 20 at the given duties, in Hall ticks, before saturation (inf where the
        turn-off current never reaches zero), and its denominator W in counts."""
        emf, u_d = self.emf_and_bus(period, bus)
        p = float(self.period_counts)
        i_amps = (current - self.current_offset).astype(np.float64) * float(self.amps_per_code)
        d_on, d_off = on_counts / p, off_counts / p
        w_volts = self.time_denominator(emf, u_d, d_on, d_off)  # type: ignore[operator]
        w_counts = w_volts * 2 * p / u_d
        with np.errstate(divide="ignore", invalid="ignore"):
            seconds = 3 * i_amps * float(self.inductance) / w_volts
        ticks = np.where(w_counts > 0, seconds * float(self.hall_clock_hz), np.inf)
        for k in np.flatnonzero(np.abs(w_counts) < 1e-6):
            ticks.flat[k], w_counts.flat[k] = self._exact_time(
                int(period.flat[k]),
                int(bus.flat[k]),
                int(current.flat[k]),
                int(on_counts.flat[k]),
                int(off_counts.flat[k]),
            )
        return ticks, w_counts

    def _exact_time(
        self, period: int, bus: int, current: int, on: int, off: int
    ) -> tuple[float, float]:
        emf = self.k_e * self.speed_per_tick / period
        u_d = self.volts_per_code * bus
        p = self.period_counts
        w_volts = u_d * (1 + Fraction(on, p) - 2 * Fraction(off, p)) - 2 * emf
        w_counts = w_volts * 2 * p / u_d
        if w_counts <= 0:
            return float("inf"), float(w_counts)
        i_amps = (current - self.current_offset) * self.amps_per_code
        return float(3 * i_amps * self.inductance / w_volts * self.hall_clock_hz), float(w_counts)


@dataclass(frozen=True)
class Expected:
    """What the core must return for arrays of inputs (duties exact, not rounded)."""

    turn_on: Floats  # counts, 0 in the safe state
    turn_off: Floats
    turn_on_switch: Ints
    turn_off_switch: Ints
    sector: Ints
    flags: Ints  # every flag but FLAG_TIME_CLAMPED, which depends on t_com
    active: npt.NDArray[np.bool_]  # a commutation is applied (not the safe state)
    bus: Ints  # the saturated bus code the duties and t_com were evaluated at
    rule: ReferenceBatch | None  # improved_r: the rule at every point (x_c, S, flags)


def expected(
    model: ExactModel,
    hall: Ints,
    previous: Ints,
    period: Ints,
    bus: Ints,
    current: Ints,
    main: Ints,
) -> Expected:
    n = hall.size
    edge_on = np.full(64, NO_SWITCH, dtype=np.int64)
    edge_off = np.full(64, NO_SWITCH, dtype=np.int64)
    for a in range(8):
        for b in range(8):
            edge = model.edge(a, b)
            if edge is not None:
                edge_on[a << 3 | b], edge_off[a << 3 | b] = model.edge_switches[edge]
    sector_of = np.array([model.sector_of(c) for c in range(8)] + [INVALID_SECTOR], dtype=np.int64)
    codes_ok = (hall <= 7) & (previous <= 7)
    index = np.where(codes_ok, (previous << 3) | hall, 0)
    valid = codes_ok & (edge_on[index] != NO_SWITCH)
    sector = sector_of[np.where(codes_ok, hall, 8)]
    saturated_bus = np.clip(bus, model.bus_min, model.bus_max)
    unsafe = (period < model.period_min) | (bus > model.bus_max)
    active = valid & ~unsafe
    batch = None
    if model.rule is not None:
        batch = model.rule_batch(np.maximum(period, 1), saturated_bus, current)
        on, off, high = batch.on_exact, batch.off_exact, batch.total < model.period_counts
    else:
        on, off, high = model.duties(np.maximum(period, 1), saturated_bus, main)
    i_code = current - model.current_offset
    out_of_range = (
        (bus < model.bus_min)
        | (period > model.period_max)
        | (i_code < 0)
        | (i_code > model.current_code_max)
    )
    if uses_main_duty(model.method):
        out_of_range |= main > model.period_counts
    flags = np.where(out_of_range, FLAG_INPUT_SATURATED, 0) | np.where(high, FLAG_HIGH_SPEED, 0)
    if model.method == "conventional":
        flags |= np.where(
            model.fail_area(
                np.maximum(period, 1), saturated_bus, np.minimum(main, model.period_counts)
            ),
            FLAG_FAIL_AREA_CLAMPED,
            0,
        )
    if batch is not None:
        flags |= np.where(
            (batch.flags & (RULE_CANNOT_HOLD | RULE_ABOVE_BUS)) != 0, FLAG_FAIL_AREA_CLAMPED, 0
        )
    flags = np.where(active, flags, np.where(valid, FLAG_INPUT_SATURATED, FLAG_INVALID_HALL))
    zero = np.zeros(n)
    return Expected(
        turn_on=np.where(active, on, zero),
        turn_off=np.where(active, off, zero),
        turn_on_switch=np.where(active, edge_on[index], NO_SWITCH),
        turn_off_switch=np.where(active, edge_off[index], NO_SWITCH),
        sector=sector,
        flags=flags.astype(np.int64),
        active=active,
        bus=saturated_bus,
        rule=batch,
    )


def time_interval(
    model: ExactModel,
    fx: FixedPointDesign,
    period: npt.NDArray[np.int64],
    bus: npt.NDArray[np.int64],
    current: npt.NDArray[np.int64],
    w_counts: npt.NDArray[np.float64],
) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]:
    """Unsaturated commutation time the design allows: [lo, hi] ticks (hi may be inf).

    The firmware computes round(tn i / W_q) with |tn - K_G 2^f / B| <= e_g and
    |W_q - W 2^f| <= e_x; K_G 2^f i / B = 6 I L f_hall P 2^f / U_d is Eq. 20's numerator
    in these units (3 I L / W_volts with W_volts = W U_d / (2P)).
    """
    scale = 2.0**fx.x_frac_bits
    p = model.period_counts
    i_amps = (current - model.current_offset) * float(model.amps_per_code)
    u_d = bus * float(model.volts_per_code)
    a = 6 * i_amps * float(model.inductance) * float(model.hall_clock_hz) * p * scale / u_d
    spread = (current - model.current_offset) * float(fx.time_numerator_error)
    e_x = float(fx.x_q_error)
    w_lo, w_hi = w_counts * scale - e_x, w_counts * scale + e_x
    with np.errstate(divide="ignore", invalid="ignore"):
        lo = np.where(w_hi > 0, np.floor((a - spread) / w_hi + 0.5), np.inf)
        hi = np.where(w_lo > 0, np.floor((a + spread) / w_lo + 0.5), np.inf)
    return lo - SLACK, hi + SLACK


def operating_codes(spec: Spec, sc: Scaling) -> tuple[int, int, int]:
    """Bus code at the nominal voltage, current code at the nominal braking current and
    the first operating point's main duty in counts: the inputs a check holds fixed."""
    bus = round(spec.inverter.bus_voltage_nominal_v / sc.volts_per_bus_code)
    current = sc.current_offset_code + round(
        spec.controller.braking_current_nominal_a / sc.amps_per_current_code
    )
    duty = round(spec.operating_points[0].main_duty * sc.period_counts)
    return int(bus), int(current), int(duty)


def build_model(spec: Spec, derivation: Derivation, sc: Scaling) -> ExactModel:
    rule = derivation["18"]
    mods = "numpy"
    args = (s.E, s.U_d)
    t_com = sp.together(derivation["20"].row(""))
    numerator, denominator = sp.fraction(t_com)
    # Eq. 20 = 3 I L / W: W is the denominator with the numerator's sign moved into it.
    coefficient = sp.simplify(numerator / (s.I * s.L))
    if coefficient not in (3, -3):
        raise ValueError(f"Eq. 20 is not 3 I L / W: {t_com}")
    time_denominator = denominator if coefficient == 3 else -denominator
    # Boundary n_b = c U_d from Eq. 18's row: high <=> 10 f / (pp T) > c B vpc.
    boundary = sp.Rational(
        rule.row("boundary_speed").subs(
            {s.U_d: 1, s.k_e: _q(spec.motor.back_emf_constant_v_per_rpm)}
        )
    )
    speed_per_tick = Fraction(10) * _fraction(sc.hall_clock_hz) / sc.pole_pairs
    lhs = speed_per_tick / (_fraction(boundary) * _fraction(sc.volts_per_bus_code))
    switches = {}
    for direction in ("forward", "reverse"):
        for sector in range(6):
            e = derivation.switching.edge_into(sector, direction)
            switches[(direction, sector)] = (
                int(e.modulated_on[1:]) - 1,
                int(e.modulated_off[1:]) - 1,
            )
    method = spec.controller.method
    return ExactModel(
        rule=rule_constants(spec, sc) if method == "improved_r" else None,
        method=method,
        period_counts=sc.period_counts,
        hall_sequence=tuple(spec.hall.sequence),
        edge_switches=switches,
        period_min=sc.period_min_ticks,
        period_max=sc.period_max_ticks,
        bus_min=sc.bus_code_min,
        bus_max=sc.bus_code_max,
        current_offset=sc.current_offset_code,
        current_code_max=sc.current_code_max,
        boundary_lhs=lhs.numerator,
        boundary_rhs=lhs.denominator,
        speed_per_tick=speed_per_tick,
        volts_per_code=_fraction(sc.volts_per_bus_code),
        amps_per_code=_fraction(sc.amps_per_current_code),
        k_e=Fraction(spec.motor.back_emf_constant_v_per_rpm),
        inductance=Fraction(spec.motor.phase_inductance_h),
        hall_clock_hz=_fraction(sc.hall_clock_hz),
        on_high=sp.lambdify(args, rule.row("on_high"), mods),
        off_high=sp.lambdify(args, rule.row("off_high"), mods),
        on_low=sp.lambdify(args, rule.row("on_low"), mods),
        off_low=sp.lambdify(args, rule.row("off_low"), mods),
        off_conventional=sp.lambdify((s.E, s.U_d, s.D_on), derivation["16"].row(""), mods),
        time_denominator=sp.lambdify((s.E, s.U_d, s.D_on, s.D_off), time_denominator, mods),
    )


def _q(value: Fraction) -> sp.Rational:
    return sp.Rational(value.numerator, value.denominator)

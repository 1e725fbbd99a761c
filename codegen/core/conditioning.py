"""Input conditioning every method shares, as IR: the limits and the current's offset.

Each input of the core is a uint32_t in C, so every value of that type must give a
defined result. The conditioning saturates what the arithmetic cannot take (a Hall
period above the counter, an ADC code above the converter's full scale) and flags
what lies outside the spec's ranges. Range edges are exact: a code is in range when
its exact physical value is (the spec's rationals decide, never a rounded offset).

The current sensor's zero is at `offset` codes, a rational that need not be whole
(0.5 V of a 3.0 V reference is 682.667 codes of 4096). The core carries the current as

    i_m = m C - OFFSET_M,   OFFSET_M = round(m offset)

so that i_m / m is the offset-removed current in codes: exact when m offset is whole
(m = the offset's denominator when it is small), else within 1/(2m) code. m is the
method design's choice (`CurrentFormat`), made against its accuracy target.
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction

import sympy as sp

from codegen.abi import TIMING, flag_const, value_const
from codegen.dead_time import COMMUTATION_END_ALLOWANCE_S
from codegen.fixedpoint.scaling import Scaling
from codegen.ir.nodes import (
    Expr,
    IBin,
    IConst,
    SAssign,
    SIf,
    SLet,
    SOrAssign,
    SReturn,
    SStruct,
    Stmt,
    SVar,
    cast,
    cmp,
    const,
    div,
    fld,
    lor,
    minimum,
    mul,
    sub,
    var,
)
from codegen.ir.types import I32, U16, U32


def _fraction(value: sp.Rational | Fraction | int) -> Fraction:
    r = sp.Rational(value)
    return Fraction(int(r.p), int(r.q))


@dataclass(frozen=True)
class CoreLimits:
    """The spec's limits as integer constants (public: the header defines them)."""

    period_counts: IConst  # P, TIM1 counts per PWM period
    period_min: IConst  # the Hall period at speed_max
    period_max: IConst  # the Hall period at speed_min
    period_cap: IConst  # the Hall counter's range
    #: a commutation ends at least this many Hall ticks before its sector's end
    period_guard: IConst
    period_never: IConst
    bus_min: IConst
    bus_max: IConst
    adc_max: IConst  # the ADC's full-scale code
    current_low: IConst  # raw codes of the braking-current range
    current_high: IConst
    #: k of the sector-shortening margin ceil(T / 2^k) (None: no margin)
    margin_shift: int | None = None

    def latest_end(self, period: Expr) -> Expr:
        """The latest commutation end in a sector of `period` Hall ticks: the guard and
        the margin ceil(T / 2^k) before its end, T - ceil(T / 2^k) - G, as
        T (2^k - 1) / 2^k - G: a product by a constant, a shift and a subtraction, each
        a function of T alone, so that an interval analysis (the IR's, EVA's) bounds it
        at T's ends (T - ((T + c) >> k), one instruction fewer, holds T twice: EVA
        raised an unsigned-overflow alarm on it), and a division by the constant 2^k
        (the compiler shifts), from which WP proves t + G <= T (it timed out on the
        shift's bit-level model)."""
        k = self.margin_shift
        if k is None:
            return sub(period, self.period_guard)
        return sub(div(mul(period, const(2**k - 1)), const(2**k)), self.period_guard)

    @property
    def public(self) -> tuple[IConst, ...]:
        return (
            self.period_counts,
            self.period_min,
            self.period_max,
            self.period_cap,
            self.period_guard,
            self.bus_min,
            self.bus_max,
            self.adc_max,
            self.current_low,
            self.current_high,
        )


def core_limits(spec: object, sc: Scaling) -> CoreLimits:
    from codegen.spec_model import Spec

    assert isinstance(spec, Spec)
    volts = float(sc.volts_per_bus_code)
    amps = float(sc.amps_per_current_code)
    offset = float(sc.current_offset_exact)
    return CoreLimits(
        period_counts=IConst(
            U32,
            sc.period_counts,
            "BLDC_PWM_PERIOD_COUNTS",
            doc="TIM1 counts per PWM period: duty 1",
        ),
        period_min=IConst(
            U32,
            sc.period_min_ticks,
            "BLDC_PERIOD_MIN_TICKS",
            doc=f"{float(spec.controller.speed_max_rpm):g} rpm reads {sc.period_min_ticks} or more"
            " (whole ticks): a shorter period is over-speed",
        ),
        period_max=IConst(
            U32,
            sc.period_max_ticks,
            "BLDC_PERIOD_MAX_TICKS",
            doc=f"{float(spec.controller.speed_min_rpm):g} rpm reads {sc.period_max_ticks} or less"
            " (whole ticks): a longer period is flagged",
        ),
        period_cap=IConst(
            U32,
            sc.period_cap_ticks,
            "BLDC_PERIOD_CAP_TICKS",
            doc="the Hall counter's range: longer periods saturate",
        ),
        period_guard=IConst(
            U32,
            sc.commutation_guard_ticks,
            "BLDC_COMMUTATION_GUARD_TICKS",
            doc=f"a commutation ends at least this long before its sector does: dead time"
            f" {float(spec.inverter.dead_time_s) * 1e6:g} us + {float(COMMUTATION_END_ALLOWANCE_S) * 1e6:g} us"
            " of the end's latency (the next edge switches on the other switch of the leg"
            " the end switched off) + one current sample (a PWM period and the ADC's"
            " injected sequence: the braking-current loop samples between commutations)",
        ),
        period_never=value_const("PERIOD_NEVER"),
        bus_min=IConst(
            U32,
            sc.bus_code_min,
            "BLDC_BUS_CODE_MIN",
            doc=f"{float(spec.inverter.bus_voltage_min_v):g} V ({sc.bus_code_min * volts:.4g} V)",
        ),
        bus_max=IConst(
            U32,
            sc.bus_code_max,
            "BLDC_BUS_CODE_MAX",
            doc=f"{float(spec.inverter.bus_voltage_max_v):g} V ({sc.bus_code_max * volts:.4g} V): above it over-voltage",
        ),
        adc_max=IConst(
            U32,
            sc.adc_full_scale - 1,
            "BLDC_ADC_CODE_MAX",
            doc=f"{spec.adc.bits}-bit ADC full scale",
        ),
        current_low=IConst(
            U32,
            sc.current_code_low,
            "BLDC_CURRENT_CODE_LOW",
            doc=f"first code at or above {float(spec.controller.braking_current_min_a):g} A "
            f"({(sc.current_code_low - offset) * amps:.4g} A)",
        ),
        current_high=IConst(
            U32,
            sc.current_code_high,
            "BLDC_CURRENT_CODE_HIGH",
            doc=f"last code at or below {float(spec.controller.braking_current_max_a):g} A "
            f"({(sc.current_code_high - offset) * amps:.4g} A)",
        ),
        margin_shift=sc.sector_margin_shift,
    )


@dataclass(frozen=True)
class CurrentFormat:
    """i_m = m C - round(m offset): the current in 1/m codes, offset removed."""

    scale: int  # m
    offset_exact: Fraction  # offset in codes

    @property
    def offset_q(self) -> IConst:
        exact = self.offset_exact * self.scale
        value = int(exact + Fraction(1, 2)) if exact >= 0 else -int(-exact + Fraction(1, 2))
        return IConst(
            I32,
            value,
            "CURRENT_OFFSET_Q",
            exact=exact,
            doc=f"zero current: {float(self.offset_exact):.6g} codes x {self.scale}"
            + ("" if exact == value else f" (exact {float(exact):.6g})"),
        )

    @property
    def scale_const(self) -> IConst:
        return IConst(U32, self.scale, "CURRENT_SCALE", doc="current in 1/CURRENT_SCALE codes")

    @property
    def is_exact(self) -> bool:
        return (self.offset_exact * self.scale).denominator == 1


def current_formats(sc: Scaling, max_bits: int = 8) -> list[CurrentFormat]:
    """Candidate scales: the offset's own denominator when small (exact), then 2^g."""
    offset = _fraction(sc.current_offset_exact)
    out = []
    if offset.denominator <= 1 << max_bits:
        out.append(CurrentFormat(offset.denominator, offset))
    out += [
        CurrentFormat(1 << g, offset) for g in range(max_bits + 1) if (1 << g) != offset.denominator
    ]
    return out


def flag_if(cond: Expr, flag: str, comment: str = "") -> SIf:
    return SIf(cond, (SOrAssign("flags", flag_const(flag)),), comment=comment)


def current_statements(
    limits: CoreLimits, fmt: CurrentFormat, current_adc: Expr
) -> tuple[Stmt, ...]:
    """Defines `current` (int32, 1/m codes): the ADC code saturated to the converter's
    range, range flag from the exact raw limits, offset removed."""
    out_of_range: Expr = cmp(">", current_adc, limits.current_high)
    if limits.current_low.value > 0:
        out_of_range = lor(cmp("<", current_adc, limits.current_low), out_of_range)
    scaled = (
        mul(var("current_code", U32), fmt.scale_const)
        if fmt.scale > 1
        else var("current_code", U32)
    )
    return (
        SLet(
            "current_code",
            minimum(current_adc, limits.adc_max),
            "above the ADC's range: full scale",
        ),
        flag_if(out_of_range, "INPUT_SATURATED", "outside the braking-current range"),
        SLet(
            "current",
            sub(cast(scaled, I32), fmt.offset_q),
            f"I in 1/{fmt.scale} codes, offset removed"
            if fmt.scale > 1
            else "I in codes, offset removed",
        ),
    )


def period_statements(limits: CoreLimits, period_ticks: Expr) -> tuple[Stmt, ...]:
    """Defines `period`: the Hall period saturated to the counter's range."""
    return (
        SLet(
            "period",
            minimum(period_ticks, limits.period_cap),
            "the proven range: the full Hall counter",
        ),
    )


def zero(ctype: object = U32) -> IConst:
    return const(0, ctype)  # type: ignore[arg-type]


def bus_code_statements(limits: CoreLimits) -> tuple[Stmt, ...]:
    """Defines `code` (the bus code saturated to the spec's range), `period_min` (the
    shortest Hall period braking is controlled at: none above the range, over-voltage)
    and `flags` (INPUT_SATURATED outside the range): the start of every method's
    `bldc_bus_condition`."""
    code = var("code", U32)
    return (
        SVar("code", U32, var("bus_code", U32)),
        SVar("period_min", U32, limits.period_min),
        SVar("flags", U32, const(0)),
        SIf(
            cmp(">", code, limits.bus_max),
            (
                SAssign("code", limits.bus_max),
                SAssign(
                    "period_min",
                    limits.period_never,
                    "over-voltage: every edge goes to the safe state",
                ),
                SAssign("flags", flag_const("INPUT_SATURATED")),
            ),
            (
                SIf(
                    cmp("<", code, limits.bus_min),
                    (
                        SAssign("code", limits.bus_min),
                        SAssign("flags", flag_const("INPUT_SATURATED")),
                    ),
                ),
            ),
        ),
    )


def safe_state_statements(limits: CoreLimits, period: Expr) -> SIf:
    """Return the safe state's timing (no switch applied: period_min never reached, the
    compares and the time 0, INPUT_SATURATED) when `period` is shorter than the bus
    state's `period_min`: above the top speed, or over-voltage."""
    return SIf(
        cmp("<", period, fld("bus", "period_min", U32)),
        (
            SStruct(
                "safe",
                TIMING,
                (
                    ("period_min", limits.period_never),
                    ("turn_on_compare", const(0, U16)),
                    ("turn_off_compare", const(0, U16)),
                    ("commutation_ticks", const(0, U16)),
                    (
                        "flags",
                        cast(IBin(U32, "|", var("flags", U32), flag_const("INPUT_SATURATED")), U16),
                    ),
                ),
            ),
            SReturn(var("safe", U32)),
        ),
        comment="above the top speed or over-voltage: braking is no longer controlled",
    )


def latest_statement(limits: CoreLimits, period: Expr) -> SLet:
    """Defines `latest`: the latest commutation end in a sector of `period` ticks."""
    return SLet(
        "latest",
        limits.latest_end(period),
        "the latest end: the guard and the sector-shortening margin before the sector's"
        " end (positive from the minimum period on), so the next edge, up to"
        " hall.sector_shortening early, switches the other switch of the leg on at"
        " least the dead time after this end switched its partner off",
    )

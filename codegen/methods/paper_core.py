"""The arithmetic the paper's methods share (none, conventional, improved), as IR.

Per bus code B (`bldc_bus_condition`, recomputed only when the bus voltage changes):

    x_numerator       = round(N_X / B),  N_X = round(K_X 2^f)          Eqs. 3, 9
    high_speed_period = ceil(C / B),     C = ceil(K_X / P)             Eq. 18's cut-off
    time_numerator    = round(N_G / B),  N_G = round(K_G 2^f / m)      Eq. 20

with X = P 4E/U_d = K_X / (T B) in TIM1 counts and t_com f_hall = K_G I_code / (B W).
Per Hall interval T (`bldc_commutation_timing`): one divide for the speed and one for
Eq. 20,

    X_q = round(x_numerator / T)                       X in Q(f) counts
    X_c = round(X_q / 2^f)                             X in counts
    duties: the method's rule (Eq. 16 or 18) from X_c, clamped to [0, P]
    W_q = (2P + 2 C_on - 4 C_off) 2^f - X_q            Eq. 20's denominator, Q(f)
    t   = round(time_numerator i_m / W_q), saturated to [0, T]

The segment decision T < ceil(C/B) is exactly T B < K_X / P, that is 4E > U_d: an
integer comparison, no rounding. The method folder supplies only its duty rule
(`DutyRule`); the formats f and m are chosen by `design.py` from the spec's targets.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from fractions import Fraction

from codegen.abi import TIMING, flag_const
from codegen.core.conditioning import (
    CoreLimits,
    CurrentFormat,
    bus_code_statements,
    current_statements,
    flag_if,
    latest_statement,
    period_statements,
    safe_state_statements,
)
from codegen.ir.nodes import (
    Expr,
    Function,
    IConst,
    ILongDiv,
    IVar,
    Param,
    SAssign,
    SIf,
    SLet,
    SOrAssign,
    SReturn,
    SStruct,
    Stmt,
    StructField,
    StructType,
    SVar,
    add,
    cast,
    cmp,
    const,
    div,
    fld,
    lor,
    maximum,
    minimum,
    mul,
    round_shr,
    select,
    sub,
    var,
)
from codegen.ir.types import I32, U16, U32, U64
from codegen.ir.walk import all_exprs


@dataclass(frozen=True)
class PaperConstants:
    """The exact constants of Eqs. 9/18/20 at one spec (from codegen.fixedpoint.scaling)."""

    k_x: Fraction  # X = K_X / (T B), counts
    k_g: Fraction  # t_com f_hall = K_G I_code / (B W)
    period_counts: int


@dataclass(frozen=True)
class PaperFormats:
    x_frac_bits: int  # f
    current: CurrentFormat


@dataclass(frozen=True)
class DutyContext:
    """What a duty rule may read: IR expressions of the timing function's locals."""

    limits: CoreLimits
    constants: PaperConstants
    formats: PaperFormats
    x_q: Expr  # X in Q(f) counts (uint32)
    x_c: Expr  # X in counts (int32)
    high_speed: Expr  # comparison: Eq. 18's high-speed segment
    period: Expr  # Hall period, saturated to the counter (uint32)
    bus_code: Expr  # saturated bus code (uint32)
    main_duty_counts: Expr  # the raw parameter (uint32)


@dataclass(frozen=True)
class DutyRule:
    """A paper method's duties: statements that assign the int32 locals `on` and `off`
    (TIM1 counts, within [0, P]) and may raise flags."""

    method: str
    uses_main_duty: bool
    statements: Callable[[DutyContext], tuple[Stmt, ...]]
    #: header text: the rule and its flags, one line each
    doc: tuple[str, ...]


BUS = StructType(
    "bldc_bus_t",
    "Bus",
    (
        StructField("x_numerator", U32, "round(N_X / B): X = x_numerator / T in Q(f) counts"),
        StructField("high_speed_period", U32, "ceil(C / B): Eq. 18's high-speed segment below it"),
        StructField("time_numerator", I32, "round(N_G / B): Eq. 20's numerator per unit current"),
        StructField(
            "period_min", U32, "BLDC_PERIOD_MIN_TICKS, or BLDC_PERIOD_NEVER when over-voltage"
        ),
        StructField("bus_code", U32, "the saturated bus code B"),
        StructField("flags", U32, "BLDC_FLAG_INPUT_SATURATED when the code was saturated"),
    ),
    "What the Hall-edge step needs of the bus voltage (see the formats above)",
)


def numerator(name: str, exact: Fraction, doc: str) -> IConst:
    value = int(exact + Fraction(1, 2))
    return IConst(U64, value, name, exact=exact, doc=doc)


def paper_numerators(c: PaperConstants, fmt: PaperFormats) -> tuple[IConst, IConst, IConst]:
    scale = 1 << fmt.x_frac_bits
    n_x = numerator(
        "N_X",
        c.k_x * scale,
        f"round(K_X 2^{fmt.x_frac_bits}), K_X = {float(c.k_x):.6e} (Eqs. 3, 9)",
    )
    n_g = numerator(
        "N_G",
        c.k_g * scale / fmt.current.scale,
        f"round(K_G 2^{fmt.x_frac_bits} / {fmt.current.scale}), K_G = {float(c.k_g):.6e} (Eq. 20)",
    )
    cut = -(-c.k_x.numerator // (c.k_x.denominator * c.period_counts))  # ceil(K_X / P)
    high_speed_tb = IConst(
        U32, cut, "HIGH_SPEED_TB", doc="ceil(K_X / P): 4E > U_d <=> T B < it (Eq. 18)"
    )
    return n_x, n_g, high_speed_tb


def bus_condition_function(limits: CoreLimits, c: PaperConstants, fmt: PaperFormats) -> Function:
    n_x, n_g, high_speed_tb = paper_numerators(c, fmt)
    code = var("code", U32)
    return Function(
        c_name="bldc_bus_condition",
        py_name="bus_condition",
        params=(Param("bus_code", U32),),
        returns=BUS,
        doc="Saturate a bus code and precompute its reciprocals (pure, reentrant)",
        body=(
            *bus_code_statements(limits),
            SStruct(
                "bus",
                BUS,
                (
                    ("x_numerator", ILongDiv(U32, n_x, code)),
                    ("high_speed_period", div(high_speed_tb, code, "ceil")),
                    ("time_numerator", cast(ILongDiv(U32, n_g, code), I32)),
                    ("period_min", var("period_min", U32)),
                    ("bus_code", code),
                    ("flags", var("flags", U32)),
                ),
            ),
            SReturn(var("bus", U32)),
        ),
    )


def timing_function(
    limits: CoreLimits, c: PaperConstants, fmt: PaperFormats, rule: DutyRule, bus: StructType = BUS
) -> Function:
    f = fmt.x_frac_bits
    period = var("period", U32)
    latest = var("latest", U32)
    x_q, x_c = var("x_q", U32), var("x_c", I32)
    current = var("current", I32)
    on, off = var("on", I32), var("off", I32)
    p = cast(limits.period_counts, I32)
    ctx = DutyContext(
        limits=limits,
        constants=c,
        formats=fmt,
        x_q=x_q,
        x_c=x_c,
        high_speed=cmp("!=", var("high_speed", U32), const(0)),
        period=period,
        bus_code=fld("bus", "bus_code", U32),
        main_duty_counts=var("main_duty_counts", U32),
    )
    duties = rule.statements(ctx)
    # X in counts where the rule uses it (the main-duty rule does not: an unused local
    # fails -Werror=unused-variable)
    uses_x_c = any(isinstance(e, IVar) and e.name == "x_c" for e in all_exprs(duties))
    w_q = var("w_q", I32)
    scale = const(1 << f, I32)
    duty_sum = sub(add(mul(const(2, I32), p), mul(const(2, I32), on)), mul(const(4, I32), off))
    quotient = var("t", I32)
    eq20 = (
        SLet("t", div(mul(fld("bus", "time_numerator", I32), current), w_q, "nearest"), "Eq. 20"),
        SAssign(
            "ticks",
            cast(maximum(quotient, const(0, I32)), U32),
            "a negative current: nothing to commutate",
        ),
        # Saturated without a branch (a flag OR and a select): from flash every branch
        # fetches its target.
        flag_if(cmp(">", var("ticks", U32), latest), "TIME_CLAMPED"),
        SAssign("ticks", minimum(var("ticks", U32), latest), "at most the sector, less the guard"),
    )
    never = (
        SIf(
            cmp(">", current, const(0, I32)),
            (SAssign("ticks", latest), SOrAssign("flags", flag_const("TIME_CLAMPED"))),
            comment="unless there is no current to commutate",
        ),
    )
    body: tuple[Stmt, ...] = (
        SVar("flags", U32, fld("bus", "flags", U32)),
        *period_statements(limits, var("period_ticks", U32)),
        safe_state_statements(limits, period),
        flag_if(
            cmp(">", period, limits.period_max),
            "INPUT_SATURATED",
            "below the minimum speed: still exact",
        ),
        *current_statements(limits, fmt.current, var("current_adc", U32)),
        latest_statement(limits, period),
        SLet(
            "x_q",
            div(fld("bus", "x_numerator", U32), period, "nearest"),
            f"X = P 4E/U_d in Q{f} counts (Eqs. 3, 9)",
        ),
        *((SLet("x_c", cast(round_shr(x_q, f), I32), "X in counts"),) if uses_x_c else ()),
        SLet(
            "high_speed",
            select(cmp("<", period, fld("bus", "high_speed_period", U32)), const(1), const(0)),
            "Eq. 18: 4E > U_d, exactly",
        ),
        flag_if(ctx.high_speed, "HIGH_SPEED"),
        SVar("on", I32, const(0, I32)),
        SVar("off", I32, const(0, I32)),
        *duties,
        SLet(
            "w_q",
            sub(mul(duty_sum, scale), cast(x_q, I32)),
            "Eq. 20's denominator at the emitted duties, Q{f}".replace("{f}", str(f)),
        ),
        SVar("ticks", U32, const(0)),
        SIf(
            cmp("<=", w_q, const(0, I32), exact=False),
            never,
            eq20,
            comment="the turn-off current never reaches zero: the whole sector",
        ),
        SStruct(
            "timing",
            TIMING,
            (
                ("period_min", fld("bus", "period_min", U32)),
                ("turn_on_compare", cast(on, U16)),
                ("turn_off_compare", cast(off, U16)),
                ("commutation_ticks", cast(var("ticks", U32), U16)),
                ("flags", cast(var("flags", U32), U16)),
            ),
        ),
        SReturn(var("timing", U32)),
    )
    return Function(
        c_name="bldc_commutation_timing",
        py_name="commutation_timing",
        params=(
            Param("bus", struct=bus, const=True, doc="from bldc_bus_condition()"),
            Param("period_ticks", U32),
            Param("current_adc", U32),
            Param("main_duty_counts", U32),
        ),
        returns=TIMING,
        doc="Duties and commutation time (pure, reentrant): period in Hall ticks, current as its "
        "ADC code, main duty in TIM1 counts; any uint32_t value of each is allowed",
        body=body,
    )


def saturated_main_duty(ctx: DutyContext) -> tuple[Stmt, ...]:
    """`main_duty`: the controller's duty, saturated to one PWM period (flagged)."""
    p = ctx.limits.period_counts
    return (
        SLet("main_duty", minimum(ctx.main_duty_counts, p), "duty above 1: saturated"),
        flag_if(cmp(">", ctx.main_duty_counts, p), "INPUT_SATURATED"),
    )


def fail_area_condition(ctx: DutyContext) -> Expr:
    """Eq. 16's D_off outside [0, 1], exactly: X > 2P - M or X < P - M with X = K_X/(T B),
    i.e. K_X_num > T B K_X_den (2P - M) or K_X_num < T B K_X_den (P - M)."""
    k = ctx.constants.k_x
    num = IConst(U64, k.numerator, "K_X_NUM", doc="K_X = X T B exactly: numerator")
    den = IConst(U64, k.denominator, "K_X_DEN", doc="K_X denominator")
    p = ctx.limits.period_counts
    main = var("main_duty", U32)
    two_p_minus = cast(sub(mul(const(2), p), main), U64)
    p_minus = cast(sub(p, main), U64)
    tb = mul(cast(mul(ctx.period, ctx.bus_code), U64), den)
    return lor(cmp(">", num, mul(tb, two_p_minus)), cmp("<", num, mul(tb, p_minus)))

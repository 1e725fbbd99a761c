"""The resistance-aware rule's integer arithmetic, as IR (printed to C and Python, proven).

Formats (Qf: value = integer / 2^f), with fc the counts' fraction bits, K the bisection
steps, fu = min(K + 16, 30) the unit functions' fraction bits:

  bus rate, B saturated:
    x_numerator = round(N_X / B)        N_X = round(K_X 2^fc)           long division
    y_numerator = round(N_Y / B)        N_Y = round(K_Y 2^(fc+gy) / m)  long division
  edge, T saturated to the speed range, i = m C - OFFSET_M clamped at 0:
    X   = round(x_numerator / T)        Q fc   one UDIV
    Y   = round(y_numerator i / 2^gy)   Q fc
    A   = round(X (KAPPA i) / 2^fk)     Q fc   KAPPA = round(kappa 2^fk / m)
    RHO = K_RHO T                       Q frho rho = R T_s / L
    S0  = 2P 2^fc + Y - X, S1 = round(X THETA / 2^20), THETA = round(theta/2 2^20)
  bisection over x in Q K on the sign of 2 g(x):
    y = RHO x >> (frho + K - fy)                      Q fy
    psi1, psi2 = 2^16 - interpolated complements      Q16 (octave table, one CLZ)
    e  = 2^fu - min(round(y psi1 / 2^(fy+16-fu)), 2^fu)   e^{-y} = 1 - y psi1
    u1 = round(x psi1 / 2^(K+16-fu)), v2 = round(x (x psi2) / 2^(2K+16-fu))
    S  = S0 + round(S1 x / 2^K); C_on = clamp(S, 0, P 2^fc), C_off = clamp(S - P 2^fc, 0, P 2^fc)
    F2 = 4 C_off - 2 C_on - 2 P 2^fc + X
    2g = 2A e + F2 u1 - X v2                          int64
  result: x_c = the middle of the last bracket (or 1, flagged, when the current does not
  reach zero in the sector); C_on, C_off at S(x_c) rounded to counts; ticks = round(x_c T).

The products whose width depends on the spec (`WIDE_PRODUCTS`) are named locals; the
design proves them once in 64 bits and then prints each in the narrowest type its
proven range allows, so a Cortex-M3 multiplies in 32 bits wherever it can.
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction

import sympy as sp

from codegen.abi import TIMING, flag_const
from codegen.core.conditioning import CoreLimits, CurrentFormat, current_statements, flag_if
from codegen.ir.nodes import (
    Expr,
    Function,
    IAddr,
    IBin,
    IBitLength,
    ICall,
    IConst,
    ILongDiv,
    ILookup,
    IShl,
    IStep,
    Param,
    SAssign,
    SFor,
    SIf,
    SLet,
    SOrAssign,
    SReturn,
    SStruct,
    Stmt,
    StructField,
    StructType,
    SVar,
    Table,
    add,
    cast,
    clamp,
    cmp,
    const,
    div,
    fld,
    land,
    lor,
    maximum,
    minimum,
    mul,
    round_shr,
    select,
    shl,
    shr,
    sub,
    var,
)
from codegen.ir.types import I32, I64, U16, U32, U64, CType
from codegen.methods.improved_r.fixed import THETA_FRAC_BITS, FixedRule
from codegen.methods.improved_r.table import ONE_Q16, grid_point

#: product local -> its signedness; the design picks each one's width from its range
WIDE_PRODUCTS: dict[str, bool] = {
    "x_kappa_i": False,
    "x_theta": False,
    "rho_x": False,
    "y_psi1": False,
    "x_x_psi2": False,
    "s1_x": False,
}
ALL_WIDE: dict[str, CType] = dict.fromkeys(WIDE_PRODUCTS, U64)

BUS = StructType(
    "bldc_bus_t",
    "Bus",
    (
        StructField("x_numerator", U32, "round(N_X / B): X = x_numerator / T in Q(fc) counts"),
        StructField("y_numerator", U32, "round(N_Y / B): Y = y_numerator i / 2^gy"),
        StructField(
            "period_min", U32, "BLDC_PERIOD_MIN_TICKS, or BLDC_PERIOD_NEVER when over-voltage"
        ),
        StructField("bus_code", U32, "the saturated bus code B"),
        StructField("flags", U32, "BLDC_FLAG_INPUT_SATURATED when the code was saturated"),
    ),
    "What the timing step needs of the bus voltage (see the formats above)",
)

EDGE = StructType(
    "bldc_rule_edge_t",
    "RuleEdge",
    (
        StructField("x", I32, "X = 4 P E / U_d, Q(fc) counts"),
        StructField("a2", I32, "2 A, A = 3 P L I / (U_d T_s): the turn-off current at the edge"),
        StructField("rho", U32, "rho = R T_s / L, Q(frho)"),
        StructField("s0", I32, "2P + Y - X: the held duty sum at the edge's EMFs"),
        StructField("s1", I32, "theta X / 2: its growth per sector of commutation"),
    ),
    "Per-edge quantities of the rule (Q(fc) duty counts unless noted)",
)


@dataclass(frozen=True)
class RuleConsts:
    n_x: IConst
    n_y: IConst
    kappa: IConst
    k_rho: IConst
    theta_half: IConst
    period_q: IConst
    unit_q: IConst
    current_high: IConst


def _exact(value: sp.Expr, digits: int = 60) -> Fraction:
    """An exact rational, or a 60-digit one for an irrational (theta)."""
    r = sp.nsimplify(value) if not isinstance(value, sp.Rational) else value
    if isinstance(r, sp.Rational):
        return Fraction(int(r.p), int(r.q))
    return Fraction(str(sp.N(value, digits)))


def rule_consts(rule: FixedRule, current: CurrentFormat) -> RuleConsts:
    c = rule.constants
    fc = rule.counts_frac_bits
    m = current.scale
    i_high = c.current_high
    return RuleConsts(
        n_x=IConst(
            U64,
            rule.n_x.numerator,
            "N_X",
            exact=_exact(c.k_x) * 2**fc,
            doc=f"round(K_X 2^{fc}), K_X = {float(c.k_x):.6e}",
        ),
        n_y=IConst(
            U64,
            rule.n_y.numerator,
            "N_Y",
            exact=_exact(c.k_y) * 2 ** (fc + rule.y_guard_bits) / m,
            doc=f"round(K_Y 2^{fc + rule.y_guard_bits} / {m}), K_Y = {float(c.k_y):.6e}",
        ),
        kappa=IConst(
            U32,
            rule.kappa_q,
            "KAPPA_Q",
            exact=_exact(c.kappa) * 2**rule.kappa_frac_bits / m,
            doc=f"kappa = {float(c.kappa):.6e} in Q{rule.kappa_frac_bits} / {m}: A = kappa i X",
        ),
        k_rho=IConst(
            U32,
            rule.k_rho_q,
            "K_RHO_Q",
            exact=_exact(c.k_rho) * 2**rule.rho_frac_bits,
            doc=f"K_rho = R/(L f_hall) = {float(c.k_rho):.6e} in Q{rule.rho_frac_bits}: rho = K_rho T",
        ),
        theta_half=IConst(
            U32,
            rule.theta_half_q,
            "THETA_HALF_Q",
            exact=_exact(c.ramp_weight) / 2 * 2**THETA_FRAC_BITS,
            doc=f"theta/2 in Q{THETA_FRAC_BITS}, theta = sqrt(2) - 1 = {float(c.ramp_weight):.9f}",
        ),
        period_q=IConst(I32, rule.period_q, "PERIOD_Q", doc=f"P in Q{fc} counts"),
        unit_q=IConst(
            U32, 1 << rule.unit_frac_bits, "UNIT_Q", doc=f"1 in Q{rule.unit_frac_bits} (e, u1, v2)"
        ),
        current_high=IConst(
            I32, i_high, "CURRENT_HIGH", doc=f"largest current in 1/{m} codes (ADC full scale)"
        ),
    )


def psi_table(rule: FixedRule) -> Table:
    t = rule.table
    per = 1 << t.segment_bits
    comments = tuple(
        f"y = {float(grid_point(k, t.segment_bits)):.6g}"
        + (f", octave {k // per}" if k % per == 0 else "")
        for k in range(t.entries)
    )
    return Table(
        "bldc_psi_complement",
        U16,
        tuple(zip(t.complement1, t.complement2, strict=True)),
        comments,
        f"Complements round((1 - psi) 2^16) of psi1(y) = (1 - e^-y)/y and psi2(y) = 2(y - 1 + "
        f"e^-y)/y^2 on octave segments: rows 0..{per - 1} cover [0, 1) in steps of 2^-{t.segment_bits}, "
        f"octave j >= 1 covers [2^(j-1), 2^j) in steps of 2^(j-1-{t.segment_bits}); one closing row. "
        f"Linear interpolation error <= {t.error1:.2e} (psi1), {t.error2:.2e} (psi2). {t.flash_bytes} bytes.",
    )


def bus_condition_function(limits: CoreLimits, k: RuleConsts) -> Function:
    code = var("code", U32)
    return Function(
        c_name="bldc_bus_condition",
        py_name="bus_condition",
        params=(Param("bus_code", U32),),
        returns=BUS,
        doc="Saturate a bus code and precompute its reciprocals (pure, reentrant)",
        body=(
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
            SStruct(
                "bus",
                BUS,
                (
                    ("x_numerator", ILongDiv(U32, k.n_x, code)),
                    ("y_numerator", ILongDiv(U32, k.n_y, code)),
                    ("period_min", var("period_min", U32)),
                    ("bus_code", code),
                    ("flags", var("flags", U32)),
                ),
            ),
            SReturn(var("bus", U32)),
        ),
    )


def _rule_sum(x: Expr, frac_bits: int, width: CType, comment: str) -> tuple[Stmt, Stmt]:
    """total = S0 + round(S1 x / 2^frac_bits): the held duty sum for x (Q frac_bits)."""
    s1 = cast(cast(fld("st", "s1", I32), U32), width)
    return (
        SLet("s1_x", mul(s1, cast(x, width), width)),
        SLet(
            "total",
            add(fld("st", "s0", I32), cast(round_shr(var("s1_x", width), frac_bits), I32)),
            comment,
        ),
    )


def current_remains_function(
    rule: FixedRule, k: RuleConsts, table: Table, widths: dict[str, CType]
) -> Function:
    t = rule.table
    fy, n = t.y_frac_bits, t.segment_bits
    ku, fu = rule.steps, rule.unit_frac_bits
    base_shift = fy - n
    x = var("x", U32)
    y = var("y", U32)
    octave, shift, row, r = var("octave", U32), var("shift", U32), var("row", U32), var("r", U32)
    mask = const((1 << n) - 1)
    psi = []
    body: list[Stmt] = [
        SLet(
            "rho_x",
            mul(
                cast(fld("st", "rho", U32), widths["rho_x"]),
                cast(x, widths["rho_x"]),
                widths["rho_x"],
            ),
        ),
        SLet(
            "y", cast(shr(var("rho_x", widths["rho_x"]), rule.y_shift), U32), f"y = rho x in Q{fy}"
        ),
        SLet("whole", shr(y, fy)),
        SLet(
            "octave",
            select(
                cmp("==", var("whole", U32), const(0)), const(0), IBitLength(U32, var("whole", U32))
            ),
            "table segment: 0 for y < 1, else 32 - CLZ(integer part)",
            split=True,
        ),
        SLet(
            "shift",
            select(
                cmp("==", octave, const(0)), const(base_shift), add(const(base_shift - 1), octave)
            ),
            "fraction bits of y within its row",
        ),
        SLet("row", add(IShl(U32, octave, n), IBin(U32, "&", shr(y, shift), mask))),
        SLet("r", IBin(U32, "&", y, sub(IShl(U32, const(1), shift), const(1)))),
        SLet("half", IShl(U32, const(1), sub(shift, const(1)))),
    ]
    for column in (0, 1):
        name = f"psi{column + 1}"
        step = mul(IStep(U32, table, row, column), r)
        interpolated = shr(add(step, var("half", U32)), shift)
        low = cast(ILookup(U16, table, row, column), U32)
        body.append(
            SLet(
                name,
                sub(const(ONE_Q16), add(low, interpolated)),
                f"psi{column + 1}(y) in Q16, linear interpolation",
            )
        )
        psi.append(var(name, U32))
    psi1, psi2 = psi
    e_shift = fy + 16 - fu
    wide_y = widths["y_psi1"]
    body += [
        SLet("y_psi1", mul(cast(y, wide_y), cast(psi1, wide_y), wide_y)),
        # a local of its own, so that a non-relational analysis (Frama-C's EVA) narrows
        # it in the clamp below as the IR's proof does
        SLet("one_minus_e", round_shr(var("y_psi1", wide_y), e_shift), f"1 - e^-y in Q{fu}"),
        SLet(
            "e",
            cast(
                sub(
                    cast(k.unit_q, wide_y),
                    minimum(var("one_minus_e", wide_y), cast(k.unit_q, wide_y)),
                ),
                I32,
            ),
            f"e^-y = 1 - y psi1 in Q{fu}, kept >= 0 against the table's error",
        ),
        SLet("u1", cast(round_shr(mul(x, psi1), ku + 16 - fu), I32), "x psi1"),
        SLet(
            "x_x_psi2",
            mul(
                cast(x, widths["x_x_psi2"]),
                cast(mul(x, psi2), widths["x_x_psi2"]),
                widths["x_x_psi2"],
            ),
        ),
        SLet(
            "v2",
            cast(round_shr(var("x_x_psi2", widths["x_x_psi2"]), 2 * ku + 16 - fu), I32),
            "x^2 psi2",
        ),
        *_rule_sum(x, ku, widths["s1_x"], "S(x)"),
        SLet("on", clamp(var("total", I32), const(0, I32), k.period_q)),
        SLet("off", clamp(sub(var("total", I32), k.period_q), const(0, I32), k.period_q)),
        SLet(
            "f2",
            add(
                sub(
                    sub(mul(const(4, I32), var("off", I32)), mul(const(2, I32), var("on", I32))),
                    mul(const(2, I32), k.period_q),
                ),
                fld("st", "x", I32),
            ),
            "2F",
        ),
        SLet(
            "twice_g",
            sub(
                add(
                    mul(cast(fld("st", "a2", I32), I64), cast(var("e", I32), I64)),
                    mul(cast(var("f2", I32), I64), cast(var("u1", I32), I64)),
                ),
                mul(cast(fld("st", "x", I32), I64), cast(var("v2", I32), I64)),
            ),
            "2 g(x)",
        ),
        SReturn(select(cmp(">", var("twice_g", I64), const(0, I64)), const(1), const(0))),
    ]
    return Function(
        c_name="bldc_current_remains",
        py_name="current_remains",
        params=(Param("st", struct=EDGE, const=True), Param("x", U32)),
        returns=U32,
        static=True,
        doc="Sign of 2 g(x): the turn-off current after x sectors (Q K) under the pair held at "
        "S(x), g = A e^-rho x + F x psi1(rho x) - X x^2/2 psi2(rho x), F = 2 C_off - C_on - P + X/2. "
        "1 while the current has not yet reached zero",
        body=tuple(body),
    )


def _safe_state(limits: CoreLimits) -> tuple[Stmt, ...]:
    return (
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
    )


def timing_function(
    rule: FixedRule,
    limits: CoreLimits,
    current: CurrentFormat,
    k: RuleConsts,
    remains: Function,
    widths: dict[str, CType],
) -> Function:
    steps = rule.steps
    fc = rule.counts_frac_bits
    measured, period = var("measured", U32), var("period", U32)
    x = var("x", U32)
    i = var("i", U32)
    lo, hi = var("lo", U32), var("hi", U32)
    full = const(1 << steps)
    fraction = var("fraction", U32)
    total = var("total", I32)
    wide_a = widths["x_kappa_i"]
    wide_t = widths["x_theta"]

    def remains_at(point: Expr) -> Expr:
        return cmp("!=", ICall(U32, remains, (IAddr(U32, "st"), point)), const(0))

    body: tuple[Stmt, ...] = (
        SVar("flags", U32, fld("bus", "flags", U32)),
        SLet(
            "measured",
            minimum(var("period_ticks", U32), limits.period_cap),
            "the Hall counter's range",
        ),
        SIf(
            cmp("<", measured, fld("bus", "period_min", U32)),
            _safe_state(limits),
            comment="above the top speed or over-voltage: braking is no longer controlled",
        ),
        flag_if(
            cmp(">", measured, limits.period_max), "INPUT_SATURATED", "below the minimum speed"
        ),
        SLet(
            "period",
            minimum(measured, limits.period_max),
            "the table covers rho up to the slowest speed",
        ),
        *current_statements(limits, current, var("current_adc", U32)),
        SLet(
            "i",
            cast(maximum(var("current", I32), const(0, I32)), U32),
            "negative currents count as 0",
        ),
        SLet("x", div(fld("bus", "x_numerator", U32), period, "nearest"), f"X in Q{fc} counts"),
        SLet(
            "y",
            round_shr(mul(fld("bus", "y_numerator", U32), i), rule.y_guard_bits),
            f"Y = 3 P R I / U_d, Q{fc}",
        ),
        SLet("x_kappa_i", mul(cast(x, wide_a), cast(mul(k.kappa, i), wide_a), wide_a)),
        SLet(
            "a",
            cast(round_shr(var("x_kappa_i", wide_a), rule.kappa_frac_bits), U32),
            "A = kappa i X",
        ),
        SLet("x_theta", mul(cast(x, wide_t), cast(k.theta_half, wide_t), wide_t)),
        SStruct(
            "st",
            EDGE,
            (
                ("x", cast(x, I32)),
                ("a2", mul(const(2, I32), cast(var("a", U32), I32))),
                ("rho", mul(k.k_rho, period)),
                (
                    "s0",
                    sub(
                        add(mul(const(2, I32), k.period_q), cast(var("y", U32), I32)), cast(x, I32)
                    ),
                ),
                ("s1", cast(round_shr(var("x_theta", wide_t), THETA_FRAC_BITS), I32)),
            ),
        ),
        SVar("lo", U32, const(0)),
        SVar("hi", U32, full),
        SFor(
            "step",
            steps,
            (
                SLet("mid", shr(add(lo, hi), 1)),
                SIf(
                    remains_at(var("mid", U32)),
                    (SAssign("lo", var("mid", U32)),),
                    (SAssign("hi", var("mid", U32)),),
                ),
            ),
            invariants=(("lo", 0, 1 << steps), ("hi", 0, 1 << steps)),
            comment="t_com: bisection over x in (0, 1] sectors; g(0) = A >= 0 changes sign once",
        ),
        SVar("fraction", U32, add(lo, hi), f"Q{steps + 1}: the middle of the last bracket"),
        SIf(
            land(cmp("==", hi, full), remains_at(hi)),
            (
                SAssign(
                    "fraction",
                    shl(const(2), steps),
                    "does not finish within the sector: the whole sector",
                ),
                SOrAssign("flags", flag_const("TIME_CLAMPED")),
            ),
        ),
        *_rule_sum(fraction, steps + 1, widths["s1_x"], "S(x_c)"),
        flag_if(
            lor(cmp(">", total, mul(const(2, I32), k.period_q)), cmp("<", total, const(0, I32))),
            "FAIL_AREA_CLAMPED",
            "no duty pair in [0, 1] holds the current",
        ),
        flag_if(
            cmp("<", total, k.period_q),
            "HIGH_SPEED",
            "the turn-off phase off, the turn-on one modulated",
        ),
        SLet("on", cast(clamp(total, const(0, I32), k.period_q), U32)),
        SLet("off", cast(clamp(sub(total, k.period_q), const(0, I32), k.period_q), U32)),
        SLet("scaled", round_shr(mul(fraction, period), steps + 1), "x_c T"),
        SLet("ticks", minimum(var("scaled", U32), measured), "at most the measured period"),
        SStruct(
            "timing",
            TIMING,
            (
                ("period_min", fld("bus", "period_min", U32)),
                ("turn_on_compare", cast(round_shr(var("on", U32), fc), U16)),
                ("turn_off_compare", cast(round_shr(var("off", U32), fc), U16)),
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
            Param("bus", struct=BUS, const=True, doc="from bldc_bus_condition()"),
            Param("period_ticks", U32),
            Param("current_adc", U32),
            Param("main_duty_counts", U32),
        ),
        returns=TIMING,
        doc="Duties and commutation time of the resistance-aware rule (pure, reentrant); any "
        "uint32_t value of each parameter is allowed. The rule holds the current by itself: "
        "the main duty is not used",
        body=body,
    )


def functions(
    rule: FixedRule, limits: CoreLimits, current: CurrentFormat, widths: dict[str, CType]
) -> tuple[Function, Function, Table]:
    k = rule_consts(rule, current)
    table = psi_table(rule)
    remains = current_remains_function(rule, k, table, widths)
    return (
        bus_condition_function(limits, k),
        timing_function(rule, limits, current, k, remains, widths),
        table,
    )

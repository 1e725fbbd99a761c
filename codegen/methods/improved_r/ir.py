"""The resistance-aware rule's integer arithmetic, as IR (printed to C and Python, proven).

The rule (`codegen.derivation.constant_pair.AlignedRule`): one duty pair per
commutation, held at the minimax duty sum of the spec's EMF over the commutation; the
commutation ends on the first carrier boundary m tau (m whole PWM periods after the
edge, where the port restarts the carrier) at which the turn-off current under that
pair has reached zero; and the split is eased (C_on - delta, C_off + delta, the sum
unchanged) so that the current reaches zero exactly there. Formats and constants are
in `fixed.py`; the search is a binary lifting over m with the decay e^-y_1 m taken
from a table of D^(2^k): no exponential, table of psi or divide inside the loop.
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction

import sympy as sp

from codegen.abi import TIMING
from codegen.core.conditioning import (
    CoreLimits,
    CurrentFormat,
    bus_code_statements,
    current_statements,
    flag_if,
    latest_statement,
    safe_state_statements,
)
from codegen.ir.longdiv import DIVIDE_LONG, bytewise_quotient
from codegen.ir.nodes import (
    Expr,
    Function,
    IBitLength,
    ICall,
    IConst,
    ILongDiv,
    ILookup,
    IShl,
    Param,
    SAssign,
    SFor,
    SIf,
    SLet,
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
    lor,
    maximum,
    minimum,
    mul,
    round_shr,
    select,
    shr,
    sub,
    var,
)
from codegen.ir.types import I32, I64, U16, U32, U64
from codegen.methods.improved_r.fixed import (
    E1_SHIFT,
    PER_TICK_BITS,
    FixedRule,
)

BUS = StructType(
    "bldc_bus_t",
    "Bus",
    (
        StructField("x_numerator", U32, "round(N_X / B): X = x_numerator / T in Q(fc) counts"),
        StructField("y_numerator", U32, "Y per unit of current, Q(fc + gy): Y = 3 P R I / U_d"),
        StructField("a_numerator", U32, "A rho per unit of current, Q(fc + ga)"),
        StructField(
            "period_min", U32, "BLDC_PERIOD_MIN_TICKS, or BLDC_PERIOD_NEVER when over-voltage"
        ),
        StructField("bus_code", U32, "the saturated bus code B"),
        StructField("flags", U32, "BLDC_FLAG_INPUT_SATURATED when the code was saturated"),
    ),
    "What the timing step needs of the bus voltage (see the formats above)",
)

ONE_Q31 = 1 << 31


def _exact(value: sp.Expr, digits: int = 60) -> Fraction:
    """An exact rational, or a 60-digit one for an irrational (theta)."""
    if isinstance(value, sp.Rational):
        return Fraction(int(value.p), int(value.q))
    if isinstance(value, Fraction):
        return value
    return Fraction(str(sp.N(value, digits)))


@dataclass(frozen=True)
class RuleConsts:
    n_x: IConst
    kyx: IConst
    kar: IConst
    qc: IConst
    hs: IConst
    y1: IConst
    period_q: IConst
    sum0_q: IConst  # sigma_0: Sigma(0) = 2P + Y - round(X sigma_0 / 4)
    force0_q: IConst  # phi_0: F_0 = F_d + round(X phi_0 / 4)
    periods_num: IConst
    periods_den: IConst


def _quarter(value: Fraction, name: str, what: str) -> IConst:
    if value.denominator != 1 or value < 0:
        # sigma_0 = 4, phi_0 = 2 for the affine shapes (the frozen EMF, 120 deg)
        raise ValueError(f"{what} = {value} is not a whole non-negative number")
    return IConst(U32, int(value), name, doc=f"{what} of the spec's EMF at the edge (X {what}/4)")


def rule_consts(rule: FixedRule) -> RuleConsts:
    c = rule.constants
    fc = rule.counts_frac_bits
    fw = PER_TICK_BITS
    return RuleConsts(
        n_x=IConst(
            U64,
            rule.n_x.numerator,
            "N_X",
            exact=_exact(c.k_x) * 2**fc,
            doc=f"round(K_X 2^{fc}), K_X = {float(c.k_x):.6e}",
        ),
        kyx=IConst(
            U32,
            rule.kyx,
            "KYX_Q",
            exact=_exact(c.k_y / c.k_x) * 2 ** (rule.y_guard_bits + rule.kyx_shift),
            doc=f"K_Y / K_X in Q{rule.y_guard_bits + rule.kyx_shift}: Y per unit = x_numerator K_Y/K_X",
        ),
        kar=IConst(
            U32,
            rule.kar,
            "KAR_Q",
            exact=_exact(c.kappa * c.k_rho) * 2 ** (rule.a_guard_bits + rule.kar_shift),
            doc=f"kappa K_rho in Q{rule.a_guard_bits + rule.kar_shift}: A rho per unit = "
            "x_numerator kappa K_rho",
        ),
        qc=IConst(
            U32,
            rule.qc,
            "RAMP_Q",
            exact=_exact(c.ramp_per_x / c.k_rho) * 2 ** (rule.ramp_frac_bits - fw + rule.qc_shift),
            doc="(-phi_1/4) / K_rho: the EMF ramp's forcing over rho, per X per tick",
        ),
        hs=IConst(
            U32,
            rule.hs,
            "GROWTH_Q",
            exact=_exact(c.hold_slope * c.carrier_ticks)
            * 2 ** (rule.growth_frac_bits - fw + rule.hs_shift),
            doc="hold slope x tau: the held duty sum's growth per carrier period, per X per tick",
        ),
        y1=IConst(
            U32,
            rule.y1,
            "STEP_DECAY_Q",
            exact=_exact(c.step_decay) * 2 ** (32 - rule.ramp_frac_bits),
            doc=f"y_1 = K_rho tau = {float(c.step_decay):.6e} in Q{32 - rule.ramp_frac_bits}: "
            "rho x over one PWM period",
        ),
        period_q=IConst(I32, rule.period_q, "PERIOD_Q", doc=f"P in Q{fc} counts"),
        sum0_q=_quarter(Fraction(c.shape.sum0), "SIGMA0", "sigma_0"),
        force0_q=_quarter(Fraction(c.shape.force0), "PHI0", "phi_0"),
        periods_num=IConst(
            U32, rule.periods_num, "CARRIER_DEN", doc="N = floor(T CARRIER_DEN / CARRIER_NUM)"
        ),
        periods_den=IConst(
            U32,
            rule.periods_den,
            "CARRIER_NUM",
            doc=f"tau = CARRIER_NUM / CARRIER_DEN = {float(c.carrier_ticks):g} Hall ticks per "
            "PWM period",
        ),
    )


def decay_table(rule: FixedRule) -> Table:
    """Rows in the search's order, k = K-1 down to 0: D^(2^k) in Q32 (the row's 2^k is
    2^(K-1) >> step, a shift, not a second column)."""
    c = rule.constants
    steps = len(rule.decay)
    rows = tuple((rule.decay[k],) for k in range(steps - 1, -1, -1))
    return Table(
        "bldc_decay",
        U32,
        rows,
        tuple(f"D^{2**k}: {2**k} PWM periods" for k in range(steps - 1, -1, -1)),
        f"D^(2^k) in Q32 for k = {steps - 1} .. 0 (row step: 2^k = 2^{steps - 1} >> step),"
        f" D = e^-y_1, y_1 = R tau / (L f_hall) = {float(c.step_decay):.6e}: the turn-off"
        " current's decay over 2^k PWM periods",
    )


def shares_current_scale(rule: FixedRule) -> bool:
    """A rho = Y exactly (rho = R T_s / L): when both per-unit constants round to the
    same integer in the same format, the core computes one product for both."""
    return (rule.kar, rule.kar_shift, rule.a_guard_bits) == (
        rule.kyx,
        rule.kyx_shift,
        rule.y_guard_bits,
    )


def bus_condition_function(rule: FixedRule, limits: CoreLimits, k: RuleConsts) -> Function:
    code = var("code", U32)
    xn = var("xn", U32)
    a_stmts: tuple[Stmt, ...] = ()
    a_numerator: Expr = var("yn", U32)
    if not shares_current_scale(rule):
        a_stmts = (
            SLet(
                "an",
                cast(round_shr(mul(cast(xn, U64), cast(k.kar, U64), U64), rule.kar_shift), U32),
                "A rho per unit of current",
            ),
        )
        a_numerator = var("an", U32)
    return Function(
        c_name="bldc_bus_condition",
        py_name="bus_condition",
        params=(Param("bus_code", U32),),
        returns=BUS,
        doc="Saturate a bus code and precompute its reciprocals (pure, reentrant)",
        body=(
            *bus_code_statements(limits),
            SLet("xn", ILongDiv(U32, k.n_x, code), "round(N_X / B)"),
            SLet(
                "yn",
                cast(round_shr(mul(cast(xn, U64), cast(k.kyx, U64), U64), rule.kyx_shift), U32),
                "Y per unit of current",
            ),
            *a_stmts,
            SStruct(
                "bus",
                BUS,
                (
                    ("x_numerator", xn),
                    ("y_numerator", var("yn", U32)),
                    ("a_numerator", a_numerator),
                    ("period_min", var("period_min", U32)),
                    ("bus_code", code),
                    ("flags", var("flags", U32)),
                ),
            ),
            SReturn(var("bus", U32)),
        ),
    )


def _grid_current(
    rule: FixedRule, k: RuleConsts, m: Expr, em: Expr, tag: str, comment: str
) -> tuple[list[Stmt], Expr]:
    """Statements defining, at grid point m with decay em (Q31), the held sum's forcing
    and H = 2^(32+fc) rho g. Returns (statements, H)."""
    fs = rule.growth_frac_bits
    pq = k.period_q
    stmts: list[Stmt] = []
    if rule.hs:
        stmts += [
            SLet(
                f"{tag}total",
                add(var("sigma0", I32), cast(shr(mul(var("growth", U32), m), fs), I32)),
                f"Sigma at {comment}: the held duty sum",
            ),
            SLet(
                f"{tag}held",
                clamp(var(f"{tag}total", I32), const(0, I32), mul(const(2, I32), pq)),
                "the duties' range: C_on + C_off in [0, 2P]",
            ),
            SLet(
                f"{tag}fd",
                sub(
                    sub(
                        mul(const(3, I32), maximum(sub(var(f"{tag}held", I32), pq), const(0, I32))),
                        var(f"{tag}held", I32),
                    ),
                    pq,
                ),
                "F_d = 2 C_off - C_on - P = 3 C_off - (C_on + C_off) - P of the split",
            ),
        ]
        fd = var(f"{tag}fd", I32)
        c2 = sub(var("ca2", I32), mul(const(2, I32), fd))
        r = add(fd, var("cb", I32))
    else:
        c2 = var("ca2_held", I32)
        r = var("cb_held", I32)
    term = add(
        mul(cast(c2, I64), cast(cast(em, I32), I64)),
        mul(cast(r, I64), const(1 << 32, I64)),
    )
    if rule.qc:
        term = sub(
            term,
            cast(mul(cast(var("q", U32), U64), cast(mul(k.y1, m), U64)), I64),
        )
    stmts.append(SLet(f"{tag}h", term, f"2^(32+fc) rho g at {comment}"))
    return stmts, var(f"{tag}h", I64)


def _split(k: RuleConsts, tag: str, total: Expr) -> list[Stmt]:
    return [
        SLet(f"{tag}on", clamp(total, const(0, I32), k.period_q)),
        SLet(f"{tag}off", clamp(sub(total, k.period_q), const(0, I32), k.period_q)),
        SLet(
            f"{tag}fd",
            sub(sub(mul(const(2, I32), var(f"{tag}off", I32)), var(f"{tag}on", I32)), k.period_q),
            "F_d = 2 C_off - C_on - P",
        ),
    ]


def timing_function(
    rule: FixedRule, limits: CoreLimits, current: CurrentFormat, k: RuleConsts, table: Table
) -> Function:
    fc = rule.counts_frac_bits
    fw = PER_TICK_BITS
    steps = rule.steps
    measured, period = var("measured", U32), var("period", U32)
    x = var("x", U32)
    i = var("i", U32)
    n, e = var("n", U32), var("e", U32)
    pq = k.period_q

    def quarter(value: Expr, q: IConst) -> Expr:
        """round(X q / 4), q = sigma_0 or phi_0 (a whole number >= 0)."""
        if q.value == 0:
            return const(0, I32)
        if q.value == 4:
            return cast(value, I32)
        return cast(round_shr(mul(value, q), 2), I32)

    prologue: list[Stmt] = [
        SVar("flags", U32, fld("bus", "flags", U32)),
        SLet(
            "measured",
            minimum(var("period_ticks", U32), limits.period_cap),
            "the Hall counter's range",
        ),
        safe_state_statements(limits, measured),
        flag_if(
            cmp(">", measured, limits.period_max), "INPUT_SATURATED", "below the minimum speed"
        ),
        SLet(
            "period",
            minimum(measured, limits.period_max),
            "the rule's constants cover the speed range",
        ),
        latest_statement(limits, measured),
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
        SLet(
            "a_rho",
            var("y", U32)
            if shares_current_scale(rule)
            else round_shr(mul(fld("bus", "a_numerator", U32), i), rule.a_guard_bits),
            f"A rho = 3 P R I / U_d x (L / (R T_s)) rho: the current at the edge, Q{fc}"
            + (" (= Y: the same constant and format)" if shares_current_scale(rule) else ""),
        ),
        SLet(
            "periods",
            div(mul(limits.latest_end(period), k.periods_num), k.periods_den),
            "N: whole PWM periods in the sector, less the guard and the margin at its end",
        ),
        SLet(
            "sigma0",
            sub(add(mul(const(2, I32), pq), cast(var("y", U32), I32)), quarter(x, k.sum0_q)),
            "Sigma(0) = 2P + Y - (sigma_0/4) X: the held duty sum at the edge's EMFs",
        ),
    ]
    if rule.qc or rule.hs:
        prologue.append(
            SLet(
                "per_tick",
                ICall(U32, DIVIDE_LONG, (x, const(0), const(fw), period)),
                f"X / T in Q{fc + fw}",
            )
        )
    force0 = quarter(x, k.force0_q)
    if rule.qc:
        prologue.append(
            SLet(
                "q",
                cast(
                    shr(mul(cast(var("per_tick", U32), U64), cast(k.qc, U64), U64), rule.qc_shift),
                    U32,
                ),
                f"q = (-phi_1/4) X / rho: the EMF ramp's forcing, Q{fc + rule.ramp_frac_bits}",
            )
        )
        q_counts = cast(round_shr(var("q", U32), rule.ramp_frac_bits), I32)
    else:
        q_counts = const(0, I32)
    if rule.hs:
        prologue.append(
            SLet(
                "growth",
                cast(
                    shr(mul(cast(var("per_tick", U32), U64), cast(k.hs, U64), U64), rule.hs_shift),
                    U32,
                ),
                f"the held sum's growth per PWM period, Q{fc + rule.growth_frac_bits}",
            )
        )
        prologue += [
            SLet(
                "ca2",
                mul(
                    const(2, I32),
                    sub(sub(cast(var("a_rho", U32), I32), q_counts), force0),
                ),
                "2 (A rho - q - (phi_0/4) X)",
            ),
            SLet("cb", add(force0, q_counts), "(phi_0/4) X + q"),
        ]
    else:
        prologue += [
            *_split(k, "held_", var("sigma0", I32)),
            SLet(
                "ca2_held",
                mul(
                    const(2, I32),
                    sub(
                        sub(sub(cast(var("a_rho", U32), I32), q_counts), force0),
                        var("held_fd", I32),
                    ),
                ),
                "2 (A rho - q - F_0): the held pair does not move",
            ),
            SLet("cb_held", add(add(force0, q_counts), var("held_fd", I32)), "F_0 + q"),
        ]

    m = var("m", U32)
    em = var("em", U32)
    step_stmts, h = _grid_current(rule, k, m, em, "", "m")
    index = var("step", U32)
    loop = SFor(
        "step",
        steps,
        (
            SLet(
                "m",
                add(n, shr(const(1 << (steps - 1)), index)),
                f"the next candidate: n + 2^k, 2^k = 2^{steps - 1} >> step",
            ),
            SIf(
                cmp("<=", m, var("periods", U32)),
                (
                    SLet(
                        "em",
                        cast(
                            shr(mul(cast(e, U64), cast(ILookup(U32, table, index), U64), U64), 32),
                            U32,
                        ),
                        "e^-rho x_m in Q31",
                    ),
                    *step_stmts,
                    SIf(
                        cmp(">=", h, const(0, I64)),
                        (SAssign("n", m), SAssign("e", em)),
                        (SAssign("end_h", h), SAssign("end_e", em)),
                        comment="the turn-off current has not reached zero at m (else: the "
                        "last candidate refused is n + 1, the end)",
                    ),
                ),
            ),
        ),
        start="first",
        invariants=(
            ("n", 0, rule.periods_max),
            ("e", 0, ONE_Q31),
            ("end_h", I64.low + 1, -1),
            ("end_e", 0, (ONE_Q31 * max(rule.decay)) >> 32),
        ),
        comment="binary lifting: n = the last carrier boundary at which the current remains",
    )
    # the end: m = n + 1 (its current and decay were kept when it was refused); when the
    # current remains at every boundary (n = N) the pair is held at the last one, uneased
    # (end_h = -1 and end_e = 0 give delta = 0), over the whole sector
    end = var("end", U32)
    end_h = var("end_h", I64)
    end_e = var("end_e", U32)
    unfinished = cmp(">=", n, var("periods", U32))
    tail: list[Stmt] = [
        SLet(
            "end",
            minimum(add(n, const(1)), var("periods", U32)),
            "the first carrier boundary with the current at zero (or the sector's last)",
        ),
    ]
    if rule.hs:
        tail += [
            SLet(
                "end_total",
                add(
                    var("sigma0", I32),
                    cast(shr(mul(var("growth", U32), end), rule.growth_frac_bits), I32),
                ),
                "Sigma at the end: the held duty sum",
            ),
            SLet(
                "end_held",
                clamp(var("end_total", I32), const(0, I32), mul(const(2, I32), pq)),
                "C_on + C_off in [0, 2P]",
            ),
            SLet("end_on", minimum(var("end_held", I32), pq)),
            SLet("end_off", maximum(sub(var("end_held", I32), pq), const(0, I32))),
        ]
        total: Expr = var("end_total", I32)
        end_on, end_off = var("end_on", I32), var("end_off", I32)
    else:
        total = var("sigma0", I32)
        end_on, end_off = var("held_on", I32), var("held_off", I32)
    delta_bits = rule.delta_frac_bits
    numerator_shift = 32 + fc - delta_bits - 31 + E1_SHIFT
    shift_down = fc - delta_bits
    room_q_max = (rule.period_q >> shift_down) + 1
    shortfall = var("shortfall", U32)

    tail += [
        SLet(
            "room",
            minimum(end_on, sub(pq, end_off)),
            "what the split can give: C_on down to 0, C_off up to P",
        ),
        SLet(
            "shortfall",
            mul(const(3), shr(sub(const(ONE_Q31), end_e), E1_SHIFT)),
            f"3 (1 - e) in Q{31 - E1_SHIFT}",
        ),
        SLet(
            "overshoot",
            shr(cast(sub(const(0, I64), end_h), U64), numerator_shift),
            f"-rho g / 3 in Q{delta_bits + 31 - E1_SHIFT}, > 0",
        ),
        SLet(
            "cap",
            mul(
                cast(add(cast(shr(var("room", I32), shift_down), U32), const(1)), U64),
                cast(shortfall, U64),
            ),
            "(room + 1) 3 (1 - e): a larger easing is cut to the room below",
        ),
        # locals of their own, so that a non-relational analysis (EVA) narrows the
        # overshoot in the comparison as the IR's proof does
        SLet(
            "numerator",
            minimum(var("overshoot", U64), var("cap", U64)),
            "the overshoot, at most the cap (it never binds sooner than the room)",
        ),
        *bytewise_quotient(
            "eased",
            "numerator",
            shortfall,
            room_q_max >> 16,
            f"delta = -rho g / (3 (1 - e)) in Q{delta_bits}: ends the current at the"
            " boundary (at most room + 1: the numerator's cap)",
        ),
        SLet(
            "delta",
            IShl(
                I32,
                minimum(
                    cast(minimum(var("eased", U32), const((1 << (31 - shift_down)) - 1)), I32),
                    shr(var("room", I32), shift_down),
                ),
                shift_down,
            ),
            f"the easing in Q{fc}, at most the room",
        ),
        # the eased values are locals of their own, so that a non-relational analysis
        # (Frama-C's EVA) narrows them in the clamps below as the IR's proof does
        SLet("eased_on", sub(end_on, var("delta", I32)), "C_on - delta"),
        SLet("eased_off", add(end_off, var("delta", I32)), "C_off + delta"),
        SLet(
            "on",
            cast(maximum(var("eased_on", I32), const(0, I32)), U32),
            "delta <= the room: never below 0",
        ),
        SLet(
            "off",
            cast(minimum(var("eased_off", I32), pq), U32),
            "never above P",
        ),
        flag_if(unfinished, "TIME_CLAMPED", "the current remains at every carrier boundary"),
        flag_if(
            lor(cmp(">", total, mul(const(2, I32), pq)), cmp("<", total, const(0, I32))),
            "FAIL_AREA_CLAMPED",
            "no duty pair in [0, 1] holds the current",
        ),
        flag_if(
            cmp("<", total, pq),
            "HIGH_SPEED",
            "the upper segment: the turn-off phase at most eased, the turn-on one modulated",
        ),
        SLet(
            "ticks",
            select(
                unfinished,
                var("latest", U32),
                div(add(mul(end, k.periods_den), const(rule.periods_num // 2)), k.periods_num),
            ),
            "round(end tau), a carrier boundary; the whole sector less the guard when the"
            " current remains",
        ),
        SStruct(
            "timing",
            TIMING,
            (
                ("period_min", fld("bus", "period_min", U32)),
                ("turn_on_compare", cast(round_shr(var("on", U32), fc), U16)),
                ("turn_off_compare", cast(round_shr(var("off", U32), fc), U16)),
                ("commutation_ticks", cast(minimum(var("ticks", U32), var("latest", U32)), U16)),
                ("flags", cast(var("flags", U32), U16)),
            ),
        ),
    ]
    body: list[Stmt] = [
        *prologue,
        SLet(
            "skipped",
            sub(
                const(steps, I32),
                cast(IBitLength(U32, maximum(var("periods", U32), const(1))), I32),
            ),
            "the steps whose 2^k is past the sector",
        ),
        SLet(
            "first",
            cast(maximum(var("skipped", I32), const(0, I32)), U32),
            f"the first step whose 2^k fits in the sector: 2^{steps - 1} >> step <= N (a"
            " larger candidate is past the sector, from n = 0: the same result, fewer steps)",
        ),
        SVar("n", U32, const(0)),
        SVar("e", U32, const(ONE_Q31)),
        SVar("end_h", I64, const(-1, I64)),
        SVar("end_e", U32, const(0)),
        loop,
        *tail,
        SReturn(var("timing", U32)),
    ]
    del e, i
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
        body=tuple(body),
    )


def functions(
    rule: FixedRule, limits: CoreLimits, current: CurrentFormat
) -> tuple[Function, Function, Table]:
    k = rule_consts(rule)
    table = decay_table(rule)
    return (
        bus_condition_function(rule, limits, k),
        timing_function(rule, limits, current, k, table),
        table,
    )

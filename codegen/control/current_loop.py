"""The braking-current PI: design, fixed point as IR, proof and error bounds.

Plant (PWM-OFF-PWM braking, averaged over a period, the two conducting phases in
series): ON the phases are shorted through one switch and one diode, OFF the current
returns through the bus, so 2L dI/dt = 2E - 2RI - (1 - D) U_d, i.e. per phase

    L dI/dt = -R I + (U_d / 2) D + (E - U_d / 2):  I(s)/D(s) = (U_d/2) / (L s + R).

Controller: a PI whose zero cancels the plant's pole, K_i / K_p = R / L, and whose
open loop K_p (U_d/2) / (L s) crosses over at w_c = 2 pi `current_loop.bandwidth`:

    K_p = 2 L w_c / U_d  (duty per ampere),   K_i = 2 R w_c / U_d  (duty per ampere second)

at the nominal bus voltage. Discretised at the PWM period T (forward Euler, the sample
of period k sets the duty of period k + 1), in TIM1 counts per current code:

    e[k]   = r - m[k]                                  (codes)
    v[k]   = k_p e[k] + x[k]                            k_p = K_p P a
    D[k]   = clamp(v[k], 0, D_max)                      (counts)
    x[k+1] = x[k]                         if v[k] > D_max and e[k] > 0, or v[k] < 0 and e[k] < 0
           = clamp(x[k] + k_i e[k], 0, D_max)  otherwise   k_i = K_i T P a

with P the counts of a period, a the amperes of a current code and D_max the largest
duty whose OFF time holds the current sample (codegen/control/sensing.py). The
integrator stops where the output is saturated and the error drives it further
(clamping anti-windup), and never leaves the output range. Where 0 <= k_i <= k_p (every
example motor) the clamp never acts unless the output saturates, and the update is
printed as x + k_i e, or x where v is outside [0, D_max]: one range test, no branch.

Fixed point: x and v in Q`f` counts (int32), the gains rounded to Q`f`, the inputs
clamped to the ADC range first, so every intermediate is proven for every value of
every parameter's C type; `f` is the largest that the proof accepts. Where k_i rounds
too coarsely in Q`f` for the periods of a step response, x and k_i take Q(f + s) and v
reads x rounded to Q`f` (`_widest_design`). The error claims count the errors r - m
that can leave v unsaturated (`_error_limit`): beyond them both the exact and the
printed v saturate, and both integrators hold. The reference
conversion mA -> code is exact (nearest code, ties up) for every mA in the spec's
braking range: computed in 64 bits with gains rounded up by less than half of the
smallest distance between a value and a rounding boundary.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from fractions import Fraction
from functools import lru_cache
from math import lcm

from codegen.control.sensing import SenseDesign, sense_design
from codegen.fixedpoint.scaling import period_counts
from codegen.ir import acsl, c_printer, py_printer
from codegen.ir.errors import error as ir_error
from codegen.ir.intervals import (
    Interval,
    ProofError,
    ProvenRange,
    full,
    new_prover,
    prove_function,
)
from codegen.ir.nodes import (
    Expr,
    Function,
    IConst,
    ISelect,
    Param,
    SLet,
    SReturn,
    Stmt,
    add,
    cast,
    clamp,
    cmp,
    const,
    div,
    lor,
    minimum,
    mul,
    round_shr,
    sub,
    var,
)
from codegen.ir.types import I32, U32, U64
from codegen.methods.base import FixedPointError
from codegen.spec_drive import BANDWIDTH_MAX_PER_PWM
from codegen.spec_model import (
    LOOP_DUTY_COUNTS_MAX,
    Spec,
    integrator_step_tolerance_counts,
    loop_periods_per_step_response,
)

HEADER = "bldc_current_loop.h"
SOURCE = "bldc_current_loop.c"
TWIN = "bldc_current_loop.py"
#: pi to 40 digits: the gains are real numbers; this is exact far beyond any format.
PI = Fraction("3.141592653589793238462643383279502884197")
FRACTION_BITS_MAX = 24
#: the most bits x may have beyond v's (x's bound, D_max in Q(f + s), must fit int32 too)
STATE_SHIFT_MAX = 24
REFERENCE_SHIFT_MAX = 60


@dataclass(frozen=True)
class LoopGains:
    """The controller in exact rationals (pi to 40 digits), TIM1 counts and ADC codes."""

    kp_counts_per_code: Fraction
    ki_counts_per_code: Fraction  # per PWM period
    duty_max_counts: int
    kp_duty_per_amp: Fraction
    ki_duty_per_amp_second: Fraction
    bus_voltage_v: Fraction
    omega_c: Fraction
    amps_per_code: Fraction
    zero_current_code: Fraction


@dataclass(frozen=True)
class LoopDesign:
    spec: Spec
    gains: LoopGains
    sensing: SenseDesign
    fraction_bits: int  # v's (and the gains' k_p) Q format
    state_shift: int  # x (and k_i) in Q(fraction_bits + state_shift)
    kp_q: int
    ki_q: int
    state_max: int
    code_max: int
    reference_shift: int
    reference_scale: int
    reference_offset: int
    milliamps_min: int
    milliamps_max: int
    duty: Function
    integrate: Function
    reference: Function
    ranges: tuple[ProvenRange, ...]
    #: one step from a given state: |duty - exact| (counts), |x' - exact| (counts)
    duty_claim: Fraction
    integrator_claim: Fraction
    #: the integrator's drift over a ramp through the whole output range, 0 to D_max
    #: (counts): D_max times k_i's relative rounding error
    ramp_claim: Fraction = Fraction(0)

    @property
    def constants(self) -> tuple[IConst, ...]:
        return _constants(self)

    @property
    def state_bits(self) -> int:
        """x's fraction bits (v's, f, plus the state shift)."""
        return self.fraction_bits + self.state_shift


def gains(spec: Spec) -> LoopGains:
    m, inv = spec.motor, spec.inverter
    p = period_counts(spec)
    full_scale = 2**spec.adc.bits
    amps = spec.adc.reference_v / (spec.adc.current_gain_v_per_a * full_scale)
    zero = spec.adc.current_offset_v / spec.adc.reference_v * full_scale
    u_d = inv.bus_voltage_nominal_v
    omega = 2 * PI * spec.current_loop.bandwidth_hz
    kp = 2 * m.phase_inductance_h * omega / u_d
    ki = 2 * m.phase_resistance_ohm * omega / u_d
    period_s = 1 / inv.pwm_frequency_hz
    return LoopGains(
        kp_counts_per_code=kp * p * amps,
        ki_counts_per_code=ki * period_s * p * amps,
        duty_max_counts=sense_design(spec).window.duty_max_counts,
        kp_duty_per_amp=kp,
        ki_duty_per_amp_second=ki,
        bus_voltage_v=u_d,
        omega_c=omega,
        amps_per_code=amps,
        zero_current_code=zero,
    )


def _round(x: Fraction) -> int:
    return (2 * x.numerator + x.denominator) // (2 * x.denominator)


def _ceil(x: Fraction) -> int:
    return -((-x.numerator) // x.denominator)


def _floor(x: Fraction) -> int:
    return x.numerator // x.denominator


def _top_bits(state: Expr, s: int) -> Expr:
    """x rounded to v's format, (x + 2^(s-1)) / 2^s: printed as a division, not the
    equal shift (x >= 0, so truncation is the floor; GCC emits the shift, the range of x
    known from its clamp), so that WP reads the code as the contracts state it: with
    `>> 4u`, Z3 and CVC4 failed the integrator's three postconditions (2^4: init's 600 V,
    20 mH motor), which they prove in about a second with `/ 16`."""
    return div(add(state, const(1 << (s - 1), I32)), const(1 << s, I32))


def cheap_form_valid(kp_q: int, ki_q: int, state_shift: int) -> bool:
    """Whether the hold-or-integrate anti-windup equals the general clamp: x + k_i e stays
    in [0, D_max] wherever v does not saturate. With x in Q(f + s) and v = k_p e +
    round(x / 2^s), e > 0 and v <= D_max 2^f give x <= (v - k_p e) 2^s + 2^(s-1), so
    x + k_i e <= D_max 2^(f+s) + 2^(s-1) - (k_p 2^s - k_i) e: within bound where
    k_i <= k_p 2^s - 2^(s-1) (s > 0; k_i <= k_p at s = 0); e < 0 and v >= 0 give
    x >= (k_p |e| - 1/2) 2^s, so x + k_i e >= 0 by the same condition."""
    if state_shift == 0:
        return 0 <= ki_q <= kp_q
    return 0 <= ki_q <= (kp_q << state_shift) - (1 << (state_shift - 1))


def _functions(
    f: int,
    kp_q: int,
    ki_q: int,
    state_max: int,
    code_max: int,
    g: LoopGains,
    conditional: bool | None = None,
    state_shift: int = 0,
) -> tuple[Function, Function]:
    """The duty and the integrator update. `conditional` chooses the anti-windup's
    form: hold-or-integrate (valid only where k_i never steps past k_p: see
    `cheap_form_valid`) or the general clamp; None takes the first wherever it is valid.
    `state_shift` s > 0 keeps x in Q(f + s), finer than v's Q f: x + k_i e then rounds
    nothing (k_i in Q(f + s)), and v reads x's top bits, (x + 2^(s-1)) / 2^s (x >= 0:
    `_top_bits`)."""
    s = state_shift
    kp = IConst(
        I32,
        kp_q,
        "BLDC_LOOP_KP",
        exact=g.kp_counts_per_code * 2**f,
        doc=f"k_p = {float(g.kp_counts_per_code):.6g} counts per code, Q{f}",
    )
    ki = IConst(
        I32,
        ki_q,
        "BLDC_LOOP_KI",
        exact=g.ki_counts_per_code * 2 ** (f + s),
        doc=f"k_i = {float(g.ki_counts_per_code):.6g} counts per code per PWM period, Q{f + s}",
    )
    top = IConst(
        I32, state_max, "BLDC_LOOP_STATE_MAX", doc=f"D_max = {g.duty_max_counts} counts in Q{f + s}"
    )
    # v's bound: the state's where both share Q f, else D_max in v's own Q f
    demand_top = (
        top
        if s == 0
        else IConst(
            I32,
            g.duty_max_counts << f,
            "BLDC_LOOP_DEMAND_MAX",
            doc=f"D_max = {g.duty_max_counts} counts in Q{f}, v's format",
        )
    )
    codes = IConst(U32, code_max, "BLDC_LOOP_CODE_MAX", doc="ADC full scale: inputs saturate here")
    zero = IConst(I32, 0)
    params = (
        Param(
            "integrator", I32, doc=f"x in Q{f + s} TIM1 counts (any value: clamped to [0, D_max])"
        ),
        Param("reference_code", U32, doc="braking-current reference, ADC code"),
        Param("measured_code", U32, doc="measured braking current I, ADC code"),
    )
    state = var("state", I32)
    common = (
        SLet("reference", minimum(var("reference_code", U32), codes)),
        SLet("measured", minimum(var("measured_code", U32), codes)),
        SLet(
            "error",
            sub(cast(var("reference", U32), I32), cast(var("measured", U32), I32)),
            "codes: reference - measured",
        ),
        SLet("state", clamp(var("integrator", I32), zero, top), f"Q{f + s} counts"),
        SLet(
            "demand",
            add(mul(kp, var("error", I32)), state if s == 0 else _top_bits(state, s)),
            "k_p e + x" if s == 0 else f"k_p e + x, in Q{f}",
        ),
    )
    duty = Function(
        "bldc_current_loop_duty",
        "current_loop_duty",
        params,
        (
            *common,
            SLet("limited", clamp(var("demand", I32), zero, demand_top)),
            SReturn(cast(round_shr(var("limited", I32), f), U32)),
        ),
        returns=U32,
        doc="main duty in TIM1 counts, 0..D_max, for this period's sample",
        inline=True,
    )
    # Clamping anti-windup: where the output saturates (v > D_max, which needs e > 0 as
    # x <= D_max, or v < 0, which needs e < 0) the integrator keeps its value; elsewhere
    # it integrates, clamped to [0, D_max].
    demand = var("demand", I32)
    total = SLet("total", add(state, mul(ki, var("error", I32))), "x + k_i e")
    if conditional is None:
        conditional = cheap_form_valid(kp_q, ki_q, s)
    if conditional:
        # With k_i never past k_p (`cheap_form_valid`) and x in [0, D_max] the clamp never
        # acts where the output does not saturate: e > 0 gives x < x + k_i e <= v <= D_max,
        # e < 0 gives D_max >= x > x + k_i e >= v >= 0 (in x's format). So the step is
        # x + k_i e or x, by one range test of v (one unsigned compare, no branch, in the
        # interrupt).
        saturated = lor(
            cmp(">", demand, demand_top, exact=False), cmp("<", demand, zero, exact=False)
        )
        body: tuple[Stmt, ...] = (
            total,
            SReturn(ISelect(I32, saturated, state, var("total", I32))),
        )
    else:
        # Written as a clamp of x + k_i e between bounds that close on x from the side
        # the error drives it to: [0, x] when v > D_max, [x, D_max] when v < 0, [0, D_max]
        # otherwise.
        body = (
            total,
            SLet(
                "upper",
                ISelect(I32, cmp(">", demand, demand_top, exact=False), state, top),
                "saturated high: no further up",
            ),
            SLet(
                "lower",
                ISelect(I32, cmp("<", demand, zero, exact=False), state, zero),
                "saturated low: no further down",
            ),
            SReturn(clamp(var("total", I32), var("lower", I32), var("upper", I32))),
        )
    integrate = Function(
        "bldc_current_loop_integrate",
        "current_loop_integrate",
        params,
        (*common, *body),
        returns=I32,
        doc="the integrator for the next period (clamping anti-windup)",
        inline=True,
    )
    return duty, integrate


def _reference_function(spec: Spec, g: LoopGains) -> tuple[Function, int, int, int, int, int]:
    """mA -> the nearest current code (ties up), clamped to the braking range, exact.

    code = (ma M + O) >> s rounded, M = ceil(2^s g), O = ceil(2^s C0) with g the codes
    per mA and C0 the zero-current code: the computed value lies in [exact, exact +
    (ma_max + 1) / 2^s], below the distance 1 / (2 D) between any exact value and a
    rounding boundary it does not sit on (D the common denominator), so it rounds as
    the exact one does, ties included."""
    c = spec.controller
    per_ma = 1 / (1000 * g.amps_per_code)
    ma_min = _ceil(c.braking_current_min_a * 1000)
    ma_max = _floor(c.braking_current_max_a * 1000)
    denominator = lcm(per_ma.denominator, g.zero_current_code.denominator)
    for s in range(8, REFERENCE_SHIFT_MAX + 1):
        if Fraction(ma_max + 1, 2**s) < Fraction(1, 2 * denominator):
            break
    else:
        raise FixedPointError(
            "no 64-bit format converts milliamperes to current codes exactly",
            "controller.braking_current_max",
        )
    scale = _ceil(per_ma * 2**s)
    offset = _ceil(g.zero_current_code * 2**s)
    ma = var("milliamps", U32)
    top = IConst(U32, ma_max, "BLDC_LOOP_MA_MAX", doc="braking_current_max, mA")
    # A lower bound of 0 mA is no bound for an unsigned value (and `< 0u` would draw
    # -Wtype-limits): only the upper clamp then.
    held = (
        minimum(ma, top)
        if ma_min == 0
        else clamp(ma, IConst(U32, ma_min, "BLDC_LOOP_MA_MIN", doc="braking_current_min, mA"), top)
    )
    fn = Function(
        "bldc_current_reference",
        "current_reference",
        (Param("milliamps", U32, doc="braking current, mA"),),
        (
            SLet("held", held, "the spec's braking range"),
            SLet(
                "scaled",
                add(
                    mul(
                        cast(var("held", U32), U64),
                        IConst(
                            U64,
                            scale,
                            "BLDC_LOOP_REF_SCALE",
                            exact=per_ma * 2**s,
                            doc=f"codes per mA, Q{s}, rounded up",
                        ),
                    ),
                    IConst(
                        U64,
                        offset,
                        "BLDC_LOOP_REF_OFFSET",
                        exact=g.zero_current_code * 2**s,
                        doc=f"zero-current code, Q{s}, rounded up",
                    ),
                ),
            ),
            SReturn(cast(round_shr(var("scaled", U64), s), U32)),
        ),
        returns=U32,
        doc="the nearest ADC code of a braking current in mA, clamped to the spec's braking range",
    )
    return fn, s, scale, offset, ma_min, ma_max


def _prove(functions: tuple[Function, ...]) -> tuple[ProvenRange, ...]:
    prover = new_prover(functions)
    for fn in functions:
        prove_function(prover, fn)
    return prover.ranges


def _claims(
    duty: Function, integrate: Function, state_bits: int, state_max: int, error_limit: int
) -> tuple[Fraction, Fraction]:
    """One step from a given state (its error 0): the IR error analysis of the duty and
    of the integrator update where it integrates (an unsaturated step), in counts (the
    state in Q`state_bits`), over the errors |e| <= `error_limit` (`_error_limit`: beyond
    it the exact and the printed v saturate alike, so duty and integrator agree)."""
    prover = new_prover((duty, integrate))
    env = {p.name: full(p.ctype) for p in duty.params if p.ctype is not None}
    errs: dict[str, Fraction] = {}
    for s in duty.body[:-1]:
        assert isinstance(s, SLet)
        errs[s.name] = ir_error(prover, s.expr, env, errs)
        env[s.name] = prover.ev(s.expr, env)
        if s.name == "error":
            reach = env["error"]
            env["error"] = Interval(max(reach.lo, -error_limit), min(reach.hi, error_limit))
    final = duty.body[-1]
    assert isinstance(final, SReturn) and final.value is not None
    duty_error = ir_error(prover, final.value, env, errs)
    # Where it integrates (not saturated) the step is clamp(x + k_i e, 0, D_max).
    total = next(s for s in integrate.body if isinstance(s, SLet) and s.name == "total")
    errs["total"] = ir_error(prover, total.expr, env, errs)
    env["total"] = prover.ev(total.expr, env)
    unsaturated = clamp(var("total", I32), IConst(I32, 0), IConst(I32, state_max))
    integrator_error = ir_error(prover, unsaturated, env, errs) / 2**state_bits
    return duty_error, integrator_error


#: Bandwidths `_faster_bandwidth` tries, per decade of Hz (a step response's integrator
#: drift follows how k_i rounds in its format, not the bandwidth monotonically).
_NICE_BANDWIDTHS = (1, 1.2, 1.5, 2, 2.5, 3, 4, 5, 6, 8)


def _bandwidth_top(spec: Spec) -> Fraction:
    """The loader's largest current-loop bandwidth for this PWM frequency."""
    return min(Fraction(20_000), BANDWIDTH_MAX_PER_PWM * spec.inverter.pwm_frequency_hz)


def _faster_bandwidths(spec: Spec) -> list[Fraction]:
    """Bandwidths above the spec's, a few per decade, up to the loader's limit."""
    bandwidth, top = spec.current_loop.bandwidth_hz, _bandwidth_top(spec)
    return sorted(
        {
            Fraction(str(nice)) * 10**decade
            for decade in range(5)
            for nice in _NICE_BANDWIDTHS
            if bandwidth < Fraction(str(nice)) * 10**decade <= top
        }
    )


def _faster_bandwidth(spec: Spec) -> Fraction | None:
    """The lowest bandwidth above the spec's, of a few per decade up to the loader's
    limit (f_pwm / 10, 20 kHz), whose PI meets the spec's current_loop_duty_counts in
    its widest format; None where none does."""
    from dataclasses import replace

    for candidate in _faster_bandwidths(spec):
        trial = replace(spec, current_loop=replace(spec.current_loop, bandwidth_hz=candidate))
        try:
            met = accuracy_needed(widest_design(trial)) <= spec.accuracy.current_loop_duty_counts
        except FixedPointError:
            continue
        if met:
            return candidate
    return None


def _integrator_below_one_lsb(spec: Spec, g: LoopGains, f: int) -> FixedPointError:
    """The refusal of a PI whose k_i rounds to 0 in its widest format (the integrator
    would never move), naming the bandwidth, its value and one that fits, if any."""
    from dataclasses import replace

    bandwidth = spec.current_loop.bandwidth_hz
    top = _bandwidth_top(spec)
    candidates = _faster_bandwidths(spec)
    fits = None
    for candidate in candidates:
        trial = replace(spec, current_loop=replace(spec.current_loop, bandwidth_hz=candidate))
        try:
            _widest_design(trial, explain=False)
        except FixedPointError:
            continue
        fits = candidate
        break
    m = spec.motor
    allowed = (
        f"e.g. {float(fits):g} Hz fits"
        if fits is not None
        else f"none up to the loader's limit {float(top):g} Hz: k_i / k_p = R / L ="
        f" {float(m.phase_resistance_ohm / m.phase_inductance_h):.3g} /s is too small for"
        " the PI's fixed point; check motor.phase_resistance and motor.phase_inductance"
    )
    return FixedPointError(
        f"current_loop.bandwidth = {float(bandwidth):g} Hz: k_i = 2 R omega_c / U_d ="
        f" {float(g.ki_counts_per_code):.3g} counts per code per period is below one LSB"
        f" of the braking-current PI's finest integrator format that fits (Q{f}), so its integrator"
        f" would never move (allowed: a bandwidth whose k_i is at least one LSB: {allowed})",
        "current_loop.bandwidth",
    )


def _larger_gain(spec: Spec) -> tuple[Fraction, Fraction] | None:
    """The lowest current-sense gain above the spec's, of a few per decade, whose PI
    meets the spec's current_loop_duty_counts in its widest format and whose sensing
    still reads `protection.over_current` (both ways with phase shunts), with the
    accuracy it needs; else the one needing the least accuracy a spec may ask; None
    where none does. A current code of fewer amperes shrinks k_p in counts per code, and so widens
    the format in which k_i rounds: the integrator's drift over a step response, which
    no bandwidth changes (k_p and the periods of a step response scale inversely), falls
    with the gain."""
    from dataclasses import replace

    adc = spec.adc
    room = adc.reference_v - adc.current_offset_v
    if spec.sensing.topology == "low_side_phase_shunts":
        room = min(room, adc.current_offset_v)
    if room <= 0:
        return None
    top = room / spec.protection.over_current_a
    gain = adc.current_gain_v_per_a
    candidates = sorted(
        {
            Fraction(str(nice)) * Fraction(10) ** decade
            for decade in range(-3, 3)
            for nice in _NICE_BANDWIDTHS
            if gain < Fraction(str(nice)) * Fraction(10) ** decade <= top
        }
    )
    best: tuple[Fraction, Fraction] | None = None
    for candidate in candidates:
        trial = replace(spec, adc=replace(adc, current_gain_v_per_a=candidate))
        try:
            needed = accuracy_needed(widest_design(trial))
        except FixedPointError:
            continue
        if needed <= spec.accuracy.current_loop_duty_counts:
            return candidate, needed
        if needed <= LOOP_DUTY_COUNTS_MAX and (best is None or needed < best[1]):
            best = (candidate, needed)
    return best


def _hold_claims(d: LoopDesign) -> None:
    """The widest format's error bounds against what the spec allows: a design that
    would fail `verify` is refused here, naming the key to change: the accuracy, or,
    where the accuracy it would need is beyond what a spec may ask (a slow loop's step
    response accumulates the integrator's error over many periods), the bandwidth."""
    allowed = d.spec.accuracy.current_loop_duty_counts
    periods = loop_periods_per_step_response(d.spec)
    step = float(d.integrator_claim)
    if accuracy_needed(d) > LOOP_DUTY_COUNTS_MAX:
        bandwidth = d.spec.current_loop.bandwidth_hz
        faster = _faster_bandwidth(d.spec)
        if faster is not None:
            meets = f"e.g. {float(faster):g} Hz meets it"
        else:
            found = _larger_gain(d.spec)
            motor = d.spec.motor
            tau = motor.phase_inductance_h / motor.phase_resistance_ohm
            periods_tau = tau * d.spec.inverter.pwm_frequency_hz
            # what sets k_i's smallness: a misread resistance (0.0001 ohm) had the line
            # name the bandwidth alone, which no value fixes (a hunt)
            meets = (
                "none up to the loader's limit in the PI's widest format: k_i / k_p = R / L,"
                f" L/R = {float(tau):.4g} s = {float(periods_tau):.4g} PWM periods from"
                f" motor.phase_resistance = {float(motor.phase_resistance_ohm):g} ohm and"
                f" motor.phase_inductance = {float(motor.phase_inductance_h):g} H"
            )
            if found is not None:
                gain, needed = found
                meets += (
                    f"; a current code of fewer amperes does: adc.current_gain ="
                    f" {float(gain) * 1000:g} mV/A"
                    + (
                        " meets it"
                        if needed <= allowed
                        else " with accuracy.current_loop_duty_counts >="
                        f" {math.ceil(float(needed) * 1000) / 1000:g} counts"
                    )
                )
        drift = step * periods
        ramp = float(d.duty_claim + d.ramp_claim)
        if drift >= ramp:
            why = (
                f"a braking-current step response takes {periods:.1f} PWM periods, over"
                f" which the PI's integrator, off by up to {step:.4f} counts a period in its"
                f" widest format ({_format_name(d)}), drifts {drift:.4f} counts"
            )
        else:
            # the ramp's bound, not the step's, is over (the message had named the
            # step's drift, 0.025 counts, as "more than 16 counts")
            why = (
                f"over a ramp from 0 to D_max the PI's widest format ({_format_name(d)}) is"
                f" off by up to {ramp:.4f} counts (its duty {float(d.duty_claim):.4f}, its"
                f" integrator's drift {float(d.ramp_claim):.4f}: k_i's rounding over the"
                " ramp's periods)"
            )
        raise FixedPointError(
            f"current_loop.bandwidth = {float(bandwidth):g} Hz: {why}, more than the"
            f" {LOOP_DUTY_COUNTS_MAX} counts accuracy.current_loop_duty_counts may be"
            f" (allowed: a bandwidth whose PI meets accuracy.current_loop_duty_counts ="
            f" {float(allowed):g} counts: {meets})",
            "current_loop.bandwidth",
        )
    if d.duty_claim + d.ramp_claim > allowed or step > integrator_step_tolerance_counts(d.spec):
        raise FixedPointError(
            f"accuracy.current_loop_duty_counts = {float(allowed):g} counts: the"
            f" braking-current PI's widest format ({_format_name(d)}) is off by up to"
            f" {float(d.duty_claim):.4f} counts in the duty and {step:.4f} counts a period"
            f" in the integrator, {step * periods:.4f} counts over a step response"
            f" ({periods:.1f} PWM periods), {float(d.ramp_claim):.4f} over a ramp from 0"
            f" to D_max (allowed: >="
            f" {math.ceil(float(accuracy_needed(d)) * 1000) / 1000:g} counts)",
            "accuracy.current_loop_duty_counts",
        )


def _format_name(d: LoopDesign) -> str:
    f = d.fraction_bits
    return f"Q{f}" if d.state_shift == 0 else f"Q{f}, its integrator Q{d.state_bits}"


def accuracy_needed(d: LoopDesign) -> Fraction:
    """The smallest accuracy.current_loop_duty_counts the design meets: its duty bound,
    its integrator bound a period over the periods of a step response, and its duty
    bound with the integrator's drift over a ramp through the whole output range (from
    rest at a low EMF the current stays at zero until the duty passes 1 - 2E/U_d, and
    the integrator ramps with one error for hundreds of periods: k_i's relative rounding
    error times the ramp's travel, D_max; `verify`'s windup scenario is such a ramp)."""
    periods = Fraction(loop_periods_per_step_response(d.spec))
    return max(d.duty_claim, d.integrator_claim * periods, d.duty_claim + d.ramp_claim)


@lru_cache(maxsize=16)
def design(spec: Spec) -> LoopDesign:
    """The PI in the widest Q format whose every intermediate is proven to fit, held to
    the spec's accuracy (refused, naming the key, where it falls short)."""
    d = widest_design(spec)
    _hold_claims(d)
    return d


@lru_cache(maxsize=16)
def widest_design(spec: Spec) -> LoopDesign:
    """The PI in the widest Q format whose every intermediate is proven to fit, with its
    error bounds (not yet held to the spec's accuracy: `design` does)."""
    return _widest_design(spec, explain=True)


def _widest_design(spec: Spec, explain: bool) -> LoopDesign:
    """widest_design; `explain` searches a bandwidth that fits for the refusal of a k_i
    below one LSB (the search's own trials do not: one level, not one per candidate).

    v's format Q f is the widest whose k_p e fits; x shares it where that meets the
    spec's accuracy (the printed loop as it always was), else x takes the widest finer
    format Q(f + s) that is proven to fit: a large k_p (a motor of large L) leaves f few
    bits, in which k_i would round coarsely and its error build up over the many periods
    of a step response."""
    g = gains(spec)
    code_max = 2**spec.adc.bits - 1
    if g.duty_max_counts <= 0:
        raise FixedPointError("the current sample window leaves no duty", "sensing.settling_time")
    last: Exception | None = None
    for f in range(FRACTION_BITS_MAX, 0, -1):
        try:
            plain = _candidate(spec, g, code_max, f, 0)
        except ProofError as exc:
            last = exc
            continue
        if plain is not None and plain.ki_q >= 1 and _meets(plain):
            return plain
        for s in range(STATE_SHIFT_MAX, 0, -1):
            try:
                finer = _candidate(spec, g, code_max, f, s)
            except ProofError:
                continue
            if finer is not None and finer.ki_q >= 1:
                return finer
        if plain is None:
            continue
        if plain.ki_q < 1:
            if not explain:
                raise FixedPointError("k_i below one LSB", "current_loop.bandwidth")
            # named in the finest integrator format x may take (its bound within int32)
            finest = max(
                b for b in range(f, f + STATE_SHIFT_MAX + 1) if g.duty_max_counts << b <= I32.high
            )
            raise _integrator_below_one_lsb(spec, g, finest)
        return plain
    slower = _slower_fitting_bandwidth(spec) if explain else None
    allowed = (
        f"a bandwidth of at most about {float(slower):g} Hz, whose k_p fits"
        if slower is not None
        else "no bandwidth from 1 Hz up: a current code of more amperes (a smaller"
        " adc.current_gain) or a smaller inductance shrinks k_p"
    )
    raise FixedPointError(
        f"current_loop.bandwidth = {float(spec.current_loop.bandwidth_hz):g} Hz: no Q format"
        f" of the braking-current PI fits int32 for every input ({last}) (allowed:"
        f" {allowed})",
        "current_loop.bandwidth",
    )


def _slower_fitting_bandwidth(spec: Spec) -> Fraction | None:
    """The highest bandwidth below the spec's, of a few per decade down to the loader's
    1 Hz, in whose Q formats the PI fits int32 (k_p scales with it); None where none."""
    from dataclasses import replace

    bandwidth = spec.current_loop.bandwidth_hz
    candidates = sorted(
        {
            Fraction(str(nice)) * 10**decade
            for decade in range(5)
            for nice in _NICE_BANDWIDTHS
            if Fraction(str(nice)) * 10**decade < bandwidth
        },
        reverse=True,
    )
    for candidate in candidates:
        trial = replace(spec, current_loop=replace(spec.current_loop, bandwidth_hz=candidate))
        try:
            _widest_design(trial, explain=False)
        except FixedPointError as exc:
            if "fits int32" in str(exc):
                continue
            return candidate  # fits; refused for another reason, said when it is set
        return candidate
    return None


def _candidate(spec: Spec, g: LoopGains, code_max: int, f: int, s: int) -> LoopDesign | None:
    """The PI with v in Q f and x in Q(f + s), proven (ProofError where an intermediate
    may not fit), with its error bounds; None where k_p rounds to nothing or the state's
    bound leaves int32 (a k_i that rounds to nothing is the caller's to refuse)."""
    kp_q = _round(g.kp_counts_per_code * 2**f)
    ki_q = _round(g.ki_counts_per_code * 2 ** (f + s))
    state_max = g.duty_max_counts << (f + s)
    if kp_q < 1 or state_max > I32.high:
        return None
    duty, integrate = _functions(f, kp_q, ki_q, state_max, code_max, g, state_shift=s)
    ranges = _prove((duty, integrate))
    reference, shift, scale, offset, ma_min, ma_max = _reference_function(spec, g)
    ranges += _prove((reference,))
    duty_claim, integrator_claim = _claims(
        duty, integrate, f + s, state_max, _error_limit(g, kp_q, f)
    )
    return LoopDesign(
        spec=spec,
        gains=g,
        sensing=sense_design(spec),
        fraction_bits=f,
        state_shift=s,
        kp_q=kp_q,
        ki_q=ki_q,
        state_max=state_max,
        code_max=code_max,
        reference_shift=shift,
        reference_scale=scale,
        reference_offset=offset,
        milliamps_min=ma_min,
        milliamps_max=ma_max,
        duty=duty,
        integrate=integrate,
        reference=reference,
        ranges=ranges,
        duty_claim=duty_claim,
        integrator_claim=integrator_claim,
        ramp_claim=_ramp_drift(g, ki_q, f + s),
    )


def _error_limit(g: LoopGains, kp_q: int, f: int) -> int:
    """The largest |e| at which v may be unsaturated, exactly or as printed. With x in
    [0, D_max] (v's state term round(x / 2^s) too), e > 0 and k_p e > D_max give v >
    D_max, e < 0 and k_p |e| > D_max give v < 0, for either gain, k_p or KP / 2^f: both
    duties are then the same bound and both integrators hold (clamping anti-windup)."""
    slowest = min(g.kp_counts_per_code, Fraction(kp_q, 2**f))
    return _floor(g.duty_max_counts / slowest)


def _ramp_drift(g: LoopGains, ki_q: int, state_bits: int) -> Fraction:
    """The integrator's drift over a ramp from 0 to D_max with one sign of error: the
    exact one travels D_max = sum k_i e, the printed one sum KI e / 2^b, apart by D_max
    |KI / 2^b - k_i| / k_i (x + KI e rounds nothing: x is in KI's format)."""
    if g.ki_counts_per_code <= 0:
        return Fraction(0)
    error = abs(Fraction(ki_q, 2**state_bits) - g.ki_counts_per_code)
    return g.duty_max_counts * error / g.ki_counts_per_code


def _meets(d: LoopDesign) -> bool:
    """Whether `_hold_claims` accepts the design."""
    allowed = d.spec.accuracy.current_loop_duty_counts
    return (
        accuracy_needed(d) <= LOOP_DUTY_COUNTS_MAX
        and d.duty_claim + d.ramp_claim <= allowed
        and d.integrator_claim <= integrator_step_tolerance_counts(d.spec)
    )


def _constants(d: LoopDesign) -> tuple[IConst, ...]:
    from codegen.ir.nodes import Module
    from codegen.ir.walk import named_constants

    return tuple(named_constants(Module(functions=(d.duty, d.integrate, d.reference))))


# ------------------------------------------------------------------ printing


def _range_lines(ranges: tuple[ProvenRange, ...]) -> list[str]:
    out = []
    for r in ranges:
        spare = r.headroom_bits
        spare_text = "inf" if spare == float("inf") else f"{spare:.1f}"
        out.append(
            f"{r.function}: {r.name}: {r.c_type} in [{r.low}, {r.high}] ({spare_text} bits spare)"
        )
    return out


def _clamped(name: str, high: str, low: str | None = None) -> str:
    """An ACSL term: `name` clamped to [low, high] (to high alone without low)."""
    upper = f"({name} > {high} ? {high} : {name})"
    return upper if low is None else f"({name} < {low} ? {low} : {upper})"


def contracts(d: LoopDesign) -> dict[str, acsl.Contract]:
    """What the loop's functions promise, as ACSL (`make prove` proves each clause with
    WP or checks it with EVA over every input). The yardsticks are the design's limits
    and the anti-windup rule of the module's docstring, restated over mathematical
    integers from the parameters, not from the printed body."""
    s = d.state_shift
    # v reads x rounded to its own format: (x + 2^(s-1)) / 2^s of x >= 0 is the floor
    top_bits = "x" if s == 0 else f"(x + {1 << (s - 1)}) / {1 << s}"
    v_max = "BLDC_LOOP_STATE_MAX" if s == 0 else "BLDC_LOOP_DEMAND_MAX"
    e = (
        f"\\let r = {_clamped('reference_code', 'BLDC_LOOP_CODE_MAX')};"
        f" \\let m = {_clamped('measured_code', 'BLDC_LOOP_CODE_MAX')};"
        f" \\let x = {_clamped('integrator', 'BLDC_LOOP_STATE_MAX', '0')};"
        f" \\let e = r - m; \\let v = BLDC_LOOP_KP * e + {top_bits};"
    )
    saturated = f"((v > {v_max} && e > 0) || (v < 0 && e < 0))"
    return {
        d.duty.c_name: acsl.Contract(
            ensures=(acsl.Clause("ensures", "within_d_max", "\\result <= BLDC_LOOP_DUTY_MAX"),),
        ),
        d.integrate.c_name: acsl.Contract(
            ensures=(
                acsl.Clause("ensures", "in_range", "0 <= \\result <= BLDC_LOOP_STATE_MAX"),
                acsl.Clause(
                    "ensures", "holds_where_saturated", f"{e} {saturated} ==> \\result == x"
                ),
                acsl.Clause(
                    "ensures",
                    "integrates_elsewhere",
                    f"{e} !{saturated} ==> \\result =="
                    f" {_clamped('(x + BLDC_LOOP_KI * e)', 'BLDC_LOOP_STATE_MAX', '0')}",
                ),
            ),
        ),
        d.reference.c_name: acsl.Contract(
            ensures=(acsl.Clause("ensures", "an_adc_code", "\\result <= BLDC_LOOP_CODE_MAX"),),
        ),
    }


def loop_context(d: LoopDesign) -> dict[str, object]:
    """Printed C and Python of the loop, for templates/c/bldc_current_loop.* and
    templates/python/bldc_current_loop.py.j2."""
    g = d.gains
    spec = d.spec
    extra = [
        IConst(
            U32,
            d.state_bits,
            "BLDC_LOOP_FRAC_BITS",
            doc="fraction bits of x and v"
            if d.state_shift == 0
            else f"fraction bits of x (v: Q{d.fraction_bits})",
        ),
        IConst(
            U32,
            g.duty_max_counts,
            "BLDC_LOOP_DUTY_MAX",
            doc="D_max, TIM1 counts: the OFF time holds the current sample",
        ),
    ]
    constants = [*d.constants, *extra]
    ideal = [
        f"K_p = 2 L w_c / U_d = {float(g.kp_duty_per_amp):.6g} per A"
        f" (L = {float(spec.motor.phase_inductance_h) * 1e3:g} mH,"
        f" w_c = 2 pi {float(spec.current_loop.bandwidth_hz):g} Hz,"
        f" U_d = {float(g.bus_voltage_v):g} V nominal)",
        f"K_i = 2 R w_c / U_d = {float(g.ki_duty_per_amp_second):.6g} per A s (R ="
        f" {float(spec.motor.phase_resistance_ohm):g} ohm): zero at R/L, the plant's pole",
        f"per period T = 1/{float(spec.inverter.pwm_frequency_hz):g} Hz in counts per code"
        f" (P = {period_counts(spec)}, a = {float(g.amps_per_code) * 1e3:.6g} mA per code):"
        f" k_p = {float(g.kp_counts_per_code):.6g}, k_i = {float(g.ki_counts_per_code):.6g}",
        f"Q{d.fraction_bits}: KP = {d.kp_q} ({float(Fraction(d.kp_q, 2**d.fraction_bits) / g.kp_counts_per_code - 1) * 1e6:+.1f} ppm),"
        f"{'' if d.state_shift == 0 else f' Q{d.state_bits}:'}"
        f" KI = {d.ki_q} ({float(Fraction(d.ki_q, 2**d.state_bits) / g.ki_counts_per_code - 1) * 1e6:+.1f} ppm)",
        f"claimed, one step from a given state (IR error analysis): duty <= {float(d.duty_claim):.4f}"
        f" counts, integrator <= {float(d.integrator_claim):.4f} counts a step,"
        f" {float(d.ramp_claim):.4f} over a ramp from 0 to D_max",
        f"reference: code = round((mA x {d.reference_scale} + {d.reference_offset}) / 2^{d.reference_shift}),"
        f" exact nearest code for every mA in [{d.milliamps_min}, {d.milliamps_max}]",
    ]
    functions = (d.duty, d.integrate)
    promised = {name: acsl.contract(c) for name, c in contracts(d).items()}
    formats = (
        f"x and v in Q{d.fraction_bits} counts"
        if d.state_shift == 0
        else f"x in Q{d.state_bits} counts, v in Q{d.fraction_bits} (x rounded to it)"
    )
    return {
        "formats": formats,
        "doc": ideal,
        "ranges": _range_lines(d.ranges),
        "defines": [c_printer.define(c) for c in constants],
        "inline_functions": [
            c_printer.function_definition(fn, promised[fn.c_name]) for fn in functions
        ],
        "prototypes": [
            f"/* {c_printer.comment_text(d.reference.doc)} */\n{promised[d.reference.c_name]}\n"
            f"{c_printer.prototype(d.reference)}"
        ],
        "functions": [c_printer.function_definition(d.reference)],
        "py_constants": [py_printer.assignment(c) for c in constants],
        "py_helpers": py_printer.helpers((*functions, d.reference)),
        "py_functions": [py_printer.function_definition(fn) for fn in (*functions, d.reference)],
    }


def manifest_entry(d: LoopDesign) -> dict[str, object]:
    shift = {} if d.state_shift == 0 else {"state_shift": d.state_shift}
    return {
        "fraction_bits": d.state_bits,  # x's: the integrator the C takes and returns
        **shift,
        "duty_max_counts": d.gains.duty_max_counts,
        "claims": {
            "duty_counts": float(d.duty_claim),
            "integrator_counts": float(d.integrator_claim),
            "integrator_ramp_counts": float(d.ramp_claim),
        },
        "functions": {
            "duty": d.duty.c_name,
            "integrate": d.integrate.c_name,
            "reference": d.reference.c_name,
        },
    }


def render_loop_files(spec: Spec) -> dict[str, str]:
    """Output path -> text of the loop's C header, C source and Python twin."""
    from codegen.render import provenance, render

    context = loop_context(design(spec))
    files = {
        f"c/{HEADER}": "c/bldc_current_loop.h.j2",
        f"c/{SOURCE}": "c/bldc_current_loop.c.j2",
        f"python/{TWIN}": "python/bldc_current_loop.py.j2",
    }
    return {
        out: render(template, provenance=provenance(f"templates/{template}", spec), **context)
        for out, template in files.items()
    }

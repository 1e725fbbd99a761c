"""Formats, proof and claimed bounds of the paper's methods (none, conventional, improved).

The search: the most fraction bits f of X (precision costs nothing at run time, a
shift count) for which the interval proof of the printed IR succeeds; at that f, the
current scale m (`core.conditioning.current_formats`) with the widest region where the
commutation time meets the spec's target. The bounds come from the IR's error analysis
(`codegen.ir.errors`) of the very functions that are printed:

* duties: the error of C_on and C_off against Eq. 16/18 at the exact X;
* commutation time, against Eq. 20 at the emitted duties: with the relative errors of
  the time numerator (eps_g) and of W_q (eps_w = e(X_q) / (W 2^f)) and the offset's
  residue e_off (codes x m),

      |t - t*| <= 1/2 + T_cap (eps_g + eps_w) / (1 - eps_w)
                 + tn_max (1 + eps_g) e_off / (W 2^f (1 - eps_w)),

  for t* <= T_cap (beyond, both saturate at the sector). It falls as W grows; the design
  states W_ok, the smallest W (counts) where it meets the spec's target. Below W_ok
  Eq. 20 is ill-conditioned (the top-speed limit, where W -> 0) and the spec's declared
  relaxation applies there: where one count of W moves t* by more than
  ill_conditioned_above (A). Where it moves t* by less, `verify` holds the target even
  below W_ok (a small current makes t* small at any W): `_region_bound` bounds the
  error over those points, and a format that misses it is not taken (the refusal names
  the Hall clock that gives X the bits). Without a declared relaxation the target holds
  everywhere; the claim stays W >= W_ok and `verify` checks the rest.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from fractions import Fraction

from codegen.core.conditioning import CoreLimits, CurrentFormat, current_formats
from codegen.fixedpoint.scaling import Scaling
from codegen.ir.errors import ErrorAnalysisError, walk_errors
from codegen.ir.intervals import Interval, ProofError, Prover, new_prover, prove_function
from codegen.ir.nodes import Function, IConst
from codegen.ir.types import U32
from codegen.methods.base import Claims, CoreDesign, FixedPointError
from codegen.methods.paper_core import (
    BUS,
    DutyRule,
    PaperConstants,
    PaperFormats,
    bus_condition_function,
    paper_numerators,
    timing_function,
)
from codegen.spec_model import COMMUTATION_TICKS_MAX, Spec

MAX_FRACTION_BITS = 12


def _fraction(value: object) -> Fraction:
    import sympy as sp

    r = sp.Rational(value)
    return Fraction(int(r.p), int(r.q))


def round_up(value: Fraction, places: int = 3) -> float:
    """A bound printed for people: rounded up, never down."""
    scale = 10**places
    return float(-(-value * scale // 1) / scale)


@dataclass(frozen=True)
class _Candidate:
    formats: PaperFormats
    prover: Prover
    bus_fields: dict[str, Interval]
    duty_error: Fraction
    x_q_error: Fraction
    time_numerator_error: Fraction


def _bits_needed(spec: Spec, f: int) -> int:
    """The fraction bits of X, from f up, where the spread of half an LSB of W times
    ill_conditioned_above ticks a count takes at most 3/4 of what the target leaves
    beyond the final rounding (`PaperMethod._region_bound`); f where no relaxation is
    declared."""
    above = spec.accuracy.ill_conditioned_above
    if above is None:
        return f
    room = _fraction(spec.accuracy.commutation_time_ticks) - Fraction(1, 2)
    needed = f
    while needed < MAX_FRACTION_BITS and _fraction(above) / 2 ** (needed + 1) > room * Fraction(
        3, 4
    ):
        needed += 1
    return needed


def _numerator_overflow(
    spec: Spec, sc: Scaling, c: PaperConstants, timer: Fraction, reason: str
) -> str:
    """Why no format is safe where even Q0 overflows: Eq. 20's product K_G I / B (Hall
    ticks x W, in Q0) at the lowest bus code and the current code farthest from the
    offset, and the Hall clock it scales with down to int32_t, and further down to the
    fraction bits X needs where the spec holds t_com to its target (`_bits_needed`)."""
    offset = _fraction(sc.current_offset_exact)
    current = max(offset, sc.adc_full_scale - offset)
    peak = c.k_g * current / sc.bus_code_min
    clock = _fraction(sc.hall_clock_hz)
    limit = clock * (2**31 - 1) / peak / 2 ** _bits_needed(spec, 0)
    divider = -(-timer // limit)
    return (
        f"hall.timer_clock = {float(clock):.10g} Hz: no format from Q0 to Q{MAX_FRACTION_BITS}"
        " is safe, whatever the time target: Eq. 20's numerator times the current code"
        f" (K_G I / B, Hall ticks x W) reaches {float(peak):.4g} at the lowest bus code and"
        f" the current code farthest from the offset, beyond int32_t ({reason}); it scales"
        f" with the Hall clock (allowed: <= {float(limit):.6g} Hz, {float(timer):.10g} Hz / N"
        f" for N >= {divider}: {float(timer / divider):.10g} Hz)"
    )


#: How the refusal of a time bound over the well-conditioned points names it (printed
#: rounded up to 0.01 tick); `refused_time_bound` reads it back.
REGION_REFUSAL = "bounds t_com's error by"
_REGION_REFUSED = re.compile(re.escape(REGION_REFUSAL) + r" (\d+\.\d{2}) Hall ticks where")


def refused_time_bound(message: str) -> Fraction | None:
    """The t_com bound (Hall ticks) a paper core's refusal over the spec's
    well-conditioned points names (`_region_refusal`), or None for another message."""
    found = _REGION_REFUSED.search(message)
    return Fraction(found.group(1)) if found else None


def _region_refusal(
    spec: Spec, sc: Scaling, c: PaperConstants, region: tuple[Fraction, int]
) -> str:
    """Why every safe format misses the target where the spec holds t_com to it: X's
    format, as wide as Eq. 20's product leaves it, errs by up to half an LSB of W, which
    a time of up to ill_conditioned_above ticks a count turns into more than the target.
    Each halving of the Hall clock halves K_G and gives X one more bit."""
    bound, f = region
    target = _fraction(spec.accuracy.commutation_time_ticks)
    above = _fraction(spec.accuracy.ill_conditioned_above)
    needed = max(_bits_needed(spec, f), f + 1)
    clock = _fraction(sc.hall_clock_hz)
    timer = _fraction(spec.inverter.timer_clock_hz)
    limit = clock / 2 ** (needed - f)
    divider = -(-timer // limit)
    return (
        f"hall.timer_clock = {float(clock):.10g} Hz: X's widest safe format, Q{f} (Eq. 20's"
        f" numerator times the current code fills int32_t), {REGION_REFUSAL}"
        f" {math.ceil(bound * 100) / 100:.2f} Hall ticks where the spec holds it to"
        f" accuracy.commutation_time_ticks = {float(target):g} (where one count of W moves"
        f" it by at most accuracy.ill_conditioned_above = {float(above):g} ticks): half an LSB"
        f" of W times {float(above):g} ticks a count; each halving of the Hall clock gives X"
        f" one more bit (allowed: <= {float(limit):.6g} Hz, {float(timer):.10g} Hz / N for"
        f" N >= {divider}: {float(timer / divider):.10g} Hz)"
    )


class PaperMethod:
    def __init__(self, rule: DutyRule) -> None:
        self.rule = rule
        self.name = rule.method
        self.uses_main_duty = rule.uses_main_duty

    def _prove(self, limits: CoreLimits, c: PaperConstants, fmt: PaperFormats) -> _Candidate:
        bus_fn = bus_condition_function(limits, c, fmt)
        timing = timing_function(limits, c, fmt, self.rule)
        prover = new_prover((bus_fn, timing))
        bus = prove_function(prover, bus_fn)
        fields = {f"bus.{k}": v for k, v in bus.struct_returns.items()}
        prove_function(prover, timing, fields)
        return self._errors(prover, timing, limits, c, fmt, fields)

    def _errors(
        self,
        prover: Prover,
        timing: Function,
        limits: CoreLimits,
        c: PaperConstants,
        fmt: PaperFormats,
        fields: dict[str, Interval],
    ) -> _Candidate:
        """Errors of X_q, the duties and the time numerator from the printed IR."""
        n_x, n_g, _ = paper_numerators(c, fmt)
        bus_range = Interval(limits.bus_min.value, limits.bus_max.value)
        from codegen.ir.errors import error
        from codegen.ir.nodes import ILongDiv, var

        code = var("code", U32)
        env = {"code": bus_range}
        e_xn = error(prover, ILongDiv(U32, n_x, code), env, {})
        e_tn = error(prover, ILongDiv(U32, n_g, code), env, {})
        inputs = {
            "period_ticks": Interval(limits.period_min.value, limits.period_cap.value),
            "current_adc": Interval(0, limits.adc_max.value),
            "main_duty_counts": Interval(0, limits.period_counts.value),
            **fields,
            "bus.period_min": Interval(limits.period_min.value, limits.period_min.value),
        }
        errs = {"bus.x_numerator": e_xn, "bus.time_numerator": e_tn}
        body = tuple(s for s in timing.body)
        try:
            out = walk_errors(prover, body, dict(inputs), errs)
        except ErrorAnalysisError as exc:
            raise FixedPointError(f"error analysis of {timing.c_name}: {exc}") from None
        duty = max(out.get("on", Fraction(10**9)), out.get("off", Fraction(10**9)))
        return _Candidate(fmt, prover, fields, duty, out["x_q"], e_tn)

    def _time_bound(self, sc: Scaling, cand: _Candidate, w_counts: Fraction) -> Fraction:
        scale = 1 << cand.formats.x_frac_bits
        tn = cand.bus_fields["bus.time_numerator"]
        eps_g = cand.time_numerator_error / max(tn.lo, 1)
        eps_w = cand.x_q_error / (w_counts * scale)
        if eps_w >= 1:
            return Fraction(10**9)
        e_off = cand.formats.current.offset_q.error
        cap = sc.period_cap_ticks
        return (
            Fraction(1, 2)
            + cap * (eps_g + eps_w) / (1 - eps_w)
            + tn.hi * (1 + eps_g) * e_off / (w_counts * scale * (1 - eps_w))
        )

    def _region_bound(self, spec: Spec, sc: Scaling, cand: _Candidate) -> Fraction:
        """The t_com error bound over the points `verify` holds to the target: where the
        spec declares a relaxation, those whose exact time moves by at most A =
        ill_conditioned_above ticks a count of W (t* <= A W), else every point whose
        exact time is below the counter's cap. The W_ok of `_w_ok` does not bound them:
        a small current makes t* small at any W, so such points reach down to

            W_min = sqrt(G I_min / A)  (t* = G I / W <= A W),  or G I_min / T_cap,

        with G = tn 2^-f m the time numerator per code at the widest bus code and I_min
        the smallest positive current (codes) the offset leaves. There the W error
        delta = e(X_q) / 2^f moves t by t* delta / W <= min(A delta, T_cap delta / W_min),
        and the numerator's relative error eps_g by t* eps_g, with t*^2 <= A W G I / W
        <= A G_max I_max (the widest current code from the offset)."""
        fmt = cand.formats
        scale = 1 << fmt.x_frac_bits
        tn = cand.bus_fields["bus.time_numerator"]
        eps_g = cand.time_numerator_error / max(tn.lo, 1)
        delta = cand.x_q_error / scale
        cap = Fraction(sc.period_cap_ticks)
        g_min = Fraction(tn.lo * fmt.current.scale, scale)
        offset = fmt.current.offset_exact
        residue = offset - math.floor(offset)
        i_min = 1 - residue if residue else Fraction(1)
        above = spec.accuracy.ill_conditioned_above
        if above is None:
            w_min = g_min * i_min / cap
            spread_cap = None
        else:
            square = g_min * i_min / above  # W_min^2, taken from below (a smaller W_min is safe)
            w_min = Fraction(math.isqrt(square * 2**80 // 1), 2**40)
            spread_cap = above * delta
        if w_min <= delta:
            return Fraction(10**9)
        spread = cap * delta / w_min
        longest = cap
        if spread_cap is not None:
            spread = min(spread, spread_cap)
            g_max = Fraction(tn.hi * fmt.current.scale, scale)
            i_max = max(offset, sc.adc_full_scale - 1 - offset)
            square = above * g_max * i_max  # t*^2, taken from above
            longest = min(cap, Fraction(math.isqrt(math.ceil(square)) + 1))
        e_off = fmt.current.offset_q.error
        off = tn.hi * (1 + eps_g) * e_off / (w_min * scale)
        return Fraction(1, 2) + (longest * eps_g + spread + off) / (1 - delta / w_min)

    def _w_ok(self, sc: Scaling, cand: _Candidate, target: Fraction) -> Fraction | None:
        hi = Fraction(4 * sc.period_counts)
        if self._time_bound(sc, cand, hi) > target:
            return None
        lo = Fraction(1, 2**20)
        for _ in range(40):
            mid = (lo + hi) / 2
            lo, hi = (mid, hi) if self._time_bound(sc, cand, mid) > target else (lo, mid)
        return Fraction(-(-hi * 1000 // 1), 1000)

    def design(self, spec: Spec, sc: Scaling, limits: CoreLimits) -> CoreDesign:
        c = PaperConstants(_fraction(sc.k_x), _fraction(sc.k_g), sc.period_counts)
        duty_target = _fraction(spec.accuracy.duty_counts)
        time_target = _fraction(spec.accuracy.commutation_time_ticks)
        reasons: list[str] = []
        #: the tightest t_com bound any format that fits reaches (at the widest W)
        reach: tuple[Fraction, int] | None = None
        #: the tightest bound over the spec's well-conditioned points (`_region_bound`)
        region: tuple[Fraction, int] | None = None
        safe = False  # some format proven free of overflow
        for f in range(MAX_FRACTION_BITS, -1, -1):
            best: tuple[Fraction, _Candidate] | None = None
            for current in current_formats(sc):
                fmt = PaperFormats(f, current)
                try:
                    cand = self._prove(limits, c, fmt)
                except ProofError as exc:
                    reasons.append(f"Q{f}, current x{current.scale}: {exc}")
                    continue
                safe = True
                w_ok = self._w_ok(sc, cand, time_target)
                if w_ok is None:
                    bound = self._time_bound(sc, cand, Fraction(4 * sc.period_counts))
                    if reach is None or bound < reach[0]:
                        reach = (bound, f)
                    continue
                if spec.accuracy.ill_conditioned_above is not None:
                    # met at the widest W: the points of small current and small W
                    # (`_region_bound`) are what X's format may still miss
                    bound = self._region_bound(spec, sc, cand)
                    if bound > time_target:
                        if region is None or bound < region[0]:
                            region = (bound, f)
                        continue
                key = w_ok
                if best is None or key < best[0]:
                    best = (key, cand)
            if best is None:
                continue
            w_ok, cand = best
            if cand.duty_error > duty_target:
                raise FixedPointError(
                    f"the best format, Q{f}, gives a duty error of {float(cand.duty_error):.3f} counts, "
                    f"above accuracy.duty_counts = {float(duty_target)}",
                    "accuracy.duty_counts",
                )
            return self._finish(spec, sc, limits, c, cand, w_ok)
        if not safe:
            # Not the time target: no format is safe at all, Q0 included (a 72 MHz Hall
            # clock's Eq. 20 numerator times the current code overflows int32_t, and the
            # message blamed accuracy.commutation_time_ticks, which no value could meet).
            timer = _fraction(spec.inverter.timer_clock_hz)
            raise FixedPointError(
                _numerator_overflow(spec, sc, c, timer, reasons[-1]), "hall.timer_clock"
            )
        if region is not None:
            # a format met the target at the widest W and missed it only where a small
            # current meets a small W: more bits of X, from a slower Hall clock
            raise FixedPointError(_region_refusal(spec, sc, c, region), "hall.timer_clock")
        if reach is not None:
            # formats fit, none meets the target: say what they do meet (the internal
            # overflows of the ones that do not fit said nothing a user could act on)
            least = math.ceil(float(reach[0]) * 1000) / 1000
            allowed = (
                f">= {least:g} ticks"
                if least <= COMMUTATION_TICKS_MAX
                else f"none up to the loader's limit {COMMUTATION_TICKS_MAX} ticks"
            )
            raise FixedPointError(
                f"accuracy.commutation_time_ticks = {float(time_target):g} ticks: no format"
                f" from Q0 to Q{MAX_FRACTION_BITS} is both safe and accurate enough; the"
                f" best, Q{reach[1]}, bounds the commutation time's error by"
                f" {float(reach[0]):.4g} Hall timer ticks (allowed: {allowed})",
                "accuracy.commutation_time_ticks",
            )
        detail = "; ".join(reversed(reasons[-3:])) if reasons else "the time target is out of reach"
        raise FixedPointError(
            f"no format from Q0 to Q{MAX_FRACTION_BITS} is both safe and accurate enough for "
            f"accuracy.commutation_time_ticks = {float(time_target)}: {detail}",
            "accuracy.commutation_time_ticks",
        )

    def _finish(
        self,
        spec: Spec,
        sc: Scaling,
        limits: CoreLimits,
        c: PaperConstants,
        cand: _Candidate,
        w_ok: Fraction,
    ) -> CoreDesign:
        fmt = cand.formats
        f = fmt.x_frac_bits
        time_bound = self._time_bound(sc, cand, w_ok)
        n_x, n_g, tb = paper_numerators(c, fmt)
        current: CurrentFormat = fmt.current
        offset_note = (
            "exact"
            if current.is_exact
            else f"within {float(current.offset_q.error / current.scale):.2g} code"
        )
        doc = (
            f'Method "{self.name}".',
            *self.rule.doc,
            "",
            "Formats (codegen/methods/paper_method.py chose them; the IR proof checked them):",
            f"  X = P 4E/U_d = K_X / (T B), K_X = {float(c.k_x):.6e} counts ticks codes (Eqs. 3, 9)",
            f"  per bus code B: x_numerator = round(N_X / B), N_X = {n_x.value};",
            f"    time_numerator = round(N_G / B), N_G = {n_g.value}, K_G = {float(c.k_g):.6e}",
            "    (Eq. 20: t_com f_hall = K_G I_code / (B W));",
            f"    high_speed_period = ceil(C / B), C = {tb.value}: T < it <=> 4E > U_d (exact)",
            f"  per speed: X_q = round(x_numerator / T) in Q{f}, X_c = round(X_q / 2^{f});",
            f"    current i_m = {current.scale} C - {current.offset_q.value} (offset {float(current.offset_exact):.6g} codes, {offset_note});",
            f"    W_q = (2P + 2 C_on - 4 C_off) 2^{f} - X_q; t_com = round(time_numerator i_m / W_q),",
            "    saturated to [0, T] (W_q <= 0: the current never reaches zero, t_com = T)",
            "  rounding is half up everywhere.",
            f"Claimed bounds (IR error analysis): duties <= {round_up(cand.duty_error)} counts;",
            f"  t_com <= {round_up(time_bound)} ticks wherever W >= {float(w_ok):g} counts.",
        )
        formats: dict[str, int | float | str] = {
            "x_frac_bits": f,
            "time_bound_min_w_counts": float(w_ok),
            "current_scale": current.scale,
            "current_offset_q": current.offset_q.value,
            "n_x": n_x.value,
            "n_g": n_g.value,
            "high_speed_tb": tb.value,
        }
        bus_fn = bus_condition_function(limits, c, fmt)
        timing = timing_function(limits, c, fmt, self.rule)
        return CoreDesign(
            method=self.name,
            uses_main_duty=self.uses_main_duty,
            bus_struct=BUS,
            bus_condition=bus_fn,
            commutation_timing=timing,
            tables=(),
            doc=doc,
            extra_constants=(IConst(U32, f, "BLDC_X_FRAC_BITS", doc="fraction bits of X_q"),),
            ranges=cand.prover.ranges,
            claims=Claims(
                duty_counts=round_up(cand.duty_error),
                time_ticks=round_up(time_bound),
                time_region=f"W >= {float(w_ok):g} counts",
            ),
            formats=formats,
            summary=(
                f"X in Q{f}, current x{current.scale} ({offset_note}); bounds: duties "
                f"{round_up(cand.duty_error)} counts, t_com {round_up(time_bound)} ticks where W >= {float(w_ok):g} counts"
            ),
        )

"""Checks of the paper's tables, numbering and statements against the derivation.

Each check returns `Check` records: what was checked, the paper's words, a verdict
("consistent", "contradiction" or "minor"), the reason, a one-line summary and the
equations it concerns. Numbers use the paper's own Table 3 motor (U_d = 24 V,
k_e = 2.36 V/krpm, from the transcription), never a user's spec: the audit is of the
paper, the same for every motor.
"""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass
from itertools import pairwise

import sympy as sp

from codegen.audit.transcription import Range, Transcription, parse_printed
from codegen.derivation import symbols as s
from codegen.derivation.intervals import solve_inequality
from codegen.derivation.paper import Derivation

CONSISTENT = "consistent"
CONTRADICTION = "contradiction"
MINOR = "minor"


@dataclass(frozen=True)
class Check:
    id: str
    where: str
    quote: str
    verdict: str
    detail: str
    #: One line for the findings list (math between $...$).
    summary: str
    #: Keys of the printed equations the check concerns ("18", "1b").
    refs: tuple[str, ...]


def _table3(tr: Transcription) -> dict[sp.Symbol, sp.Expr]:
    return {s.U_d: tr.table3_voltage, s.k_e: tr.table3_ke_per_krpm / 1000}


def _interval(rng: Range, tr: Transcription) -> sp.Interval:
    low = parse_printed(rng.low, tr).expr
    high = parse_printed(rng.high, tr).expr
    return sp.Interval(low, high, rng.low_open, rng.high_open)


def _same_interval(a: sp.Interval, b: sp.Interval) -> bool:
    return (
        sp.simplify(a.start - b.start) == 0
        and sp.simplify(a.end - b.end) == 0
        and a.left_open == b.left_open
        and a.right_open == b.right_open
    )


def equation_labels(tr: Transcription) -> list[Check]:
    """Printed labels against the order of the display equations."""
    labels = [eq.label for eq in sorted(tr.equations, key=lambda e: e.sequence)]
    out: list[Check] = []
    for label, count in sorted(Counter(labels).items()):
        if count > 1:
            where = ", ".join(
                f"display {eq.sequence} ({eq.title})" for eq in tr.equations if eq.label == label
            )
            out.append(
                Check(
                    f"label-{label}-twice",
                    "labels",
                    f"({label})",
                    CONTRADICTION,
                    f"label ({label}) is printed {count} times: {where}",
                    f"label ({label}) is printed {count} times",
                    tuple(eq.key for eq in tr.equations if eq.label == label),
                )
            )
    ordered = sorted(tr.equations, key=lambda e: e.sequence)
    for before, after in pairwise(ordered):
        previous, current = before.label, after.label
        if current < previous:
            out.append(
                Check(
                    f"label-{current}-order",
                    "labels",
                    f"({current})",
                    CONTRADICTION,
                    f"label ({current}) follows ({previous}): out of order",
                    f"label ({current}) follows ({previous})",
                    (before.key, after.key),
                )
            )
    shifted = [eq for eq in tr.equations if eq.sequence - eq.label == 2]
    if shifted:
        first = min(eq.sequence for eq in shifted)
        out.append(
            Check(
                "labels-shifted",
                "labels",
                "(3) ... (20)",
                CONTRADICTION,
                f"from display equation {first} on, every printed label is its position"
                f" minus 2 ({len(shifted)} equations): the paper has 22 display equations"
                " but labels them (1)-(20)",
                f"from display equation {first} on, each label is its position minus 2",
                (),
            )
        )
    return out


def citations(tr: Transcription) -> list[Check]:
    out = []
    for index, cite in enumerate(tr.citations):
        eq = tr.equation(cite.means)
        if cite.cited == eq.label:
            verdict, detail = (
                CONSISTENT,
                f"cites ({cite.cited}), the printed label of Eq. {eq.label}",
            )
            summary = f"({cite.cited}) is Eq. ({eq.label}), as printed"
        else:
            by_sequence = " = its position in the paper" if cite.cited == eq.sequence else ""
            verdict = CONTRADICTION
            detail = (
                f"cites ({cite.cited}) for the equation printed as ({eq.label}), "
                f"display equation {eq.sequence}{by_sequence}: {eq.title}"
            )
            summary = f"cites ({cite.cited}) for Eq. ({eq.label}), display equation {eq.sequence}"
        out.append(
            Check(
                f"cite-{index + 1}",
                f"section {cite.section}",
                cite.quote,
                verdict,
                detail,
                summary,
                (eq.key,),
            )
        )
    return out


def table2(tr: Transcription, d: Derivation) -> list[Check]:
    rule = d["18"]
    derived_speed = {"high": rule.row("high_region"), "low": rule.row("low_region")}
    out = []
    for row in tr.table2:
        where = f"Table 2, {row.quantity}, {row.region}-speed row"
        speed = _interval(row.speed, tr)
        emf = _interval(row.emf, tr)
        emf_from_speed = sp.Interval(
            sp.simplify(speed.start * s.k_e),
            sp.simplify(speed.end * s.k_e),
            speed.left_open,
            speed.right_open,
        )
        problems = []
        shorts = []
        if not _same_interval(speed, derived_speed[row.region]):
            shorts.append("speed range differs from Eq. 18")
            problems.append(
                f"speed range ${sp.latex(speed)}$ differs from Eq. 18's "
                f"${sp.latex(derived_speed[row.region])}$"
            )
        if not _same_interval(emf, emf_from_speed):
            shorts.append(
                f"back-EMF range ${sp.latex(emf)}$ is not the row's speed range times $k_e$"
            )
            problems.append(
                f"back-EMF range ${sp.latex(emf)}$ contradicts the row's own speed range"
                f" (E = k_e n gives ${sp.latex(emf_from_speed)}$)"
            )
        duty = parse_printed(row.duty, tr).expr
        derived_duty = rule.row(f"{'on' if row.quantity == 'D_on' else 'off'}_{row.region}")
        if sp.simplify(duty - derived_duty) != 0:
            shorts.append("duty differs from Eq. 18")
            problems.append(
                f"duty ${sp.latex(duty)}$ differs from Eq. 18's ${sp.latex(derived_duty)}$"
            )
        quote = f"{row.quantity}: n in ${sp.latex(speed)}$, E in ${sp.latex(emf)}$, duty ${sp.latex(duty)}$"
        if problems:
            out.append(
                Check(
                    f"table2-{row.quantity}-{row.region}",
                    where,
                    quote,
                    CONTRADICTION,
                    "; ".join(problems),
                    "; ".join(shorts),
                    ("18",),
                )
            )
        else:
            out.append(
                Check(
                    f"table2-{row.quantity}-{row.region}",
                    where,
                    quote,
                    CONSISTENT,
                    "speed range, EMF range and duty agree with Eq. 18",
                    "agrees with Eq. 18",
                    ("18",),
                )
            )
    return out


def table4(tr: Transcription, d: Derivation) -> list[Check]:
    boundary = d["18"].row("boundary_speed").subs(_table3(tr))
    out = []
    for row in tr.table4:
        region = "low" if row.speed_rpm <= boundary else "high"
        if region == "low":
            expected = "turn-on phase held on (1 transition), turn-off phase modulated"
            ok = row.improved_on == 1 and row.improved_off > 1
        else:
            expected = "turn-off phase held off (1 transition), turn-on phase modulated"
            ok = row.improved_off == 1 and row.improved_on > 1
        both_modulated = row.conventional_on > 1 and row.conventional_off > 1
        quote = (
            f"{row.speed_rpm} rpm: conventional on/off {row.conventional_on}/{row.conventional_off},"
            f" improved on/off {row.improved_on}/{row.improved_off}"
        )
        detail = (
            f"{row.speed_rpm} rpm is in Eq. 18's {region}-speed segment (cut-off "
            f"{float(boundary):.1f} rpm with Table 3): expected {expected}"
        )
        if ok and both_modulated:
            out.append(
                Check(
                    f"table4-{row.speed_rpm}",
                    "Table 4",
                    quote,
                    CONSISTENT,
                    detail,
                    f"{row.speed_rpm} rpm: the {region}-speed pattern, as Eq. 18 gives",
                    ("18",),
                )
            )
        else:
            observed = (
                "turn-on phase modulated and turn-off phase switched once"
                if row.improved_off == 1
                else "turn-on phase switched once"
            )
            out.append(
                Check(
                    f"table4-{row.speed_rpm}",
                    "Table 4",
                    quote,
                    CONTRADICTION,
                    f"{detail}; the table shows {observed}, the other segment's pattern",
                    f"the {row.speed_rpm} rpm row shows the other segment's pattern, though"
                    f" {row.speed_rpm} rpm is {'below' if region == 'low' else 'above'} the"
                    f" {float(boundary):.1f} rpm cut-off",
                    ("18",),
                )
            )
    return out


def figures(tr: Transcription) -> list[Check]:
    out = []
    for fig in tr.figures:
        if fig.text == fig.caption:
            out.append(
                Check(
                    f"fig-{fig.text}",
                    "figure captions",
                    fig.caption_text,
                    CONSISTENT,
                    f"text and caption both number it {fig.text}",
                    f"Fig. {fig.text} is captioned Fig. {fig.caption}",
                    (),
                )
            )
        else:
            out.append(
                Check(
                    f"fig-{fig.text}",
                    "figure captions",
                    fig.caption_text,
                    CONTRADICTION,
                    f"the text calls it Fig. {fig.text}; its caption is numbered {fig.caption},"
                    " a number already used by an earlier figure",
                    f"Fig. {fig.text} is captioned Fig. {fig.caption}",
                    (),
                )
            )
    return out


def _region_at(d: Derivation, tr: Transcription, speed: float) -> str:
    boundary = d["18"].row("boundary_speed").subs(_table3(tr))
    return "low" if sp.nsimplify(speed) <= boundary else "high"


def claims(tr: Transcription, d: Derivation) -> list[Check]:
    example = d.switching.paper_example()
    roles = {
        example.non_commutating: "non_commutating",
        example.turn_off: "turn_off",
        example.turn_on: "turn_on",
    }
    phase_index = {"a": 0, "b": 1, "c": 2}
    values = _table3(tr)
    out = []
    for claim in tr.claims:
        where = f"section {claim.section}"
        verdict, detail, summary, refs = CONSISTENT, "", "", ("18",)
        if claim.kind == "phase_role":
            actual = roles[phase_index[claim.get("phase")]]
            claimed = claim.get("role")
            verdict = CONSISTENT if actual == claimed else CONTRADICTION
            detail = (
                f"calls i_{claim.get('phase')} the {claimed.replace('_', '-')} phase current; at the"
                f" paper's 60 deg edge (BA to CA) phase {claim.get('phase').upper()} is the"
                f" {actual.replace('_', '-')} phase"
            )
            summary = (
                f"calls $i_{claim.get('phase')}$ the {claimed.replace('_', '-')} phase current;"
                f" phase {claim.get('phase').upper()} is the {actual.replace('_', '-')} phase"
            )
            refs = ("3b",)
        elif claim.kind == "switch_pattern":
            got = (example.modulated_on, example.modulated_off, example.freewheel_diode)
            want = (claim.get("modulated_on"), claim.get("modulated_off"), claim.get("freewheel"))
            verdict = CONSISTENT if got == want else CONTRADICTION
            detail = f"switching table: {example.describe()}"
            summary = f"{want[0]} modulated, {want[1]} off, return through {want[2]}: " + (
                "as the derived switching table" if got == want else "not the switching table"
            )
            refs = ("3b",)
        elif claim.kind == "faster_phase":
            slopes = d["17"]
            margin = -slopes.row("b") - slopes.row("c")  # |off slope| - |on slope|
            cond = margin > 0 if claim.get("faster") == "turn_off" else margin < 0
            holds = solve_inequality(cond, s.E)
            holds_n = sp.Interval(
                sp.simplify(holds.start / s.k_e),
                sp.simplify(holds.end / s.k_e),
                holds.left_open,
                holds.right_open,
            )
            low_text, high_text = (
                claim.get("region").split("<")[0],
                claim.get("region").split("<")[-1],
            )
            region = sp.Interval(
                parse_printed(low_text.strip(), tr).expr,
                parse_printed(high_text.strip(), tr).expr,
                True,
                True,
            )
            inside = bool(
                sp.simplify(region.start - holds_n.start).is_extended_nonnegative
            ) and bool(sp.simplify(holds_n.end - region.end).is_extended_nonnegative)
            verdict = CONSISTENT if inside else CONTRADICTION
            detail = (
                f"Eq. 17: the {claim.get('faster').replace('_', '-')} phase is faster for n in"
                f" ${sp.latex(holds_n.intersect(sp.Interval.open(0, sp.oo)))}$"
            )
            summary = (
                f"the {claim.get('faster').replace('_', '-')} phase is faster on"
                f" ${sp.latex(region)}$: {'as' if inside else 'not what'} Eq. (17) gives"
            )
            refs = ("17",)
        elif claim.kind == "fail_area":
            condition = parse_printed(
                claim.get("condition").split(">")[0].split("<")[0].strip(), tr
            ).expr
            d_off = d["16"].row("")
            # Eq. 16: D_off = 2 - (D_on + 4E/U_d): negative iff the sum exceeds 2, above 1 iff
            # the sum is below 1.
            below = claim.get("consequence") == "below"
            ok = sp.simplify(d_off + condition - 2) == 0
            verdict = CONSISTENT if ok else CONTRADICTION
            detail = (
                f"Eq. 16 gives $D_{{off}} = {sp.latex(d_off)}$, so $D_{{off}}$ is "
                f"{'negative' if below else 'above 1'} exactly when "
                f"${sp.latex(condition)} {'>' if below else '<'} {2 if below else 1}$"
            )
            summary = (
                f"$D_{{off}} {'< 0' if below else '> 1'}$ exactly when"
                f" ${sp.latex(condition)} {'>' if below else '<'} {2 if below else 1}$"
                + ("" if ok else ": not what Eq. (16) gives")
            )
            refs = ("16",)
        elif claim.kind == "equivalent_conditions":
            first = claim.get("first")
            lhs, rhs = (parse_printed(x.strip(), tr).expr for x in first.split("<"))
            set_first = solve_inequality((lhs < rhs).subs(s.E, s.k_e * s.n), s.n)
            second = claim.get("second")
            bound = parse_printed(second.split("\\leq")[-1].strip(), tr).expr
            set_second = sp.Interval(0, bound)
            same_ends = sp.simplify(set_first.end - set_second.end) == 0
            verdict = (
                MINOR
                if same_ends and set_first.right_open != set_second.right_open
                else (CONSISTENT if same_ends else CONTRADICTION)
            )
            detail = (
                f"${first}$ means $n < {sp.latex(set_first.end)}$ (open), but 'namely' "
                f"${second}$ includes $n = {sp.latex(bound)}$, where 2E = U_d and braking is lost"
            )
            summary = (
                f"'namely ${second}$' includes $n = {sp.latex(bound)}$, where $2E = U_d$"
                if verdict == MINOR
                else f"${first}$ is ${second}$"
            )
        elif claim.kind == "number":
            value = d["18"].row(claim.get("expression")).subs(values)
            verdict = (
                CONSISTENT if round(float(value)) == int(claim.get("value")) else CONTRADICTION
            )
            detail = f"Eq. 18 with Table 3: U_d/(4 k_e) = {float(value):.2f} rpm"
            summary = (
                f"{claim.get('value')} rpm: Eq. (18) with Table 3 gives {float(value):.2f} rpm"
            )
        elif claim.kind == "region_overlap":
            rule = d["18"]
            at = {**values, s.E: values[s.U_d] / 4}
            on_gap = sp.simplify(rule.row("on_high").subs(at) - rule.row("on_low").subs(at))
            off_gap = sp.simplify(rule.row("off_high").subs(at) - rule.row("off_low").subs(at))
            verdict = CONSISTENT if on_gap == 0 and off_gap == 0 else CONTRADICTION
            detail = (
                "both segments claim the cut-off speed, which is harmless: Eq. 18 is continuous"
                " there (both give D_on = 1, D_off = 0)"
            )
            summary = (
                "both segments claim the cut-off speed: harmless, Eq. (18) is continuous there"
            )
        elif claim.kind == "speed_condition":
            region = _region_at(d, tr, claim.get("speed"))
            four_e = float(4 * values[s.k_e] * claim.get("speed"))
            verdict = CONSISTENT if region == claim.get("region") else CONTRADICTION
            detail = (
                f"4 k_e n = {four_e:.2f} V against U_d = {float(values[s.U_d]):g} V: "
                f"{region}-speed segment"
            )
            summary = f"{claim.get('speed')} rpm is in the {region}-speed segment"
        elif claim.kind == "conventional_fails":
            n = sp.nsimplify(claim.get("speed"))
            duty = sp.nsimplify(str(claim.get("main_duty")))
            d_off = d["16"].row("").subs({**values, s.E: values[s.k_e] * n, s.D_on: duty})
            fails = not 0 <= d_off <= 1
            verdict = CONSISTENT if fails else CONTRADICTION
            detail = (
                f"Eq. 16 with D_on = {float(duty):g} at {n} rpm: D_off = {float(d_off):.3f}, "
                f"{'outside' if fails else 'inside'} [0, 1] (control fail area), so the"
                " residual ripple of Fig. 13 is what the equations predict"
            )
            summary = (
                f"$D_{{off}} = {float(d_off):.3f}$ at {n} rpm with $D_{{on}} = {float(duty):g}$:"
                f" {'in' if fails else 'outside'} the control fail area"
            )
            refs = ("16",)
        elif claim.kind == "pattern_speed":
            region = _region_at(d, tr, claim.get("speed"))
            verdict = CONSISTENT if region == claim.get("pattern") else CONTRADICTION
            detail = (
                f"turn-on phase held on while the turn-off phase is modulated is Eq. 18's "
                f"{claim.get('pattern')}-speed branch; {claim.get('speed')} rpm is in the "
                f"{region}-speed segment"
            )
            summary = (
                f"says {claim.get('speed')} rpm ({region}-speed segment) for the"
                f" {claim.get('pattern')}-speed pattern"
                if verdict == CONTRADICTION
                else f"{claim.get('speed')} rpm: the {region}-speed pattern, as Eq. (18) gives"
            )
        else:
            raise ValueError(f"unknown claim kind {claim.kind!r}")
        out.append(Check(claim.id, where, claim.quote, verdict, detail, summary, refs))
    return out


def defects(tr: Transcription) -> list[Check]:
    return [
        Check(f"defect-{i + 1}", f"section {x.section}", x.quote, CONTRADICTION, x.what, x.what, ())
        for i, x in enumerate(tr.defects)
    ]

"""Turn an AuditResult into the Markdown report (templates/AUDIT.md.j2).

Everything the template needs is printed here into strings; the template only lays
it out. Math is LaTeX between $...$ / $$...$$, which code hosts render.
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from codegen.audit.compare import RowResult, Verdict
from codegen.audit.run import AuditResult, EquationAudit
from codegen.audit.transcription import Transcription
from codegen.derivation.figures import SpecFigures, spec_figures
from codegen.derivation.paper import Derivation
from codegen.derivation.switching import PHASE_NAMES
from codegen.render import provenance, render
from codegen.spec_model import Spec

TEMPLATE = "AUDIT.md.j2"

ICONS = {
    Verdict.MATCH: "✅ match",
    Verdict.NOTATION: "✅ match (notation)",
    Verdict.ENDPOINT: "⚠️ end point differs",
    Verdict.MISMATCH: "❌ mismatch",
    Verdict.MODEL: "📘 model",
}
CHECK_ICONS = {"consistent": "✅", "contradiction": "❌", "minor": "⚠️"}


@dataclass(frozen=True)
class Counts:
    rows: int
    match: int
    notation: int
    endpoint: int
    mismatch: int
    findings: int
    errors: int
    inconsistencies: int
    minor: int


def _row_display(row: RowResult, value: sp.Basic, var: str) -> str:
    """One aligned line of the derived block: `lhs &= rhs`."""
    if isinstance(value, sp.Equality):
        return f"{sp.latex(value.lhs)} &= {sp.latex(value.rhs)}"
    if isinstance(value, sp.Set):
        return f"{var} &\\in {sp.latex(value)}"
    if row.lhs == "0":
        return f"{sp.latex(value)} &= 0"
    return f"{row.lhs} &= {sp.latex(value)}"


def _derived_block(eq: EquationAudit, derivation: Derivation, tr: Transcription) -> str:
    if eq.verdict == Verdict.MODEL:
        return ""
    result = derivation[eq.key]
    printed = tr.equation(eq.key)
    lines = []
    for row, printed_row in zip(eq.rows, printed.rows, strict=True):
        var = printed_row.var or "x"
        lines.append(_row_display(row, result.row(row.name), var))
    return " \\\\ ".join(lines)


def _equation_context(
    eq: EquationAudit, derivation: Derivation, tr: Transcription
) -> dict[str, object]:
    return {
        "label": eq.label,
        "key": eq.key,
        "title": eq.title,
        "section": eq.section,
        "sequence": eq.sequence,
        "printed": eq.printed,
        "derived": _derived_block(eq, derivation, tr),
        "verdict": ICONS[eq.verdict],
        "method": eq.derivation_method,
        "reliance": eq.reliance,
        "rows": [
            {
                "name": row.name or "-",
                "verdict": ICONS[row.verdict],
                "method": row.method,
                "findings": list(row.findings),
                "notes": list(row.notes),
            }
            for row in eq.rows
        ],
    }


def _fmt(value: sp.Expr, digits: int = 4) -> str:
    return f"{float(value):.{digits}g}"


def _figures_context(figs: SpecFigures, spec: Spec) -> list[dict[str, str]]:
    rows = [
        {
            "quantity": "segment cut-off $U_d/(4k_e)$",
            "value": f"{_fmt(figs.boundary_speed_rpm, 5)} rpm",
            "source": "Eq. 18",
        },
        {
            "quantity": "upper limit $U_d/(2k_e)$",
            "value": f"{_fmt(figs.upper_speed_rpm, 5)} rpm",
            "source": "Eqs. 11, 18",
        },
    ]
    for p in figs.points:
        n = f"{int(p.speed_rpm)} rpm"
        rows += [
            {"quantity": f"segment at {n}", "value": p.region, "source": "Eq. 18"},
            {
                "quantity": f"improved $D_{{on}}$ at {n}",
                "value": _fmt(p.improved_on),
                "source": "Eq. 18",
            },
            {
                "quantity": f"improved $D_{{off}}$ at {n}",
                "value": _fmt(p.improved_off),
                "source": "Eq. 18",
            },
            {
                "quantity": f"improved $t_{{com}}$ at {n}, I = {float(spec.controller.braking_current_nominal_a):g} A",
                "value": f"{float(p.improved_t_com_s) * 1e6:.0f} us of a {float(p.sector_time_s) * 1e6:.0f} us sector",
                "source": "Eq. 20",
            },
            {
                "quantity": f"conventional $D_{{off}}$ at {n}, $D_{{on}}$ = {float(p.main_duty):g}",
                "value": _fmt(p.conventional_off)
                + (" (control fail area)" if p.conventional_fails else ""),
                "source": "Eq. 16",
            },
        ]
    return rows


def _switching_context(derivation: Derivation, spec: Spec) -> list[dict[str, str]]:
    table = derivation.switching
    rows = []
    for direction in ("forward", "reverse"):
        sectors = table.sectors(direction)
        for k in range(6):
            edge = table.edge_into(k, direction)
            rows.append(
                {
                    "direction": direction,
                    "hall": f"{spec.hall.sequence[k]} ({spec.hall.sequence[k]:03b})",
                    "sector": f"{60 * k}-{60 * (k + 1)}",
                    "pair": sectors[k].pair_name(),
                    "edge": f"{edge.angle_deg % 360}",
                    "non_commutating": f"{PHASE_NAMES[edge.non_commutating]} via {edge.freewheel_diode}",
                    "turn_off": f"{PHASE_NAMES[edge.turn_off]}: {edge.modulated_off} at $D_{{off}}$",
                    "turn_on": f"{PHASE_NAMES[edge.turn_on]}: {edge.modulated_on} at $D_{{on}}$",
                    "kind": edge.kind,
                    "after": f"{edge.modulated_on} at main duty",
                }
            )
    return rows


def _checks(group: tuple) -> list[dict[str, str]]:
    return [
        {
            "id": c.id,
            "where": c.where,
            "quote": c.quote,
            "icon": CHECK_ICONS[c.verdict],
            "verdict": c.verdict,
            "detail": c.detail,
        }
        for c in group
    ]


def counts(result: AuditResult) -> Counts:
    severities = [f.severity for f in result.findings]
    return Counts(
        rows=sum(len(eq.rows) for eq in result.equations),
        match=result.count(Verdict.MATCH),
        notation=result.count(Verdict.NOTATION),
        endpoint=result.count(Verdict.ENDPOINT),
        mismatch=result.count(Verdict.MISMATCH),
        findings=len(result.findings),
        errors=severities.count("error"),
        inconsistencies=severities.count("inconsistency"),
        minor=severities.count("minor"),
    )


def render_report(
    result: AuditResult, derivation: Derivation, tr: Transcription, spec: Spec
) -> str:
    figs = spec_figures(derivation, spec)
    return render(
        TEMPLATE,
        provenance=provenance(f"templates/{TEMPLATE}", spec),
        paper=tr.paper,
        spec_name=spec.name,
        counts=counts(result),
        findings=[
            {
                "n": i + 1,
                "where": f.where,
                "severity": f.severity,
                "what": f.what,
                "relied_on": f.relied_on,
            }
            for i, f in enumerate(result.findings)
        ],
        equations=[_equation_context(eq, derivation, tr) for eq in result.equations],
        labels=_checks(result.labels),
        citations=_checks(result.citations),
        table2=_checks(result.table2),
        table4=_checks(result.table4),
        claims=_checks(result.claims),
        figures=_checks(result.figures),
        defects=_checks(result.defects),
        spec_figures=_figures_context(figs, spec),
        switching=_switching_context(derivation, spec),
    )

"""Run the whole audit: printed equations, numbering, tables and statements.

The result is plain data (strings, numbers) ready for the report template. The audit
never fails because the paper is wrong; it raises only if the derivation itself or the
transcription is broken.
"""

from __future__ import annotations

from dataclasses import dataclass

from codegen.audit import checks
from codegen.audit.compare import RowResult, Verdict, compare_row
from codegen.audit.transcription import PrintedEquation, Transcription
from codegen.derivation.paper import Derivation


@dataclass(frozen=True)
class EquationAudit:
    key: str
    label: int
    sequence: int
    section: str
    title: str
    printed: str
    verdict: Verdict
    rows: tuple[RowResult, ...]
    derivation_method: str
    reliance: str


@dataclass(frozen=True)
class Finding:
    where: str
    severity: str  # "error", "inconsistency", "minor"
    what: str
    relied_on: str


@dataclass(frozen=True)
class AuditResult:
    equations: tuple[EquationAudit, ...]
    labels: tuple[checks.Check, ...]
    citations: tuple[checks.Check, ...]
    table2: tuple[checks.Check, ...]
    table4: tuple[checks.Check, ...]
    claims: tuple[checks.Check, ...]
    figures: tuple[checks.Check, ...]
    defects: tuple[checks.Check, ...]
    findings: tuple[Finding, ...]

    def count(self, verdict: Verdict) -> int:
        return sum(1 for eq in self.equations for row in eq.rows if row.verdict == verdict)


def _reliance(
    eq: PrintedEquation, rows: tuple[RowResult, ...], audited: dict[str, EquationAudit]
) -> str:
    bad = [r for r in rows if r.verdict.is_finding]
    if not bad:
        return ""
    parts = []
    if all(r.vanishes_without_r for r in bad):
        parts.append(
            "Only the resistance term is wrong. The paper sets R = 0 from the next step on,"
            " so no later result inherits the error."
        )
    for key in eq.downstream:
        after = audited.get(key)
        if after is None:
            continue
        if after.verdict.is_finding:
            parts.append(f"Eq. ({after.label}) carries the printed form forward.")
        else:
            parts.append(
                f"Eq. ({after.label}), which follows from this one, agrees with the derived"
                " form: the rest of the paper relies on the derived form."
            )
    return " ".join(parts)


def audit_equations(tr: Transcription, d: Derivation) -> tuple[EquationAudit, ...]:
    audited: dict[str, EquationAudit] = {}
    # Audit later equations first so that reliance can look downstream.
    for eq in sorted(tr.equations, key=lambda e: -e.sequence):
        if eq.kind == "model":
            audited[eq.key] = EquationAudit(
                eq.key,
                eq.label,
                eq.sequence,
                eq.section,
                eq.title,
                eq.printed,
                Verdict.MODEL,
                (),
                "the model the derivation starts from",
                "",
            )
            continue
        derived = d[eq.key]
        rows = tuple(
            compare_row(eq.key, row, derived.row(row.name), tr, derived.note(row.name))
            for row in eq.rows
        )
        verdict = max((r.verdict for r in rows), key=lambda v: v.severity)
        audited[eq.key] = EquationAudit(
            eq.key,
            eq.label,
            eq.sequence,
            eq.section,
            eq.title,
            eq.printed,
            verdict,
            rows,
            derived.method,
            _reliance(eq, rows, audited),
        )
    return tuple(sorted(audited.values(), key=lambda e: e.sequence))


def _equation_findings(equations: tuple[EquationAudit, ...]) -> list[Finding]:
    """One finding per equation, naming each row that differs and how."""
    out = []
    for eq in equations:
        bad = [row for row in eq.rows if row.verdict.is_finding]
        if not bad:
            continue
        severity = "error" if any(r.verdict == Verdict.MISMATCH for r in bad) else "minor"
        what = " ".join(
            (f"Row {row.name}: " if row.name else "") + "; ".join(row.findings) + "." for row in bad
        )
        out.append(Finding(f"Eq. ({eq.label})", severity, what, eq.reliance))
    return out


def _grouped(where: str, group: tuple[checks.Check, ...], summary: str) -> list[Finding]:
    """Many checks with one cause (e.g. every citation off by two) as one finding."""
    failed = [c for c in group if c.verdict != checks.CONSISTENT]
    if not failed:
        return []
    listed = "; ".join(f"{c.where}: {c.detail}" for c in failed)
    return [
        Finding(
            where,
            "inconsistency",
            f"{summary.format(n=len(failed), total=len(group))} {listed}",
            "",
        )
    ]


def _check_findings(group: tuple[checks.Check, ...]) -> list[Finding]:
    out = []
    for check in group:
        if check.verdict == checks.CONSISTENT:
            continue
        severity = "minor" if check.verdict == checks.MINOR else "inconsistency"
        out.append(Finding(check.where, severity, f"“{check.quote}”: {check.detail}", ""))
    return out


def run_audit(tr: Transcription, d: Derivation) -> AuditResult:
    equations = audit_equations(tr, d)
    labels = tuple(checks.equation_labels(tr))
    citations = tuple(checks.citations(tr))
    table2 = tuple(checks.table2(tr, d))
    table4 = tuple(checks.table4(tr, d))
    claims = tuple(checks.claims(tr, d))
    figures = tuple(checks.figures(tr))
    defects = tuple(checks.defects(tr))
    role_claims = tuple(c for c in claims if c.id.startswith("roles-"))
    other_claims = tuple(c for c in claims if not c.id.startswith("roles-"))
    findings = tuple(
        _equation_findings(equations)
        + _check_findings(labels)
        + _grouped(
            "equation citations",
            citations,
            "{n} of {total} citations in the text do not match the printed label; each cites the"
            " equation's position in the paper instead, which is the numbering the text uses"
            " throughout.",
        )
        + _check_findings(table2)
        + _check_findings(table4)
        + _grouped(
            "section 3.1",
            role_claims,
            "Cases (1)-(3) swap the turn-on and turn-off labels of i_b and i_c ({n} places), while"
            " section 3.2 and the cases' own descriptions (i_b falls to zero) use B = turn-off,"
            " C = turn-on.",
        )
        + _check_findings(other_claims)
        + _grouped(
            "figure captions",
            figures,
            "{n} of {total} figure captions restart the numbering: Figs. 10-15 are captioned"
            " Fig. 4-9, numbers already used by Figs. 4-9.",
        )
        + _check_findings(defects)
    )
    return AuditResult(
        equations, labels, citations, table2, table4, claims, figures, defects, findings
    )

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
class Evidence:
    """One item of a finding's evidence: where (a label linked to the report anchor)
    and what."""

    label: str
    text: str
    anchor: str


@dataclass(frozen=True)
class Finding:
    where: str
    severity: str  # "error", "inconsistency", "minor"
    #: One line: what is wrong, without the evidence (math between $...$).
    summary: str
    evidence: tuple[Evidence, ...]
    relied_on: str
    #: Report anchors of the equations, table rows and sentences it concerns; the first
    #: is where the finding's heading links.
    anchors: tuple[str, ...]

    @property
    def what(self) -> str:
        """The whole finding as one text: summary and every item of evidence."""
        items = (f"{e.label}: {e.text}." if e.label else f"{e.text}." for e in self.evidence)
        return " ".join([f"{self.summary}.", *items])


def equation_anchor(key: str) -> str:
    return f"eq-{key}"


def row_anchor(key: str, row: str) -> str:
    return f"eq-{key}-{row or 'row'}"


def _rows_phrase(rows: list[str]) -> str:
    named = [r for r in rows if r]
    if not named:
        return ""
    return ("row " if len(named) == 1 else "rows ") + ", ".join(named) + ": "


def _equation_summary(bad: list[RowResult]) -> str:
    """Rows with the same fault share one phrase: 'rows a, b, c: dimensionally
    inconsistent, resistance term lacks the factor 1/L; row c: wrong sign on ...'."""
    rows_of: dict[str, list[str]] = {}
    for row in bad:
        for difference in row.differences:
            if difference.short:
                rows_of.setdefault(difference.short, []).append(row.name)
    groups: list[tuple[tuple[str, ...], list[str]]] = []
    for short, rows in rows_of.items():
        if groups and groups[-1][0] == tuple(rows):
            groups[-1][1].append(short)
        else:
            groups.append((tuple(rows), [short]))
    return "; ".join(_rows_phrase(list(rows)) + ", ".join(shorts) for rows, shorts in groups)


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
        evidence = tuple(
            Evidence(
                f"Eq. ({eq.label})" + (f" row {row.name}" if row.name else ""),
                "; ".join(row.findings),
                row_anchor(eq.key, row.name),
            )
            for row in bad
        )
        out.append(
            Finding(
                f"Eq. ({eq.label})",
                severity,
                _equation_summary(bad),
                evidence,
                eq.reliance,
                (equation_anchor(eq.key),),
            )
        )
    return out


def _refs(check: checks.Check) -> tuple[str, ...]:
    return tuple(equation_anchor(key) for key in check.refs)


def _grouped(
    where: str, anchor: str, group: tuple[checks.Check, ...], summary: str
) -> list[Finding]:
    """Many checks with one cause (e.g. every citation off by two) as one finding whose
    evidence lists each of them."""
    failed = [c for c in group if c.verdict != checks.CONSISTENT]
    if not failed:
        return []
    return [
        Finding(
            where,
            "inconsistency",
            summary.format(n=len(failed), total=len(group)),
            tuple(Evidence(c.where, f"“{c.quote}”: {c.detail}", c.id) for c in failed),
            "",
            (anchor,),
        )
    ]


def _check_findings(group: tuple[checks.Check, ...]) -> list[Finding]:
    out = []
    for check in group:
        if check.verdict == checks.CONSISTENT:
            continue
        severity = "minor" if check.verdict == checks.MINOR else "inconsistency"
        out.append(
            Finding(
                check.where,
                severity,
                check.summary,
                (Evidence("", f"“{check.quote}”: {check.detail}", check.id),),
                "",
                (check.id, *_refs(check)),
            )
        )
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
            "citations",
            citations,
            "{n} of {total} citations in the text cite the equation's position in the paper,"
            " not its printed label",
        )
        + _check_findings(table2)
        + _check_findings(table4)
        + _grouped(
            "section 3.1",
            "statements",
            role_claims,
            "cases (1)-(3) swap the turn-on and turn-off labels of $i_b$ and $i_c$ ({n} places);"
            " section 3.2 and the cases' own descriptions ($i_b$ falls to zero) use B = turn-off,"
            " C = turn-on",
        )
        + _check_findings(other_claims)
        + _grouped(
            "figure captions",
            "figures",
            figures,
            "{n} of {total} figure captions restart the numbering: Figs. 10-15 are captioned"
            " Fig. 4-9, numbers already used by Figs. 4-9",
        )
        + _check_findings(defects)
    )
    return AuditResult(
        equations, labels, citations, table2, table4, claims, figures, defects, findings
    )

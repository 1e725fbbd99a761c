"""The paper audit as a document: one data model, two renderings.

`build_report` turns an `AuditResult` into plain data (strings and numbers, math as
LaTeX between $...$ or as display LaTeX), and the two templates lay the same data out:
`audit/AUDIT.md.j2` for code hosts, which render the LaTeX themselves, and
`audit/AUDIT.html.j2`, a self-contained page whose math is MathML printed here, so it
renders in a browser with no network and no script.

The printed equations are shown as the paper prints them: their verbatim LaTeX
(`spec/paper_printed.yaml`), which SymPy cannot parse as a whole (\\begin{cases},
labels), is converted by latex2mathml; so is the LaTeX SymPy prints for the derived
side, so both sides go through one converter.

The paper audit depends on no motor: where the paper's statements need numbers it uses
the paper's own Table 3 motor, transcribed with the equations.
"""

from __future__ import annotations

import hashlib
import html
import re
from dataclasses import dataclass
from functools import lru_cache

import jinja2
from latex2mathml.converter import convert as latex_to_mathml
from markupsafe import Markup

from codegen.audit import checks
from codegen.audit.compare import HIGHLIGHT, RowResult, Verdict
from codegen.audit.run import AuditResult, EquationAudit, Finding, row_anchor
from codegen.audit.transcription import DEFAULT_TRANSCRIPTION, Transcription
from codegen.render import environment, project_relative, render

MARKDOWN_TEMPLATE = "audit/AUDIT.md.j2"
HTML_TEMPLATE = "audit/AUDIT.html.j2"

VERDICT_TEXT = {
    Verdict.MATCH: "match",
    Verdict.NOTATION: "match (notation)",
    Verdict.ENDPOINT: "end point differs",
    Verdict.MISMATCH: "mismatch",
    Verdict.MODEL: "model",
}
VERDICT_ICON = {
    Verdict.MATCH: "✅",
    Verdict.NOTATION: "✅",
    Verdict.ENDPOINT: "⚠️",
    Verdict.MISMATCH: "❌",
    Verdict.MODEL: "📘",
}
CHECK_ICON = {checks.CONSISTENT: "✅", checks.CONTRADICTION: "❌", checks.MINOR: "⚠️"}
CHECK_CLASS = {
    checks.CONSISTENT: "match",
    checks.CONTRADICTION: "mismatch",
    checks.MINOR: "endpoint",
}


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


@dataclass(frozen=True)
class Link:
    anchor: str
    label: str


@dataclass(frozen=True)
class EvidenceView:
    label: str
    text: str
    anchor: str


@dataclass(frozen=True)
class FindingView:
    number: int
    anchor: str
    where: str
    severity: str
    summary: str
    evidence: tuple[EvidenceView, ...]
    relied_on: str
    #: The equation, table or sentence the finding is about (its heading links here).
    target: Link
    #: Further equations it concerns.
    concerns: tuple[Link, ...]


@dataclass(frozen=True)
class RowView:
    anchor: str
    name: str
    #: What the row states, as LaTeX ("\\frac{di_a}{dt}", "n \\in").
    quantity: str
    printed: str
    derived: str
    #: derived minus printed, LaTeX; empty when they agree.
    difference: str
    verdict: str
    icon: str
    css: str
    method: str
    findings: tuple[str, ...]
    notes: tuple[str, ...]


@dataclass(frozen=True)
class EquationView:
    anchor: str
    key: str
    label: int
    title: str
    section: str
    sequence: int
    #: The display equation as printed, verbatim LaTeX.
    printed: str
    verdict: str
    icon: str
    css: str
    is_model: bool
    method: str
    rows: tuple[RowView, ...]
    reliance: str
    findings: tuple[Link, ...]


@dataclass(frozen=True)
class CheckView:
    anchor: str
    where: str
    quote: str
    verdict: str
    icon: str
    css: str
    summary: str
    detail: str
    concerns: tuple[Link, ...]
    findings: tuple[Link, ...]


@dataclass(frozen=True)
class AuditReport:
    provenance_md: str
    provenance_html: str
    paper: str
    transcription: str
    table3: str
    counts: Counts
    findings: tuple[FindingView, ...]
    equations: tuple[EquationView, ...]
    labels: tuple[CheckView, ...]
    citations: tuple[CheckView, ...]
    table2: tuple[CheckView, ...]
    table4: tuple[CheckView, ...]
    claims: tuple[CheckView, ...]
    figures: tuple[CheckView, ...]
    defects: tuple[CheckView, ...]


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


def _equation_links(result: AuditResult) -> dict[str, Link]:
    return {f"eq-{eq.key}": Link(f"eq-{eq.key}", f"Eq. ({eq.label})") for eq in result.equations}


def _finding_links(findings: tuple[Finding, ...]) -> dict[str, tuple[Link, ...]]:
    """Report anchor -> the findings that concern it (back links)."""
    out: dict[str, list[Link]] = {}
    for number, finding in enumerate(findings, start=1):
        link = Link(f"finding-{number}", f"finding {number}")
        for anchor in (*finding.anchors, *(e.anchor for e in finding.evidence)):
            if link not in out.setdefault(anchor, []):
                out[anchor].append(link)
    return {anchor: tuple(links) for anchor, links in out.items()}


def _finding_view(
    number: int, finding: Finding, eq_links: dict[str, Link], check_where: dict[str, str]
) -> FindingView:
    main, *others = finding.anchors
    label = eq_links[main].label if main in eq_links else check_where.get(main, finding.where)
    return FindingView(
        number=number,
        anchor=f"finding-{number}",
        where=finding.where,
        severity=finding.severity,
        summary=finding.summary,
        evidence=tuple(
            EvidenceView(e.label or check_where.get(e.anchor, e.anchor), e.text, e.anchor)
            for e in finding.evidence
        ),
        relied_on=finding.relied_on,
        target=Link(main, label),
        concerns=tuple(eq_links[a] for a in others if a in eq_links),
    )


def _quantity(row_lhs: str, var: str) -> str:
    if row_lhs:
        return row_lhs
    return f"{var} \\in" if var else ""


def _row_view(eq: EquationAudit, row: RowResult, var: str) -> RowView:
    return RowView(
        anchor=row_anchor(eq.key, row.name),
        name=row.name or "-",
        quantity=_quantity(row.lhs, var),
        printed=row.printed_display,
        derived=row.derived_display,
        difference=row.difference_display,
        verdict=VERDICT_TEXT[row.verdict],
        icon=VERDICT_ICON[row.verdict],
        css=row.verdict.name.lower(),
        method=row.method,
        findings=row.findings,
        notes=row.notes,
    )


def _equation_view(
    eq: EquationAudit, tr: Transcription, back: dict[str, tuple[Link, ...]]
) -> EquationView:
    printed = tr.equation(eq.key)
    variables = {r.name: r.var for r in printed.rows}
    return EquationView(
        anchor=f"eq-{eq.key}",
        key=eq.key,
        label=eq.label,
        title=eq.title,
        section=eq.section,
        sequence=eq.sequence,
        printed=eq.printed,
        verdict=VERDICT_TEXT[eq.verdict],
        icon=VERDICT_ICON[eq.verdict],
        css=eq.verdict.name.lower(),
        is_model=eq.verdict == Verdict.MODEL,
        method=eq.derivation_method,
        rows=tuple(_row_view(eq, row, variables.get(row.name, "")) for row in eq.rows),
        reliance=eq.reliance,
        findings=back.get(f"eq-{eq.key}", ()),
    )


def _check_views(
    group: tuple[checks.Check, ...],
    eq_links: dict[str, Link],
    back: dict[str, tuple[Link, ...]],
) -> tuple[CheckView, ...]:
    return tuple(
        CheckView(
            anchor=c.id,
            where=c.where,
            quote=c.quote,
            verdict=c.verdict,
            icon=CHECK_ICON[c.verdict],
            css=CHECK_CLASS[c.verdict],
            summary=c.summary,
            detail=c.detail,
            concerns=tuple(eq_links[f"eq-{key}"] for key in c.refs),
            findings=back.get(c.id, ()),
        )
        for c in group
    )


def _provenance(template: str) -> str:
    digest = hashlib.sha256(DEFAULT_TRANSCRIPTION.read_bytes()).hexdigest()
    return (
        f"Generated from template templates/{template} with"
        f" {project_relative(DEFAULT_TRANSCRIPTION)} (sha256 {digest}). Do not edit:"
        " regenerate with `bldc-codegen audit`."
    )


def build_report(result: AuditResult, tr: Transcription) -> AuditReport:
    eq_links = _equation_links(result)
    back = _finding_links(result.findings)
    all_checks = (
        result.labels
        + result.citations
        + result.table2
        + result.table4
        + result.claims
        + result.figures
        + result.defects
    )
    check_where = {c.id: c.where for c in all_checks} | {
        "citations": "equation citations",
        "statements": "statements in the text",
        "figures": "figure captions",
    }
    return AuditReport(
        provenance_md=_provenance(MARKDOWN_TEMPLATE),
        provenance_html=_provenance(HTML_TEMPLATE),
        paper=tr.paper,
        transcription=project_relative(DEFAULT_TRANSCRIPTION),
        table3=(
            f"$U_d$ = {float(tr.table3_voltage):g} V, $k_e$ ="
            f" {float(tr.table3_ke_per_krpm):g} V/krpm"
        ),
        counts=counts(result),
        findings=tuple(
            _finding_view(n, f, eq_links, check_where)
            for n, f in enumerate(result.findings, start=1)
        ),
        equations=tuple(_equation_view(eq, tr, back) for eq in result.equations),
        labels=_check_views(result.labels, eq_links, back),
        citations=_check_views(result.citations, eq_links, back),
        table2=_check_views(result.table2, eq_links, back),
        table4=_check_views(result.table4, eq_links, back),
        claims=_check_views(result.claims, eq_links, back),
        figures=_check_views(result.figures, eq_links, back),
        defects=_check_views(result.defects, eq_links, back),
    )


# --- HTML: text with $...$ math -> escaped HTML with MathML ---------------------------

_INLINE_MATH = re.compile(r"\$([^$]+)\$")
#: A one-letter symbol with a subscript written as plain text in the paper's words or
#: ours ("D_{on}", "i_b", "k_e", "D_off"): shown as math rather than as raw TeX.
_BARE_SUBSCRIPT = re.compile(r"(?<![\w\\/.])([A-Za-z])_(\{[A-Za-z0-9]+\}|[A-Za-z0-9]+)(?!\w)")


def _mathml(latex: str, display: bool) -> str:
    # \color{red} marks a difference (compare.HIGHLIGHT); the page styles it by class.
    out = latex_to_mathml(latex, display="block" if display else "inline")
    return out.replace('<mstyle mathcolor="red">', '<mstyle class="diff" mathcolor="red">')


def _text_to_html(text: str) -> str:
    parts = []
    for index, piece in enumerate(_INLINE_MATH.split(text)):
        if index % 2:
            parts.append(_mathml(piece, display=False))
            continue
        last = 0
        for match in _BARE_SUBSCRIPT.finditer(piece):
            parts.append(html.escape(piece[last : match.start()], quote=False))
            subscript = match.group(2).strip("{}")
            parts.append(_mathml(f"{match.group(1)}_{{{subscript}}}", display=False))
            last = match.end()
        parts.append(html.escape(piece[last:], quote=False))
    return "".join(parts)


def text_filter(text: object) -> Markup:
    """Prose with inline $...$ math, as HTML with MathML."""
    return Markup(_text_to_html(str(text)))


def math_filter(latex: object) -> Markup:
    """LaTeX (no $ delimiters) as inline MathML; empty stays empty."""
    return Markup(_mathml(str(latex), display=False)) if str(latex) else Markup("")


def display_filter(latex: object) -> Markup:
    """LaTeX as block MathML (a display equation)."""
    return Markup(_mathml(str(latex), display=True))


@lru_cache(maxsize=1)
def _html_environment() -> jinja2.Environment:
    """The HTML's environment (autoescaped, the math filters), built once per process
    so that its template is compiled once."""
    env = environment()
    env.autoescape = True
    env.filters.update(text=text_filter, math=math_filter, display=display_filter)
    return env


def render_markdown(report: AuditReport) -> str:
    return render(MARKDOWN_TEMPLATE, report=report, highlight=HIGHLIGHT)


def render_html(report: AuditReport) -> str:
    return _html_environment().get_template(HTML_TEMPLATE).render(report=report)


def render_reports(result: AuditResult, tr: Transcription) -> dict[str, str]:
    """File name -> text of the paper audit: AUDIT.md and AUDIT.html."""
    report = build_report(result, tr)
    return {"AUDIT.md": render_markdown(report), "AUDIT.html": render_html(report)}

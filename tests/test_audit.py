"""The audit catches every real discrepancy in the paper and flags nothing correct."""

from __future__ import annotations

import dataclasses
import re
from pathlib import Path

import pytest
import sympy as sp

from codegen.audit.compare import HIGHLIGHT, Verdict
from codegen.audit.latex_cache import LatexCache, parse_latex_uncached
from codegen.audit.report import AuditReport, build_report, render_reports
from codegen.audit.run import AuditResult, run_audit
from codegen.audit.transcription import Transcription, load_transcription, symbol_mapper
from codegen.derivation import derive


def _paper_dir() -> Path | None:
    """The paper's text: $BLDC_PAPER_DIR, else shared/paper beside the checkout or
    beside any folder above it (CI clones next to it)."""
    import os

    if os.environ.get("BLDC_PAPER_DIR"):
        return Path(os.environ["BLDC_PAPER_DIR"])
    for folder in Path(__file__).resolve().parents[1:]:
        candidate = folder / "shared" / "paper"
        if candidate.is_dir():
            return candidate
    return None


PAPER_DIR = _paper_dir()
PAPER_FILES = sorted(PAPER_DIR.glob("*.txt")) if PAPER_DIR is not None else []

#: Printed equations that are correct (possibly with notation differences).
CORRECT = {"3b", "5", "6", "7", "8", "9", "10", "11", "12", "14", "15", "16", "17", "19", "20"}


@pytest.fixture(scope="module")
def transcription() -> Transcription:
    return load_transcription()


@pytest.fixture(scope="module")
def audit(transcription: Transcription) -> AuditResult:
    return run_audit(transcription, derive())


def _finding(audit: AuditResult, where: str) -> str:
    matches = [f.what for f in audit.findings if f.where == where]
    assert matches, f"no finding at {where}: {[f.where for f in audit.findings]}"
    return " ".join(matches)


def test_correct_equations_should_not_be_flagged(audit: AuditResult) -> None:
    verdicts = {eq.key: eq.verdict for eq in audit.equations}
    for key in CORRECT:
        assert not verdicts[key].is_finding, f"Eq. {key} flagged: {verdicts[key]}"
    assert verdicts["5"] == Verdict.NOTATION  # writes L_s for L


def test_resistance_term_of_eqs_4_and_13_should_be_dimensionally_wrong(audit: AuditResult) -> None:
    for label in ("4", "13"):
        text = _finding(audit, f"Eq. ({label})")
        for row in "abc":
            assert f"$- R i_{{{row}}}$ is in V while the other terms are in A/s" in text
            assert f"derived $- \\frac{{R i_{{{row}}}}}{{L}}$" in text


def test_eq_4_row_c_should_have_the_wrong_sign_on_2e(audit: AuditResult) -> None:
    text = _finding(audit, "Eq. (4)")
    assert "the term $- \\frac{2 E}{3 L}$ has the wrong sign" in text
    eq4 = next(eq for eq in audit.equations if eq.key == "4")
    assert "Eq. (5)" in eq4.reliance and "derived form" in eq4.reliance


def test_eq_13_error_should_not_propagate_because_r_is_dropped(audit: AuditResult) -> None:
    eq13 = next(eq for eq in audit.equations if eq.key == "13")
    assert "no later result inherits the error" in eq13.reliance


def test_findings_should_be_exactly_the_known_discrepancies(audit: AuditResult) -> None:
    wheres = sorted(f.where for f in audit.findings)
    assert wheres == sorted(
        [
            "Eq. (4)",
            "Eq. (13)",
            "Eq. (18)",
            "labels",
            "labels",
            "labels",
            "labels",
            "equation citations",
            "Table 2, D_off, low-speed row",
            "Table 4",
            "section 3.1",
            "section 4.2",
            "section 5.2",
            "section 5.2",
            "figure captions",
        ]
    )
    severities = {f.where: f.severity for f in audit.findings}
    assert severities["Eq. (4)"] == "error"
    assert severities["Eq. (18)"] == "minor"


def test_table_2_low_speed_d_off_row_should_carry_the_wrong_emf_range(audit: AuditResult) -> None:
    bad = [c.id for c in audit.table2 if c.verdict != "consistent"]
    assert bad == ["table2-D_off-low"]
    assert "contradicts the row's own speed range" in _finding(
        audit, "Table 2, D_off, low-speed row"
    )


def test_table_4_should_contradict_eq_18_only_at_2500_rpm(audit: AuditResult) -> None:
    bad = [c.id for c in audit.table4 if c.verdict != "consistent"]
    assert bad == ["table4-2500"]
    assert "cut-off 2542.4 rpm" in _finding(audit, "Table 4")


def test_citations_should_use_positions_not_labels(audit: AuditResult) -> None:
    failed = [c for c in audit.citations if c.verdict != "consistent"]
    assert len(failed) == 20 and len(audit.citations) == 21
    assert all("= its position in the paper" in c.detail for c in failed)


def test_fig_15_caption_should_contradict_its_low_speed_pattern(audit: AuditResult) -> None:
    verdicts = {c.id: c.verdict for c in audit.claims}
    assert verdicts["fig15-caption"] == "contradiction"
    assert verdicts["fig15-pattern"] == "consistent"
    assert verdicts["cutoff-5.1"] == "consistent"
    assert verdicts["fig13-fail"] == "consistent"
    assert verdicts["speed-1500"] == verdicts["speed-4600"] == "consistent"
    assert verdicts["regions-5.1"] == "consistent"


def _with_row_latex(tr: Transcription, key: str, row: str, latex: str) -> Transcription:
    equations = []
    for eq in tr.equations:
        if eq.key == key:
            rows = tuple(
                dataclasses.replace(r, latex=latex, parse=latex) if r.name == row else r
                for r in eq.rows
            )
            eq = dataclasses.replace(eq, rows=rows)
        equations.append(eq)
    return dataclasses.replace(tr, equations=tuple(equations))


def test_a_planted_sign_error_should_be_caught(transcription: Transcription) -> None:
    planted = _with_row_latex(
        transcription, "20", "", r"\frac{3IL}{(2D_{off} - 1 - D_{on})U_d + 2E}"
    )
    result = run_audit(planted, derive())
    eq20 = next(eq for eq in result.equations if eq.key == "20")
    assert eq20.verdict == Verdict.MISMATCH
    assert any(f.where == "Eq. (20)" for f in result.findings)


def test_correcting_the_misprint_should_clear_the_sign_finding(
    transcription: Transcription,
) -> None:
    fixed = _with_row_latex(
        transcription, "4", "c", r"\frac{(2D_{on} - 1)U_d + 2E}{3L} - \frac{R}{L}i_c"
    )
    result = run_audit(fixed, derive())
    eq4 = next(eq for eq in result.equations if eq.key == "4")
    row_c = next(r for r in eq4.rows if r.name == "c")
    assert row_c.verdict == Verdict.MATCH


def test_parse_cache_should_say_what_the_parser_says(transcription: Transcription) -> None:
    cache = LatexCache()
    assert len(cache.entries) > 30, "spec/paper_printed.parsed.json is missing entries"
    for latex in cache.entries:
        cached, cached_notes = cache.parse(latex, symbol_mapper(latex, transcription))
        fresh, fresh_notes = symbol_mapper(latex, transcription)(parse_latex_uncached(latex))
        assert sp.srepr(cached) == sp.srepr(fresh), latex
        assert cached_notes == fresh_notes


def _normalise(text: str) -> str:
    return re.sub(r"\s+", " ", text)


def test_transcription_should_be_verbatim(transcription: Transcription) -> None:
    """Word for word against the paper (../shared/paper, or $BLDC_PAPER_DIR): a missing
    paper fails this test, it never skips."""
    assert PAPER_FILES, "the paper's text is not beside the project: set BLDC_PAPER_DIR"
    paper = _normalise(PAPER_FILES[0].read_text(encoding="utf-8"))
    for eq in transcription.equations:
        assert _normalise(eq.printed) in paper, f"Eq. {eq.key} is not verbatim"
    for cite in transcription.citations:
        assert _normalise(cite.quote) in paper, cite.quote
    for claim in transcription.claims:
        for part in claim.quote.split(" ... "):
            assert _normalise(part.replace("\\\\", "\\")) in paper, claim.quote
    for fig in transcription.figures:
        assert _normalise(fig.caption_text) in paper


# --- the report: one data model, two renderings ----------------------------------------


@pytest.fixture(scope="module")
def report(audit: AuditResult, transcription: Transcription) -> AuditReport:
    return build_report(audit, transcription)


@pytest.fixture(scope="module")
def rendered(audit: AuditResult, transcription: Transcription) -> dict[str, str]:
    return render_reports(audit, transcription)


def test_each_finding_should_be_one_short_line(report: AuditReport) -> None:
    assert len(report.findings) == 15
    for finding in report.findings:
        assert "\n" not in finding.summary
        assert len(finding.summary) < 260, finding.summary


def test_long_findings_should_list_their_evidence_item_by_item(report: AuditReport) -> None:
    by_where = {f.where: f for f in report.findings}
    citations = by_where["equation citations"]
    assert len(citations.evidence) == 20
    assert {e.anchor for e in citations.evidence} == {
        f"cite-{n}" for n in range(1, 22) if n != 6
    }  # the 6th cites (3), Eq. (3)'s own label
    captions = by_where["figure captions"]
    assert [e.anchor for e in captions.evidence] == [f"fig-{n}" for n in range(10, 16)]
    assert all(len(e.text) < 400 for f in report.findings for e in f.evidence)


def test_each_finding_should_link_to_what_it_concerns(report: AuditReport) -> None:
    targets = {f.where: f.target.anchor for f in report.findings}
    assert targets["Eq. (4)"] == "eq-4"
    assert targets["Table 4"] == "table4-2500"
    assert targets["Table 2, D_off, low-speed row"] == "table2-D_off-low"
    assert targets["figure captions"] == "figures"
    eq4 = next(f for f in report.findings if f.where == "Eq. (4)")
    assert [e.anchor for e in eq4.evidence] == ["eq-4-a", "eq-4-b", "eq-4-c"]
    table4 = next(f for f in report.findings if f.where == "Table 4")
    assert [c.anchor for c in table4.concerns] == ["eq-18"]


def test_printed_and_derived_should_mark_the_terms_that_differ(report: AuditReport) -> None:
    eq4 = next(eq for eq in report.equations if eq.key == "4")
    row_c = next(r for r in eq4.rows if r.name == "c")
    assert f"{{{HIGHLIGHT} - \\frac{{2 E}}{{3 L}}}}" in row_c.printed
    assert f"{{{HIGHLIGHT} + \\frac{{2 E}}{{3 L}}}}" in row_c.derived
    assert f"{{{HIGHLIGHT} - R i_{{c}}}}" in row_c.printed
    assert f"{{{HIGHLIGHT} - \\frac{{R i_{{c}}}}{{L}}}}" in row_c.derived
    assert row_c.difference  # derived - printed, shown beside them
    eq18 = next(eq for eq in report.equations if eq.key == "18")
    low = next(r for r in eq18.rows if r.name == "low_region")
    assert low.printed.startswith(f"{{{HIGHLIGHT} [}}0")  # the closed end at n = 0
    assert low.derived.startswith(f"{{{HIGHLIGHT} (}}0")
    matched = next(eq for eq in report.equations if eq.key == "20")
    assert all(HIGHLIGHT not in r.printed + r.derived and not r.difference for r in matched.rows)


def test_markdown_and_html_should_carry_the_same_findings_and_anchors(
    report: AuditReport, rendered: dict[str, str]
) -> None:
    markdown, page = rendered["AUDIT.md"], rendered["AUDIT.html"]
    anchors = [f.anchor for f in report.findings] + [eq.anchor for eq in report.equations]
    anchors += [c.anchor for c in report.citations + report.table4 + report.claims]
    for anchor in anchors:
        assert f'<a id="{anchor}"></a>' in markdown, anchor
        assert f'id="{anchor}"' in page, anchor
    for finding in report.findings:
        assert f"({finding.severity}): {finding.summary}." in markdown
    # The HTML prints the math as MathML, never as TeX.
    assert "\\frac" not in page and "$" not in page.split("<body>")[1]
    assert page.count("<math ") > 300


def test_html_should_be_self_contained(rendered: dict[str, str]) -> None:
    page = rendered["AUDIT.html"]
    assert "<script" not in page and "<link" not in page and "src=" not in page
    urls = set(re.findall(r"https?://[^\s\"'<>]+", page))
    assert urls == {"http://www.w3.org/1998/Math/MathML"}  # a namespace, never fetched


def test_markdown_should_have_no_giant_cells(rendered: dict[str, str]) -> None:
    findings = rendered["AUDIT.md"].split("## Findings")[1].split("## Equations")[0]
    assert max(len(line) for line in findings.splitlines()) < 700


def test_dimensions_should_name_the_terms_that_do_not_fit() -> None:
    from codegen.audit.dimensions import check_dimensions, dimension_of
    from codegen.derivation import symbols as s

    assert dimension_of(s.E / s.L) == "A/s"
    assert dimension_of(s.k_e * s.n) == "V"
    assert dimension_of(s.I * s.L / s.E) == "s"
    assert dimension_of(s.E * s.I / s.omega_m) == "N m"
    assert check_dimensions((s.U_d - 4 * s.E) / (3 * s.L) - s.R * s.i_a / s.L) is None
    clash = check_dimensions((s.U_d - 4 * s.E) / (3 * s.L) - s.R * s.i_a)
    assert clash is not None
    assert ("- R i_{a}", "V") in clash.terms
    assert {dim for _, dim in clash.terms} == {"V", "A/s"}

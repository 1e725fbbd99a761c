"""The HTML audit in a real browser: headless Debian Chromium renders every equation as
native MathML, shows no raw TeX, and has every finding and every anchor it links to.

Chromium is required: without it this test fails (`make sysdeps` installs it).
"""

from __future__ import annotations

import struct
from pathlib import Path
from typing import Any

import pytest

from bldc import cli
from codegen.audit.browser import Chromium
from codegen.audit.run import AuditResult, run_audit
from codegen.audit.transcription import Transcription, load_transcription
from codegen.derivation import derive

#: What the page says about itself once every <details> is open. A <math> element that
#: Chromium lays out as MathML is a MathMLElement with the computed display "math" or
#: "block math"; an unknown element would be "inline". A fraction rendered in two dimensions is taller
#: than one line of its own font; TeX left as text is caught by its backslashes, carets
#: and dollar signs outside code.
PAGE_FACTS = r"""
(() => {
  document.querySelectorAll('details').forEach(d => { d.open = true; });
  const maths = [...document.querySelectorAll('math')];
  const notMathml = maths.filter(m => {
    const display = getComputedStyle(m).display;
    return !(m instanceof MathMLElement) || !(display === 'math' || display.endsWith(' math'));
  }).length;
  const empty = maths.filter(m => {
    const r = m.getBoundingClientRect(); return r.width < 1 || r.height < 1; }).length;
  const fractions = [...document.querySelectorAll('mfrac')];
  const flat = fractions.filter(f => {
    const size = parseFloat(getComputedStyle(f).fontSize);
    return f.getBoundingClientRect().height < 1.2 * size; }).length;
  const walker = document.createTreeWalker(document.body, NodeFilter.SHOW_TEXT);
  const raw = [];
  for (let n = walker.nextNode(); n; n = walker.nextNode()) {
    if (n.parentElement.closest('code, pre, math')) continue;
    if (/\\[a-zA-Z]+|\$|[_^]\{/.test(n.textContent)) raw.push(n.textContent.trim().slice(0, 80));
  }
  const ids = [...document.querySelectorAll('[id]')].map(e => e.id);
  const links = [...document.querySelectorAll('a[href]')].map(a => a.getAttribute('href'));
  const highlighted = [...document.querySelectorAll('mstyle.diff')].filter(e => {
    const c = getComputedStyle(e); return c.backgroundColor !== 'rgba(0, 0, 0, 0)'; }).length;
  const external = [...document.querySelectorAll('script, link, img, iframe, object')].length;
  return {
    maths: maths.length, notMathml, empty, fractions: fractions.length, flat, raw,
    ids, links, highlighted, external,
    findings: [...document.querySelectorAll('li.finding')].map(li => ({
      id: li.id, summary: li.querySelector('summary').textContent,
      evidence: li.querySelectorAll('ul.evidence > li').length })),
    equations: [...document.querySelectorAll('section.eq')].map(s => s.id),
    printed: [...document.querySelectorAll('section.eq .printed math')].length,
    title: document.title,
  };
})()
"""


@pytest.fixture(scope="module")
def transcription() -> Transcription:
    return load_transcription()


@pytest.fixture(scope="module")
def audit(transcription: Transcription) -> AuditResult:
    return run_audit(transcription, derive())


@pytest.fixture(scope="module")
def page(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("paper")
    assert cli.main(["audit", "-o", str(out)]) == 0
    return out / "AUDIT.html"


@pytest.fixture(scope="module")
def browser() -> Any:
    with Chromium(width=1180, height=900) as chromium:
        yield chromium


@pytest.fixture(scope="module")
def facts(browser: Chromium, page: Path) -> dict[str, Any]:
    browser.open(page)
    result: dict[str, Any] = browser.evaluate(PAGE_FACTS)
    return result


def _png_size(path: Path) -> tuple[int, int]:
    data = path.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n", f"{path} is not a PNG"
    width, height = struct.unpack(">II", data[16:24])
    return width, height


def test_every_formula_should_be_laid_out_as_mathml(facts: dict[str, Any]) -> None:
    assert facts["title"] == "Audit of the paper's derivations"
    assert facts["maths"] > 300
    assert facts["notMathml"] == 0, "math elements that Chromium does not lay out as MathML"
    assert facts["empty"] == 0, "math elements with no size"
    assert facts["fractions"] > 100
    assert facts["flat"] == 0, "fractions not stacked: the math is not rendered"


def test_no_raw_tex_should_be_left_as_text(facts: dict[str, Any]) -> None:
    assert facts["raw"] == []


def test_every_printed_equation_should_render(
    facts: dict[str, Any], transcription: Transcription
) -> None:
    assert facts["equations"] == [f"eq-{eq.key}" for eq in transcription.equations]
    assert facts["printed"] == len(transcription.equations)


def test_every_finding_should_be_one_line_with_its_evidence_beneath(
    facts: dict[str, Any], audit: AuditResult
) -> None:
    findings = facts["findings"]
    assert [f["id"] for f in findings] == [f"finding-{n}" for n in range(1, 16)]
    assert len(findings) == len(audit.findings)
    for shown, finding in zip(findings, audit.findings, strict=True):
        assert shown["evidence"] == len(finding.evidence)
        assert "\n" not in shown["summary"].strip()
    by_where = {f.where: n for n, f in enumerate(audit.findings)}
    assert findings[by_where["equation citations"]]["evidence"] == 20
    assert findings[by_where["figure captions"]]["evidence"] == 6


def test_every_link_should_land_on_an_anchor(facts: dict[str, Any], audit: AuditResult) -> None:
    ids = set(facts["ids"])
    assert len(ids) == len(facts["ids"]), "duplicate ids"
    internal = [link for link in facts["links"] if link.startswith("#")]
    assert internal and len(internal) == len(facts["links"]), "links that leave the page"
    assert {link[1:] for link in internal} <= ids
    for finding in audit.findings:
        assert set(finding.anchors) <= ids
        assert {e.anchor for e in finding.evidence} <= ids
    for group in (audit.citations, audit.table2, audit.table4, audit.claims, audit.figures):
        assert {c.id for c in group} <= ids


def test_the_page_should_be_self_contained_and_show_the_differences(
    facts: dict[str, Any],
) -> None:
    assert facts["external"] == 0
    # Eq. 4 rows a-c and Eq. 13 rows a-c: each marks the differing terms on both sides.
    assert facts["highlighted"] >= 12


def test_screenshots_should_show_the_findings_and_an_equation(
    browser: Chromium, page: Path, tmp_path: Path
) -> None:
    browser.open(page)
    top = browser.screenshot(tmp_path / "top.png")
    assert _png_size(top) == (1180, 900)
    browser.open(page, fragment="eq-4")
    assert browser.evaluate("window.scrollY") > 0
    equation = browser.screenshot(tmp_path / "eq-4.png")
    assert _png_size(equation) == (1180, 900)
    assert top.read_bytes() != equation.read_bytes()
    whole = browser.screenshot(tmp_path / "whole.png", full_height=True)
    width, height = _png_size(whole)
    assert width == 1180 and height > 5000

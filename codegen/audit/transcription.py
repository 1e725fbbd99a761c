"""Read spec/paper_printed.yaml: the paper as printed, parsed into SymPy.

The LaTeX is parsed with SymPy's LaTeX parser (lark backend) and its symbols mapped
onto the derivation's symbols, so the audit compares like with like. A symbol the
transcription does not declare is an error: it would otherwise compare as a stranger.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path
from typing import Any

import sympy as sp
import yaml

from codegen.audit.latex_cache import shared_cache
from codegen.derivation import symbols as s

DEFAULT_TRANSCRIPTION = Path(__file__).resolve().parents[2] / "spec" / "paper_printed.yaml"


class TranscriptionError(ValueError):
    """The transcription file is malformed (a project bug, not a paper finding)."""


@dataclass(frozen=True)
class PrintedRow:
    name: str
    lhs: str
    latex: str
    parse: str
    parse_note: str
    compare: str  # expr | zero_set | relation | bounds | interval
    solve_for: str
    var: str
    low: str
    high: str
    low_open: bool
    high_open: bool


@dataclass(frozen=True)
class PrintedEquation:
    key: str
    label: int
    sequence: int
    section: str
    title: str
    kind: str  # model | equations
    printed: str
    rows: tuple[PrintedRow, ...]
    downstream: tuple[str, ...]


@dataclass(frozen=True)
class Range:
    low: str
    low_open: bool
    high: str
    high_open: bool


@dataclass(frozen=True)
class Table2Row:
    quantity: str
    region: str
    speed: Range
    emf: Range
    duty: str


@dataclass(frozen=True)
class Table4Row:
    speed_rpm: int
    conventional_on: int
    conventional_off: int
    improved_on: int
    improved_off: int


@dataclass(frozen=True)
class Citation:
    section: str
    quote: str
    cited: int
    means: str


@dataclass(frozen=True)
class Claim:
    id: str
    kind: str
    section: str
    quote: str
    fields: tuple[tuple[str, Any], ...]

    def get(self, name: str) -> Any:
        for key, value in self.fields:
            if key == name:
                return value
        raise TranscriptionError(f"claim {self.id}: missing field {name!r}")


@dataclass(frozen=True)
class FigureRef:
    text: int
    caption: int
    caption_text: str


@dataclass(frozen=True)
class Defect:
    section: str
    quote: str
    what: str


@dataclass(frozen=True)
class Transcription:
    paper: str
    symbols: tuple[tuple[str, str, str], ...]  # (spelling, symbol name, notation note)
    equations: tuple[PrintedEquation, ...]
    table2: tuple[Table2Row, ...]
    table3_voltage: sp.Rational
    table3_ke_per_krpm: sp.Rational
    table4: tuple[Table4Row, ...]
    citations: tuple[Citation, ...]
    claims: tuple[Claim, ...]
    figures: tuple[FigureRef, ...]
    defects: tuple[Defect, ...]

    def equation(self, key: str) -> PrintedEquation:
        for eq in self.equations:
            if eq.key == key:
                return eq
        raise TranscriptionError(f"no printed equation with key {key!r}")

    def notation_note(self, spelling: str) -> str:
        for name, _, note in self.symbols:
            if name == spelling:
                return note
        return ""


def _label(printed: str) -> int:
    tail = printed.rsplit(r"\quad", 1)[-1].strip()
    if not (tail.startswith("(") and tail.endswith(")")):
        raise TranscriptionError(f"printed equation has no '(N)' label: {printed[-30:]!r}")
    return int(tail[1:-1])


def _row(raw: Mapping[str, Any], key: str, printed: str) -> PrintedRow:
    latex = str(raw["latex"])
    if latex not in printed and not raw.get("from_text"):
        raise TranscriptionError(f"Eq. {key}: row latex {latex!r} is not verbatim in the print")
    return PrintedRow(
        name=str(raw.get("name", "")),
        lhs=str(raw.get("lhs", "")),
        latex=latex,
        parse=str(raw.get("parse", latex)),
        parse_note=str(raw.get("parse_note", "")),
        compare=str(raw.get("compare", "expr")),
        solve_for=str(raw.get("solve_for", "")),
        var=str(raw.get("var", "")),
        low=str(raw.get("low", "")),
        high=str(raw.get("high", "")),
        low_open=bool(raw.get("low_open", False)),
        high_open=bool(raw.get("high_open", False)),
    )


def _range(raw: Mapping[str, Any]) -> Range:
    return Range(
        str(raw["low"]),
        bool(raw.get("low_open", True)),
        str(raw["high"]),
        bool(raw.get("high_open", False)),
    )


@lru_cache(maxsize=4)
def load_transcription(path: Path = DEFAULT_TRANSCRIPTION) -> Transcription:
    # libyaml's loader when PyYAML has it (same result, a tenth of the time).
    loader = getattr(yaml, "CSafeLoader", yaml.SafeLoader)
    data = yaml.load(path.read_text(encoding="utf-8"), Loader=loader)
    equations = []
    for raw in data["equations"]:
        key = str(raw["key"])
        printed = str(raw["printed"])
        equations.append(
            PrintedEquation(
                key=key,
                label=_label(printed),
                sequence=int(raw["sequence"]),
                section=str(raw["section"]),
                title=str(raw["title"]),
                kind=str(raw["kind"]),
                printed=printed,
                rows=tuple(_row(r, key, printed) for r in raw.get("rows", [])),
                downstream=tuple(str(k) for k in raw.get("downstream", [])),
            )
        )
    claims = tuple(
        Claim(
            id=str(c["id"]),
            kind=str(c["kind"]),
            section=str(c["section"]),
            quote=str(c["quote"]),
            fields=tuple(
                (k, v) for k, v in c.items() if k not in ("id", "kind", "section", "quote")
            ),
        )
        for c in data["claims"]
    )
    table3 = data["table3"]
    return Transcription(
        paper=str(data["paper"]),
        symbols=tuple(
            (str(k), str(v["symbol"]), str(v.get("notation", "")))
            for k, v in data["symbols"].items()
        ),
        equations=tuple(equations),
        table2=tuple(
            Table2Row(
                str(r["quantity"]),
                str(r["region"]),
                _range(r["speed"]),
                _range(r["emf"]),
                str(r["duty"]),
            )
            for r in data["table2"]
        ),
        table3_voltage=sp.nsimplify(str(table3["rated_voltage_v"])),
        table3_ke_per_krpm=sp.nsimplify(str(table3["back_emf_constant_v_per_krpm"])),
        table4=tuple(Table4Row(**{k: int(v) for k, v in r.items()}) for r in data["table4"]),
        citations=tuple(
            Citation(str(c["section"]), str(c["quote"]), int(c["cited"]), str(c["means"]))
            for c in data["citations"]
        ),
        claims=claims,
        figures=tuple(
            FigureRef(int(f["text"]), int(f["caption"]), str(f["caption_text"]))
            for f in data["figures"]
        ),
        defects=tuple(
            Defect(str(d["section"]), str(d["quote"]), str(d["what"])) for d in data["defects"]
        ),
    )


@dataclass(frozen=True)
class Parsed:
    expr: sp.Expr
    notations: tuple[str, ...]  # notation notes for symbol spellings that were used


def symbol_mapper(
    latex: str, transcription: Transcription
) -> Callable[[sp.Expr], tuple[sp.Expr, tuple[str, ...]]]:
    """Map the parser's symbols (D_{on}, L_s, ...) onto the derivation's symbols."""
    spellings = {name: (symbol, note) for name, symbol, note in transcription.symbols}

    def convert(expr: sp.Expr) -> tuple[sp.Expr, tuple[str, ...]]:
        mapping: dict[sp.Symbol, sp.Symbol] = {}
        notes: set[str] = set()
        for sym in expr.free_symbols:
            spelling = str(sym.name).replace("{", "").replace("}", "").replace("\\", "")
            if spelling not in spellings:
                raise TranscriptionError(f"symbol {sym.name!r} in {latex!r} is not declared")
            target, note = spellings[spelling]
            mapping[sym] = s.BY_NAME[target]
            if note:
                notes.add(f"{spelling}: {note}")
        return expr.xreplace(mapping), tuple(sorted(notes))

    return convert


def parse_printed(latex: str, transcription: Transcription) -> Parsed:
    """Parse printed LaTeX (through the checked-in cache) onto the derivation's symbols."""
    expr, notes = shared_cache().parse(latex, symbol_mapper(latex, transcription))
    return Parsed(expr=expr, notations=notes)

"""The paper's derivation at one motor: `generated/<spec>/DERIVATION.md`.

The audit of the paper is one report for every motor (`generated/paper/`); what depends
on the motor is here: the Eq. 18 cut-off and the upper limit at the spec's bus voltages,
the duties and commutation time at its operating points, the conventional method's
control fail area (Eq. 16) over its speed range, and the switching table with its Hall
codes. Every number is the derivation's expression evaluated exactly at the spec's
values and rounded only when printed.
"""

from __future__ import annotations

import json
import re
from dataclasses import dataclass
from fractions import Fraction
from pathlib import Path

import sympy as sp

from codegen.derivation import symbols as s
from codegen.derivation.figures import spec_figures, spec_values
from codegen.derivation.paper import Derivation
from codegen.derivation.switching import PHASE_NAMES
from codegen.errors import show_value
from codegen.publish import (
    MANIFEST,
    PublishError,
    manifest_record,
    publish,
    refuse_foreign,
    refuse_root,
)
from codegen.render import provenance, render, write_atomically
from codegen.spec_model import Spec

TEMPLATE = "audit/DERIVATION.md.j2"
NAME = "DERIVATION.md"
#: Main duties at which the fail area is tabulated, besides the operating points'.
DUTY_GRID = tuple(Fraction(k, 10) for k in range(1, 11))


def _fmt(value: sp.Expr | Fraction, digits: int = 4) -> str:
    return f"{float(value):.{digits}g}"


def _rpm(value: sp.Expr | Fraction) -> str:
    return f"{float(value):.1f} rpm"


@dataclass(frozen=True)
class FailBand:
    duty: str
    works: str
    fails: str


def _limits(derivation: Derivation, spec: Spec) -> list[dict[str, str]]:
    rule = derivation["18"]
    inverter = spec.inverter
    rows = []
    for name, volts in (
        ("minimum", inverter.bus_voltage_min_v),
        ("nominal", inverter.bus_voltage_nominal_v),
        ("maximum", inverter.bus_voltage_max_v),
    ):
        values = spec_values(spec, volts)
        rows.append(
            {
                "bus": f"{name}, {_fmt(volts)} V",
                "cutoff": _rpm(rule.row("boundary_speed").subs(values)),
                "upper": _rpm(rule.row("upper_speed").subs(values)),
            }
        )
    return rows


def _operating_points(derivation: Derivation, spec: Spec) -> list[dict[str, str]]:
    figures = spec_figures(derivation, spec)
    return [
        {
            "speed": f"{_fmt(p.speed_rpm, 6)} rpm",
            "emf": f"{_fmt(p.emf_v)} V",
            "segment": p.region,
            "on": _fmt(p.improved_on),
            "off": _fmt(p.improved_off),
            "t_com": f"{float(p.improved_t_com_s) * 1e6:.1f} us",
            "sector": f"{float(p.sector_time_s) * 1e6:.1f} us",
            "main_duty": _fmt(p.main_duty),
            "conventional_off": _fmt(p.conventional_off),
            "fails": "yes" if p.conventional_fails else "no",
        }
        for p in figures.points
    ]


def _fail_bounds(derivation: Derivation) -> tuple[sp.Expr, sp.Expr]:
    """Speeds between which the conventional method's D_off (Eq. 16) is a duty, for a
    main duty D: below the first D_off > 1, above the second D_off < 0."""
    feasible = derivation["16"].row("feasible_on_duty")  # D_on in [low(E), high(E)]
    bounds = []
    for end in (feasible.start, feasible.end):
        (speed,) = sp.solve(sp.Eq(end.subs(s.E, s.k_e * s.n), s.D), s.n)
        bounds.append(sp.factor(speed))
    return bounds[0], bounds[1]


def _speed_latex(speed: sp.Expr) -> str:
    """A speed bound as a multiple of U_d/(4 k_e), the form the paper uses."""
    unit = s.U_d / (4 * s.k_e)
    factor = sp.expand(speed / unit)
    if factor.free_symbols <= {s.D}:
        return f"\\left({sp.latex(factor, order='rev-lex')}\\right) \\frac{{U_d}}{{4 k_e}}"
    return sp.latex(speed)


def _fail_bands(derivation: Derivation, spec: Spec) -> list[FailBand]:
    low, high = _fail_bounds(derivation)
    values = spec_values(spec)
    slowest = sp.Rational(spec.controller.speed_min_rpm)
    fastest = sp.Rational(spec.controller.speed_max_rpm)
    duties = sorted(set(DUTY_GRID) | {p.main_duty for p in spec.operating_points})
    bands = []
    for duty in duties:
        at = {**values, s.D: sp.Rational(duty.numerator, duty.denominator)}
        from_n, to_n = low.subs(at), high.subs(at)
        fails = []
        if from_n > slowest:
            fails.append(f"below {_rpm(from_n)} ($D_{{off}} > 1$)")
        if to_n < fastest:
            fails.append(f"above {_rpm(to_n)} ($D_{{off}} < 0$)")
        bands.append(
            FailBand(
                duty=_fmt(duty),
                works=f"{_rpm(max(from_n, 0))} to {_rpm(to_n)}",
                fails=", ".join(fails) or "nowhere in the speed range",
            )
        )
    return bands


def _switching(derivation: Derivation, spec: Spec) -> list[dict[str, str]]:
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


def _markdown_text(text: str) -> str:
    """The spec's own words as plain text of one Markdown paragraph: whitespace runs
    (line breaks included) become one space, HTML's specials are entities and
    Markdown's are escaped, so a description cannot open a heading, a list, a link or a
    script (`# Injected heading` and `<script>` had been written into DERIVATION.md)."""
    text = " ".join(text.split())
    text = text.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")
    text = re.sub(r"([\\`*_\[\]#|!])", r"\\\1", text)
    # nor a list item, which the description would start at its line's start: a bullet
    # or a number and its `.` or `)`, each followed by a space (`1.5 kW` is no item,
    # and a backslash before its digits had shown in the text)
    text = re.sub(r"^([-+])(?=\s|$)", r"\\\1", text)
    return re.sub(r"^(\d{1,9})([.)])(?=\s|$)", r"\1\\\2", text)


def render_derivation(derivation: Derivation, spec: Spec) -> str:
    low, high = _fail_bounds(derivation)
    controller = spec.controller
    return render(
        TEMPLATE,
        provenance=provenance(f"templates/{TEMPLATE}", spec),
        spec_name=spec.name,
        description=_markdown_text(spec.description).rstrip("."),
        method=controller.method,
        bus_nominal=f"{_fmt(spec.inverter.bus_voltage_nominal_v)} V",
        k_e=f"{_fmt(spec.motor.back_emf_constant_v_per_rpm * 1000)} V/krpm",
        current=f"{_fmt(controller.braking_current_nominal_a)} A",
        inductance=f"{_fmt(spec.motor.phase_inductance_h * 1000)} mH",
        pole_pairs=spec.motor.pole_pairs,
        speed_range=f"{_rpm(controller.speed_min_rpm)} to {_rpm(controller.speed_max_rpm)}",
        limits=_limits(derivation, spec),
        points=_operating_points(derivation, spec),
        fail_low=_speed_latex(low),
        fail_high=_speed_latex(high),
        fail_bands=_fail_bands(derivation, spec),
        switching=_switching(derivation, spec),
    )


#: The manifest's mark of a folder that holds the audit's DERIVATION.md alone
AUDIT_ONLY = "audit"


#: what the first lines of AUDIT.md and AUDIT.html say when bldc-codegen wrote them
AUDIT_MARKER = "Generated from template templates/audit/AUDIT."


def refuse_foreign_reports(
    folder: Path, names: tuple[str, ...], derivation: bool, spec_name: str | None = None
) -> None:
    """PublishError when writing the paper audit's `names` (AUDIT.md, AUDIT.html) or,
    with `derivation`, DERIVATION.md into `folder` would replace a file bldc-codegen did
    not write: `audit -o DIR` overwrote a hand-written AUDIT.md there. An audit report
    is the tool's when its head carries AUDIT_MARKER (the audit writes no manifest).
    A file-system root is refused (`audit -o /` had written AUDIT.md into /)."""
    refuse_root(folder)
    for name in names:
        path = folder / name
        if not (path.exists() or path.is_symlink()):
            continue
        head = ""
        if path.is_file() and not path.is_symlink():
            try:
                with open(path, encoding="utf-8", errors="replace") as stream:
                    head = stream.read(1000)
            except OSError:
                head = ""
        if AUDIT_MARKER not in head:
            raise PublishError(
                f"{path} is in the way and was not written by bldc-codegen (it lacks the"
                " audit's 'Generated from template' header): move it away or choose"
                " another output folder"
            )
    if derivation:
        recorded = _recorded(folder)
        if not (isinstance(recorded, dict) and "spec_sha256" in recorded):
            refuse_foreign(folder, (NAME, MANIFEST))
        elif spec_name is not None:
            refuse_another_specs_tree(folder, recorded, spec_name)


def _recorded(folder: Path) -> object:
    """The manifest of `folder`, as JSON; None where there is none or it is unreadable."""
    try:
        return json.loads((folder / MANIFEST).read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return None


def refuse_another_specs_tree(folder: Path, recorded: dict[str, object], spec_name: str) -> None:
    """PublishError where `folder` is the generated tree of a spec other than
    `spec_name`: its DERIVATION.md is that spec's (`audit maxon.yaml -o` paper_motor's
    tree had rewritten paper_motor's derivation with the Maxon's). The tree of the same
    spec keeps its copy rewritten in place."""
    name = recorded.get("spec_name")
    if name == spec_name:
        return
    raise PublishError(
        f"{folder} holds the generated output of another spec, {show_value(name)}, not of"
        f" {spec_name!r}: its DERIVATION.md is that spec's; give -o a folder of"
        f" {spec_name}'s own"
    )


def publish_derivation(text: str, folder: Path, spec_name: str) -> None:
    """Write DERIVATION.md into `folder` as bldc-codegen's own file, so that a later
    `generate` into the same folder replaces it instead of refusing it as foreign.

    In a generated tree (its manifest records a spec) the file is the tree's own and is
    rewritten in place (the same bytes while the spec is unchanged); anywhere else it is
    published with a manifest of its own that lists it alone, marked `"output": "audit"`
    (`codegen.freshness` says so instead of calling the folder stale). Another spec's
    generated tree is refused (`refuse_another_specs_tree`)."""
    recorded = _recorded(folder)
    if isinstance(recorded, dict) and "spec_sha256" in recorded:
        refuse_another_specs_tree(folder, recorded, spec_name)
        write_atomically(folder / NAME, text)
        return
    files = {NAME: text}
    files[MANIFEST] = json.dumps({**manifest_record(files), "output": AUDIT_ONLY}, indent=2) + "\n"
    publish(files, folder)

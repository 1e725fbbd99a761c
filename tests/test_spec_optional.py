"""The spec's optional entries: `motor.back_emf_shape` (the plant's EMF waveform) and
`tolerances` (the robustness campaign's ranges). Absent, a spec loads as before."""

from __future__ import annotations

from fractions import Fraction
from pathlib import Path

import numpy as np
import pytest
from conftest import without_tolerances

from codegen.errors import SpecError
from codegen.spec_drive import line_to_line_peak
from codegen.spec_loader import load_spec
from codegen.spec_model import BackEmfShape
from sim.drive import Drive
from sim.scenario import Case, paper_edge

ROOT = Path(__file__).resolve().parents[1]
TEXT = (ROOT / "spec" / "paper_motor.yaml").read_text(encoding="utf-8")
CONVENTION = "  back_emf_convention: phase\n"
RATING = "  short_circuit_current_max: 120 A\n"
TOLERANCES = """tolerances:
  phase_resistance: [-10, 40]
  phase_inductance: [-15, 15]
  back_emf_constant: [-10, 10]
  bus_voltage: [-16, 25]
"""


def _with_shape(tmp_path: Path, shape: str) -> Path:
    """The paper motor with `shape`, its bridge rated for the short circuit of any shape
    tried here: a wide flat top rectifies sooner (150 deg: the short's 125 A at
    speed_max, k_e at its upper tolerance, R and L at their lower, over its 120 A)."""
    assert TEXT.count(CONVENTION) == 1
    path = tmp_path / "shape.yaml"
    text = TEXT.replace(CONVENTION, CONVENTION + f"  back_emf_shape: {shape}\n")
    path.write_text(text.replace(RATING, "  short_circuit_current_max: 200 A\n"))
    return path


def _without_tolerances() -> str:
    """The default spec with its `tolerances` section (and its source) taken out."""
    return without_tolerances(TEXT)


def _with_tolerances(tmp_path: Path, section: str) -> Path:
    path = tmp_path / "tolerances.yaml"
    text = _without_tolerances()
    path.write_text(text.replace("\noperating_points:", f"\n{section}\noperating_points:"))
    return path


def test_absent_keys_should_give_the_papers_trapezoid_and_no_tolerances(tmp_path: Path) -> None:
    path = tmp_path / "plain.yaml"
    path.write_text(_without_tolerances())
    assert load_spec(path).tolerances is None
    spec = load_spec(ROOT / "spec" / "paper_motor.yaml")
    assert spec.tolerances is not None
    assert spec.motor.back_emf_shape == BackEmfShape()
    assert spec.motor.back_emf_shape.flat_top_deg == 120
    assert Drive.from_spec(spec).emf_points == ((0, 0), (30, 1), (150, 1), (180, 0))


def test_flat_top_width_should_shape_the_plants_emf(tmp_path: Path) -> None:
    spec = load_spec(_with_shape(tmp_path, "150 deg"))
    assert spec.motor.back_emf_shape.points[1] == (Fraction(15), Fraction(1))
    drive = Drive.from_spec(spec)
    case = Case(drive, paper_edge(), 1000.0, 5.0, "spec")
    off = case.edge.turn_off
    e = drive.emf_v(1000.0)
    sector = case.sector_time_s
    # 150 deg: the outgoing phase stays at -E for 15 deg (a quarter sector) after the
    # edge, then ramps to +E over 30 deg (half a sector), twice as steep as 120 deg.
    assert case.emf.values(0.2 * sector)[off] == pytest.approx(-e)
    assert case.emf.values(0.5 * sector)[off] == pytest.approx(0.0, abs=1e-12)
    assert case.emf.values(0.75 * sector)[off] == pytest.approx(e)
    assert case.emf.corners(0.0, sector) == pytest.approx([0.25 * sector, 0.75 * sector])


def test_flat_should_freeze_the_plants_emf_at_the_edge(tmp_path: Path) -> None:
    """`flat`: the paper's idealisation (section 3.2): the EMFs keep their edge values
    through the commutation, in the plant as in the rule."""
    spec = load_spec(_with_shape(tmp_path, "flat"))
    shape = spec.motor.back_emf_shape
    assert shape.frozen and shape == BackEmfShape.flat()
    assert shape.describe().startswith("flat")
    drive = Drive.from_spec(spec)
    assert drive.emf_frozen
    case = Case(drive, paper_edge(), 1000.0, 5.0, "spec")
    e = drive.emf_v(1000.0)
    for t in (0.0, 0.4 * case.sector_time_s, 0.9 * case.sector_time_s):
        values = case.emf.values(t)
        assert values[case.edge.non_commutating] == pytest.approx(e)
        assert values[case.edge.turn_off] == pytest.approx(-e)
        assert values[case.edge.turn_on] == pytest.approx(-e)
    assert case.emf.corners(0.0, case.sector_time_s) == []


def test_measured_table_should_be_interpolated(tmp_path: Path) -> None:
    table = "[[0, 0], [60, 0.9], [90, 1.05], [120, 0.9], [180, 0]]"
    spec = load_spec(_with_shape(tmp_path, table))
    assert spec.motor.back_emf_shape.flat_top_deg is None
    drive = Drive.from_spec(spec)
    case = Case(drive, paper_edge(), 1000.0, 5.0, "spec")
    nc = case.edge.non_commutating
    # The non-commutating phase sits mid flat top at the edge's sector middle (90 deg).
    values = [case.emf.values(t)[nc] for t in np.linspace(0, case.sector_time_s, 7)]
    assert max(values) == pytest.approx(1.05 * drive.emf_v(1000.0))


@pytest.mark.parametrize(
    ("shape", "fragments"),
    [
        ("180 deg", ("motor.back_emf_shape", "0 < w < 180 deg")),
        ("120", ("motor.back_emf_shape", "'<w> deg'")),
        ("flats", ("motor.back_emf_shape", "'flat'")),
        # \d took other scripts' digits: '١٢٠ deg' loaded as a 120 deg flat top
        ('"\u0661\u0662\u0660 deg"', ("motor.back_emf_shape", "not a flat-top width")),
        # digits as many as a quantity takes (int()'s limit is 4300)
        (f'"{"1" * 70} deg"', ("motor.back_emf_shape", "'<w> deg'")),
        ("[[0, 0], [90, 1], [170, 0]]", ("motor.back_emf_shape", "from 0 deg to 180 deg")),
        ("[[0, 0], [90, 1], [80, 1], [180, 0]]", ("motor.back_emf_shape[2]", "not above")),
        ("[[0, 0.1], [90, 1], [180, 0]]", ("motor.back_emf_shape", "0 at 0 deg and 180 deg")),
        ("[[0, 0], [90, 3], [180, 0]]", ("motor.back_emf_shape[1]", "-2 <= e/E <= 2")),
        # a pure triplen shape: e_a - e_b = 0 everywhere (every command had divided by its
        # line-to-line peak: ZeroDivisionError)
        (
            "[[0, 0], [30, -1], [90, 1], [150, -1], [180, 0]]",
            ("motor.back_emf_shape", "no line-to-line EMF to brake with", "0 E at its peak"),
        ),
    ],
)
def test_bad_emf_shape_should_name_the_key_and_the_allowed_range(
    tmp_path: Path, shape: str, fragments: tuple[str, ...]
) -> None:
    with pytest.raises(SpecError) as error:
        load_spec(_with_shape(tmp_path, shape))
    message = str(error.value)
    assert all(f in message for f in fragments), message
    assert "shape.yaml:" in message  # the YAML line


@pytest.mark.parametrize(
    ("width", "shown"),
    [
        (Fraction("119.9999999"), "trapezoid, 119.9999999 deg flat top"),
        (Fraction(120), "trapezoid, 120 deg flat top"),
        (Fraction("150.5"), "trapezoid, 150.5 deg flat top"),
        (Fraction(400, 3), "trapezoid, 133.333333333 deg flat top"),
    ],
)
def test_a_flat_top_width_should_be_described_as_written(width: Fraction, shown: str) -> None:
    """`back_emf_shape: "119.9999999 deg"` under improved_r was refused as 'trapezoid,
    120 deg flat top' (`:g`), with '120 deg' as the allowed value: the width is shown
    exactly, so that it differs visibly from the allowed one."""
    assert BackEmfShape.trapezoid(width).describe() == shown


def test_a_width_just_off_120_deg_should_be_refused_showing_its_digits(tmp_path: Path) -> None:
    from codegen.generate import render_all
    from codegen.methods.base import FixedPointError

    path = _with_shape(tmp_path, '"119.9999999 deg"')
    path.write_text(path.read_text().replace("method: improved\n", "method: improved_r\n"))
    with pytest.raises(FixedPointError) as error:
        render_all(path)
    assert "'trapezoid, 119.9999999 deg flat top'" in str(error.value), error.value


def test_tolerances_should_load_as_fractions(tmp_path: Path) -> None:
    spec = load_spec(_with_tolerances(tmp_path, TOLERANCES))
    assert spec.tolerances is not None
    assert spec.tolerances.phase_resistance == (Fraction(-1, 10), Fraction(2, 5))
    assert spec.tolerances.bus_voltage == (Fraction(-4, 25), Fraction(1, 4))


@pytest.mark.parametrize(
    ("old", "new", "fragments"),
    [
        (
            "bus_voltage: [-16, 25]",
            "bus_voltage: [-20, 25]",
            ("tolerances.bus_voltage", "19.2", "[-16.6666, 25] %"),
        ),
        (
            "phase_inductance: [-15, 15]",
            "phase_inductance: [15, -15]",
            ("tolerances.phase_inductance", "inverted"),
        ),
        (
            "back_emf_constant: [-10, 10]",
            "back_emf_constant: 10",
            ("tolerances.back_emf_constant", "pair"),
        ),
        (
            "back_emf_constant: [-10, 10]",
            "back_emf_constan: [-10, 10]",
            ("tolerances.back_emf_constan", "unknown key"),
        ),
    ],
)
def test_bad_tolerances_should_name_the_key_and_the_allowed_range(
    tmp_path: Path, old: str, new: str, fragments: tuple[str, ...]
) -> None:
    with pytest.raises(SpecError) as error:
        load_spec(_with_tolerances(tmp_path, TOLERANCES.replace(old, new)))
    message = str(error.value)
    assert all(f in message for f in fragments), message


def test_every_bad_tolerance_should_be_listed_not_only_the_first(tmp_path: Path) -> None:
    """Exit 3 lists every error of a spec, one per line: three ranges out of bounds
    were reported one at a time (the section stopped at the first)."""
    section = TOLERANCES.replace("[-10, 40]", "[-99, 900]").replace("[-15, 15]", "[-99, 900]")
    section = section.replace("[-10, 10]", "[-99, 900]")
    with pytest.raises(SpecError) as error:
        load_spec(_with_tolerances(tmp_path, section))
    lines = str(error.value).splitlines()
    for key in ("phase_resistance", "phase_inductance", "back_emf_constant"):
        assert sum(f"tolerances.{key} = [-99, 900]" in line for line in lines) == 1, lines
    assert len(lines) == 3, lines


SINE_TABLE = "[" + ", ".join(f"[{a}, {np.sin(np.radians(a)):.4f}]" for a in range(0, 181, 15)) + "]"


@pytest.mark.parametrize("shape", ["flat", "120 deg", "150 deg", "60 deg", "100 deg", SINE_TABLE])
def test_the_edge_angles_should_give_the_switching_tables_edge_emfs(
    tmp_path: Path, shape: str
) -> None:
    """The loader's edge angles (90, -30, 210 deg from each phase's rising zero crossing)
    against the EMFs the switching table's paper edge gives (`edge_emfs`, derived from
    the table's ramps): the two ways agree on every shape."""
    from codegen.derivation import derive
    from codegen.derivation.shape_terms import edge_emfs
    from codegen.spec_drive import emf_at
    from codegen.spec_loader import EDGE_ANGLES_DEG, PAPER_EDGE_EMFS

    spec_shape = load_spec(_with_shape(tmp_path, shape)).motor.back_emf_shape
    table_says = edge_emfs(spec_shape, derive().switching, Fraction(0))
    if spec_shape.frozen:
        assert table_says == PAPER_EDGE_EMFS
    else:
        assert tuple(emf_at(spec_shape, a) for a in EDGE_ANGLES_DEG) == table_says


@pytest.mark.parametrize(
    ("shape", "shown"),
    [
        ("flat", None),
        ("120 deg", None),
        ("150 deg", None),
        ("121 deg", None),
        # a flat top of 119 deg: the turn-off and turn-on phases are at -(30/30.5) E at
        # the edge, 1.6 % off (the slack is 1 %)
        ("119 deg", "(+1, -0.984, -0.984) E"),
        ("60 deg", "(+1, -0.5, -0.5) E"),
        (SINE_TABLE, "(+1, -0.5, -0.5) E"),
    ],
)
def test_a_shape_off_the_papers_edge_emfs_should_be_warned_of_under_the_papers_methods(
    tmp_path: Path, shape: str, shown: str | None
) -> None:
    """Eq. 18 holds the non-commutating current with (E/U_d)(2 e_a - e_b - e_c)/E = 4 E/U_d
    of a PWM period; a sine's 3 at the edge moves the duty sum by E/U_d of the period,
    printed in TIM1 counts at speed_max and bus_voltage_min (computed here from the
    spec's values). The resistance-aware rule is not warned: it follows the shape, or
    refuses one it cannot follow."""
    path = _with_shape(tmp_path, shape)
    spec = load_spec(path)
    warnings = [w for w in spec.warnings if w.id == "emf-shape-not-paper"]
    assert bool(warnings) is (shown is not None)
    if shown is None:
        return
    (warning,) = warnings
    line = str(warning)
    assert "motor.back_emf_shape" in line and shown in line
    # a warning on a measured table carries the YAML list: the spec stays hashable (the
    # core's build is cached by it; generate had failed with "unhashable type: 'list'")
    # and the line shows the table as written
    hash(spec)
    if shape == SINE_TABLE:
        assert "motor.back_emf_shape = [[0, 0.0], [15, 0.2588], [30, 0.5]," in line
    assert "which controller.method improved applies" in line
    if shown == "(+1, -0.5, -0.5) E":
        inverter, motor = spec.inverter, spec.motor
        counts = inverter.timer_clock_hz / inverter.pwm_frequency_hz
        e_top = motor.back_emf_constant_v_per_rpm * spec.controller.speed_max_rpm
        assert inverter.pwm_alignment == "edge"
        assert f"{float(e_top / inverter.bus_voltage_min_v * counts):.4g} TIM1 counts" in line
    text = path.read_text(encoding="utf-8")
    path.write_text(text + "warnings:\n  silence: [emf-shape-not-paper]\n", encoding="utf-8")
    assert not [w for w in load_spec(path).warnings if w.id == "emf-shape-not-paper"]
    resistance_aware = text.replace("  method: improved\n", "  method: improved_r\n")
    assert resistance_aware != text
    path.write_text(resistance_aware, encoding="utf-8")
    assert not [w for w in load_spec(path).warnings if w.id == "emf-shape-not-paper"]


def test_a_long_measured_table_should_load_and_be_warned_of_in_one_short_line(
    tmp_path: Path,
) -> None:
    """A 2001-point measured sine: the loader's and the drive's checks evaluate the
    table at every breakpoint of the line-to-line EMF (bisection, the shape's hash kept:
    a 3001-point table had taken `generate` 150 s), and the warning names the table by
    its first points, not all of them (90 kB on one line)."""
    import math

    points = [
        [round(180 * k / 2000, 4), round(math.sin(math.pi * k / 2000), 6)] for k in range(2001)
    ]
    points[-1][1] = 0
    spec = load_spec(_with_shape(tmp_path, str(points)))
    shape = spec.motor.back_emf_shape
    assert len(shape.points) == 2001
    assert float(line_to_line_peak(shape)) == pytest.approx(math.sqrt(3), rel=1e-5)
    (warning,) = [w for w in spec.warnings if w.id == "emf-shape-not-paper"]
    line = str(warning)
    assert "motor.back_emf_shape = [[0.0, 0.0], [0.09, 0.001571], [0.18, " in line
    assert len(line) < 1000


@pytest.mark.parametrize(
    ("value", "refused"), [("1.5 V/rpm", False), ("2 V/rpm", False), ("2.5 V/rpm", True)]
)
def test_a_line_to_line_constant_should_be_held_to_the_phase_range_times_its_factor(
    tmp_path: Path, value: str, refused: bool
) -> None:
    """The range [1e-5, 1] V/rpm is the phase k_e's; line to line (2 k_e for the 120 deg
    trapezoid) it is twice that: the same motor had loaded as 0.75 V/rpm phase and been
    refused as 1.5 V/rpm line to line."""
    text = TEXT.replace(CONVENTION, "  back_emf_convention: line_to_line\n")
    path = tmp_path / "ltl.yaml"
    path.write_text(text.replace("back_emf_constant: 2.36 V/krpm", f"back_emf_constant: {value}"))
    assert path.read_text() != TEXT
    with pytest.raises(SpecError) as error:  # the paper motor's top speed is far too high
        load_spec(path)
    lines = [line for line in str(error.value).splitlines() if "motor.back_emf_constant" in line]
    if not refused:
        assert lines == []
        return
    assert len(lines) == 1
    assert "(allowed: [2e-05, 2] V/rpm line to line (the phase k_e in [1e-05, 1] V/rpm" in lines[0]


def test_a_bus_tolerance_just_past_the_inverters_range_should_show_the_difference(
    tmp_path: Path,
) -> None:
    """-16.666666666666668 % of 24 V is a hair below 20 V: the refusal had said "puts
    the bus at 20-30 V, outside the inverter's 20-30 V (allowed: [-16.67, 25] %)", and
    the allowed bound it gave was itself refused. The voltage shows the difference and
    the bounds are rounded inwards, so that a bound copied from the message loads."""
    section = TOLERANCES.replace("[-16, 25]", "[-16.666666666666668, 25]")
    with pytest.raises(SpecError) as error:
        load_spec(_with_tolerances(tmp_path, section))
    message = str(error.value)
    assert "puts the bus at 19.9999999999999997-30 V, outside the inverter's 20-30 V" in message
    assert "(allowed: [-16.6666, 25] %)" in message
    load_spec(_with_tolerances(tmp_path, TOLERANCES.replace("[-16, 25]", "[-16.6666, 25]")))


@pytest.mark.parametrize(
    ("points", "fragment"),
    [
        (3602, "a table of 3602 points: every command evaluates it at each breakpoint"),
        (4001, "a motor.back_emf_shape table at most 3601 points"),
    ],
)
def test_a_table_longer_than_allowed_should_say_how_many_points_it_may_hold(
    tmp_path: Path, points: int, fragment: str
) -> None:
    """A 4901-point table had been refused as "more than 10000 values", which named
    neither the table nor its limit."""
    import math

    n = points - 1
    table = [[round(180 * k / n, 5), round(math.sin(math.pi * k / n), 6)] for k in range(points)]
    table[-1][1] = 0
    with pytest.raises(SpecError, match=r"motor\.back_emf_shape") as error:
        load_spec(_with_shape(tmp_path, str(table)))
    assert fragment in str(error.value)


def test_an_allowed_bus_bound_above_100_percent_should_keep_four_decimals(tmp_path: Path) -> None:
    """A 24 V bus whose inverter takes 53.6296272 V: the upper bound is 123.4567 %, and
    the refusal had offered 123.457 (6 significant digits, rounded outwards), which it
    refused in turn."""
    section = TOLERANCES.replace("[-16, 25]", "[-10, 200]")
    source = _with_tolerances(tmp_path, section)
    source.write_text(
        source.read_text(encoding="utf-8").replace(
            "bus_voltage_max: 30 V", "bus_voltage_max: 53.6296272 V"
        ),
        encoding="utf-8",
    )
    with pytest.raises(SpecError) as error:
        load_spec(source)
    assert "(allowed: [-16.6666, 123.4567] %)" in str(error.value)


def test_a_bad_tolerance_should_be_named_with_its_range_when_the_inverter_is_refused_too(
    tmp_path: Path,
) -> None:
    """The tolerances were read only once the inverter was valid: with a negative PWM
    frequency beside it, a 5000-character tolerance was reported by the fallback for
    values too long to read, with no allowed range (the hostile fuzzer's finding). Each
    pair is read now, the bus pair's check against the inverter's range waiting for a
    valid inverter."""
    section = TOLERANCES.replace("[-10, 40]", '"' + "x" * 5000 + '"')
    section = section.replace("[-16, 25]", "[-99, 900]")
    path = _with_tolerances(tmp_path, section)
    text = path.read_text(encoding="utf-8")
    assert text.count("pwm_frequency: 20 kHz") == 1
    path.write_text(text.replace("pwm_frequency: 20 kHz", "pwm_frequency: -5 kHz"))
    with pytest.raises(SpecError) as error:
        load_spec(path)
    lines = str(error.value).splitlines()
    assert any("inverter.pwm_frequency" in line for line in lines), lines
    (long,) = [line for line in lines if "tolerances.phase_resistance" in line]
    assert "(allowed: [low %, high %] with" in long, long
    (bus,) = [line for line in lines if "tolerances.bus_voltage" in line]
    assert "(allowed: [low %, high %] with" in bus, bus

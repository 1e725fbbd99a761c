"""Software in the loop: the generated C core is really called and really obeyed."""

from __future__ import annotations

import re
import shutil
from pathlib import Path

import pytest

from codegen.spec_loader import load_spec
from codegen.spec_model import Spec
from codegen.spec_variant import spec_with_method
from sim.drive import Drive
from sim.runs import Controller, simulate
from sim.scenario import Case, paper_edge, schedule_for
from sim.sil import (
    CORE_HEADER,
    CoreInputs,
    CoreLibrary,
    CoreOutputs,
    CoreSet,
    compile_core,
    core_command,
    expected_switches,
    load_core,
    prepare_cores,
    spec_with_emf_shape,
)

ROOT = Path(__file__).resolve().parents[1]
SPEC = ROOT / "spec" / "paper_motor.yaml"


@pytest.fixture(scope="module")
def spec() -> Spec:
    return load_spec(SPEC)


@pytest.fixture(scope="module")
def cores(spec: Spec) -> CoreSet:
    return prepare_cores(spec, ("none", "conventional", "improved"))


def _case(spec: Spec, speed: float) -> Case:
    drive = Drive.from_spec(spec)
    return Case(drive, paper_edge(), speed, drive.braking_current_a, "spec")


def _header_fields(header: str, type_name: str) -> list[str]:
    body = re.search(r"typedef struct \{([^{}]*)\} " + type_name, header)
    assert body is not None
    return re.findall(r"uint\d+_t (\w+);", body.group(1))


def test_a_variants_core_should_be_the_one_generate_writes(tmp_path: Path) -> None:
    """The simulation renders a method's variant with `render_core`, not the whole tree:
    its core files are byte for byte those `generate` writes for the same spec."""
    from codegen.generate import CORE_FILES, render_all, render_core

    variant = tmp_path / "paper_motor.yaml"
    variant.write_text(spec_with_method(SPEC.read_text(encoding="utf-8"), "conventional"))
    core, whole = render_core(variant).files, render_all(variant).files
    assert {name: core[name] for name in CORE_FILES} == {name: whole[name] for name in CORE_FILES}
    assert sorted(core) == sorted([*CORE_FILES, "manifest.json"])


def test_ctypes_structs_should_follow_the_generated_header() -> None:
    text = (ROOT / "generated" / "paper_motor" / "c" / CORE_HEADER).read_text(encoding="utf-8")
    assert _header_fields(text, "bldc_inputs_t") == [name for name, _ in CoreInputs._fields_]
    assert _header_fields(text, "bldc_outputs_t") == [name for name, _ in CoreOutputs._fields_]


def test_plant_should_apply_the_cores_compare_values_and_switches(
    spec: Spec, cores: CoreSet
) -> None:
    case = _case(spec, 1500.0)
    command = core_command(cores.cores["improved"], spec, cores.scaling, case, 5.0, 0.42)
    raw = command.core_outputs
    assert (raw["turn_on_switch"], raw["turn_off_switch"]) == expected_switches(case)  # T5, T3
    schedule = schedule_for(case, command, case.sector_time_s)
    during = schedule.duties_at(0.5 * command.commutation_time_s)
    counts = cores.scaling.period_counts
    assert during[raw["turn_on_switch"]] == raw["turn_on_compare"] / counts
    assert during[raw["turn_off_switch"]] == raw["turn_off_compare"] / counts
    assert sum(1 for d in during if d > 0) == 2
    assert command.commutation_time_s == raw["commutation_ticks"] / float(
        cores.scaling.hall_clock_hz
    )
    segment_ends = [s.end for s in schedule.segments]
    assert command.commutation_time_s in segment_ends
    after = schedule.duties_at(command.commutation_time_s + 1e-9)
    assert after[raw["turn_off_switch"]] == 0.0
    assert after[raw["turn_on_switch"]] == raw["in.main_duty_counts"] / counts


def test_conventional_core_should_flag_the_fail_area_at_4600_rpm(
    spec: Spec, cores: CoreSet
) -> None:
    case = _case(spec, 4600.0)
    core = cores.cores["conventional"]
    command = core_command(core, spec, cores.scaling, case, 5.0, 0.42)
    assert "FAIL_AREA_CLAMPED" in core.constants.flag_names(command.flags)
    assert command.off_duty(0) == 0.0  # Eq. 16 gives -0.229, clamped


def test_a_period_sweep_should_make_the_calls_commutate_makes(spec: Spec, cores: CoreSet) -> None:
    """`CoreLibrary.over_periods` (the clamp scan's loop) reuses one input structure:
    each of its results is the one a fresh `commutate` call gives at that period, across
    the over-speed limit, the flags' changes and the counter's top."""
    core = cores.cores["improved"]
    inputs = {
        "hall_code": 5,
        "previous_hall_code": 4,
        "hall_period_ticks": 0,
        "bus_voltage_adc": 2800,
        "phase_current_adc": 2600,
        "main_duty_counts": 1500,
    }
    periods = range(0, 2**16, 97)
    swept = core.over_periods(inputs, periods)
    single = [core.commutate({**inputs, "hall_period_ticks": t}) for t in periods]
    assert swept == [(o["commutation_ticks"], o["flags"]) for o in single]
    assert len({flags for _, flags in swept}) > 2  # the sweep crosses the flags' changes
    assert inputs["hall_period_ticks"] == 0  # the caller's inputs are left alone


def _stub_core(tmp_path: Path, method: str) -> CoreLibrary:
    """A core with the same API that ignores its inputs: half duty, 100 ticks."""
    c_dir = tmp_path / "stub"
    c_dir.mkdir()
    shutil.copy(ROOT / "generated" / "paper_motor" / "c" / CORE_HEADER, c_dir / CORE_HEADER)
    (c_dir / "bldc_commutation.c").write_text(
        '#include "bldc_commutation.h"\n'
        "void bldc_commutate(const bldc_inputs_t *in, bldc_outputs_t *out)\n"
        "{\n"
        "    (void)in;\n"
        "    out->turn_on_compare = BLDC_PWM_PERIOD_COUNTS / 2u;\n"
        "    out->turn_off_compare = BLDC_PWM_PERIOD_COUNTS / 2u;\n"
        "    out->commutation_ticks = 100u;\n"
        "    out->turn_on_switch = 4u;\n"
        "    out->turn_off_switch = 2u;\n"
        "    out->sector = 1u;\n"
        "    out->flags = 0u;\n"
        "}\n",
        encoding="utf-8",
    )
    return load_core(c_dir, method, tmp_path / "build")


def test_simulation_should_change_when_the_c_core_changes(
    spec: Spec, cores: CoreSet, tmp_path: Path
) -> None:
    case = _case(spec, 1500.0)
    real = Controller(spec, cores)
    stub_cores = CoreSet(spec, {**cores.cores, "improved": _stub_core(tmp_path, "improved")})
    stub = Controller(spec, stub_cores)
    real_command = real.command("improved", case, case.pre_edge_duty)
    stub_command = stub.command("improved", case, case.pre_edge_duty)
    assert stub_command.core_outputs["commutation_ticks"] == 100
    assert stub_command.on_duties == (0.5,) and stub_command.commutation_time_s == 1e-4
    real_run = simulate(case, real_command, "switched")
    stub_run = simulate(case, stub_command, "switched")
    assert abs(real_run.metrics.deviation_worst_pct - stub_run.metrics.deviation_worst_pct) > 5.0


def test_spec_with_method_should_only_change_the_method(spec: Spec) -> None:
    text = SPEC.read_text(encoding="utf-8")
    changed = spec_with_method(text, "none")
    diff = [(a, b) for a, b in zip(text.splitlines(), changed.splitlines(), strict=True) if a != b]
    assert diff == [("  method: improved", "  method: none")]


def test_all_twelve_edges_should_brake_alike_through_the_c_core(spec: Spec, cores: CoreSet) -> None:
    """Reverse rotation negates every EMF (paper 2.2) and runs the sectors backwards;
    by symmetry each of the 12 commutations of the switching table, forward or
    reverse, upper or lower, must give the same non-commutating current."""
    from sim.scenario import switching_table

    drive = Drive.from_spec(spec)
    controller = Controller(spec, cores)
    worst = {}
    for edge in switching_table().edges:
        case = Case(drive, edge, 1500.0, drive.braking_current_a, "spec")
        command = controller.command("improved", case, case.pre_edge_duty)
        worst[(edge.direction, edge.sector_to)] = simulate(
            case, command, "switched"
        ).metrics.deviation_worst_pct
    reference = worst[("forward", paper_edge().sector_to)]
    assert -20.0 < reference < -5.0  # the paper's rule with R: a sag, not a collapse
    for key, value in worst.items():
        assert value == pytest.approx(reference, abs=0.05), key


def test_checked_in_core_should_serve_only_its_own_spec(tmp_path: Path) -> None:
    """A user's motor named like a checked-in one (or an edited spec) gets its own core."""
    from codegen.render import PROJECT_ROOT
    from sim.sil import _is_output_of

    generated = PROJECT_ROOT / "generated" / "paper_motor"
    assert _is_output_of(load_spec(SPEC), generated)
    mine = tmp_path / "paper_motor.yaml"
    text = SPEC.read_text(encoding="utf-8")
    mine.write_text(
        text.replace("phase_resistance: 0.21 ohm", "phase_resistance: 0.23 ohm", 1),
        encoding="utf-8",
    )
    assert mine.read_text(encoding="utf-8") != text
    assert not _is_output_of(load_spec(mine), generated)


def test_a_shape_improved_r_refuses_should_fall_back_to_the_paper_trapezoid(
    tmp_path: Path,
) -> None:
    """The variants are generated in this process: a spec whose EMF shape the
    resistance-aware design refuses (a 100 deg flat top is not affine over the
    commutation) gets its improved_r core for the paper's 120 deg trapezoid, said so,
    and the flat-EMF core beside it; the other methods' cores are the spec's own."""
    text = spec_with_emf_shape(SPEC.read_text(encoding="utf-8"), "100 deg")
    path = tmp_path / "shaped.yaml"
    path.write_text(text.replace("name: paper_motor", "name: shaped_motor"), encoding="utf-8")
    shaped = load_spec(path)
    assert shaped.name == "shaped_motor"
    cores = prepare_cores(shaped, ("improved", "improved_r"), tmp_path / "build")
    assert cores.shape_fallback == "120 deg"
    assert set(cores.cores) == {"improved", "improved_r"}
    assert set(cores.shaped) == {"flat"}
    fallback = (tmp_path / "build" / "specs" / "shaped_motor-improved_r.yaml").read_text()
    assert "back_emf_shape: 120 deg" in fallback


def test_an_improved_r_spec_whose_shape_its_design_refuses_should_be_refused_as_generate_does(
    tmp_path: Path,
) -> None:
    """The stand-in shape is for a rule compared on another method's motor: where the
    spec's own method is improved_r, `simulate` had run the stand-in's core and said
    "the spec's own method is another" of a spec `generate` refuses."""
    from sim.sil import SpecRefusedError

    text = spec_with_emf_shape(SPEC.read_text(encoding="utf-8"), "150 deg")
    text = text.replace("name: paper_motor", "name: shaped_ir").replace(
        "method: improved\n", "method: improved_r\n"
    )
    # the 150 deg flat top rectifies sooner: a bridge rated for its short circuit
    text = text.replace("short_circuit_current_max: 120 A", "short_circuit_current_max: 200 A")
    path = tmp_path / "shaped_ir.yaml"
    path.write_text(text, encoding="utf-8")
    shaped = load_spec(path)
    assert shaped.controller.method == "improved_r"
    with pytest.raises(SpecRefusedError) as refused:
        prepare_cores(shaped, ("improved", "improved_r"), tmp_path / "build")
    assert str(refused.value).startswith(f"{path}: motor.back_emf_shape: fixed-point design: ")
    assert "trapezoid, 150 deg flat top" in str(refused.value)


def test_a_rule_out_of_the_motors_duty_target_should_be_simulated_at_the_bound_it_meets(
    tmp_path: Path,
) -> None:
    """A motor whose own method meets its targets, where the resistance-aware rule's
    integer design misses its 0.6-count duty target (0.646 counts): its improved_r cores
    (the spec's EMF and the flat one) are generated for 0.65 counts and the report says
    so; `simulate` used to refuse the whole spec."""
    heavy = load_spec(ROOT / "tests" / "fixtures" / "odd" / "heavy_2k5_tight_duty.yaml")
    cores = prepare_cores(heavy, ("improved", "improved_r"), tmp_path / "build")
    assert cores.rule_duty_target == "0.65"
    assert set(cores.cores) == {"improved", "improved_r"}
    held = (tmp_path / "build" / "specs" / "heavy_2k5_tight_duty-improved_r.yaml").read_text()
    assert "duty_counts: 0.65" in held
    own = (tmp_path / "build" / "specs" / "heavy_2k5_tight_duty-improved.yaml").read_text()
    assert "duty_counts: 0.6\n" in own


def test_a_compared_method_out_of_the_time_target_should_be_simulated_at_its_bound(
    tmp_path: Path,
) -> None:
    """An improved_r motor at 80 A on a 2.25 kHz PWM, whose 500 kHz Hall clock leaves the
    paper's methods' X too few bits for the spec's 8 ticks where the time is well
    conditioned: `simulate` exited 5 ("generating the 'none' core failed"). The compared
    methods are generated for the bound they meet (20.75 ticks) at the same Hall clock,
    and the report says so; the spec's own core keeps its targets."""
    spec = load_spec(ROOT / "tests" / "fixtures" / "odd" / "drone_ir_80a_2k25.yaml")
    cores = prepare_cores(spec, ("none", "improved", "improved_r"), tmp_path / "build")
    assert cores.time_targets == {"none": "20.75", "improved": "20.75"}
    assert set(cores.cores) == {"none", "improved", "improved_r"}
    held = (tmp_path / "build" / "specs" / "drone_ir_80a_2k25-none.yaml").read_text()
    assert "commutation_time_ticks: 20.75" in held


def test_a_rule_its_integer_design_refuses_should_stand_in_in_real_arithmetic(
    tmp_path: Path,
) -> None:
    """The resistance-aware rule's integer design refuses a motor whose shortest sector is
    shorter than a PWM period (16 poles, 7000 rpm, 5 kHz): `simulate` failed on such a
    motor ("generating the 'improved_r' core failed") although its own method is
    `improved`. The rule in real arithmetic stands in for its cores, says why, and is
    what the clamp scan and the commands see; robustness leaves it out (it has no
    library to load)."""
    from sim.clamp import scan
    from sim.rule_stand_in import RuleStandIn

    spec = load_spec(ROOT / "tests" / "fixtures" / "odd" / "short_sector_5k_16p.yaml")
    cores = prepare_cores(spec, ("improved", "improved_r"), tmp_path / "build")
    rule = cores.cores["improved_r"]
    assert isinstance(rule, RuleStandIn) and rule.path is None
    assert cores.rule_refused is not None
    assert "shorter than one PWM period" in cores.rule_refused
    assert isinstance(cores.shaped.get("flat", rule), RuleStandIn)
    drive = Drive.from_spec(spec)
    controller = Controller(spec, cores)
    case = Case(drive, paper_edge(), 1500.0, drive.braking_current_a, "spec")
    command = controller.command("improved_r", case, 0.42)
    assert (
        command.turn_on_switch is not None and 0 < command.commutation_time_s < case.sector_time_s
    )
    clamped = scan(controller, drive, "improved_r", drive.bus_voltage_v, drive.braking_current_a)
    assert clamped.periods > 1000 and clamped.fastest_rpm is not None


def test_the_rule_in_real_arithmetic_should_agree_with_its_core_where_one_exists(
    spec: Spec, tmp_path: Path
) -> None:
    """The stand-in against the improved_r C core of the paper motor (which its integer
    design takes), on the same integers: the same switches, sector and safe state (the
    sibling core's), compare values within a count and the end within a carrier
    period, and TIME_CLAMPED where the core sets it."""
    from codegen.derivation import derive
    from codegen.fixedpoint.scaling import scaling
    from codegen.methods.improved_r.constants import rule_constants
    from sim.rule_stand_in import RuleStandIn

    cores = prepare_cores(spec, ("improved", "improved_r"), tmp_path / "build")
    rule_spec = load_spec(ROOT / "spec" / "paper_motor_improved_r.yaml")
    stand_in = RuleStandIn(
        cores.cores["improved"], rule_constants(rule_spec, scaling(rule_spec, derive())), ""
    )
    core = cores.cores["improved_r"]
    carrier = 72_000_000 // int(spec.inverter.pwm_frequency_hz) * 1_000_000 // 72_000_000
    clamped = core.constants.flags["TIME_CLAMPED"]
    compared = 0
    for period in (1500, 2000, 4000, 9000, 20000, 50000, 60000):
        for bus in (2400, 2800, 3300, 3500):
            for current in (2100, 2300, 2600, 3000):
                inputs = {
                    "hall_code": 4,
                    "previous_hall_code": 5,
                    "hall_period_ticks": period,
                    "bus_voltage_adc": bus,
                    "phase_current_adc": current,
                    "main_duty_counts": 1500,
                }
                want, got = core.commutate(inputs), stand_in.commutate(inputs)
                for key in ("turn_on_switch", "turn_off_switch", "sector"):
                    assert got[key] == want[key], (inputs, key)
                if want["turn_on_switch"] == core.constants.no_switch:
                    continue
                compared += 1
                assert abs(got["turn_on_compare"] - want["turn_on_compare"]) <= 1, inputs
                assert abs(got["turn_off_compare"] - want["turn_off_compare"]) <= 1, inputs
                assert abs(got["commutation_ticks"] - want["commutation_ticks"]) <= carrier, inputs
                assert (got["flags"] & clamped) == (want["flags"] & clamped), inputs
    assert compared > 60


def test_the_core_cache_should_be_under_the_current_folder(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """`simulate` run from a user's folder compiled its cores into the project's own
    build/sim (an installed copy's folder); it is the current folder's build/sim, as
    every command's output, and the library's path is absolute (loaded later from
    anywhere)."""
    c_dir = ROOT / "generated" / "paper_motor" / "c"
    monkeypatch.chdir(tmp_path)
    library = compile_core(c_dir)
    assert library.is_absolute() and library.parent == tmp_path / "build" / "sim"
    assert library.is_file() and [p.name for p in library.parent.iterdir()] == [library.name]

"""`make prove`: Frama-C proves the shipped C, and goes red on a planted fault.

A green proof says nothing unless it turns red when the C is wrong, so each mutant in
the table below plants one fault in a copy of a generated core (a narrowed
intermediate type, a dropped clamp, a widened input range, a wrong table entry) and
the proof must catch it: an EVA alarm in the function's own analysis over every input,
or a contract clause that neither WP nor EVA can establish any more. Each check runs
on the unmutated copy first, so it cannot pass vacuously. Frama-C missing fails these
tests (tests/conftest.py turns skips into failures).

This module also proves every checked-in spec (what `make prove` does, writing
generated/<spec>/PROOF.md) and the unusual motors in tests/fixtures/specs/, one test
each, so pytest-xdist spreads the Frama-C runs over the cores with the rest of the suite.
"""

from __future__ import annotations

import shutil
import subprocess
from functools import cache
from pathlib import Path

import pytest

from codegen.core.module import build_core
from codegen.errors import ExitCode
from codegen.proof.harness import INTERVAL, SIGNED_INTERVAL, clz_model, proof_plan
from codegen.spec_loader import load_spec
from verify.frama_c import (
    WP_LET,
    WP_NO_LET,
    EvaResult,
    Property,
    Tools,
    find_tools,
    run_eva,
)
from verify.prove import (
    StaleGeneratedError,
    _looping,
    _passes,
    establish,
    eva_established,
    main,
    shipped_output,
    target_at,
    target_for,
)

ROOT = Path(__file__).resolve().parents[1]
SPECS = {
    "paper_motor": ROOT / "spec" / "paper_motor.yaml",
    "paper_motor_improved_r": ROOT / "spec" / "paper_motor_improved_r.yaml",
    "maxon_ec45_flat_48v": ROOT / "spec" / "example_maxon_ec45_flat_48v.yaml",
}
FIXTURES = sorted((ROOT / "tests" / "fixtures" / "specs").glob("*.yaml"))
#: CPU seconds of each spec's whole proof (the order the long tests are queued in,
#: tests/conftest.py); the per-bus-code EVA partitioning is most of the longest
PROOF_SECONDS = {
    "paper_motor": 21,
    "example_maxon_ec45_flat_48v": 22,
    "hub_motor_46p": 20,
    "offset_conventional": 14,
    "paper_motor_improved_r": 18,
    "fast_14p_12v": 17,
    "short_sector_2k5_ir": 15,
}
#: the same for the mutants whose check runs WP (the others take under a second): the
#: clause they break costs its timeout in both of WP's passes, two provers at once in
#: the second
MUTANT_SECONDS = {
    "unclamped_late_time": 10,
    "anti_windup_dropped": 7,
    "invalid_hall_pair_made_valid": 7,
    "loop_duty_unclamped_above": 7,
}
#: Each prover's time per goal in the mutant checks, the unmutated baseline's and the
#: mutant's alike: the baselines' clauses are established by EVA or proven by Z3 in at
#: most 0.4 s (5 times less), and a planted fault's clause is false, so no time proves
#: it; `make prove` keeps its own WP_TIMEOUT_S (5 s). The 5 s timeouts were about 48 of
#: the suite's CPU seconds, waited out three times (Z3, then Z3 and CVC4) per mutant.
MUTANT_WP_TIMEOUT_S = 2

#: (spec, mutant, original text, replacement, function whose proof must catch it,
#:  "alarm" or the contract clause that must no longer be established)
PROOF_MUTANTS = [
    (
        "paper_motor",
        "narrowed_intermediate",
        "const int32_t w_q = ",
        "const int16_t w_q = ",
        "bldc_commutate",
        "alarm",
    ),
    (
        "paper_motor_improved_r",
        "narrowed_wide_product",
        "(((uint64_t)e * (uint64_t)bldc_decay[step]) >> 32u)",
        "((uint64_t)(e * bldc_decay[step]) >> 32u)",
        "bldc_commutation_timing",
        "alarm",
    ),
    (
        "paper_motor",
        "dropped_duty_clamp",
        "on = (2 * (int32_t)BLDC_PWM_PERIOD_COUNTS - x_c < 0) ? 0 : "
        "2 * (int32_t)BLDC_PWM_PERIOD_COUNTS - x_c;",
        "on = 2 * (int32_t)BLDC_PWM_PERIOD_COUNTS - x_c;",
        "bldc_commutate",
        "alarm",
    ),
    (
        "paper_motor",
        "dropped_time_clamp",
        "        ticks = (ticks > latest) ? latest : ticks; /* at most the sector, less the guard */\n",
        "",
        "bldc_commutate",
        "alarm",
    ),
    (
        "paper_motor_improved_r",
        "unclamped_late_time",
        ".commutation_ticks = (uint16_t)((ticks > latest) ? latest : ticks),",
        ".commutation_ticks = (uint16_t)(ticks + CARRIER_NUM),",
        "bldc_commutation_timing",
        "commutation_ends_the_guard_early",
    ),
    (
        # the issue's overflow: Eq. 20's product for current codes of 5492 and above
        "paper_motor",
        "widened_current_range",
        "const uint32_t current_code = (current_adc > BLDC_ADC_CODE_MAX) ? "
        "BLDC_ADC_CODE_MAX : current_adc;",
        "const uint32_t current_code = current_adc;",
        "bldc_commutate",
        "alarm",
    ),
    (
        # on the improved_r core (its EVA takes 0.4 s, the paper core's per-bus-code
        # partitioning 13 s): N = T CARRIER_DEN / CARRIER_NUM overflows past the cap
        "paper_motor_improved_r",
        "widened_period_range",
        "#define BLDC_PERIOD_CAP_TICKS 65535u",
        "#define BLDC_PERIOD_CAP_TICKS 4294967295u",
        "bldc_commutation_timing",
        "alarm",
    ),
    (
        "paper_motor",
        "invalid_hall_pair_made_valid",
        "255u, /* 000 -> 001: invalid: every switch off */",
        "0u, /* 000 -> 001: invalid: every switch off */",
        "bldc_edge_of",
        "no_edge",
    ),
    (
        "paper_motor",
        "anti_windup_dropped",
        "? state : total;",
        "? total : total;",
        "bldc_current_loop_integrate",
        "holds_where_saturated",
    ),
    (
        "maxon_ec45_flat_48v",
        "loop_duty_unclamped_above",
        "const int32_t limited = (demand < 0) ? 0 : (demand > BLDC_LOOP_STATE_MAX)"
        " ? BLDC_LOOP_STATE_MAX : demand;",
        "const int32_t limited = (demand < 0) ? 0 : demand;",
        "bldc_current_loop_duty",
        "within_d_max",
    ),
]


@pytest.fixture(scope="module")
def tools(tmp_path_factory: pytest.TempPathFactory) -> Tools:
    return find_tools(tmp_path_factory.mktemp("why3"))


def _copy(name: str, where: Path) -> Path:
    root = where / name
    shutil.copytree(ROOT / "generated" / name, root, ignore=shutil.ignore_patterns("PROOF.md"))
    return root


def _plant(root: Path, original: str, replacement: str) -> None:
    for path in (
        root / "c" / "bldc_commutation.c",
        root / "c" / "bldc_commutation.h",
        root / "c" / "bldc_current_loop.h",
    ):
        text = path.read_text(encoding="utf-8")
        if original in text:
            assert text.count(original) == 1, f"{original!r} is not unique in {path.name}"
            path.write_text(text.replace(original, replacement), encoding="utf-8")
            return
    raise AssertionError(f"{original!r}: the pattern no longer matches the printed C")


@cache
def _baseline(name: str, function: str, clause: str, work: str, tools: Tools) -> tuple[int, str]:
    """The unmutated core: 0 alarms and the clause established (else a test is vacuous)."""
    target = target_at(_copy(name, Path(work)), name, name)
    if clause == "alarm":
        analysis = next(a for a in target.plan["analyses"] if a["function"] == function)  # type: ignore[attr-defined]
        result = run_eva(tools, target.root, target.plan, analysis, Path(work) / "baseline")
        return result.alarm_count, ""
    eva, methods = establish(
        tools, target, function, [clause], Path(work) / "baseline", MUTANT_WP_TIMEOUT_S
    )
    return eva.alarm_count, methods[clause]


@pytest.mark.parametrize(
    ("spec", "mutant", "original", "replacement", "function", "caught_by"),
    [
        pytest.param(
            *m,
            id=f"{m[0]}-{m[1]}",
            marks=[pytest.mark.heavy(seconds=MUTANT_SECONDS[m[1]])]
            if m[1] in MUTANT_SECONDS
            else [],
        )
        for m in PROOF_MUTANTS
    ],
)
def test_prove_should_catch_every_mutant(
    tmp_path_factory: pytest.TempPathFactory,
    tools: Tools,
    spec: str,
    mutant: str,
    original: str,
    replacement: str,
    function: str,
    caught_by: str,
) -> None:
    base = tmp_path_factory.getbasetemp() / f"baseline-{spec}-{function}-{caught_by}"
    if not base.exists():
        base.mkdir()
    alarms, method = _baseline(spec, function, caught_by, str(base), tools)
    assert alarms == 0, f"the unmutated {spec} has {alarms} alarms in {function}"
    assert method != "NOT PROVEN", f"the unmutated {spec} does not establish {caught_by}"

    work = tmp_path_factory.mktemp(mutant)
    root = _copy(spec, work)
    _plant(root, original, replacement)
    target = target_at(root, spec, spec)
    if caught_by == "alarm":
        analysis = next(a for a in target.plan["analyses"] if a["function"] == function)  # type: ignore[attr-defined]
        # one alarm is enough, except where the test names the alarm it expects
        first_alarm = mutant != "widened_current_range"
        result = run_eva(
            tools, target.root, target.plan, analysis, work / "frama-c", first_alarm=first_alarm
        )
        assert result.alarm_count > 0, f"{mutant}: EVA found no alarm in {function}"
        if mutant == "widened_current_range":
            assert any("signed overflow" in a and "time_numerator" in a for a in result.alarms), (
                result.alarms
            )
    else:
        _, methods = establish(
            tools, target, function, [caught_by], work / "frama-c", MUTANT_WP_TIMEOUT_S
        )
        assert methods[caught_by] == "NOT PROVEN", f"{mutant}: {caught_by} still {methods}"


@pytest.mark.parametrize(
    "spec",
    [
        pytest.param(p, id=p.stem, marks=pytest.mark.heavy(seconds=PROOF_SECONDS[p.stem]))
        for p in [*SPECS.values(), *FIXTURES]
    ],
)
def test_prove_should_establish_every_spec(tmp_path: Path, spec: Path) -> None:
    """`make prove` on each checked-in spec (its shipped generated/<name>/, PROOF.md
    written there) and each unusual motor (generated into a work folder): proven, 0
    alarms. One test each, one Frama-C at a time: pytest-xdist spreads them."""
    loaded = load_spec(spec)
    shipped = shipped_output(loaded)
    assert (shipped is not None) == (spec in SPECS.values()), "generated/ is stale: make generate"
    status = main([str(spec), "--build", str(tmp_path), "--jobs", "1"])
    assert status == 0
    name = loaded.name
    root = shipped or tmp_path / name  # where main() generated it (target_for)
    text = (root / "PROOF.md").read_text(encoding="utf-8")
    assert text.startswith(f"# Proof of the `{name}` core: PROVEN")
    assert "NOT PROVEN" not in text
    assert "| 0 |" in text


def test_prove_should_take_the_generated_folder_under_the_current_one(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A user's motor generated into generated/<name> under their own folder is the
    one proven, PROOF.md beside it (prove had regenerated it into build/); --generated
    names another folder, and one without the spec's current output is refused."""
    from codegen.generate import generate

    monkeypatch.chdir(tmp_path)
    spec = tmp_path / "mine.yaml"
    text = SPECS["paper_motor"].read_text(encoding="utf-8")
    spec.write_text(text.replace("name: paper_motor", "name: mine_motor"), encoding="utf-8")
    generate(spec, Path("generated") / "mine_motor", tmp_path)
    target = target_for(str(spec), tmp_path / "build")
    assert target.root == tmp_path / "generated" / "mine_motor"
    assert not (tmp_path / "build").exists()
    generate(spec, tmp_path / "elsewhere", tmp_path)
    assert target_for(str(spec), tmp_path / "build", tmp_path / "elsewhere").root == (
        tmp_path / "elsewhere"
    )
    spec.write_text(spec.read_text(encoding="utf-8") + "\n# edited\n", encoding="utf-8")
    with pytest.raises(StaleGeneratedError, match=r"does not hold .* current output"):
        target_for(str(spec), tmp_path / "build", tmp_path / "elsewhere")


def test_prove_should_exit_with_one_line_on_a_bad_spec(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    bad = tmp_path / "bad.yaml"
    text = SPECS["paper_motor"].read_text(encoding="utf-8")
    assert "\n  poles: 2\n" in text
    bad.write_text(text.replace("\n  poles: 2\n", "\n  poles: 3\n"), encoding="utf-8")
    assert main([str(bad), "--build", str(tmp_path / "build")]) == ExitCode.SPEC == 3
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "poles" in err[0]


def test_prove_should_exit_with_one_line_on_a_spec_no_design_meets(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A valid spec whose current loop no fixed-point format meets: generating it for
    the proof raised FixedPointError through main(), a traceback (exit 1)."""
    refused = Path(__file__).parent / "fixtures" / "refused" / "heavy_l_pi_one_count.yaml"
    assert main([str(refused), "--build", str(tmp_path / "build")]) == ExitCode.SPEC
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1, err
    assert err[0].startswith("prove: accuracy.current_loop_duty_counts = 1 counts: ")


def test_prove_should_fail_when_frama_c_is_missing(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("PATH", str(tmp_path))  # no frama-c, no why3
    assert main([str(SPECS["paper_motor"]), "--build", str(tmp_path / "build")]) == (
        ExitCode.ENVIRONMENT
    )
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "frama-c" in err[0] and "make sysdeps" in err[0]


# ------------------------------------------------------------------ the harness


@pytest.mark.parametrize("spec", [*SPECS.values(), *FIXTURES], ids=lambda p: Path(p).stem)
def test_harness_should_give_every_input_every_value_of_its_type(spec: Path) -> None:
    """Nothing assumed away: each input is drawn over its whole C type, and the only
    annotations are partitions (split) of that space."""
    core = build_core(load_spec(spec))
    plan = proof_plan(core)
    text = "\n".join(plan.harness_functions)
    for ctype, builtin in INTERVAL.items():
        for call in text.split(f"{builtin}(")[1:]:
            low, high = call.split(")")[0].split(", ")
            assert low == "0u"
            assert high == f"{ctype.high}u", call
    for ctype, builtin in SIGNED_INTERVAL.items():
        for call in text.split(f"{builtin}(")[1:]:
            low, high = call.split(")")[0].split(", ")
            assert (low, high) == (f"{ctype.low + 1} - 1", str(ctype.high)), call
    # the current loop's functions are driven too, each over its whole input space
    for name in ("bldc_current_loop_duty", "bldc_current_loop_integrate", "bldc_current_reference"):
        assert f"void prove_{name}(void)" in text
    for banned in ("assume", "requires", "assert", "admit", "Frama_C_interval("):
        assert banned not in text
    annotations = [line.strip() for line in text.splitlines() if "@" in line]
    assert all(a.startswith(("//@ split", "/*@ split")) for a in annotations), annotations


@pytest.mark.parametrize(
    ("spec", "per_code"),
    [
        ("paper_motor", True),  # improved: D_on = 2P - X, relational
        ("maxon_ec45_flat_48v", True),
        ("paper_motor_improved_r", False),  # both duties clamped to [0, P]
    ],
)
def test_partitioning_should_follow_the_interval_proof(spec: str, per_code: bool) -> None:
    """One partition per bus code exactly when the IR's proven range of a compare value
    exceeds the PWM period, which no interval analysis can then bring back within it."""
    core = build_core(load_spec(SPECS[spec]))
    plan = proof_plan(core)
    assert plan.per_code is per_code
    timing = "\n".join(f for f in plan.harness_functions if "prove_bldc_commutation_timing" in f)
    assert ("/*@ split bus_code; */" in timing) is per_code
    assert ("//@ split period_ticks < bus.high_speed_period;" in timing) is per_code
    # the over-speed guard returns: EVA narrows the period on both sides by itself
    assert "split period_ticks < bus.period_min" not in timing


def test_clz_model_should_count_leading_zeros_as_the_compiler_does(tmp_path: Path) -> None:
    """The harness's __builtin_clz against GCC's, at every power of two and around it."""
    model = clz_model().replace(
        "int __builtin_clz(unsigned int x)", "int model_clz(unsigned int x)"
    )
    driver = tmp_path / "clz.c"
    driver.write_text(
        "#include <stdio.h>\n" + model + "\nint main(void)\n{\n    unsigned long bad = 0;\n"
        "    for (unsigned k = 0; k < 32; ++k) {\n"
        "        unsigned p = 1u << k;\n"
        "        unsigned xs[] = {p, p - 1u, p + 1u, p | (p >> 1), p | 1u};\n"
        "        for (unsigned j = 0; j < 5; ++j) {\n"
        "            if (xs[j] != 0u && model_clz(xs[j]) != __builtin_clz(xs[j])) {\n"
        '                printf("%u\\n", xs[j]);\n                ++bad;\n'
        "            }\n        }\n    }\n"
        "    if (model_clz(0xFFFFFFFFu) != 0) { ++bad; }\n"
        "    return bad != 0;\n}\n",
        encoding="utf-8",
    )
    exe = tmp_path / "clz"
    subprocess.run(["gcc", "-std=c99", "-O1", "-o", str(exe), str(driver)], check=True)
    assert subprocess.run([str(exe)], check=False).returncode == 0


@pytest.mark.parametrize(
    ("spec", "looping"),
    [("paper_motor", []), ("paper_motor_improved_r", ["bldc_commutation_timing"])],
)
def test_wp_should_take_each_function_in_its_form(
    tmp_path: Path, spec: str, looping: list[str]
) -> None:
    """Without variable elimination in both passes where a function loops (Qed's
    elimination takes minutes after the improved_r search), with it first where a
    function calls another (bldc_commutate's invalid Hall flag), without it first on a
    leaf of arithmetic (the paper core's timing: seconds of Qed a goal with it)."""
    target = target_at(_copy(spec, tmp_path), spec, spec)
    assert sorted(_looping(target)) == looping
    assert _passes(target, ["bldc_commutate"]) == (WP_LET, WP_NO_LET)
    assert _passes(target, ["bldc_bus_condition"]) == (WP_LET, WP_NO_LET)  # its long division
    mains = [str(a["main"]) for a in target.plan["analyses"]]  # type: ignore[attr-defined]
    assert _passes(target, mains) == (WP_LET, WP_NO_LET)
    assert _passes(target, ["bldc_current_loop_integrate"]) == (WP_NO_LET, WP_LET)
    timing = _passes(target, ["bldc_commutation_timing"])
    assert timing == ((WP_NO_LET, WP_NO_LET) if looping else (WP_NO_LET, WP_LET))


def _eva_with(statuses: list[tuple[str, str, str]]) -> EvaResult:
    """An EVA result of bldc_commutation_timing with these (kind, status, text) rows."""
    rows = tuple(
        Property("c/bldc_commutation.c", 10 + k, "bldc_commutation_timing", kind, status, text)
        for k, (kind, status, text) in enumerate(statuses)
    )
    return EvaResult("bldc_commutation_timing", "prove_timing", 1.0, (), 0, "", (), rows, "")


def test_wp_should_be_spared_only_what_eva_established_in_full() -> None:
    """WP's first pass leaves out a named postcondition valid in every instance, and the
    loop invariants only when EVA established every one of them (they are unnamed in
    Frama-C's report): one left Unknown and WP is asked for them all."""
    invariants = [
        ("loop invariant", "Valid", "0 ≤ step ≤ 10"),
        ("loop invariant", "Valid", "0 ≤ n ≤ 1000"),
    ]
    posts = [
        ("postcondition", "Valid", "in_period: \\result.ticks ≤ T"),
        ("postcondition", "Valid", "clamped: x"),
        ("postcondition", "Unknown", "clamped: y"),
    ]
    assert eva_established(_eva_with(invariants + posts)) == ["in_period", "@invariant"]
    invariants[1] = ("loop invariant", "Unknown", "0 ≤ n ≤ 1000")
    assert eva_established(_eva_with(invariants + posts)) == ["in_period"]
    assert eva_established(_eva_with(posts)) == ["in_period"]


def test_prove_should_take_a_relative_build_folder(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """`python -m verify.prove my.yaml --build pb` from a user's folder: Frama-C runs in
    a folder of its own, so the harness's relative include folder named nothing, the
    parse failed, and prove exited 5 (a missing tool). The proof's own runs are replaced
    by Frama-C's parse of each target, with the folders main() gives them."""
    import verify.prove as prove_module
    from verify.frama_c import parse

    def parse_only(targets: list, tools: Tools, build: Path, jobs: int) -> list:
        for t in targets:
            parse(tools, t.root, t.plan, build / t.name / "frama-c")
        return []

    monkeypatch.setattr(prove_module, "prove", parse_only)
    spec = tmp_path / "mine.yaml"
    spec.write_text(
        SPECS["paper_motor"]
        .read_text(encoding="utf-8")
        .replace("name: paper_motor", "name: mine", 1),
        encoding="utf-8",
    )
    monkeypatch.chdir(tmp_path)
    assert main(["mine.yaml", "--build", "pb"]) == 0, capsys.readouterr().err
    assert (tmp_path / "pb" / "mine" / "proof" / "plan.json").is_file()


@pytest.mark.parametrize(
    ("fixture", "shift"),
    [("heavy_l_finer_integrator", 1), ("hv600_20mh_integrator_q4", 4)],
)
def test_a_finer_integrator_should_be_proven_and_a_planted_fault_caught(
    tmp_path: Path, tools: Tools, fixture: str, shift: int
) -> None:
    """heavy_l at 50 Hz keeps the PI's integrator one bit finer than its output (Q17 and
    Q16), init's 600 V, 20 mH conventional motor four bits (Q19 and Q15): v reads x
    rounded, `(state + 2^(s-1)) / 2^s`. Its contracts restate that form over
    mathematical integers; both loop functions are proven with 0 alarms, and a v that
    reads x unshifted (the Q f bound against a Q(f + s) state) is caught. The C had
    printed the rounding as `>> 4u`, which Z3 and CVC4 could not match to the contracts'
    division: the 600 V motor's three integrator clauses were NOT PROVEN (a helper's
    hunt: 7 of 9 init motors with a finer integrator)."""
    import json

    from codegen.generate import render_all, write_tree

    spec = ROOT / "tests" / "fixtures" / "odd" / f"{fixture}.yaml"
    root = tmp_path / fixture
    write_tree(render_all(spec).files, root)
    manifest = json.loads((root / "manifest.json").read_text(encoding="utf-8"))
    assert manifest["current_loop"]["state_shift"] == shift
    target = target_at(root, fixture, str(spec))
    clauses = {
        "bldc_current_loop_duty": ["within_d_max"],
        "bldc_current_loop_integrate": [
            "in_range",
            "holds_where_saturated",
            "integrates_elsewhere",
        ],
    }
    for function, names in clauses.items():
        (tmp_path / function).mkdir()
        eva, methods = establish(tools, target, function, names, tmp_path / function)
        assert eva.alarm_count == 0, (function, eva.alarms)
        assert "NOT PROVEN" not in methods.values(), (function, methods)
        assert sorted(methods) == sorted(names), methods
    mutant = tmp_path / "mutant"
    shutil.copytree(root, mutant)
    header = mutant / "c" / "bldc_current_loop.h"
    text = header.read_text(encoding="utf-8")
    shifted = f"BLDC_LOOP_KP * error + (state + {1 << (shift - 1)}) / {1 << shift};"
    assert text.count(shifted) == 2  # the duty's and the integrator's v
    header.write_text(text.replace(shifted, "BLDC_LOOP_KP * error + state;"), encoding="utf-8")
    (tmp_path / "mutant-frama-c").mkdir()
    _, methods = establish(
        tools,
        target_at(mutant, fixture, str(spec)),
        "bldc_current_loop_integrate",
        ["holds_where_saturated"],
        tmp_path / "mutant-frama-c",
        MUTANT_WP_TIMEOUT_S,
    )
    assert methods["holds_where_saturated"] == "NOT PROVEN", methods

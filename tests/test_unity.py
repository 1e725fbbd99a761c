"""The generated Unity tests pass on the host under sanitizers and on a Cortex-M3 under
qemu, with identical per-test results; and a wrong expectation does make them fail.
"""

from __future__ import annotations

import dataclasses
import shutil
from collections.abc import Sequence
from pathlib import Path

import pytest

from codegen.render import provenance
from codegen.spec_loader import load_spec
from codegen.unity_cases import UnityCase, unity_cases
from codegen.unity_render import TEST_PREFIX, render_unity_tests
from verify.unity_run import (
    UnityRun,
    build_host,
    parse_unity_output,
    qemu_available,
    run_host,
    run_qemu,
    unity_framework,
)

ROOT = Path(__file__).resolve().parents[1]
SPEC = ROOT / "spec" / "paper_motor.yaml"
GENERATED = ROOT / "generated" / "paper_motor"
CORE_FILES = ("bldc_commutation.h", "bldc_commutation.c")
DATA = ROOT / "tests" / "data"
SELFTEST = ("unity_selftest.c",)
#: What Unity prints for each test of tests/data/unity_selftest.c.
SELFTEST_EXPECTED = {
    "test_every_assertion_should_pass": ("PASS", ""),
    "test_within_should_fail_above": ("FAIL", "Values Not Within Delta 2 Expected 100 Was 103"),
    "test_within_should_fail_below": ("FAIL", "Values Not Within Delta 0 Expected 65535 Was 0"),
    "test_equal_uint16_should_fail": ("FAIL", "Expected 1 Was 65535"),
    "test_equal_hex8_should_fail": ("FAIL", "Expected 0x0F Was 0xF0"),
    "test_equal_int_should_fail": ("FAIL", "Expected -2147483648 Was 5"),
    "test_true_should_fail": ("FAIL", "Expected TRUE Was FALSE"),
    "test_fail_message_should_fail": ("FAIL", "explicit failure"),
}


@pytest.fixture(scope="module")
def cases() -> list[UnityCase]:
    """The generator's vectors: expectations from the exact symbolic model."""
    spec = load_spec(SPEC)
    return list(unity_cases(spec))


# --- end of the temporary producer -------------------------------------------------------


def write_generated(target: Path, cases: Sequence[UnityCase]) -> Path:
    """generated/<spec>/ as generate.py will lay it out: the checked-in core beside the
    freshly rendered tests."""
    spec = load_spec(SPEC)
    (target / "c").mkdir(parents=True)
    for name in CORE_FILES:
        shutil.copyfile(GENERATED / "c" / name, target / "c" / name)
    files = render_unity_tests(cases, lambda template: provenance(template, spec))
    for name, text in files.items():
        (target / name).parent.mkdir(parents=True, exist_ok=True)
        (target / name).write_text(text, encoding="utf-8")
    return target


@pytest.fixture(scope="module")
def generated(tmp_path_factory: pytest.TempPathFactory, cases: list[UnityCase]) -> Path:
    return write_generated(tmp_path_factory.mktemp("unity") / "paper_motor", cases)


@pytest.fixture(scope="module")
def host_run(generated: Path) -> UnityRun:
    return run_host(generated, generated.parent / "build")


@pytest.fixture(scope="module")
def qemu_run(generated: Path) -> UnityRun:
    if not qemu_available():
        pytest.skip("qemu-system-arm or arm-none-eabi-gcc not installed (make sysdeps)")
    return run_qemu(generated, generated.parent / "build")


def test_every_rendered_file_should_begin_with_its_provenance(generated: Path) -> None:
    for name in ("test_bldc_commutation.c", "test_runner.c"):
        first = (generated / "tests" / name).read_text().splitlines()[0]
        assert first.startswith(f"/* Generated from template templates/unity/{name}.j2 with")
        assert first.endswith(
            "Do not edit: regenerate with `bldc-codegen generate spec/paper_motor.yaml`. */"
        )


def test_runner_should_run_every_case_once(generated: Path, cases: list[UnityCase]) -> None:
    runner = (generated / "tests" / "test_runner.c").read_text()
    assert [line.strip() for line in runner.splitlines() if "RUN_TEST(" in line] == [
        f"RUN_TEST({TEST_PREFIX}{case.name});" for case in cases
    ]


def test_unity_tests_should_pass_on_the_host_under_sanitizers(
    host_run: UnityRun, cases: list[UnityCase]
) -> None:
    assert host_run.passed, "\n".join(host_run.problems) + "\n" + host_run.stderr
    assert [r.name for r in host_run.results] == [TEST_PREFIX + c.name for c in cases]


def test_unity_tests_should_pass_on_a_cortex_m3_under_qemu(
    qemu_run: UnityRun, cases: list[UnityCase]
) -> None:
    assert qemu_run.passed, "\n".join(qemu_run.problems) + "\n" + qemu_run.stdout
    assert [r.name for r in qemu_run.results] == [TEST_PREFIX + c.name for c in cases]


def test_host_and_target_should_report_identical_results(
    host_run: UnityRun, qemu_run: UnityRun
) -> None:
    assert host_run.results == qemu_run.results


def test_a_wrong_expectation_should_fail_the_run(tmp_path: Path, cases: list[UnityCase]) -> None:
    """The runner is no pass-through: one compare value just outside its tolerance and
    one wrong transistor fail exactly their tests, and the exit status says so."""
    wrong = list(cases)
    off_by = wrong[0].turn_on_tolerance + 1
    wrong[0] = dataclasses.replace(wrong[0], turn_on_compare=wrong[0].turn_on_compare - off_by)
    wrong[1] = dataclasses.replace(wrong[1], turn_off_switch=(wrong[1].turn_off_switch + 1) % 6)
    run = run_host(write_generated(tmp_path / "paper_motor", wrong), tmp_path / "build")
    failed = {r.name: r.message for r in run.results if r.status == "FAIL"}
    assert set(failed) == {TEST_PREFIX + wrong[0].name, TEST_PREFIX + wrong[1].name}
    message = failed[TEST_PREFIX + wrong[0].name]
    assert f"Values Not Within Delta {wrong[0].turn_on_tolerance}" in message
    assert f"Expected {wrong[0].turn_on_compare} Was" in message
    assert "Expected 0x" in failed[TEST_PREFIX + wrong[1].name]
    assert run.exit_code == 2 and run.summary is not None and run.summary.failures == 2
    assert not run.passed


#: Cores with undefined behaviour: each must fail the run through its sanitizer report.
BROKEN_CORES = {
    "signed_overflow": (
        "volatile int32_t big = INT32_MAX;\n"
        "const int32_t sum = big + (int32_t)in->hall_code;\n"
        "out->flags = (uint8_t)(sum < 0 ? 1u : 0u);\n"
    ),
    "out_of_bounds_read": (
        "static const uint8_t two[2] = {1u, 2u};\nout->sector = two[in->hall_code];\n"
    ),
}


@pytest.mark.parametrize("defect", sorted(BROKEN_CORES))
def test_a_sanitizer_finding_should_fail_the_run(
    defect: str, tmp_path: Path, cases: list[UnityCase]
) -> None:
    """Undefined behaviour in the core must not pass, whatever the runner prints."""
    generated = write_generated(tmp_path / "paper_motor", cases[:1])
    broken = (
        '#include "bldc_commutation.h"\n'
        "void bldc_commutate(const bldc_inputs_t *in, bldc_outputs_t *out)\n"
        f"{{\n{BROKEN_CORES[defect]}}}\n"
    )
    (generated / "c" / "bldc_commutation.c").write_text(broken, encoding="utf-8")
    run = run_host(generated, tmp_path / "build")
    assert run.sanitizer_reports, run.stdout + run.stderr
    assert not run.passed


@pytest.fixture(scope="module")
def selftest_host(tmp_path_factory: pytest.TempPathFactory) -> UnityRun:
    return run_host(DATA, tmp_path_factory.mktemp("selftest"), sources=SELFTEST)


def test_unity_should_print_each_verdict_in_unitys_format(selftest_host: UnityRun) -> None:
    """Every assertion once passing, once failing: the message, the line of the failed
    assertion, the summary, and the exit status (the number of failures)."""
    run = selftest_host
    assert {r.name: (r.status, r.message) for r in run.results} == SELFTEST_EXPECTED
    source = (DATA / SELFTEST[0]).read_text().splitlines()
    for result in run.results:
        expected_text = "RUN_TEST(" if result.status == "PASS" else "TEST_"
        assert expected_text in source[result.line - 1], result
    assert run.summary is not None
    assert (run.summary.tests, run.summary.failures, run.summary.ignored) == (8, 7, 0)
    assert run.summary.verdict == "FAIL" and run.exit_code == 7 and not run.sanitizer_reports


def test_unity_should_print_the_same_under_qemu(selftest_host: UnityRun, tmp_path: Path) -> None:
    """Semihosting output and exit status carry the same verdicts off the target."""
    if not qemu_available():
        pytest.skip("qemu-system-arm or arm-none-eabi-gcc not installed (make sysdeps)")
    run = run_qemu(DATA, tmp_path, sources=SELFTEST)
    assert run.results == selftest_host.results
    assert run.summary == selftest_host.summary and run.exit_code == 7


def test_parser_should_read_unity_output() -> None:
    """Unity's documented format, including an ignored test and a failure message."""
    text = (
        "tests/test_runner.c:12:test_a:PASS\n"
        "tests/test_bldc_commutation.c:40:test_b:FAIL: Values Not Within Delta 1 Expected 5 Was 9\n"
        "tests/test_runner.c:14:test_c:IGNORE\n"
        "\n-----------------------\n3 Tests 1 Failures 1 Ignored \nFAIL\n"
    )
    parsed = parse_unity_output(text)
    assert [(r.name, r.status, r.line) for r in parsed.results] == [
        ("test_a", "PASS", 12),
        ("test_b", "FAIL", 40),
        ("test_c", "IGNORE", 14),
    ]
    assert parsed.results[1].message == "Values Not Within Delta 1 Expected 5 Was 9"
    assert parsed.summary is not None
    assert (parsed.summary.tests, parsed.summary.failures, parsed.summary.ignored) == (3, 1, 1)
    assert parsed.summary.verdict == "FAIL"


def test_unity_dir_should_select_real_unity_or_fail_clearly(tmp_path: Path) -> None:
    assert unity_framework({}).strict  # the stand-in, built with -Werror
    with pytest.raises(RuntimeError, match=r"unity\.c"):
        unity_framework({"UNITY_DIR": str(tmp_path)})


IMPROVED_R = ROOT / "generated" / "paper_motor_improved_r"


@pytest.mark.parametrize("target", ["host", "qemu"])
def test_improved_r_unity_tests_should_pass_on_the_checked_in_core(
    target: str, tmp_path: Path
) -> None:
    """The resistance-aware core's vectors (expectations from the rule's real-arithmetic
    reference, tolerances from each vector's proven bound) pass on host and target."""
    if target == "qemu" and not qemu_available():
        pytest.skip("qemu-system-arm or arm-none-eabi-gcc not installed (make sysdeps)")
    run = (run_host if target == "host" else run_qemu)(IMPROVED_R, tmp_path / "build")
    assert run.passed, run.stdout + run.stderr
    assert run.summary is not None and run.summary.tests == len(run.results) >= 30


def test_improved_r_unity_tests_should_fail_without_resistance_in_the_decay(
    tmp_path: Path,
) -> None:
    """The same vectors reject a core whose turn-off current leaves R out of its ramp term
    (rho x over one PWM period set to 0)."""
    generated = tmp_path / "paper_motor_improved_r"
    shutil.copytree(IMPROVED_R, generated)
    source = generated / "c" / "bldc_commutation.c"
    text = source.read_text(encoding="utf-8")
    assert text.count("#define STEP_DECAY_Q 2516582u") == 1
    source.write_text(
        text.replace("#define STEP_DECAY_Q 2516582u", "#define STEP_DECAY_Q 0u"), "utf-8"
    )
    run = run_host(generated, tmp_path / "build")
    failed = {r.name for r in run.results if r.status == "FAIL"}
    assert not run.passed and any("sector" in name for name in failed), failed


def test_a_sense_whose_zero_is_code_0_should_get_a_suite_that_builds_and_passes(
    tmp_path: Path,
) -> None:
    """current_offset 0 V (a unipolar sense): the zero-current case reads code 0, not
    the code below the offset (-1, which the suite printed as `-1u` into a uint16_t
    field and which -Werror refused). Every case's inputs fit their fields."""
    from codegen.abi import INPUTS
    from codegen.generate import generate

    spec_path = ROOT / "tests" / "fixtures" / "odd" / "offset_zero.yaml"
    spec = load_spec(spec_path)
    for case in unity_cases(spec):
        for field in INPUTS.fields:  # the ABI's one definition of the inputs' C types
            value = getattr(case, field.name)
            assert field.ctype.low <= value <= field.ctype.high, (case.name, field.name, value)
    out = tmp_path / "generated"
    generate(spec_path, out, ROOT)
    run = run_host(out, tmp_path / "build")
    assert run.passed, run.stdout + run.stderr
    zero = next(r for r in run.results if r.name.endswith("no_commutation_time_without_current"))
    assert zero.status == "PASS"


def test_expected_times_should_round_half_a_tick_up_as_the_core_does() -> None:
    """A 62.5-tick carrier: with no current the rule ends on the first boundary, at
    63 ticks in the core (round half up). Each case's expected time is the printed
    twin's, within its stated tolerance."""
    from codegen.core.module import build_core, twin_module

    spec = load_spec(ROOT / "tests" / "fixtures" / "odd" / "hub25pp_ir.yaml")
    core = build_core(spec)
    twin = twin_module(core)
    cases = {c.name: c for c in unity_cases(spec)}
    zero = cases["give_no_commutation_time_without_current"]
    assert (zero.commutation_ticks, zero.commutation_tolerance) == (63, 0)
    for case in cases.values():
        out = twin.commutate(  # type: ignore[attr-defined]
            twin.Inputs(  # type: ignore[attr-defined]
                case.hall_code,
                case.previous_hall_code,
                case.hall_period_ticks,
                case.bus_voltage_adc,
                case.phase_current_adc,
                case.main_duty_counts,
            )
        )
        assert abs(out.commutation_ticks - case.commutation_ticks) <= case.commutation_tolerance


def test_a_relative_build_folder_should_resolve_against_the_current_folder(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The compilers run in the generated folder (its includes are relative), so a
    relative `--build build/u` had been taken relative to it: gcc could not create
    build/u/host/test_runner.o there (`bldc-codegen unity SPEC --build build/u`)."""
    monkeypatch.chdir(tmp_path)
    generated = ROOT / "generated" / "paper_motor"
    exe = build_host(generated, Path("build") / "u", unity_framework({}))
    assert exe.is_absolute() and exe.is_file()
    assert exe.parent == tmp_path / "build" / "u"
    assert not (generated / "build").exists()

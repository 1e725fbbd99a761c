"""The current loop's anti-windup has two printed forms (codegen/control/current_loop.py):
hold-or-integrate, one range test of the output, used wherever 0 <= k_i <= k_p, and
the general clamp between bounds that close on x. They must agree step for step wherever
the cheap one is used; the general one must be what a loop with k_i > k_p gets."""

from __future__ import annotations

import itertools
from dataclasses import replace
from fractions import Fraction
from pathlib import Path
from types import ModuleType

import pytest

from codegen.control import current_loop
from codegen.ir import py_printer
from codegen.ir.nodes import Function, SLet
from codegen.methods.base import FixedPointError
from codegen.spec_loader import load_spec

ROOT = Path(__file__).resolve().parents[1]
SPECS = [
    *sorted((ROOT / "spec").glob("paper_motor*.yaml")),
    ROOT / "spec" / "example_maxon_ec45_flat_48v.yaml",
    *sorted((ROOT / "tests" / "fixtures" / "specs").glob("*.yaml")),
]


def _module(functions: tuple[Function, ...], constants: dict[str, int]) -> ModuleType:
    module = ModuleType("loop_forms")
    module.__dict__.update(constants)
    printed = [*py_printer.helpers(functions), *map(py_printer.function_definition, functions)]
    source = "\n\n".join(printed)
    exec(compile(source, "loop_forms", "exec"), module.__dict__)
    return module


def _constants(d: current_loop.LoopDesign, state_max: int) -> dict[str, int]:
    return {
        "BLDC_LOOP_KP": d.kp_q,
        "BLDC_LOOP_KI": d.ki_q,
        "BLDC_LOOP_STATE_MAX": state_max,
        "BLDC_LOOP_CODE_MAX": d.code_max,
    }


def _lets(fn: Function) -> set[str]:
    return {s.name for s in fn.body if isinstance(s, SLet)}


@pytest.mark.parametrize("spec_path", SPECS, ids=lambda p: p.stem)
def test_hold_or_integrate_should_equal_the_clamp_form(spec_path: Path) -> None:
    d = current_loop.design(load_spec(spec_path))
    state_max = d.state_max
    args = (d.fraction_bits, d.kp_q, d.ki_q, state_max, d.code_max, d.gains)
    assert 0 <= d.ki_q <= d.kp_q  # every example motor takes the cheap form
    _, cheap = current_loop._functions(*args)
    _, general = current_loop._functions(*args, conditional=False)
    assert "upper" not in _lets(cheap) and "upper" in _lets(general)
    constants = _constants(d, state_max)
    a = _module((cheap,), constants)
    b = _module((general,), constants)
    states = sorted({0, 1, state_max // 3, state_max // 2, state_max - 1, state_max, -5, 2**31 - 1})
    codes = sorted({0, 1, 2, 7, 100, d.code_max // 2, d.code_max - 1, d.code_max, d.code_max + 9})
    for x, r, m in itertools.product(states, codes, codes):
        assert a.current_loop_integrate(x, r, m) == b.current_loop_integrate(x, r, m), (x, r, m)
    # and every error from every state near the saturation boundaries
    for x in (0, state_max // 2, state_max):
        for m in range(0, d.code_max + 1, 3):
            r = d.code_max // 2
            assert a.current_loop_integrate(x, r, m) == b.current_loop_integrate(x, r, m)


def test_a_loop_with_ki_above_kp_should_get_the_clamp_form() -> None:
    d = current_loop.design(load_spec(ROOT / "spec" / "paper_motor.yaml"))
    state_max = d.state_max
    _, integrate = current_loop._functions(
        d.fraction_bits, d.ki_q, d.kp_q, state_max, d.code_max, d.gains
    )
    assert {"upper", "lower"} <= _lets(integrate)


@pytest.mark.parametrize(("bandwidth", "found"), [("1 Hz", "2.5 Hz"), ("2 Hz", "2.5 Hz")])
def test_a_loop_too_slow_for_any_allowed_accuracy_should_name_the_bandwidth(
    tmp_path: Path, bandwidth: str, found: str
) -> None:
    """The paper motor with the loader's lowest bandwidth: a step response of 15915 PWM
    periods drifts its PI's integrator 25.2 counts. The refusal named
    accuracy.current_loop_duty_counts with '(allowed: >= 25.248 counts)', a value the
    loader refuses (at most 16): a dead end. It names the bandwidth, and one that meets
    the spec's accuracy, found by designing it."""
    from codegen.methods.base import FixedPointError

    text = (ROOT / "spec" / "paper_motor.yaml").read_text(encoding="utf-8")
    assert "  bandwidth: 1 kHz\n" in text
    path = tmp_path / "slow_loop.yaml"
    path.write_text(text.replace("  bandwidth: 1 kHz\n", f"  bandwidth: {bandwidth}\n"))
    with pytest.raises(FixedPointError) as caught:
        current_loop.design(load_spec(path))
    assert caught.value.key == "current_loop.bandwidth"
    message = str(caught.value)
    assert message.startswith(f"current_loop.bandwidth = {bandwidth}: ")
    assert f"accuracy.current_loop_duty_counts = 1 counts: e.g. {found} meets it)" in message
    met = path.read_text().replace(f"  bandwidth: {bandwidth}\n", f"  bandwidth: {found}\n")
    path.write_text(met)
    current_loop.design(load_spec(path))  # the bandwidth named does meet it


def test_claims_should_count_only_errors_that_can_leave_the_output_unsaturated() -> None:
    """50 mH sensed at 50 mV/A: k_p is 1520 counts per code, so beyond |r - m| = 2
    codes v saturates, exactly and as printed, and the integrator holds in both. The
    claims took every error of the ADC range (k_i's rounding in Q8 times 4095 codes: 116
    counts of drift over a step response) and the PI was refused at every bandwidth; over
    the errors that can leave v unsaturated it meets half a count."""
    path = ROOT / "tests" / "fixtures" / "refused" / "l50mh_wide_sense.yaml"
    spec = load_spec(path)
    d = current_loop.design(spec)
    assert d.fraction_bits == 8
    g = d.gains
    assert current_loop._error_limit(g, d.kp_q, d.fraction_bits) == 2
    assert d.duty_claim < Fraction(51, 100)
    assert current_loop.accuracy_needed(d) <= 1
    # the limit is where k_p alone saturates v: one code more, and every state does
    limit = current_loop._error_limit(g, d.kp_q, d.fraction_bits)
    assert (limit + 1) * min(g.kp_counts_per_code, Fraction(d.kp_q, 2**8)) > g.duty_max_counts
    assert limit * g.kp_counts_per_code <= g.duty_max_counts


def test_a_finer_integrator_should_round_nothing_and_keep_its_forms_equal() -> None:
    """heavy_l at 50 Hz: k_p e + x fits int32 in Q16 at most, where k_i's rounding makes
    2.98 counts over a step response; x takes Q17 (v reads it rounded) and meets 1.002.
    The hold-or-integrate form and the general clamp agree (`cheap_form_valid`)."""
    path = ROOT / "tests" / "fixtures" / "odd" / "heavy_l_finer_integrator.yaml"
    d = current_loop.design(load_spec(path))
    assert (d.fraction_bits, d.state_shift, d.state_bits) == (16, 1, 17)
    assert current_loop.accuracy_needed(d) <= Fraction(11, 10)
    plain = current_loop._candidate(d.spec, d.gains, d.code_max, 16, 0)
    assert plain is not None and current_loop.accuracy_needed(plain) > Fraction(29, 10)
    args = (d.fraction_bits, d.kp_q, d.ki_q, d.state_max, d.code_max, d.gains)
    assert current_loop.cheap_form_valid(d.kp_q, d.ki_q, 1)
    _, cheap = current_loop._functions(*args, state_shift=1)
    _, general = current_loop._functions(*args, conditional=False, state_shift=1)
    constants = {
        **_constants(d, d.state_max),
        "BLDC_LOOP_DEMAND_MAX": d.gains.duty_max_counts << d.fraction_bits,
    }
    a, b = _module((cheap,), constants), _module((general,), constants)
    top = d.state_max
    states = sorted({0, 1, 2, 3, top // 3, top // 2, top - 2, top - 1, top, -5, 2**31 - 1})
    codes = [0, 1, 2, 1000, 2047, 2048, 2049, 3000, 4094, 4095, 9999]
    for x in states:
        for r in codes:
            for m in codes:
                assert a.current_loop_integrate(x, r, m) == b.current_loop_integrate(x, r, m), (
                    x,
                    r,
                    m,
                )


def test_a_refusal_on_the_ramps_drift_should_name_the_ramp_not_the_step() -> None:
    """A 64-pole 5 mH motor of 2.5 mohm: the PI's widest format drifts 0.025 counts
    over a step response but 63 over a ramp from 0 to D_max; the refusal had said the
    step's "drifts 0.0250 counts, more than the 16 counts" the key may be."""
    path = ROOT / "tests" / "fixtures" / "refused" / "pi_ramp_drift_64p.yaml"
    with pytest.raises(FixedPointError) as caught:
        current_loop.design(load_spec(path))
    message = str(caught.value)
    assert "over a ramp from 0 to D_max the PI's widest format" in message
    assert "drifts 0.0" not in message
    d = current_loop.widest_design(load_spec(path))
    assert d.duty_claim + d.ramp_claim > 16 >= d.integrator_claim * 100


def test_a_pi_whose_k_p_overflows_should_name_a_bandwidth_that_fits() -> None:
    """1 H and 500 A on 3.3 V: k_p e overflows int32 in every Q format at 1 kHz; the
    refusal had named no allowed value. k_p scales with the bandwidth: 200 Hz fits."""
    path = ROOT / "tests" / "fixtures" / "refused" / "pi_kp_overflow_1h.yaml"
    spec = load_spec(path)
    with pytest.raises(FixedPointError) as caught:
        current_loop.design(spec)
    message = str(caught.value)
    assert message.startswith("current_loop.bandwidth = 1000 Hz: no Q format of the")
    assert message.endswith("(allowed: a bandwidth of at most about 200 Hz, whose k_p fits)")
    slower = replace(spec, current_loop=replace(spec.current_loop, bandwidth_hz=Fraction(200)))
    current_loop.widest_design(slower)  # fits (what accuracy it meets is another matter)

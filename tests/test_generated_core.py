"""The generated core: builds warning-free, matches its bit-exact twin, key values.

The full symbolic cross-check is the verifier's job; here the default spec's headline
numbers and the safe-state and saturation paths are asserted.
"""

from __future__ import annotations

import ctypes
import dataclasses
import importlib.util
import random
import shutil
import subprocess
from pathlib import Path
from types import ModuleType

import pytest
import sympy as sp

from codegen.derivation import derive
from codegen.fixedpoint.design import FixedPointError, design
from codegen.fixedpoint.scaling import scaling
from codegen.generate import render_all, write_tree
from codegen.spec_loader import load_spec
from sim.sil import CoreInputs, CoreOutputs

ROOT = Path(__file__).resolve().parents[1]
SPEC = ROOT / "spec" / "paper_motor.yaml"
WARNINGS = ["-std=c99", "-Wall", "-Wextra", "-Wconversion", "-Wpedantic", "-Werror"]


@pytest.fixture(scope="module")
def generated(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("gen") / "paper_motor"
    write_tree(render_all(SPEC).files, out)
    return out


@pytest.fixture(scope="module")
def core(generated: Path) -> ctypes.CDLL:
    lib = generated / "libcore.so"
    subprocess.run(
        [
            "gcc",
            *WARNINGS,
            "-O2",
            "-shared",
            "-fPIC",
            "-o",
            str(lib),
            str(generated / "c" / "bldc_commutation.c"),
        ],
        check=True,
    )
    dll = ctypes.CDLL(str(lib))
    dll.bldc_commutate.argtypes = [ctypes.POINTER(CoreInputs), ctypes.POINTER(CoreOutputs)]
    dll.bldc_commutate.restype = None
    return dll


@pytest.fixture(scope="module")
def twin(generated: Path) -> ModuleType:
    spec = importlib.util.spec_from_file_location(
        "bldc_fixed", generated / "python" / "bldc_fixed.py"
    )
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def run_c(core: ctypes.CDLL, *args: int) -> tuple[int, ...]:
    out = CoreOutputs()
    core.bldc_commutate(ctypes.byref(CoreInputs(*args)), ctypes.byref(out))
    return tuple(getattr(out, name) for name, _ in CoreOutputs._fields_)


def ticks(speed_rpm: float) -> int:
    return round(1e6 * 60 / (6 * speed_rpm))  # 1 MHz Hall timer, 1 pole pair


BUS_24V = round(24 / (3.3 * 11) * 4096)  # 2979
CURRENT_5A = 2048 + round(5 / (3.3 / 0.05) * 4096)


def test_c_and_bit_exact_twin_should_agree(core: ctypes.CDLL, twin: ModuleType) -> None:
    rng = random.Random(20261121)
    for _ in range(3000):
        args = (
            rng.randrange(8),
            rng.randrange(8),
            rng.randrange(65536),
            rng.randrange(4096),
            rng.randrange(4096),
            rng.randrange(4000),
        )
        assert run_c(core, *args) == tuple(twin.commutate(*args)), args


def test_low_speed_should_hold_the_on_phase_and_modulate_the_off_phase(twin: ModuleType) -> None:
    out = twin.commutate(4, 5, ticks(1500), BUS_24V, CURRENT_5A, 1512)  # forward 60 deg edge
    period = twin.PERIOD_COUNTS
    assert out.turn_on_compare == period  # D_on = 1
    assert abs(out.turn_off_compare / period - 0.41) < 0.001  # D_off = 1 - 4E/U_d
    assert out.turn_on_switch == 4 and out.turn_off_switch == 2  # T5 on, T3 off (paper)
    assert not out.flags & twin.FLAG_HIGH_SPEED


def test_high_speed_should_hold_the_off_phase_off(twin: ModuleType) -> None:
    out = twin.commutate(4, 5, ticks(4600), BUS_24V, CURRENT_5A, 1512)
    assert abs(out.turn_on_compare / twin.PERIOD_COUNTS - 0.1907) < 0.001
    assert out.turn_off_compare == 0
    assert out.flags & twin.FLAG_HIGH_SPEED


def test_invalid_hall_codes_should_switch_everything_off(core: ctypes.CDLL) -> None:
    for code, previous in ((0, 5), (7, 5), (4, 0), (4, 2), (4, 4)):
        out = run_c(core, code, previous, ticks(1500), BUS_24V, CURRENT_5A, 1000)
        assert out[3] == out[4] == 0xFF and out[0] == out[1] == 0
        assert out[6] & 0x08


def test_over_speed_and_over_voltage_should_switch_everything_off(core: ctypes.CDLL) -> None:
    for period, bus in ((1000, BUS_24V), (ticks(1500), 4095)):
        out = run_c(core, 4, 5, period, bus, CURRENT_5A, 1000)
        assert out[3] == out[4] == 0xFF and out[6] & 0x04


def test_under_range_inputs_should_saturate_and_flag(core: ctypes.CDLL, twin: ModuleType) -> None:
    low_bus = run_c(core, 4, 5, ticks(1500), 1000, CURRENT_5A, 1000)
    floor_bus = run_c(core, 4, 5, ticks(1500), twin.BUS_CODE_MIN, CURRENT_5A, 1000)
    assert low_bus[:6] == floor_bus[:6] and low_bus[6] & 0x04 and not floor_bus[6] & 0x04
    negative = run_c(core, 4, 5, ticks(1500), BUS_24V, 1000, 1000)
    assert negative[2] == 0 and negative[6] & 0x04  # nothing to commutate


def test_inputs_beyond_the_spec_but_within_their_type_should_stay_exact_and_flag(
    core: ctypes.CDLL, twin: ModuleType
) -> None:
    # Below the minimum speed Eq. 18 still holds: D_off = 1 - 4E/U_d keeps rising
    # towards 1 instead of freezing at the minimum speed's value.
    slow = run_c(core, 4, 5, 65535, BUS_24V, CURRENT_5A, 1000)
    floor = run_c(core, 4, 5, twin.PERIOD_MAX_TICKS, BUS_24V, CURRENT_5A, 1000)
    assert slow[6] & 0x04 and not floor[6] & 0x04
    assert floor[1] < slow[1] < twin.PERIOD_COUNTS
    # A current above the braking range lengthens t_com (Eq. 20 is linear in I).
    big = run_c(core, 4, 5, ticks(1500), BUS_24V, 4095, 1000)
    nominal = run_c(core, 4, 5, ticks(1500), BUS_24V, CURRENT_5A, 1000)
    assert big[6] & 0x04 and big[2] > nominal[2]


def test_commutation_time_should_clamp_to_the_sector_near_top_speed(twin: ModuleType) -> None:
    out = twin.commutate(4, 5, ticks(5000), 2700, 2048 + 620, 0)
    assert out.commutation_ticks == ticks(5000) and out.flags & twin.FLAG_TIME_CLAMPED


def _design_of(tmp_path: Path, text: str) -> None:
    bad = tmp_path / "bad.yaml"
    bad.write_text(text)
    spec = load_spec(bad)
    design(scaling(spec, derive()), spec.accuracy.duty_counts, spec.accuracy.commutation_time_ticks)


def test_overflow_proof_should_reject_a_spec_whose_intermediates_overflow() -> None:
    # A K_X a thousand times the paper motor's (say a far faster Hall clock) makes
    # round(K_X / B) overflow 32 bits in every format, even Q0.
    spec = load_spec(SPEC)
    sc = scaling(spec, derive())
    with pytest.raises(FixedPointError, match=r"N_X / B = .* does not fit uint32_t"):
        design(dataclasses.replace(sc, k_x=sc.k_x * 1000), sp.Integer(1), sp.Integer(8))


def test_design_should_reject_an_unreachable_accuracy_target(tmp_path: Path) -> None:
    text = SPEC.read_text().replace("duty_counts: 1.0", "duty_counts: 0.501")
    with pytest.raises(FixedPointError, match="accurate enough"):
        _design_of(tmp_path, text)


def test_design_should_prove_every_intermediate_of_the_default_spec() -> None:
    spec = load_spec(SPEC)
    fx = design(
        scaling(spec, derive()), spec.accuracy.duty_counts, spec.accuracy.commutation_time_ticks
    )
    limits = {"uint32_t": 2**32 - 1, "int32_t": 2**31 - 1, "uint64_t": 2**64 - 1}
    assert len(fx.ranges) == 13
    for proven in fx.ranges:
        assert proven.high <= limits[proven.c_type], proven
    assert fx.duty_error_bound_counts < spec.accuracy.duty_counts
    assert fx.time_error_bound_ticks <= spec.accuracy.commutation_time_ticks
    assert fx.duty_error_bound_counts < sp.Rational(51, 100)  # 1/2 plus the quantisation


@pytest.mark.skipif(shutil.which("arm-none-eabi-gcc") is None, reason="arm-none-eabi-gcc missing")
def test_core_should_build_for_cortex_m3_without_helpers(generated: Path, tmp_path: Path) -> None:
    obj = tmp_path / "core.o"
    subprocess.run(
        [
            "arm-none-eabi-gcc",
            *WARNINGS,
            "-mcpu=cortex-m3",
            "-mthumb",
            "-O2",
            "-c",
            str(generated / "c" / "bldc_commutation.c"),
            "-o",
            str(obj),
        ],
        check=True,
    )
    listing = subprocess.run(
        ["arm-none-eabi-objdump", "-d", str(obj)], check=True, capture_output=True, text=True
    ).stdout
    assert "__aeabi" not in listing and "vfp" not in listing.lower()
    assert "udiv" in listing  # the hardware divide, not a library call


@pytest.mark.parametrize("method", ["improved", "improved_r"])
@pytest.mark.parametrize("compiler", ["gcc", "arm-none-eabi-gcc"])
def test_generated_c_should_compile_warning_free(
    generated: Path, tmp_path: Path, compiler: str, method: str
) -> None:
    """The fresh render of the default spec, and the checked-in resistance-aware core."""
    if shutil.which(compiler) is None:
        pytest.skip(f"{compiler} missing")
    if method == "improved_r":
        generated = ROOT / "generated" / "paper_motor_improved_r"
    target = ["-mcpu=cortex-m3", "-mthumb"] if compiler.startswith("arm") else []
    for source in ("bldc_commutation.c", "stm32f103_port.c"):
        subprocess.run(
            [
                compiler,
                *WARNINGS,
                *target,
                "-O2",
                "-c",
                str(generated / "c" / source),
                "-o",
                str(tmp_path / f"{source}.o"),
            ],
            check=True,
        )

"""Software in the loop: the generated C core decides, the simulated plant obeys.

The core (`generated/<spec>/c/bldc_commutation.c`) is compiled for the host into a
shared library and called through ctypes with the same integers the STM32 port would
pass: Hall codes, the Hall period in Hall-timer ticks, bus voltage and current in ADC
codes, the main duty in TIM1 counts. Its compare values, transistor indices and
commutation time (Hall ticks) become the plant's gate schedule. Nothing of the core's
arithmetic is re-implemented here, so a change in the C changes the simulation.

The checked-in core implements the spec's `controller.method` only. For the other
methods the spec is copied with the method changed and `python -m codegen generate`
renders that variant into build/sim/; variants and libraries are cached by content.
"""

from __future__ import annotations

import ctypes
import hashlib
import re
import shutil
import subprocess
import sys
from dataclasses import dataclass
from functools import cached_property
from pathlib import Path

from codegen.abi import INPUTS, OUTPUTS, ctypes_struct
from codegen.derivation import derive
from codegen.fixedpoint.scaling import Scaling, scaling
from codegen.render import PROJECT_ROOT
from codegen.spec_model import Spec
from codegen.spec_variant import spec_with_method
from sim.command import Command
from sim.scenario import Case
from sim.schedule import switch_index

BUILD_ROOT = PROJECT_ROOT / "build" / "sim"
CORE_SOURCE = "bldc_commutation.c"
CORE_HEADER = "bldc_commutation.h"


class SilError(RuntimeError):
    """The core could not be generated, compiled or loaded."""


#: bldc_inputs_t and bldc_outputs_t, from the ABI's one definition (codegen.abi)
CoreInputs = ctypes_struct(INPUTS)
CoreOutputs = ctypes_struct(OUTPUTS)


def _fields(structure: ctypes.Structure) -> dict[str, int]:
    return {name: int(getattr(structure, name)) for name, _ in structure._fields_}


@dataclass(frozen=True)
class CoreConstants:
    """Constants the header defines (read from it, not assumed)."""

    period_counts: int
    no_switch: int
    flags: dict[str, int]

    @staticmethod
    def from_header(text: str) -> CoreConstants:
        def define(name: str) -> int:
            match = re.search(rf"#define {name} (0x[0-9A-Fa-f]+|\d+)u", text)
            if match is None:
                raise SilError(f"{CORE_HEADER} does not define {name}")
            return int(match.group(1), 0)

        flags = {
            m.group(1): int(m.group(2), 0)
            for m in re.finditer(r"#define BLDC_FLAG_(\w+) (0x[0-9A-Fa-f]+)u", text)
        }
        return CoreConstants(define("BLDC_PWM_PERIOD_COUNTS"), define("BLDC_NO_SWITCH"), flags)

    def flag_names(self, flags: int) -> tuple[str, ...]:
        return tuple(name for name, bit in sorted(self.flags.items()) if flags & bit)


class CoreLibrary:
    """The compiled core, loaded once; `commutate` is one call of the C function."""

    def __init__(self, library: Path, constants: CoreConstants, method: str) -> None:
        self.path = library
        self.constants = constants
        self.method = method
        self._dll = ctypes.CDLL(str(library))
        self._function = self._dll.bldc_commutate
        self._function.argtypes = [ctypes.POINTER(CoreInputs), ctypes.POINTER(CoreOutputs)]
        self._function.restype = None

    def commutate(self, inputs: dict[str, int]) -> dict[str, int]:
        c_in = CoreInputs(**inputs)
        c_out = CoreOutputs()
        self._function(ctypes.byref(c_in), ctypes.byref(c_out))
        return _fields(c_out)


def compile_core(c_dir: Path, build_dir: Path = BUILD_ROOT) -> Path:
    """gcc -O2 -fPIC -shared of the core into build_dir, cached by source hash."""
    source, header = c_dir / CORE_SOURCE, c_dir / CORE_HEADER
    digest = hashlib.sha256(source.read_bytes() + header.read_bytes()).hexdigest()[:16]
    library = build_dir / f"libbldc_{digest}.so"
    if library.exists():
        return library
    build_dir.mkdir(parents=True, exist_ok=True)
    partial = library.with_suffix(".so.partial")
    command = ["gcc", "-O2", "-fPIC", "-shared", "-std=c99", "-Wall", "-Wextra"]
    command += ["-I", str(c_dir), str(source), "-o", str(partial)]
    result = subprocess.run(command, capture_output=True, text=True, check=False)
    if result.returncode != 0:
        raise SilError(f"compiling {source} failed:\n{result.stderr}")
    partial.replace(library)
    return library


def load_core(c_dir: Path, method: str, build_dir: Path = BUILD_ROOT) -> CoreLibrary:
    constants = CoreConstants.from_header((c_dir / CORE_HEADER).read_text(encoding="utf-8"))
    return CoreLibrary(compile_core(c_dir, build_dir), constants, method)


def _toolchain_digest() -> str:
    """Hash of everything that shapes a generated core, so stale variants rebuild."""
    digest = hashlib.sha256()
    roots = [PROJECT_ROOT / "codegen", PROJECT_ROOT / "templates" / "c"]
    for root in roots:
        for path in sorted(root.rglob("*")):
            if path.is_file() and path.suffix in {".py", ".j2"}:
                digest.update(path.relative_to(PROJECT_ROOT).as_posix().encode())
                digest.update(path.read_bytes())
    return digest.hexdigest()


@dataclass(frozen=True)
class CoreSet:
    """One compiled core per method for one spec."""

    spec: Spec
    cores: dict[str, CoreLibrary]

    @cached_property
    def scaling(self) -> Scaling:
        return scaling(self.spec, derive())


def prepare_cores(spec: Spec, methods: tuple[str, ...], build_dir: Path = BUILD_ROOT) -> CoreSet:
    """Compile the checked-in core and generate + compile the other methods' variants.

    Variant generation runs `python -m codegen generate` in parallel subprocesses (one
    per missing method): the same command a user runs, so the variant is exactly what
    the toolchain emits for that method.
    """
    spec_path = Path(spec.source_path)
    checked_in = PROJECT_ROOT / "generated" / spec.name / "c"
    toolchain = _toolchain_digest()
    pending: list[tuple[str, Path, subprocess.Popen[str]]] = []
    c_dirs: dict[str, Path] = {}
    for method in methods:
        if method == spec.controller.method and (checked_in / CORE_SOURCE).exists():
            c_dirs[method] = checked_in
            continue
        text = spec_with_method(spec_path.read_text(encoding="utf-8"), method)
        key = hashlib.sha256((text + toolchain).encode()).hexdigest()[:12]
        out = build_dir / f"{spec.name}-{method}-{key}"
        c_dirs[method] = out / "c"
        if (out / "c" / CORE_SOURCE).exists():
            continue
        for stale in build_dir.glob(f"{spec.name}-{method}-*"):
            shutil.rmtree(stale, ignore_errors=True)  # variants of an older toolchain
        variant_spec = build_dir / "specs" / f"{spec.name}-{method}.yaml"
        variant_spec.parent.mkdir(parents=True, exist_ok=True)
        variant_spec.write_text(text, encoding="utf-8")
        command = [sys.executable, "-m", "codegen", "generate", str(variant_spec), "-o", str(out)]
        process = subprocess.Popen(
            command, cwd=PROJECT_ROOT, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True
        )
        pending.append((method, out, process))
    for method, _out, process in pending:
        output, _ = process.communicate()
        if process.returncode != 0:
            raise SilError(f"generating the {method!r} core failed:\n{output}")
    cores = {method: load_core(c_dirs[method], method, build_dir) for method in methods}
    return CoreSet(spec, cores)


def core_inputs(
    spec: Spec, scale: Scaling, case: Case, measured_current_a: float, main_duty: float
) -> dict[str, int]:
    """The integers the port would hand the core at this Hall edge."""
    hall = spec.hall.sequence
    ticks = round(case.sector_time_s * float(scale.hall_clock_hz))
    bus = round(case.drive.bus_voltage_v / float(scale.volts_per_bus_code))
    current = scale.current_offset_code + round(
        measured_current_a / float(scale.amps_per_current_code)
    )
    return {
        "hall_code": hall[case.edge.sector_to],
        "previous_hall_code": hall[case.edge.sector_from],
        "hall_period_ticks": min(max(ticks, 0), 2**16 - 1),
        "bus_voltage_adc": min(max(bus, 0), 2**16 - 1),
        "phase_current_adc": min(max(current, 0), 2**16 - 1),
        "main_duty_counts": min(max(round(main_duty * scale.period_counts), 0), 2**16 - 1),
    }


def core_command(
    core: CoreLibrary,
    spec: Spec,
    scale: Scaling,
    case: Case,
    measured_current_a: float,
    main_duty: float,
) -> Command:
    """Call the C core at the edge and translate its outputs into a gate command.

    The main duty after the commutation is the one handed to the core, in counts,
    because that is what the port keeps writing to the turn-on transistor.
    """
    inputs = core_inputs(spec, scale, case, measured_current_a, main_duty)
    outputs = core.commutate(inputs)
    counts = core.constants.period_counts
    no_switch = core.constants.no_switch
    on = None if outputs["turn_on_switch"] == no_switch else outputs["turn_on_switch"]
    off = None if outputs["turn_off_switch"] == no_switch else outputs["turn_off_switch"]
    return Command(
        method=core.method,
        turn_on_switch=on,
        turn_off_switch=off,
        on_duties=(outputs["turn_on_compare"] / counts,),
        off_duties=(outputs["turn_off_compare"] / counts,),
        commutation_time_s=outputs["commutation_ticks"] / float(scale.hall_clock_hz),
        main_duty=inputs["main_duty_counts"] / counts,
        flags=outputs["flags"],
        core_outputs={**{f"in.{k}": v for k, v in inputs.items()}, **outputs},
    )


def expected_switches(case: Case) -> tuple[int, int]:
    """(turn-on, turn-off) transistor of the edge per the derived switching table."""
    return switch_index(case.edge.modulated_on), switch_index(case.edge.modulated_off)

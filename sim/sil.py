"""Software in the loop: the generated C core decides, the simulated plant obeys.

The core (`generated/<spec>/c/bldc_commutation.c`) is compiled for the host into a
shared library and called through ctypes with the same integers the STM32 port would
pass: Hall codes, the Hall period in Hall-timer ticks, bus voltage and current in ADC
codes, the main duty in TIM1 counts. Its compare values, transistor indices and
commutation time (Hall ticks) become the plant's gate schedule. Nothing of the core's
arithmetic is re-implemented here, so a change in the C changes the simulation.

The checked-in core implements the spec's `controller.method` only. For the other
methods the spec is copied with the method changed and the generator renders that
variant's core (`codegen.generate.render_core`: the files `generate` writes for it)
into build/sim/; variants and libraries are cached by content.

The resistance-aware core is generated for an EMF shape (`motor.back_emf_shape`): the
one of the spec, and the paper's frozen (flat) EMF, so that a commutation on the flat
plant is decided by the firmware an engineer would generate for that motor. A shape
the firmware cannot take (a corner inside the commutation sector) gets the 120 deg
trapezoid's core instead, reported as such.
"""

from __future__ import annotations

import ctypes
import hashlib
import os
import re
import shutil
import subprocess
from dataclasses import dataclass, field
from functools import cached_property
from pathlib import Path

from codegen.abi import INPUTS, OUTPUTS, ctypes_struct
from codegen.derivation import derive
from codegen.fixedpoint.scaling import Scaling, scaling
from codegen.freshness import StaleOutputError, check_fresh
from codegen.methods.improved_r.constants import rule_constants
from codegen.methods.improved_r.design import reachable_duty_target, refused_duty_bound
from codegen.methods.paper_method import refused_time_bound
from codegen.render import PROJECT_ROOT
from codegen.spec_loader import load_spec
from codegen.spec_model import Spec
from codegen.spec_variant import (
    FALLBACK_SHAPE,
    shape_refused,
    spec_with_duty_target,
    spec_with_emf_shape,
    spec_with_method,
    spec_with_time_target,
)
from sim.command import Command
from sim.rule_stand_in import RuleStandIn
from sim.scenario import Case
from sim.schedule import switch_index

#: the cache of compiled cores and generated variants, under the current folder as every
#: command's output (it was the package's own build/: a run from a user's folder, or of an
#: installed copy, wrote into the project)
BUILD_ROOT = Path("build") / "sim"
CORE_SOURCE = "bldc_commutation.c"
CORE_HEADER = "bldc_commutation.h"


class SilError(RuntimeError):
    """The core could not be generated, compiled or loaded."""


class SpecRefusedError(SilError):
    """The generator refuses the spec itself: its own method's core has no design (a
    fixed-point target no format meets, the current loop's among them), which is what
    `generate SPEC` says. A bad spec, in the same one line, not a failed simulation."""


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

    def over_periods(self, inputs: dict[str, int], periods: range) -> list[tuple[int, int]]:
        """(commutation_ticks, flags) of one call per Hall period of `periods`, the other
        inputs held: the same calls as `commutate`, on one input and output structure
        (a clamp scan makes tens of thousands)."""
        c_in = CoreInputs(**inputs)
        c_out = CoreOutputs()
        function, at_in, at_out = self._function, ctypes.byref(c_in), ctypes.byref(c_out)
        found = []
        for ticks in periods:
            c_in.hall_period_ticks = ticks
            function(at_in, at_out)
            found.append((c_out.commutation_ticks, c_out.flags))
        return found


def compile_core(c_dir: Path, build_dir: Path = BUILD_ROOT) -> Path:
    """gcc -O2 -fPIC -shared of the core into build_dir, cached by source hash."""
    build_dir = build_dir.resolve()  # a relative folder is the current one's
    source, header = c_dir / CORE_SOURCE, c_dir / CORE_HEADER
    digest = hashlib.sha256(source.read_bytes() + header.read_bytes()).hexdigest()[:16]
    library = build_dir / f"libbldc_{digest}.so"
    if library.exists():
        return library
    build_dir.mkdir(parents=True, exist_ok=True)
    # one partial file per process: two processes compiling the same core (pytest's
    # workers, two simulations) wrote one file at once
    partial = library.with_suffix(f".so.{os.getpid()}.partial")
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


#: The resistance-aware method, generated per EMF shape.
SHAPED_METHOD = "improved_r"
#: `back_emf_shape` of the extra improved_r variant (the fallback for a shape the
#: firmware cannot take is `codegen.spec_variant.FALLBACK_SHAPE`).
FLAT_SHAPE = "flat"


@dataclass(frozen=True)
class CoreSet:
    """One compiled core per method for one spec; the resistance-aware one also for the
    flat EMF (`shaped["flat"]`) when the spec's own shape is another."""

    spec: Spec
    cores: dict[str, CoreLibrary | RuleStandIn]
    shaped: dict[str, CoreLibrary | RuleStandIn] = field(default_factory=dict)
    #: the shape the spec's improved_r core was generated for, when not the spec's own
    shape_fallback: str | None = None
    #: the duty target (counts) the improved_r cores were generated for, when the
    #: spec's own is out of the rule's reach (its method is another: the rule is compared)
    rule_duty_target: str | None = None
    #: why the rule's integer design refuses this motor, when it is compared only and
    #: its cores are the rule in real arithmetic (sim/rule_stand_in.py)
    rule_refused: str | None = None
    #: compared paper methods generated for a looser time target (Hall ticks) than the
    #: spec's, the bound their design meets at the spec's Hall clock
    time_targets: dict[str, str] = field(default_factory=dict)

    @cached_property
    def scaling(self) -> Scaling:
        return scaling(self.spec, derive())


def _is_output_of(spec: Spec, generated: Path) -> bool:
    try:
        check_fresh(spec, generated)
    except StaleOutputError:
        return False
    return True


def prepare_cores(spec: Spec, methods: tuple[str, ...], build_dir: Path = BUILD_ROOT) -> CoreSet:
    """Compile the checked-in core and generate + compile the other methods' variants
    (`build_dir`: relative to the current folder, as it is when the call is made).

    Variant generation runs the generator's `generate()` (what `codegen generate` runs)
    for each missing variant, so the variant is exactly what the toolchain emits for that
    method (and, for improved_r, EMF shape).
    """
    build_dir = build_dir.resolve()
    spec_path = Path(spec.source_path)
    checked_in = PROJECT_ROOT / "generated" / spec.name / "c"
    # The checked-in core only where it is this spec's output (a user's motor may share
    # a name with a checked-in one, or the spec may have been edited since).
    use_checked_in = _is_output_of(spec, checked_in.parent)
    if not use_checked_in:
        _refuse_without_loop(spec)
    toolchain = _toolchain_digest()
    text = spec_path.read_text(encoding="utf-8")
    variants: dict[tuple[str, str | None], str] = {}
    for method in methods:
        if method == spec.controller.method and use_checked_in:
            continue
        variants[(method, None)] = spec_with_method(text, method)
    if SHAPED_METHOD in methods and not spec.motor.back_emf_shape.frozen:
        variants[(SHAPED_METHOD, FLAT_SHAPE)] = spec_with_emf_shape(
            spec_with_method(text, SHAPED_METHOD), FLAT_SHAPE
        )
    outputs = _generate_all(spec, variants, toolchain, build_dir)
    fallback = None
    refused = outputs.get((SHAPED_METHOD, None))
    # a stand-in shape only for a compared rule: where the spec's own method is the
    # rule, its refusal is the spec's (simulate had run the stand-in's core and said
    # "the spec's own method is another" of an improved_r spec generate refuses)
    if (
        spec.controller.method != SHAPED_METHOD
        and isinstance(refused, str)
        and shape_refused(refused)
    ):  # any other error: below
        fallback = FALLBACK_SHAPE
        retry = {
            (SHAPED_METHOD, None): spec_with_emf_shape(variants[(SHAPED_METHOD, None)], fallback)
        }
        variants.update(retry)
        outputs.update(_generate_all(spec, retry, toolchain, build_dir))
    rule_duty_target = None
    if spec.controller.method != SHAPED_METHOD:
        # the rule is compared on a motor whose firmware is another method: where its
        # integer design cannot meet the spec's duty target, hold it to the bound it
        # can meet (to 0.01 counts up), and say so, rather than simulate nothing
        refused = {
            key: result
            for key, result in outputs.items()
            if key[0] == SHAPED_METHOD
            and isinstance(result, str)
            and refused_duty_bound(result) is not None
        }
        rule_duty_target = reachable_duty_target(refused.values())
        if rule_duty_target is not None:
            relaxed = {k: spec_with_duty_target(variants[k], rule_duty_target) for k in refused}
            outputs.update(_generate_all(spec, relaxed, toolchain, build_dir))
    # a compared paper method whose design misses the spec's time target where the spec
    # holds it (its X too coarse at this Hall clock, which the spec's own method takes):
    # generated for the bound it meets, at the same Hall clock, and said so
    time_targets: dict[str, str] = {}
    timed = {
        key: refused_time_bound(result)
        for key, result in outputs.items()
        if key[0] not in (spec.controller.method, SHAPED_METHOD) and isinstance(result, str)
    }
    relaxed_time = {k: f"{float(b):.2f}" for k, b in timed.items() if b is not None}
    if relaxed_time:
        outputs.update(
            _generate_all(
                spec,
                {k: spec_with_time_target(variants[k], v) for k, v in relaxed_time.items()},
                toolchain,
                build_dir,
            )
        )
        time_targets = {k[0]: v for k, v in relaxed_time.items()}
    rule_refused = None
    if spec.controller.method != SHAPED_METHOD and isinstance(
        outputs.get((SHAPED_METHOD, None)), str
    ):
        # compared only, and its integer design refuses this motor: the rule in real
        # arithmetic stands in for its cores (sim/rule_stand_in.py), and the report says so
        rule_refused = str(outputs[(SHAPED_METHOD, None)]).split("fixed-point design: ")[-1]
        stand_ins = {k: variants[k] for k in outputs if k[0] == SHAPED_METHOD}
        for key in stand_ins:
            del outputs[key]
    own_result = outputs.get((spec.controller.method, None))
    if isinstance(own_result, str):
        raise _refused(spec, spec.controller.method, own_result, build_dir)
    for key, result in outputs.items():
        if isinstance(result, str):
            raise SilError(f"generating the {key[0]!r} core failed:\n{result}")
    cores: dict[str, CoreLibrary | RuleStandIn] = {}
    for method in methods:
        if rule_refused is not None and method == SHAPED_METHOD:
            continue
        c_dir = outputs.get((method, None), checked_in)
        assert isinstance(c_dir, Path)
        cores[method] = load_core(c_dir, method, build_dir)
    shaped: dict[str, CoreLibrary | RuleStandIn] = {}
    if (SHAPED_METHOD, FLAT_SHAPE) in outputs:
        flat_dir = outputs[(SHAPED_METHOD, FLAT_SHAPE)]
        assert isinstance(flat_dir, Path)
        shaped[FLAT_SHAPE] = load_core(flat_dir, SHAPED_METHOD, build_dir)
    if rule_refused is not None and SHAPED_METHOD in methods:
        sibling = next(iter(cores.values()), None)
        if sibling is None:  # improved_r alone was asked for: the spec's own core
            own = spec.controller.method
            own_dir = (
                checked_in
                if use_checked_in
                else _generate_all(
                    spec, {(own, None): spec_with_method(text, own)}, toolchain, build_dir
                )[(own, None)]
            )
            if isinstance(own_dir, str):
                raise _refused(spec, own, own_dir, build_dir)
            sibling = load_core(own_dir, own, build_dir)
        for (_, shape), variant_text in stand_ins.items():
            variant = build_dir / "specs" / f"{spec.name}-{SHAPED_METHOD}-stand-in.yaml"
            variant.write_text(variant_text, encoding="utf-8")
            copy = load_spec(variant)
            rule = rule_constants(copy, scaling(copy, derive()))
            stand_in = RuleStandIn(sibling, rule, rule_refused)
            if shape is None:
                cores[SHAPED_METHOD] = stand_in
            else:
                shaped[shape] = stand_in
    return CoreSet(spec, cores, shaped, fallback, rule_duty_target, rule_refused, time_targets)


def _variant_spec(spec: Spec, tag: str, build_dir: Path) -> Path:
    """Where the text of one variant of the spec is written to be generated."""
    return build_dir / "specs" / f"{spec.name}-{tag}.yaml"


def _refuse_without_loop(spec: Spec) -> None:
    """The spec's own firmware holds the braking-current loop, which the core files the
    simulation generates leave out: where no format of the loop meets the spec,
    `generate` refuses the spec, and so does the simulation (a check of the spec, not of
    a variant, so a cached variant does not skip it)."""
    from codegen.control import current_loop
    from codegen.methods.base import FixedPointError

    try:
        current_loop.design(spec)
    except FixedPointError as exc:
        where = f"{spec.source_path}: {exc.key}: fixed-point design: {exc}"
        raise SpecRefusedError(" ".join(where.split())) from None


def _refused(spec: Spec, method: str, error: str, build_dir: Path) -> SpecRefusedError:
    """The error of the spec's own method's variant, said of the spec itself (the
    variant's text is the spec's: the same lines, the method spelled out)."""
    variant = str(_variant_spec(spec, method, build_dir))
    lines = error.replace(variant, spec.source_path).splitlines()
    return SpecRefusedError("\n".join(" ".join(line.split()) for line in lines))


def _generate_all(
    spec: Spec,
    variants: dict[tuple[str, str | None], str],
    toolchain: str,
    build_dir: Path,
) -> dict[tuple[str, str | None], Path | str]:
    """Generate each variant text (cached by content); its c/ folder, or the error of a
    variant the generator refused (a spec or fixed-point design error, which names its
    key). One after the other in this process, through the generator's own
    `render_core()` (the core files `codegen generate` writes, and only those: the
    simulation compiles nothing else): the derivation, the device description and the
    imports are loaded once for all of them, which takes less time than one process
    per variant on two cores. An error of any other kind is a bug and is raised as it
    is."""
    from codegen.errors import SpecError
    from codegen.generate import render_core, write_tree
    from codegen.methods.base import FixedPointError

    out: dict[tuple[str, str | None], Path | str] = {}
    for key, text in variants.items():
        method, shape = key
        tag = method if shape is None else f"{method}-{shape.replace(' ', '')}"
        digest = hashlib.sha256((text + toolchain).encode()).hexdigest()[:12]
        folder = build_dir / f"{spec.name}-{tag}-{digest}"
        out[key] = folder / "c"
        if (folder / "c" / CORE_SOURCE).exists():
            continue
        own = re.compile(rf"{re.escape(spec.name)}-{re.escape(tag)}-[0-9a-f]{{12}}")
        for stale in build_dir.glob(f"{spec.name}-{tag}-*"):
            if own.fullmatch(stale.name):  # not improved_r-flat's for improved_r's
                shutil.rmtree(stale, ignore_errors=True)  # variants of an older toolchain
        variant_spec = _variant_spec(spec, tag, build_dir)
        variant_spec.parent.mkdir(parents=True, exist_ok=True)
        variant_spec.write_text(text, encoding="utf-8")
        try:
            write_tree(render_core(variant_spec).files, folder)
        except FixedPointError as exc:
            out[key] = f"{variant_spec}: {exc.key}: fixed-point design: {exc}"
        except SpecError as exc:
            out[key] = str(exc)
    return out


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
    core: CoreLibrary | RuleStandIn,
    spec: Spec,
    scale: Scaling,
    case: Case,
    measured_current_a: float,
    main_duty: float,
    overrides: dict[str, int] | None = None,
) -> Command:
    """Call the C core at the edge and translate its outputs into a gate command.

    The main duty after the commutation is the one handed to the core, in counts,
    because that is what the port keeps writing to the turn-on transistor.
    `overrides` replaces inputs by the integers a firmware actually used (the emulated
    drive's comparison hands the core the Hall interval, bus code, current and main
    duty its timing handler read).
    """
    inputs = {**core_inputs(spec, scale, case, measured_current_a, main_duty), **(overrides or {})}
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

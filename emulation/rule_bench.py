"""`make bench`'s figures for the resistance-aware rule (controller.method improved_r).

The bench's SPEC is re-used with its method replaced by improved_r (a spec that already
has it is used as it is), generated and linked into a folder of its own (build/bench/ by
default), and measured with the machinery of emulation/isr_bench.py:

* flash and RAM of core + port, with the share of the core's largest table (the octave
  psi table of the rule);
* the three handlers in their order over `bench`'s sweep (the Hall edge must stay at
  its targets: it does no arithmetic);
* TIM1_TRG_COM_IRQHandler, which runs the rule (a binary search over the PWM carrier
  boundaries of the sector, whose number of active steps grows with the Hall period),
  once per point of a denser sweep of the Hall period over the whole speed range plus
  the counter's full range, bus min/middle/max and braking current 0/nominal/max; and
  again with the current ADC one code below full scale (beyond the spec's maximum; a
  rail is a sensor fault), saturated;
* which functions the timing handler can reach in the linked image (no library divide,
  64-bit or float helper) and which symbols the core object leaves undefined.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass, replace
from pathlib import Path

from elftools.elf.elffile import ELFFile
from elftools.elf.sections import SymbolTableSection

from codegen.build_firmware import Sizes, build, linked_flash
from codegen.derivation import derive
from codegen.fixedpoint.scaling import scaling
from codegen.generate import generate
from codegen.methods.base import FixedPointError
from codegen.methods.improved_r.design import reachable_duty_target
from codegen.render import PROJECT_ROOT
from codegen.spec_loader import load_spec
from codegen.spec_variant import (
    FALLBACK_SHAPE,
    shape_refused,
    spec_with_duty_target,
    spec_with_emf_shape,
    spec_with_method,
)
from emulation.callgraph import reached_functions
from emulation.figures import Figure
from emulation.isr_bench import (
    BUS_HANDLER,
    TIMING_HANDLER,
    PortRig,
    Sample,
    Stats,
    Sweep,
    TimingPoint,
    TimingSweep,
    bench,
    sector_share,
    shortest_sector_cycles,
    sweep,
    timing_sweep,
)

METHOD = "improved_r"
#: Log-spaced Hall periods of the rule sweep, top speed to slowest (the counter's full
#: range is added).
RULE_PERIOD_POINTS = 32
#: Issue 17's targets for the rule: core + port within 2 KiB of flash, the timing
#: handler within 600 cycles in the worst case; the Hall edge keeps its 120.
FLASH_TARGET_BYTES = 2048
TIMING_TARGET_CYCLES = 600
HALL_TARGET_CYCLES = 120


def improved_r_spec(spec_path: str | Path, folder: Path) -> Path:
    """The spec with controller.method improved_r: itself if it has it, else a copy in
    `folder` named <name>_improved_r, identical in every other value."""
    spec = load_spec(spec_path)
    if spec.controller.method == METHOD:
        return Path(spec_path)
    name = f"{spec.name}_{METHOD}"[:64]
    text = spec_with_method(Path(spec_path).read_text(encoding="utf-8"), METHOD, name)
    folder.mkdir(parents=True, exist_ok=True)
    out = folder / f"{name}.yaml"
    out.write_text(text, encoding="utf-8")
    return out


@dataclass(frozen=True)
class RuleVariant:
    """What the improved_r copy of a spec was generated for, where not the spec's own."""

    #: the duty target (counts) it was held to, when the spec's is out of the rule's reach
    duty_target: str | None = None
    #: the EMF shape it took, when the rule's firmware refuses the spec's
    emf_shape: str | None = None


def generate_rule(spec_path: str | Path, variant: Path, generated: Path) -> RuleVariant:
    """Generate the improved_r `variant` into `generated`. Where it is a copy (the
    spec's own method is another), as the simulation does: a shape the rule's firmware
    cannot take (not affine over the commutation) becomes the paper's 120 deg
    trapezoid, and a duty target its integer design cannot meet becomes the bound it
    meets (to 0.01 counts up). Any other refusal is raised."""
    copy = variant != Path(spec_path)
    shape = None
    for _ in range(3):  # the shape, then the duty target, then done
        try:
            generate(variant, generated, PROJECT_ROOT)
            return RuleVariant(emf_shape=shape)
        except FixedPointError as error:
            text = variant.read_text(encoding="utf-8")
            if copy and shape is None and shape_refused(str(error)):
                shape = FALLBACK_SHAPE
                variant.write_text(spec_with_emf_shape(text, shape), encoding="utf-8")
                continue
            target = reachable_duty_target([str(error)])
            if target is None or not copy:
                raise
        variant.write_text(spec_with_duty_target(text, target), encoding="utf-8")
        generate(variant, generated, PROJECT_ROOT)
        return RuleVariant(target, shape)
    raise AssertionError("unreachable: each refusal is handled once")


def rule_sweep(
    spec_path: str | Path, period_points: int = RULE_PERIOD_POINTS
) -> tuple[Sweep, Sweep]:
    """The timing handler's sweep within the spec (periods over the whole speed range
    and up to the Hall counter's full range, bus min/middle/max, current 0/nominal/max,
    duty 0/half/full), and the same periods with the current ADC at the top of its
    range: one code below full scale, the highest the port hands the timing (a sample
    at either rail is a current-sensor fault, and trips the bridge)."""
    spec = load_spec(spec_path)
    sc = scaling(spec, derive())
    base = sweep(spec, sc, period_points)
    within = replace(base, periods=(*base.periods, sc.period_cap_ticks))
    return within, replace(within, currents=(sc.adc_full_scale - 2,))


def undefined_symbols(obj: Path) -> frozenset[str]:
    """Symbols an object file uses but does not define (calls to library helpers)."""
    with obj.open("rb") as stream:
        elf = ELFFile(stream)
        return frozenset(
            entry.name
            for table in elf.iter_sections()
            if isinstance(table, SymbolTableSection)
            for entry in table.iter_symbols()
            if entry.name and entry["st_shndx"] == "SHN_UNDEF"
        )


def helper_names(names: Iterable[str]) -> frozenset[str]:
    """The names that are compiler run-time helpers (libgcc / AEABI: division, 64-bit
    shifts and multiplies, soft float): every such name starts with two underscores."""
    return frozenset(n for n in names if n.startswith("__"))


def largest_table(sizes: Sizes) -> tuple[str, int]:
    """The core's largest read-only data section, name and bytes."""
    tables = [(k, v) for k, v in sizes.sections.items() if k.startswith(".rodata")]
    return max(tables, key=lambda t: t[1], default=("none", 0))


def point_breakdown(spec_path: str | Path, elf: Path, point: TimingPoint) -> dict[str, Sample]:
    """The timing handler at one sweep point again, its cost split by the function each
    step ran in. The core's functions are pure functions of the port's inputs, so their
    part repeats the sweep's; the port's own part may differ by a few instructions with
    the timing slot it fills (which depends on the edges before)."""
    rig = PortRig(load_spec(spec_path), elf)
    rig.prime(point.bus, point.current, point.period)
    rig.set_inputs(point.bus, point.current, point.duty)
    sequence = rig.spec.hall.sequence
    # an edge before it, as in the sweep: the Hall edge measured must follow a valid one
    rig.hall_edge(sequence[-1], point.period)
    rig.timing()
    rig.commutation_end()
    rig.hall_edge(sequence[0], point.period)
    result = rig.timing()
    if rig.entries(result.trace) != point.entries:
        raise AssertionError("the timing handler did not repeat its sweep run")
    functions = sorted((rig.image.symbol(name) for name in point.entries), key=lambda s: -s.size)
    return {s.name: rig.part(result, s) for s in functions}


@dataclass(frozen=True)
class RuleBench:
    spec: Path  # the improved_r spec measured
    generated: Path
    build_dir: Path
    sizes: dict[str, Sizes]
    linked: dict[str, int]  # flash by part as linked (what --gc-sections kept)
    handlers: Stats  # `bench` on the image
    within: TimingSweep  # inputs within the spec
    saturated: TimingSweep  # current ADC one code below full scale
    breakdown: dict[str, Sample]  # the worst point of `within`, by function
    reached: frozenset[str]  # from the timing handler, static call graph
    indirect: bool
    core_undefined: frozenset[str]
    sector_cycles: int
    #: the duty target (counts) the variant was held to, when the spec's is out of reach
    duty_target: str | None = None
    #: the EMF shape the variant took, when the rule's firmware refuses the spec's
    emf_shape: str | None = None

    def figures(self) -> list[Figure]:
        core, port = self.linked.get("core", 0), self.linked.get("port", 0)
        code = core + port
        table, table_bytes = largest_table(self.sizes["core"])
        # judged as the paper method's timing handler is (`emulation.bench`): on the cached
        # bus state; a bus change (its handler, then the timing it pends) is a figure of
        # its own, without a target, and in the CPU-load budget
        paths = [self.within.stats, self.saturated.stats]
        if self.handlers.timing is not None:
            paths.append(self.handlers.timing)
        worst = max(paths, key=lambda p: p.cycles_worst)
        changes = [p for p in (self.within.bus_change_stats, self.handlers.timing_bus) if p]
        change = max(changes, key=lambda p: p.cycles_worst, default=None)
        helpers = helper_names(self.reached) | helper_names(self.core_undefined)
        return [
            Figure(
                f"{METHOD} core + port flash",
                code,
                "B",
                FLASH_TARGET_BYTES,
                f"as linked: core {core}, port {port} (objects {self.sizes['core'].flash} and"
                f" {self.sizes['port'].flash}: the linker drops what no handler reaches); its"
                f" largest table {table} {table_bytes} B ({100.0 * table_bytes / code:.1f} %)",
            ),
            Figure(
                f"{METHOD} Hall edge worst",
                self.handlers.hall.cycles_worst,
                "cycles",
                HALL_TARGET_CYCLES,
                "entry and exit included",
            ),
            Figure(
                f"{METHOD} {TIMING_HANDLER} worst, bus state cached",
                worst.cycles_worst,
                "cycles",
                TIMING_TARGET_CYCLES,
                f"{worst.name}{sector_share(worst.cycles_worst, self.sector_cycles)}",
            ),
            *(
                [
                    Figure(
                        f"{METHOD} {change.name} worst",
                        change.cycles_worst,
                        "cycles",
                        None,
                        "both handlers' entry and exit included; in the CPU-load budget"
                        f"{sector_share(change.cycles_worst, self.sector_cycles)}",
                    )
                ]
                if change is not None
                else []
            ),
            Figure(
                f"{METHOD} library helpers reachable from {TIMING_HANDLER} and {BUS_HANDLER}",
                len(helpers),
                "",
                0,
                ", ".join(sorted(helpers))
                or f"none (static call graph: {', '.join(sorted(self.reached))}"
                f"{'; INDIRECT branches' if self.indirect else ''})",
            ),
        ]

    def lines(self) -> list[str]:
        name = load_spec(self.spec).name
        lines = [f"{METHOD} variant {name} ({self.spec}, generated into {self.generated})"]
        if self.emf_shape is not None:
            lines.append(
                f"{METHOD}   generated for a {self.emf_shape} trapezoid EMF: the rule's firmware"
                " holds the EMF affine over the commutation and refuses the spec's shape (the"
                " simulation falls back the same way)"
            )
        if self.duty_target is not None:
            lines.append(
                f"{METHOD}   held to {self.duty_target} duty counts: its integer design cannot"
                " meet the spec's accuracy.duty_counts (the spec's own method is another)"
            )
        lines += self._sweep_lines(self.within, "rule sweep")
        worst = self.within.worst
        parts = ", ".join(
            f"{fn} {worst.entries[fn]}x {s.instructions} instructions {s.cycles_worst} cycles"
            + (
                f" ({s.cycles_worst / worst.entries[fn]:.0f} per call)"
                if worst.entries[fn] > 1
                else ""
            )
            for fn, s in self.breakdown.items()
            if fn != TIMING_HANDLER
        )
        lines.append(f"{METHOD}   worst call by function (no entry/exit): {parts}")
        lines += self._sweep_lines(
            self.saturated, "current ADC one code below full scale, beyond the spec's max"
        )
        return lines

    def _sweep_lines(self, result: TimingSweep, title: str) -> list[str]:
        stats = result.stats
        worst = result.worst
        calls = {
            fn: sorted({p.entries[fn] for p in result.points}) for fn in sorted(result.functions())
        }
        entered = ", ".join(
            f"{fn} {c[0]}" if len(c) == 1 else f"{fn} {c[0]}..{c[-1]}"
            for fn, c in calls.items()
            if fn != TIMING_HANDLER
        )
        applied = [p.applied for p in result.points if p.applied is not None]
        ticks = sorted({a[0] for a in applied})
        return [
            f"{METHOD} {TIMING_HANDLER}, {title} ({result.inputs.describe()}):"
            f" {stats.calls} calls; instructions worst {stats.instructions_worst} mean"
            f" {stats.instructions_mean:.1f}; cycles worst {stats.cycles_worst} mean"
            f" {stats.cycles_mean:.1f}{sector_share(stats.cycles_worst, self.sector_cycles)};"
            f" worst at T = {worst.period} ticks, bus code {worst.bus}, current code"
            f" {worst.current}",
            f"{METHOD}   per call: {entered} (entries); {len(set(applied))} distinct applied"
            f" (t_com, duties) in {len(applied)} applied edges, t_com {ticks[0]}..{ticks[-1]}"
            f" ticks"
            if ticks
            else f"{METHOD}   per call: {entered} (entries); no edge applied a timing",
        ]


def run(spec_path: str | Path, work: Path, *, quick: bool = False) -> RuleBench:
    """Generate, build and measure the improved_r variant of `spec_path` under `work`;
    `quick` shrinks every sweep (a check that it runs, not headline figures)."""
    variant = improved_r_spec(spec_path, work)
    spec = load_spec(variant)
    generated = work / spec.name
    build_dir = work / f"{spec.name}.build"
    made = generate_rule(spec_path, variant, generated)
    spec = load_spec(variant)
    sizes = build(generated, build_dir)
    # The Hall edge and the commutation end do not depend on the rule: a small sweep of
    # them; the rule's cost is the timing sweeps' business.
    full = sweep(spec, scaling(spec, derive()), 2 if quick else 3)
    inputs = replace(
        full, buses=full.buses[::2], currents=full.currents[-1:], duties=full.duties[1:2]
    )
    handlers = bench(variant, generated, build_dir, inputs)
    elf = build_dir / "firmware.elf"
    within_inputs, saturated_inputs = rule_sweep(variant, 2 if quick else RULE_PERIOD_POINTS)
    # The rule does not read the main duty (uses_main_duty): one duty of the sweep.
    within_inputs = replace(within_inputs, duties=within_inputs.duties[1:2])
    saturated_inputs = replace(saturated_inputs, duties=saturated_inputs.duties[1:2])
    if quick:
        within_inputs = replace(
            within_inputs, buses=within_inputs.buses[::2], currents=within_inputs.currents[-1:]
        )
    within = timing_sweep(spec, elf, within_inputs)
    saturated = timing_sweep(spec, elf, saturated_inputs)
    rig = PortRig(spec, elf)
    # the timing handler and the bus-change handler, whose bus state it computes with
    timing_reached, timing_indirect = reached_functions(rig.image, TIMING_HANDLER)
    bus_reached, bus_indirect = reached_functions(rig.image, BUS_HANDLER)
    reached, indirect = timing_reached | bus_reached, timing_indirect or bus_indirect
    return RuleBench(
        spec=variant,
        generated=generated,
        build_dir=build_dir,
        sizes=sizes,
        linked=linked_flash(build_dir),
        handlers=handlers,
        within=within,
        saturated=saturated,
        breakdown=point_breakdown(variant, elf, within.worst),
        reached=reached,
        indirect=indirect,
        core_undefined=undefined_symbols(build_dir / "core.o"),
        sector_cycles=shortest_sector_cycles(variant),
        duty_target=made.duty_target,
        emf_shape=made.emf_shape,
    )

"""Scenario 1 of issue 13: the firmware brakes the simulated motor.

The drive firmware boots on the emulated chip (`scenarios.Run`, with every invariant
of the fault scenarios watched at every step); then the motor of `emulation.pil.plant`
is attached, spinning at the start speed with no current (the bridge is idle until
the first Hall edge), and the closed current loop holds the commanded braking current
(`app_braking_current_ma`, the firmware's command variable) while the rotor slows
under the braking torque down to the stop speed.

The chip runs in chunks that end at the next Hall crossing the plant predicts from
its speed; at the end of each chunk the plant is advanced to the chip's tick and the
Hall pins take the rotor's sector (one line changes per sector, at the crossing to
within the CPU's last basic block).

Each commutation is measured the way `sim.metrics` measures a simulated one: time 0
is the COM event the Hall edge's handler raises (the pattern changes and the carrier
restarts there, as at the simulation's t = 0); I is the turn-off current's mean over
the last whole PWM period before it; the commutation ends when the turn-off current
reaches zero or at the commutation-end COM event, whichever is later (the zero alone
where the command acts like the main duty: its end is then no event in the plant,
decided on the SIL's command with `sim.metrics.acts_like_main_duty`); the window is
every PWM period overlapping the commutation plus the one after (issue 16), and the
deviation is the signed extreme of (|i_nc| - I) / I over the window's period means.
The SIL simulation of the same commutation (`sim.runs`: the generated C core on the
host against the switched plant) runs at the PIL's speed, current and main duty.
"""

from __future__ import annotations

import bisect
import math
import time
from collections import Counter, deque
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from unicorn import UC_HOOK_MEM_READ, UC_HOOK_MEM_WRITE

from codegen.control.sensing import sense_design, steady_signals
from codegen.spec_model import Spec
from emulation.pil.bus import PilError, svd_interrupt
from emulation.pil.comparator import OverCurrentComparator
from emulation.pil.plant import LoadTorque, Mechanics, MotorPlant, PeriodRecord
from emulation.pil.rcc import TICK_HZ
from emulation.pil.scenarios import MAIN_WAIT_PERIODS, Outcome, Run
from emulation.pil.scs import IRQ_BASE
from emulation.pil.timer import cc_flag
from sim.scenario import PRE_EDGE_PERIODS, Case, previous_edge, switching_table

#: What the timing handler hands the core, as fields of the port's state (`static
#: struct {...} port` of templates/c/stm32f103_port.c.j2), read from the chip's RAM
#: (the ELF has no debug information: the offsets come from the generated source,
#: `port_layout`). A wrong offset would make the SIL core's outputs differ from those
#: the chip applied, which the comparison reports for every commutation.
PORT_FIELDS = ("period", "main_duty", "bus_code", "current")
#: The key of a timing run's record that counts the reads of PORT_FIELDS seen (every
#: run reads the Hall interval before it publishes: 0 means the reads went unobserved,
#: and the record holds the fields' values at the handler's entry instead)
READS = "reads_seen"
_C_SIZES = {"uint32_t": 4, "int32_t": 4, "uint16_t": 2, "int16_t": 2, "uint8_t": 1, "*": 4}


def port_layout(port_source: Path) -> dict[str, tuple[int, int]]:
    """(offset, size) of PORT_FIELDS in the port's state, from its declaration in the
    generated stm32f103_port.c (ARM EABI: each scalar aligned to its size)."""
    text = port_source.read_text(encoding="utf-8")
    start = text.index("static struct {")
    body = text[start : text.index("} port;", start)].splitlines()[1:]
    out: dict[str, tuple[int, int]] = {}
    offset = 0
    for line in body:
        declaration = line.split(";")[0].strip()
        if not declaration:
            continue
        name = declaration.split()[-1].lstrip("*")
        kind = "*" if "*" in declaration else declaration.split()[-2]
        if kind not in _C_SIZES:
            break  # a struct member: every field the timing reads comes before it
        size = _C_SIZES[kind]
        offset = -(-offset // size) * size
        out[name] = (offset, size)
        offset += size
    missing = [f for f in PORT_FIELDS if f not in out]
    if missing:
        raise PilError(f"{port_source}: the port's state has no field {', '.join(missing)}")
    return {f: out[f] for f in PORT_FIELDS}


#: TIM1 CCER's output enables of channels 1 to 3 (CCxE and CCxNE): the switches a COM
#: event leaves enabled
CCER_OUTPUTS = 0b0101_0101_0101


def edge_coms(
    com_ticks: list[int], com_ccers: list[int], hall: int, following: int
) -> tuple[int, int | None] | None:
    """(index of the edge's own COM event, index of its commutation-end COM event or
    None) among the COM events (`com_ticks`, with the CCER each put in force), for the
    Hall edge whose pins changed at `hall` and the next one at `following`.

    The edge's own COM event is the first one from `hall` on that enables a switch
    (its incoming one). A commutation end only disables the outgoing switch: when the
    previous edge's commutation lasts about its whole sector (commutation ticks at the
    Hall interval), its end lands on or just after the next pin change, before the
    firmware's Hall edge handler runs, and it is not that edge's time 0. The
    commutation end is the next COM event if it enables nothing, wherever it lands."""
    for k in range(max(bisect.bisect_left(com_ticks, hall), 1), len(com_ticks)):
        if com_ticks[k] >= following:
            return None
        if not com_ccers[k] & ~com_ccers[k - 1] & CCER_OUTPUTS:
            continue
        if k + 1 < len(com_ticks) and not com_ccers[k + 1] & ~com_ccers[k] & CCER_OUTPUTS:
            return k, k + 1
        return k, None
    return None


#: Commutations after the first edge that are not measured: the Hall interval, the
#: current loop and the commutation timing start from nothing at the first edge.
SETTLING_EDGES = 6


@dataclass(frozen=True)
class BrakingSetup:
    start_rpm: float
    stop_rpm: float
    current_a: float
    inertia_scale: float = 1.0  # times the spec's rotor inertia
    load_torque: LoadTorque = 0.0
    #: emulated seconds after which the run stops whatever the speed
    max_seconds: float = 10.0
    #: stop after this many Hall edges (None: at the stop speed)
    max_edges: int | None = None
    #: seconds from the start whose instantaneous currents are kept (the figures)
    trace_seconds: float = 0.0


@dataclass(frozen=True)
class Commutation:
    """One Hall edge of the braking run, measured as `sim.metrics` measures one."""

    index: int
    hall_tick: int
    com_tick: int  # the Hall edge handler's COM event: time 0
    end_com_tick: int | None  # the commutation-end COM event
    sector_to: int
    speed_rpm: float  # at time 0
    current_a: float  # I: the turn-off current's mean over the last whole pre-edge period
    main_duty: float  # the steady switch's last compare value written before the edge, / period
    sampled_code: int  # the firmware's I at the edge: its latest sample, ADC code
    #: the phase currents PRE_EDGE_PERIODS whole PWM periods before the cut one
    start_currents: tuple[float, float, float]
    #: the steady switch's duty in force in each of those periods and the cut one (in
    #: each half of each, centre-aligned: `duty_halves`)
    pre_duties: tuple[float, ...]
    #: what the timing handler read at its last run before the edge (port state), and
    #: how many reads of it were seen (READS)
    firmware_inputs: dict[str, int]
    #: (D_on, D_off, commutation ticks) the chip applied: CCRx at the COM event, TIM3 CCR2
    applied: tuple[int, int, int]
    #: the turn-on switch's duty from the commutation end on (the loop's latest)
    main_duty_after: float
    #: the fraction of a PWM period that had run at the COM event (the carrier restarts)
    carrier_phase: float
    commutation_s: float  # from time 0 to the end of the commutation
    zero_s: float | None  # the turn-off current reaching zero, from time 0
    period_deviations_pct: tuple[float, ...]
    deviation_worst_pct: float
    #: the turn-on switch's duty in force in each PWM period from the commutation end
    #: (in each half, centre-aligned)
    post_duties: tuple[float, ...] = ()
    #: `pre_duties` and `post_duties` hold two duties a period, the up-count's and the
    #: down-count's: centre-aligned TIM1 loads preloaded compare values at its overflow
    #: as well as at its underflow (RCR = 0), so the loop's write in a period's first
    #: half takes effect in its second
    duty_halves: bool = False
    #: the rotor's speed at the end of the window (the SIL holds `speed_rpm` throughout)
    window_speed_rpm: float | None = None
    #: the window's length from time 0, s
    window_s: float = 0.0
    sil_worst_pct: float | None = None
    #: the host-compiled core's (D_on, D_off, ticks) for the firmware's inputs
    sil_outputs: tuple[int, int, int] | None = None
    sil_period_deviations_pct: tuple[float, ...] = ()
    #: the period means' deviations from time 0 on, past the window (the same periods
    #: in both runs, whichever window is longer)
    extended_deviations_pct: tuple[float, ...] = ()
    sil_extended_deviations_pct: tuple[float, ...] = ()
    #: the window and the commutation's length without the commanded end: what they are
    #: where the command acts like the main duty (`sim.metrics.acts_like_main_duty`:
    #: no suppression, the end no event in the plant), decided with the SIL's command
    physical_period_deviations_pct: tuple[float, ...] = ()
    physical_commutation_s: float = 0.0
    #: the firmware's latest sample at the Hall edge before this one (`sampled_code` of
    #: the edge before): the steady I the port holds through that edge's commutation,
    #: which the timing run at its end, the last before this edge, reads
    previous_sampled_code: int | None = None

    @property
    def compared_periods(self) -> int:
        """The periods both runs are compared on: the longer of the two windows. Each
        window ends one period after the commutation; where the turn-off current reaches
        zero a few nanoseconds either side of a period boundary in the two runs, one
        window is a period longer by definition alone, and the other run's deviation is
        taken over the same periods."""
        return max(len(self.period_deviations_pct), len(self.sil_period_deviations_pct))

    @property
    def difference_pp(self) -> float | None:
        """How far the PIL's deviation is from the SIL's over the same periods (the
        longer window): the largest difference of the period means, period by period,
        and of the worst deviations' magnitudes (where the positive and the negative
        extreme of a window are nearly equal, its signed extreme flips sign on a
        hundredth of a point; the magnitudes and the periods do not)."""
        where = self.difference_at
        return None if where is None else where[0]

    @property
    def difference_at(self) -> tuple[float, int | None, float, float] | None:
        """`difference_pp` and where it is: (pp, the period (0 from the edge; None where
        the worst deviations' magnitudes differ most), the PIL's and the SIL's value
        there). A report of two equal worst deviations "1.16 pp apart" had not said
        that the runs parted in one period after the commutation's end (a hunt)."""
        if self.sil_worst_pct is None:
            return None
        n = self.compared_periods
        pil = self.extended_deviations_pct[:n] or self.period_deviations_pct
        sil = self.sil_extended_deviations_pct[:n] or self.sil_period_deviations_pct
        if len(pil) < n or len(sil) < n:
            # a run whose trace ends with its sector (the SIL's, or the PIL's at the next
            # edge) has no period past it: the periods both have (the PIL's extra period
            # before the next edge had been set against nothing: 4-5 pp "apart" on a
            # motor whose current reached zero late in its sector)
            m = min(len(self.period_deviations_pct), len(self.sil_period_deviations_pct))
            pil, sil = self.period_deviations_pct[:m], self.sil_period_deviations_pct[:m]
        gaps = [(abs(a - b), k, a, b) for k, (a, b) in enumerate(zip(pil, sil, strict=True))]
        worst = max(gaps, default=(0.0, 0, 0.0, 0.0))
        pil_extreme = max(map(abs, pil), default=0.0)
        sil_extreme = max(map(abs, sil), default=0.0)
        if abs(pil_extreme - sil_extreme) > worst[0]:
            return abs(pil_extreme - sil_extreme), None, pil_extreme, sil_extreme
        return worst[0], worst[1], worst[2], worst[3]

    @property
    def window_lengths(self) -> tuple[int, int]:
        """Periods in the PIL's and the SIL's window."""
        return len(self.period_deviations_pct), len(self.sil_period_deviations_pct)


@dataclass(frozen=True)
class SteadySector:
    """The samples the current loop closed on in one Hall sector, and what it made of
    each: the conversions of the sector's current signal (the JDRx the port reads I from
    there) whose injected sequence was triggered at or after the previous edge's
    commutation-end COM event (the port drops the sequence in flight then, `stale`, and
    runs no loop step while the commutation runs) and ended (JEOC, where the loop runs)
    before the Hall edge (from its handler on the next commutation runs)."""

    index: int  # the Hall edge that ends the sector
    speed_rpm: float  # at that edge
    codes: tuple[int, ...]  # ADC codes
    #: the steady switch's compare preload (TIM1 counts) at the end of the next injected
    #: sequence after each sample (at the Hall edge, where that ends after it): the duty
    #: the loop set from the sample, which runs at its sequence's end
    duties: tuple[int, ...]


@dataclass
class BrakingResult:
    spec: Spec
    setup: BrakingSetup
    outcome: Outcome
    commutations: list[Commutation]
    periods: list[PeriodRecord]
    start_tick: int
    end_tick: int
    end_rpm: float
    gate_log: list[tuple[int, tuple[bool | None, ...]]]
    speed_trace: list[tuple[int, float]] = field(default_factory=list)
    mechanics: Mechanics | None = None
    #: (s, phase currents) of the first `setup.trace_seconds`
    trace: list[tuple[float, np.ndarray]] = field(default_factory=list)
    edges: int = 0
    wall_s: float = 0.0
    #: why the Hall edges after the settling ones that were not measured were not
    #: (reason -> edges)
    unmeasured: dict[str, int] = field(default_factory=dict)
    #: the largest |phase current| of the run, A, and the comparator's trips (the
    #: crossing's tick, the pin's tick, the peak so far A)
    peak_current_a: float = 0.0
    comparator_trips: list[tuple[int, int, float]] = field(default_factory=list)
    #: every Hall sector's loop samples from the settling edges on (`SteadySector`),
    #: measured commutation or not
    steady_sectors: list[SteadySector] = field(default_factory=list)

    @property
    def emulated_s(self) -> float:
        return (self.end_tick - self.start_tick) / TICK_HZ


@dataclass(frozen=True)
class ShuntSense:
    """A current channel's pin: offset + gain x the shunt's current at the sample
    (`MotorPlant.shunt_currents`, index 0 the DC link, 1..3 phases A..C), bounded for
    the ADC (emulation/pil/adc.py `BoundedInput`) from the plant's largest possible
    phase current: a low-side shunt carries one phase's current or none, the DC link
    the sum over a subset of the phases, at most half the sum of their magnitudes
    (they sum to 0). No bound where the current may reach the over-current
    comparator's trip (its level now: a test may lower it): the comparator sees the
    currents at the points the plant is advanced to, and each conversion the ADC
    converts advances it."""

    plant: MotorPlant
    index: int
    offset_v: float
    gain_v_per_a: float
    comparator: OverCurrentComparator

    def __call__(self, tick: int) -> float:
        return self.offset_v + self.gain_v_per_a * self.plant.shunt_currents(tick)[self.index]

    def volts_range(self, lo: int, hi: int) -> tuple[float, float] | None:
        peak = self.plant.current_bound(lo, hi)
        if not peak < self.comparator.trip_a:
            return None
        swing = abs(self.gain_v_per_a) * (1.5 if self.index == 0 else 1.0) * peak
        swing = swing * (1.0 + 1e-9) + 1e-12  # the shunt's sum rounded, the gain's product
        return self.offset_v - swing, self.offset_v + swing


class BrakingLoop:
    """A booted `Run` with the motor attached; `run()` brakes it."""

    def __init__(self, elf: Path, port_source: Path, spec: Spec, setup: BrakingSetup) -> None:
        self.spec = spec
        self.setup = setup
        self.run = Run(elf, spec)
        self.machine = self.run.machine
        self.mechanics = Mechanics.of_spec(
            spec, inertia_scale=setup.inertia_scale, load_torque=setup.load_torque
        )
        sector = spec.hall.sequence.index(self._pins_code())
        self.plant = MotorPlant(
            spec,
            self.machine.tim1,
            self.mechanics,
            setup.start_rpm,
            angle_deg=60.0 * sector + 30.0,
            trace_seconds=setup.trace_seconds,
        )
        #: the board's over-current comparator on BKIN, its input the plant's currents
        self.comparator = OverCurrentComparator(
            float(spec.protection.over_current_a),
            lambda active, at: self.run.board.set_break(active, at),
            lambda: self.machine.now,
        )
        self.plant.current_watchers.append(self.comparator.observe)
        self._couple_sensing()
        #: (tick sampled, code) of every injected conversion of a current channel since
        #: the third Hall edge back: what the firmware's I may be
        self._current_codes: deque[tuple[int, int]] = deque()
        self._foreign_current_noted = False
        #: the port has stored a sample in `current` (before, it reads its reset value)
        self._current_stored = False
        current_channels = frozenset(spec.sensing.current_channels)
        self._current_channels = current_channels
        self.machine.adc1.injected_listeners.append(
            lambda tick, channel, code: (
                self._current_codes.append((tick, code)) if channel in current_channels else None
            )
        )
        #: (tick sampled, channel, code, tick its sequence was triggered, TIM1 CCR1..CCR3
        #: preloads at its end) of every injected conversion of a current channel: the
        #: preloads then hold the duty the loop set from the sequence before
        self._current_samples: list[tuple[int, int, int, int, tuple[int, ...]]] = []
        #: the tick each injected sequence (by its trigger's tick) ended: JEOC, where the
        #: current loop runs
        self._sequence_ends: dict[int, int] = {}
        self.machine.adc1.injected_listeners.append(self._injected_converted)
        self.machine.write_symbol_u32("app_braking_current_ma", round(setup.current_a * 1000))
        self.com_ticks: list[int] = []
        #: TIM1 CCR1..CCR3 in force from each COM event on
        self.com_compares: list[tuple[int, ...]] = []
        #: TIM3 CCR2 (the commutation end the last Hall edge scheduled) at each COM event
        self.com_tim3_ccr2: list[int] = []
        #: TIM1 CCER in force from each COM event on
        self.com_ccers: list[int] = []
        self._coms_seen = self.machine.tim1.com_events
        self.machine.tim1.period_listeners.append(self._period_started)
        #: (tick, sector entered, compare values last written (CCRx preload), ARR) at every Hall edge
        self.edges: list[tuple[int, int, tuple[int, ...], int]] = []
        #: the braking current's latest injected sample (the firmware's I) at each edge
        self.sampled_codes: list[int] = []
        #: the ADC channel of that JDRx at each edge (the injected sequence as programmed)
        self.sampled_channels: list[int] = []
        #: JDRx index holding I in each sector (forward), as the port reads it
        self._slots = {s.sector: s.slot for s in steady_signals(spec) if s.direction == "forward"}
        self.speed_trace: list[tuple[int, float]] = []
        self.start_tick = self.machine.now
        self._code = self._pins_code()
        self._ccer_at_edge = self.machine.tim1.ccer
        #: a Hall code the board forces on the pins (a fault), instead of the rotor's
        self.hall_override: int | None = None
        #: (tick, inputs) at every entry of the timing handler (TIM1_TRG_COM)
        self.timing_runs: list[tuple[int, dict[str, int]]] = []
        #: why each edge `commutations()` did not measure was not measured
        self.unmeasured: Counter[str] = Counter()
        self._timing = IRQ_BASE + svd_interrupt("TIM1", "TIM1_TRG_COM_TIM11")
        self._hall_irq = IRQ_BASE + svd_interrupt("TIM3", "TIM3")
        #: TIM1's compare preloads (CCR1..CCR3) at the entry of each Hall edge's handler
        #: (TIM3 with CC1IF): what the current loop left before the edge's commutation
        #: writes its own; None until that handler runs
        self.compares_at_handler: list[tuple[int, ...] | None] = []
        self._entries_seen = len(self.machine.entry_log)
        self._port = self.machine.symbol("port")
        self._layout = port_layout(port_source)
        self.machine.listeners.append(self._watch_entries)
        # what the timing handler reads is taken as it reads it (a higher-priority
        # handler may change a field between the handler's entry and its read)
        self.machine.uc.hook_add(
            UC_HOOK_MEM_WRITE, self._on_publish, None, self._port, self._port + 3
        )
        for name, (offset, size) in self._layout.items():
            address = self._port + offset
            self.machine.uc.hook_add(
                UC_HOOK_MEM_READ, self._on_port_read, name, address, address + size - 1
            )
            # a field the timing handler writes itself before it computes (the bus code,
            # at a bus change) is an input from then on: its new value
            self.machine.uc.hook_add(
                UC_HOOK_MEM_WRITE, self._on_port_write, name, address, address + size - 1
            )
        # Unicorn 2 builds a memory hook into the code it translates from then on: the
        # timing handler, translated while the firmware booted, would never call these
        # (its inputs would stay the snapshot at its entry, not what it read). Dropping
        # every translation makes the next run of each handler translated with them.
        self.machine.uc.ctl_flush_tb()

    def _watch_entries(self, _machine: object) -> None:
        """At each entry of the timing handler, a new record of its inputs (the fields'
        values now, replaced by what it reads); at the first entry of TIM3's handler
        with a capture (CC1IF) after a Hall edge, the compare preloads then."""
        log = self.machine.entry_log
        for tick, exception in log[self._entries_seen :]:
            if exception == self._timing:
                self.timing_runs.append((tick, self._port_inputs()))
            elif (
                exception == self._hall_irq
                and self.compares_at_handler
                and self.compares_at_handler[-1] is None
                and self.machine.tim3.sr & cc_flag(1)
            ):
                self.compares_at_handler[-1] = tuple(self.machine.tim1.ccr_preload[1:4])
        self._entries_seen = len(log)

    def _on_publish(
        self, _uc: object, _access: int, _address: int, _size: int, _value: int, _data: object
    ) -> None:
        """The timing handler publishes its result (`port.timing`, the state's first
        word): the Hall edge applies it from now on."""
        active = self.machine.nvic.active
        if active and active[-1] == self._timing and self.timing_runs:
            self.timing_runs[-1][1]["published"] = self.machine.now

    def _on_port_read(
        self, _uc: object, _access: int, _address: int, _size: int, _value: int, name: str
    ) -> None:
        if self._timing_reading():  # reads after it published are not inputs
            offset, size = self._layout[name]
            word = self.machine.read_u32(self._port + offset)
            record = self.timing_runs[-1][1]
            record[name] = word & ((1 << (8 * size)) - 1)
            record[READS] = record.get(READS, 0) + 1
            if name == "current":
                self._check_current_source(record[name])

    def _check_current_source(self, code: int) -> None:
        """The current the timing handler reads must be a conversion of one of the spec's
        current channels (sensing.current_channels) from this sector or the two before
        (the loop holds its last sample through a commutation, which may fill a sector):
        a port that stored another JDRx (the bus) or a stale sample gives the core a
        current the braking does not have."""
        if self._foreign_current_noted or not self._current_stored:
            return
        since = self.edges[-3][0] if len(self.edges) >= 3 else self.start_tick
        while self._current_codes and self._current_codes[0][0] < since:
            self._current_codes.popleft()
        if not any(code == sampled for _, sampled in self._current_codes):
            self._foreign_current_noted = True
            self.run._note(
                f"the timing handler read the current code {code} at tick {self.machine.now},"
                " which no conversion of the current channel(s)"
                f" {list(self.spec.sensing.current_channels)} (sensing.current_channels) gave"
                " since the third Hall edge back: another signal, or a sample older than"
                " two sectors (the loop sampled nothing since: commutations that fill their"
                " sectors)"
            )

    def _on_port_write(
        self, _uc: object, _access: int, address: int, size: int, value: int, name: str
    ) -> None:
        if name == "current":
            self._current_stored = True
        if self._timing_reading():
            offset, field_size = self._layout[name]
            shift = 8 * (self._port + offset - address)  # the field's bytes in the access
            if shift >= 0 and shift + 8 * field_size <= 8 * size:
                self.timing_runs[-1][1][name] = (value >> shift) & ((1 << (8 * field_size)) - 1)

    def _timing_reading(self) -> bool:
        """The timing handler runs and has not published its result yet."""
        active = self.machine.nvic.active
        return bool(
            active
            and active[-1] == self._timing
            and self.timing_runs
            and "published" not in self.timing_runs[-1][1]
        )

    def _port_inputs(self) -> dict[str, int]:
        out = {}
        for name, (offset, size) in self._layout.items():
            word = self.machine.read_u32(self._port + offset)
            out[name] = word & ((1 << (8 * size)) - 1)
        return out

    def _pins_code(self) -> int:
        from emulation.pil.runner import HALL_PINS

        code = 0
        for port, pin, bit in HALL_PINS:
            code |= int(getattr(self.machine, port).input_level(pin)) << bit
        return code

    def _couple_sensing(self) -> None:
        """Each current channel reads its shunt through the spec's chain at the ADC's
        sample instant."""
        offset = float(self.spec.adc.current_offset_v)
        gain = float(self.spec.adc.current_gain_v_per_a)
        sensing = self.spec.sensing
        plant = self.plant
        channels = sensing.current_channels
        if sensing.topology == "dc_link_shunt":
            shunts = {channels[0]: 0}
        else:
            shunts = {channel: 1 + phase for phase, channel in enumerate(channels)}
        for channel, index in shunts.items():
            sense = ShuntSense(plant, index, offset, gain, self.comparator)
            self.machine.adc1.set_input(channel, sense)

    def _injected_converted(self, tick: int, channel: int, code: int) -> None:
        started = self.machine.adc1.injected_started or 0
        self._sequence_ends[started] = self.machine.now
        if channel in self._current_channels:
            preloads = tuple(self.machine.tim1.ccr_preload[1:4])
            self._current_samples.append((tick, channel, code, started, preloads))

    def _period_started(self, tick: int) -> None:
        tim1 = self.machine.tim1
        if tim1.com_events != self._coms_seen:
            self._coms_seen = tim1.com_events
            self.com_ticks.append(tick)
            self.com_compares.append(tuple(tim1.ccr[1:4]))
            self.com_tim3_ccr2.append(self.machine.tim3.ccr[2])
            self.com_ccers.append(tim1.ccer)

    def _hall_edge(self) -> None:
        tim1 = self.machine.tim1
        before = tim1.ccer
        if self.edges and tim1.moe and self._ccer_at_edge == before and len(self.edges) > 1:
            self.run._note(
                f"the Hall edge at {self.edges[-1][0]} did not commutate (CCER 0x{before:04x})"
            )
        self._ccer_at_edge = before
        leaving = self.plant.sector_before_edge()
        code = self.machine.adc1.jdr[self._slots[leaving]]
        channels = {slot - 1: ch for slot, ch in self.machine.adc1.injected_channels()}
        self.sampled_channels.append(channels.get(self._slots[leaving], -1))
        self.run.board.set_hall(self.plant.hall_code)
        self.edges.append(
            (self.machine.now, self.plant.sector, tuple(tim1.ccr_preload[1:4]), tim1.arr)
        )
        self.compares_at_handler.append(None)
        self.sampled_codes.append(code)

    def _await_faults(self) -> None:
        """After a trip, up to MAIN_WAIT_PERIODS PWM periods for main to publish
        app_faults (the outcome reads them), as the fault scenarios wait."""
        for _ in range(MAIN_WAIT_PERIODS):
            if self.run.board.symbol("app_faults"):
                break
            self.advance_to(self.machine.now + self.run.main_wait_ticks())

    def advance_to(self, target: int) -> None:
        """Run the chip and the motor to `target`, the Hall pins following the rotor
        (chunks end at each Hall crossing the plant predicts)."""
        machine, plant = self.machine, self.plant
        while machine.now < target:
            crossing = plant.next_sector_tick()
            machine.run_until(min(target, crossing if crossing is not None else target))
            plant.advance(machine.now)
            self._follow_rotor()

    def _follow_rotor(self) -> None:
        if self.hall_override is None and self.plant.hall_code != self._code:
            self._code = self.plant.hall_code
            self._hall_edge()

    def edge_budget(self) -> int:
        """The Hall edges a run to the stop speed may take: EDGE_BUDGET times the
        constant-torque estimate (`braking_edges`, friction and losses left out: they
        shorten the run) plus the settling edges."""
        s = self.setup
        expected = braking_edges(
            self.spec, s.start_rpm, max(s.stop_rpm, 0.0), s.current_a, s.inertia_scale
        )
        return SETTLING_EDGES + math.ceil(EDGE_BUDGET * min(expected, 1e9))

    def run_braking(self) -> BrakingResult:
        """Brake to the stop speed (or `max_edges` Hall edges, or `max_seconds`). The run
        ends at once, with a note that fails it, when the bridge trips (MOE cleared: a
        fault latched, the rotor would coast for ever) or when the rotor takes more Hall
        edges than `edge_budget` (it cannot reach the stop speed)."""
        setup = self.setup
        machine, plant = self.machine, self.plant
        limit = self.start_tick + round(setup.max_seconds * TICK_HZ)
        trace_step = round(TICK_HZ / self.spec.inverter.pwm_frequency_hz) * 10
        budget = self.edge_budget()
        while machine.now < limit and plant.speed_rpm > setup.stop_rpm:
            if setup.max_edges is not None and len(self.edges) >= setup.max_edges:
                break
            if machine.tim1.moe_cleared_at is not None:
                saw = self.comparator.trips
                over = (
                    f", the over-current comparator having seen {saw[0][2]:.1f} A"
                    f" (trip {self.comparator.trip_a:g} A, protection.over_current)"
                    if saw
                    else ""
                )
                self.run._note(
                    f"the braking run ended at Hall edge {len(self.edges)},"
                    f" {plant.speed_rpm:.0f} rpm, {(machine.now - self.start_tick) / TICK_HZ * 1e3:.2f} ms"
                    f" after the attach: the bridge tripped (MOE cleared at tick"
                    f" {machine.tim1.moe_cleared_at}), a fault latched{over}"
                )
                self._await_faults()
                break
            if len(self.edges) > budget:
                self.run._note(
                    f"the rotor did not reach {setup.stop_rpm:g} rpm within {budget} Hall edges"
                    f" ({EDGE_BUDGET:g} x the constant-torque estimate): {plant.speed_rpm:.0f} rpm"
                    f" after {(machine.now - self.start_tick) / TICK_HZ * 1e3:.2f} ms"
                )
                break
            self.speed_trace.append((machine.now, plant.speed_rpm))
            self.advance_to(min(limit, machine.now + trace_step))
        else:
            if (
                setup.stop_rpm > 0.0
                and plant.speed_rpm > setup.stop_rpm
                and setup.max_edges is None
            ):
                self.run._note(
                    f"the rotor did not reach {setup.stop_rpm:g} rpm within {setup.max_seconds:g} s"
                    f" of motor time: {plant.speed_rpm:.0f} rpm"
                )
        # half a sector more, so the last commutations have their window
        self.advance_to(
            machine.now
            + round(TICK_HZ * self.plant.drive.sector_time_s(max(plant.speed_rpm, 1.0)) / 2)
        )
        outcome = self.run.outcome(
            "braking",
            None,
            None,
            None,
            f"from {setup.start_rpm:g} rpm to {setup.stop_rpm:g} rpm at {setup.current_a:g} A",
        )
        log = machine.tim1.gate_log or []
        commutations = self.commutations()  # fills `unmeasured`
        return BrakingResult(
            self.spec,
            setup,
            outcome,
            commutations,
            list(plant.periods),
            self.start_tick,
            machine.now,
            plant.speed_rpm,
            log,
            self.speed_trace,
            self.mechanics,
            list(plant.trace),
            len(self.edges),
            time.perf_counter() - self.run.wall,
            dict(self.unmeasured),
            self.comparator.peak_a,
            list(self.comparator.trips),
            self.steady_sectors(),
        )

    # ------------------------------------------------------------------ measurement
    def commutations(self) -> list[Commutation]:
        """The measured commutations; why each other edge is not one goes to
        `unmeasured`."""
        out = []
        self.unmeasured.clear()
        for index in range(SETTLING_EDGES, len(self.edges) - 1):
            measured = self._measure(index)
            if isinstance(measured, Commutation):
                out.append(measured)
            else:
                self.unmeasured[measured] += 1
        return out

    def steady_sectors(self) -> list[SteadySector]:
        """`SteadySector` of every Hall edge from the settling ones on."""
        periods = self.plant.periods
        ends = [p.end for p in periods]
        sampled = [s[0] for s in self._current_samples]
        return [
            self._steady_sector(index, periods, ends, sampled)
            for index in range(SETTLING_EDGES, len(self.edges))
        ]

    def _steady_sector(
        self, index: int, periods: list[PeriodRecord], ends: list[int], sampled: list[int]
    ) -> SteadySector:
        hall, sector, compares, _ = self.edges[index]
        at_handler = self.compares_at_handler[index] or compares  # the run's last edge: none
        at = bisect.bisect_left(ends, hall)
        speed = periods[at].speed_rpm if at < len(periods) else self.plant.speed_rpm
        previous = edge_coms(self.com_ticks, self.com_ccers, self.edges[index - 1][0], hall)
        if previous is None or previous[1] is None:
            return SteadySector(index, speed, (), ())  # the commutation filled the sector
        end = self.com_ticks[previous[1]]
        # the port modulates the incoming switch of the sector's own edge through it
        steady = previous_edge(switching_table().edge_into(sector, "forward")).modulated_on
        channel = (int(steady[1:]) - 1) // 2  # T1..T6 -> CCR1..CCR3
        signal = self.sampled_channels[index]
        samples = self._current_samples
        codes, duties = [], []
        for k in range(bisect.bisect_left(sampled, end), bisect.bisect_left(sampled, hall)):
            _, ch, code, started, _ = samples[k]
            if ch != signal or started < end or self._sequence_ends[started] >= hall:
                continue
            # the duty the loop set from it: the preload at the next sequence's end (the
            # loop runs within the period), or, where that ends after the edge, at the
            # entry of the edge's handler: the loop's handler, at the same priority and
            # pended first, has run by then, not by the pins' change (a hunt: 17.6 kHz,
            # each sector's last sample ending 70-118 ticks before its edge, credited with
            # the duty before it, and a loop that moved as k_i x its errors failed)
            later = k + 1
            while later < len(samples) and samples[later][3] == started:
                later += 1
            after = (
                samples[later][4]
                if later < len(samples) and samples[later][0] < hall
                else at_handler
            )
            codes.append(code)
            duties.append(after[channel])
        return SteadySector(index, speed, tuple(codes), tuple(duties))

    def _measure(self, index: int) -> Commutation | str:
        """The commutation of Hall edge `index`, or why it cannot be compared."""
        hall, sector, compares, arr = self.edges[index]
        following = self.edges[index + 1][0]
        own = edge_coms(self.com_ticks, self.com_ccers, hall, following)
        if own is None:
            return "no COM event of its own before the next edge"
        first, end_index = own
        start = self.com_ticks[first]
        end_com = None if end_index is None else self.com_ticks[end_index]
        if first + 1 >= len(self.com_ticks):
            return "the run ended within its commutation"
        # the inputs of the last timing published before the edge's handler applied it
        runs = [inputs for _, inputs in self.timing_runs if inputs.get("published", start) < start]
        if not runs:
            return "no timing published before it"
        edge = switching_table().edge_into(sector, "forward")
        periods = self.plant.periods
        full = round(TICK_HZ / self.spec.inverter.pwm_frequency_hz)
        # the period the COM event cuts short (the carrier restarts there): I is the
        # turn-off current's mean over it (the SIL it is compared with is handed the
        # chip's currents, so this sets only the reference; `sim.scenario.pre_edge_state`
        # solves its own start for the last whole period, the loop's mean, instead)
        before = [p for p in periods if p.end <= start]
        if len(before) < PRE_EDGE_PERIODS + 1 or before[-1].end != start:
            return f"fewer than {PRE_EDGE_PERIODS + 1} PWM periods recorded before it"
        phase = (before[-1].end - before[-1].start) / full
        phase = 0.0 if phase >= 1.0 else phase
        # the simulation starts PRE_EDGE_PERIODS whole periods before the cut one
        origin = -PRE_EDGE_PERIODS - (1 if phase > 0.0 else 0)
        if any(p.end - p.start != full for p in before[origin:-1]):
            # the simulation starts from steady whole periods (`sim.scenario`)
            return (
                f"a carrier restart (the previous commutation's end) within the"
                f" {PRE_EDGE_PERIODS} whole PWM periods before it: the commutation fills"
                " its sector at this speed"
            )
        off, nc = edge.turn_off, edge.non_commutating
        current = edge.current_signs[off] * before[-1].currents[off]
        if current <= 0.0:
            return "no turn-off current at the edge"
        zero = next(
            (
                t
                for t, kind, phase in self.plant.events
                if kind == "zero" and phase == off and start <= t < following
            ),
            None,
        )
        sector_ticks = following - start
        physical = min(zero - start if zero is not None else sector_ticks, sector_ticks)
        commanded = end_com - start if end_com is not None else 0
        length = min(max(commanded, physical), sector_ticks)
        sign = edge.current_signs[nc]

        # the periods that end by the next edge: the one its carrier restart cuts (or
        # its pins' change falls in) holds the next commutation's start, which the SIL,
        # whose trace ends with the sector, does not have; kept, it was the PIL's worst
        # and was set against nothing (-55.9 % "0.02 pp" from the SIL's -45.1 %)
        whole = [p for p in periods if p.start >= start and p.end <= following]

        def window_of(ticks: int) -> list[PeriodRecord]:
            """Every period overlapping [start, start + ticks), and the one after, within
            the sector: a period from the next edge on is the next commutation's (a
            commutation whose current reached zero late in its sector had its window run
            into the next one, where the SIL's, which ends with the sector, does not)."""
            inside = [p for p in whole if p.start >= start and p.start < start + ticks]
            if not inside:
                inside = [p for p in periods if p.start >= start][:1]
            later = [p for p in whole if p.start >= inside[-1].end]
            return inside + later[:1]

        def deviations_of(window: list[PeriodRecord]) -> tuple[float, ...]:
            return tuple((sign * p.currents[nc] - current) / current * 100 for p in window)

        window = window_of(length)
        later = [p for p in whole if p.start >= window[-1].end]
        deviations = deviations_of(window)
        extended = deviations_of(window + later[:2])
        worst = max(deviations, key=abs)
        # the port modulates the incoming switch of the last edge through the sector
        steady = previous_edge(edge).modulated_on
        steady_channel = (int(steady[1:]) - 1) // 2 + 1  # T1..T6 -> CH1..CH3
        counts = arr if self.machine.tim1.centre_aligned else arr + 1
        duty = compares[steady_channel - 1] / counts
        speed = next((p.speed_rpm for p in periods if p.end >= start), self.plant.speed_rpm)
        on_channel = (int(edge.modulated_on[1:]) - 1) // 2
        end_tick = end_com if end_com is not None else start
        halves = self.machine.tim1.centre_aligned

        def duties(p: PeriodRecord, channel: int) -> tuple[float, ...]:
            """The channel's duty in force in the period: centre-aligned, in each half
            (the overflow's update event loads what the loop wrote in the first)."""
            if halves:
                return (p.compares[channel] / counts, p.half_compares[channel] / counts)
            return (p.compares[channel] / counts,)

        post = tuple(
            d
            for p in periods
            if end_tick <= p.start < following and p.start <= window[-1].end
            for d in duties(p, on_channel)
        )
        off_channel = (int(edge.modulated_off[1:]) - 1) // 2
        during = self.com_compares[first]
        after = self.com_compares[first + 1][on_channel]
        applied = (during[on_channel], during[off_channel], self.com_tim3_ccr2[first + 1])
        return Commutation(
            window_speed_rpm=window[-1].speed_rpm,
            window_s=(window[-1].end - start) / TICK_HZ,
            index=index,
            hall_tick=hall,
            com_tick=start,
            end_com_tick=end_com,
            sector_to=sector,
            speed_rpm=speed,
            current_a=current,
            main_duty=duty,
            sampled_code=self.sampled_codes[index],
            previous_sampled_code=self.sampled_codes[index - 1] if index > 0 else None,
            start_currents=before[origin].start_currents,
            pre_duties=tuple(d for p in before[origin:] for d in duties(p, steady_channel - 1)),
            duty_halves=bool(halves),
            firmware_inputs=runs[-1],
            applied=applied,
            main_duty_after=after / counts,
            post_duties=post,
            carrier_phase=phase,
            commutation_s=length / TICK_HZ,
            zero_s=None if zero is None else (zero - start) / TICK_HZ,
            period_deviations_pct=deviations,
            deviation_worst_pct=worst,
            extended_deviations_pct=extended,
            physical_period_deviations_pct=deviations_of(window_of(physical)),
            physical_commutation_s=physical / TICK_HZ,
        )


def with_sil(spec: Spec, commutations: list[Commutation]) -> list[Commutation]:
    """Each commutation with the SIL simulation's deviation (the spec's method, the
    generated C core on the host, the switched plant) at the PIL's speed, current I,
    carrier phase and main duty, the core told the current the firmware sampled, and
    the bridge modulated as the port modulates it (`Case.mid_sector_takeover` False)."""
    from dataclasses import replace

    from sim.drive import Drive
    from sim.metrics import acts_like_main_duty
    from sim.runs import simulate
    from sim.sil import core_command, prepare_cores

    method = spec.controller.method
    cores = prepare_cores(spec, (method,))
    core, scale = cores.cores[method], cores.scaling
    per_code = float(scale.amps_per_current_code)
    # the plant's EMF (`Drive.rotating`): with the spec's `flat`, Case's "spec" shape froze
    # the EMFs at the edge while the chip's plant turned them (a 24-pole flat-EMF motor
    # read 9 pp apart at every commutation)
    drive = Drive.from_spec(spec).rotating()
    out = []
    for c in commutations:
        edge = switching_table().edge_into(c.sector_to, "forward")
        case = Case(
            drive,
            edge,
            c.speed_rpm,
            c.current_a,
            "spec",
            c.carrier_phase,
            mid_sector_takeover=False,
            pre_duty=c.pre_duties,
            start_currents=c.start_currents,
            post_duties=c.post_duties or None,
            duty_halves=c.duty_halves,
            tim1_centre=True,
            # the rotor crossed into the sector when the Hall lines changed (hall_tick),
            # the handler's COM event (time 0) comes after it
            emf_lead_s=(c.com_tick - c.hall_tick) / TICK_HZ,
        )
        fw = c.firmware_inputs
        overrides = {
            "hall_period_ticks": fw["period"],
            "bus_voltage_adc": fw["bus_code"],
            "phase_current_adc": fw["current"],
            "main_duty_counts": fw["main_duty"],
        }
        sampled = (fw["current"] - scale.current_offset_code) * per_code
        command = core_command(core, spec, scale, case, sampled, c.main_duty, overrides)
        # the chip's COM-to-COM time: the commutation ticks plus the end handler's
        # latency minus the edge handler's (the SIL's ideal timing has neither)
        if c.end_com_tick is not None:
            command = replace(command, commutation_time_s=(c.end_com_tick - c.com_tick) / TICK_HZ)
        command = replace(command, main_duty=c.main_duty_after)
        if acts_like_main_duty(command) and c.physical_period_deviations_pct:
            # the commanded end is no event in the plant: the window ends one period
            # after the turn-off current's zero, in the PIL as in the SIL
            physical = c.physical_period_deviations_pct
            c = replace(
                c,
                period_deviations_pct=physical,
                deviation_worst_pct=max(physical, key=abs),
                commutation_s=c.physical_commutation_s,
            )
        outputs = command.core_outputs
        run = simulate(case, command, "switched")
        trace = run.trace
        nc = edge.non_commutating
        after = np.flatnonzero(trace.period_ends > 1e-12)
        after = after[np.argsort(trace.period_starts[after])]
        sign = edge.current_signs[nc]
        extended = tuple(
            float((sign * trace.period_currents[k, nc] - c.current_a) / c.current_a * 100)
            for k in after
        )
        out.append(
            replace(
                c,
                sil_worst_pct=run.metrics.deviation_worst_pct,
                sil_period_deviations_pct=run.metrics.period_deviations_pct,
                sil_extended_deviations_pct=extended,
                sil_outputs=(
                    outputs["turn_on_compare"],
                    outputs["turn_off_compare"],
                    outputs["commutation_ticks"],
                ),
            )
        )
    return out


def brake(
    elf: Path, port_source: Path, spec: Spec, setup: BrakingSetup, *, sil: bool = True
) -> BrakingResult:
    """The braking run of `setup`; `port_source` the generated stm32f103_port.c the ELF
    was built from."""
    result = BrakingLoop(elf, port_source, spec, setup).run_braking()
    if sil:
        result.commutations = with_sil(spec, result.commutations)
    return result


#: A braking run that takes this many times the constant-torque estimate of its Hall
#: edges (`braking_edges`) does not reach its stop speed: it ends there, failed
EDGE_BUDGET = 3.0


#: Hall edges of the short version (`make test`): the settling ones and a dozen measured
SHORT_EDGES = SETTLING_EDGES + 12


#: Hall edges a full braking run takes at most: about 2.7 times the paper motor's (558
#: with its own inertia), so `make pil` stays within minutes on any spec; and at least,
#: so that a strong brake on a light rotor still gives commutations to compare (the
#: Maxon's own inertia takes about 160)
BRAKING_EDGES = (150, 1500)


def _braking_torque(spec: Spec, current_a: float) -> float:
    """k_t I (N m): two conducting phases convert 2 E I, E = k_e n per phase."""
    k_t = 2.0 * float(spec.motor.back_emf_constant_v_per_rpm) * 60.0 / (2.0 * math.pi)
    return k_t * current_a


def _deceleration(spec: Spec, current_a: float, inertia_scale: float, rpm: float = 0.0) -> float:
    """The rotor's deceleration (rad/s^2) at `rpm` under the constant braking torque k_t I
    and the spec's viscous friction b w."""
    friction = float(spec.motor.viscous_friction_n_m_s) * rpm * 2.0 * math.pi / 60.0
    inertia = float(spec.motor.rotor_inertia_kg_m2) * inertia_scale
    return (_braking_torque(spec, current_a) + friction) / inertia


#: Below this b w / (k_t I) the friction's closed forms below lose their digits to
#: cancellation: their series to the first order in it is used instead
_FRICTION_SERIES_BELOW = 1e-6


def _speeds(start_rpm: float, stop_rpm: float) -> tuple[float, float]:
    return start_rpm * 2.0 * math.pi / 60.0, stop_rpm * 2.0 * math.pi / 60.0


#: Motor time a full braking run takes at most, seconds: a little above the paper motor's
#: (2.1 s with its own inertia; the emulation with the plant runs about 5 ms of motor
#: time a wall second), so that a slow motor's long sectors do not take `make pil` an hour
BRAKING_MOTOR_S = 2.5


def braking_seconds(
    spec: Spec, start_rpm: float, stop_rpm: float, current_a: float, inertia_scale: float = 1.0
) -> float:
    """About how long braking from `start_rpm` to `stop_rpm` takes at the constant torque
    T = k_t I of `braking_edges` and the spec's viscous friction b w, seconds:
    J dw/dt = -(T + b w), so t = J/b ln((T + b w1)/(T + b w2)), J (w1 - w2)/T without it."""
    torque = _braking_torque(spec, current_a)
    b = float(spec.motor.viscous_friction_n_m_s)
    inertia = float(spec.motor.rotor_inertia_kg_m2) * inertia_scale
    w1, w2 = _speeds(start_rpm, stop_rpm)
    if b == 0.0:
        alpha = _deceleration(spec, current_a, inertia_scale)
        return (w1 - w2) / alpha if alpha > 0 else math.inf
    if torque + b * w2 <= 0.0:
        return math.inf  # no torque, and friction alone never brings w to 0
    return inertia / b * math.log1p(b * (w1 - w2) / (torque + b * w2))


def braking_edges(
    spec: Spec, start_rpm: float, stop_rpm: float, current_a: float, inertia_scale: float = 1.0
) -> float:
    """About how many Hall edges braking from `start_rpm` to `stop_rpm` takes: a constant
    torque T = k_t I (two conducting phases convert 2 E I, E = k_e n per phase) and the
    spec's viscous friction b w against the rotor inertia times `inertia_scale`, losses
    left out (they shorten it). The angle is J times the integral of w dw / (T + b w):
    J/b ((w1 - w2) - T/b ln((T + b w1)/(T + b w2))), J (w1^2 - w2^2) / (2 T) without
    friction. A friction that stops the rotor within a few edges (10 N m s/rad on the
    paper motor's rotor: a twentieth of one) left out, the run's inertia was scaled for
    hundreds, and the rotor stopped before the motor-in-the-loop faults' settling."""
    torque = _braking_torque(spec, current_a)
    b = float(spec.motor.viscous_friction_n_m_s)
    inertia = float(spec.motor.rotor_inertia_kg_m2) * inertia_scale
    w1, w2 = _speeds(start_rpm, stop_rpm)
    edges_per_radian = 6.0 * spec.motor.pole_pairs / (2.0 * math.pi)
    if b == 0.0:
        alpha = _deceleration(spec, current_a, inertia_scale)
        return edges_per_radian * (w1 * w1 - w2 * w2) / (2.0 * alpha) if alpha > 0 else math.inf
    if torque > 0 and b * w1 / torque < _FRICTION_SERIES_BELOW:
        # the series in u = b/T to its first order
        u = b / torque
        squares = (w1 * w1 - w2 * w2) / 2.0 - u * (w1**3 - w2**3) / 3.0
        return edges_per_radian * inertia * squares / torque
    angle = inertia / b * ((w1 - w2) - torque / b * math.log1p(b * (w1 - w2) / (torque + b * w2)))
    return edges_per_radian * angle


#: The share of I_nominal the saturated loop still drives where a braking run that
#: reaches below the hold speed (`held_down_to_rpm`) stops at the latest
HELD_SHARE = 0.5


def held_down_to_rpm(spec: Spec, current_a: float) -> float:
    """The lowest speed at which the loop holds `current_a` on the nominal bus: steady
    braking (1 - D) U_d = 2E - 2RI at the port's largest duty D_max (its sample window,
    `sense_design`), E = k_e n. With D_max = 1 it is E = R I, where only the back-EMF
    drives the current; a D_max well below 1 (an 80 kHz PWM's 0.84) lifts it: below it
    the loop saturates, the current and the torque fall with the speed and the rotor
    slows exponentially (a run to its stop speed under it took over half an hour)."""
    window = sense_design(spec).window
    d_max = window.duty_max_counts / window.period_counts
    bus = float(spec.inverter.bus_voltage_nominal_v)
    r_i = float(spec.motor.phase_resistance_ohm) * current_a
    return ((1.0 - d_max) * bus / 2.0 + r_i) / float(spec.motor.back_emf_constant_v_per_rpm)


def current_gone_rpm(spec: Spec) -> float:
    """The speed below which the loop, saturated at its D_max, drives no braking current
    on the nominal bus: (1 - D_max) U_d = 2E, E = k_e n."""
    window = sense_design(spec).window
    d_max = window.duty_max_counts / window.period_counts
    bus = float(spec.inverter.bus_voltage_nominal_v)
    return (1.0 - d_max) * bus / 2.0 / float(spec.motor.back_emf_constant_v_per_rpm)


def braking_setup(spec: Spec, *, short: bool) -> BrakingSetup:
    """From 92 % of the spec's top speed down to a tenth of it (at least its lowest
    speed) at its nominal braking current, with its own rotor inertia: for the paper
    motor 4600 rpm down to 500 rpm at 5 A (issue 13, scenario 1). Where that would take
    more Hall edges than BRAKING_EDGES allows (a weak motor on a heavy rotor) or fewer (a
    strong brake on a light one), the inertia is scaled to take about the limit: the
    report says so, with how much the speed then changes over a sector. The short
    version stops after SHORT_EDGES Hall edges.

    In braking only the back-EMF drives the current, at most E/R, and the loop's duty
    stops at D_max: below the speed where (1 - D_max) U_d = 2E - 2RI (`held_down_to_rpm`;
    E = R I where D_max = 1) the braking current, and the torque, fall with the speed,
    which the constant-torque estimate leaves out (the rotor then slows exponentially and the run
    would take many times its estimate, or never end where the saturated current falls
    to zero above the stop). So where that speed is above the stop speed, the run stops
    at the latest where the saturated loop still drives HELD_SHARE of the current."""
    top = float(spec.controller.speed_max_rpm)
    low = float(spec.controller.speed_min_rpm)
    current = float(spec.controller.braking_current_nominal_a)
    # within the speed range: a narrow one (4000..4100 rpm) would start below its minimum
    start, stop = max(0.92 * top, 0.5 * (low + top)), max(low, 0.1 * top)
    held_down_to = held_down_to_rpm(spec, current)
    if stop < held_down_to:
        # below the hold speed the saturated loop's current falls linearly to none at
        # `current_gone_rpm`: a stop under that one is never reached (a 310 V servo's
        # 300 rpm, its current gone at 707 rpm, and an 80 kHz motor's 1140 rpm, gone at
        # 1933 rpm, ran to the edge budget and the motor-time limit, over half an hour
        # of emulation). The run brakes on to where HELD_SHARE of the current is left:
        # the paper motor to its 500 rpm (issue 13, scenario 1: 58 % of 5 A left there,
        # 573 commutations, every one within the SIL's point), the 80 kHz motor to 2253.
        gone = current_gone_rpm(spec)
        stop = max(stop, gone + HELD_SHARE * (held_down_to - gone))
        if stop >= start and start > gone:
            # the loop saturates above the start itself (a 246 V motor on a centre-aligned
            # 2.25 kHz PWM, D_max 0.909: a stop of 585 rpm above its 570 rpm start, and
            # every run ended at once; a hunt): to where HELD_SHARE of the current the
            # saturated loop drives at the start is left
            stop = max(low, gone + HELD_SHARE * (start - gone))
    edges = braking_edges(spec, start, stop, current)
    fewest, most = BRAKING_EDGES
    scale = min(max(1.0, fewest / edges), most / edges) if 0 < edges < math.inf else 1.0
    # and within BRAKING_MOTOR_S of motor time (the emulation's cost follows motor time):
    # a slow motor's long sectors take fewer edges then, never fewer than SHORT_EDGES x 2
    seconds = braking_seconds(spec, start, stop, current, scale)
    if 0 < seconds < math.inf and seconds > BRAKING_MOTOR_S:
        floor = 2 * SHORT_EDGES / (edges * scale)
        scale *= max(BRAKING_MOTOR_S / seconds, min(1.0, floor))
    sector = 10.0 / (start * spec.motor.pole_pairs)
    return BrakingSetup(
        start,
        stop,
        current,
        inertia_scale=scale,
        max_edges=SHORT_EDGES if short else None,
        max_seconds=30.0,
        # the first measured commutation and its window, for the figure
        trace_seconds=(SETTLING_EDGES + 3) * sector,
    )


def speed_change_per_sector(spec: Spec, setup: BrakingSetup) -> float:
    """The relative speed change over one sector at the stop speed (the largest of the
    run), at the constant torque and the friction of `braking_edges`."""
    alpha = _deceleration(spec, setup.current_a, setup.inertia_scale, setup.stop_rpm)
    w = setup.stop_rpm * 2.0 * math.pi / 60.0
    return alpha * (2.0 * math.pi / (6.0 * spec.motor.pole_pairs * w)) / w if w > 0 else math.inf


def worst_difference(commutations: list[Commutation]) -> Commutation | None:
    measured = [c for c in commutations if c.difference_pp is not None]
    return max(measured, key=lambda c: abs(c.difference_pp or 0.0), default=None)

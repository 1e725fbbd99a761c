"""The motor of `sim/` driven by the emulated chip's TIM1 outputs.

The six gate signals TIM1 drives (dead time included: `AdvancedTimer.gate_log`, every
change of the outputs at its tick) set the bridge's leg voltages; an undriven output
counts as off, so during a dead time or with the outputs off the body diodes conduct
as `sim.circuit` resolves them. Between two changes the gates are constant and the
winding is advanced by `sim.switched.run_piece`, the switched plant's own exact
piece (closed-form currents, diode zero crossings and floating phases found as
events): no second bridge model, and no fixed step.

The plant is advanced lazily, from its last instant to the tick something needs it
at: an ADC sample instant (the ADC's input callables), the start of a PWM period
(TIM1's `period_listeners`, for the per-period means the deviation is measured on),
or the end of a chunk of emulated time (the runner's, placed at the next Hall
crossing). A question about an instant already passed (an ADC conversion processed
after a later event) is answered by re-running the exact piece from the last
recorded point before it.

Rotor: the electrical angle advances at the mechanical speed times the pole pairs;
the phase EMFs are the spec's waveform (`motor.back_emf_shape`; `flat`, the paper's EMFs frozen
at an edge, as the 120 deg trapezoid they idealise: `Drive.rotating`; placed on the Hall
sectors as `sim.emf` places them, forward rotation) times k_e n. Within a piece the
speed is held (the mechanical time constant is many PWM periods) and the piece is
split at every EMF corner and every Hall sector boundary, so the EMFs are affine in
each piece. After each piece J dw/dt = T_e - T_load - b w with T_e the piece's mean
of sum e_x i_x over w (the power the EMFs convert), the spec's rotor inertia J, the
viscous friction b and an external load torque (a constant or a function of the
time in seconds).

Sensing chain (`codegen/control/sensing.py`): every shunt carries the current that
flows from the negative rail up into the bridge; a DC-link shunt the sum over the
legs at the negative rail of their phase currents, a low-side phase shunt its own
phase current while its leg sits at the negative rail (the lower transistor or
diode conducts). Each channel reads adc.current_offset + adc.current_gain x I,
quantised by the ADC model at the sample instant its trigger gives.
"""

from __future__ import annotations

import bisect
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np

from codegen.spec_model import Spec
from emulation.pil.bus import NotYetKnownError, PilError
from emulation.pil.rcc import TICK_HZ
from emulation.pil.tim1 import AdvancedTimer
from sim.circuit import LegVoltages, resolve_floats
from sim.drive import Drive
from sim.emf import Waveform, rising_zero_deg
from sim.scenario import switching_table
from sim.switched import run_piece
from sim.trace import Event

LoadTorque = float | Callable[[float], float]
#: Degrees: an angle this close to a breakpoint is on it (float residue of a piece).
_ANGLE_SLACK = 1e-9
#: Recorded points kept for questions about the past (a few PWM periods' worth).
_HISTORY = 512


@dataclass(frozen=True)
class Mechanics:
    """The rotor's load: J (kg m^2), viscous friction b (N m s/rad), load torque (N m,
    positive against forward rotation; a constant or a function of the time in s)."""

    inertia_kg_m2: float
    friction_n_m_s: float = 0.0
    load_torque: LoadTorque = 0.0

    @staticmethod
    def of_spec(
        spec: Spec, *, inertia_scale: float = 1.0, load_torque: LoadTorque = 0.0
    ) -> Mechanics:
        return Mechanics(
            float(spec.motor.rotor_inertia_kg_m2) * inertia_scale,
            float(spec.motor.viscous_friction_n_m_s),
            load_torque,
        )

    def load_at(self, seconds: float) -> float:
        return self.load_torque(seconds) if callable(self.load_torque) else self.load_torque


@dataclass(frozen=True)
class PeriodRecord:
    """One PWM period as TIM1 ran it (cut short by an UG), with the plant's means."""

    start: int  # tick
    end: int
    currents: tuple[float, float, float]  # mean phase currents, A
    power: float  # mean sum e_x i_x, W (negative: braking)
    speed_rpm: float  # at its end
    start_currents: tuple[float, float, float]  # the phase currents at its start
    compares: tuple[int, int, int]  # TIM1 CCR1..CCR3 in force from its start
    #: TIM1 CCR1..CCR3 in force from the counter's overflow on: centre-aligned, the
    #: update event in the middle of the period loads what the current loop wrote in
    #: its first half (RM0008 14.3.4, RCR = 0); `compares` where the period has no
    #: overflow (edge-aligned, or cut short before it)
    half_compares: tuple[int, int, int] = (0, 0, 0)


class _Recorder:
    """What `run_piece` reports into: the period's charge and energy, points, events."""

    def __init__(self) -> None:
        self.charge = [0.0, 0.0, 0.0]  # A s, per phase (floats: it is summed every piece)
        self.energy = 0.0
        self.covered = 0.0
        self.events: list[Event] = []
        self.points: list[tuple[float, np.ndarray]] = []

    def point(self, t: float, currents: np.ndarray) -> None:
        self.points.append((t, currents))

    def accumulate(
        self, _period: int, duration: float, charge: Sequence[float], energy: float
    ) -> None:
        self.add_charge(charge)
        self.energy += energy
        self.covered += duration

    def add_charge(self, charge: Sequence[float]) -> None:
        total = self.charge
        total[0] += charge[0]
        total[1] += charge[1]
        total[2] += charge[2]


class _OnePeriod:
    """`run_piece` asks which carrier period a piece is in; the plant keeps its own."""

    @staticmethod
    def period_index(_t: float) -> int:
        return 0


def phase_current_bound(
    start_a: float, span_s: float, volts: float, inductance_h: float, resistance_ohm: float
) -> float:
    """The largest |phase current| `span_s` before or after an instant whose largest is
    `start_a`, whatever the gates do, where `volts` >= U + 2 E_peak (the bus, and the
    EMF's largest magnitude): a conducting phase has L di/dt = u - u_n - e - R i
    (sim/circuit.py `forcing_of`) with u in [0, U] and u_n the conducting phases' mean
    of u - e, so |L di/dt| <= volts + R |i|; a floating phase carries none, and the
    currents are continuous (a phase stops conducting at zero). Hence
    |i| <= (start + K / a) e^(a span) - K / a, K = volts / L, a = R / L, either way in
    time (tests/test_pil_current_bound.py holds it to the switched plant)."""
    rate = volts / inductance_h
    decay = resistance_ohm / inductance_h
    if decay * span_s < 1e-9:
        return start_a + (rate + decay * start_a) * span_s * (1.0 + 1e-6)
    return start_a + (start_a + rate / decay) * math.expm1(decay * span_s)


@dataclass
class _Emf:
    """The phase EMFs over one piece: angle linear in time from (t0, angle0)."""

    plant: MotorPlant
    t0: float
    angle0: float
    rate: float  # electrical deg per second
    amplitude: float  # E = k_e n, V

    def values(self, t: float) -> np.ndarray:
        return np.array(self.floats(t))

    def floats(self, t: float) -> list[float]:
        """`values` as Python floats (asked at every piece and every current sample)."""
        angle = self.angle0 + self.rate * (t - self.t0)
        waveform, zeros, amplitude = self.plant.waveform, self.plant.zeros, self.amplitude
        return [
            amplitude * waveform(angle - zeros[0]),
            amplitude * waveform(angle - zeros[1]),
            amplitude * waveform(angle - zeros[2]),
        ]

    def affine(self, lo: float, hi: float) -> tuple[np.ndarray, np.ndarray]:
        if hi <= lo:
            return self.values(lo), np.zeros(3)
        a, b = lo + 0.25 * (hi - lo), lo + 0.75 * (hi - lo)
        start, end = self.floats(a), self.floats(b)
        width = b - a
        slope = [(end[k] - start[k]) / width for k in range(3)]
        return np.array([start[k] - slope[k] * a for k in range(3)]), np.array(slope)


@dataclass
class MotorPlant:
    """The motor and bridge of `spec` behind `tim1`'s gate signals."""

    spec: Spec
    tim1: AdvancedTimer
    mechanics: Mechanics
    speed_rpm: float
    angle_deg: float = 0.0  # electrical, forward; sector k spans [60 k, 60 k + 60)
    bus_voltage_v: float | None = None  # None: the spec's nominal, a stiff source
    #: seconds after the attach whose every point (t, currents) is kept in `trace`
    trace_seconds: float = 0.0
    drive: Drive = field(init=False)
    periods: list[PeriodRecord] = field(init=False, default_factory=list)
    #: every diode event (a current reaching zero, a floating phase conducting), in ticks
    events: list[tuple[float, str, int]] = field(init=False, default_factory=list)
    #: (s, phase currents) of every piece end within `trace_seconds` of the attach
    trace: list[tuple[float, np.ndarray]] = field(init=False, default_factory=list)
    #: called with the (s, phase currents) points of every piece integrated (the board's
    #: over-current comparator, emulation/pil/comparator.py)
    current_watchers: list[Callable[[list[tuple[float, np.ndarray]]], None]] = field(
        init=False, default_factory=list
    )
    _legs_made: dict[tuple[tuple[bool, ...], float], LegVoltages] = field(
        init=False, default_factory=dict, repr=False
    )

    def __post_init__(self) -> None:
        # the rotor turns the EMFs: the spec's `flat` (frozen at an edge) has no rotating
        # motor but the 120 deg trapezoid it idealises (`Drive.rotating`)
        self.drive = Drive.from_spec(self.spec).rotating()
        if self.bus_voltage_v is None:
            self.bus_voltage_v = self.drive.bus_voltage_v
        self.waveform = Waveform(self.drive.emf_points)
        self._emf_peak = max(abs(v) for _, v in self.drive.emf_points)
        sectors = switching_table().sectors("forward")
        self.zeros = tuple(rising_zero_deg(sectors, p) for p in range(3))
        marks = {60.0 * k for k in range(6)}
        for zero in self.zeros:
            marks.update((zero + corner) % 360.0 for corner in self.waveform.corner_angles())
        self.breakpoints = sorted(round(m, 9) % 360.0 for m in marks)
        if self.tim1.gate_log is None:
            self.tim1.record_gates()
        log = self.tim1.gate_log
        assert log is not None
        self.tick = self.tim1.machine.now
        self.attached = self.tick
        self._trace_end = self.tick + self.trace_seconds * TICK_HZ
        self._log_pos = len(log) - 1
        gates = log[-1][1]
        if any(g is True for g in gates):
            raise PilError(f"the plant is attached with switches on ({gates}): attach it idle")
        self.currents = np.zeros(3)
        self.turns = 0  # whole electrical revolutions, for the unwrapped angle
        self._history: list[tuple[float, np.ndarray]] = [(self.tick / TICK_HZ, self.currents)]
        self._period_start = self.tick
        self._period = _Recorder()
        self._period_currents: tuple[float, float, float] = (0.0, 0.0, 0.0)
        self._period_compares: tuple[int, int, int] = (0, 0, 0)
        self._half_compares: tuple[int, int, int] = (0, 0, 0)
        self.tim1.period_listeners.append(self._period_started)
        self.tim1.half_period_listeners.append(self._half_period)

    # ------------------------------------------------------------------ state
    @property
    def seconds(self) -> float:
        return self.tick / TICK_HZ

    @property
    def omega(self) -> float:
        """Mechanical speed, rad/s."""
        return self.speed_rpm * math.pi / 30.0

    @property
    def electrical_rate(self) -> float:
        """Electrical degrees per second."""
        return self.speed_rpm * 6.0 * self.drive.pole_pairs

    @property
    def sector(self) -> int:
        return int((self.angle_deg + _ANGLE_SLACK) // 60.0) % 6

    def sector_before_edge(self) -> int:
        """The sector the rotor has just left (forward rotation)."""
        return (self.sector - 1) % 6

    @property
    def hall_code(self) -> int:
        return self.spec.hall.sequence[self.sector]

    def next_sector_tick(self) -> int | None:
        """The tick at which the rotor reaches the next Hall sector at today's speed
        (rounded up), or None when it stands still."""
        rate = self.electrical_rate
        if rate <= 0.0:
            return None
        boundary = (math.floor((self.angle_deg + _ANGLE_SLACK) / 60.0) + 1) * 60.0
        ticks = (boundary - self.angle_deg) / rate * TICK_HZ
        # a rotor that viscous friction has all but stopped (its speed decays towards a
        # subnormal float) never gets there: the ticks overflowed to infinity
        if not math.isfinite(ticks):
            return None
        return self.tick + max(1, math.ceil(ticks))

    def gates_at(self, tick: int) -> tuple[bool, ...]:
        """The six gates in force at `tick` (which must be recorded): True where on."""
        log = self.tim1.gate_log
        assert log is not None
        if log[-1][0] <= tick:  # the gates in force now: the sensing's usual question
            return tuple(g is True for g in log[-1][1])
        index = bisect.bisect_right(log, tick, key=lambda entry: entry[0]) - 1
        return tuple(g is True for g in log[max(index, 0)][1])

    # ------------------------------------------------------------------ sensing
    def shunt_currents(self, tick: int) -> tuple[float, float, float, float]:
        """(DC link, low-side A, B, C) at `tick`: the current from the negative rail up
        into the bridge through each."""
        currents = self.currents_at(tick).tolist()
        legs = self._legs(self.gates_at(tick))
        positive, negative, _ = legs.floats
        conducting, voltages = resolve_floats(
            positive, negative, currents, self._emf().floats(tick / TICK_HZ)
        )
        phase = [currents[k] if conducting[k] and voltages[k] == 0.0 else 0.0 for k in range(3)]
        # sum() adds as numpy's sum of three did: from 0, left to right
        return sum(phase), phase[0], phase[1], phase[2]

    def current_bound(self, lo: int, hi: int) -> float:
        """The largest |phase current| the motor can carry at any tick in [lo, hi],
        whatever the gates do meanwhile (`phase_current_bound` from the latest point
        recorded: the currents at a piece's end, also while `_integrate` is between
        pieces and the plant's tick not yet moved), the bus and the EMF's peak with a
        margin of a half: a bus or a speed that moves within the span (the scenarios'
        bus steps are 10 % over the spec's maximum)."""
        assert self.bus_voltage_v is not None
        volts = 1.5 * (self.bus_voltage_v + 2.0 * self._emf_peak * self._amplitude())
        at, currents = self._history[-1]
        return phase_current_bound(
            max(abs(c) for c in currents.tolist()),
            max(abs(lo / TICK_HZ - at), abs(hi / TICK_HZ - at)),
            volts,
            self.drive.inductance_h,
            self.drive.resistance_ohm,
        )

    def currents_at(self, tick: int) -> np.ndarray:
        """The phase currents at `tick`: advanced to it, or re-run from the last point
        recorded before it when the plant is already past it."""
        if tick >= self.tick:
            self.advance(tick)
            return self.currents.copy()
        t = tick / TICK_HZ
        index = bisect.bisect_right(self._history, t, key=lambda entry: entry[0]) - 1
        if index < 0 and tick < self.attached:
            return np.zeros(3)  # before the motor was attached: no current
        if index < 0:
            raise PilError(
                f"the plant no longer holds tick {tick} (history from {self._history[0][0]} s)"
            )
        start, currents = self._history[index]
        if start >= t:
            return currents.copy()
        start_tick = math.floor(start * TICK_HZ + 1e-6)
        gates = self.gates_at(start_tick)
        emf = self._emf_from(start)
        return run_piece(
            self.drive, emf, _OnePeriod(), self._legs(gates), start, t, currents, _Recorder()
        )

    # ------------------------------------------------------------------ advancing
    def advance(self, tick: int) -> None:
        """Integrate from the plant's tick to `tick`, the gates as TIM1 drove them."""
        if tick <= self.tick:
            return
        if self.tim1.machine.looking_ahead:
            # a look ahead (the ADC's watchdog) must not move the motor past events
            # the chip has not processed yet (a PWM period's start): it asks again then
            raise NotYetKnownError(f"the plant is at {self.tick}, asked ahead to {tick}")
        if tick > self.tim1.machine.now:
            raise NotYetKnownError(
                f"the plant asked to run to {tick}, ahead of the chip ({self.tim1.machine.now})"
            )
        self.tim1._flush(tick)
        log = self.tim1.gate_log
        assert log is not None
        while self.tick < tick:
            while self._log_pos + 1 < len(log) and log[self._log_pos + 1][0] <= self.tick:
                self._log_pos += 1
            upcoming = log[self._log_pos + 1][0] if self._log_pos + 1 < len(log) else tick
            end = min(tick, upcoming)
            self._integrate(end, tuple(g is True for g in log[self._log_pos][1]))
            self.tick = end

    def _legs(self, gates: tuple[bool, ...]) -> LegVoltages:
        """The legs' voltages under `gates` at the bus voltage in force (kept per gate
        state and bus voltage: the plant asks at every piece and every sample)."""
        assert self.bus_voltage_v is not None
        key = (gates, self.bus_voltage_v)
        legs = self._legs_made.get(key)
        if legs is None:
            duties = tuple(1.0 if g else 0.0 for g in gates)
            legs = self._legs_made[key] = LegVoltages.from_duties(duties, self.bus_voltage_v)
        return legs

    def _emf(self) -> _Emf:
        """The EMF from the plant's instant on (and back: affine in time at its speed)."""
        return _Emf(self, self.seconds, self.angle_deg, self.electrical_rate, self._amplitude())

    def _emf_from(self, start: float) -> _Emf:
        """The EMF over a past piece from `start`: the angle there, from today's by the
        speed (the speed changes by parts per million within a few PWM periods)."""
        angle = self.angle_deg - self.electrical_rate * (self.seconds - start)
        return _Emf(self, start, angle, self.electrical_rate, self._amplitude())

    def _amplitude(self) -> float:
        return self.drive.emf_v(self.speed_rpm)

    def _next_breakpoint(self) -> float:
        """Degrees from the angle to the next breakpoint (a corner or a sector edge)."""
        within = self.angle_deg % 360.0
        index = bisect.bisect_right(self.breakpoints, within + _ANGLE_SLACK)
        target = (
            self.breakpoints[index]
            if index < len(self.breakpoints)
            else 360.0 + self.breakpoints[0]
        )
        return target - within

    def _integrate(self, end_tick: int, gates: tuple[bool, ...]) -> None:
        legs = self._legs(gates)
        t, end = self.seconds, end_tick / TICK_HZ
        while t < end:
            rate = self.electrical_rate
            ahead = self._next_breakpoint()
            hi = end if rate <= 0.0 else min(end, t + ahead / rate)
            reaches = rate > 0.0 and hi < end
            emf = _Emf(self, t, self.angle_deg, rate, self._amplitude())
            recorder = _Recorder()
            self.currents = run_piece(
                self.drive, emf, _OnePeriod(), legs, t, hi, self.currents, recorder
            )
            for event in recorder.events:
                self.events.append((event.time * TICK_HZ, event.kind, event.phase))
            for point in recorder.points:
                self._history.append(point)
            for watcher in self.current_watchers:
                watcher(recorder.points)
            if recorder.points and recorder.points[0][0] * TICK_HZ < self._trace_end:
                self.trace.extend(recorder.points)
            if len(self._history) > 2 * _HISTORY:
                del self._history[:_HISTORY]
            self._period.add_charge(recorder.charge)
            self._period.energy += recorder.energy
            self._period.covered += recorder.covered
            step = hi - t
            if reaches:
                self.angle_deg += ahead  # exactly on the breakpoint
            else:
                self.angle_deg += rate * step
            if self.angle_deg >= 360.0 - _ANGLE_SLACK:
                self.angle_deg -= 360.0
                self.turns += 1
            self._mechanics(recorder.energy, step, t)
            t = hi

    def _mechanics(self, energy: float, step: float, t: float) -> None:
        if step <= 0.0:
            return
        omega = self.omega
        torque = energy / step / omega if omega > 0.0 else 0.0
        m = self.mechanics
        accel = (torque - m.load_at(t) - m.friction_n_m_s * omega) / m.inertia_kg_m2
        self.speed_rpm = max(0.0, omega + accel * step) * 30.0 / math.pi

    # ------------------------------------------------------------------ PWM periods
    def _period_started(self, tick: int) -> None:
        if tick < self.tick:
            raise PilError(f"a PWM period started at {tick}, behind the plant ({self.tick})")
        self.advance(tick)
        length = (tick - self._period_start) / TICK_HZ
        if length > 0.0:
            record = self._period
            self.periods.append(
                PeriodRecord(
                    self._period_start,
                    tick,
                    tuple(v / length for v in record.charge),  # type: ignore[arg-type]
                    record.energy / length,
                    self.speed_rpm,
                    self._period_currents,
                    self._period_compares,
                    self._half_compares,
                )
            )
        self._period_start = tick
        self._period = _Recorder()
        self._period_currents = tuple(float(v) for v in self.currents)  # type: ignore[assignment]
        self._period_compares = tuple(self.tim1.ccr[1:4])  # type: ignore[assignment]
        self._half_compares = self._period_compares

    def _half_period(self, _tick: int) -> None:
        """A centre-aligned counter's overflow: the compare values in force from it on."""
        self._half_compares = tuple(self.tim1.ccr[1:4])  # type: ignore[assignment]

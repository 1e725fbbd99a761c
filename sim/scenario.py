"""One commutation: the edge, the operating point, the gate schedule around it.

Time 0 is the Hall edge. The run starts a few carrier periods earlier in the previous
sector's second half, where PWM-OFF-PWM modulates the transistor that the edge turns
off (T3 before the paper's 60 deg edge) at the duty that holds the braking current.
After the commutation the turn-on transistor runs at the main duty until the middle
of the sector, then the transistor that the next edge will turn off takes over: each
transistor is modulated in the first and last 30 deg of its 120 deg conduction and
off in between, which is what keeps the inactive phase free of current.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from functools import lru_cache
from typing import Literal

import numpy as np

from codegen.derivation import derive
from codegen.derivation.switching import Edge, SwitchingTable
from sim.command import Command
from sim.drive import Drive
from sim.emf import BackEmf, EmfShape, Waveform
from sim.schedule import OFF, Schedule, Segment, switch_index
from sim.trace import Trace

#: "averaged" is solved exactly (`simulate_averaged_exact`); "averaged_cvodes" is the
#: same model integrated by casadi CVODES (`sim.averaged`), the cross-check.
PlantModel = Literal["switched", "averaged", "averaged_cvodes"]
#: Carrier periods simulated before the edge (the last one gives the measured current).
PRE_EDGE_PERIODS = 2


@lru_cache(maxsize=1)
def switching_table() -> SwitchingTable:
    return derive().switching


def paper_edge() -> Edge:
    """Section 3.2's example: 60 deg, forward, BA -> CA (T3 off, T5 modulated)."""
    return switching_table().paper_example()


def next_edge(edge: Edge) -> Edge:
    step = 1 if edge.direction == "forward" else -1
    return switching_table().edge_into((edge.sector_to + step) % 6, edge.direction)


def previous_edge(edge: Edge) -> Edge:
    step = 1 if edge.direction == "forward" else -1
    return switching_table().edge_into((edge.sector_to - step) % 6, edge.direction)


@dataclass(frozen=True)
class Case:
    drive: Drive
    edge: Edge
    speed_rpm: float
    current_a: float
    emf_shape: EmfShape
    #: Fraction of a carrier period that had run when the Hall edge came: the port's
    #: update event at the edge restarts the carrier there (0: the edge falls on a
    #: carrier boundary and the restart changes nothing).
    carrier_phase: float = 0.0
    #: The port ends the commutation with COM + update (EGR.COMG | EGR.UG): the
    #: carrier restarts at the commutation end. False: COM only, so the new enables
    #: apply at once and the turn-on compare value at the next carrier boundary.
    end_restarts_carrier: bool = True
    #: PWM-OFF-PWM as the paper modulates (True): the transistor the next edge turns off
    #: takes over at the middle of the sector, and it is the one modulated before the
    #: edge. False: as the STM32 port modulates, the incoming switch of the last edge
    #: runs at the main duty through the whole sector (it is the one modulated before
    #: the edge, and the turn-on switch runs to the end of the run after the commutation).
    mid_sector_takeover: bool = True
    #: The modulated switch's duty before the edge; None: the steady duty that holds I
    #: (`Drive.steady_duty`). The emulated drive's comparison gives its loop's duty in
    #: force in each carrier period from the run's start (the last: the period the
    #: edge cuts short).
    pre_duty: float | tuple[float, ...] | None = None
    #: The phase currents at `start_time`; None: two phases at the magnitude that makes
    #: the last pre-edge period's turn-off current average I (`pre_edge_state`). The
    #: emulated drive's comparison gives the chip's, which carry what the port's
    #: modulation lets the inactive phase's diode conduct before the edge.
    start_currents: tuple[float, float, float] | None = None
    #: The turn-on switch's duty in each carrier period from the commutation end on
    #: (the last holds); None: the command's main duty throughout. The emulated drive's
    #: comparison gives its current loop's, which acts from the commutation end on.
    post_duties: tuple[float, ...] | None = None
    #: Centre-aligned PWM as TIM1 runs it in the port (`Schedule.on_at_boundaries`).
    tim1_centre: bool = False
    #: `pre_duty` (a tuple) and `post_duties` give two duties a carrier period, its
    #: first half's and its second's: centre-aligned TIM1 loads the preloaded compare
    #: values at the overflow in the middle of a period as well (RCR = 0), so the
    #: emulated drive's loop, writing in a first half, changes the second.
    duty_halves: bool = False
    #: How long before t = 0 the rotor passed the edge's angle (`BackEmf.lead_s`): the
    #: emulated drive's Hall-lines-to-COM-event delay; 0 in the simulation's own studies.
    emf_lead_s: float = 0.0

    @property
    def sector_time_s(self) -> float:
        return self.drive.sector_time_s(self.speed_rpm)

    @property
    def emf(self) -> BackEmf:
        # BackEmf negates the forward trapezoid itself for reverse rotation (paper 2.2),
        # so it takes the forward sectors in both directions.
        frozen = self.emf_shape == "flat" or self.drive.emf_frozen
        return BackEmf(
            "flat" if frozen else "spec",
            self.edge,
            switching_table().sectors("forward"),
            self.drive.emf_v(self.speed_rpm),
            self.sector_time_s,
            Waveform(self.drive.emf_points),
            self.emf_lead_s,
        )

    @property
    def pre_edge_duty(self) -> float:
        """The duty of the last pre-edge period."""
        if isinstance(self.pre_duty, tuple):
            return self.pre_duty[-1]
        if self.pre_duty is not None:
            return self.pre_duty
        return self.drive.steady_duty(self.speed_rpm, self.current_a)

    @property
    def start_time(self) -> float:
        return -(PRE_EDGE_PERIODS + self.carrier_phase) * self.drive.pwm_period_s

    def roles(self) -> tuple[int, int, int]:
        return self.edge.non_commutating, self.edge.turn_off, self.edge.turn_on

    def edge_currents(self, magnitude: float) -> np.ndarray:
        """Currents of the conduction before the edge: nc and off carry +-magnitude."""
        signs = self.edge.current_signs
        out = np.zeros(3)
        out[self.edge.non_commutating] = signs[self.edge.non_commutating] * magnitude
        out[self.edge.turn_off] = signs[self.edge.turn_off] * magnitude
        return out


def schedule_for(case: Case, command: Command | None, end: float) -> Schedule:
    """Gate duties from the run's start to `end`; `command` None: pre-edge only."""
    period = case.drive.pwm_period_s
    pre_switch = switch_index(
        case.edge.modulated_off
        if case.mid_sector_takeover
        else previous_edge(case.edge).modulated_on
    )
    if isinstance(case.pre_duty, tuple):
        step = 0.5 * period if case.duty_halves else period
        bounds = [min(case.start_time + k * step, 0.0) for k in range(len(case.pre_duty))]
        segments = [
            Segment(lo, hi, _only({pre_switch: duty}))
            for lo, hi, duty in zip(bounds, [*bounds[1:], 0.0], case.pre_duty, strict=True)
            if hi > lo
        ]
    else:
        segments = [Segment(case.start_time, 0.0, _only({pre_switch: case.pre_edge_duty}))]
    restarts = [0.0]
    if case.carrier_phase > 0.0:
        restarts.insert(0, -case.carrier_phase * period)
    if command is not None and end > 0.0:
        segments.extend(_after_edge(case, command, period, end))
        # The port's commutation end is a COM event with an update: the carrier restarts.
        t_com = command.commutation_time_s
        if case.end_restarts_carrier and command.turn_on_switch is not None and 0.0 < t_com < end:
            restarts.append(t_com)
    return Schedule(
        tuple(segments), period, case.drive.pwm_alignment, tuple(restarts), case.tim1_centre
    )


def _after_edge(case: Case, command: Command, period: float, end: float) -> list[Segment]:
    if command.turn_on_switch is None or command.turn_off_switch is None:
        return [Segment(0.0, end, OFF)]
    on, off = command.turn_on_switch, command.turn_off_switch
    t_com = min(max(command.commutation_time_s, 0.0), end)
    out: list[Segment] = []
    if command.constant_duties:
        if t_com > 0.0:
            out.append(
                Segment(0.0, t_com, _only({on: command.on_duty(0), off: command.off_duty(0)}))
            )
    else:
        k = 0
        while k * period < t_com:
            duties = _only({on: command.on_duty(k), off: command.off_duty(k)})
            out.append(Segment(k * period, min((k + 1) * period, t_com), duties))
            k += 1
    main_from = t_com
    if not case.end_restarts_carrier and t_com > 0.0:
        # Preloaded CCRx: the turn-on transistor keeps its commutation compare value
        # until the next update; the turn-off transistor's enable drops at once.
        main_from = min(math.ceil(t_com / period - 1e-9) * period, end)
        if main_from > t_com:
            last = math.ceil(t_com / period - 1e-9) - 1
            out.append(Segment(t_com, main_from, _only({on: command.on_duty(last)})))
    middle = max(0.5 * case.sector_time_s, main_from) if case.mid_sector_takeover else end
    if case.post_duties and main_from < min(middle, end):
        # the current loop's duties as the chip ran them, one per carrier period
        step = 0.5 * period if case.duty_halves else period
        k = 0
        while main_from + k * step < min(middle, end):
            duty = case.post_duties[min(k, len(case.post_duties) - 1)]
            hi = min(main_from + (k + 1) * step, middle, end)
            out.append(Segment(main_from + k * step, hi, _only({on: duty})))
            k += 1
    elif main_from < min(middle, end):
        out.append(Segment(main_from, min(middle, end), _only({on: command.main_duty})))
    if middle < end:
        takeover = switch_index(next_edge(case.edge).modulated_off)
        out.append(Segment(middle, end, _only({takeover: command.main_duty})))
    return out


def _only(duties: dict[int, float]) -> tuple[float, ...]:
    out = list(OFF)
    for switch, duty in duties.items():
        out[switch] = min(max(duty, 0.0), 1.0)
    return tuple(out)


Plant = Callable[[Drive, BackEmf, Schedule, float, float, np.ndarray], Trace]


def plant(model: PlantModel) -> Plant:
    if model == "switched":
        from sim.switched import simulate_switched

        return simulate_switched
    if model == "averaged":
        from sim.switched import simulate_averaged_exact

        return simulate_averaged_exact
    from sim.averaged import simulate_averaged

    return simulate_averaged


def pre_edge_state(case: Case, model: PlantModel) -> np.ndarray:
    """Currents at the run's start such that the last whole pre-edge period averages I.

    The averaged plant holds I exactly. The switched plant's ripple makes the
    instantaneous value at a carrier start differ from the period average, so the
    start value is solved for: the period average is affine in it (linear circuit).
    A whole period, not the one the edge's carrier restart cuts short: the current loop
    holds I as a whole period's mean, and the edge at carrier phase p finds the current
    where the steady ripple is p into its period (at a small p just past the valley,
    not at I, which the cut period's mean had made it: a step of the ripple's half
    height between phase 0 and phase 0+).
    """
    if case.start_currents is not None:
        return np.array(case.start_currents, dtype=float)
    magnitude = case.current_a
    if model != "switched":
        return case.edge_currents(magnitude)
    return case.edge_currents(_switched_start_magnitude(case))


@lru_cache(maxsize=256)
def _switched_start_magnitude(case: Case) -> float:
    """`pre_edge_state`'s solve on the switched plant. It depends on the case alone, not
    on the command: every method at one edge, and both runs of `sim.runs.simulate`,
    share it."""
    magnitude = case.current_a
    run = plant("switched")
    schedule = schedule_for(case, None, 0.0)
    off = case.edge.turn_off
    sign = case.edge.current_signs[off]
    period = case.drive.pwm_period_s

    def last_mean(start_magnitude: float) -> float:
        trace = run(
            case.drive,
            case.emf,
            schedule,
            case.start_time,
            0.0,
            case.edge_currents(start_magnitude),
        )
        whole = np.flatnonzero(
            np.abs(trace.period_ends - trace.period_starts - period) < 1e-9 * period
        )
        return sign * float(trace.period_currents[whole[-1], off])

    low, high = last_mean(magnitude), last_mean(magnitude + 1.0)
    gain = high - low
    return magnitude + (magnitude - low) / gain if gain > 1e-9 else magnitude


def run_case(case: Case, command: Command, model: PlantModel, end: float) -> Trace:
    """Simulate from the pre-edge start to `end` under `command`."""
    schedule = schedule_for(case, command, end)
    return plant(model)(
        case.drive, case.emf, schedule, case.start_time, end, pre_edge_state(case, model)
    )

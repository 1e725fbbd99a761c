"""Render context of the thin STM32F103 port around the pure commutation core.

The port only reads peripherals, calls bldc_commutate() and writes registers; every
number it needs (prescalers, reload values, the dead-time code) is computed here from
the spec and printed with its physical meaning, so the templates only lay them out.

Timer resources (STM32F103 default pin mapping, no AFIO remap; datasheet DS5319
Table 5):
  TIM1  CH1..CH3  PA8, PA9, PA10   upper switches T1, T3, T5 (phases A, B, C)
        CH1N..3N  PB13, PB14, PB15 lower switches T2, T4, T6
  TIM3  CH1..CH3  PA6, PA7, PB0    Hall A, B, C (code bits 2, 1, 0), Hall-sensor mode
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction

from codegen.core.hall import edge_index, edge_of_hall_pair
from codegen.derivation import derive
from codegen.render import provenance, render
from codegen.spec_model import Spec, uses_main_duty
from codegen.svd import REGS_HEADER, render_regs_header

PORT_HEADER_TEMPLATE = "c/stm32f103_port.h.j2"
PORT_SOURCE_TEMPLATE = "c/stm32f103_port.c.j2"
PORT_HEADER = "stm32f103_port.h"
PORT_SOURCE = "stm32f103_port.c"
CORE_HEADER = "bldc_commutation.h"

#: RM0008 TIMx_CR1.CMS: 00 edge-aligned; 01 centre-aligned mode 1 (the counter counts
#: up and down; the mode number only chooses when compare flags are set, unused here).
CMS_EDGE = 0
CMS_CENTER_1 = 1

#: RM0008 TIMx_CCMR1.IC1F = 0011: f_SAMPLING = f_CK_INT, N = 8 consecutive equal samples.
HALL_FILTER_IC1F = 0b0011
HALL_FILTER_SAMPLES = 8

#: RM0008 TIMx_BDTR.DTG: the largest dead time, in t_DTS, of the last range
#: (DTG[7:5] = 111: (32 + 31) x 16).
DTG_MAX_TICKS = 1008


@dataclass(frozen=True)
class Pin:
    port: str  # "GPIOA"
    number: int
    signal: str  # alternate function, e.g. "TIM1_CH1N"
    role: str


OUTPUT_PINS: tuple[Pin, ...] = (
    Pin("GPIOA", 8, "TIM1_CH1", "T1, phase A upper"),
    Pin("GPIOA", 9, "TIM1_CH2", "T3, phase B upper"),
    Pin("GPIOA", 10, "TIM1_CH3", "T5, phase C upper"),
    Pin("GPIOB", 13, "TIM1_CH1N", "T2, phase A lower"),
    Pin("GPIOB", 14, "TIM1_CH2N", "T4, phase B lower"),
    Pin("GPIOB", 15, "TIM1_CH3N", "T6, phase C lower"),
)

#: Hall inputs in code-bit order A, B, C = bits 2, 1, 0 (core contract).
HALL_PINS: tuple[Pin, ...] = (
    Pin("GPIOA", 6, "TIM3_CH1", "Hall A, code bit 2"),
    Pin("GPIOA", 7, "TIM3_CH2", "Hall B, code bit 1"),
    Pin("GPIOB", 0, "TIM3_CH3", "Hall C, code bit 0"),
)


@dataclass(frozen=True)
class DeadTime:
    """A dead time as TIM1 programs it: the BDTR.DTG code and what it really gives."""

    dtg: int
    dts_ticks: int  # dead time in t_DTS (= t_CK_INT with CKD = 00)
    requested_s: Fraction
    programmed_s: Fraction


def dtg_dead_time_ticks(dtg: int) -> int:
    """Dead time of a BDTR.DTG code in t_DTS, RM0008 TIMx_BDTR bits 7:0:

    DTG[7:5] = 0xx: DT = DTG[7:0] x t_DTS              0 .. 127
    DTG[7:5] = 10x: DT = (64 + DTG[5:0]) x 2 t_DTS   128 .. 254, step 2
    DTG[7:5] = 110: DT = (32 + DTG[4:0]) x 8 t_DTS   256 .. 504, step 8
    DTG[7:5] = 111: DT = (32 + DTG[4:0]) x 16 t_DTS  512 .. 1008, step 16
    """
    if not 0 <= dtg <= 0xFF:
        raise ValueError(f"DTG is an 8-bit field, got {dtg}")
    if dtg >> 7 == 0:
        return dtg
    if dtg >> 6 == 0b10:
        return (64 + (dtg & 0x3F)) * 2
    if dtg >> 5 == 0b110:
        return (32 + (dtg & 0x1F)) * 8
    return (32 + (dtg & 0x1F)) * 16


def encode_dead_time(dead_time_s: Fraction, timer_clock_hz: Fraction) -> DeadTime:
    """The DTG code of the shortest encodable dead time not shorter than requested.

    Rounds up, never down: a shorter dead time than the spec asks for risks
    shoot-through. t_DTS = t_CK_INT (CR1.CKD = 00), so at 72 MHz the step is 13.9 ns
    and the longest dead time 1008 t_DTS = 14 us. Raises ValueError past that.
    """
    if dead_time_s < 0:
        raise ValueError(f"dead time must not be negative, got {_time(dead_time_s)}")
    wanted = Fraction(dead_time_s) * Fraction(timer_clock_hz)
    if wanted > DTG_MAX_TICKS:
        longest = Fraction(DTG_MAX_TICKS) / Fraction(timer_clock_hz)
        raise ValueError(
            f"dead time {_time(dead_time_s)} is {float(wanted):.1f} TIM1 clocks at"
            f" {_freq(timer_clock_hz)}: not representable in TIM1_BDTR.DTG, whose longest"
            f" dead time is {DTG_MAX_TICKS} t_DTS = {_time(longest)} (RM0008 DTG encoding,"
            " t_DTS = t_CK_INT with CKD = 00); shorten inverter.dead_time or lower"
            " inverter.timer_clock"
        )
    best = min(
        (code for code in range(256) if dtg_dead_time_ticks(code) >= wanted),
        key=lambda code: (dtg_dead_time_ticks(code), code),
    )
    ticks = dtg_dead_time_ticks(best)
    return DeadTime(
        dtg=best,
        dts_ticks=ticks,
        requested_s=Fraction(dead_time_s),
        programmed_s=Fraction(ticks) / Fraction(timer_clock_hz),
    )


def _freq(hz: Fraction) -> str:
    value = float(hz)
    for scale, unit in ((1e6, "MHz"), (1e3, "kHz")):
        if value >= scale:
            return f"{value / scale:g} {unit}"
    return f"{value:g} Hz"


def _time(seconds: Fraction) -> str:
    value = float(seconds)
    if value == 0:
        return "0 s"
    for scale, unit in ((1e-9, "ns"), (1e-6, "us"), (1e-3, "ms")):
        if abs(value) < scale * 1000:
            return f"{value / scale:.4g} {unit}"
    return f"{value:.4g} s"


def _define(name: str, value: str, comment: str) -> dict[str, str]:
    return {"name": name, "value": value, "comment": comment}


def _pin(p: Pin, code_bit: int | None = None) -> dict[str, str]:
    return {
        "port": p.port,
        "name": f"P{p.port[-1]}{p.number}",
        "cr": "CRL" if p.number < 8 else "CRH",
        "n": str(p.number),
        "signal": p.signal,
        "role": p.role,
        "code_bit": "" if code_bit is None else f"{code_bit:#x}u",
    }


def _switch_registers(switch: str) -> tuple[str, str, str]:
    """T1..T6 -> (its CCER enable bit, its partner's, its compare register)."""
    index = int(switch[1:]) - 1
    channel = index // 2 + 1
    own = f"TIM_CCER_CC{channel}{'N' if index % 2 else ''}E"
    partner = f"TIM_CCER_CC{channel}{'' if index % 2 else 'N'}E"
    return own, partner, f"CCR{channel}"


def hall_code_of_pins(raw: int) -> int:
    """Pin levels as read (HALL_PINS[i] in bit i) -> Hall code (A B C as bits 2 1 0)."""
    return sum(((raw >> i) & 1) << (2 - i) for i in range(3))


def _edge_context(spec: Spec) -> dict[str, object]:
    """The port's per-edge register table, in the core's edge numbering, and the Hall
    pin decoding."""
    switching = derive().switching
    edges = []
    for direction in ("forward", "reverse"):
        for sector in range(6):
            edge = switching.edge_into(sector, direction)
            on, on_partner, on_ccr = _switch_registers(edge.modulated_on)
            off, off_partner, off_ccr = _switch_registers(edge.modulated_off)
            edges.append(
                {
                    "index": edge_index(direction, sector),
                    "ccer_during": f"{on} | {off}",
                    "forbidden": f"{on_partner} | {off_partner}",
                    "ccer_after": on,
                    "on_ccr": on_ccr,
                    "off_ccr": off_ccr,
                    "comment": f"{direction} into sector {sector}: {edge.modulated_on} on,"
                    f" {edge.modulated_off} off",
                }
            )
    a, b, c = HALL_PINS
    if not (a.port == b.port and b.number == a.number + 1 and c.port != a.port):
        raise ValueError("the Hall pin read expects two neighbouring pins and one on another port")
    core_edges = edge_of_hall_pair(spec.hall.sequence)
    edge_of_pins = []
    for index in range(64):
        previous, now = hall_code_of_pins(index >> 3), hall_code_of_pins(index & 7)
        edge = core_edges[(previous << 3) | now]
        what = "invalid" if edge >= len(edges) else f"edge {edge}"
        edge_of_pins.append(
            {
                "value": edge,
                "comment": f"pins {index >> 3:03b} -> {index & 7:03b}: Hall {previous:03b} -> {now:03b}, {what}",
            }
        )
    return {
        # The improved rule (Eq. 18) does not use the main duty for the commutation.
        "method": spec.controller.method,
        "uses_main_duty": uses_main_duty(spec.controller.method),
        "port_edges": edges,
        "edge_of_pins": edge_of_pins,
        "pins_expression": f"(({a.port}->IDR >> {a.number}) & 3u) | (({c.port}->IDR >> {c.number} & 1u) << 2)",
        "pins_expression_text": f"P{a.port[-1]}{a.number} | P{b.port[-1]}{b.number} << 1 |"
        f" P{c.port[-1]}{c.number} << 2",
    }


def port_context(
    spec: Spec, *, hall_timer_input_clock_hz: Fraction | None = None
) -> dict[str, object]:
    """Numbers of the STM32F103 port for this spec, printed for the templates.

    hall_timer_input_clock_hz is TIM3's input clock (TIMxCLK on APB1). The spec only
    gives TIM1's; with the usual 72 MHz clock tree (APB1 = HCLK/2, which RM0008 7.2
    doubles back for the timers) both are equal, which is the default.
    """
    inv = spec.inverter
    clk = inv.timer_clock_hz
    # load_spec guarantees a whole number of counts in [256, 65536] per period, so
    # TIM1 runs unprescaled: the finest duty resolution the spec allows.
    tim1_psc = 0
    if inv.pwm_alignment == "edge":
        period = clk / inv.pwm_frequency_hz
        tim1_arr = int(period) - 1
        full_scale = tim1_arr + 1
        cms = CMS_EDGE
        align_text = "edge-aligned"
        full_scale_why = "ARR + 1: PWM mode 1 upcounting is active while CNT < CCRx"
    else:
        period = clk / inv.pwm_frequency_hz / 2
        tim1_arr = int(period)
        full_scale = tim1_arr
        cms = CMS_CENTER_1
        align_text = "centre-aligned"
        full_scale_why = "ARR: centre-aligned PWM mode 1 is active for CNT < CCRx up, <= CCRx down"
    if tim1_arr > 0xFFFF:
        raise ValueError(
            f"TIM1 needs ARR = {tim1_arr} for {_freq(inv.pwm_frequency_hz)} {align_text} at"
            f" {_freq(clk)}, beyond the 16-bit auto-reload register"
        )
    dead = encode_dead_time(inv.dead_time_s, clk)

    hall_in = clk if hall_timer_input_clock_hz is None else Fraction(hall_timer_input_clock_hz)
    hall_ratio = hall_in / spec.hall.timer_clock_hz
    if hall_ratio.denominator != 1 or not 1 <= hall_ratio <= 0x10000:
        raise ValueError(
            f"hall.timer_clock = {_freq(spec.hall.timer_clock_hz)} is not TIM3's input clock"
            f" {_freq(hall_in)} divided by a whole prescaler in [1, 65536]"
        )
    tim3_psc = int(hall_ratio) - 1
    hall_max = (1 << spec.hall.counter_bits) - 1
    overflow_s = Fraction(hall_max + 1) / spec.hall.timer_clock_hz
    filter_s = Fraction(HALL_FILTER_SAMPLES) / hall_in

    pwm = _freq(inv.pwm_frequency_hz)
    defines = [
        _define(
            "BLDC_PORT_TIM1_PSC",
            f"{tim1_psc}u",
            f"TIM1 counts at the full {_freq(clk)} timer clock",
        ),
        _define(
            "BLDC_PORT_TIM1_ARR",
            f"{tim1_arr}u",
            f"{pwm} {align_text} at {_freq(clk)}",
        ),
        _define(
            "BLDC_PORT_TIM1_CMS",
            f"{cms}u",
            f"CR1.CMS: {align_text}" + (" mode 1" if cms else ""),
        ),
        _define(
            "BLDC_PORT_DUTY_FULL_SCALE",
            f"{full_scale}u",
            f"CCRx for 100 % duty = {full_scale_why}",
        ),
        _define(
            "BLDC_PORT_TIM1_DTG",
            f"{dead.dtg:#04x}u",
            f"dead time {_time(dead.requested_s)} requested, {dead.dts_ticks} t_DTS ="
            f" {_time(dead.programmed_s)} programmed (t_DTS = 1 / {_freq(clk)})",
        ),
        _define(
            "BLDC_PORT_TIM3_PSC",
            f"{tim3_psc}u",
            f"Hall timer ticks at {_freq(spec.hall.timer_clock_hz)} from {_freq(hall_in)}",
        ),
        _define(
            "BLDC_PORT_TIM3_ARR",
            f"{hall_max}u",
            f"{spec.hall.counter_bits}-bit Hall counter: overflows {_time(overflow_s)} after"
            " the last edge, and a longer interval reads as this value",
        ),
        _define(
            "BLDC_PORT_TIM3_IC1F",
            f"{HALL_FILTER_IC1F}u",
            f"Hall input filter: {HALL_FILTER_SAMPLES} equal samples at {_freq(hall_in)},"
            f" ignores glitches shorter than {_time(filter_s)} and delays each edge as much",
        ),
    ]
    return {
        **_edge_context(spec),
        "core_header": CORE_HEADER,
        "regs_header": REGS_HEADER,
        "port_header": PORT_HEADER,
        "pwm_text": f"{pwm} {align_text}",
        "hall_clock_text": _freq(spec.hall.timer_clock_hz),
        "tim1_clock_text": _freq(clk),
        "hall_input_clock_text": _freq(hall_in),
        "defines": defines,
        "output_pins": [_pin(p) for p in OUTPUT_PINS],
        "hall_pins": [_pin(p, 1 << (2 - i)) for i, p in enumerate(HALL_PINS)],
    }


def render_port_files(
    spec: Spec, *, hall_timer_input_clock_hz: Fraction | None = None
) -> dict[str, str]:
    """File name -> text of the three port files (register header, port header and
    source), each starting with its provenance line."""
    ctx = port_context(spec, hall_timer_input_clock_hz=hall_timer_input_clock_hz)
    return {
        REGS_HEADER: render_regs_header(spec),
        PORT_HEADER: render(
            PORT_HEADER_TEMPLATE, provenance=provenance(PORT_HEADER_TEMPLATE, spec), **ctx
        ),
        PORT_SOURCE: render(
            PORT_SOURCE_TEMPLATE, provenance=provenance(PORT_SOURCE_TEMPLATE, spec), **ctx
        ),
    }

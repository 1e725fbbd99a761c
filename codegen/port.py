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

import math
from dataclasses import dataclass
from fractions import Fraction

from codegen.control.hall_timeout import hall_timeout_design
from codegen.control.sensing import sense_design
from codegen.core.hall import edge_index, edge_of_hall_pair
from codegen.core.module import build_core, timing_is_leaf
from codegen.dead_time import (  # noqa: F401  (the port's public names)
    DTG_MAX_TICKS,
    DeadTime,
    _freq,
    _time,
    dtg_dead_time_ticks,
    encode_dead_time,
    sector_margin_shift,
)
from codegen.derivation import derive
from codegen.fixedpoint.scaling import scaling
from codegen.port_drive import drive_context
from codegen.render import provenance, render
from codegen.spec_model import Spec, uses_main_duty
from codegen.svd import REGS_HEADER, load_device, render_regs_header

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

#: Bus codes by which a new bus-voltage sample may differ from the one the timing was
#: computed for before the bus state is recomputed (BLDC_PORT_BUS_HYSTERESIS_CODES): one
#: code of ADC noise then costs no recomputation.
BUS_HYSTERESIS_CODES = 1

#: While a fault is latched the bus watchdog watches the bound below which all-off
#: rectifies at the Hall interval now (BLDC_PORT_FAULTED_BUS_HYSTERESIS_CODES): the short
#: circuit is left for all-off only once the bus reads this many codes above the bound,
#: so ADC noise about the bound (a few codes) raises no interrupt at each conversion. The
#: way into the short circuit has none: a bus at or below the bound interrupts at once.
FAULTED_BUS_HYSTERESIS_CODES = 8

#: While a fault is latched, the faulted drive's periodic work (the Hall interval and
#: the safe state's region for it, the bus watchdog's window, a bus its watchdog flagged
#: meanwhile) runs at an injected sample once in this long at the most: every PWM period
#: up to 39.9 kHz (as it always had), every second at 40 kHz, every fifth at 100 kHz
#: (BLDC_PORT_FAULTED_TICK_PERIODS). At 100 kHz every period, with the bus at a rail
#: flagging every conversion, had taken 78 % of the CPU, and main published the latched
#: over-voltage 133 us after its cause (a hunt). The bus watchdog's own interrupt still
#: acts at once.
FAULTED_TICK_S = Fraction(50, 10**6)


def faulted_tick_periods(pwm_frequency_hz: Fraction) -> int:
    """PWM periods from one faulted tick to the next: the whole periods in
    FAULTED_TICK_S, one at least."""
    return max(1, math.floor(FAULTED_TICK_S * pwm_frequency_hz))


def bus_min_periods(shortest_sector_s: Fraction, pwm_frequency_hz: Fraction) -> int:
    """PWM periods from one bus change to the next at the earliest
    (BLDC_PORT_BUS_MIN_PERIODS): the shortest sector's whole periods, at least one. A
    noisy or rippling bus then costs at most one bus change a top-speed sector, the rate
    the CPU-load budget prices, at every speed."""
    return max(1, math.floor(shortest_sector_s * pwm_frequency_hz))


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


#: RM0008 TIMx_CCER: CCxE is bit 4 (x - 1), CCxNE bit 4 (x - 1) + 2.
CCER_BITS_PER_CHANNEL = 4
CCER_COMPLEMENTARY_OFFSET = 2
#: The packed edge record of the port's pin-indexed table (see EDGE_RECORD_LAYOUT).
#: TIM1_CCER.CC4E (bit 12) is set in every pattern the port writes: channel 4 only
#: triggers the ADC (OC4REF) and its pin PA11 is not an alternate-function output, so
#: the bit drives nothing, but it makes CCER never 0. An invalid pair's record is the
#: marker alone, whose partner field is CC4E: the Hall edge's one test of the partner
#: bits against CCER then refuses it too (no separate test for an invalid pair).
CCER_CC4E = 1 << 12
RECORD_CCER_MASK = 0x1FFF
RECORD_CHANNEL_ON_SHIFT = 13
RECORD_FORBIDDEN_SHIFT = 16
RECORD_SENSE_LOW_SHIFT = 27
RECORD_INVALID = CCER_CC4E << RECORD_FORBIDDEN_SHIFT  # bit 28
RECORD_CHANNEL_OFF_SHIFT = 29
RECORD_SENSE_HIGH_SHIFT = 31
EDGE_RECORD_LAYOUT = (
    "bits 12:0 CCER during the commutation (turn-on and turn-off switch, and CC4E), bits"
    " 14:13 and 30:29 the TIM1 channel (0..2 = CCR1..CCR3) of the turn-on and turn-off"
    " switch, bits 26:16 the CCER bits of their phase partners, bits 31 and 27 the"
    " injected data register (0..2 = JDR1..JDR3) that holds the braking current once the"
    " commutation has ended (high and low bit), bit 28 set alone: no valid edge (shifted"
    " down by 16 it is CC4E, which every pattern has). Shifted down by 16 a valid record's"
    " bits above the partners land on CCER bits 11 and 13..15 (CC3NP, CC4P, reserved),"
    " which the port keeps 0"
)


@dataclass(frozen=True)
class Switch:
    """One transistor T1..T6 as TIM1 drives it."""

    name: str
    channel: int  # 0..2: TIM1 CH1..CH3 (phases A, B, C)
    lower: bool  # CHxN: the lower switch of the phase

    @property
    def ccer_bit(self) -> int:
        return 1 << (
            CCER_BITS_PER_CHANNEL * self.channel + (CCER_COMPLEMENTARY_OFFSET if self.lower else 0)
        )

    @property
    def partner_bit(self) -> int:
        """The CCER bit of the other switch of the same phase."""
        return 1 << (
            CCER_BITS_PER_CHANNEL * self.channel + (0 if self.lower else CCER_COMPLEMENTARY_OFFSET)
        )


def switch(name: str) -> Switch:
    """T1..T6 -> its TIM1 channel and output: T1/T2, T3/T4, T5/T6 are the upper/lower
    switches of phases A, B, C."""
    index = int(name[1:]) - 1
    return Switch(name, index // 2, bool(index % 2))


def edge_record(turn_on: Switch, turn_off: Switch, sense_slot: int = 0) -> int:
    """The packed record of one commutation edge (EDGE_RECORD_LAYOUT)."""
    return (
        turn_on.ccer_bit
        | turn_off.ccer_bit
        | CCER_CC4E
        | turn_on.channel << RECORD_CHANNEL_ON_SHIFT
        | turn_off.channel << RECORD_CHANNEL_OFF_SHIFT
        | (turn_on.partner_bit | turn_off.partner_bit) << RECORD_FORBIDDEN_SHIFT
        | (sense_slot & 1) << RECORD_SENSE_LOW_SHIFT
        | (sense_slot >> 1) << RECORD_SENSE_HIGH_SHIFT
    )


def hall_code_of_pins(raw: int) -> int:
    """Pin levels as read (HALL_PINS[i] in bit i) -> Hall code (A B C as bits 2 1 0)."""
    return sum(((raw >> i) & 1) << (2 - i) for i in range(3))


def edge_records(spec: Spec) -> list[int]:
    """The core's edge of every Hall pin pair, (previous << 3 | now) as the pins read,
    as the packed record of its switches (0 where the pair is not a commutation)."""
    switching = derive().switching
    slots = {s.edge: s.slot for s in sense_design(spec).signals}
    by_edge: dict[int, int] = {}
    for direction in ("forward", "reverse"):
        for sector in range(6):
            edge = switching.edge_into(sector, direction)
            index = edge_index(direction, sector)
            by_edge[index] = edge_record(
                switch(edge.modulated_on), switch(edge.modulated_off), slots[index]
            )
    core_edges = edge_of_hall_pair(spec.hall.sequence)
    records = []
    for index in range(64):
        previous, now = hall_code_of_pins(index >> 3), hall_code_of_pins(index & 7)
        records.append(by_edge.get(core_edges[(previous << 3) | now], RECORD_INVALID))
    return records


def _edge_context(spec: Spec) -> dict[str, object]:
    """The port's pin-indexed table of packed edge records and the Hall pin decoding."""
    switching = derive().switching
    described: dict[int, str] = {}
    for direction in ("forward", "reverse"):
        for sector in range(6):
            edge = switching.edge_into(sector, direction)
            described[edge_index(direction, sector)] = (
                f"edge {edge_index(direction, sector)}, {direction} into sector {sector}:"
                f" {edge.modulated_on} on, {edge.modulated_off} off"
            )
    a, b, c = HALL_PINS
    if not (a.port == b.port and b.number == a.number + 1 and c.port != a.port):
        raise ValueError("the Hall pin read expects two neighbouring pins and one on another port")
    core_edges = edge_of_hall_pair(spec.hall.sequence)
    rows = []
    for index, record in enumerate(edge_records(spec)):
        previous, now = hall_code_of_pins(index >> 3), hall_code_of_pins(index & 7)
        edge = core_edges[(previous << 3) | now]
        rows.append(
            {
                "value": f"{record:#010x}u",
                "comment": f"pins {index >> 3:03b} -> {index & 7:03b}: Hall {previous:03b} ->"
                f" {now:03b}, {described.get(edge, 'invalid')}",
            }
        )
    return {
        # The improved rule (Eq. 18) does not use the main duty for the commutation.
        "method": spec.controller.method,
        "uses_main_duty": uses_main_duty(spec.controller.method),
        # improved_r's rule ends a commutation at a carrier boundary, the first at the
        # earliest, even with no current (the other methods' Eq. 20 gives 0 there)
        "zero_current_commutates": spec.controller.method == "improved_r",
        "edge_records": rows,
        "edge_record_layout": EDGE_RECORD_LAYOUT,
        "record_on_shift": RECORD_CHANNEL_ON_SHIFT,
        "record_off_shift": RECORD_CHANNEL_OFF_SHIFT,
        "record_forbidden_shift": RECORD_FORBIDDEN_SHIFT,
        "record_ccer_mask": f"{RECORD_CCER_MASK:#06x}u",
        "record_invalid": f"{RECORD_INVALID:#010x}u",
        "record_sense_low_shift": RECORD_SENSE_LOW_SHIFT,
        "record_sense_high_shift": RECORD_SENSE_HIGH_SHIFT,
        "pins_expression": f"(({a.port}->IDR >> {a.number}) & 3u) | (({c.port}->IDR >> {c.number} & 1u) << 2)",
        "pins_expression_anchored": f"((PORT_AT(anchor, {a.port}, GPIO_TypeDef)->IDR >> {a.number}) & 3u) |"
        f" ((PORT_AT(anchor, {c.port}, GPIO_TypeDef)->IDR >> {c.number} & 1u) << 2)",
        "pins_expression_text": f"P{a.port[-1]}{a.number} | P{b.port[-1]}{b.number} << 1 |"
        f" P{c.port[-1]}{c.number} << 2",
        **_hall_exti(HALL_PINS),
    }


#: RM0008 9.4.3-9.4.6 AFIO_EXTICRx: four bits per EXTI line, the port (0 = PA, 1 = PB).
EXTI_PORT_CODE = {"GPIOA": 0, "GPIOB": 1}
#: How long the Hall lines must read alike (code 0 or 7) for the EXTI path to trip: at
#: least TIM3's input filter (8 samples at 72 MHz = 111 ns, what a Hall edge needs), so a
#: shorter spike on the lines trips nothing, and far below one PWM period.
HALL_CONFIRM_NS = 1000
CPU_HZ = 72_000_000


def _hall_exti(pins: tuple[Pin, ...]) -> dict[str, object]:
    """The EXTI lines of the Hall pins (line n is pin n of the port AFIO_EXTICR selects),
    the AFIO_EXTICRx writes that route them, and the vectors that serve them."""
    registers: dict[int, list[Pin]] = {}
    for pin in pins:
        registers.setdefault(pin.number // 4, []).append(pin)
    exticr = []
    for index, members in sorted(registers.items()):
        exticr.append(
            {
                "index": index,
                "register": f"EXTICR{index + 1}",
                "mask": " | ".join(f"AFIO_EXTICR{index + 1}_EXTI{p.number}_Msk" for p in members),
                "value": " | ".join(
                    f"({EXTI_PORT_CODE[p.port]}u << AFIO_EXTICR{index + 1}_EXTI{p.number}_Pos)"
                    for p in members
                ),
                "pins": ", ".join(f"P{p.port[-1]}{p.number} on EXTI{p.number}" for p in members),
            }
        )
    vectors = {
        "EXTI0" if p.number == 0 else "EXTI9_5" if 5 <= p.number <= 9 else None for p in pins
    }
    if vectors != {"EXTI0", "EXTI9_5"}:
        raise ValueError("the port's EXTI handlers serve EXTI0 and EXTI9_5: the Hall pins moved")
    cycles = -(-HALL_CONFIRM_NS * CPU_HZ // 10**9)
    return {
        "hall_exti_lines": " | ".join(f"EXTI_PR_PR{p.number}" for p in pins),
        "hall_exti_text": ", ".join(f"P{p.port[-1]}{p.number} EXTI{p.number}" for p in pins),
        "hall_exticr": exticr,
        "hall_confirm_cycles": cycles,
        "hall_confirm_text": f"{HALL_CONFIRM_NS / 1000:g} us",
    }


def _pin_groups(pins: tuple[Pin, ...], mode: str, cnf: str, bsrr: str) -> list[dict[str, object]]:
    """The pins by configuration register (GPIOx CRL/CRH): one read-modify-write and one
    BSRR write per register configure all of its pins."""
    groups: dict[tuple[str, str], list[Pin]] = {}
    for pin in pins:
        groups.setdefault((pin.port, "CRL" if pin.number < 8 else "CRH"), []).append(pin)
    return [
        {
            "port": port,
            "cr": cr,
            "bsrr": " | ".join(f"GPIO_BSRR_{bsrr}{p.number}" for p in members),
            "mask": " | ".join(
                f"GPIO_{cr}_MODE{p.number}_Msk | GPIO_{cr}_CNF{p.number}_Msk" for p in members
            ),
            "value": [
                f"({mode} << GPIO_{cr}_MODE{p.number}_Pos) | ({cnf} << GPIO_{cr}_CNF{p.number}_Pos)"
                for p in members
            ],
            "pins": [f"P{p.port[-1]}{p.number} {p.signal}: {p.role}" for p in members],
        }
        for (port, cr), members in groups.items()
    ]


#: RM0008 3.3: the peripheral registers lie in one 512 MB region of the Cortex-M3 map.
PERIPHERAL_REGION_BYTES = 0x2000_0000


def _peripheral_region() -> dict[str, str]:
    """The start of the peripheral region holding the port's timers and GPIO ports (from
    the SVD): the handlers build their addresses from it (one MOV, a Thumb-2 modified
    immediate) instead of loading each from a literal pool in flash."""
    device = load_device()
    bases = {
        device.peripheral(n).base_address
        for n in ("TIM1", "TIM3", "GPIOA", "GPIOB", "ADC1", "ADC2", "EXTI")
    }
    (start,) = {b - b % PERIPHERAL_REGION_BYTES for b in bases}
    return {
        "peripheral_region": f"{start:#010x}u",
        "peripheral_region_text": "start of the peripheral region holding TIM1, TIM3, ADC1, ADC2,"
        " EXTI, GPIOA and GPIOB (RM0008 3.3, bases from the SVD)",
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
    timeout = hall_timeout_design(spec)
    filter_s = Fraction(HALL_FILTER_SAMPLES) / hall_in

    pwm = _freq(inv.pwm_frequency_hz)
    sc = scaling(spec, derive())
    volts = sc.volts_per_bus_code
    # X = k_x / (T B) counts: a bus code H off moves it most at the top speed and the
    # lowest bus code.
    gate = bus_min_periods(
        Fraction(sc.period_min_ticks) / spec.hall.timer_clock_hz, inv.pwm_frequency_hz
    )
    stale = (
        sc.k_x
        * BUS_HYSTERESIS_CODES
        / (sc.period_min_ticks * sc.bus_code_min * (sc.bus_code_min + BUS_HYSTERESIS_CODES))
    )
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
            "BLDC_PORT_HALL_TIMEOUT_SHIFT",
            f"{timeout.shift}u",
            f"Hall time-out: TIM3 CC3 at T << {timeout.shift} after the edge ending an"
            f" interval T (codegen/control/hall_timeout.py): a rotor braking at up to"
            f" {timeout.deceleration:.4g} rad/s^2 (the bridge's rating through the worst"
            " k_e, on the rotor's inertia) that reaches its next edge does so by then",
        ),
        _define(
            "BLDC_PORT_HALL_TIMEOUT_PERIOD_MAX",
            f"{timeout.period_max}u",
            "T in [1, this]: the time-out is T << BLDC_PORT_HALL_TIMEOUT_SHIFT"
            + (
                f" (a mean speed from {timeout.speed_min_rpm:.0f} rpm up); above, the"
                " counter's wrap (a rotor that slow may stop within the sector)"
                if timeout.speed_min_rpm is not None
                else "; 0: none, the counter's wrap at every speed (a rotor may stop within"
                " a sector in the speed range)"
            ),
        ),
        _define(
            "BLDC_PORT_BUS_CODE_MAX",
            f"{sc.bus_code_max}u",
            f"the core's over-voltage threshold, {float(sc.bus_code_max * volts):.4g} V: the analog"
            " watchdog's HTR trips over-voltage above it, whatever the hysteresis",
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
        **drive_context(spec),
        "core_header": CORE_HEADER,
        "core_inlined": timing_is_leaf(build_core(spec)),
        "regs_header": REGS_HEADER,
        "port_header": PORT_HEADER,
        "pwm_text": f"{pwm} {align_text}",
        "hall_clock_text": _freq(spec.hall.timer_clock_hz),
        "tim1_clock_text": _freq(clk),
        "hall_input_clock_text": _freq(hall_in),
        "defines": defines,
        "output_pins": [_pin(p) for p in OUTPUT_PINS],
        "hall_pins": [_pin(p, 1 << (2 - i)) for i, p in enumerate(HALL_PINS)],
        "hall_pin_groups": _pin_groups(
            HALL_PINS, "BLDC_PORT_GPIO_MODE_INPUT", "BLDC_PORT_GPIO_CNF_INPUT_PULL", "BS"
        ),
        "output_pin_groups": _pin_groups(
            OUTPUT_PINS, "BLDC_PORT_GPIO_MODE_OUTPUT_50MHZ", "BLDC_PORT_GPIO_CNF_AF_PUSH_PULL", "BR"
        ),
        **_peripheral_region(),
        "bus_hysteresis_codes": BUS_HYSTERESIS_CODES,
        # TIM1's dead time in processor cycles, rounded up: the refusal's wait between a
        # switch off and its partner on, where TIM1 inserts none (single-output mode)
        "dead_time_cycles": -(-dead.dts_ticks * CPU_HZ // clk),
        "dead_time_text": _time(dead.programmed_s),
        "faulted_bus_hysteresis_codes": FAULTED_BUS_HYSTERESIS_CODES,
        "faulted_tick_periods": faulted_tick_periods(inv.pwm_frequency_hz),
        "bus_hysteresis_text": f"{BUS_HYSTERESIS_CODES} code"
        f"{'' if BUS_HYSTERESIS_CODES == 1 else 's'} = {float(BUS_HYSTERESIS_CODES * volts) * 1e3:.4g} mV",
        "bus_hysteresis_duty_text": f"{float(stale):.3g} counts",
        # hall.sector_shortening as the core's latest end takes it (2^-k >= it): a Hall
        # interval shorter than T (1 - 2^-k) after one of T is no rotor's
        "sector_margin_shift": sector_margin_shift(spec.hall.sector_shortening),
        "sector_shortening_text": f"{float(spec.hall.sector_shortening) * 100:g} %",
        "bus_min_periods": gate,
        "bus_min_periods_text": f"{float(Fraction(gate) / inv.pwm_frequency_hz) * 1e6:.4g} us",
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
            PORT_HEADER_TEMPLATE,
            provenance=provenance(f"templates/{PORT_HEADER_TEMPLATE}", spec),
            **ctx,
        ),
        PORT_SOURCE: render(
            PORT_SOURCE_TEMPLATE,
            provenance=provenance(f"templates/{PORT_SOURCE_TEMPLATE}", spec),
            **ctx,
        ),
    }

"""Render context of the drive half of the STM32F103 port: the ADC (injected
conversions triggered by TIM1, the analog watchdog), the current loop's interrupt, the
break input, the faults and their safe state, and how the handlers are named.

Resources (default mapping, DS5319 Table 5):
  ADC1   injected sequence JSQ1..JSQ4 triggered by TIM1 TRGO = OC4REF (CR2.MMS = 111):
         the current channel(s) first, then the bus divider; JEOC and the analog
         watchdog (bus channel, injected) raise ADC1_2
  TIM1   CH4 (no pin: OC4REF only) places the trigger; BKIN on PB12
  ADC12_INx  PA0..PA7 (IN0..IN7), PB0..PB1 (IN8..IN9): analog inputs
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from fractions import Fraction

from codegen.control import current_loop
from codegen.control.safe_state import safe_state_design
from codegen.control.sensing import PHASES, sense_design
from codegen.derivation import derive
from codegen.fixedpoint.scaling import scaling
from codegen.port_faults import FAULTS, PERMANENT
from codegen.spec_drive import (
    ADC_CLOCK_HZ,
    ADC_PRESCALER,
    ADC_SAMPLE_CYCLES,
    INJECTED_CONVERSIONS,
    injected_conversions_s,
    injected_sequence_s,
)
from codegen.spec_model import Spec
from codegen.system_clock import SYSCLK_HZ

LOOP_HEADER = current_loop.HEADER

#: CPU cycles from the commutation end's load of TIM1 CNT to its load of ADC1 SR, at
#: the most: the CR1 load between them (centre-aligned), each APB2 load a few cycles
#: (PM0056 3.3.1: LDR 2, plus the bridge); the age's arithmetic is kept after both
#: (BLDC_PORT_AFTER_LOADS). About three times the 5 and 7 cycles the bench's model
#: measures (tests/emulation/test_end_reads.py). A higher-priority interrupt between the
#: two loads only counts one more stale sequence (a clean sample dropped), never fewer.
END_READ_GAP_CYCLES = 16
#: CPU cycles from the commutation end's load of TIM1 CNT to its store of the COM event
#: (EGR), at the most: the CR1 load between them (centre-aligned) and the store, each a
#: few cycles on APB2. A trigger the counter puts within this many counts of its read
#: fires before the COM event: its sequence samples the commutating bridge, though its
#: JSTRT may not show yet when SR is read after the store (the injection latency, up
#: to 3 ADC cycles, comes before the conversion starts). The bench's model measures 6
#: cycles edge-aligned and 10 centre-aligned (tests/emulation/test_end_reads.py); two
#: more for the store's way through the APB2 bridge. Not more: a trigger counted here
#: that fires after the COM event is a clean sample dropped, and a steady braking's
#: ends keep their phase to the carrier, sector after sector.
END_COM_GAP_CYCLES = 12
#: CPU cycles from the commutation end's first load of TIM1 CNT, which waits out an
#: imminent trigger (BLDC_PORT_WAIT_COUNTS), to its second, the age's, at the most: the
#: compare and the branch past the wait, the CR1 load (centre-aligned) and the load.
#: The bench's model measures 18 cycles edge-aligned and 26 centre-aligned
#: (tests/emulation/test_end_reads.py; 21 before the Hall time-out moved the handler's
#: layout: the branch past the wait lands on a target the prefetch fetches afresh, so a
#: few bytes before it move this by cycles). Too few, and a trigger between the second read
#: and the COM event is counted by its age alone (BLDC_PORT_IMMINENT_AGE), as before the
#: wait: a clean sample may be dropped, never a stale one taken.
END_WAIT_GAP_CYCLES = 30

#: CPU cycles one read of the commutation end's wait for an imminent trigger takes at
#: the least: the APB2 load of CNT (PM0056 3.3.1: LDR 2) and the compare and branch.
IMMINENT_READ_MIN_CYCLES = 4

#: RM0008 TIMx_CCMRx.OCxM: 110 PWM mode 1, 111 PWM mode 2.
OC_MODE_PWM1 = 6
OC_MODE_PWM2 = 7
#: RM0008 TIMx_CR2.MMS = 111: OC4REF is TRGO (the ADC's injected trigger, JEXTSEL = 000).
MMS_OC4REF = 7
#: RM0008 ADC_CR2.JEXTSEL = 000: ADC1/2 injected trigger = TIM1 TRGO.
JEXTSEL_TIM1_TRGO = 0
#: RM0008 RCC_CFGR.ADCPRE = 10: PCLK2 / 6.
ADCPRE_DIV6 = 2
#: TIM1_BKIN on PB12 (DS5319 Table 5, no remap).
BKIN_PORT, BKIN_PIN = "GPIOB", 12
#: Open-loop marker of the current reference: above every ADC code.
OPEN_LOOP = 0xFFFFFFFF
#: The bound of the wait for the ADC's calibration, in loop iterations: it takes 83 ADC
#: cycles (RM0008 11.4), 6.9 us = 498 CPU cycles at 72 MHz, and each iteration at least
#: 3 cycles, so 1000 is 6 times the longest it can need.
ADC_WAIT_LOOPS = 1000


@dataclass(frozen=True)
class Handler:
    """One of the port's interrupt handlers and how it is named.

    vector: its CMSIS name, the vector table's entry (startup_stm32f103xb.s).
    cube_call: in Cube integration, the function the project's stm32f1xx_it.c calls from
        its handler of that vector; None where the port owns the vector in Cube
        integration too: a hot handler, entered without stm32f1xx_it.c's extra branch
        (from flash, a taken branch refetches through the wait states), for which the
        Cube project unticks NVIC > Code generation > "Generate IRQ handler".
    cube_interrupt: the interrupt's name in CubeMX's NVIC tab.
    """

    vector: str
    cube_call: str | None
    cube_interrupt: str

    @property
    def cube_owned(self) -> bool:
        """The port defines the vector itself in Cube integration too."""
        return self.cube_call is None

    def name(self, cube: bool) -> str:
        """The name the port compiles the handler with."""
        return self.cube_call if cube and self.cube_call is not None else self.vector


HANDLERS = {
    # the Hall edge and the timing run at every commutation: the port owns their vectors in
    # Cube integration too
    "hall": Handler(
        "TIM3_IRQHandler",
        None,
        cube_interrupt="TIM3 global interrupt",
    ),
    "timing": Handler(
        "TIM1_TRG_COM_IRQHandler",
        None,
        cube_interrupt="TIM1 trigger and commutation interrupts",
    ),
    # the bus voltage moved beyond the hysteresis (rare): TIM1's update vector, which
    # TIM1 never raises; the current loop pends it
    "bus": Handler(
        "TIM1_UP_IRQHandler",
        "bldc_port_tim1_up_irq",
        cube_interrupt="TIM1 update interrupt",
    ),
    "adc": Handler(
        "ADC1_2_IRQHandler",
        "bldc_port_adc_irq",
        cube_interrupt="ADC1 and ADC2 global interrupts",
    ),
    "brk": Handler(
        "TIM1_BRK_IRQHandler",
        "bldc_port_tim1_brk_irq",
        cube_interrupt="TIM1 break interrupt",
    ),
    # the Hall lines' EXTI (PB0 on EXTI0, PA6 and PA7 on EXTI9_5): a code 0 or 7 at once
    "hall_line0": Handler(
        "EXTI0_IRQHandler",
        "bldc_port_exti0_irq",
        cube_interrupt="EXTI line0 interrupt",
    ),
    "hall_lines9_5": Handler(
        "EXTI9_5_IRQHandler",
        "bldc_port_exti9_5_irq",
        cube_interrupt="EXTI line[9:5] interrupts",
    ),
}


def handler_names(spec: Spec) -> dict[str, str]:
    """The name each of the port's handlers is compiled with: the vector table's (the
    port owns the entry: always in vector-table integration, the hot handlers in Cube's)
    or a function the Cube project's stm32f1xx_it.c calls."""
    cube = spec.firmware.integration == "cube"
    return {role: h.name(cube) for role, h in HANDLERS.items()}


def cube_handlers() -> dict[str, list[dict[str, str]]]:
    """For Cube integration: the vectors the port defines itself ("owned": the project
    unticks "Generate IRQ handler" for them) and those stm32f1xx_it.c's handlers call
    the port from ("called")."""
    out: dict[str, list[dict[str, str]]] = {"owned": [], "called": []}
    for h in HANDLERS.values():
        entry = {"vector": h.vector, "call": h.cube_call or "", "interrupt": h.cube_interrupt}
        out["owned" if h.cube_owned else "called"].append(entry)
    return out


def _define(name: str, value: str, comment: str) -> dict[str, str]:
    return {"name": name, "value": value, "comment": comment}


def adc_pin(channel: int) -> tuple[str, int]:
    """ADC12_INx -> (GPIO port, pin): IN0..IN7 on PA0..PA7, IN8..IN9 on PB0..PB1."""
    return ("GPIOA", channel) if channel < 8 else ("GPIOB", channel - 8)


def _analog_groups(spec: Spec) -> list[dict[str, object]]:
    channels = [*spec.sensing.current_channels, spec.sensing.bus_voltage_channel]
    roles = {}
    if spec.sensing.topology == "dc_link_shunt":
        roles[spec.sensing.current_channels[0]] = "DC-link shunt current"
    else:
        for phase, ch in zip(PHASES, spec.sensing.current_channels, strict=True):
            roles[ch] = f"phase {phase} low-side shunt current"
    roles[spec.sensing.bus_voltage_channel] = "bus voltage divider"
    groups: dict[tuple[str, str], list[tuple[int, int]]] = {}
    for ch in channels:
        port, pin = adc_pin(ch)
        groups.setdefault((port, "CRL" if pin < 8 else "CRH"), []).append((pin, ch))
    return [
        {
            "port": port,
            "cr": cr,
            "mask": " | ".join(f"GPIO_{cr}_MODE{p}_Msk | GPIO_{cr}_CNF{p}_Msk" for p, _ in pins),
            "pins": [f"P{port[-1]}{p} ADC12_IN{ch}: {roles[ch]}" for p, ch in pins],
        }
        for (port, cr), pins in groups.items()
    ]


def _sequence_expression(spec: Spec) -> str:
    d = sense_design(spec)
    parts = [f"({INJECTED_CONVERSIONS - 1}u << ADC_JSQR_JL_Pos)"]
    parts += [f"({ch}u << ADC_JSQR_JSQ{k + 1}_Pos)" for k, ch in enumerate(d.sequence)]
    return " | ".join(parts)


def _sample_time_expression(spec: Spec, register: str) -> str:
    code = ADC_SAMPLE_CYCLES.index(spec.sensing.adc_sample_cycles)
    channels = sorted({*spec.sensing.current_channels, spec.sensing.bus_voltage_channel})
    low = register == "SMPR2"
    parts = [f"({code}u << ADC_{register}_SMP{ch}_Pos)" for ch in channels if (ch < 10) == low]
    return " | ".join(parts) if parts else "0u"


def _sense_lines(spec: Spec) -> list[str]:
    d = sense_design(spec)
    lines = []
    for s in d.signals:
        lines.append(
            f"edge {s.edge:2d} ({s.direction} into sector {s.sector}): {s.modulated} modulated,"
            f" phase {s.returning_phase} returns: {s.signal} -> JDR{s.slot + 1}"
        )
    return lines


@dataclass(frozen=True)
class CurrentWatch:
    """ADC2's continuous watch of the current channel(s): the analog watchdog's
    thresholds, in raw codes. A rail is watched unless zero current itself reads on it
    (a current-sense offset of 0 V or of the reference): every current the chain can
    measure reads strictly between the rails, so a conversion at a rail, at any instant,
    is a current the loop cannot measure (an open or saturated sensor, or a current
    beyond the sensing range)."""

    ltr: int  # a raw code below it sets AWD: 1 watches the low rail, 0 does not
    htr: int  # above it: full scale - 1 watches the high rail, full scale does not
    channels: tuple[int, ...]
    conversion_us: float  # one conversion of ADC2 (sample + 12.5 cycles at 12 MHz)

    @property
    def rails(self) -> str:
        watched = [r for r, on in (("0", self.ltr > 0), ("full scale", self.htr < 2**12 - 1)) if on]
        return " and ".join(watched) if watched else "none"


def current_watch(spec: Spec) -> CurrentWatch:
    full = 2**spec.adc.bits - 1
    offset = Fraction(spec.adc.current_offset_v) / Fraction(spec.adc.reference_v) * 2**spec.adc.bits
    low_watched = offset >= 1  # zero current reads code 1 or above
    high_watched = offset < full  # zero current reads below full scale
    return CurrentWatch(
        ltr=1 if low_watched else 0,
        htr=full - 1 if high_watched else full,
        channels=tuple(spec.sensing.current_channels),
        conversion_us=float(
            (Fraction(spec.sensing.adc_sample_cycles) + Fraction(25, 2))
            / 12
            * len(spec.sensing.current_channels)
        ),
    )


def _sequence_counts(spec: Spec) -> int:
    """TIM1 counts from an injected trigger to JEOC, rounded up, with one ADC cycle
    more (the datasheet's PCLK2 cycle of an external trigger) and, centre-aligned, the
    two counts the trigger age takes the peak for the rising edge after it."""
    clock = Fraction(spec.inverter.timer_clock_hz)
    counts = injected_sequence_s(Fraction(spec.sensing.adc_sample_cycles)) * clock
    counts += clock / ADC_CLOCK_HZ + (2 if spec.inverter.pwm_alignment != "edge" else 0)
    return math.ceil(counts)


def _sequence_min_counts(spec: Spec) -> int:
    """TIM1 counts from an injected trigger to JEOC at the least, in the trigger age's
    terms: the conversions' exact time rounded down (centre-aligned the age counts from
    the peak, one count before the trigger's edge). A sequence younger than this has not
    ended: a JEOC set then is an older sequence's.

    The injection latency is left out: DS5319 gives only its largest value (3 ADC cycles,
    INJECTED_LATENCY_CYCLES), so at the least it is none. With it (18 counts at 12 MHz
    ADCCLK) a sequence that had ended when a commutation end read its age, up to 18
    counts short of that bound, read as still converting and its JEOC as an older one's:
    two stale sequences, so the next one, begun after the end, was dropped too (at top
    speed on a 24 kHz centre-aligned 7-pole-pair motor and a 20 kHz edge-aligned one,
    the timing then ran on a sample older than two sectors).

    Less the counts between the commutation end's reads of TIM1's CNT and ADC1's SR
    (END_READ_GAP_CYCLES): a sequence that ends between them reads as young yet ended.
    A JEOC that is an older sequence's while the last trigger is this young would need
    the loop's interrupt held off that long after it, several times the longest handler
    above it."""
    clock = Fraction(spec.inverter.timer_clock_hz)
    counts = injected_conversions_s(Fraction(spec.sensing.adc_sample_cycles)) * clock
    read_gap = math.ceil(END_READ_GAP_CYCLES * clock / SYSCLK_HZ)
    return math.floor(counts) + (1 if spec.inverter.pwm_alignment != "edge" else 0) - read_gap


def _imminent_age(spec: Spec, period_counts: int) -> int:
    """The trigger age (BLDC_PORT_TRIGGER_AGE) from which the next injected trigger
    comes within END_COM_GAP_CYCLES of the counter's read, before the COM event the
    end stores after it: the age of the next trigger less that gap in counts. The next
    trigger is one carrier period after the last (P = ARR + 1 counts) edge-aligned, and
    centre-aligned one count after the next peak (2 P + 1 counts from the last, P = ARR)."""
    edge = spec.inverter.pwm_alignment == "edge"
    cycle = period_counts if edge else 2 * period_counts + 1
    return cycle - _imminent_counts(spec)


def _imminent_counts(spec: Spec) -> int:
    """END_COM_GAP_CYCLES in TIM1 counts, rounded up."""
    clock = Fraction(spec.inverter.timer_clock_hz)
    return math.ceil(END_COM_GAP_CYCLES * clock / SYSCLK_HZ)


def wait_counts(spec: Spec) -> int:
    """The counts before the next trigger from which the commutation end's first read of
    the counter waits it out: the COM event's gap after the second read and the gap
    between the two reads (END_COM_GAP_CYCLES + END_WAIT_GAP_CYCLES), rounded up."""
    clock = Fraction(spec.inverter.timer_clock_hz)
    return math.ceil((END_COM_GAP_CYCLES + END_WAIT_GAP_CYCLES) * clock / SYSCLK_HZ)


def trigger_within(centre: bool, arr: int, ccr4: int, most: int) -> str:
    """BLDC_PORT_TRIGGER_WITHIN(cnt, cr1, n): the next injected trigger within n counts
    of CNT, for every n up to `most`, as one compare of the counter where it can be: the
    trigger age (BLDC_PORT_TRIGGER_AGE) at least its cycle less n. Edge-aligned that is
    CNT in [CCR4 - n, CCR4) when CCR4 >= n (from CCR4 on the age is CNT - CCR4 <= ARR -
    CCR4 < ARR + 1 - n); centre-aligned, counting up from ARR + 1 - n when ARR >= n
    (counting down the age is ARR - CNT <= ARR < 2 ARR + 1 - n). Otherwise the age.
    tests/test_port.py compares the two at every count."""
    if centre and arr >= most:
        return "((((cr1) & TIM_CR1_DIR) == 0u) && ((cnt) >= " + f"{arr + 1}u - (n)))"
    if not centre and ccr4 >= most:
        return f"((uint32_t)((cnt) - ({ccr4}u - (n))) < (n))"
    cycle = 2 * arr + 1 if centre else arr + 1
    return f"(BLDC_PORT_TRIGGER_AGE(cnt, cr1) >= {cycle}u - (n))"


def _imminent_reads(spec: Spec) -> int:
    """The commutation end's reads of the counter while it waits out an imminent trigger,
    at the most: the trigger comes within BLDC_PORT_WAIT_COUNTS of the first read, and
    each read advances the counter by at least IMMINENT_READ_MIN_CYCLES; one read more
    past it."""
    clock = Fraction(spec.inverter.timer_clock_hz)
    per_read = IMMINENT_READ_MIN_CYCLES * clock / SYSCLK_HZ
    return math.ceil(wait_counts(spec) / per_read) + 1


def _adc2_sequence(spec: Spec) -> str:
    channels = spec.sensing.current_channels
    return " | ".join(f"({ch}u << ADC_SQR3_SQ{k + 1}_Pos)" for k, ch in enumerate(channels))


def drive_context(spec: Spec) -> dict[str, object]:
    sd = sense_design(spec)
    ss = safe_state_design(spec)
    loop = current_loop.design(spec)
    sc = scaling(spec, derive())
    clk = spec.inverter.timer_clock_hz
    window = sd.window
    centre = window.alignment != "edge"
    p = spec.protection
    adc_max = 2**spec.adc.bits - 1
    bkp = p.break_polarity == "active_high"
    volts = sc.volts_per_bus_code
    watch = current_watch(spec)
    defines = [
        _define(
            "BLDC_PORT_TIM1_CCR4",
            f"{window.trigger_counts}u",
            (
                "the current sample: the counter's peak (OC4REF in PWM mode 1, CCR4 = ARR - 1:"
                " inactive at ARR - 1 counting up and at ARR, rising one count after the peak)"
                if centre
                else f"the current sample: OC4REF (PWM mode 2) rises at CNT = {window.trigger_counts},"
                f" {window.span_counts} counts before the samples end, 1 before the next period"
            ),
        ),
        _define(
            "BLDC_PORT_SEQUENCE_COUNTS",
            f"{_sequence_counts(spec)}u",
            "TIM1 counts from an injected trigger to JEOC, one ADC cycle (and for the"
            " centre-aligned trigger one count after the peak, two counts) over",
        ),
        _define(
            "BLDC_PORT_SEQUENCE_MIN_COUNTS",
            f"{_sequence_min_counts(spec)}u",
            "TIM1 counts from an injected trigger to JEOC at the least (the trigger age's"
            " terms, no injection latency: the datasheet gives only its largest), less the"
            " commutation end's gap between its CNT and SR reads: a younger sequence has not"
            " ended, so a JEOC set then is an older one's",
        ),
        _define(
            "BLDC_PORT_IMMINENT_AGE",
            f"{_imminent_age(spec, window.period_counts)}u",
            "a trigger age from which the next trigger comes within the commutation end's"
            " gap between its CNT read and its COM event (END_COM_GAP_CYCLES): that"
            " sequence samples the commutating bridge",
        ),
        _define(
            "BLDC_PORT_IMMINENT_READS",
            f"{_imminent_reads(spec)}u",
            "the commutation end's reads of the counter, at the most, while it waits out a"
            " trigger within BLDC_PORT_WAIT_COUNTS (it then fires before the COM event, for"
            " certain)",
        ),
        _define(
            "BLDC_PORT_WAIT_COUNTS",
            f"{wait_counts(spec)}u",
            "counts before the next trigger from which the commutation end's first counter"
            " read waits it out: the COM event's gap after the second read and the reads'"
            " gap (END_COM_GAP_CYCLES + END_WAIT_GAP_CYCLES)",
        ),
        _define(
            "BLDC_PORT_TRIGGER_WITHIN(cnt, cr1, n)",
            trigger_within(
                centre,
                window.period_counts - (0 if centre else 1),
                window.trigger_counts,
                wait_counts(spec),
            ),
            "the next injected trigger within n counts of CNT (n up to BLDC_PORT_WAIT_COUNTS):"
            " BLDC_PORT_TRIGGER_AGE(cnt, cr1) at least its cycle less n, in one compare",
        ),
        _define(
            "BLDC_PORT_AGE_CR1(tim1)",
            "((tim1)->CR1)" if centre else "0u",
            "what BLDC_PORT_TRIGGER_AGE takes of CR1: its DIR bit (centre-aligned), else no read",
        ),
        _define(
            "BLDC_PORT_TRIGGER_AGE(cnt, cr1)",
            (
                "((((cr1) & TIM_CR1_DIR) != 0u) ? BLDC_PORT_TIM1_ARR - (cnt)"
                " : BLDC_PORT_TIM1_ARR + (cnt))"
                if centre
                else "(((cnt) >= BLDC_PORT_TIM1_CCR4) ? (cnt) - BLDC_PORT_TIM1_CCR4"
                " : (cnt) + BLDC_PORT_TIM1_ARR + 1u - BLDC_PORT_TIM1_CCR4)"
            ),
            "TIM1 counts since the last injected trigger, from CNT and CR1 read before a"
            " COM event restarts the carrier: "
            + ("the counter's peak (down-counting: ARR - CNT since)" if centre else "CNT = CCR4"),
        ),
        _define(
            "BLDC_PORT_OC4_MODE",
            f"{OC_MODE_PWM1 if centre else OC_MODE_PWM2}u",
            "OC4M: PWM mode 1 (centre-aligned, rising after the peak)"
            if centre
            else "OC4M: PWM mode 2 (rising at CNT = CCR4)",
        ),
        _define(
            "BLDC_PORT_ADC_JSQR",
            f"({_sequence_expression(spec)})",
            "JL = 3: JSQ1..JSQ4 land in JDR1..JDR4; "
            + ", ".join(f"JSQ{k + 1} IN{ch}" for k, ch in enumerate(sd.sequence)),
        ),
        _define(
            "BLDC_PORT_ADC_SMPR1",
            f"({_sample_time_expression(spec, 'SMPR1')})",
            f"{float(spec.sensing.adc_sample_cycles):g} ADC cycles on channels 10..17 in use",
        ),
        _define(
            "BLDC_PORT_ADC_SMPR2",
            f"({_sample_time_expression(spec, 'SMPR2')})",
            f"{float(spec.sensing.adc_sample_cycles):g} ADC cycles on the channels in use (SMPx ="
            f" {sd.sample_code})",
        ),
        _define(
            "BLDC_PORT_ADC_BUS_CHANNEL",
            f"{spec.sensing.bus_voltage_channel}u",
            "analog watchdog channel: the bus divider",
        ),
        _define(
            "BLDC_PORT_ADC_HTR",
            f"{sc.bus_code_max}u",
            f"over-voltage: above {float(sc.bus_code_max * volts):.4g} V (the core's BLDC_BUS_CODE_MAX)",
        ),
        _define(
            "BLDC_PORT_ADC_LTR",
            f"{sc.bus_code_min}u",
            f"under-voltage or a stuck bus ADC: below {float(sc.bus_code_min * volts):.4g} V (the"
            " core's BLDC_BUS_CODE_MIN)",
        ),
        _define(
            "BLDC_PORT_ADC_CODE_MAX",
            f"{adc_max}u",
            "ADC full scale: a current sample at 0 or here is a rail",
        ),
        _define(
            "BLDC_PORT_ADC_BITS",
            f"{spec.adc.bits}u",
            "ADC resolution: a value with a bit at or above this is no ADC code",
        ),
        _define(
            "BLDC_PORT_CURRENT_LTR",
            f"{watch.ltr}u",
            "ADC2's analog watchdog: a current conversion below it is at the low rail"
            if watch.ltr
            else "ADC2's analog watchdog: 0, the low rail not watched (zero current reads 0)",
        ),
        _define(
            "BLDC_PORT_CURRENT_HTR",
            f"{watch.htr}u",
            "ADC2's analog watchdog: a current conversion above it is at the high rail"
            if watch.htr < adc_max
            else "ADC2's analog watchdog: full scale, the high rail not watched",
        ),
        _define(
            "BLDC_PORT_ADC2_SQR1",
            f"({len(watch.channels) - 1}u << ADC_SQR1_L_Pos)",
            f"ADC2's regular sequence: {len(watch.channels)} conversion(s), continuously",
        ),
        _define(
            "BLDC_PORT_ADC2_SQR3",
            f"({_adc2_sequence(spec)})",
            "ADC2's regular sequence: the current channel(s) "
            + ", ".join(f"IN{ch}" for ch in watch.channels)
            + f", each converted every {watch.conversion_us:.2f} us",
        ),
        _define(
            "BLDC_PORT_ADC_PRESCALER",
            f"{ADCPRE_DIV6}u",
            f"RCC_CFGR.ADCPRE: PCLK2 / {ADC_PRESCALER} = 12 MHz (<= 14 MHz)",
        ),
        _define(
            "BLDC_PORT_ADC_WAIT_LOOPS",
            f"{ADC_WAIT_LOOPS}u",
            "bound of the start-up waits (ADC power-up, calibration)",
        ),
        _define(
            "BLDC_PORT_BREAK_ACTIVE_HIGH",
            f"{int(bkp)}u",
            f"TIM1 BKIN ({BKIN_PORT[-1]}{BKIN_PIN}) is {p.break_polarity.replace('_', ' ')}"
            f" (BDTR.BKP = {int(bkp)}); the comparator trips at {float(p.over_current_a):g} A",
        ),
        _define(
            "BLDC_PORT_RECTIFYING_PRODUCT",
            f"{ss.k_rect}u",
            f"T B at or below it: lambda k_e n c >= U_d (lambda = {ss.line_to_line_peak},"
            " k_e at its upper tolerance, c = 1/(1 - hall.sector_shortening): the rotor up"
            " to c faster than T says), all-off may rectify: the safe state is the short"
            " circuit",
        ),
        _define(
            "BLDC_PORT_SHORT_VALID_PERIOD",
            f"{min(ss.short_valid_period, 0xFFFFFFFF)}u",
            "Hall interval at or above it: the short circuit is within"
            f" protection.short_circuit_current_max = {float(p.short_circuit_current_max_a):g} A"
            + (
                f" (up to {ss.short_valid_speed_rpm:.0f} rpm for the worst motor the spec"
                " declares, the rotor up to c faster than T says)"
                if ss.short_valid_speed_rpm is not None
                else " at every speed"
            ),
        ),
        _define(
            "BLDC_PORT_SHORT_WHILE_UNKNOWN",
            f"{int(ss.short_while_unknown)}u",
            "a wrapped Hall interval (the speed unknown before the first edges, or below the"
            " counter's range): "
            + (
                "the short circuit, within the rating up to controller.speed_max"
                if ss.short_while_unknown
                else "all-off (the short exceeds the rating below controller.speed_max)"
            ),
        ),
        _define(
            "BLDC_PORT_SHORT_WHERE_BOTH",
            f"{int(ss.policy == 'short_circuit')}u",
            f"protection.safe_state = {ss.policy}: the safe state where both are valid",
        ),
        _define(
            "BLDC_PORT_OPEN_LOOP",
            f"{OPEN_LOOP:#010x}u",
            "current reference in open loop (bldc_port_set_main_duty)",
        ),
        _define(
            "BLDC_PORT_FAULTS_PERMANENT",
            f"{PERMANENT:#06x}u",
            "faults only a reset clears",
        ),
    ]
    faults = [
        {
            "name": f"BLDC_FAULT_{f.name}",
            "value": f"{f.value:#06x}u",
            "doc": f.doc,
            "by": f.detected_by,
            "clears": f.clears_when,
        }
        for f in FAULTS
    ]
    names = handler_names(spec)
    return {
        "cube_handlers": cube_handlers(),
        "loop_header": LOOP_HEADER,
        "integration": spec.firmware.integration,
        "cube": spec.firmware.integration == "cube",
        "handler": names,
        "drive_defines": defines,
        "faults": faults,
        "low_side": spec.sensing.topology == "low_side_phase_shunts",
        "topology_text": "DC-link shunt"
        if spec.sensing.topology == "dc_link_shunt"
        else "low-side phase shunts",
        "sense_lines": _sense_lines(spec),
        # the JDRx that hold a bus sample: the analog watchdog may flag the first of them
        # before the later ones of the same sequence are written
        "bus_jdr_slots": [
            k + 1 for k, ch in enumerate(sd.sequence) if ch == spec.sensing.bus_voltage_channel
        ],
        "sense_proof": list(sd.proof),
        "safe_lines": list(ss.regions),
        "analog_groups": _analog_groups(spec),
        "bkin": {
            "port": BKIN_PORT,
            "n": BKIN_PIN,
            "cr": "CRH" if BKIN_PIN >= 8 else "CRL",
            "name": f"P{BKIN_PORT[-1]}{BKIN_PIN}",
            "pull": "pull-down" if bkp else "pull-up",
            # ODR through BSRR picks the pull: reset (BR) for down, set (BS) for up
            "bsrr": f"GPIO_BSRR_{'BR' if bkp else 'BS'}{BKIN_PIN}",
        },
        "loop_duty_max": loop.gains.duty_max_counts,
        "sample_text": f"{float(spec.sensing.adc_sample_cycles):g}-cycle samples at 12 MHz, dead time"
        f" {sd.dead_time_counts} + settling {window.guard_counts - sd.dead_time_counts} counts",
        "duty_max_text": f"{window.duty_max_counts} of {window.period_counts} counts"
        f" ({100 * float(Fraction(window.duty_max_counts, window.period_counts)):.1f} %)",
        "timer_clock_text": f"{float(clk) / 1e6:g} MHz",
        "current_watch_rails": watch.rails,
        "current_watch_both": watch.ltr > 0 and watch.htr < adc_max,
        "current_watch_low": watch.ltr > 0,
        "current_watch_high": watch.htr < adc_max,
        "current_watch_us": f"{watch.conversion_us:.2f} us",
    }

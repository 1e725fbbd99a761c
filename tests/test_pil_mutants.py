"""Port mutants on the emulated drive: each plants one fault in a copy of the generated
port (the generator's output edited, then linked), and a PIL scenario or invariant of
emulation/pil/scenarios.py must notice it. The unmutated port passes the same scenarios
(tests/test_pil_scenarios.py)."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import pytest

from codegen.spec_loader import load_spec
from emulation.pil.build import checked_in, generate, link_mutant
from emulation.pil.scenarios import SCENARIOS, run_scenario

ROOT = Path(__file__).resolve().parents[1]
PAPER = ROOT / "spec" / "paper_motor.yaml"
PAPER_IR = ROOT / "spec" / "paper_motor_improved_r.yaml"
HUB = ROOT / "tests" / "fixtures" / "specs" / "hub_motor_46p.yaml"
SHORT_RATED = ROOT / "tests" / "fixtures" / "pil" / "short_rated_mid_range.yaml"
IR_5K = ROOT / "tests" / "fixtures" / "odd" / "pwm5k_improved_r.yaml"
SHORT_PREFERRED = ROOT / "tests" / "fixtures" / "pil" / "paper_short_preferred.yaml"
SHORT_16P = ROOT / "tests" / "fixtures" / "odd" / "short_sector_5k_16p.yaml"
PORT = "c/stm32f103_port.c"
#: port_refuse's test of a refused edge's part sector (shorter than a rotor makes after
#: the last right interval), and the same with it gone
PART_SECTOR_GUARD = (
    "            if ((bounce != 0u) || ((measured < port_plausible_after(port.timed_period)) &&"
)
PART_SECTOR_GUARD_OFF = "            if ((bounce != 0u) || ((measured < 1u) &&"
HEADER = "c/stm32f103_port.h"


@dataclass(frozen=True)
class Mutant:
    name: str
    file: str
    old: str
    new: str
    spec: Path
    scenario: str  # the scenario that must report a problem
    caught_by: str  # the problem's text, as the scenario words it
    #: further (old, new) edits of the same file: a guard another one shadows, mutated
    #: with the one in front of it
    also: tuple[tuple[str, str], ...] = ()


MUTANTS = (
    Mutant(
        # the paper motor's K = 6166864 (T B at or below it: all-off may rectify, for k_e
        # 10 % high and a rotor up to 1/0.95 faster than its interval says) 10 % low: at
        # 24 V all-off is chosen up to 4879 rpm, where the worst motor rectifies from 4622
        "rectifying product 10 % low: all-off chosen just above the speed it may rectify from",
        HEADER,
        "#define BLDC_PORT_RECTIFYING_PRODUCT ",
        "#define BLDC_PORT_RECTIFYING_PRODUCT 5550178u",
        PAPER,
        "above_rectifying",
        "not the short circuit",
    ),
    Mutant(
        # ... 10 % high: at 24 V the short chosen from 3992 rpm, where all-off is the spec's
        # up to 4391 rpm even read as 1/0.95 faster
        "rectifying product 10 % high: the short chosen below the speed all-off may rectify from",
        HEADER,
        "#define BLDC_PORT_RECTIFYING_PRODUCT ",
        "#define BLDC_PORT_RECTIFYING_PRODUCT 6783550u",
        PAPER,
        "below_rectifying",
        "not all off",
    ),
    Mutant(
        # the fixture prefers the short circuit, within its 150 A rating up to 2216 rpm
        # (T >= 4072 ticks: 3869 for a rotor up to 1/0.95 faster than T says); 10 %
        # short: the short chosen up to 2339 rpm, over the rating
        "short's rated interval 10 % short: the short chosen above the speed of its rating",
        HEADER,
        "#define BLDC_PORT_SHORT_VALID_PERIOD ",
        "#define BLDC_PORT_SHORT_VALID_PERIOD 3665u",
        SHORT_RATED,
        "above_short_rating",
        "not all off",
    ),
    Mutant(
        # ... 25 % long: all-off from 1684 rpm, where the spec prefers the rated short
        "short's rated interval 25 % long: all-off chosen where the spec's rated short is due",
        HEADER,
        "#define BLDC_PORT_SHORT_VALID_PERIOD ",
        "#define BLDC_PORT_SHORT_VALID_PERIOD 5090u",
        SHORT_RATED,
        "below_short_rating",
        "not the short circuit",
    ),
    Mutant(
        # a wrapped Hall interval (no interval yet after start-up) read as slow: all-off,
        # which rectifies into a low bus while the rotor turns at 4900 rpm
        "unknown speed taken as slow: all-off before the first Hall interval",
        PORT,
        "? BLDC_PORT_TIM3_ARR - from",
        "? 0u - from /* mutant: the wrapped interval all-off */",
        PAPER,
        "under_voltage_at_start",
        "not the short circuit",
    ),
    Mutant(
        "clock security system never enabled: a crystal failing while braking stops the chip",
        "firmware/system_stm32f103.c",
        "    RCC->CR |= RCC_CR_CSSON;",
        "    (void)0; /* mutant: no CSS */",
        PAPER,
        "hse_fails_running",
        "CSSON = 0",
    ),
    Mutant(
        "the clock failure not recorded: the NMI leaves no fault for the application",
        PORT,
        "    port_request_trip(BLDC_FAULT_CLOCK);",
        "    (void)0; /* mutant: no CLOCK fault */",
        PAPER,
        "hse_fails_running",
        "expected CLOCK",
    ),
    Mutant(
        "Hall timer's prescaler one low: TIM3 ticks 1.4 % fast, every speed read slow",
        HEADER,
        "#define BLDC_PORT_TIM3_PSC ",
        "#define BLDC_PORT_TIM3_PSC 70u /* mutant: 72 MHz / 71 */",
        PAPER,
        "over_voltage",
        "TIM3 ticks every 71 ticks",
    ),
    Mutant(
        "PWM period one count long: 3601 counts at 20 kHz's 3600",
        HEADER,
        "#define BLDC_PORT_TIM1_ARR ",
        "#define BLDC_PORT_TIM1_ARR 3600u /* mutant: one count long */",
        PAPER,
        "over_voltage",
        "duty 1 is 3601 counts",
    ),
    Mutant(
        "current sample 2 counts late: the trigger (CCR4) at 3538 of 3600",
        HEADER,
        "#define BLDC_PORT_TIM1_CCR4 ",
        "#define BLDC_PORT_TIM1_CCR4 3538u /* mutant: 2 counts late */",
        PAPER,
        "over_voltage",
        "inside the window as the chip may take it",
    ),
    Mutant(
        # RM0008 14.4.7: counting down, OC4REF (PWM mode 1) is inactive only while
        # CNT > CCR4, so CCR4 = ARR holds it at 1: no rising edge, no trigger, no sample
        # (the timer model had raised it one count after the peak, and the port had
        # CCR4 = ARR: on the chip its current loop never ran)
        "centre-aligned current trigger at CCR4 = ARR: OC4REF held at 1, no sample at all",
        HEADER,
        "#define BLDC_PORT_TIM1_CCR4 ",
        "#define BLDC_PORT_TIM1_CCR4 900u /* mutant: = ARR, 40 kHz centre-aligned */",
        SHORT_RATED,
        "under_voltage",
        "no injected sequence ended",
    ),
    Mutant(
        "current sample time 13.5 ADC cycles, not the spec's 7.5",
        HEADER,
        "#define BLDC_PORT_ADC_SMPR2 ",
        "#define BLDC_PORT_ADC_SMPR2 ((2u << ADC_SMPR2_SMP0_Pos) | (1u << ADC_SMPR2_SMP1_Pos))"
        " /* mutant: 13.5 cycles on the current channel */",
        PAPER,
        "over_voltage",
        "the current loop's sample of channel 0",
    ),
    Mutant(
        "current sample time 1.5 ADC cycles, not the spec's 7.5: a clean but short window",
        HEADER,
        "#define BLDC_PORT_ADC_SMPR2 ",
        "#define BLDC_PORT_ADC_SMPR2 ((0u << ADC_SMPR2_SMP0_Pos) | (1u << ADC_SMPR2_SMP1_Pos))"
        " /* mutant: 1.5 cycles on the current channel */",
        PAPER,
        "over_voltage",
        "ADC1 samples channel 0 for 1.5 ADC cycles",
    ),
    Mutant(
        "invalid-Hall safe state dropped (the EXTI's trip on code 0/7 without an edge)",
        PORT,
        "port_trip(anchor, BLDC_FAULT_HALL_INVALID);",
        "(void)0;",
        PAPER,
        "hall_unplugged",
        "faults",
    ),
    Mutant(
        "cycle counter never started: the Hall lines' confirmation waits for ever",
        PORT,
        "    DWT->CTRL |= DWT_CTRL_CYCCNTENA_Msk;\n",
        "",
        PAPER,
        "hall_unplugged",
        "faults",
    ),
    Mutant(
        "Hall lines' confirmation dropped: the EXTI trips on its first read",
        PORT,
        "    if (((pins - 1u) > 5u) && ((port.faults & BLDC_FAULT_HALL_INVALID) == 0u)) {",
        "    if ((port.faults & BLDC_FAULT_HALL_INVALID) == (pins & 0u)) { /* mutant: no confirming read */",
        PAPER,
        "hall_spike",
        "faults",
    ),
    Mutant(
        "ADC2's analog watchdog off: nothing sees the current rail",
        PORT,
        "    ADC2->CR1 = BLDC_PORT_ADC2_CR1;\n    ADC2->CR2",
        "    ADC2->CR1 = 0u;\n    ADC2->CR2",
        PAPER,
        "current_sensor_low",
        "expected CURRENT_SENSOR",
    ),
    Mutant(
        "wrong CCER bits: phase 2's enables left out of the safe state's CCER",
        PORT,
        "TIM_CCER_CC2E | TIM_CCER_CC2NE |",
        "",
        HUB,
        "break_input",
        "no safe state",
    ),
    Mutant(
        "EGR bit changed: UG without COMG at each commutation",
        PORT,
        "#define BLDC_PORT_EGR_COMMUTATE (TIM_EGR_COMG | TIM_EGR_UG)",
        "#define BLDC_PORT_EGR_COMMUTATE (TIM_EGR_UG)",
        PAPER,
        "over_voltage",
        "did not commutate",
    ),
    Mutant(
        "preload disabled: OC1PE cleared",
        PORT,
        "TIM_CCMR1_OC1PE |",
        "",
        PAPER,
        "over_voltage",
        "no preload",
    ),
    Mutant(
        "interrupt priorities swapped: Hall edge and timing handler",
        PORT,
        "NVIC_SetPriority(TIM1_TRG_COM_IRQn, BLDC_PORT_TIMING_PRIORITY);",
        "NVIC_SetPriority(TIM1_TRG_COM_IRQn, BLDC_PORT_HALL_PRIORITY);\n"
        "    NVIC_SetPriority(TIM3_IRQn, BLDC_PORT_TIMING_PRIORITY);",
        PAPER,
        "over_voltage",
        "preempted",
    ),
    Mutant(
        "dead time zeroed",
        HEADER,
        "#define BLDC_PORT_TIM1_DTG ",
        "#define BLDC_PORT_TIM1_DTG 0x00u /* mutant */",
        HUB,
        "break_input",
        "dead time",
    ),
    Mutant(
        "over-voltage threshold off by much: the analog watchdog misses a bus 10 % over",
        HEADER,
        "#define BLDC_PORT_ADC_HTR ",
        "#define BLDC_PORT_ADC_HTR 3900u /* mutant */",
        PAPER,
        "over_voltage_between_samples",
        "latency",
    ),
    Mutant(
        "safe-state region inverted: all-off where it rectifies, the short where all-off is preferred",
        PORT,
        "return (uint32_t)((period - port.all_off_from) >= port.all_off_span);",
        "return (uint32_t)((period - port.all_off_from) < port.all_off_span);",
        PAPER,
        "under_voltage",
        "not the short circuit",
    ),
    Mutant(
        "watchdog refreshed whether or not the current loop runs",
        "firmware/main.c",
        "        if (bldc_port_alive() != 0u) {\n            bldc_system_watchdog_refresh();\n        }",
        "        (void)bldc_port_alive();\n        bldc_system_watchdog_refresh();",
        PAPER,
        "current_loop_stalls",
        "no watchdog reset",
    ),
    Mutant(
        "watchdog never refreshed: the first time-out must already be the spec's",
        "firmware/main.c",
        "            bldc_system_watchdog_refresh();\n",
        "            (void)0;\n",
        PAPER,
        "current_loop_stalls",
        "WatchdogResetError",
    ),
    Mutant(
        "watchdog sized at the slowest LSI: half the spec's time-out at the fastest",
        "firmware/system_stm32f103.c",
        "#define BLDC_SYSTEM_IWDG_RLR 299u",
        "#define BLDC_SYSTEM_IWDG_RLR 149u /* mutant */",
        PAPER,
        "current_loop_stalls",
        "sooner than firmware.watchdog_timeout",
    ),
    Mutant(
        "reversal refusal dropped: a reverse edge hands a leg over in one COM event",
        PORT,
        "const uint32_t refused = too_fast | (tim1->CCER & PORT_RECORD_FORBIDDEN(record));",
        "const uint32_t refused = too_fast | (0u & tim1->CCER & PORT_RECORD_FORBIDDEN(record));",
        HUB,
        "reversal",
        "ticks after its partner turned off",
    ),
    Mutant(
        # the port before the fix: a refused edge turned every switch off, whatever the
        # region (the paper motor at 4408 rpm on 20.2 V: rectifying until the next edge)
        "refusal all-off in every region: all-off where it rectifies, MOE set, no fault",
        PORT,
        "    if (port_idle_short(period) == 0u) {",
        "    if ((port_idle_short(period) & 0u) == 0u) { /* mutant: all-off */",
        PAPER,
        "hall_back_step",
        "not the short circuit",
    ),
    Mutant(
        # the refusal hands a phase from one switch to the other with no wait: an upper
        # switch on 36 ticks after its partner turned off, the instructions between
        # alone (dead time 72 ticks: 1 us; on the paper improved_r motor's 500 ns those
        # 36 ticks are just enough, since the machine times each access within its
        # block, and the mutant there breaks nothing)
        "refusal's dead-time wait dropped: into and out of its short with no dead time",
        PORT,
        "#define BLDC_PORT_DEAD_TIME_CYCLES ",
        "#define BLDC_PORT_DEAD_TIME_CYCLES 1u /* mutant: no wait */",
        IR_5K,
        "hall_back_step",
        "after its partner turned off",
    ),
    Mutant(
        "Hall time-out interrupt never enabled: the current loop's next look finds the wrap",
        PORT,
        "    tim3->DIER = BLDC_PORT_HALL_INTERRUPTS | TIM_DIER_UIE | TIM_DIER_CC3IE;\n}",
        "    tim3->DIER = BLDC_PORT_HALL_INTERRUPTS;\n}",
        PAPER,
        "rotor_stops",
        "found by the current loop",
    ),
    Mutant(
        # frozen Hall lines at 2600 rpm trip at the counter's wrap, 65 ms after the last
        # edge: not by 4 intervals (15.4 ms) and a PWM period, the scenario's wait
        "Hall time-out only at the counter's wrap: frozen Hall lines brake on for 65 ms",
        HEADER,
        "#define BLDC_PORT_HALL_TIMEOUT_PERIOD_MAX ",
        "#define BLDC_PORT_HALL_TIMEOUT_PERIOD_MAX 0u",
        PAPER,
        "rotor_stops",
        "MOE was never cleared",
    ),
    Mutant(
        # the forward edge after a refused step back, 2.1 ms into an 12 ms sector, sets
        # the time-out to 4 x 2.1 ms: it trips before the rotor's next edge
        "Hall time-out from the part sector after a refused edge: a rocking rotor trips",
        PORT,
        "(uint32_t)port.period | (0u - (uint32_t)port.after_refusal);",
        "(uint32_t)port.period;",
        PAPER,
        "hall_rocks_early",
        "faults ['HALL_TIMEOUT'], expected none",
    ),
    Mutant(
        # a 3 us bounce read as a rotor a thousand times the top speed, beyond the short's
        # rating: all-off at 4950 rpm on 24 V, where it rectifies from 4622 rpm
        "bounce interval kept for the safe state: all-off where it rectifies",
        PORT,
        "                port.period = port.timed_period; /* the rotor's: the last right edge's */",
        "                /* the interval measured kept */",
        SHORT_PREFERRED,
        "hall_bounce",
        "not the short circuit",
    ),
    Mutant(
        # every interval past twice the top speed's taken for a bounce: the safe state of
        # 2 x held at 3 x, all-off, where it rectifies into 30 V from 2.27 x
        "bounce judged against half the top speed's interval: a rotor past 2 x frozen",
        PORT,
        "        } else if (captured < port_bounce_below(held)) {",
        "        } else if (captured < (BLDC_PERIOD_MIN_TICKS >> 1)) {",
        SHORT_16P,
        "overhauling",
        "not the short circuit",
    ),
    Mutant(
        # a 100 ns comparator pulse while main clears an over-current, after the pin's read
        "break flag cleared after the clear read the pin: a pulse then is lost, re-armed",
        PORT,
        "        TIM1->DIER = TIM_DIER_COMIE | TIM_DIER_BIE;",
        "        TIM1->SR = ~TIM_SR_BIF;\n        TIM1->DIER = TIM_DIER_COMIE | TIM_DIER_BIE;",
        PAPER,
        "break_during_clear",
        "was lost",
    ),
    Mutant(
        # the first bounce edge's half sector read as twice the speed, beyond the rating
        # the refused edge's part-sector guard (port_refuse) keeps the bounce's half
        # sector out of the interval first: mutated too, so this guard behind it is tested
        "faulted Hall interval under the top speed's: all-off where it rectifies",
        PORT,
        "        port.period = (uint16_t)((shortest < BLDC_PERIOD_MIN_TICKS) ? BLDC_PERIOD_MIN_TICKS",
        "        port.period = (uint16_t)((shortest < 1u) ? BLDC_PERIOD_MIN_TICKS",
        SHORT_PREFERRED,
        "hall_unplugged_bouncing",
        "safe state",
        also=((PART_SECTOR_GUARD, PART_SECTOR_GUARD_OFF),),
    ),
    Mutant(
        # a 2 us glitch at 0.6 of a sector at 4950 rpm: read as 8250 rpm, beyond the
        # short's 5359 rpm rating, all-off where all-off rectifies from 4622 rpm
        "part sector of a refused edge read as the rotor's: all-off where it rectifies",
        PORT,
        PART_SECTOR_GUARD,
        PART_SECTOR_GUARD_OFF,
        SHORT_PREFERRED,
        "hall_glitch_late",
        "not the short circuit",
    ),
    Mutant(
        # a rotor braking at the machine's limit makes its next edge 2.35 intervals on
        "Hall time-out of 2 intervals: a rotor braking at the machine's limit trips",
        HEADER,
        "#define BLDC_PORT_HALL_TIMEOUT_SHIFT ",
        "#define BLDC_PORT_HALL_TIMEOUT_SHIFT 1u",
        PAPER,
        "hardest_braking",
        "faults ['HALL_TIMEOUT'], expected none",
    ),
    Mutant(
        "timing slot published before it is filled: an edge in between applies a torn timing",
        PORT,
        "    bldc_timing_t *const next = port_other_slot(published);\n",
        "    bldc_timing_t *const next = port_other_slot(published);\n    port.timing = next;\n",
        PAPER,
        "over_voltage",
        "in the slot published then",
    ),
    Mutant(
        "current loop below the Hall edge: ADC1_2 at the timing handler's priority",
        PORT,
        "NVIC_SetPriority(ADC1_2_IRQn, BLDC_PORT_HALL_PRIORITY);",
        "NVIC_SetPriority(ADC1_2_IRQn, BLDC_PORT_TIMING_PRIORITY);",
        PAPER,
        "hall_off_marks",
        "share one level",
    ),
    Mutant(
        # the gate at one PWM period: on a noisy bus a bus change almost every period
        "bus changes ungated: one a PWM period on a noisy bus",
        HEADER,
        "#define BLDC_PORT_BUS_MIN_PERIODS ",
        "#define BLDC_PORT_BUS_MIN_PERIODS 1u",
        PAPER,
        "bus_noise",
        "more than one per top-speed sector",
    ),
    Mutant(
        # arming as before: all-off with MOE set, then the short through the dead time
        # (2.7 us rectifying on a 400 V motor and on the paper motor; a hunt)
        "clear arms all-off first: MOE up into all-off where all-off rectifies",
        PORT,
        "    if (port_idle_short(port.period) != 0u) {\n        /* Where all-off rectifies",
        "    if (0u) {\n        /* Where all-off rectifies",
        PAPER,
        "clear_where_all_off_rectifies",
        "after the clear, before the next edge",
    ),
)


def _mutate(mutant: Mutant) -> Callable[[Path], None]:
    def edit(generated: Path) -> None:
        path = generated / mutant.file
        text = path.read_text(encoding="utf-8")
        assert text.count(mutant.old) >= 1, f"{mutant.name}: {mutant.old!r} not in {mutant.file}"
        if mutant.old.endswith(" "):  # a #define: the whole line
            lines = text.splitlines(keepends=True)
            lines = [mutant.new + "\n" if ln.startswith(mutant.old) else ln for ln in lines]
            text = "".join(lines)
        else:
            text = text.replace(mutant.old, mutant.new, 1)
        for old, new in mutant.also:
            assert text.count(old) == 1, f"{mutant.name}: {old!r} not once in {mutant.file}"
            text = text.replace(old, new)
        path.write_text(text, encoding="utf-8")

    return edit


@pytest.fixture(scope="module")
def generated(tmp_path_factory: pytest.TempPathFactory) -> Callable[[Path], Path]:
    """Each spec generated once, when a mutant of it first runs (a worker that runs no
    hub mutant generates no hub motor); every mutant edits a copy."""
    folders: dict[Path, Path] = {}

    def of(spec: Path) -> Path:
        if spec not in folders:
            made = checked_in(spec) or generate(spec, tmp_path_factory.mktemp(spec.stem) / "g")
            folders[spec] = made
        return folders[spec]

    return of


@pytest.mark.parametrize("mutant", MUTANTS, ids=[m.name.split(":")[0] for m in MUTANTS])
def test_each_port_mutant_should_be_caught_by_a_scenario(
    mutant: Mutant, generated: Callable[[Path], Path], tmp_path: Path
) -> None:
    elf = link_mutant(generated(mutant.spec), tmp_path / "mutant", _mutate(mutant))
    spec = load_spec(str(mutant.spec))
    scenario = next(s for s in SCENARIOS if s.key == mutant.scenario)
    problems = run_scenario(elf, spec, scenario).problems
    assert any(mutant.caught_by in p for p in problems), problems

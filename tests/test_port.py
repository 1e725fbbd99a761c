"""The STM32F103 port: its numbers, its dead-time code, and its C on target and host.

The port is compiled against a stub of the core's header (the contract only), for the
Cortex-M3 with warnings as errors, and its object code is checked for library division
and floating-point helpers. On the host, the same source runs against fake register
blocks, so the register values of each commutation step can be checked against
RM0008 without hardware.
"""

from __future__ import annotations

import dataclasses
import math
import re
import shutil
import subprocess
from fractions import Fraction
from pathlib import Path

import pytest

from codegen import port
from codegen.build_firmware import CFLAGS
from codegen.port_drive import trigger_within
from codegen.spec_loader import load_spec
from codegen.spec_model import Spec
from emulation.pil.safe_state import said_line_emf_v, short_rated_speed
from verify.unity_run import WARNINGS as HOST_WARNINGS

ROOT = Path(__file__).resolve().parents[1]
SPEC = ROOT / "spec" / "paper_motor.yaml"
ARM_GCC = shutil.which("arm-none-eabi-gcc")
ARM_OBJDUMP = shutil.which("arm-none-eabi-objdump")
HOST_CC = shutil.which("cc") or shutil.which("gcc")

STUB_CORE_HEADER = """\
/* Stub of the generated core's header: the contract only. bldc_commutation_timing()
 * records its arguments and returns what the harness scripted, so the port calls it
 * (BLDC_PORT_CORE_OUT_OF_LINE) instead of compiling the core's definitions in. */
#ifndef BLDC_COMMUTATION_H
#define BLDC_COMMUTATION_H
#include <stdint.h>
#define BLDC_PORT_CORE_OUT_OF_LINE 1
#define BLDC_PWM_PERIOD_COUNTS   {period}u
#define BLDC_EDGE_NONE           0xFFu
#define BLDC_EDGE_COUNT          12u
#define BLDC_PERIOD_NEVER        0x10000u
#define BLDC_PERIOD_MIN_TICKS    {period_min}u
#define BLDC_FLAG_INPUT_SATURATED 0x04u
#define BLDC_BUS_CODE_MAX        {bus_max}u
typedef struct {{
    uint32_t x_numerator;
    uint32_t high_speed_period;
    int32_t time_numerator;
    uint32_t period_min;
    uint32_t bus_code;
    uint32_t flags;
}} bldc_bus_t;
typedef struct {{
    uint32_t period_min;
    uint16_t turn_on_compare;
    uint16_t turn_off_compare;
    uint16_t commutation_ticks;
    uint16_t flags;
}} bldc_timing_t;
bldc_bus_t bldc_bus_condition(uint32_t bus_code);
bldc_timing_t bldc_commutation_timing(const bldc_bus_t *bus, uint32_t period_ticks,
                                      uint32_t current_adc, uint32_t main_duty_counts);
#endif
"""


@pytest.fixture(scope="module")
def spec() -> Spec:
    return load_spec(SPEC)


def _write_port(directory: Path, spec: Spec, period: int | None = None) -> None:
    """The port's files, the real current loop (header and source) and a stub of the
    core's header (its contract only)."""
    from codegen.control.current_loop import render_loop_files
    from codegen.derivation import derive
    from codegen.fixedpoint.scaling import scaling

    sc = scaling(spec, derive())
    for name, text in port.render_port_files(spec).items():
        (directory / name).write_text(text, encoding="utf-8")
    for name, text in render_loop_files(spec).items():
        if name.startswith("c/"):
            (directory / name[2:]).write_text(text, encoding="utf-8")
    full_scale = sc.period_counts if period is None else period
    (directory / "bldc_commutation.h").write_text(
        STUB_CORE_HEADER.format(
            period=full_scale, bus_max=sc.bus_code_max, period_min=sc.period_min_ticks
        ),
        encoding="utf-8",
    )


def _defines(ctx: dict[str, object]) -> dict[str, str]:
    return {d["name"]: d["value"] for d in ctx["defines"]}  # type: ignore[attr-defined]


# ------------------------------------------------------------------- dead-time code


@pytest.mark.parametrize(
    ("dead_time_ns", "dtg", "ticks"),
    [
        (0, 0x00, 0),
        (500, 0x24, 36),  # DTG[7] = 0: 36 t_DTS at 72 MHz
        (1750, 0x7E, 126),  # last step of range 1 exactly
        (2000, 0x88, 144),  # DTG[7:6] = 10: (64 + 8) x 2
        (5000, 0xCD, 360),  # DTG[7:5] = 110: (32 + 13) x 8
        (10000, 0xED, 720),  # DTG[7:5] = 111: (32 + 13) x 16
        (14000, 0xFF, 1008),  # the longest: (32 + 31) x 16
    ],
)
def test_dead_time_should_encode_per_rm0008(dead_time_ns: int, dtg: int, ticks: int) -> None:
    code = port.encode_dead_time(Fraction(dead_time_ns, 10**9), Fraction(72_000_000))
    assert (code.dtg, code.dts_ticks) == (dtg, ticks)
    assert code.programmed_s == Fraction(ticks, 72_000_000)


def test_dead_time_should_round_up_never_down() -> None:
    code = port.encode_dead_time(Fraction(100, 10**9), Fraction(72_000_000))  # 7.2 t_DTS
    assert (code.dtg, code.dts_ticks) == (8, 8)
    code = port.encode_dead_time(Fraction(3600, 10**9), Fraction(72_000_000))  # 259.2 t_DTS
    assert (code.dtg, code.dts_ticks) == (0xC1, 264)  # range 3 steps by 8


def test_dead_time_encoding_should_be_minimal_for_every_tick_count() -> None:
    one_hz = Fraction(1)  # at 1 Hz a dead time in seconds is a count of t_DTS
    for wanted in range(port.DTG_MAX_TICKS + 1):
        code = port.encode_dead_time(Fraction(wanted), one_hz)
        assert code.dts_ticks >= wanted
        assert port.dtg_dead_time_ticks(code.dtg) == code.dts_ticks
        shorter = [c for c in range(256) if wanted <= port.dtg_dead_time_ticks(c) < code.dts_ticks]
        assert not shorter


def test_unrepresentable_dead_time_should_raise_a_clear_error() -> None:
    with pytest.raises(ValueError, match=r"15 us .* not representable .*1008 t_DTS = 14 us"):
        port.encode_dead_time(Fraction(15, 10**6), Fraction(72_000_000))


# ------------------------------------------------------------------- render context


def test_context_should_give_the_paper_motor_timer_numbers(spec: Spec) -> None:
    ctx = port.port_context(spec)
    d = _defines(ctx)
    assert d["BLDC_PORT_TIM1_PSC"] == "0u"
    assert d["BLDC_PORT_TIM1_ARR"] == "3599u"
    assert d["BLDC_PORT_TIM1_CMS"] == "0u"
    assert d["BLDC_PORT_DUTY_FULL_SCALE"] == "3600u"
    assert d["BLDC_PORT_TIM1_DTG"] == "0x24u"
    assert d["BLDC_PORT_TIM3_PSC"] == "71u"
    assert d["BLDC_PORT_TIM3_ARR"] == "65535u"
    comments = {x["name"]: x["comment"] for x in ctx["defines"]}  # type: ignore[attr-defined]
    assert comments["BLDC_PORT_TIM1_ARR"] == "20 kHz edge-aligned at 72 MHz"


def test_centre_aligned_pwm_should_halve_the_reload(spec: Spec) -> None:
    centre = dataclasses.replace(
        spec, inverter=dataclasses.replace(spec.inverter, pwm_alignment="center")
    )
    d = _defines(port.port_context(centre))
    assert d["BLDC_PORT_TIM1_ARR"] == "1800u"
    assert d["BLDC_PORT_DUTY_FULL_SCALE"] == "1800u"
    assert d["BLDC_PORT_TIM1_CMS"] == "1u"


def test_hall_clock_without_a_whole_prescaler_should_raise(spec: Spec) -> None:
    with pytest.raises(ValueError, match="whole prescaler"):
        port.port_context(spec, hall_timer_input_clock_hz=Fraction(1_500_000))


def test_every_port_file_should_start_with_its_provenance(spec: Spec) -> None:
    files = port.render_port_files(spec)
    assert sorted(files) == ["stm32f103_port.c", "stm32f103_port.h", "stm32f103_regs.h"]
    for name, text in files.items():
        first = text.splitlines()[0]
        assert first.startswith(
            f"/* Generated from template templates/c/{name}.j2 with spec spec/paper_motor.yaml"
        )
        assert spec.sha256 in first
    assert files == port.render_port_files(spec)  # byte-stable


# ------------------------------------------------------------------- target compile


def _compile_arm(directory: Path, *extra: str) -> subprocess.CompletedProcess[str]:
    assert ARM_GCC is not None
    return subprocess.run(
        [ARM_GCC, *CFLAGS, *extra, "-c", "stm32f103_port.c", "-o", "stm32f103_port.o"],
        cwd=directory,
        capture_output=True,
        text=True,
    )


def _port_disassembly(folder: Path) -> str:
    """The port compiled for the Cortex-M3 in `folder`, disassembled with relocations."""
    run = _compile_arm(folder)
    assert run.returncode == 0, run.stderr
    assert ARM_OBJDUMP is not None
    return subprocess.run(
        [ARM_OBJDUMP, "-d", "-r", "stm32f103_port.o"],
        cwd=folder,
        capture_output=True,
        text=True,
        check=True,
    ).stdout


@pytest.mark.skipif(ARM_GCC is None or ARM_OBJDUMP is None, reason="arm-none-eabi-gcc missing")
def test_port_should_compile_for_cortex_m3_without_division_or_float_helpers(
    tmp_path: Path, spec: Spec
) -> None:
    _write_port(tmp_path, spec)
    dump = _port_disassembly(tmp_path)
    assert "<TIM3_IRQHandler>:" in dump
    assert "<bldc_port_init>:" in dump
    assert "__aeabi_" not in dump
    # hardware divides only for the safe state's interval bound floor(K / B): in the
    # bus-change handler (once per change beyond the hysteresis), in the analog
    # watchdog's trip, after MOE is clear (the bus that tripped), and while faulted for
    # the bus's bound floor(K / T) at the Hall interval (the watchdog's window, MOE
    # clear), and the clear in thread mode (the region of the bus's last sample); no
    # other handler divides
    divides = [
        name
        for name, body in re.findall(r"<(\w+)>:\n(.*?)(?:\n\n|\Z)", dump, re.S)
        for _ in re.findall(r"\b[us]div\b", body)
    ]
    bus_handler = port.port_context(spec)["handler"]["bus"]  # type: ignore[index]
    assert bus_handler in divides and set(divides) <= {
        bus_handler,
        "port_bus_fault",
        "port_watch_while_faulted",
        "port_clear_masked",  # thread mode, masked: the region of the bus at the clear
    }, divides
    called = set(re.findall(r"R_ARM_THM_(?:CALL|JUMP24)\s+(\w+)", dump))
    # nothing else leaves the object but the core and the current loop's reference (the
    # port's own static functions are its cold paths), and the Hall edge calls neither
    outside = {c for c in called if not c.startswith("port_")}
    assert {"bldc_bus_condition", "bldc_commutation_timing"} <= outside
    assert outside <= {"bldc_bus_condition", "bldc_commutation_timing", "bldc_current_reference"}
    handler = dump[dump.index("<TIM3_IRQHandler>:") :].split("\n\n")[0]
    assert "bldc_" not in handler
    # the current loop runs inline in its interrupt: no call, no divide
    adc = dump[dump.index("<ADC1_2_IRQHandler>:") :].split("\n\n")[0]
    assert "bldc_" not in adc and "div" not in adc


@pytest.mark.parametrize(
    ("path", "inlined"),
    [
        (SPEC, True),
        (ROOT / "tests" / "fixtures" / "specs" / "offset_conventional.yaml", True),
        (ROOT / "spec" / "paper_motor_improved_r.yaml", False),
    ],
    ids=lambda v: v.stem if isinstance(v, Path) else str(v),
)
def test_timing_handler_should_inline_a_straight_line_core(
    path: Path, inlined: bool, tmp_path: Path
) -> None:
    """With the real core beside it, the port compiles bldc_commutation.c's text in and
    its timing handler has bldc_commutation_timing() inlined (the core's two divides run
    in the handler, no call); a core with helpers or loops (improved_r) is called. Either
    way the bus state comes from the core's own bldc_bus_condition()."""
    from codegen.generate import render_all

    assert ARM_GCC is not None and ARM_OBJDUMP is not None
    for name, text in render_all(path).files.items():
        if name.startswith("c/"):
            (tmp_path / name[2:]).write_text(text, encoding="utf-8")
    dump = _port_disassembly(tmp_path)
    assert "__aeabi_" not in dump
    name = port.port_context(load_spec(path))["handler"]["timing"]  # type: ignore[index]
    handler = dump[dump.index(f"<{name}>:") :].split("\n\n")[0]
    called = set(re.findall(r"R_ARM_THM_(?:CALL|JUMP24)\s+(\w+)", handler))
    bus_name = port.port_context(load_spec(path))["handler"]["bus"]  # type: ignore[index]
    update = dump[dump.index(f"<{bus_name}>:") :].split("\n\n")[0]
    assert "bldc_bus_condition" in update
    assert "bldc_bus_condition" not in handler  # the timing handler reads no bus request
    if inlined:
        assert not any("commutation_timing" in c for c in called), called
        assert re.search(r"\budiv\b", handler) and re.search(r"\bsdiv\b", handler)
    else:
        assert "bldc_commutation_timing" in called


def test_port_should_compile_warning_free_on_the_host(tmp_path: Path, spec: Spec) -> None:
    """The same -Werror set as the target build, with the host's gcc (the PRIMASK and
    anchor asm compile there too; the register header maps the peripherals)."""
    assert HOST_CC is not None, "no host C compiler"
    _write_port(tmp_path, spec)
    flags = ["-std=c99", "-Wall", "-Wextra", "-Wconversion", "-Wpedantic", "-Werror", "-O2"]
    run = subprocess.run(
        [HOST_CC, *flags, "-c", "stm32f103_port.c", "-o", "port.o"],
        cwd=tmp_path,
        capture_output=True,
        text=True,
    )
    assert run.returncode == 0, run.stderr


@pytest.mark.skipif(ARM_GCC is None, reason="arm-none-eabi-gcc missing")
def test_port_should_refuse_a_core_with_another_pwm_full_scale(tmp_path: Path, spec: Spec) -> None:
    _write_port(tmp_path, spec, period=3599)
    run = _compile_arm(tmp_path)
    assert run.returncode != 0
    assert "core and port disagree on the PWM full scale" in run.stderr


# ------------------------------------------------------------------- host behaviour
#
# The port compiled for the host against fake register blocks (the generated register
# header with its instances pointed at plain memory), the real current loop, and a stub
# core whose timing the harness scripts. A small NVIC model runs what a handler raised:
# the timing handler after a COM event or a software pend, the break handler after a
# software break (EGR.BG, which also clears MOE as TIM1 does). Each step prints the
# registers and the API's answers; the tests below hold them to RM0008 and the design.

HOST_SHIM = """\
/* Force-included before the port: the generated register header, with the
 * peripheral instances pointing at plain memory instead of the STM32 address map, and
 * the NVIC calls recorded. The ADC's calibration bit is made to read as done (plain
 * memory would hold it set) unless the harness tests a calibration that never ends. */
#include "stm32f103_regs.h"
extern TIM_TypeDef fake_tim1, fake_tim3;
extern RCC_TypeDef fake_rcc;
extern GPIO_TypeDef fake_gpioa, fake_gpiob;
extern ADC_TypeDef fake_adc1, fake_adc2;
extern AFIO_TypeDef fake_afio;
extern EXTI_TypeDef fake_exti;
extern DWT_Type fake_dwt;
extern CoreDebug_Type fake_coredebug;
extern uint32_t fake_cycles;
extern unsigned long fake_nvic_enabled, fake_nvic_pending, fake_nvic_cleared;
extern unsigned fake_nvic_priority[64];
#undef TIM1
#undef TIM3
#undef RCC
#undef GPIOA
#undef GPIOB
#undef ADC1
#undef ADC2
#undef AFIO
#undef EXTI
#undef DWT
#undef CoreDebug
#define DWT (&fake_dwt)
#define CoreDebug (&fake_coredebug)
/* the host's cycle counter: each read a few cycles on */
#define BLDC_PORT_CYCLES() (fake_cycles += 5u)
#define ADC2 (&fake_adc2)
#define AFIO (&fake_afio)
#define EXTI (&fake_exti)
#define TIM1 (&fake_tim1)
#define TIM3 (&fake_tim3)
#define RCC (&fake_rcc)
#define GPIOA (&fake_gpioa)
#define GPIOB (&fake_gpiob)
#define ADC1 (&fake_adc1)
#define NVIC_EnableIRQ(n) (fake_nvic_enabled |= 1ul << (n))
#define NVIC_SetPendingIRQ(n) (fake_nvic_pending |= 1ul << (n))
#define BLDC_PORT_PEND_BUS_WHEN(moved) \
    (fake_nvic_pending |= (unsigned long)((moved) != 0) << TIM1_UP_IRQn)
#define NVIC_ClearPendingIRQ(n) (fake_nvic_cleared |= 1ul << (n))
#define NVIC_SetPriority(n, p) (fake_nvic_priority[(n)] = (p))
#ifndef HARNESS_CALIBRATION_STUCK
#undef ADC_CR2_CAL
#define ADC_CR2_CAL 0u
#endif
"""

#: The peripherals and NVIC state the host builds of the port link against.
FAKE_PERIPHERALS = r"""
TIM_TypeDef fake_tim1, fake_tim3;
RCC_TypeDef fake_rcc;
GPIO_TypeDef fake_gpioa, fake_gpiob;
ADC_TypeDef fake_adc1, fake_adc2;
AFIO_TypeDef fake_afio;
EXTI_TypeDef fake_exti;
DWT_Type fake_dwt;
CoreDebug_Type fake_coredebug;
uint32_t fake_cycles = 0xFFFFFFF0u; /* wraps within the first confirmation */
unsigned long fake_nvic_enabled, fake_nvic_pending, fake_nvic_cleared;
unsigned fake_nvic_priority[64];
"""

HOST_HARNESS = (
    r"""
#include <stdio.h>
#include "stm32f103_port.h"

"""
    + FAKE_PERIPHERALS
    + r"""
static bldc_timing_t stub_next = {BLDC_PERIOD_NEVER, 0u, 0u, 0u, 0u};
/* The stub's flags: a function of all four inputs (test_status_should_be_the_flags_of_the_published_timing). */
#define STUB_FLAGS(bus, period, current, duty) \
    ((uint16_t)(((bus) * 5u + (period) * 7u + (current) * 11u + (duty) * 13u) & 0xFFFFu))
static uint32_t stub_bus_flags;
static uint32_t seen_bus, seen_period, seen_current, seen_duty;
static unsigned timing_runs, bus_runs, break_runs;
static unsigned long raw_egr, raw_sr; /* TIM1 EGR and TIM3 SR as the last TIM3 handler left them */
static int break_active;
static unsigned preempt_bus; /* a bus sample the current loop takes during the next bus change, or 0 */
static void preempt_with_sample(unsigned bus);

bldc_bus_t bldc_bus_condition(uint32_t bus_code)
{
    bldc_bus_t bus = {0u, 0u, 0, 0u, bus_code, stub_bus_flags};
    ++bus_runs;
    if (preempt_bus != 0u) {
        const unsigned sample = preempt_bus;
        preempt_bus = 0u;
        preempt_with_sample(sample);
    }
    return bus;
}

bldc_timing_t bldc_commutation_timing(const bldc_bus_t *bus, uint32_t period_ticks,
                                      uint32_t current_adc, uint32_t main_duty_counts)
{
    seen_bus = bus->bus_code;
    seen_period = period_ticks;
    seen_current = current_adc;
    seen_duty = main_duty_counts;
    ++timing_runs;
    bldc_timing_t out = stub_next;
    out.flags = STUB_FLAGS(bus->bus_code, period_ticks, current_adc, main_duty_counts);
    return out;
}

#define SET(reg, value) (*(volatile uint32_t *)&(reg) = (uint32_t)(value))

/* The Hall pins and the break input (BKIN, PB12): inactive unless break_active. */
static void pins(unsigned code)
{
    const unsigned brk = (break_active != 0) == (BLDC_PORT_BREAK_ACTIVE_HIGH != 0u);
    SET(fake_gpioa.IDR, ((code >> 2) & 1u) << 6 | ((code >> 1) & 1u) << 7);
    SET(fake_gpiob.IDR, (code & 1u) | (brk << 12));
}
static unsigned hall_now = 0u;

/* After a handler at the Hall edge's priority: a software break runs the break
 * handler (TIM1 clears MOE, sets BIF); a COM event with COMIE, or a software pend, runs
 * the timing handler. */
static void settle(void)
{
    for (int round = 0; round < 8; ++round) {
        int ran = 0;
        if ((fake_tim1.EGR & TIM_EGR_BG) != 0u) {
            fake_tim1.EGR &= ~TIM_EGR_BG;
            fake_tim1.BDTR &= ~TIM_BDTR_MOE;
            fake_tim1.SR |= TIM_SR_BIF;
            if ((fake_tim1.DIER & TIM_DIER_BIE) != 0u) {
                ++break_runs;
                %(brk)s();
                ran = 1;
            }
        }
        /* the bus change first: the timing's priority and a lower IRQ number */
        if ((fake_nvic_pending & (1ul << TIM1_UP_IRQn)) != 0u) {
            fake_nvic_pending &= ~(1ul << TIM1_UP_IRQn);
            %(bus)s();
            ran = 1;
        }
        const int com = (fake_tim1.EGR & TIM_EGR_COMG) != 0u && (fake_tim1.DIER & TIM_DIER_COMIE) != 0u;
        const int pended = (fake_nvic_pending & (1ul << TIM1_TRG_COM_IRQn)) != 0u;
        fake_tim1.EGR &= ~(TIM_EGR_COMG | TIM_EGR_UG);
        if (com || pended) {
            fake_nvic_pending &= ~(1ul << TIM1_TRG_COM_IRQn);
            %(timing)s();
            ran = 1;
        }
        if (!ran) {
            break;
        }
    }
}

static void plan(unsigned period_min, unsigned on_cmp, unsigned off_cmp, unsigned ticks)
{
    stub_next.period_min = period_min;
    stub_next.turn_on_compare = (uint16_t)on_cmp;
    stub_next.turn_off_compare = (uint16_t)off_cmp;
    stub_next.commutation_ticks = (uint16_t)ticks;
    fake_nvic_pending |= 1ul << TIM1_TRG_COM_IRQn; /* as a new input would */
    settle();
}

static void edge(unsigned code, unsigned status, unsigned captured, unsigned cnt)
{
    hall_now = code;
    pins(code);
    fake_tim3.CCR1 = captured;
    fake_tim3.CNT = cnt;
    fake_tim3.EGR = 0u;
    fake_tim1.EGR = 0u;
    fake_tim3.SR = status;
    timing_runs = 0u;
    %(hall)s();
    raw_egr = fake_tim1.EGR;
    raw_sr = fake_tim3.SR;
    settle();
}

static void end_of_commutation(void)
{
    fake_tim1.EGR = 0u;
    /* the end mid-period, long after the last injected trigger (whose sequence the loop
     * took): no sequence in flight by the trigger's age (BLDC_PORT_TRIGGER_AGE) */
    fake_tim1.CNT = BLDC_PORT_TIM1_CCR4 / 2u;
    fake_tim3.SR = TIM_SR_CC2IF;
    timing_runs = 0u;
    %(hall)s();
    settle();
}

/* The injected conversions end: every current channel reads `current`, the bus `bus`. */
static void adc_with(unsigned bus, unsigned current, unsigned awd, unsigned tim3_sr)
{
    SET(fake_adc1.JDR1, current); /* read-only to the firmware (__I) */
    SET(fake_adc1.JDR2, current);
    SET(fake_adc1.JDR3, current);
    SET(fake_adc1.JDR4, bus);
    SET(fake_adc1.DR, bus); /* the regular group converts the bus continuously */
    SET(fake_adc2.DR, current); /* ADC2 converts the current continuously */
    /* converting; its watchdog (RM0008 11.3.7, every regular channel with AWDEN) flags
     * a result outside [LTR, HTR], as the port set them */
    fake_adc2.SR = ADC_SR_EOC | ADC_SR_STRT |
                   ((((fake_adc2.CR1 & ADC_CR1_AWDEN) != 0u) &&
                     ((current < fake_adc2.LTR) || (current > fake_adc2.HTR)))
                        ? ADC_SR_AWD
                        : 0u);
    fake_adc1.SR = ADC_SR_JEOC | (awd ? ADC_SR_AWD : 0u);
    fake_tim3.SR = tim3_sr;
    fake_tim1.EGR = 0u;
    %(adc)s();
    settle();
}

static void adc(unsigned bus, unsigned current, unsigned awd, unsigned overflow)
{
    adc_with(bus, current, awd, overflow ? TIM_SR_UIF : 0u);
}

/* BUS_GATE samples at one bus code: a bus change is open again after them. */
static void quiet(unsigned bus, unsigned current)
{
    for (unsigned k = 0u; k < BUS_GATE; ++k) {
        adc(bus, current, 0u, 0u);
    }
}

/* The injected conversions end while the timing handler runs: the current loop
 * preempts it (the same registers as adc_with, the handler at once, no settle: what
 * it pends runs after the timing handler returns). */
static void preempt_with_sample(unsigned bus)
{
    SET(fake_adc1.JDR4, bus);
    SET(fake_adc1.DR, bus);
    fake_adc1.SR = ADC_SR_JEOC;
    %(adc)s();
}

/* A regular conversion of the bus (the group converts it continuously) left the
 * watchdog's window: AWD alone, no injected end; the last injected sample stays. */
static void adc_regular(unsigned bus)
{
    SET(fake_adc1.DR, bus);
    fake_adc1.SR = ADC_SR_AWD;
    fake_tim3.SR = 0u;
    fake_tim1.EGR = 0u;
    %(adc)s();
    settle();
}

/* The watchdog flags the first injected bus conversion (JSQ2 of the DC-link shunt's
 * sequence) at its end: JDR2 holds the new sample, JDR3, JDR4 and DR (the regular
 * conversion the injected sequence reset, RM0008 11.3.9) the bus before the step. */
static void adc_first_bus(unsigned bus, unsigned before)
{
    SET(fake_adc1.JDR2, bus);
    SET(fake_adc1.JDR3, before);
    SET(fake_adc1.JDR4, before);
    SET(fake_adc1.DR, before);
    fake_adc1.SR = ADC_SR_AWD;
    fake_tim3.SR = 0u;
    fake_tim1.EGR = 0u;
    %(adc)s();
    settle();
}

/* ADC2's analog watchdog: a conversion of the current read `raw` (a rail), at any
 * instant; ADC1 has nothing (the interrupt is ADC2's alone). */
static void adc2_rail(unsigned raw)
{
    SET(fake_adc2.DR, raw);
    fake_adc2.SR = ADC_SR_AWD | ADC_SR_EOC | ADC_SR_STRT;
    fake_adc1.SR = 0u;
    fake_tim3.SR = 0u;
    fake_tim1.EGR = 0u;
    %(adc)s();
    settle();
}

/* The Hall lines read `code` and their EXTI pending bits are set (and line 5, not the
 * port's, which must stay pending): the EXTI handler of `vector` runs. */
static void exti(unsigned code, int vector)
{
    hall_now = code;
    pins(code);
    fake_exti.PR = EXTI_PR_PR0 | EXTI_PR_PR6 | EXTI_PR_PR7 | EXTI_PR_PR5;
    fake_tim1.EGR = 0u;
    if (vector == 0) {
        %(line0)s();
    } else {
        %(lines9_5)s();
    }
    settle();
}

/* TIM3 wraps: no Hall edge for the counter's whole range (UIF, with UIE as the port
 * left it). */
static void wrap(void)
{
    fake_tim1.EGR = 0u;
    fake_tim3.SR = TIM_SR_UIF;
    %(hall)s();
    settle();
}

static void brk(void)
{
    break_active = 1;
    pins(hall_now);
    fake_tim1.BDTR &= ~TIM_BDTR_MOE; /* TIM1 clears MOE in hardware */
    fake_tim1.SR = TIM_SR_BIF;
    %(brk)s();
    settle();
}

static void show(const char *step)
{
    /* bldc_port_status() runs the core (the stub) again: it must not count as a run. */
    const uint32_t bus = seen_bus, period = seen_period, current = seen_current, duty = seen_duty;
    const unsigned runs = timing_runs;
    const unsigned long status = (unsigned long)bldc_port_status();
    seen_bus = bus;
    seen_period = period;
    seen_current = current;
    seen_duty = duty;
    timing_runs = runs;
    printf("%%s tim1 ccer=%%lu ccr1=%%lu ccr2=%%lu ccr3=%%lu ccr4=%%lu egr=%%lu bdtr=%%lu cr2=%%lu "
           "dier=%%lu tim3 dier=%%lu ccr2=%%lu ccr3=%%lu egr=%%lu sr=%%lu adc cr1=%%lu htr=%%lu ltr=%%lu in bus=%%lu period=%%lu cur=%%lu duty=%%lu "
           "runs=%%u busruns=%%u breaks=%%u edge egr=%%lu sr=%%lu port faults=%%lu safe=%%lu "
           "current=%%lu status=%%lu nvic cleared=%%lu adc2 cr1=%%lu sr=%%lu exti pr=%%lu\n",
           step, (unsigned long)fake_tim1.CCER, (unsigned long)fake_tim1.CCR1,
           (unsigned long)fake_tim1.CCR2, (unsigned long)fake_tim1.CCR3,
           (unsigned long)fake_tim1.CCR4, (unsigned long)fake_tim1.EGR,
           (unsigned long)fake_tim1.BDTR, (unsigned long)fake_tim1.CR2,
           (unsigned long)fake_tim1.DIER, (unsigned long)fake_tim3.DIER,
           (unsigned long)fake_tim3.CCR2, (unsigned long)fake_tim3.CCR3,
           (unsigned long)fake_tim3.EGR,
           (unsigned long)fake_tim3.SR, (unsigned long)fake_adc1.CR1,
           (unsigned long)fake_adc1.HTR, (unsigned long)fake_adc1.LTR, (unsigned long)seen_bus, (unsigned long)seen_period, (unsigned long)seen_current,
           (unsigned long)seen_duty, timing_runs, bus_runs, break_runs, raw_egr, raw_sr,
           (unsigned long)bldc_port_faults(), (unsigned long)bldc_port_safe_state(),
           (unsigned long)bldc_port_current_code(), status,
           fake_nvic_cleared, (unsigned long)fake_adc2.CR1, (unsigned long)fake_adc2.SR,
           (unsigned long)fake_exti.PR);
    fake_nvic_cleared = 0u;
}

/* A Hall edge into sector `code`, then its commutation end with ADC1's SR and TIM1's
 * counter as given, then two injected sequences of currents `first` and `second`:
 * `<tag>_end`, `<tag>` and `after_<tag>` show the port after each. */
static void end_then_two_samples(unsigned code, uint32_t sr, uint32_t cnt, unsigned first,
                                 unsigned second, const char *tag)
{
    char name[64];
    plan(100u, 900u, 700u, 300u);
    edge(code, TIM_SR_CC1IF, 5000u, 10u);
    fake_tim1.EGR = 0u;
    fake_adc1.SR = sr;
    fake_tim3.SR = TIM_SR_CC2IF;
    timing_runs = 0u;
    fake_tim1.CNT = cnt;
    %(hall)s();
    settle();
    snprintf(name, sizeof name, "%%s_end", tag);
    show(name);
    adc(BUS_OK, first, 0u, 0u);
    show(tag);
    adc(BUS_OK, second, 0u, 0u);
    snprintf(name, sizeof name, "after_%%s", tag);
    show(name);
}

static void clear(const char *step)
{
    char name[64];
    /* The fake SR is plain memory: the port's rc_w0 writes (SR = ~COMIF and the like)
     * set every other bit, BIF too, where TIM1 leaves them. On the chip BIF is set only by
     * a break event, which this harness makes (brk(), a software break): none while the
     * input is inactive and no break is unhandled. */
    if (break_active == 0) {
        fake_tim1.SR &= ~TIM_SR_BIF;
    }
    const unsigned long left = bldc_port_clear_faults();
    snprintf(name, sizeof name, "%%s", step);
    show(name);
    printf("%%s_left clear left=%%lu\n", step, left);
}

int main(int argc, char **argv)
{
    const unsigned *seq = SEQUENCE;
    const unsigned start_faults = (argc > 1) ? 0x100u : 0u; /* argv: start with BLDC_FAULT_CLOCK */
    fake_gpioa.CRL = fake_gpioa.CRH = fake_gpiob.CRL = fake_gpiob.CRH = 0x44444444u; /* reset */
    fake_rcc.CSR = WATCHDOG_RESET ? RCC_CSR_IWDGRSTF : 0u;
    pins(seq[0]);
    hall_now = seq[0];
    bldc_port_init(start_faults);
    printf("init tim1 cr1=%%lu cr2=%%lu ccmr1=%%lu ccmr2=%%lu ccer=%%lu bdtr=%%lu psc=%%lu arr=%%lu "
           "ccr4=%%lu dier=%%lu tim3 cr1=%%lu cr2=%%lu smcr=%%lu ccmr1=%%lu ccer=%%lu dier=%%lu "
           "psc=%%lu arr=%%lu cnt=%%lu adc cr1=%%lu cr2=%%lu jsqr=%%lu sqr1=%%lu sqr3=%%lu smpr1=%%lu smpr2=%%lu htr=%%lu "
           "ltr=%%lu rcc apb2=%%lu apb1=%%lu cfgr=%%lu csr=%%lu gpioa crl=%%lu crh=%%lu gpiob "
           "crl=%%lu crh=%%lu bsrr=%%lu nvic enabled=%%lu hall=%%u adc=%%u brk=%%u timing=%%u bus=%%u port "
           "faults=%%lu\n",
           (unsigned long)fake_tim1.CR1, (unsigned long)fake_tim1.CR2,
           (unsigned long)fake_tim1.CCMR1, (unsigned long)fake_tim1.CCMR2,
           (unsigned long)fake_tim1.CCER, (unsigned long)fake_tim1.BDTR,
           (unsigned long)fake_tim1.PSC, (unsigned long)fake_tim1.ARR,
           (unsigned long)fake_tim1.CCR4, (unsigned long)fake_tim1.DIER,
           (unsigned long)fake_tim3.CR1, (unsigned long)fake_tim3.CR2,
           (unsigned long)fake_tim3.SMCR, (unsigned long)fake_tim3.CCMR1,
           (unsigned long)fake_tim3.CCER, (unsigned long)fake_tim3.DIER,
           (unsigned long)fake_tim3.PSC, (unsigned long)fake_tim3.ARR,
           (unsigned long)fake_tim3.CNT, (unsigned long)fake_adc1.CR1,
           (unsigned long)fake_adc1.CR2, (unsigned long)fake_adc1.JSQR,
           (unsigned long)fake_adc1.SQR1, (unsigned long)fake_adc1.SQR3,
           (unsigned long)fake_adc1.SMPR1, (unsigned long)fake_adc1.SMPR2,
           (unsigned long)fake_adc1.HTR, (unsigned long)fake_adc1.LTR,
           (unsigned long)fake_rcc.APB2ENR, (unsigned long)fake_rcc.APB1ENR,
           (unsigned long)fake_rcc.CFGR, (unsigned long)fake_rcc.CSR,
           (unsigned long)fake_gpioa.CRL, (unsigned long)fake_gpioa.CRH,
           (unsigned long)fake_gpiob.CRL, (unsigned long)fake_gpiob.CRH,
           (unsigned long)fake_gpiob.BSRR, fake_nvic_enabled,
           fake_nvic_priority[TIM3_IRQn], fake_nvic_priority[ADC1_2_IRQn],
           fake_nvic_priority[TIM1_BRK_IRQn], fake_nvic_priority[TIM1_TRG_COM_IRQn],
           fake_nvic_priority[TIM1_UP_IRQn],
           (unsigned long)bldc_port_faults());
    printf("init2 adc2 cr1=%%lu cr2=%%lu sqr1=%%lu sqr3=%%lu smpr1=%%lu smpr2=%%lu htr=%%lu ltr=%%lu "
           "afio exticr1=%%lu exticr2=%%lu exti imr=%%lu rtsr=%%lu ftsr=%%lu nvic exti0=%%u exti9_5=%%u\n",
           (unsigned long)fake_adc2.CR1, (unsigned long)fake_adc2.CR2,
           (unsigned long)fake_adc2.SQR1, (unsigned long)fake_adc2.SQR3,
           (unsigned long)fake_adc2.SMPR1, (unsigned long)fake_adc2.SMPR2,
           (unsigned long)fake_adc2.HTR, (unsigned long)fake_adc2.LTR,
           (unsigned long)fake_afio.EXTICR[0], (unsigned long)fake_afio.EXTICR[1],
           (unsigned long)fake_exti.IMR, (unsigned long)fake_exti.RTSR,
           (unsigned long)fake_exti.FTSR, fake_nvic_priority[EXTI0_IRQn],
           fake_nvic_priority[EXTI9_5_IRQn]);
    settle(); /* the COM event of the initial UG | COMG */
    if (start_faults != 0u || WATCHDOG_RESET || CALIBRATION_STUCK) {
        show("start");
        clear("start_clear");
        adc(BUS_OK, OFFSET, 0u, 0u);
        clear("start_clear_again");
        return 0;
    }

    /* Before any bus sample: the timing is the safe state, the bridge stays off. */
    edge(seq[1], TIM_SR_CC1IF, 5000u, 10u);
    show("nobus");
    /* The first sample pends the timing, which computes the bus state once. */
    adc(BUS_OK, OFFSET, 0u, 0u);
    show("bus");
    bus_runs = 0u;
    quiet(BUS_OK, OFFSET);
    /* The requirement, not the header's macro: one code of ADC noise costs no
     * recomputation, a move of two codes is one (the duties at most one code stale). */
    adc(BUS_OK + 1u, OFFSET, 0u, 0u);
    show("bus_noise");
    adc(BUS_OK + 2u, OFFSET, 0u, 0u);
    show("bus_step");
    /* The next change waits BUS_GATE samples (a noisy bus: one change a top-speed
     * sector at most), however far the bus moves meanwhile; the BUS_GATE-th takes it. */
    for (unsigned k = 1u; k < BUS_GATE; ++k) {
        adc(BUS_OK + 20u, OFFSET, 0u, 0u);
    }
    show("bus_gated");
    adc(BUS_OK + 20u, OFFSET, 0u, 0u);
    show("bus_gate_open");
    quiet(BUS_OK + 20u, OFFSET);
    /* A sample outside the new band taken while the timing handler computes a bus
     * change: it waits for the gate like any other, then a run takes it. */
    bus_runs = 0u;
    preempt_bus = BUS_OK + 40u;
    adc(BUS_OK + 60u, OFFSET, 0u, 0u);
    show("bus_race");
    quiet(BUS_OK + 40u, OFFSET);
    show("bus_race_served");
    quiet(BUS_OK, OFFSET);

    /* Open loop, then forward into the next sector: the first interval after start-up
     * is unknown (UIF from the counter preset). */
    bldc_port_set_main_duty(1500u);
    settle();
    plan(100u, 2000u, 1000u, 300u);
    edge(seq[2], TIM_SR_CC1IF | TIM_SR_UIF, 1234u, 10u);
    show("edge1");
    adc(BUS_OK, OFFSET + 300u, 0u, 0u); /* commutating: no sample of I, no loop */
    show("commutating");
    end_of_commutation();
    show("end1");
    adc(BUS_OK, OFFSET + 300u, 0u, 0u); /* steady: I sampled; open loop leaves the duty */
    show("steady_open");
    /* A bus change while the interval is still unknown (edge1 read a wrapped counter):
     * the bus state is new, the timing waits for the next edge's run, which has the
     * interval (with the sampled current it would commutate for most of a sector). */
    bus_runs = 0u;
    quiet(BUS_OK, OFFSET + 300u); /* the gate open: only the interval keeps it waiting */
    adc(BUS_OK + 3u, OFFSET + 300u, 0u, 0u);
    show("bus_unknown_interval");
    adc(BUS_OK, OFFSET + 300u, 0u, 0u);
    bldc_port_set_main_duty(1700u);
    settle();
    show("duty");
    bldc_port_set_main_duty(60000u);
    settle();
    show("clamp");
    bldc_port_set_main_duty(1700u);
    settle();

    /* Closed loop from the duty in force (no bump): each period's sample sets the
     * steady switch's compare value. */
    bldc_set_braking_current(LOOP_MA);
    for (unsigned k = 0u; k < LOOP_STEPS; ++k) {
        char name[32];
        adc(BUS_OK, loop_measured[k], 0u, 0u);
        snprintf(name, sizeof name, "loop%%u", k);
        show(name);
    }
    /* The timing after the next COM event uses the loop's duty and the held current. */
    plan(100u, 900u, 700u, 300u);
    edge(seq[3], TIM_SR_CC1IF, 5000u, 10u);
    show("edge2");
    end_of_commutation();
    show("end2");

    /* A commutation end 10 counts after an injected trigger whose JSTRT the current
     * loop's SR write had cleared (it ran after that trigger, which the carrier's
     * restart at the Hall edge brought within the sequence before): that sequence,
     * still converting, is not I; the next one is. */
    /* the trigger 10 counts before the end */
    end_then_two_samples(seq[4], 0u, BLDC_PORT_TIM1_CCR4 + 10u, OFFSET + 77u, OFFSET + 78u,
                         "wiped");

    /* A commutation end just after the last sequence's JEOC, its loop step not yet run
     * (the end's priority is the loop's): that one sequence is not I, the next one is.
     * Counting two whenever JEOC was set dropped the one sample a commutation filling
     * its sector leaves before the next edge (a 64-pole-pair centre-aligned motor: the
     * timing ran on a sample two sectors old). */
    end_then_two_samples(seq[5], ADC_SR_JSTRT | ADC_SR_JEOC,
                         BLDC_PORT_TIM1_CCR4 + BLDC_PORT_SEQUENCE_COUNTS + 5u, /* it ended */
                         OFFSET + 81u, OFFSET + 82u, "ended");

    /* The same end where the sequence has just ended with no injection latency (the
     * datasheet gives only its largest, 3 ADC cycles): its JEOC is still the last
     * trigger's. The bound that took the latency for certain counted two here and
     * dropped the next sample too (`make pil` on a 24 kHz centre-aligned and a 20 kHz
     * edge-aligned motor: the timing ran on a sample older than two sectors). */
    end_then_two_samples(seq[0], ADC_SR_JSTRT | ADC_SR_JEOC,
                         BLDC_PORT_TIM1_CCR4 + CONVERSIONS_COUNTS, /* it has just ended */
                         OFFSET + 83u, OFFSET + 84u, "ended_unlatched");

    /* The same sequence ending between the end's read of TIM1's counter and its read of
     * ADC1's SR (the compiled handler has them 5 to 7 cycles apart): the counter reads
     * 8 counts short of its conversions, and its JEOC is set. Still the last trigger's:
     * the next sample is I (an end landing there sector after sector had dropped the one
     * clean sample of two sectors running, `make pil`). */
    end_then_two_samples(seq[1], ADC_SR_JSTRT | ADC_SR_JEOC,
                         BLDC_PORT_TIM1_CCR4 + CONVERSIONS_COUNTS - 8u,
                         OFFSET + 85u, OFFSET + 86u, "ended_between_reads");

    /* A commutation end one count before an injected trigger (SR shows no JSTRT: the
     * injection latency still holds the conversion's start): that trigger fires before
     * the COM event the end stores after its counter read, and its sequence samples the
     * commutating bridge. Not I; the next one is (the end had read SR, then stored the
     * COM event after the age's arithmetic, and taken such a sequence as I). */
    end_then_two_samples(seq[2], 0u, BLDC_PORT_TIM1_CCR4 - 1u, OFFSET + 87u, OFFSET + 88u,
                         "imminent");

    /* ---- faults: each acts now, latches, and holds until its cause is gone ---- */
#define STEADY()                                              \
    do {                                                      \
        plan(100u, 900u, 700u, 300u);                         \
        edge(seq[(hall_index + 1u) %% 6u], TIM_SR_CC1IF, 5000u, 10u); \
        hall_index = (hall_index + 1u) %% 6u;                  \
        end_of_commutation();                                 \
    } while (0)
    unsigned hall_index = 5u;

    adc(BUS_OVER, OFFSET, 1u, 0u);
    show("over_voltage");
    clear("over_voltage_held");
    adc(BUS_OK, OFFSET, 0u, 0u);
    clear("over_voltage_cleared");
    STEADY();

    adc_regular(BUS_OVER); /* between two injected samples, both within the window */
    show("over_voltage_regular");
    clear("over_voltage_regular_held");
    adc(BUS_OK, OFFSET, 0u, 0u);
    clear("over_voltage_regular_cleared");
    STEADY();

    adc_first_bus(BUS_OVER, BUS_OK);
    show("over_voltage_first_bus");
    adc(BUS_OK, OFFSET, 0u, 0u);
    clear("over_voltage_first_bus_cleared");
    STEADY();

    /* The watchdog flags a conversion the interrupt can no longer read: DR and every
     * bus JDRx within the window (a spike shorter than a conversion, the entry held by
     * the Hall edge's handler) */
    adc_first_bus(BUS_OK, BUS_OK);
    show("bus_transient");
    clear("bus_transient_cleared");
    STEADY();

    adc(0u, OFFSET, 1u, 0u);
    show("under_voltage");
    timing_runs = 0u;
    adc(0u, OFFSET, 1u, 0u); /* the regular conversions keep setting AWD */
    show("under_voltage_again");
    adc(0u, OFFSET, 0u, 0u); /* the next sample, its conversions inside the window */
    show("under_voltage_sampled");
    clear("under_voltage_held");
    adc(BUS_OK, OFFSET, 0u, 0u);
    clear("under_voltage_cleared");
    STEADY();

    adc(BUS_OK, 0u, 0u, 0u);
    show("current_sensor");
    clear("current_sensor_held");
    adc(BUS_OK, OFFSET, 0u, 0u);
    clear("current_sensor_cleared");
    STEADY();
    show("steady_again");

    adc2_rail(0u); /* ADC2's watchdog: the current at a rail between two samples */
    show("current_rail_low");
    timing_runs = 0u;
    adc2_rail(0u); /* ADC2 keeps setting AWD at every conversion */
    show("current_rail_low_again");
    clear("current_rail_low_held");
    adc(BUS_OK, OFFSET, 0u, 0u);
    clear("current_rail_low_cleared");
    STEADY();
    adc2_rail(BLDC_PORT_ADC_CODE_MAX);
    show("current_rail_high");
    adc(BUS_OK, OFFSET, 0u, 0u);
    clear("current_rail_high_cleared");
    STEADY();
    show("current_rail_steady");

    adc(BUS_OK, OFFSET, 0u, 1u);
    show("hall_timeout");
    clear("hall_timeout_cleared");
    STEADY();

    wrap(); /* the counter wraps while the bridge switches: the Hall timeout at once */
    show("hall_timeout_wrap");
    clear("hall_timeout_wrap_cleared");
    STEADY();
    show("steady_wrap_armed");
    fake_tim1.EGR = 0u;
    fake_tim3.SR = TIM_SR_CC3IF; /* the Hall time-out's match: no edge by 4 T */
    %(hall)s();
    settle();
    show("hall_timeout_cc3");
    clear("hall_timeout_cc3_cleared");
    STEADY();
    /* A reversal turns every output off (no fault); a wrap then is no timeout: the
     * interrupt goes off and UIF stays for the next edge to read. */
    hall_index = (hall_index + 5u) %% 6u;
    edge(seq[hall_index], TIM_SR_CC1IF, 5000u, 10u);
    wrap();
    show("wrap_idle");
    STEADY();
    /* The same reversal with the rotor at an interval where all-off would rectify into
     * the bus (a forward edge at it: its timing run keeps it as the last right
     * interval, which the refusal takes, not its own, part of a sector): the lower
     * switches on (each alone, at the full scale), MOE kept, no fault; the next valid
     * edge (forward again) commutates from there. */
    plan(100u, 900u, 700u, 300u);
    edge(seq[(hall_index + 1u) %% 6u], TIM_SR_CC1IF, FAST_PERIOD, 10u);
    hall_index = (hall_index + 1u) %% 6u;
    end_of_commutation();
    hall_index = (hall_index + 5u) %% 6u;
    edge(seq[hall_index], TIM_SR_CC1IF, FAST_PERIOD, 10u);
    show("reversal_short");
    edge(seq[(hall_index + 1u) %% 6u], TIM_SR_CC1IF, FAST_PERIOD, 10u);
    hall_index = (hall_index + 1u) %% 6u;
    show("out_of_short");
    end_of_commutation();
    show("out_of_short_end");
    STEADY();

    edge(7u, TIM_SR_CC1IF, 5000u, 10u);
    show("hall_invalid");
    clear("hall_invalid_held");
    pins(seq[hall_index]);
    hall_now = seq[hall_index];
    clear("hall_invalid_cleared");
    STEADY();

    /* Two lines change within TIM3's input filter: no edge; the EXTI sees 7, then 0. */
    exti(7u, 1);
    show("hall_alike_7");
    clear("hall_alike_7_held");
    pins(seq[hall_index]);
    hall_now = seq[hall_index];
    clear("hall_alike_7_cleared");
    STEADY();
    exti(0u, 0);
    show("hall_alike_0");
    pins(seq[hall_index]);
    hall_now = seq[hall_index];
    clear("hall_alike_0_cleared");
    STEADY();
    show("hall_alike_steady");
    /* A valid code on a line's edge (every Hall edge): nothing but the pending bits. */
    exti(seq[hall_index], 1);
    show("hall_line_valid");
    /* The current loop no longer reads the pins: a code 7 it would see trips nothing there. */
    pins(7u);
    adc(BUS_OK, OFFSET, 0u, 0u);
    show("hall_alike_loop");
    pins(seq[hall_index]);
    STEADY();

    edge(seq[(hall_index + 2u) %% 6u], TIM_SR_CC1IF, 5000u, 10u); /* a sector skipped */
    show("hall_sequence");
    clear("hall_sequence_cleared");
    hall_index = (hall_index + 2u) %% 6u;
    STEADY();

    plan(BLDC_PERIOD_MIN_TICKS, 900u, 700u, 300u);
    edge(seq[(hall_index + 1u) %% 6u], TIM_SR_CC1IF, BLDC_PERIOD_MIN_TICKS - 1u, 10u); /* below the minimum period */
    hall_index = (hall_index + 1u) %% 6u;
    show("over_speed");
    clear("over_speed_held"); /* the last interval measured is still over speed */
    fake_tim3.CCR1 = BLDC_PERIOD_MIN_TICKS; /* the rotor slower: the faulted tick takes it */
    adc_with(BUS_OK, OFFSET, 0u, TIM_SR_CC1IF);
    clear("over_speed_cleared");
    STEADY();

    brk();
    show("over_current");
    clear("over_current_held");
    break_active = 0;
    pins(hall_now);
    clear("over_current_cleared");
    STEADY();

    bldc_port_raise_fault(0x800u);
    settle();
    show("external");
    clear("external_cleared");
    STEADY();

    /* The core flags the bus out of range (the analog watchdog missed it): the timing
     * handler asks for a software break, which latches the fault at the break's level. */
    stub_bus_flags = BLDC_FLAG_INPUT_SATURATED;
    adc(BUS_OK - 20u, OFFSET, 0u, 0u);
    show("core_flag");
    stub_bus_flags = 0u;
    adc(BUS_OK, OFFSET, 0u, 0u);
    clear("core_flag_cleared");
    STEADY();

    bldc_port_clock_failure();
    settle();
    show("clock");
    clear("clock_held");

    /* A Hall edge after a trip finds nothing to apply (TIM3's interrupts are off; one
     * already pended sees no flag: the trip cleared them). */
    fake_tim3.SR = 0u;
    %(hall)s();
    show("after_trip");

    /* The safe state of the region while faulted: the captured interval sets it. */
    fake_tim3.CCR1 = FAST_PERIOD;
    adc_with(BUS_OK, OFFSET, 0u, TIM_SR_CC1IF);
    show("faulted_fast");
    fake_tim3.CCR1 = 0xFFFEu; /* one tick inside the counter's range: slow, but known */
    adc_with(BUS_OK, OFFSET, 0u, TIM_SR_CC1IF);
    show("faulted_slow");
    adc_with(BUS_OK, OFFSET, 0u, TIM_SR_UIF);
    show("faulted_stopped");

    /* Faulted, the bus watchdog's entry with an injected bus slot still holding a
     * sample from before the bus moved (below the range) and the regular group's
     * latest in it: the latest decides, nothing more is latched. */
    adc_first_bus(0u, BUS_OK);
    show("faulted_stale_injected");
    return 0;
}
"""
)


def _parse(line: str) -> dict[str, int]:
    values: dict[str, int] = {}
    section = ""
    for word in line.split()[1:]:
        if "=" not in word:
            section = word
            continue
        key, value = word.split("=")
        values[f"{section}.{key}"] = int(value)
    return values


@dataclasses.dataclass(frozen=True)
class LoopRun:
    """What the harness's closed-loop steps feed and where the bus sits."""

    milliamps: int
    measured: tuple[int, ...]
    bus_ok: int
    bus_over: int
    offset: int
    fast_period: int


def _loop_run(spec: Spec) -> LoopRun:
    from codegen.derivation import derive
    from codegen.fixedpoint.scaling import scaling

    sc = scaling(spec, derive())
    nominal = round(float(spec.controller.braking_current_nominal_a / sc.amps_per_current_code))
    offset = sc.current_offset_code
    measured = tuple(
        offset + m for m in (0, nominal // 4, nominal // 2, nominal, nominal + 40, nominal)
    )
    # a bus in the range, the nominal voltage's code
    bus_ok = round(float(spec.inverter.bus_voltage_nominal_v / sc.volts_per_bus_code))
    # a Hall interval inside the rectifying region at that bus (T B <= K_RECT) where the
    # short is within its rating (T >= the short's rated interval) and the speed within
    # the range: half-way between the two ends (K_RECT / B / 2 had been above speed_max,
    # where the worst motor's short exceeds the rating)
    from codegen.control.safe_state import safe_state_design

    design = safe_state_design(spec)
    slowest = design.k_rect // bus_ok
    fastest = max(sc.period_min_ticks, design.short_valid_period)
    assert fastest < slowest, "no interval of the range where all-off rectifies at the bus"
    fast = (slowest + fastest) // 2
    return LoopRun(
        milliamps=int(spec.controller.braking_current_nominal_a * 1000),
        measured=measured,
        bus_ok=bus_ok,
        bus_over=sc.bus_code_max + 1,
        offset=offset,
        fast_period=fast,
    )


def _conversions_counts(spec: Spec) -> int:
    """TIM1 counts from an edge-aligned injected trigger to JEOC with no injection
    latency (the emulated ADC's, and the chip's at the least): the conversions alone,
    rounded up to the count at which the sequence has ended."""
    from codegen.spec_drive import ADC_CLOCK_HZ, ADC_CONVERSION_CYCLES, INJECTED_CONVERSIONS

    cycles = INJECTED_CONVERSIONS * (
        Fraction(spec.sensing.adc_sample_cycles) + ADC_CONVERSION_CYCLES
    )
    return math.ceil(cycles / ADC_CLOCK_HZ * Fraction(spec.inverter.timer_clock_hz))


def _build_harness(
    directory: Path, spec: Spec, *, watchdog_reset: bool = False, calibration_stuck: bool = False
) -> Path:
    from codegen.port_drive import handler_names

    _write_port(directory, spec)
    run = _loop_run(spec)
    names = handler_names(spec)
    defines = [
        f"-DSEQUENCE=((const unsigned[]){{{', '.join(map(str, spec.hall.sequence))}}})",
        f"-DBUS_OK={run.bus_ok}u",
        f"-DBUS_GATE={_bus_gate(spec)}u",
        f"-DBUS_OVER={run.bus_over}u",
        f"-DOFFSET={run.offset}u",
        f"-DLOOP_MA={run.milliamps}u",
        f"-DLOOP_STEPS={len(run.measured)}u",
        f"-DFAST_PERIOD={run.fast_period}u",
        f"-DCONVERSIONS_COUNTS={_conversions_counts(spec)}u",
        f"-DWATCHDOG_RESET={int(watchdog_reset)}",
        f"-DCALIBRATION_STUCK={int(calibration_stuck)}",
    ]
    if calibration_stuck:
        defines.append("-DHARNESS_CALIBRATION_STUCK")
    (directory / "shim.h").write_text(HOST_SHIM, encoding="utf-8")
    measured = ", ".join(f"{m}u" for m in run.measured)
    harness = HOST_HARNESS % {
        "hall": names["hall"],
        "adc": names["adc"],
        "brk": names["brk"],
        "timing": names["timing"],
        "bus": names["bus"],
        "line0": names["hall_line0"],
        "lines9_5": names["hall_lines9_5"],
    }
    harness = harness.replace(
        '#include "stm32f103_port.h"',
        f'#include "stm32f103_port.h"\nstatic const unsigned loop_measured[] = {{{measured}}};',
        1,
    )
    (directory / "harness.c").write_text(harness, encoding="utf-8")
    assert HOST_CC is not None, "no host C compiler"
    build = subprocess.run(
        [
            HOST_CC,
            "-std=c99",
            "-O1",
            "-Wall",
            "-Werror",
            *defines,
            "-include",
            "shim.h",
            "-I.",
            "harness.c",
            "stm32f103_port.c",
            "bldc_current_loop.c",
            "-o",
            "harness",
        ],
        cwd=directory,
        capture_output=True,
        text=True,
    )
    assert build.returncode == 0, build.stderr
    return directory / "harness"


def _run(binary: Path, *args: str) -> dict[str, dict[str, int]]:
    out = subprocess.run(
        [str(binary), *args], cwd=binary.parent, capture_output=True, text=True, check=True
    ).stdout
    return {line.split()[0]: _parse(line) for line in out.splitlines()}


@pytest.fixture(scope="module")
def host_run(tmp_path_factory: pytest.TempPathFactory, spec: Spec) -> dict[str, dict[str, int]]:
    return _run(_build_harness(tmp_path_factory.mktemp("host"), spec))


def _fault(name: str) -> int:
    from codegen.port_faults import FAULT

    return FAULT[name]


CC4E = 1 << 12
SAFE_CCER = 0x555 | CC4E  # CC1E, CC1NE, CC2E, CC2NE, CC3E, CC3NE
SHORT_CCER = 0x444 | CC4E  # CC1NE, CC2NE, CC3NE: the lower switches, MOE set
MOE = 0x8000
AWDIE = 1 << 6  # ADC_CR1.AWDIE
OIS_SHORT = (1 << 9) | (1 << 11) | (1 << 13)  # OIS1N, OIS2N, OIS3N


def test_init_should_configure_the_timers_and_the_adc_per_rm0008(
    host_run: dict[str, dict[str, int]], spec: Spec
) -> None:
    from codegen.control.sensing import sense_design

    r = host_run["init"]
    assert r["tim1.cr2"] & 0x1 and (r["tim1.cr2"] >> 4) & 7 == 7  # CCPC; MMS = 111: TRGO = OC4REF
    assert r["tim1.ccmr1"] == 0x6868  # OC1M = OC2M = 110 (PWM 1), OC1PE, OC2PE
    assert r["tim1.ccmr2"] == 0x7868  # OC3M = 110, OC3PE; OC4M = 111 (PWM 2: edge-aligned), OC4PE
    assert r["tim1.ccr4"] == sense_design(spec).window.trigger_counts
    assert r["tim1.ccer"] == CC4E  # every switch off; CC4E drives no pin
    # MOE, OSSR, OSSI, BKE, BKP = 0 (active low), DTG = 36
    assert r["tim1.bdtr"] == MOE | 0x800 | 0x400 | 0x1000 | 0x24
    assert (r["tim1.psc"], r["tim1.arr"]) == (0, 3599)
    assert r["tim1.cr1"] == 0x81  # ARPE, CEN, edge-aligned
    assert r["tim1.dier"] == 0x20 | 0x80  # COMIE, BIE
    assert r["tim3.cr2"] == 0x80  # TI1S: XOR of CH1..CH3
    assert r["tim3.smcr"] == 0x44  # TS = 100 (TI1F_ED), SMS = 100 (reset)
    assert r["tim3.ccmr1"] == 0x33  # CC1S = 11 (TRC), IC1F = 0011; CC2 frozen compare
    assert r["tim3.ccer"] == 0x1
    assert r["tim3.dier"] == 0x6  # CC1IE, CC2IE; UIF is polled
    assert r["tim3.cnt"] == 65535
    assert (r["tim3.psc"], r["tim3.arr"]) == (71, 65535)
    # ADC: SCAN, JEOCIE, AWDIE, JAWDEN, AWDEN, AWDSGL, AWDCH = 1 (the bus); injected
    # trigger TIM1 TRGO, JEXTTRIG; the regular group (the bus, again and again) started:
    # CONT, EXTTRIG, EXTSEL = 111, SWSTART; ADON; four injected conversions IN0, IN1,
    # IN1, IN1; 7.5 cycles
    assert r["adc.cr1"] == (1 << 8) | (1 << 7) | (1 << 6) | (1 << 22) | (1 << 23) | (1 << 9) | 1
    assert r["adc.cr2"] == (1 << 15) | (1 << 20) | (7 << 17) | (1 << 22) | (1 << 1) | 1
    assert (r["adc.sqr1"], r["adc.sqr3"]) == (0, 1)
    assert r["adc.jsqr"] == (3 << 20) | (0 << 0) | (1 << 5) | (1 << 10) | (1 << 15)
    assert r["adc.smpr2"] == (1 << 0) | (1 << 3)
    assert r["adc.smpr1"] == 0
    assert (r["adc.htr"], r["adc.ltr"]) == (3385, 2257)
    # IOPA, IOPB, AFIO, ADC1, ADC2, TIM1
    assert r["rcc.apb2"] == (1 << 2) | (1 << 3) | 1 | (1 << 9) | (1 << 10) | (1 << 11)
    assert r["rcc.apb1"] == 1 << 1  # TIM3
    assert (r["rcc.cfgr"] >> 14) & 3 == 2  # ADCPRE = PCLK2 / 6
    assert r["rcc.csr"] & (1 << 24)  # RMVF: the reset flags are read and cleared
    assert r["gpioa.crh"] == 0x44444BBB  # PA8..10 AF push-pull 50 MHz
    assert r["gpiob.crh"] == 0xBBB84444  # PB13..15 AF push-pull; PB12 (BKIN) input with pull
    assert r["gpioa.crl"] == 0x88444400  # PA0, PA1 analog; PA6, PA7 input with pull
    assert r["gpiob.crl"] == 0x44444448  # PB0 input with pull
    # EXTI0 = 6, ADC1_2 = 18, EXTI9_5 = 23, TIM1_BRK = 24, TIM1_UP = 25 (the bus change),
    # TIM1_TRG_COM = 26, TIM3 = 29
    enabled = (1 << 6) | (1 << 18) | (1 << 23) | (1 << 24) | (1 << 25) | (1 << 26) | (1 << 29)
    assert r["nvic.enabled"] == enabled
    assert r["nvic.hall"] == r["nvic.adc"] == r["nvic.brk"] < r["nvic.timing"] == r["nvic.bus"]
    assert r["port.faults"] == 0


def test_bridge_should_stay_off_until_the_first_bus_sample(
    host_run: dict[str, dict[str, int]],
) -> None:
    r = host_run["nobus"]
    assert r["in.bus"] == 0xFFFF  # the start-up bus code is the over-voltage one
    assert r["tim1.ccer"] == CC4E
    assert r["port.faults"] == 0  # no valid timing yet is not a fault
    assert host_run["bus"]["in.bus"] == _loop_run_paper().bus_ok


def _loop_run_paper() -> LoopRun:
    return _loop_run(load_spec(SPEC))


def _bus_gate(spec: Spec) -> int:
    """The requirement: at most one bus change per whole PWM periods of the top-speed
    sector (its Hall interval in whole ticks), at least one period."""
    ticks = math.floor(
        spec.hall.timer_clock_hz * 60 / (spec.controller.speed_max_rpm * spec.motor.pole_pairs * 6)
    )
    return max(1, math.floor(ticks * spec.inverter.pwm_frequency_hz / spec.hall.timer_clock_hz))


def test_bus_state_should_be_recomputed_only_beyond_the_hysteresis(
    host_run: dict[str, dict[str, int]],
) -> None:
    assert host_run["bus_noise"]["in.busruns"] == 0  # within the hysteresis: nothing
    r = host_run["bus_step"]
    assert r["in.busruns"] == 1
    assert r["in.bus"] == _loop_run_paper().bus_ok + 2  # one code stale at most


def test_bus_changes_should_wait_the_gate_however_far_the_bus_moves(
    host_run: dict[str, dict[str, int]],
) -> None:
    """A noisy or rippling bus leaves the band at almost every sample: one change per
    top-speed sector's PWM periods at most (40 on the paper motor), the rate the CPU
    load prices; the first sample after the gate takes the bus as it is then."""
    assert _bus_gate(load_spec(SPEC)) == 40
    gated = host_run["bus_gated"]
    assert gated["in.busruns"] == 1 and gated["in.bus"] == _loop_run_paper().bus_ok + 2
    opened = host_run["bus_gate_open"]
    assert opened["in.busruns"] == 2 and opened["in.bus"] == _loop_run_paper().bus_ok + 20


def test_a_bus_sample_during_a_bus_change_should_be_served_after_the_gate(
    host_run: dict[str, dict[str, int]],
) -> None:
    """The current loop preempts the timing handler inside the bus change with a sample
    outside the new band: no rerun at once (the gate), and the first sample after the
    gate computes from the bus then."""
    r = host_run["bus_race"]
    assert r["in.busruns"] == 1
    assert r["in.bus"] == _loop_run_paper().bus_ok + 60
    served = host_run["bus_race_served"]
    assert served["in.busruns"] == 2
    assert served["in.bus"] == _loop_run_paper().bus_ok + 40


def test_no_timing_should_run_on_a_sampled_current_while_the_interval_is_unknown(
    host_run: dict[str, dict[str, int]],
) -> None:
    """In the first sector after arming TIM3 has wrapped: the core would take the
    interval for the slowest speed and, with the current the loop sampled, compute a
    commutation most of a sector long for the next edge at the rotor's true speed (a
    run pended there tripped BKIN at 15 A on the second edge in the PIL). A bus change
    there waits, its state and the timing (bldc_port_status() reads the bus state with
    the published timing's inputs), for the first sample after the next edge; the runs
    of that sector's COM events read no sample (the first end's run: current 0)."""
    r = host_run["bus_unknown_interval"]
    assert r["in.busruns"] == 0  # the bus state waits
    assert r["in.runs"] == host_run["steady_open"]["in.runs"]  # no timing run with it
    assert host_run["end1"]["in.cur"] == 0  # the end's own run: no sample yet
    # once the interval is known the timing follows the loop again (edge2's run)
    assert host_run["edge2"]["in.period"] != 65535


def test_hall_edge_should_apply_the_precomputed_pattern_at_one_com_event(
    host_run: dict[str, dict[str, int]],
) -> None:
    # forward into sector 2: T4 (B lower) on at 2000, T2 (A lower) off at 1000
    r = host_run["edge1"]
    assert r["tim1.ccer"] == 0x044 | CC4E  # CC1NE (T2), CC2NE (T4)
    # CCxNE alone: OCxN = OCxREF (RM0008 Table 83), so CCR = the ON time, not ARR - it
    assert (r["tim1.ccr1"], r["tim1.ccr2"]) == (1000, 2000)
    assert r["edge.egr"] == 0x21  # COMG | UG
    assert r["tim3.ccr2"] == 300
    assert r["tim3.egr"] == 0
    assert r["edge.sr"] == 0xFFFFFFFF & ~0x5  # CC2IF and the timeout's UIF cleared
    assert r["in.period"] == 65535  # the first interval after start-up is unknown
    assert r["in.runs"] == 1
    # unknown: the short circuit, rated at every speed of the paper motor's range, where
    # all-off would rectify if the rotor turned fast (test_safe_state_should_follow_...)
    assert r["port.safe"] == 1


def test_current_should_be_sampled_only_between_commutations(
    host_run: dict[str, dict[str, int]],
) -> None:
    offset = _loop_run_paper().offset
    assert host_run["commutating"]["port.current"] != offset + 300  # held during it
    assert host_run["steady_open"]["port.current"] == offset + 300
    assert host_run["end1"]["tim1.ccer"] == 0x040 | CC4E  # T2 off, T4 at the main duty
    # open loop: the sample does not touch the duty
    assert host_run["steady_open"]["tim1.ccr2"] == 1500
    assert host_run["duty"]["tim1.ccr2"] == 1700
    assert host_run["clamp"]["tim1.ccr2"] == 3600


def test_a_sequence_still_converting_at_the_end_should_not_be_i_even_without_jstrt(
    host_run: dict[str, dict[str, int]],
) -> None:
    """The loop's SR write clears JSTRT and JEOC together; when it runs after the next
    trigger (the carrier's restart at the Hall edge brings that trigger within the
    sequence before), the next sequence's JSTRT is gone, and an end read only JSTRT:
    the PIL's 1-pole-pair improved_r motor at 80 kHz centre-aligned closed its loop on 6
    such samples in 1542 commutations, gate edges in their windows. The end reads the
    trigger's age from TIM1's counter too: 10 counts old, that sequence is not I."""
    offset = _loop_run_paper().offset
    assert host_run["wiped"]["port.current"] != offset + 77  # held: still converting
    assert host_run["after_wiped"]["port.current"] == offset + 78


def test_a_sequence_ended_before_the_end_should_hold_one_sample_not_two(
    host_run: dict[str, dict[str, int]],
) -> None:
    """An end just after the last sequence's JEOC, its loop step still to run: that
    sequence is stale, the next one is I (JEOC had counted two: the next sample too was
    dropped, the only one a commutation filling its sector leaves before the next edge)."""
    offset = _loop_run_paper().offset
    assert host_run["ended"]["port.current"] != offset + 81  # the ended sequence: held
    assert host_run["after_ended"]["port.current"] == offset + 82


def test_a_sequence_ended_without_injection_latency_should_hold_one_sample_not_two(
    host_run: dict[str, dict[str, int]], spec: Spec
) -> None:
    """An end at the earliest count the last sequence can have ended (no injection
    latency: DS5319 gives only its largest, 3 ADC cycles): its JEOC is the last
    trigger's, one stale sequence. BLDC_PORT_SEQUENCE_MIN_COUNTS took the latency for
    certain (498 counts, the conversions 480): two were counted and the next sample,
    begun after the end, dropped too; on a motor whose commutations fill their sectors
    the timing then ran on a sample older than two sectors (`make pil`, 24 kHz
    centre-aligned and 20 kHz edge-aligned motors)."""
    assert spec.inverter.pwm_alignment == "edge"  # the harness's CNT is CCR4 + the age
    offset = _loop_run_paper().offset
    assert host_run["ended_unlatched"]["port.current"] != offset + 83  # the ended one: held
    assert host_run["after_ended_unlatched"]["port.current"] == offset + 84


def test_a_sequence_ending_between_the_ends_two_reads_should_hold_one_sample_not_two(
    host_run: dict[str, dict[str, int]],
) -> None:
    """The end reads TIM1's counter, then ADC1's SR; a sequence that ends between the two
    reads has a JEOC yet an age short of its conversions. It is the last trigger's: one
    stale sequence, the next is I. The bound had no room for the reads' gap, and the SR
    read came after the end's other work: an end that landed there sector after sector
    (a steady braking's ends keep their phase to the carrier) counted two each time."""
    offset = _loop_run_paper().offset
    assert host_run["ended_between_reads"]["port.current"] != offset + 85
    assert host_run["after_ended_between_reads"]["port.current"] == offset + 86


def test_a_trigger_between_the_ends_counter_read_and_its_com_should_not_be_i(
    host_run: dict[str, dict[str, int]],
) -> None:
    """An end whose counter read comes a count before an injected trigger: the trigger
    fires before the COM event, so its sequence samples the commutating bridge. The end
    counts it stale although SR shows no JSTRT yet (the injection latency); the next
    sequence is I. The end had read SR before the COM event, with the age's arithmetic
    between: a trigger there went unseen (`make pil`, conv_80k_centre)."""
    offset = _loop_run_paper().offset
    assert host_run["imminent"]["port.current"] != offset + 87
    assert host_run["after_imminent"]["port.current"] == offset + 88


def test_current_loop_should_set_the_steady_switch_from_each_sample(
    host_run: dict[str, dict[str, int]], spec: Spec
) -> None:
    """The duties the port writes are the generated PI's (its Python twin, from the duty
    in force: no bump), on the steady switch's compare register (T4: CCR2)."""
    from codegen.control.current_loop import design, loop_context
    from codegen.render import render

    twin_text = render(
        "python/bldc_current_loop.py.j2", provenance="test", **loop_context(design(spec))
    )
    twin: dict[str, object] = {}
    exec(compile(twin_text, "<loop twin>", "exec"), twin)
    run = _loop_run(spec)
    reference = twin["current_reference"](run.milliamps)  # type: ignore[operator]
    state = 1700 << int(twin["BLDC_LOOP_FRAC_BITS"])  # type: ignore[call-overload]
    for k, measured in enumerate(run.measured):
        duty = twin["current_loop_duty"](state, reference, measured)  # type: ignore[operator]
        state = twin["current_loop_integrate"](state, reference, measured)  # type: ignore[operator]
        r = host_run[f"loop{k}"]
        assert r["tim1.ccr2"] == duty, k
        assert r["port.current"] == measured
    assert host_run["loop0"]["tim1.ccr2"] > 1700  # below the reference: more braking duty
    # the next timing takes the loop's latest duty
    assert host_run["edge2"]["in.duty"] == host_run[f"loop{len(run.measured) - 1}"]["tim1.ccr2"]


def _stub_flags(bus: int, period: int, current: int, duty: int) -> int:
    """STUB_FLAGS of the harness: the stub core's flags, a function of its four inputs."""
    return (bus * 5 + period * 7 + current * 11 + duty * 13) & 0xFFFF


def test_status_should_be_the_flags_of_the_published_timing(
    host_run: dict[str, dict[str, int]], spec: Spec
) -> None:
    """The timing handler stores no flags; bldc_port_status() runs the core again on the
    inputs the published timing took. So at every step it gives the flags of the last
    timing run's inputs (`in.*`, what the stub saw), not of the inputs now: the current
    loop's samples move `port.current` between runs, and a Hall edge `port.period`."""
    uses_duty = bool(port.port_context(spec)["uses_main_duty"])
    checked = moved = 0
    for step, r in host_run.items():
        if "port.status" not in r:
            continue
        duty = r["in.duty"] if uses_duty else 0  # a method without it gets 0 from status
        expected = _stub_flags(r["in.bus"], r["in.period"], r["in.cur"], duty)
        assert r["port.status"] == expected, step
        checked += 1
        moved += r["port.current"] != r["in.cur"]
    assert checked > 40
    assert moved > 5  # steps where the current sampled since differs from the timed one


def _assert_tripped(r: dict[str, int], fault: str) -> None:
    assert r["port.faults"] & _fault(fault), (fault, r["port.faults"])
    assert r["tim1.bdtr"] & MOE == 0  # outputs to their idle level
    assert r["tim1.ccer"] == SAFE_CCER  # every output of every phase held there
    assert r["tim3.dier"] == 0  # no Hall edge applies a pattern


@pytest.mark.parametrize(
    ("step", "fault"),
    [
        ("over_voltage", "OVER_VOLTAGE"),
        ("over_voltage_regular", "OVER_VOLTAGE"),
        ("under_voltage", "UNDER_VOLTAGE"),
        ("current_sensor", "CURRENT_SENSOR"),
        ("hall_timeout", "HALL_TIMEOUT"),
        ("hall_timeout_wrap", "HALL_TIMEOUT"),
        ("hall_invalid", "HALL_INVALID"),
        ("hall_sequence", "HALL_SEQUENCE"),
        ("over_speed", "OVER_SPEED"),
        ("over_current", "OVER_CURRENT"),
        ("external", "EXTERNAL"),
        ("clock", "CLOCK"),
    ],
)
def test_each_fault_should_reach_the_safe_state_at_once_and_latch(
    host_run: dict[str, dict[str, int]], step: str, fault: str
) -> None:
    _assert_tripped(host_run[step], fault)


@pytest.mark.parametrize(
    "step",
    [
        "over_voltage",
        "over_voltage_regular",
        "under_voltage",
        "current_sensor",
        "hall_invalid",
        "over_current",
        "over_speed",
    ],
)
def test_a_fault_should_not_clear_while_its_cause_is_present(
    host_run: dict[str, dict[str, int]], step: str
) -> None:
    held = host_run[f"{step}_held"]
    assert host_run[f"{step}_held_left"]["clear.left"] == held["port.faults"] != 0
    _assert_tripped(
        held,
        {
            "over_voltage": "OVER_VOLTAGE",
            "over_voltage_regular": "OVER_VOLTAGE",
            "under_voltage": "UNDER_VOLTAGE",
            "current_sensor": "CURRENT_SENSOR",
            "hall_invalid": "HALL_INVALID",
            "over_current": "OVER_CURRENT",
            "over_speed": "OVER_SPEED",
        }[step],
    )


@pytest.mark.parametrize(
    "step",
    [
        "over_voltage",
        "over_voltage_regular",
        "under_voltage",
        "current_sensor",
        "hall_timeout",
        "hall_timeout_wrap",
        "hall_invalid",
        "hall_sequence",
        "over_speed",
        "over_current",
        "external",
        "core_flag",
    ],
)
def test_an_explicit_clear_should_rearm_the_bridge_once_the_cause_is_gone(
    host_run: dict[str, dict[str, int]], step: str
) -> None:
    r = host_run[f"{step}_cleared"]
    assert host_run[f"{step}_cleared_left"]["clear.left"] == 0
    assert r["port.faults"] == 0
    assert r["tim1.bdtr"] & MOE
    # armed, in the idle state until the next edge: every switch off, but for the over
    # speed, cleared at speed_max on the nominal bus, where the worst motor the spec
    # declares (k_e 10 % high) rectifies: the short (the PIL's physics, not the port's)
    spec = load_spec(SPEC)
    rpm = float(spec.controller.speed_max_rpm)
    rectifies = said_line_emf_v(spec, rpm) >= float(spec.inverter.bus_voltage_nominal_v)
    assert r["tim1.ccer"] == (SHORT_CCER if step == "over_speed" and rectifies else CC4E)
    assert r["tim3.dier"] == 0x6
    assert r["tim1.dier"] & 0x80  # the break interrupt on again
    # no held current: the first sector's timing runs (its interval unknown) read none,
    # not the sample from before the fault (test_no_timing_should_run_on_a_sampled_...)
    assert r["port.current"] == 0


ADC_CODE_MAX = 4095


@pytest.mark.parametrize("step", ["over_voltage", "over_voltage_regular", "under_voltage"])
def test_a_bus_fault_should_open_its_side_of_the_watchdog_window_until_the_clear(
    host_run: dict[str, dict[str, int]], step: str
) -> None:
    # The regular group converts the bus every few microseconds and raises AWD each time
    # while the bus stays outside: the latched fault's side of the window opens (no
    # interrupt storm at the Hall edge's priority), the other side still watches, and
    # the clear gives back the bus's range. After the watchdog's own entry its
    # interrupt is off until the next faulted tick (an injected sample's entry), which
    # turns it on again: while faulted it follows the safe state's bound as well.
    init = host_run["init"]
    assert init["adc.cr1"] & AWDIE
    for moment in (step, f"{step}_held"):
        r = host_run[moment]
        # the under-voltage's held moment follows a sample without AWD (`..._sampled`)
        sampled = moment == "under_voltage_held"
        assert r["adc.cr1"] == init["adc.cr1"] & (~0 if sampled else ~AWDIE)
        if step.startswith("over"):
            assert r["adc.htr"] == ADC_CODE_MAX
            assert r["adc.ltr"] >= init["adc.ltr"]
        else:
            assert r["adc.ltr"] == 0
            assert r["adc.htr"] <= init["adc.htr"]
    if step == "under_voltage":
        # an entry with AWD again (faulted: judged whatever AWDIE): off still; the next
        # sample's entry without it: on again
        again = host_run["under_voltage_again"]
        assert again["adc.cr1"] == init["adc.cr1"] & ~AWDIE
        assert again["adc.ltr"] == 0
        assert host_run["under_voltage_sampled"]["adc.cr1"] == init["adc.cr1"]
    cleared = host_run[f"{step}_cleared"]
    assert cleared["adc.cr1"] == init["adc.cr1"]
    assert (cleared["adc.htr"], cleared["adc.ltr"]) == (init["adc.htr"], init["adc.ltr"])


def test_an_over_voltage_seen_first_in_jdr2_should_latch_over_voltage(
    host_run: dict[str, dict[str, int]],
) -> None:
    # the analog watchdog's interrupt at the end of JSQ2, before JDR4 and with DR from
    # before the step: every bus JDRx is read (was UNDER_VOLTAGE, found by the PIL)
    _assert_tripped(host_run["over_voltage_first_bus"], "OVER_VOLTAGE")
    assert host_run["over_voltage_first_bus"]["port.faults"] == _fault("OVER_VOLTAGE")
    assert host_run["over_voltage_first_bus_cleared"]["port.faults"] == 0


def test_a_watchdog_trip_whose_conversion_is_gone_should_claim_neither_side(
    host_run: dict[str, dict[str, int]],
) -> None:
    """The analog watchdog's flag with every bus reading back inside the window: a
    transient shorter than a conversion, overwritten before the entry. Was UNDER_VOLTAGE
    for a 1 us over-voltage spike (a helper's hunt); now its own fault, the safe state
    at once, and a clear that finds the bus in range clears it."""
    r = host_run["bus_transient"]
    _assert_tripped(r, "BUS_TRANSIENT")
    assert r["port.faults"] == _fault("BUS_TRANSIENT")
    assert host_run["bus_transient_cleared"]["port.faults"] == 0


@pytest.mark.parametrize("code", [7, 0])
def test_hall_lines_all_alike_without_an_edge_should_trip_in_the_exti(
    host_run: dict[str, dict[str, int]], code: int
) -> None:
    # two lines changing within TIM3's filter make no TI1 edge: the EXTI on the Hall
    # lines reads the pins at once (and again after its confirmation wait)
    r = host_run[f"hall_alike_{code}"]
    _assert_tripped(r, "HALL_INVALID")
    assert r["port.faults"] == _fault("HALL_INVALID")
    # the last write to PR (rc_w1, plain memory here): a 1 for each of the port's lines
    # alone, so line 5's pending bit (not the port's) stays
    assert r["exti.pr"] == (1 << 0) | (1 << 6) | (1 << 7)
    if code == 7:
        assert host_run["hall_alike_7_held"]["port.faults"] == _fault("HALL_INVALID")
    assert host_run[f"hall_alike_{code}_cleared"]["port.faults"] == 0
    assert host_run["hall_alike_steady"]["port.faults"] == 0


@pytest.mark.parametrize("step", ["under_voltage_again", "current_rail_low_again"])
def test_a_watchdog_that_has_tripped_should_not_trip_again_each_period(
    host_run: dict[str, dict[str, int]], step: str
) -> None:
    # AWD is set again by every conversion outside the window: acting on it again would
    # raise a COM event, and a timing run, every PWM period while the fault is latched
    r = host_run[step]
    assert r["in.runs"] == 0
    assert r["in.breaks"] == host_run[step.replace("_again", "")]["in.breaks"]
    assert not r["tim1.bdtr"] & MOE


def test_a_valid_code_on_a_hall_line_edge_should_only_clear_the_lines(
    host_run: dict[str, dict[str, int]],
) -> None:
    r = host_run["hall_line_valid"]
    assert r["port.faults"] == 0 and r["tim1.bdtr"] & MOE
    assert r["exti.pr"] == (1 << 0) | (1 << 6) | (1 << 7)  # rc_w1: line 5 stays pending
    # the current loop's interrupt does not read the pins any more (the EXTI does)
    assert host_run["hall_alike_loop"]["port.faults"] == 0


def test_init_should_route_the_hall_lines_to_the_exti_and_start_adc2(
    host_run: dict[str, dict[str, int]], spec: Spec
) -> None:
    r, init = host_run["init2"], host_run["init"]
    # RM0008 9.4.3/9.4.4: EXTI0 <- PB0 (0001), EXTI6 and EXTI7 <- PA6, PA7 (0000)
    assert r["afio.exticr1"] & 0xF == 1
    assert (r["afio.exticr2"] >> 8) & 0xFF == 0
    lines = (1 << 0) | (1 << 6) | (1 << 7)
    assert r["exti.imr"] == r["exti.rtsr"] == r["exti.ftsr"] == lines  # both edges
    assert r["nvic.exti0"] == r["nvic.exti9_5"] == init["nvic.hall"]
    assert init["nvic.enabled"] & (1 << 6) and init["nvic.enabled"] & (1 << 23)
    assert init["rcc.apb2"] & (1 << 0) and init["rcc.apb2"] & (1 << 10)  # AFIOEN, ADC2EN
    # ADC2: SCAN, AWDIE, AWDEN on every regular channel; continuous, software start
    assert r["adc2.cr1"] == (1 << 8) | (1 << 6) | (1 << 23)
    assert r["adc2.cr2"] & 0b11 == 0b11 and (r["adc2.cr2"] >> 17) & 7 == 7
    channels = spec.sensing.current_channels
    assert (r["adc2.sqr1"] >> 20) & 0xF == len(channels) - 1
    assert [(r["adc2.sqr3"] >> (5 * k)) & 0x1F for k in range(len(channels))] == list(channels)
    assert (r["adc2.smpr1"], r["adc2.smpr2"]) == (init["adc.smpr1"], init["adc.smpr2"])
    assert (r["adc2.ltr"], r["adc2.htr"]) == (1, 4094)  # both rails (offset at mid-scale)


@pytest.mark.parametrize("rail", ["low", "high"])
def test_a_current_at_a_rail_between_samples_should_trip_through_adc2(
    host_run: dict[str, dict[str, int]], rail: str
) -> None:
    r = host_run[f"current_rail_{rail}"]
    _assert_tripped(r, "CURRENT_SENSOR")
    assert r["port.faults"] == _fault("CURRENT_SENSOR")
    assert not r["adc2.cr1"] & AWDIE and not r["adc2.sr"] & 1  # silenced until the clear
    if rail == "low":
        assert host_run["current_rail_low_held"]["port.faults"] == _fault("CURRENT_SENSOR")
    cleared = host_run[f"current_rail_{rail}_cleared"]
    assert cleared["port.faults"] == 0 and cleared["adc2.cr1"] & AWDIE
    assert host_run["current_rail_steady"]["port.faults"] == 0


def test_a_wrap_should_be_the_hall_timeout_only_while_the_bridge_switches(
    host_run: dict[str, dict[str, int]],
) -> None:
    # the commutation end turns the wrap's and the time-out's interrupts on: CC1IE, CC2IE,
    # UIE, CC3IE; the time-out 4 T after the edge (T = 5000 ticks, within the paper
    # motor's BLDC_PORT_HALL_TIMEOUT_PERIOD_MAX)
    assert host_run["steady_wrap_armed"]["tim3.dier"] == 0xF
    assert host_run["steady_wrap_armed"]["tim3.ccr3"] == 4 * 5000
    assert host_run["steady_wrap_armed"]["port.faults"] == 0
    # its match while the bridge switches: the Hall timeout at once
    _assert_tripped(host_run["hall_timeout_cc3"], "HALL_TIMEOUT")
    assert host_run["hall_timeout_cc3_cleared"]["port.faults"] == 0
    # bridge off after a reversal: no fault, the interrupt off, UIF left for the next edge
    r = host_run["wrap_idle"]
    assert r["port.faults"] == 0
    assert r["tim3.dier"] == 0x6
    assert r["tim3.sr"] & 1  # UIF
    assert r["tim1.bdtr"] & MOE


def test_a_reversal_should_take_the_safe_state_of_the_region_without_a_fault(
    host_run: dict[str, dict[str, int]], spec: Spec
) -> None:
    from codegen.derivation import derive
    from codegen.fixedpoint.scaling import scaling

    full_scale = scaling(spec, derive()).period_counts
    # at the slow interval (all-off does not rectify): every output off
    assert host_run["wrap_idle"]["tim1.ccer"] == CC4E
    # where all-off would rectify into the bus: each lower switch alone, on all period
    r = host_run["reversal_short"]
    assert r["tim1.ccer"] == SHORT_CCER
    assert (r["tim1.ccr1"], r["tim1.ccr2"], r["tim1.ccr3"]) == (full_scale,) * 3
    assert r["port.faults"] == 0 and r["tim1.bdtr"] & MOE
    # forward again: the edge's commutation, its end scheduled, no fault
    out = host_run["out_of_short"]
    assert out["port.faults"] == 0 and out["tim1.bdtr"] & MOE
    assert out["tim3.ccr2"] == 300  # the plan's commutation ticks
    assert out["tim1.ccer"] not in (CC4E, SHORT_CCER, SAFE_CCER)
    assert bin(out["tim1.ccer"] & 0xFFF).count("1") == 2  # the turn-on and turn-off switch
    for channel in range(3):  # no phase with both switches enabled
        assert (out["tim1.ccer"] >> 4 * channel) & 0b101 != 0b101
    end = host_run["out_of_short_end"]
    assert end["port.faults"] == 0 and bin(end["tim1.ccer"] & 0xFFF).count("1") == 1


def test_the_drive_should_switch_again_after_a_clear(host_run: dict[str, dict[str, int]]) -> None:
    r = host_run["steady_again"]
    assert r["port.faults"] == 0 and r["tim1.bdtr"] & MOE
    assert r["tim1.ccer"] not in (CC4E, SAFE_CCER)


def test_the_core_flag_should_trip_through_a_software_break(
    host_run: dict[str, dict[str, int]],
) -> None:
    r = host_run["core_flag"]
    _assert_tripped(r, "UNDER_VOLTAGE")
    assert r["in.breaks"] >= 1  # latched by the break handler


def test_a_clock_failure_should_never_clear(host_run: dict[str, dict[str, int]]) -> None:
    held = host_run["clock_held"]
    assert host_run["clock_held_left"]["clear.left"] & _fault("CLOCK")
    _assert_tripped(held, "CLOCK")


def test_a_trip_should_drop_a_pended_hall_edge(host_run: dict[str, dict[str, int]]) -> None:
    assert host_run["clock"]["nvic.cleared"] & (1 << 29)  # TIM3's pending request cleared
    r = host_run["after_trip"]
    assert r["tim1.ccer"] == SAFE_CCER


def test_safe_state_should_follow_the_speed_region_while_faulted(
    host_run: dict[str, dict[str, int]],
) -> None:
    """Above U_d/(2 k_e) all-off rectifies into the bus: the short circuit (lower
    switches at their idle level OISxN = 1); a slow rotor, all-off (the paper motor's
    preference). A wrapped counter, the speed unknown (the first edges after arming) or
    below the counter's range: the short circuit, which the paper motor's bridge is
    rated for at every speed (the PIL's own bound), where all-off would rectify if the
    rotor turned fast."""
    fast = host_run["faulted_fast"]
    assert fast["tim1.cr2"] & OIS_SHORT == OIS_SHORT
    assert fast["port.safe"] == 1
    assert fast["tim1.cr2"] & ((1 << 8) | (1 << 10) | (1 << 12)) == 0  # upper switches off
    slow = host_run["faulted_slow"]
    assert slow["tim1.cr2"] & OIS_SHORT == 0
    assert slow["port.safe"] == 0
    rated = short_rated_speed(load_spec(SPEC))
    assert rated is None or rated >= float(load_spec(SPEC).controller.speed_max_rpm)
    stopped = host_run["faulted_stopped"]
    assert stopped["tim1.cr2"] & OIS_SHORT == OIS_SHORT
    assert stopped["port.safe"] == 1


def test_a_faulted_watchdog_entry_should_judge_the_bus_by_the_latest_conversion(
    host_run: dict[str, dict[str, int]], spec: Spec
) -> None:
    """While faulted the window is narrower than the bus's range, and an injected bus
    slot may hold the sample before the bus moved: judged by it, each entry latched a
    bus fault and chose the region from a bus that was no longer there (a helper's hunt:
    all-off, rectifying, 53 us after a bus fall that followed an over-voltage)."""
    before = host_run["faulted_stopped"]["port.faults"]
    after = host_run["faulted_stale_injected"]["port.faults"]
    slots = port.port_context(spec)["bus_jdr_slots"]
    if 2 in slots:  # the stale slot is one of the bus's (else the entry reads no stale bus)
        assert after == before, (hex(before), hex(after))
    assert after & _fault("UNDER_VOLTAGE") == before & _fault("UNDER_VOLTAGE")


SAFE_STATE_CHECK = (
    r"""
/* Every bus code the ADC gives (12 bits) and the start-up code 0xFFFF, through the
 * port's own bus change; for each, every Hall interval 0..65535 through the port's own
 * CR2 choice, against the design's product rule. */
#include <stdio.h>
#include "stm32f103_port.c"

"""
    + FAKE_PERIPHERALS
    + r"""
bldc_bus_t bldc_bus_condition(uint32_t bus_code)
{
    bldc_bus_t bus = {0u, 0u, 0, 0u, bus_code, 0u};
    return bus;
}

bldc_timing_t bldc_commutation_timing(const bldc_bus_t *bus, uint32_t period_ticks,
                                      uint32_t current_adc, uint32_t main_duty_counts)
{
    bldc_timing_t none = {0u, 0u, 0u, 0u, 0u};
    (void)bus, (void)period_ticks, (void)current_adc, (void)main_duty_counts;
    return none;
}

int main(void)
{
    const uint32_t ois = (1u << 9) | (1u << 11) | (1u << 13); /* OIS1N..OIS3N, RM0008 */
    unsigned long codes = 0ul, wrong = 0ul;
    for (uint32_t b = 0u; b <= 0xFFFFu; b = (b == 4095u) ? 0xFFFFu : b + 1u) {
        *(volatile uint32_t *)&fake_adc1.JDR4 = b;
        port.bus_moved = 1u;
        port_update_bus();
        wrong += port.bus_moved; /* the request taken */
        for (uint32_t t = 0u; t <= 0xFFFFu; ++t) {
            const int rectifying = (unsigned long long)t * b <= RULE_K;
            /* a wrapped interval (the speed unknown): the short where it is rated at
             * every speed of the range (RULE_UNKNOWN), else all-off, whatever the
             * policy prefers; a rectifying interval is the short whatever */
            const int wrapped = (t == 0xFFFFu);
            /* preferring the short: wherever it is rated, whatever the bus reads (the
             * loader keeps the short rated where all-off rectifies within the ranges) */
            const int short_circuit =
                RULE_BOTH      ? (t >= RULE_V && !(wrapped && !RULE_UNKNOWN))
                : RULE_UNKNOWN ? (rectifying || wrapped)
                               : (rectifying && t >= RULE_V);
            const uint32_t cr2 = port_safe_state_cr2(t);
            /* While faulted (a fault of no bus), the watchdog's window at t: the codes
             * whose bus needs the short circuit at t are [0, need] (none: -1); with
             * all-off in force every one of them is outside the window (LTR above them,
             * or an empty window: the short at that conversion), the code that chose the region is inside it (no
             * interrupt at each conversion), and the short is left within the
             * hysteresis above `need`. */
            port.faults = BLDC_FAULT_HALL_TIMEOUT;
            port.period = (uint16_t)t;
            port_watch_while_faulted(port_peripherals(), 1u);
            port.faults = 0u;
            const unsigned long ltr = fake_adc1.LTR, htr = fake_adc1.HTR;
            long need = -1;
            if (!RULE_BOTH && RULE_UNKNOWN && wrapped) {
                need = 4095;
            } else if (!RULE_BOTH && (RULE_UNKNOWN || t >= RULE_V)) {
                need = (t == 0u) ? 4095 : (long)((RULE_K / t > 4095ull) ? 4095ull : RULE_K / t);
            }
            const int in_range = (b >= BLDC_PORT_ADC_LTR) && (b <= BLDC_PORT_ADC_HTR);
            if ((!short_circuit && need >= 0 && ltr <= htr && ltr <= (unsigned long)need)
                || (in_range && (ltr > b || htr < b))
                || (short_circuit && in_range && need >= 0
                    && need + (long)BLDC_PORT_FAULTED_BUS_HYSTERESIS_CODES < (long)BLDC_PORT_ADC_HTR
                    && htr > (unsigned long)need + BLDC_PORT_FAULTED_BUS_HYSTERESIS_CODES)) {
                if (wrong < 5ul) {
                    printf("B %lu T %lu: faulted window [%lu, %lu], need %ld\n", (unsigned long)b,
                           (unsigned long)t, ltr, htr, need);
                }
                ++wrong;
            }
            if ((cr2 & ois) != (short_circuit ? ois : 0u) || (cr2 & ~ois) != BLDC_PORT_TIM1_CR2) {
                if (wrong < 5ul) {
                    printf("B %lu T %lu: CR2 %#lx\n", (unsigned long)b, (unsigned long)t,
                           (unsigned long)cr2);
                }
                ++wrong;
            }
        }
        ++codes;
    }
    printf("codes %lu wrong %lu\n", codes, wrong);
    return wrong != 0ul;
}
"""
)


@pytest.mark.parametrize(
    ("path", "short_valid_period"),
    [
        (SPEC, None),
        (ROOT / "spec" / "example_maxon_ec45_flat_48v.yaml", None),
        (ROOT / "tests" / "fixtures" / "specs" / "hub_motor_46p.yaml", None),
        (ROOT / "tests" / "fixtures" / "specs" / "fast_14p_12v.yaml", None),
        # the short circuit preferred but rated only at and above an interval: the two
        # regions' union (no fixture has it, so the fast motor's header is edited)
        (ROOT / "tests" / "fixtures" / "specs" / "fast_14p_12v.yaml", 9000),
        # preferred, rated only up to 2216 rpm: a wrapped interval is all-off
        (ROOT / "tests" / "fixtures" / "pil" / "short_rated_mid_range.yaml", None),
        # all-off preferred, the short rated only below 79 rpm (under speed_min): it
        # only where rated, even on a bus reading 0
        (ROOT / "tests" / "fixtures" / "pil" / "l20uh_100v_100k.yaml", None),
    ],
    ids=[
        "paper",
        "maxon",
        "hub",
        "fast",
        "fast-short-rated-above-9000",
        "short-rated",
        "all-off-short-rated-below-range",
    ],
)
def test_safe_state_bound_should_decide_as_the_product_for_every_bus_and_interval(
    path: Path, short_valid_period: int | None, tmp_path: Path
) -> None:
    """The timing handler compares T with floor(K / B), found at the bus change, where
    the design's rule is T B <= K: the same choice for every interval the Hall counter
    gives and every bus code, checked exhaustively on the compiled port against the
    design's K, policy and rated interval (codegen/control/safe_state.py)."""
    from codegen.control.safe_state import safe_state_design

    assert HOST_CC is not None, "no host C compiler"
    spec = load_spec(path)
    design = safe_state_design(spec)
    _write_port(tmp_path, spec)
    both = design.policy == "short_circuit"
    valid = design.short_valid_period
    # the short rated at every speed of the range, by the PIL's own bound (the FFT of
    # sim's EMF waveform), not the design's
    rated = short_rated_speed(spec)
    rated_everywhere = rated is None or rated >= float(spec.controller.speed_max_rpm)
    if short_valid_period is not None:
        both, valid = True, short_valid_period
        header = tmp_path / "stm32f103_port.h"
        text = header.read_text(encoding="utf-8")
        text, n_valid = re.subn(
            r"#define BLDC_PORT_SHORT_VALID_PERIOD \d+u",
            f"#define BLDC_PORT_SHORT_VALID_PERIOD {valid}u",
            text,
        )
        text, n_both = re.subn(
            r"#define BLDC_PORT_SHORT_WHERE_BOTH \d+u",
            "#define BLDC_PORT_SHORT_WHERE_BOTH 1u",
            text,
        )
        assert n_valid == n_both == 1
        header.write_text(text, encoding="utf-8")
    (tmp_path / "shim.h").write_text(HOST_SHIM, encoding="utf-8")
    (tmp_path / "check.c").write_text(SAFE_STATE_CHECK, encoding="utf-8")
    build = subprocess.run(
        [
            HOST_CC,
            "-std=c99",
            "-O2",
            "-Wall",
            "-Werror",
            "-Wno-unused-function",
            f"-DRULE_K={design.k_rect}ull",
            f"-DRULE_BOTH={int(both)}",
            f"-DRULE_V={valid}u",
            f"-DRULE_UNKNOWN={int(rated_everywhere)}",
            "-include",
            "shim.h",
            "-I.",
            "check.c",
            "bldc_current_loop.c",
            "-o",
            "check",
        ],
        cwd=tmp_path,
        capture_output=True,
        text=True,
    )
    assert build.returncode == 0, build.stderr
    run = subprocess.run([str(tmp_path / "check")], capture_output=True, text=True, timeout=120)
    assert run.stdout.strip().endswith("codes 4097 wrong 0"), run.stdout
    assert run.returncode == 0


@pytest.mark.parametrize("case", ["clock_at_start", "watchdog_reset", "calibration_stuck"])
def test_start_up_faults_should_latch_before_the_bridge_is_armed(
    tmp_path: Path, spec: Spec, case: str
) -> None:
    binary = _build_harness(
        tmp_path,
        spec,
        watchdog_reset=case == "watchdog_reset",
        calibration_stuck=case == "calibration_stuck",
    )
    run = _run(binary, *(["clock"] if case == "clock_at_start" else []))
    fault = {"clock_at_start": "CLOCK", "watchdog_reset": "WATCHDOG", "calibration_stuck": "ADC"}[
        case
    ]
    assert run["init"]["port.faults"] & _fault(fault)
    assert run["init"]["tim1.bdtr"] & MOE == 0  # never armed
    left = run["start_clear_again_left"]["clear.left"]
    if fault == "WATCHDOG":
        assert left == 0  # a report of the past reset: clears
        assert run["start_clear_again"]["tim1.bdtr"] & MOE
    else:
        assert left & _fault(fault)  # only a reset clears it


def test_low_side_shunts_should_read_the_sectors_signal(tmp_path: Path) -> None:
    """With low-side phase shunts the port reads I from the register the sensing design
    names for the steady switch (codegen/control/sensing.py): a sample is taken from
    that JDRx only."""
    from codegen.control.sensing import sense_design

    maxon = load_spec(ROOT / "spec" / "example_maxon_ec45_flat_48v.yaml")
    table = port.edge_records(maxon)
    slots = {s.edge: s.slot for s in sense_design(maxon).signals}
    assert set(slots.values()) == {0, 1, 2}  # every phase's shunt is used somewhere
    for record in table:
        if record == port.RECORD_INVALID:
            continue
        slot = ((record >> port.RECORD_SENSE_LOW_SHIFT) & 1) | (
            (record >> port.RECORD_SENSE_HIGH_SHIFT) & 1
        ) << 1
        assert slot in (0, 1, 2)
    # and the harness runs on that spec too, closed loop included
    run = _run(_build_harness(tmp_path, maxon))
    assert run["loop0"]["port.current"] == _loop_run(maxon).measured[0]


def test_pin_indexed_edge_table_should_give_the_cores_edge_for_every_pair(spec: Spec) -> None:
    """PA6 = Hall A, PA7 = Hall B, PB0 = Hall C, read as PA6 | PA7 << 1 | PB0 << 2; each
    entry is the packed record of the edge's two switches (codegen.port.EDGE_RECORD_LAYOUT),
    checked here against RM0008's CCER layout written out by hand; an invalid pair's
    record makes the partner test see CC4E, which every pattern has."""
    from codegen.derivation import derive

    def pins(code: int) -> int:
        a, b, c = (code >> 2) & 1, (code >> 1) & 1, code & 1
        return a | b << 1 | c << 2

    def ccer_bit(switch: str) -> int:
        # T1/T2 = CH1/CH1N (bits 0, 2), T3/T4 = CH2/CH2N (4, 6), T5/T6 = CH3/CH3N (8, 10)
        return 1 << {"T1": 0, "T2": 2, "T3": 4, "T4": 6, "T5": 8, "T6": 10}[switch]

    def partner(switch: str) -> str:
        n = int(switch[1:])
        return f"T{n + 1 if n % 2 else n - 1}"

    def channel(switch: str) -> int:
        return (int(switch[1:]) - 1) // 2

    table = port.edge_records(spec)
    switching = derive().switching
    sequence = spec.hall.sequence
    expected = {}
    for sector, code in enumerate(sequence):
        for direction, previous in (
            ("forward", sequence[sector - 1]),
            ("reverse", sequence[(sector + 1) % 6]),
        ):
            edge = switching.edge_into(sector, direction)
            on, off = edge.modulated_on, edge.modulated_off
            expected[(previous, code)] = (
                ccer_bit(on)
                | ccer_bit(off)
                | CC4E
                | channel(on) << 13
                | channel(off) << 29
                | (ccer_bit(partner(on)) | ccer_bit(partner(off))) << 16
            )  # DC-link shunt: the sense slot is 0
    assert len(expected) == 12
    for previous in range(8):
        for code in range(8):
            want = expected.get((previous, code), CC4E << 16)
            assert table[pins(previous) << 3 | pins(code)] == want, (previous, code)
            # from any pattern the port writes (all of which hold CC4E) an invalid pair is refused
            assert ((want >> 16) & CC4E != 0) == ((previous, code) not in expected)


@pytest.mark.parametrize(
    ("offset_v", "watched", "ltr", "htr"),
    [("0", "full scale", 0, 4094), ("3.3", "0", 1, 4095), ("1.65", "0 and full scale", 1, 4094)],
)
def test_adc2_should_watch_every_rail_zero_current_does_not_sit_on(
    tmp_path: Path, spec: Spec, offset_v: str, watched: str, ltr: int, htr: int
) -> None:
    """A current-sense offset at a rail reads zero current there: that rail is left out of
    ADC2's watch and out of the port's own rail test (`port_at_a_rail`, the faulted tick's
    and the loop's out-of-line path), which flags exactly the watched rails (it flagged
    both, and latched CURRENT_SENSOR at zero current with a 0 V offset); the current
    loop's hot path leaves the rails to ADC2's watchdog."""
    from codegen.port_drive import current_watch

    variant = dataclasses.replace(
        spec, adc=dataclasses.replace(spec.adc, current_offset_v=Fraction(offset_v))
    )
    watch = current_watch(variant)
    assert (watch.ltr, watch.htr, watch.rails) == (ltr, htr, watched)
    ctx = port.port_context(variant)
    defines = {d["name"]: d["value"] for d in ctx["drive_defines"]}  # type: ignore[attr-defined]
    assert (defines["BLDC_PORT_CURRENT_LTR"], defines["BLDC_PORT_CURRENT_HTR"]) == (
        f"{ltr}u",
        f"{htr}u",
    )
    _write_port(tmp_path, variant)
    source = (tmp_path / "stm32f103_port.c").read_text(encoding="utf-8")
    handler = source[source.index("void ADC1_2_IRQHandler(void)") :]
    handler = handler[: handler.index("\n}\n")]
    assert "port_at_a_rail" not in handler
    helper = source[source.index("static inline uint32_t port_at_a_rail(") :]
    helper = helper[: helper.index("\n}\n") + 3]
    probe = tmp_path / "rail_probe.c"
    probe.write_text(
        "#include <stdint.h>\n#include <stdio.h>\n#define BLDC_PORT_ADC_CODE_MAX 4095u\n"
        + helper
        + "int main(void) { for (uint32_t c = 0u; c < 5000u; ++c) if (port_at_a_rail(c)) "
        'printf("%u\\n", (unsigned)c); return 0; }\n',
        encoding="utf-8",
    )
    built = subprocess.run(
        ["gcc", *HOST_WARNINGS, "-Werror", str(probe), "-o", str(tmp_path / "rail_probe")],
        capture_output=True,
        text=True,
        check=False,
    )
    assert built.returncode == 0, built.stderr
    flagged = subprocess.run(
        [str(tmp_path / "rail_probe")], capture_output=True, text=True, check=True
    ).stdout.split()
    rails = {
        "0": {0},
        "full scale": set(range(4095, 5000)),
        "0 and full scale": {0, *range(4095, 5000)},
    }
    assert {int(c) for c in flagged} == rails[watched]
    run = _compile_arm(tmp_path)
    assert run.returncode == 0, run.stderr


_WITHIN_CHECK = r"""
#include <stdio.h>
#include "stm32f103_regs.h"
#include "stm32f103_port.h"
int main(void)
{
    const uint32_t cycle = (BLDC_PORT_TIM1_CMS == 0u) ? BLDC_PORT_TIM1_ARR + 1u
                                                      : 2u * BLDC_PORT_TIM1_ARR + 1u;
    unsigned long wrong = 0ul, within = 0ul;
    for (uint32_t n = 0u; n <= BLDC_PORT_WAIT_COUNTS; ++n) {
        for (uint32_t down = 0u; down < 2u; ++down) {
            const uint32_t cr1 = (down != 0u) ? TIM_CR1_DIR : 0u;
            for (uint32_t cnt = 0u; cnt <= BLDC_PORT_TIM1_ARR; ++cnt) {
                const int fast = (BLDC_PORT_TRIGGER_WITHIN(cnt, cr1, n)) ? 1 : 0;
                const int aged = (BLDC_PORT_TRIGGER_AGE(cnt, cr1) >= cycle - n) ? 1 : 0;
                wrong += (unsigned long)(fast != aged);
                within += (unsigned long)fast;
            }
        }
    }
    printf("%lu %lu\n", wrong, within);
    return 0;
}
"""


@pytest.mark.parametrize(
    "relative", ["spec/paper_motor.yaml", "tests/fixtures/pil/conv_cen_ps.yaml"]
)
def test_the_trigger_within_n_counts_should_be_the_age_at_every_count(
    tmp_path: Path, relative: str
) -> None:
    """BLDC_PORT_TRIGGER_WITHIN, the commutation end's one compare that waits out an
    imminent trigger, against BLDC_PORT_TRIGGER_AGE at least its cycle less n, at every
    counter value, direction and n up to BLDC_PORT_WAIT_COUNTS (edge- and
    centre-aligned)."""
    assert HOST_CC is not None, "no host C compiler"
    _write_port(tmp_path, load_spec(ROOT / relative))
    (tmp_path / "within.c").write_text(_WITHIN_CHECK, encoding="utf-8")
    subprocess.run(
        [HOST_CC, "-std=c99", "-O1", "within.c", "-o", "within"], cwd=tmp_path, check=True
    )
    wrong, within = subprocess.run(
        [str(tmp_path / "within")], capture_output=True, text=True, check=True
    ).stdout.split()
    assert int(wrong) == 0 and int(within) > 0
    # where the one compare does not hold (a trigger within n counts of the period's
    # start), the macro is the age itself
    assert "BLDC_PORT_TRIGGER_AGE" in trigger_within(False, 299, 27, 28)
    assert "BLDC_PORT_TRIGGER_AGE" in trigger_within(True, 27, 26, 28)
    assert "BLDC_PORT_TRIGGER_AGE" not in trigger_within(False, 299, 28, 28)

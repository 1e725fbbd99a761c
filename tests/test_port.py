"""The STM32F103 port: its numbers, its dead-time code, and its C on target and host.

The port is compiled against a stub of the core's header (the contract only), for the
Cortex-M3 with warnings as errors, and its object code is checked for library division
and floating-point helpers. On the host, the same source runs against fake register
blocks, so the register values of each commutation step can be checked against
RM0008 without hardware.
"""

from __future__ import annotations

import dataclasses
import re
import shutil
import subprocess
from fractions import Fraction
from pathlib import Path

import pytest

from codegen import port
from codegen.build_firmware import CFLAGS
from codegen.spec_loader import load_spec
from codegen.spec_model import Spec

ROOT = Path(__file__).resolve().parents[1]
SPEC = ROOT / "spec" / "paper_motor.yaml"
ARM_GCC = shutil.which("arm-none-eabi-gcc")
ARM_OBJDUMP = shutil.which("arm-none-eabi-objdump")
HOST_CC = shutil.which("cc") or shutil.which("gcc")

STUB_CORE_HEADER = """\
/* Stub of the generated core's header: the contract only. bldc_commutation_timing()
 * records its arguments and returns what the harness scripted. */
#ifndef BLDC_COMMUTATION_H
#define BLDC_COMMUTATION_H
#include <stdint.h>
#define BLDC_PWM_PERIOD_COUNTS   {period}u
#define BLDC_EDGE_NONE           0xFFu
#define BLDC_EDGE_COUNT          12u
#define BLDC_PERIOD_NEVER        0x10000u
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


def _write_port(directory: Path, spec: Spec, period: int = 3600) -> None:
    for name, text in port.render_port_files(spec).items():
        (directory / name).write_text(text, encoding="utf-8")
    (directory / "bldc_commutation.h").write_text(
        STUB_CORE_HEADER.format(period=period), encoding="utf-8"
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
            f"/* Generated from template c/{name}.j2 with spec spec/paper_motor.yaml"
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


@pytest.mark.skipif(ARM_GCC is None or ARM_OBJDUMP is None, reason="arm-none-eabi-gcc missing")
def test_port_should_compile_for_cortex_m3_without_division_or_float_helpers(
    tmp_path: Path, spec: Spec
) -> None:
    _write_port(tmp_path, spec)
    run = _compile_arm(tmp_path)
    assert run.returncode == 0, run.stderr
    assert ARM_OBJDUMP is not None
    dump = subprocess.run(
        [ARM_OBJDUMP, "-d", "-r", "stm32f103_port.o"],
        cwd=tmp_path,
        capture_output=True,
        text=True,
        check=True,
    ).stdout
    assert "<TIM3_IRQHandler>:" in dump
    assert "<bldc_port_init>:" in dump
    assert "__aeabi_" not in dump
    assert not re.search(r"\b[us]div\b", dump)
    called = set(re.findall(r"R_ARM_THM_(?:CALL|JUMP24)\s+(\w+)", dump))
    # nothing else leaves the object (port_update_bus and port_outputs_off are the port's
    # own cold paths), and the Hall edge does not call the core
    assert {"bldc_bus_condition", "bldc_commutation_timing"} <= called
    assert called <= {
        "bldc_bus_condition",
        "bldc_commutation_timing",
        "port_update_bus",
        "port_outputs_off",
    }
    handler = dump[dump.index("<TIM3_IRQHandler>:") :].split("\n\n")[0]
    assert "bldc_" not in handler


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

HOST_SHIM = """\
/* Force-included before the port: the generated register header, with the
 * peripheral instances pointing at plain memory instead of the STM32 address map, and
 * the NVIC calls recorded. */
#include "stm32f103_regs.h"
extern TIM_TypeDef fake_tim1, fake_tim3;
extern RCC_TypeDef fake_rcc;
extern GPIO_TypeDef fake_gpioa, fake_gpiob;
extern unsigned long fake_nvic_enabled, fake_nvic_pending;
extern unsigned fake_nvic_priority[64];
#undef TIM1
#undef TIM3
#undef RCC
#undef GPIOA
#undef GPIOB
#define TIM1 (&fake_tim1)
#define TIM3 (&fake_tim3)
#define RCC (&fake_rcc)
#define GPIOA (&fake_gpioa)
#define GPIOB (&fake_gpiob)
#define NVIC_EnableIRQ(n) (fake_nvic_enabled |= 1ul << (n))
#define NVIC_SetPendingIRQ(n) (fake_nvic_pending |= 1ul << (n))
#define NVIC_SetPriority(n, p) (fake_nvic_priority[(n)] = (p))
"""

HOST_HARNESS = r"""
#include <stdio.h>
#include "stm32f103_port.h"

TIM_TypeDef fake_tim1, fake_tim3;
RCC_TypeDef fake_rcc;
GPIO_TypeDef fake_gpioa, fake_gpiob;
unsigned long fake_nvic_enabled, fake_nvic_pending;
unsigned fake_nvic_priority[64];

static bldc_timing_t stub_next = {BLDC_PERIOD_NEVER, 0u, 0u, 0u, 0u};
static uint32_t stub_seen[4];
static unsigned timing_runs;
static unsigned bus_runs;
static unsigned long raw_egr, raw_sr; /* TIM1 EGR and TIM3 SR as the Hall edge left them */

bldc_bus_t bldc_bus_condition(uint32_t bus_code)
{
    bldc_bus_t bus = {0u, 0u, 0, 0u, bus_code, 0u};
    ++bus_runs;
    return bus;
}

bldc_timing_t bldc_commutation_timing(const bldc_bus_t *bus, uint32_t period_ticks,
                                      uint32_t current_adc, uint32_t main_duty_counts)
{
    stub_seen[0] = bus->bus_code;
    stub_seen[1] = period_ticks;
    stub_seen[2] = current_adc;
    stub_seen[3] = main_duty_counts;
    ++timing_runs;
    return stub_next;
}

#define SET(reg, value) (*(volatile uint32_t *)&(reg) = (uint32_t)(value))

/* The NVIC: a COM event with COMIE set, or a software pend, runs the timing handler
 * once the higher-priority TIM3 handler has returned. */
static void settle_after(int handler_wrote_egr)
{
    const int com = handler_wrote_egr && (fake_tim1.EGR & TIM_EGR_COMG) != 0u &&
                    (fake_tim1.DIER & TIM_DIER_COMIE) != 0u;
    const int pended = (fake_nvic_pending & (1ul << TIM1_TRG_COM_IRQn)) != 0u;
    fake_nvic_pending = 0u;
    if (com || pended) {
        TIM1_TRG_COM_IRQHandler();
    }
}

static void settle(void)
{
    settle_after(0);
}

/* The duties and commutation time the next timing computation returns. */
static void plan(unsigned period_min, unsigned on_cmp, unsigned off_cmp, unsigned ticks)
{
    stub_next.period_min = period_min;
    stub_next.turn_on_compare = (uint16_t)on_cmp;
    stub_next.turn_off_compare = (uint16_t)off_cmp;
    stub_next.commutation_ticks = (uint16_t)ticks;
    fake_nvic_pending |= 1ul << TIM1_TRG_COM_IRQn; /* as a new input would */
    settle();
}

static void hall(unsigned code)
{
    SET(fake_gpioa.IDR, ((code >> 2) & 1u) << 6 | ((code >> 1) & 1u) << 7);
    SET(fake_gpiob.IDR, code & 1u);
}

/* A Hall edge into `code`: the TIM3 handler, then whatever it raised. */
static void edge(unsigned code, unsigned status, unsigned captured, unsigned cnt)
{
    hall(code);
    fake_tim3.CCR1 = captured;
    fake_tim3.CNT = cnt;
    fake_tim3.EGR = 0u;
    fake_tim1.EGR = 0u;
    fake_tim3.SR = status;
    timing_runs = 0u;
    TIM3_IRQHandler();
    raw_egr = fake_tim1.EGR;
    raw_sr = fake_tim3.SR;
    settle_after(1);
}

static void end_of_commutation(void)
{
    fake_tim1.EGR = 0u;
    fake_tim3.SR = TIM_SR_CC2IF;
    timing_runs = 0u;
    TIM3_IRQHandler();
    settle_after(1);
}

static void show(const char *step)
{
    printf("%s tim1 ccer=%lu ccr1=%lu ccr2=%lu ccr3=%lu egr=%lu tim3 ccr2=%lu egr=%lu "
           "in bus=%lu period=%lu cur=%lu duty=%lu runs=%u busruns=%u edge egr=%lu sr=%lu\n",
           step, (unsigned long)fake_tim1.CCER, (unsigned long)fake_tim1.CCR1,
           (unsigned long)fake_tim1.CCR2, (unsigned long)fake_tim1.CCR3,
           (unsigned long)fake_tim1.EGR, (unsigned long)fake_tim3.CCR2,
           (unsigned long)fake_tim3.EGR, (unsigned long)stub_seen[0],
           (unsigned long)stub_seen[1], (unsigned long)stub_seen[2],
           (unsigned long)stub_seen[3], timing_runs, bus_runs, raw_egr, raw_sr);
}

int main(void)
{
    fake_gpioa.CRL = fake_gpioa.CRH = fake_gpiob.CRL = fake_gpiob.CRH = 0x44444444u; /* reset */
    hall(5u);
    bldc_port_init();
    printf("init tim1 cr1=%lu cr2=%lu ccmr1=%lu ccmr2=%lu ccer=%lu bdtr=%lu psc=%lu arr=%lu "
           "dier=%lu tim3 cr1=%lu cr2=%lu smcr=%lu ccmr1=%lu ccer=%lu dier=%lu psc=%lu arr=%lu "
           "cnt=%lu rcc apb2=%lu apb1=%lu gpioa crl=%lu crh=%lu gpiob crl=%lu crh=%lu "
           "nvic enabled=%lu hall=%u timing=%u\n",
           (unsigned long)fake_tim1.CR1, (unsigned long)fake_tim1.CR2,
           (unsigned long)fake_tim1.CCMR1, (unsigned long)fake_tim1.CCMR2,
           (unsigned long)fake_tim1.CCER, (unsigned long)fake_tim1.BDTR,
           (unsigned long)fake_tim1.PSC, (unsigned long)fake_tim1.ARR,
           (unsigned long)fake_tim1.DIER,
           (unsigned long)fake_tim3.CR1, (unsigned long)fake_tim3.CR2,
           (unsigned long)fake_tim3.SMCR, (unsigned long)fake_tim3.CCMR1,
           (unsigned long)fake_tim3.CCER, (unsigned long)fake_tim3.DIER,
           (unsigned long)fake_tim3.PSC, (unsigned long)fake_tim3.ARR,
           (unsigned long)fake_tim3.CNT,
           (unsigned long)fake_rcc.APB2ENR, (unsigned long)fake_rcc.APB1ENR,
           (unsigned long)fake_gpioa.CRL, (unsigned long)fake_gpioa.CRH,
           (unsigned long)fake_gpiob.CRL, (unsigned long)fake_gpiob.CRH, fake_nvic_enabled,
           fake_nvic_priority[TIM3_IRQn], fake_nvic_priority[TIM1_TRG_COM_IRQn]);
    settle_after(1); /* the COM event of the initial UG | COMG */

    /* before any bus voltage: the timing is the safe state */
    edge(5u, TIM_SR_CC1IF, 5000u, 10u);
    show("nobus");
    bldc_port_set_bus_voltage(2000u);
    settle();
    bldc_adc_phase_current = 2500u;
    bldc_port_set_main_duty(1500u);
    settle();
    show("inputs");
    /* forward into sector 1 (edge 1): T5 (C upper) on at 2000, T3 (B upper) off at 1000;
     * the first interval after start-up is unknown (UIF from the counter preset) */
    plan(100u, 2000u, 1000u, 300u);
    edge(4u, TIM_SR_CC1IF | TIM_SR_UIF, 1234u, 10u);
    show("edge1");
    end_of_commutation();
    show("end1");
    timing_runs = 0u;
    bldc_port_set_main_duty(1700u);
    settle();
    show("duty");
    bldc_port_set_main_duty(4000u);
    settle();
    show("clamp");
    timing_runs = 0u;
    bldc_port_set_main_duty(4000u);
    settle();
    show("same");
    bldc_port_set_main_duty(1500u);
    settle();
    /* forward into sector 2 (edge 2): T4 (B lower) on at 500, T2 (A lower) off at 800;
     * latency past t_com */
    plan(100u, 500u, 800u, 300u);
    edge(6u, TIM_SR_CC1IF, 5000u, 400u);
    show("edge2");
    end_of_commutation();
    show("end2");
    /* back into sector 1 (reverse edge 7): T1 (A upper) on, T3 (B upper) off, while T4
     * (B lower) conducts: phase B would swap switches, refused, all off */
    plan(100u, 900u, 700u, 300u);
    edge(4u, TIM_SR_CC1IF, 5000u, 10u);
    show("swap");
    end_of_commutation();
    show("after_swap");
    /* from all-off anything is safe again */
    edge(6u, TIM_SR_CC1IF, 5000u, 10u);
    show("recover");
    /* over-speed now: an interval below the timing's minimum period */
    plan(6000u, 900u, 700u, 300u);
    edge(2u, TIM_SR_CC1IF, 5000u, 10u);
    show("overspeed");
    plan(100u, 900u, 700u, 300u);
    /* invalid Hall: all off, and the pending end is dropped */
    edge(7u, TIM_SR_CC1IF, 5000u, 10u);
    show("invalid");
    end_of_commutation();
    show("after_invalid");
    /* Hall timeout since the last edge: the interval reads as the full counter */
    edge(6u, TIM_SR_CC1IF | TIM_SR_UIF, 17u, 10u);
    show("timeout");

    /* The bus state is cached: recomputed only for a change beyond the hysteresis. */
    timing_runs = 0u;
    bus_runs = 0u;
    bldc_port_set_bus_voltage(2000u); /* unchanged */
    settle();
    show("bus_same");
    bldc_port_set_bus_voltage((uint16_t)(2000u + BLDC_PORT_BUS_HYSTERESIS_CODES)); /* noise */
    settle();
    show("bus_noise");
    bldc_port_set_bus_voltage((uint16_t)(2001u + BLDC_PORT_BUS_HYSTERESIS_CODES));
    settle();
    show("bus_step");
    timing_runs = 0u;
    bus_runs = 0u;
    edge(2u, TIM_SR_CC1IF, 5000u, 10u); /* an edge recomputes the timing, not the bus */
    show("bus_edge");
    bldc_port_set_bus_voltage((uint16_t)BLDC_PORT_BUS_CODE_MAX);
    settle();
    timing_runs = 0u;
    bus_runs = 0u;
    bldc_port_set_bus_voltage((uint16_t)(BLDC_PORT_BUS_CODE_MAX + 1u)); /* over-voltage */
    settle();
    show("bus_over");
    timing_runs = 0u;
    bus_runs = 0u;
    bldc_port_set_bus_voltage((uint16_t)BLDC_PORT_BUS_CODE_MAX); /* and back */
    settle();
    show("bus_back");
    return 0;
}
"""


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


@pytest.fixture(scope="module")
def host_run(tmp_path_factory: pytest.TempPathFactory, spec: Spec) -> dict[str, dict[str, int]]:
    if HOST_CC is None:
        pytest.skip("no host C compiler")
    directory = tmp_path_factory.mktemp("host")
    _write_port(directory, spec)
    (directory / "shim.h").write_text(HOST_SHIM, encoding="utf-8")
    (directory / "harness.c").write_text(HOST_HARNESS, encoding="utf-8")
    build = subprocess.run(
        [
            HOST_CC,
            "-std=c99",
            "-O1",
            "-include",
            "shim.h",
            "-I.",
            "harness.c",
            "stm32f103_port.c",
            "-o",
            "harness",
        ],
        cwd=directory,
        capture_output=True,
        text=True,
    )
    assert build.returncode == 0, build.stderr
    out = subprocess.run(
        ["./harness"], cwd=directory, capture_output=True, text=True, check=True
    ).stdout
    return {line.split()[0]: _parse(line) for line in out.splitlines()}


def test_init_should_configure_the_timers_per_rm0008(host_run: dict[str, dict[str, int]]) -> None:
    r = host_run["init"]
    assert r["tim1.cr2"] == 0x1  # CCPC: enables preloaded until a COM event
    assert r["tim1.ccmr1"] == 0x6868  # OC1M = OC2M = 110 (PWM 1), OC1PE, OC2PE
    assert r["tim1.ccmr2"] == 0x68  # OC3M = 110, OC3PE
    assert r["tim1.ccer"] == 0  # every output disabled
    assert r["tim1.bdtr"] == 0x8000 | 0x800 | 0x400 | 0x24  # MOE, OSSR, OSSI, DTG
    assert (r["tim1.psc"], r["tim1.arr"]) == (0, 3599)
    assert r["tim1.cr1"] == 0x81  # ARPE, CEN, edge-aligned
    assert r["tim1.dier"] == 0x20  # COMIE: every COM event runs the next edge's timing
    assert r["tim3.cr2"] == 0x80  # TI1S: XOR of CH1..CH3
    assert r["tim3.smcr"] == 0x44  # TS = 100 (TI1F_ED), SMS = 100 (reset)
    assert r["tim3.ccmr1"] == 0x33  # CC1S = 11 (TRC), IC1F = 0011; CC2 frozen compare
    assert r["tim3.ccer"] == 0x1  # CC1 capture on, CC2 output off
    assert r["tim3.dier"] == 0x6  # CC1IE, CC2IE; UIF is polled by the next edge
    assert r["tim3.cnt"] == 65535  # preset: the first tick overflows and sets UIF
    assert (r["tim3.psc"], r["tim3.arr"]) == (71, 65535)
    assert r["tim3.cr1"] == 0x5  # URS, CEN
    assert r["rcc.apb2"] == (1 << 2) | (1 << 3) | (1 << 11)  # IOPA, IOPB, TIM1
    assert r["rcc.apb1"] == 1 << 1  # TIM3
    assert r["gpioa.crh"] == 0x44444BBB  # PA8..10 AF push-pull 50 MHz
    assert r["gpiob.crh"] == 0xBBB44444  # PB13..15 AF push-pull 50 MHz
    assert r["gpioa.crl"] == 0x88444444  # PA6, PA7 input with pull
    assert r["gpiob.crl"] == 0x44444448  # PB0 input with pull
    assert r["nvic.enabled"] == (1 << 26) | (1 << 29)  # TIM1_TRG_COM, TIM3 (SVD numbers)
    assert r["nvic.hall"] < r["nvic.timing"]  # the Hall edge preempts the timing


def test_hall_edge_should_apply_the_precomputed_pattern_at_one_com_event(
    host_run: dict[str, dict[str, int]],
) -> None:
    r = host_run["edge1"]
    assert r["tim1.ccer"] == 0x110  # CC2E (T3), CC3E (T5)
    assert (r["tim1.ccr2"], r["tim1.ccr3"]) == (1000, 2000)
    assert r["edge.egr"] == 0x21  # COMG | UG
    assert r["tim3.ccr2"] == 300  # counter restarted at the edge: compare = t_com
    assert r["tim3.egr"] == 0  # still ahead: the hardware match will end it
    assert r["edge.sr"] == 0xFFFFFFFF & ~0x5  # CC2IF and the timeout's UIF cleared


def test_every_hall_edge_should_recompute_the_timing_from_the_interval_just_measured(
    host_run: dict[str, dict[str, int]],
) -> None:
    r = host_run["edge1"]
    assert r["in.runs"] == 1  # the edge's COM event ran the timing once
    assert r["in.period"] == 65535  # the first interval after start-up is unknown
    assert (r["in.bus"], r["in.cur"], r["in.duty"]) == (2000, 2500, 1500)
    assert host_run["edge2"]["in.period"] == 5000
    assert host_run["timeout"]["in.period"] == 65535  # a wrapped counter reads as its range
    for step in ("nobus", "swap", "invalid", "overspeed"):
        assert host_run[step]["in.runs"] == 1  # the safe state is a COM event too


def test_new_inputs_should_recompute_the_timing_only_when_they_matter(
    host_run: dict[str, dict[str, int]],
) -> None:
    assert host_run["inputs"]["in.bus"] == 2000  # a new bus voltage pends the timing
    # The improved rule (Eq. 18) does not use the main duty: a new one changes the
    # steady switch's compare value but pends no recomputation.
    assert host_run["inputs"]["in.duty"] == 0
    assert host_run["duty"]["in.runs"] == 0
    assert host_run["same"]["in.runs"] == 0
    # A commutation end is a COM event too: the timing is recomputed with the latest
    # current after it.
    assert host_run["end1"]["in.runs"] == 1


def test_port_should_keep_the_bridge_off_until_it_knows_the_bus_voltage(
    host_run: dict[str, dict[str, int]],
) -> None:
    r = host_run["nobus"]
    assert r["in.bus"] == 0xFFFF  # the start-up bus code is the over-voltage one
    assert r["tim1.ccer"] == 0
    assert r["edge.egr"] == 0x21


def test_commutation_end_should_leave_the_incoming_switch_at_main_duty(
    host_run: dict[str, dict[str, int]],
) -> None:
    r = host_run["end1"]
    assert r["tim1.ccer"] == 0x100  # CC3E only: T3 off
    assert r["tim1.ccr3"] == 1500
    assert r["tim1.egr"] == 0x21
    assert host_run["duty"]["tim1.ccr3"] == 1700
    assert host_run["clamp"]["tim1.ccr3"] == 3600


def test_lower_switch_should_get_its_on_time_as_compare(
    host_run: dict[str, dict[str, int]],
) -> None:
    r = host_run["edge2"]
    # CCxNE alone: OCxN = OCxREF (RM0008 Table 83), so CCR = the ON time, not ARR - it.
    assert r["tim1.ccer"] == 0x044  # CC1NE (T2), CC2NE (T4)
    assert (r["tim1.ccr1"], r["tim1.ccr2"]) == (800, 500)
    assert r["tim3.egr"] == 0x4  # CNT 400 already past 300: CC2G raises the end
    assert host_run["end2"]["tim1.ccer"] == 0x40


def test_a_phase_swapping_switches_should_turn_everything_off(
    host_run: dict[str, dict[str, int]],
) -> None:
    assert host_run["swap"]["tim1.ccer"] == 0
    assert host_run["swap"]["edge.egr"] == 0x21
    assert host_run["after_swap"]["tim1.ccer"] == 0
    assert host_run["after_swap"]["tim1.egr"] == 0  # no end was pending
    assert host_run["recover"]["tim1.ccer"] == 0x044


def test_an_interval_below_the_timings_minimum_should_turn_everything_off(
    host_run: dict[str, dict[str, int]],
) -> None:
    r = host_run["overspeed"]
    assert r["tim1.ccer"] == 0
    assert r["edge.egr"] == 0x21
    assert r["edge.sr"] == 0xFFFFFFFF & ~0x5  # no commutation end left to run


def test_invalid_hall_should_disable_all_outputs(host_run: dict[str, dict[str, int]]) -> None:
    assert host_run["invalid"]["tim1.ccer"] == 0
    assert host_run["after_invalid"]["tim1.ccer"] == 0
    assert host_run["after_invalid"]["tim1.egr"] == 0


def test_bus_state_should_be_recomputed_only_beyond_the_hysteresis(
    host_run: dict[str, dict[str, int]],
) -> None:
    # the same code and a change within the hysteresis cost nothing
    for step in ("bus_same", "bus_noise"):
        assert (host_run[step]["in.runs"], host_run[step]["in.busruns"]) == (0, 0), step
    # a larger change recomputes the bus state once and the timing with it
    r = host_run["bus_step"]
    assert (r["in.runs"], r["in.busruns"]) == (1, 1)
    assert r["in.bus"] == 2001 + port.BUS_HYSTERESIS_CODES
    # the Hall edge's own timing run reuses the cached bus state
    r = host_run["bus_edge"]
    assert (r["in.runs"], r["in.busruns"]) == (1, 0)
    assert r["in.bus"] == 2001 + port.BUS_HYSTERESIS_CODES


def test_over_voltage_should_be_recomputed_whatever_the_hysteresis(
    host_run: dict[str, dict[str, int]], spec: Spec
) -> None:
    from codegen.derivation import derive
    from codegen.fixedpoint.scaling import scaling

    bus_max = scaling(spec, derive()).bus_code_max
    # the port's threshold is the core's
    assert _defines(port.port_context(spec))["BLDC_PORT_BUS_CODE_MAX"] == f"{bus_max}u"
    core = (ROOT / "generated" / spec.name / "c" / "bldc_commutation.h").read_text()
    assert f"#define BLDC_BUS_CODE_MAX {bus_max}u" in core
    assert port.BUS_HYSTERESIS_CODES >= 1  # so one code is within it
    over, back = host_run["bus_over"], host_run["bus_back"]
    assert (over["in.runs"], over["in.busruns"], over["in.bus"]) == (1, 1, bus_max + 1)
    assert (back["in.runs"], back["in.busruns"], back["in.bus"]) == (1, 1, bus_max)


def test_pin_indexed_edge_table_should_give_the_cores_edge_for_every_pair(spec: Spec) -> None:
    """PA6 = Hall A, PA7 = Hall B, PB0 = Hall C, read as PA6 | PA7 << 1 | PB0 << 2; each
    entry is the packed record of the edge's two switches (codegen.port.EDGE_RECORD_LAYOUT),
    checked here against RM0008's CCER layout written out by hand."""
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
                | channel(on) << 11
                | channel(off) << 13
                | (ccer_bit(partner(on)) | ccer_bit(partner(off))) << 16
            )
    assert len(expected) == 12
    for previous in range(8):
        for code in range(8):
            want = expected.get((previous, code), 0)
            assert table[pins(previous) << 3 | pins(code)] == want, (previous, code)

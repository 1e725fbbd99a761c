"""The STM32F103 register map read from the vendor SVD, and the header built from it.

The numbers typed here are checks of the parse against RM0008 (memory map, register
descriptions, vector table), not inputs of the generator.
"""

from __future__ import annotations

import re
import shutil
import subprocess
from pathlib import Path

import pytest

from codegen import svd
from codegen.render import TEMPLATE_DIR
from codegen.spec_loader import load_spec

ROOT = Path(__file__).resolve().parents[1]
SPEC = ROOT / "spec" / "paper_motor.yaml"
ARM_GCC = shutil.which("arm-none-eabi-gcc")


@pytest.fixture(scope="module")
def device() -> svd.Device:
    return svd.load_device()


@pytest.fixture(scope="module")
def header() -> str:
    return svd.render_regs_header(load_spec(SPEC))


def test_parse_should_find_the_reference_manual_base_addresses(device: svd.Device) -> None:
    assert device.peripheral("TIM1").base_address == 0x40012C00
    assert device.peripheral("TIM3").base_address == 0x40000400
    assert device.peripheral("RCC").base_address == 0x40021000
    assert device.peripheral("GPIOA").base_address == 0x40010800
    assert device.peripheral("GPIOB").base_address == 0x40010C00
    assert device.peripheral("AFIO").base_address == 0x40010000


def test_derived_peripheral_should_reuse_its_base_registers_but_keep_its_interrupts(
    device: svd.Device,
) -> None:
    tim3 = device.peripheral("TIM3")
    assert tim3.derived_from == "TIM2"
    assert tim3.registers == device.peripheral("TIM2").registers
    assert tim3.register("CCR1").address_offset == 0x34
    assert [(i.name, i.value) for i in tim3.interrupts] == [("TIM3", 29)]
    assert device.peripheral("GPIOB").registers == device.peripheral("GPIOA").registers


def test_parse_should_read_field_positions_and_widths(device: svd.Device) -> None:
    bdtr = device.peripheral("TIM1").register("BDTR")
    fields = {f.name: (f.bit_offset, f.bit_width) for f in bdtr.fields}
    assert bdtr.address_offset == 0x44
    assert fields["MOE"] == (15, 1)
    assert fields["DTG"] == (0, 8)
    apb2 = device.peripheral("RCC").register("APB2ENR")
    assert {f.name: f.bit_offset for f in apb2.fields}["TIM1EN"] == 11


def test_header_should_carry_cube_field_macros(header: str) -> None:
    assert "#define TIM_BDTR_MOE_Pos (15U)" in header
    assert "#define TIM_BDTR_MOE_Msk (0x1U << TIM_BDTR_MOE_Pos)" in header
    assert "#define TIM_BDTR_MOE TIM_BDTR_MOE_Msk" in header
    assert "#define TIM_CR1_CEN_Pos (0U)" in header
    assert "#define RCC_APB2ENR_TIM1EN_Pos (11U)" in header
    assert "#define RCC_APB1ENR_TIM3EN_Pos (1U)" in header
    assert "#define TIM_BDTR_DTG_7 (0x80U << TIM_BDTR_DTG_Pos)" in header
    # Fields from both timer kinds: TIM1's complementary enables, TIM3's are a subset.
    assert "#define TIM_CCER_CC1NE_Pos (2U)" in header
    assert "#define TIM_CR2_TI1S_Pos (7U)" in header


def test_header_should_correct_the_svd_misspellings(header: str) -> None:
    assert "#define TIM_CCMR1_IC1PSC_Pos (2U)" in header
    assert "#define TIM_CCMR2_OC4CE_Pos (15U)" in header
    assert "ICPCS" not in header
    assert "O24CE" not in header


def test_header_should_take_irq_numbers_from_the_svd(header: str) -> None:
    assert "TIM1_UP_IRQn = 25," in header
    assert "TIM1_CC_IRQn = 27," in header
    assert "TIM3_IRQn = 29 " in header


def test_header_should_take_the_nvic_address_from_the_svd(header: str) -> None:
    assert "#define NVIC_ISER_BASE 0xE000E100UL" in header


def test_header_should_start_with_provenance_and_be_guarded_for_cube(header: str) -> None:
    first = header.splitlines()[0]
    assert first.startswith("/* Generated from template templates/c/stm32f103_regs.h.j2")
    assert "Do not edit" in first
    assert '#if defined(USE_CMSIS_DEVICE_HEADER)\n\n#include "stm32f1xx.h"' in header


def test_templates_should_not_type_addresses() -> None:
    for name in ("stm32f103_regs.h.j2", "stm32f103_port.h.j2", "stm32f103_port.c.j2"):
        text = (TEMPLATE_DIR / "c" / name).read_text(encoding="utf-8")
        assert not re.findall(r"0x[0-9A-Fa-f]{4,}", text), name


def test_struct_padding_should_follow_the_offsets(header: str) -> None:
    afio = header[header.index("typedef struct {\n    __IO uint32_t EVCR") :]
    afio = afio[: afio.index("} AFIO_TypeDef;")]
    assert "__IO uint32_t EXTICR[4];" in afio
    assert "uint32_t RESERVED0; /* Reserved, 0x18-0x1b */" in afio
    assert "__O uint32_t EGR;" in header  # write-only in the SVD
    assert "__I uint32_t IDR;" in header  # read-only in the SVD


SMALL_SVD = b"""<?xml version="1.0" encoding="utf-8"?>
<device><name>TOY</name><version>0.1</version><size>32</size>
<peripherals>
  <peripheral><name>T1</name><groupName>T</groupName><baseAddress>0x40000000</baseAddress>
    <interrupt><name>T1_UP</name><description>update</description><value>7</value></interrupt>
    <registers>
      <register><name>MODE_Output</name><addressOffset>0x0</addressOffset>
        <fields><field><name>OM</name><bitOffset>4</bitOffset><bitWidth>3</bitWidth></field></fields>
      </register>
      <register><name>MODE_Input</name><alternateRegister>MODE_Output</alternateRegister>
        <addressOffset>0x0</addressOffset>
        <fields><field><name>IF</name><lsb>4</lsb><msb>7</msb></field></fields>
      </register>
      <register><name>CNT</name><addressOffset>0xC</addressOffset><access>read-only</access>
        <fields><field><name>CNT</name><bitRange>[15:0]</bitRange></field></fields>
      </register>
    </registers>
  </peripheral>
  <peripheral derivedFrom="T1"><name>T2</name><baseAddress>0x40000400</baseAddress></peripheral>
</peripherals></device>
"""


def test_parse_svd_should_read_every_bit_range_form_and_resolve_derivation() -> None:
    dev = svd.parse_svd(SMALL_SVD, "toy.svd")
    t1, t2 = dev.peripheral("T1"), dev.peripheral("T2")
    assert t2.registers == t1.registers and t2.group_name == "T"
    # cmsis-svd follows the SVD spec literally: a derived peripheral that lists no
    # interrupt of its own inherits its base's (ST's file lists each instance's own).
    assert t2.interrupts == t1.interrupts
    fields = {f.name: (f.bit_offset, f.bit_width) for r in t1.registers for f in r.fields}
    assert fields == {"OM": (4, 3), "IF": (4, 4), "CNT": (0, 16)}
    assert t1.register("CNT").access == "read-only"
    assert t1.register("MODE_Input").alternate_of == "MODE_Output"


def test_parse_svd_should_refuse_a_derivation_cycle() -> None:
    cyclic = SMALL_SVD.replace(
        b"<peripheral><name>T1</name>", b'<peripheral derivedFrom="T2"><name>T1</name>'
    )
    with pytest.raises(ValueError, match="derivedFrom cycle"):
        svd.parse_svd(cyclic)


@pytest.mark.skipif(ARM_GCC is None, reason="arm-none-eabi-gcc not installed")
def test_header_should_compile_with_the_layout_of_the_reference_manual(
    tmp_path: Path, header: str
) -> None:
    (tmp_path / "stm32f103_regs.h").write_text(header, encoding="utf-8")
    checks = """
#include <stddef.h>
#include "stm32f103_regs.h"
_Static_assert(offsetof(TIM_TypeDef, CCMR1) == 0x18, "CCMR1");
_Static_assert(offsetof(TIM_TypeDef, RCR) == 0x30, "RCR");
_Static_assert(offsetof(TIM_TypeDef, BDTR) == 0x44, "BDTR");
_Static_assert(offsetof(TIM_TypeDef, DMAR) == 0x4C, "DMAR");
_Static_assert(offsetof(RCC_TypeDef, APB2ENR) == 0x18, "APB2ENR");
_Static_assert(offsetof(RCC_TypeDef, APB1ENR) == 0x1C, "APB1ENR");
_Static_assert(offsetof(GPIO_TypeDef, IDR) == 0x08, "IDR");
_Static_assert(offsetof(GPIO_TypeDef, LCKR) == 0x18, "LCKR");
_Static_assert(offsetof(AFIO_TypeDef, EXTICR) == 0x08, "EXTICR");
_Static_assert(offsetof(AFIO_TypeDef, MAPR2) == 0x1C, "MAPR2");
_Static_assert(TIM_BDTR_MOE == 0x8000UL, "MOE");
_Static_assert(TIM_EGR_COMG == 0x20UL, "COMG");
_Static_assert(TIM_CCER_CC3NE == 0x400UL, "CC3NE");
_Static_assert(TIM_SMCR_SMS_Msk == 0x7UL, "SMS");
_Static_assert(GPIO_CRH_CNF15_Pos == 30U, "CNF15");
_Static_assert(TIM3_IRQn == 29, "TIM3_IRQn");
/* the core's cycle counter, as ARMv7-M ARM C1.8.7 and C1.6.5 (and CMSIS core_cm3.h) */
_Static_assert(offsetof(DWT_Type, CYCCNT) == 0x4, "CYCCNT");
_Static_assert(offsetof(CoreDebug_Type, DEMCR) == 0xC, "DEMCR");
_Static_assert(DWT_BASE == 0xE0001000UL, "DWT");
_Static_assert(CoreDebug_BASE == 0xE000EDF0UL, "CoreDebug");
_Static_assert(DWT_CTRL_CYCCNTENA_Msk == 0x1UL, "CYCCNTENA");
_Static_assert(CoreDebug_DEMCR_TRCENA_Msk == 0x1000000UL, "TRCENA");
void enable(void) { NVIC_EnableIRQ(TIM3_IRQn); TIM1->BDTR |= TIM_BDTR_MOE; }
"""
    (tmp_path / "check.c").write_text(checks, encoding="utf-8")
    flags = ["-std=c11", "-mcpu=cortex-m3", "-mthumb", "-O2", "-Wall", "-Wextra", "-Werror"]
    run = subprocess.run(
        [ARM_GCC, *flags, "-c", "check.c", "-o", "check.o"],
        cwd=tmp_path,
        capture_output=True,
        text=True,
    )
    assert run.returncode == 0, run.stderr


@pytest.mark.skipif(ARM_GCC is None, reason="arm-none-eabi-gcc not installed")
def test_cube_projects_should_get_their_own_device_header(tmp_path: Path, header: str) -> None:
    (tmp_path / "stm32f103_regs.h").write_text(header, encoding="utf-8")
    (tmp_path / "stm32f1xx.h").write_text("int cube_device_header_was_used;\n", encoding="utf-8")
    (tmp_path / "use.c").write_text('#include "stm32f103_regs.h"\n', encoding="utf-8")
    run = subprocess.run(
        [ARM_GCC, "-DUSE_CMSIS_DEVICE_HEADER", "-E", "-P", "use.c"],
        cwd=tmp_path,
        capture_output=True,
        text=True,
    )
    assert run.returncode == 0, run.stderr
    assert "cube_device_header_was_used" in run.stdout
    assert "TIM_TypeDef" not in run.stdout

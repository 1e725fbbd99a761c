"""STM32F103 register map from the vendor SVD, and the minimal CMSIS header built from it.

No address, offset or bit position of the generated `stm32f103_regs.h` is typed by
hand: they all come from ST's CMSIS-SVD description of the STM32F103
(`codegen/data/STM32F103xx.svd`, the file pyocd ships; see codegen/data/NOTICE.md),
read with the cmsis-svd parser. Typing them in would make the header a second,
unchecked copy of RM0008; reading them keeps one source.

The header is deliberately small (only what the port uses) and CMSIS/Cube compatible:
the same type, instance, field and IRQ names as STM32Cube's `stm32f103xb.h`, so that a
Cube project can define USE_CMSIS_DEVICE_HEADER and get Cube's own `stm32f1xx.h`.
"""

from __future__ import annotations

import functools
import hashlib
import importlib.resources
import re
import xml.etree.ElementTree as ET
from dataclasses import dataclass

from codegen.render import provenance, render
from codegen.spec_model import Spec

SVD_MEMBER = "STM32F103xx.svd"
#: Where the file came from, for the header's provenance (codegen/data/NOTICE.md).
SVD_ORIGIN = "ST STM32F103xx.svd v1.3 (Apache-2.0), as shipped in pyocd's svd_data.zip"

REGS_TEMPLATE = "c/stm32f103_regs.h.j2"
REGS_HEADER = "stm32f103_regs.h"


@dataclass(frozen=True)
class Field:
    name: str
    bit_offset: int
    bit_width: int
    description: str


@dataclass(frozen=True)
class Register:
    name: str
    address_offset: int
    size_bits: int
    access: str  # "read-write", "read-only", "write-only", ...
    fields: tuple[Field, ...]
    #: Name of the register this one overlays (SVD <alternateRegister>), e.g. the
    #: capture view CCMR1_Input of the compare view CCMR1_Output.
    alternate_of: str | None
    description: str


@dataclass(frozen=True)
class Interrupt:
    name: str
    value: int
    description: str


@dataclass(frozen=True)
class Peripheral:
    name: str
    group_name: str
    base_address: int
    #: SVD derivedFrom: the peripheral whose registers this one reuses (TIM3 <- TIM2).
    derived_from: str | None
    registers: tuple[Register, ...]
    interrupts: tuple[Interrupt, ...]

    def register(self, name: str) -> Register:
        for reg in self.registers:
            if reg.name == name:
                return reg
        raise KeyError(f"{self.name} has no register {name!r}")


@dataclass(frozen=True)
class Device:
    name: str
    version: str
    source: str  # archive member the device was read from
    sha256: str  # of the SVD bytes, so the header says exactly which file it used
    peripherals: tuple[Peripheral, ...]

    def peripheral(self, name: str) -> Peripheral:
        for p in self.peripherals:
            if p.name == name:
                return p
        raise KeyError(f"{self.name} SVD has no peripheral {name!r}")


# --------------------------------------------------------------------------- parsing


def _words(text: str | None) -> str:
    """SVD descriptions wrap lines inside the XML: one space between words."""
    return " ".join((text or "").split())


def _access(value: object, default: str) -> str:
    if value is None:
        return default
    return str(getattr(value, "value", value))


def _check_derivations(data: bytes) -> None:
    """Refuse a derivedFrom cycle before the parser follows it (it would not return)."""
    root = ET.fromstring(data)
    base = {
        (el.findtext("name") or "").strip(): el.get("derivedFrom") for el in root.iter("peripheral")
    }
    for name in base:
        chain = [name]
        while (parent := base.get(chain[-1])) is not None:
            if parent in chain:
                raise ValueError(f"SVD: derivedFrom cycle {' -> '.join((*chain, parent))}")
            if parent not in base:
                raise ValueError(f"SVD: {chain[-1]} is derived from unknown peripheral {parent!r}")
            chain.append(parent)


def parse_svd(data: bytes, source: str = SVD_MEMBER) -> Device:
    """Parse CMSIS-SVD bytes with cmsis-svd (derivedFrom resolved) into the frozen view
    the header is built from. A derived peripheral keeps its own name and base address
    and inherits whatever else it does not redefine (registers, group, and interrupts if
    it lists none; ST's file lists each instance's own)."""
    from cmsis_svd.parser import SVDParser

    _check_derivations(data)
    parsed = SVDParser(_lxml_tree(data)).get_device()
    device_access = _access(parsed.access, "read-write")
    peripherals = []
    for p in parsed.peripherals:
        registers = []
        for r in p.registers or ():
            if getattr(r, "dim", None):
                raise ValueError(
                    f"SVD: {p.name}.{r.name} is a dim array, which this reader does not expand"
                )
            fields = tuple(
                sorted(
                    (
                        Field(f.name, int(f.bit_offset), int(f.bit_width), _words(f.description))
                        for f in r.fields or ()
                    ),
                    key=lambda f: f.bit_offset,
                )
            )
            registers.append(
                Register(
                    name=r.name,
                    address_offset=int(r.address_offset),
                    size_bits=int(r.size),
                    access=_access(r.access, _access(p.access, device_access)),
                    fields=fields,
                    alternate_of=r.alternate_register,
                    description=_words(r.description),
                )
            )
        peripherals.append(
            Peripheral(
                name=p.name,
                group_name=p.group_name or p.name,
                base_address=int(p.base_address),
                derived_from=p.derived_from,
                registers=tuple(registers),
                interrupts=tuple(
                    Interrupt(i.name, int(i.value), _words(i.description))
                    for i in p.interrupts or ()
                ),
            )
        )
    return Device(
        name=parsed.name,
        version=parsed.version or "",
        source=source,
        sha256=hashlib.sha256(data).hexdigest(),
        peripherals=tuple(peripherals),
    )


def _lxml_tree(data: bytes) -> object:
    """The lxml tree cmsis-svd's SVDParser takes, without entity expansion or network."""
    from lxml import etree

    parser = etree.XMLParser(resolve_entities=False, no_network=True, huge_tree=False)
    return etree.ElementTree(etree.fromstring(data, parser))


def svd_bytes() -> bytes:
    """The vendor SVD kept in the package (codegen/data, see its NOTICE)."""
    return importlib.resources.files("codegen.data").joinpath(SVD_MEMBER).read_bytes()


@functools.lru_cache(maxsize=1)
def load_device() -> Device:
    """The parsed STM32F103 device (cached: the SVD is 850 kB)."""
    return parse_svd(svd_bytes(), SVD_MEMBER)


# ------------------------------------------------------------ the CMSIS header's content

#: Known misspellings in ST's STM32F103xx.svd v1.3, mapped to the names RM0008 and Cube
#: use: (group, CMSIS register, SVD field) -> field. The merge below checks that the
#: corrected name lands on the same bits as the correctly spelled field of the other
#: timer instance (TIM1's ICPCS sits where TIM3's IC1PSC does).
SVD_FIELD_ERRATA: dict[tuple[str, str, str], str] = {
    ("TIM", "CCMR1", "ICPCS"): "IC1PSC",
    ("TIM", "CCMR2", "O24CE"): "OC4CE",
}


@dataclass(frozen=True)
class CmsisType:
    """One CMSIS struct type, e.g. TIM_TypeDef, shared by several SVD instances."""

    type_name: str
    #: Peripheral whose register map lays out the struct: the superset (TIM1 is the
    #: advanced timer; TIM3's map must match it wherever both have a register).
    layout_from: str
    instances: tuple[str, ...]
    #: Registers whose fields get _Pos/_Msk macros: the ones the port reads or writes.
    field_registers: tuple[str, ...]
    #: Cube declares runs of numbered registers as one array (AFIO EXTICR1..4 ->
    #: EXTICR[4]); other numbered registers (TIM CCR1..4) stay separate members.
    arrays: tuple[str, ...] = ()


CMSIS_TYPES: tuple[CmsisType, ...] = (
    CmsisType(
        "TIM_TypeDef",
        layout_from="TIM1",
        instances=("TIM1", "TIM3"),
        field_registers=(
            "CR1",
            "CR2",
            "SMCR",
            "DIER",
            "SR",
            "EGR",
            "CCMR1",
            "CCMR2",
            "CCER",
            "CNT",
            "PSC",
            "ARR",
            "CCR1",
            "CCR2",
            "CCR3",
            "CCR4",
            "BDTR",
        ),
    ),
    CmsisType(
        "RCC_TypeDef",
        layout_from="RCC",
        instances=("RCC",),
        field_registers=("CR", "CFGR", "CIR", "APB2ENR", "APB1ENR", "CSR"),
    ),
    CmsisType(
        "GPIO_TypeDef",
        layout_from="GPIOA",
        instances=("GPIOA", "GPIOB"),
        field_registers=("CRL", "CRH", "IDR", "BSRR"),
    ),
    CmsisType(
        "ADC_TypeDef",
        layout_from="ADC1",
        instances=("ADC1", "ADC2"),
        field_registers=(
            "SR",
            "CR1",
            "CR2",
            "SMPR1",
            "SMPR2",
            "HTR",
            "LTR",
            "SQR1",
            "SQR3",
            "JSQR",
            "JDR1",
            "JDR2",
            "JDR3",
            "JDR4",
            "DR",
        ),
    ),
    CmsisType(
        "FLASH_TypeDef",
        layout_from="FLASH",
        instances=("FLASH",),
        field_registers=("ACR",),
    ),
    CmsisType(
        "IWDG_TypeDef",
        layout_from="IWDG",
        instances=("IWDG",),
        field_registers=("KR", "PR", "RLR", "SR"),
    ),
    CmsisType(
        "AFIO_TypeDef",
        layout_from="AFIO",
        instances=("AFIO",),
        field_registers=("MAPR", "EXTICR1", "EXTICR2"),
        arrays=("EXTICR",),
    ),
    CmsisType(
        "EXTI_TypeDef",
        layout_from="EXTI",
        instances=("EXTI",),
        field_registers=("IMR", "RTSR", "FTSR", "SWIER", "PR"),
    ),
)

#: Cube IRQn name (without _IRQn) -> the peripheral whose SVD <interrupt> gives its
#: number, and the SVD's own name where it is not the Cube name or its prefix. The SVD
#: describes the XL-density line, where TIM9..11 share TIM1's vectors (TIM1_UP_TIM10);
#: Cube's stm32f103xb.h calls the same vector TIM1_UP_IRQn. ADC1 and ADC2 share one
#: vector, which the SVD calls ADC and Cube ADC1_2.
CMSIS_IRQS: tuple[tuple[str, str, str | None], ...] = (
    ("EXTI0", "EXTI", None),
    ("ADC1_2", "ADC1", "ADC"),
    ("EXTI9_5", "EXTI", None),
    ("TIM1_BRK", "TIM1", None),
    ("TIM1_UP", "TIM1", None),
    ("TIM1_TRG_COM", "TIM1", None),
    ("TIM1_CC", "TIM1", None),
    ("TIM3", "TIM3", None),
)

#: Core peripherals the vendor SVD does not describe: the Cortex-M3's SysTick timer,
#: from the ARMv7-M Architecture Reference Manual (B3.3.2: SYST_CSR at 0xE000E010, its
#: ENABLE, CLKSOURCE and COUNTFLAG bits), the same on every Cortex-M3. The one place
#: the header's addresses are typed rather than read.
SYSTICK_BASE = 0xE000E010
SYSTICK_CSR_BITS: tuple[tuple[str, int, str], ...] = (
    ("SysTick_CTRL_ENABLE_Msk", 0, "counter enabled"),
    ("SysTick_CTRL_CLKSOURCE_Msk", 2, "counts the processor clock"),
    ("SysTick_CTRL_COUNTFLAG_Msk", 16, "wrapped since the last read (the read clears it)"),
)

#: The cycle counter, the same on every Cortex-M3 with the DWT (the STM32F103's): the
#: ARMv7-M ARM C1.8.7 DWT_CTRL at 0xE0001000 (CYCCNTENA, bit 0) and DWT_CYCCNT after it,
#: counting the processor clock once CoreDebug DEMCR.TRCENA (C1.6.5, 0xE000EDFC, bit 24)
#: enables the DWT: the Hall lines' confirmation waits on it.
DWT_BASE = 0xE0001000
COREDEBUG_BASE = 0xE000EDF0
CYCLE_COUNTER_BITS: tuple[tuple[str, int, str], ...] = (
    ("DWT_CTRL_CYCCNTENA_Msk", 0, "DWT_CTRL: CYCCNT counts the processor clock"),
    ("CoreDebug_DEMCR_TRCENA_Msk", 24, "DEMCR: the DWT and ITM enabled"),
)

#: The SVD's NVIC peripheral gives the core registers the header needs.
NVIC_PERIPHERAL = "NVIC"
NVIC_ENABLE_REGISTER = "ISER0"
NVIC_PENDING_REGISTER = "ISPR0"
NVIC_PRIORITY_REGISTER = "IPR0"
NVIC_CLEAR_PENDING_REGISTER = "ICPR0"

_QUALIFIER = {
    "read-only": "__I",
    "write-only": "__O",
    "read-write": "__IO",
    "writeOnce": "__IO",
    "read-writeOnce": "__IO",
}


@dataclass(frozen=True)
class _Member:
    """A struct member: one register, an alternate-view group, or a Cube array."""

    name: str
    offset: int
    count: int  # 1, or the array length
    access: str
    description: str


def _cmsis_register_name(group: list[Register]) -> str:
    """Registers sharing an offset are views of one register (CCMR1_Output and
    CCMR1_Input); Cube names the member by their common stem (CCMR1)."""
    if len(group) == 1:
        return group[0].name
    stem = group[0].name
    for reg in group[1:]:
        while not reg.name.startswith(stem):
            stem = stem[:-1]
    stem = stem.rstrip("_")
    if not stem:
        raise ValueError(f"SVD: registers {[r.name for r in group]} share an offset but no name")
    return stem


def _by_offset(p: Peripheral) -> dict[int, list[Register]]:
    groups: dict[int, list[Register]] = {}
    for reg in p.registers:
        groups.setdefault(reg.address_offset, []).append(reg)
    return groups


def _members(p: Peripheral, arrays: tuple[str, ...]) -> list[_Member]:
    members: list[_Member] = []
    for offset, group in sorted(_by_offset(p).items()):
        for reg in group:
            if reg.size_bits != 32:
                raise ValueError(
                    f"SVD: {p.name}.{reg.name} is {reg.size_bits} bits; CMSIS structs here are 32-bit"
                )
        primary = next((r for r in group if r.alternate_of is None), group[0])
        members.append(
            _Member(_cmsis_register_name(group), offset, 1, primary.access, primary.description)
        )
    collapsed: list[_Member] = []
    for m in members:
        match = re.fullmatch(r"([A-Z]+)(\d+)", m.name)
        if match and match.group(1) in arrays:
            stem, index = match.group(1), int(match.group(2))
            if collapsed and collapsed[-1].name == stem:
                last = collapsed[-1]
                if index != last.count + 1 or m.offset != last.offset + 4 * last.count:
                    raise ValueError(f"SVD: {p.name}.{m.name} does not continue array {stem}")
                count = last.count + 1
                collapsed[-1] = _Member(
                    stem, last.offset, count, last.access, f"{stem}1..{stem}{count}"
                )
                continue
            if index != 1:
                raise ValueError(f"SVD: {p.name} array {stem} does not start at {stem}1")
            collapsed.append(_Member(stem, m.offset, 1, m.access, f"{stem}1"))
            continue
        collapsed.append(m)
    return collapsed


def _comment(text: str) -> str:
    """One line, safe inside a C block comment."""
    return " ".join(text.split()).replace("*/", "* /")


def _struct(device: Device, ctype: CmsisType) -> dict[str, object]:
    layout = device.peripheral(ctype.layout_from)
    members = _members(layout, ctype.arrays)
    # Every instance must agree with the layout wherever it has a register: TIM3 (a
    # general-purpose timer) lacks RCR and BDTR but must not move anything.
    layout_offsets = {m.name: m.offset for m in _members(layout, ())}
    for name in ctype.instances:
        inst = device.peripheral(name)
        if inst.group_name != layout.group_name:
            raise ValueError(f"SVD: {name} is in group {inst.group_name}, not {layout.group_name}")
        for m in _members(inst, ()):
            if layout_offsets.get(m.name) != m.offset:
                raise ValueError(
                    f"SVD: {name}.{m.name} at offset {m.offset:#x} does not fit"
                    f" {ctype.type_name} laid out from {ctype.layout_from}"
                )
    lines: list[dict[str, str]] = []
    next_offset = 0
    reserved = 0
    for m in members:
        gap = m.offset - next_offset
        if gap < 0 or gap % 4:
            raise ValueError(f"SVD: {layout.name}.{m.name} overlaps or misaligns the struct")
        if gap:
            words = gap // 4
            lines.append(
                {
                    "qualifier": "uint32_t",
                    "declarator": f"RESERVED{reserved}" + (f"[{words}]" if words > 1 else ""),
                    "comment": f"Reserved, {next_offset:#04x}-{m.offset - 1:#04x}",
                }
            )
            reserved += 1
        declarator = m.name + (f"[{m.count}]" if m.count > 1 else "")
        lines.append(
            {
                "qualifier": f"{_QUALIFIER.get(m.access, '__IO')} uint32_t",
                "declarator": declarator,
                "comment": f"{_comment(m.description)}, offset {m.offset:#04x}",
            }
        )
        next_offset = m.offset + 4 * m.count
    return {"type_name": ctype.type_name, "members": lines}


def _merged_fields(device: Device, ctype: CmsisType) -> dict[str, list[Field]]:
    """Fields per CMSIS register name, merged over the instances and the alternate
    views (capture and compare), misspellings corrected, conflicts refused."""
    group = device.peripheral(ctype.layout_from).group_name
    merged: dict[str, dict[str, Field]] = {}
    for name in dict.fromkeys((ctype.layout_from, *ctype.instances)):
        inst = device.peripheral(name)
        for regs in _by_offset(inst).values():
            reg_name = _cmsis_register_name(regs)
            if reg_name not in ctype.field_registers:
                continue
            for reg in regs:
                for f in reg.fields:
                    fname = SVD_FIELD_ERRATA.get((group, reg_name, f.name), f.name)
                    field = Field(fname, f.bit_offset, f.bit_width, f.description)
                    known = merged.setdefault(reg_name, {}).get(fname)
                    if known is None:
                        merged[reg_name][fname] = field
                    elif (known.bit_offset, known.bit_width) != (f.bit_offset, f.bit_width):
                        raise ValueError(
                            f"SVD: {group}_{reg_name}_{fname} is bits {known.bit_offset}+{known.bit_width}"
                            f" in one instance and {f.bit_offset}+{f.bit_width} in {name}"
                        )
    missing = set(ctype.field_registers) - merged.keys()
    if missing:
        raise ValueError(f"SVD: {ctype.layout_from} has no register(s) {sorted(missing)}")
    return {
        reg: sorted(fields.values(), key=lambda f: (f.bit_offset, f.name))
        for reg, fields in merged.items()
    }


def _field_macros(group: str, reg: str, fields: list[Field]) -> list[dict[str, str]]:
    """Cube's pattern: X_Pos (n), X_Msk (m << X_Pos), X = X_Msk, and X_0.. X_k for
    each bit of a multi-bit field (up to 8 bits, as Cube does for codes like OC1M)."""
    out: list[dict[str, str]] = []
    for f in fields:
        base = f"{group}_{reg}_{f.name}"
        ones = (1 << f.bit_width) - 1
        mask = ones << f.bit_offset
        out.append({"name": f"{base}_Pos", "value": f"({f.bit_offset}U)", "comment": ""})
        out.append(
            {
                "name": f"{base}_Msk",
                "value": f"({ones:#x}U << {base}_Pos)",
                "comment": f"0x{mask:08X}",
            }
        )
        out.append({"name": base, "value": f"{base}_Msk", "comment": _comment(f.description)})
        if 1 < f.bit_width <= 8:
            for bit in range(f.bit_width):
                out.append(
                    {
                        "name": f"{base}_{bit}",
                        "value": f"({1 << bit:#x}U << {base}_Pos)",
                        "comment": f"0x{1 << (f.bit_offset + bit):08X}",
                    }
                )
    return out


def _irq(
    device: Device, cmsis: str, peripheral: str, svd_name: str | None = None
) -> dict[str, str]:
    p = device.peripheral(peripheral)
    if svd_name is not None:
        hits = [i for i in p.interrupts if i.name == svd_name]
    else:
        hits = [i for i in p.interrupts if i.name == cmsis or i.name.startswith(cmsis + "_")]
    if len(hits) != 1:
        raise ValueError(
            f"SVD: {peripheral} interrupts {[i.name for i in p.interrupts]} give"
            f" {len(hits)} candidates for {cmsis}_IRQn"
        )
    irq = hits[0]
    return {
        "name": f"{cmsis}_IRQn",
        "value": str(irq.value),
        "comment": f"{_comment(irq.description)} (SVD {irq.name})",
    }


def regs_context(device: Device | None = None) -> dict[str, object]:
    """Everything stm32f103_regs.h.j2 needs, printed: structs, bases, IRQs, fields."""
    dev = device if device is not None else load_device()
    structs = [_struct(dev, t) for t in CMSIS_TYPES]
    instances = []
    fields = []
    for t in CMSIS_TYPES:
        group = dev.peripheral(t.layout_from).group_name
        for name in t.instances:
            p = dev.peripheral(name)
            derived = f", registers of {p.derived_from}" if p.derived_from else ""
            instances.append(
                {
                    "name": name,
                    "base": f"0x{p.base_address:08X}UL",
                    "type_name": t.type_name,
                    "comment": f"SVD {name}{derived}",
                }
            )
        merged = _merged_fields(dev, t)
        for reg in t.field_registers:
            fields.append(
                {"title": f"{group}_{reg}", "macros": _field_macros(group, reg, merged[reg])}
            )
    nvic = dev.peripheral(NVIC_PERIPHERAL)
    iser = nvic.register(NVIC_ENABLE_REGISTER)
    ispr = nvic.register(NVIC_PENDING_REGISTER)
    ipr = nvic.register(NVIC_PRIORITY_REGISTER)
    icpr = nvic.register(NVIC_CLEAR_PENDING_REGISTER)
    return {
        "svd_name": dev.name,
        "svd_version": dev.version,
        "svd_source": f"codegen/data/{dev.source} ({SVD_ORIGIN})",
        "svd_sha256": dev.sha256,
        "structs": structs,
        "instances": instances,
        "irqs": [_irq(dev, c, p, n) for c, p, n in CMSIS_IRQS],
        "nvic_iser_base": f"0x{nvic.base_address + iser.address_offset:08X}UL",
        "nvic_iser_comment": f"SVD {NVIC_PERIPHERAL}.{NVIC_ENABLE_REGISTER}: {_comment(iser.description)}",
        "nvic_ispr_base": f"0x{nvic.base_address + ispr.address_offset:08X}UL",
        "nvic_ispr_comment": f"SVD {NVIC_PERIPHERAL}.{NVIC_PENDING_REGISTER}: {_comment(ispr.description)}",
        "nvic_ipr_base": f"0x{nvic.base_address + ipr.address_offset:08X}UL",
        "nvic_icpr_base": f"0x{nvic.base_address + icpr.address_offset:08X}UL",
        "nvic_icpr_comment": f"SVD {NVIC_PERIPHERAL}.{NVIC_CLEAR_PENDING_REGISTER}: {_comment(icpr.description)}",
        "nvic_ipr_comment": f"SVD {NVIC_PERIPHERAL}.{NVIC_PRIORITY_REGISTER}: {_comment(ipr.description)}",
        "field_groups": fields,
        "systick_base": f"0x{SYSTICK_BASE:08X}UL",
        "systick_comment": "ARMv7-M ARM B3.3.2 SYST_CSR (not in the vendor SVD)",
        "systick_bits": [
            {"name": name, "value": f"(1UL << {bit}U)", "comment": doc}
            for name, bit, doc in SYSTICK_CSR_BITS
        ],
        "dwt_base": f"0x{DWT_BASE:08X}UL",
        "dwt_comment": "ARMv7-M ARM C1.8.7 DWT_CTRL (not in the vendor SVD)",
        "coredebug_base": f"0x{COREDEBUG_BASE:08X}UL",
        "coredebug_comment": "ARMv7-M ARM C1.6 DHCSR (not in the vendor SVD)",
        "cycle_counter_bits": [
            {"name": name, "value": f"(1UL << {bit}U)", "comment": doc}
            for name, bit, doc in CYCLE_COUNTER_BITS
        ],
    }


def render_regs_header(spec: Spec, device: Device | None = None) -> str:
    """Text of stm32f103_regs.h (spec-independent content; the spec only names the run)."""
    return render(
        REGS_TEMPLATE,
        provenance=provenance(f"templates/{REGS_TEMPLATE}", spec),
        **regs_context(device),
    )

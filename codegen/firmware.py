"""Start-up code, linker script, clock tree and main() for the project's own STM32F103
build, and (for `firmware.integration: cube`) the stm32f1xx_it.c a Cube project would
hold.

`make firmware` links them with the generated core, current loop and port. The vector
table is laid out here (a plain list of handler names) so the template stays free of
arithmetic; the interrupt numbers come from the vendor SVD.
"""

from __future__ import annotations

from codegen.port_drive import HANDLERS, cube_handlers, handler_names
from codegen.render import provenance, render
from codegen.spec_model import Spec
from codegen.svd import load_device
from codegen.system_clock import system_context

#: STM32F103xB peripheral interrupts (RM0008 Table 63: IRQ 0..42).
PERIPHERAL_IRQS = 43
TEMPLATES = {
    "firmware/stm32f103.ld": "firmware/stm32f103.ld.j2",
    "firmware/startup_stm32f103.c": "firmware/startup_stm32f103.c.j2",
    "firmware/system_stm32f103.c": "firmware/system_stm32f103.c.j2",
    "firmware/system_stm32f103.h": "firmware/system_stm32f103.h.j2",
    "firmware/main.c": "firmware/main.c.j2",
}
CUBE_TEMPLATES = {"firmware/stm32f1xx_it.c": "firmware/stm32f1xx_it.c.j2"}
#: Exception numbers (ARMv7-M ARM B1.5.2) of the core handlers the firmware defines.
CORE_HANDLERS = {2: "NMI_Handler", 3: "HardFault_Handler"}


#: The port's handlers: role -> (SVD peripheral, SVD interrupt name). The SVD describes
#: the XL-density line, whose TIM1 vectors TIM9..TIM11 share; ADC1 and ADC2 share one.
PORT_INTERRUPTS: dict[str, tuple[str, str]] = {
    "timing": ("TIM1", "TIM1_TRG_COM_TIM11"),
    "bus": ("TIM1", "TIM1_UP_TIM10"),
    "hall": ("TIM3", "TIM3"),
    "adc": ("ADC1", "ADC"),
    "brk": ("TIM1", "TIM1_BRK_TIM9"),
    "hall_line0": ("EXTI", "EXTI0"),
    "hall_lines9_5": ("EXTI", "EXTI9_5"),
}


def irq_number(peripheral: str, interrupt: str) -> int:
    p = load_device().peripheral(peripheral)
    (irq,) = [i.value for i in p.interrupts if i.name == interrupt]
    return irq


def tim3_irq_number() -> int:
    return irq_number("TIM3", "TIM3")


def port_handlers() -> list[dict[str, object]]:
    """The vector table entries of the port's interrupts, under their CMSIS names (the
    port's own names in vector-table integration, stm32f1xx_it.c's in Cube's)."""
    return [
        {
            "name": HANDLERS[role].vector,
            "irq": irq_number(*PORT_INTERRUPTS[role]),
            "svd": PORT_INTERRUPTS[role][1],
        }
        for role in ("timing", "bus", "hall", "adc", "brk", "hall_line0", "hall_lines9_5")
    ]


def vector_table() -> list[str]:
    """Handler of each vector: initial SP slot first, then exceptions, then IRQs."""
    table = ["Reset_Handler"] + ["Default_Handler"] * (15 + PERIPHERAL_IRQS - 1)
    for exception, name in CORE_HANDLERS.items():
        table[exception - 1] = name
    for handler in port_handlers():
        table[15 + int(str(handler["irq"]))] = str(handler["name"])
    return table


def render_firmware_files(spec: Spec) -> dict[str, str]:
    cube = spec.firmware.integration == "cube"
    context = {
        "cube_handlers": cube_handlers(),
        "handlers": port_handlers(),
        "vectors": vector_table(),
        "vector_count": 16 + PERIPHERAL_IRQS,
        "cube": cube,
        "handler": handler_names(spec),
        **system_context(spec),
    }
    templates = {**TEMPLATES, **(CUBE_TEMPLATES if cube else {})}
    return {
        out: render(template, provenance=provenance(f"templates/{template}", spec), **context)
        for out, template in templates.items()
    }

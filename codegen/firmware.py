"""Start-up code, linker script and main() for the project's own STM32F103 build.

`make firmware` links them with the generated core and port to measure flash and RAM.
The vector table is laid out here (a plain list of handler names) so the template stays
free of arithmetic; the interrupt numbers come from the vendor SVD.
"""

from __future__ import annotations

from codegen.render import provenance, render
from codegen.spec_model import Spec
from codegen.svd import load_device

#: STM32F103xB peripheral interrupts (RM0008 Table 63: IRQ 0..42).
PERIPHERAL_IRQS = 43
TEMPLATES = {
    "firmware/stm32f103.ld": "firmware/stm32f103.ld.j2",
    "firmware/startup_stm32f103.c": "firmware/startup_stm32f103.c.j2",
    "firmware/main.c": "firmware/main.c.j2",
}


#: The port's handlers: (SVD peripheral, SVD interrupt name) -> CMSIS handler name. The
#: SVD describes the XL-density line, whose TIM1 trigger/COM vector TIM11 shares.
PORT_HANDLERS: tuple[tuple[str, str, str], ...] = (
    ("TIM1", "TIM1_TRG_COM_TIM11", "TIM1_TRG_COM_IRQHandler"),
    ("TIM3", "TIM3", "TIM3_IRQHandler"),
)


def irq_number(peripheral: str, interrupt: str) -> int:
    p = load_device().peripheral(peripheral)
    (irq,) = [i.value for i in p.interrupts if i.name == interrupt]
    return irq


def tim3_irq_number() -> int:
    return irq_number("TIM3", "TIM3")


def port_handlers() -> list[dict[str, object]]:
    return [
        {"name": handler, "irq": irq_number(peripheral, interrupt), "svd": interrupt}
        for peripheral, interrupt, handler in PORT_HANDLERS
    ]


def vector_table() -> list[str]:
    """Handler of each vector: initial SP slot first, then exceptions, then IRQs."""
    table = ["Reset_Handler"] + ["Default_Handler"] * (15 + PERIPHERAL_IRQS - 1)
    for handler in port_handlers():
        table[15 + int(str(handler["irq"]))] = str(handler["name"])
    return table


def render_firmware_files(spec: Spec) -> dict[str, str]:
    context = {
        "handlers": port_handlers(),
        "vectors": vector_table(),
        "vector_count": 16 + PERIPHERAL_IRQS,
    }
    return {
        out: render(template, provenance=provenance(f"templates/{template}", spec), **context)
        for out, template in TEMPLATES.items()
    }

"""Start-up code, linker script and main() for the project's own STM32F103 build.

`make firmware` links them with the generated core and port to measure flash and RAM.
The vector table is laid out here (a plain list of handler names) so the template stays
free of arithmetic; the TIM3 interrupt number comes from the vendor SVD.
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


def tim3_irq_number() -> int:
    tim3 = load_device().peripheral("TIM3")
    (irq,) = [i.value for i in tim3.interrupts if i.name == "TIM3"]
    return irq


def vector_table() -> list[str]:
    """Handler of each vector: initial SP slot first, then exceptions, then IRQs."""
    table = ["Reset_Handler"] + ["Default_Handler"] * (15 + PERIPHERAL_IRQS - 1)
    table[15 + tim3_irq_number()] = "TIM3_IRQHandler"
    return table


def render_firmware_files(spec: Spec) -> dict[str, str]:
    context = {
        "tim3_irq": tim3_irq_number(),
        "vectors": vector_table(),
        "vector_count": 16 + PERIPHERAL_IRQS,
    }
    return {
        out: render(template, provenance=provenance(f"templates/{template}", spec), **context)
        for out, template in TEMPLATES.items()
    }

"""Register plumbing shared by the peripheral models: names from the SVD, dispatch, errors.

Every peripheral model declares, per register name, what a read returns and what a
write does. An access to a register the model does not declare, to a peripheral no model
covers, or with a width the model does not accept, is a `PilError` naming the address,
the peripheral and the register as the vendor SVD calls them: a model says what it does
not model (STYLE.md 15), it never answers with a silent zero.

The core's own registers (SysTick, SCB, DWT, CoreDebug) are not in the vendor SVD; their names and
offsets come from the ARMv7-M Architecture Reference Manual (`CORE_REGISTERS`).
"""

from __future__ import annotations

import functools
from collections.abc import Callable
from typing import TYPE_CHECKING

from codegen.svd import load_device

if TYPE_CHECKING:
    from emulation.pil.machine import Machine

#: ARMv7-M ARM B3.3.2 (SysTick), B3.2.2 (System control block), C1.8.7 (DWT: its
#: control and cycle counter) and C1.6 (CoreDebug: DEMCR): base, name -> offset.
CORE_REGISTERS: dict[str, tuple[int, dict[str, int]]] = {
    "DWT": (0xE0001000, {"CTRL": 0x0, "CYCCNT": 0x4}),
    "CoreDebug": (0xE000EDF0, {"DHCSR": 0x0, "DCRSR": 0x4, "DCRDR": 0x8, "DEMCR": 0xC}),
    "SysTick": (0xE000E010, {"CSR": 0x0, "RVR": 0x4, "CVR": 0x8, "CALIB": 0xC}),
    "SCB": (
        0xE000ED00,
        {
            "CPUID": 0x00,
            "ICSR": 0x04,
            "VTOR": 0x08,
            "AIRCR": 0x0C,
            "SCR": 0x10,
            "CCR": 0x14,
            "SHPR1": 0x18,
            "SHPR2": 0x1C,
            "SHPR3": 0x20,
            "SHCSR": 0x24,
            "CFSR": 0x28,
            "HFSR": 0x2C,
        },
    ),
}


class PilError(RuntimeError):
    """The firmware did something the emulated STM32F103 cannot answer faithfully, or
    something that would fail on the chip (a hard fault, a watchdog reset)."""


class UnmodelledAccessError(PilError):
    """A register or peripheral access that no model implements."""


class NotYetKnownError(PilError):
    """An input asked for an instant the emulated time has not reached: a causal source
    (the motor in the loop) knows its value only once the chip has run to it. A model
    that looks ahead (the ADC's analog watchdog) stops there and checks again then."""


Reader = Callable[[], int]
Writer = Callable[[int], None]


@functools.lru_cache(maxsize=1)
def _svd_names() -> dict[int, tuple[str, str]]:
    """Absolute word address -> (peripheral, register) for every SVD register, and the
    core registers; alternate views (CCMR1_Output / CCMR1_Input) share one name."""
    names: dict[int, tuple[str, str]] = {}
    for peripheral in load_device().peripherals:
        for register in peripheral.registers:
            address = peripheral.base_address + register.address_offset
            name = register.name.split("_")[0] if register.alternate_of else register.name
            if register.name.endswith("_Output"):
                name = register.name[: -len("_Output")]
            names.setdefault(address, (peripheral.name, name))
    for peripheral_name, (base, registers) in CORE_REGISTERS.items():
        for register_name, offset in registers.items():
            names[base + offset] = (peripheral_name, register_name)
    return names


def describe_address(address: int) -> str:
    """`TIM1.CCR1 (0x40012c34)`, or the peripheral and offset when the SVD has no register
    there, or just the address."""
    word = address & ~3
    hit = _svd_names().get(word)
    if hit is not None:
        byte = f" byte {address - word}" if address != word else ""
        return f"{hit[0]}.{hit[1]}{byte} (0x{address:08x})"
    device = load_device()
    for peripheral in device.peripherals:
        if peripheral.base_address <= address < peripheral.base_address + 0x400:
            return f"{peripheral.name} offset 0x{address - peripheral.base_address:03x} (0x{address:08x}, no register in the SVD)"
    return f"0x{address:08x} (no peripheral in the SVD)"


def svd_offsets(peripheral: str) -> dict[str, int]:
    """Register name -> offset of an SVD peripheral (or a core block of CORE_REGISTERS)."""
    if peripheral in CORE_REGISTERS:
        return dict(CORE_REGISTERS[peripheral][1])
    offsets: dict[str, int] = {}
    for register in load_device().peripheral(peripheral).registers:
        name = register.name
        for suffix in ("_Output", "_Input"):
            if name.endswith(suffix):
                name = name[: -len(suffix)]
        offsets.setdefault(name, register.address_offset)
    return offsets


def svd_base(peripheral: str) -> int:
    if peripheral in CORE_REGISTERS:
        return CORE_REGISTERS[peripheral][0]
    return load_device().peripheral(peripheral).base_address


def svd_interrupt(peripheral: str, name: str) -> int:
    """The IRQ number of the SVD interrupt `name` of `peripheral`."""
    for interrupt in load_device().peripheral(peripheral).interrupts:
        if interrupt.name == name:
            return interrupt.value
    raise KeyError(f"SVD: {peripheral} has no interrupt {name!r}")


class Peripheral:
    """A memory-mapped register block. Subclasses fill `readers` and `writers` by
    register name (SVD spelling); `byte_access` names the registers that take 8- and
    16-bit accesses (the NVIC's priority bytes); every other register is word-only.

    Time: `next_event()` is the tick (1/72 MHz) of the model's next autonomous change
    (a counter wrap, a conversion's end), None for none; the machine calls `on_event`
    at that tick. A model computes what it shows at a register read (a counter) from
    `machine.now`.
    """

    name: str
    base: int
    size: int = 0x400

    def __init__(self, machine: Machine, svd_name: str) -> None:
        self.machine = machine
        self.svd_name = svd_name
        self.base = svd_base(svd_name)
        offsets = svd_offsets(svd_name)
        self.register_at: dict[int, str] = {offset: name for name, offset in offsets.items()}
        self.readers: dict[str, Reader] = {}
        self.writers: dict[str, Writer] = {}
        self.byte_access: frozenset[str] = frozenset()

    def _register(self, offset: int, size: int, write: bool) -> str:
        word = offset & ~3
        name = self.register_at.get(word)
        what = "write to" if write else "read of"
        if name is None:
            raise UnmodelledAccessError(
                f"{what} {describe_address(self.base + offset)}: no {self.svd_name} register there"
            )
        table = self.writers if write else self.readers
        if name not in table:
            raise UnmodelledAccessError(
                f"{what} {describe_address(self.base + offset)}: {self.svd_name}.{name} is not modelled"
                f" for {'writes' if write else 'reads'} (emulation/pil models only what it cites from RM0008)"
            )
        if (size != 4 or offset != word) and name not in self.byte_access:
            raise UnmodelledAccessError(
                f"{size}-byte {what} {describe_address(self.base + offset)}: {self.svd_name}.{name}"
                " is modelled for 32-bit accesses only"
            )
        return name

    def read(self, offset: int, size: int) -> int:
        name = self._register(offset, size, write=False)
        value = self.readers[name]()
        shift = 8 * (offset & 3)
        return (value >> shift) & ((1 << (8 * size)) - 1)

    def write(self, offset: int, size: int, value: int) -> None:
        name = self._register(offset, size, write=True)
        if size == 4:
            self.writers[name](value & 0xFFFFFFFF)
        else:
            self.write_part(name, offset & 3, size, value)

    def write_part(self, name: str, byte: int, size: int, value: int) -> None:
        """A sub-word write to a register listed in `byte_access`."""
        raise UnmodelledAccessError(f"{self.svd_name}.{name}: sub-word write not modelled")

    def next_event(self) -> int | None:
        return None

    def on_event(self, now: int) -> None:
        """Process what is due at `now` (called when `next_event()` <= now)."""

    def clock_changed(self, now: int) -> None:
        """The RCC changed a clock: re-anchor anything counting on it."""


def bits(value: int, position: int, width: int = 1) -> int:
    return (value >> position) & ((1 << width) - 1)

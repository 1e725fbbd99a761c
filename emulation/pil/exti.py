"""AFIO's EXTI line selection and the EXTI controller (RM0008 sections 9.4 and 10.2).

Behaviours, with their RM0008 sections:
* 9.4.3-9.4.6 AFIO_EXTICR1..4: four bits per EXTI line x (0..15), the GPIO port whose
  pin x drives the line (0000 PA, 0001 PB, ...). Written with the AFIO clock on (the
  machine refuses the access otherwise, RM0008 7.3.7).
* 10.2.2 (the block diagram) and 10.2.4: an edge on line x, of a kind selected in
  10.3.3 RTSR (rising) or 10.3.4 FTSR (falling), sets PR bit x; 10.3.1 IMR bit x lets a
  pending bit request the line's interrupt (EXTI0..EXTI4, EXTI9_5, EXTI15_10 on the
  NVIC, numbers from the SVD). Both edges when both are selected. As the block diagram
  draws it, the pending register comes before the mask: a masked line's edge still sets
  PR (the port clears PR before it unmasks, so it does not depend on this).
* 10.3.6 PR: rc_w1, a 1 clears the bit (and the matching SWIER bit, 10.3.5).
* 10.3.5 SWIER: writing 1 to a bit at 0 with the line's IMR bit set sets its PR bit.
* The line sees the pin's input level (the Schmitt trigger, RM0008 9.1.4): a GPIO input
  pin's level change is passed on at once (`Gpio.watch`).
Not modelled (an error if set): EMR (events), lines 16..18 (PVD, RTC alarm, USB wake-up),
ports other than PA and PB.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from emulation.pil.bus import Peripheral, PilError, svd_interrupt

if TYPE_CHECKING:
    from emulation.pil.gpio import Gpio
    from emulation.pil.machine import Machine

GPIO_LINES = 16
LINE_MASK = (1 << GPIO_LINES) - 1
#: AFIO_EXTICRx port codes (RM0008 9.4.3)
PORT_CODES = {"A": 0, "B": 1}


class Afio(Peripheral):
    def __init__(self, machine: Machine) -> None:
        super().__init__(machine, "AFIO")
        self.exticr = [0, 0, 0, 0]
        for k in range(4):
            self.readers[f"EXTICR{k + 1}"] = lambda k=k: self.exticr[k]
            self.writers[f"EXTICR{k + 1}"] = lambda v, k=k: self._write_exticr(k, v)

    def _write_exticr(self, index: int, value: int) -> None:
        for field in range(4):
            code = (value >> (4 * field)) & 0xF
            if code not in PORT_CODES.values():
                raise PilError(
                    f"AFIO.EXTICR{index + 1} routes EXTI{4 * index + field} to port code {code}:"
                    " only PA and PB are modelled"
                )
        self.exticr[index] = value & 0xFFFF

    def port_of_line(self, line: int) -> int:
        """The port code AFIO_EXTICR gives EXTI line `line` (0..15)."""
        return (self.exticr[line // 4] >> (4 * (line % 4))) & 0xF


class Exti(Peripheral):
    def __init__(self, machine: Machine, afio: Afio, ports: tuple[Gpio, ...]) -> None:
        super().__init__(machine, "EXTI")
        self.afio = afio
        self.imr = 0
        self.rtsr = 0
        self.ftsr = 0
        self.swier = 0
        self.pr = 0
        #: (line, tick) of every edge that set a pending bit
        self.edge_log: list[tuple[int, int]] = []
        self.irqs = {
            line: svd_interrupt("EXTI", name)
            for line, name in [(k, f"EXTI{k}") for k in range(5)]
            + [(k, "EXTI9_5") for k in range(5, 10)]
            + [(k, "EXTI15_10") for k in range(10, 16)]
        }
        self.readers = {
            "IMR": lambda: self.imr,
            "RTSR": lambda: self.rtsr,
            "FTSR": lambda: self.ftsr,
            "SWIER": lambda: self.swier,
            "PR": lambda: self.pr,
        }
        self.writers = {
            "IMR": lambda v: self._write_mask("IMR", "imr", v),
            "RTSR": lambda v: self._write_mask("RTSR", "rtsr", v),
            "FTSR": lambda v: self._write_mask("FTSR", "ftsr", v),
            "SWIER": self._write_swier,
            "PR": self._write_pr,
        }
        for gpio in ports:
            code = PORT_CODES[gpio.port]
            for pin in range(GPIO_LINES):
                gpio.watch(
                    pin, lambda level, tick, pin=pin, code=code: self._edge(pin, code, level)
                )

    def _write_mask(self, name: str, attribute: str, value: int) -> None:
        if value & ~LINE_MASK & 0x7FFFF:
            raise PilError(
                f"EXTI.{name} = 0x{value:08x}: lines 16..18 (PVD, RTC alarm, USB wake-up) are not modelled"
            )
        setattr(self, attribute, value & LINE_MASK)
        self._update_lines()

    def _write_swier(self, value: int) -> None:
        rising = value & ~self.swier & self.imr & LINE_MASK
        self.swier |= value & LINE_MASK
        self.pr |= rising
        self._update_lines()

    def _write_pr(self, value: int) -> None:
        cleared = value & LINE_MASK
        self.pr &= ~cleared
        self.swier &= ~cleared
        self._update_lines()

    def _edge(self, line: int, port_code: int, level: bool) -> None:
        if self.afio.port_of_line(line) != port_code:
            return
        selected = self.rtsr if level else self.ftsr
        if selected >> line & 1:
            self.pr |= 1 << line
            self.edge_log.append((line, self.machine.now))
            self._update_lines()

    def _update_lines(self) -> None:
        requests: dict[int, bool] = {}
        for line, irq in self.irqs.items():
            requests[irq] = requests.get(irq, False) or bool((self.pr & self.imr) >> line & 1)
        for irq, level in requests.items():
            self.machine.nvic.set_line(irq, level)

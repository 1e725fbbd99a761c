"""The port's fault codes, defined once: the header's BLDC_FAULT_* macros, the manifest
(from which tests and the firmware-in-the-loop read them) and the README's table.

Each fault latches a bit in the word `bldc_port_faults()` returns; the bridge goes to
its safe state at once and stays there until `bldc_port_clear_faults()` finds the cause
gone (a `permanent` fault never clears: only a reset does).
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Fault:
    name: str  # BLDC_FAULT_<name>
    bit: int
    detected_by: str
    doc: str
    clears_when: str
    permanent: bool = False

    @property
    def value(self) -> int:
        return 1 << self.bit


FAULTS: tuple[Fault, ...] = (
    Fault(
        "OVER_CURRENT",
        0,
        "TIM1 BKIN (the hardware clears MOE), then TIM1_BRK",
        "the external comparator saw a phase current above protection.over_current",
        "the break input is inactive",
    ),
    Fault(
        "OVER_VOLTAGE",
        1,
        "ADC analog watchdog on the bus channel (regular conversions, continuously, every"
        " 20 ADC cycles or so, and the injected ones)",
        "bus above inverter.bus_voltage_max",
        "the last bus sample is within the range",
    ),
    Fault(
        "UNDER_VOLTAGE",
        2,
        "ADC analog watchdog on the bus channel (as OVER_VOLTAGE)",
        "bus below inverter.bus_voltage_min, or its ADC reading stuck low (the core would"
        " compute with the minimum)",
        "the last bus sample is within the range",
    ),
    Fault(
        "CURRENT_SENSOR",
        3,
        "ADC2's analog watchdog on the current channel(s), converted continuously (every"
        " conversion, at any instant), and the current-loop interrupt's sample",
        "a current sample at an ADC rail (0 or full scale): the sensor is open or saturated",
        "every current channel's last sample is off the rails",
    ),
    Fault(
        "HALL_INVALID",
        4,
        "the Hall edge, and the EXTI on both edges of every Hall line (the code 0 or 7 for"
        " 1 us: two lines changing within TIM3's input filter make no Hall edge)",
        "Hall code 000 or 111 (a sensor unplugged or shorted)",
        "the Hall code now is valid",
    ),
    Fault(
        "HALL_SEQUENCE",
        5,
        "the Hall edge",
        "a Hall code pair that is not one sector forward or back (a skipped or repeated code)",
        "always (the next edge checks again)",
    ),
    Fault(
        "HALL_TIMEOUT",
        6,
        "TIM3's CC3 at 4 T after the last edge (T the interval it ended, where a turning"
        " rotor reaches its next edge by then: codegen/control/hall_timeout.py), else its"
        " update interrupt at the counter's wrap, while the bridge switches (and the"
        " current-loop interrupt, which reads both too)",
        "no Hall edge in time: the rotor stopped, a sensor is unplugged, or the Hall lines"
        " froze at a valid code",
        "always (the next edge checks again)",
    ),
    Fault(
        "OVER_SPEED",
        7,
        "the Hall edge",
        "a Hall interval shorter than at controller.speed_max",
        "always (the next edge checks again)",
    ),
    Fault(
        "CLOCK",
        8,
        "start-up (HSE or PLL timeout) and the clock security system (NMI)",
        "the HSE did not start or failed: the timers do not run at their design clock",
        "never: only a reset",
        permanent=True,
    ),
    Fault(
        "WATCHDOG",
        9,
        "start-up (RCC_CSR.IWDGRSTF)",
        "the last reset was the independent watchdog's",
        "always (it reports the past reset)",
    ),
    Fault(
        "ADC",
        10,
        "start-up",
        "the ADC's calibration did not finish",
        "never: only a reset",
        permanent=True,
    ),
    Fault(
        "EXTERNAL",
        11,
        "bldc_port_raise_fault()",
        "raised by the application",
        "always",
    ),
    Fault(
        "BUS_TRANSIENT",
        12,
        "ADC analog watchdog on the bus channel (as OVER_VOLTAGE), where no bus conversion"
        " its interrupt can read is outside the window any more",
        "the bus left its window for less than a conversion and was back before the"
        " watchdog's interrupt could read the conversion that tripped it (its entry held"
        " by the Hall edge's handler, at the same priority): a spike or a dip, its side not"
        " seen, so neither OVER_VOLTAGE nor UNDER_VOLTAGE is claimed",
        "the last bus sample is within the range",
    ),
)
FAULT = {f.name: f.value for f in FAULTS}
PERMANENT = sum(f.value for f in FAULTS if f.permanent)


def manifest_entry() -> dict[str, object]:
    return {
        "bits": {f.name: f.value for f in FAULTS},
        "permanent": [f.name for f in FAULTS if f.permanent],
    }

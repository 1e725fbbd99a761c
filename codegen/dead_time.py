"""TIM1's dead-time generator: the BDTR.DTG code of a dead time (RM0008 TIMx_BDTR).

Used by the port (the register value) and by the current-sensing design (the dead time
TIM1 really inserts, which the sample window keeps clear of).
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction

#: RM0008 TIMx_BDTR.DTG: the largest dead time, in t_DTS, of the last range
#: (DTG[7:5] = 111: (32 + 31) x 16).
DTG_MAX_TICKS = 1008


@dataclass(frozen=True)
class DeadTime:
    """A dead time as TIM1 programs it: the BDTR.DTG code and what it really gives."""

    dtg: int
    dts_ticks: int  # dead time in t_DTS (= t_CK_INT with CKD = 00)
    requested_s: Fraction
    programmed_s: Fraction


def dtg_dead_time_ticks(dtg: int) -> int:
    """Dead time of a BDTR.DTG code in t_DTS, RM0008 TIMx_BDTR bits 7:0:

    DTG[7:5] = 0xx: DT = DTG[7:0] x t_DTS              0 .. 127
    DTG[7:5] = 10x: DT = (64 + DTG[5:0]) x 2 t_DTS   128 .. 254, step 2
    DTG[7:5] = 110: DT = (32 + DTG[4:0]) x 8 t_DTS   256 .. 504, step 8
    DTG[7:5] = 111: DT = (32 + DTG[4:0]) x 16 t_DTS  512 .. 1008, step 16
    """
    if not 0 <= dtg <= 0xFF:
        raise ValueError(f"DTG is an 8-bit field, got {dtg}")
    if dtg >> 7 == 0:
        return dtg
    if dtg >> 6 == 0b10:
        return (64 + (dtg & 0x3F)) * 2
    if dtg >> 5 == 0b110:
        return (32 + (dtg & 0x1F)) * 8
    return (32 + (dtg & 0x1F)) * 16


def encode_dead_time(dead_time_s: Fraction, timer_clock_hz: Fraction) -> DeadTime:
    """The DTG code of the shortest encodable dead time not shorter than requested.

    Rounds up, never down: a shorter dead time than the spec asks for risks
    shoot-through. t_DTS = t_CK_INT (CR1.CKD = 00), so at 72 MHz the step is 13.9 ns
    and the longest dead time 1008 t_DTS = 14 us. Raises ValueError past that.
    """
    if dead_time_s < 0:
        raise ValueError(f"dead time must not be negative, got {_time(dead_time_s)}")
    wanted = Fraction(dead_time_s) * Fraction(timer_clock_hz)
    if wanted > DTG_MAX_TICKS:
        longest = Fraction(DTG_MAX_TICKS) / Fraction(timer_clock_hz)
        raise ValueError(
            f"dead time {_time(dead_time_s)} is {float(wanted):.1f} TIM1 clocks at"
            f" {_freq(timer_clock_hz)}: not representable in TIM1_BDTR.DTG, whose longest"
            f" dead time is {DTG_MAX_TICKS} t_DTS = {_time(longest)} (RM0008 DTG encoding,"
            " t_DTS = t_CK_INT with CKD = 00); shorten inverter.dead_time or lower"
            " inverter.timer_clock"
        )
    best = min(
        (code for code in range(256) if dtg_dead_time_ticks(code) >= wanted),
        key=lambda code: (dtg_dead_time_ticks(code), code),
    )
    ticks = dtg_dead_time_ticks(best)
    return DeadTime(
        dtg=best,
        dts_ticks=ticks,
        requested_s=Fraction(dead_time_s),
        programmed_s=Fraction(ticks) / Fraction(timer_clock_hz),
    )


def _freq(hz: Fraction) -> str:
    value = float(hz)
    for scale, unit in ((1e6, "MHz"), (1e3, "kHz")):
        if value >= scale:
            return f"{value / scale:g} {unit}"
    return f"{value:g} Hz"


def _time(seconds: Fraction) -> str:
    value = float(seconds)
    if value == 0:
        return "0 s"
    for scale, unit in ((1e-9, "ns"), (1e-6, "us"), (1e-3, "ms")):
        if abs(value) < scale * 1000:
            return f"{value / scale:.4g} {unit}"
    return f"{value:.4g} s"

"""TIM1's dead-time generator: the BDTR.DTG code of a dead time (RM0008 TIMx_BDTR), and
the guard the dead time asks of a commutation's end.

Used by the port (the register value), by the current-sensing design (the dead time
TIM1 really inserts, which the sample window keeps clear of) and by the core's limits
(`commutation_guard_ticks`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from fractions import Fraction
from typing import Any

#: RM0008 TIMx_BDTR.DTG: the largest dead time, in t_DTS, of the last range
#: (DTG[7:5] = 111: (32 + 31) x 16).
DTG_MAX_TICKS = 1008

#: How much later, at most, a commutation end's switch-off can come after its TIM3 match
#: than the next Hall edge's switch-on after that edge: the end may wait for one handler
#: of the Hall edge's priority (213 cycles on the paper motor, `make bench`'s fault
#: paths) and then runs its own path to the CCER write, where the edge's own path to its
#: CCER write is never shorter than about 60 cycles: about 2.8 us at 72 MHz, taken as
#: 4 us, which also covers the DTG code's rounding up (at most 16 t_DTS, 0.22 us). On the
#: HSI fallback the CPU and both timers slow down together, so the guard in Hall ticks
#: holds there too. `make bench` prints the measured figure against it.
COMMUTATION_END_ALLOWANCE_S = Fraction(4, 1_000_000)


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


def commutation_guard_ticks(
    dead_time_s: Fraction, hall_clock_hz: Fraction, sample_room_s: Fraction
) -> int:
    """Hall ticks by which a commutation ends before its sector does at the latest:
    ceil((dead time + COMMUTATION_END_ALLOWANCE_S + sample room) f_hall).

    The commutation end switches the outgoing phase's switch off; the next Hall edge
    switches the other switch of the same leg on, the leg's only output then enabled,
    so TIM1 inserts no dead time between the two (RM0008: dead time is inserted only
    between the complementary outputs of one channel, both enabled). The time between
    them is the guard, at a constant or falling speed: a braking motor's next sector is
    no shorter than the one its timing was computed for.

    The sample room (`codegen.spec_drive.end_sample_room_s`) keeps one current sample
    between the end and the next edge: the braking-current loop samples only outside
    commutations, so a commutation that filled its sector (a conventional one at its
    steady duty lasts L/(2R) at any speed; the improved rule's high segment grows
    without bound near the braking limit) left the loop with no sample, and the timing
    with a current several sectors old."""
    return math.ceil(
        (Fraction(dead_time_s) + COMMUTATION_END_ALLOWANCE_S + Fraction(sample_room_s))
        * Fraction(hall_clock_hz)
    )


#: `hall.sector_shortening` when the spec leaves it out, percent: a Hall placement error
#: of 0.75 electrical degrees (one sensor early, its neighbours late: 4 x 0.75 / 60)
SECTOR_SHORTENING_DEFAULT_PERCENT = 5
#: the largest `hall.sector_shortening` a spec may give, percent
SECTOR_SHORTENING_MAX_PERCENT = 25


#: the largest shift of the margin: T (2^k - 1) stays within 32 bits for a 16-bit T, and
#: from 2^-16 down the margin is one tick at every T
SECTOR_MARGIN_SHIFT_MAX = 16


def sector_margin_shift(shortening: Fraction) -> int | None:
    """k of the margin ceil(T / 2^k) a commutation ends by, beyond the guard, before a
    sector of T measured Hall ticks: the largest k with 2^-k >= `shortening` (5 % -> 4,
    1/16), at most SECTOR_MARGIN_SHIFT_MAX; None for 0. The margin is at least
    shortening x T.

    The guard holds where a sector is as long as the one its timing was computed from
    (two sectors before it: the timing runs after an edge on the interval that edge
    ends, for the next edge). It is not when a Hall sensor sits off its 60 deg mark (a
    sector up to 4 x the error shorter: 6.7 % per electrical degree) or the rotor
    speeds up: the next edge then comes that much earlier, up to onto the end, and
    switches on the partner of the switch the end has just switched off with no dead
    time (`make pil`, a 2 us bridge whose commutations fill their sectors, sectors each
    a little shorter than the one before: a lower switch on 137 TIM1 ticks after its
    partner turned off, dead time 144). In the core the latest end is
    T (2^k - 1) / 2^k - G (`codegen.core.conditioning.CoreLimits.latest_end`)."""
    if shortening <= 0:
        return None
    if shortening > 1:
        raise ValueError(f"a sector cannot be shorter by more than itself: {shortening}")
    k = 0
    while k < SECTOR_MARGIN_SHIFT_MAX and Fraction(1, 2 ** (k + 1)) >= shortening:
        k += 1
    return k


def latest_end_ticks(period_ticks: Any, guard_ticks: int, shift: int | None) -> Any:
    """The latest commutation end in a sector of `period_ticks` (an int or an integer
    array): the guard and the sector-shortening margin ceil(T / 2^k) before its end, as
    the core computes it (`CoreLimits.latest_end`)."""
    if shift is None:
        return period_ticks - guard_ticks
    return ((period_ticks * (2**shift - 1)) >> shift) - guard_ticks


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

"""Spec quantities <-> the integers the firmware sees, written independently of codegen.

Every conversion is one line of physics, in exact rationals:

  Hall ticks -> speed   one Hall interval is 60 electrical degrees, so one electrical
                        turn is 6 T ticks and n = 60 f_hall / (6 p T) rpm (p pole pairs)
  bus code -> volts     U_d = B V_ref k_div / 2^bits
  current code -> amps  I = (C - C0) V_ref / (G 2^bits), C0 = V_off / V_ref 2^bits
                        (the code of zero current; often not a whole code)
  TIM1 counts -> duty   D = counts / P, P = f_timer / f_pwm (halved when centre-aligned:
                        the counter runs up and down)
  carrier period        tau = f_hall / f_pwm Hall ticks (one PWM period, up and down)
  end guard             G = ceil((t_dead + 4 us + t_sample) f_hall) Hall ticks: a
                        commutation ends at least G before its sector does (README,
                        "The commutation's end and the next edge"): the next edge
                        switches on the other switch of the leg the end switched off,
                        with no dead time of TIM1's between them, the end may lag its
                        match by up to 4 us more than the edge lags its own, and the
                        braking-current loop, which samples only outside commutations,
                        takes one sample in between: t_sample = 1/f_pwm (the end
                        restarts the carrier; its trigger comes within a period) + the
                        injected sequence, 3 + 4 (t_s + 12.5) cycles of the 12 MHz ADC
                        clock (RM0008 11.6; the port converts four injected channels)
  latest end            L(T) = T - ceil(T / 2^k) - G for a sector measured at T ticks:
                        beyond the guard, a margin of 2^-k of the sector, 2^-k the
                        smallest power of two not below hall.sector_shortening (at
                        most 16 halvings; none for 0 %): the next sector may be that
                        much shorter (a Hall sensor off its mark, the rotor speeding up)

and every limit is the exact set of codes whose physical value lies in the spec's range.
Nothing here is imported from the generator: tests compare these with values worked
out by hand for each example spec.
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction
from typing import Any

from codegen.spec_model import Spec

#: the drive's allowance for the commutation end's latency beyond the Hall edge's (README)
END_LATENCY_ALLOWANCE_S = Fraction(4, 1_000_000)
#: the ADC clock (72 MHz / 6), the injected trigger's latency and a conversion's cycles
#: beyond its sample time (DS5319 Table 46, RM0008 11.6), and the port's four injected
#: conversions (JL = 3): the current loop's sample, which the end's guard leaves room for
ADC_CLOCK_HZ = Fraction(12_000_000)
INJECTED_LATENCY_CYCLES = 3
CONVERSION_CYCLES = Fraction(25, 2)
INJECTED_CONVERSIONS = 4


def sample_room_s(spec: Spec) -> Fraction:
    """One current sample after a commutation's end: a PWM period and the sequence."""
    conversion = spec.sensing.adc_sample_cycles + CONVERSION_CYCLES
    sequence = INJECTED_LATENCY_CYCLES + INJECTED_CONVERSIONS * conversion
    return 1 / spec.inverter.pwm_frequency_hz + sequence / ADC_CLOCK_HZ


def _ceil(x: Fraction) -> int:
    return -((-x.numerator) // x.denominator)


def _floor(x: Fraction) -> int:
    return x.numerator // x.denominator


@dataclass(frozen=True)
class Units:
    pwm_counts: int  # P: TIM1 counts of one PWM period (duty 1)
    hall_hz: Fraction
    pole_pairs: int
    volts_per_code: Fraction
    amps_per_code: Fraction
    zero_current_code: Fraction  # C0
    adc_max: int  # the ADC's full-scale code
    hall_counter_max: int  # the Hall timer's largest count
    carrier_ticks: Fraction  # Hall ticks per PWM period: f_hall / f_pwm
    end_guard_ticks: int  # G: a commutation ends at least G before its sector does
    #: k of the latest end's margin ceil(T / 2^k) (None: hall.sector_shortening 0)
    end_margin_shift: int | None = None

    def latest_end(self, period: Any) -> Any:
        """L(T) = T - ceil(T / 2^k) - G: the latest a commutation may end in a sector
        measured at `period` Hall ticks (an int or an integer array)."""
        k = self.end_margin_shift
        if k is None:
            return period - self.end_guard_ticks
        return period - (-((-period) // 2**k)) - self.end_guard_ticks

    # ------------------------------------------------------------ conversions

    def rpm(self, ticks: int | Fraction) -> Fraction:
        return 60 * self.hall_hz / (6 * self.pole_pairs * Fraction(ticks))

    def ticks_at(self, rpm: Fraction) -> Fraction:
        """The exact (fractional) Hall interval at a speed."""
        return 60 * self.hall_hz / (6 * self.pole_pairs * rpm)

    def volts(self, code: int) -> Fraction:
        return code * self.volts_per_code

    def amps(self, code: int | Fraction) -> Fraction:
        return (code - self.zero_current_code) * self.amps_per_code

    def duty(self, counts: int | Fraction) -> Fraction:
        return Fraction(counts) / self.pwm_counts

    def bus_code(self, volts: Fraction) -> int:
        """The nearest bus code to a voltage."""
        return _floor(volts / self.volts_per_code + Fraction(1, 2))

    def current_code(self, amps: Fraction) -> int:
        """The nearest current code to a current."""
        return _floor(self.zero_current_code + amps / self.amps_per_code + Fraction(1, 2))


@dataclass(frozen=True)
class Limits:
    """The codes of the spec's ranges, decided exactly."""

    #: the shortest Hall interval the timer reads at a speed not above speed_max: it
    #: counts whole ticks, so a sector of T ticks reads floor(T) or ceil(T)
    period_min: int
    #: the longest Hall interval it reads at a speed not below speed_min (the counter's
    #: range at most)
    period_max: int
    bus_min: int
    bus_max: int
    current_low: int  # raw ADC codes of [I_min, I_max]
    current_high: int


def units(spec: Spec) -> Units:
    alignment = 2 if spec.inverter.pwm_alignment == "center" else 1
    p = spec.inverter.timer_clock_hz / (spec.inverter.pwm_frequency_hz * alignment)
    if p.denominator != 1:
        raise ValueError(f"the PWM period is not a whole number of timer counts: {p}")
    full = 2**spec.adc.bits
    return Units(
        pwm_counts=int(p),
        hall_hz=Fraction(spec.hall.timer_clock_hz),
        pole_pairs=spec.motor.poles // 2,
        volts_per_code=spec.adc.reference_v * spec.adc.bus_voltage_divider / full,
        amps_per_code=spec.adc.reference_v / (spec.adc.current_gain_v_per_a * full),
        zero_current_code=spec.adc.current_offset_v / spec.adc.reference_v * full,
        adc_max=full - 1,
        hall_counter_max=2**spec.hall.counter_bits - 1,
        carrier_ticks=Fraction(spec.hall.timer_clock_hz) / spec.inverter.pwm_frequency_hz,
        end_guard_ticks=_ceil(
            (spec.inverter.dead_time_s + END_LATENCY_ALLOWANCE_S + sample_room_s(spec))
            * Fraction(spec.hall.timer_clock_hz)
        ),
        end_margin_shift=_halvings(spec.hall.sector_shortening),
    )


#: the margin's finest fraction: 2^-16 of a sector
_MARGIN_HALVINGS_MAX = 16


def _halvings(shortening: Fraction) -> int | None:
    """k: the most halvings of a sector that stay at least `shortening` of it."""
    if shortening <= 0:
        return None
    k = 0
    while k < _MARGIN_HALVINGS_MAX and 2 * shortening * 2**k <= 1:
        k += 1
    return k


def limits(spec: Spec, u: Units) -> Limits:
    c = spec.controller
    inv = spec.inverter
    return Limits(
        period_min=_floor(u.ticks_at(c.speed_max_rpm)),
        period_max=min(_ceil(u.ticks_at(c.speed_min_rpm)), u.hall_counter_max),
        bus_min=_ceil(inv.bus_voltage_min_v / u.volts_per_code),
        bus_max=_floor(inv.bus_voltage_max_v / u.volts_per_code),
        current_low=max(_ceil(u.zero_current_code + c.braking_current_min_a / u.amps_per_code), 0),
        current_high=min(
            _floor(u.zero_current_code + c.braking_current_max_a / u.amps_per_code), u.adc_max
        ),
    )

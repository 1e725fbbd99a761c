"""The bus voltage's reciprocal: Cortex-M3 hardware divide or a lookup table.

The core needs, per bus code B, round(N_X / B) and round(N_G / B) (the speed and Eq. 20
numerators) and the exact segment boundary ceil(C / B). `bldc_bus_condition()` computes
them with five hardware divides. The alternative is a flash table over the spec's bus
range, interpolated linearly between entries every s codes. Its error for f(B) = N / B
is at most s^2 / 8 max|f''| = s^2 N / (4 B_min^3) numerator units, and it may only use
what the accuracy target leaves over the generator's proven bound:

* duties: a numerator error d moves X by at most d / (T_min 2^f) counts, so
  d <= (target - bound) T_min 2^f;
* t_com: the bound is already stated at the target where the design has no slack, and
  then the table must be exact: one entry per bus code.

The boundary C / B must be exact in every case (it is a decision, Eq. 18), so a table
needs it per code too. The table's flash is set against the divide's measured cycles
(the bldc_bus_condition() part of the timing handler's trace), and the one that meets
the 2 KiB budget at the accuracy target wins.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import sympy as sp

from codegen.core.module import Core
from codegen.spec_model import Spec

FLASH_BUDGET_BYTES = 2048
ENTRY_BYTES = 4  # one uint32 numerator


@dataclass(frozen=True)
class TableOption:
    codes: int  # bus codes in the spec's range
    step_x: int  # codes between entries of the speed numerator (1 = exact)
    step_g: int  # the same for the Eq. 20 numerator
    flash_bytes: int  # both numerator tables and the exact boundary table

    def describe(self) -> str:
        return (
            f"{self.codes} bus codes, entries every {self.step_x} (speed) and"
            f" {self.step_g} (Eq. 20) codes, plus the exact Eq. 18 boundary per code:"
            f" {self.flash_bytes} B of flash"
        )


def _step(numerator: int, b_min: int, budget: sp.Rational) -> int:
    """Largest interpolation step whose error stays within `budget` numerator units."""
    if budget <= 0:
        return 1
    step = math.isqrt(int(sp.floor(4 * budget * b_min**3 / numerator)))
    return max(step, 1)


def table_option(spec: Spec, core: Core) -> TableOption:
    """For a paper-method core: its bus reciprocals as interpolated tables instead."""
    sc = core.scaling
    formats, claims = core.design.formats, core.design.claims
    b_min, b_max = sc.bus_code_min, sc.bus_code_max
    codes = b_max - b_min + 1
    f = int(formats["x_frac_bits"])
    duty_slack = sp.Rational(str(spec.accuracy.duty_counts)) - sp.Rational(str(claims.duty_counts))
    time_slack = sp.Rational(str(spec.accuracy.commutation_time_ticks)) - sp.Rational(
        str(claims.time_ticks)
    )
    step_x = _step(int(formats["n_x"]), b_min, duty_slack * sc.period_min_ticks * 2**f)
    # A time error budget in ticks maps to the numerator through t = n i / W at the
    # largest current and the smallest W where the bound holds.
    w_ok = sp.Rational(str(formats["time_bound_min_w_counts"])) * 2**f
    step_g = _step(int(formats["n_g"]), b_min, time_slack * w_ok / max(sc.current_code_max, 1))
    entries = math.ceil(codes / step_x) + 1 + math.ceil(codes / step_g) + 1
    boundary = codes * 2  # ceil(C / B) as uint16 per code
    return TableOption(codes, step_x, step_g, entries * ENTRY_BYTES + boundary)


@dataclass(frozen=True)
class ReciprocalChoice:
    table: TableOption
    divide_instructions: int
    divide_cycles: int
    flash_in_use: int

    @property
    def choice(self) -> str:
        fits = self.flash_in_use + self.table.flash_bytes <= FLASH_BUDGET_BYTES
        return "table" if fits else "hardware divide"

    def lines(self) -> list[str]:
        return [
            f"bus reciprocal by hardware divide: {self.divide_instructions} instructions,"
            f" {self.divide_cycles} cycles worst (UDIV at 12), off the Hall edge",
            f"bus reciprocal by table at the accuracy target: {self.table.describe()};"
            f" core + port already take {self.flash_in_use} B of their {FLASH_BUDGET_BYTES} B"
            " budget (the arithmetic's, not the image's firmware.flash_budget)",
            f"bus reciprocal: {self.choice} chosen",
        ]

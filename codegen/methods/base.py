"""The interface every commutation method implements (one folder per method).

A method turns a validated spec into the two functions of the core that depend on it,
`bldc_bus_condition()` and `bldc_commutation_timing()`, as IR, with the formats it
chose, the proof that they are safe and the bounds it claims. Everything else (Hall
decoding, `bldc_commutate()`, printing, the manifest) is shared by all methods.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol

from codegen.core.conditioning import CoreLimits
from codegen.fixedpoint.scaling import Scaling
from codegen.ir.intervals import ProvenRange
from codegen.ir.nodes import Function, IConst, StructType, Table
from codegen.spec_model import Spec


class FixedPointError(ValueError):
    """The spec's ranges or accuracy targets make a safe fixed-point design impossible.

    `key` names the spec key a user would change (for the one-line error)."""

    def __init__(self, message: str, key: str = "accuracy") -> None:
        super().__init__(message)
        self.key = key


@dataclass(frozen=True)
class Claims:
    """What the design promises, stated in the manifest and the header. The verifier
    holds them against the spec's targets; it never takes its tolerance from here."""

    duty_counts: float  # |duty - exact| bound, counts
    time_ticks: float  # |t_com - exact| bound where the time is well conditioned, ticks
    #: where that time bound holds (human-readable condition)
    time_region: str


@dataclass(frozen=True)
class CoreDesign:
    method: str
    uses_main_duty: bool
    bus_struct: StructType
    bus_condition: Function
    commutation_timing: Function
    tables: tuple[Table, ...]
    #: header lines: the rule, formats and rounding, flags (printed as a comment block)
    doc: tuple[str, ...]
    #: named constants the header documents though no expression uses them
    extra_constants: tuple[IConst, ...]
    ranges: tuple[ProvenRange, ...]
    claims: Claims
    #: key -> value of the chosen formats (manifest and CLI)
    formats: dict[str, int | float | str]
    summary: str  # one line for the CLI


class Method(Protocol):
    name: str
    uses_main_duty: bool

    def design(self, spec: Spec, sc: Scaling, limits: CoreLimits) -> CoreDesign: ...

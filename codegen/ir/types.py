"""The C integer types of the IR, with their ranges.

Only fixed-width <stdint.h> types: the arithmetic is proven against these limits, and
SymPy's own type mappings (which map unsigned types to signed ones) are never used for
fixed point.
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class CType:
    name: str  # "uint32_t"
    bits: int
    signed: bool

    @property
    def low(self) -> int:
        return -(1 << (self.bits - 1)) if self.signed else 0

    @property
    def high(self) -> int:
        return (1 << (self.bits - 1)) - 1 if self.signed else (1 << self.bits) - 1

    @property
    def literal_suffix(self) -> str:
        """C literal suffix that gives a constant this type's signedness and width."""
        if self.bits == 64:
            return "ll" if self.signed else "ull"
        return "" if self.signed else "u"

    def fits(self, low: int, high: int) -> bool:
        return self.low <= low and high <= self.high

    def __str__(self) -> str:
        return self.name


U8 = CType("uint8_t", 8, False)
U16 = CType("uint16_t", 16, False)
U32 = CType("uint32_t", 32, False)
U64 = CType("uint64_t", 64, False)
I32 = CType("int32_t", 32, True)
I64 = CType("int64_t", 64, True)
#: A comparison's result: printed as a C int 0/1, never stored in a wider type.
BOOL = CType("bool", 1, False)

BY_NAME = {t.name: t for t in (U8, U16, U32, U64, I32, I64)}


def narrowest(low: int, high: int, signed: bool) -> CType:
    """The narrowest 32- or 64-bit type of the given signedness holding [low, high]."""
    for candidate in (I32, I64) if signed else (U32, U64):
        if candidate.fits(low, high):
            return candidate
    raise OverflowError(f"[{low}, {high}] fits no 64-bit type")

"""Which transistors each Hall edge modulates, from the paper's 60 deg example alone.

The anchor (section 3.2): at the forward edge into sector 1 (60 deg) conduction moves
from BA to CA; A is non-commutating with e_a = +E, its current returning through D1
(upper diode); B is turned off (T3), C turned on (T5 modulated). Hence the flat tops:
A +E over sectors 0-1, B -E over 5-0, C -E over 1-2; each flat lasts two sectors, the
opposite one follows three sectors later, and the phase ramps in between.

Braking: a conducting phase's current opposes its EMF. At an edge the phase flat in
both sectors is non-commutating, the one flat only before is turned off, the one flat
only after is turned on. If the non-commutating current is negative (EMF +E) it returns
through its upper diode and the upper transistors of the turn-on and turn-off phases
steer the commutation (the paper's case); if positive, the lower ones. Reverse
rotation negates every EMF and runs the sectors backwards.

Switch index 0..5 = T1..T6, T(2p+1) upper and T(2p+2) lower of phase p (A, B, C).
"""

from __future__ import annotations

#: EMF sign of phase A, B, C in sectors 0..5 during forward rotation (0: ramping)
FORWARD_EMF: tuple[tuple[int, int, int], ...] = (
    (+1, -1, 0),
    (+1, 0, -1),
    (0, +1, -1),
    (-1, +1, 0),
    (-1, 0, +1),
    (0, -1, +1),
)


def _signs(sector: int, reverse: bool) -> tuple[int, int, int]:
    a, b, c = FORWARD_EMF[sector]
    return (-a, -b, -c) if reverse else (a, b, c)


def modulated(sector_from: int, sector_to: int, reverse: bool) -> tuple[int, int]:
    """(switch at D_on, switch at D_off) of the edge from one sector to the next."""
    before, after = _signs(sector_from, reverse), _signs(sector_to, reverse)
    steady = next(p for p in range(3) if before[p] != 0 and after[p] != 0)
    turn_off = next(p for p in range(3) if before[p] != 0 and after[p] == 0)
    turn_on = next(p for p in range(3) if before[p] == 0 and after[p] != 0)
    upper = after[steady] > 0  # EMF +E: the braking current is negative, upper diode
    offset = 0 if upper else 1
    return 2 * turn_on + offset, 2 * turn_off + offset


def switches(sequence: tuple[int, ...]) -> dict[tuple[int, int], tuple[int, int]]:
    """(previous Hall code, Hall code) -> (on switch, off switch) for the 12 valid edges."""
    sector_of = {code: k for k, code in enumerate(sequence)}
    out = {}
    for previous, k0 in sector_of.items():
        for code, k1 in sector_of.items():
            if k1 == (k0 + 1) % 6:
                out[(previous, code)] = modulated(k0, k1, reverse=False)
            elif k0 == (k1 + 1) % 6:
                out[(previous, code)] = modulated(k0, k1, reverse=True)
    return out

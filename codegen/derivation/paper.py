"""The paper's chain of results, derived step by step from Eq. 1.

Each step is a `DerivedResult` carrying the paper's printed equation label. R stays
symbolic in the slopes (Eqs. 4 and 13) and is set to zero exactly where the paper
does ("ignoring the stator resistance", Eqs. 5, 14, 17 and everything after them).

The 60 deg commutation of section 3.2 is the paper's worked example: phase A is
non-commutating (current -I, returning through D1), B is turned off and C turned on.
Its terminal voltages are not typed in here: they come from the switching table
(`codegen.derivation.switching`), which derives them from Table 1 and the anchor.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass
from functools import lru_cache

import sympy as sp

from codegen.derivation import symbols as s
from codegen.derivation.circuit import integrate_constant_slopes, solve_slopes
from codegen.derivation.intervals import interval_where, must_hold
from codegen.derivation.switching import SwitchingTable, derive_switching_table
from codegen.errors import DerivationError

Row = tuple[str, sp.Basic]


@dataclass(frozen=True)
class DerivedResult:
    """One derived equation of the paper.

    key: the printed label ("4", "18"), with "1b"/"3b" for the labels the paper prints
    twice (see the audit). rows: named parts, e.g. ("a", slope of i_a).
    """

    key: str
    name: str
    title: str
    rows: tuple[Row, ...]
    method: str
    neglects_resistance: bool
    #: Why a row is what it is where that is not obvious (e.g. an excluded end point).
    row_notes: tuple[tuple[str, str], ...] = ()

    def note(self, name: str) -> str:
        return dict(self.row_notes).get(name, "")

    def row(self, name: str = "") -> sp.Basic:
        for row_name, value in self.rows:
            if row_name == name:
                return value
        raise KeyError(f"Eq. {self.key} has no row {name!r}")

    @property
    def row_names(self) -> tuple[str, ...]:
        return tuple(name for name, _ in self.rows)


@dataclass(frozen=True)
class Derivation:
    results: tuple[DerivedResult, ...]
    switching: SwitchingTable

    def __getitem__(self, key: str) -> DerivedResult:
        for result in self.results:
            if result.key == key:
                return result
        raise KeyError(f"no derived result for Eq. {key}")

    def __iter__(self) -> Iterator[DerivedResult]:
        return iter(self.results)

    def by_name(self, name: str) -> DerivedResult:
        for result in self.results:
            if result.name == name:
                return result
        raise KeyError(name)


def _rows(names: str, values: tuple[sp.Basic, ...]) -> tuple[Row, ...]:
    return tuple(zip(names.split(), values, strict=True))


def _no_r(expr: sp.Basic) -> sp.Basic:
    return sp.cancel(expr.subs(s.R, 0))


def _solve_one(equation: sp.Basic, unknown: sp.Symbol, what: str) -> sp.Expr:
    solutions = sp.solve(equation, unknown, dict=False)
    if len(solutions) != 1:
        raise DerivationError(f"{what}: expected one solution for {unknown}, got {solutions}")
    return sp.simplify(solutions[0])


@lru_cache(maxsize=1)
def derive() -> Derivation:
    """Run the whole derivation once per process; all outputs reuse this object."""
    table = derive_switching_table()
    edge = table.paper_example()  # 60 deg edge, forward: BA -> CA
    results: list[DerivedResult] = []

    # --- Section 3.2: commutation without suppression (turn-off switch held off) ---
    u_none = edge.terminal_voltages(d_on=s.D_on, d_off=sp.S.Zero)
    emfs = edge.back_emfs()
    results.append(
        DerivedResult(
            "3b",
            "terminal_voltages_no_suppression",
            "Terminal voltages during commutation, turn-off switch off",
            _rows("a b c", u_none),
            "switching table at the 60 deg edge, PWM-averaged, D_off = 0",
            False,
        )
    )
    slopes_none = solve_slopes(u_none, emfs)
    results.append(
        DerivedResult(
            "4",
            "current_slopes_no_suppression",
            "Phase current slopes, D_off = 0",
            _rows("a b c", slopes_none),
            "Eq. 1 with i_a + i_b + i_c = 0 eliminating u_n, R kept",
            False,
        )
    )
    initial = edge.initial_currents()
    currents_none = integrate_constant_slopes([_no_r(x) for x in slopes_none], initial)
    results.append(
        DerivedResult(
            "5",
            "currents_no_suppression",
            "Phase currents during commutation, D_off = 0",
            _rows("a b c", tuple(sp.expand(c) for c in currents_none)),
            "Eq. 4 with R = 0 integrated from i_a = -I, i_b = I, i_c = 0",
            True,
        )
    )
    # Eq. 2 (printed as a second "(1)"): P_e = T_e omega_m = sum e_x i_x.
    torque = sp.expand(sum(e * i for e, i in zip(emfs, currents_none, strict=True)) / s.omega_m)
    results.append(
        DerivedResult(
            "6",
            "torque_no_suppression",
            "Electromagnetic torque during commutation",
            (("", torque),),
            "T_e = sum(e_x i_x) / omega_m with the currents of Eq. 5",
            True,
        )
    )
    ripple = sp.expand(torque - torque.subs(s.t, 0))
    results.append(
        DerivedResult(
            "7",
            "torque_ripple_no_suppression",
            "Commutation torque ripple",
            (("", ripple),),
            "T_e(t) - T_e(0)",
            True,
        )
    )
    ripple_rate = sp.factor(sp.diff(ripple, s.t))
    # The ripple is linear in t, so it vanishes for all t iff its slope does.
    numerator = sp.expand(ripple_rate * 3 * s.L * s.omega_m)
    results.append(
        DerivedResult(
            "8",
            "ripple_free_condition",
            "Ripple-free condition",
            (("", ripple), ("condition", numerator)),
            "Delta T_e = 0 for all t: the t coefficient times 3 L omega_m must vanish",
            True,
        )
    )
    d_on_free = _solve_one(numerator, s.D_on, "Eq. 9")
    results.append(
        DerivedResult(
            "9",
            "ripple_free_on_duty",
            "Ripple-free turn-on duty, D_off = 0",
            (("", d_on_free),),
            "Eq. 8 solved for D_on",
            True,
        )
    )
    emf_range = interval_where(d_on_free, sp.S.Zero, sp.S.One, s.E)
    results.append(
        DerivedResult(
            "10",
            "ripple_free_emf_range",
            "Back-EMF range where Eq. 9 is a duty",
            (("", d_on_free), ("set", emf_range)),
            "0 <= D_on <= 1 solved for E > 0",
            True,
        )
    )
    d_on_free_n = d_on_free.subs(s.E, s.k_e * s.n)
    speed_range = interval_where(d_on_free_n, sp.S.Zero, sp.S.One, s.n)
    results.append(
        DerivedResult(
            "11",
            "ripple_free_speed_range",
            "Speed range where Eq. 9 is a duty",
            (("", d_on_free_n), ("set", speed_range)),
            "Eq. 10 with E = k_e n (Eq. 3)",
            True,
        )
    )

    # --- Section 4.2: overlapping commutation, both outgoing and incoming modulated ---
    u_overlap = edge.terminal_voltages(d_on=s.D_on, d_off=s.D_off)
    results.append(
        DerivedResult(
            "12",
            "terminal_voltages_overlap",
            "Terminal voltages, overlapping commutation",
            _rows("a b c", u_overlap),
            "switching table at the 60 deg edge, PWM-averaged",
            False,
        )
    )
    slopes = solve_slopes(u_overlap, emfs)
    results.append(
        DerivedResult(
            "13",
            "current_slopes_overlap",
            "Phase current slopes, overlapping commutation",
            _rows("a b c", slopes),
            "Eq. 1 with i_a + i_b + i_c = 0 eliminating u_n, R kept",
            False,
        )
    )
    slopes_no_r = tuple(_no_r(x) for x in slopes)
    currents = integrate_constant_slopes(slopes_no_r, initial)
    results.append(
        DerivedResult(
            "14",
            "currents_overlap",
            "Phase currents, overlapping commutation",
            _rows("a b c", tuple(sp.expand(c) for c in currents)),
            "Eq. 13 with R = 0 integrated from i_a = -I, i_b = I, i_c = 0",
            True,
        )
    )
    duty_sum = _solve_one(slopes_no_r[0], s.D_off, "Eq. 15") + s.D_on
    results.append(
        DerivedResult(
            "15",
            "duty_sum_overlap",
            "Duty sum that holds the non-commutating current",
            (("", sp.Eq(s.D_on + s.D_off, sp.simplify(duty_sum))),),
            "d i_a/dt of Eq. 14 set to zero",
            True,
        )
    )
    d_off_conventional = _solve_one(slopes_no_r[0], s.D_off, "Eq. 16")
    feasible = interval_where(d_off_conventional, sp.S.Zero, sp.S.One, s.D_on)
    results.append(
        DerivedResult(
            "16",
            "off_duty_conventional",
            "Turn-off duty of conventional overlapping",
            (("", d_off_conventional), ("feasible_on_duty", feasible)),
            "Eq. 15 solved for D_off; 0 <= D_off <= 1 bounds D_on (outside: control fail area)",
            True,
        )
    )

    # --- Section 4.3: improved, speed-segmented duty distribution ---
    extreme = {s.D_on: 1, s.D_off: 0}
    slope_off_max = sp.simplify(slopes_no_r[1].subs(extreme))
    slope_on_max = sp.simplify(slopes_no_r[2].subs(extreme))
    results.append(
        DerivedResult(
            "17",
            "extreme_slopes",
            "Fastest turn-off and turn-on slopes (D_on = 1, D_off = 0)",
            _rows("b c", (slope_off_max, slope_on_max)),
            "Eq. 13 rows b and c, R = 0",
            True,
        )
    )
    boundary_emf = _solve_one(sp.Eq(-slope_off_max, slope_on_max), s.E, "Eq. 18 boundary")
    upper_emf = emf_range.end
    low_region = sp.Interval(0, boundary_emf, left_open=True)
    high_region = sp.Interval(boundary_emf, upper_emf, left_open=True)
    # Where the turn-off phase is the faster one, hold the turn-on phase fully on and
    # slow the turn-off phase down; elsewhere hold the turn-off phase off and slow the
    # turn-on phase. Prove which region is which instead of assuming it.
    must_hold(-slope_off_max >= slope_on_max, s.E, low_region, "turn-off faster at low speed")
    must_hold(-slope_off_max <= slope_on_max, s.E, high_region, "turn-on faster at high speed")
    d_off_low = _solve_one(slopes_no_r[0].subs(s.D_on, 1), s.D_off, "Eq. 18 low")
    d_on_high = _solve_one(slopes_no_r[0].subs(s.D_off, 0), s.D_on, "Eq. 18 high")
    for bound in (d_off_low >= 0, d_off_low <= 1):
        must_hold(bound, s.E, low_region, "Eq. 18 low-speed D_off is a duty")
    for bound in (d_on_high >= 0, d_on_high <= 1):
        must_hold(bound, s.E, high_region, "Eq. 18 high-speed D_on is a duty")
    boundary_speed = sp.simplify(boundary_emf / s.k_e)
    upper_speed = sp.simplify(upper_emf / s.k_e)
    results.append(
        DerivedResult(
            "18",
            "improved_duty_rule",
            "Improved (segmented) duty distribution",
            (
                ("on_high", d_on_high),
                ("off_high", sp.S.Zero),
                ("on_low", sp.S.One),
                ("off_low", d_off_low),
                ("boundary_speed", boundary_speed),
                ("upper_speed", upper_speed),
                ("high_region", sp.Interval.Lopen(boundary_speed, upper_speed)),
                ("low_region", sp.Interval.Lopen(0, boundary_speed)),
            ),
            "compare |Eq. 17 b| with |Eq. 17 c|; saturate the slower phase's partner at its "
            "extreme and solve Eq. 15 for the other",
            True,
            (
                (
                    "low_region",
                    "n = 0 is excluded: there E = 0, D_off = 1 holds the turn-off current"
                    " and the low-speed commutation time I L/(2E) (Eq. 20) is unbounded; Table 2"
                    " also writes 0 < n",
                ),
            ),
        )
    )
    i_off = currents[1]
    results.append(
        DerivedResult(
            "19",
            "turn_off_current",
            "Turn-off phase current reaching zero",
            (("", i_off),),
            "Eq. 14 row b",
            True,
        )
    )
    t_com = _solve_one(i_off, s.t, "Eq. 20")
    t_low = sp.simplify(t_com.subs({s.D_on: 1, s.D_off: d_off_low}))
    t_high = sp.simplify(t_com.subs({s.D_on: d_on_high, s.D_off: 0}))
    t_conventional = sp.simplify(
        t_com.subs({s.D_on: s.D, s.D_off: d_off_conventional.subs(s.D_on, s.D)})
    )
    t_none = sp.simplify(t_com.subs({s.D_on: s.D, s.D_off: 0}))
    results.append(
        DerivedResult(
            "20",
            "commutation_time",
            "Commutation time",
            (
                ("", t_com),
                ("improved_low", t_low),
                ("improved_high", t_high),
                ("conventional", t_conventional),
                ("none", t_none),
            ),
            "Eq. 19 solved for t; then each method's duties substituted",
            True,
        )
    )
    return Derivation(results=tuple(results), switching=table)

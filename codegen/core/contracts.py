"""What the public API promises, as ACSL contracts printed above each prototype.

The promises are the ABI's, the same for every method:

* every compare value lies in [0, BLDC_PWM_PERIOD_COUNTS];
* an invalid Hall code or pair (000, 111, a code above 7, a jump that is not one sector
  of the spec's Hall sequence) switches nothing and raises BLDC_FLAG_INVALID_HALL;
* the commutation time is at most the Hall period it was computed for;
* over-speed and over-voltage switch nothing;
* a function writes only its output struct (`assigns`).

Their yardsticks come from the spec and the ABI, never from the tables they judge: the
valid Hall pairs are spelled from `hall.sequence`, not read from the generated edge
table. The one predicate taken from the code is `bldc_bus_conditioned`, the precondition
of `bldc_commutation_timing()` ("its bus argument comes from bldc_bus_condition()"):
it restates the IR of bldc_bus_condition() over mathematical integers, which is what a
precondition is for. `make prove` proves each contract with WP or checks it with EVA
over every input, and says which (verify/prove.py).
"""

from __future__ import annotations

from dataclasses import dataclass

from codegen.dead_time import sector_margin_shift
from codegen.ir.acsl import Behavior, Clause, Contract, Predicate, term
from codegen.ir.intervals import ProvenRange
from codegen.ir.nodes import Expr, Function, IConst, IVar, SAssign, SLet, SReturn, SStruct, SVar
from codegen.ir.walk import all_statements, expressions
from codegen.spec_model import Spec

VALID_PAIR = "bldc_valid_hall_pair"
CONDITIONED = "bldc_bus_conditioned"

#: contract clauses every method's core must meet, by function (name: what it says)
NO_SWITCH = "{o}turn_on_switch == BLDC_NO_SWITCH && {o}turn_off_switch == BLDC_NO_SWITCH"
COMPARE_FIELDS = ("turn_on_compare", "turn_off_compare")
IN_PERIOD = (
    ("turn_on_compare_in_period", "{o}turn_on_compare <= BLDC_PWM_PERIOD_COUNTS"),
    ("turn_off_compare_in_period", "{o}turn_off_compare <= BLDC_PWM_PERIOD_COUNTS"),
)


@dataclass(frozen=True)
class ApiContracts:
    predicates: tuple[Predicate, ...]
    #: by C name: every public function and every static helper
    functions: dict[str, Contract]


def valid_hall_pair(sequence: tuple[int, ...]) -> Predicate:
    """The 12 Hall code pairs one sector apart in the spec's sequence, either direction."""
    n = len(sequence)
    pairs = [(sequence[k], sequence[(k + 1) % n]) for k in range(n)]
    pairs += [(b, a) for a, b in pairs]
    return Predicate(
        VALID_PAIR,
        (("integer", "previous"), ("integer", "code")),
        tuple(f"(previous == {a} && code == {b})" for a, b in pairs),
        "||",
        "a Hall edge of the spec's sequence (hall.sequence), forward or reverse",
    )


def bus_conditioned(fn: Function, ranges: tuple[ProvenRange, ...]) -> Predicate:
    """What bldc_bus_condition() returns, field by field, from its IR: each field is a
    function of the saturated code (over its proven range), or one of the constants its
    variable is ever given."""
    mutable = {s.name: s for s in all_statements(fn.body) if isinstance(s, SVar)}
    given: dict[str, list[Expr]] = {name: [s.init] for name, s in mutable.items()}
    for s in all_statements(fn.body):
        if isinstance(s, SAssign) and s.name in given:
            given[s.name].append(s.expr)
    returned = next(s for s in all_statements(fn.body) if isinstance(s, SReturn))
    assert isinstance(returned.value, IVar)
    built = next(
        s
        for s in all_statements(fn.body)
        if isinstance(s, SStruct) and s.name == returned.value.name
    )
    key = [
        (field, value.name)
        for field, value in built.values
        if isinstance(value, IVar)
        and value.name in given
        and not all(isinstance(v, IConst) for v in given[value.name])
    ]
    if len(key) != 1:
        raise ValueError(f"{fn.c_name}: expected one field holding the saturated input")
    key_field, key_var = key[0]
    proven = {r.name: r for r in ranges if r.function == fn.c_name}
    span = proven[f"{built.name}.{key_field}"]
    named = {v.value: v.name for v in given[key_var] if isinstance(v, IConst) and v.name}

    def bound(value: int) -> str:
        return named.get(value) or str(value)

    body = [f"{bound(span.low)} <= b.{key_field} <= {bound(span.high)}"]
    names = {key_var: f"b.{key_field}"}
    # a local computed from the saturated input alone (a reciprocal shared by fields)
    # is restated in place wherever a field uses it
    for s in all_statements(fn.body):
        if isinstance(s, SLet) and all(
            e.name in names for e in expressions(s.expr) if isinstance(e, IVar)
        ):
            names[s.name] = term(s.expr, names)
    for field, value in built.values:
        if field == key_field:
            continue
        if isinstance(value, IVar) and value.name in given:
            choices = []
            for v in given[value.name]:
                assert isinstance(v, IConst), f"{fn.c_name}: {value.name} takes a computed value"
                text = f"b.{field} == {v.name or v.value}"
                if text not in choices:
                    choices.append(text)
            body.append("(" + " || ".join(choices) + ")")
            continue
        for e in expressions(value):
            if isinstance(e, IVar) and e.name not in names:
                raise ValueError(f"{fn.c_name}: field {field} depends on {e.name}")
        body.append(f"b.{field} == {term(value, names)}")
    return Predicate(
        CONDITIONED,
        ((built.struct.c_name, "b"),),
        tuple(body),
        "&&",
        "a bus state bldc_bus_condition() returns: its precondition for "
        "bldc_commutation_timing(), restated from its IR over mathematical integers",
    )


def _ensures(name: str, text: str) -> Clause:
    return Clause("ensures", name, text)


def bus_condition_contract() -> Contract:
    return Contract(
        ensures=(
            _ensures("conditioned", f"{CONDITIONED}(\\result)"),
            _ensures(
                "over_voltage_never_applies",
                "bus_code > BLDC_BUS_CODE_MAX ==> \\result.period_min == BLDC_PERIOD_NEVER",
            ),
        ),
    )


#: the Hall period `bldc_commutate` was given
OLD_PERIOD = "\\old(inputs->hall_period_ticks)"


def _latest_end(period: str, shift: int | None) -> str:
    """The latest end in ACSL: the sector less the margin (`hall.sector_shortening`,
    T (2^k - 1) / 2^k in integers), the guard being on the other side."""
    if shift is None:
        return period
    return f"{period} * {2**shift - 1} / {2**shift}"


def timing_contract(shift: int | None = None) -> Contract:
    r = "\\result."
    return Contract(
        requires=(
            Clause("requires", "readable", "\\valid_read(bus)"),
            Clause("requires", "conditioned", f"{CONDITIONED}(*bus)"),
        ),
        ensures=(
            *(_ensures(name, text.format(o=r)) for name, text in IN_PERIOD),
            _ensures(
                "commutation_ends_the_guard_early",
                f"{r}commutation_ticks == 0"
                f" || {r}commutation_ticks + BLDC_COMMUTATION_GUARD_TICKS"
                f" <= {_latest_end('period_ticks', shift)}",
            ),
            _ensures("applies_at_most_from_bus_minimum", f"{r}period_min >= bus->period_min"),
        ),
    )


def edge_of_contract() -> Contract:
    pair = f"{VALID_PAIR}(previous_hall_code, hall_code)"
    return Contract(
        behaviors=(
            Behavior(
                "invalid_pair",
                f"!{pair}",
                (_ensures("no_edge", "\\result == BLDC_EDGE_NONE"),),
            ),
            Behavior("valid_pair", pair, (_ensures("an_edge", "\\result < BLDC_EDGE_COUNT"),)),
        ),
        partition=True,
    )


def commutate_contract(shift: int | None = None) -> Contract:
    o = "out->"
    pair = f"{VALID_PAIR}(inputs->previous_hall_code, inputs->hall_code)"
    over = (
        "\\old(inputs->hall_period_ticks) < BLDC_PERIOD_MIN_TICKS"
        " || \\old(inputs->bus_voltage_adc) > BLDC_BUS_CODE_MAX"
    )
    return Contract(
        requires=(
            Clause("requires", "readable", "\\valid_read(inputs)"),
            Clause("requires", "writable", "\\valid(out)"),
            Clause("requires", "separated", "\\separated(inputs, out)"),
        ),
        assigns=("*out",),
        ensures=(
            *(_ensures(name, text.format(o=o)) for name, text in IN_PERIOD),
            _ensures(
                "commutation_ends_the_guard_early",
                f"{o}commutation_ticks == 0 || {o}commutation_ticks + BLDC_COMMUTATION_GUARD_TICKS"
                f" <= {_latest_end(OLD_PERIOD, shift)}",
            ),
            _ensures("over_speed_or_voltage_no_switch", f"{over} ==> {NO_SWITCH.format(o=o)}"),
        ),
        behaviors=(
            Behavior(
                "invalid_hall",
                f"!{pair}",
                (
                    _ensures("no_switch", NO_SWITCH.format(o=o)),
                    _ensures("invalid_flag", f"({o}flags & BLDC_FLAG_INVALID_HALL) != 0"),
                ),
            ),
        ),
    )


#: the public functions, each with its contract (`api_contracts`)
PUBLIC = ("bldc_bus_condition", "bldc_commutation_timing", "bldc_edge_of", "bldc_commutate")


def helper_contract(fn: Function) -> Contract:
    """A static helper reads its pointers and writes nothing (the IR has no stores
    through a helper's parameters)."""
    return Contract(
        requires=tuple(
            Clause("requires", f"readable_{p.name}", f"\\valid_read({p.name})")
            for p in fn.params
            if p.is_pointer
        ),
    )


def api_contracts(
    spec: Spec, functions: list[Function], bus_condition: Function, ranges: tuple[ProvenRange, ...]
) -> ApiContracts:
    shift = sector_margin_shift(spec.hall.sector_shortening)
    public = {
        "bldc_bus_condition": bus_condition_contract(),
        "bldc_commutation_timing": timing_contract(shift),
        "bldc_edge_of": edge_of_contract(),
        "bldc_commutate": commutate_contract(shift),
    }
    assert tuple(public) == PUBLIC
    contracts: dict[str, Contract] = {}
    for fn in functions:
        if fn.c_name in public:
            contracts[fn.c_name] = public[fn.c_name]
        elif fn.static and not fn.inline:
            if any(p.is_pointer and not p.const for p in fn.params):
                raise ValueError(f"{fn.c_name}: a helper that writes through a pointer")
            contracts[fn.c_name] = helper_contract(fn)
        else:
            raise ValueError(f"{fn.c_name}: a public function without a contract")
    return ApiContracts(
        (valid_hall_pair(spec.hall.sequence), bus_conditioned(bus_condition, ranges)),
        contracts,
    )

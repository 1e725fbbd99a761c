"""The EVA harness of one core: every public function over every value of its inputs.

Frama-C's EVA is an abstract interpreter: from an entry point it computes, for every
statement, a superset of the values the program can hold, and raises an alarm wherever
a run-time error (overflow, division by zero, invalid shift, out-of-bounds access,
lossy conversion) is not ruled out. The harness's entry points give each parameter every
value of its C type (`Frama_C_*_interval`), so nothing is assumed away; only how that
input space is partitioned is chosen, and a partition never changes what is covered.

The partitioning comes from the design, not from the spec by hand:

* The bus code. Every field of the bus state is a function of one saturated code, but
  EVA, like the IR's own proof, keeps one interval per variable: it cannot see that a
  large `x_numerator` goes with a small `high_speed_period`. When the IR's proof leaves a
  compare value's proven range above the PWM period (the contract is then relational:
  the "improved" rule's D_on = 2P - X at high speed, where X > P exactly when the period
  is below the bus code's boundary), the harness gives EVA one partition per code of the
  saturation range (plus one below and one above it), and splits the period at each bus
  field the timing compares it with and keeps the outcome of (the high-speed flag):
  within a partition those fields are single values, and the decision carries over to
  the arithmetic. A guard that returns (over-speed) needs no split: EVA narrows the
  period on each side of it by itself. When the proven ranges already meet
  the contract, one partition is enough. `bldc_bus_condition()` is always analysed code
  by code (it is cheap), so that EVA checks its exact postcondition for every code.
* `bldc_commutate()` is analysed over every input at once: EVA rules out run-time
  errors there, and WP carries its callees' contracts to its own.
* A parameter that indexes a table through a small guard (the Hall codes of
  `bldc_edge_of`, guarded by `<= 7`): one partition per value of the guarded domain,
  one for the rest, so every entry is checked against the contract on its own.
* Inside the core, the IR's own case splits and loop invariants are printed as ACSL
  hints (`codegen/ir/acsl.py`).

`__builtin_clz` gets a definition for the analysis (Frama-C's declaration only bounds
its result to [0, 31]); it computes what the Cortex-M3's CLZ does for a non-zero
argument and requires a non-zero argument, so EVA also proves it is never given 0.
"""

from __future__ import annotations

import json
from dataclasses import dataclass, replace

from codegen.control import current_loop
from codegen.core.contracts import COMPARE_FIELDS
from codegen.core.module import Core
from codegen.ir.c_printer import literal
from codegen.ir.nodes import (
    Expr,
    Function,
    IBitLength,
    ICall,
    ICmp,
    IConst,
    IField,
    ILongDiv,
    IStep,
    IVar,
    SAssign,
    SIf,
    SLet,
    SReturn,
    SVar,
)
from codegen.ir.types import I32, U8, U16, U32, CType
from codegen.ir.walk import all_exprs, all_statements, called_functions, expressions
from codegen.render import project_relative, provenance, regenerate_hint, render

#: the ACSL anchor for a hint between declarations (see codegen/ir/acsl.py)
ANCHOR = "/*@ ghost ; */"
#: an enumerated guard domain is at most this wide (Hall codes: 8)
SMALL_DOMAIN = 64
INTERVAL = {
    U8: "Frama_C_unsigned_char_interval",
    U16: "Frama_C_unsigned_short_interval",
    U32: "Frama_C_unsigned_int_interval",
}
#: signed types: every value from the most negative to the most positive
SIGNED_INTERVAL = {I32: "Frama_C_int_interval"}


@dataclass(frozen=True)
class Analysis:
    """One EVA run: `main` drives `function` over every input."""

    function: str
    main: str
    partitions: str  # how the input space is partitioned, in words
    split_limit: int  # the largest partition count EVA must keep apart
    #: functions whose per-statement values this run need not keep: the entry point,
    #: and callees whose own analysis covers the same inputs the same way
    no_results: tuple[str, ...] = ()
    #: one analysis per bus code: no two calls share a context, so EVA's cache of the
    #: calls it analysed (memexec) only costs its look-ups and copies (a tenth of the
    #: run); without it each call is analysed as it would be anyway, the same results
    per_code: bool = False


@dataclass(frozen=True)
class ProofPlan:
    analyses: tuple[Analysis, ...]
    per_code: bool
    reason: str
    harness_functions: tuple[str, ...]  # printed C
    clz_model: str  # printed C, "" when the core has no CLZ


# ------------------------------------------------------------------ IR facts


def _definitions(fn: Function) -> dict[str, list[Expr]]:
    out: dict[str, list[Expr]] = {}
    for s in all_statements(fn.body):
        if isinstance(s, SLet):
            out.setdefault(s.name, []).append(s.expr)
        elif isinstance(s, SVar):
            out.setdefault(s.name, []).append(s.init)
        elif isinstance(s, SAssign):
            out.setdefault(s.name, []).append(s.expr)
    return out


def _sources(fn: Function, e: Expr, seen: frozenset[str] = frozenset()) -> set[str]:
    """The scalar parameters e depends on, through the function's locals."""
    params = {p.name for p in fn.params if p.struct is None}
    defs = _definitions(fn)
    out: set[str] = set()
    for node in expressions(e):
        if isinstance(node, IVar) and node.name not in seen:
            if node.name in params:
                out.add(node.name)
            for d in defs.get(node.name, []):
                out |= _sources(fn, d, seen | {node.name})
    return out


def bus_code_bounds(bus_condition: Function) -> tuple[IConst, IConst]:
    """The saturation range of the bus code: the constants its IR saturates it to."""
    code = bus_condition.params[0].name
    saturated = {
        s.name
        for s in all_statements(bus_condition.body)
        if isinstance(s, SVar) and isinstance(s.init, IVar) and s.init.name == code
    }
    consts = {
        s.expr.value: s.expr
        for s in all_statements(bus_condition.body)
        if isinstance(s, SAssign) and s.name in saturated and isinstance(s.expr, IConst)
    }
    if len(consts) != 2:
        raise ValueError(f"{bus_condition.c_name}: expected a saturation range, got {consts}")
    low, high = sorted(consts)
    return consts[low], consts[high]


def early_exits(fn: Function) -> set[int]:
    """The comparisons (by identity) that are the whole condition of a branch ending in
    a return: EVA narrows the state on each side of such a guard by itself, and the
    rest of the function runs on the narrowed side only."""
    return {
        id(s.cond)
        for s in all_statements(fn.body)
        if isinstance(s, SIf) and isinstance(s.cond, ICmp) and s.then
        if isinstance(s.then[-1], SReturn)
    }


def bus_decisions(timing: Function) -> list[tuple[str, str]]:
    """(scalar parameter, bus field) pairs the timing compares and whose outcome it
    keeps (a flag, a select) past the join of the two sides: its exact decisions between
    an input and a value of the bus state that EVA must keep apart. A guard that returns
    (over-speed: the safe state) is not one: splitting on it too cost a third more
    partitions (3393 calls of the timing in place of 2262, 2 s of 13 on the paper
    motor) and kept nothing apart the function's own branch does not."""
    bus = next(p.name for p in timing.params if p.struct is not None)
    guards = early_exits(timing)
    out: list[tuple[str, str]] = []
    for e in all_exprs(timing.body):
        if not isinstance(e, ICmp) or id(e) in guards:
            continue
        for mine, other in ((e.a, e.b), (e.b, e.a)):
            if isinstance(other, IField) and other.base == bus:
                sources = _sources(timing, mine)
                if len(sources) == 1:
                    pair = (sources.pop(), other.field)
                    if pair not in out:
                        out.append(pair)
    return out


def guarded_domains(fn: Function) -> dict[str, int]:
    """Scalar parameters compared directly with a small constant: the largest value of
    the guarded domain [0, v] (the rest of the type is one more partition)."""
    params = {p.name for p in fn.params if p.struct is None}
    out: dict[str, int] = {}
    for e in all_exprs(fn.body):
        if (
            isinstance(e, ICmp)
            and isinstance(e.a, IVar)
            and isinstance(e.b, IConst)
            and e.a.name in params
            and e.b.value < SMALL_DOMAIN
        ):
            top = e.b.value if e.op in (">", "<=") else e.b.value - 1
            out[e.a.name] = max(out.get(e.a.name, 0), top)
    return out


def callees(fn: Function) -> list[str]:
    """The functions `fn` calls (the long division included), by C name."""
    from codegen.ir.longdiv import DIVIDE_LONG

    out: list[str] = []
    for e in all_exprs(fn.body):
        if isinstance(e, ICall):
            name = e.function.c_name
        elif isinstance(e, ILongDiv):
            name = DIVIDE_LONG.c_name
        else:
            continue
        if name not in out:
            out.append(name)
    return out


def relational_outputs(core: Core) -> list[str]:
    """Compare values whose interval-proven range exceeds the PWM period: the contract
    then needs one partition per bus code (see the module's docstring)."""
    timing = core.design.commutation_timing.c_name
    period = core.limits.period_counts.value
    return [
        f"{r.name} in [{r.low}, {r.high}]"
        for r in core.ranges
        if r.function == timing and r.name.split(".")[-1] in COMPARE_FIELDS and r.high > period
    ]


# ------------------------------------------------------------------ printing


def _any(ctype: CType) -> str:
    if ctype in SIGNED_INTERVAL:
        return f"{SIGNED_INTERVAL[ctype]}({ctype.low + 1} - 1, {ctype.high})"
    return f"{INTERVAL[ctype]}(0u, {literal(ctype.high, U32)})"


def _loop_harness(fn: Function) -> str:
    """A function of the current loop (codegen/control/current_loop.py) over every
    value of every parameter at once: its IR is proven over the same domain."""
    body = []
    for p in fn.params:
        assert p.ctype is not None
        body.append(f"    {p.ctype.name} {p.name} = {_any(p.ctype)};")
    assert fn.returns is not None and not hasattr(fn.returns, "fields")
    ret = fn.returns.name  # type: ignore[union-attr]
    args = ", ".join(p.name for p in fn.params)
    body += [f"    const {ret} result = {fn.c_name}({args});", "    (void)result;"]
    return _harness(f"prove_{fn.c_name}", f"{fn.c_name}() for every value of its arguments", body)


def _partition_codes(name: str, low: IConst, high: IConst, per_code: bool) -> list[str]:
    if not per_code:
        return []
    return [
        f"    /* one partition below {low.name}, one above {high.name}, one per code between */",
        f"    //@ split {name} < {low.name};",
        f"    //@ split {name} > {high.name};",
        f"    if ({name} >= {low.name}) {{",
        f"        if ({name} <= {high.name}) {{",
        f"            /*@ split {name}; */ {ANCHOR}",
        "        }",
        "    }",
    ]


def _decision_splits(period: str, bus: str, fields: list[str]) -> list[str]:
    return [f"    //@ split {period} < {bus}.{f};" for f in fields]


def _harness(name: str, doc: str, body: list[str]) -> str:
    return "\n".join([f"/* {doc} */", f"void {name}(void)", "{", *body, "}"])


def _bus_condition_harness(core: Core, low: IConst, high: IConst) -> str:
    fn = core.design.bus_condition
    code = fn.params[0].name
    body = [
        f"    uint32_t {code} = {_any(U32)};",
        *_partition_codes(code, low, high, per_code=True),
        f"    const {core.design.bus_struct.c_name} bus = {fn.c_name}({code});",
        "    (void)bus;",
    ]
    return _harness(
        f"prove_{fn.c_name}", f"{fn.c_name}() for every uint32_t bus code, code by code", body
    )


def _timing_harness(
    core: Core, low: IConst, high: IConst, per_code: bool, decisions: list[tuple[str, str]]
) -> str:
    fn = core.design.commutation_timing
    bus_fn = core.design.bus_condition
    code = bus_fn.params[0].name
    # The other inputs are drawn before the bus code is partitioned: the same values
    # in every partition, but one call of each interval builtin instead of one per
    # partition (3 x 1131 on the paper motor, 2 of the analysis's 13 s)
    draws = []
    splits = []
    args = []
    for p in fn.params:
        if p.struct is not None:
            args.append("&bus")
            continue
        assert p.ctype is not None
        draws.append(f"    {p.ctype.name} {p.name} = {_any(p.ctype)};")
        if per_code:
            splits += _decision_splits(p.name, "bus", [f for q, f in decisions if q == p.name])
        args.append(p.name)
    body = [
        *draws,
        f"    uint32_t {code} = {_any(U32)};",
        *_partition_codes(code, low, high, per_code),
        f"    const {core.design.bus_struct.c_name} bus = {bus_fn.c_name}({code});",
    ]
    call = f"{fn.c_name}({', '.join(args)});"
    if splits:  # a split annotates a statement, which a declaration is not
        body += ["    bldc_timing_t timing;", *splits, f"    timing = {call}"]
    else:
        body.append(f"    const bldc_timing_t timing = {call}")
    body.append("    (void)timing;")
    return _harness(
        f"prove_{fn.c_name}",
        f"{fn.c_name}() for a bus state of every uint32_t code and every uint32_t period, "
        "current and duty",
        body,
    )


def _commutate_harness(core: Core) -> str:
    """bldc_commutate() over every input at once: its contracts follow from its
    callees' by WP, so EVA has only run-time errors to rule out here."""
    fn = next(f for f in core.module.functions if f.c_name == "bldc_commutate")
    inputs = next(p for p in fn.params if p.struct is not None and p.const)
    outputs = next(p for p in fn.params if p.struct is not None and not p.const)
    assert inputs.struct is not None and outputs.struct is not None
    body = [f"    {inputs.struct.c_name} {inputs.name};"]
    body += [f"    {inputs.name}.{f.name} = {_any(f.ctype)};" for f in inputs.struct.fields]
    body += [
        f"    {outputs.struct.c_name} {outputs.name};",
        f"    {fn.c_name}(&{inputs.name}, &{outputs.name});",
    ]
    return _harness(
        f"prove_{fn.c_name}", f"{fn.c_name}() for every value of every input field", body
    )


def _guarded_harness(fn: Function) -> str:
    domains = guarded_domains(fn)
    body = []
    for p in fn.params:
        assert p.ctype is not None
        body.append(f"    {p.ctype.name} {p.name} = {_any(p.ctype)};")
        top = domains.get(p.name)
        if top is not None:
            bound = literal(top, p.ctype)
            body += [
                f"    /* one partition per value of [0, {top}], one for the rest */",
                f"    //@ split {p.name} <= {bound};",
                f"    if ({p.name} <= {bound}) {{",
                f"        /*@ split {p.name}; */ {ANCHOR}",
                "    }",
            ]
    assert fn.returns is not None and not hasattr(fn.returns, "fields")
    ret = fn.returns.name  # type: ignore[union-attr]
    args = ", ".join(p.name for p in fn.params)
    body += [f"    const {ret} result = {fn.c_name}({args});", "    (void)result;"]
    return _harness(f"prove_{fn.c_name}", f"{fn.c_name}() for every pair of arguments", body)


def clz_model() -> str:
    """__builtin_clz for a non-zero argument: the count of leading zero bits."""
    lines = [
        "/* __builtin_clz as the Cortex-M3's CLZ computes it for a non-zero argument (GCC",
        " * leaves 0 undefined: required). Frama-C's declaration only bounds the result to",
        " * [0, 31]; this definition gives EVA the exact count. */",
        "/*@ requires nonzero: x != 0;",
        "    assigns \\nothing;",
        "    ensures leading_zeros: x >> (31 - \\result) == 1;",
        "*/",
        "int __builtin_clz(unsigned int x)",
        "{",
    ]
    for k in range(31):
        lines.append(f"    if (x >= {literal(1 << (31 - k), U32)}) {{")
        lines += [f"        return {k};", "    }"]
    lines += ["    return 31;", "}"]
    return "\n".join(lines)


def proof_plan(core: Core) -> ProofPlan:
    low, high = bus_code_bounds(core.design.bus_condition)
    relational = relational_outputs(core)
    per_code = bool(relational)
    decisions = bus_decisions(core.design.commutation_timing)
    codes = high.value - low.value + 1
    code_partitions = (
        f"one per bus code of [{low.value}, {high.value}] ({codes}), one below, one above"
    )
    if per_code:
        reason = (
            "the IR's interval proof leaves "
            + "; ".join(relational)
            + f", above the PWM period {core.limits.period_counts.value}: a relational "
            "contract, so one partition per bus code and the period split at "
            + ", ".join(f"bus.{f}" for _, f in decisions)
        )
    else:
        reason = "the IR's interval proof keeps every compare value within the PWM period"
    timing_partitions = (
        f"{code_partitions}; the period split at " + ", ".join(f"bus.{f}" for _, f in decisions)
        if per_code
        else "one (every value of every input at once)"
    )
    edge_of = next(f for f in core.module.functions if f.inline)
    domains = guarded_domains(edge_of)
    edge_partitions = ", ".join(f"{p}: each of [0, {v}] and the rest" for p, v in domains.items())
    analyses = (
        Analysis(
            core.design.bus_condition.c_name,
            "prove_bldc_bus_condition",
            code_partitions,
            codes + 2,
            per_code=True,
        ),
        Analysis(
            core.design.commutation_timing.c_name,
            "prove_bldc_commutation_timing",
            timing_partitions,
            codes + 2 if per_code else 1,
            # code by code, the bus state's functions are analysed exactly as in their
            # own run (which reports their statements): keeping their values and the
            # harness's for each of the 2 x 1131 partitions again cost 14 % of this run
            (
                "prove_bldc_commutation_timing",
                core.design.bus_condition.c_name,
                *callees(core.design.bus_condition),
            )
            if per_code
            else (),
            per_code,
        ),
        Analysis(
            edge_of.c_name, f"prove_{edge_of.c_name}", edge_partitions or "one", SMALL_DOMAIN + 1
        ),
        Analysis(
            "bldc_commutate", "prove_bldc_commutate", "one (every value of every input at once)", 1
        ),
    )
    hints = max(
        [SMALL_DOMAIN + 1]
        + [
            len(e.table.rows)
            for fn in called_functions(core.module)
            for e in all_exprs(fn.body)
            if isinstance(e, IStep)
        ]
    )
    analyses = tuple(replace(a, split_limit=max(a.split_limit, hints)) for a in analyses)
    loop = current_loop.design(core.spec)
    loop_functions = (loop.duty, loop.integrate, loop.reference)
    analyses += tuple(
        Analysis(fn.c_name, f"prove_{fn.c_name}", "one (every value of every argument at once)", 1)
        for fn in loop_functions
    )
    uses_clz = any(
        isinstance(e, IBitLength)
        for fn in called_functions(core.module)
        for e in all_exprs(fn.body)
    )
    functions = (
        _bus_condition_harness(core, low, high),
        _timing_harness(core, low, high, per_code, decisions),
        _guarded_harness(edge_of),
        _commutate_harness(core),
        *(_loop_harness(fn) for fn in loop_functions),
    )
    return ProofPlan(analyses, per_code, reason, functions, clz_model() if uses_clz else "")


def render_proof_files(core: Core) -> dict[str, str]:
    """generated/<spec>/proof/: the harness and the plan `make prove` runs."""
    plan = proof_plan(core)
    spec = core.spec
    harness_template = "proof/harness.c.j2"
    files = {
        "proof/harness.c": render(
            harness_template,
            provenance=provenance(f"templates/{harness_template}", spec),
            reason=plan.reason,
            clz_model=plan.clz_model,
            functions=list(plan.harness_functions),
        )
    }
    helpers = [fn.c_name for fn in called_functions(core.module) if fn.static and not fn.inline]
    inline = {fn.c_name for fn in core.module.functions if fn.inline}
    loop = current_loop.design(spec)
    inline |= {fn.c_name for fn in (loop.duty, loop.integrate, loop.reference) if fn.inline}
    data = {
        "provenance": f"Generated by codegen/proof/harness.py with spec "
        f"{project_relative(spec.source_path)} (sha256 {spec.sha256}). Do not edit: "
        f"regenerate with `{regenerate_hint(spec)}`.",
        "sources": [
            "c/bldc_commutation.c",
            f"c/{current_loop.SOURCE}",
            "proof/harness.c",
        ],
        "include": "c",
        "partitioning": plan.reason,
        "analyses": [
            {
                "function": a.function,
                "main": a.main,
                "partitions": a.partitions,
                "inline": a.function in inline,
                "eva_options": [
                    "-eva-interprocedural-splits",
                    "-eva-split-limit",
                    str(a.split_limit),
                    *(["-eva-no-results-function", ",".join(a.no_results)] if a.no_results else []),
                    *(["-eva-no-memexec"] if a.per_code else []),
                ],
            }
            for a in plan.analyses
        ],
        "helpers": helpers,
    }
    files["proof/plan.json"] = json.dumps(data, indent=2) + "\n"
    return files

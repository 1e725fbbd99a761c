"""One spec's whole core: the method's functions, the Hall part, the ABI, proven.

`build_core` assembles the IR module and proves every public function over every value
of its parameters' types (a struct parameter over what its producer returns).
`core_context` prints it for the templates: C definitions, declarations and the
Python twin, ready strings only.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

from codegen import abi
from codegen.core.conditioning import CoreLimits, core_limits
from codegen.core.contracts import api_contracts
from codegen.core.hall import commutate_function, edge_of_function, hall_tables
from codegen.derivation import derive
from codegen.fixedpoint.scaling import Scaling, scaling
from codegen.ir import acsl, c_printer, py_printer
from codegen.ir.intervals import ProvenRange, full, new_prover, prove_function
from codegen.ir.longdiv import DIVIDE_LONG
from codegen.ir.nodes import Function, ICall, IConst, ILongDiv, Module, SFor, SStruct, StructType
from codegen.ir.types import U32
from codegen.ir.walk import called_functions, named_constants, tables
from codegen.methods import method
from codegen.methods.base import CoreDesign
from codegen.spec_model import Spec


@dataclass(frozen=True)
class Core:
    spec: Spec
    scaling: Scaling
    limits: CoreLimits
    design: CoreDesign
    module: Module
    ranges: tuple[ProvenRange, ...]

    @property
    def public_constants(self) -> tuple[IConst, ...]:
        return self.limits.public

    def function(self, c_name: str) -> Function:
        for fn in called_functions(self.module):
            if fn.c_name == c_name:
                return fn
        raise KeyError(c_name)


def prove_module(
    module: Module, bus_condition: Function, timing: Function
) -> tuple[ProvenRange, ...]:
    """Every public function over every value of its inputs."""
    prover = new_prover(module.functions)
    bus = prove_function(prover, bus_condition)
    fields = {f"bus.{k}": v for k, v in bus.struct_returns.items()}
    prove_function(prover, timing, fields)
    for fn in module.functions:
        if fn in (bus_condition, timing):
            continue
        params = {}
        for p in fn.params:
            if p.struct is not None and p.const:
                params.update({f"{p.name}.{f.name}": full(f.ctype) for f in p.struct.fields})
        prove_function(prover, fn, params)
    return prover.ranges


@lru_cache(maxsize=16)
def build_core(spec: Spec) -> Core:
    derivation = derive()
    sc = scaling(spec, derivation)
    limits = core_limits(spec, sc)
    design = method(spec.controller.method).design(spec, sc, limits)
    sectors, edges, switches = hall_tables(spec, derivation)
    edge_of = edge_of_function(edges)
    commutate = commutate_function(
        sectors, switches, edge_of, design.bus_condition, design.commutation_timing
    )
    module = Module(
        functions=(design.bus_condition, design.commutation_timing, edge_of, commutate),
        tables=(sectors, edges, switches, *design.tables),
        structs=(*abi.PUBLIC_STRUCTS, design.bus_struct),
        extra_constants=design.extra_constants,
    )
    ranges = prove_module(module, design.bus_condition, design.commutation_timing)
    return Core(spec, sc, limits, design, module, ranges)


def timing_is_leaf(core: Core) -> bool:
    """Whether bldc_commutation_timing() is straight-line arithmetic: no call, no helper
    (a long division prints as one), no loop. The port inlines such a function into its
    timing handler (no code grows: the linker drops the out-of-line copy it no longer
    calls); a method with helpers or loops keeps the call."""
    from codegen.ir.walk import all_exprs, all_statements

    body = core.design.commutation_timing.body
    calls = any(isinstance(e, (ICall, ILongDiv)) for e in all_exprs(body))
    loops = any(isinstance(s, SFor) for s in all_statements(body))
    return not calls and not loops


# ------------------------------------------------------------------------ printing


def _abi_defines() -> list[str]:
    lines = [c_printer.define(abi.value_const(name)) for name, _, _ in abi.VALUES]
    lines += [
        f"#define BLDC_FLAG_{f.name} 0x{f.value:02X}u /* {c_printer.comment_text(f.doc)} */"
        for f in abi.FLAGS
    ]
    return lines


def _range_lines(ranges: tuple[ProvenRange, ...]) -> list[str]:
    out = []
    for r in ranges:
        spare = r.headroom_bits
        spare_text = "inf" if spare == float("inf") else f"{spare:.1f}"
        out.append(
            f"{r.function}: {r.name}: {r.c_type} in [{r.low}, {r.high}] ({spare_text} bits spare)"
        )
    return out


def core_context(core: Core) -> dict[str, object]:
    """Printed C and Python of the core, for templates/c and templates/python."""
    module = core.module
    functions = called_functions(module)
    helpers = [fn for fn in functions if fn.static and not fn.inline]
    if DIVIDE_LONG not in helpers and any(fn is DIVIDE_LONG for fn in functions):
        helpers.insert(0, DIVIDE_LONG)
    public_names = {c.name for c in core.public_constants} | {
        c.name for c in module.extra_constants
    }
    abi_names = {f"BLDC_{n}" for n, _, _ in abi.VALUES} | {f"BLDC_FLAG_{f.name}" for f in abi.FLAGS}
    constants = named_constants(module)
    private = [c for c in constants if c.name not in public_names | abi_names]
    public = [*core.public_constants, *module.extra_constants]
    table_list = tables(module)
    public_tables = [t for t in table_list if not t.static]
    struct_defs = [c_printer.struct_typedef(s) for s in module.structs]
    private_structs = [s for s in used_structs(functions) if s not in module.structs]
    design = core.design
    contracts = api_contracts(core.spec, functions, design.bus_condition, core.ranges)

    def contract(fn: Function) -> str:
        return acsl.contract(contracts.functions[fn.c_name])

    return {
        "method": design.method,
        "doc": list(design.doc),
        "ranges": _range_lines(core.ranges),
        "h_defines": _abi_defines() + [c_printer.define(c) for c in public],
        "h_structs": struct_defs,
        "h_tables": [c_printer.table_declaration(t) for t in public_tables],
        "h_acsl": [acsl.predicate(p) for p in contracts.predicates],
        "h_prototypes": [
            f"/* {c_printer.comment_text(fn.doc)} */\n{contract(fn)}\n{c_printer.prototype(fn)}"
            for fn in module.functions
            if not fn.inline and not fn.static
        ],
        "h_inline": [
            c_printer.function_definition(fn, contract(fn)) for fn in module.functions if fn.inline
        ],
        "c_defines": [c_printer.define(c) for c in private],
        "c_structs": [c_printer.struct_typedef(s) for s in private_structs],
        "c_tables": [c_printer.table_definition(t) for t in table_list],
        "c_functions": [
            c_printer.function_definition(fn, contract(fn) if fn.static else "")
            for fn in functions
            if not fn.inline
        ],
        "py_constants": [py_printer.assignment(c) for c in constants]
        + [py_printer.assignment(c) for c in public if c.name not in {k.name for k in constants}]
        + [f"{n} = {v}" for n, v, _ in abi.VALUES if f"BLDC_{n}" not in {c.name for c in constants}]
        + [f"FLAG_{f.name} = {f.value}  # {f.doc}" for f in abi.FLAGS],
        "py_tables": [py_printer.table_definition(t) for t in table_list],
        "py_structs": [py_printer.named_tuple(s) for s in (*module.structs, *private_structs)],
        "py_helpers": py_printer.helpers(functions, always=True),
        "py_functions": [py_printer.function_definition(fn) for fn in functions],
        "uses_main_duty": design.uses_main_duty,
    }


def used_structs(functions: list[Function]) -> list[StructType]:
    """Struct types the functions take or build, in first-use order."""
    from codegen.ir.walk import all_statements

    out: list[StructType] = []
    for fn in functions:
        found = [p.struct for p in fn.params if p.struct is not None]
        found += [s.struct for s in all_statements(fn.body) if isinstance(s, SStruct)]
        for struct in found:
            if struct not in out:
                out.append(struct)
    return out


def manifest_entry(core: Core) -> dict[str, object]:
    """What the verifier reads: the method, its formats, claims and the ABI."""
    design = core.design
    return {
        "method": design.method,
        "formats": design.formats,
        "claims": {
            "duty_counts": design.claims.duty_counts,
            "commutation_time_ticks": design.claims.time_ticks,
            "commutation_time_region": design.claims.time_region,
        },
        "abi": abi.manifest_entry(),
        "limits": {c.name: c.value for c in core.public_constants},
    }


def u32(value: int, name: str, doc: str = "") -> IConst:
    return IConst(U32, value, name, doc=doc)


def twin_module(core: Core) -> object:
    """The bit-exact Python twin of this core, rendered and loaded in memory (for
    design-time checks and tests; the checked-in copy is python/bldc_fixed.py)."""
    import types

    from codegen.render import render

    text = render("python/bldc_fixed.py.j2", provenance="in memory", **core_context(core))
    module = types.ModuleType(f"bldc_fixed_{core.spec.name}")
    exec(compile(text, f"<twin {core.spec.name}>", "exec"), module.__dict__)
    return module

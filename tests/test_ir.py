"""The integer IR: printers agree with each other, the proof refuses what C would not
define, the proven ranges hold on the printed code, and the error analysis is sound."""

from __future__ import annotations

import random
import subprocess
import sys
from fractions import Fraction
from pathlib import Path

import pytest

from codegen.core.module import build_core, twin_module
from codegen.ir import c_printer, py_printer
from codegen.ir.errors import error
from codegen.ir.intervals import Interval, ProofError, new_prover, prove_function
from codegen.ir.nodes import (
    Function,
    IBin,
    IConst,
    IShl,
    Param,
    SAssign,
    SFor,
    SLet,
    SReturn,
    SVar,
    add,
    cast,
    cmp,
    const,
    div,
    maximum,
    mul,
    round_shr,
    select,
    shr,
    sub,
    var,
)
from codegen.ir.types import I32, U32, U64
from codegen.spec_loader import load_spec

ROOT = Path(__file__).resolve().parents[1]
SPECS = sorted(
    [*(ROOT / "spec").glob("*.yaml"), *(ROOT / "tests" / "fixtures" / "specs").glob("*.yaml")]
)
SPECS = [p for p in SPECS if p.name != "paper_printed.yaml"]

a, b = var("a", U32), var("b", U32)


def _fn(body: tuple, params: tuple = (Param("a", U32), Param("b", U32)), returns=U32) -> Function:  # type: ignore[no-untyped-def]
    return Function("ir_test", "ir_test", params, body, returns)


def _prove(fn: Function) -> None:
    prove_function(new_prover((fn,)), fn)


def test_proof_should_refuse_a_product_that_can_overflow() -> None:
    with pytest.raises(ProofError, match="beyond uint32_t"):
        _prove(_fn((SReturn(mul(a, b)),)))


def test_proof_should_accept_the_same_product_once_the_operands_are_saturated() -> None:
    body = (
        SLet("x", select(cmp(">", a, const(65535)), const(65535), a)),
        SLet("y", select(cmp(">", b, const(65535)), const(65535), b)),
        SReturn(mul(var("x", U32), var("y", U32))),
    )
    _prove(_fn(body))


@pytest.mark.parametrize(
    ("expr", "problem"),
    [
        (div(a, b), "divisor spans"),
        (sub(cast(a, I32), const(5, I32)), "cast to int32_t"),
        (
            shr(sub(cast(select(cmp(">", a, const(9)), const(9), a), I32), const(5, I32)), 1),
            "negative",
        ),
        (IShl(U32, const(1), var("b", U32)), "shift count"),
    ],
    ids=["division_by_zero", "a_wrapping_cast", "shift_of_a_negative", "shift_too_far"],
)
def test_proof_should_refuse_undefined_behaviour(expr: object, problem: str) -> None:
    ret = I32 if getattr(expr, "ctype", U32) == I32 else U32
    with pytest.raises(ProofError, match=problem):
        _prove(_fn((SReturn(expr),), returns=ret))  # type: ignore[arg-type]


def test_proof_should_hold_a_loop_to_its_declared_invariant() -> None:
    grows = SFor(
        "k", 4, (SAssign("acc", add(var("acc", U32), const(1))),), invariants=(("acc", 0, 2),)
    )
    with pytest.raises(ProofError, match="outside its invariant"):
        _prove(_fn((SVar("acc", U32, const(0)), grows, SReturn(var("acc", U32)))))
    kept = SFor(
        "k",
        4,
        (SAssign("acc", shr(add(var("acc", U32), const(2)), 1)),),
        invariants=(("acc", 0, 2),),
    )
    _prove(_fn((SVar("acc", U32, const(0)), kept, SReturn(var("acc", U32)))))


def _counting_loop(start_high: int) -> Function:
    """acc marks the steps (bit 3 - k) of a loop from min(a, start_high) to 4."""
    body = (
        SLet("first", select(cmp(">", a, const(start_high)), const(start_high), a)),
        SVar("acc", U32, const(0)),
        SFor(
            "k",
            4,
            (SAssign("acc", IBin(U32, "|", var("acc", U32), shr(const(8), var("k", U32)))),),
            invariants=(("acc", 0, 15),),
            start="first",
        ),
        SReturn(add(mul(var("acc", U32), const(16)), var("first", U32))),
    )
    return _fn(body)


def test_a_loop_from_a_variable_start_should_be_proven_and_printed_alike(tmp_path: Path) -> None:
    """The start is checked against [0, count]; C and Python run the same steps."""
    with pytest.raises(ProofError, match=r"loop start first is \[0, 5\], outside \[0, 4\]"):
        _prove(_counting_loop(5))
    fn = _counting_loop(4)
    _prove(fn)
    source = tmp_path / "loop.c"
    source.write_text(
        "#include <stdint.h>\n#include <stdio.h>\n"
        + c_printer.function_definition(fn)
        + '\nint main(void) { for (uint32_t a = 0u; a < 7u; ++a) { printf("%u\\n",'
        " ir_test(a, 0u)); } return 0; }\n"
    )
    exe = tmp_path / "loop"
    subprocess.run(["gcc", "-std=c99", "-Wall", "-Werror", str(source), "-o", str(exe)], check=True)
    out = subprocess.run([str(exe)], capture_output=True, text=True, check=True)
    namespace: dict[str, object] = {}
    exec(py_printer.C_DIV + "\n" + py_printer.function_definition(fn), namespace)
    python = [namespace["ir_test"](v, 0) for v in range(7)]  # type: ignore[operator]
    expected = [sum(8 >> k for k in range(min(v, 4), 4)) * 16 + min(v, 4) for v in range(7)]
    assert [int(v) for v in out.stdout.split()] == python == expected


def test_printers_should_compute_the_same_integers(tmp_path: Path) -> None:
    """A function with every rounding mode, printed to C and Python, on random inputs."""
    x = select(cmp(">", a, const(1 << 20)), const(1 << 20), a)
    y = add(select(cmp(">", b, const(1000)), const(1000), b), const(1))
    body = (
        SLet("x", x),
        SLet("y", y),
        SLet("q", div(var("x", U32), var("y", U32), "nearest")),
        SLet("c", div(var("x", U32), var("y", U32), "ceil")),
        SLet("t", div(var("x", U32), var("y", U32))),
        SLet("s", sub(cast(var("t", U32), I32), cast(var("q", U32), I32))),
        SLet("r", round_shr(mul(cast(var("x", U32), U64), cast(var("y", U32), U64), U64), 7)),
        SReturn(
            add(
                add(var("q", U32), var("c", U32)),
                cast(
                    add(var("r", U64), cast(cast(maximum(var("s", I32), const(0, I32)), U32), U64)),
                    U32,
                ),
            )
        ),
    )
    fn = _fn(body)
    _prove(fn)
    source = tmp_path / "f.c"
    source.write_text(
        "#include <stdint.h>\n#include <stdio.h>\n"
        + c_printer.function_definition(fn)
        + '\nint main(void) { uint32_t a, b; while (scanf("%u %u", &a, &b) == 2) '
        '{ printf("%u\\n", ir_test(a, b)); } return 0; }\n'
    )
    exe = tmp_path / "f"
    subprocess.run(
        [
            "gcc",
            "-std=c99",
            "-Wall",
            "-Wextra",
            "-Wconversion",
            "-Werror",
            "-fsanitize=undefined",
            "-fno-sanitize-recover",
            str(source),
            "-o",
            str(exe),
        ],
        check=True,
    )
    namespace: dict[str, object] = {}
    exec(py_printer.C_DIV + "\n" + py_printer.function_definition(fn), namespace)
    rng = random.Random(5)
    pairs = [(rng.randrange(2**32), rng.randrange(2**32)) for _ in range(2000)] + [
        (0, 0),
        (2**32 - 1, 2**32 - 1),
    ]
    out = subprocess.run(
        [str(exe)],
        input="\n".join(f"{p} {q}" for p, q in pairs),
        capture_output=True,
        text=True,
        check=True,
    )
    c_values = [int(v) for v in out.stdout.split()]
    assert c_values == [namespace["ir_test"](p, q) for p, q in pairs]  # type: ignore[operator]


def test_error_analysis_should_bound_the_real_error() -> None:
    """round(N / B) then round(x / T): the analysis' bound holds at every point."""
    from codegen.ir.nodes import ILongDiv

    exact = Fraction(10**12, 7)
    n = IConst(U64, round(exact), "N", exact=exact)
    bus, period = var("B", U32), var("T", U32)
    x = div(ILongDiv(U32, n, bus), period, "nearest")
    fn = _fn((SReturn(x),), params=(Param("B", U32), Param("T", U32)))
    prover = new_prover((fn,))
    env = {"B": Interval(2000, 3000), "T": Interval(500, 60000)}
    bound = error(prover, x, env, {})
    rng = random.Random(1)
    for _ in range(3000):
        bv, tv = rng.randint(2000, 3000), rng.randint(500, 60000)
        numerator = (round(exact) * 2 + bv) // (2 * bv)
        computed = (numerator + tv // 2) // tv
        assert abs(Fraction(computed) - exact / (bv * tv)) <= bound


@pytest.mark.parametrize("spec_path", SPECS, ids=[p.stem for p in SPECS])
def test_every_local_should_stay_inside_its_proven_range(spec_path: Path) -> None:
    """Trace the printed Python twin over random and extreme inputs: every local of
    every function lies in the interval the proof found for it."""
    core = build_core(load_spec(spec_path))
    twin = twin_module(core)
    proven: dict[tuple[str, str], tuple[int, int]] = {}
    names = {fn.py_name: fn.c_name for fn in _functions(core)}
    for r in core.ranges:
        proven[(r.function, r.name)] = (r.low, r.high)
    seen: list[str] = []

    def tracer(frame, event, arg):  # type: ignore[no-untyped-def]
        function = names.get(frame.f_code.co_name)
        if function is None:
            return tracer
        if event == "return":
            for local, value in frame.f_locals.items():
                if isinstance(value, int) and not isinstance(value, bool):
                    bounds = proven.get((function, local))
                    if bounds is not None:
                        seen.append(local)
                        assert bounds[0] <= value <= bounds[1], (function, local, value, bounds)
        return tracer

    rng = random.Random(9)
    inputs = [
        twin.Inputs(  # type: ignore[attr-defined]
            rng.randrange(256),
            rng.randrange(256),
            rng.randrange(65536),
            rng.randrange(65536),
            rng.randrange(65536),
            rng.randrange(65536),
        )
        for _ in range(300)
    ]
    sequence = core.spec.hall.sequence
    inputs += [
        twin.Inputs(sequence[1], sequence[0], t, bus, c, m)  # type: ignore[attr-defined]
        for t in (0, 1, core.limits.period_min.value, 65535)
        for bus in (0, core.limits.bus_min.value, core.limits.bus_max.value, 65535)
        for c in (0, core.limits.current_high.value, 65535)
        for m in (0, 65535)
    ]
    sys.settrace(tracer)
    try:
        for value in inputs:
            twin.commutate(value)  # type: ignore[attr-defined]
    finally:
        sys.settrace(None)
    assert {"x_q", "current"} & set(seen) or {"x", "current"} & set(seen)


def _functions(core: object) -> list[Function]:
    from codegen.ir.walk import called_functions

    return called_functions(core.module)  # type: ignore[attr-defined]

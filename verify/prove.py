"""`make prove`: Frama-C on the shipped C of each core, and PROOF.md.

    python -m verify.prove SPEC [SPEC ...] [--jobs N]

For each spec the shipped files are proven: generated/<name>/ when its manifest is of
this spec (`make check-generated` keeps it current), else the spec is generated into
build/prove/<name>/ first (a new motor, the test fixtures). The harness and its
partitioning are generated with the code (generated/<name>/proof/, codegen/proof/).

* EVA, once per public function, from the harness entry point that gives every input
  every value of its C type: the result must be 0 alarms (no overflow, division by
  zero, invalid shift, out-of-bounds access or lossy conversion for any input).
* WP on every contract of the core (the ACSL printed into the header) and on the
  harness's calls.
* Each contract clause must be established by WP or by EVA (EVA checks a function's
  postconditions over every input of its own analysis; WP is asked only for what EVA
  leaves). PROOF.md says which, with the alarms and the time per function. WP's proofs use the contracts of the callees and
  the absence of run-time errors, which EVA establishes: the two together close.

Exit status: 0 all proven, 1 an alarm or an unproven contract, 2 a bad spec, 3 a
missing or failing tool.
"""

from __future__ import annotations

import argparse
import json
import re
import sys
import time
from concurrent.futures import Future, ThreadPoolExecutor
from dataclasses import dataclass
from pathlib import Path

from codegen.argtypes import path_text, whole_number
from codegen.errors import ExitCode, SpecError
from codegen.generate import render_all, write_tree
from codegen.methods.base import FixedPointError
from codegen.publish import os_error_line, require_writable_folder
from codegen.render import PROJECT_ROOT, project_relative, render, write_atomically
from codegen.spec_loader import load_spec
from codegen.spec_model import Spec
from verify.frama_c import (
    EVA_POLICY,
    MACHDEP,
    SHIPPED_FILES,
    WP_LET,
    WP_NO_LET,
    WP_PROVEN,
    WP_PROVERS,
    WP_SECOND_PROVERS,
    WP_TIMEOUT_S,
    EvaResult,
    Property,
    ToolError,
    Tools,
    WpResult,
    find_tools,
    run_eva,
    run_wp,
    wp_passes,
)

#: the exit statuses of bldc-codegen (codegen.errors.ExitCode): a proof failed, the spec
#: (or its design) refused, Frama-C or a prover missing or failing
EXIT_FAILED, EXIT_SPEC, EXIT_TOOL = ExitCode.CHECK_FAILED, ExitCode.SPEC, ExitCode.ENVIRONMENT
#: the clause kinds a function's contract is made of (the report's rows)
CONTRACT_KINDS = (
    "postcondition",
    "assigns clause",
    "loop invariant",
    "complete behaviors",
    "disjoint behaviors",
)


@dataclass(frozen=True)
class Target:
    name: str
    spec: str
    root: Path  # holds c/ and proof/
    shipped: bool  # generated/<name>/ (else generated into build/prove/)
    plan: dict[str, object]


class StaleGeneratedError(ValueError):
    """--generated names a folder without the spec's current output."""


def shipped_output(spec: Spec, folders: tuple[Path, ...] = ()) -> Path | None:
    """The first of `folders`, then generated/<name>/ under the current folder, then
    the project's, that holds this spec's current output; else None (a user's motor
    generated under their own folder had been regenerated into build/ and proven
    there, its PROOF.md written beside the copy)."""
    candidates = (*folders, Path("generated") / spec.name, PROJECT_ROOT / "generated" / spec.name)
    for shipped in candidates:
        manifest = shipped / "manifest.json"
        try:
            recorded = json.loads(manifest.read_text(encoding="utf-8"))
        except (OSError, ValueError):
            continue
        if (
            isinstance(recorded, dict)
            and recorded.get("spec_sha256") == spec.sha256
            and (shipped / "proof" / "plan.json").is_file()
        ):
            return shipped.resolve()
    return None


def target_for(spec_path: str, build: Path, generated: Path | None = None) -> Target:
    """The shipped output of this spec (in `generated` first), or a fresh generation of
    it in build/."""
    spec = load_spec(spec_path)
    if generated is not None and shipped_output(spec, (generated,)) != generated.resolve():
        raise StaleGeneratedError(
            f"{generated} does not hold {spec_path}'s current output: give the folder"
            f" `bldc-codegen generate {spec_path} -o DIR` wrote (into a folder of another"
            " spec's output it would replace that)"
        )
    root = shipped_output(spec, () if generated is None else (generated,))
    if root is None:
        root = build / spec.name
        write_tree(render_all(spec_path).files, root)
        return target_at(root, spec.name, project_relative(spec_path), False)
    return target_at(root, spec.name, project_relative(spec_path), True)


def target_at(root: Path, name: str, spec: str, shipped: bool = False) -> Target:
    """A generated folder (c/ and proof/) as a proof target."""
    plan = json.loads((root / "proof" / "plan.json").read_text(encoding="utf-8"))
    return Target(name, spec, root, shipped, plan)


# ------------------------------------------------------------------ verdicts


@dataclass(frozen=True)
class Clause:
    function: str
    name: str
    kind: str
    text: str
    wp: bool
    eva: bool
    provers: str

    @property
    def method(self) -> str:
        if self.wp and self.eva:
            return "WP and EVA"
        return "WP" if self.wp else ("EVA" if self.eva else "NOT PROVEN")


def _key(p: Property) -> tuple[str, str, str, int, str]:
    return (p.owner, p.kind, p.name, p.line, p.text)


def _provers(wp: list[WpResult], function: str, name: str) -> str:
    """The provers of WP's goals for one clause (goal names are typed_<function>_...,
    ending with the clause's name, cut at Frama-C's length limit)."""
    found = set()
    for run in wp:
        for goal, prover in run.goals.items():
            base = re.sub(r"_part\d+$", "", goal)
            if not base.startswith(f"typed_{function}_"):
                continue
            tail = base.rsplit("_ensures_", 1)[-1] if "_ensures_" in base else base
            if name.startswith(tail) or base.endswith(name):
                found.add(prover or "-")
    return ", ".join(sorted(found - {"-"}))


def _wp_valid(wp: list[WpResult]) -> dict[tuple[str, str, str, int, str], list[bool]]:
    """Per clause, per copy and pass: proven by WP."""
    out: dict[tuple[str, str, str, int, str], dict[str, bool]] = {}
    for run in wp:
        for p in run.properties:
            if p.file in SHIPPED_FILES and p.kind in CONTRACT_KINDS:
                copies = out.setdefault(_key(p), {})
                copies[p.function] = copies.get(p.function, False) or p.status in WP_PROVEN
    return {k: list(v.values()) for k, v in out.items()}


def clauses(eva: list[EvaResult], wp: list[WpResult]) -> list[Clause]:
    """Every contract clause of the core's functions, and what established it: WP (every
    goal of the clause, in every copy Frama-C makes of an inline function, in one pass or
    the other) or EVA (valid in the analysis of the function's own harness, over every
    input)."""
    own = [p for r in eva for p in r.properties if p.owner == r.function]
    eva_valid = {_key(p) for p in own if p.status == "Valid"}
    texts = {_key(p): p for run in wp for p in run.properties}
    by_wp_copies = _wp_valid(wp)
    for p in own:  # the clauses WP was not asked for (EVA had established them)
        if p.file in SHIPPED_FILES and p.kind in CONTRACT_KINDS and _key(p) not in by_wp_copies:
            texts[_key(p)] = p
            by_wp_copies[_key(p)] = [False]
    out = []
    for key, copies in by_wp_copies.items():
        p = texts[key]
        by_wp = all(copies)
        provers = _provers(wp, p.owner, p.name) if by_wp and p.kind == "postcondition" else ""
        if by_wp and not provers:
            provers = "Qed"
        out.append(Clause(p.owner, p.name, p.kind, p.text, by_wp, key in eva_valid, provers))
    return sorted(out, key=lambda c: (c.function, c.kind, c.name))


def call_preconditions(wp: list[WpResult], eva: list[EvaResult]) -> list[tuple[Property, str]]:
    """Every precondition instance at a call of a core function (the callers' obligations)."""
    eva_valid = {(p.file, p.line, p.text) for r in eva for p in r.properties if p.status == "Valid"}
    wp_valid: dict[tuple[str, int, str], bool] = {}
    instances: dict[tuple[str, int, str], Property] = {}
    for run in wp:
        for p in run.properties:
            callee = p.kind.removeprefix("precondition of ")
            if callee != p.kind and not callee.startswith("Frama_C_"):
                key = (p.file, p.line, p.text)
                instances[key] = p
                wp_valid[key] = wp_valid.get(key, False) or p.status in WP_PROVEN
    out = []
    for key, p in sorted(instances.items()):
        methods = [m for m, ok in (("WP", wp_valid[key]), ("EVA", key in eva_valid)) if ok]
        out.append((p, " and ".join(methods) or "NOT PROVEN"))
    return out


# ------------------------------------------------------------------ running


@dataclass(frozen=True)
class Outcome:
    target: Target
    eva: list[EvaResult]
    wp: list[WpResult]


def _groups(t: Target) -> list[tuple[str, list[str]]]:
    """WP's runs: one per function of the core (public and static, so each has its
    time), one for the harness's entry points (its calls' preconditions)."""
    analyses = t.plan["analyses"]
    helpers = t.plan["helpers"]
    assert isinstance(analyses, list) and isinstance(helpers, list)
    core = [str(a["function"]) for a in analyses] + [str(h) for h in helpers]
    return [(f, [f]) for f in core] + [("harness", [str(a["main"]) for a in analyses])]


def _copies(t: Target) -> tuple[str, ...]:
    """The copy of each inline function that the harness's translation unit gets
    (Frama-C names it f_0): WP proves the one in the core's."""
    analyses = t.plan["analyses"]
    assert isinstance(analyses, list)
    return tuple(f"{a['function']}_0" for a in analyses if a.get("inline"))


_DEFINITION = re.compile(r"^[A-Za-z_][\w \*]*?\b(\w+)\([^;{]*\)\s*\n\{(.*?)^\}", re.M | re.S)


def _definitions(t: Target) -> dict[str, str]:
    """Each function defined in the proof's sources, and its body."""
    found = {}
    for source in t.plan["sources"]:  # type: ignore[attr-defined]
        text = (t.root / str(source)).read_text(encoding="utf-8")
        for m in _DEFINITION.finditer(text):
            found[m.group(1)] = m.group(2)
    return found


def _looping(t: Target) -> frozenset[str]:
    """The functions of the proof's sources whose body has a loop (its ACSL loop
    annotations, which the generator prints on every loop the proof must cover)."""
    return frozenset(
        name
        for name, body in _definitions(t).items()
        if "loop invariant" in body or re.search(r"\b(for|while|do)\b\s*[({]", body)
    )


def _calling(t: Target) -> frozenset[str]:
    """The functions of the proof's sources that call another one defined there (the
    harness's entry points, bldc_commutate, the bus state's long division)."""
    bodies = _definitions(t)
    return frozenset(
        name
        for name, body in bodies.items()
        if any(re.search(rf"\b{other}\s*\(", body) for other in bodies if other != name)
    )


def _passes(t: Target, functions: list[str]) -> tuple[tuple[str, ...], tuple[str, ...]]:
    """WP's two passes for a group: its functions' form (`wp_passes`); a group with a
    looping function takes the loop's, one with a calling function the caller's."""
    return wp_passes(
        any(f in _looping(t) for f in functions), any(f in _calling(t) for f in functions)
    )


def eva_established(eva: EvaResult) -> list[str]:
    """What of the analysed function's contract EVA established, in WP's selection
    syntax: each named postcondition every instance of which is valid over every input
    of its analysis, and `@invariant` when every loop invariant is. WP is not asked for
    them (a clause WP cannot prove costs its timeout, a clause EVA has closed costs WP
    nothing more than a second proof); WP still assumes them where it proves the rest,
    as Frama-C's consolidation does for a property another analysis established."""
    valid: dict[str, bool] = {}
    invariants: list[bool] = []
    for p in eva.properties:
        if p.owner != eva.function:
            continue
        if p.kind == "postcondition" and p.name != p.kind:
            valid[p.name] = valid.get(p.name, True) and p.status == "Valid"
        elif p.kind == "loop invariant":
            invariants.append(p.status == "Valid")
    done = sorted(name for name, ok in valid.items() if ok)
    return [*done, "@invariant"] if invariants and all(invariants) else done


def _first_pass(
    tools: Tools,
    t: Target,
    functions: list[str],
    work: Path,
    tag: str,
    eva: Future[EvaResult] | None,
) -> WpResult:
    """WP's first pass on a group, after its function's EVA analysis when it has one:
    every clause but those EVA established."""
    done = eva_established(eva.result()) if eva is not None else []
    selection = [f"-{name}" for name in done] or None
    first, _ = _passes(t, functions)
    return run_wp(
        tools, t.root, t.plan, functions, work, selection, first, tag=tag, skip=_copies(t)
    )


def prove(targets: list[Target], tools: Tools, build: Path, jobs: int) -> list[Outcome]:
    """Every EVA analysis, then WP's first pass on what each left, `jobs` at a time;
    then WP's second pass on the clauses neither established. Each WP run waits only
    for an EVA analysis submitted before it, so the pool never waits on itself."""
    with ThreadPoolExecutor(max_workers=jobs) as pool:
        analyses = {
            t.name: {
                str(a["function"]): pool.submit(
                    run_eva, tools, t.root, t.plan, a, build / t.name / "frama-c"
                )
                for a in t.plan["analyses"]  # type: ignore[attr-defined]
            }
            for t in targets
        }
        first = {
            t.name: [
                pool.submit(
                    _first_pass,
                    tools,
                    t,
                    fns,
                    build / t.name / "frama-c",
                    f"wp_{g}",
                    analyses[t.name].get(g),
                )
                for g, fns in _groups(t)
            ]
            for t in targets
        }
        outcomes = [
            Outcome(
                t,
                [f.result() for f in analyses[t.name].values()],
                [f.result() for f in first[t.name]],
            )
            for t in targets
        ]
        second: list[tuple[Outcome, Future[WpResult]]] = []
        for o in outcomes:
            left = [c for c in clauses(o.eva, o.wp) if c.method == "NOT PROVEN"]
            for g, fns in _groups(o.target):
                names = sorted({c.name for c in left if c.function in fns})
                if names:
                    run = pool.submit(
                        run_wp,
                        tools,
                        o.target.root,
                        o.target.plan,
                        fns,
                        build / o.target.name / "frama-c",
                        names,
                        _passes(o.target, fns)[1],
                        f"wp2_{g}",
                        WP_SECOND_PROVERS,
                        _copies(o.target),
                        True,
                    )
                    second.append((o, run))
        for o, run in second:
            o.wp.append(run.result())
    return outcomes


def establish(
    tools: Tools,
    target: Target,
    function: str,
    names: list[str],
    work: Path,
    timeout_s: float = WP_TIMEOUT_S,
) -> tuple[EvaResult, dict[str, str]]:
    """One function's EVA analysis, and what establishes each of the named clauses of
    its contract (WP's two passes restricted to them, or EVA): the quick form of the
    whole proof, for checks that a planted fault is caught. `timeout_s`: each prover's
    time per goal in both passes."""
    analysis = next(a for a in target.plan["analyses"] if a["function"] == function)  # type: ignore[attr-defined]
    eva = run_eva(tools, target.root, target.plan, analysis, work)
    skip = _copies(target)
    by_eva = set(eva_established(eva)) & set(names)
    asked = sorted(set(names) - by_eva)
    first, second = _passes(target, [function])

    def wp_pass(
        selection: list[str], options: tuple[str, ...], tag: str, provers: tuple[str, ...]
    ) -> WpResult:
        return run_wp(
            tools,
            target.root,
            target.plan,
            [function],
            work,
            selection,
            options,
            tag,
            provers,
            skip,
            tag != "wp",
            timeout_s,
        )

    wp = [wp_pass(asked, first, "wp", WP_PROVERS)] if asked else []

    def methods() -> dict[str, str]:
        rows = clauses([eva], wp)
        found = {c.name: c.method for c in rows if c.function == function and c.name in names}
        return {**found, **dict.fromkeys(sorted(by_eva), "EVA")}

    left = sorted(n for n, m in methods().items() if m == "NOT PROVEN")
    if left:
        wp.append(wp_pass(left, second, "wp2", WP_SECOND_PROVERS))
    return eva, methods()


def _times(o: Outcome) -> list[dict[str, str]]:
    """Per function: EVA's analysis from its entry point, and WP's runs on its contract."""
    eva = {r.function: r for r in o.eva}
    rows = []
    for group, functions in _groups(o.target):
        runs = [w for w in o.wp if list(w.functions) == functions]
        goals = {g: v for w in runs for g, v in w.goals.items()}
        first = next((w for w in runs if not w.second_pass), None)
        second = next((w for w in runs if w.second_pass), None)
        r = eva.get(group)
        rows.append(
            {
                "function": group,
                "eva": f"{r.seconds:.1f}" if r else "(within its callers)",
                "goals": f"{sum(1 for v in goals.values() if v)} / {len(goals)}",
                "wp": " + ".join(f"{w.seconds:.1f}" for w in (first, second) if w),
            }
        )
    return rows


def report(o: Outcome, tools: Tools) -> tuple[bool, str]:
    target = o.target
    rows = clauses(o.eva, o.wp)
    calls = call_preconditions(o.wp, o.eva)
    proven = (
        all(r.clean for r in o.eva)
        and all(c.method != "NOT PROVEN" for c in rows)
        and all(m != "NOT PROVEN" for _, m in calls)
        and bool(rows)
    )
    analyses = {str(a["function"]): a for a in target.plan["analyses"]}  # type: ignore[attr-defined]
    text = render(
        "proof/PROOF.md.j2",
        name=target.name,
        spec=target.spec,
        where=project_relative(target.root),
        shipped=target.shipped,
        verdict="PROVEN" if proven else "NOT PROVEN",
        tools=tools.version,
        provers=", ".join(tools.provers),
        machdep=MACHDEP,
        eva_policy=" ".join(EVA_POLICY),
        wp_provers=", ".join(WP_PROVERS),
        wp_second_provers=", ".join(WP_SECOND_PROVERS),
        wp_timeout=WP_TIMEOUT_S,
        wp_let=" ".join(WP_LET),
        wp_no_let=" ".join(WP_NO_LET),
        looping=sorted(_looping(target)),
        calling=sorted(_calling(target) - _looping(target)),
        partitioning=target.plan["partitioning"],
        analyses=[
            {
                "function": r.function,
                "partitions": analyses[r.function]["partitions"],
                "alarms": r.alarm_count,
                "alarm_list": list(r.alarms),
                "warnings": list(r.warnings)
                + [f"{p.kind} {p.text} is false for some input" for p in r.invalid],
                "reached": r.reached,
                "seconds": f"{r.seconds:.1f}",
            }
            for r in o.eva
        ],
        clauses=rows,
        calls=[
            {
                "caller": p.owner,
                "line": f"{p.file}:{p.line}",
                "callee": p.kind.removeprefix("precondition of "),
                "text": p.text,
                "method": m,
            }
            for p, m in calls
        ],
        times=_times(o),
        total_seconds=f"{sum(r.seconds for r in o.eva) + sum(w.seconds for w in o.wp):.1f}",
    )
    return proven, text


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(
        prog="verify.prove", description="Frama-C EVA and WP on the generated C core."
    )
    parser.add_argument("specs", nargs="+", help="motor spec YAML files")
    parser.add_argument(
        "--jobs", type=whole_number(1, 64), default=2, help="Frama-C runs at a time"
    )
    parser.add_argument(
        "--build",
        type=lambda text: Path(path_text(text)),
        default=Path("build") / "prove",
        help="work folder (default build/prove under the current folder)",
    )
    parser.add_argument(
        "--generated",
        type=lambda text: Path(path_text(text)),
        default=None,
        help="the spec's generated folder, where PROOF.md is written (one spec only;"
        " default generated/<name> under the current folder, then the project's, where"
        " it is the spec's current output; else a fresh generation under --build)",
    )
    args = parser.parse_args(argv)
    if args.generated is not None and len(args.specs) > 1:
        parser.error(f"--generated {args.generated}: one spec only (got {len(args.specs)})")
    # absolute: Frama-C runs in a folder of its own, where a relative include folder
    # named nothing (a relative --build failed to parse, reported as the environment's)
    args.build = args.build.resolve()
    start = time.monotonic()
    try:
        require_writable_folder(args.build)
        targets = [target_for(s, args.build, args.generated) for s in args.specs]
        for target in targets:  # PROOF.md goes there: before Frama-C's minutes, not after
            require_writable_folder(target.root)
    except (SpecError, FixedPointError) as exc:  # the design's refusal names its key
        print(f"prove: {exc}", file=sys.stderr)
        return int(EXIT_SPEC)
    except StaleGeneratedError as exc:
        print(f"prove: {exc}", file=sys.stderr)
        return int(ExitCode.STALE)
    except OSError as exc:  # a traceback had said FileExistsError (--build a file)
        print(f"prove: {os_error_line(exc).removeprefix('error: ')}", file=sys.stderr)
        return int(ExitCode.ENVIRONMENT)
    try:
        tools = find_tools(args.build)
        outcomes = prove(targets, tools, args.build, max(1, args.jobs))
    except ToolError as exc:
        print(f"prove: {exc}", file=sys.stderr)
        return int(EXIT_TOOL)
    status = 0
    for o in outcomes:
        proven, text = report(o, tools)
        out = o.target.root / "PROOF.md"
        try:
            write_atomically(out, text)
        except OSError as exc:
            print(f"prove: {os_error_line(exc).removeprefix('error: ')}", file=sys.stderr)
            return int(ExitCode.ENVIRONMENT)
        times = ", ".join(f"{r.function} {r.seconds:.1f} s" for r in o.eva)
        alarms = sum(r.alarm_count for r in o.eva)
        wp_time = " + ".join(f"{w.seconds:.1f}" for w in o.wp)
        print(
            f"prove {o.target.name}: {'PROVEN' if proven else 'NOT PROVEN'}: {alarms} alarms; "
            f"EVA {times}; WP {wp_time} s -> {project_relative(out)}"
        )
        if not proven:
            status = int(EXIT_FAILED)
    print(f"prove: {len(targets)} spec(s) in {time.monotonic() - start:.1f} s")
    return status


if __name__ == "__main__":
    from codegen.interrupts import exit_status

    raise SystemExit(exit_status(main))

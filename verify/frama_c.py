"""Run Frama-C (EVA and WP) on a generated core and read back what it established.

Only the tools' own reports are trusted: EVA's alarm count and the property statuses
Frama-C's report plugin writes (`-report-csv`), WP's per-goal verdicts from its log.
A missing tool is an error, never a skipped proof.
"""

from __future__ import annotations

import hashlib
import os
import re
import shutil
import subprocess
import threading
import time
from dataclasses import dataclass, field
from pathlib import Path

#: the analysis policy (not the partitioning, which the generated plan gives)
MACHDEP = "gcc_x86_32"  # int, long and pointers of 32 bits, as on the Cortex-M3 (ILP32)
EVA_POLICY = (
    "-eva",
    "-eva-no-show-progress",
    "-eva-msg-key=-initial-state,-final-states",
    # C defines unsigned wrap-around and leaves narrowing conversions to the compiler;
    # the core's arithmetic is designed never to wrap or narrow a value (the IR's proof
    # requires every value to fit its type), so both are alarms here
    "-warn-unsigned-overflow",
    "-warn-unsigned-downcast",
    "-warn-signed-downcast",
)
#: through Why3, after Qed (WP's own simplifier); the first pass uses Z3, which proves
#: every goal CVC4 proves here in a fraction of the time; the second pass tries both
WP_PROVERS = ("z3",)
WP_SECOND_PROVERS = ("z3", "cvc4")
WP_TIMEOUT_S = 5  # a goal Z3 proves takes at most 1.5 s here: margin for a loaded machine
#: provers WP keeps running at once: WP polls its provers every 50 ms, so one at a time
#: leaves the core idle between goals (bldc_commutate's 37 goals: 5.2 s wall for 3.1 s
#: of CPU with one, 3.1 s with two)
WP_PARALLEL = 2
#: kernel messages that are expected: the harness defines __builtin_clz with a contract,
#: which Frama-C merges with the one its library declares
EXPECTED_WARNINGS = (re.compile(r"found two contracts \(old location: FRAMAC_SHARE/libc/"),)
#: the same merge, as Frama-C reports it again at the harness's definition when a third
#: translation unit (the current loop's) declares the builtin too; only the harness
#: defines a function with a contract, so at a harness location it is that merge
EXPECTED_HARNESS_WARNINGS = (re.compile(r"^found two contracts\. Merging them$"),)

#: the shipped C that `make prove` proves: the core and the current loop
SHIPPED_FILES = frozenset(
    {"bldc_commutation.h", "bldc_commutation.c", "bldc_current_loop.h", "bldc_current_loop.c"}
)


class ToolError(RuntimeError):
    """A tool the proof needs is missing or broken."""


@dataclass(frozen=True)
class Tools:
    frama_c: str
    version: str
    why3_config: Path
    provers: tuple[str, ...]  # "Z3 4.8.12", ...


def find_tools(work: Path) -> Tools:
    """Frama-C and the SMT provers WP reaches through Why3 (configured in `work`, so a
    fresh machine needs no ~/.why3.conf)."""
    frama_c = shutil.which("frama-c")
    why3 = shutil.which("why3")
    missing = [n for n, p in (("frama-c", frama_c), ("why3", why3)) if p is None]
    if missing:
        raise ToolError(f"{', '.join(missing)} not found: install them with `make sysdeps`")
    assert frama_c is not None and why3 is not None
    work.mkdir(parents=True, exist_ok=True)
    version = _run([frama_c, "-version"], work).stdout.strip()
    config = work / "why3.conf"
    detected = _run([why3, "-C", str(config), "config", "detect"], work)
    found = re.finditer(
        r"Found prover (\S+) version (\S+), OK\.", detected.stdout + detected.stderr
    )
    provers = tuple(sorted({f"{m.group(1)} {m.group(2)}" for m in found}))
    wanted = {p.lower() for p in WP_PROVERS}
    if not any(p.split()[0].lower() in wanted for p in provers):
        raise ToolError(
            f"no SMT prover for WP among {', '.join(WP_PROVERS)} (Why3 found "
            f"{', '.join(provers) or 'none'}): install them with `make sysdeps`"
        )
    return Tools(frama_c, version, config, provers)


def _run(
    cmd: list[str], cwd: Path, env: dict[str, str] | None = None
) -> subprocess.CompletedProcess[str]:
    try:
        return subprocess.run(
            cmd, cwd=cwd, env=env, capture_output=True, text=True, check=False, timeout=1800
        )
    except OSError as exc:
        raise ToolError(f"{cmd[0]}: {exc}") from exc


# ------------------------------------------------------------------ statuses


@dataclass(frozen=True)
class Property:
    """One row of Frama-C's property report."""

    file: str
    line: int
    function: str
    kind: str  # postcondition, assigns clause, precondition of f, loop invariant, ...
    status: str  # Valid, Unknown, Invalid, Considered valid, Dead, ...
    text: str

    @property
    def name(self) -> str:
        """The ACSL label (`ensures name: ...`), or the kind for unnamed clauses."""
        m = re.match(r"([A-Za-z_]\w*): ", self.text)
        return m.group(1) if m else self.kind

    @property
    def owner(self) -> str:
        """The function, with the copy Frama-C makes of an inline function per
        translation unit (f_0, f_1) folded into f."""
        return re.sub(r"_\d+$", "", self.function)


def read_report(path: Path) -> list[Property]:
    """The rows of `-report-csv` (tab-separated; a property spanning lines continues on
    lines of its own), without Frama-C's own library."""
    records: list[list[str]] = []
    lines = path.read_text(encoding="utf-8").splitlines()
    header = lines[0].split("\t")
    for line in lines[1:]:
        cells = line.split("\t")
        if len(cells) == len(header):
            records.append(cells)
        elif records:
            records[-1][-1] += " " + line
    rows = []
    for cells in records:
        row = dict(zip(header, cells, strict=True))
        if row["directory"].startswith("FRAMAC_SHARE"):
            continue
        rows.append(
            Property(
                row["file"],
                int(row["line"] or 0),
                row["function"],
                row["property kind"],
                row["status"],
                " ".join(row["property"].split()),
            )
        )
    return rows


# ------------------------------------------------------------------ EVA


@dataclass(frozen=True)
class EvaResult:
    function: str
    main: str
    seconds: float
    alarms: tuple[str, ...]  # each alarm as EVA states it, with its location
    alarm_count: int
    reached: str  # "119 statements reached (out of 121)"
    warnings: tuple[str, ...]  # unexpected kernel or EVA warnings (not alarms)
    properties: tuple[Property, ...]
    log: str = field(repr=False)

    @property
    def invalid(self) -> tuple[Property, ...]:
        """Properties of the core or the current loop EVA found false for some input."""
        return tuple(
            p for p in self.properties if p.status.startswith("Invalid") and p.file in SHIPPED_FILES
        )

    @property
    def clean(self) -> bool:
        return self.alarm_count == 0 and not self.warnings and not self.invalid


#: the plug-ins the proof runs, and those EVA uses when they are there (inout: its
#: precision; scope: removing redundant alarms), which it warns about when they are
#: not: the same analyses and logs as with every installed plug-in, which Frama-C
#: loads by default (0.15 s of each of a spec's 16 runs)
PLUGINS = ("eva", "inout", "scope", "wp", "report")


def _frama_c(tools: Tools) -> list[str]:
    return [tools.frama_c, "-no-autoload-plugins", "-load-module", ",".join(PLUGINS)]


def _sources(root: Path, sources: list[str], include: str) -> list[str]:
    return [f"-cpp-extra-args=-I{root / include}", *(str(root / s) for s in sources)]


_ALARM = re.compile(r"^\[eva:alarm\] (\S+): Warning: *\n((?:  .*\n?)+)", re.M)
#: a warning of the kernel or EVA, with its location (empty for a warning about the
#: analysis as a whole, such as a plug-in it misses)
_WARNING = re.compile(r"^\[(kernel|eva)[^\]]*\] (?:(\S+): )?Warning: *(.*)\n?((?:  .*\n?)*)", re.M)


def _read_warnings(log: str) -> tuple[list[str], list[str]]:
    """EVA's run-time error alarms, and the kernel's and EVA's warnings that are not
    expected (property statuses are read from the report, not from here)."""
    alarms = []
    warnings = []
    for m in _WARNING.finditer(log):
        category, where = m.group(1), m.group(2) or ""
        text = " ".join(f"{m.group(3)} {m.group(4)}".split())
        if m.group(0).startswith("[eva:alarm]"):
            if "assert" in text and "postcondition" not in text and "precondition" not in text:
                alarms.append(f"{where}: {text}")
            continue
        if any(p.search(text) for p in EXPECTED_WARNINGS):
            continue
        if "proof/harness.c:" in where and any(p.search(text) for p in EXPECTED_HARNESS_WARNINGS):
            continue
        warnings.append(f"[{category}] {where}: {text}" if where else f"[{category}] {text}")
    return alarms, warnings


# ------------------------------------------------------------------ parsing


@dataclass(frozen=True)
class Parsed:
    """A plan's sources as Frama-C parsed them, saved (`-save`) for its runs to load:
    the preprocessing, parsing and typing of the core, the current loop and the harness
    are the same in every EVA and WP run of a target, a third of a light run's time."""

    session: Path
    warnings: tuple[str, ...]  # the kernel's unexpected warnings while parsing


#: the sessions parsed by this process, by _digest; never reused by another process
_PARSED: dict[str, Parsed] = {}
_PARSING: dict[str, threading.Lock] = {}
_PARSING_LOCK = threading.Lock()


def _digest(tools: Tools, root: Path, plan: dict[str, object]) -> str:
    """What a parse depends on: Frama-C, where the sources are (the locations Frama-C
    reports) and the content of the sources and of every header beside them."""
    h = hashlib.sha256(f"{tools.frama_c}\0{tools.version}\0{MACHDEP}\0{root}".encode())
    include = root / str(plan["include"])
    files = [root / str(s) for s in plan["sources"]]  # type: ignore[attr-defined]
    files += sorted(p for p in include.iterdir() if p.is_file())
    for path in files:
        h.update(f"\0{path}\0".encode())
        h.update(path.read_bytes())
    return h.hexdigest()


def parse(tools: Tools, root: Path, plan: dict[str, object], work: Path) -> Parsed:
    """The plan's sources parsed once per process (a source or header that changes is
    parsed again); each EVA and WP run loads the saved session."""
    key = _digest(tools, root, plan)
    with _PARSING_LOCK:
        lock = _PARSING.setdefault(key, threading.Lock())
    with lock:
        known = _PARSED.get(key)
        if known is not None and known.session.is_file():
            return known
        work.mkdir(parents=True, exist_ok=True)
        session = work / f"sources-{key[:16]}.sav"
        cmd = [
            *_frama_c(tools),
            "-machdep",
            MACHDEP,
            *_sources(root, list(plan["sources"]), str(plan["include"])),  # type: ignore[call-overload]
            "-save",
            str(session),
        ]
        done = _run(cmd, work)
        log = done.stdout + done.stderr
        (work / f"{session.stem}.log").write_text(log, encoding="utf-8")
        if done.returncode != 0 or not session.is_file():
            raise ToolError(
                f"Frama-C failed to parse {root} (exit {done.returncode}): {log[-2000:]}"
            )
        _, warnings = _read_warnings(log)
        _PARSED[key] = Parsed(session, tuple(warnings))
        return _PARSED[key]


#: how EVA ends when told to stop at its first alarm (an exit status of 1, no report)
STOPPED_AT_ALARM = "Stopping at nth alarm"


def run_eva(
    tools: Tools,
    root: Path,
    plan: dict[str, object],
    analysis: dict[str, object],
    work: Path,
    *,
    first_alarm: bool = False,
) -> EvaResult:
    """One EVA analysis of the plan: `main` over every input, with its partitioning.
    `first_alarm` stops it at its first alarm: for a check that only needs one (a
    planted fault must raise one), never for a proof."""
    parsed = parse(tools, root, plan, work)
    main = str(analysis["main"])
    report = work / f"eva_{main}.csv"
    cmd = [
        *_frama_c(tools),
        "-load",
        str(parsed.session),
        *EVA_POLICY,
        "-main",
        main,
        *analysis["eva_options"],  # type: ignore[misc]
        *(["-eva-stop-at-nth-alarm", "1"] if first_alarm else []),
        "-then",
        "-report-csv",
        str(report),
    ]
    start = time.monotonic()
    done = _run(cmd, work)
    seconds = time.monotonic() - start
    log = done.stdout + done.stderr
    (work / f"eva_{main}.log").write_text(log, encoding="utf-8")
    count = re.search(r"(\d+) alarms? generated by the analysis", log)
    stopped = first_alarm and STOPPED_AT_ALARM in log
    if not stopped and (done.returncode != 0 or count is None or not report.is_file()):
        raise ToolError(f"EVA failed on {main} (exit {done.returncode}): {log[-2000:]}")
    alarms, warnings = _read_warnings(log)
    reached = re.search(r"(\d+ statements reached \(out of \d+\))", log)
    return EvaResult(
        str(analysis["function"]),
        main,
        seconds,
        tuple(alarms),
        max(len(alarms), 1) if stopped else int(count.group(1)),  # type: ignore[union-attr]
        reached.group(1) if reached else "",
        (*parsed.warnings, *warnings),
        () if stopped else tuple(read_report(report)),
        log,
    )


# ------------------------------------------------------------------ WP


@dataclass(frozen=True)
class WpResult:
    functions: tuple[str, ...]
    second_pass: bool
    seconds: float
    goals: dict[str, str]  # goal -> "Qed", "Z3 4.8.12", ... or "" when not proven
    properties: tuple[Property, ...]
    log: str = field(repr=False)


_GOAL = re.compile(r"^\[wp\] \[([^\]]+)\] Goal (\S+) : (\w+)", re.M)
_FAILED = re.compile(r"^\[wp\] \[(?:Failed|Unknown|Timeout)\] Goal (\S+)", re.M)


#: WP without variable elimination: Qed keeps a local that holds a shifted value as one
#: term instead of rewriting one occurrence of the shift into a division and not the
#: other (which no prover then relates), and it simplifies the long straight-line code
#: after a loop in milliseconds instead of half a minute a goal (improved_r's
#: bldc_commutation_timing: the same 90 of 95 goals in 37 s, not 212 s), and a leaf
#: function's arithmetic in a fraction of the time (the paper core's
#: bldc_commutation_timing: 1.4 s of Frama-C for its whole contract, not 14 s)
WP_NO_LET = ("-wp-no-let",)
#: WP with variable elimination (Qed's default): proves in milliseconds goals the other
#: form leaves to a prover's timeout (bldc_commutate's flag of an invalid Hall code,
#: through its callees' contracts)
WP_LET = ("-wp-let",)


def wp_passes(has_loop: bool, calls: bool) -> tuple[tuple[str, ...], tuple[str, ...]]:
    """WP's first and second pass for a function, the second on what the first left:
    - with a loop, without variable elimination in both (with it, Qed takes half a
      minute a goal after the loop before any prover starts);
    - calling another function of the core, with it first (the callees' contracts
      simplify away), then without;
    - a leaf of straight-line arithmetic, without it first, then with it."""
    if has_loop:
        return (WP_NO_LET, WP_NO_LET)
    return (WP_LET, WP_NO_LET) if calls else (WP_NO_LET, WP_LET)


#: statuses that count as proven by WP: "Partially proven" is a proof that rests on
#: other clauses of the session (a loop invariant, a callee's contract), each of which
#: must itself be established for the verdict
WP_PROVEN = ("Valid", "Partially proven")


def run_wp(
    tools: Tools,
    root: Path,
    plan: dict[str, object],
    functions: list[str],
    work: Path,
    properties: list[str] | None = None,
    options: tuple[str, ...] = WP_NO_LET,
    tag: str = "wp",
    provers: tuple[str, ...] = WP_PROVERS,
    skip: tuple[str, ...] = (),
    second_pass: bool = False,
    timeout_s: float = WP_TIMEOUT_S,
) -> WpResult:
    """WP on the contracts of `functions` (the core's and the harness's), or on the
    selection `properties` of them: clause names, or `-name` to leave a clause out.
    `timeout_s`: each prover's time per goal (the proof's is WP_TIMEOUT_S)."""
    parsed = parse(tools, root, plan, work)
    report = work / f"{tag}.csv"
    selection = [f"-wp-prop={','.join(properties)}"] if properties else []
    cmd = [
        *_frama_c(tools),
        "-load",
        str(parsed.session),
        "-wp",
        "-wp-fct",
        ",".join(functions),
        *selection,
        *options,
        *(["-wp-skip-fct", ",".join(skip)] if skip else []),
        "-wp-prover",
        ",".join(provers),
        "-wp-timeout",
        f"{timeout_s:g}",
        "-wp-par",
        str(WP_PARALLEL),
        "-wp-out",
        str(work / tag),
        "-then",
        "-report-csv",
        str(report),
    ]
    env = dict(os.environ, WHY3CONFIG=str(tools.why3_config))
    start = time.monotonic()
    done = _run(cmd, work, env)
    seconds = time.monotonic() - start
    log = done.stdout + done.stderr
    (work / f"{tag}.log").write_text(log, encoding="utf-8")
    if not report.is_file() or "Proved goals" not in log:
        raise ToolError(f"WP failed (exit {done.returncode}): {log[-2000:]}")
    goals: dict[str, str] = {}
    for m in _GOAL.finditer(log):
        prover, goal, verdict = m.groups()
        if verdict == "Valid":
            goals[goal] = prover
        else:
            goals.setdefault(goal, "")
    for m in _FAILED.finditer(log):
        goals.setdefault(m.group(1), "")
    return WpResult(
        tuple(functions),
        second_pass,
        seconds,
        goals,
        tuple(read_report(report)),
        log,
    )

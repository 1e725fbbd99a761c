"""Build and run the generated Unity tests on the host (with sanitizers) and on a
Cortex-M3 under qemu, and read Unity's output into per-test results.

Why both: the host run catches undefined behaviour and out-of-bounds access with
AddressSanitizer and UBSan, which the target cannot; the qemu run executes the very
Thumb-2 code arm-none-eabi-gcc produces, with 32-bit `int` and hardware UDIV, which the
host cannot. The same test sources run on both, so the per-test results must be
identical; a difference is a portability bug in the core.

Unity comes from `UNITY_DIR` (a checkout: UNITY_DIR/src/unity.c) when that environment
variable is set, else from verify/unity_standin, our own implementation of the part of
Unity's API the generated tests use. Both print Unity's format, which is what we parse,
never the exit status alone: a runner that prints nothing or skips tests must not pass.

Layout expected under `generated` (generated/<spec>/ or a copy): c/bldc_commutation.{h,c}
and tests/test_bldc_commutation.c, tests/test_runner.c. Compilers run in that folder
with relative paths, so `__FILE__`, and with it every reported line, is the same on
host and target.

    python -m verify.unity_run generated/paper_motor [build-dir]
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

VERIFY_DIR = Path(__file__).resolve().parent
STANDIN_DIR = VERIFY_DIR / "unity_standin"
QEMU_DIR = VERIFY_DIR / "qemu"

#: Generated sources, relative to generated/<spec>/.
SOURCES = ("tests/test_runner.c", "tests/test_bldc_commutation.c", "c/bldc_commutation.c")
INCLUDES = ("-Ic", "-Itests")
WARNINGS = ("-std=c99", "-Wall", "-Wextra", "-Wconversion", "-Wpedantic")
HOST_CC = "gcc"
HOST_FLAGS = (
    "-O1",
    "-g",
    "-fno-omit-frame-pointer",
    "-fsanitize=address,undefined",
    "-fno-sanitize-recover=all",
)
#: Make every sanitizer finding fatal and keep its report on stderr.
SANITIZER_ENV = {
    "ASAN_OPTIONS": "abort_on_error=0:halt_on_error=1:detect_stack_use_after_return=1",
    "UBSAN_OPTIONS": "halt_on_error=1:print_stacktrace=1",
}
SANITIZER_MARKERS = ("ERROR: AddressSanitizer", "ERROR: LeakSanitizer", "runtime error:")

TARGET_CC = "arm-none-eabi-gcc"
QEMU = "qemu-system-arm"
TARGET_FLAGS = (
    "-mcpu=cortex-m3",
    "-mthumb",
    "-O2",
    "-g",
    "-ffreestanding",
    "-ffunction-sections",
    "-fdata-sections",
    "-fno-tree-loop-distribute-patterns",  # memcpy/memset must not call themselves
)
#: Unity's own configuration macros: the stand-in honours them as well, so one set of
#: flags serves both. No libc on target: characters leave through semihosting.
TARGET_DEFINES = (
    "-DUNITY_OUTPUT_CHAR=semihosting_putchar",
    "-DUNITY_OUTPUT_CHAR_HEADER_DECLARATION=semihosting_putchar(int)",
    "-DUNITY_EXCLUDE_FLOAT",
    "-DUNITY_EXCLUDE_DOUBLE",
    "-DUNITY_EXCLUDE_SETJMP_H",
    "-DUNITY_EXCLUDE_MATH_H",
)
TARGET_SUPPORT = (QEMU_DIR / "startup_mps2_an385.c", QEMU_DIR / "semihosting.c")
LINKER_SCRIPT = QEMU_DIR / "mps2_an385.ld"
#: Semihosting output would go to qemu's stderr; a stdio chardev puts it on stdout, as on
#: the host, and leaves stderr to qemu's own diagnostics. No UART, no monitor.
QEMU_ARGS = (
    "-machine",
    "mps2-an385",
    "-cpu",
    "cortex-m3",
    "-nographic",
    "-serial",
    "none",
    "-monitor",
    "none",
    "-chardev",
    "stdio,id=semihosting",
    "-semihosting-config",
    "enable=on,target=native,chardev=semihosting",
)
#: A core stuck in a loop must fail the run, not hang the test session.
RUN_TIMEOUT_S = 60.0
TIMED_OUT = -1  # exit_code of a run that was stopped at its time limit

RESULT_LINE = re.compile(
    r"^(?P<file>[^:\n]+):(?P<line>\d+):(?P<name>[A-Za-z_]\w*):"
    r"(?P<status>PASS|FAIL|IGNORE)(?::[ ]?(?P<message>.*))?$"
)
SUMMARY_LINE = re.compile(
    r"^(?P<tests>\d+) Tests (?P<failures>\d+) Failures (?P<ignored>\d+) Ignored"
)


class UnityBuildError(RuntimeError):
    """A compile or link step failed; the message carries the command and its output."""


@dataclass(frozen=True)
class UnityFramework:
    """Which Unity is compiled in. `strict`: the runner is ours, so -Werror applies to it
    too; a third-party checkout is compiled with the same warnings but not made fatal."""

    name: str
    include_dir: Path
    source: Path
    strict: bool


@dataclass(frozen=True)
class UnityResult:
    name: str
    status: str  # PASS, FAIL or IGNORE
    file: str
    line: int
    message: str


@dataclass(frozen=True)
class UnitySummary:
    tests: int
    failures: int
    ignored: int
    verdict: str  # the closing OK or FAIL


@dataclass(frozen=True)
class UnityOutput:
    results: tuple[UnityResult, ...]
    summary: UnitySummary | None


@dataclass(frozen=True)
class UnityRun:
    platform: str  # "host" or "qemu mps2-an385"
    framework: str
    results: tuple[UnityResult, ...]
    summary: UnitySummary | None
    exit_code: int
    stdout: str
    stderr: str
    build_seconds: float
    run_seconds: float

    @property
    def sanitizer_reports(self) -> tuple[str, ...]:
        return tuple(
            line for line in self.stderr.splitlines() if any(m in line for m in SANITIZER_MARKERS)
        )

    @property
    def problems(self) -> tuple[str, ...]:
        """Why the run does not count as all-passed; empty when it does. Each test must
        have printed PASS and the summary must agree with the lines and the exit status,
        so a crash, a truncated run or a silent runner cannot pass."""
        found = [
            f"{r.file}:{r.line}:{r.name}: {r.status} {r.message}".rstrip()
            for r in self.results
            if r.status != "PASS"
        ]
        found += [f"sanitizer: {line}" for line in self.sanitizer_reports]
        if self.exit_code != 0:
            found.append(f"exit status {self.exit_code}")
        if self.summary is None:
            found.append("no Unity summary line: the run ended early")
        else:
            if self.summary.tests != len(self.results):
                found.append(
                    f"summary counts {self.summary.tests} tests, {len(self.results)} printed"
                )
            s = self.summary
            if s.failures or s.ignored or s.verdict != "OK":
                found.append(
                    f"summary: {s.tests} tests, {s.failures} failures, {s.ignored} ignored, {s.verdict}"
                )
        if not self.results:
            found.append("no test ran")
        return tuple(found)

    @property
    def passed(self) -> bool:
        return not self.problems


def unity_framework(environ: Mapping[str, str] = os.environ) -> UnityFramework:
    """Real Unity when UNITY_DIR names a checkout, else the stand-in."""
    unity_dir = environ.get("UNITY_DIR")
    if not unity_dir:
        return UnityFramework(
            "stand-in (verify/unity_standin)", STANDIN_DIR, STANDIN_DIR / "unity.c", True
        )
    src = Path(unity_dir) / "src"
    missing = [f for f in ("unity.c", "unity.h", "unity_internals.h") if not (src / f).is_file()]
    if missing:
        raise UnityBuildError(f"UNITY_DIR={unity_dir}: {', '.join(missing)} missing in {src}")
    return UnityFramework(f"Unity ({src})", src, src / "unity.c", False)


def parse_unity_output(text: str) -> UnityOutput:
    """Per-test lines and the closing summary of a Unity run; other lines are ignored
    (semihosting or sanitizer chatter). The summary's verdict is the line after it."""
    results: list[UnityResult] = []
    summary: UnitySummary | None = None
    lines = [line.rstrip("\r") for line in text.splitlines()]
    for index, line in enumerate(lines):
        result = RESULT_LINE.match(line)
        if result:
            results.append(
                UnityResult(
                    name=result["name"],
                    status=result["status"],
                    file=result["file"],
                    line=int(result["line"]),
                    message=(result["message"] or "").strip(),
                )
            )
            continue
        counts = SUMMARY_LINE.match(line)
        if counts:
            verdict = lines[index + 1].strip() if index + 1 < len(lines) else ""
            summary = UnitySummary(
                int(counts["tests"]), int(counts["failures"]), int(counts["ignored"]), verdict
            )
    return UnityOutput(tuple(results), summary)


def _run_tool(command: Sequence[str | Path], cwd: Path) -> None:
    """Run a compiler or linker in `cwd` (the generated folder, whose includes are
    relative); the caller passes its output paths absolute (`_absolute`)."""
    done = subprocess.run(
        [str(part) for part in command], cwd=cwd, capture_output=True, text=True, check=False
    )
    if done.returncode != 0:
        raise UnityBuildError(
            f"{' '.join(str(p) for p in command)} (in {cwd}) failed:\n{done.stdout}{done.stderr}"
        )


def _compile(
    cc: str, flags: Sequence[str], source: Path | str, obj: Path, generated: Path, strict: bool
) -> None:
    errors = ("-Werror",) if strict else ()
    _run_tool([cc, *WARNINGS, *errors, *flags, "-c", source, "-o", obj], generated)


def _objects(
    cc: str,
    flags: Sequence[str],
    generated: Path,
    build_dir: Path,
    unity: UnityFramework,
    sources: Sequence[str | Path],
) -> list[Path]:
    """Our code with -Werror; Unity too when it is the stand-in."""
    build_dir = build_dir.absolute()  # the compiler runs in `generated`: not relative to it
    build_dir.mkdir(parents=True, exist_ok=True)
    include = (*INCLUDES, f"-I{unity.include_dir}")
    objects = []
    for source in sources:
        obj = build_dir / f"{Path(source).stem}.o"
        _compile(cc, (*flags, *include), source, obj, generated, strict=True)
        objects.append(obj)
    unity_obj = build_dir / "unity.o"
    _compile(cc, (*flags, *include), unity.source, unity_obj, generated, unity.strict)
    return [*objects, unity_obj]


def build_host(
    generated: Path, build_dir: Path, unity: UnityFramework, sources: Sequence[str] = SOURCES
) -> Path:
    """Native test program with AddressSanitizer and UBSan, every finding fatal."""
    objects = _objects(HOST_CC, HOST_FLAGS, generated, build_dir, unity, sources)
    exe = build_dir.absolute() / "test_bldc_commutation"
    _run_tool([HOST_CC, *HOST_FLAGS, *objects, "-o", exe], generated)
    return exe


def build_qemu(
    generated: Path, build_dir: Path, unity: UnityFramework, sources: Sequence[str] = SOURCES
) -> Path:
    """Cortex-M3 image for mps2-an385: our start-up and semihosting, no libc."""
    flags = (*TARGET_FLAGS, *TARGET_DEFINES, f"-I{QEMU_DIR}")
    objects = _objects(TARGET_CC, flags, generated, build_dir, unity, (*sources, *TARGET_SUPPORT))
    elf = build_dir.absolute() / "test_bldc_commutation.elf"
    link = (
        "-nostdlib",
        f"-T{LINKER_SCRIPT}",
        "-Wl,--gc-sections",
        "-Wl,--no-warn-rwx-segments",
    )
    _run_tool([TARGET_CC, *TARGET_FLAGS, *link, *objects, "-lgcc", "-o", elf], generated)
    return elf


def _execute(
    platform: str,
    framework: UnityFramework,
    command: Sequence[str | Path],
    build_seconds: float,
    env: Mapping[str, str] | None,
    timeout: float,
) -> UnityRun:
    start = time.perf_counter()
    try:
        done = subprocess.run(
            [str(part) for part in command],
            capture_output=True,
            stdin=subprocess.DEVNULL,
            env=None if env is None else {**os.environ, **env},
            timeout=timeout,
            check=False,
        )
        exit_code, stdout, stderr = done.returncode, done.stdout, done.stderr
    except subprocess.TimeoutExpired as hung:
        exit_code, stdout = TIMED_OUT, hung.stdout or b""
        stderr = (hung.stderr or b"") + f"\ntimed out after {timeout} s\n".encode()
    seconds = time.perf_counter() - start
    out = stdout.decode(errors="replace")
    parsed = parse_unity_output(out)
    return UnityRun(
        platform=platform,
        framework=framework.name,
        results=parsed.results,
        summary=parsed.summary,
        exit_code=exit_code,
        stdout=out,
        stderr=stderr.decode(errors="replace"),
        build_seconds=build_seconds,
        run_seconds=seconds,
    )


def run_host(
    generated: Path,
    build_dir: Path,
    unity: UnityFramework | None = None,
    sources: Sequence[str] = SOURCES,
) -> UnityRun:
    """(a) Build with sanitizers and run natively."""
    framework = unity or unity_framework()
    start = time.perf_counter()
    exe = build_host(generated, build_dir / "host", framework, sources)
    built = time.perf_counter() - start
    return _execute("host", framework, [exe], built, SANITIZER_ENV, RUN_TIMEOUT_S)


def run_qemu(
    generated: Path,
    build_dir: Path,
    unity: UnityFramework | None = None,
    sources: Sequence[str] = SOURCES,
) -> UnityRun:
    """(b) Cross-build for the Cortex-M3 and run under qemu; the guest's exit status
    (semihosting SYS_EXIT_EXTENDED) becomes qemu's."""
    framework = unity or unity_framework()
    start = time.perf_counter()
    elf = build_qemu(generated, build_dir / "qemu", framework, sources)
    built = time.perf_counter() - start
    command: list[str | Path] = [QEMU, *QEMU_ARGS, "-kernel", elf]
    return _execute("qemu mps2-an385", framework, command, built, None, RUN_TIMEOUT_S)


def run_host_and_qemu(generated: Path, build_dir: Path) -> tuple[UnityRun, UnityRun]:
    """(c) Both runs with the same Unity, for comparing their per-test results."""
    framework = unity_framework()
    return run_host(generated, build_dir, framework), run_qemu(generated, build_dir, framework)


def qemu_available() -> bool:
    return shutil.which(QEMU) is not None and shutil.which(TARGET_CC) is not None


def report(run: UnityRun) -> str:
    verdict = "passed" if run.passed else "FAILED"
    lines = [
        f"{run.platform}: {len(run.results)} tests {verdict} with {run.framework}"
        f" (build {run.build_seconds:.1f} s, run {run.run_seconds:.2f} s)"
    ]
    lines += [f"  {problem}" for problem in run.problems]
    return "\n".join(lines)


#: bldc-codegen's status for a missing tool (ExitCode.ENVIRONMENT); 3 is a bad spec's
EXIT_MISSING_TOOL = 5


def _names_a_spec(path: Path) -> bool:
    """Whether GENERATED_DIR names a spec file (a file, or a .yaml path that is no folder)
    rather than a generated folder."""
    return path.is_file() or (path.suffix in (".yaml", ".yml") and not path.is_dir())


def _spec_given(path: Path) -> int:
    """A spec given for GENERATED_DIR: its errors, one line each (exit 3; a bad spec had
    read "has no generated Unity tests: generate it first"), else where its generated
    folder is (a usage error, exit 2)."""
    from codegen.errors import ExitCode, SpecError
    from codegen.shown import said
    from codegen.spec_loader import load_spec

    try:
        spec = load_spec(path)
    except SpecError as exc:
        for line in str(exc).splitlines():
            print(f"error: {line}", file=sys.stderr)
        return int(ExitCode.SPEC)
    print(
        f"error: {said(path)} is a spec, not a generated folder: give its generated folder"
        f" (generated/{spec.name}, made by `bldc-codegen generate {said(path)}`), or run"
        f" `bldc-codegen unity {said(path)}`",
        file=sys.stderr,
    )
    return int(ExitCode.USAGE)


def main(argv: Sequence[str] | None = None) -> int:
    import argparse

    parser = argparse.ArgumentParser(
        prog="python -m verify.unity_run",
        description="Build and run the generated Unity tests on the host (ASan/UBSan) and"
        " on a Cortex-M3 under qemu (mps2-an385), with real Unity when UNITY_DIR points to a"
        " checkout, else the stand-in runner. Exit 0 when both pass with identical per-test"
        " results; 1 when a test fails or they differ; 2 for a usage error; 3 for a spec"
        " given that does not load; 5 when qemu-system-arm or arm-none-eabi-gcc is missing"
        " (the target run cannot be skipped).",
    )
    parser.add_argument("generated", metavar="GENERATED_DIR", help="e.g. generated/paper_motor")
    parser.add_argument(
        "build", metavar="BUILD_DIR", nargs="?", help="build folder (default: a temporary one)"
    )
    args = parser.parse_args(argv)
    generated = Path(args.generated)
    if _names_a_spec(generated):
        return _spec_given(generated)
    if not (generated / "tests" / "test_runner.c").is_file():
        print(f"{generated} has no generated Unity tests: generate it first", file=sys.stderr)
        return 2
    if not qemu_available():
        print(
            f"unity_run: {QEMU} or {TARGET_CC} not found: install them (make sysdeps)",
            file=sys.stderr,
        )
        return EXIT_MISSING_TOOL
    with tempfile.TemporaryDirectory() as scratch:
        build_dir = Path(args.build) if args.build else Path(scratch)
        runs = [run_host(generated, build_dir), run_qemu(generated, build_dir)]
    for run in runs:
        print(report(run))
    identical = all(run.results == runs[0].results for run in runs)
    if not identical:
        print("per-test results differ between host and target")
    return 0 if identical and all(run.passed for run in runs) else 1


if __name__ == "__main__":
    sys.exit(main())

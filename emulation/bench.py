"""`make bench`: speed and size figures, measured, never asserted in tests.

* derive + audit from a cold start: a fresh interpreter runs `python -m codegen audit`;
* regeneration in a warm process;
* flash and RAM of the commutation code (core + port) and of the whole image;
* instructions and estimated Cortex-M3 cycles of the three interrupt handlers (Hall
  edge, commutation end, and the next edge's timing at low priority), run in unicorn
  over all Hall codes, both directions and a sweep of inputs (emulation/isr_bench.py);
* the same for the resistance-aware rule: the SPEC with its method replaced by
  improved_r, generated and linked under build/bench/ (emulation/rule_bench.py): flash and
  RAM with the psi table's share, the three handlers, and the timing handler that runs
  the rule's bisection over a sweep of the whole speed range, bus voltage and current,
  as a share of the shortest sector; no library helper reachable from it;
* the bus reciprocal: hardware divide (measured) against a lookup table sized for the
  accuracy target (emulation/reciprocal_bench.py), and which one the budget allows;
* the exhaustive host verification of the spec (`python -m verify`, whole run);
* the generated Unity tests built for and run on the emulated Cortex-M3 (qemu);
* the whole simulation of the spec (`python -m sim`: sweep, figures, report).
"""

from __future__ import annotations

import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

RUNS = 5
TARGET_DERIVE_AUDIT_S = 3.0
TARGET_REGENERATE_WARM_S = 2.0
TARGET_VERIFY_S = 10.0
TARGET_QEMU_S = 60.0
TARGET_SIMULATE_S = 60.0
#: Where the improved_r variant of the spec is generated and built.
RULE_BENCH_DIR = Path("build") / "bench"


def cold_audit_seconds(spec: str) -> list[float]:
    times = []
    with tempfile.TemporaryDirectory() as out:
        for _ in range(RUNS):
            started = time.perf_counter()
            subprocess.run(
                [sys.executable, "-m", "codegen", "audit", spec, "-o", out],
                check=True,
                stdout=subprocess.DEVNULL,
            )
            times.append(time.perf_counter() - started)
    return times


def warm_generate_seconds(spec: str) -> list[float]:
    """Regeneration in a process that has already imported and derived once."""
    from codegen.derivation import derive
    from codegen.generate import render_all

    derive()
    times = []
    for _ in range(RUNS):
        started = time.perf_counter()
        render_all(spec)
        times.append(time.perf_counter() - started)
    return times


def module_seconds(module: str, *args: str) -> float:
    """Wall time of `python -m module args` in a fresh interpreter (output discarded)."""
    started = time.perf_counter()
    subprocess.run([sys.executable, "-m", module, *args], check=True, stdout=subprocess.DEVNULL)
    return time.perf_counter() - started


def _verdict(ok: bool) -> str:
    return "meets" if ok else "MISSES"


def main(argv: list[str]) -> int:
    from codegen.build_firmware import build
    from codegen.generate import fixed_point_design
    from codegen.spec_loader import load_spec
    from emulation.isr_bench import bench, report, shortest_sector_cycles
    from emulation.reciprocal_bench import ReciprocalChoice, table_option

    spec = argv[0] if argv else "spec/paper_motor.yaml"
    cold = cold_audit_seconds(spec)
    median = statistics.median(cold)
    print(
        f"bench: derive + audit, cold start ({RUNS} runs): min {min(cold):.2f} s, median"
        f" {median:.2f} s -> {_verdict(median < TARGET_DERIVE_AUDIT_S)} the 3 s target"
    )
    warm = statistics.median(warm_generate_seconds(spec))
    print(
        f"bench: regenerate, warm: median {warm:.2f} s ->"
        f" {_verdict(warm < TARGET_REGENERATE_WARM_S)} the 2 s target"
    )
    name = load_spec(spec).name
    generated, build_dir = Path("generated") / name, Path("build") / name
    sizes = build(generated, build_dir)
    code = sizes["core"].flash + sizes["port"].flash
    ram = sizes["core"].ram + sizes["port"].ram
    print(
        f"bench: core + port flash {code} B, RAM {ram} B ->"
        f" {_verdict(code <= 2048 and ram <= 64)} the 2 KiB / 64 B target;"
        f" whole image {sizes['firmware.elf'].flash} B flash, {sizes['firmware.elf'].ram} B RAM"
    )
    stats = bench(spec, generated, build_dir)
    for line in report(stats, shortest_sector_cycles(spec)):
        print(f"bench: {line}")
    reciprocal = ReciprocalChoice(
        table=table_option(load_spec(spec), fixed_point_design(load_spec(spec))),
        divide_instructions=stats[3].instructions_worst,
        divide_cycles=stats[3].cycles_worst,
        flash_in_use=code,
    )
    for line in reciprocal.lines():
        print(f"bench: {line}")
    from emulation import rule_bench

    started = time.perf_counter()
    rule = rule_bench.run(spec, RULE_BENCH_DIR)
    for line in rule.lines():
        print(f"bench: {line}")
    print(
        f"bench: {rule_bench.METHOD} generate + build + measure {time.perf_counter() - started:.1f} s"
    )
    seconds = module_seconds("verify", spec, "--no-progress")
    print(
        f"bench: verify (exhaustive + 20000 random + boundary, host) {seconds:.1f} s ->"
        f" {_verdict(seconds < TARGET_VERIFY_S)} the 10 s target"
    )
    from verify.unity_run import run_qemu

    started = time.perf_counter()
    with tempfile.TemporaryDirectory() as qemu_build:
        run = run_qemu(generated, Path(qemu_build))
    seconds = time.perf_counter() - started
    print(
        f"bench: Unity tests on the emulated Cortex-M3 (build + qemu run,"
        f" {len(run.results)} tests, {'pass' if run.passed else 'FAIL'}) {seconds:.1f} s ->"
        f" {_verdict(seconds < TARGET_QEMU_S and run.passed)} the 60 s target"
    )
    with tempfile.TemporaryDirectory() as sim_out:
        seconds = module_seconds("sim", spec, "-o", sim_out, "--no-progress")
    print(
        f"bench: simulate (full sweep, operating points, Ipopt optimum, figures, report)"
        f" {seconds:.1f} s -> {_verdict(seconds < TARGET_SIMULATE_S)} the 60 s target"
    )
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))

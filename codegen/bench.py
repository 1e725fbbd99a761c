"""`make bench`: speed figures of the toolchain, measured, never asserted in tests.

Cold start: a fresh interpreter runs `python -m codegen audit SPEC` (import, derive,
audit, render, write), the way a user runs it. Repeated to report min and median.
"""

from __future__ import annotations

import statistics
import subprocess
import sys
import tempfile
import time

COLD_RUNS = 5
TARGET_DERIVE_AUDIT_S = 3.0


def cold_audit_seconds(spec: str) -> list[float]:
    times = []
    with tempfile.TemporaryDirectory() as out:
        for _ in range(COLD_RUNS):
            started = time.perf_counter()
            subprocess.run(
                [sys.executable, "-m", "codegen", "audit", spec, "-o", out],
                check=True,
                stdout=subprocess.DEVNULL,
            )
            times.append(time.perf_counter() - started)
    return times


def main(argv: list[str]) -> int:
    spec = argv[0] if argv else "spec/paper_motor.yaml"
    times = cold_audit_seconds(spec)
    median = statistics.median(times)
    verdict = "meets" if median < TARGET_DERIVE_AUDIT_S else "MISSES"
    print(
        f"bench: derive + audit, cold start, {COLD_RUNS} runs of `python -m codegen audit {spec}`"
    )
    print(f"bench:   min {min(times):.2f} s, median {median:.2f} s, max {max(times):.2f} s")
    print(f"bench:   {verdict} the {TARGET_DERIVE_AUDIT_S:.0f} s target")
    return 0 if median < TARGET_DERIVE_AUDIT_S else 1


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))

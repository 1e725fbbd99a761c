"""The robustness campaign: Latin-hypercube sampling of the spec's tolerances, the C
cores on Dask (a LocalCluster, or a scheduler's address), a byte-stable report."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import psutil
import pytest
from dask.distributed import LocalCluster

from bldc import cli
from codegen.errors import ExitCode
from codegen.spec_loader import load_spec
from sim.drive import Drive
from sim.robustness import argument_parser, build_campaign, latin_hypercube, main, perturbed

ROOT = Path(__file__).resolve().parents[1]
SPEC = ROOT / "spec" / "paper_motor.yaml"
TINY = ["--samples", "4", "--speeds", "2", "--methods", "none,improved_r", "--no-progress"]


def test_latin_hypercube_should_put_one_point_in_every_stratum() -> None:
    points = latin_hypercube(50, 4, seed=3)
    assert points.shape == (50, 4)
    for axis in range(4):
        assert sorted(np.floor(points[:, axis] * 50).astype(int)) == list(range(50))
    assert np.array_equal(points, latin_hypercube(50, 4, seed=3))


def test_campaign_should_sample_the_specs_declared_tolerances() -> None:
    spec = load_spec(SPEC)
    campaign = build_campaign(spec, 200, 3, ("improved_r",), "averaged", seed=1)
    assert campaign.declared
    resistance = campaign.samples[:, campaign.parameters.index("phase_resistance")]
    assert resistance.min() >= -0.10 and resistance.max() <= 0.40
    assert resistance.max() > 0.35  # the hot end is reached
    drive, phase = perturbed(Drive.from_spec(spec), campaign.parameters, campaign.samples[0])
    assert drive.resistance_ohm == pytest.approx(0.21 * (1 + resistance[0]))
    assert phase == 0.0  # the carrier phase is sampled for the switched plant only
    switched = build_campaign(spec, 20, 3, ("improved_r",), "switched", seed=1)
    assert switched.parameters[-1] == "carrier_phase"


@pytest.mark.heavy(seconds=6)
def test_robustness_should_run_on_a_local_cluster_and_on_a_given_scheduler(
    tmp_path: Path,
) -> None:
    assert main([str(SPEC), *TINY, "--workers", "1", "-o", str(tmp_path / "local")]) == 0
    text = (tmp_path / "local" / "ROBUSTNESS.md").read_text()
    assert "| improved_r | " in text and "ρ R" in text
    assert (tmp_path / "local" / "robustness.png").exists()
    with LocalCluster(
        n_workers=1, threads_per_worker=1, processes=True, dashboard_address=None
    ) as cluster:
        address = cluster.scheduler_address
        assert main([str(SPEC), *TINY, "--scheduler", address, "-o", str(tmp_path / "remote")]) == 0
    # Same seed, same samples: the same report wherever it ran.
    assert (tmp_path / "remote" / "ROBUSTNESS.md").read_bytes() == text.encode()


def test_robustness_should_refuse_bad_arguments_with_one_line(
    capsys: pytest.CaptureFixture[str],
) -> None:
    assert main([str(SPEC), "--methods", "improved,bogus"]) == 2
    assert "--methods" in capsys.readouterr().err
    with pytest.raises(SystemExit) as caught:  # argparse: usage, then the one error line
        main([str(SPEC), "--samples", "1"])
    assert caught.value.code == 2
    assert capsys.readouterr().err.splitlines()[-1].endswith("argument --samples: 1: at least 2")


@pytest.mark.parametrize("methods", ["improved,,none", "improved,", ",none", ""])
def test_an_empty_method_should_be_refused_not_dropped(
    capsys: pytest.CaptureFixture[str], methods: str
) -> None:
    """`--methods 'improved,,none'` dropped its empty item and ran the others: refused
    as a usage error in one line, before any work."""
    assert main([str(SPEC), "--methods", methods]) == ExitCode.USAGE
    err = capsys.readouterr().err.strip().splitlines()
    assert err == [
        f"error: --methods {methods!r}: an empty item (allowed: a comma-separated list of"
        " none, conventional, improved, improved_r)"
    ]


def test_a_method_given_twice_should_be_refused_not_run_twice(
    capsys: pytest.CaptureFixture[str],
) -> None:
    """`--methods improved,improved` ran every row twice (and its report listed it
    twice); it is a usage error now, naming the option and the method, before any work."""
    assert main([str(SPEC), "--methods", "improved,none,improved"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err == [
        "error: --methods 'improved,none,improved': improved given more than once"
        " (allowed: each of none, conventional, improved, improved_r once)"
    ]
    assert cli.main(["robustness", str(SPEC), "--methods", "none,none"]) == ExitCode.USAGE
    assert "--methods 'none,none': none given more than once" in capsys.readouterr().err


@pytest.mark.parametrize(
    ("samples", "speeds", "methods", "plant", "seed"),
    [
        (4, 2, ("improved_r", "none"), "switched", 7),
        (1000, 10, ("none", "conventional", "improved", "improved_r"), "averaged", 1),
    ],
)
def test_the_reports_command_should_reproduce_its_campaign(
    samples: int, speeds: int, methods: tuple[str, ...], plant: str, seed: int
) -> None:
    """The report's "Generated by" command left out --methods: rerun, it ran all four
    methods, not the report's. Parsed back, it builds the same campaign."""
    from sim.robustness_report import report_command

    spec = load_spec(SPEC)
    campaign = build_campaign(spec, samples, speeds, methods, plant, seed)
    command = report_command(spec, campaign)
    prefix = "python -m sim.robustness spec/paper_motor.yaml "
    assert command.startswith(prefix)
    args = argument_parser().parse_args(["spec/paper_motor.yaml", *command[len(prefix) :].split()])
    again = build_campaign(
        spec, args.samples, args.speeds, tuple(args.methods.split(",")), args.plant, args.seed
    )
    assert again.methods == campaign.methods
    assert (again.plant, again.seed, again.speeds_rpm) == (plant, seed, campaign.speeds_rpm)
    assert np.array_equal(again.samples, campaign.samples)
    # all four methods (the default, as the checked-in reports ran) are not spelled out
    assert ("--methods" in command) == (len(methods) < 4)


def test_a_parameter_that_does_not_vary_should_correlate_with_nothing() -> None:
    """Tolerances of [0, 0]: every sample the same value. Ranked by index, its ties had
    correlated +1.00 with a deviation that did not vary either, and every method's
    driver was R; ties now share their mean rank, and no driver is named."""
    from sim.robustness_report import _ranks, spearman

    constant = np.full(8, 0.5)
    assert spearman(constant, np.full(8, -12.0)) == 0.0
    assert spearman(constant, np.arange(8.0)) == 0.0
    assert list(_ranks(np.array([3.0, 1.0, 3.0, 2.0]))) == [2.5, 0.0, 2.5, 1.0]
    x = np.array([0.1, 0.4, 0.2, 0.3])
    assert spearman(x, 2 * x) == pytest.approx(1.0)
    assert spearman(x, -x) == pytest.approx(-1.0)


def _group(pgid: int) -> list[psutil.Process]:
    """The live processes of a process group (a zombie has ended)."""
    alive = []
    for process in psutil.process_iter():
        try:
            if os.getpgid(process.pid) == pgid and process.status() != psutil.STATUS_ZOMBIE:
                alive.append(process)
        except (ProcessLookupError, psutil.Error):
            continue
    return alive


def _worker_at(pid: int, stage: str) -> bool:
    """A worker process (a child of `pid`) is there: spawned ("starting": the cluster
    is starting), or with a compiled core mapped ("running": its first task runs)."""
    try:
        children = psutil.Process(pid).children(recursive=True)
    except psutil.Error:
        return False
    for child in children:
        try:
            if stage == "starting" and "--multiprocessing-fork" in child.cmdline():
                return True
            if stage == "running" and any("libbldc_" in m.path for m in child.memory_maps()):
                return True
        except psutil.Error:
            continue
    return False


@pytest.mark.heavy(seconds=10)
@pytest.mark.parametrize("stage", ["starting", "running"])
def test_ctrl_c_should_say_interrupted_in_one_line_and_leave_no_worker(
    tmp_path: Path, stage: str
) -> None:
    """A terminal's Ctrl-C reaches the whole process group: the Dask workers had
    stopped mid-task and printed 48-93 lines of tracebacks (CancelledError,
    KeyboardInterrupt, the nanny's errors) around the one line `interrupted`. The
    workers keep SIGINT blocked now; the command closes them, quietly, and exits 130,
    also when the Ctrl-C comes while the cluster starts (it is held until it is up)."""
    out = tmp_path / "out"
    out.mkdir()
    (out / "notes.txt").write_text("mine\n")
    argv = [sys.executable, "-m", "bldc", "robustness", str(SPEC), "-o", str(out)]
    # one worker, one method at one speed, one sample a task: it stops within a task
    argv += ["--samples", "2000", "--speeds", "1", "--methods", "improved", "--workers", "1"]
    argv += ["--chunk", "1"]
    process = subprocess.Popen(
        [*argv, "--no-progress"],
        cwd=ROOT,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        start_new_session=True,  # its own process group, as a terminal's job
        # SIGINT as a terminal leaves it (a background or xdist runner may ignore it)
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
    )
    try:
        deadline = time.monotonic() + 60
        while not _worker_at(process.pid, stage):
            assert process.poll() is None, process.communicate()
            assert time.monotonic() < deadline, f"no worker {stage} in 60 s"
            time.sleep(0.1)
        os.killpg(process.pid, signal.SIGINT)
        stdout, stderr = process.communicate(timeout=60)
    finally:
        if process.poll() is None:
            os.killpg(process.pid, signal.SIGKILL)
            process.communicate()
    assert (process.returncode, stderr, stdout) == (130, "interrupted\n", "")
    deadline = time.monotonic() + 10
    while _group(process.pid) and time.monotonic() < deadline:
        time.sleep(0.1)
    assert _group(process.pid) == []
    assert [p.name for p in out.iterdir()] == ["notes.txt"]  # the user's file alone
    assert (out / "notes.txt").read_text() == "mine\n"


def test_the_module_entry_should_end_a_ctrl_c_in_one_line(
    monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """`python -m sim.robustness`, what `make robustness` runs, had ended a Ctrl-C with
    Python's traceback (the CLI's `robustness` says `interrupted`, 130)."""
    import sim.robustness as robustness

    def interrupted(_: object) -> int:
        raise KeyboardInterrupt

    monkeypatch.setattr(robustness, "run", interrupted)
    assert main([str(SPEC)]) == 130
    assert capsys.readouterr().err == "interrupted\n"

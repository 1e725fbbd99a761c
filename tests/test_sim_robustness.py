"""The robustness campaign: Latin-hypercube sampling of the spec's tolerances, the C
cores on Dask (a LocalCluster, or a scheduler's address), a byte-stable report."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from dask.distributed import LocalCluster

from bldc import cli
from codegen.errors import ExitCode
from codegen.spec_loader import load_spec
from sim.drive import Drive
from sim.robustness import build_campaign, latin_hypercube, main, perturbed

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

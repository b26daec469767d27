"""LMB filter speed: one 100-scan run of the paper's scenario per association method.

Run the timings with::

    python -m pytest benchmarks/test_bench_tracking.py --benchmark-enable

(in the default suite each runs once as a smoke test). Targets: ``ShortChainGibbs(400, 25, tau_stall=5, tau_stale=10)`` at most 0.2 s per 100-scan run on the ``"paper"`` preset and at most 0.07 s on ``"vo"``
(``test_bench_vo_scenario``; Vo's example, the preset other LMB implementations are timed on),
``OriginalGibbs(10 000)`` under 5 s, all after warm-up; the numbers are in
``benchmarks/README.md``.
``Exact()`` (the exact LMB update by the oracle's component/frontier DP) and the short chains
with Rao-Blackwellised marginals (``marginals="rao-blackwell"``) are timed for reference.
The same two samplers are also timed on the ``"paper-var"`` preset with one call per group,
empty groups included (the reading that reproduces the paper's observation counts).
``extra_info`` holds the mean per-scan seconds of prediction, cost matrix, association and
update (from the last round), the observations (sweeps), row updates, mean tracks and
measurements per scan.
"""

import numpy as np
import pytest

from rankedassign.tracking import Exact, OriginalGibbs, ShortChainGibbs, run_scenario

METHODS = {
    "short-chain-400x25": (lambda: ShortChainGibbs(400, 25, tau_stall=5, tau_stale=10), 5),
    "short-chain-400x25-rao-blackwell": (
        lambda: ShortChainGibbs(400, 25, tau_stall=5, tau_stale=10, marginals="rao-blackwell"), 5
    ),
    "original-10000": (lambda: OriginalGibbs(10_000), 3),
    "exact": (Exact, 3),
}


@pytest.fixture(scope="module", autouse=True)
def _warm():
    # compile every kernel the filter and both samplers use
    for make, _ in METHODS.values():
        run_scenario("paper", make(), rng=0, n_scans=3)
        run_scenario("vo", make(), rng=0, n_scans=3)

def _record(benchmark, run):
    """Per-scan step times and the run's accounting, into the benchmark's ``extra_info``."""
    benchmark.extra_info.update(
        {f"per_scan_{k}_s": float(np.mean(v)) for k, v in run.timings.items()}
    )
    benchmark.extra_info.update(
        sweeps=int(run.sweeps.sum()),
        row_updates=int(run.row_updates.sum()),
        invocations=int(run.invocations.sum()),
        mean_tracks=float(run.n_tracks.mean()),
        mean_meas=float(run.n_meas.mean()),
        mean_meas_gated=float(run.n_meas_gated.mean()),
    )


@pytest.mark.parametrize("method", sorted(METHODS))
def test_bench_paper_scenario(benchmark, method):
    make, rounds = METHODS[method]
    benchmark.group = "LMB filter, paper scenario, 100 scans"
    run = benchmark.pedantic(
        run_scenario, args=("paper", make()), kwargs=dict(rng=0, n_scans=100), rounds=rounds,
        warmup_rounds=0,
    )
    assert run.n_scans == 100
    _record(benchmark, run)


@pytest.mark.parametrize("method", ["exact", "short-chain-400x25"])
def test_bench_vo_scenario(benchmark, method):
    make, rounds = METHODS[method]
    benchmark.group = "LMB filter, vo preset, 100 scans"
    run = benchmark.pedantic(
        run_scenario, args=("vo", make()), kwargs=dict(rng=0, n_scans=100), rounds=3 * rounds,
        warmup_rounds=1,
    )
    assert run.n_scans == 100
    _record(benchmark, run)


@pytest.mark.parametrize("method", ["original-10000", "short-chain-400x25"])
def test_bench_paper_var_per_group(benchmark, method):
    make, rounds = METHODS[method]
    benchmark.group = "LMB filter, paper-var preset, one call per group, 100 scans"
    run = benchmark.pedantic(
        run_scenario, args=("paper-var", make()),
        kwargs=dict(rng=0, n_scans=100, grouping=True, sample_empty_groups=True),
        rounds=rounds, warmup_rounds=0,
    )
    np.testing.assert_array_equal(run.invocations, run.n_groups)
    _record(benchmark, run)

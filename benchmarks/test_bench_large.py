"""Seconds per scan on large scenes (issue #43): the LMB filter and the clustered δ-GLMB filter.

Run the timings with::

    python -m pytest benchmarks/test_bench_large.py --benchmark-enable -m "slow or not slow"

(in the default suite the N = 100 and N = 1 000 cases run once each as smoke tests; N = 10 000
is marked ``slow``). Group "large scene, seconds per scan": ``make_scenario("large",
n_targets=N)`` (one target per 200 m x 200 m, Vo's noise and clutter density), the N targets as
the prior (``set_prior`` at their state one scan before the first, covariance
``diag(100, 25, 100, 25)``, LMB existence 0.99), one warm scan, then the timed second scan
(a fresh filter for every round, built and warmed outside the timing). Both filters with
``ShortChainGibbs(400, 25, tau_stall=5, tau_stale=10)``; the LMB filter with ``grouping=True``
(its spatial cluster path above ``SPATIAL_MIN_PAIRS``), ``max_tracks = 10 N + 100`` and the
MAP cardinality of every cluster as its extraction (``extraction="cluster-map"``); the
clustered δ-GLMB filter with its defaults (``h_upd = h_max = 1000`` per cluster). Each case
records in ``extra_info`` the seconds per target, the clusters and the largest cluster. The
numbers are in ``benchmarks/README.md``.
"""

import numpy as np
import pytest

from rankedassign.tracking import (
    ClusteredGLMBFilter,
    LMBFilter,
    ShortChainGibbs,
    make_scenario,
)

SIZES = [100, 1000, pytest.param(10_000, marks=pytest.mark.slow)]
FILTERS = ("lmb", "clustered-glmb")


def _assoc():
    return ShortChainGibbs(400, 25, tau_stall=5, tau_stale=10)


def _prior(sc):
    """Labels, means (the truth one scan before the first) and covariances of the targets."""
    n = sc.truth.states.shape[1]
    F = sc.model.motion.F
    means = np.linalg.solve(F, sc.truth.states[0].T).T
    labels = np.column_stack([np.zeros(n, np.int64), np.arange(1, n + 1)])
    covs = np.tile(np.diag([100.0, 25.0, 100.0, 25.0]), (n, 1, 1))
    return labels, means, covs


def _filter(kind, sc):
    labels, means, covs = _prior(sc)
    n = labels.shape[0]
    if kind == "lmb":
        f = LMBFilter(sc.model, _assoc(), grouping=True, max_tracks=10 * n + 100,
                      extraction="cluster-map")
        f.set_prior(labels, means, covs, existence=np.full(n, 0.99))
    else:
        f = ClusteredGLMBFilter(sc.model, _assoc())
        f.set_prior(labels, means, covs)
    f.step(sc.scans[0].z, rng=0)  # the warm scan: kernels loaded, clusters formed
    return f


@pytest.fixture(scope="module")
def scenarios():
    return {}


@pytest.mark.parametrize("n", SIZES)
@pytest.mark.parametrize("kind", FILTERS)
def test_bench_large_scan(benchmark, scenarios, kind, n):
    benchmark.group = "large scene, seconds per scan"
    if n not in scenarios:
        scenarios[n] = make_scenario("large", n_targets=n, n_scans=2, rng=0)
    sc = scenarios[n]
    z = sc.scans[1].z
    rec = benchmark.pedantic(lambda f: f.step(z, rng=1),
                             setup=lambda: ((_filter(kind, sc),), {}),
                             rounds=1 if benchmark.disabled else 3, iterations=1)
    assert rec.n_meas == z.shape[0]
    # the targets are found: at least 90 % of them reported after two scans
    assert len(rec.labels) >= 0.9 * n
    if benchmark.stats is not None and not benchmark.disabled:
        benchmark.extra_info["seconds_per_target"] = benchmark.stats.stats.min / n
    if kind == "clustered-glmb":
        benchmark.extra_info["n_clusters"] = int(rec.n_clusters)
        benchmark.extra_info["largest_cluster"] = int(rec.cluster_sizes.max())
    else:
        benchmark.extra_info["n_groups"] = int(rec.n_groups)

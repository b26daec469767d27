"""Oracle speed: enumeration, Murty (numba vs the SciPy-per-subproblem reference), exact DPs.

Run the timings with::

    python -m pytest benchmarks/test_bench_oracle.py --benchmark-enable

(in the default suite each runs once as a smoke test). Benchmarks sharing a group (for
example ``murty 20x90 k=1000``) differ only in the method, so the numba / SciPy ratio reads
off one table. Problems: the paper's ``4 x 24`` random matrix (``synthetic.random(rng=0)``),
a tracking-sized ``P = 20, M = 50`` matrix (``synthetic.random(R=20, M=50, rng=0)``), for
the subset DP ``P = 16, M = 100``, and for the frontier DP two gated problems beyond the subset
DP's reach: a synthetic one (:func:`gated_problem`, 22 rows and 57 measurements in one connected
component) and the largest problem the LMB filter meets on the paper's scenario (exact
association, ``rng=0``, first 70 scans; a component of about 30 rows and 60 measurements).
"""

import math

import numpy as np
import pytest

from oracle import enumerate_assignments, log_normalizer, marginals, murty
from rankedassign import AssignmentProblem, synthetic

PROBLEMS = {
    "4x24": lambda: synthetic.random(rng=0),
    "20x90": lambda: synthetic.random(R=20, M=50, rng=0),
}


@pytest.fixture(scope="module", autouse=True)
def _compiled():
    """Compile (or load) every oracle kernel once, outside the timings."""
    tiny = synthetic.random(R=2, M=3, rng=0)
    enumerate_assignments(tiny)
    murty(tiny, 5)
    log_normalizer(tiny)
    marginals(tiny)


def test_bench_enumerate_4x24(benchmark):
    problem = PROBLEMS["4x24"]()
    benchmark.group = "enumerate 4x24"
    r = benchmark(enumerate_assignments, problem)
    assert len(r.costs) == 76_848


@pytest.mark.parametrize("method", ["numba", "scipy"])
@pytest.mark.parametrize("k", [100, 1000])
@pytest.mark.parametrize("size", sorted(PROBLEMS))
def test_bench_murty(benchmark, size, k, method):
    problem = PROBLEMS[size]()
    benchmark.group = f"murty {size} k={k}"
    benchmark.extra_info.update(P=problem.n_rows, M=problem.n_meas, k=k, method=method)
    r = benchmark(murty, problem, k, method=method)
    assert len(r.costs) == k


def test_bench_log_normalizer_16x100(benchmark):
    problem = synthetic.random(R=16, M=100, rng=0)
    benchmark.group = "subset DP 16x100"
    z = benchmark(log_normalizer, problem)
    assert math.isfinite(z)


def test_bench_marginals_16x100(benchmark):
    problem = synthetic.random(R=16, M=100, rng=0)
    benchmark.group = "subset DP 16x100"
    m = benchmark(marginals, problem)
    assert m.shape == (16, 102)


def gated_problem(rng, n_rows=22, n_meas=57, n_wide=4, side=2000.0, gate=300.0, wide_gate=900.0):
    """A tracking-like gated problem: rows (predicted tracks) and measurements at random 2-D
    positions in a ``side`` square, a third of the measurements near a track; an entry is
    finite iff within ``gate`` (``wide_gate`` for the first ``n_wide`` rows, the births), with a
    Gaussian likelihood (10 m, births 300 m) over a uniform clutter density of 50 per square.
    ``rng=1`` gives one connected component of 22 rows and 57 measurements, ~3 rows per
    measurement."""
    rows = rng.uniform(0, side, (n_rows, 2))
    meas = np.concatenate([rows[: n_meas // 3] + rng.normal(0, 10, (n_meas // 3, 2)),
                           rng.uniform(0, side, (n_meas - n_meas // 3, 2))])
    d = np.linalg.norm(rows[:, None] - meas[None], axis=2)
    wide = (np.arange(n_rows) < n_wide)[:, None]
    sigma = np.where(wide, 300.0, 10.0)
    log_eta = (np.log(0.9 * 0.98) - d**2 / (2 * sigma**2) - np.log(2 * np.pi * sigma**2)
               - np.log(50 / side**2))
    log_eta[d >= np.where(wide, wide_gate, gate)] = -np.inf
    return AssignmentProblem.from_log_eta(log_eta, np.full(n_rows, np.log(0.9 * 0.02)),
                                          np.full(n_rows, np.log(0.1)))


@pytest.fixture(scope="module")
def tracking_problem():
    """The scan problem of the paper's scenario with the largest connected component."""
    from rankedassign.tracking import Exact, run_scenario

    seen = []

    class Recording(Exact):
        def __call__(self, problem, rng):
            seen.append(problem)
            return super().__call__(problem, rng)

    run_scenario("paper", Recording(), rng=0, n_scans=70)

    def largest_component(p):
        from scipy.sparse.csgraph import connected_components

        fin = np.isfinite(p.compact_cost[:, : p.n_meas])
        _, lab = connected_components(np.block([[np.zeros((p.n_rows, p.n_rows)), fin],
                                                [fin.T, np.zeros((p.n_meas, p.n_meas))]]),
                                      directed=False)
        return int(np.bincount(lab[: p.n_rows]).max())

    return max(seen, key=largest_component)


@pytest.mark.parametrize("fn", [log_normalizer, marginals])
def test_bench_frontier_gated_22x57(benchmark, fn):
    problem = gated_problem(np.random.default_rng(1))
    benchmark.group = "frontier DP gated 22x57"
    benchmark.extra_info.update(P=problem.n_rows, M=problem.n_meas)
    out = benchmark(fn, problem)
    assert np.all(np.isfinite(out))


@pytest.mark.parametrize("fn", [log_normalizer, marginals])
def test_bench_frontier_tracking_scan(benchmark, fn, tracking_problem):
    benchmark.group = "frontier DP paper-scenario scan"
    benchmark.extra_info.update(P=tracking_problem.n_rows, M=tracking_problem.n_meas)
    out = benchmark(fn, tracking_problem)
    assert np.all(np.isfinite(out))

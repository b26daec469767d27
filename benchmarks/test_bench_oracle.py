"""Oracle speed: enumeration, Murty (numba vs the SciPy-per-subproblem reference), subset DP.

Run the timings with::

    python -m pytest benchmarks/test_bench_oracle.py --benchmark-enable

(in the default suite each runs once as a smoke test). Benchmarks sharing a group (for
example ``murty 20x90 k=1000``) differ only in the method, so the numba / SciPy ratio reads
off one table. Problems: the paper's ``4 x 24`` random matrix (``synthetic.random(rng=0)``),
a tracking-sized ``P = 20, M = 50`` matrix (``synthetic.random(R=20, M=50, rng=0)``) and, for
the DP, ``P = 16, M = 100``.
"""

import math

import pytest

from oracle import enumerate_assignments, log_normalizer, marginals, murty
from rankedassign import synthetic

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

"""How the cost of a sweep grows with the number of measurements M and of rows P.

Run the timings with::

    python -m pytest benchmarks/test_bench_sweep_scaling.py --benchmark-enable

A row update draws either by the direct sum over the row's ``M + 2`` candidates (``O(M)``) or,
when :func:`rankedassign._sampling.uses_prefix_sums` says so (``M > 32`` and ``M > 2 P``), from
per-row prefix sums corrected for the measurements the other rows hold (``O(P + log M)``).
``extra_info["sweeps"]`` holds the sweeps per call (one long chain, de-duplication included),
so ``mean / sweeps`` is the time per sweep; the problems are the paper's random family
(``synthetic.random(R=P, M=M)``).
"""

import pytest

from rankedassign import sample_original, synthetic, warmup

# (P, M) -> sweeps per call (a call of ~10-50 ms)
BY_M = {(50, 50): 2_000, (50, 500): 2_000, (50, 5_000): 1_000, (50, 10_000): 500}
BY_P = {(10, 1_000): 5_000, (50, 1_000): 2_000, (200, 1_000): 200}


@pytest.fixture(scope="module", autouse=True)
def _compiled():
    warmup()


def _run(benchmark, P, M, n):
    problem = synthetic.random(R=P, M=M, rng=0)
    res = benchmark.pedantic(sample_original, args=(problem, n), kwargs=dict(rng=1), rounds=3,
                             warmup_rounds=1)
    assert res.n_observations == n
    benchmark.extra_info.update(sweeps=n, P=P, M=M)


@pytest.mark.parametrize("P, M", sorted(BY_M))
def test_bench_sweep_against_M(benchmark, P, M):
    benchmark.group = "sweep cost against M (P = 50)"
    _run(benchmark, P, M, BY_M[P, M])


@pytest.mark.parametrize("P, M", sorted(BY_P))
def test_bench_sweep_against_P(benchmark, P, M):
    benchmark.group = "sweep cost against P (M = 1000)"
    _run(benchmark, P, M, BY_P[P, M])

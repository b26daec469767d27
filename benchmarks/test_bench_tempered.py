"""Per-step cost of the tempered Gibbs sampler (Zanella & Roberts) against M and against P.

Run the timings with::

    python -m pytest benchmarks/test_bench_tempered.py --benchmark-enable

``extra_info["steps"]`` is the moves per call, so ``min / steps`` is the time per move (one row
update). The problems are the paper's random family (``synthetic.random(R=P, M=M)``), as in the
sweep-scaling benchmark. A move keeps every row's sums of its available weights by updating
them with the two measurements it releases and takes (``O(P)``) and draws the new value by a
direct sum (``O(M)``), so the time per move should grow linearly in ``P + M``, not in ``P M``.
"""

import pytest

from rankedassign import sample_tempered
from rankedassign.single import synthetic

MS = (50, 500, 5_000)
PS = (10, 50, 200)


def _run(benchmark, P, M):
    problem = synthetic.random(R=P, M=M, rng=0)
    n = int(min(200_000, max(200, 2e7 // (P + M) // 4)))
    sample_tempered(problem, 10, beta=0.5, rng=0)
    res = benchmark.pedantic(sample_tempered, args=(problem, n), kwargs=dict(beta=0.5, rng=1),
                             rounds=3, warmup_rounds=1)
    assert res.n_steps == n
    benchmark.extra_info.update(steps=n, P=P, M=M, n_unique=len(res.counts))


@pytest.mark.parametrize("M", MS)
def test_bench_tempered_step_against_M(benchmark, M):
    benchmark.group = "tempered Gibbs move against M (P = 50)"
    _run(benchmark, 50, M)


@pytest.mark.parametrize("P", PS)
def test_bench_tempered_step_against_P(benchmark, P):
    benchmark.group = "tempered Gibbs move against P (M = 1000)"
    _run(benchmark, P, 1_000)

"""Multi-sensor oracle speed: enumeration at the canonical sizes, the row DP, the surrogate.

Run the timings with::

    python -m pytest benchmarks/test_bench_multisensor_oracle.py --benchmark-enable

(in the default suite each runs once as a smoke test). Problems: the coupled random family
``multisensor.synthetic.random_coupled(P, M, rng=0)`` at sizes A ``P = 4, M = (4, 4)``,
B ``P = 2, M = (16, 16)``, C ``P = 3, M = (4, 4, 4)``, and beyond enumeration
``P = 8, M = (8, 8)`` (``|Gamma| = 3.6e12``, 16 bits) for the row DP; the separable random
family ``P = 16, M = (20, 20)`` for the surrogate normaliser.
"""

import pytest

import oracle
from oracle.multisensor.dp import surrogate_log_normalizer
from rankedassign.multisensor import synthetic

SIZES = {"A": (4, (4, 4)), "B": (2, (16, 16)), "C": (3, (4, 4, 4))}
COUNTS = {"A": 67_744, "B": 75_108, "C": 417_176}


@pytest.fixture(scope="module", autouse=True)
def _compiled():
    """Compile (or load) every multi-sensor oracle kernel once, outside the timings."""
    tiny = synthetic.random_coupled(2, (2, 2), rng=0)
    oracle.enumerate_assignments(tiny)
    oracle.log_normalizer(tiny)
    oracle.marginals(tiny)
    surrogate_log_normalizer(tiny)


@pytest.mark.parametrize("size", sorted(SIZES))
def test_bench_ms_enumerate(benchmark, size):
    P, M = SIZES[size]
    problem = synthetic.random_coupled(P, M, rng=0)
    benchmark.group = "multi-sensor enumerate"
    benchmark.extra_info.update(P=P, M=list(M))
    r = benchmark(oracle.enumerate_assignments, problem)
    assert len(r.costs) == COUNTS[size]


@pytest.mark.parametrize("what", ["log_normalizer", "marginals"])
def test_bench_ms_row_dp_8x8x8(benchmark, what):
    problem = synthetic.random_coupled(8, (8, 8), rng=0)
    benchmark.group = "multi-sensor row DP P=8 M=(8,8)"
    benchmark.extra_info.update(P=8, M=[8, 8], function=what)
    benchmark(getattr(oracle, what), problem)


def test_bench_ms_surrogate_16x20x20(benchmark):
    problem = synthetic.random(16, (20, 20), rng=0)
    benchmark.group = "multi-sensor surrogate P=16 M=(20,20)"
    benchmark(surrogate_log_normalizer, problem)

"""The herded sweep against the Gibbs sweep, in one group per problem.

Run the timings with::

    python -m pytest benchmarks/test_bench_herding.py --benchmark-enable

``extra_info["sweeps"]`` is the sweeps per call, so ``min / sweeps`` is the time per sweep;
``new_key_share`` is the fraction of row updates that met a key for the first time (they must
build the key's weights), ``fallbacks`` the row updates that drew by Gibbs because the table was
full. Problems: the paper's ``4 x 24`` random matrix and the ``P = 50, M = 5 000`` matrix of the
sweep-scaling benchmark, where the Gibbs sweep draws from prefix sums in ``O(P + log M)`` per
row and the herded one, which needs every row's whole conditional, in ``O(M)``.
"""

import pytest

from rankedassign import sample_herded, sample_original, warmup
from rankedassign.single import synthetic

CASES = {
    "4x24": (lambda: synthetic.random(rng=0), 200_000),
    "50x5000": (lambda: synthetic.random(R=50, M=5_000, rng=0), 100),
}
DRAWS = ("gibbs", "herded-shared", "herded-full")


@pytest.fixture(scope="module", autouse=True)
def _compiled():
    warmup()
    sample_herded(synthetic.random(rng=0), 3, keys="full")


@pytest.mark.parametrize("draw", DRAWS)
@pytest.mark.parametrize("size", sorted(CASES))
def test_bench_herded_sweep(benchmark, size, draw):
    make, n = CASES[size]
    problem = make()
    benchmark.group = f"herded vs Gibbs sweep {size}"
    if draw == "gibbs":
        fn, kw = sample_original, dict(rng=1)
    else:
        fn, kw = sample_herded, dict(rng=1, keys=draw.split("-")[1])
    res = benchmark.pedantic(fn, args=(problem, n), kwargs=kw, rounds=5, warmup_rounds=1)
    assert res.n_observations == n
    benchmark.extra_info.update(
        sweeps=n, P=problem.n_rows, M=problem.n_meas, n_unique=len(res),
        new_key_share=res.n_keys / (n * problem.n_rows), fallbacks=res.n_fallbacks,
    )


MS_METHODS = ("exact", "mm", "componentwise")


@pytest.mark.parametrize("draw", ("gibbs", "herded-shared"))
@pytest.mark.parametrize("method", MS_METHODS)
def test_bench_multisensor_herded_sweep(benchmark, method, draw):
    """The multi-sensor herded sweep against the Gibbs sweep of the same method: three sensors,
    six objects, four measurements each, 20 000 sweeps in one chain."""
    from rankedassign.multisensor import synthetic as ms_synthetic

    problem = ms_synthetic.random(6, (4, 4, 4), rng=0)
    n = 20_000
    benchmark.group = f"multi-sensor herded vs Gibbs sweep 6x(4,4,4) {method}"
    if draw == "gibbs":
        fn, kw = sample_original, dict(rng=1, method=method)
    else:
        fn, kw = sample_herded, dict(rng=1, method=method, keys="shared")
    res = benchmark.pedantic(fn, args=(problem, n), kwargs=kw, rounds=5, warmup_rounds=1)
    assert res.n_observations == n
    benchmark.extra_info.update(sweeps=n, method=method)

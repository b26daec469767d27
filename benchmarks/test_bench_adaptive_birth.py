"""Adaptive-birth sampler speed: ns per sweep against V and M_v, numba vs the reference.

Run the timings with::

    python -m pytest benchmarks/test_bench_adaptive_birth.py --benchmark-enable

(in the default suite they run once each as smoke tests). ``extra_info["sweeps"]`` holds the
sweeps per call, so ``mean / sweeps`` is the time per sweep (one sweep = ``V`` sensor updates
in the ratio form, each a Cholesky factor of the 4 x 4 information matrix and ``M_v`` quadratic
forms). Problems: the diagonal family of the adaptive-birth study
(:func:`rankedassign.adaptive_birth.synthetic.make_family`, ``rng=0``).
"""

import pytest

from rankedassign import reference, sample_original
from rankedassign.adaptive_birth.synthetic import make_family

SIZES = [(2, 10), (4, 10), (8, 4), (8, 10), (4, 30)]
SWEEPS = {"numba": 20_000, "python": 100}


@pytest.mark.parametrize("V, M", SIZES, ids=[f"V{V}-M{M}" for V, M in SIZES])
@pytest.mark.parametrize("backend", ["numba", "python"])
def test_bench_adaptive_birth_original(benchmark, backend, V, M):
    problem = make_family("diagonal", V, M, rng=0)
    n = SWEEPS[backend]
    fn = sample_original if backend == "numba" else reference.sample_original
    fn(problem, 2, rng=0)                                   # compile / warm up
    benchmark.group = f"adaptive birth V={V} M={M}"
    res = benchmark.pedantic(fn, args=(problem, n), kwargs=dict(rng=1), rounds=3,
                             warmup_rounds=0)
    assert res.n_observations == n
    benchmark.extra_info.update(sweeps=n, V=V, M=M, backend=backend, n_unique=len(res))

"""Multi-sensor sampler speed: ns per sweep of each method, numba kernel vs pure-Python
reference, and how the exact and MM methods scale with the number of sensors.

Run the timings with::

    python -m pytest benchmarks/test_bench_multisensor.py --benchmark-enable

(in the default suite they run once each as smoke tests). ``extra_info["sweeps"]`` holds the
sweeps per call, so ``mean / sweeps`` is the time per sweep. The numba side is the sweep
kernel alone (:func:`rankedassign.multisensor._kernels.run_sweeps`, one chain, no unique
set); the reference side is :func:`rankedassign.multisensor.reference.sweep` in a loop.
``test_bench_public_original`` times the public original sampler (driver, unique set and
packaging included) with both backends on family A.

Problems (spec §6.5 random-coupled family): A ``P = 4, M = (4, 4)``, B ``P = 2, M = (16,
16)``, C ``P = 3, M = (4, 4, 4)``, a tracking-sized ``P = 20, V = 3, M_v = 20``, and for the
scaling table ``P = 3, M_v = 10``, ``V = 2..4`` (more measurements than rows, so a
row's available sets stay large in the chain's steady state, as in clutter-rich scans).
"""

import numpy as np
import pytest

from rankedassign import sample_original
from rankedassign.engine._kernels import zobrist_keys
from rankedassign.engine.rng import SplitMix64
from rankedassign.multisensor import _kernels as K
from rankedassign.multisensor import reference as R
from rankedassign.multisensor import synthetic
from rankedassign.multisensor.prepare import METHODS, prepare_data, start_state

SIZES = {
    "A": (4, (4, 4)),
    "B": (2, (16, 16)),
    "C": (3, (4, 4, 4)),
    "tracking": (20, (20, 20, 20)),
}
SCALING = {f"V={V}": (3, (10,) * V) for V in (2, 3, 4)}


class _Arrays:
    """The array attributes of a multi-sensor problem (random-coupled family, spec §6.5)."""

    def __init__(self, P, M, seed=0):
        rng = np.random.default_rng(seed)
        V = len(M)
        r_ps = rng.uniform(1e-3, 1, P) * rng.uniform(1e-3, 1, P)
        self.n_rows, self.n_sensors, self.n_meas = P, V, tuple(M)
        self.log_s = np.log(r_ps)
        self.log_eta_dead = np.log1p(-r_ps)
        self.log_theta = []
        la = self.log_s.reshape((P,) + (1,) * V)
        for v, m in enumerate(M):
            pd = rng.uniform(1e-3, 1, (P, 1))
            t = np.log(np.concatenate([1 - pd, pd * rng.uniform(0, 50, (P, m))], axis=1))
            self.log_theta.append(t)
            shape = [P] + [1] * V
            shape[v + 1] = m + 1
            la = la + t.reshape(shape)
        ndet = sum(np.indices(la.shape[1:])[v] > 0 for v in range(V))
        self.log_eta_alive = la + np.where(ndet >= 2, rng.normal(size=la.shape), 0.0)


def _candidates(P, M, method):
    """Candidate weights looked at per sweep (sizes the calls to ~10-50 ms)."""
    if method == "exact":
        return P * (1 + int(np.prod([m + 1 for m in M])))
    if method == "componentwise":
        return P * sum(m + 1 for m in M)
    return P * (len(M) + 2 * sum(M))


def _setup(P, M, method):
    """Problem, prepared data, a start state after 200 burn-in sweeps, Zobrist keys.

    Both backends time sweeps from the same burned-in state, so the first sweeps from the
    all-missed start (every measurement free: the largest candidate sets) do not weigh more
    in the reference's few timed sweeps than in the kernel's many.
    """
    problem = _Arrays(P, M)
    data = prepare_data(problem, method, "systematic", 1)
    x0 = start_state(problem, "all_missed", method)
    zk = zobrist_keys(len(x0), max(M) + 2, np.uint64(1))
    x0, _ = K.run_sweeps(data, zk, x0, np.uint64(99), 200)
    return problem, data, x0, zk


def _numba(data, zk, x0, n):
    return K.run_sweeps(data, zk, x0, np.uint64(1), n)


def _python(rd, x0, n):
    x = x0.tolist()
    occ = R.new_work(rd, x)
    g = SplitMix64(1)
    for _ in range(n):
        R.sweep(rd, occ, x, g)
    return x


def _bench(benchmark, P, M, method, backend, group, budget):
    problem, data, x0, zk = _setup(P, M, method)
    cand = _candidates(P, M, method)
    n = max(1, budget // cand)
    benchmark.group = group
    if backend == "numba":
        _numba(data, zk, x0, 1)  # compiled (or loaded from the cache) before timing
        benchmark.pedantic(_numba, args=(data, zk, x0, n), rounds=5, warmup_rounds=1)
    else:
        rd = R.RefData(data)  # the reference's inputs as lists, built once per call, untimed
        benchmark.pedantic(_python, args=(rd, x0, n), rounds=3, warmup_rounds=0)
    benchmark.extra_info.update(sweeps=n, P=P, M=list(M), method=method, backend=backend,
                                candidates_per_sweep=cand)


@pytest.mark.parametrize("size", sorted(SIZES))
@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("backend", ["numba", "python"])
def test_bench_sweep(benchmark, backend, method, size):
    P, M = SIZES[size]
    budget = 20_000_000 if backend == "numba" else 20_000
    _bench(benchmark, P, M, method, backend, f"multisensor sweep {size} {method}", budget)


@pytest.mark.parametrize("V", sorted(SCALING))
@pytest.mark.parametrize("method", ["exact", "mm"])
def test_bench_scaling(benchmark, method, V):
    P, M = SCALING[V]
    _bench(benchmark, P, M, method, "numba", f"multisensor scaling {method}", 20_000_000)


@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("backend", ["numba", "python"])
def test_bench_public_original(benchmark, backend, method):
    """The public original sampler (chain driver and unique set included) on family A."""
    problem = synthetic.random_coupled(P=4, M=(4, 4), rng=0)
    n = 100_000 if backend == "numba" else 300
    sample_original(problem, 2, method=method, rng=0)  # compiled before timing
    benchmark.group = f"multisensor original sampler A {method}"
    res = benchmark.pedantic(sample_original, args=(problem, n),
                             kwargs=dict(method=method, rng=1, backend=backend), rounds=3,
                             warmup_rounds=0)
    benchmark.extra_info.update(sweeps=n, P=4, M=[4, 4], method=method, backend=backend,
                                n_unique=len(res))

"""Sampler speed: ns per sweep, numba vs the pure-Python reference, sequential vs parallel.

Run the timings with::

    python -m pytest benchmarks/test_bench_samplers.py --benchmark-enable

(in the default suite they run once each as smoke tests). ``extra_info["sweeps"]`` holds the
sweeps (observations) per call, so ``mean / sweeps`` is the time per sweep, and
``extra_info["simulated_sweeps"]`` adds the speculative sweeps a parallel run discarded.

Problems: the paper's ``4 x 24`` random matrix (``synthetic.random(rng=0)``) and a
``P = 30, M = 100`` random matrix (``synthetic.random(R=30, M=100, rng=0)``).
"""

import pytest

from rankedassign import reference, sample_original, sample_short_chains, warmup
from rankedassign.single import synthetic

PROBLEMS = {
    "4x24": lambda: synthetic.random(rng=0),
    "30x160": lambda: synthetic.random(R=30, M=100, rng=0),
}
# sweeps per call, sized so a call takes ~10-100 ms
ORIGINAL_SWEEPS = {
    ("numba", "4x24"): 200_000,
    ("numba", "30x160"): 5_000,
    ("python", "4x24"): 500,
    ("python", "30x160"): 10,
}


@pytest.fixture(scope="module", autouse=True)
def _compiled():
    warmup()


def _info(benchmark, res, problem, **extra):
    benchmark.extra_info.update(
        sweeps=res.n_observations,
        simulated_sweeps=res.n_observations + res.n_speculative_discarded,
        P=problem.n_rows,
        M=problem.n_meas,
        n_unique=len(res),
        **extra,
    )


@pytest.mark.parametrize("size", sorted(PROBLEMS))
@pytest.mark.parametrize("backend", ["numba", "python"])
def test_bench_original(benchmark, backend, size):
    problem = PROBLEMS[size]()
    n = ORIGINAL_SWEEPS[backend, size]
    fn = sample_original if backend == "numba" else reference.sample_original
    benchmark.group = f"original sampler {size}"
    res = benchmark.pedantic(fn, args=(problem, n), kwargs=dict(rng=1), rounds=5,
                             warmup_rounds=1)
    assert res.n_observations == n
    _info(benchmark, res, problem, backend=backend)


@pytest.mark.parametrize("size", sorted(PROBLEMS))
@pytest.mark.parametrize("workers", [1, 2])
def test_bench_short_chains_paper_settings(benchmark, workers, size):
    """10 000 chains x 25 sweeps, tau_stall = 5, tau_stale = 25 (the paper's settings)."""
    problem = PROBLEMS[size]()
    benchmark.group = f"short chains, paper settings {size}"
    res = benchmark.pedantic(
        sample_short_chains, args=(problem, 10_000, 25),
        kwargs=dict(tau_stall=5, tau_stale=25, rng=1, workers=workers), rounds=3,
        warmup_rounds=1,
    )
    _info(benchmark, res, problem, workers=workers, stop_reason=res.stop_reason)


@pytest.mark.parametrize("size", sorted(PROBLEMS))
@pytest.mark.parametrize("workers", [1, 2])
def test_bench_short_chains_full_budget(benchmark, workers, size):
    """2 000 chains x 25 sweeps without termination: the parallel speed-up on pure sweeps."""
    problem = PROBLEMS[size]()
    benchmark.group = f"short chains, full budget {size}"
    res = benchmark.pedantic(
        sample_short_chains, args=(problem, 2_000, 25), kwargs=dict(rng=1, workers=workers),
        rounds=3, warmup_rounds=1,
    )
    assert res.n_observations == 50_000
    _info(benchmark, res, problem, workers=workers)


@pytest.fixture
def busy_core():
    """A process spinning on the machine's last core for the duration of the benchmark."""
    import multiprocessing as mp
    import os

    cpus = sorted(os.sched_getaffinity(0))
    if len(cpus) < 2:
        pytest.skip("needs two cores to keep one busy")
    ctx = mp.get_context("spawn")
    proc = ctx.Process(target=_spin, args=(cpus[-1],), daemon=True)
    proc.start()
    yield cpus[-1]
    proc.terminate()
    proc.join()


def _spin(cpu):
    import os
    import time

    os.sched_setaffinity(0, {cpu})
    end = time.monotonic() + 600  # bounded even if the parent dies
    while time.monotonic() < end:
        pass


@pytest.mark.parametrize("workers", [1, 2])
def test_bench_short_chains_with_a_busy_core(benchmark, busy_core, workers):
    """The paper's settings on 30 x 160 while another process keeps one core busy: two workers
    must not be slower than one (idle OpenMP threads sleep, chains are handed out in small
    chunks)."""
    problem = PROBLEMS["30x160"]()
    benchmark.group = "short chains, paper settings 30x160, one core busy"
    res = benchmark.pedantic(
        sample_short_chains, args=(problem, 10_000, 25),
        kwargs=dict(tau_stall=5, tau_stale=25, rng=1, workers=workers), rounds=3,
        warmup_rounds=1,
    )
    _info(benchmark, res, problem, workers=workers, stop_reason=res.stop_reason)

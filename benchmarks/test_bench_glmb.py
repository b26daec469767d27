"""δ-GLMB filter speed against the LMB filter, and its memory over a long run.

Run the timings with::

    python -m pytest benchmarks/test_bench_glmb.py --benchmark-enable

(in the default suite each runs once, on a few scans, as a smoke test). Group
"GLMB vs LMB, vo preset, 100 scans": one 100-scan run of Vo's example on the same measurements
(``run_scenario(..., rng=0)``) by the LMB filter and by the δ-GLMB filter, both with
``ShortChainGibbs(400, 25, tau_stall=5, tau_stale=10)``; the GLMB filter also with the long chain
(``OriginalGibbs(10 000)``, ``T_h − 1`` sweeps per component) and Murty's ``k = min(1000, T_h)``
best (one compiled loop over the components); the LMB filter also with Murty(1000) and the
exact marginals. Target of issue #26: GLMB with
short chains at most 20× the LMB filter's time. ``test_bench_glmb_memory`` runs 1 000 scans and
records the filter's state size (:meth:`GLMBFilter.nbytes`) per scan in ``extra_info``: it
must not grow once the caps bind. The numbers are in ``benchmarks/README.md``.
"""

import numpy as np
import pytest

from rankedassign.tracking import (
    Exact,
    GLMBFilter,
    Murty,
    OriginalGibbs,
    ShortChainGibbs,
    make_scenario,
    run_scenario,
)

METHODS = {
    "lmb-short-chain": ("lmb", lambda: ShortChainGibbs(400, 25, tau_stall=5, tau_stale=10)),
    "glmb-short-chain": ("glmb", lambda: ShortChainGibbs(400, 25, tau_stall=5, tau_stale=10)),
    "glmb-original-10000": ("glmb", lambda: OriginalGibbs(10_000)),
    # the compiled per-component loop of the oracle's Murty search, k = min(1000, T_h)
    "glmb-murty-1000": ("glmb", lambda: Murty(1000)),
    "lmb-murty-1000": ("lmb", lambda: Murty(1000)),
    "lmb-exact": ("lmb", lambda: Exact()),
}


def _scans(benchmark, n):
    """``n`` scans when timing, 3 in the smoke run of the default suite."""
    return n if not benchmark.disabled else 3


@pytest.fixture(scope="module", autouse=True)
def _warm():
    for filt, make in METHODS.values():
        run_scenario("vo", make(), rng=0, n_scans=3, filter=filt)


@pytest.mark.parametrize("method", sorted(METHODS))
def test_bench_glmb_vs_lmb(benchmark, method):
    filt, make = METHODS[method]
    benchmark.group = "GLMB vs LMB, vo preset, 100 scans"
    n = _scans(benchmark, 100)
    run = benchmark.pedantic(
        run_scenario, args=("vo", make()), kwargs=dict(rng=0, n_scans=n, filter=filt),
        rounds=5, warmup_rounds=1,
    )
    assert run.n_scans == n
    benchmark.extra_info.update(
        {f"per_scan_{k}_s": float(np.mean(v)) for k, v in run.timings.items()})
    benchmark.extra_info.update(sweeps=int(run.sweeps.sum()),
                                n_unique=int(run.n_unique.sum()),
                                mean_tracks=float(run.n_tracks.mean()))


def test_bench_glmb_memory(benchmark):
    benchmark.group = "GLMB memory, vo preset, 1 000 scans"
    n = _scans(benchmark, 1000)
    sc = make_scenario("vo", rng=0, n_scans=n)

    def run():
        # the same run without the whole histories (the default) and with them (same
        # numbers, tested)
        fs = [GLMBFilter(sc.model, ShortChainGibbs(400, 25, tau_stall=5, tau_stale=10),
                         keep_histories=keep) for keep in (None, True)]
        sizes, comps, tracks = [], [], []
        for k, s in enumerate(sc.scans):
            for f in fs:
                f.step(s.z, rng=k)
            sizes.append([f.nbytes() for f in fs])
            comps.append(fs[0].n_components)
            tracks.append(fs[0].n_tracks)
        return np.array(sizes), np.array(comps), np.array(tracks), fs

    sizes, comps, tracks, fs = benchmark.pedantic(run, rounds=1, warmup_rounds=0)
    assert comps.max() <= fs[0].h_max
    half = max(n // 2, 1)
    for j, name in enumerate(("without_histories", "with_histories")):
        benchmark.extra_info[f"max_bytes_{name}_per_100_scans"] = [
            int(sizes[i:i + 100, j].max()) for i in range(0, n, 100)]
        benchmark.extra_info[f"max_bytes_{name}_halves"] = [int(sizes[:half, j].max()),
                                                           int(sizes[half:, j].max())]
    benchmark.extra_info.update(
        max_components=int(comps.max()), max_tracks=int(tracks.max()),
        history_nodes=int(fs[1]._node_parent.size),
    )

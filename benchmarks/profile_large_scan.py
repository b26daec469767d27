"""Profile or time one scan of the LMB or δ-GLMB filters on a large scene (issue #43).

N known targets at constant density (one per 200 m x 200 m square) start as the filter's prior
(``set_prior``); one scan of measurements (Vo's noise and clutter density, position sensor) is
filtered under cProfile, after a warm-up scan at N = 10 that loads the compiled kernels::

    python benchmarks/profile_large_scan.py lmb 1000
    python benchmarks/profile_large_scan.py glmb 300 --top 12

The LMB filter runs with ``grouping=True`` (it then takes the spatial cluster path above
``SPATIAL_MIN_PAIRS``) and ``max_tracks`` large enough for every target.

``--second`` filters the scene of ``benchmarks/test_bench_large.py`` instead (the prior one
scan before the first, that filter's settings, ``clustered-glmb`` too) and profiles its second
scan, after the first on the same filter; with ``--cpu R`` it profiles nothing and prints the
seconds of CPU (:func:`time.process_time`) of that second scan, the minimum of ``R`` rounds
(a fresh filter each), with the minimum wall time beside it: a scan is single-threaded, so CPU time is its wall time on an idle
machine and moves less than wall time with other jobs' load::

    python benchmarks/profile_large_scan.py lmb 10000 --second
    python benchmarks/profile_large_scan.py clustered-glmb 10000 --second --cpu 2
"""

from __future__ import annotations

import argparse
import contextlib
import cProfile
import io
import pathlib
import pstats
import sys
import time

import numpy as np

from rankedassign.tracking import GLMBFilter, LMBFilter, ShortChainGibbs, make_scenario

sys.path.insert(0, str(pathlib.Path(__file__).parent))
from test_bench_large import _filter  # noqa: E402  (the benchmark's filters and prior)


def one_scan(kind: str, n: int, top: int = 8) -> float:
    """Seconds of one profiled scan of filter ``kind`` with ``n`` targets (prints the profile)."""
    sc = make_scenario("large", n_targets=n, n_scans=1, rng=0)
    x0 = sc.truth.states[0]
    labels = np.column_stack([np.zeros(n, np.int64), np.arange(1, n + 1)])
    covs = np.tile(np.diag([100.0, 25.0, 100.0, 25.0]), (n, 1, 1))
    assoc = ShortChainGibbs(400, 25, tau_stall=5, tau_stale=10)
    if kind == "glmb":
        f = GLMBFilter(sc.model, assoc)
        f.set_prior(labels, x0, covs)
    else:
        f = LMBFilter(sc.model, assoc, grouping=True, max_tracks=max(100, 10 * n))
        f.set_prior(labels, x0, covs, existence=np.full(n, 0.99))
    return _profiled(kind, n, f, sc.scans[0].z, top)


def _profiled(kind, n, f, z, top) -> float:
    prof = cProfile.Profile()
    t = time.perf_counter()
    prof.enable()
    rec = f.step(z, rng=1)
    prof.disable()
    dt = time.perf_counter() - t
    print(f"== {kind} N={n} M={rec.n_meas} seconds={dt:.3f} "
          f"timings={ {k: round(v, 3) for k, v in rec.timings.items()} }")
    pstats.Stats(prof).sort_stats("tottime").print_stats(top)
    return dt


def second_scan(kind: str, n: int, top: int = 8, cpu_rounds: int = 0) -> float:
    """The benchmark's second scan: profiled, or its CPU seconds (minimum of the rounds)."""
    sc = make_scenario("large", n_targets=n, n_scans=2, rng=0)
    z = sc.scans[1].z
    if not cpu_rounds:
        return _profiled(kind, n, _filter(kind, sc), z, top)
    best = wall = np.inf
    for _ in range(cpu_rounds):
        f = _filter(kind, sc)  # the first scan runs here
        t, w = time.process_time(), time.perf_counter()
        f.step(z, rng=1)
        best = min(best, time.process_time() - t)
        wall = min(wall, time.perf_counter() - w)
    print(f"== {kind} N={n} CPU seconds of the second scan, minimum of {cpu_rounds}: "
          f"{best:.3f} (wall {wall:.3f})")
    return best


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("kind", choices=("lmb", "glmb", "clustered-glmb"))
    ap.add_argument("n", type=int)
    ap.add_argument("--top", type=int, default=8)
    ap.add_argument("--second", action="store_true")
    ap.add_argument("--cpu", type=int, default=0, metavar="R")
    args = ap.parse_args(argv)
    if args.kind == "clustered-glmb" and not args.second:
        ap.error("clustered-glmb runs with --second (the benchmark's scene)")
    with contextlib.redirect_stdout(io.StringIO()):
        if args.second:
            second_scan("lmb", 10, cpu_rounds=1)  # loads the kernels
        else:
            one_scan(args.kind, 10)
    if args.second:
        second_scan(args.kind, args.n, args.top, args.cpu)
    else:
        one_scan(args.kind, args.n, args.top)


if __name__ == "__main__":
    main()

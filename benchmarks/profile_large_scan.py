"""Profile one scan of the LMB or δ-GLMB filter on a large scene (issue #43).

N known targets at constant density (one per 200 m x 200 m square) start as the filter's prior
(``set_prior``); one scan of measurements (Vo's noise and clutter density, position sensor) is
filtered under cProfile, after a warm-up scan at N = 10 that loads the compiled kernels::

    python benchmarks/profile_large_scan.py lmb 1000
    python benchmarks/profile_large_scan.py glmb 300 --top 12

The LMB filter runs with ``grouping=True`` (it then takes the spatial cluster path above
``SPATIAL_MIN_PAIRS``) and ``max_tracks`` large enough for every target.
"""

from __future__ import annotations

import argparse
import contextlib
import cProfile
import io
import pstats
import time

import numpy as np

from rankedassign.tracking import GLMBFilter, LMBFilter, ShortChainGibbs, make_scenario


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
    prof = cProfile.Profile()
    t = time.perf_counter()
    prof.enable()
    rec = f.step(sc.scans[0].z, rng=1)
    prof.disable()
    dt = time.perf_counter() - t
    print(f"== {kind} N={n} M={rec.n_meas} seconds={dt:.3f} "
          f"timings={ {k: round(v, 3) for k, v in rec.timings.items()} }")
    pstats.Stats(prof).sort_stats("tottime").print_stats(top)
    return dt


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("kind", choices=("lmb", "glmb"))
    ap.add_argument("n", type=int)
    ap.add_argument("--top", type=int, default=8)
    args = ap.parse_args(argv)
    with contextlib.redirect_stdout(io.StringIO()):
        one_scan(args.kind, 10)  # loads the kernels
    one_scan(args.kind, args.n, args.top)


if __name__ == "__main__":
    main()

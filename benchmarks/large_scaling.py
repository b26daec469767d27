"""Cost, memory and accuracy per target on the ``"large"`` scenario against N (issue #43).

For every N, a few scans of ``make_scenario("large", n_targets=N)`` from the known targets as
the prior (as ``test_bench_large.py``), by the LMB filter (``grouping=True``) and the clustered
δ-GLMB filter, both with ``ShortChainGibbs(400, 25, tau_stall=5, tau_stale=10)``::

    python benchmarks/large_scaling.py --sizes 100 1000 10000 --scans 5
    python benchmarks/large_scaling.py --sizes 100 10000 --filters lmb --seeds 0 1 2
    python benchmarks/large_scaling.py --sizes 10000 --filters lmb --sensor bearing-range

prints one line per filter and N: median seconds per scan after the first (the first loads the
kernels and forms the clusters), seconds per target, the process's peak resident memory so far,
the labelled error per target at the last scan, and for the clustered filter the clusters, the
largest one and the scene's retained mass. The labelled error of a target is
``min(c, |p̂ − p|)`` with ``c = 100`` m, where ``p̂`` is the position the filter reports for the
target's prior label (``c`` when it reports none); its mean over the targets is OSPA with the
assignment fixed by the labels, which unlike OSPA costs ``O(N)`` at N = 10 000. Reported tracks
of other labels (births, clutter) are counted as ``false_per_target``; ``error_inside_m`` is
the labelled error over the targets at least ``EDGE = 300`` m inside the square at the last
scan (a target near the edge has less clutter and fewer neighbours about it, and a small
square has a larger share of such targets). With several ``--seeds`` every (filter, N) runs
once per scenario seed (the filter's streams are keyed by the scan, as before), one line
each, then the mean, standard deviation and range of the errors over the seeds.
``--sensor bearing-range`` runs the scenario's bearing–range sensor
(``make_scenario("large", ..., sensor="bearing-range")``). ``unreported_per_target`` is the
share of targets the filter does not report (each counts
``c`` in the labelled error) and ``error_reported_m`` the error over the reported ones.
"""

from __future__ import annotations

import argparse
import resource
import time

import numpy as np

from rankedassign.tracking import ClusteredGLMBFilter, LMBFilter, ShortChainGibbs, make_scenario
from rankedassign.tracking.scenario import LARGE_CELL

CUTOFF = 100.0
EDGE = 300.0


def run(kind: str, n: int, n_scans: int, seed: int = 0, sensor: str = "position") -> dict:
    """One run; the numbers of the docstring as a dict."""
    sc = make_scenario("large", n_targets=n, n_scans=n_scans, rng=seed, sensor=sensor)
    F = sc.model.motion.F
    means = np.linalg.solve(F, sc.truth.states[0].T).T
    labels = np.column_stack([np.zeros(n, np.int64), np.arange(1, n + 1)])
    covs = np.tile(np.diag([100.0, 25.0, 100.0, 25.0]), (n, 1, 1))
    assoc = ShortChainGibbs(400, 25, tau_stall=5, tau_stale=10)
    if kind == "lmb":
        f = LMBFilter(sc.model, assoc, grouping=True, max_tracks=10 * n + 100)
        f.set_prior(labels, means, covs, existence=np.full(n, 0.99))
    else:
        f = ClusteredGLMBFilter(sc.model, assoc, retained_mass=True)
        f.set_prior(labels, means, covs)
    seconds = []
    for k, scan in enumerate(sc.scans):
        t = time.perf_counter()
        rec = f.step(scan.z, rng=k)
        seconds.append(time.perf_counter() - t)
    err = np.full(n, CUTOFF)
    prior = rec.labels[:, 0] == 0
    idx = rec.labels[prior, 1] - 1
    pos = rec.states[prior][:, [0, 2]]
    err[idx] = np.minimum(CUTOFF, np.linalg.norm(pos - sc.truth.states[-1][idx][:, [0, 2]],
                                                 axis=1))
    # targets at least EDGE inside the square at the last scan: their neighbourhood (targets,
    # clutter) is that of every N, where one near the edge sees less clutter and fewer
    # neighbours, and a small square has more of them
    half = 0.5 * LARGE_CELL * np.sqrt(max(n, 1))
    inside = np.all(np.abs(sc.truth.states[-1][:, [0, 2]]) <= half - EDGE, axis=1)
    out = {"filter": kind, "N": n, "seconds_per_scan": float(np.median(seconds[1:])),
           "peak_rss_GiB": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 2**20,
           "error_per_target_m": float(err.mean()),
           "error_inside_m": float(err[inside].mean()) if inside.any() else float("nan"),
           # targets the filter does not report (each counts c in the labelled error), and
           # the error over the reported ones
           "unreported_per_target": float(1.0 - idx.size / max(n, 1)),
           "error_reported_m": float(err[idx].mean()) if idx.size else float("nan"),
           "false_per_target": float((~prior).sum() / max(n, 1))}
    out["ms_per_target"] = 1e3 * out["seconds_per_scan"] / max(n, 1)
    if kind != "lmb":
        out.update(n_clusters=rec.n_clusters, largest_cluster=int(rec.cluster_sizes.max()),
                   retained_mass=rec.retained_mass,
                   clusters_beyond_dp=int(np.isnan(rec.cluster_retained_mass).sum()))
    return out


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", type=int, nargs="+", default=[100, 1000])
    ap.add_argument("--scans", type=int, default=5)
    ap.add_argument("--filters", nargs="+", default=["lmb", "clustered-glmb"])
    ap.add_argument("--seeds", type=int, nargs="+", default=[0])
    ap.add_argument("--sensor", choices=("position", "bearing-range"), default="position")
    args = ap.parse_args(argv)
    run("lmb", 10, 2)  # loads the kernels
    for kind in args.filters:
        for n in args.sizes:
            errs, inner, rep = [], [], []
            for seed in args.seeds:
                r = run(kind, n, args.scans, seed, args.sensor)
                errs.append(r["error_per_target_m"])
                inner.append(r["error_inside_m"])
                rep.append(r["error_reported_m"])
                print(f"seed={seed} " + " ".join(
                    f"{k}={v:.4g}" if isinstance(v, float) else f"{k}={v}"
                    for k, v in r.items()), flush=True)
            if len(errs) > 1:
                for name, v in (("error_per_target_m", errs), ("error_inside_m", inner),
                                ("error_reported_m", rep)):
                    print(f"filter={kind} N={n} seeds={len(v)} {name} mean={np.mean(v):.4g} "
                          f"sd={np.std(v, ddof=1):.3g} min={min(v):.4g} max={max(v):.4g}",
                          flush=True)


if __name__ == "__main__":
    main()

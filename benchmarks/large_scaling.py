"""Cost, memory and accuracy per target on the ``"large"`` scenario against N (issue #43).

For every N, a few scans of ``make_scenario("large", n_targets=N)`` from the known targets as
the prior (as ``test_bench_large.py``), by the LMB filter (``grouping=True``) and the clustered
δ-GLMB filter, both with ``ShortChainGibbs(400, 25, tau_stall=5, tau_stale=10)``::

    python benchmarks/large_scaling.py --sizes 100 1000 10000 --scans 5
    python benchmarks/large_scaling.py --sizes 100 10000 --filters lmb --seeds 0 1 2
    python benchmarks/large_scaling.py --sizes 10000 --filters lmb --sensor bearing-range
    python benchmarks/large_scaling.py --sizes 100 1000 --filters lmb --seeds 0 1 2 3 4 5 6 7 8 9

prints one line per filter and N: median seconds per scan after the first (the first loads the
kernels and forms the clusters; wall and CPU time, ``cpu_seconds_per_scan``, the measure that
holds on a loaded machine: a scan is single-threaded), seconds per target, the process's peak resident memory so far,
OSPA(2) (``ospa2_m``: :func:`rankedassign.metrics.ospa2` on the positions with ``c = 100`` m,
``p = 1``, a window of 5 scans with uniform weights and the filter's labels as its tracks,
averaged over the run's scans; ``ospa2_last_m`` at the last scan; OSPA(2) is a mean distance
per target by its normalisation), GOSPA at the last scan over N (``gospa_per_target_m``), both
by the metrics' exact sparse route (``metric_seconds`` and ``metric_cpu_seconds`` for both,
untimed in the scan's), the labelled error per target at the last scan, and for the clustered filter the clusters, the
largest one and the scene's retained mass. The labelled error of a target is
``min(c, |p̂ − p|)`` with ``c = 100`` m, where ``p̂`` is the position the filter reports for the
target's prior label (``c`` when it reports none); its mean over the targets is OSPA with the
assignment fixed by the labels, which unlike OSPA costs ``O(N)`` at N = 10 000. Reported tracks
of other labels (births, clutter) are counted as ``false_per_target``; ``error_inside_m`` is
the labelled error over the targets at least ``EDGE = 300`` m inside the square at the last
scan (a target near the edge has less clutter and fewer neighbours about it, and a small
square has a larger share of such targets). With several ``--seeds`` every (filter, N) runs
once per scenario seed (the filter's streams are keyed by the scan, as before), one line
each, then the mean, standard deviation and range of the errors and of OSPA(2) over the seeds,
and for every N above the smallest the 95 % interval of the relative change of OSPA(2) (and of
the labelled error) from the smallest N.
``--no-mass`` runs the clustered filter without the exact retained mass (its estimates are
the same: the mass draws nothing from the filter's streams), for accuracy runs at N = 10 000
where the mass's DP costs many times the scan. ``--sensor bearing-range`` runs the scenario's bearing–range sensor
(``make_scenario("large", ..., sensor="bearing-range")``). ``unreported_per_target`` is the
share of targets the filter does not report (each counts
``c`` in the labelled error) and ``error_reported_m`` the error over the reported ones.

The LMB filter extracts by the MAP cardinality of every cluster of the scan
(``--extraction cluster-map``, the default; ``map`` for the global MAP cardinality). Its state
does not depend on which (neither keeps anything between scans), so every LMB line also gives
the other one's numbers from the same run, computed from the filter's final tracks:
``map_unreported_per_target``, ``map_error_per_target_m`` for the global MAP and
``cluster_unreported_per_target``, ``cluster_error_per_target_m`` per cluster (one of the two
pairs repeats the line's own numbers). With several seeds the summary line of an LMB filter
also gives the 95 % interval of the relative change of the error per target from the smallest
N, for both extractions (a t interval of the difference of the means, by the delta method).
"""

from __future__ import annotations

import argparse
import resource
import time

import numpy as np

from rankedassign import metrics
from rankedassign.experiments.studies.scaling import _track_array
from rankedassign.tracking import ClusteredGLMBFilter, LMBFilter, ShortChainGibbs, make_scenario
from rankedassign.tracking.scenario import LARGE_CELL
from rankedassign.tracking.single.lmb import cluster_map_tracks, map_cardinality

CUTOFF = 100.0
EDGE = 300.0
#: OSPA(2)'s window (scans, uniform weights) and order; its cut-off is CUTOFF.
WINDOW = 5
ORDER = 1.0


def _labelled_error(labels, states, truth, n):
    """Per-target labelled error (``c`` when the target's prior label is not reported) and the
    indices of the reported targets."""
    err = np.full(n, CUTOFF)
    prior = labels[:, 0] == 0
    idx = labels[prior, 1] - 1
    pos = states[prior][:, [0, 2]]
    err[idx] = np.minimum(CUTOFF, np.linalg.norm(pos - truth[idx][:, [0, 2]], axis=1))
    return err, idx


def run(kind: str, n: int, n_scans: int, seed: int = 0, sensor: str = "position",
        extraction: str = "cluster-map", mass: bool = True) -> dict:
    """One run; the numbers of the docstring as a dict."""
    sc = make_scenario("large", n_targets=n, n_scans=n_scans, rng=seed, sensor=sensor)
    F = sc.model.motion.F
    means = np.linalg.solve(F, sc.truth.states[0].T).T
    labels = np.column_stack([np.zeros(n, np.int64), np.arange(1, n + 1)])
    covs = np.tile(np.diag([100.0, 25.0, 100.0, 25.0]), (n, 1, 1))
    assoc = ShortChainGibbs(400, 25, tau_stall=5, tau_stale=10)
    if kind == "lmb":
        f = LMBFilter(sc.model, assoc, grouping=True, max_tracks=10 * n + 100,
                      extraction=extraction)
        f.set_prior(labels, means, covs, existence=np.full(n, 0.99))
    else:
        f = ClusteredGLMBFilter(sc.model, assoc, retained_mass=mass)
        f.set_prior(labels, means, covs)
    seconds, cpu = [], []
    reported = []
    seen = {}
    if kind == "lmb":
        # the clusters of the kept tracks that the scan hands to the extraction (None from the
        # dense path with extraction="map"), for the other extraction's numbers
        extract = f._extract

        def spy(cluster=None):
            seen["cluster"] = cluster
            return extract(cluster)

        f._extract = spy
    for k, scan in enumerate(sc.scans):
        t, c = time.perf_counter(), time.process_time()
        rec = f.step(scan.z, rng=k)
        seconds.append(time.perf_counter() - t)
        cpu.append(time.process_time() - c)
        reported.append((rec.labels, rec.states[:, [0, 2]]))
    t, c = time.perf_counter(), time.process_time()
    o2 = metrics.ospa2(sc.truth.positions, _track_array(reported), CUTOFF, ORDER, WINDOW).value
    g = metrics.gospa(sc.truth.positions[-1], rec.states[:, [0, 2]], CUTOFF, ORDER).value
    metric_seconds, metric_cpu = time.perf_counter() - t, time.process_time() - c
    err, idx = _labelled_error(rec.labels, rec.states, sc.truth.states[-1], n)
    # targets at least EDGE inside the square at the last scan: their neighbourhood (targets,
    # clutter) is that of every N, where one near the edge sees less clutter and fewer
    # neighbours, and a small square has more of them
    half = 0.5 * LARGE_CELL * np.sqrt(max(n, 1))
    inside = np.all(np.abs(sc.truth.states[-1][:, [0, 2]]) <= half - EDGE, axis=1)
    out = {"filter": kind, "N": n, "seconds_per_scan": float(np.median(seconds[1:])),
           "cpu_seconds_per_scan": float(np.median(cpu[1:])),
           "peak_rss_GiB": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 2**20,
           "ospa2_m": float(o2.mean()), "ospa2_last_m": float(o2[-1]),
           "gospa_per_target_m": float(g) / max(n, 1), "metric_seconds": metric_seconds,
           "metric_cpu_seconds": metric_cpu,
           "error_per_target_m": float(err.mean()),
           "error_inside_m": float(err[inside].mean()) if inside.any() else float("nan"),
           # targets the filter does not report (each counts c in the labelled error), and
           # the error over the reported ones
           "unreported_per_target": float(1.0 - idx.size / max(n, 1)),
           "error_reported_m": float(err[idx].mean()) if idx.size else float("nan"),
           "false_per_target": float((rec.labels[:, 0] != 0).sum() / max(n, 1))}
    out["ms_per_target"] = 1e3 * out["seconds_per_scan"] / max(n, 1)
    if kind == "lmb":
        # both extractions from the filter's final tracks (states: heaviest component)
        states = f.m[f.offsets[:-1]]
        top = np.argsort(-f.r, kind="stable")[:map_cardinality(f.r)]
        for name, sel in (("map", np.sort(top)),
                          ("cluster", None if seen.get("cluster") is None
                           else cluster_map_tracks(f.r, seen["cluster"]))):
            if sel is None:
                out[f"{name}_unreported_per_target"] = out[f"{name}_error_per_target_m"] = \
                    float("nan")
                continue
            e, i = _labelled_error(f.labels[sel], states[sel], sc.truth.states[-1], n)
            out[f"{name}_unreported_per_target"] = float(1.0 - i.size / max(n, 1))
            out[f"{name}_error_per_target_m"] = float(e.mean())
    if kind != "lmb":
        out.update(n_clusters=rec.n_clusters, largest_cluster=int(rec.cluster_sizes.max()),
                   retained_mass=rec.retained_mass,
                   clusters_beyond_dp=(int(np.isnan(rec.cluster_retained_mass).sum()) if mass
                                       else None))
    return out


def _relative_change(a, b) -> str:
    """``mean(b) / mean(a) − 1`` with its 95 % interval (delta method, Welch's t)."""
    from scipy import stats

    a, b = np.asarray(a, float), np.asarray(b, float)
    ma, mb = a.mean(), b.mean()
    va, vb = a.var(ddof=1) / a.size, b.var(ddof=1) / b.size
    ratio = mb / ma
    se = ratio * np.sqrt(va / ma**2 + vb / mb**2)
    df = (va + vb) ** 2 / (va**2 / (a.size - 1) + vb**2 / (b.size - 1))
    half = stats.t.ppf(0.975, df) * se
    return (f"{100 * (ratio - 1):+.2f} % (95 % interval {100 * (ratio - half - 1):+.2f} to "
            f"{100 * (ratio + half - 1):+.2f} %)")


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", type=int, nargs="+", default=[100, 1000])
    ap.add_argument("--scans", type=int, default=5)
    ap.add_argument("--filters", nargs="+", default=["lmb", "clustered-glmb"])
    ap.add_argument("--seeds", type=int, nargs="+", default=[0])
    ap.add_argument("--sensor", choices=("position", "bearing-range"), default="position")
    ap.add_argument("--extraction", choices=("cluster-map", "map"), default="cluster-map")
    ap.add_argument("--no-mass", action="store_true",
                    help="the clustered filter without its exact retained mass (the same "
                         "estimates: the mass draws nothing; NaN mass in the line)")
    args = ap.parse_args(argv)
    run("lmb", 10, 2)  # loads the kernels
    for kind in args.filters:
        by_n = {}
        for n in args.sizes:
            errs, inner, rep, o2 = [], [], [], []
            for seed in args.seeds:
                r = run(kind, n, args.scans, seed, args.sensor, args.extraction,
                        not args.no_mass)
                o2.append(r["ospa2_m"])
                errs.append(r["error_per_target_m"])
                inner.append(r["error_inside_m"])
                rep.append(r["error_reported_m"])
                by_n.setdefault(n, []).append(r)
                print(f"seed={seed} " + " ".join(
                    f"{k}={v:.4g}" if isinstance(v, float) else f"{k}={v}"
                    for k, v in r.items()), flush=True)
            if len(errs) > 1:
                for name, v in (("ospa2_m", o2), ("error_per_target_m", errs),
                                ("error_inside_m", inner),
                                ("error_reported_m", rep)):
                    print(f"filter={kind} N={n} seeds={len(v)} {name} mean={np.mean(v):.4g} "
                          f"sd={np.std(v, ddof=1):.3g} min={min(v):.4g} max={max(v):.4g}",
                          flush=True)
        n0 = min(by_n)
        keys = ["ospa2_m"] + (["map_error_per_target_m", "cluster_error_per_target_m"]
                              if kind == "lmb" else ["error_per_target_m"])
        for n in sorted(by_n):
            if n == n0 or len(by_n[n]) < 2 or len(by_n[n0]) < 2:
                continue
            for key in keys:
                a = [r[key] for r in by_n[n0]]
                b = [r[key] for r in by_n[n]]
                if np.isfinite(a).all() and np.isfinite(b).all():
                    print(f"filter={kind} {key} N={n0}->{n} change {_relative_change(a, b)}",
                          flush=True)


if __name__ == "__main__":
    main()

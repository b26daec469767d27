"""Study ``scaling``: cost, memory and accuracy per target against the number of targets.

The ``"large"`` scenario (:func:`~rankedassign.tracking.make_scenario` with ``n_targets=N``:
N targets at constant density over a square, one per 200 m × 200 m, Vo's noise and clutter
density, a position sensor) run by the LMB filter (``grouping=True``: spatial gating and
clusters; by default the estimate per cluster, ``lmb_extraction="cluster-map"``) and the
clustered δ-GLMB filter (:class:`~rankedassign.tracking.ClusteredGLMBFilter`,
Beard, Vo & Vo 2020), each with the short chains and with Murty's k best, from the known
targets as the prior. Per run, truncation and N the task records the wall and CPU seconds and
the sampler's row updates of every scan (the row updates are the cost measure that does not
depend on the machine's load; Murty makes none, and its cost measure is the CPU time of the
single-threaded scans), the process's peak
memory, OSPA(2) (Beard, Vo & Vo 2020; :func:`~rankedassign.metrics.ospa2` on the positions,
cut-off ``ospa_c``, order ``ospa_p``, a window of ``ospa_window`` scans with uniform weights,
averaged over the run's scans; the estimated tracks are the filter's labels), GOSPA per target
(GOSPA at the last scan divided by N), the labelled error per target (``min(c, |p̂ − p|)`` with
the position the filter reports for a target's prior label, ``c`` when it reports none: OSPA
with the assignment fixed by the labels) and for the clustered filter the clusters, the largest
one and the scene's exact retained mass (the product of the clusters' DPs). OSPA(2) and GOSPA
take the metrics' sparse route at large N (exact, in time and memory about linear in N).

OSPA(2) is already a mean distance per target: its normalisation divides the assignment's cost
by the larger number of tracks, so "OSPA(2) per target" is OSPA(2) itself. The report says
whether the cost per target stays flat (at most 1.5× from N = 100 to the largest N, in row
updates per target and scan; wall time beside it) and whether the accuracy per target holds
(OSPA(2) within 5 % of N = 100, the issue's measure; the labelled error beside it).
"""

from __future__ import annotations

import math
import resource
import time
from dataclasses import asdict, dataclass, field, replace
from pathlib import Path

import numpy as np

from ... import metrics, tracking
from ...tracking.single.lmb import LMB_EXTRACTIONS
from ...validation import check_choice, check_fields
from .. import _format as fmt
from .._executor import run_seed
from .._plots import figure, legend_below, series_style
from .._records import RunRecord
from ..config import check_ospa, check_positive
from ..registry import Study, register_study

__all__ = ["SCALING", "SCALING_FILTERS", "SCALING_TRUNCATIONS", "ScalingConfig", "ScalingRow",
           "ScalingRun", "ScalingSummary", "scaling_task", "summarise_scaling"]

#: The filters: the LMB filter with clusters, the clustered δ-GLMB filter.
SCALING_FILTERS = ("lmb", "clustered-glmb")
_LABEL = {"lmb": "LMB (clusters)", "clustered-glmb": "clustered δ-GLMB"}
#: The truncations (the association classes' ``name``): the short chains and Murty's k best.
SCALING_TRUNCATIONS = ("short-chain", "murty")
_TRUNCATION_LABEL = {"short-chain": "short chains", "murty": "Murty"}
#: Growth of the cost per target from N = 100 to the largest N the issue allows.
COST_GROWTH_TARGET = 1.5
#: Growth of the error per target it allows.
ERROR_GROWTH_TARGET = 1.05


@dataclass(frozen=True)
class ScalingConfig:
    """Settings of the ``scaling`` study.

    Attributes
    ----------
    n_mc : int
        Monte Carlo runs per filter and N.
    sizes : tuple of int
        The numbers of targets N.
    n_scans : int
        Scans per run (the first, which forms the clusters, is not timed).
    filters : tuple of str
        Of :data:`SCALING_FILTERS`.
    truncations : tuple of str
        Of :data:`SCALING_TRUNCATIONS`: every filter runs with each.
    n_chains, chain_length, tau_stall, tau_stale : int
        The short chains (``ShortChainGibbs``).
    murty_k : int
        Murty's ``k`` (``Murty(k)``: the k best assignments of every group or component).
    ospa_c, ospa_p : float
        Cut-off (m) of OSPA(2), GOSPA and the labelled error, and the order of OSPA(2) and
        GOSPA.
    mass_max_n : int
        Largest N whose exact retained mass the clustered filter computes, in a second,
        untimed pass over the same measurements and streams (the oracle's DP on every
        cluster's components costs tens of times the filter's own scan).
    lmb_extraction : str
        The LMB filter's state extraction (one of
        :data:`~rankedassign.tracking.single.lmb.LMB_EXTRACTIONS`); default ``"cluster-map"``,
        the MAP cardinality of every cluster of the scan, as the clustered δ-GLMB filter
        extracts per cluster. The global MAP cardinality (``"map"``) leaves about
        ``Σ_i (1 − r_i)`` likely tracks unreported, 0.7 % of the targets at N ≥ 1 000.
    ospa_window : int
        OSPA(2)'s window in scans (uniform weights), 5 as in the tracking studies.
    """

    n_mc: int = 3
    sizes: tuple = (10, 100, 1000, 10000)
    n_scans: int = 10
    filters: tuple = SCALING_FILTERS
    truncations: tuple = SCALING_TRUNCATIONS
    n_chains: int = 400
    chain_length: int = 25
    tau_stall: int = 5
    tau_stale: int = 10
    ospa_c: float = 100.0
    ospa_p: float = 1.0
    mass_max_n: int = 1000
    lmb_extraction: str = "cluster-map"
    ospa_window: int = 5
    murty_k: int = 100

    def __post_init__(self):
        check_fields(self, where="scaling: ")
        for name in ("sizes", "filters", "truncations"):
            object.__setattr__(self, name, tuple(getattr(self, name)))
        if not self.sizes:
            raise ValueError("sizes must name at least one number of targets")
        for n in self.sizes:
            check_positive("sizes: N", n)
        if not self.filters:
            raise ValueError(f"filters must name at least one of {SCALING_FILTERS}")
        for f in self.filters:
            check_choice(f, "filter", SCALING_FILTERS)
        if not self.truncations:
            raise ValueError(f"truncations must name at least one of {SCALING_TRUNCATIONS}")
        for t in self.truncations:
            check_choice(t, "truncation", SCALING_TRUNCATIONS)
        check_choice(self.lmb_extraction, "lmb_extraction", LMB_EXTRACTIONS)
        for name in ("n_mc", "n_scans", "n_chains", "chain_length", "tau_stall", "tau_stale",
                     "mass_max_n", "ospa_window", "murty_k"):
            check_positive(name, getattr(self, name))
        check_ospa(self.ospa_c, self.ospa_p)


#: Quick: N up to 1 000, two runs of five scans, the retained mass up to N = 100.
QUICK = ScalingConfig(n_mc=2, sizes=(10, 100, 1000), n_scans=5, mass_max_n=100)
FULL = ScalingConfig()


@dataclass(frozen=True)
class ScalingRun(RunRecord):
    """One run of one filter at one N (:func:`scaling_task`).

    Attributes
    ----------
    filter : str
        ``"lmb"`` or ``"clustered-glmb"`` (:data:`SCALING_FILTERS`).
    N : int
        Targets.
    run : int
        Monte Carlo run (both filters of a run see the same scene).
    seconds : list of float
        Wall seconds of every scan.
    row_updates : list of int
        The sampler's row updates of every scan (the cost measure that does not depend on the
        machine's load).
    peak_rss_gib : float
        The worker process's peak resident memory so far (GiB).
    error_per_target : float
        The labelled error at the last scan (m).
    false_per_target : float
        Reported tracks without a prior label, per target.
    ospa2 : float
        OSPA(2) averaged over the run's scans (m; itself a distance per target).
    ospa2_last : float
        OSPA(2) at the last scan (m).
    gospa_per_target : float
        GOSPA at the last scan over N (m).
    n_clusters, largest_cluster : int or None
        The clustered filter's clusters and its largest one at the last scan (None for LMB).
    log10_retained_mass : float or None
        ``log10`` of the scene's exact retained mass (the product of the clusters' DPs) at the
        last scan, up to ``mass_max_n`` targets (else None).
    clusters_beyond_dp : int or None
        Clusters whose DP was out of reach (their mass NaN), where the mass was computed.
    truncation : str
        Of :data:`SCALING_TRUNCATIONS`.
    cpu_seconds : list of float
        CPU seconds of the process in every scan (:func:`time.process_time`; a scan runs on
        one thread, so this is its cost on an idle machine, and it moves less with other
        jobs' load than the wall time).
    """

    filter: str
    N: int
    run: int
    seconds: list
    row_updates: list
    peak_rss_gib: float
    error_per_target: float
    false_per_target: float
    ospa2: float
    ospa2_last: float
    gospa_per_target: float
    n_clusters: int | None = None
    largest_cluster: int | None = None
    log10_retained_mass: float | None = None
    clusters_beyond_dp: int | None = None
    truncation: str = "short-chain"
    cpu_seconds: list = field(default_factory=list)


def scaling_task(cfg: ScalingConfig, seed: int, run: int, filter_name: str, n: int,
                 truncation: str = "short-chain") -> ScalingRun:
    """One run of one filter on the ``"large"`` scenario with ``n`` targets.

    Parameters
    ----------
    cfg : ScalingConfig
        The study's settings.
    seed : int
        The study's seed; the run's scenario and filter streams come from
        ``run_seed(seed, run)`` (the same scenario for both filters).
    run : int
        Monte Carlo run index.
    filter_name : str
        ``"lmb"`` or ``"clustered-glmb"``.
    n : int
        Targets.
    truncation : str, optional
        ``"short-chain"`` (the short chains of the settings) or ``"murty"``
        (``Murty(cfg.murty_k)``).

    Returns
    -------
    ScalingRun
        The run's record.

    Examples
    --------
    >>> cfg = ScalingConfig(n_mc=1, sizes=(5,), n_scans=2, n_chains=10)
    >>> scaling_task(cfg, 0, 0, "lmb", 5).N
    5
    """
    scenario_ss, filter_ss = run_seed(seed, run).spawn(2)
    sc = tracking.make_scenario("large", n_targets=n, n_scans=cfg.n_scans,
                                rng=np.random.default_rng(scenario_ss))
    F = sc.model.motion.F
    # the known targets one scan before the first, as the prior (their labels (0, i))
    means = np.linalg.solve(F, sc.truth.states[0].T).T if n else np.empty((0, 4))
    labels = np.column_stack([np.zeros(n, np.int64), np.arange(1, n + 1)])
    covs = np.tile(np.diag([100.0, 25.0, 100.0, 25.0]), (n, 1, 1))
    check_choice(truncation, "truncation", SCALING_TRUNCATIONS)
    assoc = (tracking.Murty(cfg.murty_k) if truncation == "murty" else
             tracking.ShortChainGibbs(cfg.n_chains, cfg.chain_length, tau_stall=cfg.tau_stall,
                                      tau_stale=cfg.tau_stale))

    # one seed sequence per scan, spawned once: both passes build the same generators from them
    scan_seeds = filter_ss.spawn(len(sc.scans))

    def run_filter(mass: bool):
        if filter_name == "lmb":
            f = tracking.LMBFilter(sc.model, assoc, grouping=True, max_tracks=10 * n + 100,
                                   extraction=cfg.lmb_extraction)
            f.set_prior(labels, means, covs, existence=np.full(n, 0.99))
        else:
            f = tracking.ClusteredGLMBFilter(sc.model, assoc, retained_mass=mass)
            f.set_prior(labels, means, covs)
        seconds, cpu, row_updates, reported = [], [], [], []
        for scan, ss in zip(sc.scans, scan_seeds, strict=True):
            t = time.perf_counter()
            c = time.process_time()
            rec = f.step(scan.z, rng=np.random.default_rng(ss))
            cpu.append(time.process_time() - c)
            seconds.append(time.perf_counter() - t)
            row_updates.append(int(rec.row_updates))
            reported.append((rec.labels, rec.states[:, [0, 2]]))
        return rec, (seconds, cpu), row_updates, reported

    rec, (seconds, cpu), row_updates, reported = run_filter(False)
    # OSPA(2) on the positions, the filter's labels as its tracks (untimed)
    o2 = metrics.ospa2(sc.truth.positions, _track_array(reported), cfg.ospa_c, cfg.ospa_p,
                       cfg.ospa_window).value
    truth = sc.truth.states[-1][:, [0, 2]]
    err = np.full(n, cfg.ospa_c)
    prior = rec.labels[:, 0] == 0
    idx = rec.labels[prior, 1] - 1
    pos = rec.states[prior][:, [0, 2]]
    err[idx] = np.minimum(cfg.ospa_c, np.linalg.norm(pos - truth[idx], axis=1))
    out = {"filter": filter_name, "truncation": truncation, "N": n, "run": run,
           "seconds": seconds, "cpu_seconds": cpu,
           "row_updates": row_updates,
           "peak_rss_gib": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 2**20,
           "error_per_target": float(err.mean()) if n else 0.0,
           "false_per_target": float((~prior).sum() / max(n, 1)),
           "ospa2": float(o2.mean()), "ospa2_last": float(o2[-1]),
           "gospa_per_target": float(metrics.gospa(truth, rec.states[:, [0, 2]], cfg.ospa_c,
                                                   cfg.ospa_p).value) / max(n, 1)}
    if filter_name != "lmb":
        out.update(n_clusters=int(rec.n_clusters),
                   largest_cluster=int(np.max(rec.cluster_sizes, initial=0)))
        if n <= cfg.mass_max_n:
            # the same filter again with its exact mass (the mass draws nothing from the
            # streams, so the estimates are the timed pass's)
            again, _, _, _ = run_filter(True)
            if not (np.array_equal(again.labels, rec.labels)
                    and np.array_equal(again.states, rec.states)):
                raise RuntimeError("the retained mass pass gave other estimates than the timed "
                                   "pass: the mass must not draw from the filter's streams")
            masses = np.asarray(again.cluster_retained_mass, dtype=float)
            ok = masses[np.isfinite(masses) & (masses > 0)]
            # the scene's mass is a product of thousands of factors: kept as log10
            out.update(log10_retained_mass=float(np.sum(np.log10(ok))) if ok.size else 0.0,
                       clusters_beyond_dp=int((~np.isfinite(masses)).sum()))
    return ScalingRun(**out)


def _track_array(reported) -> np.ndarray:
    """The ``(n_scans, n_tracks, 2)`` array of :func:`~rankedassign.metrics.ospa2` from each
    scan's ``(labels, positions)``: one track per label, in order of the labels, NaN where a
    label is not reported (as :func:`~rankedassign.metrics.tracks_to_array`, vectorised for
    tens of thousands of tracks)."""
    labels = np.concatenate([lab.reshape(-1, 2) for lab, _ in reported]).astype(np.int64)
    uniq, track = np.unique(labels, axis=0, return_inverse=True)
    out = np.full((len(reported), uniq.shape[0], 2), np.nan)
    at = 0
    for k, (lab, pos) in enumerate(reported):
        out[k, track.reshape(-1)[at:at + len(lab)]] = pos
        at += len(lab)
    return out


def scaling_tasks(cfg: ScalingConfig, seed: int) -> list[tuple]:
    """``(cfg, seed, run, filter, N, truncation)`` of every task, the largest N first (the
    longest)."""
    return [(cfg, seed, r, f, n, t) for n in sorted(cfg.sizes, reverse=True)
            for f in cfg.filters for t in cfg.truncations for r in range(cfg.n_mc)]


# ----------------------------------------------------------------------------------- summary
@dataclass(frozen=True)
class ScalingRow:
    """One filter and N over its runs.

    Attributes
    ----------
    filter : str
        The filter.
    N : int
        Targets.
    n_runs : int
        Runs.
    seconds_per_scan, seconds_per_scan_se : float
        Mean over runs of the median seconds per scan after the first, and its standard error.
    ms_per_target : float
        ``1000 · seconds_per_scan / N``.
    row_updates_per_target, row_updates_per_target_se : float
        Mean over runs of the median row updates per scan after the first, divided by N (the
        association's work, independent of the machine's load), and its standard error.
    peak_rss_gib : float
        Largest peak resident memory of the worker processes (GiB).
    error_per_target, error_per_target_se : float
        Labelled error per target at the last scan (m), mean and standard error over runs.
    false_per_target : float
        Reported tracks of other labels (births, clutter) per target.
    gospa_per_target : float
        GOSPA at the last scan divided by N (m), mean over runs.
    n_clusters, largest_cluster : float
        Mean clusters and the largest cluster seen (clustered filter; NaN otherwise).
    log10_retained_mass : float
        Mean ``log10`` of the scene's exact retained mass at the last scan (NaN for the LMB).
    clusters_beyond_dp : int
        Clusters whose mass the DP could not reach, over all runs.
    ms_per_target_se, false_per_target_se, gospa_per_target_se, n_clusters_se : float
        Standard errors over the runs of ``ms_per_target``, ``false_per_target``,
        ``gospa_per_target`` and ``n_clusters`` (over the runs that have the value; NaN with
        fewer than two).
    log10_retained_mass_se : float
        The same for ``log10_retained_mass``.
    ospa2, ospa2_se : float
        OSPA(2) averaged over the run's scans (m; a mean distance per target by its
        normalisation), mean and standard error over runs (NaN for records without it).
    truncation : str
        Of :data:`SCALING_TRUNCATIONS`.
    cpu_ms_per_target, cpu_ms_per_target_se : float
        Mean over runs of the median CPU seconds per scan after the first, per target (ms),
        and its standard error (NaN for records without CPU times).
    """

    filter: str
    N: int
    n_runs: int
    seconds_per_scan: float
    seconds_per_scan_se: float
    ms_per_target: float
    row_updates_per_target: float
    row_updates_per_target_se: float
    peak_rss_gib: float
    error_per_target: float
    error_per_target_se: float
    false_per_target: float
    gospa_per_target: float
    n_clusters: float
    largest_cluster: float
    log10_retained_mass: float
    clusters_beyond_dp: int
    # last and with defaults, so a record built with the fields above stays valid
    ms_per_target_se: float = math.nan
    false_per_target_se: float = math.nan
    gospa_per_target_se: float = math.nan
    n_clusters_se: float = math.nan
    log10_retained_mass_se: float = math.nan
    ospa2: float = math.nan
    ospa2_se: float = math.nan
    truncation: str = "short-chain"
    cpu_ms_per_target: float = math.nan
    cpu_ms_per_target_se: float = math.nan


@dataclass(frozen=True)
class ScalingSummary:
    """The study's summary.

    Attributes
    ----------
    rows : list of ScalingRow
        Every filter, truncation and N, by filter, then truncation, then N.
    """

    rows: list


def _se(x) -> float:
    x = np.asarray(x, dtype=float)
    return float(x.std(ddof=1) / math.sqrt(x.size)) if x.size > 1 else math.nan


def _mean(values) -> float:
    v = [x for x in values if x is not None]
    return float(np.mean(v)) if v else math.nan


def _se_present(values) -> float:
    """:func:`_se` over the values that are not ``None`` (those :func:`_mean` averages)."""
    return _se([x for x in values if x is not None])


def summarise_scaling(runs: list[ScalingRun], cfg: ScalingConfig) -> ScalingSummary:
    """One row per filter, truncation and N.

    Parameters
    ----------
    runs : list of ScalingRun
        The task records (:func:`scaling_task`).
    cfg : ScalingConfig
        The study's settings.

    Returns
    -------
    ScalingSummary
    """
    cells: dict = {}
    for r in runs:
        cells.setdefault((r.filter, r.truncation, r.N), []).append(r)
    rows = []
    for f, t in _series():
        for n in sorted(cfg.sizes):
            rs = cells.get((f, t, n))
            if not rs:
                continue
            # after the first scan, which forms the clusters (the first alone if it is all)
            secs = [float(np.median(r.seconds[1:] or r.seconds)) for r in rs]
            ups = [float(np.median(r.row_updates[1:] or r.row_updates)) for r in rs]
            errs = [r.error_per_target for r in rs]
            largest = [r.largest_cluster for r in rs if r.largest_cluster is not None]
            cpus = [float(np.median(r.cpu_seconds[1:] or r.cpu_seconds)) for r in rs
                    if r.cpu_seconds]
            rows.append(ScalingRow(
                filter=f, truncation=t, N=n, n_runs=len(rs), seconds_per_scan=float(np.mean(secs)),
                seconds_per_scan_se=_se(secs),
                ms_per_target=1e3 * float(np.mean(secs)) / max(n, 1),
                row_updates_per_target=float(np.mean(ups)) / max(n, 1),
                row_updates_per_target_se=_se(ups) / max(n, 1),
                peak_rss_gib=float(max(r.peak_rss_gib for r in rs)),
                error_per_target=float(np.mean(errs)), error_per_target_se=_se(errs),
                false_per_target=_mean(r.false_per_target for r in rs),
                gospa_per_target=_mean(r.gospa_per_target for r in rs),
                n_clusters=_mean(r.n_clusters for r in rs),
                largest_cluster=float(max(largest)) if largest else math.nan,
                log10_retained_mass=_mean(r.log10_retained_mass for r in rs),
                clusters_beyond_dp=int(sum(r.clusters_beyond_dp or 0 for r in rs)),
                ms_per_target_se=1e3 * _se(secs) / max(n, 1),
                false_per_target_se=_se_present(r.false_per_target for r in rs),
                gospa_per_target_se=_se_present(r.gospa_per_target for r in rs),
                n_clusters_se=_se_present(r.n_clusters for r in rs),
                log10_retained_mass_se=_se_present(r.log10_retained_mass for r in rs),
                ospa2=_mean(r.ospa2 for r in rs),
                ospa2_se=_se_present(r.ospa2 for r in rs),
                cpu_ms_per_target=(1e3 * float(np.mean(cpus)) / max(n, 1) if cpus
                                   else math.nan),
                cpu_ms_per_target_se=1e3 * _se(cpus) / max(n, 1)))
    return ScalingSummary(rows=rows)


def _series() -> list[tuple[str, str]]:
    """Every ``(filter, truncation)`` in the report's order."""
    return [(f, t) for f in SCALING_FILTERS for t in SCALING_TRUNCATIONS]


def _label(f: str, t: str) -> str:
    return f"{_LABEL[f]}, {_TRUNCATION_LABEL[t]}"


# ----------------------------------------------------------------------------------- report
def _verdict(summary: ScalingSummary) -> str:
    out = []
    for f, t in _series():
        rows = {r.N: r for r in summary.rows if r.filter == f and r.truncation == t}
        if 100 not in rows or max(rows) <= 100:
            continue
        big = rows[max(rows)]
        small = rows[100]
        # the verdict rests on the row updates (the association's work, the same on any
        # machine) where a sampler makes them; Murty makes none, and its cost measure is the
        # CPU time of the scans (a scan runs on one thread); the wall time, which moves with
        # the machine's load, is the second measure
        if small.row_updates_per_target > 0:
            growth = big.row_updates_per_target / small.row_updates_per_target
            cost = (f"the sampler's row updates per target and scan change {growth:.2f}× "
                    f"({fmt.num(small.row_updates_per_target, 1)} → "
                    f"{fmt.num(big.row_updates_per_target, 1)})")
        else:
            growth = big.cpu_ms_per_target / small.cpu_ms_per_target
            cost = (f"the CPU time per target and scan changes {growth:.2f}× "
                    f"({fmt.num(small.cpu_ms_per_target, 3)} → "
                    f"{fmt.num(big.cpu_ms_per_target, 3)} ms)")
        wall = big.ms_per_target / small.ms_per_target
        err = big.error_per_target / small.error_per_target
        o2 = big.ospa2 / small.ospa2
        out.append(
            f"**{_label(f, t)}:** from N = 100 to N = {big.N:,} {cost}: "
            + ("flat, within the target of at most 1.5×" if growth <= COST_GROWTH_TARGET
               else f"above the target of at most {COST_GROWTH_TARGET}×")
            + f"; the wall time per target and scan changes {wall:.2f}× "
            f"({fmt.num(small.ms_per_target, 3)} → {fmt.num(big.ms_per_target, 3)} ms, the "
            "median scan of each run on a machine whose load is not controlled: a secondary "
            f"measure); OSPA(2), a mean distance per target, changes "
            f"{o2:.3f}× ({fmt.num(small.ospa2, 2)} → {fmt.num(big.ospa2, 2)} m"
            + (f", ± {fmt.num(big.ospa2_se, 2)} m over runs" if fmt.finite(big.ospa2_se)
               else "")
            + "): " + ("within 5 %" if o2 <= ERROR_GROWTH_TARGET else "more than 5 % worse")
            + f" (the issue's measure); the labelled error per target changes {err:.3f}× "
            f"({fmt.num(small.error_per_target, 2)} → {fmt.num(big.error_per_target, 2)} m"
            + (f", ± {fmt.num(big.error_per_target_se, 2)} m over runs"
               if fmt.finite(big.error_per_target_se) else "")
            + ").")
    if not out:
        return ("**Verdict.** These settings have no N above 100 beside N = 100: no verdict on "
                "scaling.")
    return "**Verdict.** " + "\n\n".join(out)


def render_scaling(summary: ScalingSummary, cfg: ScalingConfig) -> str:
    """The report's section: the verdict and the table.

    Parameters
    ----------
    summary : ScalingSummary
    cfg : ScalingConfig

    Returns
    -------
    str
        Markdown.
    """
    lines = ["## Scaling: thousands of targets, clusters as independent filters", "",
             f"The `\"large\"` scenario (one target per 200 m × 200 m, Vo's noise and clutter "
             f"density, a position sensor) with N = {', '.join(f'{n:,}' for n in cfg.sizes)} "
             f"known targets as the prior, {fmt.plural(cfg.n_mc, 'run')} of {cfg.n_scans} "
             f"scans; short chains {cfg.n_chains} × {cfg.chain_length} (τ_stall = "
             f"{cfg.tau_stall}, τ_stale = {cfg.tau_stale}) and Murty's {cfg.murty_k} best "
             "(of each group or component), where the settings name them; row updates and "
             "seconds per scan are the median after the first scan (which forms the "
             "clusters). The row updates (the sampler's work; Murty makes none) do not depend "
             "on the machine's load; the CPU seconds of a scan (single-threaded) depend on it "
             "less than the wall seconds, a secondary measure. The LMB filter's extraction is "
             f"`{cfg.lmb_extraction}`. OSPA(2) (c = {fmt.num(cfg.ospa_c, 0)} m, p = "
             f"{fmt.num(cfg.ospa_p, 0)}, a window of {cfg.ospa_window} scans with uniform "
             "weights, the filter's labels as its tracks) is averaged over the run's scans; "
             "it is a mean distance per target by its normalisation, so it is reported as it "
             "is. GOSPA per target is GOSPA at the last scan over N; the labelled error per "
             "target is OSPA at the last scan with the assignment fixed by the prior labels.",
             "", _verdict(summary), ""]
    header = ["filter", "truncation", "N", "row updates / target", "s / scan", "ms / target",
              "CPU ms / target",
              "peak memory (GiB)", "OSPA(2) (m)",
              "error / target (m)", "false / target", "GOSPA / target", "clusters (largest)",
              "log10 retained mass"]
    body = [[_LABEL[r.filter], _TRUNCATION_LABEL[r.truncation], f"{r.N:,}",
             (fmt.pm(r.row_updates_per_target, r.row_updates_per_target_se, 1,
                     n_runs=r.n_runs) if r.row_updates_per_target > 0 else "–"),
             fmt.pm(r.seconds_per_scan, r.seconds_per_scan_se, 3, n_runs=r.n_runs),
             fmt.pm(r.ms_per_target, r.ms_per_target_se, 3, n_runs=r.n_runs),
             fmt.pm(r.cpu_ms_per_target, r.cpu_ms_per_target_se, 3, n_runs=r.n_runs),
             fmt.num(r.peak_rss_gib, 2),
             fmt.pm(r.ospa2, r.ospa2_se, 2, n_runs=r.n_runs),
             fmt.pm(r.error_per_target, r.error_per_target_se, 2, n_runs=r.n_runs),
             fmt.pm(r.false_per_target, r.false_per_target_se, 3, n_runs=r.n_runs),
             fmt.pm(r.gospa_per_target, r.gospa_per_target_se, 2, n_runs=r.n_runs),
             (f"{fmt.pm_count(r.n_clusters, r.n_clusters_se, n_runs=r.n_runs)} "
              f"({int(r.largest_cluster)})" if fmt.finite(r.n_clusters) else "–"),
             fmt.pm(r.log10_retained_mass, r.log10_retained_mass_se, 2, n_runs=r.n_runs)]
            for r in summary.rows]
    lines += [fmt.table(header, body), ""]
    beyond = sum(r.clusters_beyond_dp for r in summary.rows)
    lines += [f"The exact retained mass is computed up to N = {cfg.mass_max_n:,} (in an "
              "untimed second pass: the oracle's DP over every cluster's components costs tens "
              "of times the filter's own scan). "
              f"Clusters beyond the exact DP: {beyond} (their mass is NaN, never the scene's). "
              "The scene's retained mass is the product of its clusters' exact masses, so it "
              "falls geometrically with N while each cluster keeps most of its own.", "",
              "![Cost and error per target against N](scaling.png)", ""]
    return "\n".join(lines)


def plot_scaling(summary: ScalingSummary, directory: Path) -> list[str]:
    """``scaling.png``: the sampler's row updates and the CPU time per target against N
    (log–log), and OSPA(2), for every filter and truncation.

    Parameters
    ----------
    summary : ScalingSummary
    directory : pathlib.Path

    Returns
    -------
    list of str
        The file written.
    """
    from matplotlib.ticker import FuncFormatter, LogLocator, NullFormatter

    fig, axes = figure(3, 4.0, 3.4)
    for i, (f, t) in enumerate(_series()):
        rows = [r for r in summary.rows if r.filter == f and r.truncation == t]
        if not rows:
            continue
        n = [r.N for r in rows]
        style = series_style(i)
        # every series in the legend: an empty line where a truncation makes no row updates
        sampled = [r for r in rows if r.row_updates_per_target > 0]
        axes[0].plot([r.N for r in sampled], [r.row_updates_per_target for r in sampled],
                     label=_label(f, t), **style)
        # the CPU time of a scan (single-threaded), the wall time where a record has none
        axes[1].plot(n, [r.cpu_ms_per_target if fmt.finite(r.cpu_ms_per_target)
                         else r.ms_per_target for r in rows], **style)
        axes[2].errorbar(n, [r.ospa2 for r in rows],
                         yerr=[0 if not fmt.finite(r.ospa2_se) else r.ospa2_se for r in rows],
                         capsize=3, **style)
    axes[0].set_ylabel("row updates per target and scan")
    axes[0].set_title("sampler work (load-free; Murty makes none)", fontsize=9)
    axes[1].set_ylabel("CPU ms per target and scan")
    axes[1].set_title("cost per target (one thread)", fontsize=9)
    axes[2].set_ylabel("OSPA(2) (m)")
    axes[2].set_title("accuracy per target (±1 SE)", fontsize=9)
    for ax in axes[:2]:
        ys = np.concatenate([np.asarray(line.get_ydata(), dtype=float)
                             for line in ax.get_lines()] or [np.empty(0)])
        ys = ys[np.isfinite(ys) & (ys > 0)]
        if ys.size and ys.max() / ys.min() < 10:
            # within a decade a log axis labels one tick or none: linear from 0 instead
            ax.set_ylim(0, 1.1 * ys.max())
            continue
        ax.set_yscale("log")
        # a short log range has one decade or none: label 1, 2 and 5 of every decade as plain
        # numbers (matplotlib's minor labels print as "6 × 10⁰" and crowd the axis)
        ax.yaxis.set_major_locator(LogLocator(base=10, subs=(1.0, 2.0, 5.0)))
        ax.yaxis.set_major_formatter(FuncFormatter(lambda v, _: f"{v:g}"))
        ax.yaxis.set_minor_formatter(NullFormatter())
        ax.margins(y=0.15)
    for ax in axes:
        ax.set_xscale("log")
        ax.xaxis.set_major_locator(LogLocator(base=10))
        ax.set_xlabel("targets N")
        ax.grid(alpha=0.3, which="both")
    fig.suptitle("Cost and accuracy per target against the number of targets", fontsize=10)
    legend_below(fig)
    name = "scaling.png"
    fig.savefig(Path(directory) / name, dpi=110)
    return [name]


def _csv(summary: ScalingSummary) -> list[dict]:
    return [asdict(r) for r in summary.rows]


def _warm(cfg: ScalingConfig) -> ScalingConfig:
    return replace(cfg, n_mc=1, sizes=(10,), n_scans=2, n_chains=10)


SCALING = register_study(Study(
    name="scaling",
    title="Cost, memory and accuracy per target against the number of targets (clusters)",
    config_type=ScalingConfig,
    full=lambda: FULL,
    quick=lambda: QUICK,
    tasks=scaling_tasks,
    task=scaling_task,
    summarise=summarise_scaling,
    render=render_scaling,
    plot=plot_scaling,
    csv_rows=_csv,
    paper="",
    order=78,
    default_run=False,
    warm=_warm,
    warm_group=lambda args: (args[3], args[5]),  # (filter, truncation)
    run_from_dict=ScalingRun.from_dict,
))

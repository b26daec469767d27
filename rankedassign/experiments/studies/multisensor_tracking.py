"""The multi-sensor tracking study: fusion gain and the associations on the ``"multi"`` scenario.

For every run (a seed) the measurements of the four sensors are drawn once; each sensor set
(``V = 1, 2, 3``) and each association then run on the same data, with the static birth of the
configuration, and the adaptive-birth cells (spec §7.2 variant: births from the adaptive-birth
sampler, no birth placed by hand) on the same data too. Per run and scan the study records
OSPA(2) and the cardinality error, and per run the sampler work (observations = full sweeps,
row updates, sampler calls), the births per scan and the targets lost (the single-sensor
study's coverage rule: an estimate within 50 m covers a target, the first 10 scans of its life
are left out, a target covered on less than half of the rest is lost).

The δ-GLMB rows (:class:`~rankedassign.tracking.MultiSensorGLMBFilter`) run on their own
cells, ``glmb_sensor_sets × glmb_associations`` with the static birth ``glmb_birth`` (the
narrow one by default: the paper's wide birth tracks gate every measurement, and every
component's dense tuple table would grow with it) and ``glmb_adaptive_*`` with adaptive
birth; the LMB filter runs on the same cells, so each GLMB row has its LMB row on the same
measurements and birth beside it.

The functions here are the study's computation: :func:`multisensor_tracking_task` (one run),
:func:`summarise_multisensor_tracking` (means, standard errors, totals, reductions),
:func:`multisensor_tracking_table` (a Markdown table) and :func:`plot_multisensor_tracking`
(OSPA(2) and cardinality error per scan, one panel per sensor set or per association).
"""

from __future__ import annotations

import dataclasses
import math
import warnings
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from ...metrics import gospa_series, ospa2, track_coverage
from ...tracking.association import Exact, OriginalGibbs, ShortChainGibbs
from ...tracking.filters import FILTERS
from ...tracking.marginals import MARGINALS
from ...tracking.multisensor.scenario import BIRTHS, MULTI_SENSORS
from ...tracking.run import run_multisensor_scenario
from ...validation import check_choice, check_fields, check_int
from .. import _format as fmt
from .._plots import legend_below, series_style
from .._records import RunRecord
from ..config import renamed_settings
from ..registry import Study, register_study
from ..vocabulary import DEPRECATED_ASSOCIATIONS, ROW_METHODS, canonical_pair

__all__ = [
    "MULTISENSOR_TRACKING",
    "LONG_CHAIN_SWEEPS",
    "STUDY_FILTERS",
    "STUDY_TRUNCATIONS",
    "STUDY_ASSOCIATIONS",
    "MultiSensorStudyConfig",
    "MultiSensorTrackingRecord",
    "MultiSensorTrackingSummary",
    "check_association",
    "association_label",
    "make_association",
    "multisensor_tracking_task",
    "summarise_multisensor_tracking",
    "multisensor_tracking_table",
    "PLOT_BY",
    "plot_multisensor_tracking",
]

#: Truncations of the study, by their classes' ``name``
#: (:mod:`rankedassign.experiments.vocabulary`): the long chain, the short chains, and the
#: exact DP (where a group fits it; otherwise the long chain, counted as a fallback).
STUDY_TRUNCATIONS = (OriginalGibbs.name, ShortChainGibbs.name, Exact.name)
#: Associations of the study, each a ``(truncation, method)`` pair, ``method`` the row
#: conditional (:data:`~rankedassign.experiments.vocabulary.ROW_METHODS`; of the exact DP, its
#: long-chain fallback's): the long chain (Alg. 1), the short chains with the Alg. 1 kernel and
#: with the MM kernels, and the exact DP. The old one-string spellings (``"long"``,
#: ``"short-mm"``, ...) still read, deprecated
#: (:data:`~rankedassign.experiments.vocabulary.DEPRECATED_ASSOCIATIONS`).
STUDY_ASSOCIATIONS = (("original", "exact"), ("short-chain", "exact"), ("short-chain", "mm"),
                      ("short-chain", "mm-fixed"), ("exact", "exact"))
#: Sweeps per sampler call of the long chain the sweep reduction is measured against (spec §7.2).
LONG_CHAIN_SWEEPS = 10_000
#: Filters of the study's rows (the names of :data:`~rankedassign.tracking.filters.FILTERS`).
STUDY_FILTERS = tuple(FILTERS)
#: Coverage rule of the single-sensor tracking study.
COVERAGE_RADIUS, COVERAGE_SETTLE, LOST_BELOW = 50.0, 10, 0.5


@renamed_settings(methods="associations", adaptive_methods="adaptive_associations",
                  glmb_methods="glmb_associations",
                  glmb_adaptive_methods="glmb_adaptive_associations")
@dataclass(frozen=True)
class MultiSensorStudyConfig:
    """Settings of the multi-sensor tracking study.

    Attributes
    ----------
    n_mc, n_scans : int
        Monte Carlo runs (seeds ``seed .. seed + n_mc - 1``) and scans per run.
    sensor_sets : tuple of tuple of int
        Sensor subsets (indices into
        :data:`~rankedassign.tracking.multisensor.scenario.MULTI_SENSORS`).
    associations : tuple of (str, str)
        Associations, ``(truncation, method)`` pairs (:data:`STUDY_ASSOCIATIONS`; a
        ``--config`` file writes each as a two-element list, ``["short-chain", "mm"]``). This
        and the three settings below named ``*associations`` were ``*methods``: the old names
        still read, deprecated.
    adaptive_sensor_sets, adaptive_associations : tuple
        The (sensor set, association) cells that also run with adaptive birth
        (:class:`~rankedassign.tracking.AdaptiveBirth` with its defaults, the
        spec §7.2 values); empty to leave adaptive birth out.
    long_obs : int
        Sweeps of the long chain (spec §7.2: 10 000).
    n_chains, chain_length, tau_stall, tau_stale : int
        Short-chain settings (400, 25, 5, 10).
    marginals : {"truncated", "rao-blackwell"}
        How hypotheses become marginals.
    birth : {"paper", "narrow"}
        Static birth model of the cells of ``sensor_sets × associations``.
    glmb_sensor_sets, glmb_associations : tuple
        The cells of the δ-GLMB filter (and of the LMB filter beside it) with the static birth
        ``glmb_birth``; empty to leave the GLMB rows out. The GLMB filter's long chain runs
        ``min(T_h − 1, long_obs)`` sweeps per component, its short chains at most ``T_h − 1``
        (:class:`~rankedassign.tracking.GLMBFilter`).
    glmb_birth : {"paper", "narrow"}
        Static birth of the GLMB cells (default ``"narrow"``).
    glmb_adaptive_sensor_sets, glmb_adaptive_associations : tuple
        The GLMB cells with adaptive birth (and the LMB filter beside them).
    glmb_extraction : {"map", "hysteresis"}
        State extraction of the GLMB filter (default ``"map"``, Vo's estimator for the δ-GLMB:
        the MAP cardinality's heaviest component). Hysteresis on ``r(ℓ)`` (the LMB rows')
        misses targets whose existence the δ-GLMB posterior splits between two labels, the
        birth of one scan and of the next (docs, "The δ-GLMB filter").
    seed : int
        First seed.
    """

    n_mc: int = 10
    n_scans: int = 100
    sensor_sets: tuple = ((0,), (1,), (2,), (0, 1), (0, 1, 2))
    associations: tuple = STUDY_ASSOCIATIONS
    adaptive_sensor_sets: tuple = ((0,), (0, 1), (0, 1, 2))
    adaptive_associations: tuple = (("short-chain", "exact"), ("short-chain", "mm"))
    long_obs: int = 10_000
    n_chains: int = 400
    chain_length: int = 25
    tau_stall: int = 5
    tau_stale: int = 10
    marginals: str = "truncated"
    birth: str = "paper"
    glmb_sensor_sets: tuple = ((0,), (1,), (2,), (0, 1), (0, 1, 2))
    glmb_associations: tuple = (("original", "exact"), ("short-chain", "exact"),
                           ("short-chain", "mm"))
    glmb_birth: str = "narrow"
    glmb_adaptive_sensor_sets: tuple = ((0, 1, 2),)
    glmb_adaptive_associations: tuple = (("short-chain", "exact"), ("short-chain", "mm"))
    glmb_extraction: str = "map"
    seed: int = 0

    @classmethod
    def quick(cls) -> MultiSensorStudyConfig:
        """A small version for the quick reproduction: 1 run of 15 scans, sensors 0, 1, 2 alone
        and together, the short chains (Alg. 1 and MM kernels) and a 300-sweep long chain with
        the paper's static birth; the short chains with adaptive birth on sensors 0, 1, 2;
        the δ-GLMB filter (and the LMB filter beside it) with MM short chains on sensor 0 and
        on sensors 0, 1, 2 with the narrow birth, and with adaptive birth on sensors 0, 1, 2.

        Examples
        --------
        >>> from rankedassign.experiments.studies.multisensor_tracking import MultiSensorStudyConfig
        >>> MultiSensorStudyConfig.quick().n_scans
        15
        """
        return cls(n_mc=1, n_scans=15, sensor_sets=((0,), (1,), (2,), (0, 1, 2)),
                   associations=(("original", "exact"), ("short-chain", "exact"),
                                 ("short-chain", "mm")), long_obs=300,
                   adaptive_sensor_sets=((0, 1, 2),),
                   adaptive_associations=(("short-chain", "exact"),),
                   glmb_sensor_sets=((0,), (0, 1, 2)),
                   glmb_associations=(("short-chain", "mm"),),
                   glmb_adaptive_sensor_sets=((0, 1, 2),),
                   glmb_adaptive_associations=(("short-chain", "mm"),))

    def __post_init__(self):
        check_fields(self)
        for name in ("n_mc", "n_scans", "long_obs", "n_chains", "chain_length", "tau_stall",
                     "tau_stale"):
            check_int(getattr(self, name), name, minimum=1)
        check_int(self.seed, "seed")
        for name, sets, associations in (
            ("", self.sensor_sets, self.associations),
            ("adaptive_", self.adaptive_sensor_sets, self.adaptive_associations),
            ("glmb_", self.glmb_sensor_sets, self.glmb_associations),
            ("glmb_adaptive_", self.glmb_adaptive_sensor_sets,
             self.glmb_adaptive_associations),
        ):
            if not name and not (sets and associations):
                raise ValueError("sensor_sets and associations must not be empty")
            for ss in sets:
                if not isinstance(ss, (tuple, list)) or not ss:
                    raise TypeError(f"{name}sensor_sets entries must be non-empty lists of "
                                    f"sensor indices, got {ss!r}")
                for v in ss:
                    check_int(v, f"{name}sensor_sets: sensor", maximum=len(MULTI_SENSORS) - 1)
                if len(set(ss)) != len(ss):
                    raise ValueError(f"{name}sensor_sets entry {ss!r} repeats a sensor")
            # the old one-string spellings, deprecated; a --config file's lists as tuples
            associations = tuple(
                canonical_pair(m, f"{name}associations", DEPRECATED_ASSOCIATIONS)
                for m in associations)
            object.__setattr__(self, f"{name}associations", associations)
            for m in associations:
                check_association(m, f"{name}associations")
        check_choice(self.marginals, "marginals", MARGINALS)
        check_choice(self.birth, "birth", ("paper", "narrow"))
        check_choice(self.glmb_birth, "glmb_birth", ("paper", "narrow"))
        check_choice(self.glmb_extraction, "glmb_extraction", ("map", "hysteresis"))


def check_association(association, setting: str = "association") -> tuple:
    """``association`` if it is a ``(truncation, method)`` pair of the study.

    Parameters
    ----------
    association : object
        The pair to check.
    setting : str, optional
        What it is an entry of, for the messages.

    Returns
    -------
    tuple of str
        ``association`` as a tuple.

    Raises
    ------
    TypeError
        If it is not a pair.
    ValueError
        On a truncation not in :data:`STUDY_TRUNCATIONS` or a method not in
        :data:`~rankedassign.experiments.vocabulary.ROW_METHODS`.

    Examples
    --------
    >>> check_association(["short-chain", "mm"])
    ('short-chain', 'mm')
    >>> check_association(("murty", "mm"))  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    ValueError: unknown association: truncation 'murty'; expected one of ('original', ...)
    """
    if not isinstance(association, (tuple, list)) or len(association) != 2:
        raise TypeError(f"{setting} entries must be (truncation, method) pairs such as "
                        f"['short-chain', 'mm'], got {association!r}")
    truncation, method = association
    check_choice(truncation, f"{setting}: truncation", STUDY_TRUNCATIONS)
    check_choice(method, f"{setting}: method", ROW_METHODS)
    return (truncation, method)


def association_label(truncation: str, method: str) -> str:
    """How the report's text and plots name an association: ``"short-chain (mm)"``.

    Parameters
    ----------
    truncation : str
        The truncation's name (one of the vocabulary's ``TRUNCATIONS``).
    method : str
        The multi-sensor row conditional.

    Returns
    -------
    str
        ``"truncation (method)"``.

    Examples
    --------
    >>> association_label("short-chain", "mm")
    'short-chain (mm)'
    """
    return f"{truncation} ({method})"


def make_association(cfg: MultiSensorStudyConfig, association):
    """The association of the pair ``association`` under the settings ``cfg``.

    Parameters
    ----------
    cfg : MultiSensorStudyConfig
        Settings the association takes: ``long_obs`` (the long chain's sweeps per call),
        ``n_chains``, ``chain_length``, ``tau_stall``, ``tau_stale`` (the short chains) and
        ``marginals``.
    association : (str, str)
        ``(truncation, method)`` (:func:`check_association`): the long chain
        (``"original"``), the short chains (``"short-chain"``) or the exact DP with the long
        chain as its fallback (``"exact"``), with the row conditional ``method``: the Alg. 1
        row kernel (``"exact"``), the MM-Gibbs kernel and its exclusion-aware proposal
        (``"mm"``) or its fixed proposal (``"mm-fixed"``). An old one-string spelling
        (``"short-mm"``) still reads, with a ``DeprecationWarning``.

    Returns
    -------
    OriginalGibbs or ShortChainGibbs or Exact
        A new association object (the exact DP's counts ``n_fallback`` from zero).

    Raises
    ------
    TypeError, ValueError
        On an association that is not a pair of the study (:func:`check_association`).

    Examples
    --------
    >>> from rankedassign.experiments.studies.multisensor_tracking import (
    ...     MultiSensorStudyConfig, make_association)
    >>> make_association(MultiSensorStudyConfig(), ("short-chain", "mm"))
    ShortChainGibbs(400, 25, tau_stall=5, tau_stale=10)
    """
    truncation, method = check_association(
        canonical_pair(association, "association", DEPRECATED_ASSOCIATIONS))
    long = OriginalGibbs(cfg.long_obs, method=method, marginals=cfg.marginals)
    if truncation == OriginalGibbs.name:
        return long
    if truncation == Exact.name:
        return Exact(fallback=long)
    return ShortChainGibbs(cfg.n_chains, cfg.chain_length, tau_stall=cfg.tau_stall,
                           tau_stale=cfg.tau_stale, method=method, marginals=cfg.marginals)


@dataclass(frozen=True)
class MultiSensorTrackingRecord(RunRecord):
    """One run of one association on one sensor set.

    Attributes
    ----------
    run : int
    sensors : tuple of int
    truncation, method : str
        The association (:func:`check_association`): the truncation's class name and the row
        conditional.
    ospa2, cardinality_error : ndarray, shape (n_scans,)
        OSPA(2) (``c = 200``, ``p = 1``, window 5) and ``|#estimates − #targets|`` per scan.
    coverage : ndarray, shape (n_targets,)
        Coverage of every target (NaN for one too short-lived to count).
    sweeps, row_updates, invocations : int
        Totals over the run.
    n_fallback : int
        Groups the exact DP could not take (solved by the long chain); 0 for the others.
    seconds : float
        Filter time of the run.
    birth : str
        ``cfg.birth`` (static) or ``"adaptive"``.
    births_per_scan : float
        Mean birth tracks appended per scan.
    birth_seconds : float
        Seconds of the run spent making adaptive births (0 for a static birth).
    filter : {"lmb", "glmb"}
        The multi-sensor LMB or δ-GLMB filter.
    gospa : ndarray, shape (n_scans,) or None
        GOSPA (``α = 2``, ``c = 200``, ``p = 1``, :func:`~rankedassign.metrics.gospa`) of each
        scan's estimated positions; None in a record made without it.
    """

    run: int
    sensors: tuple
    truncation: str
    method: str
    ospa2: np.ndarray
    cardinality_error: np.ndarray
    coverage: np.ndarray
    sweeps: int
    row_updates: int
    invocations: int
    n_fallback: int
    seconds: float
    birth: str = "paper"
    births_per_scan: float = float("nan")
    birth_seconds: float = 0.0
    filter: str = "lmb"
    gospa: np.ndarray | None = None

    @classmethod
    def from_dict(cls, data: dict) -> MultiSensorTrackingRecord:
        """The record of one object of ``multisensor_tracking_runs.json``.

        Parameters
        ----------
        data : dict
            Its fields; the per-scan and per-target series as lists (``null`` for NaN).

        Returns
        -------
        MultiSensorTrackingRecord
            With the series as float arrays (NaN again) and ``sensors`` a tuple.
        """
        data = dict(data)
        for name in ("ospa2", "cardinality_error", "coverage", "gospa"):
            if data.get(name) is not None:
                data[name] = np.array(data[name], dtype=float)
        if "sensors" in data:
            data["sensors"] = tuple(data["sensors"])
        return super().from_dict(data)

    @property
    def targets_lost(self) -> int:
        """Targets covered on less than half of their counted scans."""
        c = self.coverage[~np.isnan(self.coverage)]
        return int((c < LOST_BELOW).sum())


def multisensor_tracking_task(cfg: MultiSensorStudyConfig, run: int, sensors,
                              association, birth: str | None = None,
                              filter: str = "lmb") -> MultiSensorTrackingRecord:
    """Run the filter once (seed ``cfg.seed + run``) and measure it.

    Parameters
    ----------
    cfg : MultiSensorStudyConfig
        Settings: ``seed``, ``n_scans``, the association's settings (:func:`make_association`)
        and ``birth``, the static birth used when ``birth`` is None.
    run : int
        Index of the Monte Carlo run; the scenario is drawn with ``rng=cfg.seed + run``, so
        every sensor set, association and birth of one run sees the same measurements.
    sensors : sequence of int
        Sensors the filter fuses (distinct indices into
        :data:`~rankedassign.tracking.multisensor.scenario.MULTI_SENSORS`).
    association : (str, str)
        ``(truncation, method)`` (:data:`STUDY_ASSOCIATIONS`, built by
        :func:`make_association`).
    birth : {"paper", "narrow", "adaptive"}, optional
        Birth model (:data:`~rankedassign.tracking.multisensor.scenario.BIRTHS`); None
        (default) is ``cfg.birth``.
    filter : {"lmb", "glmb"}, optional
        The multi-sensor LMB filter (default) or the δ-GLMB filter (:data:`STUDY_FILTERS`),
        the latter with the extraction ``cfg.glmb_extraction``.

    Returns
    -------
    MultiSensorTrackingRecord
        OSPA(2), GOSPA and cardinality error per scan, the coverage of every target, the sampler
        work summed over the run, the DP's fallbacks, the seconds and the births per scan.

    Examples
    --------
    >>> cfg = MultiSensorStudyConfig(n_scans=3, n_chains=20, chain_length=5)
    >>> rec = multisensor_tracking_task(cfg, 0, (0,), ("short-chain", "exact"))
    >>> rec.ospa2.shape, rec.sensors, rec.invocations >= 3
    ((3,), (0,), True)
    """
    check_int(run, "run")
    birth = cfg.birth if birth is None else check_choice(birth, "birth", BIRTHS)
    check_choice(filter, "filter", STUDY_FILTERS)
    truncation, method = check_association(
        canonical_pair(association, "association", DEPRECATED_ASSOCIATIONS))
    assoc = make_association(cfg, (truncation, method))
    extraction = cfg.glmb_extraction if filter == "glmb" else None
    sr = run_multisensor_scenario(assoc, rng=cfg.seed + run, n_scans=cfg.n_scans,
                                  sensors=sensors, birth=birth, filter=filter,
                                  extraction=extraction)
    o2 = ospa2(sr.truth, sr.estimates, c=200.0, p=1.0, window=5).value
    # GOSPA (α = 2) with OSPA(2)'s c and p, beside it in the table and the CSV
    g = gospa_series(sr.truth, sr.estimates, c=200.0, p=1.0).value
    n_true = (~np.isnan(sr.truth[:, :, 0])).sum(axis=1)
    cov = track_coverage(sr.truth, sr.estimates, COVERAGE_RADIUS, settle=COVERAGE_SETTLE)
    return MultiSensorTrackingRecord(
        run=run, sensors=tuple(int(v) for v in sensors), truncation=truncation, method=method,
        ospa2=np.asarray(o2, dtype=float),
        cardinality_error=np.abs(sr.n_estimated - n_true).astype(float),
        coverage=np.asarray(cov, dtype=float),
        sweeps=int(sr.sweeps.sum()), row_updates=int(sr.row_updates.sum()),
        invocations=int(sr.invocations.sum()),
        n_fallback=int(getattr(assoc, "n_fallback", 0)),
        seconds=float(sum(np.sum(v) for v in sr.timings.values())),
        birth=birth, births_per_scan=float(np.mean(sr.n_births)),
        birth_seconds=float(np.sum(sr.timings["birth"])),
        filter=filter, gospa=np.asarray(g, dtype=float),
    )


def _se(x) -> float:
    x = np.asarray(x, dtype=float)
    return float(x.std(ddof=1) / math.sqrt(x.size)) if x.size > 1 else float("nan")


@dataclass(frozen=True)
class MultiSensorTrackingSummary:
    """Means over runs of one (sensor set, association, birth) cell.

    Attributes
    ----------
    sensors : tuple of int
    truncation, method : str
        The association: the truncation's class name and the row conditional.
    n_runs : int
    ospa2_mean, ospa2_se : float
        Mean OSPA(2) over scans and runs, and the standard error over runs of the run means.
    card_mean, card_se : float
        The same for the cardinality error.
    ospa2_curve, card_curve : ndarray, shape (n_scans,)
        Per-scan means over runs.
    sweeps, row_updates, invocations : float
        Mean totals per run.
    targets_lost : int
        Over all runs.
    n_fallback : int
        Over all runs.
    seconds : float
        Mean filter seconds per run.
    sweep_reduction : float
        LMB rows: ``1 − sweeps / (10 000 × calls)``, the saving against a long chain of
        :data:`LONG_CHAIN_SWEEPS` sweeps on every sampler call of the same runs (1 for the
        exact DP, which sweeps nothing; NaN without any call). GLMB rows: ``1 − sweeps /
        sweeps of the GLMB long chain`` of the same sensors and birth (whose budget is the
        components' counts, not 10 000 per call); NaN without that row.
    birth : str
        The static birth's name or ``"adaptive"``.
    births_per_scan : float
        Mean birth tracks appended per scan.
    birth_seconds : float
        Mean seconds per run spent making adaptive births.
    filter : {"lmb", "glmb"}
        The filter of the cell.
    gospa_mean, gospa_se : float
        Mean GOSPA over scans and runs and its standard error over runs (NaN when a run's
        record has no GOSPA).
    sweeps_se, row_updates_se, invocations_se, seconds_se, births_per_scan_se : float
        Standard errors over runs of ``sweeps``, ``row_updates``, ``invocations``,
        ``seconds`` and ``births_per_scan`` (NaN for one run).
    """

    sensors: tuple
    truncation: str
    method: str
    n_runs: int
    ospa2_mean: float
    ospa2_se: float
    card_mean: float
    card_se: float
    ospa2_curve: np.ndarray = field(repr=False)
    card_curve: np.ndarray = field(repr=False)
    sweeps: float
    row_updates: float
    invocations: float
    targets_lost: int
    n_fallback: int
    seconds: float
    sweep_reduction: float
    birth: str = "paper"
    births_per_scan: float = float("nan")
    birth_seconds: float = 0.0
    filter: str = "lmb"
    gospa_mean: float = float("nan")
    gospa_se: float = float("nan")
    sweeps_se: float = float("nan")
    row_updates_se: float = float("nan")
    invocations_se: float = float("nan")
    seconds_se: float = float("nan")
    births_per_scan_se: float = float("nan")


def summarise_multisensor_tracking(records) -> list[MultiSensorTrackingSummary]:
    """One summary per (sensor set, truncation, method, birth, filter), in order of first
    appearance.

    Parameters
    ----------
    records : iterable of MultiSensorTrackingRecord
        Records of :func:`multisensor_tracking_task`, in any order; the runs of one cell must
        have the same number of scans (their curves are averaged scan by scan).

    Returns
    -------
    list of MultiSensorTrackingSummary
        One per distinct ``(sensors, truncation, method, birth, filter)``, in order of first
        appearance;
        the runs of a cell are taken in order of ``run``.

    Examples
    --------
    >>> import numpy as np
    >>> recs = [MultiSensorTrackingRecord(r, (0,), t, "exact", np.full(2, o), np.zeros(2),
    ...         np.ones(3), s, 2 * s, 2, 0, 1.0)
    ...         for r in (0, 1)
    ...         for t, o, s in (("original", 10.0, 20_000), ("short-chain", 11.0, 1000))]
    >>> [(s.truncation, s.ospa2_mean, round(s.sweep_reduction, 2))
    ...  for s in summarise_multisensor_tracking(recs)]
    [('original', 10.0, 0.0), ('short-chain', 11.0, 0.95)]
    """
    records = list(records)

    def key(r):
        return (r.sensors, (r.truncation, r.method), r.birth, r.filter)

    keys = list(dict.fromkeys(key(r) for r in records))
    cells = {k: sorted((r for r in records if key(r) == k), key=lambda r: r.run) for k in keys}
    # the GLMB long chain of the same sensors and birth (the Alg. 1 one the study runs, or
    # any long chain when there is none)
    long_sweeps = {}
    for k, rs in sorted(cells.items(), key=lambda kv: kv[0][1] != ("original", "exact")):
        if k[3] == "glmb" and k[1][0] == OriginalGibbs.name:
            long_sweeps.setdefault((k[0], k[2]), float(np.mean([r.sweeps for r in rs])))
    out = []
    for (sensors, (truncation, method), birth, filt), rs in cells.items():
        o = np.array([r.ospa2 for r in rs])
        c = np.array([r.cardinality_error for r in rs])
        g = (np.array([r.gospa for r in rs]) if all(r.gospa is not None for r in rs)
             else np.full((1, 1), np.nan))
        sweeps = float(np.mean([r.sweeps for r in rs]))
        calls = float(np.mean([r.invocations for r in rs]))
        if filt == "glmb":
            base = long_sweeps.get((sensors, birth), 0.0)
            reduction = float(1.0 - sweeps / base) if base > 0 else float("nan")
        else:
            reduction = float("nan") if calls == 0 else \
                float(1.0 - sweeps / (LONG_CHAIN_SWEEPS * calls))
        out.append(MultiSensorTrackingSummary(
            sensors=sensors, truncation=truncation, method=method, n_runs=len(rs),
            ospa2_mean=float(o.mean()), ospa2_se=_se(o.mean(axis=1)),
            card_mean=float(c.mean()), card_se=_se(c.mean(axis=1)),
            ospa2_curve=o.mean(axis=0), card_curve=c.mean(axis=0),
            sweeps=sweeps, row_updates=float(np.mean([r.row_updates for r in rs])),
            invocations=calls,
            targets_lost=int(sum(r.targets_lost for r in rs)),
            n_fallback=int(sum(r.n_fallback for r in rs)),
            seconds=float(np.mean([r.seconds for r in rs])),
            sweep_reduction=reduction,
            birth=birth, births_per_scan=float(np.mean([r.births_per_scan for r in rs])),
            birth_seconds=float(np.mean([r.birth_seconds for r in rs])), filter=filt,
            gospa_mean=float(g.mean()), gospa_se=_se(g.mean(axis=1)),
            sweeps_se=_se([r.sweeps for r in rs]), row_updates_se=_se([r.row_updates for r in rs]),
            invocations_se=_se([r.invocations for r in rs]),
            seconds_se=_se([r.seconds for r in rs]),
            births_per_scan_se=_se([r.births_per_scan for r in rs]),
        ))
    return out


def multisensor_tracking_table(summaries) -> str:
    """The summaries as a Markdown table.

    Parameters
    ----------
    summaries : iterable of MultiSensorTrackingSummary
        Rows of the table, in order (:func:`summarise_multisensor_tracking`).

    Returns
    -------
    str
        A Markdown table of 16 columns (filter, sensors, ``V``, truncation, method, birth,
        OSPA(2),
        GOSPA and cardinality error with their standard errors — ``(1 run)`` instead of one
        for a cell of one run —, sweeps, row updates and calls per run, sweep reduction in percent,
        births per scan, targets lost, seconds per run, the means with their standard errors
        too): the header, the rule, then one line per summary. A NaN sweep reduction or
        births per scan is left blank.

    Examples
    --------
    >>> from rankedassign.experiments.studies.multisensor_tracking import multisensor_tracking_table
    >>> multisensor_tracking_table([]).splitlines()[0].startswith("| filter | sensors")
    True
    """
    head = ("| filter | sensors | V | truncation | method | birth | OSPA(2) mean ± se (m) | "
            "GOSPA mean ± se (m) | card. error ± se | "
            "sweeps / run | row updates / run | calls / run | sweep reduction | births / scan | "
            "targets lost | s / run |")
    lines = [head, "|" + "---|" * 16]
    for s in summaries:
        red = "" if math.isnan(s.sweep_reduction) else f"{100 * s.sweep_reduction:.1f} %"
        births = ("" if math.isnan(s.births_per_scan)
                  else fmt.pm(s.births_per_scan, s.births_per_scan_se, 1, n_runs=s.n_runs))
        lines.append(
            f"| {s.filter.upper()} | {','.join(map(str, s.sensors))} | {len(s.sensors)} | "
            f"{s.truncation} | {s.method} | {s.birth} | "
            f"{fmt.pm(s.ospa2_mean, s.ospa2_se, 1, n_runs=s.n_runs)} | "
            f"{fmt.pm(s.gospa_mean, s.gospa_se, 1, n_runs=s.n_runs)} | "
            f"{fmt.pm(s.card_mean, s.card_se, 2, n_runs=s.n_runs)} | "
            f"{fmt.pm_count(s.sweeps, s.sweeps_se, n_runs=s.n_runs)} | "
            f"{fmt.pm_count(s.row_updates, s.row_updates_se, n_runs=s.n_runs)} | "
            f"{fmt.pm_count(s.invocations, s.invocations_se, n_runs=s.n_runs)} | {red} | "
            f"{births} | {s.targets_lost} | "
            f"{fmt.pm(s.seconds, s.seconds_se, 1, n_runs=s.n_runs)} |"
        )
    return "\n".join(lines)


#: How :func:`plot_multisensor_tracking` splits the lines into panels: one panel per sensor set
#: (the associations and births on it as lines) or one per association and birth (the sensor
#: sets as lines).
PLOT_BY = ("sensors", "association")
#: Most panel columns of one row of :func:`plot_multisensor_tracking`; more panels wrap.
PLOT_COLUMNS = 4


def _sensor_label(sensors) -> str:
    return "{" + ",".join(map(str, sensors)) + "}"


def _method_label(s) -> str:
    return (("GLMB " if s.filter == "glmb" else "") + association_label(s.truncation, s.method)
            + (" adaptive" if s.birth == "adaptive" else
               f" {s.birth}" if s.filter == "glmb" or s.birth == "narrow" else ""))


def plot_multisensor_tracking(summaries, path, *, by: str = "sensors") -> None:
    """OSPA(2) and cardinality error per scan, one panel per sensor set or per association.

    Parameters
    ----------
    summaries : list of MultiSensorTrackingSummary
    path : str or path-like
        Image file to write (format from the suffix).
    by : {"sensors", "association"}, optional
        ``"sensors"`` (default): one panel per sensor set, one line per association and birth
        on it, the cells that pair the δ-GLMB filter with the LMB filter in a panel of their
        own beside it; ``"association"``: one panel per association and birth, one line per
        sensor
        set. Each panel has its OSPA(2) above its cardinality error; a line keeps its colour,
        dashes and marker in every panel, one legend below the panels names them, and at most
        :data:`PLOT_COLUMNS` panels share a row. ``"method"``, the old name of
        ``"association"``, still reads, with a ``DeprecationWarning``.

    Raises
    ------
    ValueError
        On an unknown ``by`` or no summary to plot.

    Examples
    --------
    >>> import tempfile
    >>> from pathlib import Path
    >>> import numpy as np
    >>> from rankedassign.experiments.studies.multisensor_tracking import (
    ...     MultiSensorTrackingRecord, plot_multisensor_tracking, summarise_multisensor_tracking)
    >>> recs = [MultiSensorTrackingRecord(0, s, t, "exact", np.full(5, 50.0 / len(s)),
    ...                                   np.zeros(5), np.ones(12), 100, 200, 5, 0, 1.0)
    ...         for s in ((0,), (0, 1)) for t in ("short-chain", "original")]
    >>> out = Path(tempfile.mkdtemp()) / "ms.png"
    >>> plot_multisensor_tracking(summarise_multisensor_tracking(recs), out, by="association")
    >>> out.stat().st_size > 0
    True
    """
    _tracking_figure(summaries, by).savefig(path, dpi=110)


def _tracking_figure(summaries, by: str):
    """The matplotlib Figure of :func:`plot_multisensor_tracking` (no pyplot state)."""
    if by == "method":  # "method" means the row conditional alone now
        warnings.warn("by: 'method' is deprecated; write 'association'", DeprecationWarning,
                      stacklevel=3)
        by = "association"
    check_choice(by, "by", PLOT_BY)
    summaries = list(summaries)
    if not summaries:
        raise ValueError("nothing to plot: summaries is empty")
    from matplotlib.figure import Figure  # optional dependency (the "plot" extra)
    from matplotlib.ticker import MaxNLocator


    # The cells that pair a δ-GLMB filter with the LMB filter on the same birth get panels of
    # their own beside the LMB associations of the same sensors: together they made eight
    # lines in one panel.
    glmb = {(s.sensors, s.truncation, s.method, s.birth) for s in summaries
            if s.filter == "glmb"}

    def paired(s):
        return (s.sensors, s.truncation, s.method, s.birth) in glmb

    def panel_of(s):
        if by == "sensors":
            return _sensor_label(s.sensors) + (", δ-GLMB and LMB" if paired(s) else "")
        return _method_label(s)

    def line_of(s):
        if by == "sensors":
            return ("LMB " if paired(s) and s.filter == "lmb" else "") + _method_label(s)
        return _sensor_label(s.sensors)

    panels = list(dict.fromkeys(panel_of(s) for s in summaries))
    lines = list(dict.fromkeys(line_of(s) for s in summaries))
    # colour, dashes and marker per line, the same in every panel (series_style: the first
    # eight differ in all three, so they stay apart in greyscale too)
    styles = {name: series_style(i) for i, name in enumerate(lines)}
    ncols = min(len(panels), PLOT_COLUMNS)
    nrows = -(-len(panels) // ncols)
    fig = Figure(figsize=(max(3.6 * ncols + 0.6, 5.5), 4.4 * nrows + 1.0), layout="constrained")
    axes = fig.subplots(2 * nrows, ncols, squeeze=False)
    for i, name in enumerate(panels):
        top, bottom = axes[2 * (i // ncols), i % ncols], axes[2 * (i // ncols) + 1, i % ncols]
        # the cardinality panel below shares the scan axis and carries its labels
        top.sharex(bottom)
        top.tick_params(labelbottom=False)
        bottom.xaxis.set_major_locator(MaxNLocator(integer=True))
        for s in summaries:
            if panel_of(s) != name:
                continue
            label = line_of(s)
            k = np.arange(1, s.ospa2_curve.size + 1)
            style = {**styles[label], "markevery": max(1, k.size // 10)}
            top.plot(k, s.ospa2_curve, label=label, **style)
            bottom.plot(k, s.card_curve, label=label, **style)
        title = f"sensors {name}" if by == "sensors" else name
        top.set(title=title, ylabel="OSPA(2) (m)" if i % ncols == 0 else None)
        bottom.set(xlabel="scan",
                   ylabel="|#estimates − #targets|" if i % ncols == 0 else None)
        for ax in (top, bottom):
            ax.grid(True, alpha=0.3)
    for i in range(len(panels), nrows * ncols):  # empty places of the last row
        axes[2 * (i // ncols), i % ncols].set_visible(False)
        axes[2 * (i // ncols) + 1, i % ncols].set_visible(False)
    # one y scale per metric, so that panels compare at a glance
    for row in range(2):
        shown = [ax for ax in axes[row::2].ravel() if ax.get_visible()]
        lo = min(ax.get_ylim()[0] for ax in shown)
        hi = max(ax.get_ylim()[1] for ax in shown)
        for ax in shown:
            ax.set_ylim(lo, hi)
    # one legend for every panel, below them: a legend inside a panel lay on its curves
    legend_below(fig, axes.ravel(), ncol=min(4, len(lines)))
    runs = sorted({s.n_runs for s in summaries})
    fig.suptitle("OSPA(2) and cardinality error, "
                 + ("one run (no mean)" if runs == [1] else
                    f"mean of {'–'.join(map(str, (runs[0], runs[-1])[:len(runs)]))} runs"))
    return fig


def _warm_group(task: tuple) -> str:
    """The kernels a task compiles (:attr:`rankedassign.experiments.Study.warm_group`): the
    δ-GLMB filter's, the adaptive-birth LMB filter's, or the static-birth LMB filter's (every
    sensor set and sampler of one group compiles the same kernels, measured from an empty
    cache one task after another)."""
    if task[5:6] == ("glmb",):
        return "glmb"
    return "adaptive" if task[4] == "adaptive" else "static"


def _tasks(cfg: MultiSensorStudyConfig, seed: int) -> list[tuple]:
    """One task per (run, sensor set, association, birth); run ``r`` uses seed ``seed + r``."""
    cfg = dataclasses.replace(cfg, seed=int(seed))
    static = [(cfg, r, tuple(sensors), assoc, cfg.birth) for r in range(cfg.n_mc)
              for sensors in cfg.sensor_sets for assoc in cfg.associations]
    adaptive = [(cfg, r, tuple(sensors), assoc, "adaptive") for r in range(cfg.n_mc)
                for sensors in cfg.adaptive_sensor_sets for assoc in cfg.adaptive_associations]
    # the GLMB cells, each with the LMB filter beside it (unless that cell is already above)
    done = {(t[1], t[2], t[3], t[4]) for t in static + adaptive}
    glmb = []
    for birth, sets, associations in (
            (cfg.glmb_birth, cfg.glmb_sensor_sets, cfg.glmb_associations),
            ("adaptive", cfg.glmb_adaptive_sensor_sets, cfg.glmb_adaptive_associations)):
        for r in range(cfg.n_mc):
            for sensors in sets:
                for assoc in associations:
                    glmb.append((cfg, r, tuple(sensors), assoc, birth, "glmb"))
                    if (r, tuple(sensors), assoc, birth) not in done:
                        glmb.append((cfg, r, tuple(sensors), assoc, birth, "lmb"))
    return static + adaptive + glmb


def _summarise(runs, cfg):
    return summarise_multisensor_tracking(runs)


def _fusion_gains(summary, cfg) -> str:
    """Per filter, the fused OSPA(2) of the GLMB cells against the best single sensor."""
    out = []
    for filt in STUDY_FILTERS:
        for assoc in cfg.glmb_associations:
            rows = {s.sensors: s.ospa2_mean for s in summary if s.filter == filt
                    and (s.truncation, s.method) == assoc and s.birth == cfg.glmb_birth
                    and s.sensors in {tuple(x) for x in cfg.glmb_sensor_sets}}
            singles = [v for k, v in rows.items() if len(k) == 1]
            many = [k for k in rows if len(k) > 1]
            if not singles or not many:
                continue
            fused = max(many, key=len)
            gain = 1.0 - rows[fused] / min(singles)
            out.append(f"{filt.upper()} {association_label(*assoc)}: "
                       f"sensors {_sensor_label(fused)} "
                       f"{rows[fused]:.1f} m against {min(singles):.1f} m for the best single "
                       f"sensor, {100 * gain:.0f} % lower")
    if not out:
        return ""
    return ("Fusion gain on the GLMB cells (" + cfg.glmb_birth + " birth, mean OSPA(2)): "
            + "; ".join(out) + ".\n\n")


#: Longer runs of the same scenario, as the multi-sensor tracking page of the documentation
#: records them; a quick verdict names them, since one 15-scan run resolves no difference.
LONGER_RUNS = ("the longer runs documented on the multi-sensor tracking page found, over 100 "
               "scans (seed 0, short chains), 23.3 m mean OSPA(2) on all three sensors against "
               "52.2 m for the best single sensor (55 % lower), and over 10 seeds with the "
               "narrow birth 19.01 m for the short chains against 20.65 m for the exact update")


def _verdict(summary, cfg) -> str:
    """The section's verdict in words: fusion gain, short against long chains, adaptive
    birth, δ-GLMB against LMB, each with its numbers, and what one run can resolve."""
    cells = {(s.filter, s.sensors, (s.truncation, s.method), s.birth): s for s in summary}

    def val(s):
        return fmt.pm(s.ospa2_mean, s.ospa2_se, 1) + " m"  # "1 run" is said once, below

    parts = []
    for assoc in cfg.associations:
        rows = {k[1]: s for k, s in cells.items()
                if k[0] == "lmb" and k[2] == assoc and k[3] == cfg.birth}
        singles = {k: s for k, s in rows.items() if len(k) == 1}
        many = [k for k in rows if len(k) > 1]
        if singles and many:
            fused = rows[max(many, key=len)]
            best = min(singles.values(), key=lambda s: s.ospa2_mean)
            gain = 100 * (1 - fused.ospa2_mean / best.ospa2_mean)
            parts.append(f"{association_label(*assoc)}: sensors "
                         f"{_sensor_label(fused.sensors)} {val(fused)} against "
                         f"{val(best)} for the best single sensor "
                         f"{_sensor_label(best.sensors)} ({gain:.0f} % "
                         f"{'lower' if gain >= 0 else 'higher'})")
    text = ("Fusing the sensors lowers the mean OSPA(2) — " + "; ".join(parts) + "."
            if parts else "")
    fused_sets = sorted({k[1] for k in cells if len(k[1]) > 1}, key=len)
    if fused_sets:
        big = fused_sets[-1]
        long_ = cells.get(("lmb", big, ("original", "exact"), cfg.birth))
        short = cells.get(("lmb", big, ("short-chain", "exact"), cfg.birth))
        if long_ is not None and short is not None:
            text += (f" On sensors {_sensor_label(big)} the short chains reach {val(short)} "
                     f"with {short.sweeps:,.0f} sweeps per run against the {cfg.long_obs}-sweep "
                     f"long chain's {val(long_)} with {long_.sweeps:,.0f}.")
        adaptive = cells.get(("lmb", big, ("short-chain", "exact"), "adaptive"))
        if adaptive is not None and short is not None:
            text += (f" Adaptive birth gives {val(adaptive)} against {val(short)} with the "
                     f"static birth: its births come from the previous scan's measurements, so "
                     "it confirms the targets of scan 1 later.")
    pairs = []
    for (filt, sensors, assoc, birth), g in cells.items():
        lmb = cells.get(("lmb", sensors, assoc, birth))
        if filt == "glmb" and lmb is not None:
            pairs.append(f"sensors {_sensor_label(sensors)}, {association_label(*assoc)}, "
                         f"{birth} birth: δ-GLMB "
                         f"{val(g)}, LMB {val(lmb)}")
    if pairs:
        text += " The δ-GLMB against the LMB filter on the same cells: " + "; ".join(pairs) + "."
    n = min((s.n_runs for s in summary), default=0)
    if n < 3:
        text += (f" With {fmt.plural(n, 'run')} of {cfg.n_scans} scans per cell there is no "
                 "standard error and the first scans (the targets of scan 1 being confirmed) "
                 "weigh on every mean, so only the direction of the fusion gain is resolved; "
                 f"{LONGER_RUNS}.")
    return text


def _render(summary, cfg) -> str:
    runs = "run" if cfg.n_mc == 1 else "runs"
    glmb = ""
    if cfg.glmb_sensor_sets or cfg.glmb_adaptive_sensor_sets:
        glmb = (
            f"The GLMB rows are the multi-sensor δ-GLMB filter (H_upd = 1000, H_max = 1000; "
            f"every component truncated by the association with its count T_h, the long chain "
            f"with min(T_h − 1, {cfg.long_obs}) sweeps; {cfg.glmb_extraction} extraction) on "
            f"the {cfg.glmb_birth} static birth and on adaptive birth; the LMB filter "
            f"(hysteresis) runs on the same cells, so each GLMB row has an LMB row of the same "
            f"birth and measurements. Their sweep reduction is against the GLMB long chain of "
            f"the same cell.\n\n" + _fusion_gains(summary, cfg))
    return (
        "## Multi-sensor tracking — fusion gain and the associations on the \"multi\" "
        "scenario\n\n"
        f"The \"multi\" scenario (multi-sensor spec §7.2: the paper's 12 targets seen by position "
        f"sensors of σ = 10, 15, 20 m and P_D = 0.6, 0.7, 0.8, 20 clutter points each), "
        f"{cfg.n_mc} Monte Carlo {runs} of {cfg.n_scans} scans, {cfg.birth} static birth, and "
        f"adaptive birth (μ_0 = 0, P_0 = diag(1000², 50², 1000², 50²), τ_rU = 0.9, n_min = 2, "
        f"r_B,max = 0.03, λ_B = 1; no static birth) on the rows marked adaptive; every "
        f"sensor set runs on the same measurements. The long chain takes {cfg.long_obs} sweeps "
        f"per call; the short chains {cfg.n_chains} × {cfg.chain_length} with τ_stall = "
        f"{cfg.tau_stall}, τ_stale = {cfg.tau_stale}. The paper has no multi-sensor numbers. "
        f"{fmt.runs_note([s.n_runs for s in summary])}\n\n"
        f"**Verdict.** {_verdict(summary, cfg)}\n\n"
        + glmb + multisensor_tracking_table(summary) + "\n\n![multi-sensor tracking]"
        "(multisensor_tracking.png)\n"
    )


def _plot(summary, directory: Path) -> list[str]:
    name = "multisensor_tracking.png"
    plot_multisensor_tracking(summary, Path(directory) / name)
    return [name]


def _csv_rows(summary) -> list[dict]:
    return [{k: v for k, v in dataclasses.asdict(s).items() if not hasattr(v, "shape")}
            for s in summary]


MULTISENSOR_TRACKING = register_study(Study(
    name="multisensor_tracking",
    title="multi-sensor LMB and δ-GLMB filters: fusion gain and the associations on the "
          "'multi' scenario",
    config_type=MultiSensorStudyConfig,
    full=MultiSensorStudyConfig,
    quick=MultiSensorStudyConfig.quick,
    tasks=_tasks,
    task=multisensor_tracking_task,
    run_from_dict=MultiSensorTrackingRecord.from_dict,
    summarise=_summarise,
    render=_render,
    plot=_plot,
    csv_rows=_csv_rows,
    paper="",
    order=95,
    default_run=False,
    warm=lambda c: replace(
        c, n_mc=1, n_scans=3, long_obs=30, n_chains=10, chain_length=4,
        sensor_sets=tuple(c.sensor_sets[:1]) + tuple(c.sensor_sets[1:][-1:])),
    warm_group=_warm_group,
))

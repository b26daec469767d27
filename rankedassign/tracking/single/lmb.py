"""The labeled multi-Bernoulli (LMB) filter with a pluggable ranked-assignment association.

One scan of :class:`LMBFilter` (spec §6) runs these phases, each a method of its own so that a
filter with several sensors can reuse them (one measurement array and one set of problems per
sensor):

1. prediction (6.1, :meth:`LMBFilter.predict`): survivors ``r ← P_S r``, Gaussian components
   ``m ← F m``, ``P ← F P Fᵀ + Q``; then the birth Bernoullis of the scan are appended with
   labels ``(k, b)`` (:meth:`LMBFilter._append_births`);
2. likelihoods and gate (:meth:`LMBFilter._measurement_terms`): the innovation statistics of
   every component and measurement, the χ² gate, and the measurements some track gates;
3. groups (§6.5a, :func:`group_tracks`): tracks that share no gated measurement are
   independent problems (one problem per scan without grouping);
4. the association problem of a group (6.2, :meth:`LMBFilter._group_problem`):
   ``η_i(−1) = 1 − r_i``, ``η_i(0) = r_i (1 − P_D)``, ``η_i(j) = r_i P_D q_i(z_j)`` with
   ``q_i`` the mixture likelihood over ``κ``, in log space;
5. association (:meth:`LMBFilter._associate`): any
   :class:`~rankedassign.tracking.Association` returns the marginals ``β`` of every
   problem; a group without measurements is solved in closed form;
6. update from the marginals (6.3–6.4, :meth:`LMBFilter._posterior`): ``r_i = Σ_{j≥0} β_ij``
   and the posterior mixture ``(1/r_i) Σ_j β_ij p^(j)``;
7. track pruning and cap, then mixture pruning, merging and cap
   (:meth:`LMBFilter._prune_and_merge`, one compiled kernel per scan);
8. state extraction (:meth:`LMBFilter._extract`: hysteresis 6.5, the MAP cardinality, or the
   MAP cardinality of every cluster of the scan, :func:`cluster_map_tracks`).

The Kalman algebra is batched with numpy over all components; the per-pair likelihoods, the
log-sum-exp over each mixture, the cost matrices and the mixture reduction run in compiled
kernels (:mod:`rankedassign.tracking._kernels`), which repeat numpy's operations in numpy's
order, so the filter's numbers do not depend on which of the two computes them.
"""

from __future__ import annotations

import copy
import dataclasses
import math
from time import perf_counter
from typing import NamedTuple

import numpy as np

from ...engine.rng import spawning_generator
from ...numba_options import interruptible
from ...single.problem import AssignmentProblem
from ...validation import check_bool, check_choice, check_int, check_real, check_type
from .. import _kernels
from .._checks import check_prior
from .._kernels import MERGE_RULES
from ..association import Association, AssociationResult, check_truncation
from ..birth import BirthComponents, MeasurementBirth
from ..common import BETA_TOL, gate_threshold
from ..common import check_distribution as _check_distribution
from ..common import check_measurements as _check_measurements
from ..gating import GatedPairs, clusters, gate_pairs
from ..models import EXTRACTIONS, ConstantVelocity, LinearMotion, Model
from ..nonlinear.step import single_object
from ..nonlinear.vo import NonlinearModel
from ..protocol import record_base
from . import _glmb_kernels
from .glmb import _zobrist

__all__ = [
    "BETA_TOL",
    "EXTRACTIONS",
    "ESTIMATES",
    "MERGE_RULES",
    "LMBFilter",
    "SPATIAL_BATCH_PAIRS",
    "LMB_EXTRACTIONS",
    "SPATIAL_MIN_PAIRS",
    "ScanRecord",
    "cluster_map_tracks",
    "gate_threshold",
    "group_tracks",
    "map_cardinality",
]

#: State estimates of a reported track (``estimate``).
ESTIMATES = ("max-weight", "mean")
#: With ``grouping=True`` and a gate, a scan of ``T`` predicted tracks and ``M`` measurements
#: with ``T * M`` at least this many pairs is gated through a k-d tree and solved cluster by
#: cluster (:meth:`LMBFilter._spatial_scan`, about ``O((T + M) log(T + M))`` outside the
#: clusters' own work) instead of through the dense ``(T, M)`` terms. Both give the same
#: gate, clusters, problems and random streams; a track's posterior existence
#: ``Σ_j β_ij`` is summed over its cluster's columns rather than over every gated column, so the
#: two agree to rounding (about 1e-16), not bit for bit. Smaller scans, which the recorded
#: digests cover, keep the dense path. The bound (``2**20``, about 900 tracks against 1 200
#: measurements) is about where the dense terms' ``O(T M)`` cost overtakes the cluster path's
#: Python work per batch of clusters (both paths took 0.36-0.63 s a scan at N = 1 000 on the
#: ``large`` scenario, the cluster path 0.8-1.4 s against 1.3-3.5 s at N = 3 000).
SPATIAL_MIN_PAIRS = 1 << 20
#: The cluster path computes the terms and the posterior of consecutive clusters together, in
#: batches of at most this many (tracks x measurements) pairs.
SPATIAL_BATCH_PAIRS = 4096

#: The LMB filter's state extractions: those a model can carry (:data:`EXTRACTIONS`) and
#: ``"cluster-map"``, the MAP cardinality of every cluster of the scan
#: (:func:`cluster_map_tracks`).
LMB_EXTRACTIONS = EXTRACTIONS + ("cluster-map",)



def group_tracks(gated: np.ndarray) -> list[tuple[np.ndarray, np.ndarray]]:
    """Split tracks into groups that share no gated measurement (spec §6.5a).

    Parameters
    ----------
    gated : ndarray of bool, shape (T, M)
        ``gated[i, j]``: measurement ``j`` is in the gate of track ``i``.

    Returns
    -------
    list of (rows, cols)
        Connected components of the bipartite track–measurement graph: sorted int arrays of
        track and measurement indices, ordered by their first track. Tracks that gate nothing are
        singleton groups with no measurement; measurements that no track gates belong to no group.

    Raises
    ------
    ValueError
        If ``gated`` is not 2-D.

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign.tracking.single.lmb import group_tracks
    >>> g = np.array([[1, 0, 0], [0, 0, 1], [1, 1, 0], [0, 0, 0]], dtype=bool)
    >>> [(r.tolist(), c.tolist()) for r, c in group_tracks(g)]
    [([0, 2], [0, 1]), ([1], [2]), ([3], [])]
    """
    gated = np.ascontiguousarray(gated, dtype=np.bool_)
    if gated.ndim != 2:
        raise ValueError(f"gated must be a 2-D (T, M) array, got shape {gated.shape}")
    # the sparse connected components (near-linear in the gated pairs) give the partition and
    # numbering of the dense kernel _kernels.connected_groups, without its T x M x T scan
    track, meas = np.nonzero(gated)
    pairs = GatedPairs(track.astype(np.int64), meas.astype(np.int64), gated.shape[0],
                       gated.shape[1], int(track.size))
    return clusters(pairs).groups()


def map_cardinality(r: np.ndarray) -> int:
    """MAP cardinality of an LMB with existence probabilities ``r`` (Vo's default extraction).

    The cardinality distribution of independent Bernoullis is the Poisson-binomial, computed by
    the convolution recursion; ties go to the smaller cardinality.

    Parameters
    ----------
    r : array_like of float, shape (T,)
        Existence probabilities of the ``T`` tracks, in ``[0, 1]`` (any shape is flattened;
        converted to float64).

    Returns
    -------
    int
        ``argmax_n ρ(n)`` of the Poisson-binomial ``ρ`` on ``0..T``: the number of tracks to
        report, 0 for no track.

    Examples
    --------
    >>> from rankedassign.tracking.single.lmb import map_cardinality
    >>> map_cardinality([0.9, 0.8, 0.1]), map_cardinality([])
    (2, 0)
    """
    r = np.ascontiguousarray(r, dtype=np.float64).reshape(-1)
    with interruptible:
        return int(np.argmax(_kernels.cardinality_distribution(r)))


def cluster_map_tracks(r, cluster) -> np.ndarray:
    """The tracks the MAP cardinality of every cluster reports (the ``"cluster-map"`` extraction).

    Within each cluster the ``n̂_c = argmax_n ρ_c(n)`` most likely tracks are reported, with
    ``ρ_c`` the Poisson-binomial cardinality distribution of the cluster's tracks
    (:func:`map_cardinality`); ties of ``r`` go to the earlier track, as in the global MAP
    extraction.

    Parameters
    ----------
    r : array_like of float, shape (T,)
        Existence probabilities, in ``[0, 1]`` (converted to float64).
    cluster : array_like of int, shape (T,)
        Cluster of every track (any integers; tracks with equal values form one cluster).

    Returns
    -------
    ndarray of int64
        Sorted indices of the reported tracks. With every track in one cluster they are those
        of the global MAP extraction (the ``n̂ = map_cardinality(r)`` most likely tracks).

    Raises
    ------
    ValueError
        If ``r`` and ``cluster`` differ in length.

    Notes
    -----
    The cardinalities of independent clusters are independent, so the vector
    ``(n̂_1, …, n̂_K)`` is the mode of their joint distribution, where the global MAP is the
    mode of their sum only. With ``N`` tracks of existence ``r ≈ 0.99`` in clusters of a few
    tracks each, the global MAP cardinality falls about ``Σ_i (1 − r_i)`` short of ``N`` and
    leaves that many likely tracks unreported; each cluster's own MAP reports all of them. A
    cluster of one track reports it when ``r > 1 − r`` (``r > 0.5``), the comparison
    :func:`map_cardinality` makes for one track.

    Examples
    --------
    >>> from rankedassign.tracking.single.lmb import cluster_map_tracks, map_cardinality
    >>> r = [0.99, 0.99, 0.6, 0.4, 0.45]
    >>> map_cardinality(r), cluster_map_tracks(r, [0, 0, 0, 0, 0]).tolist()
    (3, [0, 1, 2])
    >>> cluster_map_tracks(r, [0, 1, 2, 3, 4]).tolist()
    [0, 1, 2]
    >>> cluster_map_tracks([0.7, 0.7, 0.2], [0, 0, 1]).tolist()
    [0, 1]
    """
    r = np.ascontiguousarray(r, dtype=np.float64).reshape(-1)
    cluster = np.asarray(cluster).reshape(-1)
    if cluster.size != r.size:
        raise ValueError(f"cluster has {cluster.size} entries for {r.size} tracks")
    T = r.size
    if T == 0:
        return np.empty(0, dtype=np.int64)
    _, cid = np.unique(cluster, return_inverse=True)
    cid = cid.reshape(-1).astype(np.int64)
    sizes = np.bincount(cid)
    # n̂_c: a one-track cluster's ρ = [1 − r, r], argmax 1 iff r > 1 − r (ties to 0)
    n_hat = np.zeros(sizes.size, dtype=np.int64)
    lone = sizes[cid] == 1
    n_hat[cid[lone]] = (r[lone] > 1.0 - r[lone]).astype(np.int64)
    # every cluster's tracks by decreasing r, ties in track order (lexsort is stable)
    order = np.lexsort((-r, cid))
    start = np.concatenate([[0], np.cumsum(sizes)[:-1]])
    # ρ_c convolved over the cluster's tracks in track order, the order map_cardinality(r)
    # takes with one cluster (so that it is the global MAP there, bit for bit)
    members = np.argsort(cid, kind="stable")
    for size in np.unique(sizes[sizes > 1]).tolist():
        cs = np.flatnonzero(sizes == size)
        if cs.size == 1 or size > 64:
            for c in cs.tolist():
                n_hat[c] = map_cardinality(r[members[start[c]:start[c] + size]])
            continue
        # every cluster of this size at once (a large scene has thousands of small ones): the
        # kernel's recursion ρ_k ← ρ_k (1 − r_i) + ρ_{k−1} r_i, ρ_0 ← ρ_0 (1 − r_i) with the
        # same operations, row by row
        q = r[members[start[cs][:, None] + np.arange(size)]]
        rho = np.zeros((cs.size, size + 1))
        rho[:, 0] = 1.0
        for i in range(size):
            qi = q[:, i:i + 1]
            pi = 1.0 - qi
            rho[:, 1:] = rho[:, 1:] * pi + rho[:, :-1] * qi
            rho[:, :1] *= pi
        n_hat[cs] = np.argmax(rho, axis=1)
    c_of = cid[order]
    rank = np.arange(T) - start[c_of]
    return np.sort(order[rank < n_hat[c_of]]).astype(np.int64)


class ScanRecord(record_base("ScanRecord")):
    """What the filter reports for one scan.

    Attributes
    ----------
    labels : ndarray of int64, shape (n, 2)
        Labels ``(birth scan, birth index)`` (both 1-based) of the reported tracks.
    states : ndarray, shape (n, d)
        Their state estimates (``d = 4`` on a linear model, the model's state dimension on a
        non-linear one).
    existence : ndarray, shape (n,)
        Their existence probabilities.
    track_labels, track_existence : ndarray
        Every track kept after the update, ``(T, 2)`` and ``(T,)``.
    n_tracks : int
        Predicted tracks (rows of the association, births included).
    n_meas, n_meas_gated : int
        Measurements received and measurements in some gate.
    n_groups : int
        Problems solved by the association (0 when no measurement is gated).
    invocations, sweeps, row_updates, n_unique : int
        Association accounting summed over the problems of the scan.
    timings : dict
        Seconds spent in ``prediction``, ``cost``, ``association``, ``update``.
    """

    __slots__ = ()  # no instance dict: a plain named tuple, fields from record_base


# ------------------------------------------------------------------------------- filter
class LMBFilter:
    """Compact LMB filter with Gaussian-mixture tracks and pluggable association.

    Parameters
    ----------
    model : Model or NonlinearModel
        Motion, sensor, clutter, birth and survival models. A
        :class:`~rankedassign.tracking.nonlinear.NonlinearModel` (e.g. ``make_model("vo-ekf")``)
        runs its single-object filter (Kalman, EKF or UKF) through
        :mod:`rankedassign.tracking.nonlinear.step`; a linear :class:`Model` the compiled
        Kalman kernels.
    association : Association or callable
        Called as ``association(problem, rng)`` on every ranked-assignment problem. The
        multi-sensor associations
        (:class:`~rankedassign.tracking.multisensor.association.MultiSensorAssociation`) are
        refused: they belong to :class:`~rankedassign.tracking.MultiSensorLMBFilter`. The
        marginals it returns must be finite and non-negative with rows summing to 1 (within
        :data:`BETA_TOL`).
    gate_prob : float or None, optional
        χ² gate probability (default ``0.9999999``, spec §6.3); None disables gating (every
        measurement enters every row).
    grouping : bool, optional
        Solve independent groups of tracks separately (spec §6.5a). Default False (one problem
        per scan, as in Vo's code). ``True`` or ``False`` only (a string is refused).
    sample_empty_groups : bool, optional
        Hand problems without gated measurements (with grouping: the groups of tracks that gate
        nothing) to the association too, instead of solving them in closed form. The posterior
        is the same in expectation; only the association's cost and counters change. The
        paper's observation totals fit a sampler call on every group, these included
        (ambiguity A13; see the Tracking page of the documentation). Default False.
    extraction : {"hysteresis", "map", "cluster-map"} or None, optional
        Hysteresis state extraction (6.5, the paper), the MAP cardinality of Vo's code
        (:data:`EXTRACTIONS`), or the MAP cardinality of every cluster of the scan
        (``"cluster-map"``, :func:`cluster_map_tracks`: the tracks linked through shared gated
        measurements, as ``grouping=True`` forms them, whatever ``grouping`` is; for large
        scenes, where the global MAP cardinality leaves about ``Σ_i (1 − r_i)`` likely tracks
        unreported). None (default): the model's own,
        :attr:`Model.extraction <rankedassign.tracking.models.Model>`, which is the preset's
        for a model of :func:`~rankedassign.tracking.models.make_model`
        (:data:`~rankedassign.tracking.models.PRESET_EXTRACTION`: MAP cardinality for
        ``"vo"``, as Vo's example; hysteresis for ``"paper"``) and hysteresis for a
        :class:`~rankedassign.tracking.models.Model` built by hand. An explicit value wins; the
        attribute :attr:`extraction` says which one the filter took.
    theta_upper, theta_lower : float, optional
        Hysteresis thresholds ``ϑ_u = 0.9`` and ``ϑ_l = 10⁻³``.
    prune_track : float, optional
        Drop tracks with ``r <= prune_track`` (default ``10⁻³``).
    max_tracks : int, optional
        Keep at most this many tracks, the most likely ones (default 100).
    prune_component, merge_threshold, max_components : float, float, int, optional
        Mixture pruning (``10⁻⁵``), merging (4) and cap (10) per track.
    merge_rule : {"bhattacharyya", "vo-ma", "heaviest"}, optional
        Which pairs of components merge (``tracking._kernels.reduce_mixtures``): eight times their
        Bhattacharyya distance at most ``merge_threshold`` (default; the Mahalanobis test when
        the two covariances are equal), the Mahalanobis distance in the candidate's covariance
        (Vo & Ma 2006), or in the heaviest component's covariance (Vo's MATLAB).
    estimate : {"max-weight", "mean"}, optional
        State estimate of a reported track: mean of its heaviest component (Vo's code) or of the
        whole mixture.
    birth : MeasurementBirth or None, optional
        None (default): the model's static birth at every scan. A
        :class:`~rankedassign.tracking.birth.MeasurementBirth`: the births of scan ``k + 1``
        are made from the measurements of scan ``k`` that the tracks do not explain,
        ``r_A(z_j) = Σ_i β_ij`` (Reuter et al. 2014, adaptive birth); the model's static
        birth is not used.

    Notes
    -----
    Rows of every problem are the persisting tracks in their order, then the births (A21).
    A problem without measurements factorises over rows and is solved in closed form
    (``β_i0 ∝ η_i(0)``, ``β_i,−1 ∝ η_i(−1)``) without calling the association; it counts no
    invocation (unless ``sample_empty_groups``). Pair ``(i, j)`` passes the gate when the
    squared Mahalanobis distance of ``z_j`` to *some* component of track ``i`` is at most the
    threshold; its ``q_i(z_j)`` uses every component. A component weight ``β_ij / r_i · w̃``
    below the pruning threshold would be pruned, so pairs with
    ``β_ij / r_i <= prune_component`` are not expanded at all.

    References
    ----------
    .. [1] S. Reuter, B.-T. Vo, B.-N. Vo, K. Dietmayer, "The Labeled Multi-Bernoulli Filter",
       IEEE Trans. Signal Process. 62(12), 2014.
    .. [2] B.-N. Vo, B.-T. Vo, H. G. Hoang, "An Efficient Implementation of the Generalized
       Labeled Multi-Bernoulli Filter", IEEE Trans. Signal Process. 65(8), 2017.
    .. [3] A. Trezza, D. J. Bucci Jr., P. K. Varshney, "On Gibbs Sampling Architecture for
       Labeled Random Finite Sets Multi-Object Tracking", arXiv:2306.15135, 2023.

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign.tracking import LMBFilter, make_model
    >>> from rankedassign.tracking.single.association import Association, AssociationResult
    >>> class AllMissed(Association):     # a trivial association, for illustration only
    ...     def __call__(self, problem, rng):
    ...         beta = np.zeros((problem.n_rows, problem.n_meas + 2))
    ...         beta[:, problem.n_meas] = 1.0
    ...         return AssociationResult(beta, 1, 0, 0, 1)
    >>> f = LMBFilter(make_model("paper"), AllMissed())
    >>> rec = f.step(np.array([[0.0, 0.0]]), rng=0)
    >>> rec.n_tracks, rec.track_labels.tolist()
    (4, [[1, 1], [1, 2], [1, 3], [1, 4]])

    The extraction travels with a preset's model; an explicit ``extraction`` wins:

    >>> LMBFilter(make_model("vo"), AllMissed()).extraction
    'map'
    >>> LMBFilter(make_model("vo"), AllMissed(), extraction="hysteresis").extraction
    'hysteresis'
    """

    #: The extractions this filter takes (the multi-sensor filter: :data:`EXTRACTIONS` only).
    _extractions = LMB_EXTRACTIONS

    def __init__(
        self,
        model: Model,
        association: Association,
        *,
        gate_prob: float | None = 0.9999999,
        grouping: bool = False,
        sample_empty_groups: bool = False,
        extraction: str | None = None,
        theta_upper: float = 0.9,
        theta_lower: float = 1e-3,
        prune_track: float = 1e-3,
        max_tracks: int = 100,
        prune_component: float = 1e-5,
        merge_threshold: float = 4.0,
        merge_rule: str = "bhattacharyya",
        max_components: int = 10,
        estimate: str = "max-weight",
        birth: MeasurementBirth | None = None,
    ):
        check_type(model, "model", (Model, NonlinearModel),
                   "build one with make_model(preset) or Model(...)")
        self._check_association(association)
        if birth is not None:
            check_type(birth, "birth", MeasurementBirth,
                       "None for the model's static birth or MeasurementBirth(...)")
            # a prior of the wrong dimension is refused now, not at the first scan
            birth.births_from(np.empty((0, np.shape(model.sensor.R)[0])), np.empty(0),
                              model.sensor)
        #: The measurement-driven birth in use, or None for the model's static birth.
        self.birth = birth
        #: The state extraction in use: ``extraction``, or the model's when that is None.
        self.extraction = check_choice(model.extraction if extraction is None else extraction,
                                       "extraction", self._extractions)
        self.estimate = check_choice(estimate, "estimate", ESTIMATES)
        self.merge_rule = check_choice(merge_rule, "merge_rule", tuple(MERGE_RULES))
        self.theta_upper = check_real(theta_upper, "theta_upper", minimum=0.0, maximum=1.0)
        self.theta_lower = check_real(theta_lower, "theta_lower", minimum=0.0,
                                      maximum=self.theta_upper)
        self.prune_track = check_real(prune_track, "prune_track", minimum=0.0)
        if self.prune_track >= 1:
            raise ValueError(f"prune_track must be < 1, got {self.prune_track}")
        self.prune_component = check_real(prune_component, "prune_component", minimum=0.0)
        if self.prune_component >= 1:
            raise ValueError(f"prune_component must be < 1, got {self.prune_component}")
        self.merge_threshold = check_real(merge_threshold, "merge_threshold", minimum=0.0,
                                          finite=False)
        self.max_tracks = check_int(max_tracks, "max_tracks", minimum=1)
        self.max_components = check_int(max_components, "max_components", minimum=1)
        self.model = model
        self.association = association
        # chains the cluster path may run for many problems in one compiled call (the
        # truncation's own plan; None: one call of the association per problem)
        plan = getattr(association, "batch_plan", None)
        plan = plan(self._sensors) if callable(plan) else None
        self._chain_batch = None
        if plan is not None and plan.chains and plan.marginal_chains is not None:
            self._chain_batch = (plan.marginal_chains, _glmb_kernels.ChainRules(
                random_scan=plan.random_scan, tau_stall=plan.tau_stall,
                tau_stale=plan.tau_stale))
        #: The single-object path of a non-linear model (None: the linear Kalman kernels).
        self._so = single_object(model)
        self._d = 4 if self._so is None else self._so.ndim
        self._dz = 2 if self._so is None else self._so.meas_ndim
        self.gate = None if gate_prob is None else gate_threshold(gate_prob, self._dz)
        self.grouping = check_bool(grouping, "grouping")
        self.sample_empty_groups = check_bool(sample_empty_groups, "sample_empty_groups")
        self._rule = MERGE_RULES[self.merge_rule]
        if self._so is not None:
            self._nonlinear_constants(self._so)
            self.reset()
            return
        # model matrices and constants, cached
        self._F = np.array(model.motion.F)
        self._FT = self._F.T
        self._Q = np.array(model.motion.Q)
        self._R = np.array(model.sensor.R)
        self._pd = float(model.sensor.p_d)
        self._ps = float(model.survival.p_s)
        self._log_pd = math.log(self._pd)
        self._log_miss = math.log1p(-self._pd) if self._pd < 1 else -np.inf
        self._log_kappa = math.log(model.clutter.intensity)
        self._birth_r = model.birth.r
        self._birth_m = model.birth.means
        self._birth_P = model.birth.covs
        self._birth_index = np.arange(1, self._birth_r.size + 1, dtype=np.int64)
        self.reset()

    def _nonlinear_constants(self, so) -> None:
        """The constants of a non-linear model (the prediction and update are ``so``'s)."""
        self._pd = so.p_d
        self._ps = so.p_s
        self._log_pd = math.log(self._pd)
        self._log_miss = math.log1p(-self._pd) if self._pd < 1 else -np.inf
        self._log_kappa = math.log(so.clutter_intensity)
        self._birth_r = so.birth_r
        self._birth_m = so.birth_m
        self._birth_P = so.birth_P
        self._birth_index = np.arange(1, self._birth_r.size + 1, dtype=np.int64)

    #: The problems this filter's association solves (:func:`check_truncation`).
    _sensors = "single-sensor"

    def _check_association(self, association) -> None:
        """Refuse what this filter cannot use, with the reason (one place for every filter)."""
        check_truncation(association, type(self).__name__, self._sensors, "marginals")

    def set_motion(self, motion) -> None:
        """Predict with ``motion`` from the next scan on (the tracks are kept).

        For a motion model whose matrices depend on the time between scans (a Stone Soup
        transition model, :class:`rankedassign.stonesoup.LMBTracker`); :attr:`model` becomes
        the model with this motion.

        Parameters
        ----------
        motion : ConstantVelocity or LinearMotion
            The motion model of the next prediction(s).

        Raises
        ------
        TypeError
            If ``motion`` is neither, or the filter runs a non-linear model.

        Examples
        --------
        >>> import numpy as np
        >>> from rankedassign.tracking import Exact, LMBFilter, make_model
        >>> from rankedassign.tracking.models import LinearMotion
        >>> f = LMBFilter(make_model("paper"), Exact())
        >>> f.set_motion(LinearMotion(np.eye(4), np.zeros((4, 4))))
        >>> f.model.motion.F.tolist() == np.eye(4).tolist()
        True
        """
        if self._so is not None:  # a motion of the non-linear interface, same dimension
            self._so.set_motion(motion, type(self).__name__)
            self.model = dataclasses.replace(self.model, motion=motion)
            return
        check_type(motion, "motion", (ConstantVelocity, LinearMotion))
        self.model = dataclasses.replace(self.model, motion=motion)
        self._F = np.array(motion.F)
        self._FT = self._F.T
        self._Q = np.array(motion.Q)

    # ----------------------------------------------------------------------- state
    def reset(self) -> None:
        """Forget every track and restart at scan 1."""
        self.k = 0
        self.labels = np.empty((0, 2), dtype=np.int64)
        self.r = np.empty(0)
        self.offsets = np.zeros(1, dtype=np.int64)
        self.w = np.empty(0)
        self.m = np.empty((0, self._d))
        self.P = np.empty((0, self._d, self._d))
        self.confirmed = np.empty(0, dtype=bool)
        if getattr(self, "birth", None) is not None:
            self._set_measurement_births(BirthComponents.empty())

    def _set_measurement_births(self, b: BirthComponents) -> None:
        """The births the next prediction appends (means and covariances not yet predicted)."""
        self._birth_r = np.ascontiguousarray(b.r, dtype=np.float64)
        d = self._d
        self._birth_m = np.ascontiguousarray(b.means, dtype=np.float64).reshape(-1, d)
        self._birth_P = np.ascontiguousarray(b.covs, dtype=np.float64).reshape(-1, d, d)
        self._birth_index = np.arange(1, self._birth_r.size + 1, dtype=np.int64)

    def _measurement_births(self, z: np.ndarray, r_A: np.ndarray) -> float:
        """Make the next scan's births from ``r_A(z_j) = Σ_i β_ij``; return the seconds."""
        t0 = perf_counter()
        self._set_measurement_births(self.birth.births_from(
            z, r_A, self.model.sensor))
        return perf_counter() - t0

    def set_prior(self, labels, means, covs, existence=None) -> None:
        """Start from an LMB prior of single-Gaussian tracks (instead of no track).

        Parameters
        ----------
        labels : array_like of int, shape (T, 2)
            Distinct labels ``(birth scan, index)``, as
            :meth:`GLMBFilter.set_prior <rankedassign.tracking.GLMBFilter.set_prior>` takes
            them (birth scan 0 for tracks known before the first scan).
        means, covs : array_like, shapes (T, 4) and (T, 4, 4)
            Their Gaussians: finite means, symmetric positive definite covariances.
        existence : array_like, shape (T,), optional
            Existence probabilities in ``(0, 1]`` (default 1). The tracks start confirmed
            where ``r >= theta_upper``.

        Raises
        ------
        TypeError, ValueError
            As :meth:`GLMBFilter.set_prior <rankedassign.tracking.GLMBFilter.set_prior>`;
            ``ValueError`` for existence probabilities of the wrong shape or outside
            ``(0, 1]``.

        Examples
        --------
        >>> import numpy as np
        >>> from rankedassign.tracking import Exact, LMBFilter, make_model
        >>> f = LMBFilter(make_model("vo"), Exact())
        >>> f.set_prior([[0, 1]], np.zeros((1, 4)), np.eye(4)[None], existence=[0.5])
        >>> f.n_tracks, f.r.tolist()
        (1, [0.5])
        """
        labels, means, covs, _, _ = check_prior(labels, means, covs, None, None,
                                                max_birth_index=int(self._birth_r.size))
        T = labels.shape[0]
        r = np.ones(T) if existence is None else np.asarray(existence, dtype=np.float64)
        if r.shape != (T,) or not np.all((r > 0) & (r <= 1)):
            raise ValueError(f"existence must be {T} probabilities in (0, 1], got "
                             f"{np.asarray(existence).tolist()!r}")
        self.reset()
        self.labels = labels.copy()
        self.r = r.copy()
        self.offsets = np.arange(T + 1, dtype=np.int64)
        self.w = np.ones(T)
        self.m = np.ascontiguousarray(means, dtype=np.float64)
        self.P = np.ascontiguousarray(covs, dtype=np.float64)
        self.confirmed = r >= self.theta_upper

    @property
    def n_tracks(self) -> int:
        """Number of tracks currently held."""
        return int(self.r.size)

    def track_index(self) -> np.ndarray:
        """Track of every component, shape (C,).

        Returns
        -------
        ndarray of int64, shape (C,)
            ``C`` is the total number of Gaussian components: entry ``c`` is the (0-based)
            index into ``labels`` and ``r`` of the track that owns component ``c``
            (components ``offsets[i]:offsets[i + 1]`` belong to track ``i``), non-decreasing.
        """
        return np.repeat(np.arange(self.n_tracks), np.diff(self.offsets))

    # ----------------------------------------------------------------------- 1. prediction
    def predict(self) -> None:
        """LMB prediction (spec 6.1): survive, propagate, append the births of the next scan.

        Called by :meth:`step`; public for tests and for custom update loops.

        Examples
        --------
        >>> from rankedassign.tracking import Exact, LMBFilter, make_model
        >>> f = LMBFilter(make_model("paper"), Exact())
        >>> f.predict()
        >>> f.n_tracks, f.r.tolist()
        (4, [0.03, 0.03, 0.03, 0.03])
        """
        self.k += 1
        if self._so is not None:  # through the motion model (Kalman, EKF or UKF)
            self.m, self.P = self._so.predict(self.m, self.P)
        else:
            F = self._F
            # m <- F m ; P <- F P F' + Q ; r <- P_S r (weights and labels kept)
            self.m = self.m @ self._FT
            self.P = F @ self.P @ self._FT + self._Q
        self.r = self._ps * self.r
        self._append_births()

    def _append_births(self) -> None:
        """Append the birth Bernoullis of scan ``k``, labels ``(k, 1..B)``, one component each."""
        B = self._birth_r.size
        labels = np.empty((B, 2), dtype=np.int64)
        labels[:, 0] = self.k
        labels[:, 1] = self._birth_index
        birth_m, birth_P = self._birth_m, self._birth_P
        measured = getattr(self, "birth", None) is not None
        if measured and self._so is not None:
            # measurement births sit at the last scan's time: predict them with this scan's
            # motion (the model's filter), as every track
            birth_m, birth_P = self._so.predict(birth_m, birth_P)
        elif measured:
            birth_m = birth_m @ self._FT
            birth_P = self._F @ birth_P @ self._FT + self._Q
        self.labels = np.concatenate([self.labels, labels])
        self.r = np.concatenate([self.r, self._birth_r])
        if self._so is not None and not measured:  # Gaussian-mixture birth terms
            self.offsets = np.concatenate([self.offsets,
                                           self.w.size + np.cumsum(self._so.birth_counts)])
            self.w = np.concatenate([self.w, self._so.birth_w])
        else:
            self.offsets = np.concatenate([self.offsets, self.w.size + self._birth_index])
            self.w = np.concatenate([self.w, np.ones(B)])
        self.m = np.concatenate([self.m, birth_m])
        self.P = np.concatenate([self.P, birth_P])
        self.confirmed = np.concatenate([self.confirmed, np.zeros(B, dtype=bool)])

    # ----------------------------------------------------------------------- 2. likelihoods
    def _measurement_terms(self, z: np.ndarray) -> _Terms:
        """Likelihoods of one measurement array against the predicted tracks, and the gate.

        Keeps the measurements that some track gates (all of them without gating) and returns
        per component the innovation statistics the update needs, per track the log-weights
        ``ln η`` of eq. (6.2).
        """
        T = self.n_tracks
        M = z.shape[0]
        if M == 0:
            return _Terms.empty(self, T)
        gate = 0.0 if self.gate is None else self.gate
        gain = None
        if self._so is not None:  # the model's filter: wrapped innovations, any d, d_z
            st = self._so.measurement_terms(self.m, self.P, z, self.offsets, self.gate)
            maha, log_det_S, nu, gated = st.maha, st.log_det_S, st.nu, st.gated
            Sinv, gain = None, (st.gain, st.P_upd)
        else:
            with interruptible:
                det, Sinv, nu, maha, gated = _kernels.gate_and_distances(
                    self.m, self.P, self._R, z, self.offsets, gate, self.gate is not None
                )
            log_det_S = np.log(det)
        used = np.flatnonzero(gated.any(axis=0))
        # C order whatever numpy's fancy indexing returns: one signature of the kernels below
        # (a Fortran-ordered `gated` or a strided `nu` compiled each a second time)
        gated = np.ascontiguousarray(gated[:, used])
        with np.errstate(divide="ignore"):
            log_r = np.log(self.r)
            log_dead = np.log1p(-self.r)
        # ln w_c + ln N(z_j; H m_c, S_c), ln Σ_c w_c N(...) per track, ln η_t(j) (6.2)
        with interruptible:
            lw, log_g, log_det = _kernels.detection_log_weights(
                maha, log_det_S, np.log(self.w), self.offsets, used, gated, log_r,
                self._log_pd, self._log_kappa,
            )
        return _Terms(
            used=used, gated=gated, Sinv=Sinv, nu=np.ascontiguousarray(nu[:, used]), lw=lw,
            log_g=log_g, log_det=log_det, log_miss=log_r + self._log_miss, log_dead=log_dead,
            gain=gain,
        )

    # ----------------------------------------------------------------------- 3.-5. association
    def _groups(self, terms: _Terms) -> list[tuple[np.ndarray, np.ndarray]]:
        """The problems of the scan: one group per connected component, or all tracks in one."""
        if self.grouping and terms.used.size:
            return group_tracks(terms.gated)
        return [(np.arange(self.n_tracks), np.arange(terms.used.size))]

    @staticmethod
    def _group_problem(terms: _Terms, rows: np.ndarray, cols: np.ndarray) -> AssignmentProblem:
        """The ranked-assignment problem (cost ``−ln η``, paper layout) of tracks ``rows``."""
        with interruptible:
            cost = _kernels.group_cost_matrix(terms.log_det, terms.log_miss, terms.log_dead,
                                              rows, cols)
        return AssignmentProblem(cost)

    def _associate(self, terms: _Terms, groups, gen: np.random.Generator):
        """Marginals ``β`` (T, U + 2) of every group and the accounting summed over them."""
        T = self.n_tracks
        U = terms.used.size
        beta = np.zeros((T, U + 2))
        sample_empty = self.sample_empty_groups
        n_problems = sum(1 for _, cols in groups if cols.size or sample_empty)
        children = iter(gen.spawn(n_problems)) if n_problems else iter(())
        counts = np.zeros(4, dtype=np.int64)  # invocations, sweeps, row updates, unique
        beta = self._fill_marginals(beta, terms, groups, children, counts)
        return beta, n_problems, counts

    def _fill_marginals(self, beta, terms: _Terms, groups, children, counts) -> np.ndarray:
        """Write the marginals of every group into ``beta`` (T, U + 2), one child stream per
        problem from ``children``; returns ``beta`` (a new array for one whole problem)."""
        T, U = terms.gated.shape
        sample_empty = self.sample_empty_groups
        for rows, cols in groups:
            if cols.size == 0 and not sample_empty:
                beta[rows, -2:] = self._closed_form(terms, rows)
                continue
            b = self._group_marginals(terms, rows, cols, next(children), counts)
            if rows.size == T and cols.size == U:  # one problem: every track and measurement
                beta = np.ascontiguousarray(b)
            else:
                beta[np.ix_(rows, cols)] = b[:, :-2]
                beta[rows, -2] = b[:, -2]
                beta[rows, -1] = b[:, -1]
        return beta

    @staticmethod
    def _closed_form(terms: _Terms, rows: np.ndarray) -> np.ndarray:
        """``[β_missed, β_dead]`` of rows without gated measurements: independent Bernoullis."""
        lm, ld = terms.log_miss[rows], terms.log_dead[rows]
        top = np.maximum(lm, ld)
        em, ed = np.exp(lm - top), np.exp(ld - top)
        return np.column_stack([em / (em + ed), ed / (em + ed)])

    def _group_marginals(self, terms: _Terms, rows, cols, child, counts) -> np.ndarray:
        """The association's checked marginals ``(P, M + 2)`` of one group; adds its counts."""
        res = self.association(self._group_problem(terms, rows, cols), child)
        if not isinstance(res, AssociationResult):
            res = AssociationResult(*res)
        b = np.asarray(res.beta, dtype=np.float64)
        if b.shape != (rows.size, cols.size + 2):
            raise ValueError(
                f"association returned beta of shape {b.shape}, expected "
                f"{(rows.size, cols.size + 2)}"
            )
        _check_distribution(self.association, {"beta": b}, b.sum(axis=1),
                            "beta[{i}, :].sum()")
        whole = rows.size == terms.gated.shape[0] and cols.size == terms.gated.shape[1]
        gated = terms.gated if whole else terms.gated[np.ix_(rows, cols)]
        if (b[:, :-2][~gated] != 0).any():
            # a forbidden pair (cost +inf) has marginal 0; the update does not compute its
            # likelihoods
            raise ValueError("association returned a nonzero marginal for a pair outside "
                             "the gate (a forbidden pair of the problem)")
        counts += (int(res.invocations), int(res.sweeps), int(res.row_updates),
                   int(res.n_unique))
        return b

    # ----------------------------------------------------------------------- spatial path
    def _use_spatial(self, T: int, M: int) -> bool:
        """Gate through the k-d tree and solve cluster by cluster (see SPATIAL_MIN_PAIRS)."""
        return self.grouping and self.gate is not None and T * M >= SPATIAL_MIN_PAIRS

    def _subset(self, rows: np.ndarray) -> LMBFilter:
        """A shallow copy of the filter holding only the predicted tracks ``rows``."""
        sub = copy.copy(self)
        n = np.diff(self.offsets)[rows]
        starts = np.cumsum(n) - n
        comp = np.repeat(self.offsets[rows] - starts, n) + np.arange(int(n.sum()))
        sub.offsets = np.concatenate([[0], np.cumsum(n)]).astype(np.int64)
        sub.w = self.w[comp]
        sub.m = self.m[comp]
        sub.P = self.P[comp]
        sub.r = self.r[rows]
        sub.labels = self.labels[rows]
        sub.confirmed = self.confirmed[rows]
        return sub

    def _spatial_scan(self, z: np.ndarray, gen: np.random.Generator):
        """Gate, clusters, association and posterior of one scan, cluster by cluster.

        The gate is :func:`~rankedassign.tracking.gating.gate_pairs` (a k-d tree of the
        measurements, the exact χ² test on its candidates), the groups
        :func:`~rankedassign.tracking.gating.clusters`: the same groups, in the same order and
        with the same child streams as the dense path. The terms and the posterior are computed
        for batches of consecutive clusters (:meth:`_batches`) on their own tracks and
        measurements, each cluster's problem on its rows and columns of the batch; the tracks
        that gate nothing are updated together in closed form. Returns the gated measurements'
        count, the problems, the counts, the posterior existence and mixtures (as
        :meth:`_posterior`) and the phase timings.
        """
        t0 = perf_counter()
        T = self.n_tracks
        if self._so is None:
            pairs = gate_pairs(self.m, self.P, self._R, z, self.offsets, self.gate)
        else:  # in the sensor's own coordinates (a bearing wraps)
            pairs = self._so.gate_pairs(self.m, self.P, z, self.offsets, self.gate)
        found = clusters(pairs)
        groups = found.groups()
        n_used = int(np.unique(pairs.meas).size)
        sample_empty = self.sample_empty_groups
        n_problems = sum(1 for _, cols in groups if cols.size or sample_empty)
        children = iter(gen.spawn(n_problems)) if n_problems else iter(())
        counts = np.zeros(4, dtype=np.int64)
        t_assoc = t_update = 0.0
        parts = []
        lone = [rows for rows, cols in groups if cols.size == 0 and not sample_empty]
        if lone:
            rows = np.concatenate(lone)
            sub = self._subset(rows)
            terms = _Terms.empty(sub, rows.size)
            beta = np.zeros((rows.size, 2))
            beta[:, -2:] = sub._closed_form(terms, np.arange(rows.size))
            parts.append((rows, *self._part_posterior(sub, np.empty((0, 2)), beta, terms)))
        t_cost = perf_counter() - t0
        # the association probability of every measurement, for the measurement birth: a
        # measurement no track gates has none (0)
        r_A = np.zeros(z.shape[0]) if self.birth is not None else None
        for batch in self._batches([g for g in groups if g[1].size or sample_empty]):
            ta = perf_counter()
            rows = np.concatenate([r for r, _ in batch])
            cols = np.unique(np.concatenate([c for _, c in batch]))
            sub = self._subset(rows)
            zc = z[cols]
            terms = sub._measurement_terms(zc)
            tb = perf_counter()
            beta = self._chain_marginals(terms, batch, children, counts)
            if beta is None:  # one call of the association per cluster
                # each cluster's rows and columns within the batch's terms
                local, start = [], 0
                for r, c in batch:
                    pos = np.searchsorted(terms.used, np.searchsorted(cols, c))
                    local.append((np.arange(start, start + r.size), pos))
                    start += r.size
                beta = np.zeros((rows.size, terms.used.size + 2))
                beta = sub._fill_marginals(beta, terms, local, children, counts)
            tc = perf_counter()
            if r_A is not None:  # r_A(z_j) = Σ_i β_ij over the batch's tracks
                r_A[cols[terms.used]] = beta[:, :terms.used.size].sum(axis=0)
            parts.append((rows, *self._part_posterior(sub, zc[terms.used], beta, terms)))
            t_cost += tb - ta
            t_assoc += tc - tb
            t_update += perf_counter() - tc
        td = perf_counter()
        r_new = np.empty(T)
        all_rows = np.concatenate([p[0] for p in parts])
        r_new[all_rows] = np.concatenate([p[1] for p in parts])
        n_comp = np.concatenate([np.diff(p[2]) for p in parts])
        start = np.cumsum(n_comp) - n_comp
        order = np.argsort(all_rows, kind="stable")  # the parts' tracks back in table order
        n_sorted = n_comp[order]
        idx = (np.repeat(start[order] - (np.cumsum(n_sorted) - n_sorted), n_sorted)
               + np.arange(int(n_sorted.sum())))
        w = np.concatenate([p[3] for p in parts])[idx]
        m = np.concatenate([p[4] for p in parts])[idx]
        P = np.concatenate([p[5] for p in parts])[idx]
        offsets = np.concatenate([[0], np.cumsum(n_sorted)]).astype(np.int64)
        t_update += perf_counter() - td
        return (n_used, n_problems, counts, r_new, (offsets, w, m, P),
                {"cost": t_cost, "association": t_assoc, "update": t_update}, r_A,
                found.track_cluster)

    def _chain_marginals(self, terms: _Terms, batch, children, counts) -> np.ndarray | None:
        """The truncated marginals ``β`` (T_b, U_b + 2) of every cluster of a batch, the chains
        of all of them in one compiled call; None when the association has no such plan.

        Each cluster is a component of
        :func:`~rankedassign.tracking.single._glmb_kernels.sample_components` (its rows, no
        births) with the base key its child stream would draw in
        :func:`rankedassign.sample_short_chains`, so its unique assignments, their costs
        (summed row by row, left to right, as ``AssignmentProblem._sum_costs``) and the
        marginals ``β_ij = Σ_h w_h 1[γ_i^(h) = j]`` (summed over ``h`` in discovery order, as
        :func:`~rankedassign.tracking._kernels.truncated_marginals`) are those of one call of
        the association per cluster, bit for bit; the Python work per cluster is one key and
        one sum.
        """
        if self._chain_batch is None or self.sample_empty_groups:
            return None
        (n_chains, chain_length), rules = self._chain_batch
        T, U = terms.gated.shape
        log_miss = terms.log_miss
        if not np.isfinite(log_miss).all():
            # the samplers refuse an all-missed start with a row that cannot be missed; the
            # per-problem path says so
            return None
        sizes = np.array([r.size for r, _ in batch], dtype=np.int64)
        H = sizes.size
        comp_off = np.concatenate([[0], np.cumsum(sizes)]).astype(np.int64)
        # −ln η over [gated measurements | missed | dead] and the samplers' shifted weights
        # (rankedassign.single.prepare.shifted_weights: a row's minimum is over its own
        # cluster's columns, the others are +inf)
        cc = np.empty((T, U + 2))
        cc[:, :U] = -terms.log_det
        cc[:, U] = -log_miss
        cc[:, U + 1] = -terms.log_dead
        W = np.exp(-(cc - cc.min(axis=1, keepdims=True)))
        # The kernel sizes its work space for every observation being new (chains x sweeps
        # + 1 states a cluster). A cluster has at most F <= Π_i (m_i + 2) feasible assignments
        # (m_i: row i's gated measurements), so the stall rule ends a chain within F tau_stall
        # sweeps and the stale rule the run within F tau_stale chains (each new assignment
        # resets a counter, at most F - 1 are new): budgets cut to those bounds run the same
        # chains, draw for draw.
        feasible = np.multiply.reduceat(terms.gated.sum(axis=1) + 2.0, comp_off[:-1])
        chains = np.full(H, n_chains, dtype=np.int64)
        length = np.full(H, chain_length, dtype=np.int64)
        if rules.tau_stale > 0:
            chains = np.minimum(chains, np.minimum(feasible * rules.tau_stale, n_chains)
                                .astype(np.int64))
        if rules.tau_stall > 0:
            length = np.minimum(length, np.minimum(feasible * rules.tau_stall, chain_length)
                                .astype(np.int64))
        # the base key sample_short_chains draws from each cluster's child stream
        base = np.array([int(next(children).integers(0, 2**63, dtype=np.uint64))
                         for _ in range(H)], dtype=np.uint64)
        with interruptible:
            comp, cost, off, entry, meas, sweeps, n_rows = _glmb_kernels.sample_components(
                comp_off, np.arange(T, dtype=np.int64), np.empty(0, dtype=np.int64), W, cc,
                np.ascontiguousarray(terms.gated), chains, length, rules, base,
                _zobrist(int(sizes.max()), U + 2))
        N = comp.size
        # w_h ∝ exp(−cost_h), normalised per cluster as single_marginals does: the shift by
        # the largest −cost, then the division by the cluster's sum (numpy's own summation)
        first = np.searchsorted(comp, np.arange(H))
        neg = -cost
        lw = neg - np.maximum.reduceat(neg, first)[comp]
        w = np.exp(lw)
        bounds = np.append(first, N).tolist()
        total = np.array([w[a:b].sum() for a, b in zip(bounds[:-1], bounds[1:], strict=True)])
        w = w / total[comp]
        # every (child, row of its cluster): dead unless the child lists the row
        n_slot = sizes[comp]
        slot0 = np.cumsum(n_slot) - n_slot
        child = np.repeat(np.arange(N), n_slot)
        row = np.repeat(comp_off[comp] - slot0, n_slot) + np.arange(int(n_slot.sum()))
        col = np.full(row.size, U + 1, dtype=np.int64)
        listed = np.repeat(np.arange(N), np.diff(off))
        col[slot0[listed] + entry - comp_off[comp[listed]]] = np.where(meas >= 0, meas, U)
        # Σ_h w_h over the children in order (bincount adds in the order of its input)
        beta = np.bincount(row * (U + 2) + col, weights=w[child],
                           minlength=T * (U + 2)).reshape(T, U + 2)
        counts += (H, int(sweeps.sum()), int((sweeps * n_rows).sum()), N)
        return beta

    @staticmethod
    def _batches(groups):
        """Consecutive clusters in batches of at most ``SPATIAL_BATCH_PAIRS`` (rows x columns)
        pairs: one call of the terms and of the posterior per batch, not per cluster (the
        Python work per call is what a scan of many small clusters costs); a larger cluster
        is a batch of its own."""
        batch, n_rows, n_cols = [], 0, 0
        for rows, cols in groups:
            if batch and (n_rows + rows.size) * (n_cols + cols.size) > SPATIAL_BATCH_PAIRS:
                yield batch
                batch, n_rows, n_cols = [], 0, 0
            batch.append((rows, cols))
            n_rows += rows.size
            n_cols += cols.size
        if batch:
            yield batch

    @staticmethod
    def _part_posterior(sub: LMBFilter, z, b, terms):
        r_new, (offsets, w, m, P) = sub._posterior(z, np.ascontiguousarray(b), terms)
        return r_new, offsets, w, m, P

    # ----------------------------------------------------------------------- the scan
    def step(self, z, rng=None) -> ScanRecord:
        """Run one scan: predict, build the problem(s), associate, update, extract.

        Parameters
        ----------
        z : array_like, shape (M, d_z)
            Measurements of the scan (positions, ``d_z = 2``, on a linear model; the sensor's
            own on a non-linear one, e.g. ``[bearing, range]``).
        rng : optional
            Randomness of the association (anything :func:`numpy.random.default_rng` accepts);
            one child stream per problem is spawned from it. A
            :class:`numpy.random.RandomState` is replaced by the Generator seeded with one draw
            from it (:func:`rankedassign.engine.rng.spawning_generator`).

        Returns
        -------
        ScanRecord

        Raises
        ------
        TypeError
            On measurements that are not real numbers (strings, booleans, complex), or an
            ``rng`` numpy cannot seed from.
        ValueError
            On measurements not of shape ``(M, 2)`` (``[]``, shape ``(0,)``, and shape
            ``(0, 2)`` are a scan without measurements), ragged or non-finite measurements, an
            invalid seed, or if the association returns ``beta`` of the wrong shape, with a
            non-finite or negative entry, with a row not summing to 1 (:data:`BETA_TOL`) or
            with weight on a forbidden pair.

        Examples
        --------
        >>> import numpy as np
        >>> from rankedassign.tracking import LMBFilter, Murty, make_model
        >>> f = LMBFilter(make_model("vo"), Murty(50))
        >>> for k in range(3):          # one target near birth location 2, no clutter
        ...     rec = f.step([[400.0 - 10 * k, -600.0 + 5 * k]], rng=k)
        >>> rec.labels.tolist(), rec.existence.round(3).tolist()
        ([[1, 2]], [1.0])
        """
        z = _check_measurements(z) if self._so is None else self._so.check_measurements(z)
        gen = spawning_generator(rng)
        t0 = perf_counter()
        self.predict()
        t1 = perf_counter()
        T = self.n_tracks
        M_all = z.shape[0]
        if T == 0:  # an empty birth model and no tracks: nothing to associate
            t2 = perf_counter()
            timings = {"prediction": t1 - t0, "cost": t2 - t1, "association": 0.0,
                       "update": 0.0}
            if self.birth is not None:   # no track explains anything: r_A = 0
                timings["birth"] = self._measurement_births(z, np.zeros(z.shape[0]))
            return ScanRecord(
                labels=np.empty((0, 2), np.int64), states=np.empty((0, self._d)),
                existence=np.empty(0), track_labels=self.labels.copy(),
                track_existence=self.r.copy(), n_tracks=0, n_meas=M_all, n_meas_gated=0,
                n_groups=0, invocations=0, sweeps=0, row_updates=0, n_unique=0,
                timings=timings,
            )
        r_A = None
        if self._use_spatial(T, M_all):
            (n_used, n_problems, counts, r_new, mixture, phases, r_A,
             track_cluster) = self._spatial_scan(z, gen)
            t2 = t1 + phases["cost"]
            t3 = t2 + phases["association"]
            t_upd = perf_counter()
            keep = self._prune_and_merge(r_new, *mixture)
            labels, states, ex = self._extract(track_cluster[keep])
            t4 = t3 + phases["update"] + (perf_counter() - t_upd)
        else:
            terms = self._measurement_terms(z)
            groups = self._groups(terms)
            n_used = int(terms.used.size)
            t2 = perf_counter()
            beta, n_problems, counts = self._associate(terms, groups, gen)
            t3 = perf_counter()
            r_new, mixture = self._posterior(z[terms.used], beta, terms)
            keep = self._prune_and_merge(r_new, *mixture)
            cluster = None
            if self.extraction == "cluster-map":
                # the clusters of the gate, whether or not the association was grouped
                track, meas = np.nonzero(terms.gated)
                cluster = clusters(GatedPairs(track.astype(np.int64), meas.astype(np.int64),
                                              T, terms.gated.shape[1], int(track.size))
                                   ).track_cluster[keep]
            labels, states, ex = self._extract(cluster)
            t4 = perf_counter()
        inv, sweeps, rows_upd, n_unique = counts.tolist()
        timings = {"prediction": t1 - t0, "cost": t2 - t1, "association": t3 - t2,
                   "update": t4 - t3}
        if self.birth is not None:
            if r_A is None:  # the dense path: Σ_i β_ij over every track
                r_A = np.zeros(z.shape[0])
                r_A[terms.used] = beta[:, :terms.used.size].sum(axis=0)
            timings["birth"] = self._measurement_births(z, r_A)
        return ScanRecord(
            labels=labels, states=states, existence=ex, track_labels=self.labels.copy(),
            track_existence=self.r.copy(), n_tracks=T, n_meas=M_all,
            n_meas_gated=n_used, n_groups=n_problems, invocations=inv,
            sweeps=sweeps, row_updates=rows_upd, n_unique=n_unique, timings=timings,
        )

    # ----------------------------------------------------------------------- 6. update
    def _posterior(self, z, beta, terms: _Terms):
        """Posterior existence and mixtures from the marginals (6.3, 6.4), before pruning.

        Returns ``r_new`` (T,) and ``(offsets, w, m, P)`` of the posterior components, grouped
        by track: the missed-detection components first, then the updates with each
        measurement in turn.
        """
        M = z.shape[0]
        Sinv, nu, lw, log_g = terms.Sinv, terms.nu, terms.lw, terms.log_g
        # r_i = Σ_{j >= 0} β_ij  (6.3)
        r_new = np.clip(beta[:, : M + 1].sum(axis=1), 0.0, 1.0)
        safe_r = np.where(r_new > 0, r_new, 1.0)
        rel = beta[:, : M + 1] / safe_r[:, None]  # β_ij / r_i, (T, M + 1)
        # which predicted component, track and measurement (-1: missed) each posterior
        # component comes from, grouped by track
        with interruptible:
            comp, track, meas, log_ratio, counts = _kernels.posterior_sources(
                self.offsets, rel, self.prune_component, lw, log_g
            )
        # w̃_cj = w_c N(z_j; H m_c, S_c) / Σ_c' w_c' N(z_j; H m_c', S_c')
        ratio = np.exp(log_ratio)
        if self._so is not None:  # the non-linear path: K = C S⁻¹, P' from the model's filter
            d, dz = self._d, self._dz
            K, P_upd = terms.gain or (np.empty((0, d, dz)), np.empty((0, d, d)))
            w_all, m_all, P_all = self._so.posterior_components(
                comp, track, meas, ratio, rel, self.w, self.m, self.P, K, nu, P_upd)
            offsets = np.concatenate([[0], np.cumsum(counts)]).astype(np.int64)
            return r_new, (offsets, w_all, m_all, P_all)
        if (meas >= 0).any():
            # Kalman gain and updated covariance per component: K = P H' S⁻¹, P' = P − K S K'
            PHt = self.P[:, :, [0, 2]]  # (C, 4, 2)
            K = PHt @ Sinv
            P_upd = self.P - K @ PHt.transpose(0, 2, 1)
            P_upd = 0.5 * (P_upd + P_upd.transpose(0, 2, 1))
        else:
            K, P_upd = np.empty((0, 4, 2)), np.empty((0, 4, 4))
        with interruptible:
            w_all, m_all, P_all = _kernels.posterior_components(
                comp, track, meas, ratio, rel, self.w, self.m, self.P, K, nu, P_upd
            )
        offsets = np.concatenate([[0], np.cumsum(counts)]).astype(np.int64)
        return r_new, (offsets, w_all, m_all, P_all)

    # ----------------------------------------------------------------------- 7. housekeeping
    def _prune_and_merge(self, r_new, offsets, w, m, P) -> np.ndarray:
        """Drop unlikely tracks (``r <= prune_track``, then all but the ``max_tracks`` most
        likely) and prune, merge and cap every kept mixture (``_kernels.reduce_mixtures``).
        Returns the mask of the kept tracks, shape (T,)."""
        T = r_new.size
        keep = (r_new > self.prune_track) & (offsets[1:] > offsets[:-1])
        if keep.sum() > self.max_tracks:
            cand = np.flatnonzero(keep)
            best = cand[np.argsort(-r_new[cand], kind="stable")[: self.max_tracks]]
            keep = np.zeros(T, dtype=bool)
            keep[best] = True
        # weights within each track sum to Σ_j β_ij / r_i · Σ w̃ = 1 before pruning
        reduce = _kernels.reduce_mixtures if self._so is None else self._so.reduce_mixtures
        with interruptible:
            self.offsets, self.w, self.m, self.P = reduce(
                offsets, np.ascontiguousarray(w), np.ascontiguousarray(m), np.ascontiguousarray(P),
                keep, self.prune_component, self.merge_threshold, self.max_components, self._rule,
            )
        self.r = r_new[keep]
        self.labels = self.labels[keep]
        self.confirmed = self.confirmed[keep]
        return keep

    # ----------------------------------------------------------------------- 8. extraction
    def _extract(self, cluster=None):
        """Labels, states and existence of the reported tracks (hysteresis 6.5, MAP, or MAP per
        cluster: ``cluster`` (T,) is every kept track's cluster of the scan, None for one)."""
        r = self.r
        if self.extraction == "hysteresis":
            # confirmed_k = [r >= ϑ_u] or (confirmed_{k-1} and r >= ϑ_l)   (6.5)
            self.confirmed = (r >= self.theta_upper) | (self.confirmed & (r >= self.theta_lower))
            sel = np.flatnonzero(self.confirmed)
        elif self.extraction == "cluster-map":
            sel = cluster_map_tracks(r, np.zeros(r.size, np.int64) if cluster is None
                                     else cluster)
        else:
            n_hat = map_cardinality(r)
            sel = np.sort(np.argsort(-r, kind="stable")[:n_hat])
        if self.estimate == "max-weight":
            states = self.m[self.offsets[sel]]  # components are sorted by decreasing weight
        else:
            wm = self.w[:, None] * self.m
            sums = np.add.reduceat(wm, self.offsets[:-1], axis=0) if wm.size else wm
            states = sums[sel] if sel.size else np.empty((0, self._d))
        return self.labels[sel], np.array(states).reshape(-1, self._d), r[sel]


class _Terms(NamedTuple):
    """Per-scan quantities of one measurement array (``U`` = measurements some track gates)."""

    used: np.ndarray  # (U,) kept measurement columns
    gated: np.ndarray  # (T, U) bool
    Sinv: np.ndarray  # (C, 2, 2) inverse innovation covariances
    nu: np.ndarray  # (C, U, 2) innovations
    lw: np.ndarray  # (C, U) ln w_c + ln N(z_j; H m_c, S_c)
    log_g: np.ndarray  # (T, U) ln Σ_c w_c N(z_j; H m_c, S_c)
    log_det: np.ndarray  # (T, U) ln η_t(j), -inf outside the gate
    log_miss: np.ndarray  # (T,) ln η_t(0)
    log_dead: np.ndarray  # (T,) ln η_t(-1)
    gain: tuple | None = None  # non-linear path: (K (C, d, d_z), P' (C, d, d)); else None

    @classmethod
    def empty(cls, filt: LMBFilter, T: int) -> _Terms:
        """The terms of a scan without measurements."""
        with np.errstate(divide="ignore"):
            log_r = np.log(filt.r)
            log_dead = np.log1p(-filt.r)
        C = filt.w.size
        return cls(
            used=np.empty(0, dtype=np.int64), gated=np.zeros((T, 0), dtype=bool),
            Sinv=np.empty((C, 2, 2)), nu=np.empty((C, 0, filt._dz)), lw=np.empty((C, 0)),
            log_g=np.empty((T, 0)), log_det=np.empty((T, 0)),
            log_miss=log_r + filt._log_miss, log_dead=log_dead,
        )



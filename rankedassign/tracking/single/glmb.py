"""The δ-GLMB filter with joint prediction and update (Vo, Vo & Hoang 2017).

A δ-GLMB density is a weighted list of *components* ``(w_h, I_h)``: ``I_h`` is a set of entries
of a shared *track table*, whose every entry holds a label ``ℓ = (birth scan, birth index)``, a
Gaussian mixture and the association history ``ξ`` (the measurement per scan since birth).
One scan of :class:`GLMBFilter` (``../shared/spec/glmb.md`` §2) runs these phases:

1. prediction (:meth:`GLMBFilter._predict`): every entry ``m ← F m``, ``P ← F P Fᵀ + Q``; the
   births of the scan are appended to the table;
2. shared terms (:meth:`GLMBFilter._terms`): per (entry, measurement) the likelihoods, the
   χ² gate and ``−ln η`` (spec §2.1) once for every entry — every component's cost matrix is
   gathered from them, never recomputed;
3. allocation: ``T_h = round(H_upd √w_h / Σ √w)`` (spec §2.2);
4. truncation (:meth:`GLMBFilter._truncate`): the association turns each component's problem
   into unique assignments ``γ``; the Gibbs samplers run for all components in one compiled
   call (:func:`rankedassign.tracking.single._glmb_kernels.sample_components`);
5. children (:meth:`GLMBFilter._update`): ``ln w = ln w_h − cost(γ)``, normalised together;
   children with the same track set merged; pruning, the ``H_max`` cap, the new track table
   (unused entries dropped) and the Kalman update of the entries kept;
6. estimation (:meth:`GLMBFilter._extract`): MAP cardinality and the heaviest component, the
   trajectories along the histories (of the best hypothesis, or Vo's recursive estimator),
   or hysteresis on ``r(ℓ)`` (spec §3).

The per-(track, measurement) algebra is that of the LMB filter
(:mod:`rankedassign.tracking._kernels`), so both filters see the same numbers.
"""

from __future__ import annotations

import dataclasses
import math
import numbers
from time import perf_counter
from typing import NamedTuple

import numpy as np

from oracle.single.dp import PlanCache, compact_log_normalizer

from ...engine.rng import spawning_generator
from ...numba_options import interruptible
from ...single.problem import AssignmentProblem
from ...validation import (
    MAX_WORK_BYTES,
    check_bool,
    check_choice,
    check_int,
    check_real,
    check_type,
)
from .. import _kernels
from .._checks import check_prior
from .._kernels import MERGE_RULES
from ..association import EXACT_LIMIT, Hypotheses, check_truncation, truncate
from ..birth import BirthComponents, MeasurementBirth
from ..common import Children as _Children
from ..common import check_measurements as _check_measurements
from ..common import concat as _concat
from ..common import gate_threshold, retained_ratio, zobrist_table
from ..common import logsumexp as _logsumexp
from ..models import ConstantVelocity, LinearMotion, Model
from ..nonlinear.step import single_object
from ..nonlinear.vo import NonlinearModel
from ..protocol import record_base
from . import _glmb_kernels

__all__ = [
    "GLMB_EXTRACTIONS",
    "GLMBFilter",
    "GLMBScanRecord",
    "Hypotheses",
    "truncate",
]

#: State extraction rules of :class:`GLMBFilter` (``extraction``).
GLMB_EXTRACTIONS = ("map", "trajectory", "recursive", "hysteresis")
#: Largest number of assignments :class:`~rankedassign.tracking.Exact` keeps in one scan, over
#: all components (their children must fit in memory before the merge and the cap).
EXACT_SCAN_LIMIT = 5_000_000
#: Assignments per compiled call of the Murty and Exact truncations (a slice of components).
_RANKED_SLICE = 20_000
_ZOBRIST_SEED = np.uint64(0x6A09E667F3BCC909)
_TWO63 = 2**63


class GLMBScanRecord(record_base(
        "GLMBScanRecord", cardinality=np.ndarray, n_components=int, retained_mass=float,
        carried_mass=float, retained_mass_reason=str, trajectories=tuple)):
    """What :class:`GLMBFilter` reports for one scan.

    The first fields are those of :class:`~rankedassign.tracking.ScanRecord` that apply.

    Attributes
    ----------
    labels : ndarray of int64, shape (n, 2)
        Labels of the reported tracks, in increasing order.
    states : ndarray, shape (n, d)
        Their state estimates (mean of the heaviest Gaussian of the track's entry; ``d = 4``
        on a linear model, the model's state dimension on a non-linear one).
    existence : ndarray, shape (n,)
        Their existence probabilities ``r(ℓ)``.
    track_labels, track_existence : ndarray
        Every label of the posterior with ``r(ℓ) = Σ_{h: ℓ ∈ L(I_h)} w_h``, the GLMB → LMB
        conversion (spec §1), ``(L, 2)`` in increasing order and ``(L,)``.
    n_tracks : int
        Entries of the predicted track table (births included).
    n_meas, n_meas_gated : int
        Measurements received and measurements in some entry's gate.
    n_groups : int
        Problems solved (one per prior component).
    invocations, sweeps, row_updates, n_unique : int
        Association calls, Markov-chain observations, single-row draws and unique
        assignments (children before merging), summed over the components.
    timings : dict
        Seconds spent in ``prediction``, ``cost``, ``association``, ``update``.
    cardinality : ndarray, shape (n_max + 1,)
        ``ρ(n) = Σ_{h: |I_h| = n} w_h``.
    n_components : int
        Components kept after pruning and capping.
    retained_mass : float
        ``Σ_h w_h K_h / Σ_h w_h Z_h`` (spec §4): the share of the exact posterior the
        truncation keeps, *before* the scan's merge, prune and ``H_max`` cap; NaN when not
        computed or not available.
    carried_mass : float
        The share of the exact posterior the filter carries into the next scan:
        ``retained_mass`` times the normalised weight of the merged components that survive
        the pruning and the cap (``<= retained_mass``, equal when nothing is pruned or
        capped); NaN when ``retained_mass`` is.
    retained_mass_reason : str
        Why ``retained_mass`` (and ``carried_mass``) is NaN ("" when it is a number).
    trajectories : tuple
        With ``extraction="trajectory"``: per reported track ``(label, scans, states)``, the
        scans (1-based) since its birth and its filtered state at each. With
        ``extraction="recursive"``: the same for every label the estimator has reported so
        far, in increasing label order, a label that left the best hypothesis with the
        trajectory it had when it was last in it. Else empty.
    """

    __slots__ = ()  # no instance dict: a plain named tuple, fields from record_base


# ------------------------------------------------------------------------------- truncation
def _check_count(value, name: str) -> int:
    """A positive int option (``h_upd``, ``h_max``): ValueError for a non-integer number too."""
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise TypeError(f"{name} must be a positive integer, got {type(value).__name__} "
                        f"{value!r}")
    if not isinstance(value, numbers.Integral) or value < 1:
        raise ValueError(f"{name} must be a positive integer, got {value!r}")
    return check_int(value, name, minimum=1)


def _check_threshold(value, name: str) -> float:
    """A probability threshold in ``[0, 1)``."""
    v = check_real(value, name)
    if not 0.0 <= v < 1.0:
        raise ValueError(f"{name} must be in [0, 1), got {v!r}")
    return v


def _gibbs_budget(association, counts: np.ndarray):
    """Chains and sweeps per chain of every component (the chain truncation's ``budget``)."""
    return association.budget(counts)


def _unique_inverse(x: np.ndarray, bound: int | None = None) -> tuple[np.ndarray, np.ndarray]:
    """``np.unique(x, return_inverse=True)`` of a 1-D int64 array, with the inverse as int64.

    The same two arrays (the sorted distinct values are unique, and so is the index of each
    value among them), with less of ``np.unique``'s fixed cost: the clustered filter runs
    thousands of scans of a few entries each, three of these per scan.

    With ``bound`` (every value in ``0 .. bound − 1``) no larger than about twice the size of
    ``x``, and ``x`` of 512 values or more, the values are marked in a table of ``bound``
    flags instead of sorted: linear in the size of ``x``, where a scan of the exact δ-GLMB
    filter keys millions of children's entries (10.9 million below 80 in one test). Measured
    on 100 000 values below 80: 0.23 ms against 4.0 ms for the sort; on 20 values the sort is
    faster (6.0 against 8.5 µs).
    """
    if bound is not None and 512 <= x.size and bound <= 2 * x.size + 4096:
        present = np.zeros(bound, dtype=np.bool_)
        present[x] = True
        rank = np.cumsum(present, dtype=np.int64)
        rank -= 1
        return np.flatnonzero(present).astype(np.int64, copy=False), rank[x]
    s = np.sort(x)
    if s.size:
        s = s[np.concatenate(([True], s[1:] != s[:-1]))]
    return s, np.searchsorted(s, x).astype(np.int64, copy=False)


def _zobrist(L: int, K: int) -> np.ndarray:
    """Zobrist keys for problems of at most ``L`` rows and ``K − 2`` columns (cached, read-only)."""
    return zobrist_table(L, K, _ZOBRIST_SEED)


class _Terms(NamedTuple):
    """The scan's shared per-(entry, measurement) terms (``U`` gated measurements)."""

    used: np.ndarray  # (U,) measurement indices in some gate
    gated: np.ndarray  # (T, U) bool
    Sinv: np.ndarray  # (C, 2, 2)
    nu: np.ndarray  # (C, U, 2) innovations
    lw: np.ndarray  # (C, U) ln w_c N(z_j; H m_c, S_c)
    log_g: np.ndarray  # (T, U) ln Σ_c w_c N(z_j; ...)
    log_det: np.ndarray  # (T, U) ln η_t(j)
    log_miss: np.ndarray  # (T,) ln η_t(0)
    log_dead: np.ndarray  # (T,) ln η_t(−1)
    cc: np.ndarray  # (T, U + 2) −ln η over [measurements | missed | dead]
    W: np.ndarray  # (T, U + 2) exp(−(cc − row minimum))
    gain: tuple | None = None  # non-linear path: (K (C, d, d_z), P' (C, d, d)); else None


#: Bytes of the work array of :func:`_component_groups`' adjacency (one slice of components).
_GROUP_BYTES = 1 << 24


def _component_groups(comp_off, comp_tracks, births, gated):
    """The gate groups of every component's problem, for all components at once.

    Component ``h``'s rows are the births, then its entries (the order of
    :func:`~rankedassign.tracking.single._glmb_kernels.component_problem`); its groups are the
    connected components of those rows linked by shared gated measurements, in the order of
    their first row, each row in its group in row order: the partition and order of
    :func:`~rankedassign.tracking.gating.clusters` on the component's gate, found here for
    every component by one label propagation over a padded ``(H, P, P)`` adjacency rather
    than by a graph search per component.

    Returns
    -------
    None when no component has a row, else
    uniq : ndarray of int64, shape (G, P_max)
        The distinct groups in the order of their first use, their entries in row order,
        padded with ``-1``.
    first : ndarray of int64, shape (G,)
        Index of the first use of each distinct group in the list of all groups (components in
        order, each component's groups in order).
    inv : ndarray of int64, shape (n_groups,)
        The distinct group of every group of that list.
    g_comp : ndarray of int64, shape (n_groups,)
        The component of every group of that list.
    """
    H = comp_off.size - 1
    B = births.size
    sizes = np.diff(comp_off)
    P_max = B + int(sizes.max(initial=0))
    if H == 0 or P_max == 0:
        return None
    R = np.full((H, P_max), -1, dtype=np.int64)
    R[:, :B] = births
    pos = np.arange(comp_tracks.size) - np.repeat(comp_off[:-1], sizes)
    R[np.repeat(np.arange(H), sizes), B + pos] = comp_tracks
    valid = R >= 0
    # rows of a component that share a gated measurement, on the gate's bytes (a BLAS product
    # of the gate cost more than all the rest: its threads, on small matrices), in slices of
    # components so that the work array stays within _GROUP_BYTES whatever the scene's size
    packed = np.packbits(gated, axis=1)[np.where(valid, R, 0)]  # (H, P, bytes)
    adj = np.empty((H, P_max, P_max), dtype=bool)
    step = max(1, _GROUP_BYTES // (P_max * P_max * max(packed.shape[2], 1)))
    for h0 in range(0, H, step):
        pr = packed[h0:h0 + step]
        adj[h0:h0 + step] = (pr[:, :, None, :] & pr[:, None, :, :]).any(axis=3)
    adj |= np.eye(P_max, dtype=bool)  # every row with itself
    adj &= valid[:, :, None] & valid[:, None, :]
    # every row takes the least row position it reaches: its group's first row
    lab = np.broadcast_to(np.arange(P_max, dtype=np.int32), (H, P_max)).copy()
    while True:
        new = np.where(adj, lab[:, None, :], P_max).min(axis=2)
        new = np.where(valid, new, lab)
        if np.array_equal(new, lab):
            break
        lab = new
    hh, aa = np.nonzero(valid)
    ll = lab[hh, aa]
    order = np.lexsort((aa, ll, hh))  # by component, group, row
    hh, aa, ll = hh[order], aa[order], ll[order]
    start = np.r_[True, (hh[1:] != hh[:-1]) | (ll[1:] != ll[:-1])]
    gidx = np.cumsum(start) - 1
    starts = np.flatnonzero(start)
    groups = np.full((starts.size, P_max), -1, dtype=np.int64)
    groups[gidx, np.arange(hh.size) - starts[gidx]] = R[hh, aa]
    # distinct groups in the order of first use, by their bytes (np.unique(axis=0) sorts
    # structured rows, several times slower at a few thousand groups a scan)
    index: dict = {}
    inv = np.fromiter((index.setdefault(row, len(index))
                       for row in map(bytes, groups)), dtype=np.int64, count=starts.size)
    first = np.full(len(index), starts.size, dtype=np.int64)
    np.minimum.at(first, inv, np.arange(starts.size))
    return groups[first], first, inv, hh[starts]


# ------------------------------------------------------------------------------- the filter
class GLMBFilter:
    """δ-GLMB filter with joint prediction and update and pluggable truncation.

    Parameters
    ----------
    model : Model or NonlinearModel
        Motion, sensor, clutter, birth and survival models (as :class:`LMBFilter`; a
        :class:`~rankedassign.tracking.nonlinear.NonlinearModel` runs its EKF or UKF).
    association : OriginalGibbs, ShortChainGibbs, Murty, Exact or object
        The truncation of every component's problem, with the component's count ``T_h``
        (spec §2.3): :class:`~rankedassign.tracking.OriginalGibbs` runs one chain of
        ``min(T_h − 1, n_obs)`` sweeps (``T_h`` stored solutions with the all-missed start, as
        Vo's code); :class:`~rankedassign.tracking.ShortChainGibbs` chains of
        ``L = min(N_C, T_h − 1)`` sweeps, at most ``min(N_S, ⌈(T_h − 1) / L⌉)`` of them, with
        its stall and stale rules; :class:`~rankedassign.tracking.Murty` the
        ``min(k, max(T_h, 1))`` best; :class:`~rankedassign.tracking.Exact` every assignment
        (at most :data:`EXACT_LIMIT` per component and :data:`EXACT_SCAN_LIMIT` per scan, else
        ``ValueError``). Any object with a method
        ``hypotheses(problem, budget, rng)`` returning :class:`Hypotheses` works too. An
        association that gives marginals only (LBP, a plain LMB association) is refused with
        ``TypeError``.
    h_upd : int, optional
        ``H_upd``, the scan's total count (default 1000).
    h_max : int, optional
        ``H_max``, components kept (default 1000).
    prune_hypothesis : float, optional
        Drop components with ``w < prune_hypothesis`` (default ``10⁻¹⁵``), in ``[0, 1)``.
    gate_prob : float or None, optional
        χ² gate probability (default ``1 − 10⁻⁷``, Vo's); None disables gating.
    extraction : {"map", "trajectory", "recursive", "hysteresis"} or None, optional
        None (default): the model's :attr:`~rankedassign.tracking.Model.extraction` (its preset's:
        ``"map"`` for ``"vo"``, ``"hysteresis"`` for ``"paper"``). ``"map"`` (Vo's): the MAP
        cardinality ``n̂ = argmax ρ``, the heaviest component with ``n̂`` tracks, the mean of each
        track's heaviest Gaussian. ``"trajectory"``: the same tracks, and each one's filtered states
        along its association history (the record's ``trajectories``, :class:`GLMBScanRecord`): the
        trajectories of the current best hypothesis only, so a label that leaves it loses its past.
        ``"recursive"`` (Vo's ``extract_estimates_recursive``): the same tracks and, besides, the
        trajectory of every label that was ever in the best hypothesis; a label still in it has its
        past rewritten to its current association history, a label that left keeps the trajectory it
        had (:meth:`trajectory_estimates` gives every scan's rewritten estimate, the one to score
        with OSPA(2)). ``"hysteresis"``: labels with ``r(ℓ) >= theta_upper``, kept while ``r(ℓ) >=
        theta_lower`` (the paper's rule, spec 6.5), each with its heaviest entry.
    theta_upper, theta_lower : float, optional
        Hysteresis thresholds (0.9 and ``10⁻³``), in ``[0, 1)``.
    prune_component, merge_threshold, max_components, merge_rule : optional
        Mixture reduction of every entry, as :class:`LMBFilter` (``10⁻⁵``, 4, 10,
        ``"bhattacharyya"``).
    retained_mass : bool, optional
        Compute the record's ``retained_mass`` (spec §4) and ``carried_mass``
        (:class:`GLMBScanRecord`) with the oracle's DP (default False: it costs one
        exact normaliser per gate group of a component).
    keep_histories : bool or None, optional
        Keep every entry's whole association history: the trajectories of
        ``extraction="trajectory"`` and the histories of :meth:`components` read it, and it
        grows by one node (56 bytes) per live entry and scan, with the ages of the tracks.
        False keeps only the last scan's node, so the state stays bounded by the caps however
        long the run (an entry is told apart by its table index, never by its history, so the
        filter's numbers do not change). None (default): True for
        ``extraction="trajectory"`` and ``"recursive"``, else False.
    birth : MeasurementBirth or None, optional
        None (default): the model's static birth at every scan. A
        :class:`~rankedassign.tracking.birth.MeasurementBirth`: the births of scan ``k + 1``
        are made from the measurements of scan ``k`` that the tracks do not explain,
        ``r_A(z) = Σ_h w_h [some entry of component h took z]`` (Reuter et al. 2014, adaptive
        birth); the model's static birth is not used.

    Notes
    -----
    Rows of a component's problem are the births of the scan, then its entries in table order
    (spec §2.1); ``η(−1) = 1 − r_B`` or ``1 − P_S``, ``η(0) = r_B (1 − P_D)`` or
    ``P_S (1 − P_D)``, ``η(j) = r_B P_D q(z_j) / κ`` or ``P_S P_D q(z_j) / κ``. Its columns are
    the measurements some row gates. The terms are computed once per scan for every entry of
    the predicted table (:class:`_Terms`) and gathered per component. A child's log weight is
    ``ln w_h − cost(γ)``; the scan constant ``−λ_c + m ln(λ_c c)`` cancels in the
    normalisation. Two entries with the same label and history are one entry, so children with
    the same entries are the same component and merge.

    The chains of :class:`OriginalGibbs` and :class:`ShortChainGibbs` (default readings,
    ``start="all_missed"``) run for all components in one compiled call; other options run
    the public sampler component by component, as do Murty and Exact. Component ``h`` draws
    from the streams of base key ``chain_state(key, h)``, ``key`` one draw from ``rng``.

    References
    ----------
    .. [1] B.-N. Vo, B.-T. Vo, H. G. Hoang, "An Efficient Implementation of the Generalized
       Labeled Multi-Bernoulli Filter", IEEE Trans. Signal Process. 65(8):1975-1987, 2017.
    .. [2] B.-T. Vo, B.-N. Vo, "Labeled Random Finite Sets and Multi-Object Conjugate Priors",
       IEEE Trans. Signal Process. 61(13):3460-3475, 2013.
    .. [3] A. Trezza, D. J. Bucci Jr., P. K. Varshney, "On Gibbs Sampling Architecture for
       Labeled Random Finite Sets Multi-Object Tracking", arXiv:2306.15135, 2023.

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign.tracking import GLMBFilter, ShortChainGibbs, make_model
    >>> f = GLMBFilter(make_model("vo"), ShortChainGibbs(400, 25, tau_stall=5, tau_stale=10))
    >>> for k in range(4):          # one target near birth location 2, no clutter
    ...     rec = f.step([[400.0 - 10 * k, -600.0 + 5 * k]], rng=k)
    >>> rec.labels.tolist(), int(rec.cardinality.argmax()), rec.n_components
    ([[1, 2]], 1, 10)
    """

    #: Shape of one history node's measurement record (a single sensor: a scalar index).
    _meas_shape: tuple = ()

    def __init__(
        self,
        model: Model,
        association,
        *,
        h_upd: int = 1000,
        h_max: int = 1000,
        prune_hypothesis: float = 1e-15,
        gate_prob: float | None = 0.9999999,
        extraction: str | None = None,
        theta_upper: float = 0.9,
        theta_lower: float = 1e-3,
        prune_component: float = 1e-5,
        merge_threshold: float = 4.0,
        merge_rule: str = "bhattacharyya",
        max_components: int = 10,
        retained_mass: bool = False,
        keep_histories: bool | None = None,
        birth: MeasurementBirth | None = None,
    ):
        check_type(model, "model", (Model, NonlinearModel),
                   "build one with make_model(preset) or Model(...)")
        self._check_truncation(association)
        if birth is not None:
            check_type(birth, "birth", MeasurementBirth,
                       "None for the model's static birth or MeasurementBirth(...)")
            # a prior of the wrong dimension is refused now, not at the first scan
            birth.births_from(np.empty((0, np.shape(model.sensor.R)[0])), np.empty(0),
                              model.sensor)
        #: The measurement-driven birth in use, or None for the model's static birth.
        self.birth = birth
        self.model = model
        self.association = association
        self.h_upd = _check_count(h_upd, "h_upd")
        self.h_max = _check_count(h_max, "h_max")
        self.prune_hypothesis = _check_threshold(prune_hypothesis, "prune_hypothesis")
        if extraction is None:  # the model's (its preset's, PRESET_EXTRACTION)
            extraction = getattr(model, "extraction", "map")
        self.extraction = check_choice(extraction, "extraction", GLMB_EXTRACTIONS)
        self.theta_upper = _check_threshold(theta_upper, "theta_upper")
        self.theta_lower = _check_threshold(theta_lower, "theta_lower")
        if self.theta_lower > self.theta_upper:
            raise ValueError(f"theta_lower must be <= theta_upper = {self.theta_upper!r}, got "
                             f"{self.theta_lower!r}")
        self.prune_component = _check_threshold(prune_component, "prune_component")
        self.merge_threshold = check_real(merge_threshold, "merge_threshold", minimum=0.0,
                                          finite=False)
        self.merge_rule = check_choice(merge_rule, "merge_rule", tuple(MERGE_RULES))
        self.max_components = check_int(max_components, "max_components", minimum=1)
        self.retained_mass = check_bool(retained_mass, "retained_mass")
        # the DP plans of the retained mass's normalisers, by gate pattern (see _retained)
        self._plans = PlanCache()
        reads_histories = self.extraction in ("trajectory", "recursive")
        if keep_histories is None:
            keep_histories = reads_histories
        self.keep_histories = check_bool(keep_histories, "keep_histories")
        if reads_histories and not self.keep_histories:
            raise ValueError(f"extraction={self.extraction!r} needs keep_histories=True (a "
                             "trajectory is read along the association history)")
        #: The single-object path of a non-linear model (None: the linear Kalman kernels).
        self._so = single_object(model)
        self._d = 4 if self._so is None else self._so.ndim
        self._dz = 2 if self._so is None else self._so.meas_ndim
        self.gate = None if gate_prob is None else gate_threshold(gate_prob, self._dz)
        plan = getattr(association, "batch_plan", None)
        self._plan = plan(self._sensors) if callable(plan) else None
        self._rules = None if self._plan is None or not self._plan.chains else \
            _glmb_kernels.ChainRules(random_scan=self._plan.random_scan,
                                     tau_stall=self._plan.tau_stall,
                                     tau_stale=self._plan.tau_stale)
        self._rule = MERGE_RULES[self.merge_rule]
        if self._so is not None:
            self._nonlinear_constants(self._so)
            self.reset()
            return
        self._F = np.array(model.motion.F)
        self._Q = np.array(model.motion.Q)
        self._R = np.array(model.sensor.R)
        self._pd = float(model.sensor.p_d)
        self._ps = float(model.survival.p_s)
        self._log_pd = math.log(self._pd)
        self._log_1m_pd = math.log1p(-self._pd) if self._pd < 1 else -math.inf
        self._log_kappa = math.log(model.clutter.intensity)
        self._birth_r = np.array(model.birth.r, dtype=np.float64).reshape(-1)
        self._birth_m = np.array(model.birth.means, dtype=np.float64).reshape(-1, 4)
        self._birth_P = np.array(model.birth.covs, dtype=np.float64).reshape(-1, 4, 4)
        self.reset()

    def _nonlinear_constants(self, so) -> None:
        """The constants of a non-linear model (the prediction and update are ``so``'s)."""
        self._pd = so.p_d
        self._ps = so.p_s
        self._log_pd = math.log(self._pd)
        self._log_1m_pd = math.log1p(-self._pd) if self._pd < 1 else -math.inf
        self._log_kappa = math.log(so.clutter_intensity)
        self._birth_r = so.birth_r
        self._birth_m = so.birth_m
        self._birth_P = so.birth_P

    #: The problems this filter truncates (:func:`~rankedassign.tracking.check_truncation`).
    _sensors = "single-sensor"

    def _check_truncation(self, association) -> None:
        """Refuse what this filter cannot use, with the reason (one place for every filter)."""
        check_truncation(association, type(self).__name__, self._sensors, "hypotheses")

    def set_motion(self, motion) -> None:
        """Predict with ``motion`` from the next scan on (the components are kept).

        For a motion model whose matrices depend on the time between scans (a Stone Soup
        transition model, :class:`rankedassign.stonesoup.GLMBTracker`); :attr:`model` becomes
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
        >>> from rankedassign.tracking import GLMBFilter, Murty, make_model
        >>> from rankedassign.tracking.models import LinearMotion
        >>> f = GLMBFilter(make_model("paper"), Murty(10))
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
        self._Q = np.array(motion.Q)

    # ----------------------------------------------------------------------- state
    def reset(self) -> None:
        """Forget every track: one component, the empty set, with weight 1; scan 0."""
        self.k = 0
        # the track table
        self.labels = np.empty((0, 2), dtype=np.int64)
        self.offsets = np.zeros(1, dtype=np.int64)
        self.w = np.empty(0)
        self.m = np.empty((0, self._d))
        self.P = np.empty((0, self._d, self._d))
        self.hist = np.empty(0, dtype=np.int64)  # history node of every entry
        # the components: entries (CSR, increasing within a component) and weights
        self.comp_off = np.zeros(2, dtype=np.int64)
        self.comp_tracks = np.empty(0, dtype=np.int64)
        self.comp_w = np.ones(1)
        # the history forest: parent node, scan, measurement (−1 missed), filtered state
        self._node_parent = np.empty(0, dtype=np.int64)
        self._node_scan = np.empty(0, dtype=np.int64)
        self._node_meas = np.empty((0, *self._meas_shape), dtype=np.int64)
        self._node_state = np.empty((0, self._d))
        self._live_nodes = 0
        self._confirmed = np.empty(0, dtype=np.int64)  # label keys (hysteresis)
        self._tracks_seen: dict = {}  # label -> (scans, states) (extraction="recursive")
        if getattr(self, "birth", None) is not None:
            self._set_measurement_births(BirthComponents.empty())

    def _set_measurement_births(self, b: BirthComponents) -> None:
        """The births the next prediction appends (means and covariances not yet predicted)."""
        self._birth_r = np.ascontiguousarray(b.r, dtype=np.float64)
        d = self._d
        self._birth_m = np.ascontiguousarray(b.means, dtype=np.float64).reshape(-1, d)
        self._birth_P = np.ascontiguousarray(b.covs, dtype=np.float64).reshape(-1, d, d)

    def set_prior(self, labels, means, covs, components=None, weights=None) -> None:
        """Start from a δ-GLMB prior over single-Gaussian tracks (instead of the empty one).

        Parameters
        ----------
        labels : array_like of int, shape (T, 2)
            Distinct labels ``(birth scan, index)`` of the tracks: non-negative ints, the scan
            below ``2**31`` and the index below ``2**32`` (a label is packed into 64 bits). The
            births of scan ``k >= 1`` are labelled ``(k, 1..B)``, so a prior label of that form
            would merge with a birth and is refused: label the prior's tracks with birth scan
            0 (or, with a static birth, an index above ``B``).
        means, covs : array_like, shapes (T, d) and (T, d, d)
            Their Gaussians (``d = 4`` on a linear model, the model's state dimension on a
            non-linear one): finite means, symmetric positive definite covariances.
        components : sequence of sequences of int, optional
            Track indices (ints) of every component (default: one component holding every
            track).
        weights : array_like, shape (H,), optional
            Component weights (normalised here; default equal).

        Raises
        ------
        TypeError
            On labels, track indices or numbers of the wrong kind (``1.5``, ``True``, ``"0"``).
        ValueError
            On shapes that disagree, labels out of range, repeated or a birth's, a mean that
            is not finite or a covariance that is not SPD (the message names the track), a
            component with an index out of range or repeated, or weights that are negative,
            not finite or all zero.

        Examples
        --------
        >>> import numpy as np
        >>> from rankedassign.tracking import Exact, GLMBFilter, make_model
        >>> f = GLMBFilter(make_model("vo"), Exact())
        >>> f.set_prior([[0, 1], [0, 2]], np.zeros((2, 4)), np.tile(np.eye(4), (2, 1, 1)),
        ...             components=[[0], [0, 1]], weights=[1.0, 3.0])
        >>> f.n_components, f.comp_w.tolist()
        (2, [0.25, 0.75])
        """
        labels, means, covs, comps, w = check_prior(labels, means, covs, components, weights,
                                                    max_birth_index=self._max_birth_index(),
                                                    dim=self._d)
        T = labels.shape[0]
        self.reset()
        self.labels = labels.copy()
        self.offsets = np.arange(T + 1, dtype=np.int64)
        self.w = np.ones(T)
        self.m = np.ascontiguousarray(means)
        self.P = np.ascontiguousarray(covs)
        self._append_nodes(np.full(T, -1, dtype=np.int64),
                           np.full((T, *self._meas_shape), -1, dtype=np.int64), self.m)
        self.hist = np.arange(T, dtype=np.int64)
        self.comp_off = np.concatenate([[0], np.cumsum([len(c) for c in comps])]).astype(
            np.int64)
        self.comp_tracks = np.array([i for c in comps for i in sorted(c)], dtype=np.int64)
        self.comp_w = w / w.sum()

    def _max_birth_index(self):
        """Births of every scan are labelled ``(k, 1..B)``: ``B`` (None if it varies)."""
        if getattr(self, "birth", None) is not None:
            return None     # measurement births: B changes from scan to scan
        return int(self._birth_r.size)

    @property
    def n_components(self) -> int:
        """Number of components held."""
        return int(self.comp_w.size)

    @property
    def n_tracks(self) -> int:
        """Entries of the track table."""
        return int(self.labels.shape[0])

    def components(self) -> list[tuple[float, tuple]]:
        """Every component as ``(w, ((label, history), ...))``, in the order held.

        ``label`` is a tuple ``(birth scan, birth index)``, ``history`` the tuple of the
        measurement indices (0-based, ``−1`` missed) of every scan since birth (of the last
        scan only with ``keep_histories=False``).

        Returns
        -------
        list of tuple
            ``(w, tracks)`` per component: its weight (float, the weights sum to 1) and its
            tracks as ``((label, history), ...)``.

        Examples
        --------
        >>> from rankedassign.tracking import Exact, GLMBFilter, make_model
        >>> f = GLMBFilter(make_model("vo"), Exact())
        >>> f.components()
        [(1.0, ())]
        """
        out = []
        for h in range(self.n_components):
            tracks = self.comp_tracks[self.comp_off[h]:self.comp_off[h + 1]]
            items = tuple((tuple(self.labels[e].tolist()), self._history(e)) for e in tracks)
            out.append((float(self.comp_w[h]), tuple(sorted(items))))
        return out

    def _history(self, e: int) -> tuple:
        """Measurement per scan since birth of entry ``e`` (a prior's own node excluded)."""
        out = []
        v = int(self.hist[e])
        while v >= 0:
            if self._node_scan[v] >= 1:
                x = self._node_meas[v]
                out.append(int(x) if x.ndim == 0 else tuple(x.tolist()))
            v = int(self._node_parent[v])
        return tuple(reversed(out))

    def nbytes(self) -> int:
        """Bytes held by the filter's state (track table, components, history forest).

        Returns
        -------
        int
            The sum of the ``nbytes`` of the state's arrays.

        Examples
        --------
        >>> from rankedassign.tracking import Exact, GLMBFilter, make_model
        >>> GLMBFilter(make_model("vo"), Exact()).nbytes() > 0
        True
        """
        arrays = (self.labels, self.offsets, self.w, self.m, self.P, self.hist, self.comp_off,
                  self.comp_tracks, self.comp_w, self._node_parent, self._node_scan,
                  self._node_meas, self._node_state, self._confirmed)
        return int(sum(a.nbytes for a in arrays))

    # ----------------------------------------------------------------------- 1. prediction
    def _predict(self) -> np.ndarray:
        """Propagate every entry, append the births of the new scan; return the survival or
        birth probability of every entry of the predicted table."""
        self.k += 1
        T_old = self.n_tracks
        if self._so is not None:  # through the motion model (Kalman, EKF or UKF)
            self.m, self.P = self._so.predict(self.m, self.P)
        else:
            # m <- F m ; P <- F P F' + Q
            self.m = self.m @ self._F.T
            self.P = self._F @ self.P @ self._F.T + self._Q
        B = self._birth_r.size
        labels = np.empty((B, 2), dtype=np.int64)
        labels[:, 0] = self.k
        labels[:, 1] = np.arange(1, B + 1)
        self.labels = np.concatenate([self.labels, labels])
        measured = getattr(self, "birth", None) is not None
        if self._so is not None and not measured:  # Gaussian-mixture birth terms
            self.offsets = np.concatenate([self.offsets,
                                           self.w.size + np.cumsum(self._so.birth_counts)])
            self.w = np.concatenate([self.w, self._so.birth_w])
        else:
            self.offsets = np.concatenate([self.offsets, self.w.size + np.arange(1, B + 1)])
            self.w = np.concatenate([self.w, np.ones(B)])
        birth_m, birth_P = self._birth_m, self._birth_P
        if measured and self._so is not None:
            # measurement births sit at the last scan's time: predict them with this scan's
            # motion (the model's filter), as every entry
            birth_m, birth_P = self._so.predict(birth_m, birth_P)
        elif measured:
            # measurement births sit at the last scan's time: predict them with this scan's
            # motion, as every entry
            birth_m = birth_m @ self._F.T
            birth_P = self._F @ birth_P @ self._F.T + self._Q
        self.m = np.ascontiguousarray(np.concatenate([self.m, birth_m]))
        self.P = np.ascontiguousarray(np.concatenate([self.P, birth_P]))
        self.hist = np.concatenate([self.hist, np.full(B, -1, dtype=np.int64)])
        self._births = np.arange(T_old, T_old + B, dtype=np.int64)
        return np.concatenate([np.full(T_old, self._ps), self._birth_r])

    # ----------------------------------------------------------------------- 2. shared terms
    def _terms(self, z: np.ndarray, p_exist: np.ndarray) -> _Terms:
        """``ln η`` of every entry and measurement, the gate and the Kalman statistics."""
        T = self.n_tracks
        C = self.w.size
        with np.errstate(divide="ignore"):
            log_p = np.log(p_exist)
            log_dead = np.log1p(-p_exist)
        log_miss = log_p + self._log_1m_pd
        gain = None
        if z.shape[0] == 0 or T == 0:
            used = np.empty(0, dtype=np.int64)
            gated = np.zeros((T, 0), dtype=bool)
            Sinv, nu, lw = np.empty((C, 2, 2)), np.empty((C, 0, self._dz)), np.empty((C, 0))
            log_g = log_det = np.empty((T, 0))
        else:
            gate = 0.0 if self.gate is None else self.gate
            if self._so is not None:  # the model's filter: wrapped innovations, any d, d_z
                st = self._so.measurement_terms(self.m, self.P, z, self.offsets, self.gate)
                maha, log_det_S, nu, gated = st.maha, st.log_det_S, st.nu, st.gated
                Sinv, gain = None, (st.gain, st.P_upd)
            else:
                with interruptible:
                    det, Sinv, nu, maha, gated = _kernels.gate_and_distances(
                        self.m, self.P, self._R, z, self.offsets, gate, self.gate is not None)
                log_det_S = np.log(det)
            used = np.flatnonzero(gated.any(axis=0))
            gated = np.ascontiguousarray(gated[:, used])
            # ln η_t(j) = ln p_t + ln P_D + ln q_t(z_j) − ln κ   (spec §2.1)
            with interruptible:
                lw, log_g, log_det = _kernels.detection_log_weights(
                    maha, log_det_S, np.log(self.w), self.offsets, used, gated, log_p,
                    self._log_pd, self._log_kappa)
            nu = nu[:, used]
        U = used.size
        cc = np.empty((T, U + 2))
        cc[:, :U] = -log_det
        cc[:, U] = -log_miss
        cc[:, U + 1] = -log_dead
        # the shifted weights of the samplers (rankedassign.single.prepare.shifted_weights): a row's
        # minimum is over its own gated measurements, so it is the same in every component
        W = np.exp(-(cc - cc.min(axis=1, keepdims=True))) if T else np.empty((0, U + 2))
        return _Terms(used, gated, Sinv, nu, lw, log_g, log_det, log_miss, log_dead,
                      np.ascontiguousarray(cc), np.ascontiguousarray(W), gain)

    # ----------------------------------------------------------------------- 3.-4. truncation
    def _counts(self) -> np.ndarray:
        """``T_h = round(H_upd √w_h / Σ √w)`` (half away from zero, as MATLAB's round)."""
        s = np.sqrt(self.comp_w)
        return np.floor(self.h_upd * s / s.sum() + 0.5).astype(np.int64)

    def _problem(self, h: int, terms: _Terms, mark, rows, cols):
        """Rows, columns and the AssignmentProblem of component ``h`` (gathered terms)."""
        with interruptible:
            P, M = _glmb_kernels.component_problem(h, self.comp_off, self.comp_tracks,
                                                   self._births, terms.gated, mark, rows, cols)
        r, c = rows[:P].copy(), cols[:M].copy()
        with interruptible:
            cost = _kernels.group_cost_matrix(terms.log_det, terms.log_miss, terms.log_dead,
                                              r, c)
        return r, c, AssignmentProblem(cost)

    def _truncate(self, terms: _Terms, counts: np.ndarray, base: np.ndarray) -> _Children:
        """The children of every component (spec §2.3)."""
        H = self.n_components
        U = terms.used.size
        if self._rules is not None:
            chains, length = _gibbs_budget(self.association, counts)
            sizes = self.comp_off[1:] - self.comp_off[:-1]  # np.diff, without its call cost
            P_max = int(self._births.size + (sizes.max() if H else 0))
            with interruptible:
                comp, cost, off, entry, meas, sweeps, n_rows = _glmb_kernels.sample_components(
                    self.comp_off, self.comp_tracks, self._births, terms.W, terms.cc,
                    terms.gated, chains, length, self._rules, base, _zobrist(P_max, U + 2))
            return _Children(comp, cost, off, entry, meas, int(sweeps.sum()),
                             int((sweeps * n_rows).sum()))
        if self._plan is not None and self._plan.ranked:
            ranked = self._ranked(terms, counts)
            if ranked is not None:
                return ranked
        # component by component: the public samplers, Murty, enumeration, custom
        mark = np.zeros(U, dtype=bool)
        rows = np.empty(self._births.size + int(np.diff(self.comp_off).max(initial=0)),
                        dtype=np.int64)
        cols = np.empty(U, dtype=np.int64)
        comp, cost, off, entry, meas = [], [], [0], [], []
        sweeps = row_updates = 0
        for h in range(H):
            r, c, problem = self._problem(h, terms, mark, rows, cols)
            hyp = truncate(self.association, problem, int(counts[h]), rng=int(base[h]),
                           caller="GLMBFilter")
            a = np.asarray(hyp.assignments, dtype=np.int64)
            P, M = r.size, c.size
            exists = a < M + P  # a measurement or missed: the row is there after the scan
            e = np.broadcast_to(r, a.shape)[exists]
            j = np.where(a < M, c[np.minimum(a, max(M - 1, 0))] if M else -1, -1)[exists]
            comp.append(np.full(a.shape[0], h, dtype=np.int64))
            cost.append(np.asarray(hyp.costs, dtype=np.float64))
            off.extend((off[-1] + np.cumsum(exists.sum(axis=1))).tolist())
            entry.append(e)
            meas.append(j)
            sweeps += hyp.sweeps
            row_updates += hyp.row_updates
        return _Children(_concat(comp, np.int64), _concat(cost, np.float64),
                         np.array(off, dtype=np.int64), _concat(entry, np.int64),
                         _concat(meas, np.int64), sweeps, row_updates)

    def _ranked(self, terms: _Terms, counts: np.ndarray) -> _Children | None:
        """Murty's ``k = min(k, max(T_h, 1))`` best or every assignment of every component, in
        compiled loops over the components (the oracle's searches, :mod:`oracle.kernels`).

        None when a component is beyond :data:`EXACT_LIMIT` or the work arrays' limit: the
        component-by-component path then raises the error of :func:`truncate` for it.
        """
        exact = self._plan.k == 0  # every assignment, else Murty's k best
        args = (self.comp_off, self.comp_tracks, self._births, terms.cc, terms.gated)
        if exact:
            with interruptible:
                n_want, sizes = _glmb_kernels.count_components(*args, EXACT_LIMIT)
            if (n_want > EXACT_LIMIT).any():
                return None
            total = int(n_want.sum())
            if total > EXACT_SCAN_LIMIT:
                raise ValueError(
                    f"Exact() would keep {total} assignments of {n_want.size} components in "
                    f"one scan, above EXACT_SCAN_LIMIT = {EXACT_SCAN_LIMIT} (each component "
                    f"has at most {int(n_want.max())}); use Murty(k) or a sampler for "
                    "problems of this size")
        else:
            n_want = np.minimum(self._plan.k, np.maximum(counts, 1)).astype(np.int64)
        P_max = self._births.size + int(np.diff(self.comp_off).max(initial=0))
        if int(n_want.max(initial=0)) * (32 * P_max + 128) > MAX_WORK_BYTES:
            return None
        # slices of components of about _RANKED_SLICE assignments: Ctrl-C stays prompt
        cum = np.cumsum(n_want)
        cuts = np.searchsorted(cum, np.arange(_RANKED_SLICE, cum[-1], _RANKED_SLICE),
                               side="right")
        bounds = np.unique(np.r_[0, cuts, n_want.size])
        parts = []
        for h0, h1 in zip(bounds[:-1], bounds[1:], strict=True):
            with interruptible:
                parts.append(_glmb_kernels.ranked_components(*args, n_want, exact, int(h0),
                                                             int(h1)))
        comp, cost, off, entry, meas = (list(x) for x in zip(*parts, strict=True))
        shift = np.cumsum([0] + [o[-1] for o in off[:-1]])
        off = np.concatenate([off[0][:1]] + [o[1:] + d for o, d in zip(off, shift, strict=True)])
        return _Children(_concat(comp, np.int64), _concat(cost, np.float64), off,
                         _concat(entry, np.int64), _concat(meas, np.int64), 0, 0)

    def _retained(self, terms: _Terms, children: _Children) -> tuple[float, str]:
        """``Σ_h w_h K_h / Σ_h w_h Z_h`` with the exact ``Z_h`` (spec §4).

        ``Z_h`` factorises over the connected components of the problem's gate graph (rows
        that share no measurement are independent, and every row's missed and dead columns are
        its own): ``Z_h = Π_g Z_g``. A group is named by its entries, so a group met in several
        components is solved once per scan, by :func:`oracle.single.dp.compact_log_normalizer`
        (with the filter's :class:`~oracle.single.dp.PlanCache`: the components share most of
        their tracks, so their groups repeat a few gate patterns); a group of one row is its
        closed form ``Σ_j η(j)``.
        """
        groups = _component_groups(self.comp_off, self.comp_tracks, self._births,
                                   terms.gated)
        log_Z = np.zeros(self.n_components)
        if groups is None:  # no rows at all: every Z_h is 1
            return retained_ratio(self.comp_w, children, log_Z), ""
        uniq, first, inv, g_comp = groups
        value = np.empty(uniq.shape[0])
        size = (uniq >= 0).sum(axis=1)
        # the compact cost of every entry, [measurements | missed | dead] (as
        # _kernels.group_cost_matrix), negated once a scan
        cost_all = np.concatenate([-terms.log_det, -terms.log_miss[:, None],
                                   -terms.log_dead[:, None]], axis=1)
        # every group's columns at once: the measurements some row of it gates, then the
        # missed and dead columns
        flat = uniq[uniq >= 0]
        gate = np.logical_or.reduceat(terms.gated[flat], np.r_[0, np.cumsum(size)[:-1]],
                                      axis=0)
        cols_of = np.concatenate([gate, np.ones((gate.shape[0], 2), dtype=bool)], axis=1)
        # solved in the order of first use, so that a group beyond the DP is reported for the
        # first component that has it
        for u, n in enumerate(size.tolist()):
            rr = uniq[u, :n]
            cols = np.flatnonzero(cols_of[u])
            if n == 1:
                value[u] = _logsumexp(-cost_all[rr[0], cols])
                continue
            cost = cost_all[rr[:, None], cols]
            try:
                value[u] = compact_log_normalizer(cost, plans=self._plans)
            except ValueError as err:
                h = int(g_comp[first[u]])
                return math.nan, (
                    f"component {h} has a group of {rr.size} rows and {cols.size - 2} "
                    f"measurements beyond the oracle's DP: {err}")
        # Σ_g ln Z_g per component, group by group in order (np.add.at is unbuffered)
        np.add.at(log_Z, g_comp, value[inv])
        return retained_ratio(self.comp_w, children, log_Z), ""

    # ----------------------------------------------------------------------- 5. children
    def _update(self, terms: _Terms, children: _Children, z: np.ndarray) -> tuple[int, float]:
        """Merge, prune, cap; the new track table with its Kalman update.

        Returns the number of children and the normalised weight (over every merged child)
        of the components kept by the pruning and the cap, the factor that turns the
        retained mass into the carried mass.
        """
        U = self._radix(terms) - 1
        N = children.comp.size
        with np.errstate(divide="ignore"):
            log_w = np.log(self.comp_w)[children.comp] - children.cost
        # the new entries: one per distinct (predicted entry, measurement or missed); in place,
        # for the exact filter's millions of children's entries
        key = children.entry * (U + 1)
        key += children.meas
        key += 1
        uniq, ids = _unique_inverse(key, self.labels.shape[0] * (U + 1))
        with interruptible:  # (it sorts ids within each child, in place)
            group, g_log_w, first = _glmb_kernels.merge_children(children.off, ids, log_w)
        # normalise (log-sum-exp), prune, cap to the H_max heaviest, renormalise
        w = np.exp(g_log_w - _logsumexp(g_log_w))
        order = np.argsort(-w, kind="stable")
        order = order[w[order] >= self.prune_hypothesis][: self.h_max]
        if order.size == 0:  # everything below the threshold: keep the heaviest
            order = np.argsort(-w, kind="stable")[:1]
        w = w[order]
        kept = float(w.sum())
        w = w / kept
        starts = children.off[first[order]]
        sizes = children.off[first[order] + 1] - starts
        # (concatenate, not np.r_: the clustered filter runs thousands of these scans a scan)
        idx = (np.repeat(starts - np.cumsum(np.concatenate(([0], sizes[:-1]))), sizes)
               + np.arange(sizes.sum()))
        kept_ids = ids[idx]
        # drop the entries no kept component uses; the remap keeps the order
        used_ids, comp_tracks = _unique_inverse(kept_ids)
        k_new = uniq[used_ids]
        e_src = k_new // (U + 1)
        j_src = k_new % (U + 1) - 1
        self._kalman(terms, e_src, j_src)
        self.comp_off = np.concatenate([[0], np.cumsum(sizes)]).astype(np.int64)
        self.comp_tracks = comp_tracks.astype(np.int64).reshape(-1)
        self.comp_w = w
        meas = self._history_meas(terms, j_src)
        parents = self.hist[e_src] if self.keep_histories else np.full(e_src.size, -1)
        self.labels = self.labels[e_src]
        self.hist = self._append_nodes(parents, meas, self.m[self.offsets[:-1]])
        self._compact_history()
        return N, kept

    @staticmethod
    def _radix(terms: _Terms) -> int:
        """Distinct updates of one entry: a gated measurement or missed (``U + 1``)."""
        return int(terms.used.size) + 1

    @staticmethod
    def _history_meas(terms: _Terms, j_src: np.ndarray) -> np.ndarray:
        """The measurement index (−1 missed) each new entry's history node records."""
        if terms.used.size == 0:
            return np.full(j_src.size, -1, dtype=np.int64)
        return np.where(j_src >= 0, terms.used[np.maximum(j_src, 0)], -1)

    def _kalman(self, terms: _Terms, e_src: np.ndarray, j_src: np.ndarray) -> None:
        """The mixtures of the new entries: entry ``e_src`` predicted (``j_src = −1``) or
        updated with gated measurement ``j_src``; then pruned, merged and capped."""
        n_comp = (self.offsets[1:] - self.offsets[:-1])[e_src]
        offsets = np.concatenate([[0], np.cumsum(n_comp)]).astype(np.int64)
        within = np.arange(offsets[-1]) - np.repeat(offsets[:-1], n_comp)
        comp = np.repeat(self.offsets[:-1][e_src], n_comp) + within
        track = np.repeat(e_src, n_comp)
        j = np.repeat(j_src, n_comp)
        # (fancy indexing copies: the updates below do not touch the table)
        w = self.w[comp]
        m = self.m[comp]
        P = self.P[comp]
        det = j >= 0
        if det.any():
            c, t, jj = comp[det], track[det], j[det]
            # w̃_c = w_c N(z_j; H m_c, S_c) / Σ_c' w_c' N(z_j; H m_c', S_c')
            w[det] = np.exp(terms.lw[c, jj] - terms.log_g[t, jj])
            if self._so is not None:  # K = C S⁻¹ and P' of the model's filter, ν wrapped
                K, P_upd = terms.gain
                m[det] = m[det] + np.einsum("cij,cj->ci", K[c], terms.nu[c, jj])
                P[det] = P_upd[c]
            else:
                # K = P H' S⁻¹, m' = m + K ν, P' = P − K S K' = P − K H P
                P_c = P[det]
                PHt = P_c[:, :, [0, 2]]
                K = PHt @ terms.Sinv[c]
                m[det] = m[det] + np.einsum("cij,cj->ci", K, terms.nu[c, jj])
                P_upd = P_c - K @ PHt.transpose(0, 2, 1)
                P[det] = 0.5 * (P_upd + P_upd.transpose(0, 2, 1))
        self._reduce_mixtures(offsets, w, m, P, e_src.size)

    def _reduce_mixtures(self, offsets, w, m, P, n_entries: int) -> None:
        """Every updated entry's mixture merged, pruned and capped (all ``n_entries`` kept)."""
        keep = np.ones(n_entries, dtype=bool)
        reduce = _kernels.reduce_mixtures if self._so is None else self._so.reduce_mixtures
        with interruptible:
            self.offsets, self.w, self.m, self.P = reduce(
                offsets, np.ascontiguousarray(w), np.ascontiguousarray(m),
                np.ascontiguousarray(P), keep, self.prune_component, self.merge_threshold,
                self.max_components, self._rule)

    # ----------------------------------------------------------------------- histories
    def _append_nodes(self, parents, meas, states) -> np.ndarray:
        """Append history nodes of scan ``k``; return their indices."""
        n0 = self._node_parent.size
        n = parents.size
        self._node_parent = np.concatenate([self._node_parent, parents])
        self._node_scan = np.concatenate([self._node_scan, np.full(n, self.k, np.int64)])
        self._node_meas = np.concatenate([self._node_meas, meas])
        self._node_state = np.concatenate([self._node_state, states])
        return np.arange(n0, n0 + n, dtype=np.int64)

    def _compact_history(self) -> None:
        """Drop the history nodes no entry reaches, when they are most of the forest."""
        n = self._node_parent.size
        if n <= 2 * self._live_nodes + 4096:
            return
        with interruptible:
            keep = _glmb_kernels.mark_reachable(self._node_parent, self.hist)
        new_index = np.cumsum(keep) - 1
        parent = self._node_parent[keep]
        self._node_parent = np.where(parent >= 0, new_index[np.maximum(parent, 0)], -1)
        self._node_scan = self._node_scan[keep]
        self._node_meas = self._node_meas[keep]
        self._node_state = self._node_state[keep]
        self.hist = new_index[self.hist]
        self._live_nodes = int(keep.sum())

    def _trajectory(self, e: int):
        scans, states = [], []
        v = int(self.hist[e])
        while v >= 0:
            if self._node_scan[v] >= 1:
                scans.append(int(self._node_scan[v]))
                states.append(self._node_state[v])
            v = int(self._node_parent[v])
        return (np.array(scans[::-1], dtype=np.int64),
                np.array(states[::-1]).reshape(-1, self._d))

    # ----------------------------------------------------------------------- 6. estimation
    def _extract(self):
        """Labels, states, existence of the reported tracks; every label with ``r(ℓ)``;
        the cardinality distribution; the trajectories."""
        w = self.comp_w
        sizes = self.comp_off[1:] - self.comp_off[:-1]
        T = self.n_tracks
        # r_e = Σ_{h ∋ e} w_h, then r(ℓ) = Σ over the entries of label ℓ
        r_e = np.bincount(self.comp_tracks, weights=np.repeat(w, sizes), minlength=T)
        lkey = self.labels[:, 0] * (1 << 32) + self.labels[:, 1]
        ukey, linv = _unique_inverse(lkey)
        r_label = np.minimum(np.bincount(linv, weights=r_e, minlength=ukey.size), 1.0)
        track_labels = np.column_stack([ukey >> 32, ukey & 0xFFFFFFFF]).astype(np.int64)
        # ρ(n) = Σ_{h: |I_h| = n} w_h
        rho = np.bincount(sizes, weights=w)
        trajectories = ()
        if self.extraction == "hysteresis":
            # confirmed_k = [r >= ϑ_u] or (confirmed_{k-1} and r >= ϑ_l)   (spec 6.5)
            was = np.isin(ukey, self._confirmed)
            conf = (r_label >= self.theta_upper) | (was & (r_label >= self.theta_lower))
            self._confirmed = ukey[conf]
            # each confirmed label's heaviest entry
            order = np.lexsort((-r_e, linv))
            best = order[np.r_[True, linv[order][1:] != linv[order][:-1]]] if T else order
            entries = best[conf]
        else:
            n_hat = int(np.argmax(rho))
            h = int(np.flatnonzero(sizes == n_hat)[0])  # components are heaviest first
            entries = self.comp_tracks[self.comp_off[h]:self.comp_off[h + 1]]
            entries = entries[np.argsort(lkey[entries], kind="stable")]
            if self.extraction == "trajectory":
                trajectories = tuple((tuple(self.labels[e].tolist()), *self._trajectory(e))
                                     for e in entries)
            elif self.extraction == "recursive":
                # Vo's recursive estimator: the labels of the best hypothesis take their
                # current history (their past is rewritten), the labels that left it keep
                # the trajectory they had, so a track stays continuous when the best
                # hypothesis switches
                for e in entries:
                    self._tracks_seen[tuple(self.labels[e].tolist())] = self._trajectory(e)
                trajectories = tuple((lab, *self._tracks_seen[lab])
                                     for lab in sorted(self._tracks_seen))
        states = self.m[self.offsets[entries]].reshape(-1, self._d)
        return (self.labels[entries], states, r_label[linv[entries]], track_labels, r_label,
                rho, trajectories)

    def trajectory_estimates(self) -> list[dict]:
        """Every scan's estimate so far by Vo's recursive estimator (``extraction="recursive"``).

        The estimate of scan ``k`` is read from the stored trajectories *now*, so it changes
        when a later scan rewrites a label's past: it holds every label whose trajectory
        reaches scan ``k``, with its filtered state there (Vo's ``extract_estimates_recursive``
        writes its ``est.X`` the same way after each scan). Score these, not the per-scan
        records, to measure the estimator.

        Returns
        -------
        list of dict
            One per scan ``1..k``: ``{label: state}``, ``label`` a tuple ``(birth scan,
            index)``, ``state`` an ndarray of shape (4,).

        Raises
        ------
        ValueError
            If the filter's extraction is not ``"recursive"``.

        Examples
        --------
        >>> from rankedassign.tracking import GLMBFilter, Murty, make_model
        >>> f = GLMBFilter(make_model("vo"), Murty(20), extraction="recursive")
        >>> for k in range(3):
        ...     rec = f.step([[400.0 - 10 * k, -600.0 + 5 * k]], rng=k)
        >>> [sorted(est) for est in f.trajectory_estimates()]
        [[(1, 2)], [(1, 2)], [(1, 2)]]
        """
        if self.extraction != "recursive":
            raise ValueError("trajectory_estimates() needs extraction='recursive', got "
                             f"extraction={self.extraction!r}")
        out = [{} for _ in range(self.k)]
        for lab in sorted(self._tracks_seen):
            scans, states = self._tracks_seen[lab]
            for k, x in zip(scans, states, strict=True):
                out[k - 1][lab] = x
        return out

    # ----------------------------------------------------------------------- the scan
    def step(self, z, rng=None) -> GLMBScanRecord:
        """Run one scan: predict, truncate every component, update, estimate.

        Parameters
        ----------
        z : array_like, shape (M, d_z)
            Measurements of the scan (as :meth:`LMBFilter.step`).
        rng : optional
            Anything :func:`numpy.random.default_rng` accepts; one draw from it keys the
            streams of every component.

        Returns
        -------
        GLMBScanRecord

        Raises
        ------
        TypeError, ValueError
            On measurements as :meth:`LMBFilter.step`; ``ValueError`` when :class:`Exact`
            meets a component too large to enumerate or a custom association returns bad
            hypotheses.

        Examples
        --------
        >>> from rankedassign.tracking import GLMBFilter, Murty, make_model
        >>> f = GLMBFilter(make_model("vo"), Murty(100), retained_mass=True)
        >>> rec = f.step([[0.0, 0.0], [400.0, -600.0]], rng=0)
        >>> rec.labels.tolist(), rec.n_components, round(rec.retained_mass, 6)
        ([[1, 1], [1, 2]], 36, 1.0)
        >>> capped = GLMBFilter(make_model("vo"), Murty(100), h_max=5, retained_mass=True)
        >>> rec = capped.step([[0.0, 0.0], [400.0, -600.0]], rng=0)
        >>> rec.n_components, round(rec.retained_mass, 6), rec.carried_mass < 0.999
        (5, 1.0, True)
        """
        z = _check_measurements(z) if self._so is None else self._so.check_measurements(z)
        return self._scan(z, rng)

    # hooks of the scan that a filter of several sensors replaces (its measurements are one
    # array per sensor, its terms hold one gate per sensor, its births may adapt)
    @staticmethod
    def _n_meas(z) -> int:
        return int(z.shape[0])

    @staticmethod
    def _n_gated(terms) -> int:
        return int(terms.used.size)

    def _entry_measurements(self) -> tuple[np.ndarray, np.ndarray]:
        """``r_e = Σ_{h ∋ e} w_h`` of every entry and the measurement it took this scan (-1:
        none), one per sensor: shapes ``(T,)`` and ``(T, *meas_shape)``."""
        r_e = np.bincount(self.comp_tracks, weights=np.repeat(self.comp_w,
                                                              np.diff(self.comp_off)),
                          minlength=self.n_tracks)
        last = (self._node_meas[self.hist] if self.n_tracks
                else np.empty((0, *self._meas_shape), np.int64))
        return r_e, last

    def _after_scan(self, z, gen) -> dict:
        """Work after the estimate (the measurement births, if on); extra ``timings``."""
        if self.birth is None:
            return {}
        t0 = perf_counter()
        # r_A(z_j) = Σ_e r_e [entry e took z_j this scan]: the weight of the components that
        # use z_j (an entry takes at most one measurement, and a component's entries take
        # distinct ones)
        r_e, last = self._entry_measurements()
        hit = last >= 0
        r_A = np.bincount(last[hit], weights=r_e[hit], minlength=z.shape[0])
        self._set_measurement_births(self.birth.births_from(
            z, r_A, self.model.sensor))
        return {"birth": perf_counter() - t0}

    def _scan(self, z, rng) -> GLMBScanRecord:
        """One scan on validated measurements ``z`` (see :meth:`step`)."""
        gen = spawning_generator(rng)
        key = np.uint64(gen.integers(0, _TWO63, dtype=np.uint64))
        t0 = perf_counter()
        p_exist = self._predict()
        T = self.n_tracks
        t1 = perf_counter()
        terms = self._terms(z, p_exist)
        counts = self._counts()
        with interruptible:
            base = _glmb_kernels.component_keys(key, self.n_components)
        t2 = perf_counter()
        children = self._truncate(terms, counts, base)
        H = self.n_components
        if self.retained_mass:
            retained, reason = self._retained(terms, children)
        else:
            retained, reason = math.nan, "not computed (retained_mass=False)"
        t3 = perf_counter()
        n_children, kept = self._update(terms, children, z)
        # what survives the scan: the truncation's share times the capped components' share
        carried = retained * min(kept, 1.0)
        labels, states, ex, track_labels, track_r, rho, traj = self._extract()
        t4 = perf_counter()
        timings = {"prediction": t1 - t0, "cost": t2 - t1, "association": t3 - t2,
                   "update": t4 - t3}
        timings.update(self._after_scan(z, gen))
        return GLMBScanRecord(
            labels=labels, states=states, existence=ex, track_labels=track_labels,
            track_existence=track_r, n_tracks=T, n_meas=self._n_meas(z),
            n_meas_gated=self._n_gated(terms), n_groups=H, invocations=H,
            sweeps=children.sweeps, row_updates=children.row_updates, n_unique=n_children,
            timings=timings, cardinality=rho, n_components=self.n_components,
            retained_mass=retained, carried_mass=carried, retained_mass_reason=reason,
            trajectories=traj,
        )

"""The multi-sensor δ-GLMB filter (Vo, Vo & Beard 2019) on the multi-sensor samplers.

:class:`MultiSensorGLMBFilter` is :class:`~rankedassign.tracking.GLMBFilter` (the components,
the track table, the allocation ``T_h = round(H_upd √w_h / Σ √w)``, the merge of children with
the same track set, pruning, the ``H_max`` cap, mixture reduction and the estimates) with each
component's problem replaced by the multi-sensor one (``../shared/spec/glmb.md`` §6,
``multisensor.md`` §1.3–1.5):

1. shared terms (:meth:`MultiSensorGLMBFilter._terms`): per sensor the χ² gate of every entry
   of the predicted table; per entry every measurement tuple it allows (one gated measurement
   or missed per sensor) with ::

       ln η(t) = ln p + Σ_{v∉D} ln(1 − P_D^v) + Σ_{v∈D} (ln P_D^v − ln κ_v)
                 + ln Σ_c w_c N(z_D; H_D m_c, H_D P_c H_Dᵀ + R_D)

   (``D`` the sensors that detect, ``p`` the survival or birth probability), and the
   single-sensor factors ``θ^(v)`` of MM-Gibbs — once per scan, never per component;
2. per component a :class:`~rankedassign.multisensor.MultiSensorProblem` gathered from them
   (births first, then the component's entries; the columns of sensor ``v`` are the
   measurements some row gates), truncated by the multi-sensor long or short chains
   (``method="exact"``, ``"mm"``, ``"mm-fixed"``) or enumerated. Where the truncation's
   :meth:`~rankedassign.tracking.association.Association.batch_plan` allows it (the chains
   with ``"exact"`` or ``"mm"``), every component's chains run in one compiled call
   (:func:`rankedassign.tracking.multisensor._glmb_kernels.sample_components`), which
   gathers each problem from the shared terms and gives the children of the
   component-by-component path bit for bit;
3. children: a row alive in ``γ`` becomes the entry updated with its tuple (the stacked
   Kalman update on ``z_D``, in sensor order) or predicted only; ``ln w = ln w_h − cost(γ)``.

With adaptive birth (:class:`~rankedassign.tracking.AdaptiveBirth`) the births of the next
scan come from the measurements the posterior does not explain,
``r_U^(v)(j) = 1 − Σ_h w_h Σ_{e ∈ I_h} 1[e took z_j^(v)]``.
"""

from __future__ import annotations

import math
from time import perf_counter
from typing import NamedTuple

import numpy as np

import oracle

from ...engine._kernels import Rules
from ...engine.rng import base_key
from ...multisensor import MultiSensorProblem
from ...numba_options import interruptible
from ...validation import (
    STALE_CONSECUTIVE,
    STALE_OFF,
    STALL_GLOBAL_CONSECUTIVE,
    STALL_OFF,
    check_real,
)
from ..association import GLMB_METHODS, Hypotheses, truncate
from ..common import Children as _Children
from ..common import concat as _concat
from ..common import logsumexp as _logsumexp
from ..common import retained_ratio, zobrist_table
from ..nonlinear.step import multi_sensor_path
from ..single.glmb import EXACT_SCAN_LIMIT, GLMBFilter, GLMBScanRecord
from ..single.lmb import group_tracks
from . import _glmb_kernels
from .adaptive_birth import AdaptiveBirth, empty_birth
from .lmb import _check_model, _sensor_gates, _sensor_log_terms, check_scans

__all__ = ["GLMB_METHODS", "TUPLE_LIMIT", "MultiSensorGLMBFilter", "truncate_multisensor"]

#: Most measurement tuples (over every entry of the predicted table) one scan of
#: :class:`MultiSensorGLMBFilter` builds. Each tuple's likelihood stacks the Kalman matrices of
#: the sensors that detect, for every Gaussian of the entry (about 1.5 KB a tuple with four
#: sensors): four sensors of 30 measurements without gates were 3.7 million tuples, 25 s and
#: 5.4 GB. Checked before anything per tuple is allocated.
TUPLE_LIMIT = 1_000_000
_POS = [0, 2]  # H picks p_x, p_y
_LOG_2PI = math.log(2.0 * math.pi)
#: Seed of the Zobrist keys of the compiled path (the keys only place states in the unique
#: set's table: the unique states and their order do not depend on them).
_ZOBRIST_SEED = np.uint64(0x6D5347)


class _MSTerms(NamedTuple):
    """The scan's shared terms: per sensor the gated measurements, per entry its tuples."""

    used: tuple  # V arrays (U_v,): measurement indices in some entry's gate
    gated: tuple  # V arrays (T, U_v) bool
    zu: tuple  # V arrays (U_v, 2): the gated measurements
    dims: np.ndarray  # (V,) U_v + 1
    strides: np.ndarray  # (V,) of the flat tuple index over dims (C order)
    tup_off: np.ndarray  # (T + 1,) CSR offsets of every entry's tuples (all-missed first)
    tup_g: np.ndarray  # (N, V) per sensor 0 missed or 1 + index into used_v
    tup_la: np.ndarray  # (N,) ln η(t)
    log_dead: np.ndarray  # (T,) ln η(−1)
    log_p: np.ndarray  # (T,) ln p (survival or birth), the MM factor ln s
    log_theta: tuple  # V arrays (T, U_v + 1): ln θ^(v), column 0 missed


def _stacked(m, P, zD, R_D, update: bool):
    """``ln N(z_D; H_D m, H_D P H_Dᵀ + R_D)`` for a batch, with the Kalman update if asked.

    ``m`` (N, 4), ``P`` (N, 4, 4), ``zD`` (N, 2d) stacked positions of ``d`` sensors whose
    noise covariances ``R_D`` (2d, 2d) are block diagonal; every sensor measures the position.
    """
    d = zD.shape[1] // 2
    HPH = P[:, _POS][:, :, _POS]
    S = np.tile(HPH, (1, d, d)) + R_D
    nu = zD - np.tile(m[:, _POS], (1, d))
    L = np.linalg.cholesky(S)
    y = np.linalg.solve(L, nu[:, :, None])[:, :, 0]
    ll = (-0.5 * (y * y).sum(axis=1) - np.log(np.diagonal(L, axis1=1, axis2=2)).sum(axis=1)
          - d * _LOG_2PI)
    if not update:
        return ll, None, None
    PHt = np.tile(P[:, :, _POS], (1, 1, d))  # (N, 4, 2d)
    K = np.linalg.solve(S, PHt.transpose(0, 2, 1)).transpose(0, 2, 1)
    m_upd = m + np.einsum("nij,nj->ni", K, nu)
    P_upd = P - K @ PHt.transpose(0, 2, 1)
    return ll, m_upd, 0.5 * (P_upd + P_upd.transpose(0, 2, 1))


def _block_diag(Rs) -> np.ndarray:
    d = len(Rs)
    out = np.zeros((2 * d, 2 * d))
    for i, R in enumerate(Rs):
        out[2 * i:2 * i + 2, 2 * i:2 * i + 2] = R
    return out


def _zobrist(L: int, K: int) -> np.ndarray:
    """Zobrist keys for states of at most ``L`` positions and values ``0..K − 1`` (cached)."""
    return zobrist_table(L, K, _ZOBRIST_SEED)


def _shifted(logs: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``exp(logs − max)`` along each row (0 where ``logs`` is not finite) and the maxima.

    The operations of the multi-sensor kind's ``prepare_data`` on one row's candidates, run
    here once per scan for every entry: a row's finite candidates all lie among its
    component's columns, so its maximum, and each shifted weight, are the same bits in every
    component.
    """
    m = np.max(logs, axis=1, keepdims=True)
    with np.errstate(invalid="ignore"):
        W = np.exp(logs - m)
    W[~np.isfinite(logs)] = 0.0
    return W, np.squeeze(m, axis=1)


def _segment_logsumexp(x: np.ndarray, seg: np.ndarray, n: int) -> np.ndarray:
    """``ln Σ exp(x)`` within each segment ``seg`` (sorted ids ``0..n-1``, all present)."""
    top = np.full(n, -np.inf)
    np.maximum.at(top, seg, x)
    safe = np.where(np.isfinite(top), top, 0.0)
    with np.errstate(divide="ignore"):
        return np.log(np.bincount(seg, weights=np.exp(x - safe[seg]), minlength=n)) + safe


def _entry_tuples(gated, T: int, V: int):
    """Every entry's measurement tuples: the product of its gated lists (0 = missed), the
    all-missed tuple first, in ``itertools.product``'s order (the last sensor fastest).

    ``gated[v]`` is the ``(T, U_v)`` gate of sensor ``v``. Returns ``tup_off`` (T + 1,), the
    CSR offsets, ``tup_g`` (N, V), per sensor 0 or ``1 +`` the gated measurement, and
    ``tup_e`` (N,), the entry of every tuple. Built for all entries at once: tuple ``k`` of an
    entry has the mixed-radix digits of ``k`` over its lists' lengths (a loop over the entries
    cost more than the rest of the scan's terms).
    """
    nz = [np.nonzero(g) for g in gated]  # per sensor, every entry's gated list (increasing)
    width = np.ones((T, V), dtype=np.int64)  # 1 + the list's length: missed, then the list
    for v, (r, _) in enumerate(nz):
        width[:, v] += np.bincount(r, minlength=T)
    counts = np.prod(width, axis=1, dtype=np.int64)
    tup_off = np.concatenate([[0], np.cumsum(counts)]).astype(np.int64)
    tup_e = np.repeat(np.arange(T), counts)
    k = np.arange(tup_off[-1], dtype=np.int64) - tup_off[:-1][tup_e]
    tup_g = np.empty((k.size, V), dtype=np.int64)
    stride = np.ones(T, dtype=np.int64)
    for v in range(V - 1, -1, -1):
        digit = (k // stride[tup_e]) % width[tup_e, v]
        start = np.concatenate([[0], np.cumsum(width[:, v] - 1)])[:-1]  # the list in nz[v]
        cols = nz[v][1]
        pick = cols[np.maximum(start[tup_e] + digit - 1, 0)] + 1 if cols.size else 0
        tup_g[:, v] = np.where(digit > 0, pick, 0)
        stride *= width[:, v]
    return tup_off, tup_g, tup_e


def truncate_multisensor(association, problem: MultiSensorProblem, budget: int,
                         rng=None) -> Hypotheses:
    """Truncate one component's multi-sensor problem with ``association`` and ``T_h = budget``.

    Parameters
    ----------
    association : OriginalGibbs, ShortChainGibbs, HerdedGibbs, Exact or object
        The library's truncations (their ``method`` one of :data:`GLMB_METHODS`), or any
        object with a method ``hypotheses(problem, budget, rng)`` returning assignments of
        shape ``(n, P, V)``. The same as
        :func:`~rankedassign.tracking.association.truncate`, kept under this name.
    problem : MultiSensorProblem
    budget : int
        The component's count ``T_h >= 0``: the chains get ``T_h − 1`` observations as in
        :class:`~rankedassign.tracking.GLMBFilter`; :class:`~rankedassign.tracking.Exact`
        ignores it (its ``fallback``, if any, gets it on a problem beyond the enumeration's
        limit, :data:`~rankedassign.tracking.association.EXACT_LIMIT`).
    rng : optional
        Anything :func:`numpy.random.default_rng` accepts.

    Returns
    -------
    Hypotheses
        ``assignments`` of shape ``(n, P, V)`` and their exact costs ``−ln w(γ)``.

    Raises
    ------
    ValueError
        If :class:`~rankedassign.tracking.Exact` without a fallback meets a problem of more than
        :data:`~rankedassign.tracking.association.EXACT_LIMIT` assignments, or a custom
        association returns duplicates,
        infeasible assignments or wrong shapes.

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign.multisensor import MultiSensorProblem
    >>> from rankedassign.tracking import Exact
    >>> from rankedassign.tracking.multisensor.glmb import truncate_multisensor
    >>> p = MultiSensorProblem.from_eta([1.0], np.ones((1, 2, 2)))
    >>> truncate_multisensor(Exact(), p, 0).assignments.shape
    (5, 1, 2)
    """
    return truncate(association, problem, budget, rng, caller="MultiSensorGLMBFilter")


def _check_tuple_count(gated, T: int, V: int) -> None:
    """Refuse a scan whose entries allow more than :data:`TUPLE_LIMIT` measurement tuples.

    ``gated[v]`` is the ``(T, U_v)`` gate of sensor ``v``; entry ``t`` has
    ``prod_v (1 + sum_j gated[v][t, j])`` tuples. Counted in Python ints: the product of a few
    sensors' counts can pass 2**63.
    """
    per_sensor = [np.asarray(g.sum(axis=1), dtype=np.int64) for g in gated]
    approx = np.ones(T)
    for c in per_sensor:
        approx *= c + 1.0
    if approx.sum() <= TUPLE_LIMIT:
        return
    total = sum(math.prod(int(c[t]) + 1 for c in per_sensor) for t in range(T))
    widest = [int(c.max(initial=0)) for c in per_sensor]
    raise ValueError(
        f"MultiSensorGLMBFilter: the {T} entries of this scan allow {total} measurement tuples "
        f"(one gated measurement or missed per sensor; at most {widest} gated measurements "
        f"per sensor for one entry), above TUPLE_LIMIT = {TUPLE_LIMIT}: each tuple's stacked "
        f"Kalman terms would be built. Gate the measurements (gate_prob, not None), fuse "
        f"fewer sensors, or thin the scans"
    )



class MultiSensorGLMBFilter(GLMBFilter):
    """δ-GLMB filter fusing ``V`` position sensors by the multi-sensor joint update.

    Parameters
    ----------
    model : MultiSensorModel, Model, NonlinearMultiSensorModel or NonlinearModel
        A single-sensor model is taken as ``V = 1`` (as
        :class:`~rankedassign.tracking.MultiSensorLMBFilter`).
    association : ShortChainGibbs, OriginalGibbs, HerdedGibbs, Exact or object
        The truncation of every component's multi-sensor problem with its count ``T_h``, as
        in :class:`~rankedassign.tracking.GLMBFilter`: the long chain runs
        ``min(T_h − 1, n_obs)`` sweeps, the short chains ``L = min(N_C, T_h − 1)`` sweeps, at
        most ``min(N_S, ⌈(T_h − 1) / L⌉)`` of them, with the row kernel ``method`` of the
        association (one of :data:`GLMB_METHODS`); :class:`~rankedassign.tracking.Exact`
        enumerates every assignment (at most
        :data:`~rankedassign.tracking.association.EXACT_LIMIT` per component, or its
        ``fallback`` runs). Any object with a method
        ``hypotheses(problem, budget, rng)`` works too. Murty, LBP and associations that give
        marginals only are refused with ``TypeError``
        (:func:`~rankedassign.tracking.check_truncation`).
    birth : AdaptiveBirth or None, optional
        None (default): the model's static birth at every scan. An
        :class:`~rankedassign.tracking.AdaptiveBirth`: the births of scan ``k + 1`` are made
        from the measurements of scan ``k`` that the posterior does not explain (module
        docstring); births with ``r_B <= birth_threshold`` are dropped.
    birth_threshold : float, optional
        See ``birth`` (default ``10⁻³``, the LMB filter's ``prune_track``).
    **options
        The options of :class:`~rankedassign.tracking.GLMBFilter`: ``h_upd``, ``h_max``,
        ``prune_hypothesis``, ``gate_prob`` (per sensor), ``extraction``, ``theta_upper``,
        ``theta_lower``, ``prune_component``, ``merge_threshold``, ``merge_rule``,
        ``max_components``, ``retained_mass`` (by the multi-sensor DP, per connected group of
        rows), ``keep_histories``.

    Attributes
    ----------
    V : int
        Number of sensors.
    n_births : int
        Births appended by the last prediction.
    r_U : list of ndarray or None
        With adaptive birth, per sensor ``r_U`` of the last scan's measurements.

    Notes
    -----
    A component whose count ``T_h`` is 0 or 1 keeps its all-missed child alone (the chains'
    start state), without building its problem. A history node records, per sensor, the
    measurement index of the update (−1 missed): :meth:`components` gives a track's history as
    one tuple of ``V`` indices per scan. With one sensor the filter is the single-sensor
    δ-GLMB filter on the same data (tested with enumeration to ``10⁻¹²`` in the weights).

    References
    ----------
    .. [1] B.-N. Vo, B.-T. Vo, M. Beard, "Multi-Sensor Multi-Object Tracking with the
       Generalized Labeled Multi-Bernoulli Filter", IEEE Trans. Signal Process.
       67(23):5952-5967, 2019.
    .. [2] B.-N. Vo, B.-T. Vo, H. G. Hoang, "An Efficient Implementation of the Generalized
       Labeled Multi-Bernoulli Filter", IEEE Trans. Signal Process. 65(8):1975-1987, 2017.
    .. [3] A. Trezza, D. J. Bucci Jr., P. K. Varshney, "On Gibbs Sampling Architecture for
       Labeled Random Finite Sets Multi-Object Tracking", arXiv:2306.15135, 2023.

    Examples
    --------
    >>> from rankedassign.tracking import make_multisensor_model
    >>> from rankedassign.tracking import ShortChainGibbs
    >>> from rankedassign.tracking.multisensor.glmb import MultiSensorGLMBFilter
    >>> model = make_multisensor_model((0, 1), birth="narrow")
    >>> f = MultiSensorGLMBFilter(model, ShortChainGibbs(
    ...     400, 25, tau_stall=5, tau_stale=10, method="mm"))
    >>> for k in range(4):          # one target near birth location 2, seen by both sensors
    ...     z = [[400.0 - 10 * k, -600.0 + 5 * k]]
    ...     rec = f.step([z, z], rng=k)
    >>> rec.labels.tolist(), int(rec.cardinality.argmax())
    ([[1, 2]], 1)
    """

    def __init__(self, model, association, *, birth: AdaptiveBirth | None = None,
                 birth_threshold: float = 1e-3, **options):
        model = _check_model(model, birth)
        self.adaptive_birth = birth
        #: The non-linear model's per-sensor gates and stacked update (None: linear).
        self._ms = multi_sensor_path(model, options.get("gate_prob", 0.9999999))
        self.birth_threshold = check_real(birth_threshold, "birth_threshold", minimum=0.0)
        self.ms_model = model
        self.V = model.n_sensors
        self._meas_shape = (self.V,)
        super().__init__(model.single(0), association, **options)
        self._Rs = [np.array(s.R, dtype=np.float64) for s in model.sensors]
        self._log_pds, self._log_misses, self._log_kappas = _sensor_log_terms(model)

    _sensors = "multi-sensor"

    def _max_birth_index(self):
        # adaptive births are labelled (k, 1..n) with n changing from scan to scan
        return None if self.adaptive_birth is not None else int(self._birth_r.size)

    def reset(self) -> None:
        """Forget every track (and the pending adaptive births); one empty component."""
        super().reset()
        self.n_births = 0
        self.r_U = None
        if getattr(self, "adaptive_birth", None) is not None:
            b = empty_birth()
            self._birth_r = np.ascontiguousarray(b.r, dtype=np.float64)
            self._birth_m = np.ascontiguousarray(b.means, dtype=np.float64).reshape(-1, 4)
            self._birth_P = np.ascontiguousarray(b.covs, dtype=np.float64).reshape(-1, 4, 4)

    # ----------------------------------------------------------------------- shared terms
    def _terms(self, zs, p_exist: np.ndarray) -> _MSTerms:
        """``ln η`` of every entry's tuples, the MM factors and the per-sensor gates."""
        T = self.n_tracks
        V = self.V
        with np.errstate(divide="ignore"):
            log_p = np.log(p_exist)
            log_dead = np.log1p(-p_exist)
        used, gated = _sensor_gates(self, zs)
        zu = [z[u] for z, u in zip(zs, used, strict=True)]
        dims = np.array([u.size + 1 for u in used], dtype=np.int64)
        strides = np.ones(V, dtype=np.int64)
        for v in range(V - 2, -1, -1):
            strides[v] = strides[v + 1] * dims[v + 1]
        # sized before anything per tuple is allocated: without gates (gate_prob=None) an
        # entry has prod_v (M_v + 1) tuples
        _check_tuple_count(gated, T, V)
        tup_off, tup_g, tup_e = _entry_tuples(gated, T, V)
        det = tup_g > 0
        # ln η(t) = ln p + Σ_{v∉D} ln(1 − P_D^v) + Σ_{v∈D} (ln P_D^v − ln κ_v) + ln q(z_D)
        with np.errstate(invalid="ignore"):
            tup_la = (log_p[tup_e] + np.where(det, self._log_pds - self._log_kappas,
                                              self._log_misses).sum(axis=1))
        log_q = np.zeros(tup_g.shape[0])
        patterns = det @ (1 << np.arange(V))
        log_w = np.log(self.w)
        for pat in np.unique(patterns[patterns > 0]):
            D = [v for v in range(V) if pat >> v & 1]
            sel = np.flatnonzero(patterns == pat)
            n_c = np.diff(self.offsets)[tup_e[sel]]
            pair = np.repeat(np.arange(sel.size), n_c)
            comp = (np.repeat(self.offsets[:-1][tup_e[sel]] - np.cumsum(np.r_[0, n_c[:-1]]),
                              n_c) + np.arange(n_c.sum()))
            zD = np.hstack([zu[v][tup_g[sel[pair], v] - 1] for v in D])
            ll, _, _ = self._stacked(D, self.m[comp], self.P[comp], zD, update=False)
            log_q[sel] = _segment_logsumexp(ll + log_w[comp], pair, sel.size)
        tup_la = tup_la + log_q
        # MM factors: ln s = ln p, ln θ^(v)(0) = ln(1 − P_D^v), ln θ^(v)(j) from the one-sensor
        # tuples (the entry's single-detection likelihoods)
        log_theta = []
        for v in range(V):
            th = np.full((T, dims[v]), -np.inf)
            th[:, 0] = self._log_misses[v]
            one = np.flatnonzero(patterns == (1 << v))
            th[tup_e[one], tup_g[one, v]] = (self._log_pds[v] - self._log_kappas[v]
                                             + log_q[one])
            log_theta.append(th)
        return _MSTerms(tuple(used), tuple(gated), tuple(zu), dims, strides, tup_off, tup_g,
                        np.ascontiguousarray(tup_la), log_dead, log_p, tuple(log_theta))

    def _radix(self, terms: _MSTerms) -> int:
        return int(np.prod(terms.dims))

    def _history_meas(self, terms: _MSTerms, j_src: np.ndarray) -> np.ndarray:
        g = ((j_src + 1)[:, None] // terms.strides[None, :]) % terms.dims[None, :]
        out = np.full(g.shape, -1, dtype=np.int64)
        for v in range(self.V):
            hit = g[:, v] > 0
            out[hit, v] = terms.used[v][g[hit, v] - 1]
        return out

    # ----------------------------------------------------------------------- a component
    def _rows(self, h: int) -> np.ndarray:
        return np.r_[self._births, self.comp_tracks[self.comp_off[h]:self.comp_off[h + 1]]] \
            .astype(np.int64)

    def _problem(self, rows: np.ndarray, terms: _MSTerms):
        """The columns per sensor and the MultiSensorProblem of the entries ``rows``."""
        V = self.V
        cols = [np.flatnonzero(terms.gated[v][rows].any(axis=0)) for v in range(V)]
        maps = []
        for v in range(V):
            mp = np.full(terms.dims[v], -1, dtype=np.int64)
            mp[0] = 0
            mp[cols[v] + 1] = np.arange(1, cols[v].size + 1)
            maps.append(mp)
        n_t = terms.tup_off[rows + 1] - terms.tup_off[rows]
        idx = (np.repeat(terms.tup_off[rows] - np.cumsum(np.r_[0, n_t[:-1]]), n_t)
               + np.arange(n_t.sum()))
        g = terms.tup_g[idx]
        la = np.full((rows.size, *(c.size + 1 for c in cols)), -np.inf)
        la[(np.repeat(np.arange(rows.size), n_t), *(maps[v][g[:, v]] for v in range(V)))] = \
            terms.tup_la[idx]
        theta = [terms.log_theta[v][rows][:, np.r_[0, cols[v] + 1]] for v in range(V)]
        return cols, MultiSensorProblem(terms.log_dead[rows], la, terms.log_p[rows], theta)

    def _batch_terms(self, terms: _MSTerms, method: str) -> _glmb_kernels.ScanTerms:
        """The scan's terms as the compiled path reads them, with the shifted weights of the
        row conditional ``method`` (``"exact"`` or ``"mm"``) of every entry."""
        T = self.n_tracks
        c = np.ascontiguousarray
        gated = c(np.hstack(terms.gated))
        goff = np.r_[0, np.cumsum([g.shape[1] for g in terms.gated])].astype(np.int64)
        toff = np.r_[0, np.cumsum([th.shape[1] for th in terms.log_theta])].astype(np.int64)
        none = np.empty(0)
        if method == "exact":
            # exp(ln η − m) over a row's candidates, dead and its tuples (prepare_data)
            tup_e = np.repeat(np.arange(T), np.diff(terms.tup_off))
            top = terms.log_dead.copy()
            np.maximum.at(top, tup_e, terms.tup_la)
            with np.errstate(invalid="ignore"):
                tup_w = np.exp(terms.tup_la - top[tup_e])
                dead_w = np.exp(terms.log_dead - top)
            tup_w[~np.isfinite(terms.tup_la)] = 0.0
            dead_w[~np.isfinite(terms.log_dead)] = 0.0
            lth = Th = np.zeros((T, 0))
            Ea = Ed = none
        else:
            # MM's factors (prepare_data): θ shifted per sensor; the alive prefactor
            # s Π_v max_j θ^(v)(j) and dead, shifted together
            tup_w = dead_w = none
            parts = [_shifted(np.asarray(th, dtype=np.float64)) for th in terms.log_theta]
            lth = c(np.hstack(terms.log_theta))
            Th = c(np.hstack([W for W, _ in parts]))
            top = np.stack([m for _, m in parts], axis=1)
            with np.errstate(invalid="ignore"):
                lalive = terms.log_p + top.sum(axis=1)
                m = np.maximum(lalive, terms.log_dead)
                Ea = np.nan_to_num(np.exp(lalive - m), nan=0.0)
                Ed = np.nan_to_num(np.exp(terms.log_dead - m), nan=0.0)
        return _glmb_kernels.ScanTerms(
            comp_off=self.comp_off, comp_tracks=self.comp_tracks,
            births=c(self._births, dtype=np.int64), gated=gated, goff=goff,
            tup_off=terms.tup_off, tup_g=c(terms.tup_g), tup_la=terms.tup_la, tup_w=c(tup_w),
            log_dead=c(terms.log_dead), dead_w=c(dead_w), log_p=c(terms.log_p), toff=toff,
            lth=lth, Th=Th, Ea=c(Ea), Ed=c(Ed), strides=c(terms.strides))

    def _sample_batch(self, terms: _MSTerms, counts: np.ndarray,
                      base: np.ndarray) -> _Children:
        """The chains of every component in one compiled call: the children of
        :meth:`_truncate`'s component-by-component path, bit for bit."""
        plan = self._plan
        H = self.n_components
        chains, length = self.association.budget(counts)
        # the per-component path seeds each component's sampler with rng=int(base[h]): the
        # streams are those of that seed's base key
        keys = np.zeros(H, dtype=np.uint64)
        for h in np.flatnonzero(chains > 0):
            keys[h] = base_key(int(base[h]))
        rules = Rules(STALL_GLOBAL_CONSECUTIVE if plan.tau_stall else STALL_OFF, plan.tau_stall,
                      STALE_CONSECUTIVE if plan.tau_stale else STALE_OFF, plan.tau_stale)
        sizes = self.comp_off[1:] - self.comp_off[:-1]
        P_max = int(self._births.size + (sizes.max() if H else 0))
        U_max = max((u.size for u in terms.used), default=0)
        method = _glmb_kernels.EXACT if plan.method == "exact" else _glmb_kernels.MM
        with interruptible:
            comp, cost, off, entry, meas, sweeps, n_rows = _glmb_kernels.sample_components(
                self._batch_terms(terms, plan.method), method, plan.random_scan, chains,
                length, rules, keys, _zobrist(P_max * self.V, U_max + 2))
        kept = np.cumsum(np.bincount(comp, minlength=H))
        if H and kept[-1] > EXACT_SCAN_LIMIT:
            h = int(np.argmax(kept > EXACT_SCAN_LIMIT))  # where the per-component path stops
            raise ValueError(
                f"the truncation keeps more than EXACT_SCAN_LIMIT = {EXACT_SCAN_LIMIT} "
                f"assignments in one scan (component {h} of {H}); use the chains for "
                "problems of this size")
        return _Children(comp, cost, off, entry, meas, int(sweeps.sum()),
                         int((sweeps * n_rows).sum()))

    def _truncate(self, terms: _MSTerms, counts: np.ndarray, base: np.ndarray) -> _Children:
        """The children of every component (spec §2.3): in one compiled call where the
        truncation's plan allows it, else component by component."""
        H = self.n_components
        # the chains start with every row missed by every sensor: a row that cannot be (its
        # all-missed tuple has weight 0) is refused by the sampler's start state, per component
        if (self._plan is not None and self._plan.chains and self.V
                and not np.isneginf(terms.tup_la[terms.tup_off[:-1]]).any()):
            return self._sample_batch(terms, counts, base)
        # a chain truncation keeps its start state alone for a count of 0 or 1
        chains_ok = self._plan is not None and self._plan.start_alone
        comp, cost, off, entry, meas = [], [], [0], [], []
        sweeps = row_updates = 0
        kept = 0
        for h in range(H):
            rows = self._rows(h)
            if rows.size == 0 or (chains_ok and counts[h] <= 1):
                # the chains' start state alone: every row missed by every sensor (an empty
                # component has the empty assignment only)
                a_cost = np.array([-terms.tup_la[terms.tup_off[rows]].sum()])
                comp.append(np.array([h], dtype=np.int64))
                cost.append(a_cost)
                off.append(off[-1] + rows.size)
                entry.append(rows)
                meas.append(np.full(rows.size, -1, dtype=np.int64))
                kept += 1
                continue
            cols, problem = self._problem(rows, terms)
            with interruptible:
                hyp = truncate_multisensor(self.association, problem, int(counts[h]),
                                           rng=int(base[h]))
            a = np.asarray(hyp.assignments, dtype=np.int64).reshape(-1, rows.size, self.V)
            kept += a.shape[0]
            if kept > EXACT_SCAN_LIMIT:
                raise ValueError(
                    f"the truncation keeps more than EXACT_SCAN_LIMIT = {EXACT_SCAN_LIMIT} "
                    f"assignments in one scan (component {h} of {H}); use the chains for "
                    "problems of this size")
            alive = a[:, :, 0] >= 0
            flat = np.zeros(a.shape[:2], dtype=np.int64)
            for v in range(self.V):
                gv = a[:, :, v]
                glob = np.where(gv > 0, cols[v][np.maximum(gv - 1, 0)] + 1 if cols[v].size
                                else 0, 0)
                flat += glob * terms.strides[v]
            comp.append(np.full(a.shape[0], h, dtype=np.int64))
            cost.append(np.asarray(hyp.costs, dtype=np.float64))
            off.extend((off[-1] + np.cumsum(alive.sum(axis=1))).tolist())
            entry.append(np.broadcast_to(rows, alive.shape)[alive])
            meas.append(flat[alive] - 1)
            sweeps += hyp.sweeps
            row_updates += hyp.row_updates
        return _Children(_concat(comp, np.int64), _concat(cost, np.float64),
                         np.array(off, dtype=np.int64), _concat(entry, np.int64),
                         _concat(meas, np.int64), sweeps, row_updates)

    # ----------------------------------------------------------------------- retained mass
    def _retained(self, terms: _MSTerms, children: _Children) -> tuple[float, str]:
        """``Σ_h w_h K_h / Σ_h w_h Z_h`` with ``Z_h`` the product over the component's groups
        of rows that share no measurement of any sensor (each by the multi-sensor DP)."""
        H = self.n_components
        log_Z = np.zeros(H)
        cache: dict = {}
        gated_all = np.hstack(terms.gated) if terms.gated else np.zeros((self.n_tracks, 0))
        for h in range(H):
            rows = self._rows(h)
            for g_rows, _ in group_tracks(gated_all[rows]):
                rr = rows[g_rows]
                name = tuple(rr.tolist())
                value = cache.get(name)
                if value is None:
                    if rr.size == 1:
                        t = rr[0]
                        value = _logsumexp(np.r_[terms.tup_la[terms.tup_off[t]:
                                                              terms.tup_off[t + 1]],
                                                 terms.log_dead[t]])
                    else:
                        _, problem = self._problem(rr, terms)
                        try:
                            with interruptible:
                                value = oracle.log_normalizer(problem)
                        except ValueError as err:
                            return math.nan, (
                                f"component {h} has a group of {rr.size} rows and "
                                f"M = {problem.n_meas} measurements beyond the oracle's DP: "
                                f"{err}")
                    cache[name] = value
                log_Z[h] += value
        return retained_ratio(self.comp_w, children, log_Z), ""

    def _stacked(self, D, m, P, zD, update: bool):
        """``ln N(z_D; ...)`` of a batch of components, with the update if asked: the linear
        stacked Kalman step, or the model's filter on the stacked sensors ``D``."""
        if self._ms is not None:
            return self._ms.stacked(D, m, P, zD, update)
        return _stacked(m, P, zD, _block_diag([self._Rs[v] for v in D]), update=update)

    # ----------------------------------------------------------------------- the update
    def _kalman(self, terms: _MSTerms, e_src: np.ndarray, j_src: np.ndarray) -> None:
        """Mixtures of the new entries: ``e_src`` predicted (``j_src = −1``) or updated with
        its tuple (the stacked update on ``z_D``); then pruned, merged and capped."""
        n_comp = np.diff(self.offsets)[e_src]
        offsets = np.concatenate([[0], np.cumsum(n_comp)]).astype(np.int64)
        within = np.arange(offsets[-1]) - np.repeat(offsets[:-1], n_comp)
        comp = np.repeat(self.offsets[:-1][e_src], n_comp) + within
        new = np.repeat(np.arange(e_src.size), n_comp)
        g = ((j_src + 1)[:, None] // terms.strides[None, :]) % terms.dims[None, :]
        g = g[new]
        w = self.w[comp].copy()
        m = self.m[comp].copy()
        P = self.P[comp].copy()
        patterns = (g > 0) @ (1 << np.arange(self.V))
        for pat in np.unique(patterns[patterns > 0]):
            D = [v for v in range(self.V) if pat >> v & 1]
            sel = np.flatnonzero(patterns == pat)
            zD = np.hstack([terms.zu[v][g[sel, v] - 1] for v in D])
            ll, m_upd, P_upd = self._stacked(D, self.m[comp[sel]], self.P[comp[sel]], zD,
                                             update=True)
            # w̃_c = w_c N(z_D; ...) / Σ_c' w_c' N(z_D; ...) within each new entry
            seg_ids, seg = np.unique(new[sel], return_inverse=True)
            lw = np.log(self.w[comp[sel]]) + ll
            w[sel] = np.exp(lw - _segment_logsumexp(lw, seg.reshape(-1), seg_ids.size)[seg])
            m[sel] = m_upd
            P[sel] = P_upd
        self._reduce_mixtures(offsets, w, m, P, e_src.size)

    # ----------------------------------------------------------------------- adaptive birth
    def _adaptive_births(self, zs, gen) -> dict:
        """The births of the next scan from ``r_U`` of this scan's measurements."""
        if self.adaptive_birth is None:
            return {}
        t0 = perf_counter()
        r_e, last = self._entry_measurements()
        r_U = []
        for v, z in enumerate(zs):
            hit = last[:, v] >= 0
            r_A = np.bincount(last[hit, v], weights=r_e[hit], minlength=z.shape[0])
            r_U.append(np.clip(1.0 - r_A, 0.0, 1.0))
        self.r_U = r_U
        birth_rng = gen.spawn(1)[0]
        m = self.ms_model
        b = self.adaptive_birth.births(zs, r_U, sensors=m.sensors, clutters=m.clutters,
                                       F=self._F, Q=self._Q, rng=birth_rng,
                                       r_min=self.birth_threshold)
        self._birth_r = np.ascontiguousarray(b.r, dtype=np.float64)
        self._birth_m = np.ascontiguousarray(b.means, dtype=np.float64).reshape(-1, 4)
        self._birth_P = np.ascontiguousarray(b.covs, dtype=np.float64).reshape(-1, 4, 4)
        return {"birth": perf_counter() - t0}

    # ----------------------------------------------------------------------- the scan
    def step(self, zs, rng=None) -> GLMBScanRecord:
        """Run one scan: predict, truncate every component, update, estimate.

        Parameters
        ----------
        zs : sequence of V array_like, shape (M_v, d_v)
            One measurement set per sensor, in the model's sensor order.
        rng : optional
            Anything :func:`numpy.random.default_rng` accepts; one draw keys the streams of
            every component, a child spawned after it drives the adaptive birth.

        Returns
        -------
        GLMBScanRecord
            ``n_meas`` and ``n_meas_gated`` count every sensor; ``timings`` has ``birth``
            with adaptive birth.

        Raises
        ------
        TypeError, ValueError
            If ``zs`` is not one measurement array per sensor (the message gives ``V``), on
            bad measurements (the message names the sensor), when the entries of the scan
            allow more than :data:`TUPLE_LIMIT` measurement tuples (``ValueError`` with the
            count, before they are built), or as
            :meth:`GLMBFilter.step <rankedassign.tracking.GLMBFilter.step>`.
        """
        self.n_births = int(self._birth_r.size)  # the births this scan's prediction appends
        return self._scan(check_scans(zs, self.V, self._ms), rng)

    @staticmethod
    def _n_meas(zs) -> int:
        return int(sum(z.shape[0] for z in zs))

    @staticmethod
    def _n_gated(terms) -> int:
        return int(sum(u.size for u in terms.used))

    def _after_scan(self, zs, gen) -> dict:
        return self._adaptive_births(zs, gen)

"""The labeled multi-Bernoulli (LMB) filter with a pluggable ranked-assignment association.

One scan of :class:`LMBFilter` (spec §6):

1. prediction (6.1): survivors ``r ← P_S r``, Gaussian components ``m ← F m``,
   ``P ← F P Fᵀ + Q``; the birth Bernoullis are appended with labels ``(k, b)``;
2. cost matrix (6.2): ``η_i(−1) = 1 − r_i``, ``η_i(0) = r_i (1 − P_D)``,
   ``η_i(j) = r_i P_D q_i(z_j)`` with ``q_i`` the mixture likelihood over ``κ``, built in log
   space with :meth:`AssignmentProblem.from_log_eta`; optional χ² gating drops pairs and the
   measurements no track gates; optional grouping (§6.5a) splits the problem into independent
   groups;
3. association: any :class:`~rankedassign.tracking.association.Association` returns the
   marginals ``β`` of every problem;
4. update (6.3–6.4): ``r_i = Σ_{j≥0} β_ij`` and the posterior mixture
   ``(1/r_i) Σ_j β_ij p^(j)``; housekeeping (track pruning and cap, mixture pruning, merging and
   cap) and state extraction (hysteresis 6.5, or MAP cardinality).

The Kalman and likelihood algebra is batched with numpy over all components and measurements;
the mixture reduction runs in one compiled kernel per scan.
"""

from __future__ import annotations

import math
from time import perf_counter
from typing import NamedTuple

import numpy as np

from ..numba_options import jit
from ..problem import AssignmentProblem
from .association import Association, AssociationResult
from .models import Model

__all__ = [
    "MERGE_RULES",
    "LMBFilter",
    "ScanRecord",
    "gate_threshold",
    "group_tracks",
    "map_cardinality",
]

#: Mixture merging criteria of :class:`LMBFilter` (``merge_rule``), with their kernel codes.
MERGE_RULES = {"bhattacharyya": 0, "vo-ma": 1, "heaviest": 2}

_LOG_2PI = math.log(2.0 * math.pi)


def gate_threshold(gate_prob: float, dim: int = 2) -> float:
    """χ² gate on the squared Mahalanobis distance for a ``dim``-dimensional measurement.

    Parameters
    ----------
    gate_prob : float
        Probability mass inside the gate, in ``(0, 1)``.
    dim : int
        Measurement dimension.

    Returns
    -------
    float
        ``χ²_dim⁻¹(gate_prob)``; for ``dim = 2`` exactly ``−2 ln(1 − gate_prob)``.

    Examples
    --------
    >>> from rankedassign.tracking.lmb import gate_threshold
    >>> round(gate_threshold(0.9999999), 3)
    32.236
    """
    if not (0 < gate_prob < 1):
        raise ValueError(f"gate_prob must be in (0, 1), got {gate_prob}")
    if dim == 2:
        return -2.0 * math.log1p(-gate_prob)
    from scipy.stats import chi2

    return float(chi2.ppf(gate_prob, dim))


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

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign.tracking.lmb import group_tracks
    >>> g = np.array([[1, 0, 0], [0, 0, 1], [1, 1, 0], [0, 0, 0]], dtype=bool)
    >>> [(r.tolist(), c.tolist()) for r, c in group_tracks(g)]
    [([0, 2], [0, 1]), ([1], [2]), ([3], [])]
    """
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    T, M = gated.shape
    i, j = np.nonzero(gated)
    n = T + M
    graph = coo_matrix((np.ones(i.size), (i, T + j)), shape=(n, n))
    _, comp = connected_components(graph, directed=False)
    groups = []
    seen = {}
    for t in range(T):
        c = comp[t]
        if c not in seen:
            seen[c] = len(groups)
            groups.append(c)
    track_comp = comp[:T]
    meas_comp = comp[T:]
    return [(np.flatnonzero(track_comp == c), np.flatnonzero(meas_comp == c)) for c in groups]


def map_cardinality(r: np.ndarray) -> int:
    """MAP cardinality of an LMB with existence probabilities ``r`` (Vo's default extraction).

    The cardinality distribution of independent Bernoullis is the Poisson-binomial, computed by
    the convolution recursion; ties go to the smaller cardinality.

    Examples
    --------
    >>> from rankedassign.tracking.lmb import map_cardinality
    >>> map_cardinality([0.9, 0.8, 0.1]), map_cardinality([])
    (2, 0)
    """
    rho = np.zeros(len(r) + 1)
    rho[0] = 1.0
    for q in np.asarray(r, dtype=np.float64):
        rho[1:] = rho[1:] * (1.0 - q) + rho[:-1] * q
        rho[0] *= 1.0 - q
    return int(np.argmax(rho))


class ScanRecord(NamedTuple):
    """What the filter reports for one scan.

    Attributes
    ----------
    labels : ndarray of int64, shape (n, 2)
        Labels ``(birth scan, birth index)`` (both 1-based) of the reported tracks.
    states : ndarray, shape (n, 4)
        Their state estimates.
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

    labels: np.ndarray
    states: np.ndarray
    existence: np.ndarray
    track_labels: np.ndarray
    track_existence: np.ndarray
    n_tracks: int
    n_meas: int
    n_meas_gated: int
    n_groups: int
    invocations: int
    sweeps: int
    row_updates: int
    n_unique: int
    timings: dict


# ------------------------------------------------------------------------------- kernels
@jit()
def _reduce_mixtures(offsets, w, m, P, keep, elim, merge_thr, cap, rule):  # pragma: no cover
    """Prune, merge and cap the Gaussian mixture of every kept track.

    Parameters
    ----------
    offsets : int64 (T + 1,)
        Component range of track ``t`` is ``offsets[t]:offsets[t + 1]``.
    w, m, P : (C,), (C, 4), (C, 4, 4)
        Component weights (summing to 1 per track), means and covariances.
    keep : bool (T,)
        Tracks to keep; the others are dropped.
    elim, merge_thr, cap : float, float, int
        Pruning threshold (keep ``w > elim``; the heaviest component always stays), merging
        threshold ``U`` and the maximum number of components.
    rule : int
        Merging criterion (:data:`MERGE_RULES`), ``j`` the heaviest remaining component and
        ``i`` a candidate, ``d = m_i − m_j``:

        * 0, ``"bhattacharyya"``: ``dᵀ P̄⁻¹ d + 4 ln(|P̄| / √(|P_i| |P_j|)) <= U`` with
          ``P̄ = (P_i + P_j) / 2``, i.e. eight times the Bhattacharyya distance of the two
          Gaussians. It equals the Mahalanobis test below when ``P_i = P_j`` and refuses to
          merge components of very different spread;
        * 1, ``"vo-ma"``: ``dᵀ P_i⁻¹ d <= U`` (Vo & Ma 2006, Table II);
        * 2, ``"heaviest"``: ``dᵀ P_j⁻¹ d <= U`` (the distance of Vo's MATLAB ``gaus_merge``).

    Returns
    -------
    (offsets', w', m', P')
        Components of each kept track in decreasing weight, weights renormalised.

    Notes
    -----
    Pruning and merging of Vo & Ma (2006, Table II) followed by the cap of Vo's code
    (``gaus_cap``), with the thresholds of spec §6.4: repeatedly take the heaviest remaining
    component ``j``, merge every remaining ``i`` that passes the ``rule`` into
    ``w = Σ w_i``, ``m = Σ w_i m_i / w``, ``P = Σ w_i (P_i + (m − m_i)(m − m_i)ᵀ) / w``
    (moment matching). Vo's MATLAB ``gaus_merge`` also omits the spread-of-means term; that
    is not offered.

    Why the Bhattacharyya criterion is the default: after its first scan, a newborn track of
    the paper's preset holds sharp detection components (σ ≈ 10 m) and the broad
    missed-detection component of the birth (σ = 300 m). Both Mahalanobis rules merge the
    broad component into the detection component of a target born near the birth mean, and
    moment matching then gives a σ ≈ 100 m component that explains the next detection
    poorly; the track's existence barely grows, the next scan's birth picks the target up as
    well, and the two duplicate tracks share it for several scans with ``r ≈ 0.5`` each. The
    Bhattacharyya test keeps the two apart. Measured with ``Exact()`` on the paper's preset,
    seeds 0–4: mean OSPA(2) 39.2 m (Vo & Ma), 43.8 m (heaviest), 36.0 m (Bhattacharyya),
    36.5 m with ``merge_threshold=0`` (only coincident components merge).

    References
    ----------
    .. [1] B.-N. Vo, W.-K. Ma, "The Gaussian Mixture Probability Hypothesis Density Filter",
       IEEE Trans. Signal Process. 54(11), 2006.
    """
    T = offsets.size - 1
    C = w.size
    ow = np.empty(C)
    om = np.empty((C, 4))
    oP = np.empty((C, 4, 4))
    n_kept = 0
    for t in range(T):
        if keep[t]:
            n_kept += 1
    ooff = np.zeros(n_kept + 1, dtype=np.int64)
    n_out = 0
    tk = 0
    for t in range(T):
        if not keep[t]:
            continue
        a = offsets[t]
        b = offsets[t + 1]
        # prune: w > elim, always keep the heaviest component
        best = a
        for c in range(a, b):
            if w[c] > w[best]:
                best = c
        idx = np.empty(b - a, dtype=np.int64)
        n = 0
        for c in range(a, b):
            if w[c] > elim or c == best:
                idx[n] = c
                n += 1
        idx = idx[:n]
        inv = np.empty((n, 4, 4))
        logdet = np.empty(n)
        for q in range(n):
            if rule == 0:
                logdet[q] = np.linalg.slogdet(P[idx[q]])[1]
            else:
                inv[q] = np.linalg.inv(P[idx[q]])
        alive = np.ones(n, dtype=np.bool_)
        start = n_out
        n_alive = n
        while n_alive > 0:
            # heaviest remaining component
            jq = -1
            for q in range(n):
                if alive[q] and (jq < 0 or w[idx[q]] > w[idx[jq]]):
                    jq = q
            mj = m[idx[jq]]
            wsum = 0.0
            mean = np.zeros(4)
            members = np.empty(n, dtype=np.int64)
            nm = 0
            for q in range(n):
                if not alive[q]:
                    continue
                d = m[idx[q]] - mj
                val = 0.0
                if q == jq:
                    pass
                elif rule == 0:
                    # dᵀ P̄⁻¹ d >= |d|² / λ_max(P̄) >= |d|² / tr(P̄) and the log-det term is
                    # >= 0: pairs farther apart than that cannot merge, skip the 4 × 4 algebra
                    dd = 0.0
                    tr = 0.0
                    for u in range(4):
                        dd += d[u] * d[u]
                        tr += 0.5 * (P[idx[q], u, u] + P[idx[jq], u, u])
                    if dd > merge_thr * tr:
                        continue
                    Pbar = 0.5 * (P[idx[q]] + P[idx[jq]])
                    Pbi = np.linalg.inv(Pbar)
                    for u in range(4):
                        for v in range(4):
                            val += d[u] * Pbi[u, v] * d[v]
                    val += 4.0 * (np.linalg.slogdet(Pbar)[1] - 0.5 * (logdet[q] + logdet[jq]))
                else:
                    qq = q if rule == 1 else jq
                    for u in range(4):
                        for v in range(4):
                            val += d[u] * inv[qq, u, v] * d[v]
                if val <= merge_thr:
                    members[nm] = q
                    nm += 1
                    alive[q] = False
                    n_alive -= 1
                    wq = w[idx[q]]
                    wsum += wq
                    mean += wq * m[idx[q]]
            mean /= wsum
            cov = np.zeros((4, 4))
            for s in range(nm):
                c = idx[members[s]]
                d = m[c] - mean
                cov += w[c] * (P[c] + np.outer(d, d))
            cov /= wsum
            ow[n_out] = wsum
            om[n_out] = mean
            oP[n_out] = 0.5 * (cov + cov.T)
            n_out += 1
        # sort the merged components by decreasing weight (a later cluster can outweigh an
        # earlier one), then cap and renormalise
        n_new = n_out - start
        order = np.argsort(-ow[start:n_out], kind="mergesort")
        sw = ow[start:n_out][order].copy()
        sm = om[start:n_out][order].copy()
        sP = oP[start:n_out][order].copy()
        ow[start:n_out] = sw
        om[start:n_out] = sm
        oP[start:n_out] = sP
        n_out = start + min(n_new, cap)
        tot = 0.0
        for c in range(start, n_out):
            tot += ow[c]
        for c in range(start, n_out):
            ow[c] /= tot
        tk += 1
        ooff[tk] = n_out
    return ooff, ow[:n_out].copy(), om[:n_out].copy(), oP[:n_out].copy()


# ------------------------------------------------------------------------------- filter
class LMBFilter:
    """Compact LMB filter with Gaussian-mixture tracks and pluggable association.

    Parameters
    ----------
    model : Model
        Motion, sensor, clutter, birth and survival models.
    association : Association
        Called as ``association(problem, rng)`` on every ranked-assignment problem.
    gate_prob : float or None, optional
        χ² gate probability (default ``0.9999999``, spec §6.3); None disables gating (every
        measurement enters every row).
    grouping : bool, optional
        Solve independent groups of tracks separately (spec §6.5a). Default False (one problem
        per scan, as in Vo's code).
    sample_empty_groups : bool, optional
        Hand problems without gated measurements (with grouping: the groups of tracks that gate
        nothing) to the association too, instead of solving them in closed form. The posterior
        is the same in expectation; only the association's cost and counters change. The
        paper's observation totals fit a sampler call on every group, these included
        (ambiguity A13; see the Tracking page of the documentation). Default False.
    extraction : {"hysteresis", "map"}, optional
        Hysteresis state extraction (6.5, the paper) or the MAP cardinality of Vo's code.
    theta_upper, theta_lower : float, optional
        Hysteresis thresholds ``ϑ_u = 0.9`` and ``ϑ_l = 10⁻³``.
    prune_track : float, optional
        Drop tracks with ``r <= prune_track`` (default ``10⁻³``).
    max_tracks : int, optional
        Keep at most this many tracks, the most likely ones (default 100).
    prune_component, merge_threshold, max_components : float, float, int, optional
        Mixture pruning (``10⁻⁵``), merging (4) and cap (10) per track.
    merge_rule : {"bhattacharyya", "vo-ma", "heaviest"}, optional
        Which pairs of components merge (``_reduce_mixtures``): eight times their
        Bhattacharyya distance at most ``merge_threshold`` (default; the Mahalanobis test when
        the two covariances are equal), the Mahalanobis distance in the candidate's covariance
        (Vo & Ma 2006), or in the heaviest component's covariance (Vo's MATLAB).
    estimate : {"max-weight", "mean"}, optional
        State estimate of a reported track: mean of its heaviest component (Vo's code) or of the
        whole mixture.

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
    >>> from rankedassign.tracking.association import Association, AssociationResult
    >>> class AllMissed(Association):     # a trivial association, for illustration only
    ...     def __call__(self, problem, rng):
    ...         beta = np.zeros((problem.n_rows, problem.n_meas + 2))
    ...         beta[:, problem.n_meas] = 1.0
    ...         return AssociationResult(beta, 1, 0, 0, 1)
    >>> f = LMBFilter(make_model("paper"), AllMissed())
    >>> rec = f.step(np.array([[0.0, 0.0]]), rng=0)
    >>> rec.n_tracks, rec.track_labels.tolist()
    (4, [[1, 1], [1, 2], [1, 3], [1, 4]])
    """

    def __init__(
        self,
        model: Model,
        association: Association,
        *,
        gate_prob: float | None = 0.9999999,
        grouping: bool = False,
        sample_empty_groups: bool = False,
        extraction: str = "hysteresis",
        theta_upper: float = 0.9,
        theta_lower: float = 1e-3,
        prune_track: float = 1e-3,
        max_tracks: int = 100,
        prune_component: float = 1e-5,
        merge_threshold: float = 4.0,
        merge_rule: str = "bhattacharyya",
        max_components: int = 10,
        estimate: str = "max-weight",
    ):
        if not isinstance(model, Model):
            raise TypeError(f"model must be a Model, got {type(model).__name__}")
        if not callable(association):
            raise TypeError(
                f"association must be callable as association(problem, rng), got "
                f"{type(association).__name__}"
            )
        if extraction not in ("hysteresis", "map"):
            raise ValueError(f"extraction must be 'hysteresis' or 'map', got {extraction!r}")
        if estimate not in ("max-weight", "mean"):
            raise ValueError(f"estimate must be 'max-weight' or 'mean', got {estimate!r}")
        if not (0 <= theta_lower <= theta_upper <= 1):
            raise ValueError(
                f"need 0 <= theta_lower <= theta_upper <= 1, got {theta_lower}, {theta_upper}"
            )
        if not (0 <= prune_track < 1):
            raise ValueError(f"prune_track must be in [0, 1), got {prune_track}")
        if not (0 <= prune_component < 1):
            raise ValueError(f"prune_component must be in [0, 1), got {prune_component}")
        if not merge_threshold >= 0:
            raise ValueError(f"merge_threshold must be >= 0, got {merge_threshold}")
        if merge_rule not in MERGE_RULES:
            raise ValueError(
                f"merge_rule must be one of {sorted(MERGE_RULES)}, got {merge_rule!r}"
            )
        for name, v in (("max_tracks", max_tracks), ("max_components", max_components)):
            if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or v < 1:
                raise ValueError(f"{name} must be a positive integer, got {v!r}")
        self.model = model
        self.association = association
        self.gate = None if gate_prob is None else gate_threshold(gate_prob, 2)
        self.grouping = bool(grouping)
        self.sample_empty_groups = bool(sample_empty_groups)
        self.extraction = extraction
        self.theta_upper = float(theta_upper)
        self.theta_lower = float(theta_lower)
        self.prune_track = float(prune_track)
        self.max_tracks = int(max_tracks)
        self.prune_component = float(prune_component)
        self.merge_threshold = float(merge_threshold)
        self.merge_rule = merge_rule
        self.max_components = int(max_components)
        self.estimate = estimate
        # model matrices, cached
        self._F = np.array(model.motion.F)
        self._Q = np.array(model.motion.Q)
        self._R = np.array(model.sensor.R)
        self._pd = float(model.sensor.p_d)
        self._ps = float(model.survival.p_s)
        self._log_kappa = math.log(model.clutter.intensity)
        self._birth_r = model.birth.r
        self._birth_m = model.birth.means
        self._birth_P = model.birth.covs
        self.reset()

    # ----------------------------------------------------------------------- state
    def reset(self) -> None:
        """Forget every track and restart at scan 1."""
        self.k = 0
        self.labels = np.empty((0, 2), dtype=np.int64)
        self.r = np.empty(0)
        self.offsets = np.zeros(1, dtype=np.int64)
        self.w = np.empty(0)
        self.m = np.empty((0, 4))
        self.P = np.empty((0, 4, 4))
        self.confirmed = np.empty(0, dtype=bool)

    @property
    def n_tracks(self) -> int:
        """Number of tracks currently held."""
        return int(self.r.size)

    def track_index(self) -> np.ndarray:
        """Track of every component, shape (C,)."""
        return np.repeat(np.arange(self.n_tracks), np.diff(self.offsets))

    # ----------------------------------------------------------------------- steps
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
        F, Q = self._F, self._Q
        # m <- F m ; P <- F P F' + Q
        m = self.m @ F.T
        P = F @ self.P @ F.T + Q
        r = self._ps * self.r
        B = self._birth_r.size
        Tn = self.n_tracks
        labels = np.column_stack([np.full(B, self.k, dtype=np.int64), np.arange(1, B + 1)])
        self.labels = np.vstack([self.labels, labels]).astype(np.int64)
        self.r = np.concatenate([r, self._birth_r])
        C = self.w.size
        self.offsets = np.concatenate([self.offsets, C + np.arange(1, B + 1)]).astype(np.int64)
        self.w = np.concatenate([self.w, np.ones(B)])
        self.m = np.vstack([m, self._birth_m])
        self.P = np.concatenate([P, self._birth_P], axis=0)
        self.confirmed = np.concatenate([self.confirmed, np.zeros(B, dtype=bool)])
        assert self.offsets.size == Tn + B + 1

    def _likelihoods(self, z: np.ndarray):
        """Per component: innovation covariance, gain, updated covariance; per pair: log N."""
        m, P, R = self.m, self.P, self._R
        Hm = m[:, [0, 2]]
        # S = H P H' + R (H picks p_x, p_y)
        S = P[:, [0, 2]][:, :, [0, 2]] + R
        det = S[:, 0, 0] * S[:, 1, 1] - S[:, 0, 1] * S[:, 1, 0]
        Sinv = np.empty_like(S)
        Sinv[:, 0, 0] = S[:, 1, 1] / det
        Sinv[:, 1, 1] = S[:, 0, 0] / det
        Sinv[:, 0, 1] = -S[:, 0, 1] / det
        Sinv[:, 1, 0] = -S[:, 1, 0] / det
        nu = z[None, :, :] - Hm[:, None, :]  # (C, M, 2)
        maha = (
            Sinv[:, None, 0, 0] * nu[..., 0] ** 2
            + (Sinv[:, None, 0, 1] + Sinv[:, None, 1, 0]) * nu[..., 0] * nu[..., 1]
            + Sinv[:, None, 1, 1] * nu[..., 1] ** 2
        )
        # ln N(z; H m, S) = -(d ln 2π + ln|S| + ν' S⁻¹ ν) / 2, d = 2
        logN = -0.5 * maha - _LOG_2PI - 0.5 * np.log(det)[:, None]
        return S, Sinv, nu, maha, logN

    def step(self, z, rng=None) -> ScanRecord:
        """Run one scan: predict, build the problem(s), associate, update, extract.

        Parameters
        ----------
        z : array_like, shape (M, 2)
            Measurements of the scan (positions).
        rng : optional
            Randomness of the association (anything :func:`numpy.random.default_rng` accepts);
            one child stream per problem is spawned from it.

        Returns
        -------
        ScanRecord

        Raises
        ------
        ValueError
            On measurements not of shape ``(M, 2)`` (an empty list is a scan without
            measurements), on non-finite measurements, or if the association returns ``beta``
            of the wrong shape.

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
        z = np.asarray(z, dtype=np.float64)
        if z.size == 0:  # no measurements, e.g. [] or an empty (0, 2) array
            z = z.reshape(0, 2)
        elif z.ndim != 2 or z.shape[1] != 2:
            raise ValueError(f"measurements must have shape (M, 2), got shape {z.shape}")
        if not np.isfinite(z).all():
            raise ValueError("measurements must be finite")
        gen = np.random.default_rng(rng)
        t0 = perf_counter()
        self.predict()
        t1 = perf_counter()

        # ---- cost matrix (6.2)
        T = self.n_tracks
        M_all = z.shape[0]
        if T == 0:  # an empty birth model and no tracks: nothing to associate
            t2 = perf_counter()
            return ScanRecord(
                np.empty((0, 2), np.int64), np.empty((0, 4)), np.empty(0),
                self.labels.copy(), self.r.copy(), 0, M_all, 0, 0, 0, 0, 0, 0,
                {"prediction": t1 - t0, "cost": t2 - t1, "association": 0.0, "update": 0.0},
            )
        starts = self.offsets[:-1]
        S, Sinv, nu, maha, logN = self._likelihoods(z)
        if M_all:
            lw = np.log(self.w)[:, None] + logN  # ln w_k + ln N(z_j; H m_k, S_k)
            log_g = np.logaddexp.reduceat(lw, starts, axis=0)  # ln Σ_k w_k N(...), (T, M)
            if self.gate is None:
                gated = np.ones((T, M_all), dtype=bool)
            else:
                gated = np.logical_or.reduceat(maha <= self.gate, starts, axis=0)
        else:
            lw = np.empty((self.w.size, 0))
            log_g = np.empty((T, 0))
            gated = np.zeros((T, 0), dtype=bool)
        used = np.flatnonzero(gated.any(axis=0))
        gated = gated[:, used]
        r = self.r
        log_r = np.log(r)
        with np.errstate(divide="ignore"):
            log_det = np.where(gated, log_r[:, None] + math.log(self._pd) + log_g[:, used]
                               - self._log_kappa, -np.inf)
            log_miss = log_r + (math.log1p(-self._pd) if self._pd < 1 else -np.inf)
            log_dead = np.log1p(-r)
        if self.grouping and used.size:
            groups = group_tracks(gated)
        else:
            groups = [(np.arange(T), np.arange(used.size))]
        t2 = perf_counter()

        # ---- association
        beta = np.zeros((T, used.size + 2))
        sample_empty = self.sample_empty_groups
        n_problems = sum(1 for _, cols in groups if cols.size or sample_empty)
        children = iter(gen.spawn(n_problems)) if n_problems else iter(())
        inv = sweeps = rows_upd = n_unique = 0
        for rows, cols in groups:
            if cols.size == 0 and not sample_empty:
                # rows take only missed/dead: independent Bernoullis, closed form
                lm, ld = log_miss[rows], log_dead[rows]
                top = np.maximum(lm, ld)
                em, ed = np.exp(lm - top), np.exp(ld - top)
                beta[rows, -2] = em / (em + ed)
                beta[rows, -1] = ed / (em + ed)
                continue
            prob = AssignmentProblem.from_log_eta(
                log_det[np.ix_(rows, cols)], log_miss[rows], log_dead[rows]
            )
            res = self.association(prob, next(children))
            if not isinstance(res, AssociationResult):
                res = AssociationResult(*res)
            b = np.asarray(res.beta, dtype=np.float64)
            if b.shape != (rows.size, cols.size + 2):
                raise ValueError(
                    f"association returned beta of shape {b.shape}, expected "
                    f"{(rows.size, cols.size + 2)}"
                )
            beta[np.ix_(rows, cols)] = b[:, :-2]
            beta[rows, -2] = b[:, -2]
            beta[rows, -1] = b[:, -1]
            inv += int(res.invocations)
            sweeps += int(res.sweeps)
            rows_upd += int(res.row_updates)
            n_unique += int(res.n_unique)
        t3 = perf_counter()

        # ---- update (6.3, 6.4) and housekeeping
        self._update(z[used], beta, Sinv, nu[:, used], lw[:, used], log_g[:, used])
        labels, states, ex = self._extract()
        t4 = perf_counter()
        return ScanRecord(
            labels, states, ex, self.labels.copy(), self.r.copy(), T, M_all, int(used.size),
            n_problems, inv, sweeps, rows_upd, n_unique,
            {"prediction": t1 - t0, "cost": t2 - t1, "association": t3 - t2, "update": t4 - t3},
        )

    def _update(self, z, beta, Sinv, nu, lw, log_g) -> None:
        T = self.n_tracks
        M = z.shape[0]
        # r_i = Σ_{j >= 0} β_ij  (6.3)
        r_new = np.clip(beta[:, : M + 1].sum(axis=1), 0.0, 1.0)
        safe_r = np.where(r_new > 0, r_new, 1.0)
        rel = beta[:, : M + 1] / safe_r[:, None]  # β_ij / r_i, (T, M + 1)
        elim = self.prune_component
        ncomp = np.diff(self.offsets)
        tidx = self.track_index()
        # Kalman gain and updated covariance per component: K = P H' S⁻¹, P' = P − K S K'
        PHt = self.P[:, :, [0, 2]]  # (C, 4, 2)
        K = PHt @ Sinv
        P_upd = self.P - K @ PHt.transpose(0, 2, 1)
        P_upd = 0.5 * (P_upd + P_upd.transpose(0, 2, 1))

        # missed detection: predicted components, weight β_i0 / r_i · w_k
        miss_keep = rel[:, M] > elim
        cm = np.flatnonzero(miss_keep[tidx])
        w_parts = [rel[tidx[cm], M] * self.w[cm]]
        m_parts = [self.m[cm]]
        P_parts = [self.P[cm]]
        t_parts = [tidx[cm]]
        # detections: pairs (i, j) worth expanding, every component of track i
        pi, pj = np.nonzero(rel[:, :M] > elim)
        if pi.size:
            cnt = ncomp[pi]
            tot = int(cnt.sum())
            first = np.repeat(self.offsets[pi], cnt)
            within = np.arange(tot) - np.repeat(np.cumsum(cnt) - cnt, cnt)
            cc = first + within  # component index
            pt = np.repeat(pi, cnt)
            pz = np.repeat(pj, cnt)
            # w̃_kj = w_k N(z_j; H m_k, S_k) / Σ_k' w_k' N(z_j; H m_k', S_k')
            wt = np.exp(lw[cc, pz] - log_g[pt, pz]) * rel[pt, pz]
            # m' = m + K (z_j − H m)
            mu = self.m[cc] + np.einsum("cij,cj->ci", K[cc], nu[cc, pz])
            w_parts.append(wt)
            m_parts.append(mu)
            P_parts.append(P_upd[cc])
            t_parts.append(pt)
        w_all = np.concatenate(w_parts)
        m_all = np.concatenate(m_parts)
        P_all = np.concatenate(P_parts)
        t_all = np.concatenate(t_parts)
        order = np.argsort(t_all, kind="stable")
        w_all, m_all, P_all, t_all = w_all[order], m_all[order], P_all[order], t_all[order]
        counts = np.bincount(t_all, minlength=T)
        offsets = np.concatenate([[0], np.cumsum(counts)]).astype(np.int64)

        # track pruning (r <= prune_track) and cap (most likely max_tracks)
        keep = (r_new > self.prune_track) & (counts > 0)
        if keep.sum() > self.max_tracks:
            cand = np.flatnonzero(keep)
            best = cand[np.argsort(-r_new[cand], kind="stable")[: self.max_tracks]]
            keep = np.zeros(T, dtype=bool)
            keep[best] = True
        # weights within each track sum to Σ_j β_ij / r_i · Σ w̃ = 1 before pruning
        new_off, w, m, P = _reduce_mixtures(
            offsets, np.ascontiguousarray(w_all), np.ascontiguousarray(m_all),
            np.ascontiguousarray(P_all), keep, elim, self.merge_threshold, self.max_components,
            MERGE_RULES[self.merge_rule],
        )
        self.offsets = new_off
        self.w, self.m, self.P = w, m, P
        self.r = r_new[keep]
        self.labels = self.labels[keep]
        self.confirmed = self.confirmed[keep]

    def _extract(self):
        r = self.r
        if self.extraction == "hysteresis":
            # confirmed_k = [r >= ϑ_u] or (confirmed_{k-1} and r >= ϑ_l)   (6.5)
            self.confirmed = (r >= self.theta_upper) | (self.confirmed & (r >= self.theta_lower))
            sel = np.flatnonzero(self.confirmed)
        else:
            n_hat = map_cardinality(r)
            sel = np.sort(np.argsort(-r, kind="stable")[:n_hat])
        if self.estimate == "max-weight":
            states = self.m[self.offsets[sel]]  # components are sorted by decreasing weight
        else:
            wm = self.w[:, None] * self.m
            sums = np.add.reduceat(wm, self.offsets[:-1], axis=0) if wm.size else wm
            states = sums[sel] if sel.size else np.empty((0, 4))
        return self.labels[sel].copy(), np.array(states).reshape(-1, 4), r[sel].copy()

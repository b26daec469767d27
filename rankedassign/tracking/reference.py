"""Plain-numpy twins of the LMB filter's kernels: the specification they are tested against.

Every function here has the name and signature of a kernel in
:mod:`rankedassign.tracking._kernels` and computes the same result the obvious way, with numpy
and no numba. They are slow and meant for tests and for reading.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

__all__ = [
    "cardinality_distribution",
    "connected_groups",
    "detection_log_weights",
    "gate_and_distances",
    "group_cost_matrix",
    "posterior_components",
    "posterior_sources",
    "reduce_mixtures",
    "truncated_marginals",
]

_BHATTACHARYYA, _VO_MA, _HEAVIEST = 0, 1, 2


def _merge_distances(m, P, j, cand, rule):
    """Merging statistic of every candidate against component ``j`` (spec §6.4, ``rule``)."""
    d = m[cand] - m[j]
    if rule == _BHATTACHARYYA:
        Pbar = 0.5 * (P[cand] + P[j])
        maha = np.einsum("ci,cij,cj->c", d, np.linalg.inv(Pbar), d)
        # 4 ln(|P̄| / sqrt(|P_i| |P_j|)): eight times the Bhattacharyya distance, with the
        # Mahalanobis term above
        logdet = np.linalg.slogdet(Pbar)[1]
        ld_i = np.linalg.slogdet(P[cand])[1]
        ld_j = np.linalg.slogdet(P[j])[1]
        return maha + 4.0 * (logdet - 0.5 * (ld_i + ld_j))
    inv = np.linalg.inv(P[cand]) if rule == _VO_MA else np.linalg.inv(P[j])[None]
    dim = m.shape[1]
    return np.einsum("ci,cij,cj->c", d, np.broadcast_to(inv, (len(cand), dim, dim)), d)


def _reduce_one(w, m, P, elim, merge_thr, cap, rule):
    """Prune, merge and cap one track's mixture; components in decreasing weight."""
    if w.size == 0:  # a track without components keeps none
        d = m.shape[1]
        return np.empty(0), np.empty((0, d)), np.empty((0, d, d))
    # prune: w > elim, and the heaviest component always stays
    keep = w > elim
    keep[np.argmax(w)] = True
    w, m, P = w[keep], m[keep], P[keep]
    alive = np.ones(w.size, dtype=bool)
    out_w, out_m, out_P = [], [], []
    while alive.any():
        # the heaviest remaining component (the first one on ties) absorbs its neighbours
        j = int(np.argmax(np.where(alive, w, -np.inf)))
        cand = np.flatnonzero(alive)
        dist = _merge_distances(m, P, j, cand, rule)
        dist[cand == j] = 0.0
        members = cand[dist <= merge_thr]
        alive[members] = False
        # moment matching: w = Σ w_i, m = Σ w_i m_i / w, P = Σ w_i (P_i + (m − m_i)(m − m_i)ᵀ) / w
        wsum = w[members].sum()
        mean = (w[members, None] * m[members]).sum(axis=0) / wsum
        d = m[members] - mean
        cov = (w[members, None, None] * (P[members] + d[:, :, None] * d[:, None, :])).sum(
            axis=0) / wsum
        out_w.append(wsum)
        out_m.append(mean)
        out_P.append(0.5 * (cov + cov.T))
    # a later cluster can outweigh an earlier one: sort (stable), cap, renormalise
    order = np.argsort(-np.array(out_w), kind="stable")[:cap]
    ow = np.array(out_w)[order]
    return ow / ow.sum(), np.array(out_m)[order], np.array(out_P)[order]


def reduce_mixtures(offsets, w, m, P, keep, elim, merge_thr, cap, rule):
    """Prune, merge and cap the Gaussian mixture of every kept track (reference).

    The specification of :func:`rankedassign.tracking._kernels.reduce_mixtures`, with the same
    parameters and results; see there.

    Parameters
    ----------
    offsets : ndarray of int64, shape (T + 1,)
        Component range of track ``t`` is ``offsets[t]:offsets[t + 1]``.
    w : ndarray of float64, shape (C,)
        Component weights, summing to 1 within each track.
    m : ndarray of float64, shape (C, d)
        Component means (``(p_x, v_x, p_y, v_y)`` in the linear filters; any dimension ``d``
        here, which is why the non-linear path uses this twin).
    P : ndarray of float64, shape (C, d, d)
        Component covariances.
    keep : ndarray of bool, shape (T,)
        Tracks to keep; the others are dropped with their components.
    elim : float
        Pruning threshold: a component is kept if ``w > elim``; the heaviest one of each track
        always stays.
    merge_thr : float
        Merging threshold ``U`` on the statistic chosen by ``rule``.
    cap : int
        Maximum number of components per track after merging.
    rule : int
        Merging criterion: 0 Bhattacharyya (eight times the distance), 1 Vo & Ma
        (``d' P_i^-1 d``), 2 heaviest (``d' P_j^-1 d``), as in the kernel.

    Returns
    -------
    offsets : ndarray of int64, shape (T_kept + 1,)
        Component ranges of the kept tracks, in their original order.
    w : ndarray of float64, shape (C_out,)
        Weights, in decreasing order within each track (stable on ties) and renormalised to
        sum to 1 per track.
    m : ndarray of float64, shape (C_out, 4)
        Means of the reduced components (moment-matched where components merged).
    P : ndarray of float64, shape (C_out, 4, 4)
        Their covariances, symmetrised.

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign.tracking.reference import reduce_mixtures
    >>> P = np.tile(np.eye(4), (3, 1, 1))
    >>> m = np.array([[0.0, 0, 0, 0], [0.5, 0, 0, 0], [9.0, 0, 0, 0]])
    >>> off, w, mm, PP = reduce_mixtures(np.array([0, 3]), np.array([0.5, 0.3, 0.2]), m, P,
    ...                                  np.array([True]), 1e-5, 4.0, 10, 0)
    >>> off.tolist(), w.round(2).tolist(), mm[:, 0].round(4).tolist()
    ([0, 2], [0.8, 0.2], [0.1875, 9.0])
    """
    parts = []
    for t in np.flatnonzero(keep):
        a, b = offsets[t], offsets[t + 1]
        parts.append(_reduce_one(w[a:b], m[a:b], P[a:b], elim, merge_thr, cap, rule))
    counts = [len(p[0]) for p in parts]
    new_off = np.concatenate([[0], np.cumsum(counts, dtype=np.int64)]).astype(np.int64)
    if not parts:
        d = m.shape[1]
        return new_off, np.empty(0), np.empty((0, d)), np.empty((0, d, d))
    return (new_off, np.concatenate([p[0] for p in parts]), np.concatenate([p[1] for p in parts]),
            np.concatenate([p[2] for p in parts]))


_LOG_2PI = math.log(2.0 * math.pi)


def gate_and_distances(m, P, R, z, offsets, gate, use_gate):
    """Innovation statistics and the χ² gate per track (reference; see the kernel).

    The specification of :func:`rankedassign.tracking._kernels.gate_and_distances`.

    Parameters
    ----------
    m : ndarray of float64, shape (C, 4)
        Predicted component means ``(p_x, v_x, p_y, v_y)``.
    P : ndarray of float64, shape (C, 4, 4)
        Predicted component covariances.
    R : ndarray of float64, shape (2, 2)
        Measurement noise covariance (``H`` picks ``p_x, p_y``).
    z : ndarray of float64, shape (M, 2)
        The scan's measurements.
    offsets : ndarray of int64, shape (T + 1,)
        Component range of every track.
    gate : float
        Threshold on the squared Mahalanobis distance (a χ²₂ quantile).
    use_gate : bool
        False: every track–measurement pair is in the gate.

    Returns
    -------
    det : ndarray of float64, shape (C,)
        ``|S|`` with ``S = H P Hᵀ + R``.
    Sinv : ndarray of float64, shape (C, 2, 2)
        ``S⁻¹`` (the closed-form 2 x 2 inverse).
    nu : ndarray of float64, shape (C, M, 2)
        Innovations ``z_j − H m_c``.
    maha : ndarray of float64, shape (C, M)
        ``ν' S⁻¹ ν``.
    gated : ndarray of bool, shape (T, M)
        Whether measurement ``j`` lies in the gate of some component of track ``t``.

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign.tracking.reference import gate_and_distances
    >>> det, Sinv, nu, maha, gated = gate_and_distances(
    ...     np.zeros((1, 4)), np.zeros((1, 4, 4)), np.eye(2), np.array([[3.0, 4.0]]),
    ...     np.array([0, 1]), 9.0, True)
    >>> maha.tolist(), gated.tolist()
    ([[25.0]], [[False]])
    """
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
    T = offsets.size - 1
    if not use_gate:
        gated = np.ones((T, z.shape[0]), dtype=bool)
    elif maha.size:
        gated = np.logical_or.reduceat(maha <= gate, offsets[:-1], axis=0)
    else:
        gated = np.zeros((T, z.shape[0]), dtype=bool)
    return det, Sinv, nu, maha, gated


def detection_log_weights(maha, log_det_S, log_w, offsets, used, gated, log_r, log_pd,
                          log_kappa):
    """Per-component and per-track log-likelihoods of the measurements ``used`` (reference).

    The specification of :func:`rankedassign.tracking._kernels.detection_log_weights`.

    Parameters
    ----------
    maha : ndarray of float64, shape (C, M)
        Squared Mahalanobis distances of every component and measurement
        (:func:`gate_and_distances`).
    log_det_S : ndarray of float64, shape (C,)
        ``ln|S_c|`` of the innovation covariances.
    log_w : ndarray of float64, shape (C,)
        ``ln w_c``, the log component weights.
    offsets : ndarray of int64, shape (T + 1,)
        Component range of every track.
    used : ndarray of int64, shape (U,)
        Measurement columns kept (those in some gate).
    gated : ndarray of bool, shape (T, U)
        Gate of the kept columns.
    log_r : ndarray of float64, shape (T,)
        ``ln r_+``, the log predicted existence probabilities.
    log_pd : float
        ``ln P_D``.
    log_kappa : float
        ``ln κ``, the log clutter intensity.

    Returns
    -------
    lw : ndarray of float64, shape (C, U)
        ``ln w_c + ln N(z_j; H m_c, S_c)`` where track ``t`` of component ``c`` gates ``j``,
        ``−inf`` elsewhere.
    log_g : ndarray of float64, shape (T, U)
        ``ln Σ_c w_c N(z_j; H m_c, S_c)`` over the components of each track in the gate,
        ``−inf`` elsewhere.
    log_det : ndarray of float64, shape (T, U)
        ``ln η_t(j) = ln r_t + ln P_D + log_g − ln κ`` in the gate, ``−inf`` outside
        (spec eq. 6.2).

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign.tracking.reference import detection_log_weights
    >>> lw, log_g, log_det = detection_log_weights(
    ...     np.zeros((2, 1)), np.zeros(2), np.log([0.5, 0.5]), np.array([0, 2]),
    ...     np.array([0]), np.array([[True]]), np.zeros(1), 0.0, 0.0)
    >>> bool(np.isclose(log_g[0, 0], -np.log(2 * np.pi)))
    True
    """
    # ln N(z; H m, S) = -(d ln 2π + ln|S| + ν' S⁻¹ ν) / 2, d = 2
    log_n = -0.5 * maha[:, used] - _LOG_2PI - 0.5 * log_det_S[:, None]
    lw = log_w[:, None] + log_n
    T = offsets.size - 1
    if lw.size:
        log_g = np.logaddexp.reduceat(lw, offsets[:-1], axis=0)  # ln Σ_c w_c N(...), (T, U)
    else:
        log_g = np.empty((T, used.size))
    log_det = np.where(gated, log_r[:, None] + log_pd + log_g - log_kappa, -np.inf)
    # pairs outside the gate are forbidden: their likelihoods are never read
    comp_gated = np.repeat(gated, np.diff(offsets), axis=0)
    lw = np.where(comp_gated, lw, -np.inf)
    log_g = np.where(gated, log_g, -np.inf)
    return lw, log_g, log_det


def connected_groups(gated):
    """Connected components of the track–measurement graph (reference, by SciPy).

    Parameters
    ----------
    gated : ndarray of bool, shape (T, M)
        ``gated[t, j]``: measurement ``j`` lies in the gate of track ``t`` (an edge of the
        bipartite graph).

    Returns
    -------
    track_group : ndarray of int64, shape (T,)
        Group of every track; groups are numbered ``0, 1, ...`` in the order of their first
        track.
    meas_group : ndarray of int64, shape (M,)
        Group of every measurement, ``-1`` for a measurement no track gates.
    n_groups : int
        Number of groups (a track gating nothing is a group of its own).

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign.tracking.reference import connected_groups
    >>> g = np.array([[1, 0, 0], [0, 0, 1], [1, 1, 0], [0, 0, 0]], dtype=bool)
    >>> [a.tolist() if hasattr(a, "tolist") else a for a in connected_groups(g)]
    [[0, 1, 0, 2], [0, 0, 1], 3]
    """
    T, M = gated.shape
    i, j = np.nonzero(gated)
    graph = coo_matrix((np.ones(i.size), (i, T + j)), shape=(T + M, T + M))
    _, comp = connected_components(graph, directed=False)
    number = {}
    for c in comp[:T]:
        number.setdefault(int(c), len(number))
    track_group = np.array([number[int(c)] for c in comp[:T]], dtype=np.int64)
    meas_group = np.array([number.get(int(c), -1) for c in comp[T:]], dtype=np.int64)
    return track_group, meas_group, len(number)


def group_cost_matrix(log_det, log_miss, log_dead, rows, cols):
    """Cost matrix ``−ln η`` of the tracks ``rows`` and measurements ``cols`` (reference).

    Parameters
    ----------
    log_det : ndarray of float64, shape (T, U)
        ``ln η_t(j)`` of every track and kept measurement (:func:`detection_log_weights`);
        ``−inf`` outside the gate.
    log_miss : ndarray of float64, shape (T,)
        ``ln η_t(0)``, track ``t`` survives undetected.
    log_dead : ndarray of float64, shape (T,)
        ``ln η_t(−1)``, track ``t`` does not exist.
    rows : ndarray of int64, shape (P,)
        Tracks of the group, in row order.
    cols : ndarray of int64, shape (M,)
        Measurement columns (into ``log_det``) of the group, in column order.

    Returns
    -------
    ndarray of float64, shape (P, M + 2P)
        The paper's layout (spec §1.5): ``C[i, j] = −log_det[rows[i], cols[j]]``,
        ``C[i, M + i] = −log_miss[rows[i]]``, ``C[i, M + P + i] = −log_dead[rows[i]]``,
        ``+inf`` elsewhere.

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign.tracking.reference import group_cost_matrix
    >>> group_cost_matrix(np.array([[-1.0]]), np.array([-2.0]), np.array([-3.0]),
    ...                   np.array([0]), np.array([0])).tolist()
    [[1.0, 2.0, 3.0]]
    """
    P, M = rows.size, cols.size
    C = np.full((P, M + 2 * P), np.inf)
    C[:, :M] = -log_det[np.ix_(rows, cols)]
    k = np.arange(P)
    C[k, M + k] = -log_miss[rows]
    C[k, M + P + k] = -log_dead[rows]
    return C


def truncated_marginals(a, w, M):
    """``β[i, j] = Σ_h w_h 1[γ_i^(h) = j]``, compact columns (reference, by ``bincount``).

    Parameters
    ----------
    a : ndarray of int64, shape (H, P)
        Assignments as cost-matrix columns (one row per hypothesis ``h``).
    w : ndarray of float64, shape (H,)
        Normalised hypothesis weights.
    M : int
        Number of measurement columns of the cost matrix.

    Returns
    -------
    ndarray of float64, shape (P, M + 2)
        ``β`` in compact columns ``[measurements | missed | dead]``: entry ``[i, j]`` for
        ``j < M`` is the weight of the hypotheses giving measurement ``j`` to row ``i``,
        ``[i, M]`` of those leaving it undetected, ``[i, M + 1]`` of those where it is dead.

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign.tracking.reference import truncated_marginals
    >>> truncated_marginals(np.array([[0], [1], [2]]), np.array([0.6, 0.3, 0.1]), 1).tolist()
    [[0.6, 0.3, 0.1]]
    """
    H, P = a.shape
    # compact column: measurement j -> j, missed (M + i) -> M, dead (M + P + i) -> M + 1
    compact = np.where(a < M, a, np.where(a < M + P, M, M + 1))
    flat = (np.arange(P)[None, :] * (M + 2) + compact).ravel()
    beta = np.bincount(flat, weights=np.repeat(w, P), minlength=P * (M + 2))
    return beta.reshape(P, M + 2)


def cardinality_distribution(r):
    """Poisson-binomial distribution of the number of existing tracks (reference).

    Parameters
    ----------
    r : ndarray of float64, shape (T,)
        Existence probabilities of the tracks, each in ``[0, 1]``.

    Returns
    -------
    ndarray of float64, shape (T + 1,)
        ``ρ[n]``, the probability that exactly ``n`` tracks exist (independent Bernoulli
        existences), by the convolution recursion over the tracks in order.

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign.tracking.reference import cardinality_distribution
    >>> cardinality_distribution(np.array([0.5, 0.5])).tolist()
    [0.25, 0.5, 0.25]
    """
    rho = np.zeros(len(r) + 1)
    rho[0] = 1.0
    for q in r:
        rho[1:] = rho[1:] * (1.0 - q) + rho[:-1] * q
        rho[0] *= 1.0 - q
    return rho


def posterior_sources(offsets, rel, elim, lw, log_g):
    """Where each posterior component comes from, grouped by track (reference; see the kernel).

    The specification of :func:`rankedassign.tracking._kernels.posterior_sources` (spec eq.
    6.4).

    Parameters
    ----------
    offsets : ndarray of int64, shape (T + 1,)
        Component ranges of the predicted tracks.
    rel : ndarray of float64, shape (T, M + 1)
        ``β_ij / r_i``; column ``M`` is the missed detection.
    elim : float
        Pairs with ``rel <= elim`` are not expanded (their components would be pruned).
    lw : ndarray of float64, shape (C, M)
        ``ln w_c N(z_j; H m_c, S_c)`` (:func:`detection_log_weights`).
    log_g : ndarray of float64, shape (T, M)
        Its log-sum over each track's components.

    Returns
    -------
    comp : ndarray of int64, shape (N,)
        Predicted component of every posterior component.
    track : ndarray of int64, shape (N,)
        Its track; the output is grouped by track, per track the missed-detection
        components first, then the updates with each measurement in turn, each over the
        track's components in order.
    meas : ndarray of int64, shape (N,)
        Its measurement, ``-1`` for a missed detection.
    log_ratio : ndarray of float64, shape (N,)
        ``lw[c, j] − log_g[t, j]`` for an update (0 for a missed detection).
    counts : ndarray of int64, shape (T,)
        Posterior components per track.

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign.tracking.reference import posterior_sources
    >>> comp, track, meas, log_ratio, counts = posterior_sources(
    ...     np.array([0, 2]), np.array([[0.7, 0.3]]), 1e-5, np.zeros((2, 1)), np.zeros((1, 1)))
    >>> comp.tolist(), meas.tolist(), counts.tolist()
    ([0, 1, 0, 1], [-1, -1, 0, 0], [4])
    """
    T = offsets.size - 1
    M = rel.shape[1] - 1
    ncomp = np.diff(offsets)
    tidx = np.repeat(np.arange(T), ncomp)
    # missed detection: every component of the tracks with β_i0 / r_i above the threshold
    cm = np.flatnonzero((rel[:, M] > elim)[tidx])
    # updates: the pairs (i, j) worth expanding, every component of track i
    pi, pj = np.nonzero(rel[:, :M] > elim)
    cnt = ncomp[pi]
    within = np.arange(cnt.sum()) - np.repeat(np.cumsum(cnt) - cnt, cnt)
    cc = np.repeat(offsets[:-1][pi], cnt) + within
    pt, pz = np.repeat(pi, cnt), np.repeat(pj, cnt)
    comp = np.concatenate([cm, cc]).astype(np.int64)
    track = np.concatenate([tidx[cm], pt]).astype(np.int64)
    meas = np.concatenate([np.full(cm.size, -1), pz]).astype(np.int64)
    log_ratio = np.concatenate([np.zeros(cm.size), lw[cc, pz] - log_g[pt, pz]])
    # grouped by track, the missed-detection components first (a stable sort)
    order = np.argsort(track, kind="stable")
    counts = np.bincount(track, minlength=T).astype(np.int64)
    return comp[order], track[order], meas[order], log_ratio[order], counts


def posterior_components(comp, track, meas, ratio, rel, w, m, P, K, nu, P_upd):
    """Weights, means and covariances of the posterior components (reference; see the kernel).

    The specification of :func:`rankedassign.tracking._kernels.posterior_components` (spec
    eq. 6.4).

    Parameters
    ----------
    comp, track, meas : ndarray of int64, shape (N,)
        Sources of the posterior components (:func:`posterior_sources`); ``meas = -1`` is a
        missed detection.
    ratio : ndarray of float64, shape (N,)
        ``w_c N_cj / Σ_c' w_c' N_c'j`` for an update (``exp`` of the ``log_ratio`` of
        :func:`posterior_sources`); not read for a missed detection.
    rel : ndarray of float64, shape (T, M + 1)
        ``β_ij / r_i``; column ``M`` is the missed detection.
    w : ndarray of float64, shape (C,)
        Predicted component weights.
    m : ndarray of float64, shape (C, 4)
        Predicted component means.
    P : ndarray of float64, shape (C, 4, 4)
        Predicted component covariances.
    K : ndarray of float64, shape (C, 4, 2)
        Kalman gain of every component; may be empty, shape ``(0, 4, 2)``, when no posterior
        component is an update.
    nu : ndarray of float64, shape (C, M, 2)
        Innovations ``z_j − H m_c`` of the kept measurements.
    P_upd : ndarray of float64, shape (C, 4, 4)
        Updated covariance ``P − K S Kᵀ`` of every component; may be empty as ``K``.

    Returns
    -------
    w : ndarray of float64, shape (N,)
        ``rel[t, M] w_c`` for a missed detection, ``ratio · rel[t, j]`` for an update.
    m : ndarray of float64, shape (N, 4)
        ``m_c`` for a missed detection, ``m_c + K_c ν_cj`` for an update.
    P : ndarray of float64, shape (N, 4, 4)
        ``P_c`` for a missed detection, ``P'_c`` for an update.

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign.tracking.reference import posterior_components
    >>> w, m, P = posterior_components(
    ...     np.array([0]), np.array([0]), np.array([-1]), np.ones(1), np.array([[0.2, 0.8]]),
    ...     np.ones(1), np.zeros((1, 4)), np.eye(4)[None], np.empty((0, 4, 2)),
    ...     np.empty((1, 1, 2)), np.empty((0, 4, 4)))
    >>> w.tolist()
    [0.8]
    """
    M = rel.shape[1] - 1
    miss = meas < 0
    det = ~miss
    w_out = np.empty(comp.size)
    w_out[miss] = rel[track[miss], M] * w[comp[miss]]
    m_out = m[comp].copy()
    P_out = P[comp].copy()
    if det.any():
        cc, pt, pz = comp[det], track[det], meas[det]
        w_out[det] = ratio[det] * rel[pt, pz]
        # m' = m + K (z_j − H m)
        m_out[det] = m[cc] + np.einsum("cij,cj->ci", K[cc], nu[cc, pz])
        P_out[det] = P_upd[cc]
    return w_out, m_out, P_out

"""Compiled kernels of the LMB filter: Gaussian-mixture reduction, track grouping, cardinality.

Each kernel has a plain-numpy twin of the same name and signature in
:mod:`rankedassign.tracking.reference`, the specification the kernel is tested against. The
kernels assume clean input (the filter prepares it): float64, C-contiguous, 4-D states.

Compile cost. The mixture reduction runs in every filter's first step, so its kernels are
written to compile quickly: element loops over the 4-D states instead of array expressions,
and no assignment of an array into a slice or a fancy index (numba compiles, for each shape of
such an assignment, a formatted shape-mismatch error, about a second each plus the string
formatting it needs the first time), nor a call of numba's generic sort (the stable
``np.argsort(..., kind="mergesort")`` took about 1.2 s of compile CPU; a short insertion sort
gives the same order). The arithmetic is the same, element by element, so the results are
unchanged bit for bit. Measured on the first step of ``make_model("vo")``'s
filters with an empty cache: ``reduce_mixtures`` 12-16 s of compile CPU before, see
``docs/reproduction.md`` for after.
"""

from __future__ import annotations

import math

import numpy as np

from ..numba_options import jit

__all__ = [
    "MERGE_RULES",
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

#: Mixture merging criteria of :class:`~rankedassign.tracking.LMBFilter` (``merge_rule``),
#: with their kernel codes.
MERGE_RULES = {"bhattacharyya": 0, "vo-ma": 1, "heaviest": 2}

_BHATTACHARYYA = 0
_VO_MA = 1


# ------------------------------------------------------------------ mixture reduction phases
@jit()
def _prune_components(w, a, b, elim):
    """Components ``a <= c < b`` with ``w[c] > elim``, and always the heaviest (first maximum).

    Parameters
    ----------
    w : ndarray of float64, shape (C,)
        Component weights.
    a, b : int
        The track's component range ``a:b`` (``a < b``).
    elim : float
        Pruning threshold.

    Returns
    -------
    ndarray of int64
        The kept components, increasing.
    """
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
    return idx[:n]


@jit()
def _merge_prepare(idx):
    """Room for ``P⁻¹`` (the Mahalanobis rules) or ``ln|P|`` (Bhattacharyya) of every kept
    component, filled on first use (:func:`_component_inverse`, :func:`_component_logdet`):
    most pairs are decided by a cheap bound and never need them.

    Parameters
    ----------
    idx : ndarray of int64, shape (n,)
        The kept components (:func:`_prune_components`).

    Returns
    -------
    inv : ndarray of float64, shape (n, 4, 4)
        Uninitialised room for the inverses.
    logdet : ndarray of float64, shape (n,)
        ``nan`` (not yet computed).
    have_inv : ndarray of bool, shape (n,)
        False (no inverse yet).
    """
    n = idx.size
    return np.empty((n, 4, 4)), np.full(n, np.nan), np.zeros(n, dtype=np.bool_)


@jit()
def _component_logdet(P, idx, logdet, q):
    """``ln|P_q|``, computed once.

    Parameters
    ----------
    P : ndarray of float64, shape (C, 4, 4)
        Component covariances.
    idx : ndarray of int64, shape (n,)
        The kept components.
    logdet : ndarray of float64, shape (n,)
        Cache (:func:`_merge_prepare`), ``nan`` where not yet computed; filled at ``q``.
    q : int
        Position in ``idx``.

    Returns
    -------
    float
    """
    if np.isnan(logdet[q]):
        logdet[q] = np.linalg.slogdet(P[idx[q]])[1]
    return logdet[q]


@jit()
def _component_inverse(P, idx, inv, have_inv, q):
    """``P_q⁻¹``, computed once.

    Parameters
    ----------
    P, idx, q
        As in :func:`_component_logdet`.
    inv : ndarray of float64, shape (n, 4, 4)
        Cache of the inverses (:func:`_merge_prepare`); filled at ``q``.
    have_inv : ndarray of bool, shape (n,)
        Which entries of ``inv`` are computed; set at ``q``.

    Returns
    -------
    ndarray of float64, shape (4, 4)
        ``inv[q]`` (a view).
    """
    if not have_inv[q]:
        iq = np.linalg.inv(P[idx[q]])
        for u in range(4):  # element by element: see "Compile cost" above
            for v in range(4):
                inv[q, u, v] = iq[u, v]
        have_inv[q] = True
    return inv[q]


@jit()
def _position_bound(d, A):
    """``d_pᵀ A_pp⁻¹ d_p`` over the position coordinates (0, 2) of the 4 x 4 SPD ``A``.

    A lower bound of ``dᵀ A⁻¹ d``: the Mahalanobis distance of a sub-vector under its marginal
    covariance never exceeds the full one (the Schur complement is positive definite).

    Parameters
    ----------
    d : ndarray of float64, shape (4,)
        Difference of two means.
    A : ndarray of float64, shape (4, 4)
        Symmetric positive definite.

    Returns
    -------
    float
    """
    a = A[0, 0]
    b = A[0, 2]
    c = A[2, 2]
    return (c * d[0] * d[0] - 2.0 * b * d[0] * d[2] + a * d[2] * d[2]) / (a * c - b * b)


# a bound decides a pair only when it clears the threshold by this much, far more than the
# rounding of the exact statistic (a 4 x 4 SPD solve), so the decision is the one the exact
# statistic would make
_BOUND_MARGIN = 1e-9


@jit()
def _heaviest(w, idx, alive):
    """Position in ``idx`` of the heaviest alive component (the first one on ties).

    Parameters
    ----------
    w : ndarray of float64, shape (C,)
        Component weights.
    idx : ndarray of int64, shape (n,)
        The kept components.
    alive : ndarray of bool, shape (n,)
        The components not yet merged.

    Returns
    -------
    int
        The position, ``-1`` when none is alive.
    """
    jq = -1
    for q in range(idx.size):
        if alive[q] and (jq < 0 or w[idx[q]] > w[idx[jq]]):
            jq = q
    return jq


@jit()
def _difference(m, a, b):
    """``m[a] − m[b]`` (4,), element by element.

    Parameters
    ----------
    m : ndarray of float64, shape (C, 4)
        Component means.
    a, b : int
        Components.

    Returns
    -------
    ndarray of float64, shape (4,)
    """
    d = np.empty(4)
    for u in range(4):
        d[u] = m[a, u] - m[b, u]
    return d


@jit()
def _merge_distance(m, P, idx, inv, have_inv, logdet, q, jq, rule,
                    merge_thr):
    """Merging statistic of candidate ``q`` against the heaviest ``jq`` (``inf``: cannot merge).

    ``d = m_q − m_j``; rule 0: ``dᵀ P̄⁻¹ d + 4 ln(|P̄| / √(|P_q| |P_j|))``, ``P̄ = (P_q + P_j)/2``;
    rule 1: ``dᵀ P_q⁻¹ d``; rule 2: ``dᵀ P_j⁻¹ d``. Pairs that a lower bound of the statistic
    puts clearly above ``merge_thr`` return ``inf`` without the 4 x 4 algebra.

    Parameters
    ----------
    m : ndarray of float64, shape (C, 4)
        Component means.
    P, idx, logdet
        As in :func:`_component_logdet`.
    inv, have_inv
        As in :func:`_component_inverse`.
    q, jq : int
        Positions in ``idx`` of the candidate and of the heaviest component.
    rule : int
        Merging criterion, as in :func:`reduce_mixtures`.
    merge_thr : float
        Merging threshold ``U``.

    Returns
    -------
    float
        The statistic (0 when ``q == jq``), or ``inf``.
    """
    if q == jq:
        return 0.0
    cq = idx[q]
    cj = idx[jq]
    val = 0.0
    if rule == _BHATTACHARYYA:
        # dᵀ P̄⁻¹ d >= |d|² / λ_max(P̄) >= |d|² / tr(P̄) and the log-det term is >= 0: pairs
        # farther apart than that cannot merge, so the 4 x 4 algebra is skipped for them
        dd = 0.0
        tr = 0.0
        for u in range(4):
            du = m[cq, u] - m[cj, u]
            dd += du * du
            tr += 0.5 * (P[cq, u, u] + P[cj, u, u])
        if dd > merge_thr * tr:
            return np.inf
        d = _difference(m, cq, cj)
        Pbar = np.empty((4, 4))
        for u in range(4):
            for v in range(4):
                Pbar[u, v] = 0.5 * (P[cq, u, v] + P[cj, u, v])
        # the log-det term is >= 0 too, so the position part of dᵀ P̄⁻¹ d bounds the statistic
        if _position_bound(d, Pbar) > merge_thr * (1.0 + _BOUND_MARGIN) + _BOUND_MARGIN:
            return np.inf
        Pbi = np.linalg.inv(Pbar)
        for u in range(4):
            for v in range(4):
                val += d[u] * Pbi[u, v] * d[v]
        val += 4.0 * (np.linalg.slogdet(Pbar)[1]
                      - 0.5 * (_component_logdet(P, idx, logdet, q)
                               + _component_logdet(P, idx, logdet, jq)))
        return val
    d = _difference(m, cq, cj)
    qq = q if rule == _VO_MA else jq
    if _position_bound(d, P[idx[qq]]) > merge_thr * (1.0 + _BOUND_MARGIN) + _BOUND_MARGIN:
        return np.inf
    Pi = _component_inverse(P, idx, inv, have_inv, qq)
    for u in range(4):
        for v in range(4):
            val += d[u] * Pi[u, v] * d[v]
    return val


@jit()
def _moment_match(w, m, P, idx, members, nm, ow, om, oP, o):
    """``w = Σ w_i``, ``m = Σ w_i m_i / w``, ``P = Σ w_i (P_i + (m − m_i)(m − m_i)ᵀ) / w``,
    written into ``ow[o], om[o], oP[o]``.

    Parameters
    ----------
    w, m, P : ndarray of float64, shapes (C,), (C, 4), (C, 4, 4)
        Component weights, means and covariances.
    idx : ndarray of int64, shape (n,)
        The kept components.
    members : ndarray of int64, shape (n,)
        ``members[:nm]``: positions in ``idx`` of the components to merge.
    nm : int
        Their number (at least 1).
    ow, om, oP : ndarray of float64, shapes (C,), (C, 4), (C, 4, 4)
        Output components; entry ``o`` is written (``oP[o]`` symmetrised).
    o : int
        The output entry.
    """
    wsum = 0.0
    mean = np.zeros(4)
    for s in range(nm):
        c = idx[members[s]]
        wsum += w[c]
        for u in range(4):
            mean[u] += w[c] * m[c, u]
    for u in range(4):
        mean[u] /= wsum
    cov = np.zeros((4, 4))
    d = np.empty(4)
    for s in range(nm):
        c = idx[members[s]]
        for u in range(4):
            d[u] = m[c, u] - mean[u]
        for u in range(4):
            for v in range(4):
                cov[u, v] += w[c] * (P[c, u, v] + d[u] * d[v])
    for u in range(4):
        for v in range(4):
            cov[u, v] /= wsum
    ow[o] = wsum
    for u in range(4):
        om[o, u] = mean[u]
        for v in range(4):
            oP[o, u, v] = 0.5 * (cov[u, v] + cov[v, u])


@jit()
def _sort_cap_normalise(ow, om, oP, start, stop, cap):
    """Sort ``start:stop`` by decreasing weight (stable), keep ``cap``, renormalise; new stop.

    Parameters
    ----------
    ow, om, oP : ndarray of float64, shapes (C,), (C, 4), (C, 4, 4)
        Output components, sorted in place in ``start:stop``.
    start, stop : int
        One track's output range.
    cap : int
        Maximum number of components kept.

    Returns
    -------
    int
        The new stop, ``start + min(stop - start, cap)``; the kept weights sum to 1.
    """
    n = stop - start
    # np.argsort(-w, kind="mergesort") by a stable insertion sort: the same order (ties keep
    # their order in both), without compiling numba's generic merge sort (about 1.2 s of
    # every filter's first step). The merge loop emits its clusters heaviest first, so the
    # weights arrive nearly sorted and the insertion sort runs in about n steps.
    order = np.empty(n, dtype=np.int64)
    for i in range(n):
        x = -ow[start + i]
        j = i
        while j > 0 and -ow[start + order[j - 1]] > x:
            order[j] = order[j - 1]
            j -= 1
        order[j] = i
    sw = np.empty(n)
    sm = np.empty((n, 4))
    sP = np.empty((n, 4, 4))
    for i in range(n):
        c = start + order[i]
        sw[i] = ow[c]
        for u in range(4):
            sm[i, u] = om[c, u]
            for v in range(4):
                sP[i, u, v] = oP[c, u, v]
    for i in range(n):
        c = start + i
        ow[c] = sw[i]
        for u in range(4):
            om[c, u] = sm[i, u]
            for v in range(4):
                oP[c, u, v] = sP[i, u, v]
    stop = start + min(n, cap)
    tot = 0.0
    for c in range(start, stop):
        tot += ow[c]
    for c in range(start, stop):
        ow[c] /= tot
    return stop


@jit()
def reduce_mixtures(offsets, w, m, P, keep, elim, merge_thr, cap, rule):
    """Prune, merge and cap the Gaussian mixture of every kept track.

    Parameters
    ----------
    offsets : ndarray of int64, shape (T + 1,)
        Component range of track ``t`` is ``offsets[t]:offsets[t + 1]``.
    w, m, P : ndarray, shapes (C,), (C, 4), (C, 4, 4)
        Component weights (summing to 1 per track), means and covariances.
    keep : ndarray of bool, shape (T,)
        Tracks to keep; the others are dropped.
    elim : float
        Pruning threshold: keep ``w > elim``; the heaviest component always stays.
    merge_thr : float
        Merging threshold ``U``.
    cap : int
        Maximum number of components per track.
    rule : int
        Merging criterion (:data:`MERGE_RULES`); with ``j`` the heaviest remaining component,
        ``i`` a candidate and ``d = m_i − m_j``:

        * 0, ``"bhattacharyya"``: ``dᵀ P̄⁻¹ d + 4 ln(|P̄| / √(|P_i| |P_j|)) <= U`` with
          ``P̄ = (P_i + P_j) / 2``, i.e. eight times the Bhattacharyya distance of the two
          Gaussians. It equals the Mahalanobis test below when ``P_i = P_j`` and refuses to
          merge components of very different spread;
        * 1, ``"vo-ma"``: ``dᵀ P_i⁻¹ d <= U`` (Vo & Ma 2006, Table II);
        * 2, ``"heaviest"``: ``dᵀ P_j⁻¹ d <= U`` (the distance of Vo's MATLAB ``gaus_merge``).

    Returns
    -------
    offsets : ndarray of int64, shape (T_kept + 1,)
    w, m, P : ndarray
        Components of each kept track in decreasing weight (stable on ties), weights
        renormalised to sum to 1 per track.

    Notes
    -----
    Pruning and merging of Vo & Ma (2006, Table II) followed by the cap of Vo's code
    (``gaus_cap``), with the thresholds of spec §6.4, in four phases per track:
    :func:`_prune_components`; then repeatedly the heaviest remaining component
    (:func:`_heaviest`) absorbs every remaining one whose :func:`_merge_distance` is at most
    ``U``, by moment matching (:func:`_moment_match`); finally :func:`_sort_cap_normalise`.
    A pair whose statistic a cheap lower bound (:func:`_position_bound`) puts clearly above
    ``U`` is decided without the 4 x 4 inverse and determinants.
    Vo's MATLAB ``gaus_merge`` omits the spread-of-means term of the merged covariance; that is
    not offered. Why the Bhattacharyya criterion is the filter's default is explained on the
    Tracking page of the documentation.

    References
    ----------
    .. [1] B.-N. Vo, W.-K. Ma, "The Gaussian Mixture Probability Hypothesis Density Filter",
       IEEE Trans. Signal Process. 54(11), 2006.

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign.tracking._kernels import reduce_mixtures
    >>> P = np.tile(np.eye(4), (3, 1, 1))
    >>> m = np.array([[0.0, 0, 0, 0], [0.5, 0, 0, 0], [9.0, 0, 0, 0]])
    >>> off, w, mm, PP = reduce_mixtures(np.array([0, 3]), np.array([0.5, 0.3, 0.2]), m, P,
    ...                                  np.array([True]), 1e-5, 4.0, 10, 0)
    >>> off.tolist(), w.round(2).tolist(), mm[:, 0].round(4).tolist()
    ([0, 2], [0.8, 0.2], [0.1875, 9.0])
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
    n_out = np.int64(0)  # (a literal would compile a second signature of the phases)
    tk = 0
    for t in range(T):
        if not keep[t]:
            continue
        idx = _prune_components(w, offsets[t], offsets[t + 1], elim)
        n = idx.size
        inv, logdet, have_inv = _merge_prepare(idx)
        alive = np.ones(n, dtype=np.bool_)
        members = np.empty(n, dtype=np.int64)
        start = n_out
        n_alive = n
        while n_alive > 0:
            jq = _heaviest(w, idx, alive)
            nm = np.int64(0)
            for q in range(n):
                if alive[q] and _merge_distance(m, P, idx, inv, have_inv, logdet, q, jq, rule,
                                                merge_thr) <= merge_thr:
                    members[nm] = q
                    nm += 1
                    alive[q] = False
                    n_alive -= 1
            _moment_match(w, m, P, idx, members, nm, ow, om, oP, n_out)
            n_out += 1
        # a later cluster can outweigh an earlier one: sort, then cap and renormalise
        n_out = _sort_cap_normalise(ow, om, oP, start, n_out, cap)
        tk += 1
        ooff[tk] = n_out
    return ooff, ow[:n_out].copy(), om[:n_out].copy(), oP[:n_out].copy()


# ------------------------------------------------------------------ measurement likelihoods
_LOG_2PI = math.log(2.0 * math.pi)
_LOGE2 = math.log(2.0)


@jit()
def gate_and_distances(m, P, R, z, offsets, gate, use_gate):
    """Innovation statistics of every component and measurement, and the χ² gate per track.

    Parameters
    ----------
    m, P : ndarray, shapes (C, 4), (C, 4, 4)
        Predicted component means and covariances.
    R : ndarray, shape (2, 2)
        Measurement noise covariance (``H`` picks ``p_x, p_y``).
    z : ndarray, shape (M, 2)
        Measurements.
    offsets : ndarray of int64, shape (T + 1,)
        Component range of every track.
    gate : float
        Threshold on the squared Mahalanobis distance.
    use_gate : bool
        False: every pair is in the gate.

    Returns
    -------
    det : ndarray, shape (C,)
        ``|S|`` with ``S = H P Hᵀ + R``.
    Sinv : ndarray, shape (C, 2, 2)
        ``S⁻¹`` (the closed-form 2 x 2 inverse).
    nu : ndarray, shape (C, M, 2)
        Innovations ``z_j − H m_c``.
    maha : ndarray, shape (C, M)
        ``ν' S⁻¹ ν``.
    gated : ndarray of bool, shape (T, M)
        Measurement ``j`` lies in the gate of some component of track ``t``.

    Notes
    -----
    The operations and their order are those of the numpy expressions of
    :func:`rankedassign.tracking.reference.gate_and_distances`, so that both give the same
    numbers bit for bit (no fused multiply-add: fastmath is off).
    """
    C = m.shape[0]
    M = z.shape[0]
    T = offsets.size - 1
    det = np.empty(C)
    Sinv = np.empty((C, 2, 2))
    nu = np.empty((C, M, 2))
    maha = np.empty((C, M))
    gated = np.zeros((T, M), dtype=np.bool_)
    for t in range(T):
        for c in range(offsets[t], offsets[t + 1]):
            # S = H P H' + R
            s00 = P[c, 0, 0] + R[0, 0]
            s01 = P[c, 0, 2] + R[0, 1]
            s10 = P[c, 2, 0] + R[1, 0]
            s11 = P[c, 2, 2] + R[1, 1]
            d = s00 * s11 - s01 * s10
            det[c] = d
            i00 = s11 / d
            i11 = s00 / d
            i01 = -s01 / d
            i10 = -s10 / d
            Sinv[c, 0, 0] = i00
            Sinv[c, 0, 1] = i01
            Sinv[c, 1, 0] = i10
            Sinv[c, 1, 1] = i11
            cross = i01 + i10
            for j in range(M):
                n0 = z[j, 0] - m[c, 0]
                n1 = z[j, 1] - m[c, 2]
                nu[c, j, 0] = n0
                nu[c, j, 1] = n1
                q = i00 * (n0 * n0) + cross * n0 * n1 + i11 * (n1 * n1)
                maha[c, j] = q
                if not use_gate or q <= gate:
                    gated[t, j] = True
    return det, Sinv, nu, maha, gated


@jit()
def _logaddexp(x, y):
    """``ln(eˣ + eʸ)`` by the same steps as numpy's ``logaddexp`` (so, bit for bit, the same).

    Parameters
    ----------
    x, y : float

    Returns
    -------
    float
    """
    if x == y:
        return x + _LOGE2
    tmp = x - y
    if tmp > 0:
        return x + math.log1p(math.exp(-tmp))
    if tmp <= 0:
        return y + math.log1p(math.exp(tmp))
    return tmp


@jit()
def detection_log_weights(maha, log_det_S, log_w, offsets, used, gated, log_r, log_pd,
                          log_kappa):
    """Per component and per track: the log-likelihoods of the measurements ``used``.

    Parameters
    ----------
    maha : ndarray, shape (C, M)
        Squared Mahalanobis distances (:func:`gate_and_distances`).
    log_det_S, log_w : ndarray, shape (C,)
        ``ln|S_c|`` and ``ln w_c``.
    offsets : ndarray of int64, shape (T + 1,)
    used : ndarray of int64, shape (U,)
        Measurement columns kept (those in some gate).
    gated : ndarray of bool, shape (T, U)
        Gate of the kept columns.
    log_r : ndarray, shape (T,)
        ``ln r_+``.
    log_pd, log_kappa : float
        ``ln P_D`` and ``ln κ``.

    Returns
    -------
    lw : ndarray, shape (C, U)
        ``ln w_c + ln N(z_j; H m_c, S_c)`` where track ``t`` of component ``c`` gates ``j``,
        ``−inf`` elsewhere.
    log_g : ndarray, shape (T, U)
        ``ln Σ_c w_c N(z_j; H m_c, S_c)`` over the components of each track (log-sum-exp,
        folded in component order as numpy's ``logaddexp.reduceat``) in the gate, ``−inf``
        elsewhere.
    log_det : ndarray, shape (T, U)
        ``ln η_t(j) = ln r_t + ln P_D + log_g − ln κ`` in the gate, ``−inf`` outside (eq. 6.2).

    Notes
    -----
    Pairs outside the gate are forbidden (``η = 0``): their marginals are 0 and the update never
    reads their likelihoods, so only gated pairs are computed.
    """
    C = maha.shape[0]
    T = offsets.size - 1
    U = used.size
    lw = np.empty((C, U))
    log_g = np.empty((T, U))
    log_det = np.empty((T, U))
    for t in range(T):
        a = offsets[t]
        b = offsets[t + 1]
        for k in range(U):
            if not gated[t, k]:
                for c in range(a, b):
                    lw[c, k] = -np.inf
                log_g[t, k] = -np.inf
                log_det[t, k] = -np.inf
                continue
            for c in range(a, b):
                # ln N(z; H m, S) = -(d ln 2π + ln|S| + ν' S⁻¹ ν) / 2, d = 2
                log_n = (-0.5 * maha[c, used[k]] - _LOG_2PI) - 0.5 * log_det_S[c]
                lw[c, k] = log_w[c] + log_n
            acc = lw[a, k]
            for c in range(a + 1, b):
                acc = _logaddexp(acc, lw[c, k])
            log_g[t, k] = acc
            log_det[t, k] = ((log_r[t] + log_pd) + acc) - log_kappa
    return lw, log_g, log_det


# ------------------------------------------------------------------ association problems
@jit()
def connected_groups(gated):
    """Connected components of the bipartite track–measurement graph of ``gated`` (T, M).

    Parameters
    ----------
    gated : ndarray of bool, shape (T, M)
        ``gated[t, j]``: measurement ``j`` lies in the gate of track ``t``.

    Returns
    -------
    track_group : ndarray of int64, shape (T,)
        Group of every track; groups are numbered in the order of their first track.
    meas_group : ndarray of int64, shape (M,)
        Group of every measurement, ``-1`` for a measurement no track gates.
    n_groups : int
        Number of groups (a track that gates nothing is a group of its own).
    """
    T, M = gated.shape
    tg = np.full(T, -1, dtype=np.int64)
    mg = np.full(M, -1, dtype=np.int64)
    stack = np.empty(T, dtype=np.int64)
    n = 0
    for t0 in range(T):
        if tg[t0] >= 0:
            continue
        tg[t0] = n
        stack[0] = t0
        top = 1
        while top > 0:
            top -= 1
            t = stack[top]
            for j in range(M):
                if gated[t, j] and mg[j] < 0:
                    mg[j] = n
                    for u in range(T):
                        if gated[u, j] and tg[u] < 0:
                            tg[u] = n
                            stack[top] = u
                            top += 1
        n += 1
    return tg, mg, n


@jit()
def group_cost_matrix(log_det, log_miss, log_dead, rows, cols):
    """Cost matrix ``−ln η`` of the tracks ``rows`` and measurements ``cols``, paper layout.

    ``C[i, j] = −log_det[rows[i], cols[j]]``, ``C[i, M + i] = −log_miss[rows[i]]``,
    ``C[i, M + P + i] = −log_dead[rows[i]]``, ``+inf`` elsewhere (spec §1.5).

    Parameters
    ----------
    log_det : ndarray of float64, shape (T, U)
        ``ln η_t(j)`` of every track and kept measurement (:func:`detection_log_weights`).
    log_miss, log_dead : ndarray of float64, shape (T,)
        ``ln η`` of a missed detection and of non-existence, per track.
    rows : ndarray of int64, shape (P,)
        The group's tracks.
    cols : ndarray of int64, shape (M,)
        The group's measurements (columns of ``log_det``).

    Returns
    -------
    ndarray of float64, shape (P, M + 2 P)
    """
    P = rows.size
    M = cols.size
    C = np.full((P, M + 2 * P), np.inf)
    for i in range(P):
        r = rows[i]
        for j in range(M):
            C[i, j] = -log_det[r, cols[j]]
        C[i, M + i] = -log_miss[r]
        C[i, M + P + i] = -log_dead[r]
    return C


@jit()
def truncated_marginals(a, w, M):
    """``β[i, j] = Σ_h w_h 1[γ_i^(h) = j]`` in compact columns ``[meas | missed | dead]``.

    The sum runs over ``h`` in order, as ``numpy.bincount`` does.

    Parameters
    ----------
    a : ndarray of integers, shape (H, P)
        Assignments as columns of the paper-layout cost matrix (``M + 2 P`` columns).
    w : ndarray of float64, shape (H,)
        Normalised weights of the assignments.
    M : int
        Number of measurements.

    Returns
    -------
    ndarray of float64, shape (P, M + 2)
        ``β``: columns ``0..M-1`` the measurements, ``M`` missed, ``M + 1`` dead.
    """
    H, P = a.shape
    beta = np.zeros((P, M + 2))
    for h in range(H):
        for i in range(P):
            col = a[h, i]
            if col < M:
                k = col
            elif col < M + P:
                k = M
            else:
                k = M + 1
            beta[i, k] += w[h]
    return beta


# ------------------------------------------------------------------ extraction
@jit()
def cardinality_distribution(r):
    """Poisson-binomial distribution of the number of tracks that exist, shape (T + 1,).

    ``ρ ← ρ (1 − r_i)`` shifted-added ``ρ r_i`` for every track in turn (the convolution
    recursion).

    Parameters
    ----------
    r : ndarray of float64, shape (T,)
        Existence probabilities.

    Returns
    -------
    ndarray of float64, shape (T + 1,)
        ``ρ[n]``: probability that exactly ``n`` tracks exist.
    """
    n = r.size
    rho = np.zeros(n + 1)
    rho[0] = 1.0
    for i in range(n):
        q = r[i]
        p = 1.0 - q
        for k in range(n, 0, -1):
            rho[k] = rho[k] * p + rho[k - 1] * q
        rho[0] *= p
    return rho


# ------------------------------------------------------------------ update from the marginals
@jit()
def posterior_sources(offsets, rel, elim, lw, log_g):
    """Where each posterior component comes from, grouped by track (spec eq. 6.4).

    Parameters
    ----------
    offsets : ndarray of int64, shape (T + 1,)
        Component ranges of the predicted tracks.
    rel : ndarray, shape (T, M + 1)
        ``β_ij / r_i``; column ``M`` is the missed detection.
    elim : float
        Pairs with ``rel <= elim`` are not expanded (their components would be pruned).
    lw, log_g : ndarray, shapes (C, M), (T, M)
        ``ln w_c N(z_j; ...)`` and its log-sum over each track's components.

    Returns
    -------
    comp, track, meas : ndarray of int64, shape (N,)
        Predicted component, track and measurement (``-1``: missed detection) of every
        posterior component; per track the missed-detection components first, then the
        updates with each measurement in turn, each over the track's components in order.
    log_ratio : ndarray, shape (N,)
        ``lw[c, j] − log_g[t, j]`` for an update (0 for a missed detection).
    counts : ndarray of int64, shape (T,)
        Posterior components per track.
    """
    T = offsets.size - 1
    M = rel.shape[1] - 1
    n = 0
    for t in range(T):
        nc = offsets[t + 1] - offsets[t]
        for j in range(M + 1):
            if rel[t, j] > elim:
                n += nc
    comp = np.empty(n, dtype=np.int64)
    track = np.empty(n, dtype=np.int64)
    meas = np.empty(n, dtype=np.int64)
    log_ratio = np.zeros(n)
    counts = np.zeros(T, dtype=np.int64)
    k = 0
    for t in range(T):
        start = k
        if rel[t, M] > elim:
            for c in range(offsets[t], offsets[t + 1]):
                comp[k] = c
                track[k] = t
                meas[k] = -1
                k += 1
        for j in range(M):
            if rel[t, j] > elim:
                for c in range(offsets[t], offsets[t + 1]):
                    comp[k] = c
                    track[k] = t
                    meas[k] = j
                    log_ratio[k] = lw[c, j] - log_g[t, j]
                    k += 1
        counts[t] = k - start
    return comp, track, meas, log_ratio, counts


@jit()
def posterior_components(comp, track, meas, ratio, rel, w, m, P, K, nu,
                         P_upd):
    """Weights, means and covariances of the posterior components (spec eq. 6.4).

    For a missed detection of track ``t``: ``(rel[t, M] w_c, m_c, P_c)``; for an update with
    measurement ``j``: ``(ratio · rel[t, j], m_c + K_c ν_cj, P'_c)`` with ``ratio = w_c N_cj /
    Σ_c' w_c' N_c'j`` and ``K_c``, ``P'_c`` the Kalman gain and updated covariance (computed by
    the caller; ``K`` and ``P_upd`` may be empty when there is no update).

    Parameters
    ----------
    comp, track, meas : ndarray of int64, shape (N,)
        Sources of the posterior components (:func:`posterior_sources`).
    ratio : ndarray of float64, shape (N,)
        ``exp`` of :func:`posterior_sources`' ``log_ratio``.
    rel : ndarray of float64, shape (T, M + 1)
        ``β_ij / r_i``; column ``M`` is the missed detection.
    w, m, P : ndarray of float64, shapes (C,), (C, 4), (C, 4, 4)
        Predicted component weights, means and covariances.
    K : ndarray of float64, shape (C, 4, 2)
        Kalman gains (or empty).
    nu : ndarray of float64, shape (C, M, 2)
        Innovations (:func:`gate_and_distances`, restricted to the kept columns).
    P_upd : ndarray of float64, shape (C, 4, 4)
        Updated covariances (or empty).

    Returns
    -------
    w, m, P : ndarray of float64, shapes (N,), (N, 4), (N, 4, 4)
        The posterior components, in the order of ``comp``.
    """
    n = comp.size
    M = rel.shape[1] - 1
    w_out = np.empty(n)
    m_out = np.empty((n, 4))
    P_out = np.empty((n, 4, 4))
    for k in range(n):
        c = comp[k]
        t = track[k]
        j = meas[k]
        if j < 0:
            w_out[k] = rel[t, M] * w[c]
            for u in range(4):  # element by element: see "Compile cost" above
                m_out[k, u] = m[c, u]
                for v in range(4):
                    P_out[k, u, v] = P[c, u, v]
        else:
            w_out[k] = ratio[k] * rel[t, j]
            # m' = m + K (z_j − H m)
            for i in range(4):
                m_out[k, i] = m[c, i] + (K[c, i, 0] * nu[c, j, 0] + K[c, i, 1] * nu[c, j, 1])
            for u in range(4):
                for v in range(4):
                    P_out[k, u, v] = P_upd[c, u, v]
    return w_out, m_out, P_out

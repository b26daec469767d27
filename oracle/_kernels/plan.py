"""Compiled planning of the frontier DP: components, measurement orders, the operation list.

The δ-GLMB filter's retained mass (spec §4) asks :mod:`oracle.single.dp` for thousands of small
normalisers a run, and there the planning (which component, which measurement order, which
operations), not the DP itself, took most of the time when it was written with NumPy and
SciPy calls per measurement. These kernels do the same work in compiled loops and give the
same answer to the last bit: :mod:`oracle.single._plan_reference` is the pure-Python
specification they are tested against (``tests/test_oracle_plan.py``).

Every kernel takes the boolean gate matrix ``finite`` (P, K) of one problem or component (True
where the row may take the measurement); the bipartite graph has nodes ``0..P-1`` (rows) and
``P..P+K-1`` (measurements), each node's neighbours in increasing index, as in the CSR matrix
SciPy's routines walk.
"""

from __future__ import annotations

import numpy as np

from rankedassign.numba_options import jit

from .dp import ENTER, RETIRE, TRANS

__all__ = [
    "bipartite_components",
    "frontier_candidates",
    "frontier_ops",
    "frontier_profile",
    "greedy_order",
]


@jit()
def bipartite_components(finite):
    """Connected components of rows and measurements, numbered by their first row.

    Parameters
    ----------
    finite : ndarray of bool, shape (P, K)
        ``finite[i, j]``: row ``i`` may take measurement ``j``.

    Returns
    -------
    row_comp : ndarray, int64, shape (P,)
        Component of every row, ``-1`` for a row without any finite measurement.
    meas_comp : ndarray, int64, shape (K,)
        Component of every measurement, ``-1`` for one that no row gates.
    n : int
        Number of components (each holds at least one finite entry).
    """
    P, K = finite.shape
    row_comp = np.full(P, -1, dtype=np.int64)
    meas_comp = np.full(K, -1, dtype=np.int64)
    stack = np.empty(P + K, dtype=np.int64)
    n = 0
    for r0 in range(P):
        if row_comp[r0] >= 0:
            continue
        has = False
        for j in range(K):
            if finite[r0, j]:
                has = True
                break
        if not has:
            continue
        # depth-first flood fill; node v < P is a row, v >= P the measurement v - P
        row_comp[r0] = n
        top = 0
        stack[top] = r0
        top += 1
        while top > 0:
            top -= 1
            v = stack[top]
            if v < P:
                for j in range(K):
                    if finite[v, j] and meas_comp[j] < 0:
                        meas_comp[j] = n
                        stack[top] = P + j
                        top += 1
            else:
                j = v - P
                for i in range(P):
                    if finite[i, j] and row_comp[i] < 0:
                        row_comp[i] = n
                        stack[top] = i
                        top += 1
        n += 1
    return row_comp, meas_comp, n


@jit()
def frontier_profile(finite, order):
    """Frontier width and operation count of the frontier DP for a measurement order.

    Row ``i`` is active at step ``t`` when its first finite measurement in ``order`` comes at
    or before ``t`` and its last one at or after ``t``; a step with ``n`` active rows and ``d``
    finite entries costs ``(3 + d) 2^n``.

    Parameters
    ----------
    finite : ndarray of bool, shape (P, K)
        Gate matrix of one connected component.
    order : ndarray of int64, shape (K,)
        A permutation of the measurements.

    Returns
    -------
    width : int
        Most rows active at one step.
    work : float
        ``sum_t (3 + d_t) 2^{n_t}``, summed in step order. Every term is an integer, so the
        sum is exact, and equal to NumPy's pairwise sum, while it is below ``2^53``; the caller
        recomputes it with NumPy above that (see :func:`oracle.single.dp._frontier_order`).
    """
    P, K = finite.shape
    delta = np.zeros(K + 1, dtype=np.int64)
    for i in range(P):
        first = -1
        last = -1
        for t in range(K):
            if finite[i, order[t]]:
                if first < 0:
                    first = t
                last = t
        if first < 0:
            # an all-False row: np.argmax gives 0 from both ends (first 0, last K - 1)
            first = 0
            last = K - 1
        delta[first] += 1
        delta[last + 1] -= 1
    width = 0
    work = 0.0
    active = 0
    for t in range(K):
        active += delta[t]
        if active > width:
            width = active
        d = 0
        for i in range(P):
            if finite[i, order[t]]:
                d += 1
        work += (3.0 + d) * 2.0 ** active
    return width, work


@jit()
def greedy_order(finite, start):
    """Measurement order grown one measurement at a time from ``start``.

    Next comes the measurement that brings in the fewest new rows, then the one that lets the
    most rows retire (their last remaining measurement), then the one touching the most active
    rows, then the lowest index — the rule of
    :func:`oracle.single._plan_reference._greedy_order`.

    Parameters
    ----------
    finite : ndarray of bool, shape (P, K)
        Gate matrix of one connected component.
    start : int
        The first measurement.

    Returns
    -------
    ndarray of int64, shape (K,)
        The order, a permutation of the measurements.
    """
    P, K = finite.shape
    done = np.zeros(K, dtype=np.bool_)
    entered = np.zeros(P, dtype=np.bool_)
    left = np.zeros(P, dtype=np.int64)
    for i in range(P):
        for j in range(K):
            if finite[i, j]:
                left[i] += 1
    order = np.empty(K, dtype=np.int64)
    j = start
    for t in range(K):
        order[t] = j
        done[j] = True
        for i in range(P):
            if finite[i, j]:
                entered[i] = True
                left[i] -= 1
        if t == K - 1:
            break
        # the lexicographic minimum of (new, -retire, -touch, index) over the candidates
        best = -1
        b_new = b_ret = b_touch = 0
        for c in range(K):
            if done[c]:
                continue
            new = ret = touch = 0
            for i in range(P):
                if finite[i, c]:
                    if entered[i]:
                        touch += 1
                    else:
                        new += 1
                    if left[i] == 1:
                        ret += 1
            if best < 0 or new < b_new or (new == b_new and (
                    ret > b_ret or (ret == b_ret and touch > b_touch))):
                best, b_new, b_ret, b_touch = c, new, ret, touch
        j = best
    return order


@jit()
def _bfs(finite, src, dist, queue):
    """Breadth-first distances (float64, ``inf`` unreachable) of every node from ``src``.

    Parameters
    ----------
    finite : ndarray of bool, shape (P, K)
        The bipartite graph: node ``i < P`` is row ``i``, node ``P + j`` measurement ``j``.
    src : int
        The start node.
    dist : ndarray of float64, shape (P + K,)
        Overwritten with the distances (in edges).
    queue : ndarray of int64, shape (P + K,)
        Scratch.
    """
    P, K = finite.shape
    dist[:] = np.inf
    dist[src] = 0.0
    head = 0
    tail = 1
    queue[0] = src
    while head < tail:
        v = queue[head]
        head += 1
        dv = dist[v] + 1.0
        if v < P:
            for j in range(K):
                if finite[v, j] and dist[P + j] == np.inf:
                    dist[P + j] = dv
                    queue[tail] = P + j
                    tail += 1
        else:
            j = v - P
            for i in range(P):
                if finite[i, j] and dist[i] == np.inf:
                    dist[i] = dv
                    queue[tail] = i
                    tail += 1


@jit()
def _peripheral(finite, deg):
    """A pseudo-peripheral measurement and the BFS distances of the measurements from it
    (:func:`oracle.single._plan_reference._peripheral`).

    Parameters
    ----------
    finite : ndarray of bool, shape (P, K)
        Gate matrix of one connected component.
    deg : ndarray of int64, shape (K,)
        Degrees of the measurements (the search starts from the first of least degree).

    Returns
    -------
    start : int
        The measurement.
    dist : ndarray of float64, shape (K,)
        Distances of the measurements from it, in edges of the bipartite graph.
    """
    P, K = finite.shape
    dist = np.empty(P + K)
    d2 = np.empty(P + K)
    queue = np.empty(P + K, dtype=np.int64)
    start = np.argmin(deg)
    _bfs(finite, P + start, dist, queue)
    for _ in range(8):
        far = np.argmax(dist[P:])
        _bfs(finite, P + far, d2, queue)
        if d2[P:].max() <= dist[P:].max():
            break
        start = far
        dist, d2 = d2, dist
    return start, dist[P:].copy()


@jit()
def _cuthill_mckee(finite, inds, degree):
    """Reverse Cuthill–McKee order of the measurements (SciPy's ``reverse_cuthill_mckee``).

    SciPy's algorithm on the symmetric bipartite graph: breadth first from the first
    unvisited node of ``inds`` (the nodes by degree, ``np.argsort(degree)``), each node's
    unvisited neighbours appended in index order and then stably sorted by degree (an insertion
    sort), a new start for every connected component, the whole order reversed; here only its
    measurements are kept.

    Parameters
    ----------
    finite : ndarray of bool, shape (P, K)
        Gate matrix: node ``i < P`` is row ``i``, node ``P + j`` measurement ``j``.
    inds : ndarray of int64, shape (P + K,)
        The nodes by degree (``np.argsort(degree)``).
    degree : ndarray of int64, shape (P + K,)
        Node degrees.

    Returns
    -------
    ndarray of int64, shape (K,)
        The measurements in reverse Cuthill–McKee order.
    """
    P, K = finite.shape
    N = P + K
    order = np.empty(N, dtype=np.int64)
    seen = np.zeros(N, dtype=np.bool_)
    n = 0
    for zz in range(N):
        seed = inds[zz]
        if seen[seed]:
            continue
        order[n] = seed
        seen[seed] = True
        n += 1
        level_start = n - 1
        level_end = n
        while level_start < level_end:
            for ii in range(level_start, level_end):
                v = order[ii]
                n_old = n
                if v < P:
                    for j in range(K):
                        if finite[v, j] and not seen[P + j]:
                            seen[P + j] = True
                            order[n] = P + j
                            n += 1
                else:
                    j = v - P
                    for i in range(P):
                        if finite[i, j] and not seen[i]:
                            seen[i] = True
                            order[n] = i
                            n += 1
                # insertion sort of the new nodes by degree (stable: ties keep their order)
                for kk in range(n_old + 1, n):
                    node = order[kk]
                    dk = degree[node]
                    ll = kk
                    while ll > n_old and dk < degree[order[ll - 1]]:
                        order[ll] = order[ll - 1]
                        ll -= 1
                    order[ll] = node
            level_start = level_end
            level_end = n
        if n == N:
            break
    out = np.empty(K, dtype=np.int64)
    m = 0
    for kk in range(N - 1, -1, -1):
        if order[kk] >= P:
            out[m] = order[kk] - P
            m += 1
    return out


@jit()
def frontier_candidates(finite, inds, degree):
    """The candidate measurement orders of :func:`oracle.single.dp._frontier_order`.

    Parameters
    ----------
    finite : ndarray, bool, shape (P, K)
        Gate matrix of one connected component.
    inds : ndarray, int64, shape (P + K,)
        ``np.argsort(degree)`` as SciPy's reverse Cuthill–McKee takes it (the caller sorts
        with NumPy, whose sort decides the ties, so the start node is SciPy's).
    degree : ndarray, int64, shape (P + K,)
        Node degrees of the bipartite graph.

    Returns
    -------
    cands : ndarray, int64, shape (n, K)
        The reverse Cuthill–McKee order, the breadth-first order from a pseudo-peripheral
        measurement (by distance, then degree, then index), and the greedy orders
        (:func:`greedy_order`) from that measurement, from the first measurement of least
        degree and from both ends of the RCM order (each start once, first occurrence kept).
    widths : ndarray, int64, shape (n,)
    works : ndarray, float64, shape (n,)
        :func:`frontier_profile` of each.
    """
    P, K = finite.shape
    deg = degree[P:]
    rcm = _cuthill_mckee(finite, inds, degree)
    far, dist = _peripheral(finite, deg)
    # np.lexsort((deg, dist)): by distance, then degree, then index (both sorts stable)
    by_deg = np.argsort(deg, kind="mergesort")
    bfs = by_deg[np.argsort(dist[by_deg], kind="mergesort")]
    starts = np.array([far, np.argmin(deg), rcm[0], rcm[K - 1]], dtype=np.int64)
    n_starts = 0
    for a in range(4):
        dup = False
        for b in range(a):
            if starts[b] == starts[a]:
                dup = True
        if not dup:
            starts[n_starts] = starts[a]
            n_starts += 1
    n = 2 + n_starts
    cands = np.empty((n, K), dtype=np.int64)
    cands[0] = rcm
    cands[1] = bfs
    for a in range(n_starts):
        cands[2 + a] = greedy_order(finite, starts[a])
    widths = np.empty(n, dtype=np.int64)
    works = np.empty(n)
    for a in range(n):
        widths[a], works[a] = frontier_profile(finite, cands[a])
    return cands, widths, works


@jit()
def frontier_ops(finite, order, width):
    """Operations ``(kind, arg, slot)`` of the frontier DP and the row in every slot.

    The compiled :func:`oracle.single._plan_reference._frontier_ops` (see there and
    :mod:`oracle._kernels.dp`): per step ``t``, ``ENTER`` for the rows whose first measurement
    it is (in row order), one ``TRANS``, then ``RETIRE`` for the rows whose last measurement
    it is (in row order); a retiring row's slot is taken over by the row in the highest slot.

    Parameters
    ----------
    finite : ndarray of bool, shape (P, K)
        Gate matrix of one connected component.
    order : ndarray of int64, shape (K,)
        The measurement order.
    width : int
        Its frontier width (:func:`frontier_profile`), the most slots in use.

    Returns
    -------
    ops : ndarray, int64, shape (K + 2P, 3)
    row_in_slot : ndarray, int64, shape (K, width)
        Row in slot ``e`` during the transition of step ``t`` (``-1``: free).
    """
    P, K = finite.shape
    first = np.zeros(P, dtype=np.int64)
    last = np.zeros(P, dtype=np.int64)
    for i in range(P):
        f = -1
        la = K - 1
        for t in range(K):
            if finite[i, order[t]]:
                if f < 0:
                    f = t
                la = t
        # an all-False row: np.argmax gives 0 for both ends (first 0, last K - 1)
        first[i] = f if f >= 0 else 0
        last[i] = la
    ops = np.empty((K + 2 * P, 3), dtype=np.int64)
    row_in_slot = np.full((K, width), -1, dtype=np.int64)
    slot_of = np.full(P, -1, dtype=np.int64)
    slots = np.empty(P, dtype=np.int64)
    n = 0
    k = 0
    for t in range(K):
        for i in range(P):
            if first[i] == t:
                slot_of[i] = n
                ops[k, 0], ops[k, 1], ops[k, 2] = ENTER, i, n
                k += 1
                slots[n] = i
                n += 1
        for e in range(n):
            row_in_slot[t, e] = slots[e]
        ops[k, 0], ops[k, 1], ops[k, 2] = TRANS, t, 0
        k += 1
        for i in range(P):
            if last[i] == t:
                e = slot_of[i]
                ops[k, 0], ops[k, 1], ops[k, 2] = RETIRE, i, e
                k += 1
                n -= 1
                top = slots[n]
                if top != i:
                    slots[e] = top
                    slot_of[top] = e
                slot_of[i] = -1
    return ops[:k], row_in_slot

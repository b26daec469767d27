"""Pure-Python planning of the frontier DP: the specification of :mod:`oracle._kernels.plan`.

:mod:`oracle.single.dp` plans each connected component with the compiled kernels; these
functions, written with NumPy and SciPy (connected components, reverse Cuthill–McKee,
breadth-first distances), are the slow, obviously-correct versions with the same names and
return values, and ``tests/test_oracle_plan.py`` checks that both give the same components,
orders, widths, operation counts and operations, element for element.
"""

from __future__ import annotations

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components, reverse_cuthill_mckee, shortest_path

from .._kernels.dp import ENTER, RETIRE, TRANS

__all__ = ["_components", "_frontier_ops", "_frontier_order", "_greedy_order", "_peripheral",
           "_profile"]


def _components(finite: np.ndarray):
    """Connected components of the bipartite graph rows <-> measurements (finite entries).

    Returns
    -------
    comps : list of (rows, meas)
        Sorted int64 index arrays of every component holding at least one finite entry,
        ordered by their first row.
    isolated : ndarray, int64
        Rows without any finite measurement (they can only be missed or dead).
    """
    P, M = finite.shape
    i, j = np.nonzero(finite)
    graph = coo_matrix((np.ones(i.size), (i, P + j)), shape=(P + M, P + M))
    _, lab = connected_components(graph, directed=False)
    has_meas = finite.any(axis=1)
    isolated = np.flatnonzero(~has_meas)
    comps = []
    seen = set()
    for r in np.flatnonzero(has_meas):
        c = lab[r]
        if c in seen:
            continue
        seen.add(c)
        comps.append((np.flatnonzero(lab[:P] == c), np.flatnonzero(lab[P:] == c)))
    return comps, isolated


def _profile(finite: np.ndarray, order: np.ndarray):
    """Frontier width and operation count of the frontier DP for a measurement order.

    Row ``i`` is active at step ``t`` when its first finite measurement in ``order`` comes
    at or before ``t`` and its last one at or after ``t``; a step with ``n`` active rows and
    ``d`` finite entries costs about ``(3 + d) 2^n``.
    """
    fo = finite[:, order]
    K = fo.shape[1]
    first = np.argmax(fo, axis=1)
    last = K - 1 - np.argmax(fo[:, ::-1], axis=1)
    delta = np.zeros(K + 1, dtype=np.int64)
    np.add.at(delta, first, 1)
    np.add.at(delta, last + 1, -1)
    active = np.cumsum(delta[:K])
    work = float(np.sum((3.0 + fo.sum(axis=0)) * np.exp2(active)))
    return int(active.max(initial=0)), work


def _greedy_order(finite: np.ndarray, start: int) -> np.ndarray:
    """Measurement order grown one measurement at a time from ``start``.

    Next comes the measurement that brings in the fewest new rows, then the one that lets the
    most rows retire (their last remaining measurement), then the one touching the most active
    rows, then the lowest index — a min-degree-like heuristic for a narrow path decomposition.
    """
    P, K = finite.shape
    done = np.zeros(K, dtype=bool)
    entered = np.zeros(P, dtype=bool)
    left = finite.sum(axis=1)
    order = np.empty(K, dtype=np.int64)
    j = int(start)
    for t in range(K):
        order[t] = j
        done[j] = True
        col = finite[:, j]
        entered |= col
        left = left - col
        if t == K - 1:
            break
        cand = np.flatnonzero(~done)
        sub = finite[:, cand]
        new = (sub & ~entered[:, None]).sum(axis=0)
        retire = (sub & (left == 1)[:, None]).sum(axis=0)
        touch = (sub & entered[:, None]).sum(axis=0)
        j = int(cand[np.lexsort((cand, -touch, -retire, new))[0]])
    return order


def _peripheral(graph, P: int, K: int) -> tuple[int, np.ndarray]:
    """A pseudo-peripheral measurement (George & Liu) and the BFS distances from it.

    Starting from a measurement of least degree, jump to the farthest measurement until the
    eccentricity stops growing: a path-like graph is then walked from one of its ends.
    """
    deg = np.diff(graph.indptr)[P:]
    start = int(np.argmin(deg))
    dist = shortest_path(graph, unweighted=True, indices=P + start)[P:]
    for _ in range(8):
        far = int(np.argmax(dist))
        d2 = shortest_path(graph, unweighted=True, indices=P + far)[P:]
        if d2.max() <= dist.max():
            break
        start, dist = far, d2
    return start, dist


def _frontier_order(finite: np.ndarray):
    """A measurement order with a small frontier: the cheapest of a few candidates.

    Candidates are the measurements in reverse Cuthill–McKee order of the bipartite graph, in
    breadth-first order from a pseudo-peripheral measurement, and greedy orders
    (:func:`_greedy_order`) started from that measurement, from a measurement of least degree
    and from both ends of the RCM order. Returns ``(order, width, work)``.
    """
    P, K = finite.shape
    if finite.all():  # complete: every row is active at every step, whatever the order
        order = np.arange(K)
        return (order, *_profile(finite, order))
    i, j = np.nonzero(finite)
    graph = coo_matrix((np.ones(i.size), (i, P + j)), shape=(P + K, P + K)).tocsr()
    graph = graph + graph.T
    rcm = reverse_cuthill_mckee(graph, symmetric_mode=True)
    rcm = rcm[rcm >= P] - P
    far, dist = _peripheral(graph, P, K)
    deg = finite.sum(axis=0)
    cands = [rcm, np.lexsort((deg, dist))]
    for s in dict.fromkeys([far, int(np.argmin(deg)), int(rcm[0]), int(rcm[-1])]):
        cands.append(_greedy_order(finite, s))
    best = None
    for order in cands:
        width, work = _profile(finite, order)
        if best is None or (work, width) < (best[2], best[1]):
            best = (order, width, work)
    return best


def _frontier_ops(finite: np.ndarray, order: np.ndarray, width: int):
    """Operations ``(kind, arg, slot)`` of the frontier DP and the row in every slot.

    Returns
    -------
    ops : ndarray, int64, shape (K + 2P, 3)
        Per step ``t``: ``ENTER`` for the rows whose first measurement it is, one
        ``TRANS``, then ``RETIRE`` for the rows whose last measurement it is (see
        :mod:`oracle._kernels.dp`). A retiring row's slot is taken over by the row in the
        highest slot, exactly as the kernel moves the bits.
    row_in_slot : ndarray, int64, shape (K, width)
        Row in slot ``e`` during the transition of step ``t`` (``-1``: free).
    """
    fo = finite[:, order]
    P, K = fo.shape
    first = np.argmax(fo, axis=1)
    last = K - 1 - np.argmax(fo[:, ::-1], axis=1)
    ops = []
    row_in_slot = np.full((K, width), -1, dtype=np.int64)
    slot_of = np.full(P, -1, dtype=np.int64)
    slots: list[int] = []
    for t in range(K):
        for i in np.flatnonzero(first == t):
            slot_of[i] = len(slots)
            ops.append((ENTER, i, len(slots)))
            slots.append(int(i))
        row_in_slot[t, : len(slots)] = slots
        ops.append((TRANS, t, 0))
        for i in np.flatnonzero(last == t):
            e = int(slot_of[i])
            ops.append((RETIRE, i, e))
            top = slots.pop()
            if top != i:
                slots[e] = top
                slot_of[top] = e
            slot_of[i] = -1
    return np.array(ops, dtype=np.int64).reshape(-1, 3), row_in_slot

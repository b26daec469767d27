"""Exact normalising constant and association marginals by dynamic programming.

Spec §5.2, eqs. (5.1)–(5.2). ``Z`` is a rectangular permanent (#P-hard in general). The
bipartite graph of rows and measurements (an edge where the cost is finite) is first split into
connected components, which are independent: ``Z`` is the product of the components' ``Z`` and
each component's marginals are its own. A component is then solved by whichever of two exact
DPs is cheaper:

* the **subset DP** (spec eq. 5.1): a DP over subsets of the smaller side, stepping through
  the larger side, ``O(max(P, M) min(P, M) 2^min(P, M))`` — any density;
* the **frontier DP**: the same recursion, but the state only records which of the rows that
  are *active* (between their first and last gated measurement in a well-chosen measurement
  order) are already matched, ``O(M F 2^F)`` for a frontier width ``F`` — small on gated
  (sparse) problems however many rows they have.
"""

from __future__ import annotations

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components, reverse_cuthill_mckee, shortest_path

from rankedassign.multisensor import AdaptiveBirthProblem, MultiSensorProblem
from rankedassign.numba_options import interruptible

from . import adaptive_birth, multisensor_dp
from ._kernels.dp import (
    ENTER,
    RETIRE,
    TRANS,
    FrontierDP,
    FrontierMarginals,
    FrontierWork,
    SubsetDP,
    SubsetMarginals,
    SubsetWork,
    dp_marginal_slice,
    dp_terminal,
    dp_total_finish,
    dp_total_slice,
    frontier_layout,
    frontier_marginal_slice,
    frontier_total_slice,
)
from ._kernels.lsap import lsap_kernel
from ._result import check_problem

__all__ = ["log_normalizer", "marginals", "MAX_SUBSET_BITS", "MAX_FRONTIER"]

#: Largest ``min(P, M)`` of a component the subset DP accepts (``2^20`` states, 8 MiB per
#: state vector).
MAX_SUBSET_BITS = 20

#: Largest frontier width of a component the frontier DP accepts (same ``2^20``-state bound).
MAX_FRONTIER = 20

# Components whose subset DP has at most this many bits are solved by it without looking for a
# measurement order: it costs at most ``max(P, M) * 12 * 2^10`` operations.
_SMALL_BITS = 10


# ----------------------------------------------------------------------------- decomposition
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


def _scaled(cm: np.ndarray, c_un: np.ndarray):
    """LSAP-dual rescaling of one component (every factor ``<= 1``, best assignment ``1``).

    Every row either takes a measurement or is *unmatched* (missed or dead, weight
    ``a_i = eta_i(0) + eta_i(-1)``, cost ``c_un_i = -ln a_i``). The ``P x (M + P)`` LSAP on
    ``L = [C_meas | diag(c_un)]`` gives optimal duals ``u, v`` with reduced costs
    ``Cbar = L - u - v >= 0``, ``v <= 0``, ``v = 0`` on unused columns, and
    ``sum(u) + sum(v) = c*`` (the best cost). Every DP factor is then a reduced weight
    ``exp(-Cbar) <= 1`` or a column factor ``exp(v) <= 1``: a used column ``c`` of row ``i``
    contributes ``exp(-Cbar[i, c])``, an unused column ``exp(v[c])``, so a complete
    assignment gets ``w(gamma) exp(c*) <= 1``, the best one exactly 1. No partial product
    that matters can underflow, and the total ``Z exp(c*)`` lies in ``[1, |Gamma|]``.

    Returns
    -------
    w_meas : (P, M) reduced weights of the measurement entries (0 where forbidden)
    e_meas : (M,) factor of a measurement left unused
    w_un : (P,) reduced weight of row ``i`` unmatched
    e_un : (P,) factor of row ``i``'s unmatched column left unused (row ``i`` matched)
    shift : float, ``c*``
    """
    P, M = cm.shape
    rows = np.arange(P)
    L = np.full((P, M + P), np.inf)
    L[:, :M] = cm
    L[rows, M + rows] = c_un
    with interruptible:
        ok, _, u, v = lsap_kernel(L)
    if not ok:  # pragma: no cover - AssignmentProblem guarantees feasibility
        raise AssertionError("merged LSAP infeasible although the problem is feasible")
    shift = float(u.sum() + v.sum())
    with np.errstate(invalid="ignore"):
        red = L - u[:, None] - v[None, :]
    # tiny negative round-off on tight edges: clamp so every factor is <= 1
    wred = np.where(np.isfinite(L), np.exp(-np.maximum(red, 0.0)), 0.0)
    ev = np.exp(v)
    return wred[:, :M], ev[:M], wred[rows, M + rows], ev[M + rows], shift


# ----------------------------------------------------------------------------- subset DP
def _dense_inputs(w_meas, e_meas, w_un, e_un):
    """The generic subset DP of :mod:`oracle._kernels.dp` for one component (spec eq. 5.1)."""
    P, M = w_meas.shape
    if P <= M:
        # states: subsets of rows; steps: measurements
        return (np.ascontiguousarray(w_meas.T), np.ascontiguousarray(e_meas),
                np.ascontiguousarray(e_un), np.ascontiguousarray(w_un), False)
    # states: subsets of measurements; steps: rows (a matched row's unmatched column is unused)
    return (np.ascontiguousarray(w_meas * e_un[:, None]), np.ascontiguousarray(w_un),
            np.ones(M), np.ascontiguousarray(e_meas), True)


#: Vector entries times bits per slice of a DP kernel (tens of milliseconds): the kernels
#: run in slices so that Ctrl-C ends a long DP promptly (:mod:`oracle._kernels.dp`).
_SLICE_WORK = 1 << 24


def _steps_per_slice(bits: int) -> int:
    """Steps (operations) per slice of a DP over ``2^bits`` states (one is ``O(bits 2^bits)``)."""
    return max(1, _SLICE_WORK // ((bits + 1) << bits))


def _dense_total(scaled):
    W, s, tin, tout, _ = _dense_inputs(*scaled)
    K, k = W.shape
    F = np.zeros(1 << k)
    F[0] = 1.0
    G = np.empty(1 << k)
    pos = np.zeros(1, dtype=np.int64)
    budget = _steps_per_slice(k)
    with interruptible:
        while not dp_total_slice(W, s, F, G, pos, budget):
            pass
        return dp_total_finish(F, G, K, tin, tout)


def _dense_marginals(scaled):
    """Scaled total, pair weights ``(P, M)`` and unmatched weights ``(P,)`` of a component."""
    W, s, tin, tout, over_rows = _dense_inputs(*scaled)
    K, k = W.shape
    n = 1 << k
    L = 1
    while L * L < K:
        L += 1
    n_blocks = (K + L - 1) // L if K > 0 else 0
    with interruptible:
        T = dp_terminal(tin, tout, k)
    Bst = np.empty((n_blocks + 1, n))
    Bst[n_blocks] = T
    F = np.zeros(n)
    F[0] = 1.0
    dp = SubsetDP(W, s, T)
    work = SubsetWork(Bst, T.copy(), np.empty(n), F, np.empty(n), np.empty((L + 1, n)))
    pair, stay, term_out = np.zeros((K, k)), np.zeros(K), np.zeros(k)
    out = SubsetMarginals(pair, stay, term_out)
    pos = np.array([0, 0, K - 1], dtype=np.int64)
    budget = _steps_per_slice(k)
    with interruptible:
        while not dp_marginal_slice(dp, work, out, pos, budget):
            pass
    total = Bst[0][0] if K > 0 else T[0]
    if over_rows:
        return total, pair, stay
    return total, pair.T, term_out


def _dense_work(P: int, M: int) -> float:
    """Operation count of the subset DP of a ``P x M`` component (inf beyond its limit)."""
    k = min(P, M)
    return float(max(P, M) * (k + 2) * 2.0**k) if k <= MAX_SUBSET_BITS else np.inf


# ----------------------------------------------------------------------------- frontier DP
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


def _frontier_inputs(finite, order, width, scaled):
    w_meas, e_meas, w_un, e_un = scaled
    ops, row_in_slot = _frontier_ops(finite, order, width)
    r = np.maximum(row_in_slot, 0)
    # a matched row's unmatched column is left unused: fold its factor into the match weight
    W = np.where(row_in_slot >= 0, w_meas[r, order[:, None]] * e_un[r], 0.0)
    return ops, np.ascontiguousarray(W), np.ascontiguousarray(e_meas[order]), \
        np.ascontiguousarray(w_un), row_in_slot


def _frontier_total(finite, order, width, scaled):
    ops, W, s, w_un, _ = _frontier_inputs(finite, order, width, scaled)
    full = 1 << W.shape[1]
    F, G = np.zeros(full), np.zeros(full)
    F[0] = 1.0
    pos = np.zeros(2, dtype=np.int64)
    dp = FrontierDP(ops, W, s, w_un)
    budget = _steps_per_slice(W.shape[1])
    with interruptible:
        while not frontier_total_slice(dp, F, G, pos, budget):
            pass
    return F[0] if ops.shape[0] % 2 == 0 else G[0]


def _frontier_marginals(finite, order, width, scaled):
    """Scaled total, pair weights ``(P, M)`` and unmatched weights ``(P,)`` of a component."""
    ops, W, s, w_un, row_in_slot = _frontier_inputs(finite, order, width, scaled)
    K, n_slots = W.shape
    n_ops = ops.shape[0]
    L = 1
    while L * L < n_ops:
        L += 1
    n_blocks = (n_ops + L - 1) // L
    with interruptible:
        nb, ck_off, blk_max = frontier_layout(ops)
    full = 1 << n_slots
    F, G, B, Bn = np.zeros(full), np.zeros(full), np.zeros(full), np.zeros(full)
    F[0] = B[0] = 1.0
    dp = FrontierDP(ops, W, s, w_un)
    work = FrontierWork(nb, ck_off, np.empty(ck_off[-1]), F, G, np.empty(blk_max),
                        np.zeros(L + 1, dtype=np.int64), B, Bn)
    pair, unmatched, acc = np.zeros((K, n_slots)), np.zeros(w_un.shape[0]), np.zeros(1)
    out = FrontierMarginals(pair, unmatched, acc)
    pos = np.array([0, n_blocks - 1, 0, 0], dtype=np.int64)
    budget = _steps_per_slice(n_slots)
    with interruptible:
        while not frontier_marginal_slice(dp, work, out, pos, budget):
            pass
    total = acc[0]
    pm = np.zeros(finite.shape)
    t, e = np.nonzero(row_in_slot >= 0)
    pm[row_in_slot[t, e], order[t]] = pair[t, e]
    return total, pm, unmatched


# ----------------------------------------------------------------------------- dispatch
def _plan(finite: np.ndarray, method: str):
    """Choose the DP of one component: ``("dense", None)`` or ``("frontier", (order, F))``.

    ``method="auto"`` takes the cheaper of the two by operation count among those within
    their limits; ``"dense"`` / ``"frontier"`` force one (for testing).
    """
    P, M = finite.shape
    k = min(P, M)
    dense = _dense_work(P, M)
    if method == "dense" or (method == "auto" and k <= _SMALL_BITS):
        if dense < np.inf:
            return "dense", None
        raise ValueError(
            f"problem too large for the exact subset DP: min(P, M) = min({P}, {M}) = {k} "
            f"> {MAX_SUBSET_BITS} in a connected component"
        )
    order, width, work = _frontier_order(finite)
    if width <= MAX_FRONTIER and (method == "frontier" or work < dense):
        return "frontier", (order, width)
    if method == "auto" and dense < np.inf:
        return "dense", None
    if method == "frontier":
        raise ValueError(f"frontier width {width} > {MAX_FRONTIER} in a connected component")
    raise ValueError(
        f"problem too large for the exact subset DP: min(P, M) = min({P}, {M}) = {k} "
        f"> {MAX_SUBSET_BITS} in a connected component, and for the frontier DP: frontier "
        f"width {width} > {MAX_FRONTIER} (limit 2^{MAX_FRONTIER} states); use enumeration "
        "or Murty bounds instead"
    )


def _solve(problem, *, with_marginals: bool, method: str = "auto"):
    """``ln Z`` and (optionally) the marginals, component by component."""
    P, M = problem.n_rows, problem.n_meas
    cc = problem.compact_cost
    finite = np.isfinite(cc[:, :M])
    # cost of the merged unmatched option: -ln(exp(-C_miss) + exp(-C_dead)) = -ln a_i
    c_un = -np.logaddexp(-cc[:, M], -cc[:, M + 1])
    comps, isolated = _components(finite)
    plans = [_plan(finite[np.ix_(rows, meas)], method) for rows, meas in comps]
    log_z = 0.0
    pm = np.zeros((P, M)) if with_marginals else None
    unmatched = np.zeros(P)
    for (rows, meas), (kind, arg) in zip(comps, plans, strict=True):
        scaled = _scaled(cc[np.ix_(rows, meas)], c_un[rows])
        shift, scaled = scaled[4], scaled[:4]
        fin = finite[np.ix_(rows, meas)]
        if with_marginals:
            if kind == "dense":
                total, pair, un = _dense_marginals(scaled)
            else:
                total, pair, un = _frontier_marginals(fin, *arg, scaled)
            pm[np.ix_(rows, meas)] = pair
            unmatched[rows] = un
        elif kind == "dense":
            total = _dense_total(scaled)
        else:
            total = _frontier_total(fin, *arg, scaled)
        log_z += float(np.log(total)) - shift
    # a row without any finite measurement is missed or dead with probability 1: factor a_i
    log_z -= float(np.sum(c_un[isolated]))
    unmatched[isolated] = 1.0
    return log_z, pm, unmatched, c_un


# ----------------------------------------------------------------------------- public API
def log_normalizer(problem) -> float:
    """Exact ``ln Z``, ``Z = sum over feasible gamma of w(gamma)`` (spec eqs. 1.6, 5.1).

    Parameters
    ----------
    problem : AssignmentProblem or MultiSensorProblem
        The ``P x (M + 2P)`` problem. Every connected component of its row–measurement graph
        must fit one of the two DPs (see Notes). A multi-sensor problem goes to
        :func:`oracle.multisensor_dp.log_normalizer`.

    Returns
    -------
    float
        ``ln Z = ln sum_Gamma exp(-cost(gamma))``; ``0.0`` for ``P = 0``.

    Raises
    ------
    TypeError
        If ``problem`` is not an :class:`~rankedassign.AssignmentProblem`.
    ValueError
        If a connected component has both ``min(P_c, M_c) > 20`` and a frontier width
        ``> 20`` (the message names both and the limits).

    Notes
    -----
    *Decomposition.* Rows and measurements joined by a finite cost form a bipartite graph;
    its connected components share nothing, so ``Z = prod_c Z_c * prod_i a_i`` over the
    components and the rows without any finite measurement (``a_i = eta_i(0) + eta_i(-1)``).

    *Subset DP* (spec eq. 5.1), over subsets ``S`` of the component's rows matched so far,
    one measurement per step::

        f_j(S) = f_{j-1}(S) + sum_{i in S} eta_i(j) f_{j-1}(S \\ {i})
        Z_c    = sum_S f_M(S) prod_{i not in S} a_i

    or the transposed DP over subsets of measurements, row by row, when ``M_c < P_c``.
    Time ``O(max(P_c, M_c) min(P_c, M_c) 2^min(P_c, M_c))``, memory ``O(2^min(P_c, M_c))``.

    *Frontier DP*, for sparse (gated) components. The measurements are put in an order with a
    narrow *frontier* (the cheapest of reverse Cuthill–McKee and a few greedy orders). A row is
    *active* from its first to its last finite measurement in that order, and the state is
    the subset of *active* rows already matched: a row enters unmatched at its first
    measurement, each measurement is left unused or taken by one active unmatched row with a
    finite entry, and a row retires after its last measurement, times ``a_i`` if still
    unmatched. Time ``O(M_c F 2^F)`` with ``F`` the largest number of rows active at once
    (the frontier width), memory ``O(2^F)``.

    Each component uses whichever DP is cheaper by operation count among those within their
    limits (``min(P_c, M_c) <= 20``, ``F <= 20``, i.e. at most ``2^20`` states); the problem
    is refused only when neither fits. On the paper's gated tracking problems
    (``P ~ 22``, ``M ~ 60``) ``F`` is about 10 and a call takes milliseconds.

    Weights are rescaled by the optimal duals of an LSAP on ``[C_meas | diag(-ln a)]`` so that
    every factor is at most one and the best assignment has weight exactly one: nothing
    under- or overflows, whatever the range of the costs, and ``ln Z_c = ln Z_c,scaled - c*_c``
    with ``c*_c`` the component's minimum cost.

    References
    ----------
    .. [1] B.-N. Vo, B.-T. Vo, H. G. Hoang, "An Efficient Implementation of the Generalized
       Labeled Multi-Bernoulli Filter", IEEE Trans. Signal Process. 65(8), 2017.
    .. [2] A. Trezza, D. J. Bucci Jr., P. K. Varshney, "On Gibbs Sampling Architecture for
       Labeled Random Finite Sets Multi-Object Tracking", arXiv:2306.15135, 2023.
    .. [3] K. G. Murty, "An Algorithm for Ranking all the Assignments in Order of Increasing
       Cost", Operations Research 16(3), 1968 (the LSAP dual view used for the scaling).
    .. [4] M. L. Miller, H. S. Stone, I. J. Cox, "Optimizing Murty's Ranked Assignment
       Method", IEEE Trans. Aerosp. Electron. Syst. 33(3), 1997.
    .. [5] E. Cuthill, J. McKee, "Reducing the Bandwidth of Sparse Symmetric Matrices",
       Proc. 24th ACM National Conference, 1969 (the measurement order).

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign import AssignmentProblem, synthetic
    >>> from oracle import log_normalizer
    >>> p = AssignmentProblem.from_eta([[2.0]], [0.5], [0.25])   # Z = 2 + 0.5 + 0.25
    >>> round(float(np.exp(log_normalizer(p))), 12)
    2.75
    >>> u = synthetic.uniform()          # 76 848 assignments, each of cost 4 * 0.5
    >>> round(float(np.exp(log_normalizer(u) + 4 * 0.5)), 6)
    76848.0

    A banded problem with 30 rows (beyond the subset DP; at most 2 rows active at once):

    >>> eta = np.zeros((30, 80))
    >>> for i in range(30):
    ...     eta[i, 2 * i: 2 * i + 4] = 1.0
    >>> band = AssignmentProblem.from_eta(eta, np.ones(30), np.zeros(30))
    >>> round(log_normalizer(band), 6)
    45.630949
    """
    if isinstance(problem, MultiSensorProblem):
        return multisensor_dp.log_normalizer(problem)
    if isinstance(problem, AdaptiveBirthProblem):
        return adaptive_birth.log_normalizer(problem)
    check_problem(problem)
    if problem.n_rows == 0:
        return 0.0
    return _solve(problem, with_marginals=False)[0]


def marginals(problem) -> np.ndarray:
    """Exact association probabilities of every row (spec eq. 5.2).

    Parameters
    ----------
    problem : AssignmentProblem or MultiSensorProblem
        The ``P x (M + 2P)`` problem; same size limit as :func:`log_normalizer`. A
        multi-sensor problem goes to :func:`oracle.multisensor_dp.marginals` (which returns a
        :class:`~oracle.multisensor_dp.MultiSensorMarginals`).

    Returns
    -------
    ndarray, float64, shape (P, M + 2)
        ``[:, j]`` for ``j < M``: ``P(gamma_i = j + 1)``, row ``i`` takes measurement ``j``;
        ``[:, M]``: ``P(gamma_i = 0)`` (missed); ``[:, M + 1]``: ``P(gamma_i = -1)`` (dead).
        Each row sums to one; each measurement column sums to at most one.

    Raises
    ------
    TypeError
        If ``problem`` is not an :class:`~rankedassign.AssignmentProblem`.
    ValueError
        If a connected component fits neither DP (see :func:`log_normalizer`).

    Notes
    -----
    ``P(gamma_i = j) = eta_i(j) Z_{-i,-j} / Z`` and
    ``P(gamma_i in {0, -1}) = (eta_i(0) + eta_i(-1)) Z_{-i} / Z``. Components are independent,
    so each is solved on its own (a row without finite measurements is unmatched with
    probability one). Rather than one DP per pair, one forward and one backward pass of the
    component's DP (subset or frontier, chosen as in :func:`log_normalizer`) give every
    transition's weight at once: the weight through "row ``i`` takes measurement ``j``" is
    ``sum_{S not containing i} F(S) eta_i(j) B(S | {i})`` at that measurement's step, and the
    weight through "row ``i`` unmatched" is read off where it leaves the state (the terminal
    weights of the subset DP, the retirement of the frontier DP). Forward or backward vectors
    are checkpointed every ``sqrt(K)`` steps, so memory stays ``O(sqrt(K) 2^k)``
    (``k = min(P_c, M_c)`` or ``F``). The unmatched weight of a row is split between missed
    and dead in proportion ``eta_i(0) : eta_i(-1)``. Rows are normalised by their own total,
    which equals ``Z_c`` in exact arithmetic. Unreachable measurements (all ``+inf``) get
    probability 0. Time about four times that of :func:`log_normalizer`.

    References
    ----------
    .. [1] B.-N. Vo, B.-T. Vo, H. G. Hoang, "An Efficient Implementation of the Generalized
       Labeled Multi-Bernoulli Filter", IEEE Trans. Signal Process. 65(8), 2017.
    .. [2] S. Reuter, B.-T. Vo, B.-N. Vo, K. Dietmayer, "The Labeled Multi-Bernoulli Filter",
       IEEE Trans. Signal Process. 62(12), 2014.
    .. [3] A. Trezza, D. J. Bucci Jr., P. K. Varshney, "On Gibbs Sampling Architecture for
       Labeled Random Finite Sets Multi-Object Tracking", arXiv:2306.15135, 2023.

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign import AssignmentProblem
    >>> from oracle import marginals
    >>> p = AssignmentProblem.from_eta([[2.0]], [0.5], [0.25])
    >>> marginals(p).round(6).tolist()       # [z1, missed, dead] = [2, 0.5, 0.25] / 2.75
    [[0.727273, 0.181818, 0.090909]]

    Two rows competing for one measurement, and a third row gating nothing:

    >>> q = AssignmentProblem.from_eta([[3.0], [1.0], [0.0]], [1.0, 1.0, 1.0], [0.0, 0.0, 3.0])
    >>> marginals(q).round(4).tolist()       # Z_c = 3 + 1 + 1 = 5 for rows 0 and 1
    [[0.6, 0.4, 0.0], [0.2, 0.8, 0.0], [0.0, 0.25, 0.75]]
    """
    if isinstance(problem, MultiSensorProblem):
        return multisensor_dp.marginals(problem)
    if isinstance(problem, AdaptiveBirthProblem):
        return adaptive_birth.marginals(problem)
    check_problem(problem)
    P, M = problem.n_rows, problem.n_meas
    if P == 0:
        return np.zeros((0, M + 2))
    return _assemble(problem, *_solve(problem, with_marginals=True)[1:])


def _assemble(problem, pm, unmatched, c_un) -> np.ndarray:
    """Marginals ``(P, M + 2)`` from the pair and unmatched weights, rows normalised."""
    P, M = problem.n_rows, problem.n_meas
    cc = problem.compact_cost
    out = np.zeros((P, M + 2))
    out[:, :M] = pm
    with np.errstate(invalid="ignore"):
        # share of "missed" within the unmatched option: eta_i(0) / (eta_i(0) + eta_i(-1))
        f_miss = np.where(np.isfinite(cc[:, M]), np.exp(c_un - cc[:, M]), 0.0)
        f_dead = np.where(np.isfinite(cc[:, M + 1]), np.exp(c_un - cc[:, M + 1]), 0.0)
    out[:, M] = unmatched * f_miss
    out[:, M + 1] = unmatched * f_dead
    out /= out.sum(axis=1, keepdims=True)
    return out


def _log_normalizer(problem, method: str) -> float:
    """:func:`log_normalizer` with the DP forced (``"auto"``, ``"dense"``, ``"frontier"``)."""
    if problem.n_rows == 0:
        return 0.0
    return _solve(problem, with_marginals=False, method=method)[0]


def _marginals(problem, method: str) -> np.ndarray:
    """:func:`marginals` with the DP forced (``"auto"``, ``"dense"``, ``"frontier"``)."""
    if problem.n_rows == 0:
        return np.zeros((0, problem.n_meas + 2))
    return _assemble(problem, *_solve(problem, with_marginals=True, method=method)[1:])

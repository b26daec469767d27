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

from rankedassign.numba_options import interruptible

from .._kernels.dp import (
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
from .._kernels.lsap import lsap_kernel
from .._kernels.plan import (
    bipartite_components,
    frontier_candidates,
    frontier_ops,
    frontier_profile,
)
from .._result import check_problem
from . import _plan_reference

__all__ = ["log_normalizer", "marginals", "compact_log_normalizer", "PlanCache",
           "MAX_SUBSET_BITS", "MAX_FRONTIER"]

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

    Notes
    -----
    The flood fill is :func:`oracle._kernels.plan.bipartite_components`; the same result as
    :func:`oracle.single._plan_reference._components` (SciPy's ``connected_components``).
    """
    with interruptible:
        row_comp, meas_comp, n = bipartite_components(np.ascontiguousarray(finite, dtype=bool))
    comps = [(np.flatnonzero(row_comp == c), np.flatnonzero(meas_comp == c)) for c in range(n)]
    return comps, np.flatnonzero(row_comp < 0)


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
    # Only the measurement block and the diagonal of the unmatched block are ever read: their
    # reduced costs alone, each as (L - u) - v. A forbidden entry has a reduced cost of +inf
    # (u and v are finite), so exp(-inf) = 0 is its weight without a mask; tiny negative
    # round-off on tight edges is clamped so that every factor is <= 1.
    v_un = v[M + rows]
    w_meas = np.exp(-np.maximum(cm - u[:, None] - v[None, :M], 0.0))
    w_un = np.exp(-np.maximum(c_un - u - v_un, 0.0))
    return w_meas, np.exp(v[:M]), w_un, np.exp(v_un), shift


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
    finite = np.ascontiguousarray(finite, dtype=bool)
    with interruptible:
        width, work = frontier_profile(finite, np.ascontiguousarray(order, dtype=np.int64))
    if work >= _EXACT_SUM:
        # beyond 2^53 the kernel's sum in step order may round differently from NumPy's
        # pairwise sum, which decided between orders before: take NumPy's
        return _plan_reference._profile(finite, order)
    return int(width), float(work)


#: Below this, a sum of integer-valued float64 terms is exact in any order.
_EXACT_SUM = 2.0**53


def _frontier_order(finite: np.ndarray):
    """A measurement order with a small frontier: the cheapest of a few candidates.

    Candidates are the measurements in reverse Cuthill–McKee order of the bipartite graph, in
    breadth-first order from a pseudo-peripheral measurement, and greedy orders started from
    that measurement, from a measurement of least degree and from both ends of the RCM order
    (:func:`oracle._kernels.plan.frontier_candidates`, compiled; the pure-Python
    specification is :func:`oracle.single._plan_reference._frontier_order`, with the same
    result). Returns ``(order, width, work)``.
    """
    finite = np.ascontiguousarray(finite, dtype=bool)
    P, K = finite.shape
    if finite.all():  # complete: every row is active at every step, whatever the order
        order = np.arange(K)
        return (order, *_profile(finite, order))
    degree = np.concatenate([finite.sum(axis=1), finite.sum(axis=0)])
    # SciPy's reverse_cuthill_mckee starts from np.argsort of its int32 degrees; NumPy's
    # sort breaks the ties, so the start is taken from the same call
    inds = np.argsort(degree.astype(np.int32)).astype(np.int64)
    with interruptible:
        cands, widths, works = frontier_candidates(finite, inds, degree)
    best = None
    for order, width, work in zip(cands, widths.tolist(), works.tolist(), strict=True):
        if work >= _EXACT_SUM:
            width, work = _plan_reference._profile(finite, order)
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

    Notes
    -----
    Compiled as :func:`oracle._kernels.plan.frontier_ops`; ``width`` must be the order's
    frontier width (:func:`_profile`).
    """
    with interruptible:
        return frontier_ops(np.ascontiguousarray(finite, dtype=bool),
                            np.ascontiguousarray(order, dtype=np.int64), int(width))


def _frontier_inputs(finite, order, width, scaled, ops=None):
    w_meas, e_meas, w_un, e_un = scaled
    if ops is None:
        ops = _frontier_ops(finite, order, width)
    ops, row_in_slot = ops
    r = np.maximum(row_in_slot, 0)
    # a matched row's unmatched column is left unused: fold its factor into the match weight
    W = np.where(row_in_slot >= 0, w_meas[r, order[:, None]] * e_un[r], 0.0)
    return ops, np.ascontiguousarray(W), np.ascontiguousarray(e_meas[order]), \
        np.ascontiguousarray(w_un), row_in_slot


def _frontier_total(finite, order, width, scaled, ops=None):
    ops, W, s, w_un, _ = _frontier_inputs(finite, order, width, scaled, ops)
    return _frontier_run(ops, W, s, w_un)


def _frontier_run(ops, W, s, w_un):
    """The frontier DP's total from its operation list and weights (:func:`_frontier_inputs`)."""
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
def _plan(finite: np.ndarray, method: str, small_bits: int = _SMALL_BITS):
    """Choose the DP of one component: ``("dense", None)`` or ``("frontier", (order, F))``.

    ``method="auto"`` takes the cheaper of the two by operation count among those within
    their limits, except that a component of at most ``small_bits`` bits goes to the subset
    DP without a search for a measurement order (which would cost more than it saves, unless
    the plan is reused: :class:`PlanCache`); ``"dense"`` / ``"frontier"`` force one (for
    testing).
    """
    P, M = finite.shape
    k = min(P, M)
    dense = _dense_work(P, M)
    if method == "dense" or (method == "auto" and k <= small_bits):
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


class PlanCache:
    """DP plans of single-sensor problems, by gate pattern, for many calls of
    :func:`compact_log_normalizer`.

    A plan (the connected components, the DP of each, the frontier DP's measurement order and
    operation list) depends only on which entries are finite, not on their values, and its
    search for a measurement order (:func:`_frontier_order`) costs more than the DP itself on
    the gated problems of a tracking scan. A δ-GLMB scan's components share most of their
    tracks, so their problems repeat a few gate patterns many times, and each is planned once.
    A pattern met a second time also has its small components (which
    :func:`oracle.log_normalizer` sends to the subset DP without a search) planned in full, so
    that each component gets the cheaper DP by operation count. A planned problem is scaled
    by its rows' least costs (:func:`_row_scaled`) rather than by an LSAP's duals, the LSAP's
    scaling kept as the fallback near underflow: ``ln Z`` then equals that of the unplanned
    call to round-off, not bit for bit.

    Parameters
    ----------
    maxsize : int, optional
        Patterns kept (default 4096, each a few kilobytes); the oldest is dropped first.

    Examples
    --------
    >>> import numpy as np
    >>> from oracle.single.dp import PlanCache, compact_log_normalizer
    >>> plans = PlanCache()
    >>> cc = np.array([[0.0, np.inf, 1.0, 2.0], [0.5, 0.5, 1.0, np.inf]])
    >>> a = compact_log_normalizer(cc, plans=plans)
    >>> b = compact_log_normalizer(cc + 1.0, plans=plans)     # same pattern: planned once
    >>> len(plans), plans.hits, round(a - b, 12)
    (1, 1, 2.0)
    """

    def __init__(self, maxsize: int = 4096):
        if isinstance(maxsize, bool) or not isinstance(maxsize, int) or maxsize < 1:
            raise ValueError(f"maxsize must be a positive int, got {maxsize!r}")
        self.maxsize = maxsize
        self.hits = 0
        self._plans: dict = {}

    def __len__(self) -> int:
        return len(self._plans)

    def _layout(self, finite: np.ndarray, method: str):
        # the key is exact: shape and every bit of the pattern
        key = (method, finite.shape, np.packbits(finite).tobytes())
        entry = self._plans.get(key)
        if entry is None:
            # first use: a small component goes to the subset DP unplanned, as without a cache
            layout = _layout(finite, method, with_ops=True)
            if len(self._plans) >= self.maxsize:
                del self._plans[next(iter(self._plans))]
            self._plans[key] = (layout, False)
            return layout
        self.hits += 1
        layout, searched = entry
        if not searched:
            # second use: the pattern recurs, so the search for a measurement order that the
            # small components skipped pays for itself (on δ-GLMB groups of 5 to 10 rows and
            # some 50 measurements the frontier DP is several times cheaper than the subset
            # DP); it is made once
            if any(kind == "dense" for kind, _ in layout[2]):
                layout = _layout(finite, method, with_ops=True, small_bits=-1)
            self._plans[key] = (layout, True)
        return layout


def _layout(finite: np.ndarray, method: str, *, with_ops: bool = False,
            small_bits: int = _SMALL_BITS):
    """Components, isolated rows and the plan of every component (``_plan``); with
    ``with_ops`` a frontier plan also carries its operation list (``_frontier_ops``)."""
    comps, isolated = _components(finite)
    plans = []
    for rows, meas in comps:
        fin = finite[np.ix_(rows, meas)]
        kind, arg = _plan(fin, method, small_bits)
        if kind == "frontier" and with_ops:
            ops = _frontier_ops(fin, *arg)
            row_in_slot = ops[1]
            # what _frontier_inputs derives from the plan on every call, kept with it
            arg = (*arg, ops, np.maximum(row_in_slot, 0), row_in_slot >= 0,
                   np.ones(row_in_slot.shape[0]))
        plans.append((kind, arg))
    return comps, isolated, plans


#: A total scaled by the rows' least costs below this is recomputed with the LSAP's scaling.
_ROW_SCALED_FLOOR = 1e-200


def _row_scaled(cm: np.ndarray, c_un: np.ndarray):
    """Scaling by each row's least cost: ``(w_meas, w_un)`` as in :func:`_scaled`, and the
    shift.

    Every factor is at most one (each row's best option exactly one) and there is no column
    factor (the unused measurements' and unmatched columns' factors of :func:`_scaled` are all
    one), so it takes a few array operations where :func:`_scaled` solves an LSAP. Unlike the
    LSAP's, the best *assignment* is not scaled to one: when rows compete for the same
    measurement the total can be far below one, and :func:`_planned_total` falls back to
    :func:`_scaled` when it comes near underflow (:data:`_ROW_SCALED_FLOOR`).
    """
    m = np.minimum(cm.min(axis=1, initial=np.inf), c_un)
    # exp(-(c - m)) <= 1; a forbidden entry's exp(-inf) = 0
    return np.exp(m[:, None] - cm), np.exp(m - c_un), float(m.sum())


def _planned_total(cm, c_un, kind, arg):
    """Scaled total and shift of one planned component (:class:`PlanCache`): rows scaled by
    their least cost, by the LSAP's duals only when that total is near underflow."""
    w_meas, w_un, shift = _row_scaled(cm, c_un)
    if kind == "dense":
        total = _dense_total((w_meas, np.ones(w_meas.shape[1]), w_un, np.ones(w_un.size)))
    else:
        order, width, ops, slot_row, slot_used, ones = arg
        # _frontier_inputs without its unit factors: the weight of the row in each slot
        W = np.where(slot_used, w_meas[slot_row, order[:, None]], 0.0)
        total = _frontier_run(ops[0], W, ones, w_un)
    if not total > _ROW_SCALED_FLOOR:
        # the LSAP's duals scale the best assignment to exactly one: nothing underflows
        out = _scaled(cm, c_un)
        shift = out[4]
        if kind == "dense":
            total = _dense_total(out[:4])
        else:
            total = _frontier_total(None, arg[0], arg[1], out[:4], arg[2])
    return total, shift


def _solve(problem, *, with_marginals: bool, method: str = "auto"):
    """``ln Z`` and (optionally) the marginals, component by component."""
    return _solve_compact(problem.compact_cost, with_marginals=with_marginals, method=method)


def _solve_compact(cc: np.ndarray, *, with_marginals: bool, method: str = "auto",
                   plans: PlanCache | None = None):
    """:func:`_solve` on the compact cost ``(P, M + 2)``; ``plans`` (totals only) reuses the
    plans of earlier problems with the same gate pattern."""
    P, M = cc.shape[0], cc.shape[1] - 2
    finite = np.isfinite(cc[:, :M])
    # cost of the merged unmatched option: -ln(exp(-C_miss) + exp(-C_dead)) = -ln a_i
    c_un = -np.logaddexp(-cc[:, M], -cc[:, M + 1])
    if plans is not None and not with_marginals:
        comps, isolated, comp_plans = plans._layout(finite, method)
    else:
        comps, isolated, comp_plans = _layout(finite, method)
    log_z = 0.0
    if plans is not None and not with_marginals:
        for (rows, meas), (kind, arg) in zip(comps, comp_plans, strict=True):
            whole = rows.size == P and meas.size == M  # one component: no copies by index
            cm = cc[:, :M] if whole else cc[np.ix_(rows, meas)]
            total, shift = _planned_total(cm, c_un if whole else c_un[rows], kind, arg)
            log_z += float(np.log(total)) - shift
        if isolated.size:
            log_z -= float(np.sum(c_un[isolated]))
        return log_z, None, None, c_un
    pm = np.zeros((P, M)) if with_marginals else None
    unmatched = np.zeros(P)
    for (rows, meas), (kind, arg) in zip(comps, comp_plans, strict=True):
        whole = rows.size == P and meas.size == M  # one component: no copies by index
        cm = cc[:, :M] if whole else cc[np.ix_(rows, meas)]
        scaled = _scaled(cm, c_un[rows])
        shift, scaled = scaled[4], scaled[:4]
        if with_marginals:
            fin = finite[np.ix_(rows, meas)]
            if kind == "dense":
                total, pair, un = _dense_marginals(scaled)
            else:
                total, pair, un = _frontier_marginals(fin, *arg, scaled)
            pm[np.ix_(rows, meas)] = pair
            unmatched[rows] = un
        elif kind == "dense":
            total = _dense_total(scaled)
        else:
            total = _frontier_total(finite[np.ix_(rows, meas)], *arg, scaled)
        log_z += float(np.log(total)) - shift
    # a row without any finite measurement is missed or dead with probability 1: factor a_i
    log_z -= float(np.sum(c_un[isolated]))
    unmatched[isolated] = 1.0
    return log_z, pm, unmatched, c_un


# ----------------------------------------------------------------------------- public API
def log_normalizer(problem) -> float:
    """The single-sensor case of :func:`oracle.log_normalizer` (see there).

    Parameters
    ----------
    problem : AssignmentProblem

    Returns
    -------
    float
    """
    check_problem(problem)
    if problem.n_rows == 0:
        return 0.0
    return _solve(problem, with_marginals=False)[0]


def compact_log_normalizer(cost, *, plans: PlanCache | None = None) -> float:
    """:func:`oracle.log_normalizer` of a problem given by its compact cost matrix.

    The entry point for many small normalisers (the δ-GLMB filter's retained mass asks for
    hundreds a scan): no :class:`~rankedassign.AssignmentProblem` is built, and ``plans``
    reuses the DP plans of earlier problems with the same gate pattern.

    Parameters
    ----------
    cost : array_like of float64, shape (P, M + 2)
        ``-ln eta`` in compact columns ``[measurements | missed | dead]``
        (:attr:`~rankedassign.AssignmentProblem.compact_cost`); ``+inf`` = forbidden. Every
        row needs a finite missed or dead cost (so that the problem is feasible).
    plans : PlanCache or None, optional
        Plans by gate pattern, shared across calls (default None: plan this problem alone).

    Returns
    -------
    float
        ``ln Z``; ``0.0`` for ``P = 0``. Without ``plans``, bit for bit that of
        ``oracle.log_normalizer(AssignmentProblem.from_cost(full))`` for the same problem in
        the paper's layout; with ``plans``, equal to it to round-off (see
        :class:`PlanCache`).

    Raises
    ------
    ValueError
        On a wrong shape, NaN or ``-inf``, a row whose missed and dead costs are both
        ``+inf``, or a component beyond both DPs (as :func:`oracle.log_normalizer`).

    Examples
    --------
    >>> import numpy as np
    >>> from oracle.single.dp import compact_log_normalizer
    >>> cc = -np.log([[2.0, 0.5, 0.25]])                  # Z = 2 + 0.5 + 0.25
    >>> round(float(np.exp(compact_log_normalizer(cc))), 12)
    2.75
    """
    cc = np.asarray(cost, dtype=np.float64)
    if cc.ndim != 2 or cc.shape[1] < 2:
        raise ValueError(
            f"compact cost must be 2-D with shape (P, M + 2), got shape {cc.shape}")
    if not (cc > -np.inf).all():  # one pass for both (NaN compares False)
        if np.isnan(cc).any():
            raise ValueError("compact cost contains NaN")
        raise ValueError("compact cost contains -inf; a cost must be finite or +inf")
    M = cc.shape[1] - 2
    bad = (cc[:, M:] == np.inf).all(axis=1)
    if bad.any():
        raise ValueError(
            f"row {int(np.flatnonzero(bad)[0])} has neither a finite missed nor a finite "
            "dead cost")
    if plans is not None and not isinstance(plans, PlanCache):
        raise TypeError(f"plans must be a PlanCache or None, got {type(plans).__name__}")
    if cc.shape[0] == 0:
        return 0.0
    return _solve_compact(cc, with_marginals=False, plans=plans)[0]


def marginals(problem) -> np.ndarray:
    """The single-sensor case of :func:`oracle.marginals` (see there).

    Parameters
    ----------
    problem : AssignmentProblem

    Returns
    -------
    ndarray, shape (P, M + 2)
    """
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

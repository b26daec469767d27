"""Murty's k-best ranked assignment on the ``P x (M + 2P)`` matrix (spec §5.1)."""

from __future__ import annotations

import heapq

import numpy as np

from rankedassign.numba_options import interruptible
from rankedassign.validation import MAX_WORK_BYTES, check_int, format_bytes

from .._kernels.murty import (
    DONE,
    FULL,
    grow_search,
    murty_compact_start,
    murty_slice,
    search_output,
)
from .._result import Ranked, check_problem, ranked

__all__ = ["murty"]

_BACKENDS = ("numba", "scipy")


def _k_cap(problem, k: int) -> int:
    """``min(k, |Gamma|)`` when the count is cheap, else ``k`` (caps the output buffer)."""
    try:
        return min(k, problem.n_feasible())
    except ValueError:
        return k


def _bytes_per_assignment(P: int) -> int:
    """Bytes the compiled search keeps for each assignment it reports (a lower bound).

    Per reported assignment :func:`._kernels.murty.murty_compact_kernel` holds at least its solved
    node's solution, row duals and column duals (``3 P`` numbers, and 3 more: the free-column
    potential, the cost and its rounding scale), the node itself (key, solution slot, parent,
    forbidden-pair list, heap key and id: 6, and the ``ceil(P / 64)`` words of its fixed rows),
    its forbidden pair (3), its output slot, cost and entry in the max-heap of solved costs (3)
    and its row of the output (``P``): ``8 (4 P + ceil(P / 64) + 15)`` bytes. Children that are
    never reported and the doubling of the arrays come on top.
    """
    return 8 * (4 * P + (P + 63) // 64 + 15)


def _check_k_memory(problem, k: int) -> None:
    """Refuse a ``k`` whose assignments the search could not hold in :data:`MAX_WORK_BYTES`.

    Only when ``k`` is that large is ``|Gamma|`` asked for (when it is cheap to count): ``k``
    above it is fine (every assignment is returned), as long as all of them fit.
    """
    P = problem.n_rows
    per = _bytes_per_assignment(P)
    if k * per <= MAX_WORK_BYTES:
        return
    try:
        count = problem.n_feasible()
    except ValueError:  # too costly to count exactly: k it is
        count = None
    if count is not None and count * per <= MAX_WORK_BYTES:
        return
    n = k if count is None else min(k, count)
    known = "" if count is None else f"; the problem has {count} feasible assignments"
    raise ValueError(
        f"k = {k} is too large: {n} assignments need at least {format_bytes(n * per)} of "
        f"Murty work arrays ({per} bytes each for P = {P} rows), more than the limit of "
        f"{format_bytes(MAX_WORK_BYTES)} (rankedassign.validation.MAX_WORK_BYTES){known}"
    )


def _lsap(C: np.ndarray):
    """SciPy LSAP; ``None`` when the subproblem is infeasible."""
    from scipy.optimize import linear_sum_assignment  # (0.3 s to import: on the first call)

    try:
        _, cols = linear_sum_assignment(C)
    except ValueError:  # "cost matrix is infeasible"
        return None
    return cols.astype(np.int64)


def _murty_scipy(problem, k: int) -> np.ndarray:
    """The plain algorithm of spec §5.1: one full LSAP per child, rows in natural order.

    The node's matrix carries its fixings (row ``r`` may only take ``s[r]``, and no other row
    may take that column) and its forbidden pairs as ``+inf``; the missed and dead columns
    are treated as the distinct, row-specific columns they are.
    """
    C = np.array(problem.cost)
    P = problem.n_rows
    s = _lsap(C)
    out = []
    if s is None:  # pragma: no cover - AssignmentProblem guarantees feasibility
        return np.zeros((0, P), dtype=np.int64)
    count = 0  # insertion counter: deterministic order among equal costs
    heap = [(float(problem.cost_of(s)), count, s, C, np.zeros(P, dtype=bool))]
    while heap and len(out) < k:
        _, _, s, Cn, fixed = heapq.heappop(heap)
        out.append(s)
        if len(out) == k:
            break
        Cw = Cn.copy()
        fx = fixed.copy()
        for r in range(P):
            if fx[r]:
                continue
            Cx = Cw.copy()
            Cx[r, s[r]] = np.inf  # child: forbid (r, s[r]), keep the earlier fixings
            sx = _lsap(Cx)
            if sx is not None:
                count += 1
                heapq.heappush(heap, (float(problem.cost_of(sx)), count, sx, Cx, fx.copy()))
            # fix (r, s[r]) for the later children
            keep = Cw[r, s[r]]
            Cw[r, :] = np.inf
            Cw[:, s[r]] = np.inf
            Cw[r, s[r]] = keep
            fx[r] = True
    return np.array(out, dtype=np.int64).reshape(-1, P)


def murty(problem, k: int, *, backend: str = "numba") -> Ranked:
    """The ``k`` best assignments in non-decreasing cost (Murty's ranked assignment).

    Parameters
    ----------
    problem : AssignmentProblem
        The ``P x (M + 2P)`` problem; costs may be negative, ``+inf`` marks a forbidden pair.
    k : int
        Number of assignments wanted, ``k >= 0``. More than ``|Gamma|`` gives all of them.
        A ``k`` whose assignments would need more than
        :data:`~rankedassign.validation.MAX_WORK_BYTES` (4 GiB) of work arrays, about
        ``32 P + 128`` bytes per assignment, is refused (``min(k, |Gamma|)`` counts when
        ``|Gamma|`` is cheap to count): about 4 million assignments for ``P = 30``.
    backend : {"numba", "scipy"}, optional
        ``"numba"`` (default): compiled Murty with the Miller–Stone–Cox improvements (lazy
        lower bounds, warm starts, partition ordering) on sparse rows.
        ``"scipy"``: the plain algorithm of spec §5.1 calling
        :func:`scipy.optimize.linear_sum_assignment` on every subproblem (the reference).

    Returns
    -------
    Ranked
        ``min(k, |Gamma|)`` distinct feasible assignments (``(n, P)`` int64 column indices)
        and their costs (``problem.cost_of``), in non-decreasing cost. The order among equal
        costs is deterministic but may differ between the two backends.

    Raises
    ------
    TypeError
        If ``problem`` is not an :class:`~rankedassign.AssignmentProblem` or ``k`` is not an
        int.
    ValueError
        If ``k < 0``, ``backend`` is unknown, or the ``k`` assignments would not fit in
        :data:`~rankedassign.validation.MAX_WORK_BYTES` (the message gives ``k``, the bytes
        and the limit).

    Notes
    -----
    Murty (1968): pop the best open subproblem, report its optimum ``s``, and partition the
    rest of its solution set into ``P'`` children (``P'`` = rows not fixed in it): child
    ``t`` forbids ``(r_t, s[r_t])`` and fixes ``r_1..r_{t-1}`` to ``s``. The children
    partition the parent's set minus ``s``, so no assignment appears twice.

    The ``"numba"`` backend follows Miller, Stone & Cox (1997) on the compact layout. Each row
    keeps only its finite entries (its measurements, its own missed and dead column: at most
    ``M + 2``), so a row scan costs ``O(M + 2)``. A child enters the queue with a lower bound,
    its parent's cost plus the smallest reduced cost of an allowed alternative for the row
    whose pair it forbids (lazy evaluation), and is solved only when it reaches the top: it
    inherits its parent's optimal duals and partial assignment and is completed by one
    shortest augmenting path (Dijkstra on reduced costs) from that row, then re-enters with its
    exact cost. Rows are partitioned in decreasing order of the same bound (partition ordering).
    Once ``k - n`` solved subproblems wait in the queue (``n`` reported so far), the largest of
    their costs bounds everything still to be reported: a solve stops as soon as its subproblem
    is proven dearer, and a child bounded above it is not created (the early stop of Motro's
    ``fastmurty``; under the cut a child's bound is its own first step, with the columns of the
    rows fixed before it inactive too); asking for fewer assignments gives the first ones of a
    longer ranking (up to the last-bit reordering by the final sort). ``+inf`` entries are
    missing edges (no large stand-in constant), so huge and negative costs stay exact. The
    missed column ``M + i`` and dead column ``M + P + i`` belong to row ``i`` only: they are not
    interchangeable dummy columns, and no shortcut that treats them as such is taken.

    References
    ----------
    .. [1] K. G. Murty, "An Algorithm for Ranking all the Assignments in Order of Increasing
       Cost", Operations Research 16(3):682–687, 1968.
    .. [2] M. L. Miller, H. S. Stone, I. J. Cox, "Optimizing Murty's Ranked Assignment
       Method", IEEE Trans. Aerosp. Electron. Syst. 33(3):851–862, 1997.
    .. [3] B.-N. Vo, B.-T. Vo, H. G. Hoang, "An Efficient Implementation of the Generalized
       Labeled Multi-Bernoulli Filter", IEEE Trans. Signal Process. 65(8), 2017.
    .. [4] A. Trezza, D. J. Bucci Jr., P. K. Varshney, "On Gibbs Sampling Architecture for
       Labeled Random Finite Sets Multi-Object Tracking", arXiv:2306.15135, 2023.
    .. [5] M. Motro, ``fastmurty``: k-best data association in C, github.com/motrom/fastmurty
       (the early stop at the ``k``-th best; its optimizations were presented at IEEE FUSION
       2019).

    Examples
    --------
    >>> from rankedassign import AssignmentProblem, synthetic
    >>> from oracle import murty
    >>> p = AssignmentProblem.from_eta([[2.0, 0.5], [0.1, 3.0]], [0.2, 0.4], [0.1, 0.1])
    >>> r = murty(p, 3)
    >>> p.cols_to_gamma(r.assignments).tolist()     # gamma labels: (z1, z2), (z1, missed), ...
    [[1, 2], [1, 0], [0, 2]]
    >>> r.costs.round(4).tolist()                   # -ln(2*3), -ln(2*0.4), -ln(0.2*3)
    [-1.7918, 0.2231, 0.5108]
    >>> len(murty(p, 100).costs)       # only 14 feasible assignments
    14
    >>> murty(synthetic.diagonal(), 1, backend="scipy").assignments.tolist()
    [[0, 1, 2, 3]]
    """
    check_problem(problem)
    k = check_int(k, "k", minimum=0)
    if backend not in _BACKENDS:
        raise ValueError(f"backend must be one of {_BACKENDS}, got {backend!r}")
    P = problem.n_rows
    if k == 0:
        return ranked(problem, np.zeros((0, P), dtype=np.int64))
    if P == 0:
        return ranked(problem, np.zeros((1, 0), dtype=np.int64))
    _check_k_memory(problem, k)
    if backend == "scipy":
        return ranked(problem, _murty_scipy(problem, _k_cap(problem, k)))
    # the kernel's costs are problem.cost_of's, bit for bit, sorted stably
    # a writable copy: the δ-GLMB filter's compact costs are writable, and a read-only array
    # would compile the search's entry a second time
    return Ranked(*_murty_sliced(np.array(problem.compact_cost, dtype=np.float64, order="C"), k))


#: Graph entries (``P (M + 2P)``, an iteration's bound) times iterations per slice of the
#: search (tens of milliseconds): Ctrl-C ends a long ranking promptly.
_SLICE_WORK = 1 << 24


def _murty_sliced(cc, k):
    """The compiled search on compact costs ``cc`` (``P >= 1``), run in slices: the output of
    :func:`oracle._kernels.murty.murty_compact_kernel`, bit for bit, for every budget."""
    P, M = cc.shape[0], cc.shape[1] - 2
    N = M + 2 * P
    budget = max(1, _SLICE_WORK // (P * N))
    with interruptible:
        out, costs, rest = murty_compact_start(cc, k, budget)
        if rest is None:
            return out, costs
        costs, search = rest
        while True:  # later slices return an integer: a signal is raised here, between two
            status = murty_slice(costs, search, k, budget)
            if status == DONE:
                return search_output(search)
            if status == FULL:
                search = grow_search(search, k)

"""Compiled Murty k-best ranked assignment (spec §5.1) with the Miller–Stone–Cox improvements.

The driver :func:`murty_compact_kernel` takes the best open subproblem of the partition tree.
A node that is only *bounded* is solved (one warm-started shortest augmenting path) and goes
back into the queue with its exact cost; a *solved* node is reported and partitioned: its
children enter the queue with a lower bound only, so most of them are never solved. Once
``k - n`` solved nodes wait in the queue (``n`` reported), the largest of their costs (a
max-heap of the least solved costs keeps it) is a cut: a solve stops as soon as its node is
proven to cost more, and a child bounded above it is not created (under the cut a child's
bound is its own first step: its row's least reduced cost with the columns of the rows fixed
before it inactive too). Neither can ever be reported, so the output is unchanged. Forbidden
pairs are switched on and off in the shared cost matrix. Costs are accumulated row by row in
the order ``0..P-1`` from ``0.0``, exactly as :meth:`rankedassign.AssignmentProblem.cost_of`
does.

The residual problem, row by row. The problem is the compact ``(P, M + 2)`` matrix (the
measurements, the row's own missed and dead column), held as :data:`CompactCosts`; columns
are numbered as in the ``P x (M + 2P)`` layout (``M + i`` missed, ``M + P + i`` dead for row
``i``). A subproblem's columns are of three kinds. Its *fixed* rows' columns are out of it.
Each *open* row's column (the parent's solution; for the row whose pair the subproblem
forbids, the *freed* column, where the augmenting path ends) has a dual of its own: so these
columns are indexed by their row, and the shortest-path search keeps its distances, its
frontier and its tree in arrays of ``P`` entries (:data:`PathWork`), scanning only the open
rows' columns: ``O(P_open)`` per step however many measurements and fixed rows there are.
The other columns are *free* (held by the zero-cost dummy rows that make the rectangular
problem square): measurements no row takes, and every row's own missed or dead column that
it does not take. They share one dual ``v_free``, and only the closest of them can ever be
scanned (the first one scanned opens the dummy rows' hub, and then no free column is needed
any more), so the search keeps one running minimum for all of them instead of a frontier.
A row's own free columns are two entries; the free measurements are one pass over the row's
measurements, made only when some measurement is free and only until the hub opens. The
results are those of the column-indexed search of :func:`.lsap.sap_augment` (same arithmetic
and tie-breaking: the least distance, then the freed column, then the lower column index),
which the partition's bounds and the search's order depend on, bit for bit.

Records. The search's state is a :data:`Search` of named records: the workspace of one
augmenting path, indexed by row (:data:`PathWork`), the partition tree and its queue
(:data:`Tree`), the forbidden-pair lists (:data:`Forbidden`), the solved nodes
(:data:`Solutions`), the output and the cut (:data:`Ranking`), the partition's scratch
(:data:`PartitionWork`) and the counters (``state``, indexed by ``S_*``); the problem is a
:data:`CompactCosts`. A record crosses into Python as a plain tuple (:func:`pack_search`; see
:mod:`rankedassign.numba_options`, "Signals").

Layout for speed. The search (:func:`_search`) is one compiled loop on flat arrays that it
never reallocates: the tree, the solutions, the forbidden-pair lists and the heap are plain
arrays indexed by integers. When an array is full the loop returns, the arrays are grown
(:func:`grow_search`) and it is called again. At these sizes calls between compiled
functions that each receive a dozen arrays, array views made per node and arrays rebound
inside the loop (each costs atomic reference count updates) cost as much as the arithmetic.
The loop's phases (solve a node: :func:`_solve_node`; partition one: :func:`_partition`; the
heap's sift-down and push) are functions of their own, compiled with ``inline="always"``:
numba writes each into its caller before typing, so the loop is still one function and
nothing is called, allocated or reference-counted per node. Further savings that leave every
result bit for bit unchanged: a step of the search relaxes the scanned row and picks the
closest column in one pass over the open rows; a solve writes its solution straight into its
slot (nothing shared to restore when the cut drops it); the top of the heap is replaced in
one sift-down (by the node itself once solved, by its first child once partitioned).

Slices. The loop also returns after a budget of iterations, so that :func:`oracle.murty`
can run the search in slices (:func:`murty_compact_start`, then :func:`murty_slice` until
done, the state a packed :data:`Search`) and a signal ends a long ranking promptly; the slices
make the same iterations as one call, so the output does not depend on the budget.
"""

from __future__ import annotations

from collections import namedtuple

import numpy as np

from rankedassign.numba_options import instantiate, jit

from .lsap import HUB, UNASSIGNED

__all__ = ["murty_compact_kernel", "murty_compact_inline", "murty_start", "murty_slice",
           "grow_search", "search_output", "pack_search", "unpack_search", "compact_costs",
           "murty_compact_start", "CompactCosts", "Search", "PathWork", "Tree", "Forbidden",
           "Solutions", "Ranking", "PartitionWork", "DONE", "PAUSED", "FULL"]

NO_ENTRY = -1  # end of a forbidden-pair list; slot of a node that is not solved yet
ESTIMATED = -2  # slot ESTIMATED - s: the node's solution is in slot s, its cost is estimated
_INITIAL_CAPACITY = 1024
# Relative slack subtracted from a lower bound so that rounding can never lift it above the
# exact cost it bounds (the order of the output then equals that of solving every child).
_BOUND_SLACK = 1e-9
#: Up to this many rows a partition keeps the reduced costs between its free rows (a
#: ``P x P`` table) for its children's bounds; above, it computes them again.
RC_ROWS = 128

# ----------------------------------------------------------------------------- records
#: The problem: ``cost0`` (P, M + 3) the compact costs ``[measurements | missed | dead]`` and
#: a last column of ``+inf`` (the entry of another row's own missed or dead column, which no
#: row but its owner can take); ``cost`` a copy in which the forbidden pairs of the node at
#: hand are switched to ``+inf`` for a while.
CompactCosts = namedtuple("CompactCosts", ["cost", "cost0"])

#: Workspace of one shortest augmenting path. Per position ``t`` of the frontier (the open
#: rows whose columns are not scanned yet, ``n_open`` of them): ``row`` the row, ``off`` the
#: entry of its column in another row of ``cost`` (``M + 2``, ``+inf``, for a row's own missed
#: or dead column), ``tie`` the column's rank among columns at equal distance (the column,
#: ``-1`` for the freed one), ``v`` its dual, ``d`` its distance and ``via`` the row it was
#: reached from (``HUB``: through the dummy rows). Per scanned column, in order: ``done`` its
#: row, ``done_d``, ``done_v``, ``done_via`` its distance, dual and the row it was reached
#: from; ``at`` (per row) the position of the row's column in ``done``. ``vf`` (M,) the dual
#: subtracted for each measurement by the free columns' pass (``v_free``, or ``-inf`` for a
#: measurement some row takes). A partition uses ``off`` and ``v`` per row.
PathWork = namedtuple("PathWork", ["row", "off", "tie", "v", "d", "via", "done", "done_d",
                                   "done_v", "done_via", "at", "vf"])

#: The partition tree and its queue, per node: ``key`` its heap key (exact cost once solved, a
#: lower bound before), ``slot`` its solution (``NO_ENTRY`` until solved), ``parent`` the slot
#: of its parent's solution, ``forb`` the head of its forbidden-pair list (its own pair first,
#: then the ancestors'), ``end`` the end of its open rows: ``forb.row[forb:end]`` (its own
#: row, then the rows its parent partitioned after it; every other row is fixed to the
#: parent's column); ``heap_key``, ``heap_id`` the binary heap of ``(key, node id)``. The root
#: has no forbidden pair (``forb = end = NO_ENTRY``) and every row open.
Tree = namedtuple("Tree", ["key", "slot", "parent", "forb", "end", "heap_key", "heap_id"])

#: The forbidden-pair lists (a node's list continues into its ancestors'): per entry the
#: ``row``, its ``entry`` (the column of ``cost``) and the ``next`` entry (``NO_ENTRY`` ends a
#: list). A partition writes one entry per free row, in its order, whether or not the child is
#: created, so that ``row`` also lists each child's open rows.
Forbidden = namedtuple("Forbidden", ["row", "entry", "next"])

#: Solved nodes: ``cols`` (n, P) the assignment, ``u`` (n, P) the row duals, ``v`` (n, P) the
#: dual of each row's column, ``v_free`` the free columns' shared potential, ``cost`` the exact
#: cost, ``scale`` the rounding scale of its children's solves (set when it is partitioned)
#: and ``taken`` the number of measurements its rows take.
Solutions = namedtuple("Solutions", ["cols", "u", "v", "v_free", "cost", "scale", "taken"])

#: The output and the cut: ``slot`` the solution slot of each reported node, ``kbest`` a
#: max-heap of the least solved costs.
Ranking = namedtuple("Ranking", ["slot", "kbest"])

#: Scratch of a partition, per row: ``entry_of`` the entry of its own column in ``cost``,
#: ``order`` the free rows by decreasing bound, ``rank`` a row's position in it, ``lb`` its
#: bound and ``lb_row`` the row whose column gives it (``-1``: a free column), ``free_rc`` its
#: least reduced cost into a free column; ``rc`` (P, P) the reduced cost of row ``i`` in row
#: ``r``'s column (kept for the children's bounds when ``P <= RC_ROWS``, else (1, 1) unused).
PartitionWork = namedtuple("PartitionWork", ["entry_of", "order", "rank", "lb", "lb_row",
                                             "free_rc", "rc"])

#: The search's state between two calls of :func:`murty_slice`: the path workspace, the tree,
#: the forbidden pairs, the solutions, the ranking, the partition's scratch and the counters
#: ``state`` (int64, ``S_*``).
Search = namedtuple("Search", ["path", "tree", "forb", "sols", "ranking", "part", "state"])

# entries of the ``state`` array that carries the search's counters across calls of _search
S_HEAP = 0  # nodes in the heap
S_NODES = 1  # nodes created
S_SOLS = 2  # solutions stored
S_FORB = 3  # forbidden-pair entries used
S_OUT = 4  # assignments reported
S_BEST = 5  # entries in the max-heap of solved costs (kbest), reported ones included
S_STALE = 6  # entries of kbest that belong to reported nodes
S_ITER = 7  # iterations run (nodes taken from the top of the queue)
N_STATE = 8


@jit()
def pack_search(sr):
    """A :data:`Search` as plain tuples, the form it crosses into Python in.

    numba boxes a named tuple by calling its class, Python code, where a signal handler's
    exception crashes numba's return path (a segmentation fault, not an error); a plain tuple
    is built in C and only ever raises. :func:`unpack_search` names it again in compiled code.

    Parameters
    ----------
    sr : Search
        The search's state.

    Returns
    -------
    tuple
        ``(path, tree, forb, sols, ranking, part, state)``, each record a plain tuple of its
        fields; the arrays are shared, not copied.
    """
    return (sr.path[:], sr.tree[:], sr.forb[:], sr.sols[:], sr.ranking[:], sr.part[:],
            sr.state)


@jit(inline="always")
def unpack_search(t):
    """The :data:`Search` of a packed one (:func:`pack_search`).

    Parameters
    ----------
    t : tuple
        A packed search.

    Returns
    -------
    Search
        The same arrays, named.
    """
    return Search(PathWork(*t[0]), Tree(*t[1]), Forbidden(*t[2]), Solutions(*t[3]),
                  Ranking(*t[4]), PartitionWork(*t[5]), t[6])


# ----------------------------------------------------------------------------- small helpers
@jit()
def _grow(a, n):
    """``a`` copied into a new array with ``n`` rows (first axis).

    Parameters
    ----------
    a : ndarray
        C-contiguous, ``a.shape[0] <= n``.
    n : int
        Rows of the copy.

    Returns
    -------
    ndarray, shape (n, *a.shape[1:]), dtype of ``a``
        ``a`` in the first rows, the rest uninitialised.
    """
    out = np.empty((n,) + a.shape[1:], dtype=a.dtype)
    # element by element through flat views (both C-contiguous): an array assigned into a
    # slice compiles numba's formatted shape-mismatch error for each shape, about a second
    flat = out.reshape(out.size)
    src = a.reshape(a.size)
    for t in range(a.size):
        flat[t] = src[t]
    return out


@jit(inline="always")
def _sift_down_max(a, n, h, x):
    """Put ``x`` at ``h`` in the max-heap ``a[:n]`` and move it down to its place.

    Parameters
    ----------
    a : ndarray of float64
        The heap, ``a[:n]``; the entry at ``h`` is replaced.
    n : int
        Its size.
    h : int
        The position.
    x : float
        The new value.
    """
    while True:
        ch = 2 * h + 1
        if ch >= n:
            break
        if ch + 1 < n and a[ch + 1] > a[ch]:
            ch += 1
        if a[ch] > x:
            a[h] = a[ch]
            h = ch
        else:
            break
    a[h] = x


@jit(inline="always")
def _own_entry(i, c, M, P):
    """The entry of row ``i``'s column ``c`` in its row of the compact costs.

    Parameters
    ----------
    i : int
        The row.
    c : int
        One of its columns in the ``P x (M + 2P)`` layout (a measurement, its own missed
        ``M + i`` or dead ``M + P + i``).
    M, P : int
        Measurements and rows.

    Returns
    -------
    int
        ``c``, ``M`` or ``M + 1``.
    """
    return c if c < M else (M if c < M + P else M + 1)


@jit(inline="always")
def _switch_off(cost, forb, head):
    """Forbid every pair of the list that starts at ``head``: its cost becomes ``+inf``.

    Parameters
    ----------
    cost : ndarray of float64, shape (P, M + 3)
        :data:`CompactCosts`' working copy.
    forb : Forbidden
        The forbidden-pair lists.
    head : int
        The list's first entry (``NO_ENTRY``: empty).
    """
    g = head
    while g != NO_ENTRY:
        gu = np.uint64(g)
        cost[np.uint64(forb.row[gu]), np.uint64(forb.entry[gu])] = np.inf
        g = forb.next[gu]


@jit(inline="always")
def _switch_on(cost, cost0, forb, head):
    """Allow the pairs of the list that starts at ``head`` again (their costs from ``cost0``).

    Parameters
    ----------
    cost, forb, head
        As in :func:`_switch_off`.
    cost0 : ndarray of float64, shape (P, M + 3)
        The original costs.
    """
    g = head
    while g != NO_ENTRY:
        gu = np.uint64(g)
        i = np.uint64(forb.row[gu])
        e = np.uint64(forb.entry[gu])
        cost[i, e] = cost0[i, e]
        g = forb.next[gu]


@jit(inline="always")
def _is_full(sr, k, n_out, n_sols, n_nodes, n_forb, n_best):
    """Whether some array of ``sr`` lacks room for the next iteration's worst case (``P``
    children; kbest never holds more than ``k``).

    Parameters
    ----------
    sr : Search
        The search.
    k : int
        Number of assignments wanted.
    n_out, n_sols, n_nodes, n_forb, n_best : int
        The counters ``S_OUT``, ``S_SOLS``, ``S_NODES``, ``S_FORB``, ``S_BEST``.

    Returns
    -------
    bool
    """
    P = sr.path.row.shape[0]
    return (n_out == sr.ranking.slot.shape[0] or n_sols == sr.sols.cols.shape[0]
            or n_nodes + P > sr.tree.key.shape[0] or n_forb + P > sr.forb.row.shape[0]
            or n_best == sr.ranking.kbest.shape[0] < k)


@jit(inline="always")
def _free_duals(vf, sols, s, v_free):
    """Fill ``vf`` for the free columns' pass of solution ``s``: ``v_free`` for a free
    measurement, ``-inf`` for one a row takes. Returns whether some measurement is free.

    Parameters
    ----------
    vf : ndarray of float64, shape (M,)
        :data:`PathWork`'s ``vf``; left unchanged when no measurement is free.
    sols : Solutions
        The solutions.
    s : int
        The solution's slot.
    v_free : float
        Its free columns' shared potential.

    Returns
    -------
    bool
    """
    M = vf.shape[0]
    su = np.uint64(s)
    if sols.taken[su] == M:
        return False
    cols = sols.cols
    vf[:] = v_free
    for i in range(cols.shape[1]):
        c = cols[su, np.uint64(i)]
        if c < M:
            vf[np.uint64(c)] = -np.inf
    return True


@jit(inline="always")
def _least_free(cost, vf, free_meas, i, ci, ui, v_free, min_val):
    """The closest free column of row ``i`` (its column ``ci``, dual ``ui``) reached at
    ``min_val``: ``(distance, column)``, the lower column among equal distances (``+inf, -1``:
    none). The free measurements (``vf``, when ``free_meas``), then the row's own missed and
    dead columns when it does not take them.

    Parameters
    ----------
    cost : ndarray of float64, shape (P, M + 3)
        The working costs.
    vf : ndarray of float64, shape (M,)
        The free measurements' duals (:func:`_free_duals`).
    free_meas : bool
        Some measurement is free.
    i : int
        The row.
    ci : int
        Its column in the parent's solution.
    ui : float
        Its dual.
    v_free : float
        The free columns' shared potential.
    min_val : float
        The distance the row is reached at.

    Returns
    -------
    (float, int)
    """
    M = vf.shape[0]
    P = cost.shape[0]
    iu = np.uint64(i)
    best = np.inf
    best_j = -1
    if free_meas:
        for j in range(M):
            ju = np.uint64(j)
            dist = min_val + (cost[iu, ju] - ui - vf[ju])
            if dist < best:
                best = dist
                best_j = j
    if ci != M + i:
        dist = min_val + (cost[iu, np.uint64(M)] - ui - v_free)
        if dist < best:
            best = dist
            best_j = M + i
    if ci != M + P + i:
        dist = min_val + (cost[iu, np.uint64(M + 1)] - ui - v_free)
        if dist < best:
            best = dist
            best_j = M + P + i
    return best, best_j


# ----------------------------------------------------------------------------- solve a node
@jit(inline="always")
def _load_parent(pw, sols, forb, f, end, ps):
    """Load the open rows of a node (``forb.row[f:end]``, the first one ``root``, whose pair
    it forbids: its column is the freed one) and their columns in solution ``ps`` (its
    parent) into the frontier of ``pw``. Returns the number of open rows.

    Parameters
    ----------
    pw : PathWork
        The path workspace (its frontier written).
    sols : Solutions
        The solutions.
    forb : Forbidden
        The forbidden-pair lists (their ``row`` lists the open rows).
    f, end : int
        The node's ``forb`` and ``end``.
    ps : int
        The parent's solution slot.

    Returns
    -------
    int
    """
    row, off, tie, v, d = pw.row, pw.off, pw.tie, pw.v, pw.d
    s_cols, s_v = sols.cols, sols.v
    M = pw.vf.shape[0]
    rows = forb.row
    n_open = end - f
    pu = np.uint64(ps)
    for t in range(n_open):
        tu = np.uint64(t)
        r = rows[np.uint64(f + t)]
        row[tu] = r
        c = s_cols[pu, np.uint64(r)]
        off[tu] = c if c < M else M + 2
        tie[tu] = c
        v[tu] = s_v[pu, np.uint64(r)]
        d[tu] = np.inf
    tie[0] = -1  # the freed column ends the path: first among equal distances
    return n_open


@jit(inline="always")
def _relax_and_pick(cost, pw, n_open, i, ui, min_val):
    """Relax row ``i`` (dual ``ui``, reached at ``min_val``) into the frontier's columns and
    return the position of the closest one (``-1``: none reached): ties by ``tie``, so the
    freed column, then the lower column.

    Parameters
    ----------
    cost : ndarray of float64, shape (P, M + 3)
        The working costs (the node's forbidden pairs at ``+inf``).
    pw : PathWork
        The frontier: ``d`` and ``via`` updated.
    n_open : int
        Columns in the frontier.
    i : int
        The row scanned.
    ui : float
        Its dual.
    min_val : float
        The distance it is reached at.

    Returns
    -------
    int
    """
    off, tie, v, d, via = pw.off, pw.tie, pw.v, pw.d, pw.via
    iu = np.uint64(i)
    index = 0
    lowest = np.inf  # (an unreached column, d = inf, is never picked)
    for t in range(n_open):
        tu = np.uint64(t)  # (unsigned: no negative-index wraparound)
        dist = min_val + (cost[iu, np.uint64(off[tu])] - ui - v[tu])
        dt = d[tu]
        if dist < dt:
            dt = dist
            d[tu] = dist
            via[tu] = i
        if dt < lowest:
            lowest = dt
            index = t
        elif dt == lowest and tie[tu] < tie[np.uint64(index)]:
            index = t
    return index if lowest < np.inf else -1


@jit(inline="always")
def _open_hub(pw, n_open, v_free, min_val):
    """A free column was scanned at ``min_val``: the dummy rows reach every frontier column
    at reduced cost ``v_free - v``. Returns the position of the closest one afterwards
    (``-1``: none).

    Parameters
    ----------
    pw : PathWork
        The frontier: ``d`` and ``via`` (``HUB``) updated.
    n_open : int
        Columns in the frontier.
    v_free : float
        The free columns' shared potential.
    min_val : float
        The free column's distance.

    Returns
    -------
    int
    """
    tie, v, d, via = pw.tie, pw.v, pw.d, pw.via
    index = 0
    lowest = np.inf
    for t in range(n_open):
        tu = np.uint64(t)
        dist = min_val + (v_free - v[tu])
        dt = d[tu]
        if dist < dt:
            dt = dist
            d[tu] = dist
            via[tu] = HUB
        if dt < lowest:
            lowest = dt
            index = t
        elif dt == lowest and tie[tu] < tie[np.uint64(index)]:
            index = t
    return index if lowest < np.inf else -1


@jit(inline="always")
def _scan(pw, t, n_open, n_done):
    """Move the frontier's column at position ``t`` to the scanned ones (``done``); returns
    its row.

    Parameters
    ----------
    pw : PathWork
        The path workspace; the frontier's last entry moves to position ``t``.
    t : int
        The position.
    n_open : int
        Columns in the frontier (one fewer afterwards, which the caller counts).
    n_done : int
        Columns scanned so far (the new one's position in ``done``).

    Returns
    -------
    int
        The row whose column was scanned.
    """
    row, off, tie, v, d, via = pw.row, pw.off, pw.tie, pw.v, pw.d, pw.via
    t = np.uint64(t)
    n = np.uint64(n_done)
    r = row[t]
    pw.done[n] = r
    pw.done_d[n] = d[t]
    pw.done_v[n] = v[t]
    pw.done_via[n] = via[t]
    pw.at[np.uint64(r)] = n_done
    last = np.uint64(n_open - 1)
    row[t] = row[last]
    off[t] = off[last]
    tie[t] = tie[last]
    v[t] = v[last]
    d[t] = d[last]
    via[t] = via[last]
    return r


@jit(inline="always")
def _solve_node(cs, sr, node, cut, s):
    """Solve the bounded ``node`` by one shortest augmenting path from its parent's duals
    and assignment minus ``(root, freed)`` (the algorithm of :func:`.lsap.sap_augment`, warm
    start), unless the cut drops it; when solved, its solution (and ``v_free``) is written
    into slot ``s``. Returns ``(solved, distance)``: the node costs its parent's cost plus the
    distance, up to rounding.

    Parameters
    ----------
    cs : CompactCosts
        The problem (the node's forbidden pairs are switched off and on again).
    sr : Search
        The search.
    node : int
        The node's id.
    cut : float
        The cut: a node proven to cost more is dropped (``+inf``: no cut).
    s : int
        The free solution slot.

    Returns
    -------
    (bool, float)
    """
    cost = cs.cost
    pw, tree, forb, sols = sr.path, sr.tree, sr.forb, sr.sols
    done, done_d, done_v, done_via, at = pw.done, pw.done_d, pw.done_v, pw.done_via, pw.at
    s_cols, s_u, s_v = sols.cols, sols.u, sols.v
    ps = tree.parent[node]
    head = tree.forb[node]
    root = forb.row[head]
    base = sols.cost[ps]
    # the margin for rounding: the parent's, set when it was partitioned
    cut += _BOUND_SLACK * (sols.scale[ps] + abs(cut))  # (+inf stays +inf)
    v_free = sols.v_free[ps]
    n_open = _load_parent(pw, sols, forb, head, tree.end[node], ps)
    free_meas = _free_duals(pw.vf, sols, ps, v_free)
    _switch_off(cost, forb, head)
    # Dijkstra from the root's row. The free columns are one running minimum (free_d at
    # free_j, reached from free_row) until the first of them is scanned and opens the hub.
    n_done = 0
    min_val = 0.0
    i = root
    free_d = np.inf
    free_j = -1
    free_row = -1
    hub_src = -1  # the free column that opened the hub (-1: still closed)
    hub_row = -1
    hub_dist = 0.0
    solved = False
    index = _relax_and_pick(cost, pw, n_open, i, s_u[ps, i], min_val)
    while True:
        if hub_src < 0:
            fd, fj = _least_free(cost, pw.vf, free_meas, i, s_cols[ps, i], s_u[ps, i], v_free,
                                 min_val)
            if fd < free_d or (fd == free_d and fj < free_j):
                free_d = fd
                free_j = fj
                free_row = i
        # the closest column: the best frontier one, or the closest free one
        if index >= 0:
            dt = pw.d[index]
            if free_d < dt or (free_d == dt and free_j < pw.tie[index]):
                index = -1
        elif free_d == np.inf:
            break  # nothing reachable: the node has no feasible assignment
        if index < 0:  # a free column is scanned: the hub opens
            min_val = free_d
            if base + min_val > cut:  # the node costs at least this much: drop it
                break
            hub_src = free_j
            hub_row = free_row
            hub_dist = min_val
            free_d = np.inf  # the free columns leave the frontier
            index = _open_hub(pw, n_open, v_free, min_val)
            continue
        min_val = pw.d[index]
        r = _scan(pw, index, n_open, n_done)
        n_open -= 1
        n_done += 1
        if r == root:  # the freed column: the path ends
            solved = True
            break
        if base + min_val > cut:
            break
        i = r  # scan the row that holds the column
        index = _relax_and_pick(cost, pw, n_open, i, s_u[ps, i], min_val)
    _switch_on(cost, cs.cost0, forb, head)
    if not solved:
        return False, min_val
    # The solution: the parent's; the duals of each scanned row and column moved by how far
    # it was passed (with the old matching); the path flipped from the freed column back to
    # the root.
    P = at.shape[0]
    su = np.uint64(s)
    pu = np.uint64(ps)
    for q in range(P):
        s_cols[su, np.uint64(q)] = s_cols[pu, np.uint64(q)]
    for q in range(P):
        s_u[su, np.uint64(q)] = s_u[pu, np.uint64(q)]
    for q in range(P):
        s_v[su, np.uint64(q)] = s_v[pu, np.uint64(q)]
    for t in range(n_done):
        tu = np.uint64(t)
        ru = np.uint64(done[tu])
        x = min_val - done_d[tu]
        s_u[su, ru] = s_u[pu, ru] + x  # (the root's is set below: it was scanned at 0.0)
        done_v[tu] -= x
        s_v[su, ru] = done_v[tu]
    s_u[su, np.uint64(root)] = s_u[pu, np.uint64(root)] + (min_val - 0.0)
    v_hub = v_free
    if hub_src >= 0:
        v_hub -= min_val - hub_dist
        v_free = v_free - (min_val - hub_dist)
    e = root  # the row whose (old) column is taken next
    while True:
        t = np.uint64(at[np.uint64(e)])
        r = done_via[t]
        if r == HUB:  # that column goes to a dummy row; the path came through a free column
            r = hub_row
            s_cols[su, np.uint64(r)] = hub_src
            s_v[su, np.uint64(r)] = v_hub
        else:
            s_cols[su, np.uint64(r)] = s_cols[pu, np.uint64(e)]
            s_v[su, np.uint64(r)] = done_v[t]
        if r == root:
            break
        e = r
    sols.v_free[su] = v_free
    return True, min_val


@jit(inline="always")
def _store_cost(cs, sols, s):
    """Set the cost (summed row by row from ``0.0``) and the number of measurements taken of
    solution ``s``; returns the cost.

    Parameters
    ----------
    cs : CompactCosts
        The problem (``cost0`` is read).
    sols : Solutions
        ``cost`` and ``taken`` of slot ``s`` written.
    s : int
        The solution's slot (its ``cols`` set).

    Returns
    -------
    float
    """
    cost0 = cs.cost0
    P = cost0.shape[0]
    M = cost0.shape[1] - 3
    s_cols = sols.cols
    su = np.uint64(s)
    key = 0.0
    taken = 0
    for i in range(P):
        c = s_cols[su, np.uint64(i)]
        key += cost0[np.uint64(i), np.uint64(_own_entry(i, c, M, P))]
        taken += c < M
    sols.cost[su] = key
    sols.taken[su] = taken
    return key


@jit(inline="always")
def _keep_least(kbest, n_best, n_stale, want, key):
    """Keep the ``want`` least solved costs in ``kbest`` (``n_stale`` of its ``n_best``
    entries belong to reported nodes): appended until there are that many, then a max-heap
    (made once) whose top is replaced. Returns the new ``n_best``.

    Parameters
    ----------
    kbest : ndarray of float64
        :data:`Ranking`'s ``kbest``, with room for one more entry while not full.
    n_best : int
        Its entries.
    n_stale : int
        Those of reported nodes.
    want : int
        The least costs to keep (``k - n`` with ``n`` reported).
    key : float
        A solved node's cost.

    Returns
    -------
    int
    """
    if n_best - n_stale < want:
        kbest[n_best] = key
        n_best += 1
        if n_best - n_stale == want:  # full: heapify kbest[:n_best]
            for h0 in range((n_best >> 1) - 1, -1, -1):
                _sift_down_max(kbest, n_best, h0, kbest[h0])
    elif key < kbest[0]:
        _sift_down_max(kbest, n_best, 0, key)
    return n_best


# ----------------------------------------------------------------------------- partition a node
@jit(inline="always")
def _load_partition(cs, sr, node, sl, key):
    """Prepare the partition of the solved ``node`` (solution ``sl``, cost ``key``): the entry
    of each row's own column, the free rows (the node's open rows) as ``open`` and the entries
    and duals of their columns in the path workspace. Returns ``(scale, n_free)``: the
    rounding scale of its children's solves (also stored in ``sols.scale[sl]``) and the number
    of free rows.

    Parameters
    ----------
    cs : CompactCosts
        The problem.
    sr : Search
        The search: ``part.entry_of``, ``path.row`` (the free rows) and ``path.off``,
        ``path.v`` at the free rows written.
    node : int
        The node's id.
    sl : int
        Its solution's slot.
    key : float
        Its cost.

    Returns
    -------
    (float, int)
    """
    cost0 = cs.cost0
    pw, part, sols, tree = sr.path, sr.part, sr.sols, sr.tree
    off, v, op = pw.off, pw.v, pw.row
    entry_of = part.entry_of
    s_cols, s_u, s_v = sols.cols, sols.u, sols.v
    P = op.shape[0]
    M = pw.vf.shape[0]
    slu = np.uint64(sl)
    sum_c = 0.0  # (two sums: neither waits on the other; a margin needs no exact order)
    sum_u = 0.0
    for i in range(P):
        iu = np.uint64(i)
        e = _own_entry(i, s_cols[slu, iu], M, P)
        entry_of[iu] = e
        sum_c += abs(cost0[iu, np.uint64(e)])
        sum_u += abs(s_u[slu, iu])
    slack = 1.0 + abs(key) + sum_c + sum_u
    f = tree.forb[node]
    if f == NO_ENTRY:  # the root: every row is free
        n_free = P
        for i in range(P):
            op[np.uint64(i)] = i
    else:
        n_free = tree.end[node] - f
        for t in range(n_free):
            op[np.uint64(t)] = sr.forb.row[np.uint64(f + t)]
    for t in range(n_free):
        ru = np.uint64(op[np.uint64(t)])
        c = s_cols[slu, ru]
        off[ru] = c if c < M else M + 2
        v[ru] = s_v[slu, ru]
    sols.scale[sl] = slack
    return slack, n_free


@jit(inline="always")
def _least_free_rc(cost, vf, free_meas, i, ci, ui, v_free):
    """The least reduced cost ``cost - ui - v_free`` of row ``i`` (column ``ci``) over its free
    columns (as :func:`_least_free`, the value only).

    Parameters
    ----------
    cost, vf, free_meas, i, ci, ui, v_free
        As in :func:`_least_free`.

    Returns
    -------
    float
        ``+inf`` when the row has no free column.
    """
    M = vf.shape[0]
    P = cost.shape[0]
    iu = np.uint64(i)
    best = np.inf
    if free_meas:
        for j in range(M):
            ju = np.uint64(j)
            rc = cost[iu, ju] - ui - vf[ju]
            best = rc if rc < best else best
    if ci != M + i:
        rc = cost[iu, np.uint64(M)] - ui - v_free
        best = rc if rc < best else best
    if ci != M + P + i:
        rc = cost[iu, np.uint64(M + 1)] - ui - v_free
        best = rc if rc < best else best
    return best


@jit(inline="always")
def _row_bound(cost, cost0, pw, rows, lo, hi, i, ci, ui, free_meas, v_free):
    """The least reduced cost of an alternative for the free row ``i`` (its column ``ci``, dual
    ``ui``): over the columns of the rows ``rows[lo:hi]`` but its own, and over the free
    columns. Returns ``(bound, row)``, ``row`` the one whose column gives it (``-1``: a free
    column).

    Parameters
    ----------
    cost : ndarray of float64, shape (P, M + 3)
        The working costs (row ``i``'s own entry is set to ``+inf`` and restored).
    cost0 : ndarray of float64, shape (P, M + 3)
        The original costs.
    pw : PathWork
        ``off`` and ``v`` of the rows (:func:`_load_partition`), ``vf``.
    rows : ndarray of int64
        Rows whose columns are candidates: ``rows[lo:hi]``.
    lo, hi : int
        Their range.
    i, ci, ui, free_meas, v_free
        As in :func:`_least_free`.

    Returns
    -------
    (float, int)
    """
    off, v = pw.off, pw.v
    iu = np.uint64(i)
    oi = np.uint64(off[iu])
    cost[iu, oi] = np.inf  # the row's own entry is no alternative
    best = np.inf
    best_row = -1
    for t in range(lo, hi):
        r = rows[np.uint64(t)]
        ru = np.uint64(r)
        rc = cost[iu, np.uint64(off[ru])] - ui - v[ru]
        if rc < best:
            best = rc
            best_row = r
    cost[iu, oi] = cost0[iu, oi]  # (M + 2 of a private column: +inf in both)
    free = _least_free_rc(cost, pw.vf, free_meas, i, ci, ui, v_free)
    if free < best:
        best = free
        best_row = -1
    return best, best_row


@jit(inline="always")
def _order_rows(cs, sr, sl, n_free, free_meas, v_free):
    """The bound ``lb[i]`` of each free row's child, the smallest reduced cost of an allowed,
    active alternative ``j != s[i]`` (and the row ``lb_row[i]`` whose column gives it), and
    ``order``: the free rows by decreasing bound, ties in row order (partition ordering), with
    each one's ``rank`` in it. (As :func:`_row_bound` over the free rows, keeping ``rc`` and
    ``free_rc``.)

    Parameters
    ----------
    cs : CompactCosts
        The problem (the node's forbidden pairs switched off).
    sr : Search
        The search: ``part``'s ``order``, ``rank``, ``lb``, ``lb_row``, ``free_rc`` and, when
        ``P <= RC_ROWS``, ``rc`` written.
    sl : int
        The node's solution slot.
    n_free : int
        Its free rows (``path.row[:n_free]``).
    free_meas : bool
        Some measurement is free (:func:`_free_duals`).
    v_free : float
        The free columns' shared potential.
    """
    cost, cost0 = cs.cost, cs.cost0
    pw, part, sols = sr.path, sr.part, sr.sols
    order, rank, lb, lb_row, free_rc, rcm = (part.order, part.rank, part.lb, part.lb_row,
                                             part.free_rc, part.rc)
    op, off, v = pw.row, pw.off, pw.v
    s_cols, s_u = sols.cols, sols.u
    slu = np.uint64(sl)
    keep = rcm.shape[0] == op.shape[0]
    for t in range(n_free):
        i = op[np.uint64(t)]
        iu = np.uint64(i)
        ui = s_u[slu, iu]
        oi = np.uint64(off[iu])
        cost[iu, oi] = np.inf  # the row's own entry is no alternative
        best = np.inf
        best_row = -1
        for t2 in range(n_free):
            r = op[np.uint64(t2)]
            ru = np.uint64(r)
            rc = cost[iu, np.uint64(off[ru])] - ui - v[ru]
            if keep:
                rcm[iu, ru] = rc
            if rc < best:
                best = rc
                best_row = r
        cost[iu, oi] = cost0[iu, oi]
        free = _least_free_rc(cost, pw.vf, free_meas, i, s_cols[slu, iu], ui, v_free)
        free_rc[iu] = free
        if free < best:
            best = free
            best_row = -1
        lb_row[iu] = best_row
        x = 0.0 if 0.0 > best else best  # (max(best, 0.0) without the call)
        lb[iu] = x
        # insert row i, keeping decreasing bounds, ties in row order
        b = t - 1
        while b >= 0 and (lb[order[b]] < x or (lb[order[b]] == x and order[b] > i)):
            order[b + 1] = order[b]
            b -= 1
        order[b + 1] = i
    for t in range(n_free):
        rank[order[t]] = t


@jit(inline="always")
def _make_children(cs, sr, node, key, slack, cut, n_free, free_meas, v_free, n_nodes, n_forb):
    """Create the children of the solved ``node`` (cost ``key``): child ``t`` forbids
    ``(order[t], s[order[t]])`` and fixes ``order[:t]``; a child whose bound (minus
    ``slack``, the rounding margin) exceeds ``cut`` is not created. Returns ``(n_nodes,
    n_forb)``.

    A child's bound is the least reduced cost of its row's first step (``lb``), plus that of
    the last step of its path, into the freed column: from a row the child leaves open
    (``order[t + 1:]``) or from a dummy row (``v_free - v``). The path has both (its row's
    pair is forbidden) and every reduced cost is at least 0. With the reduced costs between
    the free rows at hand (``rc``), the bound looks one step further: a first step into the
    column of an open row ``q`` is followed either by ``q``'s step into the freed column or
    by another step (at least ``lb[q]``) and the last one; a first step into a free column,
    by the last one. The least of these sums is at least the two-step bound.

    Parameters
    ----------
    cs : CompactCosts
        The problem (the node's forbidden pairs switched off).
    sr : Search
        The search (``part`` as :func:`_order_rows` left it); the new nodes and their
        forbidden pairs are written into ``tree`` and ``forb``.
    node : int
        The node's id.
    key : float
        Its cost.
    slack : float
        The rounding margin subtracted from each bound.
    cut : float
        The cut (``+inf``: none).
    n_free, free_meas, v_free
        As in :func:`_order_rows`.
    n_nodes, n_forb : int
        Nodes and forbidden-pair entries used so far.

    Returns
    -------
    (int, int)
    """
    cost = cs.cost
    entry_of, order, rank, lb, lb_row, free_rc, rcm = sr.part
    keep = rcm.shape[0] == order.shape[0]
    tree, forb, sols = sr.tree, sr.forb, sr.sols
    off = sr.path.off
    s_u = sols.u
    sl = tree.slot[node]
    slu = np.uint64(sl)
    head = tree.forb[node]
    base = n_forb
    for t in range(n_free):
        r = order[t]
        forb.row[base + t] = r
        forb.entry[base + t] = entry_of[r]
        forb.next[base + t] = head
        # the bound, step by step while the child may still be created (each step only
        # raises it)
        bx = lb[r]
        if not (bx < np.inf and key + bx - slack <= cut):
            continue
        if t > 0 and cut < np.inf and lb_row[r] >= 0 and rank[lb_row[r]] < t:
            # Under a cut, child t's first step is lb[r] again, with the columns of the rows
            # fixed before it (order[:t]) inactive as well, that is the distance its solve
            # would pop first. (Unless the column that gave lb[r] is now inactive, that is
            # lb[r] itself.)
            if keep:
                bx = free_rc[np.uint64(r)]
                for t2 in range(t, n_free):  # (rc[r, r] is +inf)
                    x = rcm[np.uint64(r), np.uint64(order[np.uint64(t2)])]
                    bx = x if x < bx else bx
            else:
                bx, _ = _row_bound(cost, cs.cost0, sr.path, order, t, n_free, r,
                                   sols.cols[sl, r], s_u[sl, r], free_meas, v_free)
            bx = 0.0 if 0.0 > bx else bx
            if not (bx < np.inf and key + bx - slack <= cut):
                continue
        f_off = np.uint64(off[np.uint64(r)])
        vr = sols.v[slu, np.uint64(r)]
        into = v_free - vr
        if keep:
            for t2 in range(t + 1, n_free):
                x = rcm[np.uint64(order[np.uint64(t2)]), np.uint64(r)]
                into = x if x < into else into
        else:
            for t2 in range(t + 1, n_free):
                q = np.uint64(order[np.uint64(t2)])
                rc = cost[q, f_off] - s_u[slu, q] - vr
                into = rc if rc < into else into
        into = 0.0 if 0.0 > into else into
        bx = bx + into
        if keep:  # the bound with the second step (each term is at least bx)
            ru = np.uint64(r)
            b2 = free_rc[ru] + into
            for t2 in range(t + 1, n_free):
                q = np.uint64(order[np.uint64(t2)])
                x = rcm[ru, q]
                if x < b2:
                    rest = lb[q] + into  # q's step elsewhere, then the last step
                    direct = rcm[q, ru]  # q's step into the freed column
                    x += direct if direct < rest else rest
                    b2 = x if x < b2 else b2
            bx = b2 if b2 > bx else bx
        if key + bx - slack <= cut:
            tree.key[n_nodes] = key + bx - slack
            tree.slot[n_nodes] = NO_ENTRY
            tree.parent[n_nodes] = sl
            tree.forb[n_nodes] = base + t
            tree.end[n_nodes] = base + n_free
            n_nodes += 1
    return n_nodes, base + n_free


@jit(inline="always")
def _partition(cs, sr, node, key, cut, n_nodes, n_forb):
    """Partition the solved, reported ``node`` of cost ``key`` (lazily: its children enter
    the queue with a lower bound only), with the node's forbidden pairs switched off meanwhile.
    Returns ``(n_nodes, n_forb)``.

    Parameters
    ----------
    cs : CompactCosts
        The problem.
    sr : Search
        The search.
    node : int
        The node's id.
    key : float
        Its cost.
    cut : float
        The cut (``+inf``: none).
    n_nodes, n_forb : int
        Nodes and forbidden-pair entries used so far.

    Returns
    -------
    (int, int)
    """
    tree, sols = sr.tree, sr.sols
    sl = tree.slot[node]
    head = tree.forb[node]
    _switch_off(cs.cost, sr.forb, head)
    slack, n_free = _load_partition(cs, sr, node, sl, key)
    slack *= _BOUND_SLACK
    cut += slack + _BOUND_SLACK * abs(cut)  # the margin, as in a solve
    v_free = sols.v_free[sl]
    free_meas = _free_duals(sr.path.vf, sols, sl, v_free)
    _order_rows(cs, sr, sl, n_free, free_meas, v_free)
    n_nodes, n_forb = _make_children(cs, sr, node, key, slack, cut, n_free, free_meas, v_free,
                                     n_nodes, n_forb)
    _switch_on(cs.cost, cs.cost0, sr.forb, head)
    return n_nodes, n_forb


# ----------------------------------------------------------------------------- the queue
@jit(inline="always")
def _replace_top(heap_key, heap_id, n_heap, kx, x):
    """Put ``(kx, x)`` at the top of the min-heap ``(heap_key, heap_id)[:n_heap]`` (ordered by
    key, then id) and sift it down to its place.

    Parameters
    ----------
    heap_key : ndarray of float64
        The keys.
    heap_id : ndarray of int64
        The node ids.
    n_heap : int
        The heap's size (``>= 1``).
    kx : float
        The new entry's key.
    x : int
        Its node id.
    """
    h = 0
    while True:
        ch = 2 * h + 1
        if ch >= n_heap:
            break
        ka = heap_key[ch]
        a = heap_id[ch]
        if ch + 1 < n_heap:
            kb = heap_key[ch + 1]
            b = heap_id[ch + 1]
            if kb < ka or (kb == ka and b < a):
                ch += 1
                ka = kb
                a = b
        if ka < kx or (ka == kx and a < x):
            heap_key[h] = ka
            heap_id[h] = a
            h = ch
        else:
            break
    heap_key[h] = kx
    heap_id[h] = x


@jit(inline="always")
def _push(heap_key, heap_id, n_heap, ky, y):
    """Push ``(ky, y)`` onto the min-heap of :func:`_replace_top`; returns its new size.

    Parameters
    ----------
    heap_key, heap_id, n_heap
        As in :func:`_replace_top` (with room for one more entry).
    ky : float
        The key.
    y : int
        The node id.

    Returns
    -------
    int
    """
    h = n_heap
    while h > 0:
        p = (h - 1) >> 1
        kp = heap_key[p]
        if ky < kp or (ky == kp and y < heap_id[p]):
            heap_key[h] = kp
            heap_id[h] = heap_id[p]
            h = p
        else:
            break
    heap_key[h] = ky
    heap_id[h] = y
    return n_heap + 1


# ----------------------------------------------------------------------------- the search
@jit(nrt=False)  # allocates nothing: no reference counts for the records its phases get
def _search(cs, sr, k, budget):
    """Run the search until ``k`` assignments are reported, the queue is empty, an array is
    full or ``budget`` iterations are done.

    Parameters
    ----------
    cs : CompactCosts
        The problem; ``cs.cost`` equals ``cs.cost0`` between iterations.
    sr : Search
        The search, updated in place: its counters live in ``sr.state`` between calls.
    k : int
        Number of assignments wanted.
    budget : int
        Iterations in this call (nodes taken from the top of the queue).

    Returns
    -------
    bool
        True when finished; False when an array is full (grow the arrays, :func:`grow_search`)
        or the budget is spent: call again.

    Notes
    -----
    An iteration starts only when every array has room for its worst case (``P`` children),
    so a return never leaves one half done, and the calls together make the same iterations
    as one call.
    """
    tree, kbest, state = sr.tree, sr.ranking.kbest, sr.state
    heap_key, heap_id = tree.heap_key, tree.heap_id
    n_heap = state[S_HEAP]
    n_nodes = state[S_NODES]
    n_sols = state[S_SOLS]
    n_forb = state[S_FORB]
    n_out = state[S_OUT]
    n_best = state[S_BEST]
    n_stale = state[S_STALE]
    n_iter = state[S_ITER]
    stop_iter = n_iter + budget
    finished = True
    while n_heap > 0 and n_out < k:
        if _is_full(sr, k, n_out, n_sols, n_nodes, n_forb, n_best) or n_iter >= stop_iter:
            finished = False
            break
        n_iter += 1
        # The least (key, id) is at the top. It stays there while it is processed and is then
        # replaced in one sift-down: by itself with its exact cost once solved, by its first
        # child once partitioned, or by the heap's last entry when it just leaves.
        node = heap_id[0]
        first = n_nodes  # children made in this iteration: first..n_nodes-1
        # The cut. kbest is a max-heap of solved costs: costs of solved nodes still in the
        # queue, and n_stale entries counted for the nodes reported since (a reported cost
        # stays in it; it may also have been evicted, so n_best - n_stale never overcounts
        # the queued ones). When it holds k - n_out queued costs, the largest entry is at
        # least the (k - n_out)-th least queued cost: every cost still to be reported is at
        # most that, so a node dearer than kbest[0] (beyond a margin for rounding), and every
        # descendant of it, is never reported.
        if n_best - n_stale == k - n_out:
            cut = kbest[0]
        else:
            cut = np.inf
        sl = tree.slot[node]
        if sl == NO_ENTRY:
            # A bounded node at the top: solve it and queue it again with its cost up to
            # rounding (its parent's cost plus the path's length, less the margin for rounding
            # that the bounds use; and plus the margin in kbest): its exact cost, summed row by
            # row, is only needed if it comes back to the top, and most solved nodes never do.
            solved, dist = _solve_node(cs, sr, node, cut, n_sols)
            if solved:
                ps = tree.parent[node]
                cost_ = sr.sols.cost[ps] + dist
                margin = _BOUND_SLACK * (sr.sols.scale[ps] + abs(cost_))
                n_best = _keep_least(kbest, n_best, n_stale, k - n_out, cost_ + margin)
                tree.slot[node] = ESTIMATED - n_sols
                n_sols += 1
                kx = cost_ - margin
                tree.key[node] = kx
                x = node
            else:
                n_heap -= 1  # the node leaves
                kx = heap_key[n_heap]
                x = heap_id[n_heap]
        elif sl <= ESTIMATED:
            # a solved node back at the top: its exact cost, and into the queue again with it
            sl = ESTIMATED - sl
            kx = _store_cost(cs, sr.sols, sl)
            tree.slot[node] = sl
            tree.key[node] = kx
            x = node
        else:
            # a solved node at the top: report it
            key = tree.key[node]
            sr.ranking.slot[n_out] = tree.slot[node]  # copied into the output at the end
            n_out += 1
            n_stale += 1  # its cost, the least in kbest, stays there as a stale entry
            if n_out == k:
                break
            n_nodes, n_forb = _partition(cs, sr, node, key, cut, n_nodes, n_forb)
            if n_nodes == first:  # no child: the node leaves
                n_heap -= 1
                kx = heap_key[n_heap]
                x = heap_id[n_heap]
            else:
                kx = tree.key[first]
                x = first
        _replace_top(heap_key, heap_id, n_heap, kx, x)
        for y in range(first + 1, n_nodes):  # push the other children
            n_heap = _push(heap_key, heap_id, n_heap, tree.key[y], y)
    state[S_HEAP] = n_heap
    state[S_NODES] = n_nodes
    state[S_SOLS] = n_sols
    state[S_FORB] = n_forb
    state[S_OUT] = n_out
    state[S_BEST] = n_best
    state[S_STALE] = n_stale
    state[S_ITER] = n_iter
    return finished




@jit(nrt=False)  # allocates nothing: no reference counts for the records it reads
def _root_lsap(cs, pw, sols, free):
    """The root's LSAP, a cold shortest augmenting path from each row in turn, stored as
    solution 0 (``v_free = 0``); returns False when some row cannot be assigned.

    :func:`.lsap.sap_augment` with ``freed = COLD`` and ``v_free = 0`` (same arithmetic and
    tie-breaking: the least distance, then a free column, which ends the path, then the lower
    column index), by row as a solve is (module notes): the frontier is the columns of the
    rows already assigned, and of the free columns (potential 0) only the closest matters,
    since the first one scanned ends the path. ``free`` (M,) is scratch: the measurements no
    row takes.

    Parameters
    ----------
    cs : CompactCosts
        The problem.
    pw : PathWork
        The path workspace (scratch).
    sols : Solutions
        Slot 0 receives the root's solution (``cols``, ``u``, ``v``).
    free : ndarray of int64, shape (M,)
        Scratch.

    Returns
    -------
    bool
    """
    cost = cs.cost
    P = cost.shape[0]
    M = cost.shape[1] - 3
    row, off, tie, v, d = pw.row, pw.off, pw.tie, pw.v, pw.d
    done, done_d, done_v, done_via, at = pw.done, pw.done_d, pw.done_v, pw.done_via, pw.at
    cols, u, vs = sols.cols, sols.u, sols.v  # solution 0, built row by row
    z = np.uint64(0)
    for j in range(M):
        free[np.uint64(j)] = j  # the measurements no row takes (potential 0)
    n_free = M
    for root in range(P):
        n_open = root  # the frontier: the columns of rows 0..root-1
        for t in range(n_open):
            tu = np.uint64(t)
            c = cols[z, tu]
            row[tu] = t
            off[tu] = c if c < M else M + 2
            tie[tu] = c
            v[tu] = vs[z, tu]
            d[tu] = np.inf
        ru = np.uint64(root)
        cols[z, ru] = UNASSIGNED
        u[z, ru] = 0.0
        n_done = 0
        min_val = 0.0
        i = root
        free_d = np.inf
        free_j = -1
        free_row = -1
        while True:
            iu = np.uint64(i)
            ui = u[z, iu]
            index = _relax_and_pick(cost, pw, n_open, i, ui, min_val)
            # the free columns of row i: the measurements no row takes, its own missed and
            # dead column unless it takes one (a row's column is never free: ci >= 0)
            ci = cols[z, iu]
            for t in range(n_free):
                j = free[np.uint64(t)]
                dist = min_val + (cost[iu, np.uint64(j)] - ui - 0.0)
                if dist < free_d or (dist == free_d and j < free_j):
                    free_d = dist
                    free_j = j
                    free_row = i
            if ci != M + i:
                dist = min_val + (cost[iu, np.uint64(M)] - ui - 0.0)
                if dist < free_d or (dist == free_d and M + i < free_j):
                    free_d = dist
                    free_j = M + i
                    free_row = i
            if ci != M + P + i:
                dist = min_val + (cost[iu, np.uint64(M + 1)] - ui - 0.0)
                if dist < free_d or (dist == free_d and M + P + i < free_j):
                    free_d = dist
                    free_j = M + P + i
                    free_row = i
            # the closest column (ties: a free one, then the lower column)
            if index >= 0 and d[np.uint64(index)] < free_d:
                min_val = d[np.uint64(index)]
                i = _scan(pw, index, n_open, n_done)
                n_open -= 1
                n_done += 1
                continue
            if free_d == np.inf:
                return False
            min_val = free_d
            break
        # duals (with the old matching), then the path flipped from the free column found
        u[z, ru] += min_val - 0.0
        for t in range(n_done):
            tu = np.uint64(t)
            r = np.uint64(done[tu])
            x = min_val - done_d[tu]
            u[z, r] += x
            done_v[tu] -= x
            vs[z, r] = done_v[tu]
        v_sink = 0.0
        v_sink -= min_val - min_val
        r = free_row
        j = free_j
        vj = v_sink
        while True:
            rq = np.uint64(r)
            prev = cols[z, rq]
            cols[z, rq] = j
            vs[z, rq] = vj
            if r == root:
                break
            t = np.uint64(at[rq])  # the row's old column, scanned: reached from done_via
            j = prev
            vj = done_v[t]
            r = done_via[t]
        if free_j < M:  # the measurement is taken now
            t = 0
            while free[np.uint64(t)] != free_j:
                t += 1
            n_free -= 1
            free[np.uint64(t)] = free[np.uint64(n_free)]
    return True


#: :func:`murty_slice`: the search is over, a slice's budget is spent, an array is full.
DONE, PAUSED, FULL = 0, 1, 2


# ----------------------------------------------------------------------------- the records' arrays
@jit()
def _new_path_work(P, M):
    """A :data:`PathWork` for ``P`` rows and ``M`` measurements.

    Parameters
    ----------
    P, M : int
        Rows and measurements of the problem.

    Returns
    -------
    PathWork
        Uninitialised arrays: ``vf`` of ``M`` entries, the others of ``P``.
    """
    return PathWork(np.empty(P, dtype=np.int64), np.empty(P, dtype=np.int64),
                    np.empty(P, dtype=np.int64), np.empty(P), np.empty(P),
                    np.empty(P, dtype=np.int64), np.empty(P, dtype=np.int64), np.empty(P),
                    np.empty(P), np.empty(P, dtype=np.int64), np.empty(P, dtype=np.int64),
                    np.empty(M))


@jit()
def _new_tree(n, P):
    """An empty :data:`Tree` with room for ``n`` nodes of ``P`` rows.

    Parameters
    ----------
    n : int
        Nodes.
    P : int
        Rows (unused: a node's arrays do not depend on it).

    Returns
    -------
    Tree
        Uninitialised arrays of ``n`` entries.
    """
    return Tree(np.empty(n), np.empty(n, dtype=np.int64), np.empty(n, dtype=np.int64),
                np.empty(n, dtype=np.int64), np.empty(n, dtype=np.int64), np.empty(n),
                np.empty(n, dtype=np.int64))


@jit()
def _new_forbidden(n):
    """An empty :data:`Forbidden` with room for ``n`` entries.

    Parameters
    ----------
    n : int
        Entries.

    Returns
    -------
    Forbidden
        Uninitialised int64 arrays of ``n`` entries.
    """
    return Forbidden(np.empty(n, dtype=np.int64), np.empty(n, dtype=np.int64),
                     np.empty(n, dtype=np.int64))


@jit()
def _new_solutions(n, P):
    """An empty :data:`Solutions` with room for ``n`` solutions of ``P`` rows.

    Parameters
    ----------
    n : int
        Solutions.
    P : int
        Rows.

    Returns
    -------
    Solutions
        Uninitialised: ``cols``, ``u``, ``v`` of shape (n, P), the others (n,).
    """
    return Solutions(np.empty((n, P), dtype=np.int64), np.empty((n, P)), np.empty((n, P)),
                     np.empty(n), np.empty(n), np.empty(n), np.empty(n, dtype=np.int64))


@jit()
def _new_partition_work(P):
    """A :data:`PartitionWork` for ``P`` rows.

    Parameters
    ----------
    P : int
        Rows.

    Returns
    -------
    PartitionWork
        Uninitialised arrays of ``P`` entries; ``rc`` (P, P) when ``P <= RC_ROWS``, else
        (1, 1).
    """
    n = P if P <= RC_ROWS else 1
    return PartitionWork(np.empty(P, dtype=np.int64), np.empty(P, dtype=np.int64),
                         np.empty(P, dtype=np.int64), np.empty(P), np.empty(P, dtype=np.int64),
                         np.empty(P), np.empty((n, n)))


@jit()
def _grown_tree(t, n):
    """:data:`Tree` ``t`` copied into arrays with room for ``n`` nodes.

    Parameters
    ----------
    t : Tree
        The tree.
    n : int
        Nodes of the copy (at least as many as ``t`` holds).

    Returns
    -------
    Tree
    """
    return Tree(_grow(t.key, n), _grow(t.slot, n), _grow(t.parent, n), _grow(t.forb, n),
                _grow(t.end, n), _grow(t.heap_key, n), _grow(t.heap_id, n))


@jit()
def _grown_forbidden(f, n):
    """:data:`Forbidden` ``f`` copied into arrays with room for ``n`` entries.

    Parameters
    ----------
    f : Forbidden
        The lists.
    n : int
        Entries of the copy (at least as many as ``f`` holds).

    Returns
    -------
    Forbidden
    """
    return Forbidden(_grow(f.row, n), _grow(f.entry, n), _grow(f.next, n))


@jit()
def _grown_solutions(s, n):
    """:data:`Solutions` ``s`` copied into arrays with room for ``n`` solutions.

    Parameters
    ----------
    s : Solutions
        The solutions.
    n : int
        Solutions of the copy (at least as many as ``s`` holds).

    Returns
    -------
    Solutions
    """
    return Solutions(_grow(s.cols, n), _grow(s.u, n), _grow(s.v, n), _grow(s.v_free, n),
                     _grow(s.cost, n), _grow(s.scale, n), _grow(s.taken, n))


@jit()
def _grown_ranking(r, n_out, n_best):
    """:data:`Ranking` ``r`` with room for ``n_out`` reported nodes and ``n_best`` costs.

    Parameters
    ----------
    r : Ranking
        The ranking.
    n_out, n_best : int
        Room wanted in ``slot`` and ``kbest``; an array already that large is kept, not
        copied.

    Returns
    -------
    Ranking
    """
    slot, kbest = r
    if n_out > slot.shape[0]:
        slot = _grow(slot, n_out)
    if n_best > kbest.shape[0]:
        kbest = _grow(kbest, n_best)
    return Ranking(slot, kbest)


# ----------------------------------------------------------------------------- entry points
@jit()
def compact_costs(cc):
    """The :data:`CompactCosts` of a problem's compact costs ``cc`` ``(P, M + 2)``.

    Parameters
    ----------
    cc : ndarray of float64, shape (P, M + 2)
        Compact costs ``[measurements | missed | dead]``, ``+inf`` forbidding a pair.

    Returns
    -------
    CompactCosts
        ``cost`` and ``cost0``, two equal (P, M + 3) arrays: ``cc`` and a last column of
        ``+inf``.
    """
    P, W = cc.shape
    cost0 = np.empty((P, W + 1))
    for i in range(P):
        for o in range(W):
            cost0[i, o] = cc[i, o]
        cost0[i, W] = np.inf
    return CompactCosts(cost0.copy(), cost0)


@jit()
def new_search(cs, k):
    """The root's LSAP and a :data:`Search` with the root in the queue.

    Parameters
    ----------
    cs : CompactCosts
        The problem (:func:`compact_costs`), ``P >= 1`` rows.
    k : int
        Number of assignments wanted (>= 1).

    Returns
    -------
    ok : bool
        False when the problem has no feasible assignment (the search is then empty).
    search : tuple
        The search, packed (:func:`pack_search`).
    """
    P = cs.cost.shape[0]
    M = cs.cost.shape[1] - 3
    cap = max(_INITIAL_CAPACITY, 2 * P)
    out_cap = min(k, _INITIAL_CAPACITY)
    sr = Search(_new_path_work(P, M), _new_tree(cap, P), _new_forbidden(cap),
                _new_solutions(_INITIAL_CAPACITY, P),
                Ranking(np.empty(out_cap, dtype=np.int64), np.empty(out_cap)),
                _new_partition_work(P), np.zeros(N_STATE, dtype=np.int64))
    if not _root_lsap(cs, sr.path, sr.sols, np.empty(M, dtype=np.int64)):
        return False, pack_search(sr)
    sr.sols.v_free[0] = 0.0
    key0 = _store_cost(cs, sr.sols, 0)
    sr.ranking.kbest[0] = key0
    tree = sr.tree
    tree.key[0] = key0
    tree.slot[0] = 0
    tree.parent[0] = NO_ENTRY
    tree.forb[0] = NO_ENTRY
    tree.end[0] = NO_ENTRY
    tree.heap_key[0] = key0
    tree.heap_id[0] = 0
    state = sr.state
    state[S_HEAP] = 1
    state[S_NODES] = 1
    state[S_SOLS] = 1
    state[S_BEST] = 1
    return True, pack_search(sr)


@jit()
def murty_slice(costs, search, k, budget):
    """At most ``budget`` iterations of ``search``, in place.

    Parameters
    ----------
    costs : tuple
        The fields of the problem's :data:`CompactCosts` (``cost, cost0``).
    search : tuple
        A packed :data:`Search` (:func:`pack_search`).
    k : int
        Number of assignments wanted.
    budget : int
        Iterations in this call (``>= 1``).

    Returns
    -------
    int
        :data:`DONE`, :data:`PAUSED` (call again) or :data:`FULL` (an array is full:
        :func:`grow_search`, then call again). Only an integer comes back, so a signal that
        arrived during the call is raised by the caller as itself.
    """
    sr = unpack_search(search)
    if _search(CompactCosts(*costs), sr, k, budget):
        return DONE
    state = sr.state
    if _is_full(sr, k, state[S_OUT], state[S_SOLS], state[S_NODES], state[S_FORB],
                state[S_BEST]):
        return FULL
    return PAUSED


@jit()
def grow_search(search, k):
    """Packed ``search`` with every full array doubled (every array the next iteration may
    fill); ``k`` the number of assignments wanted (the output and kbest never need more).

    Parameters
    ----------
    search : tuple
        A packed :data:`Search` (:func:`pack_search`) whose last :func:`murty_slice`
        returned :data:`FULL`.
    k : int
        Number of assignments wanted.

    Returns
    -------
    tuple
        The packed search with the grown arrays (the others shared).
    """
    sr = unpack_search(search)
    P = sr.path.row.shape[0]
    state = sr.state
    tree, forb, sols, ranking = sr.tree, sr.forb, sr.sols, sr.ranking
    n_out = ranking.slot.shape[0]
    if state[S_OUT] == n_out:
        n_out = min(k, 2 * n_out)
    n_best = ranking.kbest.shape[0]
    if state[S_BEST] == n_best < k:
        n_best = min(k, 2 * n_best)
    ranking = _grown_ranking(ranking, n_out, n_best)
    if state[S_SOLS] == sols.cols.shape[0]:
        sols = _grown_solutions(sols, 2 * sols.cols.shape[0])
    if state[S_NODES] + P > tree.key.shape[0]:
        tree = _grown_tree(tree, 2 * tree.key.shape[0])
    if state[S_FORB] + P > forb.row.shape[0]:
        forb = _grown_forbidden(forb, 2 * forb.row.shape[0])
    return pack_search(Search(sr.path, tree, forb, sols, ranking, sr.part, state))


@jit()
def search_output(search):
    """The reported assignments ``(n, P)`` and their costs ``(n,)`` of a finished (packed)
    search, as documented in :func:`murty_compact_kernel`.

    Parameters
    ----------
    search : tuple
        A packed :data:`Search` whose :func:`murty_slice` returned :data:`DONE`.

    Returns
    -------
    assignments : ndarray of int64, shape (n, P)
        As in :func:`murty_compact_kernel`.
    costs : ndarray of float64, shape (n,)
        Non-decreasing (a stable sort by value).
    """
    sr = unpack_search(search)
    P = sr.path.row.shape[0]
    cols, cost, out_slot = sr.sols.cols, sr.sols.cost, sr.ranking.slot
    n_out = sr.state[S_OUT]
    out = np.empty((n_out, P), dtype=np.int64)
    out_cost = np.empty(n_out)
    for t in range(n_out):
        out_cost[t] = cost[out_slot[t]]
        for i in range(P):
            out[t, i] = cols[out_slot[t], i]
    # A stable insertion sort removes the rare last-bit inversion between a node and a child
    # of equal cost summed in another order (the output is already sorted up to those).
    row = np.empty(P, dtype=np.int64)
    for t in range(1, n_out):
        x = out_cost[t]
        if not x < out_cost[t - 1]:
            continue
        for i in range(P):
            row[i] = out[t, i]
        b = t - 1
        while b >= 0 and x < out_cost[b]:
            out_cost[b + 1] = out_cost[b]
            for i in range(P):
                out[b + 1, i] = out[b, i]
            b -= 1
        out_cost[b + 1] = x
        for i in range(P):
            out[b + 1, i] = row[i]
    return out, out_cost


@jit(inline="always")
def murty_start(cs, k, budget):
    """:func:`new_search` and its first ``budget`` iterations (:func:`murty_slice`), written
    into :func:`murty_compact_start` (``inline="always"``), so that the search is compiled
    into that one entry and not optimised once more for this one.

    Parameters
    ----------
    cs : CompactCosts
        The problem (:func:`compact_costs`), ``P >= 1`` rows.
    k, budget : int
        As in :func:`murty_slice`.

    Returns
    -------
    tuple
        ``(assignments, costs, None)`` as documented in :func:`murty_compact_kernel` when the
        search ends within the budget (one call: small searches cost what they cost before),
        else ``(empty, empty, search)`` with the packed :data:`Search` to continue.
    """
    P = cs.cost.shape[0]
    ok, search = new_search(cs, k)
    if not ok:
        return np.empty((0, P), dtype=np.int64), np.empty(0), None
    costs = cs[:]
    status = _murty_slice_inline(costs, search, k, budget)
    while status == FULL:
        search = grow_search(search, k)
        done = unpack_search(search).state[S_ITER]
        status = _murty_slice_inline(costs, search, k, max(1, budget - done))
    if status == DONE:
        out, out_costs = search_output(search)
        return out, out_costs, None
    return np.empty((0, P), dtype=np.int64), np.empty(0), search


@jit()
def murty_compact_start(cc, k, budget):
    """:func:`murty_start` on a problem's compact costs ``(P, M + 2)``, ``P >= 1``.

    Parameters
    ----------
    cc : ndarray of float64, shape (P, M + 2)
        As in :func:`murty_compact_kernel`.
    k, budget : int
        As in :func:`murty_slice`.

    Returns
    -------
    tuple
        ``(assignments, costs, None)`` when done within the budget, else ``(empty, empty,
        (costs, search))`` with the fields of the problem's :data:`CompactCosts` (from
        :func:`compact_costs`) and the packed search to continue with :func:`murty_slice`.
    """
    cs = compact_costs(cc)
    out, out_costs, search = murty_start(cs, k, budget)
    if search is None:
        return out, out_costs, None
    return out, out_costs, (cs[:], search)


@jit()
def murty_compact_kernel(cc, k):
    """Murty's ranked assignment with the Miller–Stone–Cox improvements.

    Parameters
    ----------
    cc : ndarray, float64, shape (P, M + 2)
        A problem's compact costs (:attr:`rankedassign.AssignmentProblem.compact_cost`:
        the measurements, the row's missed and its dead entry; ``+inf`` forbids a pair),
        ``P >= 1``, with at least one feasible assignment.
    k : int
        Number of assignments wanted (>= 1).

    Returns
    -------
    assignments : ndarray, int64, shape (n, P)
        The ``n = min(k, |Gamma|)`` best assignments as columns of the ``P x (M + 2P)``
        layout (``M + i`` missed, ``M + P + i`` dead for row ``i``), best first; among equal
        costs, in the order of creation of their nodes.
    costs : ndarray, float64, shape (n,)
        Their costs summed row by row from ``0.0`` (bit for bit
        ``AssignmentProblem.cost_of``), non-decreasing: a child's cost can come out one ulp
        below its parent's (sums of equal value in different orders), and a final stable
        sort by value puts it first (the order of the search otherwise).

    Notes
    -----
    Each node of the partition tree is a subproblem: rows fixed to their parent's columns and
    a set of forbidden pairs (a linked list shared with the ancestors). Popping a solved node
    with solution ``s`` reports ``s`` and creates one child per free row ``r``: forbid
    ``(r, s[r])`` and fix the rows processed before it. Rows are processed in decreasing
    order of ``lb[r]``, the smallest reduced cost of an allowed alternative for row ``r``
    (partition ordering). A child enters the queue with the lower bound ``cost(s) + lb[r]``
    (lazy evaluation, Miller, Stone & Cox 1997, spec §5.1 item 2), raised by the least
    reduced cost of the last step of its path and, where the partition's table of reduced
    costs allows, by its second step (:func:`_make_children`), and is solved only if it
    reaches the top, by one shortest augmenting path from its parent's duals and assignment
    minus ``(r, s[r])`` (item 1), then re-enters with its exact cost. A bound never exceeds
    the cost it bounds, so the output is that of solving every child at once, in the same
    order. The heap orders nodes by ``(key, node id)``: equal keys leave in order of
    creation.

    Rectangular LSAP is the square problem in which every free column is held by a zero-cost
    dummy row; all free columns share one implicit potential ``v_free`` (see
    :mod:`.lsap`). A solution is stored with its row duals ``u``, the dual ``v`` of each
    row's column and ``v_free``: ``O(P)`` numbers, not ``O(M + P)``. A solve works on the
    subproblem's open rows (module notes): a step relaxes one row into the open rows'
    columns, ``O(P)``, and into the free columns, ``O(M)`` while the hub is closed and some
    measurement is free, ``O(1)`` otherwise. The root is a cold LSAP (:func:`_root_lsap`).

    References
    ----------
    .. [1] K. G. Murty, "An Algorithm for Ranking all the Assignments in Order of Increasing
       Cost", Operations Research 16(3):682–687, 1968.
    .. [2] M. L. Miller, H. S. Stone, I. J. Cox, "Optimizing Murty's Ranked Assignment
       Method", IEEE Trans. Aerosp. Electron. Syst. 33(3), 1997.
    """
    # The loop of murty_start without its slices, written out: the δ-GLMB filter's
    # per-component loop calls this kernel, and numba optimises and compiles a callee's machine
    # code again in each caller it is linked into, so the two levels between here and _search
    # (murty_start, murty_slice) cost seconds of a first filter step's compile. One call runs
    # every iteration (an unbounded budget), as murty_start's slices together do. The budget
    # is an int64, not a literal: numba compiles a callee once per literal argument value, and
    # murty_start(cc, k, 1 << 62) compiled _search twice (the literal, then int64 after a
    # grow_search), about 12 s each.
    cs = compact_costs(cc)
    ok, search = new_search(cs, k)
    if not ok:
        return np.empty((0, cc.shape[0]), dtype=np.int64), np.empty(0)
    unbounded = np.int64(1 << 62)
    while not _search(cs, unpack_search(search), k, unbounded):
        search = grow_search(search, k)  # only an array can be full: the budget is unbounded
    return search_output(search)


#: :func:`murty_compact_kernel` written into its caller (numba's ``inline="always"``), for a
#: compiled loop that ranks many problems (the δ-GLMB filter's components). Called as a
#: function of its own, the kernel's whole search (:func:`_search` and the functions around
#: it, linked into it) is optimised and compiled once more for it and once more for the loop;
#: written in, only for the loop. A first δ-GLMB step with Murty took 4–7 s less (see
#: ``benchmarks/README.md``, "Ninth pass"); the code that runs is the same.
murty_compact_inline = instantiate(getattr(murty_compact_kernel, "py_func", murty_compact_kernel),
                                   "murty_compact_inline", {}, inline="always")

#: :func:`murty_slice` written into :func:`murty_start` (which is written into
#: :func:`murty_compact_start`): the first call of :func:`oracle.murty` compiles the search
#: into one entry, and :func:`murty_slice` only when a ranking needs a second slice.
_murty_slice_inline = instantiate(getattr(murty_slice, "py_func", murty_slice),
                                  "murty_slice_inline", {}, inline="always")

"""Compiled Murty k-best ranked assignment (spec §5.1) with the Miller–Stone–Cox improvements.

The driver :func:`murty_kernel` takes the best open subproblem of the partition tree. A node
that is only *bounded* is solved (one warm-started shortest augmenting path) and goes back
into the queue with its exact cost; a *solved* node is reported and partitioned: its children
enter the queue with a lower bound only, so most of them are never solved. Once ``k - n``
solved nodes wait in the queue (``n`` reported), the largest of their costs (a max-heap of
the least solved costs keeps it) is a cut: a solve stops as soon as its node is proven to
cost more, and a child bounded above it is not created (under the cut a child's bound is its
own first step: its row's least reduced cost with the columns of the rows fixed before it
inactive too). Neither can ever be reported, so the output is unchanged. Forbidden pairs
are switched on and off in the shared graph's ``cost`` array. Costs are accumulated row by
row in the order ``0..P-1`` from ``0.0``, exactly as
:meth:`rankedassign.AssignmentProblem.cost_of` does.

Records. The search's state is a :data:`Search` of named records: the assignment state of the
node at hand (:data:`.lsap.Matching`), the workspace of one augmenting path
(:data:`PathWork`), the partition tree and its queue (:data:`Tree`), the forbidden-pair lists
(:data:`Forbidden`), the solved nodes (:data:`Solutions`), the output and the cut
(:data:`Ranking`), the partition's scratch (:data:`PartitionWork`) and the counters
(``state``, indexed by ``S_*``); the problem is a :data:`.lsap.Graph`. A record crosses into
Python as a plain tuple (:func:`pack_search`; see :mod:`rankedassign.numba_options`,
"Signals").

Layout for speed. The search (:func:`_search`) is one compiled loop on flat arrays that it
never reallocates: the warm-started augmenting path (the algorithm of
:func:`.lsap.sap_augment`, same arithmetic and tie-breaking) runs on the search's own arrays,
and the tree, the solutions, the forbidden-pair lists and the heap are plain arrays indexed by
integers. When an array is full the loop returns, the arrays are grown (:func:`grow_search`)
and it is called again. At these sizes (tens of rows, about one augmenting path of one or two
row scans per reported assignment) calls between compiled functions that each receive a dozen
arrays, array views made per node and arrays rebound inside the loop (each costs atomic
reference count updates) cost as much as the arithmetic. The loop's phases (solve a node:
:func:`_solve_node`; partition one: :func:`_partition`; the heap's sift-down and push) are
functions of their own, compiled with ``inline="always"``: numba writes each into its caller
before typing, so the loop is still one function and nothing is called, allocated or
reference-counted per node. Further savings that leave every result bit for bit unchanged:
the partition's bounds read each column's dual from one array (``-inf`` for the columns of
fixed rows) without branches; the top of the heap is replaced in one sift-down (by the node
itself once solved, by its first child once partitioned); a scanned column is marked by
``d = -inf``; and a warm start keeps only the closest free column of its first row when that
column opens the dummy-row hub (the other free columns would leave the frontier unscanned).

Slices. The loop also returns after a budget of iterations, so that :func:`oracle.murty`
can run the search in slices (:func:`murty_compact_start`, then :func:`murty_slice` until
done, the state a packed :data:`Search`) and a signal ends a long ranking promptly; the slices
make the same iterations as one call, so the output does not depend on the budget.
"""

from __future__ import annotations

from collections import namedtuple

import numpy as np

from rankedassign.numba_options import jit

from .lsap import HUB, UNASSIGNED, Graph, Matching, new_matching

__all__ = ["murty_kernel", "murty_compact_kernel", "murty_start", "murty_slice", "grow_search",
           "search_output", "pack_search", "unpack_search", "compact_graph",
           "murty_compact_start", "Search", "PathWork", "Tree", "Forbidden", "Solutions",
           "Ranking", "PartitionWork", "DONE", "PAUSED", "FULL"]

NO_ENTRY = -1  # end of a forbidden-pair list; slot of a node that is not solved yet
_INITIAL_CAPACITY = 1024
# Relative slack subtracted from a lower bound so that rounding can never lift it above the
# exact cost it bounds (the order of the output then equals that of solving every child).
_BOUND_SLACK = 1e-9

# ----------------------------------------------------------------------------- records
#: Workspace of one shortest augmenting path: ``d`` (N,) the distance of each column
#: (``+inf`` unreached, ``-inf`` scanned), ``path`` (N,) the row it was reached from (or
#: ``HUB``), ``cand`` (N,) the reached, unscanned columns, ``touched`` (N,) every column whose
#: distance was set (to clean ``d``), ``done``, ``done_d`` (N,) the scanned columns and their
#: distances, ``rows``, ``rows_d`` (P,) the scanned rows and their distances.
PathWork = namedtuple("PathWork", ["d", "path", "cand", "touched", "done", "done_d", "rows",
                                   "rows_d"])

#: The partition tree and its queue, per node: ``key`` its heap key (exact cost once solved, a
#: lower bound before), ``slot`` its solution (``NO_ENTRY`` until solved), ``parent`` the slot
#: of its parent's solution, ``forb`` the head of its forbidden-pair list (its own pair first,
#: then the ancestors'), ``fixed`` (n, ceil(P / 64)) the rows fixed to the parent's columns as
#: bits, 64 to a word; ``heap_key``, ``heap_id`` the binary heap of ``(key, node id)``.
Tree = namedtuple("Tree", ["key", "slot", "parent", "forb", "fixed", "heap_key", "heap_id"])

#: The forbidden-pair lists (a node's list continues into its ancestors'): per entry the
#: ``row``, the graph ``entry`` and the ``next`` entry (``NO_ENTRY`` ends a list).
Forbidden = namedtuple("Forbidden", ["row", "entry", "next"])

#: Solved nodes: ``cols`` (n, P) the assignment, ``u`` (n, P) the row duals, ``v`` (n, P) the
#: dual of each row's column, ``v_free`` the free columns' shared potential, ``cost`` the exact
#: cost and ``scale`` the rounding scale of its children's solves (set when it is partitioned).
Solutions = namedtuple("Solutions", ["cols", "u", "v", "v_free", "cost", "scale"])

#: The output and the cut: ``slot``, ``cost`` the solution slot and cost of each reported node,
#: ``kbest`` a max-heap of the least solved costs.
Ranking = namedtuple("Ranking", ["slot", "cost", "kbest"])

#: Scratch of a partition (``vx`` also of a solve), per row: ``entry_of`` the graph entry of
#: its column, ``order`` the free rows by decreasing bound, ``lb`` its bound and ``lb_col`` the
#: column that gives it; ``fix_now`` the rows fixed so far as bits; ``vx`` (N,) the dual
#: subtracted for each column (``-inf``: inactive).
PartitionWork = namedtuple("PartitionWork", ["entry_of", "order", "lb", "lb_col", "fix_now",
                                             "vx"])

#: The search's state between two calls of :func:`murty_slice`: the assignment state
#: (:data:`.lsap.Matching`), the path workspace, the tree, the forbidden pairs, the solutions,
#: the ranking, the partition's scratch and the counters ``state`` (int64, ``S_*``).
Search = namedtuple("Search", ["match", "path", "tree", "forb", "sols", "ranking", "part",
                               "state"])

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

#: The end of one shortest augmenting path (:func:`_shortest_path`): the column it reached
#: (``-1``: none, or the node was dropped by the cut), its distance, the rows and columns
#: scanned, the columns touched, and the dummy-held column that opened the hub (``-1``: the hub
#: stayed closed) with its distance.
PathEnd = namedtuple("PathEnd", ["sink", "min_val", "n_rows", "n_done", "n_touched", "hub_src",
                                 "hub_dist"])


@jit()
def pack_search(sr):
    """A :data:`Search` as plain tuples, the form it crosses into Python in.

    numba boxes a named tuple by calling its class, Python code, where a signal handler's
    exception crashes numba's return path (a segmentation fault, not an error); a plain tuple
    is built in C and only ever raises. :func:`unpack_search` names it again in compiled code.
    """
    return (sr.match[:], sr.path[:], sr.tree[:], sr.forb[:], sr.sols[:], sr.ranking[:],
            sr.part[:], sr.state)


@jit(inline="always")
def unpack_search(t):
    """The :data:`Search` of a packed one (:func:`pack_search`)."""
    return Search(Matching(*t[0]), PathWork(*t[1]), Tree(*t[2]), Forbidden(*t[3]),
                  Solutions(*t[4]), Ranking(*t[5]), PartitionWork(*t[6]), t[7])


# ----------------------------------------------------------------------------- small helpers
@jit()
def _grow(a, n):
    """``a`` copied into a new array with ``n`` rows (first axis)."""
    out = np.empty((n,) + a.shape[1:], dtype=a.dtype)
    out[: a.shape[0]] = a
    return out


@jit(inline="always")
def _sift_down_max(a, n, h, x):
    """Put ``x`` at ``h`` in the max-heap ``a[:n]`` and move it down to its place."""
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
def _least_reduced_cost(ptr, col, cost, vx, i, ui):
    """The least ``cost - u_i - vx[j]`` over row ``i``'s entries (the partition's bounds)."""
    best = np.inf
    for e in range(np.uint64(ptr[i]), np.uint64(ptr[i + 1])):
        best = min(best, cost[e] - ui - vx[np.uint64(col[e])])
    return best


@jit(inline="always")
def _switch_off(cost, forb, head):
    """Forbid every pair of the list that starts at ``head``: its cost becomes ``+inf``."""
    g = head
    while g != NO_ENTRY:
        cost[forb.entry[g]] = np.inf
        g = forb.next[g]


@jit(inline="always")
def _switch_on(cost, cost0, forb, head):
    """Allow the pairs of the list that starts at ``head`` again (their costs from ``cost0``)."""
    g = head
    while g != NO_ENTRY:
        e = forb.entry[g]
        cost[e] = cost0[e]
        g = forb.next[g]


@jit(inline="always")
def _is_full(sr, k, n_out, n_sols, n_nodes, n_forb, n_best):
    """Whether some array of ``sr`` lacks room for the next iteration's worst case (``P``
    children; kbest never holds more than ``k``)."""
    P = sr.match.col4row.shape[0]
    return (n_out == sr.ranking.slot.shape[0] or n_sols == sr.sols.cols.shape[0]
            or n_nodes + P > sr.tree.key.shape[0] or n_forb + P > sr.forb.row.shape[0]
            or n_best == sr.ranking.kbest.shape[0] < k)


# ----------------------------------------------------------------------------- solve a node
@jit(inline="always")
def _load_warm_start(g, m, vx, tree, forb, sols, node):
    """Load the warm start of the bounded ``node`` into ``m``: its parent's duals and
    assignment minus ``(root, freed)``, its fixed rows' columns inactive and its forbidden
    pairs switched off; ``vx`` the dual of each column (``-inf`` if inactive), as in the
    partition. Returns ``(root, freed, v_free)``."""
    cost = g.cost
    u, v, col4row, row4col, active = m
    fixed = tree.fixed
    s_cols, s_u, s_v = sols.cols, sols.u, sols.v
    P = col4row.shape[0]
    ps = tree.parent[node]
    f = tree.forb[node]
    root = forb.row[f]
    v_free = sols.v_free[ps]
    vx[:] = v_free
    for i in range(P):
        c = s_cols[ps, i]
        col4row[i] = c
        row4col[c] = i
        vc = s_v[ps, i]
        v[c] = vc  # free columns: the shared potential, never read
        if (fixed[node, i >> 6] >> (i & 63)) & 1:
            active[c] = False  # a fixed row's column is out of the residual problem
            vx[c] = -np.inf
        else:
            vx[c] = vc
        u[i] = s_u[ps, i]
    freed = s_cols[ps, root]
    col4row[root] = UNASSIGNED
    row4col[freed] = UNASSIGNED
    _switch_off(cost, forb, f)
    return root, freed, v_free


@jit(inline="always")
def _scan_root(g, m, pw, vx, root, freed):
    """Scan the root's row first, when nothing is reached yet; returns ``(n_cand, index)``.

    Every allowed, active entry is reached (``vx`` gives ``+inf`` for the others), and the
    closest column is picked in the same pass. Of the dummy-held (free) columns only the
    closest is kept at first: when it is the closest of all, the hub opens through it and the
    other free columns would leave the frontier unscanned anyway; otherwise a second pass
    reaches them too. The reached columns are the first ``n_cand`` touched ones.
    """
    ptr, col, cost = g.ptr, g.col, g.cost
    row4col = m.row4col
    d, path, cand, touched = pw.d, pw.path, pw.cand, pw.touched
    n_cand = 0
    min_val = 0.0
    ui = m.u[root]
    index = -1  # the closest matched (or the freed) column
    lowest = np.inf
    best_ends = False
    best_j = -1
    free_low = np.inf  # the closest free column
    free_j = -1
    for e in range(np.uint64(ptr[root]), np.uint64(ptr[root + 1])):
        j = col[e]
        ju = np.uint64(j)  # unsigned indices: no negative-index wraparound
        dist = min_val + (cost[e] - ui - vx[ju])
        if dist < np.inf:
            if row4col[ju] < 0 and j != freed:
                if dist < free_low or (dist == free_low and j < free_j):
                    free_low = dist
                    free_j = j
                continue
            cand[np.uint64(n_cand)] = j
            d[ju] = dist
            path[ju] = root
            ends = j == freed
            if dist < lowest or (dist == lowest and ((ends and not best_ends)
                                                     or (ends == best_ends and j < best_j))):
                lowest = dist
                index = n_cand
                best_ends = ends
                best_j = j
            n_cand += 1
    if free_j >= 0:
        if index < 0 or free_low < lowest or (free_low == lowest and not best_ends
                                              and free_j < best_j):
            cand[n_cand] = free_j  # the closest of all: the only free one needed
            d[free_j] = free_low
            path[free_j] = root
            index = n_cand
            n_cand += 1
        else:
            for e in range(np.uint64(ptr[root]), np.uint64(ptr[root + 1])):
                j = col[e]
                ju = np.uint64(j)
                if row4col[ju] < 0 and j != freed:
                    dist = min_val + (cost[e] - ui - vx[ju])
                    if dist < np.inf:
                        cand[np.uint64(n_cand)] = j
                        d[ju] = dist
                        path[ju] = root
                        n_cand += 1
    for t in range(n_cand):
        touched[t] = cand[t]
    return n_cand, index


@jit(inline="always")
def _open_hub(m, pw, freed, v_free, min_val, n_cand, n_touched):
    """A dummy-held column was scanned at ``min_val``: open the hub, every column reachable
    through it (the dummy rows' edges, reduced cost ``v_free - v[k]``); the dummy-held columns
    leave the frontier. Returns ``(n_cand, n_touched)``."""
    v, col4row, row4col, active = m.v, m.col4row, m.row4col, m.active
    d, path, cand, touched = pw.d, pw.path, pw.cand, pw.touched
    P = col4row.shape[0]
    it = 0
    while it < n_cand:
        q = cand[it]
        if row4col[q] < 0 and q != freed:
            n_cand -= 1
            cand[it] = cand[n_cand]
        else:
            it += 1
    for q in range(-1, P):
        kk = freed if q < 0 else col4row[q]
        if kk >= 0 and active[kk] and d[kk] != -np.inf:
            dist = min_val + (v_free - v[kk])
            if dist < d[kk]:
                if d[kk] == np.inf:
                    cand[n_cand] = kk
                    n_cand += 1
                    touched[n_touched] = kk
                    n_touched += 1
                d[kk] = dist
                path[kk] = HUB
    return n_cand, n_touched


@jit(inline="always")
def _scan_row(g, m, pw, i, freed, v_free, hub_open, min_val, n_cand, n_touched):
    """Relax the entries of the matched row ``i``, reached at ``min_val``; returns
    ``(n_cand, n_touched)``."""
    ptr, col, cost = g.ptr, g.col, g.cost
    v, row4col, active = m.v, m.row4col, m.active
    d, path, cand, touched = pw.d, pw.path, pw.cand, pw.touched
    ui = m.u[i]
    for e in range(ptr[i], ptr[i + 1]):
        cij = cost[e]
        j = col[e]
        if cij == np.inf or not active[j]:  # scanned: d[j] = -inf
            continue
        if row4col[j] < 0 and j != freed:  # dummy-held: the shared potential
            if hub_open:
                continue
            dist = min_val + (cij - ui - v_free)
        else:
            dist = min_val + (cij - ui - v[j])
        if dist < d[j]:
            if d[j] == np.inf:
                cand[n_cand] = j
                n_cand += 1
                touched[n_touched] = j
                n_touched += 1
            d[j] = dist
            path[j] = i
    return n_cand, n_touched


@jit(inline="always")
def _closest(pw, n_cand, freed):
    """Index in ``cand`` of the closest reached column; ties: the freed column, then the
    lowest index (``-1``: none)."""
    cand, d = pw.cand, pw.d
    index = -1
    lowest = np.inf
    best_ends = False
    best_j = -1
    for it in range(n_cand):
        j = cand[it]
        dj = d[j]
        if dj > lowest:
            continue
        ends = j == freed
        if dj < lowest or (ends and not best_ends) or (ends == best_ends and j < best_j):
            lowest = dj
            index = it
            best_ends = ends
            best_j = j
    return index


@jit(inline="always")
def _shortest_path(g, m, pw, root, freed, v_free, base, cut, n_cand, index):
    """Dijkstra from ``root`` (its row already scanned: :func:`_scan_root`) until ``freed`` is
    scanned, or until the node, of cost ``base`` plus the distance, is proven dearer than
    ``cut``; returns the :data:`PathEnd`."""
    row4col = m.row4col
    d, cand, done, done_d, rows, rows_d = pw.d, pw.cand, pw.done, pw.done_d, pw.rows, pw.rows_d
    n_rows = 1
    rows[0] = root
    rows_d[0] = 0.0
    n_done = 0
    n_touched = n_cand
    min_val = 0.0
    sink = -1
    hub_src = -1
    hub_dist = 0.0
    while index >= 0:
        j = cand[index]
        n_cand -= 1
        cand[index] = cand[n_cand]
        min_val = d[j]
        done[n_done] = j  # scanned: its distance kept in done_d, d[j] = -inf
        done_d[n_done] = min_val
        n_done += 1
        d[j] = -np.inf
        if j == freed:
            sink = j
            break
        elif base + min_val > cut:  # the node costs at least this much: drop it
            break
        elif row4col[j] < 0:
            m.v[j] = v_free  # about to be matched: its potential made explicit
            hub_src = j
            hub_dist = min_val
            n_cand, n_touched = _open_hub(m, pw, freed, v_free, min_val, n_cand, n_touched)
        else:  # scan row i
            i = row4col[j]
            rows[n_rows] = i
            rows_d[n_rows] = min_val
            n_rows += 1
            n_cand, n_touched = _scan_row(g, m, pw, i, freed, v_free, hub_src >= 0, min_val,
                                          n_cand, n_touched)
        index = _closest(pw, n_cand, freed)
    return PathEnd(sink, min_val, n_rows, n_done, n_touched, hub_src, hub_dist)


@jit(inline="always")
def _augment(m, pw, root, end, v_free):
    """Dual update (with the old matching), then flip the path of ``end``; returns the new
    ``v_free``."""
    u, v, col4row, row4col = m.u, m.v, m.col4row, m.row4col
    rows, rows_d, done, done_d, path = pw.rows, pw.rows_d, pw.done, pw.done_d, pw.path
    min_val = end.min_val
    for t in range(end.n_rows):  # (min_val - 0.0 is min_val for the root)
        u[rows[t]] += min_val - rows_d[t]
    for t in range(end.n_done):
        v[done[t]] -= min_val - done_d[t]
    if end.hub_src >= 0:
        v_free = v_free - (min_val - end.hub_dist)
    j = end.sink
    while True:
        r = path[j]
        if r == HUB:
            row4col[j] = UNASSIGNED  # j is handed to a dummy row: free again
            j = end.hub_src
            continue
        row4col[j] = r
        prev = col4row[r]
        col4row[r] = j
        if r == root:
            break
        j = prev
    return v_free


@jit(inline="always")
def _solve_node(g, sr, node, cut):
    """Solve the bounded ``node`` by one shortest augmenting path from its parent's duals
    and assignment minus ``(root, freed)`` (:func:`.lsap.sap_augment`, warm start), unless
    the cut drops it. Returns ``(solved, v_free)``: when solved its solution is in
    ``sr.match`` (store it with :func:`_store_solution`), else the matching is cleared."""
    m, pw, tree, forb, sols = sr.match, sr.path, sr.tree, sr.forb, sr.sols
    ps = tree.parent[node]
    base = sols.cost[ps]
    # the margin for rounding: the parent's, set when it was partitioned
    cut += _BOUND_SLACK * (sols.scale[ps] + abs(cut))  # (+inf stays +inf)
    vx = sr.part.vx
    root, freed, v_free = _load_warm_start(g, m, vx, tree, forb, sols, node)
    n_cand, index = _scan_root(g, m, pw, vx, root, freed)
    end = _shortest_path(g, m, pw, root, freed, v_free, base, cut, n_cand, index)
    if end.sink >= 0:
        v_free = _augment(m, pw, root, end, v_free)
    d, touched = pw.d, pw.touched
    for t in range(end.n_touched):  # clean workspace (path is only read where reached)
        d[touched[t]] = np.inf
    _switch_on(g.cost, g.cost0, forb, tree.forb[node])
    if end.sink < 0:
        col4row, row4col, active = m.col4row, m.row4col, m.active
        col4row[root] = freed  # restore the loaded matching so that it can be cleared
        row4col[freed] = root
        for i in range(col4row.shape[0]):
            c = col4row[i]
            row4col[c] = UNASSIGNED
            active[c] = True
    return end.sink >= 0, v_free


@jit(inline="always")
def _store_solution(g, m, sols, s, v_free):
    """Store the assignment state ``m`` as solution ``s`` and clear the matching (every
    column active again); returns its cost, summed row by row from ``0.0``."""
    cost0, pos = g.cost0, g.pos
    u, v, col4row, row4col, active = m
    s_cols, s_u, s_v = sols.cols, sols.u, sols.v
    key = 0.0
    for i in range(col4row.shape[0]):
        c = col4row[i]
        s_cols[s, i] = c
        s_u[s, i] = u[i]
        s_v[s, i] = v[c]
        key += cost0[pos[i, c]]
        row4col[c] = UNASSIGNED
        active[c] = True
    sols.v_free[s] = v_free
    sols.cost[s] = key
    return key


@jit(inline="always")
def _keep_least(kbest, n_best, n_stale, want, key):
    """Keep the ``want`` least solved costs in ``kbest`` (``n_stale`` of its ``n_best``
    entries belong to reported nodes): appended until there are that many, then a max-heap
    (made once) whose top is replaced. Returns the new ``n_best``."""
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
def _load_partition(g, part, tree, sols, node, sl, key):
    """Prepare the partition of the solved ``node`` (solution ``sl``, cost ``key``): the rows
    it fixes (``fix_now``), the graph entry of each row's column and ``vx[j]``, the dual the
    bounds subtract for column ``j``: the shared potential for a free column, ``v`` of its row
    for a matched one, ``-inf`` for the column of a fixed row (inactive: its reduced cost is
    ``+inf``), so the scan has no branch. Returns the rounding scale of its children's solves
    (also stored in ``sols.scale[sl]``)."""
    cost0, pos = g.cost0, g.pos
    entry_of, fix_now, vx = part.entry_of, part.fix_now, part.vx
    s_cols, s_u, s_v = sols.cols, sols.u, sols.v
    vx[:] = sols.v_free[sl]
    slack = 1.0 + abs(key)
    for w in range(fix_now.shape[0]):
        fix_now[w] = tree.fixed[node, w]
    for i in range(entry_of.shape[0]):
        c = s_cols[sl, i]
        e = pos[i, c]
        entry_of[i] = e
        slack += abs(cost0[e]) + abs(s_u[sl, i])
        vx[c] = -np.inf if (fix_now[i >> 6] >> (i & 63)) & 1 else s_v[sl, i]
    sols.scale[sl] = slack
    return slack


@jit(inline="always")
def _order_rows(g, part, sols, sl, cut):
    """The bound ``lb[i]`` of each free row's child, the smallest reduced cost of an allowed,
    active alternative ``j != s[i]`` (and under a cut the column ``lb_col[i]`` that gives it),
    and ``order``: the free rows by decreasing bound, ties in row order (partition ordering).
    Returns the number of free rows."""
    ptr, col, cost, cost0 = g.ptr, g.col, g.cost, g.cost0
    entry_of, order, lb, lb_col, fix_now, vx = part
    s_u = sols.u
    n_free = 0
    for i in range(entry_of.shape[0]):
        if (fix_now[i >> 6] >> (i & 63)) & 1:
            continue
        ei = entry_of[i]
        cost[ei] = np.inf  # the row's own entry is no alternative
        best = np.inf
        ui = s_u[sl, i]
        if cut == np.inf:
            best = _least_reduced_cost(ptr, col, cost, vx, i, ui)
        else:  # the same, and which column gives it (for the children's bounds)
            best_col = -1
            for e in range(np.uint64(ptr[i]), np.uint64(ptr[i + 1])):
                rc = cost[e] - ui - vx[np.uint64(col[e])]
                if rc < best:
                    best = rc
                    best_col = col[e]
            lb_col[i] = best_col
        cost[ei] = cost0[ei]
        x = max(best, 0.0)
        lb[i] = x
        # insert row i, keeping decreasing bounds (ties keep row order)
        b = n_free - 1
        while b >= 0 and lb[order[b]] < x:
            order[b + 1] = order[b]
            b -= 1
        order[b + 1] = i
        n_free += 1
    return n_free


@jit(inline="always")
def _make_children(g, sr, node, key, slack, cut, n_free, n_nodes, n_forb):
    """Create the children of the solved ``node`` (cost ``key``): child ``t`` forbids
    ``(order[t], s[order[t]])`` and fixes ``order[:t]``; a child whose bound (minus
    ``slack``, the rounding margin) exceeds ``cut`` is not created. Returns ``(n_nodes,
    n_forb)``."""
    ptr, col, cost, cost0 = g.ptr, g.col, g.cost, g.cost0
    entry_of, order, lb, lb_col, fix_now, vx = sr.part
    tree, forb, sols = sr.tree, sr.forb, sr.sols
    sl = tree.slot[node]
    head = tree.forb[node]
    for t in range(n_free):
        r = order[t]
        bx = lb[r]
        if t > 0 and bx < np.inf and cut < np.inf and vx[lb_col[r]] == -np.inf:
            # Under a cut, child t's bound is its own first step: lb[r] again, with the
            # columns of the rows fixed before it (order[:t]) inactive as well. It is the
            # distance its solve would pop first, so a child that the solve would drop there
            # is not created. (Unless the column that gave lb[r] is now inactive, that is
            # lb[r] itself.)
            ei = entry_of[r]
            cost[ei] = np.inf
            bx = _least_reduced_cost(ptr, col, cost, vx, r, sols.u[sl, r])
            cost[ei] = cost0[ei]
            bx = max(bx, 0.0)
        if bx < np.inf and key + bx - slack <= cut:
            forb.row[n_forb] = r
            forb.entry[n_forb] = entry_of[r]
            forb.next[n_forb] = head
            ck = key + bx - slack
            tree.key[n_nodes] = ck
            tree.slot[n_nodes] = NO_ENTRY
            tree.parent[n_nodes] = sl
            tree.forb[n_nodes] = n_forb
            for w in range(fix_now.shape[0]):
                tree.fixed[n_nodes, w] = fix_now[w]
            n_forb += 1
            n_nodes += 1
        fix_now[r >> 6] |= np.int64(1) << (r & 63)  # later children: row r stays
        vx[sols.cols[sl, r]] = -np.inf  # (its column, for the bounds of the later ones)
    return n_nodes, n_forb


@jit(inline="always")
def _partition(g, sr, node, key, cut, n_nodes, n_forb):
    """Partition the solved, reported ``node`` of cost ``key`` (lazily: its children enter
    the queue with a lower bound only), with the node's forbidden pairs switched off meanwhile.
    Returns ``(n_nodes, n_forb)``."""
    tree = sr.tree
    sl = tree.slot[node]
    head = tree.forb[node]
    _switch_off(g.cost, sr.forb, head)
    slack = _load_partition(g, sr.part, tree, sr.sols, node, sl, key)
    slack *= _BOUND_SLACK
    cut += slack + _BOUND_SLACK * abs(cut)  # the margin, as in a solve
    n_free = _order_rows(g, sr.part, sr.sols, sl, cut)
    n_nodes, n_forb = _make_children(g, sr, node, key, slack, cut, n_free, n_nodes, n_forb)
    _switch_on(g.cost, g.cost0, sr.forb, head)
    return n_nodes, n_forb


# ----------------------------------------------------------------------------- the queue
@jit(inline="always")
def _replace_top(heap_key, heap_id, n_heap, kx, x):
    """Put ``(kx, x)`` at the top of the min-heap ``(heap_key, heap_id)[:n_heap]`` (ordered by
    key, then id) and sift it down to its place."""
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
    """Push ``(ky, y)`` onto the min-heap of :func:`_replace_top`; returns its new size."""
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
def _search(g, sr, k, budget):
    """Run the search until ``k`` assignments are reported, the queue is empty, an array is
    full or ``budget`` iterations are done.

    Parameters
    ----------
    g : Graph
        The problem (:data:`.lsap.Graph`); ``g.cost`` equals ``g.cost0`` between iterations.
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
        if tree.slot[node] == NO_ENTRY:
            # a bounded node at the top: solve it and queue it again with its exact cost
            solved, v_free = _solve_node(g, sr, node, cut)
            if solved:
                key = _store_solution(g, sr.match, sr.sols, n_sols, v_free)
                n_best = _keep_least(kbest, n_best, n_stale, k - n_out, key)
                tree.slot[node] = n_sols
                n_sols += 1
                tree.key[node] = key
                kx = key  # back into the queue with its exact cost
                x = node
            else:
                n_heap -= 1  # the node leaves
                kx = heap_key[n_heap]
                x = heap_id[n_heap]
        else:
            # a solved node at the top: report it
            key = tree.key[node]
            sr.ranking.slot[n_out] = tree.slot[node]  # copied into the output at the end
            sr.ranking.cost[n_out] = key
            n_out += 1
            n_stale += 1  # its cost, the least in kbest, stays there as a stale entry
            if n_out == k:
                break
            n_nodes, n_forb = _partition(g, sr, node, key, cut, n_nodes, n_forb)
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


@jit()
def _root_lsap(g, m, pw):
    """The root's LSAP: a cold shortest augmenting path from each row in turn.

    :func:`.lsap.sap_augment` with ``freed = COLD`` and ``v_free = 0`` (same arithmetic and
    tie-breaking), on the search's arrays, a scanned column marked by ``d = -inf`` as in
    :func:`_search`.

    Parameters
    ----------
    g : Graph
        The problem (:data:`.lsap.Graph`), nothing forbidden.
    m : Matching
        Empty (:func:`.lsap.new_matching`); the optimal assignment and duals on return.
    pw : PathWork
        ``d`` must be ``+inf`` everywhere on entry (and is on return).

    Returns
    -------
    bool
        False when some row cannot be assigned (the problem is infeasible).
    """
    ptr, col, cost = g.ptr, g.col, g.cost
    u, v, col4row, row4col = m.u, m.v, m.col4row, m.row4col
    d, path, cand, touched, done, done_d, rows, rows_d = pw
    P = col4row.shape[0]
    for root in range(P):
        n_cand = 0
        n_touched = 0
        n_rows = 0
        n_done = 0
        min_val = 0.0
        i = root
        sink = -1
        while sink < 0:
            # scan row i
            rows[n_rows] = i
            rows_d[n_rows] = min_val
            n_rows += 1
            ui = u[i]
            for e in range(ptr[i], ptr[i + 1]):
                cij = cost[e]
                j = col[e]
                if cij == np.inf:
                    continue
                if row4col[j] < 0:  # a free column: the shared potential 0
                    dist = min_val + (cij - ui - 0.0)
                else:
                    dist = min_val + (cij - ui - v[j])
                if dist < d[j]:  # (never for a scanned column, d = -inf)
                    if d[j] == np.inf:
                        cand[n_cand] = j
                        n_cand += 1
                        touched[n_touched] = j
                        n_touched += 1
                    d[j] = dist
                    path[j] = i
            # the closest reached column; ties: a free one (it ends the path), the lowest index
            index = -1
            lowest = np.inf
            best_ends = False
            best_j = -1
            for it in range(n_cand):
                j = cand[it]
                dj = d[j]
                if dj > lowest:
                    continue
                ends = row4col[j] < 0
                if dj < lowest or (ends and not best_ends) or (ends == best_ends and j < best_j):
                    lowest = dj
                    index = it
                    best_ends = ends
                    best_j = j
            if index < 0:
                for t in range(n_touched):
                    d[touched[t]] = np.inf
                return False
            j = cand[index]
            n_cand -= 1
            cand[index] = cand[n_cand]
            min_val = d[j]
            done[n_done] = j
            done_d[n_done] = min_val
            n_done += 1
            d[j] = -np.inf
            if row4col[j] < 0:
                v[j] = 0.0  # a free column about to be matched: its potential made explicit
                sink = j
            else:
                i = row4col[j]
        for t in range(n_rows):  # (min_val - 0.0 is min_val for the root)
            u[rows[t]] += min_val - rows_d[t]
        for t in range(n_done):
            v[done[t]] -= min_val - done_d[t]
        j = sink
        while True:
            r = path[j]
            row4col[j] = r
            prev = col4row[r]
            col4row[r] = j
            if r == root:
                break
            j = prev
        for t in range(n_touched):
            d[touched[t]] = np.inf
    return True


#: :func:`murty_slice`: the search is over, a slice's budget is spent, an array is full.
DONE, PAUSED, FULL = 0, 1, 2


# ----------------------------------------------------------------------------- the records' arrays
@jit()
def _new_path_work(P, N):
    """A clean :data:`PathWork` (``d = +inf``)."""
    return PathWork(np.full(N, np.inf), np.empty(N, dtype=np.int64), np.empty(N, dtype=np.int64),
                    np.empty(N, dtype=np.int64), np.empty(N, dtype=np.int64), np.empty(N),
                    np.empty(P, dtype=np.int64), np.empty(P))


@jit()
def _new_tree(n, P):
    """An empty :data:`Tree` with room for ``n`` nodes of ``P`` rows."""
    return Tree(np.empty(n), np.empty(n, dtype=np.int64), np.empty(n, dtype=np.int64),
                np.empty(n, dtype=np.int64), np.zeros((n, (P + 63) >> 6), dtype=np.int64),
                np.empty(n), np.empty(n, dtype=np.int64))


@jit()
def _new_forbidden(n):
    """An empty :data:`Forbidden` with room for ``n`` entries."""
    return Forbidden(np.empty(n, dtype=np.int64), np.empty(n, dtype=np.int64),
                     np.empty(n, dtype=np.int64))


@jit()
def _new_solutions(n, P):
    """An empty :data:`Solutions` with room for ``n`` solutions of ``P`` rows."""
    return Solutions(np.empty((n, P), dtype=np.int64), np.empty((n, P)), np.empty((n, P)),
                     np.empty(n), np.empty(n), np.empty(n))


@jit()
def _new_partition_work(P, N):
    """A :data:`PartitionWork` for ``P`` rows and ``N`` columns."""
    return PartitionWork(np.empty(P, dtype=np.int64), np.empty(P, dtype=np.int64), np.empty(P),
                         np.empty(P, dtype=np.int64), np.empty((P + 63) >> 6, dtype=np.int64),
                         np.empty(N))


@jit()
def _grown_tree(t, n):
    """:data:`Tree` ``t`` copied into arrays with room for ``n`` nodes."""
    return Tree(_grow(t.key, n), _grow(t.slot, n), _grow(t.parent, n), _grow(t.forb, n),
                _grow(t.fixed, n), _grow(t.heap_key, n), _grow(t.heap_id, n))


@jit()
def _grown_forbidden(f, n):
    """:data:`Forbidden` ``f`` copied into arrays with room for ``n`` entries."""
    return Forbidden(_grow(f.row, n), _grow(f.entry, n), _grow(f.next, n))


@jit()
def _grown_solutions(s, n):
    """:data:`Solutions` ``s`` copied into arrays with room for ``n`` solutions."""
    return Solutions(_grow(s.cols, n), _grow(s.u, n), _grow(s.v, n), _grow(s.v_free, n),
                     _grow(s.cost, n), _grow(s.scale, n))


@jit()
def _grown_ranking(r, n_out, n_best):
    """:data:`Ranking` ``r`` with room for ``n_out`` reported nodes and ``n_best`` costs."""
    slot, cost, kbest = r
    if n_out > slot.shape[0]:
        slot = _grow(slot, n_out)
        cost = _grow(cost, n_out)
    if n_best > kbest.shape[0]:
        kbest = _grow(kbest, n_best)
    return Ranking(slot, cost, kbest)


# ----------------------------------------------------------------------------- entry points
@jit()
def new_search(g, k):
    """The root's LSAP and a :data:`Search` with the root in the queue.

    Parameters
    ----------
    g : Graph
        The problem (:data:`.lsap.Graph`), as in :func:`murty_kernel`.
    k : int
        Number of assignments wanted (>= 1).

    Returns
    -------
    ok : bool
        False when the problem has no feasible assignment (the search is then empty).
    search : tuple
        The search, packed (:func:`pack_search`).
    """
    P, N = g.pos.shape
    m = new_matching(P, N)
    pw = _new_path_work(P, N)
    ok = _root_lsap(g, m, pw)
    cap = max(_INITIAL_CAPACITY, 2 * P)
    out_cap = min(k, _INITIAL_CAPACITY)
    sr = Search(m, pw, _new_tree(cap, P), _new_forbidden(cap),
                _new_solutions(_INITIAL_CAPACITY, P),
                Ranking(np.empty(out_cap, dtype=np.int64), np.empty(out_cap), np.empty(out_cap)),
                _new_partition_work(P, N), np.zeros(N_STATE, dtype=np.int64))
    if not ok:
        return False, pack_search(sr)
    key0 = _store_solution(g, m, sr.sols, 0, 0.0)
    sr.ranking.kbest[0] = key0
    tree = sr.tree
    tree.key[0] = key0
    tree.slot[0] = 0
    tree.parent[0] = NO_ENTRY
    tree.forb[0] = NO_ENTRY
    tree.heap_key[0] = key0
    tree.heap_id[0] = 0
    state = sr.state
    state[S_HEAP] = 1
    state[S_NODES] = 1
    state[S_SOLS] = 1
    state[S_BEST] = 1
    return True, pack_search(sr)


@jit()
def murty_slice(graph, search, k, budget):
    """At most ``budget`` iterations of ``search``, in place.

    Parameters
    ----------
    graph : tuple
        The fields of the problem's :data:`.lsap.Graph` (``ptr, col, cost, cost0, pos``).
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
    if _search(Graph(*graph), sr, k, budget):
        return DONE
    state = sr.state
    if _is_full(sr, k, state[S_OUT], state[S_SOLS], state[S_NODES], state[S_FORB],
                state[S_BEST]):
        return FULL
    return PAUSED


@jit()
def grow_search(search, k):
    """Packed ``search`` with every full array doubled (every array the next iteration may
    fill); ``k`` the number of assignments wanted (the output and kbest never need more)."""
    sr = unpack_search(search)
    P = sr.match.col4row.shape[0]
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
    return pack_search(Search(sr.match, sr.path, tree, forb, sols, ranking, sr.part, state))


@jit()
def search_output(search):
    """The reported assignments ``(n, P)`` and their costs ``(n,)`` of a finished (packed)
    search, as documented in :func:`murty_kernel`."""
    sr = unpack_search(search)
    P = sr.match.col4row.shape[0]
    cols, out_slot, out_cost = sr.sols.cols, sr.ranking.slot, sr.ranking.cost
    n_out = sr.state[S_OUT]
    out = np.empty((n_out, P), dtype=np.int64)
    for t in range(n_out):
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
    return out, out_cost[:n_out]


@jit()
def murty_start(g, k, budget):
    """:func:`new_search` and its first ``budget`` iterations (:func:`murty_slice`).

    Parameters
    ----------
    g : Graph
        The problem (:data:`.lsap.Graph`), as in :func:`murty_kernel`.
    k, budget : int
        As in :func:`murty_slice`.

    Returns
    -------
    tuple
        ``(assignments, costs, None)`` as documented in :func:`murty_kernel` when the search
        ends within the budget (one call: small searches cost what they cost before), else
        ``(empty, empty, search)`` with the packed :data:`Search` to continue.
    """
    P = g.pos.shape[0]
    ok, search = new_search(g, k)
    if not ok:
        return np.empty((0, P), dtype=np.int64), np.empty(0), None
    graph = g[:]
    status = murty_slice(graph, search, k, budget)
    while status == FULL:
        search = grow_search(search, k)
        done = unpack_search(search).state[S_ITER]
        status = murty_slice(graph, search, k, max(1, budget - done))
    if status == DONE:
        out, costs = search_output(search)
        return out, costs, None
    return np.empty((0, P), dtype=np.int64), np.empty(0), search


@jit()
def murty_kernel(ptr, col, cost0, pos, k):
    """Murty's ranked assignment with the Miller–Stone–Cox improvements.

    Parameters
    ----------
    ptr, col, cost0 : ndarray
        The finite entries of a ``(P, N)`` cost matrix, ``1 <= P <= N``, row by row (CSR:
        row ``i`` owns entries ``ptr[i]:ptr[i + 1]``, entry ``e`` is column ``col[e]`` at
        cost ``cost0[e]``), with at least one feasible assignment.
    pos : ndarray, int64, shape (P, N)
        ``pos[i, j]``: the entry of ``(i, j)`` (-1: none).
    k : int
        Number of assignments wanted (>= 1).

    Returns
    -------
    assignments : ndarray, int64, shape (n, P)
        The ``n = min(k, |Gamma|)`` best assignments, best first; among equal costs, in the
        order of creation of their nodes.
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
    (lazy evaluation, Miller, Stone & Cox 1997, spec §5.1 item 2) and is solved only if it
    reaches the top, by one shortest augmenting path from its parent's duals and assignment
    minus ``(r, s[r])`` (item 1), then re-enters with its exact cost. A bound never exceeds
    the cost it bounds, so the output is that of solving every child at once, in the same
    order. The heap orders nodes by ``(key, node id)``: equal keys leave in order of
    creation.

    Rectangular LSAP is the square problem in which every free column is held by a zero-cost
    dummy row; all free columns share one implicit potential ``v_free`` (see
    :mod:`.lsap`). A solution is stored with its row duals ``u``, the dual ``v`` of each
    row's column and ``v_free``: ``O(P)`` numbers, not ``O(N)``. The root is a cold LSAP
    (:func:`.lsap.sap_augment` from each row in turn).

    References
    ----------
    .. [1] K. G. Murty, "An Algorithm for Ranking all the Assignments in Order of Increasing
       Cost", Operations Research 16(3):682–687, 1968.
    .. [2] M. L. Miller, H. S. Stone, I. J. Cox, "Optimizing Murty's Ranked Assignment
       Method", IEEE Trans. Aerosp. Electron. Syst. 33(3), 1997.
    """
    # forbidden entries of the current node are set to +inf in the working copy for a while
    out, costs, _ = murty_start(Graph(ptr, col, cost0.copy(), cost0, pos), k, 1 << 62)
    return out, costs


@jit()
def compact_graph(cc):
    """CSR arrays of a problem's compact costs in the ``(P, M + 2P)`` layout.

    Row ``i`` of ``cc = [meas 0..M-1 | missed | dead]`` has at most ``M + 2`` finite entries:
    measurement ``j`` is column ``j``, missed is column ``M + i``, dead is column
    ``M + P + i`` (increasing column order). Returns ``(ptr, col, cost, pos)`` as in
    :func:`murty_kernel`.
    """
    P = cc.shape[0]
    M = cc.shape[1] - 2
    ptr = np.zeros(P + 1, dtype=np.int64)
    for i in range(P):
        n = 0
        for o in range(M + 2):
            if cc[i, o] < np.inf:
                n += 1
        ptr[i + 1] = ptr[i] + n
    col = np.empty(ptr[P], dtype=np.int64)
    cost = np.empty(ptr[P])
    pos = np.full((P, M + 2 * P), -1, dtype=np.int64)
    e = 0
    for i in range(P):
        for o in range(M + 2):
            if cc[i, o] < np.inf:
                col[e] = o if o < M else (M + i if o == M else M + P + i)
                cost[e] = cc[i, o]
                pos[i, col[e]] = e
                e += 1
    return ptr, col, cost, pos


@jit()
def murty_compact_start(cc, k, budget):
    """:func:`murty_start` on a problem's compact costs ``(P, M + 2)``, ``P >= 1``.

    Returns ``(assignments, costs, None)`` when done within the budget, else ``(empty,
    empty, (graph, search))`` with the fields of the problem's :data:`.lsap.Graph` (from
    :func:`compact_graph`) and the packed search to continue with :func:`murty_slice`.
    """
    ptr, col, cost0, pos = compact_graph(cc)
    g = Graph(ptr, col, cost0.copy(), cost0, pos)
    out, costs, search = murty_start(g, k, budget)
    if search is None:
        return out, costs, None
    return out, costs, (g[:], search)


@jit()
def murty_compact_kernel(cc, k):
    """:func:`murty_kernel` on a problem's compact costs ``(P, M + 2)``, ``P >= 1``."""
    ptr, col, cost, pos = compact_graph(cc)
    return murty_kernel(ptr, col, cost, pos, k)

"""Compiled Murty k-best ranked assignment (spec §5.1) with the Miller–Stone–Cox improvements.

The driver :func:`murty_kernel` pops the best open subproblem of the partition tree. A node
that is only *bounded* is solved (:func:`_solve_node`) and pushed back with its exact cost; a
*solved* node is reported and partitioned: its children are pushed with a lower bound only
(:func:`_partition_order` computes the bounds and the order), so most of them are never
solved. Forbidden pairs are switched on and off in the shared :data:`~.lsap.Graph`
(:func:`_forbid`, :func:`_allow`). Costs are accumulated row by row in the order ``0..P-1``
from ``0.0``, exactly as :meth:`rankedassign.AssignmentProblem.cost_of` does.
"""

from __future__ import annotations

from collections import namedtuple

import numpy as np

from rankedassign.numba_options import jit

from .lsap import (
    COLD,
    UNASSIGNED,
    Graph,
    new_matching,
    new_workspace,
    sap_augment,
)

__all__ = ["murty_kernel"]

NO_ENTRY = -1  # end of a forbidden-pair list; slot of a node that is not solved yet
_INITIAL_CAPACITY = 1024
# Relative slack subtracted from a lower bound so that rounding can never lift it above the
# exact cost it bounds (the order of the output then equals that of solving every child).
_BOUND_SLACK = 1e-9

#: The partition tree, one entry per node: its heap key (exact cost once solved, a lower bound
#: before), its slot in :data:`Solutions` (``NO_ENTRY`` until solved), the slot of its parent's
#: solution, the head of its forbidden-pair list (its own pair first, then its ancestors') and
#: which rows it fixes to the parent's columns.
Nodes = namedtuple("Nodes", ["key", "slot", "parent", "forb_head", "fixed"])

#: Solved nodes: optimal assignment ``sol``, row duals ``u``, the dual ``v`` of each row's
#: column (``v[n, i]`` belongs to column ``sol[n, i]``) and the shared potential ``v_free`` of
#: the free columns: the duals of a solution in ``O(P)`` numbers, not ``O(N)``.
Solutions = namedtuple("Solutions", ["sol", "u", "v", "v_free"])

#: Forbidden pairs as linked lists: entry ``f`` forbids row ``row[f]``'s graph entry
#: ``entry[f]`` and continues at ``next[f]`` (``NO_ENTRY`` ends the list).
Forbidden = namedtuple("Forbidden", ["row", "entry", "next"])


@jit()
def _assignment_cost(g, P, col4row, entry_of):
    """Cost of an assignment summed row by row from ``0.0`` (as ``AssignmentProblem.cost_of``).

    ``entry_of`` is scratch (one int per row); it receives the graph entry of each row.
    """
    s = 0.0
    for i in range(P):
        e = g.pos[i, col4row[i]]
        entry_of[i] = e
        s += g.cost0[e]
    return s


@jit()
def _heap_push(heap, n, keys, node):
    # sift up: (key, node id) order, so equal keys leave in order of creation
    kx = keys[node]
    k = n
    while k > 0:
        p = (k - 1) >> 1
        q = heap[p]
        if kx < keys[q] or (kx == keys[q] and node < q):
            heap[k] = q
            k = p
        else:
            break
    heap[k] = node
    return n + 1


@jit()
def _heap_pop(heap, n, keys):
    top = heap[0]
    n -= 1
    x = heap[n]
    kx = keys[x]
    k = 0
    while True:  # sift down the last entry
        c = 2 * k + 1
        if c >= n:
            break
        a = heap[c]
        if c + 1 < n:
            b = heap[c + 1]
            if keys[b] < keys[a] or (keys[b] == keys[a] and b < a):
                c += 1
                a = b
        if keys[a] < kx or (keys[a] == kx and a < x):
            heap[k] = a
            k = c
        else:
            break
    heap[k] = x
    return top, n


@jit()
def _grow(a, n):
    """``a`` copied into a new array with ``n`` rows (first axis)."""
    out = np.empty((n,) + a.shape[1:], dtype=a.dtype)
    out[: a.shape[0]] = a
    return out


@jit()
def _new_nodes(cap, P):
    return Nodes(np.empty(cap), np.empty(cap, dtype=np.int64), np.empty(cap, dtype=np.int64),
                 np.empty(cap, dtype=np.int64), np.empty((cap, P), dtype=np.bool_))


@jit()
def _grow_nodes(nodes, cap):
    return Nodes(_grow(nodes.key, cap), _grow(nodes.slot, cap), _grow(nodes.parent, cap),
                 _grow(nodes.forb_head, cap), _grow(nodes.fixed, cap))


@jit()
def _new_solutions(cap, P):
    return Solutions(np.empty((cap, P), dtype=np.int64), np.empty((cap, P)), np.empty((cap, P)),
                     np.empty(cap))


@jit()
def _grow_solutions(sols, cap):
    return Solutions(_grow(sols.sol, cap), _grow(sols.u, cap), _grow(sols.v, cap),
                     _grow(sols.v_free, cap))


@jit()
def _store_solution(sols, slot, m, v_free):
    """Keep the optimum now in ``m`` in slot ``slot`` (column duals of the matched columns)."""
    for i in range(m.col4row.shape[0]):
        c = m.col4row[i]
        sols.sol[slot, i] = c
        sols.u[slot, i] = m.u[i]
        sols.v[slot, i] = m.v[c]
    sols.v_free[slot] = v_free


@jit()
def _grow_forbidden(forb, cap):
    return Forbidden(_grow(forb.row, cap), _grow(forb.entry, cap), _grow(forb.next, cap))


@jit()
def _forbid(g, forb, head):
    """Switch off the graph entries of the forbidden list starting at ``head``."""
    f = head
    while f != NO_ENTRY:
        g.cost[forb.entry[f]] = np.inf
        f = forb.next[f]


@jit()
def _allow(g, forb, head):
    """Undo :func:`_forbid`."""
    f = head
    while f != NO_ENTRY:
        e = forb.entry[f]
        g.cost[e] = g.cost0[e]
        f = forb.next[f]


@jit()
def _load(m, s, fixed):
    """Matching ``s`` in ``m``: ``row4col`` and the inactive columns of the fixed rows."""
    for i in range(s.shape[0]):
        m.col4row[i] = s[i]
        m.row4col[s[i]] = i
        if fixed[i]:
            m.active[s[i]] = False  # a fixed row's column is out of the residual problem


@jit()
def _unload(m):
    """Undo :func:`_load` for the matching now in ``m`` (every column free and active again)."""
    for i in range(m.col4row.shape[0]):
        c = m.col4row[i]
        if c >= 0:
            m.row4col[c] = UNASSIGNED
            m.active[c] = True


@jit()
def _partition_order(g, s, entry_of, u, v, v_free, m, fixed, lb, order):
    """Free rows of a node in decreasing order of a lower bound on their child's increase.

    ``m`` holds the node's matching ``s`` (:func:`_load`); ``v[q]`` is the dual of row ``q``'s
    column and ``v_free`` that of every free column. ``lb[i]`` is the smallest reduced
    cost ``cost - u[i] - v_j`` of an allowed, active alternative ``j != s[i]`` of row ``i``
    (``+inf``: the child is infeasible); the child's optimum is at least the node's plus
    ``lb[i]`` (Miller, Stone & Cox 1997). Children expected to be worst get the fewest
    fixings, the most promising ones the smallest residual problems. Returns the number of
    free rows, listed in ``order``; ties keep row order.
    """
    n_free = 0
    for i in range(s.shape[0]):
        if fixed[i]:
            continue
        best = np.inf
        for e in range(g.ptr[i], g.ptr[i + 1]):
            j = g.col[e]
            if e == entry_of[i] or g.cost[e] == np.inf or not m.active[j]:
                continue
            q = m.row4col[j]
            vj = v_free if q < 0 else v[q]  # v[q]: dual of row q's column; free: shared
            r = g.cost[e] - u[i] - vj
            if r < best:
                best = r
        lb[i] = max(best, 0.0)
        order[n_free] = i
        n_free += 1
    # stable insertion sort by decreasing bound
    for a in range(1, n_free):
        x = order[a]
        b = a - 1
        while b >= 0 and lb[order[b]] < lb[x]:
            order[b + 1] = order[b]
            b -= 1
        order[b + 1] = x
    return n_free


@jit()
def _bound_slack(key, s, entry_of, g, u):
    """Absolute slack of a lower bound: ``_BOUND_SLACK`` times the magnitudes it was made of."""
    scale = 1.0 + abs(key)
    for i in range(s.shape[0]):
        scale += abs(g.cost0[entry_of[i]]) + abs(u[i])
    return _BOUND_SLACK * scale


@jit()
def _solve_node(g, nodes, sols, forb, node, m, ws):
    """Solve a bounded node by one warm-started augmenting path; return ``(ok, v_free)``.

    Warm start (Miller, Stone & Cox 1997): the parent's duals and assignment minus the row
    ``r`` whose pair ``(r, c)`` the node forbids, completed by one shortest augmenting path
    from ``r`` with ``c`` the only free column of the square view. On success ``m`` holds the
    node's optimum (to be unloaded by the caller).
    """
    ps = nodes.parent[node]
    f = nodes.forb_head[node]
    r = forb.row[f]
    s = sols.sol[ps]
    _load(m, s, nodes.fixed[node])
    c = s[r]
    m.col4row[r] = UNASSIGNED
    m.row4col[c] = UNASSIGNED
    for i in range(s.shape[0]):
        m.u[i] = sols.u[ps, i]
        m.v[s[i]] = sols.v[ps, i]  # free columns: the shared potential, never read
    _forbid(g, forb, f)
    inc, v_free = sap_augment(g, r, c, m, sols.v_free[ps], ws)
    _allow(g, forb, f)
    if inc == np.inf:
        m.col4row[r] = c  # restore the loaded matching so that _unload clears it
        m.row4col[c] = r
        _unload(m)
        return False, v_free
    return True, v_free


@jit()
def murty_kernel(g, P, N, k):
    """Murty's ranked assignment with the Miller–Stone–Cox improvements.

    Parameters
    ----------
    g : Graph
        The finite entries of a ``(P, N)`` cost matrix, ``1 <= P <= N``, with at least one
        feasible assignment (its ``cost`` is modified during the run and restored).
    P, N : int
        Shape of the cost matrix.
    k : int
        Number of assignments wanted (>= 1).

    Returns
    -------
    assignments : ndarray, int64, shape (n, P)
        The ``n = min(k, |Gamma|)`` best assignments, best first; among equal costs, in the
        order of creation of their nodes.
    costs : ndarray, float64, shape (n,)
        Their costs summed row by row from ``0.0`` (bit for bit
        ``AssignmentProblem.cost_of``); non-decreasing up to the rounding of sums of equal
        value in different orders (a child's cost can be one ulp below its parent's).

    Notes
    -----
    Each node of the partition tree is a subproblem: rows fixed to their parent's columns and
    a set of forbidden pairs (a linked list shared with the ancestors). Popping a solved node
    with solution ``s`` reports ``s`` and creates one child per free row ``r``: forbid
    ``(r, s[r])`` and fix the rows processed before it (partition ordering). A child enters
    the queue with the lower bound ``cost(s) + lb[r]`` (lazy evaluation, Miller, Stone & Cox
    1997, spec §5.1 item 2) and is solved only if it reaches the top, by one warm-started
    shortest augmenting path from its parent's duals (item 1), then re-enters with its exact
    cost. A bound never exceeds the cost it bounds, so the output is that of solving every
    child at once, in the same order.
    """
    out = np.empty((k, P), dtype=np.int64)
    out_cost = np.empty(k)
    m = new_matching(P, N)
    ws = new_workspace(P, N)
    for root in range(P):  # the root: a cold LSAP
        inc, _ = sap_augment(g, root, COLD, m, 0.0, ws)
        if inc == np.inf:
            return out[:0], out_cost[:0]
    nodes = _new_nodes(_INITIAL_CAPACITY, P)
    sols = _new_solutions(_INITIAL_CAPACITY, P)
    forb = Forbidden(np.empty(_INITIAL_CAPACITY, dtype=np.int64),
                     np.empty(_INITIAL_CAPACITY, dtype=np.int64),
                     np.empty(_INITIAL_CAPACITY, dtype=np.int64))
    heap = np.empty(_INITIAL_CAPACITY, dtype=np.int64)
    entry_of = np.empty(P, dtype=np.int64)
    _store_solution(sols, 0, m, 0.0)
    nodes.key[0] = _assignment_cost(g, P, m.col4row, entry_of)
    nodes.slot[0] = 0
    nodes.parent[0] = NO_ENTRY
    nodes.forb_head[0] = NO_ENTRY
    for i in range(P):
        nodes.fixed[0, i] = False
    _unload(m)
    n_nodes = 1
    n_sols = 1
    n_forb = 0
    n_heap = _heap_push(heap, 0, nodes.key, 0)

    order = np.empty(P, dtype=np.int64)
    lb = np.empty(P)
    fix_now = np.empty(P, dtype=np.bool_)
    n_out = 0
    while n_heap > 0 and n_out < k:
        node, n_heap = _heap_pop(heap, n_heap, nodes.key)
        if nodes.slot[node] == NO_ENTRY:
            # a bounded node at the top: solve it, and queue it again with its exact cost
            ok, v_free = _solve_node(g, nodes, sols, forb, node, m, ws)
            if not ok:
                continue
            if n_sols == sols.sol.shape[0]:
                sols = _grow_solutions(sols, 2 * n_sols)
            _store_solution(sols, n_sols, m, v_free)
            nodes.slot[node] = n_sols
            n_sols += 1
            _unload(m)
            nodes.key[node] = _assignment_cost(g, P, sols.sol[nodes.slot[node]], entry_of)
            n_heap = _heap_push(heap, n_heap, nodes.key, node)
            continue
        sl = nodes.slot[node]
        s = sols.sol[sl]
        for i in range(P):
            out[n_out, i] = s[i]
        out_cost[n_out] = nodes.key[node]
        n_out += 1
        if n_out == k:
            break
        # partition the node: children with lower bounds only
        key = _assignment_cost(g, P, s, entry_of)
        head = nodes.forb_head[node]
        for i in range(P):
            fix_now[i] = nodes.fixed[node, i]
        _forbid(g, forb, head)
        _load(m, s, fix_now)
        n_free = _partition_order(g, s, entry_of, sols.u[sl], sols.v[sl], sols.v_free[sl], m,
                                  fix_now, lb, order)
        _unload(m)
        _allow(g, forb, head)
        slack = _bound_slack(key, s, entry_of, g, sols.u[sl])
        for t in range(n_free):
            r = order[t]
            if lb[r] < np.inf:
                # child t: forbid (r, s[r]), rows order[:t] fixed
                if n_nodes + 1 >= nodes.key.shape[0]:
                    nodes = _grow_nodes(nodes, 2 * n_nodes)
                    heap = _grow(heap, 2 * n_nodes)
                if n_forb == forb.row.shape[0]:
                    forb = _grow_forbidden(forb, 2 * n_forb)
                forb.row[n_forb] = r
                forb.entry[n_forb] = entry_of[r]
                forb.next[n_forb] = head
                nodes.key[n_nodes] = key + lb[r] - slack
                nodes.slot[n_nodes] = NO_ENTRY
                nodes.parent[n_nodes] = sl
                nodes.forb_head[n_nodes] = n_forb
                for i in range(P):
                    nodes.fixed[n_nodes, i] = fix_now[i]
                n_forb += 1
                n_heap = _heap_push(heap, n_heap, nodes.key, n_nodes)
                n_nodes += 1
            fix_now[r] = True  # later children keep row r on its parent column
    return out[:n_out], out_cost[:n_out]


@jit()
def compact_graph(cc):
    """The :data:`~.lsap.Graph` of a problem's compact costs, in the ``(P, M + 2P)`` layout.

    Row ``i`` of ``cc = [meas 0..M-1 | missed | dead]`` has at most ``M + 2`` finite entries:
    measurement ``j`` is column ``j``, missed is column ``M + i``, dead is column
    ``M + P + i`` (increasing column order).
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
    return Graph(ptr, col, cost, cost.copy(), pos)


@jit()
def murty_compact_kernel(cc, k):
    """:func:`murty_kernel` on a problem's compact costs ``(P, M + 2)``, ``P >= 1``."""
    P = cc.shape[0]
    M = cc.shape[1] - 2
    return murty_kernel(compact_graph(cc), P, M + 2 * P, k)

"""Compiled Murty k-best ranked assignment (spec §5.1) with the Miller–Stone–Cox improvements.

The driver :func:`murty_kernel` pops the best open subproblem of the partition tree. A node
that is only *bounded* is solved (one warm-started shortest augmenting path) and pushed back
with its exact cost; a *solved* node is reported and partitioned: its children are pushed with
a lower bound only, so most of them are never solved. Forbidden pairs are switched on and off
in the shared graph's ``cost`` array. Costs are accumulated row by row in the order
``0..P-1`` from ``0.0``, exactly as :meth:`rankedassign.AssignmentProblem.cost_of` does.

Layout for speed. The whole search is one compiled function on flat arrays: the augmenting
path (the algorithm of :func:`.lsap.sap_augment`, same arithmetic and tie-breaking) is an
inner function that numba inlines, and the tree, the solutions, the forbidden-pair lists and
the heap are plain arrays indexed by integers. At these sizes (tens of rows, about one
augmenting path of one or two row scans per reported assignment) the calls between small
compiled helpers that each received a dozen arrays, and the array views made for each node,
cost as much as the arithmetic; here nothing is allocated and nothing is called per node.
"""

from __future__ import annotations

import numpy as np

from rankedassign.numba_options import jit

from .lsap import COLD, HUB, UNASSIGNED

__all__ = ["murty_kernel", "murty_compact_kernel"]

NO_ENTRY = -1  # end of a forbidden-pair list; slot of a node that is not solved yet
_INITIAL_CAPACITY = 1024
# Relative slack subtracted from a lower bound so that rounding can never lift it above the
# exact cost it bounds (the order of the output then equals that of solving every child).
_BOUND_SLACK = 1e-9


@jit()
def _grow(a, n):
    """``a`` copied into a new array with ``n`` rows (first axis)."""
    out = np.empty((n,) + a.shape[1:], dtype=a.dtype)
    out[: a.shape[0]] = a
    return out


@jit()
def murty_kernel(ptr, col, cost0, pos, P, N, k):
    """Murty's ranked assignment with the Miller–Stone–Cox improvements.

    Parameters
    ----------
    ptr, col, cost0 : ndarray
        The finite entries of a ``(P, N)`` cost matrix, ``1 <= P <= N``, row by row (CSR:
        row ``i`` owns entries ``ptr[i]:ptr[i + 1]``, entry ``e`` is column ``col[e]`` at
        cost ``cost0[e]``), with at least one feasible assignment.
    pos : ndarray, int64, shape (P, N)
        ``pos[i, j]``: the entry of ``(i, j)`` (-1: none).
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
    row's column and ``v_free``: ``O(P)`` numbers, not ``O(N)``.
    """
    cost = cost0.copy()  # forbidden entries of the current node are set to +inf for a while
    out_cap = min(k, _INITIAL_CAPACITY)
    out = np.empty((out_cap, P), dtype=np.int64)
    out_cost = np.empty(out_cap)
    # the assignment state (duals, matching, active columns) and the search workspace
    u = np.zeros(P)
    v = np.zeros(N)
    col4row = np.full(P, UNASSIGNED, dtype=np.int64)
    row4col = np.full(N, UNASSIGNED, dtype=np.int64)
    active = np.ones(N, dtype=np.bool_)
    d = np.full(N, np.inf)
    path = np.full(N, UNASSIGNED, dtype=np.int64)
    scanned = np.zeros(N, dtype=np.bool_)
    cand = np.empty(N, dtype=np.int64)
    touched = np.empty(N, dtype=np.int64)
    done = np.empty(N, dtype=np.int64)
    rows = np.empty(P, dtype=np.int64)

    def augment(root, freed, v_free):
        # One shortest augmenting path (Dijkstra on reduced costs) from the free row ``root``:
        # the algorithm, arithmetic and tie-breaking of lsap.sap_augment, inlined. Returns
        # (increase, new v_free); increase = +inf (state unchanged) when no path exists.
        n_cand = 0
        n_touched = 0
        n_rows = 0
        n_done = 0
        min_val = 0.0
        i = root
        sink = -1
        hub_open = False
        hub_src = -1
        hub_dist = 0.0
        while sink < 0:
            if i >= 0:  # scan row i
                rows[n_rows] = i
                n_rows += 1
                ui = u[i]
                for e in range(ptr[i], ptr[i + 1]):
                    cij = cost[e]
                    j = col[e]
                    if cij == np.inf or not active[j] or scanned[j]:
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
            # the closest reached column; ties: one that ends the path, then the lowest index
            index = -1
            lowest = np.inf
            best_ends = False
            best_j = -1
            for it in range(n_cand):
                j = cand[it]
                dj = d[j]
                ends = j == freed or (freed == COLD and row4col[j] < 0)
                if dj < lowest or (dj == lowest and ((ends and not best_ends)
                                                     or (ends == best_ends and j < best_j))):
                    lowest = dj
                    index = it
                    best_ends = ends
                    best_j = j
            if index < 0:  # no augmenting path: clear the workspace, state unchanged
                for t in range(n_touched):
                    j = touched[t]
                    d[j] = np.inf
                    scanned[j] = False
                    path[j] = UNASSIGNED
                return np.inf, v_free
            j = cand[index]
            n_cand -= 1
            cand[index] = cand[n_cand]
            scanned[j] = True
            done[n_done] = j
            n_done += 1
            min_val = d[j]
            if j == freed:
                sink = j
            elif row4col[j] < 0:
                v[j] = v_free  # a free column about to be matched: its potential made explicit
                if freed == COLD:
                    sink = j
                else:  # open the dummy-row hub: every column reachable through it
                    hub_open = True
                    hub_src = j
                    hub_dist = min_val
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
                        if kk >= 0 and active[kk] and not scanned[kk]:
                            dist = min_val + (v_free - v[kk])
                            if dist < d[kk]:
                                if d[kk] == np.inf:
                                    cand[n_cand] = kk
                                    n_cand += 1
                                    touched[n_touched] = kk
                                    n_touched += 1
                                d[kk] = dist
                                path[kk] = HUB
                    i = -1
            else:
                i = row4col[j]
        # dual update (with the old matching), then flip the path
        for t in range(n_rows):
            r = rows[t]
            if r == root:
                u[r] += min_val
            else:
                u[r] += min_val - d[col4row[r]]
        for t in range(n_done):
            j = done[t]
            v[j] -= min_val - d[j]
        new_v_free = v_free
        if hub_open:
            new_v_free = v_free - (min_val - hub_dist)
        j = sink
        while True:
            r = path[j]
            if r == HUB:
                row4col[j] = UNASSIGNED  # j is handed to a dummy row: free again
                j = hub_src
                continue
            row4col[j] = r
            prev = col4row[r]
            col4row[r] = j
            if r == root:
                break
            j = prev
        for t in range(n_touched):
            j = touched[t]
            d[j] = np.inf
            scanned[j] = False
            path[j] = UNASSIGNED
        return min_val, new_v_free

    for root in range(P):  # the root: a cold LSAP
        inc, _ = augment(root, COLD, 0.0)
        if inc == np.inf:
            return out[:0], out_cost[:0]

    # the partition tree: heap key (exact cost once solved, a lower bound before), slot of
    # the solution (NO_ENTRY until solved), slot of the parent's solution, head of the
    # forbidden-pair list (own pair first, then the ancestors'), rows fixed to the parent
    cap = _INITIAL_CAPACITY
    node_key = np.empty(cap)
    node_slot = np.empty(cap, dtype=np.int64)
    node_parent = np.empty(cap, dtype=np.int64)
    node_forb = np.empty(cap, dtype=np.int64)
    node_fixed = np.empty((cap, P), dtype=np.bool_)
    # solved nodes: assignment, row duals, dual of each row's column, free-column potential
    sol_cap = _INITIAL_CAPACITY
    sol = np.empty((sol_cap, P), dtype=np.int64)
    sol_u = np.empty((sol_cap, P))
    sol_v = np.empty((sol_cap, P))
    sol_vfree = np.empty(sol_cap)
    # forbidden pairs: row, graph entry, next entry of the list
    forb_cap = _INITIAL_CAPACITY
    forb_row = np.empty(forb_cap, dtype=np.int64)
    forb_entry = np.empty(forb_cap, dtype=np.int64)
    forb_next = np.empty(forb_cap, dtype=np.int64)
    # binary heap of (key, node id)
    heap_key = np.empty(cap)
    heap_id = np.empty(cap, dtype=np.int64)
    entry_of = np.empty(P, dtype=np.int64)
    order = np.empty(P, dtype=np.int64)
    lb = np.empty(P)
    fix_now = np.empty(P, dtype=np.bool_)

    key0 = 0.0
    for i in range(P):
        c = col4row[i]
        sol[0, i] = c
        sol_u[0, i] = u[i]
        sol_v[0, i] = v[c]
        key0 += cost0[pos[i, c]]
        row4col[c] = UNASSIGNED
        node_fixed[0, i] = False
    sol_vfree[0] = 0.0
    node_key[0] = key0
    node_slot[0] = 0
    node_parent[0] = NO_ENTRY
    node_forb[0] = NO_ENTRY
    n_nodes = 1
    n_sols = 1
    n_forb = 0
    heap_key[0] = key0
    heap_id[0] = 0
    n_heap = 1

    n_out = 0
    while n_heap > 0 and n_out < k:
        # pop the least (key, id)
        node = heap_id[0]
        n_heap -= 1
        kx = heap_key[n_heap]
        x = heap_id[n_heap]
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

        if node_slot[node] == NO_ENTRY:
            # a bounded node at the top: solve it, and queue it again with its exact cost
            ps = node_parent[node]
            f = node_forb[node]
            r = forb_row[f]
            for i in range(P):
                c = sol[ps, i]
                col4row[i] = c
                row4col[c] = i
                if node_fixed[node, i]:
                    active[c] = False  # a fixed row's column is out of the residual problem
                u[i] = sol_u[ps, i]
                v[c] = sol_v[ps, i]  # free columns: the shared potential, never read
            c = sol[ps, r]
            col4row[r] = UNASSIGNED
            row4col[c] = UNASSIGNED
            g = f
            while g != NO_ENTRY:
                cost[forb_entry[g]] = np.inf
                g = forb_next[g]
            inc, v_free = augment(r, c, sol_vfree[ps])
            g = f
            while g != NO_ENTRY:
                e = forb_entry[g]
                cost[e] = cost0[e]
                g = forb_next[g]
            if inc == np.inf:
                col4row[r] = c  # restore the loaded matching so that it can be cleared
                row4col[c] = r
                for i in range(P):
                    cc = col4row[i]
                    row4col[cc] = UNASSIGNED
                    active[cc] = True
                continue
            if n_sols == sol_cap:
                sol_cap = 2 * n_sols
                sol = _grow(sol, sol_cap)
                sol_u = _grow(sol_u, sol_cap)
                sol_v = _grow(sol_v, sol_cap)
                sol_vfree = _grow(sol_vfree, sol_cap)
            key = 0.0
            for i in range(P):
                cc = col4row[i]
                sol[n_sols, i] = cc
                sol_u[n_sols, i] = u[i]
                sol_v[n_sols, i] = v[cc]
                key += cost0[pos[i, cc]]
                row4col[cc] = UNASSIGNED
                active[cc] = True
            sol_vfree[n_sols] = v_free
            node_slot[node] = n_sols
            n_sols += 1
            node_key[node] = key
            # push (key, node)
            h = n_heap
            while h > 0:
                p = (h - 1) >> 1
                kp = heap_key[p]
                if key < kp or (key == kp and node < heap_id[p]):
                    heap_key[h] = kp
                    heap_id[h] = heap_id[p]
                    h = p
                else:
                    break
            heap_key[h] = key
            heap_id[h] = node
            n_heap += 1
            continue

        # a solved node at the top: report it
        sl = node_slot[node]
        if n_out == out_cap:
            out_cap = min(k, 2 * out_cap)
            out = _grow(out, out_cap)
            out_cost = _grow(out_cost, out_cap)
        key = node_key[node]
        for i in range(P):
            out[n_out, i] = sol[sl, i]
        out_cost[n_out] = key
        n_out += 1
        if n_out == k:
            break
        # partition it: the bound of each free row's child, with the node's forbidden pairs
        # switched off and its matching loaded (row4col, inactive columns of the fixed rows)
        head = node_forb[node]
        g = head
        while g != NO_ENTRY:
            cost[forb_entry[g]] = np.inf
            g = forb_next[g]
        vfree = sol_vfree[sl]
        slack = 1.0 + abs(key)
        for i in range(P):
            c = sol[sl, i]
            e = pos[i, c]
            entry_of[i] = e
            slack += abs(cost0[e]) + abs(sol_u[sl, i])
            row4col[c] = i
            fx = node_fixed[node, i]
            fix_now[i] = fx
            if fx:
                active[c] = False
        slack *= _BOUND_SLACK
        n_free = 0
        for i in range(P):
            if fix_now[i]:
                continue
            # smallest reduced cost of an allowed, active alternative j != s[i]
            best = np.inf
            ui = sol_u[sl, i]
            ei = entry_of[i]
            for e in range(ptr[i], ptr[i + 1]):
                cij = cost[e]
                j = col[e]
                if e == ei or cij == np.inf or not active[j]:
                    continue
                q = row4col[j]
                vj = vfree if q < 0 else sol_v[sl, q]
                rc = cij - ui - vj
                if rc < best:
                    best = rc
            lb[i] = max(best, 0.0)
            # insert row i, keeping decreasing bounds (ties keep row order)
            b = n_free - 1
            x = lb[i]
            while b >= 0 and lb[order[b]] < x:
                order[b + 1] = order[b]
                b -= 1
            order[b + 1] = i
            n_free += 1
        for i in range(P):
            c = sol[sl, i]
            row4col[c] = UNASSIGNED
            active[c] = True
        g = head
        while g != NO_ENTRY:
            e = forb_entry[g]
            cost[e] = cost0[e]
            g = forb_next[g]
        # children: child t forbids (order[t], s[order[t]]) and fixes order[:t]
        for t in range(n_free):
            r = order[t]
            if lb[r] < np.inf:
                if n_nodes == cap:
                    cap = 2 * n_nodes
                    node_key = _grow(node_key, cap)
                    node_slot = _grow(node_slot, cap)
                    node_parent = _grow(node_parent, cap)
                    node_forb = _grow(node_forb, cap)
                    node_fixed = _grow(node_fixed, cap)
                    heap_key = _grow(heap_key, cap)
                    heap_id = _grow(heap_id, cap)
                if n_forb == forb_cap:
                    forb_cap = 2 * n_forb
                    forb_row = _grow(forb_row, forb_cap)
                    forb_entry = _grow(forb_entry, forb_cap)
                    forb_next = _grow(forb_next, forb_cap)
                forb_row[n_forb] = r
                forb_entry[n_forb] = entry_of[r]
                forb_next[n_forb] = head
                ck = key + lb[r] - slack
                node_key[n_nodes] = ck
                node_slot[n_nodes] = NO_ENTRY
                node_parent[n_nodes] = sl
                node_forb[n_nodes] = n_forb
                for i in range(P):
                    node_fixed[n_nodes, i] = fix_now[i]
                n_forb += 1
                # push (ck, n_nodes)
                h = n_heap
                while h > 0:
                    p = (h - 1) >> 1
                    kp = heap_key[p]
                    if ck < kp or (ck == kp and n_nodes < heap_id[p]):
                        heap_key[h] = kp
                        heap_id[h] = heap_id[p]
                        h = p
                    else:
                        break
                heap_key[h] = ck
                heap_id[h] = n_nodes
                n_heap += 1
                n_nodes += 1
            fix_now[r] = True  # later children keep row r on its parent column
    return out[:n_out], out_cost[:n_out]


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
def murty_compact_kernel(cc, k):
    """:func:`murty_kernel` on a problem's compact costs ``(P, M + 2)``, ``P >= 1``."""
    P = cc.shape[0]
    M = cc.shape[1] - 2
    ptr, col, cost, pos = compact_graph(cc)
    return murty_kernel(ptr, col, cost, pos, P, M + 2 * P, k)

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

Layout for speed. The search (:func:`_search`) is one compiled loop on flat arrays that it
never reallocates: the warm-started augmenting path (the algorithm of
:func:`.lsap.sap_augment`, same arithmetic and tie-breaking) is written inline, and the tree,
the solutions, the forbidden-pair lists and the heap are plain arrays indexed by integers.
When an array is full the loop returns, the arrays are grown (:func:`grow_search`) and it is
called again. At these sizes (tens of rows, about one augmenting path of one or two row scans
per reported assignment) calls between small compiled helpers that each receive a dozen arrays,
array views made per node and arrays rebound inside the loop (each costs atomic reference
count updates) cost as much as the arithmetic; here nothing is allocated, called or
reference-counted per node. Further savings that leave every result bit for bit unchanged:
the partition's bounds read each column's dual from one array (``-inf`` for the columns of
fixed rows) without branches; the top of the heap is replaced in one sift-down (by the node
itself once solved, by its first child once partitioned); a scanned column is marked by
``d = -inf``; and a warm start keeps only the closest free column of its first row when that
column opens the dummy-row hub (the other free columns would leave the frontier unscanned).

Slices. The loop also returns after a budget of iterations, so that :func:`oracle.murty`
can run the search in slices (:func:`murty_compact_start`, then :func:`murty_slice` until
done, the state a :class:`Search`) and a signal ends a long ranking promptly; the slices make
the same iterations as one call, so the output does not depend on the budget.
"""

from __future__ import annotations

from collections import namedtuple

import numpy as np

from rankedassign.numba_options import jit

from .lsap import HUB, UNASSIGNED

__all__ = ["murty_kernel", "murty_compact_kernel", "murty_start", "murty_slice", "grow_search",
           "search_output", "pack_search", "compact_graph", "murty_compact_start", "Search",
           "DONE", "PAUSED", "FULL"]

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
def _search(ptr, col, cost, cost0, pos, u, v, col4row, row4col, active, d, path, rows_d,
            cand, touched, done, done_d, rows, node_key, node_slot, node_parent, node_forb,
            node_fixed, sol, sol_u, sol_v, sol_vfree, forb_row, forb_entry, forb_next, heap_key,
            heap_id, out_slot, out_cost, entry_of, order, lb, lb_col, fix_now, vx, sol_cost,
            sol_scale, kbest, state, k, budget):
    """Run the search until ``k`` assignments are reported, the queue is empty, an array is
    full or ``budget`` iterations are done; return True when finished (False: grow the arrays
    if one is full, and call again).

    The counters live in ``state`` between calls; an iteration starts only when every array
    has room for its worst case (``P`` children), so a return never leaves one half done, and
    the calls together make the same iterations as one call.
    """
    P = col4row.shape[0]
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
        if (n_out == out_slot.shape[0] or n_sols == sol.shape[0] or n_nodes + P > node_key.shape[0]
                or n_forb + P > forb_row.shape[0]
                or n_best == kbest.shape[0] < k  # (kbest never holds more than k)
                or n_iter >= stop_iter):
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

        if node_slot[node] == NO_ENTRY:
            # A bounded node at the top: solve it and queue it again with its exact cost.
            # Warm start: the parent's duals and assignment minus (root, freed), the node's
            # forbidden pairs switched off and its fixed rows' columns inactive.
            ps = node_parent[node]
            f = node_forb[node]
            root = forb_row[f]
            base = sol_cost[ps]
            # the margin for rounding: the parent's, set when it was partitioned
            cut += _BOUND_SLACK * (sol_scale[ps] + abs(cut))  # (+inf stays +inf)
            v_free = sol_vfree[ps]
            vx[:] = v_free  # as in the partition: the dual of each column, -inf if inactive
            for i in range(P):
                c = sol[ps, i]
                col4row[i] = c
                row4col[c] = i
                vc = sol_v[ps, i]
                v[c] = vc  # free columns: the shared potential, never read
                if (node_fixed[node, i >> 6] >> (i & 63)) & 1:
                    active[c] = False  # a fixed row's column is out of the residual problem
                    vx[c] = -np.inf
                else:
                    vx[c] = vc
                u[i] = sol_u[ps, i]
            freed = sol[ps, root]
            col4row[root] = UNASSIGNED
            row4col[freed] = UNASSIGNED
            g = f
            while g != NO_ENTRY:
                cost[forb_entry[g]] = np.inf
                g = forb_next[g]
            # One shortest augmenting path from root to freed (lsap.sap_augment, warm start).
            # The root's row is scanned first, when nothing is reached yet: every allowed,
            # active entry is reached (vx gives +inf for the others), and the closest column
            # is picked in the same pass. Of the dummy-held (free) columns only the closest is
            # kept at first: when it is the closest of all, the hub opens through it and the
            # other free columns would leave the frontier unscanned anyway; otherwise a second
            # pass reaches them too.
            n_rows = 1
            rows[0] = root
            rows_d[0] = 0.0
            n_cand = 0
            n_done = 0
            min_val = 0.0
            ui = u[root]
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
                                                             or (ends == best_ends
                                                                 and j < best_j))):
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
            n_touched = n_cand
            sink = -1
            hub_open = False
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
                i = -1
                if j == freed:
                    sink = j
                    break
                elif base + min_val > cut:  # the node costs at least this much: drop it
                    break
                elif row4col[j] < 0:
                    # a dummy-held column: open the hub, every column reachable through it
                    v[j] = v_free  # about to be matched: its potential made explicit
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
                else:
                    i = row4col[j]
                if i >= 0:  # scan row i
                    rows[n_rows] = i
                    rows_d[n_rows] = min_val
                    n_rows += 1
                    ui = u[i]
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
                # the closest reached column; ties: the freed column, then the lowest index
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
                    if dj < lowest or (ends and not best_ends) or (ends == best_ends
                                                                    and j < best_j):
                        lowest = dj
                        index = it
                        best_ends = ends
                        best_j = j
            if sink >= 0:
                # dual update (with the old matching), then flip the path
                for t in range(n_rows):  # (min_val - 0.0 is min_val for the root)
                    u[rows[t]] += min_val - rows_d[t]
                for t in range(n_done):
                    v[done[t]] -= min_val - done_d[t]
                if hub_open:
                    v_free = v_free - (min_val - hub_dist)
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
            for t in range(n_touched):  # clean workspace (path is only read where reached)
                j = touched[t]
                d[j] = np.inf
            g = f
            while g != NO_ENTRY:
                e = forb_entry[g]
                cost[e] = cost0[e]
                g = forb_next[g]
            if sink < 0:
                col4row[root] = freed  # restore the loaded matching so that it can be cleared
                row4col[freed] = root
                for i in range(P):
                    c = col4row[i]
                    row4col[c] = UNASSIGNED
                    active[c] = True
                n_heap -= 1  # the node leaves
                kx = heap_key[n_heap]
                x = heap_id[n_heap]
            else:
                key = 0.0
                for i in range(P):
                    c = col4row[i]
                    sol[n_sols, i] = c
                    sol_u[n_sols, i] = u[i]
                    sol_v[n_sols, i] = v[c]
                    key += cost0[pos[i, c]]
                    row4col[c] = UNASSIGNED
                    active[c] = True
                sol_vfree[n_sols] = v_free
                sol_cost[n_sols] = key
                # keep the k - n_out least solved costs in kbest: appended until there are
                # that many, then a max-heap (made once) whose top is replaced
                if n_best - n_stale < k - n_out:
                    kbest[n_best] = key
                    n_best += 1
                    if n_best - n_stale == k - n_out:  # full: heapify kbest[:n_best]
                        for h0 in range((n_best >> 1) - 1, -1, -1):
                            _sift_down_max(kbest, n_best, h0, kbest[h0])
                elif key < kbest[0]:
                    _sift_down_max(kbest, n_best, 0, key)
                node_slot[node] = n_sols
                n_sols += 1
                node_key[node] = key
                kx = key  # back into the queue with its exact cost
                x = node
        else:
            # a solved node at the top: report it
            sl = node_slot[node]
            key = node_key[node]
            out_slot[n_out] = sl  # copied into the output at the end
            out_cost[n_out] = key
            n_out += 1
            n_stale += 1  # its cost, the least in kbest, stays there as a stale entry
            if n_out == k:
                break
            # partition it: the bound of each free row's child, with the node's forbidden pairs
            # switched off. vx[j] is the dual the bound subtracts for column j: the shared
            # potential for a free column, v of its row for a matched one, -inf for the column of
            # a fixed row (inactive: its reduced cost is +inf), so the scan has no branch.
            head = node_forb[node]
            g = head
            while g != NO_ENTRY:
                cost[forb_entry[g]] = np.inf
                g = forb_next[g]
            vx[:] = sol_vfree[sl]
            slack = 1.0 + abs(key)
            for w in range(fix_now.shape[0]):
                fix_now[w] = node_fixed[node, w]
            for i in range(P):
                c = sol[sl, i]
                e = pos[i, c]
                entry_of[i] = e
                slack += abs(cost0[e]) + abs(sol_u[sl, i])
                vx[c] = -np.inf if (fix_now[i >> 6] >> (i & 63)) & 1 else sol_v[sl, i]
            sol_scale[sl] = slack  # the rounding scale of its children's solves
            slack *= _BOUND_SLACK
            cut += slack + _BOUND_SLACK * abs(cut)  # the margin, as in a solve
            n_free = 0
            for i in range(P):
                if (fix_now[i >> 6] >> (i & 63)) & 1:
                    continue
                # smallest reduced cost of an allowed, active alternative j != s[i]
                ei = entry_of[i]
                cost[ei] = np.inf  # the row's own entry is no alternative
                best = np.inf
                ui = sol_u[sl, i]
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
            # children: child t forbids (order[t], s[order[t]]) and fixes order[:t]
            for t in range(n_free):
                r = order[t]
                bx = lb[r]
                if t > 0 and bx < np.inf and cut < np.inf and vx[lb_col[r]] == -np.inf:
                    # Under a cut, child t's bound is its own first step: lb[r] again, with
                    # the columns of the rows fixed before it (order[:t]) inactive as well.
                    # It is the distance its solve would pop first, so a child that the
                    # solve would drop there is not created. (Unless the column that gave
                    # lb[r] is now inactive, that is lb[r] itself.)
                    ei = entry_of[r]
                    cost[ei] = np.inf
                    bx = _least_reduced_cost(ptr, col, cost, vx, r, sol_u[sl, r])
                    cost[ei] = cost0[ei]
                    bx = max(bx, 0.0)
                if bx < np.inf and key + bx - slack <= cut:
                    forb_row[n_forb] = r
                    forb_entry[n_forb] = entry_of[r]
                    forb_next[n_forb] = head
                    ck = key + bx - slack
                    node_key[n_nodes] = ck
                    node_slot[n_nodes] = NO_ENTRY
                    node_parent[n_nodes] = sl
                    node_forb[n_nodes] = n_forb
                    for w in range(fix_now.shape[0]):
                        node_fixed[n_nodes, w] = fix_now[w]
                    n_forb += 1
                    n_nodes += 1
                fix_now[r >> 6] |= np.int64(1) << (r & 63)  # later children: row r stays
                vx[sol[sl, r]] = -np.inf  # (its column, for the bounds of the later ones)
            g = head
            while g != NO_ENTRY:
                e = forb_entry[g]
                cost[e] = cost0[e]
                g = forb_next[g]
            if n_nodes == first:  # no child: the node leaves
                n_heap -= 1
                kx = heap_key[n_heap]
                x = heap_id[n_heap]
            else:
                kx = node_key[first]
                x = first
        # sift (kx, x) down from the top
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
        # push the other children
        for y in range(first + 1, n_nodes):
            ky = node_key[y]
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
            n_heap += 1
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
def _root_lsap(ptr, col, cost, u, v, col4row, row4col, d, path, rows_d, cand, touched, done,
               done_d, rows):
    """The root's LSAP: a cold shortest augmenting path from each row in turn.

    :func:`.lsap.sap_augment` with ``freed = COLD`` and ``v_free = 0`` (same arithmetic and
    tie-breaking), on flat arrays, a scanned column marked by ``d = -inf`` as in
    :func:`_search`. ``d`` must be ``+inf`` everywhere on entry (and is on return). Returns
    False when some row cannot be assigned (the problem is infeasible).
    """
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


#: The search's state between two calls of :func:`murty_slice`: the graph's current costs, the
#: assignment state and workspace, the partition tree and heap, the solutions, the max-heap of
#: the least solved costs, the forbidden-pair lists, the reported nodes, the counters
#: (``S_*``) and the partition's scratch arrays.
Search = namedtuple("Search", [
    "cost", "u", "v", "col4row", "row4col", "active", "d", "path", "cand", "touched", "done",
    "done_d", "rows", "rows_d", "node_key", "node_slot", "node_parent", "node_forb",
    "node_fixed", "heap_key", "heap_id", "sol", "sol_u", "sol_v", "sol_vfree", "sol_cost",
    "sol_scale", "kbest", "forb_row", "forb_entry", "forb_next", "out_slot", "out_cost",
    "state", "entry_of", "order", "lb", "lb_col", "fix_now", "vx"])

@jit()
def pack_search(sr):
    """A :class:`Search` as a plain tuple, the form it crosses into Python in.

    numba boxes a named tuple by calling its class, Python code, where a signal handler's
    exception crashes numba's return path (a segmentation fault, not an error); a plain tuple
    is built in C and only ever raises. ``Search(*t)`` unpacks it in compiled code.
    """
    return (sr.cost, sr.u, sr.v, sr.col4row, sr.row4col, sr.active, sr.d, sr.path, sr.cand,
            sr.touched, sr.done, sr.done_d, sr.rows, sr.rows_d, sr.node_key, sr.node_slot,
            sr.node_parent, sr.node_forb, sr.node_fixed, sr.heap_key, sr.heap_id, sr.sol, sr.sol_u,
            sr.sol_v, sr.sol_vfree, sr.sol_cost, sr.sol_scale, sr.kbest, sr.forb_row,
            sr.forb_entry, sr.forb_next, sr.out_slot, sr.out_cost, sr.state, sr.entry_of, sr.order,
            sr.lb, sr.lb_col, sr.fix_now, sr.vx)


#: :func:`murty_slice`: the search is over, a slice's budget is spent, an array is full.
DONE, PAUSED, FULL = 0, 1, 2


@jit()
def new_search(ptr, col, cost0, pos, P, N, k):
    """The root's LSAP and a :class:`Search` with the root in the queue.

    Arguments as in :func:`murty_kernel`. Returns ``(ok, search)``, the search packed
    (:func:`pack_search`); ``ok`` is False when the problem has no feasible assignment (the
    search is then empty).
    """
    cost = cost0.copy()  # forbidden entries of the current node are set to +inf for a while
    # the assignment state (duals, matching, active columns) and the search's workspace
    u = np.zeros(P)
    v = np.zeros(N)
    col4row = np.full(P, UNASSIGNED, dtype=np.int64)
    row4col = np.full(N, UNASSIGNED, dtype=np.int64)
    active = np.ones(N, dtype=np.bool_)
    d = np.full(N, np.inf)
    path = np.empty(N, dtype=np.int64)
    cand = np.empty(N, dtype=np.int64)
    touched = np.empty(N, dtype=np.int64)
    done = np.empty(N, dtype=np.int64)
    done_d = np.empty(N)
    rows = np.empty(P, dtype=np.int64)
    rows_d = np.empty(P)
    ok = _root_lsap(ptr, col, cost, u, v, col4row, row4col, d, path, rows_d, cand, touched,
                    done, done_d, rows)
    # the partition tree: heap key (exact cost once solved, a lower bound before), slot of
    # the solution (NO_ENTRY until solved), slot of the parent's solution, head of the
    # forbidden-pair list (own pair first, then the ancestors'), rows fixed to the parent
    cap = max(_INITIAL_CAPACITY, 2 * P)
    node_key = np.empty(cap)
    node_slot = np.empty(cap, dtype=np.int64)
    node_parent = np.empty(cap, dtype=np.int64)
    node_forb = np.empty(cap, dtype=np.int64)
    n_words = (P + 63) >> 6  # fixed rows as bits, 64 to a word
    node_fixed = np.zeros((cap, n_words), dtype=np.int64)
    heap_key = np.empty(cap)  # binary heap of (key, node id)
    heap_id = np.empty(cap, dtype=np.int64)
    # solved nodes: assignment, row duals, dual of each row's column, free-column potential
    sol_cap = _INITIAL_CAPACITY
    sol = np.empty((sol_cap, P), dtype=np.int64)
    sol_u = np.empty((sol_cap, P))
    sol_v = np.empty((sol_cap, P))
    sol_vfree = np.empty(sol_cap)
    sol_cost = np.empty(sol_cap)  # exact cost of each solution, and its rounding scale
    sol_scale = np.empty(sol_cap)
    kbest = np.empty(min(k, _INITIAL_CAPACITY))  # max-heap: the least solved costs
    # forbidden pairs: row, graph entry, next entry of the list
    forb_cap = max(_INITIAL_CAPACITY, 2 * P)
    forb_row = np.empty(forb_cap, dtype=np.int64)
    forb_entry = np.empty(forb_cap, dtype=np.int64)
    forb_next = np.empty(forb_cap, dtype=np.int64)
    out_cap = min(k, _INITIAL_CAPACITY)
    out_slot = np.empty(out_cap, dtype=np.int64)  # solution slot of each reported node
    out_cost = np.empty(out_cap)
    state = np.zeros(N_STATE, dtype=np.int64)
    search = Search(cost, u, v, col4row, row4col, active, d, path, cand, touched, done, done_d,
                    rows, rows_d, node_key, node_slot, node_parent, node_forb, node_fixed,
                    heap_key, heap_id, sol, sol_u, sol_v, sol_vfree, sol_cost, sol_scale, kbest,
                    forb_row, forb_entry, forb_next, out_slot, out_cost, state,
                    np.empty(P, dtype=np.int64), np.empty(P, dtype=np.int64), np.empty(P),
                    np.empty(P, dtype=np.int64), np.empty(n_words, dtype=np.int64),
                    np.empty(N))
    if not ok:
        return False, pack_search(search)
    key0 = 0.0
    for i in range(P):
        c = col4row[i]
        sol[0, i] = c
        sol_u[0, i] = u[i]
        sol_v[0, i] = v[c]
        key0 += cost0[pos[i, c]]
        row4col[c] = UNASSIGNED
    sol_vfree[0] = 0.0
    sol_cost[0] = key0
    kbest[0] = key0
    node_key[0] = key0
    node_slot[0] = 0
    node_parent[0] = NO_ENTRY
    node_forb[0] = NO_ENTRY
    heap_key[0] = key0
    heap_id[0] = 0
    state[S_HEAP] = 1
    state[S_NODES] = 1
    state[S_SOLS] = 1
    state[S_BEST] = 1
    return True, pack_search(search)


@jit()
def murty_slice(ptr, col, cost0, pos, search, k, budget):
    """At most ``budget`` iterations of ``search`` (a packed :class:`Search`), in place.

    Returns :data:`DONE`, :data:`PAUSED` (call again) or :data:`FULL` (an array is full:
    :func:`grow_search`, then call again). Only an integer comes back, so a signal that
    arrived during the call is raised by the caller as itself.
    """
    sr = Search(*search)
    if _search(ptr, col, sr.cost, cost0, pos, sr.u, sr.v, sr.col4row, sr.row4col, sr.active,
               sr.d, sr.path, sr.rows_d, sr.cand, sr.touched, sr.done, sr.done_d, sr.rows,
               sr.node_key, sr.node_slot, sr.node_parent, sr.node_forb, sr.node_fixed, sr.sol,
               sr.sol_u, sr.sol_v, sr.sol_vfree, sr.forb_row, sr.forb_entry, sr.forb_next,
               sr.heap_key, sr.heap_id, sr.out_slot, sr.out_cost, sr.entry_of, sr.order, sr.lb,
               sr.lb_col, sr.fix_now, sr.vx, sr.sol_cost, sr.sol_scale, sr.kbest, sr.state, k,
               budget):
        return DONE
    state = sr.state
    P = sr.col4row.shape[0]
    if (state[S_OUT] == sr.out_slot.shape[0] or state[S_SOLS] == sr.sol.shape[0]
            or state[S_BEST] == sr.kbest.shape[0] < k or state[S_NODES] + P > sr.node_key.shape[0]
            or state[S_FORB] + P > sr.forb_row.shape[0]):
        return FULL
    return PAUSED


@jit()
def grow_search(search, k):
    """Packed ``search`` with every full array doubled (every array the next iteration may
    fill)."""
    sr = Search(*search)
    P = sr.col4row.shape[0]
    state = sr.state
    out_slot, out_cost = sr.out_slot, sr.out_cost
    if state[S_OUT] == out_slot.shape[0]:
        out_slot = _grow(out_slot, min(k, 2 * out_slot.shape[0]))
        out_cost = _grow(out_cost, out_slot.shape[0])
    sol, sol_u, sol_v = sr.sol, sr.sol_u, sr.sol_v
    sol_vfree, sol_cost, sol_scale = sr.sol_vfree, sr.sol_cost, sr.sol_scale
    if state[S_SOLS] == sol.shape[0]:
        n = 2 * sol.shape[0]
        sol = _grow(sol, n)
        sol_u = _grow(sol_u, n)
        sol_v = _grow(sol_v, n)
        sol_vfree = _grow(sol_vfree, n)
        sol_cost = _grow(sol_cost, n)
        sol_scale = _grow(sol_scale, n)
    kbest = sr.kbest
    if state[S_BEST] == kbest.shape[0] < k:
        kbest = _grow(kbest, min(k, 2 * kbest.shape[0]))
    node_key, node_slot, node_parent = sr.node_key, sr.node_slot, sr.node_parent
    node_forb, node_fixed, heap_key, heap_id = sr.node_forb, sr.node_fixed, sr.heap_key, sr.heap_id
    if state[S_NODES] + P > node_key.shape[0]:
        n = 2 * node_key.shape[0]
        node_key = _grow(node_key, n)
        node_slot = _grow(node_slot, n)
        node_parent = _grow(node_parent, n)
        node_forb = _grow(node_forb, n)
        node_fixed = _grow(node_fixed, n)
        heap_key = _grow(heap_key, n)
        heap_id = _grow(heap_id, n)
    forb_row, forb_entry, forb_next = sr.forb_row, sr.forb_entry, sr.forb_next
    if state[S_FORB] + P > forb_row.shape[0]:
        n = 2 * forb_row.shape[0]
        forb_row = _grow(forb_row, n)
        forb_entry = _grow(forb_entry, n)
        forb_next = _grow(forb_next, n)
    return pack_search(Search(
        sr.cost, sr.u, sr.v, sr.col4row, sr.row4col, sr.active, sr.d, sr.path, sr.cand,
        sr.touched, sr.done, sr.done_d, sr.rows, sr.rows_d, node_key, node_slot, node_parent,
        node_forb, node_fixed, heap_key, heap_id, sol, sol_u, sol_v, sol_vfree, sol_cost,
        sol_scale, kbest, forb_row, forb_entry, forb_next, out_slot, out_cost, state,
        sr.entry_of, sr.order, sr.lb, sr.lb_col, sr.fix_now, sr.vx))


@jit()
def search_output(search):
    """The reported assignments ``(n, P)`` and their costs ``(n,)`` of a finished (packed)
    search."""
    sr = Search(*search)
    P = sr.col4row.shape[0]
    sol, out_slot, out_cost = sr.sol, sr.out_slot, sr.out_cost
    n_out = sr.state[S_OUT]
    out = np.empty((n_out, P), dtype=np.int64)
    for t in range(n_out):
        for i in range(P):
            out[t, i] = sol[out_slot[t], i]
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
def murty_start(ptr, col, cost0, pos, P, N, k, budget):
    """:func:`new_search` and its first ``budget`` iterations (:func:`murty_slice`).

    Returns ``(assignments, costs, None)`` as documented in :func:`murty_kernel` when the
    search ends within the budget (one call: small searches cost what they cost before),
    else ``(empty, empty, search)`` with the packed :class:`Search` to continue.
    """
    ok, search = new_search(ptr, col, cost0, pos, P, N, k)
    if not ok:
        return np.empty((0, P), dtype=np.int64), np.empty(0), None
    status = murty_slice(ptr, col, cost0, pos, search, k, budget)
    while status == FULL:
        search = grow_search(search, k)
        done = Search(*search).state[S_ITER]
        status = murty_slice(ptr, col, cost0, pos, search, k, max(1, budget - done))
    if status == DONE:
        out, costs = search_output(search)
        return out, costs, None
    return np.empty((0, P), dtype=np.int64), np.empty(0), search


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
    """
    out, costs, _ = murty_start(ptr, col, cost0, pos, P, N, k, 1 << 62)
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
    empty, (graph, search))`` with the graph ``(ptr, col, cost, pos)`` of
    :func:`compact_graph` and the packed search to continue with :func:`murty_slice`.
    """
    P = cc.shape[0]
    M = cc.shape[1] - 2
    ptr, col, cost, pos = compact_graph(cc)
    out, costs, search = murty_start(ptr, col, cost, pos, P, M + 2 * P, k, budget)
    if search is None:
        return out, costs, None
    return out, costs, ((ptr, col, cost, pos), search)


@jit()
def murty_compact_kernel(cc, k):
    """:func:`murty_kernel` on a problem's compact costs ``(P, M + 2)``, ``P >= 1``."""
    P = cc.shape[0]
    M = cc.shape[1] - 2
    ptr, col, cost, pos = compact_graph(cc)
    return murty_kernel(ptr, col, cost, pos, P, M + 2 * P, k)

"""Compiled Murty k-best ranked assignment (spec §5.1) with the Miller–Stone–Cox improvements.

The driver :func:`murty_kernel` pops the best open subproblem, reports it and partitions it;
each phase is a small helper: the node's working matrix (:func:`_apply_forbidden`), the
partition order (:func:`_partition_order`), one warm-started child (:func:`_solve_child`) and
its storage (:func:`_store_node`). Costs are accumulated row by row in the order ``0..P-1``
from ``0.0``, exactly as :meth:`rankedassign.AssignmentProblem.cost_of` does.
"""

from __future__ import annotations

from collections import namedtuple

import numpy as np

from rankedassign.numba_options import jit

from .lsap import UNASSIGNED, lsap_kernel, new_workspace, sap_augment

__all__ = ["murty_kernel"]

NO_NODE = -1  # end of a forbidden-pair list
_INITIAL_CAPACITY = 1024

#: The partition tree. Node ``n`` holds its optimal assignment ``sol[n]``, optimal duals
#: ``u[n], v[n]``, the common potential ``v_free[n]`` of its free columns, its cost ``key[n]``,
#: which rows it fixes (``fixed[n]``) and the head of its forbidden-pair list
#: (``forb_head[n]``, an index into :data:`Forbidden`, shared with its ancestors).
Nodes = namedtuple("Nodes", ["sol", "u", "v", "v_free", "key", "fixed", "forb_head"])

#: Forbidden pairs as linked lists: entry ``f`` forbids ``(row[f], col[f])`` and continues at
#: ``next[f]`` (``NO_NODE`` ends the list).
Forbidden = namedtuple("Forbidden", ["row", "col", "next"])

#: One child's assignment state, warm-started from its parent.
ChildState = namedtuple("ChildState", ["u", "v", "col4row", "row4col", "active"])


@jit()
def _row_cost(C, a):
    s = 0.0
    for i in range(a.shape[0]):
        s += C[i, a[i]]  # row order 0..P-1, as AssignmentProblem.cost_of
    return s


@jit()
def _heap_less(keys, heap, a, b):
    """Compare heap slots ``a, b`` by (cost, node id): deterministic order among equal costs."""
    na = heap[a]
    nb = heap[b]
    return keys[na] < keys[nb] or (keys[na] == keys[nb] and na < nb)


@jit()
def _heap_push(heap, n, keys, node):
    heap[n] = node
    k = n
    while k > 0:
        p = (k - 1) >> 1
        if _heap_less(keys, heap, k, p):
            heap[k], heap[p] = heap[p], heap[k]
            k = p
        else:
            break
    return n + 1


@jit()
def _heap_pop(heap, n, keys):
    top = heap[0]
    n -= 1
    heap[0] = heap[n]
    k = 0
    while True:
        left = 2 * k + 1
        if left >= n:
            break
        c = left
        if left + 1 < n and _heap_less(keys, heap, left + 1, left):
            c = left + 1
        if _heap_less(keys, heap, c, k):
            heap[k], heap[c] = heap[c], heap[k]
            k = c
        else:
            break
    return top, n


@jit()
def _grow(a, n):
    """``a`` copied into a new array with ``n`` rows (first axis)."""
    out = np.empty((n,) + a.shape[1:], dtype=a.dtype)
    out[: a.shape[0]] = a
    return out


@jit()
def _new_nodes(cap, P, N):
    return Nodes(np.empty((cap, P), dtype=np.int64), np.empty((cap, P)), np.empty((cap, N)),
                 np.empty(cap), np.empty(cap), np.zeros((cap, P), dtype=np.bool_),
                 np.empty(cap, dtype=np.int64))


@jit()
def _grow_nodes(nodes, cap):
    return Nodes(_grow(nodes.sol, cap), _grow(nodes.u, cap), _grow(nodes.v, cap),
                 _grow(nodes.v_free, cap), _grow(nodes.key, cap), _grow(nodes.fixed, cap),
                 _grow(nodes.forb_head, cap))


@jit()
def _grow_forbidden(forb, cap):
    return Forbidden(_grow(forb.row, cap), _grow(forb.col, cap), _grow(forb.next, cap))


@jit()
def _apply_forbidden(C, W, forb, head):
    """``W = C`` with the pairs of the forbidden list starting at ``head`` set to ``+inf``."""
    P, N = C.shape
    for i in range(P):
        for j in range(N):
            W[i, j] = C[i, j]
    f = head
    while f != NO_NODE:
        W[forb.row[f], forb.col[f]] = np.inf
        f = forb.next[f]


@jit()
def _partition_order(W, s, pu, pv, fixed, lb, order):
    """Free rows of a node in decreasing order of a lower bound on their child's increase.

    ``lb[i]`` is the smallest reduced cost ``W[i, j] - pu[i] - pv[j]`` of an alternative column
    ``j != s[i]`` (``+inf``: the child is infeasible). Children expected to be worst get the
    fewest fixings, the most promising ones the smallest residual problems (Miller, Stone &
    Cox 1997). Returns the number of free rows, listed in ``order``; ties keep row order.
    """
    P, N = W.shape
    n_free = 0
    for i in range(P):
        if not fixed[i]:
            best = np.inf
            for j in range(N):
                if j != s[i] and W[i, j] < np.inf:
                    r = W[i, j] - pu[i] - pv[j]
                    if r < best:
                        best = r
            lb[i] = best
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
def _solve_child(W, C, r, s, fix_now, pu, pv, pvf, st, ws):
    """Child of a node with solution ``s``: forbid ``(r, s[r])``, keep the rows ``fix_now``.

    Warm start (Miller, Stone & Cox 1997): the parent's duals and assignment minus row ``r``,
    completed by one shortest augmenting path from ``r``. Fills ``st`` and returns
    ``(increase, v_free)``; ``increase = +inf`` when the child is infeasible.
    """
    P, N = W.shape
    c = s[r]
    for j in range(N):
        st.row4col[j] = UNASSIGNED
        st.active[j] = True
    for i in range(P):
        st.col4row[i] = s[i]
        st.row4col[s[i]] = i
        if fix_now[i]:
            st.active[s[i]] = False  # a fixed row's column is out of the residual problem
    st.col4row[r] = UNASSIGNED
    st.row4col[c] = UNASSIGNED
    st.u[:] = pu
    st.v[:] = pv
    W[r, c] = np.inf
    inc, nvf = sap_augment(W, r, c, st.u, st.v, st.col4row, st.row4col, st.active, pvf, ws)
    W[r, c] = C[r, c]
    return inc, nvf


@jit()
def _store_node(nodes, nd, st, v_free, fix_now, forb_entry, key):
    """Write a solved child into slot ``nd`` of the tree."""
    nodes.sol[nd] = st.col4row
    nodes.u[nd] = st.u
    nodes.v[nd] = st.v
    nodes.v_free[nd] = v_free
    nodes.fixed[nd] = fix_now
    nodes.forb_head[nd] = forb_entry
    nodes.key[nd] = key


@jit()
def murty_kernel(C, k):
    """Murty's ranked assignment with the Miller–Stone–Cox improvements.

    Parameters
    ----------
    C : ndarray, float64, shape (P, N), 1 <= P <= N
        Cost matrix (``+inf`` = forbidden); at least one feasible assignment exists.
    k : int
        Number of assignments wanted (>= 1).

    Returns
    -------
    ndarray, int64, shape (n, P)
        The ``n = min(k, |Gamma|)`` best assignments in non-decreasing cost; among equal
        costs, in order of creation.

    Notes
    -----
    Each node of the partition tree is a subproblem: a set of rows fixed to their parent's
    columns and a set of forbidden pairs (a linked list shared with the ancestors). Popping a
    node with solution ``s`` creates one child per free row ``r``: forbid ``(r, s[r])`` and
    fix the rows processed before it (:func:`_partition_order`). Each child is solved by a
    single warm-started shortest augmenting path (:func:`_solve_child`), ``O(P N)`` instead of
    a full LSAP.
    """
    P, N = C.shape
    out = np.empty((k, P), dtype=np.int64)
    ok, col4row, u, v = lsap_kernel(C)  # the root: a cold LSAP
    if not ok:
        return out[:0]
    nodes = _new_nodes(_INITIAL_CAPACITY, P, N)
    forb = Forbidden(np.empty(_INITIAL_CAPACITY, dtype=np.int64),
                     np.empty(_INITIAL_CAPACITY, dtype=np.int64),
                     np.empty(_INITIAL_CAPACITY, dtype=np.int64))
    heap = np.empty(_INITIAL_CAPACITY, dtype=np.int64)
    st = ChildState(u, v, col4row, np.empty(N, dtype=np.int64), np.empty(N, dtype=np.bool_))
    _store_node(nodes, 0, st, 0.0, np.zeros(P, dtype=np.bool_), NO_NODE, _row_cost(C, col4row))
    st = ChildState(np.empty(P), np.empty(N), np.empty(P, dtype=np.int64),
                    np.empty(N, dtype=np.int64), np.empty(N, dtype=np.bool_))
    n_nodes = 1
    n_forb = 0
    n_heap = _heap_push(heap, 0, nodes.key, 0)

    W = np.empty((P, N))
    ws = new_workspace(P, N)
    order = np.empty(P, dtype=np.int64)
    lb = np.empty(P)
    fix_now = np.empty(P, dtype=np.bool_)
    n_out = 0
    while n_heap > 0 and n_out < k:
        node, n_heap = _heap_pop(heap, n_heap, nodes.key)
        s = nodes.sol[node].copy()
        out[n_out] = s
        n_out += 1
        if n_out == k:
            break
        pu = nodes.u[node].copy()
        pv = nodes.v[node].copy()
        pvf = nodes.v_free[node]
        _apply_forbidden(C, W, forb, nodes.forb_head[node])
        fix_now[:] = nodes.fixed[node]
        n_free = _partition_order(W, s, pu, pv, fix_now, lb, order)
        for t in range(n_free):
            r = order[t]
            if lb[r] < np.inf:
                # child t: forbid (r, s[r]), rows order[:t] fixed
                inc, nvf = _solve_child(W, C, r, s, fix_now, pu, pv, pvf, st, ws)
                if inc < np.inf:
                    if n_nodes == nodes.sol.shape[0]:
                        nodes = _grow_nodes(nodes, 2 * n_nodes)
                        heap = _grow(heap, 2 * n_nodes)
                    if n_forb == forb.row.shape[0]:
                        forb = _grow_forbidden(forb, 2 * n_forb)
                    forb.row[n_forb] = r
                    forb.col[n_forb] = s[r]
                    forb.next[n_forb] = nodes.forb_head[node]
                    _store_node(nodes, n_nodes, st, nvf, fix_now, n_forb,
                                _row_cost(C, st.col4row))
                    n_forb += 1
                    n_heap = _heap_push(heap, n_heap, nodes.key, n_nodes)
                    n_nodes += 1
            fix_now[r] = True  # later children keep row r on its parent column
    return out[:n_out]

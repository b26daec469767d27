"""Compiled kernels of the oracle: enumeration, shortest-augmenting-path LSAP, Murty, subset DP.

Every kernel lives in this one file because numba's on-disk cache only tracks the file of the
decorated function: a helper imported from another module could change without invalidating
the cached callers. The public wrappers (:mod:`oracle.enumerate`, :mod:`oracle.murty`,
:mod:`oracle.dp`) validate their input once; the kernels assume clean, C-contiguous float64 /
int64 arrays and never raise.

Conventions shared by the kernels
---------------------------------
* ``C`` is the ``(P, N)`` cost matrix in the paper's layout, ``N = M + 2P``; ``+inf`` marks a
  missing edge. No "big number" stands in for ``+inf``: an infinite entry is simply never
  relaxed, so arbitrarily large (and negative) finite costs stay exact.
* A cost is accumulated row by row in the order ``0..P-1`` starting from ``0.0``, exactly as
  :meth:`rankedassign.AssignmentProblem.cost_of` does, so a kernel's cost of an assignment is
  bit-for-bit the public one.
"""

from __future__ import annotations

import numpy as np

from rankedassign.numba_options import jit

_HUB = -2  # path marker: the column was reached through a dummy row (rectangular slack)


# ----------------------------------------------------------------------------- enumeration
@jit()
def enumerate_kernel(cc, n_out):  # pragma: no cover - compiled
    """Depth-first enumeration of every feasible assignment.

    Parameters
    ----------
    cc : ndarray, float64, shape (P, M + 2)
        Compact costs ``[meas 0..M-1 | missed | dead]`` per row (``+inf`` = forbidden).
    n_out : int
        Exact number of feasible assignments (the caller counted them).

    Returns
    -------
    ndarray, int64, shape (n_out, P)
        Column indices in the full ``(P, M + 2P)`` layout, in depth-first order (row 0 slowest,
        options of each row in increasing compact index).
    """
    P = cc.shape[0]
    M = cc.shape[1] - 2
    out = np.empty((n_out, P), dtype=np.int64)
    if P == 0:
        return out
    used = np.zeros(M, dtype=np.bool_)
    opt = np.full(P, -1, dtype=np.int64)  # current compact option of each row on the stack
    row = 0
    n = 0
    while row >= 0:
        # release the option this row held before trying the next one
        o = opt[row]
        if 0 <= o < M:
            used[o] = False
        o += 1
        while o < M + 2 and (not np.isfinite(cc[row, o]) or (o < M and used[o])):
            o += 1
        if o == M + 2:  # options of this row exhausted: backtrack
            opt[row] = -1
            row -= 1
            continue
        opt[row] = o
        if o < M:
            used[o] = True
        if row == P - 1:
            if n < n_out:
                for i in range(P):
                    oi = opt[i]
                    if oi < M:
                        out[n, i] = oi
                    elif oi == M:
                        out[n, i] = M + i  # the row's own missed column
                    else:
                        out[n, i] = M + P + i  # the row's own dead column
            n += 1
        else:
            row += 1
    return out


@jit()
def count_kernel(cc, cap):  # pragma: no cover - compiled
    """Count feasible assignments by depth-first search, stopping once the count exceeds ``cap``.

    Returns ``min(count, cap + 1)``. Used only when the exact counting DP of
    :meth:`~rankedassign.AssignmentProblem.n_feasible` refuses the size.
    """
    P = cc.shape[0]
    M = cc.shape[1] - 2
    if P == 0:
        return 1
    used = np.zeros(M, dtype=np.bool_)
    opt = np.full(P, -1, dtype=np.int64)
    row = 0
    n = 0
    while row >= 0:
        o = opt[row]
        if 0 <= o < M:
            used[o] = False
        o += 1
        while o < M + 2 and (not np.isfinite(cc[row, o]) or (o < M and used[o])):
            o += 1
        if o == M + 2:
            opt[row] = -1
            row -= 1
            continue
        opt[row] = o
        if o < M:
            used[o] = True
        if row == P - 1:
            n += 1
            if n > cap:
                return n
        else:
            row += 1
    return n


# ----------------------------------------------------------------------------- LSAP
@jit()
def sap_augment(
    C, root, freed, u, v, col4row, row4col, col_active, v_free, d, path, scanned_r, scanned_c,
    remaining,
):  # pragma: no cover - compiled
    """One shortest augmenting path (Dijkstra on reduced costs) from the free row ``root``.

    Rectangular LSAP (rows <= columns) viewed as the square problem in which every free
    column is held by a zero-cost dummy row. Invariants on entry: ``C[i, j] - u[i] - v[j] >= 0``
    on every finite edge of an active column, equality on matched edges, and every free active
    column other than ``freed`` has potential ``v_free`` with ``v[j] <= v_free`` for all ``j``
    (the dummy rows' dual feasibility).

    ``freed = -1`` (a cold step, as in SciPy's ``linear_sum_assignment``): the path ends at the
    first free column reached. ``freed = c >= 0`` (a warm start after un-assigning the pair
    ``(root, c)``, Miller, Stone & Cox 1997): in the square view ``c`` is the only free column,
    and any dummy-held column ``j`` hops to every column ``k`` at reduced cost
    ``v_free - v[k] >= 0`` (the dummy row's edges). All dummy-held columns are reached at the
    same distance, so the first one popped opens that "hub" for all of them at once.

    Updates ``u, v, col4row, row4col`` in place and returns ``(increase, new_v_free)``;
    ``increase = +inf`` when no augmenting path exists (the subproblem is infeasible; the
    arrays are then left partly updated and must be discarded).
    """
    N = C.shape[1]
    P = C.shape[0]
    n_rem = 0
    for j in range(N):
        d[j] = np.inf
        path[j] = -1
        scanned_c[j] = False
        if col_active[j]:
            remaining[n_rem] = j
            n_rem += 1
    for i in range(P):
        scanned_r[i] = False
    min_val = 0.0
    i = root
    sink = -1
    hub_open = False
    hub_src = -1
    while sink < 0:
        if i >= 0:
            scanned_r[i] = True
            ui = u[i]
            for it in range(n_rem):
                j = remaining[it]
                cij = C[i, j]
                if cij < np.inf:
                    r = min_val + (cij - ui - v[j])
                    if r < d[j]:
                        d[j] = r
                        path[j] = i
        lowest = np.inf
        index = -1
        for it in range(n_rem):
            j = remaining[it]
            dj = d[j]
            # ties: prefer a column that ends the path (shorter paths, deterministic)
            if dj < lowest or (
                dj == lowest and index >= 0 and (j == freed or (freed < 0 and row4col[j] < 0))
            ):
                lowest = dj
                index = it
        if index < 0 or lowest == np.inf:
            return np.inf, v_free
        min_val = lowest
        j = remaining[index]
        scanned_c[j] = True
        n_rem -= 1
        remaining[index] = remaining[n_rem]
        if j == freed:
            sink = j
        elif row4col[j] < 0:
            if freed < 0:
                sink = j
            else:
                # open the hub: every other dummy-held column is reached at min_val too, and
                # every column k at min_val + v_free - v[k]
                hub_open = True
                hub_src = j
                it = 0
                while it < n_rem:
                    k = remaining[it]
                    if row4col[k] < 0 and k != freed:
                        d[k] = min_val
                        path[k] = _HUB
                        scanned_c[k] = True
                        n_rem -= 1
                        remaining[it] = remaining[n_rem]
                    else:
                        h = min_val + (v_free - v[k])
                        if h < d[k]:
                            d[k] = h
                            path[k] = _HUB
                        it += 1
                i = -1
        else:
            i = row4col[j]
    # dual update (before augmenting: uses the old col4row)
    u[root] += min_val
    for r in range(P):
        if scanned_r[r] and r != root:
            u[r] += min_val - d[col4row[r]]
    for j in range(N):
        if scanned_c[j]:
            v[j] -= min_val - d[j]
    new_v_free = v_free
    if hub_open:
        new_v_free = v_free - (min_val - d[hub_src])
    # augment along the path
    j = sink
    while True:
        r = path[j]
        if r == _HUB:
            row4col[j] = -1  # j is handed to a dummy row: free again
            j = hub_src
            continue
        row4col[j] = r
        prev = col4row[r]
        col4row[r] = j
        if r == root:
            break
        j = prev
    return min_val, new_v_free


@jit()
def lsap_kernel(C):  # pragma: no cover - compiled
    """Rectangular LSAP with duals by successive shortest augmenting paths.

    Parameters
    ----------
    C : ndarray, float64, shape (P, N), P <= N
        ``+inf`` = no edge; finite entries may be negative and arbitrarily large.

    Returns
    -------
    ok : bool
        False when no assignment of every row exists.
    col4row : ndarray, int64, shape (P,)
    u, v : ndarray, float64, shapes (P,), (N,)
        Optimal duals: ``C - u - v >= 0`` on finite edges, ``= 0`` on matched edges,
        ``v <= 0`` and ``v = 0`` on unmatched columns; ``sum(u) + sum(v)`` is the optimum.
    """
    P, N = C.shape
    u = np.zeros(P)
    v = np.zeros(N)
    col4row = np.full(P, -1, dtype=np.int64)
    row4col = np.full(N, -1, dtype=np.int64)
    active = np.ones(N, dtype=np.bool_)
    d = np.empty(N)
    path = np.empty(N, dtype=np.int64)
    sr = np.empty(P, dtype=np.bool_)
    sc = np.empty(N, dtype=np.bool_)
    rem = np.empty(N, dtype=np.int64)
    for root in range(P):
        inc, _ = sap_augment(C, root, -1, u, v, col4row, row4col, active, 0.0, d, path, sr, sc,
                             rem)
        if inc == np.inf:
            return False, col4row, u, v
    return True, col4row, u, v


# ----------------------------------------------------------------------------- Murty
@jit()
def _row_cost(C, a):  # pragma: no cover - compiled
    s = 0.0
    for i in range(a.shape[0]):
        s += C[i, a[i]]  # row order 0..P-1, as AssignmentProblem.cost_of
    return s


@jit()
def _heap_less(keys, heap, a, b):  # pragma: no cover - compiled
    # compare heap slots a, b by (cost, node id): deterministic order among equal costs
    na = heap[a]
    nb = heap[b]
    return keys[na] < keys[nb] or (keys[na] == keys[nb] and na < nb)


@jit()
def _heap_push(heap, n, keys, node):  # pragma: no cover - compiled
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
def _heap_pop(heap, n, keys):  # pragma: no cover - compiled
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
def _grow2(a, n):  # pragma: no cover - compiled
    out = np.empty((n, a.shape[1]), dtype=a.dtype)
    out[: a.shape[0]] = a
    return out


@jit()
def _grow1(a, n):  # pragma: no cover - compiled
    out = np.empty(n, dtype=a.dtype)
    out[: a.shape[0]] = a
    return out


@jit()
def murty_kernel(C, k):  # pragma: no cover - compiled
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
    columns and a set of forbidden pairs (kept as a linked list shared with the ancestors).
    A node stores its optimal assignment, its optimal duals ``u, v`` and the common potential
    ``v_free`` of its free columns. Popping a node with solution ``s`` creates one child per
    free row ``r``: forbid ``(r, s[r])`` and fix the rows processed before it. Each child is
    solved by a single warm-started shortest augmenting path from the parent's duals and
    partial assignment (:func:`sap_augment`), ``O(P N)`` instead of a full LSAP. Rows are
    processed in decreasing order of a lower bound on their child's cost increase (the
    smallest reduced cost of an alternative column), so that the children expected to be
    worst get the fewest fixings and the most promising ones the smallest residual problems
    (partition ordering).
    """
    P, N = C.shape
    cap = 1024
    sol = np.empty((cap, P), dtype=np.int64)
    us = np.empty((cap, P))
    vs = np.empty((cap, N))
    vfree = np.empty(cap)
    key = np.empty(cap)
    fixed = np.zeros((cap, P), dtype=np.bool_)
    forb_head = np.empty(cap, dtype=np.int64)
    fcap = 1024
    forb_row = np.empty(fcap, dtype=np.int64)
    forb_col = np.empty(fcap, dtype=np.int64)
    forb_next = np.empty(fcap, dtype=np.int64)
    n_forb = 0
    heap = np.empty(cap, dtype=np.int64)
    n_heap = 0

    # root node: a cold LSAP
    ok, col4row, u, v = lsap_kernel(C)
    out = np.empty((k, P), dtype=np.int64)
    if not ok:
        return out[:0]
    sol[0] = col4row
    us[0] = u
    vs[0] = v
    vfree[0] = 0.0
    key[0] = _row_cost(C, col4row)
    forb_head[0] = -1
    n_nodes = 1
    n_heap = _heap_push(heap, n_heap, key, 0)

    W = np.empty((P, N))
    row4col = np.empty(N, dtype=np.int64)
    active = np.empty(N, dtype=np.bool_)
    cu = np.empty(P)
    cv = np.empty(N)
    cc4r = np.empty(P, dtype=np.int64)
    d = np.empty(N)
    path = np.empty(N, dtype=np.int64)
    sr = np.empty(P, dtype=np.bool_)
    sc = np.empty(N, dtype=np.bool_)
    rem = np.empty(N, dtype=np.int64)
    order = np.empty(P, dtype=np.int64)
    lb = np.empty(P)
    fix_now = np.empty(P, dtype=np.bool_)

    n_out = 0
    while n_heap > 0 and n_out < k:
        node, n_heap = _heap_pop(heap, n_heap, key)
        s = sol[node].copy()
        out[n_out] = s
        n_out += 1
        if n_out == k:
            break
        pu = us[node].copy()
        pv = vs[node].copy()
        pvf = vfree[node]
        # working matrix of this node: C with its forbidden pairs removed
        for i in range(P):
            for j in range(N):
                W[i, j] = C[i, j]
        f = forb_head[node]
        while f >= 0:
            W[forb_row[f], forb_col[f]] = np.inf
            f = forb_next[f]
        # partition ordering: lower bound of each free row's child increase
        n_free = 0
        for i in range(P):
            fix_now[i] = fixed[node, i]
            if not fixed[node, i]:
                best = np.inf
                for j in range(N):
                    if j != s[i] and W[i, j] < np.inf:
                        r = W[i, j] - pu[i] - pv[j]
                        if r < best:
                            best = r
                lb[i] = best
                order[n_free] = i
                n_free += 1
        # stable insertion sort by decreasing bound (ties: lower row index first)
        for a in range(1, n_free):
            x = order[a]
            b = a - 1
            while b >= 0 and lb[order[b]] < lb[x]:
                order[b + 1] = order[b]
                b -= 1
            order[b + 1] = x
        for t in range(n_free):
            r = order[t]
            c = s[r]
            if lb[r] < np.inf:
                # child t: forbid (r, c), rows order[:t] fixed; warm start from the parent
                for j in range(N):
                    row4col[j] = -1
                    active[j] = True
                for i in range(P):
                    cc4r[i] = s[i]
                    row4col[s[i]] = i
                    if fix_now[i]:
                        active[s[i]] = False
                cc4r[r] = -1
                row4col[c] = -1
                for i in range(P):
                    cu[i] = pu[i]
                for j in range(N):
                    cv[j] = pv[j]
                W[r, c] = np.inf
                inc, nvf = sap_augment(W, r, c, cu, cv, cc4r, row4col, active, pvf, d, path,
                                       sr, sc, rem)
                W[r, c] = C[r, c]
                if inc < np.inf:
                    if n_nodes == sol.shape[0]:
                        cap2 = 2 * sol.shape[0]
                        sol = _grow2(sol, cap2)
                        us = _grow2(us, cap2)
                        vs = _grow2(vs, cap2)
                        fixed = _grow2(fixed, cap2)
                        vfree = _grow1(vfree, cap2)
                        key = _grow1(key, cap2)
                        forb_head = _grow1(forb_head, cap2)
                        heap = _grow1(heap, cap2)
                    if n_forb == forb_row.shape[0]:
                        fcap = 2 * forb_row.shape[0]
                        forb_row = _grow1(forb_row, fcap)
                        forb_col = _grow1(forb_col, fcap)
                        forb_next = _grow1(forb_next, fcap)
                    forb_row[n_forb] = r
                    forb_col[n_forb] = c
                    forb_next[n_forb] = forb_head[node]
                    nd = n_nodes
                    forb_head[nd] = n_forb
                    n_forb += 1
                    sol[nd] = cc4r
                    us[nd] = cu
                    vs[nd] = cv
                    vfree[nd] = nvf
                    for i in range(P):
                        fixed[nd, i] = fix_now[i]
                    key[nd] = _row_cost(C, cc4r)
                    n_nodes += 1
                    n_heap = _heap_push(heap, n_heap, key, nd)
            # later children keep row r on its parent column
            fix_now[r] = True
    return out[:n_out]


# ----------------------------------------------------------------------------- subset DP
@jit()
def _dp_forward_step(F, G, W, s, t, k):  # pragma: no cover - compiled
    """``G(S) = s[t] F(S) + sum_{e in S} W[t, e] F(S \\ {e})`` (spec eq. 5.1)."""
    n = F.shape[0]
    st = s[t]
    for S in range(n):
        G[S] = st * F[S]
    for e in range(k):
        w = W[t, e]
        if w == 0.0:
            continue
        bit = 1 << e
        for hi in range(0, n, 2 * bit):
            base = hi + bit
            for lo in range(bit):
                G[base + lo] += w * F[hi + lo]


@jit()
def _dp_backward_step(B, G, W, s, t, k):  # pragma: no cover - compiled
    """``G(S) = s[t] B(S) + sum_{e not in S} W[t, e] B(S | {e})`` (adjoint of the forward step)."""
    n = B.shape[0]
    st = s[t]
    for S in range(n):
        G[S] = st * B[S]
    for e in range(k):
        w = W[t, e]
        if w == 0.0:
            continue
        bit = 1 << e
        for hi in range(0, n, 2 * bit):
            base = hi + bit
            for lo in range(bit):
                G[hi + lo] += w * B[base + lo]


@jit()
def _dp_terminal(tin, tout, k):  # pragma: no cover - compiled
    """``T(S) = prod_{e in S} tin[e] * prod_{e not in S} tout[e]``."""
    n = 1 << k
    T = np.ones(n)
    for e in range(k):
        bit = 1 << e
        for S in range(n):
            if S & bit:
                T[S] *= tin[e]
            else:
                T[S] *= tout[e]
    return T


@jit()
def dp_total_kernel(W, s, tin, tout):  # pragma: no cover - compiled
    """Total weight ``sum_S F_K(S) T(S)`` of the generic subset DP.

    Parameters
    ----------
    W : ndarray, float64, shape (K, k)
        ``W[t, e]``: weight of adding element ``e`` to the state at step ``t``.
    s : ndarray, float64, shape (K,)
        Weight of leaving the state unchanged at step ``t``.
    tin, tout : ndarray, float64, shape (k,)
        Terminal weight of an element inside / outside the final state.
    """
    K, k = W.shape
    n = 1 << k
    F = np.zeros(n)
    G = np.empty(n)
    F[0] = 1.0
    for t in range(K):
        _dp_forward_step(F, G, W, s, t, k)
        F, G = G, F
    T = _dp_terminal(tin, tout, k)
    tot = 0.0
    for S in range(n):
        tot += F[S] * T[S]
    return tot


@jit()
def dp_marginal_kernel(W, s, tin, tout):  # pragma: no cover - compiled
    """Forward/backward subset DP: total weight and the weight through every transition.

    Returns
    -------
    total : float
    pair : ndarray, shape (K, k)
        ``sum_{S not containing e} F_t(S) W[t, e] B_{t+1}(S | {e})``.
    stay : ndarray, shape (K,)
        ``sum_S F_t(S) s[t] B_{t+1}(S)``.
    term_out : ndarray, shape (k,)
        ``sum_{S not containing e} F_K(S) T(S)``.

    Notes
    -----
    Backward vectors are stored only at block boundaries (``L = ceil(sqrt(K))`` steps apart)
    and recomputed inside each block, so memory is ``O(sqrt(K) 2^k)`` instead of
    ``O(K 2^k)`` for about one extra backward pass.
    """
    K, k = W.shape
    n = 1 << k
    L = 1
    while L * L < K:
        L += 1
    n_blocks = (K + L - 1) // L if K > 0 else 0
    T = _dp_terminal(tin, tout, k)
    # backward vectors at block starts t = b*L, plus the terminal one
    Bst = np.empty((n_blocks + 1, n))
    Bst[n_blocks] = T
    cur = T.copy()
    G = np.empty(n)
    for t in range(K - 1, -1, -1):
        _dp_backward_step(cur, G, W, s, t, k)
        cur, G = G, cur
        if t % L == 0:
            Bst[t // L] = cur
    total = 0.0
    if K > 0:
        total = Bst[0][0]
    else:
        total = T[0]
    pair = np.zeros((K, k))
    stay = np.zeros(K)
    F = np.zeros(n)
    F[0] = 1.0
    Fn = np.empty(n)
    Bblk = np.empty((L + 1, n))
    for b in range(n_blocks):
        t0 = b * L
        t1 = min(K, t0 + L)
        # recompute B_{t} for t in (t0, t1] from the stored B_{t1}
        if t1 == K:
            Bblk[t1 - t0] = T
        else:
            Bblk[t1 - t0] = Bst[t1 // L]
        for t in range(t1 - 1, t0, -1):
            _dp_backward_step(Bblk[t + 1 - t0], Bblk[t - t0], W, s, t, k)
        for t in range(t0, t1):
            Bn = Bblk[t + 1 - t0]
            acc = 0.0
            for S in range(n):
                acc += F[S] * Bn[S]
            stay[t] = s[t] * acc
            for e in range(k):
                w = W[t, e]
                if w == 0.0:
                    continue
                bit = 1 << e
                acc = 0.0
                for hi in range(0, n, 2 * bit):
                    base = hi + bit
                    for lo in range(bit):
                        acc += F[hi + lo] * Bn[base + lo]
                pair[t, e] = w * acc
            _dp_forward_step(F, Fn, W, s, t, k)
            F, Fn = Fn, F
    term_out = np.zeros(k)
    for e in range(k):
        bit = 1 << e
        acc = 0.0
        for S in range(n):
            if not S & bit:
                acc += F[S] * T[S]
        term_out[e] = acc
    return total, pair, stay, term_out


# ----------------------------------------------------------------------------- frontier DP
# A frontier (path-decomposition) DP walks through the measurements of one connected component
# in a fixed order. Its state is the subset of *active* rows already matched; a row is active
# from its first to its last finite measurement in the order and occupies one bit ("slot").
# Active slots are always bits 0..n-1: a row enters at bit n, and a retiring row's bit is
# filled by the row in the highest slot, so each vector has exactly 2^n entries. The walk is a
# sequence of primitive linear operations, ``ops[k] = (kind, arg, slot)``:
#
#   _ENTER   (arg = row, slot = n):  new(S) = old(S) if bit n of S is clear, else 0
#   _TRANS   (arg = step t):         new(S) = s[t] old(S) + sum_{e in S} W[t, e] old(S \ {e})
#   _RETIRE  (arg = row, slot = e):  new(S') = w_un[row] old(S0) + old(S0 | {e}), S0 = S' with
#                                    bit e cleared and the old top bit n-1 set to bit e of S'
#
# starting from the one-entry vector [1] and ending at the one-entry vector [Z].
_ENTER = 0
_TRANS = 1
_RETIRE = 2


@jit()
def _retire_source(Sp, e, top):  # pragma: no cover - compiled
    """State ``S0`` (bit ``e`` clear) before retiring slot ``e`` that maps to state ``Sp``."""
    if e == top:
        return Sp
    hb = (Sp >> e) & 1
    return (Sp & ~(1 << e)) | (hb << top)


@jit()
def _frontier_forward(kind, arg, slot, n, F, G, W, s, w_un):  # pragma: no cover - compiled
    """Apply one operation to ``F[:2^n]``, writing ``G``; return the new number of slots."""
    size = 1 << n
    if kind == _ENTER:
        for S in range(size):
            G[S] = F[S]
        for S in range(size, 2 * size):
            G[S] = 0.0
        return n + 1
    if kind == _TRANS:
        _dp_forward_step(F[:size], G[:size], W, s, arg, n)
        return n
    # _RETIRE: the row leaves matched (factor 1) or unmatched (factor w_un)
    w = w_un[arg]
    bit = 1 << slot
    for Sp in range(size >> 1):
        S0 = _retire_source(Sp, slot, n - 1)
        G[Sp] = w * F[S0] + F[S0 | bit]
    return n - 1


@jit()
def _frontier_adjoint(kind, arg, slot, n, B, G, W, s, w_un):  # pragma: no cover - compiled
    """Transpose of :func:`_frontier_forward`: ``n`` slots *before* the operation,
    ``B`` the backward vector after it; writes the backward vector before it into ``G``."""
    size = 1 << n
    if kind == _ENTER:
        for S in range(size):
            G[S] = B[S]
    elif kind == _TRANS:
        _dp_backward_step(B[:size], G[:size], W, s, arg, n)
    else:
        w = w_un[arg]
        bit = 1 << slot
        for Sp in range(size >> 1):
            S0 = _retire_source(Sp, slot, n - 1)
            G[S0] = w * B[Sp]
            G[S0 | bit] = B[Sp]


@jit()
def frontier_total_kernel(ops, W, s, w_un):  # pragma: no cover - compiled
    """Total weight of a frontier DP (the scaled ``Z`` of one component).

    Parameters
    ----------
    ops : ndarray, int64, shape (n_ops, 3)
        ``(kind, arg, slot)`` per operation (see the comment above :data:`_ENTER`).
    W : ndarray, float64, shape (K, F)
        ``W[t, e]``: weight of the row in slot ``e`` taking the measurement of step ``t``
        (0 when the pair is forbidden or the slot is free).
    s : ndarray, float64, shape (K,)
        Weight of leaving the measurement of step ``t`` unused.
    w_un : ndarray, float64, shape (P,)
        Weight of row ``i`` retiring unmatched.
    """
    n_slots = W.shape[1]
    F = np.zeros(1 << n_slots)
    G = np.zeros(1 << n_slots)
    F[0] = 1.0
    n = 0
    for k in range(ops.shape[0]):
        n = _frontier_forward(ops[k, 0], ops[k, 1], ops[k, 2], n, F, G, W, s, w_un)
        F, G = G, F
    return F[0]


@jit()
def frontier_marginal_kernel(ops, W, s, w_un):  # pragma: no cover - compiled
    """Forward/backward frontier DP: total weight and the weight through every choice.

    Returns
    -------
    total : float
    pair : ndarray, shape (K, F)
        ``sum_{S not containing e} F_k(S) W[t, e] B_{k+1}(S | {e})`` at the transition ``k``
        of step ``t``: the weight of the row in slot ``e`` taking that step's measurement.
    unmatched : ndarray, shape (P,)
        Weight of row ``i`` retiring unmatched.

    Notes
    -----
    Forward vectors are checkpointed every ``L = ceil(sqrt(n_ops))`` operations and recomputed
    block by block during the backward sweep, so memory is ``O(sqrt(n_ops) 2^F)``.
    """
    n_ops = ops.shape[0]
    K, n_slots = W.shape
    # slots before each operation
    nb = np.zeros(n_ops + 1, dtype=np.int64)
    for k in range(n_ops):
        if ops[k, 0] == _ENTER:
            nb[k + 1] = nb[k] + 1
        elif ops[k, 0] == _RETIRE:
            nb[k + 1] = nb[k] - 1
        else:
            nb[k + 1] = nb[k]
    L = 1
    while L * L < n_ops:
        L += 1
    n_blocks = (n_ops + L - 1) // L
    # checkpoints f_{bL}, stored back to back
    ck_off = np.zeros(n_blocks + 1, dtype=np.int64)
    for b in range(n_blocks):
        ck_off[b + 1] = ck_off[b] + (1 << nb[b * L])
    ck = np.empty(ck_off[n_blocks])
    full = 1 << n_slots
    F = np.zeros(full)
    G = np.zeros(full)
    F[0] = 1.0
    for k in range(n_ops):
        if k % L == 0:
            b = k // L
            ck[ck_off[b]:ck_off[b + 1]] = F[:ck_off[b + 1] - ck_off[b]]
        _frontier_forward(ops[k, 0], ops[k, 1], ops[k, 2], nb[k], F, G, W, s, w_un)
        F, G = G, F
    total = F[0]
    pair = np.zeros((K, n_slots))
    unmatched = np.zeros(w_un.shape[0])
    # the largest block of forward vectors
    blk_max = 0
    for b in range(n_blocks):
        tot = 0
        for k in range(b * L, min(n_ops, (b + 1) * L)):
            tot += 1 << nb[k]
        blk_max = max(blk_max, tot)
    blk = np.empty(blk_max)
    blk_off = np.zeros(L + 1, dtype=np.int64)
    B = np.zeros(full)  # backward vector after the current operation
    Bn = np.zeros(full)
    B[0] = 1.0
    for b in range(n_blocks - 1, -1, -1):
        k0 = b * L
        k1 = min(n_ops, k0 + L)
        # recompute f_k, k0 <= k < k1, from the checkpoint
        for k in range(k0, k1):
            blk_off[k - k0 + 1] = blk_off[k - k0] + (1 << nb[k])
        blk[0:blk_off[1]] = ck[ck_off[b]:ck_off[b + 1]]
        for k in range(k0, k1 - 1):
            i0, i1 = blk_off[k - k0], blk_off[k - k0 + 1]
            _frontier_forward(ops[k, 0], ops[k, 1], ops[k, 2], nb[k], blk[i0:i1], G, W, s,
                              w_un)
            blk[i1:blk_off[k - k0 + 2]] = G[:blk_off[k - k0 + 2] - i1]
        for k in range(k1 - 1, k0 - 1, -1):
            Fk = blk[blk_off[k - k0]:blk_off[k - k0 + 1]]
            kind, arg, slot, n = ops[k, 0], ops[k, 1], ops[k, 2], nb[k]
            if kind == _TRANS:
                # weight through "slot e takes this measurement" (spec eq. 5.2)
                for e in range(n):
                    w = W[arg, e]
                    if w == 0.0:
                        continue
                    bit = 1 << e
                    acc = 0.0
                    for hi in range(0, 1 << n, 2 * bit):
                        base = hi + bit
                        for lo in range(bit):
                            acc += Fk[hi + lo] * B[base + lo]
                    pair[arg, e] = w * acc
            elif kind == _RETIRE:
                # weight through "row arg leaves unmatched"
                acc = 0.0
                for Sp in range((1 << n) >> 1):
                    acc += Fk[_retire_source(Sp, slot, n - 1)] * B[Sp]
                unmatched[arg] = w_un[arg] * acc
            _frontier_adjoint(kind, arg, slot, n, B, Bn, W, s, w_un)
            B, Bn = Bn, B
    return total, pair, unmatched

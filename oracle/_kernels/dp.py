"""Compiled kernels of the exact normaliser and marginals: the subset DP and the frontier DP.

Spec §5.2, eqs. (5.1)–(5.2). The public wrappers live in :mod:`oracle.dp`, which prepares the
scaled weights of one connected component; these kernels assume clean, C-contiguous float64 /
int64 arrays and never raise.
"""

from __future__ import annotations

import numpy as np

from rankedassign.numba_options import jit

__all__ = [
    "ENTER",
    "RETIRE",
    "TRANS",
    "dp_marginal_kernel",
    "dp_total_kernel",
    "frontier_marginal_kernel",
    "frontier_total_kernel",
]


# ----------------------------------------------------------------------------- subset DP
@jit()
def _dp_forward_step(F, G, W, s, t, k):
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
def _dp_backward_step(B, G, W, s, t, k):
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
def _dp_terminal(tin, tout, k):
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
def dp_total_kernel(W, s, tin, tout):
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
def dp_marginal_kernel(W, s, tin, tout):
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
#   ENTER    (arg = row, slot = n):  new(S) = old(S) if bit n of S is clear, else 0
#   TRANS    (arg = step t):         new(S) = s[t] old(S) + sum_{e in S} W[t, e] old(S \ {e})
#   RETIRE   (arg = row, slot = e):  new(S') = w_un[row] old(S0) + old(S0 | {e}), S0 = S' with
#                                    bit e cleared and the old top bit n-1 set to bit e of S'
#
# starting from the one-entry vector [1] and ending at the one-entry vector [Z].
ENTER = 0
TRANS = 1
RETIRE = 2


@jit()
def _retire_source(Sp, e, top):
    """State ``S0`` (bit ``e`` clear) before retiring slot ``e`` that maps to state ``Sp``."""
    if e == top:
        return Sp
    hb = (Sp >> e) & 1
    return (Sp & ~(1 << e)) | (hb << top)


@jit()
def _frontier_forward(kind, arg, slot, n, F, G, W, s, w_un):
    """Apply one operation to ``F[:2^n]``, writing ``G``; return the new number of slots."""
    size = 1 << n
    if kind == ENTER:
        for S in range(size):
            G[S] = F[S]
        for S in range(size, 2 * size):
            G[S] = 0.0
        return n + 1
    if kind == TRANS:
        _dp_forward_step(F[:size], G[:size], W, s, arg, n)
        return n
    # RETIRE: the row leaves matched (factor 1) or unmatched (factor w_un)
    w = w_un[arg]
    bit = 1 << slot
    for Sp in range(size >> 1):
        S0 = _retire_source(Sp, slot, n - 1)
        G[Sp] = w * F[S0] + F[S0 | bit]
    return n - 1


@jit()
def _frontier_adjoint(kind, arg, slot, n, B, G, W, s, w_un):
    """Transpose of :func:`_frontier_forward`: ``n`` slots *before* the operation,
    ``B`` the backward vector after it; writes the backward vector before it into ``G``."""
    size = 1 << n
    if kind == ENTER:
        for S in range(size):
            G[S] = B[S]
    elif kind == TRANS:
        _dp_backward_step(B[:size], G[:size], W, s, arg, n)
    else:
        w = w_un[arg]
        bit = 1 << slot
        for Sp in range(size >> 1):
            S0 = _retire_source(Sp, slot, n - 1)
            G[S0] = w * B[Sp]
            G[S0 | bit] = B[Sp]


@jit()
def frontier_total_kernel(ops, W, s, w_un):
    """Total weight of a frontier DP (the scaled ``Z`` of one component).

    Parameters
    ----------
    ops : ndarray, int64, shape (n_ops, 3)
        ``(kind, arg, slot)`` per operation (see the comment above :data:`ENTER`).
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
def frontier_marginal_kernel(ops, W, s, w_un):
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
        if ops[k, 0] == ENTER:
            nb[k + 1] = nb[k] + 1
        elif ops[k, 0] == RETIRE:
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
            if kind == TRANS:
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
            elif kind == RETIRE:
                # weight through "row arg leaves unmatched"
                acc = 0.0
                for Sp in range((1 << n) >> 1):
                    acc += Fk[_retire_source(Sp, slot, n - 1)] * B[Sp]
                unmatched[arg] = w_un[arg] * acc
            _frontier_adjoint(kind, arg, slot, n, B, Bn, W, s, w_un)
            B, Bn = Bn, B
    return total, pair, unmatched

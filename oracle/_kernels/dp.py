"""Compiled kernels of the exact normaliser and marginals: the subset DP and the frontier DP.

Spec §5.2, eqs. (5.1)–(5.2). The public wrappers live in :mod:`oracle.single.dp`, which prepares the
scaled weights of one connected component; these kernels assume clean, C-contiguous float64 /
int64 arrays and never raise.

A DP over ``2^20`` states can take minutes, so each DP is a *slice* kernel that runs at most
``budget`` steps (operations) and keeps its place in ``pos`` and its vectors in arrays the
caller allocates; :mod:`oracle.single.dp` calls it until it reports completion, and between two
slices the interpreter runs pending signal handlers (Ctrl-C). Two vectors that the unsliced
loop swapped after every step alternate by the step's parity instead, so every budget
performs the same operations in the same order: the same bits.
"""

from __future__ import annotations

from collections import namedtuple

import numpy as np

from rankedassign.numba_options import jit

__all__ = [
    "ENTER",
    "FrontierDP",
    "FrontierMarginals",
    "FrontierWork",
    "SubsetDP",
    "SubsetMarginals",
    "SubsetWork",
    "RETIRE",
    "TRANS",
    "dp_marginal_slice",
    "dp_terminal",
    "dp_total_finish",
    "dp_total_slice",
    "frontier_layout",
    "frontier_marginal_slice",
    "frontier_total_slice",
]


# ----------------------------------------------------------------------------- subset DP
@jit()
def _dp_forward_step(F, G, W, s, t, k):
    """``G(S) = s[t] F(S) + sum_{e in S} W[t, e] F(S \\ {e})`` (spec eq. 5.1).

    Parameters
    ----------
    F : ndarray of float64, shape (2^k,)
        The vector before step ``t``, indexed by subsets (bit ``e``: element ``e``).
    G : ndarray of float64, shape (2^k,)
        Overwritten with the vector after it.
    W : ndarray of float64, shape (K, k)
        ``W[t, e]``: weight of adding element ``e`` at step ``t``.
    s : ndarray of float64, shape (K,)
        Weight of leaving the state unchanged at step ``t``.
    t : int
        The step.
    k : int
        Number of elements (bits).
    """
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
    """``G(S) = s[t] B(S) + sum_{e not in S} W[t, e] B(S | {e})`` (adjoint of the forward step).

    Parameters
    ----------
    B : ndarray of float64, shape (2^k,)
        The backward vector after step ``t``.
    G : ndarray of float64, shape (2^k,)
        Overwritten with the backward vector before it.
    W, s, t, k
        As in :func:`_dp_forward_step`.
    """
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
def dp_terminal(tin, tout, k):
    """``T(S) = prod_{e in S} tin[e] * prod_{e not in S} tout[e]``.

    Parameters
    ----------
    tin, tout : ndarray of float64, shape (k,)
        Terminal weight of an element inside / outside the final state.
    k : int
        Number of elements.

    Returns
    -------
    ndarray of float64, shape (2^k,)
        ``T``, indexed by subsets (bit ``e``: element ``e``).
    """
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
def dp_total_slice(W, s, F, G, pos, budget):
    """Up to ``budget`` steps of the generic subset DP ``F_{t+1} = step_t(F_t)``; True when
    all ``K`` are done (the total is then ``sum_S F_K(S) T(S)``, :func:`dp_total_finish`).

    Parameters
    ----------
    W : ndarray, float64, shape (K, k)
        ``W[t, e]``: weight of adding element ``e`` to the state at step ``t``.
    s : ndarray, float64, shape (K,)
        Weight of leaving the state unchanged at step ``t``.
    F, G : ndarray, float64, shape (2^k,)
        ``F_0 = [1, 0, ...]`` and work space: step ``t`` reads ``F`` and writes ``G`` when
        ``t`` is even, the other way round when odd.
    pos : ndarray, int64, shape (1,)
        Steps done (start at zero).
    budget : int
        Steps in this call (``>= 1``; one step is ``O(k 2^k)``).

    Returns
    -------
    bool
        True when all ``K`` steps are done.
    """
    K, k = W.shape
    t = pos[0]
    stop = min(K, t + budget)
    while t < stop:
        if t % 2 == 0:
            _dp_forward_step(F, G, W, s, t, k)
        else:
            _dp_forward_step(G, F, W, s, t, k)
        t += 1
    pos[0] = t
    return t >= K


@jit()
def dp_total_finish(F, G, K, tin, tout):
    """``sum_S F_K(S) T(S)`` after :func:`dp_total_slice` (``F_K`` is ``F`` for even ``K``).

    Parameters
    ----------
    F, G : ndarray of float64, shape (2^k,)
        The two vectors of :func:`dp_total_slice` after its last step.
    K : int
        Number of steps (rows of its ``W``).
    tin, tout : ndarray of float64, shape (k,)
        Terminal weight of an element inside / outside the final state.

    Returns
    -------
    float
        The total weight.
    """
    k = tin.shape[0]
    cur = F if K % 2 == 0 else G
    T = dp_terminal(tin, tout, k)
    tot = 0.0
    for S in range(1 << k):
        tot += cur[S] * T[S]
    return tot


#: The data of a subset DP's marginal pass: ``W`` (K, k) and ``s`` (K,) as in
#: :func:`dp_total_slice`, ``T`` (2^k,) the terminal weights (:func:`dp_terminal`).
SubsetDP = namedtuple("SubsetDP", ["W", "s", "T"])

#: The vectors of a subset DP's marginal pass, each of ``2^k`` float64 entries: ``Bst``
#: (n_blocks + 1, 2^k) the backward vectors at block starts ``t = b L`` (``L = ceil(sqrt(K))``),
#: row ``n_blocks`` ``T``; ``X``, ``Y`` ``T`` and work space of the first backward sweep (they
#: alternate, ``X`` first); ``F``, ``Fn`` ``F_0 = [1, 0, ...]`` and work space (forward step
#: ``t`` reads ``F`` when ``t`` is even); ``Bblk`` (L + 1, 2^k) the backward vectors of one
#: block, recomputed from its stored end.
SubsetWork = namedtuple("SubsetWork", ["Bst", "X", "Y", "F", "Fn", "Bblk"])

#: What a subset DP's marginal pass adds up, zero at the start: ``pair`` (K, k)
#: ``sum_{S not containing e} F_t(S) W[t, e] B_{t+1}(S | {e})``, ``stay`` (K,)
#: ``sum_S F_t(S) s[t] B_{t+1}(S)``, ``term_out`` (k,) ``sum_{S not containing e} F_K(S) T(S)``.
SubsetMarginals = namedtuple("SubsetMarginals", ["pair", "stay", "term_out"])


@jit()
def _subset_backward_sweep(dp, work, pos, left):
    """Pass 0: backward steps from ``t = pos[2]`` down, storing ``B_t`` at block starts; on
    completion ``pos = [1, 0, -1]``. Returns the budget left.

    Parameters
    ----------
    dp : SubsetDP
        The DP's data.
    work : SubsetWork
        Its vectors (``Bst`` filled at the block starts).
    pos : ndarray of int64, shape (3,)
        As in :func:`dp_marginal_slice`.
    left : int
        Steps left in this call.

    Returns
    -------
    int
        Steps left; the pass is complete when ``pos[0]`` has moved on.
    """
    W, s, _ = dp
    Bst, X, Y = work.Bst, work.X, work.Y
    K, k = W.shape
    L = work.Bblk.shape[0] - 1
    t = pos[2]
    while t >= 0:
        if left <= 0:
            pos[2] = t
            return left
        if (K - 1 - t) % 2 == 0:
            _dp_backward_step(X, Y, W, s, t, k)
            if t % L == 0:
                Bst[t // L] = Y
        else:
            _dp_backward_step(Y, X, W, s, t, k)
            if t % L == 0:
                Bst[t // L] = X
        t -= 1
        left -= 1
    pos[0] = 1
    pos[1] = 0
    pos[2] = -1
    return left


@jit()
def _subset_block_backward(dp, work, pos, left):
    """Pass 1: recompute ``B_t`` for ``t`` in ``(t0, t1]`` of block ``pos[1]`` from its stored
    end (``pos[2] = -1``: not begun); on completion ``pos[0] = 2``, ``pos[2] = t0``. Returns
    the budget left.

    Parameters
    ----------
    dp, work, pos, left
        As in :func:`_subset_backward_sweep` (``work.Bblk`` filled).

    Returns
    -------
    int
        Steps left.
    """
    W, s, T = dp
    Bst, Bblk = work.Bst, work.Bblk
    K, k = W.shape
    L = Bblk.shape[0] - 1
    t0 = pos[1] * L
    t1 = min(K, t0 + L)
    if pos[2] < 0:
        if t1 == K:
            Bblk[t1 - t0] = T
        else:
            Bblk[t1 - t0] = Bst[t1 // L]
        pos[2] = t1 - 1
    t = pos[2]
    while t > t0:
        if left <= 0:
            pos[2] = t
            return left
        _dp_backward_step(Bblk[t + 1 - t0], Bblk[t - t0], W, s, t, k)
        t -= 1
        left -= 1
    pos[0] = 2
    pos[2] = t0
    return left


@jit()
def _subset_block_forward(dp, work, out, pos, left):
    """Pass 2: the forward steps of block ``pos[1]`` from ``t = pos[2]`` and the weights
    through them (spec eq. 5.2); on completion ``pos = [1, block + 1, -1]``. Returns the
    budget left.

    Parameters
    ----------
    dp, work, pos, left
        As in :func:`_subset_backward_sweep`.
    out : SubsetMarginals
        ``pair`` and ``stay`` written at the block's steps.

    Returns
    -------
    int
        Steps left.
    """
    W, s, _ = dp
    F, Fn, Bblk = work.F, work.Fn, work.Bblk
    pair, stay = out.pair, out.stay
    K, k = W.shape
    n = 1 << k
    L = Bblk.shape[0] - 1
    b = pos[1]
    t0 = b * L
    t1 = min(K, t0 + L)
    t = pos[2]
    while t < t1:
        if left <= 0:
            pos[2] = t
            return left
        Ft = F if t % 2 == 0 else Fn
        Bn = Bblk[t + 1 - t0]
        acc = 0.0
        for S in range(n):
            acc += Ft[S] * Bn[S]
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
                    acc += Ft[hi + lo] * Bn[base + lo]
            pair[t, e] = w * acc
        if t % 2 == 0:
            _dp_forward_step(F, Fn, W, s, t, k)
        else:
            _dp_forward_step(Fn, F, W, s, t, k)
        t += 1
        left -= 1
    pos[0] = 1
    pos[1] = b + 1
    pos[2] = -1
    return left


@jit()
def dp_marginal_slice(dp, work, out, pos, budget):
    """Up to ``budget`` steps of the forward/backward subset DP; True when it is done.

    Parameters
    ----------
    dp : SubsetDP
        ``W`` (K, k), ``s`` (K,), ``T`` (2^k,) float64: the step weights as in
        :func:`dp_total_slice` and the terminal weights (:func:`dp_terminal`).
    work : SubsetWork
        ``Bst`` (n_blocks + 1, 2^k) with row ``n_blocks`` ``T``; ``X`` ``T`` and ``Y`` any;
        ``F`` ``[1, 0, ...]`` and ``Fn`` any; ``Bblk`` (L + 1, 2^k) any (``L =
        ceil(sqrt(K))``, ``n_blocks = ceil(K / L)``).
    out : SubsetMarginals
        ``pair`` (K, k), ``stay`` (K,), ``term_out`` (k,), zero.
    pos : ndarray, int64, shape (3,)
        ``[pass, block, step]``: pass 0 is the backward sweep (step from ``K - 1`` down), 1
        the recomputation of a block's backward vectors (step -1: not begun), 2 the block's
        forward steps, 3 done; start at ``[0, 0, K - 1]``.
    budget : int
        Steps in this call (``>= 1``).

    Returns
    -------
    bool
        True when done: ``work.Bst[0, 0]`` (``T[0]`` when ``K = 0``) is then the total
        weight and ``out`` holds the sums documented in :data:`SubsetMarginals`.

    Notes
    -----
    Backward vectors are stored only at block boundaries and recomputed inside each block, so
    memory is ``O(sqrt(K) 2^k)`` instead of ``O(K 2^k)`` for about one extra backward pass.
    """
    left = budget
    if pos[0] == 0:
        left = _subset_backward_sweep(dp, work, pos, left)
        if pos[0] == 0:
            return False
    n_blocks = work.Bst.shape[0] - 1
    while pos[1] < n_blocks:
        if pos[0] == 1:
            left = _subset_block_backward(dp, work, pos, left)
            if pos[0] == 1:
                return False
        left = _subset_block_forward(dp, work, out, pos, left)
        if pos[0] == 2:
            return False
    W, _, T = dp
    K, k = W.shape
    FK = work.F if K % 2 == 0 else work.Fn
    for e in range(k):
        bit = 1 << e
        acc = 0.0
        for S in range(1 << k):
            if not S & bit:
                acc += FK[S] * T[S]
        out.term_out[e] = acc
    pos[0] = 3
    return True


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
    """State ``S0`` (bit ``e`` clear) before retiring slot ``e`` that maps to state ``Sp``.

    Parameters
    ----------
    Sp : int
        A state after the retirement (bits ``0..top-1``).
    e : int
        The retiring slot.
    top : int
        The highest slot before the retirement (``n - 1``), whose row moves into slot ``e``.

    Returns
    -------
    int
    """
    if e == top:
        return Sp
    hb = (Sp >> e) & 1
    return (Sp & ~(1 << e)) | (hb << top)


#: The data of a frontier DP: ``ops`` (n_ops, 3) int64, ``(kind, arg, slot)`` per operation
#: (see the comment above :data:`ENTER`); ``W`` (K, F) float64, ``W[t, e]`` the weight of the
#: row in slot ``e`` taking the measurement of step ``t`` (0 when the pair is forbidden or the
#: slot is free); ``s`` (K,) float64, the weight of leaving the measurement of step ``t``
#: unused; ``w_un`` (P,) float64, the weight of row ``i`` retiring unmatched.
FrontierDP = namedtuple("FrontierDP", ["ops", "W", "s", "w_un"])


@jit()
def _frontier_forward(dp, k, n, F, G):
    """Apply operation ``k`` to ``F[:2^n]``, writing ``G``; return the new number of slots.

    Parameters
    ----------
    dp : FrontierDP
        The DP's data.
    k : int
        The operation.
    n : int
        Slots in use before it.
    F : ndarray of float64
        The forward vector before it, ``2^n`` entries read.
    G : ndarray of float64
        Receives the vector after it (``2^(n+1)``, ``2^n`` or ``2^(n-1)`` entries written for
        ``ENTER``, ``TRANS``, ``RETIRE``).

    Returns
    -------
    int
        Slots in use after the operation.
    """
    kind, arg, slot = dp.ops[k, 0], dp.ops[k, 1], dp.ops[k, 2]
    size = 1 << n
    if kind == ENTER:
        for S in range(size):
            G[S] = F[S]
        for S in range(size, 2 * size):
            G[S] = 0.0
        return n + 1
    if kind == TRANS:
        _dp_forward_step(F[:size], G[:size], dp.W, dp.s, arg, n)
        return n
    # RETIRE: the row leaves matched (factor 1) or unmatched (factor w_un)
    w = dp.w_un[arg]
    bit = 1 << slot
    for Sp in range(size >> 1):
        S0 = _retire_source(Sp, slot, n - 1)
        G[Sp] = w * F[S0] + F[S0 | bit]
    return n - 1


@jit()
def _frontier_adjoint(dp, k, n, B, G):
    """Transpose of :func:`_frontier_forward`: ``n`` slots *before* operation ``k``, ``B``
    the backward vector after it; writes the backward vector before it into ``G``.

    Parameters
    ----------
    dp : FrontierDP
        The DP's data.
    k : int
        The operation.
    n : int
        Slots in use before it.
    B : ndarray of float64
        The backward vector after it.
    G : ndarray of float64
        Receives the ``2^n`` entries of the backward vector before it.
    """
    kind, arg, slot = dp.ops[k, 0], dp.ops[k, 1], dp.ops[k, 2]
    size = 1 << n
    if kind == ENTER:
        for S in range(size):
            G[S] = B[S]
    elif kind == TRANS:
        _dp_backward_step(B[:size], G[:size], dp.W, dp.s, arg, n)
    else:
        w = dp.w_un[arg]
        bit = 1 << slot
        for Sp in range(size >> 1):
            S0 = _retire_source(Sp, slot, n - 1)
            G[S0] = w * B[Sp]
            G[S0 | bit] = B[Sp]


@jit()
def frontier_total_slice(dp, F, G, pos, budget):
    """Up to ``budget`` operations of a frontier DP; True when all are done (the total, the
    scaled ``Z`` of one component, is then ``F[0]`` for an even number of operations, else
    ``G[0]``).

    Parameters
    ----------
    dp : FrontierDP
        ``ops``, ``W``, ``s``, ``w_un`` (:data:`FrontierDP`).
    F, G : ndarray, float64, shape (2^F,)
        ``[1, 0, ...]`` and zero: operation ``k`` reads ``F`` and writes ``G`` when ``k`` is
        even, the other way round when odd.
    pos : ndarray, int64, shape (2,)
        Operations done and the slots in use; start at zero.
    budget : int
        Operations in this call (``>= 1``; one is at most ``O(F 2^F)``).

    Returns
    -------
    bool
        True when all operations are done.
    """
    n_ops = dp.ops.shape[0]
    k, n = pos[0], pos[1]
    stop = min(n_ops, k + budget)
    while k < stop:
        if k % 2 == 0:
            n = _frontier_forward(dp, k, n, F, G)
        else:
            n = _frontier_forward(dp, k, n, G, F)
        k += 1
    pos[0], pos[1] = k, n
    return k >= n_ops


@jit()
def frontier_layout(ops):
    """Slots before each operation and the checkpoint layout of :func:`frontier_marginal_slice`.

    Parameters
    ----------
    ops : ndarray of int64, shape (n_ops, 3)
        The operations ``(kind, arg, slot)`` (:data:`FrontierDP`).

    Returns
    -------
    nb : (n_ops + 1,) int64
        Slots in use before operation ``k``.
    ck_off : (n_blocks + 1,) int64
        Offsets of the checkpoints ``f_{bL}`` stored back to back (``L = ceil(sqrt(n_ops))``).
    blk_max : int
        Entries of the largest block of forward vectors.
    """
    n_ops = ops.shape[0]
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
    ck_off = np.zeros(n_blocks + 1, dtype=np.int64)
    for b in range(n_blocks):
        ck_off[b + 1] = ck_off[b] + (1 << nb[b * L])
    blk_max = 0
    for b in range(n_blocks):
        tot = 0
        for k in range(b * L, min(n_ops, (b + 1) * L)):
            tot += 1 << nb[k]
        blk_max = max(blk_max, tot)
    return nb, ck_off, blk_max


#: The vectors of a frontier DP's marginal pass: ``nb`` (n_ops + 1,) int64 and ``ck_off``
#: (n_blocks + 1,) int64 from :func:`frontier_layout`, ``ck`` (``ck_off[-1]``,) float64 the
#: checkpoints ``f_{bL}`` back to back (``L = ceil(sqrt(n_ops))``); ``F``, ``G`` (2^F,) float64
#: the forward sweep (alternating as in :func:`frontier_total_slice`; ``G`` is also the scratch
#: vector of a block); ``blk`` (blk_max,) float64 one block of forward vectors back to back and
#: ``blk_off`` (L + 1,) int64 their offsets; ``B``, ``Bn`` (2^F,) float64 the backward vector
#: after the current operation (they alternate with every adjoint operation).
FrontierWork = namedtuple("FrontierWork", ["nb", "ck_off", "ck", "F", "G", "blk", "blk_off", "B",
                                           "Bn"])

#: What a frontier DP's marginal pass adds up: ``pair`` (K, F), at the transition of step
#: ``t``, ``sum_{S not containing e} F_k(S) W[t, e] B_{k+1}(S | {e})`` (the weight of the row in
#: slot ``e`` taking that step's measurement); ``unmatched`` (P,) the weight of row ``i``
#: retiring unmatched; ``acc`` (1,) the total weight.
FrontierMarginals = namedtuple("FrontierMarginals", ["pair", "unmatched", "acc"])


@jit()
def _frontier_forward_sweep(dp, work, out, pos, left):
    """Pass 0: forward operations from ``pos[2]``, checkpointing every ``L``-th vector; on
    completion ``out.acc[0]`` is the total and ``pos[0] = 1``, ``pos[2] = -1``. Returns the
    budget left.

    Parameters
    ----------
    dp : FrontierDP
        The DP's data.
    work : FrontierWork
        Its vectors (``ck`` filled with the checkpoints).
    out : FrontierMarginals
        ``acc`` written on completion.
    pos : ndarray of int64, shape (4,)
        As in :func:`frontier_marginal_slice`.
    left : int
        Operations left in this call.

    Returns
    -------
    int
        Operations left; the pass is complete when ``pos[0]`` has moved on.
    """
    nb, ck_off, ck, F, G = work.nb, work.ck_off, work.ck, work.F, work.G
    n_ops = dp.ops.shape[0]
    L = work.blk_off.shape[0] - 1
    k = pos[2]
    while k < n_ops:
        if left <= 0:
            pos[2] = k
            return left
        cur = F if k % 2 == 0 else G
        if k % L == 0:
            b = k // L
            ck[ck_off[b]:ck_off[b + 1]] = cur[:ck_off[b + 1] - ck_off[b]]
        if k % 2 == 0:
            _frontier_forward(dp, k, nb[k], F, G)
        else:
            _frontier_forward(dp, k, nb[k], G, F)
        k += 1
        left -= 1
    out.acc[0] = F[0] if n_ops % 2 == 0 else G[0]
    pos[0] = 1
    pos[2] = -1
    return left


@jit()
def _frontier_block_forward(dp, work, pos, left):
    """Pass 1: recompute ``f_k``, ``k0 <= k < k1``, of block ``pos[1]`` from its checkpoint
    (``pos[2] = -1``: not begun); on completion ``pos[0] = 2``, ``pos[2] = k1 - 1``. Returns
    the budget left.

    Parameters
    ----------
    dp, work, pos, left
        As in :func:`_frontier_forward_sweep` (``work.blk`` and ``work.blk_off`` filled).

    Returns
    -------
    int
        Operations left.
    """
    nb, ck_off, ck, G = work.nb, work.ck_off, work.ck, work.G
    blk, blk_off = work.blk, work.blk_off
    n_ops = dp.ops.shape[0]
    L = blk_off.shape[0] - 1
    b = pos[1]
    k0 = b * L
    k1 = min(n_ops, k0 + L)
    if pos[2] < 0:
        blk_off[0] = 0
        for k in range(k0, k1):
            blk_off[k - k0 + 1] = blk_off[k - k0] + (1 << nb[k])
        blk[0:blk_off[1]] = ck[ck_off[b]:ck_off[b + 1]]
        pos[2] = k0
    k = pos[2]
    while k < k1 - 1:
        if left <= 0:
            pos[2] = k
            return left
        i0, i1 = blk_off[k - k0], blk_off[k - k0 + 1]
        _frontier_forward(dp, k, nb[k], blk[i0:i1], G)
        blk[i1:blk_off[k - k0 + 2]] = G[:blk_off[k - k0 + 2] - i1]
        k += 1
        left -= 1
    pos[0] = 2
    pos[2] = k1 - 1
    return left


@jit()
def _frontier_block_backward(dp, work, out, pos, left):
    """Pass 2: the adjoint operations of block ``pos[1]`` from ``pos[2]`` down and the
    weights through them (spec eq. 5.2); on completion ``pos = [1, block - 1, -1, ...]``.
    Returns the budget left.

    Parameters
    ----------
    dp, work, out, pos, left
        As in :func:`_frontier_forward_sweep` (``out.pair`` and ``out.unmatched`` written at
        the block's ``TRANS`` and ``RETIRE`` operations; ``work.B``, ``work.Bn`` alternate).

    Returns
    -------
    int
        Operations left.
    """
    ops, W, _, w_un = dp
    nb, blk, blk_off, B, Bn = work.nb, work.blk, work.blk_off, work.B, work.Bn
    pair, unmatched = out.pair, out.unmatched
    L = blk_off.shape[0] - 1
    b = pos[1]
    k0 = b * L
    k = pos[2]
    while k >= k0:
        if left <= 0:
            pos[2] = k
            return left
        odd = pos[3] % 2 == 1
        Bk = Bn if odd else B  # the backward vector after operation k
        Fk = blk[blk_off[k - k0]:blk_off[k - k0 + 1]]
        kind, arg, slot, n = ops[k, 0], ops[k, 1], ops[k, 2], nb[k]
        if kind == TRANS:
            # weight through "slot e takes this measurement" (spec eq. 5.2)
            for e in range(n):
                w = W[arg, e]
                if w == 0.0:
                    continue
                bit = 1 << e
                a = 0.0
                for hi in range(0, 1 << n, 2 * bit):
                    base = hi + bit
                    for lo in range(bit):
                        a += Fk[hi + lo] * Bk[base + lo]
                pair[arg, e] = w * a
        elif kind == RETIRE:
            # weight through "row arg leaves unmatched"
            a = 0.0
            for Sp in range((1 << n) >> 1):
                a += Fk[_retire_source(Sp, slot, n - 1)] * Bk[Sp]
            unmatched[arg] = w_un[arg] * a
        if odd:
            _frontier_adjoint(dp, k, n, Bn, B)
        else:
            _frontier_adjoint(dp, k, n, B, Bn)
        pos[3] += 1
        k -= 1
        left -= 1
    pos[0] = 1
    pos[1] = b - 1
    pos[2] = -1
    return left


@jit()
def frontier_marginal_slice(dp, work, out, pos, budget):
    """Up to ``budget`` operations of the forward/backward frontier DP; True when it is done.

    Parameters
    ----------
    dp : FrontierDP
        ``ops``, ``W``, ``s``, ``w_un`` as in :func:`frontier_total_slice`.
    work : FrontierWork
        ``nb``, ``ck_off`` from :func:`frontier_layout`; ``ck`` any; ``F``, ``B`` ``[1, 0,
        ...]`` and ``G``, ``Bn`` zero; ``blk`` (blk_max,) any; ``blk_off`` (L + 1,) any.
    out : FrontierMarginals
        ``pair`` (K, F), ``unmatched`` (P,) zero; ``acc`` (1,).
    pos : ndarray, int64, shape (4,)
        ``[pass, block, operation, adjoint operations done]``: pass 0 is the forward sweep, 1
        a block's recomputation (operation -1: not begun), 2 its backward operations, 3
        done; start at ``[0, n_blocks - 1, 0, 0]``.
    budget : int
        Operations in this call (``>= 1``).

    Returns
    -------
    bool
        True when done: ``out`` then holds the sums documented in :data:`FrontierMarginals`.

    Notes
    -----
    Forward vectors are checkpointed every ``L = ceil(sqrt(n_ops))`` operations and recomputed
    block by block during the backward sweep, so memory is ``O(sqrt(n_ops) 2^F)``.
    """
    left = budget
    if pos[0] == 0:
        left = _frontier_forward_sweep(dp, work, out, pos, left)
        if pos[0] == 0:
            return False
    while pos[1] >= 0:
        if pos[0] == 1:
            left = _frontier_block_forward(dp, work, pos, left)
            if pos[0] == 1:
                return False
        left = _frontier_block_backward(dp, work, out, pos, left)
        if pos[0] == 2:
            return False
    pos[0] = 3
    return True

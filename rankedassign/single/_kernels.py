"""numba row update of the single-sensor Gibbs samplers (clean inputs only; validate in
:mod:`.samplers`).

The single-sensor problem type of the generic chain driver (:mod:`rankedassign.engine._kernels`):
:func:`alloc_work`, :func:`reset_work` and :func:`row_sweep`, compiled into :data:`run_chains`.
The kernels mirror :mod:`rankedassign.reference` operation for operation so that both give
bit-identical results for the same inputs:

* the random stream is SplitMix64 (:mod:`rankedassign.engine.rng`), one stream per chain;
* a row update draws exactly one uniform and turns it into a candidate with the cumulative loop
  of :func:`sweep` (candidates in the order measurements ``0..M-1``, missed, dead);
* a random-scan sweep first draws its row permutation with the Fisher-Yates loop of
  :func:`sweep`.

State representation. A state is the vector of *compact* indices ``k_i`` in ``0..M+1`` (the
columns of :attr:`AssignmentProblem.compact_cost`): ``k < M`` is measurement ``k``, ``M`` is
missed, ``M + 1`` is dead. ``free[j]`` is 1.0 while measurement ``j`` is free, 0.0 while held.

Two drivers share the arithmetic: ``"direct"`` (rows draw with the direct sum,
:func:`sweep`) and ``"prefix"`` (rows draw from prefix sums, :func:`sweep_prefix`;
:func:`rankedassign.single.prepare.uses_prefix_sums` picks one per problem). Each has its own
compiled driver with only the arrays it reads: every array passed to a call costs several
machine words, and a direct-draw problem of the paper's size is fast enough for that to show.

* ``"direct"``: ``data`` is a :class:`~rankedassign.single.prepare.DirectData` (shifted
  weights, compact costs, scan order); the workspace of ``nb`` chains is a
  :class:`DirectWork`, the free-measurement masks ``(nb, M)`` and the row permutations
  ``(nb, P)``.
* ``"prefix"``: ``data`` is a :class:`~rankedassign.single.prepare.PrefixData` (plus the
  prefix sums and the next positive weight); the workspace is a :class:`PrefixWork`: also
  the scratch rows ``(nb, M + 2)`` and the sorted held measurements ``(nb, P)`` with their
  count ``(nb, 1)``.

Both sweeps are compiled with ``inline="always"``: numba writes them into the driver's loop,
which saves the call (its arguments are some 60 machine words) once per observation.

References
----------
.. [1] B.-N. Vo, B.-T. Vo, H. G. Hoang, "An Efficient Implementation of the Generalized
   Labeled Multi-Bernoulli Filter", IEEE Trans. Signal Process. 65(8):1975-1987, 2017.
.. [2] A. Trezza, D. J. Bucci Jr., P. K. Varshney, "On Gibbs Sampling Architecture for
   Labeled Random Finite Sets Multi-Object Tracking", arXiv:2306.15135, 2023.
.. [3] A. L. Zobrist, "A New Hashing Method with Application for Game Playing", Tech. Rep.
   88, Univ. of Wisconsin, 1970.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ..engine._kernels import (
    KeyTable,
    alloc_key_table,
    herd_lookup,
    key_table_done,
    key_table_sweep_done,
    make_driver,
    next_uniform,
    reset_key_table,
)
from ..engine.records import record
from ..numba_options import jit
from .prepare import CANCEL_GUARD


# ---------------------------------------------------------------------------------- Gibbs
@jit(inline="always")
def cheapest_available(cc, i, free):
    """The cheapest compact cost of row ``i`` among its available candidates (``free`` mask).

    Parameters
    ----------
    cc : ndarray of float64, shape (P, M + 2)
        Compact costs.
    i : int
        The row.
    free : ndarray of float64, shape (M,)
        Free-measurement mask (1.0 free, 0.0 held by another row).

    Returns
    -------
    float
        ``min cc[i, k]`` over the free measurements, missed and dead.
    """
    M = cc.shape[1] - 2
    m = np.inf
    for k in range(M + 2):
        if (k >= M or free[k] > 0.0) and cc[i, k] < m:
            m = cc[i, k]
    return m


@jit()
def draw_exact(cc, i, free, u):
    """Row ``i``'s draw from exact weights, for when every shifted weight underflowed.

    Used by :func:`sweep` with the row's uniform ``u`` when all of row ``i``'s available
    weights ``W`` are 0 (its cheapest entry is held by another row and the rest are more than
    ~745 above it). The weights are ``exp(-(cc[i, k] - m))``, ``m`` the cheapest *available*
    cost; the current entry of row ``i`` is always available and finite, so ``m`` is finite.
    The loop is the same inverse CDF as in :func:`sweep`. This path calls ``exp``, so it
    matches the reference as far as both use the same libm (they do on one machine).

    Parameters
    ----------
    cc, i, free
        As in :func:`cheapest_available`.
    u : float
        The row's uniform in ``[0, 1)``.

    Returns
    -------
    int
        The compact column drawn (a free measurement ``< M``, missed ``M`` or dead ``M + 1``).
    """
    M = cc.shape[1] - 2
    K = M + 2
    m = cheapest_available(cc, i, free)
    total = 0.0
    for k in range(K):
        if k >= M or free[k] > 0.0:
            total += np.exp(-(cc[i, k] - m))
    target = u * total
    acc = 0.0
    last = -1
    for k in range(K):
        if k >= M or free[k] > 0.0:
            w = np.exp(-(cc[i, k] - m))
            if w > 0.0:
                acc += w
                last = k
                if acc > target:
                    return k
    return last


@jit()
def draw_prefix(W, S, next_pos, cc, i, free, held, n_held, cum, u):
    """Row ``i``'s draw from its prefix sums, ``O(P + log M)`` (twin of the reference's).

    ``held[:n_held]`` are the measurements held by the other rows, sorted. The rule, its
    bisection over the runs of free measurements, the cancellation guard and the fall-backs
    are those of :func:`rankedassign.single.reference.draw_prefix`, operation for operation.

    Parameters
    ----------
    W, cc, i, free, cum, u
        As in :func:`draw_direct` (``cum`` the scratch of the held runs' sums).
    S : ndarray of float64, shape (P, M + 1)
        Per-row prefix sums of the measurement weights.
    next_pos : ndarray of int64, shape (P, M)
        First measurement at or after each one with a positive weight, or ``M``.
    held : ndarray of int64
        ``held[:n_held]``: the measurements the other rows hold, increasing.
    n_held : int
        Their number.

    Returns
    -------
    int
        The compact column drawn.
    """
    M = W.shape[1] - 2
    cs = cum  # cs[t]: held weight left of run t, summed left to right (scratch row)
    cs[0] = 0.0
    for t in range(n_held):
        cs[t + 1] = cs[t] + W[i, held[t]]
    meas = S[i, M] - cs[n_held]
    if meas < CANCEL_GUARD * S[i, M]:  # held weight cancels the prefix sum: direct draw
        return draw_direct(W, cc, i, free, cum, u)
    total = (meas + W[i, M]) + W[i, M + 1]
    if not total > 0.0:  # every available weight underflowed
        return draw_direct(W, cc, i, free, cum, u)
    target = u * total
    a = 0
    b = n_held + 1
    while a < b:  # the first run whose last cum exceeds target
        mid = (a + b) // 2
        h = held[mid] if mid < n_held else M
        if S[i, h] - cs[mid] > target:
            b = mid
        else:
            a = mid + 1
    for t in range(a, n_held + 1):  # normally one run
        lo = held[t - 1] + 1 if t > 0 else 0
        h = held[t] if t < n_held else M
        if h > lo and S[i, h] - cs[t] > target:
            p = lo
            q = h - 1
            while p < q:  # the first k in the run with S[i, k + 1] - cs[t] > target
                mid = (p + q) // 2
                if S[i, mid + 1] - cs[t] > target:
                    q = mid
                else:
                    p = mid + 1
            k = next_pos[i, p]
            if k < h:
                return k
    if W[i, M] > 0.0 and meas + W[i, M] > target:
        return M
    if W[i, M + 1] > 0.0:
        return M + 1
    if W[i, M] > 0.0:
        return M
    for k in range(M - 1, -1, -1):  # rounding: the last positive free measurement
        if W[i, k] > 0.0 and free[k] > 0.0:
            return k
    return -1  # unreachable: total > 0 means some available weight is positive


@jit()
def draw_direct(W, cc, i, free, cum, u):
    """Row ``i``'s draw by the direct sum (twin of the reference's ``draw_direct``), ``O(M)``.

    ``p(k) ∝ W[i, k]`` over the available candidates, in the order measurements ``0..M-1``
    (free ones: row ``i``'s own is released first), missed, dead. ``total`` is their sum
    accumulated sequentially in that order, ``target = u * total``, and the pick is the first
    candidate whose running sum exceeds ``target`` (inverse CDF), or the last positive-weight
    candidate if rounding leaves none; :func:`draw_exact` if ``total = 0``. Held measurements
    enter the running sum as ``W * 0.0 = +0.0``, which leaves every partial sum bit-identical
    to the reference's loop that skips them; the running sums are stored so that the search is
    a branch-free count of ``cum[k] <= target`` (the sums never decrease, so the count is the
    index of the first one above ``target``).

    Parameters
    ----------
    W : ndarray of float64, shape (P, M + 2)
        Shifted weights.
    cc : ndarray of float64, shape (P, M + 2)
        Compact costs (read by the :func:`draw_exact` fall-back only).
    i : int
        The row.
    free : ndarray of float64, shape (M,)
        Free-measurement mask.
    cum : ndarray of float64, shape (M + 2,)
        Scratch row: the running sums.
    u : float
        The row's uniform in ``[0, 1)``.

    Returns
    -------
    int
        The compact column drawn.
    """
    M = W.shape[1] - 2
    K = M + 2
    total = 0.0
    for k in range(M):
        total += W[i, k] * free[k]
        cum[k] = total
    total += W[i, M]
    cum[M] = total
    total += W[i, M + 1]
    cum[M + 1] = total
    if total > 0.0:
        target = u * total
        pick = 0
        for k in range(K):
            pick += cum[k] <= target
        if pick < K:
            return pick
        # rounding left u * total at or above the last running sum
        for k in range(K - 1, -1, -1):
            if W[i, k] > 0.0 and (k >= M or free[k] > 0.0):
                return k
    return draw_exact(cc, i, free, u)


@jit()
def _release(held, n_held, k):
    """Remove ``k`` from the sorted ``held[:n_held]``; return the new count.

    Parameters
    ----------
    held : ndarray of int64
        Sorted measurements, ``held[:n_held]``; ``k`` among them.
    n_held : int
        Their number.
    k : int
        The measurement to remove.

    Returns
    -------
    int
        ``n_held - 1``.
    """
    t = 0
    while held[t] != k:
        t += 1
    for s in range(t, n_held - 1):
        held[s] = held[s + 1]
    return n_held - 1


@jit()
def _hold(held, n_held, k):
    """Insert ``k`` into the sorted ``held[:n_held]``; return the new count.

    Parameters
    ----------
    held : ndarray of int64
        Sorted measurements, ``held[:n_held]``, with room for one more.
    n_held : int
        Their number.
    k : int
        The measurement to insert (not among them).

    Returns
    -------
    int
        ``n_held + 1``.
    """
    t = n_held
    while t > 0 and held[t - 1] > k:
        held[t] = held[t - 1]
        t -= 1
    held[t] = k
    return n_held + 1


@jit()
def _shuffle(perm, rs):
    """The random scan's row order: Fisher-Yates from the identity (see :func:`sweep`).

    Parameters
    ----------
    perm : ndarray of int64, shape (P,)
        Filled with the permutation of ``0..P-1``.
    rs : ndarray of uint64, shape (1,)
        The chain's stream state (advanced by ``P - 1`` uniforms).
    """
    P = perm.shape[0]
    for t in range(P):
        perm[t] = t
    for t in range(P - 1, 0, -1):
        j = np.int64(next_uniform(rs) * (t + 1))
        if j > t:
            j = t
        tmp = perm[t]
        perm[t] = perm[j]
        perm[j] = tmp


@jit(inline="always")
def sweep(data, zkeys, state, h, rs, free, perm):
    """One Gibbs sweep over all rows with the direct draw, in place (Gauss-Seidel, spec §2.2).

    Parameters
    ----------
    data : DirectData
        The call's :class:`~rankedassign.single.prepare.DirectData` (or any record with its
        fields): ``W[i, k] = exp(-(cc[i, k] - min_k cc[i, k]))`` (0 where ``cc`` is ``+inf``),
        the compact costs ``cc`` (read only by :func:`draw_exact`) and ``random_scan``: the
        systematic order ``0..P-1`` if False; otherwise a fresh uniformly random order drawn
        first, by Fisher-Yates from the identity: for ``t = P-1..1``,
        ``j = min(floor(u (t + 1)), t)``, swap ``perm[t], perm[j]``.
    zkeys : ndarray, shape (P, M + 2), uint64
        Zobrist keys.
    state : ndarray, shape (P,), int32
        Compact state, updated in place.
    h : uint64
        Zobrist hash of ``state``.
    rs : ndarray, shape (1,), uint64
        Stream state.
    free : ndarray, shape (M,), float64
        1.0 for a free measurement, 0.0 for a held one; updated in place.
    perm : ndarray, shape (P,), int64
        Work space.

    Returns
    -------
    uint64
        Zobrist hash of the updated state.

    Notes
    -----
    Row ``i`` releases its measurement and draws from its conditional (spec eq. 2.1) with one
    uniform by the rule of :func:`draw_direct`, written out here in two passes that give the
    same bits: the first sums the available weights left to right without storing the running
    sums, the second (only when the pick is a measurement) adds the same terms in the same
    order again and stops at the first running sum above ``target``. Storing every running
    sum, as :func:`draw_direct` does, costs more than adding half of them again at ``M = 24``.
    """
    W = data.W
    cc = data.cc
    random_scan = data.random_scan
    P = state.shape[0]
    M = W.shape[1] - 2
    if random_scan:
        _shuffle(perm, rs)
    for t in range(P):
        i = perm[t] if random_scan else t
        k_old = state[i]
        if k_old < M:  # release row i's own measurement
            free[k_old] = 1.0
        meas = 0.0  # the available measurements' weight, left to right (held: W * 0.0 = +0.0)
        for k in range(M):
            meas += W[i, k] * free[k]
        missed = meas + W[i, M]
        total = missed + W[i, M + 1]
        u = next_uniform(rs)
        k_new = -1
        if total > 0.0:
            target = u * total
            if meas > target:  # the same running sums again, up to the first above target
                acc = 0.0
                for k in range(M):
                    acc += W[i, k] * free[k]
                    if acc > target:
                        k_new = k
                        break
            elif missed > target:
                k_new = M
            elif total > target:
                k_new = M + 1
            if k_new < 0:  # rounding left u * total at or above the last running sum
                for k in range(M + 1, -1, -1):
                    if W[i, k] > 0.0 and (k >= M or free[k] > 0.0):
                        k_new = k
                        break
        if k_new < 0:
            k_new = draw_exact(cc, i, free, u)
        if k_new < M:
            free[k_new] = 0.0
        if k_new != k_old:
            state[i] = k_new
            h = h ^ zkeys[i, k_old] ^ zkeys[i, k_new]
    return h


@jit(inline="always")
def sweep_prefix(data, zkeys, state, h, rs, free, perm, cum, held, n_held):
    """One Gibbs sweep whose rows draw from prefix sums (:func:`draw_prefix`), in place.

    Parameters
    ----------
    data : PrefixData
        The call's :class:`~rankedassign.single.prepare.PrefixData`: the fields of
        :class:`~rankedassign.single.prepare.DirectData` (see :func:`sweep`), the prefix sums
        ``S`` of the measurement weights and the next positive weight ``next_pos``
        (:func:`rankedassign.single.prepare.prefix_sums`).
    zkeys, state, h, rs, free, perm
        As in :func:`sweep`.
    cum : ndarray, shape (M + 2,), float64
        Work space.
    held : ndarray, shape (P,), int64
        The held measurements in increasing order in ``held[:n_held[0]]``; updated in place.
    n_held : ndarray, shape (1,), int64
        Their number.

    Returns
    -------
    uint64
        Zobrist hash of the updated state.

    Notes
    -----
    The scan order and the bookkeeping are those of :func:`sweep`; each row's draw costs
    ``O(P + log M)`` instead of ``O(M)``.
    """
    W = data.W
    cc = data.cc
    S = data.S
    next_pos = data.next_pos
    random_scan = data.random_scan
    P = state.shape[0]
    M = W.shape[1] - 2
    if random_scan:
        _shuffle(perm, rs)
    for t in range(P):
        i = perm[t] if random_scan else t
        k_old = state[i]
        if k_old < M:  # release row i's own measurement
            free[k_old] = 1.0
            n_held[0] = _release(held, n_held[0], k_old)
        u = next_uniform(rs)
        k_new = draw_prefix(W, S, next_pos, cc, i, free, held, n_held[0], cum, u)
        if k_new < M:
            free[k_new] = 0.0
            n_held[0] = _hold(held, n_held[0], k_new)
        if k_new != k_old:
            state[i] = k_new
            h = h ^ zkeys[i, k_old] ^ zkeys[i, k_new]
    return h


# ------------------------------------------------------------------------ the problem types
@jit()
def _reset_free(free, x0):
    """The free-measurement mask of the start state ``x0``.

    Parameters
    ----------
    free : ndarray of float64, shape (M,)
        Filled: 0.0 at the measurements ``x0`` holds, else 1.0.
    x0 : ndarray of int32, shape (P,)
        The start state (compact columns).
    """
    M = free.shape[0]
    free[:] = 1.0
    for i in range(x0.shape[0]):
        if x0[i] < M:
            free[x0[i]] = 0.0


class DirectWork(NamedTuple):
    """Workspace of ``nb`` chains of the direct draw (:func:`alloc_work`), one row per chain.

    Attributes
    ----------
    free : ndarray, shape (nb, M), float64
        Free-measurement masks (1.0 free, 0.0 held).
    perm : ndarray, shape (nb, P), int64
        Row orders of the random scan.
    """

    free: np.ndarray
    perm: np.ndarray


class PrefixWork(NamedTuple):
    """Workspace of ``nb`` chains of the prefix-sum draw (:func:`alloc_work_prefix`).

    Attributes
    ----------
    free, perm
        As in :class:`DirectWork`.
    cum : ndarray, shape (nb, M + 2), float64
        Scratch rows of the draw.
    held : ndarray, shape (nb, max(P, 1)), int64
        The measurements the chain's rows hold, sorted, in ``held[b, :n_held[b, 0]]``.
    n_held : ndarray, shape (nb, 1), int64
        Their number.
    """

    free: np.ndarray
    perm: np.ndarray
    cum: np.ndarray
    held: np.ndarray
    n_held: np.ndarray


@jit()
def alloc_work(data, nb):
    """Workspace of ``nb`` chains of the direct draw: free masks and row permutations.

    Parameters
    ----------
    data : DirectData
        The call's data record (its ``W`` sizes the workspace).
    nb : int
        Chains simulated at once.

    Returns
    -------
    DirectWork
        Uninitialised (:func:`reset_work` prepares a slab).
    """
    W = data.W
    return DirectWork(free=np.empty((nb, W.shape[1] - 2)),
                      perm=np.empty((nb, W.shape[0]), dtype=np.int64))


@jit()
def reset_work(data, work, b, x0):
    """Slab ``b``'s free-measurement mask for the start state ``x0``.

    Parameters
    ----------
    data : DirectData
        The call's data record (unused).
    work : DirectWork
        The workspace.
    b : int
        The slab.
    x0 : ndarray of int32, shape (P,)
        The start state.
    """
    _reset_free(work.free[b], x0)


@jit(inline="always")
def row_sweep(data, work, b, zkeys, state, h, rs):
    """One sweep of chain slab ``b`` (:func:`sweep` on the slab's workspace).

    Parameters
    ----------
    data : DirectData
        The call's data record.
    work : DirectWork
        The workspace.
    b : int
        The chain's slab.
    zkeys, state, h, rs
        As in :func:`sweep`.

    Returns
    -------
    uint64
        The new Zobrist hash of ``state``.
    """
    return sweep(data, zkeys, state, h, rs, work.free[b], work.perm[b])


@jit()
def alloc_work_prefix(data, nb):
    """Workspace of ``nb`` chains of the prefix draw: also running sums and held lists.

    Parameters
    ----------
    data, nb
        As in :func:`alloc_work`, with a :class:`PrefixData`.

    Returns
    -------
    PrefixWork
        Uninitialised (:func:`reset_work_prefix` prepares a slab).
    """
    W = data.W
    P = W.shape[0]
    M = W.shape[1] - 2
    return PrefixWork(free=np.empty((nb, M)), perm=np.empty((nb, P), dtype=np.int64),
                      cum=np.empty((nb, M + 2)),
                      held=np.empty((nb, max(P, 1)), dtype=np.int64),
                      n_held=np.empty((nb, 1), dtype=np.int64))


@jit()
def reset_work_prefix(data, work, b, x0):
    """Slab ``b``'s free-measurement mask and sorted held list for the start state ``x0``.

    Parameters
    ----------
    data, work, b, x0
        As in :func:`reset_work`, with a :class:`PrefixData` and a :class:`PrefixWork`.
    """
    _reset_free(work.free[b], x0)
    held = work.held[b]
    M = work.free.shape[1]
    n = np.int64(0)  # int64 as in the sweep's calls: one signature of _hold
    for i in range(x0.shape[0]):
        if x0[i] < M:
            n = _hold(held, n, np.int64(x0[i]))
    work.n_held[b, 0] = n


@jit(inline="always")
def row_sweep_prefix(data, work, b, zkeys, state, h, rs):
    """One sweep of chain slab ``b`` (:func:`sweep_prefix` on the slab's workspace).

    Parameters
    ----------
    data, work, b
        As in :func:`row_sweep`, with a :class:`PrefixData` and a :class:`PrefixWork`.
    zkeys, state, h, rs
        As in :func:`sweep_prefix`.

    Returns
    -------
    uint64
        The new Zobrist hash of ``state``.
    """
    return sweep_prefix(data, zkeys, state, h, rs, work.free[b], work.perm[b], work.cum[b],
                        work.held[b], work.n_held[b])


# ---------------------------------------------------------------------------- herded draw
@jit(inline="always")
def sweep_herded(data, work, b, zkeys, state, h, rs):
    """One herded sweep of chain slab ``b``, in place (twin of the reference's ``herd_sweep``).

    ``data`` is a :class:`~rankedassign.single.prepare.HerdedData`; slab ``b`` of ``work``
    (a :class:`HerdedWork`) holds the free mask, the row order, the scratch rows ``p`` (each
    row's conditional: the reference's ``conditional``, operation for operation) and ``cum``
    (the fall-back draw's), ``keyv`` (the row's key, the reference's ``herd_key``: the state
    with row ``i`` as -1, or its gated measurements held by the other rows in increasing
    order, padded with -1), the key table, the chain's tallies ``cnt`` and ``hist`` (read by
    :func:`rankedassign.engine._kernels.key_table_done`).

    Parameters
    ----------
    data : HerdedData
        The call's data record.
    work : HerdedWork
        The workspace.
    b : int
        The chain's slab.
    zkeys : ndarray of uint64, shape (P, M + 2)
        Zobrist keys.
    state : ndarray of int32, shape (P,)
        Compact state, updated in place.
    h : uint64
        Its Zobrist hash.
    rs : ndarray of uint64, shape (1,)
        The chain's stream state.

    Returns
    -------
    uint64
        The new Zobrist hash of ``state``.
    """
    W, cc, random_scan = data.W, data.cc, data.random_scan
    key_mode, init_mode, capacity = data.key_mode, data.init_mode, data.capacity
    free, perm, p, cum, keyv = (work.free[b], work.perm[b], work.p[b], work.cum[b],
                                work.keyv[b])
    hw, kst, krow, tslot, thash = (work.hw[b], work.kst[b], work.krow[b], work.tslot[b],
                                   work.thash[b])
    cnt = work.cnt[b]
    P = state.shape[0]
    M = W.shape[1] - 2
    K = M + 2
    if random_scan:
        _shuffle(perm, rs)
    for t in range(P):
        i = perm[t] if random_scan else t
        k_old = state[i]
        if k_old < M:
            free[k_old] = 1.0
        # the key (the reference's herd_key): it reads only the other rows' state
        if key_mode == 0:
            for r in range(P):
                keyv[r] = state[r]
            keyv[i] = -1
        else:
            n = 0
            for r in range(P):
                v = state[r]
                if r != i and v < M and cc[i, v] < np.inf:
                    q = n  # insert v: keyv[:n] stays increasing
                    while q > 0 and keyv[q - 1] > v:
                        keyv[q] = keyv[q - 1]
                        q -= 1
                    keyv[q] = v
                    n += 1
            for r in range(n, P):
                keyv[r] = -1
        s, new = herd_lookup(i, keyv, cnt, capacity, krow, kst, tslot, thash)
        if s < 0:  # the table is full (a fall-back, counted): an ordinary Gibbs draw
            k_new = draw_direct(W, cc, i, free, cum, next_uniform(rs))
        else:
            # the conditional (the reference's conditional()), herded in the same pass
            meas = 0.0
            for k in range(M):
                meas += W[i, k] * free[k]
            total = (meas + W[i, M]) + W[i, M + 1]
            exact = not total > 0.0
            inv = 0.0
            if exact:  # every available weight underflowed: exact weights
                m = cheapest_available(cc, i, free)
                tot = 0.0
                for k in range(K):
                    if k >= M or free[k] > 0.0:
                        p[k] = np.exp(-(cc[i, k] - m))
                        tot += p[k]
                    else:
                        p[k] = 0.0
                for k in range(K):
                    p[k] = p[k] / tot
            else:
                inv = 1.0 / total
            if new:  # the key's initial weights; -inf where the key's conditional is 0
                for k in range(K):
                    if exact:
                        pk = p[k]
                    elif k < M:
                        pk = (W[i, k] * free[k]) * inv
                    else:
                        pk = W[i, k] * inv
                    if init_mode == 0:
                        w0 = pk
                    elif init_mode == 1:
                        w0 = 0.0
                    else:
                        w0 = next_uniform(rs)
                    hw[s, k] = w0 if pk > 0.0 else -np.inf
            # w += p and the first largest w (a candidate of probability 0 holds -inf)
            best = -1
            bw = -np.inf
            if exact:
                for k in range(K):
                    v = hw[s, k] + p[k]
                    hw[s, k] = v
                    if v > bw:
                        best = k
                        bw = v
            else:  # the hot loop
                for k in range(M):
                    v = hw[s, k] + (W[i, k] * free[k]) * inv
                    hw[s, k] = v
                    if v > bw:
                        best = k
                        bw = v
                for k in range(M, K):
                    v = hw[s, k] + W[i, k] * inv
                    hw[s, k] = v
                    if v > bw:
                        best = k
                        bw = v
            hw[s, best] = bw - 1.0
            k_new = best
        if k_new < M:
            free[k_new] = 0.0
        if k_new != k_old:
            state[i] = k_new
            h = h ^ zkeys[i, k_old] ^ zkeys[i, k_new]
    key_table_sweep_done(work, b)
    return h


class HerdedWork(record(DirectWork, {"cum": np.ndarray}, KeyTable)):
    """Workspace of ``nb`` herded chains (:func:`alloc_work_herded`): the fields of
    :class:`DirectWork`, the fall-back draw's scratch rows and those of a
    :class:`~rankedassign.engine._kernels.KeyTable` (``K = M + 2`` candidates, key vectors of
    length ``P``).

    Attributes
    ----------
    free, perm
        As in :class:`DirectWork`.
    cum : ndarray, shape (nb, K), float64
        Scratch row of the fall-back (Gibbs) draw.
    p, keyv, hw, kst, krow, tslot, thash, cnt, hist
        As in :class:`~rankedassign.engine._kernels.KeyTable`: the row's conditional and
        key, the key table and the chain's tallies.
    """


@jit()
def alloc_work_herded(data, nb):
    """Workspace of ``nb`` herded chains: the direct draw's, a scratch row and key tables.

    Parameters
    ----------
    data : HerdedData
        The call's data record (``W``, ``capacity`` and ``chain_length`` size the workspace).
    nb : int
        Chains simulated at once.

    Returns
    -------
    HerdedWork
        Its key tables empty only after :func:`reset_work_herded`.
    """
    W = data.W
    P = W.shape[0]
    K = W.shape[1]
    table = alloc_key_table(nb, K, P, data.capacity, data.chain_length)
    return HerdedWork(*(alloc_work(data, nb)[:] + (np.empty((nb, K)),) + table[:]))


@jit()
def reset_work_herded(data, work, b, x0):
    """Slab ``b`` for a new chain from ``x0``: free mask, an empty key table, zero tallies.

    Parameters
    ----------
    data, work, b, x0
        As in :func:`reset_work`, with a :class:`HerdedData` and a :class:`HerdedWork`.
    """
    _reset_free(work.free[b], x0)
    reset_key_table(work, b)


#: The chain driver compiled for the single-sensor problem with the direct draw
#: (:func:`rankedassign.engine._kernels.make_driver`).
run_chains = make_driver("single", alloc_work, reset_work, row_sweep, work=DirectWork)
#: The chain driver compiled for the single-sensor problem with the prefix-sum draw.
run_chains_prefix = make_driver("single_prefix", alloc_work_prefix, reset_work_prefix,
                                row_sweep_prefix, work=PrefixWork)
#: The chain driver compiled for the single-sensor problem with the herded draw.
run_chains_herded = make_driver("single_herded", alloc_work_herded, reset_work_herded,
                                sweep_herded, work=HerdedWork, chain_done=key_table_done)

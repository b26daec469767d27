"""numba row update of the single-sensor Gibbs samplers (clean inputs only; validate in
:mod:`.samplers`).

The single-sensor problem type of the generic chain driver (:mod:`rankedassign._chains`):
:func:`alloc_work`, :func:`reset_work` and :func:`row_sweep`, compiled into :data:`run_chains`.
The kernels mirror :mod:`rankedassign.reference` operation for operation so that both give
bit-identical results for the same inputs:

* the random stream is SplitMix64 (:mod:`rankedassign._rng`), one stream per chain;
* a row update draws exactly one uniform and turns it into a candidate with the cumulative loop
  of :func:`sweep` (candidates in the order measurements ``0..M-1``, missed, dead);
* a random-scan sweep first draws its row permutation with the Fisher-Yates loop of
  :func:`sweep`.

State representation. A state is the vector of *compact* indices ``k_i`` in ``0..M+1`` (the
columns of :attr:`AssignmentProblem.compact_cost`): ``k < M`` is measurement ``k``, ``M`` is
missed, ``M + 1`` is dead. ``free[j]`` is 1.0 while measurement ``j`` is free, 0.0 while held.

``data`` is the tuple ``(W, cc, random_scan)`` (shifted weights, compact costs, scan order);
the workspace of ``nb`` chains is ``(free, perm, cum)``: the free-measurement masks
``(nb, M)``, the row permutations ``(nb, P)`` and the running sums ``(nb, M + 2)``.

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

import numpy as np

from ._chains import make_driver
from ._rng_kernels import next_uniform
from .numba_options import jit


# ---------------------------------------------------------------------------------- Gibbs
@jit()
def draw_exact(cc, i, free, u):
    """Row ``i``'s draw from exact weights, for when every shifted weight underflowed.

    Used by :func:`sweep` with the row's uniform ``u`` when all of row ``i``'s available
    weights ``W`` are 0 (its cheapest entry is held by another row and the rest are more than
    ~745 above it). The weights are ``exp(-(cc[i, k] - m))``, ``m`` the cheapest *available*
    cost; the current entry of row ``i`` is always available and finite, so ``m`` is finite.
    The loop is the same inverse CDF as in :func:`sweep`. This path calls ``exp``, so it
    matches the reference as far as both use the same libm (they do on one machine).
    """
    M = cc.shape[1] - 2
    K = M + 2
    m = np.inf
    for k in range(K):
        if (k >= M or free[k] > 0.0) and cc[i, k] < m:
            m = cc[i, k]
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
def sweep(W, cc, zkeys, state, free, h, rs, perm, cum, random_scan):
    """One Gibbs sweep over all rows, in place (Gauss-Seidel, spec §2.2); return the new hash.

    Parameters
    ----------
    W : ndarray, shape (P, M + 2), float64
        ``W[i, k] = exp(-(cc[i, k] - min_k cc[i, k]))`` (0 where ``cc`` is ``+inf``).
    cc : ndarray, shape (P, M + 2), float64
        Compact costs (used only by :func:`draw_exact`).
    zkeys : ndarray, shape (P, M + 2), uint64
        Zobrist keys.
    state : ndarray, shape (P,), int32
        Compact state, updated in place.
    free : ndarray, shape (M,), float64
        1.0 for a free measurement, 0.0 for a held one; updated in place.
    h : uint64
        Zobrist hash of ``state``.
    rs : ndarray, shape (1,), uint64
        Stream state.
    perm, cum : ndarray, shapes (P,) int64 and (M + 2,) float64
        Work space.
    random_scan : bool
        Systematic order ``0..P-1`` if False; otherwise a fresh uniformly random order drawn
        first, by Fisher-Yates from the identity: for ``t = P-1..1``,
        ``j = min(floor(u (t + 1)), t)``, swap ``perm[t], perm[j]``.

    Returns
    -------
    uint64
        Zobrist hash of the updated state.

    Notes
    -----
    Row ``i`` is drawn from its conditional (spec eq. 2.1) with one uniform ``u``:
    ``p(k) ∝ W[i, k]`` over the available candidates, in the order measurements ``0..M-1``
    (free, or held by row ``i`` itself, which is released first), missed, dead. ``total`` is
    their sum accumulated sequentially in that order, ``target = u * total``, and the pick is
    the first candidate whose running sum exceeds ``target`` (inverse CDF), or the last
    positive-weight candidate if rounding leaves none; :func:`draw_exact` if ``total = 0``.
    Held measurements enter the running sum as ``W * 0.0 = +0.0``, which leaves every partial
    sum bit-identical to the reference's loop that skips them; the running sums are stored so
    that the search is a branch-free count of ``cum[k] <= target`` (the sums never decrease,
    so the count is the index of the first one above ``target``). The draw is written out
    here rather than in a helper because a call per row costs ~10 % of the sweep.
    """
    P = state.shape[0]
    M = W.shape[1] - 2
    K = M + 2
    if random_scan:
        for t in range(P):
            perm[t] = t
        for t in range(P - 1, 0, -1):
            j = np.int64(next_uniform(rs) * (t + 1))
            if j > t:
                j = t
            tmp = perm[t]
            perm[t] = perm[j]
            perm[j] = tmp
    for t in range(P):
        i = perm[t] if random_scan else t
        k_old = state[i]
        if k_old < M:  # row i's own measurement is available to it
            free[k_old] = 1.0
        # total = sum over available k of W[i, k], sequentially in candidate order
        total = 0.0
        for k in range(M):
            total += W[i, k] * free[k]
            cum[k] = total
        total += W[i, M]
        cum[M] = total
        total += W[i, M + 1]
        cum[M + 1] = total
        u = next_uniform(rs)
        k_new = -1
        if total > 0.0:
            target = u * total
            pick = 0
            for k in range(K):
                pick += cum[k] <= target
            if pick < K:
                k_new = pick
            else:  # rounding left u * total at or above the last running sum
                for k in range(K - 1, -1, -1):
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


# ------------------------------------------------------------------------ the problem type
@jit()
def alloc_work(data, nb):
    """Workspace of ``nb`` chains: free-measurement masks, row permutations, running sums."""
    W = data[0]
    P = W.shape[0]
    M = W.shape[1] - 2
    return np.empty((nb, M)), np.empty((nb, P), dtype=np.int64), np.empty((nb, M + 2))


@jit()
def reset_work(data, work, b, x0):
    """Slab ``b``'s free-measurement mask for the start state ``x0``."""
    free = work[0][b]
    M = free.shape[0]
    free[:] = 1.0
    for i in range(x0.shape[0]):
        if x0[i] < M:
            free[x0[i]] = 0.0


@jit()
def row_sweep(data, work, b, zkeys, state, h, rs):
    """One sweep of chain slab ``b`` (:func:`sweep` on the slab's workspace)."""
    return sweep(data[0], data[1], zkeys, state, work[0][b], h, rs, work[1][b], work[2][b],
                 data[2])


#: The chain driver compiled for the single-sensor problem (:func:`._chains.make_driver`).
run_chains = make_driver("single", alloc_work, reset_work, row_sweep)

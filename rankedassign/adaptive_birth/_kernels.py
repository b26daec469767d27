"""numba row update of the adaptive-birth Gibbs sampler (clean inputs only).

The compiled twin of :mod:`rankedassign.adaptive_birth.reference`: the same operations in the
same order (Fisher-Yates sensor order, ratio-form log-weights with running information sums,
plain-loop Cholesky and forward substitution, ``exp(lw - max)`` and the sequential
inverse-CDF loop), so both give bit-identical chains for the same stream. The three
functions follow the generic chain driver's interface:

* :func:`alloc_work` ``(data, nb) -> work``: a tuple of scratch arrays, leading dimension
  ``nb`` (one slab per chain simulated at once);
* :func:`reset_work` ``(data, work, b, x0)``: nothing to reset (the information sums are
  recomputed from the state at the start of every sweep, so a sweep's transition depends on
  the state only);
* :func:`sweep` ``(data, work, b, zkeys, state, h, rs) -> h``: one sweep in place on the
  ``int32`` tuple ``state``, keeping the Zobrist hash ``h``.

``data`` is the tuple of :func:`rankedassign.adaptive_birth.prepare.chain_inputs`.

References
----------
.. [1] A. Trezza, D. J. Bucci Jr., P. K. Varshney, "Multi-sensor joint adaptive birth sampler
   for labeled random finite set tracking", IEEE Trans. Signal Process. 70, 2022.
"""

from __future__ import annotations

import math

import numpy as np

from ..engine._kernels import herd_lookup, herd_pick, make_driver, next_uniform
from ..numba_options import jit

__all__ = ["alloc_work", "reset_work", "sweep", "draw", "cholesky", "half_logdet", "quad",
           "run_chains", "sweep_herded", "alloc_work_herded", "reset_work_herded",
           "chain_done_herded", "run_chains_herded"]


@jit()
def alloc_work(data, nb):
    """Scratch arrays for ``nb`` chains: ``(order, M, b, c, Mp, L, y, bj, lw)``.

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign.adaptive_birth.prepare import AdaptiveBirthProblem, chain_inputs
    >>> work = alloc_work(chain_inputs(AdaptiveBirthProblem.from_log_weights(np.zeros((2, 4)))), 3)
    >>> work[0].shape, work[8].shape
    ((3, 2), (3, 4))
    """
    V = data[1]
    n = data[2]
    K = 1
    for v in range(V):
        K = max(K, data[4][v])
    return (np.zeros((nb, V), dtype=np.int64), np.zeros((nb, n, n)), np.zeros((nb, n)),
            np.zeros((nb, 1)), np.zeros((nb, n, n)), np.zeros((nb, n, n)), np.zeros((nb, n)),
            np.zeros((nb, n)), np.zeros((nb, K)))


@jit()
def reset_work(data, work, b, x0):
    """Prepare slab ``b`` for a chain started at ``x0`` (nothing to do; see module notes).

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign.adaptive_birth.prepare import AdaptiveBirthProblem, chain_inputs
    >>> d = chain_inputs(AdaptiveBirthProblem.from_log_weights(np.zeros((2, 2))))
    >>> reset_work(d, alloc_work(d, 1), 0, np.zeros(2, dtype=np.int32))
    """
    return None


@jit()
def draw(lw, K, u):
    """Index in ``0..K-1`` with probability ``∝ exp(lw[j])`` from the uniform ``u``.

    Twin of :func:`rankedassign.adaptive_birth.reference.draw` (which draws ``u`` itself).

    Examples
    --------
    >>> import numpy as np
    >>> int(draw(np.array([-np.inf, 0.0, -np.inf]), 3, 0.5))
    1
    """
    mx = lw[0]
    for j in range(K):
        if lw[j] > mx:
            mx = lw[j]
    for j in range(K):
        lw[j] = math.exp(lw[j] - mx)
    total = 0.0
    for j in range(K):
        total += lw[j]
    target = u * total
    acc = 0.0
    last = 0
    for j in range(K):
        w = lw[j]
        if w > 0.0:
            acc += w
            last = j
            if acc > target:
                return j
    return last


@jit()
def cholesky(M, L, n):
    """Lower Cholesky factor of ``M`` into ``L`` (plain loops, as the reference).

    Examples
    --------
    >>> import numpy as np
    >>> L = np.zeros((2, 2))
    >>> cholesky(np.array([[4.0, 2.0], [2.0, 5.0]]), L, 2)
    >>> L.tolist()
    [[2.0, 0.0], [1.0, 2.0]]
    """
    for i in range(n):
        for j in range(i + 1):
            s = M[i, j]
            for k in range(j):
                s -= L[i, k] * L[j, k]
            if i == j:
                L[i, i] = math.sqrt(s)
            else:
                L[i, j] = s / L[j, j]


@jit()
def half_logdet(L, n):
    """``sum_i ln L_ii = ln|M| / 2`` for ``M = L L'``.

    Examples
    --------
    >>> import numpy as np
    >>> half_logdet(np.array([[2.0, 0.0], [1.0, 2.0]]), 2)
    1.3862943611198906
    """
    hl = 0.0
    for i in range(n):
        hl += math.log(L[i, i])
    return hl


@jit()
def quad(L, b, y, n):
    """``|L^-1 b|^2 = b' M^-1 b`` for ``M = L L'``, using ``y`` as scratch.

    Examples
    --------
    >>> import numpy as np
    >>> quad(np.array([[2.0, 0.0], [1.0, 2.0]]), np.array([2.0, 1.0]), np.zeros(2), 2)
    1.0
    """
    q = 0.0
    for i in range(n):
        s = b[i]
        for k in range(i):
            s -= L[i, k] * y[k]
        y[i] = s / L[i, i]
        q += y[i] * y[i]
    return q


@jit()
def _sums(data, M, b, c, state):
    """``(M, b, c)`` = prior information plus the terms of the detecting sensors of ``state``."""
    n = data[2]
    off, M0, b0, A, a, cz = data[5], data[8], data[9], data[11], data[12], data[13]
    for i in range(n):
        for k in range(n):
            M[i, k] = M0[i, k]
        b[i] = b0[i]
    c[0] = data[10]
    for v in range(data[1]):
        if state[v] > 0:
            t = off[v] + state[v] - 1
            for i in range(n):
                for k in range(n):
                    M[i, k] += A[v, i, k]
                b[i] += a[t, i]
            c[0] += cz[t]


@jit()
def _gaussian_weights(data, M, b, c, Mp, L, y, bj, lw, state, s):
    """Sensor ``s``'s log-weights into ``lw`` (ratio form); leaves ``(M-, b-, c-)``, ``M+``."""
    n = data[2]
    off, A, a, cz, const = data[5], data[11], data[12], data[13], data[14]
    Ms = data[4][s] - 1
    if state[s] > 0:                                     # remove sensor s: (M-, b-, c-)
        t = off[s] + state[s] - 1
        for i in range(n):
            for k in range(n):
                M[i, k] -= A[s, i, k]
            b[i] -= a[t, i]
        c[0] -= cz[t]
    cholesky(M, L, n)
    lw[0] = data[15][s] - half_logdet(L, n) - 0.5 * (c[0] - quad(L, b, y, n))   # missed by s
    for i in range(n):
        for k in range(n):
            Mp[i, k] = M[i, k] + A[s, i, k]              # M+ = M- + A_s
    cholesky(Mp, L, n)
    hl = half_logdet(L, n)
    for j in range(1, Ms + 1):
        t = off[s] + j - 1
        for i in range(n):
            bj[i] = b[i] + a[t, i]                       # b_j = b- + H' R^-1 z_j
        lw[j] = const[t] - hl - 0.5 * ((c[0] + cz[t]) - quad(L, bj, y, n))


@jit(inline="always")
def sweep(data, work, b, zkeys, state, h, rs):
    """One sweep over the sensors of slab ``b``'s chain; returns the updated Zobrist hash.

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign.adaptive_birth.prepare import AdaptiveBirthProblem, chain_inputs
    >>> t = np.full((3, 3), -np.inf); t[0, 0] = 0.0; t[0, 2] = 50.0
    >>> d = chain_inputs(AdaptiveBirthProblem.from_log_weights(t), "fixed")
    >>> state = np.zeros(2, dtype=np.int32)
    >>> keys = np.arange(6, dtype=np.uint64).reshape(2, 3)
    >>> h = sweep(d, alloc_work(d, 1), 0, keys, state, np.uint64(0),
    ...           np.zeros(1, dtype=np.uint64))
    >>> state.tolist(), int(h) == int(keys[1, 0] ^ keys[1, 2])
    ([0, 2], True)
    """
    V = data[1]
    strides = data[6]
    logw = data[7]
    order = work[0][b]
    M, bb, c, Mp, L, y, bj, lw = (work[1][b], work[2][b], work[3][b], work[4][b], work[5][b],
                                  work[6][b], work[7][b], work[8][b])
    for v in range(V):
        order[v] = v
    if data[3]:                                          # Fisher-Yates, t = V-1..1
        for t in range(V - 1, 0, -1):
            k = min(np.int64(next_uniform(rs) * (t + 1)), t)
            tmp = order[t]
            order[t] = order[k]
            order[k] = tmp
    gaussian = data[0] == 1
    if gaussian:
        _sums(data, M, bb, c, state)
    for r in range(V):
        s = order[r]
        K = data[4][s]
        if gaussian:
            _gaussian_weights(data, M, bb, c, Mp, L, y, bj, lw, state, s)
        else:
            base = 0
            for v in range(V):
                if v != s:
                    base += state[v] * strides[v]
            for j in range(K):
                lw[j] = logw[base + j * strides[s]]
        j = draw(lw, K, next_uniform(rs))
        if gaussian and j > 0:                           # (M, b, c) <- sums of the new tuple
            t = data[5][s] + j - 1
            n = data[2]
            for i in range(n):
                for k in range(n):
                    M[i, k] = Mp[i, k]
                bb[i] += data[12][t, i]
            c[0] += data[13][t]
        old = state[s]
        if j != old:
            h ^= zkeys[s, old] ^ zkeys[s, j]
            state[s] = j
    return h


#: The chain driver compiled for the adaptive-birth problem (:func:`.._chains.make_driver`).
run_chains = make_driver("adaptive_birth", alloc_work, reset_work, sweep)


# ---------------------------------------------------------------------------- herded draw
@jit(inline="always")
def _conditional(lw, p, K):
    """Twin of :func:`rankedassign.adaptive_birth.reference.conditional` into ``p``."""
    mx = lw[0]
    for j in range(K):
        if lw[j] > mx:
            mx = lw[j]
    total = 0.0
    for j in range(K):
        p[j] = math.exp(lw[j] - mx)
        total += p[j]
    inv = 1.0 / total
    for j in range(K):
        p[j] = p[j] * inv


@jit(inline="always")
def sweep_herded(data, work, b, zkeys, state, h, rs):
    """One herded sweep of slab ``b`` (twin of the reference's ``herd_sweep``).

    ``data`` is the Gibbs data (``data[0..15]``) followed by the key mode, the init mode, the
    capacity, ``chain_length`` and the tally (one flat tuple: the parallel speculation takes
    no nested tuple); ``work`` is
    the Gibbs workspace (``work[0..8]``) followed by the conditional ``p``, the key vector
    ``keyv`` (``J`` with the redrawn sensor as -1; the key is the same for both key modes),
    the key table (weights ``hw``, keys ``kst``/``krow``, index ``tslot``/``thash``), the
    chain's ``cnt = [keys, fall-backs, sweeps]`` and ``hist`` (:func:`chain_done_herded`).
    """
    gd = data
    V = gd[1]
    strides = gd[6]
    logw = gd[7]
    order = work[0][b]
    M, bb, c, Mp, L, y, bj, lw = (work[1][b], work[2][b], work[3][b], work[4][b], work[5][b],
                                  work[6][b], work[7][b], work[8][b])
    p, keyv, cnt = work[9][b], work[10][b], work[16][b]
    for v in range(V):
        order[v] = v
    if gd[3]:                                            # Fisher-Yates, t = V-1..1
        for t in range(V - 1, 0, -1):
            k = min(np.int64(next_uniform(rs) * (t + 1)), t)
            tmp = order[t]
            order[t] = order[k]
            order[k] = tmp
    gaussian = gd[0] == 1
    if gaussian:
        _sums(gd, M, bb, c, state)
    for r in range(V):
        s = order[r]
        K = gd[4][s]
        if gaussian:
            _gaussian_weights(gd, M, bb, c, Mp, L, y, bj, lw, state, s)
        else:
            base = 0
            for v in range(V):
                if v != s:
                    base += state[v] * strides[v]
            for j in range(K):
                lw[j] = logw[base + j * strides[s]]
        _conditional(lw, p, K)
        for v in range(V):
            keyv[v] = -1 if v == s else state[v]
        slot, new = herd_lookup(s, keyv, cnt, data[18], work[13][b], work[12][b], work[14][b],
                                work[15][b])
        if slot < 0:  # the table is full: an ordinary Gibbs draw
            j = draw(lw, K, next_uniform(rs))
        else:
            j = herd_pick(work[11][b, slot], p, K, new, data[17], rs)
        if gaussian and j > 0:                           # (M, b, c) <- sums of the new tuple
            t = gd[5][s] + j - 1
            n = gd[2]
            for i in range(n):
                for k in range(n):
                    M[i, k] = Mp[i, k]
                bb[i] += gd[12][t, i]
            c[0] += gd[13][t]
        old = state[s]
        if j != old:
            h ^= zkeys[s, old] ^ zkeys[s, j]
            state[s] = j
    cnt[2] += 1
    hist = work[17]
    if hist.shape[1] > 1:  # speculation: the tallies after every sweep
        hist[b, cnt[2], 0] = cnt[0]
        hist[b, cnt[2], 1] = cnt[1]
    return h


@jit()
def alloc_work_herded(data, nb):
    """Workspace of ``nb`` herded chains: the Gibbs scratch, the conditional, key tables.

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign.adaptive_birth.prepare import AdaptiveBirthProblem, chain_inputs
    >>> d = chain_inputs(AdaptiveBirthProblem.from_log_weights(np.zeros((2, 4))))
    >>> work = alloc_work_herded(d + (1, 0, 8, 5, np.zeros(2, dtype=np.int64)), 3)
    >>> work[9].shape, work[11].shape
    ((3, 4), (3, 8, 4))
    """
    g = alloc_work(data, nb)
    V = data[1]
    K = g[8].shape[1]
    cap = data[18]
    T = 4
    while T < 2 * cap:
        T *= 2
    L = max(V, 1)
    return (g[0], g[1], g[2], g[3], g[4], g[5], g[6], g[7], g[8], np.zeros((nb, K)),
            np.empty((nb, L), dtype=np.int32), np.empty((nb, cap, K)),
            np.empty((nb, cap, L), dtype=np.int32), np.empty((nb, cap), dtype=np.int32),
            np.zeros((nb, T), dtype=np.int64), np.zeros((nb, T), dtype=np.uint64),
            np.zeros((nb, 3), dtype=np.int64),
            np.zeros((nb, data[19] + 1 if nb > 1 else 1, 2), dtype=np.int64))


@jit()
def reset_work_herded(data, work, b, x0):
    """Slab ``b`` for a new chain: an empty key table and zero tallies."""
    work[14][b, :] = 0
    work[16][b, :] = 0
    work[17][b, 0, :] = 0


@jit()
def chain_done_herded(data, work, b, j):
    """Add the tallies of slab ``b``'s chain at its last observation ``j`` to the run's."""
    tally = data[20]
    hist = work[17]
    if hist.shape[1] > 1:
        tally[0] += hist[b, j, 0]
        tally[1] += hist[b, j, 1]
    else:  # simulated up to j exactly
        tally[0] += work[16][b, 0]
        tally[1] += work[16][b, 1]


#: The chain driver compiled for the adaptive-birth problem with the herded draw.
run_chains_herded = make_driver("adaptive_birth_herded", alloc_work_herded, reset_work_herded,
                                sweep_herded, chain_done=chain_done_herded)

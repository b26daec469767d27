"""numba row updates of the multi-sensor Gibbs samplers (clean inputs only).

Twins, operation for operation, of :mod:`rankedassign.multisensor.reference` (the
specification of record; read its docstring for the state encoding, the order of the uniforms
and the edge cases). The three functions the generic chain driver needs are
:func:`alloc_work`, :func:`reset_work` and :func:`sweep`; one sweep function serves every
method (the method is a code in ``data``), so one driver is compiled for all of them.

``data`` (built by :func:`rankedassign.multisensor.prepare.prepare_data`)::

    params  int64[4]          method code, random scan (0/1), P, V
    n_meas  int64[V]          M_v
    strides int64[V]          C-order strides of the tuple axes (M_1+1, ..., M_V+1)
    Wd, ld  float64[P]        shifted weight / log-weight of dead
    Wa, la  float64[P, T]     shifted / log eta of every tuple (T = prod(M_v+1); exact and
                              componentwise, the latter collapsed; (P, 0) for MM)
    Th, lth float64[P, V, K]  shifted / log theta_n^(v)(j), K = max M_v + 1 (MM; padding 0/-inf)
    las     float64[P]        alpha * log s_n
    Ea, Ed  float64[P]        shifted alive prefactor and dead weight (MM exclusion)
    qdead   float64[P]        Q_n of MM-fixed

``work`` (one slab per chain simulated at once, leading dimension ``nb``)::

    occ     int64[nb, V, K]   rows holding measurement j of sensor v
    avail   int64[nb, V, K]   A_n^(v) of the row being updated (first navail entries)
    navail  int64[nb, V]
    idx     int64[nb, V]      odometer over the product of the A_n^(v)
    wbuf    float64[nb, C]    candidate weights (C = max(1 + T, K))
    lbuf    float64[nb, C]    candidate log-weights (for the underflow fall-back)
    perm    int64[nb, P]      row order of the sweep
    row     int64[nb, V]      the updated row (gamma values)

References
----------
.. [1] B.-N. Vo, B.-T. Vo, M. Beard, "Multi-Sensor Multi-Object Tracking with the Generalized
   Labeled Multi-Bernoulli Filter", IEEE Trans. Signal Process. 67(23):5952-5967, 2019.
"""

from __future__ import annotations

import numpy as np

from ..engine._kernels import make_driver, next_uniform
from ..numba_options import jit

EXACT, MM, MM_FIXED, COMPONENTWISE = 0, 1, 2, 3


@jit()
def pick(w, b, n, total, u):
    """Twin of :func:`rankedassign.multisensor.reference.pick` on ``w[b, :n]``.

    Examples
    --------
    >>> import numpy as np
    >>> int(pick(np.array([[0.5, 0.0, 0.5]]), 0, 3, 1.0, 0.75))
    2
    """
    target = u * total
    acc = 0.0
    last = -1
    for k in range(n):
        wk = w[b, k]
        if wk > 0.0:
            acc += wk
            last = k
            if acc > target:
                return k
    return last


@jit()
def draw(w, lw, b, n, u):
    """Twin of :func:`rankedassign.multisensor.reference.draw` on ``w[b, :n]``, ``lw[b, :n]``.

    Overwrites ``w[b]`` on the underflow fall-back.

    Examples
    --------
    >>> import numpy as np
    >>> int(draw(np.zeros((1, 2)), np.array([[-800.0, -801.0]]), 0, 2, 0.5))
    0
    """
    total = 0.0
    for k in range(n):
        total += w[b, k]
    if total > 0.0:
        return pick(w, b, n, total, u)
    m = -np.inf
    for k in range(n):
        if lw[b, k] > m:
            m = lw[b, k]
    if m == -np.inf:
        return -1
    for k in range(n):
        w[b, k] = np.exp(lw[b, k] - m)
    total = 0.0
    for k in range(n):
        total += w[b, k]
    return pick(w, b, n, total, u)


@jit()
def alloc_work(data, nb):
    """Work arrays for ``nb`` chains simulated at once (see the module docstring)."""
    params, n_meas, strides, Wd, ld, Wa, la, Th, lth, las, Ea, Ed, qdead = data
    P = params[2]
    V = params[3]
    K = 1
    for v in range(V):
        if n_meas[v] + 1 > K:
            K = n_meas[v] + 1
    C = max(1 + Wa.shape[1], K)
    return (
        np.zeros((nb, V, K), dtype=np.int64),
        np.zeros((nb, V, K), dtype=np.int64),
        np.zeros((nb, V), dtype=np.int64),
        np.zeros((nb, V), dtype=np.int64),
        np.zeros((nb, C), dtype=np.float64),
        np.zeros((nb, C), dtype=np.float64),
        np.zeros((nb, max(P, 1)), dtype=np.int64),
        np.zeros((nb, V), dtype=np.int64),
    )


@jit()
def reset_work(data, work, b, x0):
    """Slab ``b`` to the start state ``x0``: the occupancy table of ``x0``."""
    V = data[0][3]
    occ = work[0]
    occ[b, :, :] = 0
    for i in range(x0.shape[0]):
        val = x0[i]
        if val >= 2:
            occ[b, i % V, val - 1] += 1


@jit()
def _mm_log_alive(lth, las, avail, navail, b, n, V):
    """``log(s_n^alpha prod_v sum_{j in A_n^(v)} theta_n^(v)(j))`` on exact log-weights (the
    MM underflow fall-back)."""
    lal = las[n]
    for v in range(V):
        m = -np.inf
        for c in range(navail[b, v]):
            lw = lth[n, v, avail[b, v, c]]
            if lw > m:
                m = lw
        if m == -np.inf:
            return -np.inf
        s = 0.0
        for c in range(navail[b, v]):
            s += np.exp(lth[n, v, avail[b, v, c]] - m)
        lal += m + np.log(s)
    return lal


@jit(inline="always")
def sweep(data, work, b, zkeys, state, h, rs):
    """One sweep over all rows of slab ``b``, in place on ``state``; return the new hash.

    Parameters
    ----------
    data : tuple
        Prepared arrays (module docstring).
    work : tuple
        Work arrays from :func:`alloc_work`; slab ``b`` is used and kept up to date.
    b : int
        Slab index.
    zkeys : ndarray, shape (P * V, K), uint64
        Zobrist keys; for every position ``l`` whose value changes from ``a`` to ``c``,
        ``h ^= zkeys[l, a] ^ zkeys[l, c]``.
    state : ndarray, shape (P * V,), int32
        State (``gamma + 1``), updated in place.
    h : uint64
        Zobrist hash of ``state``.
    rs : ndarray, shape (1,), uint64
        The chain's stream state.

    Returns
    -------
    uint64
        The hash of the updated state.

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign.engine._kernels import zobrist_keys
    >>> from rankedassign.multisensor.prepare import prepare_data
    >>> class Stub:
    ...     n_rows, n_sensors, n_meas = 1, 2, (1, 1)
    ...     log_eta_dead = np.array([-50.0]); log_eta_alive = np.full((1, 2, 2), -50.0)
    ...     log_s = None; log_theta = None
    >>> Stub.log_eta_alive[0, 1, 1] = 0.0
    >>> data = prepare_data(Stub(), "exact", "systematic", 1)
    >>> work = alloc_work(data, 1)
    >>> x = np.ones(2, dtype=np.int32)
    >>> reset_work(data, work, 0, x)
    >>> h = sweep(data, work, 0, zobrist_keys(2, 3, np.uint64(1)), x, np.uint64(0),
    ...           np.zeros(1, dtype=np.uint64))
    >>> x.tolist()
    [2, 2]
    """
    params, n_meas, strides, Wd, ld, Wa, la, Th, lth, las, Ea, Ed, qdead = data
    occ, avail, navail, idx, wbuf, lbuf, perm, row = work
    method = params[0]
    P = params[2]
    V = params[3]
    for t in range(P):
        perm[b, t] = t
    if params[1]:  # random scan: Fisher-Yates from the identity
        for t in range(P - 1, 0, -1):
            j = np.int64(next_uniform(rs) * (t + 1))
            if j > t:
                j = t
            tmp = perm[b, t]
            perm[b, t] = perm[b, j]
            perm[b, j] = tmp
    for t in range(P):
        n = perm[b, t]
        for v in range(V):  # A_n^(v): missed, and measurements free of the other rows
            own = state[n * V + v] - 1
            avail[b, v, 0] = 0
            c = 1
            for j in range(1, n_meas[v] + 1):
                if occ[b, v, j] == 0 or own == j:
                    avail[b, v, c] = j
                    c += 1
            navail[b, v] = c
        # Row update into row[b] (ok = False: no positive candidate, the row stays). The draws
        # are written out (sum, then the inverse-CDF loop of pick) rather than called: a call
        # per draw costs more than the draw on small problems. The rare underflow fall-back is
        # a call to draw.
        ok = True
        if method == EXACT:
            # spec eq. 2.1: dead, then A_1 x ... x A_V in C order (odometer, last sensor fastest)
            wbuf[b, 0] = Wd[n]
            lbuf[b, 0] = ld[n]
            nc = 1
            for v in range(V):
                idx[b, v] = 0
            while True:
                off = 0
                for v in range(V):
                    off += avail[b, v, idx[b, v]] * strides[v]
                wbuf[b, nc] = Wa[n, off]
                lbuf[b, nc] = la[n, off]
                nc += 1
                v = V - 1
                while v >= 0:
                    idx[b, v] += 1
                    if idx[b, v] < navail[b, v]:
                        break
                    idx[b, v] = 0
                    v -= 1
                if v < 0:
                    break
            total = 0.0
            for k in range(nc):
                total += wbuf[b, k]
            u = next_uniform(rs)
            k = -1
            if total > 0.0:
                target = u * total
                acc = 0.0
                for kk in range(nc):
                    wk = wbuf[b, kk]
                    if wk > 0.0:
                        acc += wk
                        k = kk
                        if acc > target:
                            break
            else:
                k = draw(wbuf, lbuf, b, nc, u)
            if k < 0:
                ok = False
            elif k == 0:
                for v in range(V):
                    row[b, v] = -1
            else:
                r = k - 1  # mixed-radix digits of the candidate, last sensor fastest
                for v in range(V - 1, -1, -1):
                    row[b, v] = avail[b, v, r % navail[b, v]]
                    r //= navail[b, v]
        elif method == COMPONENTWISE:
            # spec §2.4: each component from its exact conditional under eta', in turn
            for v in range(V):
                row[b, v] = state[n * V + v] - 1
            for v in range(V):
                base = 0
                for w in range(V):
                    if w != v:
                        base += row[b, w] * strides[w]
                na = navail[b, v]
                sv = strides[v]
                total = 0.0
                for c in range(na):
                    total += Wa[n, base + avail[b, v, c] * sv]
                u = next_uniform(rs)
                k = -1
                if total > 0.0:
                    target = u * total
                    acc = 0.0
                    for c in range(na):
                        wk = Wa[n, base + avail[b, v, c] * sv]
                        if wk > 0.0:
                            acc += wk
                            k = c
                            if acc > target:
                                break
                else:
                    for c in range(na):
                        off = base + avail[b, v, c] * sv
                        wbuf[b, c] = Wa[n, off]
                        lbuf[b, c] = la[n, off]
                    k = draw(wbuf, lbuf, b, na, u)
                if k >= 0:
                    row[b, v] = avail[b, v, k]
        else:
            # spec §3.2: dead with probability Q_n, else independent per-sensor draws
            u = next_uniform(rs)
            if method == MM_FIXED:
                dead = u < qdead[n]
            else:
                # alive mass s_n^alpha prod_v sum_{j in A_n^(v)} theta_n^(v)(j), shifted
                alive = Ea[n]
                for v in range(V):
                    sv = 0.0
                    for c in range(navail[b, v]):
                        sv += Th[n, v, avail[b, v, c]]
                    alive *= sv
                wd = Ed[n]
                target = u * (wd + alive)
                k = -1
                acc = 0.0
                if wd > 0.0:
                    acc += wd
                    k = 0
                if not (k == 0 and acc > target) and alive > 0.0:
                    acc += alive
                    k = 1
                if k < 0:  # both underflowed: the same decision on exact log-weights
                    wbuf[b, 0] = 0.0
                    wbuf[b, 1] = 0.0
                    lbuf[b, 0] = ld[n]
                    lbuf[b, 1] = _mm_log_alive(lth, las, avail, navail, b, n, V)
                    k = draw(wbuf, lbuf, b, 2, u)
                    if k < 0:
                        ok = False
                dead = k == 0
            if ok and dead:
                for v in range(V):
                    row[b, v] = -1
            elif ok:
                for v in range(V):  # j ~ theta_n^(v)(j) 1[j in A_n^(v)], one uniform each
                    na = navail[b, v]
                    total = 0.0
                    for c in range(na):
                        total += Th[n, v, avail[b, v, c]]
                    u = next_uniform(rs)
                    k = -1
                    if total > 0.0:
                        target = u * total
                        acc = 0.0
                        for c in range(na):
                            wk = Th[n, v, avail[b, v, c]]
                            if wk > 0.0:
                                acc += wk
                                k = c
                                if acc > target:
                                    break
                    else:
                        for c in range(na):
                            wbuf[b, c] = Th[n, v, avail[b, v, c]]
                            lbuf[b, c] = lth[n, v, avail[b, v, c]]
                        k = draw(wbuf, lbuf, b, na, u)
                    if k < 0:  # mm-fixed only: the alive branch is infeasible here
                        if ld[n] > -np.inf:
                            for w in range(V):
                                row[b, w] = -1
                        else:
                            ok = False
                        break
                    row[b, v] = avail[b, v, k]
        if not ok:
            continue
        for v in range(V):
            pos = n * V + v
            old = np.int64(state[pos])
            new = row[b, v] + 1
            if old != new:
                if old >= 2:
                    occ[b, v, old - 1] -= 1
                if new >= 2:
                    occ[b, v, new - 1] += 1
                state[pos] = new
                h = h ^ zkeys[pos, old] ^ zkeys[pos, new]
    return h


@jit()
def run_sweeps(data, zkeys, x0, seed, n_sweeps):
    """``n_sweeps`` sweeps of one chain from ``x0`` with stream state ``seed`` (no unique set).

    The sweep kernel alone, for timing it and for tests that need many independent chains;
    the samplers run it through the generic chain driver instead.

    Returns
    -------
    state : ndarray, shape (P * V,), int32
        The state after the last sweep.
    h : uint64
        Its Zobrist hash.

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign.engine._kernels import zobrist_keys
    >>> from rankedassign.multisensor.prepare import prepare_data
    >>> class Stub:
    ...     n_rows, n_sensors, n_meas = 1, 2, (1, 1)
    ...     log_eta_dead = np.array([-50.0]); log_eta_alive = np.full((1, 2, 2), -50.0)
    ...     log_s = None; log_theta = None
    >>> Stub.log_eta_alive[0, 1, 1] = 0.0
    >>> data = prepare_data(Stub(), "exact", "systematic", 1)
    >>> x0 = np.ones(2, dtype=np.int32)
    >>> state, h = run_sweeps(data, zobrist_keys(2, 3, np.uint64(1)), x0, np.uint64(0), 3)
    >>> state.tolist()
    [2, 2]
    """
    work = alloc_work(data, 1)
    state = x0.copy()
    reset_work(data, work, 0, state)
    h = np.uint64(0)
    for pos in range(state.shape[0]):
        h ^= zkeys[pos, state[pos]]
    rs = np.empty(1, dtype=np.uint64)
    rs[0] = seed
    for _ in range(n_sweeps):
        h = sweep(data, work, 0, zkeys, state, h, rs)
    return state, h


#: The chain driver compiled for the multi-sensor problem (:func:`.._chains.make_driver`).
run_chains = make_driver("multisensor", alloc_work, reset_work, sweep)

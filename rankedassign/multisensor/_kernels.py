"""numba row updates of the multi-sensor Gibbs samplers (clean inputs only).

Twins, operation for operation, of :mod:`rankedassign.multisensor.reference` (the
specification of record; read its docstring for the state encoding, the order of the uniforms
and the edge cases). The three functions the generic chain driver needs are
:func:`alloc_work`, :func:`reset_work` and :func:`sweep`; one sweep function serves every
method (the method is a code in ``data``), so one driver is compiled for all of them.

``data`` is the :class:`~rankedassign.multisensor.prepare.MultiSensorData` of
:func:`rankedassign.multisensor.prepare.prepare_data` (the method, the scan order, ``P`` and
``V`` are named fields of it); ``work`` is a :class:`MultiSensorWork`, one slab per chain
simulated at once.

References
----------
.. [1] B.-N. Vo, B.-T. Vo, M. Beard, "Multi-Sensor Multi-Object Tracking with the Generalized
   Labeled Multi-Bernoulli Filter", IEEE Trans. Signal Process. 67(23):5952-5967, 2019.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ..engine._kernels import (
    KeyTable,
    alloc_key_table,
    herd_lookup,
    herd_pick,
    key_table_done,
    key_table_sweep_done,
    make_driver,
    next_uniform,
    reset_key_table,
)
from ..engine.records import record
from ..numba_options import jit

EXACT, MM, MM_FIXED, COMPONENTWISE = 0, 1, 2, 3


@jit()
def pick(w, b, n, total, u):
    """Twin of :func:`rankedassign.multisensor.reference.pick` on ``w[b, :n]``.

    Parameters
    ----------
    w : ndarray of float64, shape (nb, C)
        Candidate weights, slab by slab.
    b : int
        The slab.
    n : int
        Candidates (``n <= C``).
    total : float
        ``sum(w[b, :n])``, positive.
    u : float
        A uniform in ``[0, 1)``.

    Returns
    -------
    int
        The first candidate whose running sum exceeds ``u * total``, else the last one of
        positive weight.

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

    Parameters
    ----------
    w, b, n, u
        As in :func:`pick` (``w`` may sum to 0: underflow).
    lw : ndarray of float64, shape (nb, C)
        The candidates' log-weights, for the fall-back.

    Returns
    -------
    int
        The candidate drawn, ``-1`` when every log-weight is ``-inf``.

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


class MultiSensorWork(NamedTuple):
    """Workspace of ``nb`` chains (:func:`alloc_work`), leading dimension ``nb``.

    ``K = max_v M_v + 1``, ``C = max(1 + T, K, 2)`` candidates of the widest draw.

    Attributes
    ----------
    occ : ndarray, shape (nb, V, K), int64
        Rows holding measurement ``j`` of sensor ``v``.
    avail : ndarray, shape (nb, V, K), int64
        ``A_n^(v)`` of the row being updated (the first ``navail`` entries).
    navail : ndarray, shape (nb, V), int64
        Their number.
    idx : ndarray, shape (nb, V), int64
        Odometer over the product of the ``A_n^(v)``.
    wbuf, lbuf : ndarray, shape (nb, C), float64
        Candidate weights and log-weights (the latter for the underflow fall-back).
    perm : ndarray, shape (nb, max(P, 1)), int64
        Row order of the sweep.
    row : ndarray, shape (nb, V), int64
        The updated row (``gamma`` values).
    """

    occ: np.ndarray
    avail: np.ndarray
    navail: np.ndarray
    idx: np.ndarray
    wbuf: np.ndarray
    lbuf: np.ndarray
    perm: np.ndarray
    row: np.ndarray


@jit()
def _widths(data):
    """``K = max_v M_v + 1`` and ``C = max(1 + T, K, 2)`` of the workspace.

    Parameters
    ----------
    data : MultiSensorData
        The call's data (``T`` is ``data.Wa.shape[1]``, 0 for the MM methods).

    Returns
    -------
    (int, int)
        ``K`` and ``C``.
    """
    n_meas = data.n_meas
    K = 1
    for v in range(data.V):
        if n_meas[v] + 1 > K:
            K = n_meas[v] + 1
    return K, max(1 + data.Wa.shape[1], K, 2)  # MM's dead/alive draw has two candidates


@jit()
def alloc_work(data, nb):
    """Work arrays for ``nb`` chains simulated at once (a :class:`MultiSensorWork`).

    Parameters
    ----------
    data : MultiSensorData
        The call's data.
    nb : int
        Chains.

    Returns
    -------
    MultiSensorWork
        Zero arrays of the shapes listed there.
    """
    V = data.V
    K, C = _widths(data)
    return MultiSensorWork(
        occ=np.zeros((nb, V, K), dtype=np.int64), avail=np.zeros((nb, V, K), dtype=np.int64),
        navail=np.zeros((nb, V), dtype=np.int64), idx=np.zeros((nb, V), dtype=np.int64),
        wbuf=np.zeros((nb, C), dtype=np.float64), lbuf=np.zeros((nb, C), dtype=np.float64),
        perm=np.zeros((nb, max(data.P, 1)), dtype=np.int64),
        row=np.zeros((nb, V), dtype=np.int64))


@jit()
def reset_work(data, work, b, x0):
    """Slab ``b`` to the start state ``x0``: the occupancy table of ``x0``.

    Parameters
    ----------
    data : MultiSensorData
        The call's data.
    work : MultiSensorWork
        ``occ[b]`` rebuilt.
    b : int
        The slab.
    x0 : ndarray of int32, shape (P * V,)
        The start state (``gamma + 1``; a value ``>= 2`` holds measurement ``value - 1``).
    """
    V = data.V
    occ = work.occ
    occ[b, :, :] = 0
    for i in range(x0.shape[0]):
        val = x0[i]
        if val >= 2:
            occ[b, i % V, val - 1] += 1


@jit()
def _mm_log_alive(lth, las, avail, navail, b, n, V):
    """``log(s_n^alpha prod_v sum_{j in A_n^(v)} theta_n^(v)(j))`` on exact log-weights (the
    MM underflow fall-back).

    Parameters
    ----------
    lth : ndarray of float64, shape (P, V, K)
        ``log theta_n^(v)(j)``.
    las : ndarray of float64, shape (P,)
        ``alpha log s_n``.
    avail : ndarray of int64, shape (nb, V, K)
        The available entries ``A_n^(v)`` (:func:`_available`).
    navail : ndarray of int64, shape (nb, V)
        Their numbers.
    b : int
        The slab.
    n : int
        The row.
    V : int
        Sensors.

    Returns
    -------
    float
        The log-weight, ``-inf`` when some sensor has no available entry of finite weight.
    """
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
def _scan_order(data, work, b, rs):
    """Slab ``b``'s row order ``perm[b]``: ``0..P-1``, for the random scan shuffled by
    Fisher-Yates from the identity (``t = P-1..1``: ``j = min(floor(u (t + 1)), t)``).

    Parameters
    ----------
    data : MultiSensorData
        The call's data (``P``, ``random_scan``).
    work : MultiSensorWork
        ``perm[b]`` written.
    b : int
        The slab.
    rs : ndarray of uint64, shape (1,)
        The chain's stream state (``P - 1`` uniforms for the random scan, none otherwise).
    """
    perm = work.perm
    P = data.P
    for t in range(P):
        perm[b, t] = t
    if data.random_scan:
        for t in range(P - 1, 0, -1):
            j = np.int64(next_uniform(rs) * (t + 1))
            if j > t:
                j = t
            tmp = perm[b, t]
            perm[b, t] = perm[b, j]
            perm[b, j] = tmp


@jit(inline="always")
def _available(data, work, b, state, n):
    """``A_n^(v)`` of row ``n`` for every sensor into ``avail[b]``, ``navail[b]``: missed, and
    the measurements free of the other rows.

    Parameters
    ----------
    data : MultiSensorData
        The call's data.
    work : MultiSensorWork
        ``avail[b]`` and ``navail[b]`` written (entry 0 is always missed, 0).
    b : int
        The slab.
    state : ndarray of int32, shape (P * V,)
        The current state (``gamma + 1``).
    n : int
        The row.
    """
    n_meas, occ, avail, navail = data.n_meas, work.occ, work.avail, work.navail
    V = data.V
    for v in range(V):
        own = state[n * V + v] - 1
        avail[b, v, 0] = 0
        c = 1
        for j in range(1, n_meas[v] + 1):
            if occ[b, v, j] == 0 or own == j:
                avail[b, v, c] = j
                c += 1
        navail[b, v] = c


@jit()
def _exact_logs(ld, la, strides, avail, navail, idx, lbuf, b, n, V):
    """The log-weights of row ``n``'s exact candidates into ``lbuf[b]``, in the order of
    :func:`_row_exact` (dead, then ``A_1 x ... x A_V`` in C order): its underflow fall-back,
    so that the common case gathers one table, not two.

    Parameters
    ----------
    ld : ndarray of float64, shape (P,)
        The dead log-weights.
    la : ndarray of float64, shape (P, prod_v (M_v + 1))
        The alive log-weights, flat.
    strides : ndarray of int64, shape (V,)
        The flat table's strides.
    avail, navail : ndarray of int64
        As :func:`_available` left them for row ``n``.
    idx : ndarray of int64, shape (nb, V)
        The odometer's scratch (overwritten).
    lbuf : ndarray of float64, shape (nb, C)
        ``lbuf[b]`` written.
    b, n, V : int
        The slab, the row and the number of sensors.
    """
    lbuf[b, 0] = ld[n]
    nc = 1
    for v in range(V):
        idx[b, v] = 0
    while True:
        off = 0
        for v in range(V):
            off += avail[b, v, idx[b, v]] * strides[v]
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


# The row updates below write the new row into row[b] and return False when no candidate has
# weight (the row stays). Their draws are written out (sum, then the inverse-CDF loop of pick)
# rather than called: a call per draw costs more than the draw on small problems; the rare
# underflow fall-back is a call to draw.
@jit(inline="always")
def _row_exact(data, work, b, n, rs):
    """Row ``n`` from its exact conditional (spec eq. 2.1): dead, then ``A_1 x ... x A_V`` in
    C order (an odometer, the last sensor fastest).

    Parameters
    ----------
    data : MultiSensorData
        The call's data (exact method).
    work : MultiSensorWork
        ``avail[b]`` as :func:`_available` left it; the new row written to ``row[b]``.
    b : int
        The slab.
    n : int
        The row.
    rs : ndarray of uint64, shape (1,)
        The chain's stream state (one uniform).

    Returns
    -------
    bool
        False when no candidate has weight (the row stays).
    """
    V, strides, Wd, Wa = data.V, data.strides, data.Wd, data.Wa
    avail, navail, idx, wbuf, row = work.avail, work.navail, work.idx, work.wbuf, work.row
    # The candidates' weights in C order and their sum, in that order, in one pass: the odometer
    # runs over sensors 0..V-2 and the last sensor's entries are the inner loop (the same
    # candidates, offsets and additions as one odometer over all V). The log-weights are
    # gathered only for the underflow fall-back (_exact_logs).
    wbuf[b, 0] = Wd[n]
    total = 0.0
    total += wbuf[b, 0]
    nc = 1
    vl = V - 1
    nl = navail[b, vl]
    sl = strides[vl]
    for v in range(V):
        idx[b, v] = 0
    while True:
        base = 0
        for v in range(vl):
            base += avail[b, v, idx[b, v]] * strides[v]
        for c in range(nl):
            w = Wa[n, base + avail[b, vl, c] * sl]
            wbuf[b, nc] = w
            total += w
            nc += 1
        v = vl - 1
        while v >= 0:
            idx[b, v] += 1
            if idx[b, v] < navail[b, v]:
                break
            idx[b, v] = 0
            v -= 1
        if v < 0:
            break
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
        _exact_logs(data.ld, data.la, strides, avail, navail, idx, work.lbuf, b, n, V)
        k = draw(wbuf, work.lbuf, b, nc, u)
    if k < 0:
        return False
    if k == 0:
        for v in range(V):
            row[b, v] = -1
    else:
        r = k - 1  # mixed-radix digits of the candidate, last sensor fastest
        for v in range(V - 1, -1, -1):
            row[b, v] = avail[b, v, r % navail[b, v]]
            r //= navail[b, v]
    return True


@jit(inline="always")
def _row_componentwise(data, work, b, state, n, rs):
    """Row ``n``'s components, each from its exact conditional under ``eta'`` in turn
    (spec §2.4).

    Parameters
    ----------
    data, work, b, n
        As in :func:`_row_exact` (componentwise method).
    state : ndarray of int32, shape (P * V,)
        The current state (``gamma + 1``), row ``n``'s start.
    rs : ndarray of uint64, shape (1,)
        The chain's stream state (one uniform per sensor).

    Returns
    -------
    bool
        Always True; a sensor without a candidate keeps its value.
    """
    V, strides, Wa, la = data.V, data.strides, data.Wa, data.la
    avail, navail, wbuf, lbuf, row = work.avail, work.navail, work.wbuf, work.lbuf, work.row
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
    return True


@jit(inline="always")
def _row_mm(data, work, b, n, rs):
    """Row ``n`` by MM (spec §3.2): dead with probability ``Q_n``, else independent
    per-sensor draws ``j ~ theta_n^(v)(j) 1[j in A_n^(v)]``.

    Parameters
    ----------
    data, work, b, n
        As in :func:`_row_exact` (the MM methods).
    rs : ndarray of uint64, shape (1,)
        The chain's stream state (one uniform for dead or alive, then one per sensor).

    Returns
    -------
    bool
        False when the row stays.
    """
    V, ld, Th, lth, las = data.V, data.ld, data.Th, data.lth, data.las
    avail, navail, wbuf, lbuf, row = work.avail, work.navail, work.wbuf, work.lbuf, work.row
    u = next_uniform(rs)
    if data.method == MM_FIXED:
        dead = u < data.qdead[n]
    else:
        # alive mass s_n^alpha prod_v sum_{j in A_n^(v)} theta_n^(v)(j), shifted
        alive = data.Ea[n]
        for v in range(V):
            sv = 0.0
            for c in range(navail[b, v]):
                sv += Th[n, v, avail[b, v, c]]
            alive *= sv
        wd = data.Ed[n]
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
            k = draw(wbuf, lbuf, b, np.int64(2), u)  # (a literal: a second signature)
            if k < 0:
                return False
        dead = k == 0
    if dead:
        for v in range(V):
            row[b, v] = -1
        return True
    for v in range(V):  # one uniform each
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
                return True
            return False
        row[b, v] = avail[b, v, k]
    return True


@jit(inline="always")
def _write_row(data, work, b, zkeys, state, n, h):
    """Row ``n``'s new values ``row[b]`` into ``state``, the occupancy table and the hash;
    return the hash.

    Parameters
    ----------
    data : MultiSensorData
        The call's data.
    work : MultiSensorWork
        ``row[b]`` read (``gamma`` values), ``occ[b]`` updated.
    b : int
        The slab.
    zkeys : ndarray of uint64, shape (P * V, K)
        Zobrist keys.
    state : ndarray of int32, shape (P * V,)
        Updated in place (``gamma + 1``).
    n : int
        The row.
    h : np.uint64
        The hash of ``state`` before.

    Returns
    -------
    np.uint64
    """
    V = data.V
    occ, row = work.occ, work.row
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


@jit(inline="always")
def sweep(data, work, b, zkeys, state, h, rs):
    """One sweep over all rows of slab ``b``, in place on ``state``; return the new hash.

    Parameters
    ----------
    data : MultiSensorData
        Prepared arrays (module docstring).
    work : MultiSensorWork
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
    method = data.method
    _scan_order(data, work, b, rs)
    for t in range(data.P):
        n = work.perm[b, t]
        _available(data, work, b, state, n)
        if method == EXACT:
            ok = _row_exact(data, work, b, n, rs)
        elif method == COMPONENTWISE:
            ok = _row_componentwise(data, work, b, state, n, rs)
        else:
            ok = _row_mm(data, work, b, n, rs)
        if ok:
            h = _write_row(data, work, b, zkeys, state, n, h)
    return h


@jit()
def run_sweeps(data, zkeys, x0, seed, n_sweeps):
    """``n_sweeps`` sweeps of one chain from ``x0`` with stream state ``seed`` (no unique set).

    The sweep kernel alone, for timing it and for tests that need many independent chains;
    the samplers run it through the generic chain driver instead.

    Parameters
    ----------
    data : MultiSensorData
        The call's data.
    zkeys : ndarray of uint64, shape (P * V, K)
        Zobrist keys.
    x0 : ndarray of int32, shape (P * V,)
        The start state (not modified).
    seed : np.uint64
        The stream state before the first uniform.
    n_sweeps : int
        Sweeps.

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
    work = alloc_work(data, np.int64(1))  # (int64 as in the driver: one signature each)
    state = x0.copy()
    reset_work(data, work, np.int64(0), state)
    h = np.uint64(0)
    for pos in range(state.shape[0]):
        h ^= zkeys[pos, state[pos]]
    rs = np.empty(1, dtype=np.uint64)
    rs[0] = seed
    h = _sweeps(data, work, zkeys, state, h, rs, n_sweeps)
    return state, h


@jit(nrt=False)
def _sweeps(data, work, zkeys, state, h, rs, n_sweeps):
    """``n_sweeps`` sweeps of slab 0 (:func:`run_sweeps`); the loop the sweep is written into
    runs without reference counting, as the chain driver's do
    (:func:`rankedassign.engine._kernels.make_driver`).

    Parameters
    ----------
    data : MultiSensorData
        The call's data.
    work : MultiSensorWork
        One slab.
    zkeys, state, h, rs
        As in :func:`sweep`.
    n_sweeps : int
        Sweeps.

    Returns
    -------
    np.uint64
        The hash of the final state.
    """
    for _ in range(n_sweeps):
        h = sweep(data, work, 0, zkeys, state, h, rs)
    return h


#: The chain driver compiled for the multi-sensor problem (:func:`.._chains.make_driver`).
run_chains = make_driver("multisensor", alloc_work, reset_work, sweep, work=MultiSensorWork)


# ---------------------------------------------------------------------------- herded draw
# Twins of the herded row updates of rankedassign.multisensor.reference (herd_sweep). The
# herded driver's data is a MultiSensorHerdedData (the Gibbs data's fields followed by the
# herded draw's: rankedassign.multisensor.prepare.herd_inputs; one flat record, so that the
# Gibbs phases read it as they read MultiSensorData), its workspace a MultiSensorHerdedWork.


@jit(inline="always")
def _row_key(data, work, b, state, n, vlo, vhi):
    """Row ``n``'s key vector into ``keyv[b]`` (twin of the reference's ``herd_key``): the
    state with row ``n`` as -1 (full), or the codes ``v K + j`` of the gated measurements of
    sensors ``vlo..vhi-1`` that other rows hold (shared).

    Parameters
    ----------
    data : MultiSensorHerdedData
        The call's data (``key_mode`` 0 full, else shared; ``gate`` (P, V, Kc) bool).
    work : MultiSensorHerdedWork
        ``keyv[b]`` written, padded with -1.
    b : int
        The slab.
    state : ndarray of int32, shape (P * V,)
        The current state (``gamma + 1``).
    n : int
        The row.
    vlo, vhi : int
        The sensors of the shared key.
    """
    n_meas = data.n_meas
    P = data.P
    V = data.V
    gate = data.gate
    Kc = gate.shape[2]
    occ, keyv = work.occ, work.keyv[b]
    c = 0
    if data.key_mode == 0:
        for r in range(P * V):
            keyv[r] = -1 if r // V == n else state[r]
        c = P * V
    else:
        for v in range(vlo, vhi):
            own = state[n * V + v] - 1
            for j in range(1, n_meas[v] + 1):
                if occ[b, v, j] > 0 and own != j and gate[n, v, j]:
                    keyv[c] = v * Kc + j
                    c += 1
    for r in range(c, keyv.shape[0]):
        keyv[r] = -1


@jit(inline="always")
def _component_key(data, work, b, state, n, v, off):
    """Component ``v`` of row ``n``'s key vector (twin of the reference's
    ``_component_key``); ``off`` is the tuple offset of the row's other components.

    Parameters
    ----------
    data, work, b, state, n
        As in :func:`_row_key` (``row[b]`` holds the row's current components).
    v : int
        The component (sensor).
    off : int
        Offset in the flat tuple index of the row's other components.
    """
    n_meas, strides, la = data.n_meas, data.strides, data.la
    P = data.P
    V = data.V
    Kc = data.gate.shape[2]
    occ, row, keyv = work.occ, work.row, work.keyv[b]
    c = 0
    if data.key_mode == 0:
        for r in range(P * V):
            keyv[r] = state[r]
        for w in range(V):
            keyv[n * V + w] = -1 if w == v else row[b, w] + 1
        c = P * V
    else:
        for w in range(V):
            if w != v:
                keyv[c] = row[b, w]
                c += 1
        own = state[n * V + v] - 1
        for j in range(1, n_meas[v] + 1):
            if occ[b, v, j] > 0 and own != j and la[n, off + j * strides[v]] > -np.inf:
                keyv[c] = v * Kc + j
                c += 1
    for r in range(c, keyv.shape[0]):
        keyv[r] = -1


@jit(inline="always")
def _herd_stage(data, work, b, rid, nc, K, rs):
    """One herded draw (twin of the reference's ``_herd_stage``) over ``K`` candidates, the
    ``nc`` available ones in ``wbuf/lbuf/cand[b]``, key in ``keyv[b]``: the candidate, -1 if
    none has weight, or the Gibbs draw of the same lists when the table is full.

    Parameters
    ----------
    data : MultiSensorHerdedData
        The call's data (``capacity``, ``init_mode``).
    work : MultiSensorHerdedWork
        ``wbuf[b]``, ``lbuf[b]``, ``cand[b]`` the available candidates' weights,
        log-weights and full indices, ``keyv[b]`` the key; ``p[b]`` and the key table
        updated.
    b : int
        The slab.
    rid : int
        The key's row id (``n (V + 1) + stage``).
    nc : int
        Available candidates.
    K : int
        Width of the full candidate range.
    rs : ndarray of uint64, shape (1,)
        The chain's stream state.

    Returns
    -------
    int
        The full candidate index drawn, or -1.
    """
    wbuf, lbuf, cand, p, keyv = work.wbuf, work.lbuf, work.cand, work.p[b], work.keyv[b]
    for k in range(K):
        p[k] = 0.0
    total = 0.0
    for c in range(nc):
        total += wbuf[b, c]
    if total > 0.0:
        inv = 1.0 / total
        for c in range(nc):
            p[cand[b, c]] = wbuf[b, c] * inv
    else:  # every available weight underflowed: exact weights
        m = -np.inf
        for c in range(nc):
            if lbuf[b, c] > m:
                m = lbuf[b, c]
        if m == -np.inf:
            return -1
        tot = 0.0
        for c in range(nc):
            e = np.exp(lbuf[b, c] - m)
            p[cand[b, c]] = e
            tot += e
        for c in range(nc):
            p[cand[b, c]] = p[cand[b, c]] / tot
    s, new = herd_lookup(rid, keyv, work.cnt[b], data.capacity, work.krow[b], work.kst[b],
                         work.tslot[b], work.thash[b])
    if s < 0:  # the table is full: an ordinary Gibbs draw
        c = draw(wbuf, lbuf, b, nc, next_uniform(rs))
        return -1 if c < 0 else cand[b, c]
    return herd_pick(work.hw[b, s], p, K, new, data.init_mode, rs)


@jit(inline="always")
def _herd_row_exact(data, work, b, state, n, rs):
    """Row ``n`` herded over dead (0) and every tuple (``1 + offset``) into ``row[b]``.

    Parameters
    ----------
    data : MultiSensorHerdedData
        The call's data (exact method).
    work : MultiSensorHerdedWork
        ``avail[b]`` as :func:`_available` left it.
    b : int
        The slab.
    state : ndarray of int32, shape (P * V,)
        The current state (``gamma + 1``).
    n : int
        The row.
    rs : ndarray of uint64, shape (1,)
        The chain's stream state.

    Returns
    -------
    bool
        False when no candidate has weight (the row stays).
    """
    n_meas, strides, Wd, ld, Wa, la = (data.n_meas, data.strides, data.Wd, data.ld, data.Wa,
                                       data.la)
    V = data.V
    avail, navail, idx, wbuf, lbuf, row, cand = (work.avail, work.navail, work.idx, work.wbuf,
                                                 work.lbuf, work.row, work.cand)
    wbuf[b, 0] = Wd[n]
    lbuf[b, 0] = ld[n]
    cand[b, 0] = 0
    nc = 1
    for v in range(V):
        idx[b, v] = 0
    while True:  # A_1 x ... x A_V in C order (odometer, last sensor fastest)
        off = 0
        for v in range(V):
            off += avail[b, v, idx[b, v]] * strides[v]
        wbuf[b, nc] = Wa[n, off]
        lbuf[b, nc] = la[n, off]
        cand[b, nc] = 1 + off
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
    _row_key(data, work, b, state, n, 0, V)
    k = _herd_stage(data, work, b, n * (V + 1), nc, 1 + Wa.shape[1], rs)
    if k < 0:
        return False
    for v in range(V):
        row[b, v] = -1 if k == 0 else (k - 1) // strides[v] % (n_meas[v] + 1)
    return True


@jit(inline="always")
def _herd_row_mm(data, work, b, state, n, rs):
    """Row ``n`` herded as MM does it (dead/alive, then each sensor) into ``row[b]``.

    Parameters
    ----------
    data, work, b, state, n, rs
        As in :func:`_herd_row_exact` (the MM methods).

    Returns
    -------
    bool
        False when the row stays.
    """
    n_meas, ld, Th, lth, las = data.n_meas, data.ld, data.Th, data.lth, data.las
    Ea, Ed, qdead = data.Ea, data.Ed, data.qdead
    V = data.V
    avail, navail, wbuf, lbuf, row, cand, p = (work.avail, work.navail, work.wbuf, work.lbuf,
                                               work.row, work.cand, work.p[b])
    rid = n * (V + 1)
    if data.method == MM_FIXED:  # dead with probability Q_n, whatever the other rows hold
        _row_key(data, work, b, state, n, 0, 0)
        p[0] = qdead[n]
        p[1] = 1.0 - qdead[n]
        s, new = herd_lookup(rid, work.keyv[b], work.cnt[b], data.capacity, work.krow[b],
                             work.kst[b], work.tslot[b], work.thash[b])
        if s < 0:
            dead = next_uniform(rs) < qdead[n]
        else:
            dead = herd_pick(work.hw[b, s], p, 2, new, data.init_mode, rs) == 0
    else:
        alive = Ea[n]
        for v in range(V):
            sv = 0.0
            for c in range(navail[b, v]):
                sv += Th[n, v, avail[b, v, c]]
            alive *= sv
        wbuf[b, 0] = Ed[n]
        wbuf[b, 1] = alive
        lbuf[b, 0] = ld[n]
        lbuf[b, 1] = 0.0 if Ed[n] + alive > 0.0 else _mm_log_alive(lth, las, avail, navail,
                                                                     b, n, V)
        cand[b, 0] = 0
        cand[b, 1] = 1
        _row_key(data, work, b, state, n, 0, V)
        k = _herd_stage(data, work, b, rid, 2, 2, rs)
        if k < 0:
            return False
        dead = k == 0
    if dead:
        for v in range(V):
            row[b, v] = -1
        return True
    for v in range(V):
        na = navail[b, v]
        for c in range(na):
            j = avail[b, v, c]
            wbuf[b, c] = Th[n, v, j]
            lbuf[b, c] = lth[n, v, j]
            cand[b, c] = j
        _row_key(data, work, b, state, n, v, v + 1)
        k = _herd_stage(data, work, b, rid + 1 + v, na, n_meas[v] + 1, rs)
        if k < 0:  # mm-fixed only: the alive branch is infeasible here
            if ld[n] > -np.inf:
                for w in range(V):
                    row[b, w] = -1
                return True
            return False
        row[b, v] = k
    return True


@jit(inline="always")
def _herd_row_componentwise(data, work, b, state, n, rs):
    """Row ``n``'s components herded in turn (collapsed target) into ``row[b]``.

    Parameters
    ----------
    data, work, b, state, n, rs
        As in :func:`_herd_row_exact` (componentwise method).

    Returns
    -------
    bool
        Always True; a component without a candidate keeps its value.
    """
    n_meas, strides, Wa, la = data.n_meas, data.strides, data.Wa, data.la
    V = data.V
    avail, navail, wbuf, lbuf, row, cand = (work.avail, work.navail, work.wbuf, work.lbuf,
                                            work.row, work.cand)
    for v in range(V):
        row[b, v] = state[n * V + v] - 1
    for v in range(V):
        off = 0
        for w in range(V):
            if w != v:
                off += row[b, w] * strides[w]
        na = navail[b, v]
        for c in range(na):
            j = avail[b, v, c]
            wbuf[b, c] = Wa[n, off + j * strides[v]]
            lbuf[b, c] = la[n, off + j * strides[v]]
            cand[b, c] = j
        _component_key(data, work, b, state, n, v, off)
        k = _herd_stage(data, work, b, n * (V + 1) + 1 + v, na, n_meas[v] + 1, rs)
        if k >= 0:
            row[b, v] = k
    return True


@jit(inline="always")
def sweep_herded(data, work, b, zkeys, state, h, rs):
    """One herded sweep of slab ``b``, in place (twin of the reference's ``herd_sweep``).

    The row order and the sets ``A_n^(v)`` are those of :func:`sweep`; each row update is
    :func:`_herd_row_exact`, :func:`_herd_row_mm` or :func:`_herd_row_componentwise` by the
    method, then the row is written back as in :func:`sweep`. The chain's tallies are
    ``cnt[b]`` (keys, fall-backs, sweeps) and, when chains are speculated, ``hist``.

    Parameters
    ----------
    data : MultiSensorHerdedData
        The call's data.
    work : MultiSensorHerdedWork
        Slab ``b`` used and kept up to date.
    b, zkeys, state, h, rs
        As in :func:`sweep`.

    Returns
    -------
    np.uint64
        The hash of the updated state.
    """
    method = data.method
    _scan_order(data, work, b, rs)
    for t in range(data.P):
        n = work.perm[b, t]
        _available(data, work, b, state, n)
        if method == EXACT:
            ok = _herd_row_exact(data, work, b, state, n, rs)
        elif method == COMPONENTWISE:
            ok = _herd_row_componentwise(data, work, b, state, n, rs)
        else:
            ok = _herd_row_mm(data, work, b, state, n, rs)
        if ok:
            h = _write_row(data, work, b, zkeys, state, n, h)
    key_table_sweep_done(work, b)
    return h


class MultiSensorHerdedWork(record(MultiSensorWork, {"cand": np.ndarray}, KeyTable)):
    """Workspace of ``nb`` herded chains (:func:`alloc_work_herded`): the fields of
    :class:`MultiSensorWork`, the candidates' full indices and those of a
    :class:`~rankedassign.engine._kernels.KeyTable` (weights of width
    ``MultiSensorHerdedData.width``, key vectors of length ``max(P V, 1)``).

    Attributes
    ----------
    occ, avail, navail, idx, wbuf, lbuf, perm, row
        As in :class:`MultiSensorWork`.
    cand : ndarray, shape (nb, C), int64
        Full candidate index of each compact candidate.
    p, keyv, hw, kst, krow, tslot, thash, cnt, hist
        As in :class:`~rankedassign.engine._kernels.KeyTable`: the draw's conditional over
        its full candidate range and its key (padded with -1), the key table (row ids
        ``n (V + 1) + stage``) and the chain's tallies.
    """


@jit()
def alloc_work_herded(data, nb):
    """Workspace of ``nb`` herded chains: the Gibbs workspace, scratch rows and key tables.

    Parameters
    ----------
    data : MultiSensorHerdedData
        The call's data (``width``, ``capacity``, ``chain_length``).
    nb : int
        Chains.

    Returns
    -------
    MultiSensorHerdedWork
    """
    g = alloc_work(data, nb)
    cand = np.zeros((nb, g.wbuf.shape[1]), dtype=np.int64)
    table = alloc_key_table(nb, data.width, max(data.P * data.V, 1), data.capacity,
                            data.chain_length)
    return MultiSensorHerdedWork(*(g[:] + (cand,) + table[:]))


@jit()
def reset_work_herded(data, work, b, x0):
    """Slab ``b`` for a new chain from ``x0``: occupancy, an empty key table, zero tallies.

    Parameters
    ----------
    data, b, x0
        As in :func:`reset_work`.
    work : MultiSensorHerdedWork
        Slab ``b`` reset.
    """
    reset_work(data, work, b, x0)
    reset_key_table(work, b)


#: The chain driver compiled for the multi-sensor problem with the herded draw.
run_chains_herded = make_driver("multisensor_herded", alloc_work_herded, reset_work_herded,
                                sweep_herded, work=MultiSensorHerdedWork,
                                chain_done=key_table_done)

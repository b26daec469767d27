"""numba row update of the adaptive-birth Gibbs sampler (clean inputs only).

The compiled twin of :mod:`rankedassign.adaptive_birth.reference`: the same operations in the
same order (Fisher-Yates sensor order, ratio-form log-weights with running information sums,
plain-loop Cholesky and forward substitution, ``exp(lw - max)`` and the sequential
inverse-CDF loop), so both give bit-identical chains for the same stream. The three
functions follow the generic chain driver's interface:

* :func:`alloc_work` ``(data, nb) -> work``: the scratch arrays, leading dimension ``nb`` (one
  slab per chain simulated at once), an :class:`AdaptiveBirthWork`;
* :func:`reset_work` ``(data, work, b, x0)``: nothing to reset (the information sums are
  recomputed from the state at the start of every sweep, so a sweep's transition depends on
  the state only);
* :func:`sweep` ``(data, work, b, zkeys, state, h, rs) -> h``: one sweep in place on the
  ``int32`` tuple ``state``, keeping the Zobrist hash ``h``.

``data`` is the :class:`~rankedassign.adaptive_birth.prepare.AdaptiveBirthData` of
:func:`rankedassign.adaptive_birth.prepare.chain_inputs`.

References
----------
.. [1] A. Trezza, D. J. Bucci Jr., P. K. Varshney, "Multi-sensor joint adaptive birth sampler
   for labeled random finite set tracking", IEEE Trans. Signal Process. 70, 2022.
"""

from __future__ import annotations

import math
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

__all__ = ["alloc_work", "reset_work", "sweep", "draw", "cholesky", "half_logdet", "quad",
           "run_chains", "sweep_herded", "alloc_work_herded", "reset_work_herded",
           "run_chains_herded", "RowScratch", "AdaptiveBirthWork", "AdaptiveBirthHerdedWork"]


class RowScratch(NamedTuple):
    """The scratch of a sensor's row update (:func:`_sums`, :func:`_log_weights`,
    :func:`_take`), held by the chains' workspace (:class:`AdaptiveBirthWork`, one slab per
    chain: a leading dimension ``nb`` on every field) and by the tempered one
    (:class:`~rankedassign.adaptive_birth._tempered_kernels.AdaptiveBirthTemperedWork`).

    ``n`` is the state dimension, ``K = max_s (M_s + 1)``.

    Attributes
    ----------
    M : ndarray, shape (n, n), float64
        Running information matrix.
    b : ndarray, shape (n,), float64
        Running information vector.
    c : ndarray, shape (1,), float64
        Running scalar term.
    Mp : ndarray, shape (n, n), float64
        ``M+ = M- + A_s``.
    L : ndarray, shape (n, n), float64
        Cholesky factors.
    y : ndarray, shape (n,), float64
        Forward-substitution scratch.
    bj : ndarray, shape (n,), float64
        ``b- + a_sj``.
    lw : ndarray, shape (K,), float64
        The sensor's log-weights.
    """

    M: np.ndarray
    b: np.ndarray
    c: np.ndarray
    Mp: np.ndarray
    L: np.ndarray
    y: np.ndarray
    bj: np.ndarray
    lw: np.ndarray


class AdaptiveBirthWork(record({"order": np.ndarray}, RowScratch)):
    """Scratch of ``nb`` chains (:func:`alloc_work`), leading dimension ``nb``.

    Attributes
    ----------
    order : ndarray, shape (nb, V), int64
        The sweep's sensor order.
    M, b, c, Mp, L, y, bj, lw : ndarray
        A :class:`RowScratch` per chain (shapes there, after ``nb``).
    """


@jit()
def alloc_work(data, nb):
    """Scratch arrays for ``nb`` chains (an :class:`AdaptiveBirthWork`).

    Parameters
    ----------
    data : AdaptiveBirthData
        The call's data (``V``, ``n``, ``shape``).
    nb : int
        Chains.

    Returns
    -------
    AdaptiveBirthWork
        Zero arrays of the shapes listed there.

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign.adaptive_birth.prepare import AdaptiveBirthProblem, chain_inputs
    >>> work = alloc_work(chain_inputs(AdaptiveBirthProblem.from_log_weights(np.zeros((2, 4)))), 3)
    >>> work.order.shape, work.lw.shape
    ((3, 2), (3, 4))
    """
    V = data.V
    n = data.n
    K = 1
    for v in range(V):
        K = max(K, data.shape[v])
    return AdaptiveBirthWork(
        order=np.zeros((nb, V), dtype=np.int64), M=np.zeros((nb, n, n)), b=np.zeros((nb, n)),
        c=np.zeros((nb, 1)), Mp=np.zeros((nb, n, n)), L=np.zeros((nb, n, n)),
        y=np.zeros((nb, n)), bj=np.zeros((nb, n)), lw=np.zeros((nb, K)))


@jit()
def reset_work(data, work, b, x0):
    """Prepare slab ``b`` for a chain started at ``x0`` (nothing to do; see module notes).

    Parameters
    ----------
    data : AdaptiveBirthData
        The call's data.
    work : AdaptiveBirthWork
        The workspace.
    b : int
        The slab.
    x0 : ndarray of int32, shape (V,)
        The start tuple.

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

    Parameters
    ----------
    lw : ndarray of float64, shape (>= K,)
        Log-weights, at least one finite; overwritten by ``exp(lw - max)``.
    K : int
        Candidates.
    u : float
        A uniform in ``[0, 1)``.

    Returns
    -------
    int

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

    Parameters
    ----------
    M : ndarray of float64, shape (n, n)
        Symmetric positive definite (its lower triangle is read).
    L : ndarray of float64, shape (n, n)
        Receives the factor in its lower triangle (the upper one is not written).
    n : int
        The dimension.

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

    Parameters
    ----------
    L : ndarray of float64, shape (n, n)
        A Cholesky factor.
    n : int
        The dimension.

    Returns
    -------
    float

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

    Parameters
    ----------
    L : ndarray of float64, shape (n, n)
        A Cholesky factor.
    b : ndarray of float64, shape (n,)
        The vector.
    y : ndarray of float64, shape (n,)
        Receives ``L^-1 b``.
    n : int
        The dimension.

    Returns
    -------
    float

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
    """``(M, b, c)`` = prior information plus the terms of the detecting sensors of ``state``.

    Parameters
    ----------
    data : AdaptiveBirthData
        The call's data (Gaussian mode).
    M : ndarray of float64, shape (n, n)
        Receives the information matrix.
    b : ndarray of float64, shape (n,)
        Receives the information vector.
    c : ndarray of float64, shape (1,)
        Receives the scalar term.
    state : ndarray of int32, shape (V,)
        The tuple ``J`` (0 missed, ``j >= 1`` measurement ``j`` of the sensor).
    """
    n = data.n
    off, M0, b0, A, a, cz = data.off, data.M0, data.b0, data.A, data.a, data.cz
    for i in range(n):
        for k in range(n):
            M[i, k] = M0[i, k]
        b[i] = b0[i]
    c[0] = data.c0
    for v in range(data.V):
        if state[v] > 0:
            t = off[v] + state[v] - 1
            for i in range(n):
                for k in range(n):
                    M[i, k] += A[v, i, k]
                b[i] += a[t, i]
            c[0] += cz[t]


@jit()
def _gaussian_weights(data, M, b, c, Mp, L, y, bj, lw, state, s):
    """Sensor ``s``'s log-weights into ``lw`` (ratio form); leaves ``(M-, b-, c-)``, ``M+``.

    Parameters
    ----------
    data : AdaptiveBirthData
        The call's data (Gaussian mode).
    M, b, c
        The information sums of ``state`` (as :func:`_sums` makes them); sensor ``s``'s
        terms removed in place.
    Mp : ndarray of float64, shape (n, n)
        Receives ``M+ = M- + A_s``.
    L : ndarray of float64, shape (n, n)
        Scratch for the Cholesky factors (left holding that of ``M+``).
    y, bj : ndarray of float64, shape (n,)
        Scratch.
    lw : ndarray of float64, shape (>= M_s + 1,)
        Receives the log-weights: 0 missed, ``j`` measurement ``j``.
    state : ndarray of int32, shape (V,)
        The tuple.
    s : int
        The sensor.
    """
    n = data.n
    off, A, a, cz, const = data.off, data.A, data.a, data.cz, data.const
    Ms = data.shape[s] - 1
    if state[s] > 0:                                     # remove sensor s: (M-, b-, c-)
        t = off[s] + state[s] - 1
        for i in range(n):
            for k in range(n):
                M[i, k] -= A[s, i, k]
            b[i] -= a[t, i]
        c[0] -= cz[t]
    cholesky(M, L, n)
    lw[0] = data.log_miss[s] - half_logdet(L, n) - 0.5 * (c[0] - quad(L, b, y, n))  # missed by s
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
def _sensor_order(order, V, random_order, rs):
    """The sweep's sensor order into ``order``: ``0..V-1``, shuffled if ``random_order``.

    Parameters
    ----------
    order : ndarray of int64, shape (V,)
        Filled.
    V : int
        Sensors.
    random_order : bool
        Shuffle (Fisher-Yates, ``t = V-1..1``, one uniform each) instead of the fixed order.
    rs : ndarray of uint64, shape (1,)
        The chain's stream state.
    """
    for v in range(V):
        order[v] = v
    if random_order:                                     # Fisher-Yates, t = V-1..1
        for t in range(V - 1, 0, -1):
            k = min(np.int64(next_uniform(rs) * (t + 1)), t)
            tmp = order[t]
            order[t] = order[k]
            order[k] = tmp


@jit(inline="always")
def _log_weights(data, M, b, c, Mp, L, y, bj, lw, state, s):
    """Sensor ``s``'s conditional log-weights (spec eq. 4.3) into ``lw[:M_s + 1]``.

    Read from the tensor, or (linear-Gaussian mode) :func:`_gaussian_weights` from the
    information sums ``(M, b, c)`` of ``state``.

    Parameters
    ----------
    data : AdaptiveBirthData
        The problem.
    M, b, c, Mp, L, y, bj
        The sums and the scratch of :func:`_gaussian_weights`.
    lw : ndarray of float64, shape (>= M_s + 1,)
        Filled.
    state : ndarray of int32, shape (V,)
        The tuple.
    s : int
        The sensor.
    """
    if data.mode == 1:
        _gaussian_weights(data, M, b, c, Mp, L, y, bj, lw, state, s)
        return
    strides = data.strides
    base = 0
    for v in range(data.V):
        if v != s:
            base += state[v] * strides[v]
    for j in range(data.shape[s]):
        lw[j] = data.logw[base + j * strides[s]]


@jit(inline="always")
def _take(data, M, b, c, Mp, zkeys, state, h, s, j):
    """Sensor ``s`` takes entry ``j``: ``state``, its hash and (linear-Gaussian mode, a
    measurement) the sums ``(M, b, c)`` updated; returns the new hash.

    Parameters
    ----------
    data : AdaptiveBirthData
        The problem.
    M, b, c : ndarray of float64
        The information sums of ``state``, updated.
    Mp : ndarray of float64, shape (n, n)
        ``M`` with sensor ``s``'s term (from :func:`_gaussian_weights`).
    zkeys : ndarray of uint64, shape (V, K)
        Zobrist keys.
    state : ndarray of int32, shape (V,)
        The tuple, updated.
    h : np.uint64
        Its hash.
    s, j : int
        The sensor and its new entry.

    Returns
    -------
    np.uint64
    """
    if data.mode == 1 and j > 0:                         # (M, b, c) <- sums of the new tuple
        t = data.off[s] + j - 1
        n = data.n
        for i in range(n):
            for k in range(n):
                M[i, k] = Mp[i, k]
            b[i] += data.a[t, i]
        c[0] += data.cz[t]
    old = state[s]
    if j != old:
        h ^= zkeys[s, old] ^ zkeys[s, j]
        state[s] = j
    return h


@jit(inline="always")
def sweep(data, work, b, zkeys, state, h, rs):
    """One sweep over the sensors of slab ``b``'s chain; returns the updated Zobrist hash.

    Parameters
    ----------
    data : AdaptiveBirthData
        The call's data.
    work : AdaptiveBirthWork
        Slab ``b`` used as scratch.
    b : int
        The slab.
    zkeys : ndarray of uint64, shape (V, K)
        Zobrist keys.
    state : ndarray of int32, shape (V,)
        The tuple ``J``, updated in place.
    h : np.uint64
        Its hash.
    rs : ndarray of uint64, shape (1,)
        The chain's stream state (``V - 1`` uniforms for a random order, then one per sensor).

    Returns
    -------
    np.uint64

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
    V = data.V
    order = work.order[b]
    M, bb, c, Mp, L, y, bj, lw = (work.M[b], work.b[b], work.c[b], work.Mp[b], work.L[b],
                                  work.y[b], work.bj[b], work.lw[b])
    _sensor_order(order, V, data.random_order, rs)
    gaussian = data.mode == 1
    if gaussian:
        _sums(data, M, bb, c, state)
    for r in range(V):
        s = order[r]
        K = data.shape[s]
        _log_weights(data, M, bb, c, Mp, L, y, bj, lw, state, s)
        j = draw(lw, K, next_uniform(rs))
        h = _take(data, M, bb, c, Mp, zkeys, state, h, s, j)
    return h


#: The chain driver compiled for the adaptive-birth problem (:func:`.._chains.make_driver`).
run_chains = make_driver("adaptive_birth", alloc_work, reset_work, sweep,
                         work=AdaptiveBirthWork)


# ---------------------------------------------------------------------------- herded draw
@jit(inline="always")
def _conditional(lw, p, K):
    """Twin of :func:`rankedassign.adaptive_birth.reference.conditional` into ``p``.

    Parameters
    ----------
    lw : ndarray of float64, shape (>= K,)
        Log-weights, at least one finite (not modified).
    p : ndarray of float64, shape (>= K,)
        Receives the normalised weights in ``p[:K]``.
    K : int
        Candidates.
    """
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

    ``data`` is an :class:`~rankedassign.adaptive_birth.prepare.AdaptiveBirthHerdedData`,
    ``work`` an :class:`AdaptiveBirthHerdedWork`: the Gibbs workspace followed by the
    conditional ``p``, the key vector ``keyv`` (``J`` with the redrawn sensor as -1; the key is
    the same for both key modes), the key table and the chain's tallies
    (:func:`rankedassign.engine._kernels.key_table_done`).

    Parameters
    ----------
    data : AdaptiveBirthHerdedData
        The call's data.
    work : AdaptiveBirthHerdedWork
        Slab ``b`` used and kept up to date.
    b, zkeys, state, h, rs
        As in :func:`sweep`.

    Returns
    -------
    np.uint64
    """
    V = data.V
    order = work.order[b]
    M, bb, c, Mp, L, y, bj, lw = (work.M[b], work.b[b], work.c[b], work.Mp[b], work.L[b],
                                  work.y[b], work.bj[b], work.lw[b])
    p, keyv, cnt = work.p[b], work.keyv[b], work.cnt[b]
    _sensor_order(order, V, data.random_order, rs)
    gaussian = data.mode == 1
    if gaussian:
        _sums(data, M, bb, c, state)
    for r in range(V):
        s = order[r]
        K = data.shape[s]
        _log_weights(data, M, bb, c, Mp, L, y, bj, lw, state, s)
        _conditional(lw, p, K)
        for v in range(V):
            keyv[v] = -1 if v == s else state[v]
        slot, new = herd_lookup(s, keyv, cnt, data.capacity, work.krow[b], work.kst[b],
                                work.tslot[b], work.thash[b])
        if slot < 0:  # the table is full: an ordinary Gibbs draw
            j = draw(lw, K, next_uniform(rs))
        else:
            j = herd_pick(work.hw[b, slot], p, K, new, data.init_mode, rs)
        h = _take(data, M, bb, c, Mp, zkeys, state, h, s, j)
    key_table_sweep_done(work, b)
    return h


class AdaptiveBirthHerdedWork(record(AdaptiveBirthWork, KeyTable)):
    """Scratch of ``nb`` herded chains (:func:`alloc_work_herded`): the fields of
    :class:`AdaptiveBirthWork`, then those of a
    :class:`~rankedassign.engine._kernels.KeyTable` (weights of width ``K``, key vectors of
    length ``max(V, 1)``).

    Attributes
    ----------
    order, M, b, c, Mp, L, y, bj, lw
        As in :class:`AdaptiveBirthWork`.
    p, keyv, hw, kst, krow, tslot, thash, cnt, hist
        As in :class:`~rankedassign.engine._kernels.KeyTable`: the sensor's conditional and
        key, the key table (row ids: the sensor) and the chain's tallies.
    """


@jit()
def alloc_work_herded(data, nb):
    """Workspace of ``nb`` herded chains: the Gibbs scratch, the conditional, key tables.

    Parameters
    ----------
    data : AdaptiveBirthHerdedData
        The call's data (with ``capacity`` and ``chain_length``).
    nb : int
        Chains.

    Returns
    -------
    AdaptiveBirthHerdedWork

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign.adaptive_birth.prepare import AdaptiveBirthProblem, herd_inputs, prepare
    >>> from rankedassign.engine.herding import Herding
    >>> prep = prepare(AdaptiveBirthProblem.from_log_weights(np.zeros((2, 4))), "all_missed",
    ...                "systematic", 0, {})
    >>> data = herd_inputs(prep, Herding(max_keys=8), 5)[0]
    >>> work = alloc_work_herded(data, 3)
    >>> work.p.shape, work.hw.shape
    ((3, 4), (3, 8, 4))
    """
    g = alloc_work(data, nb)
    table = alloc_key_table(nb, g.lw.shape[1], max(data.V, 1), data.capacity,
                            data.chain_length)
    return AdaptiveBirthHerdedWork(*(g[:] + table[:]))


@jit()
def reset_work_herded(data, work, b, x0):
    """Slab ``b`` for a new chain: an empty key table and zero tallies.

    Parameters
    ----------
    data, b, x0
        As in :func:`reset_work`.
    work : AdaptiveBirthHerdedWork
        Slab ``b``'s key table reset.
    """
    reset_key_table(work, b)


#: The chain driver compiled for the adaptive-birth problem with the herded draw.
run_chains_herded = make_driver("adaptive_birth_herded", alloc_work_herded, reset_work_herded,
                                sweep_herded, work=AdaptiveBirthHerdedWork,
                                chain_done=key_table_done)

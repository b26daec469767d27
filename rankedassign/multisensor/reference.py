"""Pure-Python row updates of the multi-sensor Gibbs samplers: the specification of record.

The numba kernels of :mod:`rankedassign.multisensor._kernels` must agree with these functions
bit for bit (tested with hypothesis). Both consume the same uniforms in the same order and turn
each into a candidate with the same sequential inverse-CDF loop (:func:`pick`) over the same
weights, computed once per call with numpy by :func:`rankedassign.multisensor.prepare.prepare`.

State. One flat list ``x`` of ``P * V`` ints: ``x[n * V + v] = gamma_n^(v) + 1`` (0 dead, 1
missed by sensor ``v``, ``j + 1`` measurement ``j`` of sensor ``v``). A dead row is dead on
every sensor (spec eq. 1.1). The work object is the per-sensor occupancy table
``occ[v][j]`` = number of rows holding measurement ``j`` of sensor ``v`` (0 or 1 in a feasible
state; index 0 unused).

One sweep (:func:`sweep`): for a random scan, first ``P - 1`` uniforms for the Fisher-Yates
permutation of the rows; then one row update per row, in that order (Gauss-Seidel):

* ``"exact"`` (Vo, Vo & Beard 2019, Alg. 1; spec §2): one uniform; the candidates are dead,
  then the tuples of ``A_n^(1) x ... x A_n^(V)`` in C order (last sensor fastest), with
  ``A_n^(v) = {0} ∪ {free measurements of sensor v, or the row's own}`` (spec eq. 2.1);
* ``"mm"`` (MM-Gibbs, exclusion variant; spec §3.2-3.3): one uniform for dead vs alive with
  weights ``eta_n(-1)`` and ``s_n^alpha prod_v sum_{j in A_n^(v)} theta_n^(v)(j)``; if
  alive, one uniform per sensor ``v = 0..V-1`` for ``j ~ theta_n^(v)(j) 1[j in A_n^(v)]``;
* ``"mm-fixed"``: as ``"mm"`` but dead iff ``u < Q_n``, ``Q_n`` computed once per call
  without exclusions (spec §3.3, table);
* ``"componentwise"`` (spec §2.4): on the collapsed target of spec §1.6, one uniform per
  sensor ``v = 0..V-1``: ``gamma_n^(v) ~ eta'_n(gamma_n with component v set to j)`` over
  ``j in A_n^(v)``, the other components held at their current values.

Edge cases, identical in the kernels: when every available shifted weight of a draw has
underflowed to 0 the draw is repeated on exact weights ``exp(l - max l)`` of the available
log-weights (this path calls ``exp``/``log``, which agree between Python and the kernels on one
machine, as in the single-sensor samplers); a draw with no positive weight at all leaves the
row as it is (it cannot happen at a feasible state for ``"exact"`` and ``"componentwise"``).
For ``"mm-fixed"``, if the alive branch is drawn but some sensor has no available positive
weight (``theta_n^(v)(0) = 0`` and every positive measurement taken), the row becomes dead
(kept unchanged if dead is forbidden); the per-sensor draws stop at the first such sensor.

References
----------
.. [1] B.-N. Vo, B.-T. Vo, M. Beard, "Multi-Sensor Multi-Object Tracking with the Generalized
   Labeled Multi-Bernoulli Filter", IEEE Trans. Signal Process. 67(23):5952-5967, 2019.
"""

from __future__ import annotations

import math

__all__ = ["RefData", "pick", "draw", "new_work", "sweep"]

EXACT, MM, MM_FIXED, COMPONENTWISE = 0, 1, 2, 3
NEG_INF = float("-inf")


class RefData:
    """The prepared arrays of :func:`rankedassign.multisensor.prepare.prepare` as lists.

    Parameters
    ----------
    arrays : tuple
        The numba ``data`` tuple ``(params, n_meas, strides, Wd, ld, Wa, la, Th, lth, las, Ea,
        Ed, qdead)`` (see :func:`rankedassign.multisensor.prepare.prepare`).

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign.multisensor.prepare import prepare_data
    >>> class Stub:
    ...     n_rows, n_sensors, n_meas = 1, 1, (0,)
    ...     log_eta_dead = np.zeros(1); log_eta_alive = np.zeros((1, 1))
    ...     log_s = None; log_theta = None
    >>> d = RefData(prepare_data(Stub(), "exact", "systematic", 1))
    >>> d.P, d.V, d.Wd
    (1, 1, [1.0])
    """

    def __init__(self, arrays):
        params, n_meas, strides, Wd, ld, Wa, la, Th, lth, las, Ea, Ed, qdead = arrays
        self.method, self.random_scan, self.P, self.V = (int(a) for a in params)
        self.n_meas = [int(m) for m in n_meas]
        self.strides = [int(s) for s in strides]
        self.Wd, self.ld = Wd.tolist(), ld.tolist()
        self.Wa, self.la = Wa.tolist(), la.tolist()
        self.Th, self.lth = Th.tolist(), lth.tolist()
        self.las, self.Ea, self.Ed, self.qdead = las.tolist(), Ea.tolist(), Ed.tolist(), \
            qdead.tolist()


def pick(weights, total, u):
    """Sequential inverse CDF: the candidate of uniform ``u`` under ``weights``.

    Parameters
    ----------
    weights : sequence of float
        Non-negative weights of the candidates, in candidate order (0 = impossible).
    total : float
        Their sum, accumulated left to right by the caller.
    u : float
        The draw's uniform in ``[0, 1)``.

    Returns
    -------
    int
        The first index whose running sum of the positive weights exceeds ``u * total``; the
        last positive one if rounding leaves none; ``-1`` if no weight is positive.

    Examples
    --------
    >>> pick([0.5, 0.0, 0.5], 1.0, 0.75)
    2
    """
    target = u * total
    acc = 0.0
    last = -1
    for k, w in enumerate(weights):
        if w > 0.0:
            acc += w
            last = k
            if acc > target:
                return k
    return last


def draw(weights, logs, u):
    """One categorical draw with uniform ``u`` from ``weights`` (shifted, may underflow).

    Parameters
    ----------
    weights : sequence of float
        Shifted weights ``exp(log - max)`` of the candidates (from the prepared arrays), in
        candidate order; may all have underflowed to 0.
    logs : sequence of float
        The same candidates' log-weights, same length (``-inf`` = impossible).
    u : float
        The draw's uniform in ``[0, 1)``, used once by :func:`pick`.

    Returns
    -------
    int
        Index of the candidate drawn. If every weight is 0 the draw uses
        ``exp(logs[k] - max(logs))`` instead; ``-1`` if every log-weight is ``-inf``.

    Examples
    --------
    >>> draw([0.0, 0.0], [-800.0, -801.0], 0.5)
    0
    """
    total = 0.0
    for w in weights:
        total += w
    if total > 0.0:
        return pick(weights, total, u)
    m = NEG_INF
    for lw in logs:
        if lw > m:
            m = lw
    if m == NEG_INF:
        return -1
    weights = [math.exp(lw - m) for lw in logs]
    total = 0.0
    for w in weights:
        total += w
    return pick(weights, total, u)


def new_work(data, x):
    """Occupancy table ``occ[v][j]`` of the state ``x`` (rows holding measurement ``j``).

    Parameters
    ----------
    data : RefData
        Gives ``V`` and the measurement counts ``n_meas``.
    x : list of int, length P * V
        State, ``x[n * V + v] = gamma_n^(v) + 1``.

    Returns
    -------
    list of list of int
        ``occ[v]`` has length ``M_v + 1``; ``occ[v][j]`` counts the rows holding measurement
        ``j`` of sensor ``v`` (0 or 1 for a feasible ``x``; ``occ[v][0]`` unused, 0).

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign.multisensor.prepare import prepare_data
    >>> class Stub:
    ...     n_rows, n_sensors, n_meas = 1, 2, (1, 0)
    ...     log_eta_dead = np.zeros(1); log_eta_alive = np.zeros((1, 2, 1))
    ...     log_s = None; log_theta = None
    >>> new_work(RefData(prepare_data(Stub(), "exact", "systematic", 1)), [2, 1])
    [[0, 1], [0]]
    """
    V = data.V
    occ = [[0] * (m + 1) for m in data.n_meas]
    for i, val in enumerate(x):
        if val >= 2:
            occ[i % V][val - 1] += 1
    return occ


def _available(data, occ, x, n):
    """``A_n^(v)`` for every sensor: 0 and the measurements free of the other rows."""
    V = data.V
    out = []
    for v in range(V):
        own = x[n * V + v] - 1
        a = [0]
        for j in range(1, data.n_meas[v] + 1):
            if occ[v][j] == 0 or own == j:
                a.append(j)
        out.append(a)
    return out


def _row_exact(data, avail, n, g):
    """Spec eq. 2.1: ``p(u) ∝ eta_n(u)`` over dead and ``A_n^(1) x ... x A_n^(V)``."""
    V = data.V
    tuples = [[]]
    for v in range(V):  # C order: the last sensor varies fastest
        tuples = [t + [j] for t in tuples for j in avail[v]]
    Wa, la, st = data.Wa[n], data.la[n], data.strides
    weights, logs = [data.Wd[n]], [data.ld[n]]
    for t in tuples:
        off = 0
        for v in range(V):
            off += t[v] * st[v]
        weights.append(Wa[off])
        logs.append(la[off])
    k = draw(weights, logs, g.uniform())
    if k < 0:
        return None
    if k == 0:
        return [-1] * V
    return tuples[k - 1]


def _sensor_draw(data, avail_v, n, v, g):
    """``j ~ theta_n^(v)(j) 1[j in A_n^(v)]`` with one uniform (MM, spec §3.2)."""
    Th, lth = data.Th[n][v], data.lth[n][v]
    return draw([Th[j] for j in avail_v], [lth[j] for j in avail_v], g.uniform())


def _row_mm(data, avail, n, g, fixed):
    """Spec §3.2: dead with probability ``Q_n``, else independent per-sensor draws."""
    V = data.V
    u = g.uniform()
    if fixed:
        dead = u < data.qdead[n]
    else:
        # alive mass s_n^alpha prod_v sum_{j in A_n^(v)} theta_n^(v)(j), shifted by the same
        # constant as the dead weight eta_n(-1)
        alive = data.Ea[n]
        for v in range(V):
            s = 0.0
            for j in avail[v]:
                s += data.Th[n][v][j]
            alive *= s
        k = pick([data.Ed[n], alive], data.Ed[n] + alive, u)
        if k < 0:  # both underflowed: the same decision on exact log-weights
            la = data.las[n]
            for v in range(V):
                ls = [data.lth[n][v][j] for j in avail[v]]
                m = max(ls)
                if m == NEG_INF:
                    la = NEG_INF
                    break
                s = 0.0
                for lw in ls:
                    s += math.exp(lw - m)
                la += m + math.log(s)
            k = draw([0.0, 0.0], [data.ld[n], la], u)
            if k < 0:
                return None
        dead = k == 0
    if dead:
        return [-1] * V
    row = []
    for v in range(V):
        k = _sensor_draw(data, avail[v], n, v, g)
        if k < 0:  # mm-fixed only: the alive branch is infeasible here
            return [-1] * V if data.ld[n] > NEG_INF else None
        row.append(avail[v][k])
    return row


def _row_componentwise(data, avail, x, n, g):
    """Spec §2.4: each component in turn from its exact conditional under ``eta'``."""
    V = data.V
    st = data.strides
    row = [x[n * V + v] - 1 for v in range(V)]  # never dead on the collapsed space
    Wa, la = data.Wa[n], data.la[n]
    for v in range(V):
        base = 0
        for w in range(V):
            if w != v:
                base += row[w] * st[w]
        k = draw([Wa[base + j * st[v]] for j in avail[v]],
                 [la[base + j * st[v]] for j in avail[v]], g.uniform())
        if k >= 0:
            row[v] = avail[v][k]
    return row


def sweep(data, work, x, g) -> None:
    """One sweep over all rows, in place on ``x`` and the occupancy table ``work``.

    Parameters
    ----------
    data : RefData
        Prepared weights.
    work : list of list of int
        Occupancy table of ``x`` (:func:`new_work`), kept up to date.
    x : list of int, length P * V
        State (``gamma + 1`` per row and sensor), updated in place.
    g : rankedassign.engine.rng.SplitMix64
        The chain's stream.

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign.engine.rng import SplitMix64
    >>> from rankedassign.multisensor.prepare import prepare_data
    >>> class Stub:
    ...     n_rows, n_sensors, n_meas = 1, 2, (1, 1)
    ...     log_eta_dead = np.array([-50.0]); log_eta_alive = np.full((1, 2, 2), -50.0)
    ...     log_s = None; log_theta = None
    >>> Stub.log_eta_alive[0, 1, 1] = 0.0
    >>> d = RefData(prepare_data(Stub(), "exact", "systematic", 1))
    >>> x = [1, 1]
    >>> occ = new_work(d, x)
    >>> sweep(d, occ, x, SplitMix64(0))
    >>> x, occ
    ([2, 2], [[0, 1], [0, 1]])
    """
    P, V = data.P, data.V
    order = list(range(P))
    if data.random_scan:
        for t in range(P - 1, 0, -1):
            j = min(int(g.uniform() * (t + 1)), t)
            order[t], order[j] = order[j], order[t]
    for n in order:
        avail = _available(data, work, x, n)
        if data.method == EXACT:
            row = _row_exact(data, avail, n, g)
        elif data.method == COMPONENTWISE:
            row = _row_componentwise(data, avail, x, n, g)
        else:
            row = _row_mm(data, avail, n, g, data.method == MM_FIXED)
        if row is None:
            continue
        for v in range(V):
            old, new = x[n * V + v], row[v] + 1
            if old != new:
                if old >= 2:
                    work[v][old - 1] -= 1
                if new >= 2:
                    work[v][new - 1] += 1
                x[n * V + v] = new

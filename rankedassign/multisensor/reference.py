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
from typing import NamedTuple

from ..engine.reference import herd_choice

__all__ = ["RefData", "pick", "draw", "new_work", "sweep", "exact_candidates", "HerdData",
           "new_herd_work", "herd_key", "herd_sweep"]

EXACT, MM, MM_FIXED, COMPONENTWISE = 0, 1, 2, 3
NEG_INF = float("-inf")


class RefData:
    """The prepared arrays of :func:`rankedassign.multisensor.prepare.prepare` as lists.

    Parameters
    ----------
    arrays : MultiSensorData
        The kernels' inputs (:class:`rankedassign.multisensor.prepare.MultiSensorData`).

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
        a = arrays
        self.method, self.random_scan, self.P, self.V = (int(a.method), int(a.random_scan),
                                                         int(a.P), int(a.V))
        self.n_meas = [int(m) for m in a.n_meas]
        self.strides = [int(s) for s in a.strides]
        self.Wd, self.ld = a.Wd.tolist(), a.ld.tolist()
        self.Wa, self.la = a.Wa.tolist(), a.la.tolist()
        self.Th, self.lth = a.Th.tolist(), a.lth.tolist()
        self.las, self.Ea, self.Ed, self.qdead = (a.las.tolist(), a.Ea.tolist(), a.Ed.tolist(),
                                                  a.qdead.tolist())


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


def exact_candidates(data, avail):
    """The alive candidates of an exact row update: ``A_n^(1) x ... x A_n^(V)`` in C order.

    Parameters
    ----------
    data : RefData
        Gives ``V`` and the tuple strides.
    avail : list of list of int
        ``A_n^(v)`` per sensor, increasing (:func:`_available`).

    Returns
    -------
    tuples : list of list of int
        The tuples, the last sensor varying fastest (so in increasing flat offset).
    offsets : list of int
        Their flat offsets ``Σ_v t_v strides_v`` into a row of ``Wa``/``la``.

    Examples
    --------
    >>> d = type("D", (), {"V": 2, "strides": [3, 1]})()
    >>> exact_candidates(d, [[0, 1], [0, 2]])
    ([[0, 0], [0, 2], [1, 0], [1, 2]], [0, 2, 3, 5])
    """
    V = data.V
    tuples = [[]]
    for v in range(V):  # C order: the last sensor varies fastest
        tuples = [t + [j] for t in tuples for j in avail[v]]
    st = data.strides
    offsets = []
    for t in tuples:
        off = 0
        for v in range(V):
            off += t[v] * st[v]
        offsets.append(off)
    return tuples, offsets


def _row_exact(data, avail, n, g):
    """Spec eq. 2.1: ``p(u) ∝ eta_n(u)`` over dead and ``A_n^(1) x ... x A_n^(V)``."""
    V = data.V
    tuples, offsets = exact_candidates(data, avail)
    Wa, la = data.Wa[n], data.la[n]
    weights = [data.Wd[n]] + [Wa[off] for off in offsets]
    logs = [data.ld[n]] + [la[off] for off in offsets]
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


def _mm_alive(data, avail, n):
    """MM alive mass ``s_n^alpha prod_v sum_{j in A_n^(v)} theta_n^(v)(j)``, shifted by the
    same constant as the dead weight ``eta_n(-1)``."""
    alive = data.Ea[n]
    for v in range(data.V):
        s = 0.0
        for j in avail[v]:
            s += data.Th[n][v][j]
        alive *= s
    return alive


def _mm_log_alive(data, avail, n):
    """The log of the MM alive mass on exact log-weights (the underflow fall-back)."""
    la = data.las[n]
    for v in range(data.V):
        ls = [data.lth[n][v][j] for j in avail[v]]
        m = max(ls)
        if m == NEG_INF:
            return NEG_INF
        s = 0.0
        for lw in ls:
            s += math.exp(lw - m)
        la += m + math.log(s)
    return la


def _row_mm(data, avail, n, g, fixed):
    """Spec §3.2: dead with probability ``Q_n``, else independent per-sensor draws."""
    V = data.V
    u = g.uniform()
    if fixed:
        dead = u < data.qdead[n]
    else:
        alive = _mm_alive(data, avail, n)
        k = pick([data.Ed[n], alive], data.Ed[n] + alive, u)
        if k < 0:  # both underflowed: the same decision on exact log-weights
            k = draw([0.0, 0.0], [data.ld[n], _mm_log_alive(data, avail, n)], u)
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


def _order(data, g):
    """The rows of one sweep: ``0..P-1``, or Fisher-Yates from the identity (``t = P-1..1``:
    ``j = min(floor(u (t + 1)), t)``, swap ``t`` and ``j``)."""
    order = list(range(data.P))
    if data.random_scan:
        for t in range(data.P - 1, 0, -1):
            j = min(int(g.uniform() * (t + 1)), t)
            order[t], order[j] = order[j], order[t]
    return order


def _apply_row(data, occ, x, n, row):
    """Write row ``n``'s new ``gamma`` values ``row`` into ``x`` and the occupancy table."""
    V = data.V
    for v in range(V):
        old, new = x[n * V + v], row[v] + 1
        if old != new:
            if old >= 2:
                occ[v][old - 1] -= 1
            if new >= 2:
                occ[v][new - 1] += 1
            x[n * V + v] = new


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
    for n in _order(data, g):
        avail = _available(data, work, x, n)
        if data.method == EXACT:
            row = _row_exact(data, avail, n, g)
        elif data.method == COMPONENTWISE:
            row = _row_componentwise(data, avail, x, n, g)
        else:
            row = _row_mm(data, avail, n, g, data.method == MM_FIXED)
        if row is not None:
            _apply_row(data, work, x, n, row)


# ------------------------------------------------------------------------------ herded draw
class HerdData(NamedTuple):
    """The herded sampler's inputs (:func:`rankedassign.multisensor.prepare.herd_inputs`).

    Attributes
    ----------
    base : RefData
        The Gibbs sampler's prepared weights (the method among them).
    gate : list of list of list of bool, shape (P, V, K)
        ``gate[n][v][j]``: measurement ``j`` of sensor ``v`` can carry weight for row ``n``
        (``"exact"``: some tuple with ``j`` on sensor ``v`` has ``eta_n > 0``; MM:
        ``theta_n^(v)(j) > 0``; unused by ``"componentwise"``, whose gate is read from the
        row's other components), ``K = max M_v + 1``.
    K : int
        ``max M_v + 1``; the code of measurement ``j`` of sensor ``v`` in a key is ``v K + j``.
    keys : {"full", "shared"}
        What a key is (:class:`~rankedassign.engine.herding.Herding`).
    init : {"conditional", "zero", "uniform"}
        A new key's initial weights.
    capacity : int
        Keys a chain's table may hold.
    tally : list of int
        ``[keys created, fall-back draws]`` over the run, updated in place.
    """

    base: RefData
    gate: list
    K: int
    keys: str
    init: str
    capacity: int
    tally: list


class HerdWork(NamedTuple):
    """A herded chain's bookkeeping: the occupancy table and the key table."""

    occ: list      # occ[v][j]: rows holding measurement j of sensor v
    table: dict    # key -> list of weights


def new_herd_work(data: HerdData, x) -> HerdWork:
    """Bookkeeping of a herded chain in state ``x``: its occupancy table, an empty key table.

    Parameters
    ----------
    data : HerdData
    x : list of int, length P * V
        State, ``x[n * V + v] = gamma_n^(v) + 1``.

    Returns
    -------
    HerdWork

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign.multisensor.prepare import prepare_data
    >>> class Stub:
    ...     n_rows, n_sensors, n_meas = 1, 2, (1, 0)
    ...     log_eta_dead = np.zeros(1); log_eta_alive = np.zeros((1, 2, 1))
    ...     log_s = None; log_theta = None
    >>> base = RefData(prepare_data(Stub(), "exact", "systematic", 1))
    >>> new_herd_work(HerdData(base, [], 2, "shared", "zero", 4, [0, 0]), [2, 1])
    HerdWork(occ=[[0, 1], [0]], table={})
    """
    return HerdWork(new_work(data.base, x), {})


def herd_key(data: HerdData, x, occ, n, stage, sensors) -> tuple:
    """The key of draw ``stage`` of row ``n`` (0: the row, or MM's dead/alive; ``1 + v``:
    sensor ``v``'s component).

    Parameters
    ----------
    data : HerdData
    x : list of int, length P * V
        The state before row ``n``'s update.
    occ : list of list of int
        Its occupancy table.
    n, stage : int
        The row and the draw.
    sensors : iterable of int
        The sensors whose held measurements the draw's conditional depends on.

    Returns
    -------
    tuple
        ``(n (V + 1) + stage,)`` followed, for ``"full"`` keys, by ``x`` with row ``n``'s
        positions ``-1`` (the other rows' whole state ``γ_{-n}``), or, for ``"shared"``
        keys, by the codes ``v K + j`` (increasing) of the measurements ``j`` of the
        ``sensors`` that another row holds and that are gated for row ``n``
        (``gate[n][v][j]``): the statistic of the other rows that the conditional depends
        on, since a measurement that cannot carry weight for row ``n`` changes no weight of
        its conditional when it is taken.

    Examples
    --------
    >>> d = HerdData(None, [[[False, True]], [[False, False]]], 2, "shared", "zero", 9, [0, 0])
    >>> d = d._replace(base=type("B", (), {"V": 1, "P": 2, "n_meas": [1]})())
    >>> herd_key(d, [1, 2], [[0, 1]], 0, 0, [0])     # row 1 holds measurement 1
    (0, 1)
    >>> herd_key(d._replace(keys="full"), [1, 2], [[0, 1]], 0, 0, [0])
    (0, -1, 2)
    """
    base = data.base
    V = base.V
    rid = n * (V + 1) + stage
    if data.keys == "full":
        return (rid,) + tuple(-1 if r // V == n else x[r] for r in range(base.P * V))
    codes = []
    for v in sensors:
        own = x[n * V + v] - 1
        for j in range(1, base.n_meas[v] + 1):
            if occ[v][j] > 0 and own != j and data.gate[n][v][j]:
                codes.append(v * data.K + j)
    return (rid,) + tuple(codes)


def _component_key(data: HerdData, x, occ, row, n, v, base_off):
    """The key of component ``v`` of row ``n`` (``"componentwise"``): ``γ`` but that
    component (``"full"``), or the row's other components and the measurements of sensor ``v``
    that other rows hold and that carry weight beside those components (``"shared"``)."""
    base = data.base
    V = base.V
    rid = n * (V + 1) + 1 + v
    if data.keys == "full":
        key = [x[r] for r in range(base.P * V)]
        for w in range(V):
            key[n * V + w] = -1 if w == v else row[w] + 1
        return (rid,) + tuple(key)
    codes = [row[w] for w in range(V) if w != v]
    own = x[n * V + v] - 1
    la, sv = base.la[n], base.strides[v]
    for j in range(1, base.n_meas[v] + 1):
        if occ[v][j] > 0 and own != j and la[base_off + j * sv] > NEG_INF:
            codes.append(v * data.K + j)
    return (rid,) + tuple(codes)


def _stage_conditional(weights, logs):
    """A draw's conditional over its available candidates: ``w / total`` (``w * (1 / total)``),
    or on underflow the exact weights ``exp(l - max l)`` normalised; None if none is positive."""
    total = 0.0
    for w in weights:
        total += w
    if total > 0.0:
        inv = 1.0 / total
        return [w * inv for w in weights]
    m = NEG_INF
    for lw in logs:
        if lw > m:
            m = lw
    if m == NEG_INF:
        return None
    e = [math.exp(lw - m) for lw in logs]
    total = 0.0
    for w in e:
        total += w
    return [w / total for w in e]


def _herd_stage(data: HerdData, work: HerdWork, key, cands, weights, logs, K, g):
    """One herded draw over ``K`` candidates, of which ``cands`` are available with the
    Gibbs ``weights``/``logs``: the candidate, ``-1`` if none has weight, or the Gibbs draw
    of the same lists when the key is new and the table full (one uniform, :func:`draw`)."""
    pc = _stage_conditional(weights, logs)
    if pc is None:
        return -1
    p = [0.0] * K
    for c, k in enumerate(cands):
        p[k] = pc[c]
    k = herd_choice(work.table, key, p, data.init, data.capacity, data.tally, g)
    if k is None:  # the table is full: an ordinary Gibbs draw
        c = draw(weights, logs, g.uniform())
        k = -1 if c < 0 else cands[c]
    return k


def _herd_row_exact(data: HerdData, work: HerdWork, x, n, avail, g):
    """Row ``n`` herded over its joint candidates: dead (0), tuple ``t`` (``1 + offset(t)``)."""
    base = data.base
    V = base.V
    _, offsets = exact_candidates(base, avail)
    Wa, la, st = base.Wa[n], base.la[n], base.strides
    weights = [base.Wd[n]] + [Wa[off] for off in offsets]
    logs = [base.ld[n]] + [la[off] for off in offsets]
    cands = [0] + [1 + off for off in offsets]
    key = herd_key(data, x, work.occ, n, 0, range(V))
    k = _herd_stage(data, work, key, cands, weights, logs, 1 + len(Wa), g)
    if k < 0:
        return None
    if k == 0:
        return [-1] * V
    return [(k - 1) // st[v] % (base.n_meas[v] + 1) for v in range(V)]


def _herd_row_mm(data: HerdData, work: HerdWork, x, n, avail, g, fixed):
    """Row ``n`` herded as MM does it: dead/alive (draw 0), then each sensor's component."""
    base = data.base
    V = base.V
    if fixed:  # dead with probability Q_n, whatever the other rows hold
        q = base.qdead[n]
        k = herd_choice(work.table, herd_key(data, x, work.occ, n, 0, ()), [q, 1.0 - q],
                        data.init, data.capacity, data.tally, g)
        dead = (g.uniform() < q) if k is None else k == 0
    else:
        alive = _mm_alive(base, avail, n)
        la = 0.0 if base.Ed[n] + alive > 0.0 else _mm_log_alive(base, avail, n)
        key = herd_key(data, x, work.occ, n, 0, range(V))
        k = _herd_stage(data, work, key, [0, 1], [base.Ed[n], alive], [base.ld[n], la], 2, g)
        if k < 0:
            return None
        dead = k == 0
    if dead:
        return [-1] * V
    row = []
    for v in range(V):
        Th, lth = base.Th[n][v], base.lth[n][v]
        key = herd_key(data, x, work.occ, n, 1 + v, (v,))
        k = _herd_stage(data, work, key, avail[v], [Th[j] for j in avail[v]],
                        [lth[j] for j in avail[v]], base.n_meas[v] + 1, g)
        if k < 0:  # mm-fixed only: the alive branch is infeasible here
            return [-1] * V if base.ld[n] > NEG_INF else None
        row.append(k)
    return row


def _herd_row_componentwise(data: HerdData, work: HerdWork, x, n, avail, g):
    """Row ``n``'s components herded in turn, each from its exact conditional under ``eta'``."""
    base = data.base
    V = base.V
    st = base.strides
    row = [x[n * V + v] - 1 for v in range(V)]
    Wa, la = base.Wa[n], base.la[n]
    for v in range(V):
        off = 0
        for w in range(V):
            if w != v:
                off += row[w] * st[w]
        key = _component_key(data, x, work.occ, row, n, v, off)
        k = _herd_stage(data, work, key, avail[v], [Wa[off + j * st[v]] for j in avail[v]],
                        [la[off + j * st[v]] for j in avail[v]], base.n_meas[v] + 1, g)
        if k >= 0:
            row[v] = k
    return row


def herd_sweep(data: HerdData, work: HerdWork, x, g) -> None:
    """One herded sweep over all rows, updating ``x`` and ``work`` in place.

    Parameters
    ----------
    data : HerdData
    work : HerdWork
        The chain's bookkeeping (:func:`new_herd_work`).
    x : list of int, length P * V
        State (``gamma + 1`` per row and sensor).
    g : SplitMix64
        The chain's stream (a random scan, uniform initial weights, fall-backs).

    Notes
    -----
    Rows are visited as in :func:`sweep`. Each *draw* of a row update is herded
    (:func:`rankedassign.engine.reference.herd_choice`) with the key of :func:`herd_key`:

    * ``"exact"``: one draw per row over dead and every tuple (``1 + T`` candidates, the
      unavailable ones of probability 0), with the conditional of spec eq. 2.1;
    * ``"mm"``: the dead/alive draw (its conditional depends on the held measurements of
      every sensor), then one draw per sensor ``v`` over ``0..M_v`` (depends on the held
      measurements of sensor ``v`` only); ``"mm-fixed"``: the same, but the dead/alive draw
      is ``(Q_n, 1 - Q_n)`` whatever the other rows hold, so its shared key is the row alone;
    * ``"componentwise"``: one draw per component, keyed also by the row's other components.

    A draw whose conditional has no positive candidate is not herded and behaves as in
    :func:`sweep` (the row stays, or MM-fixed's infeasible alive branch makes it dead). A
    draw whose key is new while the table is full is the Gibbs sampler's draw of the same
    candidates (one uniform) and is counted as a fall-back.

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign.engine.rng import SplitMix64
    >>> from rankedassign.multisensor.prepare import prepare_data
    >>> class Stub:
    ...     n_rows, n_sensors, n_meas = 1, 1, (1,)
    ...     log_eta_dead = np.log([0.5]); log_eta_alive = np.log([[0.25, 0.25]])
    ...     log_s = None; log_theta = None
    >>> base = RefData(prepare_data(Stub(), "exact", "systematic", 1))
    >>> data = HerdData(base, [[[True, True]]], 2, "shared", "zero", 8, [0, 0])
    >>> x = [1]
    >>> work = new_herd_work(data, x)
    >>> seen = []
    >>> for _ in range(4):
    ...     herd_sweep(data, work, x, SplitMix64(0))
    ...     seen.append(x[0])
    >>> seen, data.tally          # dead, missed, measurement 1 in proportion 2 : 1 : 1
    ([0, 1, 2, 0], [1, 0])
    """
    base = data.base
    for n in _order(base, g):
        avail = _available(base, work.occ, x, n)
        if base.method == EXACT:
            row = _herd_row_exact(data, work, x, n, avail, g)
        elif base.method == COMPONENTWISE:
            row = _herd_row_componentwise(data, work, x, n, avail, g)
        else:
            row = _herd_row_mm(data, work, x, n, avail, g, base.method == MM_FIXED)
        if row is not None:
            _apply_row(base, work.occ, x, n, row)

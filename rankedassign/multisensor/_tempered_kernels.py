"""numba row functions of the multi-sensor tempered Gibbs sampler (clean inputs only).

Twins, operation for operation, of :func:`rankedassign.multisensor.tempered.tempered_weights`,
:func:`~rankedassign.multisensor.tempered.tempered_move` and
:func:`~rankedassign.multisensor.tempered.tempered_accumulate`, compiled into the loop of
:mod:`rankedassign.engine._tempered_kernels` (:data:`KERNELS`).

``data`` is a :class:`MultiSensorTemperedData`, ``work`` a :class:`MultiSensorTemperedWork`
(both built by :func:`rankedassign.multisensor.tempered.sample_tempered`).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ..engine._kernels import next_uniform
from ..engine._tempered_kernels import make_tempered, store_ratio
from ..numba_options import jit

__all__ = ["occupancy", "row_weights", "move", "accumulate", "KERNELS",
           "MultiSensorTemperedData", "MultiSensorTemperedWork"]


class MultiSensorTemperedData(NamedTuple):
    """The tempered kernels' inputs (shifted per row; ``T = prod_v (M_v + 1)``).

    Attributes
    ----------
    n_meas, strides : ndarray, shape (V,), int64
        ``M_v`` and the C-order strides of the tuple axes.
    Wd, Wbd, Rd : ndarray, shape (P,), float64
        ``W``, ``W^beta`` and ``W^(beta - 1)`` of dead.
    Wa, Wba, Ra : ndarray, shape (P, T), float64
        The same of every tuple.
    """

    n_meas: np.ndarray
    strides: np.ndarray
    Wd: np.ndarray
    Wbd: np.ndarray
    Rd: np.ndarray
    Wa: np.ndarray
    Wba: np.ndarray
    Ra: np.ndarray


class MultiSensorTemperedWork(NamedTuple):
    """The tempered kernels' workspace (``K = max_v M_v + 1``).

    Attributes
    ----------
    occ : ndarray, shape (V, K), int64
        Rows holding measurement ``j`` of sensor ``v``.
    avail : ndarray, shape (V, K), int64
        ``A_n^(v)`` of the row at hand (the first ``navail`` entries).
    navail : ndarray, shape (V,), int64
        Their number.
    idx : ndarray, shape (V,), int64
        Odometer over the product of the ``A_n^(v)``.
    Sb : ndarray, shape (P,), float64
        Each row's sum of ``W^beta`` over its available candidates.
    row : ndarray, shape (V,), int64
        The moved row's new ``gamma``.
    """

    occ: np.ndarray
    avail: np.ndarray
    navail: np.ndarray
    idx: np.ndarray
    Sb: np.ndarray
    row: np.ndarray


@jit()
def occupancy(occ, x0):
    """The occupancy table ``occ`` (V, K) of the state ``x0`` (``gamma + 1`` per row, sensor).

    Parameters
    ----------
    occ : ndarray of int64, shape (V, K)
        Overwritten: rows holding measurement ``j`` of sensor ``v``.
    x0 : ndarray of int32, shape (P * V,)
        The state.

    Examples
    --------
    >>> import numpy as np
    >>> occ = np.zeros((2, 3), np.int64)
    >>> occupancy(occ, np.array([2, 3, 1, 1], np.int32))
    >>> occ.tolist()
    [[0, 1, 0], [0, 0, 1]]
    """
    V = occ.shape[0]
    occ[:, :] = 0
    for i in range(x0.shape[0]):
        if x0[i] >= 2:
            occ[i % V, x0[i] - 1] += 1


@jit()
def _available(n_meas, occ, state, n, avail, navail):
    """``A_n^(v)`` for every sensor: missed, and the measurements free of the other rows.

    Parameters
    ----------
    n_meas : ndarray of int64, shape (V,)
        ``M_v``.
    occ : ndarray of int64, shape (V, K)
        The occupancy table of ``state``.
    state : ndarray of int32, shape (P * V,)
        The state (``gamma + 1``).
    n : int
        The row.
    avail : ndarray of int64, shape (V, K)
        Receives the available entries (entry 0 missed, 0).
    navail : ndarray of int64, shape (V,)
        Receives their numbers.
    """
    V = n_meas.shape[0]
    for v in range(V):
        own = state[n * V + v] - 1
        avail[v, 0] = 0
        c = 1
        for j in range(1, n_meas[v] + 1):
            if occ[v, j] == 0 or own == j:
                avail[v, c] = j
                c += 1
        navail[v] = c


@jit()
def _code(strides, state, n, V):
    """Candidate code of row ``n``: 0 dead, ``1 + offset`` of its tuple.

    Parameters
    ----------
    strides : ndarray of int64, shape (V,)
        C-order strides of the tuple axes.
    state : ndarray of int32, shape (P * V,)
        The state (``gamma + 1``).
    n : int
        The row.
    V : int
        Sensors.

    Returns
    -------
    int
    """
    if state[n * V] == 0:
        return 0
    off = 0
    for v in range(V):
        off += (state[n * V + v] - 1) * strides[v]
    return 1 + off


@jit()
def _advance(idx, navail, V):
    """Next digit vector of the odometer (last sensor fastest); False when it wrapped.

    Parameters
    ----------
    idx : ndarray of int64, shape (V,)
        The digits, advanced in place (all zero again when it wrapped).
    navail : ndarray of int64, shape (V,)
        Each digit's base.
    V : int
        Sensors.

    Returns
    -------
    bool
    """
    v = V - 1
    while v >= 0:
        idx[v] += 1
        if idx[v] < navail[v]:
            return True
        idx[v] = 0
        v -= 1
    return False


@jit()
def row_weights(data, work, state, p):
    """``p[n] = (R(gamma_n) S_n) / Sb_n`` for every row; ``Z`` or -1.0 (not representable).

    The kind's ``row_weights`` (:mod:`rankedassign.engine._tempered_kernels`).

    Parameters
    ----------
    data : MultiSensorTemperedData
        The call's weights.
    work : MultiSensorTemperedWork
        ``occ`` the occupancy of ``state``; ``Sb`` written.
    state : ndarray of int32, shape (P * V,)
        The state (``gamma + 1``).
    p : ndarray of float64, shape (P,)
        Receives the ratios.

    Returns
    -------
    float
        ``Z``, summed left to right, or -1.0.
    """
    n_meas, strides, Wd, Wbd, Wa, Wba = (data.n_meas, data.strides, data.Wd, data.Wbd,
                                         data.Wa, data.Wba)
    Rd, Ra = data.Rd, data.Ra
    occ, avail, navail, idx, Sb = work.occ, work.avail, work.navail, work.idx, work.Sb
    P = Wd.shape[0]
    V = n_meas.shape[0]
    Z = 0.0
    for n in range(P):
        _available(n_meas, occ, state, n, avail, navail)
        s = Wd[n]
        sb = Wbd[n]
        for v in range(V):
            idx[v] = 0
        while True:  # the available tuples in C order
            off = 0
            for v in range(V):
                off += avail[v, idx[v]] * strides[v]
            s += Wa[n, off]
            sb += Wba[n, off]
            if not _advance(idx, navail, V):
                break
        if not (s > 0.0 and sb > 0.0):
            return -1.0
        k = _code(strides, state, n, V)
        rr = Rd[n] if k == 0 else Ra[n, k - 1]
        ratio = store_ratio(p, Sb, n, rr, s, sb)
        if ratio < 0.0:
            return -1.0
        Z += ratio
    return Z


@jit()
def move(data, work, zkeys, state, r, h, rs):
    """Row ``r`` drawn from its tempered conditional; ``(hash, changed)``.

    The kind's ``move`` (:mod:`rankedassign.engine._tempered_kernels`).

    Parameters
    ----------
    data : MultiSensorTemperedData
        The call's weights.
    work : MultiSensorTemperedWork
        ``Sb`` from :func:`row_weights`; ``occ`` updated.
    zkeys : ndarray of uint64, shape (P * V, K)
        Zobrist keys.
    state : ndarray of int32, shape (P * V,)
        Updated in place.
    r : int
        The row.
    h : np.uint64
        The hash of ``state``.
    rs : ndarray of uint64, shape (1,)
        The stream state (one uniform).

    Returns
    -------
    (np.uint64, bool)
        The new hash and whether a position changed.
    """
    n_meas, strides, Wbd, Wba = data.n_meas, data.strides, data.Wbd, data.Wba
    occ, avail, navail, idx, Sb, row = (work.occ, work.avail, work.navail, work.idx, work.Sb,
                                        work.row)
    V = n_meas.shape[0]
    _available(n_meas, occ, state, r, avail, navail)
    # the inverse CDF of reference.pick: dead (code 0), then the available tuples (1 + off)
    target = next_uniform(rs) * Sb[r]
    acc = 0.0
    last = -1
    code = -1
    wk = Wbd[r]
    if wk > 0.0:
        acc += wk
        last = 0
        if acc > target:
            code = 0
    if code < 0:
        for v in range(V):
            idx[v] = 0
        while True:
            off = 0
            for v in range(V):
                off += avail[v, idx[v]] * strides[v]
            wk = Wba[r, off]
            if wk > 0.0:
                acc += wk
                last = 1 + off
                if acc > target:
                    code = 1 + off
                    break
            if not _advance(idx, navail, V):
                break
    if code < 0:
        code = last
    if code == 0:
        for v in range(V):
            row[v] = -1
    else:
        for v in range(V):
            row[v] = ((code - 1) // strides[v]) % (n_meas[v] + 1)
    changed = False
    for v in range(V):
        pos = r * V + v
        old = state[pos]
        new = row[v] + 1
        if old != new:
            if old >= 2:
                occ[v, old - 1] -= 1
            if new >= 2:
                occ[v, new - 1] += 1
            h ^= zkeys[pos, old] ^ zkeys[pos, new]
            state[pos] = new
            changed = True
    return h, changed


@jit()
def accumulate(data, work, state, acc, w):
    """``acc[n, code(gamma_n)] += w`` for every row.

    Parameters
    ----------
    data : MultiSensorTemperedData
        The call's weights (``strides``).
    work : MultiSensorTemperedWork
        Unused.
    state : ndarray of int32, shape (P * V,)
        The state.
    acc : ndarray of float64, shape (P, 1 + T)
        The accumulator: column 0 dead, ``1 + offset`` a tuple.
    w : float
        The state's importance weight.
    """
    strides = data.strides
    V = strides.shape[0]
    for n in range(acc.shape[0]):
        acc[n, _code(strides, state, n, V)] += w


#: The tempered loop compiled for the multi-sensor row functions: ``(start, steps)``.
KERNELS = make_tempered("multisensor", row_weights, move, accumulate)

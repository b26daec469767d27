"""The single-sensor row functions of the tempered Gibbs sampler of Zanella & Roberts (numba;
clean inputs only: validate in :mod:`.tempered`).

The loop is the engine's (:func:`rankedassign.engine._tempered_kernels.make_tempered`: the row
choice, the weights, the unique set, the slices); this module gives it the single-sensor
kind's ``row_weights``, ``move`` and ``accumulate``. Each row keeps the sums of its available
weights and tempered weights (:class:`SingleTemperedWork`), updated by the measurement a move
releases and the one it takes, so a move costs ``O(P + M)``. Together they mirror
:func:`rankedassign.single.tempered.tempered_reference` operation for operation (same sums in
the same order, one SplitMix64 stream), so both give the same bits.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ..engine._kernels import next_uniform
from ..engine._tempered_kernels import make_tempered
from ..numba_options import jit
from .prepare import CANCEL_GUARD


class SingleTemperedData(NamedTuple):
    """The tempered kernel's inputs (:func:`rankedassign.single.tempered.sample_tempered`).

    Attributes
    ----------
    W : ndarray, shape (P, M + 2), float64
        Shifted weights (:func:`rankedassign.single.prepare.shifted_weights`).
    Wb : ndarray, shape (P, M + 2), float64
        ``W^beta`` (shifted per row).
    R : ndarray, shape (P, M + 2), float64
        ``W^(beta - 1)``, the ratio ``g / pi`` up to the row sums.
    refresh : int
        The row sums are formed again every ``refresh`` moves.
    """

    W: np.ndarray
    Wb: np.ndarray
    R: np.ndarray
    refresh: int


class SingleTemperedWork(NamedTuple):
    """The single-sensor workspace of a tempered run, kept between the engine's slices.

    Attributes
    ----------
    free : ndarray, shape (M,), float64
        Free-measurement mask of the run's state.
    S, Sb : ndarray, shape (P,), float64
        Every row's sums of ``W`` and ``Wb`` over its available candidates.
    ctr : ndarray, shape (2,), int64
        ``[moves made, underflow]``: the moves count the refresh of the sums; ``underflow`` is
        set by :func:`move` when a row's available tempered weights all underflowed.
    """

    free: np.ndarray
    S: np.ndarray
    Sb: np.ndarray
    ctr: np.ndarray


@jit()
def _row_sums(W, Wb, free, state, i):
    """Row ``i``'s sums of ``W`` and ``Wb`` over its available candidates (the measurements no
    other row holds, its own included; missed; dead), left to right.

    Parameters
    ----------
    W, Wb : ndarray of float64, shape (P, M + 2)
        Shifted weights and their tempered power (:class:`SingleTemperedData`).
    free : ndarray of float64, shape (M,)
        Free-measurement mask of ``state``.
    state : ndarray of int32, shape (P,)
        The chain's compact state.
    i : int
        The row.

    Returns
    -------
    (float, float)
        The sums of ``W`` and of ``Wb``.
    """
    M = W.shape[1] - 2
    s = 0.0
    sb = 0.0
    own = state[i]
    for k in range(M):
        f = 1.0 if k == own else free[k]
        s += W[i, k] * f
        sb += Wb[i, k] * f
    s = (s + W[i, M]) + W[i, M + 1]
    sb = (sb + Wb[i, M]) + Wb[i, M + 1]
    return s, sb


@jit()
def _weights(R, S, Sb, state, p):
    """``p[i] = R[i, x_i] * S[i] / Sb[i]``; return their sum (or -1.0 if one is not finite).

    Parameters
    ----------
    R : ndarray of float64, shape (P, M + 2)
        ``W^(beta - 1)`` (:class:`SingleTemperedData`).
    S, Sb : ndarray of float64, shape (P,)
        Every row's sums (:func:`_row_sums`).
    state : ndarray of int32, shape (P,)
        The chain's compact state.
    p : ndarray of float64, shape (P,)
        Filled with the rows' ratios.

    Returns
    -------
    float
        ``Z = Σ p``, or -1.0.
    """
    Z = 0.0
    for i in range(state.shape[0]):
        if not (S[i] > 0.0 and Sb[i] > 0.0):  # every available weight underflowed
            return -1.0
        v = (R[i, state[i]] * S[i]) / Sb[i]
        if not (v >= 0.0 and v < np.inf):
            return -1.0
        p[i] = v
        Z += v
    return Z


@jit()
def init_work(data, work, state):
    """The workspace at the start ``state``: the free-measurement mask and every row's sums.

    Parameters
    ----------
    data : SingleTemperedData
        The call's weights.
    work : SingleTemperedWork
        Filled in place (``ctr`` zeroed).
    state : ndarray of int32, shape (P,)
        The start state (compact).

    Examples
    --------
    >>> import numpy as np
    >>> W = np.array([[1.0, 0.5, 0.25]])
    >>> data = SingleTemperedData(W=W, Wb=W, R=np.ones_like(W), refresh=3)
    >>> work = SingleTemperedWork(free=np.empty(1), S=np.empty(1), Sb=np.empty(1),
    ...                           ctr=np.ones(2, np.int64))
    >>> init_work(data, work, np.array([0], np.int32))
    >>> work.free.tolist(), work.S.tolist(), work.ctr.tolist()
    ([0.0], [1.75], [0, 0])
    """
    W, Wb = data.W, data.Wb
    free, S, Sb = work.free, work.S, work.Sb
    M = W.shape[1] - 2
    free[:] = 1.0
    for i in range(state.shape[0]):
        if state[i] < M:
            free[state[i]] = 0.0
    for i in range(state.shape[0]):
        S[i], Sb[i] = _row_sums(W, Wb, free, state, i)
    work.ctr[0] = 0
    work.ctr[1] = 0


@jit()
def row_weights(data, work, state, p):
    """The kind's ``row_weights`` (:mod:`rankedassign.engine._tempered_kernels`): every row's
    ratio from the sums the moves keep; ``Z``, or -1.0 (not representable).

    Parameters
    ----------
    data : SingleTemperedData
        The call's weights.
    work : SingleTemperedWork
        The sums of ``state`` (:func:`init_work`, :func:`move`).
    state : ndarray of int32, shape (P,)
        The chain's compact state.
    p : ndarray of float64, shape (P,)
        Receives the ratios.

    Returns
    -------
    float
        ``Z = Σ p``, or -1.0 (also after a move whose row underflowed).
    """
    if work.ctr[1] != 0:
        return -1.0
    return _weights(data.R, work.S, work.Sb, state, p)


@jit()
def move(data, work, zkeys, state, r, h, rs):
    """The kind's ``move``: row ``r`` drawn from its tempered conditional (inverse CDF over its
    available ``Wb``), the sums updated by the measurement released and the one taken.

    Every move reports a change: the sums move by floating-point additions even when the row
    keeps its value, so the ratios are formed again after every move, as the specification
    (:func:`rankedassign.single.tempered.tempered_reference`) does. The sums are formed anew
    every ``refresh`` moves, and where a subtraction cancels (``CANCEL_GUARD``).

    Parameters
    ----------
    data : SingleTemperedData
        The call's weights.
    work : SingleTemperedWork
        Updated in place; ``ctr[1]`` set when the row's available weights underflowed.
    zkeys : ndarray of uint64, shape (P, M + 2)
        Zobrist keys.
    state : ndarray of int32, shape (P,)
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
        The new hash and ``True``.
    """
    W, Wb, refresh = data.W, data.Wb, data.refresh
    free, S, Sb, ctr = work.free, work.S, work.Sb, work.ctr
    P = state.shape[0]
    M = W.shape[1] - 2
    K = M + 2
    # release its measurement: available again to the other rows
    a = state[r]
    if a < M:
        free[a] = 1.0
        for i in range(P):
            if i != r:
                S[i] += W[i, a]
                Sb[i] += Wb[i, a]
    tot = 0.0
    for k in range(M):
        tot += Wb[r, k] * free[k]
    tot = (tot + Wb[r, M]) + Wb[r, M + 1]
    if not tot > 0.0:
        ctr[1] = 1
        return h, True
    u = next_uniform(rs) * tot
    c = -1
    csum = 0.0
    for k in range(K):
        wk = Wb[r, k] * free[k] if k < M else Wb[r, k]
        if wk > 0.0:
            csum += wk
            c = k
            if csum > u:
                break
    if c < M:
        free[c] = 0.0
        for i in range(P):
            if i != r:
                before = S[i]
                beforeb = Sb[i]
                S[i] -= W[i, c]
                Sb[i] -= Wb[i, c]
                if S[i] < CANCEL_GUARD * before or Sb[i] < CANCEL_GUARD * beforeb:
                    S[i], Sb[i] = _row_sums(W, Wb, free, state, i)
    if c != a:
        h ^= zkeys[r, a] ^ zkeys[r, c]
        state[r] = c
    ctr[0] += 1
    if ctr[0] % refresh == 0:
        for i in range(P):
            S[i], Sb[i] = _row_sums(W, Wb, free, state, i)
    return h, True


@jit()
def accumulate(data, work, state, acc, w):
    """The kind's ``accumulate``: ``acc[i, x_i] += w`` for every row.

    Parameters
    ----------
    data : SingleTemperedData
        Unused.
    work : SingleTemperedWork
        Unused.
    state : ndarray of int32, shape (P,)
        The state.
    acc : ndarray of float64, shape (P, M + 2)
        The marginal accumulator.
    w : float
        The state's importance weight.
    """
    for i in range(state.shape[0]):
        acc[i, state[i]] += w


#: The tempered loop compiled for the single-sensor row functions: ``(start, steps)``.
KERNELS = make_tempered("single", row_weights, move, accumulate)

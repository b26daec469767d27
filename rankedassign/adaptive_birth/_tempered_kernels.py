"""numba row functions of the adaptive-birth tempered Gibbs sampler (clean inputs only).

Twins, operation for operation, of
:func:`rankedassign.adaptive_birth.tempered.tempered_weights`,
:func:`~rankedassign.adaptive_birth.tempered.tempered_move` and
:func:`~rankedassign.adaptive_birth.tempered.tempered_accumulate`, compiled into the loop of
:mod:`rankedassign.engine._tempered_kernels` (:data:`KERNELS`). The log-weights of a sensor's
conditional are those of the Gibbs kernel (:mod:`rankedassign.adaptive_birth._kernels`: the
tensor read, or its information sums and ratio form).

``data`` is an :class:`AdaptiveBirthTemperedData` (the Gibbs inputs of
:func:`rankedassign.adaptive_birth.prepare.chain_inputs` and ``beta``), ``work`` an
:class:`AdaptiveBirthTemperedWork`.
"""

from __future__ import annotations

import math

import numpy as np

from ..engine._kernels import next_uniform
from ..engine._tempered_kernels import make_tempered, store_ratio
from ..engine.records import record
from ..multisensor._kernels import pick
from ..numba_options import jit
from ._kernels import RowScratch, _log_weights, _sums
from .prepare import AdaptiveBirthData

__all__ = ["row_weights", "move", "accumulate", "KERNELS", "AdaptiveBirthTemperedData",
           "AdaptiveBirthTemperedWork"]


class AdaptiveBirthTemperedData(record(AdaptiveBirthData, {"beta": float})):
    """The tempered kernels' inputs: the fields of
    :class:`~rankedassign.adaptive_birth.prepare.AdaptiveBirthData`, then ``beta``.

    One flat record, so that the Gibbs kernel's functions read it as they read the Gibbs
    inputs.

    Attributes
    ----------
    mode, V, n, random_order, shape, off, strides, logw, M0, b0, c0, A, a, cz, const, log_miss
        As in :class:`~rankedassign.adaptive_birth.prepare.AdaptiveBirthData`.
    beta : float
        Inverse temperature.
    """


class AdaptiveBirthTemperedWork(record(RowScratch, {"Wb": np.ndarray, "Sb": np.ndarray})):
    """The tempered kernels' workspace: the Gibbs scratch of one chain and the tempered
    weights (``K = max_s (M_s + 1)``).

    Attributes
    ----------
    M, b, c, Mp, L, y, bj, lw : ndarray
        The row update's scratch (:class:`~rankedassign.adaptive_birth._kernels.RowScratch`).
    Wb : ndarray, shape (V, K), float64
        Each sensor's tempered weights.
    Sb : ndarray, shape (V,), float64
        Their sums.
    """


@jit()
def row_weights(data, work, state, p):
    """``p[s]`` for every sensor (and ``Wb``, ``Sb`` into ``work``); ``Z`` or -1.0.

    The kind's ``row_weights`` (:mod:`rankedassign.engine._tempered_kernels`): a "row" is a
    sensor.

    Parameters
    ----------
    data : AdaptiveBirthTemperedData
        The call's data.
    work : AdaptiveBirthTemperedWork
        Scratch; ``Wb`` and ``Sb`` written.
    state : ndarray of int32, shape (V,)
        The tuple ``J``.
    p : ndarray of float64, shape (V,)
        Receives the ratios.

    Returns
    -------
    float
        ``Z``, summed left to right, or -1.0 when a ratio is not representable.
    """
    V = data.V
    shape = data.shape
    beta = data.beta
    M, b, c, Mp, L, y, bj, lw = (work.M, work.b, work.c, work.Mp, work.L, work.y, work.bj,
                                 work.lw)
    Wb, Sb = work.Wb, work.Sb
    gaussian = data.mode == 1
    Z = 0.0
    for s in range(V):
        K = shape[s]
        if gaussian:
            _sums(data, M, b, c, state)
        _log_weights(data, M, b, c, Mp, L, y, bj, lw, state, s)
        mx = lw[0]
        for j in range(K):
            if lw[j] > mx:
                mx = lw[j]
        S = 0.0
        sb = 0.0
        for j in range(K):
            S += math.exp(lw[j] - mx)
            e = math.exp(beta * (lw[j] - mx))
            Wb[s, j] = e
            sb += e
        rr = math.exp((1.0 - beta) * (mx - lw[state[s]]))
        ratio = store_ratio(p, Sb, s, rr, S, sb)
        if ratio < 0.0:
            return -1.0
        Z += ratio
    return Z


@jit()
def move(data, work, zkeys, state, r, h, rs):
    """Sensor ``r``'s entry drawn from its tempered conditional; ``(hash, changed)``.

    Parameters
    ----------
    data : AdaptiveBirthTemperedData
        The call's data.
    work : AdaptiveBirthTemperedWork
        ``Wb`` and ``Sb`` from :func:`row_weights`.
    zkeys : ndarray of uint64, shape (V, K)
        Zobrist keys.
    state : ndarray of int32, shape (V,)
        Updated in place.
    r : int
        The sensor.
    h : np.uint64
        The hash of ``state``.
    rs : ndarray of uint64, shape (1,)
        The stream state (one uniform).

    Returns
    -------
    (np.uint64, bool)
        The new hash and whether the entry changed.
    """
    # the first entry whose running sum of the positive Wb[r] exceeds u Sb[r], else the last
    k = pick(work.Wb, r, data.shape[r], work.Sb[r], next_uniform(rs))
    old = state[r]
    if k == old:
        return h, False
    h ^= zkeys[r, old] ^ zkeys[r, k]
    state[r] = k
    return h, True


@jit()
def accumulate(data, work, state, acc, w):
    """``acc[s, state[s]] += w`` for every sensor.

    Parameters
    ----------
    data, work
        Unused.
    state : ndarray of int32, shape (V,)
        The tuple.
    acc : ndarray of float64, shape (V, K)
        The accumulator.
    w : float
        The state's importance weight.
    """
    for s in range(state.shape[0]):
        acc[s, state[s]] += w


#: The tempered loop compiled for the adaptive-birth row functions: ``(start, steps)``.
KERNELS = make_tempered("adaptive_birth", row_weights, move, accumulate)

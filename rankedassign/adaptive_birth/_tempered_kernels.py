"""numba row functions of the adaptive-birth tempered Gibbs sampler (clean inputs only).

Twins, operation for operation, of
:func:`rankedassign.adaptive_birth.tempered.tempered_weights`,
:func:`~rankedassign.adaptive_birth.tempered.tempered_move` and
:func:`~rankedassign.adaptive_birth.tempered.tempered_accumulate`, compiled into the loop of
:mod:`rankedassign.engine._tempered_kernels` (:data:`KERNELS`). The log-weights of a sensor's
conditional are those of the Gibbs kernel (:mod:`rankedassign.adaptive_birth._kernels`: the
tensor read, or its information sums and ratio form).

``data`` is the Gibbs data tuple of :func:`rankedassign.adaptive_birth.prepare.chain_inputs`
followed by ``beta``. ``work`` is ``(M, b, c, Mp, L, y, bj, lw, Wb, Sb)``: the Gibbs scratch
of one chain (``M``, ``Mp``, ``L`` (n, n); ``b``, ``y``, ``bj`` (n,); ``c`` (1,); ``lw``
(K,)), each sensor's tempered weights ``Wb`` (V, K) and their sums ``Sb`` (V,).
"""

from __future__ import annotations

import math

import numpy as np

from ..engine._kernels import next_uniform
from ..engine._tempered_kernels import make_tempered
from ..numba_options import jit
from ._kernels import _gaussian_weights, _sums

__all__ = ["row_weights", "move", "accumulate", "KERNELS"]


@jit()
def row_weights(data, work, state, p):
    """``p[s]`` for every sensor (and ``Wb``, ``Sb`` into ``work``); ``Z`` or -1.0."""
    V = data[1]
    shape, strides, logw = data[4], data[6], data[7]
    beta = data[16]
    M, b, c, Mp, L, y, bj, lw, Wb, Sb = work
    gaussian = data[0] == 1
    Z = 0.0
    for s in range(V):
        K = shape[s]
        if gaussian:
            _sums(data, M, b, c, state)
            _gaussian_weights(data, M, b, c, Mp, L, y, bj, lw, state, s)
        else:
            base = 0
            for v in range(V):
                if v != s:
                    base += state[v] * strides[v]
            for j in range(K):
                lw[j] = logw[base + j * strides[s]]
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
        ratio = (rr * S) / sb
        if not (ratio >= 0.0 and ratio < np.inf):
            return -1.0
        p[s] = ratio
        Sb[s] = sb
        Z += ratio
    return Z


@jit()
def move(data, work, zkeys, state, r, h, rs):
    """Sensor ``r``'s entry drawn from its tempered conditional; ``(hash, changed)``."""
    Wb, Sb = work[8], work[9]
    K = data[4][r]
    target = next_uniform(rs) * Sb[r]
    acc = 0.0
    k = -1
    for j in range(K):
        w = Wb[r, j]
        if w > 0.0:
            acc += w
            k = j
            if acc > target:
                break
    old = state[r]
    if k == old:
        return h, False
    h ^= zkeys[r, old] ^ zkeys[r, k]
    state[r] = k
    return h, True


@jit()
def accumulate(data, work, state, acc, w):
    """``acc[s, state[s]] += w`` for every sensor."""
    for s in range(state.shape[0]):
        acc[s, state[s]] += w


#: The tempered loop compiled for the adaptive-birth row functions: ``(start, steps)``.
KERNELS = make_tempered("adaptive_birth", row_weights, move, accumulate)

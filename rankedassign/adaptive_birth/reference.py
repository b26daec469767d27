"""Pure-Python row update of the adaptive-birth Gibbs sampler: the specification of record.

One sweep (spec ``multisensor.md`` §4.3) visits the ``V`` sensors in a fresh random order (or
``0..V-1``) and redraws each entry ``j^(s)`` of the tuple ``J`` from its conditional (spec
eq. 4.3)::

    pi_B(j^(s) = j | J^-s)  ∝  r_U^(s)(j) psibar_B(J^-s ⊕ j),     j = 0..M_s

The numba kernel :mod:`rankedassign.adaptive_birth._kernels` performs the same floating-point
operations in the same order, so both agree bit for bit:

* the random order: ``V - 1`` uniforms first, Fisher-Yates from the identity
  (``t = V-1..1``: ``k = min(floor(u (t + 1)), t)``, swap ``t`` and ``k``); ``0..V-1`` with
  ``sensor_order="fixed"`` (no uniform);
* per sensor, the ``M_s + 1`` log-weights below, then one uniform turned into a candidate by
  the sequential inverse-CDF loop of :func:`draw` over ``exp(lw - max lw)``.

Log-weights. From a tensor (``mode 0``): ``lw[j] = ln rho(J^-s ⊕ j)``, read from the flat
tensor. Linear-Gaussian (``mode 1``), the ratio form of spec §4.2 with running information
sums ``(M, b, c)`` over the prior and the detecting sensors (recomputed from ``J`` at the start
of every sweep, updated after each sensor)::

    (M-, b-, c-) = (M, b, c) minus sensor s's term if j^(s) > 0
    lw[0] = ln(1 - P_D^(s)) - ln|M-|/2 - (c- - |L-^-1 b-|^2)/2           L- = chol(M-)
    M+ = M- + A_s,  L+ = chol(M+)
    lw[j] = const_sj - ln|M+|/2 - (c- + cz_sj - |L+^-1 (b- + a_sj)|^2)/2   j >= 1

(``ln|M|/2 = sum_i ln L_ii``). The Cholesky factor and the forward substitution are written
out as plain loops (:func:`cholesky`, :func:`half_logdet`, :func:`quad`) so that both
implementations do the same operations; ``ln|M+|/2`` is computed once per update.

References
----------
.. [1] A. Trezza, D. J. Bucci Jr., P. K. Varshney, "Multi-sensor joint adaptive birth sampler
   for labeled random finite set tracking", IEEE Trans. Signal Process. 70, 2022.
"""

from __future__ import annotations

import math
from typing import NamedTuple

__all__ = ["RefData", "reference_data", "new_work", "sweep", "draw", "cholesky", "half_logdet",
           "quad", "conditional_log_weights"]


class RefData(NamedTuple):
    """The chain inputs of :func:`rankedassign.adaptive_birth.prepare.chain_inputs` as
    Python lists (exact copies of the float64 values)."""

    mode: int
    V: int
    n: int
    random_order: bool
    shape: list
    off: list
    strides: list
    logw: list
    M0: list
    b0: list
    c0: float
    A: list
    a: list
    cz: list
    const: list
    log_miss: list


def reference_data(data) -> RefData:
    """Convert the kernel's data tuple into :class:`RefData` (lists of Python numbers).

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign.adaptive_birth.prepare import AdaptiveBirthProblem, chain_inputs
    >>> d = reference_data(chain_inputs(AdaptiveBirthProblem.from_log_weights(np.zeros((2, 2)))))
    >>> d.mode, d.shape, d.strides
    (0, [2, 2], [2, 1])
    """
    vals = [x.tolist() if hasattr(x, "tolist") else x for x in data]
    vals[0], vals[1], vals[2] = int(vals[0]), int(vals[1]), int(vals[2])
    vals[3] = bool(vals[3])
    vals[10] = float(vals[10])
    return RefData(*vals)


class Work(NamedTuple):
    """Scratch of one chain: running information sums and the log-weights of one update."""

    M: list          # n x n running information matrix
    b: list          # n running information vector
    c: list          # [c], running scalar


def new_work(data: RefData, x) -> Work:
    """Scratch for a chain started at ``x`` (the sums are recomputed every sweep).

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign.adaptive_birth.prepare import AdaptiveBirthProblem, chain_inputs
    >>> d = reference_data(chain_inputs(AdaptiveBirthProblem.from_log_weights(np.zeros((2, 2)))))
    >>> len(new_work(d, [0, 0]).b)
    1
    """
    n = data.n
    return Work([[0.0] * n for _ in range(n)], [0.0] * n, [0.0])


def draw(lw, g) -> int:
    """Draw an index with probability ``∝ exp(lw[j])`` using one uniform of ``g``.

    Parameters
    ----------
    lw : list of float
        Log-weights, at least one finite (``-inf`` = weight 0).
    g : SplitMix64
        Advanced by exactly one draw.

    Returns
    -------
    int

    Notes
    -----
    ``W[j] = exp(lw[j] - max lw)`` (so ``max W = 1``, no underflow of the total), then the
    inverse CDF: the first ``j`` with ``W[0] + ... + W[j] > u * sum W`` among positive ``W``;
    if rounding leaves none, the last positive one.

    Examples
    --------
    >>> from rankedassign.engine.rng import SplitMix64
    >>> draw([float("-inf"), 0.0, float("-inf")], SplitMix64(0))
    1
    """
    mx = lw[0]
    for w in lw:
        if w > mx:
            mx = w
    W = [math.exp(w - mx) for w in lw]
    total = 0.0
    for w in W:
        total += w
    target = g.uniform() * total
    acc = 0.0
    last = 0
    for j, w in enumerate(W):
        if w > 0.0:
            acc += w
            last = j
            if acc > target:
                return j
    return last


def cholesky(M, n):
    """Lower Cholesky factor of the ``n x n`` list-of-lists ``M`` (plain loops).

    Examples
    --------
    >>> cholesky([[4.0, 2.0], [2.0, 5.0]], 2)
    [[2.0, 0.0], [1.0, 2.0]]
    """
    L = [[0.0] * n for _ in range(n)]
    for i in range(n):
        for j in range(i + 1):
            s = M[i][j]
            for k in range(j):
                s -= L[i][k] * L[j][k]
            if i == j:
                L[i][i] = math.sqrt(s)
            else:
                L[i][j] = s / L[j][j]
    return L


def half_logdet(L, n):
    """``sum_i ln L_ii = ln|M| / 2`` for ``M = L L'``.

    Examples
    --------
    >>> half_logdet([[2.0, 0.0], [1.0, 2.0]], 2)
    1.3862943611198906
    """
    hl = 0.0
    for i in range(n):
        hl += math.log(L[i][i])
    return hl


def quad(L, b, n):
    """``|L^-1 b|^2 = b' M^-1 b`` for ``M = L L'`` (forward substitution).

    Examples
    --------
    >>> quad([[2.0, 0.0], [1.0, 2.0]], [2.0, 1.0], 2)
    1.0
    """
    y = [0.0] * n
    q = 0.0
    for i in range(n):
        s = b[i]
        for k in range(i):
            s -= L[i][k] * y[k]
        y[i] = s / L[i][i]
        q += y[i] * y[i]
    return q


def _sums(data: RefData, work: Work, x) -> None:
    """``(M, b, c)`` = prior information plus the terms of the detecting sensors of ``x``."""
    n = data.n
    for i in range(n):
        for k in range(n):
            work.M[i][k] = data.M0[i][k]
        work.b[i] = data.b0[i]
    work.c[0] = data.c0
    for v in range(data.V):
        if x[v] > 0:
            t = data.off[v] + x[v] - 1
            for i in range(n):
                for k in range(n):
                    work.M[i][k] += data.A[v][i][k]
                work.b[i] += data.a[t][i]
            work.c[0] += data.cz[t]


def conditional_log_weights(data: RefData, work: Work, x, s):
    """Log-weights ``lw[0..M_s]`` of sensor ``s``'s conditional given the other entries of ``x``.

    In Gaussian mode ``work`` must hold the sums of ``x`` (as :func:`sweep` keeps them); on
    return it holds ``(M-, b-, c-)`` and ``M+`` is returned with the weights.

    Returns
    -------
    lw : list of float, length M_s + 1
    Mp : list of list of float or None
        ``M+`` (Gaussian mode).

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign.adaptive_birth.prepare import AdaptiveBirthProblem, chain_inputs
    >>> p = AdaptiveBirthProblem.from_log_weights(np.log([[1.0, 2.0], [3.0, 4.0]]))
    >>> d = reference_data(chain_inputs(p))
    >>> lw, _ = conditional_log_weights(d, new_work(d, [1, 0]), [1, 0], 1)
    >>> [round(math.exp(w), 12) for w in lw]
    [3.0, 4.0]
    """
    Ms = data.shape[s] - 1
    if data.mode == 0:
        base = 0
        for v in range(data.V):
            if v != s:
                base += x[v] * data.strides[v]
        return [data.logw[base + j * data.strides[s]] for j in range(Ms + 1)], None
    n = data.n
    M, b, c = work.M, work.b, work.c
    if x[s] > 0:                                         # remove sensor s: (M-, b-, c-)
        t = data.off[s] + x[s] - 1
        for i in range(n):
            for k in range(n):
                M[i][k] -= data.A[s][i][k]
            b[i] -= data.a[t][i]
        c[0] -= data.cz[t]
    lw = [0.0] * (Ms + 1)
    L = cholesky(M, n)
    lw[0] = data.log_miss[s] - half_logdet(L, n) - 0.5 * (c[0] - quad(L, b, n))   # missed
    Mp = [[M[i][k] + data.A[s][i][k] for k in range(n)] for i in range(n)]   # M+ = M- + A_s
    Lp = cholesky(Mp, n)
    hl = half_logdet(Lp, n)
    bj = [0.0] * n
    for j in range(1, Ms + 1):
        t = data.off[s] + j - 1
        for i in range(n):
            bj[i] = b[i] + data.a[t][i]                  # b_j = b- + H' R^-1 z_j
        lw[j] = data.const[t] - hl - 0.5 * ((c[0] + data.cz[t]) - quad(Lp, bj, n))
    return lw, Mp


def sweep(data: RefData, work: Work, x, g) -> None:
    """One sweep over the sensors, in place on the tuple ``x`` (a list of ints).

    Parameters
    ----------
    data : RefData
    work : Work
        From :func:`new_work`.
    x : list of int, length V
        The tuple ``J``.
    g : SplitMix64
        The chain's stream.

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign.engine.rng import SplitMix64
    >>> from rankedassign.adaptive_birth.prepare import AdaptiveBirthProblem, chain_inputs
    >>> t = np.full((3, 3), -np.inf); t[0, 0] = 0.0; t[2, 1] = 50.0
    >>> d = reference_data(chain_inputs(AdaptiveBirthProblem.from_log_weights(t), "fixed"))
    >>> x = [0, 0]
    >>> sweep(d, new_work(d, x), x, SplitMix64(1))
    >>> x                   # (0, 0) -> (2, 0) is impossible; only one move leaves (0, 0)
    [0, 0]
    """
    V = data.V
    order = list(range(V))
    if data.random_order:
        for t in range(V - 1, 0, -1):
            k = min(int(g.uniform() * (t + 1)), t)
            order[t], order[k] = order[k], order[t]
    if data.mode == 1:
        _sums(data, work, x)
    for s in order:
        lw, Mp = conditional_log_weights(data, work, x, s)
        j = draw(lw, g)
        if data.mode == 1 and j > 0:                     # (M, b, c) <- sums of the new tuple
            t = data.off[s] + j - 1
            for i in range(data.n):
                for k in range(data.n):
                    work.M[i][k] = Mp[i][k]
                work.b[i] += data.a[t][i]
            work.c[0] += data.cz[t]
        x[s] = j

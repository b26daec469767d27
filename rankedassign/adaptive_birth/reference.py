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

from ..engine.reference import herd_choice

__all__ = ["RefData", "reference_data", "new_work", "sweep", "draw", "cholesky", "half_logdet",
           "quad", "conditional_log_weights", "HerdData", "new_herd_work", "conditional",
           "herd_key", "herd_sweep"]


class RefData(NamedTuple):
    """The chain inputs of :func:`rankedassign.adaptive_birth.prepare.chain_inputs` as
    Python lists (exact copies of the float64 values).

    ``T = off[V]`` is the number of kept measurements over all sensors; sensor ``s``'s
    measurement ``j >= 1`` is row ``t = off[s] + j - 1`` of the stacked ``a``, ``cz`` and
    ``const``. The arrays the other mode does not read are placeholders of length 1 (``n = 1``
    in tensor mode).

    Attributes
    ----------
    mode : int
        0: ``ln rho`` read from the tensor ``logw``; 1: linear-Gaussian closed form from the
        information sums (spec ``multisensor.md`` §4.2).
    V : int
        Number of sensors, the length of a tuple ``J``.
    n : int
        State dimension of the Gaussian model (1 in tensor mode).
    random_order : bool
        A fresh random sensor order every sweep (``sensor_order="random"``), else ``0..V-1``.
    shape : list of int, length V
        ``M_s + 1``: the candidates ``j = 0..M_s`` of each sensor (Gaussian mode: kept
        measurements only).
    off : list of int, length V + 1
        Offsets of each sensor's measurements in ``a``, ``cz``, ``const`` (zeros in tensor
        mode).
    strides : list of int, length V
        C-order strides of the tensor, in entries (last sensor fastest).
    logw : list of float, length prod(shape)
        Tensor mode: ``ln rho(J)`` of every tuple, flat in C order (``-inf`` = weight 0).
    M0 : list of list of float, shape (n, n)
        Prior information matrix ``P0^-1``.
    b0 : list of float, length n
        Prior information vector ``P0^-1 mu0``.
    c0 : float
        ``mu0' P0^-1 mu0``.
    A : list, shape (V, n, n)
        ``A_s = H_s' R_s^-1 H_s`` per sensor.
    a : list of list of float, shape (T, n)
        ``a_sj = H_s' R_s^-1 z_sj`` per kept measurement (one placeholder row when ``T = 0``).
    cz, const : list of float, length T
        ``cz_sj = z_sj' R_s^-1 z_sj`` and ``const_sj = ln r_U^(s)(j) + ln(P_D^(s) / kappa_s)
        - (d_s ln 2 pi + ln|R_s|) / 2`` per kept measurement (a placeholder when ``T = 0``).
    log_miss : list of float, length V
        ``ln(1 - P_D^(s))`` per sensor (zeros in tensor mode).
    """

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
    """Convert the kernels' inputs into :class:`RefData` (lists of Python numbers).

    Parameters
    ----------
    data : AdaptiveBirthData
        The arrays and scalars of :func:`rankedassign.adaptive_birth.prepare.chain_inputs`
        (:class:`~rankedassign.adaptive_birth.prepare.AdaptiveBirthData`, whose fields are
        those of :class:`RefData`).

    Returns
    -------
    RefData
        ``mode``, ``V``, ``n`` as int, ``random_order`` as bool, ``c0`` as float, every array
        as (nested) lists of the same values.

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign.adaptive_birth.prepare import AdaptiveBirthProblem, chain_inputs
    >>> d = reference_data(chain_inputs(AdaptiveBirthProblem.from_log_weights(np.zeros((2, 2)))))
    >>> d.mode, d.shape, d.strides
    (0, [2, 2], [2, 1])
    """
    vals = {name: getattr(data, name) for name in RefData._fields}
    vals = {k: x.tolist() if hasattr(x, "tolist") else x for k, x in vals.items()}
    vals.update(mode=int(vals["mode"]), V=int(vals["V"]), n=int(vals["n"]),
                random_order=bool(vals["random_order"]), c0=float(vals["c0"]))
    return RefData(**vals)


class Work(NamedTuple):
    """Scratch of one chain: running information sums and the log-weights of one update."""

    M: list          # n x n running information matrix
    b: list          # n running information vector
    c: list          # [c], running scalar


def new_work(data: RefData, x) -> Work:
    """Scratch for a chain started at ``x`` (the sums are recomputed every sweep).

    Parameters
    ----------
    data : RefData
        Gives the state dimension ``n``.
    x : list of int, length V
        The start tuple; not read, since :func:`sweep` recomputes the sums from the tuple.

    Returns
    -------
    Work
        Zeroed running sums: ``M`` (n x n), ``b`` (length n) and ``c`` (``[0.0]``).

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

    Parameters
    ----------
    M : list of list of float, shape (n, n)
        Symmetric positive definite; only the lower triangle (``M[i][j]``, ``j <= i``) is read.
    n : int
        Its dimension.

    Returns
    -------
    L : list of list of float, shape (n, n)
        Lower triangular with positive diagonal, ``L L' = M``; zeros above the diagonal.
        Row by row, ``L_ij = (M_ij - sum_{k<j} L_ik L_jk) / L_jj`` and
        ``L_ii = sqrt(M_ii - sum_{k<i} L_ik^2)``, sums left to right.

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

    Parameters
    ----------
    L : list of list of float, shape (n, n)
        Lower Cholesky factor (:func:`cholesky`); only its diagonal is read.
    n : int
        Its dimension.

    Returns
    -------
    float
        Half the log-determinant of ``M``, summed over ``i = 0..n-1`` in order.

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

    Parameters
    ----------
    L : list of list of float, shape (n, n)
        Lower Cholesky factor (:func:`cholesky`).
    b : list of float, length n
        Information vector.
    n : int
        The dimension.

    Returns
    -------
    float
        ``sum_i y_i^2`` with ``y = L^-1 b`` solved row by row.

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

    Parameters
    ----------
    data : RefData
    work : Work
        Gaussian mode: the running sums ``(M, b, c)`` of ``x``, updated in place to the sums
        without sensor ``s``. Not read in tensor mode.
    x : list of int, length V
        The current tuple ``J``; only ``x[s]`` (Gaussian mode) or the entries other than
        ``x[s]`` (tensor mode) matter.
    s : int
        The sensor whose entry is redrawn, ``0 <= s < V``.

    Returns
    -------
    lw : list of float, length M_s + 1
        ``lw[j] = ln rho(J^-s ⊕ j)`` up to a constant common to all ``j`` (exact in tensor
        mode); ``lw[0]`` is missed.
    Mp : list of list of float or None
        ``M+ = M- + A_s`` (Gaussian mode, for :func:`sweep`'s update on a detection); None in
        tensor mode.

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


def _order(data: RefData, g):
    """The sensors of one sweep: ``0..V-1``, or Fisher-Yates from the identity."""
    V = data.V
    order = list(range(V))
    if data.random_order:
        for t in range(V - 1, 0, -1):
            k = min(int(g.uniform() * (t + 1)), t)
            order[t], order[k] = order[k], order[t]
    return order


def _accept(data: RefData, work: Work, Mp, s, j):
    """Gaussian mode, sensor ``s`` detecting ``j > 0``: ``(M, b, c)`` <- the new tuple's sums."""
    if data.mode == 1 and j > 0:
        t = data.off[s] + j - 1
        for i in range(data.n):
            for k in range(data.n):
                work.M[i][k] = Mp[i][k]
            work.b[i] += data.a[t][i]
        work.c[0] += data.cz[t]


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
    if data.mode == 1:
        _sums(data, work, x)
    for s in _order(data, g):
        lw, Mp = conditional_log_weights(data, work, x, s)
        j = draw(lw, g)
        _accept(data, work, Mp, s, j)
        x[s] = j


# ------------------------------------------------------------------------------ herded draw
class HerdData(NamedTuple):
    """The herded sampler's inputs (:func:`rankedassign.adaptive_birth.prepare.herd_inputs`).

    Attributes
    ----------
    base : RefData
        The Gibbs sampler's inputs.
    keys : {"full", "shared"}
        What a key is; both are the other sensors' entries here (:func:`herd_key`).
    init : {"conditional", "zero", "uniform"}
        A new key's initial weights.
    capacity : int
        Keys a chain's table may hold.
    tally : list of int
        ``[keys created, fall-back draws]`` over the run, updated in place.
    """

    base: RefData
    keys: str
    init: str
    capacity: int
    tally: list


class HerdWork(NamedTuple):
    """A herded chain's bookkeeping: the Gibbs scratch and the key table."""

    sums: Work
    table: dict


def new_herd_work(data: HerdData, x) -> HerdWork:
    """Bookkeeping of a herded chain started at ``x``: the Gibbs scratch, an empty key table.

    Parameters
    ----------
    data : HerdData
    x : list of int, length V
        The start tuple.

    Returns
    -------
    HerdWork

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign.adaptive_birth.prepare import AdaptiveBirthProblem, chain_inputs
    >>> d = reference_data(chain_inputs(AdaptiveBirthProblem.from_log_weights(np.zeros((2, 2)))))
    >>> new_herd_work(HerdData(d, "shared", "zero", 4, [0, 0]), [0, 0]).table
    {}
    """
    return HerdWork(new_work(data.base, x), {})


def conditional(lw) -> list:
    """Sensor ``s``'s conditional from its log-weights: ``exp(lw - max lw) * (1 / total)``.

    Parameters
    ----------
    lw : list of float
        :func:`conditional_log_weights`, at least one finite.

    Returns
    -------
    list of float
        The probabilities, the weights of :func:`draw` normalised.

    Examples
    --------
    >>> conditional([0.0, float("-inf"), 0.0])
    [0.5, 0.0, 0.5]
    """
    mx = lw[0]
    for w in lw:
        if w > mx:
            mx = w
    W = [math.exp(w - mx) for w in lw]
    total = 0.0
    for w in W:
        total += w
    inv = 1.0 / total
    return [w * inv for w in W]


def herd_key(data: HerdData, x, s) -> tuple:
    """The key of sensor ``s``'s draw: ``(s, J^-s)`` with entry ``s`` as ``-1``.

    Parameters
    ----------
    data : HerdData
    x : list of int, length V
        The tuple ``J`` before the draw.
    s : int
        The sensor.

    Returns
    -------
    tuple

    Notes
    -----
    ``"shared"`` and ``"full"`` keys are the same here. The conditional of ``j^(s)`` (spec
    eq. 4.3) is ``ρ(J^-s ⊕ j)`` over ``j``: read from the tensor at the offset of ``J^-s``,
    or, for a linear-Gaussian problem, from the information sums ``(M-, b-, c-)`` over the
    other detecting sensors, a sum of one term per (sensor, measurement) of ``J^-s``. Either
    way it depends on every entry of ``J^-s`` (no coarser statistic of the other entries fixes
    it), so the shared key, the statistic the conditional depends on, is ``J^-s`` itself.

    Examples
    --------
    >>> herd_key(None, [2, 0, 1], 1)
    (1, 2, -1, 1)
    """
    return (s,) + tuple(-1 if v == s else x[v] for v in range(len(x)))


def herd_sweep(data: HerdData, work: HerdWork, x, g) -> None:
    """One herded sweep over the sensors, in place on the tuple ``x``.

    Parameters
    ----------
    data : HerdData
    work : HerdWork
        From :func:`new_herd_work`.
    x : list of int, length V
        The tuple ``J``.
    g : SplitMix64
        The chain's stream (the random sensor order, uniform initial weights, fall-backs).

    Notes
    -----
    The order and the log-weights are those of :func:`sweep`; sensor ``s``'s entry is then
    the herded choice (:func:`rankedassign.engine.reference.herd_choice`) of the key
    :func:`herd_key` over ``0..M_s`` with the probabilities of :func:`conditional`, or, when
    the key is new and the table full, the Gibbs draw (:func:`draw`, one uniform).

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign.engine.rng import SplitMix64
    >>> from rankedassign.adaptive_birth.prepare import AdaptiveBirthProblem, chain_inputs
    >>> p = AdaptiveBirthProblem.from_log_weights(np.log([1.0, 3.0]))    # one sensor
    >>> d = HerdData(reference_data(chain_inputs(p, "fixed")), "shared", "zero", 4, [0, 0])
    >>> x = [0]
    >>> work = new_herd_work(d, x)
    >>> seen = []
    >>> for _ in range(4):
    ...     herd_sweep(d, work, x, SplitMix64(0))
    ...     seen.append(x[0])
    >>> seen, d.tally                      # 1 : 3, deterministically
    ([1, 0, 1, 1], [1, 0])
    """
    base = data.base
    if base.mode == 1:
        _sums(base, work.sums, x)
    for s in _order(base, g):
        lw, Mp = conditional_log_weights(base, work.sums, x, s)
        j = herd_choice(work.table, herd_key(data, x, s), conditional(lw), data.init,
                        data.capacity, data.tally, g)
        if j is None:  # the table is full: an ordinary Gibbs draw
            j = draw(lw, g)
        _accept(base, work.sums, Mp, s, j)
        x[s] = j

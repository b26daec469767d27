"""numba kernel of loopy belief propagation on the single-sensor problem (clean inputs only;
validate in :mod:`.lbp`).

The kernel mirrors :func:`rankedassign.single.lbp.lbp_reference` operation for operation, so
both give bit-identical messages and marginals: the reference works on dense ``(P, M)`` arrays
with zeros at the forbidden pairs, the kernel on the gated pairs only (adding an exact zero to a
float sum changes nothing, so the sums agree bit for bit).

Layout: the gated pairs (edges) are stored row by row, ``rptr[i]..rptr[i+1]`` the edges of row
``i`` with their columns ``col[e]`` in increasing order and their weights ``w[e]``; ``cptr`` and
``cedge`` list the same edges column by column (edges of a column in increasing row order).
"""

from __future__ import annotations

import numpy as np

from ..numba_options import jit


@jit()
def lbp_kernel(rptr, w, w0, cptr, cedge, tol, max_iter):  # pragma: no cover (jit)
    """Iterate the messages; return ``(nu, iterations, change)`` (module docstring: layout).

    ``nu[e]`` is the message of measurement ``col[e]`` to the row of edge ``e`` after the last
    iteration, ``change`` the largest change of a message in that iteration.

    Parameters
    ----------
    rptr : ndarray of int64, shape (P + 1,)
        Row offsets of the edges.
    w : ndarray of float64, shape (E,)
        Weight of every edge (row by row).
    w0 : ndarray of float64, shape (P,)
        Every row's unmatched weight (missed plus dead).
    cptr : ndarray of int64, shape (M + 1,)
        Column offsets of ``cedge``.
    cedge : ndarray of int64, shape (E,)
        The edges of every column, in increasing row order.
    tol : float
        Stop when no message changes by more than it.
    max_iter : int
        Iterations at most.

    Returns
    -------
    nu : ndarray of float64, shape (E,)
        The measurements' messages.
    iterations : int
        Iterations run.
    change : float
        The largest change of a message in the last one.
    """
    P = rptr.size - 1
    n_edges = w.size
    nu = np.ones(n_edges)
    mu = np.empty(n_edges)
    scratch = np.empty(n_edges)
    change = 0.0
    it = 0
    while it < max_iter:
        it += 1
        # rows -> measurements: mu_e = w_e / (w0_i + sum over the row's other edges w nu)
        for i in range(P):
            a, b = rptr[i], rptr[i + 1]
            run = 0.0
            for e in range(a, b):          # scratch[e] = sum of the row's edges before e
                scratch[e] = run
                run += w[e] * nu[e]
            run = 0.0
            for e in range(b - 1, a - 1, -1):
                d = (w0[i] + scratch[e]) + run
                run += w[e] * nu[e]
                mu[e] = w[e] / d if d > 0.0 else np.inf
        # measurements -> rows: nu_e = 1 / (1 + sum over the column's other edges mu)
        change = 0.0
        n_cols = cptr.size - 1
        for j in range(n_cols):
            a, b = cptr[j], cptr[j + 1]
            run = 0.0
            for k in range(a, b):
                scratch[cedge[k]] = run
                run += mu[cedge[k]]
            run = 0.0
            for k in range(b - 1, a - 1, -1):
                e = cedge[k]
                new = 1.0 / (1.0 + (scratch[e] + run))
                run += mu[e]
                diff = abs(new - nu[e])
                if diff > change:
                    change = diff
                nu[e] = new
        if change <= tol:
            break
    return nu, it, change


@jit()
def lbp_beliefs(rptr, col, w, w0, missed, dead, nu, M):  # pragma: no cover (jit)
    """Marginals ``(P, M + 2)`` from the final messages (``missed[i]``, ``dead[i]``: the shares
    of row ``i``'s unmatched weight).

    A row whose belief has no mass (only from contradictory messages) gets NaN; the caller
    raises on it.

    Parameters
    ----------
    rptr, w, w0
        As in :func:`lbp_kernel`.
    col : ndarray of int64, shape (E,)
        Column of every edge.
    missed, dead : ndarray of float64, shape (P,)
        Every row's missed and dead weights (``missed + dead = w0``).
    nu : ndarray of float64, shape (E,)
        The final messages (:func:`lbp_kernel`).
    M : int
        Measurements.

    Returns
    -------
    ndarray of float64, shape (P, M + 2)
        Every row's marginal over the measurements, missed and dead.
    """
    P = rptr.size - 1
    out = np.zeros((P, M + 2))
    for i in range(P):
        a, b = rptr[i], rptr[i + 1]
        tot = w0[i]
        for e in range(a, b):
            tot += w[e] * nu[e]
        if not tot > 0.0:
            for c in range(M + 2):
                out[i, c] = np.nan
            continue
        for e in range(a, b):
            out[i, col[e]] = (w[e] * nu[e]) / tot
        un = w0[i] / tot
        out[i, M] = un * missed[i]
        out[i, M + 1] = un * dead[i]
    return out

"""Loopy belief propagation for the marginal association probabilities (Williams & Lau 2014).

The single-sensor problem's association marginals without sampling or enumeration: messages
between rows (tracks) and measurements on the bipartite graph of gated pairs, iterated to a
fixed point. Williams & Lau prove that the iteration converges; the beliefs it converges to are
an approximation of the exact marginals (:func:`oracle.marginals`), exact when no two rows
share a measurement.

:func:`lbp_reference` is the specification of record (dense numpy); :func:`lbp_marginals`
runs the numba kernel of :mod:`._lbp_kernels` on the gated pairs only, bit for bit the same.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ..numba_options import interruptible
from ..validation import check_int, check_real, check_type
from . import _lbp_kernels
from .problem import AssignmentProblem

__all__ = ["LBPResult", "lbp_marginals", "lbp_reference", "check_lbp_settings", "LBP_TOL",
           "LBP_MAX_ITER"]

#: Default stopping tolerance: the largest change of a measurement-to-row message.
LBP_TOL = 1e-9
#: Default iteration cap.
LBP_MAX_ITER = 1000

_HINT = ("loopy belief propagation takes single-sensor problems; for the others use "
         "oracle.marginals or a sampler's marginals")


class LBPResult(NamedTuple):
    """Marginals from loopy belief propagation and how the iteration ended.

    Attributes
    ----------
    marginals : ndarray, float64, shape (P, M + 2)
        The layout of :func:`oracle.marginals`: ``[:, j]`` for ``j < M`` the belief that row
        ``i`` takes measurement ``j``, ``[:, M]`` missed, ``[:, M + 1]`` dead. Rows sum to one;
        forbidden pairs are exactly 0.
    converged : bool
        Whether the largest message change fell to ``tol`` within ``max_iter`` iterations. When
        False the marginals are those of the last iteration.
    iterations : int
        Iterations run (at least 1).
    change : float
        The largest change of a measurement-to-row message in the last iteration.
    """

    marginals: np.ndarray
    converged: bool
    iterations: int
    change: float


def check_lbp_settings(tol, max_iter):
    """Return ``(tol, max_iter)`` checked: ``tol >= 0`` real, ``max_iter >= 1`` int.

    Parameters
    ----------
    tol : float
        Stopping tolerance of :func:`lbp_marginals`.
    max_iter : int
        Its iteration cap.

    Returns
    -------
    (float, int)

    Raises
    ------
    TypeError, ValueError
        If either is of the wrong type or out of range (the message names it).

    Examples
    --------
    >>> check_lbp_settings(1e-6, 10)
    (1e-06, 10)
    """
    tol = check_real(tol, "tol", minimum=0.0)
    max_iter = check_int(max_iter, "max_iter", minimum=1)
    return tol, max_iter


def _weights(problem):
    """Row-scaled weights: ``(W (P, M) with 0 where forbidden, w0 (P,), missed (P,), dead (P,))``.

    Each row is divided by its largest weight (a message is a ratio of one row's weights, so
    the scale cancels, and nothing overflows); ``w0`` is the unmatched weight
    ``eta(0) + eta(-1)``, ``missed : dead`` its split.
    """
    cc = problem.compact_cost
    M = problem.n_meas
    shift = cc.min(axis=1)                       # every row has a finite entry (validated)
    with np.errstate(over="ignore", under="ignore", invalid="ignore"):
        e = np.exp(-(cc - shift[:, None]))       # +inf - finite = +inf -> exp(-inf) = 0
    W = e[:, :M].copy()
    w0 = e[:, M] + e[:, M + 1]
    with np.errstate(invalid="ignore", divide="ignore"):
        missed = np.where(w0 > 0, e[:, M] / np.where(w0 > 0, w0, 1.0), 0.0)
        dead = np.where(w0 > 0, e[:, M + 1] / np.where(w0 > 0, w0, 1.0), 0.0)
    return W, w0, missed, dead


def _check_result(marginals):
    bad = np.flatnonzero(np.isnan(marginals).any(axis=1))
    if bad.size:
        raise ValueError(
            f"loopy belief propagation: row {int(bad[0])} has no belief mass left (its "
            "messages rule out every choice); the problem has no assignment that the messages "
            "can reach"
        )


def lbp_reference(problem, *, tol=LBP_TOL, max_iter=LBP_MAX_ITER) -> LBPResult:
    """Loopy belief propagation in dense numpy: the specification of :func:`lbp_marginals`.

    Same parameters, result and messages as :func:`lbp_marginals` (bit for bit), in
    ``O(P M)`` per iteration however sparse the gate. For reading and for tests; use
    :func:`lbp_marginals`.

    Parameters
    ----------
    problem : AssignmentProblem
    tol : float, optional
    max_iter : int, optional
        As in :func:`lbp_marginals`.

    Returns
    -------
    LBPResult

    Examples
    --------
    >>> from rankedassign import AssignmentProblem
    >>> from rankedassign.single.lbp import lbp_reference
    >>> p = AssignmentProblem.from_eta([[2.0]], [0.5], [0.25])
    >>> lbp_reference(p).marginals.round(6).tolist()
    [[0.727273, 0.181818, 0.090909]]
    """
    problem = check_type(problem, "problem", AssignmentProblem, _HINT)
    tol, max_iter = check_lbp_settings(tol, max_iter)
    W, w0, missed, dead = _weights(problem)
    P, M = W.shape
    gated = W > 0
    nu = np.ones((P, M))
    it, change = 0, 0.0
    with np.errstate(divide="ignore", over="ignore", invalid="ignore"):
        while it < max_iter:
            it += 1
            a = W * nu
            before = np.zeros((P, M))                   # sum of the row's entries before j
            before[:, 1:] = np.cumsum(a, axis=1)[:, :-1]
            after = np.zeros((P, M))                    # ... after j, summed from the end
            after[:, :-1] = np.cumsum(a[:, ::-1], axis=1)[:, ::-1][:, 1:]
            d = (w0[:, None] + before) + after
            mu = np.where(d > 0, W / np.where(d > 0, d, 1.0), np.inf)
            mu = np.where(gated, mu, 0.0)
            above = np.zeros((P, M))                    # sum of the column's rows before i
            above[1:] = np.cumsum(mu, axis=0)[:-1]
            below = np.zeros((P, M))
            below[:-1] = np.cumsum(mu[::-1], axis=0)[::-1][1:]
            new = np.where(gated, 1.0 / (1.0 + (above + below)), 1.0)
            change = float(np.abs(new - nu).max()) if new.size else 0.0
            nu = new
            if change <= tol:
                break
        tot = w0.copy()
        for j in range(M):                              # the kernel's order of summation
            tot = tot + W[:, j] * nu[:, j]
        out = np.zeros((P, M + 2))
        ok = tot > 0
        safe = np.where(ok, tot, 1.0)
        out[:, :M] = (W * nu) / safe[:, None]
        un = w0 / safe
        out[:, M] = un * missed
        out[:, M + 1] = un * dead
        out[~ok] = np.nan
    _check_result(out)
    return LBPResult(out, bool(change <= tol), int(it), change)


def _edges(W):
    """Gated pairs of ``W`` row by row and column by column (the kernel's layout)."""
    P, M = W.shape
    rows, cols = np.nonzero(W > 0)                      # row-major: rows, then columns, sorted
    rptr = np.zeros(P + 1, dtype=np.int64)
    np.cumsum(np.bincount(rows, minlength=P), out=rptr[1:])
    order = np.argsort(cols, kind="stable")             # by column, rows increasing in each
    cptr = np.zeros(M + 1, dtype=np.int64)
    np.cumsum(np.bincount(cols, minlength=M), out=cptr[1:])
    return rptr, cols.astype(np.int64), np.ascontiguousarray(W[rows, cols]), cptr, \
        order.astype(np.int64)


def lbp_marginals(problem, *, tol=LBP_TOL, max_iter=LBP_MAX_ITER) -> LBPResult:
    """Marginal association probabilities by loopy belief propagation (Williams & Lau 2014).

    Parameters
    ----------
    problem : AssignmentProblem
        A single-sensor problem (LBP's messages are those of one measurement set).
    tol : float, optional
        Stop when no measurement-to-row message changed by more than ``tol`` in an iteration
        (default ``1e-9``).
    max_iter : int, optional
        Give up after this many iterations (default 1000); the result then says
        ``converged=False``.

    Returns
    -------
    LBPResult
        ``marginals`` (the ``(P, M + 2)`` layout of :func:`oracle.marginals`), ``converged``,
        ``iterations`` and the last ``change``.

    Raises
    ------
    TypeError
        If ``problem`` is not an :class:`~rankedassign.AssignmentProblem`.
    ValueError
        If ``tol`` is negative or not a real number, or ``max_iter`` is below 1.

    Notes
    -----
    Let ``w_i(j) = eta_i(j)`` for measurement ``j`` and ``w_i(0) = eta_i(0) + eta_i(-1)``
    (unmatched). With the measurement-to-row messages ``nu_{j->i}`` starting at 1, one
    iteration computes

    .. math::

        \\mu_{i \\to j} = \\frac{w_i(j)}{w_i(0) + \\sum_{j' \\ne j} w_i(j')\\, \\nu_{j' \\to i}},
        \\qquad
        \\nu_{j \\to i} = \\frac{1}{1 + \\sum_{i' \\ne i} \\mu_{i' \\to j}},

    over the gated pairs only, and the beliefs are
    ``p_i(j) ∝ w_i(j) nu_{j->i}``, ``p_i(unmatched) ∝ w_i(0)``; the unmatched belief is split
    between missed and dead as ``eta_i(0) : eta_i(-1)``, as in :func:`oracle.marginals`. The
    iteration stops after the first iteration in which no ``nu`` changed by more than ``tol``
    (Williams & Lau's message-change criterion). The leave-one-out sums are formed from prefix
    and suffix sums, never by subtracting a term from a total (which would cancel when one
    term dominates), and each row is scaled by its largest weight. Cost ``O(E)`` per
    iteration for ``E`` gated pairs. When no two rows gate the same measurement every
    ``nu`` is 1 and the beliefs are the exact marginals after one iteration.

    References
    ----------
    .. [1] J. Williams, R. Lau, "Approximate evaluation of marginal association probabilities
       with belief propagation", IEEE Trans. Aerosp. Electron. Syst. 50(4):2942-2959, 2014.
    .. [2] S. Reuter, B.-T. Vo, B.-N. Vo, K. Dietmayer, "The Labeled Multi-Bernoulli Filter",
       IEEE Trans. Signal Process. 62(12):3246-3260, 2014.

    Examples
    --------
    >>> import numpy as np
    >>> import oracle
    >>> from rankedassign import AssignmentProblem, lbp_marginals
    >>> p = AssignmentProblem.from_eta([[2.0, 1.0], [1.0, 3.0]], [0.5, 0.5], [0.1, 0.1])
    >>> res = lbp_marginals(p)
    >>> res.converged, res.marginals.shape
    (True, (2, 4))
    >>> bool(np.abs(res.marginals - oracle.marginals(p)).max() < 0.05)
    True
    """
    problem = check_type(problem, "problem", AssignmentProblem, _HINT)
    tol, max_iter = check_lbp_settings(tol, max_iter)
    W, w0, missed, dead = _weights(problem)
    rptr, col, w, cptr, cedge = _edges(W)
    with interruptible:
        nu, it, change = _lbp_kernels.lbp_kernel(rptr, w, w0, cptr, cedge, tol, max_iter)
        out = _lbp_kernels.lbp_beliefs(rptr, col, w, w0, missed, dead, nu, problem.n_meas)
    _check_result(out)
    return LBPResult(out, bool(change <= tol), int(it), float(change))


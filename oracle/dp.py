"""Exact normalising constant and association marginals by subset dynamic programming.

Spec §5.2, eqs. (5.1)–(5.2). ``Z`` is a rectangular permanent (#P-hard in general) but is
exponential only in ``min(P, M)``: a DP over subsets of the smaller side, stepping through the
larger side, costs ``O(max(P, M) min(P, M) 2^min(P, M))``.
"""

from __future__ import annotations

import numpy as np

from ._kernels import dp_marginal_kernel, dp_total_kernel, lsap_kernel
from ._result import check_problem

__all__ = ["log_normalizer", "marginals", "MAX_SUBSET_BITS"]

#: Largest ``min(P, M)`` the subset DP accepts (``2^20`` states, 8 MiB per state vector).
MAX_SUBSET_BITS = 20


def _setup(problem):
    """Reduce the problem to the generic subset DP of :mod:`oracle._kernels`.

    Every row either takes a measurement or is *unmatched* (missed or dead, weight
    ``a_i = eta_i(0) + eta_i(-1)``, cost ``-ln a_i``). The ``P x (M' + P)`` LSAP on
    ``[C_meas | diag(-ln a)]`` (``M'`` = measurements some row can take) gives optimal duals
    ``u, v`` with reduced costs ``Cbar = C - u - v >= 0``, ``v <= 0``, ``v = 0`` on unused
    columns, and ``sum(u) + sum(v) = c*`` (the best cost). Every DP factor is then a reduced
    weight ``exp(-Cbar) <= 1`` or a column factor ``exp(v) <= 1``: used column ``c`` by row
    ``i`` contributes ``exp(-Cbar[i, c])``, an unused column ``exp(v[c])``, so a complete
    assignment gets ``w(gamma) exp(c*) <= 1``, the best one exactly 1. No partial product
    that matters can underflow and the total ``Z exp(c*)`` lies in ``[1, |Gamma|]``.
    """
    P, M = problem.n_rows, problem.n_meas
    cc = problem.compact_cost
    reach = np.isfinite(cc[:, :M]).any(axis=0)
    meas = np.flatnonzero(reach)
    Mr = len(meas)
    k = min(P, Mr)
    if k > MAX_SUBSET_BITS:
        raise ValueError(
            f"problem too large for the exact subset DP: min(P, M) = min({P}, {Mr}) = {k} "
            f"> {MAX_SUBSET_BITS} (2^{k} states); use enumeration or Murty bounds instead"
        )
    # cost of the merged unmatched option: -ln(exp(-C_miss) + exp(-C_dead))
    c_un = -np.logaddexp(-cc[:, M], -cc[:, M + 1])
    L = np.full((P, Mr + P), np.inf)
    L[:, :Mr] = cc[:, meas]
    L[np.arange(P), Mr + np.arange(P)] = c_un
    ok, _, u, v = lsap_kernel(L)
    if not ok:  # pragma: no cover - AssignmentProblem guarantees feasibility
        raise AssertionError("merged LSAP infeasible although the problem is feasible")
    shift = float(u.sum() + v.sum())
    with np.errstate(invalid="ignore"):
        red = L - u[:, None] - v[None, :]
    # tiny negative round-off on tight edges: clamp so every factor is <= 1
    wred = np.where(np.isfinite(L), np.exp(-np.maximum(red, 0.0)), 0.0)
    ev = np.exp(v)
    rows = np.arange(P)
    w_un = wred[rows, Mr + rows]  # row i unmatched
    ev_un = ev[Mr + rows]  # row i's unmatched column left unused
    if P <= Mr:
        # states: subsets of rows; steps: measurements (spec 5.1)
        W = np.ascontiguousarray(wred[:, :Mr].T)
        s = np.ascontiguousarray(ev[:Mr])
        tin, tout = ev_un.copy(), w_un.copy()
        over_rows = False
    else:
        # states: subsets of measurements; steps: rows
        W = np.ascontiguousarray(wred[:, :Mr] * ev_un[:, None])
        s = np.ascontiguousarray(w_un)
        tin, tout = np.ones(Mr), np.ascontiguousarray(ev[:Mr])
        over_rows = True
    return W, s, tin, tout, shift, meas, c_un, over_rows


def log_normalizer(problem) -> float:
    """Exact ``ln Z``, ``Z = sum over feasible gamma of w(gamma)`` (spec eqs. 1.6, 5.1).

    Parameters
    ----------
    problem : AssignmentProblem
        The ``P x (M + 2P)`` problem; ``min(P, M') <= 20`` where ``M'`` counts the
        measurements at least one row can take.

    Returns
    -------
    float
        ``ln Z = ln sum_Gamma exp(-cost(gamma))``; ``0.0`` for ``P = 0``.

    Raises
    ------
    TypeError
        If ``problem`` is not an :class:`~rankedassign.AssignmentProblem`.
    ValueError
        If ``min(P, M') > 20`` (the message names both sizes).

    Notes
    -----
    Spec eq. (5.1), DP over subsets ``S`` of rows matched so far, one measurement per step::

        f_j(S) = f_{j-1}(S) + sum_{i in S} eta_i(j) f_{j-1}(S \\ {i})
        Z      = sum_S f_M(S) prod_{i not in S} (eta_i(0) + eta_i(-1))

    or the transposed DP over subsets of measurements, row by row, when ``M' < P``. Weights
    are rescaled by the optimal LSAP duals so that every factor is at most one and the best
    assignment has weight exactly one (see :func:`marginals`): nothing under- or overflows,
    whatever the range of the costs, and ``ln Z = ln Z_scaled - c*`` with ``c*`` the minimum
    cost. Time ``O(max(P, M') min(P, M') 2^min(P, M'))``, memory ``O(2^min(P, M'))``:
    a few seconds for ``P = 20, M = 200``.

    References
    ----------
    .. [1] B.-N. Vo, B.-T. Vo, H. G. Hoang, "An Efficient Implementation of the Generalized
       Labeled Multi-Bernoulli Filter", IEEE Trans. Signal Process. 65(8), 2017.
    .. [2] A. Trezza, D. J. Bucci Jr., P. K. Varshney, "On Gibbs Sampling Architecture for
       Labeled Random Finite Sets Multi-Object Tracking", arXiv:2306.15135, 2023.
    .. [3] K. G. Murty, "An Algorithm for Ranking all the Assignments in Order of Increasing
       Cost", Operations Research 16(3), 1968 (the LSAP dual view used for the scaling).
    .. [4] M. L. Miller, H. S. Stone, I. J. Cox, "Optimizing Murty's Ranked Assignment
       Method", IEEE Trans. Aerosp. Electron. Syst. 33(3), 1997.

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign import AssignmentProblem, synthetic
    >>> from oracle import log_normalizer
    >>> p = AssignmentProblem.from_eta([[2.0]], [0.5], [0.25])   # Z = 2 + 0.5 + 0.25
    >>> round(float(np.exp(log_normalizer(p))), 12)
    2.75
    >>> u = synthetic.uniform()          # 76 848 assignments, each of cost 4 * 0.5
    >>> round(float(np.exp(log_normalizer(u) + 4 * 0.5)), 6)
    76848.0
    """
    check_problem(problem)
    if problem.n_rows == 0:
        return 0.0
    W, s, tin, tout, shift, *_ = _setup(problem)
    total = dp_total_kernel(W, s, tin, tout)
    return float(np.log(total) - shift)


def marginals(problem) -> np.ndarray:
    """Exact association probabilities of every row (spec eq. 5.2).

    Parameters
    ----------
    problem : AssignmentProblem
        The ``P x (M + 2P)`` problem; same size limit as :func:`log_normalizer`.

    Returns
    -------
    ndarray, float64, shape (P, M + 2)
        ``[:, j]`` for ``j < M``: ``P(gamma_i = j + 1)``, row ``i`` takes measurement ``j``;
        ``[:, M]``: ``P(gamma_i = 0)`` (missed); ``[:, M + 1]``: ``P(gamma_i = -1)`` (dead).
        Each row sums to one; each measurement column sums to at most one.

    Raises
    ------
    TypeError
        If ``problem`` is not an :class:`~rankedassign.AssignmentProblem`.
    ValueError
        If ``min(P, M') > 20``.

    Notes
    -----
    ``P(gamma_i = j) = eta_i(j) Z_{-i,-j} / Z`` and
    ``P(gamma_i in {0, -1}) = (eta_i(0) + eta_i(-1)) Z_{-i} / Z``. Rather than one DP per pair,
    one forward and one backward pass of the DP of :func:`log_normalizer` give every
    transition's mass at once: the mass through "row ``i`` takes measurement ``j`` at step
    ``j``" is ``sum_{S not containing i} F_j(S) eta_i(j) B_{j+1}(S | {i})``. Backward vectors
    are checkpointed every ``sqrt(K)`` steps, so memory stays ``O(sqrt(K) 2^k)``. The
    unmatched mass of a row is split between missed and dead in proportion
    ``eta_i(0) : eta_i(-1)``. Rows are normalised by their own total, which equals ``Z`` in
    exact arithmetic. Unreachable measurements (all ``+inf``) get probability 0.
    Time about four times that of :func:`log_normalizer`.

    References
    ----------
    .. [1] B.-N. Vo, B.-T. Vo, H. G. Hoang, "An Efficient Implementation of the Generalized
       Labeled Multi-Bernoulli Filter", IEEE Trans. Signal Process. 65(8), 2017.
    .. [2] S. Reuter, B.-T. Vo, B.-N. Vo, K. Dietmayer, "The Labeled Multi-Bernoulli Filter",
       IEEE Trans. Signal Process. 62(12), 2014.
    .. [3] A. Trezza, D. J. Bucci Jr., P. K. Varshney, "On Gibbs Sampling Architecture for
       Labeled Random Finite Sets Multi-Object Tracking", arXiv:2306.15135, 2023.

    Examples
    --------
    >>> from rankedassign import AssignmentProblem
    >>> from oracle import marginals
    >>> p = AssignmentProblem.from_eta([[2.0]], [0.5], [0.25])
    >>> marginals(p).round(6).tolist()       # [z1, missed, dead] = [2, 0.5, 0.25] / 2.75
    [[0.727273, 0.181818, 0.090909]]
    """
    check_problem(problem)
    P, M = problem.n_rows, problem.n_meas
    out = np.zeros((P, M + 2))
    if P == 0:
        return out
    W, s, tin, tout, _, meas, c_un, over_rows = _setup(problem)
    _, pair, stay, term_out = dp_marginal_kernel(W, s, tin, tout)
    if over_rows:
        pm, unmatched = pair, stay
    else:
        pm, unmatched = pair.T, term_out
    out[:, meas] = pm
    cc = problem.compact_cost
    with np.errstate(invalid="ignore"):
        # share of "missed" within the unmatched option: eta_i(0) / (eta_i(0) + eta_i(-1))
        f_miss = np.where(np.isfinite(cc[:, M]), np.exp(c_un - cc[:, M]), 0.0)
        f_dead = np.where(np.isfinite(cc[:, M + 1]), np.exp(c_un - cc[:, M + 1]), 0.0)
    out[:, M] = unmatched * f_miss
    out[:, M + 1] = unmatched * f_dead
    out /= out.sum(axis=1, keepdims=True)
    return out

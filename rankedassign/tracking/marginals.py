"""Association marginals from hypotheses, for one sensor and for several.

A sampler or Murty's method gives a set of unique hypotheses, each weighted by
``w ∝ exp(−cost)``; the LMB filters need the association marginals of that set (spec
§6.3–6.4, multi-sensor spec §7.4). :func:`marginals_from_hypotheses` forms them for an
:class:`~rankedassign.AssignmentProblem` (``beta`` of shape ``(P, M + 2)``),
:func:`multisensor_marginals_from_hypotheses` for a
:class:`~rankedassign.multisensor.MultiSensorProblem` (``dead`` and ``tuples``).

``marginals="rao-blackwell"`` (an extension, not the paper's method) replaces the indicator
of the hypothesis' own choice by the conditional distribution of each row given the other rows
of the hypothesis, :func:`marginals_from_hypotheses` explains it.

This module is the floor both filter folders stand on (:mod:`rankedassign.tracking.single`,
:mod:`rankedassign.tracking.multisensor`); the truncation classes of
:mod:`rankedassign.tracking.association` call it.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ..multisensor import MultiSensorProblem
from ..numba_options import interruptible, jit
from ..single.problem import AssignmentProblem
from ..validation import check_choice
from . import _kernels

__all__ = [
    "MARGINALS",
    "AssociationResult",
    "Hypotheses",
    "MultiSensorAssociationResult",
    "marginals_from_hypotheses",
    "multisensor_marginals_from_hypotheses",
    "multisensor_marginals",
    "single_marginals",
    "split_collapsed",
]

#: How association marginals are formed from a set of hypotheses (``marginals=`` of the
#: sampler and Murty associations, ``marginals=`` of :func:`marginals_from_hypotheses`).
MARGINALS = ("truncated", "rao-blackwell")


class AssociationResult(NamedTuple):
    """Association marginals of one problem and the work spent on them.

    Attributes
    ----------
    beta : ndarray, shape (P, M + 2)
        ``beta[i, j]`` = weight of the hypotheses in which row ``i`` takes measurement ``j``;
        ``beta[i, M]`` missed, ``beta[i, M + 1]`` dead / not born. Rows sum to 1.
    invocations : int
        Number of solver calls (1 per problem).
    sweeps : int
        Markov-chain observations (full systematic sweeps); 0 for Murty and Exact.
    row_updates : int
        Single-row conditional draws; 0 for Murty and Exact.
    n_unique : int
        Number of unique hypotheses the marginals are built from (0 for :class:`Exact`, which
        sums over all of them implicitly).
    """

    beta: np.ndarray
    invocations: int
    sweeps: int
    row_updates: int
    n_unique: int


@jit()
def _rao_blackwell_single(cost, a, w, M, ptr, cols):  # pragma: no cover (jit)
    """Σ_h w_h π(γ_i = · | γ_{−i}^(h)) for every row ``i``, compact columns.

    Parameters
    ----------
    cost : ndarray of float64, shape (P, M + 2 P)
        The problem's cost matrix (paper layout).
    a : ndarray of int64, shape (H, P)
        The hypotheses, as cost-matrix columns.
    w : ndarray of float64, shape (H,)
        Their normalised weights.
    M : int
        Number of measurements.
    ptr : ndarray of int64, shape (P + 1,)
        CSR offsets: row ``i``'s finite measurement columns are ``cols[ptr[i]:ptr[i + 1]]``.
    cols : ndarray of int64
        Those columns, increasing within a row.

    Returns
    -------
    ndarray of float64, shape (P, M + 2)
        ``β``: columns ``0..M-1`` the measurements, ``M`` missed, ``M + 1`` dead.
    """
    H, P = a.shape
    beta = np.zeros((P, M + 2))
    occupied = np.zeros(M, dtype=np.bool_)
    lp = np.empty(M + 2)
    for h in range(H):
        for i in range(P):
            if a[h, i] < M:
                occupied[a[h, i]] = True
        for i in range(P):
            own = a[h, i]
            # log-weights of the options row i has while the other rows stay put: a free
            # measurement (or its own), missed, dead
            top = -np.inf
            for k in range(ptr[i], ptr[i + 1]):
                j = cols[k]
                v = -cost[i, j] if (j == own or not occupied[j]) else -np.inf
                lp[k - ptr[i]] = v
                top = max(top, v)
            n = ptr[i + 1] - ptr[i]
            lm = -cost[i, M + i]
            ld = -cost[i, M + P + i]
            top = max(top, max(lm, ld))
            tot = 0.0
            for k in range(n):
                lp[k] = np.exp(lp[k] - top)
                tot += lp[k]
            em = np.exp(lm - top)
            ed = np.exp(ld - top)
            tot += em + ed
            f = w[h] / tot
            for k in range(n):
                beta[i, cols[ptr[i] + k]] += f * lp[k]
            beta[i, M] += f * em
            beta[i, M + 1] += f * ed
        for i in range(P):
            if a[h, i] < M:
                occupied[a[h, i]] = False
    return beta


def marginals_from_hypotheses(
    problem: AssignmentProblem, assignments, costs=None, *, marginals: str = "truncated"
) -> np.ndarray:
    """Association marginals from a set of unique hypotheses (spec eqs. 6.3–6.4).

    Parameters
    ----------
    problem : AssignmentProblem
    assignments : array_like of int, shape (H, P)
        Unique feasible assignments (column indices); duplicates would be counted twice.
    costs : array_like, shape (H,), optional
        Their costs (default: ``problem.cost_of(assignments)``).
    marginals : {"truncated", "rao-blackwell"}, optional
        ``"truncated"`` (default, the paper's and Vo's construction): the marginals of the
        truncated GLMB, ``beta[i, j] = Σ_h w_h 1[γ_i^(h) = j]``. ``"rao-blackwell"``:
        ``beta[i, j] = Σ_h w_h π(γ_i = j | γ_{−i}^(h))``, each hypothesis contributing row
        ``i``'s conditional distribution given its other rows (the distribution a Gibbs row
        update draws from) instead of the indicator of its own choice.

    Returns
    -------
    ndarray, shape (P, M + 2)
        Compact columns ``[meas | missed | dead]``; rows sum to 1. ``w_h = exp(−cost_h) /
        Σ exp(−cost)`` is computed by log-sum-exp.

    Raises
    ------
    ValueError
        If there is no hypothesis, shapes disagree, a cost is not finite or ``marginals`` is
        unknown.

    Notes
    -----
    Both are exact when the set holds every feasible hypothesis: the Rao-Blackwellised sum
    then runs over ``γ_{−i}`` with weights ``π(γ_{−i})`` (Gelfand & Smith 1990; Casella &
    Robert 1996). On a truncated set they differ where it matters to a filter: a hypothesis of
    small weight that no chain visited, such as "this newborn track exists but was not
    detected", gets no weight in the truncated marginals, so the track's existence is 0 and
    it is pruned; the Rao-Blackwellised marginals give it its conditional weight next to every
    hypothesis that was visited. The cost is one pass over the feasible options of every row
    per hypothesis, like one Gibbs sweep per hypothesis, and no further sampling.

    References
    ----------
    .. [1] A. E. Gelfand, A. F. M. Smith, "Sampling-Based Approaches to Calculating Marginal
       Densities", J. Amer. Statist. Assoc. 85(410), 1990.
    .. [2] G. Casella, C. P. Robert, "Rao-Blackwellisation of sampling schemes", Biometrika
       83(1), 1996.

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign import AssignmentProblem
    >>> from rankedassign.tracking.marginals import marginals_from_hypotheses
    >>> p = AssignmentProblem.from_eta([[3.0]], [1.0], [1.0])
    >>> marginals_from_hypotheses(p, [[0], [1], [2]]).round(2).tolist()   # all 3 hypotheses
    [[0.6, 0.2, 0.2]]
    >>> marginals_from_hypotheses(p, [[0]]).tolist()                      # the best alone
    [[1.0, 0.0, 0.0]]
    >>> marginals_from_hypotheses(p, [[0]], marginals="rao-blackwell").round(2).tolist()
    [[0.6, 0.2, 0.2]]
    """
    check_choice(marginals, "marginals", MARGINALS)
    a = np.asarray(assignments, dtype=np.int64)
    P = problem.n_rows
    if a.ndim != 2 or a.shape[1] != P:
        raise ValueError(f"assignments must have shape (H, P) = (H, {P}), got {a.shape}")
    if a.shape[0] == 0:
        raise ValueError("at least one hypothesis is needed to form association marginals")
    c = problem.cost_of(a) if costs is None else np.asarray(costs, dtype=np.float64)
    if c.shape != (a.shape[0],):
        raise ValueError(f"costs must have shape ({a.shape[0]},), got {c.shape}")
    if not np.isfinite(c).all():
        raise ValueError("every hypothesis must be feasible (finite cost)")
    return single_marginals(problem, a, c, marginals)


def _writable(a) -> np.ndarray:
    """Assignments as a C-contiguous, writable int64 array (copied only when they are not).

    numba compiles a read-only array as a type of its own: a sampler's assignments are
    read-only, Murty's and the oracle's writable, so the marginals' kernels would be compiled
    twice, once per flag. Copies ``H * P`` integers at most, once per call.
    """
    return np.require(a, dtype=np.int64, requirements=["C", "W"])


def single_marginals(problem: AssignmentProblem, a: np.ndarray, c: np.ndarray, method: str):
    """:func:`marginals_from_hypotheses` on inputs already checked (a sampler's own output).

    Parameters
    ----------
    problem : AssignmentProblem
    a : ndarray of int, shape (H, P)
        Unique feasible assignments.
    c : ndarray, shape (H,)
        Their costs.
    method : {"truncated", "rao-blackwell"}
        The estimator.

    Returns
    -------
    ndarray, shape (P, M + 2)

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign import AssignmentProblem
    >>> p = AssignmentProblem.from_eta([[3.0]], [1.0], [1.0])
    >>> single_marginals(p, np.array([[0]]), np.array([0.0]), "truncated").tolist()
    [[1.0, 0.0, 0.0]]
    """
    M = problem.n_meas
    c = np.asarray(c, dtype=np.float64)
    # w_h ∝ exp(-cost_h), normalised in log space (log-sum-exp)
    lw = -c - (-c).max()
    w = np.exp(lw)
    w /= w.sum()
    a = _writable(a)
    if method == "rao-blackwell":
        C = np.ascontiguousarray(problem.cost, dtype=np.float64)
        finite = np.isfinite(C[:, :M])
        ptr = np.concatenate([[0], np.cumsum(finite.sum(axis=1))]).astype(np.int64)
        cols = np.nonzero(finite)[1].astype(np.int64)
        with interruptible:
            return _rao_blackwell_single(C, a, w, M, ptr, cols)
    with interruptible:
        return _kernels.truncated_marginals(a, w, M)


class Hypotheses(NamedTuple):
    """The unique assignments a truncation keeps of one component's problem.

    Attributes
    ----------
    assignments : ndarray of int64, shape (n, P)
        Unique feasible assignments (column indices of the problem's cost matrix).
    costs : ndarray, shape (n,)
        Their costs ``Σ_i −ln η_i(γ_i)``.
    sweeps, row_updates : int
        Markov-chain observations and single-row draws spent (0 for Murty and enumeration).
    """

    assignments: np.ndarray
    costs: np.ndarray
    sweeps: int = 0
    row_updates: int = 0


class MultiSensorAssociationResult(NamedTuple):
    """Association marginals of one multi-sensor problem and the work spent on them.

    Attributes
    ----------
    dead : ndarray, shape (P,)
        ``P(γ_n = −1)``.
    tuples : ndarray, shape (P, M_1+1, ..., M_V+1)
        ``P(γ_n = t)``; ``dead[n] + tuples[n].sum() = 1``.
    invocations : int
        Solver calls (1 per problem).
    sweeps : int
        Markov-chain observations (full sweeps); 0 for the exact DP.
    row_updates : int
        Single-row conditional draws; 0 for the exact DP.
    n_unique : int
        Unique hypotheses the marginals are built from (0 for the exact DP).
    """

    dead: np.ndarray
    tuples: np.ndarray
    invocations: int
    sweeps: int
    row_updates: int
    n_unique: int


@jit()
def _truncated(flat, dead_h, w, n_t):  # pragma: no cover (jit)
    """Σ_h w_h 1[γ_n^(h) = t] for flat tuple indices ``flat`` (H, P); ``dead_h`` marks −1.

    Parameters
    ----------
    flat : ndarray of int64, shape (H, P)
        Flat index of each row's measurement tuple in each hypothesis (ignored where dead).
    dead_h : ndarray of bool, shape (H, P)
        The row is dead in the hypothesis.
    w : ndarray of float64, shape (H,)
        Normalised weights of the hypotheses.
    n_t : int
        Number of tuples (flat indices ``0..n_t-1``).

    Returns
    -------
    dead : ndarray of float64, shape (P,)
        Weight of each row being dead.
    tup : ndarray of float64, shape (P, n_t)
        Weight of each row taking each tuple.
    """
    H, P = flat.shape
    dead = np.zeros(P)
    tup = np.zeros((P, n_t))
    for h in range(H):
        for n in range(P):
            if dead_h[h, n]:
                dead[n] += w[h]
            else:
                tup[n, flat[h, n]] += w[h]
    return dead, tup


@jit()
def _rao_blackwell_multi(g, w, log_dead, ptr, opt_tuple, opt_flat, opt_logw, n_t, n_meas):
    # pragma: no cover (jit)
    """Σ_h w_h π(γ_n = · | γ_{−n}^(h)) over the finite options of every row.

    Parameters
    ----------
    g : ndarray of int64, shape (H, P, V)
        The hypotheses: per row and sensor ``j >= 1`` measurement ``j``, 0 missed; ``-1`` in
        sensor 0's entry marks a dead row.
    w : ndarray of float64, shape (H,)
        Their normalised weights.
    log_dead : ndarray of float64, shape (P,)
        Log-weight of each row being dead.
    ptr : ndarray of int64, shape (P + 1,)
        CSR offsets: row ``n``'s finite options are ``ptr[n]:ptr[n + 1]`` of the three arrays
        below.
    opt_tuple : ndarray of int64, shape (K, V)
        Each option's measurement tuple.
    opt_flat : ndarray of int64, shape (K,)
        Its flat tensor index (``0..n_t-1``).
    opt_logw : ndarray of float64, shape (K,)
        Its log-weight.
    n_t : int
        Number of tuples.
    n_meas : ndarray of int64, shape (V,)
        Measurements per sensor.

    Returns
    -------
    dead : ndarray of float64, shape (P,)
        Rao-Blackwellised weight of each row being dead.
    tup : ndarray of float64, shape (P, n_t)
        Rao-Blackwellised weight of each row taking each tuple.
    """
    H, P, V = g.shape
    dead = np.zeros(P)
    tup = np.zeros((P, n_t))
    max_m = 0
    for v in range(V):
        max_m = max(max_m, n_meas[v])
    used = np.zeros((V, max_m + 1), dtype=np.int64)  # how many rows use measurement j
    lp = np.empty(opt_flat.size)
    for h in range(H):
        for n in range(P):
            if g[h, n, 0] >= 0:
                for v in range(V):
                    if g[h, n, v] > 0:
                        used[v, g[h, n, v]] += 1
        for n in range(P):
            own = g[h, n]
            top = log_dead[n]
            for k in range(ptr[n], ptr[n + 1]):
                ok = True
                for v in range(V):
                    j = opt_tuple[k, v]
                    if j > 0:
                        held = used[v, j] - (1 if (own[0] >= 0 and own[v] == j) else 0)
                        if held > 0:
                            ok = False
                            break
                lp[k] = opt_logw[k] if ok else -np.inf
                top = max(top, lp[k])
            tot = np.exp(log_dead[n] - top)
            for k in range(ptr[n], ptr[n + 1]):
                lp[k] = np.exp(lp[k] - top)
                tot += lp[k]
            f = w[h] / tot
            dead[n] += f * np.exp(log_dead[n] - top)
            for k in range(ptr[n], ptr[n + 1]):
                tup[n, opt_flat[k]] += f * lp[k]
        for n in range(P):
            if g[h, n, 0] >= 0:
                for v in range(V):
                    if g[h, n, v] > 0:
                        used[v, g[h, n, v]] -= 1
    return dead, tup


def multisensor_marginals_from_hypotheses(problem: MultiSensorProblem, assignments,
                                          costs=None, *, marginals: str = "truncated"):
    """Association marginals of a multi-sensor problem from a set of unique hypotheses.

    Parameters
    ----------
    problem : MultiSensorProblem
    assignments : array_like of int, shape (H, P, V)
        Unique feasible assignments (``−1`` rows dead, else per sensor ``0`` missed or ``j``).
    costs : array_like, shape (H,), optional
        Their costs ``−ln w`` (default ``problem.cost_of(assignments)``).
    marginals : {"truncated", "rao-blackwell"}, optional
        ``"truncated"``: ``β_{n,t} = Σ_h w_h 1[γ_n^(h) = t]`` (multi-sensor spec §7.4).
        ``"rao-blackwell"``: ``β_{n,t} = Σ_h w_h π(γ_n = t | γ_{−n}^(h))``.

    Returns
    -------
    dead : ndarray, shape (P,)
    tuples : ndarray, shape (P, M_1+1, ..., M_V+1)
        ``dead[n] + tuples[n].sum() = 1``.

    Raises
    ------
    ValueError
        If there is no hypothesis, the shapes disagree or a hypothesis is infeasible.

    Notes
    -----
    Both are exact on the full feasible set (Gelfand & Smith 1990; Casella & Robert 1996); on
    a truncated set the Rao-Blackwellised marginals give each row its conditional weight on
    options no sampled hypothesis holds (a newborn track that exists but was missed).

    References
    ----------
    .. [1] B.-N. Vo, B.-T. Vo, M. Beard, "Multi-Sensor Multi-Object Tracking with the
       Generalized Labeled Multi-Bernoulli Filter", IEEE Trans. Signal Process. 67(23), 2019.
    .. [2] G. Casella, C. P. Robert, "Rao-Blackwellisation of sampling schemes", Biometrika
       83(1), 1996.

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign.multisensor import MultiSensorProblem
    >>> from rankedassign.tracking.marginals import multisensor_marginals_from_hypotheses
    >>> p = MultiSensorProblem.from_eta([1.0], [[[1.0, 2.0], [3.0, 0.0]]])   # Z = 7
    >>> dead, tup = multisensor_marginals_from_hypotheses(p, [[[0, 1]]])
    >>> float(dead[0]), tup[0].tolist()
    (0.0, [[0.0, 1.0], [0.0, 0.0]])
    >>> dead, tup = multisensor_marginals_from_hypotheses(p, [[[0, 1]]], marginals="rao-blackwell")
    >>> (7 * dead).round(9).tolist(), (7 * tup[0]).round(9).tolist()
    ([1.0], [[1.0, 2.0], [3.0, 0.0]])
    """
    check_choice(marginals, "marginals", MARGINALS)
    g = np.asarray(assignments, dtype=np.int64)
    P, V = problem.n_rows, problem.n_sensors
    if g.ndim != 3 or g.shape[1:] != (P, V):
        raise ValueError(f"assignments must have shape (H, P, V) = (H, {P}, {V}), got {g.shape}")
    if g.shape[0] == 0:
        raise ValueError("at least one hypothesis is needed to form association marginals")
    c = problem.cost_of(g) if costs is None else np.asarray(costs, dtype=np.float64)
    c = np.atleast_1d(c)
    if c.shape != (g.shape[0],):
        raise ValueError(f"costs must have shape ({g.shape[0]},), got {c.shape}")
    if not np.isfinite(c).all():
        raise ValueError("every hypothesis must be feasible (finite cost)")
    return multisensor_marginals(problem, g, c, marginals)


def multisensor_marginals(problem: MultiSensorProblem, g: np.ndarray, c: np.ndarray, method: str):
    """:func:`multisensor_marginals_from_hypotheses` on checked hypotheses (a sampler's own
    output).

    Parameters
    ----------
    problem : MultiSensorProblem
    g : ndarray of int, shape (H, P, V)
        Unique feasible assignments.
    c : ndarray, shape (H,)
        Their costs.
    method : {"truncated", "rao-blackwell"}
        The estimator.

    Returns
    -------
    dead : ndarray, shape (P,)
    tuples : ndarray, shape (P, M_1+1, ..., M_V+1)

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign.multisensor import MultiSensorProblem
    >>> p = MultiSensorProblem.from_eta([1.0], [[[1.0, 2.0], [3.0, 0.0]]])
    >>> dead, tup = multisensor_marginals(p, np.array([[[0, 1]]]), np.zeros(1), "truncated")
    >>> float(dead[0]), tup[0].tolist()
    (0.0, [[0.0, 1.0], [0.0, 0.0]])
    """
    dims = problem.log_eta_alive.shape
    P = dims[0]
    n_t = int(np.prod(dims[1:]))
    lw = -c - (-c).max()
    w = np.exp(lw)
    w /= w.sum()
    g = _writable(g)
    if method == "rao-blackwell":
        la = problem.log_eta_alive.reshape(P, n_t)
        finite = np.isfinite(la)
        ptr = np.concatenate([[0], np.cumsum(finite.sum(axis=1))]).astype(np.int64)
        rows, flat = np.nonzero(finite)
        opt_tuple = np.ascontiguousarray(problem.tuples[flat], dtype=np.int64)
        with interruptible:
            dead, tup = _rao_blackwell_multi(
                g, w, np.ascontiguousarray(problem.log_eta_dead), ptr, opt_tuple,
                flat.astype(np.int64), np.ascontiguousarray(la[rows, flat]), n_t,
                np.array(problem.n_meas, dtype=np.int64),
            )
    else:
        strides = np.array([int(np.prod(dims[v + 2:])) for v in range(len(dims) - 1)],
                           dtype=np.int64)
        flat = (np.maximum(g, 0) * strides).sum(axis=2)
        with interruptible:
            dead, tup = _truncated(np.ascontiguousarray(flat), np.ascontiguousarray(g[:, :, 0] < 0),
                                   w, n_t)
    return dead, tup.reshape(dims)


def split_collapsed(problem, dead, tup):
    """Split the all-missed mass of the collapsed target (spec §1.6) into dead and missed.

    ``"componentwise"`` samples never hold a dead row: ``(0, ..., 0)`` stands for "dead or
    missed by every sensor". Given the other rows both choices leave the same measurements
    free, so the split is ``η_n(−1) : η_n(0, ..., 0)`` in every hypothesis.

    Parameters
    ----------
    problem : MultiSensorProblem
    dead : ndarray, shape (P,)
        Marginals of the dead rows (0 from the collapsed samples).
    tup : ndarray, shape (P, M_1+1, ..., M_V+1)
        Marginals of the tuples; the all-missed one holds "dead or missed".

    Returns
    -------
    dead, tuples : ndarray
        The same shapes, the all-missed mass split.

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign.multisensor import MultiSensorProblem
    >>> p = MultiSensorProblem.from_eta([1.0], [[[3.0, 0.0], [0.0, 0.0]]])
    >>> dead, tup = split_collapsed(p, np.zeros(1), np.array([[[1.0, 0.0], [0.0, 0.0]]]))
    >>> dead.tolist(), tup[0, 0, 0].item()
    ([0.25], 0.75)
    """
    P = problem.n_rows
    zero = (slice(None),) + (0,) * problem.n_sensors
    ld, lm = problem.log_eta_dead, problem.log_eta_alive[zero]
    top = np.maximum(ld, lm)
    ed = np.exp(ld - top)
    em = np.exp(lm - top)
    both = dead + tup[zero]
    tup = tup.copy()
    tup[zero] = both * em / (ed + em)
    return (both * ed / (ed + em)).reshape(P), tup

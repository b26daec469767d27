"""Exact truncation error of a set of multi-sensor assignments (multi-sensor spec §5, §6).

The error is always measured against the exact target ``pi`` (with the coupled ``eta``), never
against the MM-Gibbs surrogate ``pi~``: MM-Gibbs samples are a truncation support whose members
carry their exact weights (spec §3.4).
"""

from __future__ import annotations

import numpy as np
from scipy.special import logsumexp

from rankedassign.rows import unique_rows
from rankedassign.validation import check_int

from .dp import _log_normalizer
from .enumerate import check_ms_problem, count_assignments, enumerate_assignments

__all__ = ["truncation_error", "best_mass"]

#: ``best_mass`` enumerates up to this many assignments (there is no multi-sensor Murty).
_ENUMERATE_LIMIT = 2_000_000


def _unique_feasible(problem, assignments) -> np.ndarray:
    """Validate ``(n, P, V)`` assignments, reject infeasible ones, drop duplicates."""
    g, _ = problem._as_gamma(assignments, "assignments")
    if g.shape[0] == 0:
        return g
    feasible = problem.is_feasible(g)
    if not feasible.all():
        bad = int(np.flatnonzero(~feasible)[0])
        raise ValueError(
            f"assignment {bad} of the input, {g[bad].tolist()}, is infeasible: it has an entry "
            "out of range, a row mixing -1 with other values, a forbidden option, or a "
            "measurement of some sensor used twice"
        )
    if g[0].size == 0:  # P = 0: the one, empty, assignment
        return g[:1]
    return unique_rows(g.reshape(g.shape[0], -1)).reshape(-1, *g.shape[1:])


def truncation_error(problem, assignments) -> float:
    """``1 - sum_{unique gamma} w(gamma) / Z``: the posterior mass the assignments miss.

    Parameters
    ----------
    problem : MultiSensorProblem
        ``Z`` comes from :func:`oracle.multisensor.dp.log_normalizer` (row DP, or enumeration).
    assignments : array_like of int, shape (n, P, V) or (P, V)
        For instance a sampler's output. Duplicates count once; ``n = 0`` gives 1.

    Returns
    -------
    float
        In ``[0, 1]`` (round-off below zero is clipped to ``0.0``).

    Raises
    ------
    TypeError
        If ``problem`` is not a :class:`~rankedassign.multisensor.MultiSensorProblem` or the
        assignments are not integers.
    ValueError
        If an assignment is infeasible (the message names its index in the input), has the
        wrong shape, or the problem is too large for the exact normaliser.

    References
    ----------
    .. [1] A. Trezza, D. J. Bucci Jr., P. K. Varshney, "On Gibbs Sampling Architecture for
       Labeled Random Finite Sets Multi-Object Tracking", arXiv:2306.15135, 2023.
    .. [2] B.-N. Vo, B.-T. Vo, M. Beard, "Multi-Sensor Multi-Object Tracking with the
       Generalized Labeled Multi-Bernoulli Filter", IEEE Trans. Signal Process. 67(23), 2019.

    Examples
    --------
    >>> from rankedassign.multisensor import MultiSensorProblem
    >>> from oracle import truncation_error
    >>> p = MultiSensorProblem.from_eta([0.5], [[[1.0, 2.0], [3.0, 0.0]]])     # Z = 6.5
    >>> round(truncation_error(p, [[[1, 0]], [[0, 1]], [[1, 0]]]), 12)        # 1 - 5 / 6.5
    0.230769230769
    """
    problem = check_ms_problem(problem)
    g = _unique_feasible(problem, assignments)
    if g.shape[0] == 0:
        return 1.0
    log_kept = logsumexp(problem.log_weight_of(g))
    err = float(-np.expm1(log_kept - _log_normalizer(problem)))
    return err if err > 0.0 else 0.0


def best_mass(problem, k: int) -> float:
    """Fraction of ``Z`` held by the ``k`` best assignments of a multi-sensor problem.

    Parameters
    ----------
    problem : MultiSensorProblem
        With ``|Gamma| <= 2 000 000`` (the ``k`` best come from the enumeration: a
        multi-sensor Murty would solve a ``(V + 1)``-dimensional assignment problem, NP-hard
        for ``V >= 2``).
    k : int
        ``k >= 0``; ``0`` gives ``0.0``, ``k >= |Gamma|`` gives 1.

    Returns
    -------
    float
        In ``[0, 1]``.

    Raises
    ------
    TypeError
        If ``problem`` is not a :class:`~rankedassign.multisensor.MultiSensorProblem` or ``k``
        is not an int.
    ValueError
        If ``k < 0`` or ``|Gamma| > 2 000 000``.

    References
    ----------
    .. [1] B.-N. Vo, B.-T. Vo, M. Beard, "Multi-Sensor Multi-Object Tracking with the
       Generalized Labeled Multi-Bernoulli Filter", IEEE Trans. Signal Process. 67(23), 2019.

    Examples
    --------
    >>> from rankedassign.multisensor import synthetic
    >>> from oracle import best_mass
    >>> round(best_mass(synthetic.diagonal(), 1), 4)
    0.9984
    >>> round(best_mass(synthetic.uniform(), 67744 // 2), 12)
    0.5
    """
    problem = check_ms_problem(problem)
    k = check_int(k, "k", minimum=0)
    if k == 0:
        return 0.0
    n = count_assignments(problem, limit=_ENUMERATE_LIMIT)
    if n > _ENUMERATE_LIMIT:
        raise ValueError(
            f"best_mass of a multi-sensor problem needs the enumeration: more than "
            f"{_ENUMERATE_LIMIT} feasible assignments (P = {problem.n_rows}, M = "
            f"{problem.n_meas})"
        )
    costs = enumerate_assignments(problem, limit=_ENUMERATE_LIMIT).costs
    return float(min(max(np.exp(logsumexp(-costs[:k]) - logsumexp(-costs)), 0.0), 1.0))

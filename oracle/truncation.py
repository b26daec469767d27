"""Exact truncation error of a set of assignments (spec §1.7, eq. 1.9)."""

from __future__ import annotations

import numpy as np
from scipy.special import logsumexp

from rankedassign import AssignmentProblem
from rankedassign.adaptive_birth import AdaptiveBirthProblem
from rankedassign.multisensor import MultiSensorProblem
from rankedassign.validation import check_int

from . import adaptive_birth, multisensor_truncation
from ._result import check_problem
from .dp import log_normalizer
from .enumerate import enumerate_assignments
from .murty import murty

__all__ = ["truncation_error", "best_mass"]

# Problems whose assignment costs can exceed this in magnitude are shifted (see _shifted): an
# ulp of a cost of 2**12 is 9e-13, below that the shift would only change the last bits.
_SHIFT_ABOVE = 2.0**12

# best_mass enumerates instead of running Murty when |Gamma| is at most this
_ENUMERATE_BELOW = 200_000


def _shifted(problem) -> AssignmentProblem:
    """The problem with each row shifted by its entry in the best assignment.

    Every assignment takes one entry per row, so subtracting a constant from a row moves every
    assignment's cost by that constant and changes neither the truncation error nor
    ``best_mass``. What it changes is that ``ln Z`` and the log of the kept mass no longer
    share the best cost as a large offset: with costs near ``4e9`` an ulp of ``ln Z`` is
    ``5e-7``, and near ``1e307`` about ``1e291``, far more than the ``ln`` of any ratio of
    weights, so the difference of the two logs would keep only that much accuracy (or none).
    After the shift the best assignment costs exactly 0 and the others their (rounded)
    excess over it. Problems whose costs cannot add up to more than ``2**12`` in magnitude,
    and problems whose shifted costs would exceed ``COST_LIMIT``, are used as they are.
    """
    C = problem.cost
    finite = np.isfinite(C)
    if np.where(finite, np.abs(C), 0.0).max(axis=1, initial=0.0).sum() <= _SHIFT_ABOVE:
        return problem  # no assignment costs more than 2**12 in magnitude: nothing to gain
    best = murty(problem, 1).assignments[0]
    shift = C[np.arange(problem.n_rows), best]
    if not shift.any():
        return problem
    try:
        return AssignmentProblem.from_cost(C - shift[:, None])
    except ValueError:
        return problem


def _log_z(problem) -> float:
    """``ln Z`` by the subset DP; by enumeration when the DP refuses but ``|Gamma|`` is small."""
    try:
        return log_normalizer(problem)
    except ValueError as too_large:
        try:
            costs = enumerate_assignments(problem).costs
        except ValueError:
            raise too_large from None
        return float(logsumexp(-costs))


def _unique_feasible(problem, assignments) -> np.ndarray:
    """Validate ``(n, P)`` column indices, reject infeasible rows, drop duplicates."""
    a, _ = problem._as_assignments(assignments)
    if a.shape[0] == 0:
        return a
    feasible = problem.is_feasible(a)
    if not feasible.all():
        bad = int(np.flatnonzero(~feasible)[0])
        raise ValueError(
            f"assignment {bad} (row {bad} of the input), columns {a[bad].tolist()}, is "
            "infeasible: it uses a forbidden pair, another row's missed/dead column, a column "
            "out of range, or a measurement twice"
        )
    return np.unique(a, axis=0)


def truncation_error(problem, assignments) -> float:
    """``1 - sum_{unique gamma} w(gamma) / Z``: the posterior mass the assignments miss.

    Parameters
    ----------
    problem : AssignmentProblem or MultiSensorProblem
        The ``P x (M + 2P)`` problem; ``Z`` is computed by :func:`~oracle.log_normalizer`, so
        ``min(P, M) <= 20``. A multi-sensor problem goes to
        :func:`oracle.multisensor_truncation.truncation_error` (assignments ``(n, P, V)``).
    assignments : array_like of int, shape (n, P) or (P,)
        Column indices (for instance a sampler's output). Duplicates count once; ``n = 0``
        gives an error of 1.

    Returns
    -------
    float
        In ``[0, 1]``. After the shift described in Notes, ``Z`` and the kept sum each
        carry a relative round-off of a few ulps of the (shifted) costs that matter: about
        ``1e-15`` absolute when those are of order 1, less accurate when an assignment mixes
        costs of very different magnitude (see Validation in the docs). Round-off can make
        ``1 - sum w / Z`` a few ulps negative when the assignments hold (nearly) all the
        mass; such values are clipped to ``0.0``.

    Raises
    ------
    TypeError
        If ``problem`` is not an :class:`~rankedassign.AssignmentProblem` or the assignments
        are not integers.
    ValueError
        If an assignment is infeasible (the message names its row in the input), has the
        wrong shape, or the problem is too large for the DP.

    Notes
    -----
    Spec eq. (1.9), with the paper's "cost" read as the weight ``w = exp(-cost)`` (spec A6):
    ``eps = 1 - exp(logsumexp(-cost(unique)) - ln Z)``. Everything stays in log space, so
    problems whose weights overflow ``exp`` are fine, and each row is first shifted by its
    entry in the best assignment (which moves every assignment's cost by the same constant),
    so that large costs, up to :data:`~rankedassign.single.problem.COST_LIMIT`, keep their
    differences. ``ln Z`` comes from the subset DP
    (:func:`~oracle.log_normalizer`); when the DP refuses the size but the feasible set is
    small enough to enumerate (many forbidden pairs), from the enumeration.

    References
    ----------
    .. [1] A. Trezza, D. J. Bucci Jr., P. K. Varshney, "On Gibbs Sampling Architecture for
       Labeled Random Finite Sets Multi-Object Tracking", arXiv:2306.15135, 2023.
    .. [2] B.-N. Vo, B.-T. Vo, H. G. Hoang, "An Efficient Implementation of the Generalized
       Labeled Multi-Bernoulli Filter", IEEE Trans. Signal Process. 65(8), 2017.

    Examples
    --------
    >>> from rankedassign import AssignmentProblem, synthetic
    >>> from oracle import truncation_error
    >>> p = AssignmentProblem.from_eta([[2.0]], [0.5], [0.25])    # Z = 2.75
    >>> round(truncation_error(p, [[0], [0], [1]]), 12)        # 1 - (2 + 0.5) / 2.75
    0.090909090909
    >>> round(truncation_error(synthetic.diagonal(), [[0, 1, 2, 3]]), 5)
    0.00423
    """
    if isinstance(problem, MultiSensorProblem):
        return multisensor_truncation.truncation_error(problem, assignments)
    if isinstance(problem, AdaptiveBirthProblem):
        return adaptive_birth.truncation_error(problem, assignments)
    check_problem(problem)
    a = _unique_feasible(problem, assignments)
    if a.shape[0] == 0:
        return 1.0
    problem = _shifted(problem)
    log_kept = logsumexp(-problem.cost_of(a))
    err = float(-np.expm1(log_kept - _log_z(problem)))
    return err if err > 0.0 else 0.0  # clip round-off (and -0.0) to 0.0


def best_mass(problem, k: int) -> float:
    """Fraction of ``Z`` held by the ``k`` best assignments.

    Equivalently ``1 -`` the smallest truncation error any ``k`` assignments can achieve.

    Parameters
    ----------
    problem : AssignmentProblem or MultiSensorProblem
        A multi-sensor problem goes to :func:`oracle.multisensor_truncation.best_mass`.
    k : int
        Number of assignments, ``k >= 0`` (``0`` gives ``0.0``; ``k >= |Gamma|`` gives 1).

    Returns
    -------
    float
        In ``[0, 1]`` (clipped against round-off).

    Raises
    ------
    TypeError
        If ``problem`` is not an :class:`~rankedassign.AssignmentProblem` or ``k`` is not an
        int.
    ValueError
        If ``k < 0`` or the problem is too large for the DP (and for enumeration).

    Notes
    -----
    The ``k`` best come from :func:`~oracle.enumerate_assignments` when
    ``|Gamma| <= 200 000`` (then ``Z`` is the enumeration's own sum) and from
    :func:`~oracle.murty` otherwise, with ``Z`` from :func:`~oracle.log_normalizer`.

    References
    ----------
    .. [1] K. G. Murty, "An Algorithm for Ranking all the Assignments in Order of Increasing
       Cost", Operations Research 16(3), 1968.
    .. [2] M. L. Miller, H. S. Stone, I. J. Cox, "Optimizing Murty's Ranked Assignment
       Method", IEEE Trans. Aerosp. Electron. Syst. 33(3), 1997.
    .. [3] A. Trezza, D. J. Bucci Jr., P. K. Varshney, "On Gibbs Sampling Architecture for
       Labeled Random Finite Sets Multi-Object Tracking", arXiv:2306.15135, 2023.

    Examples
    --------
    >>> from rankedassign import synthetic
    >>> from oracle import best_mass
    >>> round(best_mass(synthetic.diagonal(), 1), 5)       # spec §1.6: 99.577 %
    0.99577
    >>> round(best_mass(synthetic.uniform(), 76848 // 2), 12)
    0.5
    """
    if isinstance(problem, MultiSensorProblem):
        return multisensor_truncation.best_mass(problem, k)
    check_problem(problem)
    k = check_int(k, "k", minimum=0)
    if k == 0:
        return 0.0
    problem = _shifted(problem)
    try:
        n = problem.n_feasible()
    except ValueError:
        n = None
    if n is not None and n <= _ENUMERATE_BELOW:
        costs = enumerate_assignments(problem, limit=_ENUMERATE_BELOW).costs
        log_z = logsumexp(-costs)
        top = costs[:k]
    else:
        top = murty(problem, k).costs
        log_z = _log_z(problem)
    return float(min(max(np.exp(logsumexp(-top) - log_z), 0.0), 1.0))

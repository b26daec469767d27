"""Exact truncation error of a set of assignments (spec §1.7, eq. 1.9)."""

from __future__ import annotations

import numpy as np
from scipy.special import logsumexp

from rankedassign import AssignmentProblem
from rankedassign.rows import unique_rows
from rankedassign.validation import check_int

from .._result import check_problem
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
    return unique_rows(a)  # np.unique(a, axis=0), several times faster


def truncation_error(problem, assignments) -> float:
    """The single-sensor case of :func:`oracle.truncation_error` (see there).

    Parameters
    ----------
    problem : AssignmentProblem
    assignments : array_like of int, shape (n, P)

    Returns
    -------
    float
    """
    check_problem(problem)
    a = _unique_feasible(problem, assignments)
    if a.shape[0] == 0:
        return 1.0
    problem = _shifted(problem)
    log_kept = logsumexp(-problem.cost_of(a))
    err = float(-np.expm1(log_kept - _log_z(problem)))
    return err if err > 0.0 else 0.0  # clip round-off (and -0.0) to 0.0


def best_mass(problem, k: int) -> float:
    """The single-sensor case of :func:`oracle.best_mass` (see there).

    Parameters
    ----------
    problem : AssignmentProblem
    k : int

    Returns
    -------
    float
    """
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

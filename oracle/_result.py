"""The result type of the ranking functions and the problem check shared by the oracle."""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from rankedassign import AssignmentProblem
from rankedassign.validation import MAX_WORK_BYTES, format_bytes

__all__ = ["Ranked"]


class Ranked(NamedTuple):
    """Assignments ranked by cost (best first).

    Attributes
    ----------
    assignments : ndarray, int64, shape (n, P)
        Column indices into the ``(P, M + 2P)`` cost matrix, one row per assignment; every
        assignment is feasible and appears once.
    costs : ndarray, float64, shape (n,)
        ``problem.cost_of(assignments)`` (bit for bit), non-decreasing.

    Examples
    --------
    >>> import numpy as np
    >>> from oracle import Ranked
    >>> r = Ranked(np.zeros((0, 2), dtype=np.int64), np.zeros(0))
    >>> len(r.costs)
    0
    """

    assignments: np.ndarray
    costs: np.ndarray


def check_problem(problem) -> AssignmentProblem:
    """Raise ``TypeError`` unless ``problem`` is an :class:`AssignmentProblem`."""
    if not isinstance(problem, AssignmentProblem):
        raise TypeError(
            "problem must be a rankedassign.AssignmentProblem (build one with "
            f"AssignmentProblem.from_cost or from_eta), got {type(problem).__name__}"
        )
    return problem


def ranked(problem: AssignmentProblem, assignments: np.ndarray) -> Ranked:
    """Package assignments with their public costs (``problem.cost_of``), sorted by cost.

    The solvers already produce non-decreasing costs up to the rounding of their dual
    variables (about one ulp of the largest cost); the stable sort here removes such
    last-bit inversions without disturbing the solvers' own order among equal costs.
    """
    a = np.ascontiguousarray(assignments, dtype=np.int64)
    if len(a) == 0:
        return Ranked(a, np.zeros(0))
    costs = np.asarray(problem.cost_of(a), dtype=np.float64)
    order = np.argsort(costs, kind="stable")
    return Ranked(np.ascontiguousarray(a[order]), costs[order])


def check_enumeration_size(n: int, exact: bool, limit: int, per: int, what: str) -> None:
    """Refuse an enumeration of ``n`` items above ``limit`` or above :data:`MAX_WORK_BYTES`.

    Parameters
    ----------
    n : int
        The count, or, when ``exact`` is False, one more than the cap a counting search
        stopped past (the count is known to exceed ``n - 1``).
    exact : bool
    limit : int
        The caller's ``limit``.
    per : int
        Bytes the enumeration allocates per item (output, costs, sort).
    what : str
        Names the items and the problem's size, e.g. ``"feasible assignments (P = 3, M = 4)"``.

    Raises
    ------
    ValueError
        ``"problem too large to enumerate: ..."`` with the count and the bytes: above ``limit``
        (as before), or within it but above the memory limit.
    """
    count = f"{n}" if exact else f"more than {n - 1}"
    size = format_bytes(n * per) if exact else f"more than {format_bytes((n - 1) * per)}"
    if n > limit:
        raise ValueError(f"problem too large to enumerate: {count} {what} exceed limit = "
                         f"{limit} (they would take {size})")
    if n * per > MAX_WORK_BYTES:
        size = f"{format_bytes(n * per)}, more than" if exact else "more than"
        raise ValueError(
            f"problem too large to enumerate: {count} {what} would take {size} the limit of "
            f"{format_bytes(MAX_WORK_BYTES)} (rankedassign.validation.MAX_WORK_BYTES; "
            f"{per} bytes each)"
        )

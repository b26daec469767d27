"""Exhaustive enumeration of the feasible set ``Gamma`` (spec §1.2, eq. 1.3)."""

from __future__ import annotations

import numpy as np

from rankedassign.numba_options import interruptible
from rankedassign.validation import MAX_WORK_BYTES, check_int

from .._kernels.enumeration import NO_OPTION, count_slice, enumerate_sorted_kernel
from .._result import Ranked, check_enumeration_size, check_problem, ranked

__all__ = ["enumerate_assignments"]


def _bytes_per_assignment(P: int) -> int:
    """Bytes :func:`enumerate_sorted_kernel` may allocate per assignment, a bound: its row of
    column indices (``8 P``), the sort's keys and their copy, one of which becomes the costs
    (16), and the two int32 index arrays (8) make ``8 P + 24``; the bound keeps the 16 more
    bytes of the earlier kernel (a separate costs array and an ``arange``), so that the sizes
    refused stay the same."""
    return 8 * P + 40


def _count(problem, limit: int) -> tuple[int, bool]:
    """``(|Gamma|, True)``, or ``(limit + 1, False)`` once the count is known to pass ``limit``."""
    try:
        return problem.n_feasible(), True
    except ValueError:
        # the exact counting DP refuses the size: count by search, stopping past the limit
        n = _count_by_search(np.ascontiguousarray(problem.compact_cost), limit)
        return n, n <= limit


#: Options tried (times ``M + 2``) per slice of the counting search (tens of milliseconds).
_SLICE_WORK = 1 << 24


def _count_by_search(cc, cap: int) -> int:
    """``min(|Gamma|, cap + 1)`` by the depth-first search of :func:`count_slice`, in slices."""
    P, M = cc.shape[0], cc.shape[1] - 2
    if P == 0:
        return 1
    used = np.zeros(M, dtype=np.bool_)
    opt = np.full(P, NO_OPTION, dtype=np.int64)
    at = np.zeros(2, dtype=np.int64)
    budget = max(1, _SLICE_WORK // (M + 2))
    with interruptible:
        while not count_slice(cc, cap, used, opt, at, budget):
            pass
    return int(at[1])


def enumerate_assignments(problem, *, limit: int = 2_000_000) -> Ranked:
    """The single-sensor case of :func:`oracle.enumerate_assignments` (see there).

    Parameters
    ----------
    problem : AssignmentProblem
    limit : int

    Returns
    -------
    Ranked
    """
    check_problem(problem)
    limit = check_int(limit, "limit", minimum=1)
    P = problem.n_rows
    per = _bytes_per_assignment(P)
    # a counting search stops as soon as the count passes what could be enumerated at all
    n, exact = _count(problem, min(limit, MAX_WORK_BYTES // per))
    check_enumeration_size(n, exact, limit, per,
                           f"feasible assignments (P = {P}, M = {problem.n_meas})")
    if P == 0:
        return ranked(problem, np.zeros((1, 0), dtype=np.int64))
    # The search emits assignments in lexicographic order of their column indices (row 0
    # slowest; a row's options in increasing column order: measurements j < M, then its
    # missed column M + i, then its dead column M + P + i) and scores each one as it goes; one
    # stable sort by cost then leaves equal costs in lexicographic order.
    # (n <= MAX_WORK_BYTES // 48 < 2**31: the sort's int32 indices cannot overflow)
    with interruptible:
        a, costs = enumerate_sorted_kernel(np.ascontiguousarray(problem.compact_cost), n)
    return Ranked(a, costs)

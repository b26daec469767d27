"""Exhaustive enumeration of the feasible set ``Gamma`` (spec §1.2, eq. 1.3)."""

from __future__ import annotations

import numpy as np

from rankedassign.adaptive_birth import AdaptiveBirthProblem
from rankedassign.multisensor import MultiSensorProblem
from rankedassign.numba_options import interruptible
from rankedassign.validation import MAX_WORK_BYTES, check_int

from . import adaptive_birth, multisensor_enumerate
from ._kernels.enumeration import NO_OPTION, count_slice, enumerate_sorted_kernel
from ._result import Ranked, check_enumeration_size, check_problem, ranked

__all__ = ["enumerate_assignments"]


def _bytes_per_assignment(P: int) -> int:
    """Bytes :func:`enumerate_sorted_kernel` allocates per assignment: its row of column
    indices and its cost (``8 P + 8``), the sort's keys and their copy (16), the ``arange``
    its indices come from (8) and the two int32 index arrays (8)."""
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
    """Every feasible assignment with its cost, best first.

    Parameters
    ----------
    problem : AssignmentProblem or MultiSensorProblem
        The ``P x (M + 2P)`` problem; a multi-sensor problem goes to
        :func:`oracle.multisensor_enumerate.enumerate_assignments` (assignments of shape
        ``(|Gamma|, P, V)``).
    limit : int, optional
        Refuse (``ValueError``) when ``|Gamma|`` exceeds this many assignments. The output
        takes ``8 P |Gamma|`` bytes, the enumeration ``(8 P + 40) |Gamma|`` with its sort: a
        ``|Gamma|`` within ``limit`` that needs more than
        :data:`~rankedassign.validation.MAX_WORK_BYTES` (4 GiB) is refused as well.

    Returns
    -------
    Ranked
        ``assignments`` (``|Gamma|``, P) int64 column indices and ``costs``
        (``problem.cost_of``, bit for bit), sorted by cost; equal costs are ordered
        lexicographically by their column indices, so the order is fully deterministic.

    Raises
    ------
    TypeError
        If ``problem`` is not an :class:`~rankedassign.AssignmentProblem` or ``limit`` is not
        an int.
    ValueError
        If ``limit < 1``, ``|Gamma| > limit`` (the message states both numbers and the
        bytes), or the enumeration would take more than
        :data:`~rankedassign.validation.MAX_WORK_BYTES` (the message gives the count and the
        bytes).

    Notes
    -----
    A compiled depth-first search over rows; row ``i`` takes a measurement not used by the
    rows before it, or its own missed or dead column, skipping ``+inf`` entries. The search
    scores each assignment as it goes (row by row from ``0.0``, as ``cost_of``) and the result
    is sorted once by a stable radix sort. The count is
    checked first with :meth:`~rankedassign.AssignmentProblem.n_feasible` (spec eq. 1.3, or
    its exact subset DP when pairs are forbidden). The number of feasible assignments is
    ``sum_k C(P,k) C(M,k) k! 2^(P-k)`` without forbidden pairs: 76 848 for the paper's
    ``4 x 24`` matrices. The empty problem (``P = 0``) has exactly one, empty, assignment.

    References
    ----------
    .. [1] B.-N. Vo, B.-T. Vo, H. G. Hoang, "An Efficient Implementation of the Generalized
       Labeled Multi-Bernoulli Filter", IEEE Trans. Signal Process. 65(8), 2017.
    .. [2] A. Trezza, D. J. Bucci Jr., P. K. Varshney, "On Gibbs Sampling Architecture for
       Labeled Random Finite Sets Multi-Object Tracking", arXiv:2306.15135, 2023.

    Examples
    --------
    >>> from rankedassign import AssignmentProblem, synthetic
    >>> from oracle import enumerate_assignments
    >>> p = AssignmentProblem.from_eta([[2.0, 0.5], [0.1, 3.0]], [0.2, 0.3], [0.1, 0.1])
    >>> r = enumerate_assignments(p)
    >>> len(r.costs), r.assignments[0].tolist()       # best: row 0 -> z1, row 1 -> z2
    (14, [0, 1])
    >>> len(enumerate_assignments(synthetic.uniform()).costs)
    76848
    """
    if isinstance(problem, MultiSensorProblem):
        return multisensor_enumerate.enumerate_assignments(problem, limit=limit)
    if isinstance(problem, AdaptiveBirthProblem):
        return adaptive_birth.enumerate_assignments(problem, limit=limit)
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

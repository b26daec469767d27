"""Exhaustive enumeration of the multi-sensor feasible set (multi-sensor spec §1.5, §6.1).

Depth-first over rows; the state is the set of used measurements of every sensor; row ``n``
may take ``-1`` (dead) or any allowed tuple whose detected measurements are all unused. Cost
``O(|Gamma| P V)``. The compiled search (:func:`_enumerate_slice`, run in slices so that
Ctrl-C ends a long count promptly, by :func:`_enumerate`) is tested against the pure-Python
generator :func:`_enumerate_reference`, which is its specification.
"""

from __future__ import annotations

import numpy as np

from rankedassign.multisensor import MultiSensorProblem
from rankedassign.numba_options import interruptible, jit
from rankedassign.validation import MAX_WORK_BYTES, check_int, check_type

from .._result import Ranked, check_enumeration_size

__all__ = ["enumerate_assignments", "count_assignments", "gamma_from_codes"]

_HINT = "build one with MultiSensorProblem.from_eta, from_log_eta or from_factors"


def check_ms_problem(problem) -> MultiSensorProblem:
    """Raise ``TypeError`` unless ``problem`` is a :class:`MultiSensorProblem`."""
    return check_type(problem, "problem", MultiSensorProblem, _HINT)


def row_options(problem: MultiSensorProblem) -> tuple[np.ndarray, np.ndarray]:
    """Allowed options of every row in enumeration order: ``-1`` (dead) first, then flat
    tuple indices in increasing (lexicographic) order.

    Returns
    -------
    options : ndarray, int64, shape (P, K)
        Padded with ``-2`` beyond ``counts[n]``.
    counts : ndarray, int64, shape (P,)
    """
    P = problem.n_rows
    flat = problem.log_eta_alive.reshape(P, problem.n_tuples)
    ok = np.isfinite(flat)
    dead = np.isfinite(problem.log_eta_dead)
    counts = ok.sum(axis=1) + dead
    K = int(counts.max(initial=0))
    options = np.full((P, K), -2, dtype=np.int64)
    for n in range(P):
        opts = np.flatnonzero(ok[n])
        if dead[n]:
            opts = np.r_[-1, opts]
        options[n, : opts.size] = opts
    return options, counts.astype(np.int64)


def gamma_from_codes(problem: MultiSensorProblem, codes) -> np.ndarray:
    """Assignments ``(n, P, V)`` from per-row option codes ``(n, P)`` (``-1`` dead, else the
    flat tuple index into ``problem.tuples``).

    Parameters
    ----------
    problem : MultiSensorProblem
    codes : array_like of int, shape (n, P)

    Returns
    -------
    ndarray, int64, shape (n, P, V)

    References
    ----------
    .. [1] B.-N. Vo, B.-T. Vo, M. Beard, "Multi-Sensor Multi-Object Tracking with the
       Generalized Labeled Multi-Bernoulli Filter", IEEE Trans. Signal Process. 67(23), 2019.

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign.multisensor import MultiSensorProblem
    >>> p = MultiSensorProblem.from_eta([1.0, 1.0], np.ones((2, 2, 3)))
    >>> gamma_from_codes(p, [[-1, 5]]).tolist()
    [[[-1, -1], [1, 2]]]
    """
    codes = np.asarray(codes, dtype=np.int64)
    ext = np.vstack([problem.tuples, np.full((1, problem.n_sensors), -1, dtype=np.int64)])
    return np.ascontiguousarray(ext[np.where(codes < 0, ext.shape[0] - 1, codes)])


# ----------------------------------------------------------------------------- kernels
@jit()
def _enumerate_slice(options, counts, tuples, out, used, pos, at, n_out, count_only,
                     budget):  # pragma: no cover - compiled
    """Up to ``budget`` steps of the depth-first enumeration (or count) of every feasible
    assignment; True when it is done.

    Parameters
    ----------
    options, counts : from :func:`row_options`
    tuples : ndarray, int64, shape (T, V)
        The tuple table of the problem (flat index -> tuple).
    out : ndarray, int64, shape (n_out, P) (``(0, P)`` with ``count_only``)
        Receives the option codes in depth-first order (row 0 slowest, each row's options in
        the order of ``options``: dead, then tuples lexicographically).
    used : ndarray, bool, shape (V, max M_v + 1)
        Measurements in use (start all False).
    pos : ndarray, int64, shape (P,)
        Each row's option (start at -1).
    at : ndarray, int64, shape (2,)
        The search's row and the assignments found so far; start at zero. Once done
        ``at[1]`` is the number found (``n_out + 1`` once a count passes the limit).
    n_out : int
        Capacity of ``out`` (the exact count), or, with ``count_only``, the limit past
        which counting stops.
    count_only : bool
    budget : int
        Steps (one option tried per step) in this call, ``>= 1``.

    Returns
    -------
    bool
        True when the enumeration (or count) is done.
    """
    P = options.shape[0]
    V = tuples.shape[1]
    row, n = at[0], at[1]
    steps = 0
    while row >= 0:
        if steps >= budget:
            at[0], at[1] = row, n
            return False
        steps += 1
        k = pos[row]
        if k >= 0:  # release the option this row held
            c = options[row, k]
            if c >= 0:
                for v in range(V):
                    j = tuples[c, v]
                    if j > 0:
                        used[v, j] = False
        k += 1
        while k < counts[row]:
            c = options[row, k]
            free = True
            if c >= 0:
                for v in range(V):
                    j = tuples[c, v]
                    if j > 0 and used[v, j]:
                        free = False
                        break
            if free:
                break
            k += 1
        if k == counts[row]:  # options exhausted: backtrack
            pos[row] = -1
            row -= 1
            continue
        pos[row] = k
        c = options[row, k]
        if c >= 0:
            for v in range(V):
                j = tuples[c, v]
                if j > 0:
                    used[v, j] = True
        if row == P - 1:
            if not count_only:
                for i in range(P):
                    out[n, i] = options[i, pos[i]]
            n += 1
            if count_only and n > n_out:
                at[0], at[1] = row, n
                return True
        else:
            row += 1
    at[0], at[1] = row, n
    return True


#: Option tests (times ``V``) per slice of the search (tens of milliseconds): the search runs
#: in slices so that Ctrl-C ends a long count promptly.
_SLICE_WORK = 1 << 24


def _enumerate(options, counts, tuples, n_meas, n_out, count_only):
    """Depth-first enumeration (or count) of every feasible assignment, in slices
    (:func:`_enumerate_slice`).

    Returns
    -------
    out : ndarray, int64, shape (n_out, P) (``(0, P)`` with ``count_only``)
        Option codes in depth-first order.
    n : int
        Number of feasible assignments found (``n_out + 1`` once a count passes the limit).
    """
    P, T = options.shape
    V = tuples.shape[1]
    out = np.empty((0 if count_only else n_out, P), dtype=np.int64)
    if P == 0:
        return out, 1
    used = np.zeros((V, max((int(m) for m in n_meas), default=0) + 1), dtype=np.bool_)
    pos = np.full(P, -1, dtype=np.int64)
    at = np.zeros(2, dtype=np.int64)
    budget = max(1, _SLICE_WORK // ((T + 1) * max(V, 1)))
    with interruptible:
        while not _enumerate_slice(options, counts, tuples, out, used, pos, at, n_out,
                                   count_only, budget):
            pass
    return out, int(at[1])


def _enumerate_reference(problem: MultiSensorProblem):
    """Pure-Python specification of the kernel: option codes in the same order (a generator)."""
    options, counts = row_options(problem)
    tuples = problem.tuples
    P = problem.n_rows

    def dets(c):
        return () if c < 0 else tuple((v, int(j)) for v, j in enumerate(tuples[c]) if j > 0)

    def rec(n, used):
        if n == P:
            yield ()
            return
        for c in options[n, : counts[n]]:
            d = dets(int(c))
            if used.isdisjoint(d):
                for rest in rec(n + 1, used | set(d)):
                    yield (int(c), *rest)

    yield from rec(0, frozenset())


def _kernel_args(problem: MultiSensorProblem):
    options, counts = row_options(problem)
    return (options, counts, np.ascontiguousarray(problem.tuples),
            np.asarray(problem.n_meas, dtype=np.int64))


def _bytes_per_assignment(P: int, V: int) -> int:
    """Bytes :func:`enumerate_assignments` holds per assignment at its peak: the option codes
    and their masked copy (``16 P``), ``gamma`` and its sorted copy (``16 P V``), the costs,
    the sort order and the sorted costs (24); ``cost_of``'s temporaries come on top."""
    return 16 * P * V + 16 * P + 24


# ----------------------------------------------------------------------------- public
def count_assignments(problem, *, limit: int | None = None) -> int:
    """``|Gamma|``, exactly: by the problem's count when it can, else by search.

    Parameters
    ----------
    problem : MultiSensorProblem
    limit : int, optional
        Stop a search once the count passes ``limit`` and return ``limit + 1``. Without it a
        search (needed only when the problem's own counting DP refuses, i.e. with forbidden
        tuples and many measurements) takes ``O(|Gamma|)`` steps.

    Returns
    -------
    int

    References
    ----------
    .. [1] B.-N. Vo, B.-T. Vo, M. Beard, "Multi-Sensor Multi-Object Tracking with the
       Generalized Labeled Multi-Bernoulli Filter", IEEE Trans. Signal Process. 67(23), 2019.

    Examples
    --------
    >>> from rankedassign.multisensor import synthetic
    >>> count_assignments(synthetic.uniform(2, (16, 16)))
    75108
    """
    problem = check_ms_problem(problem)
    if limit is not None:
        limit = check_int(limit, "limit", minimum=0)
    try:
        return problem.n_feasible()
    except ValueError:
        cap = limit if limit is not None else 2**62
        _, n = _enumerate(*_kernel_args(problem), cap, True)
        return int(n)


def enumerate_assignments(problem, *, limit: int = 2_000_000) -> Ranked:
    """Every feasible assignment of a multi-sensor problem with its cost, best first.

    Parameters
    ----------
    problem : MultiSensorProblem
    limit : int, optional
        Refuse (``ValueError``) when ``|Gamma|`` exceeds this many assignments. The output
        takes ``8 P V |Gamma|`` bytes, the enumeration at least ``(16 P V + 16 P + 24)
        |Gamma|``: a ``|Gamma|`` within ``limit`` that needs more than
        :data:`~rankedassign.validation.MAX_WORK_BYTES` (4 GiB) is refused as well.

    Returns
    -------
    Ranked
        ``assignments``: int64, shape ``(|Gamma|, P, V)`` (a dead row all ``-1``);
        ``costs``: ``problem.cost_of(assignments)`` bit for bit, non-decreasing. Equal costs
        are ordered lexicographically by the flattened ``gamma``, so the order is fully
        deterministic.

    Raises
    ------
    TypeError
        If ``problem`` is not a :class:`~rankedassign.multisensor.MultiSensorProblem` or
        ``limit`` is not an int.
    ValueError
        If ``limit < 1``, ``|Gamma| > limit`` (the message states both numbers and the
        bytes), or the enumeration would take more than
        :data:`~rankedassign.validation.MAX_WORK_BYTES` (the message gives the count and the
        bytes).

    Notes
    -----
    The count is known before anything is enumerated (spec eq. 1.7, or the exact counting DP
    of :meth:`~rankedassign.multisensor.MultiSensorProblem.n_feasible`, or a compiled counting
    search that stops past ``limit``, or past what the memory limit can hold), so a refusal
    is immediate. Sizes of spec §1.5: A
    ``P = 4, M = (4, 4)``: 67 744; B ``P = 2, M = (16, 16)``: 75 108; C
    ``P = 3, M = (4, 4, 4)``: 417 176. ``P = 0`` has exactly one, empty, assignment.

    References
    ----------
    .. [1] B.-N. Vo, B.-T. Vo, M. Beard, "Multi-Sensor Multi-Object Tracking with the
       Generalized Labeled Multi-Bernoulli Filter", IEEE Trans. Signal Process. 67(23), 2019.
    .. [2] A. Trezza, D. J. Bucci Jr., P. K. Varshney, "On Gibbs Sampling Architecture for
       Labeled Random Finite Sets Multi-Object Tracking", arXiv:2306.15135, 2023.

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign.multisensor import MultiSensorProblem, synthetic
    >>> from oracle import enumerate_assignments
    >>> p = MultiSensorProblem.from_eta([0.5], [[[1.0, 2.0], [3.0, 0.0]]])   # P = 1, V = 2
    >>> r = enumerate_assignments(p)
    >>> r.assignments.tolist(), np.exp(-r.costs).round(6).tolist()
    ([[[1, 0]], [[0, 1]], [[0, 0]], [[-1, -1]]], [3.0, 2.0, 1.0, 0.5])
    >>> len(enumerate_assignments(synthetic.diagonal()).costs)
    67744
    """
    problem = check_ms_problem(problem)
    limit = check_int(limit, "limit", minimum=1)
    P, V = problem.n_rows, problem.n_sensors
    per = _bytes_per_assignment(P, V)
    # a counting search stops as soon as the count passes what could be enumerated at all
    cap = min(limit, MAX_WORK_BYTES // per)
    try:
        n, exact = problem.n_feasible(), True
    except ValueError:  # the counting DP refuses the size: count by search, up to cap + 1
        _, n = _enumerate(*_kernel_args(problem), cap, True)
        n = int(n)
        exact = n <= cap
    check_enumeration_size(n, exact, limit, per,
                           f"feasible assignments (P = {P}, M = {problem.n_meas})")
    if P == 0:
        return Ranked(np.zeros((1, 0, V), dtype=np.int64), np.zeros(1))
    codes, found = _enumerate(*_kernel_args(problem), n, False)
    if found != n:  # pragma: no cover - the count and the search are exact
        raise AssertionError(f"enumeration found {found} assignments, counted {n}")
    gamma = gamma_from_codes(problem, codes)
    costs = np.asarray(problem.cost_of(gamma), dtype=np.float64)
    # depth-first order is lexicographic in gamma, so a stable sort by cost keeps ties in it
    order = np.argsort(costs, kind="stable")
    return Ranked(np.ascontiguousarray(gamma[order]), costs[order])

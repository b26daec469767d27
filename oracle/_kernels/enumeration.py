"""Compiled kernels of the exhaustive enumeration of ``Gamma`` (spec §1.2, eq. 1.3).

The search walks the compact per-row layout ``cc = [meas 0..M-1 | missed | dead]``
(:attr:`rankedassign.AssignmentProblem.compact_cost`): row ``i`` takes a measurement not used by
the rows before it, or its own missed or dead column, skipping ``+inf`` entries. A cost is
accumulated row by row in the order ``0..P-1`` starting from ``0.0``, exactly as
:meth:`rankedassign.AssignmentProblem.cost_of` does, so a kernel's cost is bit-for-bit the
public one.
"""

from __future__ import annotations

import numpy as np

from rankedassign.numba_options import jit

__all__ = ["count_slice", "enumerate_kernel", "enumerate_sorted_kernel", "NO_OPTION"]

NO_OPTION = -1  # a row on the search stack before its first option

# Digit width of the radix sort: 2^11 buckets, six passes over the 64-bit keys.
_RADIX_BITS = 11
_SIGN = np.uint64(1) << np.uint64(63)


@jit()
def _next_option(cc, row, o, used):
    """The first option of ``row`` after ``o`` that is finite and, for a measurement, unused.

    Returns ``M + 2`` when the row's options are exhausted.

    Parameters
    ----------
    cc : ndarray of float64, shape (P, M + 2)
        Compact costs ``[meas 0..M-1 | missed | dead]`` (``+inf`` = forbidden).
    row : int
        The row.
    o : int
        Its current compact option (:data:`NO_OPTION`, -1, before the first).
    used : ndarray of bool, shape (M,)
        Measurements held by the rows before ``row``.

    Returns
    -------
    int
        The next compact option, or ``M + 2``.
    """
    M = cc.shape[1] - 2
    o += 1
    while o < M + 2 and (not np.isfinite(cc[row, o]) or (o < M and used[o])):
        o += 1
    return o


@jit()
def _full_column(o, i, P, M):
    """Column of compact option ``o`` of row ``i`` in the ``(P, M + 2P)`` layout.

    Parameters
    ----------
    o : int
        Compact option: a measurement ``< M``, missed ``M`` or dead ``M + 1``.
    i : int
        The row.
    P, M : int
        Rows and measurements.

    Returns
    -------
    int
    """
    if o < M:
        return o
    if o == M:
        return M + i  # the row's own missed column
    return M + P + i  # the row's own dead column


@jit()
def enumerate_kernel(cc, n_out):
    """Depth-first enumeration of every feasible assignment, with its cost.

    Parameters
    ----------
    cc : ndarray, float64, shape (P, M + 2)
        Compact costs ``[meas 0..M-1 | missed | dead]`` per row (``+inf`` = forbidden),
        ``P >= 1``.
    n_out : int
        Exact number of feasible assignments (the caller counted them).

    Returns
    -------
    assignments : ndarray, int64, shape (n_out, P)
        Column indices in the full ``(P, M + 2P)`` layout (:func:`_full_column`), in
        depth-first order: row 0 slowest, the options of each row in increasing compact index
        (measurements, missed, dead), which is the lexicographic order of the columns.
    costs : ndarray, float64, shape (n_out,)
        ``cc`` summed row by row from ``0.0`` (bit for bit ``AssignmentProblem.cost_of``).
    """
    P = cc.shape[0]
    M = cc.shape[1] - 2
    out = np.empty((n_out, P), dtype=np.int64)
    costs = np.empty(n_out)
    used = np.zeros(M, dtype=np.bool_)
    opt = np.full(P, NO_OPTION, dtype=np.int64)  # current compact option of each row
    partial = np.zeros(P + 1)  # partial[i]: cost of rows 0..i-1 (left-to-right sum)
    row = 0
    n = 0
    while row >= 0:
        # release the option this row held before trying the next one
        o = opt[row]
        if 0 <= o < M:
            used[o] = False
        o = _next_option(cc, row, o, used)
        if o == M + 2:  # options of this row exhausted: backtrack
            opt[row] = NO_OPTION
            row -= 1
            continue
        opt[row] = o
        if o < M:
            used[o] = True
        partial[row + 1] = partial[row] + cc[row, o]
        if row == P - 1:
            if n < n_out:
                for i in range(P):
                    out[n, i] = _full_column(opt[i], i, P, M)
                costs[n] = partial[P]
            n += 1
        else:
            row += 1
    return out, costs


@jit()
def _cost_keys(keys):
    """Turn the float64 bits in ``keys`` (no NaN) into order-preserving keys, in place.

    Negative floats: every bit flipped (reverses their order); others: the sign bit set.

    Parameters
    ----------
    keys : ndarray of uint64, shape (n,)
        The bits of float64 values; overwritten by the keys.
    """
    for t in range(keys.shape[0]):
        b = keys[t]
        keys[t] = ~b if b & _SIGN else b | _SIGN


@jit()
def _key_costs(keys):
    """Undo :func:`_cost_keys` in place; returns the float64 view of ``keys``.

    Parameters
    ----------
    keys : ndarray of uint64, shape (n,)
        Order-preserving keys; overwritten by the floats' bits.

    Returns
    -------
    ndarray of float64, shape (n,)
        A view of ``keys``.
    """
    for t in range(keys.shape[0]):
        b = keys[t]
        keys[t] = b & ~_SIGN if b & _SIGN else ~b
    return keys.view(np.float64)


@jit()
def _radix_sort(keys):
    """Stable LSD radix sort of ``keys`` (uint64, overwritten).

    Parameters
    ----------
    keys : ndarray of uint64, shape (n,)
        The keys, ``n < 2^31``; used as one of the sort's two buffers.

    Returns
    -------
    idx : ndarray, int32
        The stable argsort of the input keys.
    sorted_keys : ndarray, uint64
        The keys in that order (``keys`` itself or a buffer of the sort).
    spare : ndarray, int32
        A scratch array of the same length the caller may reuse.
    """
    n = keys.shape[0]
    idx = np.empty(n, dtype=np.int32)  # n < 2**31: the caller's limit keeps it far below
    for t in range(n):
        idx[t] = t
    tmp = np.empty(n, dtype=np.int32)
    keys_tmp = np.empty(n, dtype=np.uint64)  # keys travel with their indices: sequential reads
    n_buckets = 1 << _RADIX_BITS
    mask = np.uint64(n_buckets - 1)
    count = np.empty(n_buckets + 1, dtype=np.int64)
    shift = 0
    while shift < 64:
        sh = np.uint64(shift)
        for b in range(n_buckets + 1):
            count[b] = 0
        for t in range(n):
            count[((keys[t] >> sh) & mask) + 1] += 1
        if n == 0 or count[((keys[0] >> sh) & mask) + 1] == n:
            shift += _RADIX_BITS  # every key has the same digit here: the pass changes nothing
            continue
        for b in range(n_buckets):
            count[b + 1] += count[b]
        for t in range(n):
            kt = keys[t]
            b = (kt >> sh) & mask
            p = count[b]
            tmp[p] = idx[t]
            keys_tmp[p] = kt
            count[b] = p + 1
        idx, tmp = tmp, idx
        keys, keys_tmp = keys_tmp, keys
        shift += _RADIX_BITS
    return idx, keys, tmp


@jit()
def _radix_argsort(x):
    """Stable argsort of a float64 array without NaN (LSD radix sort on order-preserving keys).

    ``-0.0`` sorts as ``+0.0``, and equal values keep their input order, as
    ``np.argsort(x, kind="stable")``.

    Parameters
    ----------
    x : ndarray of float64, shape (n,)
        The values (not modified), ``n < 2^31``.

    Returns
    -------
    ndarray of int32, shape (n,)
        The stable argsort.
    """
    keys = (x + 0.0).view(np.uint64)  # a copy (+ 0.0 maps -0.0 to +0.0), viewed as bits
    _cost_keys(keys)
    return _radix_sort(keys)[0]


@jit()
def _search(cc, n_out, costs, rank, out):
    """The depth-first search of :func:`enumerate_kernel`, as one of two passes.

    With ``rank`` empty, ``costs[n]`` gets the cost of the ``n``-th assignment (summed as
    :func:`enumerate_kernel` sums it); otherwise the ``n``-th assignment is written to row
    ``rank[n]`` of ``out``, its sorted position, and ``costs`` is not used.

    Parameters
    ----------
    cc : ndarray of float64, shape (P, M + 2)
        Compact costs, as in :func:`enumerate_kernel`.
    n_out : int
        Number of feasible assignments.
    costs : ndarray of float64, shape (n_out,) or empty
        Receives the costs in search order (first pass).
    rank : ndarray of int32, shape (n_out,) or empty
        Sorted position of each assignment (second pass); empty selects the first pass.
    out : ndarray of int64, shape (n_out, P) or empty
        Receives the assignments at their sorted rows (second pass).
    """
    P = cc.shape[0]
    M = cc.shape[1] - 2
    scoring = rank.shape[0] == 0
    used = np.zeros(M, dtype=np.bool_)
    opt = np.full(P, NO_OPTION, dtype=np.int64)
    partial = np.zeros(P + 1)
    row = 0
    n = 0
    while row >= 0:
        o = opt[row]
        if 0 <= o < M:
            used[o] = False
        o = _next_option(cc, row, o, used)
        if o == M + 2:
            opt[row] = NO_OPTION
            row -= 1
            continue
        opt[row] = o
        if o < M:
            used[o] = True
        if scoring:
            partial[row + 1] = partial[row] + cc[row, o]
        if row == P - 1:
            if n < n_out:
                if scoring:
                    costs[n] = partial[P]
                else:
                    r = rank[n]
                    for i in range(P):
                        out[r, i] = _full_column(opt[i], i, P, M)
            n += 1
        else:
            row += 1


@jit()
def enumerate_sorted_kernel(cc, n_out):
    """:func:`enumerate_kernel` followed by one stable sort by cost.

    Parameters
    ----------
    cc : ndarray of float64, shape (P, M + 2)
        Compact costs, as in :func:`enumerate_kernel`.
    n_out : int
        Exact number of feasible assignments.

    Returns
    -------
    assignments : ndarray of int64, shape (n_out, P)
        As in :func:`enumerate_kernel`, sorted by cost; equal costs stay in the search's
        (lexicographic) order.
    costs : ndarray of float64, shape (n_out,)
        Their costs, non-decreasing.

    Notes
    -----
    The search runs twice: first for the costs alone, whose order-preserving keys are sorted
    (:func:`_radix_sort`), then for the assignments, each written straight to its sorted row.
    That replaces permuting the finished rows in place and saves the temporaries a separate
    copy of the costs and of their keys took: this call's time is mostly the first touch of
    freshly allocated pages (the allocator returns a large freed block to the system, and
    the next call faults it in again), so every array not allocated counts. The costs come
    back from the sorted keys: a cost is never ``-0.0`` (a sum started from ``+0.0``), so
    decoding the key gives back its exact bits.
    """
    P = cc.shape[0]
    keys = np.empty(n_out, dtype=np.uint64)
    _search(cc, n_out, keys.view(np.float64), np.empty(0, dtype=np.int32),
            np.empty((0, P), dtype=np.int64))
    _cost_keys(keys)
    idx, sorted_keys, rank = _radix_sort(keys)
    for t in range(n_out):
        rank[idx[t]] = t
    out = np.empty((n_out, P), dtype=np.int64)
    _search(cc, n_out, np.empty(0), rank, out)
    return out, _key_costs(sorted_keys)


@jit()
def count_slice(cc, cap, used, opt, at, budget):
    """Up to ``budget`` steps of counting feasible assignments by depth-first search; True when
    it is done.

    Once done ``at[1]`` is ``min(count, cap + 1)``: the search stops once the count exceeds
    ``cap``. ``used`` (M,) bool starts all False, ``opt`` (P,) int64 at :data:`NO_OPTION`,
    ``at`` (the search's row, the count) at zero; ``P >= 1``. Used only when the exact
    counting DP of :meth:`~rankedassign.AssignmentProblem.n_feasible` refuses the size; the
    caller loops over slices so that Ctrl-C ends a long count promptly.

    Parameters
    ----------
    cc : ndarray of float64, shape (P, M + 2)
        Compact costs, as in :func:`enumerate_kernel`.
    cap : int
        The count above which the search stops.
    used : ndarray of bool, shape (M,)
        Measurements held; the search's state, kept between slices.
    opt : ndarray of int64, shape (P,)
        Current option of each row; kept between slices.
    at : ndarray of int64, shape (2,)
        The search's row and the count so far; kept between slices.
    budget : int
        Steps in this call.

    Returns
    -------
    bool
        True when the count is done.
    """
    P = cc.shape[0]
    M = cc.shape[1] - 2
    row, n = at[0], at[1]
    steps = 0
    while row >= 0:
        if steps >= budget:
            at[0], at[1] = row, n
            return False
        steps += 1
        o = opt[row]
        if 0 <= o < M:
            used[o] = False
        o = _next_option(cc, row, o, used)
        if o == M + 2:
            opt[row] = NO_OPTION
            row -= 1
            continue
        opt[row] = o
        if o < M:
            used[o] = True
        if row == P - 1:
            n += 1
            if n > cap:
                break
        else:
            row += 1
    at[0], at[1] = row, n
    return True

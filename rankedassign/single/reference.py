"""The single-sensor row update in pure Python: the specification of record of its kernels.

Written for reading, not speed: plain loops over lists. The numba twin is
:mod:`rankedassign.single._kernels`; both must give the same bits. The arithmetic they share:

* the weights ``W`` (:func:`rankedassign.single.prepare.shifted_weights`) and their per-row
  prefix sums (:func:`rankedassign.single.prepare.prefix_sums`), computed once with numpy;
* the SplitMix64 stream of each chain (:mod:`rankedassign.engine.rng`);
* one uniform per row update, turned into a candidate by the inverse-CDF rule of
  :func:`draw_direct` or (many measurements) :func:`draw_prefix`; in a random-scan sweep,
  first ``P - 1`` uniforms for the Fisher-Yates permutation of :func:`sweep`.

States are compact index vectors: ``k < M`` measurement ``k``, ``k = M`` missed,
``k = M + 1`` dead (the columns of :attr:`AssignmentProblem.compact_cost`).
"""

from __future__ import annotations

import bisect
import math
from typing import NamedTuple

from .prepare import CANCEL_GUARD, HerdData, SingleData


def draw_direct(W_i, cc_i, i, owner, u) -> int:
    """Row ``i``'s draw by the direct sum over its available candidates, ``O(M)``.

    Parameters
    ----------
    W_i : sequence of float, length M + 2
        Row ``i`` of the shifted weights ``W``.
    cc_i : sequence of float, length M + 2
        Row ``i`` of the compact costs (only for the underflow fall-back).
    i : int
        The row.
    owner : list of int, length M
        Row holding each measurement, ``-1`` if free.
    u : float
        The row's uniform in ``[0, 1)``.

    Returns
    -------
    int
        The compact index drawn.

    Notes
    -----
    ``p(k) ∝ eta_i(k) * 1[k available]`` where the candidates, in this order, are the
    measurements ``0..M-1`` not held by another row, missed (``M``) and dead (``M + 1``)::

        total  = sum of W_i[k] over available k, left to right
        target = u * total
        pick the first k with  W_i[0] + ... + W_i[k] > target   (available, positive k only)

    (inverse CDF, like Vo's ``histc(rand, [0; cumsum / sum])``). If rounding leaves no such
    ``k`` the last available positive-weight candidate is taken. If every available ``W``
    underflowed to 0, the same loop runs on the exact weights ``exp(-(cc_i[k] - m))``, ``m``
    the cheapest available cost; this path calls ``exp`` and matches the kernel as far as
    both use the same libm (they do on one machine).

    Examples
    --------
    >>> draw_direct([1.0, 0.0, 0.0], [0.0, float("inf"), float("inf")], 0, [-1], 0.5)
    0
    """
    M = len(owner)
    avail = [k for k in range(M) if owner[k] in (-1, i)] + [M, M + 1]
    total = 0.0
    for k in avail:
        total += W_i[k]
    if total > 0.0:
        weights = [W_i[k] for k in avail]
    else:  # underflow fall-back: exact weights relative to the cheapest available entry
        m = min(cc_i[k] for k in avail)
        weights = [math.exp(-(cc_i[k] - m)) for k in avail]
        total = 0.0
        for w in weights:
            total += w
    target = u * total
    acc = 0.0
    last = None
    for k, w in zip(avail, weights, strict=True):
        if w > 0.0:
            acc += w
            last = k
            if acc > target:
                return k
    return last


def draw_prefix(W_i, S_i, next_i, cc_i, i, owner, held, u) -> int:
    """Row ``i``'s draw from per-row prefix sums, ``O(P + log M)`` (row ``i`` released).

    Parameters
    ----------
    W_i, cc_i, i, owner, u
        As in :func:`draw_direct`.
    S_i : sequence of float, length M + 1
        Prefix sums of the row's measurement weights, ``S_i[k] = W_i[0] + ... + W_i[k-1]``
        summed left to right (``S_i[0] = 0``).
    next_i : sequence of int, length M
        ``next_i[k]``: the first ``k' >= k`` with ``W_i[k'] > 0`` (``M`` if none).
    held : list of int
        Sorted measurements held by the *other* rows.

    Returns
    -------
    int
        The compact index drawn.

    Notes
    -----
    The same conditional as :func:`draw_direct`, with the sums over available measurements
    written as a prefix sum minus the held measurements before it. With ``c`` the sum of
    ``W_i`` over the held measurements (in column order) and ``meas = S_i[M] - c``::

        total  = (meas + W_i[M]) + W_i[M + 1],   target = u * total
        cum(k) = S_i[k + 1] - c(k)   for a free k < M, c(k) the held weight left of k
        pick the first free k with W_i[k] > 0 and cum(k) > target; else missed if
        W_i[M] > 0 and meas + W_i[M] > target; else dead if W_i[M + 1] > 0 (its cum is total)

    The free measurements form runs between held ones; in each run ``c`` is constant and
    ``cum`` does not decrease. The run is found by bisection over the runs' last ``cum``
    (``cs[t]``, the held weight left of run ``t``, is summed once per draw), the first ``k``
    of the run with ``cum(k) > target`` by bisection inside it, and ``next_i`` skips zero
    weights (a run may start with one whose rounded ``cum`` already exceeds ``target``; the
    search then moves on to the next run), so a draw costs ``O(P + log M)``. If rounding
    leaves no candidate, the last available positive-weight candidate is taken, as in
    :func:`draw_direct`. When the held measurements
    carry all but :data:`CANCEL_GUARD` of the row's measurement weight, ``S_i[M] - c`` loses
    its digits to cancellation and the draw is :func:`draw_direct`'s; so is it when every
    available weight underflowed to 0.

    Examples
    --------
    >>> W = [0.5, 0.0, 0.25, 1.0, 0.0]            # M = 3 measurements, missed, dead
    >>> draw_prefix(W, [0.0, 0.5, 0.5, 0.75], [0, 2, 2], [0.7, 9e9, 1.4, 0.0, 9e9], 0,
    ...             [-1, -1, -1], [], 0.5)       # target 0.875: past 0.75, missed
    3
    """
    M = len(owner)
    n = len(held)
    cs = [0.0] * (n + 1)  # cs[t]: held weight left of run t, summed left to right
    for t in range(n):
        cs[t + 1] = cs[t] + W_i[held[t]]
    meas = S_i[M] - cs[n]
    if meas < CANCEL_GUARD * S_i[M]:  # held weight cancels the prefix sum: direct draw
        return draw_direct(W_i, cc_i, i, owner, u)
    total = (meas + W_i[M]) + W_i[M + 1]
    if not total > 0.0:  # every available weight underflowed
        return draw_direct(W_i, cc_i, i, owner, u)
    target = u * total
    ends = held + [M]  # run t is [lo_t, ends[t]) with lo_0 = 0, lo_t = ends[t - 1] + 1
    # the first run whose last cum, S_i[ends[t]] - cs[t], exceeds target (bisection over runs)
    a, b = 0, n + 1
    while a < b:
        mid = (a + b) // 2
        if S_i[ends[mid]] - cs[mid] > target:
            b = mid
        else:
            a = mid + 1
    for t in range(a, n + 1):  # normally one run; more only past zero weights or rounding
        lo = ends[t - 1] + 1 if t > 0 else 0
        h = ends[t]
        if h > lo and S_i[h] - cs[t] > target:
            p, q = lo, h - 1  # the first k in the run with S_i[k + 1] - cs[t] > target
            while p < q:
                mid = (p + q) // 2
                if S_i[mid + 1] - cs[t] > target:
                    q = mid
                else:
                    p = mid + 1
            k = next_i[p]
            if k < h:
                return k
    if W_i[M] > 0.0 and meas + W_i[M] > target:
        return M
    if W_i[M + 1] > 0.0:
        return M + 1  # cum(M + 1) = total > target, or rounding: the last candidate
    if W_i[M] > 0.0:
        return M
    free = set(range(M)) - set(held)
    return max(k for k in free if W_i[k] > 0.0)  # rounding: last positive free measurement


def scan_order(P: int, random_scan: bool, g) -> list:
    """The rows of one sweep: ``0..P-1``, or a Fisher-Yates permutation of them drawn from ``g``
    (``t = P-1..1``: ``j = min(floor(u (t + 1)), t)``, swap ``t`` and ``j``).

    Examples
    --------
    >>> scan_order(3, False, None)
    [0, 1, 2]
    """
    order = list(range(P))
    if random_scan:
        for t in range(P - 1, 0, -1):
            j = min(int(g.uniform() * (t + 1)), t)
            order[t], order[j] = order[j], order[t]
    return order


class SingleWork(NamedTuple):
    """A chain's bookkeeping: who holds each measurement, and the held ones in order."""

    owner: list    # length M: row holding each measurement, -1 if free
    held: list     # sorted measurements held by some row


def new_work(data: SingleData, x) -> SingleWork:
    """Bookkeeping of a chain in state ``x``."""
    owner = [-1] * data.M
    for i, k in enumerate(x):
        if k < data.M:
            owner[k] = i
    return SingleWork(owner, sorted(k for k in x if k < data.M))


def sweep(data: SingleData, work: SingleWork, x, g) -> None:
    """One Gibbs sweep over all rows, updating ``x`` and ``work`` in place (spec §2.2).

    Parameters
    ----------
    data : SingleData
        Shifted weights, compact costs, prefix sums, scan order.
    work : SingleWork
        The chain's bookkeeping (:func:`new_work`).
    x : list of int, length P
        Compact state.
    g : SplitMix64
        The chain's stream.

    Notes
    -----
    Rows are visited in order ``0..P-1`` or, for a random scan, in an order drawn first by
    Fisher-Yates from the identity (``t = P-1..1``: ``j = min(floor(u (t + 1)), t)``, swap
    ``t`` and ``j``). Gauss-Seidel: row ``n`` conditions on the rows already updated in this
    sweep and on the others from the previous sweep (Vo 2017, Alg. 1). Each row update
    releases the row's measurement, draws one uniform and turns it into a candidate with
    :func:`draw_direct` or, where :func:`rankedassign.single.prepare.uses_prefix_sums` says
    so, :func:`draw_prefix`.

    Examples
    --------
    >>> from rankedassign.engine.rng import SplitMix64
    >>> data = SingleData([[0.0, 1.0, 0.0]], [[9.0, 0.0, float("inf")]], [[0.0, 0.0]], [[1]],
    ...                   False, 1, False)
    >>> x = [1]
    >>> work = new_work(data, x)
    >>> sweep(data, work, x, SplitMix64(0))
    >>> x, work.owner
    ([1], [-1])
    """
    M = data.M
    owner, held = work
    for i in scan_order(len(x), data.random_scan, g):
        if x[i] < M:  # release row i's measurement
            owner[x[i]] = -1
            held.remove(x[i])
        u = g.uniform()
        if not data.prefix:
            k_new = draw_direct(data.W[i], data.cc[i], i, owner, u)
        else:
            k_new = draw_prefix(data.W[i], data.S[i], data.next_pos[i], data.cc[i], i, owner,
                                held, u)
        if k_new < M:
            owner[k_new] = i
            bisect.insort(held, k_new)
        x[i] = k_new


# ------------------------------------------------------------------------------ herded draw
class HerdWork(NamedTuple):
    """A herded chain's bookkeeping: who holds each measurement, and its key table."""

    owner: list    # length M: row holding each measurement, -1 if free
    table: dict    # key -> list of K weights


def new_herd_work(data: HerdData, x) -> HerdWork:
    """Bookkeeping of a herded chain in state ``x``: an empty key table."""
    owner = [-1] * data.M
    for i, k in enumerate(x):
        if k < data.M:
            owner[k] = i
    return HerdWork(owner, {})


def conditional(W_i, cc_i, i, owner) -> list:
    """Row ``i``'s conditional ``π_i(k | γ_{-i})`` over its ``M + 2`` candidates, as a list.

    ``W_i[k] * (1 / total)`` for an available candidate, 0 for a measurement another row
    holds; ``total`` is the sum of the available weights left to right, as in
    :func:`draw_direct`.
    If every available weight underflowed, the exact weights ``exp(-(cc_i[k] - m))`` are used
    (``m`` the cheapest available cost), as in :func:`draw_direct`'s fall-back.

    Examples
    --------
    >>> conditional([1.0, 1.0, 3.0, 0.0], [0.0, 0.0, -1.1, float("inf")], 0, [-1, 1])
    [0.25, 0.0, 0.75, 0.0]
    """
    M = len(owner)
    K = M + 2
    avail = [k >= M or owner[k] in (-1, i) for k in range(K)]
    meas = 0.0
    for k in range(M):
        meas += W_i[k] if avail[k] else 0.0
    total = (meas + W_i[M]) + W_i[M + 1]
    if total > 0.0:
        inv = 1.0 / total
        return [(W_i[k] if avail[k] else 0.0) * inv for k in range(K)]
    m = min(cc_i[k] for k in range(K) if avail[k])
    e = [math.exp(-(cc_i[k] - m)) if avail[k] else 0.0 for k in range(K)]
    total = 0.0
    for k in range(K):
        if avail[k]:
            total += e[k]
    return [v / total for v in e]


def herd_key(data: HerdData, x, i, owner) -> tuple:
    """Row ``i``'s key: ``(i, γ_{-i})`` (``"full"``) or ``(i, its gated measurements that the
    other rows hold, increasing)`` (``"shared"``), with row ``i``'s measurement released."""
    if data.keys == "full":
        return (i,) + tuple(-1 if r == i else v for r, v in enumerate(x))
    cc_i = data.cc[i]
    return (i,) + tuple(k for k in range(data.M)
                        if owner[k] not in (-1, i) and cc_i[k] < math.inf)


def herd_sweep(data: HerdData, work: HerdWork, x, g) -> None:
    """One herded sweep over all rows, updating ``x`` and ``work`` in place.

    Parameters
    ----------
    data : HerdData
    work : HerdWork
        The chain's bookkeeping (:func:`new_herd_work`).
    x : list of int, length P
        Compact state.
    g : SplitMix64
        The chain's stream (used by a random scan, uniform initial weights and fall-backs).

    Notes
    -----
    Rows are visited as in :func:`sweep`. Row ``i`` releases its measurement, computes its
    conditional ``p`` (:func:`conditional`) and its key (:func:`herd_key`). A key not in the
    table gets initial weights (``p`` itself, zeros, or ``M + 2`` uniforms from ``g`` in
    candidate order) if the table has room; otherwise the row draws as the Gibbs sampler
    does (one uniform, :func:`draw_direct`) and the draw is tallied as a fall-back. With the
    key's weights ``w``: ``w[k] += p[k]`` for every candidate, then the pick is the first
    ``k`` with ``p[k] > 0`` of the largest ``w[k]``, and ``w[pick] -= 1``. The key fixes its
    conditional, so the candidates of probability 0 are known when the key is created: their
    weights are set to ``-inf`` then, and the pick is simply the first largest ``w[k]``.

    Examples
    --------
    >>> from rankedassign.engine.rng import SplitMix64
    >>> data = HerdData([[1.0, 1.0, 0.0]], [[0.0, 0.0, float("inf")]], False, 1, "shared",
    ...                 "zero", 8, [0, 0])
    >>> x = [1]
    >>> work = new_herd_work(data, x)
    >>> picks = []
    >>> for _ in range(4):
    ...     herd_sweep(data, work, x, SplitMix64(0))
    ...     picks.append(x[0])
    >>> picks, data.tally                 # alternates between measurement 0 and missed
    ([0, 1, 0, 1], [1, 0])
    """
    M = data.M
    K = M + 2
    owner = work.owner
    for i in scan_order(len(x), data.random_scan, g):
        if x[i] < M:
            owner[x[i]] = -1
        key = herd_key(data, x, i, owner)
        w = work.table.get(key)
        p = conditional(data.W[i], data.cc[i], i, owner)
        if w is None and len(work.table) < data.capacity:
            if data.init == "conditional":
                w = list(p)
            elif data.init == "zero":
                w = [0.0] * K
            else:
                w = [g.uniform() for _ in range(K)]
            # a candidate the key's conditional gives probability 0 can never be picked
            w = [v if p[k] > 0.0 else -math.inf for k, v in enumerate(w)]
            work.table[key] = w
            data.tally[0] += 1
        if w is None:  # the table is full: an ordinary Gibbs draw
            data.tally[1] += 1
            k_new = draw_direct(data.W[i], data.cc[i], i, owner, g.uniform())
        else:
            best = -1
            for k in range(K):
                w[k] += p[k]
                if w[k] > (w[best] if best >= 0 else -math.inf):
                    best = k
            w[best] -= 1.0
            k_new = best
        if k_new < M:
            owner[k_new] = i
        x[i] = k_new

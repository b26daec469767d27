"""The tempered Gibbs loop of Zanella & Roberts, compiled once per problem kind (numba).

The twin of :func:`rankedassign.engine.tempered.run_reference`, operation for operation. A kind
supplies three compiled row functions and :func:`make_tempered` compiles the loop for them
(as :func:`rankedassign.engine._kernels.make_driver` does for the chains):

* ``row_weights(data, work, state, p) -> Z``: ``p[i] = g_i(x_i | x_-i) / π_i(x_i | x_-i)``
  for every row ``i`` of the state ``state`` (and whatever the move needs into ``work``);
  returns ``Z = Σ_i p[i]`` summed left to right, or ``-1.0`` if a ratio is not a finite
  non-negative number in the kind's arithmetic;
* ``move(data, work, zkeys, state, r, h, rs) -> (h, changed)``: draw row ``r``'s new value
  from its tempered conditional ``g_r`` with uniforms of the stream ``rs``
  (:func:`rankedassign.engine._kernels.next_uniform`), write it into ``state`` (and ``work``),
  update the Zobrist hash ``h`` (``h ^= zkeys[l, a] ^ zkeys[l, c]`` for every position ``l``
  whose value changes from ``a`` to ``c``); ``changed`` tells whether any position changed;
* ``accumulate(data, work, state, acc, w)``: add the weight ``w`` to the kind's marginal
  accumulator ``acc`` (a 2-D float64 array) at the values of ``state``.

A run is a :class:`TemperedRun`: the state, the ratios, the accumulator, the unique set and
the running sums. The moves run in slices (:func:`make_tempered`'s ``steps``), so a signal
ends a long run within one slice; moves in several calls are the moves of one call, bit for
bit.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ..numba_options import instantiate, jit
from ._kernels import EMPTY, OTHER, next_uniform, probe, same_row

__all__ = ["OK", "UNDERFLOW", "NEED_ROOM", "TemperedRun", "make_tempered", "store_ratio", "visit",
           "rehash"]

#: Status codes of a run's start and of its slices.
OK, UNDERFLOW, NEED_ROOM = 0, 1, 2


class TemperedRun(NamedTuple):
    """The state of a compiled tempered run between two slices (built and grown in Python).

    Attributes
    ----------
    state : ndarray, shape (L,), int32
        The chain's state.
    p : ndarray, shape (R,), float64
        Every row's ratio at ``state``.
    acc : ndarray, 2-D, float64
        The kind's marginal accumulator.
    states : ndarray, shape (cap, L), int32
        The unique states in discovery order.
    hashes : ndarray, shape (cap,), uint64
        Their Zobrist hashes.
    counts : ndarray, shape (cap,), int64
        Their visits.
    table : ndarray, shape (2 cap,), int64
        Open-addressing index of the unique states: ``index + 1`` (0 empty), a power of two
        long.
    hu : ndarray, shape (3,), uint64
        ``[hash of the state, unique states, stream state]``.
    fs : ndarray, shape (3,), float64
        ``[Σ w, Σ w², Z]``.
    """

    state: np.ndarray
    p: np.ndarray
    acc: np.ndarray
    states: np.ndarray
    hashes: np.ndarray
    counts: np.ndarray
    table: np.ndarray
    hu: np.ndarray
    fs: np.ndarray


def row_weights(data, work, state, p):  # pragma: no cover - replaced in every instantiation
    raise NotImplementedError


def move(data, work, zkeys, state, r, h, rs):  # pragma: no cover - replaced
    raise NotImplementedError


def accumulate(data, work, state, acc, w):  # pragma: no cover - replaced
    raise NotImplementedError


@jit(inline="always")
def store_ratio(p, Sb, n, rr, s, sb):
    """Row ``n``'s ratio ``p_n = (R_n(x_n) S_n) / Sb_n`` into ``p``, ``Sb_n`` into ``Sb``.

    The last step of every kind's ``row_weights``. The references' ``weights`` run this same
    function as plain Python (``rankedassign.engine.tempered.store_ratio``, its ``py_func``),
    on lists.

    Parameters
    ----------
    p, Sb : ndarray of float64, shape (R,)
        The ratios and the rows' tempered totals; entry ``n`` written unless refused.
    n : int
        The row.
    rr : float
        ``R_n(x_n) = (g_n / π_n)(x_n)`` up to the sums.
    s, sb : float
        The row's sums of its weights and of its tempered weights.

    Returns
    -------
    float
        The ratio, or -1.0 (nothing written) when it is not a finite non-negative number.
    """
    ratio = (rr * s) / sb
    if not (ratio >= 0.0 and ratio < np.inf):
        return -1.0
    p[n] = ratio
    Sb[n] = sb
    return ratio


@jit()
def visit(states, hashes, counts, table, state, h, n_u):
    """Count one visit of ``state`` (hash ``h``) in the unique set; return the new size.

    A new state is appended (the caller keeps ``2 (n_u + 1) <= capacity``); a hash hit is
    confirmed on the whole state.

    Parameters
    ----------
    states : ndarray of int32, shape (cap, L)
        The unique states.
    hashes : ndarray of uint64, shape (cap,)
        Their hashes.
    counts : ndarray of int64, shape (cap,)
        Their visits.
    table : ndarray of int64, shape (2 cap,)
        Open-addressing index: ``index + 1``, 0 empty; a power of two long.
    state : ndarray of int32, shape (L,)
        The state visited.
    h : np.uint64
        Its hash.
    n_u : int
        Unique states so far.

    Returns
    -------
    int
        ``n_u``, or ``n_u + 1`` when ``state`` is new.

    Examples
    --------
    >>> import numpy as np
    >>> states, hashes = np.empty((4, 1), np.int32), np.empty(4, np.uint64)
    >>> counts, table = np.zeros(4, np.int64), np.zeros(8, np.int64)
    >>> x = np.array([3], np.int32)
    >>> n = visit(states, hashes, counts, table, x, np.uint64(5), 0)
    >>> n = visit(states, hashes, counts, table, x, np.uint64(5), n)
    >>> int(n), counts[:1].tolist()
    (1, [2])
    """
    slot, cand = probe(table.shape[0], h, _look_state, (table, hashes, states, state, h))
    if cand >= 0:
        counts[cand] += 1
        return n_u
    states[n_u] = state
    hashes[n_u] = h
    counts[n_u] = 1
    table[slot] = n_u + 1
    return n_u + 1


@jit()
def rehash(hashes, n_u, table):
    """Insert unique states ``0..n_u-1`` by their ``hashes`` into the empty ``table``.

    Parameters
    ----------
    hashes : ndarray of uint64, shape (>= n_u,)
        The states' hashes.
    n_u : int
        Unique states.
    table : ndarray of int64
        Zero on entry, a power of two long (more than ``n_u`` entries).

    Examples
    --------
    >>> import numpy as np
    >>> table = np.zeros(4, np.int64)
    >>> rehash(np.array([1, 5], np.uint64), 2, table)
    >>> table.tolist()
    [0, 1, 2, 0]
    """
    for u in range(n_u):  # each state to the first empty entry of its hash's probe
        t, _ = probe(table.shape[0], hashes[u], _look_empty, (table,))
        table[t] = u + 1


@jit(inline="always")
def _look_state(tab, slot):
    """:func:`~rankedassign.engine._kernels.probe`'s ``look`` of the unique set of a run (its
    index, hashes and states; the state and its hash)."""
    table, hashes, states, state, h = tab
    if table[slot] == 0:
        return EMPTY
    cand = table[slot] - 1
    if hashes[cand] == h and same_row(states, cand, state):
        return cand
    return OTHER


@jit(inline="always")
def _look_empty(tab, t):
    """:func:`~rankedassign.engine._kernels.probe`'s ``look`` of a rehash: free or taken."""
    return EMPTY if tab[0][t] == 0 else OTHER


def _start(data, work, zkeys, run):
    """The run (a :class:`TemperedRun`) at its start state: its hash, ``U = {x0}`` (count 0),
    the ratios and ``Z``.

    Parameters
    ----------
    data, work : records
        The kind's data and workspace (read by its row functions).
    zkeys : ndarray of uint64, shape (L, K)
        Zobrist keys.
    run : TemperedRun
        ``state`` the start state; the rest filled.

    Returns
    -------
    int
        :data:`OK` or :data:`UNDERFLOW`.
    """
    state, p, states, hashes = run.state, run.p, run.states, run.hashes
    counts, table, hu, fs = run.counts, run.table, run.hu, run.fs
    h = np.uint64(0)
    for i in range(state.shape[0]):
        h ^= zkeys[i, state[i]]
    states[0] = state
    hashes[0] = h
    counts[0] = 0
    table[np.int64(h & np.uint64(table.shape[0] - 1))] = 1
    hu[0] = h
    hu[1] = 1
    Z = row_weights(data, work, state, p)
    fs[0] = 0.0
    fs[1] = 0.0
    fs[2] = Z
    return OK if Z > 0.0 else UNDERFLOW


def _steps(data, work, zkeys, run, t0, t1):
    """Moves ``t0 .. t1 - 1`` of a run (:func:`_start`), in place.

    Returns ``(status, t)``: :data:`OK` with ``t = t1``; :data:`NEED_ROOM` with the move
    ``t`` not yet made when the unique set may not hold one more state (grow it, then go on
    from ``t``); :data:`UNDERFLOW` when a ratio is not representable.

    Parameters
    ----------
    data, work, zkeys, run
        As in :func:`_start` (``run`` as the last call left it).
    t0, t1 : int
        The moves to make.

    Returns
    -------
    (int, int)
        The status and the next move ``t``.
    """
    state, p, acc, states, hashes = run.state, run.p, run.acc, run.states, run.hashes
    counts, table, hu, fs = run.counts, run.table, run.hu, run.fs
    R = p.shape[0]
    rs = hu[2:3]
    h = hu[0]
    n_u = np.int64(hu[1])
    wsum = fs[0]
    w2sum = fs[1]
    Z = fs[2]
    status = OK
    t = t0
    while t < t1:
        if 2 * (n_u + 1) > states.shape[0]:
            status = NEED_ROOM
            break
        # the row: i with probability p_i / Z (the first whose running sum exceeds u Z)
        target = next_uniform(rs) * Z
        r = R - 1
        acc_p = 0.0
        for i in range(R):
            acc_p += p[i]
            if acc_p > target:
                r = i
                break
        h, changed = move(data, work, zkeys, state, r, h, rs)
        t += 1
        if changed:
            Z = row_weights(data, work, state, p)
            if not Z > 0.0:
                status = UNDERFLOW
                break
        # the state's importance weight 1 / Z(x)
        w = 1.0 / Z
        wsum += w
        w2sum += w * w
        accumulate(data, work, state, acc, w)
        n_u = visit(states, hashes, counts, table, state, h, n_u)
    hu[0] = h
    hu[1] = np.uint64(n_u)
    fs[0] = wsum
    fs[1] = w2sum
    fs[2] = Z
    return status, t


def make_tempered(name, row_weights, move, accumulate, *, cache=None):
    """Compile the tempered loop for one problem kind's row functions.

    Parameters
    ----------
    name : str
        Unique name of the kind (names the compiled functions and their cache files).
    row_weights, move, accumulate : compiled functions
        The kind's row functions (module docstring).
    cache : bool, optional
        As in :func:`rankedassign.numba_options.jit`.

    Returns
    -------
    start, steps : compiled functions
        ``start(data, work, zkeys, run) -> status`` and ``steps(data, work, zkeys, run, t0,
        t1) -> (status, t)`` (``run`` a :class:`TemperedRun`).

    Examples
    --------
    A toy kind: one row, two values, ``π`` uniform, so every ratio is 1:

    >>> import numpy as np
    >>> @jit(cache=False)
    ... def weights(data, work, state, p):
    ...     p[0] = 1.0
    ...     return 1.0
    >>> @jit(cache=False)
    ... def flip(data, work, zkeys, state, r, h, rs):
    ...     c = 1 if next_uniform(rs) < 0.5 else 0
    ...     if c == state[0]:
    ...         return h, False
    ...     h ^= zkeys[0, state[0]] ^ zkeys[0, c]
    ...     state[0] = c
    ...     return h, True
    >>> @jit(cache=False)
    ... def add(data, work, state, acc, w):
    ...     acc[0, state[0]] += w
    >>> start, steps = make_tempered("coin", weights, flip, add, cache=False)
    >>> run = TemperedRun(
    ...     state=np.zeros(1, np.int32), p=np.zeros(1), acc=np.zeros((1, 2)),
    ...     states=np.empty((64, 1), np.int32), hashes=np.empty(64, np.uint64),
    ...     counts=np.zeros(64, np.int64), table=np.zeros(128, np.int64),
    ...     hu=np.array([0, 0, 7], np.uint64), fs=np.zeros(3))
    >>> zkeys = np.array([[1, 2]], np.uint64)
    >>> int(start((0.0,), (0,), zkeys, run)), steps((0.0,), (0,), zkeys, run, 0, 100)
    (0, (0, 100))
    >>> float(run.acc.sum()), int(run.counts[:2].sum())
    (100.0, 100)
    """
    bindings = {"row_weights": row_weights, "move": move, "accumulate": accumulate}
    start = instantiate(_start, f"tempered_start_{name}", bindings, cache=cache)
    steps = instantiate(_steps, f"tempered_steps_{name}", bindings, cache=cache)
    return start, steps

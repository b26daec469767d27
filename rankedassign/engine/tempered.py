"""Tempered Gibbs sampling (Zanella & Roberts 2019), the part shared by the problem kinds.

At state ``x`` every row ``i`` of a problem has the ratio
``p_i(x) = g_i(x_i | x_-i) / π_i(x_i | x_-i)`` of its tempered conditional ``g_i ∝ π_i^β`` to
its conditional. A move picks row ``i`` with probability ``p_i(x) / Z(x)``,
``Z(x) = Σ_i p_i(x)``, and draws ``x_i`` from ``g_i``. The chain is reversible with respect to
``f(x) ∝ π(x) Z(x)``, so the weights ``1 / Z(x)`` of its states turn their averages into
expectations under ``π``.

What a *row* is and how its conditional is computed is the kind's: a row of the single-sensor
matrix (:mod:`rankedassign.single.tempered`, whose rows keep running sums), an object's joint
measurement tuple (:mod:`rankedassign.multisensor.tempered`), a sensor's entry of the birth
tuple (:mod:`rankedassign.adaptive_birth.tempered`). The loop is written once for every kind:
:func:`run_reference` in plain Python (the specification of record) and its numba twin
:mod:`rankedassign.engine._tempered_kernels`, compiled for each kind's row functions;
:func:`run_compiled` runs the twin in slices and grows its unique set.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ..numba_options import interruptible
from . import _tempered_kernels
from ._kernels import zobrist_keys
from .rng import ZOBRIST_SEED, SplitMix64, chain_state

__all__ = ["TemperedResult", "run_reference", "run_compiled", "ess", "pick_row"]

#: :func:`rankedassign.engine._tempered_kernels.store_ratio` run as plain Python: the
#: references' ``weights`` store each row's ratio with the kernels' own text.
store_ratio = getattr(_tempered_kernels.store_ratio, "py_func", _tempered_kernels.store_ratio)


class TemperedResult(NamedTuple):
    """Unique states and importance-weighted marginals of a tempered Gibbs run.

    Attributes
    ----------
    assignments : ndarray, int64
        Each unique assignment visited, in order of discovery (the start state first), in the
        kind's layout: shape ``(n_unique, P)`` column indices for an
        :class:`~rankedassign.AssignmentProblem`, ``(n_unique, P, V)`` labels ``γ`` for a
        :class:`~rankedassign.multisensor.MultiSensorProblem`, ``(n_unique, V)`` tuples for
        an :class:`~rankedassign.adaptive_birth.AdaptiveBirthProblem`.
    costs : ndarray, shape (n_unique,)
        Their costs ``-ln w`` (``problem.cost_of``).
    counts : ndarray, shape (n_unique,), int64
        Visits after each move (the start state's may be 0); sums to ``n_steps``.
    marginals : ndarray or tuple
        The importance-weighted marginals ``Σ_t w_t 1[x_t ∈ ·] / Σ_t w_t`` over the states
        after each move, ``w_t = 1 / Z(x_t)``, in the layout of the kind's exact marginals
        (:func:`oracle.marginals`): a ``(P, M + 2)`` array for the single-sensor kind, a
        :class:`~rankedassign.multisensor.tempered.TemperedMarginals` (``dead``, ``tuples``,
        ``sensors``) for the multi-sensor kind, a list of ``V`` arrays ``(M_v + 1,)`` for the
        adaptive-birth kind. All zero when ``n_steps = 0``.
    n_steps : int
        Moves made (each one row update).
    ess : float
        Kish's effective sample size of the weights, ``(Σ w)^2 / Σ w^2`` (0 without moves).
    """

    assignments: np.ndarray
    costs: np.ndarray
    counts: np.ndarray
    marginals: np.ndarray
    n_steps: int
    ess: float


def ess(wsum: float, w2sum: float) -> float:
    """Kish's effective sample size ``(Σ w)^2 / Σ w^2`` (0.0 when there is no weight).

    Parameters
    ----------
    wsum, w2sum : float
        The sum of the weights and of their squares.

    Returns
    -------
    float

    Examples
    --------
    >>> ess(3.0, 3.0), ess(0.0, 0.0)
    (3.0, 0.0)
    """
    return float(wsum * wsum / w2sum) if w2sum > 0 else 0.0


def pick_row(p, Z, g) -> int:
    """The row of one move: the first whose running sum of ``p`` exceeds ``u Z``.

    Parameters
    ----------
    p : list of float
        Every row's ratio (at least one row).
    Z : float
        Their sum.
    g : SplitMix64
        The stream (one uniform ``u``).

    Returns
    -------
    int
        The row; the last one if rounding leaves none.

    Examples
    --------
    >>> class Half:
    ...     def uniform(self):
    ...         return 0.5
    >>> pick_row([1.0, 1.0, 2.0], 4.0, Half())
    2
    """
    target = g.uniform() * Z
    r, run = len(p) - 1, 0.0
    for i in range(len(p)):
        run += p[i]
        if run > target:
            r = i
            break
    return r


def run_reference(weights, move, accumulate, data, work, x, n_rows, acc, n_steps, base):
    """The tempered loop in plain Python: the specification of :func:`run_compiled`.

    Parameters
    ----------
    weights : callable
        ``weights(data, work, x, p) -> Z``: the ratios ``p_i(x)`` of every row into the list
        ``p``; ``Z = Σ_i p_i`` summed left to right, or ``-1.0`` when a ratio is not a finite
        non-negative number.
    move : callable
        ``move(data, work, x, r, g) -> changed``: row ``r``'s new value drawn from ``g_r``
        with uniforms of the stream ``g``, written into ``x`` (and ``work``); whether ``x``
        changed.
    accumulate : callable
        ``accumulate(data, work, x, acc, w)``: the weight ``w`` added to the marginal
        accumulator ``acc`` (a list of lists) at the values of ``x``.
    data, work
        The kind's inputs and bookkeeping (``work`` in the start state ``x``).
    x : list of int
        The start state, updated in place.
    n_rows : int
        Rows (length of ``p``), >= 1.
    acc : list of list of float
        The accumulator, zero.
    n_steps : int
        Moves.
    base : int
        Base key of the stream (:func:`rankedassign.engine.rng.base_key`); the moves draw from
        ``SplitMix64(chain_state(base, 0))``.

    Returns
    -------
    tuple or None
        ``(states, counts, wsum, w2sum)``: the unique states (tuples, in order of discovery,
        the start first, with its count 0 unless revisited), their visits after each move, and
        the sums of the weights ``1 / Z`` and of their squares; None when a state's ratios are
        not representable (the kind says why).

    Notes
    -----
    One move:

    1. one uniform ``u``: row ``r`` is the first whose running sum of ``p`` exceeds ``u Z``
       (the last row if rounding leaves none);
    2. ``move`` draws row ``r``'s value from ``g_r``;
    3. if the state changed, every ratio and ``Z`` are computed again (else they stay);
    4. the state gets the weight ``w = 1 / Z``, ``accumulate`` adds it to the marginals, and
       the state is counted in the unique set.

    Examples
    --------
    A toy kind: one row, two values, ``π`` uniform, so every ratio is 1:

    >>> def weights(data, work, x, p):
    ...     p[0] = 1.0
    ...     return 1.0
    >>> def move(data, work, x, r, g):
    ...     c = 1 if g.uniform() < 0.5 else 0
    ...     changed, x[0] = c != x[0], c
    ...     return changed
    >>> def add(data, work, x, acc, w):
    ...     acc[0][x[0]] += w
    >>> acc = [[0.0, 0.0]]
    >>> states, counts, wsum, _ = run_reference(weights, move, add, None, None, [0], 1, acc,
    ...                                         100, 7)
    >>> sorted(states), sum(counts), wsum, sum(acc[0])
    ([(0,), (1,)], 100, 100.0, 100.0)
    """
    g = SplitMix64(chain_state(base, 0))
    p = [0.0] * n_rows
    Z = weights(data, work, x, p)
    if not Z > 0.0:
        return None
    index = {tuple(x): 0}
    states, counts = [tuple(x)], [0]
    wsum = w2sum = 0.0
    for _ in range(n_steps):
        r = pick_row(p, Z, g)
        if move(data, work, x, r, g):
            Z = weights(data, work, x, p)
            if not Z > 0.0:
                return None
        w = 1.0 / Z
        wsum += w
        w2sum += w * w
        accumulate(data, work, x, acc, w)
        key = tuple(x)
        if key in index:
            counts[index[key]] += 1
        else:
            index[key] = len(states)
            states.append(key)
            counts.append(1)
    return states, counts, wsum, w2sum


def _grow(run):
    """The run with its unique set doubled (states, hashes, counts, a fresh hash table)."""
    states, hashes, counts = run.states, run.hashes, run.counts
    n_u = int(run.hu[1])
    cap = 2 * states.shape[0]
    new_states = np.empty((cap, states.shape[1]), dtype=np.int32)
    new_states[:n_u] = states[:n_u]
    new_hashes = np.empty(cap, dtype=np.uint64)
    new_hashes[:n_u] = hashes[:n_u]
    new_counts = np.zeros(cap, dtype=np.int64)
    new_counts[:n_u] = counts[:n_u]
    table = np.zeros(2 * cap, dtype=np.int64)
    with interruptible:
        _tempered_kernels.rehash(new_hashes, n_u, table)
    return run._replace(states=new_states, hashes=new_hashes, counts=new_counts, table=table)


def run_compiled(kernels, data, work, x0, n_values, n_rows, acc, n_steps, base, moves):
    """The compiled tempered loop (:func:`make_tempered
    <rankedassign.engine._tempered_kernels.make_tempered>`), bit for bit
    :func:`run_reference`.

    Parameters
    ----------
    kernels : tuple
        ``(start, steps)`` compiled for the kind.
    data, work : tuple
        The kind's compiled inputs and workspace (``work`` in the start state ``x0``): named
        tuples of the kind's kernel module.
    x0 : ndarray, shape (L,), int32
        Start state; every entry in ``0..n_values-1``.
    n_values : int
        Width of the Zobrist table.
    n_rows : int
        Rows, >= 1.
    acc : ndarray, 2-D, float64
        The accumulator, zero; filled in place.
    n_steps : int
        Moves.
    base : int
        Base key of the stream.
    moves : int
        Moves per compiled slice (>= 1); between slices the interpreter runs pending signal
        handlers. The bits do not depend on it.

    Returns
    -------
    tuple or None
        ``(states, counts, wsum, w2sum)`` as :func:`run_reference` (``states`` an ``(n_u,
        L)`` int32 array), or None when a state's ratios are not representable.

    Examples
    --------
    >>> from rankedassign.engine import _tempered_kernels as tk
    >>> from rankedassign.numba_options import jit
    >>> from rankedassign.engine._kernels import next_uniform
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
    >>> kernels = tk.make_tempered("coin_doc", weights, flip, add, cache=False)
    >>> acc = np.zeros((1, 2))
    >>> states, counts, wsum, _ = run_compiled(kernels, (0.0,), (0,), np.zeros(1, np.int32),
    ...                                        2, 1, acc, 100, 7, 30)
    >>> states.ravel().tolist(), int(counts.sum()), wsum, float(acc.sum())
    ([0, 1], 100, 100.0, 100.0)
    """
    start, steps = kernels
    L = x0.shape[0]
    with interruptible:
        zkeys = zobrist_keys(L, n_values, np.uint64(ZOBRIST_SEED))
    cap = 64
    run = _tempered_kernels.TemperedRun(
        state=np.ascontiguousarray(x0, dtype=np.int32).copy(), p=np.zeros(n_rows), acc=acc,
        states=np.empty((cap, L), dtype=np.int32), hashes=np.empty(cap, dtype=np.uint64),
        counts=np.zeros(cap, dtype=np.int64), table=np.zeros(2 * cap, dtype=np.int64),
        hu=np.array([0, 0, chain_state(base, 0)], dtype=np.uint64), fs=np.zeros(3))
    with interruptible:
        status = start(data, work, zkeys, run)
    t = 0
    while status == _tempered_kernels.OK and t < n_steps:
        with interruptible:
            status, t = steps(data, work, zkeys, run, t, min(n_steps, t + moves))
        if status == _tempered_kernels.NEED_ROOM:
            run = _grow(run)
            status = _tempered_kernels.OK
    if status != _tempered_kernels.OK:
        return None
    n_u = int(run.hu[1])
    return run.states[:n_u], run.counts[:n_u], float(run.fs[0]), float(run.fs[1])

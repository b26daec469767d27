"""numba kernel of the tempered Gibbs sampler of Zanella & Roberts (clean inputs only; validate
in :mod:`.tempered`).

Mirrors :func:`rankedassign.single.tempered.tempered_reference` operation for operation (same
sums in the same order, one SplitMix64 stream), so both give the same bits. The unique set is
an open-addressing hash set keyed by the Zobrist hash of the state (confirmed on the state),
grown by doubling between two calls; the moves run in slices (:func:`tempered_steps`), so a
signal ends a long run within one slice.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ..engine._kernels import next_uniform
from ..numba_options import jit
from .prepare import CANCEL_GUARD

#: Status codes of :func:`tempered_steps`.
OK, UNDERFLOW, NEED_ROOM = 0, 1, 2


class SingleTemperedData(NamedTuple):
    """The tempered kernel's inputs (:func:`rankedassign.single.tempered.sample_tempered`).

    Attributes
    ----------
    W : ndarray, shape (P, M + 2), float64
        Shifted weights (:func:`rankedassign.single.prepare.shifted_weights`).
    Wb : ndarray, shape (P, M + 2), float64
        ``W^beta`` (shifted per row).
    R : ndarray, shape (P, M + 2), float64
        ``W^(beta - 1)``, the ratio ``g / pi`` up to the row sums.
    refresh : int
        The row sums are formed again every ``refresh`` moves.
    """

    W: np.ndarray
    Wb: np.ndarray
    R: np.ndarray
    refresh: int


class SingleTemperedRun(NamedTuple):
    """The state of a tempered run between two slices (built and grown in Python).

    Attributes
    ----------
    state : ndarray, shape (P,), int32
        The chain's compact state.
    free : ndarray, shape (M,), float64
        Free-measurement mask of ``state``.
    S, Sb : ndarray, shape (P,), float64
        Every row's sums of ``W`` and ``Wb`` over its available candidates.
    p : ndarray, shape (P,), float64
        Every row's ratio.
    acc : ndarray, shape (P, M + 2), float64
        The marginal accumulator.
    states : ndarray, shape (cap, P), int32
        The unique states in discovery order.
    hashes : ndarray, shape (cap,), uint64
        Their Zobrist hashes.
    counts : ndarray, shape (cap,), int64
        Their visits.
    table : ndarray, shape (2 cap,), int64
        Open-addressing index of the unique states: ``index + 1`` (0 empty).
    hu : ndarray, shape (3,), uint64
        ``[hash of the state, unique states, stream state]``.
    fs : ndarray, shape (3,), float64
        ``[Σ w, Σ w², Z]``.
    """

    state: np.ndarray
    free: np.ndarray
    S: np.ndarray
    Sb: np.ndarray
    p: np.ndarray
    acc: np.ndarray
    states: np.ndarray
    hashes: np.ndarray
    counts: np.ndarray
    table: np.ndarray
    hu: np.ndarray
    fs: np.ndarray


@jit()
def _row_sums(W, Wb, free, state, i):
    """Row ``i``'s sums of ``W`` and ``Wb`` over its available candidates (the measurements no
    other row holds, its own included; missed; dead), left to right.

    Parameters
    ----------
    W, Wb : ndarray of float64, shape (P, M + 2)
        Shifted weights and their tempered power (:class:`SingleTemperedData`).
    free : ndarray of float64, shape (M,)
        Free-measurement mask of ``state``.
    state : ndarray of int32, shape (P,)
        The chain's compact state.
    i : int
        The row.

    Returns
    -------
    (float, float)
        The sums of ``W`` and of ``Wb``.
    """
    M = W.shape[1] - 2
    s = 0.0
    sb = 0.0
    own = state[i]
    for k in range(M):
        f = 1.0 if k == own else free[k]
        s += W[i, k] * f
        sb += Wb[i, k] * f
    s = (s + W[i, M]) + W[i, M + 1]
    sb = (sb + Wb[i, M]) + Wb[i, M + 1]
    return s, sb


@jit()
def _weights(R, S, Sb, state, p):
    """``p[i] = R[i, x_i] * S[i] / Sb[i]``; return their sum (or -1.0 if one is not finite).

    Parameters
    ----------
    R : ndarray of float64, shape (P, M + 2)
        ``W^(beta - 1)`` (:class:`SingleTemperedData`).
    S, Sb : ndarray of float64, shape (P,)
        Every row's sums (:func:`_row_sums`).
    state : ndarray of int32, shape (P,)
        The chain's compact state.
    p : ndarray of float64, shape (P,)
        Filled with the rows' ratios.

    Returns
    -------
    float
        ``Z = Σ p``, or -1.0.
    """
    Z = 0.0
    for i in range(state.shape[0]):
        if not (S[i] > 0.0 and Sb[i] > 0.0):  # every available weight underflowed
            return -1.0
        v = (R[i, state[i]] * S[i]) / Sb[i]
        if not (v >= 0.0 and v < np.inf):
            return -1.0
        p[i] = v
        Z += v
    return Z


@jit()
def tempered_start(data, zkeys, run):  # pragma: no cover (jit)
    """The run's state at its start ``state``: masks, sums, ``p``, ``Z`` and ``U = {x0}``.

    ``data`` is a :class:`SingleTemperedData`, ``run`` a :class:`SingleTemperedRun`. Returns
    :data:`OK` or :data:`UNDERFLOW`.

    Parameters
    ----------
    data : SingleTemperedData
        The call's data record.
    zkeys : ndarray of uint64, shape (P, M + 2)
        Zobrist keys.
    run : SingleTemperedRun
        The run, its ``state`` the start state; filled in place.

    Returns
    -------
    int
        :data:`OK`, or :data:`UNDERFLOW` when every ratio underflowed.
    """
    W, Wb, R = data.W, data.Wb, data.R
    state, free, S, Sb, p = run.state, run.free, run.S, run.Sb, run.p
    states, hashes, counts, table, hu, fs = (run.states, run.hashes, run.counts, run.table,
                                             run.hu, run.fs)
    P = state.shape[0]
    M = W.shape[1] - 2
    free[:] = 1.0
    for i in range(P):
        if state[i] < M:
            free[state[i]] = 0.0
    h = np.uint64(0)
    for i in range(P):
        h ^= zkeys[i, state[i]]
    states[0] = state
    hashes[0] = h
    counts[0] = 0
    table[np.int64(h & np.uint64(table.shape[0] - 1))] = 1
    hu[0] = h
    hu[1] = 1
    for i in range(P):
        S[i], Sb[i] = _row_sums(W, Wb, free, state, i)
    Z = _weights(R, S, Sb, state, p)
    fs[0] = 0.0
    fs[1] = 0.0
    fs[2] = Z
    return OK if Z > 0.0 else UNDERFLOW


@jit()
def tempered_steps(data, zkeys, run, t0, t1):  # pragma: no cover (jit)
    """Moves ``t0 .. t1 - 1`` of a run (:func:`tempered_start`), in place.

    Returns ``(status, t)``: :data:`OK` with ``t = t1``; :data:`NEED_ROOM` with the move ``t``
    not yet made when the unique set may not hold one more state (grow it, then continue from
    ``t``); :data:`UNDERFLOW`. Moves in several calls are the moves of one call, bit for bit.

    Parameters
    ----------
    data, zkeys, run
        As in :func:`tempered_start` (``run`` advanced in place).
    t0, t1 : int
        The moves to make.

    Returns
    -------
    (int, int)
        ``(status, t)`` as above.
    """
    W, Wb, R, refresh = data.W, data.Wb, data.R, data.refresh
    state, free, S, Sb, p, acc = run.state, run.free, run.S, run.Sb, run.p, run.acc
    states, hashes, counts, table, hu, fs = (run.states, run.hashes, run.counts, run.table,
                                             run.hu, run.fs)
    P = state.shape[0]
    M = W.shape[1] - 2
    K = M + 2
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
        # the row: i with probability p_i / Z
        target = next_uniform_of(hu) * Z
        r = P - 1
        csum = 0.0
        for i in range(P):
            csum += p[i]
            if csum > target:
                r = i
                break
        # release its measurement: available again to the other rows
        a = state[r]
        if a < M:
            free[a] = 1.0
            for i in range(P):
                if i != r:
                    S[i] += W[i, a]
                    Sb[i] += Wb[i, a]
        # the new value from the tempered conditional (inverse CDF over the available Wb)
        tot = 0.0
        for k in range(M):
            tot += Wb[r, k] * free[k]
        tot = (tot + Wb[r, M]) + Wb[r, M + 1]
        if not tot > 0.0:
            status = UNDERFLOW
            break
        u = next_uniform_of(hu) * tot
        c = -1
        csum = 0.0
        for k in range(K):
            wk = Wb[r, k] * free[k] if k < M else Wb[r, k]
            if wk > 0.0:
                csum += wk
                c = k
                if csum > u:
                    break
        if c < M:
            free[c] = 0.0
            for i in range(P):
                if i != r:
                    before = S[i]
                    beforeb = Sb[i]
                    S[i] -= W[i, c]
                    Sb[i] -= Wb[i, c]
                    if S[i] < CANCEL_GUARD * before or Sb[i] < CANCEL_GUARD * beforeb:
                        S[i], Sb[i] = _row_sums(W, Wb, free, state, i)
        if c != a:
            h ^= zkeys[r, a] ^ zkeys[r, c]
            state[r] = c
        if (t + 1) % refresh == 0:
            for i in range(P):
                S[i], Sb[i] = _row_sums(W, Wb, free, state, i)
        t += 1
        Z = _weights(R, S, Sb, state, p)
        if not Z > 0.0:
            status = UNDERFLOW
            break
        w = 1.0 / Z
        wsum += w
        w2sum += w * w
        for i in range(P):
            acc[i, state[i]] += w
        # the unique set
        mask = table.shape[0] - 1
        slot = np.int64(h & np.uint64(mask))
        found = -1
        while table[slot] != 0:
            cand = table[slot] - 1
            if hashes[cand] == h:
                same = True
                for i in range(P):
                    if states[cand, i] != state[i]:
                        same = False
                        break
                if same:
                    found = cand
                    break
            slot = (slot + 1) & mask
        if found >= 0:
            counts[found] += 1
        else:
            states[n_u] = state
            hashes[n_u] = h
            counts[n_u] = 1
            table[slot] = n_u + 1
            n_u += 1
    hu[0] = h
    hu[1] = np.uint64(n_u)
    fs[0] = wsum
    fs[1] = w2sum
    fs[2] = Z
    return status, t


@jit()
def next_uniform_of(hu):  # pragma: no cover (jit)
    """A uniform from the stream whose state is ``hu[2]`` (the run's record keeps it there).

    Parameters
    ----------
    hu : ndarray of uint64, shape (3,)
        The run's ``hu`` record; ``hu[2]`` is advanced.

    Returns
    -------
    float
        A uniform in ``[0, 1)``.
    """
    return next_uniform(hu[2:3])


@jit()
def rehash(hashes, n_u, table):  # pragma: no cover (jit)
    """Insert unique states ``0..n_u-1`` by their ``hashes`` into the empty ``table``.

    Parameters
    ----------
    hashes : ndarray of uint64, shape (cap,)
        Hashes of the unique states, in discovery order.
    n_u : int
        Unique states.
    table : ndarray of int64, shape (T,)
        Empty open-addressing index (T a power of two, at least ``2 n_u``), filled with
        ``index + 1``.
    """
    mask = table.shape[0] - 1
    for u in range(n_u):
        t = np.int64(hashes[u] & np.uint64(mask))
        while table[t] != 0:
            t = (t + 1) & mask
        table[t] = u + 1

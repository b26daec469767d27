"""numba kernel of the tempered Gibbs sampler of Zanella & Roberts (clean inputs only; validate
in :mod:`.tempered`).

Mirrors :func:`rankedassign.single.tempered.tempered_reference` operation for operation (same
sums in the same order, one SplitMix64 stream), so both give the same bits. The unique set is
an open-addressing hash set keyed by the Zobrist hash of the state (confirmed on the state),
grown by doubling.
"""

from __future__ import annotations

import numpy as np

from ..engine._kernels import next_uniform
from ..numba_options import jit
from .prepare import CANCEL_GUARD

#: Status codes of :func:`tempered_kernel`.
OK, UNDERFLOW = 0, 1


@jit()
def _row_sums(W, Wb, free, state, i):
    """Row ``i``'s sums of ``W`` and ``Wb`` over its available candidates (the measurements no
    other row holds, its own included; missed; dead), left to right."""
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
    """``p[i] = R[i, x_i] * S[i] / Sb[i]``; return their sum (or -1.0 if one is not finite)."""
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
def _grow(states, hashes, counts, n_u):
    """The unique set with twice the room (states, hashes, counts, table)."""
    cap = 2 * states.shape[0]
    P = states.shape[1]
    st = np.empty((cap, P), dtype=np.int32)
    hs = np.empty(cap, dtype=np.uint64)
    ct = np.zeros(cap, dtype=np.int64)
    st[:n_u] = states[:n_u]
    hs[:n_u] = hashes[:n_u]
    ct[:n_u] = counts[:n_u]
    table = np.zeros(2 * cap, dtype=np.int64)
    mask = 2 * cap - 1
    for u in range(n_u):
        t = np.int64(hs[u] & np.uint64(mask))
        while table[t] != 0:
            t = (t + 1) & mask
        table[t] = u + 1
    return st, hs, ct, table


@jit()
def tempered_kernel(W, Wb, R, zkeys, x0, rs, n_steps, refresh):  # pragma: no cover (jit)
    """Run ``n_steps`` moves; see :func:`rankedassign.single.tempered.tempered_reference`.

    Returns ``(status, states, counts, n_unique, acc, wsum, w2sum)``: the unique states in
    discovery order (``x0`` first) with their visits, the importance-weighted indicator sums
    ``acc`` (P, M + 2), and the sums of the weights and of their squares.
    """
    P = x0.shape[0]
    M = W.shape[1] - 2
    K = M + 2
    state = x0.copy()
    free = np.ones(M)
    for i in range(P):
        if state[i] < M:
            free[state[i]] = 0.0
    S = np.empty(P)
    Sb = np.empty(P)
    p = np.empty(P)
    acc = np.zeros((P, K))
    cap = 64
    states = np.empty((cap, P), dtype=np.int32)
    hashes = np.empty(cap, dtype=np.uint64)
    counts = np.zeros(cap, dtype=np.int64)
    table = np.zeros(2 * cap, dtype=np.int64)
    h = np.uint64(0)
    for i in range(P):
        h ^= zkeys[i, state[i]]
    states[0] = state
    hashes[0] = h
    table[np.int64(h & np.uint64(2 * cap - 1))] = 1
    n_u = 1
    wsum = 0.0
    w2sum = 0.0
    for i in range(P):
        S[i], Sb[i] = _row_sums(W, Wb, free, state, i)
    Z = _weights(R, S, Sb, state, p)
    if not Z > 0.0:
        return UNDERFLOW, states[:1], counts[:1], 1, acc, wsum, w2sum
    for t in range(n_steps):
        # the row: i with probability p_i / Z
        target = next_uniform(rs) * Z
        r = P - 1
        run = 0.0
        for i in range(P):
            run += p[i]
            if run > target:
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
            return UNDERFLOW, states[:n_u], counts[:n_u], n_u, acc, wsum, w2sum
        u = next_uniform(rs) * tot
        c = -1
        run = 0.0
        for k in range(K):
            wk = Wb[r, k] * free[k] if k < M else Wb[r, k]
            if wk > 0.0:
                run += wk
                c = k
                if run > u:
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
        if refresh > 0 and (t + 1) % refresh == 0:
            for i in range(P):
                S[i], Sb[i] = _row_sums(W, Wb, free, state, i)
        Z = _weights(R, S, Sb, state, p)
        if not Z > 0.0:
            return UNDERFLOW, states[:n_u], counts[:n_u], n_u, acc, wsum, w2sum
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
            if 2 * (n_u + 1) > states.shape[0]:
                states, hashes, counts, table = _grow(states, hashes, counts, n_u)
                mask = table.shape[0] - 1
                slot = np.int64(h & np.uint64(mask))
                while table[slot] != 0:
                    slot = (slot + 1) & mask
            states[n_u] = state
            hashes[n_u] = h
            counts[n_u] = 1
            table[slot] = n_u + 1
            n_u += 1
    return OK, states[:n_u], counts[:n_u], n_u, acc, wsum, w2sum

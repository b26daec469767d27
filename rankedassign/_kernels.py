"""numba kernels of the Gibbs samplers (clean inputs only; validate in :mod:`.samplers`).

Every helper lives in this file because numba's on-disk cache does not notice changes in other
modules. The kernels mirror :mod:`rankedassign.reference` operation for operation so that both
give bit-identical results for the same inputs:

* the random stream is SplitMix64 (:mod:`rankedassign._rng`), one stream per chain;
* a row update draws exactly one uniform and turns it into a candidate with the cumulative loop
  of :func:`sweep` (candidates in the order measurements ``0..M-1``, missed, dead);
* a random-scan sweep first draws its row permutation with the Fisher-Yates loop of
  :func:`sweep`.

State representation. A state is the vector of *compact* indices ``k_i`` in ``0..M+1`` (the
columns of :attr:`AssignmentProblem.compact_cost`): ``k < M`` is measurement ``k``, ``M`` is
missed, ``M + 1`` is dead. ``free[j]`` is 1.0 while measurement ``j`` is free, 0.0 while held.
States are de-duplicated with an open-addressing hash set keyed by a Zobrist hash (XOR of one
random 64-bit key per (row, compact index)) that is updated incrementally on every row change;
a hash hit is confirmed by comparing the full row.

Parallelism. :func:`speculate` (``parallel=True``) simulates a batch of chains, one ``prange``
iteration per chain with its own stream and slab rows; :func:`run_chains` replays the batch in
chain order with the sequential stall/stale logic (spec §3.3, "Parallelism"), so its result is
independent of the number of threads.

References
----------
.. [1] B.-N. Vo, B.-T. Vo, H. G. Hoang, "An Efficient Implementation of the Generalized
   Labeled Multi-Bernoulli Filter", IEEE Trans. Signal Process. 65(8):1975-1987, 2017.
.. [2] A. Trezza, D. J. Bucci Jr., P. K. Varshney, "On Gibbs Sampling Architecture for
   Labeled Random Finite Sets Multi-Object Tracking", arXiv:2306.15135, 2023.
.. [3] A. L. Zobrist, "A New Hashing Method with Application for Game Playing", Tech. Rep.
   88, Univ. of Wisconsin, 1970.
"""

from __future__ import annotations

import numpy as np
from numba import prange

from .numba_options import jit

# SplitMix64 constants (see rankedassign._rng); np.uint64 so numba stays in unsigned arithmetic.
_GOLDEN = np.uint64(0x9E3779B97F4A7C15)
_MUL1 = np.uint64(0xBF58476D1CE4E5B9)
_MUL2 = np.uint64(0x94D049BB133111EB)
_S30 = np.uint64(30)
_S27 = np.uint64(27)
_S31 = np.uint64(31)
_S11 = np.uint64(11)
_TWO_M53 = 1.0 / 9007199254740992.0
_ONE = np.uint64(1)

# Stall / stale reading codes (the public names are mapped in rankedassign.samplers).
STALL_OFF, STALL_GLOBAL_CONSECUTIVE, STALL_GLOBAL_CUMULATIVE, STALL_CHAIN_LOCAL = 0, 1, 2, 3
STALE_OFF, STALE_CONSECUTIVE, STALE_CUMULATIVE, STALE_LITERAL_SET, STALE_LITERAL_MULTISET = (
    0,
    1,
    2,
    3,
    4,
)

# Slots of the run counter array ``ctr``.
_NU, _NOBS, _NCHAINS, _STALE_RUN, _STALE_CUM, _STALE_FIRED, _DISCARDED = 0, 1, 2, 3, 4, 5, 6
# Slots of the per-chain counter array ``cctr``.
_STALL_RUN, _STALL_CUM, _NEW_IN_CHAIN, _LOCAL_UNIQUE = 0, 1, 2, 3


# ---------------------------------------------------------------------------------- RNG
@jit()
def mix64(z):
    """SplitMix64 output function on ``np.uint64`` (twin of :func:`rankedassign._rng.mix64`).

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign import _rng
    >>> int(mix64(np.uint64(1))) == _rng.mix64(1)
    True
    """
    # np.multiply / np.add wrap modulo 2**64 silently, also when NUMBA_DISABLE_JIT=1 runs
    # this as Python (the * and + operators warn on numpy scalar overflow there)
    z = np.multiply(z ^ (z >> _S30), _MUL1)
    z = np.multiply(z ^ (z >> _S27), _MUL2)
    return z ^ (z >> _S31)


@jit()
def chain_state(base, chain):
    """Initial stream state of chain ``chain``: ``mix64(base ^ mix64(chain + 1))``.

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign import _rng
    >>> int(chain_state(np.uint64(99), 3)) == _rng.chain_state(99, 3)
    True
    """
    return mix64(base ^ mix64(np.add(np.uint64(chain), _ONE)))


@jit()
def next_uniform(rs):
    """Advance the one-element ``uint64`` state array ``rs``; return a double in ``[0, 1)``.

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign import _rng
    >>> rs = np.array([5], dtype=np.uint64)
    >>> next_uniform(rs) == _rng.SplitMix64(5).uniform()
    True
    """
    s = np.add(rs[0], _GOLDEN)
    rs[0] = s
    return np.float64(mix64(s) >> _S11) * _TWO_M53


@jit()
def uniform_stream(state, n):
    """``n`` consecutive uniforms of the stream started at ``state`` (used by the tests).

    Examples
    --------
    >>> import numpy as np
    >>> uniform_stream(np.uint64(0), 3).shape
    (3,)
    """
    rs = np.empty(1, dtype=np.uint64)
    rs[0] = state
    out = np.empty(n)
    for t in range(n):
        out[t] = next_uniform(rs)
    return out


@jit()
def zobrist_keys(P, K, seed):
    """``(P, K)`` table of 64-bit Zobrist keys, drawn row-major from SplitMix64 at ``seed``.

    Examples
    --------
    >>> import numpy as np
    >>> zobrist_keys(2, 3, np.uint64(1)).shape
    (2, 3)
    """
    keys = np.empty((P, K), dtype=np.uint64)
    s = seed
    for i in range(P):
        for k in range(K):
            s = np.add(s, _GOLDEN)
            keys[i, k] = mix64(s)
    return keys


# ---------------------------------------------------------------------------------- Gibbs
@jit()
def draw_exact(cc, i, free, u):
    """Row ``i``'s draw from exact weights, for when every shifted weight underflowed.

    Used by :func:`sweep` with the row's uniform ``u`` when all of row ``i``'s available
    weights ``W`` are 0 (its cheapest entry is held by another row and the rest are more than
    ~745 above it). The weights are ``exp(-(cc[i, k] - m))``, ``m`` the cheapest *available*
    cost; the current entry of row ``i`` is always available and finite, so ``m`` is finite.
    The loop is the same inverse CDF as in :func:`sweep`. This path calls ``exp``, so it
    matches the reference as far as both use the same libm (they do on one machine).
    """
    M = cc.shape[1] - 2
    K = M + 2
    m = np.inf
    for k in range(K):
        if (k >= M or free[k] > 0.0) and cc[i, k] < m:
            m = cc[i, k]
    total = 0.0
    for k in range(K):
        if k >= M or free[k] > 0.0:
            total += np.exp(-(cc[i, k] - m))
    target = u * total
    acc = 0.0
    last = -1
    for k in range(K):
        if k >= M or free[k] > 0.0:
            w = np.exp(-(cc[i, k] - m))
            if w > 0.0:
                acc += w
                last = k
                if acc > target:
                    return k
    return last


@jit()
def sweep(W, cc, zkeys, state, free, h, rs, perm, cum, random_scan):
    """One Gibbs sweep over all rows, in place (Gauss-Seidel, spec §2.2); return the new hash.

    Parameters
    ----------
    W : ndarray, shape (P, M + 2), float64
        ``W[i, k] = exp(-(cc[i, k] - min_k cc[i, k]))`` (0 where ``cc`` is ``+inf``).
    cc : ndarray, shape (P, M + 2), float64
        Compact costs (used only by :func:`draw_exact`).
    zkeys : ndarray, shape (P, M + 2), uint64
        Zobrist keys.
    state : ndarray, shape (P,), int32
        Compact state, updated in place.
    free : ndarray, shape (M,), float64
        1.0 for a free measurement, 0.0 for a held one; updated in place.
    h : uint64
        Zobrist hash of ``state``.
    rs : ndarray, shape (1,), uint64
        Stream state.
    perm, cum : ndarray, shapes (P,) int64 and (M + 2,) float64
        Work space.
    random_scan : bool
        Systematic order ``0..P-1`` if False; otherwise a fresh uniformly random order drawn
        first, by Fisher-Yates from the identity: for ``t = P-1..1``,
        ``j = min(floor(u (t + 1)), t)``, swap ``perm[t], perm[j]``.

    Returns
    -------
    uint64
        Zobrist hash of the updated state.

    Notes
    -----
    Row ``i`` is drawn from its conditional (spec eq. 2.1) with one uniform ``u``:
    ``p(k) ∝ W[i, k]`` over the available candidates, in the order measurements ``0..M-1``
    (free, or held by row ``i`` itself, which is released first), missed, dead. ``total`` is
    their sum accumulated sequentially in that order, ``target = u * total``, and the pick is
    the first candidate whose running sum exceeds ``target`` (inverse CDF), or the last
    positive-weight candidate if rounding leaves none; :func:`draw_exact` if ``total = 0``.
    Held measurements enter the running sum as ``W * 0.0 = +0.0``, which leaves every partial
    sum bit-identical to the reference's loop that skips them; the running sums are stored so
    that the search is a branch-free count of ``cum[k] <= target`` (the sums never decrease,
    so the count is the index of the first one above ``target``). The draw is written out
    here rather than in a helper because a call per row costs ~10 % of the sweep.
    """
    P = state.shape[0]
    M = W.shape[1] - 2
    K = M + 2
    if random_scan:
        for t in range(P):
            perm[t] = t
        for t in range(P - 1, 0, -1):
            j = np.int64(next_uniform(rs) * (t + 1))
            if j > t:
                j = t
            tmp = perm[t]
            perm[t] = perm[j]
            perm[j] = tmp
    for t in range(P):
        i = perm[t] if random_scan else t
        k_old = state[i]
        if k_old < M:  # row i's own measurement is available to it
            free[k_old] = 1.0
        # total = sum over available k of W[i, k], sequentially in candidate order
        total = 0.0
        for k in range(M):
            total += W[i, k] * free[k]
            cum[k] = total
        total += W[i, M]
        cum[M] = total
        total += W[i, M + 1]
        cum[M + 1] = total
        u = next_uniform(rs)
        k_new = -1
        if total > 0.0:
            target = u * total
            pick = 0
            for k in range(K):
                pick += cum[k] <= target
            if pick < K:
                k_new = pick
            else:  # rounding left u * total at or above the last running sum
                for k in range(K - 1, -1, -1):
                    if W[i, k] > 0.0 and (k >= M or free[k] > 0.0):
                        k_new = k
                        break
        if k_new < 0:
            k_new = draw_exact(cc, i, free, u)
        if k_new < M:
            free[k_new] = 0.0
        if k_new != k_old:
            state[i] = k_new
            h = h ^ zkeys[i, k_old] ^ zkeys[i, k_new]
    return h


# ---------------------------------------------------------------------------------- unique set
# The hash set is a (size, 2) uint64 table of [hash, index + 1] rows (0 = empty slot), linear
# probing; hash and index share a cache line, and a hash hit is confirmed on the full state.
@jit()
def _find(table, uniq, state, h):
    """Index of ``state`` in the unique set, or ``-1 - slot`` of the empty slot to fill."""
    mask = table.shape[0] - 1
    s = np.int64(h & np.uint64(mask))
    P = state.shape[0]
    while True:
        v = table[s, 1]
        if v == 0:
            return -1 - s
        if table[s, 0] == h:
            u = np.int64(v) - 1
            same = True
            for i in range(P):
                if uniq[u, i] != state[i]:
                    same = False
                    break
            if same:
                return u
        s = (s + 1) & mask


@jit()
def _grow(uniq, uhash, counts, lastc, table, n_unique):
    """Double the unique-set arrays when full; rehash at load factor 0.5."""
    cap = uniq.shape[0]
    if n_unique >= cap:
        new_cap = 2 * cap
        u2 = np.empty((new_cap, uniq.shape[1]), dtype=uniq.dtype)
        u2[:cap] = uniq
        h2 = np.empty(new_cap, dtype=uhash.dtype)
        h2[:cap] = uhash
        c2 = np.zeros(new_cap, dtype=counts.dtype)
        c2[:cap] = counts
        l2 = np.full(new_cap, -1, dtype=lastc.dtype)
        l2[:cap] = lastc
        uniq, uhash, counts, lastc = u2, h2, c2, l2
    if 2 * (n_unique + 1) > table.shape[0]:
        size = table.shape[0]
        while 2 * (n_unique + 1) > size:
            size *= 2
        table = np.zeros((size, 2), dtype=np.uint64)
        mask = size - 1
        for u in range(n_unique):
            s = np.int64(uhash[u] & np.uint64(mask))
            while table[s, 1] != 0:
                s = (s + 1) & mask
            table[s, 0] = uhash[u]
            table[s, 1] = np.uint64(u + 1)
    return uniq, uhash, counts, lastc, table


@jit()
def _begin_chain(c, lastc, cctr):
    """Reset the per-chain counters; the start state (unique 0) is the chain's ``x[0]``."""
    cctr[:] = 0
    cctr[_LOCAL_UNIQUE] = 1
    lastc[0] = c


@jit()
def _end_chain(ctr, cctr, stale_mode, tau_stale):
    """Close a chain; return True if the stale rule stops the run (spec §3.2).

    * consecutive (T3): most recent completed chains in a row that added nothing to ``U``;
    * cumulative (T2): completed chains, ever, that added nothing;
    * literal-set (T1): ``|x| - n_u`` with ``x`` the set of samples, i.e. ``|U| - |U|``;
    * literal-multiset (T1): ``|x| - n_u`` with ``x`` the multiset of every chain's start state
      and every observation, i.e. ``(chains + observations) - |U|``.
    """
    ctr[_NCHAINS] += 1
    if cctr[_NEW_IN_CHAIN] > 0:
        ctr[_STALE_RUN] = 0
    else:
        ctr[_STALE_RUN] += 1
        ctr[_STALE_CUM] += 1
    fired = False
    if stale_mode == STALE_CONSECUTIVE:
        fired = ctr[_STALE_RUN] >= tau_stale
    elif stale_mode == STALE_CUMULATIVE:
        fired = ctr[_STALE_CUM] >= tau_stale
    elif stale_mode == STALE_LITERAL_SET:
        size_of_set = ctr[_NU]
        fired = size_of_set - ctr[_NU] >= tau_stale
    elif stale_mode == STALE_LITERAL_MULTISET:
        size_of_multiset = ctr[_NCHAINS] + ctr[_NOBS]
        fired = size_of_multiset - ctr[_NU] >= tau_stale
    if fired:
        ctr[_STALE_FIRED] = 1
    return fired


@jit()
def _start(zkeys, x0, M):
    """Free-measurement mask and Zobrist hash of the start state."""
    free0 = np.ones(M)
    h0 = np.uint64(0)
    for i in range(x0.shape[0]):
        k = x0[i]
        h0 = h0 ^ zkeys[i, k]
        if k < M:
            free0[k] = 0.0
    return free0, h0


# ---------------------------------------------------------------------------------- drivers
@jit(parallel=True)
def speculate(W, cc, zkeys, x0, free0, h0, base, c_first, n_batch, n_sweeps, random_scan,
              traj, hashes, states, frees, hs, rss, perms, cums):
    """Simulate the first ``n_sweeps`` sweeps of chains ``c_first .. c_first + n_batch - 1``.

    Chain ``c_first + b`` writes its trajectory to ``traj[b, :n_sweeps]`` and the Zobrist hash
    of each state to ``hashes[b, :n_sweeps]``, and leaves its simulation state (``states[b]``,
    ``frees[b]``, ``hs[b]``, ``rss[b, 0]``) ready for :func:`run_chains` to continue it. Chains
    are independent (each has its own stream), so the loop over chains runs in parallel
    (``prange``); each iteration writes only its own slab rows (``rss`` rows are padded to a
    cache line so that neighbouring streams do not share one).
    """
    for b in prange(n_batch):
        state = states[b]
        free = frees[b]
        perm = perms[b]
        cum = cums[b]
        rs = rss[b, 0:1]
        state[:] = x0
        free[:] = free0
        rs[0] = chain_state(base, c_first + b)
        h = h0
        for j in range(n_sweeps):
            h = sweep(W, cc, zkeys, state, free, h, rs, perm, cum, random_scan)
            traj[b, j, :] = state
            hashes[b, j] = h
        hs[b] = h


@jit()
def _prefix_length(used_hist, chain_length, workers):
    """Sweeps to speculate per chain: the ``1 - 1/workers`` quantile of the used lengths.

    Speculating ``s`` sweeps costs ``s / workers`` per chain in parallel; each sweep a chain
    needs beyond ``s`` costs 1 in the (sequential) replay. The expected time is minimal where
    ``P(length > s) = 1 / workers``. Before any chain has finished, speculate everything.
    """
    n = used_hist.sum()
    if n == 0:
        return chain_length
    need = n - n // workers  # at least this many chains end within s sweeps
    acc = 0
    for s in range(chain_length + 1):
        acc += used_hist[s]
        if acc >= need:
            return min(max(s, 1), chain_length)
    return chain_length


@jit()
def _advance(W, cc, zkeys, b, c, j0, j1, done, random_scan, traj, hashes, states, frees, hs, rss,
             perms, cums, uniq, uhash, counts, lastc, table, ctr, cctr, stall_mode, tau_stall):
    """Observations ``j0 + 1 .. j1`` of chain ``c``, whose simulation state is slab row ``b``.

    Sweeps ``<= done`` were simulated ahead by :func:`speculate` and are read from ``traj`` and
    ``hashes``; later ones are simulated here from the saved state (``done = 0``: all of them,
    the sequential kernel). Each observation is looked up in the unique set ``U`` (inserted if
    new, spec §3.3) and counted, then the stall rule is applied (spec §3.2):

    * global-consecutive (S3): observations since the chain's last find new to ``U``;
    * global-cumulative (S2): the chain's observations that were already in ``U``;
    * chain-local (S1): ``(j + 1) - NumUnique(x[0..j])``, repeats among the chain's own states
      including its start state (``lastc[u]`` is the last chain that saw unique ``u``).

    The caller guarantees room for ``j1 - j0`` new unique states (:func:`_room`), so this hot
    loop never reallocates; the look-up is written out here rather than called because a call
    passing the dozen arrays of the unique set costs as much as the look-up itself.

    Returns
    -------
    (j, stalled, done) : (int, bool, int)
        The last observation made, whether the stall rule fired there, sweeps simulated.
    """
    P = uniq.shape[1]
    mask = table.shape[0] - 1
    state = states[b]
    rs = rss[b, 0:1]
    h = hs[b]
    for j in range(j0 + 1, j1 + 1):
        if j <= done:
            x = traj[b, j - 1]
            hx = hashes[b, j - 1]
        else:
            h = sweep(W, cc, zkeys, state, frees[b], h, rs, perms[b], cums[b], random_scan)
            x = state
            hx = h
            done = j
        # look x up in U: linear probing from its hash, confirmed on the full state
        slot = np.int64(hx & np.uint64(mask))
        u = -1
        while True:
            v = table[slot, 1]
            if v == 0:
                break
            if table[slot, 0] == hx:
                cand = np.int64(v) - 1
                same = True
                for i in range(P):
                    if uniq[cand, i] != x[i]:
                        same = False
                        break
                if same:
                    u = cand
                    break
            slot = (slot + 1) & mask
        if u < 0:  # new to U: U.add(x); the stall run restarts
            u = ctr[_NU]
            table[slot, 0] = hx
            table[slot, 1] = np.uint64(u + 1)
            uniq[u, :] = x
            uhash[u] = hx
            counts[u] = 1
            lastc[u] = c
            ctr[_NU] += 1
            cctr[_NEW_IN_CHAIN] += 1
            cctr[_STALL_RUN] = 0
            cctr[_LOCAL_UNIQUE] += 1
        else:
            counts[u] += 1
            cctr[_STALL_RUN] += 1
            cctr[_STALL_CUM] += 1
            if lastc[u] != c:  # first visit of this chain to a state found before
                lastc[u] = c
                cctr[_LOCAL_UNIQUE] += 1
        ctr[_NOBS] += 1
        if stall_mode == STALL_GLOBAL_CONSECUTIVE:
            stalled = cctr[_STALL_RUN] >= tau_stall
        elif stall_mode == STALL_GLOBAL_CUMULATIVE:
            stalled = cctr[_STALL_CUM] >= tau_stall
        elif stall_mode == STALL_CHAIN_LOCAL:
            stalled = (j + 1) - cctr[_LOCAL_UNIQUE] >= tau_stall
        else:
            stalled = False
        if stalled:
            hs[b] = h
            return j, True, done
    hs[b] = h
    return j1, False, done


@jit()
def _room(uniq, table, n_unique):
    """Insertions the unique set takes before :func:`_grow` must run (load factor 0.5)."""
    return min(uniq.shape[0], table.shape[0] // 2) - n_unique


@jit()
def run_chains(W, cc, zkeys, x0, base, n_chains, chain_length, stall_mode, tau_stall,
               stale_mode, tau_stale, random_scan, batch, workers):
    """Short-chain sampler (spec §3.3); the original sampler is one chain without termination.

    Parameters
    ----------
    W, cc : ndarray, shape (P, M + 2), float64
        Shifted weights and compact costs (see :func:`sweep`).
    zkeys : ndarray, shape (P, M + 2), uint64
        Zobrist keys.
    x0 : ndarray, shape (P,), int32
        Feasible compact start state.
    base : uint64
        Base key of the run (chain ``c`` uses ``chain_state(base, c)``).
    n_chains, chain_length : int
        ``N_S`` and ``N_C``.
    stall_mode, tau_stall, stale_mode, tau_stale : int
        Reading codes (``STALL_*``, ``STALE_*``; 0 = off) and thresholds.
    random_scan : bool
        Row order of each sweep (see :func:`sweep`).
    batch : int
        0: simulate chain after chain, stopping each as soon as the stall rule fires.
        ``> 0``: take up to ``batch`` chains at a time (``max(64, 16 workers)`` in the first
        batch, doubling), simulate a prefix of each in parallel (:func:`speculate`,
        prefix length from :func:`_prefix_length`), then replay them in chain order applying
        stall and stale exactly as the sequential run does, continuing a chain in the replay
        if it outlives its prefix (spec §3.3, "Parallelism"). A chain's trajectory depends
        only on its stream, so the result does not depend on ``batch``, ``workers`` or the
        prefix lengths; only the discarded sweeps do.
    workers : int
        Threads used by :func:`speculate` (sets the prefix quantile).

    Returns
    -------
    uniq : ndarray, shape (n_unique, P), int32
        Unique compact states in discovery order, ``x0`` first.
    counts : ndarray, shape (n_unique,), int64
        Observations of each.
    ctr : ndarray, shape (7,), int64
        ``[n_unique, n_observations, n_chains_run, stale_run, stale_cumulative, stale_fired,
        n_speculative_discarded]``.
    """
    P = x0.shape[0]
    M = W.shape[1] - 2
    free0, h0 = _start(zkeys, x0, M)
    cap = 1024
    uniq = np.empty((cap, P), dtype=np.int32)
    uhash = np.empty(cap, dtype=np.uint64)
    counts = np.zeros(cap, dtype=np.int64)
    lastc = np.full(cap, -1, dtype=np.int64)
    table = np.zeros((2 * cap, 2), dtype=np.uint64)
    ctr = np.zeros(7, dtype=np.int64)
    cctr = np.zeros(4, dtype=np.int64)
    # U <- {x0}: x0 is stored (unique 0) but is not an observation (count 0 so far)
    slot = -1 - _find(table, uniq, x0, h0)
    table[slot, 0] = h0
    table[slot, 1] = 1
    uniq[0, :] = x0
    uhash[0] = h0
    ctr[_NU] = 1

    speculative = batch > 0
    nb = min(batch, n_chains) if speculative else 1
    traj = np.empty((nb, chain_length if speculative else 0, P), dtype=np.int32)
    hashes = np.empty((nb, chain_length if speculative else 0), dtype=np.uint64)
    states = np.empty((nb, P), dtype=np.int32)
    frees = np.empty((nb, M))
    hs = np.empty(nb, dtype=np.uint64)
    rss = np.empty((nb, 8), dtype=np.uint64)  # one stream per cache line
    perms = np.empty((nb, P), dtype=np.int64)
    cums = np.empty((nb, M + 2))
    used_hist = np.zeros(chain_length + 1, dtype=np.int64)
    # Batches start small (the first one learns the chain lengths for the prefix) and double
    # up to ``batch``: a run that stops early by stale then discards little.
    ramp = max(64, 16 * workers)
    c0 = 0
    while c0 < n_chains:
        n_b = min(nb, n_chains - c0)
        if speculative:
            n_b = min(n_b, ramp)
            ramp = min(2 * ramp, nb)
            s = _prefix_length(used_hist, chain_length, workers)
            speculate(W, cc, zkeys, x0, free0, h0, base, c0, n_b, s, random_scan, traj, hashes,
                      states, frees, hs, rss, perms, cums)
        else:
            s = 0
        stale = False
        for b in range(n_b):
            c = c0 + b
            if not speculative:
                states[b, :] = x0
                frees[b, :] = free0
                hs[b] = h0
                rss[b, 0] = chain_state(base, c)
            _begin_chain(c, lastc, cctr)
            done = s
            j = 0
            stalled = False
            while j < chain_length and not stalled:
                if _room(uniq, table, ctr[_NU]) <= 0:
                    uniq, uhash, counts, lastc, table = _grow(
                        uniq, uhash, counts, lastc, table, ctr[_NU]
                    )
                j, stalled, done = _advance(
                    W, cc, zkeys, b, c, j,
                    min(chain_length, j + _room(uniq, table, ctr[_NU])), done, random_scan,
                    traj, hashes, states, frees, hs, rss, perms, cums, uniq, uhash, counts,
                    lastc, table, ctr, cctr, stall_mode, tau_stall,
                )
            used_hist[j] += 1
            ctr[_DISCARDED] += done - j
            if _end_chain(ctr, cctr, stale_mode, tau_stale):
                ctr[_DISCARDED] += (n_b - b - 1) * s
                stale = True
                break
        if stale:
            break
        c0 += n_b
    n = ctr[_NU]
    return uniq[:n].copy(), counts[:n].copy(), ctr

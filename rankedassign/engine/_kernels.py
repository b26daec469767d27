"""The chain driver, written once for every problem type (numba; clean inputs only).

The architecture of the samplers — chains started from one state, one observation per sweep,
the global unique set ``U``, the stall and stale rules in every reading, speculative parallel
chains replayed in chain order — does not depend on what a *row update* is. A problem type
(single-sensor ranked assignment, multi-sensor, adaptive birth) supplies only

* ``alloc_work(data, nb) -> work``: a named tuple of arrays (the kind's workspace record,
  passed to :func:`make_driver` as ``work``), each with leading dimension ``nb``, the per-chain
  workspace of ``nb`` chains simulated at once (free-measurement masks, occupancy counters,
  scratch rows);
* ``reset_work(data, work, b, x0)``: put slab ``b`` of the workspace in the start state ``x0``;
* ``sweep(data, work, b, zkeys, state, h, rs) -> h``: one sweep (one observation) in place on
  the ``int32`` state vector ``state``, returning its new Zobrist hash (for every position
  ``l`` whose value changes from ``a`` to ``c``: ``h ^= zkeys[l, a] ^ zkeys[l, c]``), drawing
  uniforms from the chain's stream ``rs`` with :func:`rankedassign.engine._kernels.next_uniform`;

and, optionally, ``chain_done(data, work, b, j)`` (called in chain order when the chain of slab
``b`` ends at its observation ``j``, for a kind that keeps a tally per chain, such as the
herded draw's key-table fall-backs); :func:`make_driver` compiles the driver for it.
``data`` is the problem's named tuple of read-only arrays and scalars (its kernel data record,
built by the kind's ``prepare``; the scalars are named fields, never packed into an array). A
state is a flat ``int32`` vector of length ``L`` whose values index the columns of the
Zobrist table ``zkeys`` of shape ``(L, K)``.

How it is generic. :func:`_speculate`, :func:`_speculate_chain`, :func:`_advance`,
:func:`_new_run`, :func:`_run_slice`, :func:`_pack`, :func:`_unpack` and
:func:`_grow_run` below are plain Python templates that call the three functions above (and
each other) by their global names; :func:`rankedassign.numba_options.instantiate` compiles a
copy of each template whose globals bind those names to the problem's compiled functions.
numba freezes global functions at compile time, so an instantiation calls the row update
directly (as inlined as a hand-written kernel) and has its own cache file.

Unique set. States are de-duplicated with an open-addressing hash set keyed by the Zobrist hash
(XOR of one random 64-bit key per (position, value)), updated incrementally by the sweep; a
hash hit is confirmed on the full state. It is the :class:`UniqueSet` record.

Parallelism. :func:`_speculate` (``parallel=True``) simulates a batch of chains, one ``prange``
iteration per chain with its own stream and slab rows; :func:`_run_slice` replays the batch in
chain order with the sequential stall/stale logic (spec §3.3, "Parallelism"), so its result is
independent of the number of threads.

Slices. A compiled call cannot be interrupted: Python runs a signal handler (Ctrl-C's
``KeyboardInterrupt``, a SIGTERM handler) only when control is back in the interpreter. The
driver therefore runs in slices of a bounded number of sweeps (``budget``, which the samplers
size so that a slice takes at most about a tenth of a second): :func:`_new_run` builds the
run's state, a :class:`Run` of arrays (packed into plain tuples, :func:`_pack`, whenever it
crosses into Python), and each call of :func:`_run_slice` continues it where the last one
stopped. A slice stops only between two observations or between two speculation steps, and
keeps every position in ``Run.pos``, so the slices together perform exactly the operations of
one unbounded call: the result is the same bit for bit for every budget. Python calls
:func:`_new_run` and then :func:`_run_slice` for every slice, the first included: a compiled
entry that ran both would have the whole driver optimised and compiled once more for itself
(numba compiles a callee's code again into each caller): 1.6–6 s of a first call, against
about 25 µs of every run. The slices return two integers and no array,
so a signal that arrives during one is raised as itself in the Python loop between slices
(boxing an array runs Python code inside numba's return path, where a signal handler's
exception becomes a ``SystemError``; see :data:`rankedassign.numba_options.interruptible`;
boxing a named tuple there crashes, hence the plain tuples).
One sweep is never split: the longest pause between two checks is one slice plus one sweep.

Random streams. Every row update draws its uniforms with :func:`next_uniform` from a
one-element ``uint64`` state array, one SplitMix64 stream per chain started at
:func:`chain_state`; the pure-Python reference draws the same numbers from
:class:`rankedassign.engine.rng.SplitMix64` (tested bit for bit). :func:`zobrist_keys` draws
the Zobrist table from the same generator.

References
----------
.. [1] A. Trezza, D. J. Bucci Jr., P. K. Varshney, "On Gibbs Sampling Architecture for
   Labeled Random Finite Sets Multi-Object Tracking", arXiv:2306.15135, 2023.
.. [2] A. L. Zobrist, "A New Hashing Method with Application for Game Playing", Tech. Rep.
   88, Univ. of Wisconsin, 1970.
.. [3] G. L. Steele Jr., D. Lea, C. H. Flood, "Fast Splittable Pseudorandom Number
   Generators", OOPSLA 2014.
"""

from __future__ import annotations

from collections import namedtuple
from typing import NamedTuple

import numpy as np
from numba import prange

from ..numba_options import instantiate, interruptible, jit
from ..validation import (
    STALE_CONSECUTIVE,
    STALE_CUMULATIVE,
    STALE_LITERAL_MULTISET,
    STALE_LITERAL_SET,
    STALL_CHAIN_LOCAL,
    STALL_GLOBAL_CONSECUTIVE,
    STALL_GLOBAL_CUMULATIVE,
)

__all__ = ["mix64", "chain_state", "next_uniform", "uniform_stream", "zobrist_keys"]

# SplitMix64 constants (see rankedassign.engine.rng); np.uint64 so numba stays in unsigned
# arithmetic.
_GOLDEN = np.uint64(0x9E3779B97F4A7C15)
_MUL1 = np.uint64(0xBF58476D1CE4E5B9)
_MUL2 = np.uint64(0x94D049BB133111EB)
_S30 = np.uint64(30)
_S27 = np.uint64(27)
_S31 = np.uint64(31)
_S11 = np.uint64(11)
_TWO_M53 = 1.0 / 9007199254740992.0
_ONE = np.uint64(1)


@jit()
def mix64(z):
    """SplitMix64 output function on ``np.uint64`` (twin of :func:`rankedassign.engine.rng.mix64`).

    Parameters
    ----------
    z : np.uint64

    Returns
    -------
    np.uint64

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign.engine import rng as _rng
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

    Parameters
    ----------
    base : np.uint64
        The run's base state (from the seed).
    chain : int
        The chain's index (``>= 0``).

    Returns
    -------
    np.uint64

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign.engine import rng as _rng
    >>> int(chain_state(np.uint64(99), 3)) == _rng.chain_state(99, 3)
    True
    """
    return mix64(base ^ mix64(np.add(np.uint64(chain), _ONE)))


@jit()
def next_uniform(rs):
    """Advance the one-element ``uint64`` state array ``rs``; return a double in ``[0, 1)``.

    Parameters
    ----------
    rs : ndarray of uint64, shape (1,)
        The stream's state, advanced in place by the golden-ratio increment.

    Returns
    -------
    float
        The top 53 bits of ``mix64`` of the new state, times ``2^-53``.

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign.engine import rng as _rng
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

    Parameters
    ----------
    state : np.uint64
        The stream's state before the first draw.
    n : int
        Number of uniforms.

    Returns
    -------
    ndarray of float64, shape (n,)
        The values of ``n`` calls of :func:`next_uniform`.

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
def zobrist_keys(L, K, seed):
    """``(L, K)`` table of 64-bit Zobrist keys, drawn row-major from SplitMix64 at ``seed``.

    Position ``l`` of a sampler state holding value ``k`` contributes ``keys[l, k]`` to the
    state's hash (XOR over positions), so a change of one position updates the hash with two
    XORs.

    Parameters
    ----------
    L : int
        Positions of a state.
    K : int
        Values a position can hold.
    seed : np.uint64
        Start state of the SplitMix64 stream.

    Returns
    -------
    ndarray of uint64, shape (L, K)

    Examples
    --------
    >>> import numpy as np
    >>> zobrist_keys(2, 3, np.uint64(1)).shape
    (2, 3)
    """
    keys = np.empty((L, K), dtype=np.uint64)
    s = seed
    for i in range(L):
        for k in range(K):
            s = np.add(s, _GOLDEN)
            keys[i, k] = mix64(s)
    return keys



# ------------------------------------------------------------------------ open addressing
# The one probe of the open-addressing tables (the unique set, the herded draw's key table,
# the tempered loop's unique set): linear probing from the hash's home entry. Each table says
# through its own ``look`` what one index entry holds; the walk is written here once, so every
# table visits its entries in the same order.

#: What a probe's ``look`` says of an index entry that holds no hit: empty (the key is absent
#: and would go there), or holding another key (walk on). A hit is the key's stored index, >= 0.
EMPTY, OTHER = -1, -2


@jit(inline="always")
def probe(size, h, look, tab):
    """The first index entry on the probe sequence of hash ``h`` that is empty or holds the key.

    The entries ``t = h mod size, t + 1, t + 2, ...`` (mod ``size``) are read in turn by
    ``look(tab, t)``, until one is not :data:`OTHER`. Inlined into each caller, ``look``
    with it (``inline="always"``): the generated code is that of the loop written out.

    Parameters
    ----------
    size : int
        Entries of the index, a power of two; at least one is empty.
    h : np.uint64
        The key's hash.
    look : compiled function
        ``look(tab, t) -> int``: the stored index of the key at entry ``t`` (>= 0, a hit),
        :data:`EMPTY` or :data:`OTHER`.
    tab : tuple
        The table's arrays and the key, as ``look`` reads them.

    Returns
    -------
    (int, int)
        The entry ``t`` and ``look``'s answer there (a stored index or :data:`EMPTY`).

    Examples
    --------
    >>> import numpy as np
    >>> @jit(cache=False)
    ... def occupied(tab, t):
    ...     return EMPTY if tab[0][t] == 0 else OTHER
    >>> probe(4, np.uint64(6), occupied, (np.array([0, 1, 1, 1]),))
    (0, -1)
    """
    mask = size - 1
    t = np.int64(h & np.uint64(mask))
    while True:
        r = look(tab, t)
        if r != OTHER:
            return t, r
        t = (t + 1) & mask


@jit(inline="always")
def same_row(stored, u, key):
    """Whether row ``u`` of ``stored`` equals ``key`` (a hash hit confirmed on the whole key).

    Parameters
    ----------
    stored : ndarray of int32, shape (cap, L)
        Stored keys.
    u : int
        The row to compare.
    key : ndarray of int32, shape (L,)
        The key.

    Returns
    -------
    bool
    """
    for i in range(key.shape[0]):
        if stored[u, i] != key[i]:
            return False
    return True


# ------------------------------------------------------------------------ herded draw
# The key table of a herded chain (rankedassign.engine.herding), shared by every kind that
# herds: keys are a row id and an int32 vector of entries >= -1, stored with open addressing.
_HGOLD = np.uint64(0x9E3779B97F4A7C15)
_TWO = np.int64(2)


@jit(inline="always")
def key_hash(i, keyv):
    """Hash of row ``i``'s key vector ``keyv`` (entries >= -1), for the key table.

    Parameters
    ----------
    i : int
        The row (draw) id.
    keyv : ndarray of int32, shape (L,)
        The key vector.

    Returns
    -------
    np.uint64

    Examples
    --------
    >>> import numpy as np
    >>> k = np.array([1, -1], dtype=np.int32)
    >>> bool(key_hash(0, k) == key_hash(0, k.copy())), bool(key_hash(0, k) == key_hash(1, k))
    (True, False)
    """
    h = mix64(np.multiply(np.uint64(i + 1), _HGOLD))
    for t in range(keyv.shape[0]):
        h = mix64(h ^ np.uint64(np.int64(keyv[t]) + _TWO))
    return h


@jit(inline="always")
def table_find(i, keyv, h, krow, kst, tslot, thash):
    """Slot of row ``i``'s key in the table, or ``-1 - t`` with ``t`` the free table entry.

    ``krow``/``kst`` are the stored keys (row id, key vector) by slot, ``tslot``/``thash`` the
    open-addressing index (slot + 1, 0 = empty; the key's hash ``h``), a power of two long,
    walked by :func:`probe`.

    Parameters
    ----------
    i : int
        The row (draw) id.
    keyv : ndarray of int32, shape (L,)
        The key vector.
    h : np.uint64
        Its hash (:func:`key_hash`).
    krow : ndarray of int32, shape (cap,)
        Stored row ids by slot.
    kst : ndarray of int32, shape (cap, L)
        Stored key vectors by slot.
    tslot : ndarray of int64, shape (T,)
        Index: slot + 1, 0 for an empty entry; ``T`` a power of two larger than the keys
        stored (so an empty entry is always found).
    thash : ndarray of uint64, shape (T,)
        Hash of the key at each index entry.

    Returns
    -------
    int
        The key's slot, or ``-1 - t`` with ``t`` the empty index entry where it would go.
    """
    t, s = probe(tslot.shape[0], h, _look_key, (tslot, thash, krow, kst, i, keyv, h))
    return s if s >= 0 else -1 - t


@jit(inline="always")
def _look_key(tab, t):
    """:func:`probe`'s ``look`` of the key table (:func:`table_find`'s arrays and key)."""
    tslot, thash, krow, kst, i, keyv, h = tab
    v = tslot[t]
    if v == 0:
        return EMPTY
    s = v - 1
    if thash[t] == h and krow[s] == i and same_row(kst, s, keyv):
        return s
    return OTHER


@jit(inline="always")
def herd_lookup(i, keyv, cnt, capacity, krow, kst, tslot, thash):
    """The table slot of key ``(i, keyv)``: ``(slot, is_new)``, or ``(-1, False)`` when the
    key is new and the table holds ``capacity`` keys already.

    A new key is stored in slot ``cnt[0]`` (then incremented); ``cnt[1]`` counts the
    fall-backs (the full-table case). The twin of the dictionary look-up of
    :func:`rankedassign.engine.reference.herd_choice`.

    Parameters
    ----------
    i, keyv, krow, kst, tslot, thash
        As in :func:`table_find` (a new key is stored into them).
    cnt : ndarray of int64, shape (>= 2,)
        ``[keys stored, fall-backs, ...]`` of the table, updated.
    capacity : int
        The keys the table can hold.

    Returns
    -------
    slot : int
        The key's slot, or ``-1`` when the table is full.
    is_new : bool
        True when the key was stored by this call.
    """
    hk = key_hash(i, keyv)
    s = table_find(i, keyv, hk, krow, kst, tslot, thash)
    if s >= 0:
        return s, False
    if cnt[0] >= capacity:
        cnt[1] += 1
        return np.int64(-1), False
    e = -1 - s
    s = cnt[0]
    cnt[0] += 1
    tslot[e] = s + 1
    thash[e] = hk
    krow[s] = i
    for r in range(keyv.shape[0]):
        kst[s, r] = keyv[r]
    return s, True


@jit(inline="always")
def herd_pick(w, p, K, new, init_mode, rs):
    """One herded choice among ``K`` candidates on the key's weights ``w`` (twin of
    :func:`rankedassign.engine.reference.herd_choice`).

    A new key first gets its initial weights (``init_mode`` 0: ``p``, 1: zeros, 2: ``K``
    uniforms from ``rs``), ``-inf`` where ``p`` is 0. Then ``w += p``, the choice is the first
    candidate of ``p > 0`` of the largest ``w``, and ``w[choice] -= 1``.

    Parameters
    ----------
    w : ndarray of float64, shape (>= K,)
        The key's herding weights, updated in place.
    p : ndarray of float64, shape (>= K,)
        The conditional; at least one ``p[k] > 0``.
    K : int
        Number of candidates.
    new : bool
        The key was just stored (its weights are initialised first).
    init_mode : int
        Initial weights of a new key: 0 ``p``, 1 zeros, 2 uniforms.
    rs : ndarray of uint64, shape (1,)
        The chain's stream state (advanced by ``K`` uniforms for a new key in mode 2 only).

    Returns
    -------
    int
        The candidate chosen.
    """
    if new:
        for k in range(K):
            if init_mode == 0:
                w0 = p[k]
            elif init_mode == 1:
                w0 = 0.0
            else:
                w0 = next_uniform(rs)
            w[k] = w0 if p[k] > 0.0 else -np.inf
    best = -1
    bw = -np.inf
    for k in range(K):
        v = w[k] + p[k]
        w[k] = v
        if p[k] > 0.0 and (best < 0 or v > bw):
            best = k
            bw = v
    w[best] = bw - 1.0
    return best

class KeyTable(NamedTuple):
    """The key tables of ``nb`` herded chains and the scratch of their draws
    (:func:`alloc_key_table`), leading dimension ``nb``.

    A kind's herded workspace record is its Gibbs workspace's fields followed by these (one
    flat record: numba's parallel loop takes no nested tuple); it builds it from the two
    records, ``Work(*(gibbs[:] + ... + table[:]))``. ``K`` is the width of a draw's
    weights, ``L`` the length of a key vector, ``cap`` the keys a table holds and ``T`` (a
    power of two, at least ``2 cap``) its index slots.

    Attributes
    ----------
    p : ndarray, shape (nb, K), float64
        The draw's conditional.
    keyv : ndarray, shape (nb, L), int32
        The draw's key vector.
    hw : ndarray, shape (nb, cap, K), float64
        The herding weights of every key.
    kst : ndarray, shape (nb, cap, L), int32
        Stored key vectors.
    krow : ndarray, shape (nb, cap), int32
        Stored row (draw) ids.
    tslot : ndarray, shape (nb, T), int64
        Open-addressing index: slot + 1 (0 empty).
    thash : ndarray, shape (nb, T), uint64
        The key's hash at each index entry.
    cnt : ndarray, shape (nb, 3), int64
        The chain's ``[keys, fall-backs, sweeps]``.
    hist : ndarray, shape (nb, chain_length + 1, 2) or (nb, 1, 2), int64
        The tallies ``[keys, fall-backs]`` after each sweep, which speculation needs
        (``nb > 1``: a chain may be simulated past its last observation); one chain at a time
        reads ``cnt`` itself.
    """

    p: np.ndarray
    keyv: np.ndarray
    hw: np.ndarray
    kst: np.ndarray
    krow: np.ndarray
    tslot: np.ndarray
    thash: np.ndarray
    cnt: np.ndarray
    hist: np.ndarray


@jit()
def alloc_key_table(nb, K, L, cap, chain_length):
    """Empty key tables of ``nb`` herded chains (a :class:`KeyTable`).

    Parameters
    ----------
    nb : int
        Chains (slabs).
    K : int
        Width of a draw's weights.
    L : int
        Length of a key vector.
    cap : int
        Keys a table holds.
    chain_length : int
        Sweeps of a chain (sizes ``hist`` when ``nb > 1``).

    Returns
    -------
    KeyTable
        ``tslot``, ``thash``, ``cnt``, ``hist`` and ``p`` zero, the others uninitialised;
        ``T`` the smallest power of two ``>= 4`` and ``>= 2 cap``.

    Examples
    --------
    >>> t = alloc_key_table(2, 5, 3, 10, 4)
    >>> t.hw.shape, t.tslot.shape, t.hist.shape
    ((2, 10, 5), (2, 32), (2, 5, 2))
    """
    T = 4
    while T < 2 * cap:
        T *= 2
    return KeyTable(
        p=np.zeros((nb, K)), keyv=np.empty((nb, L), dtype=np.int32),
        hw=np.empty((nb, cap, K)), kst=np.empty((nb, cap, L), dtype=np.int32),
        krow=np.empty((nb, cap), dtype=np.int32), tslot=np.zeros((nb, T), dtype=np.int64),
        thash=np.zeros((nb, T), dtype=np.uint64), cnt=np.zeros((nb, 3), dtype=np.int64),
        hist=np.zeros((nb, chain_length + 1 if nb > 1 else 1, 2), dtype=np.int64))


@jit()
def reset_key_table(work, b):
    """Slab ``b``'s key table emptied and its tallies zeroed (``work`` holds the fields of a
    :class:`KeyTable`).

    Parameters
    ----------
    work : record
        A herded kind's workspace (with the fields of a :class:`KeyTable`).
    b : int
        The slab.
    """
    work.tslot[b, :] = 0
    work.cnt[b, :] = 0
    work.hist[b, 0, :] = 0


@jit()
def key_table_done(data, work, b, j):
    """Add the tallies of slab ``b``'s chain at its last observation ``j`` to ``data.tally``
    (a herded kind's ``chain_done``, :func:`make_driver`).

    Parameters
    ----------
    data : record
        The call's data record; its ``tally`` (int64, ``[keys, fall-backs]``) is updated.
    work : record
        The herded workspace (:func:`reset_key_table`).
    b : int
        The slab.
    j : int
        The chain's last observed sweep.
    """
    tally = data.tally
    hist = work.hist
    if hist.shape[1] > 1:
        tally[0] += hist[b, j, 0]
        tally[1] += hist[b, j, 1]
    else:  # simulated up to j exactly
        tally[0] += work.cnt[b, 0]
        tally[1] += work.cnt[b, 1]


@jit(inline="always")
def key_table_sweep_done(work, b):
    """Count a sweep of slab ``b`` and, when chains are speculated, record its tallies.

    Parameters
    ----------
    work : record
        The herded workspace (:func:`reset_key_table`).
    b : int
        The slab.
    """
    cnt = work.cnt[b]
    cnt[2] += 1
    hist = work.hist
    if hist.shape[1] > 1:
        hist[b, cnt[2], 0] = cnt[0]
        hist[b, cnt[2], 1] = cnt[1]


__all__ = ["Rules", "UniqueSet", "Slab", "Run", "Step", "Span", "KeyTable", "make_driver",
           "make_problem_runner", "ProblemScratch", "problem_scratch", "problem_states",
           "unique_set",
           "add_state",
           "N_COUNTERS", "DEFAULT_BUDGET", "EMPTY", "OTHER", "probe", "same_row", "key_hash",
           "table_find", "herd_lookup", "herd_pick",
           "alloc_key_table", "reset_key_table", "key_table_done", "key_table_sweep_done"]

# Slots of the run counter array ``ctr`` (returned by run_chains).
NU, NOBS, NCHAINS, STALE_RUN, STALE_CUM, STALE_FIRED, DISCARDED = 0, 1, 2, 3, 4, 5, 6
N_COUNTERS = 7
# Slots of the per-chain counter array ``cctr``.
_STALL_RUN, _STALL_CUM, _NEW_IN_CHAIN, _LOCAL_UNIQUE = 0, 1, 2, 3

#: Termination rules: reading codes (:data:`rankedassign.validation.STALL_READINGS`,
#: ``STALE_READINGS``; 0 = off) and thresholds.
Rules = namedtuple("Rules", ["stall_mode", "tau_stall", "stale_mode", "tau_stale"])
#: The unique set ``U``: states in discovery order, their hashes, visit counts, the last chain
#: that visited each (for the chain-local stall reading), and the hash table of
#: ``[hash, index + 1]`` rows (0 = empty slot, linear probing).
UniqueSet = namedtuple("UniqueSet", ["states", "hashes", "counts", "last_chain", "table"])
#: Per-chain simulation slabs: speculated trajectories and their hashes, the live state, its
#: hash and the stream state (one cache line per chain) of each of ``nb`` chains.
Slab = namedtuple("Slab", ["traj", "hashes", "states", "h", "rs"])

#: A run of the driver between two slices: the unique set, the slab, the problem's
#: workspace, the chain lengths seen (speculation), the run and chain counters and the
#: positions ``pos`` (slots ``_C0`` ...: batch, chain, observation, sweeps simulated, ramp).
Run = namedtuple("Run", ["U", "slab", "work", "used_hist", "ctr", "cctr", "pos"])


class Step(NamedTuple):
    """One speculation step (:func:`_speculate`): which sweeps of which chains to simulate.

    Attributes
    ----------
    h0 : uint64
        Zobrist hash of the start state ``x0``.
    base : uint64
        Base key of the run: chain ``c`` draws from ``chain_state(base, c)``.
    c_first : int
        First chain of the batch (slab row 0).
    n_batch : int
        Chains of the batch (slab rows ``0 .. n_batch - 1``).
    j_from, j_to : int
        The step simulates sweeps ``j_from + 1 .. j_to`` of every chain of the batch
        (``j_from = 0``: the chains start from ``x0``).
    """

    h0: np.uint64
    base: np.uint64
    c_first: int
    n_batch: int
    j_from: int
    j_to: int


class Span(NamedTuple):
    """The observations one call of :func:`_advance` makes of one chain.

    Attributes
    ----------
    b : int
        The chain's slab row.
    c : int
        The chain's index in the run.
    j0, j1 : int
        Observations ``j0 + 1 .. j1`` are made.
    done : int
        Sweeps of the chain simulated so far (ahead by the speculation, or here); those up to
        ``done`` are read from the slab instead of simulated.
    """

    b: int
    c: int
    j0: int
    j1: int
    done: int

# Slots of ``Run.pos``: first chain of the open batch, its size (0: no batch open), its prefix
# length and the sweeps of the prefix speculated so far, the chain being replayed (index in
# the batch), whether that chain has begun, its last observation and its sweeps simulated,
# and the size of the next batch (the ramp).
_C0, _NB, _S, _SPEC, _B, _IN_CHAIN, _J, _DONE, _RAMP = range(9)
N_POS = 9

#: Status of a slice (:func:`_run_slice`): the run is over, the budget is spent, ``U`` is full.
DONE, PAUSED, NEED_ROOM = 0, 1, 2

#: Sweeps per slice when the caller gives no budget (the samplers size it by the sweep's cost).
DEFAULT_BUDGET = 1 << 16

# Initial capacity of the unique set (doubles when full).
_CAP = 1024


# ------------------------------------------------------------------------ problem interface
# Placeholders: make_driver binds these names to a problem type's compiled functions.
def alloc_work(data, nb):  # pragma: no cover - replaced in every instantiation
    """Per-chain workspace of ``nb`` chains (a tuple of arrays with leading dimension ``nb``)."""
    raise NotImplementedError


def reset_work(data, work, b, x0):  # pragma: no cover - replaced in every instantiation
    """Put slab ``b`` of the workspace in the start state ``x0``."""
    raise NotImplementedError


def sweep(data, work, b, zkeys, state, h, rs):  # pragma: no cover - replaced
    """One sweep in place on ``state``; return its new Zobrist hash."""
    raise NotImplementedError


def chain_done(data, work, b, j):  # pragma: no cover - replaced in every instantiation
    """Chain of slab ``b`` ended at its observation ``j`` (the replay's order)."""
    raise NotImplementedError


def no_chain_done(data, work, b, j):
    """The default :func:`make_driver` ``chain_done``: a kind that keeps no per-chain tally
    (compiled for each kind, as every function that takes the kind's records is).

    Parameters
    ----------
    data, work, b, j
        As in :func:`key_table_done`; unused.
    """
    return None


def _instantiated(*args):  # pragma: no cover - replaced in every instantiation
    """Stands for a compiled phase that :func:`make_driver` binds in each instantiation."""
    raise NotImplementedError


def no_speculation(data, work, zkeys, slab, x0, step):
    """The speculation of a run without speculation (``batch == 0``): never called.

    :func:`make_driver` compiles the slice of a sequential run with this in place of
    :func:`_speculate`, so that a process that runs only sequentially (one worker, the filters'
    and studies' case) compiles neither the parallel loop nor the kind's sweep a second time
    (:func:`_speculate_chain` holds a copy of it). Compiled for each kind, as every function
    that takes the kind's records is.

    Parameters
    ----------
    data, work, zkeys, slab, x0, step
        As in :func:`_speculate`; unused.
    """
    return None


# The phases the templates call by name; make_driver binds each to the kind's compiled copy.
_speculate_impl = _advance_impl = _new_run_impl = _run_slice_impl = _instantiated
_speculate_chain_impl = _pack_impl = _unpack_impl = _instantiated


Work = tuple  # placeholder: make_driver binds the kind's workspace record class


def as_work(fields):  # pragma: no cover - replaced in every instantiation
    """The kind's workspace record of the plain tuple ``fields`` (:func:`_unpack`)."""
    raise NotImplementedError


# ------------------------------------------------------------------------ unique set
@jit()
def hash_of(zkeys, x):
    """Zobrist hash of the state ``x``: XOR of ``zkeys[l, x[l]]`` over positions ``l``.

    Parameters
    ----------
    zkeys : ndarray of uint64, shape (L, K)
        Zobrist keys (:func:`zobrist_keys`).
    x : ndarray of int32, shape (L,)
        The state, entries in ``0..K-1``.

    Returns
    -------
    np.uint64

    Examples
    --------
    >>> import numpy as np
    >>> z = np.array([[1, 2], [4, 8]], dtype=np.uint64)
    >>> int(hash_of(z, np.array([1, 0], dtype=np.int32)))
    6
    """
    h = np.uint64(0)
    for i in range(x.shape[0]):
        h = h ^ zkeys[i, x[i]]
    return h


@jit()
def _new_unique_set(L, cap):
    """An empty :data:`UniqueSet` of capacity ``cap``.

    Parameters
    ----------
    L : int
        Length of a state.
    cap : int
        States it holds before :func:`_grow`; a power of two (its table has ``2 cap`` rows).

    Returns
    -------
    UniqueSet
        ``states`` (cap, L) int32 and ``hashes`` (cap,) uint64 uninitialised, ``counts``
        (cap,) int64 zero, ``last_chain`` (cap,) int64 ``-1``, ``table`` (2 cap, 2) uint64
        zero (every slot empty).
    """
    return UniqueSet(
        np.empty((cap, L), dtype=np.int32),
        np.empty(cap, dtype=np.uint64),
        np.zeros(cap, dtype=np.int64),
        np.full(cap, -1, dtype=np.int64),
        np.zeros((2 * cap, 2), dtype=np.uint64),
    )


@jit(inline="always")
def _find(U, state, h):
    """Index of ``state`` in ``U``, or ``-1 - slot`` of the empty slot to fill.

    The one look-up of the unique set (:func:`probe` from the hash, a hit confirmed on the
    full state): :func:`_advance`, :func:`_grow`, :func:`_new_run` and every caller outside
    the driver (:func:`add_state`, :func:`make_problem_runner`) look states up through it. It is
    written into each caller (``inline="always"``): a call passing the arrays of the unique
    set costs as much as the look-up itself.

    Parameters
    ----------
    U : UniqueSet
        The set; its table has at least one empty slot.
    state : ndarray of int32, shape (L,)
        The state.
    h : np.uint64
        Its hash.

    Returns
    -------
    int
        The state's index in discovery order, or ``-1 - slot``.
    """
    table = U.table
    s, u = probe(table.shape[0], h, _look_state, (table, U.states, state, h))
    return u if u >= 0 else -1 - s


@jit(inline="always")
def _look_state(tab, s):
    """:func:`probe`'s ``look`` of the unique set (its table, its states, the state, its hash)."""
    table, states, state, h = tab
    v = table[s, 1]
    if v == 0:
        return EMPTY
    u = np.int64(v) - 1
    if table[s, 0] == h and same_row(states, u, state):
        return u
    return OTHER


@jit()
def _insert(U, slot, state, h, n_unique, count, chain):
    """Store ``state`` as unique number ``n_unique`` at the empty hash-table ``slot``.

    Parameters
    ----------
    U : UniqueSet
        The set, with room for ``n_unique + 1`` states.
    slot : int
        The empty table slot (:func:`_find`'s ``-1 - slot``).
    state : ndarray of int32, shape (L,)
        The state (copied).
    h : np.uint64
        Its hash.
    n_unique : int
        States in ``U`` so far (the new state's index).
    count : int
        Its visit count.
    chain : int
        The chain that found it.
    """
    U.table[slot, 0] = h
    U.table[slot, 1] = np.uint64(n_unique + 1)
    for i in range(state.shape[0]):  # a loop, not a slice: see _grow
        U.states[n_unique, i] = state[i]
    U.hashes[n_unique] = h
    U.counts[n_unique] = count
    U.last_chain[n_unique] = chain


@jit()
def _grow(U, n_unique):
    """Double the arrays of ``U`` when full; rehash at load factor 0.5. Returns the new ``U``.

    Parameters
    ----------
    U : UniqueSet
        The set.
    n_unique : int
        States in it.

    Returns
    -------
    UniqueSet
        With room for at least one more state: the state arrays doubled if full (the new
        entries as :func:`_new_unique_set` leaves them), the table doubled until it has
        more than ``2 n_unique`` rows and rebuilt; arrays that needed neither are shared.
    """
    states, hashes, counts, last_chain, table = U
    cap = states.shape[0]
    if n_unique >= cap:
        new_cap = 2 * cap
        s2 = np.empty((new_cap, states.shape[1]), dtype=states.dtype)
        h2 = np.empty(new_cap, dtype=hashes.dtype)
        c2 = np.zeros(new_cap, dtype=counts.dtype)
        l2 = np.full(new_cap, -1, dtype=last_chain.dtype)
        # Copied in loops, not by slice assignment: a slice assignment compiles numba's
        # shape-mismatch error path (its message formatting, about 3 s of the first call's
        # compile), and these shapes match by construction.
        for u in range(cap):
            for i in range(states.shape[1]):
                s2[u, i] = states[u, i]
            h2[u] = hashes[u]
            c2[u] = counts[u]
            l2[u] = last_chain[u]
        states, hashes, counts, last_chain = s2, h2, c2, l2
    if 2 * (n_unique + 1) > table.shape[0]:
        size = table.shape[0]
        while 2 * (n_unique + 1) > size:
            size *= 2
        table = np.zeros((size, 2), dtype=np.uint64)
        fresh = UniqueSet(states, hashes, counts, last_chain, table)
        for u in range(n_unique):  # the states are distinct: each look-up ends on an empty slot
            s = -1 - _find(fresh, states[u], hashes[u])
            table[s, 0] = hashes[u]
            table[s, 1] = np.uint64(u + 1)
    return UniqueSet(states, hashes, counts, last_chain, table)


def _pack(run):
    """A :class:`Run` as nested plain tuples, the form it crosses into Python in.

    numba boxes a named tuple by calling its class, Python code, where a signal handler's
    exception crashes numba's return path (a segmentation fault, not an error); plain tuples
    are built in C and only ever raise. The kind's workspace record becomes the plain tuple of
    its fields (``work[:]``); :func:`_unpack` rebuilds it.

    Parameters
    ----------
    run : Run
        The run.

    Returns
    -------
    tuple
        ``(U fields, slab fields, work fields, used_hist, ctr, cctr, pos)``; arrays shared.
    """
    U, S = run.U, run.slab
    return ((U.states, U.hashes, U.counts, U.last_chain, U.table),
            (S.traj, S.hashes, S.states, S.h, S.rs), run.work[:], run.used_hist, run.ctr,
            run.cctr, run.pos)


def _unpack(run):
    """The :class:`Run` of a packed run (:func:`_pack`); ``as_work`` rebuilds the kind's
    workspace record from its fields.

    Parameters
    ----------
    run : tuple
        A packed run.

    Returns
    -------
    Run
        The same arrays, named.
    """
    return Run(UniqueSet(*run[0]), Slab(*run[1]), as_work(run[2]), run[3], run[4], run[5],
               run[6])


def _grow_run(run):
    """Packed ``run`` with its unique set grown (:func:`_grow`); every other field shared.

    Parameters
    ----------
    run : tuple
        A packed run (:func:`_pack`) whose slice returned ``NEED_ROOM``.

    Returns
    -------
    tuple
        The packed run.
    """
    r = _unpack_impl(run)
    return _pack_impl(Run(_grow(r.U, r.ctr[NU]), r.slab, r.work, r.used_hist, r.ctr, r.cctr,
                          r.pos))


@jit()
def _room(U, n_unique):
    """Insertions ``U`` takes before :func:`_grow` must run (load factor 0.5).

    Parameters
    ----------
    U : UniqueSet
        The set.
    n_unique : int
        States in it.

    Returns
    -------
    int
    """
    return min(U.states.shape[0], U.table.shape[0] // 2) - n_unique


@jit()
def unique_set(L, n):
    """An empty unique set of length-``L`` states with room for ``n`` without growing.

    Its capacity is the smallest power of two ``>= n`` (at least 2), so its hash table keeps
    a load factor of at most one half (:func:`_room` is at least ``n``).

    Parameters
    ----------
    L : int
        Length of a state (``int32`` entries).
    n : int
        States it must hold.

    Returns
    -------
    UniqueSet
        Empty: fill it with :func:`add_state` (or :func:`_find` and :func:`_insert`).

    Examples
    --------
    >>> U = unique_set(3, 5)
    >>> U.states.shape, int(_room(U, 0))
    ((8, 3), 8)
    """
    return _new_unique_set(L, _capacity(n))


@jit(inline="always")
def add_state(U, x, h, n_u):
    """Index of the state ``x`` (hash ``h``) in ``U``, stored as number ``n_u`` if new.

    The caller keeps the number of states ``n_u`` and guarantees room for one more
    (:func:`unique_set`); a new state is stored with count 0 and no chain.

    Parameters
    ----------
    U : UniqueSet
        The set.
    x : ndarray of int32, shape (L,)
        The state.
    h : uint64
        Its hash (any 64-bit hash that equal states share).
    n_u : int
        States in ``U`` so far.

    Returns
    -------
    (u, new) : (int, bool)
        The state's index in discovery order, and whether it was added.

    Examples
    --------
    >>> import numpy as np
    >>> U = unique_set(2, 4)
    >>> x, y = np.array([1, 2], np.int32), np.array([2, 1], np.int32)
    >>> add_state(U, x, np.uint64(7), 0), add_state(U, y, np.uint64(7), 1)
    ((0, True), (1, True))
    >>> add_state(U, y.copy(), np.uint64(7), 2)
    (1, False)
    """
    r = _find(U, x, h)
    if r >= 0:
        return r, False
    slot = -1 - r  # :func:`_insert`, its state copied by a loop (no reference counting here)
    U.table[slot, 0] = h
    U.table[slot, 1] = np.uint64(n_u + 1)
    for i in range(x.shape[0]):
        U.states[n_u, i] = x[i]
    U.hashes[n_u] = h
    U.counts[n_u] = 0
    U.last_chain[n_u] = -1
    return n_u, True


# ------------------------------------------------------------------------ stall and stale
@jit()
def _begin_chain(c, last_chain, cctr):
    """Reset the per-chain counters; the start state (unique 0) is the chain's ``x[0]``.

    Parameters
    ----------
    c : int
        The chain's index in the run.
    last_chain : ndarray of int64
        ``U.last_chain``; entry 0 (the start state) set to ``c``.
    cctr : ndarray of int64
        The per-chain counters, zeroed but for the chain's local unique count, 1.
    """
    cctr[:] = 0
    cctr[_LOCAL_UNIQUE] = 1
    last_chain[0] = c


@jit()
def _stalled(cctr, j, stall_mode, tau_stall):
    """The stall rule after observation ``j`` of a chain (spec §3.2).

    * global-consecutive (S3): observations since the chain's last find new to ``U``;
    * global-cumulative (S2): the chain's observations that were already in ``U``;
    * chain-local (S1): ``(j + 1) - NumUnique(x[0..j])``, repeats among the chain's own
      states including its start state.

    Parameters
    ----------
    cctr : ndarray of int64
        The chain's counters.
    j : int
        The observation just made (1-based sweep number).
    stall_mode : int
        The stall reading's code (``rankedassign.validation``; 0 off).
    tau_stall : int
        The threshold.

    Returns
    -------
    bool
        True when the chain stops.
    """
    if stall_mode == STALL_GLOBAL_CONSECUTIVE:
        return cctr[_STALL_RUN] >= tau_stall
    if stall_mode == STALL_GLOBAL_CUMULATIVE:
        return cctr[_STALL_CUM] >= tau_stall
    if stall_mode == STALL_CHAIN_LOCAL:
        return (j + 1) - cctr[_LOCAL_UNIQUE] >= tau_stall
    return False


@jit()
def _end_chain(ctr, cctr, stale_mode, tau_stale):
    """Close a chain; return True if the stale rule stops the run (spec §3.2).

    * consecutive (T3): most recent completed chains in a row that added nothing to ``U``;
    * cumulative (T2): completed chains, ever, that added nothing;
    * literal-set (T1): ``|x| - n_u`` with ``x`` the set of samples, i.e. ``|U| - |U|``;
    * literal-multiset (T1): ``|x| - n_u`` with ``x`` the multiset of every chain's start state
      and every observation, i.e. ``(chains + observations) - |U|``.

    Parameters
    ----------
    ctr : ndarray of int64, shape (N_COUNTERS,)
        The run's counters (chains, stale runs and the stale flag updated).
    cctr : ndarray of int64
        The closing chain's counters.
    stale_mode : int
        The stale reading's code (``rankedassign.validation``; 0 off).
    tau_stale : int
        The threshold.

    Returns
    -------
    bool
        True when the run stops.
    """
    ctr[NCHAINS] += 1
    if cctr[_NEW_IN_CHAIN] > 0:
        ctr[STALE_RUN] = 0
    else:
        ctr[STALE_RUN] += 1
        ctr[STALE_CUM] += 1
    fired = False
    if stale_mode == STALE_CONSECUTIVE:
        fired = ctr[STALE_RUN] >= tau_stale
    elif stale_mode == STALE_CUMULATIVE:
        fired = ctr[STALE_CUM] >= tau_stale
    elif stale_mode == STALE_LITERAL_SET:
        size_of_set = ctr[NU]
        fired = size_of_set - ctr[NU] >= tau_stale
    elif stale_mode == STALE_LITERAL_MULTISET:
        size_of_multiset = ctr[NCHAINS] + ctr[NOBS]
        fired = size_of_multiset - ctr[NU] >= tau_stale
    if fired:
        ctr[STALE_FIRED] = 1
    return fired


@jit()
def _prefix_length(used_hist, chain_length, workers):
    """Sweeps to speculate per chain: the ``1 - 1/workers`` quantile of the used lengths.

    Speculating ``s`` sweeps costs ``s / workers`` per chain in parallel; each sweep a chain
    needs beyond ``s`` costs 1 in the (sequential) replay. The expected time is minimal where
    ``P(length > s) = 1 / workers``. Before any chain has finished, speculate everything.

    Parameters
    ----------
    used_hist : ndarray of int64, shape (chain_length + 1,)
        Number of finished chains by the sweeps they used.
    chain_length : int
        Sweeps of a full chain.
    workers : int
        Threads of the speculation (``>= 1``).

    Returns
    -------
    int
        Sweeps to speculate, in ``1..chain_length``.
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


# ------------------------------------------------------------------------ templates
def _speculate(data, work, zkeys, slab, x0, step):
    """Sweeps ``step.j_from + 1 .. step.j_to`` of the chains of a batch (a :class:`Step`).

    Chain ``step.c_first + b`` writes its trajectory to ``slab.traj[b, j_from:j_to]`` and
    the hash of each state to ``slab.hashes[b, j_from:j_to]``, and leaves its simulation
    state (``slab.states[b]``, ``slab.h[b]``, ``slab.rs[b, 0]``, workspace slab ``b``) ready
    for the next call (``j_from = 0`` starts the chains from ``x0``) or for the replay to
    continue it; a prefix simulated in several calls is therefore the same trajectory as one
    simulated in one call. Chains are independent (each has its own stream), so the loop over
    chains runs in parallel (``prange``); each iteration writes only its own slab rows (``rs``
    rows are padded to a cache line so that neighbouring streams do not share one).

    Each iteration is one call of :func:`_speculate_chain`, compiled apart: written into the
    ``prange`` loop, numba's dead-code elimination of the loop's body drops writes to an array
    read from an attribute of a named tuple (``work.occ[b, v] += 1``), because the body's
    copy of the record is not known to alias the loop's arguments (numba issue #7135;
    ``tests/test_engine.py`` keeps a reproducer). The call costs once per chain and step.
    The chain index is passed as ``int64``: numba's parallel lowering types a ``prange`` index
    as ``uint64`` where the loop's typing saw ``int64``, and the call would otherwise compile
    the chain's function (with the kind's whole sweep in it) a second time.

    Parameters
    ----------
    data : record
        The kind's data record of the call.
    work : record
        The kind's workspace, one slab per chain of the batch.
    zkeys : ndarray of uint64, shape (L, K)
        Zobrist keys.
    slab : Slab
        The chains' simulation slabs.
    x0 : ndarray of int32, shape (L,)
        The start state.
    step : Step
        What to simulate.
    """
    n_batch = step.n_batch
    for b in prange(n_batch):
        _speculate_chain_impl(data, work, zkeys, slab, x0, step, np.int64(b))


def _speculate_chain(data, work, zkeys, slab, x0, step, b):
    """The sweeps of ``step`` (a :class:`Step`) of the chain of slab row ``b``.

    Parameters
    ----------
    data, work, zkeys, slab, x0, step
        As in :func:`_speculate`.
    b : int64
        The slab row (chain ``step.c_first + b``).
    """
    state = slab.states[b]
    rs = slab.rs[b, 0:1]
    if step.j_from == 0:
        for i in range(x0.shape[0]):  # (a slice assignment would need reference counting)
            state[i] = x0[i]
        reset_work(data, work, b, x0)
        rs[0] = chain_state(step.base, step.c_first + b)
        h = step.h0
    else:
        h = slab.h[b]
    traj = slab.traj
    hashes = slab.hashes
    L = state.shape[0]
    for j in range(step.j_from, step.j_to):
        h = sweep(data, work, b, zkeys, state, h, rs)
        for i in range(L):
            traj[b, j, i] = state[i]
        hashes[b, j] = h
    slab.h[b] = h


def _advance(data, work, zkeys, slab, U, ctr, cctr, rules, span):
    """Observations ``j0 + 1 .. j1`` of chain ``c``, whose simulation state is slab row ``b``
    (the fields of the :class:`Span` ``span``).

    Sweeps ``<= done`` were simulated ahead by the speculation and are read from the slab; later
    ones are simulated here from the saved state (``done = 0``: all of them, the sequential
    run). Each observation is looked up in ``U`` (inserted if new, spec §3.3) and counted, then
    the stall rule is applied (:func:`_stalled`).

    The caller guarantees room for ``j1 - j0`` new unique states (:func:`_room`), so this hot
    loop never reallocates; the look-up (:func:`_find`) is written into it (``inline``).

    :func:`make_driver` compiles it, and :func:`_speculate_chain`, without reference counting
    (:func:`rankedassign.numba_options.jit`, ``nrt=False``): the sweep written into them
    reads its arrays from the kind's records in each of its phases, and every such read
    would otherwise cost an atomic reference-count update per array, row and sweep (the
    multi-sensor sweep split into phases ran twice as slowly with them). Neither allocates,
    and the run keeps every array they touch alive.

    Parameters
    ----------
    data, work, zkeys, slab
        As in :func:`_speculate`.
    U : UniqueSet
        The unique set, with room for ``j1 - j0`` more states.
    ctr : ndarray of int64, shape (N_COUNTERS,)
        The run's counters.
    cctr : ndarray of int64
        The chain's counters.
    rules : Rules
        The stall and stale readings and thresholds.
    span : Span
        The chain's slab row, index, observations and sweeps simulated.

    Returns
    -------
    (j, stalled, done) : (int, bool, int)
        The last observation made, whether the stall rule fired there, sweeps simulated.
    """
    b, c, j0, j1, done = span.b, span.c, span.j0, span.j1, span.done
    L = U.states.shape[1]
    table = U.table
    state = slab.states[b]
    rs = slab.rs[b, 0:1]
    h = slab.h[b]
    for j in range(j0 + 1, j1 + 1):
        if j <= done:
            x = slab.traj[b, j - 1]
            hx = slab.hashes[b, j - 1]
        else:
            h = sweep(data, work, b, zkeys, state, h, rs)
            x = state
            hx = h
            done = j
        u = _find(U, x, hx)
        if u < 0:  # new to U: U.add(x) at the empty slot the look-up ended on; the stall
            slot = -1 - u  # run restarts
            u = ctr[NU]
            table[slot, 0] = hx
            table[slot, 1] = np.uint64(u + 1)
            for i in range(L):
                U.states[u, i] = x[i]
            U.hashes[u] = hx
            U.counts[u] = 1
            U.last_chain[u] = c
            ctr[NU] += 1
            cctr[_NEW_IN_CHAIN] += 1
            cctr[_STALL_RUN] = 0
            cctr[_LOCAL_UNIQUE] += 1
        else:
            U.counts[u] += 1
            cctr[_STALL_RUN] += 1
            cctr[_STALL_CUM] += 1
            if U.last_chain[u] != c:  # first visit of this chain to a state found before
                U.last_chain[u] = c
                cctr[_LOCAL_UNIQUE] += 1
        ctr[NOBS] += 1
        if _stalled(cctr, j, rules.stall_mode, rules.tau_stall):
            slab.h[b] = h
            return j, True, done
    slab.h[b] = h
    return j1, False, done


def _new_run(data, zkeys, x0, n_chains, chain_length, batch, workers):
    """A :class:`Run` before its first observation: ``U = {x0}``, every position at zero.

    ``batch`` and ``workers`` as in :func:`_run_slice`; they size the slab (``nb`` chains and,
    when speculating, ``chain_length`` sweeps of each) and the first speculation batch.

    Parameters
    ----------
    data, zkeys, x0, n_chains, chain_length, batch, workers
        As in :func:`_run_slice`.

    Returns
    -------
    tuple
        The packed run (:func:`_pack`).
    """
    L = x0.shape[0]
    h0 = hash_of(zkeys, x0)
    U = _new_unique_set(L, np.int64(_CAP))  # (int64: a literal would compile a second signature)
    ctr = np.zeros(N_COUNTERS, dtype=np.int64)
    cctr = np.zeros(4, dtype=np.int64)
    # U <- {x0}: x0 is stored (unique 0) but is not an observation (count 0 so far)
    _insert(U, -1 - _find(U, x0, h0), x0, h0, 0, 0, -1)
    ctr[NU] = 1
    speculative = batch > 0
    nb = min(batch, n_chains) if speculative else 1
    n_spec = chain_length if speculative else 0  # bounded by the caller's slab limit
    slab = Slab(
        np.empty((nb, n_spec, L), dtype=np.int32),
        np.empty((nb, n_spec), dtype=np.uint64),
        np.empty((nb, L), dtype=np.int32),
        np.empty(nb, dtype=np.uint64),
        np.empty((nb, 8), dtype=np.uint64),  # one stream per cache line
    )
    work = alloc_work(data, nb)
    used_hist = np.zeros(n_spec + 1, dtype=np.int64)  # chain lengths seen (speculation only)
    pos = np.zeros(N_POS, dtype=np.int64)
    # Batches start small (the first one learns the chain lengths for the prefix) and double
    # up to ``batch``: a run that stops early by stale then discards little.
    pos[_RAMP] = max(64, 16 * workers)
    return _pack_impl(Run(U, slab, work, used_hist, ctr, cctr, pos))


def _run_slice(data, zkeys, x0, base, n_chains, chain_length, rules, batch, workers, budget,
               run):
    """Continue the short-chain sampler (spec §3.3) in ``run`` for about ``budget`` sweeps.

    Parameters
    ----------
    data : named tuple
        The problem type's data record (passed to its ``alloc_work``, ``reset_work``,
        ``sweep``).
    zkeys : ndarray, shape (L, K), uint64
        Zobrist keys.
    x0 : ndarray, shape (L,), int32
        Feasible start state.
    base : uint64
        Base key of the run (chain ``c`` uses ``chain_state(base, c)``).
    n_chains, chain_length : int
        ``N_S`` and ``N_C``.
    rules : Rules
        Stall and stale readings and thresholds.
    batch : int
        0: simulate chain after chain, stopping each as soon as the stall rule fires.
        ``> 0``: take up to ``batch`` chains at a time (``max(64, 16 workers)`` in the first
        batch, doubling), simulate a prefix of each in parallel (:func:`_speculate`, prefix
        length from :func:`_prefix_length`), then replay them in chain order applying stall
        and stale exactly as the sequential run does, continuing a chain in the replay if it
        outlives its prefix (spec §3.3, "Parallelism"). A chain's trajectory depends only on
        its stream, so the result does not depend on ``batch``, ``workers`` or the prefix
        lengths; only the discarded sweeps do.
    workers : int
        Threads of the speculation (sets the prefix quantile).
    budget : int
        Sweeps this call may simulate or replay (``>= 1``; a speculation step of ``n`` chains
        counts ``n`` per sweep). The call stops at the first observation, or speculation step,
        that would exceed it, with every position saved in ``run``.
    run : Run
        The run's state (:func:`_new_run`), updated in place.

    Returns
    -------
    (status, left) : (int, int)
        :data:`DONE` (the run is over: budget exhausted or stale), :data:`PAUSED` (budget
        spent; call again) or :data:`NEED_ROOM` (``U`` is full: grow it with
        :func:`_grow_run`, then call again); ``left`` is the budget not spent.

    Notes
    -----
    The run advances through the same operations, in the same order, whatever the budgets
    of its slices: a slice ends only between two observations of a chain, or between two
    speculation steps whose sweep ranges then continue each other (:func:`_speculate`), and
    every position (batch, chain, observation, sweeps simulated, batch ramp) lives in
    ``run.pos``. So a run in slices gives the same bits as a run in one call.
    """
    U, slab, work, used_hist, ctr, cctr, pos = _unpack_impl(run)
    speculative = batch > 0
    nb = slab.states.shape[0]
    h0 = hash_of(zkeys, x0)
    left = budget
    while pos[_C0] < n_chains:
        c0 = pos[_C0]
        if pos[_NB] == 0:  # open the next batch
            n_b = min(nb, n_chains - c0)
            s = 0
            if speculative:
                n_b = min(n_b, pos[_RAMP])
                pos[_RAMP] = min(2 * pos[_RAMP], nb)
                s = _prefix_length(used_hist, chain_length, workers)
            pos[_NB] = n_b
            pos[_S] = s
            pos[_SPEC] = 0
            pos[_B] = 0
            pos[_IN_CHAIN] = 0
        n_b = pos[_NB]
        s = pos[_S]
        while pos[_SPEC] < s:  # the batch's prefixes, a few sweeps of every chain per step
            if left <= 0:
                return PAUSED, left
            k = min(s - pos[_SPEC], max(1, left // n_b))
            _speculate_impl(data, work, zkeys, slab, x0,
                            Step(h0=h0, base=base, c_first=c0, n_batch=n_b, j_from=pos[_SPEC],
                                 j_to=pos[_SPEC] + k))
            pos[_SPEC] += k
            left -= k * n_b
        while pos[_B] < n_b:  # replay in chain order
            b = pos[_B]
            c = c0 + b
            if pos[_IN_CHAIN] == 0:
                if not speculative:
                    for i in range(x0.shape[0]):  # a loop, not a slice: see _grow
                        slab.states[b, i] = x0[i]
                    reset_work(data, work, b, x0)
                    slab.h[b] = h0
                    slab.rs[b, 0] = chain_state(base, c)
                _begin_chain(c, U.last_chain, cctr)
                pos[_IN_CHAIN] = 1
                pos[_J] = 0
                pos[_DONE] = s
            j = pos[_J]
            done = pos[_DONE]
            stalled = False
            while j < chain_length and not stalled:
                room = _room(U, ctr[NU])
                if room <= 0 or left <= 0:
                    pos[_J] = j
                    pos[_DONE] = done
                    return (NEED_ROOM if room <= 0 else PAUSED), left
                j1 = min(chain_length, j + min(room, left))
                j_before = j
                j, stalled, done = _advance_impl(data, work, zkeys, slab, U, ctr, cctr, rules,
                                                 Span(b=b, c=c, j0=j, j1=j1, done=done))
                left -= j - j_before
            if speculative:
                used_hist[j] += 1
            chain_done(data, work, b, j)
            ctr[DISCARDED] += done - j
            pos[_IN_CHAIN] = 0
            pos[_B] = b + 1
            if _end_chain(ctr, cctr, rules.stale_mode, rules.tau_stale):
                ctr[DISCARDED] += (n_b - b - 1) * s
                pos[_C0] = n_chains
                return DONE, left
        pos[_C0] = c0 + n_b
        pos[_NB] = 0
    return DONE, left


def _as_record(fields):
    """The workspace record ``Work`` of its fields (template of :func:`make_driver`'s
    ``as_work``).

    Parameters
    ----------
    fields : tuple
        The record's fields, in order.

    Returns
    -------
    Work
    """
    return Work(*fields)


@jit()
def _as_tuple(fields):
    """A workspace that is a plain tuple, as it is (:func:`make_driver`'s ``as_work``).

    Parameters
    ----------
    fields : tuple
        The workspace.

    Returns
    -------
    tuple
        ``fields``.
    """
    return fields


def make_driver(name, alloc_work, reset_work, sweep, *, work=None, chain_done=None,
                cache=None):
    """Compile the chain driver for one problem type.

    Parameters
    ----------
    name : str
        Unique name of the problem type (names the compiled functions and their cache files).
    alloc_work, reset_work, sweep : compiled functions
        The problem type's workspace allocation, reset and sweep (see the module docstring).
    work : type, optional
        The named tuple class of the workspace ``alloc_work`` returns; None (default) for a
        plain tuple. A run crosses into Python with its workspace as a plain tuple of the
        same fields (:func:`_pack`), rebuilt as this record in the next slice.
    chain_done : compiled function, optional
        ``chain_done(data, work, b, j)``, called once per chain in the replay's (chain) order
        when the chain of slab ``b`` ends at its observation ``j``: where a kind keeps a tally
        of its chains (the herded draw counts its key-table fall-backs) it reads the slab's
        state at ``j``, so sweeps speculated past ``j`` are not counted. Default (None):
        nothing.
    cache : bool, optional
        As in :func:`rankedassign.numba_options.jit`; off for functions defined interactively.

    Returns
    -------
    run_chains : function
        ``run_chains(data, zkeys, x0, base, n_chains, chain_length, rules, batch, workers,
        budget=DEFAULT_BUDGET) -> (states, counts, ctr)``, the short-chain sampler (spec
        §3.3; the original sampler is one chain without rules), arguments as in
        :func:`_run_slice`, run in compiled slices of at most about ``budget`` sweeps each
        (see the module docstring, "Slices"). It returns

        * ``states`` : ndarray, shape (n_unique, L), int32 — unique states in discovery
          order, ``x0`` first;
        * ``counts`` : ndarray, shape (n_unique,), int64 — observations of each;
        * ``ctr`` : ndarray, shape (7,), int64 — ``[n_unique, n_observations,
          n_chains_run, stale_run, stale_cumulative, stale_fired,
          n_speculative_discarded]``;

        the same bits for every ``budget``. Its attribute ``kernels`` maps ``"new_run"``,
        ``"run_slice"``, ``"speculate"``, ``"speculate_chain"`` and ``"advance"`` to the
        compiled functions behind it (to inspect their signatures), and
        ``"run_slice_sequential"`` to the slice of a run with ``batch == 0``, which never
        speculates: a process that runs only sequentially compiles neither
        :func:`_speculate` nor :func:`_speculate_chain`;
        ``"grow_run"`` to :func:`_grow_run`, compiled by the first run that fills its unique
        set.

    Examples
    --------
    A toy "problem" whose state is one bit flipped with probability one half per sweep:

    >>> import numpy as np
    >>> from rankedassign.numba_options import jit
    >>> from rankedassign.engine._kernels import next_uniform
    >>> @jit(cache=False)
    ... def alloc(data, nb):
    ...     return (np.zeros((nb, 1)),)
    >>> @jit(cache=False)
    ... def reset(data, work, b, x0):
    ...     pass
    >>> @jit(cache=False)
    ... def flip(data, work, b, zkeys, state, h, rs):
    ...     if next_uniform(rs) < data[0]:
    ...         h ^= zkeys[0, state[0]] ^ zkeys[0, 1 - state[0]]
    ...         state[0] = 1 - state[0]
    ...     return h
    >>> run = make_driver("coin", alloc, reset, flip, cache=False)
    >>> zkeys = np.array([[1, 2]], dtype=np.uint64)
    >>> args = ((0.5,), zkeys, np.zeros(1, np.int32), np.uint64(7), 1, 100, Rules(0, 0, 0, 0),
    ...         0, 1)
    >>> states, counts, ctr = run(*args)
    >>> sorted(states[:, 0].tolist()), int(counts.sum())
    ([0, 1], 100)
    >>> sliced = run(*args, budget=3)          # 34 slices of at most 3 sweeps: same bits
    >>> all(bool((a == b).all()) for a, b in zip(sliced, (states, counts, ctr)))
    True
    """
    # Every function that takes the kind's records is compiled for the kind, with its cache
    # setting: a cached function of the engine compiled for the records of a kind defined
    # elsewhere would name their module in the engine's cache index, which every later
    # process must then import.
    as_work = (_as_tuple if work is None else
               instantiate(_as_record, f"as_work_{name}", {"Work": work}, cache=cache))
    if chain_done is None:
        chain_done = instantiate(no_chain_done, f"no_chain_done_{name}", {}, cache=cache)
    pack = instantiate(_pack, f"pack_{name}", {}, cache=cache)
    unpack = instantiate(_unpack, f"unpack_{name}", {"as_work": as_work}, cache=cache)
    grow = instantiate(_grow_run, f"grow_run_{name}",
                       {"_unpack_impl": unpack, "_pack_impl": pack}, cache=cache)
    # The two loops the sweep is written into run without reference counting (see
    # :func:`_advance`): they allocate nothing, and their caller keeps every array alive.
    chain = instantiate(_speculate_chain, f"speculate_chain_{name}",
                        {"sweep": sweep, "reset_work": reset_work}, cache=cache, nrt=False)
    spec = instantiate(_speculate, f"speculate_{name}", {"_speculate_chain_impl": chain},
                       parallel=True, cache=cache)
    adv = instantiate(_advance, f"advance_{name}", {"sweep": sweep}, cache=cache, nrt=False)
    new_run = instantiate(_new_run, f"new_run_{name}",
                          {"alloc_work": alloc_work, "_pack_impl": pack}, cache=cache)
    run_slice = instantiate(_run_slice, f"run_slice_{name}",
                            {"_speculate_impl": spec, "_advance_impl": adv,
                             "_unpack_impl": unpack, "reset_work": reset_work,
                             "chain_done": chain_done}, cache=cache)
    # A sequential run (batch == 0) has a slice of its own that never speculates:
    # the same code with the speculation bound to a no-op, so that its first call compiles
    # neither the parallel loop nor the second copy of the sweep. Same operations, same bits.
    no_spec = instantiate(no_speculation, f"no_speculation_{name}", {}, cache=cache)
    run_slice_seq = instantiate(_run_slice, f"run_slice_sequential_{name}",
                                {"_speculate_impl": no_spec, "_advance_impl": adv,
                                 "_unpack_impl": unpack, "reset_work": reset_work,
                                 "chain_done": chain_done}, cache=cache)

    def run_chains(data, zkeys, x0, base, n_chains, chain_length, rules, batch, workers,
                   budget=DEFAULT_BUDGET):
        budget = max(1, int(budget))
        step = run_slice if batch > 0 else run_slice_seq
        with interruptible:  # the new run, and growing U, return arrays
            # Two calls, not one compiled entry that makes the run and its first slice (see
            # the module docstring, "Slices"). A slice returns two integers and no array; a
            # signal handler's exception is raised here, between two slices. U grows here,
            # between slices, so that a run that never fills it never compiles the growth.
            run = new_run(data, zkeys, x0, n_chains, chain_length, batch, workers)
            status, _ = step(data, zkeys, x0, base, n_chains, chain_length, rules, batch,
                             workers, budget, run)
            while status != DONE:
                if status == NEED_ROOM:
                    run = grow(run)
                status, _ = step(data, zkeys, x0, base, n_chains, chain_length, rules,
                                 batch, workers, budget, run)
        (states, _, counts, _, _), _, _, _, ctr, _, _ = run  # the packed Run
        n = ctr[NU]
        return states[:n].copy(), counts[:n].copy(), ctr

    run_chains.__name__ = run_chains.__qualname__ = f"run_chains_{name}"
    run_chains.kernels = {"new_run": new_run, "run_slice": run_slice, "speculate": spec,
                          "speculate_chain": chain, "advance": adv,
                          "run_slice_sequential": run_slice_seq,
                          "grow_run": grow}
    run_chains.__doc__ = f"The chain driver of the {name!r} problem type (see make_driver)."
    return run_chains


class ProblemScratch(NamedTuple):
    """Flat buffers from which :func:`_run_problem` carves its unique set, slab and counters,
    problem after problem, without allocating (:func:`problem_scratch`).

    A caller that runs thousands of problems of a few sweeps each (the δ-GLMB filter's
    components) would otherwise spend more time allocating a run's dozen arrays than running
    it. ``cap`` is the largest capacity (a power of two) and ``L`` the longest state.

    Attributes
    ----------
    states : ndarray, shape (cap L,), int32
    hashes, counts, last_chain : ndarray, shape (cap,), uint64, int64, int64
    table : ndarray, shape (4 cap,), uint64
        The buffers of a :class:`UniqueSet`.
    traj : ndarray, shape (0,), int32
    thash : ndarray, shape (0,), uint64
    slab_states : ndarray, shape (L,), int32
    h : ndarray, shape (1,), uint64
    rs : ndarray, shape (8,), uint64
        The buffers of a one-chain :class:`Slab` that speculates nothing.
    ctr : ndarray, shape (N_COUNTERS,), int64
    cctr : ndarray, shape (4,), int64
        The run's and the chain's counters.
    """

    states: np.ndarray
    hashes: np.ndarray
    counts: np.ndarray
    last_chain: np.ndarray
    table: np.ndarray
    traj: np.ndarray
    thash: np.ndarray
    slab_states: np.ndarray
    h: np.ndarray
    rs: np.ndarray
    ctr: np.ndarray
    cctr: np.ndarray


@jit()
def _capacity(n):
    """Smallest power of two ``>= n``, at least 2 (a unique set's capacity for ``n`` states).

    Parameters
    ----------
    n : int
        States to hold.

    Returns
    -------
    int
        The capacity.
    """
    cap = 2
    while cap < n:
        cap *= 2
    return cap


@jit()
def problem_scratch(L, n):
    """A :class:`ProblemScratch` for problems with states of length ``<= L`` and runs of at
    most ``n`` unique states (``n_chains * chain_length + 1``).

    Parameters
    ----------
    L : int
        The longest state.
    n : int
        The most unique states of a run.

    Returns
    -------
    ProblemScratch
        Uninitialised buffers.

    Examples
    --------
    >>> s = problem_scratch(3, 5)
    >>> s.states.shape, s.table.shape
    ((24,), (32,))
    """
    cap = _capacity(n)
    return ProblemScratch(
        states=np.empty(cap * L, dtype=np.int32), hashes=np.empty(cap, dtype=np.uint64),
        counts=np.empty(cap, dtype=np.int64), last_chain=np.empty(cap, dtype=np.int64),
        table=np.empty(4 * cap, dtype=np.uint64), traj=np.empty(0, dtype=np.int32),
        thash=np.empty(0, dtype=np.uint64), slab_states=np.empty(L, dtype=np.int32),
        h=np.empty(1, dtype=np.uint64), rs=np.empty(8, dtype=np.uint64),
        ctr=np.empty(N_COUNTERS, dtype=np.int64), cctr=np.empty(4, dtype=np.int64))


@jit(inline="always")
def _carve(scratch, L, n):
    """An empty unique set with room for ``n`` states of length ``L``, a one-chain slab and
    zeroed counters, all views of ``scratch``: ``(U, slab, ctr, cctr)``.

    The buffers are cleared by loops: for the few entries of a small problem a slice
    assignment's set-up costs more than the stores.

    Parameters
    ----------
    scratch : ProblemScratch
        The buffers (:func:`problem_scratch`), large enough.
    L : int
        Length of a state.
    n : int
        States the unique set must hold.

    Returns
    -------
    (UniqueSet, Slab, ndarray, ndarray)
        ``U`` (capacity :func:`_capacity` of ``n``), the slab of one chain, ``ctr`` and
        ``cctr``.

    Raises
    ------
    ValueError
        If ``scratch`` is too small.
    """
    cap = _capacity(n)
    if cap * L > scratch.states.size or cap > scratch.hashes.size or \
            L > scratch.slab_states.size:
        raise ValueError("problem_scratch: the scratch is smaller than the problem")
    counts = scratch.counts
    last_chain = scratch.last_chain
    for u in range(cap):
        counts[u] = 0
        last_chain[u] = -1
    table = scratch.table
    for t in range(4 * cap):
        table[t] = 0
    ctr = scratch.ctr
    for k in range(ctr.size):
        ctr[k] = 0
    U = UniqueSet(scratch.states[:cap * L].reshape((cap, L)), scratch.hashes[:cap],
                  counts[:cap], last_chain[:cap], table[:4 * cap].reshape((2 * cap, 2)))
    slab = Slab(scratch.traj.reshape((1, 0, L)), scratch.thash.reshape((1, 0)),
                scratch.slab_states[:L].reshape((1, L)), scratch.h,
                scratch.rs.reshape((1, 8)))
    return U, slab, ctr, scratch.cctr


@jit()
def problem_states(scratch, L, n):
    """The first ``n`` unique states of the last run in ``scratch`` (:func:`_run_problem`),
    shape (n, L), in discovery order: a view, valid until the scratch's next use.

    Parameters
    ----------
    scratch : ProblemScratch
        The buffers of the last run.
    L : int
        Its state length.
    n : int
        Its unique states (the run's ``n_unique``).

    Returns
    -------
    ndarray of int32, shape (n, L)

    Examples
    --------
    >>> s = problem_scratch(2, 4)
    >>> problem_states(s, 2, 3).shape
    (3, 2)
    """
    return scratch.states[:n * L].reshape((n, L))


def _run_problem(data, work, zkeys, x0, base, n_chains, chain_length, rules, scratch):
    """The short-chain run of one small problem, chain after chain, in one call.

    The sequential run of :func:`_run_slice` (``batch = 0``) with the same chains, streams,
    unique set and stall and stale rules, for a caller that runs many small problems inside
    one compiled loop (the δ-GLMB filter's per-component truncation): no slices, no
    speculation, ``U`` sized for every observation up front so that it never grows, and the
    unique set, slab and counters carved from ``scratch``. It allocates nothing and runs
    without reference counting (``nrt=False``, as :func:`_advance`): for problems of a few
    sweeps, a run's set-up would otherwise cost more than its chains.

    Parameters
    ----------
    data, zkeys, x0, base, n_chains, chain_length, rules
        As in :func:`_run_slice`.
    work : named tuple
        The kind's workspace of one chain (its ``alloc_work(data, 1)``).
    scratch : ProblemScratch
        Large enough for the problem (:func:`problem_scratch`); overwritten.

    Returns
    -------
    n_unique : int
        Unique states, in discovery order (``x0`` first): :func:`problem_states`.
    n_observations : int
        Observations (sweeps). ``scratch.ctr`` holds every counter of the run
        (:func:`make_driver`).
    """
    L = x0.shape[0]
    h0 = hash_of(zkeys, x0)
    U, slab, ctr, cctr = _carve(scratch, L, n_chains * chain_length + 1)
    add_state(U, x0, h0, 0)  # U <- {x0}, not an observation
    ctr[NU] = 1
    state = slab.states[0]
    for c in range(n_chains):
        for i in range(L):
            state[i] = x0[i]
        reset_work(data, work, np.int64(0), x0)
        slab.h[0] = h0
        slab.rs[0, 0] = chain_state(base, c)
        _begin_chain(c, U.last_chain, cctr)
        _advance_impl(data, work, zkeys, slab, U, ctr, cctr, rules,
                      Span(b=0, c=c, j0=0, j1=chain_length, done=0))
        if _end_chain(ctr, cctr, rules.stale_mode, rules.tau_stale):
            break
    return ctr[NU], ctr[NOBS]


def make_problem_runner(name, reset_work, sweep, *, cache=None):
    """Compile the one-call run of one problem (:func:`_run_problem`) for a problem type.

    For callers that loop over many small problems in compiled code: the returned function
    is a compiled kernel, callable from another one, with the chains, unique set and
    stall/stale rules of :func:`make_driver`'s ``run_chains`` (sequential, ``batch = 0``).

    Parameters
    ----------
    name : str
        Unique name of the instantiation (names its compiled functions and cache files).
    reset_work, sweep : compiled functions
        The problem type's functions, as in :func:`make_driver` (the caller allocates the
        workspace with the kind's ``alloc_work(data, 1)``).
    cache : bool, optional
        As in :func:`rankedassign.numba_options.jit`.

    Returns
    -------
    run_problem : compiled function
        ``run_problem(data, work, zkeys, x0, base, n_chains, chain_length, rules, scratch)
        -> (n_unique, n_observations)`` (:func:`_run_problem`, ``scratch`` from
        :func:`problem_scratch`, the states then read with :func:`problem_states`): the same
        unique states, in the same order, and the same counters as
        ``run_chains(..., batch=0, ...)``.
    """
    adv = instantiate(_advance, f"advance_{name}", {"sweep": sweep}, cache=cache, nrt=False)
    return instantiate(_run_problem, f"run_problem_{name}",
                       {"reset_work": reset_work, "_advance_impl": adv}, cache=cache,
                       nrt=False)

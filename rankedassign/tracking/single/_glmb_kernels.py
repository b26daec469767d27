"""Compiled kernels of the δ-GLMB filter: every component's problem, sampled in one call.

The δ-GLMB joint prediction and update (Vo, Vo & Hoang 2017, Alg. 2; ``../shared/spec/glmb.md``
§2) solves one ranked-assignment problem per prior component, a thousand of them per scan in
Vo's example. A Python loop over them costs more than the sampling, so the Gibbs truncations
run here in one compiled call per scan:

1. :func:`component_problem` lists the rows (the birth tracks, then the component's survivors)
   and the columns (the measurements some row gates) of one component;
2. :func:`sample_components` gathers each problem's weights from the scan's shared
   per-(track, measurement) terms, runs the chains and emits every unique assignment as a
   child (its parent, its cost, and the (track, measurement) pair of every row that exists
   after the scan);
   :func:`ranked_components` does the same for Murty's ``k`` best and for the enumeration of
   every assignment (:class:`~rankedassign.tracking.Murty`, :class:`~rankedassign.tracking.Exact`),
   with the oracle's compiled searches (:mod:`oracle.kernels`), after
   :func:`count_components` has counted each component's assignments for the enumeration;
3. :func:`merge_children` merges children with the same track set and sums their weights;
4. :func:`mark_reachable` finds the association-history nodes that live tracks still use.

The chains are those of :func:`rankedassign.sample_short_chains` with the default readings of
the stall and stale rules (the original sampler is one chain without rules): the same sweep
(:func:`rankedassign.single._kernels.sweep`, or
:func:`~rankedassign.single._kernels.sweep_prefix` where
:func:`rankedassign.single.prepare.uses_prefix_sums` says so), the same SplitMix64 stream per
chain, the same start state and the same unique set in discovery order. Given the base key of
:func:`rankedassign.engine.rng.base_key` a component's children are the sampler's unique
assignments
(``tests/test_tracking_glmb.py`` holds the two together).

References
----------
.. [1] B.-N. Vo, B.-T. Vo, H. G. Hoang, "An Efficient Implementation of the Generalized
   Labeled Multi-Bernoulli Filter", IEEE Trans. Signal Process. 65(8):1975-1987, 2017.
.. [2] A. Trezza, D. J. Bucci Jr., P. K. Varshney, "On Gibbs Sampling Architecture for
   Labeled Random Finite Sets Multi-Object Tracking", arXiv:2306.15135, 2023.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from oracle.kernels import NO_OPTION, count_slice, enumerate_sorted_kernel, murty_compact_kernel

from ...engine._kernels import chain_state, hash_of, mix64
from ...numba_options import jit
from ...single._kernels import sweep, sweep_prefix
from ...single.prepare import M_DIRECT, PrefixData, prefix_sums
from .._kernels import _logaddexp

__all__ = ["component_keys", "component_problem", "component_costs", "count_components",
           "ranked_components", "sample_components", "ChainRules", "merge_children",
           "mark_reachable"]


@jit()
def component_keys(key, H):
    """Base keys of the streams of ``H`` components: ``chain_state(key, h)``, shape (H,).

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign.tracking.single._glmb_kernels import component_keys
    >>> from rankedassign.engine.rng import chain_state
    >>> int(component_keys(np.uint64(5), 2)[1]) == chain_state(5, 1)
    True
    """
    out = np.empty(H, dtype=np.uint64)
    for h in range(H):
        out[h] = chain_state(key, h)
    return out


@jit()
def component_problem(h, comp_off, comp_tracks, births, gated, mark, rows, cols):
    """Rows and columns of the problem of component ``h``; returns ``(P, M)``.

    Parameters
    ----------
    h : int
        Component.
    comp_off, comp_tracks : ndarray of int64, shapes (H + 1,), (N,)
        Track-table entries of every component (CSR).
    births : ndarray of int64, shape (B,)
        Entries of the birth tracks of the scan (rows of every component).
    gated : ndarray of bool, shape (T, U)
        Gate of every entry against the scan's gated measurements.
    mark : ndarray of bool, shape (U,)
        Work space, all False (left all False).
    rows, cols : ndarray of int64
        Filled with the ``P`` rows (births first, then the component's entries in their order)
        and the ``M`` columns (increasing: every measurement some row gates).

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign.tracking.single._glmb_kernels import component_problem
    >>> gated = np.array([[1, 0, 0], [0, 0, 1], [0, 0, 1]], dtype=bool)
    >>> rows, cols = np.empty(3, np.int64), np.empty(3, np.int64)
    >>> P, M = component_problem(0, np.array([0, 1]), np.array([1]), np.array([2]), gated,
    ...                          np.zeros(3, bool), rows, cols)
    >>> rows[:P].tolist(), cols[:M].tolist()
    ([2, 1], [2])
    """
    P = 0
    for b in range(births.size):
        rows[P] = births[b]
        P += 1
    for q in range(comp_off[h], comp_off[h + 1]):
        rows[P] = comp_tracks[q]
        P += 1
    U = gated.shape[1]
    for i in range(P):
        r = rows[i]
        for j in range(U):
            if gated[r, j]:
                mark[j] = True
    M = 0
    for j in range(U):
        if mark[j]:
            cols[M] = j
            M += 1
            mark[j] = False
    return P, M


@jit(inline="always")
def _emit_rows(child_entry, child_meas, e_out, rows, cols, option, M, dead):
    """Write the (entry, measurement or ``−1``) of every row of one child that exists after
    the scan (``option[i] < dead``; a measurement when ``< M``, else missed); return the new
    end of the pairs."""
    for i in range(option.size):
        k = option[i]
        if k < dead:
            child_entry[e_out] = rows[i]
            child_meas[e_out] = cols[k] if k < M else -1
            e_out += 1
    return e_out


@jit()
def component_costs(h, comp_off, comp_tracks, births, cc_all, gated, mark, rows, cols):
    """The compact costs of component ``h``'s problem, gathered from the scan's terms.

    Parameters
    ----------
    h, comp_off, comp_tracks, births, gated, mark, rows, cols
        As in :func:`component_problem` (``rows`` and ``cols`` are filled).
    cc_all : ndarray of float64, shape (T, U + 2)
        ``−ln η`` of every entry: its gated measurements, missed, dead (``+inf`` outside the
        gate).

    Returns
    -------
    P, M : int
        Rows and columns of the problem.
    cc : ndarray of float64, shape (P, M + 2)
        Its compact costs (:attr:`rankedassign.AssignmentProblem.compact_cost`).

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign.tracking.single._glmb_kernels import component_costs
    >>> gated = np.array([[True, False], [False, True]])
    >>> cc_all = np.array([[0.5, np.inf, 1.0, 2.0], [np.inf, 0.25, 3.0, 4.0]])
    >>> rows, cols = np.empty(2, np.int64), np.empty(2, np.int64)
    >>> P, M, cc = component_costs(0, np.array([0, 1]), np.array([1]), np.array([0]), cc_all,
    ...                            gated, np.zeros(2, bool), rows, cols)
    >>> cc.tolist()
    [[0.5, inf, 1.0, 2.0], [inf, 0.25, 3.0, 4.0]]
    """
    P, M = component_problem(h, comp_off, comp_tracks, births, gated, mark, rows, cols)
    U = gated.shape[1]
    cc = np.empty((P, M + 2))
    for i in range(P):
        r = rows[i]
        for j in range(M):
            cc[i, j] = cc_all[r, cols[j]]
        cc[i, M] = cc_all[r, U]
        cc[i, M + 1] = cc_all[r, U + 1]
    return P, M, cc


@jit()
def count_components(comp_off, comp_tracks, births, cc_all, gated, cap):
    """``min(|Γ_h|, cap + 1)`` for every component (the depth-first count of the oracle).

    Parameters
    ----------
    comp_off, comp_tracks, births, cc_all, gated
        As in :func:`component_costs`.
    cap : int
        The count stops past it.

    Returns
    -------
    counts : ndarray of int64, shape (H,)
        The number of feasible assignments of each component's problem, ``cap + 1`` for one
        with more than ``cap``.
    sizes : ndarray of int64, shape (H, 2)
        ``(P, M)`` of each problem.

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign.tracking.single._glmb_kernels import count_components
    >>> gated = np.array([[True]])
    >>> counts, sizes = count_components(np.array([0, 0]), np.empty(0, np.int64),
    ...                                  np.array([0]), np.array([[0.5, 1.0, 2.0]]), gated, 10)
    >>> counts.tolist(), sizes.tolist()
    ([3], [[1, 1]])
    """
    H = comp_off.size - 1
    T, U = gated.shape
    mark = np.zeros(U, dtype=np.bool_)
    width = 0
    for h in range(H):
        width = max(width, comp_off[h + 1] - comp_off[h])
    rows = np.empty(births.size + width, dtype=np.int64)
    cols = np.empty(U, dtype=np.int64)
    counts = np.empty(H, dtype=np.int64)
    sizes = np.empty((H, 2), dtype=np.int64)
    for h in range(H):
        P, M, cc = component_costs(h, comp_off, comp_tracks, births, cc_all, gated, mark, rows,
                                   cols)
        sizes[h, 0], sizes[h, 1] = P, M
        if P == 0:
            counts[h] = 1
            continue
        used = np.zeros(M, dtype=np.bool_)
        opt = np.full(P, NO_OPTION, dtype=np.int64)
        at = np.zeros(2, dtype=np.int64)
        count_slice(cc, cap, used, opt, at, 1 << 62)
        counts[h] = at[1]
    return counts, sizes


@jit()
def ranked_components(comp_off, comp_tracks, births, cc_all, gated, n_want, exact, h0, h1):
    """Murty's ``k`` best, or every assignment, of components ``h0 .. h1 − 1``: the children.

    Parameters
    ----------
    comp_off, comp_tracks, births, cc_all, gated
        As in :func:`component_costs`.
    n_want : ndarray of int64, shape (H,)
        Murty's ``k >= 1`` of every component, or (``exact``) its count of assignments from
        :func:`count_components`.
    exact : bool
        Enumerate every assignment (:func:`oracle.kernels.enumerate_sorted_kernel`) instead of
        Murty's search (:func:`oracle.kernels.murty_compact_kernel`).
    h0, h1 : int
        The components, ``0 <= h0 <= h1 <= H``.

    Returns
    -------
    comp, cost, off, entry, meas : ndarray
        The children, as :func:`sample_components` returns them: parent, cost (best first
        within a parent, as the oracle returns them), and the (entry, measurement or ``−1``)
        of every row that exists after the scan, child ``c``'s in ``off[c]:off[c + 1]``
        (``off[0] = 0``).

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign.tracking.single._glmb_kernels import ranked_components
    >>> gated = np.array([[True]])
    >>> out = ranked_components(np.array([0, 0]), np.empty(0, np.int64), np.array([0]),
    ...                         np.array([[0.5, 1.0, 2.0]]), gated, np.array([2]), False, 0, 1)
    >>> [x.tolist() for x in out]
    [[0, 0], [0.5, 1.0], [0, 1, 2], [0, 0], [0, -1]]
    """
    T, U = gated.shape
    mark = np.zeros(U, dtype=np.bool_)
    width = 0
    n_cap = 0
    e_cap = 0
    for h in range(h0, h1):
        size = comp_off[h + 1] - comp_off[h]
        width = max(width, size)
        n_cap += n_want[h]
        e_cap += n_want[h] * (births.size + size)
    rows = np.empty(births.size + width, dtype=np.int64)
    cols = np.empty(U, dtype=np.int64)
    child_comp = np.empty(n_cap, dtype=np.int64)
    child_cost = np.empty(n_cap)
    child_off = np.zeros(n_cap + 1, dtype=np.int64)
    child_entry = np.empty(e_cap, dtype=np.int64)
    child_meas = np.empty(e_cap, dtype=np.int64)
    n_out = 0
    e_out = 0
    for h in range(h0, h1):
        P, M, cc = component_costs(h, comp_off, comp_tracks, births, cc_all, gated, mark, rows,
                                   cols)
        if P == 0:  # no row at all: the one empty assignment
            child_comp[n_out] = h
            child_cost[n_out] = 0.0
            n_out += 1
            child_off[n_out] = e_out
            continue
        if exact:
            a, c = enumerate_sorted_kernel(cc, n_want[h])
        else:
            a, c = murty_compact_kernel(cc, n_want[h])
        for u in range(a.shape[0]):
            child_comp[n_out] = h
            child_cost[n_out] = c[u]
            # full columns: a measurement (< M) or missed (< M + P), then dead
            e_out = _emit_rows(child_entry, child_meas, e_out, rows, cols, a[u], M, M + P)
            n_out += 1
            child_off[n_out] = e_out
    return (child_comp[:n_out].copy(), child_cost[:n_out].copy(),
            child_off[:n_out + 1].copy(), child_entry[:e_out].copy(),
            child_meas[:e_out].copy())


@jit()
def _find_or_insert(table, hashes, states, n_u, x, hx):
    """Index of ``x`` in the unique set, inserting it as number ``n_u`` if new; ``(u, new)``."""
    mask = table.shape[0] - 1
    P = x.shape[0]
    slot = np.int64(hx & np.uint64(mask))
    while True:
        v = table[slot]
        if v == 0:
            table[slot] = n_u + 1
            hashes[n_u] = hx
            for i in range(P):
                states[n_u, i] = x[i]
            return n_u, True
        u = v - 1
        if hashes[u] == hx:
            same = True
            for i in range(P):
                if states[u, i] != x[i]:
                    same = False
                    break
            if same:
                return u, False
        slot = (slot + 1) & mask


@jit()
def _table_size(n):
    """Smallest power of two >= 2 n (load factor at most one half)."""
    size = 2
    while size < 2 * n:
        size *= 2
    return size


class ChainRules(NamedTuple):
    """How :func:`sample_components` runs the chains of every component.

    Attributes
    ----------
    random_scan : bool
        Random instead of systematic row order.
    tau_stall : int
        Threshold of the stall rule (global-consecutive reading), 0 = off.
    tau_stale : int
        Threshold of the stale rule (consecutive reading), 0 = off.
    """

    random_scan: bool
    tau_stall: int
    tau_stale: int


class ComponentChains(NamedTuple):
    """The chains of one component (:func:`_component_chains`): start, scratch, unique set.

    Attributes
    ----------
    x0 : ndarray, shape (P,), int32
        The start state (every row missed where it can be, else dead).
    h0 : uint64
        Its Zobrist hash.
    state : ndarray, shape (P,), int32
        The chain's state.
    free : ndarray, shape (M,), float64
        Its free-measurement mask.
    perm : ndarray, shape (P,), int64
        Row order of the random scan.
    cum : ndarray, shape (M + 2,), float64
        Scratch row of the prefix-sum draw.
    held : ndarray, shape (max(P, 1),), int64
        The held measurements, sorted (prefix-sum draw).
    n_held : ndarray, shape (1,), int64
        Their number.
    rs : ndarray, shape (1,), uint64
        The chain's stream state.
    table, hashes, states
        The component's unique set (:func:`_find_or_insert`), ``x0`` its unique 0.
    """

    x0: np.ndarray
    h0: np.uint64
    state: np.ndarray
    free: np.ndarray
    perm: np.ndarray
    cum: np.ndarray
    held: np.ndarray
    n_held: np.ndarray
    rs: np.ndarray
    table: np.ndarray
    hashes: np.ndarray
    states: np.ndarray


@jit(nrt=False)
def _component_chains(data, prefix, zkeys, chains, n_chains, chain_length, base, rules):
    """The chains of one component (spec §3.3, the default readings of stall and stale).

    ``data`` is the component's :class:`~rankedassign.single.prepare.PrefixData` (its prefix
    sums placeholders unless ``prefix``: the rows draw from them, else by the direct sum);
    ``chains`` a :class:`ComponentChains` whose unique set holds ``x0`` alone. Compiled without
    reference counting, as the chain driver's loops are
    (:func:`rankedassign.engine._kernels.make_driver`): the sweep written into the loop reads
    its arrays from the records on every sweep.

    Returns
    -------
    (n_unique, n_observations) : (int, int)
    """
    x0, state, free, perm, cum = chains.x0, chains.state, chains.free, chains.perm, chains.cum
    held, n_held, rs = chains.held, chains.n_held, chains.rs
    table, hashes, states = chains.table, chains.hashes, chains.states
    P = x0.shape[0]
    n_u = 1
    obs = 0
    stale_run = 0
    for c in range(n_chains):
        for i in range(P):
            state[i] = x0[i]
        free[:] = 1.0  # the start state holds no measurement
        n_held[0] = 0
        rs[0] = chain_state(base, c)
        hx = chains.h0
        stall_run = 0
        new_in_chain = 0
        for _ in range(chain_length):
            if prefix:
                hx = sweep_prefix(data, zkeys, state, hx, rs, free, perm, cum, held, n_held)
            else:
                hx = sweep(data, zkeys, state, hx, rs, free, perm)
            obs += 1
            u, new = _find_or_insert(table, hashes, states, n_u, state, hx)
            if new:
                n_u += 1
                new_in_chain += 1
                stall_run = 0
            else:
                stall_run += 1
            if rules.tau_stall > 0 and stall_run >= rules.tau_stall:
                break
        if new_in_chain > 0:
            stale_run = 0
        else:
            stale_run += 1
        if rules.tau_stale > 0 and stale_run >= rules.tau_stale:
            break
    return n_u, obs


@jit()
def sample_components(comp_off, comp_tracks, births, W_all, cc_all, gated, n_chains,
                      chain_length, rules, base, zkeys):
    """Run the Gibbs truncation of every component; return the children.

    Parameters
    ----------
    comp_off, comp_tracks, births, gated
        As in :func:`component_problem`.
    W_all, cc_all : ndarray, shape (T, U + 2)
        Per entry, over ``[gated measurements | missed | dead]``: the compact costs
        ``−ln η`` (``+inf`` outside the gate) and the shifted weights
        ``exp(−(cc − min cc))`` of its row (the row minimum does not depend on the component:
        a row's finite entries are all among its component's columns).
    n_chains, chain_length : ndarray of int64, shape (H,)
        Budget of every component: chains and sweeps per chain (0 chains: the start state only).
    rules : ChainRules
        Scan order and the thresholds of the stall and stale rules.
    base : ndarray of uint64, shape (H,)
        Base key of every component's streams (chain ``c``: ``chain_state(base, c)``).
    zkeys : ndarray of uint64, shape (P_max, M_max + 2)
        Zobrist keys, at least as large as every problem.

    Returns
    -------
    child_comp : ndarray of int64, shape (N,)
        Parent component of every child, children of a component in discovery order (the
        start state first).
    child_cost : ndarray, shape (N,)
        ``Σ_i −ln η_i(γ_i)``.
    child_off : ndarray of int64, shape (N + 1,)
        CSR offsets of the rows that exist after the scan (not ``γ_i = −1``).
    child_entry, child_meas : ndarray of int64
        Their entry and measurement (a column of ``gated``; ``−1``: missed).
    sweeps : ndarray of int64, shape (H,)
        Observations (full sweeps) of every component.
    n_rows : ndarray of int64, shape (H,)
        Rows of every component's problem.

    Notes
    -----
    The start state has every row missed where ``η(0) > 0`` (Vo's choice), else dead.
    Each chain ``c`` starts there with the stream ``chain_state(base, c)``; each sweep is an
    observation added to the component's unique set; a chain stops after ``tau_stall``
    observations in a row that were not new, the run after ``tau_stale`` chains in a row that
    added nothing (spec §3.3).
    """
    H = comp_off.size - 1
    U = W_all.shape[1] - 2
    B = births.size
    P_max = B
    for h in range(H):
        P_max = max(P_max, B + comp_off[h + 1] - comp_off[h])
    # upper bounds of the output: every observation new, every row present
    n_cap = 0
    e_cap = 0
    for h in range(H):
        c = n_chains[h] * chain_length[h] + 1
        n_cap += c
        e_cap += c * (B + comp_off[h + 1] - comp_off[h])
    child_comp = np.empty(n_cap, dtype=np.int64)
    child_cost = np.empty(n_cap)
    child_off = np.zeros(n_cap + 1, dtype=np.int64)
    child_entry = np.empty(e_cap, dtype=np.int64)
    child_meas = np.empty(e_cap, dtype=np.int64)
    sweeps = np.zeros(H, dtype=np.int64)
    n_rows = np.zeros(H, dtype=np.int64)
    mark = np.zeros(U, dtype=np.bool_)
    rows = np.empty(P_max, dtype=np.int64)
    cols = np.empty(U, dtype=np.int64)
    rs = np.empty(1, dtype=np.uint64)
    n_out = 0
    e_out = 0
    for h in range(H):
        P, M = component_problem(h, comp_off, comp_tracks, births, gated, mark, rows, cols)
        n_rows[h] = P
        K = M + 2
        # gather the problem's weights from the shared terms
        W = np.empty((P, K))
        cc = np.empty((P, K))
        for i in range(P):
            r = rows[i]
            for k in range(M):
                W[i, k] = W_all[r, cols[k]]
                cc[i, k] = cc_all[r, cols[k]]
            W[i, M] = W_all[r, U]
            W[i, M + 1] = W_all[r, U + 1]
            cc[i, M] = cc_all[r, U]
            cc[i, M + 1] = cc_all[r, U + 1]
        x0 = np.empty(P, dtype=np.int32)
        for i in range(P):
            x0[i] = M if cc[i, M] < np.inf else M + 1
        cap = n_chains[h] * chain_length[h] + 1
        states = np.empty((cap, P), dtype=np.int32)
        hashes = np.empty(cap, dtype=np.uint64)
        table = np.zeros(_table_size(cap), dtype=np.int64)
        h0 = hash_of(zkeys, x0)
        _find_or_insert(table, hashes, states, 0, x0, h0)
        prefix = M > M_DIRECT and M > 2 * P
        if prefix:
            S, next_pos = prefix_sums(W)
        else:
            S = np.zeros((P, 1))
            next_pos = np.zeros((P, 1), dtype=np.int64)
        data = PrefixData(W=W, cc=cc, S=S, next_pos=next_pos, random_scan=rules.random_scan)
        chains = ComponentChains(
            x0=x0, h0=h0, state=np.empty(P, dtype=np.int32), free=np.empty(M),
            perm=np.empty(P, dtype=np.int64), cum=np.empty(K),
            held=np.empty(max(P, 1), dtype=np.int64), n_held=np.zeros(1, dtype=np.int64),
            rs=rs, table=table, hashes=hashes, states=states)
        n_u, obs = _component_chains(data, prefix, zkeys, chains, n_chains[h], chain_length[h],
                                     base[h], rules)
        sweeps[h] = obs
        # the children: cost, and the (entry, measurement) of every row that exists
        for u in range(n_u):
            cost = 0.0
            for i in range(P):
                cost += cc[i, states[u, i]]
            child_comp[n_out] = h
            child_cost[n_out] = cost
            # compact columns: a measurement (< M) or missed (M), then dead (M + 1)
            e_out = _emit_rows(child_entry, child_meas, e_out, rows, cols, states[u], M, M + 1)
            n_out += 1
            child_off[n_out] = e_out
    return (child_comp[:n_out].copy(), child_cost[:n_out].copy(),
            child_off[:n_out + 1].copy(), child_entry[:e_out].copy(),
            child_meas[:e_out].copy(), sweeps, n_rows)


@jit()
def merge_children(child_off, child_ids, log_w):
    """Group children with the same track set; sum their weights in log space.

    Parameters
    ----------
    child_off : ndarray of int64, shape (N + 1,)
        CSR offsets of the children's track lists.
    child_ids : ndarray of int64
        New track-table entries of every child, increasing within each child.
    log_w : ndarray, shape (N,)
        Log weights of the children.

    Returns
    -------
    group : ndarray of int64, shape (N,)
        Group of every child, numbered in the order of first appearance.
    group_log_w : ndarray, shape (G,)
        ``ln Σ exp(log_w)`` over each group's children (folded in child order).
    first : ndarray of int64, shape (G,)
        The first child of each group.

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign.tracking.single._glmb_kernels import merge_children
    >>> g, lw, first = merge_children(np.array([0, 2, 3, 5]), np.array([0, 4, 1, 0, 4]),
    ...                               np.log([0.2, 0.3, 0.5]))
    >>> g.tolist(), np.exp(lw).round(3).tolist(), first.tolist()
    ([0, 1, 0], [0.7, 0.3], [0, 1])
    """
    N = child_off.size - 1
    table = np.zeros(_table_size(max(N, 1)), dtype=np.int64)
    mask = table.shape[0] - 1
    keys = np.empty(N, dtype=np.uint64)
    group = np.empty(N, dtype=np.int64)
    group_log_w = np.empty(N)
    first = np.empty(N, dtype=np.int64)
    G = 0
    for n in range(N):
        a = child_off[n]
        b = child_off[n + 1]
        key = mix64(np.uint64(b - a + 1))
        for q in range(a, b):
            key = mix64(key ^ np.uint64(child_ids[q] + 1))
        keys[n] = key
        slot = np.int64(key & np.uint64(mask))
        while True:
            v = table[slot]
            if v == 0:
                table[slot] = G + 1
                group[n] = G
                group_log_w[G] = log_w[n]
                first[G] = n
                G += 1
                break
            g = v - 1
            f = first[g]
            same = keys[f] == key and child_off[f + 1] - child_off[f] == b - a
            if same:
                fa = child_off[f]
                for q in range(b - a):
                    if child_ids[fa + q] != child_ids[a + q]:
                        same = False
                        break
            if same:
                group[n] = g
                group_log_w[g] = _logaddexp(group_log_w[g], log_w[n])
                break
            slot = (slot + 1) & mask
    return group, group_log_w[:G].copy(), first[:G].copy()


@jit()
def mark_reachable(parent, live):
    """Nodes of the history forest reachable from the nodes ``live`` (``parent −1``: a root).

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign.tracking.single._glmb_kernels import mark_reachable
    >>> mark_reachable(np.array([-1, 0, 0, 2, -1]), np.array([3])).tolist()
    [True, False, True, True, False]
    """
    keep = np.zeros(parent.size, dtype=np.bool_)
    for s in range(live.size):
        v = live[s]
        while v >= 0 and not keep[v]:
            keep[v] = True
            v = parent[v]
    return keep

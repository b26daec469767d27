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

The chains are the engine's: :func:`sample_components` hands each component's problem to
:func:`rankedassign.engine._kernels.make_problem_runner`'s compiled run (the sequential run of
:func:`rankedassign.sample_short_chains`, with the default readings of the stall and stale
rules; the original sampler is one chain without rules), compiled for the single-sensor kind's
direct and prefix-sum sweeps (:func:`rankedassign.single._kernels.row_sweep`,
:func:`~rankedassign.single._kernels.row_sweep_prefix`, where
:func:`rankedassign.single.prepare.uses_prefix_sums` says so): the same SplitMix64 stream per
chain, the same start state and the same unique set in discovery order. Given the base key of
:func:`rankedassign.engine.rng.base_key` a component's children are the sampler's unique
assignments (``tests/test_tracking_glmb.py`` holds the two together). The merge of children
(:func:`merge_children`) keys the same unique set by track sets. No chain loop or hash table
is written here: this module keeps only what is δ-GLMB, the gather, the children, the merge.

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

from oracle.kernels import NO_OPTION, count_slice, enumerate_sorted_kernel, murty_compact_inline

from ...engine._kernels import (
    Rules,
    add_state,
    chain_state,
    make_problem_runner,
    mix64,
    problem_scratch,
    problem_states,
    unique_set,
)
from ...numba_options import instantiate, jit
from ...single._kernels import (
    alloc_work,
    alloc_work_prefix,
    reset_work,
    reset_work_prefix,
    row_sweep,
    row_sweep_prefix,
)
from ...single.prepare import M_DIRECT, PrefixData, prefix_sums
from ...validation import STALE_CONSECUTIVE, STALE_OFF, STALL_GLOBAL_CONSECUTIVE, STALL_OFF
from .._glmb_gather import child_bounds, component_rows, cut_children, new_children
from .._kernels import _logaddexp

__all__ = ["component_keys", "component_problem", "component_costs", "count_components",
           "ranked_components", "sample_components", "ChainRules", "merge_children",
           "mark_reachable"]


@jit()
def component_keys(key, H):
    """Base keys of the streams of ``H`` components: ``chain_state(key, h)``, shape (H,).

    Parameters
    ----------
    key : uint64
        The scan's base key (:func:`rankedassign.engine.rng.base_key`).
    H : int
        Components.

    Returns
    -------
    ndarray of uint64, shape (H,)
        Component ``h``'s base key.

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

    Returns
    -------
    (int, int)
        ``P`` and ``M``.

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
    P = component_rows(h, comp_off, comp_tracks, births, gated, mark, rows)
    U = gated.shape[1]
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
    end of the pairs.

    Parameters
    ----------
    child_entry, child_meas : ndarray of int64
        The children's pairs, written from ``e_out`` on.
    e_out : int
        End of the pairs so far.
    rows : ndarray of int64, shape (P,)
        Track-table entries of the problem's rows.
    cols : ndarray of int64, shape (M,)
        Gated measurements of its columns.
    option : ndarray, shape (P,)
        The child's column of every row.
    M : int
        Measurements of the problem.
    dead : int
        The first column that means the row does not exist after the scan.

    Returns
    -------
    int
        The new end of the pairs.
    """
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


def ranked_components(comp_off, comp_tracks, births, cc_all, gated, n_want, exact, h0, h1):
    """Murty's ``k`` best, or every assignment, of components ``h0 .. h1 − 1``: the children.

    Two compiled loops do the work, one over Murty's search and one over the enumeration, so
    that a filter compiles only the one it uses (Murty's search is most of a first δ-GLMB
    step's compile).

    Parameters
    ----------
    comp_off, comp_tracks, births, cc_all, gated
        As in :func:`component_costs`.
    n_want : ndarray of int64, shape (H,)
        Murty's ``k >= 1`` of every component, or (``exact``) its count of assignments from
        :func:`count_components`.
    exact : bool
        Enumerate every assignment (:func:`oracle.kernels.enumerate_sorted_kernel`) instead of
        Murty's search (:func:`oracle.kernels.murty_compact_kernel`, written into the loop:
        :data:`oracle.kernels.murty_compact_inline`).
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
    kernel = _ranked_enumerated if exact else _ranked_murty
    return kernel(comp_off, comp_tracks, births, cc_all, gated, n_want, h0, h1)


def _rank_component(cc, k):  # pragma: no cover - replaced in every instantiation
    raise NotImplementedError


def _ranked(comp_off, comp_tracks, births, cc_all, gated, n_want, h0, h1):
    """:func:`ranked_components` with one search, ``_rank_component(cc, k)`` (the template of
    :data:`_ranked_murty` and :data:`_ranked_enumerated`)."""
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
    child_comp, child_cost, child_off, child_entry, child_meas = new_children(n_cap, e_cap)
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
        a, c = _rank_component(cc, n_want[h])
        for u in range(a.shape[0]):
            child_comp[n_out] = h
            child_cost[n_out] = c[u]
            # full columns: a measurement (< M) or missed (< M + P), then dead
            e_out = _emit_rows(child_entry, child_meas, e_out, rows, cols, a[u], M, M + P)
            n_out += 1
            child_off[n_out] = e_out
    return cut_children(child_comp, child_cost, child_off, child_entry, child_meas, n_out,
                        e_out)


#: :func:`ranked_components`' loop over Murty's ``k`` best of each component.
_ranked_murty = instantiate(_ranked, "ranked_components_murty",
                            {"_rank_component": murty_compact_inline})
#: :func:`ranked_components`' loop over the sorted enumeration of each component.
_ranked_enumerated = instantiate(_ranked, "ranked_components_enumerated",
                                 {"_rank_component": enumerate_sorted_kernel})


class ChainRules(NamedTuple):
    """How :func:`sample_components` runs the chains of every component.

    The filter's reading of the engine's rules (:func:`engine_rules`): the engine runs the
    chains and applies the rules.

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


#: The engine's one-call run of a component's problem (its chains, unique set and stall and
#: stale rules), compiled for the single-sensor kind's direct and prefix-sum draws.
_run_direct = make_problem_runner("glmb_component", reset_work, row_sweep)
_run_prefix = make_problem_runner("glmb_component_prefix", reset_work_prefix,
                                  row_sweep_prefix)


@jit()
def engine_rules(rules):
    """The engine's :class:`~rankedassign.engine._kernels.Rules` of a :class:`ChainRules`.

    The stall rule in its global-consecutive reading, the stale rule in its consecutive one
    (spec §3.2; the samplers' defaults), a threshold of 0 turning the rule off.

    Parameters
    ----------
    rules : ChainRules
        The filter's thresholds.

    Returns
    -------
    Rules
        ``(stall_mode, tau_stall, stale_mode, tau_stale)``.

    Examples
    --------
    >>> from rankedassign.tracking.single._glmb_kernels import ChainRules, engine_rules
    >>> tuple(engine_rules(ChainRules(random_scan=False, tau_stall=5, tau_stale=0)))
    (1, 5, 0, 0)
    """
    return Rules(STALL_GLOBAL_CONSECUTIVE if rules.tau_stall > 0 else STALL_OFF,
                 rules.tau_stall,
                 STALE_CONSECUTIVE if rules.tau_stale > 0 else STALE_OFF,
                 rules.tau_stale)


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
    added nothing (spec §3.3). The chains are the engine's
    (:func:`rankedassign.engine._kernels.make_problem_runner`): this kernel only gathers each
    problem and emits its unique states as children.

    A scan of at most ``M_DIRECT`` measurements cannot give a component the prefix-sum draw,
    so it runs a loop compiled without it: a first step on a small scene compiles one runner,
    not two. Same components, same draws, same bits.
    """
    direct_only = W_all.shape[1] - 2 <= M_DIRECT
    kernel = _sample_direct if direct_only else _sample_any
    return kernel(comp_off, comp_tracks, births, W_all, cc_all, gated, n_chains, chain_length,
                  rules, base, zkeys)


#: Measurements above which a component may take the prefix-sum draw (bound per instantiation
#: of :func:`_sample`).
_PREFIX_FROM = M_DIRECT


def _sample(comp_off, comp_tracks, births, W_all, cc_all, gated, n_chains, chain_length,
            rules, base, zkeys):
    """:func:`sample_components`, the prefix-sum draw above ``_PREFIX_FROM`` measurements (the
    template of :data:`_sample_any` and :data:`_sample_direct`)."""
    H = comp_off.size - 1
    U = W_all.shape[1] - 2
    # upper bounds of the output: every observation new, every row present
    P_max, n_cap, e_cap, c_max = child_bounds(comp_off, births.size, n_chains, chain_length)
    scratch = problem_scratch(P_max, c_max)  # every component's run, one after another
    child_comp, child_cost, child_off, child_entry, child_meas = new_children(n_cap, e_cap)
    sweeps = np.zeros(H, dtype=np.int64)
    n_rows = np.zeros(H, dtype=np.int64)
    mark = np.zeros(U, dtype=np.bool_)
    rows = np.empty(P_max, dtype=np.int64)
    cols = np.empty(U, dtype=np.int64)
    chain_rules = engine_rules(rules)
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
        prefix = M > _PREFIX_FROM and M > 2 * P
        if prefix:
            S, next_pos = prefix_sums(W)
        else:
            S = np.zeros((P, 1))
            next_pos = np.zeros((P, 1), dtype=np.int64)
        data = PrefixData(W=W, cc=cc, S=S, next_pos=next_pos, random_scan=rules.random_scan)
        if prefix:
            n_u, obs = _run_prefix(data, alloc_work_prefix(data, np.int64(1)), zkeys, x0, base[h],
                                   n_chains[h], chain_length[h], chain_rules, scratch)
        else:
            n_u, obs = _run_direct(data, alloc_work(data, np.int64(1)), zkeys, x0, base[h],
                                   n_chains[h], chain_length[h], chain_rules, scratch)
        states = problem_states(scratch, P, n_u)
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
    return cut_children(child_comp, child_cost, child_off, child_entry, child_meas, n_out,
                        e_out) + (sweeps, n_rows)


#: :func:`sample_components`' loop, either draw as a component needs it.
_sample_any = instantiate(_sample, "sample_components", {})
#: The loop of a scan of at most ``M_DIRECT`` measurements: the prefix-sum branch is never
#: taken (``M <= U <= M_DIRECT``), and binds the direct runner, so it compiles nothing more.
_sample_direct = instantiate(_sample, "sample_components_direct",
                             {"_PREFIX_FROM": np.iinfo(np.int64).max,
                              "_run_prefix": _run_direct, "alloc_work_prefix": alloc_work})


@jit()
def merge_children(child_off, child_ids, log_w):
    """Group children with the same track set; sum their weights in log space.

    Parameters
    ----------
    child_off : ndarray of int64, shape (N + 1,)
        CSR offsets of the children's track lists.
    child_ids : ndarray of int64
        New track-table entries of every child, each child's distinct. Sorted in place
        within each child (insertion sort: linear in the entries when they come nearly in
        order, as the scan's rows put them, births first).
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
    >>> ids = np.array([4, 0, 1, 0, 4])
    >>> g, lw, first = merge_children(np.array([0, 2, 3, 5]), ids, np.log([0.2, 0.3, 0.5]))
    >>> g.tolist(), np.exp(lw).round(3).tolist(), first.tolist(), ids.tolist()
    ([0, 1, 0], [0.7, 0.3], [0, 1], [0, 4, 1, 0, 4])
    """
    N = child_off.size - 1
    width = 0
    for n in range(N):
        width = max(width, child_off[n + 1] - child_off[n])
    # A child's key in the engine's unique set: its number of tracks, then its entries, padded
    # with -1 (entries index the scan's track table, far below 2**31).
    groups = unique_set(width + 1, max(N, 1))
    x = np.empty(width + 1, dtype=np.int32)
    group = np.empty(N, dtype=np.int64)
    group_log_w = np.empty(N)
    first = np.empty(N, dtype=np.int64)
    G = 0
    for n in range(N):
        a = child_off[n]
        b = child_off[n + 1]
        for q in range(a + 1, b):  # insertion sort of the child's entries
            v = child_ids[q]
            r = q - 1
            while r >= a and child_ids[r] > v:
                child_ids[r + 1] = child_ids[r]
                r -= 1
            child_ids[r + 1] = v
        key = mix64(np.uint64(b - a + 1))
        x[0] = b - a
        for q in range(a, b):
            key = mix64(key ^ np.uint64(child_ids[q] + 1))
            x[q - a + 1] = child_ids[q]
        for q in range(b - a + 1, width + 1):
            x[q] = -1
        g, new = add_state(groups, x, key, G)
        group[n] = g
        if new:
            group_log_w[G] = log_w[n]
            first[G] = n
            G += 1
        else:
            group_log_w[g] = _logaddexp(group_log_w[g], log_w[n])
    return group, group_log_w[:G].copy(), first[:G].copy()


@jit()
def mark_reachable(parent, live):
    """Nodes of the history forest reachable from the nodes ``live`` (``parent −1``: a root).

    Parameters
    ----------
    parent : ndarray of int64, shape (N,)
        Parent of every node, ``-1`` for a root.
    live : ndarray of int64
        The nodes live tracks use.

    Returns
    -------
    ndarray of bool, shape (N,)
        Whether each node is ``live`` or an ancestor of one.

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

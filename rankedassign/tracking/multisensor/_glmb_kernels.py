"""Compiled kernels of the multi-sensor δ-GLMB filter: every component's problem, sampled in one
call.

The multi-sensor δ-GLMB update (Vo, Vo & Beard 2019; ``../shared/spec/glmb.md`` §6) solves one
multi-sensor ranked-assignment problem per prior component. Building each as a
:class:`~rankedassign.multisensor.MultiSensorProblem` and calling the public samplers costs a
few hundred microseconds of Python per component, more than its chains, so the chain
truncations (:class:`~rankedassign.tracking.OriginalGibbs`,
:class:`~rankedassign.tracking.ShortChainGibbs`) run here in one compiled call per scan:

1. :func:`component_columns` lists the rows (the birth tracks, then the component's entries)
   and, per sensor, the columns (the gated measurements some row gates) of one component;
2. :func:`sample_components` gathers each problem's kernel data
   (:class:`~rankedassign.multisensor.prepare.MultiSensorData`) from the scan's shared
   per-entry terms, runs the chains and emits every unique assignment as a child (its parent,
   its cost, and the (entry, flat tuple index) of every row alive after the scan).

The chains are the engine's: :func:`sample_components` hands each component's problem to
:func:`rankedassign.engine._kernels.make_problem_runner`'s compiled run, compiled for the
multi-sensor kind's sweep (:func:`rankedassign.multisensor._kernels.sweep`), which is the
sequential run of :func:`rankedassign.sample_short_chains` (the original sampler is one chain
without rules): the same SplitMix64 stream per chain, the same start state (every row missed by
every sensor), the same unique set in discovery order. No chain loop or hash table is written
here: this module keeps only what is δ-GLMB, the gather and the children.

Bit for bit. The filter's component-by-component path (``truncate`` on the component's
:class:`~rankedassign.multisensor.MultiSensorProblem`) and this kernel give the same children:
the shifted weights of :func:`rankedassign.multisensor.prepare.prepare_data` are row-wise
(``exp(log − max)`` over one row's candidates, whose finite entries all lie among its
component's columns), so the filter computes them once per scan for every entry with the same
numpy operations and this kernel only gathers them; a child's cost is
``−Σ_n ln η_n(γ_n)`` summed in numpy's pairwise order (:func:`pairwise_sum`), as
:func:`rankedassign.multisensor.prepare.assignment_costs` sums it.

References
----------
.. [1] B.-N. Vo, B.-T. Vo, M. Beard, "Multi-Sensor Multi-Object Tracking with the Generalized
   Labeled Multi-Bernoulli Filter", IEEE Trans. Signal Process. 67(23):5952-5967, 2019.
.. [2] A. Trezza, D. J. Bucci Jr., P. K. Varshney, "On Gibbs Sampling Architecture for
   Labeled Random Finite Sets Multi-Object Tracking", arXiv:2306.15135, 2023.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ...engine._kernels import make_problem_runner, problem_scratch, problem_states
from ...multisensor._kernels import alloc_work, reset_work, sweep
from ...multisensor.prepare import METHOD_CODES, MultiSensorData
from ...numba_options import jit
from .._glmb_gather import child_bounds, component_rows, cut_children, new_children

__all__ = ["ScanTerms", "component_columns", "pairwise_sum", "sample_components"]

#: ``method`` codes of :class:`~rankedassign.multisensor.prepare.MultiSensorData` this kernel
#: gathers (the multi-sensor kind's ``METHOD_CODES``).
EXACT, MM = METHOD_CODES["exact"], METHOD_CODES["mm"]


class ScanTerms(NamedTuple):
    """The scan's shared terms, as :func:`sample_components` reads them.

    ``T`` entries of the predicted table, ``V`` sensors, ``U_v`` gated measurements of sensor
    ``v``, ``N`` measurement tuples over all entries.

    Attributes
    ----------
    comp_off, comp_tracks : ndarray of int64, shapes (H + 1,), (E,)
        Track-table entries of every component (CSR).
    births : ndarray of int64, shape (B,)
        Entries of the scan's birth tracks (rows of every component, first).
    gated : ndarray of bool, shape (T, sum_v U_v)
        Every sensor's gate, side by side: sensor ``v`` in columns ``goff[v]:goff[v + 1]``.
    goff : ndarray of int64, shape (V + 1,)
        Offsets of the sensors in ``gated``.
    tup_off : ndarray of int64, shape (T + 1,)
        CSR offsets of every entry's tuples (the all-missed tuple first).
    tup_g : ndarray of int64, shape (N, V)
        Per sensor 0 (missed) or ``1 +`` the index of the gated measurement.
    tup_la : ndarray of float64, shape (N,)
        ``ln η`` of every tuple.
    tup_w : ndarray of float64, shape (N,) or (0,)
        ``method = EXACT``: the shifted weight ``exp(ln η − m_t)`` of every tuple, ``m_t`` the
        largest of its entry's ``ln η`` (dead included), 0 where ``ln η = −inf``.
    log_dead : ndarray of float64, shape (T,)
        ``ln η(−1)``.
    dead_w : ndarray of float64, shape (T,) or (0,)
        ``method = EXACT``: the shifted weight of dead.
    log_p : ndarray of float64, shape (T,)
        ``ln s`` of MM (survival or birth probability).
    toff : ndarray of int64, shape (V + 1,)
        Offsets of the sensors in ``lth`` and ``Th``: sensor ``v`` in columns
        ``toff[v]:toff[v + 1]`` (``U_v + 1`` of them, missed first).
    lth, Th : ndarray of float64, shape (T, sum_v (U_v + 1))
        ``method = MM``: ``ln θ^(v)`` and its shifted weight ``exp(ln θ − max_j ln θ)`` per
        entry and sensor (0 where ``ln θ = −inf``).
    Ea, Ed : ndarray of float64, shape (T,)
        ``method = MM``: the shifted alive prefactor and dead weight of the exclusion variant
        (:class:`~rankedassign.multisensor.prepare.MultiSensorData`).
    strides : ndarray of int64, shape (V,)
        Strides of the scan's flat tuple index over ``(U_1 + 1, ..., U_V + 1)`` (C order).
    """

    comp_off: np.ndarray
    comp_tracks: np.ndarray
    births: np.ndarray
    gated: np.ndarray
    goff: np.ndarray
    tup_off: np.ndarray
    tup_g: np.ndarray
    tup_la: np.ndarray
    tup_w: np.ndarray
    log_dead: np.ndarray
    dead_w: np.ndarray
    log_p: np.ndarray
    toff: np.ndarray
    lth: np.ndarray
    Th: np.ndarray
    Ea: np.ndarray
    Ed: np.ndarray
    strides: np.ndarray


#: The engine's one-call run of a problem (its chains, unique set and stall and stale rules),
#: compiled for the multi-sensor kind's sweep.
_run = make_problem_runner("msglmb_component", reset_work, sweep)


@jit()
def _block_sum(x, lo, n):
    """numpy's pairwise sum of ``x[lo:lo + n]`` for ``n <= 128`` (no further split).

    Parameters
    ----------
    x : ndarray of float64, shape (L,)
        The values.
    lo, n : int
        The run ``x[lo:lo + n]``, ``n <= 128``.

    Returns
    -------
    float
        The sum: fewer than 8 terms one after another from 0, else eight interleaved partial
        sums combined as a tree, then the rest in turn.
    """
    if n < 8:
        res = 0.0
        for i in range(lo, lo + n):
            res += x[i]
        return res
    r0, r1, r2, r3 = x[lo], x[lo + 1], x[lo + 2], x[lo + 3]
    r4, r5, r6, r7 = x[lo + 4], x[lo + 5], x[lo + 6], x[lo + 7]
    i = 8
    while i < n - (n % 8):
        r0 += x[lo + i]
        r1 += x[lo + i + 1]
        r2 += x[lo + i + 2]
        r3 += x[lo + i + 3]
        r4 += x[lo + i + 4]
        r5 += x[lo + i + 5]
        r6 += x[lo + i + 6]
        r7 += x[lo + i + 7]
        i += 8
    res = ((r0 + r1) + (r2 + r3)) + ((r4 + r5) + (r6 + r7))
    while i < n:
        res += x[lo + i]
        i += 1
    return res


@jit()
def pairwise_sum(x, lo, n):
    """``x[lo] + ... + x[lo + n − 1]`` in numpy's pairwise order (``np.add.reduce``).

    numpy sums a contiguous run of float64 by blocks: fewer than 8 terms one after another from
    0; up to 128 in eight interleaved partial sums, combined as a tree, then the rest in turn
    (:func:`_block_sum`); longer runs as the sum of two halves (the first a multiple of 8
    long), each summed the same way. Summing in the same order gives the same bits as
    ``np.sum`` of the same values. The halving is walked with an explicit stack: numba's
    on-disk cache cannot link a kernel that calls itself.

    Parameters
    ----------
    x : ndarray of float64, shape (L,)
        The values.
    lo, n : int
        The run ``x[lo:lo + n]``.

    Returns
    -------
    float
        The sum.

    Examples
    --------
    >>> import numpy as np
    >>> x = np.random.default_rng(0).standard_normal(600) * 1e3
    >>> all(pairwise_sum(x, 0, n) == x[:n].sum() for n in range(600))
    True
    """
    if n <= 128:
        return _block_sum(x, lo, n)
    # a node waits for its first half (stage 1), then for its second (stage 2)
    s_lo = np.empty(64, dtype=np.int64)
    s_n = np.empty(64, dtype=np.int64)
    s_stage = np.empty(64, dtype=np.int64)
    s_first = np.empty(64)
    top = 0
    s_lo[0], s_n[0], s_stage[0] = lo, n, 0
    val = 0.0
    while True:
        cl, cn, stage = s_lo[top], s_n[top], s_stage[top]
        if stage == 0 and cn <= 128:
            val = _block_sum(x, cl, cn)
            top -= 1
        elif stage == 0 or stage == 1:
            n2 = cn // 2
            n2 -= n2 % 8
            if stage == 1:
                s_first[top] = val
            s_stage[top] = stage + 1
            top += 1
            s_lo[top] = cl if stage == 0 else cl + n2
            s_n[top] = n2 if stage == 0 else cn - n2
            s_stage[top] = 0
            continue
        else:
            val = s_first[top] + val
            top -= 1
        if top < 0:
            return val


@jit()
def component_columns(h, terms, mark, rows, cols, ncol):
    """Rows and per-sensor columns of component ``h``'s problem; returns ``P``.

    Parameters
    ----------
    h : int
        Component.
    terms : ScanTerms
        The scan's terms (reads ``comp_off``, ``comp_tracks``, ``births``, ``gated``,
        ``goff``).
    mark : ndarray of bool, shape (sum_v U_v,)
        Work space, all False (left all False).
    rows : ndarray of int64
        Filled with the ``P`` rows: the births, then the component's entries in their order.
    cols : ndarray of int64, shape (V, max_v U_v)
        ``cols[v, :ncol[v]]`` filled with sensor ``v``'s columns: its gated measurements (an
        index into the sensor's gated list) some row gates, increasing.
    ncol : ndarray of int64, shape (V,)
        Filled with ``M_v``.

    Returns
    -------
    int
        ``P``.

    Examples
    --------
    >>> import numpy as np
    >>> e = np.empty(0, np.int64)
    >>> gated = np.array([[1, 0, 0, 1], [0, 1, 0, 0]], dtype=bool)   # U = (2, 2)
    >>> terms = ScanTerms(np.array([0, 1]), np.array([1]), np.array([0]), gated,
    ...                   np.array([0, 2, 4]), *([e] * 13))
    >>> rows, cols, ncol = np.empty(2, np.int64), np.empty((2, 2), np.int64), np.empty(2, np.int64)
    >>> P = component_columns(0, terms, np.zeros(4, bool), rows, cols, ncol)
    >>> P, rows.tolist(), cols[0, :ncol[0]].tolist(), cols[1, :ncol[1]].tolist()
    (2, [0, 1], [0, 1], [1])
    """
    goff = terms.goff
    P = component_rows(h, terms.comp_off, terms.comp_tracks, terms.births, terms.gated, mark,
                       rows)
    for v in range(goff.size - 1):
        m = 0
        for j in range(goff[v], goff[v + 1]):
            if mark[j]:
                cols[v, m] = j - goff[v]
                m += 1
                mark[j] = False
        ncol[v] = m
    return P


@jit(inline="always")
def _scatter_tuples(out, i, values, r, tup_off, tup_g, local, strides):
    """``out[i, t] = values[q]`` for every tuple ``q`` of entry ``r``, ``t`` its offset in the
    component's tuple axes.

    Parameters
    ----------
    out : ndarray of float64, shape (P, T_c)
        The component's per-row tuple values (``ln η`` or the shifted weights).
    i : int
        The row.
    values : ndarray of float64, shape (N,)
        The scan's value of every tuple.
    r : int
        The row's entry.
    tup_off, tup_g : ndarray of int64
        As in :class:`ScanTerms`.
    local : ndarray of int64, shape (V, max_v U_v + 1)
        The component's local column (``1 +`` its position, 0 missed) of every sensor's
        gated measurement ``1 + j`` (0 missed).
    strides : ndarray of int64, shape (V,)
        Strides of the component's tuple axes.
    """
    for q in range(tup_off[r], tup_off[r + 1]):
        off = 0
        for v in range(strides.size):
            off += local[v, tup_g[q, v]] * strides[v]
        out[i, off] = values[q]


@jit()
def sample_components(terms, method, random_scan, n_chains, chain_length, rules, keys, zkeys):
    """Run the chain truncation of every component's multi-sensor problem; return the children.

    Parameters
    ----------
    terms : ScanTerms
        The scan's shared terms.
    method : int
        The row conditional: ``EXACT`` (0) or ``MM`` (1), the multi-sensor kind's codes.
    random_scan : bool
        Random instead of systematic row order.
    n_chains, chain_length : ndarray of int64, shape (H,)
        Budget of every component: chains and sweeps per chain (0 chains: the start state
        only).
    rules : Rules
        The engine's stall and stale rules (:class:`rankedassign.engine._kernels.Rules`).
    keys : ndarray of uint64, shape (H,)
        Base key of every component's streams (chain ``c``: ``chain_state(keys[h], c)``).
    zkeys : ndarray of uint64, shape (L, K)
        Zobrist keys, ``L >= P V`` and ``K >= max_v M_v + 2`` for every problem.

    Returns
    -------
    child_comp : ndarray of int64, shape (N,)
        Parent component of every child, children of a component in discovery order (the
        start state first).
    child_cost : ndarray of float64, shape (N,)
        ``−Σ_n ln η_n(γ_n)`` (summed as numpy sums it).
    child_off : ndarray of int64, shape (N + 1,)
        CSR offsets of the rows alive after the scan (``γ_n ≠ −1``).
    child_entry : ndarray of int64
        Their entries.
    child_meas : ndarray of int64
        Their tuples: the scan's flat tuple index (``terms.strides``) minus 1 (``−1``: missed
        by every sensor).
    sweeps : ndarray of int64, shape (H,)
        Observations (full sweeps) of every component.
    n_rows : ndarray of int64, shape (H,)
        Rows of every component's problem.

    Notes
    -----
    Component ``h``'s problem is the one the filter's component-by-component path builds: rows
    the births then its entries; per sensor the columns its rows gate; ``ln η`` of every tuple
    of its rows (``−inf`` elsewhere); for ``MM`` the factors ``ln s`` and ``ln θ^(v)`` of those
    columns. Each chain ``c`` starts with every row missed by every sensor and the stream
    ``chain_state(keys[h], c)``; a component without rows, or with 0 chains, keeps that start
    state alone (no sweep).
    """
    H = terms.comp_off.size - 1
    V = terms.goff.size - 1
    B = terms.births.size
    U = terms.gated.shape[1]
    Umax = 0
    for v in range(V):
        Umax = max(Umax, terms.goff[v + 1] - terms.goff[v])
    P_max, n_cap, e_cap, c_max = child_bounds(terms.comp_off, B, n_chains, chain_length)
    scratch = problem_scratch(max(P_max * V, 1), c_max)
    child_comp, child_cost, child_off, child_entry, child_meas = new_children(n_cap, e_cap)
    sweeps = np.zeros(H, dtype=np.int64)
    n_rows = np.zeros(H, dtype=np.int64)
    mark = np.zeros(U, dtype=np.bool_)
    rows = np.empty(max(P_max, 1), dtype=np.int64)
    cols = np.empty((V, max(Umax, 1)), dtype=np.int64)
    ncol = np.empty(V, dtype=np.int64)
    # global -> local column of every sensor: 0 missed, 1 + the column's position
    local = np.zeros((V, Umax + 1), dtype=np.int64)
    n_meas = np.empty(V, dtype=np.int64)
    strides = np.empty(V, dtype=np.int64)
    lw = np.empty(max(P_max, 1))
    tup_off, tup_g, tup_la = terms.tup_off, terms.tup_g, terms.tup_la
    n_out = 0
    e_out = 0
    for h in range(H):
        P = component_columns(h, terms, mark, rows, cols, ncol)
        n_rows[h] = P
        if P == 0 or n_chains[h] == 0:
            # the chains' start state alone: every row missed by every sensor
            for i in range(P):
                lw[i] = tup_la[tup_off[rows[i]]]
            child_comp[n_out] = h
            child_cost[n_out] = -pairwise_sum(lw, 0, P)
            for i in range(P):
                child_entry[e_out] = rows[i]
                child_meas[e_out] = -1
                e_out += 1
            n_out += 1
            child_off[n_out] = e_out
            continue
        # the component's tuple axes (M_v + 1, C order) and its columns' local indices
        Tc = 1
        K = 1
        for v in range(V - 1, -1, -1):
            n_meas[v] = ncol[v]
            strides[v] = Tc
            Tc *= ncol[v] + 1
            K = max(K, ncol[v] + 1)
            for m in range(ncol[v]):
                local[v, cols[v, m] + 1] = m + 1
        # ln η of every tuple of the rows (−inf: a tuple outside the rows' gates)
        la = np.full((P, Tc), -np.inf)
        ld = np.empty(P)
        for i in range(P):
            ld[i] = terms.log_dead[rows[i]]
            _scatter_tuples(la, i, tup_la, rows[i], tup_off, tup_g, local, strides)
        if method == EXACT:
            Wd = np.empty(P)
            Wa = np.zeros((P, Tc))
            for i in range(P):
                Wd[i] = terms.dead_w[rows[i]]
                _scatter_tuples(Wa, i, terms.tup_w, rows[i], tup_off, tup_g, local, strides)
            Th = np.zeros((P, V, K))
            lth = np.full((P, V, K), -np.inf)
            las = np.zeros(P)
            Ea = np.zeros(P)
            Ed = np.zeros(P)
            la_data = la
        else:
            Wd = np.zeros(P)
            Wa = np.zeros((P, 0))
            la_data = np.zeros((P, 0))
            Th = np.zeros((P, V, K))
            lth = np.full((P, V, K), -np.inf)
            las = np.empty(P)
            Ea = np.empty(P)
            Ed = np.empty(P)
            for i in range(P):
                r = rows[i]
                las[i] = terms.log_p[r]
                Ea[i] = terms.Ea[r]
                Ed[i] = terms.Ed[r]
                for v in range(V):
                    t0 = terms.toff[v]
                    lth[i, v, 0] = terms.lth[r, t0]
                    Th[i, v, 0] = terms.Th[r, t0]
                    for m in range(ncol[v]):
                        lth[i, v, m + 1] = terms.lth[r, t0 + cols[v, m] + 1]
                        Th[i, v, m + 1] = terms.Th[r, t0 + cols[v, m] + 1]
        for v in range(V):
            for m in range(ncol[v]):
                local[v, cols[v, m] + 1] = 0
        data = MultiSensorData(
            method=np.int64(method), random_scan=random_scan, P=np.int64(P), V=np.int64(V),
            n_meas=n_meas, strides=strides, Wd=Wd, ld=ld, Wa=Wa, la=la_data, Th=Th, lth=lth,
            las=las, Ea=Ea, Ed=Ed, qdead=np.zeros(P))
        L = P * V
        x0 = np.ones(L, dtype=np.int32)  # every row missed by every sensor (γ + 1 = 1)
        n_u, obs = _run(data, alloc_work(data, np.int64(1)), zkeys, x0, keys[h], n_chains[h],
                        chain_length[h], rules, scratch)
        states = problem_states(scratch, L, n_u)
        sweeps[h] = obs
        for u in range(n_u):
            # −Σ_n ln η_n(γ_n), in the order of assignment_costs (dead rows: ln η(−1))
            for i in range(P):
                if states[u, i * V] == 0:
                    lw[i] = ld[i]
                else:
                    off = 0
                    for v in range(V):
                        off += (states[u, i * V + v] - 1) * strides[v]
                    lw[i] = la[i, off]
            child_comp[n_out] = h
            child_cost[n_out] = -pairwise_sum(lw, 0, P)
            # the rows alive after the scan: their entry and the scan's flat tuple index
            for i in range(P):
                if states[u, i * V] == 0:
                    continue
                flat = 0
                for v in range(V):
                    s = states[u, i * V + v]
                    if s >= 2:
                        flat += (cols[v, s - 2] + 1) * terms.strides[v]
                child_entry[e_out] = rows[i]
                child_meas[e_out] = flat - 1
                e_out += 1
            n_out += 1
            child_off[n_out] = e_out
    return cut_children(child_comp, child_cost, child_off, child_entry, child_meas, n_out,
                        e_out) + (sweeps, n_rows)

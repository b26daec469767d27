"""The gather of the δ-GLMB filters' compiled all-component paths, written once (numba).

Both δ-GLMB filters solve one problem per prior component in one compiled call per scan
(:mod:`rankedassign.tracking.single._glmb_kernels`,
:mod:`rankedassign.tracking.multisensor._glmb_kernels`). What a component's problem is does not
depend on the sensor count: its rows are the scan's birth tracks, then the component's entries
of the predicted track table, and its columns the gated measurements some row gates
(:func:`component_rows`); its children are written into flat arrays sized for the worst case,
every observation new and every row alive (:func:`child_bounds`, :func:`new_children`), and
cut to what was written (:func:`cut_children`). The per-kind part, the problem's weights and
its children's measurements, stays in each kernel module.
"""

from __future__ import annotations

import numpy as np

from ..numba_options import jit

__all__ = ["component_rows", "child_bounds", "new_children", "cut_children"]


@jit(inline="always")
def component_rows(h, comp_off, comp_tracks, births, gated, mark, rows):
    """The rows of component ``h``'s problem, and the gated columns they gate; returns ``P``.

    Parameters
    ----------
    h : int
        Component.
    comp_off, comp_tracks : ndarray of int64, shapes (H + 1,), (N,)
        Track-table entries of every component (CSR).
    births : ndarray of int64, shape (B,)
        Entries of the birth tracks of the scan (rows of every component).
    gated : ndarray of bool, shape (T, U)
        Gate of every entry against the scan's gated measurements (every sensor's side by
        side for the multi-sensor filter).
    mark : ndarray of bool, shape (U,)
        All False on entry; ``mark[j]`` set for every column ``j`` some row gates (the caller
        lists them and clears it).
    rows : ndarray of int64
        Filled with the ``P`` rows: the births first, then the component's entries in their
        order.

    Returns
    -------
    int
        ``P``.
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
    return P


@jit(inline="always")
def child_bounds(comp_off, B, n_chains, chain_length):
    """Sizes of a chain truncation's children over every component, for the worst case.

    Parameters
    ----------
    comp_off : ndarray of int64, shape (H + 1,)
        CSR offsets of every component's entries.
    B : int
        Birth tracks (rows of every component).
    n_chains, chain_length : ndarray of int64, shape (H,)
        Every component's budget: chains and sweeps per chain.

    Returns
    -------
    P_max : int
        The most rows of a problem (at least ``B``).
    n_cap : int
        Children if every observation of every chain is new (plus each start state).
    e_cap : int
        Their rows if every row is alive.
    c_max : int
        The most children of one component (at least 1).
    """
    P_max = B
    # int64 from the start: a literal's type would reach the callers' calls (this function
    # is written into them) and compile a second signature of each callee
    n_cap = np.int64(0)
    e_cap = np.int64(0)
    c_max = np.int64(1)
    for h in range(comp_off.size - 1):
        P_h = B + comp_off[h + 1] - comp_off[h]
        P_max = max(P_max, P_h)
        c = n_chains[h] * chain_length[h] + 1
        n_cap += c
        e_cap += c * P_h
        c_max = max(c_max, c)
    return P_max, n_cap, e_cap, c_max


@jit(inline="always")
def new_children(n_cap, e_cap):
    """Room for ``n_cap`` children with ``e_cap`` rows in all.

    Parameters
    ----------
    n_cap, e_cap : int
        Children and rows.

    Returns
    -------
    child_comp, child_cost, child_off, child_entry, child_meas : ndarray
        Parent (int64, ``n_cap``), cost (float64, ``n_cap``), CSR offsets of the rows (int64,
        ``n_cap + 1``, zero), and each row's entry and measurement (int64, ``e_cap``).
    """
    return (np.empty(n_cap, dtype=np.int64), np.empty(n_cap),
            np.zeros(n_cap + 1, dtype=np.int64), np.empty(e_cap, dtype=np.int64),
            np.empty(e_cap, dtype=np.int64))


@jit(inline="always")
def cut_children(child_comp, child_cost, child_off, child_entry, child_meas, n_out, e_out):
    """Copies of the ``n_out`` children written, and of their ``e_out`` rows.

    Parameters
    ----------
    child_comp, child_cost, child_off, child_entry, child_meas : ndarray
        As :func:`new_children` made them, filled up to ``n_out`` and ``e_out``.
    n_out, e_out : int
        Children and rows written.

    Returns
    -------
    tuple of ndarray
        The five arrays cut to length (``child_off`` to ``n_out + 1``).
    """
    return (child_comp[:n_out].copy(), child_cost[:n_out].copy(),
            child_off[:n_out + 1].copy(), child_entry[:e_out].copy(),
            child_meas[:e_out].copy())

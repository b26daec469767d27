"""Compiled shortest-augmenting-path LSAP: the solver behind Murty and the DP's rescaling.

Conventions
-----------
* ``C`` is the ``(P, N)`` cost matrix in the paper's layout, ``N = M + 2P``; ``+inf`` marks a
  missing edge. No "big number" stands in for ``+inf``: an infinite entry is simply never
  relaxed, so arbitrarily large (and negative) finite costs stay exact.
* The assignment state is ``(u, v, col4row, row4col)``: row and column duals and the matching
  (``UNASSIGNED`` where a row or column has no partner).
* One augmentation runs in named phases, each a small compiled helper: reset the search
  (:func:`reset_search`), scan a row (:func:`relax_row`), pick the closest column
  (:func:`closest_column`), open the dummy-row hub of a warm start (:func:`open_hub`), update
  the duals (:func:`update_duals`) and flip the path (:func:`flip_path`).
"""

from __future__ import annotations

from collections import namedtuple

import numpy as np

from rankedassign.numba_options import jit

__all__ = [
    "COLD",
    "HUB",
    "UNASSIGNED",
    "SearchWorkspace",
    "lsap_kernel",
    "new_workspace",
    "sap_augment",
]

UNASSIGNED = -1  # col4row / row4col entry of a row / column without a partner
COLD = -1  # ``freed`` of a cold augmentation: the path ends at the first free column
HUB = -2  # path marker: the column was reached through a dummy row (rectangular slack)

#: Scratch arrays of one shortest-path search (contents are meaningless between calls).
#: ``d, path, scanned_c, remaining`` have one entry per column, ``scanned_r`` one per row.
SearchWorkspace = namedtuple("SearchWorkspace", ["d", "path", "scanned_r", "scanned_c",
                                                 "remaining"])


@jit()
def new_workspace(P, N):
    """A :data:`SearchWorkspace` for a ``(P, N)`` matrix."""
    return SearchWorkspace(np.empty(N), np.empty(N, dtype=np.int64), np.empty(P, dtype=np.bool_),
                           np.empty(N, dtype=np.bool_), np.empty(N, dtype=np.int64))


@jit()
def reset_search(ws, col_active):
    """Clear the workspace; list the active columns in ``ws.remaining``; return their number."""
    n_rem = 0
    for j in range(ws.d.shape[0]):
        ws.d[j] = np.inf
        ws.path[j] = UNASSIGNED
        ws.scanned_c[j] = False
        if col_active[j]:
            ws.remaining[n_rem] = j
            n_rem += 1
    for i in range(ws.scanned_r.shape[0]):
        ws.scanned_r[i] = False
    return n_rem


@jit()
def relax_row(C, i, min_val, u, v, ws, n_rem):
    """Scan row ``i`` at distance ``min_val``.

    ``d[j] = min(d[j], min_val + C[i, j] - u[i] - v[j])`` over the remaining columns.
    """
    ws.scanned_r[i] = True
    ui = u[i]
    for it in range(n_rem):
        j = ws.remaining[it]
        cij = C[i, j]
        if cij < np.inf:
            r = min_val + (cij - ui - v[j])
            if r < ws.d[j]:
                ws.d[j] = r
                ws.path[j] = i


@jit()
def closest_column(ws, n_rem, freed, row4col):
    """Position in ``ws.remaining`` of the unscanned column closest to the root (-1: none).

    Ties prefer a column that ends the path (the freed column of a warm start, a free column
    of a cold one): shorter paths, deterministic.
    """
    lowest = np.inf
    index = -1
    for it in range(n_rem):
        j = ws.remaining[it]
        dj = ws.d[j]
        if dj < lowest or (
            dj == lowest and index >= 0 and (j == freed or (freed == COLD and row4col[j] < 0))
        ):
            lowest = dj
            index = it
    if lowest == np.inf:
        return -1
    return index


@jit()
def open_hub(ws, n_rem, min_val, v_free, v, row4col, freed):
    """Reach every column through the dummy rows at once; return the new ``n_rem``.

    The path reached a dummy-held (free) column at ``min_val``: every other dummy-held column
    is reached at ``min_val`` too (scanned now), and every other column ``k`` at
    ``min_val + v_free - v[k]`` (the dummy row's zero-cost edge, reduced).
    """
    it = 0
    while it < n_rem:
        k = ws.remaining[it]
        if row4col[k] < 0 and k != freed:
            ws.d[k] = min_val
            ws.path[k] = HUB
            ws.scanned_c[k] = True
            n_rem -= 1
            ws.remaining[it] = ws.remaining[n_rem]
        else:
            h = min_val + (v_free - v[k])
            if h < ws.d[k]:
                ws.d[k] = h
                ws.path[k] = HUB
            it += 1
    return n_rem


@jit()
def update_duals(root, min_val, u, v, col4row, ws):
    """Dual update after a search that ended at distance ``min_val`` (uses the old matching).

    ``u[i] += min_val - d[col4row[i]]`` on scanned rows (``min_val`` for the root),
    ``v[j] -= min_val - d[j]`` on scanned columns: reduced costs stay ``>= 0`` and become 0
    along the shortest path.
    """
    u[root] += min_val
    for r in range(u.shape[0]):
        if ws.scanned_r[r] and r != root:
            u[r] += min_val - ws.d[col4row[r]]
    for j in range(v.shape[0]):
        if ws.scanned_c[j]:
            v[j] -= min_val - ws.d[j]


@jit()
def flip_path(sink, root, hub_src, col4row, row4col, path):
    """Augment along the shortest path ending at ``sink``, back to ``root``."""
    j = sink
    while True:
        r = path[j]
        if r == HUB:
            row4col[j] = UNASSIGNED  # j is handed to a dummy row: free again
            j = hub_src
            continue
        row4col[j] = r
        prev = col4row[r]
        col4row[r] = j
        if r == root:
            break
        j = prev


@jit()
def sap_augment(C, root, freed, u, v, col4row, row4col, col_active, v_free, ws):
    """One shortest augmenting path (Dijkstra on reduced costs) from the free row ``root``.

    Rectangular LSAP (rows <= columns) viewed as the square problem in which every free
    column is held by a zero-cost dummy row. Invariants on entry: ``C[i, j] - u[i] - v[j] >= 0``
    on every finite edge of an active column, equality on matched edges, and every free active
    column other than ``freed`` has potential ``v_free`` with ``v[j] <= v_free`` for all ``j``
    (the dummy rows' dual feasibility).

    ``freed = COLD`` (as in SciPy's ``linear_sum_assignment``): the path ends at the first free
    column reached. ``freed = c >= 0`` (a warm start after un-assigning the pair ``(root, c)``,
    Miller, Stone & Cox 1997): in the square view ``c`` is the only free column, and any
    dummy-held column ``j`` hops to every column ``k`` at reduced cost ``v_free - v[k] >= 0``
    (the dummy row's edges). All dummy-held columns are reached at the same distance, so the
    first one popped opens that "hub" for all of them at once (:func:`open_hub`).

    Updates ``u, v, col4row, row4col`` in place and returns ``(increase, new_v_free)``;
    ``increase = +inf`` when no augmenting path exists (the subproblem is infeasible; the
    arrays are then left partly updated and must be discarded).
    """
    n_rem = reset_search(ws, col_active)
    min_val = 0.0
    i = root
    sink = -1
    hub_open = False
    hub_src = -1
    while sink < 0:
        if i >= 0:
            relax_row(C, i, min_val, u, v, ws, n_rem)
        index = closest_column(ws, n_rem, freed, row4col)
        if index < 0:
            return np.inf, v_free
        j = ws.remaining[index]
        min_val = ws.d[j]
        ws.scanned_c[j] = True
        n_rem -= 1
        ws.remaining[index] = ws.remaining[n_rem]
        if j == freed:
            sink = j
        elif row4col[j] < 0:
            if freed == COLD:
                sink = j
            else:
                hub_open = True
                hub_src = j
                n_rem = open_hub(ws, n_rem, min_val, v_free, v, row4col, freed)
                i = -1  # no row to scan: the next column comes from the hub's relaxations
        else:
            i = row4col[j]
    update_duals(root, min_val, u, v, col4row, ws)
    new_v_free = v_free
    if hub_open:
        new_v_free = v_free - (min_val - ws.d[hub_src])
    flip_path(sink, root, hub_src, col4row, row4col, ws.path)
    return min_val, new_v_free


@jit()
def lsap_kernel(C):
    """Rectangular LSAP with duals by successive shortest augmenting paths.

    Parameters
    ----------
    C : ndarray, float64, shape (P, N), P <= N
        ``+inf`` = no edge; finite entries may be negative and arbitrarily large.

    Returns
    -------
    ok : bool
        False when no assignment of every row exists.
    col4row : ndarray, int64, shape (P,)
    u, v : ndarray, float64, shapes (P,), (N,)
        Optimal duals: ``C - u - v >= 0`` on finite edges, ``= 0`` on matched edges,
        ``v <= 0`` and ``v = 0`` on unmatched columns; ``sum(u) + sum(v)`` is the optimum.
    """
    P, N = C.shape
    u = np.zeros(P)
    v = np.zeros(N)
    col4row = np.full(P, UNASSIGNED, dtype=np.int64)
    row4col = np.full(N, UNASSIGNED, dtype=np.int64)
    active = np.ones(N, dtype=np.bool_)
    ws = new_workspace(P, N)
    for root in range(P):
        inc, _ = sap_augment(C, root, COLD, u, v, col4row, row4col, active, 0.0, ws)
        if inc == np.inf:
            return False, col4row, u, v
    return True, col4row, u, v

"""Compiled shortest-augmenting-path LSAP on sparse rows: the solver behind Murty and the DP.

Conventions
-----------
* The problem is a :data:`Graph`: the finite entries of a ``(P, N)`` cost matrix, ``P <= N``,
  row by row (CSR). A row of the paper's ``P x (M + 2P)`` layout has at most ``M + 2``
  entries (the measurements, its own missed and its own dead column), fewer when gating
  forbids pairs, so a row scan costs ``O(M + 2)``, not ``O(M + 2P)``. No "big number" stands
  in for ``+inf``: a missing (or temporarily forbidden, ``cost = +inf``) entry is never
  relaxed, so arbitrarily large (and negative) finite costs stay exact.
* The assignment state is a :data:`Matching` ``(u, v, col4row, row4col, active)``: row and
  column duals, the matching (``UNASSIGNED`` where a row or column has no partner) and the
  columns taking part in the (residual) problem.
* Rectangular LSAP is solved as the square problem in which every free column is held by a
  zero-cost dummy row. All free columns share one potential ``v_free`` (the dummy rows' dual
  feasibility: ``v[j] <= v_free`` for every column); it is *implicit*: ``v[j]`` of a free
  column is never read (a search reads ``v_free`` instead), so a search costs
  ``O(touched columns)``, not ``O(N)``.
* One augmentation (:func:`sap_augment`) runs in named phases, each a small compiled helper:
  scan a row (:func:`relax_row`), pick the closest column (:func:`closest_column`), open the
  dummy-row hub of a warm start (:func:`open_hub`), update the duals (:func:`update_duals`),
  flip the path (:func:`flip_path`) and clear the workspace (:func:`clear_search`).
"""

from __future__ import annotations

from collections import namedtuple

import numpy as np

from rankedassign.numba_options import jit

__all__ = [
    "COLD",
    "HUB",
    "UNASSIGNED",
    "Graph",
    "Matching",
    "SearchWorkspace",
    "graph_from_dense",
    "lsap_kernel",
    "new_workspace",
    "sap_augment",
]

UNASSIGNED = -1  # col4row / row4col entry of a row / column without a partner
COLD = -1  # ``freed`` of a cold augmentation: the path ends at the first free column
HUB = -2  # path marker: the column was reached through a dummy row (rectangular slack)

# counters of a SearchWorkspace (entries of ``ws.n``)
N_CAND = 0  # columns reached but not scanned (the Dijkstra frontier, ``ws.cand``)
N_TOUCHED = 1  # columns whose distance was set (cleared afterwards, ``ws.touched``)
N_ROWS = 2  # rows scanned (``ws.rows``)
N_DONE = 3  # columns scanned (``ws.done``)

#: Finite entries of a cost matrix, row by row: row ``i`` owns entries ``ptr[i]:ptr[i + 1]``,
#: entry ``e`` is column ``col[e]`` at cost ``cost[e]`` (set to ``+inf`` to forbid it for a
#: while; ``cost0[e]`` keeps the original); ``pos[i, j]`` is the entry of ``(i, j)`` (-1: none).
Graph = namedtuple("Graph", ["ptr", "col", "cost", "cost0", "pos"])

#: Duals, matching and the active columns of an assignment state (see the module notes).
Matching = namedtuple("Matching", ["u", "v", "col4row", "row4col", "active"])

#: Scratch arrays of one shortest-path search. Between searches every ``d`` is ``+inf`` and
#: every ``scanned_c`` False; :func:`clear_search` restores that in ``O(touched)``.
SearchWorkspace = namedtuple("SearchWorkspace", ["d", "path", "scanned_c", "cand", "touched",
                                                 "done", "rows", "n"])


@jit()
def new_workspace(P, N):
    """A clean :data:`SearchWorkspace` for ``P`` rows and ``N`` columns.

    Parameters
    ----------
    P, N : int
        Rows and columns of the problem.

    Returns
    -------
    SearchWorkspace
        ``d`` (N,) ``+inf``, ``path`` (N,) ``UNASSIGNED``, ``scanned_c`` (N,) False,
        ``cand``, ``touched``, ``done`` (N,) int64 and ``rows`` (P,) int64 uninitialised,
        ``n`` (4,) int64 zero.
    """
    return SearchWorkspace(np.full(N, np.inf), np.full(N, UNASSIGNED, dtype=np.int64),
                           np.zeros(N, dtype=np.bool_), np.empty(N, dtype=np.int64),
                           np.empty(N, dtype=np.int64), np.empty(N, dtype=np.int64),
                           np.empty(P, dtype=np.int64), np.zeros(4, dtype=np.int64))


@jit()
def new_matching(P, N):
    """An empty :data:`Matching`: zero duals, nothing assigned, every column active.

    Parameters
    ----------
    P, N : int
        Rows and columns of the problem.

    Returns
    -------
    Matching
        ``u`` (P,), ``v`` (N,) float64 zero; ``col4row`` (P,), ``row4col`` (N,) int64
        ``UNASSIGNED``; ``active`` (N,) bool True.
    """
    return Matching(np.zeros(P), np.zeros(N), np.full(P, UNASSIGNED, dtype=np.int64),
                    np.full(N, UNASSIGNED, dtype=np.int64), np.ones(N, dtype=np.bool_))


@jit()
def graph_from_dense(C):
    """The :data:`Graph` of the finite entries of ``C`` (columns in increasing order).

    Parameters
    ----------
    C : ndarray of float64, shape (P, N)
        Costs, ``+inf`` for a missing entry (no NaN).

    Returns
    -------
    Graph
        ``ptr`` (P + 1,), ``col`` (E,) int64, ``cost`` and ``cost0`` (E,) float64 (two
        copies), ``pos`` (P, N) int64, with ``E`` the number of finite entries.
    """
    P, N = C.shape
    ptr = np.zeros(P + 1, dtype=np.int64)
    for i in range(P):
        n = 0
        for j in range(N):
            if C[i, j] < np.inf:
                n += 1
        ptr[i + 1] = ptr[i] + n
    col = np.empty(ptr[P], dtype=np.int64)
    cost = np.empty(ptr[P])
    pos = np.full((P, N), -1, dtype=np.int64)
    e = 0
    for i in range(P):
        for j in range(N):
            if C[i, j] < np.inf:
                col[e] = j
                cost[e] = C[i, j]
                pos[i, j] = e
                e += 1
    return Graph(ptr, col, cost, cost.copy(), pos)


@jit()
def _mark_reached(ws, j):
    """Column ``j`` is reached for the first time: onto the frontier and the touched list.

    Parameters
    ----------
    ws : SearchWorkspace
        The search's workspace.
    j : int
        The column.
    """
    ws.cand[ws.n[N_CAND]] = j
    ws.n[N_CAND] += 1
    ws.touched[ws.n[N_TOUCHED]] = j
    ws.n[N_TOUCHED] += 1


@jit()
def relax_row(g, i, min_val, freed, hub_open, v_free, m, ws):
    """Scan row ``i`` at distance ``min_val``: ``d[j] = min(d[j], min_val + C[i,j] - u[i] - v[j])``.

    Only the row's own finite, active, unscanned entries are visited. Once the hub is open
    every dummy-held column is already reached, so those are skipped.

    Parameters
    ----------
    g : Graph
        The problem.
    i : int
        The row.
    min_val : float
        Distance of the row (of the column it was reached through; 0 for the root).
    freed : int
        The freed column of a warm start, or ``COLD``.
    hub_open : bool
        The dummy rows' hub is open (:func:`open_hub`).
    v_free : float
        The free columns' shared potential.
    m : Matching
        Duals and matching.
    ws : SearchWorkspace
        Distances and paths updated; ``i`` appended to the scanned rows.
    """
    ws.rows[ws.n[N_ROWS]] = i
    ws.n[N_ROWS] += 1
    ui = m.u[i]
    d = ws.d
    row4col = m.row4col
    active = m.active
    scanned = ws.scanned_c
    v = m.v
    for e in range(g.ptr[i], g.ptr[i + 1]):
        cij = g.cost[e]
        j = g.col[e]
        if cij == np.inf or not active[j] or scanned[j]:
            continue
        if row4col[j] < 0 and j != freed:  # dummy-held: the shared potential
            if hub_open:
                continue
            dist = min_val + (cij - ui - v_free)
        else:
            dist = min_val + (cij - ui - v[j])
        if dist < d[j]:
            if d[j] == np.inf:
                _mark_reached(ws, j)
            d[j] = dist
            ws.path[j] = i


@jit()
def closest_column(ws, freed, m):
    """Position in ``ws.cand`` of the reached, unscanned column closest to the root (-1: none).

    Ties prefer a column that ends the path (the freed column of a warm start, a free column
    of a cold one), then the lowest column index: shorter paths, and an order that does not
    depend on the order in which columns were reached.

    Parameters
    ----------
    ws : SearchWorkspace
        The search's workspace.
    freed : int
        The freed column, or ``COLD``.
    m : Matching
        The matching (which columns are free).

    Returns
    -------
    int
    """
    index = -1
    lowest = np.inf
    best_ends = False
    best_j = -1
    for it in range(ws.n[N_CAND]):
        j = ws.cand[it]
        dj = ws.d[j]
        ends = j == freed or (freed == COLD and m.row4col[j] < 0)
        if dj < lowest or (dj == lowest and ((ends and not best_ends)
                                             or (ends == best_ends and j < best_j))):
            lowest = dj
            index = it
            best_ends = ends
            best_j = j
    return index


@jit()
def _take(ws, index):
    """Remove ``ws.cand[index]`` from the frontier, mark it scanned, and return it.

    Parameters
    ----------
    ws : SearchWorkspace
        The search's workspace.
    index : int
        Position in the frontier (:func:`closest_column`).

    Returns
    -------
    int
        The column.
    """
    j = ws.cand[index]
    ws.n[N_CAND] -= 1
    ws.cand[index] = ws.cand[ws.n[N_CAND]]
    ws.scanned_c[j] = True
    ws.done[ws.n[N_DONE]] = j
    ws.n[N_DONE] += 1
    return j


@jit()
def open_hub(min_val, v_free, freed, m, ws):
    """The path reached a dummy-held column at ``min_val``: reach every column through it.

    Every other dummy-held column is reached at ``min_val`` too, so it leaves the frontier
    (its potential stays the shared ``v_free``); every matched active column ``k`` and the
    freed column are reached at ``min_val + v_free - v[k]`` (the dummy row's zero-cost edge,
    reduced).

    Parameters
    ----------
    min_val : float
        Distance of the dummy-held column just scanned.
    v_free : float
        The free columns' shared potential.
    freed : int
        The freed column (a warm start).
    m : Matching
        Duals and matching.
    ws : SearchWorkspace
        Frontier, distances and paths updated.
    """
    it = 0
    while it < ws.n[N_CAND]:
        k = ws.cand[it]
        if m.row4col[k] < 0 and k != freed:
            ws.n[N_CAND] -= 1
            ws.cand[it] = ws.cand[ws.n[N_CAND]]
        else:
            it += 1
    d = ws.d
    for q in range(-1, m.col4row.shape[0]):
        k = freed if q < 0 else m.col4row[q]
        if k >= 0 and m.active[k] and not ws.scanned_c[k]:
            dist = min_val + (v_free - m.v[k])
            if dist < d[k]:
                if d[k] == np.inf:
                    _mark_reached(ws, k)
                d[k] = dist
                ws.path[k] = HUB


@jit()
def update_duals(root, min_val, m, ws):
    """Dual update after a search that ended at distance ``min_val`` (uses the old matching).

    ``u[i] += min_val - d[col4row[i]]`` on scanned rows (``min_val`` for the root),
    ``v[j] -= min_val - d[j]`` on scanned columns: reduced costs stay ``>= 0`` and become 0
    along the shortest path.

    Parameters
    ----------
    root : int
        The row the search started from.
    min_val : float
        Length of the shortest augmenting path.
    m : Matching
        Duals updated in place (the matching is read, not changed).
    ws : SearchWorkspace
        The finished search.
    """
    for t in range(ws.n[N_ROWS]):
        r = ws.rows[t]
        if r == root:
            m.u[r] += min_val
        else:
            m.u[r] += min_val - ws.d[m.col4row[r]]
    for t in range(ws.n[N_DONE]):
        j = ws.done[t]
        m.v[j] -= min_val - ws.d[j]


@jit()
def flip_path(sink, root, hub_src, m, path):
    """Augment along the shortest path ending at ``sink``, back to ``root``.

    Parameters
    ----------
    sink : int
        The column the path ends at.
    root : int
        The row it starts from.
    hub_src : int
        The dummy-held column that opened the hub (read when the path passes it).
    m : Matching
        ``col4row`` and ``row4col`` updated in place.
    path : ndarray of int64, shape (N,)
        The row each column was reached from (``HUB``: through the dummy rows).
    """
    j = sink
    while True:
        r = path[j]
        if r == HUB:
            m.row4col[j] = UNASSIGNED  # j is handed to a dummy row: free again
            j = hub_src
            continue
        m.row4col[j] = r
        prev = m.col4row[r]
        m.col4row[r] = j
        if r == root:
            break
        j = prev


@jit()
def clear_search(ws):
    """Restore the clean state of the workspace (``d = +inf``, nothing scanned).

    Parameters
    ----------
    ws : SearchWorkspace
        Cleared in ``O(touched)``; its counters zeroed.
    """
    for t in range(ws.n[N_TOUCHED]):
        j = ws.touched[t]
        ws.d[j] = np.inf
        ws.scanned_c[j] = False
        ws.path[j] = UNASSIGNED
    for t in range(ws.n.shape[0]):
        ws.n[t] = 0


@jit()
def sap_augment(g, root, freed, m, v_free, ws):
    """One shortest augmenting path (Dijkstra on reduced costs) from the free row ``root``.

    Invariants on entry: ``cost - u[i] - v[j] >= 0`` on every finite entry of an active
    column, equality on matched entries, every free active column other than ``freed`` has
    the implicit potential ``v_free``, and ``v[j] <= v_free`` for all ``j``.

    ``freed = COLD`` (as in SciPy's ``linear_sum_assignment``): the path ends at the first free
    column reached. ``freed = c >= 0`` (a warm start after un-assigning the pair ``(root, c)``,
    Miller, Stone & Cox 1997): in the square view ``c`` is the only free column, and any
    dummy-held column ``j`` hops to every column ``k`` at reduced cost ``v_free - v[k] >= 0``
    (the dummy row's edges). All dummy-held columns are reached at the same distance, so the
    first one popped opens that "hub" for all of them at once (:func:`open_hub`).

    Updates ``m`` in place and returns ``(increase, new_v_free)``; ``increase = +inf`` when no
    augmenting path exists (the subproblem is infeasible; ``m`` is then unchanged).

    Parameters
    ----------
    g : Graph
        The problem.
    root : int
        The free row to augment from.
    freed : int
        ``COLD``, or the column un-assigned from ``root`` (a warm start).
    m : Matching
        Duals and matching, updated in place.
    v_free : float
        The free columns' shared potential.
    ws : SearchWorkspace
        Clean on entry and on return.

    Returns
    -------
    increase : float
        The path's length (the cost's increase), or ``+inf``.
    new_v_free : float
        The shared potential after the augmentation.
    """
    min_val = 0.0
    i = root
    sink = -1
    hub_open = False
    hub_src = -1
    hub_dist = 0.0
    while sink < 0:
        if i >= 0:
            relax_row(g, i, min_val, freed, hub_open, v_free, m, ws)
        index = closest_column(ws, freed, m)
        if index < 0:
            clear_search(ws)
            return np.inf, v_free
        j = _take(ws, index)
        min_val = ws.d[j]
        if j == freed:
            sink = j
        elif m.row4col[j] < 0:
            m.v[j] = v_free  # a free column about to be matched: its potential made explicit
            if freed == COLD:
                sink = j
            else:
                hub_open = True
                hub_src = j
                hub_dist = min_val
                open_hub(min_val, v_free, freed, m, ws)
                i = -1  # no row to scan: the next column comes from the hub's relaxations
        else:
            i = m.row4col[j]
    update_duals(root, min_val, m, ws)
    new_v_free = v_free
    if hub_open:
        new_v_free = v_free - (min_val - hub_dist)
    flip_path(sink, root, hub_src, m, ws.path)
    clear_search(ws)
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
    g = graph_from_dense(C)
    m = new_matching(P, N)
    ws = new_workspace(P, N)
    for root in range(P):
        inc, _ = sap_augment(g, root, COLD, m, 0.0, ws)
        if inc == np.inf:
            return False, m.col4row, m.u, m.v
    return True, m.col4row, m.u, m.v

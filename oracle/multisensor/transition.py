"""Exact transition matrices of the multi-sensor Gibbs samplers on tiny problems (spec §6.4).

Built from the mathematics of each row conditional, independently of the sampler code: every
state of ``Gamma`` is listed, each single-row kernel ``K_n`` is written down from its
conditional, and a sweep is the product ``K = K_{o_1} ... K_{o_P}`` over the scan order
(averaged over all ``P!`` orders for a random scan). The stationary law of ``K`` is then
compared with the method's target:

* ``"exact"`` (spec eq. 2.1): ``K_n(gamma, gamma') ∝ eta_n(gamma'_n)`` over dead and
  ``A_n^(1) x ... x A_n^(V)``; target ``pi``.
* ``"mm"`` (spec §3.2, exclusion variant): dead with probability
  ``eta_n(-1) / (eta_n(-1) + s_n^alpha prod_v sum_{j in A_n^(v)} theta_n^(v)(j))``, else each
  component independently ``∝ theta_n^(v)`` on ``A_n^(v)``; target ``pi~`` (spec §3.1 with
  ``s_n -> s_n^alpha``).
* ``"mm-fixed"`` (spec §3.3): as ``"mm"`` with the sums over every ``j`` (no exclusions); no
  closed-form target — its stationary law ``mu`` is the golden value of spec §6.4 (b).
* ``"componentwise"`` (spec §2.4): the collapsed space ``Gamma'`` of spec §1.6 (no dead
  rows); row ``n``'s update is ``K_{n,1} ... K_{n,V}``, each component drawn from its exact
  conditional under ``eta'``; target ``pi'``.

Dense matrices: keep ``|Gamma|`` to about 2 000.

References
----------
.. [1] B.-N. Vo, B.-T. Vo, M. Beard, "Multi-Sensor Multi-Object Tracking with the Generalized
   Labeled Multi-Bernoulli Filter", IEEE Trans. Signal Process. 67(23):5952-5967, 2019.
"""

from __future__ import annotations

import itertools
import math

import numpy as np

from rankedassign.validation import check_choice, check_int

__all__ = ["multisensor_states", "row_kernels", "transition_matrix",
           "stationary_distribution", "target_distribution"]

METHODS = ("exact", "mm", "mm-fixed", "componentwise")


def _alive_tuples(problem):
    return list(itertools.product(*[range(int(m) + 1) for m in problem.n_meas]))


def multisensor_states(problem, *, collapsed=False, limit=5000):
    """Every ``gamma`` of ``Gamma`` (spec eq. 1.2), or of ``Gamma'`` (spec §1.6), in a fixed order.

    Structural feasibility only (all-or-none dead rows, each measurement of each sensor used at
    most once); weights are not looked at.

    Parameters
    ----------
    problem : MultiSensorProblem
        Uses ``n_rows``, ``n_sensors`` and ``n_meas``.
    collapsed : bool
        Leave out dead rows (the collapsed space of the component-wise sampler).
    limit : int
        Refuse (``ValueError``) more states than this.

    Returns
    -------
    ndarray, shape (S, P, V), int64
        Rows ``-1`` (dead) or a tuple of ``0`` (missed) / ``j >= 1`` (measurement ``j``).

    Examples
    --------
    >>> class Stub:
    ...     n_rows, n_sensors, n_meas = 2, 2, (1, 1)
    >>> multisensor_states(Stub()).shape      # spec eq. 1.7: 1 + 2 * 2**2 + 3**2 = 18
    (18, 2, 2)
    """
    limit = check_int(limit, "limit", minimum=1)
    P, V = int(problem.n_rows), int(problem.n_sensors)
    rows = ([] if collapsed else [(-1,) * V]) + _alive_tuples(problem)
    out = []

    def rec(prefix, used):
        if len(prefix) == P:
            out.append(list(prefix))
            if len(out) > limit:
                raise ValueError(f"more than limit={limit} states; the oracle is for tiny "
                                 "problems")
            return
        for r in rows:
            if any(r[v] > 0 and r[v] in used[v] for v in range(V)):
                continue
            rec(prefix + [r], [used[v] | ({r[v]} if r[v] > 0 else set()) for v in range(V)])

    rec([], [set() for _ in range(V)])
    return np.array(out, dtype=np.int64).reshape(len(out), P, V)


def _log_eta(problem, n, row, collapsed):
    """``log eta_n(row)`` (``log eta'_n`` when collapsed)."""
    ld = float(problem.log_eta_dead[n])
    if row[0] < 0:
        return ld
    la = float(np.asarray(problem.log_eta_alive)[(n,) + tuple(row)])
    if collapsed and all(r == 0 for r in row):
        return float(np.logaddexp(ld, la))
    return la


def _normalise(logs):
    """Probabilities from log-weights (exact ratios; all ``-inf`` -> ``None``)."""
    m = max(logs)
    if m == -math.inf:
        return None
    w = [math.exp(lw - m) for lw in logs]
    s = sum(w)
    return [x / s for x in w]


def _free(problem, g, n, v):
    """``A_n^(v)``: missed and the measurements of sensor ``v`` not held by another row."""
    held = {int(g[m][v]) for m in range(len(g)) if m != n and g[m][v] > 0}
    return [0] + [j for j in range(1, int(problem.n_meas[v]) + 1) if j not in held]


def _row_moves(problem, g, n, method, alpha):
    """``[(new row, probability)]`` of row ``n``'s update from state ``g`` (a list of rows)."""
    V = int(problem.n_sensors)
    A = [_free(problem, g, n, v) for v in range(V)]
    if method == "exact":
        cands = [(-1,) * V] + list(itertools.product(*A))
        p = _normalise([_log_eta(problem, n, c, False) for c in cands])
        return [] if p is None else list(zip(cands, p, strict=True))
    if method == "componentwise":
        moves = [(tuple(g[n]), 1.0)]
        for v in range(V):  # K_{n,1} ... K_{n,V}
            nxt = []
            for row, q in moves:
                cands = [row[:v] + (j,) + row[v + 1:] for j in A[v]]
                p = _normalise([_log_eta(problem, n, c, True) for c in cands])
                nxt += [(row, q)] if p is None else [(c, q * pc) for c, pc in zip(cands, p,
                                                                                   strict=True)]
            moves = nxt
        return moves
    # MM: theta_n^(v)(j) and the dead probability (spec §3.2-3.3)
    lth = [np.asarray(problem.log_theta[v], dtype=float)[n] for v in range(V)]
    sums = [A[v] if method == "mm" else range(int(problem.n_meas[v]) + 1) for v in range(V)]
    log_alive = alpha * float(problem.log_s[n])
    for v in range(V):
        log_alive += float(np.logaddexp.reduce([lth[v][j] for j in sums[v]]))
    pd = _normalise([float(problem.log_eta_dead[n]), log_alive])
    per_sensor = [_normalise([lth[v][j] for j in A[v]]) for v in range(V)]
    if pd is None:
        return []
    moves = [((-1,) * V, pd[0])] if pd[0] > 0 else []
    if pd[1] > 0:
        if any(p is None for p in per_sensor):  # alive branch infeasible (mm-fixed): dead
            return [((-1,) * V, 1.0)] if problem.log_eta_dead[n] > -math.inf else []
        for combo in itertools.product(*[range(len(A[v])) for v in range(V)]):
            q = pd[1]
            for v in range(V):
                q *= per_sensor[v][combo[v]]
            moves.append((tuple(A[v][combo[v]] for v in range(V)), q))
    return moves


def _row_kernel(problem, states, index, n, method, alpha):
    S = len(states)
    K = np.zeros((S, S))
    for s in range(S):
        g = [tuple(int(x) for x in r) for r in states[s]]
        moves = _row_moves(problem, g, n, method, alpha)
        if not moves:  # no positive candidate: the row stays as it is
            K[s, s] = 1.0
        for row, q in moves:
            g2 = g[:n] + [tuple(row)] + g[n + 1:]
            K[s, index[tuple(g2)]] += q
    return K


def _check(problem, method, survival_power):
    check_choice(method, "method", METHODS)
    if survival_power not in (1, "V") or isinstance(survival_power, bool):
        raise ValueError(f"unknown survival_power {survival_power!r}; expected one of (1, 'V')")
    return 1 if survival_power == 1 else int(problem.n_sensors)


def row_kernels(problem, method="exact", *, survival_power=1, states=None):
    """The single-row kernels ``K_n`` (one row update each) of a multi-sensor sampler.

    Parameters
    ----------
    problem : MultiSensorProblem
        A tiny problem (uses ``n_rows``, ``n_sensors``, ``n_meas``, ``log_eta_dead``,
        ``log_eta_alive``, and for the MM methods ``log_s`` and ``log_theta``).
    method : {"exact", "mm", "mm-fixed", "componentwise"}
        Which sampler's row conditional to write down (module docstring).
    survival_power : {1, "V"}
        ``alpha`` of the MM alive mass ``s_n^alpha`` (``"V"``: ``alpha = V``); ignored by
        ``"exact"`` and ``"componentwise"``.
    states : ndarray of int64, shape (S, P, V), optional
        The state list the kernels are indexed by (default :func:`multisensor_states`,
        collapsed for ``"componentwise"``).

    Returns
    -------
    kernels : list of P ndarray of float64, shape (S, S)
        ``kernels[n][s, t]`` = probability that updating row ``n`` moves state ``s`` to ``t``;
        each row sums to 1 (a state whose row has no candidate of positive weight stays put).
    states : ndarray of int64, shape (S, P, V)
        The states, in the order of the kernels' rows and columns.

    Raises
    ------
    ValueError
        On an unknown method or survival power, or too many states.

    Examples
    --------
    >>> import numpy as np
    >>> class Stub:
    ...     n_rows, n_sensors, n_meas = 1, 1, (1,)
    ...     log_eta_dead = np.log([1.0]); log_eta_alive = np.log([[1.0, 2.0]])
    >>> kernels, states = row_kernels(Stub())
    >>> len(kernels), kernels[0].shape
    (1, (3, 3))
    """
    alpha = _check(problem, method, survival_power)
    if states is None:
        states = multisensor_states(problem, collapsed=method == "componentwise")
    index = {tuple(tuple(int(x) for x in r) for r in s): i for i, s in enumerate(states)}
    kernels = [_row_kernel(problem, states, index, n, method, alpha)
               for n in range(int(problem.n_rows))]
    return kernels, states


def transition_matrix(problem, method="exact", *, scan="systematic", survival_power=1,
                      states=None):
    """The one-sweep transition matrix of a multi-sensor Gibbs sampler.

    Parameters
    ----------
    problem : MultiSensorProblem
        A tiny problem (uses the arrays named in :mod:`rankedassign.multisensor`).
    method : {"exact", "mm", "mm-fixed", "componentwise"}
        Which sampler's row conditional (module docstring).
    scan : {"systematic", "random"}
        Rows ``0..P-1`` in order, or a uniformly random order per sweep (``K`` averaged over
        the ``P!`` orders).
    survival_power : {1, "V"}
        ``alpha`` of the MM alive mass.
    states : ndarray, shape (S, P, V), optional
        The state list (default :func:`multisensor_states`, collapsed for componentwise).

    Returns
    -------
    K : ndarray, shape (S, S)
        ``K[s, t]`` = probability that one sweep moves state ``s`` to state ``t``.
    states : ndarray of int64, shape (S, P, V)
        The states, in the order of the rows and columns of ``K``.

    Raises
    ------
    ValueError
        On an unknown method, scan or survival power, or too many states.

    Examples
    --------
    >>> import numpy as np
    >>> class Stub:
    ...     n_rows, n_sensors, n_meas = 1, 1, (1,)
    ...     log_eta_dead = np.log([1.0]); log_eta_alive = np.log([[1.0, 2.0]])
    >>> K, states = transition_matrix(Stub())
    >>> states[:, 0, 0].tolist(), K[0].round(4).tolist()
    ([-1, 0, 1], [0.25, 0.25, 0.5])
    """
    check_choice(scan, "scan", ("systematic", "random"))
    kernels, states = row_kernels(problem, method, survival_power=survival_power,
                                  states=states)
    P = int(problem.n_rows)
    orders = [tuple(range(P))] if scan == "systematic" else list(itertools.permutations(range(P)))
    K = np.zeros((len(states), len(states)))
    for order in orders:
        Ko = np.eye(len(states))
        for n in order:
            Ko = Ko @ kernels[n]
        K += Ko
    return K / len(orders), states


def stationary_distribution(K):
    """The stationary row vector ``mu = mu K`` of a transition matrix with one recurrent class.

    Solved as the least-squares solution of ``mu (K - I) = 0``, ``sum(mu) = 1``.

    Parameters
    ----------
    K : array_like of float, shape (S, S)
        A row-stochastic matrix (``K[s, t]``: probability of moving from ``s`` to ``t``), e.g.
        from :func:`transition_matrix`.

    Returns
    -------
    ndarray of float64, shape (S,)
        ``mu``, summing to 1; entries below ``1e-15`` in magnitude (round-off of transient
        states) are set to 0.

    Examples
    --------
    >>> import numpy as np
    >>> stationary_distribution(np.array([[0.5, 0.5], [0.25, 0.75]])).round(6).tolist()
    [0.333333, 0.666667]
    """
    K = np.asarray(K, dtype=float)
    S = K.shape[0]
    A = np.vstack([K.T - np.eye(S), np.ones((1, S))])
    b = np.zeros(S + 1)
    b[-1] = 1.0
    mu = np.linalg.lstsq(A, b, rcond=None)[0]
    mu[np.abs(mu) < 1e-15] = 0.0
    return mu


def target_distribution(problem, states, method="exact", *, survival_power=1):
    """The normalised target of ``method`` on ``states``: ``pi``, ``pi'`` or ``pi~``.

    ``"exact"``: ``pi ∝ prod_n eta_n(gamma_n)``; ``"componentwise"``: ``pi'`` with the
    collapsed ``eta'``; ``"mm"``: ``pi~ ∝ prod_n eta~_n(gamma_n)``, ``eta~_n(-1) = eta_n(-1)``,
    ``eta~_n(t) = s_n^alpha prod_v theta_n^(v)(t^(v))`` (spec eq. 3.2). ``"mm-fixed"`` has no
    closed-form target (``ValueError``).

    Parameters
    ----------
    problem : MultiSensorProblem
        The problem whose weights define the target (``log_s`` and ``log_theta`` for
        ``"mm"``).
    states : ndarray of int, shape (S, P, V)
        The states to evaluate it on, e.g. those of :func:`transition_matrix` (collapsed
        states for ``"componentwise"``).
    method : {"exact", "mm", "componentwise"}
        Which target: ``pi``, ``pi~`` or ``pi'``.
    survival_power : {1, "V"}
        ``alpha`` of ``s_n^alpha`` in ``pi~`` (``"V"``: ``alpha = V``); used by ``"mm"`` only.

    Returns
    -------
    ndarray of float64, shape (S,)
        The target probability of each state, normalised over ``states``.

    Raises
    ------
    ValueError
        On an unknown method (``"mm-fixed"`` included).

    Examples
    --------
    >>> import numpy as np
    >>> class Stub:
    ...     n_rows, n_sensors, n_meas = 1, 1, (1,)
    ...     log_eta_dead = np.log([1.0]); log_eta_alive = np.log([[1.0, 2.0]])
    >>> target_distribution(Stub(), multisensor_states(Stub())).tolist()
    [0.25, 0.25, 0.5]
    """
    check_choice(method, "method", ("exact", "mm", "componentwise"))
    alpha = 1 if survival_power == 1 else int(problem.n_sensors)
    logw = np.zeros(len(states))
    for i, g in enumerate(states):
        for n, row in enumerate(g):
            row = tuple(int(x) for x in row)
            if method == "mm" and row[0] >= 0:
                lw = alpha * float(problem.log_s[n]) + sum(
                    float(np.asarray(problem.log_theta[v])[n, row[v]]) for v in range(len(row)))
            else:
                lw = _log_eta(problem, n, row, method == "componentwise")
            logw[i] += lw
    p = np.exp(logw - logw.max())
    return p / p.sum()

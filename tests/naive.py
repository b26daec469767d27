"""Slow, obviously correct references the tests hold the library to (one place for all).

Every function here is the definition written out with loops over small inputs — no numba, no
cleverness, and nothing from :mod:`oracle` unless the caller passes it in — so that a test
comparing fast code with it compares with the mathematics:

* :func:`feasible_assignments`, :func:`compact_states`: the feasible set Γ by brute force;
* :func:`log_weights`, :func:`log_normalizer`, :func:`marginals`: π = w / Z over Γ;
* :func:`rao_blackwell`: the Rao-Blackwellised association marginals of a hypothesis set;
* :func:`ospa`, :func:`ospa2`: OSPA by every injection, OSPA(2) loop by loop.
"""

from __future__ import annotations

import itertools

import numpy as np
from scipy.special import logsumexp

__all__ = [
    "feasible_assignments",
    "compact_states",
    "log_weights",
    "log_normalizer",
    "marginals",
    "rao_blackwell",
    "ospa",
    "ospa2",
]


def feasible_assignments(problem) -> np.ndarray:
    """Every feasible assignment (column indices), lexicographic, by brute force.

    A tuple of one finite column per row is feasible when no measurement is used twice
    (spec eq. 1.5); the missed and dead columns are row-specific, so they never collide.
    """
    P, M = problem.n_rows, problem.n_meas
    choices = [np.flatnonzero(np.isfinite(problem.cost[i])).tolist() for i in range(P)]
    out = []
    for cols in itertools.product(*choices):
        meas = [c for c in cols if c < M]
        if len(meas) == len(set(meas)):
            out.append(cols)
    return np.array(out, dtype=np.int64).reshape(len(out), P)


def compact_states(problem) -> list[tuple]:
    """Γ as compact states (measurement ``k < M``, missed ``M``, dead ``M + 1`` per row)."""
    cc = problem.compact_cost
    P, M = problem.n_rows, problem.n_meas
    options = [[k for k in range(M + 2) if np.isfinite(cc[i, k])] for i in range(P)]
    out = []
    for x in itertools.product(*options):
        meas = [k for k in x if k < M]
        if len(meas) == len(set(meas)):
            out.append(x)
    return out


def log_weights(problem, assignments) -> np.ndarray:
    """``ln w`` of each assignment: minus the sum of its chosen costs, row by row."""
    a = np.asarray(assignments, dtype=np.int64)
    a = a[None, :] if a.ndim == 1 else a
    return np.array([-sum(problem.cost[i, c] for i, c in enumerate(row)) for row in a],
                    dtype=float)


def log_normalizer(problem, assignments=None) -> float:
    """``ln Z`` over ``assignments`` (default: every feasible assignment)."""
    if assignments is None:
        assignments = feasible_assignments(problem)
    if problem.n_rows == 0:
        return 0.0
    return float(logsumexp(log_weights(problem, assignments)))


def marginals(problem, assignments=None) -> np.ndarray:
    """Per-row marginals ``(P, M + 2)`` — measurements, missed, dead — by summing π.

    ``assignments`` defaults to every feasible assignment; pass an enumeration of your own to
    check something else against the same sum.
    """
    if assignments is None:
        assignments = feasible_assignments(problem)
    P, M = problem.n_rows, problem.n_meas
    out = np.zeros((P, M + 2))
    if P == 0:
        return out
    a = np.asarray(assignments, dtype=np.int64)
    lw = log_weights(problem, a)
    w = np.exp(lw - lw.max())
    w /= w.sum()
    for h in range(a.shape[0]):
        for i in range(P):
            c = a[h, i]
            k = c if c < M else (M if c < M + P else M + 1)
            out[i, k] += w[h]
    return out


def rao_blackwell(problem, assignments) -> np.ndarray:
    """``Σ_h w_h π(γ_i = · | γ_{−i}^(h))`` written out densely, in compact columns."""
    P, M = problem.n_rows, problem.n_meas
    C = problem.cost
    a = np.asarray(assignments)
    lw = log_weights(problem, a)
    w = np.exp(lw - lw.max())
    w /= w.sum()
    beta = np.zeros((P, M + 2))
    for h in range(a.shape[0]):
        for i in range(P):
            taken = {int(a[h, k]) for k in range(P) if k != i}
            logp = np.array([-C[i, c] if c not in taken else -np.inf for c in range(C.shape[1])])
            p = np.exp(logp - logp.max())
            p /= p.sum()
            beta[i, :M] += w[h] * p[:M]
            beta[i, M] += w[h] * p[M:M + P].sum()
            beta[i, M + 1] += w[h] * p[M + P:].sum()
    return beta


def ospa(X, Y, c, p) -> float:
    """OSPA by enumerating every injection (the definition, spec §7.3)."""
    X, Y = np.asarray(X, float), np.asarray(Y, float)
    if len(X) > len(Y):
        X, Y = Y, X
    m, n = len(X), len(Y)
    if n == 0:
        return 0.0
    best = np.inf
    for perm in itertools.permutations(range(n), m):
        s = sum(min(c, np.linalg.norm(X[i] - Y[perm[i]])) ** p for i in range(m))
        best = min(best, s)
    return ((best + c**p * (n - m)) / n) ** (1 / p)


def ospa2(X, Y, c, p, N, r=0.0, base="euclidean") -> np.ndarray:
    """OSPA(2) written out loop by loop from spec §7 (and A18 for the lp base)."""
    K = X.shape[0]
    out = []
    for k in range(K):
        W = range(max(0, k - N + 1), k + 1)
        wt = {t: float(t - k + N) ** r for t in W}

        def alive(A, f, t):
            return not np.isnan(A[t, f]).any()

        fx = [f for f in range(X.shape[1]) if any(alive(X, f, t) for t in W)]
        fy = [g for g in range(Y.shape[1]) if any(alive(Y, g, t) for t in W)]
        D = np.zeros((len(fx), len(fy)))
        for a, f in enumerate(fx):
            for b, g in enumerate(fy):
                num = den = 0.0
                for t in W:
                    ex, ey = alive(X, f, t), alive(Y, g, t)
                    if not (ex or ey):
                        continue
                    if ex and ey:
                        diff = X[t, f] - Y[t, g]
                        if base == "euclidean":
                            d = min(c, float(np.sqrt((diff**2).sum())))
                        else:
                            d = min(c**p, float((np.abs(diff) ** p).sum()))
                    else:
                        d = c if base == "euclidean" else c**p
                    num += wt[t] * d
                    den += wt[t]
                D[a, b] = (num / den) ** p if base == "euclidean" else num / den
        m, n = len(fx), len(fy)
        if m > n:
            D, m, n = D.T, n, m
        if n == 0:
            out.append(0.0)
            continue
        best = min(
            (sum(D[i, perm[i]] for i in range(m)) for perm in itertools.permutations(range(n), m)),
            default=0.0,
        )
        cost = c**p if base == "euclidean" else c**p
        out.append(((best + cost * (n - m)) / n) ** (1 / p))
    return np.array(out)

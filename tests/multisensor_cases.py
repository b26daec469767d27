"""Shared multi-sensor test problems: a hypothesis strategy, a brute-force enumerator and a
small table of hand-built cases (every one small enough to enumerate)."""

from __future__ import annotations

import itertools

import numpy as np

from rankedassign.multisensor import MultiSensorProblem

__all__ = ["ms_problems", "brute_force", "MS_CASES", "MS_CASE_IDS"]

inf = np.inf


def ms_problems(max_rows: int = 3, max_sensors: int = 3, max_tuples: int = 27):
    """Hypothesis strategy: small multi-sensor problems with forbidden options and ties.

    ``P`` in ``0..max_rows``, ``V`` in ``1..max_sensors``, ``M_v`` in ``0..3`` with at most
    ``max_tuples`` tuples per row; log-weights uniform in ``[-5, 5]`` or integers in
    ``[-5, 5]`` (exact ties); about a quarter of the tuples and of the dead options are
    forbidden (``-inf``). Infeasible draws are rejected.
    """
    from hypothesis import assume
    from hypothesis import strategies as st

    @st.composite
    def _problems(draw):
        P = draw(st.integers(0, max_rows))
        V = draw(st.integers(1, max_sensors))
        M = []
        for _ in range(V):
            M.append(draw(st.integers(0, 3)))
        assume(int(np.prod([m + 1 for m in M])) <= max_tuples)
        T = int(np.prod([m + 1 for m in M]))
        integer = draw(st.booleans())
        n = P * (T + 1)
        if integer:
            vals = draw(st.lists(st.integers(-5, 5), min_size=n, max_size=n))
        else:
            vals = draw(st.lists(st.floats(-5, 5, allow_nan=False), min_size=n, max_size=n))
        forbid = draw(st.lists(st.integers(0, 7), min_size=n, max_size=n))
        w = np.array(vals, dtype=float).reshape(P, T + 1)
        w[np.array(forbid, dtype=int).reshape(P, T + 1) < 2] = -inf
        try:
            return MultiSensorProblem.from_log_eta(w[:, 0], w[:, 1:].reshape(P, *(m + 1 for m in M)))
        except ValueError:
            assume(False)

    return _problems()


def brute_force(problem: MultiSensorProblem) -> np.ndarray:
    """Every feasible assignment ``(n, P, V)`` by brute force over each row's allowed options,
    in lexicographic order of the flattened gamma."""
    P, V = problem.n_rows, problem.n_sensors
    tuples = problem.tuples
    flat = problem.log_eta_alive.reshape(P, problem.n_tuples)
    choices = []
    for n in range(P):
        opts = [tuple([-1] * V)] if np.isfinite(problem.log_eta_dead[n]) else []
        opts += [tuple(int(x) for x in tuples[k]) for k in np.flatnonzero(np.isfinite(flat[n]))]
        choices.append(opts)
    out = []
    for g in itertools.product(*choices):
        ok = True
        for v in range(V):
            used = [row[v] for row in g if row[v] > 0]
            if len(used) != len(set(used)):
                ok = False
                break
        if ok:
            out.append(g)
    return np.array(out, dtype=np.int64).reshape(len(out), P, V)


def _build():
    cases = []
    add = cases.append
    add(("empty_P0", MultiSensorProblem.from_eta(np.zeros(0), np.zeros((0, 3, 2)))))
    add(("no_meas", MultiSensorProblem.from_eta([0.5, 2.0], np.full((2, 1, 1), 0.25))))
    add(("one_row_V3", MultiSensorProblem.from_eta([0.1], np.arange(1.0, 13.0).reshape(1, 2, 3, 2))))
    must = np.zeros((2, 3, 3))
    must[0, 1, 1] = 2.0
    must[0, 2, 0] = 1.0
    must[1, 1, 2] = 3.0
    must[1, 0, 0] = 0.0
    add(("must_detect_rows", MultiSensorProblem.from_eta([0.0, 0.5], must)))
    rng = np.random.default_rng(7)
    w = rng.uniform(-3, 3, (3, 3, 4))
    w[rng.random(w.shape) < 0.3] = -inf
    add(("random_inf", MultiSensorProblem.from_log_eta(rng.uniform(-3, 3, 3), w)))
    huge = np.array([[[1e6, -1e6], [0.0, 3e5]], [[-2e5, 1e6], [5.0, -7e5]]])
    add(("huge_range", MultiSensorProblem.from_log_eta([-1e6, 2e5], huge)))
    add(("ties", MultiSensorProblem.from_eta([1.0, 1.0, 1.0], np.ones((3, 3, 3)))))
    return cases


MS_CASES = _build()
MS_CASE_IDS = [name for name, _ in MS_CASES]

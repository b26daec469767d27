"""One table of hand-built ranked-assignment problems, shared by every solver's tests.

``CASES`` is a list of ``(name, AssignmentProblem)``; every problem is small enough to
enumerate (``|Gamma| <= 10 000``) so that any solver or sampler can be checked against the
exhaustive oracle. Use it through ``pytest.mark.parametrize("name, problem", CASES,
ids=CASE_IDS)`` or :func:`case`.
"""

from __future__ import annotations

import numpy as np
import pytest

from rankedassign import AssignmentProblem
from rankedassign.single import synthetic

__all__ = ["CASES", "CASE_IDS", "case"]

inf = np.inf


def _layout(detect, missed, dead) -> AssignmentProblem:
    """Assemble a problem from compact costs (``+inf`` = forbidden)."""
    detect = np.asarray(detect, dtype=float).reshape(len(missed), -1)
    P, M = detect.shape
    C = np.full((P, M + 2 * P), inf)
    C[:, :M] = detect
    rows = np.arange(P)
    C[rows, M + rows] = missed
    C[rows, M + P + rows] = dead
    return AssignmentProblem.from_cost(C)


def _build() -> list[tuple[str, AssignmentProblem]]:
    cases = []
    add = cases.append
    # --- degenerate shapes
    add(("empty_P0_M0", AssignmentProblem.from_cost(np.zeros((0, 0)))))
    add(("no_rows_P0_M3", AssignmentProblem.from_cost(np.zeros((0, 3)))))
    add(("no_meas_P3_M0", _layout(np.zeros((3, 0)), [0.5, -1.0, 2.0], [1.0, 0.25, -3.0])))
    add(("single_row_only_missed", _layout([[inf, inf]], [0.7], [inf])))
    add(("single_entry", _layout([[-2.0]], [inf], [inf])))  # the one row must detect
    # --- forbidden pairs
    add((
        "forbidden_pairs",
        _layout([[1.0, inf, 0.5, inf], [inf, -0.5, inf, 2.0], [0.3, 0.3, inf, inf]],
                [1.0, inf, 2.0], [inf, 1.5, 0.0]),
    ))
    add((
        "must_detect_rows",  # rows 0 and 1 can be neither missed nor dead
        _layout([[0.0, 1.0, inf], [0.5, inf, 2.0], [1.0, 1.0, 1.0]],
                [inf, inf, 0.2], [inf, inf, 0.1]),
    ))
    add(("row_without_detections", _layout([[inf, inf, inf], [0.1, 0.2, 0.3]], [0.5, 1.0],
                                           [0.5, 2.0])))
    # --- ties
    add(("ties_integer", _layout([[0, 1, 0, 1], [1, 0, 1, 0], [0, 0, 1, 1]], [1, 1, 0],
                                 [2, 0, 1])))
    add(("all_equal", _layout(np.full((3, 3), 0.5), [0.5] * 3, [0.5] * 3)))
    add(("two_best_tied", _layout([[0.0, 5.0], [5.0, 0.0]], [0.0, 0.0], [9.0, 9.0])))
    # --- one dominant assignment
    add(("dominant", _layout([[-20.0, 5.0, 5.0], [5.0, -20.0, 5.0]], [3.0, 3.0], [3.0, 3.0])))
    add(("diagonal_2x4", synthetic.diagonal(R=2, M=4)))
    # --- negative costs (eta > 1)
    add(("negative_costs", _layout([[-3.0, -2.5, -1.0], [-2.9, -3.1, -0.5], [-1.0, -1.0, -4.0]],
                                   [-0.5, 0.0, -1.5], [1.0, -2.0, 0.5])))
    add(("all_want_one_meas", _layout([[-5.0, 2.0, 2.0], [-5.1, 2.0, 2.0], [-4.9, 2.0, 2.0],
                                       [-5.05, 2.0, 2.0]], [1.0] * 4, [1.5] * 4)))
    # --- best solutions on the last measurement columns / on the row-specific columns
    add((
        "best_on_last_meas",  # rows prefer measurements M-1, M-2, M-3 (not the first ones)
        _layout([[3.0, 3.0, 3.0, 2.0, 1.0, -4.0], [3.0, 3.0, 3.0, 1.0, -4.0, 2.0],
                 [3.0, 3.0, 2.0, -4.0, 1.0, 2.0]], [0.0, 0.0, 0.0], [0.5, 0.5, 0.5]),
    ))
    add((
        "best_on_dead_columns",  # the last P columns (the dead ones) hold the optimum
        _layout([[2.0, 3.0], [3.0, 2.0], [2.5, 2.5]], [1.0, 1.0, 1.0], [-1.0, -2.0, -3.0]),
    ))
    add((
        "mixed_missed_dead_best",  # row-specific columns are not interchangeable dummies
        _layout([[0.0, 4.0, 4.0], [4.0, 4.0, 4.0], [4.0, 4.0, 4.0]], [-1.0, inf, 2.0],
                [inf, -1.0, -2.0]),
    ))
    # --- huge cost ranges
    add(("huge_range", _layout([[1e8, -1e8, 0.0], [1e-8, 1e8, -1e8], [7e7, 3.0, -2e8]],
                               [1e9, 0.0, 1e-9], [-1e9, 5.0, 1e10])))
    add(("large_negative", _layout([[-800.0, -800.5], [-801.0, -799.0]], [0.0, 0.0],
                                   [700.0, -700.0])))
    # --- random and paper-like
    rng = np.random.default_rng(2023)
    D = rng.uniform(-5, 5, (4, 5))
    D[rng.random((4, 5)) < 0.3] = inf
    add(("random_4x5_inf", _layout(D, rng.uniform(-5, 5, 4), rng.uniform(-5, 5, 4))))
    add(("synthetic_random_3x4", synthetic.random(R=3, M=4, rng=7)))
    add(("synthetic_uniform_3x3", synthetic.uniform(R=3, M=3)))
    add(("more_rows_than_meas", synthetic.random(R=6, M=2, rng=11)))
    return cases


CASES: list[tuple[str, AssignmentProblem]] = _build()
CASE_IDS: list[str] = [name for name, _ in CASES]


def case(name: str) -> AssignmentProblem:
    """The problem called ``name`` in :data:`CASES`.

    Examples
    --------
    >>> case("single_entry").n_feasible()
    1
    """
    for n, p in CASES:
        if n == name:
            return p
    raise KeyError(f"no case named {name!r}; known: {CASE_IDS}")


# ----------------------------------------------------------------------------- hypothesis
def problems(max_rows: int = 4, max_meas: int = 5):
    """Hypothesis strategy: small problems with forbidden pairs, negative costs and ties.

    ``P`` in ``0..max_rows``, ``M`` in ``0..max_meas``; costs uniform in ``[-5, 5]`` or
    integers in ``[-5, 5]`` (many exact ties); about a third of the measurement entries and
    a quarter of the missed/dead entries are ``+inf``. Infeasible draws are rejected.
    """
    from hypothesis import assume
    from hypothesis import strategies as st

    @st.composite
    def _problems(draw):
        P = draw(st.integers(0, max_rows))
        M = draw(st.integers(0, max_meas))
        integer = draw(st.booleans())
        n = P * (M + 2)
        if integer:
            vals = draw(st.lists(st.integers(-5, 5), min_size=n, max_size=n))
        else:
            vals = draw(st.lists(st.floats(-5, 5, allow_nan=False), min_size=n, max_size=n))
        forbid = draw(st.lists(st.integers(0, 11), min_size=n, max_size=n))
        cc = np.array(vals, dtype=float).reshape(P, M + 2)
        fb = np.array(forbid, dtype=int).reshape(P, M + 2)
        cc[:, :M][fb[:, :M] < 4] = inf
        cc[:, M:][fb[:, M:] < 3] = inf
        try:
            return _layout(cc[:, :M], cc[:, M], cc[:, M + 1])
        except ValueError:
            assume(False)

    return _problems()


# ----------------------------------------------------------------------------- comparison
def marginal_atol(problem):
    """1e-12, widened for huge costs: a sum of costs of size |C| is only known to ~eps |C|
    (absolute, in nats), which moves a probability by about that much relative."""
    cc = problem.compact_cost
    big = np.abs(cc[np.isfinite(cc)]).max(initial=0.0)
    return 1e-12 + 8 * np.finfo(float).eps * big


def assert_same_ranking(got, want, *, complete: bool, rtol: float = 1e-12,
                        atol: float = 1e-12) -> None:
    """Tie-aware comparison of two rankings ``(assignments, costs)`` of the same problem.

    The sorted costs must agree within ``rtol``/``atol``; within every level of equal cost
    (consecutive costs closer than the tolerance) the *sets* of assignments must agree,
    except at the last level when the rankings were cut at ``k`` (``complete=False``),
    where either side may hold a different subset of the tied assignments.
    """
    from numpy.testing import assert_allclose, assert_array_equal

    ga, gc = np.asarray(got[0]), np.asarray(got[1])
    wa, wc = np.asarray(want[0]), np.asarray(want[1])
    assert len(gc) == len(wc), f"{len(gc)} assignments, expected {len(wc)}"
    assert_allclose(np.sort(gc), np.sort(wc), rtol=rtol, atol=atol)
    if len(wc) == 0 or wa.shape[1] == 0:
        return
    order = np.argsort(wc, kind="stable")
    wc_s = wc[order]
    tol = atol + rtol * np.abs(wc_s)
    new_level = np.r_[True, np.diff(wc_s) > tol[1:]]
    w_level = np.empty(len(wc), dtype=np.int64)
    w_level[order] = np.cumsum(new_level) - 1
    n_levels = int(w_level.max()) + 1
    starts = wc_s[new_level]  # lowest cost of each level
    g_level = np.searchsorted(starts, gc + atol + rtol * np.abs(gc), side="right") - 1
    g_level = np.clip(g_level, 0, n_levels - 1)
    last = n_levels if complete else n_levels - 1

    def canonical(a, level):
        keep = level < last
        a, level = a[keep], level[keep]
        idx = np.lexsort([a[:, i] for i in range(a.shape[1] - 1, -1, -1)] + [level])
        return level[idx], a[idx]

    gl, ga_c = canonical(ga, g_level)
    wl, wa_c = canonical(wa, w_level)
    assert len(gl) == len(wl), (
        f"{len(gl)} assignments below the last cost level, expected {len(wl)}"
    )
    assert_array_equal(gl, wl)
    assert_array_equal(ga_c, wa_c)


#: The herded one-worker-against-two tests run in the slow tier: their first call with
#: ``workers=2`` compiles the kind's parallel herded chain driver, which no study and no
#: precompile compiles (in a fresh CI run on the 2-core machine the first such test of each
#: kind took 120 s multi-sensor, 21 s adaptive birth, 14 s single-sensor, mostly compiling).
TWO_WORKERS_HERDED = pytest.mark.slow

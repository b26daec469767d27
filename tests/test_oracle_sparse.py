"""Exact normaliser and marginals of sparse (gated) problems: decomposition and frontier DP.

The frontier DP (``oracle.single.dp``, forced with ``_log_normalizer(p, "frontier")``) is checked
against the subset DP (forced with ``"dense"``) and against enumeration; the dispatching public
functions are checked beyond the subset DP's reach against the per-pair identity of spec
eq. (5.2) and the cases it must still refuse.
"""

import naive
import numpy as np
import pytest
from cases import CASE_IDS, CASES, problems
from hypothesis import assume, given
from hypothesis import strategies as st
from numpy.testing import assert_allclose, assert_array_equal
from scipy.special import logsumexp
from test_oracle_dp import enumerated_marginals, permuted

from oracle import best_mass, log_normalizer, marginals, truncation_error
from oracle import enumerate_assignments as oracle_enumerate
from oracle.single import murty
from oracle.single.dp import (
    MAX_FRONTIER,
    PlanCache,
    _components,
    _frontier_ops,
    _frontier_order,
    _log_normalizer,
    _marginals,
    _plan,
    compact_log_normalizer,
)
from rankedassign import AssignmentProblem

METHODS = ["dense", "frontier", "auto"]


def from_compact(cc):
    """Problem from compact costs ``(P, M + 2)`` = [measurements | missed | dead]."""
    cc = np.asarray(cc, dtype=float)
    M = cc.shape[1] - 2
    return AssignmentProblem.from_log_eta(-cc[:, :M], -cc[:, M], -cc[:, M + 1])


@st.composite
def sparse_problems(draw, max_rows=6, max_meas=8):
    """Problems with a drawn gate density in [0.05, 0.5]: often several components, rows
    that gate nothing and measurements no row gates; costs uniform in [-8, 8] or integers."""
    P = draw(st.integers(0, max_rows))
    M = draw(st.integers(0, max_meas))
    density = draw(st.floats(0.05, 0.5))
    seed = draw(st.integers(0, 2**32 - 1))
    rng = np.random.default_rng(seed)
    if draw(st.booleans()):
        cc = rng.integers(-8, 9, (P, M + 2)).astype(float)
    else:
        cc = rng.uniform(-8, 8, (P, M + 2))
    cc[:, :M][rng.random((P, M)) >= density] = np.inf
    cc[:, M:][rng.random((P, 2)) < 0.2] = np.inf
    try:
        return from_compact(cc)
    except ValueError:  # infeasible draw (a row with no finite option)
        assume(False)


def enumerated_log_z(problem):
    """``ln Z`` over the oracle's enumeration (itself held to brute force)."""
    return naive.log_normalizer(problem, oracle_enumerate(problem).assignments)


def banded(P, M, width, rng, shuffle=False):
    """Row ``i`` gates ``width`` consecutive measurements starting at ``i (M - width) / (P - 1)``
    (rounded): overlapping windows covering every measurement, a path-like gated problem."""
    cc = np.full((P, M + 2), np.inf)
    for i in range(P):
        lo = round(i * (M - width) / (P - 1))
        cc[i, lo: lo + width] = rng.uniform(-3, 3, width)
    cc[:, M] = rng.uniform(0, 3, P)
    cc[:, M + 1] = rng.uniform(0, 5, P)
    p = from_compact(cc)
    if shuffle:
        p = permuted(p, rng.permutation(P), rng.permutation(M))
    return p


def gated(rng, n_rows=22, n_meas=57, n_wide=4, side=2000.0, gate=300.0, wide_gate=900.0):
    """A tracking-like gated problem: rows and measurements at random 2-D positions, entry
    finite iff within ``gate`` (``wide_gate`` for the first ``n_wide`` rows, e.g. births),
    costs from a Gaussian likelihood over a uniform clutter density."""
    rows = rng.uniform(0, side, (n_rows, 2))
    meas = np.concatenate([rows[: n_meas // 3] + rng.normal(0, 10, (n_meas // 3, 2)),
                           rng.uniform(0, side, (n_meas - n_meas // 3, 2))])
    d = np.linalg.norm(rows[:, None] - meas[None], axis=2)
    sigma = np.where(np.arange(n_rows) < n_wide, 300.0, 10.0)[:, None]
    log_eta = (np.log(0.9 * 0.98) - d**2 / (2 * sigma**2) - np.log(2 * np.pi * sigma**2)
               - np.log(50 / side**2))
    reach = np.where(np.arange(n_rows) < n_wide, wide_gate, gate)[:, None]
    log_eta[d >= reach] = -np.inf
    return AssignmentProblem.from_log_eta(log_eta, np.full(n_rows, np.log(0.9 * 0.02)),
                                          np.full(n_rows, np.log(0.1)))


# --------------------------------------------------------------------------- exactness
@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("name, problem", CASES, ids=CASE_IDS)
def test_cases_every_method_against_enumeration(name, problem, method):
    assert_allclose(_log_normalizer(problem, method), enumerated_log_z(problem), rtol=1e-12,
                    atol=1e-12)
    big = np.abs(problem.compact_cost[np.isfinite(problem.compact_cost)]).max(initial=0.0)
    # huge costs are only known to ~eps |C| in nats (see test_oracle_dp.marginal_atol)
    assert_allclose(_marginals(problem, method), enumerated_marginals(problem), rtol=0,
                    atol=1e-12 + 8 * np.finfo(float).eps * big)


@given(sparse_problems())
def test_property_sparse_frontier_dense_enumeration(problem):
    want = enumerated_log_z(problem)
    want_m = enumerated_marginals(problem)
    for method in METHODS:
        assert_allclose(_log_normalizer(problem, method), want, rtol=1e-12, atol=1e-12)
        assert_allclose(_marginals(problem, method), want_m, rtol=0, atol=1e-12)


@given(problems(max_rows=5, max_meas=6))
def test_property_frontier_equals_dense(problem):
    assert_allclose(_log_normalizer(problem, "frontier"), _log_normalizer(problem, "dense"),
                    rtol=1e-12, atol=1e-12)
    assert_allclose(_marginals(problem, "frontier"), _marginals(problem, "dense"), rtol=0,
                    atol=1e-12)


def test_several_components_and_rows_without_measurements():
    rng = np.random.default_rng(3)
    inf = np.inf
    # components {0, 2} x {0, 3}, {1} x {1}, {4, 5} x {4, 5, 6}; row 3 gates nothing;
    # measurement 2 is gated by nobody
    cc = np.full((6, 9), inf)
    cc[0, [0, 3]] = rng.uniform(-2, 2, 2)
    cc[2, [0]] = -1.0
    cc[1, 1] = 0.5
    cc[4, [4, 5]] = rng.uniform(-2, 2, 2)
    cc[5, [5, 6]] = rng.uniform(-2, 2, 2)
    cc[:, 7] = rng.uniform(0, 2, 6)
    cc[:, 8] = rng.uniform(0, 2, 6)
    cc[1, 8] = inf  # row 1 may be missed but not dead
    p = from_compact(cc)
    comps, isolated = _components(np.isfinite(cc[:, :7]))
    assert [(r.tolist(), m.tolist()) for r, m in comps] == [([0, 2], [0, 3]), ([1], [1]),
                                                           ([4, 5], [4, 5, 6])]
    assert_array_equal(isolated, [3])
    want_m = enumerated_marginals(p)
    for method in METHODS:
        assert_allclose(_log_normalizer(p, method), enumerated_log_z(p), rtol=1e-12)
        assert_allclose(_marginals(p, method), want_m, rtol=0, atol=1e-12)
    m = marginals(p)
    assert_allclose(m[3, 7:], np.exp(-cc[3, 7:]) / np.exp(-cc[3, 7:]).sum(), rtol=1e-13)
    assert_array_equal(m[:, 2], 0.0)
    # ln Z is the sum over the components and the isolated row
    parts = [log_normalizer(from_compact(cc[np.ix_(r, list(c) + [7, 8])])) for r, c in comps]
    assert_allclose(log_normalizer(p), sum(parts) + np.logaddexp(-cc[3, 7], -cc[3, 8]),
                    rtol=1e-13)


@pytest.mark.parametrize("method", METHODS)
def test_degenerate_shapes(method):
    empty = AssignmentProblem.from_cost(np.zeros((0, 5)))
    assert _log_normalizer(empty, method) == 0.0
    assert _marginals(empty, method).shape == (0, 7)
    p = AssignmentProblem.from_eta(np.zeros((2, 0)), [1.0, 3.0], [1.0, 1.0])
    assert_allclose(_log_normalizer(p, method), np.log(2.0 * 4.0), rtol=1e-14)
    assert_allclose(_marginals(p, method), [[0.5, 0.5], [0.75, 0.25]], rtol=1e-14)
    # measurements that nobody gates behave as M = 0
    q = AssignmentProblem.from_eta(np.zeros((2, 3)), [1.0, 3.0], [1.0, 1.0])
    assert_allclose(_log_normalizer(q, method), np.log(8.0), rtol=1e-14)
    assert_allclose(_marginals(q, method)[:, 3:], [[0.5, 0.5], [0.75, 0.25]], rtol=1e-14)


# --------------------------------------------------------------------------- beyond 2^20
def pair_identity(problem, pairs):
    """Spec eq. (5.2) with one normaliser per removed (row, measurement) pair."""
    cc = problem.compact_cost
    P, M = problem.n_rows, problem.n_meas
    log_z = log_normalizer(problem)
    out = []
    for i, j in pairs:
        rows = [r for r in range(P) if r != i]
        if j < M:
            cols = [c for c in range(M) if c != j] + [M, M + 1]
            out.append(np.exp(-cc[i, j] + log_normalizer(from_compact(cc[np.ix_(rows, cols)]))
                              - log_z))
        else:  # unmatched: (eta_i(0) + eta_i(-1)) Z_{-i} / Z
            z_i = log_normalizer(from_compact(cc[rows]))
            out.append(np.exp(np.logaddexp(-cc[i, M], -cc[i, M + 1]) + z_i - log_z))
    return np.array(out)


def test_large_banded_problem_the_subset_dp_refused():
    rng = np.random.default_rng(7)
    p = banded(30, 80, 4, rng, shuffle=True)
    with pytest.raises(ValueError, match=r"too large for the exact subset DP: min\(P, M\) = "
                                         r"min\(30, 80\) = 30 > 20"):
        _log_normalizer(p, "dense")
    m = marginals(p)
    assert m.shape == (30, 82)
    assert np.all(m >= 0)
    assert_allclose(m.sum(axis=1), 1.0, rtol=1e-13)
    assert np.all(m[:, :80].sum(axis=0) <= 1 + 1e-12)
    # a few entries against the per-pair identity (each a frontier DP on a reduced problem)
    cc = p.compact_cost
    fin = np.argwhere(np.isfinite(cc[:, :80]))
    pairs = [tuple(fin[k]) for k in rng.choice(len(fin), 4, replace=False)] + [(5, 80), (17, 80)]
    got = [m[i, j] if j < 80 else m[i, 80] + m[i, 81] for i, j in pairs]
    assert_allclose(got, pair_identity(p, pairs), rtol=1e-10, atol=1e-15)


def test_banded_sub_case_matches_the_subset_dp():
    rng = np.random.default_rng(8)
    full = banded(30, 80, 4, rng)
    cc = full.compact_cost
    sub = from_compact(cc[np.ix_(range(18), list(range(40)) + [80, 81])])  # rows 0..17
    assert _plan(np.isfinite(sub.compact_cost[:, :40]), "auto")[0] == "frontier"
    assert_allclose(_log_normalizer(sub, "frontier"), _log_normalizer(sub, "dense"),
                    rtol=1e-12)
    assert_allclose(_marginals(sub, "frontier"), _marginals(sub, "dense"), rtol=0, atol=1e-12)
    assert_allclose(marginals(sub), _marginals(sub, "dense"), rtol=0, atol=1e-12)


def test_frontier_is_found_after_shuffling():
    # the band has frontier width 2 in its natural order; the order search must recover a
    # narrow order from a random relabelling
    rng = np.random.default_rng(9)
    p = banded(30, 80, 4, rng)
    q = permuted(p, rng.permutation(30), rng.permutation(80))
    _, width, _ = _frontier_order(np.isfinite(q.compact_cost[:, :80]))
    assert width <= 3
    assert_allclose(log_normalizer(q), log_normalizer(p), rtol=1e-12)


def test_gated_tracking_like_problem():
    # one connected component of 22 rows and 57 measurements, about 3 rows per measurement
    p = gated(np.random.default_rng(1))
    M = p.n_meas
    fin = np.isfinite(p.compact_cost[:, :M])
    comps, _ = _components(fin)
    assert max((len(r), len(m)) for r, m in comps) == (22, 57)
    with pytest.raises(ValueError, match="too large for the exact subset DP"):
        _log_normalizer(p, "dense")
    m = marginals(p)
    assert_allclose(m.sum(axis=1), 1.0, rtol=1e-13)
    assert np.all(m[:, :M].sum(axis=0) <= 1 + 1e-12)
    pairs = [tuple(x) for x in np.argwhere(fin)[::17]] + [(0, M), (10, M)]
    got = [m[i, j] if j < M else m[i, M] + m[i, M + 1] for i, j in pairs]
    assert_allclose(got, pair_identity(p, pairs), rtol=1e-10, atol=1e-15)


def test_truncation_error_and_best_mass_gain_the_reach():
    p = banded(30, 80, 4, np.random.default_rng(10))
    top = murty(p, 50)
    log_z = log_normalizer(p)
    kept = np.exp(logsumexp(-top.costs) - log_z)
    assert 0 < kept < 1
    assert_allclose(truncation_error(p, top.assignments), 1 - kept, rtol=1e-12)
    assert_allclose(best_mass(p, 50), kept, rtol=1e-12)


@pytest.mark.heavy_python
def test_wide_dense_block_still_refuses():
    # a sparse band plus a dense 21 x 21 block: the block fits neither DP
    rng = np.random.default_rng(11)
    cc = np.full((31, 43), np.inf)
    cc[:21, :21] = rng.uniform(-1, 1, (21, 21))
    for i in range(21, 31):
        cc[i, 21 + 2 * (i - 21): 23 + 2 * (i - 21)] = 0.0
    cc[:, 41] = 1.0
    cc[:, 42] = 2.0
    p = from_compact(cc)
    msg = (r"too large for the exact subset DP: min\(P, M\) = min\(21, 21\) = 21 > 20 in a "
           r"connected component, and for the frontier DP: frontier width 21 > 20 \(limit "
           r"2\^20 states\)")
    with pytest.raises(ValueError, match=msg):
        log_normalizer(p)
    with pytest.raises(ValueError, match=msg):
        marginals(p)
    with pytest.raises(ValueError, match="too large for the exact subset DP"):
        truncation_error(p, murty(p, 1).assignments)
    # the same block on its own side of the limit: 20 x 20 is solved
    q = from_compact(np.concatenate([cc[:20, :20], cc[:20, 41:]], axis=1))
    assert np.isfinite(log_normalizer(q))


def test_forced_frontier_message():
    p = AssignmentProblem.from_eta(np.ones((21, 21)), np.ones(21), np.ones(21))
    with pytest.raises(ValueError, match=rf"frontier width 21 > {MAX_FRONTIER} in a connected"):
        _log_normalizer(p, "frontier")


# --------------------------------------------------------------------------- internals
def test_frontier_ops_are_consistent():
    rng = np.random.default_rng(12)
    p = banded(12, 30, 4, rng, shuffle=True)
    fin = np.isfinite(p.compact_cost[:, :30])
    order, width, _ = _frontier_order(fin)
    assert sorted(order.tolist()) == list(range(30))
    ops, row_in_slot = _frontier_ops(fin, order, width)
    kinds = ops[:, 0]
    assert_array_equal(np.bincount(kinds, minlength=3), [12, 30, 12])  # enter, trans, retire
    # every row enters before its first measurement and retires after its last one, and
    # during every transition the slots hold exactly the active rows
    fo = fin[:, order]
    for t in range(30):
        active = row_in_slot[t][row_in_slot[t] >= 0]
        assert len(set(active.tolist())) == len(active) <= width
        want = np.flatnonzero(fo[:, : t + 1].any(axis=1) & fo[:, t:].any(axis=1))
        assert_array_equal(np.sort(active), want)
    # slots in use are always 0..n-1
    assert np.all((row_in_slot >= 0).sum(axis=1) == np.argmin(
        np.concatenate([row_in_slot, np.full((30, 1), -1)], axis=1) >= 0, axis=1))


def test_dispatch_prefers_the_cheaper_dp():
    dense = np.ones((12, 30), dtype=bool)
    assert _plan(dense, "auto")[0] == "dense"
    band = np.zeros((25, 60), dtype=bool)
    for i in range(25):
        band[i, 2 * i: 2 * i + 4] = True
    kind, (order, width) = _plan(band, "auto")
    assert (kind, width) == ("frontier", 2)
    small = np.zeros((5, 5), dtype=bool)
    np.fill_diagonal(small, True)
    assert _plan(small, "auto")[0] == "dense"  # tiny: no order search


@pytest.mark.parametrize("width", [12, pytest.param(19, marks=pytest.mark.slow)])
def test_wide_band_near_the_frontier_limit(width):
    # row i gates measurements i .. i + width - 1: the frontier is exactly `width` rows, the
    # subset DP would need 2^40 states
    rng = np.random.default_rng(width)
    P = 40
    M = P + width - 1
    eta = np.zeros((P, M))
    for i in range(P):
        eta[i, i: i + width] = rng.uniform(0.1, 2.0, width)
    p = AssignmentProblem.from_eta(eta, rng.uniform(0.1, 1, P), rng.uniform(0.1, 1, P))
    q = permuted(p, rng.permutation(P), rng.permutation(M))
    fin = np.isfinite(q.compact_cost[:, :M])
    assert _plan(fin, "auto")[0] == "frontier"
    assert _frontier_order(fin)[1] == width
    assert_allclose(log_normalizer(q), log_normalizer(p), rtol=1e-12)
    m = marginals(q)
    assert_allclose(m.sum(axis=1), 1.0, rtol=1e-13)
    assert np.all(m[:, :M].sum(axis=0) <= 1 + 1e-12)
    pairs = [tuple(x) for x in np.argwhere(fin)[:: len(np.argwhere(fin)) // 3]] + [(7, M)]
    got = [m[i, j] if j < M else m[i, M] + m[i, M + 1] for i, j in pairs]
    assert_allclose(got, pair_identity(q, pairs), rtol=1e-10, atol=1e-15)


# ------------------------------------------------------------- the compact entry point
@given(sparse_problems())
def test_compact_entry_point_is_the_public_normaliser(problem):
    cc = problem.compact_cost
    # its domain: every row can be unmatched (so the problem is feasible without a check)
    assume(np.isfinite(cc[:, -2:]).any(axis=1).all())
    want = log_normalizer(problem)
    assert compact_log_normalizer(cc) == want  # the same computation, bit for bit
    # planned once, then reused: rows scaled by their least cost, so equal to round-off
    plans = PlanCache()
    for _ in range(2):
        assert_allclose(compact_log_normalizer(cc, plans=plans), want, rtol=1e-13, atol=1e-12)
    if problem.n_rows:
        assert (len(plans), plans.hits) == (1, 1)


def test_compact_entry_point_on_a_gated_tracking_like_problem():
    p = gated(np.random.default_rng(1))  # 22 rows, 57 measurements: the frontier DP
    plans = PlanCache()
    want = log_normalizer(p)
    assert compact_log_normalizer(p.compact_cost) == want
    assert_allclose(compact_log_normalizer(p.compact_cost, plans=plans), want, rtol=1e-13)
    # another problem with the same gate pattern reuses the plan
    q = from_compact(p.compact_cost + np.random.default_rng(2).uniform(0, 1, p.compact_cost.shape))
    assert_allclose(compact_log_normalizer(q.compact_cost, plans=plans), log_normalizer(q),
                    rtol=1e-13)
    assert (len(plans), plans.hits) == (1, 1)


def _underflowing(kind):
    """Problems whose every row's least cost is a measurement all cannot have: scaled by the
    rows' least costs, the best assignment weighs exp(-800) or less, which underflows."""
    if kind == "dense":  # 4 rows, 1 measurement: Z = 4 e^{-2400} + e^{-3200}
        cc = np.full((4, 3), np.inf)
        cc[:, 0], cc[:, 1] = 0.0, 800.0
        return cc, np.log(4.0) - 2400.0 + np.log1p(np.exp(-800.0) / 4)
    # a path of 12 rows and 11 measurements (row i gates i - 1 and i), beyond the subset DP's
    # small sizes: one row is missed in each of the 12 best assignments, Z = 12 e^{-800} (1 +
    # terms below e^{-800})
    cc = np.full((12, 13), np.inf)
    for i in range(12):
        cc[i, max(i - 1, 0):min(i + 1, 11)] = 0.0
    cc[:, 11] = 800.0
    return cc, np.log(12.0) - 800.0


@pytest.mark.parametrize("kind", ["dense", "frontier"])
def test_planned_normaliser_falls_back_to_the_lsap_scaling_near_underflow(kind):
    cc, want = _underflowing(kind)
    assert _plan(np.isfinite(cc[:, :-2]), "auto")[0] == kind
    assert_allclose(log_normalizer(from_compact(cc)), want, rtol=1e-15)
    plans = PlanCache()
    for _ in range(3):  # planned, then planned in full, then reused
        assert_allclose(compact_log_normalizer(cc, plans=plans), want, rtol=1e-15)


@pytest.mark.parametrize(
    ("cost", "error", "match"),
    [
        (np.zeros(3), ValueError,
         r"compact cost must be 2-D with shape \(P, M \+ 2\), got shape \(3,\)"),
        (np.zeros((2, 1)), ValueError, r"got shape \(2, 1\)"),
        ([[np.nan, 0.0, 0.0]], ValueError, "compact cost contains NaN"),
        ([[-np.inf, 0.0, 0.0]], ValueError, "compact cost contains -inf; a cost must be finite"),
        ([[0.0, 1.0, 1.0], [0.0, np.inf, np.inf]], ValueError,
         "row 1 has neither a finite missed nor a finite dead cost"),
    ],
)
def test_compact_entry_point_refuses(cost, error, match):
    with pytest.raises(error, match=match):
        compact_log_normalizer(cost)


def test_plan_cache_settings_and_eviction():
    with pytest.raises(TypeError, match="plans must be a PlanCache or None, got dict"):
        compact_log_normalizer(np.zeros((1, 3)), plans={})
    for bad in (0, 1.5, True):
        with pytest.raises(ValueError, match="maxsize must be a positive int, got"):
            PlanCache(bad)
    plans = PlanCache(maxsize=1)
    a = np.array([[0.0, np.inf, 1.0, 1.0], [np.inf, 0.0, 1.0, 1.0]])
    b = np.array([[0.0, 0.0, 1.0, 1.0], [0.0, 0.0, 1.0, 1.0]])
    for cc in (a, b, a):
        compact_log_normalizer(cc, plans=plans)
    assert (len(plans), plans.hits) == (1, 0)  # the oldest pattern is dropped for the new

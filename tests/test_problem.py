"""Tests of rankedassign.single.problem: layout, conversions, costs, counting and bad input."""

import math

import numpy as np
import pytest
from cases import problems
from hypothesis import given
from hypothesis import strategies as st
from naive import feasible_assignments as brute_force
from numpy.testing import assert_allclose, assert_array_equal

from rankedassign import AssignmentProblem
from rankedassign.single import synthetic
from rankedassign.single.problem import COST_LIMIT

inf = np.inf


# ---------------------------------------------------------------- strategies and helpers
# ---------------------------------------------------------------- construction
def test_from_eta_layout():
    p = AssignmentProblem.from_eta([[2.0, 0.0], [0.5, 4.0]], [0.25, 0.5], [0.125, 1.0])
    C = p.cost
    assert C.shape == (2, 6)
    assert C.flags.c_contiguous and not C.flags.writeable and C.dtype == np.float64
    assert_allclose(C[0], [-np.log(2), inf, np.log(4), inf, np.log(8), inf], rtol=1e-15)
    assert_allclose(C[1], [np.log(2), -np.log(4), inf, np.log(2), inf, 0.0], rtol=1e-15)
    assert p.n_rows == 2 and p.n_meas == 2 and p.n_cols == 6


def test_compact_cost_and_eta_round_trip():
    D = np.array([[2.0, 0.5, 1.0]])
    p = AssignmentProblem.from_eta(D, [0.3], [0.7])
    assert_allclose(p.compact_cost, -np.log([[2.0, 0.5, 1.0, 0.3, 0.7]]), rtol=1e-15)
    d, m, x = p.eta()
    assert_allclose(d, D, rtol=1e-15)
    assert_allclose(m, [0.3], rtol=1e-15)
    assert_allclose(x, [0.7], rtol=1e-15)


def test_from_log_eta_equals_from_eta():
    rng = np.random.default_rng(0)
    D = rng.uniform(0.01, 3, size=(3, 4))
    m, d = rng.uniform(0.01, 1, 3), rng.uniform(0.01, 1, 3)
    a = AssignmentProblem.from_eta(D, m, d)
    b = AssignmentProblem.from_log_eta(np.log(D), np.log(m), np.log(d))
    assert a == b and hash(a) == hash(b)


def test_caller_arrays_not_modified():
    C = synthetic.random(rng=3).cost.copy()
    C.setflags(write=True)
    before = C.copy()
    p = AssignmentProblem.from_cost(C)
    assert_array_equal(C, before)
    assert p.cost is not C
    D = np.ones((2, 3))
    AssignmentProblem.from_eta(D, np.ones(2), np.ones(2))
    assert_array_equal(D, np.ones((2, 3)))


def test_degenerate_shapes():
    p0 = AssignmentProblem.from_cost(np.zeros((0, 5)))
    assert (p0.n_rows, p0.n_meas, p0.n_feasible()) == (0, 5, 1)
    assert p0.cost_of(np.zeros((1, 0), dtype=int)).tolist() == [0.0]
    pm = AssignmentProblem.from_eta(np.zeros((3, 0)), [0.5] * 3, [0.5] * 3)
    assert (pm.n_rows, pm.n_meas, pm.n_feasible()) == (3, 0, 8)


def test_negative_and_huge_costs_stay_in_log_space():
    p = AssignmentProblem.from_log_eta([[800.0, -800.0]], [-900.0], [0.0])
    assert p.cost_of([0]) == -800.0
    assert p.log_weight_of([1]) == -800.0
    assert np.isfinite(p.cost).sum() == 4


# ---------------------------------------------------------------- bad input (pinned)
@pytest.mark.parametrize(
    ("cost", "exc", "match"),
    [
        (np.zeros(6), ValueError, r"must be 2-D with shape \(P, M \+ 2P\), got 1-D shape \(6,\)"),
        (np.zeros((3, 5)), ValueError, r"shape \(3, 5\) is not \(P, M \+ 2P\).*at least 2P = 6"),
        ([[np.nan, 0.0, 0.0]], ValueError, r"cost matrix contains NaN at \(0, 0\)"),
        ([[-inf, 0.0, 0.0]], ValueError, r"contains -inf at \(0, 0\)"),
        (
            [[0.0, 0.0, 1.0, 0.5, 1.0, inf], [0.0, inf, inf, 1.0, inf, 1.0]],
            ValueError,
            r"finite entry at \(0, 3\) where the layout requires \+inf: column 3 is the "
            r"missed column of row 1",
        ),
        (
            [[0.0, 1.0, inf, 1.0, 2.0], [inf, inf, 1.0, inf, 1.0]],
            ValueError,
            r"finite entry at \(0, 4\).*column 4 is the dead column of row 1",
        ),
        ([[inf, inf, inf], [inf, inf, inf]][:1], ValueError, r"row 0 has no finite entry"),
        ([["a", "b", "c"]], TypeError, r"cost matrix must be a numeric array, got dtype <U1"),
        ([[1 + 1j, 0, 0]], TypeError, r"must be real"),
        ([[0.0, 1.0], [2.0]], TypeError, r"must be a numeric array"),
    ],
)
def test_from_cost_bad_input(cost, exc, match):
    with pytest.raises(exc, match=match):
        AssignmentProblem.from_cost(cost)


def test_infeasible_problem_is_rejected():
    # two rows that can only take measurement 1
    C = np.array([[0.0, inf, inf, inf, inf], [0.0, inf, inf, inf, inf]])
    with pytest.raises(ValueError, match=r"no feasible assignment: rows \[0, 1\]"):
        AssignmentProblem.from_cost(C)
    # three rows, two measurements, all must be detected
    C = np.full((3, 8), inf)
    C[:, :2] = 0.0
    with pytest.raises(ValueError, match=r"no feasible assignment: rows \[0, 1, 2\]"):
        AssignmentProblem.from_cost(C)
    # feasible: rows 0 and 1 must be detected, two measurements available
    C = np.full((2, 6), inf)
    C[:, :2] = 0.0
    assert AssignmentProblem.from_cost(C).n_feasible() == 2


@pytest.mark.parametrize(
    ("args", "match"),
    [
        (([1.0, 2.0], [1.0], [1.0]), r"eta_detect must be 2-D with shape \(P, M\), got 1-D"),
        (([[1.0]], [1.0, 1.0], [1.0]), r"eta_missed must have shape \(P,\) = \(1,\).*got shape \(2,\)"),
        (([[1.0]], [1.0], [[1.0]]), r"eta_dead must have shape \(P,\) = \(1,\)"),
        (([[-1.0]], [1.0], [1.0]), r"eta_detect has a negative entry at \(0, 0\)"),
        (([[1.0]], [-0.5], [1.0]), r"eta_missed has a negative entry at \(0,\)"),
        (([[np.nan]], [1.0], [1.0]), r"eta_detect contains NaN at \(0, 0\)"),
        (([[inf]], [1.0], [1.0]), r"eta_detect contains inf"),
        (([[0.0]], [0.0], [0.0]), r"row 0 has no finite entry"),
        ((None, [1.0], [1.0]), r"eta_detect must be a numeric array, got dtype object"),
    ],
)
def test_from_eta_bad_input(args, match):
    exc = TypeError if args[0] is None else ValueError
    with pytest.raises(exc, match=match):
        AssignmentProblem.from_eta(*args)


def test_from_log_eta_bad_input():
    with pytest.raises(ValueError, match=r"log_eta_missed contains \+inf at \(0,\)"):
        AssignmentProblem.from_log_eta([[0.0]], [inf], [0.0])
    with pytest.raises(ValueError, match=r"log_eta_detect contains NaN"):
        AssignmentProblem.from_log_eta([[np.nan]], [0.0], [0.0])


def test_vo_layout_bad_shape():
    with pytest.raises(ValueError, match=r"Vo-layout cost matrix must be 2-D with shape \(P, 2P \+ M\)"):
        AssignmentProblem.from_vo_layout(np.zeros((3, 4)))


def test_assignment_argument_errors():
    p = synthetic.uniform()
    with pytest.raises(ValueError, match=r"must have shape \(n, P\) = \(n, 4\) or \(P,\) = \(4,\), got shape \(3,\)"):
        p.cost_of([0, 1, 2])
    with pytest.raises(ValueError, match=r"column index 24 outside \[0, 24\)"):
        p.cost_of([0, 1, 2, 24])
    with pytest.raises(TypeError, match=r"integer array of column indices, got dtype float64"):
        p.cost_of([0.5, 1, 2, 3])
    with pytest.raises(ValueError, match=r"cols\[0, 1\] = 16 is the missed/dead column of another row"):
        p.cols_to_gamma([0, 16, 18, 19])
    with pytest.raises(ValueError, match=r"gamma contains 17 outside \[-1, M\] = \[-1, 16\]"):
        p.gamma_to_cols([0, 0, 0, 17])


# ---------------------------------------------------------------- properties
@given(problems())
def test_gamma_round_trip(p):
    a = brute_force(p)
    g = p.cols_to_gamma(a)
    assert g.shape == a.shape
    assert ((g >= -1) & (g <= p.n_meas)).all()
    assert_array_equal(p.gamma_to_cols(g), a)
    if len(a):
        assert_array_equal(p.cols_to_gamma(a[0]), g[0])


@given(problems())
def test_vo_layout_round_trip(p):
    vo = p.to_vo_layout()
    assert vo.shape == (p.n_rows, 2 * p.n_rows + p.n_meas)
    assert AssignmentProblem.from_vo_layout(vo) == p


@given(problems())
def test_cost_additivity_and_feasibility(p):
    a = brute_force(p)
    c = p.cost_of(a)
    rows = np.arange(p.n_rows)
    expected = np.array([sum(p.cost[i, s[i]] for i in rows) for s in a])
    assert_allclose(c, expected, rtol=1e-12, atol=1e-12)
    assert np.isfinite(c).all()
    assert p.is_feasible(a).all()
    assert_array_equal(p.log_weight_of(a), -c)
    if p.n_rows >= 2 and p.n_meas >= 1:
        dup = np.zeros(p.n_rows, dtype=np.int64)
        assert not p.is_feasible(dup)
        assert p.cost_of(dup) == inf


@given(problems())
def test_n_feasible_equals_brute_force(p):
    assert p.n_feasible() == len(brute_force(p))


@given(st.integers(0, 6), st.integers(0, 8))
def test_n_feasible_closed_form(P, M):
    p = synthetic.uniform(R=P, M=M)
    expected = sum(math.comb(P, k) * math.comb(M, k) * math.factorial(k) * 2 ** (P - k)
                   for k in range(min(P, M) + 1))
    assert p.n_feasible() == expected
    if P <= 3 and M <= 4:
        assert expected == len(brute_force(p))


def test_n_feasible_paper_families():
    for p in (synthetic.diagonal(), synthetic.uniform(), synthetic.random(rng=0),
              synthetic.random(rng=1, granularity="matrix", pbar_d="pd")):
        assert p.n_feasible() == 76_848
    assert synthetic.uniform(R=2, M=2).n_feasible() == 14  # spec §10.1


def test_n_feasible_large_closed_form_is_exact():
    p = synthetic.uniform(R=30, M=100)
    n = p.n_feasible()
    assert isinstance(n, int) and n > 2**63  # beyond int64: exact Python int


def test_n_feasible_gated_large_uses_object_ints():
    # 12 rows, 14 measurements, some pairs forbidden: the count exceeds int64? Check vs int64 path.
    rng = np.random.default_rng(5)
    C = np.array(synthetic.uniform(R=12, M=14).cost)
    C[:, :14][rng.random((12, 14)) < 0.3] = inf
    p = AssignmentProblem.from_cost(C)
    n = p.n_feasible()
    # transposed counting route (measurement subsets) must agree
    from rankedassign.single.problem import _count_meas_small, _count_rows_small

    B = np.isfinite(p.compact_cost[:, :14])
    a = np.full(12, 2)
    assert n == _count_rows_small(B, a, object) == _count_meas_small(B, a, object)


def test_n_feasible_refuses_too_large():
    C = np.array(synthetic.uniform(R=30, M=40).cost)
    C[0, 0] = inf
    p = AssignmentProblem.from_cost(C)
    with pytest.raises(ValueError, match=r"problem too large to count exactly: P = 30 rows and 40 "
                                         r"reachable measurements.*2\^30 states"):
        p.n_feasible()


def test_all_missed_all_dead():
    p = synthetic.uniform(R=3, M=2)
    assert_array_equal(p.all_missed(), [2, 3, 4])
    assert_array_equal(p.all_dead(), [5, 6, 7])
    assert_array_equal(p.cols_to_gamma(p.all_missed()), [0, 0, 0])
    assert_array_equal(p.cols_to_gamma(p.all_dead()), [-1, -1, -1])
    assert p.cost_of(p.all_missed()) == 1.5


def test_repr_and_equality():
    p = synthetic.diagonal()
    assert repr(p) == "AssignmentProblem(P=4, M=16)"
    assert p == synthetic.diagonal()
    assert p != synthetic.uniform()
    assert (p == 3) is False


# ---------------------------------------------------------------- extremes (hardening)
def test_costs_whose_sums_could_overflow_are_refused():
    # the hardening issue: +-1e308 was accepted and an assignment's cost overflowed to inf
    C = [[1e308, 1e308, inf, 1e308, inf], [1e308, inf, 1e308, inf, 1e308]]
    with pytest.raises(ValueError, match=r"cost matrix has finite costs too large to add up: the "
                                         r"rows' largest \|finite cost\| sum to 2\.000e\+308 "
                                         r"\(row 0: 1e\+308\), beyond COST_LIMIT = 2\*\*1020"):
        AssignmentProblem.from_cost(C)
    with pytest.raises(ValueError, match=r"sum to 1\.798e\+308"):
        AssignmentProblem.from_cost([[-np.finfo(float).max, 0.0, 0.0]])
    with pytest.raises(ValueError, match=r"finite costs too large to add up"):
        AssignmentProblem.from_log_eta([[1e308]], [0.0], [0.0])
    with pytest.raises(ValueError, match=r"finite costs too large to add up"):
        AssignmentProblem.from_vo_layout([[0.0, -1e308, 0.0]])
    # at the limit exactly: accepted, and every assignment's cost is finite
    h = 2.0**1019
    p = AssignmentProblem.from_cost([[h, -h, inf, 1.0, inf], [-h, inf, h, inf, 1.0]])
    assert p.cost_of([1, 0]) == -2 * h == -COST_LIMIT
    assert np.isfinite(p.cost_of(brute_force(p))).all()
    # many rows: the bound is on the sum over rows, not on any one entry
    P = 1024
    ok = np.full((P, 2 * P), inf)
    ok[np.arange(P), np.arange(P)] = 2.0**1010  # sums to exactly 2**1020
    AssignmentProblem.from_cost(ok)
    ok[0, 0] = 2.0**1011
    with pytest.raises(ValueError, match=r"row 0: 2\.19445e\+304"):
        AssignmentProblem.from_cost(ok)


def test_tiny_and_subnormal_costs_are_exact():
    tiny = 5e-324
    p = AssignmentProblem.from_cost([[tiny, -tiny, inf, 1e-300, inf], [0.0, inf, tiny, inf, 1.0]])
    assert p.cost_of([0, 2]) == 2 * tiny
    assert p.cost_of([1, 0]) == -tiny
    assert COST_LIMIT == 2.0**1020


@pytest.mark.parametrize(
    ("cost", "exc", "match"),
    [
        ([[10**400, 0, 0]], ValueError,
         r"cost matrix has an entry too large for a float64: 100000000000\.\.\. \(401 digits\)"),
        ([[None, 0.0, 0.0]], TypeError, r"cost matrix must be a numeric array, got dtype object"),
        (np.zeros((1, 3), dtype="datetime64[s]"), TypeError, r"got dtype datetime64\[s\]"),
        (np.zeros((1, 3), dtype="timedelta64[s]"), TypeError, r"got dtype timedelta64\[s\]"),
        ([[b"a", b"b", b"c"]], TypeError, r"got dtype \|S1"),
        (np.zeros((1, 1, 3)), ValueError, r"got 3-D shape \(1, 1, 3\)"),
        (np.float64(1.0), ValueError, r"got 0-D shape \(\)"),
    ],
)
def test_from_cost_extreme_input(cost, exc, match):
    with pytest.raises(exc, match=match):
        AssignmentProblem.from_cost(cost)


def test_huge_python_ints_that_fit_a_double_are_costs():
    assert AssignmentProblem.from_cost([[10**30, 0, 0]]).cost_of([0]) == 1e30
    assert AssignmentProblem.from_cost([[2**64, 0, 0]]).cost_of([0]) == 2.0**64


def test_empty_shapes():
    for shape in [(0, 0), (0, 7), (2, 4)]:
        C = np.full(shape, inf)
        if shape[0]:
            C[np.arange(2), 2 + np.arange(2)] = 0.0
        p = AssignmentProblem.from_cost(C)
        assert p.shape == shape
    with pytest.raises(ValueError, match=r"got 1-D shape \(0,\)"):
        AssignmentProblem.from_cost([])


@pytest.mark.parametrize(
    ("assignments", "exc", "match"),
    [
        ([2**63, 0, 0, 0], ValueError, r"assignments contains 9223372036854775808, beyond any index"),
        ([2**64, 0, 0, 0], ValueError, r"assignments contains 18446744073709551616, beyond any index"),
        ([-(10**30), 0, 0, 0], ValueError, r"assignments contains -1000000000000000000000000000000"),
        (np.array([2**62 + 1, 0, 0, 0]), ValueError, r"contains 4611686018427387905, beyond"),
        ([1e30, 0.0, 0.0, 0.0], ValueError, r"assignments contains 1e\+30, beyond any index"),
        ([np.inf, 0.0, 0.0, 0.0], TypeError, r"got dtype float64 with non-integer values"),
        ([np.nan, 0.0, 0.0, 0.0], TypeError, r"got dtype float64 with non-integer values"),
        ([True, False, True, False], TypeError, r"integer array of column indices, got dtype bool"),
        (["0", "1", "2", "3"], TypeError, r"got dtype <U1"),
        ([None, 1, 2, 3], TypeError, r"got dtype object"),
        ([[0, 1, 2, 3], [0, 1]], TypeError, r"could not convert"),
        (5, ValueError, r"must have shape \(n, P\) = \(n, 4\) or \(P,\) = \(4,\), got shape \(\)"),
        (np.zeros((1, 1, 4), dtype=int), ValueError, r"got shape \(1, 1, 4\)"),
    ],
)
def test_assignment_arguments_at_the_extremes(assignments, exc, match):
    p = synthetic.uniform()
    for method in (p.cost_of, p.is_feasible, p.log_weight_of):
        with pytest.raises(exc, match=match):
            method(assignments)


def test_assignment_extremes_that_are_accepted():
    p = synthetic.uniform()
    # whole floats, unsigned ints, int64 values within 2**62 (infeasible, not an error)
    assert p.cost_of([0.0, 1.0, 2.0, 3.0]) == 2.0
    assert p.cost_of(np.array([0, 1, 2, 3], dtype=np.uint64)) == 2.0
    assert not p.is_feasible([2**62, 0, 0, 0])
    assert p.is_feasible(np.zeros((0, 4))).shape == (0,)
    assert p.cost_of(np.zeros((0, 4), dtype=np.uint8)).shape == (0,)
    with pytest.raises(ValueError, match=r"gamma contains 4611686018427387904 outside \[-1, M\]"):
        p.gamma_to_cols([2**62, 0, 0, 0])

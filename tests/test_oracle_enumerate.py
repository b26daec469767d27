"""Exhaustive enumeration: count, order, costs, against a naive itertools enumeration."""


import numpy as np
import pytest
from cases import CASE_IDS, CASES, problems
from hypothesis import given
from naive import feasible_assignments as naive_enumeration
from numpy.testing import assert_array_equal

from oracle import Ranked, enumerate_assignments
from rankedassign import AssignmentProblem
from rankedassign.single import synthetic

#: The message of an object of no known problem kind (rankedassign.kinds.kind_of).
NOT_A_PROBLEM = (r"problem must be one of \(AssignmentProblem, MultiSensorProblem, "
                 r"AdaptiveBirthProblem\), got ")


def check_ranked(problem, r):
    a, c = r
    assert isinstance(r, Ranked)
    assert a.dtype == np.int64 and c.dtype == np.float64
    assert a.shape == (len(c), problem.n_rows)
    assert_array_equal(c, problem.cost_of(a))  # bit for bit
    assert np.all(np.diff(c) >= 0)
    assert problem.is_feasible(a).all()
    if problem.n_rows:
        assert len(np.unique(a, axis=0)) == len(a)


@pytest.mark.parametrize("name, problem", CASES, ids=CASE_IDS)
def test_cases_count_order_and_naive_set(name, problem):
    r = enumerate_assignments(problem)
    check_ranked(problem, r)
    assert len(r.costs) == problem.n_feasible()
    if problem.n_cols ** problem.n_rows <= 200_000:
        a = r.assignments
        assert_array_equal(np.unique(a, axis=0) if problem.n_rows else a,
                           naive_enumeration(problem))


@given(problems())
def test_property_matches_naive(problem):
    r = enumerate_assignments(problem)
    check_ranked(problem, r)
    assert len(r.costs) == problem.n_feasible()
    a = r.assignments
    assert_array_equal(np.unique(a, axis=0) if problem.n_rows else a,
                       naive_enumeration(problem))


def test_ties_are_lexicographic():
    p = synthetic.uniform(R=3, M=3)  # every assignment costs 1.5
    r = enumerate_assignments(p)
    keys = [tuple(row) for row in r.assignments]
    assert keys == sorted(keys)
    # mixed levels: inside every level of equal cost, rows are in lexicographic order
    p = AssignmentProblem.from_cost(
        [[0, 1, 0, 0, np.inf, 1, np.inf], [1, 0, 0, np.inf, 0, np.inf, 1]]
    )
    r = enumerate_assignments(p)
    for level in np.unique(r.costs):
        rows = [tuple(x) for x in r.assignments[r.costs == level]]
        assert rows == sorted(rows)


def test_paper_matrices():
    for p in (synthetic.uniform(), synthetic.diagonal(), synthetic.random(rng=0)):
        r = enumerate_assignments(p)
        assert len(r.costs) == 76_848
        check_ranked(p, r)
    assert_array_equal(enumerate_assignments(synthetic.diagonal()).assignments[0], [0, 1, 2, 3])


def test_deterministic():
    p = synthetic.random(rng=3)
    a, b = enumerate_assignments(p), enumerate_assignments(p)
    assert_array_equal(a.assignments, b.assignments)
    assert_array_equal(a.costs, b.costs)


def test_degenerate_shapes():
    r = enumerate_assignments(AssignmentProblem.from_cost(np.zeros((0, 4))))
    assert r.assignments.shape == (1, 0)
    assert_array_equal(r.costs, [0.0])
    p = AssignmentProblem.from_eta(np.zeros((2, 0)), [1.0, 0.5], [0.5, 0.25])
    r = enumerate_assignments(p)
    assert_array_equal(r.assignments, [[0, 1], [0, 3], [2, 1], [2, 3]])


def test_count_by_search_when_counting_dp_refuses():
    # 23 rows that must each take "their" measurement: n_feasible refuses (2^23 subsets),
    # the search fallback counts the single assignment
    P = 23
    C = np.full((P, 3 * P), np.inf)
    C[np.arange(P), np.arange(P)] = np.linspace(-1, 1, P)
    p = AssignmentProblem.from_cost(C)
    with pytest.raises(ValueError, match="too large to count"):
        p.n_feasible()
    r = enumerate_assignments(p)
    assert_array_equal(r.assignments, [np.arange(P)])
    # and the same shape with missed columns open is refused without being enumerated
    C[np.arange(P), P + np.arange(P)] = 0.0
    with pytest.raises(ValueError, match="more than 1000 feasible assignments .* limit = 1000"):
        enumerate_assignments(AssignmentProblem.from_cost(C), limit=1000)


def test_too_large_message_states_count_and_limit():
    with pytest.raises(
        ValueError,
        match=r"too large to enumerate: 76848 feasible assignments \(P = 4, M = 16\) exceed "
        r"limit = 76847",
    ):
        enumerate_assignments(synthetic.uniform(), limit=76_847)
    assert len(enumerate_assignments(synthetic.uniform(), limit=76_848).costs) == 76_848


def test_too_large_message_also_states_the_bytes():
    # 8 P + 40 = 72 bytes per assignment for P = 4
    with pytest.raises(ValueError, match=r"exceed limit = 76847 \(they would take 5\.3 MiB "
                                         r"\(5533056 bytes\)\)$"):
        enumerate_assignments(synthetic.uniform(), limit=76_847)


@pytest.mark.heavy_python
def test_huge_limit_is_refused_with_the_count_and_the_bytes_before_allocating():
    # limit = 10**18 used to let a count of 1.8e9 through to an impossible allocation
    p = synthetic.random(R=10, M=10, rng=0)
    with pytest.raises(ValueError, match=(
            r"^problem too large to enumerate: 1815177984 feasible assignments \(P = 10, "
            r"M = 10\) would take 202\.9 GiB \(217821358080 bytes\), more than the limit of "
            r"4\.0 GiB \(4294967296 bytes\) \(rankedassign\.validation\.MAX_WORK_BYTES; 120 "
            r"bytes each\)$")):
        enumerate_assignments(p, limit=10**18)
    # too costly to count exactly (a forbidden pair, 200 rows): the counting search stops as
    # soon as it passes what the memory limit holds, 2**32 // 1640 assignments
    C = synthetic.random(R=200, M=30, rng=0).cost.copy()
    C[0, 0] = np.inf
    q = AssignmentProblem.from_cost(C)
    with pytest.raises(ValueError, match=(
            r"^problem too large to enumerate: more than 2618882 feasible assignments "
            r"\(P = 200, M = 30\) would take more than the limit of 4\.0 GiB \(4294967296 "
            r"bytes\) \(rankedassign\.validation\.MAX_WORK_BYTES; 1640 bytes each\)$")):
        enumerate_assignments(q, limit=10**18)
    # a huge limit on a small problem changes nothing
    small = synthetic.random(R=3, M=4, rng=1)
    got, want = enumerate_assignments(small, limit=10**18), enumerate_assignments(small)
    assert_array_equal(got.assignments, want.assignments)
    assert_array_equal(got.costs, want.costs)


@pytest.mark.parametrize(
    "kwargs, exc, match",
    [
        ({"limit": 0}, ValueError, "limit must be an int >= 1, got 0"),
        ({"limit": -3}, ValueError, "limit must be an int >= 1, got -3"),
        ({"limit": 2.5}, TypeError, "limit must be an int, got float 2.5"),
        ({"limit": True}, TypeError, "limit must be an int, got bool True"),
    ],
)
def test_bad_limit(kwargs, exc, match):
    with pytest.raises(exc, match=match):
        enumerate_assignments(synthetic.diagonal(R=1, M=1), **kwargs)


def test_not_a_problem():
    with pytest.raises(TypeError, match=NOT_A_PROBLEM + r"ndarray"):
        enumerate_assignments(np.zeros((1, 3)))


def test_radix_sort_is_a_stable_argsort():
    from oracle._kernels.enumeration import _radix_argsort

    rng = np.random.default_rng(0)
    x = np.concatenate([rng.normal(0, 1e3, 500), rng.integers(-3, 3, 500).astype(float),
                        [0.0, -0.0, np.inf, -1e308, 1e308, 5e-324, -5e-324, 0.0, -0.0]])
    rng.shuffle(x)
    assert_array_equal(_radix_argsort(x), np.argsort(x, kind="stable"))
    assert _radix_argsort(np.zeros(0)).shape == (0,)

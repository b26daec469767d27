"""Murty k-best: both methods against enumeration and each other, tie-aware."""

import hashlib

import numpy as np
import pytest
from cases import CASE_IDS, CASES, assert_same_ranking, problems
from hypothesis import given
from hypothesis import strategies as st
from numpy.testing import assert_array_equal
from scipy.optimize import linear_sum_assignment

from oracle import enumerate_assignments
from oracle.single import murty
from rankedassign import AssignmentProblem
from rankedassign.single import synthetic
from rankedassign.validation import MAX_WORK_BYTES

METHODS = ["numba", "scipy"]


def check_output(problem, r):
    a, c = r
    assert a.dtype == np.int64 and a.shape == (len(c), problem.n_rows)
    assert_array_equal(c, problem.cost_of(a))  # bit for bit
    assert np.all(np.diff(c) >= 0)
    if problem.n_rows:
        assert problem.is_feasible(a).all()
        assert len(np.unique(a, axis=0)) == len(a)


def square_problem(n, seed, *, integer=False):
    """The square case of fastmurty's benchmark: an ``n x n`` block of nearly equal costs
    (``U(0, 1) - (n + 1)``, or integers in ``-4..-2`` with many ties), missed at cost 0, no
    dead column. Most children cost more than the ``k``-th best: the kernel's cut drops them."""
    rng = np.random.default_rng(seed)
    cost = np.full((n, 3 * n), np.inf)
    cost[:, :n] = (rng.integers(0, 3, (n, n)) - 4.0) if integer else rng.random((n, n)) - (n + 1)
    cost[np.arange(n), n + np.arange(n)] = 0.0
    return AssignmentProblem.from_cost(cost)


def last_columns_problem(P, M, seed):
    """Random costs where the cheapest entries sit on the last measurement columns."""
    rng = np.random.default_rng(seed)
    D = rng.uniform(0.0, 5.0, (P, M))
    D[:, M - P:] -= rng.uniform(6.0, 9.0, (P, P))  # the optimum lives on columns M-P..M-1
    D[rng.random((P, M)) < 0.2] = np.inf
    return AssignmentProblem.from_log_eta(-D, -rng.uniform(0, 3, P), -rng.uniform(0, 3, P))


@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("name, problem", CASES, ids=CASE_IDS)
def test_cases_complete_ranking(name, problem, method):
    full = enumerate_assignments(problem)
    r = murty(problem, len(full.costs) + 5, backend=method)  # more than |Gamma|: all of them
    check_output(problem, r)
    assert_same_ranking(r, full, complete=True)


@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("name, problem", CASES, ids=CASE_IDS)
def test_cases_top_k(name, problem, method):
    full = enumerate_assignments(problem)
    k = max(1, len(full.costs) // 3)
    r = murty(problem, k, backend=method)
    check_output(problem, r)
    assert_same_ranking(r, (full.assignments[:k], full.costs[:k]), complete=False)


@given(problems(), st.integers(1, 40))
def test_property_numba_against_enumeration(problem, k):
    full = enumerate_assignments(problem)
    r = murty(problem, k)
    check_output(problem, r)
    kk = min(k, len(full.costs))
    assert_same_ranking(r, (full.assignments[:kk], full.costs[:kk]), complete=kk == len(full.costs))


@given(problems(max_rows=3, max_meas=4), st.integers(1, 25))
def test_property_scipy_against_enumeration(problem, k):
    full = enumerate_assignments(problem)
    r = murty(problem, k, backend="scipy")
    kk = min(k, len(full.costs))
    assert_same_ranking(r, (full.assignments[:kk], full.costs[:kk]), complete=kk == len(full.costs))


@pytest.mark.parametrize("seed", range(4))
def test_best_solutions_on_last_measurement_columns(seed):
    p = last_columns_problem(4, 9, seed)
    full = enumerate_assignments(p)
    assert np.all(full.assignments[0] >= 9 - 4)  # the construction did what it says
    for method in METHODS:
        r = murty(p, 300, backend=method)
        assert_same_ranking(r, (full.assignments[:300], full.costs[:300]), complete=False)


@pytest.mark.parametrize("method", METHODS)
def test_rank_one_is_the_lsap_optimum(method):
    for seed in range(5):
        p = synthetic.random(R=8, M=12, rng=seed)
        rows, cols = linear_sum_assignment(p.cost)
        r = murty(p, 1, backend=method)
        assert_array_equal(r.costs, [p.cost_of(cols)])


@pytest.mark.parametrize(
    "problem, k",
    [
        (synthetic.random(rng=0), 2000),
        (synthetic.random(R=8, M=12, rng=1, pbar_d="pd"), 500),
        (last_columns_problem(6, 14, 7), 500),
        (synthetic.random(R=20, M=50, rng=2), 150),
    ],
    ids=["paper_4x24", "8x12", "last_columns_6x14", "tracking_20x50"],
)
def test_numba_equals_scipy_reference(problem, k):
    a = murty(problem, k)
    b = murty(problem, k, backend="scipy")
    check_output(problem, a)
    assert_same_ranking(a, b, complete=False)


def test_uniform_ties_are_all_distinct():
    p = synthetic.uniform()
    r = murty(p, 5000)
    check_output(p, r)
    assert len(r.costs) == 5000 and np.all(r.costs == r.costs[0])


@pytest.mark.heavy_python
def test_paper_4x24_complete_ranking():
    p = synthetic.random(rng=1)
    full = enumerate_assignments(p)
    r = murty(p, 100_000)  # more than |Gamma| = 76 848
    assert_same_ranking(r, full, complete=True)


def test_deterministic():
    p = synthetic.random(R=6, M=10, rng=3)
    a, b = murty(p, 400), murty(p, 400)
    assert_array_equal(a.assignments, b.assignments)


def test_k_zero_and_degenerate_shapes():
    p = synthetic.diagonal()
    for method in METHODS:
        r = murty(p, 0, backend=method)
        assert r.assignments.shape == (0, 4) and r.costs.shape == (0,)
        e = murty(AssignmentProblem.from_cost(np.zeros((0, 2))), 3, backend=method)
        assert e.assignments.shape == (1, 0)
        assert_array_equal(e.costs, [0.0])
        m0 = AssignmentProblem.from_eta(np.zeros((2, 0)), [1.0, 0.5], [0.5, 0.25])
        assert_array_equal(murty(m0, 10, backend=method).assignments,
                           [[0, 1], [2, 1], [0, 3], [2, 3]])


@pytest.mark.parametrize(
    "k, exc, match",
    [
        (-1, ValueError, "k must be an int >= 0, got -1"),
        (1.0, TypeError, "k must be an int, got float 1.0"),
        (True, TypeError, "k must be an int, got bool True"),
        ("3", TypeError, "k must be an int, got str '3'"),
    ],
)
def test_bad_k(k, exc, match):
    with pytest.raises(exc, match=match):
        murty(synthetic.diagonal(), k)


def test_bad_method_and_problem():
    with pytest.raises(ValueError, match=r"backend must be one of \('numba', 'scipy'\), got 'x'"):
        murty(synthetic.diagonal(), 3, backend="x")
    with pytest.raises(TypeError, match="must be a rankedassign.AssignmentProblem.*got ndarray"):
        murty(synthetic.diagonal().cost, 3)
    assert murty(synthetic.diagonal(), np.int64(2)).costs.shape == (2,)


def test_huge_k_is_refused_with_the_bytes_it_would_need():
    # 30 x 30: |Gamma| ~ 6.3e37, so nothing caps k = 10**18; the search used to grow to
    # gigabytes before a MemoryError. 8 (4 P + ceil(P / 64) + 15) = 1088 bytes per assignment.
    p = synthetic.random(R=30, M=30, rng=0)
    msg = (r"^k = 1000000000000000000 is too large: 1000000000000000000 assignments need at "
           r"least 943\.7 EiB \(1088000000000000000000 bytes\) of Murty work arrays \(1088 "
           r"bytes each for P = 30 rows\), more than the limit of 4\.0 GiB \(4294967296 bytes\) "
           r"\(rankedassign\.validation\.MAX_WORK_BYTES\); the problem has "
           r"62773844750873636145663070102318219264 feasible assignments$")
    for method in METHODS:
        with pytest.raises(ValueError, match=msg):
            murty(p, 10**18, backend=method)
    # the first k beyond the limit (the bound is exact in k)
    k = MAX_WORK_BYTES // 1088 + 1
    with pytest.raises(ValueError, match=rf"^k = {k} is too large: {k} assignments need at "
                                         rf"least 4\.0 GiB \({k * 1088} bytes\)"):
        murty(p, k)
    # forbidden pairs and 30 rows: too costly to count, so k itself is judged
    C = p.cost.copy()
    C[0, 0] = np.inf
    q = AssignmentProblem.from_cost(C)
    with pytest.raises(ValueError, match=r"^k = 1000000000000000000 is too large: .*"
                                         r"\(rankedassign\.validation\.MAX_WORK_BYTES\)$"):
        murty(q, 10**18)


@pytest.mark.parametrize("method", METHODS)
def test_huge_k_on_a_small_problem_still_gives_every_assignment(method):
    # k beyond |Gamma| is documented to return all of them; a huge k is no exception, and
    # the output is that of any other k >= |Gamma| bit for bit (costs and tie order)
    for p in (AssignmentProblem.from_eta([[2.0, 0.5], [0.1, 3.0]], [0.2, 0.4], [0.1, 0.1]),
              last_columns_problem(3, 5, 0), synthetic.uniform(R=2, M=3)):
        n = p.n_feasible()
        want = murty(p, n + 5, backend=method)
        got = murty(p, 2**62, backend=method)
        assert len(got.costs) == n
        assert_array_equal(got.assignments, want.assignments)
        assert_array_equal(got.costs, want.costs)


def test_comparison_helper_detects_a_wrong_ranking():
    p = synthetic.random(R=3, M=4, rng=0)
    full = enumerate_assignments(p)
    wrong = full.assignments[:10].copy()
    wrong[3] = full.assignments[50]  # a worse assignment in place of a top-10 one
    with pytest.raises(AssertionError):
        assert_same_ranking((wrong, p.cost_of(wrong)), (full.assignments[:10], full.costs[:10]),
                            complete=False)


@pytest.mark.parametrize("seed", [67, 73, 89, 224, 243])
def test_every_prefix_is_the_k_best(seed):
    # regression: a lazily bounded child must never leave the queue after a worse solution
    # (these problems once lost their 10th-best assignment behind a too-high bound)
    p = synthetic.random(R=4, M=2, rng=seed)
    full = enumerate_assignments(p)
    for k in range(1, len(full.costs) + 1):
        assert_array_equal(murty(p, k).costs, full.costs[:k])


def test_gated_rows_and_huge_costs():
    # sparse rows (most pairs forbidden) with costs far apart in magnitude: exact, no big-M
    rng = np.random.default_rng(5)
    D = rng.uniform(-1e12, 1e12, (5, 7))
    D[rng.random((5, 7)) < 0.6] = np.inf
    p = AssignmentProblem.from_log_eta(-D, -rng.uniform(-1e12, 1e12, 5), np.full(5, -np.inf))
    full = enumerate_assignments(p)
    r = murty(p, len(full.costs))
    check_output(p, r)
    assert_same_ranking(r, full, complete=True)


def gated_problem(seed, P, M, frac, dead=True, integer=False):
    """Seeded sparse problem: a fraction ``frac`` of the measurement pairs forbidden (gating);
    ``dead=False`` forbids death too; ``integer`` costs make many ties."""
    rng = np.random.default_rng(seed)
    D = rng.integers(0, 3, (P, M)).astype(float) if integer else rng.uniform(-3.0, 5.0, (P, M))
    D[rng.random((P, M)) < frac] = np.inf
    miss = -np.ones(P) if integer else -rng.uniform(0.0, 3.0, P)
    death = -rng.uniform(0.0, 3.0, P) if dead else np.full(P, -np.inf)
    return AssignmentProblem.from_log_eta(-D, miss, death)


# Seeded problems on which the compiled kernel is pinned to the reference rankings: dense
# (every pair allowed), the GLMB layout (P = 20, M = 50) and gated ones, some with death
# forbidden or with integer costs (many ties). Small ones against enumeration, the others
# against the SciPy path (method="scipy"); expected values are never the kernel's own.
PINNED = [
    ("dense_6x6", lambda: synthetic.random(R=6, M=6, rng=3), 700, "enumerate"),
    ("dense_20x20", lambda: synthetic.random(R=20, M=20, rng=0), 100, "scipy"),
    ("glmb_20x50", lambda: synthetic.random(R=20, M=50, rng=0), 150, "scipy"),
    ("glmb_20x50_seed4", lambda: synthetic.random(R=20, M=50, rng=4), 100, "scipy"),
    ("gated_7x10", lambda: gated_problem(1, 7, 10, 0.6), 900, "enumerate"),
    ("gated_no_death_6x9", lambda: gated_problem(2, 6, 9, 0.5, dead=False), 1000, "enumerate"),
    ("gated_ties_6x9", lambda: gated_problem(12, 6, 9, 0.5, dead=False, integer=True), 400,
     "enumerate"),
    ("gated_18x40", lambda: gated_problem(3, 18, 40, 0.8), 200, "scipy"),
    ("gated_no_death_15x30", lambda: gated_problem(5, 15, 30, 0.7, dead=False), 200, "scipy"),
    ("rows_70x10", lambda: synthetic.random(R=70, M=10, rng=1), 40, "scipy"),  # > 64 rows
]


@pytest.mark.parametrize("name, make, k, source", PINNED, ids=[c[0] for c in PINNED])
def test_kernel_pinned_to_reference_rankings(name, make, k, source):
    p = make()
    if source == "enumerate":
        full = enumerate_assignments(p)
        kk = min(k, len(full.costs))
        want = (full.assignments[:kk], full.costs[:kk])
        complete = kk == len(full.costs)
    else:
        want = murty(p, k, backend="scipy")
        complete = False
    r = murty(p, k)
    check_output(p, r)
    assert_same_ranking(r, want, complete=complete)


# The order among equal costs is the kernel's documented one (order of creation of the
# nodes); these digests of the assignment arrays were taken from the kernel before its
# rewrite for speed, so the rewrite reproduces that order exactly, ties included.
TIE_ORDER_DIGESTS = [
    ("uniform", lambda: synthetic.uniform(), 500, "25bdf67713511a4c"),
    ("dense_20x20", lambda: synthetic.random(R=20, M=20, rng=0), 100, "f96e2a97b95b4028"),
    ("glmb_20x50", lambda: synthetic.random(R=20, M=50, rng=0), 1000, "0f2363ce5bb35b41"),
    ("paper", lambda: synthetic.random(rng=0), 3000, "6d9509bcfdc95284"),
    ("gated_ties_6x9", lambda: gated_problem(12, 6, 9, 0.5, dead=False, integer=True), 400,
     "8620fbc389174bd3"),
    ("rows_70x10", lambda: synthetic.random(R=70, M=10, rng=1), 300, "a43f6242649e37e3"),
    # taken before the cut at the k-th best solved cost, which drops most solves here
    ("square_20", lambda: square_problem(20, 0), 100, "da6c96b59ee5c720"),
    ("square_ties_10", lambda: square_problem(10, 1, integer=True), 400, "9673f5c01d59772e"),
]


@pytest.mark.parametrize("name, make, k, digest", TIE_ORDER_DIGESTS,
                         ids=[c[0] for c in TIE_ORDER_DIGESTS])
def test_kernel_order_among_ties_is_unchanged(name, make, k, digest):
    r = murty(make(), k)
    got = hashlib.sha256(np.ascontiguousarray(r.assignments, dtype="<i8").tobytes())
    assert got.hexdigest()[:16] == digest


@pytest.mark.parametrize("integer", [False, True], ids=["near_equal", "integer_ties"])
@pytest.mark.parametrize("seed", range(3))
def test_square_problems_against_enumeration(seed, integer):
    # the cut at the k-th best solved cost is active on almost every solve here
    p = square_problem(6, seed, integer=integer)
    full = enumerate_assignments(p)
    for k in (1, 7, 60, 400):
        r = murty(p, k)
        check_output(p, r)
        assert_same_ranking(r, (full.assignments[:k], full.costs[:k]), complete=False)


@pytest.mark.parametrize("make", [lambda: square_problem(12, 4), lambda: square_problem(9, 5, integer=True),
                                  lambda: synthetic.random(R=10, M=15, rng=6),
                                  lambda: gated_problem(13, 8, 10, 0.5, dead=False, integer=True)],
                         ids=["square", "square_ties", "random", "gated_ties"])
def test_fewer_wanted_is_a_prefix(make):
    # The cut depends on k (it drops what cannot be among the k best), the order does not:
    # asking for fewer gives the first ones, ties included. (Exactly, on these problems: the
    # final sort could only swap across the end two costs that differ in the last bit.)
    p = make()
    big = murty(p, 300)
    for k in (1, 2, 17, 120, 299):
        r = murty(p, k)
        assert_array_equal(r.assignments, big.assignments[:k])
        assert_array_equal(r.costs, big.costs[:k])

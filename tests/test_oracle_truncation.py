"""Truncation error (spec eq. 1.9) and best_mass."""

import numpy as np
import pytest
from cases import CASE_IDS, CASES, problems
from hypothesis import given
from hypothesis import strategies as st
from numpy.testing import assert_allclose
from scipy.special import logsumexp

from oracle import best_mass, enumerate_assignments, truncation_error
from oracle import log_normalizer as oracle_log_normalizer
from oracle.single import murty
from rankedassign import AssignmentProblem
from rankedassign.single import synthetic

#: The message of an object of no known problem kind (rankedassign.kinds.kind_of).
NOT_A_PROBLEM = (r"problem must be one of \(AssignmentProblem, MultiSensorProblem, "
                 r"AdaptiveBirthProblem\), got ")


def exact_weights(problem, assignments):
    """Weights relative to the best, from exact (Decimal) sums of the cost entries."""
    from decimal import Decimal, getcontext

    getcontext().prec = 50
    C = problem.cost
    costs = [sum((Decimal(float(C[i, j])) for i, j in enumerate(a)), Decimal(0))
             for a in assignments]
    low = min(costs)
    return [(-(c - low)).exp() for c in costs]


@pytest.mark.parametrize("name, problem", CASES, ids=CASE_IDS)
def test_cases_all_zero_best_and_monotone(name, problem):
    full = enumerate_assignments(problem)
    # zero up to the round-off of Z (relative ~1e-16 per term)
    assert_allclose(truncation_error(problem, full.assignments), 0.0, atol=1e-14)
    # Against the exact weights (Decimal sums of the exact double entries). The enumeration's
    # first assignment is the best only up to the rounding of cost_of: in "huge_range" (costs
    # of 1e9 and 1e-8 in one assignment) it is 1e-8 worse than the best, so its error is not
    # 1 - best_mass(1) exactly; the DP's ln Z there carries a relative 3e-9.
    w = exact_weights(problem, full.assignments)
    err1 = float(1 - w[0] / sum(w))
    assert_allclose(truncation_error(problem, full.assignments[:1]), err1, rtol=1e-8, atol=1e-12)
    assert_allclose(best_mass(problem, 1), float(max(w) / sum(w)), rtol=1e-12, atol=1e-14)
    assert truncation_error(problem, full.assignments[:1]) >= 1 - best_mass(problem, 1) - 1e-12
    # adding assignments never increases the error
    rng = np.random.default_rng(0)
    shuffled = full.assignments[rng.permutation(len(full.costs))]
    errs = [truncation_error(problem, shuffled[:n]) for n in range(len(shuffled) + 1)][:60]
    assert errs[0] == 1.0
    assert np.all(np.diff(errs) <= 1e-12)
    assert all(0.0 <= e <= 1.0 for e in errs)


@given(problems(), st.data())
def test_property_against_enumerated_weights(problem, data):
    full = enumerate_assignments(problem)
    n = len(full.costs)
    idx = data.draw(st.lists(st.integers(0, n - 1), max_size=12))  # duplicates allowed
    want = 1.0 - np.exp(logsumexp(-full.costs[np.unique(idx)]) - logsumexp(-full.costs)) \
        if idx else 1.0
    got = truncation_error(problem, full.assignments[idx].reshape(len(idx), problem.n_rows))
    assert_allclose(got, max(want, 0.0), rtol=1e-9, atol=1e-12)
    k = data.draw(st.integers(0, n + 2))
    assert_allclose(best_mass(problem, k), 1 - truncation_error(problem, full.assignments[:k]),
                    rtol=1e-9, atol=1e-12)


def test_duplicates_count_once_and_order_is_irrelevant():
    p = synthetic.random(R=4, M=6, rng=3)
    top = murty(p, 20).assignments
    e = truncation_error(p, top)
    assert_allclose(truncation_error(p, np.vstack([top, top[::-1], top[:5]])), e, rtol=1e-14)
    assert_allclose(truncation_error(p, top[::-1]), e, rtol=1e-14)
    assert truncation_error(p, top[0]) == truncation_error(p, top[:1])  # a single (P,) row


def test_paper_diagonal_best_holds_99_577_percent():
    # spec §1.6 [verified]: the best solution of the diagonal matrix carries 99.577 % of Z
    p = synthetic.diagonal()
    assert_allclose(best_mass(p, 1), 0.99577, atol=5e-6)
    assert_allclose(truncation_error(p, [[0, 1, 2, 3]]), 1 - best_mass(p, 1), rtol=1e-10)


def test_uniform_error_is_the_missing_fraction():
    p = synthetic.uniform()
    a = enumerate_assignments(p).assignments
    assert_allclose(truncation_error(p, a[:1000]), 1 - 1000 / 76_848, rtol=1e-12)
    assert_allclose(best_mass(p, 1000), 1000 / 76_848, rtol=1e-12)


def test_beyond_enumeration_uses_the_dp():
    p = synthetic.random(R=10, M=30, rng=1)  # |Gamma| ~ 1e14: Murty + DP path of best_mass
    top = murty(p, 200)
    e = truncation_error(p, top.assignments)
    assert 0.0 < e < 1.0
    assert_allclose(e, 1 - best_mass(p, 200), rtol=1e-12)
    masses = [best_mass(p, k) for k in (1, 10, 100)]
    assert masses[0] < masses[1] < masses[2] < 1 - e + 1e-15


def test_best_mass_edges():
    p = synthetic.random(R=2, M=3, rng=0)
    n = p.n_feasible()
    assert best_mass(p, 0) == 0.0
    assert best_mass(p, n) == pytest.approx(1.0, abs=1e-14)
    assert best_mass(p, 10 * n) == pytest.approx(1.0, abs=1e-14)
    with pytest.raises(ValueError, match="k must be an int >= 0, got -2"):
        best_mass(p, -2)
    with pytest.raises(TypeError, match="k must be an int, got float"):
        best_mass(p, 2.0)


def test_degenerate_shapes():
    empty = AssignmentProblem.from_cost(np.zeros((0, 3)))
    assert truncation_error(empty, np.zeros((1, 0), dtype=int)) == 0.0
    assert truncation_error(empty, np.zeros((0, 0), dtype=int)) == 1.0
    assert best_mass(empty, 1) == 1.0
    no_meas = AssignmentProblem.from_eta(np.zeros((2, 0)), [1.0, 3.0], [1.0, 1.0])
    assert_allclose(truncation_error(no_meas, [[0, 1]]), 1 - 3 / 8, rtol=1e-14)


def test_infeasible_assignment_names_its_row():
    p = AssignmentProblem.from_eta([[2.0, 0.5], [0.1, 3.0]], [0.2, 0.3], [0.1, 0.1])
    with pytest.raises(ValueError, match=r"assignment 2 \(row 2 of the input\), columns "
                                         r"\[0, 0\], is infeasible"):
        truncation_error(p, [[0, 1], [1, 0], [0, 0]])
    with pytest.raises(ValueError, match=r"assignment 0 \(row 0 of the input\), columns "
                                         r"\[3, 1\], is infeasible"):
        truncation_error(p, [[3, 1]])  # column 3 is row 1's missed column
    with pytest.raises(ValueError, match=r"assignment 1 \(row 1 of the input\)"):
        truncation_error(p, [[0, 1], [0, 9]])  # out of range


def test_bad_input_types_and_sizes():
    p = synthetic.diagonal()
    with pytest.raises(ValueError, match=r"must have shape \(n, P\) = \(n, 4\)"):
        truncation_error(p, [[0, 1, 2]])
    with pytest.raises(TypeError, match="integer array of column indices"):
        truncation_error(p, [[0.5, 1, 2, 3]])
    with pytest.raises(TypeError, match=NOT_A_PROBLEM + r"str"):
        truncation_error("p", [[0, 1, 2, 3]])
    with pytest.raises(TypeError, match=NOT_A_PROBLEM + r"NoneType"):
        best_mass(None, 3)
    with pytest.raises(ValueError, match="too large for the exact subset DP"):
        truncation_error(synthetic.random(R=21, M=21, rng=0), np.arange(21)[None, :])


def test_falls_back_to_enumeration_when_the_dp_refuses():
    # 21 rows that must take "their" measurement (5 may also be missed) plus one measurement
    # every row can take: one connected component with min(P, M) = 21 and frontier width 21,
    # beyond both DPs, but |Gamma| = 624 is small enough to enumerate
    P = 21
    M = P + 1
    C = np.full((P, M + 2 * P), np.inf)
    C[np.arange(P), np.arange(P)] = np.linspace(-2, 2, P)
    C[:, P] = 1.0
    C[np.arange(5), M + np.arange(5)] = 0.5
    p = AssignmentProblem.from_cost(C)
    with pytest.raises(ValueError, match="too large for the exact subset DP"):
        oracle_log_normalizer(p)
    full = enumerate_assignments(p)
    assert len(full.costs) == 624
    want = 1 - np.exp(logsumexp(-full.costs[:3]) - logsumexp(-full.costs))
    assert_allclose(truncation_error(p, full.assignments[:3]), want, rtol=1e-12)
    assert_allclose(best_mass(p, 3), 1 - want, rtol=1e-12)


# ------------------------------------------------------------------ both ends of the cost range
def test_costs_at_the_overflow_limit():
    # The hardening issue: costs of +-1e308 were accepted, their sum overflowed, and a
    # feasible assignment was called infeasible. Such costs are now refused by the problem
    # (see test_problem); at the limit (rows' largest |cost| summing to 2**1020) every oracle
    # answer is exact.
    inf = np.inf
    h = 2.0**1019
    # all finite entries equal: the distribution is uniform on the 8 feasible assignments
    p = AssignmentProblem.from_cost([[-h, -h, inf, -h, inf], [-h, inf, -h, inf, -h]])
    full = enumerate_assignments(p)
    assert len(full.costs) == 8 and np.isfinite(full.costs).all()
    assert_allclose(oracle_log_normalizer(p), 2 * h, rtol=1e-15)  # ln(8 e^(2h)) = 2h + ln 8
    for k in range(9):
        assert_allclose(truncation_error(p, full.assignments[:k]), 1 - k / 8, rtol=1e-14,
                        atol=1e-15)
    assert_allclose(best_mass(p, 3), 3 / 8, rtol=1e-14)
    # +h costs weigh exp(-h) = 0 against the rest; -h costs dominate everything else
    hi = AssignmentProblem.from_cost([[h, 0.0, inf, 1.0, inf], [0.0, inf, h, inf, 1.0]])
    lo = AssignmentProblem.from_cost([[-h, 0.0, inf, 1.0, inf], [0.0, inf, -h, inf, 1.0]])
    z_hi = 1 + 2 * np.exp(-1) + np.exp(-2)  # the four assignments without an h entry
    assert_allclose(truncation_error(hi, [[1, 4], [0, 4]]), 1 - np.exp(-1) / z_hi, rtol=1e-14)
    assert truncation_error(hi, [[0, 2]]) == 1.0  # cost h: weight 0, but feasible
    assert truncation_error(lo, [[1, 2]]) == 1.0  # cost -h: all but the best
    assert truncation_error(lo, [[0, 2]]) == 0.0  # the best, cost -2h, holds all the mass
    assert best_mass(lo, 1) == 1.0


def test_subnormal_costs():
    tiny = 5e-324
    p = AssignmentProblem.from_cost([[tiny, -tiny, np.inf, 0.0, np.inf],
                                     [0.0, np.inf, tiny, np.inf, 0.0]])
    full = enumerate_assignments(p)
    assert len(full.costs) == 8
    # every weight is 1 to double precision
    for k in range(9):
        assert_allclose(truncation_error(p, full.assignments[:k]), 1 - k / 8, rtol=1e-14,
                        atol=1e-15)

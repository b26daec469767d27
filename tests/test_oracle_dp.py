"""Exact normaliser and marginals against enumeration and the per-pair formula.

The sparse (frontier DP) path and the decomposition into components: test_oracle_sparse.py.
"""

import naive
import numpy as np
import pytest
from cases import CASE_IDS, CASES, marginal_atol, problems
from hypothesis import given
from numpy.testing import assert_allclose
from scipy.special import logsumexp

from oracle import enumerate_assignments, log_normalizer, marginals
from rankedassign import AssignmentProblem
from rankedassign.single import synthetic

#: The message of an object of no known problem kind (rankedassign.kinds.kind_of).
NOT_A_PROBLEM = (r"problem must be one of \(AssignmentProblem, MultiSensorProblem, "
                 r"AdaptiveBirthProblem\), got ")


def enumerated_marginals(problem):
    """Marginals by summing π over the oracle's enumeration (itself held to brute force)."""
    return naive.marginals(problem, enumerate_assignments(problem).assignments)


def pairwise_marginals(problem):
    """Spec eq. (5.2) literally: ``eta_i(j) Z_{-i,-j} / Z`` with one DP per removed pair."""
    cc = problem.compact_cost
    P, M = problem.n_rows, problem.n_meas
    log_z = log_normalizer(problem)

    def sub_log_z(rows, meas):
        sub = cc[np.ix_(rows, list(meas) + [M, M + 1])]
        m = len(meas)
        return log_normalizer(AssignmentProblem.from_log_eta(-sub[:, :m], -sub[:, m],
                                                             -sub[:, m + 1]))

    out = np.zeros((P, M + 2))
    for i in range(P):
        rows = [r for r in range(P) if r != i]
        z_i = sub_log_z(rows, range(M))
        for j in range(M):
            if np.isfinite(cc[i, j]):
                z_ij = sub_log_z(rows, [t for t in range(M) if t != j])
                out[i, j] = np.exp(-cc[i, j] + z_ij - log_z)
        out[i, M] = np.exp(-cc[i, M] + z_i - log_z)
        out[i, M + 1] = np.exp(-cc[i, M + 1] + z_i - log_z)
    return out


@pytest.mark.parametrize("name, problem", CASES, ids=CASE_IDS)
def test_cases_against_enumeration(name, problem):
    costs = enumerate_assignments(problem).costs
    assert_allclose(log_normalizer(problem), logsumexp(-costs), rtol=1e-10, atol=1e-12)
    m = marginals(problem)
    assert m.shape == (problem.n_rows, problem.n_meas + 2)
    assert_allclose(m, enumerated_marginals(problem), rtol=0, atol=marginal_atol(problem))
    assert_allclose(m.sum(axis=1), 1.0, rtol=1e-14)


@given(problems())
def test_property_against_enumeration(problem):
    costs = enumerate_assignments(problem).costs
    assert_allclose(log_normalizer(problem), logsumexp(-costs), rtol=1e-10, atol=1e-12)
    assert_allclose(marginals(problem), enumerated_marginals(problem), rtol=0, atol=1e-12)


@pytest.mark.parametrize("R, M", [(7, 9), (9, 6)])  # DP over rows and over measurements
def test_against_pairwise_formula(R, M):
    p = synthetic.random(R=R, M=M, rng=R * M)
    assert_allclose(marginals(p), pairwise_marginals(p), rtol=1e-9, atol=1e-14)


def test_paper_values():
    # spec §1.6: diagonal Z = 5.3442e6; uniform: 76 848 assignments of cost 4 * 0.5
    assert_allclose(np.exp(log_normalizer(synthetic.diagonal())), 5.3442e6, rtol=1e-4)
    assert_allclose(log_normalizer(synthetic.uniform()), np.log(76_848) - 2.0, rtol=1e-13)


@pytest.mark.parametrize("seed", [0, 1])
def test_rows_sum_to_one_and_measurements_at_most_one(seed):
    p = synthetic.random(R=12, M=30, rng=seed)
    m = marginals(p)
    assert_allclose(m.sum(axis=1), 1.0, rtol=1e-13)
    assert np.all(m >= 0)
    assert np.all(m[:, : p.n_meas].sum(axis=0) <= 1 + 1e-12)


def test_no_underflow_when_only_tiny_terms_matter():
    # rows 0 and 1 both want measurement 1; everything else costs 800 nats more, so
    # Z ~ 2 exp(-800): a DP with plain per-row shifts underflows to ln Z = -inf
    p = AssignmentProblem.from_cost(
        [[0.0, np.inf, 800.0, np.inf, 900.0, np.inf], [0.0, 850.0, np.inf, 800.0, np.inf, 900.0]]
    )
    want = logsumexp(-enumerate_assignments(p).costs)
    assert_allclose(log_normalizer(p), want, rtol=1e-13)
    assert_allclose(marginals(p), enumerated_marginals(p), atol=1e-12)


def test_huge_negative_costs_do_not_overflow():
    rng = np.random.default_rng(5)
    p = AssignmentProblem.from_log_eta(rng.uniform(1e5, 1e5 + 50, (3, 4)), [1e5] * 3,
                                       [2e5, 0.0, -1e5])
    want = logsumexp(-enumerate_assignments(p).costs)
    assert_allclose(log_normalizer(p), want, rtol=1e-13)
    assert_allclose(marginals(p), enumerated_marginals(p), atol=1e-12)


def test_unreachable_measurements_get_zero():
    p = AssignmentProblem.from_cost(
        [[0.5, np.inf, 1.0, 1.0, np.inf, 2.0, np.inf], [np.inf, np.inf, 0.2, np.inf, 1.0,
                                                        np.inf, 0.1]]
    )
    m = marginals(p)
    assert m[:, 1].tolist() == [0.0, 0.0]
    assert_allclose(m, enumerated_marginals(p), atol=1e-12)


def test_degenerate_shapes():
    empty = AssignmentProblem.from_cost(np.zeros((0, 5)))
    assert log_normalizer(empty) == 0.0
    assert marginals(empty).shape == (0, 7)
    p = AssignmentProblem.from_eta(np.zeros((2, 0)), [1.0, 3.0], [1.0, 1.0])
    assert_allclose(log_normalizer(p), np.log(2.0 * 4.0), rtol=1e-14)
    assert_allclose(marginals(p), [[0.5, 0.5], [0.75, 0.25]], rtol=1e-14)


def test_size_limit_message():
    big = synthetic.random(R=21, M=21, rng=0)
    # every pair finite: every row is active at every step, so the frontier is 21 too
    with pytest.raises(ValueError, match=r"too large for the exact subset DP: min\(P, M\) = "
                                         r"min\(21, 21\) = 21 > 20 in a connected component, "
                                         r"and for the frontier DP: frontier width 21 > 20"):
        log_normalizer(big)
    with pytest.raises(ValueError, match="too large for the exact subset DP"):
        marginals(big)


def test_transposed_dp_handles_many_rows():
    p = synthetic.random(R=30, M=3, rng=4)  # 30 rows, only 3 measurements: DP over 2^3
    m = marginals(p)
    assert_allclose(m.sum(axis=1), 1.0, rtol=1e-13)
    assert np.isfinite(log_normalizer(p))


@pytest.mark.parametrize("fn", [log_normalizer, marginals])
def test_not_a_problem(fn):
    with pytest.raises(TypeError, match=NOT_A_PROBLEM + r"list"):
        fn([[0.0, 1.0, 2.0]])


def permuted(problem, rows, meas):
    """The same problem with rows and measurements relabelled."""
    cc = problem.compact_cost
    M = problem.n_meas
    sub = cc[np.ix_(rows, list(meas) + [M, M + 1])]
    return AssignmentProblem.from_log_eta(-sub[:, :M], -sub[:, M], -sub[:, M + 1])


@pytest.mark.parametrize("R, M", [(10, 14), (13, 8)])
def test_permutation_equivariance(R, M):
    p = synthetic.random(R=R, M=M, rng=R + M)
    rng = np.random.default_rng(0)
    rows, meas = rng.permutation(R), rng.permutation(M)
    q = permuted(p, rows, meas)
    assert_allclose(log_normalizer(q), log_normalizer(p), rtol=1e-13)
    mp, mq = marginals(p), marginals(q)
    assert_allclose(mq, mp[np.ix_(rows, list(meas) + [M, M + 1])], rtol=1e-10, atol=1e-15)


@pytest.mark.slow
def test_largest_sizes():
    # P = 20, M = 200 (2^20 states, 200 steps) and the transposed M = 20, P = 60
    p = synthetic.random(R=20, M=200, rng=0)
    rng = np.random.default_rng(1)
    q = permuted(p, rng.permutation(20), rng.permutation(200))
    assert_allclose(log_normalizer(q), log_normalizer(p), rtol=1e-12)
    t = synthetic.random(R=60, M=20, rng=2)
    m = marginals(t)
    assert_allclose(m.sum(axis=1), 1.0, rtol=1e-12)
    assert np.all(m[:, :20].sum(axis=0) <= 1 + 1e-12)

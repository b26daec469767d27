"""Statistical tests: the samplers draw from the right distributions.

The exact one-sweep transition matrix ``K`` of the Gibbs chain is computed here by brute force
on problems small enough to enumerate the feasible set ``Gamma`` (no dependence on the oracle
package). Then

* ``pi K = pi`` checks the algebra (``pi = w / Z`` is stationary for both scans);
* the visit counts of one long original chain are compared with ``n pi`` through the Markov
  chain central limit theorem, whose covariance is exact here (Kemeny & Snell's fundamental
  matrix), so no thinning or effective-sample-size guess is needed;
* the visit counts of many independent short chains (no termination) are compared with their
  exact finite-time expectation ``N sum_j delta_x0 K^j`` and exact covariance: the chains are
  i.i.d., so this is the ordinary multivariate CLT.

Each statistic is asymptotically chi-square with ``|Gamma| - 1`` degrees of freedom (the
counts sum to a constant); the threshold is the ``1 - 1e-6`` quantile, so each assertion
fails with probability about 1e-6 for a correct sampler (the seeds are fixed, so the tests
are deterministic; a failure means a bias of a few standard errors, not bad luck).
"""

import itertools

import numpy as np
import pytest
from naive import compact_states as enumerate_gamma
from numpy.testing import assert_allclose
from scipy import stats

from rankedassign import AssignmentProblem, sample_original, sample_short_chains
from rankedassign.single import prepare as single_prepare

FALSE_FAILURE = 1e-6
INF = np.inf


def target(problem, states):
    cc = problem.compact_cost
    logw = np.array([-sum(cc[i, k] for i, k in enumerate(x)) for x in states])
    w = np.exp(logw - logw.max())
    return w / w.sum()


def row_conditional(problem, x, i):
    """Spec eq. (2.1): p(k) ∝ eta_i(k) over k finite and not held by another row."""
    cc = problem.compact_cost
    M = problem.n_meas
    held = {x[r] for r in range(len(x)) if r != i and x[r] < M}
    ks = [k for k in range(M + 2) if np.isfinite(cc[i, k]) and k not in held]
    c = np.array([cc[i, k] for k in ks])
    p = np.exp(-(c - c.min()))
    return ks, p / p.sum()


def sweep_matrix(problem, states, order):
    """Exact transition matrix of one Gauss-Seidel sweep visiting rows in ``order``."""
    index = {x: n for n, x in enumerate(states)}
    K = np.zeros((len(states), len(states)))
    for a, x in enumerate(states):
        dist = {x: 1.0}
        for i in order:
            new = {}
            for y, q in dist.items():
                ks, p = row_conditional(problem, y, i)
                for k, pk in zip(ks, p, strict=True):
                    z = y[:i] + (k,) + y[i + 1:]
                    new[z] = new.get(z, 0.0) + q * pk
            dist = new
        for y, q in dist.items():
            K[a, index[y]] += q
    return K


def transition(problem, states, scan):
    P = problem.n_rows
    if scan == "systematic":
        return sweep_matrix(problem, states, range(P))
    perms = list(itertools.permutations(range(P)))
    return sum(sweep_matrix(problem, states, o) for o in perms) / len(perms)


def visit_counts(problem, res, states):
    index = {x: n for n, x in enumerate(states)}
    counts = np.zeros(len(states))
    compact = single_prepare.to_compact(problem, res.assignments)
    for x, c in zip(map(tuple, compact.tolist()), res.counts, strict=True):
        counts[index[x]] += c
    return counts


def chi2_statistic(dev, cov):
    """``dev' cov^+ dev`` and the rank of ``cov`` (its null space: the constant total)."""
    evals, evecs = np.linalg.eigh(cov)
    keep = evals > 1e-10 * evals.max()
    z = evecs[:, keep].T @ dev
    return float(np.sum(z**2 / evals[keep])), int(keep.sum())


def _wide(rows_allowed, M, seed):
    """``len(rows_allowed)`` rows over ``M > max(M_DIRECT, 2 P)`` measurements (prefix-sum draws), each row
    allowed only the measurements listed (the rest gated out, so runs of zero weight)."""
    rng = np.random.default_rng(seed)
    D = np.full((len(rows_allowed), M), INF)
    for i, allowed in enumerate(rows_allowed):
        D[i, allowed] = rng.uniform(-1.5, 1.5, len(allowed))
    miss = rng.uniform(-0.5, 0.5, len(rows_allowed))
    dead = rng.uniform(-0.5, 0.5, len(rows_allowed))
    return AssignmentProblem.from_cost(AssignmentProblem._assemble(D, miss, dead))


PROBLEMS = {
    # P = 2, M = 2, every pair allowed: |Gamma| = 14
    "2x2": AssignmentProblem.from_eta([[2.0, 0.5], [0.7, 3.0]], [0.6, 0.3], [0.4, 0.5]),
    # P = 3, M = 2, gated-out pairs, a row that cannot die, costs of both signs: |Gamma| = 22
    "3x2-gated": AssignmentProblem.from_eta(
        [[1.5, 0.0], [0.8, 2.5], [0.0, 1.2]], [0.5, 0.9, 0.4], [0.3, 0.0, 0.6]
    ),
    # M = 40 > max(M_DIRECT, 2 P): prefix-sum draws with held measurements between free runs
    "3x40-prefix": _wide([[0, 7, 20, 39], [0, 20, 33], [7, 33, 39]], 40, seed=3),
}


@pytest.mark.parametrize("name", sorted(PROBLEMS))
@pytest.mark.parametrize("scan", ["systematic", "random"])
def test_target_is_stationary_for_the_sweep(name, scan):
    p = PROBLEMS[name]
    states = enumerate_gamma(p)
    assert len(states) == p.n_feasible()
    K = transition(p, states, scan)
    assert_allclose(K.sum(axis=1), 1.0, rtol=1e-12)
    pi = target(p, states)
    assert_allclose(pi @ K, pi, rtol=1e-11, atol=1e-15)


@pytest.mark.parametrize("name", sorted(PROBLEMS))
@pytest.mark.parametrize("scan", ["systematic", "random"])
def test_original_chain_visits_match_target(name, scan):
    p = PROBLEMS[name]
    states = enumerate_gamma(p)
    K = transition(p, states, scan)
    pi = target(p, states)
    n = 200_000
    res = sample_original(p, n, scan=scan, rng=20230615)
    counts = visit_counts(p, res, states)
    # Markov-chain CLT: (counts - n pi) / sqrt(n) -> N(0, S) with (Kemeny & Snell)
    # S_ab = pi_a Z_ab + pi_b Z_ba - pi_a delta_ab - pi_a pi_b,  Z = (I - K + 1 pi')^-1.
    # The start state shifts the counts by O(1), negligible against sqrt(n).
    s = len(states)
    Z = np.linalg.inv(np.eye(s) - K + np.outer(np.ones(s), pi))
    S = pi[:, None] * Z + (pi[:, None] * Z).T - np.diag(pi) - np.outer(pi, pi)
    t, dof = chi2_statistic((counts - n * pi) / np.sqrt(n), S)
    assert dof == s - 1
    assert t < stats.chi2.isf(FALSE_FAILURE, dof), (t, dof)


@pytest.mark.parametrize("name", sorted(PROBLEMS))
@pytest.mark.parametrize("scan", ["systematic", "random"])
def test_short_chain_visits_match_exact_finite_time_law(name, scan):
    p = PROBLEMS[name]
    states = enumerate_gamma(p)
    index = {x: n for n, x in enumerate(states)}
    K = transition(p, states, scan)
    N, L = 20_000, 6
    res = sample_short_chains(p, N, L, scan=scan, rng=7, workers=2)
    assert res.n_observations == N * L
    counts = visit_counts(p, res, states)
    # One chain's visit vector V = sum_{j=1..L} e_{x_j}, x_0 = all missed:
    #   E V = sum_j p_j,   p_j = delta_x0 K^j
    #   E V V' = sum_j diag(p_j) + sum_{j<j'} (diag(p_j) K^(j'-j) + its transpose)
    s = len(states)
    p_j = [np.eye(s)[index[tuple(single_prepare.to_compact(p, p.all_missed()).tolist())]]]
    for _ in range(L):
        p_j.append(p_j[-1] @ K)
    mean = sum(p_j[1:])
    second = sum(np.diag(p_j[j]) for j in range(1, L + 1))
    for j in range(1, L + 1):
        for jj in range(j + 1, L + 1):
            A = np.diag(p_j[j]) @ np.linalg.matrix_power(K, jj - j)
            second = second + A + A.T
    cov = second - np.outer(mean, mean)
    # the N chains are i.i.d. (one stream each): counts ~ N(N mean, N cov)
    t, dof = chi2_statistic((counts - N * mean) / np.sqrt(N), cov)
    assert dof == s - 1
    assert t < stats.chi2.isf(FALSE_FAILURE, dof), (t, dof)
    # after a burn-in of L sweeps the per-sweep law is close to pi (the chain mixes fast)
    assert_allclose(p_j[L], target(p, states), atol=0.02)


def test_underflow_fallback_draws_exact_conditional():
    # Row 1 holds measurement 0 for good (cost -2000); row 0's cheapest entry is that same
    # measurement, so every draw of row 0 takes the exact-weight fall-back over its available
    # entries (measurement 1, missed, dead) with weights (1, 1, e^-1). Given row 1, the draws
    # of row 0 are i.i.d. across sweeps: Pearson chi-square with 2 degrees of freedom.
    C = np.array([
        [-800.0, 0.0, 0.0, INF, 1.0, INF],
        [-2000.0, 0.0, INF, 0.0, INF, 0.0],
    ])
    p = AssignmentProblem.from_cost(C)
    n = 30_000
    res = sample_original(p, n, start=[2, 0], rng=3)
    observed = np.array([res.counts[res.assignments[:, 0] == c].sum() for c in (1, 2, 4)])
    assert observed.sum() == n
    expected = n * np.array([1.0, 1.0, np.exp(-1.0)]) / (2.0 + np.exp(-1.0))
    t = float(np.sum((observed - expected) ** 2 / expected))
    assert t < stats.chi2.isf(FALSE_FAILURE, 2), t


@pytest.mark.parametrize("name", sorted(PROBLEMS))
@pytest.mark.parametrize("beta", [0.5, 0.8])
def test_tempered_chain_is_stationary_for_and_visits_pi_to_the_beta(name, beta):
    # the exact sweep matrix of the conditionals raised to beta, built from the costs times
    # beta here (independently of the sampler's tempering); pi^beta is stationary for it, and
    # the visits of sample_original(..., beta=beta) follow the Markov-chain CLT around it
    p = PROBLEMS[name]
    hot = AssignmentProblem(p.cost * beta)
    states = enumerate_gamma(p)
    K = transition(hot, states, "systematic")
    pi_beta = target(p, states) ** beta
    pi_beta /= pi_beta.sum()
    assert_allclose(target(hot, states), pi_beta, rtol=1e-11)
    assert_allclose(pi_beta @ K, pi_beta, rtol=1e-11, atol=1e-15)
    n = 200_000
    res = sample_original(p, n, rng=20230615, beta=beta)
    assert_allclose(res.costs, p.cost_of(res.assignments))  # the problem's own costs
    counts = visit_counts(p, res, states)
    s = len(states)
    Z = np.linalg.inv(np.eye(s) - K + np.outer(np.ones(s), pi_beta))
    S = pi_beta[:, None] * Z + (pi_beta[:, None] * Z).T - np.diag(pi_beta) - np.outer(
        pi_beta, pi_beta)
    t, dof = chi2_statistic((counts - n * pi_beta) / np.sqrt(n), S)
    assert dof == s - 1
    assert t < stats.chi2.isf(FALSE_FAILURE, dof), (t, dof)

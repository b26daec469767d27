"""Stationary laws of the multi-sensor samplers, against exact transition matrices (spec §6.4,
§6.6).

Two kinds of check:

* exact algebra (:mod:`oracle.multisensor.transition`, built from each conditional's mathematics, not from
  the sampler code): ``"exact"`` leaves ``pi`` invariant, ``"componentwise"`` the collapsed
  ``pi'``, ``"mm"`` its surrogate ``pi~`` (``s_n -> s_n^V`` with ``survival_power="V"``);
  on the separable random family ``pi~ = pi``; ``"mm-fixed"`` has a stationary law ``mu`` that
  no single-row kernel leaves invariant;
* statistics: the kernels' chains are run as many independent chains from one start state, and
  the state after ``t`` sweeps is compared by a chi-square test with the oracle's exact law
  ``delta_{x0} K^t`` (independent draws, so the multinomial test is exact). Each test uses a
  fixed seed (deterministic outcome); its false-failure probability — the chance that a correct
  sampler fails it for a random seed — is the stated p-value threshold.
"""

import dataclasses

import numpy as np
import pytest
from ms_standin import random_problem
from numpy.testing import assert_allclose
from scipy.stats import chi2_contingency, chisquare

from oracle.multisensor.transition import (
    multisensor_states,
    row_kernels,
    stationary_distribution,
    target_distribution,
    transition_matrix,
)
from rankedassign import kinds
from rankedassign.engine._kernels import chain_state, zobrist_keys
from rankedassign.multisensor import _kernels as K
from rankedassign.multisensor.prepare import METHODS, prepare_data, start_state

# p-value threshold of every chi-square test below = its false-failure probability
ALPHA = 1e-4

SHAPES = [(2, (2, 2)), (2, (1, 1, 1)), (3, (1, 2))]


def _key(states):
    return {tuple(s.reshape(-1).tolist()): i for i, s in enumerate(states)}


# ------------------------------------------------------------------------------ exact algebra
def test_state_count_matches_spec_formula():
    # spec eq. 1.7 and §6.6: P = 2, M = (2, 2) has |Gamma| = 68
    assert len(multisensor_states(random_problem(2, (2, 2), 0))) == 68
    # collapsed: |Gamma'| = prod_v N(P, M_v) = 7 * 7
    assert len(multisensor_states(random_problem(2, (2, 2), 0), collapsed=True)) == 49


@pytest.mark.parametrize("P, M", SHAPES)
@pytest.mark.parametrize("kind", ["separable", "coupled"])
@pytest.mark.parametrize("scan", ["systematic", "random"])
def test_exact_and_componentwise_leave_pi_invariant(P, M, kind, scan):
    problem = random_problem(P, M, 3, kind)
    for method in ("exact", "componentwise"):
        Kmat, states = transition_matrix(problem, method, scan=scan)
        assert_allclose(Kmat.sum(axis=1), 1.0, rtol=1e-13)
        pi = target_distribution(problem, states, method)
        assert_allclose(pi @ Kmat, pi, atol=1e-14)
        for Kn in row_kernels(problem, method)[0]:  # every single-row update, too
            assert_allclose(pi @ Kn, pi, atol=1e-14)
        assert_allclose(stationary_distribution(Kmat), pi, atol=1e-12)


@pytest.mark.parametrize("P, M", SHAPES)
@pytest.mark.parametrize("power", [1, "V"])
def test_mm_leaves_its_surrogate_invariant(P, M, power):
    problem = random_problem(P, M, 4, "coupled")
    Kmat, states = transition_matrix(problem, "mm", survival_power=power)
    pit = target_distribution(problem, states, "mm", survival_power=power)
    assert_allclose(stationary_distribution(Kmat), pit, atol=1e-12)
    # on a coupled problem the surrogate is not pi (spec §3.1)
    pi = target_distribution(problem, states, "exact")
    assert 0.5 * np.abs(pi - pit).sum() > 1e-3


@pytest.mark.parametrize("P, M", SHAPES)
def test_on_the_separable_family_mm_targets_pi(P, M):
    problem = random_problem(P, M, 5, "separable")
    Kmm, states = transition_matrix(problem, "mm")
    Kex, _ = transition_matrix(problem, "exact", states=states)
    pi = target_distribution(problem, states, "exact")
    assert_allclose(target_distribution(problem, states, "mm"), pi, rtol=1e-12)
    assert_allclose(stationary_distribution(Kmm), pi, atol=1e-12)
    assert_allclose(stationary_distribution(Kex), pi, atol=1e-12)


def test_mm_fixed_is_not_a_gibbs_sampler_of_its_stationary_law():
    # spec §3.4: mu is unique, but single-row kernels do not leave it invariant
    problem = random_problem(2, (2, 2), 6, "coupled")
    Kmat, states = transition_matrix(problem, "mm-fixed")
    mu = stationary_distribution(Kmat)
    assert_allclose(mu @ Kmat, mu, atol=1e-13)
    assert mu.min() >= 0 and abs(mu.sum() - 1) < 1e-12
    kernels, _ = row_kernels(problem, "mm-fixed", states=states)
    assert max(np.abs(mu @ Kn - mu).max() for Kn in kernels) > 1e-4
    pit = target_distribution(problem, states, "mm")
    assert 0.5 * np.abs(mu - pit).sum() > 1e-3  # and it is not pi~


# ------------------------------------------------------------------------------ statistics
def run_independent_chains(problem, method, scan, power, start, n_chains, t, seed):
    """Final states (as tuples) of ``n_chains`` independent chains of ``t`` kernel sweeps.

    Each chain is one call of :func:`~rankedassign.multisensor._kernels.run_sweeps` (its ``t``
    sweeps in compiled code, from a fresh work slab), not ``t`` calls of the sweep from Python:
    the same states, one call instead of ``t`` per chain (20 000 chains of 30 sweeps took 6 s
    of calls from Python).
    """
    data = prepare_data(problem, method, scan, power)
    x0 = start_state(problem, start, method)
    zk = zobrist_keys(len(x0), max(problem.n_meas) + 2, np.uint64(1))
    return [tuple(K.run_sweeps(data, zk, x0, np.uint64(chain_state(np.uint64(seed), c)), t)[0]
                  .tolist())
            for c in range(n_chains)]


def chi_square_p(samples, states, law):
    """p-value of the multinomial chi-square of ``samples`` against ``law`` on ``states``
    (bins with expected count < 5 pooled into one)."""
    index = _key(states + 1)  # states are gamma; samples are gamma + 1
    obs = np.zeros(len(states))
    for s in samples:
        obs[index[s]] += 1
    exp = law * len(samples)
    small = exp < 5
    if small.any():
        obs = np.append(obs[~small], obs[small].sum())
        exp = np.append(exp[~small], exp[small].sum())
    keep = exp > 0
    assert obs[~keep].sum() == 0  # nothing sampled where the law is 0
    return chisquare(obs[keep], exp[keep]).pvalue


@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("scan", ["systematic", "random"])
def test_kernel_matches_the_exact_transition_matrix(method, scan):
    # N = 20 000 independent chains, t = 2 sweeps, from two starts; chi-square at ALPHA
    problem = random_problem(2, (2, 2), 8, "coupled")
    Kmat, states = transition_matrix(problem, method, scan=scan)
    index = _key(states + 1)
    for start in ("all_missed", [[2, 1], [-1, -1]] if method != "componentwise" else [[2, 1],
                                                                                        [0, 0]]):
        x0 = start_state(problem, start, method)
        law = np.linalg.matrix_power(Kmat, 2)[index[tuple(x0.tolist())]]
        samples = run_independent_chains(problem, method, scan, 1, start, 20_000, 2, 17)
        assert chi_square_p(samples, states, law) > ALPHA


def test_mm_with_survival_power_v_matches_its_matrix():
    problem = random_problem(2, (1, 1, 1), 9, "coupled")
    Kmat, states = transition_matrix(problem, "mm", survival_power="V")
    law = Kmat[_key(states + 1)[tuple(start_state(problem, "all_missed", "mm").tolist())]]
    samples = run_independent_chains(problem, "mm", "systematic", "V", "all_missed", 20_000, 1,
                                     3)
    assert chi_square_p(samples, states, law) > ALPHA


def test_separable_family_mm_and_exact_sample_pi():
    # After t = 30 sweeps both chains are within 1e-5 of pi in total variation (checked on the
    # oracle); 10 000 independent chains each are tested against pi at ALPHA, and against each
    # other by a two-sample chi-square at ALPHA.
    problem = random_problem(2, (2, 2), 10, "separable")
    states = multisensor_states(problem)
    pi = target_distribution(problem, states, "exact")
    x0 = _key(states + 1)[tuple(start_state(problem, "all_missed", "exact").tolist())]
    counts = []
    for method in ("exact", "mm"):
        Kmat, _ = transition_matrix(problem, method, states=states)
        lawt = np.linalg.matrix_power(Kmat, 30)[x0]
        assert 0.5 * np.abs(lawt - pi).sum() < 1e-5
        samples = run_independent_chains(problem, method, "systematic", 1, "all_missed",
                                         10_000, 30, 21)
        assert chi_square_p(samples, states, pi) > ALPHA
        idx = _key(states + 1)
        c = np.zeros(len(states))
        for s in samples:
            c[idx[s]] += 1
        counts.append(c)
    table = np.array(counts)
    table = table[:, table.sum(axis=0) > 0]
    assert chi2_contingency(table).pvalue > ALPHA


def test_oracle_error_messages():
    problem = random_problem(2, (1, 1), 0)
    with pytest.raises(ValueError, match=r"unknown method 'gibbs'; expected one of"):
        transition_matrix(problem, "gibbs")
    with pytest.raises(ValueError, match=r"unknown scan 'rand'"):
        transition_matrix(problem, scan="rand")
    with pytest.raises(ValueError, match=r"unknown survival_power 3; expected one of"):
        row_kernels(problem, "mm", survival_power=3)
    with pytest.raises(ValueError, match=r"more than limit=10 states; the oracle is for tiny"):
        multisensor_states(problem, limit=10)
    with pytest.raises(ValueError, match=r"unknown method 'mm-fixed'; expected one of"):
        target_distribution(problem, multisensor_states(problem), "mm-fixed")


@pytest.fixture(scope="module")
def registered():
    """The stand-in problem dispatches like the real MultiSensorProblem."""
    from ms_standin import StandIn


    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(kinds, "KINDS", kinds.KINDS + (dataclasses.replace(kinds.kind_named("multisensor"), problem_type=StandIn),))
        yield


@pytest.mark.parametrize("method", METHODS)
def test_public_sampler_one_sweep_law(registered, method):
    # sample_short_chains with chains of one sweep: the counts of the returned unique set are
    # multinomial(N, delta_{x0} K) exactly (independent chains); chi-square at ALPHA, through
    # the whole public path (preparation, chain driver, parallel replay, packaging)
    from rankedassign import sample_short_chains

    problem = random_problem(2, (2, 1), 12, "coupled")
    Kmat, states = transition_matrix(problem, method, scan="random")
    x0 = start_state(problem, "all_missed", method)
    law = Kmat[_key(states + 1)[tuple(x0.tolist())]]
    res = sample_short_chains(problem, 20_000, 1, scan="random", method=method, rng=5,
                              workers=2)
    samples = [tuple((g.reshape(-1) + 1).tolist()) for g, c in
               zip(res.assignments, res.counts, strict=True) for _ in range(c)]
    assert len(samples) == 20_000
    assert chi_square_p(samples, states, law) > ALPHA

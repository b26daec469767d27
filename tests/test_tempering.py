"""Fixed-temperature tempering: ``beta`` on the samplers of every kind.

With ``beta < 1`` a sampler runs its chains on the kind's tempered problem (every weight to the
power ``beta``, so every row conditional is raised to ``beta``) and reports the costs of the
problem itself. The tests hold the draws to those of the tempered problem, the costs to the
original ones, ``beta = 1`` to today's draws, the reference to the kernels and one thread to
two; the stationary law ``π^β`` is tested with the exact transition matrix in
``test_samplers_stats.py``.
"""

import math

import numpy as np
import pytest
from numpy.testing import assert_array_equal

from rankedassign import (
    AssignmentProblem,
    sample_original,
    sample_short_chains,
    synthetic,
)
from rankedassign.adaptive_birth import AdaptiveBirthProblem
from rankedassign.adaptive_birth import synthetic as ab_synthetic
from rankedassign.kinds import kind_of
from rankedassign.multisensor import MultiSensorProblem
from rankedassign.multisensor import synthetic as ms_synthetic
from rankedassign.tracking import ShortChainGibbs, run_scenario

BETAS = (0.5, 0.7, 0.9)

CASES = {
    "single-4x24": (lambda: synthetic.random(rng=3), {}),
    "multi-exact": (lambda: ms_synthetic.random(rng=1), {"method": "exact"}),
    "multi-mm": (lambda: ms_synthetic.random(rng=1), {"method": "mm"}),
    "multi-mm-fixed": (lambda: ms_synthetic.random(rng=1), {"method": "mm-fixed"}),
    "birth-tensor": (lambda: AdaptiveBirthProblem.from_log_weights(
        np.random.default_rng(2).normal(size=(4, 5, 3))), {}),
    "birth-gaussian": (lambda: ab_synthetic.make_family("random", 2, rng=4), {}),
}


def _same(a, b, *, costs=True):
    assert_array_equal(a.assignments, b.assignments)
    assert_array_equal(a.counts, b.counts)
    assert a.n_observations == b.n_observations and a.n_chains_run == b.n_chains_run
    if costs:
        assert_array_equal(a.costs, b.costs)


def _own_costs(problem, assignments):
    if isinstance(problem, AssignmentProblem):
        return problem.cost_of(assignments)
    if isinstance(problem, MultiSensorProblem):
        return -problem.log_weight_of(assignments)
    return problem.cost_of(assignments)


@pytest.mark.parametrize("case", sorted(CASES))
@pytest.mark.parametrize("beta", BETAS)
def test_the_chains_run_on_the_tempered_problem_with_the_problems_own_costs(case, beta):
    make, opts = CASES[case]
    p = make()
    hot = kind_of(p).temper(p, beta, opts)
    got = sample_short_chains(p, 40, 10, tau_stall=5, tau_stale=10, rng=7, beta=beta, **opts)
    want = sample_short_chains(hot, 40, 10, tau_stall=5, tau_stale=10, rng=7, **opts)
    _same(got, want, costs=False)
    np.testing.assert_allclose(got.costs, _own_costs(p, got.assignments), rtol=1e-12,
                               atol=1e-12)
    long = sample_original(p, 300, rng=7, beta=beta, **opts)
    _same(long, sample_original(hot, 300, rng=7, **opts), costs=False)


@pytest.mark.parametrize("case", sorted(CASES))
def test_beta_one_is_todays_draws_bit_for_bit(case):
    make, opts = CASES[case]
    p = make()
    _same(sample_short_chains(p, 30, 10, tau_stall=5, rng=5, beta=1.0, **opts),
          sample_short_chains(p, 30, 10, tau_stall=5, rng=5, **opts))
    _same(sample_original(p, 200, rng=5, beta=1, **opts), sample_original(p, 200, rng=5, **opts))


@pytest.mark.parametrize("case", sorted(CASES))
def test_reference_equals_numba_and_threads_do_not_matter(case):
    make, opts = CASES[case]
    p = make()
    kw = dict(tau_stall=5, tau_stale=10, rng=11, beta=0.6, **opts)
    numba = sample_short_chains(p, 60, 8, **kw)
    _same(numba, sample_short_chains(p, 60, 8, backend="python", **kw))
    _same(numba, sample_short_chains(p, 60, 8, workers=2, **kw))
    _same(sample_original(p, 150, rng=3, beta=0.6, **opts),
          sample_original(p, 150, rng=3, beta=0.6, backend="python", **opts))


def test_the_tempered_weights_are_the_weights_to_the_power_beta():
    p = synthetic.random(rng=0)
    hot = kind_of(p).temper(p, 0.5, {})
    finite = np.isfinite(p.cost)
    np.testing.assert_allclose(np.exp(-hot.cost[finite]), np.exp(-p.cost[finite]) ** 0.5,
                               rtol=1e-12)
    assert_array_equal(np.isfinite(hot.cost), finite)
    m = ms_synthetic.random(rng=0)
    hm = kind_of(m).temper(m, 0.25, {"method": "mm"})
    np.testing.assert_allclose(hm.log_eta_alive, 0.25 * m.log_eta_alive)
    np.testing.assert_allclose(hm.log_s, 0.25 * m.log_s)
    for a, b in zip(hm.log_theta, m.log_theta, strict=True):
        np.testing.assert_allclose(a, 0.25 * b)
    b = ab_synthetic.make_family("random", 2, rng=1)
    hb = kind_of(b).temper(b, 0.5, {})
    np.testing.assert_allclose(hb.log_weights(), 0.5 * b.log_weights())
    assert hb.n_min == b.n_min


@pytest.mark.parametrize("beta", [0, 0.0, -0.5, 1.5, 1.0000001, math.nan, math.inf, "0.5",
                                  True, None, 0.5 + 0j])
def test_beta_outside_the_unit_interval_is_refused_naming_beta(beta):
    p = synthetic.diagonal()
    msg = r"beta must be a real number in \(0, 1\] \(the conditionals are raised to beta\)"
    with pytest.raises(ValueError, match=msg):
        sample_original(p, 10, beta=beta)
    with pytest.raises(ValueError, match=msg):
        sample_short_chains(p, 10, 5, beta=beta, backend="python")


def test_the_componentwise_kernel_refuses_tempering():
    m = ms_synthetic.random(rng=0)
    with pytest.raises(ValueError, match="beta != 1 does not apply to method='componentwise'"):
        sample_original(m, 10, beta=0.5, method="componentwise")
    sample_original(m, 10, beta=1.0, method="componentwise")  # untempered: as before


def test_tempering_flattens_the_visits():
    # a colder chain (beta = 1) concentrates on the heaviest assignments; beta = 0.3 spreads
    p = synthetic.random(rng=5)
    cold = sample_original(p, 20_000, rng=1)
    hot = sample_original(p, 20_000, rng=1, beta=0.3)
    assert len(hot.costs) > 1.5 * len(cold.costs)


def test_an_lmb_association_passes_beta_to_its_sampler():
    run = run_scenario("vo", ShortChainGibbs(100, 10, tau_stall=5, tau_stale=10, beta=0.7),
                       rng=0, n_scans=4)
    assert run.sweeps.sum() > 0
    glmb = run_scenario("vo", ShortChainGibbs(100, 10, tau_stall=5, tau_stale=10, beta=0.7),
                        rng=0, n_scans=3, filter="glmb")
    assert glmb.n_unique.sum() > 0

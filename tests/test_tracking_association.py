"""Association adapters (samplers, Murty, exact) against each other and inside the filter."""

import copy

import numpy as np
import pytest
from numpy.testing import assert_allclose, assert_array_equal

import oracle
import rankedassign
from rankedassign import AssignmentProblem
from rankedassign.tracking import (
    Association,
    AssociationResult,
    Exact,
    LMBFilter,
    Murty,
    OriginalGibbs,
    ShortChainGibbs,
    make_model,
    make_scenario,
    marginals_from_hypotheses,
    run_scenario,
)


class Recording(Association):
    """Wrap an association and keep the problems it was given."""

    def __init__(self, inner):
        self.inner = inner
        self.problems = []

    def __call__(self, problem, rng):
        self.problems.append(problem)
        return self.inner(problem, rng)


@pytest.fixture(scope="module")
def small_scan():
    """A filter after 5 scans of the "vo" scenario and the 6th scan's measurements.

    The joint problem of the 6th scan has P = 8 rows, M = 5 gated measurements and 4 704
    feasible hypotheses: small enough to enumerate.
    """
    f = LMBFilter(make_model("vo"), Exact())
    sc = make_scenario("vo", rng=0, n_scans=6)
    for s in sc.scans[:-1]:
        f.step(s.z, rng=0)
    return f, sc.scans[-1].z


def step_with(state, association, rng=0):
    f, z = state
    g = copy.deepcopy(f)
    rec = Recording(association)
    g.association = rec
    out = g.step(z, rng=rng)
    return out, rec.problems


def test_small_scan_size(small_scan):
    _, problems = step_with(small_scan, Exact())
    assert len(problems) == 1
    assert problems[0].shape == (8, 5 + 16)
    assert problems[0].n_feasible() == 4704


def test_exact_matches_enumeration_marginals(small_scan):
    _, (prob,) = step_with(small_scan, Exact())
    ranked = oracle.enumerate_assignments(prob)
    beta_enum = marginals_from_hypotheses(prob, ranked.assignments, ranked.costs)
    res = Exact()(prob, None)
    assert isinstance(res, AssociationResult)
    assert_allclose(res.beta, beta_enum, rtol=1e-9, atol=1e-13)
    assert (res.invocations, res.sweeps, res.row_updates, res.n_unique) == (1, 0, 0, 0)


def test_murty_all_hypotheses_equals_exact(small_scan):
    exact, _ = step_with(small_scan, Exact())
    murty, (prob,) = step_with(small_scan, Murty(10_000))
    assert murty.n_unique == prob.n_feasible()
    assert_array_equal(murty.track_labels, exact.track_labels)
    assert_allclose(murty.track_existence, exact.track_existence, rtol=1e-9, atol=1e-12)
    assert_allclose(murty.states, exact.states, rtol=1e-9, atol=1e-9)


def test_original_gibbs_large_budget_matches_exact(small_scan):
    # Marginals from a subset U of hypotheses of missing mass eps (the truncation error),
    # renormalised, differ from the exact ones by at most eps in every entry:
    # beta_U - beta = A eps / (1 - eps) - B with A <= 1 - eps, 0 <= B <= eps. The filter spawns
    # one child stream per problem from the scan's rng, so the chain is reproduced here.
    n_obs = 100_000
    exact, _ = step_with(small_scan, Exact())
    gibbs, (prob,) = step_with(small_scan, OriginalGibbs(n_obs), rng=5)
    res = rankedassign.sample_original(prob, n_obs, rng=np.random.default_rng(5).spawn(1)[0])
    eps = oracle.truncation_error(prob, res.assignments)
    assert eps < 1e-3  # a long chain on 4 704 hypotheses leaves little mass unvisited
    assert gibbs.n_unique == len(res.costs)
    beta = OriginalGibbs(n_obs)(prob, np.random.default_rng(5).spawn(1)[0]).beta
    assert np.abs(beta - oracle.marginals(prob)).max() <= eps + 1e-12
    assert_array_equal(gibbs.track_labels, exact.track_labels)
    assert np.abs(gibbs.track_existence - exact.track_existence).max() <= eps + 1e-12
    assert gibbs.sweeps == n_obs and gibbs.invocations == 1
    assert gibbs.row_updates == n_obs * 8


def test_short_chain_adapter_equals_direct_sampler_call():
    prob = AssignmentProblem.from_eta(
        [[2.0, 0.5, 0.0], [0.3, 3.0, 1.0], [1.0, 1.0, 1.0]], [0.2, 0.3, 0.1], [0.5, 0.1, 0.2]
    )
    assoc = ShortChainGibbs(50, 10, tau_stall=3, tau_stale=4)
    got = assoc(prob, np.random.default_rng(9))
    res = rankedassign.sample_short_chains(
        prob, 50, 10, tau_stall=3, tau_stale=4, rng=np.random.default_rng(9)
    )
    assert_allclose(got.beta, marginals_from_hypotheses(prob, res.assignments), rtol=1e-12)
    assert got.sweeps == res.n_observations
    assert got.row_updates == res.n_row_updates
    assert got.n_unique == len(res.costs)
    assert got.invocations == 1
    assert_allclose(got.beta.sum(axis=1), 1.0, rtol=1e-12)
    # options are forwarded
    orig = OriginalGibbs(100, scan="systematic")(prob, np.random.default_rng(1))
    direct = rankedassign.sample_original(prob, 100, rng=np.random.default_rng(1))
    assert orig.sweeps == direct.n_observations
    assert_allclose(orig.beta, marginals_from_hypotheses(prob, direct.assignments), rtol=1e-12)


def test_reprs():
    assert repr(ShortChainGibbs(400, 25, tau_stall=5, tau_stale=10)) == (
        "ShortChainGibbs(400, 25, tau_stall=5, tau_stale=10)"
    )
    assert repr(OriginalGibbs(10, scan="random")) == "OriginalGibbs(10, scan='random')"
    assert repr(Murty(3, backend="scipy")) == "Murty(3, backend='scipy')"


@pytest.mark.parametrize(
    ("build", "exc", "match"),
    [
        (lambda: OriginalGibbs(0), ValueError, "n_obs must be an int >= 1, got 0"),
        (lambda: OriginalGibbs(1.5), TypeError, "n_obs must be an int, got float 1.5"),
        (lambda: ShortChainGibbs(0, 25), ValueError, "n_chains must be an int >= 1, got 0"),
        (lambda: ShortChainGibbs(10, True), TypeError, "chain_length must be an int, got bool"),
        (lambda: ShortChainGibbs(10, 25, tau_stall=0), ValueError,
         r"tau_stall must be None \(off\) or an int >= 1, got 0"),
        (lambda: ShortChainGibbs(10, 25, tau_stale=-2), ValueError,
         r"tau_stale must be None \(off\) or an int >= 1, got -2"),
        (lambda: ShortChainGibbs(10, 25, tau_stale=2.0), TypeError,
         "tau_stale must be None or an int, got float 2.0"),
        (lambda: Murty(0), ValueError, "k must be an int >= 1, got 0"),
        (lambda: Murty(3, backend="lapjv"), ValueError,
         r"unknown backend 'lapjv'; expected one of \('numba', 'scipy'\)"),
    ],
)
def test_association_errors(build, exc, match):
    with pytest.raises(exc, match=match):
        build()


def test_exact_refuses_problems_too_large_for_the_dp():
    big = AssignmentProblem.from_eta(np.ones((21, 21)), np.ones(21), np.ones(21))
    with pytest.raises(ValueError, match="too large"):
        Exact()(big, None)


# --------------------------------------------------------------------------- inside run_scenario
def test_same_rng_same_run_and_same_measurements_across_methods():
    a = run_scenario("paper", ShortChainGibbs(400, 25, tau_stall=5, tau_stale=10), rng=7, n_scans=12)
    b = run_scenario("paper", ShortChainGibbs(400, 25, tau_stall=5, tau_stale=10), rng=7, n_scans=12)
    c = run_scenario("paper", OriginalGibbs(200), rng=7, n_scans=12)
    assert_array_equal(a.estimates, b.estimates)
    assert_array_equal(a.sweeps, b.sweeps)
    for sa, sc in zip(a.scenario.scans, c.scenario.scans, strict=True):
        assert_array_equal(sa.z, sc.z)
    assert_array_equal(c.sweeps, 200 * c.invocations)
    assert np.all(c.invocations == 1)
    assert np.all(a.row_updates >= a.sweeps)
    d = run_scenario("paper", ShortChainGibbs(400, 25, tau_stall=5, tau_stale=10), rng=8, n_scans=12)
    assert not np.array_equal(a.scenario.scans[0].z, d.scenario.scans[0].z)


def test_grouping_with_exact_on_vo_preset_counts_groups():
    run = run_scenario("vo", Exact(), rng=3, n_scans=20, grouping=True)
    assert np.all(run.n_groups >= 1)
    assert_array_equal(run.invocations, run.n_groups)
    assert run.n_groups.mean() > 2  # narrow births: several independent groups per scan
    assert np.all(run.sweeps == 0)

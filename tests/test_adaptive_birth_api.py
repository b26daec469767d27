"""The public samplers on an AdaptiveBirthProblem: backends, parallel runs, readings, options."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from numpy.testing import assert_array_equal
from scipy.stats import chi2

import oracle
from oracle.adaptive_birth import exact as ob
from rankedassign import sample_original, sample_short_chains
from rankedassign.adaptive_birth import AdaptiveBirthProblem
from rankedassign.adaptive_birth.synthetic import make_family

STALLS = ["global-consecutive", "global-cumulative", "chain-local"]
STALES = ["consecutive", "cumulative", "literal-set", "literal-multiset"]


def _same(a, b, discarded=True):
    assert_array_equal(a.assignments, b.assignments)
    assert_array_equal(a.counts, b.counts)
    assert np.array_equal(a.costs, b.costs)
    assert (a.n_observations, a.n_row_updates, a.n_chains_run, a.stop_reason) == (
        b.n_observations, b.n_row_updates, b.n_chains_run, b.stop_reason)
    if discarded:
        assert a.n_speculative_discarded == b.n_speculative_discarded


@st.composite
def problems(draw):
    V = draw(st.integers(1, 4))
    M = tuple(draw(st.integers(0, 3)) for _ in range(V))
    g = np.random.default_rng(draw(st.integers(0, 2**32 - 1)))
    if draw(st.booleans()):
        z = [g.uniform(-10, 10, (m, 1)) for m in M]
        return AdaptiveBirthProblem.from_measurements(
            z, [g.uniform(0.5, 1, m) for m in M], H=[[1.0]], R=[[2.0]],
            P_D=list(g.uniform(0.3, 0.9, V)), clutter_intensity=0.02, mu0=[0.0], P0=[[50.0]],
            tau_rU=0.0)
    t = g.normal(0, 2, tuple(m + 1 for m in M))
    t[g.uniform(size=t.shape) < 0.3] = -np.inf
    t[(0,) * V] = 0.0
    return AdaptiveBirthProblem.from_log_weights(t)


@settings(max_examples=25)
@given(problems(), st.sampled_from(STALLS), st.sampled_from(STALES),
       st.sampled_from(["random", "fixed"]), st.integers(0, 2**32 - 1),
       st.integers(1, 8), st.integers(1, 6), st.integers(1, 4))
def test_numba_python_and_parallel_agree(problem, stall, stale, order, seed, n_chains, length,
                                         tau):
    kw = dict(tau_stall=tau, tau_stale=tau, stall=stall, stale=stale, rng=seed,
              sensor_order=order)
    a = sample_short_chains(problem, n_chains, length, **kw)
    b = sample_short_chains(problem, n_chains, length, backend="python", **kw)
    c = sample_short_chains(problem, n_chains, length, workers=2, **kw)
    _same(a, b)
    _same(a, c, discarded=False)
    assert int(a.counts.sum()) == a.n_observations
    assert a.n_row_updates == a.n_observations * problem.n_sensors
    assert_array_equal(a.assignments[0], np.zeros(problem.n_sensors))
    assert np.array_equal(a.costs, problem.cost_of(a.assignments))
    assert len({tuple(r) for r in a.assignments.tolist()}) == len(a)


@pytest.mark.parametrize("stale", STALES)
@pytest.mark.parametrize("stall", STALLS)
def test_every_reading_numba_python_parallel(stall, stale):
    p = make_family("random", 3, 4, rng=9)
    kw = dict(tau_stall=2, tau_stale=3, stall=stall, stale=stale, rng=5)
    a = sample_short_chains(p, 300, 8, **kw)
    _same(a, sample_short_chains(p, 300, 8, backend="python", **kw))
    _same(a, sample_short_chains(p, 300, 8, workers=2, **kw), discarded=False)


def test_original_equals_one_long_chain_and_reference():
    p = make_family("random", 4, 5, rng=2)
    a = sample_original(p, 300, rng=4)
    _same(a, sample_original(p, 300, rng=4, backend="python"))
    _same(a, sample_short_chains(p, 1, 300, rng=4))
    assert a.n_chains_run == 1 and a.stop_reason == "budget"


def test_parallel_batches_equal_sequential_on_a_study_problem():
    p = make_family("diagonal", 6, rng=0)
    kw = dict(tau_stall=5, tau_stale=25, rng=7)
    _same(sample_short_chains(p, 2000, 25, **kw),
          sample_short_chains(p, 2000, 25, workers=2, **kw), discarded=False)


def test_one_sweep_law_through_the_public_sampler():
    # As tests/test_adaptive_birth_sampler.py, through the chain driver: from each start tuple,
    # 600 chains of one sweep are 600 independent draws of K[start, :] (each chain has its own
    # stream); pooled chi-square, cells with expected count < 5 pooled per row, alpha = 1e-4:
    # fixed seed, false-failure probability 1e-4.
    p = make_family("random", 2, 3, rng=5)
    K, _ = ob.transition_matrix(p, "random")
    n, stat, df = 600, 0.0, 0
    for a in range(p.n_feasible()):
        start = np.array(np.unravel_index(a, p.shape))
        res = sample_short_chains(p, n, 1, start=start, rng=a)
        obs = np.zeros(p.n_feasible())
        obs[np.ravel_multi_index(tuple(res.assignments.T), p.shape)] = res.counts
        exp = n * K[a]
        big = exp >= 5
        o, e = np.append(obs[big], obs[~big].sum()), np.append(exp[big], exp[~big].sum())
        if e[-1] == 0:
            assert o[-1] == 0
            o, e = o[:-1], e[:-1]
        stat += float(np.sum((o - e) ** 2 / e))
        df += len(e) - 1
    assert chi2.sf(stat, df) > 1e-4, (stat, df)


def test_restarts_reach_every_target_where_one_long_chain_sticks():
    # Spec §5 note (ii): in the diagonal family a chain at one target's full tuple must pass
    # through the all-missed region (factors 1 - P_D = 0.05 per sensor) to reach another
    # target, so one long chain stays with the first target it finds; short chains restart
    # from the all-missed tuple and find all three. Fixed seeds (deterministic).
    p = make_family("diagonal", 4, rng=1)
    long = sample_original(p, 1000, rng=0)
    short = sample_short_chains(p, 40, 25, tau_stall=5, tau_stale=25, rng=0)
    assert oracle.truncation_error(p, long.assignments) > 0.3
    assert oracle.truncation_error(p, short.assignments) < 0.01
    assert short.n_observations < long.n_observations


@pytest.mark.parametrize("kw, exc, match", [
    (dict(scan="random"), ValueError, "scan='random' does not apply to an AdaptiveBirthProblem"),
    (dict(sensor_order="x"), ValueError, "unknown sensor_order 'x'"),
    (dict(method="y"), TypeError, r"unexpected option\(s\) \['method'\] for an AdaptiveBirth"),
    (dict(start="all_dead"), ValueError, "unknown start 'all_dead'"),
    (dict(start=[0, 0]), ValueError, r"start must have shape \(n, V\) or \(V,\) with V = 3"),
    (dict(start=[[0, 0, 0]]), ValueError, r"start must be a single tuple of shape \(3,\)"),
    (dict(start=[0, 0, 9]), ValueError, "start has an entry outside 0..M_v"),
    (dict(start=[0.0, 0.0, 0.0]), TypeError, "start must be integers"),
    (dict(start=[1, 1, 0]), ValueError, r"start tuple \[1, 1, 0\] has zero weight"),
])
def test_option_errors(kw, exc, match):
    t = np.zeros((2, 2, 2))
    t[1, 1, 0] = -np.inf
    p = AdaptiveBirthProblem.from_log_weights(t)
    with pytest.raises(exc, match=match):
        sample_short_chains(p, 2, 2, **kw)
    with pytest.raises(exc, match=match):
        sample_original(p, 2, backend="python", **kw)


def test_explicit_start_is_stored_first():
    p = AdaptiveBirthProblem.from_log_weights(np.zeros((3, 3)))
    res = sample_short_chains(p, 3, 2, start=[2, 1], rng=0)
    assert res.assignments[0].tolist() == [2, 1]

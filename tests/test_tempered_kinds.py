"""Tempered Gibbs sampling (Zanella & Roberts) on the multi-sensor and adaptive-birth kinds.

The numba loop is held to the pure-Python references bit for bit (assignments, counts,
marginals, effective sample size) over random problems of both kinds, one move per slice to
one slice; every unique assignment to feasibility and to ``problem.cost_of``; ``beta = 1`` to
a random-scan Gibbs sampler with equal weights; the importance-weighted marginals to the exact
marginals of the oracle; bad input to pinned messages.
"""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from ms_standin import KINDS as FAMILIES
from ms_standin import random_problem
from numpy.testing import assert_allclose, assert_array_equal

import oracle
from rankedassign import kinds, sample_tempered
from rankedassign.adaptive_birth import AdaptiveBirthProblem
from rankedassign.adaptive_birth import synthetic as ab_synthetic
from rankedassign.adaptive_birth import tempered as ab_tempered
from rankedassign.multisensor import MultiSensorProblem
from rankedassign.multisensor import synthetic as ms_synthetic
from rankedassign.multisensor import tempered as ms_tempered


def _flat(marginals):
    """Every marginal of either kind's layout as one float64 vector."""
    if isinstance(marginals, ms_tempered.TemperedMarginals):
        parts = [marginals.dead, marginals.tuples, *marginals.sensors]
    else:
        parts = list(marginals)
    return np.concatenate([np.ravel(a) for a in parts])


def _same(a, b):
    assert_array_equal(a.assignments, b.assignments)
    assert_array_equal(a.costs.view(np.uint64), b.costs.view(np.uint64))
    assert_array_equal(a.counts, b.counts)
    assert_array_equal(_flat(a.marginals).view(np.uint64), _flat(b.marginals).view(np.uint64))
    assert a.n_steps == b.n_steps
    assert a.ess == b.ess or (math.isnan(a.ess) and math.isnan(b.ess))


def _ms_problem(problem):
    """The stand-in's arrays as a real MultiSensorProblem (exact conditionals only)."""
    return MultiSensorProblem.from_log_eta(problem.log_eta_dead, problem.log_eta_alive)


@st.composite
def ms_cases(draw):
    V = draw(st.integers(1, 3))
    P = draw(st.integers(1, 3))
    cap = {1: 4, 2: 3, 3: 2}[V]
    M = tuple(draw(st.integers(0, cap)) for _ in range(V))
    seed = draw(st.integers(0, 2**32 - 1))
    source = draw(st.sampled_from(FAMILIES + ("random", "random_coupled", "diagonal")))
    if source in FAMILIES:
        problem = _ms_problem(random_problem(P, M, seed, source))
    elif source == "diagonal":
        problem = ms_synthetic.diagonal(P, tuple(max(m, 1) for m in M))
    else:
        problem = getattr(ms_synthetic, source)(P, M, rng=seed)
    start = draw(st.sampled_from(["all_missed", "all_dead"]))
    if not np.isfinite(problem.log_eta_dead).all():
        start = "all_missed"
    return problem, start


def _gaussian(seed, M, n_state):
    g = np.random.default_rng(seed)
    V = len(M)
    H = np.eye(n_state)[: min(2, n_state)]
    d = H.shape[0]
    z = [g.uniform(-20, 20, (m, d)) for m in M]
    ru = [g.uniform(0.0, 1.0, m) for m in M]
    R = [np.diag(g.uniform(1.0, 9.0, d)) for _ in range(V)]
    return AdaptiveBirthProblem.from_measurements(
        z, ru, H=H, R=R, P_D=list(g.uniform(0.2, 0.95, V)), clutter_intensity=1e-3,
        mu0=np.zeros(n_state), P0=np.diag(g.uniform(50.0, 400.0, n_state)), tau_rU=0.2)


@st.composite
def ab_cases(draw):
    V = draw(st.integers(1, 4))
    M = tuple(draw(st.integers(0, 3)) for _ in range(V))
    seed = draw(st.integers(0, 2**32 - 1))
    source = draw(st.sampled_from(["gaussian", "tensor", "family"]))
    if source == "gaussian":
        return _gaussian(seed, M, draw(st.integers(1, 3)))
    if source == "family":
        return ab_synthetic.make_family(draw(st.sampled_from(ab_synthetic.FAMILIES)),
                                        draw(st.integers(1, 3)), 3, rng=seed)
    g = np.random.default_rng(seed)
    t = g.normal(0, 3, tuple(m + 1 for m in M))
    t[g.uniform(size=t.shape) < 0.3] = -np.inf
    t[(0,) * V] = 0.0
    return AdaptiveBirthProblem.from_log_weights(t)


def _check_result(problem, res, n):
    assert int(res.counts.sum()) == n and res.n_steps == n
    assert problem.is_feasible(res.assignments).all() if isinstance(
        problem, MultiSensorProblem) else np.isfinite(problem.log_weight_of(res.assignments)).all()
    assert_array_equal(res.costs, problem.cost_of(res.assignments))
    assert len(np.unique(res.assignments.reshape(len(res.counts), -1), axis=0)) == len(res.counts)
    if isinstance(problem, MultiSensorProblem):
        m = res.marginals
        assert m.tuples.shape == (problem.n_rows,) + tuple(k + 1 for k in problem.n_meas)
        if n:
            total = m.dead + m.tuples.reshape(problem.n_rows, -1).sum(axis=1)
            assert_allclose(total, 1.0, rtol=0, atol=1e-12)
            for s in m.sensors:
                assert_allclose(s.sum(axis=1), 1.0, rtol=0, atol=1e-12)
    else:
        assert [len(m) for m in res.marginals] == list(problem.shape)
        if n:
            for m in res.marginals:
                assert_allclose(m.sum(), 1.0, rtol=0, atol=1e-12)


# ------------------------------------------------------------------ reference = numba, bits
@settings(max_examples=80, deadline=None)
@given(data=st.data())
def test_multisensor_kernel_equals_reference(data):
    problem, start = data.draw(ms_cases())
    kw = dict(beta=data.draw(st.sampled_from([1.0, 0.7, 0.3])), start=start,
              rng=data.draw(st.integers(0, 2**32)))
    n = data.draw(st.integers(0, 300))
    try:
        ref = ms_tempered.tempered_reference(problem, n, **kw)
    except ValueError as e:   # a state whose weights underflow: both must refuse it
        assert "underflowed" in str(e)
        with pytest.raises(ValueError, match="available weights underflowed"):
            sample_tempered(problem, n, **kw)
        return
    res = sample_tempered(problem, n, **kw)
    _same(ref, res)
    _check_result(problem, res, n)


@settings(max_examples=80, deadline=None)
@given(data=st.data())
def test_adaptive_birth_kernel_equals_reference(data):
    problem = data.draw(ab_cases())
    kw = dict(beta=data.draw(st.sampled_from([1.0, 0.7, 0.3])),
              rng=data.draw(st.integers(0, 2**32)))
    n = data.draw(st.integers(0, 300))
    try:
        ref = ab_tempered.tempered_reference(problem, n, **kw)
    except ValueError as e:   # a ratio that overflows: both must refuse it
        assert "overflowed" in str(e)
        with pytest.raises(ValueError, match="tempering ratio overflowed"):
            sample_tempered(problem, n, **kw)
        return
    res = sample_tempered(problem, n, **kw)
    _same(ref, res)
    _check_result(problem, res, n)
    _same(ref, sample_tempered(problem, n, backend="python", **kw))


@pytest.mark.parametrize("problem", [
    ms_synthetic.random(P=4, M=(3, 3), rng=2),
    ab_synthetic.make_family("uniform", 4, 4),
], ids=["multisensor", "adaptive_birth"])
def test_slices_change_no_bit(problem, monkeypatch):
    """One move per slice and a growing unique set give the bits of one slice."""
    whole = sample_tempered(problem, 3_000, beta=0.4, rng=2)
    module = ms_tempered if isinstance(problem, MultiSensorProblem) else ab_tempered
    monkeypatch.setattr(module, "_SLICE_WORK", 1)
    _same(whole, sample_tempered(problem, 3_000, beta=0.4, rng=2))
    assert len(whole.counts) > 64                  # the unique set grew at least once


def test_an_explicit_start_and_the_same_seed():
    p = ms_synthetic.random(P=3, M=(2, 2), rng=4)
    start = np.array([[1, 2], [-1, -1], [0, 1]])
    res = sample_tempered(p, 500, beta=0.6, start=start, rng=7)
    assert_array_equal(res.assignments[0], start)
    _same(res, sample_tempered(p, 500, beta=0.6, start=start, rng=7))
    _same(res, ms_tempered.tempered_reference(p, 500, beta=0.6, start=start, rng=7))
    ab = AdaptiveBirthProblem.from_log_weights(np.random.default_rng(4).normal(0, 2, (3, 2, 4)))
    res = sample_tempered(ab, 500, beta=0.6, start=[1, 0, 2], rng=7)
    assert res.assignments[0].tolist() == [1, 0, 2]
    _same(res, ab_tempered.tempered_reference(ab, 500, beta=0.6, start=[1, 0, 2], rng=7))


# ------------------------------------------------------------------ beta = 1
@pytest.mark.parametrize("problem", [
    ms_synthetic.random(P=3, M=(2, 2), rng=1),
    ab_synthetic.make_family("random", 3, 4, rng=1),
], ids=["multisensor", "adaptive_birth"])
def test_beta_one_is_random_scan_gibbs_with_equal_weights(problem):
    """At beta = 1 every ratio is exactly 1: Z = rows, the weights are equal, and the weighted
    marginals are the visit frequencies of the states."""
    n = 5_000
    res = sample_tempered(problem, n, beta=1.0, rng=0)
    assert res.ess == pytest.approx(n, rel=1e-9)
    freq = res.counts / n
    if isinstance(problem, MultiSensorProblem):
        P = problem.n_rows
        dead = np.array([(freq * (res.assignments[:, i, 0] < 0)).sum() for i in range(P)])
        assert_allclose(res.marginals.dead, dead, rtol=0, atol=1e-12)
    else:
        for v, m in enumerate(res.marginals):
            want = np.bincount(res.assignments[:, v], weights=freq, minlength=len(m))
            assert_allclose(m, want, rtol=0, atol=1e-12)


def test_lower_beta_visits_more_states():
    p = ms_synthetic.random_coupled(P=4, M=(3, 3), rng=3)
    cold = sample_tempered(p, 20_000, beta=1.0, rng=1)
    hot = sample_tempered(p, 20_000, beta=0.3, rng=1)
    assert len(hot.counts) > 1.3 * len(cold.counts)
    assert hot.ess < 20_000


# ------------------------------------------------------------------ against the oracle
def _errors(problem, exact, res):
    """Every marginal's signed error against the exact one, in the flat layout of _flat."""
    if isinstance(problem, MultiSensorProblem):
        want = np.concatenate([np.ravel(a) for a in (exact.dead, exact.tuples, *exact.sensors)])
    else:
        want = np.concatenate([np.ravel(a) for a in exact])
    return _flat(res.marginals) - want


@pytest.mark.parametrize("problem, beta", [
    (ms_synthetic.random(P=3, M=(2, 2), rng=0), 1.0),
    (ms_synthetic.random(P=3, M=(2, 2), rng=0), 0.5),
    (ms_synthetic.random_coupled(P=3, M=(2, 1, 2), rng=1), 0.5),
    (ms_synthetic.random_coupled(P=3, M=(2, 1, 2), rng=1), 0.3),
    (ab_synthetic.make_family("random", 3, 4, rng=0), 1.0),
    (ab_synthetic.make_family("random", 3, 4, rng=0), 0.5),
    (AdaptiveBirthProblem.from_log_weights(
        np.random.default_rng(5).normal(0, 2, (4, 3, 5))), 0.3),
], ids=["ms-random-1", "ms-random-0.5", "ms-coupled-0.5", "ms-coupled-0.3", "ab-gaussian-1",
        "ab-gaussian-0.5", "ab-tensor-0.3"])
def test_weighted_marginals_converge_to_the_exact_marginals(problem, beta):
    """Importance weights 1/Z recover π: over 8 runs of 100 000 moves the mean weighted
    marginals are within 6 standard errors (batch means over the runs, + 1e-3) of the
    oracle's, and within 0.01 everywhere. The seeds are fixed, so the test is deterministic;
    under the normal approximation a correct sampler would miss the 6-SE bound in one of
    these <= 60 cells with probability below 1e-6 (t with 7 degrees of freedom: ~5e-4 per
    cell, 3e-2 for all cells of one problem at most, hence the + 1e-3 floor for cells whose
    spread across runs is tiny)."""
    exact = oracle.marginals(problem)
    runs = np.array([_errors(problem, exact, sample_tempered(problem, 100_000, beta=beta,
                                                             rng=s)) for s in range(8)])
    mean = runs.mean(axis=0)
    se = runs.std(axis=0, ddof=1) / np.sqrt(len(runs))
    assert np.all(np.abs(mean) <= 6 * se + 1e-3), np.abs(mean).max()
    assert np.abs(mean).max() < 0.01


# ------------------------------------------------------------------ errors
def test_underflow_is_refused_with_a_message():
    # row 1 must take measurement 1; row 0's remaining candidate (missed) is 800 below its best
    p = MultiSensorProblem.from_log_eta([-np.inf, -np.inf], [[0.0, 800.0], [-np.inf, 0.0]])
    for backend in ("numba", "python"):
        with pytest.raises(ValueError, match="a row's available weights underflowed"):
            sample_tempered(p, 10, beta=0.5, start=[[0], [1]], rng=0, backend=backend)


def test_overflow_is_refused_with_a_message():
    # the start tuple (1, 0) is 2000 below the rest: its ratio exp(0.5 * 2000) overflows
    t = np.zeros((2, 2))
    t[1, 0] = -2000.0
    p = AdaptiveBirthProblem.from_log_weights(t)
    for backend in ("numba", "python"):
        with pytest.raises(ValueError, match="a sensor's tempering ratio overflowed"):
            sample_tempered(p, 10, beta=0.5, start=[1, 0], rng=0, backend=backend)


MS = ms_synthetic.random(P=2, M=(2, 2), rng=0)
AB = ab_synthetic.make_family("uniform", 3, 2)


@pytest.mark.parametrize("problem, kw, exc, msg", [
    (MS, {"beta": 0.0}, ValueError, r"beta must be a real number in \(0, 1\]"),
    (MS, {"beta": 1.5}, ValueError, "beta must be"),
    (AB, {"beta": float("nan")}, ValueError, "beta must be"),
    (AB, {"beta": 0.0}, ValueError, "beta must be"),
    (MS, {"beta": 0.5, "method": "mm"}, ValueError,
     "method='mm' does not apply to tempered Gibbs sampling: its target is the exact posterior"),
    (MS, {"beta": 0.5, "method": "componentwise"}, ValueError,
     "method='componentwise' does not apply"),
    (MS, {"beta": 0.5, "method": "mm-fixed", "backend": "python"}, ValueError,
     "method='mm-fixed' does not apply"),
    (MS, {"beta": 0.5, "method": "gibbs"}, ValueError, "unknown method 'gibbs'"),
    (MS, {"beta": 0.5, "survival_power": "V"}, TypeError,
     r"unexpected option\(s\) \['survival_power'\] for tempered Gibbs sampling "
     r"\(MultiSensorProblem\): its options are \['method'\]"),
    (AB, {"beta": 0.5, "sensor_order": "fixed"}, TypeError,
     r"unexpected option\(s\) \['sensor_order'\] for tempered Gibbs sampling "
     r"\(AdaptiveBirthProblem\): it takes none"),
    (AB, {"beta": 0.5, "backend": "c"}, ValueError, "backend"),
    (MS, {"beta": 0.5, "start": "lsap"}, ValueError, "start"),
    (MS, {"beta": 0.5, "start": [[1, 1], [1, 0]]}, ValueError, "twice"),
    (AB, {"beta": 0.5, "start": [3, 0, 0]}, ValueError, "outside"),
])
def test_bad_input(problem, kw, exc, msg):
    with pytest.raises(exc, match=msg):
        sample_tempered(problem, 10, **kw)


def test_negative_steps_no_rows_and_other_types():
    for p in (MS, AB):
        with pytest.raises(ValueError, match="n_steps"):
            sample_tempered(p, -1, beta=0.5)
    empty = MultiSensorProblem.from_log_eta(np.zeros(0), np.zeros((0, 2, 2)))
    with pytest.raises(ValueError, match="needs at least one row; this problem has P = 0"):
        sample_tempered(empty, 10, beta=0.5)
    with pytest.raises(TypeError, match="problem must be one of"):
        sample_tempered([[1.0]], 10, beta=0.5)
    with pytest.raises(TypeError, match="problem must be a MultiSensorProblem"):
        ms_tempered.sample_tempered(AB, 10, beta=0.5)
    with pytest.raises(TypeError, match="problem must be an AdaptiveBirthProblem"):
        ab_tempered.sample_tempered(MS, 10, beta=0.5)


def test_every_kind_has_a_tempered_sampler():
    assert all(kind.tempered is not None for kind in kinds.KINDS)
    assert kinds.kind_named("multisensor").tempered is ms_tempered.sample_tempered

"""Tempered Gibbs sampling (Zanella & Roberts 2019): ``sample_tempered``.

The kernel is held to the plain-Python reference bit for bit; the chain's visit frequencies to
its stationary law ``f ∝ π Z``, computed independently of the sampler from the enumerated
assignments; the importance-weighted marginals to the exact marginals of the oracle; bad input
to pinned messages.
"""

import math

import numpy as np
import pytest
from cases import problems
from hypothesis import given, settings
from hypothesis import strategies as st
from numpy.testing import assert_array_equal

import oracle
from rankedassign import AssignmentProblem, sample_tempered, synthetic
from rankedassign.multisensor import synthetic as ms_synthetic
from rankedassign.single.tempered import tempered_reference


def _same(a, b):
    assert_array_equal(a.assignments, b.assignments)
    assert_array_equal(a.counts, b.counts)
    assert_array_equal(a.marginals.view(np.uint64), b.marginals.view(np.uint64))
    assert a.ess == b.ess or (math.isnan(a.ess) and math.isnan(b.ess))


@settings(max_examples=100, deadline=None)
@given(data=st.data())
def test_kernel_equals_reference(data):
    problem = data.draw(problems(max_rows=4, max_meas=5))
    M = problem.n_meas
    start = "all_missed" if np.isfinite(problem.compact_cost[:, M]).all() else "lsap"
    kw = dict(beta=data.draw(st.sampled_from([1.0, 0.7, 0.3])), start=start,
              rng=data.draw(st.integers(0, 2**32)))
    n = data.draw(st.integers(0, 300))
    try:
        ref = tempered_reference(problem, n, **kw)
    except ValueError as e:   # a state whose weights underflow: both must refuse it
        with pytest.raises(ValueError, match="underflowed"):
            sample_tempered(problem, n, **kw)
        assert "underflowed" in str(e)
        return
    res = sample_tempered(problem, n, **kw)
    _same(ref, res)
    assert int(res.counts.sum()) == n
    assert problem.is_feasible(res.assignments).all()
    assert_array_equal(res.costs, problem.cost_of(res.assignments))
    if n:
        np.testing.assert_allclose(res.marginals.sum(axis=1), 1.0, rtol=0, atol=1e-12)


def test_slices_change_no_bit(monkeypatch):
    """The moves run in slices (a signal ends a long run between two); one move per slice and
    a growing unique set give the bits of one slice."""
    from rankedassign.single import tempered

    p = synthetic.random(rng=3)
    whole = sample_tempered(p, 5_000, beta=0.6, rng=2)
    monkeypatch.setattr(tempered, "_SLICE_WORK", 1)
    _same(whole, sample_tempered(p, 5_000, beta=0.6, rng=2))
    assert len(whole.counts) > 64                  # the unique set grew at least once


def _stationary(problem, beta):
    """``f(x) ∝ π(x) Z(x)`` over the enumerated assignments, from the costs alone."""
    ranked = oracle.enumerate_assignments(problem)
    A = ranked.assignments
    logw = -ranked.costs
    P, M = problem.n_rows, problem.n_meas
    C = problem.cost
    f = np.empty(len(A))
    for n, a in enumerate(A):
        Z = 0.0
        for i in range(P):
            held = {int(a[r]) for r in range(P) if r != i and a[r] < M}
            cols = [j for j in range(M) if j not in held] + [M + i, M + P + i]
            c = np.array([C[i, j] for j in cols])
            c = c[np.isfinite(c)]
            lse = np.logaddexp.reduce(-c)
            lse_b = np.logaddexp.reduce(-beta * c)
            # p_i = g_i(x_i) / pi_i(x_i) = exp(-beta c_x - lse_b) / exp(-c_x - lse)
            Z += math.exp((1 - beta) * C[i, a[i]] - lse_b + lse)
        f[n] = logw[n] + math.log(Z)
    f = np.exp(f - f.max())
    return A, f / f.sum()


@pytest.mark.parametrize("beta", [0.4, 0.8])
def test_visit_frequencies_follow_pi_times_z(beta):
    """The chain is reversible with respect to f ∝ π Z: its visits after 400 000 moves on a
    3 x 7 problem (41 states) are within 5 standard errors (batch means) of f."""
    p = synthetic.random(R=3, M=2, rng=4)
    A, f = _stationary(p, beta)
    index = {tuple(a): n for n, a in enumerate(A.tolist())}
    batches = []
    for seed in range(8):
        res = sample_tempered(p, 50_000, beta=beta, rng=seed)
        freq = np.zeros(len(A))
        for a, c in zip(res.assignments.tolist(), res.counts, strict=True):
            freq[index[tuple(a)]] += c
        batches.append(freq / freq.sum())
    batches = np.array(batches)
    mean = batches.mean(axis=0)
    se = batches.std(axis=0, ddof=1) / np.sqrt(len(batches))
    assert np.all(np.abs(mean - f) <= 5 * se + 2e-3), np.abs(mean - f).max()


@pytest.mark.parametrize("beta", [1.0, 0.6, 0.3])
def test_weighted_marginals_converge_to_the_exact_marginals(beta):
    """Importance weights 1/Z recover π: over 8 runs of 100 000 moves on a random-family 4 x 24
    problem the weighted marginals are within 5 standard errors (+1e-3) of the oracle's."""
    p = synthetic.random(rng=6)
    exact = oracle.marginals(p)
    runs = np.array([sample_tempered(p, 100_000, beta=beta, rng=s).marginals for s in range(8)])
    mean = runs.mean(axis=0)
    se = runs.std(axis=0, ddof=1) / np.sqrt(len(runs))
    assert np.all(np.abs(mean - exact) <= 5 * se + 1e-3), np.abs(mean - exact).max()
    assert np.abs(mean - exact).max() < 0.01


def test_beta_one_has_equal_weights():
    res = sample_tempered(synthetic.random(rng=1), 5_000, beta=1.0, rng=0)
    assert res.ess == pytest.approx(5_000, rel=1e-9)


def test_lower_beta_visits_more_states():
    p = synthetic.random(rng=2)
    cold = sample_tempered(p, 20_000, beta=1.0, rng=1)
    hot = sample_tempered(p, 20_000, beta=0.3, rng=1)
    assert len(hot.counts) > 1.3 * len(cold.counts)
    assert hot.ess < 20_000


def test_underflow_is_refused_with_a_message():
    # row 1 must take measurement 0; row 0's remaining entries are 800 above its cheapest
    p = AssignmentProblem.from_cost(np.array([
        [-800.0, 0.0, np.inf, 0.0, np.inf],     # [meas 0 | missed 0, 1 | dead 0, 1]
        [0.0, np.inf, np.inf, np.inf, np.inf],
    ]))
    for backend in ("numba", "python"):
        with pytest.raises(ValueError, match="available weights underflowed"):
            sample_tempered(p, 10, beta=0.5, start="lsap", rng=0, backend=backend)


@pytest.mark.parametrize("kw, exc, msg", [
    ({"beta": 0.0}, ValueError, "beta"),
    ({"beta": 1.5}, ValueError, "beta"),
    ({"beta": float("nan")}, ValueError, "beta"),
    ({"beta": 0.5, "backend": "c"}, ValueError, "backend"),
])
def test_bad_settings(kw, exc, msg):
    with pytest.raises(exc, match=msg):
        sample_tempered(synthetic.random(rng=0), 10, **kw)


def test_negative_steps_and_other_kinds():
    from rankedassign.single import tempered

    with pytest.raises(ValueError, match="n_steps"):
        sample_tempered(synthetic.random(rng=0), -1, beta=0.5)
    # the other kinds have tempered samplers of their own (tests/test_tempered_kinds.py);
    # this kind's refuses them
    with pytest.raises(TypeError, match="tempered Gibbs sampling is implemented for "
                                        "single-sensor problems"):
        tempered.sample_tempered(ms_synthetic.random(rng=0), 10, beta=0.5)
    with pytest.raises(TypeError, match=r"unexpected option\(s\) \['method'\] for tempered "
                                        r"Gibbs sampling \(AssignmentProblem\): it takes none"):
        sample_tempered(synthetic.random(rng=0), 10, beta=0.5, method="exact")

"""Association marginals from a set of hypotheses: truncated and Rao-Blackwellised.

``marginals_from_hypotheses(..., marginals="rao-blackwell")`` weighs each hypothesis' row ``i``
by its conditional distribution given the other rows. Over *every* feasible hypothesis both
methods equal the oracle's exact marginals; over a subset the Rao-Blackwellised ones are
checked against an independent dense implementation of the same formula.
"""

import numpy as np
import pytest
from cases import CASE_IDS, CASES, marginal_atol, problems
from hypothesis import given
from hypothesis import strategies as st
from naive import rao_blackwell as dense_rao_blackwell
from numpy.testing import assert_allclose

import oracle
from rankedassign import AssignmentProblem
from rankedassign.tracking import (
    Exact,
    Murty,
    OriginalGibbs,
    ShortChainGibbs,
    marginals_from_hypotheses,
    run_scenario,
)
from rankedassign.tracking.single.association import MARGINALS


@pytest.mark.parametrize(("name", "problem"), CASES, ids=CASE_IDS)
@pytest.mark.parametrize("method", MARGINALS)
def test_all_hypotheses_give_the_exact_marginals(name, problem, method):
    ranked = oracle.enumerate_assignments(problem)
    beta = marginals_from_hypotheses(problem, ranked.assignments, ranked.costs, marginals=method)
    assert beta.shape == (problem.n_rows, problem.n_meas + 2)
    assert_allclose(beta, oracle.marginals(problem), rtol=0, atol=marginal_atol(problem))


@given(problems(), st.data())
def test_rao_blackwell_on_subsets_matches_the_dense_formula(problem, data):
    ranked = oracle.enumerate_assignments(problem)
    H = ranked.assignments.shape[0]
    keep = data.draw(st.lists(st.integers(0, H - 1), min_size=1, max_size=H, unique=True))
    a = ranked.assignments[np.sort(keep)]
    beta = marginals_from_hypotheses(problem, a, marginals="rao-blackwell")
    assert_allclose(beta, dense_rao_blackwell(problem, a), rtol=1e-9, atol=1e-12)
    assert_allclose(beta.sum(axis=1), 1.0, rtol=1e-12)
    # every hypothesis on its own: the row's conditional given the others, never an
    # indicator unless the row has a single option
    one = marginals_from_hypotheses(problem, a[:1], marginals="rao-blackwell")
    assert_allclose(one, dense_rao_blackwell(problem, a[:1]), rtol=1e-9, atol=1e-12)


@given(problems())
def test_all_hypotheses_exact_property(problem):
    ranked = oracle.enumerate_assignments(problem)
    beta = marginals_from_hypotheses(problem, ranked.assignments, marginals="rao-blackwell")
    assert_allclose(beta, oracle.marginals(problem), rtol=0, atol=marginal_atol(problem))


def test_a_newborn_that_was_missed_keeps_its_existence():
    # Row 0: a confirmed track that takes measurement 0. Row 1: a newborn track, r = 0.01,
    # missed this scan (it gates nothing): eta(-1) = 0.99, eta(0) = 0.01 * 0.02.
    prob = AssignmentProblem.from_eta([[50.0], [0.0]], [0.02, 0.01 * 0.02], [0.0, 0.99])
    best = [[0, 1 + 2 + 1]]  # row 0 -> measurement 0, row 1 -> dead (column M + P + 1)
    assert prob.is_feasible(best).all()
    trunc = marginals_from_hypotheses(prob, best)
    rb = marginals_from_hypotheses(prob, best, marginals="rao-blackwell")
    exact = oracle.marginals(prob)
    # the truncated set says the newborn does not exist; the exact existence is 2e-4 / 0.9902
    assert trunc[1, :2].sum() == 0.0
    assert_allclose(rb[1], exact[1], rtol=1e-12)
    assert_allclose(rb[1, :2].sum(), 0.0002 / 0.9902, rtol=1e-12)


def test_errors_and_reprs():
    prob = AssignmentProblem.from_eta([[3.0]], [1.0], [1.0])
    with pytest.raises(ValueError, match="unknown marginals 'rb'; expected one of"):
        marginals_from_hypotheses(prob, [[0]], marginals="rb")
    for build in (lambda: OriginalGibbs(10, marginals="exact"),
                  lambda: ShortChainGibbs(10, 5, marginals="x"),
                  lambda: Murty(3, marginals="")):
        with pytest.raises(ValueError, match="unknown marginals .*; expected one of"):
            build()
    assert repr(OriginalGibbs(10, marginals="rao-blackwell", scan="random")) == (
        "OriginalGibbs(10, marginals='rao-blackwell', scan='random')"
    )
    assert repr(Murty(3, backend="scipy", marginals="rao-blackwell")) == (
        "Murty(3, backend='scipy', marginals='rao-blackwell')"
    )
    assert repr(ShortChainGibbs(400, 25, tau_stall=5, tau_stale=10, marginals="truncated")) == (
        "ShortChainGibbs(400, 25, tau_stall=5, tau_stale=10)"
    )


ADAPTERS = {
    "short": lambda m: ShortChainGibbs(40, 10, tau_stall=5, tau_stale=10, marginals=m),
    "original": lambda m: OriginalGibbs(300, marginals=m),
    "murty": lambda m: Murty(20, marginals=m),
}


@pytest.mark.parametrize("name", sorted(ADAPTERS))
def test_adapters_use_the_rao_blackwell_marginals(name):
    prob = AssignmentProblem.from_eta(
        [[2.0, 0.5, 0.0], [0.3, 3.0, 1.0], [1.0, 1.0, 1.0]], [0.2, 0.3, 0.1], [0.5, 0.1, 0.2]
    )
    res = ADAPTERS[name]("rao-blackwell")(prob, np.random.default_rng(4))
    ref = ADAPTERS[name]("truncated")(prob, np.random.default_rng(4))
    # the same hypotheses (same stream), only the marginals differ
    assert (res.sweeps, res.row_updates, res.n_unique) == (ref.sweeps, ref.row_updates,
                                                           ref.n_unique)
    assert_allclose(res.beta.sum(axis=1), 1.0, rtol=1e-12)
    # closer to the exact marginals than the truncated ones (or as close)
    exact = oracle.marginals(prob)
    assert np.abs(res.beta - exact).max() <= np.abs(ref.beta - exact).max() + 1e-12


def test_short_chains_keep_a_missed_newborn_in_the_filter():
    # vo preset, seed 0: target 8 is detected at scan 40 (its birth) and missed at scan 41.
    # The exact update leaves its track r ≈ 3e-3; the short chains never visit the
    # hypotheses in which it exists undetected, so the truncated marginals give r = 0 and the
    # track is pruned; the Rao-Blackwellised marginals keep it, as the exact update does.
    runs = {m: run_scenario("vo", ShortChainGibbs(400, 25, tau_stall=5, tau_stale=10, marginals=m), rng=0,
                            n_scans=42) for m in MARGINALS}
    exact = run_scenario("vo", Exact(), rng=0, n_scans=42)
    label = (40, 4)
    assert label in exact.existence[40] and exact.existence[40][label] < 0.01
    assert label not in runs["truncated"].existence[40]
    assert label in runs["rao-blackwell"].existence[40]
    assert_allclose(runs["rao-blackwell"].existence[40][label], exact.existence[40][label],
                    rtol=0.05)

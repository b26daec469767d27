"""Herded Gibbs as the δ-GLMB filter's truncation (``HerdedGibbs.hypotheses``)."""

from __future__ import annotations

import numpy as np
import pytest

from rankedassign import synthetic
from rankedassign.tracking import GLMBFilter, HerdedGibbs, OriginalGibbs, make_model, run_scenario


@pytest.mark.parametrize("budget, sweeps", [(0, 0), (1, 0), (2, 1), (51, 50), (5000, 300)])
def test_one_chain_gets_t_h_minus_one_observations_at_most_its_own(budget, sweeps):
    p = synthetic.random(rng=3)
    hyp = HerdedGibbs(300).hypotheses(p, budget, rng=0)
    assert hyp.sweeps == sweeps and hyp.row_updates == sweeps * p.n_rows
    a = np.asarray(hyp.assignments)
    assert len(np.unique(a, axis=0)) == len(a) and p.is_feasible(a).all()
    assert np.allclose(hyp.costs, p.cost_of(a))
    if sweeps == 0:
        assert a.tolist() == [list(range(p.n_meas, p.n_meas + p.n_rows))]  # all missed


@pytest.mark.parametrize("budget", [1, 2, 30, 400, 10**6])
def test_short_chains_follow_the_gibbs_truncation_rule(budget):
    p = synthetic.random(rng=4)
    hyp = HerdedGibbs(25, n_chains=8, tau_stall=None, tau_stale=None).hypotheses(p, budget, 1)
    n = max(budget - 1, 0)
    length = min(25, n)
    want = 0 if n == 0 else min(8, -(-n // length)) * length
    assert hyp.sweeps == want


def test_the_glmb_filter_runs_with_the_herded_truncation_reproducibly():
    runs = [run_scenario("vo", HerdedGibbs(200), filter="glmb", rng=2, n_scans=8)
            for _ in range(2)]
    a, b = runs
    assert np.sum(a.sweeps) > 0
    assert all(np.array_equal(x, y, equal_nan=True)
               for x, y in zip(a.estimates, b.estimates, strict=True))
    assert any(np.isfinite(e).any() for e in a.estimates)  # NaN rows: targets absent
    gibbs = run_scenario("vo", OriginalGibbs(200), filter="glmb", rng=2, n_scans=8)
    assert [len(e) for e in gibbs.truth] == [len(e) for e in a.truth]  # same measurements


def test_the_glmb_filter_accepts_it_and_still_refuses_marginal_only_methods():
    GLMBFilter(make_model("vo"), HerdedGibbs(100))
    GLMBFilter(make_model("vo"), HerdedGibbs(25, n_chains=10, tau_stall=5, tau_stale=10))

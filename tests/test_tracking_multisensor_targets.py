"""Targets of the multi-sensor tracking study on the narrow birth: short chains against the
exact update, many-sweep Gibbs against the exact marginals, adaptive birth tracking every
target. The targets on the paper's wide birth (the fusion gain) are in
``tests/test_tracking_multisensor_paper_birth.py``: a module of their own, so that the test
tier that runs whole modules per worker (``--dist loadfile``) runs the two on two cores.

These run the multi-sensor filter over 100 scans on many seeds — about three minutes on an
idle two-core machine — so they sit behind their own marker, outside the default run:
``python -m pytest -m study``; CI runs them as a tier of their own. The adaptive-birth target
(about a minute for its ten runs) is also marked ``slow``."""

import numpy as np
import pytest
from multisensor_targets import SHORT, mean_ospa
from numpy.testing import assert_allclose

import oracle
from rankedassign.experiments.studies.multisensor_tracking import (
    COVERAGE_RADIUS,
    COVERAGE_SETTLE,
    LOST_BELOW,
)
from rankedassign.metrics import track_coverage
from rankedassign.tracking import (
    Exact,
    OriginalGibbs,
    ShortChainGibbs,
    run_multisensor_scenario,
)

pytestmark = pytest.mark.study

@pytest.fixture(scope="module")
def narrow_runs():
    """Exact update and short chains on the narrow-birth 'multi' scenario, V = 3, seeds 0-9
    (narrow births, P_B = 100 I, keep the groups within the exact DP; same measurements)."""
    out = []
    for seed in range(10):
        exact = run_multisensor_scenario(Exact(), rng=seed, sensors=(0, 1, 2),
                                         birth="narrow")
        short = run_multisensor_scenario(ShortChainGibbs(**SHORT), rng=seed,
                                         sensors=(0, 1, 2), birth="narrow")
        out.append((exact, short))
    return out


def test_short_chains_use_95_percent_fewer_sweeps_than_the_long_chain(narrow_runs):
    # a long chain spends 10 000 sweeps on every sampler call; the short chains get the same
    # calls (one per group with measurements)
    sweeps = sum(int(short.sweeps.sum()) for _, short in narrow_runs)
    calls = sum(int(short.invocations.sum()) for _, short in narrow_runs)
    assert sweeps <= 0.05 * 10_000 * calls


@pytest.mark.xfail(strict=True,
                   reason="10 seeds, V = 3, narrow birth: short chains 19.01 m, exact update "
                          "20.65 m mean OSPA(2); the short chains are 8.0 % lower, outside 5 %")
def test_short_chains_within_5_percent_of_the_exact_update(narrow_runs):
    exact = np.mean([mean_ospa(e) for e, _ in narrow_runs])
    short = np.mean([mean_ospa(s) for _, s in narrow_runs])
    assert abs(short - exact) <= 0.05 * exact


def test_many_sweep_gibbs_agrees_with_the_exact_marginals():
    # The problems of a narrow-birth filter run that the exact DP takes. 20 000 sweeps visit
    # practically every hypothesis of these small groups (a few hundred at most), and the
    # marginals of the visited set are then exact; a missed hypothesis of mass q moves a
    # marginal by at most q, and one of mass > 0.01 is missed by 20 000 sweeps with
    # probability below 1e-80, so the tolerance 0.01 fails falsely with negligible probability.
    problems = []

    def capture(problem, rng):
        problems.append(problem)
        return Exact()(problem, rng)

    run_multisensor_scenario(capture, rng=0, n_scans=40, sensors=(0, 1, 2), birth="narrow")
    problems = [p for p in problems if p.n_rows > 1][:30]
    assert len(problems) >= 10
    gibbs = OriginalGibbs(20_000, method="exact")
    for i, p in enumerate(problems):
        ex = oracle.marginals(p)
        res = gibbs(p, np.random.default_rng(i))
        assert_allclose(res.dead, ex.dead, atol=0.01)
        assert_allclose(res.tuples, ex.tuples, atol=0.01)


@pytest.mark.slow  # about a minute for the ten seeds: also in the slow tier (-m slow)
@pytest.mark.parametrize("seed", range(10))
def test_adaptive_birth_tracks_every_target(seed):
    # No birth positioned by hand: the model has no static birth, every track comes from the
    # adaptive-birth sampler (spec §7.2 variant). V = 3, the study's short chains, 100 scans;
    # the study's coverage rule decides whether a target is lost.
    run = run_multisensor_scenario(ShortChainGibbs(**SHORT), rng=seed,
                                   sensors=(0, 1, 2), birth="adaptive")
    assert run.scenario.model.birth.components == ()
    cov = track_coverage(run.truth, run.estimates, COVERAGE_RADIUS, settle=COVERAGE_SETTLE)
    cov = np.asarray(cov, dtype=float)
    assert cov[~np.isnan(cov)].size == 12
    assert (cov[~np.isnan(cov)] >= LOST_BELOW).all()

"""Tracking accuracy on the paper's scenario (spec §6–§8) for every association method.

The default suite runs one cheap single-seed check; the studies over several seeds are marked
``slow``. Every run is seeded, so each number below is deterministic; a target the
implementation does not reach is kept at its stated value and marked ``xfail(strict=True)``
with the measured number in the reason (it turns into a failure if the number changes enough
to meet the target, so the marker cannot go stale).
"""

from functools import cache

import numpy as np
import pytest

from rankedassign.metrics import ospa, ospa2
from rankedassign.tracking import Exact, Murty, OriginalGibbs, ShortChainGibbs, run_scenario

PAPER_SHORT = ("short", 400, 25, 5, 10)


def make_assoc(key):
    kind = key[0]
    if kind == "short":
        return ShortChainGibbs(key[1], key[2], tau_stall=key[3], tau_stale=key[4])
    if kind == "original":
        return OriginalGibbs(key[1])
    if kind == "murty":
        return Murty(key[1])
    return Exact()


@cache
def cached_run(preset, key, seed, grouping=False):
    return run_scenario(preset, make_assoc(key), rng=seed, grouping=grouping)


def mean_ospa2(run):
    # the paper's settings: Euclidean base, c = 200 m, p = 1, window 5, uniform weights
    return float(ospa2(run.truth, run.estimates, c=200.0, p=1, window=5).value.mean())


def mean_ospa(run, c=100.0):
    vals = []
    for k in range(run.n_scans):
        x = run.truth[k][~np.isnan(run.truth[k]).any(axis=1)]
        y = run.estimates[k][~np.isnan(run.estimates[k]).any(axis=1)]
        vals.append(ospa(x, y, c, 1).value)
    return float(np.mean(vals))


def coverage(run, radius=50.0, settle=5):
    """Per true target: fraction of its scans (after its first ``settle``) with an estimate
    within ``radius`` metres."""
    cov = []
    for t in range(run.truth.shape[1]):
        scans = np.flatnonzero(~np.isnan(run.truth[:, t, 0]))[settle:]
        hits = 0
        for k in scans:
            y = run.estimates[k][~np.isnan(run.estimates[k]).any(axis=1)]
            if len(y) and np.linalg.norm(y - run.truth[k, t], axis=1).min() < radius:
                hits += 1
        cov.append(hits / len(scans))
    return np.array(cov)


# --------------------------------------------------------------------------- default suite
def test_paper_scenario_single_seed_short_chain():
    """One 100-scan run of the paper's scenario with the paper's short-chain settings."""
    run = cached_run("paper", PAPER_SHORT, 0)
    assert run.estimates.shape[0] == 100
    # every one of the 12 targets is tracked (within 50 m) on >= 90 % of its scans once the
    # track has had 5 scans to confirm
    assert np.all(coverage(run) >= 0.9)
    # single-seed version of the accuracy target (the 5-seed study is below, marked slow)
    assert mean_ospa2(run) <= 35.0
    # sweeps are the observations; each call stops early (at most N_S * N_C = 10 000 sweeps)
    assert np.all(run.invocations == 1)
    assert np.all((run.sweeps > 0) & (run.sweeps < 10_000))
    assert np.all(run.row_updates == run.sweeps * run.n_tracks)


# --------------------------------------------------------------------------- slow studies
SEEDS = range(5)


@pytest.mark.slow
@pytest.mark.parametrize(
    "key", [PAPER_SHORT, ("original", 10_000), ("murty", 1000)], ids=["short", "original", "murty"]
)
@pytest.mark.parametrize("seed", range(3))
def test_every_method_tracks_all_targets_paper(key, seed):
    run = cached_run("paper", key, seed)
    assert np.all(coverage(run) >= 0.9), coverage(run)


@pytest.mark.slow
@pytest.mark.parametrize("seed", range(3))
def test_exact_tracks_all_targets_vo(seed):
    # Exact() on the "paper" preset is out of reach: the 300 m birth spread joins every track
    # into one group of P ≈ 21 rows and min(P, M) > 20 exceeds the oracle's subset DP. On the
    # "vo" preset grouping keeps every problem small.
    run = cached_run("vo", ("exact",), seed, True)
    assert np.all(coverage(run) >= 0.9), coverage(run)


@pytest.mark.slow
def test_short_chain_accuracy_matches_original_paper():
    short = np.mean([mean_ospa2(cached_run("paper", PAPER_SHORT, s)) for s in SEEDS])
    orig = np.mean([mean_ospa2(cached_run("paper", ("original", 10_000), s)) for s in SEEDS])
    # measured: 38.85 m (short) vs 38.63 m (original)
    assert abs(short - orig) <= 0.05 * orig, (short, orig)


@pytest.mark.slow
def test_short_chain_accuracy_matches_exact_vo_grouped():
    # Exact is feasible on the "vo" preset with grouping; the short-chain sampler is run per
    # group as well. Measured: 23.93 m (short) vs 24.14 m (exact).
    short = np.mean([mean_ospa2(cached_run("vo", PAPER_SHORT, s, True)) for s in SEEDS])
    exact = np.mean([mean_ospa2(cached_run("vo", ("exact",), s, True)) for s in SEEDS])
    assert abs(short - exact) <= 0.05 * exact, (short, exact)


@pytest.mark.slow
@pytest.mark.xfail(
    strict=True,
    reason="target: 95 % fewer observations; measured 88.8 % fewer sweeps (~1 120 sweeps per "
    "call vs 10 000) on the paper preset, seeds 0-4",
)
def test_short_chain_saves_observations_paper():
    short = sum(cached_run("paper", PAPER_SHORT, s).sweeps.sum() for s in SEEDS)
    orig = sum(cached_run("paper", ("original", 10_000), s).sweeps.sum() for s in SEEDS)
    assert short <= 0.05 * orig, (short, orig)


@pytest.mark.slow
@pytest.mark.xfail(
    strict=True,
    reason="target: mean OSPA(2) <= 35 m; measured 38.8 m (seeds 0-4: 34.3, 39.4, 38.9, 41.4, "
    "40.3), dominated by the cardinality lag of the 300 m-wide births under hysteresis",
)
def test_paper_accuracy_five_seeds():
    vals = [mean_ospa2(cached_run("paper", PAPER_SHORT, s)) for s in SEEDS]
    assert np.mean(vals) <= 35.0, vals


@pytest.mark.slow
@pytest.mark.xfail(
    strict=True,
    reason="target: mean OSPA (c = 100, p = 1) <= 12 m; measured 13.8 m over seeds 0-9 "
    "(localisation on cardinality-correct scans 9.8 m, the Kalman steady-state floor is 9.9 m)",
)
def test_vo_accuracy_ten_seeds():
    vals = [mean_ospa(cached_run("vo", PAPER_SHORT, s)) for s in range(10)]
    assert np.mean(vals) <= 12.0, vals

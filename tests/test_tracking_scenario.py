"""Tracking accuracy and sampler cost on the paper's scenario (spec §6–§8, A13).

The default suite checks, on one seed, properties every seed must meet (coverage of all 12
targets, cardinality, no persistent false tracks, steady-state localisation, the accounting of
spec §6.6) and compares the short-chain sampler with the original one on the same
measurements. The studies over several seeds are marked ``slow`` (``pytest -m slow``); each
asserts the issue's target as stated. Every run is seeded, so each outcome is deterministic.
The values these tests measure, and why some targets are not met (the confirmation lag of
newborn tracks under the paper's birth model, ``test_idealised_filter_floor``), are on the
Tracking page of the documentation (``docs/tracking.md``, "What the tests measure"); the
``"paper_var"`` tests hold the preset whose birth numbers are read as variances to the
paper's observation totals (one call per group) and to the accuracy and cost targets (one call
per scan).
"""

from functools import cache

import numpy as np
import pytest

from rankedassign.metrics import ospa, ospa2, track_coverage
from rankedassign.tracking import (
    Exact,
    Murty,
    OriginalGibbs,
    ShortChainGibbs,
    paper_truth,
    run_scenario,
)

PAPER_SHORT = ("short", 400, 25, 5, 10)
# the same sampler with Rao-Blackwellised association marginals (an extension of the paper)
PAPER_SHORT_RB = ("short-rb", 400, 25, 5, 10)
ORIGINAL = ("original", 10_000)
EXACT = ("exact",)
SEEDS = range(5)
# scans (0-based) whose OSPA(2) window of 5 scans holds no birth (scans 1, 20, 40, 60, 80) and
# no death (target 1 and 3 exist up to scan 70) and lies at least 10 scans after a birth
STEADY = np.r_[29:39, 49:59, 89:100]
# the split of the module docstring: the 10 scans from each birth time, then scans 71-79
BIRTHS = np.r_[0:10, 19:29, 39:49, 59:69, 79:89]
DEATHS = np.r_[70:79]


def make_assoc(key):
    kind = key[0]
    if kind in ("short", "short-rb"):
        marginals = "rao-blackwell" if kind == "short-rb" else "truncated"
        return ShortChainGibbs(key[1], key[2], tau_stall=key[3], tau_stale=key[4],
                               marginals=marginals)
    if kind == "original":
        return OriginalGibbs(key[1])
    if kind == "murty":
        return Murty(key[1])
    return Exact()


@cache
def cached_run(preset, key, seed, grouping=False, sample_empty=False):
    return run_scenario(preset, make_assoc(key), rng=seed, grouping=grouping,
                        sample_empty_groups=sample_empty)


#: The paper's total observations over 100 scans (spec A13): original and short chains.
PAPER_TOTALS = (10_760_000, 63_474)


def ospa2_curve(run):
    # the paper's settings: Euclidean base, c = 200 m, p = 1, window 5, uniform weights
    return ospa2(run.truth, run.estimates, c=200.0, p=1, window=5).value


def mean_ospa2(run):
    return float(ospa2_curve(run).mean())


def mean_ospa(run, c=100.0):
    vals = []
    for k in range(run.n_scans):
        x = run.truth[k][~np.isnan(run.truth[k]).any(axis=1)]
        y = run.estimates[k][~np.isnan(run.estimates[k]).any(axis=1)]
        vals.append(ospa(x, y, c, 1).value)
    return float(np.mean(vals))


def coverage(run, radius=50.0, settle=10):
    """Per true target: fraction of its scans (after its first ``settle``) with an estimate
    within ``radius`` metres."""
    return track_coverage(run.truth, run.estimates, radius, settle=settle)


def far_estimates(run, radius=100.0):
    """Fraction of reported estimates (over all scans) farther than ``radius`` from every true
    target of their scan."""
    far = total = 0
    for k in range(run.n_scans):
        x = run.truth[k][~np.isnan(run.truth[k]).any(axis=1)]
        y = run.estimates[k][~np.isnan(run.estimates[k]).any(axis=1)]
        total += len(y)
        if len(y):
            d = np.linalg.norm(y[:, None, :] - x[None, :, :], axis=2).min(axis=1)
            far += int(np.sum(d > radius))
    return far / total


def check_paper_properties(run):
    """What every 100-scan run of the paper preset must meet, whatever the seed and method.

    The margins are wide against the values measured on seeds 0-4 for the short-chain, the
    original and the exact association (quoted beside each), so that a failure means a
    regression rather than an unlucky seed.
    """
    assert run.truth.shape == (100, 12, 2)
    assert run.estimates.shape[0] == 100 and run.estimates.shape[2] == 2
    # every target is tracked within 50 m on >= 85 % of its scans once it had 10 scans to be
    # confirmed (measured minimum over targets, seeds and methods: 0.961)
    cov = coverage(run)
    assert np.all(cov >= 0.85), cov
    # reported tracks are real: <= 5 % of the estimates lie > 100 m from every target
    # (measured <= 1.2 %; they are tracks of targets that died at scan 70, kept by hysteresis
    # until pruned, A19)
    assert far_estimates(run) <= 0.05
    n_true = (~np.isnan(run.truth[:, :, 0])).sum(axis=1)
    # never more than 3 tracks too many, and more than 2 on at most 5 % of the scans: the two
    # targets that die at scan 70 keep their tracks for 2-3 scans (hysteresis, A19); measured
    # max +3 on 3 scans of one run (short chains, seed 1: a duplicate track of a target born at
    # scan 60 still confirmed while it decays, r 0.098 -> 0.002, at scans 71-73)
    excess = run.n_estimated - n_true
    assert np.all(excess <= 3)
    assert np.mean(excess > 2) <= 0.05
    # the right number of tracks on >= 45 % of the scans; most misses are the confirmation
    # lag after each birth (measured 55-76 %)
    assert np.mean(run.n_estimated == n_true) >= 0.45
    # steady state (no birth or death in the window, every track >= 10 scans old): OSPA(2)
    # near the localisation floor of ~10 m (measured per-run means 9.2-13.1 m; above 10 m when
    # a duplicate track of one target is confirmed for a few scans)
    assert ospa2_curve(run)[STEADY].mean() <= 25.0
    # one association problem per scan (the 300 m birth spread joins every track into one
    # group, spec §6.5a); every call is accounted for
    assert np.all(run.invocations == 1)
    assert np.all(run.n_groups == 1)


# --------------------------------------------------------------------------- default suite
def test_paper_scenario_short_chain_properties_one_seed():
    """The properties every seed meets, on one seed (all five: the slow test below)."""
    run = cached_run("paper", PAPER_SHORT, 0)
    check_paper_properties(run)
    # sweeps are the observations; each call stops early (at most N_S * N_C = 10 000 sweeps,
    # at least tau_stale = 10 chains of tau_stall = 5 sweeps)
    assert np.all((run.sweeps >= 50) & (run.sweeps < 10_000))
    assert np.all(run.row_updates == run.sweeps * run.n_tracks)
    assert np.all(run.n_unique >= 1)


def test_paper_scenario_short_chain_vs_original_one_seed():
    """Both samplers on the same measurements (seed 0): accuracy and observations."""
    short = cached_run("paper", PAPER_SHORT, 0)
    orig = cached_run("paper", ORIGINAL, 0)
    for s1, s2 in zip(short.scenario.scans, orig.scenario.scans, strict=True):
        np.testing.assert_array_equal(s1.z, s2.z)
    check_paper_properties(orig)
    # the original always runs its T = 10 000 sweeps, one call per scan
    np.testing.assert_array_equal(orig.sweeps, np.full(100, 10_000))
    np.testing.assert_array_equal(orig.row_updates, 10_000 * orig.n_tracks)
    # the short-chain sampler spends at most 15 % of the original's sweeps (measured 10.0 %
    # on this seed, 10.8 % over seeds 0-4; the 95 % target is the slow test below)
    assert short.sweeps.sum() <= 0.15 * orig.sweeps.sum()
    # accuracy: over one run the two differ by which births each sampler happens to catch and
    # by short-lived duplicate tracks, up to 13.5 % of the original's value on seeds 0-4
    # (2.1 % here: 33.7 vs 33.0 m), hence the 15 % margin; the 5-seed means are 5.3 % apart
    # (slow test below)
    assert abs(mean_ospa2(short) - mean_ospa2(orig)) <= 0.15 * mean_ospa2(orig)


def test_grouped_accounting_one_call_per_group():
    """With grouping (spec §6.5a) every group with a gated measurement is one sampler call."""
    run = run_scenario("paper", OriginalGibbs(200), rng=0, n_scans=15, grouping=True)
    np.testing.assert_array_equal(run.invocations, run.n_groups)
    np.testing.assert_array_equal(run.sweeps, 200 * run.invocations)
    assert np.all(run.row_updates <= run.sweeps * run.n_tracks)
    assert np.all(run.row_updates >= run.sweeps)
    ungrouped = run_scenario("vo", OriginalGibbs(200), rng=0, n_scans=15)
    grouped = run_scenario("vo", OriginalGibbs(200), rng=0, n_scans=15, grouping=True)
    # the vo preset's narrow births keep tracks apart: several calls per scan, each on fewer
    # rows, so fewer row updates for more sweeps
    assert grouped.invocations.sum() > ungrouped.invocations.sum()
    np.testing.assert_array_equal(ungrouped.invocations, np.ones(15, dtype=np.int64))
    assert grouped.row_updates.sum() < grouped.sweeps.sum() * grouped.n_tracks.mean()


def test_paper_var_reproduces_the_papers_totals_one_seed():
    """``"paper-var"`` (the birth numbers read as variances) with one sampler call per group,
    empty groups included, reproduces the paper's observation totals (spec A13)."""
    orig = cached_run("paper-var", ORIGINAL, 0, True, True)
    short = cached_run("paper-var", PAPER_SHORT, 0, True, True)
    for s1, s2 in zip(short.scenario.scans, orig.scenario.scans, strict=True):
        np.testing.assert_array_equal(s1.z, s2.z)
    np.testing.assert_array_equal(orig.sweeps, 10_000 * orig.invocations)
    np.testing.assert_array_equal(orig.invocations, orig.n_groups)
    assert abs(orig.sweeps.sum() / PAPER_TOTALS[0] - 1) <= 0.10, orig.sweeps.sum()
    assert abs(short.sweeps.sum() / PAPER_TOTALS[1] - 1) <= 0.15, short.sweeps.sum()
    # each short-chain call stops near its floor of tau_stale = 10 chains of tau_stall = 5
    assert 50 <= short.sweeps.sum() / short.invocations.sum() <= 70
    assert 1 - short.sweeps.sum() / orig.sweeps.sum() >= 0.99


def test_paper_var_one_call_per_scan_one_seed():
    """``"paper-var"`` with one call per scan: the issue's targets on one seed (five seeds: the
    slow tests)."""
    short = cached_run("paper-var", PAPER_SHORT, 0)
    orig = cached_run("paper-var", ORIGINAL, 0)
    check_paper_properties(short)
    check_paper_properties(orig)
    assert short.sweeps.sum() <= 0.05 * orig.sweeps.sum()
    assert mean_ospa2(short) <= 35.0
    assert abs(mean_ospa2(short) - mean_ospa2(orig)) <= 0.05 * mean_ospa2(orig)


def test_idealised_filter_floor():
    """The OSPA(2) floor the confirmation lag alone imposes (docs/tracking.md).

    Estimates equal to the truth plus N(0, 7²) per axis (≈ 10 m, the filter's steady-state
    error), reported from the ``lag``-th scan after each birth on and for ``extra`` scans after
    each death (extrapolated at constant velocity).
    """
    truth = paper_truth()
    pos = truth.positions
    rng = np.random.default_rng(0)

    def floor(lag, extra):
        est = np.full(pos.shape, np.nan)
        for t in range(pos.shape[1]):
            b, d = truth.birth[t] - 1, truth.death[t] - 1
            for k in range(b + lag, min(pos.shape[0], d + 1 + extra)):
                kk = min(k, d)
                step = pos[kk, t] - pos[kk - 1, t]
                est[k, t] = pos[kk, t] + max(0, k - d) * step + rng.normal(0.0, 7.0, 2)
        return float(ospa2(pos, est, c=200.0, p=1, window=5).value.mean())

    # With r_B = 0.03, the 300 m birth spread and ϑ_u = 0.9, the exact update gives a newborn
    # track r ≈ 0.02-0.04, 0.06-0.18, 0.4-0.8 and 0.8-0.97 after its 1st-4th scans (median
    # 0.03, 0.09, 0.59, 0.91; targets 1-3, seeds 0-2, one of them missed on its 2nd scan): it
    # is confirmed on its 4th scan, often the 5th. A dead target's track falls below
    # ϑ_l = 10⁻³ after 2-3 missed scans.
    # Confirmed on the 4th scan and dropped after 2: already above 30 m (measured 30.4 m).
    assert 30.0 <= floor(3, 2) <= 31.5
    # Confirmed on the 5th scan and dropped after 3: at the 35 m target (measured 35.4 m).
    assert 34.5 <= floor(4, 3) <= 36.0


# --------------------------------------------------------------------------- slow studies
@pytest.mark.slow
@pytest.mark.parametrize("key", [PAPER_SHORT, ORIGINAL, EXACT], ids=["short", "original", "exact"])
def test_births_dominate_the_error_paper(key):
    # Diagnosis of the gap to 35 m: >= 70 % of the mean OSPA(2) is earned in the 10 scans after
    # each birth time, for the samplers and the exact update alike (measured 79-80 %; deaths
    # 8 %, steady state 11-13 %).
    curves = np.array([ospa2_curve(cached_run("paper", key, s)) for s in SEEDS])
    total = curves.sum(axis=1).mean()
    births = curves[:, BIRTHS].sum(axis=1).mean()
    deaths = curves[:, DEATHS].sum(axis=1).mean()
    assert births >= 0.7 * total, (births / total, deaths / total)
    assert deaths <= 0.15 * total


@pytest.mark.slow
@pytest.mark.parametrize("key", [PAPER_SHORT, ORIGINAL, EXACT], ids=["short", "original", "exact"])
@pytest.mark.parametrize("seed", SEEDS)
def test_paper_properties_every_seed(key, seed):
    check_paper_properties(cached_run("paper", key, seed))


@pytest.mark.slow
@pytest.mark.parametrize("seed", range(3))
def test_murty_tracks_all_targets_paper(seed):
    cov = coverage(cached_run("paper", ("murty", 1000), seed))
    assert np.all(cov >= 0.85), cov


@pytest.mark.slow
@pytest.mark.parametrize("seed", range(3))
def test_exact_tracks_all_targets_vo(seed):
    # MAP-cardinality extraction (the preset's default) drops a track for a scan when one
    # missed detection halves its r below 1/2, so short-lived targets lose a few scans:
    # measured minimum 0.88 (target 11, 21 scans, seed 2)
    cov = coverage(cached_run("vo", EXACT, seed, True), settle=5)
    assert np.all(cov >= 0.8), cov


@pytest.mark.slow
@pytest.mark.xfail(strict=True, reason=(
    "ruled out by the model (docs/validation.md): on the 'paper' preset the short chains' mean "
    "OSPA(2) is 36.97 m against the original's 35.12 m (5.3 % apart, target 5 %); the exact "
    "update itself gives 36.04 m"))
def test_short_chain_accuracy_matches_original_paper():
    short = np.mean([mean_ospa2(cached_run("paper", PAPER_SHORT, s)) for s in SEEDS])
    orig = np.mean([mean_ospa2(cached_run("paper", ORIGINAL, s)) for s in SEEDS])
    # measured: 36.97 m (short) vs 35.12 m (original), 5.3 % apart: not met. Per seed the short
    # chains are 0.7-5.1 m worse (1.9 ± 0.9 m): they lose low-weight hypotheses (see
    # test_vo_accuracy_ten_seeds). With Vo & Ma's merge rule both were ~3 m worse and within
    # 1 % (38.85 vs 38.63 m).
    assert abs(short - orig) <= 0.05 * orig, (short, orig)


@pytest.mark.slow
def test_short_chain_accuracy_matches_original_paper_twenty_seeds():
    # The same comparison with more seeds, to see past the seed-to-seed spread of the 5-seed
    # test above (not instead of it). Measured over seeds 0-19: 36.39 ± 0.48 m (short) vs
    # 35.26 ± 0.32 m (original); paired difference 1.13 ± 0.32 m, 3.2 % of the original's
    # value. (The exact update: 35.88 ± 0.48 m. The 100 runs of the full tracking study: paired
    # difference 0.73 ± 0.14 m, 2.0 %.)
    seeds = range(20)
    short = np.array([mean_ospa2(cached_run("paper", PAPER_SHORT, s)) for s in seeds])
    orig = np.array([mean_ospa2(cached_run("paper", ORIGINAL, s)) for s in seeds])
    assert abs(short.mean() - orig.mean()) <= 0.05 * orig.mean(), (short.mean(), orig.mean())


@pytest.mark.slow
def test_short_chain_accuracy_matches_exact_paper():
    # Exact() is the exact LMB update (oracle.marginals: exact per connected component, with a
    # frontier DP for the sparse gated problems of P ~ 20 rows). Measured: 36.97 m (short) vs
    # 36.04 m (exact), 2.6 % apart.
    short = np.mean([mean_ospa2(cached_run("paper", PAPER_SHORT, s)) for s in SEEDS])
    exact = np.mean([mean_ospa2(cached_run("paper", EXACT, s)) for s in SEEDS])
    assert abs(short - exact) <= 0.05 * exact, (short, exact)


@pytest.mark.slow
def test_short_chain_accuracy_matches_exact_vo_grouped():
    # Exact with grouping on the "vo" preset (MAP-cardinality extraction, the preset's
    # default); the short-chain sampler runs per group as well.
    short = np.mean([mean_ospa2(cached_run("vo", PAPER_SHORT, s, True)) for s in SEEDS])
    exact = np.mean([mean_ospa2(cached_run("vo", EXACT, s, True)) for s in SEEDS])
    assert abs(short - exact) <= 0.05 * exact, (short, exact)


@pytest.mark.slow
@pytest.mark.xfail(strict=True, reason=(
    "ruled out by the model: with the 'paper' preset's 300 m births every posterior stays "
    "diffuse and the short chains save 89.2 % of the sweeps (541 138 of 5 000 000), target 95 %; "
    "under the variance reading ('paper-var') they save 98.4 %"))
def test_short_chain_saves_observations_paper():
    # The target: >= 95 % fewer observations, counted as sweeps with one sampler call
    # per scan (spec §6.6, A13). Measured: 89.2 % (1 082 vs 10 000 sweeps per scan, seeds 0-4).
    # Other conventions, for the record: row updates 89.9 % fewer; grouping changes nothing on
    # this preset (one group per scan); the paper's own totals (10 760 000 vs 63 474) are 99.4 %.
    short = sum(cached_run("paper", PAPER_SHORT, s).sweeps.sum() for s in SEEDS)
    orig = sum(cached_run("paper", ORIGINAL, s).sweeps.sum() for s in SEEDS)
    assert np.all([np.all(cached_run("paper", k, s).invocations == 1)
                   for k in (PAPER_SHORT, ORIGINAL) for s in SEEDS])
    assert short <= 0.05 * orig, (short, orig, 1 - short / orig)


@pytest.mark.slow
@pytest.mark.parametrize("key", [PAPER_SHORT, PAPER_SHORT_RB], ids=["truncated", "rao-blackwell"])
def test_short_chain_saves_observations_vo(key):
    # On the "vo" preset (births of 10 m spread) the posteriors are concentrated and the stale
    # rule stops the short chains after a few chains: measured 117 (truncated) and 118
    # (Rao-Blackwellised) sweeps per scan against 10 000, 98.8 % fewer, seeds 0-9
    short = sum(cached_run("vo", key, s).sweeps.sum() for s in range(10))
    orig = sum(cached_run("vo", ORIGINAL, s).sweeps.sum() for s in range(10))
    assert short <= 0.05 * orig, (short, orig, 1 - short / orig)


@pytest.mark.slow
@pytest.mark.xfail(strict=True, reason=(
    "ruled out by the model: mean OSPA(2) over seeds 0-4 is 36.97 m, target 35 m; the exact "
    "update, the posterior the samplers approximate, gives 36.04 m"))
def test_paper_accuracy_five_seeds():
    # The target: mean OSPA(2) <= 35 m over seeds 0-4. Measured: 36.97 m (seeds 0-4:
    # 33.7, 42.8, 37.8, 35.5, 35.0); the exact update gives 36.04 m, the original sampler
    # 35.12 m (see the module docstring).
    vals = [mean_ospa2(cached_run("paper", PAPER_SHORT, s)) for s in SEEDS]
    assert np.mean(vals) <= 35.0, vals


@pytest.mark.slow
@pytest.mark.xfail(strict=True, reason=(
    "truncated short chains on 'vo': mean OSPA(2) 12.60 m over seeds 0-9, target 12 m (exact, "
    "original and Rao-Blackwellised short chains give 11.92 m)"))
def test_vo_accuracy_ten_seeds():
    # The target: mean OSPA (c = 100 m, p = 1) <= 12 m over seeds 0-9 on the "vo"
    # preset with the short-chain sampler, with the preset's default MAP-cardinality extraction
    # (Vo's code). Measured: 12.60 m (hysteresis: 13.81 m; with grouping: 12.12 m). Seeds 0
    # and 7 (16.6 and 13.6 m) each lose a target for good: e.g. target 8 of seed 0 is missed at
    # scan 41, right after its first detection; the exact update leaves its track r = 0.0032,
    # but the hypotheses in which it exists undetected weigh ~0.3 % and the short chains never
    # visit them, so r = 0, the track is pruned, and the 10 m-wide births cannot pick the
    # target up again. Exact() and OriginalGibbs(10 000) keep it, and so do the same short
    # chains with Rao-Blackwellised marginals (next tests).
    vals = [mean_ospa(cached_run("vo", PAPER_SHORT, s)) for s in range(10)]
    assert np.mean(vals) <= 12.0, vals


@pytest.mark.slow
def test_vo_accuracy_ten_seeds_rao_blackwell():
    # The same short chains with Rao-Blackwellised marginals keep the missed newborns (see
    # tests/test_tracking_marginals.py) and meet the target: measured 11.92 m, as Exact()
    vals = [mean_ospa(cached_run("vo", PAPER_SHORT_RB, s)) for s in range(10)]
    assert np.mean(vals) <= 12.0, vals
    assert max(vals) <= 13.0, vals


@pytest.mark.slow
def test_short_chain_rao_blackwell_matches_original_and_exact_paper():
    # measured: 36.03 m (short chains, Rao-Blackwellised) vs 35.12 m (original, truncated, the
    # paper's construction; 2.6 %) and 36.04 m (exact); 1 290 sweeps per scan, 87.1 % fewer
    # than the original (the tracks it keeps make the problems larger)
    rb = np.mean([mean_ospa2(cached_run("paper", PAPER_SHORT_RB, s)) for s in SEEDS])
    orig = np.mean([mean_ospa2(cached_run("paper", ORIGINAL, s)) for s in SEEDS])
    exact = np.mean([mean_ospa2(cached_run("paper", EXACT, s)) for s in SEEDS])
    assert abs(rb - orig) <= 0.05 * orig, (rb, orig)
    assert abs(rb - exact) <= 0.05 * exact, (rb, exact)
    for s in SEEDS:
        check_paper_properties(cached_run("paper", PAPER_SHORT_RB, s))


# ------------------------------------------------ "paper-var": birth numbers read as variances
@pytest.mark.slow
def test_paper_var_accuracy_five_seeds():
    # The accuracy and cost targets, on the preset whose birth covariance is
    # diag(300, 10, 300, 10) (sigma 17.3 m, 3.16 m/s), one call per scan. Measured (seeds
    # 0-4): short chains 27.16 m, original 27.28 m, exact 27.36 m; 159 against 10 000 sweeps per
    # scan (98.4 % fewer).
    short = [mean_ospa2(cached_run("paper-var", PAPER_SHORT, s)) for s in SEEDS]
    orig = [mean_ospa2(cached_run("paper-var", ORIGINAL, s)) for s in SEEDS]
    exact = [mean_ospa2(cached_run("paper-var", EXACT, s)) for s in SEEDS]
    assert np.mean(short) <= 35.0, short
    assert abs(np.mean(short) - np.mean(orig)) <= 0.05 * np.mean(orig), (short, orig)
    assert abs(np.mean(short) - np.mean(exact)) <= 0.05 * np.mean(exact), (short, exact)
    sw_short = sum(cached_run("paper-var", PAPER_SHORT, s).sweeps.sum() for s in SEEDS)
    sw_orig = sum(cached_run("paper-var", ORIGINAL, s).sweeps.sum() for s in SEEDS)
    assert sw_short <= 0.05 * sw_orig, (sw_short, sw_orig)


@pytest.mark.slow
@pytest.mark.parametrize("key", [PAPER_SHORT, PAPER_SHORT_RB, ORIGINAL, EXACT],
                         ids=["short", "short-rb", "original", "exact"])
@pytest.mark.parametrize("seed", SEEDS)
def test_paper_var_properties_every_seed(key, seed, request):
    if key == PAPER_SHORT and seed == 2:
        request.applymarker(pytest.mark.xfail(strict=True, reason=(
            "target 11 is never tracked by the truncated short chains on seed 2 (coverage 0 "
            "against the 0.85 target; traced below)")))
    # Fails for the short chains with the paper's truncated marginals on seed 2: target 11
    # (born at scan 80 next to birth location 1, at 25 m/s) is never tracked (coverage 0; also
    # on seed 5 of 0-9). Traced on seed 2: its first detection gives the newborn track (80, 1)
    # r = 0.16 (exact update 0.18); scan 81 misses the target (p_D = 0.98), and the exact update
    # keeps the track at r = 0.004, carried by hypotheses in which it exists undetected. The
    # short chains' 63 sweeps of that scan visit none of them, so its r is 0 and it is pruned.
    # At its next detection the target is 75 m from the birth mean, moving 8 sigma outside the
    # 3.16 m/s birth spread, and no later birth picks it up. The original sampler, the exact
    # update and the same short chains with Rao-Blackwellised marginals track every target on
    # seeds 0-9.
    check_paper_properties(cached_run("paper-var", key, seed))


@pytest.mark.slow
def test_paper_var_per_group_totals_five_seeds():
    # One call per group, empty groups included: the paper's totals within 5 % and 10 %.
    # Measured (seeds 0-4): 10 402 000 and 60 934 sweeps per run (paper: 10 760 000 and 63 474),
    # 99.41 % fewer (paper: 99.41 %); 10.40 groups per scan, 60.1 sweeps per short-chain call.
    orig = np.mean([cached_run("paper-var", ORIGINAL, s, True, True).sweeps.sum()
                    for s in SEEDS])
    short = np.mean([cached_run("paper-var", PAPER_SHORT, s, True, True).sweeps.sum()
                     for s in SEEDS])
    assert abs(orig / PAPER_TOTALS[0] - 1) <= 0.05, orig
    assert abs(short / PAPER_TOTALS[1] - 1) <= 0.10, short
    assert 1 - short / orig >= 0.99


@pytest.mark.slow
def test_paper_var_per_group_accuracy_twenty_seeds():
    # Per group, the truncated marginals of the short chains occasionally drop a newborn that
    # the original keeps (seed 4: target 3, 20 m/s against the 3.16 m/s birth spread, is lost
    # for 35 scans; 48.6 m against 27.4 m; with Rao-Blackwellised marginals 27.4 m), so five
    # seeds are 14.8 % apart (31.37 vs 27.32 m). Over seeds 0-19: 28.28 m (short chains),
    # 27.70 m (original), 2.1 %.
    seeds = range(20)
    short = np.mean([mean_ospa2(cached_run("paper-var", PAPER_SHORT, s, True, True))
                     for s in seeds])
    orig = np.mean([mean_ospa2(cached_run("paper-var", ORIGINAL, s, True, True))
                    for s in seeds])
    assert short <= 35.0
    assert abs(short - orig) <= 0.05 * orig, (short, orig)


@pytest.mark.slow
@pytest.mark.parametrize("key", [ORIGINAL, EXACT], ids=["original", "exact"])
def test_vo_accuracy_ten_seeds_exact_and_original(key):
    # The filter itself meets the vo target: measured 11.92 m for both (no target lost; every
    # seed within 11.2-12.5 m)
    vals = [mean_ospa(cached_run("vo", key, s)) for s in range(10)]
    assert np.mean(vals) <= 12.0, vals
    assert max(vals) <= 13.0, vals

"""The reproduction studies on tiny configurations: structure, sanity, reproducibility."""

import dataclasses
import math
import re
import time

import numpy as np
import pytest
from numpy.testing import assert_allclose, assert_array_equal

import oracle
from rankedassign.experiments import (
    CRITERIA,
    PAPER_TABLE1,
    STALE_READINGS,
    STALL_READINGS,
    AblationConfig,
    Config,
    OptimumConfig,
    ReproduceError,
    SweepConfig,
    SweepRow,
    Table1Config,
    Table1Row,
    TrackingConfig,
    best_error,
    local_executor,
    run_study,
)
from rankedassign.experiments.studies.tracking import summarise_tracking
from rankedassign.single import synthetic

# Paper thresholds, a small budget: 200 chains x 25 sweeps.
TINY = {"n_mc": 2, "original_obs": 5_000, "n_chains": 200, "chain_length": 25}
TABLE1_KEYS = {
    "family", "criterion", "delta_obs_pct", "delta_error_pp", "delta_obs_pct_se",
    "delta_error_pp_se", "obs_original_mean", "obs_proposed_mean", "error_original_mean",
    "error_proposed_mean", "mean_abs_delta_error_pp", "n_mc",
}


@pytest.fixture(scope="module")
def table1():
    return run_study("table1", Table1Config(**TINY), seed=11, progress=False, return_runs=True)


def test_table1_structure_and_ranges(table1):
    rows, runs = table1
    assert [(r.family, r.criterion) for r in rows] == [
        (f, c) for f in ("diagonal", "uniform", "random", "random-r_pd") for c in CRITERIA
    ]
    for r in rows:
        assert TABLE1_KEYS <= {f.name for f in dataclasses.fields(r)}
        assert r.n_mc == 2
        assert 0.0 <= r.error_original_mean <= 100.0
        assert 0.0 <= r.error_proposed_mean <= 100.0
        assert r.obs_proposed_mean <= 200 * 25
        assert r.obs_original_mean == 5_000
        assert r.delta_error_pp == pytest.approx(
            abs(r.error_original_mean - r.error_proposed_mean), rel=1e-12, abs=1e-12)
        assert r.mean_abs_delta_error_pp >= r.delta_error_pp - 1e-12
        assert r.delta_obs_pct_se is not None and r.delta_obs_pct_se >= 0
    for run in runs:
        for k in ("original", *CRITERIA):
            assert 0.0 <= getattr(run, k).error <= 1.0
    by = {(r.family, r.criterion): r for r in rows}
    # One dominant assignment: every rule stops early (spec §3.4, Table I diagonal row).
    for c in CRITERIA:
        assert by["diagonal", c].delta_obs_pct > 50.0
    # Spec §3.5: the consecutive stale rule (T3) does not fire on the uniform/random families.
    assert by["uniform", "stale"].stale_stop_fraction == 0.0
    assert by["random", "stale"].stale_stop_fraction == 0.0


def test_table1_no_rule_active_gives_zero_delta_obs():
    huge = 10**9
    cfg = Table1Config(n_mc=2, original_obs=1_000, n_chains=40, chain_length=25,
                       tau_stall=huge, tau_stale=huge, families=("uniform", "random"))
    rows = run_study("table1", cfg, seed=3, progress=False)
    for r in rows:
        assert r.delta_obs_pct == 0.0
        assert r.delta_obs_pct_se == 0.0
        assert r.obs_proposed_mean == 1_000


def test_table1_statistics_by_hand(table1):
    rows, runs = table1
    fam, crit = "random", "stall"
    rs = sorted((r for r in runs if r.family == fam), key=lambda r: r.run)
    No = np.array([r.original.n_obs for r in rs], float)
    Ns = np.array([r.criterion(crit).n_obs for r in rs], float)
    eo = 100 * np.array([r.original.error for r in rs])
    es = 100 * np.array([r.criterion(crit).error for r in rs])
    row = next(r for r in rows if (r.family, r.criterion) == (fam, crit))
    assert_allclose(row.delta_obs_pct, 100 * (No.mean() - Ns.mean()) / No.mean(), rtol=1e-12)
    assert_allclose(row.delta_error_pp, abs(eo.mean() - es.mean()), rtol=1e-12)
    assert_allclose(row.delta_error_pp_se, np.std(es - eo, ddof=1) / math.sqrt(2), rtol=1e-12)
    assert_allclose(row.mean_abs_delta_error_pp, np.abs(es - eo).mean(), rtol=1e-12)
    # Original N_o is constant, so the delta method reduces to sd(N_s) / (mean N_o sqrt(n)).
    assert_allclose(row.delta_obs_pct_se, 100 * Ns.std(ddof=1) / No.mean() / math.sqrt(2),
                    rtol=1e-10)


def test_table1_random_matrix_redrawn_and_errors_exact(table1):
    _, runs = table1
    rs = [r for r in runs if r.family == "random"]
    # Different matrices per run: the original error differs between runs.
    assert rs[0].original.error != rs[1].original.error
    # The matrix of run r is synthetic.random(rng=child 0 of run seed r): recompute one error.
    from rankedassign import sample_original
    from rankedassign.experiments import child_seed, run_seed

    s = run_seed(11, 1)
    p = synthetic.random(pbar_d="pd", granularity="matrix", rng=child_seed(s, 0))  # A2, A5
    res = sample_original(p, 5_000, rng=child_seed(s, 1, 2))
    assert rs[1].original.error == oracle.truncation_error(p, res.assignments)


@pytest.mark.e2e
def test_table1_same_seed_same_numbers_any_executor(table1):
    rows, runs = table1
    again = run_study("table1", Table1Config(**TINY), seed=11, progress=False)
    assert again == rows
    with local_executor(2) as ex:
        pooled = run_study("table1", Table1Config(**TINY), seed=11, executor=ex, progress=False,
                            return_runs=True)
    assert pooled == (rows, runs)
    other = run_study("table1", Table1Config(**TINY), seed=12, progress=False)
    assert other != rows


@pytest.mark.e2e
@pytest.mark.parametrize("processes", [False, True])
def test_dask_cluster_matches_serial(processes):
    distributed = pytest.importorskip("distributed")
    cfg = Table1Config(n_mc=2, original_obs=2_000, n_chains=80, families=("uniform", "random"))
    serial = run_study("table1", cfg, seed=5, progress=False, return_runs=True)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=processes,
                                  dashboard_address=":0") as cluster:
        with distributed.Client(cluster) as client:
            dask = run_study("table1", cfg, seed=5, executor=client.get_executor(), progress=False,
                              return_runs=True)
    assert dask == serial


def test_ablation_structure_and_readings():
    cfg = AblationConfig(n_mc=2, original_obs=2_000, n_chains=80,
                         families=("diagonal", "uniform"))
    rows, runs = run_study("ablation", cfg, seed=11, progress=False, return_runs=True)
    assert len(rows) == len(STALL_READINGS) * len(STALE_READINGS) * 2 * len(CRITERIA)
    assert {(r.stall, r.stale) for r in rows} == {
        (a, b) for a in STALL_READINGS for b in STALE_READINGS}
    assert all(TABLE1_KEYS <= {f.name for f in dataclasses.fields(r)} for r in rows)
    by = {(r.stall, r.stale, r.criterion): r for r in rows if r.family == "uniform"}
    diag = {(r.stall, r.stale, r.criterion): r for r in rows if r.family == "diagonal"}
    # Literal set form |x| - n_u never fires; the multiset form fires after the first chain.
    assert by["global-consecutive", "literal-set", "stale"].stale_stop_fraction == 0.0
    multiset = by["global-consecutive", "literal-multiset", "stale"]
    assert multiset.stale_stop_fraction == 1.0
    assert multiset.chains_proposed_mean <= cfg.tau_stale + 1
    # Chain-local stall (S1) never fires on the uniform matrix (spec A10): no saving at all.
    assert by["chain-local", "consecutive", "stall"].delta_obs_pct == 0.0
    # Global stall (S3) stops chains on the diagonal matrix, where few solutions matter.
    assert diag["global-consecutive", "consecutive", "stall"].delta_obs_pct > 50.0
    # Stall-only rows depend on the stall reading only (shared runs).
    def numbers(row):
        return {k: v for k, v in dataclasses.asdict(row).items() if k != "stale"}

    for b in STALE_READINGS:
        assert numbers(diag["global-cumulative", b, "stall"]) == numbers(
            diag["global-cumulative", "consecutive", "stall"])


def test_ablation_report_names_the_other_random_reading():
    from rankedassign.experiments import get_study

    cfg = AblationConfig(n_mc=2, original_obs=500, n_chains=20, families=("random", "random-r_pd"),
                         stall_readings=(STALL_READINGS[0],), stale_readings=(STALE_READINGS[0],))
    rows = run_study("ablation", cfg, seed=1, progress=False)
    text = get_study("ablation").render(rows, cfg)
    assert ("`random-r_pd` is the random family read as P̄_D = r·P_d, matrix P_s, P_d (spec A2)"
            in text)
    assert "| random-r_pd consistent? |" in text
    assert "These settings are not the paper's (spec §3.4), so no cell is judged" in text


def test_ablation_recommended_pair_equals_table1():
    kw = {"n_mc": 2, "original_obs": 2_000, "n_chains": 80, "families": ("diagonal", "random")}
    t1 = run_study("table1", Table1Config(**kw), seed=4, progress=False)
    ab = run_study("ablation", AblationConfig(**kw, stall_readings=(STALL_READINGS[0],),
                                     stale_readings=(STALE_READINGS[0],)), seed=4, progress=False)
    for a, t in zip(ab, t1, strict=True):
        fields = dataclasses.asdict(a)
        del fields["stall"], fields["stale"]
        assert Table1Row(**fields) == t


def test_sweep_structure_and_monotone_original():
    cfg = SweepConfig(n_mc=2, families=("uniform", "random"), obs_grid=(10, 100, 1_000),
                      chain_lengths=(5, 25))
    rows, runs = run_study("sweep", cfg, seed=2, progress=False, return_runs=True)
    keys = {(r.family, r.sampler, r.budget) for r in rows}
    assert ("uniform", "short-25", 10) not in keys  # budget below the chain length
    assert ("uniform", "short-25", 100) in keys and ("random", "original", 1_000) in keys
    for r in rows:
        assert 0.0 <= r.error_pct_q10 <= r.error_pct_mean <= r.error_pct_q90 <= 100.0
        if r.sampler != "original":
            L = r.chain_length
            assert r.n_obs_mean == (r.budget // L) * L
    by = {(r.family, r.sampler, r.budget): r for r in rows}
    for (fam, sampler, budget), r in by.items():
        if sampler == "original":
            assert r.diff_vs_original_pp_mean == 0.0
        else:
            paired = [
                100 * (p.error - q.error)
                for run in runs if run.family == fam
                for p in run.points if (p.sampler, p.budget) == (sampler, budget)
                for q in run.points if (q.sampler, q.budget) == ("original", budget)
            ]
            assert_allclose(r.diff_vs_original_pp_mean, np.mean(paired), rtol=1e-12,
                            atol=1e-12)
    for run in runs:
        # Same stream at every budget: the original chain's unique set only grows.
        errs = [p.error for p in run.points if p.sampler == "original"]
        assert errs == sorted(errs, reverse=True)
        uniq = [p.n_unique for p in run.points if p.sampler == "short-5"]
        assert uniq == sorted(uniq)


def test_best_error_exact():
    u = synthetic.uniform()
    for k in (0, 1, 1000, 76_847, 76_848, 10**6):
        assert_allclose(best_error(u, k), max(0.0, 1 - k / 76_848), rtol=1e-12, atol=1e-15)
    p = synthetic.random(rng=9)
    for k in (1, 7, 50):
        assert_allclose(best_error(p, k), 1 - oracle.best_mass(p, k), rtol=1e-9, atol=1e-14)
    with pytest.raises(ValueError, match="k must be a non-negative integer, got -1"):
        best_error(p, -1)


def test_optimum_bounds():
    cfg = OptimumConfig(n_mc=2, original_obs=2_000, n_chains=80)
    rows, runs = run_study("optimum", cfg, seed=1, progress=False, return_runs=True)
    assert [(r.family, r.sampler) for r in rows] == [
        (f, s) for f in ("diagonal", "uniform", "random") for s in ("original", "proposed")]
    for run in runs:
        for s in ("original", "proposed"):
            rec = getattr(run, s)
            assert rec.best_error <= rec.error + 1e-12
            if run.family == "uniform":  # equal weights: any k solutions are optimal
                assert_allclose(rec.error, rec.best_error, rtol=1e-9)
    for r in rows:
        assert r.excess_error_pp_mean >= -1e-9


def test_tracking_tiny():
    cfg = TrackingConfig(n_mc=2, n_scans=8, original_obs=200, n_chains=20)
    out, runs = run_study("tracking", cfg, seed=0, progress=False, return_runs=True)
    for key in ("obs_original", "obs_proposed", "reduction_pct", "row_updates_original",
                "row_updates_proposed", "reduction_row_updates_pct", "ospa2_mean_original",
                "ospa2_mean_proposed"):
        assert math.isfinite(getattr(out, key)), key
    assert out.obs_original == 8 * 200  # one call per scan without grouping
    assert out.obs_proposed <= 8 * 20 * 25
    assert_allclose(out.reduction_pct, 100 * (1 - out.obs_proposed / out.obs_original),
                    rtol=1e-12)
    cur = out.curves
    assert len(cur["ospa2_original"]) == len(cur["cumulative_obs_proposed"]) == 8
    assert cur["cumulative_obs_original"][-1] == out.obs_original
    assert all(0.0 <= v <= 200.0 for v in cur["ospa2_proposed"])
    by = {(r.run, r.truncation): r for r in runs}
    for r in range(2):  # same measurements for both samplers in a run
        assert_array_equal(by[r, "original"].n_meas, by[r, "short-chain"].n_meas)
    assert by[0, "original"].n_meas != by[1, "original"].n_meas
    assert out.config["marginals"] == "truncated"
    # 8 scans: no target lives past the 10 settling scans, so none is counted, none lost
    assert all(rec.coverage == [None] * 12 for rec in runs)
    assert out.targets_lost_original == out.targets_lost_proposed == 0


def test_tracking_reads_the_old_name_of_the_short_chains_with_a_deprecation_warning():
    from rankedassign.experiments.studies.tracking import tracking_task

    cfg = TrackingConfig(n_mc=1, n_scans=3, original_obs=50, n_chains=5)
    with pytest.warns(DeprecationWarning, match=r"^truncation: 'proposed' is deprecated; "
                                                r"write 'short-chain'$"):
        old = tracking_task(cfg, 0, 0, "proposed")
    new = tracking_task(cfg, 0, 0, "short-chain")
    assert old.truncation == new.truncation == "short-chain"
    untimed = {"total_seconds": 0.0, "association_seconds": []}
    assert dataclasses.replace(old, **untimed) == dataclasses.replace(new, **untimed)
    with pytest.raises(ValueError, match=re.escape(
            "unknown truncation 'gibbs'; expected one of ('original', 'short-chain')")):
        tracking_task(cfg, 0, 0, "gibbs")


def test_tracking_reports_gospa_beside_ospa2():
    from rankedassign.experiments.studies.tracking import render_tracking
    from rankedassign.metrics import gospa_series
    from rankedassign.tracking import run_scenario

    cfg = TrackingConfig(n_mc=2, n_scans=6, original_obs=50, n_chains=5)
    out, runs = run_study("tracking", cfg, seed=0, progress=False, return_runs=True)
    for rec in runs:
        g = np.array(rec.gospa)
        parts = np.array([getattr(rec, f"gospa_{k}") for k in ("localisation", "missed",
                                                                "false")])
        assert g.shape == (6,)
        # value^p = localisation^p + missed^p + false^p (p = 1 here)
        assert_allclose(g, parts.sum(axis=0), rtol=1e-12)
    for m, c in (("original", "original"), ("short-chain", "proposed")):
        per_run = [np.mean(r.gospa) for r in runs if r.truncation == m]
        assert_allclose(getattr(out, f"gospa_mean_{c}"), np.mean(per_run), rtol=1e-12)
        assert len(out.curves[f"gospa_{c}"]) == len(out.curves[f"gospa_missed_{c}"]) == 6
    text = render_tracking(out, cfg)
    assert "mean GOSPA (m; c = 200, p = 1)" in text and "GOSPA (α = 2" in text
    # the task's GOSPA is gospa_series of the run's arrays
    from rankedassign.experiments.studies.tracking import _association, run_seed

    rec = next(r for r in runs if r.run == 0 and r.truncation == "original")
    sr = run_scenario(cfg.preset, _association(cfg, "original"), rng=run_seed(0, 0),
                      n_scans=6, grouping=cfg.grouping, extraction=cfg.extraction)
    assert_allclose(rec.gospa, gospa_series(sr.truth, sr.estimates, 200.0, 1.0).value,
                    rtol=1e-12)


def test_tracking_lost_targets_counted_by_hand():
    cfg = TrackingConfig(n_mc=2, n_scans=4, original_obs=50, n_chains=5)
    _, runs = run_study("tracking", cfg, seed=0, progress=False, return_runs=True)
    cover = {(0, "original"): [1.0, None, 0.5], (1, "original"): [1.0, 1.0, 1.0],
             (0, "short-chain"): [1.0, 0.2, 0.49], (1, "short-chain"): [0.0, None, 1.0]}
    runs = [dataclasses.replace(rec, coverage=cover[rec.run, rec.truncation]) for rec in runs]
    out = summarise_tracking(runs, cfg)
    # lost: coverage < 0.5; 0.5 itself is kept and None (too short-lived) is not counted
    assert (out.targets_lost_original, out.runs_with_lost_target_original) == (0, 0)
    assert (out.targets_lost_proposed, out.runs_with_lost_target_proposed) == (3, 2)


def test_tracking_var_tiny():
    # the paper-var reading, one call per group with the empty groups: every group is a call,
    # and the runs see the tracking study's measurements (same seed)
    cfg = TrackingConfig.paper_var(n_mc=2, n_scans=6, original_obs=200, n_chains=20)
    out, runs = run_study("tracking_var", cfg, seed=0, progress=False, return_runs=True)
    _, base = run_study("tracking",
                        TrackingConfig(n_mc=2, n_scans=6, original_obs=200, n_chains=20),
                        seed=0, progress=False, return_runs=True)
    assert out.config["preset"] == "paper-var"
    assert out.config["sample_empty_groups"] is True
    by = {(r.run, r.truncation): r for r in runs}
    by_base = {(r.run, r.truncation): r for r in base}
    for key, rec in by.items():
        assert rec.n_meas == by_base[key].n_meas
        assert rec.invocations == rec.n_groups
        assert all(g >= 4 for g in rec.n_groups)  # the 4 births are 4 groups at least
    assert out.obs_original == 200 * out.invocations_original
    assert_allclose(out.sweeps_per_call_original, 200.0)
    assert_allclose(out.paper_calls_per_scan, 10.76)
    assert_allclose(out.paper_sweeps_per_call_proposed, 63_474 / 1_076)
    # a Config contributes its tracking_var field; None means TrackingConfig.paper_var()
    from rankedassign.experiments import get_study
    from rankedassign.experiments.registry import study_config

    assert Config.quick()["tracking_var"].preset == "paper-var"
    assert study_config(None, get_study("tracking_var")) == TrackingConfig.paper_var()


def test_tracking_tiny_rao_blackwell_marginals():
    # the switch reaches both samplers: same sampling, hence the same sweeps on the first scan
    # (the marginals differ from then on, and so do the tracks and the later problems)
    base = TrackingConfig(n_mc=1, n_scans=6, original_obs=200, n_chains=20)
    rb = TrackingConfig(n_mc=1, n_scans=6, original_obs=200, n_chains=20,
                        marginals="rao-blackwell")
    _, runs_t = run_study("tracking", base, seed=0, progress=False, return_runs=True)
    out, runs_r = run_study("tracking", rb, seed=0, progress=False, return_runs=True)
    assert out.config["marginals"] == "rao-blackwell"
    by_t = {r.truncation: r for r in runs_t}
    by_r = {r.truncation: r for r in runs_r}
    for m in ("original", "short-chain"):
        assert by_r[m].sweeps[0] == by_t[m].sweeps[0]
        assert by_r[m].n_meas == by_t[m].n_meas
    # tracks of small existence that no sampled hypothesis keeps alive are pruned under the
    # truncated marginals and kept under the Rao-Blackwellised ones (measured on this seed:
    # 12 against 9-10 tracks at scan 3, 18 against 11-12 at scan 6)
    for m in ("original", "short-chain"):
        assert sum(by_r[m].n_tracks) > sum(by_t[m].n_tracks)


def test_other_random_reading_is_paired_with_random():
    from rankedassign.experiments import child_seed, run_seed
    from rankedassign.experiments._synthetic import make_problem

    cfg = AblationConfig()
    assert cfg.families == ("diagonal", "uniform", "random", "random-r_pd")
    assert Table1Config().families == cfg.families
    # the readings the random_readings study found consistent with Table I (A2, A5)
    assert (cfg.pbar_d, cfg.diagonal_pbar_d, cfg.granularity) == ("pd", "r_pd", "matrix")
    s = run_seed(8, 3)
    a = make_problem("random", s, cfg)
    b = make_problem("random-r_pd", s, cfg)
    assert a == synthetic.random(pbar_d="pd", granularity="matrix", rng=child_seed(s, 0))
    assert a == make_problem("random-pd", s, cfg)
    assert b == synthetic.random(pbar_d="r_pd", granularity="matrix", rng=child_seed(s, 0))
    assert make_problem("diagonal", s, cfg) == synthetic.diagonal(pbar_d="r_pd")
    # Same draws: the dead weights 1 - r P_s do not depend on Pbar_D.
    assert_allclose(a.eta()[2], b.eta()[2], rtol=1e-15)
    with pytest.raises(ValueError, match="unknown family 'square'"):
        make_problem("square", s, cfg)


def _stats(obs, obs_se, err, err_se, n=100):
    from rankedassign.experiments._synthetic import PairedStats

    return PairedStats(
        n_mc=n, obs_original_mean=1.0, obs_proposed_mean=1.0, error_original_mean=1.0,
        error_proposed_mean=1.0, delta_obs_pct=obs, delta_error_pp=err,
        delta_error_signed_pp=err, mean_abs_delta_error_pp=err, unique_original_mean=1.0,
        unique_proposed_mean=1.0, chains_proposed_mean=1.0, stale_stop_fraction=0.0,
        delta_obs_pct_se=obs_se, delta_error_pp_se=err_se, mean_abs_delta_error_pp_se=err_se,
        error_original_se=0.1, error_proposed_se=0.1,
    )


def test_rows_carry_the_papers_cells_and_the_three_se_rule():
    from rankedassign.experiments._synthetic import with_paper

    # the quick-run random stale cell: 6.3 +- 2.7 % against the paper's 0.00
    r = with_paper("random", "stale", _stats(6.3, 2.7, 0.0, 0.0))
    assert (r.paper_delta_obs_pct, r.paper_delta_error_pp) == (0.0, 0.0)
    assert r.delta_obs_z == pytest.approx(2.33) and r.agrees_with_paper is True
    # the same saving with the standard error of 100 runs is more than 3 SE away
    r = with_paper("random", "stale", _stats(6.3, 1.3, 0.0, 0.0))
    assert r.delta_obs_z == pytest.approx(4.85) and r.agrees_with_paper is False
    # a zero standard error agrees only to the paper's printed precision (half a unit)
    assert with_paper("uniform", "stale", _stats(0.004, 0.0, 0.0, 0.0)).agrees_with_paper
    assert with_paper("uniform", "stale", _stats(0.006, 0.0, 0.0, 0.0)).delta_obs_z == math.inf
    # the alternative reading of a family is compared with the paper's row of that family
    alt = with_paper("random-pd", "full", _stats(56.0, 0.5, 6.0, 0.2))
    assert (alt.paper_family, alt.paper_delta_obs_pct, alt.agrees_with_paper) == (
        "random", 56.96, True)
    # one run has no standard error: nothing is judged; other settings are not judged either
    assert with_paper("random", "full", _stats(57.0, None, 6.3, None, n=1)).agrees_with_paper \
        is None
    unjudged = with_paper("random", "full", _stats(0.0, 0.1, 0.0, 0.1), judge=False)
    assert unjudged.paper_delta_obs_pct == 56.96 and unjudged.agrees_with_paper is None


def test_table1_verdict_separates_the_default_reading_from_the_other():
    from rankedassign.experiments import get_study
    from rankedassign.experiments._synthetic import with_paper

    rows = [with_paper(f, c, _stats(p.delta_obs_pct, 0.5, p.delta_error_pp, 0.1))
            for (f, c), p in PAPER_TABLE1.items()]
    rows += [with_paper("random-r_pd", c, _stats(65.0, 1.3, 5.3, 0.17))
             for c in ("stall", "full")]
    text = get_study("table1").render(rows, Table1Config())
    assert ("Under the default readings, all 18 numbers of the 9 compared cells lie within 3 "
            "standard errors of the paper's.") in text
    assert ("Under the other reading of the random family, 4 numbers of the 4 compared lie "
            "more than 3 standard errors from the paper's:") in text
    assert ("- random-r_pd: P̄_D = r·P_d, matrix P_s, P_d, stall: ΔObs 65.00 ± 1.30 % against "
            "the paper's 56.97 % (+6.2 SE)") in text


def test_ablation_verdict_uses_the_three_se_rule():
    from rankedassign.experiments._synthetic import with_paper
    from rankedassign.experiments.studies.ablation import consistency

    good = [with_paper(f, c, _stats(p.delta_obs_pct, 0.5, p.delta_error_pp, 0.1))
            for (f, c), p in PAPER_TABLE1.items()]
    assert consistency(good) == "yes"
    bad = [r if (r.family, r.criterion) != ("random", "stale")
           else with_paper("random", "stale", _stats(6.3, 1.3, 0.0, 0.0)) for r in good]
    assert consistency(bad) == "no: random stale"
    assert consistency([with_paper("random", "stale", _stats(6.3, None, 0.0, None, n=1))]) \
        == "–"


def test_table1_report_shows_the_paper_beside_ours(table1):
    from rankedassign.experiments import get_study

    rows, _ = table1
    assert all(r.paper_delta_obs_pct == PAPER_TABLE1[r.family.split("-")[0], r.criterion]
               .delta_obs_pct for r in rows)
    # TINY is not the paper's budget: the paper's cells are shown, not judged
    assert all(r.agrees_with_paper is None for r in rows)
    text = get_study("table1").render(rows, Table1Config(**TINY))
    assert "| diagonal: P̄_D = r·P_d | stall |" in text
    assert "| 79.95 |" in text and "| 10.46 |" in text
    assert "| random-r_pd: P̄_D = r·P_d, matrix P_s, P_d | full |" in text
    assert "These settings are not the paper's" in text
    assert "2 Monte Carlo runs" in text


def test_sweep_checks_the_papers_chain_length_statement():
    from rankedassign.experiments.studies.sweep import chain_length_checks, render_sweep

    def row(L, e, se=0.01, budget=1000):
        return SweepRow("random", f"short-{L}", L, budget, budget, 900, e, se, e, e, 0, 0, 10)

    checks = chain_length_checks([row(5, 10.0), row(25, 10.19), row(100, 10.05)])
    assert [(c.spread_pp, c.holds) for c in checks] == [(pytest.approx(0.19), True)]
    rows = [row(5, 10.0), row(25, 10.5), row(5, 3.0, budget=2000), row(25, 3.05, budget=2000)]
    text = render_sweep(rows, SweepConfig(obs_grid=(1000, 2000), chain_lengths=(5, 25)))
    assert "- random: **does not hold** at 1 of 2 budgets: 1,000 (0.500 pp)." in text


def test_random_readings_study(tmp_path):
    from rankedassign.experiments.studies.readings import ReadingsConfig, reading_verdicts

    cfg = ReadingsConfig(n_mc=2, original_obs=1_000, n_chains=40)
    rows, runs = run_study("random_readings", cfg, seed=4, progress=False, return_runs=True)
    # 2 diagonal readings + 1 uniform + 4 random, 2 runs each
    assert len(runs) == 7 * 2
    assert len(rows) == 8 * 9  # every diagonal reading with every random reading
    combos = {(r.diagonal_pbar_d, r.pbar_d, r.granularity) for r in rows}
    assert combos == {(d, a, b) for d in ("r_pd", "pd") for a, b in cfg.readings}
    # the default combination is the table1 study's, run for run
    t1 = run_study("table1", Table1Config(n_mc=2, original_obs=1_000, n_chains=40,
                                          families=("diagonal", "uniform", "random")),
                   seed=4, progress=False)
    default = [r for r in rows if (r.diagonal_pbar_d, r.pbar_d, r.granularity)
               == ("r_pd", "pd", "matrix")]
    for a, t in zip(default, t1, strict=True):
        fields = dataclasses.asdict(a)
        del fields["diagonal_pbar_d"], fields["pbar_d"], fields["granularity"]
        assert Table1Row(**fields) == t
    # the uniform family is shared by every reading
    uni = {dataclasses.astuple(r)[:-3] for r in rows if r.family == "uniform"}
    assert len(uni) == 3
    assert reading_verdicts(rows) == {k: [] for k in combos}  # not judged: tiny budget
    with pytest.raises(ValueError, match="readings must be a non-empty subset"):
        ReadingsConfig(readings=(("pd", "cell"),))


def test_registry_drives_config_and_runner():
    from rankedassign.experiments import Study, get_study, register_study, study_names

    assert study_names()[:6] == ("table1", "sweep", "tracking", "tracking_var", "ablation",
                                 "optimum")
    st = get_study("sweep")
    assert register_study(st) is st
    with pytest.raises(ReproduceError, match="a different study named 'sweep'"):
        register_study(dataclasses.replace(st, title="other"))
    with pytest.raises(ReproduceError, match="unknown study 'tabel1'; choose from table1"):
        get_study("tabel1")
    with pytest.raises(TypeError, match="study must be a Study, got dict"):
        register_study({})
    with pytest.raises(TypeError, match="config must be a SweepConfig or Config, got"):
        run_study("sweep", Table1Config(), progress=False)
    assert isinstance(st, Study) and Config.quick()["sweep"] == st.quick()


def test_glmb_tracking_every_truncation_on_both_presets(tmp_path):
    from rankedassign.experiments.studies.glmb_tracking import (
        GLMB_METHODS,
        GLMBStudyConfig,
        cell_name,
        plot_glmb_tracking,
        render_glmb_tracking,
    )
    cfg = GLMBStudyConfig(n_mc=1, n_scans=4, h_upd=40, h_max=20, n_chains=10, murty_k=20,
                          original_obs=200, glmb_exact_runs=1, retained_mass=("vo",),
                          tradeoff_h_upd=(20,), tradeoff_runs=1)
    s = run_study("glmb_tracking", cfg, seed=0, progress=False)
    assert [p.preset for p in s.presets] == ["vo", "paper"]
    for p in s.presets:
        rows = {(r.filter, r.truncation): r for r in p.rows}
        assert set(rows) == set(GLMB_METHODS)
        for m, r in rows.items():
            if r.n_runs:
                assert 0 <= r.ospa_mean <= cfg.ospa_c and 0 <= r.ospa2_mean <= cfg.ospa_c
                assert len(p.curves[f"ospa_{cell_name(m)}"]) == cfg.n_scans
            assert math.isfinite(r.retained_mass_mean) == (
                m[0] == "glmb" and p.preset == "vo" and r.n_runs > 0)
            assert math.isfinite(r.carried_mass_mean) == math.isfinite(r.retained_mass_mean)
            if math.isfinite(r.carried_mass_mean):
                assert r.carried_mass_mean <= r.retained_mass_mean * (1 + 1e-12)
            if r.n_runs:  # every row with its budget beside its accuracy
                assert r.sweeps_per_scan >= 0
                assert r.hypotheses_per_scan > 0 or m == ("lmb", "exact")  # marginals only
                assert 0 <= r.gospa_mean and 0 <= r.alt_ospa2_mean <= cfg.ospa_c
                assert r.alt_estimator == ("recursive" if m[0] == "glmb" else "hysteresis")
    # the paper scenario's first scan has a component no enumeration reaches: stated, no crash
    exact = {(r.filter, r.truncation): r for r in s.presets[1].rows}["glmb", "exact"]
    assert exact.n_runs == 0
    assert "1 of 1 runs do not fit; run 0 stopped at scan 1: Exact() cannot enumerate" in exact.failed
    text = render_glmb_tracking(s, cfg)
    assert "### Preset `vo`" in text and "### Preset `paper`" in text
    assert "GLMB, exact: 1 of 1 runs do not fit" in text and "does not fit" in text
    assert plot_glmb_tracking(s, tmp_path) == ["glmb_tracking.png", "glmb_tradeoff.png"]
    assert "T_h = 0" in text and "best (deviation)" in text and "95 %" in text
    for p in s.presets:  # every comparison with its paired interval (one run: none)
        assert {(c.a, c.b) for c in p.comparisons} >= {
            ("glmb/short-chain", "glmb/original"), ("glmb/murty-matched", "glmb/short-chain")}
        assert all(c.n == 1 and math.isnan(c.lo_pct) for c in p.comparisons)
        # trade-off points: every GLMB chain truncation at both H_upd, the LMB points beside
        hs = {(q["filter"], q["truncation"], q["h_upd"]) for q in p.tradeoff}
        assert {("glmb", "original", 20), ("glmb", "original", 40), ("glmb", "murty", 20),
                ("glmb", "herded", 20)} <= hs
        assert ("lmb", "original", None) in hs
    # the per-scan OSPA and OSPA(2) are run_scenario's on the same measurements and filter
    from rankedassign.experiments._executor import run_seed
    from rankedassign.experiments.studies.glmb_tracking import glmb_tracking_task
    from rankedassign.metrics import ospa2
    from rankedassign.tracking import ShortChainGibbs, run_scenario

    rec = glmb_tracking_task(cfg, 0, 0, ("lmb", "short-chain"), "vo")
    run = run_scenario("vo", ShortChainGibbs(10, 25, tau_stall=5, tau_stale=10),
                       rng=run_seed(0, 0), n_scans=cfg.n_scans)
    for key, window in (("ospa", 1), ("ospa2", cfg.ospa_window)):
        want = ospa2(run.truth, run.estimates, cfg.ospa_c, cfg.ospa_p, window).value
        assert_allclose(getattr(rec, key), want, rtol=1e-12)
    assert rec.ospa != rec.ospa2


def test_glmb_study_scores_the_lmb_hysteresis_as_a_hysteresis_filter_would():
    from rankedassign.experiments.studies.glmb_tracking import _lmb_hysteresis
    from rankedassign.tracking import LMBFilter, ShortChainGibbs, make_scenario

    sc = make_scenario("paper", rng=2, n_scans=12)
    a = LMBFilter(sc.model, ShortChainGibbs(40, 25, tau_stall=5, tau_stale=10),
                  extraction="map")
    b = LMBFilter(sc.model, ShortChainGibbs(40, 25, tau_stall=5, tau_stale=10),
                  extraction="hysteresis")
    seen = 0
    for k, scan in enumerate(sc.scans):
        a.step(scan.z, rng=k)
        rb = b.step(scan.z, rng=k)
        got = _lmb_hysteresis(a)
        assert a.extraction == "map"
        assert sorted(got) == sorted(map(tuple, rb.labels.tolist()))
        for lab, x in zip(map(tuple, rb.labels.tolist()), rb.states, strict=True):
            assert_allclose(got[lab], x, rtol=0, atol=0)
        seen += len(got)
    assert seen > 0


def test_glmb_study_matches_murtys_hypotheses_to_a_target():
    from rankedassign.experiments.studies.glmb_tracking import _matched_h_upd

    class F:
        comp_w = np.array([0.5, 0.3, 0.1, 0.05, 0.05])

    def kept(h, k):
        s = np.sqrt(F.comp_w)
        return int(np.minimum(k, np.maximum(np.floor(h * s / s.sum() + 0.5), 1)).sum())

    for target in (5, 6, 17, 40, 333):
        for k in (3, 1000):
            h = _matched_h_upd(F, target, k)
            assert kept(h, k) <= target or h == 1
            if kept(h, k) < target and kept(10**6, k) > target:
                assert kept(h + 1, k) > target  # the largest H_upd that fits
    assert _matched_h_upd(F, 3, 1000) == 1  # five components keep one each: more than 3


def test_glmb_study_paired_comparison_is_judged_by_its_95_percent_interval():
    from rankedassign.experiments.studies.glmb_tracking import PairedComparison, _compare

    c = _compare({0: 10.0, 1: 20.0, 2: 30.0}, {0: 10.0, 1: 20.0, 2: 30.0}, "a", "b",
                 target=5.0, two_sided=True)
    assert (c.mean_pct, c.lo_pct, c.hi_pct, c.n, c.status) == (0.0, 0.0, 0.0, 3, "met")
    c = _compare({0: 11.0, 1: 10.0}, {0: 10.0, 1: 10.0}, "a", "b", target=5.0)
    assert c.mean_pct == pytest.approx(5.0)
    # t(0.975, 1) = 12.706: half width 12.706 * 5 / sqrt(2)... of the sd of (10, 0)
    assert c.hi_pct - c.mean_pct == pytest.approx(12.7062 * math.sqrt(50) / math.sqrt(2),
                                                  rel=1e-4)
    assert c.status == "not resolved"
    assert PairedComparison("a", "b", "map", 20.0, 15.0, 25.0, 9, 10.0).status == "not met"
    assert PairedComparison("a", "b", "map", 2.0, -1.0, 4.0, 9, 5.0, True).status == "met"
    assert PairedComparison("a", "b", "map", 2.0, 1.0, 3.0, 9).status == "not resolved"


def test_glmb_study_config_checks_the_tradeoff_values():
    from rankedassign.experiments import get_study
    from rankedassign.experiments.studies.glmb_tracking import GLMBStudyConfig

    with pytest.raises(ValueError, match="tradeoff_h_upd must hold positive ints, got 0"):
        GLMBStudyConfig(tradeoff_h_upd=(100, 0))
    with pytest.raises(ValueError, match="tradeoff_runs must be >= 0, got -1"):
        GLMBStudyConfig(tradeoff_runs=-1)
    with pytest.raises(ValueError, match=re.escape(
            "unknown tradeoff_truncations: truncation 'lmb-long'; expected one of ('original', "
            "'short-chain', 'herded', 'murty')")):
        GLMBStudyConfig(tradeoff_truncations=("lmb-long",))
    quick = GLMBStudyConfig.quick()
    assert quick.tradeoff_truncations == ("original", "short-chain")
    assert {t[3] for t in get_study("glmb_tracking").tasks(quick, 0) if t[5] != 1000} == {
        ("glmb", "original"), ("glmb", "short-chain")}


@pytest.mark.parametrize(("old", "new"), [
    ("lmb-exact", ("lmb", "exact")), ("lmb-long", ("lmb", "original")),
    ("lmb-short", ("lmb", "short-chain")), ("lmb-murty", ("lmb", "murty")),
    ("glmb-exact", ("glmb", "exact")), ("glmb-long", ("glmb", "original")),
    ("glmb-short", ("glmb", "short-chain")), ("glmb-murty", ("glmb", "murty")),
    ("glmb-murty-matched", ("glmb", "murty-matched")), ("glmb-herded", ("glmb", "herded"))])
def test_glmb_study_reads_the_old_method_strings_with_a_deprecation_warning(old, new):
    from rankedassign.experiments.studies.glmb_tracking import GLMBStudyConfig

    want = rf'^filter_truncations: \'{old}\' is deprecated; write \["{new[0]}", "{new[1]}"\]$'
    with pytest.warns(DeprecationWarning, match=want):
        cfg = GLMBStudyConfig(filter_truncations=(old,))
    assert cfg.filter_truncations == (new,)
    # a --config file's two-element lists read as the pairs, silently
    assert GLMBStudyConfig(filter_truncations=[list(new)]).filter_truncations == (new,)


@pytest.mark.parametrize(("old", "new"), [("glmb-long", "original"),
                                          ("glmb-short", "short-chain"),
                                          ("glmb-herded", "herded"), ("glmb-murty", "murty")])
def test_glmb_study_reads_the_old_tradeoff_truncations_with_a_deprecation_warning(old, new):
    from rankedassign.experiments.studies.glmb_tracking import GLMBStudyConfig

    with pytest.warns(DeprecationWarning,
                      match=rf"^tradeoff_truncations: '{old}' is deprecated; write '{new}'$"):
        assert GLMBStudyConfig(tradeoff_truncations=(old,)).tradeoff_truncations == (new,)


def test_glmb_study_refuses_a_method_that_is_not_a_pair_of_the_study():
    from rankedassign.experiments.studies.glmb_tracking import GLMBStudyConfig, check_method

    with pytest.raises(TypeError, match=re.escape(
            "filter_truncations entries must be (filter, truncation) pairs such as ['glmb', "
            "'short-chain'], got 'glmb'")):
        GLMBStudyConfig(filter_truncations=("glmb",))
    with pytest.raises(ValueError, match=re.escape(
            "unknown filter_truncations: filter 'phd'; expected one of ('lmb', 'glmb')")):
        check_method(("phd", "murty"))
    with pytest.raises(ValueError, match=re.escape(
            "unknown filter_truncations: truncation 'lbp'; expected one of ('exact', "
            "'original', 'short-chain', 'murty', 'murty-matched', 'herded')")):
        check_method(("glmb", "lbp"))
    with pytest.raises(ValueError, match=re.escape(
            "filter_truncations: 'murty-matched' matches the δ-GLMB filter's Murty to its short chains; "
            "write ['glmb', 'murty-matched']")):
        check_method(["lmb", "murty-matched"])


def test_glmb_study_old_and_new_spelling_give_the_same_numbers():
    from rankedassign.experiments.studies.glmb_tracking import (
        GLMBStudyConfig,
        glmb_tracking_task,
    )

    cfg = GLMBStudyConfig(n_mc=1, n_scans=3, h_upd=40, h_max=20, n_chains=10, murty_k=20,
                          original_obs=200, retained_mass=("vo",), tradeoff_runs=0)
    with pytest.warns(DeprecationWarning, match=r"^method: 'glmb-short' is deprecated"):
        old = glmb_tracking_task(cfg, 0, 0, "glmb-short", "vo")
    new = glmb_tracking_task(cfg, 0, 0, ("glmb", "short-chain"), "vo")
    assert (old.filter, old.truncation) == ("glmb", "short-chain")
    assert dataclasses.replace(old, seconds=0.0) == dataclasses.replace(new, seconds=0.0)


def test_every_study_has_a_tiny_warm_up_that_runs_one_task_set():
    """The runner compiles each study's kernels just before the study (issue: a first run
    that starts in seconds): every registered study defines ``warm``, its settings keep one
    Monte Carlo run and are no larger than the quick ones, and running them works."""
    from rankedassign.experiments import get_study, study_names, warm_study
    from rankedassign.experiments.registry import study_config

    quick = Config.quick()
    assert len(study_names()) == 14
    for st in map(get_study, study_names()):
        assert st.warm is not None, st.name
        tiny = st.warm(study_config(quick, st))
        assert type(tiny) is type(study_config(quick, st)), st.name
        assert tiny.n_mc == 1, st.name
        assert len(list(st.tasks(tiny, 0))) <= len(list(st.tasks(study_config(quick, st), 0)))
    assert warm_study("table1", quick) >= 0.0


def test_a_study_without_warm_up_warms_in_no_time():
    from rankedassign.experiments import get_study, warm_study

    st = dataclasses.replace(get_study("table1"), warm=None)
    assert warm_study(st) == 0.0


def test_warm_up_on_workers_runs_one_task_per_group_first_then_the_rest():
    """With an executor, the first tiny task of every ``warm_group`` goes out first (the
    workers compile disjoint kernel sets side by side), the others only once those are
    done; every tiny task runs exactly once."""
    from concurrent.futures import ThreadPoolExecutor

    from rankedassign.experiments import get_study, warm_study

    calls = []

    def task(name, group):
        calls.append(name)
        return name

    st = dataclasses.replace(
        get_study("table1"), warm=lambda c: c,
        tasks=lambda c, seed: [("a1", "a"), ("a2", "a"), ("b1", "b"), ("a3", "a"), ("c1", "c")],
        task=task, warm_group=lambda t: t[1])
    with ThreadPoolExecutor(max_workers=1) as ex:  # one thread: the submission order shows
        assert warm_study(st, Table1Config(), executor=ex) >= 0.0
    assert calls == ["a1", "b1", "c1", "a2", "a3"]
    calls.clear()
    assert warm_study(st, Table1Config()) >= 0.0  # in this process: the tasks in order
    assert calls == ["a1", "a2", "b1", "a3", "c1"]


def test_warm_up_on_workers_runs_the_warm_units_before_the_tiny_tasks():
    from concurrent.futures import ThreadPoolExecutor

    from rankedassign.experiments import get_study, warm_study

    calls = []

    def unit(name):
        time.sleep(0.1)  # a task beside it would finish first
        calls.append(name)

    def task(name, group):
        calls.append(name)

    st = dataclasses.replace(
        get_study("table1"), warm=lambda c: c,
        tasks=lambda c, seed: [("a1", "a"), ("a2", "a"), ("b1", "b")], task=task,
        warm_group=lambda t: t[1], warm_units=lambda c: [(unit, "u1"), (unit, "u2")])
    with ThreadPoolExecutor(max_workers=1) as ex:
        assert warm_study(st, Table1Config(), executor=ex) >= 0.0
    # the tiny tasks wait for every unit (they load what the units compiled), then go out in
    # their order
    assert calls == ["u1", "u2", "a1", "a2", "b1"]
    calls.clear()
    with ThreadPoolExecutor(max_workers=3) as ex:  # side by side: still no task before a unit
        assert warm_study(st, Table1Config(), executor=ex) >= 0.0
    assert sorted(calls[:2]) == ["u1", "u2"] and sorted(calls[2:]) == ["a1", "a2", "b1"]
    calls.clear()
    assert warm_study(st, Table1Config()) >= 0.0  # in this process: only the tasks
    assert calls == ["a1", "a2", "b1"]


def test_the_tempering_study_warms_each_sampler_of_each_kind_in_a_unit_of_its_own():
    from rankedassign.experiments import get_study
    from rankedassign.experiments.registry import study_config
    from rankedassign.experiments.studies.tempering_herding import _warm_unit, kind_name

    quick = Config.quick()
    st = get_study("tempering_herding")
    tiny = st.warm(study_config(quick, st))
    units = st.warm_units(tiny)
    synthetic = [u for u in units if u[0] is _warm_unit]
    # every method on every kind exactly once; the multi-sensor herded driver (the longest
    # compile) first
    seen = [(f, m) for u in synthetic for f in u[2] for m in u[3]]
    assert len(seen) == len(set(seen))
    assert {f for f, _ in seen} == set(tiny.families)
    assert {m for _, m in seen} == set(tiny.truncations)
    assert all(len({kind_name(f) for f in u[2]}) == 1 for u in synthetic)  # one kind a unit
    assert synthetic[0][2][0].startswith("ms:") and synthetic[0][3][0][0] == "herded"
    assert sum(u[4] for u in synthetic) == 3  # one grading unit per kind
    tracking = [u[1:] for u in units if u[0] is not _warm_unit]
    assert {u[5] for u in tracking} == set(tiny.tracking_truncations) == {
        t[5] for t in st.tasks(tiny, 0) if t[0] == "tracking"}
    _warm_unit(tiny, ("diagonal",), (("original", ""), ("lbp", "")), True)  # runs (cached)


def test_warm_groups_of_the_studies_that_compile_by_kind_and_by_method():
    from rankedassign.experiments import get_study
    from rankedassign.experiments.registry import study_config

    quick = Config.quick()
    st = get_study("tempering_herding")
    groups = [st.warm_group(t) for t in st.tasks(st.warm(study_config(quick, st)), 0)]
    assert {"single", "multisensor", "adaptive_birth"} <= set(groups)
    assert ("tracking", ("herded", "keys=shared")) in groups
    st = get_study("glmb_tracking")
    tasks = st.tasks(st.warm(study_config(quick, st)), 0)
    groups = {st.warm_group(t) for t in tasks}
    # one group per method run (the same method on both presets compiles the same kernels),
    # one for every Murty truncation (each compiles Murty's search) and one per preset for the
    # δ-GLMB filter's chains (the same loop over the components; direct draws on "vo", prefix
    # sums on "paper")
    methods = set(study_config(quick, st).filter_truncations)
    chains = {("glmb-chains", "vo"), ("glmb-chains", "paper")}
    assert {"murty"} | chains <= groups
    assert groups - {"murty"} - chains <= methods and len(groups) >= 6
    assert {st.warm_group(t) for t in tasks if t[3][1].startswith("murty")} == {"murty"}
    for preset in ("vo", "paper"):
        assert {st.warm_group(t) for t in tasks if t[4] == preset and t[3] in (
            ("glmb", "original"), ("glmb", "short-chain"))} == {("glmb-chains", preset)}
    assert len(tasks) > len(groups)


#: Studies whose per-run results are records, with their tiny settings (a run in seconds).
RECORD_STUDIES = {
    "table1": lambda c: dataclasses.replace(c, n_mc=2, original_obs=200, n_chains=8),
    "random_readings": lambda c: dataclasses.replace(c, n_mc=2, original_obs=200, n_chains=8),
    "ablation": lambda c: dataclasses.replace(c, n_mc=2, original_obs=200, n_chains=8,
                                              families=("uniform", "random")),
    "optimum": lambda c: dataclasses.replace(c, n_mc=2, original_obs=200, n_chains=8),
    "sweep": lambda c: dataclasses.replace(c, n_mc=2, obs_grid=(10, 100),
                                           chain_lengths=(5,)),
    "tracking": lambda c: dataclasses.replace(c, n_mc=2, n_scans=3, original_obs=50,
                                              n_chains=4),
    "tracking_var": lambda c: dataclasses.replace(c, n_mc=1, n_scans=3, original_obs=50,
                                                  n_chains=4),
    "multisensor": lambda c: dataclasses.replace(c, n_mc=2, cases=("A/diagonal", "B/random"),
                                                 original_obs=100, n_chains=4),
    # the δ-GLMB exact truncation stops at the first scan of "paper" (a failed record)
    "glmb_tracking": lambda c: dataclasses.replace(
        c, n_mc=1, n_scans=3, murty_runs=1, h_upd=40, h_max=20, n_chains=10, murty_k=20,
        original_obs=200, glmb_exact_runs=1, tradeoff_runs=0, presets=("paper",),
        filter_truncations=(("lmb", "short-chain"), ("glmb", "short-chain"),
                            ("glmb", "exact"))),
}


@pytest.mark.parametrize("name", list(RECORD_STUDIES))
def test_the_run_records_round_trip_through_json_and_pickle(name, tmp_path):
    # the runs as <study>_runs.json holds them, read back into records by the study's
    # run_from_dict: the same JSON again, and the same summary from the records read back
    import json
    import pickle

    from rankedassign.experiments import get_study
    from rankedassign.experiments._records import RunRecord
    from rankedassign.experiments.report import write_json

    st = get_study(name)
    cfg = RECORD_STUDIES[name](st.quick())
    summary, runs = run_study(st, cfg, seed=2, progress=False, return_runs=True)
    assert all(isinstance(r, RunRecord) and dataclasses.is_dataclass(r) for r in runs)
    write_json(tmp_path / "runs.json", runs)
    back = [st.run_from_dict(d) for d in json.loads((tmp_path / "runs.json").read_text())]
    assert back == runs
    if name == "glmb_tracking":
        assert [r.failed.scan for r in back if r.failed] == [1]
    write_json(tmp_path / "again.json", back)
    assert (tmp_path / "again.json").read_text() == (tmp_path / "runs.json").read_text()
    assert st.summarise(back, cfg) == summary
    assert pickle.loads(pickle.dumps(runs)) == runs  # the workers send them back pickled


def test_a_saved_run_with_an_unknown_field_is_refused_by_name():
    from rankedassign.experiments.studies.table1 import Table1Run

    with pytest.raises(ValueError, match=r"^Table1Run.from_dict: unknown field\(s\) \['runs'\]$"):
        Table1Run.from_dict({"run": 0, "runs": 1})
    with pytest.raises(ValueError, match=r"^SamplerRun.from_dict needs a mapping of its "
                                         r"fields, got list$"):
        Table1Run.from_dict({"original": []})


def test_a_table1_run_names_its_criteria():
    from rankedassign.experiments.studies.table1 import Table1Run

    rec = Table1Run.from_dict(
        {"run": 0, "family": "uniform", **{k: {
            "n_obs": i, "n_row_updates": 0, "n_unique": 1, "n_chains": 1,
            "stop_reason": "budget", "error": 0.5} for i, k in enumerate(
                ("original", "stall", "stale", "full"))}})
    assert [rec.criterion(c).n_obs for c in CRITERIA] == [1, 2, 3]
    with pytest.raises(ValueError, match=r"^unknown criterion 'original'; expected one of "):
        rec.criterion("original")


def test_every_study_reads_its_saved_runs_back():
    # every study's task returns a record that Study.run_from_dict builds again
    from rankedassign.experiments import get_study, study_names

    assert [n for n in study_names() if get_study(n).run_from_dict is None] == []

"""The multisensor and adaptive_birth studies of the reproduction (tiny configurations)."""

import dataclasses
import math

import numpy as np
import pytest

import oracle
from rankedassign import sample_short_chains
from rankedassign.cli import main
from rankedassign.experiments import (
    Config,
    ReproduceError,
    config_from_dict,
    get_study,
    run_study,
    study_names,
)
from rankedassign.experiments.studies import adaptive_birth as S
from rankedassign.experiments.studies import multisensor as MS
from rankedassign.multisensor import synthetic

TINY_MS = MS.MultiSensorConfig(n_mc=2, cases=("A/diagonal", "B/random"),
                               methods=("exact", "mm", "componentwise"),
                               original_obs=200, n_chains=8, chain_length=25,
                               tau_stall=5, tau_stale=25)
TINY_AB = S.AdaptiveBirthStudyConfig(n_mc=2, sensors=(2,), original_obs=60, n_chains=6, chain_length=10,
                        tau_stall=3, tau_stale=2, curve_obs=(20, 60))


@pytest.fixture(scope="module")
def ms_result():
    return run_study("multisensor", TINY_MS, seed=5, progress=False, return_runs=True)


@pytest.fixture(scope="module")
def ab_result():
    return run_study("adaptive_birth", TINY_AB, seed=3, progress=False, return_runs=True)


def test_registry_presence_and_order():
    names = study_names()
    assert names[-4:-1] == ("multisensor", "adaptive_birth", "multisensor_tracking")
    assert get_study("multisensor").paper == "" and get_study("adaptive_birth").paper == ""
    assert Config.quick().multisensor == MS.MultiSensorConfig(n_mc=MS.QUICK_MC)
    assert Config.full().multisensor == MS.MultiSensorConfig()
    assert Config.quick().adaptive_birth == S.QUICK and Config.full().adaptive_birth == S.FULL
    # the full study mirrors Table I's budget rule: original chain = N_S N_C sweeps
    full = MS.MultiSensorConfig()
    assert full.original_obs == full.n_chains * full.chain_length
    assert (full.chain_length, full.tau_stall, full.tau_stale) == (25, 5, 25)  # spec §5


def test_cli_lists_the_studies(capsys):
    assert main(["reproduce", "--help"]) == 0
    out = capsys.readouterr().out
    assert "multisensor" in out and "adaptive_birth" in out


def test_multisensor_task_records(ms_result):
    _, runs = ms_result
    assert len(runs) == TINY_MS.n_mc * len(TINY_MS.cases)
    for out in runs:
        assert set(out.methods) == set(TINY_MS.methods)
        for recs in out.methods.values():
            assert recs.original.n_obs == TINY_MS.original_obs
            for crit in ("stall", "stale", "full"):
                assert 0 < getattr(recs, crit).n_obs <= TINY_MS.n_chains * TINY_MS.chain_length
            for rec in (recs.original, recs.stall, recs.stale, recs.full):
                assert 0.0 <= rec.error <= 1.0 and rec.seconds >= 0.0
    # same seed, same records (up to the wall times)
    again = MS.multisensor_task(TINY_MS, 5, 1, "B/random")

    def strip(out):
        return {m: {k: {f: v for f, v in r.items() if f != "seconds"}
                    for k, r in recs.to_dict().items()}
                for m, recs in out.methods.items()}

    ref = next(r for r in runs if r.case == "B/random" and r.run == 1)
    assert strip(again) == strip(ref)


def test_componentwise_error_is_the_uncovered_mass():
    # For the exact sampler, 1 - sum exp(-cost)/Z is the truncation error; the component-wise
    # error uses the same formula on its collapsed costs.
    p = synthetic.random(2, (3, 3), rng=4)
    res = sample_short_chains(p, 20, 10, rng=1, method="exact")
    rec = MS._record(p, res, 0.0, oracle.log_normalizer(p), "componentwise")
    assert rec.error == pytest.approx(oracle.truncation_error(p, res.assignments), abs=1e-12)


def test_multisensor_summary_definitions(ms_result):
    summary, runs = ms_result
    assert [(r.case, r.method, r.criterion) for r in summary.rows] == [
        (c, m, k) for c in TINY_MS.cases for m in TINY_MS.methods
        for k in ("stall", "stale", "full")]
    for row in summary.rows:
        rs = [r.methods[row.method] for r in runs if r.case == row.case]
        no = np.mean([r.original.n_obs for r in rs])
        ns = np.mean([getattr(r, row.criterion).n_obs for r in rs])
        eo = np.mean([r.original.error for r in rs])
        es = np.mean([getattr(r, row.criterion).error for r in rs])
        assert row.delta_obs_pct == pytest.approx(100 * (no - ns) / no)
        assert row.delta_error_pp == pytest.approx(100 * abs(eo - es))
        assert row.n_mc == 2 and row.delta_error_pp_se is not None
    acc = {(a.case, a.method): a for a in summary.accuracy}
    assert set(acc) == {(c, m) for c in TINY_MS.cases for m in TINY_MS.methods}
    for a in acc.values():
        if a.method == "exact":
            assert a.vs_exact_pp == 0.0
        assert a.n_obs == TINY_MS.original_obs and a.seconds_mean >= 0
    assert summary.verdict.startswith("With both rules")


def test_multisensor_render_plot_csv(ms_result, tmp_path):
    summary, _ = ms_result
    st = get_study("multisensor")
    text = st.render(summary, TINY_MS)
    assert text.startswith("## Multi-sensor Table I")
    assert "no multi-sensor numbers" in text and "**Verdict.**" in text
    assert "| A/diagonal | exact | stall |" in text and "(multisensor.png)" in text
    assert st.plot(summary, tmp_path) == ["multisensor.png"]
    assert (tmp_path / "multisensor.png").read_bytes()[:4] == b"\x89PNG"
    rows = st.csv_rows(summary)
    assert len(rows) == len(summary.rows) and {"case", "method", "delta_obs_pct"} <= set(rows[0])


def test_multisensor_verdict_branches(ms_result):
    summary, _ = ms_result
    row = summary.rows[2]
    worse = dataclasses.replace(row, criterion="full", delta_error_signed_pp=5.0,
                                delta_error_pp_se=0.1)
    same = dataclasses.replace(row, criterion="full", delta_error_signed_pp=0.2,
                               delta_error_pp_se=0.1)
    assert "holds for every multi-sensor sampler" in MS.verdict([same])
    assert "holds in 1 of the 2 pairs; the short chains lose accuracy in: " in MS.verdict(
        [same, worse])


@pytest.mark.parametrize(("kwargs", "exc", "match"), [
    ({"n_mc": 0}, ValueError, "n_mc"),
    ({"n_chains": 2.5}, TypeError, "n_chains"),
    ({"methods": ("gibbs",)}, ValueError, "unknown methods: method 'gibbs'"),
    ({"methods": ()}, ValueError, r"methods must be a non-empty tuple, got \(\)"),
    ({"cases": ["A/random"]}, ValueError, r"cases must be a non-empty tuple, got \['A/random'\]"),
    ({"cases": ("D/random",)}, ValueError, "unknown cases: size 'D'"),
    ({"cases": ("A/flat",)}, ValueError, "unknown cases: family 'flat'"),
    ({"cases": (3,)}, TypeError, "cases: a case must be a str such as 'A/random', got 3"),
])
def test_multisensor_bad_settings(kwargs, exc, match):
    with pytest.raises(exc, match=match):
        MS.MultiSensorConfig(**kwargs)


def test_multisensor_config_from_dict():
    cfg = config_from_dict(Config.quick(), {"multisensor": {"cases": ["C/uniform"], "n_mc": 3}})
    assert cfg.multisensor.cases == ("C/uniform",) and cfg.multisensor.n_mc == 3
    with pytest.raises(ReproduceError, match="config for 'multisensor': unknown cases: size"):
        config_from_dict(Config.quick(), {"multisensor": {"cases": ["Z/uniform"]}})


def test_adaptive_birth_wraps_the_study_functions(ab_result):
    summary, runs = ab_result
    table = [r for r in runs if r.kind == "run"]
    assert table == [S.run_task(TINY_AB, 3, r, f, 2) for f in S.FAMILIES
                     for r in range(TINY_AB.n_mc)]
    raw = S.summarise(table)
    assert [dataclasses.asdict(r) for r in summary.rows] == raw
    assert summary.curves == {f"{f}, V=2": S.curve(TINY_AB, 3, f, 2) for f in S.FAMILIES}
    assert summary.verdict == S.verdict(raw)


def test_adaptive_birth_render_plot_csv(ab_result, tmp_path):
    summary, _ = ab_result
    st = get_study("adaptive_birth")
    text = st.render(summary, TINY_AB)
    assert text.startswith("## Adaptive birth")
    assert S.format_table([dataclasses.asdict(r) for r in summary.rows]) in text
    assert "| random, V=2 |" in text and "(adaptive_birth.png)" in text
    assert st.plot(summary, tmp_path) == ["adaptive_birth.png"]
    assert (tmp_path / "adaptive_birth.png").read_bytes()[:4] == b"\x89PNG"
    assert len(st.csv_rows(summary)) == 9


def test_adaptive_birth_single_run_has_no_standard_error():
    cfg = dataclasses.replace(TINY_AB, n_mc=1, families=("uniform",), curve_obs=(20,))
    summary = run_study("adaptive_birth", cfg, seed=0, progress=False)
    assert all(r.delta_error_se_pp is None for r in summary.rows)
    assert not any(math.isnan(v) for r in summary.rows for v in dataclasses.asdict(r).values()
                   if isinstance(v, float))

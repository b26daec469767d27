"""The ``tempering_herding`` study: every method graded by the oracle on the same problems."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from numpy.testing import assert_allclose

import oracle
from rankedassign import lbp_marginals, sample_original, sample_tempered
from rankedassign.experiments import Config, child_seed, get_study, run_seed, run_study
from rankedassign.experiments.studies import tempering_herding as TH
from rankedassign.experiments.studies.tempering_herding import TH_METHODS, TemperingHerdingConfig

TINY = TemperingHerdingConfig(
    n_mc=2, families=("uniform", "random", "ms:A/random_coupled", "birth:diagonal"),
    budgets=(20, 200), tracking_mc=1, presets=("vo",), n_scans=4, tracking_obs=50,
    tracking_chains=4)


@pytest.fixture(scope="module")
def result():
    return run_study("tempering_herding", TINY, seed=5, progress=False, return_runs=True)


def test_registered_with_quick_and_full_settings():
    st = get_study("tempering_herding")
    assert st.paper == "" and st.config_type is TemperingHerdingConfig
    full, quick = Config.full().tempering_herding, Config.quick().tempering_herding
    assert full.budgets == (100, 1_000, 10_000, 250_000) and full.n_mc == 20
    assert quick.budgets == (100, 1_000, 10_000) and quick.n_mc == 3 and quick.tracking_mc == 1
    # the per-call settings are the full study's
    for name in ("chain_length", "tau_stall", "tau_stale", "zr_beta", "n_scans",
                 "tracking_obs", "tracking_chains", "truncations", "families", "presets"):
        assert getattr(quick, name) == getattr(full, name), name


def test_every_applicable_method_at_every_budget(result):
    s, runs = result
    assert len(runs) == TINY.n_mc * len(TINY.families) + len(TINY.tracking_truncations)
    for fam in TINY.families:
        problem = TH.make_problem(fam, run_seed(5, 0), TINY)
        for m in TH_METHODS:
            rows = [r for r in s.rows if r.family == fam and r.cell == m]
            if not TH.applies(m, problem):
                assert rows == [], (fam, m)
                continue
            budgets = [0] if m == TH.LBP else list(TINY.budgets)
            assert [r.budget for r in rows] == budgets, (fam, m)
            for r in rows:
                assert r.n_runs == TINY.n_mc and r.seconds_mean > 0
                if m == TH.LBP:
                    assert r.error_pct_mean is None and 0 <= r.l1_mean < 0.05
                    continue
                assert 0 <= r.error_pct_mean <= 100 and r.unique_mean >= 1
                assert (r.l1_mean is None) == (TH.kind_name(fam) == "adaptive_birth")
                if r.l1_mean is not None:
                    assert 0 <= r.l1_mean <= 2
                if m in (("original", ""), ("herded", "keys=shared"), ("herded", "keys=full"),
                         ("tempered", "beta=0.5"), ("tempered", "beta=0.7"),
                         ("tempered", "beta=0.9")):
                    assert r.obs_mean == r.budget  # one chain runs the budget
                if "short" in m[0] + m[1]:
                    assert r.obs_mean <= r.budget  # the rules may stop short chains early
    # Zanella-Roberts runs on every kind, LBP on single-sensor problems only
    for fam in TINY.families:
        assert TH.applies(TH.ZANELLA_ROBERTS, TH.make_problem(fam, run_seed(5, 0), TINY)), fam
    assert not TH.applies(TH.LBP, TH.make_problem("ms:A/random_coupled", run_seed(5, 0), TINY))
    assert not TH.applies(TH.LBP, TH.make_problem("birth:diagonal", run_seed(5, 0), TINY))
    for fam in ("ms:A/random_coupled", "birth:diagonal"):
        rows = [r for r in s.rows if r.family == fam and r.cell == TH.ZANELLA_ROBERTS]
        assert [r.budget for r in rows] == list(TINY.budgets) and all(
            r.obs_mean == r.budget for r in rows), fam


def test_records_are_the_oracle_s_numbers_on_the_same_data(result):
    """One cell recomputed from the public functions: the same problem, stream and grade."""
    _, runs = result
    rec = next(r for r in runs if r.part == "synthetic" and r.family == "random"
               and r.run == 1)
    s = run_seed(5, 1)
    problem = TH.make_problem("random", s, TINY)
    rng = child_seed(s, TH.KEY_METHOD, TH.TH_FAMILIES.index("random"),
                     TH_METHODS.index(("original", "")), 200)
    res = sample_original(problem, 200, rng=rng)
    cell = rec.calls(("original", ""))["200"]
    assert cell.n_unique == len(res.costs)
    assert cell.error == oracle.truncation_error(problem, res.assignments)
    exact = oracle.marginals(problem)
    lb = lbp_marginals(problem)
    assert_allclose(rec.calls(("lbp", ""))["0"].l1,
                    np.abs(lb.marginals - exact).sum() / problem.n_rows, rtol=1e-12)
    assert rec.calls(("tempered", "scheme=zanella-roberts"))["200"].n_obs == 200
    # the single-sensor matrices are the Table I studies' of the same run
    from rankedassign.experiments._synthetic import make_problem

    assert np.array_equal(make_problem("random", s, TINY).cost, problem.cost)


def test_zanella_roberts_cells_of_the_other_kinds(result):
    """A multi-sensor Zanella-Roberts cell recomputed: budget x P moves on the exact posterior,
    graded by its importance-weighted marginals; the adaptive-birth one has no marginals."""
    _, runs = result
    s = run_seed(5, 0)
    fam = "ms:A/random_coupled"
    rec = next(r for r in runs if r.part == "synthetic" and r.family == fam
               and r.run == 0)
    problem = TH.make_problem(fam, s, TINY)
    rng = child_seed(s, TH.KEY_METHOD, TH.TH_FAMILIES.index(fam),
                     TH_METHODS.index(("tempered", "scheme=zanella-roberts")), 200)
    res = sample_tempered(problem, 200 * problem.n_rows, beta=TINY.zr_beta, rng=rng)
    exact = oracle.marginals(problem)
    cell = rec.calls(("tempered", "scheme=zanella-roberts"))["200"]
    assert cell.n_unique == len(res.costs) and cell.n_obs == 200
    l1 = (np.abs(res.marginals.dead - exact.dead).sum()
          + np.abs(res.marginals.tuples - exact.tuples).sum()) / problem.n_rows
    assert_allclose(cell.l1, l1, rtol=1e-12)
    birth = next(r for r in runs if r.part == "synthetic" and r.family == "birth:diagonal")
    assert all(c.l1 is None and c.n_unique >= 1
               for c in birth.calls(("tempered", "scheme=zanella-roberts")).values())


def test_the_same_seed_gives_the_same_numbers(result):
    s, _ = result
    again = run_study("tempering_herding", dataclasses.replace(
        TINY, families=("random",), tracking_mc=0), seed=5, progress=False)

    def strip(rows):
        # wall times are the machine's, not results
        return [dataclasses.replace(r, seconds_mean=0.0, seconds_min=0.0) for r in rows]

    assert strip(again.rows) == strip([r for r in s.rows if r.family == "random"])


def test_verdicts_name_the_best_measured_method(result):
    s, _ = result
    for fam, v in s.verdicts.items():
        rows = [r for r in s.rows if r.family == fam]
        for b, m in v["obs"].items():
            at = {r.cell: r.error_pct_mean for r in rows if r.budget == b}
            assert at[m] == min(at.values())
        assert set(v["time"]) <= set(TINY.budgets)
        for m in v["time"].values():
            assert m is None or m in {r.cell for r in rows}
    for counts in s.herded_vs_gibbs.values():
        for k, n in counts.values():
            assert 0 <= k <= n == TINY.n_mc


def test_equal_time_reads_each_curve_without_extrapolating():
    rows = [TH.THRow("f", "single", "m", "", b, 1, b, e, None, 1, t, None, None)
            for b, e, t in ((10, 50.0, 0.001), (100, 10.0, 0.01))]
    assert TH._at_time(rows, 0.001) == 50.0
    assert math.isclose(TH._at_time(rows, math.sqrt(1e-5)), 30.0)  # halfway in log time
    assert TH._at_time(rows, 0.0005) is None  # it cannot answer that soon
    assert TH._at_time(rows, 0.02) == 10.0  # it finished sooner: its slowest call's error


def test_tracking_part_runs_every_association_on_the_same_measurements(result):
    s, runs = result
    got = {r.cell: r for r in s.tracking}
    assert list(got) == list(TINY.tracking_truncations)
    for m, r in got.items():
        assert r.preset == "vo" and r.n_runs == 1 and 0 <= r.ospa2_mean <= TINY.ospa_c
        assert (r.sweeps_mean == 0) == (m in (("exact", ""), ("lbp", "")))
    from rankedassign.tracking import Exact, run_scenario

    rec = next(r for r in runs if r.part == "tracking" and r.truncation == "exact")
    sr = run_scenario("vo", Exact(), rng=run_seed(5, 0), n_scans=TINY.n_scans)
    from rankedassign.metrics import ospa2

    want = ospa2(sr.truth, sr.estimates, TINY.ospa_c, TINY.ospa_p, TINY.ospa_window).value
    assert_allclose(rec.ospa2, np.mean(want), rtol=1e-12)
    # GOSPA beside it, per scan with the same c and p, averaged over the scans
    from rankedassign.metrics import gospa

    g = [gospa(x[~np.isnan(x).any(axis=1)], y[~np.isnan(y).any(axis=1)], TINY.ospa_c,
               TINY.ospa_p).value for x, y in zip(sr.truth, sr.estimates, strict=True)]
    assert_allclose(rec.gospa, np.mean(g), rtol=1e-12)
    exact = got[("exact", "")]
    assert exact.gospa_mean == rec.gospa and exact.gospa_se is None
    assert "GOSPA (m)" in TH.render_tempering_herding(s, TINY)


def test_report_plots_and_csv(result, tmp_path):
    s, _ = result
    text = TH.render_tempering_herding(s, TINY)
    assert TH.FUTURE_WORK in text and "The paper has no numbers here" in text
    for title in ("### uniform family", "### random family",
                  "### multi-sensor case A/random_coupled",
                  "### adaptive birth, diagonal family (4 sensors)", "### Tracking"):
        assert title in text
    assert "at equal observations" in text and "at equal time" in text
    assert TH.plot_tempering_herding(s, tmp_path) == [
        "tempering_herding_obs.png", "tempering_herding_time.png",
        "tempering_herding_marginals.png"]
    for name in ("tempering_herding_obs.png", "tempering_herding_time.png"):
        assert (tmp_path / name).read_bytes()[:4] == b"\x89PNG"
    rows = get_study("tempering_herding").csv_rows(s)
    assert {r["part"] for r in rows} == {"synthetic", "tracking"}


@pytest.mark.parametrize("bad, message", [
    ({"truncations": ("tempered",)}, "unknown truncations: truncation 'tempered'; expected one of"),
    ({"families": ("ms:D/random",)}, "unknown families: family 'ms:D/random'"),
    ({"budgets": (100, 100)}, "budgets must be a non-empty, strictly increasing tuple"),
    ({"budgets": ()}, "budgets must be a non-empty, strictly increasing tuple"),
    ({"zr_beta": 1.5}, "zr_beta must be <= 1.0, got 1.5"),
    ({"zr_beta": 0.0}, "zr_beta must be > 0.0, got 0.0"),
    ({"ms_method": "componentwise"}, "unknown ms_method 'componentwise'"),
    ({"tracking_mc": -1}, "tracking_mc must be a non-negative integer, got -1"),
    ({"n_mc": 0}, "n_mc must be a positive integer, got 0"),
    ({"presets": ("multi",)}, "unknown presets: preset 'multi'"),
])
def test_bad_settings_are_refused_by_name(bad, message):
    with pytest.raises(ValueError, match=message.replace("(", r"\(")):
        TemperingHerdingConfig(**bad)


@pytest.mark.parametrize(("setting", "old", "new"), [("truncations", "gibbs", "original"),
                                                     ("truncations", "short", "short-chain"),
                                                     ("tracking_truncations", "gibbs", "original"),
                                                     ("tracking_truncations", "short",
                                                      "short-chain")])
def test_the_old_spellings_of_the_samplers_still_read_with_a_deprecation_warning(setting, old,
                                                                                 new):
    with pytest.warns(DeprecationWarning, match=rf"^{setting}: '{old}' is deprecated; write "
                                                rf"'{new}'"):
        cfg = TemperingHerdingConfig(**{setting: (old, "lbp")})
    assert getattr(cfg, setting) == ((new, ""), ("lbp", ""))


#: Every old method string of the study and the (truncation, variant) pair it reads as.
OLD_METHODS = {
    "truncations": {"herded-shared": ("herded", "keys=shared"),
                "herded-full": ("herded", "keys=full"),
                "herded-short-shared": ("herded", "chains=short,keys=shared"),
                "herded-short-full": ("herded", "chains=short,keys=full"),
                "beta-0.5": ("tempered", "beta=0.5"), "beta-0.7": ("tempered", "beta=0.7"),
                "beta-0.9": ("tempered", "beta=0.9"),
                "zanella-roberts": ("tempered", "scheme=zanella-roberts")},
    "tracking_truncations": {"herded": ("herded", "keys=shared"),
                         "herded-short": ("herded", "chains=short,keys=shared")}}


@pytest.mark.parametrize(("setting", "old", "new"), [
    (setting, old, new) for setting, table in OLD_METHODS.items()
    for old, new in table.items()])
def test_the_old_method_strings_read_as_their_pairs_with_a_warning_naming_them(setting, old,
                                                                               new):
    shown = f'["{new[0]}", "{new[1]}"]'
    with pytest.warns(DeprecationWarning, match=rf"^{setting}: '{old}' is deprecated; write "
                                                rf"{shown.replace('[', chr(92) + '[')}$"):
        cfg = TemperingHerdingConfig(**{setting: (old,)})
    assert getattr(cfg, setting) == (new,)
    # the pairs are the study's methods, in the old strings' order (their streams are keyed
    # by the place in TH_METHODS, so the numbers are those of the old spelling)
    assert new in (TH_METHODS if setting == "truncations" else TH.TH_TRACKING_METHODS)


def test_the_defaults_are_the_old_methods_in_their_order():
    old = ("original", "short-chain", "herded-shared", "herded-full", "herded-short-shared",
           "herded-short-full", "beta-0.5", "beta-0.7", "beta-0.9", "zanella-roberts", "lbp")
    with pytest.warns(DeprecationWarning):
        cfg = TemperingHerdingConfig(truncations=old, tracking_truncations=(
            "exact", "original", "short-chain", "herded", "herded-short", "lbp"))
    assert cfg == TemperingHerdingConfig()
    # a --config file: pairs as two-element lists, a plain truncation by its name alone
    from rankedassign.experiments import config_from_dict

    got = config_from_dict(Config.quick(), {"tempering_herding": {
        "truncations": [["herded", "keys=full"], "lbp"], "tracking_truncations": [["exact", ""]]}})
    assert got.tempering_herding.truncations == (("herded", "keys=full"), ("lbp", ""))
    assert got.tempering_herding.tracking_truncations == (("exact", ""),)


@pytest.mark.parametrize("bad", [("herded", "keys=other"), ("herded",), ("tempered", ""),
                                 ("exact", "")])
def test_a_pair_outside_the_study_is_refused_listing_the_pairs(bad):
    with pytest.raises(ValueError, match=r"^unknown truncations: truncation .*; expected one of "
                                         r'\["original", ""\], \["short-chain", ""\]'):
        TemperingHerdingConfig(truncations=(bad,))


def test_the_run_records_round_trip_through_json_and_pickle(result, tmp_path):
    # the runs as <study>_runs.json holds them, read back into records: the same JSON again,
    # and the same summary (the report's numbers) from the records read back
    import json
    import pickle

    from rankedassign.experiments.report import write_json

    s, runs = result
    assert {type(r) for r in runs} == {TH.THSyntheticRun, TH.THTrackingRun}
    write_json(tmp_path / "runs.json", runs)
    data = json.loads((tmp_path / "runs.json").read_text())
    back = [TH.run_from_dict(d) for d in data]
    write_json(tmp_path / "again.json", back)
    assert (tmp_path / "again.json").read_text() == (tmp_path / "runs.json").read_text()
    assert back[0].to_dict() == runs[0].to_dict()
    assert TH.summarise_tempering_herding(back, TINY) == s
    assert pickle.loads(pickle.dumps(runs)) == runs  # the workers send them back pickled


@pytest.mark.parametrize("data, message", [
    ({"part": "other"}, "a tempering_herding run has part 'synthetic' or 'tracking', got "
                        "'other'"),
    ([1], "a tempering_herding run has part 'synthetic' or 'tracking', got None"),
    ({"part": "tracking", "runs": 1}, r"THTrackingRun.from_dict: unknown field\(s\) \['runs'\]"),
])
def test_a_bad_saved_run_is_refused_by_name(data, message):
    with pytest.raises(ValueError, match=message):
        TH.run_from_dict(data)

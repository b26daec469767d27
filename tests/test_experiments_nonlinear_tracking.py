"""The ``nonlinear_tracking`` study: the truncations on Vo's non-linear examples, EKF vs UKF."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest

from rankedassign.experiments import Config, ReproduceError, config_from_dict, get_study
from rankedassign.experiments._stats import paired_interval
from rankedassign.experiments.studies.nonlinear_tracking import (
    NonlinearConfig,
    nonlinear_task,
    render_nonlinear,
    summarise_nonlinear,
)

TINY = NonlinearConfig(n_mc=2, n_scans=4, lmb_budget=20, glmb_budget=20, chain_length=5)


@pytest.fixture(scope="module")
def runs():
    return [nonlinear_task(TINY, 0, r, p, f) for p in TINY.presets for f in TINY.filters
            for r in range(TINY.n_mc)]


def test_every_row_sees_the_same_measurements_and_records_every_scan(runs):
    for task in runs:
        assert [r.truncation for r in task] == ["original", "short-chain", "murty"]
        for r in task:
            for key in ("ospa", "ospa2", "cardinality_error", "sweeps", "seconds",
                        "single_object_seconds", "retained_mass"):
                assert len(getattr(r, key)) == TINY.n_scans, key
            assert all(0.0 <= v <= TINY.ospa_c for v in r.ospa)
            masses = [m for m in r.retained_mass if m is not None]
            if r.filter == "glmb":
                assert len(masses) == TINY.n_scans and all(0.0 < m <= 1.0 + 1e-12 for m in masses)
            else:
                assert masses == []
        assert task[2].sweeps == [0] * TINY.n_scans  # Murty draws no sweeps
    # EKF and UKF runs of one seed are the same measurements: the exact truncation's first
    # scans (no track yet) give the same OSPA
    ekf = [t for t in runs if t[0].preset == "vo-ekf" and t[0].filter == "lmb"][0]
    ukf = [t for t in runs if t[0].preset == "vo-ukf" and t[0].filter == "lmb"][0]
    assert ekf[0].ospa[0] == ukf[0].ospa[0]


def test_the_same_seed_gives_the_same_records():
    a = nonlinear_task(TINY, 3, 1, "vo-ukf", "glmb")
    b = nonlinear_task(TINY, 3, 1, "vo-ukf", "glmb")
    for ra, rb in zip(a, b, strict=True):
        assert ra.ospa2 == rb.ospa2 and ra.sweeps == rb.sweeps
        assert ra.retained_mass == rb.retained_mass


def test_summary_rows_comparisons_and_report(runs):
    s = summarise_nonlinear(runs, TINY)
    assert len(s.rows) == 2 * 2 * 3
    assert {r.n_runs for r in s.rows} == {2}
    assert [c.what for c in s.comparisons].count("short vs long") == 4
    assert [c.what for c in s.comparisons].count("UKF vs EKF") == 6
    for c in s.comparisons:
        assert c.n_runs == 2 and c.ci_low <= c.delta_ospa2 <= c.ci_high
    text = render_nonlinear(s, TINY)
    assert "**Do the savings carry over?**" in text and "**EKF or UKF?**" in text
    assert text.count("**Verdict.**") == 1
    assert "nonlinear_tracking.png" in text and "nan" not in text.lower()


def test_paired_interval_is_students_t():
    m, lo, hi = paired_interval([1.0, 3.0])
    assert m == 2.0 and hi - m == pytest.approx(12.706204736 * 1.0, rel=1e-9)
    m, lo, hi = paired_interval([5.0])
    assert m == 5.0 and math.isnan(lo) and math.isnan(hi)


@pytest.mark.parametrize(("name", "value", "message"), [
    ("presets", [], "presets must name at least one of ('vo-ekf', 'vo-ukf')"),
    ("presets", ["vo"], "unknown preset 'vo'"),
    ("filters", ["phd"], "unknown filter 'phd'"),
    ("truncations", ["lbp"], "unknown truncation 'lbp'"),
    ("glmb_budget", 0, "glmb_budget must be a positive integer, got 0"),
    ("ospa_c", -1.0, "ospa_c must be > 0.0, got -1.0"),
])
def test_bad_settings_are_refused_naming_the_setting(name, value, message):
    with pytest.raises(ReproduceError, match=rf"^config for 'nonlinear_tracking': .*"
                                             rf"{re.escape(message)}"):
        config_from_dict(Config.quick(), {"nonlinear_tracking": {name: value}})


def test_the_quick_settings_are_registered_and_smaller_than_the_full():
    st = get_study("nonlinear_tracking")
    quick, full = st.quick(), st.full()
    assert quick.n_mc < full.n_mc and quick.n_scans <= full.n_scans
    assert np.isclose(full.ospa_c, 100.0) and full.lmb_budget == 1000 and full.glmb_budget == 3000


def test_the_old_spelling_of_the_short_chains_still_reads_with_a_deprecation_warning():
    with pytest.warns(DeprecationWarning, match=r"truncations: 'short' is deprecated; write "
                                                r"'short-chain' \(the ShortChainGibbs class's "
                                                r"name\)"):
        cfg = config_from_dict(Config.quick(),
                               {"nonlinear_tracking": {"truncations": ["original", "short"]}})
    assert cfg.nonlinear_tracking.truncations == ("original", "short-chain")


def test_a_saved_task_item_reads_back_as_its_records(runs, tmp_path):
    import json

    from rankedassign.experiments.report import write_json
    from rankedassign.experiments.studies.nonlinear_tracking import NonlinearRun, task_from_json

    write_json(tmp_path / "runs.json", runs)
    back = [task_from_json(item) for item in json.loads((tmp_path / "runs.json").read_text())]
    assert back == runs and isinstance(back[0][0], NonlinearRun)
    assert summarise_nonlinear(back, TINY) == summarise_nonlinear(runs, TINY)
    with pytest.raises(ValueError, match=r"^a nonlinear_tracking task's item is a list of its "
                                         r"records, got dict$"):
        task_from_json({"run": 0})

"""Tests of the multi-sensor tracking study's functions (task, summary, table, plot)."""

import dataclasses
import math
import re

import numpy as np
import pytest
from numpy.testing import assert_array_equal

from rankedassign.experiments.studies.multisensor_tracking import (
    PLOT_BY,
    PLOT_COLUMNS,
    MultiSensorStudyConfig,
    MultiSensorTrackingRecord,
    _tracking_figure,
    check_association,
    make_association,
    multisensor_tracking_table,
    multisensor_tracking_task,
    plot_multisensor_tracking,
    summarise_multisensor_tracking,
)

TINY = MultiSensorStudyConfig(n_mc=1, n_scans=3, n_chains=10, chain_length=4, long_obs=30)
LONG, SHORT, EXACT = ("original", "exact"), ("short-chain", "exact"), ("exact", "exact")


def test_methods_share_the_measurements_and_are_recorded():
    recs = [multisensor_tracking_task(TINY, 0, (0, 2), m) for m in (LONG, SHORT, EXACT)]
    for r in recs:
        assert r.ospa2.shape == (3,) and r.cardinality_error.shape == (3,)
        assert r.coverage.shape == (12,) and r.sensors == (0, 2)
    long, short, exact = recs
    assert long.sweeps == 30 * long.invocations
    assert exact.n_fallback >= 0 and exact.sweeps == 30 * exact.n_fallback
    summ = summarise_multisensor_tracking(recs)
    assert [(s.truncation, s.method) for s in summ] == [LONG, SHORT, EXACT]
    assert math.isclose(summ[0].sweep_reduction, 1 - 30 / 10_000)
    assert math.isclose(summ[1].sweep_reduction,
                        1 - short.sweeps / (10_000 * short.invocations))
    assert math.isnan(summ[0].ospa2_se)  # one run
    table = multisensor_tracking_table(summ)
    assert table.count("\n") == 4 and "| 0,2 | 2 | short-chain | exact | paper |" in table
    # GOSPA per scan beside OSPA(2), summarised and in the table
    for r in recs:
        assert r.gospa.shape == r.ospa2.shape and (r.gospa >= 0).all()
    assert summ[0].gospa_mean == recs[0].gospa.mean() and math.isnan(summ[0].gospa_se)
    assert "GOSPA mean ± se (m)" in table and table.splitlines()[1].count("---") == 16
    assert all(r.birth == "paper" and r.births_per_scan == 4.0 and r.birth_seconds == 0.0
               for r in recs)


def test_adaptive_birth_cells_share_the_measurements_and_are_summarised_apart():
    static = multisensor_tracking_task(TINY, 0, (0, 1), SHORT)
    adaptive = multisensor_tracking_task(TINY, 0, (0, 1), SHORT, "adaptive")
    assert adaptive.birth == "adaptive" and static.birth == "paper"
    # scan 1 has no birth (no track, no earlier measurement), then births from the pairs
    assert 0 < adaptive.births_per_scan < 40 and adaptive.birth_seconds > 0
    summ = summarise_multisensor_tracking([static, adaptive])
    assert [(s.truncation, s.birth) for s in summ] == [("short-chain", "paper"),
                                                       ("short-chain", "adaptive")]
    assert summ[1].births_per_scan == adaptive.births_per_scan
    table = multisensor_tracking_table(summ)
    assert "| 0,1 | 2 | short-chain | exact | adaptive |" in table
    with pytest.raises(ValueError, match=r"unknown birth 'wide'; expected one of "
                                         r"\('paper', 'narrow', 'adaptive'\)"):
        multisensor_tracking_task(TINY, 0, (0,), SHORT, "wide")


def test_targets_lost_follows_the_coverage_rule():
    rec = MultiSensorTrackingRecord(0, (0,), "short-chain", "exact", np.zeros(2), np.zeros(2),
                                    np.array([0.2, 0.5, np.nan, 0.9]), 0, 0, 0, 0, 0.0)
    assert rec.targets_lost == 1


def test_unknown_association():
    with pytest.raises(TypeError, match=re.escape(
            "association entries must be (truncation, method) pairs such as "
            "['short-chain', 'mm'], got 'fast'")):
        make_association(TINY, "fast")
    with pytest.raises(ValueError, match=re.escape(
            "unknown association: truncation 'murty'; expected one of ('original', "
            "'short-chain', 'exact')")):
        make_association(TINY, ("murty", "mm"))
    with pytest.raises(ValueError, match=re.escape(
            "unknown association: method 'gibbs'; expected one of ('exact', 'mm', 'mm-fixed', "
            "'componentwise')")):
        check_association(("short-chain", "gibbs"))
    with pytest.raises(ValueError, match=re.escape(
            "unknown glmb_associations: truncation 'lbp'; expected one of")):
        MultiSensorStudyConfig(glmb_associations=(("lbp", "mm"),))
    with pytest.raises(TypeError, match=re.escape(
            "associations entries must be (truncation, method) pairs such as ['short-chain', "
            "'mm'], "
            "got ('short-chain',)")):
        MultiSensorStudyConfig(associations=(("short-chain",),))


@pytest.mark.parametrize(("old", "new"), [("long", ("original", "exact")),
                                          ("short", ("short-chain", "exact")),
                                          ("short-mm", ("short-chain", "mm")),
                                          ("short-mm-fixed", ("short-chain", "mm-fixed")),
                                          ("exact", ("exact", "exact"))])
@pytest.mark.parametrize("setting", ["associations", "adaptive_associations",
                                     "glmb_associations", "glmb_adaptive_associations"])
def test_the_old_association_strings_still_read_with_a_deprecation_warning(setting, old, new):
    want = rf'^{setting}: \'{old}\' is deprecated; write \["{new[0]}", "{new[1]}"\]$'
    with pytest.warns(DeprecationWarning, match=want):
        cfg = MultiSensorStudyConfig(**{setting: (old,)})
    assert getattr(cfg, setting) == (new,)
    # a --config file's two-element lists read as the pairs, silently
    assert getattr(MultiSensorStudyConfig(**{setting: [list(new)]}), setting) == (new,)


def test_the_old_spelling_gives_the_same_numbers():
    with pytest.warns(DeprecationWarning, match=r"^association: 'short-mm' is deprecated; "
                                                r'write \["short-chain", "mm"\]$'):
        old = multisensor_tracking_task(TINY, 0, (0, 1), "short-mm")
    new = multisensor_tracking_task(TINY, 0, (0, 1), ("short-chain", "mm"))
    assert (old.truncation, old.method) == ("short-chain", "mm")
    for name in ("ospa2", "cardinality_error", "coverage", "gospa"):
        assert_array_equal(getattr(old, name), getattr(new, name))
    assert (old.sweeps, old.row_updates, old.invocations) == (new.sweeps, new.row_updates,
                                                              new.invocations)
    assert repr(make_association(TINY, ("short-chain", "mm"))) == \
        "ShortChainGibbs(10, 4, tau_stall=5, tau_stale=10)"


def test_quick_config_and_plot(tmp_path):
    pytest.importorskip("matplotlib")
    cfg = MultiSensorStudyConfig.quick()
    assert set(cfg.associations) <= {LONG, SHORT, ("short-chain", "mm"),
                                     ("short-chain", "mm-fixed"), EXACT}
    assert (cfg.adaptive_sensor_sets, cfg.adaptive_associations) == (((0, 1, 2),), (SHORT,))
    rec = MultiSensorTrackingRecord(0, (0,), *SHORT, np.ones(4), np.zeros(4), np.ones(12),
                                    10, 20, 1, 0, 1.0)
    ad = MultiSensorTrackingRecord(0, (0,), *SHORT, np.ones(4), np.zeros(4), np.ones(12),
                                   10, 20, 1, 0, 1.0, "adaptive", 5.0, 0.1)
    out = tmp_path / "ms.png"
    plot_multisensor_tracking(summarise_multisensor_tracking([rec, ad]), out)
    assert out.stat().st_size > 0


def _quick_cells():
    """Summaries of the quick study's 13 cells (made-up curves)."""
    cfg = MultiSensorStudyConfig.quick()
    cells = [(s, m, "paper") for s in cfg.sensor_sets for m in cfg.associations]
    cells += [(s, m, "adaptive") for s in cfg.adaptive_sensor_sets
              for m in cfg.adaptive_associations]
    recs = [MultiSensorTrackingRecord(0, tuple(s), *m, np.full(4, 10.0 * i), np.zeros(4),
                                      np.ones(12), 10, 20, 1, 0, 1.0, b)
            for i, (s, m, b) in enumerate(cells)]
    return summarise_multisensor_tracking(recs)


def _panels(fig):
    """(title, number of lines) of every visible OSPA(2) panel, row by row."""
    return [(ax.get_title(), len(ax.get_lines())) for ax in fig.axes
            if ax.get_visible() and ax.get_title()]


def test_plot_splits_the_lines_into_panels(tmp_path):
    pytest.importorskip("matplotlib")
    summaries = _quick_cells()
    assert len(summaries) == 13  # the 13 lines that used to share one panel
    fig = _tracking_figure(summaries, "sensors")
    assert _panels(fig) == [("sensors {0}", 3), ("sensors {1}", 3), ("sensors {2}", 3),
                            ("sensors {0,1,2}", 4)]
    fig = _tracking_figure(summaries, "association")
    assert _panels(fig) == [("original (exact)", 4), ("short-chain (exact)", 4),
                            ("short-chain (mm)", 4), ("short-chain (exact) adaptive", 1)]
    # a line keeps its colour in every panel; one y scale per metric
    colours = {}
    for ax in fig.axes:
        for line in ax.get_lines():
            assert colours.setdefault(line.get_label(), line.get_color()) == line.get_color()
    assert len(colours) == 4
    ospa_axes = [ax for ax in fig.axes if ax.get_title()]
    assert len({ax.get_ylim() for ax in ospa_axes}) == 1
    # more panels than PLOT_COLUMNS wrap onto a second row, the empty places hidden
    many = [dataclasses.replace(summaries[0], sensors=(v,)) for v in range(PLOT_COLUMNS + 1)]
    fig = _tracking_figure(many, "sensors")
    assert len(_panels(fig)) == PLOT_COLUMNS + 1
    assert sum(not ax.get_visible() for ax in fig.axes) == 2 * (PLOT_COLUMNS - 1)
    for by in PLOT_BY:
        out = tmp_path / f"{by}.png"
        plot_multisensor_tracking(summaries, out, by=by)
        assert out.stat().st_size > 0


def test_plot_errors(tmp_path):
    with pytest.raises(ValueError, match=re.escape(
            "unknown by 'sensor'; expected one of ('sensors', 'association')")):
        plot_multisensor_tracking(_quick_cells(), tmp_path / "x.png", by="sensor")
    # the old name of the panels by association, deprecated
    with pytest.warns(DeprecationWarning, match=r"^by: 'method' is deprecated; write "
                                                r"'association'$"):
        fig = _tracking_figure(_quick_cells(), "method")
    assert _panels(fig)[0] == ("original (exact)", 4)
    with pytest.raises(ValueError, match="nothing to plot: summaries is empty"):
        plot_multisensor_tracking([], tmp_path / "x.png")


def test_the_run_records_round_trip_through_json(tmp_path):
    # <study>_runs.json read back into records: the same JSON again (NaN coverage included)
    # and the same summary
    import json

    from rankedassign.experiments import get_study
    from rankedassign.experiments.report import write_json

    recs = [multisensor_tracking_task(TINY, 0, (0,), m) for m in (LONG, SHORT)]
    write_json(tmp_path / "runs.json", recs)
    back = [get_study("multisensor_tracking").run_from_dict(d)
            for d in json.loads((tmp_path / "runs.json").read_text())]
    assert all(isinstance(r, MultiSensorTrackingRecord) for r in back)
    assert back[0].sensors == (0,) and back[0].coverage.dtype == float
    assert np.isnan(back[0].coverage).any()  # short-lived targets: null in the JSON
    write_json(tmp_path / "again.json", back)
    assert (tmp_path / "again.json").read_text() == (tmp_path / "runs.json").read_text()
    write_json(tmp_path / "s0.json", summarise_multisensor_tracking(recs))
    write_json(tmp_path / "s1.json", summarise_multisensor_tracking(back))
    assert (tmp_path / "s0.json").read_text() == (tmp_path / "s1.json").read_text()

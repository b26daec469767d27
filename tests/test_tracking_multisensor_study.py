"""Tests of the multi-sensor tracking study's functions (task, summary, table, plot)."""

import math

import numpy as np
import pytest

from rankedassign.tracking.multisensor_study import (
    MultiSensorStudyConfig,
    MultiSensorTrackingRecord,
    make_association,
    multisensor_tracking_table,
    multisensor_tracking_task,
    plot_multisensor_tracking,
    summarise_multisensor_tracking,
)

TINY = MultiSensorStudyConfig(n_mc=1, n_scans=3, n_chains=10, chain_length=4, long_obs=30)


def test_methods_share_the_measurements_and_are_recorded():
    recs = [multisensor_tracking_task(TINY, 0, (0, 2), m) for m in ("long", "short", "exact")]
    for r in recs:
        assert r.ospa2.shape == (3,) and r.cardinality_error.shape == (3,)
        assert r.coverage.shape == (12,) and r.sensors == (0, 2)
    long, short, exact = recs
    assert long.sweeps == 30 * long.invocations
    assert exact.n_fallback >= 0 and exact.sweeps == 30 * exact.n_fallback
    summ = summarise_multisensor_tracking(recs)
    assert [s.method for s in summ] == ["long", "short", "exact"]
    assert math.isclose(summ[0].sweep_reduction, 1 - 30 / 10_000)
    assert math.isclose(summ[1].sweep_reduction,
                        1 - short.sweeps / (10_000 * short.invocations))
    assert math.isnan(summ[0].ospa2_se)  # one run
    table = multisensor_tracking_table(summ)
    assert table.count("\n") == 4 and "| 0,2 | 2 | short |" in table


def test_targets_lost_follows_the_coverage_rule():
    rec = MultiSensorTrackingRecord(0, (0,), "short", np.zeros(2), np.zeros(2),
                                    np.array([0.2, 0.5, np.nan, 0.9]), 0, 0, 0, 0, 0.0)
    assert rec.targets_lost == 1


def test_unknown_method():
    with pytest.raises(ValueError, match="unknown method 'fast'"):
        make_association(TINY, "fast")


def test_quick_config_and_plot(tmp_path):
    pytest.importorskip("matplotlib")
    cfg = MultiSensorStudyConfig.quick()
    assert set(cfg.methods) <= {"long", "short", "short-mm", "short-mm-fixed", "exact"}
    rec = MultiSensorTrackingRecord(0, (0,), "short", np.ones(4), np.zeros(4), np.ones(12),
                                    10, 20, 1, 0, 1.0)
    out = tmp_path / "ms.png"
    plot_multisensor_tracking(summarise_multisensor_tracking([rec]), out)
    assert out.stat().st_size > 0

"""The GOSPA metric generator of the Stone Soup plug-in."""

from __future__ import annotations

import datetime

import numpy as np
import pytest

pytest.importorskip("stonesoup")

from stonesoup.measures import Euclidean  # noqa: E402
from stonesoup.metricgenerator.manager import MultiManager  # noqa: E402
from stonesoup.metricgenerator.ospametric import GOSPAMetric as StoneSoupGOSPA  # noqa: E402
from stonesoup.types.groundtruth import GroundTruthPath, GroundTruthState  # noqa: E402
from stonesoup.types.state import State  # noqa: E402
from stonesoup.types.track import Track  # noqa: E402

from rankedassign.metrics import gospa  # noqa: E402
from rankedassign.stonesoup import GOSPAMetric  # noqa: E402

T0 = datetime.datetime(2025, 1, 1)


def _paths(rng, n, n_scans, cls_path, cls_state, jitter):
    out = set()
    for _ in range(n):
        start = int(rng.integers(0, n_scans - 1))
        stop = int(rng.integers(start + 1, n_scans + 1))
        x0 = rng.uniform(0, 30, size=4)
        out.add(cls_path([cls_state((x0 + k + rng.normal(0, jitter, 4)).reshape(-1, 1),
                                    timestamp=T0 + datetime.timedelta(seconds=k))
                          for k in range(start, stop)]))
    return out


def _points(paths, t, mapping):
    return [np.asarray(s.state_vector, float).ravel()[list(mapping)]
            for path in paths for s in path if s.timestamp == t]


@pytest.mark.parametrize("c, p", [(10.0, 1.0), (5.0, 2.0), (40.0, 3.0)])
def test_gospa_metric_equals_gospa_per_timestamp(c, p):
    rng = np.random.default_rng(0)
    truths = _paths(rng, 4, 10, GroundTruthPath, GroundTruthState, 0.0)
    tracks = _paths(rng, 5, 10, Track, State, 2.0)
    gen = GOSPAMetric(c=c, p=p, mapping=(0, 2))
    manager = MultiManager([gen])
    manager.add_data({"groundtruth_paths": truths, "tracks": tracks})
    series = gen.compute_metric(manager)
    assert [m.title for m in series] == list(GOSPAMetric.TITLES)
    stamps = sorted({s.timestamp for path in truths | tracks for s in path})
    for k, t in enumerate(stamps):
        x, y = _points(truths, t, (0, 2)), _points(tracks, t, (0, 2))
        r = gospa(x if x else [], y if y else [], c=c, p=p)
        got = [float(s.value[k].value) for s in series]
        np.testing.assert_allclose(got, list(r[:4]), rtol=0, atol=0)
        assert all(s.value[k].timestamp == t for s in series)


def test_gospa_metric_agrees_with_stone_soups_dict():
    # Stone Soup's GOSPAMetric (switching penalty 0) gives the same numbers as a dict
    rng = np.random.default_rng(3)
    truths = _paths(rng, 3, 8, GroundTruthPath, GroundTruthState, 0.0)
    tracks = _paths(rng, 4, 8, Track, State, 1.0)
    ours = GOSPAMetric(c=10.0, p=2.0, mapping=(0, 2), generator_name="ours")
    theirs = StoneSoupGOSPA(c=10.0, p=2.0, measure=Euclidean(mapping=(0, 2)))
    manager = MultiManager([ours, theirs])
    manager.add_data({"groundtruth_paths": truths, "tracks": tracks})
    metrics = manager.generate_metrics()
    a = metrics["ours"]["GOSPA distances"].value
    b = metrics["gospa_generator"]["GOSPA Metrics"].value
    np.testing.assert_allclose([float(m.value) for m in a],
                               [float(m.value["distance"]) for m in b], rtol=1e-12)
    missed = metrics["ours"]["GOSPA missed"].value
    np.testing.assert_allclose([float(m.value) ** 2 for m in missed],
                               [float(m.value["missed"]) for m in b], rtol=1e-12)


def test_gospa_metric_in_a_multimanager_and_metricplotter(tmp_path):
    import matplotlib

    matplotlib.use("Agg")
    from stonesoup.plotter import MetricPlotter

    rng = np.random.default_rng(1)
    truths = _paths(rng, 3, 6, GroundTruthPath, GroundTruthState, 0.0)
    tracks = _paths(rng, 3, 6, Track, State, 1.0)
    manager = MultiManager([GOSPAMetric(c=10, p=1, mapping=(0, 2))])
    manager.add_data({"groundtruth_paths": truths, "tracks": tracks})
    metrics = manager.generate_metrics()
    assert sorted(metrics["gospa_generator"]) == sorted(GOSPAMetric.TITLES)
    plotter = MetricPlotter()
    plotter.plot_metrics(metrics, combine_plots=True)
    plotter.fig.savefig(tmp_path / "gospa.png")
    assert (tmp_path / "gospa.png").stat().st_size > 0


def test_gospa_metric_bad_input():
    gen = GOSPAMetric(c=10.0, p=1)
    manager = MultiManager([gen])
    manager.add_data({"groundtruth_paths": set(), "tracks": set()})
    with pytest.raises(ValueError, match=r"GOSPAMetric: neither the tracks nor the truths "
                                         r"have a state"):
        gen.compute_metric(manager)
    manager.add_data({"groundtruth_paths": {1}, "tracks": set()})
    with pytest.raises(TypeError, match=r"the truths must hold tracks or states, got int"):
        gen.compute_metric(manager)
    truth = GroundTruthPath([GroundTruthState([[0.0], [1.0]], timestamp=T0)])
    track = Track([State([[0.0], [1.0], [2.0]], timestamp=T0)])
    manager.add_data({"groundtruth_paths": {truth}, "tracks": {track}})
    with pytest.raises(ValueError, match=r"GOSPAMetric: the truths have states of dimension 2 "
                                         r"and the tracks 3; set mapping"):
        gen.compute_metric(manager)
    manager.add_data({"groundtruth_paths": {truth}, "tracks": set()})
    with pytest.raises(ValueError, match=r"c must be > 0.0, got -1.0"):
        GOSPAMetric(c=-1.0, p=1).compute_metric(manager)

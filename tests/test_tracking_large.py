"""Tests of the ``"large"`` scenario (make_scenario("large", n_targets=N)) and of the filters
on it at small N: its density, its refused inputs, N = 0, and the LMB filter's extraction by
the MAP cardinality of every cluster (``extraction="cluster-map"``)."""

import numpy as np
import pytest
from numpy.testing import assert_allclose, assert_array_equal

from rankedassign.tracking import (
    ClusteredGLMBFilter,
    Exact,
    LMBFilter,
    MultiSensorLMBFilter,
    Murty,
    make_model,
    make_scenario,
)
from rankedassign.tracking.nonlinear import BearingRange, NonlinearModel
from rankedassign.tracking.presets import LARGE_SIGMA_BEARING
from rankedassign.tracking.scenario import LARGE_CELL, large_model
from rankedassign.tracking.single import lmb as lmb_module
from rankedassign.tracking.single.lmb import cluster_map_tracks, map_cardinality


@pytest.mark.parametrize("n", [1, 100, 2500])
def test_large_scenario_density(n):
    sc = make_scenario("large", n_targets=n, n_scans=3, rng=0)
    (x0, x1), (y0, y1) = sc.model.clutter.region
    # one target per LARGE_CELL², Vo's clutter density
    assert_allclose((x1 - x0) * (y1 - y0) / n, LARGE_CELL**2)
    assert_allclose(sc.model.clutter.intensity, make_model("vo").clutter.intensity)
    assert sc.truth.states.shape == (3, n, 4)
    assert sc.truth.n_targets.tolist() == [n, n, n]
    assert np.all(np.abs(sc.truth.states[0][:, [0, 2]]) <= x1)
    # detections first, in target order, then clutter
    assert len(sc.scans) == 3 and sc.scans[0].z.shape[1] == 2


def test_large_scenario_is_reproducible():
    a = make_scenario("large", n_targets=50, n_scans=2, rng=7)
    b = make_scenario("large", n_targets=50, n_scans=2, rng=7)
    assert np.array_equal(a.truth.states, b.truth.states)
    assert all(np.array_equal(s.z, t.z) for s, t in zip(a.scans, b.scans, strict=True))


def test_large_scenario_refuses_bad_n_targets():
    with pytest.raises(ValueError, match="n_targets must be >= 0, got -1"):
        make_scenario("large", n_targets=-1)
    with pytest.raises(TypeError, match="n_targets must be an int, got float 1.5"):
        make_scenario("large", n_targets=1.5)
    with pytest.raises(TypeError, match="n_targets must be an int, got bool True"):
        make_scenario("large", n_targets=True)
    with pytest.raises(TypeError, match="n_targets must be an int, got str '10'"):
        make_scenario("large", n_targets="10")
    with pytest.raises(ValueError, match=r"n_targets = 10000000 with n_scans = 100 would need "
                                         r"59\.6 GiB \(64 bytes a target and scan\), above "
                                         r"MAX_WORK_BYTES = 4\.0 GiB"):
        make_scenario("large", n_targets=10**7)
    with pytest.raises(ValueError, match="n_targets is an option of the 'large' scenario only"):
        make_scenario("vo", n_targets=10)


def test_large_bearing_range_scenario():
    # the same truth as the position sensor's scenario; measurements [bearing, range] from a
    # sensor near the centre, so every bearing occurs (those below the sensor wrap at ±π)
    sc = make_scenario("large", n_targets=900, n_scans=2, rng=3, sensor="bearing-range")
    pos = make_scenario("large", n_targets=900, n_scans=2, rng=3)
    assert isinstance(sc.model, NonlinearModel) and isinstance(sc.model.sensor, BearingRange)
    assert sc.model.sensor.sigma_bearing == LARGE_SIGMA_BEARING
    assert np.array_equal(sc.truth.states, pos.truth.states)
    z, origin = sc.scans[0].z, sc.scans[0].origin
    assert z.shape[1] == 2 and np.all(np.abs(z[:, 0]) <= np.pi)
    assert (z[:, 0] > 3.0).any() and (z[:, 0] < -3.0).any()
    # detections: [bearing, range] of their target, within a few σ
    det = origin >= 0
    x = sc.truth.states[0][origin[det]]
    zz = sc.model.sensor.h(x)
    d = np.pi - np.mod(np.pi - (z[det, 0] - zz[:, 0]), 2 * np.pi)
    assert np.abs(d).max() < 6 * LARGE_SIGMA_BEARING
    assert np.abs(z[det, 1] - zz[:, 1]).max() < 60.0
    # the same clutter count on average (0.3 a target)
    assert sc.model.clutter.rate == pytest.approx(0.3 * 900)


def test_large_scenario_refuses_a_bad_sensor():
    with pytest.raises(ValueError, match=r"unknown sensor 'sonar'; expected one of \('position', "
                                         r"'bearing-range'\)"):
        make_scenario("large", n_targets=10, sensor="sonar")
    with pytest.raises(ValueError, match="sensor is an option of the 'large' scenario only"):
        make_scenario("vo", sensor="bearing-range")


def test_large_scenario_without_targets():
    sc = make_scenario("large", n_targets=0, n_scans=3, rng=0)
    assert sc.truth.states.shape == (3, 0, 4)
    assert large_model(0).clutter.region == large_model(1).clutter.region
    lmb = LMBFilter(sc.model, Murty(5), grouping=True)
    glmb = ClusteredGLMBFilter(sc.model, Murty(5))
    for k, s in enumerate(sc.scans):
        lmb.step(s.z, rng=k)
        rec = glmb.step(s.z, rng=k)
    assert rec.n_clusters >= 1


def test_filters_find_the_targets_of_a_large_scene():
    # 200 targets as the prior, three scans: the LMB filter's cluster path and the clustered
    # δ-GLMB filter report (nearly) every one of them
    sc = make_scenario("large", n_targets=200, n_scans=3, rng=1)
    n = 200
    F = sc.model.motion.F
    means = np.linalg.solve(F, sc.truth.states[0].T).T
    labels = np.column_stack([np.zeros(n, np.int64), np.arange(1, n + 1)])
    covs = np.tile(np.diag([100.0, 25.0, 100.0, 25.0]), (n, 1, 1))
    lmb = LMBFilter(sc.model, Murty(20), grouping=True, max_tracks=3000)
    lmb.set_prior(labels, means, covs, existence=np.full(n, 0.99))
    glmb = ClusteredGLMBFilter(sc.model, Murty(20), retained_mass=True)
    glmb.set_prior(labels, means, covs)
    for k, s in enumerate(sc.scans):
        a = lmb.step(s.z, rng=k)
        b = glmb.step(s.z, rng=k)
    for rec in (a, b):
        prior = rec.labels[rec.labels[:, 0] == 0]
        assert prior.shape[0] >= 0.97 * n
        est = rec.states[rec.labels[:, 0] == 0][:, [0, 2]]
        truth = sc.truth.states[-1][prior[:, 1] - 1][:, [0, 2]]
        assert np.median(np.linalg.norm(est - truth, axis=1)) < 10.0
    assert b.n_clusters > 50
    assert np.isfinite(b.retained_mass) and 0 < b.retained_mass <= 1 + 1e-12


# ------------------------------------------------------------- extraction: MAP per cluster
def _global_map(r):
    return np.sort(np.argsort(-np.asarray(r), kind="stable")[:map_cardinality(r)])


def test_cluster_map_of_one_cluster_is_the_global_map():
    rng = np.random.default_rng(5)
    for _ in range(500):
        T = int(rng.integers(0, 20))
        # ties (repeated values) and r = 0.5 included: the order of ties must agree too
        r = (rng.choice([0.2, 0.5, 0.6, 0.99, 0.3], T) if rng.random() < 0.5
             else rng.random(T))
        assert_array_equal(cluster_map_tracks(r, np.full(T, 7)), _global_map(r))


def test_cluster_map_is_map_cardinality_cluster_by_cluster():
    # the reference: map_cardinality on each cluster's tracks, its most likely ones (ties to
    # the earlier track); many clusters of one size take the vectorised recursion, bit for bit
    rng = np.random.default_rng(11)
    for trial in range(300):
        T = int(rng.integers(1, 80))
        cl = rng.integers(0, int(rng.integers(1, T + 1)), T)
        r = (rng.choice([0.5, 0.25, 0.75, 0.99, 0.01, 0.3], T) if trial % 2
             else rng.random(T))
        expected = []
        for c in np.unique(cl):
            idx = np.flatnonzero(cl == c)
            expected += idx[np.argsort(-r[idx], kind="stable")[:map_cardinality(r[idx])]].tolist()
        assert_array_equal(cluster_map_tracks(r, cl), np.sort(expected))


def test_cluster_map_reports_the_likely_tracks_the_global_map_leaves_out():
    # twenty independent tracks at r = 0.9: the Poisson-binomial mode is 18, so the global MAP
    # leaves the two last ones out; every one-track cluster's own MAP reports its track
    r = np.full(20, 0.9)
    assert _global_map(r).size == 18
    assert_array_equal(cluster_map_tracks(r, np.arange(20)), np.arange(20))
    # within a cluster its own MAP cardinality and ties to the earlier track; r = 0.5 alone
    # is not reported (ρ = [0.5, 0.5], the smaller cardinality)
    r = np.array([0.6, 0.5, 0.7, 0.5, 0.2, 0.55])
    c = np.array([3, 1, 3, 2, 3, 3])
    n3 = map_cardinality(r[c == 3])
    assert n3 == 2
    assert_array_equal(cluster_map_tracks(r, c), [0, 2])


def test_cluster_map_refuses_clusters_of_another_length():
    with pytest.raises(ValueError, match=r"^cluster has 2 entries for 3 tracks$"):
        cluster_map_tracks([0.9, 0.9, 0.9], [0, 1])


def _large_runs(extractions, n=200, rng=1, **kw):
    sc = make_scenario("large", n_targets=n, n_scans=3, rng=rng)
    F = sc.model.motion.F
    means = np.linalg.solve(F, sc.truth.states[0].T).T
    labels = np.column_stack([np.zeros(n, np.int64), np.arange(1, n + 1)])
    covs = np.tile(np.diag([100.0, 25.0, 100.0, 25.0]), (n, 1, 1))
    out = []
    for ex in extractions:
        f = LMBFilter(sc.model, Murty(20), grouping=True, max_tracks=3000, extraction=ex, **kw)
        f.set_prior(labels, means, covs, existence=np.full(n, 0.99))
        out.append([f.step(s.z, rng=k) for k, s in enumerate(sc.scans)])
    return out


def test_cluster_map_keeps_a_target_the_global_map_drops():
    # 200 known targets: at the last scan the global MAP cardinality leaves one likely target
    # unreported, the MAP of every cluster reports them all; the filter's state is the same
    glob, per = _large_runs(["map", "cluster-map"])
    for a, b in zip(glob, per, strict=True):
        assert_array_equal(a.track_labels, b.track_labels)
        assert_array_equal(a.track_existence, b.track_existence)
    a, b = glob[-1], per[-1]
    assert a.labels.shape[0] == 199 and b.labels.shape[0] == 200
    assert_array_equal(np.sort(b.labels[:, 1]), np.arange(1, 201))
    # the tracks both report have the same estimates
    both = np.isin(b.labels[:, 1], a.labels[:, 1])
    assert_array_equal(b.states[both], a.states)


def test_cluster_map_on_the_cluster_path_equals_the_dense_path(monkeypatch):
    # the clusters come from the k-d tree's gate on the cluster path and from the dense gate
    # otherwise: the same clusters, the same reported tracks
    monkeypatch.setattr(lmb_module, "SPATIAL_MIN_PAIRS", 1 << 62)
    (dense,) = _large_runs(["cluster-map"], n=100, rng=2)
    monkeypatch.setattr(lmb_module, "SPATIAL_MIN_PAIRS", 0)
    (spatial,) = _large_runs(["cluster-map"], n=100, rng=2)
    for a, b in zip(dense, spatial, strict=True):
        assert_array_equal(a.labels, b.labels)
        assert_allclose(b.states, a.states, rtol=1e-12, atol=1e-9)


def test_cluster_map_with_one_cluster_is_the_map_extraction():
    # without a gate every track gates every measurement: one cluster, so the records are
    # those of extraction="map", bit for bit (with and without grouping)
    sc = make_scenario("vo", rng=4, n_scans=12)
    for grouping in (False, True):
        runs = []
        for ex in ("map", "cluster-map"):
            f = LMBFilter(sc.model, Murty(20), gate_prob=None, grouping=grouping, extraction=ex)
            runs.append([f.step(s.z, rng=k) for k, s in enumerate(sc.scans)])
        for a, b in zip(*runs, strict=True):
            assert_array_equal(a.labels, b.labels)
            assert_array_equal(a.states, b.states)
            assert_array_equal(a.existence, b.existence)


def test_multisensor_lmb_refuses_cluster_map():
    with pytest.raises(ValueError, match=r"^unknown extraction 'cluster-map'; expected one of "
                                         r"\('hysteresis', 'map'\)$"):
        MultiSensorLMBFilter(make_model("vo"), Exact(), extraction="cluster-map")

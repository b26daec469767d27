"""Tests of the clustered δ-GLMB filter (rankedassign.tracking.clustered)."""

import numpy as np
import pytest
from numpy.testing import assert_allclose, assert_array_equal

import rankedassign.tracking.clustered as clustered_module
from rankedassign.tracking import (
    BirthComponent,
    ConstantSurvival,
    ConstantVelocity,
    GLMBFilter,
    LMBBirth,
    Model,
    Murty,
    PoissonClutter,
    PositionSensor,
    ShortChainGibbs,
    make_model,
    make_scenario,
    run_filter,
    run_scenario,
)
from rankedassign.tracking.clustered import (
    ClusteredGLMBFilter,
    _marginal,
    _product,
)
from rankedassign.tracking.nonlinear import (
    BearingRange,
    BearingRangeClutter,
    ExtendedKalmanFilter,
    GaussianBirth,
    LinearGaussianMotion,
    NonlinearModel,
)
from rankedassign.tracking.single.glmb import _unique_inverse

SHORT = ShortChainGibbs(50, 5, tau_stall=5, tau_stale=10)


def _one_place_model():
    """One birth at the origin: targets near it stay in one cluster."""
    birth = LMBBirth([BirthComponent(0.03, np.zeros(4), 100.0 * np.eye(4))])
    return Model(ConstantVelocity(1.0, 5.0), PositionSensor(0.98, 10.0), PoissonClutter(30.0),
                 birth, ConstantSurvival(0.99), extraction="map")


def _close_scans(n_scans=6, seed=0):
    """Two slow targets 20 m apart near the birth, detected every scan, no clutter."""
    rng = np.random.default_rng(seed)
    scans = []
    for k in range(n_scans):
        truth = np.array([[0.0 + k, 0.0], [20.0, 0.0 + k]])
        scans.append(truth + rng.normal(0, 3.0, truth.shape))
    return scans


@pytest.mark.parametrize("extraction", ["map", "hysteresis"])
def test_one_cluster_equals_the_glmb_filter(extraction):
    model = _one_place_model()
    f = ClusteredGLMBFilter(model, Murty(30), extraction=extraction, retained_mass=True)
    g = GLMBFilter(model, Murty(30), extraction=extraction, retained_mass=True)
    for k, z in enumerate(_close_scans()):
        a = f.step(z, rng=k)
        b = g.step(z, rng=k)
        assert a.n_clusters == 1 and a.n_splits == 0
        assert_array_equal(a.labels, b.labels)
        assert_array_equal(a.track_labels, b.track_labels)
        assert_allclose(a.states, b.states, rtol=1e-12, atol=1e-12)
        assert_allclose(a.existence, b.existence, rtol=1e-12, atol=1e-12)
        assert_allclose(a.track_existence, b.track_existence, rtol=1e-12, atol=1e-12)
        assert_allclose(a.cardinality, b.cardinality, rtol=1e-12, atol=1e-12)
        assert a.n_components == b.n_components
        assert_allclose(a.retained_mass, b.retained_mass, rtol=1e-12)
        c = f.clusters[0]
        assert_allclose(c.comp_w, g.comp_w, rtol=1e-12, atol=1e-15)
        assert_array_equal(c.comp_off, g.comp_off)


def test_processing_order_does_not_change_the_result():
    sc = make_scenario("vo", rng=5, n_scans=8)
    f1 = ClusteredGLMBFilter(sc.model, SHORT)
    f2 = ClusteredGLMBFilter(sc.model, SHORT)
    for k, s in enumerate(sc.scans):
        f2.clusters = f2.clusters[::-1]  # another processing order of the same clusters
        a = f1.step(s.z, rng=k)
        b = f2.step(s.z, rng=k)
        assert_array_equal(a.labels, b.labels)
        assert_array_equal(a.track_labels, b.track_labels)
        assert_array_equal(a.states, b.states)
        assert_array_equal(a.cluster_sizes, b.cluster_sizes)
        assert (a.sweeps, a.n_unique) == (b.sweeps, b.n_unique)
        assert_allclose(a.cardinality, b.cardinality, rtol=1e-12, atol=1e-15)


def test_the_scan_reuses_the_gate_prediction_only_for_an_unchanged_cluster():
    # a cluster's scan takes the table the gate predicted (the same numbers); a part of a
    # split or a merged product predicts its own table, never the whole cluster's
    sc = make_scenario("vo", rng=3, n_scans=6)
    f = ClusteredGLMBFilter(sc.model, Murty(30))
    for k, s in enumerate(sc.scans):
        f.step(s.z, rng=k)
        # the scans used every stored prediction, and each cluster keeps only the scan's
        # history nodes (no histories are kept)
        for c in f.clusters:
            assert c._pred is None
            assert c._node_parent.size == c.n_tracks and (c._node_parent == -1).all()
            assert_array_equal(c.hist, np.arange(c.n_tracks))
    c, d = f.clusters[:2]
    c._pred, d._pred = (c.m, c.P), (d.m, d.P)
    assert _marginal(c, np.ones(c.n_tracks, dtype=bool))._pred is None
    assert _product(c, d, cap=10)[0]._pred is None


def test_lean_unique_is_numpys(monkeypatch):
    rng = np.random.default_rng(2)
    for _ in range(300):
        x = rng.integers(-3, int(rng.integers(1, 40)), int(rng.integers(0, 25))).astype(np.int64)
        u, inv = np.unique(x, return_inverse=True)
        a, b = _unique_inverse(x)
        assert_array_equal(a, u)
        assert_array_equal(b, inv.reshape(-1))
        assert b.dtype == np.int64
        # the table of flags (values in 0 .. bound − 1, bound small, 512 values or more): the
        # same arrays
        y = x - x.min() if x.size else x
        y = np.tile(y, 512 // max(y.size, 1) + 1)[:max(512, y.size) if y.size else 0]
        bound = int(y.max()) + 1 + int(rng.integers(0, 30)) if y.size else 5
        u, inv = np.unique(y, return_inverse=True)
        with monkeypatch.context() as m:
            if y.size:  # the table, not the sort
                m.setattr(np, "sort", None)
            a, b = _unique_inverse(y, bound)
        assert_array_equal(a, u)
        assert_array_equal(b, inv.reshape(-1))
        assert a.dtype == np.int64 and b.dtype == np.int64


def test_clusters_split_and_report():
    sc = make_scenario("vo", rng=3, n_scans=12)
    f = ClusteredGLMBFilter(sc.model, Murty(30), retained_mass=True)
    recs = [f.step(s.z, rng=k) for k, s in enumerate(sc.scans)]
    last = recs[-1]
    # the four birth places are far apart: several clusters
    assert last.n_clusters >= 4
    assert last.cluster_sizes.sum() == last.track_labels.shape[0]
    assert last.cluster_retained_mass.size == last.cluster_scanned_sizes.size
    assert 0 < last.retained_mass <= 1 + 1e-12
    assert last.retained_mass_reason == ""
    assert_allclose(last.retained_mass, np.prod(last.cluster_retained_mass), rtol=1e-12)
    assert_allclose(last.cardinality.sum(), 1.0, rtol=1e-12)
    assert any(r.n_splits for r in recs) and any(r.n_merges for r in recs)
    # the true targets of the first scans are found (labels born at scan 1)
    assert {tuple(x) for x in last.labels.tolist()} >= {(1, 1), (1, 2), (1, 3)}


def test_marginal_and_product_of_a_cluster():
    f = ClusteredGLMBFilter(make_model("vo"), Murty(10), h_max=3)
    f.set_prior([[0, 1], [0, 2]], np.zeros((2, 4)), np.tile(np.eye(4), (2, 1, 1)),
                components=[[0, 1], [0], []], weights=[0.5, 0.3, 0.2])
    c = f.clusters[0]
    a = _marginal(c, np.array([True, False]))
    b = _marginal(c, np.array([False, True]))
    # w'(I ∩ {1}) sums the components with the same intersection
    assert_allclose(a.comp_w, [0.8, 0.2])
    assert [a.comp_tracks[a.comp_off[h]:a.comp_off[h + 1]].tolist() for h in range(2)] == \
        [[0], []]
    assert_allclose(b.comp_w, [0.5, 0.5])
    assert_array_equal(b.labels, [[0, 2]])
    p, dropped = _product(a, b, cap=3)
    # 4 pairs, the cap keeps 3: 0.4, 0.4, 0.1 (0.1 dropped)
    assert_allclose(dropped, 0.1)
    assert_allclose(p.comp_w, np.array([0.4, 0.4, 0.1]) / 0.9)
    sets = [p.comp_tracks[p.comp_off[h]:p.comp_off[h + 1]].tolist() for h in range(3)]
    assert sets == [[0, 1], [0], [1]]
    assert_array_equal(p.labels, [[0, 1], [0, 2]])


def test_empty_scene_and_empty_scans():
    f = ClusteredGLMBFilter(make_model("vo"), SHORT)
    rec = f.step([], rng=0)
    assert rec.n_meas == 0 and rec.labels.shape == (0, 2)
    # the four births that gate nothing: four clusters of one label
    assert rec.n_clusters == 4
    f.set_prior(np.empty((0, 2), np.int64), np.empty((0, 4)), np.empty((0, 4, 4)))
    assert f.n_clusters == 0
    rec = f.step(np.empty((0, 2)), rng=1)
    assert rec.n_clusters == 4 and rec.cardinality.sum() == pytest.approx(1.0)


def test_refused_options():
    with pytest.raises(ValueError, match=r"ClusteredGLMBFilter needs a gate \(gate_prob=None"):
        ClusteredGLMBFilter(make_model("vo"), SHORT, gate_prob=None)
    with pytest.raises(ValueError, match="ClusteredGLMBFilter keeps no whole association "
                                         "histories"):
        ClusteredGLMBFilter(make_model("vo"), SHORT, extraction="trajectory")
    with pytest.raises(ValueError, match="ClusteredGLMBFilter keeps no whole association "
                                         "histories"):
        ClusteredGLMBFilter(make_model("vo"), SHORT, keep_histories=True)
    with pytest.raises(ValueError, match="h_max must be a positive integer"):
        ClusteredGLMBFilter(make_model("vo"), SHORT, h_max=0)


def test_a_cluster_beyond_the_work_bound_is_refused_before_its_scan(monkeypatch):
    # every track gated to every measurement: one cluster of the 36 tracks, the birth at the
    # origin and 12 measurements, 37 * 12 * 64 = 28 416 bytes against a bound of 10 000
    monkeypatch.setattr(clustered_module, "CLUSTER_WORK_BYTES", 10_000)
    n = 36
    f = ClusteredGLMBFilter(make_model("vo"), SHORT)
    f.set_prior(np.column_stack([np.zeros(n, np.int64), np.arange(1, n + 1)]),
                np.zeros((n, 4)), np.tile(1e6 * np.eye(4), (n, 1, 1)))
    with pytest.raises(ValueError, match=r"a cluster of 37 labels \(37 Gaussian components\) "
                                         r"gates 12 measurements: its scan would need 27\.8 KiB "
                                         r"for its terms, above 9\.8 KiB \(CLUSTER_WORK_BYTES\)"):
        f.step(np.linspace(-500, 500, 24).reshape(12, 2), rng=0)


def test_the_runners_run_it():
    run = run_scenario("vo", Murty(10), rng=0, n_scans=4, filter=ClusteredGLMBFilter)
    assert run.n_estimated.tolist()[-1] >= 2
    with pytest.raises(ValueError, match="runs without grouping"):
        run_scenario("vo", Murty(10), rng=0, n_scans=2, filter=ClusteredGLMBFilter,
                     grouping=True)
    sc = make_scenario("vo", rng=0, n_scans=4)
    f = ClusteredGLMBFilter(sc.model, Murty(10))
    assert run_filter(f, [s.z for s in sc.scans], rng=0).n_estimated.tolist() == \
        run.n_estimated.tolist()


def test_small_cap_and_hysteresis_on_a_scene_with_merges():
    # h_max = 5: products of merging clusters are capped (the dropped mass is recorded) and no
    # cluster holds more than h_max components; hysteresis carries its memory across merges
    sc = make_scenario("vo", rng=3, n_scans=12)
    f = ClusteredGLMBFilter(sc.model, Murty(10), h_upd=5, h_max=5, extraction="hysteresis")
    recs = [f.step(s.z, rng=k) for k, s in enumerate(sc.scans)]
    assert all(c.n_components <= 5 for c in f.clusters)
    assert max(r.merge_dropped_mass for r in recs) > 0
    assert all(0 <= r.merge_dropped_mass < 1 for r in recs)
    assert {tuple(x) for x in recs[-1].labels.tolist()} >= {(1, 1), (1, 2), (1, 3)}
    for c in f.clusters:
        assert_allclose(c.comp_w.sum(), 1.0, rtol=1e-12)
        assert np.all(np.diff(c.comp_w) <= 0)  # heaviest first


def test_one_and_two_workers_give_the_same_numbers():
    sc = make_scenario("vo", rng=5, n_scans=6)
    one = ClusteredGLMBFilter(sc.model, SHORT, retained_mass=True)
    two = ClusteredGLMBFilter(sc.model, SHORT, retained_mass=True, workers=2)
    try:
        for k, s in enumerate(sc.scans):
            a = one.step(s.z, rng=k)
            b = two.step(s.z, rng=k)
            for name in ("labels", "states", "existence", "track_labels", "track_existence",
                         "cardinality", "cluster_sizes", "cluster_retained_mass"):
                assert_array_equal(getattr(a, name), getattr(b, name), err_msg=name)
            assert (a.sweeps, a.n_unique, a.retained_mass) == (b.sweeps, b.n_unique,
                                                               b.retained_mass)
    finally:
        two.close()
    with pytest.raises(ValueError, match="workers must be an int >= 1, got 0"):
        ClusteredGLMBFilter(sc.model, SHORT, workers=0)
    with pytest.raises(TypeError, match="workers must be an int, got float 1.5"):
        ClusteredGLMBFilter(sc.model, SHORT, workers=1.5)


def _one_place_bearing_range_model():
    """_one_place_model's motion and birth seen by a bearing-range sensor 1 km below."""
    return NonlinearModel(
        motion=LinearGaussianMotion.from_motion(ConstantVelocity(1.0, 5.0)),
        sensor=BearingRange(0.005, 10.0, sensor_position=(0.0, -1000.0), p_d=0.98,
                            state_ndim=4, position_indices=(0, 2)),
        clutter=BearingRangeClutter(5.0, (-np.pi, np.pi), (0.0, 3000.0)),
        birth=(GaussianBirth(0.03, np.zeros(4), 100.0 * np.eye(4)),), p_s=0.99,
        filter=ExtendedKalmanFilter())


def test_one_cluster_equals_the_glmb_filter_on_a_nonlinear_model():
    # a NonlinearModel: the EKF's prediction and update, the gate in (bearing, range)
    model = _one_place_bearing_range_model()
    f = ClusteredGLMBFilter(model, Murty(30), retained_mass=True)
    g = GLMBFilter(model, Murty(30), retained_mass=True)
    for k, xy in enumerate(_close_scans()):
        x = np.zeros((2, 4))
        x[:, [0, 2]] = xy
        z = model.sensor.h(x)
        a = f.step(z, rng=k)
        b = g.step(z, rng=k)
        assert a.n_clusters == 1 and a.n_splits == 0
        assert_array_equal(a.labels, b.labels)
        assert_array_equal(a.track_labels, b.track_labels)
        assert_allclose(a.states, b.states, rtol=1e-12, atol=1e-12)
        assert_allclose(a.track_existence, b.track_existence, rtol=1e-12, atol=1e-12)
        assert_allclose(a.cardinality, b.cardinality, rtol=1e-12, atol=1e-12)
        assert_allclose(a.retained_mass, b.retained_mass, rtol=1e-12)
    assert a.labels.shape[0] == 2


def test_a_bearing_range_large_scene():
    # make_scenario("large", sensor="bearing-range"): the clusters gate in (bearing, range)
    n = 150
    sc = make_scenario("large", n_targets=n, n_scans=3, rng=1, sensor="bearing-range")
    means = np.linalg.solve(sc.model.motion.F, sc.truth.states[0].T).T
    labels = np.column_stack([np.zeros(n, np.int64), np.arange(1, n + 1)])
    f = ClusteredGLMBFilter(sc.model, SHORT)
    f.set_prior(labels, means, np.tile(np.diag([100.0, 25.0, 100.0, 25.0]), (n, 1, 1)))
    for k, s in enumerate(sc.scans):
        rec = f.step(s.z, rng=k)
    prior = rec.labels[:, 0] == 0
    assert prior.sum() >= 0.97 * n and rec.n_clusters > 40
    est = rec.states[prior][:, [0, 2]]
    truth = sc.truth.states[-1][rec.labels[prior, 1] - 1][:, [0, 2]]
    assert np.median(np.linalg.norm(est - truth, axis=1)) < 10.0

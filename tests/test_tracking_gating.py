"""Tests of the spatial gate and the clusters (rankedassign.tracking.gating) and of the LMB
filter's cluster-by-cluster scan that uses them."""

import numpy as np
import pytest
from numpy.testing import assert_allclose, assert_array_equal

import rankedassign.tracking.single.lmb as lmb_module
from rankedassign.tracking import (
    LMBFilter,
    Murty,
    OriginalGibbs,
    ShortChainGibbs,
    _kernels,
    gate_threshold,
    group_tracks,
    make_model,
    make_scenario,
)
from rankedassign.tracking.birth import MeasurementBirth
from rankedassign.tracking.gating import (
    GatedPairs,
    candidate_pairs,
    clusters,
    dense_gate,
    gate_pairs,
    gate_radii,
    track_pairs,
)
from rankedassign.tracking.nonlinear import make_nonlinear_model
from rankedassign.tracking.nonlinear.step import SingleObject
from rankedassign.tracking.presets import large_bearing_range_model

GATE = gate_threshold(0.9999999)


def _random_scene(rng, T, M, spread=500.0):
    """Tracks of 1-3 components with random SPD covariances; half the measurements near a
    component (so many pairs sit near the gate's edge), the rest uniform."""
    nc = rng.integers(1, 4, T)
    offsets = np.r_[0, np.cumsum(nc)].astype(np.int64)
    C = int(offsets[-1])
    m = rng.uniform(-spread, spread, (C, 4))
    A = rng.normal(0, 30, (C, 4, 4))
    P = np.ascontiguousarray(A @ A.transpose(0, 2, 1) + np.eye(4))
    R = np.diag([100.0, 100.0])
    z = rng.uniform(-spread, spread, (M, 2))
    k = min(M // 2, C)
    if k:
        z[:k] = m[:k][:, [0, 2]] + rng.normal(0, 40, (k, 2))
    return m, P, R, np.ascontiguousarray(z), offsets


@pytest.mark.parametrize("seed", range(40))
def test_gate_pairs_equal_the_dense_gate(seed):
    rng = np.random.default_rng(seed)
    T, M = int(rng.integers(0, 25)), int(rng.integers(0, 40))
    m, P, R, z, offsets = _random_scene(rng, T, M)
    gate = float(rng.choice([GATE, 9.21, 1000.0]))
    dense = _kernels.gate_and_distances(m, P, R, z, offsets, gate, True)[4]
    pairs = gate_pairs(m, P, R, z, offsets, gate)
    assert_array_equal(dense_gate(pairs), dense)
    assert pairs.n_candidates >= pairs.track.size
    # clusters: the partition and numbering of the dense kernel
    tg, mg, n = _kernels.connected_groups(dense)
    cl = clusters(pairs)
    assert cl.n_clusters == n
    assert_array_equal(cl.track_cluster, tg)
    assert_array_equal(cl.meas_cluster, mg)
    expected = [(np.flatnonzero(tg == g), np.flatnonzero(mg == g)) for g in range(n)]
    got = group_tracks(dense)
    assert len(got) == len(expected)
    for (r, c), (r2, c2) in zip(got, expected, strict=True):
        assert_array_equal(r, r2)
        assert_array_equal(c, c2)


def test_gate_radius_bounds_the_ellipse():
    # S = diag(4, 1) + R = 0: the gate's ellipse has semi-axes sqrt(9 * 4) and sqrt(9 * 1)
    P = np.zeros((1, 4, 4))
    P[0, 0, 0], P[0, 2, 2] = 4.0, 1.0
    r = gate_radii(P, np.zeros((2, 2)), 9.0)
    assert_allclose(r, [6.0], rtol=1e-5)
    # a covariance that is not positive definite: every measurement is a candidate
    bad = np.zeros((1, 4, 4))
    bad[0, 0, 0] = -1.0
    assert gate_radii(bad, np.zeros((2, 2)), 9.0)[0] == np.inf
    c, j = candidate_pairs(np.zeros((1, 2)), np.array([np.inf]), np.ones((3, 2)))
    assert_array_equal(j, [0, 1, 2])


def test_empty_inputs():
    pairs = gate_pairs(np.empty((0, 4)), np.empty((0, 4, 4)), np.eye(2), np.empty((0, 2)),
                       np.zeros(1, np.int64), GATE)
    assert pairs.track.size == 0 and pairs.n_tracks == 0
    cl = clusters(pairs)
    assert cl.n_clusters == 0 and cl.groups() == []
    cl = clusters(GatedPairs(np.empty(0, np.int64), np.empty(0, np.int64), 2, 3, 0))
    assert_array_equal(cl.track_cluster, [0, 1])
    assert_array_equal(cl.meas_cluster, [-1, -1, -1])


def _run(monkeypatch, threshold, association, scenario, batch=4096, **kw):
    monkeypatch.setattr(lmb_module, "SPATIAL_MIN_PAIRS", threshold)
    monkeypatch.setattr(lmb_module, "SPATIAL_BATCH_PAIRS", batch)
    f = LMBFilter(scenario.model, association, grouping=True, **kw)
    return [f.step(s.z, rng=k) for k, s in enumerate(scenario.scans)]


@pytest.mark.parametrize("batch", [0, 4096], ids=["cluster-by-cluster", "batched"])
@pytest.mark.parametrize("association", [Murty(20), ShortChainGibbs(50, 5, tau_stall=5,
                                                                      tau_stale=10)])
def test_lmb_spatial_scan_equals_the_dense_scan(monkeypatch, association, batch):
    sc = make_scenario("vo", rng=3, n_scans=15)
    dense = _run(monkeypatch, 1 << 62, association, sc)
    spatial = _run(monkeypatch, 0, association, sc, batch=batch)
    for a, b in zip(dense, spatial, strict=True):
        assert_array_equal(a.track_labels, b.track_labels)
        assert_array_equal(a.labels, b.labels)
        # the same problems and streams: the same counts
        assert (a.n_groups, a.n_meas_gated, a.sweeps, a.row_updates, a.n_unique) == \
            (b.n_groups, b.n_meas_gated, b.sweeps, b.row_updates, b.n_unique)
        # r = Σ_j β_ij over the cluster's columns instead of every gated column: rounding only
        assert_allclose(b.track_existence, a.track_existence, rtol=1e-12, atol=1e-15)
        assert_allclose(b.states, a.states, rtol=1e-12, atol=1e-9)


@pytest.mark.parametrize("association", [
    ShortChainGibbs(50, 5, tau_stall=5, tau_stale=10),
    ShortChainGibbs(20, 4, tau_stall=2, tau_stale=3, scan="random"),
    ShortChainGibbs(6, 3),
    OriginalGibbs(30),
], ids=["short-chains", "random-scan", "no-rules", "original"])
def test_lmb_compiled_chains_equal_one_call_per_cluster(monkeypatch, association):
    # the cluster path runs the chains of a batch's clusters in one compiled call; holding it
    # to one call of the association per cluster (the filter without the plan): the same
    # records, bit for bit
    monkeypatch.setattr(lmb_module, "SPATIAL_MIN_PAIRS", 0)
    sc = make_scenario("vo", rng=5, n_scans=12)
    batched = LMBFilter(sc.model, association, grouping=True)
    assert batched._chain_batch is not None
    per_call = LMBFilter(sc.model, association, grouping=True)
    per_call._chain_batch = None
    for k, s in enumerate(sc.scans):
        a, b = batched.step(s.z, rng=k), per_call.step(s.z, rng=k)
        for name in ("labels", "states", "existence", "track_labels", "track_existence"):
            assert_array_equal(getattr(a, name), getattr(b, name))
        assert a[5:13] == b[5:13]  # the counts: problems, sweeps, row updates, unique
    assert_array_equal(batched.w, per_call.w)
    assert_array_equal(batched.P, per_call.P)


def test_lmb_chain_plan_only_for_truncated_marginals():
    # Rao-Blackwellised marginals are not the chains' truncated ones: one call per problem
    model = make_model("vo")
    assert LMBFilter(model, ShortChainGibbs(5, 5, marginals="rao-blackwell"))._chain_batch \
        is None
    assert LMBFilter(model, Murty(5))._chain_batch is None
    assert LMBFilter(model, ShortChainGibbs(5, 5, start="lsap"))._chain_batch is None


@pytest.mark.parametrize("association", [Murty(20), ShortChainGibbs(50, 5, tau_stall=5,
                                                                      tau_stale=10)])
def test_lmb_spatial_scan_with_measurement_birth(monkeypatch, association):
    # the birth reads r_A(z_j) = Σ_i β_ij of every measurement: the cluster path gathers it
    # per cluster (0 for a measurement no track gates) and gives the dense path's filter
    sc = make_scenario("vo", rng=6, n_scans=15)
    birth = MeasurementBirth(lambda_b=0.2, r_max=0.05)
    dense = _run(monkeypatch, 1 << 62, association, sc, birth=birth)
    spatial = _run(monkeypatch, 0, association, sc, birth=birth)
    assert max(len(r.labels) for r in dense) >= 2  # tracks are born from measurements
    for a, b in zip(dense, spatial, strict=True):
        assert_array_equal(a.track_labels, b.track_labels)
        assert_array_equal(a.labels, b.labels)
        assert (a.n_tracks, a.n_groups, a.sweeps, a.n_unique) == \
            (b.n_tracks, b.n_groups, b.sweeps, b.n_unique)
        assert_allclose(b.track_existence, a.track_existence, rtol=1e-12, atol=1e-15)
        assert_allclose(b.states, a.states, rtol=1e-12, atol=1e-9)


def test_lmb_spatial_scan_with_sample_empty_groups(monkeypatch):
    sc = make_scenario("vo", rng=4, n_scans=6)
    dense = _run(monkeypatch, 1 << 62, Murty(10), sc, sample_empty_groups=True)
    spatial = _run(monkeypatch, 0, Murty(10), sc, sample_empty_groups=True)
    for a, b in zip(dense, spatial, strict=True):
        assert_array_equal(a.track_labels, b.track_labels)
        assert a.invocations == b.invocations
        assert_allclose(b.track_existence, a.track_existence, rtol=1e-12, atol=1e-15)


def test_lmb_spatial_scan_without_measurements(monkeypatch):
    monkeypatch.setattr(lmb_module, "SPATIAL_MIN_PAIRS", 0)
    f = LMBFilter(make_model("vo"), Murty(5), grouping=True)
    rec = f.step([], rng=0)
    assert rec.n_meas == 0 and rec.n_groups == 0 and rec.n_tracks == 4


def test_lmb_set_prior():
    f = LMBFilter(make_model("vo"), Murty(5))
    f.set_prior([[0, 1], [0, 2]], np.zeros((2, 4)), np.tile(np.eye(4), (2, 1, 1)),
                existence=[0.95, 0.5])
    assert f.n_tracks == 2
    assert_array_equal(f.confirmed, [True, False])
    with pytest.raises(ValueError, match=r"existence must be 2 probabilities in \(0, 1\], "
                                         r"got \[0.5, 1.5\]"):
        f.set_prior([[0, 1], [0, 2]], np.zeros((2, 4)), np.tile(np.eye(4), (2, 1, 1)),
                    existence=[0.5, 1.5])
    with pytest.raises(ValueError, match="existence must be 2 probabilities"):
        f.set_prior([[0, 1], [0, 2]], np.zeros((2, 4)), np.tile(np.eye(4), (2, 1, 1)),
                    existence=[0.5])


@pytest.mark.parametrize("seed", range(12))
@pytest.mark.parametrize("preset", ["large-ekf", "vo-ekf", "vo-ukf"])
def test_sensor_gate_pairs_equal_the_dense_gate(preset, seed):
    # bearing-range gates through a k-d tree in (bearing, range), the bearing periodic: the
    # pairs are those of the dense gate of measurement_terms, exactly, also where a gate
    # straddles the bearing ±π (components and measurements straight below the sensor)
    rng = np.random.default_rng(seed)
    model = (large_bearing_range_model(400) if preset == "large-ekf"
             else make_nonlinear_model(preset))
    so = SingleObject(model)
    d = so.ndim
    sx, sy = model.sensor.sensor_position
    nc = rng.integers(1, 4, 30)
    offsets = np.r_[0, np.cumsum(nc)].astype(np.int64)
    C = int(offsets[-1])
    m = np.zeros((C, d))
    rho = rng.uniform(200.0, 2000.0, C)
    theta = np.pi + rng.normal(0.0, 0.3, C)  # around the ±π cut
    m[:, 0], m[:, 2] = sx + rho * np.sin(theta), sy + rho * np.cos(theta)
    A = rng.normal(0, 5, (C, d, d))
    P = np.ascontiguousarray(A @ A.transpose(0, 2, 1) + np.diag([100.0, 1, 100, 1, 1e-4][:d]))
    zb = np.pi - np.mod(np.pi - (np.pi + rng.normal(0.0, 0.3, 80)), 2 * np.pi)
    z = np.column_stack([zb, rng.uniform(200.0, 2000.0, 80)])
    # half the measurements near a component, across the cut
    pred = so.filter.predict_measurement(so.sensor, m, P)
    k = rng.choice(C, 40)
    z[:40] = pred.z[k] + rng.normal(0, 3, (40, 2)) * np.sqrt(np.diag(model.sensor.R))
    z[:40, 0] = np.pi - np.mod(np.pi - z[:40, 0], 2 * np.pi)
    gate = GATE
    dense = so.measurement_terms(m, P, z, offsets, gate).gated
    pairs = so.gate_pairs(m, P, z, offsets, gate)
    assert dense.sum() > 20
    assert_array_equal(dense_gate(pairs), dense)
    assert pairs.n_candidates < C * z.shape[0]
    # some gated pairs straddle the cut: raw bearing difference above π
    t = np.repeat(np.arange(30), nc)
    wraps = np.abs(z[None, :, 0] - pred.z[:, None, 0]) > np.pi
    assert (wraps & so.measurement_terms(m, P, z, offsets, gate).gated[t]).any()


def test_track_pairs():
    g = track_pairs(np.empty(0, np.int64), np.empty(0, np.int64), np.array([0, 1, 3]), 4, 0)
    assert g.track.size == 0 and (g.n_tracks, g.n_meas) == (2, 4)


def test_lmb_cluster_path_on_a_bearing_range_large_scene(monkeypatch):
    # make_scenario("large", sensor="bearing-range"): the cluster path gates in (bearing,
    # range) and gives the dense path's filter
    n = 300
    sc = make_scenario("large", n_targets=n, n_scans=3, rng=2, sensor="bearing-range")
    F = sc.model.motion.F
    means = np.linalg.solve(F, sc.truth.states[0].T).T
    labels = np.column_stack([np.zeros(n, np.int64), np.arange(1, n + 1)])
    covs = np.tile(np.diag([100.0, 25.0, 100.0, 25.0]), (n, 1, 1))
    out = []
    for threshold in (1 << 62, 0):
        monkeypatch.setattr(lmb_module, "SPATIAL_MIN_PAIRS", threshold)
        f = LMBFilter(sc.model, ShortChainGibbs(50, 5, tau_stall=5, tau_stale=10),
                      grouping=True, max_tracks=3000)
        f.set_prior(labels, means, covs, existence=np.full(n, 0.99))
        out.append([f.step(s.z, rng=k) for k, s in enumerate(sc.scans)])
    for a, b in zip(*out, strict=True):
        assert_array_equal(a.track_labels, b.track_labels)
        assert (a.n_groups, a.n_meas_gated, a.sweeps, a.n_unique) == \
            (b.n_groups, b.n_meas_gated, b.sweeps, b.n_unique)
        assert_allclose(b.track_existence, a.track_existence, rtol=1e-12, atol=1e-15)
        assert_allclose(b.states, a.states, rtol=1e-12, atol=1e-9)
    rec = out[1][-1]
    prior = rec.labels[:, 0] == 0
    assert prior.sum() >= 0.97 * n
    est = rec.states[prior][:, [0, 2]]
    truth = sc.truth.states[-1][rec.labels[prior, 1] - 1][:, [0, 2]]
    assert np.median(np.linalg.norm(est - truth, axis=1)) < 10.0

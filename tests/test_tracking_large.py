"""Tests of the ``"large"`` scenario (make_scenario("large", n_targets=N)) and of the filters
on it at small N: its density, its refused inputs, and N = 0."""

import numpy as np
import pytest
from numpy.testing import assert_allclose

from rankedassign.tracking import (
    ClusteredGLMBFilter,
    LMBFilter,
    Murty,
    make_model,
    make_scenario,
)
from rankedassign.tracking.nonlinear import BearingRange, NonlinearModel
from rankedassign.tracking.presets import LARGE_SIGMA_BEARING
from rankedassign.tracking.scenario import LARGE_CELL, large_model


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

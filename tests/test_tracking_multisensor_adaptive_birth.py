"""Adaptive birth in the multi-sensor LMB filter (multi-sensor spec §4, §7.2, §7.4)."""

import numpy as np
import pytest
from numpy.testing import assert_allclose, assert_array_equal

import oracle
from rankedassign.tracking import (
    AdaptiveBirth,
    Exact,
    MultiSensorLMBFilter,
    MultiSensorModel,
    ShortChainGibbs,
    make_model,
    make_multisensor_model,
    make_multisensor_scenario,
    run_multisensor_scenario,
)
from rankedassign.tracking.multisensor.adaptive_birth import empty_birth

SMALL = dict(n_chains=10, chain_length=10)


# ------------------------------------------------------------------ settings
@pytest.mark.parametrize("kwargs, exc, match", [
    (dict(tau_rU=1.5), ValueError, r"tau_rU must be <= 1.0, got 1.5"),
    (dict(tau_rU="a"), TypeError, r"tau_rU must be a real number, got str 'a'"),
    (dict(n_min=0), ValueError, r"n_min must be an int >= 1, got 0"),
    (dict(n_min=1.5), TypeError, r"n_min must be an int, got float 1.5"),
    (dict(r_b_max=0.0), ValueError, r"r_b_max must be > 0.0, got 0.0"),
    (dict(r_b_max=1.5), ValueError, r"r_b_max must be <= 1.0, got 1.5"),
    (dict(lambda_b=0), ValueError, r"lambda_b must be > 0.0, got 0.0"),
    (dict(max_births=0), ValueError, r"max_births must be an int >= 1, got 0"),
    (dict(sampler="x"), ValueError, r"unknown sampler 'x'; expected one of \('short', 'long'\)"),
    (dict(n_chains=0), ValueError, r"n_chains must be an int >= 1, got 0"),
    (dict(chain_length=0), ValueError, r"chain_length must be an int >= 1, got 0"),
    (dict(tau_stall=0), ValueError, r"tau_stall must be None \(off\) or an int >= 1, got 0"),
    (dict(tau_stale=0), ValueError, r"tau_stale must be None \(off\) or an int >= 1, got 0"),
    (dict(sensor_order="x"), ValueError, r"unknown sensor_order 'x'"),
    (dict(backend="x"), ValueError, r"unknown backend 'x'"),
    (dict(mu0=[0, 0]), ValueError, r"mu0 must be a finite array of shape \(4,\), got \[0.0, 0.0\]"),
    (dict(mu0=[0, 0, 0, np.nan]), ValueError, r"mu0 must be a finite array of shape \(4,\)"),
    (dict(mu0="ab"), TypeError, r"mu0 must be a numeric array of shape \(4,\), got 'ab'"),
    (dict(P0="x"), TypeError, r"P0 must be a numeric array of shape \(4, 4\), got 'x'"),
    (dict(P0=np.eye(3)), ValueError, r"P0 must be a finite array of shape \(4, 4\), got shape "
                                     r"\(3, 3\)"),
    (dict(P0=np.eye(4) + np.eye(4, k=1)), ValueError, r"P0 must be symmetric"),
    (dict(P0=-np.eye(4)), ValueError, r"P0 must be positive definite"),
])
def test_settings_are_validated(kwargs, exc, match):
    with pytest.raises(exc, match=match):
        AdaptiveBirth(**kwargs)


def test_defaults_are_those_of_spec_7_2():
    ab = AdaptiveBirth()
    assert ab.mu0 == (0.0, 0.0, 0.0, 0.0)
    assert_array_equal(np.array(ab.P0), np.diag([1000.0**2, 50.0**2, 1000.0**2, 50.0**2]))
    assert (ab.tau_rU, ab.n_min, ab.r_b_max, ab.lambda_b) == (0.9, 2, 0.03, 1.0)
    assert (ab.sampler, ab.sensor_order) == ("short", "random")
    # normalised and hashable: equal settings compare equal
    assert AdaptiveBirth(mu0=np.zeros(4), P0=np.array(ab.P0)) == ab
    assert hash(AdaptiveBirth()) == hash(ab)


def test_filter_and_runner_validate_birth():
    with pytest.raises(TypeError, match=r"birth must be an AdaptiveBirth, got str; None for the "
                                        r"model's static birth or AdaptiveBirth\(\.\.\.\)"):
        MultiSensorLMBFilter(make_multisensor_model(), ShortChainGibbs(10, 5, method="exact"),
                             birth="adaptive")
    with pytest.raises(ValueError, match=r"unknown birth 'wide'; expected one of "
                                         r"\('paper', 'narrow', 'adaptive'\)"):
        run_multisensor_scenario(ShortChainGibbs(10, 5, method="exact"), rng=0, n_scans=1,
                                 birth="wide")
    with pytest.raises(ValueError, match=r"n_sensors must be an int >= 1, got 0"):
        AdaptiveBirth().effective_n_min(0)


# ------------------------------------------------------------------ births of one scan
def test_births_from_a_consistent_pair_and_nothing_from_far_apart_points():
    m = make_multisensor_model((0, 1))
    kw = dict(sensors=m.sensors, clutters=m.clutters, F=m.motion.F, Q=m.motion.Q, rng=3)
    z = [np.array([[100.0, 200.0]]), np.array([[110.0, 195.0]])]
    b = AdaptiveBirth().births(z, [np.ones(1), np.ones(1)], **kw)
    assert b.measurements.tolist() == [[0, 0]] and b.r.tolist() == [0.03]
    # predicted one scan ahead: position within a few metres, the prior's velocity spread
    assert_allclose(b.means[0, [0, 2]], [104.0, 198.0], atol=5.0)
    assert b.covs[0, 1, 1] > 40.0**2
    # 1 km apart: the pair's rho is negligible and drops below prune_track
    far = [np.array([[100.0, 200.0]]), np.array([[900.0, -700.0]])]
    assert AdaptiveBirth().births(far, [np.ones(1), np.ones(1)], r_min=1e-3, **kw).r.size == 0
    # explained measurements (r_U <= tau_rU) make no birth
    assert AdaptiveBirth().births(z, [np.ones(1), np.array([0.9])], **kw).r.size == 0


def test_one_sensor_births_from_single_measurements():
    # n_min = 2 cannot be met by V = 1: the filter uses min(n_min, V) = 1
    m = make_multisensor_model((0,))
    z = [np.array([[0.0, 0.0], [500.0, 500.0], [-300.0, 100.0]])]
    b = AdaptiveBirth().births(z, [np.array([1.0, 1.0, 0.2])], sensors=m.sensors,
                               clutters=m.clutters, F=m.motion.F, Q=m.motion.Q, rng=0)
    assert sorted(b.measurements[:, 0].tolist()) == [0, 1]
    assert_allclose(b.r, 0.03)
    assert AdaptiveBirth(n_min=3).effective_n_min(1) == 1
    assert AdaptiveBirth(n_min=3).effective_n_min(2) == 2
    assert AdaptiveBirth().effective_n_min(4) == 2


def test_max_births_keeps_the_largest_rho():
    m = make_multisensor_model((0, 1))
    rng = np.random.default_rng(1)
    pts = rng.uniform(-900, 900, (6, 2))
    z = [pts + rng.normal(0, 5, pts.shape), pts + rng.normal(0, 5, pts.shape)]
    kw = dict(sensors=m.sensors, clutters=m.clutters, F=m.motion.F, Q=m.motion.Q, rng=2)
    r_U = [np.ones(6), np.ones(6)]
    full = AdaptiveBirth().births(z, r_U, **kw)
    capped = AdaptiveBirth(max_births=2).births(z, r_U, **kw)
    assert full.r.size > 2 and capped.r.size == 2
    top = np.sort(full.log_rho)[-2:]
    assert_allclose(np.sort(capped.log_rho), top)


def test_sampler_choices_and_backends_give_births():
    m = make_multisensor_model((0, 1))
    z = [np.array([[100.0, 200.0], [-600.0, 300.0]]), np.array([[110.0, 195.0]])]
    kw = dict(sensors=m.sensors, clutters=m.clutters, F=m.motion.F, Q=m.motion.Q, rng=7)
    r_U = [np.ones(2), np.ones(1)]
    a = AdaptiveBirth(**SMALL).births(z, r_U, **kw)
    b = AdaptiveBirth(**SMALL, backend="python").births(z, r_U, **kw)
    for x, y in zip(a, b, strict=True):
        assert_array_equal(x, y)
    c = AdaptiveBirth(sampler="long", n_chains=5, chain_length=20).births(z, r_U, **kw)
    assert c.measurements.tolist() == [[0, 0]]
    assert empty_birth().r.shape == (0,)


# ------------------------------------------------------------------ r_A from the marginals
def test_r_A_sums_the_exact_marginals_of_the_joint_update():
    # Two targets 40 m apart seen by two sensors, and one clutter point per sensor in opposite
    # corners. Scan 1 (no track) births from the pairs; at scan 2 the births share the gated
    # measurements: one group with both sensors' two near points, the far points in no gate.
    base = make_model("vo")
    ms = MultiSensorModel(base.motion, (base.sensor, base.sensor), (base.clutter, base.clutter),
                          base.birth, base.survival)
    problems = []

    def exact(problem, rng):
        problems.append(problem)
        return Exact()(problem, rng)

    f = MultiSensorLMBFilter(ms, exact, birth=AdaptiveBirth())
    near = np.array([[100.0, 100.0], [140.0, 100.0]])
    far = np.array([[-900.0, 900.0]])
    z1 = [np.vstack([near, far]), np.vstack([near + 2.0, -far])]
    rec = f.step(z1, rng=0)
    assert rec.n_tracks == 0 and not problems
    assert [r.tolist() for r in f.r_U] == [[1.0, 1.0, 1.0], [1.0, 1.0, 1.0]]  # no track yet
    assert f.n_births == 0
    z2 = [np.vstack([near + [0.0, 3.0], far + 50.0]), np.vstack([near + [1.0, 2.0],
                                                                 -far - 40.0])]
    f.step(z2, rng=1)
    assert f.n_births >= 2
    assert len(problems) == 1
    p = problems[0]
    assert p.log_eta_alive.shape[1:] == (3, 3)  # the two near points of each sensor
    ex = oracle.marginals(p)
    for v in range(2):
        # r_A^(v)(j) = Σ_n P(row n takes measurement j of sensor v)
        r_A = ex.sensors[v][:, :2].sum(axis=0)
        assert_allclose(f.r_U[v][:2], np.clip(1.0 - r_A, 0.0, 1.0), atol=1e-12)
        assert f.r_U[v][2] == 1.0  # in no gate
        assert (r_A > 0.5).all()


# ------------------------------------------------------------------ the filter
def test_adaptive_birth_replaces_the_static_birth():
    m = make_multisensor_model((0, 1))  # the paper's static birth, not used
    f = MultiSensorLMBFilter(m, ShortChainGibbs(10, 5, method="exact"), birth=AdaptiveBirth(**SMALL))
    rec = f.step([np.empty((0, 2)), np.empty((0, 2))], rng=0)
    assert rec.n_tracks == 0 and f.n_births == 0
    f.reset()
    assert f.n_births == 0 and f.r_U is None and f.k == 0
    static = MultiSensorLMBFilter(m, ShortChainGibbs(10, 5, method="exact"))
    static.step([np.empty((0, 2)), np.empty((0, 2))], rng=0)
    assert static.n_births == 4 and static.r_U is None
    assert make_multisensor_model(birth="adaptive").birth.components == ()


def test_same_rng_same_run_and_backends_agree():
    def run(backend, seed):
        return run_multisensor_scenario(
            ShortChainGibbs(30, 8, tau_stall=3, tau_stale=5, method="exact"), rng=seed, n_scans=5, sensors=(0, 1),
            birth=AdaptiveBirth(**SMALL, backend=backend))

    a, b, c = run("numba", 4), run("numba", 4), run("python", 4)
    for other in (b, c):
        assert_array_equal(other.n_births, a.n_births)
        assert other.existence == a.existence
        assert_array_equal(other.estimates, a.estimates)
    assert a.n_births.sum() > 0
    d = run("numba", 5)
    assert d.existence != a.existence


def test_short_run_starts_tracks_on_the_targets_without_static_birth():
    run = run_multisensor_scenario(ShortChainGibbs(400, 25, tau_stall=5, tau_stale=10, method="exact"), rng=0, n_scans=15,
                                   sensors=(0, 1), birth="adaptive")
    assert run.scenario.model.birth.components == ()
    assert run.n_births[0] == 0 and run.n_births[1] >= 1  # from the targets of scan 1
    # births per scan stay bounded (20 clutter points per sensor and scan; measured 3-16)
    assert run.n_births.max() <= 40
    assert (run.timings["birth"][1:] > 0).all()
    # the three targets born at scan 1 are each within 50 m of an estimate on scans 8-15
    truth = run.truth[7:]
    alive = ~np.isnan(truth[:, :, 0])
    assert alive.sum(axis=1).tolist() == [3] * 8
    for k in range(truth.shape[0]):
        est = run.estimates[7 + k]
        est = est[~np.isnan(est[:, 0])]
        for x in truth[k][alive[k]]:
            assert np.min(np.linalg.norm(est - x, axis=1)) < 50.0
    # every confirmed track was born adaptively (label scan >= 2)
    labels = {lab for scan in run.labelled_estimates for lab in scan}
    assert labels and min(lab[0] for lab in labels) >= 2


def test_one_sensor_filter_runs_with_adaptive_birth():
    run = run_multisensor_scenario(ShortChainGibbs(50, 10, tau_stall=5, tau_stale=10, method="exact"), rng=0, n_scans=4,
                                   sensors=(0,), birth=AdaptiveBirth(**SMALL))
    # every unexplained measurement of the single sensor is a candidate (n_min = min(2, 1))
    assert run.n_births[1] >= 10


def test_scenario_measurements_do_not_depend_on_the_birth():
    a = make_multisensor_scenario(rng=2, n_scans=2, sensors=(0,), birth="adaptive")
    b = make_multisensor_scenario(rng=2, n_scans=2, sensors=(0,))
    assert_array_equal(a.scans[1][0].z, b.scans[1][0].z)

"""Measurement-driven birth (rankedassign.tracking.birth) and its use by the single-sensor
LMB and δ-GLMB filters."""

import numpy as np
import pytest

from rankedassign.metrics import ospa
from rankedassign.tracking import (
    Exact,
    GLMBFilter,
    LMBFilter,
    MeasurementBirth,
    Murty,
    ShortChainGibbs,
    make_model,
)
from rankedassign.tracking.birth import BirthComponents, birth_existence
from rankedassign.tracking.scenario import Truth, generate_measurements, paper_truth

H = np.array([[1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0]])


# ----------------------------------------------------------------------------- equations
def test_existence_by_hand():
    # r_U = 1 - r_A = (1, 0.5, 0.25, 0); Σ r_U = 1.75; λ_B = 0.7 -> r_U / 1.75 * 0.7 = 0.4 r_U
    r = birth_existence([0.0, 0.5, 0.75, 1.0], lambda_b=0.7, r_max=0.3)
    np.testing.assert_allclose(r, [0.3, 0.2, 0.1, 0.0], rtol=0, atol=1e-15)


def test_existence_clips_r_A_and_handles_all_explained():
    # sums of marginals a hair above 1 count as 1; nothing unexplained: nothing is born
    assert birth_existence([1.0 + 1e-12, 1.0], 1.0, 1.0).tolist() == [0.0, 0.0]
    assert birth_existence(np.zeros(0), 1.0, 1.0).shape == (0,)
    # a single unexplained measurement takes all of λ_B, up to the cap
    assert birth_existence([0.0], 0.05, 0.5).tolist() == [0.05]


def test_births_by_hand():
    R = np.array([[4.0, 1.0], [1.0, 9.0]])
    vcov = np.array([[2.0, 0.5], [0.5, 3.0]])
    b = MeasurementBirth(lambda_b=0.5, r_max=0.3, velocity_mean=(1.0, -2.0),
                         velocity_cov=vcov, r_min=0.0)
    out = b.births([[10.0, 20.0], [30.0, 40.0], [50.0, 60.0]], [0.0, 0.6, 1.0], H=H, R=R)
    # r_U = (1, 0.4, 0): r_B = (min(0.3, 1/1.4 · 0.5 = 0.357), 0.4/1.4 · 0.5 = 0.143); the
    # third (r_B = 0) is dropped
    np.testing.assert_allclose(out.r, [0.3, 0.4 / 1.4 * 0.5], rtol=1e-15)
    assert out.measurements.tolist() == [0, 1]
    # m_B = Hᵀ z + U μ_u
    assert out.means.tolist() == [[10.0, 1.0, 20.0, -2.0], [30.0, 1.0, 40.0, -2.0]]
    # P_B = Hᵀ R H + U P_u Uᵀ: R on (p_x, p_y), the velocity prior on (v_x, v_y)
    P = np.array([[4.0, 0.0, 1.0, 0.0],
                  [0.0, 2.0, 0.0, 0.5],
                  [1.0, 0.0, 9.0, 0.0],
                  [0.0, 0.5, 0.0, 3.0]])
    np.testing.assert_array_equal(out.covs, np.stack([P, P]))


def test_births_drop_below_r_min_and_cap():
    b = MeasurementBirth(lambda_b=1.0, r_max=1.0, r_min=0.15, max_births=2)
    out = b.births(np.arange(10.0).reshape(5, 2), [0.0, 0.0, 0.5, 0.9, 0.0], H=H, R=np.eye(2))
    # r_B = r_U / 3.6 = (0.278, 0.278, 0.139, 0.028, 0.278): three above r_min, the two
    # largest (ties: first) kept, in measurement order
    assert out.measurements.tolist() == [0, 1]
    assert out.r.shape == (2,) and out.means.shape == (2, 4) and out.covs.shape == (2, 4, 4)


def test_births_of_an_empty_scan():
    out = MeasurementBirth().births(np.zeros((0, 2)), np.zeros(0), H=H, R=np.eye(2))
    assert isinstance(out, BirthComponents)
    assert out.r.shape == (0,) and out.means.shape == (0, 4) and out.covs.shape == (0, 4, 4)


def test_a_scalar_prior_is_shared_by_every_unmeasured_component():
    out = MeasurementBirth(velocity_mean=3.0, velocity_cov=25.0).births(
        [[0.0, 0.0]], [0.0], H=H, R=np.eye(2))
    assert out.means[0].tolist() == [0.0, 3.0, 0.0, 3.0]
    assert np.diag(out.covs[0]).tolist() == [1.0, 25.0, 1.0, 25.0]


# ----------------------------------------------------------------------------- bad input
@pytest.mark.parametrize("value, match", [
    (0.0, "lambda_b must be > 0.0, got 0.0"),
    (-1.0, "lambda_b must be > 0.0, got -1.0"),
    (float("nan"), "lambda_b must be a finite real number, got nan"),
    (float("inf"), "lambda_b must be a finite real number, got inf"),
])
def test_bad_lambda_b(value, match):
    with pytest.raises(ValueError, match=match):
        MeasurementBirth(lambda_b=value)


def test_bad_settings():
    with pytest.raises(TypeError, match="lambda_b must be a real number, got bool True"):
        MeasurementBirth(lambda_b=True)
    with pytest.raises(ValueError, match=r"r_max must be <= 1.0, got 1.5"):
        MeasurementBirth(r_max=1.5)
    with pytest.raises(ValueError, match=r"r_max must be > 0.0, got 0.0"):
        MeasurementBirth(r_max=0.0)
    with pytest.raises(ValueError, match=r"r_min must be <= 0.1, got 0.2"):
        MeasurementBirth(r_min=0.2)
    with pytest.raises(ValueError, match="max_births must be >= 1, got 0"):
        MeasurementBirth(max_births=0)
    with pytest.raises(TypeError, match="max_births must be an int or None, got 2.0"):
        MeasurementBirth(max_births=2.0)
    with pytest.raises(TypeError, match="velocity_cov must be a number or a numeric array"):
        MeasurementBirth(velocity_cov="big")
    with pytest.raises(ValueError, match=r"velocity_mean must be finite, got \[0.0, nan\]"):
        MeasurementBirth(velocity_mean=[0.0, float("nan")])


@pytest.mark.parametrize("options, match", [
    ({"velocity_mean": (0.0, 0.0, 0.0)},
     r"velocity_mean must have shape \(2,\) for the 2 unmeasured state components of this "
     r"sensor, got shape \(3,\)"),
    ({"velocity_cov": np.eye(3)},
     r"velocity_cov must have shape \(2, 2\) for the 2 unmeasured state components of this "
     r"sensor, got shape \(3, 3\)"),
    ({"velocity_cov": [[1.0, 2.0], [0.0, 1.0]]}, "velocity_cov must be symmetric"),
    ({"velocity_cov": [[1.0, 2.0], [2.0, 1.0]]}, "velocity_cov must be positive definite"),
])
def test_prior_of_the_wrong_dimension_or_not_a_covariance(options, match):
    with pytest.raises(ValueError, match=match):
        MeasurementBirth(**options).births([[0.0, 0.0]], [0.0], H=H, R=np.eye(2))


def test_births_refuse_what_is_not_a_position_sensor():
    with pytest.raises(ValueError, match="measurement birth needs a position sensor"):
        MeasurementBirth().births([[0.0, 0.0]], [0.0], H=0.5 * H, R=np.eye(2))
    with pytest.raises(ValueError, match=r"R must have shape \(2, 2\), got \(3, 3\)"):
        MeasurementBirth().births([[0.0, 0.0]], [0.0], H=H, R=np.eye(3))
    with pytest.raises(ValueError, match="r_A has 2 entries for 1 measurements"):
        MeasurementBirth().births([[0.0, 0.0]], [0.0, 0.0], H=H, R=np.eye(2))
    with pytest.raises(ValueError, match="r_A holds NaN"):
        birth_existence([np.nan], 1.0, 1.0)


@pytest.mark.parametrize("cls", [LMBFilter, GLMBFilter])
def test_filters_refuse_another_birth(cls):
    from rankedassign.tracking import AdaptiveBirth
    with pytest.raises(TypeError, match=r"birth must be a MeasurementBirth, got AdaptiveBirth; None for the model.s static birth or MeasurementBirth\(\.\.\.\)"):
        cls(make_model("vo"), Exact(), birth=AdaptiveBirth())


# ----------------------------------------------------------------------------- in the filters
@pytest.mark.parametrize("cls", [LMBFilter, GLMBFilter])
def test_first_scan_births_at_every_measurement(cls):
    mb = MeasurementBirth(lambda_b=0.2, r_max=0.15, velocity_cov=4.0)
    f = cls(make_model("vo"), Exact(), birth=mb)
    z = np.array([[100.0, 200.0], [-300.0, 50.0]])
    rec = f.step(z, rng=0)
    # nothing to associate on scan 1 (no static birth): both measurements are unexplained,
    # r_B = min(0.15, 0.5 · 0.2) = 0.1 each
    assert rec.labels.shape == (0, 2)
    assert rec.timings["birth"] >= 0
    np.testing.assert_array_equal(f._birth_r, [0.1, 0.1])
    np.testing.assert_array_equal(f._birth_m[:, [0, 2]], z)
    # scan 2 appends them, predicted with the motion, labels (2, 1) and (2, 2)
    rec = f.step(z + [[10.0, 0.0], [0.0, 10.0]], rng=1)
    assert sorted(map(tuple, rec.track_labels.tolist()))[:2] == [(2, 1), (2, 2)]


def test_lmb_r_A_is_the_sum_of_the_marginals():
    mb = MeasurementBirth(lambda_b=0.5, r_max=1.0, r_min=0.0)
    f = LMBFilter(make_model("vo"), Exact(), birth=mb)
    z = np.array([[100.0, 200.0], [-300.0, 50.0]])
    f.step(z, rng=0)
    f.predict()
    # the association of scan 2 on its own, to read β
    f2 = LMBFilter(make_model("vo"), Exact(), birth=mb)
    f2.step(z, rng=0)
    z2 = np.array([[101.0, 201.0], [600.0, 600.0], [-299.0, 52.0]])
    f2.predict()
    terms = f2._measurement_terms(z2)
    beta, _, _ = f2._associate(terms, f2._groups(terms), np.random.default_rng(0))
    r_A = np.zeros(3)
    r_A[terms.used] = beta[:, :terms.used.size].sum(axis=0)
    expected = birth_existence(r_A, 0.5, 1.0)
    g = LMBFilter(make_model("vo"), Exact(), birth=mb)
    g.step(z, rng=0)
    g.step(z2, rng=1)
    np.testing.assert_allclose(g._birth_r, expected[expected > 0], rtol=1e-12)
    # the far measurement is explained by nothing: it gets the largest share
    assert expected.argmax() == 1 and r_A[0] > 0.9 and r_A[2] > 0.9


def test_glmb_r_A_is_the_weight_of_the_hypotheses_using_z():
    mb = MeasurementBirth(lambda_b=0.5, r_max=1.0, r_min=0.0)
    f = GLMBFilter(make_model("vo"), Murty(200), birth=mb)
    z = np.array([[100.0, 200.0], [-300.0, 50.0]])
    f.step(z, rng=0)
    z2 = np.array([[101.0, 201.0], [600.0, 600.0], [-299.0, 52.0]])
    f.step(z2, rng=1)
    # by hand from the components: r_A(j) = Σ_h w_h [h has an entry that took z_j]
    r_A = np.zeros(3)
    for h in range(f.n_components):
        entries = f.comp_tracks[f.comp_off[h]:f.comp_off[h + 1]]
        for j in f._node_meas[f.hist[entries]]:
            if j >= 0:
                r_A[j] += f.comp_w[h]
    expected = birth_existence(r_A, 0.5, 1.0)
    np.testing.assert_allclose(f._birth_r, expected[expected > 0], rtol=1e-12)
    assert expected.argmax() == 1


@pytest.mark.parametrize("cls", [LMBFilter, GLMBFilter])
def test_reset_forgets_the_pending_births(cls):
    f = cls(make_model("vo"), Exact(), birth=MeasurementBirth())
    f.step([[0.0, 0.0]], rng=0)
    assert f._birth_r.size == 1
    f.reset()
    assert f._birth_r.size == 0


@pytest.mark.parametrize("cls", [LMBFilter, GLMBFilter])
def test_static_birth_unchanged_without_measurement_birth(cls):
    # the default (birth=None) keeps the model's births at every scan
    f = cls(make_model("vo"), Exact())
    f.step([[0.0, 0.0]], rng=0)
    assert f.birth is None and f._birth_r.size == 4


def _shifted_truth(seed, n_scans):
    """Vo's 12 targets, each moved by up to ±600 m: born where no static birth is."""
    t = paper_truth(n_scans)
    off = np.random.default_rng(seed).uniform(-600.0, 600.0, size=(t.states.shape[1], 2))
    st = t.states.copy()
    st[:, :, 0] += off[:, 0]
    st[:, :, 2] += off[:, 1]
    return Truth(st, t.birth, t.death)


def _mean_ospa(filt, truth, scans):
    values = []
    for k, sc in enumerate(scans):
        rec = filt.step(sc.z, rng=k)
        X = truth.positions[k][truth.exists[k]]
        values.append(ospa(X, np.asarray(rec.states)[:, [0, 2]], 100.0, 1.0).value)
    return float(np.mean(values))


@pytest.mark.parametrize("cls", [LMBFilter, GLMBFilter])
def test_vo_targets_born_anywhere_are_tracked(cls):
    """On "vo", measurement birth is near the static birth where that is right (Vo's birth
    locations) and far better where it is not (every target moved off them)."""
    model = make_model("vo")
    n = 40
    out = {}
    for where, truth in (("right", paper_truth(n)), ("moved", _shifted_truth(0, n))):
        scans = generate_measurements(truth, model, rng=7)
        for name, birth in (("static", None), ("measurement", MeasurementBirth())):
            f = cls(model, ShortChainGibbs(400, 25, tau_stall=5, tau_stale=10), birth=birth)
            out[where, name] = _mean_ospa(f, truth, scans)
    assert out["right", "measurement"] < out["right", "static"] + 8.0
    assert out["moved", "measurement"] < 25.0
    assert out["moved", "static"] > 3 * out["moved", "measurement"]


@pytest.mark.parametrize("filt", ["lmb", "glmb"])
def test_run_scenario_takes_the_measurement_birth(filt):
    from rankedassign.tracking import run_scenario

    run = run_scenario("vo", Murty(20), rng=3, n_scans=6, filter=filt,
                       birth=MeasurementBirth())
    assert run.n_tracks[0] == 0            # no static birth on scan 1
    assert (run.n_tracks[1:] > 0).all()    # births from the measurements after it
    assert "birth" in run.timings and run.timings["birth"].shape == (6,)


def test_more_bad_input_of_the_birth():
    with pytest.raises(ValueError, match=r"r_A must be 1-D, got shape \(1, 2\)"):
        birth_existence([[0.0, 0.5]], 1.0, 1.0)
    with pytest.raises(ValueError, match=r"H must be a \(d, n\) matrix with d <= n, got shape "
                                         r"\(4, 2\)"):
        MeasurementBirth().births([[0.0, 0.0, 0.0, 0.0]], [0.0], H=H.T, R=np.eye(4))
    with pytest.raises(ValueError, match=r"measurement birth needs a position sensor: every "
                                         r"row of H picks one distinct state component"):
        MeasurementBirth().births([[0.0, 0.0]], [0.0], H=H[[0, 0]], R=np.eye(2))
    with pytest.raises(TypeError, match=r"velocity_mean must be a number or a numeric array, "
                                        r"got True"):
        MeasurementBirth(velocity_mean=True)


# ----------------------------------------------------------------------------- non-linear sensors
def test_births_through_a_sensors_inverse():
    """A bearing–range birth sits at the inverse of its measurement with the linearised
    covariance J R Jᵀ (checked against a Monte Carlo spread of the inverse, small noise); the
    other components take the prior."""
    from rankedassign.tracking.nonlinear import BearingRange
    from rankedassign.tracking.nonlinear.sensors import ElevationBearingRange

    br = BearingRange(sigma_bearing=1e-3, sigma_range=2.0, sensor_position=(100.0, -50.0),
                      state_ndim=5)
    x = np.array([[400.0, 3.0, 350.0, -1.0, 0.02]])
    z = br.h(x)
    prior = MeasurementBirth(lambda_b=0.5, velocity_mean=[1.0, 2.0, 0.0],
                             velocity_cov=[4.0, 9.0, 1e-4])
    b = prior.births_from(z, [0.0], br)
    np.testing.assert_allclose(b.means[0, [0, 2]], x[0, [0, 2]], rtol=1e-12)
    np.testing.assert_allclose(b.means[0, [1, 3, 4]], [1.0, 2.0, 0.0])
    rng = np.random.default_rng(0)
    zs = z + rng.normal(size=(20000, 2)) * [1e-3, 2.0]
    p, _ = br.inverse(zs)
    # 20 000 draws: the sample covariance is within a few per cent of J R J'
    np.testing.assert_allclose(b.covs[0][np.ix_([0, 2], [0, 2])], np.cov(p.T), rtol=0.05,
                               atol=0.05)
    assert np.diag(b.covs[0])[[1, 3, 4]].tolist() == [4.0, 9.0, 1e-4]
    ebr = ElevationBearingRange(np.diag([1e-6, 1e-6, 1.0]), sensor_position=(1.0, 2.0, 3.0))
    x6 = np.array([[100.0, 1.0, -50.0, 0.0, 30.0, 0.0]])
    b6 = MeasurementBirth().births_from(ebr.h(x6), [0.0], ebr)
    np.testing.assert_allclose(b6.means[0, [0, 2, 4]], x6[0, [0, 2, 4]], rtol=1e-12)


def test_a_sensor_without_an_inverse_is_refused():
    from rankedassign.tracking.nonlinear.sensors import Bearing

    with pytest.raises(TypeError, match=r"measurement birth needs the measurement model's "
                                        r"inverse \(a position from a measurement\): Bearing has "
                                        r"no inverse \(a bearing alone does not place a "
                                        r"target\); give static births"):
        MeasurementBirth().births_from([[0.3]], [0.0], Bearing([[1e-4]]))


@pytest.mark.parametrize("cls", [LMBFilter, GLMBFilter])
def test_measurement_birth_on_the_vo_ekf_model(cls):
    """Vo's bearing–range example without his births: the five targets present at scan 25
    are tracked from the measurements (the births placed through the sensor's inverse)."""
    from rankedassign.tracking.nonlinear import (
        generate_nonlinear_measurements,
        make_nonlinear_model,
        vo_truth,
    )

    model = make_nonlinear_model("vo-ekf")
    truth = vo_truth(model, 25)
    scans = generate_nonlinear_measurements(truth, model, rng=3)
    f = cls(model, Murty(100), birth=MeasurementBirth(
        velocity_cov=[50.0 ** 2, 50.0 ** 2, (6 * np.pi / 180) ** 2]))
    values = []
    for k, sc in enumerate(scans):
        rec = f.step(sc.z, rng=k)
        X = truth.positions[k][truth.exists[k]]
        values.append(ospa(X, rec.states[:, [0, 2]], 100.0, 1.0).value)
    assert rec.states.shape == (X.shape[0], 5)
    # Vo's own filters with his births: about 25 m over his 100 scans (nonlinear page); with
    # five targets, one false or missing track alone is 20 m of the OSPA (c = 100)
    assert np.mean(values[-5:]) < 40.0, values

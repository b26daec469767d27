"""The non-linear single-object layer: models, Jacobians, Kalman/EKF/UKF, wrap, Vo's presets."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from numpy.testing import assert_allclose, assert_array_equal

from rankedassign.tracking.models import ConstantVelocity, LinearMotion, PositionSensor
from rankedassign.tracking.nonlinear import (
    MAX_TURN_PER_SCAN,
    VO_TARGETS,
    BearingRange,
    BearingRangeClutter,
    CoordinatedTurn,
    ExtendedKalmanFilter,
    GaussianBirth,
    KalmanFilter,
    LinearGaussianMeasurement,
    LinearGaussianMotion,
    UnscentedKalmanFilter,
    generate_nonlinear_measurements,
    make_nonlinear_model,
    make_single_object_filter,
    vo_truth,
    wrap_angle,
)
from rankedassign.tracking.reference import detection_log_weights, gate_and_distances

CV = LinearGaussianMotion.from_motion(ConstantVelocity())
POS = LinearGaussianMeasurement.from_sensor(PositionSensor())
FILTERS = [ExtendedKalmanFilter(), UnscentedKalmanFilter(),
           UnscentedKalmanFilter(augmented=True)]


def _spd(rng, n, d, scale=1.0):
    A = rng.standard_normal((n, d, d))
    return scale * (A @ A.transpose(0, 2, 1) + d * np.eye(d))


# ------------------------------------------------------------------------------ Jacobians
def _fd_jacobian(fun, x, angles=None, step=1e-6):
    """Central finite differences of ``fun`` at the single state ``x`` (angle rows wrapped)."""
    x = np.asarray(x, dtype=float)
    cols = []
    for i in range(x.size):
        h = step * max(1.0, abs(x[i]))
        e = np.zeros_like(x)
        e[i] = h
        diff = fun((x + e)[None])[0] - fun((x - e)[None])[0]
        if angles is not None:
            diff[angles] = wrap_angle(diff[angles])
        cols.append(diff / (2 * h))
    return np.stack(cols, axis=1)


def _close_relative(J, J_fd, rtol=1e-6):
    scale = max(1.0, np.abs(J).max())
    assert np.abs(J - J_fd).max() <= rtol * scale, (J, J_fd)


@pytest.mark.parametrize("omega", [0.0, 1e-9, -1e-5, 2e-3, -0.05, 0.3, 1.5])
def test_ct_jacobian_matches_central_differences(omega):
    ct = CoordinatedTurn(dt=2.0)
    x = np.array([-1500.0, 43.0, 250.0, -17.0, omega])
    # step 1e-7 rad/s on ω: the rounding error of the difference stays below 1e-7 relative
    _close_relative(ct.jacobian(x[None])[0], _fd_jacobian(ct.f, x, step=1e-7))


@pytest.mark.parametrize("omega", [0.0, 1e-12, 5e-4, 9.99e-3, 1.001e-2, 0.5])
def test_ct_is_continuous_at_the_series_switch(omega):
    # the Taylor branch (|ω Δ| < 1e-2) and the closed form agree to rounding on either side
    ct = CoordinatedTurn()
    x = np.array([[10.0, 3.0, -4.0, 7.0, omega]])
    T = ct.dt
    if omega == 0:
        a, b = T, 0.0
    else:
        # 2 sin²(ωΔ/2)/ω: 1 − cos ωΔ without the cancellation
        a, b = math.sin(omega * T) / omega, 2 * math.sin(omega * T / 2) ** 2 / omega
    expect = [10 + a * 3 - b * 7, None, -4 + b * 3 + a * 7]
    out = ct.f(x)[0]
    assert_allclose(out[[0, 2]], [expect[0], expect[2]], rtol=1e-14)


def test_ct_at_zero_turn_is_constant_velocity():
    ct = CoordinatedTurn(dt=1.5)
    x = np.array([[1.0, 2.0, 3.0, 4.0, 0.0]])
    cv = ConstantVelocity(dt=1.5)
    assert_allclose(ct.f(x)[0, :4], cv.F @ x[0, :4], rtol=0, atol=0)
    assert_allclose(ct.jacobian(x)[0, :4, :4], cv.F, rtol=0, atol=0)


@pytest.mark.parametrize("dx", [1e-3, -1e-3, 0.0, 400.0])
@pytest.mark.parametrize("dy", [-500.0, 300.0])
def test_bearing_range_jacobian_matches_central_differences(dx, dy):
    # dx = ±1e-3 with dy < 0: the target sits on the wrap line (bearing ±π)
    br = BearingRange(sensor_position=(100.0, -50.0))
    x = np.array([100.0 + dx, 5.0, -50.0 + dy, -3.0, 0.01])
    J = br.jacobian(x[None])[0]
    _close_relative(J, _fd_jacobian(br.h, x, angles=br.angles, step=1e-7))


def test_bearing_is_vo_convention():
    br = BearingRange(state_ndim=4, position_indices=(0, 2))
    z = br.h(np.array([[1.0, 0, 0, 0], [0, 0, 1.0, 0], [0, 0, -1.0, 0], [-1.0, 0, 0, 0]]))
    # from the y-axis, clockwise positive: east π/2, north 0, south π, west −π/2
    assert_allclose(z[:, 0], [np.pi / 2, 0.0, np.pi, -np.pi / 2], atol=1e-15)
    assert_allclose(z[:, 1], 1.0)


# ------------------------------------------------------------------------ linear: bit for bit
def test_kalman_path_is_todays_arithmetic_bit_for_bit():
    rng = np.random.default_rng(3)
    n, M = 6, 5
    m = rng.normal(0, 300, (n, 4))
    P = _spd(rng, n, 4, 50.0)
    z = rng.normal(0, 300, (M, 2))
    kf = KalmanFilter()
    # LMBFilter.predict: m <- m F' ; P <- F P F' + Q
    F = np.array(CV.F)
    mp, Pp = kf.predict(CV, m, P)
    assert_array_equal(mp, m @ F.T)
    assert_array_equal(Pp, F @ P @ F.T + np.array(CV.Q))
    pred = kf.predict_measurement(POS, mp, Pp)
    det, Sinv, nu, maha, _ = gate_and_distances(mp, Pp, np.array(POS.R), z,
                                                np.arange(n + 1), 9.0, True)
    assert_array_equal(pred.S_inv, Sinv)
    assert_array_equal(pred.log_det, np.log(det))
    assert_array_equal(kf.innovations(pred, z), nu)
    assert_array_equal(kf.mahalanobis(pred, z), maha)
    lw, _, _ = detection_log_weights(maha, np.log(det), np.zeros(n), np.arange(n + 1),
                                     np.arange(M), np.ones((n, M), bool), np.zeros(n), 0.0, 0.0)
    assert_array_equal(kf.log_likelihood(pred, z), lw)
    assert_array_equal(kf.gate(pred, z, 9.0), maha <= 9.0)
    # LMBFilter.update: K = P H' S⁻¹, P' = sym(P − K (P H')'), m' = m + K ν
    PHt = Pp[:, :, [0, 2]]
    K = PHt @ Sinv
    P_upd = Pp - K @ PHt.transpose(0, 2, 1)
    P_upd = 0.5 * (P_upd + P_upd.transpose(0, 2, 1))
    mu, Pu = kf.update(pred, mp, Pp, z)
    assert_array_equal(Pu, P_upd)
    for j in range(M):
        assert_array_equal(mu[:, j], mp + np.einsum("cij,cj->ci", K, nu[:, j]))


@pytest.mark.parametrize("filt", FILTERS, ids=repr)
def test_ekf_and_ukf_equal_kalman_on_a_linear_model(filt):
    rng = np.random.default_rng(7)
    n, M = 5, 4
    m = rng.normal(0, 300, (n, 4))
    P = _spd(rng, n, 4, 30.0)
    z = rng.normal(0, 300, (M, 2))
    kf = KalmanFilter()
    mk, Pk = kf.predict(CV, m, P)
    mf, Pf = filt.predict(CV, m, P)
    tol = dict(rtol=1e-12, atol=1e-12 * np.abs(Pk).max())
    assert_allclose(mf, mk, rtol=1e-12, atol=1e-12 * np.abs(mk).max())
    assert_allclose(Pf, Pk, **tol)
    pk = kf.predict_measurement(POS, mk, Pk)
    pf = filt.predict_measurement(POS, mk, Pk)
    assert_allclose(pf.z, pk.z, rtol=1e-12, atol=1e-12 * np.abs(pk.z).max())
    assert_allclose(pf.S, pk.S, **tol)
    assert_allclose(pf.cross, pk.cross, **tol)
    assert_allclose(filt.log_likelihood(pf, z), kf.log_likelihood(pk, z), rtol=1e-12)
    mu_f, Pu_f = filt.update(pf, mk, Pk, z)
    mu_k, Pu_k = kf.update(pk, mk, Pk, z)
    assert_allclose(mu_f, mu_k, rtol=1e-12, atol=1e-12 * np.abs(mu_k).max())
    assert_allclose(Pu_f, Pu_k, rtol=1e-12, atol=1e-12 * np.abs(Pk).max())


def test_linear_motion_from_todays_models_keeps_the_matrices():
    cv = ConstantVelocity(2.0, 3.0)
    lin = LinearGaussianMotion.from_motion(cv)
    assert_array_equal(lin.F, cv.F)
    assert_array_equal(lin.Q, cv.Q)
    lm = LinearGaussianMotion.from_motion(LinearMotion(cv.F, cv.Q))
    assert_array_equal(lm.Q, cv.Q)
    assert lm.name == "LinearMotion"


# ------------------------------------------------------------------------------------ wrap
def test_wrap_angle_range():
    a = np.array([-np.pi, np.pi, 3 * np.pi, -3 * np.pi, 0.0, 7.0, -7.0, 1e6])
    w = wrap_angle(a)
    assert ((w > -np.pi) & (w <= np.pi)).all()
    assert_allclose(np.cos(w), np.cos(a), atol=1e-9)
    assert_allclose(np.sin(w), np.sin(a), atol=1e-9)


@pytest.mark.parametrize("filt", FILTERS, ids=repr)
def test_target_crossing_the_wrap_line_is_kept(filt):
    # a target due south of the sensor moving east: its bearing jumps from +π to −π
    ct = CoordinatedTurn()
    br = BearingRange()
    m = np.array([[-4.0, 10.0, -800.0, 0.0, 0.0]])  # bearing just below +π ... crossing
    P = np.diag([100.0, 25.0, 100.0, 25.0, 1e-4])[None]
    mp, Pp = filt.predict(ct, m, P)
    pred = filt.predict_measurement(br, mp, Pp)
    truth = np.array([[6.0, 10.0, -800.0, 0.0, 0.0]])  # east of the line: bearing near −π
    z = br.h(truth)
    assert z[0, 0] < -3.1 and pred.z[0, 0] > 3.1 or z[0, 0] > 3.1 and pred.z[0, 0] < -3.1 \
        or abs(z[0, 0] - pred.z[0, 0]) < 0.1
    nu = filt.innovations(pred, z)
    assert abs(nu[0, 0, 0]) < 0.05
    assert filt.gate(pred, z, 9.21)[0, 0]
    # the same measurement written 2π off (a user's bearing outside (−π, π]) is the same
    z2 = z + [[2 * np.pi, 0.0]]
    assert_allclose(filt.log_likelihood(pred, z2), filt.log_likelihood(pred, z), rtol=1e-12)
    mu, _ = filt.update(pred, mp, Pp, z)
    mu2, _ = filt.update(pred, mp, Pp, z2)
    assert_allclose(mu2, mu, rtol=1e-12)
    assert abs(mu[0, 0, 0] - 6.0) < 10.0  # the update pulls the mean towards the target


def test_ukf_mean_bearing_of_sigma_points_straddling_the_wrap():
    # a mean due south: half the sigma points have bearing near +π, half near −π
    ukf = UnscentedKalmanFilter()
    br = BearingRange()
    m = np.array([[0.0, 0.0, -1000.0, 0.0, 0.0]])
    P = np.diag([400.0, 1.0, 400.0, 1.0, 1e-4])[None]
    pred = ukf.predict_measurement(br, m, P)
    assert abs(abs(pred.z[0, 0]) - np.pi) < 1e-9
    # S: the spread of the bearing is σ_x / ρ ≈ 0.02 rad, not the 2π of a naive mean
    assert pred.S[0, 0, 0] < 0.01


# ---------------------------------------------------------------------- hypothesis properties
@st.composite
def _gaussian(draw, d):
    seed = draw(st.integers(0, 2**32 - 1))
    n = draw(st.integers(1, 3))
    rng = np.random.default_rng(seed)
    m = rng.normal(0, 200, (n, d))
    m[:, 2] += 600.0  # away from the sensor: ranges well above zero
    P = _spd(rng, n, d, draw(st.floats(0.1, 20.0)))
    return m, P


@given(_gaussian(4), st.integers(0, 3))
def test_property_ukf_is_exact_on_linear_models(gauss, M):
    m, P = gauss
    z = np.random.default_rng(M).normal(0, 200, (M, 2))
    kf, ukf = KalmanFilter(), UnscentedKalmanFilter(alpha=0.5, kappa=1.0)
    pk, pu = kf.predict_measurement(POS, m, P), ukf.predict_measurement(POS, m, P)
    assert_allclose(pu.S, pk.S, rtol=1e-10, atol=1e-10 * np.abs(pk.S).max())
    assert_allclose(ukf.log_likelihood(pu, z), kf.log_likelihood(pk, z), rtol=1e-9, atol=1e-9)


@given(_gaussian(5), st.sampled_from(FILTERS))
def test_property_update_shrinks_the_covariance(gauss, filt):
    m, P = gauss
    br = BearingRange()
    pred = filt.predict_measurement(br, m, P)
    z = pred.z[:1]
    _, Pu = filt.update(pred, m, P, z)
    # P − P' = K S K' is positive semi-definite; P' stays positive definite
    low = np.linalg.eigvalsh(P - Pu).min(axis=1)
    assert (low >= -1e-8 * np.abs(P).max()).all()
    assert (np.linalg.eigvalsh(Pu).min(axis=1) > 0).all()
    assert np.isfinite(filt.log_likelihood(pred, z)).all()


@given(st.floats(-1e3, 1e3, allow_nan=False))
def test_property_wrap_is_in_range_and_equivalent(a):
    w = float(wrap_angle(a))
    assert -np.pi < w <= np.pi
    assert abs(math.remainder(w - a, 2 * math.pi)) < 1e-9


# ---------------------------------------------------------------------------- bad input
def test_target_at_the_sensor_is_refused():
    br = BearingRange(sensor_position=(5.0, 7.0))
    x = np.array([[5.0, 1.0, 7.0, 1.0, 0.0]])
    with pytest.raises(ValueError, match=r"BearingRange: state 0 is at the sensor position "
                                         r"\(5.0, 7.0\) \(range 0\): its bearing and the "
                                         r"bearing's Jacobian are undefined"):
        br.jacobian(x)
    with pytest.raises(ValueError, match="BearingRange: state 0 is at the sensor position"):
        ExtendedKalmanFilter().predict_measurement(br, x, np.eye(5)[None])


def test_target_whose_range_squared_underflows_is_at_the_sensor():
    with pytest.raises(ValueError, match="BearingRange: state 0 is at the sensor position"):
        BearingRange().jacobian([[1e-170, 0.0, 0.0, 0.0, 0.0]])


@pytest.mark.parametrize("omega", [np.nan, np.inf])
def test_nan_turn_rate_is_refused(omega):
    with pytest.raises(ValueError, match=r"CoordinatedTurn: the means and covariances must be "
                                         r"finite"):
        ExtendedKalmanFilter().predict(CoordinatedTurn(), [[0.0, 1, 0, 1, omega]],
                                       np.eye(5)[None])
    with pytest.raises(ValueError, match=r"CoordinatedTurn: state 0 is not finite"):
        CoordinatedTurn().f([[0.0, 1, 0, 1, omega]])


def test_huge_turn_rate_is_refused():
    with pytest.raises(ValueError, match=r"CoordinatedTurn: the turn rate ω \(state component "
                                         r"4\) of state 1 is 10000000.0 rad/s: \|ω Δ\| exceeds "
                                         r"1e\+06 rad per scan"):
        CoordinatedTurn().jacobian([[0.0, 1, 0, 1, 0.1], [0.0, 1, 0, 1, 1e7]])
    assert CoordinatedTurn().f([[0.0, 1, 0, 1, MAX_TURN_PER_SCAN]]).shape == (1, 5)


def test_filter_refuses_non_finite_moments():
    with pytest.raises(ValueError, match="CoordinatedTurn: the means and covariances must be "
                                         "finite"):
        UnscentedKalmanFilter().predict(CoordinatedTurn(), np.zeros((1, 5)),
                                        np.full((1, 5, 5), np.nan))


@pytest.mark.parametrize("filt", FILTERS + [KalmanFilter()], ids=repr)
def test_measurement_of_the_wrong_dimension(filt):
    sensor = POS if isinstance(filt, KalmanFilter) else BearingRange(state_ndim=4)
    m, P = np.array([[100.0, 0, 200, 0]]), 10 * np.eye(4)[None]
    pred = filt.predict_measurement(sensor, m, P)
    name = sensor.name
    with pytest.raises(ValueError, match=rf"{name}: measurements must have shape \(M, 2\), got "
                                         r"shape \(3, 3\)"):
        filt.log_likelihood(pred, np.zeros((3, 3)))
    with pytest.raises(ValueError, match=rf"{name}: measurements must have shape \(M, 2\), got "
                                         r"shape \(2,\)"):
        filt.gate(pred, np.zeros(2), 9.0)
    with pytest.raises(ValueError, match=rf"{name}: measurement 1 is not finite"):
        filt.update(pred, m, P, [[1.0, 2.0], [np.nan, 1.0]])


def test_state_of_the_wrong_dimension():
    with pytest.raises(ValueError, match=r"BearingRange: means must have shape \(n, 5\) and "
                                         r"covariances \(n, 5, 5\), got \(1, 4\)"):
        ExtendedKalmanFilter().predict_measurement(BearingRange(), np.zeros((1, 4)),
                                                   np.eye(4)[None])


@pytest.mark.parametrize("kw", [{"sigma_bearing": 0.0}, {"sigma_range": -1.0},
                                {"sigma_range": 1e-200}])
def test_non_positive_definite_bearing_range_noise(kw):
    with pytest.raises(ValueError, match="BearingRange: the noise covariance R must be "
                                         "positive definite"):
        BearingRange(**kw)


def test_non_positive_definite_linear_noise():
    with pytest.raises(ValueError, match=r"PositionSensor-like: the noise covariance R must be "
                                         r"a symmetric positive definite 2x2 matrix"):
        LinearGaussianMeasurement(np.eye(2, 4), [[1.0, 2.0], [2.0, 1.0]],
                                  name="PositionSensor-like")
    with pytest.raises(ValueError, match=r"LinearGaussianMotion: the process noise covariance "
                                         r"Q must be a symmetric positive semi-definite 2x2"):
        LinearGaussianMotion(np.eye(2), [[1.0, 0.0], [0.0, -1.0]])
    with pytest.raises(ValueError, match=r"GaussianBirth: covariance 0 must be a symmetric "
                                         r"positive definite 2x2"):
        GaussianBirth(0.1, [0.0, 0.0], np.zeros((2, 2)))


def test_kalman_filter_refuses_a_non_linear_model():
    with pytest.raises(TypeError, match="KalmanFilter: CoordinatedTurn is not linear; use "
                                        "ExtendedKalmanFilter or UnscentedKalmanFilter"):
        KalmanFilter().predict(CoordinatedTurn(), np.zeros((1, 5)), np.eye(5)[None])
    with pytest.raises(TypeError, match="KalmanFilter: BearingRange is not linear"):
        KalmanFilter().predict_measurement(BearingRange(), np.ones((1, 5)), np.eye(5)[None])


def test_ukf_weights_that_make_a_covariance_non_positive_definite():
    # κ = −4.9, β = 0: W₀ᶜ = λ/(N + λ) = −49; with a wide turn-rate spread the centre point
    # lies far from the weighted mean of the others and the weighted sum is indefinite
    ukf = UnscentedKalmanFilter(alpha=1.0, beta=0.0, kappa=-4.9)
    m = np.array([[0.0, 30.0, 100.0, 0.0, 0.0]])
    P = np.diag([1.0, 100.0, 1.0, 100.0, 1.0])[None]
    with pytest.raises(ValueError, match=r"UnscentedKalmanFilter on CoordinatedTurn: the "
                                         r"sigma-point weights \(alpha=1.0, beta=0.0, "
                                         r"kappa=-4.9: W0c = -49.0+\d*\) make the predicted "
                                         r"covariance P of component 0 non-positive-definite"):
        ukf.predict(CoordinatedTurn(), m, P)


def test_ukf_scale_must_be_positive():
    with pytest.raises(ValueError, match=r"UnscentedKalmanFilter: N \+ lambda = alpha\^2 "
                                         r"\(N \+ kappa\) = -5.0 must be positive \(N = 5, "
                                         r"kappa = -10.0\)"):
        UnscentedKalmanFilter(kappa=-10.0).predict(CoordinatedTurn(), np.zeros((1, 5)),
                                                   np.eye(5)[None])


def test_ukf_psd_covariance_fallback():
    # a covariance with a zero eigenvalue (a component without velocity uncertainty) has no
    # Cholesky factor: its symmetric square root is used instead, with the same moments
    P = np.diag([4.0, 0.0, 4.0, 0.0])[None]
    m = np.array([[1.0, 2.0, 3.0, 4.0]])
    mk, Pk = KalmanFilter().predict(CV, m, P)
    mu, Pu = UnscentedKalmanFilter().predict(CV, m, P)
    assert_allclose(Pu, Pk, rtol=1e-12, atol=1e-12)
    with pytest.raises(ValueError, match=r"UnscentedKalmanFilter on ConstantVelocity: the "
                                         r"covariance of component 0 is not positive "
                                         r"semi-definite"):
        UnscentedKalmanFilter().predict(CV, m, np.diag([4.0, -1.0, 4.0, 0.0])[None])


def test_innovation_covariance_not_positive_definite():
    sensor = LinearGaussianMeasurement(np.eye(2, 4), np.eye(2) * 1e-300)
    P = np.diag([-1.0, 1.0, 1.0, 1.0])[None]
    with pytest.raises(ValueError, match=r"KalmanFilter on LinearGaussianMeasurement: the "
                                         r"innovation covariance S of component 0 is not "
                                         r"positive definite"):
        KalmanFilter().predict_measurement(sensor, np.zeros((1, 4)), P)


def test_unknown_filter_and_gate():
    with pytest.raises(ValueError, match=r"kind must be one of \['ekf', 'kalman', 'ukf'\], "
                                         r"got 'pf'"):
        make_single_object_filter("pf")
    ekf = make_single_object_filter("ekf")
    pred = ekf.predict_measurement(POS, np.zeros((1, 4)), np.eye(4)[None])
    with pytest.raises(ValueError, match="threshold must be > 0.0, got -1.0"):
        ekf.gate(pred, np.zeros((1, 2)), -1.0)


def test_clutter_region_is_checked():
    with pytest.raises(ValueError, match=r"BearingRangeClutter: bearing must be \(min, max\) "
                                         r"with -3.14159 <= min < max <= 3.14159"):
        BearingRangeClutter(15.0, (-4.0, 1.0))
    with pytest.raises(ValueError, match=r"BearingRangeClutter: range must be \(min, max\)"):
        BearingRangeClutter(15.0, (-1.0, 1.0), (10.0, 5.0))


# ------------------------------------------------------------------------------ Vo's presets
def test_vo_preset_numbers():
    for preset in ("vo-ekf", "vo-ukf"):
        model = make_nonlinear_model(preset)
        ct = model.motion
        assert (ct.dt, ct.sigma_vel, ct.sigma_turn) == (1.0, 5.0, math.pi / 180)
        assert_allclose(np.diag(model.sensor.R), [(2 * math.pi / 180) ** 2, 100.0])
        assert model.sensor.p_d == 0.98 and model.p_s == 0.99
        assert model.clutter.rate == 15.0
        assert_allclose(model.clutter.intensity, 15.0 / (math.pi * 2000.0))
        assert [b.r for b in model.birth] == [0.02, 0.02, 0.03, 0.03]
        assert_array_equal(np.concatenate([b.means for b in model.birth])[:, [0, 2]],
                           [[-1500, 250], [-250, 1000], [250, 750], [1000, 1500]])
        assert_allclose(np.sqrt(np.diag(model.birth[0].covs[0])),
                        [50, 50, 50, 50, 6 * math.pi / 180])
        s = model.settings
        assert (s.glmb_h_upd, s.glmb_h_max, s.lmb_h_upd, s.lmb_t_max) == (3000, 3000, 1000, 100)
        assert model.position_indices == (0, 2)
    ukf = make_nonlinear_model("vo-ukf").filter
    assert (ukf.alpha, ukf.beta, ukf.kappa, ukf.augmented) == (1.0, 2.0, 2.0, True)
    with pytest.raises(ValueError, match=r"unknown preset 'vo'; expected one of \('vo-ekf', "
                                         r"'vo-ukf'\)"):
        make_nonlinear_model("vo")


def test_vo_truth_follows_his_loop():
    truth = vo_truth()
    assert_array_equal(truth.birth, [b for _, b, _ in VO_TARGETS])
    assert_array_equal(truth.death, [10**2, 100, 100, 66, 80, 100, 100, 80, 100, 100])
    # the state at the birth scan is the initial state moved one scan on
    x0 = np.array([VO_TARGETS[3][0]])
    assert_allclose(truth.states[9, 3], CoordinatedTurn().f(x0)[0], rtol=0, atol=0)
    assert np.isnan(truth.states[66, 3]).all() and not np.isnan(truth.states[65, 3]).any()


def test_vo_measurements_are_reproducible_and_in_range():
    model = make_nonlinear_model("vo-ekf")
    truth = vo_truth(model, 20)
    a = generate_nonlinear_measurements(truth, model, rng=5)
    b = generate_nonlinear_measurements(truth, model, rng=5)
    for sa, sb in zip(a, b, strict=True):
        assert_array_equal(sa.z, sb.z)
        assert_array_equal(sa.origin, sb.origin)
        assert ((sa.z[:, 0] > -np.pi) & (sa.z[:, 0] <= np.pi)).all()
        clutter = sa.z[sa.origin < 0]
        assert ((clutter[:, 0] >= -np.pi / 2) & (clutter[:, 0] <= np.pi / 2)).all()
        assert ((clutter[:, 1] >= 0) & (clutter[:, 1] <= 2000)).all()
    # detections sit near their targets: |ν| within 6 σ
    br = model.sensor
    for k, scan in enumerate(a):
        det = scan.origin >= 0
        zt = br.h(truth.states[k, scan.origin[det]])
        nu = scan.z[det] - zt
        nu[:, 0] = wrap_angle(nu[:, 0])
        assert (np.abs(nu) <= 6 * np.array([br.sigma_bearing, br.sigma_range])).all()


# ------------------------------------------------------- one component at a time, Vo's way
def _vo_ut(m, P, alpha, kappa):
    """Sigma points (columns) and weights of the scaled unscented transform, one Gaussian."""
    n = m.size
    lam = alpha**2 * (n + kappa) - n
    L = np.linalg.cholesky((n + lam) * P)
    X = np.column_stack([m, m[:, None] - L, m[:, None] + L])
    w = np.concatenate([[lam], np.full(2 * n, 0.5)]) / (n + lam)
    return X, w


def _vo_ukf_step(model, m, P, z, alpha=1.0, beta=2.0, kappa=2.0):
    """Vo's UKF prediction and update of one component, loop by loop (his ukf_*_single)."""
    ct, br = model.motion, model.sensor
    G = np.array(ct.noise_gain)
    Xa, u = _vo_ut(np.concatenate([m, np.zeros(3)]), np.block(
        [[P, np.zeros((5, 3))], [np.zeros((3, 5)), np.eye(3)]]), alpha, kappa)
    Xp = np.column_stack([ct.f(Xa[:5, i])[0] + G @ Xa[5:, i] for i in range(Xa.shape[1])])
    mp = Xp @ u
    uc = u.copy()
    uc[0] += 1 - alpha**2 + beta
    D = Xp - mp[:, None]
    Pp = D @ np.diag(uc) @ D.T
    R = np.array(br.R)
    Xb, u = _vo_ut(np.concatenate([mp, np.zeros(2)]), np.block(
        [[Pp, np.zeros((5, 2))], [np.zeros((2, 5)), R]]), alpha, kappa)
    Z = np.column_stack([br.h(Xb[:5, i])[0] + Xb[5:, i] for i in range(Xb.shape[1])])
    eta = Z @ u
    uc = u.copy()
    uc[0] += 1 - alpha**2 + beta
    Sd = Z - eta[:, None]
    S = Sd @ np.diag(uc) @ Sd.T
    Gx = (Xb[:5] - mp[:, None]) @ np.diag(uc) @ Sd.T
    K = Gx @ np.linalg.inv(S)
    nu = z - eta
    q = math.exp(-0.5 * 2 * math.log(2 * math.pi) - 0.5 * math.log(np.linalg.det(S))
                 - 0.5 * nu @ np.linalg.solve(S, nu))
    return mp, Pp, q, mp + K @ nu, Pp - Gx @ np.linalg.inv(S) @ Gx.T


def _vo_ekf_step(model, m, P, z):
    """Vo's EKF prediction and update of one component (his ekf_*_single)."""
    ct, br = model.motion, model.sensor
    F = ct.jacobian(m)[0]
    mp = ct.f(m)[0]
    Pp = np.array(ct.Q) + F @ P @ F.T
    H = br.jacobian(mp)[0]
    S = np.array(br.R) + H @ Pp @ H.T
    K = Pp @ H.T @ np.linalg.inv(S)
    nu = z - br.h(mp)[0]
    q = math.exp(-math.log(2 * math.pi) - 0.5 * math.log(np.linalg.det(S))
                 - 0.5 * nu @ np.linalg.solve(S, nu))
    return mp, Pp, q, mp + K @ nu, (np.eye(5) - K @ H) @ Pp


@pytest.mark.parametrize("preset", ["vo-ekf", "vo-ukf"])
def test_preset_filter_is_vos_single_component_step(preset):
    model = make_nonlinear_model(preset)
    filt = model.filter
    rng = np.random.default_rng(11)
    birth = model.birth[2]
    for _ in range(3):
        m = birth.means[0] + rng.normal(0, [30, 10, 30, 10, 0.02])
        P = birth.covs[0] * rng.uniform(0.2, 1.0)
        truth = model.motion.f(m)[0]
        z = model.sensor.h(truth)[0] + rng.normal(0, [0.03, 10.0])
        step = _vo_ukf_step if preset == "vo-ukf" else _vo_ekf_step
        mp_ref, Pp_ref, q_ref, mu_ref, Pu_ref = step(model, m, P, z)
        mp, Pp = filt.predict(model.motion, m[None], P[None])
        pred = filt.predict_measurement(model.sensor, mp, Pp)
        mu, Pu = filt.update(pred, mp, Pp, z[None])
        assert_allclose(mp[0], mp_ref, rtol=1e-12, atol=1e-9)
        assert_allclose(Pp[0], Pp_ref, rtol=1e-10, atol=1e-9)
        assert_allclose(np.exp(filt.log_likelihood(pred, z[None]))[0, 0], q_ref, rtol=1e-9)
        assert_allclose(mu[0, 0], mu_ref, rtol=1e-10, atol=1e-8)
        assert_allclose(Pu[0], Pu_ref, rtol=1e-8, atol=1e-8)


@pytest.mark.parametrize("filt", FILTERS, ids=repr)
def test_two_bearing_range_sensors_far_apart_beat_either_one(filt):
    # poor range (200 m), good bearing (1°): each sensor alone localises along a thin arc;
    # two sensors 2 km apart cross their arcs. Sequential updates, each with its own model.
    left = BearingRange(math.pi / 180, 200.0, sensor_position=(-1000.0, 0.0))
    right = BearingRange(math.pi / 180, 200.0, sensor_position=(1000.0, 0.0))
    truth = np.array([[0.0, 5.0, 1000.0, 0.0, 0.0]])
    m = truth + [[150.0, 0.0, -120.0, 0.0, 0.0]]
    P = np.diag([300.0**2, 10.0**2, 300.0**2, 10.0**2, 1e-4])[None]

    def update(sensor, m, P):
        pred = filt.predict_measurement(sensor, m, P)
        mu, Pu = filt.update(pred, m, P, sensor.h(truth))
        return mu[:, 0], Pu

    pos = [0, 2]
    area = {}
    for name, sensors in (("left", [left]), ("right", [right]), ("both", [left, right])):
        mm, PP = m, P
        for s in sensors:
            mm, PP = update(s, mm, PP)
        area[name] = np.linalg.det(PP[0][np.ix_(pos, pos)])
    assert area["both"] < 0.2 * min(area["left"], area["right"])

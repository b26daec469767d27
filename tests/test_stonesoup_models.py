"""Stone Soup's models and Kalman-family filters mapped onto rankedassign.tracking.nonlinear:
the same predictions and updates as Stone Soup's on the same inputs."""

import datetime

import numpy as np
import pytest

pytest.importorskip("stonesoup")

from numpy.testing import assert_allclose  # noqa: E402
from ss_analytic import (  # noqa: E402
    AnalyticBearing,
    AnalyticBearingRange,
    AnalyticElevationBearingRange,
)
from stonesoup.models.measurement.linear import LinearGaussian  # noqa: E402
from stonesoup.models.measurement.nonlinear import (  # noqa: E402
    Cartesian2DToBearing,
    CartesianToBearingRange,
    CartesianToElevationBearing,
    CartesianToElevationBearingRange,
)
from stonesoup.models.transition.linear import (  # noqa: E402
    CombinedLinearGaussianTransitionModel,
    ConstantVelocity,
)
from stonesoup.models.transition.nonlinear import (  # noqa: E402
    ConstantTurn,
    ConstantTurnSandwich,
)
from stonesoup.predictor.kalman import (  # noqa: E402
    ExtendedKalmanPredictor,
    KalmanPredictor,
    SqrtKalmanPredictor,
    UnscentedKalmanPredictor,
)
from stonesoup.predictor.particle import ParticlePredictor  # noqa: E402
from stonesoup.types.detection import Detection  # noqa: E402
from stonesoup.types.hypothesis import SingleHypothesis  # noqa: E402
from stonesoup.types.prediction import GaussianStatePrediction  # noqa: E402
from stonesoup.types.state import GaussianState  # noqa: E402
from stonesoup.updater.kalman import (  # noqa: E402
    ExtendedKalmanUpdater,
    KalmanUpdater,
    UnscentedKalmanUpdater,
)
from stonesoup.updater.particle import ParticleUpdater  # noqa: E402

from rankedassign.stonesoup.models import (  # noqa: E402
    filter_from_stonesoup,
    filters_from_stonesoup,
    measurement_from_stonesoup,
    motion_from_stonesoup,
)
from rankedassign.tracking.nonlinear import (  # noqa: E402
    BearingRange,
    ExtendedKalmanFilter,
    KalmanFilter,
    LinearGaussianMeasurement,
    UnscentedKalmanFilter,
)

T0 = datetime.datetime(2025, 1, 1)
DT = datetime.timedelta(seconds=2)
CV = CombinedLinearGaussianTransitionModel([ConstantVelocity(0.5)] * 2)
POSITION = LinearGaussian(4, (0, 2), np.diag([25.0, 9.0]))
BR = CartesianToBearingRange(4, (0, 2), np.diag([1e-4, 4.0]),
                             translation_offset=np.array([[10.0], [-20.0]]))
PAIRS = [(KalmanPredictor, KalmanUpdater), (ExtendedKalmanPredictor, ExtendedKalmanUpdater),
         (UnscentedKalmanPredictor, UnscentedKalmanUpdater)]


def _gaussian(seed=0):
    rng = np.random.default_rng(seed)
    A = rng.normal(size=(4, 4))
    return np.array([300.0, 3.0, 400.0, -2.0]), A @ A.T + np.diag([100.0, 4.0, 100.0, 4.0])


def _theirs_update(updater, m, P, z, model):
    pred = GaussianStatePrediction(m.reshape(-1, 1), P, timestamp=T0)
    mp = updater.predict_measurement(pred, measurement_model=model)
    post = updater.update(SingleHypothesis(
        pred, Detection(z, timestamp=T0, measurement_model=model)))
    return (np.asarray(mp.state_vector, dtype=float).ravel(), np.asarray(mp.covar),
            np.asarray(post.state_vector, dtype=float).ravel(), np.asarray(post.covar))


def _ours_update(filt, sensor, m, P, z):
    pred = filt.predict_measurement(sensor, m[None], P[None])
    mu, Pu = filt.update(pred, m[None], P[None], np.asarray(z, dtype=float).reshape(1, -1))
    return pred.z[0], pred.S[0], mu[0, 0], Pu[0]


# ----------------------------------------------------------------------------- 1e-10
@pytest.mark.parametrize("predictor_cls", [p for p, _ in PAIRS])
def test_predictions_equal_stone_soups(predictor_cls):
    m, P = _gaussian()
    predictor = predictor_cls(CV)
    theirs = predictor.predict(GaussianState(m.reshape(-1, 1), P, timestamp=T0),
                               timestamp=T0 + DT)
    ours = filter_from_stonesoup(predictor, ndim_state=4)
    mo, Po = ours.predict(motion_from_stonesoup(CV, DT), m[None], P[None])
    assert_allclose(mo[0], np.asarray(theirs.state_vector, float).ravel(), rtol=1e-10,
                    atol=1e-10)
    assert_allclose(Po[0], np.asarray(theirs.covar), rtol=1e-10, atol=1e-10)


@pytest.mark.parametrize("updater_cls", [u for _, u in PAIRS])
def test_position_updates_equal_stone_soups(updater_cls):
    m, P = _gaussian(1)
    z = np.array([[310.0], [395.0]])
    updater = updater_cls(POSITION)
    theirs = _theirs_update(updater, m, P, z, POSITION)
    ours = _ours_update(filter_from_stonesoup(updater, ndim_state=4),
                        measurement_from_stonesoup(POSITION), m, P, z)
    for a, b in zip(ours, theirs, strict=True):
        assert_allclose(a, b, rtol=1e-10, atol=1e-10)


@pytest.mark.parametrize("bearing", [0.3, 3.1, -3.1])   # ±3.1: next to the wrap at ±π
def test_ekf_bearing_range_update_equals_stone_soups(bearing):
    model = AnalyticBearingRange(4, (0, 2), np.diag([1e-4, 4.0]),
                                 translation_offset=np.array([[10.0], [-20.0]]))
    m, P = _gaussian(2)
    # a prediction at bearing ~`bearing` from the sensor, and a measurement near it
    m[[0, 2]] = np.array([10.0, -20.0]) + 500.0 * np.array([np.cos(bearing), np.sin(bearing)])
    z = np.array([[bearing + 0.004], [503.0]])
    z[0, 0] = (z[0, 0] + np.pi) % (2 * np.pi) - np.pi
    updater = ExtendedKalmanUpdater(model)
    theirs = _theirs_update(updater, m, P, z, model)
    ours = _ours_update(filter_from_stonesoup(updater), measurement_from_stonesoup(model), m, P,
                        z)
    for a, b in zip(ours, theirs, strict=True):
        assert_allclose(a, b, rtol=1e-10, atol=1e-10)


def test_bearing_range_differences_from_stone_soups_own_approximations():
    """Where Stone Soup approximates differently, the difference is that approximation's:
    its bearing–range Jacobian is taken by finite differences, and its unscented transform
    averages the bearing sigma points with a circular mean (atan2 of the weighted sines and
    cosines) where ours (Vo's) adds the weighted wrapped deviations to the centre point."""
    m, P = _gaussian(3)
    z = np.array([[0.93], [498.0]])
    sensor = measurement_from_stonesoup(BR)
    for updater, tol in ((ExtendedKalmanUpdater(BR), 1e-8), (UnscentedKalmanUpdater(BR), 1e-7)):
        theirs = _theirs_update(updater, m, P, z, BR)
        ours = _ours_update(filter_from_stonesoup(updater, ndim_state=4), sensor, m, P, z)
        for a, b in zip(ours, theirs, strict=True):
            assert_allclose(a, b, rtol=tol, atol=1e-5)


# ----------------------------------------------------------------------------- the mapping
def test_mapped_classes_and_parameters():
    assert isinstance(filter_from_stonesoup(KalmanUpdater(POSITION)), KalmanFilter)
    assert isinstance(filter_from_stonesoup(ExtendedKalmanPredictor(CV)), ExtendedKalmanFilter)
    ukf = filter_from_stonesoup(UnscentedKalmanUpdater(POSITION, alpha=0.3, beta=1.0,
                                                       kappa=1.5))
    assert isinstance(ukf, UnscentedKalmanFilter)
    assert (ukf.alpha, ukf.beta, ukf.kappa) == (0.3, 1.0, 1.5)
    pos = measurement_from_stonesoup(POSITION, prob_detection=0.9)
    assert isinstance(pos, LinearGaussianMeasurement) and pos.p_d == 0.9
    assert pos.position_indices == (0, 2) and pos.R.tolist() == [[25.0, 0.0], [0.0, 9.0]]
    br = measurement_from_stonesoup(BR)
    assert isinstance(br, BearingRange)
    assert br.position_indices == (2, 0) and br.sensor_position == (-20.0, 10.0)
    assert br.sigma_bearing == pytest.approx(1e-2) and br.sigma_range == pytest.approx(2.0)
    # our h equals Stone Soup's function
    x = np.array([[130.0, 1.0, -80.0, 2.0]])
    theirs = np.asarray(BR.function(GaussianState(x.T, np.eye(4))), dtype=float).ravel()
    assert_allclose(br.h(x)[0], theirs, rtol=1e-14)


def test_what_has_no_counterpart_is_refused_by_name():
    with pytest.raises(TypeError, match=r"ParticleUpdater has no counterpart in "
                                        r"rankedassign.tracking.nonlinear: the Kalman, "
                                        r"extended and unscented"):
        filter_from_stonesoup(ParticleUpdater(POSITION))
    with pytest.raises(TypeError, match=r"ParticlePredictor has no counterpart"):
        filter_from_stonesoup(ParticlePredictor(CV))
    with pytest.raises(TypeError, match=r"SqrtKalmanPredictor has no counterpart"):
        filter_from_stonesoup(SqrtKalmanPredictor(CV))
    with pytest.raises(TypeError, match=r"UnscentedKalmanUpdater has kappa=None \(3 - n\): "
                                        r"give ndim_state"):
        filter_from_stonesoup(UnscentedKalmanUpdater(POSITION))
    with pytest.raises(TypeError, match=r"the measurement model CartesianToElevationBearing "
                                        r"has no counterpart in rankedassign.tracking.nonlinear "
                                        r"\(LinearGaussian, CartesianToBearingRange, "
                                        r"CartesianToElevationBearingRange and "
                                        r"Cartesian2DToBearing have\): it needs array forms of "
                                        r"its function h, its Jacobian and its inverse"):
        measurement_from_stonesoup(CartesianToElevationBearing(6, (0, 2, 4), np.eye(2)))
    with pytest.raises(ValueError, match=r"Bearing: rotation must be an orthogonal 2x2 matrix"):
        # a roll of a planar sensor: the plane is not rotated into itself
        measurement_from_stonesoup(Cartesian2DToBearing(
            4, (0, 2), np.eye(1), rotation_offset=np.array([[0.0], [0.4], [0.0]])))
    with pytest.raises(ValueError, match=r"CartesianToBearingRange: a rotation offset "
                                         r"\[0.0, 0.0, 0.5\] has no counterpart"):
        measurement_from_stonesoup(CartesianToBearingRange(
            4, (0, 2), np.eye(2), rotation_offset=np.array([[0.0], [0.0], [0.5]])))
    with pytest.raises(ValueError, match=r"takes independent bearing and range noise"):
        measurement_from_stonesoup(CartesianToBearingRange(4, (0, 2),
                                                           np.array([[1.0, 0.1], [0.1, 1.0]])))
    with pytest.raises(ValueError, match=r"need two position components, got mapping \(0,\)"):
        measurement_from_stonesoup(LinearGaussian(4, (0,), np.eye(1)))
    with pytest.raises(TypeError, match=r"the transition model ConstantTurnSandwich is not "
                                        r"linear-Gaussian \(no matrix F and covariance Q\) nor "
                                        r"ConstantTurn"):
        motion_from_stonesoup(ConstantTurnSandwich([0.1, 0.1], 0.1, [ConstantVelocity(0.1)]),
                              DT)


def test_constant_turn_is_our_coordinated_turn_with_stone_soups_noise():
    """ConstantTurn over an interval: Stone Soup's function and covariance; the square root the
    augmented unscented filter uses gives Q back."""
    ct = ConstantTurn([0.3, 0.7], 0.01)
    dt = datetime.timedelta(seconds=2.5)
    ours = motion_from_stonesoup(ct, dt)
    x = np.array([[10.0, 5.0, -3.0, 2.0, 0.2], [0.0, 1.0, 0.0, -1.0, 0.0]])
    theirs = np.column_stack([np.asarray(ct.function(GaussianState(r.reshape(-1, 1), np.eye(5)),
                                                     time_interval=dt), float).ravel()
                              for r in x]).T
    assert_allclose(ours.f(x), theirs, rtol=1e-12, atol=1e-12)
    assert_allclose(ours.Q, np.asarray(ct.covar(time_interval=dt)), rtol=0, atol=0)
    G = np.asarray(ours.noise_gain)
    assert_allclose(G @ G.T, ours.Q, atol=1e-14)
    assert motion_from_stonesoup(ct, datetime.timedelta(0)).f(x).tolist() == x.tolist()


# ----------------------------------------------------------------------------- 3-D and bearing
ROT3 = np.array([[0.1], [-0.2], [0.7]])     # roll, pitch, yaw of the sensor
EBR = AnalyticElevationBearingRange(6, (0, 2, 4), np.diag([1e-4, 4e-4, 4.0]),
                                    translation_offset=np.array([[10.0], [-20.0], [5.0]]),
                                    rotation_offset=ROT3)
BEARING = AnalyticBearing(4, (0, 2), np.array([[1e-4]]),
                          translation_offset=np.array([[10.0], [-20.0]]),
                          rotation_offset=np.array([[0.0], [0.0], [0.6]]))


def _gaussian6(seed=0):
    rng = np.random.default_rng(seed)
    A = rng.normal(size=(6, 6))
    return (np.array([300.0, 3.0, 400.0, -2.0, 150.0, 1.0]),
            A @ A.T + np.diag([100.0, 4.0, 100.0, 4.0, 100.0, 4.0]))


@pytest.mark.parametrize("model, m", [
    (EBR, _gaussian6()[0]),
    (BEARING, _gaussian()[0]),
    (CartesianToElevationBearingRange(6, (4, 0, 2), np.eye(3)), _gaussian6(1)[0]),
    (Cartesian2DToBearing(4, (2, 0), np.eye(1)), _gaussian(1)[0]),
])
def test_angle_sensors_h_jacobian_and_inverse_equal_stone_soups(model, m):
    ours = measurement_from_stonesoup(model)
    state = GaussianState(m.reshape(-1, 1), np.eye(m.size))
    theirs = np.asarray(model.function(state), dtype=float).ravel()
    assert_allclose(ours.h(m[None])[0], theirs, rtol=1e-13, atol=1e-13)
    analytic = {CartesianToElevationBearingRange: AnalyticElevationBearingRange,
                Cartesian2DToBearing: AnalyticBearing}.get(type(model), type(model))
    twin = analytic(model.ndim_state, model.mapping, model.noise_covar,
                    translation_offset=model.translation_offset,
                    rotation_offset=model.rotation_offset)
    assert_allclose(ours.jacobian(m[None])[0], twin.jacobian(state), rtol=1e-12, atol=1e-15)
    # Stone Soup's own finite differences agree to their precision
    assert_allclose(ours.jacobian(m[None])[0], model.jacobian(state), rtol=1e-5, atol=1e-7)
    if hasattr(ours, "inverse"):
        p, J = ours.inverse(theirs[None])
        back = np.asarray(model.inverse_function(Detection(theirs.reshape(-1, 1))),
                          dtype=float).ravel()
        assert_allclose(p[0], back[list(ours.position_indices)], rtol=1e-12, atol=1e-9)
        assert_allclose(p[0], m[list(ours.position_indices)], rtol=1e-12, atol=1e-9)
        # the inverse's Jacobian is the inverse of the Jacobian in the position components
        Jh = ours.jacobian(m[None])[0][:, list(ours.position_indices)]
        assert_allclose(J[0] @ Jh, np.eye(3), atol=1e-10)


@pytest.mark.parametrize("updater_cls", [ExtendedKalmanUpdater, UnscentedKalmanUpdater])
@pytest.mark.parametrize("model", [EBR, BEARING], ids=["elevation-bearing-range", "bearing"])
def test_angle_sensor_updates_equal_stone_soups(updater_cls, model):
    """EKF with the analytic Jacobian: 1e-10. UKF: Stone Soup averages the angles of the
    sigma points with a circular mean (atan2 of the weighted sines and cosines) where ours
    adds the weighted wrapped deviations to the centre point, so 1e-10 holds only where the
    sigma points' angles are close (here they are: 1e-3 rad apart), to 1e-7."""
    m, P = _gaussian6(2) if model.ndim_state == 6 else _gaussian(2)
    P = P * 1e-3
    state = GaussianState(m.reshape(-1, 1), P)
    z = np.asarray(model.function(state), dtype=float) + 1e-3
    updater = updater_cls(model)
    theirs = _theirs_update(updater, m, P, z, model)
    ours = _ours_update(filter_from_stonesoup(updater, ndim_state=m.size),
                        measurement_from_stonesoup(model), m, P, z)
    tol = 1e-10 if updater_cls is ExtendedKalmanUpdater else 1e-7
    for a, b in zip(ours, theirs, strict=True):
        assert_allclose(a, b, rtol=tol, atol=tol)


def test_a_predictor_and_an_updater_of_two_families_pair():
    pair = filters_from_stonesoup(UnscentedKalmanPredictor(CV), ExtendedKalmanUpdater(BR), 4)
    assert type(pair).__name__ == "PairedFilter"
    assert isinstance(pair.predictor, UnscentedKalmanFilter)
    assert isinstance(pair.updater, ExtendedKalmanFilter)
    assert isinstance(filters_from_stonesoup(ExtendedKalmanPredictor(CV),
                                             ExtendedKalmanUpdater(BR), 4),
                      ExtendedKalmanFilter)
    assert isinstance(filters_from_stonesoup(None, UnscentedKalmanUpdater(BR), 4),
                      UnscentedKalmanFilter)
    assert filters_from_stonesoup(None, None, 4) is None
    m, P = _gaussian(4)
    theirs = UnscentedKalmanPredictor(CV).predict(GaussianState(m.reshape(-1, 1), P,
                                                                timestamp=T0),
                                                  timestamp=T0 + DT)
    mo, Po = pair.predict(motion_from_stonesoup(CV, DT), m[None], P[None])
    assert_allclose(mo[0], np.asarray(theirs.state_vector, float).ravel(), rtol=1e-10)
    assert_allclose(Po[0], np.asarray(theirs.covar), rtol=1e-10, atol=1e-10)

"""Stone Soup's models and Kalman-family filters mapped onto rankedassign.tracking.nonlinear:
the same predictions and updates as Stone Soup's on the same inputs."""

import datetime

import numpy as np
import pytest

pytest.importorskip("stonesoup")

from numpy.testing import assert_allclose  # noqa: E402
from stonesoup.models.measurement.linear import LinearGaussian  # noqa: E402
from stonesoup.models.measurement.nonlinear import (  # noqa: E402
    Cartesian2DToBearing,
    CartesianToBearingRange,
    CartesianToElevationBearingRange,
)
from stonesoup.models.transition.linear import (  # noqa: E402
    CombinedLinearGaussianTransitionModel,
    ConstantVelocity,
)
from stonesoup.models.transition.nonlinear import ConstantTurn  # noqa: E402
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


class AnalyticBearingRange(CartesianToBearingRange):
    """Stone Soup's bearing–range model with the analytic Jacobian (Stone Soup's own takes
    finite differences, which agree with the analytic one to about 1e-7 only)."""

    def jacobian(self, state, **kwargs):
        x = np.asarray(state.state_vector, dtype=float).ravel()
        ix, iy = self.mapping[:2]
        t = np.asarray(self.translation_offset, dtype=float).ravel()
        dx, dy = x[ix] - t[0], x[iy] - t[1]
        r2 = dx * dx + dy * dy
        r = np.sqrt(r2)
        J = np.zeros((2, self.ndim_state))
        # φ = atan2(dy, dx): ∂φ/∂x = −dy/r², ∂φ/∂y = dx/r²; ρ: dx/r, dy/r
        J[0, ix], J[0, iy] = -dy / r2, dx / r2
        J[1, ix], J[1, iy] = dx / r, dy / r
        return J


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
    with pytest.raises(TypeError, match=r"the measurement model "
                                        r"CartesianToElevationBearingRange has no counterpart"):
        measurement_from_stonesoup(CartesianToElevationBearingRange(6, (0, 2, 4),
                                                                    np.eye(3)))
    with pytest.raises(TypeError, match=r"the measurement model Cartesian2DToBearing has no "
                                        r"counterpart"):
        measurement_from_stonesoup(Cartesian2DToBearing(4, (0, 2), np.eye(1)))
    with pytest.raises(ValueError, match=r"CartesianToBearingRange: a rotation offset "
                                         r"\[0.0, 0.0, 0.5\] has no counterpart"):
        measurement_from_stonesoup(CartesianToBearingRange(
            4, (0, 2), np.eye(2), rotation_offset=np.array([[0.0], [0.0], [0.5]])))
    with pytest.raises(ValueError, match=r"takes independent bearing and range noise"):
        measurement_from_stonesoup(CartesianToBearingRange(4, (0, 2),
                                                           np.array([[1.0, 0.1], [0.1, 1.0]])))
    with pytest.raises(ValueError, match=r"need two position components, got mapping \(0,\)"):
        measurement_from_stonesoup(LinearGaussian(4, (0,), np.eye(1)))
    with pytest.raises(TypeError, match=r"the transition model ConstantTurn is not "
                                        r"linear-Gaussian"):
        motion_from_stonesoup(ConstantTurn([0.1, 0.1], 0.1), DT)

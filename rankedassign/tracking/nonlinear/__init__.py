"""The single-object model layer for non-linear tracking: models, Kalman/EKF/UKF, Vo's presets.

* :mod:`~rankedassign.tracking.nonlinear.models` — motion models (linear-Gaussian, which
  wraps today's :class:`~rankedassign.tracking.models.ConstantVelocity`, and the coordinated
  turn with the turn rate in the state), measurement models (linear-Gaussian, which wraps
  today's :class:`~rankedassign.tracking.models.PositionSensor`, and bearing–range), clutter
  uniform in (bearing, range) space, Gaussian-mixture birth terms;
* :mod:`~rankedassign.tracking.nonlinear.filters` — the Kalman filter, the EKF and the UKF
  behind one interface (``predict``, ``predict_measurement``, ``log_likelihood``, ``gate``,
  ``update``), batched over Gaussian components;
* :mod:`~rankedassign.tracking.nonlinear.vo` — the ``"vo-ekf"`` and ``"vo-ukf"`` presets of
  Vo's non-linear examples: model, filter settings, truth and measurement generator.

See the "Non-linear models" page of the documentation for the equations.
"""

from .filters import (
    FILTERS,
    ExtendedKalmanFilter,
    KalmanFilter,
    MeasurementPrediction,
    UnscentedKalmanFilter,
    make_single_object_filter,
)
from .models import (
    MAX_TURN_PER_SCAN,
    BearingRange,
    BearingRangeClutter,
    CoordinatedTurn,
    GaussianBirth,
    LinearGaussianMeasurement,
    LinearGaussianMotion,
    wrap_angle,
)
from .vo import (
    NONLINEAR_PRESETS,
    VO_TARGETS,
    NonlinearModel,
    VoFilterSettings,
    generate_nonlinear_measurements,
    make_nonlinear_model,
    vo_truth,
)

__all__ = [
    "FILTERS",
    "MAX_TURN_PER_SCAN",
    "NONLINEAR_PRESETS",
    "VO_TARGETS",
    "BearingRange",
    "BearingRangeClutter",
    "CoordinatedTurn",
    "ExtendedKalmanFilter",
    "GaussianBirth",
    "KalmanFilter",
    "LinearGaussianMeasurement",
    "LinearGaussianMotion",
    "MeasurementPrediction",
    "NonlinearModel",
    "UnscentedKalmanFilter",
    "VoFilterSettings",
    "generate_nonlinear_measurements",
    "make_nonlinear_model",
    "make_single_object_filter",
    "vo_truth",
    "wrap_angle",
]

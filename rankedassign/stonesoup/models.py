"""Stone Soup's single-object models and Kalman-family filters as our array counterparts.

The trackers do the single-object arithmetic of non-linear tracking on arrays, with
:mod:`rankedassign.tracking.nonlinear`, instead of on Stone Soup objects. This module maps what
a Stone Soup user builds a tracker from onto those classes:

* :func:`motion_from_stonesoup`: a linear-Gaussian transition model (``F`` and ``Q`` of one
  interval) as :class:`~rankedassign.tracking.nonlinear.LinearGaussianMotion`, and
  ``ConstantTurn`` as :class:`StoneSoupTurn` (our coordinated turn with Stone Soup's noise);
* :func:`measurement_from_stonesoup`: ``LinearGaussian`` as
  :class:`~rankedassign.tracking.nonlinear.LinearGaussianMeasurement`,
  ``CartesianToBearingRange`` as :class:`~rankedassign.tracking.nonlinear.BearingRange`,
  ``CartesianToElevationBearingRange`` and ``Cartesian2DToBearing`` as
  :class:`~rankedassign.tracking.nonlinear.sensors.ElevationBearingRange` and
  :class:`~rankedassign.tracking.nonlinear.sensors.Bearing`;
* :func:`filter_from_stonesoup` (and :func:`filters_from_stonesoup` for a pair): a
  ``KalmanPredictor``/``KalmanUpdater``,
  ``ExtendedKalman…`` or ``UnscentedKalman…`` (with its ``alpha``, ``beta``, ``kappa``) as
  :class:`~rankedassign.tracking.nonlinear.KalmanFilter`,
  :class:`~rankedassign.tracking.nonlinear.ExtendedKalmanFilter` or
  :class:`~rankedassign.tracking.nonlinear.UnscentedKalmanFilter`.

Anything else is refused with a ``TypeError`` naming the class and what is missing. The tests
(``tests/test_stonesoup_models.py``) check that the mapped filters' predictions and updates
equal Stone Soup's on the same inputs.

Conventions: Stone Soup measures the bearing from the x-axis,
``φ = atan2(y − s_y, x − s_x)``; :class:`~rankedassign.tracking.nonlinear.BearingRange` from
the y-axis (Vo's), ``θ = atan2(p_x − s_x, p_y − s_y)``. Swapping the two position components
(``position_indices = (mapping[1], mapping[0])``, ``sensor_position = (s_y, s_x)``) makes
``θ = φ``, so the mapping is exact.
"""

from __future__ import annotations

import datetime
from dataclasses import dataclass, field

import numpy as np
from stonesoup.models.base import GaussianModel, LinearModel
from stonesoup.models.measurement.linear import LinearGaussian
from stonesoup.models.measurement.nonlinear import (
    Cartesian2DToBearing,
    CartesianToBearingRange,
    CartesianToElevationBearingRange,
)
from stonesoup.models.transition.nonlinear import ConstantTurn, ConstantTurnSandwich
from stonesoup.predictor.kalman import (
    ExtendedKalmanPredictor,
    KalmanPredictor,
    UnscentedKalmanPredictor,
)
from stonesoup.updater.kalman import ExtendedKalmanUpdater, KalmanUpdater, UnscentedKalmanUpdater

from ..tracking.nonlinear import (
    BearingRange,
    CoordinatedTurn,
    ExtendedKalmanFilter,
    KalmanFilter,
    LinearGaussianMeasurement,
    LinearGaussianMotion,
    UnscentedKalmanFilter,
)
from ..tracking.nonlinear.filters import PairedFilter
from ..tracking.nonlinear.sensors import Bearing, ElevationBearingRange

__all__ = ["StoneSoupTurn", "filter_from_stonesoup", "filters_from_stonesoup",
           "is_constant_turn", "measurement_from_stonesoup", "motion_from_stonesoup"]


def is_constant_turn(model) -> bool:
    """Whether ``model`` is Stone Soup's ``ConstantTurn`` on ``[x, v_x, y, v_y, ω]`` (a
    subclass that only changes e.g. its Jacobian included; ``ConstantTurnSandwich``, which
    adds linear components to the state, excluded).

    Parameters
    ----------
    model : object
        A Stone Soup transition model (anything else gives False).

    Returns
    -------
    bool
        True if :func:`motion_from_stonesoup` maps it onto :class:`StoneSoupTurn`.

    Examples
    --------
    >>> from stonesoup.models.transition.nonlinear import ConstantTurn
    >>> is_constant_turn(ConstantTurn(linear_noise_coeffs=(1.0, 1.0), turn_noise_coeff=0.01))
    True
    """
    return (isinstance(model, ConstantTurn) and not isinstance(model, ConstantTurnSandwich)
            and int(model.ndim_state) == 5)


@dataclass(frozen=True, eq=False)
class StoneSoupTurn(CoordinatedTurn):
    """Stone Soup's ``ConstantTurn`` over one interval: the coordinated turn with its noise.

    The transition is :class:`~rankedassign.tracking.nonlinear.CoordinatedTurn`'s, which is
    the function of Stone Soup's ``ConstantTurn`` on the same state ``[x, v_x, y, v_y, ω]``
    (Stone Soup replaces ``ω = 0`` by machine epsilon, we use the Taylor series: the two agree
    to rounding). The process noise is Stone Soup's ``covar(time_interval)`` (white
    acceleration noise per axis with ``linear_noise_coeffs`` and a turn-rate noise), not Vo's
    ``G Gᵀ``; the unscented filter's augmented form uses a square root of it.

    Parameters
    ----------
    dt : float
        The interval in s; 0 gives the identity (the trackers' placeholder before the first
        interval is known).
    noise : ndarray, shape (5, 5)
        Stone Soup's process noise covariance over ``dt``.

    Attributes
    ----------
    dt : float
        The interval in s.
    noise : ndarray, shape (5, 5)
        The process noise covariance (read-only, symmetrised).
    sigma_vel, sigma_turn : float
        :class:`~rankedassign.tracking.nonlinear.CoordinatedTurn`'s noise parameters, unused
        here (``noise`` replaces ``G Gᵀ``).

    Raises
    ------
    ValueError
        If ``dt`` is negative or not finite, or ``noise`` is not a symmetric positive
        semi-definite 5 × 5 matrix.

    References
    ----------
    Stone Soup, ``stonesoup.models.transition.nonlinear.ConstantTurn``; X. R. Li and
    V. P. Jilkov, "Survey of maneuvering target tracking. Part I: dynamic models", IEEE Trans.
    Aerosp. Electron. Syst. 39(4), 2003 (the coordinated turn).

    Examples
    --------
    >>> import datetime
    >>> from stonesoup.models.transition.nonlinear import ConstantTurn, ConstantTurnSandwich
    >>> ct = ConstantTurn(linear_noise_coeffs=(1.0, 1.0), turn_noise_coeff=0.01)
    >>> m = motion_from_stonesoup(ct, datetime.timedelta(seconds=2))
    >>> m.f([[0.0, 10.0, 0.0, 0.0, 0.0]]).tolist()
    [[20.0, 10.0, 0.0, 0.0, 0.0]]
    >>> float(m.Q[4, 4])
    0.02
    """

    noise: np.ndarray = field(default_factory=lambda: np.zeros((5, 5)))
    name = "ConstantTurn"

    def __post_init__(self):
        dt = float(self.dt)
        if not (np.isfinite(dt) and dt >= 0):
            raise ValueError(f"ConstantTurn: the interval must be non-negative and finite, "
                             f"got {self.dt!r} s")
        Q = np.array(self.noise, dtype=np.float64)
        if Q.shape != (5, 5) or not np.all(np.isfinite(Q)) or not np.allclose(Q, Q.T) \
                or np.linalg.eigvalsh(0.5 * (Q + Q.T)).min() < -1e-12 * max(1.0, abs(Q).max()):
            raise ValueError("ConstantTurn: the process noise must be a finite symmetric "
                             "positive semi-definite 5 x 5 matrix")
        Q = 0.5 * (Q + Q.T)
        Q.setflags(write=False)
        object.__setattr__(self, "dt", dt)
        object.__setattr__(self, "noise", Q)

    @property
    def Q(self) -> np.ndarray:
        """Stone Soup's process noise covariance, shape (5, 5)."""
        return self.noise

    @property
    def noise_gain(self) -> np.ndarray:
        """A square root ``G`` of ``Q`` (``G Gᵀ = Q``, from its eigendecomposition)."""
        lam, U = np.linalg.eigh(self.noise)
        G = U * np.sqrt(np.clip(lam, 0.0, None))
        G.setflags(write=False)
        return G

    @property
    def noise_cov(self) -> np.ndarray:
        """``I₅``: the noise enters as ``G v`` with ``v ~ N(0, I)``."""
        return np.eye(5)


def motion_from_stonesoup(transition_model, time_interval: datetime.timedelta):
    """A Stone Soup transition model over one interval, as our motion model.

    Parameters
    ----------
    transition_model : stonesoup.models.base.LinearModel and GaussianModel, or ConstantTurn
        E.g. a ``CombinedLinearGaussianTransitionModel`` of ``ConstantVelocity`` models, or
        ``ConstantTurn`` (state ``[x, v_x, y, v_y, ω]``).
    time_interval : datetime.timedelta
        The interval whose ``F`` and ``Q`` are taken.

    Returns
    -------
    LinearGaussianMotion or StoneSoupTurn
        ``F = transition_model.matrix(time_interval)``,
        ``Q = transition_model.covar(time_interval)``; for ``ConstantTurn`` the coordinated
        turn over the interval with ``Q = transition_model.covar(time_interval)``.

    Raises
    ------
    TypeError
        If the model is neither linear-Gaussian nor ``ConstantTurn`` (Stone Soup's
        ``KnownTurnRate`` is linear and taken; ``ConstantTurnSandwich`` and a user's own
        non-linear model are refused).

    Examples
    --------
    >>> import datetime
    >>> from stonesoup.models.transition.linear import (
    ...     CombinedLinearGaussianTransitionModel, ConstantVelocity)
    >>> cv = CombinedLinearGaussianTransitionModel([ConstantVelocity(0.5)] * 2)
    >>> motion_from_stonesoup(cv, datetime.timedelta(seconds=2)).F[0].tolist()
    [1.0, 2.0, 0.0, 0.0]
    """
    if is_constant_turn(transition_model):
        return StoneSoupTurn(
            dt=abs(time_interval.total_seconds()),
            noise=np.asarray(transition_model.covar(time_interval=time_interval), dtype=float))
    if not (isinstance(transition_model, LinearModel)
            and isinstance(transition_model, GaussianModel)):
        raise TypeError(f"the transition model {type(transition_model).__name__} is not "
                        "linear-Gaussian (no matrix F and covariance Q) nor ConstantTurn, the "
                        "non-linear transition model with an array counterpart here")
    return LinearGaussianMotion(
        np.asarray(transition_model.matrix(time_interval=time_interval), dtype=np.float64),
        np.asarray(transition_model.covar(time_interval=time_interval), dtype=np.float64),
        name=type(transition_model).__name__)


def measurement_from_stonesoup(measurement_model, prob_detection: float = 1.0):
    """A Stone Soup measurement model as our measurement model.

    Parameters
    ----------
    measurement_model : LinearGaussian, CartesianToBearingRange, ...
        A ``LinearGaussian`` (any state dimension and mapping), a 2-D
        ``CartesianToBearingRange`` with no rotation offset and a diagonal noise covariance,
        a ``CartesianToElevationBearingRange`` or a ``Cartesian2DToBearing`` (any rotation
        about the z-axis, any noise covariance).
    prob_detection : float, optional
        ``P_D`` carried by our model (default 1; the filters take it from the tracker).

    Returns
    -------
    LinearGaussianMeasurement, BearingRange, ElevationBearingRange or Bearing
        ``H = measurement_model.matrix()``, ``R = measurement_model.covar()``,
        ``position_indices = mapping[:2]``; or the bearing–range model with the position
        components swapped (module docstring), ``sensor_position`` the translation offset;
        or :class:`~rankedassign.tracking.nonlinear.sensors.ElevationBearingRange` /
        :class:`~rankedassign.tracking.nonlinear.sensors.Bearing` (Stone Soup's convention)
        with the translation offset and the rotation matrix.

    Raises
    ------
    TypeError
        If the model is of another class (``CartesianToBearingRangeRate``, a user's own, ...:
        the message names it and what is missing).
    ValueError
        If a ``CartesianToBearingRange`` has a rotation offset or a correlated noise
        covariance, a ``Cartesian2DToBearing`` a rotation about the x- or y-axis, or a
        ``LinearGaussian`` has fewer than two mapped components.

    Examples
    --------
    >>> import numpy as np
    >>> from stonesoup.models.measurement.nonlinear import CartesianToBearingRange
    >>> br = CartesianToBearingRange(4, (0, 2), np.diag([1e-4, 1.0]))
    >>> ours = measurement_from_stonesoup(br)
    >>> ours.position_indices, ours.h([[0.0, 0.0, 1.0, 0.0]]).round(6).tolist()
    ((2, 0), [[1.570796, 1.0]])
    """
    who = type(measurement_model).__name__
    if isinstance(measurement_model, LinearGaussian):
        mapping = tuple(int(i) for i in measurement_model.mapping)
        if len(mapping) < 2:
            raise ValueError(f"{who}: our measurement models need two position components, "
                             f"got mapping {mapping}")
        return LinearGaussianMeasurement(
            np.asarray(measurement_model.matrix(), dtype=np.float64),
            np.asarray(measurement_model.covar(), dtype=np.float64), p_d=prob_detection,
            position_indices=mapping[:2], name=who)
    if isinstance(measurement_model, CartesianToBearingRange):
        rot = np.asarray(measurement_model.rotation_offset, dtype=np.float64).ravel()
        if np.any(rot != 0):
            raise ValueError(f"{who}: a rotation offset {rot.tolist()} has no counterpart in "
                             "our BearingRange (a sensor at a position, bearing from the axis)")
        R = np.asarray(measurement_model.covar(), dtype=np.float64)
        if R[0, 1] != 0 or R[1, 0] != 0:
            raise ValueError(f"{who}: our BearingRange takes independent bearing and range "
                             f"noise, got the covariance {R.tolist()}")
        mapping = tuple(int(i) for i in measurement_model.mapping[:2])
        t = np.asarray(measurement_model.translation_offset, dtype=np.float64).ravel()
        return BearingRange(sigma_bearing=float(np.sqrt(R[0, 0])),
                            sigma_range=float(np.sqrt(R[1, 1])),
                            sensor_position=(float(t[1]), float(t[0])), p_d=prob_detection,
                            state_ndim=int(measurement_model.ndim_state),
                            position_indices=(mapping[1], mapping[0]))
    if isinstance(measurement_model, CartesianToElevationBearingRange):
        mapping = tuple(int(i) for i in measurement_model.mapping[:3])
        return ElevationBearingRange(
            np.asarray(measurement_model.covar(), dtype=np.float64),
            sensor_position=_offset(measurement_model, 3),
            rotation=np.asarray(measurement_model.rotation_matrix, dtype=np.float64),
            p_d=prob_detection, state_ndim=int(measurement_model.ndim_state),
            position_indices=mapping)
    if isinstance(measurement_model, Cartesian2DToBearing):
        mapping = tuple(int(i) for i in measurement_model.mapping[:2])
        # a planar position has no third coordinate: only A's upper-left block acts on it
        A = np.asarray(measurement_model.rotation_matrix, dtype=np.float64)[:2, :2]
        return Bearing(np.asarray(measurement_model.covar(), dtype=np.float64),
                       sensor_position=_offset(measurement_model, 2), rotation=A,
                       p_d=prob_detection, state_ndim=int(measurement_model.ndim_state),
                       position_indices=mapping)
    raise TypeError(f"the measurement model {who} has no counterpart in "
                    "rankedassign.tracking.nonlinear (LinearGaussian, CartesianToBearingRange, "
                    "CartesianToElevationBearingRange and Cartesian2DToBearing have): it needs "
                    "array forms of its function h, its Jacobian and its inverse")


def _offset(model, k: int) -> tuple:
    """The first ``k`` components of a model's translation offset (the sensor position)."""
    t = np.asarray(model.translation_offset, dtype=np.float64).ravel()
    return tuple(float(v) for v in t[:k])


def filters_from_stonesoup(predictor, updater, ndim_state: int):
    """A Stone Soup predictor and updater as one single-object filter of ours.

    Parameters
    ----------
    predictor : KalmanPredictor, ExtendedKalmanPredictor or UnscentedKalmanPredictor, or None
        None: the updater's family predicts too.
    updater : KalmanUpdater, ExtendedKalmanUpdater or UnscentedKalmanUpdater, or None
        None: the predictor's family measures too; both None: the Kalman filter if
        ``linear`` else the EKF is the caller's choice (this function returns None).
    ndim_state : int
        The state dimension (an unscented component's ``kappa=None`` is ``3 − n``).

    Returns
    -------
    object or None
        :func:`filter_from_stonesoup` of the one given, or of both when they map to the same
        filter, else a :class:`~rankedassign.tracking.nonlinear.filters.PairedFilter`.

    Raises
    ------
    TypeError
        As :func:`filter_from_stonesoup`.

    Examples
    --------
    >>> import numpy as np
    >>> from stonesoup.models.measurement.nonlinear import CartesianToBearingRange
    >>> from stonesoup.models.transition.linear import (
    ...     CombinedLinearGaussianTransitionModel, ConstantVelocity)
    >>> from stonesoup.predictor.kalman import KalmanPredictor
    >>> from stonesoup.updater.kalman import ExtendedKalmanUpdater
    >>> cv = CombinedLinearGaussianTransitionModel([ConstantVelocity(0.5)] * 2)
    >>> br = CartesianToBearingRange(4, (0, 2), np.diag([1e-4, 1.0]))
    >>> filters_from_stonesoup(KalmanPredictor(cv), ExtendedKalmanUpdater(br), 4)
    PairedFilter(KalmanFilter(), ExtendedKalmanFilter())
    """
    ours = [None if c is None else filter_from_stonesoup(c, ndim_state)
            for c in (predictor, updater)]
    if ours[0] is None or ours[1] is None:
        return ours[1] if ours[0] is None else ours[0]
    if repr(ours[0]) == repr(ours[1]):   # the same family and parameters
        return ours[1]
    return PairedFilter(ours[0], ours[1])


def filter_from_stonesoup(component, ndim_state: int | None = None):
    """A Stone Soup Kalman-family predictor or updater as our single-object filter.

    Parameters
    ----------
    component : KalmanPredictor or KalmanUpdater, or their Extended/Unscented forms
        The predictor or updater.
    ndim_state : int, optional
        The state dimension ``n``: Stone Soup's unscented ``kappa=None`` means ``3 − n``,
        which needs it (ignored otherwise).

    Returns
    -------
    KalmanFilter, ExtendedKalmanFilter or UnscentedKalmanFilter
        The unscented filter with the component's ``alpha``, ``beta`` and ``kappa`` (additive
        noise, as Stone Soup's).

    Raises
    ------
    TypeError
        If ``component`` is not one of the six classes (a particle predictor or updater, a
        square-root or cubature Kalman form: the message names the class), or an unscented
        component has ``kappa=None`` and no ``ndim_state`` is given.

    Examples
    --------
    >>> from stonesoup.updater.kalman import UnscentedKalmanUpdater
    >>> ukf = filter_from_stonesoup(UnscentedKalmanUpdater(), ndim_state=4)
    >>> type(ukf).__name__, ukf.alpha, ukf.beta, ukf.kappa
    ('UnscentedKalmanFilter', 0.5, 2.0, -1.0)
    """
    kind = type(component)
    if kind in (KalmanPredictor, KalmanUpdater):
        return KalmanFilter()
    if kind in (ExtendedKalmanPredictor, ExtendedKalmanUpdater):
        return ExtendedKalmanFilter()
    if kind in (UnscentedKalmanPredictor, UnscentedKalmanUpdater):
        kappa = component.kappa
        if kappa is None:
            if ndim_state is None:
                raise TypeError(f"{kind.__name__} has kappa=None (3 - n): give ndim_state")
            kappa = 3.0 - int(ndim_state)
        return UnscentedKalmanFilter(float(component.alpha), float(component.beta),
                                     float(kappa))
    raise TypeError(f"{kind.__name__} has no counterpart in rankedassign.tracking.nonlinear: "
                    "the Kalman, extended and unscented Kalman predictors and updaters have "
                    "(our filters hold Gaussian mixtures, not particles)")

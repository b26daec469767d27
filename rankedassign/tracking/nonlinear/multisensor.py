"""Several non-linear sensors: the model, the stacked measurement model, the preset.

Each sensor is its own measurement model (any object of the measurement interface, e.g. a
:class:`~rankedassign.tracking.nonlinear.BearingRange` at its own position, or a
:class:`~rankedassign.tracking.nonlinear.LinearGaussianMeasurement`) with its own clutter.
The multi-sensor filters update a track on the detections ``z_D`` of a set ``D`` of sensors
at once; for a non-linear model that is one measurement step of the single-object filter on
:class:`StackedSensor` ``D`` (the sensors' noises are independent, so ``R_D`` is block
diagonal, and the EKF's Jacobian and the UKF's sigma points see every sensor of ``D``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ...engine.rng import check_rng
from ...validation import check_choice
from ..models import EXTRACTIONS
from ..scenario import Scan, Truth
from .filters import ExtendedKalmanFilter
from .models import BearingRange, BearingRangeClutter, CoordinatedTurn, _readonly
from .vo import NonlinearModel, VoFilterSettings, _vo_birth, generate_nonlinear_measurements

__all__ = [
    "MULTI_NONLINEAR_PRESETS",
    "NonlinearMultiSensorModel",
    "StackedSensor",
    "generate_multisensor_measurements",
    "make_nonlinear_multisensor_model",
]

#: The presets of :func:`make_nonlinear_multisensor_model`.
MULTI_NONLINEAR_PRESETS = ("multi-bearing-range",)


class StackedSensor:
    """Several measurement models read as one: ``z = [h_1(x); h_2(x); ...]``.

    Parameters
    ----------
    sensors : sequence of measurement models
        At least one, all of the same state dimension.

    Attributes
    ----------
    name : str
        The sensors' names joined by ``" + "``.
    linear : bool
        True when every sensor is linear.
    ndim, state_ndim : int
        ``Σ d_z`` and ``d``.
    angles : ndarray of bool, shape (ndim,)
        The sensors' angle flags, stacked.
    R : ndarray, shape (ndim, ndim)
        ``blkdiag(R_1, R_2, ...)`` (independent noises).
    H : ndarray, shape (ndim, d)
        The stacked matrices (linear sensors only).

    Examples
    --------
    >>> from rankedassign.tracking.nonlinear import BearingRange
    >>> from rankedassign.tracking.nonlinear.multisensor import StackedSensor
    >>> s = StackedSensor([BearingRange(), BearingRange(sensor_position=(100.0, 0.0))])
    >>> s.ndim, s.angles.tolist(), s.h([[0.0, 0, 100, 0, 0]]).round(4).tolist()
    (4, [True, False, True, False], [[0.0, 100.0, -0.7854, 141.4214]])
    """

    def __init__(self, sensors):
        self.sensors = tuple(sensors)
        if not self.sensors:
            raise ValueError("StackedSensor needs at least one sensor")
        d = {int(s.state_ndim) for s in self.sensors}
        if len(d) != 1:
            raise ValueError(f"StackedSensor: the sensors measure states of dimensions "
                             f"{sorted(d)}; they must share one")
        self.state_ndim = d.pop()
        self.name = " + ".join(s.name for s in self.sensors)
        self.linear = all(getattr(s, "linear", False) for s in self.sensors)
        self.angles = np.concatenate([np.asarray(s.angles, dtype=bool) for s in self.sensors])
        self.ndim = int(self.angles.size)
        R = np.zeros((self.ndim, self.ndim))
        i = 0
        for s in self.sensors:
            k = int(np.asarray(s.angles).size)
            R[i:i + k, i:i + k] = np.asarray(s.R)
            i += k
        self.R = _readonly(R)
        if self.linear:
            self.H = _readonly(np.vstack([np.asarray(s.H) for s in self.sensors]))

    def h(self, x) -> np.ndarray:
        """``[h_1(x), h_2(x), ...]`` of every row of ``x``.

        Parameters
        ----------
        x : ndarray, shape (n, d)
            States.

        Returns
        -------
        ndarray, shape (n, ndim)
            The sensors' predicted measurements side by side.
        """
        return np.hstack([s.h(x) for s in self.sensors])

    def jacobian(self, x) -> np.ndarray:
        """The sensors' Jacobians stacked.

        Parameters
        ----------
        x : ndarray, shape (n, d)
            States.

        Returns
        -------
        ndarray, shape (n, ndim, d)
            The Jacobians of every sensor, one above the other.
        """
        return np.concatenate([s.jacobian(x) for s in self.sensors], axis=1)


@dataclass(frozen=True)
class NonlinearMultiSensorModel:
    """Motion, birth, survival and single-object filter shared by ``V`` non-linear sensors.

    Attributes
    ----------
    motion : object
        Motion model (e.g. :class:`~rankedassign.tracking.nonlinear.CoordinatedTurn`).
    sensors : tuple
        ``V >= 1`` measurement models, each with its ``p_d`` (and, for bearing–range, its
        position).
    clutters : tuple
        One clutter model per sensor (``intensity``, ``sample(rng)``).
    birth : tuple of GaussianBirth
        Static LMB birth terms.
    p_s : float
        Survival probability.
    filter : object
        Single-object filter (EKF, UKF or, on linear models, Kalman).
    settings : VoFilterSettings
        The multi-object filters' settings.
    extraction : {"hysteresis", "map"}
        Default state extraction.

    Raises
    ------
    ValueError
        Without a sensor, with a clutter count other than ``V``, sensors of different state
        dimensions or an unknown extraction.

    Examples
    --------
    >>> from rankedassign.tracking.nonlinear.multisensor import make_nonlinear_multisensor_model
    >>> m = make_nonlinear_multisensor_model()
    >>> m.n_sensors, m.single(1).sensor.sensor_position
    (2, (2000.0, 0.0))
    """

    motion: object = field(default_factory=CoordinatedTurn)
    sensors: tuple = field(default_factory=lambda: (BearingRange(),))
    clutters: tuple = field(default_factory=lambda: (BearingRangeClutter(),))
    birth: tuple = field(default_factory=_vo_birth)
    p_s: float = 0.99
    filter: object = field(default_factory=ExtendedKalmanFilter)
    settings: VoFilterSettings = field(default_factory=VoFilterSettings)
    extraction: str = "map"

    def __post_init__(self):
        object.__setattr__(self, "sensors", tuple(self.sensors))
        object.__setattr__(self, "clutters", tuple(self.clutters))
        if not self.sensors:
            raise ValueError("a multi-sensor model needs at least one sensor, got none")
        if len(self.clutters) != len(self.sensors):
            raise ValueError(f"clutters must have one entry per sensor ({len(self.sensors)}), "
                             f"got {len(self.clutters)}")
        StackedSensor(self.sensors)  # one state dimension
        check_choice(self.extraction, "extraction", EXTRACTIONS)

    @property
    def n_sensors(self) -> int:
        """``V``."""
        return len(self.sensors)

    @classmethod
    def from_model(cls, model: NonlinearModel) -> NonlinearMultiSensorModel:
        """The one-sensor model of a single-sensor non-linear model.

        Parameters
        ----------
        model : NonlinearModel
            Its sensor and clutter become sensor 0.

        Returns
        -------
        NonlinearMultiSensorModel
        """
        return cls(model.motion, (model.sensor,), (model.clutter,), model.birth, model.p_s,
                   model.filter, model.settings, model.extraction)

    @property
    def position_indices(self) -> tuple:
        """State components of the position (sensor 0's)."""
        return tuple(self.sensors[0].position_indices)

    def single(self, v: int = 0) -> NonlinearModel:
        """Sensor ``v`` as a single-sensor :class:`~rankedassign.tracking.nonlinear.NonlinearModel`.

        Parameters
        ----------
        v : int, optional
            Index of the sensor (default 0).

        Returns
        -------
        NonlinearModel
        """
        return NonlinearModel(self.motion, self.sensors[v], self.clutters[v], self.birth,
                              self.p_s, self.filter, self.settings, self.extraction)

    def select(self, sensors) -> NonlinearMultiSensorModel:
        """The model restricted to the sensors of index ``sensors`` (in that order).

        Parameters
        ----------
        sensors : sequence of int
            Distinct sensor indices.

        Returns
        -------
        NonlinearMultiSensorModel
        """
        idx = [int(v) for v in sensors]
        if not idx or len(set(idx)) != len(idx) or not all(0 <= v < self.n_sensors for v in idx):
            raise ValueError(f"sensors must be distinct indices in [0, {self.n_sensors}), got "
                             f"{sensors!r}")
        return NonlinearMultiSensorModel(
            self.motion, tuple(self.sensors[v] for v in idx),
            tuple(self.clutters[v] for v in idx), self.birth, self.p_s, self.filter,
            self.settings, self.extraction)


def make_nonlinear_multisensor_model(preset: str = "multi-bearing-range", *,
                                     filter=None) -> NonlinearMultiSensorModel:
    """The model of a non-linear multi-sensor preset.

    Parameters
    ----------
    preset : {"multi-bearing-range"}
        Vo's CT targets, motion, births and survival (``"vo-ekf"``) seen by two bearing–range
        sensors 4 km apart, at ``(−2000, 0)`` and ``(2000, 0)`` m, each with a good bearing
        (σ = 1°) and a poor range (σ = 100 m), ``P_D = 0.9`` and 10 clutter points per scan
        uniform in bearing ``(−π, π]`` and range ``[0, 5000]`` m. Each sensor alone localises
        a target along a thin arc; the arcs of the two cross (see the "Non-linear models"
        page).
    filter : object, optional
        The single-object filter (default the EKF).

    Returns
    -------
    NonlinearMultiSensorModel

    Raises
    ------
    ValueError
        On an unknown preset.
    """
    check_choice(preset, "preset", MULTI_NONLINEAR_PRESETS)
    sensors = tuple(BearingRange(math.pi / 180, 100.0, sensor_position=(sx, 0.0), p_d=0.9)
                    for sx in (-2000.0, 2000.0))
    clutter = BearingRangeClutter(rate=10.0, bearing=(-math.pi, math.pi), range=(0.0, 5000.0))
    return NonlinearMultiSensorModel(sensors=sensors, clutters=(clutter, clutter),
                                     filter=ExtendedKalmanFilter() if filter is None else filter)


def generate_multisensor_measurements(truth: Truth, model: NonlinearMultiSensorModel, *,
                                      rng=None) -> list[list[Scan]]:
    """Every sensor's measurements of every scan, each sensor from its own stream.

    Parameters
    ----------
    truth : Truth
        Target states in the model's state space.
    model : NonlinearMultiSensorModel
        Sensors and clutters.
    rng : optional
        Anything :func:`numpy.random.default_rng` accepts; one child stream per sensor, so a
        sensor's measurements do not depend on which others exist.

    Returns
    -------
    list of list of Scan
        ``out[v][k]``: sensor ``v`` at scan ``k``.
    """
    streams = check_rng(rng).spawn(model.n_sensors)
    return [generate_nonlinear_measurements(truth, model.single(v), rng=streams[v])
            for v in range(model.n_sensors)]


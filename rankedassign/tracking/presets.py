"""Every model preset by name, linear and non-linear: :func:`make_model`, :func:`make_scenario`.

The linear presets (``"paper"``, ``"paper-var"``, ``"vo"``) are those of
:mod:`rankedassign.tracking.models` and :mod:`rankedassign.tracking.scenario`; the non-linear
ones (``"vo-ekf"``, ``"vo-ukf"``: Vo's coordinated-turn, bearing–range examples) those of
:mod:`rankedassign.tracking.nonlinear.vo`. This module sits above both (the non-linear layer
is built on the linear models and the scenario's records), so that one name serves every
preset; :mod:`rankedassign.tracking` exports these two functions.
"""

from __future__ import annotations

import math

from ..engine.rng import check_rng
from ..validation import check_choice
from .models import PRESETS as LINEAR_PRESETS
from .models import make_model as _make_linear_model
from .nonlinear.filters import ExtendedKalmanFilter
from .nonlinear.models import (
    BearingRange,
    BearingRangeClutter,
    GaussianBirth,
    LinearGaussianMotion,
)
from .nonlinear.vo import (
    NONLINEAR_PRESETS,
    NonlinearModel,
    generate_nonlinear_measurements,
    make_nonlinear_model,
    vo_truth,
)
from .scenario import LARGE_CELL, Scenario, check_n_scans, check_n_targets, large_model, large_truth
from .scenario import make_scenario as _make_linear_scenario

__all__ = ["ALL_PRESETS", "LARGE_SENSORS", "LARGE_SIGMA_BEARING", "large_bearing_range_model",
           "make_model", "make_scenario"]

#: Every preset :func:`make_model` and :func:`make_scenario` build.
ALL_PRESETS = (*LINEAR_PRESETS, *NONLINEAR_PRESETS)
#: Sensors of the ``"large"`` scenario: Vo's position sensor, or one bearing–range sensor near
#: the centre of the square (:func:`large_bearing_range_model`).
LARGE_SENSORS = ("position", "bearing-range")
#: Bearing noise (rad) of the ``"large"`` scenario's bearing–range sensor: 1 mrad, 10 m across
#: the line of sight at 10 km (the position sensor's 10 m), so that the gates stay a few
#: targets wide out to the corners of a 10 000-target square (14 km away).
LARGE_SIGMA_BEARING = 1e-3


def make_model(preset: str = "paper"):
    """The model of any preset, linear or non-linear.

    Parameters
    ----------
    preset : {"paper", "paper-var", "vo", "vo-ekf", "vo-ukf"}
        A linear preset (:func:`rankedassign.tracking.models.make_model`) or one of Vo's
        non-linear examples with his EKF or UKF
        (:func:`rankedassign.tracking.nonlinear.make_nonlinear_model`).

    Returns
    -------
    Model or NonlinearModel
        Either is accepted by :class:`~rankedassign.tracking.LMBFilter` and
        :class:`~rankedassign.tracking.GLMBFilter`.

    Raises
    ------
    ValueError
        On an unknown preset.

    Examples
    --------
    >>> from rankedassign.tracking import make_model
    >>> type(make_model("vo")).__name__, type(make_model("vo-ekf")).__name__
    ('Model', 'NonlinearModel')
    >>> make_model("vo-ukf").filter
    UnscentedKalmanFilter(alpha=1.0, beta=2.0, kappa=2.0, augmented=True)
    """
    preset = check_choice(preset, "preset", ALL_PRESETS)
    if preset in NONLINEAR_PRESETS:
        return make_nonlinear_model(preset)
    return _make_linear_model(preset)


def large_bearing_range_model(n_targets: int) -> NonlinearModel:
    """The ``"large"`` scenario's model with one bearing–range sensor near the square's centre.

    The motion, survival, births and clutter count are those of
    :func:`~rankedassign.tracking.scenario.large_model` (constant velocity, ``P_S = 0.99``,
    Vo's four birth places, ``0.3 n_targets`` clutter points a scan on average); the sensor is
    a :class:`~rankedassign.tracking.nonlinear.BearingRange` at ``(100, 100)`` m (the middle
    of a cell next to the origin, off the birth places) with
    ``σ_θ = LARGE_SIGMA_BEARING`` and ``σ_ρ = 10`` m, ``P_D = 0.98``, on the 4-D state; the
    clutter is uniform in (bearing, range) over ``(−π, π] × [0, ρ_max]``, ``ρ_max`` the
    distance to the farthest corner (so denser near the sensor, as a radar's is); the filter
    is the EKF. Every bearing occurs: those straight below the sensor wrap across ``±π``.

    Parameters
    ----------
    n_targets : int
        Number of targets (``>= 0``).

    Returns
    -------
    NonlinearModel

    Examples
    --------
    >>> from rankedassign.tracking.presets import large_bearing_range_model
    >>> m = large_bearing_range_model(100)
    >>> m.sensor.sigma_bearing, m.clutter.rate, round(m.clutter.range[1], 1)
    (0.001, 30.0, 1555.6)
    """
    base = large_model(n_targets)
    half = 0.5 * LARGE_CELL * math.sqrt(max(n_targets, 1))
    # the middle of the cell at the origin's upper right: not on a birth place (the first is
    # at the origin, where a bearing is undefined)
    s = 0.5 * LARGE_CELL
    b = base.birth
    return NonlinearModel(
        motion=LinearGaussianMotion.from_motion(base.motion),
        sensor=BearingRange(sigma_bearing=LARGE_SIGMA_BEARING, sigma_range=10.0,
                            sensor_position=(s, s), p_d=base.sensor.p_d, state_ndim=4,
                            position_indices=(0, 2)),
        clutter=BearingRangeClutter(base.clutter.rate, (-math.pi, math.pi),
                                    (0.0, (half + s) * math.sqrt(2.0))),
        birth=tuple(GaussianBirth(float(b.r[i]), b.means[i], b.covs[i])
                    for i in range(b.r.size)),
        p_s=base.survival.p_s, filter=ExtendedKalmanFilter())


def make_scenario(preset: str = "paper", *, rng=None, n_scans: int = 100,
                  n_targets: int | None = None, sensor: str = "position") -> Scenario:
    """A preset's model, its truth and simulated measurements, linear or non-linear.

    Parameters
    ----------
    preset : {"paper", "paper-var", "vo", "large", "vo-ekf", "vo-ukf"}
        The linear presets draw the truth of spec §8, ``"large"`` ``n_targets`` targets at
        constant density (:func:`rankedassign.tracking.scenario.make_scenario`); ``"vo-ekf"``
        and ``"vo-ukf"``
        Vo's ten CT targets (:func:`~rankedassign.tracking.nonlinear.vo_truth`) and his
        bearing–range measurements with clutter uniform in (bearing, range)
        (:func:`~rankedassign.tracking.nonlinear.generate_nonlinear_measurements`).
    rng : optional
        Randomness of the measurements.
    n_scans : int
        Number of scans (default 100, Vo's run length for his examples).
    n_targets : int, optional
        The targets of the ``"large"`` scenario (only there).
    sensor : {"position", "bearing-range"}, optional
        The ``"large"`` scenario's sensor (:data:`LARGE_SENSORS`): Vo's position sensor
        (default), or one bearing–range sensor near the centre of the square
        (:func:`large_bearing_range_model`: the same truth, measurements ``[bearing, range]``).
        Another preset takes its own sensor only.

    Returns
    -------
    Scenario
        For a non-linear preset the truth's states are 5-D ``[p_x, v_x, p_y, v_y, ω]`` and the
        measurements ``[bearing, range]``.

    Examples
    --------
    >>> from rankedassign.tracking import make_scenario
    >>> sc = make_scenario("vo-ekf", rng=0, n_scans=3)
    >>> sc.truth.states.shape, sc.scans[0].z.shape[1]
    ((3, 10, 5), 2)
    """
    preset = check_choice(preset, "preset", (*ALL_PRESETS, "large"))
    sensor = check_choice(sensor, "sensor", LARGE_SENSORS)
    if sensor != "position" and preset != "large":
        raise ValueError(f"sensor is an option of the 'large' scenario only (preset "
                         f"{preset!r} has its own sensor)")
    if sensor == "bearing-range":
        n_scans = check_n_scans(n_scans)
        n_targets = check_n_targets(100 if n_targets is None else n_targets, n_scans)
        model = large_bearing_range_model(n_targets)
        gen = check_rng(rng)
        # the truth of the position sensor's scenario with the same rng (it draws first)
        truth = large_truth(n_targets, n_scans, model.motion.F, gen)
        return Scenario(preset, model, truth,
                        generate_nonlinear_measurements(truth, model, rng=gen))
    if preset not in NONLINEAR_PRESETS:
        # the linear presets and "large" (which checks n_targets)
        return _make_linear_scenario(preset, rng=rng, n_scans=n_scans, n_targets=n_targets)
    if n_targets is not None:
        raise ValueError(f"n_targets is an option of the 'large' scenario only (preset "
                         f"{preset!r} has Vo's ten targets)")
    n_scans = check_n_scans(n_scans)
    model: NonlinearModel = make_nonlinear_model(preset)
    truth = vo_truth(model, n_scans)
    return Scenario(preset, model, truth, generate_nonlinear_measurements(truth, model, rng=rng))

"""The ``"multi"`` scenario (multi-sensor spec §7.2) and a runner for the multi-sensor filter.

The paper's 12-target truth (spec-of-record §8) seen by four linear position sensors:

=======  =====  =====  ======================
sensor   σ (m)  P_D    clutter
=======  =====  =====  ======================
0        10     0.6    Poisson(20), uniform
1        15     0.7    Poisson(20), uniform
2        20     0.8    Poisson(20), uniform
3        10     0.7    Poisson(20), uniform
=======  =====  =====  ======================

on ``[−1000, 1000]²`` (``κ_v = 5·10⁻⁶ m⁻²``), with the paper's motion, survival and static LMB
birth (spec §6.1), or adaptive birth from the measurements (``birth="adaptive"``, spec §7.2).
Each sensor's measurements are drawn from its own random stream, so the measurements of a
sensor do not depend on which other sensors a run uses and runs on subsets of the sensors
compare on the same data.
"""

from __future__ import annotations

import sys
import warnings
from dataclasses import dataclass

import numpy as np

from ...engine.rng import spawning_generator
from ...validation import check_choice
from ..models import LMBBirth, PoissonClutter, PositionSensor, make_model
from ..nonlinear.multisensor import MULTI_NONLINEAR_PRESETS, make_nonlinear_multisensor_model
from ..nonlinear.vo import generate_nonlinear_measurements, vo_truth
from ..scenario import (
    ScenarioRun,
    Truth,
    check_n_scans,
    generate_measurements,
    paper_truth,
)
from .lmb import MultiSensorModel, check_sensors

__all__ = [
    "BIRTHS",
    "MULTI_PRESETS",
    "MULTI_SENSORS",
    "MultiSensorRun",
    "MultiSensorScenario",
    "make_multisensor_model",
    "make_multisensor_scenario",
]

#: ``(σ_v, P_D^v)`` of the four sensors of the ``"multi"`` preset (multi-sensor spec §7.2).
MULTI_SENSORS = ((10.0, 0.6), (15.0, 0.7), (20.0, 0.8), (10.0, 0.7))
#: Mean clutter points per scan and sensor.
MULTI_CLUTTER = 20.0
#: The multi-sensor presets: ``"multi"`` (linear position sensors) and the non-linear
#: ``"multi-bearing-range"``
#: (:func:`~rankedassign.tracking.nonlinear.multisensor.make_nonlinear_multisensor_model`).
MULTI_PRESETS = ("multi", *MULTI_NONLINEAR_PRESETS)


#: Birth models: the paper's static birth (``P_B = diag(300², 10², 300², 10²)``, spec §6.1),
#: the narrow static birth of Vo's example (``P_B = 100 I``), whose birth tracks gate few
#: measurements, so that the exact DP reaches the groups of the filter, and adaptive birth
#: (:class:`~rankedassign.tracking.AdaptiveBirth` with the defaults of spec §7.2;
#: the model then has no static birth).
BIRTHS = ("paper", "narrow", "adaptive")


def __getattr__(name: str):
    # Moved up to rankedassign.tracking.run, above the filters it runs (this module is below
    # them): the old path keeps working for one release, with a warning. The package
    # rankedassign.tracking has loaded the runner before any of its modules can be asked, so
    # it is taken from sys.modules: this module does not depend on the runner above it.
    if name in ("run_multisensor_scenario", "FILTERS"):
        run = sys.modules["rankedassign.tracking.run"]
        warnings.warn(f"rankedassign.tracking.multisensor.scenario.{name} moved to "
                      f"rankedassign.tracking.run.{name} (also rankedassign.tracking."
                      f"{name}); the old path is removed in the next release",
                      DeprecationWarning, stacklevel=2)
        return getattr(run, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def make_multisensor_model(sensors=(0, 1, 2), *, birth: str = "paper") -> MultiSensorModel:
    """The model of the ``"multi"`` preset on the sensors of index ``sensors``.

    Parameters
    ----------
    sensors : sequence of int
        Indices into :data:`MULTI_SENSORS` (default the three sensors of spec §7.2).
    birth : {"paper", "narrow", "adaptive"}
        Birth model (:data:`BIRTHS`); ``"adaptive"`` gives a model without static birth (the
        filter needs ``birth=AdaptiveBirth()`` then).

    Returns
    -------
    MultiSensorModel

    Raises
    ------
    TypeError
        If ``sensors`` is not a sequence of ints (``0.5``, ``True`` and a bare ``5`` are
        refused, :func:`~rankedassign.tracking.multisensor.lmb.check_sensors`).
    ValueError
        On an empty selection, a repeated or an out-of-range index.

    Examples
    --------
    >>> from rankedassign.tracking.multisensor.scenario import make_multisensor_model
    >>> m = make_multisensor_model((0, 2))
    >>> [(s.sigma_v, s.p_d) for s in m.sensors], m.clutters[0].intensity
    ([(10.0, 0.6), (20.0, 0.8)], 5e-06)
    """
    check_choice(birth, "birth", BIRTHS)
    base = make_model("paper")
    static = {"paper": base.birth, "narrow": make_model("vo").birth, "adaptive": LMBBirth(())}
    full = MultiSensorModel(
        base.motion,
        tuple(PositionSensor(p_d, sigma) for sigma, p_d in MULTI_SENSORS),
        tuple(PoissonClutter(MULTI_CLUTTER) for _ in MULTI_SENSORS),
        static[birth],
        base.survival,
    )
    return full.select(sensors)


@dataclass(frozen=True, eq=False)
class MultiSensorScenario:
    """Model, truth and the measurements of the selected sensors.

    Attributes
    ----------
    preset : str
        ``"multi"`` or ``"multi-bearing-range"`` (:data:`MULTI_PRESETS`).
    sensors : tuple of int
        Indices of the selected sensors (into :data:`MULTI_SENSORS`, or the preset's).
    model : MultiSensorModel or NonlinearMultiSensorModel
    truth : Truth
    scans : list of tuple of Scan
        Per scan, one :class:`~rankedassign.tracking.scenario.Scan` per selected sensor.
    """

    preset: str
    sensors: tuple
    model: MultiSensorModel
    truth: Truth
    scans: list


def make_multisensor_scenario(*, rng=None, n_scans: int = 100, sensors=None,
                              birth: str = "paper", preset: str = "multi") -> MultiSensorScenario:
    """A multi-sensor preset's truth and the measurements of the sensors ``sensors``.

    Parameters
    ----------
    rng : optional
        Anything :func:`numpy.random.default_rng` accepts. One child stream per sensor of
        :data:`MULTI_SENSORS` is spawned from it; sensor ``v`` always draws from child ``v``.
        A RandomState is replaced by the Generator seeded with one draw from it
        (:func:`rankedassign.engine.rng.spawning_generator`).
    n_scans : int
        Number of scans (default 100, at most
        :data:`~rankedassign.tracking.scenario.MAX_SCANS`).
    sensors : sequence of int or None
        Which sensors to simulate (distinct indices into :data:`MULTI_SENSORS`, or into the
        non-linear preset's sensors); None: ``(0, 1, 2)`` for ``"multi"``, every sensor of
        ``"multi-bearing-range"``.
    birth : {"paper", "narrow", "adaptive"}
        Birth model of the filter (the measurements do not depend on it); ``"multi"`` only.
    preset : {"multi", "multi-bearing-range"}
        :data:`MULTI_PRESETS`. ``"multi-bearing-range"``: Vo's CT truth
        (:func:`~rankedassign.tracking.nonlinear.vo_truth`) seen by two bearing–range
        sensors, each from its own stream.

    Returns
    -------
    MultiSensorScenario

    Examples
    --------
    >>> from rankedassign.tracking.multisensor.scenario import make_multisensor_scenario
    >>> a = make_multisensor_scenario(rng=1, n_scans=3, sensors=(0, 2))
    >>> b = make_multisensor_scenario(rng=1, n_scans=3, sensors=(2,))
    >>> bool((a.scans[2][1].z == b.scans[2][0].z).all())      # sensor 2 sees the same
    True
    """
    n_scans = check_n_scans(n_scans)
    preset = check_choice(preset, "preset", MULTI_PRESETS)
    if preset != "multi":
        if birth != "paper":
            raise ValueError(f"birth applies to the 'multi' preset only, got birth={birth!r} "
                             f"with preset {preset!r} (its births are Vo's four terms)")
        full = make_nonlinear_multisensor_model(preset)
        sensors = check_sensors(tuple(range(full.n_sensors)) if sensors is None else sensors,
                                full.n_sensors)
        truth = vo_truth(full.single(0), n_scans)
        children = spawning_generator(rng).spawn(full.n_sensors)
        per_sensor = [generate_nonlinear_measurements(truth, full.single(v), rng=children[v])
                      for v in sensors]
        scans = [tuple(s[k] for s in per_sensor) for k in range(n_scans)]
        return MultiSensorScenario(preset, sensors, full.select(sensors), truth, scans)
    sensors = check_sensors((0, 1, 2) if sensors is None else sensors, len(MULTI_SENSORS))
    model = make_multisensor_model(sensors, birth=birth)
    full = make_multisensor_model(range(len(MULTI_SENSORS)))
    truth = paper_truth(n_scans, model.motion.F)
    children = spawning_generator(rng).spawn(len(MULTI_SENSORS))
    per_sensor = [generate_measurements(truth, full.single(v), rng=children[v])
                  for v in sensors]
    scans = [tuple(s[k] for s in per_sensor) for k in range(n_scans)]
    return MultiSensorScenario("multi", sensors, model, truth, scans)


@dataclass(frozen=True, eq=False)
class MultiSensorRun(ScenarioRun):
    """Result of :func:`run_multisensor_scenario` (the fields of
    :class:`~rankedassign.tracking.scenario.ScenarioRun`; ``n_meas`` counts every sensor).

    Attributes
    ----------
    scenario : MultiSensorScenario
        Model, truth and the measurements of the fused sensors.
    association : str
        ``repr`` of the association used.
    extraction : str
        State extraction used (``"hysteresis"`` or ``"map"``).
    truth : ndarray, shape (n_scans, n_targets, 2)
        True positions, NaN where a target does not exist.
    estimates : ndarray, shape (n_scans, n_est_tracks, 2)
        Estimated positions, one column per reported label (order of first report), NaN where
        a label is not reported.
    estimate_labels, labelled_estimates, existence : list
        Labels of the columns of ``estimates``; per scan ``{label: state (4,)}`` of the
        reported tracks; per scan ``{label: r}`` of every track held after the update.
    invocations, sweeps, row_updates, n_unique : ndarray of int64, shape (n_scans,)
        Association accounting per scan (sampler calls, full sweeps, single-row updates,
        unique hypotheses), summed over the groups.
    n_tracks, n_estimated : ndarray of int64, shape (n_scans,)
        Predicted tracks (births included) and reported tracks per scan.
    n_meas, n_meas_gated, n_groups : ndarray of int64, shape (n_scans,)
        Measurements received from all sensors, those inside some track's gate of their
        sensor, and problems solved, per scan.
    n_births : ndarray of int64, shape (n_scans,)
        Birth tracks appended by the prediction of each scan.
    timings : dict of ndarray
        Seconds per scan of each phase (``prediction``, ``cost``, ``association``,
        ``update``, and ``birth``: the adaptive birth, 0 for a static birth).
    """

    scenario: MultiSensorScenario
    n_births: np.ndarray = None

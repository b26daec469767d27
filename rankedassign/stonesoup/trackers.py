"""Stone Soup trackers around our LMB and δ-GLMB filters, built from Stone Soup's models.

The trackers take Stone Soup's linear-Gaussian transition model (``F`` and ``Q`` for each
interval between scans) and any measurement model whose array form
:func:`~rankedassign.stonesoup.models.measurement_from_stonesoup` gives (``LinearGaussian`` of
any state dimension and mapping, ``CartesianToBearingRange``,
``CartesianToElevationBearingRange``, ``Cartesian2DToBearing``), directly or from a Stone Soup
``KalmanPredictor`` and ``KalmanUpdater`` or their extended and unscented forms; the detection
and survival probabilities, the clutter rate and spatial density (``κ``), and either the birth
components as ``WeightedGaussianState`` whose ``weight`` is the existence probability ``r_B``
or, with ``birth_components=None``, births made from the measurements
(:class:`~rankedassign.tracking.birth.MeasurementBirth`, ``birth_options``; a non-linear
sensor places them through its inverse).

Two paths, one interface: a position measurement of a 4-D position-velocity state runs the
filters' compiled linear-Gaussian path (the Kalman filter, whatever the Kalman family of the
predictor and updater: on linear models the three are the same); every other model runs the
non-linear path (:class:`~rankedassign.tracking.nonlinear.NonlinearModel`) with the filter the
predictor and updater map to (Kalman, EKF, UKF), in the state's own order.
"""

from __future__ import annotations

import datetime
import math
from collections.abc import Mapping, Sequence
from typing import NamedTuple

import numpy as np
from stonesoup.base import Property
from stonesoup.models.base import GaussianModel, LinearModel
from stonesoup.models.measurement.base import MeasurementModel
from stonesoup.models.measurement.linear import LinearGaussian
from stonesoup.models.transition.base import TransitionModel
from stonesoup.predictor.base import Predictor
from stonesoup.predictor.kalman import KalmanPredictor
from stonesoup.reader import DetectionReader
from stonesoup.tracker.base import Tracker
from stonesoup.types.detection import Detection
from stonesoup.types.state import GaussianState, State
from stonesoup.types.track import Track
from stonesoup.updater.base import Updater
from stonesoup.updater.kalman import KalmanUpdater

from ..engine.rng import check_rng
from ..tracking import (
    Association,
    BirthComponent,
    ConstantSurvival,
    GLMBFilter,
    LinearMotion,
    LMBBirth,
    LMBFilter,
    MeasurementBirth,
    Model,
    PoissonClutter,
    PositionSensor,
    ShortChainGibbs,
)
from ..tracking.multisensor import MultiSensorGLMBFilter, MultiSensorLMBFilter
from ..tracking.nonlinear import ExtendedKalmanFilter, GaussianBirth, KalmanFilter, NonlinearModel
from ..tracking.nonlinear.multisensor import NonlinearMultiSensorModel
from ..validation import float_array
from .models import (
    filters_from_stonesoup,
    is_constant_turn,
    measurement_from_stonesoup,
    motion_from_stonesoup,
)

__all__ = ["LMBTracker", "GLMBTracker", "MultiSensorLMBTracker", "MultiSensorGLMBTracker"]

_ZERO = datetime.timedelta(0)

#: The parameters a tracker cannot do without (given by keyword, None means missing).
_REQUIRED = ("prob_detection", "clutter_rate", "clutter_spatial_density")


def _is_linear(model) -> bool:
    """Whether a Stone Soup model (and every part of a combined one) is linear-Gaussian."""
    parts = getattr(model, "model_list", None) or [model]
    return all(isinstance(p, LinearModel) and isinstance(p, GaussianModel)
               for p in [model, *parts])


def _check_linear_motion(model, who: str) -> None:
    """Refuse a transition model with no array counterpart (with its name in the message):
    linear-Gaussian models (combined or not) and ``ConstantTurn`` are taken."""
    if is_constant_turn(model):
        return
    parts = getattr(model, "model_list", None) or [model]
    for part in [model, *parts]:
        if not (isinstance(part, LinearModel) and isinstance(part, GaussianModel)):
            raise TypeError(
                f"{who} supports linear-Gaussian transition models and ConstantTurn: the "
                f"transition model {type(part).__name__} is neither (use e.g. "
                "CombinedLinearGaussianTransitionModel of ConstantVelocity models, or "
                "ConstantTurn)"
            )


class _Clutter(NamedTuple):
    """The clutter of the non-linear path: all the filters read is the intensity ``κ``."""

    rate: float
    intensity: float


def _component(obj, role: str, family: type, model_attr: str, who: str):
    """The model a Stone Soup predictor or updater holds, after checking its family."""
    if not isinstance(obj, family):
        kind = "Predictor" if role == "predictor" else "Updater"
        raise TypeError(
            f"{who}: the {role} must be a Kalman-family Stone Soup {kind} (Kalman{kind}, "
            f"ExtendedKalman{kind}, UnscentedKalman{kind}), got {type(obj).__name__}; "
            "our filters hold Gaussian mixtures, so particle and other "
            f"{role}s have no counterpart")
    return getattr(obj, model_attr, None)


def _position_layout(mm, tm, who: str) -> np.ndarray:
    """``perm`` with ``x[perm] = [p_1, v_1, p_2, v_2]``, our filters' state layout.

    The measurement model's ``mapping`` names the two position components; the velocity of
    each is the component the transition model moves it by (``F[p, v] != 0``, ``v`` not a
    position), read off ``F`` of a one-second interval.
    """
    mapping = tuple(int(i) for i in getattr(mm, "mapping", ()))
    n = int(mm.ndim_state)
    hint = ("the filters track a 2-D position and its velocity: the measurement model's "
            "mapping must name the two position components of a 4-D state, each moved by "
            "its own velocity component in the transition model (e.g. mapping (0, 2) of "
            "[x, vx, y, vy])")
    if n != 4 or len(mapping) != 2 or len(set(mapping)) != 2:
        raise ValueError(f"{who}: {hint}; got mapping {mapping} of a {n}-D state")
    F = np.asarray(tm.matrix(time_interval=datetime.timedelta(seconds=1)), float)
    velocity = []
    for p in mapping:
        cand = [v for v in range(4) if v not in mapping and v not in velocity and F[p, v] != 0]
        if len(cand) != 1:
            raise ValueError(f"{who}: {hint}; got mapping {mapping}, and the transition "
                             f"model moves position component {p} by components "
                             f"{tuple(v for v in range(4) if v != p and F[p, v] != 0)}")
        velocity.append(cand[0])
    return np.array([mapping[0], velocity[0], mapping[1], velocity[1]], dtype=np.int64)


def _birth_states(components, who: str, n: int):
    """``(r, m, P)`` of every birth component, checked; ``m`` and ``P`` in the state's order."""
    out = []
    for b, comp in enumerate(components):
        if not isinstance(comp, GaussianState):
            raise TypeError(f"{who}: birth component {b} must be a WeightedGaussianState, got "
                            f"{type(comp).__name__}")
        weight = getattr(comp, "weight", None)
        if weight is None or not 0 < float(weight) < 1:
            have = "no weight" if weight is None else f"weight {float(weight)!r}"
            raise ValueError(
                f"{who}: birth component {b} has {have}, and its weight is the existence "
                "probability r_B of the birth track: give a WeightedGaussianState with "
                "weight in (0, 1)"
            )
        m = np.asarray(comp.state_vector, float).ravel()
        P = np.asarray(comp.covar, float)
        if m.shape != (n,) or P.shape != (n, n):
            raise ValueError(f"{who}: birth component {b} has a state of shape {m.shape} and "
                             f"covariance {P.shape}, the tracker's state is {n}-D")
        out.append((float(weight), m, P))
    return out


def _birth(components, who: str, perm) -> LMBBirth:
    """The birth components as our :class:`~rankedassign.tracking.LMBBirth` (``x[perm]``)."""
    return LMBBirth(tuple(BirthComponent(r, m[perm], P[np.ix_(perm, perm)])
                          for r, m, P in _birth_states(components, who, 4)))


def _same_model(own, mm) -> bool:
    """Whether a detection's measurement model is the tracker's (the same or an equal one)."""
    if own is None or own is mm:
        return True
    if type(own) is not type(mm) or own.ndim_state != mm.ndim_state:
        return False
    if tuple(own.mapping) != tuple(mm.mapping):
        return False
    if not np.array_equal(np.asarray(own.covar(), float), np.asarray(mm.covar(), float)):
        return False
    for attr in ("translation_offset", "rotation_offset"):
        x, y = getattr(own, attr, None), getattr(mm, attr, None)
        if (x is None) != (y is None) or (x is not None and not np.array_equal(
                np.asarray(x, float), np.asarray(y, float))):
            return False
    return True


class _LabeledTracker(Tracker):
    """What :class:`LMBTracker` and :class:`GLMBTracker` share: models, scans, tracks."""

    detector: DetectionReader = Property(
        doc="Source of (time, detections) pairs, e.g. a detection simulator.")
    transition_model: TransitionModel = Property(
        default=None,
        doc="Linear-Gaussian motion of any state dimension (or the predictor's).")
    measurement_model: MeasurementModel = Property(
        default=None,
        doc="LinearGaussian, CartesianToBearingRange, CartesianToElevationBearingRange or "
            "Cartesian2DToBearing (or the updater's).")
    prob_detection: float = Property(default=None, doc="Detection probability P_D in (0, 1].")
    clutter_rate: float = Property(default=None,
                                   doc="Mean number of clutter detections per scan.")
    clutter_spatial_density: float = Property(
        default=None,
        doc="Clutter intensity kappa = rate / area (per unit measurement volume).")
    birth_components: Sequence = Property(
        default=None,
        doc="WeightedGaussianState per birth track; weight = existence probability r_B. None: "
            "births from the measurements (birth_options).")
    prob_survival: float = Property(default=0.99, doc="Survival probability P_S in (0, 1].")
    seed: int = Property(
        default=None,
        doc="Seed of the association's randomness (anything numpy.random.default_rng takes).")
    gate_prob: float = Property(default=0.9999999, doc="Chi-square gate probability.")
    filter_options: dict = Property(
        default_factory=dict, doc="Further keyword arguments of the filter.")
    predictor: Predictor = Property(
        default=None,
        doc="A Stone Soup KalmanPredictor (or Extended/Unscented) whose transition model the "
            "filter uses.")
    updater: Updater = Property(
        default=None,
        doc="A Stone Soup KalmanUpdater (or Extended/Unscented) whose measurement model the "
            "filter uses.")
    birth_options: dict = Property(
        default_factory=dict,
        doc="Keyword arguments of MeasurementBirth (birth_components=None).")

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        who = type(self).__name__
        missing = [name for name in _REQUIRED if getattr(self, name) is None]
        if missing:
            raise TypeError(f"{who} needs {', '.join(missing)}")
        self.transition_model = self._model("transition", self.transition_model,
                                            self.predictor, KalmanPredictor, who)
        self.measurement_model = self._model("measurement", self.measurement_model,
                                             self.updater, KalmanUpdater, who)
        _check_linear_motion(self.transition_model, who)
        mm = self.measurement_model
        n = int(mm.ndim_state)
        if self.transition_model.ndim_state != n:
            raise ValueError(f"{who}: the transition model has a "
                             f"{self.transition_model.ndim_state}-D state, the measurement "
                             f"model a {n}-D one")
        # the single-object filter the predictor and updater map to (refuses a particle or
        # square-root component by name)
        try:
            single = filters_from_stonesoup(self.predictor, self.updater, n)
        except TypeError as exc:
            raise TypeError(f"{who}: {exc}") from None
        density = float(self.clutter_spatial_density)
        if not (math.isfinite(density) and density > 0):
            raise ValueError(f"{who}: clutter_spatial_density must be a positive finite "
                             f"number, got {density!r}")
        rate = float(self.clutter_rate)
        if self.birth_components is None:
            if not isinstance(self.birth_options, Mapping):
                raise TypeError(f"{who}: birth_options must be a dict of MeasurementBirth's "
                                f"keyword arguments, got {type(self.birth_options).__name__}")
            measurement_birth = MeasurementBirth(**self.birth_options)
        else:
            measurement_birth = None
        #: False: the compiled linear path on ``[p_1, v_1, p_2, v_2]``; True: the non-linear
        #: path (NonlinearModel) in the state's own order.
        self._nonlinear = not (isinstance(mm, LinearGaussian) and len(mm.mapping) == 2
                               and n == 4 and _is_linear(self.transition_model))
        if self._nonlinear:
            model = self._nonlinear_model(single, rate, density, measurement_birth, who)
        else:
            model = self._linear_model(rate, density, measurement_birth, who)
        #: The measurement-driven birth in use (birth_components=None), or None.
        self.measurement_birth = measurement_birth
        options = dict(self.filter_options)
        if measurement_birth is not None:
            options["birth"] = measurement_birth
        try:
            self.filter = self._make_filter(model, options)
        except ValueError as exc:  # e.g. a birth prior of the wrong dimension: name the tracker
            raise ValueError(f"{who}: {exc}") from None
        self._start(who)

    def _start(self, who: str) -> None:
        """The generator of the association's randomness and the empty track table."""
        try:
            self._rng = check_rng(self.seed)
        except (TypeError, ValueError) as exc:  # its message names rng, the argument is seed
            raise type(exc)(f"{who}: seed must be None, a non-negative int or anything "
                            f"numpy.random.default_rng accepts, got {type(self.seed).__name__} "
                            f"{self.seed!r}") from None
        self._by_label = {}
        self._current = set()
        self._time = None
        self._interval = _ZERO
        self.detector_iter = None

    def _linear_model(self, rate, density, measurement_birth, who) -> Model:
        """Our linear :class:`~rankedassign.tracking.Model` on ``[p_1, v_1, p_2, v_2]``."""
        mm = self.measurement_model
        #: ``x[_perm]`` is a Stone Soup state in our layout ``[p_1, v_1, p_2, v_2]``.
        self._perm = _position_layout(mm, self.transition_model, who)
        # our clutter model is a rate on a region; a square of area rate / density has the
        # tracker's intensity (the filters use nothing else of the region)
        side = math.sqrt(rate / density) if rate > 0 else 1.0
        birth = (LMBBirth(()) if measurement_birth is not None
                 else _birth(self.birth_components, who, self._perm))
        return Model(
            self._motion(_ZERO),
            PositionSensor(float(self.prob_detection), noise_cov=np.asarray(mm.covar(), float)),
            PoissonClutter(rate, ((0.0, side), (0.0, side))),
            birth,
            ConstantSurvival(float(self.prob_survival)),
        )

    def _nonlinear_model(self, single, rate, density, measurement_birth, who) -> NonlinearModel:
        """A :class:`~rankedassign.tracking.nonlinear.NonlinearModel` in the state's order."""
        mm = self.measurement_model
        n = int(mm.ndim_state)
        self._perm = np.arange(n)
        p_d = float(self.prob_detection)
        if not 0 < p_d <= 1:
            raise ValueError(f"{who}: prob_detection must be in (0, 1], got {p_d!r}")
        p_s = float(self.prob_survival)
        if not 0 < p_s <= 1:
            raise ValueError(f"{who}: prob_survival must be in (0, 1], got {p_s!r}")
        if not (math.isfinite(rate) and rate >= 0):
            raise ValueError(f"{who}: clutter_rate must be a non-negative finite number, got "
                             f"{rate!r}")
        try:
            sensor = measurement_from_stonesoup(mm, p_d)
        except TypeError as exc:
            raise TypeError(f"{who}: {exc}") from None
        except ValueError as exc:
            raise ValueError(f"{who}: {exc}") from None
        if len(mm.mapping) != len(set(mm.mapping)):
            raise ValueError(f"{who}: the measurement model's mapping {tuple(mm.mapping)} "
                             "repeats a state component")
        if measurement_birth is not None and not getattr(sensor, "linear", False) \
                and not callable(getattr(sensor, "inverse", None)):
            raise TypeError(f"{who}: births from the measurements need the measurement "
                            f"model's inverse (a position from a detection): "
                            f"{type(mm).__name__} has none (a bearing alone does not place a "
                            "target); give birth_components")
        if single is None:   # no predictor nor updater: Stone Soup's usual pick for the model
            single = KalmanFilter() if getattr(sensor, "linear", False) \
                and _is_linear(self.transition_model) else \
                ExtendedKalmanFilter()
        if measurement_birth is not None:
            birth = ()
        else:
            birth = tuple(GaussianBirth(r, m, P)
                          for r, m, P in _birth_states(self.birth_components, who, n))
        return NonlinearModel(motion=motion_from_stonesoup(self.transition_model, _ZERO),
                              sensor=sensor, clutter=_Clutter(rate, density), birth=birth,
                              p_s=p_s, filter=single)

    @staticmethod
    def _model(role: str, model, component, family: type, who: str):
        """The transition or measurement model: given, or read from the predictor/updater."""
        if component is None:
            if model is None:
                raise TypeError(f"{who} needs a {role}_model or "
                                + ("a predictor" if role == "transition" else "an updater")
                                + " that holds one")
            return model
        name = "predictor" if role == "transition" else "updater"
        held = _component(component, name, family, f"{role}_model", who)
        if model is None:
            if held is None:
                raise TypeError(f"{who}: the {name} {type(component).__name__} holds no "
                                f"{role}_model; give {role}_model")
            return held
        if held is not None and held is not model:
            raise ValueError(f"{who}: {role}_model is not the {name}'s {role}_model; give "
                             "one of them")
        return model

    def _make_filter(self, model, options):  # pragma: no cover (abstract)
        raise NotImplementedError

    def _motion(self, interval: datetime.timedelta):
        tm = self.transition_model
        if getattr(self, "_nonlinear", False):
            return motion_from_stonesoup(tm, interval)
        p = self._perm
        F = np.asarray(tm.matrix(time_interval=interval), float)
        Q = np.asarray(tm.covar(time_interval=interval), float)
        return LinearMotion(F[np.ix_(p, p)], Q[np.ix_(p, p)])

    @property
    def tracks(self) -> set:
        """The tracks reported at the latest scan."""
        return set(self._current)

    def __iter__(self):
        if self.detector is None:
            raise AttributeError(f"{type(self).__name__} has no detector to iterate over")
        if self.detector_iter is None:
            self.detector_iter = iter(self.detector)
        return self

    def __next__(self):
        time, detections = next(self.detector_iter)
        return self.update_tracker(time, detections)

    def _measurements(self, time, detections) -> np.ndarray:
        """The detections as an ``(M, d_z)`` array, checked against the measurement model."""
        mm = self.measurement_model
        rows = [self._row(time, det) for det in self._detections(time, detections)]
        for det, _ in rows:
            if not _same_model(det.measurement_model, mm):
                own = det.measurement_model
                raise ValueError(
                    f"{type(self).__name__}: a detection at {time} has measurement model "
                    f"{type(own).__name__} (mapping {tuple(getattr(own, 'mapping', ()))}), "
                    "not the tracker's measurement_model; the filter applies its own model "
                    "to every detection"
                )
        return self._stack([z for _, z in rows], mm)

    def _detections(self, time, detections):
        """The scan's detections, after checking that it is a collection of ``Detection``."""
        who = type(self).__name__
        if (isinstance(detections, (str, bytes, Mapping, np.ndarray))
                or not hasattr(detections, "__iter__")):
            raise TypeError(f"{who}: detections must be a set (or list) of Detection, got "
                            f"{type(detections).__name__}"
                            + ("; an empty scan is set()" if detections is None else ""))
        out = list(detections)
        for det in out:
            if not isinstance(det, Detection):
                raise TypeError(f"{who}: detections must hold Detection objects (with a "
                                f"state_vector and a measurement_model), got "
                                f"{type(det).__name__} {det!r} in a scan at {time}")
        return out

    def _row(self, time, det, mm=None):
        """``(det, z)``: a detection's state vector as a float array (finiteness checked)."""
        who = type(self).__name__
        z = float_array(det.state_vector, f"{who}: the state_vector of a detection at "
                        f"{time}").reshape(-1)
        mm = self.measurement_model if mm is None else mm
        if mm is not None and z.size != mm.ndim_meas:
            raise ValueError(f"{who}: a detection at {time} has {z.size} dimensions, the "
                             f"measurement model gives {mm.ndim_meas}")
        if not np.isfinite(z).all():
            raise ValueError(f"{who}: a detection at {time} has a non-finite state "
                             f"vector {z.tolist()}")
        return det, z

    @staticmethod
    def _stack(rows, mm) -> np.ndarray:
        # sorted, so that a seed gives the same result whatever the set's order
        rows.sort(key=tuple)
        return np.array(rows, dtype=np.float64).reshape(-1, mm.ndim_meas)

    def update_tracker(self, time, detections):
        """Run one scan of the filter on ``detections`` at ``time``.

        Parameters
        ----------
        time : datetime.datetime
            Time of the scan (after the previous one; the motion model is evaluated on the
            interval).
        detections : set of stonesoup.types.detection.Detection
            The scan's detections (may be empty).

        Returns
        -------
        time : datetime.datetime
            ``time``.
        tracks : set of stonesoup.types.track.Track
            The tracks reported at this scan; a track's ``id`` is its label ``"k:b"`` (born
            at scan ``k`` from birth component ``b``, both 1-based) and the same label
            continues the same ``Track``; its ``metadata`` holds ``"existence"`` and
            ``"label"``.

        Raises
        ------
        TypeError
            If ``time`` is not a ``datetime.datetime`` (``None``, a number), ``detections`` is
            not a collection of ``Detection`` (``None``, an array, a list of tuples), or a
            detection's state vector is not real (complex, strings).
        ValueError
            If a detection has another measurement model, the wrong dimension or a NaN or
            infinite state vector, or if ``time`` is before the previous scan.
        """
        if not isinstance(time, datetime.datetime):
            # Stone Soup's times are datetimes; None or a number would give a zero or
            # meaningless interval for the motion model
            raise TypeError(f"{type(self).__name__}: time must be a datetime.datetime, got "
                            f"{type(time).__name__} {time!r}")
        z = self._measurements(time, detections)
        interval = _ZERO if self._time is None else time - self._time
        if interval < _ZERO:
            raise ValueError(f"{type(self).__name__}: scan time {time} is before the previous "
                             f"scan's {self._time}")
        if interval != self._interval:
            self.filter.set_motion(self._motion(interval))
            self._interval = interval
        self._time = time
        rec = self.filter.step(z, rng=self._rng)
        self._current = set()
        for label, x, r in zip(rec.labels, rec.states, rec.existence, strict=True):
            key = (int(label[0]), int(label[1]))
            track = self._by_label.get(key)
            if track is None:
                track = self._by_label[key] = Track(id=f"{key[0]}:{key[1]}")
            P = self._covariance(key, x)
            # back from our layout [p_1, v_1, p_2, v_2] to the state's own order (the
            # identity on the non-linear path)
            p = self._perm
            ours = np.asarray(x, dtype=np.float64)
            x = np.empty(p.size)
            x[p] = ours
            if P is not None:
                P_ours, P = P, np.empty((p.size, p.size))
                P[np.ix_(p, p)] = P_ours
            sv = x.reshape(-1, 1)
            state = (State(sv, timestamp=time) if P is None
                     else GaussianState(sv, P, timestamp=time))
            track.append(state)
            track.metadata.update({"existence": float(r), "label": key})
            self._current.add(track)
        return time, self.tracks

    def _covariance(self, key, x):
        """Covariance of the filter's component whose mean is the reported state ``x``."""
        f = self.filter
        for e in np.flatnonzero((f.labels[:, 0] == key[0]) & (f.labels[:, 1] == key[1])):
            c = f.offsets[e]
            if np.array_equal(f.m[c], x):
                return np.array(f.P[c])
        return None




class LMBTracker(_LabeledTracker):
    """Labeled multi-Bernoulli tracker: our :class:`~rankedassign.tracking.LMBFilter` in Stone Soup.

    Iterated as ``for time, tracks in tracker``, it pulls each scan from ``detector``, runs
    one step of the LMB filter (joint prediction and update, with ``association`` solving
    each group's ranked-assignment problem) and yields the tracks it reports.

    Parameters
    ----------
    detector : stonesoup.reader.DetectionReader
        Source of ``(time, detections)`` pairs (a detection simulator, a reader, or any
        iterable of such pairs).
    transition_model : stonesoup.models.transition.linear.CombinedLinearGaussianTransitionModel
        Linear-Gaussian motion of any state dimension (e.g. two or three
        ``ConstantVelocity``); ``F`` and ``Q`` are taken for each interval between scans.
        Optional with a ``predictor`` (its ``transition_model`` is used).
    measurement_model : stonesoup.models.measurement.base.MeasurementModel
        ``LinearGaussian`` (any state dimension and ``mapping``),
        ``CartesianToBearingRange``, ``CartesianToElevationBearingRange`` or
        ``Cartesian2DToBearing`` (:func:`rankedassign.stonesoup.models.measurement_from_stonesoup`).
        A position measurement of a 4-D position-velocity state (``mapping`` ``(0, 2)`` of
        ``[x, vx, y, vy]``, ``(0, 1)`` of ``[x, y, vx, vy]``) runs the filters' compiled
        linear path; every other model the non-linear path, in the state's own order.
        Optional with an ``updater`` (its ``measurement_model``).
    prob_detection : float
        Detection probability ``P_D`` in ``(0, 1]`` (required).
    clutter_rate : float
        Mean number of clutter detections per scan, ``> 0`` (required).
    clutter_spatial_density : float
        Clutter intensity ``κ`` per unit measurement area, ``> 0`` (a detection simulator's
        ``clutter_spatial_density``; required).
    birth_components : sequence of stonesoup.types.state.WeightedGaussianState or None
        One per birth track of every scan; ``weight`` is its existence probability ``r_B`` in
        ``(0, 1)``. None (default): no births placed by hand; every detection of a scan that
        the tracks do not explain starts a birth track of the next scan
        (:class:`~rankedassign.tracking.birth.MeasurementBirth` with ``birth_options``).
    prob_survival : float, optional
        Survival probability ``P_S`` in ``(0, 1]`` (default 0.99).
    seed : int, optional
        Seed of the association's randomness (anything :func:`numpy.random.default_rng`
        accepts; None, the default, draws fresh entropy): one generator made from it at
        construction gives every scan's ``rng``.
    gate_prob : float, optional
        χ² gate probability (default ``1 - 1e-7``); None disables gating.
    filter_options : dict, optional
        Further keyword arguments of the filter (e.g. ``max_components``).
    predictor : stonesoup.predictor.kalman.KalmanPredictor, optional
        A Stone Soup ``KalmanPredictor``, ``ExtendedKalmanPredictor`` or
        ``UnscentedKalmanPredictor``: the filter predicts with its ``transition_model``, as
        it does (the unscented one with its ``alpha``, ``beta``, ``kappa``; on the linear
        path the three are the Kalman prediction, which ours computes).
    updater : stonesoup.updater.kalman.KalmanUpdater, optional
        A Stone Soup ``KalmanUpdater``, ``ExtendedKalmanUpdater`` or
        ``UnscentedKalmanUpdater``: the filter updates with its ``measurement_model``, as it
        does (Kalman, EKF or UKF on our arrays). Neither given: the Kalman filter on a
        linear model, the EKF on a non-linear one.
    birth_options : dict, optional
        Keyword arguments of :class:`~rankedassign.tracking.birth.MeasurementBirth`
        (``lambda_b``, ``r_max``, ``velocity_mean``, ``velocity_cov``, ...) when
        ``birth_components`` is None; the velocity prior is in the order of the state's
        unmeasured components (those the measurement model's mapping does not name). A
        non-linear sensor places a birth through its inverse (bearing and range to a
        position, the covariance by linearisation); a bearing-only one has none and needs
        ``birth_components``.
    association : rankedassign.tracking.Association, optional
        Any of our single-sensor associations (default ``ShortChainGibbs(400, 25,
        tau_stall=5, tau_stale=10, marginals="rao-blackwell")``; ``Exact()`` for the exact
        update).
    extraction : {"map", "hysteresis"}, optional
        State extraction (default ``"map"``, Vo's: the MAP cardinality's most likely
        tracks; ``"hysteresis"``, the paper's).

    Attributes
    ----------
    filter : rankedassign.tracking.LMBFilter
        The filter (grouping on: independent groups of tracks are separate problems).
    tracks : set of stonesoup.types.track.Track
        The tracks reported at the latest scan.

    Raises
    ------
    TypeError
        If the transition model is not linear-Gaussian or the measurement model has no
        array form (the message names the class and what is missing), the predictor or
        updater is not of the Kalman family (a particle or square-root predictor or updater:
        the message names its class), births from the measurements are asked of a sensor
        without an inverse (``Cartesian2DToBearing``), a required parameter or model is
        missing, a birth component is not a ``GaussianState``, or ``seed`` is of a kind numpy
        cannot seed from (the message names ``seed``); from :meth:`update_tracker`, on a
        ``time`` that is not a datetime or detections that are not a collection of
        ``Detection``.
    ValueError
        If a 4-D linear position measurement's mapping names no position with a velocity,
        a model given is not the predictor's or updater's, a birth component has no
        existence probability (its weight is not in ``(0, 1)``) or the wrong dimension, a
        birth option (a prior of the wrong dimension) or a probability, rate or density is
        out of range; from :meth:`update_tracker`, on detections of another measurement
        model, of the wrong dimension or not finite.

    Notes
    -----
    A track's state is the mean of its heaviest Gaussian component, as a ``GaussianState``
    with that component's covariance; its existence probability is in its ``metadata``.
    Spec §6 describes the filter.

    References
    ----------
    .. [1] S. Reuter, B.-T. Vo, B.-N. Vo, K. Dietmayer, "The Labeled Multi-Bernoulli Filter",
       IEEE Trans. Signal Process. 62(12), 2014.
    .. [2] A. Trezza, D. J. Bucci Jr., P. K. Varshney, "On Gibbs Sampling Architecture for
       Labeled Random Finite Sets Multi-Object Tracking", arXiv:2306.15135, 2023.

    Examples
    --------
    >>> import datetime
    >>> import numpy as np
    >>> from stonesoup.models.measurement.linear import LinearGaussian
    >>> from stonesoup.models.transition.linear import (
    ...     CombinedLinearGaussianTransitionModel, ConstantVelocity)
    >>> from stonesoup.types.detection import Detection
    >>> from stonesoup.types.state import WeightedGaussianState
    >>> from rankedassign.stonesoup import LMBTracker
    >>> from rankedassign.tracking import Exact
    >>> cv = CombinedLinearGaussianTransitionModel([ConstantVelocity(0.5)] * 2)
    >>> mm = LinearGaussian(ndim_state=4, mapping=(0, 2), noise_covar=np.eye(2))
    >>> t0 = datetime.datetime(2025, 1, 1)
    >>> scans = [(t0 + datetime.timedelta(seconds=k),
    ...           {Detection([[k * 1.0], [0.0]], timestamp=t0 + datetime.timedelta(seconds=k),
    ...                      measurement_model=mm)}) for k in range(5)]
    >>> birth = [WeightedGaussianState([[0], [0], [0], [0]], np.diag([4.0, 4, 4, 4]),
    ...                                weight=0.1)]
    >>> tracker = LMBTracker(scans, cv, mm, prob_detection=0.9, clutter_rate=1.0,
    ...                      clutter_spatial_density=1e-4, birth_components=birth,
    ...                      association=Exact())
    >>> for time, tracks in tracker:
    ...     pass
    >>> [(t.id, len(t), round(t.metadata["existence"], 3)) for t in tracks]
    [('1:1', 5, 1.0)]
    """

    association: Association = Property(
        default_factory=lambda: ShortChainGibbs(400, 25, tau_stall=5, tau_stale=10,
                                                marginals="rao-blackwell"),
        doc="Our association of every group's problem.")
    extraction: str = Property(default="map", doc='State extraction: "map" or "hysteresis".')

    def _make_filter(self, model, options):
        return LMBFilter(model, self.association, gate_prob=self.gate_prob, grouping=True,
                         extraction=self.extraction, **options)



class GLMBTracker(_LabeledTracker):
    """δ-GLMB tracker: our :class:`~rankedassign.tracking.GLMBFilter` in Stone Soup.

    As :class:`LMBTracker`, with the δ-GLMB filter's joint prediction and update: every
    GLMB component's problem is truncated by ``association`` (a sampler, Murty or
    enumeration), so hypotheses are kept jointly rather than as per-track marginals.

    Parameters
    ----------
    detector : stonesoup.reader.DetectionReader
        Source of ``(time, detections)`` pairs (a detection simulator, a reader, or any
        iterable of such pairs).
    transition_model : stonesoup.models.transition.linear.CombinedLinearGaussianTransitionModel
        Linear-Gaussian motion of any state dimension (e.g. two or three
        ``ConstantVelocity``); ``F`` and ``Q`` are taken for each interval between scans.
        Optional with a ``predictor`` (its ``transition_model`` is used).
    measurement_model : stonesoup.models.measurement.base.MeasurementModel
        ``LinearGaussian`` (any state dimension and ``mapping``),
        ``CartesianToBearingRange``, ``CartesianToElevationBearingRange`` or
        ``Cartesian2DToBearing`` (:func:`rankedassign.stonesoup.models.measurement_from_stonesoup`).
        A position measurement of a 4-D position-velocity state (``mapping`` ``(0, 2)`` of
        ``[x, vx, y, vy]``, ``(0, 1)`` of ``[x, y, vx, vy]``) runs the filters' compiled
        linear path; every other model the non-linear path, in the state's own order.
        Optional with an ``updater`` (its ``measurement_model``).
    prob_detection : float
        Detection probability ``P_D`` in ``(0, 1]`` (required).
    clutter_rate : float
        Mean number of clutter detections per scan, ``> 0`` (required).
    clutter_spatial_density : float
        Clutter intensity ``κ`` per unit measurement area, ``> 0`` (a detection simulator's
        ``clutter_spatial_density``; required).
    birth_components : sequence of stonesoup.types.state.WeightedGaussianState or None
        One per birth track of every scan; ``weight`` is its existence probability ``r_B`` in
        ``(0, 1)``. None (default): no births placed by hand; every detection of a scan that
        the tracks do not explain starts a birth track of the next scan
        (:class:`~rankedassign.tracking.birth.MeasurementBirth` with ``birth_options``).
    prob_survival : float, optional
        Survival probability ``P_S`` in ``(0, 1]`` (default 0.99).
    seed : int, optional
        Seed of the association's randomness (anything :func:`numpy.random.default_rng`
        accepts; None, the default, draws fresh entropy): one generator made from it at
        construction gives every scan's ``rng``.
    gate_prob : float, optional
        χ² gate probability (default ``1 - 1e-7``); None disables gating.
    filter_options : dict, optional
        Further keyword arguments of the filter (e.g. ``max_components``).
    predictor : stonesoup.predictor.kalman.KalmanPredictor, optional
        A Stone Soup ``KalmanPredictor``, ``ExtendedKalmanPredictor`` or
        ``UnscentedKalmanPredictor``: the filter predicts with its ``transition_model``, as
        it does (the unscented one with its ``alpha``, ``beta``, ``kappa``; on the linear
        path the three are the Kalman prediction, which ours computes).
    updater : stonesoup.updater.kalman.KalmanUpdater, optional
        A Stone Soup ``KalmanUpdater``, ``ExtendedKalmanUpdater`` or
        ``UnscentedKalmanUpdater``: the filter updates with its ``measurement_model``, as it
        does (Kalman, EKF or UKF on our arrays). Neither given: the Kalman filter on a
        linear model, the EKF on a non-linear one.
    birth_options : dict, optional
        Keyword arguments of :class:`~rankedassign.tracking.birth.MeasurementBirth`
        (``lambda_b``, ``r_max``, ``velocity_mean``, ``velocity_cov``, ...) when
        ``birth_components`` is None; the velocity prior is in the order of the state's
        unmeasured components (those the measurement model's mapping does not name). A
        non-linear sensor places a birth through its inverse (bearing and range to a
        position, the covariance by linearisation); a bearing-only one has none and needs
        ``birth_components``.
    association : rankedassign.tracking.Association, optional
        ``OriginalGibbs``, ``ShortChainGibbs``, ``Murty`` or ``Exact`` (default
        ``ShortChainGibbs(400, 25, tau_stall=5, tau_stale=10)``).
    extraction : {"map", "trajectory", "recursive", "hysteresis"}, optional
        State extraction of the filter (default ``"map"``, Vo's).

    Attributes
    ----------
    filter : rankedassign.tracking.GLMBFilter
        The filter.
    tracks : set of stonesoup.types.track.Track
        The tracks reported at the latest scan.

    Raises
    ------
    TypeError
        As :class:`LMBTracker`; also if ``association`` gives no hypotheses.
    ValueError
        As :class:`LMBTracker`.

    Notes
    -----
    A track's state is the mean of the heaviest Gaussian of its entry in the heaviest
    component of the MAP cardinality, a ``GaussianState`` with that Gaussian's covariance.

    References
    ----------
    .. [1] B.-N. Vo, B.-T. Vo, H. G. Hoang, "An Efficient Implementation of the Generalized
       Labeled Multi-Bernoulli Filter", IEEE Trans. Signal Process. 65(8), 2017.
    .. [2] B.-T. Vo, B.-N. Vo, "Labeled Random Finite Sets and Multi-Object Conjugate
       Priors", IEEE Trans. Signal Process. 61(13), 2013.

    Examples
    --------
    >>> import datetime
    >>> import numpy as np
    >>> from stonesoup.models.measurement.linear import LinearGaussian
    >>> from stonesoup.models.transition.linear import (
    ...     CombinedLinearGaussianTransitionModel, ConstantVelocity)
    >>> from stonesoup.types.detection import Detection
    >>> from stonesoup.types.state import WeightedGaussianState
    >>> from rankedassign.stonesoup import GLMBTracker
    >>> from rankedassign.tracking import Murty
    >>> cv = CombinedLinearGaussianTransitionModel([ConstantVelocity(0.5)] * 2)
    >>> mm = LinearGaussian(ndim_state=4, mapping=(0, 2), noise_covar=np.eye(2))
    >>> t0 = datetime.datetime(2025, 1, 1)
    >>> scans = [(t0 + datetime.timedelta(seconds=k),
    ...           {Detection([[k * 1.0], [0.0]], timestamp=t0 + datetime.timedelta(seconds=k),
    ...                      measurement_model=mm)}) for k in range(5)]
    >>> birth = [WeightedGaussianState([[0], [0], [0], [0]], np.diag([4.0, 4, 4, 4]),
    ...                                weight=0.1)]
    >>> tracker = GLMBTracker(scans, cv, mm, prob_detection=0.9, clutter_rate=1.0,
    ...                       clutter_spatial_density=1e-4, birth_components=birth,
    ...                       association=Murty(50))
    >>> for time, tracks in tracker:
    ...     pass
    >>> [(t.id, len(t)) for t in tracks]
    [('1:1', 5)]
    """

    association: Association = Property(
        default_factory=lambda: ShortChainGibbs(400, 25, tau_stall=5, tau_stale=10),
        doc="Our truncation of every GLMB component's problem.")
    extraction: str = Property(default="map",
                               doc='State extraction: "map", "trajectory", "recursive" or '
                                   '"hysteresis".')

    def _make_filter(self, model, options):
        return GLMBFilter(model, self.association, gate_prob=self.gate_prob,
                          extraction=self.extraction, **options)



def _per_sensor(value, name: str, V: int, who: str) -> tuple:
    """A parameter given once for every sensor or once per sensor, as ``V`` floats."""
    values = tuple(value) if isinstance(value, Sequence) and not isinstance(value, str) \
        else (value,) * V
    if len(values) != V:
        raise ValueError(f"{who}: {name} must be one number or one per sensor ({V}), got "
                         f"{len(values)}")
    return tuple(float(v) for v in values)


class _MultiSensorTracker(_LabeledTracker):
    """What :class:`MultiSensorLMBTracker` and :class:`MultiSensorGLMBTracker` share."""

    measurement_models: Sequence = Property(
        default=None,
        doc="One measurement model per sensor; a detection's own measurement_model names its "
            "sensor.")

    def __init__(self, *args, **kwargs):
        Tracker.__init__(self, *args, **kwargs)
        who = type(self).__name__
        missing = [name for name in _REQUIRED if getattr(self, name) is None]
        if missing:
            raise TypeError(f"{who} needs {', '.join(missing)}")
        if self.measurement_model is not None:
            raise TypeError(f"{who} takes measurement_models (one per sensor), not "
                            "measurement_model")
        models = self.measurement_models
        if isinstance(models, (str, bytes)) or not isinstance(models, Sequence) or not models:
            raise TypeError(f"{who} needs measurement_models: a sequence of one measurement "
                            f"model per sensor, got {type(models).__name__}")
        self.measurement_models = models = tuple(models)
        V = len(models)
        self.transition_model = self._model("transition", self.transition_model,
                                            self.predictor, KalmanPredictor, who)
        if self.updater is not None:     # its family; every sensor's model is its own
            _component(self.updater, "updater", KalmanUpdater, "measurement_model", who)
        _check_linear_motion(self.transition_model, who)
        n = int(self.transition_model.ndim_state)
        for v, mm in enumerate(models):
            if int(getattr(mm, "ndim_state", -1)) != n:
                raise ValueError(f"{who}: the transition model has a {n}-D state, the "
                                 f"measurement model of sensor {v} "
                                 f"({type(mm).__name__}) a {getattr(mm, 'ndim_state', None)}-D "
                                 "one")
        try:
            single = filters_from_stonesoup(self.predictor, self.updater, n)
        except TypeError as exc:
            raise TypeError(f"{who}: {exc}") from None
        if self.birth_components is None:
            raise TypeError(f"{who} needs birth_components: births from the measurements of "
                            "several sensors are not wired here (the multi-sensor filters' "
                            "AdaptiveBirth takes only a linear MultiSensorModel of a 4-D "
                            "state)")
        p_d = _per_sensor(self.prob_detection, "prob_detection", V, who)
        rates = _per_sensor(self.clutter_rate, "clutter_rate", V, who)
        densities = _per_sensor(self.clutter_spatial_density, "clutter_spatial_density", V,
                                who)
        for name, values, ok in (("prob_detection", p_d, lambda x: 0 < x <= 1),
                                 ("clutter_rate", rates, lambda x: 0 <= x < math.inf),
                                 ("clutter_spatial_density", densities,
                                  lambda x: 0 < x < math.inf)):
            bad = [x for x in values if not ok(x)]
            if bad:
                raise ValueError(f"{who}: {name} out of range: {bad[0]!r}")
        p_s = float(self.prob_survival)
        if not 0 < p_s <= 1:
            raise ValueError(f"{who}: prob_survival must be in (0, 1], got {p_s!r}")
        sensors = []
        for v, mm in enumerate(models):
            try:
                sensors.append(measurement_from_stonesoup(mm, p_d[v]))
            except (TypeError, ValueError) as exc:
                raise type(exc)(f"{who}: sensor {v}: {exc}") from None
        if single is None:
            single = (KalmanFilter() if all(getattr(s, "linear", False) for s in sensors)
                      and _is_linear(self.transition_model)
                      else ExtendedKalmanFilter())
        birth = tuple(GaussianBirth(r, m, P)
                      for r, m, P in _birth_states(self.birth_components, who, n))
        model = NonlinearMultiSensorModel(
            motion=motion_from_stonesoup(self.transition_model, _ZERO), sensors=tuple(sensors),
            clutters=tuple(_Clutter(r, d) for r, d in zip(rates, densities, strict=True)),
            birth=birth, p_s=p_s, filter=single)
        self._nonlinear = True
        self._perm = np.arange(n)
        #: No measurement-driven birth in the multi-sensor trackers.
        self.measurement_birth = None
        try:
            self.filter = self._make_filter(model, dict(self.filter_options))
        except ValueError as exc:
            raise ValueError(f"{who}: {exc}") from None
        self._start(who)

    def _measurements(self, time, detections) -> list:
        """Every sensor's detections as an ``(M_v, d_z^v)`` array: a detection's sensor is the
        one whose measurement model is its own (the same object or an equal model)."""
        who = type(self).__name__
        models = self.measurement_models
        rows = [[] for _ in models]
        for det in self._detections(time, detections):
            own = det.measurement_model
            if own is None:
                if len(models) > 1:
                    raise ValueError(f"{who}: a detection at {time} has no measurement_model; "
                                     "with several sensors each detection names its sensor's")
                v = 0
            else:
                v = next((i for i, mm in enumerate(models) if own is mm), None)
                if v is None:
                    v = next((i for i, mm in enumerate(models) if _same_model(own, mm)), None)
                if v is None:
                    raise ValueError(
                        f"{who}: a detection at {time} has measurement model "
                        f"{type(own).__name__} (mapping {tuple(getattr(own, 'mapping', ()))}), "
                        "none of the tracker's measurement_models")
            rows[v].append(self._row(time, det, models[v])[1])
        return [self._stack(r, mm) for r, mm in zip(rows, models, strict=True)]


_MS_DOC = """

    Parameters
    ----------
    detector : stonesoup.reader.DetectionReader
        Source of ``(time, detections)`` pairs; the detections of every sensor of a scan
        together, each ``Detection`` with its sensor's ``measurement_model``.
    transition_model : stonesoup.models.base.LinearModel
        Linear-Gaussian motion of any state dimension (or the ``predictor``'s).
    measurement_models : sequence of stonesoup.models.measurement.base.MeasurementModel
        One per sensor, each as the single-sensor trackers take it (``LinearGaussian``,
        ``CartesianToBearingRange``, ``CartesianToElevationBearingRange``,
        ``Cartesian2DToBearing``), all of the transition model's state.
    prob_detection, clutter_rate, clutter_spatial_density : float or sequence of float
        One number for every sensor or one per sensor (required).
    birth_components : sequence of stonesoup.types.state.WeightedGaussianState
        The static births (required: births from the measurements are single-sensor here).
    prob_survival, seed, gate_prob, filter_options, association, extraction
        As the single-sensor tracker.
    predictor : stonesoup.predictor.kalman.KalmanPredictor, optional
        As the single-sensor tracker.
    measurement_model : None
        Not taken (give ``measurement_models``).
    birth_options : dict
        Not used (no births from the measurements here).
    updater : stonesoup.updater.kalman.KalmanUpdater, optional
        Its family (Kalman, extended, unscented, with its parameters) updates every sensor;
        its own ``measurement_model`` is not used (each sensor's is).

    Raises
    ------
    TypeError
        If ``measurement_models`` is missing or ``measurement_model`` is given, a model has no
        array form, a predictor or updater is not of the Kalman family, or
        ``birth_components`` is None (all naming the class and what is missing).
    ValueError
        If a per-sensor parameter has the wrong length or is out of range, the models'
        state dimensions differ; from :meth:`update_tracker`, on a detection of no sensor's
        model, of the wrong dimension or not finite.
"""


class MultiSensorLMBTracker(_MultiSensorTracker):
    association: Association = Property(
        default_factory=lambda: ShortChainGibbs(200, 25, tau_stall=5, tau_stale=10),
        doc="Our multi-sensor association of every group's problem.")
    extraction: str = Property(default="map", doc='State extraction: "map" or "hysteresis".')

    def _make_filter(self, model, options):
        return MultiSensorLMBFilter(model, self.association, gate_prob=self.gate_prob,
                                    extraction=self.extraction, **options)


class MultiSensorGLMBTracker(_MultiSensorTracker):
    association: Association = Property(
        default_factory=lambda: ShortChainGibbs(200, 25, tau_stall=5, tau_stale=10),
        doc="Our multi-sensor truncation of every GLMB component's problem.")
    extraction: str = Property(default="map",
                               doc='State extraction: "map", "trajectory", "recursive" or '
                                   '"hysteresis".')

    def _make_filter(self, model, options):
        return MultiSensorGLMBFilter(model, self.association, gate_prob=self.gate_prob,
                                     extraction=self.extraction, **options)


MultiSensorLMBTracker.__doc__ = ("""Multi-sensor LMB tracker: our
    :class:`~rankedassign.tracking.MultiSensorLMBFilter` in Stone Soup, one measurement model
    per sensor.

    Each scan's detections are split by sensor (a detection's own ``measurement_model``) and
    the filter's joint multi-sensor update associates them all at once; the single-object
    arithmetic is that of the non-linear path (Kalman, EKF or UKF on arrays, the state in
    Stone Soup's order)."""
    + _MS_DOC + """
    Examples
    --------
    >>> import datetime
    >>> import numpy as np
    >>> from stonesoup.models.measurement.nonlinear import CartesianToBearingRange
    >>> from stonesoup.models.transition.linear import (
    ...     CombinedLinearGaussianTransitionModel, ConstantVelocity)
    >>> from stonesoup.types.detection import Detection
    >>> from stonesoup.types.state import GaussianState, WeightedGaussianState
    >>> from rankedassign.stonesoup import MultiSensorLMBTracker
    >>> cv = CombinedLinearGaussianTransitionModel([ConstantVelocity(0.5)] * 2)
    >>> sensors = [CartesianToBearingRange(4, (0, 2), np.diag([1e-4, 1.0]),
    ...                                    translation_offset=np.array([[x], [0.0]]))
    ...            for x in (-100.0, 100.0)]
    >>> t0 = datetime.datetime(2025, 1, 1)
    >>> scans = []
    >>> for k in range(4):
    ...     x = GaussianState([[1.0 * k], [1.0], [50.0], [0.0]], np.eye(4))
    ...     t = t0 + datetime.timedelta(seconds=k)
    ...     scans.append((t, {Detection(mm.function(x), timestamp=t, measurement_model=mm)
    ...                       for mm in sensors}))
    >>> birth = [WeightedGaussianState([[0], [0], [50], [0]], np.diag([25.0, 4, 25, 4]),
    ...                                weight=0.1)]
    >>> tracker = MultiSensorLMBTracker(scans, cv, measurement_models=sensors,
    ...                                 prob_detection=0.9, clutter_rate=1.0,
    ...                                 clutter_spatial_density=1e-4, birth_components=birth,
    ...                                 seed=0)
    >>> for time, tracks in tracker:
    ...     pass
    >>> [(t.id, len(t)) for t in tracks]
    [('1:1', 4)]
    """)

MultiSensorGLMBTracker.__doc__ = ("""Multi-sensor δ-GLMB tracker: our
    :class:`~rankedassign.tracking.MultiSensorGLMBFilter` in Stone Soup, one measurement
    model per sensor.

    As :class:`MultiSensorLMBTracker`, with the δ-GLMB filter's joint multi-sensor update."""
    + _MS_DOC + """
    Examples
    --------
    >>> import datetime
    >>> import numpy as np
    >>> from stonesoup.models.measurement.linear import LinearGaussian
    >>> from stonesoup.models.transition.linear import (
    ...     CombinedLinearGaussianTransitionModel, ConstantVelocity)
    >>> from stonesoup.types.detection import Detection
    >>> from stonesoup.types.state import WeightedGaussianState
    >>> from rankedassign.stonesoup import MultiSensorGLMBTracker
    >>> cv = CombinedLinearGaussianTransitionModel([ConstantVelocity(0.5)] * 2)
    >>> a = LinearGaussian(4, (0, 2), np.eye(2))
    >>> b = LinearGaussian(4, (0, 2), 4 * np.eye(2))
    >>> t0 = datetime.datetime(2025, 1, 1)
    >>> scans = [(t0 + datetime.timedelta(seconds=k),
    ...           {Detection([[k * 10.0], [0.0]], measurement_model=a),
    ...            Detection([[k * 10.0 + 0.5], [0.0]], measurement_model=b)})
    ...          for k in range(4)]
    >>> birth = [WeightedGaussianState([[0], [0], [0], [0]], np.diag([4.0, 100, 4, 100]),
    ...                                weight=0.1)]
    >>> tracker = MultiSensorGLMBTracker(scans, cv, measurement_models=[a, b],
    ...                                  prob_detection=0.9, clutter_rate=1.0,
    ...                                  clutter_spatial_density=1e-4, birth_components=birth,
    ...                                  seed=0)
    >>> for time, tracks in tracker:
    ...     pass
    >>> [(t.id, len(t)) for t in tracks]
    [('1:1', 4)]
    """)

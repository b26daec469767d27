"""Stone Soup trackers around our LMB and δ-GLMB filters, built from Stone Soup's models.

The filters of :mod:`rankedassign.tracking` track ``[x, vx, y, vy]`` from position
measurements with linear-Gaussian motion. The trackers here take Stone Soup's
``CombinedLinearGaussianTransitionModel`` (its ``F`` and ``Q`` for each interval between
scans, :class:`~rankedassign.tracking.models.LinearMotion`) and ``LinearGaussian``
measurement model (mapping ``(0, 2)``, its ``R``), the detection and survival probabilities,
the clutter rate and spatial density (``κ``), and the birth components as
``WeightedGaussianState`` whose ``weight`` is the existence probability ``r_B``.
"""

from __future__ import annotations

import datetime
import math
from collections.abc import Mapping, Sequence

import numpy as np
from stonesoup.base import Property
from stonesoup.models.base import GaussianModel, LinearModel
from stonesoup.models.measurement.linear import LinearGaussian
from stonesoup.models.transition.base import TransitionModel
from stonesoup.reader import DetectionReader
from stonesoup.tracker.base import Tracker
from stonesoup.types.detection import Detection
from stonesoup.types.state import GaussianState, State
from stonesoup.types.track import Track

from ..engine.rng import check_rng
from ..tracking import (
    Association,
    BirthComponent,
    ConstantSurvival,
    GLMBFilter,
    LinearMotion,
    LMBBirth,
    LMBFilter,
    Model,
    PoissonClutter,
    PositionSensor,
    ShortChainGibbs,
)
from ..validation import float_array

__all__ = ["LMBTracker", "GLMBTracker"]

_ZERO = datetime.timedelta(0)


def _check_linear(model, role: str, who: str) -> None:
    """Refuse a model that is not linear-Gaussian (with its name in the message)."""
    parts = getattr(model, "model_list", None) or [model]
    for part in [model, *parts]:
        if not (isinstance(part, LinearModel) and isinstance(part, GaussianModel)):
            raise TypeError(
                f"{who} supports only linear-Gaussian models: the {role} model "
                f"{type(part).__name__} is not linear-Gaussian (use e.g. "
                + ("CombinedLinearGaussianTransitionModel of ConstantVelocity models)"
                   if role == "transition" else "LinearGaussian)")
            )


def _birth(components, who: str) -> LMBBirth:
    """The birth components as our :class:`~rankedassign.tracking.LMBBirth`."""
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
        out.append(BirthComponent(float(weight), np.asarray(comp.state_vector, float).ravel(),
                                  np.asarray(comp.covar, float)))
    return LMBBirth(tuple(out))


class _LabeledTracker(Tracker):
    """What :class:`LMBTracker` and :class:`GLMBTracker` share: models, scans, tracks."""

    detector: DetectionReader = Property(
        doc="Source of (time, detections) pairs, e.g. a detection simulator.")
    transition_model: TransitionModel = Property(
        doc="Linear-Gaussian motion of [x, vx, y, vy].")
    measurement_model: LinearGaussian = Property(
        doc="Linear-Gaussian position measurement, mapping (0, 2).")
    prob_detection: float = Property(doc="Detection probability P_D in (0, 1].")
    clutter_rate: float = Property(doc="Mean number of clutter detections per scan.")
    clutter_spatial_density: float = Property(
        doc="Clutter intensity kappa = rate / area (per unit measurement volume).")
    birth_components: Sequence = Property(
        doc="WeightedGaussianState per birth track; weight = existence probability r_B.")
    prob_survival: float = Property(default=0.99, doc="Survival probability P_S in (0, 1].")
    seed: int = Property(
        default=None,
        doc="Seed of the association's randomness (anything numpy.random.default_rng takes).")
    gate_prob: float = Property(default=0.9999999, doc="Chi-square gate probability.")
    filter_options: dict = Property(
        default_factory=dict, doc="Further keyword arguments of the filter.")

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        who = type(self).__name__
        _check_linear(self.transition_model, "transition", who)
        _check_linear(self.measurement_model, "measurement", who)
        mm = self.measurement_model
        if mm.ndim_state != 4 or tuple(mm.mapping) != (0, 2):
            raise ValueError(
                f"{who} tracks [x, vx, y, vy] from positions: the measurement model must map "
                f"dimensions (0, 2) of a 4-D state, got mapping {tuple(mm.mapping)} of a "
                f"{mm.ndim_state}-D state"
            )
        if self.transition_model.ndim_state != 4:
            raise ValueError(f"{who} tracks [x, vx, y, vy]: the transition model must have a "
                             f"4-D state, got {self.transition_model.ndim_state}-D")
        density = float(self.clutter_spatial_density)
        if not (math.isfinite(density) and density > 0):
            raise ValueError(f"{who}: clutter_spatial_density must be a positive finite "
                             f"number, got {density!r}")
        rate = float(self.clutter_rate)
        # our clutter model is a rate on a region; a square of area rate / density has the
        # tracker's intensity (the filters use nothing else of the region)
        side = math.sqrt(rate / density) if rate > 0 else 1.0
        model = Model(
            self._motion(_ZERO),
            PositionSensor(float(self.prob_detection), noise_cov=np.asarray(mm.covar(), float)),
            PoissonClutter(rate, ((0.0, side), (0.0, side))),
            _birth(self.birth_components, who),
            ConstantSurvival(float(self.prob_survival)),
        )
        self.filter = self._make_filter(model)
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

    def _make_filter(self, model):  # pragma: no cover (abstract)
        raise NotImplementedError

    def _motion(self, interval: datetime.timedelta) -> LinearMotion:
        tm = self.transition_model
        return LinearMotion(np.asarray(tm.matrix(time_interval=interval), float),
                            np.asarray(tm.covar(time_interval=interval), float))

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
        """The detections as an ``(M, 2)`` array, checked against the measurement model."""
        who = type(self).__name__
        mm = self.measurement_model
        if (isinstance(detections, (str, bytes, Mapping, np.ndarray))
                or not hasattr(detections, "__iter__")):
            raise TypeError(f"{who}: detections must be a set (or list) of Detection, got "
                            f"{type(detections).__name__}"
                            + ("; an empty scan is set()" if detections is None else ""))
        rows = []
        for det in detections:
            if not isinstance(det, Detection):
                raise TypeError(f"{who}: detections must hold Detection objects (with a "
                                f"state_vector and a measurement_model), got "
                                f"{type(det).__name__} {det!r} in a scan at {time}")
            own = det.measurement_model
            if own is not None and own is not mm and not (
                    isinstance(own, LinearGaussian) and own.ndim_state == mm.ndim_state
                    and tuple(own.mapping) == tuple(mm.mapping)
                    and np.array_equal(own.covar(), mm.covar())):
                raise ValueError(
                    f"{who}: a detection at {time} has measurement model "
                    f"{type(own).__name__} (mapping {tuple(getattr(own, 'mapping', ()))}), "
                    "not the tracker's measurement_model; the filter applies its own model "
                    "to every detection"
                )
            z = float_array(det.state_vector, f"{who}: the state_vector of a detection at "
                            f"{time}").reshape(-1)
            if z.size != mm.ndim_meas:
                raise ValueError(f"{who}: a detection at {time} has {z.size} dimensions, the "
                                 f"measurement model gives {mm.ndim_meas}")
            rows.append(z)
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
            If a detection has another measurement model or the wrong dimension, or if
            ``time`` is before the previous scan.
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
            sv = np.asarray(x, dtype=np.float64).reshape(-1, 1)
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
        Linear-Gaussian motion of ``[x, vx, y, vy]`` (e.g. two ``ConstantVelocity``); ``F``
        and ``Q`` are taken for each interval between scans.
    measurement_model : stonesoup.models.measurement.linear.LinearGaussian
        Position measurement: ``ndim_state=4``, ``mapping=(0, 2)``, noise covariance ``R``.
    prob_detection : float
        Detection probability ``P_D`` in ``(0, 1]``.
    clutter_rate : float
        Mean number of clutter detections per scan, ``> 0``.
    clutter_spatial_density : float
        Clutter intensity ``κ`` per unit measurement area, ``> 0`` (a detection simulator's
        ``clutter_spatial_density``).
    birth_components : sequence of stonesoup.types.state.WeightedGaussianState
        One per birth track of every scan; ``weight`` is its existence probability ``r_B`` in
        ``(0, 1)``.
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
        If the transition or measurement model is not linear-Gaussian (the message names it),
        a birth component is not a ``GaussianState``, or ``seed`` is of a kind numpy cannot
        seed from (the message names ``seed``); from :meth:`update_tracker`, on a ``time``
        that is not a datetime or detections that are not a collection of ``Detection``.
    ValueError
        If the measurement model is not a position measurement of a 4-D state, a birth
        component has no existence probability (its weight is not in ``(0, 1)``), or a
        probability, rate or density is out of range; from :meth:`update_tracker`, on
        detections of another measurement model or dimension.

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

    def _make_filter(self, model):
        return LMBFilter(model, self.association, gate_prob=self.gate_prob, grouping=True,
                         extraction=self.extraction, **self.filter_options)



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
        Linear-Gaussian motion of ``[x, vx, y, vy]`` (e.g. two ``ConstantVelocity``); ``F``
        and ``Q`` are taken for each interval between scans.
    measurement_model : stonesoup.models.measurement.linear.LinearGaussian
        Position measurement: ``ndim_state=4``, ``mapping=(0, 2)``, noise covariance ``R``.
    prob_detection : float
        Detection probability ``P_D`` in ``(0, 1]``.
    clutter_rate : float
        Mean number of clutter detections per scan, ``> 0``.
    clutter_spatial_density : float
        Clutter intensity ``κ`` per unit measurement area, ``> 0`` (a detection simulator's
        ``clutter_spatial_density``).
    birth_components : sequence of stonesoup.types.state.WeightedGaussianState
        One per birth track of every scan; ``weight`` is its existence probability ``r_B`` in
        ``(0, 1)``.
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

    def _make_filter(self, model):
        return GLMBFilter(model, self.association, gate_prob=self.gate_prob,
                          extraction=self.extraction, **self.filter_options)


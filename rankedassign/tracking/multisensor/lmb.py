"""The multi-sensor LMB filter: the joint update of multi-sensor spec §7.4.

:class:`MultiSensorLMBFilter` reuses the single-sensor phases of
:class:`~rankedassign.tracking.LMBFilter` (prediction and births 6.1, track pruning and
mixture reduction, state extraction 6.5) and replaces the update:

1. per sensor, the χ² gate of every track (``_kernels.gate_and_distances`` on that sensor's
   noise covariance); a tuple is allowed for a track when each of its detections is in the
   track's gate of that sensor;
2. groups (§6.5a over the union of the sensors' gated measurements);
3. per group the :class:`~rankedassign.multisensor.MultiSensorProblem` of spec eq. (1.3) with
   the stacked closed form (1.5)::

       ln η_n(−1) = ln(1 − r_n)
       ln η_n(t)  = ln r_n + Σ_{v∉D} ln(1 − P_D^v) + Σ_{v∈D} (ln P_D^v − ln κ_v)
                    + ln Σ_k w_k N(z_D; H_D m_k, H_D P_k H_Dᵀ + R_D)

   and its separable factors (``ln s_n = ln r_n``, ``ln θ_n^(v)`` the single-sensor terms) for
   MM-Gibbs;
4. association marginals ``β`` from a multi-sensor association
   (:mod:`rankedassign.tracking.multisensor.association`);
5. posterior ``r_n = 1 − β_n(−1)`` and ``p_n = r_n⁻¹ Σ_t β_{n,t} p_n^(t)`` with ``p^(t)`` the
   stacked Kalman update on ``z_{D(t)}`` (§7.4), then the single-sensor housekeeping;
6. with adaptive birth (:class:`~rankedassign.tracking.AdaptiveBirth`), the
   births of the next scan from the measurements the tracks do not explain
   (``r_A^(v)(j) = Σ_n Σ_{t: t^(v)=j} β_{n,t}``, §7.4 and §4).
"""

from __future__ import annotations

import itertools
import math
import numbers
from collections.abc import Sequence
from dataclasses import dataclass
from time import perf_counter

import numpy as np
from scipy.special import logsumexp

from ...engine.rng import spawning_generator
from ...multisensor import MultiSensorProblem
from ...numba_options import interruptible
from ...validation import check_bool, check_choice, check_int, check_type
from .. import _kernels
from ..common import check_distribution as _check_distribution
from ..common import check_measurements as _check_measurements
from ..marginals import MultiSensorAssociationResult
from ..models import (
    EXTRACTIONS,
    ConstantSurvival,
    ConstantVelocity,
    LMBBirth,
    Model,
    PoissonClutter,
    PositionSensor,
)
from ..nonlinear.multisensor import NonlinearMultiSensorModel
from ..nonlinear.step import multi_sensor_path
from ..nonlinear.vo import NonlinearModel
from ..single.lmb import LMBFilter, ScanRecord, group_tracks
from .adaptive_birth import AdaptiveBirth, empty_birth

__all__ = ["MultiSensorModel", "MultiSensorLMBFilter", "check_scans", "check_sensors"]

_POS = [0, 2]  # H picks p_x, p_y
_LOG_2PI = math.log(2.0 * math.pi)


def check_sensors(sensors, n_sensors: int, name: str = "sensors") -> tuple[int, ...]:
    """``sensors`` as a tuple of distinct sensor indices in ``0..n_sensors - 1``.

    Parameters
    ----------
    sensors : sequence of int
        A list, tuple, range or 1-D integer array; Python and numpy ints, not ``bool``.
    n_sensors : int
        Number of sensors to choose from.
    name : str
        The argument's name in the messages.

    Returns
    -------
    tuple of int
        The indices as Python ints, in the order given (not sorted), each in
        ``0..n_sensors - 1`` and none repeated; at least one.

    Raises
    ------
    TypeError
        If ``sensors`` is not a sequence (a bare int, a string, a set) or holds something other
        than ints (``0.5``, ``True``, ``"1"``).
    ValueError
        On an empty selection, a repeated or an out-of-range index.

    Examples
    --------
    >>> from rankedassign.tracking.multisensor.lmb import check_sensors
    >>> check_sensors([2, 0], 4)
    (2, 0)
    >>> check_sensors((True,), 4)
    Traceback (most recent call last):
    ...
    TypeError: sensors[0] must be an int (a sensor index), got bool True
    >>> check_sensors([0, 4], 4)
    Traceback (most recent call last):
    ...
    ValueError: sensors must be distinct indices in 0..3, got [0, 4]
    """
    if isinstance(sensors, (str, bytes)) or not isinstance(sensors, (Sequence, np.ndarray)):
        raise TypeError(f"{name} must be a sequence of sensor indices (ints), got "
                        f"{type(sensors).__name__} {sensors!r}")
    for i, v in enumerate(sensors):
        if isinstance(v, bool) or not isinstance(v, numbers.Integral):
            raise TypeError(f"{name}[{i}] must be an int (a sensor index), got "
                            f"{type(v).__name__} {v!r}")
    idx = [int(v) for v in sensors]
    if not idx or len(set(idx)) != len(idx) or min(idx) < 0 or max(idx) >= n_sensors:
        raise ValueError(f"{name} must be distinct indices in 0..{n_sensors - 1}, got {idx}")
    return tuple(idx)


def check_scans(zs, n_sensors: int, path=None) -> list:
    """One scan's measurements of every sensor, validated: a list of ``(M_v, 2)`` arrays.

    Parameters
    ----------
    zs : sequence of array_like
        One measurement set per sensor, in the model's sensor order.
    n_sensors : int
        ``V``.
    path : MultiSensorPath, optional
        A non-linear model's: each sensor's measurements have its own dimension.

    Returns
    -------
    list of ndarray

    Raises
    ------
    TypeError
        If ``zs`` is not a sequence of measurement sets (a string, a number).
    ValueError
        If it holds other than ``V`` sets (or is one array), or a set is malformed; the
        message gives ``V`` or names the sensor.

    Examples
    --------
    >>> [z.shape for z in check_scans([[[0.0, 1.0]], []], 2)]
    [(1, 2), (0, 2)]
    """
    if isinstance(zs, (str, bytes)) or not isinstance(zs, (Sequence, np.ndarray)):
        raise TypeError(f"step needs one measurement array per sensor (V = {n_sensors}), "
                        f"got {type(zs).__name__}")
    if isinstance(zs, np.ndarray) or len(zs) != n_sensors:
        got = "an array" if isinstance(zs, np.ndarray) else f"{len(zs)} arrays"
        raise ValueError(f"step needs one measurement array per sensor (V = {n_sensors}), "
                         f"got {got}")
    if path is not None:
        return [path.check_measurements(v, z) for v, z in enumerate(zs)]
    return [_check_measurements(z, f"measurements of sensor {v}") for v, z in enumerate(zs)]


@dataclass(frozen=True)
class MultiSensorModel:
    """Motion, birth and survival shared by every sensor; one sensor and clutter model each.

    Parameters
    ----------
    motion : ConstantVelocity
    sensors : tuple of PositionSensor
        ``V >= 1`` position sensors (``P_D^v``, ``R_v``).
    clutters : tuple of PoissonClutter
        One Poisson clutter model per sensor (``κ_v``).
    birth : LMBBirth
    survival : ConstantSurvival
    extraction : {"hysteresis", "map"}, optional
        The state extraction a filter on this model uses unless told otherwise (default
        hysteresis; :meth:`from_model` takes the single-sensor model's, so a preset's setting
        travels on), as :attr:`Model.extraction <rankedassign.tracking.models.Model>`.

    Attributes
    ----------
    motion : ConstantVelocity
        Motion model shared by every sensor (``F``, ``Q``).
    sensors : tuple of PositionSensor
        The ``V`` sensors, in sensor order (a list given is stored as a tuple).
    clutters : tuple of PoissonClutter
        ``clutters[v]`` is the clutter of ``sensors[v]`` (same length as ``sensors``).
    birth : LMBBirth
        Static LMB birth of every scan (empty, ``LMBBirth(())``, for a filter with adaptive
        birth).
    survival : ConstantSurvival
        Survival probability ``P_S``, shared by every sensor.
    extraction : {"hysteresis", "map"}
        Default state extraction of a filter on this model (:data:`EXTRACTIONS`).

    Raises
    ------
    TypeError
        If a part is not of its type (``sensors[v]`` a :class:`PositionSensor`, ...).
    ValueError
        If there is no sensor, ``clutters`` does not have one entry per sensor, or on an
        unknown ``extraction``.

    Examples
    --------
    >>> from rankedassign.tracking.models import make_model
    >>> from rankedassign.tracking.multisensor.lmb import MultiSensorModel
    >>> ms = MultiSensorModel.from_model(make_model("paper"))
    >>> ms.n_sensors, ms.select([0]).sensors[0].p_d
    (1, 0.98)
    >>> MultiSensorModel.from_model(make_model("vo")).extraction
    'map'
    """

    motion: ConstantVelocity
    sensors: tuple
    clutters: tuple
    birth: LMBBirth
    survival: ConstantSurvival
    extraction: str = "hysteresis"

    def __post_init__(self):
        check_type(self.motion, "motion", ConstantVelocity)
        check_type(self.birth, "birth", LMBBirth)
        check_type(self.survival, "survival", ConstantSurvival)
        check_choice(self.extraction, "extraction", EXTRACTIONS)
        for name in ("sensors", "clutters"):
            check_type(getattr(self, name), name, Sequence, "one entry per sensor")
        object.__setattr__(self, "sensors", tuple(self.sensors))
        object.__setattr__(self, "clutters", tuple(self.clutters))
        if len(self.sensors) == 0:
            raise ValueError("a multi-sensor model needs at least one sensor, got none")
        if len(self.clutters) != len(self.sensors):
            raise ValueError(
                f"clutters must have one entry per sensor ({len(self.sensors)}), got "
                f"{len(self.clutters)}"
            )
        for v, s in enumerate(self.sensors):
            check_type(s, f"sensors[{v}]", PositionSensor)
        for v, c in enumerate(self.clutters):
            check_type(c, f"clutters[{v}]", PoissonClutter)

    @property
    def n_sensors(self) -> int:
        """``V``."""
        return len(self.sensors)

    @classmethod
    def from_model(cls, model: Model) -> MultiSensorModel:
        """The one-sensor model of a single-sensor :class:`~rankedassign.tracking.Model`.

        Parameters
        ----------
        model : Model
            Single-sensor model; its sensor and clutter become sensor 0.

        Returns
        -------
        MultiSensorModel
            ``V = 1``, with the motion, birth, survival and extraction of ``model``.

        Raises
        ------
        TypeError
            If ``model`` is not a :class:`~rankedassign.tracking.Model`.
        """
        check_type(model, "model", Model)
        return cls(model.motion, (model.sensor,), (model.clutter,), model.birth, model.survival,
                   model.extraction)

    def select(self, sensors) -> MultiSensorModel:
        """The model restricted to the sensors of index ``sensors`` (in that order).

        Parameters
        ----------
        sensors : sequence of int
            Distinct indices into :attr:`sensors`, ``0..n_sensors - 1``, at least one
            (validated by :func:`check_sensors`).

        Returns
        -------
        MultiSensorModel
            A new model whose sensor ``i`` (and clutter ``i``) is sensor ``sensors[i]`` of this
            one; motion, birth, survival and extraction are shared.

        Raises
        ------
        TypeError
            If ``sensors`` is not a sequence of ints (:func:`check_sensors`).
        ValueError
            On an empty selection, a repeated or an out-of-range index.
        """
        idx = check_sensors(sensors, self.n_sensors)
        return MultiSensorModel(self.motion, tuple(self.sensors[v] for v in idx),
                                tuple(self.clutters[v] for v in idx), self.birth, self.survival,
                                self.extraction)

    def single(self, v: int = 0) -> Model:
        """Sensor ``v`` as a single-sensor :class:`~rankedassign.tracking.Model`.

        Parameters
        ----------
        v : int, optional
            Index of the sensor, ``0..n_sensors - 1`` (default 0).

        Returns
        -------
        Model
            ``sensors[v]`` and ``clutters[v]`` with the shared motion, birth, survival and
            extraction.

        Raises
        ------
        TypeError
            If ``v`` is not an int (``bool`` included).
        ValueError
            If ``v`` is outside ``0..n_sensors - 1`` (no negative indexing).
        """
        v = check_int(v, "v", minimum=0, maximum=self.n_sensors - 1)
        return Model(self.motion, self.sensors[v], self.clutters[v], self.birth, self.survival,
                     self.extraction)


def _check_model(model, birth):
    """A multi-sensor filter's model (one sensor's promoted to one sensor of several), checked
    together with its adaptive ``birth``."""
    if isinstance(model, Model):
        model = MultiSensorModel.from_model(model)
    elif isinstance(model, NonlinearModel):
        model = NonlinearMultiSensorModel.from_model(model)
    check_type(model, "model", (MultiSensorModel, NonlinearMultiSensorModel),
               "build one with MultiSensorModel(...) or make_multisensor_model()")
    if birth is not None:
        check_type(birth, "birth", AdaptiveBirth,
                   "None for the model's static birth or AdaptiveBirth(...)")
        if isinstance(model, NonlinearMultiSensorModel):
            raise ValueError("adaptive birth places births from position measurements; "
                             "it needs a linear MultiSensorModel, got a "
                             "NonlinearMultiSensorModel (use its static birth, birth=None)")
    return model


def _sensor_log_terms(model) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Per sensor ``ln P_D`` and ``ln(1 - P_D)``, and ``ln κ`` of its clutter intensity."""
    pds = np.array([s.p_d for s in model.sensors], dtype=np.float64)
    with np.errstate(divide="ignore"):
        log_pds = np.log(pds)
        log_misses = np.log1p(-pds)
    return log_pds, log_misses, np.array([math.log(c.intensity) for c in model.clutters])


def _sensor_gates(filt, zs) -> tuple[list, list]:
    """Per sensor the gated measurement columns ``used_v`` and the gate ``(T, U_v)`` of a
    multi-sensor filter's tracks."""
    T = filt.n_tracks
    used, gated = [], []
    gate = 0.0 if filt.gate is None else filt.gate
    for v, (z, R) in enumerate(zip(zs, filt._Rs, strict=True)):
        if z.shape[0] == 0 or T == 0:  # nothing to gate: no column is used
            used.append(np.empty(0, dtype=np.int64))
            gated.append(np.zeros((T, 0), dtype=bool))
            continue
        if filt._ms is not None:  # the model's filter, wrapped innovations, own χ² gate
            g = filt._ms.gated(v, filt.m, filt.P, z, filt.offsets)
        else:
            with interruptible:
                _, _, _, _, g = _kernels.gate_and_distances(
                    filt.m, filt.P, R, z, filt.offsets, gate, filt.gate is not None)
        u = np.flatnonzero(g.any(axis=0))
        used.append(u)
        gated.append(np.ascontiguousarray(g[:, u]))
    return used, gated


class MultiSensorLMBFilter(LMBFilter):
    """LMB filter fusing ``V`` position sensors by the multi-sensor joint update (spec §7.4).

    Parameters
    ----------
    model : MultiSensorModel, Model, NonlinearMultiSensorModel or NonlinearModel
        A single-sensor model is taken as ``V = 1``. The non-linear models
        (:mod:`rankedassign.tracking.nonlinear.multisensor`) update on the stacked sensors
        of each detection pattern with their EKF or UKF; adaptive birth needs a linear model.
    association : callable
        ``association(problem, rng) -> MultiSensorAssociationResult`` on every
        :class:`~rankedassign.multisensor.MultiSensorProblem`
        (:mod:`~rankedassign.tracking.association`: the same classes as for one sensor).
        Murty, LBP and associations that solve one sensor's problems only are refused
        (:func:`~rankedassign.tracking.check_truncation`). The marginals must be finite and
        non-negative, ``dead[n] + tuples[n].sum() = 1`` within
        :data:`~rankedassign.tracking.common.BETA_TOL`.
    gate_prob : float or None, optional
        χ² gate probability per sensor (default ``0.9999999``); None disables gating.
    grouping : bool, optional
        One problem per group of tracks that share gated measurements of some sensor (default
        True: the dense tuple tables grow as ``∏_v (M_v + 1)``). ``True`` or ``False`` only.
    birth : AdaptiveBirth or None, optional
        None (default): the static LMB birth of the model at every scan. An
        :class:`~rankedassign.tracking.AdaptiveBirth`: adaptive birth instead
        (the model's static birth is not used); after each update the measurements that the
        tracks do not explain make the births of the next scan (see Notes).
    **options
        The housekeeping and extraction options of
        :class:`~rankedassign.tracking.LMBFilter` (``extraction``: None, the default, takes
        the model's :attr:`MultiSensorModel.extraction`; ``theta_upper``,
        ``prune_track``, ``max_tracks``, ``prune_component``, ``merge_threshold``,
        ``merge_rule``, ``max_components``, ``estimate``). ``sample_empty_groups`` is
        accepted (a bool) and has no effect: groups without measurements are always solved in
        closed form.

    Notes
    -----
    With one sensor the problem is the single-sensor problem of eq. (6.2) in multi-sensor form
    and the posterior components come in the single-sensor order (missed detection first, then
    each measurement), so the filter reproduces :class:`LMBFilter` (tested). A group without
    gated measurements is solved in closed form. Posterior tuples with ``β_{n,t} / r_n`` at most
    ``prune_component`` are not expanded (their components would be pruned).

    Adaptive birth: after the update of scan ``k``, ``r_A^(v)(j)`` sums the marginals
    ``β_{n,t}`` of every tuple that gives measurement ``j`` of sensor ``v`` to a track
    (spec §7.4), ``r_U = 1 − r_A`` clipped to ``[0, 1]`` (1 for a measurement no track gates,
    and for every measurement while there is no track), and
    :meth:`AdaptiveBirth.births <rankedassign.tracking.AdaptiveBirth.births>`
    turns the measurements with ``r_U > τ_rU`` into the births appended by the prediction of
    scan ``k + 1`` (labels ``(k + 1, b)``), keeping those with ``r_B > prune_track``. Its
    sampler draws from the child of the scan's ``rng`` spawned after the association's
    children, so a run is reproducible from ``rng``. The attributes :attr:`r_U` (per sensor,
    the last scan's ``r_U``) and :attr:`n_births` (births appended by the last prediction)
    report it.

    References
    ----------
    .. [1] B.-N. Vo, B.-T. Vo, M. Beard, "Multi-Sensor Multi-Object Tracking with the
       Generalized Labeled Multi-Bernoulli Filter", IEEE Trans. Signal Process. 67(23), 2019.
    .. [2] S. Reuter, B.-T. Vo, B.-N. Vo, K. Dietmayer, "The Labeled Multi-Bernoulli Filter",
       IEEE Trans. Signal Process. 62(12), 2014.

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign.tracking import make_model
    >>> from rankedassign.tracking.multisensor.lmb import MultiSensorLMBFilter, MultiSensorModel
    >>> from rankedassign.tracking import Exact
    >>> base = make_model("vo")
    >>> ms = MultiSensorModel(base.motion, (base.sensor, base.sensor),
    ...                       (base.clutter, base.clutter), base.birth, base.survival)
    >>> f = MultiSensorLMBFilter(ms, Exact())
    >>> for k in range(3):      # one target near birth location 2, seen by both sensors
    ...     z = [[400.0 - 10 * k, -600.0 + 5 * k]]
    ...     rec = f.step([z, z], rng=k)
    >>> rec.labels.tolist(), rec.existence.round(3).tolist()
    ([[1, 2]], [1.0])
    """

    def __init__(self, model, association, *, gate_prob: float | None = 0.9999999,
                 grouping: bool = True, birth: AdaptiveBirth | None = None, **options):
        model = _check_model(model, birth)
        self.adaptive_birth = birth
        #: The non-linear model's per-sensor gates and stacked update (None: linear).
        self._ms = multi_sensor_path(model, gate_prob)
        if "sample_empty_groups" in options:
            check_bool(options.pop("sample_empty_groups"), "sample_empty_groups")
        super().__init__(model.single(0), association, gate_prob=gate_prob, grouping=grouping,
                         **options)
        self.ms_model = model
        self.V = model.n_sensors
        self._Rs = [np.array(s.R) for s in model.sensors]
        self._log_pds, self._log_misses, self._log_kappas = _sensor_log_terms(model)

    _sensors = "multi-sensor"
    # the per-cluster MAP ("cluster-map") reads the single-sensor scan's clusters
    _extractions = EXTRACTIONS

    def reset(self) -> None:
        """Forget every track (and, with adaptive birth, the pending births); restart at scan 1.
        """
        super().reset()
        #: Births appended by the last prediction.
        self.n_births = 0
        #: Per sensor, ``r_U`` of the last scan's measurements (adaptive birth only).
        self.r_U = None
        if getattr(self, "adaptive_birth", None) is not None:
            self._set_births(empty_birth())

    def _set_births(self, b) -> None:
        """The births the next prediction appends (already predicted to the next scan)."""
        self._birth_r = np.ascontiguousarray(b.r, dtype=np.float64)
        self._birth_m = np.ascontiguousarray(b.means, dtype=np.float64).reshape(-1, 4)
        self._birth_P = np.ascontiguousarray(b.covs, dtype=np.float64).reshape(-1, 4, 4)
        self._birth_index = np.arange(1, self._birth_r.size + 1, dtype=np.int64)

    def _append_births(self) -> None:
        self.n_births = int(self._birth_r.size)
        super()._append_births()

    # ----------------------------------------------------------------------- the scan
    def step(self, zs, rng=None) -> ScanRecord:
        """Run one scan: predict, build the multi-sensor problems, associate, update, extract.

        Parameters
        ----------
        zs : sequence of V array_like, shape (M_v, d_v)
            One measurement array per sensor, in the model's sensor order (``d_v = 2``
            positions on a linear model; sensor ``v``'s own dimension on a non-linear one).
        rng : optional
            Randomness of the association; one child stream per problem (as
            :meth:`LMBFilter.step <rankedassign.tracking.single.lmb.LMBFilter.step>`).

        Returns
        -------
        ScanRecord
            ``n_meas`` and ``n_meas_gated`` count the measurements of all sensors; with
            adaptive birth, ``timings["birth"]`` holds the seconds spent making the births of
            the next scan.

        Raises
        ------
        TypeError
            If ``zs`` is not a sequence, on measurements that are not real numbers, or on an
            ``rng`` numpy cannot seed from.
        ValueError
            If ``zs`` does not hold one array per sensor, on a malformed array (as
            :meth:`LMBFilter.step <rankedassign.tracking.single.lmb.LMBFilter.step>`, the message
            names the sensor), an invalid seed, or if the association returns marginals of
            the wrong shape, with a non-finite or negative entry, or with a row whose
            ``dead[n] + tuples[n].sum()`` is not 1.
        """
        zs = check_scans(zs, self.V, self._ms)
        gen = spawning_generator(rng)
        t0 = perf_counter()
        self.predict()
        t1 = perf_counter()
        T = self.n_tracks
        M_all = int(sum(z.shape[0] for z in zs))
        if T == 0:
            t2 = perf_counter()
            # no track explains anything: r_U = 1 for every measurement
            birth_s = self._adaptive_births(zs, [np.ones(z.shape[0]) for z in zs], gen)
            return ScanRecord(
                labels=np.empty((0, 2), np.int64), states=np.empty((0, self._d)),
                existence=np.empty(0), track_labels=self.labels.copy(),
                track_existence=self.r.copy(), n_tracks=0, n_meas=M_all, n_meas_gated=0,
                n_groups=0, invocations=0, sweeps=0, row_updates=0, n_unique=0,
                timings={"prediction": t1 - t0, "cost": t2 - t1, "association": 0.0, "update": 0.0,
                 **birth_s},
            )
        used, gated = _sensor_gates(self, zs)
        zu = [z[u] for z, u in zip(zs, used, strict=True)]
        groups = self._ms_groups(gated)
        t2 = perf_counter()
        with np.errstate(divide="ignore"):
            log_r = np.log(self.r)
            log_dead = np.log1p(-self.r)
        children = iter(gen.spawn(sum(1 for g in groups if any(c.size for c in g[1]))))
        counts = np.zeros(4, dtype=np.int64)
        n_problems = 0
        parts = []  # (rows, cols per sensor, dead (n,), tuples (n, ...))
        for rows, cols in groups:
            if not any(c.size for c in cols):
                # no measurement: dead or alive and missed by every sensor, closed form
                lm = log_r[rows] + self._log_misses.sum()
                ld = log_dead[rows]
                top = np.maximum(lm, ld)
                em, ed = np.exp(lm - top), np.exp(ld - top)
                tup = (em / (em + ed)).reshape((rows.size,) + (1,) * self.V)
                parts.append((rows, cols, ed / (em + ed), tup))
                continue
            problem = self._group_ms_problem(zu, gated, rows, cols, log_r, log_dead)
            res = self.association(problem, next(children))
            if not isinstance(res, MultiSensorAssociationResult):
                res = MultiSensorAssociationResult(*res)
            dead = np.asarray(res.dead, dtype=np.float64)
            tup = np.asarray(res.tuples, dtype=np.float64)
            shape = problem.log_eta_alive.shape
            if dead.shape != (rows.size,) or tup.shape != shape:
                raise ValueError(
                    f"association returned marginals of shapes {dead.shape} and {tup.shape}, "
                    f"expected {(rows.size,)} and {shape}"
                )
            _check_distribution(self.association, {"dead": dead, "tuples": tup},
                                dead + tup.reshape(rows.size, -1).sum(axis=1),
                                "dead[{i}] + tuples[{i}].sum()")
            n_problems += 1
            counts += (int(res.invocations), int(res.sweeps), int(res.row_updates),
                       int(res.n_unique))
            parts.append((rows, cols, dead, tup))
        t3 = perf_counter()
        r_new, mixture = self._ms_posterior(zu, parts)
        self._prune_and_merge(r_new, *mixture)
        labels, states, ex = self._extract()
        t4 = perf_counter()
        birth_s = {}
        if self.adaptive_birth is not None:
            birth_s = self._adaptive_births(zs, self._unexplained(zs, used, parts), gen)
        inv, sweeps, rows_upd, n_unique = counts.tolist()
        return ScanRecord(
            labels=labels, states=states, existence=ex, track_labels=self.labels.copy(),
            track_existence=self.r.copy(), n_tracks=T, n_meas=M_all,
            n_meas_gated=int(sum(u.size for u in used)), n_groups=n_problems,
            invocations=inv, sweeps=sweeps, row_updates=rows_upd, n_unique=n_unique,
            timings={"prediction": t1 - t0, "cost": t2 - t1, "association": t3 - t2,
                     "update": t4 - t3, **birth_s},
        )

    # ----------------------------------------------------------------------- adaptive birth
    def _unexplained(self, zs, used, parts):
        """Per sensor ``r_U = 1 − r_A`` of every measurement, clipped to ``[0, 1]``, with
        ``r_A^(v)(j) = Σ_n Σ_{t: t^(v)=j} β_{n,t}`` (spec §7.4) summed over the groups."""
        r_A = [np.zeros(z.shape[0]) for z in zs]
        for _rows, cols, _dead, tup in parts:
            for v in range(self.V):
                if cols[v].size == 0:
                    continue
                # Σ over the rows and the other sensors' entries: (U_v + 1,), entry 0 = missed
                other = tuple(a for a in range(tup.ndim) if a != v + 1)
                per_meas = tup.sum(axis=other)[1:]
                r_A[v][used[v][cols[v]]] += per_meas
        return [np.clip(1.0 - a, 0.0, 1.0) for a in r_A]

    def _adaptive_births(self, zs, r_U, gen) -> dict:
        """Make the births of the next scan (adaptive birth on); ``{"birth": seconds}``."""
        if self.adaptive_birth is None:
            return {}
        t0 = perf_counter()
        self.r_U = r_U
        birth_rng = gen.spawn(1)[0]  # after the association's children: reproducible
        m = self.ms_model
        b = self.adaptive_birth.births(zs, r_U, sensors=m.sensors, clutters=m.clutters,
                                       F=self._F, Q=self._Q, rng=birth_rng,
                                       r_min=self.prune_track)
        self._set_births(b)
        return {"birth": perf_counter() - t0}

    # ----------------------------------------------------------------------- gates and groups
    def _ms_groups(self, gated):
        """Groups ``(rows, [cols_v])`` over the union of the sensors' gated measurements."""
        T = self.n_tracks
        sizes = [g.shape[1] for g in gated]
        if not self.grouping or sum(sizes) == 0:
            return [(np.arange(T), [np.arange(s) for s in sizes])]
        bounds = np.concatenate([[0], np.cumsum(sizes)])
        out = []
        for rows, cols in group_tracks(np.hstack(gated)):
            out.append((rows, [cols[(cols >= bounds[v]) & (cols < bounds[v + 1])] - bounds[v]
                               for v in range(self.V)]))
        return out

    # ----------------------------------------------------------------------- the problem
    def _pattern_loglik(self, c, D, zD):
        """``ln N(z_D; H_D m_c, H_D P_c H_Dᵀ + R_D)`` for stacked ``zD`` (N, 2|D|), and the
        factors the Kalman update needs (innovations, ``S`` and its Cholesky factor); for a
        non-linear model the log-likelihood only."""
        if self._ms is not None:
            n = zD.shape[0]
            ll, _, _ = self._ms.stacked(D, np.repeat(self.m[c][None], n, axis=0),
                                        np.repeat(self.P[c][None], n, axis=0), zD, False)
            return ll, None, None
        d = len(D)
        HPH = self.P[c][np.ix_(_POS, _POS)]
        # S_D = 1 1ᵀ ⊗ H P Hᵀ + blkdiag(R_v), v ∈ D (every sensor measures the position)
        S = np.kron(np.ones((d, d)), HPH)
        for i, v in enumerate(D):
            S[2 * i:2 * i + 2, 2 * i:2 * i + 2] += self._Rs[v]
        L = np.linalg.cholesky(S)
        nu = zD - np.tile(self.m[c, _POS], d)
        y = np.linalg.solve(L, nu.T)  # L y = ν
        maha = (y * y).sum(axis=0)
        logdet = 2.0 * np.log(np.diag(L)).sum()
        return -0.5 * maha - 0.5 * logdet - d * _LOG_2PI, nu, S

    def _row_patterns(self, gated, row, cols):
        """Per pattern ``D`` (tuple of sensors) the tuples of row ``row``: local indices (N, V)."""
        gl = [np.flatnonzero(gated[v][row, cols[v]]) + 1 for v in range(self.V)]
        out = []
        for size in range(1, self.V + 1):
            for D in itertools.combinations(range(self.V), size):
                if any(gl[v].size == 0 for v in D):
                    continue
                t = np.zeros((int(np.prod([gl[v].size for v in D])), self.V), dtype=np.int64)
                grids = np.meshgrid(*[gl[v] for v in D], indexing="ij")
                for i, v in enumerate(D):
                    t[:, v] = grids[i].reshape(-1)
                out.append((D, t))
        return out

    def _stack(self, zu, cols, D, t):
        """Stacked measurements ``z_D`` (N, 2|D|) of the tuples ``t`` (local indices)."""
        return np.hstack([zu[v][cols[v][t[:, v] - 1]] for v in D])

    def _group_ms_problem(self, zu, gated, rows, cols, log_r, log_dead) -> MultiSensorProblem:
        """The multi-sensor problem (eq. 1.3 with 1.5) of tracks ``rows``, with its factors."""
        V = self.V
        n = rows.size
        shape = (n, *(c.size + 1 for c in cols))
        la = np.full(shape, -np.inf)
        log_theta = [np.full((n, c.size + 1), -np.inf) for c in cols]
        sum_miss = self._log_misses.sum()
        for i, row in enumerate(rows):
            la[(i,) + (0,) * V] = log_r[row] + sum_miss
            for v in range(V):
                log_theta[v][i, 0] = self._log_misses[v]
            comps = range(self.offsets[row], self.offsets[row + 1])
            log_w = np.log(self.w[self.offsets[row]:self.offsets[row + 1]])
            for D, t in self._row_patterns(gated, row, cols):
                zD = self._stack(zu, cols, D, t)
                ll = np.array([self._pattern_loglik(c, D, zD)[0] for c in comps])
                log_g = logsumexp(ll + log_w[:, None], axis=0)
                if np.isfinite(sum_miss):
                    miss = sum_miss - sum(self._log_misses[v] for v in D)
                else:
                    # a sensor with P_D = 1 has log(1 - P_D) = -inf: subtracting it from the
                    # sum would give -inf - (-inf) = NaN; sum the missing sensors instead
                    miss = sum(self._log_misses[v] for v in range(V) if v not in D)
                det = sum(self._log_pds[v] - self._log_kappas[v] for v in D)
                la[(i, *t.T)] = log_r[row] + miss + det + log_g
                if len(D) == 1:
                    v = D[0]
                    log_theta[v][i, t[:, v]] = self._log_pds[v] - self._log_kappas[v] + log_g
        return MultiSensorProblem(log_dead[rows], la, log_r[rows], log_theta)

    # ----------------------------------------------------------------------- the posterior
    def _ms_posterior(self, zu, parts):
        """Posterior existence and mixtures (spec §7.4) of every track, grouped by track."""
        T = self.n_tracks
        V = self.V
        r_new = np.zeros(T)
        comp_w, comp_m, comp_P = [[] for _ in range(T)], [[] for _ in range(T)], \
            [[] for _ in range(T)]
        elim = self.prune_component
        for rows, cols, _dead, tup in parts:
            for i, row in enumerate(rows):
                # r_n = Σ_t β_{n,t}  (as eq. 6.3)
                r = float(np.clip(tup[i].sum(), 0.0, 1.0))
                r_new[row] = r
                if r <= 0:
                    continue
                rel = tup[i] / r
                lo, hi = self.offsets[row], self.offsets[row + 1]
                # missed by every sensor: the predicted components, weights β_{n,0} / r_n w_k
                if rel[(0,) * V] > elim:
                    comp_w[row].append(rel[(0,) * V] * self.w[lo:hi])
                    comp_m[row].append(self.m[lo:hi])
                    comp_P[row].append(self.P[lo:hi])
                sel = np.argwhere(rel > elim)
                sel = sel[sel.any(axis=1)]  # the all-missed tuple is done
                if sel.size == 0:
                    continue
                pattern = sel > 0
                keys = np.unique(pattern, axis=0)
                # one batch per detection pattern, then the tuples in flat (C) order
                order_w, order_m, order_P, order_key = [], [], [], []
                for key in keys:
                    D = tuple(int(v) for v in np.flatnonzero(key))
                    tk = sel[(pattern == key).all(axis=1)]
                    zD = self._stack(zu, cols, D, tk)
                    lls, ms, Ps = [], [], []
                    for c in range(lo, hi):
                        if self._ms is not None:  # the stacked update of the model's filter
                            n = tk.shape[0]
                            ll, mu, Pu = self._ms.stacked(
                                D, np.repeat(self.m[c][None], n, axis=0),
                                np.repeat(self.P[c][None], n, axis=0), zD, True)
                            lls.append(ll)
                            ms.append(mu)
                            Ps.append(Pu)
                            continue
                        ll, nu, S = self._pattern_loglik(c, D, zD)
                        # K = P H_Dᵀ S⁻¹, m' = m + K ν, P' = P − K S Kᵀ
                        PHt = np.tile(self.P[c][:, _POS], (1, len(D)))
                        K = np.linalg.solve(S, PHt.T).T
                        Pu = self.P[c] - K @ PHt.T
                        Pu = 0.5 * (Pu + Pu.T)
                        lls.append(ll)
                        ms.append(self.m[c] + nu @ K.T)
                        Ps.append(np.broadcast_to(Pu, (tk.shape[0], self._d, self._d)))
                    lw = np.array(lls) + np.log(self.w[lo:hi])[:, None]  # (K, N)
                    ratio = np.exp(lw - logsumexp(lw, axis=0))
                    weights = ratio * rel[tuple(tk.T)][None, :]
                    # tuple-major order: every component of a tuple together
                    order_w.append(weights.T.reshape(-1))
                    order_m.append(np.stack(ms, axis=1).reshape(-1, self._d))
                    order_P.append(np.stack(Ps, axis=1).reshape(-1, self._d, self._d))
                    order_key.append(np.repeat(np.ravel_multi_index(tk.T, rel.shape),
                                               hi - lo))
                keyv = np.concatenate(order_key)
                perm = np.argsort(keyv, kind="stable")
                comp_w[row].append(np.concatenate(order_w)[perm])
                comp_m[row].append(np.concatenate(order_m)[perm])
                comp_P[row].append(np.concatenate(order_P)[perm])
        counts = np.array([sum(a.size for a in comp_w[t]) for t in range(T)], dtype=np.int64)
        offsets = np.concatenate([[0], np.cumsum(counts)]).astype(np.int64)
        w = np.concatenate([a for t in range(T) for a in comp_w[t]] or [np.empty(0)])
        d = self._d
        m = np.concatenate([a for t in range(T) for a in comp_m[t]] or [np.empty((0, d))])
        P = np.concatenate([a for t in range(T) for a in comp_P[t]] or [np.empty((0, d, d))])
        return r_new, (offsets, w, m, P)

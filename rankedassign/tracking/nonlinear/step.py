"""The model-agnostic measurement step the LMB and δ-GLMB filters run on a non-linear model.

A filter built on a :class:`~rankedassign.tracking.nonlinear.NonlinearModel` holds one
:class:`SingleObject` (Stone Soup's predictor and updater in one component): it predicts the
Gaussian components through the motion model, and for the predicted components and one scan
of measurements returns what the multi-object update needs (:class:`MeasurementTerms`): the
squared Mahalanobis distances on the wrapped innovations, ``ln |S|``, the χ² gate per track,
the gain ``K = C S⁻¹`` and the updated covariance ``P − K S Kᵀ``. The model's single-object
filter (Kalman, EKF or UKF) gives ``ẑ``, ``S`` and ``C = Cov(x, z)``; nothing below depends
on which.

The per-(track, measurement) log-likelihoods, the cost matrices and the samplers are the
compiled kernels of the linear filters (:func:`rankedassign.tracking._kernels.detection_log_weights`
takes distances and log-determinants, whatever produced them). The two kernels that assume the
4-D state of the linear filters are replaced here by numpy code for any state dimension:
``posterior_components`` by its plain-numpy twin of :mod:`rankedassign.tracking.reference`,
``reduce_mixtures`` by :func:`reduce_mixtures` (the twin's algorithm batched over the
tracks). A linear :class:`~rankedassign.tracking.models.Model` never reaches this module: its
filters keep their compiled path and its numbers bit for bit.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from .. import reference
from ..common import check_measurements, gate_threshold
from ..gating import GatedPairs, sensor_candidate_pairs, track_pairs
from .models import wrap_angle
from .multisensor import NonlinearMultiSensorModel, StackedSensor
from .vo import NonlinearModel

__all__ = ["MeasurementTerms", "MultiSensorPath", "SingleObject", "multi_sensor_path",
           "reduce_mixtures", "single_object"]

_LOG_2PI = math.log(2.0 * math.pi)


class MeasurementTerms(NamedTuple):
    """The measurement step of one scan for ``C`` components of ``T`` tracks, ``M`` measurements.

    Attributes
    ----------
    maha : ndarray of float64, shape (C, M)
        ``νᵀ S⁻¹ ν`` on the innovations with every angle coordinate wrapped to ``(−π, π]``.
    log_det_S : ndarray of float64, shape (C,)
        ``ln |S| + (d_z − 2) ln 2π``: with this, the compiled
        :func:`~rankedassign.tracking._kernels.detection_log_weights` (written for
        ``d_z = 2``) gives ``ln N(z; ẑ, S)`` in any measurement dimension; for ``d_z = 2`` it is
        ``ln |S|``.
    nu : ndarray of float64, shape (C, M, d_z)
        Wrapped innovations ``z_j − ẑ_c``.
    gain : ndarray of float64, shape (C, d, d_z)
        ``K = C S⁻¹``.
    P_upd : ndarray of float64, shape (C, d, d)
        ``P − K Cᵀ`` (= ``P − K S Kᵀ``), symmetrised.
    gated : ndarray of bool, shape (T, M)
        Measurement ``j`` is in the gate of some component of track ``t``.
    """

    maha: np.ndarray
    log_det_S: np.ndarray
    nu: np.ndarray
    gain: np.ndarray
    P_upd: np.ndarray
    gated: np.ndarray


class SingleObject:
    """The single-object path of a non-linear model: prediction, measurement step, update.

    Parameters
    ----------
    model : NonlinearModel
        Motion and measurement models, and the single-object filter (``model.filter``:
        :class:`~rankedassign.tracking.nonlinear.ExtendedKalmanFilter`,
        :class:`~rankedassign.tracking.nonlinear.UnscentedKalmanFilter`, or the
        :class:`~rankedassign.tracking.nonlinear.KalmanFilter` on linear models).

    Attributes
    ----------
    filter : object
        The single-object filter.
    motion, sensor : object
        The models.
    ndim, meas_ndim : int
        State and measurement dimensions ``d`` and ``d_z``.
    position_indices : tuple of int
        State components of the position (the sensor model names them).
    p_d, p_s, clutter_intensity : float
        Detection and survival probabilities, clutter intensity ``κ``.
    birth_r, birth_w, birth_m, birth_P : ndarray
        The birth terms flattened: existence ``(B,)``, then the Gaussians of every term in
        turn, weights ``(L,)``, means ``(L, d)``, covariances ``(L, d, d)``.
    birth_counts : ndarray of int64, shape (B,)
        Gaussians of each birth term.

    Raises
    ------
    TypeError
        If ``model`` is not a :class:`~rankedassign.tracking.nonlinear.NonlinearModel`.
    ValueError
        If the motion, the sensor and the births disagree on the state dimension.

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign.tracking.nonlinear import make_nonlinear_model
    >>> from rankedassign.tracking.nonlinear.step import SingleObject
    >>> so = SingleObject(make_nonlinear_model("vo-ekf"))
    >>> so.ndim, so.meas_ndim, so.birth_m.shape
    (5, 2, (4, 5))
    """

    def __init__(self, model: NonlinearModel):
        if not isinstance(model, NonlinearModel):
            raise TypeError(f"model must be a NonlinearModel, got {type(model).__name__}")
        self.filter = model.filter
        self.motion = model.motion
        self.sensor = model.sensor
        self.ndim = int(model.motion.ndim)
        # a measurement model states its dimension through ``angles`` (one flag per
        # coordinate, the interface of the "Non-linear models" page); ``ndim`` is optional
        self.meas_ndim = int(np.asarray(model.sensor.angles).size)
        if int(model.sensor.state_ndim) != self.ndim:
            raise ValueError(f"{model.sensor.name} measures {model.sensor.state_ndim}-D states "
                             f"but {model.motion.name} moves {self.ndim}-D states")
        self.position_indices = tuple(int(i) for i in model.sensor.position_indices)
        self.p_d = float(model.sensor.p_d)
        self.p_s = float(model.p_s)
        if not 0 <= self.p_s <= 1:
            raise ValueError(f"NonlinearModel: p_s must be in [0, 1], got {self.p_s}")
        self.clutter_intensity = float(model.clutter.intensity)
        birth = tuple(model.birth)
        for i, b in enumerate(birth):
            if b.means.shape[1] != self.ndim:
                raise ValueError(f"NonlinearModel: birth term {i} has {b.means.shape[1]}-D "
                                 f"means, the motion model {self.ndim}-D states")
        self.birth_r = np.array([b.r for b in birth], dtype=np.float64)
        self.birth_counts = np.array([b.weights.size for b in birth], dtype=np.int64)
        d = self.ndim
        self.birth_w = np.concatenate([b.weights for b in birth] or [np.empty(0)])
        self.birth_m = np.concatenate([b.means for b in birth] or [np.empty((0, d))])
        self.birth_P = np.concatenate([b.covs for b in birth] or [np.empty((0, d, d))])

    def __repr__(self) -> str:
        return f"SingleObject({self.filter!r}, {self.motion.name}, {self.sensor.name})"

    def set_motion(self, motion, who: str) -> None:
        """Predict through ``motion`` from now on (e.g. ``F`` and ``Q`` of a new interval).

        Parameters
        ----------
        motion : object
            A motion model of this interface (``f``, ``jacobian``, ``Q``, ``ndim``, ``name``)
            moving states of this path's dimension.
        who : str
            The filter's name, for messages.

        Raises
        ------
        TypeError
            If ``motion`` is not of this interface (e.g. a linear model's
            :class:`~rankedassign.tracking.models.ConstantVelocity`).
        ValueError
            If it moves states of another dimension.
        """
        if not all(callable(getattr(motion, a, None)) for a in ("f", "jacobian")):
            raise TypeError(f"set_motion replaces a linear model's motion; this {who} runs a "
                            "NonlinearModel: give a motion model of "
                            "rankedassign.tracking.nonlinear (f, jacobian, Q) of its "
                            f"{self.ndim}-D state, e.g. LinearGaussianMotion, got "
                            f"{type(motion).__name__}")
        if int(motion.ndim) != self.ndim:
            raise ValueError(f"{who}: the motion {motion.name} moves {int(motion.ndim)}-D "
                             f"states, the filter's are {self.ndim}-D")
        self.motion = motion

    # ------------------------------------------------------------------------- prediction
    def predict(self, m: np.ndarray, P: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Every component through the motion model (Kalman, EKF or UKF prediction).

        Parameters
        ----------
        m : ndarray, shape (C, d)
            Means.
        P : ndarray, shape (C, d, d)
            Covariances.

        Returns
        -------
        m, P : ndarray
            C-contiguous predicted means and covariances, same shapes.
        """
        if m.shape[0] == 0:
            return m, P
        m, P = self.filter.predict(self.motion, m, P)
        return np.ascontiguousarray(m), np.ascontiguousarray(P)

    # ------------------------------------------------------------------------- measurements
    def check_measurements(self, z) -> np.ndarray:
        """One scan's measurements as a float64 ``(M, d_z)`` array (bearings are not wrapped:
        only their wrapped differences enter).

        Parameters
        ----------
        z : array_like, shape (M, d_z)
            The scan's measurements; ``[]`` is a scan without measurements.

        Returns
        -------
        ndarray of float64, shape (M, d_z)

        Raises
        ------
        TypeError, ValueError
            As :func:`rankedassign.tracking.common.check_measurements`, the message naming the
            measurement model.
        """
        return check_measurements(z, f"measurements of {self.sensor.name}", dim=self.meas_ndim)

    def measurement_terms(self, m, P, z, offsets, gate: float | None) -> MeasurementTerms:
        """The measurement step of every component against every measurement.

        Parameters
        ----------
        m : ndarray, shape (C, d)
            Predicted means.
        P : ndarray, shape (C, d, d)
            Predicted covariances.
        z : ndarray, shape (M, d_z)
            Measurements (``M >= 1``).
        offsets : ndarray of int64, shape (T + 1,)
            Component range of every track.
        gate : float or None
            Threshold on the squared Mahalanobis distance; None: every pair is gated.

        Returns
        -------
        MeasurementTerms

        Raises
        ------
        ValueError
            From the models and the filter: a component at the sensor position, an innovation
            covariance that is not positive definite, ... (each message names the model).
        """
        filt = self.filter
        pred = filt.predict_measurement(self.sensor, m, P)
        nu = filt.innovations(pred, z)
        Si = pred.S_inv
        dz = nu.shape[-1]
        if dz == 2:  # the expression of the compiled gate, term by term
            maha = (Si[:, None, 0, 0] * nu[..., 0] ** 2
                    + (Si[:, None, 0, 1] + Si[:, None, 1, 0]) * nu[..., 0] * nu[..., 1]
                    + Si[:, None, 1, 1] * nu[..., 1] ** 2)
        else:
            maha = np.einsum("cmi,cij,cmj->cm", nu, Si, nu)
        T = offsets.size - 1
        comp_gated = np.ones(maha.shape, dtype=bool) if gate is None else maha <= gate
        track = np.repeat(np.arange(T), np.diff(offsets))
        gated = np.zeros((T, z.shape[0]), dtype=bool)
        np.logical_or.at(gated, track, comp_gated)
        # K = C S⁻¹ ; P' = P − K C' (= P − K S K')
        K = pred.cross @ Si
        P_upd = P - K @ pred.cross.transpose(0, 2, 1)
        P_upd = 0.5 * (P_upd + P_upd.transpose(0, 2, 1))
        log_det = pred.log_det + (dz - 2) * _LOG_2PI
        return MeasurementTerms(np.ascontiguousarray(maha), np.ascontiguousarray(log_det),
                                np.ascontiguousarray(nu), K, P_upd, gated)

    def gate_pairs(self, m, P, z, offsets, gate: float) -> GatedPairs:
        """The χ² gate of every track and measurement, on spatial candidates only.

        The candidates come from a k-d tree of the measurements in the sensor's own
        coordinates, each scaled by its noise standard deviation, angles periodic
        (:func:`~rankedassign.tracking.gating.sensor_candidate_pairs`); the exact test is that
        of :meth:`measurement_terms` (the wrapped innovation, the same expression of
        ``νᵀ S⁻¹ ν``), so the pairs are those of its ``gated`` matrix.

        Parameters
        ----------
        m, P : ndarray, shapes (C, d) and (C, d, d)
            Predicted means and covariances.
        z : ndarray, shape (M, d_z)
            Measurements.
        offsets : ndarray of int64, shape (T + 1,)
            Component range of every track.
        gate : float
            Threshold on the squared Mahalanobis distance.

        Returns
        -------
        GatedPairs

        Examples
        --------
        >>> import numpy as np
        >>> from rankedassign.tracking.nonlinear import make_nonlinear_model
        >>> so = SingleObject(make_nonlinear_model("vo-ekf"))
        >>> m = np.array([[0.0, 0, -500, 0, 0]])           # straight below: bearing ±π
        >>> z = np.array([[-np.pi + 0.01, 505.0], [np.pi - 0.01, 495.0], [0.0, 500.0]])
        >>> g = so.gate_pairs(m, np.diag([100.0, 1, 100, 1, 0.01])[None], z, np.array([0, 1]),
        ...                   30.0)
        >>> g.meas.tolist()
        [0, 1]
        """
        pred = self.filter.predict_measurement(self.sensor, m, P)
        scale = np.sqrt(np.diagonal(np.asarray(self.sensor.R, dtype=np.float64)))
        comp, meas = sensor_candidate_pairs(pred.z, pred.S, z, gate, pred.angles, scale)
        n_cand = int(comp.size)
        if n_cand:
            nu = z[meas] - pred.z[comp]
            if pred.angles.any():
                nu[:, pred.angles] = wrap_angle(nu[:, pred.angles])
            Si = pred.S_inv[comp]
            if nu.shape[1] == 2:  # measurement_terms' expression, term by term
                maha = (Si[:, 0, 0] * nu[:, 0] ** 2
                        + (Si[:, 0, 1] + Si[:, 1, 0]) * nu[:, 0] * nu[:, 1]
                        + Si[:, 1, 1] * nu[:, 1] ** 2)
            else:
                maha = np.einsum("ci,cij,cj->c", nu, Si, nu)
            ok = maha <= gate
            comp, meas = comp[ok], meas[ok]
        return track_pairs(comp, meas, offsets, z.shape[0], n_cand)

    # ------------------------------------------------------------------------- update
    @staticmethod
    def posterior_components(comp, track, meas, ratio, rel, w, m, P, K, nu, P_upd):
        """Posterior components (spec eq. 6.4) in any state dimension.

        The parameters and results of
        :func:`rankedassign.tracking._kernels.posterior_components`, with ``d``-dimensional
        states and ``d_z``-dimensional innovations; ``m + K ν`` uses the wrapped ``ν``. The
        arithmetic is that of the plain-numpy twin
        :func:`rankedassign.tracking.reference.posterior_components` (the compiled kernel is
        written for 4-D states).

        Parameters
        ----------
        comp, track, meas : ndarray of int64, shape (N,)
            Sources of the posterior components; ``meas = -1`` is a missed detection.
        ratio : ndarray, shape (N,)
            ``w_c N_cj / Σ_c' w_c' N_c'j`` for an update; not read for a missed detection.
        rel : ndarray, shape (T, M + 1)
            ``β_ij / r_i``; column ``M`` is the missed detection.
        w, m, P : ndarray, shapes (C,), (C, d), (C, d, d)
            Predicted component weights, means and covariances.
        K : ndarray, shape (C, d, d_z)
            Gain of every component (may be empty when no component is an update).
        nu : ndarray, shape (C, M, d_z)
            Wrapped innovations of the kept measurements.
        P_upd : ndarray, shape (C, d, d)
            Updated covariances ``P − K S Kᵀ`` (may be empty as ``K``).

        Returns
        -------
        w : ndarray, shape (N,)
        m : ndarray, shape (N, d)
        P : ndarray, shape (N, d, d)
        """
        return reference.posterior_components(comp, track, meas, ratio, rel, w, m, P, K, nu,
                                              P_upd)

    @staticmethod
    def reduce_mixtures(offsets, w, m, P, keep, elim, merge_thr, cap, rule):
        """Prune, merge and cap every kept mixture in any state dimension.

        The parameters and results of :func:`rankedassign.tracking._kernels.reduce_mixtures`
        (the compiled kernel is written for 4-D states), computed by :func:`reduce_mixtures`
        of this module.

        Parameters
        ----------
        offsets : ndarray of int64, shape (T + 1,)
            Each track's components.
        w, m, P : ndarray, shapes (C,), (C, d), (C, d, d)
            The components.
        keep : ndarray of bool, shape (T,)
            The tracks kept.
        elim, merge_thr : float
            Pruning and merging thresholds.
        cap : int
            Most components per track.
        rule : int
            0 Bhattacharyya, 1 Vo & Ma, 2 heaviest.

        Returns
        -------
        offsets, w, m, P : ndarray
        """
        return reduce_mixtures(offsets, w, m, P, keep, elim, merge_thr, cap, rule)


_BHATTACHARYYA, _VO_MA = 0, 1


def reduce_mixtures(offsets, w, m, P, keep, elim, merge_thr, cap, rule):
    """Prune, merge and cap every kept mixture, all tracks at once, in any state dimension.

    The algorithm of :func:`rankedassign.tracking.reference.reduce_mixtures` (the plain-numpy
    twin of the compiled kernel; see there for the parameters and results), batched over the
    tracks: each round takes the heaviest remaining component of every track, the merging
    statistics of all remaining components against it in one call, and moment-matches the
    clusters of every track together, so the number of numpy calls grows with the largest
    number of clusters of a track, not with the number of tracks.

    Parameters
    ----------
    offsets : ndarray of int64, shape (T + 1,)
    w : ndarray, shape (C,)
    m : ndarray, shape (C, d)
    P : ndarray, shape (C, d, d)
    keep : ndarray of bool, shape (T,)
    elim, merge_thr : float
    cap : int
    rule : int
        0 Bhattacharyya, 1 Vo & Ma, 2 heaviest (as the kernel).

    Returns
    -------
    offsets : ndarray of int64, shape (T_kept + 1,)
    w : ndarray, shape (C_out,)
    m : ndarray, shape (C_out, d)
    P : ndarray, shape (C_out, d, d)

    Notes
    -----
    The decisions (which components merge, their order, the cap) are the twin's, and so is
    the arithmetic: the per-matrix LAPACK calls are the same, and a cluster's moments are
    summed in component order by ``np.add.at``, which for clusters of fewer than eight
    components is the order of the twin's ``sum`` (the test compares the two bit for bit on
    150 random 5-D cases with merges, pruning and the cap).

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign.tracking.nonlinear.step import reduce_mixtures
    >>> P = np.tile(np.eye(5), (3, 1, 1))
    >>> m = np.array([[0.0, 0, 0, 0, 0], [0.5, 0, 0, 0, 0], [9.0, 0, 0, 0, 0]])
    >>> off, ww, mm, PP = reduce_mixtures(np.array([0, 3]), np.array([0.5, 0.3, 0.2]), m, P,
    ...                                   np.array([True]), 1e-5, 4.0, 10, 0)
    >>> off.tolist(), ww.round(2).tolist(), mm[:, 0].round(4).tolist()
    ([0, 2], [0.8, 0.2], [0.1875, 9.0])
    """
    d = m.shape[1]
    kept = np.flatnonzero(keep)
    counts = np.diff(offsets)[kept]
    K = kept.size
    n = int(counts.sum())
    if n == 0:
        return (np.zeros(K + 1, dtype=np.int64), np.empty(0), np.empty((0, d)),
                np.empty((0, d, d)))
    tid = np.repeat(np.arange(K), counts)  # kept-track index of every component
    comp = np.repeat(offsets[kept], counts) + (np.arange(n) - np.repeat(
        np.cumsum(counts) - counts, counts))
    wk, mk, Pk = w[comp], m[comp], P[comp]
    # ln|P_i| of every component once (the twin computes them per round, matrix by matrix:
    # the same LAPACK call on the same matrix, so the same numbers)
    logdet_k = np.linalg.slogdet(Pk)[1] if rule == _BHATTACHARYYA else None
    idx = np.arange(n)
    # prune: w > elim, and the heaviest (first maximum) of every track always stays
    alive = wk > elim
    order = np.lexsort((idx, -wk, tid))
    first = np.r_[True, tid[order][1:] != tid[order][:-1]]
    alive[order[first]] = True
    cl_w, cl_m, cl_P, cl_t = [], [], [], []
    while alive.any():
        # the heaviest remaining component of every track (the first one on ties)
        ww = np.where(alive, wk, -np.inf)
        order = np.lexsort((idx, -ww, tid))
        first = np.r_[True, tid[order][1:] != tid[order][:-1]]
        heads = order[first]
        heads = heads[alive[heads]]
        head_of = np.full(K, -1)
        head_of[tid[heads]] = heads
        cand = np.flatnonzero(alive)
        j = head_of[tid[cand]]
        dm = mk[cand] - mk[j]
        if rule == _BHATTACHARYYA:
            Pbar = 0.5 * (Pk[cand] + Pk[j])
            maha = np.einsum("ci,cij,cj->c", dm, np.linalg.inv(Pbar), dm)
            # 4 ln(|P̄| / sqrt(|P_i| |P_j|)): eight times the Bhattacharyya distance
            dist = maha + 4.0 * (np.linalg.slogdet(Pbar)[1]
                                 - 0.5 * (logdet_k[cand] + logdet_k[j]))
        else:
            inv = np.linalg.inv(Pk[cand] if rule == _VO_MA else Pk[j])
            dist = np.einsum("ci,cij,cj->c", dm, inv, dm)
        dist[cand == j] = 0.0
        members = cand[dist <= merge_thr]
        alive[members] = False
        # moment matching per cluster (one cluster per track this round):
        # w = Σ w_i, m = Σ w_i m_i / w, P = Σ w_i (P_i + (m − m_i)(m − m_i)ᵀ) / w
        t = tid[members]
        wsum = np.zeros(K)
        np.add.at(wsum, t, wk[members])
        msum = np.zeros((K, d))
        np.add.at(msum, t, wk[members, None] * mk[members])
        has = np.flatnonzero(np.bincount(t, minlength=K) > 0)
        mean = msum[has] / wsum[has, None]
        pos = np.searchsorted(has, t)
        dev = mk[members] - mean[pos]
        Psum = np.zeros((has.size, d, d))
        np.add.at(Psum, pos, wk[members, None, None]
                  * (Pk[members] + dev[:, :, None] * dev[:, None, :]))
        cov = Psum / wsum[has, None, None]
        cl_w.append(wsum[has])
        cl_m.append(mean)
        cl_P.append(0.5 * (cov + cov.transpose(0, 2, 1)))
        cl_t.append(has)
    cw = np.concatenate(cl_w)
    cm = np.concatenate(cl_m)
    cP = np.concatenate(cl_P)
    ct = np.concatenate(cl_t)
    # a later cluster can outweigh an earlier one: per track sort (stable), cap, renormalise
    rank = np.arange(cw.size)  # creation order: the stable tie-break
    order = np.lexsort((rank, -cw, ct))
    cw, cm, cP, ct = cw[order], cm[order], cP[order], ct[order]
    nc = np.bincount(ct, minlength=K)
    within = np.arange(cw.size) - np.repeat(np.cumsum(nc) - nc, nc)
    sel = within < cap
    cw, cm, cP, ct = cw[sel], cm[sel], cP[sel], ct[sel]
    tot = np.zeros(K)
    np.add.at(tot, ct, cw)
    nk = np.bincount(ct, minlength=K)
    new_off = np.concatenate([[0], np.cumsum(nk)]).astype(np.int64)
    return new_off, cw / tot[ct], cm, cP


def single_object(model) -> SingleObject | None:
    """The single-object path a filter holds for ``model``: None for a linear ``Model``.

    Parameters
    ----------
    model : Model or NonlinearModel
        The filter's model.

    Returns
    -------
    SingleObject or None
        None: the model is the linear :class:`~rankedassign.tracking.models.Model`, whose
        filters run their compiled Kalman path unchanged.

    Examples
    --------
    >>> from rankedassign.tracking import make_model
    >>> from rankedassign.tracking.nonlinear.step import single_object
    >>> single_object(make_model("vo")) is None, single_object(make_model("vo-ukf")).ndim
    (True, 5)
    """
    return SingleObject(model) if isinstance(model, NonlinearModel) else None


class MultiSensorPath:
    """The per-sensor gates and the stacked update of the multi-sensor filters, non-linear.

    Parameters
    ----------
    model : NonlinearMultiSensorModel
        The sensors and the single-object filter.
    gate_prob : float or None
        Gate probability; each sensor's gate is ``χ²`` of its own measurement dimension at it.

    Attributes
    ----------
    paths : list of SingleObject
        One per sensor (``model.single(v)``).
    gates : list of float or None
        The gate threshold of every sensor.
    dims : tuple of int
        Measurement dimension of every sensor.

    Examples
    --------
    >>> from rankedassign.tracking.nonlinear.multisensor import make_nonlinear_multisensor_model
    >>> from rankedassign.tracking.nonlinear.step import MultiSensorPath
    >>> MultiSensorPath(make_nonlinear_multisensor_model(), 0.99).dims
    (2, 2)
    """

    def __init__(self, model: NonlinearMultiSensorModel, gate_prob: float | None):
        self.model = model
        self.filter = model.filter
        self.paths = [SingleObject(model.single(v)) for v in range(model.n_sensors)]
        self.dims = tuple(p.meas_ndim for p in self.paths)
        self.gates = [None if gate_prob is None else gate_threshold(gate_prob, d)
                      for d in self.dims]
        self._stacks = {}

    def check_measurements(self, v: int, z) -> np.ndarray:
        """Sensor ``v``'s measurements as ``(M, d_z)`` (messages name the sensor and model).

        Parameters
        ----------
        v : int
            The sensor.
        z : array_like
            Its measurements of the scan.

        Returns
        -------
        ndarray of float64, shape (M, d_z)
        """
        return check_measurements(
            z, f"measurements of sensor {v} ({self.paths[v].sensor.name})", dim=self.dims[v])

    def gated(self, v: int, m, P, z, offsets) -> np.ndarray:
        """The χ² gate ``(T, M)`` of sensor ``v`` on the wrapped innovations.

        Parameters
        ----------
        v : int
            The sensor.
        m, P : ndarray
            Predicted components ``(C, d)``, ``(C, d, d)``.
        z : ndarray, shape (M, d_z)
            Sensor ``v``'s measurements (``M >= 1``).
        offsets : ndarray of int64, shape (T + 1,)
            Component range of every track.

        Returns
        -------
        ndarray of bool, shape (T, M)
        """
        return self.paths[v].measurement_terms(m, P, z, offsets, self.gates[v]).gated

    def stacked(self, D, m, P, zD, update: bool):
        """``ln N(z_D; ẑ_D, S_D)`` for a batch of components, with the update if asked.

        Parameters
        ----------
        D : sequence of int
            The detecting sensors.
        m, P : ndarray, shapes (N, d), (N, d, d)
            One component per row.
        zD : ndarray, shape (N, Σ_{v∈D} d_z)
            The stacked measurements of each row.
        update : bool
            Also return the updated means and covariances.

        Returns
        -------
        ll : ndarray, shape (N,)
        m_upd, P_upd : ndarray or None
            ``m + K ν`` and ``P − K S Kᵀ`` with ``K = C S⁻¹`` (None without ``update``).
        """
        D = tuple(int(v) for v in D)
        if D not in self._stacks:
            self._stacks[D] = StackedSensor([self.paths[v].sensor for v in D])
        sensor = self._stacks[D]
        pred = self.filter.predict_measurement(sensor, m, P)
        nu = np.asarray(zD, dtype=np.float64) - pred.z
        if pred.angles.any():
            nu[:, pred.angles] = wrap_angle(nu[:, pred.angles])
        y = np.einsum("nij,nj->ni", pred.S_inv, nu)
        dz = nu.shape[1]
        # ln N(z; ẑ, S) = -(ν' S⁻¹ ν + d ln 2π + ln|S|) / 2
        ll = -0.5 * (nu * y).sum(axis=1) - 0.5 * dz * _LOG_2PI - 0.5 * pred.log_det
        if not update:
            return ll, None, None
        K = pred.cross @ pred.S_inv
        m_upd = m + np.einsum("nij,nj->ni", K, nu)
        P_upd = P - K @ pred.cross.transpose(0, 2, 1)
        return ll, m_upd, 0.5 * (P_upd + P_upd.transpose(0, 2, 1))


def multi_sensor_path(model, gate_prob) -> MultiSensorPath | None:
    """The multi-sensor path a filter holds for ``model``: None for a linear model.

    Parameters
    ----------
    model : MultiSensorModel or NonlinearMultiSensorModel
        The filter's model.
    gate_prob : float or None
        The filter's gate probability.

    Returns
    -------
    MultiSensorPath or None
    """
    if isinstance(model, NonlinearMultiSensorModel):
        return MultiSensorPath(model, gate_prob)
    return None

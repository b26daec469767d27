"""Gaussian single-object filters behind one interface: Kalman, extended and unscented Kalman.

Each filter has two model-dependent steps, batched over Gaussian components (means ``m (n, d)``,
covariances ``P (n, d, d)``):

* :meth:`~KalmanFilter.predict` through a motion model, ``(m, P) -> (m', P')``;
* :meth:`~KalmanFilter.predict_measurement` through a measurement model, giving a
  :class:`MeasurementPrediction` (``ẑ``, ``S``, the cross-covariance ``C = Cov(x, z)``);

and four steps that depend only on that prediction and the measurements ``z (M, d_z)``, the
same for every filter: :meth:`~KalmanFilter.innovations` (angle coordinates wrapped to
``(−π, π]``), :meth:`~KalmanFilter.log_likelihood`, :meth:`~KalmanFilter.gate` (χ² on the
wrapped innovations) and :meth:`~KalmanFilter.update` (``K = C S⁻¹``, ``m' = m + K ν``,
``P' = P − K Cᵀ``).

On a linear model with two measurement coordinates the arithmetic is that of today's filters
(:func:`rankedassign.tracking.reference.gate_and_distances` and the updates of
:class:`~rankedassign.tracking.LMBFilter`), bit for bit.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from ...validation import check_real
from .models import wrap_angle

__all__ = [
    "MeasurementPrediction",
    "KalmanFilter",
    "ExtendedKalmanFilter",
    "UnscentedKalmanFilter",
    "PairedFilter",
    "FILTERS",
    "make_single_object_filter",
]

_LOG_2PI = math.log(2.0 * math.pi)


class MeasurementPrediction(NamedTuple):
    """The predicted measurement of every component and what the update needs of it.

    Attributes
    ----------
    z : ndarray of float64, shape (n, d_z)
        Predicted measurement ``ẑ`` (angles in ``(−π, π]``).
    S : ndarray of float64, shape (n, d_z, d_z)
        Innovation covariance.
    cross : ndarray of float64, shape (n, d, d_z)
        Cross-covariance ``C = Cov(x, z)`` (``P Hᵀ`` for the Kalman filter and the EKF).
    S_inv : ndarray of float64, shape (n, d_z, d_z)
        ``S⁻¹``.
    log_det : ndarray of float64, shape (n,)
        ``ln |S|``.
    angles : ndarray of bool, shape (d_z,)
        Which coordinates are angles (wrapped in every difference).
    model : str
        Name of the measurement model, for messages.
    """

    z: np.ndarray
    S: np.ndarray
    cross: np.ndarray
    S_inv: np.ndarray
    log_det: np.ndarray
    angles: np.ndarray
    model: str


def _gaussians(m, P, d: int, who: str) -> tuple[np.ndarray, np.ndarray]:
    m = np.asarray(m, dtype=np.float64)
    P = np.asarray(P, dtype=np.float64)
    if m.ndim != 2 or m.shape[1] != d or P.shape != (m.shape[0], d, d):
        raise ValueError(f"{who}: means must have shape (n, {d}) and covariances (n, {d}, {d}), "
                         f"got {m.shape} and {P.shape}")
    if not (np.isfinite(m).all() and np.isfinite(P).all()):
        raise ValueError(f"{who}: the means and covariances must be finite")
    return m, P


def _measurements(z, pred: MeasurementPrediction) -> np.ndarray:
    dz = pred.angles.size
    z = np.asarray(z, dtype=np.float64)
    if z.ndim != 2 or z.shape[1] != dz:
        raise ValueError(f"{pred.model}: measurements must have shape (M, {dz}), got shape "
                         f"{z.shape}")
    if not np.isfinite(z).all():
        bad = int(np.flatnonzero(~np.isfinite(z).all(axis=1))[0])
        raise ValueError(f"{pred.model}: measurement {bad} is not finite: {z[bad].tolist()}")
    return z


def _inverse(S: np.ndarray, model: str, what: str) -> tuple[np.ndarray, np.ndarray]:
    """``(S⁻¹, ln|S|)``; closed form for 2 x 2 (today's arithmetic), Cholesky otherwise."""
    n, dz, _ = S.shape
    if dz == 2:
        det = S[:, 0, 0] * S[:, 1, 1] - S[:, 0, 1] * S[:, 1, 0]
        ok = np.isfinite(det) & (det > 0) & (S[:, 0, 0] > 0)
        if not ok.all():
            bad = int(np.flatnonzero(~ok)[0])
            raise ValueError(f"{model}: the {what} of component {bad} is not positive "
                             f"definite: {S[bad].tolist()}")
        Sinv = np.empty_like(S)
        Sinv[:, 0, 0] = S[:, 1, 1] / det
        Sinv[:, 1, 1] = S[:, 0, 0] / det
        Sinv[:, 0, 1] = -S[:, 0, 1] / det
        Sinv[:, 1, 0] = -S[:, 1, 0] / det
        with np.errstate(divide="ignore"):
            return Sinv, np.log(det)
    try:
        L = np.linalg.cholesky(S)
    except np.linalg.LinAlgError:
        ok = np.array([np.linalg.eigvalsh(s).min() > 0 if np.isfinite(s).all() else False
                       for s in S])
        bad = int(np.flatnonzero(~ok)[0]) if not ok.all() else 0
        raise ValueError(f"{model}: the {what} of component {bad} is not positive "
                         f"definite: {S[bad].tolist()}") from None
    Linv = np.linalg.inv(L)
    return Linv.transpose(0, 2, 1) @ Linv, 2.0 * np.log(np.diagonal(L, axis1=1, axis2=2)).sum(1)


def _symmetric(P: np.ndarray) -> np.ndarray:
    return 0.5 * (P + P.transpose(0, 2, 1))


class _GaussianFilter:
    """The steps that depend only on a :class:`MeasurementPrediction` (shared by all)."""

    name = "GaussianFilter"

    def innovations(self, pred: MeasurementPrediction, z) -> np.ndarray:
        """``ν = z_j − ẑ_c`` for every component and measurement, angles wrapped.

        Parameters
        ----------
        pred : MeasurementPrediction
            From the filter's ``predict_measurement``.
        z : array_like, shape (M, d_z)
            Measurements (finite; a bearing may lie outside ``(−π, π]``: only its wrapped
            difference is used).

        Returns
        -------
        ndarray of float64, shape (n, M, d_z)
            Innovations; angle coordinates in ``(−π, π]``.

        Raises
        ------
        ValueError
            On measurements of the wrong dimension or not finite.
        """
        z = _measurements(z, pred)
        nu = z[None, :, :] - pred.z[:, None, :]
        if pred.angles.any():
            nu[..., pred.angles] = wrap_angle(nu[..., pred.angles])
        return nu

    def mahalanobis(self, pred: MeasurementPrediction, z) -> np.ndarray:
        """Squared Mahalanobis distances ``νᵀ S⁻¹ ν`` on the wrapped innovations.

        Parameters
        ----------
        pred : MeasurementPrediction
            From the filter's ``predict_measurement``.
        z : array_like, shape (M, d_z)
            Measurements.

        Returns
        -------
        ndarray of float64, shape (n, M)
            The distances.
        """
        nu = self.innovations(pred, z)
        Si = pred.S_inv
        if nu.shape[-1] == 2:  # the expression of today's gate, for the same bits
            return (Si[:, None, 0, 0] * nu[..., 0] ** 2
                    + (Si[:, None, 0, 1] + Si[:, None, 1, 0]) * nu[..., 0] * nu[..., 1]
                    + Si[:, None, 1, 1] * nu[..., 1] ** 2)
        return np.einsum("cmi,cij,cmj->cm", nu, Si, nu)

    def log_likelihood(self, pred: MeasurementPrediction, z) -> np.ndarray:
        """``ln N(z_j; ẑ_c, S_c)`` on the wrapped innovations.

        Parameters
        ----------
        pred : MeasurementPrediction
            From the filter's ``predict_measurement``.
        z : array_like, shape (M, d_z)
            Measurements.

        Returns
        -------
        ndarray of float64, shape (n, M)
            ``−(νᵀ S⁻¹ ν + d_z ln 2π + ln|S|) / 2``.
        """
        maha = self.mahalanobis(pred, z)
        dz = pred.angles.size
        # ln N(z; ẑ, S) = -(d ln 2π + ln|S| + ν' S⁻¹ ν) / 2
        return -0.5 * maha - 0.5 * dz * _LOG_2PI - 0.5 * pred.log_det[:, None]

    def gate(self, pred: MeasurementPrediction, z, threshold: float) -> np.ndarray:
        """χ² gate: ``νᵀ S⁻¹ ν <= threshold`` on the wrapped innovations.

        Parameters
        ----------
        pred : MeasurementPrediction
            From the filter's ``predict_measurement``.
        z : array_like, shape (M, d_z)
            Measurements.
        threshold : float
            Gate size, e.g. ``scipy.stats.chi2.ppf(P_G, d_z)`` (Vo: ``P_G = 0.9999999``).

        Returns
        -------
        ndarray of bool, shape (n, M)
            Whether measurement ``j`` is in the gate of component ``c``.

        Raises
        ------
        ValueError
            If ``threshold`` is not a positive number.
        """
        threshold = check_real(threshold, "threshold", minimum=0.0, strict_minimum=True,
                               finite=False)
        return self.mahalanobis(pred, z) <= threshold

    def update(self, pred: MeasurementPrediction, m, P, z) -> tuple[np.ndarray, np.ndarray]:
        """Posterior of every component given every measurement.

        Parameters
        ----------
        pred : MeasurementPrediction
            From the filter's ``predict_measurement`` on ``(m, P)``.
        m : array_like, shape (n, d)
            Predicted means.
        P : array_like, shape (n, d, d)
            Predicted covariances.
        z : array_like, shape (M, d_z)
            Measurements.

        Returns
        -------
        m : ndarray of float64, shape (n, M, d)
            ``m_c + K_c ν_cj`` with ``K = C S⁻¹``.
        P : ndarray of float64, shape (n, d, d)
            ``P − K Cᵀ`` (symmetrised), independent of the measurement.
        """
        m, P = _gaussians(m, P, pred.cross.shape[1], pred.model)
        nu = self.innovations(pred, z)
        # K = C S⁻¹ ; P' = P − K C' (= P − K S K')
        K = pred.cross @ pred.S_inv
        P_upd = _symmetric(P - K @ pred.cross.transpose(0, 2, 1))
        # m' = m + K ν
        m_upd = m[:, None, :] + np.einsum("cij,cmj->cmi", K, nu)
        return m_upd, P_upd

    def _prediction(self, zhat, S, cross, sensor) -> MeasurementPrediction:
        Sinv, log_det = _inverse(S, f"{self.name} on {sensor.name}",
                                 "innovation covariance S")
        return MeasurementPrediction(zhat, S, cross, Sinv, log_det,
                                     np.asarray(sensor.angles, dtype=bool), sensor.name)

    def __repr__(self) -> str:
        return f"{type(self).__name__}()"


class KalmanFilter(_GaussianFilter):
    """The linear Kalman filter: both models must be linear (``model.linear``).

    Raises
    ------
    TypeError
        (from :meth:`predict`, :meth:`predict_measurement`) if a model is not linear.

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign.tracking.models import ConstantVelocity, PositionSensor
    >>> from rankedassign.tracking.nonlinear import (KalmanFilter, LinearGaussianMeasurement,
    ...                                             LinearGaussianMotion)
    >>> kf = KalmanFilter()
    >>> cv = LinearGaussianMotion.from_motion(ConstantVelocity())
    >>> pos = LinearGaussianMeasurement.from_sensor(PositionSensor())
    >>> m, P = kf.predict(cv, np.zeros((1, 4)), np.eye(4)[None])
    >>> pred = kf.predict_measurement(pos, m, P)
    >>> pred.S[0].diagonal().tolist()
    [108.25, 108.25]
    """

    name = "KalmanFilter"

    def _linear(self, model) -> None:
        if not getattr(model, "linear", False):
            raise TypeError(f"KalmanFilter: {model.name} is not linear; use "
                            "ExtendedKalmanFilter or UnscentedKalmanFilter")

    def predict(self, motion, m, P) -> tuple[np.ndarray, np.ndarray]:
        """``m' = F m``, ``P' = F P Fᵀ + Q``.

        Parameters
        ----------
        motion : LinearGaussianMotion
            A linear motion model (``F``, ``Q``).
        m : array_like, shape (n, d)
            Means.
        P : array_like, shape (n, d, d)
            Covariances.

        Returns
        -------
        m : ndarray of float64, shape (n, d)
            Predicted means.
        P : ndarray of float64, shape (n, d, d)
            Predicted covariances.
        """
        self._linear(motion)
        m, P = _gaussians(m, P, motion.ndim, motion.name)
        F = np.array(motion.F)
        # m <- F m ; P <- F P F' + Q (today's expressions)
        return m @ F.T, F @ P @ F.T + np.array(motion.Q)

    def predict_measurement(self, sensor, m, P) -> MeasurementPrediction:
        """``ẑ = H m``, ``S = H P Hᵀ + R``, ``C = P Hᵀ``.

        Parameters
        ----------
        sensor : LinearGaussianMeasurement
            A linear measurement model (``H``, ``R``).
        m : array_like, shape (n, d)
            Predicted means.
        P : array_like, shape (n, d, d)
            Predicted covariances.

        Returns
        -------
        MeasurementPrediction
        """
        self._linear(sensor)
        m, P = _gaussians(m, P, sensor.state_ndim, sensor.name)
        H = np.array(sensor.H)
        cross = P @ H.T
        return self._prediction(m @ H.T, H @ P @ H.T + np.array(sensor.R), cross, sensor)


class ExtendedKalmanFilter(_GaussianFilter):
    """The extended Kalman filter: the models' Jacobians at the mean.

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign.tracking.nonlinear import (BearingRange, CoordinatedTurn,
    ...                                             ExtendedKalmanFilter)
    >>> ekf = ExtendedKalmanFilter()
    >>> m, P = ekf.predict(CoordinatedTurn(), np.array([[0.0, 10, 100, 0, 0]]), np.eye(5)[None])
    >>> pred = ekf.predict_measurement(BearingRange(), m, P)
    >>> float(ekf.log_likelihood(pred, pred.z)[0, 0]) > -20
    True
    """

    name = "ExtendedKalmanFilter"

    def predict(self, motion, m, P) -> tuple[np.ndarray, np.ndarray]:
        """``m' = f(m)``, ``P' = J P Jᵀ + Q`` with ``J = ∂f/∂x (m)`` (symmetrised).

        Parameters
        ----------
        motion : object
            A motion model (``f``, ``jacobian``, ``Q``, ``ndim``, ``name``).
        m : array_like, shape (n, d)
            Means.
        P : array_like, shape (n, d, d)
            Covariances.

        Returns
        -------
        m : ndarray of float64, shape (n, d)
            Predicted means.
        P : ndarray of float64, shape (n, d, d)
            Predicted covariances.
        """
        m, P = _gaussians(m, P, motion.ndim, motion.name)
        J = motion.jacobian(m)
        # P <- J P J' + Q (Vo's ekf_predict_multiple, with his symmetrisation)
        return motion.f(m), _symmetric(J @ P @ J.transpose(0, 2, 1) + np.array(motion.Q))

    def predict_measurement(self, sensor, m, P) -> MeasurementPrediction:
        """``ẑ = h(m)``, ``S = H P Hᵀ + R``, ``C = P Hᵀ`` with ``H = ∂h/∂x (m)``.

        Parameters
        ----------
        sensor : object
            A measurement model (``h``, ``jacobian``, ``R``, ``angles``, ``state_ndim``).
        m : array_like, shape (n, d)
            Predicted means.
        P : array_like, shape (n, d, d)
            Predicted covariances.

        Returns
        -------
        MeasurementPrediction
        """
        m, P = _gaussians(m, P, sensor.state_ndim, sensor.name)
        H = sensor.jacobian(m)
        cross = P @ H.transpose(0, 2, 1)
        S = _symmetric(H @ cross + np.array(sensor.R))
        return self._prediction(sensor.h(m), S, cross, sensor)


class UnscentedKalmanFilter(_GaussianFilter):
    """The unscented Kalman filter (scaled sigma points, Julier & Uhlmann; Wan & van der Merwe).

    Parameters
    ----------
    alpha : float, optional
        Spread ``α > 0`` (default 1, Vo's).
    beta : float, optional
        Prior knowledge ``β`` (default 2, Vo's; optimal for Gaussians).
    kappa : float, optional
        Secondary scaling ``κ`` (default 2, Vo's).
    augmented : bool, optional
        Draw sigma points of the noise too (Vo's ``ut`` on ``[x; v]`` with
        ``blkdiag(P, Q_v)``, the noise entering as ``G v``; and on ``[x; w]`` with
        ``blkdiag(P, R)``, ``z = h(x) + w``). False (default): additive noise, ``Q`` and ``R``
        added to the sigma-point covariances. Both are exact on linear models.

    Attributes
    ----------
    alpha, beta, kappa : float
        The parameters.
    augmented : bool
        As given.

    Raises
    ------
    ValueError
        If ``alpha`` is not positive or a parameter is not finite; (from the steps) if
        ``α²(N + κ) <= 0`` for the dimension ``N`` of the sigma points, or the weights make a
        predicted covariance non-positive-definite.

    Notes
    -----
    ``λ = α²(N + κ) − N``; points ``x₀ = m``, ``x_{±i} = m ± (√((N + λ) P))_i`` (columns of
    the Cholesky factor); weights ``W₀ᵐ = λ/(N + λ)``, ``W₀ᶜ = W₀ᵐ + 1 − α² + β``,
    ``Wᵢ = 1/(2(N + λ))``. An angle coordinate is averaged as ``ẑ₀ + Σ Wᵢ wrap(ẑᵢ − ẑ₀)``
    and its deviations are wrapped.

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign.tracking.nonlinear import (BearingRange, CoordinatedTurn,
    ...                                             UnscentedKalmanFilter)
    >>> ukf = UnscentedKalmanFilter()
    >>> P0 = np.diag([1.0, 1.0, 1.0, 1.0, 1e-8])[None]  # turn rate known to 1e-4 rad/s
    >>> m, P = ukf.predict(CoordinatedTurn(), np.array([[0.0, 10, 100, 0, 0]]), P0)
    >>> m.round(6).tolist()
    [[10.0, 10.0, 100.0, 0.0, 0.0]]
    """

    name = "UnscentedKalmanFilter"

    def __init__(self, alpha: float = 1.0, beta: float = 2.0, kappa: float = 2.0, *,
                 augmented: bool = False):
        self.alpha = check_real(alpha, "alpha", minimum=0.0, strict_minimum=True)
        self.beta = check_real(beta, "beta")
        self.kappa = check_real(kappa, "kappa")
        if not isinstance(augmented, bool):
            raise TypeError(f"augmented must be a bool, got {type(augmented).__name__}")
        self.augmented = augmented

    def __repr__(self) -> str:
        return (f"UnscentedKalmanFilter(alpha={self.alpha!r}, beta={self.beta!r}, "
                f"kappa={self.kappa!r}, augmented={self.augmented!r})")

    def weights(self, N: int) -> tuple[np.ndarray, np.ndarray, float]:
        """Mean and covariance weights of the ``2N + 1`` sigma points and the scale ``N + λ``.

        Parameters
        ----------
        N : int
            Dimension of the sigma points.

        Returns
        -------
        wm, wc : ndarray of float64, shape (2N + 1,)
            Mean and covariance weights.
        scale : float
            ``N + λ = α²(N + κ)``.

        Raises
        ------
        ValueError
            If ``α²(N + κ) <= 0``.
        """
        scale = self.alpha**2 * (N + self.kappa)
        if not scale > 0:
            raise ValueError(f"UnscentedKalmanFilter: N + lambda = alpha^2 (N + kappa) = "
                             f"{scale!r} must be positive (N = {N}, kappa = {self.kappa!r})")
        lam = scale - N
        wm = np.full(2 * N + 1, 0.5 / scale)
        wm[0] = lam / scale
        wc = wm.copy()
        wc[0] += 1.0 - self.alpha**2 + self.beta
        return wm, wc, scale

    def _sigma_points(self, m, P, who: str):
        """Points ``(n, 2N + 1, N)`` (Vo's order: centre, minus, plus) and the weights."""
        N = m.shape[1]
        wm, wc, scale = self.weights(N)
        A = scale * P
        try:
            L = np.linalg.cholesky(A)
        except np.linalg.LinAlgError:
            # a positive semi-definite covariance (a noise-free component): its symmetric
            # square root; negative eigenvalues beyond rounding are refused
            vals, vecs = np.linalg.eigh(A)
            low = vals.min(axis=1)
            tol = -1e-12 * np.maximum(1.0, np.abs(vals).max(axis=1))
            if (low < tol).any():
                bad = int(np.flatnonzero(low < tol)[0])
                raise ValueError(f"{self.name} on {who}: the covariance of component {bad} "
                                 f"is not positive semi-definite (eigenvalue "
                                 f"{float(low[bad] / scale)!r})") from None
            L = vecs * np.sqrt(np.clip(vals, 0.0, None))[:, None, :]
        cols = L.transpose(0, 2, 1)  # (n, N, N): row i is the i-th column of L
        X = np.concatenate([m[:, None, :], m[:, None, :] - cols, m[:, None, :] + cols], axis=1)
        return X, wm, wc

    def _covariance(self, dev, wc, who: str, what: str, extra=None):
        # Σ Wᶜᵢ (yᵢ − ȳ)(yᵢ − ȳ)' (+ the additive noise)
        C = np.einsum("i,cij,cik->cjk", wc, dev, dev)
        if extra is not None:
            C = C + extra
        C = _symmetric(C)
        low = np.linalg.eigvalsh(C).min(axis=1) if C.size else np.zeros(0)
        tol = -1e-9 * np.maximum(1.0, np.abs(C).max(axis=(1, 2))) if C.size else low
        if (low < tol).any() or not np.isfinite(C).all():
            bad = int(np.flatnonzero(~(low >= tol))[0])
            raise ValueError(
                f"{self.name} on {who}: the sigma-point weights (alpha={self.alpha!r}, "
                f"beta={self.beta!r}, kappa={self.kappa!r}: W0c = {float(wc[0])!r}) make the "
                f"{what} "
                f"of component {bad} non-positive-definite (eigenvalue {float(low[bad])!r}); use "
                "alpha = 1 and kappa >= 0")
        return C

    def predict(self, motion, m, P) -> tuple[np.ndarray, np.ndarray]:
        """The unscented transform of ``N(m, P)`` through ``f``, plus the process noise.

        Parameters
        ----------
        motion : object
            A motion model (``f``, ``Q``, ``ndim``, ``name``; with ``augmented``, also
            ``noise_gain`` and ``noise_cov``).
        m : array_like, shape (n, d)
            Means.
        P : array_like, shape (n, d, d)
            Covariances.

        Returns
        -------
        m : ndarray of float64, shape (n, d)
            Predicted means.
        P : ndarray of float64, shape (n, d, d)
            Predicted covariances.
        """
        m, P = _gaussians(m, P, motion.ndim, motion.name)
        n, d = m.shape
        if self.augmented:
            G = np.array(motion.noise_gain)
            Qv = np.array(motion.noise_cov)
            q = G.shape[1]
            Pa = np.zeros((n, d + q, d + q))
            Pa[:, :d, :d] = P
            Pa[:, d:, d:] = Qv
            X, wm, wc = self._sigma_points(np.concatenate([m, np.zeros((n, q))], axis=1), Pa,
                                           motion.name)
            k = X.shape[1]
            # x' = f(x) + G v for every sigma point of [x; v]
            Y = (motion.f(X[:, :, :d].reshape(-1, d)).reshape(n, k, d)
                 + X[:, :, d:] @ G.T)
            extra = None
        else:
            X, wm, wc = self._sigma_points(m, P, motion.name)
            k = X.shape[1]
            Y = motion.f(X.reshape(-1, d)).reshape(n, k, d)
            extra = np.array(motion.Q)
        mean = np.einsum("i,cij->cj", wm, Y)
        cov = self._covariance(Y - mean[:, None, :], wc, motion.name,
                               "predicted covariance P", extra)
        return mean, cov

    def predict_measurement(self, sensor, m, P) -> MeasurementPrediction:
        """The unscented transform of ``N(m, P)`` through ``h``, plus the measurement noise.

        Parameters
        ----------
        sensor : object
            A measurement model (``h``, ``R``, ``angles``, ``state_ndim``, ``name``).
        m : array_like, shape (n, d)
            Predicted means.
        P : array_like, shape (n, d, d)
            Predicted covariances.

        Returns
        -------
        MeasurementPrediction
            ``C = Σ Wᶜᵢ (xᵢ − m)(zᵢ − ẑ)ᵀ``.
        """
        m, P = _gaussians(m, P, sensor.state_ndim, sensor.name)
        n, d = m.shape
        R = np.array(sensor.R)
        dz = R.shape[0]
        if self.augmented:
            Pa = np.zeros((n, d + dz, d + dz))
            Pa[:, :d, :d] = P
            Pa[:, d:, d:] = R
            X, wm, wc = self._sigma_points(np.concatenate([m, np.zeros((n, dz))], axis=1), Pa,
                                           sensor.name)
            k = X.shape[1]
            Z = sensor.h(X[:, :, :d].reshape(-1, d)).reshape(n, k, dz) + X[:, :, d:]
            extra = None
        else:
            X, wm, wc = self._sigma_points(m, P, sensor.name)
            k = X.shape[1]
            Z = sensor.h(X.reshape(-1, d)).reshape(n, k, dz)
            extra = R
        ang = np.asarray(sensor.angles, dtype=bool)
        if ang.any():
            # circular mean about the centre point: the sigma points may straddle ±π
            ref = Z[:, :1, :]
            dev0 = Z - ref
            dev0[..., ang] = wrap_angle(dev0[..., ang])
            zhat = ref[:, 0, :] + np.einsum("i,cij->cj", wm, dev0)
            zhat[:, ang] = wrap_angle(zhat[:, ang])
            dev = Z - zhat[:, None, :]
            dev[..., ang] = wrap_angle(dev[..., ang])
        else:
            zhat = np.einsum("i,cij->cj", wm, Z)
            dev = Z - zhat[:, None, :]
        S = self._covariance(dev, wc, sensor.name, "innovation covariance S", extra)
        xdev = X[:, :, :d] - m[:, None, :]
        cross = np.einsum("i,cij,cik->cjk", wc, xdev, dev)
        return self._prediction(zhat, S, cross, sensor)


class PairedFilter(_GaussianFilter):
    """One filter predicting as ``predictor`` and measuring as ``updater``.

    Stone Soup pairs a predictor and an updater that need not be of one family (an
    ``UnscentedKalmanPredictor`` with an ``ExtendedKalmanUpdater``); the filters hold one
    single-object filter, this pair.

    Parameters
    ----------
    predictor : KalmanFilter, ExtendedKalmanFilter or UnscentedKalmanFilter
        Gives :meth:`predict`.
    updater : KalmanFilter, ExtendedKalmanFilter or UnscentedKalmanFilter
        Gives :meth:`predict_measurement` (the update steps are the same for all).

    Attributes
    ----------
    predictor, updater : object
        As given.
    name : str
        ``"<predictor> + <updater>"``.

    Examples
    --------
    >>> from rankedassign.tracking.nonlinear.filters import (
    ...     ExtendedKalmanFilter, PairedFilter, UnscentedKalmanFilter)
    >>> PairedFilter(UnscentedKalmanFilter(), ExtendedKalmanFilter()).name
    'UnscentedKalmanFilter + ExtendedKalmanFilter'
    """

    def __init__(self, predictor, updater):
        self.predictor = predictor
        self.updater = updater
        self.name = f"{predictor.name} + {updater.name}"

    def __repr__(self) -> str:
        return f"PairedFilter({self.predictor!r}, {self.updater!r})"

    def predict(self, motion, m, P) -> tuple[np.ndarray, np.ndarray]:
        """The predictor's prediction (see its ``predict``).

        Parameters
        ----------
        motion : object
            A motion model.
        m : array_like, shape (n, d)
            Means.
        P : array_like, shape (n, d, d)
            Covariances.

        Returns
        -------
        m, P : ndarray of float64
            Predicted means and covariances.
        """
        return self.predictor.predict(motion, m, P)

    def predict_measurement(self, sensor, m, P) -> MeasurementPrediction:
        """The updater's measurement prediction (see its ``predict_measurement``).

        Parameters
        ----------
        sensor : object
            A measurement model.
        m : array_like, shape (n, d)
            Predicted means.
        P : array_like, shape (n, d, d)
            Predicted covariances.

        Returns
        -------
        MeasurementPrediction
        """
        return self.updater.predict_measurement(sensor, m, P)


#: The filters by name, as a run's settings give them.
FILTERS = {"kalman": KalmanFilter, "ekf": ExtendedKalmanFilter, "ukf": UnscentedKalmanFilter}


def make_single_object_filter(kind: str, **options):
    """A single-object filter by name.

    Parameters
    ----------
    kind : {"kalman", "ekf", "ukf"}
        Which filter.
    **options
        Options of :class:`UnscentedKalmanFilter` (``alpha``, ``beta``, ``kappa``,
        ``augmented``); none for the other two.

    Returns
    -------
    KalmanFilter or ExtendedKalmanFilter or UnscentedKalmanFilter

    Raises
    ------
    ValueError
        On an unknown ``kind``.
    TypeError
        On options the filter does not take.

    Examples
    --------
    >>> from rankedassign.tracking.nonlinear import make_single_object_filter
    >>> make_single_object_filter("ukf", augmented=True)
    UnscentedKalmanFilter(alpha=1.0, beta=2.0, kappa=2.0, augmented=True)
    """
    if kind not in FILTERS:
        raise ValueError(f"kind must be one of {sorted(FILTERS)}, got {kind!r}")
    return FILTERS[kind](**options)

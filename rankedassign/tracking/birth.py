"""Measurement-driven birth for the single-sensor LMB and δ-GLMB filters.

Instead of birth components placed by hand, every measurement of scan ``k`` that the tracks do
not explain starts a birth track of scan ``k + 1`` (the adaptive birth of Reuter, Vo, Vo &
Dietmayer 2014, §IV.E):

1. ``r_A(z)``, the probability that measurement ``z`` was associated to a track: for the LMB
   filter the sum over tracks of the association marginals of ``z``; for the δ-GLMB filter
   the total weight of the hypotheses whose track set uses ``z``. ``r_U(z) = 1 − r_A(z)``,
   clipped to ``[0, 1]``;
2. the existence of the birth at ``z``::

       r_B(z) = min(r_max, r_U(z) / Σ_z' r_U(z') · λ_B)

   with ``λ_B`` the expected number of births per scan (nothing is born when every
   measurement is explained, ``Σ r_U = 0``); births with ``r_B <= r_min`` are dropped;
3. its state, one Gaussian from the measurement through the sensor: for a position sensor
   (``H`` picks ``d`` of the ``n`` state components) the measured components are ``z`` with
   covariance ``R``, the unmeasured ones the user's prior ``N(prior_mean, prior_cov)``
   (the velocity of a constant-velocity state)::

       m_B = Hᵀ z + U μ_u ,  P_B = Hᵀ R H + U P_u Uᵀ

   ``U`` the ``n × (n − d)`` selection of the unmeasured components. The filter predicts it
   to scan ``k + 1`` with the motion of that scan, as every other track.

:class:`MeasurementBirth` holds the settings and :meth:`MeasurementBirth.births` computes
steps 2–3 (pure numpy; a scan has at most a few hundred measurements). The filters call it
after each update and append the births in the next prediction with labels ``(k + 1, b)``.

References
----------
.. [1] S. Reuter, B.-T. Vo, B.-N. Vo, K. Dietmayer, "The Labeled Multi-Bernoulli Filter",
   IEEE Trans. Signal Process. 62(12):3246-3260, 2014 (§IV.E, adaptive birth).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from ..validation import check_real

__all__ = ["BirthComponents", "MeasurementBirth", "birth_existence"]


class BirthComponents(NamedTuple):
    """Birth tracks made from one scan's measurements, one Gaussian each.

    Attributes
    ----------
    r : ndarray of float64, shape (B,)
        Existence probabilities ``r_B``, in ``(r_min, r_max]``.
    means : ndarray of float64, shape (B, n)
        Means at the time of the measurements (not yet predicted).
    covs : ndarray of float64, shape (B, n, n)
        Covariances, symmetric positive definite.
    measurements : ndarray of int64, shape (B,)
        Index of the measurement each birth comes from, increasing.
    """

    r: np.ndarray
    means: np.ndarray
    covs: np.ndarray
    measurements: np.ndarray

    @classmethod
    def empty(cls, n: int = 4) -> BirthComponents:
        """No births, for a state of dimension ``n``.

        Parameters
        ----------
        n : int, optional
            State dimension (default 4).

        Returns
        -------
        BirthComponents
            Arrays of shapes (0,), (0, n), (0, n, n) and (0,).
        """
        return cls(np.zeros(0), np.zeros((0, n)), np.zeros((0, n, n)),
                   np.zeros(0, dtype=np.int64))


def birth_existence(r_A, lambda_b: float, r_max: float) -> np.ndarray:
    """``r_B(z) = min(r_max, (1 − r_A(z)) / Σ_z' (1 − r_A(z')) · λ_B)`` of every measurement.

    Parameters
    ----------
    r_A : array_like of float, shape (M,)
        Probability that each measurement was associated to a track; clipped to ``[0, 1]``
        (sums of marginals may exceed 1 by rounding).
    lambda_b : float
        Expected number of births per scan, ``> 0``.
    r_max : float
        Cap on a birth's existence, in ``(0, 1]``.

    Returns
    -------
    ndarray of float64, shape (M,)
        The existence of the birth at each measurement; all zero when every measurement is
        explained (``Σ (1 − r_A) = 0``) or there is none.

    Raises
    ------
    ValueError
        If ``r_A`` is not 1-D or holds NaN.

    Examples
    --------
    >>> from rankedassign.tracking.birth import birth_existence
    >>> birth_existence([0.0, 0.5, 1.0], lambda_b=0.3, r_max=0.15).tolist()
    [0.15, 0.1, 0.0]
    """
    r_A = np.asarray(r_A, dtype=np.float64)
    if r_A.ndim != 1:
        raise ValueError(f"r_A must be 1-D, got shape {r_A.shape}")
    if np.isnan(r_A).any():
        raise ValueError("r_A holds NaN")
    r_U = 1.0 - np.clip(r_A, 0.0, 1.0)
    total = r_U.sum()
    if total <= 0.0:
        return np.zeros(r_A.size)
    # r_B(z) = min(r_max, r_U(z) / Σ r_U · λ_B)   (Reuter et al. 2014, eq. 75)
    return np.minimum(r_max, r_U / total * lambda_b)


def _prior(value, size: int, what: str, *, cov: bool) -> np.ndarray:
    """The prior mean (``cov=False``) or covariance of the unmeasured components, checked."""
    try:
        arr = np.array(value, dtype=np.float64)
    except (TypeError, ValueError):
        raise TypeError(f"{what} must be a numeric array, got {value!r}") from None
    if cov:
        if arr.ndim == 0:               # a variance shared by every unmeasured component
            arr = arr * np.eye(size)
        elif arr.ndim == 1:             # a diagonal
            arr = np.diag(arr)
        shape = (size, size)
    else:
        if arr.ndim == 0:
            arr = np.full(size, float(arr))
        shape = (size,)
    if arr.shape != shape:
        raise ValueError(f"{what} must have shape {shape} for the {size} unmeasured state "
                         f"components of this sensor, got shape {arr.shape}")
    if not np.isfinite(arr).all():
        raise ValueError(f"{what} must be finite")
    if cov:
        if not np.allclose(arr, arr.T, rtol=1e-10, atol=0.0):
            raise ValueError(f"{what} must be symmetric")
        if size and np.linalg.eigvalsh(arr).min() <= 0:
            raise ValueError(f"{what} must be positive definite")
    return arr


def _selection(H: np.ndarray) -> np.ndarray:
    """The state component each row of a position sensor's ``H`` measures."""
    H = np.asarray(H, dtype=np.float64)
    if H.ndim != 2 or H.shape[0] > H.shape[1]:
        raise ValueError(f"H must be a (d, n) matrix with d <= n, got shape {H.shape}")
    idx = np.argmax(np.abs(H), axis=1)
    sel = np.zeros_like(H)
    sel[np.arange(H.shape[0]), idx] = 1.0
    if not np.array_equal(H, sel) or np.unique(idx).size != idx.size:
        raise ValueError("measurement birth needs a position sensor: every row of H picks one "
                         f"distinct state component, got H = {H.tolist()}")
    return idx


@dataclass(frozen=True)
class MeasurementBirth:
    """Settings of the measurement-driven (adaptive) birth of the single-sensor filters.

    Pass an instance as ``LMBFilter(model, association, birth=MeasurementBirth(...))`` or
    ``GLMBFilter(..., birth=MeasurementBirth(...))``: the model's static birth is then not
    used, and every measurement of a scan that the tracks do not explain makes a birth track
    of the next scan (module docstring).

    Parameters
    ----------
    lambda_b : float
        Expected number of births per scan ``λ_B``, ``> 0`` (default 0.1).
    r_max : float
        Cap ``r_B,max`` on a birth's existence, in ``(0, 1]`` (default 0.1).
    velocity_mean : float or array_like, shape (n − d,)
        Prior mean of the state components the sensor does not measure (the velocity of the
        4-D constant-velocity state; default 0). A scalar is used for every component.
    velocity_cov : float or array_like, shape (n − d,) or (n − d, n − d)
        Prior covariance of those components: a variance shared by all, a diagonal, or a full
        symmetric positive definite matrix (default ``10² = 100``: 10 m/s per axis).
    max_births : int or None
        Keep at most this many births per scan, those of largest ``r_B`` (default None: no
        cap).
    r_min : float
        Drop births with ``r_B <= r_min``, in ``[0, r_max]`` (default ``10⁻³``, the LMB
        filter's ``prune_track``: a birth that would be pruned after its first update is not
        worth a row of the association).

    Attributes
    ----------
    lambda_b, r_max : float
        As given, checked.
    velocity_mean, velocity_cov : tuple or float
        As given (an array is stored as nested tuples, so that settings compare by value);
        their dimension is checked against the sensor by :meth:`births`.
    max_births : int or None
        As given.
    r_min : float
        As given, checked.

    Raises
    ------
    TypeError
        If a setting is not a real number (``bool`` included) or the prior is not numeric.
    ValueError
        If ``lambda_b <= 0`` or NaN, ``r_max`` outside ``(0, 1]``, ``r_min`` outside
        ``[0, r_max]``, ``max_births < 1``, or the
        prior is not finite (its shape is checked by :meth:`births`, which knows the state
        dimension).

    References
    ----------
    .. [1] S. Reuter, B.-T. Vo, B.-N. Vo, K. Dietmayer, "The Labeled Multi-Bernoulli Filter",
       IEEE Trans. Signal Process. 62(12), 2014.

    Examples
    --------
    >>> from rankedassign.tracking.birth import MeasurementBirth
    >>> b = MeasurementBirth(lambda_b=0.2, r_max=0.05)
    >>> b.lambda_b, b.r_max, b.velocity_mean, b.velocity_cov, b.max_births, b.r_min
    (0.2, 0.05, 0.0, 100.0, None, 0.001)
    """

    lambda_b: float = 0.1
    r_max: float = 0.1
    velocity_mean: object = 0.0
    velocity_cov: object = 100.0
    max_births: int | None = None
    r_min: float = 1e-3

    def __post_init__(self):
        s = object.__setattr__
        s(self, "lambda_b", check_real(self.lambda_b, "lambda_b", minimum=0.0,
                                       strict_minimum=True))
        s(self, "r_max", check_real(self.r_max, "r_max", minimum=0.0, strict_minimum=True,
                                    maximum=1.0))
        s(self, "r_min", check_real(self.r_min, "r_min", minimum=0.0, maximum=self.r_max))
        for name in ("velocity_mean", "velocity_cov"):
            value = getattr(self, name)
            try:
                arr = np.array(value, dtype=np.float64)
            except (TypeError, ValueError):
                raise TypeError(f"{name} must be a number or a numeric array, got "
                                f"{value!r}") from None
            if isinstance(value, bool) or arr.dtype == object:
                raise TypeError(f"{name} must be a number or a numeric array, got {value!r}")
            if not np.isfinite(arr).all():
                raise ValueError(f"{name} must be finite, got {arr.tolist()}")
            s(self, name, float(arr) if arr.ndim == 0 else
              (tuple(arr.tolist()) if arr.ndim == 1 else tuple(map(tuple, arr.tolist()))))
        if self.max_births is not None:
            if isinstance(self.max_births, bool) or not isinstance(self.max_births,
                                                                   (int, np.integer)):
                raise TypeError(f"max_births must be an int or None, got {self.max_births!r}")
            if self.max_births < 1:
                raise ValueError(f"max_births must be >= 1, got {self.max_births}")
            s(self, "max_births", int(self.max_births))

    def births(self, z, r_A, *, H, R) -> BirthComponents:
        """The birth tracks made from one scan's measurements (steps 2–3 of the module).

        Parameters
        ----------
        z : array_like, shape (M, d)
            The scan's measurements.
        r_A : array_like, shape (M,)
            Probability that each was associated to a track (clipped to ``[0, 1]``).
        H : array_like, shape (d, n)
            The sensor's measurement matrix; each row picks one state component.
        R : array_like, shape (d, d)
            The sensor's noise covariance.

        Returns
        -------
        BirthComponents
            The kept births in measurement order, means and covariances at the time of ``z``.

        Raises
        ------
        ValueError
            On shapes that disagree, a sensor that is not a position sensor, or a prior whose
            dimension is not the ``n − d`` unmeasured components.

        Examples
        --------
        >>> import numpy as np
        >>> from rankedassign.tracking.birth import MeasurementBirth
        >>> H = np.array([[1.0, 0, 0, 0], [0, 0, 1.0, 0]])
        >>> b = MeasurementBirth(lambda_b=0.2, r_max=0.15, velocity_cov=4.0).births(
        ...     [[10.0, 20.0], [30.0, 40.0]], [0.0, 0.9], H=H, R=np.eye(2))
        >>> b.r.round(6).tolist(), b.means.tolist()
        ([0.15, 0.018182], [[10.0, 0.0, 20.0, 0.0], [30.0, 0.0, 40.0, 0.0]])
        >>> np.diag(b.covs[0]).tolist()
        [1.0, 4.0, 1.0, 4.0]
        """
        H = np.asarray(H, dtype=np.float64)
        idx = _selection(H)
        d, n = H.shape
        R = np.asarray(R, dtype=np.float64)
        if R.shape != (d, d):
            raise ValueError(f"R must have shape {(d, d)}, got {R.shape}")
        z, r, keep, free, mu_u, P_u = self._scan(z, r_A, d, n, idx)
        B = keep.size
        # m_B = Hᵀ z + U μ_u ; P_B = Hᵀ R H + U P_u Uᵀ
        means = np.empty((B, n))
        means[:, idx] = z[keep]
        means[:, free] = mu_u
        cov = np.zeros((n, n))
        cov[np.ix_(idx, idx)] = R
        cov[np.ix_(free, free)] = P_u
        covs = np.broadcast_to(cov, (B, n, n)).copy()
        return BirthComponents(r[keep], means, covs, keep.astype(np.int64))

    def _scan(self, z, r_A, dz: int, n: int, idx: np.ndarray) -> tuple:
        """The scan's ``(M, dz)`` measurements checked against ``r_A``, their ``r_B``, the kept
        ones, and the dimensions of an ``n``-state that ``idx`` leaves free with their prior."""
        z = np.asarray(z, dtype=np.float64).reshape(-1, dz)
        r_A = np.asarray(r_A, dtype=np.float64).reshape(-1)
        if r_A.size != z.shape[0]:
            raise ValueError(f"r_A has {r_A.size} entries for {z.shape[0]} measurements")
        free = np.setdiff1d(np.arange(n), idx)
        mu_u = _prior(self.velocity_mean, free.size, "velocity_mean", cov=False)
        P_u = _prior(self.velocity_cov, free.size, "velocity_cov", cov=True)
        r, keep = self._kept(r_A)
        return z, r, keep, free, mu_u, P_u

    def _kept(self, r_A) -> tuple[np.ndarray, np.ndarray]:
        """``r_B`` of every measurement and the measurements whose birth is kept."""
        r = birth_existence(r_A, self.lambda_b, self.r_max)
        keep = np.flatnonzero(r > self.r_min)
        if self.max_births is not None and keep.size > self.max_births:
            # the max_births most likely, back in measurement order
            keep = np.sort(keep[np.argsort(-r[keep], kind="stable")[:self.max_births]])
        return r, keep

    def births_from(self, z, r_A, sensor) -> BirthComponents:
        """The birth tracks of one scan for any measurement model (linear or not).

        A linear sensor (one with ``H``) gives :meth:`births` with its ``H`` and ``R``, bit
        for bit. A non-linear one places each birth through its inverse measurement function
        ``sensor.inverse(z) -> (p, J)``: the position components ``sensor.position_indices``
        get the mean ``p`` and, by linearisation, the covariance ``J R Jᵀ``; the other
        components the prior, as for a position sensor::

            m_B = [p ; μ_u] ,  P_B = blkdiag(J R Jᵀ, P_u)

        Parameters
        ----------
        z : array_like, shape (M, d_z)
            The scan's measurements.
        r_A : array_like, shape (M,)
            Probability that each was associated to a track.
        sensor : object
            A measurement model of :mod:`rankedassign.tracking.nonlinear` (or a
            :class:`~rankedassign.tracking.models.PositionSensor`).

        Returns
        -------
        BirthComponents
            As :meth:`births`.

        Raises
        ------
        TypeError
            If the sensor is not linear and has no ``inverse`` (a bearing-only sensor: a
            bearing does not place a target; give static births).
        ValueError
            As :meth:`births`.

        Examples
        --------
        >>> import numpy as np
        >>> from rankedassign.tracking.birth import MeasurementBirth
        >>> from rankedassign.tracking.nonlinear import BearingRange
        >>> b = MeasurementBirth(lambda_b=0.1).births_from(
        ...     [[0.0, 100.0]], [0.0], BearingRange(state_ndim=4))
        >>> b.means.round(6).tolist()
        [[0.0, 0.0, 100.0, 0.0]]
        """
        if getattr(sensor, "linear", True) and hasattr(sensor, "H"):
            return self.births(z, r_A, H=sensor.H, R=sensor.R)
        name = getattr(sensor, "name", type(sensor).__name__)
        if not callable(getattr(sensor, "inverse", None)):
            raise TypeError(f"measurement birth needs the measurement model's inverse (a "
                            f"position from a measurement): {name} has no inverse (a bearing "
                            "alone does not place a target); give static births")
        R = np.asarray(sensor.R, dtype=np.float64)
        dz = R.shape[0]
        n = int(sensor.state_ndim)
        idx = np.array(sensor.position_indices, dtype=np.int64)
        z, r, keep, free, mu_u, P_u = self._scan(z, r_A, dz, n, idx)
        B = keep.size
        p, J = sensor.inverse(z[keep]) if B else (np.empty((0, idx.size)),
                                                   np.empty((0, idx.size, dz)))
        means = np.empty((B, n))
        means[:, idx] = p
        means[:, free] = mu_u
        covs = np.zeros((B, n, n))
        # P_pos = J R Jᵀ (the linearised inverse)
        Pp = J @ R @ J.transpose(0, 2, 1)
        covs[:, idx[:, None], idx[None, :]] = 0.5 * (Pp + Pp.transpose(0, 2, 1))
        covs[:, free[:, None], free[None, :]] = P_u
        return BirthComponents(r[keep], means, covs, keep.astype(np.int64))

"""Single-object models of any state and measurement dimension: motion, measurement, clutter.

A *motion model* moves a batch of states one scan on: ``f(x)`` with its Jacobian and the
process noise ``Q``; a *measurement model* maps states to measurements: ``h(x)`` with its
Jacobian, the noise ``R``, which measurement coordinates are angles, and which state
components are the position. The filters of :mod:`rankedassign.tracking.nonlinear.filters`
(Kalman, EKF, UKF) use nothing else, so a user's own model is any object with these
attributes (see the "Non-linear models" page of the documentation).

Shapes are batched over Gaussian components: states ``x (n, d)``, Jacobians ``(n, d, d)`` and
``(n, d_z, d)``, measurements ``(M, d_z)``.

Angles are wrapped to ``(−π, π]`` by :func:`wrap_angle` wherever two of them are compared.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...validation import check_real
from ..models import ConstantVelocity, LinearMotion, PositionSensor, _readonly, _real_array

__all__ = [
    "MAX_TURN_PER_SCAN",
    "wrap_angle",
    "LinearGaussianMotion",
    "CoordinatedTurn",
    "LinearGaussianMeasurement",
    "BearingRange",
    "BearingRangeClutter",
    "GaussianBirth",
]

#: Largest turn ``|ω| Δ`` (radians per scan) a :class:`CoordinatedTurn` accepts. Beyond it
#: ``sin(ω Δ)`` keeps fewer than 6 correct digits (float64 resolves ``ω Δ`` to ``1e6 · 2.2e-16``
#: rad), and no target turns a hundred thousand times between two scans: such a rate is a
#: corrupted state, refused rather than propagated.
MAX_TURN_PER_SCAN = 1e6

# |ω Δ| below this: the CT coefficients by their Taylor series (no division by ω). The first
# omitted terms are at most (ω Δ)^6 / 5040 ≈ 2e-16 relative at the switch; above it the
# closed form of da/dω, (ωΔ cos ωΔ − sin ωΔ)/ω², loses at most 1e-16 / (ωΔ)² = 1e-12 relative
# to cancellation.
_SERIES_BELOW = 1e-2


def wrap_angle(a):
    """Angles wrapped to ``(−π, π]``.

    Parameters
    ----------
    a : array_like of float
        Angles in radians, any shape.

    Returns
    -------
    ndarray of float64
        ``π − ((π − a) mod 2π)``: the representative of ``a`` in ``(−π, π]`` (``−π`` maps to
        ``π``); NaN stays NaN.

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign.tracking.nonlinear import wrap_angle
    >>> wrap_angle([np.pi, -np.pi, 3 * np.pi / 2, 0.5]).round(6).tolist()
    [3.141593, 3.141593, -1.570796, 0.5]
    """
    a = np.asarray(a, dtype=np.float64)
    return np.pi - np.mod(np.pi - a, 2.0 * np.pi)


def _psd(Q, n: int, what: str, *, strict: bool) -> np.ndarray:
    """``Q`` as a read-only symmetric n x n matrix, positive definite (``strict``) or semi-."""
    given = _real_array(Q, what)
    Q = np.diag(given) if given.ndim == 1 else given
    kind = "positive definite" if strict else "positive semi-definite"
    with np.errstate(all="ignore"):
        ok = Q.shape == (n, n) and np.isfinite(Q).all() and np.allclose(Q, Q.T)
        if ok:
            low = np.linalg.eigvalsh(Q).min()
            ok = low > 0 if strict else low >= -1e-12 * max(1.0, np.abs(Q).max())
    if not ok:
        raise ValueError(f"{what} must be a symmetric {kind} {n}x{n} matrix, got shape "
                         f"{Q.shape}" + ("" if Q.shape != (n, n) else f" with values {Q.tolist()}"))
    return _readonly(Q)


def _states(x, d: int, who: str) -> np.ndarray:
    """``x`` as a float64 ``(n, d)`` array of finite states (a single ``(d,)`` state too)."""
    x = np.asarray(x, dtype=np.float64)
    if x.ndim == 1:
        x = x[None, :]
    if x.ndim != 2 or x.shape[1] != d:
        raise ValueError(f"{who}: states must have shape (n, {d}), got shape {x.shape}")
    if not np.isfinite(x).all():
        bad = int(np.flatnonzero(~np.isfinite(x).all(axis=1))[0])
        raise ValueError(f"{who}: state {bad} is not finite: {x[bad].tolist()}")
    return x


# ------------------------------------------------------------------------------------- motion
@dataclass(frozen=True, eq=False)
class LinearGaussianMotion:
    """Linear-Gaussian motion ``x' = F x + G v``, ``v ~ N(0, Q_v)``, ``Q = G Q_v Gᵀ``.

    Parameters
    ----------
    F : array_like, shape (d, d)
        State transition matrix (finite).
    Q : array_like, shape (d, d)
        Process noise covariance, symmetric positive semi-definite.
    noise_gain : array_like, shape (d, q), optional
        ``G``, for the augmented unscented transform; default the identity (``q = d``).
    noise_cov : array_like, shape (q, q), optional
        ``Q_v``; default ``Q``. ``G Q_v Gᵀ`` must equal ``Q``.
    name : str, optional
        The model's name in messages (default ``"LinearGaussianMotion"``).

    Attributes
    ----------
    F, Q, noise_gain, noise_cov : ndarray of float64
        Read-only matrices.
    name : str
        The model's name in messages.
    linear : bool
        True: the Kalman filter applies.
    ndim : int
        State dimension ``d``.

    Raises
    ------
    ValueError
        If ``F`` is not a finite square matrix, ``Q`` not symmetric positive semi-definite
        of its size, or ``G Q_v Gᵀ`` differs from ``Q``.

    Examples
    --------
    >>> from rankedassign.tracking.models import ConstantVelocity
    >>> from rankedassign.tracking.nonlinear import LinearGaussianMotion
    >>> cv = LinearGaussianMotion.from_motion(ConstantVelocity())
    >>> cv.ndim, cv.noise_gain.shape
    (4, (4, 2))
    """

    F: np.ndarray
    Q: np.ndarray
    noise_gain: np.ndarray | None = None
    noise_cov: np.ndarray | None = None
    name: str = "LinearGaussianMotion"

    linear = True

    def __post_init__(self):
        F = _real_array(self.F, f"{self.name}: F")
        if F.ndim != 2 or F.shape[0] != F.shape[1] or not np.isfinite(F).all():
            raise ValueError(f"{self.name}: F must be a finite square matrix, got shape {F.shape}")
        d = F.shape[0]
        Q = _psd(self.Q, d, f"{self.name}: the process noise covariance Q", strict=False)
        G = np.eye(d) if self.noise_gain is None else _real_array(self.noise_gain,
                                                                  f"{self.name}: noise_gain")
        if G.ndim != 2 or G.shape[0] != d or not np.isfinite(G).all():
            raise ValueError(f"{self.name}: noise_gain must be a finite ({d}, q) matrix, got "
                             f"shape {G.shape}")
        Qv = Q if self.noise_cov is None else _psd(
            self.noise_cov, G.shape[1], f"{self.name}: noise_cov", strict=False)
        if not np.allclose(G @ Qv @ G.T, Q, rtol=1e-12, atol=1e-12 * max(1.0, np.abs(Q).max())):
            raise ValueError(f"{self.name}: noise_gain G and noise_cov Q_v must give "
                             "Q = G Q_v G'")
        for k, v in (("F", F), ("Q", Q), ("noise_gain", G), ("noise_cov", Qv)):
            object.__setattr__(self, k, _readonly(v))

    @classmethod
    def from_motion(cls, motion) -> LinearGaussianMotion:
        """Today's motion models in this interface, with the same ``F`` and ``Q`` bit for bit.

        Parameters
        ----------
        motion : ConstantVelocity or LinearMotion
            A motion model of :mod:`rankedassign.tracking.models`.

        Returns
        -------
        LinearGaussianMotion
            With ``F = motion.F`` and ``Q = motion.Q``; for :class:`ConstantVelocity` also its
            gain ``G`` and ``Q_v = σ_w² I₂``.

        Raises
        ------
        TypeError
            If ``motion`` is of another type.
        """
        if isinstance(motion, ConstantVelocity):
            return cls(motion.F, motion.Q, motion.G, motion.sigma_w**2 * np.eye(2),
                       name="ConstantVelocity")
        if isinstance(motion, LinearMotion):
            return cls(motion.F, motion.Q, name="LinearMotion")
        raise TypeError(f"motion must be a ConstantVelocity or LinearMotion, got "
                        f"{type(motion).__name__}")

    @property
    def ndim(self) -> int:
        """State dimension ``d``."""
        return int(self.F.shape[0])

    def f(self, x) -> np.ndarray:
        """``F x`` for every row of ``x``.

        Parameters
        ----------
        x : array_like, shape (n, d)
            States.

        Returns
        -------
        ndarray of float64, shape (n, d)
            ``x Fᵀ``.
        """
        x = _states(x, self.ndim, self.name)
        return x @ self.F.T

    def jacobian(self, x) -> np.ndarray:
        """``F`` for every row of ``x``.

        Parameters
        ----------
        x : array_like, shape (n, d)
            States.

        Returns
        -------
        ndarray of float64, shape (n, d, d)
            ``F`` repeated.
        """
        x = _states(x, self.ndim, self.name)
        return np.broadcast_to(self.F, (x.shape[0],) + self.F.shape).copy()


@dataclass(frozen=True)
class CoordinatedTurn:
    """Coordinated turn with the turn rate in the state, ``x = [p_x, v_x, p_y, v_y, ω]``.

    The form of Vo's ``gen_newstate_fn.m`` (the CT examples of his toolbox).

    Parameters
    ----------
    dt : float
        Sampling period ``Δ`` in s (default 1).
    sigma_vel : float
        Standard deviation of the white acceleration noise per axis in m/s² (default 5).
    sigma_turn : float
        Standard deviation of the turn-rate noise in rad/s (default ``π/180``).

    Attributes
    ----------
    dt, sigma_vel, sigma_turn : float
        As given (Python floats).
    name : str
        ``"CoordinatedTurn"``, the model's name in messages.
    linear : bool
        False: the EKF or the UKF is needed.
    ndim : int
        5.
    noise_gain : ndarray, shape (5, 3)
        ``G = [[σ_v Δ²/2, 0, 0], [σ_v Δ, 0, 0], [0, σ_v Δ²/2, 0], [0, σ_v Δ, 0], [0, 0, σ_ω Δ]]``
        (Vo's ``B2``).
    noise_cov : ndarray, shape (3, 3)
        ``I₃`` (Vo's ``Q``).
    Q : ndarray, shape (5, 5)
        ``G Gᵀ`` (rank 3).

    Raises
    ------
    TypeError
        If a parameter is not a real number.
    ValueError
        If ``dt`` is not positive and finite or a standard deviation negative or not finite.

    Notes
    -----
    With ``a = sin(ωΔ)/ω``, ``b = (1 − cos ωΔ)/ω`` (``a → Δ``, ``b → 0`` as ``ω → 0``)::

        p_x' = p_x + a v_x − b v_y        v_x' = cos(ωΔ) v_x − sin(ωΔ) v_y
        p_y' = p_y + b v_x + a v_y        v_y' = sin(ωΔ) v_x + cos(ωΔ) v_y        ω' = ω

    For ``|ωΔ| < 10⁻²`` the coefficients and their derivatives come from their Taylor series,
    so the model is exact in the limit ``ω → 0`` and never divides by ``ω``.

    Examples
    --------
    >>> from rankedassign.tracking.nonlinear import CoordinatedTurn
    >>> ct = CoordinatedTurn()
    >>> ct.f([[0.0, 10.0, 0.0, 0.0, 0.0]]).tolist()
    [[10.0, 10.0, 0.0, 0.0, 0.0]]
    """

    dt: float = 1.0
    sigma_vel: float = 5.0
    sigma_turn: float = math.pi / 180.0

    name = "CoordinatedTurn"
    linear = False
    ndim = 5

    def __post_init__(self):
        dt = check_real(self.dt, "CoordinatedTurn: dt")
        if dt <= 0:
            raise ValueError(f"CoordinatedTurn: dt must be positive, got {dt}")
        sv = check_real(self.sigma_vel, "CoordinatedTurn: sigma_vel", minimum=0.0)
        st = check_real(self.sigma_turn, "CoordinatedTurn: sigma_turn", minimum=0.0)
        object.__setattr__(self, "dt", dt)
        object.__setattr__(self, "sigma_vel", sv)
        object.__setattr__(self, "sigma_turn", st)

    @property
    def noise_gain(self) -> np.ndarray:
        """Vo's ``B2``, shape (5, 3)."""
        T, sv = self.dt, self.sigma_vel
        G = np.zeros((5, 3))
        G[0, 0] = G[2, 1] = sv * T * T / 2
        G[1, 0] = G[3, 1] = sv * T
        G[4, 2] = self.sigma_turn * T
        return _readonly(G)

    @property
    def noise_cov(self) -> np.ndarray:
        """``I₃``."""
        return _readonly(np.eye(3))

    @property
    def Q(self) -> np.ndarray:
        """Process noise covariance ``G Gᵀ``, shape (5, 5)."""
        G = self.noise_gain
        return _readonly(G @ G.T)

    def _coefficients(self, x):
        """``(x, sin ωΔ, cos ωΔ, a, b, da/dω, db/dω)``, each ``(n,)`` but ``x``."""
        x = _states(x, 5, self.name)
        T = self.dt
        w = x[:, 4]
        wT = w * T
        if np.any(np.abs(wT) > MAX_TURN_PER_SCAN):
            bad = int(np.flatnonzero(np.abs(wT) > MAX_TURN_PER_SCAN)[0])
            raise ValueError(f"CoordinatedTurn: the turn rate ω (state component 4) of state "
                             f"{bad} is {float(w[bad])!r} rad/s: |ω Δ| exceeds "
                             f"{MAX_TURN_PER_SCAN:g} rad per scan")
        s, c = np.sin(wT), np.cos(wT)
        vers = 2.0 * np.sin(0.5 * wT) ** 2  # 1 − cos ωΔ without its cancellation
        small = np.abs(wT) < _SERIES_BELOW
        safe = np.where(small, 1.0, w)
        u = wT * wT
        # a = sin(ωΔ)/ω = Δ (1 − u/6 + u²/120 − ...),   b = (1 − cos ωΔ)/ω = Δ ωΔ (1/2 − u/24 + ...)
        a = np.where(small, T * (1 - u / 6 + u * u / 120), s / safe)
        b = np.where(small, T * wT * (0.5 - u / 24 + u * u / 720), vers / safe)
        # da/dω = (ωΔ cos ωΔ − sin ωΔ)/ω² = Δ² ωΔ (−1/3 + u/30 − u²/840 + ...)
        # db/dω = (ωΔ sin ωΔ − 1 + cos ωΔ)/ω² = Δ² (1/2 − u/8 + u²/144 − ...)
        da = np.where(small, T * T * wT * (-1 / 3 + u / 30 - u * u / 840),
                      (wT * c - s) / (safe * safe))
        db = np.where(small, T * T * (0.5 - u / 8 + u * u / 144),
                      (wT * s - vers) / (safe * safe))
        return x, s, c, a, b, da, db

    def f(self, x) -> np.ndarray:
        """The noiseless CT transition of every row of ``x``.

        Parameters
        ----------
        x : array_like, shape (n, 5)
            States ``[p_x, v_x, p_y, v_y, ω]`` (finite, ``|ω Δ| <=`` :data:`MAX_TURN_PER_SCAN`).

        Returns
        -------
        ndarray of float64, shape (n, 5)
            The states one scan on.

        Raises
        ------
        ValueError
            On a non-finite state or a turn rate beyond :data:`MAX_TURN_PER_SCAN`.
        """
        x, s, c, a, b, _, _ = self._coefficients(x)
        out = np.empty_like(x)
        out[:, 0] = x[:, 0] + a * x[:, 1] - b * x[:, 3]
        out[:, 1] = c * x[:, 1] - s * x[:, 3]
        out[:, 2] = b * x[:, 1] + x[:, 2] + a * x[:, 3]
        out[:, 3] = s * x[:, 1] + c * x[:, 3]
        out[:, 4] = x[:, 4]
        return out

    def jacobian(self, x) -> np.ndarray:
        """``∂f/∂x`` at every row of ``x`` (Vo's ``ekf_predict_mat.m``, written out).

        Parameters
        ----------
        x : array_like, shape (n, 5)
            States.

        Returns
        -------
        ndarray of float64, shape (n, 5, 5)
            The Jacobians; the last column is ``∂f/∂ω``.

        Raises
        ------
        ValueError
            As :meth:`f`.
        """
        x, s, c, a, b, da, db = self._coefficients(x)
        T = self.dt
        n = x.shape[0]
        J = np.zeros((n, 5, 5))
        J[:, 0, 0] = J[:, 2, 2] = J[:, 4, 4] = 1.0
        J[:, 0, 1], J[:, 0, 3] = a, -b
        J[:, 1, 1], J[:, 1, 3] = c, -s
        J[:, 2, 1], J[:, 2, 3] = b, a
        J[:, 3, 1], J[:, 3, 3] = s, c
        vx, vy = x[:, 1], x[:, 3]
        # ∂/∂ω of the four rows above (d sin ωΔ/dω = Δ cos ωΔ, d cos ωΔ/dω = −Δ sin ωΔ)
        J[:, 0, 4] = da * vx - db * vy
        J[:, 1, 4] = -T * s * vx - T * c * vy
        J[:, 2, 4] = db * vx + da * vy
        J[:, 3, 4] = T * c * vx - T * s * vy
        return J


# -------------------------------------------------------------------------------- measurement
@dataclass(frozen=True, eq=False)
class LinearGaussianMeasurement:
    """Linear-Gaussian measurement ``z = H x + w``, ``w ~ N(0, R)``.

    Parameters
    ----------
    H : array_like, shape (d_z, d)
        Measurement matrix (finite).
    R : array_like, shape (d_z, d_z)
        Noise covariance, symmetric positive definite.
    p_d : float, optional
        Detection probability in ``(0, 1]`` (default 0.98).
    position_indices : tuple of int, optional
        State components that are the position (default ``(0, 2)``).
    name : str, optional
        The model's name in messages (default ``"LinearGaussianMeasurement"``).

    Attributes
    ----------
    H, R : ndarray of float64
        Read-only matrices.
    p_d : float
        Detection probability.
    position_indices : tuple of int
        Position components of the state (for state extraction and OSPA).
    name : str
        The model's name in messages.
    linear : bool
        True.
    angles : ndarray of bool, shape (d_z,)
        No coordinate is an angle.
    ndim, state_ndim : int
        ``d_z`` and ``d``.

    Raises
    ------
    ValueError
        If ``H`` is not a finite 2-D matrix, ``R`` not symmetric positive definite of size
        ``d_z``, ``p_d`` outside ``(0, 1]`` or a position index out of range.

    Examples
    --------
    >>> from rankedassign.tracking.models import PositionSensor
    >>> from rankedassign.tracking.nonlinear import LinearGaussianMeasurement
    >>> pos = LinearGaussianMeasurement.from_sensor(PositionSensor())
    >>> pos.H.tolist(), pos.R.diagonal().tolist()
    ([[1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0]], [100.0, 100.0])
    """

    H: np.ndarray
    R: np.ndarray
    p_d: float = 0.98
    position_indices: tuple = (0, 2)
    name: str = "LinearGaussianMeasurement"

    linear = True

    def __post_init__(self):
        H = _real_array(self.H, f"{self.name}: H")
        if H.ndim != 2 or not np.isfinite(H).all():
            raise ValueError(f"{self.name}: H must be a finite 2-D matrix, got shape {H.shape}")
        R = _psd(self.R, H.shape[0], f"{self.name}: the noise covariance R", strict=True)
        object.__setattr__(self, "H", _readonly(H))
        object.__setattr__(self, "R", R)
        _check_sensor(self, H.shape[1])

    @classmethod
    def from_sensor(cls, sensor) -> LinearGaussianMeasurement:
        """Today's :class:`~rankedassign.tracking.models.PositionSensor` in this interface.

        Parameters
        ----------
        sensor : PositionSensor
            The position sensor (``H``, ``R``, ``P_D``).

        Returns
        -------
        LinearGaussianMeasurement
            The same ``H``, ``R`` and ``p_d``, named ``"PositionSensor"``.

        Raises
        ------
        TypeError
            If ``sensor`` is not a :class:`PositionSensor`.
        """
        if not isinstance(sensor, PositionSensor):
            raise TypeError(f"sensor must be a PositionSensor, got {type(sensor).__name__}")
        return cls(sensor.H, sensor.R, sensor.p_d, (0, 2), name="PositionSensor")

    @property
    def angles(self) -> np.ndarray:
        """No measurement coordinate is an angle, shape (d_z,)."""
        return np.zeros(self.H.shape[0], dtype=bool)

    @property
    def ndim(self) -> int:
        """Measurement dimension ``d_z``."""
        return int(self.H.shape[0])

    @property
    def state_ndim(self) -> int:
        """State dimension ``d``."""
        return int(self.H.shape[1])

    def h(self, x) -> np.ndarray:
        """``H x`` for every row of ``x``.

        Parameters
        ----------
        x : array_like, shape (n, d)
            States.

        Returns
        -------
        ndarray of float64, shape (n, d_z)
            ``x Hᵀ``.
        """
        return _states(x, self.state_ndim, self.name) @ self.H.T

    def jacobian(self, x) -> np.ndarray:
        """``H`` for every row of ``x``.

        Parameters
        ----------
        x : array_like, shape (n, d)
            States.

        Returns
        -------
        ndarray of float64, shape (n, d_z, d)
            ``H`` repeated.
        """
        x = _states(x, self.state_ndim, self.name)
        return np.broadcast_to(self.H, (x.shape[0],) + self.H.shape).copy()


def _check_sensor(model, d: int) -> None:
    p_d = check_real(model.p_d, f"{model.name}: p_d")
    if not 0 < p_d <= 1:
        raise ValueError(f"{model.name}: p_d must be in (0, 1], got {p_d}")
    object.__setattr__(model, "p_d", p_d)
    idx = tuple(int(i) for i in model.position_indices)
    if len(idx) != 2 or not all(0 <= i < d for i in idx) or idx[0] == idx[1]:
        raise ValueError(f"{model.name}: position_indices must be two distinct state "
                         f"components in [0, {d}), got {model.position_indices!r}")
    object.__setattr__(model, "position_indices", idx)


@dataclass(frozen=True)
class BearingRange:
    """Bearing and range from a sensor at ``(s_x, s_y)``: ``z = [θ, ρ]``.

    Vo's convention (``gen_observation_fn.m``): the bearing is measured from the y-axis,
    ``θ = atan2(p_x − s_x, p_y − s_y)``, in ``(−π, π]``; the range ``ρ`` is the distance.

    Parameters
    ----------
    sigma_bearing : float
        Bearing noise standard deviation in rad (default ``2π/180``, Vo's).
    sigma_range : float
        Range noise standard deviation in m (default 10, Vo's).
    sensor_position : tuple of float, optional
        ``(s_x, s_y)`` in m (default the origin).
    p_d : float, optional
        Detection probability in ``(0, 1]`` (default 0.98).
    state_ndim : int, optional
        State dimension ``d`` (default 5, ``[p_x, v_x, p_y, v_y, ω]``).
    position_indices : tuple of int, optional
        State components of ``p_x`` and ``p_y`` (default ``(0, 2)``).

    Attributes
    ----------
    sigma_bearing, sigma_range, p_d : float
        As given.
    sensor_position : tuple of float
        ``(s_x, s_y)``.
    state_ndim : int
        ``d``.
    position_indices : tuple of int
        ``(i_x, i_y)``.
    name : str
        ``"BearingRange"``.
    linear : bool
        False.
    ndim : int
        2.
    angles : ndarray of bool
        ``[True, False]``: the bearing is an angle.
    R : ndarray, shape (2, 2)
        ``diag(σ_θ², σ_ρ²)``.

    Raises
    ------
    TypeError
        If a parameter is not a real number.
    ValueError
        If a standard deviation is not positive and finite (``R`` must be positive definite),
        ``p_d`` is outside ``(0, 1]``, or the indices are out of range.

    Notes
    -----
    With ``Δx = p_x − s_x``, ``Δy = p_y − s_y``, ``ρ² = Δx² + Δy²``::

        ∂θ/∂p_x = Δy/ρ²   ∂θ/∂p_y = −Δx/ρ²   ∂ρ/∂p_x = Δx/ρ   ∂ρ/∂p_y = Δy/ρ

    A state at the sensor (``ρ = 0``) has no bearing: :meth:`h` and :meth:`jacobian` refuse
    it.

    Examples
    --------
    >>> from rankedassign.tracking.nonlinear import BearingRange
    >>> br = BearingRange()
    >>> br.h([[300.0, 0.0, 400.0, 0.0, 0.0]]).round(6).tolist()
    [[0.643501, 500.0]]
    """

    sigma_bearing: float = 2.0 * math.pi / 180.0
    sigma_range: float = 10.0
    sensor_position: tuple = (0.0, 0.0)
    p_d: float = 0.98
    state_ndim: int = 5
    position_indices: tuple = (0, 2)

    name = "BearingRange"
    linear = False
    ndim = 2

    def __post_init__(self):
        for k in ("sigma_bearing", "sigma_range"):
            v = check_real(getattr(self, k), f"BearingRange: {k}")
            if not v > 0 or not v * v > 0:
                raise ValueError(f"BearingRange: the noise covariance R must be positive "
                                 f"definite: {k} must be > 0 (and its square too), got {v}")
            object.__setattr__(self, k, v)
        s = tuple(check_real(v, "BearingRange: sensor_position") for v in self.sensor_position)
        if len(s) != 2:
            raise ValueError(f"BearingRange: sensor_position must be (s_x, s_y), got "
                             f"{self.sensor_position!r}")
        object.__setattr__(self, "sensor_position", s)
        object.__setattr__(self, "state_ndim", int(self.state_ndim))
        _check_sensor(self, self.state_ndim)

    @property
    def angles(self) -> np.ndarray:
        """``[True, False]``: the bearing is an angle."""
        return np.array([True, False])

    @property
    def R(self) -> np.ndarray:
        """``diag(σ_θ², σ_ρ²)``, shape (2, 2)."""
        return _readonly(np.diag([self.sigma_bearing**2, self.sigma_range**2]))

    def _offsets(self, x):
        x = _states(x, self.state_ndim, self.name)
        ix, iy = self.position_indices
        dx = x[:, ix] - self.sensor_position[0]
        dy = x[:, iy] - self.sensor_position[1]
        r2 = dx * dx + dy * dy
        if np.any(~(r2 > 0)):
            bad = int(np.flatnonzero(~(r2 > 0))[0])
            raise ValueError(f"BearingRange: state {bad} is at the sensor position "
                             f"{self.sensor_position} (range 0): its bearing and the bearing's "
                             "Jacobian are undefined")
        return x, dx, dy, r2

    def h(self, x) -> np.ndarray:
        """``[θ, ρ]`` of every row of ``x``.

        Parameters
        ----------
        x : array_like, shape (n, d)
            States.

        Returns
        -------
        ndarray of float64, shape (n, 2)
            Bearing in ``(−π, π]`` and range.

        Raises
        ------
        ValueError
            On a non-finite state or one at the sensor position.
        """
        _, dx, dy, r2 = self._offsets(x)
        return np.column_stack([np.arctan2(dx, dy), np.sqrt(r2)])

    def jacobian(self, x) -> np.ndarray:
        """``∂h/∂x`` at every row of ``x`` (Vo's ``ekf_update_mat.m``, written out).

        Parameters
        ----------
        x : array_like, shape (n, d)
            States.

        Returns
        -------
        ndarray of float64, shape (n, 2, d)
            Non-zero only in the position columns.

        Raises
        ------
        ValueError
            On a non-finite state or one at the sensor position (a range whose square
            underflows to 0 included).
        """
        x, dx, dy, r2 = self._offsets(x)
        r = np.sqrt(r2)
        ix, iy = self.position_indices
        J = np.zeros((x.shape[0], 2, self.state_ndim))
        # r² > 0 (checked): 1/r² <= 1/5e-324 stays finite, so the entries are finite
        J[:, 0, ix], J[:, 0, iy] = dy / r2, -dx / r2
        J[:, 1, ix], J[:, 1, iy] = dx / r, dy / r
        return J

    def inverse(self, z) -> tuple[np.ndarray, np.ndarray]:
        """The position of every measurement and the Jacobian of that map (for births).

        Parameters
        ----------
        z : array_like, shape (M, 2)
            Measurements ``[θ, ρ]``.

        Returns
        -------
        p : ndarray of float64, shape (M, 2)
            ``(s_x + ρ sin θ, s_y + ρ cos θ)``, in ``position_indices`` order.
        J : ndarray of float64, shape (M, 2, 2)
            ``∂p/∂[θ, ρ] = [[ρ cos θ, sin θ], [−ρ sin θ, cos θ]]``.
        """
        z = np.asarray(z, dtype=np.float64).reshape(-1, 2)
        s, c = np.sin(z[:, 0]), np.cos(z[:, 0])
        rho = z[:, 1]
        p = np.column_stack([self.sensor_position[0] + rho * s,
                             self.sensor_position[1] + rho * c])
        J = np.empty((z.shape[0], 2, 2))
        J[:, 0, 0], J[:, 0, 1], J[:, 1, 0], J[:, 1, 1] = rho * c, s, -rho * s, c
        return p, J


# ----------------------------------------------------------------------------- clutter, birth
@dataclass(frozen=True)
class BearingRangeClutter:
    """Poisson clutter uniform in (bearing, range) space.

    Parameters
    ----------
    rate : float
        Mean number ``λ_c`` of clutter points per scan (default 15, Vo's).
    bearing : tuple of float
        ``(θ_min, θ_max)`` in rad, inside ``[−π, π]`` (default ``(−π/2, π/2)``, Vo's).
    range : tuple of float
        ``(ρ_min, ρ_max)`` in m, ``ρ_min >= 0`` (default ``(0, 2000)``, Vo's).

    Attributes
    ----------
    rate : float
        ``λ_c``.
    bearing, range : tuple of float
        The region.
    volume : float
        ``(θ_max − θ_min)(ρ_max − ρ_min)`` in rad·m.
    intensity : float
        ``κ = λ_c / volume``, constant over the region (Vo's ``lambda_c * pdf_c``).

    Raises
    ------
    TypeError
        If a bound or the rate is not a real number.
    ValueError
        If the rate is not positive and finite or an interval is empty, not finite, a bearing
        outside ``[−π, π]`` or a range negative.

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign.tracking.nonlinear import BearingRangeClutter
    >>> cl = BearingRangeClutter()
    >>> round(cl.intensity * 2000 * np.pi, 12)
    15.0
    """

    rate: float = 15.0
    bearing: tuple = (-math.pi / 2, math.pi / 2)
    range: tuple = (0.0, 2000.0)

    def __post_init__(self):
        rate = check_real(self.rate, "BearingRangeClutter: rate")
        if rate <= 0:
            raise ValueError(f"BearingRangeClutter: rate must be positive, got {rate}")
        object.__setattr__(self, "rate", rate)
        for k, lo_bound, hi_bound in (("bearing", -math.pi, math.pi), ("range", 0.0, math.inf)):
            iv = tuple(check_real(v, f"BearingRangeClutter: {k}") for v in getattr(self, k))
            if len(iv) != 2 or not (lo_bound <= iv[0] < iv[1] <= hi_bound):
                raise ValueError(f"BearingRangeClutter: {k} must be (min, max) with "
                                 f"{lo_bound:g} <= min < max <= {hi_bound:g}, got "
                                 f"{getattr(self, k)!r}")
            object.__setattr__(self, k, iv)

    @property
    def volume(self) -> float:
        """Volume of the region in rad·m."""
        return (self.bearing[1] - self.bearing[0]) * (self.range[1] - self.range[0])

    @property
    def intensity(self) -> float:
        """``κ = λ_c / volume``."""
        return self.rate / self.volume

    def sample(self, rng: np.random.Generator) -> np.ndarray:
        """One scan of clutter: ``Poisson(λ_c)`` points uniform on the region.

        Parameters
        ----------
        rng : numpy.random.Generator
            One ``poisson`` draw for the count ``n``, then ``random((n, 2))``.

        Returns
        -------
        ndarray of float64, shape (n, 2)
            ``[θ, ρ]`` rows.
        """
        n = rng.poisson(self.rate)
        u = rng.random((n, 2))
        (b0, b1), (r0, r1) = self.bearing, self.range
        return np.column_stack([b0 + (b1 - b0) * u[:, 0], r0 + (r1 - r0) * u[:, 1]])


@dataclass(frozen=True, eq=False)
class GaussianBirth:
    """One LMB birth term: existence ``r`` and a Gaussian mixture in the model's state space.

    Parameters
    ----------
    r : float
        Existence probability in ``(0, 1)``.
    means : array_like, shape (L, d) or (d,)
        Means of the ``L`` Gaussians.
    covs : array_like, shape (L, d, d) or (d, d)
        Covariances, symmetric positive definite.
    weights : array_like, shape (L,), optional
        Mixture weights, positive, summing to 1 (default uniform).

    Attributes
    ----------
    r : float
        Existence probability.
    means : ndarray, shape (L, d)
        Read-only means.
    covs : ndarray, shape (L, d, d)
        Read-only covariances.
    weights : ndarray, shape (L,)
        Read-only weights.

    Raises
    ------
    ValueError
        On ``r`` outside ``(0, 1)``, mismatched shapes, non-finite means, a covariance that is
        not positive definite, or weights that are not positive or do not sum to 1.

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign.tracking.nonlinear import GaussianBirth
    >>> b = GaussianBirth(0.02, [-1500.0, 0, 250, 0, 0], np.diag([50.0, 50, 50, 50, 0.1]) ** 2)
    >>> b.means.shape, b.covs.shape, b.weights.tolist()
    ((1, 5), (1, 5, 5), [1.0])
    """

    r: float
    means: np.ndarray
    covs: np.ndarray
    weights: np.ndarray | None = None

    def __post_init__(self):
        r = check_real(self.r, "GaussianBirth: r")
        if not 0 < r < 1:
            raise ValueError(f"GaussianBirth: r must be in (0, 1), got {r}")
        object.__setattr__(self, "r", r)
        m = _real_array(self.means, "GaussianBirth: means")
        m = m[None, :] if m.ndim == 1 else m
        if m.ndim != 2 or not np.isfinite(m).all():
            raise ValueError(f"GaussianBirth: means must be finite, shape (L, d), got shape "
                             f"{m.shape}")
        L, d = m.shape
        P = _real_array(self.covs, "GaussianBirth: covs")
        P = P[None] if P.ndim == 2 else P
        if P.shape != (L, d, d):
            raise ValueError(f"GaussianBirth: covs must have shape ({L}, {d}, {d}), got "
                             f"{P.shape}")
        P = np.stack([_psd(p, d, f"GaussianBirth: covariance {i}", strict=True)
                      for i, p in enumerate(P)])
        w = np.full(L, 1.0 / L) if self.weights is None else _real_array(
            self.weights, "GaussianBirth: weights").reshape(-1)
        if w.shape != (L,) or not (w > 0).all() or not abs(w.sum() - 1) < 1e-12:
            raise ValueError(f"GaussianBirth: weights must be {L} positive numbers summing to "
                             f"1, got {w.tolist()}")
        for k, v in (("means", m), ("covs", P), ("weights", w)):
            object.__setattr__(self, k, _readonly(v))

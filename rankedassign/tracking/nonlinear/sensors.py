"""Angle sensors in Stone Soup's convention: bearing only (2-D), elevation–bearing–range (3-D).

Both measure the position ``p`` (the state components ``position_indices``) in the sensor's
frame, ``u = A (p − s)``: ``s`` the sensor's position, ``A`` the rotation into its frame
(Stone Soup's ``rotation_matrix``; for a 2-D sensor its upper-left 2 x 2 block, since a planar
position has no third coordinate to rotate). The bearing is measured from the frame's first
axis, counter-clockwise, ``φ = atan2(u_2, u_1)``, as Stone Soup's ``Cartesian2DToBearing`` and
``CartesianToElevationBearingRange`` do (the 2-D
:class:`~rankedassign.tracking.nonlinear.BearingRange` keeps Vo's convention, the bearing from
the y-axis).

They have the interface of the "Non-linear models" page (``h``, ``jacobian``, ``R``,
``angles``, ``p_d``, ``position_indices``, ``state_ndim``, ``ndim``, ``name``), so the EKF and
the UKF of :mod:`rankedassign.tracking.nonlinear.filters` run on them, and the 3-D sensor the
inverse ``inverse`` the measurement-driven birth places its births with.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...validation import check_real
from ..models import _readonly, _real_array
from .models import _psd, _states

__all__ = ["Bearing", "ElevationBearingRange"]


def _frame(model, k: int) -> None:
    """Check and store ``sensor_position`` (k,), ``rotation`` (k, k), ``position_indices``."""
    name = model.name
    s = _real_array(model.sensor_position, f"{name}: sensor_position").reshape(-1)
    if s.shape != (k,) or not np.isfinite(s).all():
        raise ValueError(f"{name}: sensor_position must be {k} finite numbers, got "
                         f"{np.asarray(model.sensor_position).tolist()!r}")
    A = np.eye(k) if model.rotation is None else _real_array(model.rotation,
                                                           f"{name}: rotation")
    if A.shape != (k, k) or not np.isfinite(A).all() or not np.allclose(
            A @ A.T, np.eye(k), rtol=0.0, atol=1e-12):
        raise ValueError(f"{name}: rotation must be an orthogonal {k}x{k} matrix, got "
                         f"{A.tolist()}")
    p_d = check_real(model.p_d, f"{name}: p_d")
    if not 0 < p_d <= 1:
        raise ValueError(f"{name}: p_d must be in (0, 1], got {p_d}")
    d = int(model.state_ndim)
    idx = tuple(int(i) for i in model.position_indices)
    if len(idx) != k or not all(0 <= i < d for i in idx) or len(set(idx)) != k:
        raise ValueError(f"{name}: position_indices must be {k} distinct state components "
                         f"in [0, {d}), got {model.position_indices!r}")
    for key, value in (("sensor_position", tuple(s.tolist())), ("rotation", _readonly(A)),
                       ("p_d", p_d), ("state_ndim", d), ("position_indices", idx)):
        object.__setattr__(model, key, value)


def _local(model, x):
    """``(x, u)``: the states checked and ``u = A (p − s)`` of every row, shape (n, k)."""
    x = _states(x, model.state_ndim, model.name)
    p = x[:, list(model.position_indices)] - np.asarray(model.sensor_position)
    return x, p @ model.rotation.T


@dataclass(frozen=True, eq=False)
class Bearing:
    """Bearing only, 2-D: ``z = [φ]``, ``φ = atan2(u_2, u_1)``, ``u = A (p − s)``.

    Stone Soup's ``Cartesian2DToBearing``.

    Parameters
    ----------
    R : array_like, shape (1, 1) or (1,)
        Bearing noise variance in rad², positive.
    sensor_position : sequence of float, optional
        ``s = (s_x, s_y)`` (default the origin).
    rotation : array_like, shape (2, 2), optional
        ``A``, orthogonal (default the identity).
    p_d : float, optional
        Detection probability in ``(0, 1]`` (default 0.98).
    state_ndim : int, optional
        State dimension ``d`` (default 4).
    position_indices : tuple of int, optional
        State components of ``p_x`` and ``p_y`` (default ``(0, 2)``).

    Attributes
    ----------
    R : ndarray, shape (1, 1)
        Read-only.
    sensor_position, position_indices, p_d, state_ndim
        As given, checked.
    rotation : ndarray, shape (2, 2)
        ``A``.
    name : str
        ``"Bearing"``.
    linear : bool
        False.
    ndim : int
        1.
    angles : ndarray of bool
        ``[True]``.

    Raises
    ------
    TypeError
        If a parameter is not real.
    ValueError
        If ``R`` is not a positive 1 x 1 matrix, ``A`` not orthogonal, ``p_d`` outside
        ``(0, 1]`` or the indices out of range.

    Notes
    -----
    A bearing alone does not place a target: this sensor has no ``inverse``, and a
    measurement-driven birth refuses it (give static births).

    Examples
    --------
    >>> from rankedassign.tracking.nonlinear.sensors import Bearing
    >>> Bearing([[1e-4]]).h([[0.0, 0.0, 1.0, 0.0]]).round(6).tolist()
    [[1.570796]]
    """

    R: np.ndarray
    sensor_position: tuple = (0.0, 0.0)
    rotation: np.ndarray | None = None
    p_d: float = 0.98
    state_ndim: int = 4
    position_indices: tuple = (0, 2)

    name = "Bearing"
    linear = False
    ndim = 1

    def __post_init__(self):
        object.__setattr__(self, "R", _psd(self.R, 1, "Bearing: the noise covariance R",
                                           strict=True))
        _frame(self, 2)

    @property
    def angles(self) -> np.ndarray:
        """``[True]``."""
        return np.array([True])

    def h(self, x) -> np.ndarray:
        """``[φ]`` of every row of ``x``.

        Parameters
        ----------
        x : array_like, shape (n, d)
            States.

        Returns
        -------
        ndarray of float64, shape (n, 1)
            Bearings in ``(−π, π]``.
        """
        _, u = _local(self, x)
        return np.arctan2(u[:, 1], u[:, 0])[:, None]

    def jacobian(self, x) -> np.ndarray:
        """``∂φ/∂x`` at every row of ``x``: ``[−u_2, u_1] A / |u|²`` in the position columns.

        Parameters
        ----------
        x : array_like, shape (n, d)
            States.

        Returns
        -------
        ndarray of float64, shape (n, 1, d)

        Raises
        ------
        ValueError
            On a state at the sensor position (no bearing).
        """
        x, u = _local(self, x)
        r2 = (u * u).sum(axis=1)
        if np.any(~(r2 > 0)):
            raise ValueError(f"Bearing: state {int(np.flatnonzero(~(r2 > 0))[0])} is at the "
                             "sensor position: its bearing's Jacobian is undefined")
        J = np.zeros((x.shape[0], 1, self.state_ndim))
        # ∂φ/∂u = [−u_2, u_1] / |u|² ; ∂u/∂p = A
        J[:, 0, list(self.position_indices)] = (np.column_stack([-u[:, 1], u[:, 0]])
                                                / r2[:, None]) @ self.rotation
        return J


@dataclass(frozen=True, eq=False)
class ElevationBearingRange:
    """Elevation, bearing and range, 3-D: ``z = [θ, φ, ρ]`` of ``u = A (p − s)``.

    ``ρ = |u|``, ``φ = atan2(u_2, u_1)``, ``θ = asin(u_3 / ρ)``: Stone Soup's
    ``CartesianToElevationBearingRange``.

    Parameters
    ----------
    R : array_like, shape (3, 3) or (3,)
        Noise covariance of ``[θ, φ, ρ]`` (a diagonal given as a vector), positive definite.
    sensor_position : sequence of float, optional
        ``s = (s_x, s_y, s_z)`` (default the origin).
    rotation : array_like, shape (3, 3), optional
        ``A``, orthogonal (default the identity).
    p_d : float, optional
        Detection probability in ``(0, 1]`` (default 0.98).
    state_ndim : int, optional
        State dimension ``d`` (default 6).
    position_indices : tuple of int, optional
        State components of ``p_x``, ``p_y``, ``p_z`` (default ``(0, 2, 4)``).

    Attributes
    ----------
    R : ndarray, shape (3, 3)
        Read-only.
    sensor_position, position_indices, p_d, state_ndim
        As given, checked.
    rotation : ndarray, shape (3, 3)
        ``A``.
    name : str
        ``"ElevationBearingRange"``.
    linear : bool
        False.
    ndim : int
        3.
    angles : ndarray of bool
        ``[True, True, False]`` (an elevation difference is wrapped too; it never nears ±π).

    Raises
    ------
    TypeError
        If a parameter is not real.
    ValueError
        If ``R`` is not symmetric positive definite, ``A`` not orthogonal, ``p_d`` outside
        ``(0, 1]`` or the indices out of range.

    Notes
    -----
    With ``r = |(u_1, u_2)|``::

        ∂ρ/∂u = u / ρ      ∂φ/∂u = [−u_2, u_1, 0] / r²
        ∂θ/∂u = [−u_3 u_1 / (r ρ²), −u_3 u_2 / (r ρ²), r / ρ²]

    and ``∂u/∂p = A``. The inverse is ``p = s + Aᵀ ρ [cos θ cos φ, cos θ sin φ, sin θ]``.

    Examples
    --------
    >>> from rankedassign.tracking.nonlinear.sensors import ElevationBearingRange
    >>> s = ElevationBearingRange([1e-4, 1e-4, 1.0])
    >>> s.h([[3.0, 0, 0.0, 0, 4.0, 0]]).round(6).tolist()
    [[0.927295, 0.0, 5.0]]
    >>> s.inverse([[0.927295, 0.0, 5.0]])[0].round(4).tolist()
    [[3.0, 0.0, 4.0]]
    """

    R: np.ndarray
    sensor_position: tuple = (0.0, 0.0, 0.0)
    rotation: np.ndarray | None = None
    p_d: float = 0.98
    state_ndim: int = 6
    position_indices: tuple = (0, 2, 4)

    name = "ElevationBearingRange"
    linear = False
    ndim = 3

    def __post_init__(self):
        object.__setattr__(self, "R", _psd(
            self.R, 3, "ElevationBearingRange: the noise covariance R", strict=True))
        _frame(self, 3)

    @property
    def angles(self) -> np.ndarray:
        """``[True, True, False]``."""
        return np.array([True, True, False])

    def _checked(self, x):
        x, u = _local(self, x)
        rxy2 = u[:, 0] ** 2 + u[:, 1] ** 2
        if np.any(~(rxy2 > 0)):
            bad = int(np.flatnonzero(~(rxy2 > 0))[0])
            raise ValueError(f"ElevationBearingRange: state {bad} is straight above or below "
                             "the sensor (or at it): its bearing and the Jacobian are undefined")
        return x, u, rxy2

    def h(self, x) -> np.ndarray:
        """``[θ, φ, ρ]`` of every row of ``x``.

        Parameters
        ----------
        x : array_like, shape (n, d)
            States.

        Returns
        -------
        ndarray of float64, shape (n, 3)
            Elevation in ``[−π/2, π/2]``, bearing in ``(−π, π]``, range.
        """
        _, u = _local(self, x)
        rho = np.sqrt((u * u).sum(axis=1))
        with np.errstate(invalid="ignore", divide="ignore"):
            theta = np.where(rho > 0, np.arcsin(u[:, 2] / np.where(rho > 0, rho, 1.0)), 0.0)
        return np.column_stack([theta, np.arctan2(u[:, 1], u[:, 0]), rho])

    def jacobian(self, x) -> np.ndarray:
        """``∂[θ, φ, ρ]/∂x`` at every row of ``x`` (the Notes' expressions).

        Parameters
        ----------
        x : array_like, shape (n, d)
            States.

        Returns
        -------
        ndarray of float64, shape (n, 3, d)
            Non-zero only in the position columns.

        Raises
        ------
        ValueError
            On a state straight above or below the sensor (no bearing).
        """
        x, u, rxy2 = self._checked(x)
        rho2 = rxy2 + u[:, 2] ** 2
        rho, rxy = np.sqrt(rho2), np.sqrt(rxy2)
        Ju = np.empty((x.shape[0], 3, 3))
        Ju[:, 0, 0] = -u[:, 2] * u[:, 0] / (rxy * rho2)
        Ju[:, 0, 1] = -u[:, 2] * u[:, 1] / (rxy * rho2)
        Ju[:, 0, 2] = rxy / rho2
        Ju[:, 1, 0], Ju[:, 1, 1], Ju[:, 1, 2] = -u[:, 1] / rxy2, u[:, 0] / rxy2, 0.0
        Ju[:, 2, :] = u / rho[:, None]
        J = np.zeros((x.shape[0], 3, self.state_ndim))
        J[:, :, list(self.position_indices)] = Ju @ self.rotation
        return J

    def inverse(self, z) -> tuple[np.ndarray, np.ndarray]:
        """The position of every measurement and the Jacobian of that map.

        Parameters
        ----------
        z : array_like, shape (M, 3)
            Measurements ``[θ, φ, ρ]``.

        Returns
        -------
        p : ndarray of float64, shape (M, 3)
            ``s + Aᵀ ρ [cos θ cos φ, cos θ sin φ, sin θ]``, in ``position_indices`` order.
        J : ndarray of float64, shape (M, 3, 3)
            ``∂p/∂z``.
        """
        z = np.asarray(z, dtype=np.float64).reshape(-1, 3)
        th, ph, rho = z[:, 0], z[:, 1], z[:, 2]
        ct, st, cp, sp = np.cos(th), np.sin(th), np.cos(ph), np.sin(ph)
        u = rho[:, None] * np.column_stack([ct * cp, ct * sp, st])
        Ju = np.empty((z.shape[0], 3, 3))
        # ∂u/∂θ, ∂u/∂φ, ∂u/∂ρ as columns
        Ju[:, :, 0] = rho[:, None] * np.column_stack([-st * cp, -st * sp, ct])
        Ju[:, :, 1] = rho[:, None] * np.column_stack([-ct * sp, ct * cp, np.zeros_like(ct)])
        Ju[:, :, 2] = np.column_stack([ct * cp, ct * sp, st])
        At = self.rotation.T
        return np.asarray(self.sensor_position) + u @ At.T, At @ Ju

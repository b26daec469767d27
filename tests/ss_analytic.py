"""Stone Soup's angle measurement models and ConstantTurn with analytic Jacobians, for the 1e-10 comparisons.

Stone Soup's own ``jacobian`` of these models takes finite differences, which agree with the
analytic one to about 1e-7 only; with these subclasses Stone Soup's ``ExtendedKalmanUpdater``
computes the EKF our filters compute, so the two can be compared to 1e-10. The Jacobians are
written here independently of ``rankedassign.tracking.nonlinear`` (one state at a time, from
Stone Soup's own formulas).
"""

import numpy as np
from stonesoup.models.measurement.nonlinear import (
    Cartesian2DToBearing,
    CartesianToBearingRange,
    CartesianToElevationBearingRange,
)
from stonesoup.models.transition.nonlinear import ConstantTurn


def _local(model, state, k):
    x = np.asarray(state.state_vector, dtype=float).ravel()
    t = np.asarray(model.translation_offset, dtype=float).ravel()[:k]
    idx = list(model.mapping[:k])
    A = np.asarray(model.rotation_matrix, dtype=float)[:k, :k]
    return x, idx, A, A @ (x[idx] - t)


class AnalyticBearingRange(CartesianToBearingRange):
    """``CartesianToBearingRange`` (no rotation) with its analytic Jacobian."""

    def jacobian(self, state, **kwargs):
        x, idx, A, u = _local(self, state, 2)
        r2 = u @ u
        J = np.zeros((2, self.ndim_state))
        # φ = atan2(u_y, u_x): ∂φ/∂u = [−u_y, u_x]/r² ; ρ = |u|: ∂ρ/∂u = u/ρ
        J[0, idx] = np.array([-u[1], u[0]]) / r2 @ A
        J[1, idx] = u / np.sqrt(r2) @ A
        return J


class AnalyticBearing(Cartesian2DToBearing):
    """``Cartesian2DToBearing`` with its analytic Jacobian."""

    def jacobian(self, state, **kwargs):
        x, idx, A, u = _local(self, state, 2)
        J = np.zeros((1, self.ndim_state))
        J[0, idx] = np.array([-u[1], u[0]]) / (u @ u) @ A
        return J


class AnalyticElevationBearingRange(CartesianToElevationBearingRange):
    """``CartesianToElevationBearingRange`` with its analytic Jacobian."""

    def jacobian(self, state, **kwargs):
        x, idx, A, u = _local(self, state, 3)
        rho = np.sqrt(u @ u)
        rxy = np.hypot(u[0], u[1])
        # θ = asin(u_z / ρ), φ = atan2(u_y, u_x), ρ = |u|
        d_theta = np.array([-u[2] * u[0], -u[2] * u[1], rxy ** 2]) / (rxy * rho ** 2)
        d_phi = np.array([-u[1], u[0], 0.0]) / rxy ** 2
        d_rho = u / rho
        J = np.zeros((3, self.ndim_state))
        J[:, idx] = np.vstack([d_theta, d_phi, d_rho]) @ A
        return J


class AnalyticConstantTurn(ConstantTurn):
    """``ConstantTurn`` with its analytic Jacobian (turn rate away from 0)."""

    def jacobian(self, state, **kwargs):
        x = np.asarray(state.state_vector, dtype=float).ravel()
        T = kwargs["time_interval"].total_seconds()
        vx, vy, w = x[1], x[3], x[4]
        s, c = np.sin(w * T), np.cos(w * T)
        # f0 = x + (s/ω) vx − ((1−c)/ω) vy,  f1 = c vx − s vy,
        # f2 = ((1−c)/ω) vx + y + (s/ω) vy,  f3 = s vx + c vy,  f4 = ω
        ds = (T * c * w - s) / w ** 2          # d(s/ω)/dω
        dv = (T * s * w - (1 - c)) / w ** 2    # d((1−c)/ω)/dω
        return np.array([
            [1.0, s / w, 0.0, -(1 - c) / w, ds * vx - dv * vy],
            [0.0, c, 0.0, -s, -T * s * vx - T * c * vy],
            [0.0, (1 - c) / w, 1.0, s / w, dv * vx + ds * vy],
            [0.0, s, 0.0, c, T * c * vx - T * s * vy],
            [0.0, 0.0, 0.0, 0.0, 1.0],
        ])

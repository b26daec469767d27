"""The multi-sensor adaptive-birth problem (Trezza, Bucci & Varshney 2022; spec §4).

Specification of record: ``multisensor.md`` §4 (target, conditional, birth LMB).

Newborn tracks are proposed from *measurement tuples* ``J = (j^(1), ..., j^(V))``, one entry
per sensor: ``j^(v) = 0`` means sensor ``v`` missed the newborn target, ``j^(v) = m >= 1``
means it generated the ``m``-th kept measurement of sensor ``v``. The state space is the whole
product ``{0..M_1} x ... x {0..M_V}`` (no one-to-one constraint: different births may share
measurements), and the Gibbs target is (spec eq. 4.2)::

    rho(J)  = prod_v r_U^(v)(j^(v)) * psibar_B(J),          r_U^(v)(0) := 1
    psibar_B(J) = int N(x; mu_0, P_0) prod_v psi^(v, j^(v))(x) dx
    psi^(v,0)(x) = 1 - P_D^(v),   psi^(v,m)(x) = P_D^(v) N(z^(v)_m; H_v x, R_v) / kappa^(v)(z^(v)_m)
    pi_B(J) = rho(J) / sum_J' rho(J')

``psibar_B`` has the closed (information) form of spec eq. 1.6 with ``(m, P) = (mu_0, P_0)``;
the sampler's per-sensor update uses its ratio form (spec §4.2), so no tuple tensor is ever
built. :meth:`AdaptiveBirthProblem.from_log_weights` builds a problem from an explicit tensor
of ``ln rho`` instead (tests, oracle).

A sampler run over an :class:`AdaptiveBirthProblem` (:func:`rankedassign.sample_original`,
:func:`rankedassign.sample_short_chains`) returns the unique tuples it visited;
:func:`birth_from_samples` turns them into the LMB birth components of spec §4.4.

References
----------
.. [1] A. Trezza, D. J. Bucci Jr., P. K. Varshney, "Multi-sensor joint adaptive birth sampler
   for labeled random finite set tracking", IEEE Trans. Signal Process. 70, 2022
   (arXiv:2109.04355).
.. [2] S. Reuter, D. Meissner, B. Wilking, K. Dietmayer, "Adaptive birth of the labeled
   multi-Bernoulli filter", FUSION 2014.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from ..validation import check_int, check_real, check_type, float_array

__all__ = ["AdaptiveBirthProblem", "BirthLMB", "birth_from_samples", "SENSOR_ORDERS"]


#: Sensor order of a sweep (spec §4.3, open question Q8): a fresh uniformly random permutation
#: per sweep (default, as the port) or ``0..V-1`` every sweep.
SENSOR_ORDERS = ("random", "fixed")

_LOG_2PI = math.log(2.0 * math.pi)
# Tensors larger than this are refused by AdaptiveBirthProblem.log_weights (dense oracle input).
_MAX_TENSOR = 1 << 26
# Bound on the information sums of the closed form (spec eq. 1.6): a tuple's c_J = mu0' P0^-1
# mu0 + sum_v z' R_v^-1 z and the entries of M_J = P0^-1 + sum_v H_v' R_v^-1 H_v add at most
# V + 1 terms, each kept <= _INFO_LIMIT / (V + 1), so they stay finite (with room for the
# Cholesky factor and |L^-1 b|^2 <= c_J) and c_J - |L^-1 b_J|^2 is never inf - inf = NaN.
_INFO_LIMIT = 2.0**1000




def _per_sensor(x, name: str, V: int, shared_ndim: int) -> list:
    """A list of V entries: V copies of ``x`` if it has ``shared_ndim`` dimensions, else ``x``."""
    try:
        nd = np.ndim(x)
    except ValueError:  # ragged: per-sensor arrays of different shapes
        nd = -1
    if nd == shared_ndim:
        return [x] * V
    if isinstance(x, (list, tuple, np.ndarray)):
        if len(x) != V:
            raise ValueError(f"{name} must have one entry per sensor (V = {V}), got {len(x)}")
        return list(x)
    return [x] * V


def _check_finite(a: np.ndarray, name: str) -> None:
    if not np.isfinite(a).all():
        raise ValueError(f"{name} must be finite, got {a.tolist()}")


def _spd_half_logdet(M: np.ndarray, name: str) -> float:
    """``0.5 ln |M|`` of a symmetric positive-definite matrix (``ValueError`` otherwise)."""
    if not np.allclose(M, M.T, rtol=1e-10, atol=0.0):
        raise ValueError(f"{name} must be symmetric")
    try:
        L = np.linalg.cholesky(M)
    except np.linalg.LinAlgError:
        raise ValueError(f"{name} must be positive definite") from None
    return float(np.sum(np.log(np.diag(L))))


class AdaptiveBirthProblem:
    """Measurement-tuple target of the multi-sensor adaptive-birth Gibbs sampler.

    Build one with :meth:`from_measurements` (linear-Gaussian sensors, the closed form) or
    :meth:`from_log_weights` (any tensor of log-weights). The state is a tuple
    ``J = (j^(1), ..., j^(V))`` with ``j^(v)`` in ``0..M_v`` (0 = missed by sensor ``v``).
    The constructor itself is private and trusts its arguments; the two builders validate them.

    Parameters
    ----------
    shape : sequence of int
        ``(M_1 + 1, ..., M_V + 1)``, the shape of the tuple space (one axis per sensor).
    n_min : int
        Minimum number of detections of a birth tuple, ``0 <= n_min <= V`` (already checked).
    tensor : ndarray of float64, optional
        Read-only tensor of ``ln rho`` of shape ``shape`` (:meth:`from_log_weights`);
        ``None`` for the linear-Gaussian form.
    model : dict, optional
        The linear-Gaussian model and the per-measurement information terms precomputed by
        :meth:`from_measurements` (the prior ``mu0``, ``P0``, its inverse ``M0`` and
        ``b0 = M0 mu0``, ``c0 = mu0' M0 mu0``, the sensors' ``H``, ``R``, kept ``z``, and
        ``A``, ``a``, ``cz``, ``const``, ``log_miss``, ``off`` of the Notes there); ``None``
        for a tensor problem.
    kept : tuple of V ndarray of int64, optional
        Indices of the kept measurements per sensor (see Attributes); ``None`` for a tensor
        problem.

    Attributes
    ----------
    n_sensors : int
        ``V``.
    n_meas : tuple of int
        ``(M_1, ..., M_V)``, kept measurements per sensor (after the ``tau_rU`` rule).
    shape : tuple of int
        ``(M_1 + 1, ..., M_V + 1)``, the shape of the tuple space.
    n_min : int
        Tuples with fewer detections are not births (spec §4.3); the all-missed tuple never is.
    kept : tuple of ndarray or None
        Per sensor, the indices (0-based, into the measurements given to
        :meth:`from_measurements`) of the kept measurements: ``j^(v) = m`` is measurement
        ``kept[v][m - 1]``. ``None`` for a problem built from log-weights.
    is_gaussian : bool
        Whether the problem carries the linear-Gaussian model (needed by
        :func:`birth_from_samples`).

    Notes
    -----
    Target (spec eq. 4.2): ``rho(J) = prod_v r_U^(v)(j^(v)) psibar_B(J)`` with
    ``r_U^(v)(0) = 1``; the sampler's stationary law is ``pi_B = rho / sum rho`` over the
    whole tuple space. Log-weights returned by :meth:`log_weight_of` are the complete
    ``ln rho(J)`` (every constant kept), so they can be compared across problems.

    References
    ----------
    .. [1] A. Trezza, D. J. Bucci Jr., P. K. Varshney, "Multi-sensor joint adaptive birth
       sampler for labeled random finite set tracking", IEEE Trans. Signal Process. 70, 2022.

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign.adaptive_birth import AdaptiveBirthProblem
    >>> p = AdaptiveBirthProblem.from_log_weights(np.log([[1.0, 2.0], [3.0, 4.0]]))
    >>> p.n_sensors, p.n_meas, p.n_feasible()
    (2, (1, 1), 4)
    >>> float(np.exp(p.log_weight_of([1, 1])))
    4.0
    """

    def __init__(self, *, shape, n_min, tensor=None, model=None, kept=None):
        # Private: use from_measurements / from_log_weights.
        self.shape = tuple(int(s) for s in shape)
        self.n_sensors = len(self.shape)
        self.n_meas = tuple(s - 1 for s in self.shape)
        self.n_min = n_min
        self.kept = kept
        self._tensor = tensor
        self._model = model
        self._dense = None
        self.is_gaussian = model is not None

    # ------------------------------------------------------------------ constructors
    @classmethod
    def from_log_weights(cls, log_weights, *, n_min: int | None = None) -> AdaptiveBirthProblem:
        """A problem whose target is ``rho = exp(log_weights)`` on the tuple space.

        Parameters
        ----------
        log_weights : array_like, shape (M_1 + 1, ..., M_V + 1)
            ``ln rho(J)`` for every tuple; ``-inf`` = weight zero. The all-missed entry
            ``[0, ..., 0]`` (the chains' start) must be finite.
        n_min : int, optional
            Minimum number of detections of a birth tuple (``0 <= n_min <= V``; default
            ``min(2, V)``, spec §8 Q2).

        Returns
        -------
        AdaptiveBirthProblem

        Raises
        ------
        TypeError
            If the weights are not numeric or ``n_min`` is not an int.
        ValueError
            If the tensor is 0-D, has an empty axis, contains NaN or ``+inf``, its all-missed
            entry is ``-inf``, or ``n_min`` is out of range.

        Examples
        --------
        >>> import numpy as np
        >>> p = AdaptiveBirthProblem.from_log_weights(np.zeros((3, 3, 3)), n_min=1)
        >>> p.shape, p.n_feasible(), p.is_gaussian
        ((3, 3, 3), 27, False)
        """
        try:
            t = np.array(log_weights, dtype=np.float64)
        except (TypeError, ValueError) as exc:
            raise TypeError(f"log_weights must be a numeric array, could not convert: {exc}"
                            ) from None
        if t.ndim == 0:
            raise ValueError("log_weights must have one axis per sensor (V >= 1), got a scalar")
        if 0 in t.shape:
            raise ValueError(f"log_weights has an empty axis: shape {t.shape}; each axis has "
                             "M_v + 1 >= 1 entries (index 0 = missed)")
        if np.isnan(t).any():
            raise ValueError("log_weights contains NaN")
        if np.isposinf(t).any():
            raise ValueError("log_weights contains +inf")
        if not np.isfinite(t[(0,) * t.ndim]):
            raise ValueError("log_weights of the all-missed tuple (the chains' start) must be "
                             "finite")
        n_min = min(2, t.ndim) if n_min is None else check_int(n_min, "n_min", minimum=0,
                                                               maximum=t.ndim)
        t = np.ascontiguousarray(t)
        t.setflags(write=False)
        return cls(shape=t.shape, n_min=n_min, tensor=t)

    @classmethod
    def from_measurements(cls, measurements, r_U, *, H, R, P_D, clutter_intensity, mu0, P0,
                          tau_rU: float = 0.9, n_min: int | None = None) -> AdaptiveBirthProblem:
        """Build the linear-Gaussian problem of spec §4 from raw measurements.

        Parameters
        ----------
        measurements : sequence of V array_like, each shape (M_v, d_v)
            Measurements of each sensor.
        r_U : sequence of V array_like, each shape (M_v,)
            Probability that each measurement is *not* explained by an existing track
            (spec §4.1), in ``[0, 1]``.
        H : array_like (d, n) or sequence of V such arrays
            Measurement matrices (one shared, or one per sensor).
        R : array_like (d, d) or sequence of V such arrays
            Measurement noise covariances (symmetric positive definite).
        P_D : float or sequence of V floats
            Detection probabilities, in ``(0, 1)``.
        clutter_intensity : float, or sequence of V entries each a float or shape (M_v,)
            Poisson clutter intensity ``kappa^(v)`` at each measurement (``> 0``); a scalar is
            a uniform intensity.
        mu0 : array_like, shape (n,)
            Birth prior mean.
        P0 : array_like, shape (n, n)
            Birth prior covariance (symmetric positive definite).
        tau_rU : float, optional
            Keep only measurements with ``r_U > tau_rU`` (spec §4.1; default 0.9, the port's).
        n_min : int, optional
            Minimum number of detections of a birth tuple (``0 <= n_min <= V``; default
            ``min(2, V)``, spec §8 Q2).

        Returns
        -------
        AdaptiveBirthProblem
            With ``kept`` mapping tuple entries back to the given measurements.

        Raises
        ------
        TypeError
            If an array is not numeric or a scalar has the wrong type.
        ValueError
            On inconsistent shapes, NaN, probabilities out of range, a non-SPD covariance or a
            non-positive clutter intensity; on an infinite entry of ``mu0``, ``P0``, ``H``,
            ``R`` or a kept measurement; and on inputs too large for the closed form in
            float64: a kept measurement with ``z' R_v^-1 z`` (or ``mu0' P0^-1 mu0``, or an
            entry of ``P0^-1`` or ``H_v' R_v^-1 H_v``) above ``2**1000 / (V + 1)``, beyond which
            the sums below overflow and ``ln rho`` would be NaN (the message names the input).

        Notes
        -----
        Per sensor ``v`` and kept measurement ``m`` the problem precomputes (spec eq. 1.6,
        4.2) ``A_v = H_v' R_v^-1 H_v``, ``a_vm = H_v' R_v^-1 z_vm``, ``c_vm = z_vm' R_v^-1
        z_vm`` and ``const_vm = ln r_U + ln(P_D / kappa) - (d_v ln 2 pi + ln|R_v|) / 2``;
        with ``M_J = P_0^-1 + sum_{v in D} A_v``, ``b_J = P_0^-1 mu_0 + sum a``,
        ``c_J = mu_0' P_0^-1 mu_0 + sum c``::

            ln rho(J) = sum_{v not in D} ln(1 - P_D^(v)) + sum_{v in D} const_v
                        - (ln|P_0| + ln|M_J|) / 2 - (c_J - b_J' M_J^-1 b_J) / 2

        Examples
        --------
        >>> import numpy as np
        >>> z = [np.array([[0.0], [50.0]]), np.array([[1.0]])]
        >>> p = AdaptiveBirthProblem.from_measurements(
        ...     z, [[0.99, 0.5], [0.95]], H=[[1.0]], R=[[1.0]], P_D=0.9,
        ...     clutter_intensity=0.01, mu0=[0.0], P0=[[100.0]])
        >>> p.n_meas, [k.tolist() for k in p.kept]      # z = 50 has r_U = 0.5 <= 0.9: dropped
        ((1, 1), [[0], [0]])
        >>> bool(p.log_weight_of([1, 1]) > p.log_weight_of([1, 0]))
        True
        """
        if not isinstance(measurements, (list, tuple)) or len(measurements) == 0:
            raise TypeError("measurements must be a non-empty list or tuple with one array per "
                            f"sensor, got {type(measurements).__name__}")
        V = len(measurements)
        mu0 = float_array(mu0, "mu0", ndim=1, allow_nan=False)
        n = mu0.shape[0]
        if n == 0:
            raise ValueError("mu0 must have at least one state component")
        _check_finite(mu0, "mu0")
        P0 = float_array(P0, "P0", ndim=2, allow_nan=False)
        if P0.shape != (n, n):
            raise ValueError(f"P0 must have shape (n, n) = ({n}, {n}), got {P0.shape}")
        _check_finite(P0, "P0")
        half_logdet_P0 = _spd_half_logdet(P0, "P0")
        bound = _INFO_LIMIT / (V + 1)
        limit = f"2**1000 / (V + 1) = {bound:.3g} (V = {V})"
        why = "beyond it the information sums overflow and ln rho would be NaN"
        tau_rU = check_real(tau_rU, "tau_rU", minimum=0.0, maximum=1.0)
        n_min = min(2, V) if n_min is None else check_int(n_min, "n_min", minimum=0, maximum=V)
        Hs, Rs, pds, kappas = (_per_sensor(H, "H", V, 2), _per_sensor(R, "R", V, 2),
                               _per_sensor(P_D, "P_D", V, 0),
                               _per_sensor(clutter_intensity, "clutter_intensity", V, 0))
        if not isinstance(r_U, (list, tuple)) or len(r_U) != V:
            raise ValueError(f"r_U must be a list with one array per sensor (V = {V})")
        M0 = np.linalg.inv(P0)
        M0 = 0.5 * (M0 + M0.T)
        with np.errstate(over="ignore", invalid="ignore"):
            c0 = float(mu0 @ M0 @ mu0)
        if not np.abs(M0).max() <= bound:
            raise ValueError(f"P0 is too close to singular for the closed form of ln rho: P0^-1 "
                             f"has an entry of {np.abs(M0).max():.3g}, above {limit}; {why}")
        if not c0 <= bound:
            raise ValueError(f"mu0 = {mu0.tolist()} is too large for the closed form of ln rho: "
                             f"mu0' P0^-1 mu0 = {c0:.3g} exceeds {limit}; {why}")
        model = {"n": n, "mu0": mu0, "P0": P0, "M0": M0, "b0": M0 @ mu0,
                 "c0": c0, "half_logdet_P0": half_logdet_P0,
                 "H": [], "R": [], "z": [], "log_miss": np.empty(V), "A": np.empty((V, n, n)),
                 "a": [], "cz": [], "const": []}
        kept = []
        for v in range(V):
            Hv = float_array(Hs[v], f"H[{v}]", ndim=2, allow_nan=False)
            if Hv.shape[1] != n:
                raise ValueError(f"H[{v}] must have n = {n} columns, got shape {Hv.shape}")
            _check_finite(Hv, f"H[{v}]")
            d = Hv.shape[0]
            Rv = float_array(Rs[v], f"R[{v}]", ndim=2, allow_nan=False)
            if Rv.shape != (d, d):
                raise ValueError(f"R[{v}] must have shape ({d}, {d}), got {Rv.shape}")
            _check_finite(Rv, f"R[{v}]")
            half_logdet_R = _spd_half_logdet(Rv, f"R[{v}]")
            pd = check_real(pds[v], f"P_D[{v}]", minimum=0.0, strict_minimum=True,
                            maximum=1.0)
            if pd >= 1.0:
                raise ValueError(f"P_D[{v}] must be < 1, got {pd}")
            z = np.asarray(measurements[v], dtype=np.float64) if len(measurements[v]) else \
                np.zeros((0, d))
            z = float_array(z, f"measurements[{v}]", ndim=2, allow_nan=False)
            if z.shape[1] != d:
                raise ValueError(f"measurements[{v}] must have shape (M, {d}), got {z.shape}")
            Mv = z.shape[0]
            ru = float_array(r_U[v], f"r_U[{v}]", ndim=1, allow_nan=False) if Mv else np.zeros(0)
            if ru.shape != (Mv,):
                raise ValueError(f"r_U[{v}] must have shape ({Mv},), got {ru.shape}")
            if ((ru < 0) | (ru > 1)).any():
                raise ValueError(f"r_U[{v}] must lie in [0, 1]")
            kap = float_array(np.atleast_1d(kappas[v]), f"clutter_intensity[{v}]", ndim=1,
                              allow_nan=False)
            if np.ndim(kappas[v]) == 0:
                kap = np.broadcast_to(kap, (Mv,))
            if kap.shape != (Mv,):
                raise ValueError(f"clutter_intensity[{v}] must be a scalar or have shape "
                                 f"({Mv},), got {kap.shape}")
            if not (np.isfinite(kap) & (kap > 0)).all():
                raise ValueError(f"clutter_intensity[{v}] must be finite and > 0")
            keep = np.flatnonzero(ru > tau_rU)                        # spec §4.1 drop rule
            kept.append(keep)
            z, ru, kap = z[keep], ru[keep], kap[keep]
            Ri = np.linalg.inv(Rv)
            Ri = 0.5 * (Ri + Ri.T)
            model["H"].append(Hv)
            model["R"].append(Rv)
            model["z"].append(z)
            with np.errstate(over="ignore", invalid="ignore"):   # checked just below
                A = Hv.T @ Ri @ Hv                                     # H' R^-1 H
                a = z @ (Ri @ Hv)                                      # rows H' R^-1 z
                cz = np.einsum("md,de,me->m", z, Ri, z)                # z' R^-1 z
            if not np.abs(A).max(initial=0.0) <= bound:
                raise ValueError(
                    f"H[{v}]' R[{v}]^-1 H[{v}] has an entry of {np.abs(A).max():.3g}, above "
                    f"{limit}: R[{v}] is too close to singular or H[{v}] too large for the "
                    f"closed form of ln rho; {why}")
            finite = np.isfinite(z).all(axis=1)
            bad = np.flatnonzero(~(finite & (cz <= bound)))           # (NaN cz is bad too)
            if bad.size:
                m = int(bad[0])
                text = ("is not finite" if not finite[m] else
                        f"is too large for the closed form of ln rho: z' R[{v}]^-1 z = "
                        f"{cz[m]:.3g} exceeds {limit}; {why}")
                raise ValueError(f"measurements[{v}][{int(keep[m])}] = {z[m].tolist()} {text}")
            model["A"][v] = A
            model["a"].append(a)
            model["cz"].append(cz)
            model["const"].append(np.log(ru) + math.log(pd) - np.log(kap)
                                  - 0.5 * d * _LOG_2PI - half_logdet_R)
            model["log_miss"][v] = math.log1p(-pd)
        off = np.zeros(V + 1, dtype=np.int64)
        off[1:] = np.cumsum([len(k) for k in kept])
        model["off"] = off
        for key in ("a", "cz", "const"):
            model[key] = np.ascontiguousarray(np.concatenate(model[key], axis=0))
        model["a"] = model["a"].reshape(int(off[-1]), n)
        return cls(shape=[len(k) + 1 for k in kept], n_min=n_min, model=model,
                   kept=tuple(k.astype(np.int64) for k in kept))

    # ------------------------------------------------------------------ queries
    def __repr__(self) -> str:
        kind = "gaussian" if self.is_gaussian else "tensor"
        return (f"AdaptiveBirthProblem(V={self.n_sensors}, n_meas={self.n_meas}, "
                f"n_min={self.n_min}, {kind})")

    def n_feasible(self) -> int:
        """Size of the tuple space, ``prod_v (M_v + 1)`` (spec §6.1).

        Returns
        -------
        int
            The number of tuples ``J``; every one is a state of the sampler (no one-to-one
            constraint), although tuples of weight zero are never visited.

        Examples
        --------
        >>> import numpy as np
        >>> AdaptiveBirthProblem.from_log_weights(np.zeros((11, 11, 11, 11))).n_feasible()
        14641
        """
        return math.prod(self.shape)

    def n_detections(self, tuples) -> np.ndarray:
        """Number of sensors that detect each tuple, ``#{v : j^(v) > 0}``.

        Parameters
        ----------
        tuples : array_like of int, shape (n, V) or (V,)
            Measurement tuples, entry ``v`` in ``0..M_v``.

        Returns
        -------
        ndarray of int, shape (n,)
            The count of non-zero entries of each tuple (shape ``(1,)`` for a single tuple);
            tuples with fewer than :attr:`n_min` detections are not births.

        Raises
        ------
        TypeError
            If the tuples are not integers.
        ValueError
            On a wrong shape or an entry outside ``0..M_v``.

        Examples
        --------
        >>> import numpy as np
        >>> p = AdaptiveBirthProblem.from_log_weights(np.zeros((3, 3)))
        >>> p.n_detections([[0, 0], [2, 0], [1, 2]]).tolist()
        [0, 1, 2]
        """
        J, _ = self._as_tuples(tuples)
        return (J > 0).sum(axis=1)

    def _as_tuples(self, tuples, name: str = "tuples") -> tuple[np.ndarray, bool]:
        a = np.asarray(tuples)
        if a.dtype == bool or not np.issubdtype(a.dtype, np.integer):
            if a.size == 0:
                a = a.astype(np.int64)
            else:
                raise TypeError(f"{name} must be integers, got dtype {a.dtype}")
        single = a.ndim == 1
        a = a.reshape(1, -1) if single else a
        V = self.n_sensors
        if a.ndim != 2 or a.shape[1] != V:
            raise ValueError(f"{name} must have shape (n, V) or (V,) with V = {V}, got "
                             f"{np.shape(tuples)}")
        a = a.astype(np.int64)
        if a.size and ((a < 0) | (a >= np.asarray(self.shape)[None, :])).any():
            raise ValueError(f"{name} has an entry outside 0..M_v, M = {self.n_meas}")
        return a, single

    def log_weight_of(self, tuples) -> np.ndarray | float:
        """``ln rho(J)`` of each tuple (spec eq. 4.2, every constant kept).

        Parameters
        ----------
        tuples : array_like of int, shape (n, V) or (V,)
            Measurement tuples, entry ``v`` in ``0..M_v`` (0 = missed by sensor ``v``).

        Returns
        -------
        ndarray of float64, shape (n,), or float
            ``ln rho(J)`` of each tuple, a float for a single ``(V,)`` tuple; ``-inf`` for a
            tuple of weight zero.

        Raises
        ------
        TypeError
            If the tuples are not integers.
        ValueError
            On a wrong shape or an entry outside ``0..M_v``.

        Examples
        --------
        >>> import numpy as np
        >>> p = AdaptiveBirthProblem.from_log_weights(np.log([[1.0, 2.0], [3.0, 4.0]]))
        >>> np.exp(p.log_weight_of([[0, 1], [1, 0]])).round(12).tolist()
        [2.0, 3.0]
        """
        J, single = self._as_tuples(tuples)
        out = self._tensor[tuple(J.T)] if self._tensor is not None else self._log_rho(J)
        out = np.asarray(out, dtype=np.float64)
        return float(out[0]) if single else out

    def cost_of(self, tuples) -> np.ndarray | float:
        """``-ln rho(J)`` (the samplers' ``costs``).

        Parameters
        ----------
        tuples : array_like of int, shape (n, V) or (V,)
            Measurement tuples, entry ``v`` in ``0..M_v``.

        Returns
        -------
        ndarray of float64, shape (n,), or float
            ``-self.log_weight_of(tuples)``; a float for a single ``(V,)`` tuple; ``+inf`` for
            a tuple of weight zero.

        Raises
        ------
        TypeError, ValueError
            As :meth:`log_weight_of`.

        Examples
        --------
        >>> import numpy as np
        >>> p = AdaptiveBirthProblem.from_log_weights(np.log([[1.0, 2.0]]))
        >>> round(float(p.cost_of([0, 1])), 12)
        -0.69314718056
        """
        return -self.log_weight_of(tuples)

    def log_weights(self) -> np.ndarray:
        """The dense tensor of ``ln rho`` over the tuple space, shape :attr:`shape`.

        Returns
        -------
        ndarray of float64, shape (M_1 + 1, ..., M_V + 1)
            Entry ``J`` is ``ln rho(J)`` (as :meth:`log_weight_of`); ``-inf`` for weight zero.
            Read-only: the tensor given to :meth:`from_log_weights`, or the closed form
            evaluated once for every tuple and cached.

        Raises
        ------
        ValueError
            If the tuple space has more than ``2**26`` entries.

        Examples
        --------
        >>> import numpy as np
        >>> AdaptiveBirthProblem.from_log_weights(np.zeros((2, 3))).log_weights().shape
        (2, 3)
        """
        if self._tensor is not None:
            return self._tensor
        if self._dense is None:                             # computed once, read-only
            N = self.n_feasible()
            if N > _MAX_TENSOR:
                raise ValueError(f"tuple space too large for a dense tensor: {N} > "
                                 f"{_MAX_TENSOR}")
            J = np.indices(self.shape).reshape(self.n_sensors, -1).T
            dense = self._log_rho(J).reshape(self.shape)
            dense.setflags(write=False)
            self._dense = dense
        return self._dense

    def _log_rho(self, J: np.ndarray) -> np.ndarray:
        """Closed-form ``ln rho`` of tuples ``J`` (n, V), one factorisation per pattern."""
        m = self._model
        V = self.n_sensors
        off = m["off"]
        det = J > 0
        out = np.zeros(J.shape[0])
        for v in range(V):                                  # fixed order: reproducible sums
            idx = np.where(det[:, v], off[v] + J[:, v] - 1, 0)
            out += np.where(det[:, v], m["const"][idx] if len(m["const"]) else 0.0,
                            m["log_miss"][v])
        pattern = det.astype(np.int64) @ (np.int64(1) << np.arange(V, dtype=np.int64))
        for pat in np.unique(pattern):
            rows = np.flatnonzero(pattern == pat)
            Mj = m["M0"].copy()
            b = np.repeat(m["b0"][None, :], rows.size, axis=0)
            c = np.full(rows.size, m["c0"])
            for v in range(V):
                if (pat >> v) & 1:
                    k = off[v] + J[rows, v] - 1
                    Mj += m["A"][v]
                    b += m["a"][k]
                    c += m["cz"][k]
            L = np.linalg.cholesky(Mj)
            y = np.linalg.solve(L, b.T)                     # L^-1 b
            q = c - np.sum(y * y, axis=0)                   # c - b' M^-1 b
            hl = float(np.sum(np.log(np.diag(L))))          # ln|M_J| / 2
            out[rows] += -m["half_logdet_P0"] - hl - 0.5 * q
        return out

    def posterior(self, tuples) -> tuple[np.ndarray, np.ndarray]:
        """Posterior mean ``M_J^-1 b_J`` and covariance ``M_J^-1`` of each tuple (spec §4.4).

        Parameters
        ----------
        tuples : array_like of int, shape (n, V)

        Returns
        -------
        means : ndarray, shape (n, n_x)
        covs : ndarray, shape (n, n_x, n_x)

        Raises
        ------
        ValueError
            If the problem was built from log-weights (no model).

        Examples
        --------
        >>> import numpy as np
        >>> p = AdaptiveBirthProblem.from_measurements(
        ...     [np.array([[2.0]])], [[1.0]], H=[[1.0]], R=[[1.0]], P_D=0.5,
        ...     clutter_intensity=1.0, mu0=[0.0], P0=[[1.0]], n_min=1)
        >>> m, P = p.posterior([[1]])                 # N(0,1) prior, z = 2, R = 1
        >>> m.tolist(), P.tolist()
        ([[1.0]], [[[0.5]]])
        """
        if self._model is None:
            raise ValueError("posterior needs the linear-Gaussian model: build the problem "
                             "with AdaptiveBirthProblem.from_measurements")
        J, _ = self._as_tuples(tuples)
        m = self._model
        n = m["n"]
        means = np.empty((J.shape[0], n))
        covs = np.empty((J.shape[0], n, n))
        for i, t in enumerate(J):
            Mj = m["M0"].copy()
            b = m["b0"].copy()
            for v in range(self.n_sensors):
                if t[v] > 0:
                    Mj += m["A"][v]
                    b += m["a"][m["off"][v] + t[v] - 1]
            cov = np.linalg.inv(Mj)
            covs[i] = 0.5 * (cov + cov.T)
            means[i] = np.linalg.solve(Mj, b)
        return means, covs


# ---------------------------------------------------------------------------- birth LMB
class BirthLMB(NamedTuple):
    """LMB birth components made from sampled tuples (spec §4.4).

    Attributes
    ----------
    tuples : ndarray, int64, shape (k, V)
        The kept tuples (``>= max(n_min, 1)`` detections), in the sampler's discovery order.
    measurements : ndarray, int64, shape (k, V)
        The same tuples as indices into the measurements given to
        :meth:`AdaptiveBirthProblem.from_measurements` (``-1`` = missed).
    means : ndarray, shape (k, n)
        ``F M_J^-1 b_J`` (posterior mean given J, predicted).
    covs : ndarray, shape (k, n, n)
        ``F M_J^-1 F' + Q``.
    r : ndarray, shape (k,)
        ``min(r_b_max, lambda_B rho(J) / sum_{J' kept} rho(J'))``.
    log_rho : ndarray, shape (k,)
        ``ln rho(J)``.
    """

    tuples: np.ndarray
    measurements: np.ndarray
    means: np.ndarray
    covs: np.ndarray
    r: np.ndarray
    log_rho: np.ndarray


def birth_from_samples(problem, result, *, F=None, Q=None, r_b_max: float = 0.01,
                       lambda_b: float = 1.0) -> BirthLMB:
    """LMB birth components from the tuples a sampler visited (spec §4.4).

    Parameters
    ----------
    problem : AdaptiveBirthProblem
        Built with :meth:`AdaptiveBirthProblem.from_measurements`.
    result : SamplerResult or array_like of int, shape (k, V)
        A sampler's result over ``problem`` (its ``assignments`` are tuples), or tuples.
        Duplicates count once; tuples with fewer than ``max(problem.n_min, 1)`` detections are
        dropped (the all-missed tuple always).
    F : array_like, shape (n, n), optional
        Transition matrix predicting the births to the next scan (default identity).
    Q : array_like, shape (n, n), optional
        Process noise added to the predicted covariance (default zero).
    r_b_max : float, optional
        Cap on each birth's existence probability (default 0.01, the port's class default).
    lambda_b : float, optional
        Expected number of births per scan scaling the normalised weights (default 1,
        spec §8 Q2).

    Returns
    -------
    BirthLMB
        One component per kept tuple (possibly none).

    Raises
    ------
    TypeError
        If ``problem`` is not an AdaptiveBirthProblem or a scalar has the wrong type.
    ValueError
        If the problem carries no Gaussian model, on a tuple out of range, a wrong ``F``/``Q``
        shape, ``r_b_max`` outside ``(0, 1]`` or ``lambda_b <= 0``.

    Notes
    -----
    ``m_B(J) = F M_J^-1 b_J``, ``P_B(J) = F M_J^-1 F' + Q``,
    ``r_B(J) = min(r_b_max, lambda_b rho(J) / sum_{J' in U_kept} rho(J'))`` (spec §4.4;
    ``r_U(0) = 1`` throughout, unlike the port's final weights, §4.6 item 1).

    References
    ----------
    .. [1] A. Trezza, D. J. Bucci Jr., P. K. Varshney, "Multi-sensor joint adaptive birth
       sampler for labeled random finite set tracking", IEEE Trans. Signal Process. 70, 2022.

    Examples
    --------
    >>> import numpy as np
    >>> z = [np.array([[0.0]]), np.array([[0.5]])]
    >>> p = AdaptiveBirthProblem.from_measurements(
    ...     z, [[1.0], [1.0]], H=[[1.0]], R=[[1.0]], P_D=0.9, clutter_intensity=0.01,
    ...     mu0=[0.0], P0=[[100.0]])
    >>> b = birth_from_samples(p, [[0, 0], [1, 0], [1, 1]], r_b_max=0.5)
    >>> b.tuples.tolist(), b.measurements.tolist(), b.r.tolist()
    ([[1, 1]], [[0, 0]], [0.5])
    """
    check_type(problem, "problem", AdaptiveBirthProblem)
    if not problem.is_gaussian:
        raise ValueError("birth_from_samples needs the linear-Gaussian model: build the problem "
                         "with AdaptiveBirthProblem.from_measurements")
    r_b_max = check_real(r_b_max, "r_b_max", minimum=0.0, strict_minimum=True, maximum=1.0)
    lambda_b = check_real(lambda_b, "lambda_b", minimum=0.0, strict_minimum=True)
    n = problem._model["n"]
    F = np.eye(n) if F is None else float_array(F, "F", ndim=2, allow_nan=False)
    Q = np.zeros((n, n)) if Q is None else float_array(Q, "Q", ndim=2, allow_nan=False)
    for name, X in (("F", F), ("Q", Q)):
        if X.shape != (n, n):
            raise ValueError(f"{name} must have shape ({n}, {n}), got {X.shape}")
    tuples = getattr(result, "assignments", result)
    J, _ = problem._as_tuples(tuples)
    _, first = np.unique(J, axis=0, return_index=True)
    J = J[np.sort(first)]                                   # unique, discovery order
    J = J[(J > 0).sum(axis=1) >= max(problem.n_min, 1)]
    V = problem.n_sensors
    meas = np.full(J.shape, -1, dtype=np.int64)
    for v in range(V):
        hit = J[:, v] > 0
        meas[hit, v] = problem.kept[v][J[hit, v] - 1]
    if J.shape[0] == 0:
        return BirthLMB(J, meas, np.zeros((0, n)), np.zeros((0, n, n)), np.zeros(0),
                        np.zeros(0))
    log_rho = problem.log_weight_of(J)
    mx = log_rho.max()
    share = np.exp(log_rho - mx) / np.sum(np.exp(log_rho - mx))
    r = np.minimum(r_b_max, lambda_b * share)
    means, covs = problem.posterior(J)
    means = means @ F.T                                     # m_B = F M^-1 b
    covs = F[None] @ covs @ F.T[None] + Q[None]             # P_B = F M^-1 F' + Q
    return BirthLMB(J, meas, means, covs, r, log_rho)

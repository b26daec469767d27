"""Adaptive birth for the multi-sensor LMB filter (multi-sensor spec §4, §7.2, §7.4).

Instead of a birth density placed by hand, the births of scan ``k + 1`` are made from the
measurements of scan ``k`` that the tracks do not explain:

1. after the joint update, per sensor ``v`` and measurement ``j`` the probability that some
   track generated it, ``r_A^(v)(j) = Σ_n Σ_{t: t^(v) = j} β_{n,t}`` (spec §7.4, from the
   association's posterior marginals), and ``r_U = 1 − r_A`` clipped to ``[0, 1]``
   (``r_U = 1`` for every measurement when there are no tracks);
2. the measurements with ``r_U > τ_rU`` enter an
   :class:`~rankedassign.adaptive_birth.AdaptiveBirthProblem` (target
   ``ρ(J) = Π_v r_U^(v)(j^(v)) ψ̄_B(J)`` over measurement tuples ``J``, spec eq. 4.2, with the
   broad prior ``N(μ_0, P_0)``, the sensors' ``H``, ``R``, ``P_D`` and clutter intensity);
3. the adaptive-birth Gibbs sampler (short chains by default) visits tuples; those with at
   least ``n_min`` detections become Bernoulli components (spec §4.4)::

       m_B(J) = F M_J⁻¹ b_J ,  P_B(J) = F M_J⁻¹ Fᵀ + Q
       r_B(J) = min(r_B,max , λ_B ρ(J) / Σ_{J' kept} ρ(J'))

4. births with ``r_B`` at most the filter's ``prune_track`` are dropped and at most
   ``max_births`` (the largest ``ρ``) are kept; they are the births of the next scan's
   prediction, with labels ``(k + 1, b)`` as the static births get.

:class:`AdaptiveBirth` holds the settings (defaults of spec §7.2 and the adaptive-birth study's
short chains); :meth:`AdaptiveBirth.births` runs steps 2–4 and is what
:class:`~rankedassign.tracking.multisensor.lmb.MultiSensorLMBFilter` calls after each update.

References
----------
.. [1] A. Trezza, D. J. Bucci Jr., P. K. Varshney, "Multi-sensor joint adaptive birth sampler
   for labeled random finite set tracking", IEEE Trans. Signal Process. 70, 2022
   (arXiv:2109.04355).
.. [2] S. Reuter, D. Meissner, B. Wilking, K. Dietmayer, "Adaptive birth of the labeled
   multi-Bernoulli filter", FUSION 2014.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...adaptive_birth import AdaptiveBirthProblem, BirthLMB, birth_from_samples
from ...adaptive_birth.problem import SENSOR_ORDERS
from ...samplers import sample_original, sample_short_chains
from ...validation import check_choice, check_int, check_optional_int, check_real

__all__ = ["AB_SAMPLERS", "AdaptiveBirth", "empty_birth"]

#: Samplers of the adaptive birth: the short chains (default) or one long chain.
AB_SAMPLERS = ("short", "long")

_STATE_DIM = 4


def _prior_mean(mu0) -> tuple:
    try:
        arr = np.asarray(mu0, dtype=np.float64)
    except (TypeError, ValueError):
        raise TypeError(f"mu0 must be a numeric array of shape (4,), got {mu0!r}") from None
    if arr.shape != (_STATE_DIM,) or not np.isfinite(arr).all():
        raise ValueError(f"mu0 must be a finite array of shape (4,), got {arr.tolist()}")
    return tuple(float(x) for x in arr)


def _prior_cov(P0) -> tuple:
    try:
        arr = np.asarray(P0, dtype=np.float64)
    except (TypeError, ValueError):
        raise TypeError(f"P0 must be a numeric array of shape (4, 4), got {P0!r}") from None
    if arr.shape != (_STATE_DIM, _STATE_DIM) or not np.isfinite(arr).all():
        raise ValueError(f"P0 must be a finite array of shape (4, 4), got shape {arr.shape}")
    if not np.allclose(arr, arr.T, rtol=1e-10, atol=0.0):
        raise ValueError("P0 must be symmetric")
    try:
        np.linalg.cholesky(arr)
    except np.linalg.LinAlgError:
        raise ValueError("P0 must be positive definite") from None
    return tuple(tuple(float(x) for x in row) for row in arr)


def empty_birth(n: int = _STATE_DIM) -> BirthLMB:
    """A :class:`~rankedassign.adaptive_birth.BirthLMB` without components.

    Parameters
    ----------
    n : int, optional
        State dimension of the (absent) components (default 4, ``[p_x, v_x, p_y, v_y]``).

    Returns
    -------
    BirthLMB
        Zero components: ``tuples`` and ``measurements`` int64 of shape (0, 0), ``means``
        float64 (0, n), ``covs`` float64 (0, n, n), ``r`` and ``log_rho`` float64 (0,).

    Examples
    --------
    >>> from rankedassign.tracking.multisensor.adaptive_birth import empty_birth
    >>> b = empty_birth()
    >>> b.r.shape, b.means.shape, b.covs.shape
    ((0,), (0, 4), (0, 4, 4))
    """
    z = np.zeros((0, 0), dtype=np.int64)
    return BirthLMB(z, z.copy(), np.zeros((0, n)), np.zeros((0, n, n)), np.zeros(0),
                    np.zeros(0))


@dataclass(frozen=True)
class AdaptiveBirth:
    """Settings of the adaptive birth of :class:`~rankedassign.tracking.MultiSensorLMBFilter`.

    Pass an instance as ``MultiSensorLMBFilter(model, association, birth=AdaptiveBirth())``
    (or ``birth="adaptive"`` to :func:`~rankedassign.tracking.run_multisensor_scenario`); the
    model's static birth is then not used.

    Parameters
    ----------
    mu0 : array_like, shape (4,)
        Mean of the birth prior ``N(μ_0, P_0)`` (default 0, spec §7.2).
    P0 : array_like, shape (4, 4)
        Its covariance, symmetric positive definite (default
        ``diag(1000², 50², 1000², 50²)``, spec §7.2).
    tau_rU : float
        Only measurements with ``r_U > tau_rU`` make births (default 0.9, spec §4.1).
    n_min : int
        Minimum number of detecting sensors of a birth tuple (default 2, spec §8 Q2). With
        fewer sensors than ``n_min`` the filter uses ``min(n_min, V)``: one sensor births
        from single measurements (Reuter's single-sensor adaptive birth).
    r_b_max : float
        Cap on a birth's existence probability, in ``(0, 1]`` (default 0.03, spec §7.2).
    lambda_b : float
        Expected births per scan scaling the normalised ``ρ`` (default 1, spec §7.2).
    max_births : int
        At most this many births per scan, those of largest ``ρ`` (default 100).
    sampler : {"short", "long"}
        Short chains (:func:`rankedassign.sample_short_chains`, default) or one long chain of
        ``n_chains × chain_length`` sweeps (:func:`rankedassign.sample_original`).
    n_chains, chain_length : int
        Short-chain budget (default 40 × 25: the 1 000 sweeps of spec §4.3).
    tau_stall, tau_stale : int or None
        Stall and stale thresholds of the short chains (default 5 and 25, as the adaptive-birth
        study; None switches a rule off).
    sensor_order : {"random", "fixed"}
        Sensor order of a sweep (spec §4.3, Q8; default a fresh random permutation per sweep).
    backend : {"numba", "python"}
        Backend of the sampler; the births are identical.

    Attributes
    ----------
    mu0 : tuple of float
        Prior mean ``μ_0``, 4 floats (an array given is stored as a tuple, so that settings
        compare by value).
    P0 : tuple of tuple of float
        Prior covariance ``P_0``, 4 rows of 4 floats.
    tau_rU : float
        Threshold on ``r_U`` in ``[0, 1]``: only measurements with ``r_U > tau_rU`` make births.
    n_min : int
        Minimum detecting sensors of a birth tuple (``>= 1``; :meth:`effective_n_min` caps it
        at ``V``).
    r_b_max : float
        Cap on a birth's existence probability, in ``(0, 1]``.
    lambda_b : float
        Expected births per scan (``> 0``), scaling the normalised ``ρ``.
    max_births : int
        Most births kept per scan (``>= 1``), those of largest ``ρ``.
    sampler : {"short", "long"}
        Short chains or one long chain (:data:`AB_SAMPLERS`).
    n_chains, chain_length : int
        Number and length (sweeps) of the short chains; the long chain runs
        ``n_chains * chain_length`` sweeps.
    tau_stall, tau_stale : int or None
        Stall and stale thresholds of the short chains (None: the rule is off); not used by
        the long chain.
    sensor_order : {"random", "fixed"}
        Sensor order of a sweep.
    backend : {"numba", "python"}
        Backend of the sampler.

    Raises
    ------
    TypeError
        If a setting has the wrong type.
    ValueError
        If a setting is out of range or ``P0`` is not symmetric positive definite.

    Notes
    -----
    Randomness: the filter hands :meth:`births` the child stream of the scan's ``rng`` spawned
    after the association's children (``np.random.default_rng(rng).spawn(1)`` once they are
    drawn), so a run is reproducible from the filter's ``rng``.

    References
    ----------
    .. [1] A. Trezza, D. J. Bucci Jr., P. K. Varshney, "Multi-sensor joint adaptive birth
       sampler for labeled random finite set tracking", IEEE Trans. Signal Process. 70, 2022.

    Examples
    --------
    >>> from rankedassign.tracking.multisensor.adaptive_birth import AdaptiveBirth
    >>> ab = AdaptiveBirth()
    >>> ab.tau_rU, ab.n_min, ab.r_b_max, ab.lambda_b, ab.P0[0][0], ab.P0[1][1]
    (0.9, 2, 0.03, 1.0, 1000000.0, 2500.0)
    """

    mu0: tuple = (0.0, 0.0, 0.0, 0.0)
    P0: tuple = ((1000.0 ** 2, 0.0, 0.0, 0.0), (0.0, 50.0 ** 2, 0.0, 0.0),
                 (0.0, 0.0, 1000.0 ** 2, 0.0), (0.0, 0.0, 0.0, 50.0 ** 2))
    tau_rU: float = 0.9
    n_min: int = 2
    r_b_max: float = 0.03
    lambda_b: float = 1.0
    max_births: int = 100
    sampler: str = "short"
    n_chains: int = 40
    chain_length: int = 25
    tau_stall: int | None = 5
    tau_stale: int | None = 25
    sensor_order: str = "random"
    backend: str = "numba"

    def __post_init__(self):
        s = object.__setattr__
        s(self, "mu0", _prior_mean(self.mu0))
        s(self, "P0", _prior_cov(self.P0))
        s(self, "tau_rU", check_real(self.tau_rU, "tau_rU", minimum=0.0, maximum=1.0))
        s(self, "n_min", check_int(self.n_min, "n_min", minimum=1))
        s(self, "r_b_max", check_real(self.r_b_max, "r_b_max", minimum=0.0,
                                      strict_minimum=True, maximum=1.0))
        s(self, "lambda_b", check_real(self.lambda_b, "lambda_b", minimum=0.0,
                                       strict_minimum=True))
        s(self, "max_births", check_int(self.max_births, "max_births", minimum=1))
        check_choice(self.sampler, "sampler", AB_SAMPLERS)
        s(self, "n_chains", check_int(self.n_chains, "n_chains", minimum=1))
        s(self, "chain_length", check_int(self.chain_length, "chain_length", minimum=1))
        s(self, "tau_stall", check_optional_int(self.tau_stall, "tau_stall"))
        s(self, "tau_stale", check_optional_int(self.tau_stale, "tau_stale"))
        check_choice(self.sensor_order, "sensor_order", SENSOR_ORDERS)
        check_choice(self.backend, "backend", ("numba", "python"))

    def effective_n_min(self, n_sensors: int) -> int:
        """``min(n_min, V)``: the detections a birth tuple needs with ``V`` sensors.

        Parameters
        ----------
        n_sensors : int
            Number of sensors ``V`` of the scan (``>= 1``).

        Returns
        -------
        int
            ``min(n_min, n_sensors)``, between 1 and ``n_min``.

        Raises
        ------
        TypeError
            If ``n_sensors`` is not an int (``bool`` included).
        ValueError
            If ``n_sensors`` is below 1.

        Examples
        --------
        >>> AdaptiveBirth().effective_n_min(1), AdaptiveBirth().effective_n_min(3)
        (1, 2)
        """
        return min(self.n_min, check_int(n_sensors, "n_sensors", minimum=1))

    def births(self, measurements, r_U, *, sensors, clutters, F, Q, rng,
               r_min: float = 0.0) -> BirthLMB:
        """The birth components made from one scan's measurements (steps 2–4 above).

        Parameters
        ----------
        measurements : sequence of V arrays, shape (M_v, 2)
            Position measurements of each sensor.
        r_U : sequence of V arrays, shape (M_v,)
            Probability that each measurement is not explained by a track, in ``[0, 1]``.
        sensors : sequence of V PositionSensor
            ``P_D`` and ``R`` of each sensor (``H`` picks the position).
        clutters : sequence of V PoissonClutter
            Clutter intensity ``κ_v`` of each sensor.
        F, Q : ndarray, shape (4, 4)
            Transition and process noise predicting the births to the next scan.
        rng
            Stream of the sampler (anything :func:`numpy.random.default_rng` accepts).
        r_min : float
            Drop births with ``r_B <= r_min`` (the filter passes its ``prune_track``).

        Returns
        -------
        BirthLMB
            Kept births in the sampler's discovery order (``tuples`` index the kept
            measurements of the problem, ``measurements`` the given ones, ``-1`` = missed).

        Examples
        --------
        >>> import numpy as np
        >>> from rankedassign.tracking import make_multisensor_model
        >>> m = make_multisensor_model((0, 1))
        >>> z = [np.array([[100.0, 200.0], [-700.0, 0.0]]), np.array([[110.0, 195.0]])]
        >>> b = AdaptiveBirth().births(z, [np.ones(2), np.ones(1)], sensors=m.sensors,
        ...                            clutters=m.clutters, F=m.motion.F, Q=m.motion.Q, rng=0)
        >>> b.measurements.tolist(), b.r.tolist(), b.means[0, [0, 2]].round(0).tolist()
        ([[0, 0]], [0.03], [103.0, 198.0])
        """
        V = len(measurements)
        n_min = self.effective_n_min(V)
        problem = AdaptiveBirthProblem.from_measurements(
            [np.asarray(z, dtype=np.float64).reshape(-1, np.asarray(s.H).shape[0])
             for z, s in zip(measurements, sensors, strict=True)],
            [np.clip(np.asarray(r, dtype=np.float64), 0.0, 1.0) for r in r_U],
            H=[np.asarray(s.H) for s in sensors], R=[np.asarray(s.R) for s in sensors],
            P_D=[float(s.p_d) for s in sensors],
            clutter_intensity=[float(c.intensity) for c in clutters],
            mu0=np.asarray(self.mu0), P0=np.asarray(self.P0), tau_rU=self.tau_rU, n_min=n_min,
        )
        if sum(1 for m in problem.n_meas if m > 0) < n_min:
            return empty_birth()          # no tuple can reach n_min detections: no births
        if self.sampler == "short":
            res = sample_short_chains(problem, self.n_chains, self.chain_length,
                                      tau_stall=self.tau_stall, tau_stale=self.tau_stale,
                                      rng=rng, backend=self.backend,
                                      sensor_order=self.sensor_order)
        else:
            res = sample_original(problem, self.n_chains * self.chain_length, rng=rng,
                                  backend=self.backend, sensor_order=self.sensor_order)
        b = birth_from_samples(problem, res, F=F, Q=Q, r_b_max=self.r_b_max,
                               lambda_b=self.lambda_b)
        keep = np.flatnonzero(b.r > r_min)
        if keep.size > self.max_births:
            # the max_births of largest ρ, then back in discovery order
            keep = np.sort(keep[np.argsort(-b.log_rho[keep], kind="stable")[:self.max_births]])
        return BirthLMB(*(np.asarray(a)[keep] for a in b))

"""Synthetic multi-sensor problems (multi-sensor spec §6.5) and the linear-Gaussian ``psibar``.

Canonical sizes (:data:`SIZES`): **A** ``P = 4, M = (4, 4)`` (``|Gamma| = 67 744``, closest to
the single-sensor 76 848), **B** ``P = 2, M = (16, 16)`` (75 108, clutter-rich), **C**
``P = 3, M = (4, 4, 4)`` (417 176). Every family except ``geometric`` is built from the
separable factors of spec §3.1, per row ``n`` with existence ``r_n``, survival ``P_s,n``,
per-sensor detection ``P_d,n^(v)`` and likelihood ratios ``q^(v)_nj``::

    s_n = r_n P_s,n                  eta_n(-1) = 1 - s_n
    theta_n^(v)(0) = 1 - Pbar_D      theta_n^(v)(j) = Pbar_D q^(v)_nj
    eta_n(t) = s_n prod_v theta_n^(v)(t[v]) c_n(t)

with ``Pbar_D = P_d`` (``pbar_d="pd"``, spec §6.5, the default) or ``r P_d`` (``"r_pd"``, the
single-sensor synthetic default, spec A2) and ``c = 1`` except in ``random_coupled``. With
``V = 1`` and the same ``pbar_d`` the families are the single-sensor ones of
:mod:`rankedassign.single.synthetic`.

Every family refuses, before drawing or building anything, a table ``(P, M_1+1, ..., M_V+1)``
of more than :data:`~rankedassign.multisensor.problem.MAX_TABLE_ENTRIES` ``= 2**27`` entries
(1 GiB) or more than 63 sensors (:func:`~rankedassign.multisensor.problem.check_table_size`).
"""

from __future__ import annotations

import itertools

import numpy as np
from scipy.linalg import solve_triangular
from scipy.special import logsumexp

from ..validation import check_choice, check_int, check_real
from .problem import MultiSensorProblem, check_table_size

__all__ = [
    "SIZES",
    "diagonal",
    "uniform",
    "random",
    "random_coupled",
    "geometric",
    "factors_from_parameters",
    "log_psi_linear_gaussian",
]

#: The canonical sizes of spec §6.5: name -> ``(P, (M_1, ..., M_V))``.
SIZES = {"A": (4, (4, 4)), "B": (2, (16, 16)), "C": (3, (4, 4, 4))}

_PBAR_D = ("pd", "r_pd")
_FORMS = ("information", "stacked")


def _check_sizes(P, M) -> tuple[int, tuple[int, ...]]:
    P = check_int(P, "P")
    if isinstance(M, (str, bytes)) or not hasattr(M, "__len__"):
        raise TypeError(f"M must be a sequence of measurement counts (M_1, ..., M_V), got "
                        f"{type(M).__name__} {M!r}")
    if len(M) == 0:
        raise ValueError("M must name at least one sensor, got an empty sequence")
    M = tuple(check_int(m, f"M[{v}]") for v, m in enumerate(M))
    check_table_size(P, M)  # before any factor, draw or table is made
    return P, M


def factors_from_parameters(r, p_s, p_d, q, *, pbar_d: str = "pd"):
    """Separable factors from existence, survival, detection and likelihood ratios.

    Parameters
    ----------
    r, p_s : array_like, shape (P,)
        Existence and survival probability of each row.
    p_d : array_like, shape (P, V)
        Detection probability of each row and sensor.
    q : sequence of V array_like, shape (P, M_v)
        Likelihood ratios ``q^(v)_nj = g^(v)(z_j | x, l_n) / kappa^(v)(z_j)``.
    pbar_d : {"pd", "r_pd"}
        ``Pbar_D = P_d`` (spec §6.5) or ``r P_d`` (spec A2).

    Returns
    -------
    eta_dead : ndarray, shape (P,)
        ``1 - r P_s``.
    s : ndarray, shape (P,)
        ``r P_s``.
    theta : list of V ndarrays, shape (P, M_v+1)
        ``[1 - Pbar_D | Pbar_D q^(v)]``.

    References
    ----------
    .. [1] B.-N. Vo, B.-T. Vo, M. Beard, "Multi-Sensor Multi-Object Tracking with the
       Generalized Labeled Multi-Bernoulli Filter", IEEE Trans. Signal Process. 67(23), 2019.
    .. [2] A. Trezza, D. J. Bucci Jr., P. K. Varshney, "On Gibbs Sampling Architecture for
       Labeled Random Finite Sets Multi-Object Tracking", arXiv:2306.15135, 2023.

    Examples
    --------
    >>> d, s, th = factors_from_parameters([0.99], [0.99], [[0.99]], [[[50.0]]])
    >>> round(float(d[0]), 4), round(float(s[0]), 4), th[0].round(4).tolist()
    (0.0199, 0.9801, [[0.01, 49.5]])
    """
    check_choice(pbar_d, "pbar_d", _PBAR_D)
    r = np.asarray(r, dtype=float)
    s = r * np.asarray(p_s, dtype=float)
    pd = np.asarray(p_d, dtype=float)
    if pbar_d == "r_pd":
        pd = r[:, None] * pd
    theta = []
    for v, qv in enumerate(q):
        qv = np.asarray(qv, dtype=float)
        th = np.empty((qv.shape[0], qv.shape[1] + 1))
        th[:, 0] = 1.0 - pd[:, v]
        th[:, 1:] = pd[:, v, None] * qv
        theta.append(th)
    return 1.0 - s, s, theta


def diagonal(P: int = 4, M=(4, 4), *, pbar_d: str = "pd") -> MultiSensorProblem:
    """The deterministic *diagonal* family: one dominant assignment.

    ``r = P_s = P_d = 0.99``; ``q^(v)_nj = 50`` if ``j = n`` (row ``n``'s own measurement is
    measurement ``n`` of every sensor, 1-based) and ``1e-3`` otherwise; ``c = 1``.

    Parameters
    ----------
    P : int
        Rows.
    M : sequence of int
        ``(M_1, ..., M_V)``.
    pbar_d : {"pd", "r_pd"}
        Definition of ``Pbar_D``.

    Returns
    -------
    MultiSensorProblem
        With separable factors.

    References
    ----------
    .. [1] B.-N. Vo, B.-T. Vo, M. Beard, "Multi-Sensor Multi-Object Tracking with the
       Generalized Labeled Multi-Bernoulli Filter", IEEE Trans. Signal Process. 67(23), 2019.
    .. [2] A. Trezza, D. J. Bucci Jr., P. K. Varshney, "On Gibbs Sampling Architecture for
       Labeled Random Finite Sets Multi-Object Tracking", arXiv:2306.15135, 2023.

    Examples
    --------
    >>> from rankedassign.multisensor import synthetic
    >>> p = synthetic.diagonal()
    >>> p.shape, p.n_feasible()
    ((4, 4, 4), 67744)
    >>> best = [[1, 1], [2, 2], [3, 3], [4, 4]]
    >>> round(float(p.log_weight_of(best)), 4)
    31.1354
    """
    P, M = _check_sizes(P, M)
    V = len(M)
    q = []
    for m in M:
        qv = np.full((P, m), 1e-3)
        k = min(P, m)
        qv[np.arange(k), np.arange(k)] = 50.0
        q.append(qv)
    v = np.full(P, 0.99)
    d, s, th = factors_from_parameters(v, v, np.full((P, V), 0.99), q, pbar_d=pbar_d)
    return MultiSensorProblem.from_factors(d, s, th)


def uniform(P: int = 4, M=(4, 4)) -> MultiSensorProblem:
    """The deterministic *uniform* family: every weight ``e^-0.5``, ``pi`` uniform on ``Gamma``.

    For MM-Gibbs the factors are ``theta = 1`` and ``s_n = e^-0.5`` (spec §6.5).

    Parameters
    ----------
    P : int
    M : sequence of int

    Returns
    -------
    MultiSensorProblem

    References
    ----------
    .. [1] B.-N. Vo, B.-T. Vo, M. Beard, "Multi-Sensor Multi-Object Tracking with the
       Generalized Labeled Multi-Bernoulli Filter", IEEE Trans. Signal Process. 67(23), 2019.
    .. [2] A. Trezza, D. J. Bucci Jr., P. K. Varshney, "On Gibbs Sampling Architecture for
       Labeled Random Finite Sets Multi-Object Tracking", arXiv:2306.15135, 2023.

    Examples
    --------
    >>> from rankedassign.multisensor import synthetic
    >>> p = synthetic.uniform(3, (4, 4, 4))
    >>> p.n_feasible(), float(p.log_eta_alive.max()), float(p.log_eta_dead.min())
    (417176, -0.5, -0.5)
    """
    P, M = _check_sizes(P, M)
    e = np.full(P, np.exp(-0.5))
    return MultiSensorProblem.from_factors(e, e, [np.ones((P, m + 1)) for m in M])


def _random_parameters(gen, P, M):
    # draw order (fixed): r (P), P_s (P), P_d (P x V, row-major), q^(v) (P x M_v) per sensor
    r = gen.uniform(1e-3, 1.0, size=P)
    p_s = gen.uniform(1e-3, 1.0, size=P)
    p_d = gen.uniform(1e-3, 1.0, size=(P, len(M)))
    q = [gen.uniform(0.0, 50.0, size=(P, m)) for m in M]
    return r, p_s, p_d, q


def random(P: int = 4, M=(4, 4), *, pbar_d: str = "pd", rng=None) -> MultiSensorProblem:
    """The *random* family: separable, so the MM surrogate equals the target (``pi~ = pi``).

    ``r_n, P_s,n ~ U[1e-3, 1]`` per row, ``P_d ~ U[1e-3, 1]`` per row and sensor,
    ``q ~ U[0, 50]`` per entry, ``c = 1``.

    Parameters
    ----------
    P : int
    M : sequence of int
    pbar_d : {"pd", "r_pd"}
    rng : None, int, SeedSequence or Generator
        Anything :func:`numpy.random.default_rng` accepts.

    Returns
    -------
    MultiSensorProblem

    Notes
    -----
    Draw order (fixed, so a seed always gives the same problem): ``r`` (P), ``P_s`` (P),
    ``P_d`` (P x V, row-major), then ``q^(v)`` (P x M_v, row-major) sensor by sensor. With
    ``V = 1`` these are the draws of :func:`rankedassign.single.synthetic.random` with
    ``granularity="row"``.

    References
    ----------
    .. [1] B.-N. Vo, B.-T. Vo, M. Beard, "Multi-Sensor Multi-Object Tracking with the
       Generalized Labeled Multi-Bernoulli Filter", IEEE Trans. Signal Process. 67(23), 2019.
    .. [2] A. Trezza, D. J. Bucci Jr., P. K. Varshney, "On Gibbs Sampling Architecture for
       Labeled Random Finite Sets Multi-Object Tracking", arXiv:2306.15135, 2023.

    Examples
    --------
    >>> from rankedassign.multisensor import synthetic
    >>> a, b = synthetic.random(rng=1), synthetic.random(rng=1)
    >>> a == b, a.shape
    (True, (4, 4, 4))
    """
    P, M = _check_sizes(P, M)
    check_choice(pbar_d, "pbar_d", _PBAR_D)
    gen = np.random.default_rng(rng)
    d, s, th = factors_from_parameters(*_random_parameters(gen, P, M), pbar_d=pbar_d)
    return MultiSensorProblem.from_factors(d, s, th)


def random_coupled(P: int = 4, M=(4, 4), *, sigma: float = 1.0, pbar_d: str = "pd",
                   rng=None) -> MultiSensorProblem:
    """The *random-coupled* family: :func:`random` times a coupling that breaks separability.

    ``c_n(t) = exp(sigma eps_{n,t})`` with ``eps ~ N(0, 1)`` i.i.d. for tuples detected by at
    least two sensors, ``c_n(t) = 1`` otherwise (spec §6.5). It discriminates the exact
    sampler from MM-Gibbs, whose surrogate ignores ``c``.

    Parameters
    ----------
    P : int
    M : sequence of int
    sigma : float
        Coupling strength, ``>= 0`` (``0`` gives :func:`random` with the same ``rng``).
    pbar_d : {"pd", "r_pd"}
    rng : None, int, SeedSequence or Generator

    Returns
    -------
    MultiSensorProblem
        With separable factors (the surrogate's) and the coupled weights.

    Notes
    -----
    The draws of :func:`random` come first, then ``eps`` for the whole table
    ``(P, prod_v (M_v+1))`` in C order (entries with fewer than two detections are drawn and
    ignored).

    References
    ----------
    .. [1] B.-N. Vo, B.-T. Vo, M. Beard, "Multi-Sensor Multi-Object Tracking with the
       Generalized Labeled Multi-Bernoulli Filter", IEEE Trans. Signal Process. 67(23), 2019.
    .. [2] A. Trezza, D. J. Bucci Jr., P. K. Varshney, "On Gibbs Sampling Architecture for
       Labeled Random Finite Sets Multi-Object Tracking", arXiv:2306.15135, 2023.

    Examples
    --------
    >>> from rankedassign.multisensor import synthetic
    >>> synthetic.random_coupled(sigma=0.0, rng=3) == synthetic.random(rng=3)
    True
    """
    P, M = _check_sizes(P, M)
    check_choice(pbar_d, "pbar_d", _PBAR_D)
    sigma = check_real(sigma, "sigma", minimum=0.0)
    gen = np.random.default_rng(rng)
    d, s, th = factors_from_parameters(*_random_parameters(gen, P, M), pbar_d=pbar_d)
    dims = tuple(m + 1 for m in M)
    eps = gen.standard_normal(size=(P, *dims))
    n_det = sum(np.indices(dims)[v] > 0 for v in range(len(M)))
    c = np.where(n_det[None] >= 2, np.exp(sigma * eps), 1.0)
    return MultiSensorProblem.from_factors(d, s, th, coupling=c)


def _per_sensor(x, V: int, name: str) -> np.ndarray:
    a = np.asarray(x, dtype=float)
    if a.ndim == 0:
        a = np.full(V, float(a))
    if a.shape != (V,):
        raise ValueError(f"{name} must be a scalar or have shape (V,) = ({V},), got {a.shape}")
    return a


def geometric(P: int = 4, M=(4, 4), *, region: float = 100.0, sigma_p: float = 5.0,
              sigma_z=2.0, p_d=0.9, pbar_s: float = 0.9, kappa=1e-3,
              rng=None) -> MultiSensorProblem:
    """The *geometric* family: a common 2-D state couples the sensors (spec §6.5).

    Track ``n`` has prior ``N(m_n, sigma_p^2 I)`` with ``m_n`` uniform in
    ``[0, region]^2``; its true position is drawn from that prior. Every sensor measures
    position (``H = I``, ``R_v = sigma_z[v]^2 I``): measurement ``j <= min(P, M_v)`` of sensor
    ``v`` is track ``j``'s position plus noise, the rest are clutter uniform in the region,
    with clutter intensity ``kappa[v]``. ``eta_n(-1) = 1 - pbar_s`` and
    ``eta_n(t) = pbar_s psibar_n(t)`` by the linear-Gaussian closed form (spec eq. 1.5/1.6,
    :func:`log_psi_linear_gaussian`); the separable factors are the single-sensor ``psibar``
    of each sensor (spec eq. 3.1), so ``pi~ != pi``.

    Parameters
    ----------
    P : int
    M : sequence of int
    region : float
        Side of the square region, ``> 0``.
    sigma_p : float
        Prior position standard deviation, ``> 0``.
    sigma_z : float or sequence of V floats
        Measurement noise standard deviation per sensor, ``> 0``.
    p_d : float or sequence of V floats
        Detection probability per sensor, in ``[0, 1]``.
    pbar_s : float
        ``s_n`` of every row, in ``[0, 1]``.
    kappa : float or sequence of V floats
        Clutter intensity per sensor (per unit area), ``> 0``.
    rng : None, int, SeedSequence or Generator

    Returns
    -------
    MultiSensorProblem
        With separable factors.

    Notes
    -----
    Draw order: prior means (P x 2), true positions' offsets (P x 2), then per sensor the
    detection noise (min(P, M_v) x 2) and the clutter positions ((M_v - min(P, M_v)) x 2).

    References
    ----------
    .. [1] B.-N. Vo, B.-T. Vo, M. Beard, "Multi-Sensor Multi-Object Tracking with the
       Generalized Labeled Multi-Bernoulli Filter", IEEE Trans. Signal Process. 67(23), 2019.
    .. [2] A. Trezza, D. J. Bucci Jr., P. K. Varshney, "On Gibbs Sampling Architecture for
       Labeled Random Finite Sets Multi-Object Tracking", arXiv:2306.15135, 2023.

    Examples
    --------
    >>> from rankedassign.multisensor import synthetic
    >>> p = synthetic.geometric(rng=0)
    >>> p.shape, p.log_s is not None
    ((4, 4, 4), True)
    >>> bool((p.surrogate().log_eta_alive != p.log_eta_alive).any())    # not separable
    True
    """
    P, M = _check_sizes(P, M)
    V = len(M)
    region = check_real(region, "region", minimum=0.0, strict_minimum=True)
    sigma_p = check_real(sigma_p, "sigma_p", minimum=0.0, strict_minimum=True)
    pbar_s = check_real(pbar_s, "pbar_s", minimum=0.0, maximum=1.0)
    sz = _per_sensor(sigma_z, V, "sigma_z")
    pd = _per_sensor(p_d, V, "p_d")
    kp = _per_sensor(kappa, V, "kappa")
    if not (sz > 0).all():
        raise ValueError(f"sigma_z must be > 0, got {sz.tolist()}")
    if not ((pd >= 0) & (pd <= 1)).all():
        raise ValueError(f"p_d must lie in [0, 1], got {pd.tolist()}")
    if not (kp > 0).all():
        raise ValueError(f"kappa must be > 0, got {kp.tolist()}")
    gen = np.random.default_rng(rng)
    means = gen.uniform(0.0, region, size=(P, 2))
    truth = means + sigma_p * gen.standard_normal(size=(P, 2))
    Z = []
    for v, m in enumerate(M):
        k = min(P, m)
        det = truth[:k] + sz[v] * gen.standard_normal(size=(k, 2))
        clutter = gen.uniform(0.0, region, size=(m - k, 2))
        Z.append(np.vstack([det, clutter]))
    H = [np.eye(2)] * V
    R = [np.eye(2) * sz[v] ** 2 for v in range(V)]
    cov = np.eye(2) * sigma_p**2
    log_alive = np.empty((P, *(m + 1 for m in M)))
    log_theta = [np.empty((P, m + 1)) for m in M]
    for n in range(P):
        w, mu, c = np.ones(1), means[n][None], cov[None]
        log_alive[n] = np.log(pbar_s) + log_psi_linear_gaussian(w, mu, c, Z, H, R, pd, kp)
        for v in range(V):
            log_theta[v][n] = log_psi_linear_gaussian(w, mu, c, [Z[v]], [H[v]], [R[v]],
                                                      pd[v:v + 1], kp[v:v + 1])
    with np.errstate(divide="ignore"):
        log_dead = np.full(P, np.log1p(-pbar_s))
        log_s = np.full(P, np.log(pbar_s))
    return MultiSensorProblem(log_dead, log_alive, log_s, log_theta)


def _check_gaussian_inputs(weights, means, covs, Z, H, R, p_d, kappa):
    w = np.asarray(weights, dtype=float).reshape(-1)
    mu = np.asarray(means, dtype=float)
    P0 = np.asarray(covs, dtype=float)
    K = w.shape[0]
    if mu.ndim != 2 or mu.shape[0] != K or P0.shape != (K, mu.shape[1], mu.shape[1]):
        raise ValueError(
            f"means must have shape (K, n) and covs (K, n, n) with K = {K} weights, got "
            f"{mu.shape} and {P0.shape}"
        )
    V = len(Z)
    if len(H) != V or len(R) != V:
        raise ValueError(f"Z, H and R must hold one entry per sensor, got {V}, {len(H)}, "
                         f"{len(R)}")
    nx = mu.shape[1]
    Zs, Hs, Rs, kps = [], [], [], []
    for v in range(V):
        h = np.asarray(H[v], dtype=float)
        r = np.asarray(R[v], dtype=float)
        if h.ndim != 2 or h.shape[1] != nx or r.shape != (h.shape[0], h.shape[0]):
            raise ValueError(
                f"sensor {v}: H must have shape (d, {nx}) and R (d, d), got {h.shape} and "
                f"{r.shape}"
            )
        z = np.asarray(Z[v], dtype=float)
        if z.size == 0:
            z = z.reshape(0, h.shape[0])
        if z.ndim != 2 or z.shape[1] != h.shape[0]:
            raise ValueError(
                f"sensor {v}: Z must have shape (M, d) = (M, {h.shape[0]}), got {z.shape}"
            )
        Zs.append(z)
        Hs.append(h)
        Rs.append(r)
        kps.append(np.broadcast_to(np.asarray(kappa[v], dtype=float), (z.shape[0],)))
    pd = np.asarray(p_d, dtype=float).reshape(V)
    return w, mu, P0, Zs, Hs, Rs, pd, kps


def log_psi_linear_gaussian(weights, means, covs, Z, H, R, p_d, kappa, *,
                            form: str = "information") -> np.ndarray:
    """``ln psibar(t)`` of one row for every tuple, linear-Gaussian closed form.

    Prior ``sum_k w_k N(x; m_k, P_k)``, sensor ``v``: ``g(z | x) = N(z; H_v x, R_v)``,
    constant ``P_D^(v)``, clutter intensity ``kappa^(v)(z)``.

    Parameters
    ----------
    weights : array_like, shape (K,)
    means : array_like, shape (K, n)
    covs : array_like, shape (K, n, n)
    Z : sequence of V array_like, shape (M_v, d_v)
        Measurements of each sensor.
    H : sequence of V array_like, shape (d_v, n)
    R : sequence of V array_like, shape (d_v, d_v)
    p_d : array_like, shape (V,)
    kappa : sequence of V scalars or (M_v,) arrays
        Clutter intensity at each measurement.
    form : {"information", "stacked"}
        Spec eq. (1.6): one factorisation of ``M_D = P^-1 + sum_{v in D} H_v' R_v^-1 H_v``
        per detection pattern ``D``, every tuple of the pattern by broadcasting (default); or
        spec eq. (1.5): the stacked innovation ``N(z_D; H_D m, H_D P H_D' + R_D)`` tuple by
        tuple (the specification the information form is tested against).

    Returns
    -------
    ndarray, shape (M_1+1, ..., M_V+1)
        ``ln psibar(t) = ln(Pi_miss Pi_det sum_k w_k N(z_D; H_D m_k, H_D P_k H_D' + R_D))``
        with ``Pi_miss = prod_{v not in D} (1 - P_D^(v))`` and
        ``Pi_det = prod_{v in D} P_D^(v) / kappa^(v)(z_{t[v]})``; the all-missed tuple gets
        ``ln(Pi_miss sum_k w_k)``.

    References
    ----------
    .. [1] B.-N. Vo, B.-T. Vo, M. Beard, "Multi-Sensor Multi-Object Tracking with the
       Generalized Labeled Multi-Bernoulli Filter", IEEE Trans. Signal Process. 67(23), 2019.
    .. [2] A. Trezza, D. J. Bucci Jr., P. K. Varshney, "On Gibbs Sampling Architecture for
       Labeled Random Finite Sets Multi-Object Tracking", arXiv:2306.15135, 2023.

    Examples
    --------
    >>> import numpy as np
    >>> args = ([1.0], [[0.0]], [[[1.0]]], [[[0.5]], [[-0.5]]], [[[1.0]]] * 2,
    ...         [[[1.0]]] * 2, [0.9, 0.8], [0.1, 0.1])
    >>> a = log_psi_linear_gaussian(*args)
    >>> b = log_psi_linear_gaussian(*args, form="stacked")
    >>> a.shape, bool(np.allclose(a, b, rtol=1e-12))
    ((2, 2), True)
    >>> round(float(np.exp(a[0, 0])), 6)          # (1 - 0.9)(1 - 0.8)
    0.02
    """
    check_choice(form, "form", _FORMS)
    w, mu, P0, Z, H, R, pd, kp = _check_gaussian_inputs(weights, means, covs, Z, H, R, p_d,
                                                        kappa)
    V = len(Z)
    dims = tuple(z.shape[0] + 1 for z in Z)
    with np.errstate(divide="ignore"):
        log_w = np.log(w)
        log_miss = np.log1p(-pd)
        log_det = [np.log(pd[v]) - np.log(kp[v]) for v in range(V)]
    out = np.empty(dims)
    if form == "stacked":
        for t in itertools.product(*(range(d) for d in dims)):
            D = [v for v in range(V) if t[v] > 0]
            val = sum(log_miss[v] for v in range(V) if t[v] == 0) + \
                sum(log_det[v][t[v] - 1] for v in D)
            if D:
                z = np.concatenate([Z[v][t[v] - 1] for v in D])
                HD = np.vstack([H[v] for v in D])
                RD = _blkdiag([R[v] for v in D])
                terms = [log_w[k] + _log_normal(z, HD @ mu[k], HD @ P0[k] @ HD.T + RD)
                         for k in range(len(w))]
                val = val + logsumexp(terms)
            else:
                val = val + logsumexp(log_w)
            out[t] = val
        return out
    # information form (spec eq. 1.6), one pattern D at a time
    Pinv = np.linalg.inv(P0)
    _, logdetP = np.linalg.slogdet(P0)
    Rinv = [np.linalg.inv(r) for r in R]
    consts = [-0.5 * (r.shape[0] * np.log(2 * np.pi) + np.linalg.slogdet(r)[1]) for r in R]
    # a sensor without measurements cannot detect: patterns that use it have an empty block
    # (they were skipped), so they are not generated (2**V of them with many such sensors)
    choices = [(False, True) if dims[v] > 1 else (False,) for v in range(V)]
    for pattern in itertools.product(*choices):
        D = [v for v in range(V) if pattern[v]]
        idx = tuple(slice(1, None) if pattern[v] else 0 for v in range(V))
        block_shape = tuple(dims[v] - 1 for v in D)
        base = sum(log_miss[v] for v in range(V) if not pattern[v]) + np.zeros(block_shape)
        for i, v in enumerate(D):
            base = base + _along(log_det[v], i, len(D))
        if not D:
            out[idx] = base + logsumexp(log_w)
            continue
        if 0 in block_shape:
            continue
        terms = []
        for k in range(len(w)):
            MD = Pinv[k] + sum(H[v].T @ Rinv[v] @ H[v] for v in D)
            b = Pinv[k] @ mu[k]
            c = mu[k] @ Pinv[k] @ mu[k]
            for i, v in enumerate(D):
                u = Z[v] @ Rinv[v] @ H[v]                       # (M_v, n): H' R^-1 z_j
                q = np.einsum("ij,jk,ik->i", Z[v], Rinv[v], Z[v])   # z_j' R^-1 z_j
                b = b + _along(u, i, len(D), trailing=1)
                c = c + _along(q, i, len(D))
            L = np.linalg.cholesky(MD)
            # b' M_D^-1 b = |L^-1 b|^2 with M_D = L L'
            y = solve_triangular(L, b.reshape(-1, b.shape[-1]).T, lower=True)
            quad = (y**2).sum(axis=0).reshape(block_shape)
            logdetM = 2.0 * np.log(np.diag(L)).sum()
            val = (-0.5 * logdetP[k] - 0.5 * logdetM + sum(consts[v] for v in D)
                   - 0.5 * (c - quad))
            terms.append(log_w[k] + val)
        out[idx] = base + logsumexp(np.stack(terms), axis=0)
    return out


def _along(a: np.ndarray, i: int, n: int, trailing: int = 0) -> np.ndarray:
    """``a`` (first axis of length M) reshaped to lie along axis ``i`` of ``n`` axes."""
    shape = [1] * n + list(a.shape[1:]) if trailing else [1] * n
    shape[i] = a.shape[0]
    return a.reshape(shape)


def _blkdiag(blocks) -> np.ndarray:
    n = sum(b.shape[0] for b in blocks)
    out = np.zeros((n, n))
    i = 0
    for b in blocks:
        k = b.shape[0]
        out[i:i + k, i:i + k] = b
        i += k
    return out


def _log_normal(z: np.ndarray, mean: np.ndarray, cov: np.ndarray) -> float:
    L = np.linalg.cholesky(cov)
    y = np.linalg.solve(L, z - mean)
    return float(-0.5 * (z.size * np.log(2 * np.pi) + y @ y) - np.log(np.diag(L)).sum())

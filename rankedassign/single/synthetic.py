"""The paper's synthetic test matrices: diagonal, uniform and random (spec §1.6).

Every family returns an :class:`~rankedassign.single.problem.AssignmentProblem` with ``P = R + B``
rows (``R`` persisting labels first, then ``B`` newborn labels, spec A21) and ``M``
measurements; the paper's matrices are ``R = 4, B = 0, M = 16`` (shape ``4 x 24``).

Per row ``i`` (spec eq. 1.8), with existence ``r_i``, survival ``P_s`` and detection ``P_d``::

    Pbar_S = r_i * P_s            (persisting rows)      Pbar_S = r_i    (newborn rows)
    Pbar_D = r_i * P_d            (pbar_d="r_pd", the paper's literal definition, default)
    Pbar_D = P_d                  (pbar_d="pd", Vo's filters)
    eta_i(-1) = 1 - Pbar_S,   eta_i(0) = Pbar_S (1 - Pbar_D),   eta_i(j) = Pbar_S Pbar_D q_ij
"""

from __future__ import annotations

import numpy as np

from ..validation import check_choice, check_int, check_optional_int, float_array
from .problem import AssignmentProblem

__all__ = ["diagonal", "uniform", "random", "eta_from_parameters"]

_PBAR_D = ("r_pd", "pd")
_GRANULARITY = ("row", "matrix")

# Largest cost matrix (entries) the families build: 2**27 doubles are 1 GiB.
_MAX_ENTRIES = 2**27


def _check_sizes(R, B, M) -> tuple[int, int, int]:
    R = check_int(R, "R")
    B = check_int(B, "B")
    M = check_int(M, "M")
    P = R + B
    n = P * (M + 2 * P)
    if n > _MAX_ENTRIES:
        raise ValueError(
            f"R = {R}, B = {B}, M = {M} give a {P} x {M + 2 * P} cost matrix of {n} entries, "
            f"more than the {_MAX_ENTRIES} (2**27) these families build"
        )
    return R, B, M




def eta_from_parameters(r, p_s, p_d, q, *, n_persisting=None, pbar_d="r_pd"):
    """Per-row weights ``eta`` from existence, survival, detection and likelihood ratios.

    Parameters
    ----------
    r : array_like, shape (P,)
        Existence probability of each label (``r_B`` for newborn rows).
    p_s, p_d : array_like, shape (P,)
        Survival and detection probability of each row (``p_s`` is ignored for newborn rows).
    q : array_like, shape (P, M)
        Normalised likelihoods ``q_ij = g(z_j | x, l_i) / kappa(z_j)``.
    n_persisting : int, optional
        ``R``: rows ``0..R-1`` persist, the rest are newborn. Default: all persist.
    pbar_d : {"r_pd", "pd"}
        ``Pbar_D = r P_d`` (the paper's definition) or ``P_d`` (spec ambiguity A2).

    Returns
    -------
    eta_detect : ndarray, shape (P, M)
    eta_missed, eta_dead : ndarray, shape (P,)

    Raises
    ------
    TypeError
        If an array is not numeric, ``n_persisting`` is not an int or ``pbar_d`` not a string.
    ValueError
        If a probability is outside ``[0, 1]``, ``q`` has a negative or non-finite entry, a
        shape does not match ``(P,)`` / ``(P, M)``, ``n_persisting`` is outside ``[0, P]`` or
        ``pbar_d`` is unknown.

    Examples
    --------
    >>> d, m, x = eta_from_parameters([0.99], [0.99], [0.99], [[50.0]])
    >>> round(float(x[0]), 4), round(float(m[0]), 6), round(float(d[0, 0]), 4)
    (0.0199, 0.019504, 48.0298)
    """
    check_choice(pbar_d, "pbar_d", _PBAR_D)
    r = float_array(r, "r", ndim=1, allow_nan=False)
    p_s = float_array(p_s, "p_s", ndim=1, allow_nan=False)
    p_d = float_array(p_d, "p_d", ndim=1, allow_nan=False)
    q = float_array(q, "q", ndim=2, allow_nan=False)
    P = r.shape[0]
    for name, a in (("p_s", p_s), ("p_d", p_d)):
        if a.shape != (P,):
            raise ValueError(f"{name} must have shape (P,) = ({P},) like r, got {a.shape}")
    if q.shape[0] != P:
        raise ValueError(f"q must have shape (P, M) with P = {P} rows like r, got {q.shape}")
    for name, a in (("r", r), ("p_s", p_s), ("p_d", p_d)):
        if a.size and not ((a >= 0) & (a <= 1)).all():
            bad = float(a[(a < 0) | (a > 1)][0])
            raise ValueError(f"{name} must hold probabilities in [0, 1], got {bad}")
    if q.size and not (np.isfinite(q) & (q >= 0)).all():
        bad = float(q[~(np.isfinite(q) & (q >= 0))][0])
        raise ValueError(f"q must hold finite likelihood ratios >= 0, got {bad}")
    R = check_optional_int(n_persisting, "n_persisting", minimum=0, maximum=P,
                           none_means="every row persists")
    R = P if R is None else R
    pbar_s = r.copy()
    pbar_s[:R] = r[:R] * p_s[:R]
    pbar_dd = r * p_d if pbar_d == "r_pd" else p_d.copy()
    eta_dead = 1.0 - pbar_s
    eta_missed = pbar_s * (1.0 - pbar_dd)
    eta_detect = (pbar_s * pbar_dd)[:, None] * q
    return eta_detect, eta_missed, eta_dead


def diagonal(R: int = 4, B: int = 0, M: int = 16, *, pbar_d: str = "r_pd") -> AssignmentProblem:
    """The paper's deterministic *diagonal* matrix: one dominant assignment.

    ``r = P_s = P_d = 0.99`` for every row; ``q_ii = 50`` (row ``i``'s own measurement is
    column ``i``, for ``i < min(P, M)``) and ``q_ij = 1e-3`` otherwise (spec §1.6, A4).

    Parameters
    ----------
    R, B, M : int
        Persisting rows, newborn rows (``r_B = 0.99``), measurements.
    pbar_d : {"r_pd", "pd"}
        Definition of ``Pbar_D`` (spec A2).

    Returns
    -------
    AssignmentProblem
        Shape ``(R + B, M + 2(R + B))``.

    Raises
    ------
    TypeError
        If ``R``, ``B`` or ``M`` is not an int.
    ValueError
        If one is negative, the matrix would exceed ``2**27`` entries or ``pbar_d`` is unknown.

    Examples
    --------
    >>> from rankedassign import synthetic
    >>> p = synthetic.diagonal()
    >>> p.shape, p.n_feasible()
    ((4, 24), 76848)
    >>> d, m, x = p.eta()
    >>> round(float(d[0, 0]), 4), round(float(d[0, 1]), 10), round(float(m[0]), 6)
    (48.0298, 0.0009606, 0.019504)
    """
    R, B, M = _check_sizes(R, B, M)
    check_choice(pbar_d, "pbar_d", _PBAR_D)
    P = R + B
    q = np.full((P, M), 1e-3)
    k = min(P, M)
    q[np.arange(k), np.arange(k)] = 50.0
    v = np.full(P, 0.99)
    eta = eta_from_parameters(v, v, v, q, n_persisting=R, pbar_d=pbar_d)
    return AssignmentProblem.from_eta(*eta)


def uniform(R: int = 4, B: int = 0, M: int = 16) -> AssignmentProblem:
    """The paper's deterministic *uniform* matrix: every feasible entry costs ``0.5``.

    Every feasible assignment then has the same weight ``exp(-0.5 P)``, so the target
    distribution is uniform on ``Gamma`` (76 848 points for ``4 x 24``; spec A3).

    Parameters
    ----------
    R, B, M : int
        Persisting rows, newborn rows, measurements (the rows do not differ here).

    Returns
    -------
    AssignmentProblem

    Raises
    ------
    TypeError
        If ``R``, ``B`` or ``M`` is not an int.
    ValueError
        If one is negative, the matrix would exceed ``2**27`` entries.

    Examples
    --------
    >>> from rankedassign import synthetic
    >>> p = synthetic.uniform()
    >>> float(p.cost[0, 0]), float(p.cost[0, 16]), float(p.cost[0, 17])
    (0.5, 0.5, inf)
    """
    R, B, M = _check_sizes(R, B, M)
    P = R + B
    return AssignmentProblem.from_cost(
        AssignmentProblem._assemble(np.full((P, M), 0.5), np.full(P, 0.5), np.full(P, 0.5))
    )


def random(
    R: int = 4,
    B: int = 0,
    M: int = 16,
    *,
    pbar_d: str = "r_pd",
    granularity: str = "row",
    rng=None,
) -> AssignmentProblem:
    """The paper's *random* matrix, re-drawn every Monte Carlo run.

    ``r_i ~ U[1e-3, 1]`` per row; ``P_s, P_d ~ U[1e-3, 1]`` per row (``granularity="row"``,
    the default, spec A5) or once per matrix (``"matrix"``); ``q_ij ~ U[0, 50]`` per entry.

    Parameters
    ----------
    R, B, M : int
        Persisting rows, newborn rows, measurements.
    pbar_d : {"r_pd", "pd"}
        Definition of ``Pbar_D`` (spec A2).
    granularity : {"row", "matrix"}
        Whether ``P_s`` and ``P_d`` are drawn per row or once per matrix.
    rng : None, int, SeedSequence or Generator
        Anything :func:`numpy.random.default_rng` accepts.

    Returns
    -------
    AssignmentProblem

    Raises
    ------
    TypeError
        If ``R``, ``B`` or ``M`` is not an int, or ``rng`` is not a valid seed type.
    ValueError
        If one is negative, the matrix would exceed ``2**27`` entries, an option is unknown
        or the seed is negative.

    Notes
    -----
    Draw order (fixed, so a seed always gives the same matrix): ``r`` (P values), then
    ``P_s`` and ``P_d`` (P values each, or one each), then ``q`` (P x M, row-major).

    Examples
    --------
    >>> from rankedassign import synthetic
    >>> a = synthetic.random(rng=1)
    >>> b = synthetic.random(rng=1)
    >>> a == b, a.shape
    (True, (4, 24))
    """
    R, B, M = _check_sizes(R, B, M)
    check_choice(pbar_d, "pbar_d", _PBAR_D)
    check_choice(granularity, "granularity", _GRANULARITY)
    gen = _generator(rng)
    P = R + B
    r = gen.uniform(1e-3, 1.0, size=P)
    n = P if granularity == "row" else 1
    p_s = np.broadcast_to(gen.uniform(1e-3, 1.0, size=n), (P,))
    p_d = np.broadcast_to(gen.uniform(1e-3, 1.0, size=n), (P,))
    q = gen.uniform(0.0, 50.0, size=(P, M))
    return AssignmentProblem.from_eta(
        *eta_from_parameters(r, p_s, p_d, q, n_persisting=R, pbar_d=pbar_d)
    )


def _generator(rng) -> np.random.Generator:
    """``np.random.default_rng(rng)``, its errors made ``TypeError``/``ValueError`` naming rng."""
    if isinstance(rng, (bool, float, complex, str, bytes)):
        raise TypeError(
            f"rng must be None, an int, a SeedSequence, a BitGenerator or a Generator, got "
            f"{type(rng).__name__} {rng!r}"
        )
    try:
        return np.random.default_rng(rng)
    except TypeError as exc:
        raise TypeError(
            f"rng must be None, an int, a SeedSequence, a BitGenerator or a Generator, got "
            f"{type(rng).__name__}: {exc}"
        ) from None
    except ValueError as exc:
        raise ValueError(f"rng {rng!r} is not a valid seed: {exc}") from None

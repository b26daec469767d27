"""Exact ground truth for the adaptive-birth tuple target (spec ``multisensor.md`` §5, §6.1, §6.4).

The tuple space ``{0..M_1} x ... x {0..M_V}`` has no coupling constraint, so everything is
computed from the dense tensor of ``ln rho`` (:meth:`AdaptiveBirthProblem.log_weights`): the
normaliser, the per-sensor marginals, the truncation error of a set of tuples, and the exact
one-sweep transition matrix of the Gibbs sampler on tiny problems. The public functions of
:mod:`oracle` (``enumerate_assignments``, ``log_normalizer``, ``marginals``,
``truncation_error``) dispatch here for an :class:`AdaptiveBirthProblem`.
"""

from __future__ import annotations

import itertools
import math

import numpy as np
from scipy.special import logsumexp

from rankedassign.adaptive_birth import AdaptiveBirthProblem
from rankedassign.rows import unique_rows
from rankedassign.validation import check_choice, check_int, check_type

from .._result import Ranked, check_enumeration_size

__all__ = ["enumerate_assignments", "log_normalizer", "marginals", "truncation_error",
           "kept_mask", "transition_matrix"]


def _check(problem) -> AdaptiveBirthProblem:
    return check_type(problem, "problem", AdaptiveBirthProblem)


def _all_tuples(shape) -> np.ndarray:
    """Every tuple in C order (lexicographic, sensor 0 slowest), shape (N, V), int64."""
    return np.indices(shape).reshape(len(shape), -1).T.astype(np.int64)


def enumerate_assignments(problem, *, limit: int = 2_000_000) -> Ranked:
    """Every tuple of the problem with its cost ``-ln rho``, best first.

    Parameters
    ----------
    problem : AdaptiveBirthProblem
        The tuple target to enumerate.
    limit : int, optional
        Refuse when the tuple space holds more than this many tuples. The enumeration takes
        ``8 (3 V + 3)`` bytes per tuple: more than
        :data:`~rankedassign.validation.MAX_WORK_BYTES` (4 GiB) is refused as well.

    Returns
    -------
    Ranked
        ``assignments`` (N, V) int64 tuples, ``costs`` (N,) sorted; ties stay in
        lexicographic order.

    Raises
    ------
    TypeError
        If ``problem`` is not an AdaptiveBirthProblem or ``limit`` not an int.
    ValueError
        If ``limit < 1``, the tuple space is larger than ``limit`` or would take more than
        :data:`~rankedassign.validation.MAX_WORK_BYTES` (the messages give the count and the
        bytes), or a tensor would have to be built beyond
        :meth:`~rankedassign.adaptive_birth.AdaptiveBirthProblem.log_weights`' limit.

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign.adaptive_birth import AdaptiveBirthProblem
    >>> from oracle import adaptive_birth
    >>> p = AdaptiveBirthProblem.from_log_weights(np.log([[1.0, 2.0], [3.0, 4.0]]))
    >>> adaptive_birth.enumerate_assignments(p).assignments.tolist()
    [[1, 1], [1, 0], [0, 1], [0, 0]]
    """
    _check(problem)
    limit = check_int(limit, "limit", minimum=1)
    # per tuple: the index grid and the tuples (16 V), the costs and the sort order (16), the
    # sorted tuples and costs (8 V + 8)
    V = problem.n_sensors
    check_enumeration_size(problem.n_feasible(), True, limit, 8 * (3 * V + 3),
                           f"tuples (M = {problem.n_meas})")
    costs = -problem.log_weights().reshape(-1)
    J = _all_tuples(problem.shape)
    order = np.argsort(costs, kind="stable")
    return Ranked(np.ascontiguousarray(J[order]), costs[order])


def log_normalizer(problem) -> float:
    """``ln sum_J rho(J)`` over the whole tuple space (the Gibbs target's normaliser).

    Parameters
    ----------
    problem : AdaptiveBirthProblem
        The tuple target; its dense tensor :meth:`~AdaptiveBirthProblem.log_weights` is
        built (or read) once.

    Returns
    -------
    float
        ``ln sum_J rho(J)``, computed with a log-sum-exp over the tensor; ``-inf`` never occurs
        (the all-missed tuple has a finite weight).

    Raises
    ------
    TypeError
        If ``problem`` is not an AdaptiveBirthProblem.
    ValueError
        If its tuple space is too large for the dense tensor.

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign.adaptive_birth import AdaptiveBirthProblem
    >>> from oracle import adaptive_birth
    >>> p = AdaptiveBirthProblem.from_log_weights(np.log([[1.0, 2.0], [3.0, 4.0]]))
    >>> round(float(np.exp(adaptive_birth.log_normalizer(p))), 12)
    10.0
    """
    _check(problem)
    return float(logsumexp(problem.log_weights()))


def marginals(problem) -> list:
    """Per-sensor marginals of ``pi_B``: entry ``v`` is ``P(j^(v) = j)``, shape (M_v + 1,).

    Parameters
    ----------
    problem : AdaptiveBirthProblem
        The tuple target; its dense tensor :meth:`~AdaptiveBirthProblem.log_weights` is
        built (or read) once.

    Returns
    -------
    list of V ndarray of float64, shape (M_v + 1,)
        Entry ``v``, index ``j``: the probability under ``pi_B = rho / sum rho`` that sensor
        ``v``'s component of the tuple is ``j`` (index 0: missed). Each sums to 1.

    Raises
    ------
    TypeError
        If ``problem`` is not an AdaptiveBirthProblem.
    ValueError
        If its tuple space is too large for the dense tensor.

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign.adaptive_birth import AdaptiveBirthProblem
    >>> from oracle import adaptive_birth
    >>> p = AdaptiveBirthProblem.from_log_weights(np.log([[1.0, 2.0], [3.0, 4.0]]))
    >>> [m.round(12).tolist() for m in adaptive_birth.marginals(p)]
    [[0.3, 0.7], [0.4, 0.6]]
    """
    _check(problem)
    lw = problem.log_weights()
    pi = np.exp(lw - logsumexp(lw))
    V = problem.n_sensors
    return [pi.sum(axis=tuple(u for u in range(V) if u != v)) for v in range(V)]


def kept_mask(problem) -> np.ndarray:
    """Boolean tensor of the birth tuples ``T* = {J : #det(J) >= max(n_min, 1)}`` (spec §5).

    Parameters
    ----------
    problem : AdaptiveBirthProblem
        The tuple target; only its shape and ``n_min`` are used.

    Returns
    -------
    ndarray of bool, shape (M_1 + 1, ..., M_V + 1)
        True at every tuple detected by at least ``max(n_min, 1)`` sensors (the all-missed
        tuple is never a birth).

    Raises
    ------
    TypeError
        If ``problem`` is not an AdaptiveBirthProblem.

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign.adaptive_birth import AdaptiveBirthProblem
    >>> from oracle import adaptive_birth
    >>> p = AdaptiveBirthProblem.from_log_weights(np.zeros((2, 2)), n_min=1)
    >>> adaptive_birth.kept_mask(p).tolist()
    [[False, True], [True, True]]
    """
    _check(problem)
    J = _all_tuples(problem.shape)
    return ((J > 0).sum(axis=1) >= max(problem.n_min, 1)).reshape(problem.shape)


def truncation_error(problem, assignments) -> float:
    """``1 - sum_{J in U, J in T*} rho(J) / sum_{J in T*} rho(J)`` (spec §5, Q6).

    Parameters
    ----------
    problem : AdaptiveBirthProblem
        The tuple target; its weights and ``n_min`` define ``T*``.
    assignments : array_like of int, shape (k, V) or (V,)
        Tuples (for instance a sampler's ``assignments``). Duplicates count once; tuples
        outside ``T*`` (the all-missed start, fewer than ``n_min`` detections) are ignored,
        as a birth never comes from them.

    Returns
    -------
    float
        In ``[0, 1]`` (round-off clipped).

    Raises
    ------
    TypeError
        If ``problem`` is not an AdaptiveBirthProblem or the tuples are not integers.
    ValueError
        On a tuple out of range or of the wrong shape, or if ``T*`` has zero weight.

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign.adaptive_birth import AdaptiveBirthProblem
    >>> from oracle import adaptive_birth
    >>> p = AdaptiveBirthProblem.from_log_weights(np.log([[1.0, 2.0], [3.0, 4.0]]), n_min=1)
    >>> round(adaptive_birth.truncation_error(p, [[0, 0], [1, 1], [1, 1]]), 12)   # 1 - 4/9
    0.555555555556
    """
    _check(problem)
    J, _ = problem._as_tuples(assignments, "assignments")
    lw = problem.log_weights()
    mask = kept_mask(problem)
    if not mask.any() or not np.isfinite(lw[mask]).any():
        raise ValueError("the birth tuples T* (>= max(n_min, 1) detections) have zero weight: "
                         "the truncation error is undefined")
    log_ref = logsumexp(lw[mask])
    J = unique_rows(J)
    J = J[(J > 0).sum(axis=1) >= max(problem.n_min, 1)]
    if J.shape[0] == 0:
        return 1.0
    err = float(-np.expm1(logsumexp(lw[tuple(J.T)]) - log_ref))
    return err if err > 0.0 else 0.0


def transition_matrix(problem, sensor_order: str = "random", *, limit: int = 2000):
    """Exact one-sweep transition matrix of the adaptive-birth Gibbs sampler (spec §6.4).

    Parameters
    ----------
    problem : AdaptiveBirthProblem
        A tiny tuple target (at most ``limit`` tuples).
    sensor_order : {"random", "fixed"}
        As the samplers' option: the average over all ``V!`` orders of the product of the
        per-sensor kernels, or ``K_0 K_1 ... K_{V-1}``.
    limit : int, optional
        Refuse tuple spaces larger than this.

    Returns
    -------
    K : ndarray, shape (N, N)
        ``K[a, b]`` = probability that one sweep moves tuple ``a`` to tuple ``b`` (tuples in
        C order of the tensor, as ``np.ravel_multi_index``).
    pi : ndarray, shape (N,)
        ``pi_B`` in the same order.

    Raises
    ------
    ValueError
        If the tuple space exceeds ``limit``.

    Notes
    -----
    ``K_s[a, b] = pi_B(b) / sum_{c : c^-s = a^-s} pi_B(c)`` if ``b^-s = a^-s``, else 0: the
    exact conditional of sensor ``s`` (spec eq. 4.3), from the tensor, independent of the
    samplers' ratio form. Each ``K_s`` leaves ``pi_B`` invariant, hence so does every product.
    A fiber of zero total weight (never reached from a positive-weight tuple) stays put.

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign.adaptive_birth import AdaptiveBirthProblem
    >>> from oracle import adaptive_birth
    >>> p = AdaptiveBirthProblem.from_log_weights(np.log([[1.0, 2.0], [3.0, 4.0]]))
    >>> K, pi = adaptive_birth.transition_matrix(p, "fixed")
    >>> bool(np.allclose(pi @ K, pi)), K.sum(axis=1).round(12).tolist()
    (True, [1.0, 1.0, 1.0, 1.0])
    """
    _check(problem)
    sensor_order = check_choice(sensor_order, "sensor_order", ("random", "fixed"))
    limit = check_int(limit, "limit", minimum=1)
    N = problem.n_feasible()
    if N > limit:
        raise ValueError(f"tuple space too large for a transition matrix: {N} > limit = "
                         f"{limit}")
    lw = problem.log_weights()
    pi = np.exp(lw - logsumexp(lw)).reshape(-1)
    shape = problem.shape
    V = len(shape)
    idx = np.arange(N).reshape(shape)
    kernels = []
    for s in range(V):
        Ks = np.zeros((N, N))
        lw_s = np.moveaxis(lw, s, -1)                   # (..., M_s + 1)
        id_s = np.moveaxis(idx, s, -1).reshape(-1, shape[s])
        with np.errstate(invalid="ignore"):
            cond = np.exp(lw_s - logsumexp(lw_s, axis=-1, keepdims=True)).reshape(-1, shape[s])
        for fiber, p in zip(id_s, cond, strict=True):
            if np.isfinite(p).all():
                Ks[np.ix_(fiber, fiber)] = p[None, :]
            else:
                Ks[fiber, fiber] = 1.0
        kernels.append(Ks)
    if sensor_order == "fixed":
        orders = [tuple(range(V))]
    else:
        orders = list(itertools.permutations(range(V)))
    K = np.zeros((N, N))
    for order in orders:
        prod = np.eye(N)
        for s in order:
            prod = prod @ kernels[s]
        K += prod
    K /= math.factorial(V) if sensor_order == "random" else 1
    return K, pi

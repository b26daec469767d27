"""Multi-sensor Gibbs samplers: preparation of the weights, start states and packaging.

Four row updates of the multi-sensor ranked-assignment target ``pi(gamma) ∝ 1_Gamma(gamma)
prod_n eta_n(gamma_n)`` (spec ``multisensor.md`` §1.3), selected by ``method``:

``"exact"``
    Vo, Vo & Beard (2019), Alg. 1 (spec §2): row ``n`` drawn from its exact conditional over
    dead and ``A_n^(1) x ... x A_n^(V)`` — leaves ``pi`` invariant. Cost per row update
    ``O(prod_v (M_v + 1))``.
``"mm"`` (default)
    MM-Gibbs, exclusion variant (spec §3.2-3.3): dead vs alive with the alive mass
    ``s_n^alpha prod_v sum_{j in A_n^(v)} theta_n^(v)(j)``, then each sensor's component
    independently ``∝ theta_n^(v)``. It is the exact Gibbs sampler of the surrogate
    ``pi~`` (spec §3.1; ``alpha = 1``, or ``s_n -> s_n^V`` for ``survival_power="V"``); on
    sensor-separable problems ``pi~ = pi``. Cost per row update ``O(sum_v M_v)``.
``"mm-fixed"``
    As ``"mm"`` with the dead probability ``Q_n`` computed once per call without exclusions
    (the public code's variant, spec §3.3); its stationary law has no closed form.
``"componentwise"``
    Sensor-component-wise Gibbs (spec §2.4) on the *collapsed* target ``pi'`` of spec §1.6:
    dead is merged into the all-missed tuple (weight ``eta_n(-1) + eta_n(0, ..., 0)``), and
    each (row, sensor) component is drawn from its exact conditional. Its states never hold a
    dead row: a returned row ``(0, ..., 0)`` stands for "dead or missed by every sensor", and
    its cost is ``-log`` of the collapsed weight, i.e. of the total ``pi``-mass of the
    ``2^k`` uncollapsed hypotheses it represents (``k`` rows at ``(0, ..., 0)``). Summing
    ``exp(-cost)`` over the unique set therefore gives the ``pi``-mass covered, as for the
    other methods, but the dead-versus-missed split of a row is not sampled.

Costs. Every method reports the exact ``-log w(gamma) = -sum_n log eta_n(gamma_n)`` (for
``"componentwise"`` with the collapsed weights), never the surrogate: the MM samplers are
truncation devices, not importance samplers (spec §3.4).

State encoding of the chains: a flat ``int32`` vector of length ``P * V``, position
``n * V + v`` holds ``gamma_n^(v) + 1`` (0 dead, 1 missed, ``j + 1`` measurement ``j``).

References
----------
.. [1] B.-N. Vo, B.-T. Vo, M. Beard, "Multi-Sensor Multi-Object Tracking with the Generalized
   Labeled Multi-Bernoulli Filter", IEEE Trans. Signal Process. 67(23):5952-5967, 2019.
.. [2] A. Trezza, D. J. Bucci Jr., P. K. Varshney, "On Gibbs Sampling Architecture for
   Labeled Random Finite Sets Multi-Object Tracking", arXiv:2306.15135, 2023.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ..engine.herding import INIT_CODES, KEY_CODES
from ..engine.kind import DrawInputs
from ..engine.records import HerdedDraw, record
from ..engine.result import Prepared
from ..engine.rng import base_key
from ..validation import check_choice
from .reference import HerdData, RefData

__all__ = [
    "METHODS",
    "STARTS",
    "prepare",
    "temper",
    "prepare_data",
    "start_state",
    "states_to_assignments",
    "assignment_costs",
    "herd_gate",
    "herd_inputs",
    "MultiSensorData",
    "MultiSensorHerdedData",
]

METHODS = ("exact", "mm", "mm-fixed", "componentwise")
METHOD_CODES = {"exact": 0, "mm": 1, "mm-fixed": 2, "componentwise": 3}
STARTS = ("all_missed", "all_dead")
SCANS = ("systematic", "random")
SURVIVAL_POWERS = (1, "V")


class MultiSensorData(NamedTuple):
    """The kernels' inputs of a multi-sensor sampler call (:func:`prepare_data`).

    Read by :func:`rankedassign.multisensor._kernels.sweep`; the reference reads the same
    values as lists (:class:`~rankedassign.multisensor.reference.RefData`). ``T = prod_v
    (M_v + 1)`` tuples, ``K = max_v M_v + 1``. Every shifted weight is ``exp(log - max)`` over
    the candidates of one row (0 where the log is ``-inf``); arrays a method does not read are
    placeholders of the same dtype and dimensions.

    Attributes
    ----------
    method : int
        The row conditional, ``METHOD_CODES`` (0 exact, 1 mm, 2 mm-fixed, 3 componentwise).
    random_scan : bool
        A fresh random row order every sweep, else ``0..P-1``.
    P, V : int
        Rows and sensors.
    n_meas : ndarray, shape (V,), int64
        ``M_v``.
    strides : ndarray, shape (V,), int64
        C-order strides of the tuple axes ``(M_1 + 1, ..., M_V + 1)``.
    Wd, ld : ndarray, shape (P,), float64
        Shifted weight and log-weight of dead.
    Wa, la : ndarray, shape (P, T), float64
        Shifted weight and ``log eta`` of every tuple (exact; componentwise: the collapsed
        weights); shape (P, 0) for the MM methods.
    Th, lth : ndarray, shape (P, V, K), float64
        Shifted and log ``theta_n^(v)(j)`` (MM methods; padding 0 and ``-inf``).
    las : ndarray, shape (P,), float64
        ``alpha log s_n`` (MM methods).
    Ea, Ed : ndarray, shape (P,), float64
        Shifted alive prefactor ``s_n^alpha prod_v max_j theta_n^(v)(j)`` and dead weight
        (MM's exclusion variant).
    qdead : ndarray, shape (P,), float64
        ``Q_n`` of MM-fixed.
    """

    method: np.int64
    random_scan: bool
    P: np.int64
    V: np.int64
    n_meas: np.ndarray
    strides: np.ndarray
    Wd: np.ndarray
    ld: np.ndarray
    Wa: np.ndarray
    la: np.ndarray
    Th: np.ndarray
    lth: np.ndarray
    las: np.ndarray
    Ea: np.ndarray
    Ed: np.ndarray
    qdead: np.ndarray


class MultiSensorHerdedData(record(MultiSensorData, {"gate": np.ndarray, "width": np.int64},
                                   HerdedDraw)):
    """The herded kernel's inputs (:func:`herd_inputs`): the fields of
    :class:`MultiSensorData`, then those of the herded draw.

    Read by :func:`rankedassign.multisensor._kernels.sweep_herded`; the reference's twin is
    :class:`~rankedassign.multisensor.reference.HerdData`. One flat record, so that the Gibbs
    kernel's phases read it as they read :class:`MultiSensorData`.

    Attributes
    ----------
    method, random_scan, P, V, n_meas, strides, Wd, ld, Wa, la, Th, lth, las, Ea, Ed, qdead
        As in :class:`MultiSensorData`.
    gate : ndarray, shape (P, V, K), bool
        Which measurements can carry weight for each row (:func:`herd_gate`).
    width : int
        Candidates of a key's weights (the widest herded draw).
    key_mode, init_mode, capacity, chain_length, tally
        As in :class:`~rankedassign.engine.records.HerdedDraw`.
    """


def _shape(problem):
    M = tuple(int(m) for m in problem.n_meas)
    shape = tuple(m + 1 for m in M)
    strides = [int(np.prod(shape[v + 1:], dtype=np.int64)) for v in range(len(shape))]
    return M, shape, strides


def _flat_log_alive(problem):
    """``log eta_n(t)`` as a new (P, T) float64 array, ``T = prod_v (M_v + 1)``."""
    _, shape, _ = _shape(problem)
    T = int(np.prod(shape, dtype=np.int64))
    return np.array(problem.log_eta_alive, dtype=np.float64).reshape(int(problem.n_rows), T)


def _collapsed_log_alive(problem):
    """``log eta'_n(t)`` of spec §1.6, shape (P, T): dead merged into the all-missed tuple."""
    la = _flat_log_alive(problem)
    with np.errstate(invalid="ignore"):
        la[:, 0] = np.logaddexp(np.asarray(problem.log_eta_dead, dtype=np.float64), la[:, 0])
    return la


def _shift(logs, axis):
    """``exp(logs - max)`` along ``axis`` (0 where ``logs`` is ``-inf``) and the max."""
    if logs.size == 0:
        return np.zeros(logs.shape), np.full(np.delete(logs.shape, axis), -np.inf)
    m = np.max(logs, axis=axis, keepdims=True)
    with np.errstate(invalid="ignore"):
        W = np.exp(logs - m)
    W[~np.isfinite(logs)] = 0.0
    return np.ascontiguousarray(W), np.squeeze(m, axis=axis)


def _check_method(method, problem, survival_power):
    check_choice(method, "method", METHODS)
    if survival_power not in SURVIVAL_POWERS or isinstance(survival_power, bool):
        raise ValueError(
            f"unknown survival_power {survival_power!r}; expected one of (1, 'V')"
        )
    if method in ("mm", "mm-fixed") and (problem.log_s is None or problem.log_theta is None):
        raise ValueError(
            f"method={method!r} needs the separable factors log_s and log_theta of the problem "
            "(spec §3.1), and this problem has none; use method='exact' or 'componentwise'"
        )


def prepare_data(problem, method, scan, survival_power=1):
    """The weights shared by the reference and the kernels, as the kernels' ``data`` tuple.

    Parameters
    ----------
    problem : MultiSensorProblem
        Uses ``n_rows``, ``n_sensors``, ``n_meas``, ``log_eta_dead``, ``log_eta_alive`` and,
        for the MM methods, ``log_s`` and ``log_theta``.
    method : {"exact", "mm", "mm-fixed", "componentwise"}
    scan : {"systematic", "random"}
    survival_power : {1, "V"}
        Exponent ``alpha`` of ``s_n`` in the MM alive mass (spec §3.3).

    Returns
    -------
    MultiSensorData
        Arrays float64 / int64, C-contiguous. Every shifted weight is ``exp(log - max)`` over
        the candidates of one row (``W = 0`` where the log is ``-inf``), so ``0 <= W <= 1``;
        each conditional is a ratio of one row's weights and does not change.

    Raises
    ------
    ValueError
        On an unknown method, scan or survival power, or an MM method on a problem without
        separable factors.

    Examples
    --------
    >>> import numpy as np
    >>> class Stub:
    ...     n_rows, n_sensors, n_meas = 1, 1, (1,)
    ...     log_eta_dead = np.log([0.5]); log_eta_alive = np.log([[0.25, 1.0]])
    ...     log_s = None; log_theta = None
    >>> data = prepare_data(Stub(), "exact", "systematic")
    >>> data.Wd.tolist(), data.Wa.tolist()
    ([0.5], [[0.25, 1.0]])
    """
    _check_method(method, problem, survival_power)
    check_choice(scan, "scan", SCANS)
    P, V = int(problem.n_rows), int(problem.n_sensors)
    M, shape, strides = _shape(problem)
    K = max(M) + 1 if V else 1
    ld = np.array(problem.log_eta_dead, dtype=np.float64).reshape(P)
    empty_p = np.zeros(P)
    Wd = empty_p
    Wa = la = np.zeros((P, 0))
    Th = np.zeros((P, V, K))
    lth = np.full((P, V, K), -np.inf)
    las = Ea = Ed = qdead = empty_p
    if method == "exact":
        la = _flat_log_alive(problem)
        W, _ = _shift(np.concatenate([ld[:, None], la], axis=1), axis=1)
        Wd, Wa = np.ascontiguousarray(W[:, 0]), np.ascontiguousarray(W[:, 1:])
    elif method == "componentwise":
        la = _collapsed_log_alive(problem)
        Wa, _ = _shift(la, axis=1)
    else:
        for v in range(V):
            lth[:, v, : M[v] + 1] = np.asarray(problem.log_theta[v], dtype=np.float64)
        Th, c = _shift(lth, axis=2)  # c[n, v] = max_j log theta_n^(v)(j)
        alpha = 1 if survival_power == 1 else V
        las = alpha * np.asarray(problem.log_s, dtype=np.float64).reshape(P)
        with np.errstate(invalid="ignore"):
            lalive = las + c.sum(axis=1)                       # log s^a + sum_v max_j log theta
            m = np.maximum(lalive, ld)
            Ea = np.nan_to_num(np.exp(lalive - m), nan=0.0)   # shifted s^a prod_v max theta
            Ed = np.nan_to_num(np.exp(ld - m), nan=0.0)       # shifted eta_n(-1)
            # Q_n of MM-fixed: every measurement counted, exclusions ignored (spec §3.3)
            with np.errstate(divide="ignore"):
                full = las + np.log(Th.sum(axis=2)).sum(axis=1) + c.sum(axis=1)
            qdead = np.nan_to_num(np.exp(ld - np.logaddexp(ld, full)), nan=1.0)
    c = np.ascontiguousarray
    return MultiSensorData(
        method=np.int64(METHOD_CODES[method]), random_scan=scan == "random", P=np.int64(P),
        V=np.int64(V), n_meas=np.array(M, dtype=np.int64),
        strides=np.array(strides, dtype=np.int64), Wd=c(Wd), ld=c(ld), Wa=c(Wa), la=c(la),
        Th=c(Th), lth=c(lth), las=c(las), Ea=c(Ea), Ed=c(Ed), qdead=c(qdead))


def start_state(problem, start, method):
    """Validate ``start`` and return the chain state, ``int32`` of length ``P * V``.

    Parameters
    ----------
    problem : MultiSensorProblem
    start : {"all_missed", "all_dead"} or array_like of int, shape (P, V)
        Every row ``(0, ..., 0)`` (the default of the samplers), every row dead, or an explicit
        feasible ``gamma`` (dead rows all ``-1``).
    method : str
        For ``"componentwise"`` dead rows become ``(0, ..., 0)``: the collapsed space has no
        dead row, so ``"all_dead"`` is the same state as ``"all_missed"`` there.

    Returns
    -------
    ndarray of int32, shape (P * V,)
        C-contiguous chain state: position ``n * V + v`` holds ``gamma_n^(v) + 1`` (0 dead,
        1 missed, ``j + 1`` measurement ``j``), of positive weight under the method's target
        (the collapsed weights for ``"componentwise"``).

    Raises
    ------
    TypeError
        If an explicit start is not an integer array.
    ValueError
        On an unknown name, a wrong shape, or an infeasible state (an index out of range, a
        row partly dead, a measurement used twice by one sensor, or zero weight).

    Examples
    --------
    >>> import numpy as np
    >>> class Stub:
    ...     n_rows, n_sensors, n_meas = 2, 2, (1, 1)
    ...     log_eta_dead = np.zeros(2); log_eta_alive = np.zeros((2, 2, 2))
    >>> start_state(Stub(), [[1, 0], [-1, -1]], "exact").tolist()
    [2, 1, 0, 0]
    """
    P, V = int(problem.n_rows), int(problem.n_sensors)
    M, shape, strides = _shape(problem)
    if isinstance(start, str):
        check_choice(start, "start", STARTS)
        gamma = np.zeros((P, V), dtype=np.int64) - (start == "all_dead")
    else:
        gamma = np.asarray(start)
        if gamma.dtype == bool or not np.issubdtype(gamma.dtype, np.integer):
            raise TypeError(
                "start must be 'all_missed', 'all_dead' or an integer array gamma of shape "
                f"(P, V), got dtype {gamma.dtype}"
            )
        if gamma.shape != (P, V):
            raise ValueError(f"start array must have shape (P, V) = ({P}, {V}), got "
                             f"{gamma.shape}")
        gamma = gamma.astype(np.int64)
        if (gamma < -1).any() or (gamma > np.array(M, dtype=np.int64)).any():
            raise ValueError(f"start {gamma.tolist()} has an index outside -1..M_v")
        partly = (gamma == -1).any(axis=1) & (gamma != -1).any(axis=1)
        if partly.any():
            raise ValueError(f"start rows {np.flatnonzero(partly).tolist()} are partly dead: a "
                             "dead row is -1 on every sensor")
        for v in range(V):
            used = gamma[:, v][gamma[:, v] > 0]
            if len(np.unique(used)) < len(used):
                raise ValueError(f"start {gamma.tolist()} uses a measurement of sensor {v} twice")
    if method == "componentwise":
        gamma = np.maximum(gamma, 0)
        lw = _row_log_weights(problem, gamma[None], collapsed=True)[0]
    else:
        lw = _row_log_weights(problem, gamma[None], collapsed=False)[0]
    bad = np.flatnonzero(lw == -np.inf).tolist()
    if bad:
        name = start if isinstance(start, str) else "the start array"
        raise ValueError(f"start {name!r} is infeasible: rows {bad} have zero weight there")
    return np.ascontiguousarray((gamma + 1).reshape(-1), dtype=np.int32)


def _row_log_weights(problem, gammas, collapsed):
    """``log eta_n(gamma_n)`` for gammas of shape (n, P, V) -> (n, P)."""
    P = int(problem.n_rows)
    _, _, strides = _shape(problem)
    la = _collapsed_log_alive(problem) if collapsed else _flat_log_alive(problem)
    ld = np.asarray(problem.log_eta_dead, dtype=np.float64).reshape(P)
    dead = gammas[..., 0] < 0 if gammas.shape[-1] else np.zeros(gammas.shape[:2], bool)
    flat = (np.maximum(gammas, 0) * np.array(strides, dtype=np.int64)).sum(axis=-1)
    rows = np.arange(P)[None, :]
    return np.where(dead, ld[None, :], la[rows, flat]) if P else np.zeros(gammas.shape[:2])


def states_to_assignments(problem, states):
    """Chain states (n, P * V) -> ``gamma`` of shape (n, P, V), int64.

    Parameters
    ----------
    problem : MultiSensorProblem
        Gives ``P = n_rows`` and ``V = n_sensors``.
    states : array_like of int, shape (n, P * V)
        Chain states, position ``n * V + v`` holding ``gamma_n^(v) + 1``.

    Returns
    -------
    ndarray of int64, shape (n, P, V)
        ``gamma``, one per state in the order of ``states``: ``-1`` dead, ``0`` missed,
        ``j >= 1`` measurement ``j`` of the sensor.

    Examples
    --------
    >>> import numpy as np
    >>> class Stub:
    ...     n_rows, n_sensors = 1, 2
    >>> states_to_assignments(Stub(), np.array([[0, 0], [3, 1]])).tolist()
    [[[-1, -1]], [[2, 0]]]
    """
    states = np.asarray(states, dtype=np.int64)
    return states.reshape(len(states), int(problem.n_rows), int(problem.n_sensors)) - 1


def assignment_costs(problem, assignments, method):
    """Exact ``-log w(gamma)`` of each assignment (collapsed weights for componentwise).

    Parameters
    ----------
    problem : MultiSensorProblem
        Uses ``n_rows``, ``n_meas``, ``log_eta_dead`` and ``log_eta_alive``.
    assignments : array_like of int, shape (n, P, V)
        ``gamma`` per assignment (:func:`states_to_assignments`); a dead row is ``-1`` on every
        sensor (only its first entry is read).
    method : str
        ``"componentwise"`` costs a row ``(0, ..., 0)`` with the collapsed weight
        ``eta_n(-1) + eta_n(0, ..., 0)`` of spec §1.6; any other method with ``eta``.

    Returns
    -------
    ndarray of float64, shape (n,)
        ``-sum_n log eta_n(gamma_n)`` per assignment; ``+inf`` for zero weight.

    Examples
    --------
    >>> import numpy as np
    >>> class Stub:
    ...     n_rows, n_sensors, n_meas = 1, 1, (1,)
    ...     log_eta_dead = np.log([0.5]); log_eta_alive = np.log([[0.25, 1.0]])
    >>> assignment_costs(Stub(), np.array([[[-1]], [[0]]]), "exact").round(4).tolist()
    [0.6931, 1.3863]
    >>> assignment_costs(Stub(), np.array([[[0]]]), "componentwise").round(4).tolist()
    [0.2877]
    """
    lw = _row_log_weights(problem, np.asarray(assignments, dtype=np.int64),
                          collapsed=method == "componentwise")
    return -lw.sum(axis=1)


def sweep_cost(problem, method):
    """Candidate weights looked at per sweep (sizes the parallel batches).

    Examples
    --------
    >>> class Stub:
    ...     n_rows, n_sensors, n_meas = 2, 2, (3, 1)
    >>> [sweep_cost(Stub(), m) for m in METHODS]
    [18, 20, 20, 12]
    """
    P = int(problem.n_rows)
    M = [int(m) for m in problem.n_meas]
    if method == "exact":
        return P * (1 + int(np.prod([m + 1 for m in M], dtype=np.int64)))
    if method == "componentwise":
        return P * sum(m + 1 for m in M)
    return P * (len(M) + 2 * sum(M))  # the exclusion sums and the per-sensor draws


def prepare(problem, start, scan, rng, options) -> Prepared:
    """Everything a sampler call on a multi-sensor problem needs, shared by both backends.

    Parameters
    ----------
    problem : MultiSensorProblem
    start : {"all_missed", "all_dead"} or array_like of int, shape (P, V)
    scan : {"systematic", "random"}
    rng : None, int, SeedSequence, BitGenerator or Generator
    options : dict
        ``method`` (default ``"mm"``) and ``survival_power`` (default 1); nothing else.

    Returns
    -------
    Prepared
        Kind ``"multisensor"``, driver ``"chains"``; ``data`` is the kernels'
        :class:`MultiSensorData`,
        ``make_ref_data`` builds the reference's
        :class:`~rankedassign.multisensor.reference.RefData` on first use (so a compiled run
        does not convert the arrays to lists), ``x0`` is int32 of length ``P * V``,
        ``n_values = max M_v + 2``, ``rows = P``, and ``to_result`` maps chain states
        ``(n, P * V)`` to ``(assignments (n, P, V), costs)``.

    Raises
    ------
    TypeError
        On an unknown option.

    Examples
    --------
    >>> import numpy as np
    >>> class Stub:
    ...     n_rows, n_sensors, n_meas = 1, 2, (1, 1)
    ...     log_eta_dead = np.zeros(1); log_eta_alive = np.zeros((1, 2, 2))
    ...     log_s = None; log_theta = None
    >>> f = prepare(Stub(), "all_missed", "systematic", 0, {"method": "exact"})
    >>> f.x0.tolist(), f.n_values
    ([1, 1], 3)
    >>> f.to_result(np.array([[2, 0]]))[0].tolist()
    [[[1, -1]]]
    """
    unknown = sorted(set(options) - {"method", "survival_power"})
    if unknown:
        raise TypeError(f"unexpected option(s) {unknown} for a multi-sensor problem; expected "
                        "'method' and 'survival_power'")
    method = options.get("method", "mm")
    survival_power = options.get("survival_power", 1)
    data = prepare_data(problem, method, scan, survival_power)
    x0 = start_state(problem, start, method)

    def to_result(states):
        assignments = states_to_assignments(problem, states)
        return assignments, assignment_costs(problem, assignments, method)

    return Prepared(
        kind="multisensor", driver="chains", problem=problem, data=data,
        make_ref_data=lambda: RefData(data),
        x0=x0,
        n_values=max((int(m) for m in problem.n_meas), default=0) + 2, base=base_key(rng),
        rows=int(problem.n_rows), sweep_cost=sweep_cost(problem, method), to_result=to_result,
    )


def temper(problem, beta: float, options):
    """The problem of weights ``η^β``: every log-weight (and MM factor) times ``beta``.

    The exact conditional of a row (spec §2.1) becomes the one of ``problem`` raised to
    ``beta``, so ``method="exact"`` targets ``π^β``; the factors ``s`` and ``θ^(v)`` are
    raised to ``beta`` too, so the MM kernels sample the tempered surrogate ``π̃^β``.

    Parameters
    ----------
    problem : MultiSensorProblem
    beta : float
        Inverse temperature in ``(0, 1]``.
    options : dict
        The sampler's options; ``method="componentwise"`` is refused (its collapsed weight
        ``η(−1) + η(0, ..., 0)`` raised to ``beta`` is not the sum of the tempered weights).

    Returns
    -------
    MultiSensorProblem

    Raises
    ------
    ValueError
        For ``method="componentwise"``.

    Examples
    --------
    >>> from rankedassign.multisensor import MultiSensorProblem
    >>> p = MultiSensorProblem.from_eta([1.0], [[[4.0, 1.0]]])
    >>> np.exp(temper(p, 0.5, {"method": "exact"}).log_eta_alive).tolist()
    [[[2.0, 1.0]]]
    """
    if options.get("method", "mm") == "componentwise":
        raise ValueError(
            "beta != 1 does not apply to method='componentwise': its collapsed weight "
            "eta(-1) + eta(0, ..., 0) raised to beta is not the sum of the tempered weights; "
            "use method='exact', 'mm' or 'mm-fixed'")
    theta = None if problem.log_theta is None else [t * beta for t in problem.log_theta]
    log_s = None if problem.log_s is None else problem.log_s * beta
    return type(problem)(problem.log_eta_dead * beta, problem.log_eta_alive * beta, log_s,
                         theta)



def herd_gate(data):
    """Which measurements can carry weight for each row: the gate of the shared herding keys.

    Parameters
    ----------
    data : MultiSensorData
        The kernels' inputs (:func:`prepare_data`).

    Returns
    -------
    ndarray of bool, shape (P, V, max M_v + 1)
        ``gate[n, v, j]`` for ``j >= 1``: ``"exact"``: some tuple with measurement ``j`` on
        sensor ``v`` has ``eta_n > 0``; ``"mm"``/``"mm-fixed"``: ``theta_n^(v)(j) > 0``;
        ``"componentwise"``: False (its gate depends on the row's other components and is
        read from the collapsed weights). Column 0 (missed) is False: it is never held.

    Examples
    --------
    >>> import numpy as np
    >>> class Stub:
    ...     n_rows, n_sensors, n_meas = 1, 2, (1, 1)
    ...     log_eta_dead = np.zeros(1); log_s = None; log_theta = None
    ...     log_eta_alive = np.array([[[0.0, 0.0], [-np.inf, -np.inf]]])   # sensor 0's j = 1: 0
    >>> herd_gate(prepare_data(Stub(), "exact", "systematic")).astype(int).tolist()
    [[[0, 0], [0, 1]]]
    """
    method, P, V = int(data.method), int(data.P), int(data.V)
    M = [int(m) for m in data.n_meas]
    lth, la = data.lth, data.la
    K = max(M) + 1 if V else 1
    gate = np.zeros((P, V, K), dtype=np.bool_)
    if method == METHOD_CODES["exact"]:
        alive = (la > -np.inf).reshape((P,) + tuple(m + 1 for m in M))
        for v in range(V):
            axes = tuple(a for a in range(1, V + 1) if a != v + 1)
            gate[:, v, : M[v] + 1] = alive.any(axis=axes) if axes else alive
    elif method != METHOD_CODES["componentwise"]:
        gate[:] = lth > -np.inf
    gate[:, :, 0] = False
    return gate


def herd_inputs(prep: Prepared, herding, chain_length: int):
    """The herded driver's inputs from a multi-sensor call's Gibbs inputs.

    Parameters
    ----------
    prep : Prepared
        The call's :func:`prepare` result (any method).
    herding : rankedassign.engine.herding.Herding
        Keys, initial weights and the table bound.
    chain_length : int
        Observations per chain (the key table never needs more keys than draws).

    Returns
    -------
    DrawInputs
        As :attr:`rankedassign.engine.kind.DrawRule.inputs` documents: ``data`` is a
        :class:`MultiSensorHerdedData` (the Gibbs inputs, the gate of :func:`herd_gate`, the
        width of a key's weights, the key and init codes, the table capacity,
        ``chain_length`` and the tallies ``[keys created, fall-back draws]``).

    Notes
    -----
    The herded draws of one row update (:func:`rankedassign.multisensor.reference.herd_sweep`)
    are one for ``"exact"`` (over ``1 + prod_v (M_v + 1)`` candidates: dead and every tuple),
    ``V + 1`` for the MM methods (dead/alive, then each sensor over ``0..M_v``) and ``V`` for
    ``"componentwise"``; the key table is sized for that many draws per sweep.

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign.engine.herding import Herding
    >>> class Stub:
    ...     n_rows, n_sensors, n_meas = 2, 2, (1, 2)
    ...     log_eta_dead = np.zeros(2); log_eta_alive = np.zeros((2, 2, 3))
    ...     log_s = None; log_theta = None
    >>> prep = prepare(Stub(), "all_missed", "systematic", 0, {"method": "exact"})
    >>> data, tally, make_ref = herd_inputs(prep, Herding(), 10)[:3]
    >>> int(data.width), data.capacity, tally.tolist()   # 1 + 6 candidates, 2 rows x 10 sweeps
    (7, 20, [0, 0])
    """
    data = prep.data
    method, P, V = int(data.method), int(data.P), int(data.V)
    gate = herd_gate(data)
    K = gate.shape[2]
    if method == METHOD_CODES["exact"]:
        width, draws = 1 + data.Wa.shape[1], P
    elif method == METHOD_CODES["componentwise"]:
        width, draws = K, P * V
    else:
        width, draws = max(2, K), P * (V + 1)
    cap = herding.capacity(draws, chain_length)
    tally = np.zeros(2, dtype=np.int64)
    hdata = MultiSensorHerdedData(
        **data._asdict(), gate=gate, width=np.int64(width), key_mode=KEY_CODES[herding.keys],
        init_mode=INIT_CODES[herding.init], capacity=cap, chain_length=chain_length,
        tally=tally)

    def make_ref():
        ref_tally = [0, 0]
        return HerdData(prep.ref_data, gate.tolist(), K, herding.keys, herding.init, cap,
                        ref_tally), ref_tally

    L = max(P * V, 1)
    T = 4
    while T < 2 * cap:
        T *= 2
    chain_bytes = cap * (8 * width + 4 * L + 4) + 16 * T + 16 * (chain_length + 1) + 8 * width
    return DrawInputs(data=hdata, tally=tally, make_ref=make_ref, chain_bytes=chain_bytes)

"""Single-sensor preparation: the weights, prefix sums and start state of a sampler call.

States are compact index vectors: ``k < M`` measurement ``k``, ``k = M`` missed, ``k = M + 1``
dead (the columns of :attr:`AssignmentProblem.compact_cost`); the result holds column indices
of the full ``P x (M + 2P)`` matrix. Rows draw with the direct sum (driver ``"direct"``) or
from prefix sums (driver ``"prefix"``, :func:`uses_prefix_sums`): the reference runs one row
update for both, the kernels a driver each, so that each compiled driver receives only the
arrays its draw reads.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ..engine.herding import INIT_CODES, KEY_CODES
from ..engine.kind import DrawInputs
from ..engine.records import HerdedDraw, record
from ..engine.result import SCANS, Prepared
from ..engine.rng import base_key
from ..numba_options import interruptible, jit
from ..validation import check_choice
from .problem import AssignmentProblem

__all__ = ["prepare", "temper", "herd_inputs", "HerdData", "DirectData", "PrefixData",
           "HerdedData",
           "STARTS", "M_DIRECT", "CANCEL_GUARD", "SingleData",
           "uses_prefix_sums", "shifted_weights", "prefix_sums", "to_compact", "to_columns",
           "start_columns"]

STARTS = ("all_missed", "all_dead", "lsap")


#: Problems with at most this many measurements draw with the direct sum.
M_DIRECT = 32


def uses_prefix_sums(P: int, M: int) -> bool:
    """Whether rows draw from prefix sums (:func:`rankedassign.single.reference.draw_prefix`).

    A direct draw costs ``O(M)`` per row, a prefix-sum draw ``O(P + log M)`` (the held
    measurements are summed and kept sorted); the prefix sums are used where they are the
    cheaper of the two: more than :data:`M_DIRECT` measurements and more than ``2 P``. The
    rule depends only on the problem's shape, so both implementations follow it.

    Parameters
    ----------
    P : int
        Number of rows (tracks).
    M : int
        Number of measurements.

    Returns
    -------
    bool
        ``M > M_DIRECT and M > 2 * P``: True selects driver ``"prefix"``, False ``"direct"``.

    Examples
    --------
    >>> uses_prefix_sums(4, 16), uses_prefix_sums(50, 50), uses_prefix_sums(50, 5000)
    (False, False, True)
    """
    return M > M_DIRECT and M > 2 * P


#: The prefix-sum draw falls back to the direct sum when the measurements held by other rows
#: carry all but this fraction of the row's measurement weight: ``S[M] - held`` then cancels.
CANCEL_GUARD = 2.0**-20


class SingleData(NamedTuple):
    """The single-sensor sampler's inputs as plain lists (the reference's ``data``).

    Built by :func:`prepare` from the same float64 arrays the kernels receive (``tolist``
    copies every value exactly), and read by :func:`rankedassign.single.reference.sweep`.

    Attributes
    ----------
    W : list of list of float, shape (P, M + 2)
        Shifted weights (:func:`shifted_weights`), columns in compact order: measurements
        ``0..M-1``, missed ``M``, dead ``M + 1``; 0 for a forbidden entry.
    cc : list of list of float, shape (P, M + 2)
        Compact costs (:attr:`AssignmentProblem.compact_cost`, ``+inf`` = forbidden); read
        only by the fall-back draw when every available ``W`` has underflowed to 0.
    S : list of list of float, shape (P, M + 1)
        Per-row prefix sums of the measurement weights (:func:`prefix_sums`). Without prefix
        sums (``prefix`` False) an unread placeholder of zeros, shape (P, 1).
    next_pos : list of list of int, shape (P, M)
        ``next_pos[i][k]``: the first measurement ``k' >= k`` with ``W[i][k'] > 0``, or ``M``
        (:func:`prefix_sums`). Without prefix sums an unread placeholder of zeros, shape (P, 1).
    random_scan : bool
        True for ``scan="random"`` (a fresh Fisher-Yates permutation of the rows every sweep),
        False for the systematic order ``0..P-1``.
    M : int
        Number of measurements.
    prefix : bool
        Rows draw from the prefix sums (:func:`uses_prefix_sums`), else by the direct sum.
    """

    W: list
    cc: list
    S: list
    next_pos: list
    random_scan: bool
    M: int
    prefix: bool


class HerdData(NamedTuple):
    """The herded sampler's inputs as plain lists and numbers (the reference's ``herd_sweep``).

    Attributes
    ----------
    W, cc, random_scan, M
        As in :class:`SingleData`.
    keys : {"full", "shared"}
        What a key is (:class:`~rankedassign.engine.herding.Herding`).
    init : {"conditional", "zero", "uniform"}
        A new key's initial weights.
    capacity : int
        Keys a chain's table may hold.
    tally : list of int
        ``[keys created, fall-back draws]`` over the run, updated in place.
    """

    W: list
    cc: list
    random_scan: bool
    M: int
    keys: str
    init: str
    capacity: int
    tally: list


class DirectData(NamedTuple):
    """The kernels' inputs of a call whose rows draw by the direct sum (driver ``"direct"``).

    The compiled twin of :class:`SingleData` without the prefix sums, read by
    :func:`rankedassign.single._kernels.sweep`.

    Attributes
    ----------
    W : ndarray, shape (P, M + 2), float64
        Shifted weights (:func:`shifted_weights`), columns in compact order.
    cc : ndarray, shape (P, M + 2), float64
        Compact costs (read only by the fall-back draw when every available ``W`` underflowed).
    random_scan : bool
        A fresh random row order every sweep, else ``0..P-1``.
    """

    W: np.ndarray
    cc: np.ndarray
    random_scan: bool


class PrefixData(NamedTuple):
    """The kernels' inputs of a call whose rows draw from prefix sums (driver ``"prefix"``).

    Read by :func:`rankedassign.single._kernels.sweep_prefix`.

    Attributes
    ----------
    W, cc, random_scan
        As in :class:`DirectData`.
    S : ndarray, shape (P, M + 1), float64
        Per-row prefix sums of the measurement weights (:func:`prefix_sums`).
    next_pos : ndarray, shape (P, M), int64
        The first measurement at or after each one with a positive weight, or ``M``.
    """

    W: np.ndarray
    cc: np.ndarray
    S: np.ndarray
    next_pos: np.ndarray
    random_scan: bool


class HerdedData(record(DirectData, HerdedDraw)):
    """The herded kernel's inputs (:func:`herd_inputs`; the compiled twin of :class:`HerdData`).

    Read by :func:`rankedassign.single._kernels.sweep_herded`.

    Attributes
    ----------
    W, cc, random_scan
        As in :class:`DirectData`.
    key_mode, init_mode, capacity, chain_length, tally
        As in :class:`~rankedassign.engine.records.HerdedDraw`.
    """


# ------------------------------------------------------------------------------ single sensor
def shifted_weights(problem: AssignmentProblem) -> np.ndarray:
    """Per-row weights ``W[i, k] = exp(-(cc[i, k] - min_k cc[i, k]))``, shape (P, M + 2).

    ``cc`` is :attr:`AssignmentProblem.compact_cost`; ``W = 0`` where ``cc = +inf``. Shifting
    each row by its minimum keeps ``0 <= W <= 1`` (no overflow for very negative costs) and
    does not change any conditional, which is a ratio of weights of one row. Computed once per
    call with numpy and shared by both implementations, so the samplers never call ``exp``
    in the hot loop.

    Parameters
    ----------
    problem : AssignmentProblem
        Its :attr:`~AssignmentProblem.compact_cost` is read; every row has a finite entry.

    Returns
    -------
    ndarray, shape (P, M + 2), float64
        C-contiguous; each row's largest weight is 1 (its cheapest entry), forbidden entries
        are 0. Shape (0, M + 2) of zeros when ``P = 0``.

    Examples
    --------
    >>> from rankedassign import AssignmentProblem
    >>> p = AssignmentProblem.from_eta([[2.0]], [1.0], [0.0])
    >>> shifted_weights(p).tolist()
    [[1.0, 0.5, 0.0]]
    """
    cc = problem.compact_cost
    if cc.shape[0] == 0:
        return np.zeros(cc.shape)
    mn = np.min(cc, axis=1, keepdims=True)  # finite: every row has a finite entry
    W = np.exp(-(cc - mn))  # exp(-inf) = 0 for a forbidden entry
    return np.ascontiguousarray(W)


@jit()
def prefix_sums(W):
    """Per-row prefix sums of the measurement weights and the next positive weight.

    Parameters
    ----------
    W : ndarray of float64, shape (P, M + 2)
        Shifted weights (:func:`shifted_weights`).

    Returns
    -------
    S : ndarray, shape (P, M + 1), float64
        ``S[i, k] = W[i, 0] + ... + W[i, k - 1]``, accumulated left to right (``S[i, 0] = 0``).
    next_pos : ndarray, shape (P, M), int64
        ``next_pos[i, k]``: the first ``k' >= k`` with ``W[i, k'] > 0``, or ``M``.

    Examples
    --------
    >>> import numpy as np
    >>> S, nxt = prefix_sums(np.array([[0.5, 0.0, 0.25, 1.0, 0.0]]))
    >>> S.tolist(), nxt.tolist()
    ([[0.0, 0.5, 0.5, 0.75]], [[0, 2, 2]])
    """
    P, M = W.shape[0], W.shape[1] - 2
    S = np.empty((P, M + 1))
    next_pos = np.empty((P, M), dtype=np.int64)
    for i in range(P):
        acc = 0.0
        S[i, 0] = 0.0
        for k in range(M):
            acc += W[i, k]  # left to right, as the direct draw sums
            S[i, k + 1] = acc
        nxt = M
        for k in range(M - 1, -1, -1):
            if W[i, k] > 0.0:
                nxt = k
            next_pos[i, k] = nxt
    return S, next_pos


def to_compact(problem: AssignmentProblem, cols: np.ndarray) -> np.ndarray:
    """Column indices -> compact indices (measurement k, missed M, dead M + 1), int32.

    Parameters
    ----------
    problem : AssignmentProblem
        Gives ``P = n_rows`` and ``M = n_meas``.
    cols : ndarray of int, shape (P,) or (n, P)
        Column indices of the full ``P x (M + 2P)`` cost matrix, one per row, feasible for
        their rows: ``j < M`` a measurement, ``M + i`` row ``i``'s missed column, ``M + P + i``
        its dead column.

    Returns
    -------
    ndarray of int32, same shape as ``cols``
        ``j`` for a measurement, ``M`` for missed, ``M + 1`` for dead; the row of a missed or
        dead column is not checked (the inverse of :func:`to_columns` on feasible input).

    Examples
    --------
    >>> from rankedassign import AssignmentProblem
    >>> p = AssignmentProblem.from_eta([[2.0, 1.0]], [1.0], [1.0])
    >>> to_compact(p, np.array([1])).tolist(), to_compact(p, np.array([2, 3])).tolist()
    ([1], [2, 3])
    """
    M = problem.n_meas
    return np.where(cols < M, cols, np.where(cols < M + problem.n_rows, M, M + 1)).astype(np.int32)


def to_columns(problem: AssignmentProblem, compact: np.ndarray) -> np.ndarray:
    """Compact indices (n, P) -> column indices (n, P), int64 (spec §1.5 mapping).

    Parameters
    ----------
    problem : AssignmentProblem
        Gives ``P = n_rows`` and ``M = n_meas``.
    compact : ndarray of int, shape (n, P)
        Chain states, one compact index per row: ``k < M`` measurement ``k``, ``M`` missed,
        ``M + 1`` dead. A 1-D state of shape (P,) also works.

    Returns
    -------
    ndarray of int64, shape (n, P)
        Column indices of the full ``P x (M + 2P)`` matrix: ``k`` for a measurement,
        ``M + i`` for row ``i`` missed, ``M + P + i`` for row ``i`` dead.

    Examples
    --------
    >>> from rankedassign import AssignmentProblem
    >>> p = AssignmentProblem.from_eta([[2.0, 1.0], [1.0, 2.0]], [1.0, 1.0], [1.0, 1.0])
    >>> to_columns(p, np.array([[1, 2], [3, 0]])).tolist()
    [[1, 3], [4, 0]]
    """
    P, M = problem.n_rows, problem.n_meas
    k = compact.astype(np.int64)
    rows = np.arange(P, dtype=np.int64)[None, :]
    return np.where(k < M, k, np.where(k == M, M + rows, M + P + rows)).astype(np.int64)


def start_columns(problem: AssignmentProblem, start) -> np.ndarray:
    """Validate ``start`` and return it as column indices, shape (P,), int64.

    Parameters
    ----------
    problem : AssignmentProblem
    start : {"all_missed", "all_dead", "lsap"} or array_like of int, shape (P,)
        Every row missed, every row dead, the cheapest assignment
        (:func:`scipy.optimize.linear_sum_assignment` on :attr:`AssignmentProblem.cost`), or
        explicit column indices of the full ``P x (M + 2P)`` matrix.

    Returns
    -------
    ndarray of int64, shape (P,)
        A feasible assignment: one column per row, no forbidden entry, no measurement twice.

    Raises
    ------
    TypeError
        If an explicit start is not an integer array (booleans included).
    ValueError
        On an unknown name; ``"all_missed"`` (``"all_dead"``) when some row has a ``+inf``
        missed (dead) cost; an explicit start of the wrong shape or infeasible.

    Examples
    --------
    >>> from rankedassign import AssignmentProblem
    >>> p = AssignmentProblem.from_eta([[2.0, 1.0], [1.0, 2.0]], [1.0, 1.0], [1.0, 1.0])
    >>> start_columns(p, "all_missed").tolist(), start_columns(p, "lsap").tolist()
    ([2, 3], [0, 1])
    """
    P, M = problem.n_rows, problem.n_meas
    cc = problem.compact_cost
    if isinstance(start, str):
        check_choice(start, "start", STARTS)
        if start == "all_missed":
            bad = np.flatnonzero(~np.isfinite(cc[:, M])).tolist()
            if bad:
                raise ValueError(
                    f"start='all_missed' is infeasible: rows {bad} have a +inf missed cost "
                    "(eta_i(0) = 0); use start='all_dead' or start='lsap'"
                )
            return problem.all_missed()
        if start == "all_dead":
            bad = np.flatnonzero(~np.isfinite(cc[:, M + 1])).tolist()
            if bad:
                raise ValueError(
                    f"start='all_dead' is infeasible: rows {bad} have a +inf dead cost "
                    "(eta_i(-1) = 0); use start='all_missed' or start='lsap'"
                )
            return problem.all_dead()
        x = np.empty(P, dtype=np.int64)
        if P:
            from scipy.optimize import linear_sum_assignment  # (0.3 s to import: here)

            rows, cols = linear_sum_assignment(problem.cost)
            x[rows] = cols
        return x
    x = np.asarray(start)
    if x.dtype == bool or not np.issubdtype(x.dtype, np.integer):
        raise TypeError(
            f"start must be 'all_missed', 'all_dead', 'lsap' or an integer array of column "
            f"indices, got dtype {x.dtype}"
        )
    if x.shape != (P,):
        raise ValueError(f"start array must have shape (P,) = ({P},), got {x.shape}")
    x = x.astype(np.int64)
    if not problem.is_feasible(x):
        raise ValueError(
            f"start assignment {x.tolist()} is infeasible (out-of-range or forbidden column, or a "
            "measurement used twice)"
        )
    return x


def prepare(problem: AssignmentProblem, start, scan, rng, options) -> Prepared:
    """The :class:`~rankedassign.engine.result.Prepared` inputs of a single-sensor call.

    Parameters
    ----------
    problem : AssignmentProblem
    start : {"all_missed", "all_dead", "lsap"} or array_like of int, shape (P,)
        Start state (:func:`start_columns`).
    scan : {"systematic", "random"}
    rng : None, int, SeedSequence, BitGenerator or Generator
        Draws the run's base key.
    options : dict
        Must be empty: the single-sensor kind has no options.

    Returns
    -------
    Prepared

    Raises
    ------
    TypeError
        On any option.

    Examples
    --------
    >>> from rankedassign import synthetic
    >>> prep = prepare(synthetic.diagonal(), "all_missed", "systematic", 0, {})
    >>> prep.kind, prep.driver, prep.rows, prep.sweep_cost
    ('single', 'direct', 4, 72)
    """
    if options:
        raise TypeError(
            f"unexpected option(s) {sorted(options)} for an AssignmentProblem (options such as "
            "'method' apply to other problem types)"
        )
    check_choice(scan, "scan", SCANS)
    x0 = to_compact(problem, start_columns(problem, start))
    W = shifted_weights(problem)
    cc = np.array(problem.compact_cost, dtype=np.float64, order="C")  # writable: one numba type
    random_scan = scan == "random"
    P, M = problem.n_rows, problem.n_meas
    prefix = uses_prefix_sums(P, M)
    if prefix:
        with interruptible:
            S, next_pos = prefix_sums(W)
        driver = "prefix"
        data = PrefixData(W=W, cc=cc, S=S, next_pos=next_pos, random_scan=random_scan)
    else:  # the direct draw's driver takes only what it reads
        S, next_pos = np.zeros((P, 1)), np.zeros((P, 1), dtype=np.int64)
        driver, data = "direct", DirectData(W=W, cc=cc, random_scan=random_scan)

    def to_result(states):
        assignments = to_columns(problem, states)
        return assignments, problem._sum_costs(assignments)  # feasible by construction

    return Prepared(
        kind="single", driver=driver, problem=problem, data=data,
        make_ref_data=lambda: SingleData(W.tolist(), cc.tolist(), S.tolist(),
                                         next_pos.tolist(), random_scan, M, prefix),
        x0=x0, n_values=M + 2,
        base=base_key(rng), rows=P, sweep_cost=P * (M + 2), to_result=to_result,
    )


def temper(problem: AssignmentProblem, beta: float, options) -> AssignmentProblem:
    """The problem of weights ``η^β``: every cost ``−ln η`` times ``beta``.

    Every row conditional (spec eq. 2.1) of the result is the one of ``problem`` raised to
    ``beta`` and renormalised, so the chains target ``π^β``. The support (the ``+inf``
    entries) is unchanged.

    Parameters
    ----------
    problem : AssignmentProblem
    beta : float
        Inverse temperature in ``(0, 1]``.
    options : dict
        The kind's options (none).

    Returns
    -------
    AssignmentProblem

    Examples
    --------
    >>> p = AssignmentProblem.from_eta([[4.0]], [1.0], [0.25])
    >>> np.exp(-temper(p, 0.5, {}).compact_cost).round(3).tolist()
    [[2.0, 1.0, 0.5]]
    """
    return AssignmentProblem(problem.cost * beta)



def herd_inputs(prep: Prepared, herding, chain_length: int):
    """The herded driver's inputs from a single-sensor call's Gibbs inputs.

    Parameters
    ----------
    prep : Prepared
        The call's :func:`prepare` result (either driver: the herded draw needs every row's
        whole conditional, so it always sums directly).
    herding : rankedassign.engine.herding.Herding
        Keys, initial weights and the table bound.
    chain_length : int
        Observations per chain (the key table never needs more than ``P`` keys per sweep).

    Returns
    -------
    DrawInputs
        As :attr:`rankedassign.engine.kind.DrawRule.inputs` documents; the tallies are
        ``[keys created, fall-back draws]``.
    """
    W, cc, random_scan = prep.data.W, prep.data.cc, prep.data.random_scan
    P, K = W.shape
    cap = herding.capacity(P, chain_length)
    tally = np.zeros(2, dtype=np.int64)
    data = HerdedData(W=W, cc=cc, random_scan=random_scan, key_mode=KEY_CODES[herding.keys],
                      init_mode=INIT_CODES[herding.init], capacity=cap,
                      chain_length=chain_length, tally=tally)

    def make_ref():
        ref_tally = [0, 0]
        return HerdData(W.tolist(), cc.tolist(), random_scan, K - 2, herding.keys,
                        herding.init, cap, ref_tally), ref_tally

    T = 4
    while T < 2 * cap:
        T *= 2
    chain_bytes = cap * (8 * K + 4 * P + 4) + 16 * T + 16 * (chain_length + 1) + 24 * K
    return DrawInputs(data=data, tally=tally, make_ref=make_ref, chain_bytes=chain_bytes)

"""What the reference samplers and the numba kernels share: arguments, preparation, results.

Both implementations of every sampler (:mod:`rankedassign.reference`, the specification of
record, and the numba kernels driven by :mod:`rankedassign.samplers`) start from the same
:class:`Prepared` inputs — validated once, with the weights computed once with numpy — and end
in the same :class:`SamplerResult`. Each problem type ("kind") contributes one preparation
function here; the reference and the kernels each hold their own table of row updates keyed by
the same kind name, so the layers import downwards only::

    validation, _rng, problem (and the other problem types)
        -> _sampling (this module)
        -> reference (pure Python)  |  _rng_kernels, _chains, _kernels (numba)
        -> samplers (public API)

Single-sensor preparation. States are compact index vectors: ``k < M`` measurement ``k``,
``k = M`` missed, ``k = M + 1`` dead (the columns of :attr:`AssignmentProblem.compact_cost`);
the result holds column indices of the full ``P x (M + 2P)`` matrix. A single-sensor problem is of
kind ``"single"`` (rows draw with the direct sum) or ``"single_prefix"`` (rows draw from prefix
sums, :func:`uses_prefix_sums`): the reference runs one row update for both, the kernels a
driver each, so that each compiled driver receives only the arrays its draw reads.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass, field
from typing import Any, NamedTuple

import numpy as np
from scipy.optimize import linear_sum_assignment

from ._rng import base_key
from .multisensor.adaptive_birth import AdaptiveBirthProblem, sampler_fields
from .multisensor.problem import MultiSensorProblem
from .multisensor.sampling import prepare_fields as _multisensor_fields
from .numba_options import interruptible, jit
from .problem import AssignmentProblem
from .validation import (
    STALE_READINGS,
    STALL_READINGS,
    check_choice,
    check_int,
    check_optional_int,
)

__all__ = ["SamplerResult", "Prepared", "prepare", "package", "shifted_weights", "STARTS",
           "SCANS", "BACKENDS", "zero_length_run", "SingleData", "prefix_sums",
           "M_DIRECT", "CANCEL_GUARD", "uses_prefix_sums"]

STARTS = ("all_missed", "all_dead", "lsap")
SCANS = ("systematic", "random")
BACKENDS = ("numba", "python")

#: Problems with at most this many measurements draw with the direct sum.
M_DIRECT = 32


def uses_prefix_sums(P: int, M: int) -> bool:
    """Whether rows draw from prefix sums (:func:`rankedassign.reference.draw_prefix`).

    A direct draw costs ``O(M)`` per row, a prefix-sum draw ``O(P + log M)`` (the held
    measurements are summed and kept sorted); the prefix sums are used where they are the
    cheaper of the two: more than :data:`M_DIRECT` measurements and more than ``2 P``. The
    rule depends only on the problem's shape, so both implementations follow it.

    Examples
    --------
    >>> uses_prefix_sums(4, 16), uses_prefix_sums(50, 50), uses_prefix_sums(50, 5000)
    (False, False, True)
    """
    return M > M_DIRECT and M > 2 * P


#: The prefix-sum draw falls back to the direct sum when the measurements held by other rows
#: carry all but this fraction of the row's measurement weight: ``S[M] - held`` then cancels.
CANCEL_GUARD = 2.0**-20


@dataclass(frozen=True, eq=False)
class SamplerResult:
    """Unique assignments visited by a Gibbs sampler, with visit counts and run statistics.

    Attributes
    ----------
    assignments : ndarray, shape (n_unique, P), int64
        Column indices (one per row) of each unique assignment, in order of discovery; the
        start state is first. Read-only. (Other problem types document their own layout, e.g.
        ``(n_unique, P, V)`` labels for a multi-sensor problem.)
    costs : ndarray, shape (n_unique,), float64
        ``problem.cost_of(assignments)`` (``-ln w``). Read-only.
    counts : ndarray, shape (n_unique,), int64
        Number of observations equal to each assignment (the start state's may be 0); sums to
        ``n_observations``. Read-only.
    n_observations : int
        Full sweeps performed (= observations).
    n_row_updates : int
        Single-row conditional draws, ``n_observations * P``.
    n_chains_run : int
        Chains started (1 for the original sampler).
    stop_reason : {"budget", "stale"}
        ``"stale"`` if the stale rule fired (even on the last chain), else ``"budget"``.
    n_speculative_discarded : int
        Sweeps simulated ahead by the parallel kernel and not used (0 for sequential runs).

    Examples
    --------
    >>> from rankedassign import synthetic, sample_original
    >>> res = sample_original(synthetic.diagonal(), 50, rng=0)
    >>> len(res) == res.assignments.shape[0], int(res.counts.sum())
    (True, 50)
    """

    assignments: np.ndarray
    costs: np.ndarray
    counts: np.ndarray
    n_observations: int
    n_row_updates: int
    n_chains_run: int
    stop_reason: str
    n_speculative_discarded: int = 0

    def __post_init__(self):
        for name in ("assignments", "costs", "counts"):
            arr = getattr(self, name)
            arr.setflags(write=False)

    def __len__(self) -> int:
        return int(self.assignments.shape[0])

    def __repr__(self) -> str:
        best = float(self.costs.min()) if len(self) else float("nan")
        return (
            f"SamplerResult(n_unique={len(self)}, n_observations={self.n_observations}, "
            f"n_chains_run={self.n_chains_run}, stop_reason={self.stop_reason!r}, "
            f"best_cost={best:.6g})"
        )


@dataclass(frozen=True, eq=False)
class Prepared:
    """Validated inputs of one sampler call, shared by the reference and the kernels.

    Attributes
    ----------
    kind : str
        Problem type; keys the row-update tables of the reference and of the kernels.
    problem : object
        The problem.
    data : tuple
        The kernels' read-only arrays and scalars (one numba type per kind).
    ref_data : tuple
        The same inputs as plain Python lists and numbers for the reference (built on first
        use, so a compiled run does not pay for the conversion).
    x0 : ndarray, shape (L,), int32
        Start state.
    n_values : int
        ``K``: every state entry lies in ``0..K-1`` (width of the Zobrist table).
    base : int
        Base key of the run's random streams.
    rows : int
        Row updates (conditional draws) per sweep, for ``n_row_updates``.
    sweep_cost : int
        Candidate evaluations per sweep (sizes the parallel batches).
    to_result : callable
        ``states (n, L) int64 -> (assignments, costs)``.
    """

    kind: str
    problem: Any
    data: tuple
    make_ref_data: Any = field(repr=False)
    x0: np.ndarray
    n_values: int
    base: int
    rows: int
    sweep_cost: int
    to_result: Any = field(repr=False)

    @functools.cached_property
    def ref_data(self):
        """The reference's inputs (see the class docstring)."""
        return self.make_ref_data()


class SingleData(NamedTuple):
    """The single-sensor sampler's inputs as plain lists (the reference's ``data``)."""

    W: list        # (P, M + 2) shifted weights
    cc: list       # (P, M + 2) compact costs
    S: list        # (P, M + 1) prefix sums of the measurement weights
    next_pos: list  # (P, M) first positive weight at or after each measurement
    random_scan: bool
    M: int
    prefix: bool   # rows draw from prefix sums (uses_prefix_sums)



# ------------------------------------------------------------------------------ arguments
def check_rules(tau_stall, tau_stale, stall, stale):
    """Validate the stall/stale thresholds and readings; return ``(tau_stall, tau_stale)``.

    ``None`` switches a rule off; a threshold is otherwise an int >= 1.
    """
    tau_stall = check_optional_int(tau_stall, "tau_stall")
    tau_stale = check_optional_int(tau_stale, "tau_stale")
    check_choice(stall, "stall reading", STALL_READINGS)
    check_choice(stale, "stale reading", STALE_READINGS)
    return tau_stall, tau_stale


def check_chain_budget(n_chains, chain_length):
    """Validate ``N_S`` and ``N_C`` (ints in ``[0, 2**62]``)."""
    return check_int(n_chains, "n_chains"), check_int(chain_length, "chain_length")


def zero_length_run(n_chains, tau_stale, stale):
    """Chains run and whether stale fired when every chain has no sweep (``N_C = 0``).

    Such a chain observes nothing and adds nothing to ``U``, so after ``c`` chains the stale
    counters are ``c`` (consecutive, cumulative), ``0`` (literal-set) and ``c - 1``
    (literal-multiset: ``c`` start states, no observation, ``|U| = 1``). Computed in closed
    form so that ``n_chains = 10**9`` returns at once instead of looping over empty chains.

    Examples
    --------
    >>> zero_length_run(10, 3, "consecutive"), zero_length_run(10, 3, "literal-multiset")
    ((3, True), (4, True))
    >>> zero_length_run(10**9, None, "consecutive")
    (1000000000, False)
    """
    if tau_stale is None or stale == "literal-set":
        return n_chains, False
    fire_at = tau_stale + 1 if stale == "literal-multiset" else tau_stale
    if fire_at <= n_chains:
        return fire_at, True
    return n_chains, False


# ------------------------------------------------------------------------------ single sensor
def shifted_weights(problem: AssignmentProblem) -> np.ndarray:
    """Per-row weights ``W[i, k] = exp(-(cc[i, k] - min_k cc[i, k]))``, shape (P, M + 2).

    ``cc`` is :attr:`AssignmentProblem.compact_cost`; ``W = 0`` where ``cc = +inf``. Shifting
    each row by its minimum keeps ``0 <= W <= 1`` (no overflow for very negative costs) and
    does not change any conditional, which is a ratio of weights of one row. Computed once per
    call with numpy and shared by both implementations, so the samplers never call ``exp``
    in the hot loop.

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
    """Column indices -> compact indices (measurement k, missed M, dead M + 1), int32."""
    M = problem.n_meas
    return np.where(cols < M, cols, np.where(cols < M + problem.n_rows, M, M + 1)).astype(np.int32)


def to_columns(problem: AssignmentProblem, compact: np.ndarray) -> np.ndarray:
    """Compact indices (n, P) -> column indices (n, P), int64 (spec §1.5 mapping)."""
    P, M = problem.n_rows, problem.n_meas
    k = compact.astype(np.int64)
    rows = np.arange(P, dtype=np.int64)[None, :]
    return np.where(k < M, k, np.where(k == M, M + rows, M + P + rows)).astype(np.int64)


def start_columns(problem: AssignmentProblem, start) -> np.ndarray:
    """Validate ``start`` and return it as column indices, shape (P,), int64."""
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


def _prepare_single(problem: AssignmentProblem, start, scan, rng, options) -> Prepared:
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
        kind, data = "single_prefix", (W, cc, S, next_pos, random_scan)
    else:  # the direct draw's driver takes only what it reads
        S, next_pos = np.zeros((P, 1)), np.zeros((P, 1), dtype=np.int64)
        kind, data = "single", (W, cc, random_scan)

    def to_result(states):
        assignments = to_columns(problem, states)
        return assignments, problem._sum_costs(assignments)  # feasible by construction

    return Prepared(
        kind=kind, problem=problem, data=data,
        make_ref_data=lambda: SingleData(W.tolist(), cc.tolist(), S.tolist(),
                                         next_pos.tolist(), random_scan, M, prefix),
        x0=x0, n_values=M + 2,
        base=base_key(rng), rows=P, sweep_cost=P * (M + 2), to_result=to_result,
    )


def _prepare_multisensor(problem, start, scan, rng, options) -> Prepared:
    """Multi-sensor problems (:mod:`rankedassign.multisensor.sampling`)."""
    return Prepared(**_multisensor_fields(problem, start, scan, rng, options))


# ------------------------------------------------------------------------------ dispatch
def _prepare_adaptive_birth(problem, start, scan, rng, options) -> Prepared:
    """Adaptive-birth problems (:mod:`rankedassign.multisensor.adaptive_birth`)."""
    return Prepared(**sampler_fields(problem, start, scan, rng, options))


_PREPARE = {AssignmentProblem: _prepare_single, MultiSensorProblem: _prepare_multisensor,
            AdaptiveBirthProblem: _prepare_adaptive_birth}


def prepare(problem, start, scan, rng, **options) -> Prepared:
    """Validate a sampler call's problem and common options; build its :class:`Prepared`.

    Parameters
    ----------
    problem : AssignmentProblem or MultiSensorProblem
        The problem (its type selects the preparation).
    start, scan, rng
        As in :func:`rankedassign.sample_original`.
    **options
        Options of the problem type (none for an :class:`AssignmentProblem`; ``method`` and
        ``survival_power`` for a :class:`~rankedassign.multisensor.MultiSensorProblem`, see
        :func:`rankedassign.multisensor.sampling.prepare_fields`).

    Raises
    ------
    TypeError
        If ``problem`` is of no known problem type.

    Examples
    --------
    >>> from rankedassign import synthetic
    >>> prep = prepare(synthetic.diagonal(), "all_missed", "systematic", 0)
    >>> prep.kind, prep.x0.tolist(), prep.n_values
    ('single', [16, 16, 16, 16], 18)
    """
    for cls, prep in _PREPARE.items():
        if isinstance(problem, cls):
            return prep(problem, start, scan, rng, options)
    names = ", ".join(cls.__name__ for cls in _PREPARE)
    raise TypeError(
        f"problem must be one of ({names}), got {type(problem).__name__}; build one with "
        "AssignmentProblem.from_cost / from_eta"
    )


def package(prep: Prepared, states, counts, n_obs, n_chains_run, stale, discarded
            ) -> SamplerResult:
    """Turn a run's unique states and counters into a :class:`SamplerResult`."""
    states = np.asarray(states, dtype=np.int64).reshape(len(counts), prep.x0.shape[0])
    assignments, costs = prep.to_result(states)
    return SamplerResult(
        assignments=assignments,
        costs=costs,
        counts=np.asarray(counts, dtype=np.int64).copy(),
        n_observations=int(n_obs),
        n_row_updates=int(n_obs) * prep.rows,
        n_chains_run=int(n_chains_run),
        stop_reason="stale" if stale else "budget",
        n_speculative_discarded=int(discarded),
    )

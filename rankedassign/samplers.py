"""Gibbs samplers for the ranked-assignment problem: public API.

Two samplers of the target ``pi(gamma) = w(gamma) / Z`` (spec eq. 1.6):

* :func:`sample_original` — one long systematic-scan chain (Vo, Vo & Hoang 2017, Alg. 1;
  spec §2.2);
* :func:`sample_short_chains` — many short chains restarted from the same state, with the
  stall and stale termination rules of Trezza, Bucci & Varshney (2023, Alg. 1; spec §3),
  every reading of those rules selectable (spec §3.2).

Each public function validates its input once, prepares the arrays shared by both
implementations and runs either the numba kernels (:mod:`rankedassign._kernels`,
``backend="numba"``) or the pure-Python specification (:mod:`rankedassign.reference`,
``backend="python"``). Both give identical results, bit for bit, for the same ``rng`` — as
does the parallel kernel for any ``workers`` — because

* every chain draws from its own SplitMix64 stream derived from ``rng`` and the chain index
  (:mod:`rankedassign._rng`);
* a row update consumes exactly one uniform and turns it into a candidate with the same
  explicit inverse-CDF loop over the same precomputed weights ``W`` (no ``exp`` in the hot loop,
  no ``rng.choice``);
* parallel chains are simulated speculatively and replayed in chain order, so stall and stale
  see exactly the sequential history (spec §3.3, "Parallelism").

Observations. One observation is one full sweep over all ``P`` rows (spec §2.4, A9). The start
state is stored first in the output but is not an observation; its ``count`` is the number
of observations that returned to it.
"""

from __future__ import annotations

import numbers
from dataclasses import dataclass

import numpy as np
from numba import parallel_chunksize

from . import _kernels
from ._rng import ZOBRIST_SEED, base_key
from .numba_options import threads
from .problem import AssignmentProblem

__all__ = ["SamplerResult", "sample_original", "sample_short_chains", "warmup"]

STALL_READINGS = {
    "global-consecutive": _kernels.STALL_GLOBAL_CONSECUTIVE,
    "global-cumulative": _kernels.STALL_GLOBAL_CUMULATIVE,
    "chain-local": _kernels.STALL_CHAIN_LOCAL,
}
STALE_READINGS = {
    "consecutive": _kernels.STALE_CONSECUTIVE,
    "cumulative": _kernels.STALE_CUMULATIVE,
    "literal-set": _kernels.STALE_LITERAL_SET,
    "literal-multiset": _kernels.STALE_LITERAL_MULTISET,
}
STARTS = ("all_missed", "all_dead", "lsap")
SCANS = ("systematic", "random")
BACKENDS = ("numba", "python")

# Upper bound on the speculation slab (batch x chain_length x P int32 entries, 64 MiB).
_MAX_SLAB = 1 << 24
# Candidate evaluations per speculation batch (~1 ms of sweeps).
_BATCH_WORK = 1 << 21
# Chains per work item of the parallel speculation loop.
_CHUNK = 4


@dataclass(frozen=True, eq=False)
class SamplerResult:
    """Unique assignments visited by a Gibbs sampler, with visit counts and run statistics.

    Attributes
    ----------
    assignments : ndarray, shape (n_unique, P), int64
        Column indices (one per row) of each unique assignment, in order of discovery; the
        start state is first. Read-only.
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


# ------------------------------------------------------------------------------ validation
def _check_problem(problem) -> AssignmentProblem:
    if not isinstance(problem, AssignmentProblem):
        raise TypeError(
            f"problem must be an AssignmentProblem, got {type(problem).__name__}; build one with "
            "AssignmentProblem.from_cost / from_eta"
        )
    return problem


def _check_count(name: str, value) -> int:
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise TypeError(f"{name} must be a non-negative int, got {type(value).__name__} {value!r}")
    if value < 0:
        raise ValueError(f"{name} must be >= 0, got {value}")
    return int(value)


def _check_tau(name: str, value) -> int:
    """``None`` (rule off) -> 0; otherwise a positive int."""
    if value is None:
        return 0
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise TypeError(
            f"{name} must be None or a positive int, got {type(value).__name__} {value!r}"
        )
    if value < 1:
        raise ValueError(f"{name} must be None (rule off) or >= 1, got {value}")
    return int(value)


def _check_choice(name: str, value, choices) -> None:
    if not isinstance(value, str) or value not in choices:
        raise ValueError(f"unknown {name} {value!r}; expected one of {tuple(choices)}")


def _check_workers(workers) -> int:
    if isinstance(workers, bool) or not isinstance(workers, numbers.Integral):
        raise TypeError(f"workers must be an int >= 1, got {type(workers).__name__} {workers!r}")
    if workers < 1:
        raise ValueError(f"workers must be >= 1, got {workers}")
    return int(workers)


def _start_columns(problem: AssignmentProblem, start) -> np.ndarray:
    """Validate ``start`` and return it as column indices, shape (P,), int64."""
    P, M = problem.n_rows, problem.n_meas
    cc = problem.compact_cost
    if isinstance(start, str):
        _check_choice("start", start, STARTS)
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
        from scipy.optimize import linear_sum_assignment

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


def _to_compact(problem: AssignmentProblem, cols: np.ndarray) -> np.ndarray:
    """Column indices -> compact indices (measurement k, missed M, dead M + 1), int32."""
    M = problem.n_meas
    return np.where(cols < M, cols, np.where(cols < M + problem.n_rows, M, M + 1)).astype(np.int32)


def _to_columns(problem: AssignmentProblem, compact: np.ndarray) -> np.ndarray:
    """Compact indices (n, P) -> column indices (n, P), int64 (spec §1.5 mapping)."""
    P, M = problem.n_rows, problem.n_meas
    k = compact.astype(np.int64)
    rows = np.arange(P, dtype=np.int64)[None, :]
    return np.where(k < M, k, np.where(k == M, M + rows, M + P + rows)).astype(np.int64)


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
    with np.errstate(invalid="ignore"):
        W = np.exp(-(cc - mn))
    W[~np.isfinite(cc)] = 0.0
    return np.ascontiguousarray(W)


@dataclass(frozen=True)
class _Prepared:
    """Validated inputs shared by the reference and the kernels."""

    problem: AssignmentProblem
    W: np.ndarray
    cc: np.ndarray
    x0: np.ndarray  # compact start state, int32
    base: int
    random_scan: bool


def _prepare(problem, start, scan, rng) -> _Prepared:
    problem = _check_problem(problem)
    _check_choice("scan", scan, SCANS)
    x0 = _to_compact(problem, _start_columns(problem, start))
    return _Prepared(
        problem=problem,
        W=shifted_weights(problem),
        cc=np.array(problem.compact_cost, dtype=np.float64, order="C"),  # writable: one numba type
        x0=x0,
        base=base_key(rng),
        random_scan=scan == "random",
    )


def _package(prep: _Prepared, compact, counts, n_obs, n_chains_run, stale, discarded):
    problem = prep.problem
    compact = np.asarray(compact, dtype=np.int64).reshape(len(counts), problem.n_rows)
    assignments = _to_columns(problem, compact)
    costs = np.asarray(problem.cost_of(assignments), dtype=np.float64).reshape(-1)
    return SamplerResult(
        assignments=assignments,
        costs=costs,
        counts=np.asarray(counts, dtype=np.int64).copy(),
        n_observations=int(n_obs),
        n_row_updates=int(n_obs) * problem.n_rows,
        n_chains_run=int(n_chains_run),
        stop_reason="stale" if stale else "budget",
        n_speculative_discarded=int(discarded),
    )


def _zobrist(problem: AssignmentProblem) -> np.ndarray:
    return _kernels.zobrist_keys(problem.n_rows, problem.n_meas + 2, np.uint64(ZOBRIST_SEED))


def _batch_size(workers: int, n_chains: int, chain_length: int, P: int, M: int) -> int:
    """Chains per speculation batch, or 0 for the sequential kernel.

    At least ``max(64, 16 workers)`` chains, and enough that a batch holds about
    :data:`_BATCH_WORK` candidate evaluations (``P (M + 2)`` per sweep) so that starting the
    thread team is cheap next to the work; at most :data:`_MAX_SLAB` stored states. A stale
    stop discards at most the rest of one batch. If the slab bound leaves room for fewer
    chains than workers (very long chains), speculation cannot keep the workers busy and the
    sequential kernel runs instead (same result).
    """
    if workers <= 1 or n_chains < 2:  # one chain cannot be split across threads
        return 0
    room = _MAX_SLAB // max(1, chain_length * max(P, 1))
    if room < workers:
        return 0
    by_work = -(-_BATCH_WORK // max(1, chain_length * max(P, 1) * (M + 2)))
    return min(max(64, 16 * workers, by_work), n_chains, room)


# ------------------------------------------------------------------------------ public API
def sample_original(problem, n_obs, *, start="all_missed", scan="systematic", rng=None,
                    backend="numba") -> SamplerResult:
    """Original Gibbs sampler: one long chain of ``n_obs`` sweeps (Vo, Vo & Hoang 2017).

    Parameters
    ----------
    problem : AssignmentProblem
        The ``P x (M + 2P)`` ranked-assignment problem.
    n_obs : int
        Number of observations = full sweeps over all rows (>= 0). Vo's MATLAB ``T`` (stored
        solutions including the initial one) is ``n_obs + 1`` (spec A20).
    start : {"all_missed", "all_dead", "lsap"} or array_like of int, shape (P,)
        Start state: every row missed (Vo's choice, the default), every row dead, the optimal
        assignment (:func:`scipy.optimize.linear_sum_assignment` on the full cost matrix), or
        explicit feasible column indices.
    scan : {"systematic", "random"}
        Row order of each sweep: ``0..P-1``, or a fresh uniformly random permutation per sweep.
    rng : None, int, SeedSequence, BitGenerator or Generator
        Anything :func:`numpy.random.default_rng` accepts; a Generator is advanced by one draw
        (the run's base key, see :mod:`rankedassign._rng`). The chain uses stream 0.
    backend : {"numba", "python"}
        Compiled kernels or the pure-Python reference
        (:func:`rankedassign.reference.sample_original`); the results are identical.

    Returns
    -------
    SamplerResult
        Unique assignments in discovery order (start state first) with their costs and visit
        counts; ``n_chains_run = 1``, ``stop_reason = "budget"``.

    Raises
    ------
    TypeError
        If ``problem`` is not an AssignmentProblem or ``n_obs`` is not an int.
    ValueError
        On a negative ``n_obs``, an unknown ``start``/``scan``/``backend``, or an infeasible
        start state (e.g. all-missed when some row's missed cost is ``+inf``).

    Notes
    -----
    Spec §2.2. Starting from ``x = x0``, each sweep updates rows in place (Gauss-Seidel)::

        x_n ~ p(k) ∝ eta_n(k) * 1[k not held by another row]     (spec eq. 2.1)

    and the state after the sweep is one observation. The conditional of row ``n`` is drawn by
    the inverse-CDF loop of :func:`rankedassign._kernels.sweep` with one uniform. The chain
    is irreducible and aperiodic on the feasible set, so visit frequencies converge to
    ``pi = w / Z`` (spec §2.3). The result equals
    ``sample_short_chains(problem, 1, n_obs)`` with no termination rules.

    References
    ----------
    .. [1] B.-N. Vo, B.-T. Vo, H. G. Hoang, "An Efficient Implementation of the Generalized
       Labeled Multi-Bernoulli Filter", IEEE Trans. Signal Process. 65(8):1975-1987, 2017.

    Examples
    --------
    >>> from rankedassign import synthetic, sample_original
    >>> p = synthetic.diagonal()
    >>> res = sample_original(p, 1000, rng=1)
    >>> res.n_observations, res.n_row_updates, res.stop_reason
    (1000, 4000, 'budget')
    >>> res.assignments[0].tolist()          # the all-missed start state is stored first
    [16, 17, 18, 19]
    >>> res.assignments[res.costs.argmin()].tolist()   # gamma = (1, 2, 3, 4)
    [0, 1, 2, 3]
    >>> ref = sample_original(p, 1000, rng=1, backend="python")
    >>> bool((ref.assignments == res.assignments).all() and (ref.counts == res.counts).all())
    True
    """
    _check_choice("backend", backend, BACKENDS)
    if backend == "python":
        from . import reference

        return reference.sample_original(problem, n_obs, start=start, scan=scan, rng=rng)
    n_obs = _check_count("n_obs", n_obs)
    prep = _prepare(problem, start, scan, rng)
    uniq, counts, ctr = _kernels.run_chains(
        prep.W, prep.cc, _zobrist(prep.problem), prep.x0, np.uint64(prep.base), 1, n_obs,
        0, 0, 0, 0, prep.random_scan, 0, 1,
    )
    return _package(prep, uniq, counts, ctr[1], ctr[2], ctr[5], ctr[6])


def sample_short_chains(problem, n_chains, chain_length, *, tau_stall=None, tau_stale=None,
                        stall="global-consecutive", stale="consecutive", start="all_missed",
                        scan="systematic", rng=None, backend="numba",
                        workers=1) -> SamplerResult:
    """Short-chain, multi-simulation Gibbs sampler with stall/stale termination.

    Parameters
    ----------
    problem : AssignmentProblem
        The ``P x (M + 2P)`` ranked-assignment problem.
    n_chains : int
        ``N_S``, the maximum number of chains (>= 0).
    chain_length : int
        ``N_C``, the maximum number of sweeps (observations) per chain (>= 0).
    tau_stall : int or None
        Stall threshold (>= 1); ``None`` disables the stall rule.
    tau_stale : int or None
        Stale threshold (>= 1); ``None`` disables the stale rule.
    stall : {"global-consecutive", "global-cumulative", "chain-local"}
        Reading of the stall rule (spec §3.2); see Notes.
    stale : {"consecutive", "cumulative", "literal-set", "literal-multiset"}
        Reading of the stale rule (spec §3.2); see Notes.
    start : {"all_missed", "all_dead", "lsap"} or array_like of int, shape (P,)
        Common start state ``x0`` of every chain (see :func:`sample_original`).
    scan : {"systematic", "random"}
        Row order of each sweep.
    rng : None, int, SeedSequence, BitGenerator or Generator
        Anything :func:`numpy.random.default_rng` accepts; chain ``c`` uses stream ``c``.
    backend : {"numba", "python"}
        Compiled kernels or the pure-Python reference
        (:func:`rankedassign.reference.sample_short_chains`); the results are identical.
    workers : int
        Threads for the numba backend (>= 1). With ``workers > 1`` chains are simulated
        speculatively in parallel batches and replayed in order; everything but
        ``n_speculative_discarded`` is identical to ``workers = 1``. Ignored by the Python
        backend.

    Returns
    -------
    SamplerResult
        Unique assignments in discovery order (start state first), costs, visit counts,
        observation count, chains run and why the run stopped.

    Raises
    ------
    TypeError
        If ``problem`` is not an AssignmentProblem or a count/threshold is not an int.
    ValueError
        On negative counts, thresholds < 1, unknown readings, start, scan or backend,
        ``workers < 1`` or an infeasible start state.

    Notes
    -----
    Spec §3.3: ``U = {x0}``; for each chain, ``x = x0`` and up to ``N_C`` sweeps, each one an
    observation added to ``U``; after each observation the stall rule may end the chain; after
    each chain the stale rule may end the run. With ``x[0] = x0`` and ``x[j]`` the chain's
    ``j``-th observation, the stall counter after observation ``j`` is

    * ``"global-consecutive"`` (S3, default): observations of this chain since its last
      observation that was new to ``U`` (or since ``x[0]``);
    * ``"global-cumulative"`` (S2): observations of this chain that were already in ``U``;
    * ``"chain-local"`` (S1): ``(j + 1) - NumUnique(x[0..j])``, the repeats among the
      chain's own states;

    and the chain stops when it reaches ``tau_stall``. After each completed chain the stale
    counter is

    * ``"consecutive"`` (T3, default): completed chains in a row, most recent last, that added
      no new assignment to ``U``;
    * ``"cumulative"`` (T2): completed chains, ever, that added nothing;
    * ``"literal-set"`` (T1, set): ``|x| - n_u`` with ``x`` the set of samples, i.e.
      ``|U| - |U| = 0``: never fires (implemented literally);
    * ``"literal-multiset"`` (T1, multiset): ``|x| - n_u`` with ``x`` the multiset holding
      each completed chain's ``x0`` once plus every observation, i.e.
      ``(chains + observations) - |U|``;

    and the run stops when it reaches ``tau_stale`` (``stop_reason = "stale"``). The paper's
    settings are ``N_S = 10 000, N_C = 25, tau_stall = 5, tau_stale = 25`` (synthetic study).

    Parallel runs (``workers > 1``, numba backend). A chain's trajectory depends only on its
    own stream and ``x0``; only where it stops depends on ``U`` (spec §3.3). Chains are
    therefore taken in batches (the first of ``max(64, 16 workers)`` chains, doubling up to
    about a millisecond of sweeps); within a batch every chain's first ``s`` sweeps are
    simulated in parallel, then the batch is replayed in chain order with the sequential
    stall/stale logic, continuing in the replay any chain that outlives its ``s`` sweeps.
    ``s`` is the ``1 - 1/workers`` quantile of the lengths of the chains replayed so far
    (all of ``N_C`` for the first batch), which balances parallel speculation against
    sequential continuation. Sweeps simulated but not used — the tail of a stalled chain, the
    rest of the batch after a stale stop — are reported in ``n_speculative_discarded``.

    References
    ----------
    .. [1] A. Trezza, D. J. Bucci Jr., P. K. Varshney, "On Gibbs Sampling Architecture for
       Labeled Random Finite Sets Multi-Object Tracking", arXiv:2306.15135, 2023.
    .. [2] B.-N. Vo, B.-T. Vo, H. G. Hoang, "An Efficient Implementation of the Generalized
       Labeled Multi-Bernoulli Filter", IEEE Trans. Signal Process. 65(8):1975-1987, 2017.

    Examples
    --------
    >>> from rankedassign import synthetic, sample_short_chains
    >>> p = synthetic.diagonal()
    >>> res = sample_short_chains(p, 10_000, 25, tau_stall=5, tau_stale=25, rng=3)
    >>> res.stop_reason, res.n_observations < 250_000
    ('stale', True)
    >>> par = sample_short_chains(p, 10_000, 25, tau_stall=5, tau_stale=25, rng=3, workers=2)
    >>> bool((par.assignments == res.assignments).all()), par.n_observations == res.n_observations
    (True, True)
    """
    _check_choice("backend", backend, BACKENDS)
    if backend == "python":
        from . import reference

        return reference.sample_short_chains(
            problem, n_chains, chain_length, tau_stall=tau_stall, tau_stale=tau_stale,
            stall=stall, stale=stale, start=start, scan=scan, rng=rng, workers=workers,
        )
    n_chains = _check_count("n_chains", n_chains)
    chain_length = _check_count("chain_length", chain_length)
    t_stall = _check_tau("tau_stall", tau_stall)
    t_stale = _check_tau("tau_stale", tau_stale)
    _check_choice("stall reading", stall, STALL_READINGS)
    _check_choice("stale reading", stale, STALE_READINGS)
    workers = _check_workers(workers)
    prep = _prepare(problem, start, scan, rng)
    stall_mode = STALL_READINGS[stall] if t_stall else 0
    stale_mode = STALE_READINGS[stale] if t_stale else 0
    batch = _batch_size(workers, n_chains, chain_length, prep.problem.n_rows,
                        prep.problem.n_meas)
    args = (
        prep.W, prep.cc, _zobrist(prep.problem), prep.x0, np.uint64(prep.base), n_chains,
        chain_length, stall_mode, t_stall, stale_mode, t_stale, prep.random_scan, batch, workers,
    )
    if batch:
        # Chains are handed to threads a few at a time (not one static share per thread), so
        # a thread slowed down by another process does not hold up the whole batch.
        with threads(workers), parallel_chunksize(_CHUNK):
            uniq, counts, ctr = _kernels.run_chains(*args)
    else:
        uniq, counts, ctr = _kernels.run_chains(*args)
    return _package(prep, uniq, counts, ctr[1], ctr[2], ctr[5], ctr[6])


def warmup() -> None:
    """Compile every sampler kernel (sequential, parallel, both scans) on a tiny problem.

    Call once before timing; the test suite calls it once per session. With numba's on-disk
    cache (the default) later processes load the compiled code instead.

    Examples
    --------
    >>> warmup()
    """
    # Row 0's cheapest entry (measurement 0) is ~800 below everything else: when row 1 holds
    # it, row 0's available weights underflow and the exact fall-back path runs too.
    p = AssignmentProblem.from_cost(
        [[-800.0, 0.0, 0.0, np.inf, 0.0, np.inf], [0.0, 0.0, np.inf, 0.0, np.inf, 0.0]]
    )
    for scan in SCANS:
        sample_original(p, 3, scan=scan, rng=0, start=[1, 0])
        sample_short_chains(p, 3, 2, tau_stall=1, tau_stale=1, scan=scan, rng=0)
        sample_short_chains(p, 3, 2, tau_stall=1, tau_stale=1, scan=scan, rng=0, workers=2)

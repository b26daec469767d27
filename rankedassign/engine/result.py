"""What every sampler run shares, whatever its kind: prepared inputs, rule checks, the result.

Both implementations of every sampler (:mod:`rankedassign.reference`, the specification of
record, and the compiled drivers run by :mod:`rankedassign.samplers`) start from the same
:class:`Prepared` inputs, validated once and with the weights computed once with numpy by the
kind's ``prepare`` (:class:`rankedassign.engine.kind.Kind`), and end in the same
:class:`SamplerResult`. Nothing here knows a problem kind.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..validation import (
    STALE_READINGS,
    STALL_READINGS,
    check_choice,
    check_int,
    check_optional_int,
)

__all__ = ["SamplerResult", "Prepared", "package", "SCANS", "BACKENDS", "zero_length_run",
           "check_rules", "check_chain_budget"]

SCANS = ("systematic", "random")
BACKENDS = ("numba", "python")


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
    n_keys : int
        Herded draw (:func:`rankedassign.sample_herded`): keys created in the chains' tables,
        summed over the chains; 0 for the Gibbs draw.
    n_fallbacks : int
        Herded draw: row updates that met a new key while their chain's table was full
        (``max_keys``) and drew as the Gibbs sampler does; 0 for the Gibbs draw.

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
    n_keys: int = 0
    n_fallbacks: int = 0

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
        Name of the problem kind (:func:`rankedassign.kinds.kind_named`).
    driver : str
        Which of the kind's compiled drivers runs it (a key of ``Kind.drivers``).
    problem : object
        The problem.
    data : named tuple
        The kernels' read-only arrays and scalars: the kind's data record (one numba type per
        driver; ``docs/structure.md``, "Kernel records").
    make_ref_data : callable
        ``() -> ref_data``.
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
    driver: str
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


# ------------------------------------------------------------------------------ arguments
def check_rules(tau_stall, tau_stale, stall, stale):
    """Validate the stall/stale thresholds and readings; return ``(tau_stall, tau_stale)``.

    ``None`` switches a rule off; a threshold is otherwise an int >= 1.

    Parameters
    ----------
    tau_stall : int or None
        Stall threshold (spec §3.2): a chain ends once this many of its observations were
        not new, counted as the ``stall`` reading says; ``None`` switches the rule off.
    tau_stale : int or None
        Stale threshold (spec §3.2): the run ends once this many chains added nothing new,
        counted as the ``stale`` reading says; ``None`` switches the rule off.
    stall : str
        Reading of the stall rule, a key of :data:`~rankedassign.validation.STALL_READINGS`
        (``"global-consecutive"``, ``"global-cumulative"``, ``"chain-local"``).
    stale : str
        Reading of the stale rule, a key of :data:`~rankedassign.validation.STALE_READINGS`
        (``"consecutive"``, ``"cumulative"``, ``"literal-set"``, ``"literal-multiset"``).

    Returns
    -------
    tau_stall, tau_stale : int or None
        The thresholds as Python ints, ``None`` where a rule is off.

    Raises
    ------
    TypeError
        If a threshold is neither ``None`` nor an int.
    ValueError
        If a threshold is below 1 or a reading is unknown.
    """
    tau_stall = check_optional_int(tau_stall, "tau_stall")
    tau_stale = check_optional_int(tau_stale, "tau_stale")
    check_choice(stall, "stall reading", STALL_READINGS)
    check_choice(stale, "stale reading", STALE_READINGS)
    return tau_stall, tau_stale


def check_chain_budget(n_chains, chain_length):
    """Validate ``N_S`` and ``N_C`` (ints in ``[0, 2**62]``).

    Parameters
    ----------
    n_chains : int
        ``N_S``, the number of short chains to run at most.
    chain_length : int
        ``N_C``, the sweeps (observations) per chain.

    Returns
    -------
    n_chains, chain_length : int
        Both as Python ints.

    Raises
    ------
    TypeError
        If either is not an int (``bool`` and floats included).
    ValueError
        If either is negative or above :data:`~rankedassign.validation.MAX_COUNT`.
    """
    return check_int(n_chains, "n_chains"), check_int(chain_length, "chain_length")


def zero_length_run(n_chains, tau_stale, stale):
    """Chains run and whether stale fired when every chain has no sweep (``N_C = 0``).

    Such a chain observes nothing and adds nothing to ``U``, so after ``c`` chains the stale
    counters are ``c`` (consecutive, cumulative), ``0`` (literal-set) and ``c - 1``
    (literal-multiset: ``c`` start states, no observation, ``|U| = 1``). Computed in closed
    form so that ``n_chains = 10**9`` returns at once instead of looping over empty chains.

    Parameters
    ----------
    n_chains : int
        ``N_S``, the chains allowed (already validated, ``>= 0``).
    tau_stale : int or None
        Stale threshold; ``None`` means the stale rule is off.
    stale : str
        Reading of the stale rule (a key of :data:`~rankedassign.validation.STALE_READINGS`).

    Returns
    -------
    n_chains_run : int
        Chains started before the run ends: ``n_chains``, or fewer if the stale rule fires.
    stale_fired : bool
        Whether the stale rule ended the run.

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


def package(prep: Prepared, states, counts, n_obs, n_chains_run, stale, discarded,
            tally=(0, 0)) -> SamplerResult:
    """Turn a run's unique states and counters into a :class:`SamplerResult`.

    Parameters
    ----------
    prep : Prepared
        The run's prepared inputs; ``prep.to_result`` maps states to assignments and costs and
        ``prep.rows`` gives the row updates per sweep.
    states : array_like of int, shape (n_unique, L) or (n_unique * L,)
        The unique states visited, in order of discovery (start state first), one row of
        ``L = prep.x0.shape[0]`` entries each (a flat buffer is reshaped).
    counts : array_like of int, shape (n_unique,)
        Observations of each state.
    n_obs : int
        Sweeps performed in total (= observations).
    n_chains_run : int
        Chains started.
    stale : bool
        Whether the stale rule ended the run (``stop_reason="stale"``).
    discarded : int
        Sweeps simulated ahead by the parallel kernel and not used (0 for sequential runs).
    tally : pair of int, optional
        The herded draw's ``(keys created, fall-back draws)``; ``(0, 0)`` otherwise.

    Returns
    -------
    SamplerResult
        The result record, with fresh read-only ``assignments``, ``costs`` and ``counts``
        arrays and ``n_row_updates = n_obs * prep.rows``.
    """
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
        n_keys=int(tally[0]),
        n_fallbacks=int(tally[1]),
    )

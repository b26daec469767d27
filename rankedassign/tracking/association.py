"""Pluggable association for the LMB filter: samplers, Murty's k-best, exact marginals.

An association object is called as ``assoc(problem, rng)`` on one
:class:`~rankedassign.AssignmentProblem` and returns an :class:`AssociationResult`: the
association marginals ``beta`` of shape ``(P, M + 2)`` (columns ``[meas 0..M-1 | missed |
dead]``, rows summing to 1) and the accounting of what it cost.

For the sampler and Murty methods ``beta`` is built from the set of unique hypotheses found,
each with its normalised weight ``w ∝ exp(−cost)`` (spec §6.3–6.4); :class:`Exact` returns the
exact marginals of the oracle (spec §5.2), i.e. the exact LMB update.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ..problem import AssignmentProblem

__all__ = [
    "AssociationResult",
    "Association",
    "OriginalGibbs",
    "ShortChainGibbs",
    "Murty",
    "Exact",
    "marginals_from_hypotheses",
]


class AssociationResult(NamedTuple):
    """Association marginals of one problem and the work spent on them.

    Attributes
    ----------
    beta : ndarray, shape (P, M + 2)
        ``beta[i, j]`` = weight of the hypotheses in which row ``i`` takes measurement ``j``;
        ``beta[i, M]`` missed, ``beta[i, M + 1]`` dead / not born. Rows sum to 1.
    invocations : int
        Number of solver calls (1 per problem).
    sweeps : int
        Markov-chain observations (full systematic sweeps); 0 for Murty and Exact.
    row_updates : int
        Single-row conditional draws; 0 for Murty and Exact.
    n_unique : int
        Number of unique hypotheses the marginals are built from (0 for :class:`Exact`, which
        sums over all of them implicitly).
    """

    beta: np.ndarray
    invocations: int
    sweeps: int
    row_updates: int
    n_unique: int


def marginals_from_hypotheses(problem: AssignmentProblem, assignments, costs=None) -> np.ndarray:
    """Association marginals from a set of unique hypotheses (spec eqs. 6.3–6.4).

    Parameters
    ----------
    problem : AssignmentProblem
    assignments : array_like of int, shape (H, P)
        Unique feasible assignments (column indices); duplicates would be counted twice.
    costs : array_like, shape (H,), optional
        Their costs (default: ``problem.cost_of(assignments)``).

    Returns
    -------
    ndarray, shape (P, M + 2)
        ``beta[i, j] = sum_h w_h 1[gamma_i^(h) = j]`` with ``w_h = exp(-cost_h) / sum exp(-cost)``
        computed by log-sum-exp; compact columns ``[meas | missed | dead]``.

    Raises
    ------
    ValueError
        If there is no hypothesis, shapes disagree or a cost is not finite.

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign import AssignmentProblem
    >>> from rankedassign.tracking.association import marginals_from_hypotheses
    >>> p = AssignmentProblem.from_eta([[3.0]], [1.0], [1.0])
    >>> marginals_from_hypotheses(p, [[0], [1], [2]]).round(2).tolist()   # all 3 hypotheses
    [[0.6, 0.2, 0.2]]
    """
    a = np.asarray(assignments, dtype=np.int64)
    P, M = problem.n_rows, problem.n_meas
    if a.ndim != 2 or a.shape[1] != P:
        raise ValueError(f"assignments must have shape (H, P) = (H, {P}), got {a.shape}")
    if a.shape[0] == 0:
        raise ValueError("at least one hypothesis is needed to form association marginals")
    c = problem.cost_of(a) if costs is None else np.asarray(costs, dtype=np.float64)
    if c.shape != (a.shape[0],):
        raise ValueError(f"costs must have shape ({a.shape[0]},), got {c.shape}")
    if not np.isfinite(c).all():
        raise ValueError("every hypothesis must be feasible (finite cost)")
    # w_h ∝ exp(-cost_h), normalised in log space (log-sum-exp)
    lw = -c - (-c).max()
    w = np.exp(lw)
    w /= w.sum()
    # compact column: measurement j -> j, missed (M + i) -> M, dead (M + P + i) -> M + 1
    compact = np.where(a < M, a, np.where(a < M + P, M, M + 1))
    flat = (np.arange(P)[None, :] * (M + 2) + compact).ravel()
    beta = np.bincount(flat, weights=np.repeat(w, P), minlength=P * (M + 2))
    return beta.reshape(P, M + 2)


class Association:
    """Base class of association methods: ``assoc(problem, rng) -> AssociationResult``.

    Subclass it (or pass any callable with that signature) to plug a new method into
    :class:`~rankedassign.tracking.lmb.LMBFilter`: return the marginals ``beta`` of shape
    ``(P, M + 2)`` and the accounting. ``rng`` is a :class:`numpy.random.Generator` spawned
    for this problem alone.

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign.tracking import Association, AssociationResult
    >>> class Best(Association):        # the single best hypothesis (a point estimate)
    ...     def __call__(self, problem, rng):
    ...         from scipy.optimize import linear_sum_assignment
    ...         C = np.where(np.isinf(problem.cost), 1e300, problem.cost)
    ...         _, cols = linear_sum_assignment(C)
    ...         beta = marginals_from_hypotheses(problem, cols[None, :])
    ...         return AssociationResult(beta, 1, 0, 0, 1)
    >>> from rankedassign import AssignmentProblem
    >>> p = AssignmentProblem.from_eta([[3.0]], [1.0], [1.0])
    >>> Best()(p, None).beta.tolist()
    [[1.0, 0.0, 0.0]]
    """

    name = "association"

    def __call__(self, problem: AssignmentProblem, rng) -> AssociationResult:  # pragma: no cover
        raise NotImplementedError


def _check_positive_int(value, name):
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
        raise TypeError(f"{name} must be an integer, got {type(value).__name__}")
    if value < 1:
        raise ValueError(f"{name} must be >= 1, got {value}")
    return int(value)


def _from_sampler(problem, res) -> AssociationResult:
    beta = marginals_from_hypotheses(problem, res.assignments, res.costs)
    return AssociationResult(
        beta, 1, int(res.n_observations), int(res.n_row_updates), int(len(res.costs))
    )


class OriginalGibbs(Association):
    """The original long-chain Gibbs sampler (Vo, Vo & Hoang 2017) as association.

    Parameters
    ----------
    n_obs : int
        Observations (full sweeps) per call (the paper: 10 000).
    **sampler_options
        Passed to :func:`rankedassign.sample_original` (e.g. ``start``, ``scan``, ``backend``).

    Examples
    --------
    >>> from rankedassign.tracking import OriginalGibbs
    >>> OriginalGibbs(10_000)
    OriginalGibbs(10000)
    """

    name = "original"

    def __init__(self, n_obs: int, **sampler_options):
        self.n_obs = _check_positive_int(n_obs, "n_obs")
        self.options = dict(sampler_options)

    def __repr__(self):
        extra = "".join(f", {k}={v!r}" for k, v in self.options.items())
        return f"OriginalGibbs({self.n_obs}{extra})"

    def __call__(self, problem, rng) -> AssociationResult:
        from .. import sample_original

        return _from_sampler(problem, sample_original(problem, self.n_obs, rng=rng, **self.options))


class ShortChainGibbs(Association):
    """The short-chain sampler with stall/stale termination (Trezza et al. 2023).

    Parameters
    ----------
    n_chains, chain_length : int
        ``N_S`` chains of ``N_C`` observations (the paper: 400 × 25).
    tau_stall, tau_stale : int or None
        Termination thresholds (the paper: 5 and 10); None disables a rule.
    **sampler_options
        Passed to :func:`rankedassign.sample_short_chains` (``stall``, ``stale``, ``start``,
        ``scan``, ``backend``, ``workers``).

    Examples
    --------
    >>> from rankedassign.tracking import ShortChainGibbs
    >>> ShortChainGibbs(400, 25, 5, 10)
    ShortChainGibbs(400, 25, tau_stall=5, tau_stale=10)
    """

    name = "short-chain"

    def __init__(self, n_chains: int, chain_length: int, tau_stall=None, tau_stale=None,
                 **sampler_options):
        self.n_chains = _check_positive_int(n_chains, "n_chains")
        self.chain_length = _check_positive_int(chain_length, "chain_length")
        self.tau_stall = None if tau_stall is None else _check_positive_int(tau_stall, "tau_stall")
        self.tau_stale = None if tau_stale is None else _check_positive_int(tau_stale, "tau_stale")
        self.options = dict(sampler_options)

    def __repr__(self):
        extra = "".join(f", {k}={v!r}" for k, v in self.options.items())
        return (f"ShortChainGibbs({self.n_chains}, {self.chain_length}, tau_stall={self.tau_stall}"
                f", tau_stale={self.tau_stale}{extra})")

    def __call__(self, problem, rng) -> AssociationResult:
        from .. import sample_short_chains

        res = sample_short_chains(
            problem, self.n_chains, self.chain_length, tau_stall=self.tau_stall,
            tau_stale=self.tau_stale, rng=rng, **self.options,
        )
        return _from_sampler(problem, res)


class Murty(Association):
    """Murty's k best assignments (Murty 1968; the oracle's implementation) as association.

    Parameters
    ----------
    k : int
        Number of best hypotheses per call.
    method : {"numba", "scipy"}
        Passed to :func:`oracle.murty`.

    Examples
    --------
    >>> from rankedassign.tracking import Murty
    >>> Murty(1000)
    Murty(1000)
    """

    name = "murty"

    def __init__(self, k: int, *, method: str = "numba"):
        self.k = _check_positive_int(k, "k")
        self.method = method

    def __repr__(self):
        if self.method == "numba":
            return f"Murty({self.k})"
        return f"Murty({self.k}, method={self.method!r})"

    def __call__(self, problem, rng) -> AssociationResult:
        import oracle

        ranked = oracle.murty(problem, self.k, method=self.method)
        beta = marginals_from_hypotheses(problem, ranked.assignments, ranked.costs)
        return AssociationResult(beta, 1, 0, 0, int(len(ranked.costs)))


class Exact(Association):
    """Exact association marginals (spec §5.2, :func:`oracle.marginals`): the exact LMB update.

    The oracle solves each connected component of the gated problem separately, densely when
    ``min(P_c, M_c) <= 20`` and otherwise by a frontier DP over the measurements (at most
    ``2^20`` states); it raises ``ValueError`` on a component beyond both limits. On the
    paper's preset (one group of about 23 rows and 50 gated measurements per scan) every scan
    of seeds 0-4 is solved, in about 10 ms per scan; the filter's grouping (spec §6.5a) keeps
    problems small on presets with narrow births.

    Examples
    --------
    >>> from rankedassign.tracking import Exact
    >>> Exact()
    Exact()
    """

    name = "exact"

    def __repr__(self):
        return "Exact()"

    def __call__(self, problem, rng) -> AssociationResult:
        import oracle

        beta = np.array(oracle.marginals(problem), dtype=np.float64)
        return AssociationResult(beta, 1, 0, 0, 0)

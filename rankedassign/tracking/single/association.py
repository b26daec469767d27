"""Pluggable association for the LMB filter: samplers, Murty's k-best, exact marginals.

An association object is called as ``assoc(problem, rng)`` on one
:class:`~rankedassign.AssignmentProblem` and returns an :class:`AssociationResult`: the
association marginals ``beta`` of shape ``(P, M + 2)`` (columns ``[meas 0..M-1 | missed |
dead]``, rows summing to 1) and the accounting of what it cost.

For the sampler and Murty methods ``beta`` is built from the set of unique hypotheses found,
each with its normalised weight ``w ∝ exp(−cost)`` (spec §6.3–6.4); :class:`Exact` returns the
exact marginals of the oracle (spec §5.2), i.e. the exact LMB update.

``marginals="rao-blackwell"`` (an extension, not the paper's method) replaces the indicator
of the hypothesis' own choice by the conditional distribution of each row given the other rows
of the hypothesis, :func:`marginals_from_hypotheses` explains it.
"""

from __future__ import annotations

import warnings
from typing import NamedTuple

import numpy as np

import oracle

from ...engine.herding import DEFAULT_MAX_KEYS, Herding
from ...numba_options import interruptible, jit
from ...samplers import sample_herded, sample_original, sample_short_chains
from ...single.lbp import LBP_MAX_ITER, LBP_TOL, check_lbp_settings, lbp_marginals
from ...single.problem import AssignmentProblem
from ...validation import check_choice, check_int, check_optional_int
from .. import _kernels

__all__ = [
    "AssociationResult",
    "Association",
    "Hypotheses",
    "OriginalGibbs",
    "ShortChainGibbs",
    "Murty",
    "Exact",
    "HerdedGibbs",
    "LBP",
    "LBPConvergenceWarning",
    "marginals_from_hypotheses",
    "MARGINALS",
]

#: How association marginals are formed from a set of hypotheses (``marginals=`` of the
#: sampler and Murty associations, ``marginals=`` of :func:`marginals_from_hypotheses`).
MARGINALS = ("truncated", "rao-blackwell")
#: Implementations of Murty's method (``backend=`` of :class:`Murty` and :func:`oracle.murty`).
MURTY_BACKENDS = ("numba", "scipy")


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


@jit()
def _rao_blackwell(cost, a, w, M, ptr, cols):  # pragma: no cover (jit)
    """Σ_h w_h π(γ_i = · | γ_{−i}^(h)) for every row ``i``, compact columns.

    ``ptr``/``cols``: CSR lists of the finite measurement columns of every row.
    """
    H, P = a.shape
    beta = np.zeros((P, M + 2))
    occupied = np.zeros(M, dtype=np.bool_)
    lp = np.empty(M + 2)
    for h in range(H):
        for i in range(P):
            if a[h, i] < M:
                occupied[a[h, i]] = True
        for i in range(P):
            own = a[h, i]
            # log-weights of the options row i has while the other rows stay put: a free
            # measurement (or its own), missed, dead
            top = -np.inf
            for k in range(ptr[i], ptr[i + 1]):
                j = cols[k]
                v = -cost[i, j] if (j == own or not occupied[j]) else -np.inf
                lp[k - ptr[i]] = v
                top = max(top, v)
            n = ptr[i + 1] - ptr[i]
            lm = -cost[i, M + i]
            ld = -cost[i, M + P + i]
            top = max(top, max(lm, ld))
            tot = 0.0
            for k in range(n):
                lp[k] = np.exp(lp[k] - top)
                tot += lp[k]
            em = np.exp(lm - top)
            ed = np.exp(ld - top)
            tot += em + ed
            f = w[h] / tot
            for k in range(n):
                beta[i, cols[ptr[i] + k]] += f * lp[k]
            beta[i, M] += f * em
            beta[i, M + 1] += f * ed
        for i in range(P):
            if a[h, i] < M:
                occupied[a[h, i]] = False
    return beta


def marginals_from_hypotheses(
    problem: AssignmentProblem, assignments, costs=None, *, marginals: str = "truncated"
) -> np.ndarray:
    """Association marginals from a set of unique hypotheses (spec eqs. 6.3–6.4).

    Parameters
    ----------
    problem : AssignmentProblem
    assignments : array_like of int, shape (H, P)
        Unique feasible assignments (column indices); duplicates would be counted twice.
    costs : array_like, shape (H,), optional
        Their costs (default: ``problem.cost_of(assignments)``).
    marginals : {"truncated", "rao-blackwell"}, optional
        ``"truncated"`` (default, the paper's and Vo's construction): the marginals of the
        truncated GLMB, ``beta[i, j] = Σ_h w_h 1[γ_i^(h) = j]``. ``"rao-blackwell"``:
        ``beta[i, j] = Σ_h w_h π(γ_i = j | γ_{−i}^(h))``, each hypothesis contributing row
        ``i``'s conditional distribution given its other rows (the distribution a Gibbs row
        update draws from) instead of the indicator of its own choice.

    Returns
    -------
    ndarray, shape (P, M + 2)
        Compact columns ``[meas | missed | dead]``; rows sum to 1. ``w_h = exp(−cost_h) /
        Σ exp(−cost)`` is computed by log-sum-exp.

    Raises
    ------
    ValueError
        If there is no hypothesis, shapes disagree, a cost is not finite or ``marginals`` is
        unknown.

    Notes
    -----
    Both are exact when the set holds every feasible hypothesis: the Rao-Blackwellised sum
    then runs over ``γ_{−i}`` with weights ``π(γ_{−i})`` (Gelfand & Smith 1990; Casella &
    Robert 1996). On a truncated set they differ where it matters to a filter: a hypothesis of
    small weight that no chain visited, such as "this newborn track exists but was not
    detected", gets no weight in the truncated marginals, so the track's existence is 0 and
    it is pruned; the Rao-Blackwellised marginals give it its conditional weight next to every
    hypothesis that was visited. The cost is one pass over the feasible options of every row
    per hypothesis, like one Gibbs sweep per hypothesis, and no further sampling.

    References
    ----------
    .. [1] A. E. Gelfand, A. F. M. Smith, "Sampling-Based Approaches to Calculating Marginal
       Densities", J. Amer. Statist. Assoc. 85(410), 1990.
    .. [2] G. Casella, C. P. Robert, "Rao-Blackwellisation of sampling schemes", Biometrika
       83(1), 1996.

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign import AssignmentProblem
    >>> from rankedassign.tracking.single.association import marginals_from_hypotheses
    >>> p = AssignmentProblem.from_eta([[3.0]], [1.0], [1.0])
    >>> marginals_from_hypotheses(p, [[0], [1], [2]]).round(2).tolist()   # all 3 hypotheses
    [[0.6, 0.2, 0.2]]
    >>> marginals_from_hypotheses(p, [[0]]).tolist()                      # the best alone
    [[1.0, 0.0, 0.0]]
    >>> marginals_from_hypotheses(p, [[0]], marginals="rao-blackwell").round(2).tolist()
    [[0.6, 0.2, 0.2]]
    """
    check_choice(marginals, "marginals", MARGINALS)
    a = np.asarray(assignments, dtype=np.int64)
    P = problem.n_rows
    if a.ndim != 2 or a.shape[1] != P:
        raise ValueError(f"assignments must have shape (H, P) = (H, {P}), got {a.shape}")
    if a.shape[0] == 0:
        raise ValueError("at least one hypothesis is needed to form association marginals")
    c = problem.cost_of(a) if costs is None else np.asarray(costs, dtype=np.float64)
    if c.shape != (a.shape[0],):
        raise ValueError(f"costs must have shape ({a.shape[0]},), got {c.shape}")
    if not np.isfinite(c).all():
        raise ValueError("every hypothesis must be feasible (finite cost)")
    return _marginals(problem, a, c, marginals)


def _marginals(problem: AssignmentProblem, a: np.ndarray, c: np.ndarray, method: str):
    """:func:`marginals_from_hypotheses` on inputs already checked (a sampler's own output)."""
    M = problem.n_meas
    c = np.asarray(c, dtype=np.float64)
    # w_h ∝ exp(-cost_h), normalised in log space (log-sum-exp)
    lw = -c - (-c).max()
    w = np.exp(lw)
    w /= w.sum()
    a = np.ascontiguousarray(a, dtype=np.int64)
    if method == "rao-blackwell":
        C = np.ascontiguousarray(problem.cost, dtype=np.float64)
        finite = np.isfinite(C[:, :M])
        ptr = np.concatenate([[0], np.cumsum(finite.sum(axis=1))]).astype(np.int64)
        cols = np.nonzero(finite)[1].astype(np.int64)
        with interruptible:
            return _rao_blackwell(C, a, w, M, ptr, cols)
    with interruptible:
        return _kernels.truncated_marginals(a, w, M)


class Hypotheses(NamedTuple):
    """The unique assignments a truncation keeps of one component's problem.

    Attributes
    ----------
    assignments : ndarray of int64, shape (n, P)
        Unique feasible assignments (column indices of the problem's cost matrix).
    costs : ndarray, shape (n,)
        Their costs ``Σ_i −ln η_i(γ_i)``.
    sweeps, row_updates : int
        Markov-chain observations and single-row draws spent (0 for Murty and enumeration).
    """

    assignments: np.ndarray
    costs: np.ndarray
    sweeps: int = 0
    row_updates: int = 0


class Association:
    """Base class of association methods: ``assoc(problem, rng) -> AssociationResult``.

    Subclass it (or pass any callable with that signature) to plug a new method into
    :class:`~rankedassign.tracking.LMBFilter`: return the marginals ``beta`` of shape
    ``(P, M + 2)`` and the accounting. A forbidden pair (cost ``+inf``, outside the gate) must
    have marginal 0; the filter refuses anything else. ``rng`` is a
    :class:`numpy.random.Generator` spawned for this problem alone.

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
    #: The problems it solves: ``"single-sensor"`` (the filters refuse an association of the
    #: other kind by this attribute).
    sensors = "single-sensor"

    def __call__(self, problem: AssignmentProblem, rng) -> AssociationResult:  # pragma: no cover
        raise NotImplementedError


def _check_marginals(marginals):
    return check_choice(marginals, "marginals", MARGINALS)


def _marginals_repr(marginals):
    return "" if marginals == "truncated" else f", marginals={marginals!r}"


def _from_sampler(problem, res, marginals) -> AssociationResult:
    beta = _marginals(problem, res.assignments, res.costs, marginals)
    return AssociationResult(
        beta=beta, invocations=1, sweeps=int(res.n_observations),
        row_updates=int(res.n_row_updates), n_unique=int(len(res.costs)),
    )


class OriginalGibbs(Association):
    """The original long-chain Gibbs sampler (Vo, Vo & Hoang 2017) as association.

    Parameters
    ----------
    n_obs : int
        Observations (full sweeps) per call (the paper: 10 000).
    marginals : {"truncated", "rao-blackwell"}, optional
        How the unique hypotheses become association marginals
        (:func:`marginals_from_hypotheses`); ``"truncated"`` is the paper's construction.
    **sampler_options
        Passed to :func:`rankedassign.sample_original` (e.g. ``start``, ``scan``, ``backend``).

    Examples
    --------
    >>> from rankedassign.tracking import OriginalGibbs
    >>> OriginalGibbs(10_000)
    OriginalGibbs(10000)
    """

    name = "original"

    def __init__(self, n_obs: int, *, marginals: str = "truncated", **sampler_options):
        self.n_obs = check_int(n_obs, "n_obs", minimum=1)
        self.marginals = _check_marginals(marginals)
        self.options = dict(sampler_options)

    def __repr__(self):
        extra = "".join(f", {k}={v!r}" for k, v in self.options.items())
        return f"OriginalGibbs({self.n_obs}{_marginals_repr(self.marginals)}{extra})"

    def __call__(self, problem, rng) -> AssociationResult:
        res = sample_original(problem, self.n_obs, rng=rng, **self.options)
        return _from_sampler(problem, res, self.marginals)


class ShortChainGibbs(Association):
    """The short-chain sampler with stall/stale termination (Trezza et al. 2023).

    Parameters
    ----------
    n_chains, chain_length : int
        ``N_S`` chains of ``N_C`` observations (the paper: 400 × 25).
    tau_stall, tau_stale : int or None
        Termination thresholds (the paper: 5 and 10); None disables a rule.
    marginals : {"truncated", "rao-blackwell"}, optional
        How the unique hypotheses become association marginals
        (:func:`marginals_from_hypotheses`); ``"truncated"`` is the paper's construction.
        The short chains stop after a few dozen sweeps and miss hypotheses of a few per mille,
        e.g. a newborn track that exists but was not detected; ``"rao-blackwell"`` restores
        their weight (the Tracking page of the documentation shows what that changes).
    **sampler_options
        Passed to :func:`rankedassign.sample_short_chains` (``stall``, ``stale``, ``start``,
        ``scan``, ``backend``, ``workers``).

    Examples
    --------
    >>> from rankedassign.tracking import ShortChainGibbs
    >>> ShortChainGibbs(400, 25, tau_stall=5, tau_stale=10)
    ShortChainGibbs(400, 25, tau_stall=5, tau_stale=10)
    >>> ShortChainGibbs(400, 25, tau_stall=5, tau_stale=10, marginals="rao-blackwell")
    ShortChainGibbs(400, 25, tau_stall=5, tau_stale=10, marginals='rao-blackwell')
    """

    name = "short-chain"

    def __init__(self, n_chains: int, chain_length: int, *, tau_stall=None, tau_stale=None,
                 marginals: str = "truncated", **sampler_options):
        self.n_chains = check_int(n_chains, "n_chains", minimum=1)
        self.chain_length = check_int(chain_length, "chain_length", minimum=1)
        self.tau_stall = check_optional_int(tau_stall, "tau_stall", minimum=1)
        self.tau_stale = check_optional_int(tau_stale, "tau_stale", minimum=1)
        self.marginals = _check_marginals(marginals)
        self.options = dict(sampler_options)

    def __repr__(self):
        extra = "".join(f", {k}={v!r}" for k, v in self.options.items())
        return (f"ShortChainGibbs({self.n_chains}, {self.chain_length}, tau_stall={self.tau_stall}"
                f", tau_stale={self.tau_stale}{_marginals_repr(self.marginals)}{extra})")

    def __call__(self, problem, rng) -> AssociationResult:
        res = sample_short_chains(
            problem, self.n_chains, self.chain_length, tau_stall=self.tau_stall,
            tau_stale=self.tau_stale, rng=rng, **self.options,
        )
        return _from_sampler(problem, res, self.marginals)


class HerdedGibbs(Association):
    """Herded Gibbs (Chen et al. 2016, :func:`rankedassign.sample_herded`) as association.

    One deterministic herded chain of ``n_obs`` sweeps, or, with ``n_chains``, herded short
    chains with seeded initial weights and the paper's stall/stale rules
    (:func:`rankedassign.sample_short_chains` with ``herding=``).

    Parameters
    ----------
    n_obs : int
        Sweeps of the one chain, or the length ``N_C`` of each short chain.
    keys : {"shared", "full"}
        The herding keys (:class:`rankedassign.Herding`).
    init : {"conditional", "zero", "uniform"} or None
        Initial weights; None (default): ``"conditional"`` for one chain, ``"uniform"`` for
        short chains (so that they differ).
    max_keys : int
        Bound of each chain's key table.
    n_chains : int or None
        None (default): one chain. Otherwise ``N_S`` short chains of ``n_obs`` sweeps.
    tau_stall, tau_stale : int or None
        The short chains' rules (ignored for one chain).
    marginals : {"truncated", "rao-blackwell"}, optional
        How the unique hypotheses become association marginals
        (:func:`marginals_from_hypotheses`).
    **sampler_options
        Passed to the sampler (``start``, ``scan``, ``beta``, ``backend``, ``workers`` for
        short chains).

    Examples
    --------
    >>> from rankedassign.tracking import HerdedGibbs
    >>> HerdedGibbs(1000)
    HerdedGibbs(1000)
    >>> HerdedGibbs(25, n_chains=400, tau_stall=5, tau_stale=10, keys="full")
    HerdedGibbs(25, keys='full', n_chains=400, tau_stall=5, tau_stale=10)
    """

    name = "herded"

    def __init__(self, n_obs: int, *, keys: str = "shared", init=None,
                 max_keys: int = DEFAULT_MAX_KEYS, n_chains=None, tau_stall=None,
                 tau_stale=None, marginals: str = "truncated", **sampler_options):
        self.n_obs = check_int(n_obs, "n_obs", minimum=1)
        self.n_chains = check_optional_int(n_chains, "n_chains", minimum=1)
        default_init = "conditional" if self.n_chains is None else "uniform"
        self.herding = Herding(keys=keys, init=default_init if init is None else init,
                               max_keys=max_keys)
        self.init_given = init
        self.tau_stall = check_optional_int(tau_stall, "tau_stall", minimum=1)
        self.tau_stale = check_optional_int(tau_stale, "tau_stale", minimum=1)
        self.marginals = _check_marginals(marginals)
        self.options = dict(sampler_options)

    def __repr__(self):
        h = self.herding
        parts = [str(self.n_obs)]
        if h.keys != "shared":
            parts.append(f"keys={h.keys!r}")
        if self.init_given is not None:
            parts.append(f"init={h.init!r}")
        if h.max_keys != DEFAULT_MAX_KEYS:
            parts.append(f"max_keys={h.max_keys}")
        if self.n_chains is not None:
            parts.append(f"n_chains={self.n_chains}, tau_stall={self.tau_stall}, "
                         f"tau_stale={self.tau_stale}")
        extra = "".join(f", {k}={v!r}" for k, v in self.options.items())
        return f"HerdedGibbs({', '.join(parts)}{_marginals_repr(self.marginals)}{extra})"

    def __call__(self, problem, rng) -> AssociationResult:
        res = self._sample(problem, self.n_chains or 1, self.n_obs, rng)
        return _from_sampler(problem, res, self.marginals)

    def _sample(self, problem, n_chains: int, length: int, rng):
        h = self.herding
        if self.n_chains is None:
            return sample_herded(problem, length, keys=h.keys, init=h.init,
                                 max_keys=h.max_keys, rng=rng, **self.options)
        return sample_short_chains(problem, n_chains, length, tau_stall=self.tau_stall,
                                   tau_stale=self.tau_stale, rng=rng, herding=h,
                                   **self.options)

    def hypotheses(self, problem, budget: int, rng):
        """The δ-GLMB truncation of one component's problem with the count ``budget = T_h``.

        The rule of the Gibbs truncations (:class:`~rankedassign.tracking.GLMBFilter`): ``T_h``
        counts stored solutions with the start state, so the herded draw gets ``n = T_h − 1``
        observations, at most its own budget: one chain of ``min(n, n_obs)`` sweeps, or
        ``min(n_chains, ⌈n / L⌉)`` short chains of ``L = min(n_obs, n)``. ``n = 0`` gives
        the start state alone.

        Parameters
        ----------
        problem : AssignmentProblem
        budget : int
            The component's count ``T_h >= 0``.
        rng : optional
            Anything :func:`numpy.random.default_rng` accepts.

        Returns
        -------
        Hypotheses
            The unique assignments, their costs, and the sweeps and row updates spent.

        Examples
        --------
        >>> from rankedassign import synthetic
        >>> from rankedassign.tracking import HerdedGibbs
        >>> hyp = HerdedGibbs(1000).hypotheses(synthetic.random(rng=0), 51, rng=0)
        >>> hyp.sweeps, len(hyp.costs) <= 51
        (50, True)
        >>> HerdedGibbs(25, n_chains=4).hypotheses(synthetic.random(rng=0), 1, rng=0).sweeps
        0
        """
        n = max(check_int(budget, "budget", minimum=0) - 1, 0)
        if n == 0:
            one = {k: v for k, v in self.options.items() if k != "workers"}
            res = sample_herded(problem, 0, rng=rng, **one)  # the start state alone
        elif self.n_chains is None:
            res = self._sample(problem, 1, min(n, self.n_obs), rng)
        else:
            length = min(self.n_obs, n)
            res = self._sample(problem, min(self.n_chains, -(-n // length)), length, rng)
        return Hypotheses(res.assignments, res.costs, int(res.n_observations),
                          int(res.n_row_updates))


class Murty(Association):
    """Murty's k best assignments (Murty 1968; the oracle's implementation) as association.

    Parameters
    ----------
    k : int
        Number of best hypotheses per call.
    backend : {"numba", "scipy"}
        The implementation of :func:`oracle.murty`.
    marginals : {"truncated", "rao-blackwell"}, optional
        How the k best hypotheses become association marginals
        (:func:`marginals_from_hypotheses`).

    Examples
    --------
    >>> from rankedassign.tracking import Murty
    >>> Murty(1000)
    Murty(1000)
    """

    name = "murty"

    def __init__(self, k: int, *, backend: str = "numba", marginals: str = "truncated"):
        self.k = check_int(k, "k", minimum=1)
        self.backend = check_choice(backend, "backend", MURTY_BACKENDS)
        self.marginals = _check_marginals(marginals)

    def __repr__(self):
        extra = "" if self.backend == "numba" else f", backend={self.backend!r}"
        return f"Murty({self.k}{extra}{_marginals_repr(self.marginals)})"

    def __call__(self, problem, rng) -> AssociationResult:
        ranked = oracle.murty(problem, self.k, backend=self.backend)
        beta = _marginals(problem, ranked.assignments, ranked.costs, self.marginals)
        return AssociationResult(beta=beta, invocations=1, sweeps=0, row_updates=0,
                                 n_unique=int(len(ranked.costs)))


class Exact(Association):
    """Exact association marginals (spec §5.2, :func:`oracle.marginals`): the exact LMB update.

    The oracle solves each connected component of the gated problem separately, densely when
    ``min(P_c, M_c) <= 20`` and otherwise by a frontier DP over the measurements (at most
    ``2^20`` states); it raises ``ValueError`` on a component beyond both limits. The problems
    of the paper's preset (one group of some 20 rows and 60 gated measurements per scan) are
    within the frontier DP's reach (sizes and times on the Tracking page of the
    documentation); the filter's grouping (spec §6.5a) keeps problems small on presets with
    narrow births.

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
        beta = np.array(oracle.marginals(problem), dtype=np.float64)
        return AssociationResult(beta=beta, invocations=1, sweeps=0, row_updates=0, n_unique=0)


class LBPConvergenceWarning(RuntimeWarning):
    """Loopy belief propagation stopped at ``max_iter`` before its messages settled."""


class LBP(Association):
    """Loopy belief propagation (Williams & Lau 2014, :func:`rankedassign.lbp_marginals`).

    Approximate association marginals from message passing, without sampling or
    enumeration: exact when no two tracks gate the same measurement, at most 0.002 from the
    exact marginals on 200 of the paper's random ``4 x 24`` matrices (0.071 on one gated
    30-track problem with a tight loop), and tens of times faster than :class:`Exact` on a
    30-track problem (the Herding, tempering and belief propagation page of the documentation
    has the measurements). It gives marginals only, so it serves the LMB filter, not the
    δ-GLMB filter (which needs hypotheses).

    Parameters
    ----------
    tol : float, optional
        Stop when no message changes by more than ``tol`` (default ``1e-9``).
    max_iter : int, optional
        Iteration cap (default 1000). A call that reaches it keeps its last beliefs, emits an
        :class:`LBPConvergenceWarning` naming the problem's size and the last change, and is
        counted in :attr:`n_unconverged`.

    Attributes
    ----------
    n_calls, n_unconverged : int
        Calls made and calls that stopped at ``max_iter`` (in this process).
    iterations : int
        Iterations over all calls.

    References
    ----------
    .. [1] J. Williams, R. Lau, "Approximate evaluation of marginal association probabilities
       with belief propagation", IEEE Trans. Aerosp. Electron. Syst. 50(4):2942-2959, 2014.

    Examples
    --------
    >>> from rankedassign import AssignmentProblem
    >>> from rankedassign.tracking import LBP
    >>> assoc = LBP()
    >>> assoc
    LBP()
    >>> p = AssignmentProblem.from_eta([[2.0]], [0.5], [0.25])
    >>> assoc(p, None).beta.round(6).tolist()
    [[0.727273, 0.181818, 0.090909]]
    >>> assoc.n_calls, assoc.n_unconverged
    (1, 0)
    """

    name = "lbp"

    def __init__(self, *, tol: float = LBP_TOL, max_iter: int = LBP_MAX_ITER):
        self.tol, self.max_iter = check_lbp_settings(tol, max_iter)
        self.n_calls = 0
        self.n_unconverged = 0
        self.iterations = 0

    def __repr__(self):
        parts = []
        if self.tol != LBP_TOL:
            parts.append(f"tol={self.tol!r}")
        if self.max_iter != LBP_MAX_ITER:
            parts.append(f"max_iter={self.max_iter!r}")
        return f"LBP({', '.join(parts)})"

    def __call__(self, problem, rng) -> AssociationResult:
        res = lbp_marginals(problem, tol=self.tol, max_iter=self.max_iter)
        self.n_calls += 1
        self.iterations += res.iterations
        if not res.converged:
            self.n_unconverged += 1
            warnings.warn(
                f"loopy belief propagation did not converge within max_iter={self.max_iter} "
                f"iterations on a {problem.n_rows} x {problem.n_meas} problem (last message "
                f"change {res.change:.3g} > tol={self.tol:g}); its last beliefs are used",
                LBPConvergenceWarning, stacklevel=2,
            )
        return AssociationResult(beta=res.marginals, invocations=1, sweeps=0, row_updates=0,
                                 n_unique=0)

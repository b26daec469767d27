"""Association for the multi-sensor LMB filter: Gibbs samplers, short chains, exact marginals.

A multi-sensor association is called as ``assoc(problem, rng)`` on one
:class:`~rankedassign.multisensor.MultiSensorProblem` and returns a
:class:`MultiSensorAssociationResult`: the marginals ``dead`` (``P(γ_n = −1)``, shape ``(P,)``)
and ``tuples`` (``P(γ_n = t)``, shape ``(P, M_1+1, ..., M_V+1)``), which are the ``β_{n,t}`` of
multi-sensor spec §7.4, and the accounting of what they cost.

The sampler associations form the marginals from the unique hypotheses found, each weighted by
``w ∝ ∏_n η_n(γ_n)`` (spec §7.4); ``marginals="rao-blackwell"`` replaces the indicator of each
row's own tuple by the row's conditional distribution given the other rows of the hypothesis
(as :func:`rankedassign.tracking.single.association.marginals_from_hypotheses` does for one sensor).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

import oracle

from ...engine.herding import DEFAULT_MAX_KEYS, Herding
from ...multisensor import MultiSensorProblem
from ...numba_options import interruptible, jit
from ...samplers import sample_herded, sample_original, sample_short_chains
from ...validation import check_choice, check_int, check_optional_int
from ..single.association import MARGINALS, Association

__all__ = [
    "MULTISENSOR_METHODS",
    "MultiSensorAssociation",
    "MultiSensorAssociationResult",
    "MultiSensorExact",
    "MultiSensorHerdedGibbs",
    "MultiSensorOriginalGibbs",
    "MultiSensorShortChainGibbs",
    "multisensor_marginals_from_hypotheses",
]

#: Multi-sensor Gibbs kernels (``method=`` of :func:`rankedassign.sample_original`).
MULTISENSOR_METHODS = ("exact", "mm", "mm-fixed", "componentwise")


class MultiSensorAssociationResult(NamedTuple):
    """Association marginals of one multi-sensor problem and the work spent on them.

    Attributes
    ----------
    dead : ndarray, shape (P,)
        ``P(γ_n = −1)``.
    tuples : ndarray, shape (P, M_1+1, ..., M_V+1)
        ``P(γ_n = t)``; ``dead[n] + tuples[n].sum() = 1``.
    invocations : int
        Solver calls (1 per problem).
    sweeps : int
        Markov-chain observations (full sweeps); 0 for the exact DP.
    row_updates : int
        Single-row conditional draws; 0 for the exact DP.
    n_unique : int
        Unique hypotheses the marginals are built from (0 for the exact DP).
    """

    dead: np.ndarray
    tuples: np.ndarray
    invocations: int
    sweeps: int
    row_updates: int
    n_unique: int


@jit()
def _truncated(flat, dead_h, w, n_t):  # pragma: no cover (jit)
    """Σ_h w_h 1[γ_n^(h) = t] for flat tuple indices ``flat`` (H, P); ``dead_h`` marks −1."""
    H, P = flat.shape
    dead = np.zeros(P)
    tup = np.zeros((P, n_t))
    for h in range(H):
        for n in range(P):
            if dead_h[h, n]:
                dead[n] += w[h]
            else:
                tup[n, flat[h, n]] += w[h]
    return dead, tup


@jit()
def _rao_blackwell(g, w, log_dead, ptr, opt_tuple, opt_flat, opt_logw, n_t, n_meas):
    # pragma: no cover (jit)
    """Σ_h w_h π(γ_n = · | γ_{−n}^(h)) over the finite options of every row.

    ``g`` (H, P, V) hypotheses; ``ptr`` CSR offsets of each row's options ``opt_tuple`` (K, V),
    their flat tensor indices ``opt_flat`` and log-weights ``opt_logw``.
    """
    H, P, V = g.shape
    dead = np.zeros(P)
    tup = np.zeros((P, n_t))
    max_m = 0
    for v in range(V):
        max_m = max(max_m, n_meas[v])
    used = np.zeros((V, max_m + 1), dtype=np.int64)  # how many rows use measurement j
    lp = np.empty(opt_flat.size)
    for h in range(H):
        for n in range(P):
            if g[h, n, 0] >= 0:
                for v in range(V):
                    if g[h, n, v] > 0:
                        used[v, g[h, n, v]] += 1
        for n in range(P):
            own = g[h, n]
            top = log_dead[n]
            for k in range(ptr[n], ptr[n + 1]):
                ok = True
                for v in range(V):
                    j = opt_tuple[k, v]
                    if j > 0:
                        held = used[v, j] - (1 if (own[0] >= 0 and own[v] == j) else 0)
                        if held > 0:
                            ok = False
                            break
                lp[k] = opt_logw[k] if ok else -np.inf
                top = max(top, lp[k])
            tot = np.exp(log_dead[n] - top)
            for k in range(ptr[n], ptr[n + 1]):
                lp[k] = np.exp(lp[k] - top)
                tot += lp[k]
            f = w[h] / tot
            dead[n] += f * np.exp(log_dead[n] - top)
            for k in range(ptr[n], ptr[n + 1]):
                tup[n, opt_flat[k]] += f * lp[k]
        for n in range(P):
            if g[h, n, 0] >= 0:
                for v in range(V):
                    if g[h, n, v] > 0:
                        used[v, g[h, n, v]] -= 1
    return dead, tup


def multisensor_marginals_from_hypotheses(problem: MultiSensorProblem, assignments,
                                          costs=None, *, marginals: str = "truncated"):
    """Association marginals of a multi-sensor problem from a set of unique hypotheses.

    Parameters
    ----------
    problem : MultiSensorProblem
    assignments : array_like of int, shape (H, P, V)
        Unique feasible assignments (``−1`` rows dead, else per sensor ``0`` missed or ``j``).
    costs : array_like, shape (H,), optional
        Their costs ``−ln w`` (default ``problem.cost_of(assignments)``).
    marginals : {"truncated", "rao-blackwell"}, optional
        ``"truncated"``: ``β_{n,t} = Σ_h w_h 1[γ_n^(h) = t]`` (multi-sensor spec §7.4).
        ``"rao-blackwell"``: ``β_{n,t} = Σ_h w_h π(γ_n = t | γ_{−n}^(h))``.

    Returns
    -------
    dead : ndarray, shape (P,)
    tuples : ndarray, shape (P, M_1+1, ..., M_V+1)
        ``dead[n] + tuples[n].sum() = 1``.

    Raises
    ------
    ValueError
        If there is no hypothesis, the shapes disagree or a hypothesis is infeasible.

    Notes
    -----
    Both are exact on the full feasible set (Gelfand & Smith 1990; Casella & Robert 1996); on
    a truncated set the Rao-Blackwellised marginals give each row its conditional weight on
    options no sampled hypothesis holds (a newborn track that exists but was missed).

    References
    ----------
    .. [1] B.-N. Vo, B.-T. Vo, M. Beard, "Multi-Sensor Multi-Object Tracking with the
       Generalized Labeled Multi-Bernoulli Filter", IEEE Trans. Signal Process. 67(23), 2019.
    .. [2] G. Casella, C. P. Robert, "Rao-Blackwellisation of sampling schemes", Biometrika
       83(1), 1996.

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign.multisensor import MultiSensorProblem
    >>> from rankedassign.tracking.multisensor.association import (
    ...     multisensor_marginals_from_hypotheses)
    >>> p = MultiSensorProblem.from_eta([1.0], [[[1.0, 2.0], [3.0, 0.0]]])   # Z = 7
    >>> dead, tup = multisensor_marginals_from_hypotheses(p, [[[0, 1]]])
    >>> float(dead[0]), tup[0].tolist()
    (0.0, [[0.0, 1.0], [0.0, 0.0]])
    >>> dead, tup = multisensor_marginals_from_hypotheses(p, [[[0, 1]]], marginals="rao-blackwell")
    >>> (7 * dead).round(9).tolist(), (7 * tup[0]).round(9).tolist()
    ([1.0], [[1.0, 2.0], [3.0, 0.0]])
    """
    check_choice(marginals, "marginals", MARGINALS)
    g = np.asarray(assignments, dtype=np.int64)
    P, V = problem.n_rows, problem.n_sensors
    if g.ndim != 3 or g.shape[1:] != (P, V):
        raise ValueError(f"assignments must have shape (H, P, V) = (H, {P}, {V}), got {g.shape}")
    if g.shape[0] == 0:
        raise ValueError("at least one hypothesis is needed to form association marginals")
    c = problem.cost_of(g) if costs is None else np.asarray(costs, dtype=np.float64)
    c = np.atleast_1d(c)
    if c.shape != (g.shape[0],):
        raise ValueError(f"costs must have shape ({g.shape[0]},), got {c.shape}")
    if not np.isfinite(c).all():
        raise ValueError("every hypothesis must be feasible (finite cost)")
    return _marginals(problem, g, c, marginals)


def _marginals(problem: MultiSensorProblem, g: np.ndarray, c: np.ndarray, method: str):
    """Marginals of checked hypotheses (a sampler's own output)."""
    dims = problem.log_eta_alive.shape
    P = dims[0]
    n_t = int(np.prod(dims[1:]))
    lw = -c - (-c).max()
    w = np.exp(lw)
    w /= w.sum()
    g = np.ascontiguousarray(g, dtype=np.int64)
    if method == "rao-blackwell":
        la = problem.log_eta_alive.reshape(P, n_t)
        finite = np.isfinite(la)
        ptr = np.concatenate([[0], np.cumsum(finite.sum(axis=1))]).astype(np.int64)
        rows, flat = np.nonzero(finite)
        opt_tuple = np.ascontiguousarray(problem.tuples[flat], dtype=np.int64)
        with interruptible:
            dead, tup = _rao_blackwell(
                g, w, np.ascontiguousarray(problem.log_eta_dead), ptr, opt_tuple,
                flat.astype(np.int64), np.ascontiguousarray(la[rows, flat]), n_t,
                np.array(problem.n_meas, dtype=np.int64),
            )
    else:
        strides = np.array([int(np.prod(dims[v + 2:])) for v in range(len(dims) - 1)],
                           dtype=np.int64)
        flat = (np.maximum(g, 0) * strides).sum(axis=2)
        with interruptible:
            dead, tup = _truncated(np.ascontiguousarray(flat), np.ascontiguousarray(g[:, :, 0] < 0),
                                   w, n_t)
    return dead, tup.reshape(dims)


class MultiSensorAssociation:
    """Base class: ``assoc(problem, rng) -> MultiSensorAssociationResult``.

    Subclass it (or pass any callable with that signature) to plug a method into
    :class:`~rankedassign.tracking.multisensor.lmb.MultiSensorLMBFilter`.
    """

    name = "multisensor-association"
    #: The problems it solves (see :attr:`Association.sensors
    #: <rankedassign.tracking.single.association.Association.sensors>`).
    sensors = "multi-sensor"

    def __call__(self, problem: MultiSensorProblem, rng):  # pragma: no cover
        raise NotImplementedError


def _split_collapsed(problem, dead, tup):
    """Split the all-missed mass of the collapsed target (spec §1.6) into dead and missed.

    ``"componentwise"`` samples never hold a dead row: ``(0, ..., 0)`` stands for "dead or
    missed by every sensor". Given the other rows both choices leave the same measurements
    free, so the split is ``η_n(−1) : η_n(0, ..., 0)`` in every hypothesis.
    """
    P = problem.n_rows
    zero = (slice(None),) + (0,) * problem.n_sensors
    ld, lm = problem.log_eta_dead, problem.log_eta_alive[zero]
    top = np.maximum(ld, lm)
    ed = np.exp(ld - top)
    em = np.exp(lm - top)
    both = dead + tup[zero]
    tup = tup.copy()
    tup[zero] = both * em / (ed + em)
    return (both * ed / (ed + em)).reshape(P), tup


def _from_sampler(problem, res, marginals, method) -> MultiSensorAssociationResult:
    dead, tup = _marginals(problem, res.assignments, res.costs, marginals)
    if method == "componentwise" and marginals == "truncated":
        dead, tup = _split_collapsed(problem, dead, tup)
    return MultiSensorAssociationResult(
        dead=dead, tuples=tup, invocations=1, sweeps=int(res.n_observations),
        row_updates=int(res.n_row_updates), n_unique=int(len(res.costs)))


def _extra(marginals, method, options):
    out = "" if method == "exact" else f", method={method!r}"
    out += "" if marginals == "truncated" else f", marginals={marginals!r}"
    return out + "".join(f", {k}={v!r}" for k, v in options.items())


class MultiSensorOriginalGibbs(MultiSensorAssociation):
    """One long multi-sensor Gibbs chain (Vo, Vo & Beard 2019) as association.

    Parameters
    ----------
    n_obs : int
        Observations (full sweeps) per call (spec §7.2: 10 000).
    method : {"exact", "mm", "mm-fixed", "componentwise"}, optional
        Row kernel of :func:`rankedassign.sample_original` (Alg. 1, MM-Gibbs with the
        exclusion-aware or the fixed proposal, sensor-component-wise). The component-wise
        kernel samples the collapsed target (spec §1.6), whose all-missed tuple stands for
        "dead or missed"; its truncated marginals split that mass ``η(−1) : η(0, ..., 0)``.
    marginals : {"truncated", "rao-blackwell"}, optional
        How the unique hypotheses become marginals
        (:func:`multisensor_marginals_from_hypotheses`).
    **sampler_options
        Passed to :func:`rankedassign.sample_original` (``start``, ``scan``).

    Examples
    --------
    >>> from rankedassign.tracking.multisensor.association import MultiSensorOriginalGibbs
    >>> MultiSensorOriginalGibbs(10_000, method="mm")
    MultiSensorOriginalGibbs(10000, method='mm')
    """

    name = "gibbs"

    def __init__(self, n_obs: int, *, method: str = "exact", marginals: str = "truncated",
                 **sampler_options):
        self.n_obs = check_int(n_obs, "n_obs", minimum=1)
        self.method = check_choice(method, "method", MULTISENSOR_METHODS)
        self.marginals = check_choice(marginals, "marginals", MARGINALS)
        self.options = dict(sampler_options)

    def __repr__(self):
        extra = _extra(self.marginals, self.method, self.options)
        return f"MultiSensorOriginalGibbs({self.n_obs}{extra})"

    def __call__(self, problem, rng) -> MultiSensorAssociationResult:
        res = sample_original(problem, self.n_obs, rng=rng, method=self.method, **self.options)
        return _from_sampler(problem, res, self.marginals, self.method)


class MultiSensorShortChainGibbs(MultiSensorAssociation):
    """Short chains with stall/stale termination (Trezza et al. 2023) on a multi-sensor problem.

    Parameters
    ----------
    n_chains, chain_length : int
        ``N_S`` chains of ``N_C`` observations (the tracking settings: 400 × 25).
    tau_stall, tau_stale : int or None
        Termination thresholds (5 and 10); None disables a rule.
    method : {"exact", "mm", "mm-fixed", "componentwise"}, optional
        Row kernel (see :class:`MultiSensorOriginalGibbs`).
    marginals : {"truncated", "rao-blackwell"}, optional
        How the unique hypotheses become marginals.
    **sampler_options
        Passed to :func:`rankedassign.sample_short_chains`.

    Examples
    --------
    >>> from rankedassign.tracking.multisensor.association import MultiSensorShortChainGibbs
    >>> MultiSensorShortChainGibbs(400, 25, tau_stall=5, tau_stale=10, marginals="rao-blackwell")
    MultiSensorShortChainGibbs(400, 25, tau_stall=5, tau_stale=10, marginals='rao-blackwell')
    """

    name = "short-chain"

    def __init__(self, n_chains: int, chain_length: int, *, tau_stall=None, tau_stale=None,
                 method: str = "exact", marginals: str = "truncated", **sampler_options):
        self.n_chains = check_int(n_chains, "n_chains", minimum=1)
        self.chain_length = check_int(chain_length, "chain_length", minimum=1)
        self.tau_stall = check_optional_int(tau_stall, "tau_stall", minimum=1)
        self.tau_stale = check_optional_int(tau_stale, "tau_stale", minimum=1)
        self.method = check_choice(method, "method", MULTISENSOR_METHODS)
        self.marginals = check_choice(marginals, "marginals", MARGINALS)
        self.options = dict(sampler_options)

    def __repr__(self):
        return (f"MultiSensorShortChainGibbs({self.n_chains}, {self.chain_length}, "
                f"tau_stall={self.tau_stall}, tau_stale={self.tau_stale}"
                f"{_extra(self.marginals, self.method, self.options)})")

    def __call__(self, problem, rng) -> MultiSensorAssociationResult:
        res = sample_short_chains(
            problem, self.n_chains, self.chain_length, tau_stall=self.tau_stall,
            tau_stale=self.tau_stale, rng=rng, method=self.method, **self.options,
        )
        return _from_sampler(problem, res, self.marginals, self.method)


class MultiSensorHerdedGibbs(MultiSensorAssociation):
    """Herded Gibbs (Chen et al. 2016, :func:`rankedassign.sample_herded`) on a multi-sensor
    problem, as association.

    One deterministic herded chain of ``n_obs`` sweeps, or, with ``n_chains``, herded short
    chains with seeded initial weights and the stall/stale rules
    (:func:`rankedassign.sample_short_chains` with ``herding=``); the multi-sensor twin of
    :class:`rankedassign.tracking.HerdedGibbs`.

    Parameters
    ----------
    n_obs : int
        Sweeps of the one chain, or the length ``N_C`` of each short chain.
    keys : {"shared", "full"}
        The herding keys (:class:`rankedassign.Herding`;
        :func:`rankedassign.multisensor.reference.herd_key` says what they are per method).
    init : {"conditional", "zero", "uniform"} or None
        Initial weights; None (default): ``"conditional"`` for one chain, ``"uniform"`` for
        short chains (so that they differ).
    max_keys : int
        Bound of each chain's key table.
    n_chains : int or None
        None (default): one chain. Otherwise ``N_S`` short chains of ``n_obs`` sweeps.
    tau_stall, tau_stale : int or None
        The short chains' rules (ignored for one chain).
    method : {"exact", "mm", "mm-fixed", "componentwise"}, optional
        Row kernel (see :class:`MultiSensorOriginalGibbs`); every one herds.
    marginals : {"truncated", "rao-blackwell"}, optional
        How the unique hypotheses become marginals.
    **sampler_options
        Passed to the sampler (``start``, ``scan``, ``beta``, ``backend``, ``workers`` for
        short chains).

    Examples
    --------
    >>> from rankedassign.tracking import MultiSensorHerdedGibbs
    >>> MultiSensorHerdedGibbs(1000)
    MultiSensorHerdedGibbs(1000)
    >>> MultiSensorHerdedGibbs(25, n_chains=400, tau_stall=5, tau_stale=10, method="mm")
    MultiSensorHerdedGibbs(25, n_chains=400, tau_stall=5, tau_stale=10, method='mm')
    >>> from rankedassign.multisensor import synthetic
    >>> out = MultiSensorHerdedGibbs(200)(synthetic.random(3, (2, 2), rng=0), 1)
    >>> out.sweeps, out.tuples.shape
    (200, (3, 3, 3))
    """

    name = "herded"

    def __init__(self, n_obs: int, *, keys: str = "shared", init=None,
                 max_keys: int = DEFAULT_MAX_KEYS, n_chains=None, tau_stall=None,
                 tau_stale=None, method: str = "exact", marginals: str = "truncated",
                 **sampler_options):
        self.n_obs = check_int(n_obs, "n_obs", minimum=1)
        self.n_chains = check_optional_int(n_chains, "n_chains", minimum=1)
        default_init = "conditional" if self.n_chains is None else "uniform"
        self.herding = Herding(keys=keys, init=default_init if init is None else init,
                               max_keys=max_keys)
        self.init_given = init
        self.tau_stall = check_optional_int(tau_stall, "tau_stall", minimum=1)
        self.tau_stale = check_optional_int(tau_stale, "tau_stale", minimum=1)
        self.method = check_choice(method, "method", MULTISENSOR_METHODS)
        self.marginals = check_choice(marginals, "marginals", MARGINALS)
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
        return (f"MultiSensorHerdedGibbs({', '.join(parts)}"
                f"{_extra(self.marginals, self.method, self.options)})")

    def __call__(self, problem, rng) -> MultiSensorAssociationResult:
        h = self.herding
        if self.n_chains is None:
            res = sample_herded(problem, self.n_obs, keys=h.keys, init=h.init,
                                max_keys=h.max_keys, rng=rng, method=self.method,
                                **self.options)
        else:
            res = sample_short_chains(problem, self.n_chains, self.n_obs,
                                      tau_stall=self.tau_stall, tau_stale=self.tau_stale,
                                      rng=rng, herding=h, method=self.method, **self.options)
        return _from_sampler(problem, res, self.marginals, self.method)


class MultiSensorExact(MultiSensorAssociation):
    """Exact association marginals (multi-sensor spec §6.2, :func:`oracle.marginals`).

    The row DP over used-measurement sets accepts a problem with at most
    :data:`oracle.multisensor.dp.MAX_MASK_BITS` reachable measurements over all sensors (or at
    most 2 000 000 feasible assignments, then enumerated).

    Parameters
    ----------
    fallback : MultiSensorAssociation or None, optional
        Association used on a problem beyond the DP. None (default): such a problem raises
        ``ValueError``. Problems solved by the fallback are counted in :attr:`n_fallback`.

    Raises
    ------
    TypeError
        If ``fallback`` is not callable, or is a single-sensor
        :class:`~rankedassign.tracking.Association`.
    ValueError
        When called on a problem beyond the DP and there is no fallback.

    Examples
    --------
    >>> from rankedassign.tracking.multisensor.association import MultiSensorExact
    >>> MultiSensorExact()
    MultiSensorExact()
    """

    name = "exact"

    def __init__(self, fallback=None):
        if fallback is not None and not callable(fallback):
            raise TypeError(
                f"fallback must be an association or None, got {type(fallback).__name__}"
            )
        if isinstance(fallback, Association):
            raise TypeError(
                "fallback must be a multi-sensor association such as MultiSensorShortChainGibbs; "
                f"got {type(fallback).__name__} (a single-sensor association)"
            )
        self.fallback = fallback
        self.n_fallback = 0

    def __repr__(self):
        return "MultiSensorExact()" if self.fallback is None else \
            f"MultiSensorExact(fallback={self.fallback!r})"

    def __call__(self, problem, rng) -> MultiSensorAssociationResult:
        try:
            m = oracle.marginals(problem)
        except ValueError as exc:
            if self.fallback is None:
                raise ValueError(
                    f"MultiSensorExact: a group of P = {problem.n_rows} tracks with "
                    f"M = {problem.n_meas} gated measurements is beyond the exact DP ({exc}); "
                    "enable grouping, narrow the gate, or pass fallback=<a sampler association>"
                ) from None
            self.n_fallback += 1
            return self.fallback(problem, rng)
        return MultiSensorAssociationResult(
            dead=np.asarray(m.dead, dtype=np.float64),
            tuples=np.asarray(m.tuples, dtype=np.float64), invocations=1, sweeps=0,
            row_updates=0, n_unique=0)

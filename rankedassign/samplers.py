"""Gibbs samplers for the ranked-assignment problem: public API.

Two samplers of the target ``pi(gamma) = w(gamma) / Z`` (spec eq. 1.6):

* :func:`sample_original` — one long systematic-scan chain (Vo, Vo & Hoang 2017, Alg. 1;
  spec §2.2);
* :func:`sample_short_chains` — many short chains restarted from the same state, with the
  stall and stale termination rules of Trezza, Bucci & Varshney (2023, Alg. 1; spec §3),
  every reading of those rules selectable (spec §3.2).

Each public function validates its input once, prepares the arrays shared by both
implementations (:mod:`rankedassign.engine.result`) and runs either the numba chain driver
(:mod:`rankedassign.engine._kernels`) compiled for the problem type's row update
(``backend="numba"``) or the pure-Python specification (:mod:`rankedassign.reference`,
``backend="python"``). Both give identical results, bit for bit, for the same ``rng`` — as
does the parallel kernel for any ``workers`` — because

* every chain draws from its own SplitMix64 stream derived from ``rng`` and the chain index
  (:mod:`rankedassign.engine.rng`);
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

import functools
import inspect

import numpy as np
from numba import parallel_chunksize

from . import reference
from .adaptive_birth import synthetic as ab_synthetic
from .adaptive_birth.problem import AdaptiveBirthProblem
from .engine._kernels import DISCARDED, NCHAINS, NOBS, STALE_FIRED, Rules, zobrist_keys
from .engine.herding import DEFAULT_MAX_KEYS, MAX_TABLE_BYTES, Herding, check_herding
from .engine.result import (
    BACKENDS,
    SCANS,
    Prepared,
    SamplerResult,
    check_chain_budget,
    check_rules,
    package,
    zero_length_run,
)
from .engine.rng import ZOBRIST_SEED
from .engine.tempered import TemperedResult
from .kinds import KINDS, herded_rule, kind_named, kind_of, prepare
from .multisensor import synthetic as ms_synthetic
from .multisensor.problem import MultiSensorProblem
from .numba_options import interruptible, threads
from .single import synthetic
from .single.problem import AssignmentProblem
from .validation import STALE_READINGS, STALL_READINGS, check_choice, check_int

__all__ = ["SamplerResult", "Herding", "TemperedResult", "sample_original",
           "sample_short_chains", "sample_herded", "sample_tempered", "warmup"]


# Upper bound on the speculation slab (batch x chain_length x L int32 entries, 64 MiB).
_MAX_SLAB = 1 << 24
# Candidate evaluations per speculation batch (~1 ms of sweeps).
_BATCH_WORK = 1 << 21
# Chains per work item of the parallel speculation loop.
_CHUNK = 4
# Candidate evaluations per slice of the compiled driver (``sweep_cost`` per sweep): a few ms
# to a tenth of a second of sweeps, depending on how well ``sweep_cost`` tracks the sweep time.
# Between slices the interpreter runs pending signal handlers, so Ctrl-C ends a run within
# about one slice; a slice costs microseconds of call overhead (rankedassign.engine._kernels,
# "Slices").
# The tests shrink it to a few sweeps: same bits.
_SLICE_WORK = 1 << 23


def _batch_size(workers: int, n_chains: int, chain_length: int, L: int, sweep_cost: int) -> int:
    """Chains per speculation batch, or 0 for the sequential kernel.

    At least ``max(64, 16 workers)`` chains, and enough that a batch holds about
    :data:`_BATCH_WORK` candidate evaluations (``sweep_cost`` per sweep) so that starting the
    thread team is cheap next to the work; at most :data:`_MAX_SLAB` stored state entries. A
    stale stop discards at most the rest of one batch. If the slab bound leaves room for fewer
    chains than workers (very long chains), speculation cannot keep the workers busy and the
    sequential kernel runs instead (same result). The slab therefore never grows with
    ``chain_length`` beyond :data:`_MAX_SLAB`.
    """
    if workers <= 1 or n_chains < 2:  # one chain cannot be split across threads
        return 0
    room = _MAX_SLAB // max(1, chain_length * max(L, 1))
    if room < workers:
        return 0
    by_work = -(-_BATCH_WORK // max(1, chain_length * max(sweep_cost, 1)))
    return min(max(64, 16 * workers, by_work), n_chains, room)


@functools.lru_cache(maxsize=16)
def _zobrist(L: int, K: int) -> np.ndarray:
    """Zobrist keys of an ``L``-position state with values ``0..K-1`` (fixed; cached, read-only:
    a filter calls the samplers on problems of few shapes, thousands of times)."""
    with interruptible:
        keys = zobrist_keys(L, K, np.uint64(ZOBRIST_SEED))
    keys.setflags(write=False)
    return keys


def _run(prep: Prepared, n_chains: int, chain_length: int, rules: Rules, workers: int,
         herding=None):
    """Run the kind's compiled driver (its herded one with ``herding``) and package it."""
    L = prep.x0.shape[0]
    zkeys = _zobrist(L, prep.n_values)
    batch = _batch_size(workers, n_chains, chain_length, L, prep.sweep_cost)
    budget = max(1, _SLICE_WORK // max(prep.sweep_cost, 1))  # sweeps per slice
    kind = kind_named(prep.kind)
    tally = None
    if herding is None:
        run_chains, data = kind.drivers[prep.driver], prep.data
    else:
        rule = herded_rule(kind)
        inputs = rule.inputs(prep, herding, chain_length)
        data, tally, chain_bytes = inputs.data, inputs.tally, inputs.chain_bytes
        run_chains = rule.driver
        if batch:  # every chain simulated at once has its own key table
            batch = min(batch, MAX_TABLE_BYTES // max(chain_bytes, 1))
            if batch < max(2, workers):
                batch = 0
    args = (data, zkeys, prep.x0, np.uint64(prep.base), n_chains, chain_length, rules,
            batch, workers, budget)
    if batch:
        # Chains are handed to threads a few at a time (not one static share per thread), so
        # a thread slowed down by another process does not hold up the whole batch.
        with threads(workers), parallel_chunksize(_CHUNK):
            states, counts, ctr = run_chains(*args)
    else:
        states, counts, ctr = run_chains(*args)
    return package(prep, states, counts, ctr[NOBS], ctr[NCHAINS], ctr[STALE_FIRED],
                   ctr[DISCARDED], (0, 0) if tally is None else tally.tolist())


# ------------------------------------------------------------------------------ public API
def sample_original(problem, n_obs, *, start="all_missed", scan="systematic", rng=None,
                    backend="numba", beta=1.0, **options) -> SamplerResult:
    """Original Gibbs sampler: one long chain of ``n_obs`` sweeps (Vo, Vo & Hoang 2017).

    Parameters
    ----------
    problem : AssignmentProblem, MultiSensorProblem or AdaptiveBirthProblem
        The problem; its kind (:func:`rankedassign.kinds.kind_of`) prepares the run. A
        single-sensor :class:`AssignmentProblem` is the ``P x (M + 2P)`` ranked-assignment
        problem; for the other kinds the state and the ``assignments`` of the result are as
        documented by :class:`~rankedassign.multisensor.MultiSensorProblem` and
        :class:`~rankedassign.adaptive_birth.AdaptiveBirthProblem`.
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
        (the run's base key, see :mod:`rankedassign.engine.rng`). The chain uses stream 0.
    backend : {"numba", "python"}
        Compiled kernels or the pure-Python reference
        (:func:`rankedassign.reference.sample_original`); the results are identical.
    beta : float
        Inverse temperature in ``(0, 1]`` (default 1): the chain samples ``π^β``, every row
        conditional raised to ``beta`` inside the same kernels (the kind's
        :attr:`~rankedassign.engine.kind.Kind.temper`). The result's ``costs`` are those of
        ``problem`` itself, so a truncation re-weights every unique assignment exactly.
        ``beta = 1`` gives today's draws bit for bit; the sensor-component-wise multi-sensor
        kernel refuses ``beta < 1``.
    **options
        Options of the problem's kind (``Kind.options``): none for an
        :class:`AssignmentProblem`; for a
        :class:`~rankedassign.multisensor.MultiSensorProblem`, ``method`` (the row
        conditional: ``"exact"``, ``"mm"`` (default), ``"mm-fixed"`` or ``"componentwise"``)
        and ``survival_power`` (``1``, default, or ``"V"``); for an
        :class:`~rankedassign.adaptive_birth.AdaptiveBirthProblem`, ``sensor_order``
        (``"random"``, default, or ``"fixed"``).

    Returns
    -------
    SamplerResult
        Unique assignments in discovery order (start state first) with their costs and visit
        counts; ``n_chains_run = 1``, ``stop_reason = "budget"``.

    Raises
    ------
    TypeError
        If ``problem`` is of no known kind, an option does not apply to its kind, or
        ``n_obs`` is not an int.
    ValueError
        On a negative ``n_obs``, an unknown ``start``/``scan``/``backend``, an infeasible
        start state (e.g. all-missed when some row's missed cost is ``+inf``), or ``beta``
        outside ``(0, 1]``.

    Notes
    -----
    Spec §2.2. Starting from ``x = x0``, each sweep updates rows in place (Gauss-Seidel)::

        x_n ~ p(k) ∝ eta_n(k) * 1[k not held by another row]     (spec eq. 2.1)

    and the state after the sweep is one observation. The conditional of row ``n`` is drawn by
    the inverse-CDF loop of :func:`rankedassign.single._kernels.sweep` with one uniform. The chain
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
    check_choice(backend, "backend", BACKENDS)
    if backend == "python":
        return reference.sample_original(problem, n_obs, start=start, scan=scan, rng=rng,
                                         beta=beta, **options)
    n_obs = check_int(n_obs, "n_obs")
    prep = prepare(problem, start, scan, rng, beta, **options)
    return _run(prep, 1, n_obs, Rules(0, 0, 0, 0), 1)


def sample_short_chains(problem, n_chains, chain_length, *, tau_stall=None, tau_stale=None,
                        stall="global-consecutive", stale="consecutive", start="all_missed",
                        scan="systematic", rng=None, backend="numba",
                        workers=1, beta=1.0, herding=None, **options) -> SamplerResult:
    """Short-chain, multi-simulation Gibbs sampler with stall/stale termination.

    Parameters
    ----------
    problem : AssignmentProblem, MultiSensorProblem or AdaptiveBirthProblem
        The problem; its kind (:func:`rankedassign.kinds.kind_of`) prepares the run. A
        single-sensor :class:`AssignmentProblem` is the ``P x (M + 2P)`` ranked-assignment
        problem; for the other kinds the state and the ``assignments`` of the result are as
        documented by :class:`~rankedassign.multisensor.MultiSensorProblem` and
        :class:`~rankedassign.adaptive_birth.AdaptiveBirthProblem`.
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
    beta : float
        Inverse temperature in ``(0, 1]`` (default 1), as in :func:`sample_original`.
    herding : Herding or None
        None (default): Gibbs draws. A :class:`~rankedassign.engine.herding.Herding`: every
        chain is a herded chain (:func:`sample_herded`) with its own key table; with
        ``init="uniform"`` (its default) each chain's initial weights come from its own
        stream, so the chains differ and stall and stale work unchanged. The result counts
        the keys and the fall-backs of the chains observed.
    **options
        Options of the problem's kind, as in :func:`sample_original`.

    Returns
    -------
    SamplerResult
        Unique assignments in discovery order (start state first), costs, visit counts,
        observation count, chains run and why the run stopped.

    Raises
    ------
    TypeError
        If ``problem`` is of no known kind, an option does not apply to its kind, or a
        count/threshold is not an int.
    ValueError
        On negative counts, thresholds < 1, unknown readings, start, scan or backend,
        ``workers < 1``, an infeasible start state or ``beta`` outside ``(0, 1]``.

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
    check_choice(backend, "backend", BACKENDS)
    if backend == "python":
        return reference.sample_short_chains(
            problem, n_chains, chain_length, tau_stall=tau_stall, tau_stale=tau_stale,
            stall=stall, stale=stale, start=start, scan=scan, rng=rng, workers=workers,
            beta=beta, herding=herding, **options,
        )
    n_chains, chain_length = check_chain_budget(n_chains, chain_length)
    tau_stall, tau_stale = check_rules(tau_stall, tau_stale, stall, stale)
    workers = check_int(workers, "workers", minimum=1)
    if check_herding(herding) is not None:
        herded_rule(kind_of(problem))
    prep = prepare(problem, start, scan, rng, beta, **options)
    if chain_length == 0:  # empty chains: closed form instead of looping over them
        chains_run, stale_fired = zero_length_run(n_chains, tau_stale, stale)
        return package(prep, prep.x0[None, :], [0], 0, chains_run, stale_fired, 0)
    rules = Rules(STALL_READINGS[stall] if tau_stall else 0, tau_stall or 0,
                  STALE_READINGS[stale] if tau_stale else 0, tau_stale or 0)
    return _run(prep, n_chains, chain_length, rules, workers, herding)


def sample_herded(problem, n_obs, *, keys="shared", init="conditional",
                  max_keys=DEFAULT_MAX_KEYS,
                  beta=1.0, start="all_missed", scan="systematic", rng=None, backend="numba",
                  **options) -> SamplerResult:
    """Herded Gibbs sampler: one deterministic chain of ``n_obs`` sweeps (Chen et al. 2016).

    Parameters
    ----------
    problem : AssignmentProblem, MultiSensorProblem or AdaptiveBirthProblem
        The problem; every kind has a herded draw (:attr:`Kind.draws
        <rankedassign.engine.kind.Kind>`). A multi-sensor row herds its one draw
        (``method="exact"``: dead or a tuple) or each of its draws (the MM methods: dead or
        alive, then each sensor's component; ``"componentwise"``: each component), each with
        its own key; an adaptive-birth sweep herds each sensor's entry.
    n_obs : int
        Observations (full sweeps), >= 0.
    keys : {"shared", "full"}
        What a row's key is: ``"shared"`` (default), the gated measurements of the row that
        the other rows hold (all its conditional depends on), or ``"full"``, the other rows'
        whole state ``γ_{-i}`` (Chen et al.'s key). For the other kinds, see
        :func:`rankedassign.multisensor.reference.herd_key` and
        :func:`rankedassign.adaptive_birth.reference.herd_key` (there both keys are the other
        sensors' entries).
    init : {"conditional", "zero", "uniform"}
        A new key's initial weights: the key's conditional (default), zeros, or uniforms in
        ``[0, 1)`` from the chain's stream. With the first two the chain is deterministic
        (``rng`` matters only for a random scan and for fall-backs). On the paper's random
        ``4 x 24`` family the first two find more posterior mass than Gibbs at equal sweeps
        on every problem measured, uniform initial weights (noise as large as a whole unit of
        herding) on fewer than half at 100 sweeps (the Herding, tempering and belief
        propagation page of the documentation); :class:`Herding`'s default for short chains
        is ``"uniform"``, which makes the chains differ.
    max_keys : int
        Keys the chain's table may hold (>= 1; default 65 536). A row update whose key is new
        when the table is full draws as the Gibbs sampler does and is counted in the
        result's ``n_fallbacks``; herding never stops silently and the table never grows
        beyond the bound. Memory: ``max_keys * (8 (M + 2) + 4 P + 20)`` bytes at most.
    beta : float
        Inverse temperature in ``(0, 1]``: the herded conditionals are those of ``π^β``
        (as in :func:`sample_original`).
    start, scan, rng, backend, **options
        As in :func:`sample_original`.

    Returns
    -------
    SamplerResult
        The unique assignments and their visit counts, with ``n_keys`` (keys created) and
        ``n_fallbacks``.

    Raises
    ------
    TypeError
        If the problem's kind has no herded draw, or a count is not an int.
    ValueError
        On an unknown ``keys`` or ``init`` (the message lists the choices), ``max_keys < 1``,
        and as :func:`sample_original` does.

    Notes
    -----
    Each row update of the systematic (or random) scan computes the row's conditional
    ``π_i(· | γ_{-i})`` over its ``M + 2`` candidates and looks its key up in the chain's
    table. With the key's weights ``w`` it does ``w += π_i``, takes
    ``γ_i = argmax w`` over the candidates of positive probability (ties to the lowest
    column: measurements first, then missed, then dead), and ``w[γ_i] -= 1``. For one key the
    fraction of visits that chose ``k`` then differs from ``π_i(k)`` by ``O(1/n)`` after
    ``n`` visits, against ``O(1/sqrt(n))`` for random draws; whether the chain's joint
    frequencies converge to ``π`` depends on the keys (Chen et al. prove it for full keys on
    fully connected models; shared keys are biased in the long run, Yamashita & Suzuki 2019).
    A row update costs ``O(M + P)`` (the conditional's direct sum and the key), also when
    the key was seen before: the weights must be updated for every candidate.

    References
    ----------
    .. [1] Y. Chen, L. Bornn, N. de Freitas, M. Eskelin, J. Fang, M. Welling, "Herded Gibbs
       Sampling", J. Mach. Learn. Res. 17(10):1-29, 2016.
    .. [2] H. Yamashita, H. Suzuki, "Convergence analysis of herded-Gibbs-type sampling
       algorithms: effects of weight sharing", Stat. Comput. 29:1035-1053, 2019.
    .. [3] B.-N. Vo, B.-T. Vo, H. G. Hoang, "An Efficient Implementation of the Generalized
       Labeled Multi-Bernoulli Filter", IEEE Trans. Signal Process. 65(8):1975-1987, 2017.

    Examples
    --------
    >>> from rankedassign import synthetic, sample_herded
    >>> p = synthetic.random(rng=0)
    >>> res = sample_herded(p, 1000, rng=1)
    >>> res.n_observations, res.n_fallbacks, res.n_keys > 0
    (1000, 0, True)
    >>> ref = sample_herded(p, 1000, rng=1, backend="python")
    >>> bool((ref.assignments == res.assignments).all() and (ref.counts == res.counts).all())
    True
    >>> sample_herded(p, 1000, rng=1, max_keys=10).n_fallbacks > 0
    True
    """
    herding = Herding(keys=keys, init=init, max_keys=max_keys)
    check_choice(backend, "backend", BACKENDS)
    if backend == "python":
        return reference.sample_herded(problem, n_obs, keys=keys, init=init, max_keys=max_keys,
                                       beta=beta, start=start, scan=scan, rng=rng, **options)
    n_obs = check_int(n_obs, "n_obs")
    herded_rule(kind_of(problem))
    prep = prepare(problem, start, scan, rng, beta, **options)
    return _run(prep, 1, n_obs, Rules(0, 0, 0, 0), 1, herding)


def sample_tempered(problem, n_steps, *, beta, start="all_missed", rng=None, backend="numba",
                    **options) -> TemperedResult:
    """Tempered Gibbs sampling of Zanella & Roberts (2019): unique states, weighted marginals.

    Parameters
    ----------
    problem : AssignmentProblem, MultiSensorProblem or AdaptiveBirthProblem
        The problem; its kind's tempered sampler runs (:attr:`Kind.tempered
        <rankedassign.engine.kind.Kind>`): :func:`rankedassign.single.tempered.sample_tempered`,
        :func:`rankedassign.multisensor.tempered.sample_tempered` (a row is an object, its
        value dead or a whole measurement tuple) or
        :func:`rankedassign.adaptive_birth.tempered.sample_tempered` (a row is a sensor's entry
        of the birth tuple).
    n_steps : int
        Moves (each updates one row), >= 0.
    beta : float
        Inverse temperature of the tempered conditionals ``g_i ∝ π_i^β``, in ``(0, 1]``;
        ``beta = 1`` is a random-scan Gibbs sampler with uniform row choice.
    start : str or array_like of int
        Start state, as in :func:`sample_original` for the kind.
    rng : None, int, SeedSequence, BitGenerator or Generator
        Anything :func:`numpy.random.default_rng` accepts (one draw: the stream's key).
    backend : {"numba", "python"}
        The compiled kernel or the kind's pure-Python reference; the results are identical.
    **options
        The kind's options: ``method`` for a multi-sensor problem (only ``"exact"``, the
        conditional of ``π`` itself); none for the other kinds.

    Returns
    -------
    TemperedResult
        ``assignments``, ``costs`` and ``counts`` of the unique states in the kind's layout,
        the importance-weighted ``marginals`` in the layout of the kind's
        :func:`oracle.marginals`, the number of moves and the weights' effective sample size
        ``ess``.

    Raises
    ------
    TypeError
        If ``problem`` is of no known kind, or an option does not apply to its kind.
    ValueError
        If ``beta`` is outside ``(0, 1]``, ``n_steps`` is negative, a multi-sensor ``method``
        is not ``"exact"``, the start is infeasible, or a state's weights are not
        representable (the message says why).

    Notes
    -----
    At state ``x`` row ``i`` has the ratio ``p_i(x) = g_i(x_i | x_-i) / π_i(x_i | x_-i)``; a
    move picks row ``i`` with probability ``p_i / Z``, ``Z = Σ_i p_i``, and draws ``x_i`` from
    ``g_i``. The chain is reversible with respect to ``π(x) Z(x)``, so the states weighted by
    ``1 / Z(x)`` average to expectations under ``π`` (Zanella & Roberts 2019, Prop. 1). A move
    costs ``O(P + M)`` on a single-sensor problem (running sums), and on the other kinds about
    one exact Gibbs sweep (every row's ratio is computed again; see the kinds' functions).

    References
    ----------
    .. [1] G. Zanella, G. Roberts, "Scalable importance tempering and Bayesian variable
       selection", J. R. Stat. Soc. B 81(3):489-517, 2019.

    Examples
    --------
    >>> from rankedassign import sample_tempered, synthetic
    >>> from rankedassign.multisensor import synthetic as ms_synthetic
    >>> sample_tempered(synthetic.random(rng=0), 100, beta=0.5, rng=1).marginals.shape
    (4, 18)
    >>> res = sample_tempered(ms_synthetic.diagonal(P=2, M=(2, 2)), 100, beta=0.5, rng=1)
    >>> res.assignments.shape[1:], res.marginals.tuples.shape
    ((2, 2), (2, 3, 3))
    >>> sample_tempered(ms_synthetic.diagonal(), 10, beta=0.5, method="mm")
    Traceback (most recent call last):
    ...
    ValueError: method='mm' does not apply to tempered Gibbs sampling: its target is the exact
    posterior pi, whose row conditional is method='exact' (spec eq. 2.1); the MM and
    componentwise row updates are Gibbs proposals of other targets or of several draws per
    row; use method='exact' (the default)
    """
    kind = kind_of(problem)
    if kind.tempered is None:
        have = ", ".join(k.problem_type.__name__ for k in KINDS if k.tempered is not None)
        raise TypeError(f"tempered Gibbs sampling is not implemented for a "
                        f"{kind.problem_type.__name__} yet (it is for: {have})")
    own = [name for name, par in inspect.signature(kind.tempered).parameters.items()
           if par.kind is inspect.Parameter.KEYWORD_ONLY
           and name not in ("beta", "start", "rng", "backend")]
    unknown = sorted(set(options) - set(own))
    if unknown:
        raise TypeError(f"unexpected option(s) {unknown} for tempered Gibbs sampling "
                        f"({kind.problem_type.__name__}): "
                        + (f"its options are {own}" if own else "it takes none"))
    return kind.tempered(problem, n_steps, beta=beta, start=start, rng=rng, backend=backend,
                         **options)


def warmup() -> None:
    """Compile every sampler kernel (sequential, parallel, both scans) on a tiny problem.

    Also grows the unique set of one run of each kind past its first capacity, which compiles
    the kind's growth kernel. Call once before timing; the test suite calls it once per
    session, and ``rankedassign precompile`` runs it. With numba's on-disk cache (the default)
    later processes load the compiled code instead.

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
    # The prefix-sum draw (more than 32 measurements) has a driver of its own.
    wide = synthetic.random(R=2, M=33, rng=0)
    for scan in SCANS:
        sample_original(wide, 3, scan=scan, rng=0)
        sample_short_chains(wide, 3, 2, tau_stall=1, tau_stale=1, scan=scan, rng=0, workers=2)
    # The multi-sensor kind: one compiled sweep serves every method; row 0's best tuple sits
    # ~800 above the rest of its row, so its underflow fall-back runs while row 1 holds it.
    log_s = np.zeros(2)
    th0 = np.array([[-800.0, 0.0], [-1.0, 0.0]])
    th1 = np.array([[0.0, -0.5], [0.0, -2.0]])
    ms = MultiSensorProblem(np.array([-800.0, -1.0]),
                            log_s[:, None, None] + th0[:, :, None] + th1[:, None, :],
                            log_s, (th0, th1))
    for scan in SCANS:
        sample_original(ms, 3, scan=scan, rng=0, start=[[0, 0], [1, 0]], method="exact")
        sample_short_chains(ms, 3, 2, tau_stall=1, tau_stale=1, scan=scan, rng=0)
        sample_short_chains(ms, 3, 2, tau_stall=1, tau_stale=1, scan=scan, rng=0, workers=2)
    # Adaptive birth: the dense-tensor and the Gaussian closed-form problems, both orders.
    z = [np.array([[0.0], [50.0]]), np.array([[1.0]])]
    gauss = AdaptiveBirthProblem.from_measurements(
        z, [[0.99, 0.95], [0.95]], H=[[1.0]], R=[[1.0]], P_D=0.9, clutter_intensity=0.01,
        mu0=[0.0], P0=[[100.0]])
    dense = AdaptiveBirthProblem.from_log_weights(np.log([[1.0, 2.0], [3.0, 4.0]]), n_min=1)
    for ab in (gauss, dense):
        for order in ("random", "fixed"):
            sample_original(ab, 3, rng=0, sensor_order=order)
            sample_short_chains(ab, 3, 2, tau_stall=1, tau_stale=1, rng=0, workers=2,
                                sensor_order=order)
    # A run's unique set starts with room for 512 states and grows when it fills, which
    # compiles the kind's growth kernel (1-2 s of CPU each) in the middle of a run: a run
    # of each kind with more distinct states than that compiles it here, with a chain driver
    # compiled above (one worker or two: both grow with the same kernel).
    for grows, workers in ((synthetic.random(R=8, M=10, rng=0), 1),
                           (synthetic.random(R=4, M=40, rng=0), 2),
                           (ms_synthetic.random(P=4, M=(4, 4), rng=0), 1),
                           (ab_synthetic.make_family("uniform", 4, 6, rng=0), 2)):
        sample_short_chains(grows, 64, 32, tau_stall=1 << 30, tau_stale=1 << 30, rng=0,
                            workers=workers)

"""Pure-Python Gibbs samplers: the specification of record for the compiled drivers.

Same names and signatures as :func:`rankedassign.sample_original` and
:func:`rankedassign.sample_short_chains` (the ``backend`` switch is absent: this *is* the
Python backend; ``workers`` is accepted and ignored because the run is sequential). Written
for reading, not speed. The problem's kind (:func:`rankedassign.kinds.kind_of`) prepares the
inputs and supplies its pure-Python row update (``Kind.new_work`` and ``Kind.sweep``, from the
kind's ``reference`` module); :func:`rankedassign.engine.reference.run_chains` runs the
chains. The compiled drivers must return exactly the same result for the same inputs (tested
with hypothesis over random problems and every option).
"""

from __future__ import annotations

from .engine.herding import DEFAULT_MAX_KEYS, Herding, check_herding
from .engine.reference import run_chains
from .engine.result import check_chain_budget, check_rules, package, zero_length_run
from .kinds import herded_rule, kind_named, kind_of, prepare
from .validation import check_int

__all__ = ["sample_original", "sample_short_chains", "sample_herded"]


def _run(prep, n_chains, chain_length, herding=None, **rules):
    kind = kind_named(prep.kind)
    if herding is None:
        sweep, new_work, data, tally = kind.sweep, kind.new_work, prep.ref_data, (0, 0)
    else:
        rule = herded_rule(kind)
        data, tally = rule.inputs(prep, herding, chain_length).make_ref()
        sweep, new_work = rule.sweep, rule.new_work
    states, counts, n_obs, chains_run, stale = run_chains(
        sweep, new_work, data, prep.x0.tolist(), prep.base, n_chains, chain_length, **rules,
    )
    return package(prep, states, counts, n_obs, chains_run, stale, 0, tally)


def sample_original(problem, n_obs, *, start="all_missed", scan="systematic", rng=None,
                    beta=1.0, **options):
    """Reference original Gibbs sampler (spec §2.2); see :func:`rankedassign.sample_original`.

    Parameters
    ----------
    problem : AssignmentProblem, MultiSensorProblem or AdaptiveBirthProblem
    n_obs : int
        Number of sweeps (observations); Vo's ``T`` is ``n_obs + 1``.
    start, scan, rng, beta, **options
        As in :func:`rankedassign.sample_original`.

    Returns
    -------
    SamplerResult

    References
    ----------
    .. [1] B.-N. Vo, B.-T. Vo, H. G. Hoang, "An Efficient Implementation of the Generalized
       Labeled Multi-Bernoulli Filter", IEEE Trans. Signal Process. 65(8):1975-1987, 2017.

    Examples
    --------
    >>> from rankedassign import synthetic
    >>> res = sample_original(synthetic.diagonal(), 200, rng=0)
    >>> int(res.counts.sum()), res.assignments[0].tolist()
    (200, [16, 17, 18, 19])
    """
    n_obs = check_int(n_obs, "n_obs")
    prep = prepare(problem, start, scan, rng, beta, **options)
    return _run(prep, 1, n_obs)     # one chain, neither rule: Vo's long chain


def sample_short_chains(problem, n_chains, chain_length, *, tau_stall=None, tau_stale=None,
                        stall="global-consecutive", stale="consecutive", start="all_missed",
                        scan="systematic", rng=None, workers=1, beta=1.0, herding=None,
                        **options):
    """Reference short-chain sampler (spec §3.3); see :func:`rankedassign.sample_short_chains`.

    Parameters
    ----------
    problem : AssignmentProblem, MultiSensorProblem or AdaptiveBirthProblem
    n_chains, chain_length : int
        ``N_S`` and ``N_C``.
    tau_stall, tau_stale : int or None
        Thresholds; ``None`` disables a rule.
    stall, stale : str
        Readings of the rules (spec §3.2), as in :func:`rankedassign.sample_short_chains`.
    start, scan, rng, beta, herding, **options
        As in :func:`rankedassign.sample_short_chains`.
    workers : int
        Accepted and ignored (sequential).

    Returns
    -------
    SamplerResult
        ``n_speculative_discarded`` is 0.

    References
    ----------
    .. [1] A. Trezza, D. J. Bucci Jr., P. K. Varshney, "On Gibbs Sampling Architecture for
       Labeled Random Finite Sets Multi-Object Tracking", arXiv:2306.15135, 2023.

    Examples
    --------
    >>> from rankedassign import synthetic
    >>> res = sample_short_chains(synthetic.diagonal(), 200, 25, tau_stall=5, tau_stale=25,
    ...                           rng=3)
    >>> res.stop_reason, res.n_chains_run < 200
    ('stale', True)
    """
    n_chains, chain_length = check_chain_budget(n_chains, chain_length)
    tau_stall, tau_stale = check_rules(tau_stall, tau_stale, stall, stale)
    check_int(workers, "workers", minimum=1)
    if check_herding(herding) is not None:
        herded_rule(kind_of(problem))
    prep = prepare(problem, start, scan, rng, beta, **options)
    if chain_length == 0:  # empty chains: closed form instead of looping over them
        chains_run, stale_fired = zero_length_run(n_chains, tau_stale, stale)
        return package(prep, [prep.x0.tolist()], [0], 0, chains_run, stale_fired, 0)
    return _run(prep, n_chains, chain_length, herding, tau_stall=tau_stall,
                tau_stale=tau_stale, stall=stall, stale=stale)


def sample_herded(problem, n_obs, *, keys="shared", init="conditional",
                  max_keys=DEFAULT_MAX_KEYS,
                  beta=1.0, start="all_missed", scan="systematic", rng=None, **options):
    """Reference herded Gibbs sampler; see :func:`rankedassign.sample_herded`.

    Parameters
    ----------
    problem : AssignmentProblem, MultiSensorProblem or AdaptiveBirthProblem
    n_obs : int
        Number of sweeps (observations).
    keys, init, max_keys, beta, start, scan, rng, **options
        As in :func:`rankedassign.sample_herded`.

    Returns
    -------
    SamplerResult

    References
    ----------
    .. [1] Y. Chen, L. Bornn, N. de Freitas, M. Eskelin, J. Fang, M. Welling, "Herded Gibbs
       Sampling", J. Mach. Learn. Res. 17(10):1-29, 2016.

    Examples
    --------
    >>> from rankedassign import synthetic
    >>> res = sample_herded(synthetic.diagonal(), 200, init="zero")
    >>> int(res.counts.sum()), res.n_fallbacks
    (200, 0)
    """
    herding = Herding(keys=keys, init=init, max_keys=max_keys)
    n_obs = check_int(n_obs, "n_obs")
    herded_rule(kind_of(problem))
    prep = prepare(problem, start, scan, rng, beta, **options)
    return _run(prep, 1, n_obs, herding)


"""The chain engine in pure Python: the specification of record of the compiled driver.

:func:`run_chains` is the architecture of the paper written once — chains from a common start,
one observation per sweep, the unique set, every reading of stall and stale — for any problem
kind; a kind supplies ``new_work(data, x)`` (its per-chain bookkeeping, e.g. which row holds
each measurement) and ``sweep(data, work, x, g)`` (one sweep in place), the ``new_work`` and
``sweep`` fields of its :class:`~rankedassign.engine.kind.Kind`. Chain ``c`` draws from the
SplitMix64 stream :func:`rankedassign.engine.rng.chain_state` ``(base, c)``
(:class:`~rankedassign.engine.rng.SplitMix64`). The compiled twin is
:func:`rankedassign.engine._kernels.make_driver`.

References
----------
.. [1] A. Trezza, D. J. Bucci Jr., P. K. Varshney, "On Gibbs Sampling Architecture for
   Labeled Random Finite Sets Multi-Object Tracking", arXiv:2306.15135, 2023, Alg. 1.
"""

from __future__ import annotations

from .rng import SplitMix64, chain_state


def run_chains(sweep, new_work, data, x0, base, n_chains, chain_length, *, tau_stall=None,
               tau_stale=None, stall="global-consecutive", stale="consecutive"):
    """The short-chain architecture for any problem type (spec §3.3); plain Python.

    Parameters
    ----------
    sweep : callable
        ``sweep(data, work, x, g)``: one sweep (one observation) in place on the list ``x`` and
        the bookkeeping ``work``, drawing from the stream ``g``.
    new_work : callable
        ``new_work(data, x) -> work``: the bookkeeping of a chain started at ``x``.
    data : tuple
        The problem type's inputs (``Prepared.ref_data``).
    x0 : sequence of int
        Start state of every chain.
    base : int
        Base key; chain ``c`` draws from ``SplitMix64(chain_state(base, c))``.
    n_chains, chain_length : int
        ``N_S`` and ``N_C``.
    tau_stall, tau_stale : int or None
        Thresholds; ``None`` disables a rule.
    stall, stale : str
        Readings of the rules (spec §3.2), as in :func:`rankedassign.sample_short_chains`.

    Returns
    -------
    states : list of tuple
        Unique states in discovery order, ``x0`` first.
    counts : list of int
        Observations of each.
    n_obs, chains_run : int
        Observations made and chains started.
    stale_fired : bool
        Whether the stale rule stopped the run.

    Notes
    -----
    The original sampler (Vo, Vo & Hoang 2017, Alg. 1) is one chain of ``n_obs`` sweeps with
    neither rule.

    Examples
    --------
    A coin that one uniform per sweep turns:

    >>> def flip(data, work, x, g):
    ...     if g.uniform() < 0.5:
    ...         x[0] = 1 - x[0]
    >>> states, counts, n_obs, chains, stale = run_chains(flip, lambda d, x: None, (), [0],
    ...                                                   7, 1, 100)
    >>> sorted(states), sum(counts), stale
    ([(0,), (1,)], 100, False)
    """
    x0 = tuple(x0)
    index = {x0: 0}                 # U <- {x0}; x0 is returned but is not an observation
    states, counts = [x0], [0]
    n_obs = 0
    stale_run = 0                   # T3: consecutive completed chains with nothing new
    stale_cum = 0                   # T2: completed chains, ever, with nothing new
    chains_run = 0
    stale_fired = False
    for c in range(n_chains):
        x = list(x0)
        work = new_work(data, x)
        g = SplitMix64(chain_state(base, c))
        stall_run = 0               # S3: observations since the chain's last new find
        stall_cum = 0               # S2: observations already in U
        new_in_chain = 0
        chain_states = {x0}         # S1: distinct states among x[0..j]
        for j in range(1, chain_length + 1):
            sweep(data, work, x, g)
            n_obs += 1
            key = tuple(x)
            if key not in index:    # new to U
                index[key] = len(states)
                states.append(key)
                counts.append(1)
                new_in_chain += 1
                stall_run = 0
            else:
                counts[index[key]] += 1
                stall_run += 1
                stall_cum += 1
            chain_states.add(key)
            if tau_stall is not None:
                if stall == "global-consecutive":
                    stop = stall_run >= tau_stall
                elif stall == "global-cumulative":
                    stop = stall_cum >= tau_stall
                else:  # chain-local: (j + 1) - NumUnique(x[0..j])
                    stop = (j + 1) - len(chain_states) >= tau_stall
                if stop:
                    break
        chains_run += 1
        if new_in_chain > 0:
            stale_run = 0
        else:
            stale_run += 1
            stale_cum += 1
        if tau_stale is not None:
            if stale == "consecutive":
                fired = stale_run >= tau_stale
            elif stale == "cumulative":
                fired = stale_cum >= tau_stale
            elif stale == "literal-set":
                samples = set(states)            # x as a set: |x| - n_u = 0
                fired = len(samples) - len(states) >= tau_stale
            else:  # literal-multiset: every chain's x0 once plus every observation
                fired = (chains_run + n_obs) - len(states) >= tau_stale
            if fired:
                stale_fired = True
                break
    return states, counts, n_obs, chains_run, stale_fired

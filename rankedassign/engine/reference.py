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

import math

from .rng import SplitMix64, chain_state

__all__ = ["run_chains", "herd_choice"]


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


def herd_choice(table, key, p, init, capacity, tally, g):
    """One herded choice (Chen et al. 2016) among the ``len(p)`` candidates of a draw.

    Parameters
    ----------
    table : dict
        The chain's key table, key -> list of weights; a new key is added in place.
    key : tuple
        The draw's key (its row or component, and the statistic its conditional depends on).
    p : list of float
        The draw's conditional over its candidates (0 = impossible), at least one positive.
    init : {"conditional", "zero", "uniform"}
        A new key's initial weights: ``p``, zeros, or ``len(p)`` uniforms from ``g``.
    capacity : int
        Keys the table may hold.
    tally : list of int
        ``[keys created, fall-backs]``, updated in place.
    g : SplitMix64
        The chain's stream (uniform initial weights only).

    Returns
    -------
    int or None
        The candidate chosen, or None when ``key`` is new and the table is full (counted as
        a fall-back: the caller draws as the Gibbs sampler does).

    Notes
    -----
    A new key's weights are set to ``-inf`` where ``p`` is 0. Then ``w += p``, the choice is
    the first candidate with ``p > 0`` of the largest ``w``, and ``w[choice] -= 1``. The
    numba twin is :func:`rankedassign.engine._kernels.herd_lookup` followed by
    :func:`rankedassign.engine._kernels.herd_pick`.

    Examples
    --------
    >>> table, tally = {}, [0, 0]
    >>> [herd_choice(table, ("row", 0), [0.75, 0.25], "zero", 1, tally, None)
    ...  for _ in range(4)], tally
    ([0, 0, 1, 0], [1, 0])
    >>> herd_choice(table, ("row", 1), [1.0], "zero", 1, tally, None), tally
    (None, [1, 1])
    """
    w = table.get(key)
    K = len(p)
    if w is None:
        if len(table) >= capacity:
            tally[1] += 1
            return None
        if init == "conditional":
            w = list(p)
        elif init == "zero":
            w = [0.0] * K
        else:
            w = [g.uniform() for _ in range(K)]
        # a candidate the key's conditional gives probability 0 can never be picked
        w = [v if p[k] > 0.0 else -math.inf for k, v in enumerate(w)]
        table[key] = w
        tally[0] += 1
    best = -1
    for k in range(K):
        w[k] += p[k]
        if p[k] > 0.0 and (best < 0 or w[k] > w[best]):
            best = k
    w[best] -= 1.0
    return best

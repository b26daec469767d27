"""Tempered Gibbs sampling (Zanella & Roberts 2019) for the single-sensor problem.

At state ``x`` every row ``i`` has the ratio ``p_i(x) = g_i(x_i | x_{-i}) / π_i(x_i | x_{-i})``
of its tempered conditional ``g_i ∝ π_i^β`` to its conditional. A step picks row ``i`` with
probability ``p_i(x) / Z(x)``, ``Z(x) = Σ_i p_i(x)``, and draws ``x_i`` from ``g_i``. The chain
is reversible with respect to ``f(x) ∝ π(x) Z(x)``, so the weights ``1 / Z(x)`` of its states
turn their averages into expectations under ``π``: the importance-weighted marginals. The
unique states serve a truncation as those of the other samplers do (each is re-weighted by its
exact weight).

:func:`tempered_reference` is the specification of record (plain Python); :func:`sample_tempered`
runs the engine's compiled tempered loop with the row functions of :mod:`._tempered_kernels`,
bit for bit the same. The result record,
:class:`~rankedassign.engine.tempered.TemperedResult`, is the one every kind's tempered sampler
returns; :func:`rankedassign.sample_tempered` dispatches to this module for an
:class:`AssignmentProblem` (:attr:`Kind.tempered <rankedassign.engine.kind.Kind>`).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from ..engine.rng import base_key
from ..engine.tempered import TemperedResult, ess, run_compiled, run_reference
from ..numba_options import interruptible
from ..validation import check_beta, check_choice, check_int, check_type
from . import _tempered_kernels
from .prepare import CANCEL_GUARD, shifted_weights, start_columns, to_columns, to_compact
from .problem import AssignmentProblem

__all__ = ["TemperedResult", "sample_tempered", "tempered_reference"]


def _inputs(problem, n_steps, beta, start, rng):
    problem = check_type(problem, "problem", AssignmentProblem,
                         "tempered Gibbs sampling is implemented for single-sensor problems")
    n_steps = check_int(n_steps, "n_steps")
    beta = check_beta(beta)
    x0 = to_compact(problem, start_columns(problem, start))
    W = shifted_weights(problem)
    cc = problem.compact_cost
    shift = np.where(np.isfinite(cc), cc, np.inf).min(axis=1)
    d = cc - shift[:, None]
    fin = np.isfinite(d)
    with np.errstate(over="ignore", invalid="ignore"):
        Wb = np.where(fin, np.exp(-beta * np.where(fin, d, 0.0)), 0.0)
        R = np.where(fin, np.exp((1.0 - beta) * np.where(fin, d, 0.0)), 0.0)
    P, K = W.shape
    refresh = P + K
    return problem, n_steps, x0, W, np.ascontiguousarray(Wb), np.ascontiguousarray(R), \
        refresh, base_key(rng)


# Candidate evaluations per slice of the kernel (about a few milliseconds of moves); between
# slices the interpreter runs pending signal handlers. The tests shrink it: same bits.
_SLICE_WORK = 1 << 22


def _underflow(problem):
    raise ValueError(
        "tempered Gibbs sampling: a row's available weights underflowed (its available "
        "entries cost more than ~700 above its cheapest one); the weights of such a state are "
        f"not representable in this sampler's arithmetic ({problem!r})"
    )


def _result(problem, states, counts, acc, wsum, w2sum, n_steps):
    compact = np.asarray(states, dtype=np.int64).reshape(len(counts), problem.n_rows)
    assignments = to_columns(problem, compact)
    m = np.asarray(acc, dtype=np.float64) / wsum if wsum > 0 else np.asarray(acc) * 0.0
    for a in (assignments, m):
        a.setflags(write=False)
    costs = problem._sum_costs(assignments)
    costs.setflags(write=False)
    cnt = np.asarray(counts, dtype=np.int64).copy()
    cnt.setflags(write=False)
    return TemperedResult(assignments, costs, cnt, m, int(n_steps), ess(wsum, w2sum))


def tempered_reference(problem, n_steps, *, beta, start="all_missed", rng=None):
    """Tempered Gibbs sampling in plain Python: the specification of :func:`sample_tempered`.

    Parameters
    ----------
    problem : AssignmentProblem
    n_steps : int
    beta : float
    start, rng
        As in :func:`sample_tempered`.

    Returns
    -------
    TemperedResult
        The same bits as :func:`sample_tempered`.

    Notes
    -----
    With the shifted weights ``W`` of the Gibbs sampler, ``Wb = W^β`` and ``R = W^(β-1)``
    (0 where forbidden), row ``i`` keeps ``S_i`` and ``Sb_i``, the sums of ``W`` and ``Wb``
    over its available candidates (the measurements no other row holds, its own included,
    missed, dead), so
    ``p_i(x) = R_i(x_i) S_i / Sb_i``. One step:

    1. ``u Z``, ``u`` one uniform, picks the first row whose running sum of ``p`` exceeds it;
    2. the row releases its measurement ``a``: every other row adds ``W(a)``, ``Wb(a)``;
    3. one more uniform draws the new value ``c`` from the available ``Wb`` by the inverse
       CDF (left to right; the last positive candidate if rounding leaves none);
    4. every other row subtracts ``W(c)``, ``Wb(c)`` (and sums its row again if the
       subtraction cancelled all but :data:`~rankedassign.single.prepare.CANCEL_GUARD` of it);
    5. every ``P + M + 2`` steps all sums are formed again (bounds the rounding drift);
    6. the new state gets weight ``1 / Z`` and is added to the unique set.

    A step costs ``O(P + M)``: ``O(P)`` for the sums and the row, ``O(M)`` for the draw.
    Steps 1 and 6 are the loop every kind shares,
    :func:`rankedassign.engine.tempered.run_reference`; steps 2 to 5 are this kind's ``move``.

    Examples
    --------
    >>> from rankedassign import synthetic
    >>> res = tempered_reference(synthetic.diagonal(), 200, beta=0.5, rng=0)
    >>> int(res.counts.sum()), res.marginals.shape
    (200, (4, 18))
    """
    problem, n_steps, x0, W, Wb, R, refresh, base = _inputs(problem, n_steps, beta, start, rng)
    data = _RefData(W.tolist(), Wb.tolist(), R.tolist(), refresh)
    P, M = problem.n_rows, problem.n_meas
    x = [int(v) for v in x0]
    free = [1.0] * M
    for v in x:
        if v < M:
            free[v] = 0.0
    work = _RefWork(free, [0.0] * P, [0.0] * P, [0, 0])
    for i in range(P):
        work.S[i], work.Sb[i] = _row_sums(data, work, x, i)
    acc = [[0.0] * (M + 2) for _ in range(P)]
    out = run_reference(_weights, _move, _accumulate, data, work, x, P, acc, n_steps, base)
    if out is None:
        _underflow(problem)
    states, counts, wsum, w2sum = out
    return _result(problem, states, counts, acc, wsum, w2sum, n_steps)


class _RefData(NamedTuple):
    """The reference's weights, as lists (:class:`._tempered_kernels.SingleTemperedData`)."""

    W: list
    Wb: list
    R: list
    refresh: int


class _RefWork(NamedTuple):
    """The reference's running sums (:class:`._tempered_kernels.SingleTemperedWork`)."""

    free: list
    S: list
    Sb: list
    ctr: list


def _row_sums(data, work, x, i):
    """Row ``i``'s sums of ``W`` and ``Wb`` over its available candidates (its own measurement
    is one), left to right."""
    W, Wb, free = data.W[i], data.Wb[i], work.free
    M = len(free)
    s = sb = 0.0
    for k in range(M):
        f = 1.0 if k == x[i] else free[k]
        s += W[k] * f
        sb += Wb[k] * f
    return (s + W[M]) + W[M + 1], (sb + Wb[M]) + Wb[M + 1]


def _weights(data, work, x, p):
    """:func:`~rankedassign.engine.tempered.run_reference`'s ``weights``: ``p_i = R_i(x_i)
    S_i / Sb_i``; ``Z``, or -1.0 (a row's weights underflowed)."""
    S, Sb = work.S, work.Sb
    if work.ctr[1]:
        return -1.0
    Z = 0.0
    for i in range(len(x)):
        v = (data.R[i][x[i]] * S[i]) / Sb[i] if S[i] > 0.0 and Sb[i] > 0.0 else math.nan
        if not (v >= 0.0 and v < math.inf):
            return -1.0
        p[i] = v
        Z += v
    return Z


def _move(data, work, x, r, g):
    """``run_reference``'s ``move``: steps 2-5 of :func:`tempered_reference` (always True:
    the sums change by floating-point additions even when the row keeps its value)."""
    W, Wb, refresh = data.W, data.Wb, data.refresh
    free, S, Sb, ctr = work
    P, M = len(x), len(free)
    a = x[r]
    if a < M:
        free[a] = 1.0
        for i in range(P):
            if i != r:
                S[i] += W[i][a]
                Sb[i] += Wb[i][a]
    tot = 0.0
    for k in range(M):
        tot += Wb[r][k] * free[k]
    tot = (tot + Wb[r][M]) + Wb[r][M + 1]
    if not tot > 0.0:
        ctr[1] = 1  # the row's available tempered weights underflowed: refused by _weights
        return True
    u = g.uniform() * tot
    c, run = -1, 0.0
    for k in range(M + 2):
        wk = Wb[r][k] * free[k] if k < M else Wb[r][k]
        if wk > 0.0:
            run += wk
            c = k
            if run > u:
                break
    if c < M:
        free[c] = 0.0
        for i in range(P):
            if i != r:
                before, beforeb = S[i], Sb[i]
                S[i] -= W[i][c]
                Sb[i] -= Wb[i][c]
                if S[i] < CANCEL_GUARD * before or Sb[i] < CANCEL_GUARD * beforeb:
                    S[i], Sb[i] = _row_sums(data, work, x, i)
    x[r] = c
    ctr[0] += 1
    if ctr[0] % refresh == 0:
        for i in range(P):
            S[i], Sb[i] = _row_sums(data, work, x, i)
    return True


def _accumulate(data, work, x, acc, w):
    """``run_reference``'s ``accumulate``: ``acc[i][x_i] += w`` for every row."""
    for i in range(len(x)):
        acc[i][x[i]] += w


def sample_tempered(problem, n_steps, *, beta, start="all_missed", rng=None,
                    backend="numba") -> TemperedResult:
    """Tempered Gibbs sampling of Zanella & Roberts (2019): unique states, weighted marginals.

    Parameters
    ----------
    problem : AssignmentProblem
        A single-sensor problem (other kinds raise ``TypeError`` here;
        :func:`rankedassign.sample_tempered` sends them to their own tempered samplers).
    n_steps : int
        Moves (each updates one row), >= 0. ``P`` moves cost about one Gibbs sweep.
    beta : float
        Inverse temperature of the tempered conditionals ``g_i ∝ π_i^β``, in ``(0, 1]``;
        ``beta = 1`` is a random-scan Gibbs sampler with uniform row choice and weights 1/P.
    start : {"all_missed", "all_dead", "lsap"} or array_like of int
        Start state, as in :func:`rankedassign.sample_original`.
    rng : None, int, SeedSequence, BitGenerator or Generator
        Anything :func:`numpy.random.default_rng` accepts (one draw: the stream's key).
    backend : {"numba", "python"}
        The kernel or :func:`tempered_reference`; the results are identical.

    Returns
    -------
    TemperedResult
        ``assignments``, ``costs`` and ``counts`` of the unique states, the importance-weighted
        ``marginals`` (layout of :func:`oracle.marginals`) and the weights' effective sample
        size ``ess``.

    Raises
    ------
    TypeError
        If ``problem`` is not an :class:`~rankedassign.AssignmentProblem`.
    ValueError
        If ``beta`` is outside ``(0, 1]``, ``n_steps`` is negative, the start is infeasible,
        or a state's weights underflow (available entries more than ~700 above a row's
        cheapest: the message says so).

    Notes
    -----
    The weighted averages converge to expectations under ``π`` (the chain is reversible with
    respect to ``π(x) Z(x)``; Zanella & Roberts 2019, Prop. 1). Each row keeps the sums of its
    available weights and tempered weights, updated by the two measurements a move releases and
    takes, so a step costs ``O(P + M)`` (:func:`tempered_reference` gives the details); the
    sums are formed again every ``P + M + 2`` steps, which adds ``O(P M / (P + M))`` per step
    on average. Shim, Vo, Vo, Ong & Moratuwage (arXiv:2211.16041) describe a tempered Gibbs
    sampler for GLMB filtering of linear complexity in the same sense: the Samplers page of
    the documentation compares the two.

    References
    ----------
    .. [1] G. Zanella, G. Roberts, "Scalable importance tempering and Bayesian variable
       selection", J. R. Stat. Soc. B 81(3):489-517, 2019.
    .. [2] B.-N. Vo, B.-T. Vo, H. G. Hoang, "An Efficient Implementation of the Generalized
       Labeled Multi-Bernoulli Filter", IEEE Trans. Signal Process. 65(8):1975-1987, 2017.

    Examples
    --------
    >>> import numpy as np
    >>> import oracle
    >>> from rankedassign import sample_tempered, synthetic
    >>> p = synthetic.random(rng=0)
    >>> res = sample_tempered(p, 200_000, beta=0.5, rng=1)
    >>> bool(np.abs(res.marginals - oracle.marginals(p)).max() < 0.02)
    True
    >>> ref = sample_tempered(p, 2_000, beta=0.5, rng=1, backend="python")
    >>> fast = sample_tempered(p, 2_000, beta=0.5, rng=1)
    >>> bool((ref.marginals == fast.marginals).all() and (ref.counts == fast.counts).all())
    True
    """
    check_choice(backend, "backend", ("numba", "python"))
    if backend == "python":
        return tempered_reference(problem, n_steps, beta=beta, start=start, rng=rng)
    problem, n_steps, x0, W, Wb, R, refresh, base = _inputs(problem, n_steps, beta, start, rng)
    P, K = W.shape
    data = _tempered_kernels.SingleTemperedData(W=W, Wb=Wb, R=R, refresh=refresh)
    work = _tempered_kernels.SingleTemperedWork(free=np.ones(K - 2), S=np.empty(P),
                                                Sb=np.empty(P), ctr=np.zeros(2, np.int64))
    x0 = np.ascontiguousarray(x0, dtype=np.int32)
    with interruptible:
        _tempered_kernels.init_work(data, work, x0)
    acc = np.zeros((P, K))
    moves = max(1, _SLICE_WORK // (P + K))  # moves per slice: a few ms
    out = run_compiled(_tempered_kernels.KERNELS, data, work, x0, K, P, acc, n_steps, base,
                       moves)
    if out is None:
        _underflow(problem)
    states, counts, wsum, w2sum = out
    return _result(problem, states, counts, acc, wsum, w2sum, n_steps)

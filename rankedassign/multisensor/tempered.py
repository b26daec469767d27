"""Tempered Gibbs sampling (Zanella & Roberts 2019) of the multi-sensor posterior ``π``.

A row ``n`` is one object; its value is dead or a measurement tuple, one measurement or miss
per sensor. Its conditional is the exact one of the Gibbs sampler ``method="exact"`` (spec
eq. 2.1): ``π_n(u | γ_-n) ∝ η_n(u)`` over dead and ``A_n^(1) x ... x A_n^(V)``,
``A_n^(v)`` the missed entry and the measurements of sensor ``v`` that no other row holds.
The tempered conditional is ``g_n ∝ η_n^β`` over the same candidates, so a row's ratio is

    p_n(γ) = η_n(γ_n)^(β-1) Σ_{u ∈ A_n} η_n(u) / Σ_{u ∈ A_n} η_n(u)^β

and the loop of :mod:`rankedassign.engine.tempered` does the rest: a move picks row ``n``
with probability ``p_n / Z``, draws its value from ``g_n``, and the state gets the weight
``1 / Z``. The MM and componentwise row updates (``method="mm"``, ...) sample other targets or
update a row in several draws; they do not define ``π`` and are refused here.

:func:`tempered_reference` is the specification of record (plain Python, reusing the Gibbs
reference's :func:`~rankedassign.multisensor.reference._available`,
:func:`~rankedassign.multisensor.reference.exact_candidates` and
:func:`~rankedassign.multisensor.reference.pick`); :func:`sample_tempered` runs the numba
twin of :mod:`rankedassign.multisensor._tempered_kernels`, bit for bit the same.

References
----------
.. [1] G. Zanella, G. Roberts, "Scalable importance tempering and Bayesian variable
   selection", J. R. Stat. Soc. B 81(3):489-517, 2019.
.. [2] B.-N. Vo, B.-T. Vo, M. Beard, "Multi-Sensor Multi-Object Tracking with the Generalized
   Labeled Multi-Bernoulli Filter", IEEE Trans. Signal Process. 67(23):5952-5967, 2019.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ..engine.tempered import TemperedResult, ess, run_compiled, run_reference, store_ratio
from ..numba_options import interruptible
from ..validation import check_beta, check_choice, check_int, check_type
from . import _tempered_kernels
from .prepare import METHODS, prepare, states_to_assignments
from .problem import MultiSensorProblem
from .reference import RefData, _apply_row, _available, exact_candidates, new_work, pick

__all__ = ["TemperedMarginals", "TemperedData", "sample_tempered", "tempered_reference",
           "tempered_weights", "tempered_move", "tempered_accumulate"]

# Candidate evaluations per slice of the kernel (a few milliseconds of moves); between slices
# the interpreter runs pending signal handlers. The tests shrink it: same bits.
_SLICE_WORK = 1 << 22


class TemperedMarginals(NamedTuple):
    """Importance-weighted association marginals, in the layout of
    :class:`oracle.multisensor.MultiSensorMarginals`.

    Attributes
    ----------
    dead : ndarray, float64, shape (P,)
        Estimate of ``P(γ_n = -1)``.
    tuples : ndarray, float64, shape (P, M_1+1, ..., M_V+1)
        Estimate of ``P(γ_n = t)`` for every tuple; ``dead[n] + tuples[n].sum() = 1`` (up
        to rounding) after at least one move.
    sensors : tuple of V ndarrays, float64, shape (P, M_v + 2)
        Per sensor, the single-sensor layout: ``[:, j - 1]`` ``P(γ_n^(v) = j)``, ``[:, M_v]``
        alive and missed by sensor ``v``, ``[:, M_v + 1]`` dead.
    """

    dead: np.ndarray
    tuples: np.ndarray
    sensors: tuple


class TemperedData(NamedTuple):
    """The reference's inputs: the exact Gibbs sampler's and the tempered weights, as lists.

    Every weight is shifted by the same constant per row as the Gibbs sampler's ``Wd``/``Wa``
    (the largest ``ln η_n`` of the row, ``m_n``): with ``d = ln η_n(u) - m_n``,
    ``W = exp(d)``, ``Wb = exp(β d)`` and ``R = exp((1 - β) (-d)) = W^(β - 1)``, 0 where
    ``η_n(u) = 0`` (``R`` may overflow to ``inf`` for a candidate ~``700 / (1 - β)`` below
    the row's best: such a state is refused when it is reached).

    Attributes
    ----------
    base : RefData
        The Gibbs reference's inputs for ``method="exact"`` (``V``, ``n_meas``, ``strides``,
        ``Wd``, ``Wa``).
    Wbd, Rd : list of float, length P
        ``Wb`` and ``R`` of dead.
    Wba, Ra : list of list of float, shape (P, T)
        ``Wb`` and ``R`` of every tuple (flat, C order; ``T = prod_v (M_v + 1)``).
    """

    base: RefData
    Wbd: list
    Rd: list
    Wba: list
    Ra: list


def _check_method(method):
    check_choice(method, "method", METHODS)
    if method != "exact":
        raise ValueError(
            f"method={method!r} does not apply to tempered Gibbs sampling: its target is the "
            "exact posterior pi, whose row conditional is method='exact' (spec eq. 2.1); the "
            "MM and componentwise row updates are Gibbs proposals of other targets or of "
            "several draws per row; use method='exact' (the default)")


def _underflow(problem):
    raise ValueError(
        "tempered Gibbs sampling: a row's available weights underflowed (its available "
        "candidates weigh less than ~exp(-700) times its best one); the weights of such a "
        f"state are not representable in this sampler's arithmetic ({problem!r})")


def _inputs(problem, n_steps, beta, start, rng, method):
    """Validate a call; the kernel's data, the reference's data, the start, the base key."""
    problem = check_type(problem, "problem", MultiSensorProblem,
                         "build one with MultiSensorProblem.from_eta / from_log_eta")
    n_steps = check_int(n_steps, "n_steps")
    beta = check_beta(beta)
    _check_method(method)
    if problem.n_rows == 0:
        raise ValueError("tempered Gibbs sampling needs at least one row; this problem has "
                         "P = 0 (its one assignment, the empty one, is certain)")
    prep = prepare(problem, start, "systematic", rng, {"method": "exact"})
    logs = np.concatenate([prep.data.ld[:, None], prep.data.la], axis=1)
    # the Gibbs sampler's shift (prepare._shift): the largest log-weight of the row
    d = logs - np.max(logs, axis=1, keepdims=True)
    fin = np.isfinite(d)
    with np.errstate(over="ignore", invalid="ignore"):
        Wb = np.where(fin, np.exp(beta * np.where(fin, d, 0.0)), 0.0)
        # R = g / pi up to the sums: W^(beta - 1), large for improbable candidates
        R = np.where(fin, np.exp((1.0 - beta) * np.where(fin, -d, 0.0)), 0.0)
    Wbd, Wba = np.ascontiguousarray(Wb[:, 0]), np.ascontiguousarray(Wb[:, 1:])
    Rd, Ra = np.ascontiguousarray(R[:, 0]), np.ascontiguousarray(R[:, 1:])
    data = _tempered_kernels.MultiSensorTemperedData(
        n_meas=prep.data.n_meas, strides=prep.data.strides, Wd=prep.data.Wd, Wbd=Wbd, Rd=Rd,
        Wa=prep.data.Wa, Wba=Wba, Ra=Ra)
    return problem, n_steps, prep, data


def _code(base, x, n):
    """Candidate code of row ``n``: 0 dead, ``1 + offset`` of its tuple."""
    V = base.V
    if x[n * V] == 0:
        return 0
    off = 0
    for v in range(V):
        off += (x[n * V + v] - 1) * base.strides[v]
    return 1 + off


def tempered_weights(data: TemperedData, work, x, p) -> float:
    """Every row's ratio ``p_n = R(γ_n) S_n / Sb_n`` into ``p``; their sum ``Z``.

    Parameters
    ----------
    data : TemperedData
    work : tuple
        ``(occ, Sb)``: the occupancy table of ``x``
        (:func:`rankedassign.multisensor.reference.new_work`) and a list of ``P`` floats that
        receives each row's ``Sb_n`` (the total of its tempered draw).
    x : list of int, length P * V
        State, ``x[n * V + v] = γ_n^(v) + 1``.
    p : list of float, length P
        Receives the ratios.

    Returns
    -------
    float
        ``Z = Σ_n p_n`` (left to right), or ``-1.0`` if a row's sums ``S_n`` or ``Sb_n``
        underflowed to 0 or a ratio is not finite.

    Notes
    -----
    ``S_n`` and ``Sb_n`` are the sums of ``W`` and ``Wb`` over row ``n``'s available
    candidates in candidate order: dead, then the tuples of
    :func:`~rankedassign.multisensor.reference.exact_candidates` (increasing offset).
    ``p_n = (R(γ_n) S_n) / Sb_n``: at ``β = 1`` exactly 1.

    Examples
    --------
    >>> from rankedassign.multisensor import synthetic
    >>> from rankedassign.multisensor.tempered import _inputs, _reference_data
    >>> _, _, prep, kdata = _inputs(synthetic.diagonal(), 0, 1.0, "all_missed", 0, "exact")
    >>> data = _reference_data(prep, kdata)
    >>> x = prep.x0.tolist()
    >>> p = [0.0] * 4
    >>> tempered_weights(data, (new_work(data.base, x), [0.0] * 4), x, p), p
    (4.0, [1.0, 1.0, 1.0, 1.0])
    """
    base = data.base
    occ, Sb = work
    Z = 0.0
    for n in range(base.P):
        _, offsets = exact_candidates(base, _available(base, occ, x, n))
        Wa, Wba = base.Wa[n], data.Wba[n]
        s, sb = base.Wd[n], data.Wbd[n]
        for off in offsets:
            s += Wa[off]
            sb += Wba[off]
        if not (s > 0.0 and sb > 0.0):
            return -1.0
        k = _code(base, x, n)
        rr = data.Rd[n] if k == 0 else data.Ra[n][k - 1]
        v = store_ratio(p, Sb, n, rr, s, sb)
        if v < 0.0:
            return -1.0
        Z += v
    return Z


def tempered_move(data: TemperedData, work, x, r, g) -> bool:
    """Row ``r``'s new value drawn from ``g_r ∝ Wb`` over its available candidates.

    Parameters
    ----------
    data : TemperedData
    work : tuple
        ``(occ, Sb)`` as :func:`tempered_weights` left them; ``occ`` is kept up to date.
    x : list of int, length P * V
        State, updated in place.
    r : int
        The row.
    g : SplitMix64
        The stream (one uniform).

    Returns
    -------
    bool
        Whether row ``r`` changed.

    Notes
    -----
    One uniform ``u``; :func:`~rankedassign.multisensor.reference.pick` over the tempered
    weights of dead and of the available tuples (candidate order) with the total ``Sb_r``
    of :func:`tempered_weights` (the same sum).
    """
    base = data.base
    occ, Sb = work
    V = base.V
    tuples, offsets = exact_candidates(base, _available(base, occ, x, r))
    Wba = data.Wba[r]
    k = pick([data.Wbd[r]] + [Wba[off] for off in offsets], Sb[r], g.uniform())
    row = [-1] * V if k == 0 else tuples[k - 1]
    before = x[r * V:(r + 1) * V]
    _apply_row(base, occ, x, r, row)
    return x[r * V:(r + 1) * V] != before


def tempered_accumulate(data: TemperedData, work, x, acc, w) -> None:
    """``acc[n][code(γ_n)] += w`` for every row (code 0 dead, ``1 + offset`` of a tuple).

    Parameters
    ----------
    data : TemperedData
    work : tuple
        Not read.
    x : list of int, length P * V
        The state.
    acc : list of list of float, shape (P, 1 + T)
        The accumulator.
    w : float
        The state's weight ``1 / Z``.
    """
    for n in range(data.base.P):
        acc[n][_code(data.base, x, n)] += w


def _reference_data(prep, kdata) -> TemperedData:
    return TemperedData(prep.ref_data, kdata.Wbd.tolist(), kdata.Rd.tolist(),
                        kdata.Wba.tolist(), kdata.Ra.tolist())


def _marginals(problem, acc, wsum) -> TemperedMarginals:
    P = problem.n_rows
    A = np.asarray(acc, dtype=np.float64) / wsum if wsum > 0 else np.zeros(np.shape(acc))
    dead = np.ascontiguousarray(A[:, 0])
    tuples = np.ascontiguousarray(A[:, 1:]).reshape((P,) + tuple(m + 1 for m in problem.n_meas))
    V = problem.n_sensors
    sensors = []
    for v, m in enumerate(problem.n_meas):  # as oracle.multisensor's packaging
        other = tuple(a for a in range(1, V + 1) if a != v + 1)
        per = tuples.sum(axis=other) if other else tuples
        out = np.empty((P, m + 2))
        out[:, :m] = per[:, 1:]
        out[:, m] = per[:, 0]
        out[:, m + 1] = dead
        out.setflags(write=False)
        sensors.append(out)
    for a in (dead, tuples):
        a.setflags(write=False)
    return TemperedMarginals(dead, tuples, tuple(sensors))


def _result(problem, states, counts, acc, wsum, w2sum, n_steps) -> TemperedResult:
    flat = np.asarray(states, dtype=np.int64).reshape(len(counts), -1)
    assignments = states_to_assignments(problem, flat)
    assignments.setflags(write=False)
    costs = np.asarray(problem.cost_of(assignments), dtype=np.float64).reshape(-1)
    costs.setflags(write=False)
    cnt = np.asarray(counts, dtype=np.int64).copy()
    cnt.setflags(write=False)
    return TemperedResult(assignments, costs, cnt, _marginals(problem, acc, wsum),
                          int(n_steps), ess(wsum, w2sum))


def tempered_reference(problem, n_steps, *, beta, start="all_missed", rng=None,
                       method="exact") -> TemperedResult:
    """Tempered Gibbs sampling in plain Python: the specification of :func:`sample_tempered`.

    Parameters
    ----------
    problem : MultiSensorProblem
    n_steps : int
    beta : float
    start, rng, method
        As in :func:`sample_tempered`.

    Returns
    -------
    TemperedResult
        The same bits as :func:`sample_tempered`.

    Notes
    -----
    The loop is :func:`rankedassign.engine.tempered.run_reference` with the row functions
    :func:`tempered_weights`, :func:`tempered_move` and :func:`tempered_accumulate`. After
    each move that changes the state every row's ratio is computed again from the
    occupancy table: a move costs ``O(P (T_A + Σ_v M_v))``, ``T_A <= prod_v (M_v + 1)`` the
    available tuples of a row, which is what one sweep of the exact Gibbs sampler costs.

    Examples
    --------
    >>> from rankedassign.multisensor import synthetic
    >>> res = tempered_reference(synthetic.diagonal(P=2, M=(2, 2)), 200, beta=0.5, rng=0)
    >>> int(res.counts.sum()), res.assignments.shape[1:], res.marginals.tuples.shape
    (200, (2, 2), (2, 3, 3))
    """
    problem, n_steps, prep, kdata = _inputs(problem, n_steps, beta, start, rng, method)
    data = _reference_data(prep, kdata)
    P = problem.n_rows
    x = prep.x0.tolist()
    work = (new_work(data.base, x), [0.0] * P)
    acc = [[0.0] * (1 + kdata.Wa.shape[1]) for _ in range(P)]
    out = run_reference(tempered_weights, tempered_move, tempered_accumulate, data, work, x, P,
                        acc, n_steps, prep.base)
    if out is None:
        _underflow(problem)
    states, counts, wsum, w2sum = out
    return _result(problem, states, counts, acc, wsum, w2sum, n_steps)


def sample_tempered(problem, n_steps, *, beta, start="all_missed", rng=None, backend="numba",
                    method="exact") -> TemperedResult:
    """Tempered Gibbs sampling of Zanella & Roberts (2019) on a multi-sensor problem.

    Parameters
    ----------
    problem : MultiSensorProblem
        The problem; its target is the exact posterior ``π ∝ Π_n η_n(γ_n)`` on the feasible
        assignments.
    n_steps : int
        Moves (each updates one row: dead or a whole tuple), >= 0. ``P`` moves cost about
        ``P`` exact Gibbs sweeps (each move recomputes every row's ratio).
    beta : float
        Inverse temperature of the tempered conditionals ``g_n ∝ π_n^β``, in ``(0, 1]``;
        ``beta = 1`` is a random-scan exact Gibbs sampler with uniform row choice.
    start : {"all_missed", "all_dead"} or array_like of int, shape (P, V)
        Start state, as in :func:`rankedassign.sample_original`.
    rng : None, int, SeedSequence, BitGenerator or Generator
        Anything :func:`numpy.random.default_rng` accepts (one draw: the stream's key).
    backend : {"numba", "python"}
        The kernel or :func:`tempered_reference`; the results are identical.
    method : {"exact"}
        The row conditional, for symmetry with the Gibbs samplers' option; only ``"exact"``
        defines ``π`` (the MM and componentwise updates are refused).

    Returns
    -------
    TemperedResult
        ``assignments`` (``(n_unique, P, V)`` labels ``γ``: ``-1`` dead, ``0`` missed, ``j``
        measurement ``j``), their ``costs`` (``problem.cost_of``) and ``counts``, the
        importance-weighted ``marginals`` (:class:`TemperedMarginals`, the layout of
        :func:`oracle.marginals`) and the weights' effective sample size ``ess``.

    Raises
    ------
    TypeError
        If ``problem`` is not a :class:`~rankedassign.multisensor.MultiSensorProblem`.
    ValueError
        If ``beta`` is outside ``(0, 1]``, ``n_steps`` is negative, ``method`` is not
        ``"exact"``, the problem has no row, the start is infeasible, or a state's weights
        underflow (available candidates weighing less than ~``exp(-700)`` times the row's
        best one: the message says so).

    Notes
    -----
    Row ``n``'s ratio is ``p_n = η_n(γ_n)^(β-1) Σ_{A_n} η_n / Σ_{A_n} η_n^β`` over its
    available candidates ``A_n`` (dead and the tuples whose measurements no other row holds,
    spec eq. 2.1); the weighted averages converge to expectations under ``π`` (Zanella &
    Roberts 2019, Prop. 1). Every move that changes the state computes all ``P`` ratios
    again: ``O(P (T_A + Σ_v M_v))`` per move, ``T_A <= prod_v (M_v + 1)`` a row's available
    tuples (no running sums as in the single-sensor sampler: a measurement taken or
    released changes a row's sums by a slice of its tuples, not one term).

    References
    ----------
    .. [1] G. Zanella, G. Roberts, "Scalable importance tempering and Bayesian variable
       selection", J. R. Stat. Soc. B 81(3):489-517, 2019.
    .. [2] B.-N. Vo, B.-T. Vo, M. Beard, "Multi-Sensor Multi-Object Tracking with the
       Generalized Labeled Multi-Bernoulli Filter", IEEE Trans. Signal Process.
       67(23):5952-5967, 2019.

    Examples
    --------
    >>> import numpy as np
    >>> import oracle
    >>> from rankedassign.multisensor import synthetic
    >>> p = synthetic.random(P=3, M=(2, 2), rng=0)
    >>> res = sample_tempered(p, 100_000, beta=0.5, rng=1)
    >>> bool(np.abs(res.marginals.tuples - oracle.marginals(p).tuples).max() < 0.02)
    True
    >>> ref = sample_tempered(p, 1_000, beta=0.5, rng=1, backend="python")
    >>> fast = sample_tempered(p, 1_000, beta=0.5, rng=1)
    >>> bool((ref.marginals.tuples == fast.marginals.tuples).all())
    True
    """
    check_choice(backend, "backend", ("numba", "python"))
    if backend == "python":
        return tempered_reference(problem, n_steps, beta=beta, start=start, rng=rng,
                                  method=method)
    problem, n_steps, prep, data = _inputs(problem, n_steps, beta, start, rng, method)
    P, V = problem.n_rows, problem.n_sensors
    K = max(problem.n_meas) + 1
    T = data.Wa.shape[1]
    work = _tempered_kernels.MultiSensorTemperedWork(
        occ=np.zeros((V, K), dtype=np.int64), avail=np.zeros((V, K), dtype=np.int64),
        navail=np.zeros(V, dtype=np.int64), idx=np.zeros(V, dtype=np.int64), Sb=np.zeros(P),
        row=np.zeros(V, dtype=np.int64))
    with interruptible:
        _tempered_kernels.occupancy(work.occ, prep.x0)
    acc = np.zeros((P, 1 + T))
    moves = max(1, _SLICE_WORK // (P * (1 + T + sum(problem.n_meas))))
    out = run_compiled(_tempered_kernels.KERNELS, data, work, prep.x0, prep.n_values, P, acc,
                       n_steps, prep.base, moves)
    if out is None:
        _underflow(problem)
    states, counts, wsum, w2sum = out
    return _result(problem, states, counts, acc, wsum, w2sum, n_steps)

"""Tempered Gibbs sampling (Zanella & Roberts 2019) of the adaptive-birth tuple posterior.

The state is one measurement tuple ``J = (j^(1), ..., j^(V))`` and, as in the kind's Gibbs
sweep, a *row* is one sensor's entry: its conditional is spec eq. 4.3,
``π_B(j^(s) = j | J^-s) ∝ ρ(J^-s ⊕ j)`` over ``j = 0..M_s``, from the log-weights of
:func:`rankedassign.adaptive_birth.reference.conditional_log_weights` (read from the tensor,
or the linear-Gaussian ratio form). With ``l_j`` those log-weights and ``m = max_j l_j``, the
tempered conditional is ``g_s ∝ exp(β (l_j - m))`` and sensor ``s``'s ratio

    p_s(J) = exp((1 - β) (m - l_{j^(s)})) Σ_j exp(l_j - m) / Σ_j exp(β (l_j - m))

(every sum left to right), and the loop of :mod:`rankedassign.engine.tempered` does the rest:
a move picks sensor ``s`` with probability ``p_s / Z`` and draws its entry from ``g_s``; the
state gets the weight ``1 / Z``.

:func:`tempered_reference` is the specification of record (plain Python, reusing the Gibbs
reference); :func:`sample_tempered` runs the numba twin of
:mod:`rankedassign.adaptive_birth._tempered_kernels`, bit for bit the same.

References
----------
.. [1] G. Zanella, G. Roberts, "Scalable importance tempering and Bayesian variable
   selection", J. R. Stat. Soc. B 81(3):489-517, 2019.
.. [2] A. Trezza, D. J. Bucci Jr., P. K. Varshney, "Multi-sensor joint adaptive birth sampler
   for labeled random finite set tracking", IEEE Trans. Signal Process. 70, 2022.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from ..engine.tempered import TemperedResult, ess, run_compiled, run_reference, store_ratio
from ..multisensor.reference import pick
from ..validation import check_beta, check_choice, check_int, check_type
from . import _tempered_kernels
from .prepare import prepare
from .problem import AdaptiveBirthProblem
from .reference import RefData, _sums, conditional_log_weights, new_work

__all__ = ["TemperedData", "sample_tempered", "tempered_reference", "tempered_weights",
           "tempered_move", "tempered_accumulate"]

# Candidate evaluations per slice of the kernel (a few milliseconds of moves); between slices
# the interpreter runs pending signal handlers. The tests shrink it: same bits.
_SLICE_WORK = 1 << 22


class TemperedData(NamedTuple):
    """The reference's inputs.

    Attributes
    ----------
    base : RefData
        The Gibbs reference's inputs (tensor or linear-Gaussian mode).
    beta : float
        The inverse temperature.
    """

    base: RefData
    beta: float


def _overflow(problem):
    raise ValueError(
        "tempered Gibbs sampling: a sensor's tempering ratio overflowed (its current entry is "
        "less likely than ~exp(-700 / (1 - beta)) times its best one under its conditional); "
        f"the weights of such a state are not representable in this sampler's arithmetic "
        f"({problem!r})")


def _inputs(problem, n_steps, beta, start, rng):
    """Validate a call; the Gibbs sampler's prepared inputs (a fixed order: not used)."""
    problem = check_type(problem, "problem", AdaptiveBirthProblem,
                         "build one with AdaptiveBirthProblem.from_log_weights / "
                         "from_measurements")
    n_steps = check_int(n_steps, "n_steps")
    beta = check_beta(beta)
    prep = prepare(problem, start, "systematic", rng, {"sensor_order": "fixed"})
    return problem, n_steps, beta, prep


def tempered_weights(data: TemperedData, work, x, p) -> float:
    """Every sensor's ratio ``p_s`` into ``p`` (and its tempered weights into ``work``).

    Parameters
    ----------
    data : TemperedData
    work : tuple
        ``(sums, Wb, Sb)``: the Gibbs reference's scratch
        (:func:`rankedassign.adaptive_birth.reference.new_work`), a list of ``V`` lists that
        receives each sensor's tempered weights ``exp(β (l_j - m))`` and a list of ``V``
        floats that receives their sums.
    x : list of int, length V
        The tuple ``J``.
    p : list of float, length V
        Receives the ratios.

    Returns
    -------
    float
        ``Z = Σ_s p_s`` (left to right), or ``-1.0`` if a ratio is not finite.

    Notes
    -----
    For each sensor ``s`` in turn: in linear-Gaussian mode the information sums of ``x``
    (the reference's ``_sums``), then the log-weights ``l`` of
    :func:`~rankedassign.adaptive_birth.reference.conditional_log_weights`; ``m = max l``
    (first to last), ``S = Σ exp(l_j - m)``, ``Sb = Σ exp(β (l_j - m))`` and
    ``p_s = (exp((1 - β) (m - l_{x_s})) S) / Sb``; at ``β = 1`` exactly 1.

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign.adaptive_birth.tempered import _inputs
    >>> p = AdaptiveBirthProblem.from_log_weights(np.log([[1.0, 3.0]]))
    >>> _, _, _, prep = _inputs(p, 0, 0.5, "all_missed", 0)
    >>> data = TemperedData(prep.ref_data, 0.5)
    >>> ratios = [0.0, 0.0]
    >>> Z = tempered_weights(data, (new_work(data.base, [0, 0]), [[], []], [0.0, 0.0]),
    ...                      [0, 0], ratios)
    >>> [round(r, 6) for r in ratios]     # sensor 1: g(0) / pi(0) = (1 / (1 + 3**0.5)) / (1 / 4)
    [1.0, 1.464102]
    """
    base = data.base
    beta = data.beta
    sums, Wb, Sb = work
    Z = 0.0
    for s in range(base.V):
        if base.mode == 1:
            _sums(base, sums, x)
        lw, _ = conditional_log_weights(base, sums, x, s)
        mx = lw[0]
        for w in lw:
            if w > mx:
                mx = w
        S = sb = 0.0
        wb = []
        for w in lw:
            S += math.exp(w - mx)
            e = math.exp(beta * (w - mx))
            wb.append(e)
            sb += e
        try:
            rr = math.exp((1.0 - beta) * (mx - lw[x[s]]))
        except OverflowError:  # the kernel's exp gives inf, hence a ratio it refuses too
            return -1.0
        ratio = store_ratio(p, Sb, s, rr, S, sb)
        if ratio < 0.0:
            return -1.0
        Wb[s] = wb
        Z += ratio
    return Z


def tempered_move(data: TemperedData, work, x, r, g) -> bool:
    """Sensor ``r``'s new entry drawn from ``g_r`` (one uniform, the inverse CDF).

    Parameters
    ----------
    data : TemperedData
    work : tuple
        ``(sums, Wb, Sb)`` as :func:`tempered_weights` left them.
    x : list of int, length V
        The tuple, updated in place.
    r : int
        The sensor.
    g : SplitMix64
        The stream.

    Returns
    -------
    bool
        Whether the entry changed.

    Notes
    -----
    ``j`` is the first entry whose running sum of the positive ``Wb[r]`` exceeds
    ``u Sb[r]``, the last positive one if rounding leaves none.
    """
    _, Wb, Sb = work
    k = pick(Wb[r], Sb[r], g.uniform())
    changed = k != x[r]
    x[r] = k
    return changed


def tempered_accumulate(data: TemperedData, work, x, acc, w) -> None:
    """``acc[s][x[s]] += w`` for every sensor.

    Parameters
    ----------
    data : TemperedData
    work : tuple
        Not read.
    x : list of int, length V
        The tuple.
    acc : list of list of float, shape (V, max_v M_v + 1)
        The accumulator.
    w : float
        The state's weight ``1 / Z``.
    """
    for s in range(len(x)):
        acc[s][x[s]] += w


def _result(problem, states, counts, acc, wsum, w2sum, n_steps) -> TemperedResult:
    V = problem.n_sensors
    assignments = np.asarray(states, dtype=np.int64).reshape(len(counts), V)
    assignments.setflags(write=False)
    costs = np.asarray(problem.cost_of(assignments), dtype=np.float64).reshape(-1)
    costs.setflags(write=False)
    cnt = np.asarray(counts, dtype=np.int64).copy()
    cnt.setflags(write=False)
    A = np.asarray(acc, dtype=np.float64)
    marginals = []
    for v, k in enumerate(problem.shape):
        m = A[v, :k] / wsum if wsum > 0 else np.zeros(k)
        m.setflags(write=False)
        marginals.append(m)
    return TemperedResult(assignments, costs, cnt, marginals, int(n_steps), ess(wsum, w2sum))


def tempered_reference(problem, n_steps, *, beta, start="all_missed", rng=None
                       ) -> TemperedResult:
    """Tempered Gibbs sampling in plain Python: the specification of :func:`sample_tempered`.

    Parameters
    ----------
    problem : AdaptiveBirthProblem
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
    The loop is :func:`rankedassign.engine.tempered.run_reference` with the row functions
    :func:`tempered_weights`, :func:`tempered_move` and :func:`tempered_accumulate`. After
    each move that changes the tuple every sensor's conditional is computed again: a move
    costs ``O(Σ_s M_s)`` on a tensor and ``O(V² n² + V n³ + n² Σ_s M_s)`` in linear-Gaussian
    form (``n`` the state dimension), about what one Gibbs sweep costs.

    Examples
    --------
    >>> from rankedassign.adaptive_birth import synthetic
    >>> res = tempered_reference(synthetic.make_family("uniform", 3, 2), 300, beta=0.5, rng=0)
    >>> int(res.counts.sum()), [m.shape for m in res.marginals]
    (300, [(3,), (3,), (3,)])
    """
    problem, n_steps, beta, prep = _inputs(problem, n_steps, beta, start, rng)
    data = TemperedData(prep.ref_data, beta)
    V = problem.n_sensors
    x = prep.x0.tolist()
    work = (new_work(data.base, x), [[] for _ in range(V)], [0.0] * V)
    acc = [[0.0] * max(problem.shape) for _ in range(V)]
    out = run_reference(tempered_weights, tempered_move, tempered_accumulate, data, work, x, V,
                        acc, n_steps, prep.base)
    if out is None:
        _overflow(problem)
    states, counts, wsum, w2sum = out
    return _result(problem, states, counts, acc, wsum, w2sum, n_steps)


def sample_tempered(problem, n_steps, *, beta, start="all_missed", rng=None, backend="numba"
                    ) -> TemperedResult:
    """Tempered Gibbs sampling of Zanella & Roberts (2019) on an adaptive-birth problem.

    Parameters
    ----------
    problem : AdaptiveBirthProblem
        The problem; its target is ``π_B = ρ / Σ ρ`` over the whole tuple space (spec
        eq. 4.2).
    n_steps : int
        Moves (each redraws one sensor's entry), >= 0. ``V`` moves cost about ``V`` Gibbs
        sweeps (each move recomputes every sensor's conditional).
    beta : float
        Inverse temperature of the tempered conditionals ``g_s ∝ π_s^β``, in ``(0, 1]``;
        ``beta = 1`` is a random-scan Gibbs sampler with uniform sensor choice.
    start : "all_missed" or array_like of int, shape (V,)
        Start tuple, as in :func:`rankedassign.sample_original`.
    rng : None, int, SeedSequence, BitGenerator or Generator
        Anything :func:`numpy.random.default_rng` accepts (one draw: the stream's key).
    backend : {"numba", "python"}
        The kernel or :func:`tempered_reference`; the results are identical.

    Returns
    -------
    TemperedResult
        ``assignments`` (``(n_unique, V)`` tuples), their ``costs`` (``problem.cost_of``,
        ``-ln ρ``) and ``counts``, the importance-weighted ``marginals`` (a list of ``V``
        arrays ``(M_v + 1,)``, the layout of :func:`oracle.marginals`) and the weights'
        effective sample size ``ess``.

    Raises
    ------
    TypeError
        If ``problem`` is not an :class:`~rankedassign.adaptive_birth.AdaptiveBirthProblem`.
    ValueError
        If ``beta`` is outside ``(0, 1]``, ``n_steps`` is negative, the start tuple is out of
        range or of zero weight, or a state's ratio overflows (an entry of conditional
        probability below ~``exp(-700 / (1 - β))``: the message says so).

    Notes
    -----
    A sensor's conditional is fixed by the other sensors' entries (spec eq. 4.3); there is no
    coupling constraint between sensors, but every sensor's conditional depends on every
    other entry, so every move that changes the tuple computes all ``V`` ratios again:
    ``O(Σ_s M_s)`` per move on a tensor, ``O(V² n² + V n³ + n² Σ_s M_s)`` in linear-Gaussian
    form. The weighted averages converge to expectations under ``π_B`` (Zanella & Roberts
    2019, Prop. 1). The unique tuples serve a birth (:func:`~rankedassign.adaptive_birth.
    birth_from_samples`) as the Gibbs sampler's do.

    References
    ----------
    .. [1] G. Zanella, G. Roberts, "Scalable importance tempering and Bayesian variable
       selection", J. R. Stat. Soc. B 81(3):489-517, 2019.
    .. [2] A. Trezza, D. J. Bucci Jr., P. K. Varshney, "Multi-sensor joint adaptive birth
       sampler for labeled random finite set tracking", IEEE Trans. Signal Process. 70, 2022.

    Examples
    --------
    >>> import numpy as np
    >>> import oracle
    >>> p = AdaptiveBirthProblem.from_log_weights(np.random.default_rng(0).normal(0, 2, (3, 4, 5)))
    >>> res = sample_tempered(p, 100_000, beta=0.5, rng=1)
    >>> exact = oracle.marginals(p)
    >>> bool(max(np.abs(m - e).max() for m, e in zip(res.marginals, exact)) < 0.02)
    True
    >>> ref = sample_tempered(p, 500, beta=0.5, rng=1, backend="python")
    >>> fast = sample_tempered(p, 500, beta=0.5, rng=1)
    >>> bool((ref.counts == fast.counts).all() and ref.ess == fast.ess)
    True
    """
    check_choice(backend, "backend", ("numba", "python"))
    if backend == "python":
        return tempered_reference(problem, n_steps, beta=beta, start=start, rng=rng)
    problem, n_steps, beta, prep = _inputs(problem, n_steps, beta, start, rng)
    data = _tempered_kernels.AdaptiveBirthTemperedData(**prep.data._asdict(), beta=beta)
    V = problem.n_sensors
    n = int(prep.data.n)
    K = max(problem.shape)
    work = _tempered_kernels.AdaptiveBirthTemperedWork(
        M=np.zeros((n, n)), b=np.zeros(n), c=np.zeros(1), Mp=np.zeros((n, n)),
        L=np.zeros((n, n)), y=np.zeros(n), bj=np.zeros(n), lw=np.zeros(K), Wb=np.zeros((V, K)),
        Sb=np.zeros(V))
    acc = np.zeros((V, K))
    moves = max(1, _SLICE_WORK // (prep.sweep_cost + V * V * n * n))
    out = run_compiled(_tempered_kernels.KERNELS, data, work, prep.x0, prep.n_values, V, acc,
                       n_steps, prep.base, moves)
    if out is None:
        _overflow(problem)
    states, counts, wsum, w2sum = out
    return _result(problem, states, counts, acc, wsum, w2sum, n_steps)

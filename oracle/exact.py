"""The oracle's public functions, for every problem kind.

Each function finds the problem's kind (:func:`rankedassign.kinds.kind_of`) and calls the
function of the same name in the oracle's folder for that kind: :mod:`oracle.single`,
:mod:`oracle.multisensor` or :mod:`oracle.adaptive_birth`. A new kind is a new folder there,
named as the kind, with no table to edit.
"""

from __future__ import annotations

import importlib

from rankedassign.kinds import kind_of

from ._result import Ranked

__all__ = ["enumerate_assignments", "log_normalizer", "marginals", "truncation_error",
           "best_mass"]


def _solver(problem, name: str):
    """The function ``name`` of the oracle folder of ``problem``'s kind."""
    kind = kind_of(problem)
    module = importlib.import_module(f"{__package__}.{kind.name}")
    try:
        return getattr(module, name)
    except AttributeError:
        raise TypeError(
            f"{name} does not apply to problems of type {type(problem).__name__} (the "
            f"oracle of the {kind.name!r} kind has no {name})"
        ) from None


def log_normalizer(problem) -> float:
    """Exact ``ln Z``, ``Z = sum over feasible gamma of w(gamma)`` (spec eqs. 1.6, 5.1).

    Parameters
    ----------
    problem : AssignmentProblem, MultiSensorProblem or AdaptiveBirthProblem
        The ``P x (M + 2P)`` problem. Every connected component of its row–measurement graph
        must fit one of the two DPs (see Notes). A multi-sensor problem goes to
        :func:`oracle.multisensor.dp.log_normalizer`, an adaptive-birth problem to
        :func:`oracle.adaptive_birth.exact.log_normalizer`.

    Returns
    -------
    float
        ``ln Z = ln sum_Gamma exp(-cost(gamma))``; ``0.0`` for ``P = 0``.

    Raises
    ------
    TypeError
        If ``problem`` is of no known kind (:func:`rankedassign.kinds.kind_of`).
    ValueError
        If a connected component has both ``min(P_c, M_c) > 20`` and a frontier width
        ``> 20`` (the message names both and the limits).

    Notes
    -----
    *Decomposition.* Rows and measurements joined by a finite cost form a bipartite graph;
    its connected components share nothing, so ``Z = prod_c Z_c * prod_i a_i`` over the
    components and the rows without any finite measurement (``a_i = eta_i(0) + eta_i(-1)``).

    *Subset DP* (spec eq. 5.1), over subsets ``S`` of the component's rows matched so far,
    one measurement per step::

        f_j(S) = f_{j-1}(S) + sum_{i in S} eta_i(j) f_{j-1}(S \\ {i})
        Z_c    = sum_S f_M(S) prod_{i not in S} a_i

    or the transposed DP over subsets of measurements, row by row, when ``M_c < P_c``.
    Time ``O(max(P_c, M_c) min(P_c, M_c) 2^min(P_c, M_c))``, memory ``O(2^min(P_c, M_c))``.

    *Frontier DP*, for sparse (gated) components. The measurements are put in an order with a
    narrow *frontier* (the cheapest of reverse Cuthill–McKee and a few greedy orders). A row is
    *active* from its first to its last finite measurement in that order, and the state is
    the subset of *active* rows already matched: a row enters unmatched at its first
    measurement, each measurement is left unused or taken by one active unmatched row with a
    finite entry, and a row retires after its last measurement, times ``a_i`` if still
    unmatched. Time ``O(M_c F 2^F)`` with ``F`` the largest number of rows active at once
    (the frontier width), memory ``O(2^F)``.

    Each component uses whichever DP is cheaper by operation count among those within their
    limits (``min(P_c, M_c) <= 20``, ``F <= 20``, i.e. at most ``2^20`` states); the problem
    is refused only when neither fits. On the paper's gated tracking problems
    (``P ~ 22``, ``M ~ 60``) ``F`` is about 10 and a call takes milliseconds.

    Weights are rescaled by the optimal duals of an LSAP on ``[C_meas | diag(-ln a)]`` so that
    every factor is at most one and the best assignment has weight exactly one: nothing
    under- or overflows, whatever the range of the costs, and ``ln Z_c = ln Z_c,scaled - c*_c``
    with ``c*_c`` the component's minimum cost.

    References
    ----------
    .. [1] B.-N. Vo, B.-T. Vo, H. G. Hoang, "An Efficient Implementation of the Generalized
       Labeled Multi-Bernoulli Filter", IEEE Trans. Signal Process. 65(8), 2017.
    .. [2] A. Trezza, D. J. Bucci Jr., P. K. Varshney, "On Gibbs Sampling Architecture for
       Labeled Random Finite Sets Multi-Object Tracking", arXiv:2306.15135, 2023.
    .. [3] K. G. Murty, "An Algorithm for Ranking all the Assignments in Order of Increasing
       Cost", Operations Research 16(3), 1968 (the LSAP dual view used for the scaling).
    .. [4] M. L. Miller, H. S. Stone, I. J. Cox, "Optimizing Murty's Ranked Assignment
       Method", IEEE Trans. Aerosp. Electron. Syst. 33(3), 1997.
    .. [5] E. Cuthill, J. McKee, "Reducing the Bandwidth of Sparse Symmetric Matrices",
       Proc. 24th ACM National Conference, 1969 (the measurement order).

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign import AssignmentProblem, synthetic
    >>> from oracle import log_normalizer
    >>> p = AssignmentProblem.from_eta([[2.0]], [0.5], [0.25])   # Z = 2 + 0.5 + 0.25
    >>> round(float(np.exp(log_normalizer(p))), 12)
    2.75
    >>> u = synthetic.uniform()          # 76 848 assignments, each of cost 4 * 0.5
    >>> round(float(np.exp(log_normalizer(u) + 4 * 0.5)), 6)
    76848.0

    A banded problem with 30 rows (beyond the subset DP; at most 2 rows active at once):

    >>> eta = np.zeros((30, 80))
    >>> for i in range(30):
    ...     eta[i, 2 * i: 2 * i + 4] = 1.0
    >>> band = AssignmentProblem.from_eta(eta, np.ones(30), np.zeros(30))
    >>> round(log_normalizer(band), 6)
    45.630949
    """
    return _solver(problem, "log_normalizer")(problem)


def marginals(problem):
    """Exact association probabilities of every row (spec eq. 5.2).

    Parameters
    ----------
    problem : AssignmentProblem, MultiSensorProblem or AdaptiveBirthProblem
        The ``P x (M + 2P)`` problem; same size limit as :func:`log_normalizer`. A
        multi-sensor problem goes to :func:`oracle.multisensor.dp.marginals` (which returns a
        :class:`~oracle.multisensor.dp.MultiSensorMarginals`), an adaptive-birth problem to
        :func:`oracle.adaptive_birth.exact.marginals` (per-sensor marginals).

    Returns
    -------
    ndarray, float64, shape (P, M + 2)
        ``[:, j]`` for ``j < M``: ``P(gamma_i = j + 1)``, row ``i`` takes measurement ``j``;
        ``[:, M]``: ``P(gamma_i = 0)`` (missed); ``[:, M + 1]``: ``P(gamma_i = -1)`` (dead).
        Each row sums to one; each measurement column sums to at most one.

    Raises
    ------
    TypeError
        If ``problem`` is of no known kind (:func:`rankedassign.kinds.kind_of`).
    ValueError
        If a connected component fits neither DP (see :func:`log_normalizer`).

    Notes
    -----
    ``P(gamma_i = j) = eta_i(j) Z_{-i,-j} / Z`` and
    ``P(gamma_i in {0, -1}) = (eta_i(0) + eta_i(-1)) Z_{-i} / Z``. Components are independent,
    so each is solved on its own (a row without finite measurements is unmatched with
    probability one). Rather than one DP per pair, one forward and one backward pass of the
    component's DP (subset or frontier, chosen as in :func:`log_normalizer`) give every
    transition's weight at once: the weight through "row ``i`` takes measurement ``j``" is
    ``sum_{S not containing i} F(S) eta_i(j) B(S | {i})`` at that measurement's step, and the
    weight through "row ``i`` unmatched" is read off where it leaves the state (the terminal
    weights of the subset DP, the retirement of the frontier DP). Forward or backward vectors
    are checkpointed every ``sqrt(K)`` steps, so memory stays ``O(sqrt(K) 2^k)``
    (``k = min(P_c, M_c)`` or ``F``). The unmatched weight of a row is split between missed
    and dead in proportion ``eta_i(0) : eta_i(-1)``. Rows are normalised by their own total,
    which equals ``Z_c`` in exact arithmetic. Unreachable measurements (all ``+inf``) get
    probability 0. Time about four times that of :func:`log_normalizer`.

    References
    ----------
    .. [1] B.-N. Vo, B.-T. Vo, H. G. Hoang, "An Efficient Implementation of the Generalized
       Labeled Multi-Bernoulli Filter", IEEE Trans. Signal Process. 65(8), 2017.
    .. [2] S. Reuter, B.-T. Vo, B.-N. Vo, K. Dietmayer, "The Labeled Multi-Bernoulli Filter",
       IEEE Trans. Signal Process. 62(12), 2014.
    .. [3] A. Trezza, D. J. Bucci Jr., P. K. Varshney, "On Gibbs Sampling Architecture for
       Labeled Random Finite Sets Multi-Object Tracking", arXiv:2306.15135, 2023.

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign import AssignmentProblem
    >>> from oracle import marginals
    >>> p = AssignmentProblem.from_eta([[2.0]], [0.5], [0.25])
    >>> marginals(p).round(6).tolist()       # [z1, missed, dead] = [2, 0.5, 0.25] / 2.75
    [[0.727273, 0.181818, 0.090909]]

    Two rows competing for one measurement, and a third row gating nothing:

    >>> q = AssignmentProblem.from_eta([[3.0], [1.0], [0.0]], [1.0, 1.0, 1.0], [0.0, 0.0, 3.0])
    >>> marginals(q).round(4).tolist()       # Z_c = 3 + 1 + 1 = 5 for rows 0 and 1
    [[0.6, 0.4, 0.0], [0.2, 0.8, 0.0], [0.0, 0.25, 0.75]]
    """
    return _solver(problem, "marginals")(problem)


def enumerate_assignments(problem, *, limit: int = 2_000_000) -> Ranked:
    """Every feasible assignment with its cost, best first.

    Parameters
    ----------
    problem : AssignmentProblem, MultiSensorProblem or AdaptiveBirthProblem
        The ``P x (M + 2P)`` problem; a multi-sensor problem goes to
        :func:`oracle.multisensor.enumerate.enumerate_assignments` (assignments of shape
        ``(|Gamma|, P, V)``), an adaptive-birth problem to
        :func:`oracle.adaptive_birth.exact.enumerate_assignments` (tuples ``(n, V)``).
    limit : int, optional
        Refuse (``ValueError``) when ``|Gamma|`` exceeds this many assignments. The output
        takes ``8 P |Gamma|`` bytes, the enumeration ``(8 P + 40) |Gamma|`` with its sort: a
        ``|Gamma|`` within ``limit`` that needs more than
        :data:`~rankedassign.validation.MAX_WORK_BYTES` (4 GiB) is refused as well.

    Returns
    -------
    Ranked
        ``assignments`` (``|Gamma|``, P) int64 column indices and ``costs``
        (``problem.cost_of``, bit for bit), sorted by cost; equal costs are ordered
        lexicographically by their column indices, so the order is fully deterministic.

    Raises
    ------
    TypeError
        If ``problem`` is of no known kind or ``limit`` is not
        an int.
    ValueError
        If ``limit < 1``, ``|Gamma| > limit`` (the message states both numbers and the
        bytes), or the enumeration would take more than
        :data:`~rankedassign.validation.MAX_WORK_BYTES` (the message gives the count and the
        bytes).

    Notes
    -----
    A compiled depth-first search over rows; row ``i`` takes a measurement not used by the
    rows before it, or its own missed or dead column, skipping ``+inf`` entries. The search
    scores each assignment as it goes (row by row from ``0.0``, as ``cost_of``) and the result
    is sorted once by a stable radix sort. The count is
    checked first with :meth:`~rankedassign.AssignmentProblem.n_feasible` (spec eq. 1.3, or
    its exact subset DP when pairs are forbidden). The number of feasible assignments is
    ``sum_k C(P,k) C(M,k) k! 2^(P-k)`` without forbidden pairs: 76 848 for the paper's
    ``4 x 24`` matrices. The empty problem (``P = 0``) has exactly one, empty, assignment.

    References
    ----------
    .. [1] B.-N. Vo, B.-T. Vo, H. G. Hoang, "An Efficient Implementation of the Generalized
       Labeled Multi-Bernoulli Filter", IEEE Trans. Signal Process. 65(8), 2017.
    .. [2] A. Trezza, D. J. Bucci Jr., P. K. Varshney, "On Gibbs Sampling Architecture for
       Labeled Random Finite Sets Multi-Object Tracking", arXiv:2306.15135, 2023.

    Examples
    --------
    >>> from rankedassign import AssignmentProblem, synthetic
    >>> from oracle import enumerate_assignments
    >>> p = AssignmentProblem.from_eta([[2.0, 0.5], [0.1, 3.0]], [0.2, 0.3], [0.1, 0.1])
    >>> r = enumerate_assignments(p)
    >>> len(r.costs), r.assignments[0].tolist()       # best: row 0 -> z1, row 1 -> z2
    (14, [0, 1])
    >>> len(enumerate_assignments(synthetic.uniform()).costs)
    76848
    """
    return _solver(problem, "enumerate_assignments")(problem, limit=limit)


def truncation_error(problem, assignments) -> float:
    """``1 - sum_{unique gamma} w(gamma) / Z``: the posterior mass the assignments miss.

    Parameters
    ----------
    problem : AssignmentProblem, MultiSensorProblem or AdaptiveBirthProblem
        The ``P x (M + 2P)`` problem; ``Z`` is computed by :func:`~oracle.log_normalizer`, so
        ``min(P, M) <= 20``. A multi-sensor problem goes to
        :func:`oracle.multisensor.truncation.truncation_error` (assignments ``(n, P, V)``),
        an adaptive-birth problem to :func:`oracle.adaptive_birth.exact.truncation_error`
        (tuples ``(n, V)``).
    assignments : array_like of int, shape (n, P) or (P,)
        Column indices (for instance a sampler's output). Duplicates count once; ``n = 0``
        gives an error of 1.

    Returns
    -------
    float
        In ``[0, 1]``. After the shift described in Notes, ``Z`` and the kept sum each
        carry a relative round-off of a few ulps of the (shifted) costs that matter: about
        ``1e-15`` absolute when those are of order 1, less accurate when an assignment mixes
        costs of very different magnitude (see Validation in the docs). Round-off can make
        ``1 - sum w / Z`` a few ulps negative when the assignments hold (nearly) all the
        mass; such values are clipped to ``0.0``.

    Raises
    ------
    TypeError
        If ``problem`` is of no known kind or the assignments
        are not integers.
    ValueError
        If an assignment is infeasible (the message names its row in the input), has the
        wrong shape, or the problem is too large for the DP.

    Notes
    -----
    Spec eq. (1.9), with the paper's "cost" read as the weight ``w = exp(-cost)`` (spec A6):
    ``eps = 1 - exp(logsumexp(-cost(unique)) - ln Z)``. Everything stays in log space, so
    problems whose weights overflow ``exp`` are fine, and each row is first shifted by its
    entry in the best assignment (which moves every assignment's cost by the same constant),
    so that large costs, up to :data:`~rankedassign.single.problem.COST_LIMIT`, keep their
    differences. ``ln Z`` comes from the subset DP
    (:func:`~oracle.log_normalizer`); when the DP refuses the size but the feasible set is
    small enough to enumerate (many forbidden pairs), from the enumeration.

    References
    ----------
    .. [1] A. Trezza, D. J. Bucci Jr., P. K. Varshney, "On Gibbs Sampling Architecture for
       Labeled Random Finite Sets Multi-Object Tracking", arXiv:2306.15135, 2023.
    .. [2] B.-N. Vo, B.-T. Vo, H. G. Hoang, "An Efficient Implementation of the Generalized
       Labeled Multi-Bernoulli Filter", IEEE Trans. Signal Process. 65(8), 2017.

    Examples
    --------
    >>> from rankedassign import AssignmentProblem, synthetic
    >>> from oracle import truncation_error
    >>> p = AssignmentProblem.from_eta([[2.0]], [0.5], [0.25])    # Z = 2.75
    >>> round(truncation_error(p, [[0], [0], [1]]), 12)        # 1 - (2 + 0.5) / 2.75
    0.090909090909
    >>> round(truncation_error(synthetic.diagonal(), [[0, 1, 2, 3]]), 5)
    0.00423
    """
    return _solver(problem, "truncation_error")(problem, assignments)


def best_mass(problem, k: int) -> float:
    """Fraction of ``Z`` held by the ``k`` best assignments.

    Equivalently ``1 -`` the smallest truncation error any ``k`` assignments can achieve.

    Parameters
    ----------
    problem : AssignmentProblem, MultiSensorProblem or AdaptiveBirthProblem
        A multi-sensor problem goes to :func:`oracle.multisensor.truncation.best_mass`; an
        adaptive-birth problem has none (``TypeError``).
    k : int
        Number of assignments, ``k >= 0`` (``0`` gives ``0.0``; ``k >= |Gamma|`` gives 1).

    Returns
    -------
    float
        In ``[0, 1]`` (clipped against round-off).

    Raises
    ------
    TypeError
        If ``problem`` is of no known kind or ``k`` is not an
        int.
    ValueError
        If ``k < 0`` or the problem is too large for the DP (and for enumeration).

    Notes
    -----
    The ``k`` best come from :func:`~oracle.enumerate_assignments` when
    ``|Gamma| <= 200 000`` (then ``Z`` is the enumeration's own sum) and from
    :func:`~oracle.murty` otherwise, with ``Z`` from :func:`~oracle.log_normalizer`.

    References
    ----------
    .. [1] K. G. Murty, "An Algorithm for Ranking all the Assignments in Order of Increasing
       Cost", Operations Research 16(3), 1968.
    .. [2] M. L. Miller, H. S. Stone, I. J. Cox, "Optimizing Murty's Ranked Assignment
       Method", IEEE Trans. Aerosp. Electron. Syst. 33(3), 1997.
    .. [3] A. Trezza, D. J. Bucci Jr., P. K. Varshney, "On Gibbs Sampling Architecture for
       Labeled Random Finite Sets Multi-Object Tracking", arXiv:2306.15135, 2023.

    Examples
    --------
    >>> from rankedassign import synthetic
    >>> from oracle import best_mass
    >>> round(best_mass(synthetic.diagonal(), 1), 5)       # spec §1.6: 99.577 %
    0.99577
    >>> round(best_mass(synthetic.uniform(), 76848 // 2), 12)
    0.5
    """
    return _solver(problem, "best_mass")(problem, k)

"""Exact multi-sensor normaliser and marginals (multi-sensor spec §6.2, §6.3).

* :func:`log_normalizer` and :func:`marginals` of ``pi``: a DP over rows whose state is the set
  ``S`` of used measurements of every sensor (one int64 bitset, one bit per reachable
  measurement)::

      f_0(S) = [S = {}]
      f_n(S) = eta_n(-1) f_{n-1}(S) + sum_{t : det(t) in S} eta_n(t) f_{n-1}(S \\ det(t))
      Z      = sum_S f_P(S)

  ``O(P 2^B T)`` time for ``B`` reachable measurements and ``T = prod_v (M_v + 1)`` tuples,
  ``O(2^B)`` memory; marginals from one backward and one forward pass, ``O(P 2^B)`` memory.
  When ``B`` is too large but ``|Gamma|`` is small (spec size B, ``P = 2, M = (16, 16)``),
  both fall back to enumeration.
* :func:`surrogate_log_normalizer` of the separable MM-Gibbs target ``pi~`` (spec eq. 3.2),
  exponential in ``P`` only: a single-sensor matched-subset DP per sensor and a sum over alive
  sets.

Each compiled kernel has a pure-numpy reference (``_*_reference``) that is its specification
in the tests; the marginal reference follows spec §6.2 literally (a DP over the other rows and
a zeta transform per row).
"""

from __future__ import annotations

from collections import namedtuple
from typing import NamedTuple

import numpy as np
from scipy.special import logsumexp

from rankedassign.multisensor import MultiSensorProblem
from rankedassign.numba_options import instantiate, interruptible, jit
from rankedassign.validation import check_choice

from .enumerate import check_ms_problem, count_assignments, enumerate_assignments

__all__ = [
    "MultiSensorMarginals",
    "log_normalizer",
    "marginals",
    "surrogate_log_normalizer",
    "MAX_MASK_BITS",
    "MAX_SURROGATE_ROWS",
]

#: Largest number of reachable measurements (all sensors) the row DP accepts: ``2^22`` states,
#: 32 MiB per state vector.
MAX_MASK_BITS = 22

#: Largest ``(P + 1) 2^B`` the marginal pass stores (512 MiB of backward vectors).
_MAX_MARGINAL_CELLS = 2**26

#: Largest ``|Gamma|`` the enumeration fallback accepts.
_ENUMERATE_LIMIT = 2_000_000

#: Largest ``P`` the surrogate normaliser accepts (``2^P`` alive sets).
MAX_SURROGATE_ROWS = 22

_METHODS = ("auto", "dp", "enumerate")


class MultiSensorMarginals(NamedTuple):
    """Exact association probabilities of a multi-sensor problem.

    Attributes
    ----------
    dead : ndarray, float64, shape (P,)
        ``P(gamma_n = -1)``.
    tuples : ndarray, float64, shape (P, M_1+1, ..., M_V+1)
        ``P(gamma_n = t)`` for every tuple (index 0 on axis ``v``: missed by sensor ``v``);
        ``dead[n] + tuples[n].sum() = 1``. This is what a multi-sensor LMB update needs
        (spec §7.4: ``beta_{n,t}``).
    sensors : tuple of V ndarrays, float64, shape (P, M_v + 2)
        Per sensor, in the single-sensor layout of :func:`oracle.marginals`: ``[:, j - 1]``
        ``P(gamma_n^(v) = j)``, ``[:, M_v]`` alive and missed by sensor ``v``, ``[:, M_v + 1]``
        dead. Each row sums to one, each measurement column to at most one.

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign.multisensor import MultiSensorProblem
    >>> from oracle import marginals
    >>> m = marginals(MultiSensorProblem.from_eta([1.0], [[[1.0, 2.0], [3.0, 0.0]]]))
    >>> (7 * m.dead).round(12).tolist(), (7 * m.tuples).round(12).tolist()   # Z = 7
    ([1.0], [[[1.0, 2.0], [3.0, 0.0]]])
    >>> m.sensors[0].round(4).tolist()          # [z1, missed, dead] for sensor 1
    [[0.4286, 0.4286, 0.1429]]
    """

    dead: np.ndarray
    tuples: np.ndarray
    sensors: tuple


# ----------------------------------------------------------------------------- preparation
def detection_masks(problem: MultiSensorProblem) -> tuple[np.ndarray, int]:
    """One bit per *reachable* measurement and the bitset ``det(t)`` of every tuple.

    A measurement is reachable when some row has a positive weight on some tuple using it;
    the others can never be used and get no bit.

    Returns
    -------
    masks : ndarray, int64, shape (T,)
        ``det(t)`` of the tuple at each flat index (``0`` for the all-missed tuple). A tuple
        using an unreachable measurement has weight zero in every row; its mask is ``-1``.
    n_bits : int
        ``B``, the number of reachable measurements.
    """
    P = problem.n_rows
    tuples = problem.tuples
    ok = np.isfinite(problem.log_eta_alive.reshape(P, problem.n_tuples)).any(axis=0)
    masks = np.zeros(tuples.shape[0], dtype=np.int64)
    bad = np.zeros(tuples.shape[0], dtype=bool)
    bit = 0
    for v, m in enumerate(problem.n_meas):
        reach = np.zeros(m + 1, dtype=bool)
        reach[tuples[ok, v]] = True
        reach[0] = False
        b = np.full(m + 1, -1, dtype=np.int64)
        b[np.flatnonzero(reach)] = bit + np.arange(int(reach.sum()))
        bit += int(reach.sum())
        col = tuples[:, v]
        bv = b[col]
        bad |= (col > 0) & (bv < 0)
        if bit <= 62:
            masks |= np.where((col > 0) & (bv >= 0), np.left_shift(1, np.maximum(bv, 0)), 0)
    masks[bad] = -1
    return masks, bit


#: Linear-domain kernels are used while the sum over rows of each row's log-weight range stays
#: below this many nats (every product of scaled factors then stays far above the smallest
#: double); beyond it the log-space kernels are used.
_LINEAR_RANGE = 600.0


def _use_log_space(problem: MultiSensorProblem) -> bool:
    """Whether some product of per-row scaled weights could underflow (see ``_LINEAR_RANGE``)."""
    P = problem.n_rows
    lw = np.concatenate([problem.log_eta_dead[:, None],
                         problem.log_eta_alive.reshape(P, problem.n_tuples)], axis=1)
    fin = np.isfinite(lw)
    hi = np.where(fin, lw, -np.inf).max(axis=1)
    lo = np.where(fin, lw, np.inf).min(axis=1)
    return bool((hi - lo).sum() > _LINEAR_RANGE)


def sensor_caps(problem: MultiSensorProblem, n_bits: int) -> np.ndarray:
    """``cap[S]``: the most measurements of one sensor in the bitset ``S`` (int8, ``2^B``)."""
    P = problem.n_rows
    tuples = problem.tuples
    ok = np.isfinite(problem.log_eta_alive.reshape(P, problem.n_tuples)).any(axis=0)
    S = np.arange(1 << n_bits, dtype=np.int64)
    cap = np.zeros(S.size, dtype=np.int8)
    lo = 0
    for v in range(problem.n_sensors):
        k = np.unique(tuples[ok, v])
        k = int((k > 0).sum())  # reachable measurements of sensor v hold bits lo..lo+k-1
        mask = ((1 << k) - 1) << lo
        cap = np.maximum(cap, np.bitwise_count(S & mask).astype(np.int8))
        lo += k
    return cap


def _scaled_weights(problem: MultiSensorProblem):
    """Per-row weights divided by the row's largest weight (every factor ``<= 1``).

    Returns ``(w_dead (P,), w_alive (P, T), log_shift (P,))`` with
    ``eta = w exp(log_shift)``.
    """
    P = problem.n_rows
    la = problem.log_eta_alive.reshape(P, problem.n_tuples)
    ld = problem.log_eta_dead
    shift = np.maximum(la.max(axis=1, initial=-np.inf), ld)
    w_alive = np.exp(la - shift[:, None])
    w_dead = np.exp(ld - shift)
    return np.ascontiguousarray(w_dead), np.ascontiguousarray(w_alive), shift


# ----------------------------------------------------------------------------- kernels
# The row DPs take ``O(P 2^B T)`` time, minutes at ``B = MAX_MASK_BITS``. Each is a compiled
# *slice* that does at most ``budget`` states ``S`` of its current pass and keeps its place
# in ``pos`` (pass, row, next state) and its vectors in arrays the caller keeps, and a Python
# loop that calls it until it is done (``_row_dp`` ...): between two slices the interpreter
# runs pending signal handlers (Ctrl-C). The slices perform the operations of one unbounded
# loop in the same order, so the results do not depend on the budget (tested).

#: States ``S`` times the tuples per state, per slice of a row DP (tens of milliseconds).
_SLICE_WORK = 1 << 24


def _slice_budget(T: int) -> int:
    """States per slice of a row DP over ``T`` tuples (:data:`_SLICE_WORK`)."""
    return max(1, _SLICE_WORK // (int(T) + 1))


@jit()
def _row_dp_slice(w_dead, w_alive, masks, f, g, acc, pos, budget):  # pragma: no cover
    """Up to ``budget`` states of the forward row DP (spec §6.2); True when it is done.

    Parameters
    ----------
    w_dead : (P,) float64
        Scaled weight of each row being dead (0 = forbidden).
    w_alive : (P, T) float64
        Scaled weight of each row taking each tuple (0 = forbidden).
    masks : (T,) int64
        ``det(t)`` bitsets (``-1``: the tuple is never allowed).
    f, g : (2^B,) float64
        ``f_{n-1}`` (starts as ``[1, 0, ...]``) and the row being pushed (starts at zero).
    acc : (2,) float64
        ``[ln Z, ln scale]``: ``acc[0]`` is the result once done; start at zero.
    pos : (2,) int64
        Row ``n`` and next state ``S``; start at zero.
    budget : int
        States to push in this call (``>= 1``).

    Returns
    -------
    bool
        True when done (also early, with ``acc[0] = -inf``, when a row leaves no weight).

    Notes
    -----
    Every step's vector is divided by its maximum and the logs of the divisors are added
    back: ``ln Z = ln sum_S f_P(S) + sum_n ln max g_n``.
    """
    P, T = w_alive.shape
    N = f.shape[0]
    n, S0 = pos[0], pos[1]
    left = budget
    while n < P:
        S1 = min(N, S0 + max(left, 0))
        for S in range(S0, S1):
            fs = f[S]
            if fs == 0.0:
                continue
            # f_n(S) = eta_n(-1) f(S) + sum_t eta_n(t) f(S \ det t)   (written as a push)
            g[S] += w_dead[n] * fs
            for k in range(T):
                m = masks[k]
                w = w_alive[n, k]
                if w != 0.0 and m >= 0 and (S & m) == 0:
                    g[S | m] += w * fs
        left -= S1 - S0
        if S1 < N:
            pos[0], pos[1] = n, S1
            return False
        mx = g.max()
        if mx == 0.0:
            acc[0] = -np.inf
            return True
        for S in range(N):
            f[S] = g[S] / mx
            g[S] = 0.0
        acc[1] += np.log(mx)
        n += 1
        S0 = 0
    acc[0] = np.log(f.sum()) + acc[1]
    return True


#: The data of the row DP's marginal pass: ``w_dead`` (P,) and ``w_alive`` (P, T) float64 the
#: scaled weights (0 = forbidden), ``masks`` (T,) int64 the ``det(t)`` bitsets (``-1``: the
#: tuple is never allowed) and ``cap`` (2^B,) int8 the most measurements of one sensor in each
#: set (:func:`sensor_caps`).
RowDP = namedtuple("RowDP", ["w_dead", "w_alive", "masks", "cap"])

#: The vectors of the row DP's marginal pass: ``beta`` (P + 1, 2^B) float64, zero with row ``P``
#: one; ``log_b`` (P + 1,) float64, zero (the logs of each row's divisors); ``alpha`` (2^B,)
#: ``[1, 0, ...]`` and ``nxt`` (2^B,) zero.
RowWork = namedtuple("RowWork", ["beta", "log_b", "alpha", "nxt"])

#: What the row DP's marginal pass adds up, zero at the start: ``dead`` (P,) and ``alive``
#: (P, T) row ``n``'s weights, each row on its own scale (normalise per row); ``acc`` (1,) the
#: ``ln`` of the scaled Z once done.
RowMarginals = namedtuple("RowMarginals", ["dead", "alive", "acc"])


@jit(inline="always")
def _row_backward(dp, work, pos, left):  # pragma: no cover - compiled
    """Pass 0: ``beta_n`` for ``n = pos[1]`` down to 0, from the state ``pos[2]`` on, only
    where ``cap[S] <= n``; each row divided by its maximum. Returns the budget left (the pass
    is complete when ``pos[1] < 0``).

    Parameters
    ----------
    dp : RowDP
        The DP's data.
    work : RowWork
        ``beta`` and ``log_b`` written.
    pos : ndarray of int64, shape (3,)
        As in :func:`_row_marginal_slice`.
    left : int
        States left in this call.

    Returns
    -------
    int
        States left.
    """
    w_dead, w_alive, masks, cap = dp
    beta, log_b = work.beta, work.log_b
    T = w_alive.shape[1]
    N = beta.shape[1]
    while pos[1] >= 0:
        n = pos[1]
        S0 = pos[2]
        S1 = min(N, S0 + max(left, 0))
        for S in range(S0, S1):
            if cap[S] > n:
                continue
            a = w_dead[n] * beta[n + 1, S]
            for k in range(T):
                m = masks[k]
                w = w_alive[n, k]
                if w != 0.0 and m >= 0 and (S & m) == 0:
                    a += w * beta[n + 1, S | m]
            beta[n, S] = a
        left -= S1 - S0
        pos[2] = S1
        if S1 < N:
            return left
        mx = beta[n].max()
        if mx > 0.0:
            for S in range(N):
                beta[n, S] = beta[n, S] / mx
            log_b[n] = log_b[n + 1] + np.log(mx)
        else:
            log_b[n] = log_b[n + 1]
        pos[1] = n - 1
        pos[2] = 0
    return left


@jit(inline="always")
def _row_forward(dp, work, out, pos, left):  # pragma: no cover - compiled
    """Passes 1 and 2, row ``n = pos[1]`` on: row ``n``'s marginals, then the push to
    ``alpha_{n+1}`` (divided by its maximum), from the state ``pos[2]`` on. Returns the budget
    left (the passes are complete when ``pos[1] = P``).

    Parameters
    ----------
    dp, work, pos, left
        As in :func:`_row_backward` (``work.alpha`` and ``work.nxt`` updated).
    out : RowMarginals
        ``dead`` and ``alive`` added to.

    Returns
    -------
    int
        States left.
    """
    w_dead, w_alive, masks, _ = dp
    beta, alpha, nxt = work.beta, work.alpha, work.nxt
    dead, alive = out.dead, out.alive
    P, T = w_alive.shape
    N = alpha.shape[0]
    while pos[1] < P:
        n = pos[1]
        S0 = pos[2]
        S1 = min(N, S0 + max(left, 0))
        if pos[0] == 1:  # row n's marginals
            for S in range(S0, S1):
                a = alpha[S]
                if a == 0.0:
                    continue
                dead[n] += a * w_dead[n] * beta[n + 1, S]
                for k in range(T):
                    m = masks[k]
                    w = w_alive[n, k]
                    if w != 0.0 and m >= 0 and (S & m) == 0:
                        alive[n, k] += a * w * beta[n + 1, S | m]
        else:  # alpha_{n+1}
            for S in range(S0, S1):
                a = alpha[S]
                if a == 0.0:
                    continue
                nxt[S] += w_dead[n] * a
                for k in range(T):
                    m = masks[k]
                    w = w_alive[n, k]
                    if w != 0.0 and m >= 0 and (S & m) == 0:
                        nxt[S | m] += w * a
        left -= S1 - S0
        pos[2] = S1
        if S1 < N:
            return left
        pos[2] = 0
        if pos[0] == 1:
            pos[0] = 2
            continue
        mx = nxt.max()
        for S in range(N):
            alpha[S] = nxt[S] / mx if mx > 0.0 else nxt[S]
            nxt[S] = 0.0
        pos[0] = 1
        pos[1] = n + 1
    return left


@jit()
def _row_marginal_slice(dp, work, out, pos, budget):  # pragma: no cover - compiled
    """Up to ``budget`` states of the backward then forward row DP; True when it is done.

    ``beta_n(S)`` is the weight of completing rows ``n..P-1`` when the measurements in ``S``
    are taken; ``alpha_n(S)`` the weight of rows ``0..n-1`` using exactly ``S``. Then
    ``P(gamma_n = t) ~ eta_n(t) sum_{S : S & det t = 0} alpha_n(S) beta_{n+1}(S | det t)``.

    ``cap[S]`` is the largest number of measurements ``S`` holds of any one sensor: rows
    ``0..n-1`` use at most ``n`` of each sensor, so ``beta_n`` is only needed (and only
    computed) where ``cap[S] <= n``.

    Parameters
    ----------
    dp : RowDP
        ``w_dead`` (P,), ``w_alive`` (P, T), ``masks`` (T,), ``cap`` (2^B,).
    work : RowWork
        ``beta`` (P + 1, 2^B) zero with row ``P`` one, ``log_b`` (P + 1,) zero, ``alpha``
        ``[1, 0, ...]``, ``nxt`` zero.
    out : RowMarginals
        ``dead`` (P,), ``alive`` (P, T) zero; ``acc`` (1,).
    pos : ndarray, int64, shape (3,)
        Pass (0 backward, 1 and 2 the forward pass's marginals and push), row, next state;
        start at ``[0, P - 1, 0]``.
    budget : int
        States in this call (``>= 1``).

    Returns
    -------
    bool
        True when done: ``out.dead``, ``out.alive`` then hold row ``n``'s weights (each row on
        its own scale) and ``out.acc[0]`` the ``ln`` of the scaled Z.
    """
    left = budget
    if pos[0] == 0:
        left = _row_backward(dp, work, pos, left)
        if pos[1] >= 0:
            return False
        pos[0] = 1  # the backward pass is complete: the forward pass starts at row 0
        pos[1] = 0
    _row_forward(dp, work, out, pos, left)
    if pos[1] < dp.w_alive.shape[0]:
        return False
    beta, log_b = work.beta, work.log_b
    out.acc[0] = np.log(beta[0, 0]) + log_b[0] if beta[0, 0] > 0.0 else -np.inf
    return True


@jit()
def _lae(a, b):  # pragma: no cover - compiled
    """``ln(e^a + e^b)`` without overflow (either may be ``-inf``).

    Parameters
    ----------
    a, b : float

    Returns
    -------
    float
    """
    if a == -np.inf:
        return b
    if b == -np.inf:
        return a
    if a >= b:
        return a + np.log1p(np.exp(b - a))
    return b + np.log1p(np.exp(a - b))


@jit()
def _row_dp_log_slice(l_dead, l_alive, masks, f, g, acc, pos, budget):  # pragma: no cover
    """:func:`_row_dp_slice` in log space, for weights whose range could underflow.

    Same recursion on ``ln f``; ``l_dead``, ``l_alive`` are log-weights (``-inf`` forbidden);
    ``f`` starts as ``[0, -inf, ...]``, ``g`` at ``-inf``; ``acc[0]`` is ``ln Z`` once done.

    Parameters
    ----------
    l_dead : ndarray of float64, shape (P,)
        Log-weights of each row being dead.
    l_alive : ndarray of float64, shape (P, T)
        Log-weights of each row taking each tuple.
    masks : ndarray of int64, shape (T,)
        As in :func:`_row_dp_slice`.
    f, g : ndarray of float64, shape (2^B,)
        The log-space vectors.
    acc : ndarray of float64, shape (>= 1,)
        ``acc[0]`` receives ``ln Z``.
    pos : ndarray of int64, shape (2,)
        Row and next state; start at zero.
    budget : int
        States in this call (``>= 1``).

    Returns
    -------
    bool
        True when done.
    """
    P, T = l_alive.shape
    N = f.shape[0]
    n, S0 = pos[0], pos[1]
    left = budget
    while n < P:
        S1 = min(N, S0 + max(left, 0))
        for S in range(S0, S1):
            fs = f[S]
            if fs == -np.inf:
                continue
            g[S] = _lae(g[S], l_dead[n] + fs)
            for k in range(T):
                m = masks[k]
                w = l_alive[n, k]
                if w != -np.inf and m >= 0 and (S & m) == 0:
                    g[S | m] = _lae(g[S | m], w + fs)
        left -= S1 - S0
        if S1 < N:
            pos[0], pos[1] = n, S1
            return False
        for S in range(N):
            f[S] = g[S]
            g[S] = -np.inf
        n += 1
        S0 = 0
    out = -np.inf
    for S in range(N):
        out = _lae(out, f[S])
    acc[0] = out
    return True


@jit()
def _row_marginal_log_slice(l_dead, l_alive, masks, cap, beta, dead, alive, alpha, nxt, pos,
                            budget):  # pragma: no cover - compiled
    """:func:`_row_marginal_slice` in log space: ``ln dead``, ``ln alive`` (each row on its
    own scale) and ``ln Z = beta[0, 0]`` once done.

    ``beta`` starts at ``-inf`` with row ``P`` zero; ``dead``, ``alive``, ``nxt`` at ``-inf``;
    ``alpha`` as ``[0, -inf, ...]``; ``pos`` (pass 0 backward or 1 forward, row, next state)
    at ``[0, P - 1, 0]``.

    Parameters
    ----------
    l_dead, l_alive, masks
        As in :func:`_row_dp_log_slice`.
    cap : ndarray of int8, shape (2^B,)
        As in :data:`RowDP`.
    beta : ndarray of float64, shape (P + 1, 2^B)
        The log backward vectors.
    dead : ndarray of float64, shape (P,)
        Receives ``ln`` of each row's dead weight.
    alive : ndarray of float64, shape (P, T)
        Receives ``ln`` of each row's tuple weights.
    alpha, nxt : ndarray of float64, shape (2^B,)
        The log forward vector and the next one.
    pos : ndarray of int64, shape (3,)
        Pass, row, next state.
    budget : int
        States in this call (``>= 1``).

    Returns
    -------
    bool
        True when done.
    """
    P, T = l_alive.shape
    N = alpha.shape[0]
    left = budget
    while pos[0] == 0 and pos[1] >= 0:  # backward
        n = pos[1]
        S0 = pos[2]
        S1 = min(N, S0 + max(left, 0))
        for S in range(S0, S1):
            if cap[S] > n:
                continue
            a = l_dead[n] + beta[n + 1, S]
            for k in range(T):
                m = masks[k]
                w = l_alive[n, k]
                if w != -np.inf and m >= 0 and (S & m) == 0:
                    a = _lae(a, w + beta[n + 1, S | m])
            beta[n, S] = a
        left -= S1 - S0
        pos[2] = S1
        if S1 < N:
            return False
        pos[1] = n - 1
        pos[2] = 0
    if pos[0] == 0:  # the backward pass is complete: the forward pass starts at row 0
        pos[0] = 1
        pos[1] = 0
    while pos[1] < P:  # forward
        n = pos[1]
        S0 = pos[2]
        S1 = min(N, S0 + max(left, 0))
        for S in range(S0, S1):
            a = alpha[S]
            if a == -np.inf:
                continue
            dead[n] = _lae(dead[n], a + l_dead[n] + beta[n + 1, S])
            nxt[S] = _lae(nxt[S], l_dead[n] + a)
            for k in range(T):
                m = masks[k]
                w = l_alive[n, k]
                if w != -np.inf and m >= 0 and (S & m) == 0:
                    alive[n, k] = _lae(alive[n, k], a + w + beta[n + 1, S | m])
                    nxt[S | m] = _lae(nxt[S | m], w + a)
        left -= S1 - S0
        pos[2] = S1
        if S1 < N:
            return False
        for S in range(N):
            alpha[S] = nxt[S]
            nxt[S] = -np.inf
        pos[1] = n + 1
        pos[2] = 0
    return True


def _row_dp(w_dead, w_alive, masks, n_bits) -> float:
    """``ln`` of the scaled ``Z`` by the forward row DP (:func:`_row_dp_slice`, in slices)."""
    N = 1 << n_bits
    f = np.zeros(N)
    f[0] = 1.0
    g = np.zeros(N)
    acc = np.zeros(2)
    pos = np.zeros(2, dtype=np.int64)
    budget = _slice_budget(w_alive.shape[1])
    with interruptible:
        while not _row_dp_slice(w_dead, w_alive, masks, f, g, acc, pos, budget):
            pass
    return float(acc[0])


def _row_dp_log(l_dead, l_alive, masks, n_bits) -> float:
    """:func:`_row_dp` in log space (:func:`_row_dp_log_slice`): ``ln Z``."""
    N = 1 << n_bits
    f = np.full(N, -np.inf)
    f[0] = 0.0
    g = np.full(N, -np.inf)
    acc = np.zeros(1)
    pos = np.zeros(2, dtype=np.int64)
    budget = _slice_budget(l_alive.shape[1])
    with interruptible:
        while not _row_dp_log_slice(l_dead, l_alive, masks, f, g, acc, pos, budget):
            pass
    return float(acc[0])


def _row_marginal(w_dead, w_alive, masks, n_bits, cap):
    """Unnormalised row marginals ``(dead (P,), alive (P, T))`` and ``ln`` of the scaled Z
    (:func:`_row_marginal_slice`, in slices)."""
    P, T = w_alive.shape
    N = 1 << n_bits
    beta = np.zeros((P + 1, N))
    beta[P, :] = 1.0
    log_b = np.zeros(P + 1)
    dead = np.zeros(P)
    alive = np.zeros((P, T))
    alpha = np.zeros(N)
    alpha[0] = 1.0
    nxt = np.zeros(N)
    acc = np.zeros(1)
    dp = RowDP(w_dead, w_alive, masks, cap)
    work = RowWork(beta, log_b, alpha, nxt)
    out = RowMarginals(dead, alive, acc)
    pos = np.array([0, P - 1, 0], dtype=np.int64)
    budget = _slice_budget(T)
    with interruptible:
        while not _row_marginal_slice(dp, work, out, pos, budget):
            pass
    return dead, alive, float(acc[0])


def _row_marginal_log(l_dead, l_alive, masks, n_bits, cap):
    """:func:`_row_marginal` in log space: ``(ln dead (P,), ln alive (P, T), ln Z)`` with
    each row on its own scale (:func:`_row_marginal_log_slice`, in slices)."""
    P, T = l_alive.shape
    N = 1 << n_bits
    beta = np.full((P + 1, N), -np.inf)
    beta[P, :] = 0.0
    dead = np.full(P, -np.inf)
    alive = np.full((P, T), -np.inf)
    alpha = np.full(N, -np.inf)
    alpha[0] = 0.0
    nxt = np.full(N, -np.inf)
    pos = np.array([0, P - 1, 0], dtype=np.int64)
    budget = _slice_budget(T)
    with interruptible:
        while not _row_marginal_log_slice(l_dead, l_alive, masks, cap, beta, dead, alive,
                                          alpha, nxt, pos, budget):
            pass
    return dead, alive, float(beta[0, 0])


def _row_dp_reference(w_dead, w_alive, masks, n_bits):
    """Pure-numpy specification of :func:`_row_dp` (pull form, no rescaling)."""
    P, T = w_alive.shape
    S = np.arange(1 << n_bits, dtype=np.int64)
    f = (S == 0).astype(float)
    for n in range(P):
        g = w_dead[n] * f
        for k in range(T):
            m = masks[k]
            if w_alive[n, k] == 0.0 or m < 0:
                continue
            has = (S & m) == m
            g[has] += w_alive[n, k] * f[S[has] ^ m]
        f = g
    return float(np.log(f.sum()))


def _row_marginal_reference(w_dead, w_alive, masks, n_bits):
    """Spec §6.2 literally: per row, the DP over the other rows, a zeta transform (sum over
    subsets, bit by bit), then ``P(t) ~ eta_n(t) G_n(full \\ det t)``. Normalised rows
    ``(dead (P,), alive (P, T))``."""
    P, T = w_alive.shape
    N = 1 << n_bits
    S = np.arange(N, dtype=np.int64)
    full = N - 1
    dead = np.zeros(P)
    alive = np.zeros((P, T))
    for n in range(P):
        g = (S == 0).astype(float)
        for r in range(P):
            if r == n:
                continue
            h = w_dead[r] * g
            for k in range(T):
                m = masks[k]
                if w_alive[r, k] == 0.0 or m < 0:
                    continue
                has = (S & m) == m
                h[has] += w_alive[r, k] * g[S[has] ^ m]
            g = h
        G = g.copy()
        for b in range(n_bits):
            has = (S >> b) & 1 == 1
            G[has] += G[S[has] ^ (1 << b)]
        dead[n] = w_dead[n] * G[full]
        for k in range(T):
            m = masks[k]
            if w_alive[n, k] != 0.0 and m >= 0:
                alive[n, k] = w_alive[n, k] * G[full & ~m]
        tot = dead[n] + alive[n].sum()
        dead[n] /= tot
        alive[n] /= tot
    return dead, alive


@jit(inline="always")
def _mul_add(acc, w, x):  # pragma: no cover - compiled
    """``acc + w x``: one term of the matched-subset DP.

    Parameters
    ----------
    acc, w, x : float

    Returns
    -------
    float
    """
    return acc + w * x


@jit(inline="always")
def _log_mul_add(acc, w, x):  # pragma: no cover - compiled
    """:func:`_mul_add` in log space: ``ln(e^acc + e^(w + x))``.

    Parameters
    ----------
    acc, w, x : float
        Logs.

    Returns
    -------
    float
    """
    return _lae(acc, w + x)


def _add_term(acc, w, x):  # pragma: no cover - replaced in every instantiation
    """The term :func:`_permanent_steps` adds: bound by each instantiation."""
    raise NotImplementedError


def _permanent_steps(theta, f, pos, budget):  # pragma: no cover - compiled (instantiated)
    """Up to ``budget`` steps of the single-sensor matched-subset DP (spec §6.3); True when
    it is done. A template: ``_add_term`` is :func:`_mul_add` in :func:`_permanent_slice`,
    :func:`_log_mul_add` in :func:`_permanent_log_slice`.

    Parameters
    ----------
    theta : (P, M + 1) float64
        Scaled factors ``theta_n(0..M)`` (``<= 1``), or their logs in log space.
    f : (2^P,) float64
        Starts as ``[1, 0, ...]`` (``[0, -inf, ...]`` in log space); once done ``Perm(A) =
        sum_{S in A} f(S) prod_{n in A \\ S} theta_n(0)`` (or its log): every row of the alive
        set ``A`` takes a distinct measurement or is missed.
    pos : (1,) int64
        Steps done: measurements ``1..M``, then one missed step per row; start at zero.
    budget : int
        Steps in this call (``>= 1``; one step is ``O(P 2^P)``).

    Returns
    -------
    bool
        True when all steps are done.
    """
    P, M1 = theta.shape
    N = f.shape[0]
    s = pos[0]
    stop = min(M1 - 1 + P, s + budget)
    while s < stop:
        if s < M1 - 1:
            j = s + 1
            # f_j(S) = f_{j-1}(S) + sum_{i in S} theta_i(j) f_{j-1}(S \ {i}); descending S
            # keeps f_{j-1} on the right-hand side
            for S in range(N - 1, 0, -1):
                acc = f[S]
                for i in range(P):
                    if (S >> i) & 1:
                        acc = _add_term(acc, theta[i, j], f[S ^ (1 << i)])
                f[S] = acc
        else:
            i = s - (M1 - 1)  # row i missed: f(S) += theta_i(0) f(S \ {i})
            for S in range(N - 1, 0, -1):
                if (S >> i) & 1:
                    f[S] = _add_term(f[S], theta[i, 0], f[S ^ (1 << i)])
        s += 1
    pos[0] = s
    return s >= M1 - 1 + P


#: :func:`_permanent_steps` on the scaled factors, and in log space for huge weight ranges.
_permanent_slice = instantiate(_permanent_steps, "_permanent_slice", {"_add_term": _mul_add})
_permanent_log_slice = instantiate(_permanent_steps, "_permanent_log_slice",
                                   {"_add_term": _log_mul_add})


def _permanent(theta, log_space: bool = False) -> np.ndarray:
    """``Perm(A)`` (or ``ln Perm(A)``) for every alive set ``A`` (:func:`_permanent_slice`, in
    slices of :data:`_SLICE_WORK`)."""
    P = theta.shape[0]
    N = 1 << P
    f = np.full(N, -np.inf) if log_space else np.zeros(N)
    f[0] = 0.0 if log_space else 1.0
    pos = np.zeros(1, dtype=np.int64)
    budget = max(1, _SLICE_WORK // (max(P, 1) * N))
    step = _permanent_log_slice if log_space else _permanent_slice
    with interruptible:
        while not step(theta, f, pos, budget):
            pass
    return f


def _permanent_reference(theta):
    """Pure-numpy specification of :func:`_permanent` (pull form over subsets)."""
    P, M1 = theta.shape
    S = np.arange(1 << P, dtype=np.int64)
    f = (S == 0).astype(float)
    for j in range(1, M1):
        g = f.copy()
        for i in range(P):
            has = (S >> i) & 1 == 1
            g[has] += theta[i, j] * f[S[has] ^ (1 << i)]
        f = g
    for i in range(P):
        g = f.copy()
        has = (S >> i) & 1 == 1
        g[has] += theta[i, 0] * f[S[has] ^ (1 << i)]
        f = g
    return f


# ----------------------------------------------------------------------------- dispatch
def _plan(problem: MultiSensorProblem, method: str, *, marginal: bool):
    """``("dp", (masks, B))`` or ``("enumerate", None)``; raise when neither fits."""
    masks, B = detection_masks(problem)
    P = problem.n_rows
    dp_ok = B <= MAX_MASK_BITS and (not marginal or (P + 1) * 2**B <= _MAX_MARGINAL_CELLS)
    if method in ("auto", "dp") and dp_ok:
        return "dp", (masks, B)
    if method == "dp":
        raise ValueError(
            f"problem too large for the row DP: {B} reachable measurements > "
            f"{MAX_MASK_BITS} bits (or (P + 1) 2^B > 2^26 stored vectors for the marginals)"
        )
    n = count_assignments(problem, limit=_ENUMERATE_LIMIT)
    if n <= _ENUMERATE_LIMIT:
        return "enumerate", None
    raise ValueError(
        f"problem too large for the exact row DP: {B} reachable measurements > "
        f"{MAX_MASK_BITS} bits, and for enumeration: more than {_ENUMERATE_LIMIT} feasible "
        f"assignments (P = {P}, M = {problem.n_meas})"
    )


def _log_normalizer(problem: MultiSensorProblem, method: str = "auto") -> float:
    check_choice(method, "method", _METHODS)
    P = problem.n_rows
    if P == 0:
        return 0.0
    kind, arg = _plan(problem, method, marginal=False)
    if kind == "enumerate":
        return float(logsumexp(-enumerate_assignments(problem, limit=_ENUMERATE_LIMIT).costs))
    masks, B = arg
    if _use_log_space(problem):
        la = np.ascontiguousarray(problem.log_eta_alive.reshape(P, problem.n_tuples))
        return _row_dp_log(problem.log_eta_dead, la, masks, B)
    w_dead, w_alive, shift = _scaled_weights(problem)
    return float(_row_dp(w_dead, w_alive, masks, B) + shift.sum())


def _marginals(problem: MultiSensorProblem, method: str = "auto") -> MultiSensorMarginals:
    check_choice(method, "method", _METHODS)
    P = problem.n_rows
    dims = problem.log_eta_alive.shape
    if P == 0:
        return _package(problem, np.zeros(0), np.zeros(dims))
    kind, arg = _plan(problem, method, marginal=True)
    if kind == "enumerate":
        r = enumerate_assignments(problem, limit=_ENUMERATE_LIMIT)
        w = np.exp(-(r.costs - r.costs[0]))
        w /= w.sum()
        V = problem.n_sensors
        strides = np.array([int(np.prod(dims[v + 2:])) for v in range(V)])  # C-order strides
        g = r.assignments
        flat = (np.maximum(g, 0) * strides).sum(axis=2)
        is_dead = g[:, :, 0] == -1
        dead = np.zeros(P)
        alive = np.zeros((P, int(np.prod(dims[1:]))))
        for n in range(P):
            dead[n] = w[is_dead[:, n]].sum()
            alive[n] = np.bincount(flat[~is_dead[:, n], n], weights=w[~is_dead[:, n]],
                                   minlength=alive.shape[1])
    else:
        masks, B = arg
        if _use_log_space(problem):
            la = np.ascontiguousarray(problem.log_eta_alive.reshape(P, problem.n_tuples))
            ld, lal, _ = _row_marginal_log(problem.log_eta_dead, la, masks, B,
                                           sensor_caps(problem, B))
            tot = np.logaddexp(ld, logsumexp(lal, axis=1))
            dead = np.exp(ld - tot)
            alive = np.exp(lal - tot[:, None])
        else:
            w_dead, w_alive, _ = _scaled_weights(problem)
            dead, alive, _ = _row_marginal(w_dead, w_alive, masks, B, sensor_caps(problem, B))
            tot = dead + alive.sum(axis=1)
            dead = dead / tot
            alive = alive / tot[:, None]
    return _package(problem, dead, alive.reshape(dims))


def _package(problem: MultiSensorProblem, dead, tuples) -> MultiSensorMarginals:
    P, V = problem.n_rows, problem.n_sensors
    sensors = []
    for v, m in enumerate(problem.n_meas):
        other = tuple(a for a in range(1, V + 1) if a != v + 1)
        per = tuples.sum(axis=other) if other else tuples
        out = np.empty((P, m + 2))
        out[:, :m] = per[:, 1:]
        out[:, m] = per[:, 0]
        out[:, m + 1] = dead
        sensors.append(out)
    return MultiSensorMarginals(np.asarray(dead, dtype=float), tuples, tuple(sensors))


# ----------------------------------------------------------------------------- public
def log_normalizer(problem) -> float:
    """Exact ``ln Z`` of a multi-sensor problem (multi-sensor spec §6.2).

    Parameters
    ----------
    problem : MultiSensorProblem

    Returns
    -------
    float
        ``ln sum_{gamma in Gamma} prod_n eta_n(gamma_n)``; ``0.0`` when ``P = 0``.

    Raises
    ------
    TypeError
        If ``problem`` is not a :class:`~rankedassign.multisensor.MultiSensorProblem`.
    ValueError
        If the problem has more than :data:`MAX_MASK_BITS` reachable measurements and more
        than 2 000 000 feasible assignments.

    Notes
    -----
    The row DP over the set ``S`` of used measurements (all sensors, one bit each)::

        f_n(S) = eta_n(-1) f_{n-1}(S) + sum_{t : det(t) in S} eta_n(t) f_{n-1}(S \\ det t)

    with ``det(t)`` the measurements tuple ``t`` detects (empty for the all-missed tuple) and
    ``Z = sum_S f_P(S)``. Only *reachable* measurements (used by some allowed tuple of some
    row) get a bit, so gating shrinks the state. Time ``O(P 2^B prod_v (M_v+1))``, memory
    ``O(2^B)``. Each row's weights are divided by their largest value and every step's vector
    by its maximum; when the rows' log-weight ranges add up to more than 600 nats, so that a
    product of scaled weights could underflow, the same DP runs in log space instead (about
    ten times slower), so nothing under- or overflows. With more than ``MAX_MASK_BITS`` bits
    (``P = 2, M = (16, 16)`` has 32) the sum runs over the enumeration instead when
    ``|Gamma| <= 2 000 000``. With ``V = 1`` the result equals the single-sensor
    :func:`oracle.log_normalizer`.

    References
    ----------
    .. [1] B.-N. Vo, B.-T. Vo, M. Beard, "Multi-Sensor Multi-Object Tracking with the
       Generalized Labeled Multi-Bernoulli Filter", IEEE Trans. Signal Process. 67(23), 2019.
    .. [2] A. Trezza, D. J. Bucci Jr., P. K. Varshney, "On Gibbs Sampling Architecture for
       Labeled Random Finite Sets Multi-Object Tracking", arXiv:2306.15135, 2023.

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign.multisensor import MultiSensorProblem, synthetic
    >>> from oracle import log_normalizer
    >>> p = MultiSensorProblem.from_eta([0.5], [[[1.0, 2.0], [3.0, 0.0]]])
    >>> round(float(np.exp(log_normalizer(p))), 12)          # 0.5 + 1 + 2 + 3
    6.5
    >>> round(float(np.exp(log_normalizer(synthetic.uniform()) + 4 * 0.5)), 6)
    67744.0
    """
    return _log_normalizer(check_ms_problem(problem))


def marginals(problem) -> MultiSensorMarginals:
    """Exact association probabilities of every row (multi-sensor spec §6.2).

    Parameters
    ----------
    problem : MultiSensorProblem
        Same size limits as :func:`log_normalizer`, and ``(P + 1) 2^B <= 2^26``.

    Returns
    -------
    MultiSensorMarginals
        ``dead`` (P,), ``tuples`` (P, M_1+1, ..., M_V+1) and per sensor ``sensors[v]``
        (P, M_v + 2) in the single-sensor layout ``[z_1..z_M | missed | dead]``.

    Raises
    ------
    TypeError
        If ``problem`` is not a :class:`~rankedassign.multisensor.MultiSensorProblem`.
    ValueError
        If the problem is too large for the row DP and for enumeration.

    Notes
    -----
    One backward pass stores ``beta_n(S)``, the weight of completing rows ``n..P-1`` when the
    measurements ``S`` are taken; a forward pass carries ``alpha_n(S)``, the weight of rows
    ``0..n-1`` using exactly ``S``; then::

        P(gamma_n = -1) ~ eta_n(-1) sum_S alpha_n(S) beta_{n+1}(S)
        P(gamma_n = t)  ~ eta_n(t)  sum_{S & det t = 0} alpha_n(S) beta_{n+1}(S | det t)

    normalised per row (each row's total is ``Z`` in exact arithmetic). Rows ``0..n-1`` use at
    most ``n`` measurements of each sensor, so ``beta_n`` is computed only on such sets.
    Memory ``(P + 1) 2^B`` doubles. Tested against spec §6.2's
    per-row DP with a zeta transform and against enumeration. When the DP does not fit and
    ``|Gamma| <= 2 000 000`` the marginals are summed over the enumeration.

    References
    ----------
    .. [1] B.-N. Vo, B.-T. Vo, M. Beard, "Multi-Sensor Multi-Object Tracking with the
       Generalized Labeled Multi-Bernoulli Filter", IEEE Trans. Signal Process. 67(23), 2019.
    .. [2] S. Reuter, B.-T. Vo, B.-N. Vo, K. Dietmayer, "The Labeled Multi-Bernoulli Filter",
       IEEE Trans. Signal Process. 62(12), 2014.

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign.multisensor import synthetic
    >>> from oracle import marginals
    >>> m = marginals(synthetic.diagonal())
    >>> m.tuples.shape, round(float(m.tuples[0, 1, 1]), 4)       # row 0 takes (z1, z1)
    ((4, 5, 5), 0.9996)
    >>> bool(np.allclose(m.dead + m.tuples.sum(axis=(1, 2)), 1.0))
    True
    """
    return _marginals(check_ms_problem(problem))


def surrogate_log_normalizer(problem) -> float:
    """Exact ``ln Z~`` of the separable MM-Gibbs target ``pi~`` (multi-sensor spec §6.3).

    Parameters
    ----------
    problem : MultiSensorProblem
        Built by :meth:`~rankedassign.multisensor.MultiSensorProblem.from_factors` (it needs
        ``s`` and ``theta``), with ``P <= MAX_SURROGATE_ROWS``.

    Returns
    -------
    float
        ``ln Z~``, ``Z~ = sum_Gamma prod_n eta~_n(gamma_n)`` with ``eta~_n(-1) = eta_n(-1)``,
        ``eta~_n(t) = s_n prod_v theta_n^(v)(t[v])``.

    Raises
    ------
    TypeError
        If ``problem`` is not a :class:`~rankedassign.multisensor.MultiSensorProblem`.
    ValueError
        If it has no separable factors, or ``P > MAX_SURROGATE_ROWS``.

    Notes
    -----
    Given the alive set ``A`` the sensors are independent, so::

        Z~ = sum_{A in rows} prod_{n in A} s_n prod_{n not in A} eta_n(-1) prod_v Perm_v(A)
        Perm_v(A) = sum_{S in A} f_v(S) prod_{n in A \\ S} theta_n^(v)(0)

    with ``f_v(S)`` the single-sensor matched-subset DP (spec of record eq. 5.1) of sensor
    ``v``: every row of ``S`` takes a distinct measurement. The missed factors enter as one
    extra DP step per row. Time ``O(V (M + P) P 2^P + V 2^P)``: exponential in ``P`` only,
    so it reaches far more measurements than the row DP. Equals :func:`log_normalizer` of
    :meth:`~rankedassign.multisensor.MultiSensorProblem.surrogate` (tested).

    References
    ----------
    .. [1] B.-N. Vo, B.-T. Vo, M. Beard, "Multi-Sensor Multi-Object Tracking with the
       Generalized Labeled Multi-Bernoulli Filter", IEEE Trans. Signal Process. 67(23), 2019.

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign.multisensor import synthetic
    >>> from oracle import log_normalizer
    >>> from oracle.multisensor.dp import surrogate_log_normalizer
    >>> p = synthetic.random_coupled(rng=0)
    >>> a, b = surrogate_log_normalizer(p), log_normalizer(p.surrogate())
    >>> bool(np.isclose(a, b, rtol=1e-12))
    True

    Far beyond the row DP (120 measurements): the uniform family, ``Z = e^-4 |Gamma|``:

    >>> import math
    >>> from rankedassign.multisensor import count_feasible_all_positive
    >>> n = count_feasible_all_positive(8, (40, 40, 40))
    >>> z = surrogate_log_normalizer(synthetic.uniform(8, (40, 40, 40)))
    >>> bool(np.isclose(z, math.log(n) - 4, rtol=1e-13))
    True
    """
    problem = check_ms_problem(problem)
    if problem.log_s is None:
        raise ValueError(
            "surrogate_log_normalizer needs the separable factors s and theta (spec §3.1); "
            "build the problem with MultiSensorProblem.from_factors"
        )
    P = problem.n_rows
    if P > MAX_SURROGATE_ROWS:
        raise ValueError(
            f"problem too large for the surrogate normaliser: P = {P} rows > "
            f"{MAX_SURROGATE_ROWS} (2^P alive sets)"
        )
    if P == 0:
        return 0.0
    A = np.arange(1 << P, dtype=np.int64)
    member = ((A[:, None] >> np.arange(P)) & 1).astype(bool)          # (2^P, P)
    log_s = problem.log_s.copy()
    log_perm = np.zeros(1 << P)
    for lt in problem.log_theta:
        shift = lt.max(axis=1)
        shift = np.where(np.isfinite(shift), shift, 0.0)
        low = np.where(np.isfinite(lt), lt, np.inf).min(axis=1)
        if np.where(np.isfinite(low), shift - low, 0.0).sum() > _LINEAR_RANGE:
            # a product of scaled factors could underflow: the same DP in log space
            log_perm = log_perm + _permanent(np.ascontiguousarray(lt), log_space=True)
            continue
        theta = np.ascontiguousarray(np.exp(lt - shift[:, None]))
        log_s = log_s + shift  # Perm_v(A) = prod_{n in A} e^shift_n * Perm~_v(A)
        with np.errstate(divide="ignore"):
            log_perm = log_perm + np.log(_permanent(theta))
    # ln of prod_{n in A} s_n prod_{n not in A} eta_n(-1) prod_v Perm_v(A), per alive set A
    terms = np.where(member, log_s[None, :], problem.log_eta_dead[None, :]).sum(axis=1)
    terms = terms + log_perm
    return float(logsumexp(terms))

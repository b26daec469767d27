"""Multi-object performance metrics: OSPA and OSPA(2).

:func:`ospa` is the optimal sub-pattern assignment distance between two finite sets of points
(Schuhmacher, Vo & Vo 2008). :func:`ospa2` is OSPA(2), the OSPA distance between two sets of
*tracks* over a trailing time window (Beard, Vo & Vo 2018/2020), the metric of the paper's
tracking study (spec §7). :func:`tracks_to_array` turns a filter's labelled estimates into the
NaN-padded array :func:`ospa2` takes. :func:`track_coverage` tells, per true track, how much of
its life some estimate was near it: the diagnostic that shows a target lost for good, which a
mean OSPA(2) only averages in. :func:`gospa` is the generalised OSPA of Rahmathullah,
García-Fernández & Svensson (2017) with ``α = 2``, split into localisation, missed and false
parts; :func:`gospa_series` gives it at every scan of a run (the tracking studies' column).
:func:`ospa2`, :func:`gospa` and :func:`gospa_series` have a sparse route for large scenes
(``method="sparse"``, taken by ``"auto"`` above :data:`SPARSE_MIN_PAIRS` pairs): the same
values from the pairs closer than the cut-off only, one connected component at a time.

Track arrays have shape ``(n_scans, n_tracks, d)``: entry ``[k, f]`` is the state of track ``f``
at scan ``k``, all-NaN where the track does not exist.
"""

from __future__ import annotations

import math
from collections.abc import Hashable, Mapping, Sequence
from typing import NamedTuple

import numpy as np
from scipy.sparse import coo_matrix, csr_matrix
from scipy.sparse.csgraph import (
    connected_components,
    maximum_bipartite_matching,
    min_weight_full_bipartite_matching,
)
from scipy.spatial import cKDTree

from .validation import check_choice, check_int, check_real, float_array

__all__ = ["OSPAResult", "OSPA2Result", "ospa", "ospa2", "tracks_to_array", "track_coverage",
           "GOSPAResult", "gospa", "GOSPASeries", "gospa_series", "SPARSE_MIN_PAIRS"]


def _linear_sum_assignment(cost):
    """:func:`scipy.optimize.linear_sum_assignment`, imported when first called: importing
    ``scipy.optimize`` takes about 0.3 s, which every process would otherwise pay at import.
    The first call puts SciPy's function in this one's place, so later calls (one per
    component of a large scene's metric) go to it directly."""
    global _linear_sum_assignment
    from scipy.optimize import linear_sum_assignment

    _linear_sum_assignment = linear_sum_assignment
    return linear_sum_assignment(cost)


class OSPAResult(NamedTuple):
    """OSPA distance and its two components (all floats, in the units of the points).

    With ``m <= n`` points in the smaller and larger set, ``value**p == localisation**p +
    cardinality**p`` and every component lies in ``[0, c]``.

    Attributes
    ----------
    value : float
        The OSPA distance ``d_p^(c)(X, Y)``.
    localisation : float
        The part due to the assigned pairs, ``((1/n) min_pi sum_i d^(c)(x_i, y_pi(i))^p)^(1/p)``.
    cardinality : float
        The part due to the ``n - m`` unassigned points, ``c ((n - m) / n)^(1/p)``.
    """

    value: float
    localisation: float
    cardinality: float


class OSPA2Result(NamedTuple):
    """OSPA(2) per scan: arrays of shape ``(n_scans,)``.

    Entry ``k`` of each array is the OSPA of the window ending at scan ``k`` (spec §7.3) on the
    time-averaged track distances; as for :class:`OSPAResult`, ``value**p == localisation**p +
    cardinality**p`` scan by scan.

    Attributes
    ----------
    value : ndarray of float64, shape (n_scans,)
        OSPA(2) at each scan, in ``[0, c]``; 0 where no track exists in the window.
    localisation : ndarray of float64, shape (n_scans,)
        Its component due to the assigned pairs of tracks.
    cardinality : ndarray of float64, shape (n_scans,)
        Its component due to tracks left without a partner (more true tracks than estimates or
        the other way round).
    """

    value: np.ndarray
    localisation: np.ndarray
    cardinality: np.ndarray


# exp() of anything below this is subnormal or zero: a matrix of ln(d^p / c^p) whose finite
# entries all lie above it can be exponentiated as it is, without losing a digit.
_EXP_SAFE = -700.0


# ---------------------------------------------------------------------------------- validation
def _check_cp(c, p) -> tuple[float, float]:
    c = check_real(c, "c", minimum=0.0, strict_minimum=True)
    p = check_real(p, "p", minimum=1.0)
    return c, p


def _as_points(X, name: str) -> np.ndarray:
    """A ``(n, d)`` float array; an empty list (shape ``(0,)``) becomes ``(0, 0)``."""
    a = float_array(X, name)
    if a.ndim == 1 and a.size == 0:
        a = a.reshape(0, 0)
    if a.ndim != 2:
        raise ValueError(f"{name} must be 2-D with shape (n_points, d), got shape {a.shape}")
    if not np.isfinite(a).all():
        raise ValueError(f"{name} contains NaN or inf; every point must be finite")
    return a


def _as_point_pair(X, Y) -> tuple[np.ndarray, np.ndarray]:
    """Both point sets with one dimension ``d``; an empty set without one takes the other's.

    An empty set given as ``[]`` (or with shape ``(0,)`` or ``(0, 0)``, as :func:`tracks_to_array`
    makes for nothing) has no dimension of its own; ``(0, d)`` is an empty set of dimension
    ``d`` and must match the other set as a non-empty one must.
    """
    A = _as_points(X, "X")
    B = _as_points(Y, "Y")
    dims = [None if a.shape == (0, 0) else a.shape[1] for a in (A, B)]
    if dims[0] is not None and dims[1] is not None and dims[0] != dims[1]:
        empty = [name for name, a in (("X", A), ("Y", B)) if a.shape[0] == 0]
        note = (f" ({' and '.join(empty)} empty: an empty set without a dimension is [] or "
                "shape (0, 0))") if empty else ""
        raise ValueError(
            f"X and Y must have the same point dimension, got {dims[0]} and {dims[1]}{note}"
        )
    d = dims[0] if dims[0] is not None else dims[1]
    if d is not None:
        A, B = A.reshape(A.shape[0], d), B.reshape(B.shape[0], d)
    return A, B


def _norm(diff: np.ndarray) -> np.ndarray:
    """Euclidean norm over the last axis, without overflow or underflow; ``d = 0`` gives 0.

    An entry that is ``inf`` (a difference of two finite states that overflowed) gives ``inf``,
    which is right wherever the norm is only compared with, or cut off at, a finite ``c``.
    """
    a = np.abs(diff)
    s = a.max(axis=-1, initial=0.0)
    safe = np.where((s > 0) & np.isfinite(s), s, 1.0)
    with np.errstate(over="ignore", invalid="ignore"):
        r = s * np.sqrt(((a / safe[..., None]) ** 2).sum(axis=-1))
    return np.where(np.isinf(s), np.inf, r)


def _masked_logsumexp(x: np.ndarray, mask: np.ndarray) -> np.ndarray:
    """``ln sum_t exp(x_t)`` over axis 0 where ``mask`` holds (``-inf`` if it holds nowhere)."""
    x = np.where(mask, x, -np.inf)
    top = x.max(axis=0, initial=-np.inf)
    top = np.where(np.isfinite(top), top, 0.0)
    with np.errstate(divide="ignore"):
        return top + np.log(np.exp(x - top).sum(axis=0))


def _bottleneck(L: np.ndarray) -> float:
    """Smallest ``t`` such that every row of ``L`` (``m <= n``) gets its own column with
    ``L <= t``: the bottleneck assignment value, by bisection over the entries of ``L``."""
    m = L.shape[0]
    vals = np.unique(L)
    vals = vals[vals >= L.min(axis=1).max()]  # each row needs one of its entries
    lo, hi = 0, len(vals) - 1  # vals[-1] is the largest entry: every matching is allowed
    while lo < hi:
        mid = (lo + hi) // 2
        match = maximum_bipartite_matching(
            csr_matrix((L <= vals[mid]).astype(np.int8)), perm_type="column"
        )
        if int((match >= 0).sum()) == m:
            hi = mid
        else:
            lo = mid + 1
    return float(vals[lo])


def _ospa_from_log(L: np.ndarray, m: int, n: int, c: float, p: float,
                   U: np.ndarray | None = None) -> OSPAResult:
    """OSPA from ``L = ln(d^p / c^p)``, an ``(m, n)`` matrix (``m <= n``) of entries ``<= 0``.

    ``U``, if given, is the same matrix in linear form, ``(d / c)^p``; it is used (for its
    last-digit accuracy) when no entry of it is below ``exp(-700)``. Otherwise everything stays
    in log space, so every finite order ``p`` is exact: ``(d / c)^p`` is at most 1, so it
    cannot overflow, and after the rescaling below the optimum's entries cannot underflow.
    """
    if n == 0:
        return OSPAResult(0.0, 0.0, 0.0)
    finite = L[np.isfinite(L)]
    safe = finite.size == 0 or finite.min() > _EXP_SAFE
    if U is not None and safe:
        # d_p^(c) = c ((1/n) [min_pi sum (d/c)^p + (n - m)])^(1/p)   (spec 7.3, units of c)
        if m:
            rows, cols = _linear_sum_assignment(U)
            loc = float(U[rows, cols].sum())
        else:
            loc = 0.0
        return OSPAResult(
            min(c, c * ((loc + (n - m)) / n) ** (1.0 / p)),
            min(c, c * (loc / n) ** (1.0 / p)),
            c * ((n - m) / n) ** (1.0 / p),
        )
    log_loc = -math.inf
    if m:
        if safe:
            shift = 0.0  # exp(L) loses nothing
        else:
            # Rescale by the bottleneck value b^p (spec 7.3 minimises sum d^p; its optimum S*
            # satisfies b^p <= S* <= m b^p). After the shift the optimum's entries are at most
            # m; larger entries cannot be in it and are clipped to 2m + 2, and entries that
            # underflow are below 1e-300 of S*.
            shift = _bottleneck(L)
        if shift > -math.inf:  # else a zero-distance matching exists
            with np.errstate(over="ignore", under="ignore"):
                S = np.exp(np.minimum(L - shift, math.log(2 * m + 2)))
            rows, cols = _linear_sum_assignment(S)
            total = float(S[rows, cols].sum())
            log_loc = shift + math.log(total) if total > 0 else -math.inf
    log_card = math.log(n - m) if n > m else -math.inf
    log_all = float(np.logaddexp(log_loc, log_card))
    log_n = math.log(n)

    def scaled(log_sum):
        # c ((1/n) sum)^(1/p), with the sum in units of c^p   (spec 7.3)
        return min(c, c * math.exp((log_sum - log_n) / p)) if log_sum > -math.inf else 0.0

    return OSPAResult(scaled(log_all), scaled(log_loc), scaled(log_card))


# ---------------------------------------------------------------------------------- OSPA
def ospa(X, Y, c: float, p: float) -> OSPAResult:
    """OSPA distance between two finite sets of points.

    Parameters
    ----------
    X : array_like, shape (m, d)
        First set, one point per row. ``m`` may be 0: an empty list ``[]`` (shape ``(0,)``, or
        ``(0, 0)``) is the empty set of the other set's dimension; ``(0, d)`` is the empty set
        of dimension ``d``.
    Y : array_like, shape (n, d)
        Second set, the same conventions.
    c : float
        Cut-off, ``> 0``.
    p : float
        Order, ``>= 1``.

    Returns
    -------
    OSPAResult
        ``value``, ``localisation`` and ``cardinality`` components; ``value**p`` is the sum of
        the two components raised to ``p``.

    Raises
    ------
    ValueError
        On non-finite points, mismatched dimensions (an empty ``(0, d)`` included; the
        message gives both), ``c <= 0`` or ``p < 1``.

    Notes
    -----
    With ``m <= n`` (swap otherwise) and ``d^(c)(x, y) = min(c, ||x - y||_2)``,

    ``d_p^(c)(X, Y) = ( (1/n) [ min_pi sum_i d^(c)(x_i, y_pi(i))^p + c^p (n - m) ] )^(1/p)``,

    ``0`` when both sets are empty and ``c`` when exactly one is (for any ``p``). The
    assignment is solved with :func:`scipy.optimize.linear_sum_assignment`. OSPA is a metric
    on finite sets bounded by ``c``.

    References
    ----------
    .. [1] D. Schuhmacher, B.-T. Vo, B.-N. Vo, "A Consistent Metric for Performance Evaluation
       of Multi-Object Filters", IEEE Trans. Signal Process. 56(8), 2008.

    Examples
    --------
    >>> from rankedassign.metrics import ospa
    >>> r = ospa([[0.0, 0.0], [10.0, 0.0]], [[0.0, 3.0]], c=100.0, p=1)
    >>> round(r.value, 6), round(r.localisation, 6), round(r.cardinality, 6)
    (51.5, 1.5, 50.0)
    >>> ospa([[0.0, 0.0, 0.0]], [], c=100.0, p=2).value      # nothing against a point: c
    100.0
    """
    c, p = _check_cp(c, p)
    A, B = _as_point_pair(X, Y)
    if A.shape[0] > B.shape[0]:
        A, B = B, A
    m, n = A.shape[0], B.shape[0]
    with np.errstate(over="ignore"):  # a difference beyond the largest double is beyond c
        diff = A[:, None, :] - B[None, :, :]
    with np.errstate(over="ignore", under="ignore"):
        u = np.minimum(_norm(diff) / c, 1.0)  # min(c, ||x - y||) / c
        U = u**p
    with np.errstate(divide="ignore"):
        L = p * np.log(u)  # ln(min(c, ||x - y||)^p / c^p)
    return _ospa_from_log(L, m, n, c, p, U)


# ---------------------------------------------------------------------------------- OSPA(2)
def _as_tracks(a, name: str) -> tuple[np.ndarray, np.ndarray]:
    arr = float_array(a, name)
    if arr.ndim != 3:
        raise ValueError(
            f"{name} must be 3-D with shape (n_scans, n_tracks, d), got shape {arr.shape}"
        )
    nan = np.isnan(arr)
    exists = ~nan.any(axis=2)
    partial = nan.any(axis=2) & ~nan.all(axis=2)
    if partial.any():
        k, f = (int(v) for v in np.argwhere(partial)[0])
        raise ValueError(
            f"{name}[{k}, {f}] is partly NaN; a track state must be all-NaN (absent) or finite"
        )
    if np.isinf(arr).any():
        raise ValueError(f"{name} contains inf")
    return arr, exists


def _as_track_pair(truth, estimates):
    """Validate two track arrays against each other: ``X, x_exists, Y, y_exists``.

    A side without tracks takes the other's state dimension, so that the ``(n_scans, 0, 0)``
    array of :func:`tracks_to_array` for a filter that reported nothing is accepted.
    """
    X, ex = _as_tracks(truth, "truth")
    Y, ey = _as_tracks(estimates, "estimates")
    if X.shape[0] != Y.shape[0]:
        raise ValueError(
            f"truth and estimates must have the same number of scans, got {X.shape[0]} and "
            f"{Y.shape[0]}"
        )
    if X.shape[2] != Y.shape[2]:
        if Y.shape[1] == 0:
            Y = Y.reshape(Y.shape[0], 0, X.shape[2])
        elif X.shape[1] == 0:
            X = X.reshape(X.shape[0], 0, Y.shape[2])
        else:
            raise ValueError(
                f"truth and estimates must have the same state dimension, got {X.shape[2]} "
                f"and {Y.shape[2]}"
            )
    return X, ex, Y, ey


def ospa2(
    truth,
    estimates,
    c: float,
    p: float,
    window: int,
    weight_power: float = 0,
    base: str = "euclidean",
    method: str = "auto",
) -> OSPA2Result:
    """OSPA(2) between a set of true tracks and a set of estimated tracks, at every scan.

    Parameters
    ----------
    truth : array_like, shape (n_scans, n_true, d)
        True track states, all-NaN where a track does not exist.
    estimates : array_like, shape (n_scans, n_est, d)
        Estimated track states, same convention and the same ``n_scans`` and ``d`` (a side
        without tracks may have any ``d``, e.g. :func:`tracks_to_array` of nothing).
    c : float
        Cut-off, ``> 0`` (paper: 200 m).
    p : float
        Order, ``>= 1`` (paper: 1).
    window : int
        Window length ``N >= 1`` (paper: 5). At scan ``k`` the window is the ``N`` scans ending
        at ``k``, truncated at the first scan.
    weight_power : float, optional
        Power ``r`` of the window weights ``w_t = (t - k + N)^r`` (0 = uniform, the paper).
    base : {"euclidean", "lp"}, optional
        ``"euclidean"`` (default, spec §7): per-scan distance ``min(c, ||x - y||_2)`` averaged
        (weighted) over the union of the two tracks' domains in the window, then OSPA of
        order ``p`` on those track distances. ``"lp"``: the convention of Beard's public
        ``compute_ospa2.m`` (spec A18): per-scan ``min(c^p, sum_dims |x - y|^p)`` (``c^p`` where
        exactly one track exists), averaged over the union of domains, used directly as the
        ``p``-th power of the track distance.
    method : {"auto", "dense", "sparse"}, optional
        How the assignments are solved; both routes give the same values (to rounding, about
        1e-15 relative). ``"dense"``: every pair of tracks, arrays of shape
        ``(n_scans, n_true, n_est, d)``, for small inputs. ``"sparse"``: only the pairs that
        some scan of the window has closer than ``c`` (a k-d tree per scan), the assignment
        split into the connected components of those pairs; memory and time grow with the
        number of tracks, not their product, so it reaches 100 000 tracks. ``"auto"``
        (default): sparse when ``n_true * n_est`` exceeds :data:`SPARSE_MIN_PAIRS` and the
        states have at least one component, else dense. Points of dimension 0 always take the
        dense route.

    Returns
    -------
    OSPA2Result
        ``value``, ``localisation``, ``cardinality``, each of shape ``(n_scans,)``.

    Raises
    ------
    ValueError
        On mismatched scan counts or dimensions, a partly-NaN state, ``c <= 0``, ``p < 1``,
        ``window < 1``, an unknown ``base`` or an unknown ``method``.

    Notes
    -----
    Spec §7. With ``W_k = {max(1, k-N+1), ..., k}``, only tracks that exist somewhere in
    ``W_k`` take part. Per-scan base distance (7.1): ``d_t(f, g) = min(c, ||f(t) - g(t)||)`` if
    both exist, ``c`` if exactly one does; the time average (7.2) runs over the union of the two
    domains within the window with weights ``w_t``; the OSPA (7.3) over the two sets of tracks
    uses these averages as base distances (they are already ``<= c``). With ``window = 1`` this
    is OSPA at every scan. OSPA(2) is a metric on sets of tracks bounded by ``c``.

    The sparse route rests on the cut-off: a pair of tracks whose distance is ``c`` costs
    what leaving both without a partner costs, so only the pairs closer than ``c`` can lower
    the assignment's cost, and the optimal assignment is the union of the optimal assignments
    of the connected components of the bipartite graph of those pairs (each solved by
    :func:`scipy.optimize.linear_sum_assignment` on its own small matrix, a component of one
    pair directly). A track distance is below ``c`` only if the two tracks both exist and are
    closer than ``c`` at some scan of the window (at every other scan of their union its
    per-scan distance is ``c``), for both bases; the exact windowed distance is computed for
    those candidate pairs only. For ``base="lp"`` the candidates come from max-norm balls of
    radius ``c`` (a p-norm below ``c`` implies a max-norm below ``c``).

    References
    ----------
    .. [1] M. Beard, B.-T. Vo, B.-N. Vo, "A Solution for Large-Scale Multi-Object Tracking",
       IEEE Trans. Signal Process. 68, 2020 (arXiv:1804.06622).
    .. [2] M. Beard, B.-T. Vo, B.-N. Vo, "Performance Evaluation for Large-Scale Multi-Target
       Tracking Algorithms", FUSION 2018.

    Examples
    --------
    One true track, one estimate 3 m off that starts a scan late:

    >>> import numpy as np
    >>> from rankedassign.metrics import ospa2
    >>> truth = np.array([[[0.0, 0.0]], [[1.0, 0.0]], [[2.0, 0.0]]])
    >>> est = np.array([[[np.nan, np.nan]], [[1.0, 3.0]], [[2.0, 3.0]]])
    >>> ospa2(truth, est, c=10.0, p=1, window=2).value.round(6).tolist()
    [10.0, 6.5, 3.0]
    >>> ospa2(truth, est, c=10.0, p=1, window=2, method="sparse").value.round(6).tolist()
    [10.0, 6.5, 3.0]

    Ten thousand tracks (the dense route would need arrays of 10⁸ pairs per scan):

    >>> rng = np.random.default_rng(0)
    >>> truth = rng.uniform(0.0, 20_000.0, (3, 10_000, 2))
    >>> est = truth + rng.normal(0.0, 5.0, truth.shape)
    >>> r = ospa2(truth, est, c=100.0, p=1, window=3)        # "auto": the sparse route
    >>> bool(abs(r.value[-1] - 5.0 * np.sqrt(np.pi / 2)) < 0.1)   # mean of a Rayleigh(5)
    True
    """
    c, p = _check_cp(c, p)
    N = check_int(window, "window", minimum=1)
    r = check_real(weight_power, "weight_power", minimum=0.0)
    check_choice(base, "base", ("euclidean", "lp"))
    _check_method(method)
    X, ex, Y, ey = _as_track_pair(truth, estimates)
    K = X.shape[0]
    if X.shape[2] and (method == "sparse" or (
            method == "auto" and X.shape[1] * Y.shape[1] > SPARSE_MIN_PAIRS)):
        return _ospa2_sparse(X, ex, Y, ey, c, p, N, r, base)
    # Per-scan base distances between every truth and every estimate, shape (K, m, n), in
    # units of c ("euclidean", d_t / c) or of c^p ("lp", d_t / c^p), kept both as they are (s,
    # for the last digit) and as logarithms (g, which no order p or cut-off c can overflow or
    # underflow). Missing states are NaN: set the difference to 0 there and mask with existence.
    with np.errstate(over="ignore", invalid="ignore"):
        diff = X[:, :, None, :] - Y[:, None, :, :]
    diff = np.where(np.isnan(diff), 0.0, diff)
    s, g = _base_distance(diff, c, p, base)
    both = ex[:, :, None] & ey[:, None, :]
    one = ex[:, :, None] ^ ey[:, None, :]
    # where exactly one track exists d_t = c: 1 in units of c (or c^p), 0 as a logarithm
    s = np.where(both, s, 1.0)
    g = np.where(both, g, 0.0)
    union = both | one

    value = np.empty(K)
    loc = np.empty(K)
    card = np.empty(K)
    for k, lo, lw in _windows(K, N, r):
        fx = ex[lo : k + 1].any(axis=0)
        fy = ey[lo : k + 1].any(axis=0)
        m, n = int(fx.sum()), int(fy.sum())
        if m and n:
            uw = union[lo : k + 1][:, fx][:, :, fy]  # each pair's union is non-empty (7.2)
            lwb = np.where(uw, lw[:, None, None], -np.inf)
            lwb = lwb - lwb.max(axis=0)  # per pair, the largest weight in the union is 1
            # weighted time average over the union of the two domains (7.2), as it is and as
            # a logarithm
            with np.errstate(under="ignore"):
                w = np.exp(lwb)
                avg = (w * s[lo : k + 1][:, fx][:, :, fy]).sum(axis=0) / w.sum(axis=0)
            A = _masked_logsumexp(lwb + g[lo : k + 1][:, fx][:, :, fy], uw) - _masked_logsumexp(
                lwb, uw
            )
            if base == "euclidean":
                with np.errstate(under="ignore"):
                    U = avg**p
                L = p * A  # ln(d~^p / c^p)
            else:
                U, L = avg, A
        else:
            U = L = np.zeros((m, n))
        if m > n:
            L, U = L.T, U.T
            m, n = n, m
        value[k], loc[k], card[k] = _ospa_from_log(L, m, n, c, p, U)
    return OSPA2Result(value, loc, card)


# ---------------------------------------------------------------------------------- helpers
def tracks_to_array(
    labelled_estimates: Sequence[Mapping[Hashable, object]],
    *,
    dims=None,
    return_labels: bool = False,
):
    """Build a NaN-padded track array from per-scan labelled estimates.

    Parameters
    ----------
    labelled_estimates : sequence of mappings
        One mapping per scan from a track label (any hashable, e.g. the filter's
        ``(birth scan, birth index)``) to that track's state vector at that scan.
    dims : sequence of int, optional
        State components to keep (e.g. ``(0, 2)`` for the positions of a ``[p_x, v_x, p_y,
        v_y]`` state). Default: all.
    return_labels : bool, optional
        Also return the list of labels in track order.

    Returns
    -------
    ndarray, shape (n_scans, n_tracks, d)
        Tracks ordered by first appearance (ties in the order the mapping lists them); NaN
        where a track is not reported. With ``return_labels=True``, a tuple
        ``(array, labels)``.

    Raises
    ------
    ValueError
        If state vectors differ in length, or ``dims`` is out of range.

    Examples
    --------
    >>> from rankedassign.metrics import tracks_to_array
    >>> est = [{(1, 1): [0.0, 1.0, 5.0, 0.0]},
    ...        {(1, 1): [1.0, 1.0, 5.0, 0.0], (2, 3): [9.0, 0.0, 9.0, 0.0]}]
    >>> arr, labels = tracks_to_array(est, dims=(0, 2), return_labels=True)
    >>> labels
    [(1, 1), (2, 3)]
    >>> arr.tolist()
    [[[0.0, 5.0], [nan, nan]], [[1.0, 5.0], [9.0, 9.0]]]
    """
    if isinstance(labelled_estimates, (str, bytes, Mapping)) or not isinstance(
        labelled_estimates, (Sequence, np.ndarray)
    ):
        raise TypeError(
            "labelled_estimates must be a sequence (one mapping per scan), got "
            f"{type(labelled_estimates).__name__}"
        )
    if not isinstance(return_labels, (bool, np.bool_)):
        raise TypeError(
            f"return_labels must be a bool, got {type(return_labels).__name__} {return_labels!r}"
        )
    scans = []
    order: dict[Hashable, int] = {}
    dim = None
    for k, scan in enumerate(labelled_estimates):
        if not isinstance(scan, Mapping):
            raise TypeError(
                f"labelled_estimates[{k}] must be a mapping from track label to state, got "
                f"{type(scan).__name__}"
            )
        states = {}
        for lab, x in scan.items():
            v = float_array(x, f"state of track {lab!r} at scan {k}").reshape(-1)
            if dim is None:
                dim = v.size
            elif v.size != dim:
                raise ValueError(
                    f"state of track {lab!r} has {v.size} components, expected {dim}"
                )
            states[lab] = v
            order.setdefault(lab, len(order))
        scans.append(states)
    dim = 0 if dim is None else dim
    if dims is None:
        idx = np.arange(dim)
    else:
        if isinstance(dims, (str, bytes)) or not isinstance(dims, (Sequence, np.ndarray)):
            raise TypeError(f"dims must be a sequence of ints, got {type(dims).__name__}")
        idx = np.array([check_int(j, f"dims[{i}]") for i, j in enumerate(dims)], dtype=np.int64)
        if dim and idx.size and idx.max() >= dim:
            raise ValueError(f"dims {idx.tolist()} out of range for states of length {dim}")
    out = np.full((len(scans), len(order), idx.size), np.nan)
    for k, states in enumerate(scans):
        for lab, v in states.items():
            out[k, order[lab]] = v[idx]
    if return_labels:
        return out, list(order)
    return out


def track_coverage(truth, estimates, radius: float, *, settle: int = 0) -> np.ndarray:
    """Per true track, the fraction of its scans with an estimate within ``radius``.

    A target that a filter loses for good shows up here as a coverage near 0, however small
    its share of a mean OSPA(2) over many targets and scans.

    Parameters
    ----------
    truth, estimates : array_like, shape (n_scans, n_tracks, d)
        Track arrays as for :func:`ospa2` (NaN where a track does not exist); ``d`` must agree
        unless one side has no tracks.
        The estimates' labels play no part: any estimate may cover any target.
    radius : float
        Euclidean distance (in the units of the states) within which an estimate covers a
        target. Positive and finite.
    settle : int, optional
        Scans of each true track's life, counted from its first, left out (e.g. the time a
        filter needs to confirm a newborn). Default 0.

    Returns
    -------
    ndarray, shape (n_tracks,)
        For each true track, covered scans / scans counted; NaN for a track that exists for no
        more than ``settle`` scans.

    Raises
    ------
    ValueError
        On malformed track arrays (as :func:`ospa2`), mismatched scan counts or state
        dimensions, a radius that is not positive and finite, or a negative ``settle``.

    References
    ----------
    The paper's tracking study (Trezza, Bucci & Varshney 2023) reports OSPA(2) only; this
    coverage is the diagnostic this project adds beside it (see the Tracking page).

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign.metrics import track_coverage
    >>> nan = np.nan
    >>> truth = np.array([[[0.0, 0.0], [nan, nan]],
    ...                   [[1.0, 0.0], [50.0, 50.0]],
    ...                   [[2.0, 0.0], [51.0, 50.0]]])
    >>> est = np.array([[[nan, nan]], [[1.5, 0.0]], [[2.5, 0.0]]])   # one track, on target 0
    >>> track_coverage(truth, est, radius=5.0).tolist()
    [0.6666666666666666, 0.0]
    >>> track_coverage(truth, est, radius=5.0, settle=1).tolist()
    [1.0, 0.0]
    """
    X, x_exists, Y, y_exists = _as_track_pair(truth, estimates)
    radius = check_real(radius, "radius", minimum=0.0, strict_minimum=True)
    settle = check_int(settle, "settle", minimum=0)
    # distance of every truth to every estimate per scan, (K, m, n); NaN where either is absent,
    # and NaN <= radius is False
    with np.errstate(over="ignore", invalid="ignore"):
        dist = _norm(X[:, :, None, :] - Y[:, None, :, :])
    covered = (dist <= radius).any(axis=2)
    counted = x_exists & (np.cumsum(x_exists, axis=0) > settle)  # past each life's first scans
    n = counted.sum(axis=0)
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(n > 0, (covered & counted).sum(axis=0) / n, np.nan)


# ---------------------------------------------------------------------------------- GOSPA
class GOSPAResult(NamedTuple):
    """GOSPA distance (``α = 2``) and its three parts.

    In the units of the points, with ``value**p == localisation**p + missed**p + false**p``.

    Attributes
    ----------
    value : float
        The GOSPA distance ``d_p^(c,2)(X, Y)``.
    localisation : float
        ``(Σ d(x, y)^p)^(1/p)`` over the assigned pairs (those closer than ``c``).
    missed : float
        ``(c^p / 2 · n_missed)^(1/p)``: the points of ``X`` (the truth) left unassigned.
    false : float
        ``(c^p / 2 · n_false)^(1/p)``: the points of ``Y`` (the estimates) left unassigned.
    n_missed : int
        Number of unassigned points of ``X``.
    n_false : int
        Number of unassigned points of ``Y``.
    """

    value: float
    localisation: float
    missed: float
    false: float
    n_missed: int
    n_false: int


def gospa(X, Y, c: float, p: float, *, method: str = "auto") -> GOSPAResult:
    """Generalised OSPA (GOSPA, ``α = 2``) between the truth ``X`` and the estimates ``Y``.

    Parameters
    ----------
    X : array_like, shape (m, d)
        True points, one per row (empty: ``[]`` or ``(0, d)``, as for :func:`ospa`).
    Y : array_like, shape (n, d)
        Estimated points.
    c : float
        Cut-off, ``> 0``: a pair at least ``c`` apart counts as one missed and one false point.
    p : float
        Order, ``>= 1``.
    method : {"auto", "dense", "sparse"}, optional
        ``"dense"``: the ``(m, n)`` matrix of every pair. ``"sparse"``: only the pairs closer
        than ``c`` (a k-d tree), the assignment solved per connected component of those pairs
        (see :func:`ospa2`); the same value, in memory and time that grow with ``m + n``.
        ``"auto"`` (default): sparse when ``m * n`` exceeds :data:`SPARSE_MIN_PAIRS` and the
        points have at least one coordinate.

    Returns
    -------
    GOSPAResult
        The distance, its localisation, missed and false parts and the two counts. Where
        several optimal assignments exist the two routes may split the same value differently
        between localisation and missed and false points.

    Raises
    ------
    ValueError
        On non-finite points, mismatched dimensions, ``c <= 0``, ``p < 1`` or an unknown
        ``method``.

    Notes
    -----
    With ``α = 2`` and ``d^(c) = min(c, ||x − y||_2)``, unlike OSPA not normalised by
    ``max(m, n)``::

        d_p^(c,2)(X, Y) = ( min_γ Σ_(i,j)∈γ d(x_i, y_j)^p + c^p/2 (m + n − 2|γ|) )^(1/p)

    over partial assignments ``γ`` of pairs closer than ``c``; equivalently, the optimal
    assignment of ``min(m, n)`` pairs on the costs ``d^(c)^p``, with the pairs at ``c`` or
    beyond (tied at ``c``: unassigned) counted as one missed and one false point. Solved with
    :func:`scipy.optimize.linear_sum_assignment` on ``(d^(c) / c)^p``; a term below ~1e-308
    of ``c^p`` underflows to 0.

    References
    ----------
    .. [1] A. S. Rahmathullah, Á. F. García-Fernández, L. Svensson, "Generalized optimal
       sub-pattern assignment metric", 20th Int. Conf. on Information Fusion, 2017.

    Examples
    --------
    >>> from rankedassign.metrics import gospa
    >>> r = gospa([[0.0, 0.0], [10.0, 0.0]], [[0.0, 3.0], [500.0, 0.0]], c=100.0, p=1)
    >>> r.value, r.localisation, r.missed, r.false, r.n_missed, r.n_false
    (103.0, 3.0, 50.0, 50.0, 1, 1)
    >>> gospa([], [], c=10.0, p=2).value
    0.0
    >>> gospa([[0.0, 0.0], [10.0, 0.0]], [[0.0, 3.0], [500.0, 0.0]], c=100.0, p=1,
    ...       method="sparse").value
    103.0
    """
    c, p = _check_cp(c, p)
    _check_method(method)
    A, B = _as_point_pair(X, Y)
    m, n = A.shape[0], B.shape[0]

    def root(units_of_cp):
        # c (sum / c^p)^(1/p)
        return c * units_of_cp ** (1.0 / p) if units_of_cp > 0 else 0.0

    if A.shape[1] and (method == "sparse" or (method == "auto" and m * n > SPARSE_MIN_PAIRS)):
        loc, n_pairs = _gospa_sparse(A, B, c, p)
        n_missed, n_false = m - n_pairs, n - n_pairs
        return GOSPAResult(root(loc + 0.5 * (n_missed + n_false)), root(loc),
                           root(0.5 * n_missed), root(0.5 * n_false), n_missed, n_false)
    with np.errstate(over="ignore"):
        diff = A[:, None, :] - B[None, :, :]
    with np.errstate(over="ignore", under="ignore"):
        u = np.minimum(_norm(diff) / c, 1.0)  # d^(c) / c
        U = u**p
    loc, n_pairs = 0.0, 0
    if m and n:
        rows, cols = _linear_sum_assignment(U)
        kept = u[rows, cols] < 1.0  # a pair at c or beyond: one missed and one false point
        loc = float(U[rows, cols][kept].sum())
        n_pairs = int(kept.sum())
    n_missed, n_false = m - n_pairs, n - n_pairs
    return GOSPAResult(root(loc + 0.5 * (n_missed + n_false)), root(loc), root(0.5 * n_missed),
                       root(0.5 * n_false), n_missed, n_false)


class GOSPASeries(NamedTuple):
    """GOSPA (``α = 2``) at every scan of a run: :func:`gospa` per scan, as arrays.

    Attributes
    ----------
    value, localisation, missed, false : ndarray of float64, shape (n_scans,)
        The distance and its parts at each scan (:class:`GOSPAResult`).
    n_missed, n_false : ndarray of int64, shape (n_scans,)
        The unassigned true and estimated points at each scan.
    """

    value: np.ndarray
    localisation: np.ndarray
    missed: np.ndarray
    false: np.ndarray
    n_missed: np.ndarray
    n_false: np.ndarray


def gospa_series(truth, estimates, c: float, p: float, *, method: str = "auto") -> GOSPASeries:
    """GOSPA (``α = 2``) between the truth and the estimates at every scan of a run.

    Parameters
    ----------
    truth : array_like, shape (n_scans, n_true, d)
        True states per scan, all-NaN where a target does not exist (the layout of
        :func:`ospa2` and ``ScenarioRun.truth``).
    estimates : array_like, shape (n_scans, n_est, d)
        Estimated states, all-NaN where a track is not reported.
    c : float
        Cut-off, ``> 0``.
    p : float
        Order, ``>= 1``.
    method : {"auto", "dense", "sparse"}, optional
        Passed to :func:`gospa` at every scan.

    Returns
    -------
    GOSPASeries
        :func:`gospa` of each scan's existing points.

    Raises
    ------
    ValueError
        On arrays that are not 3-D with the same number of scans and dimension, on a point
        that is partly NaN or infinite, or on an invalid ``c``, ``p`` or ``method``.

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign.metrics import gospa_series
    >>> X = np.array([[[0.0, 0.0]], [[1.0, 0.0]]])
    >>> Y = np.array([[[np.nan, np.nan]], [[1.0, 4.0]]])
    >>> gospa_series(X, Y, c=10.0, p=1).value.tolist()
    [5.0, 4.0]
    """
    c, p = _check_cp(c, p)
    _check_method(method)
    A = float_array(truth, "truth", allow_nan=True)
    B = float_array(estimates, "estimates", allow_nan=True)
    if A.ndim != 3 or B.ndim != 3 or A.shape[0] != B.shape[0] or (
            A.shape[2] != B.shape[2] and A.shape[1] and B.shape[1]):
        raise ValueError(f"truth and estimates must be (n_scans, n, d) arrays with the same "
                         f"n_scans and d, got shapes {A.shape} and {B.shape}")
    out = []
    for k in range(A.shape[0]):
        x = A[k][~np.isnan(A[k]).all(axis=1)] if A.shape[1] else A[k]
        y = B[k][~np.isnan(B[k]).all(axis=1)] if B.shape[1] else B[k]
        out.append(gospa(x if x.size else [], y if y.size else [], c, p, method=method))
    cols = list(zip(*out, strict=True)) if out else [()] * 6
    return GOSPASeries(*(np.asarray(col, dtype=np.float64) for col in cols[:4]),
                       *(np.asarray(col, dtype=np.int64) for col in cols[4:]))


# ---------------------------------------------------------------------------------- sparse route
#: ``method="auto"`` takes the sparse route when ``n_true * n_est`` (for :func:`gospa`,
#: ``m * n``) exceeds this. The sparse route is already the faster from about 50 × 50 tracks
#: (scenes of one target per 200 m × 200 m, c = 100 m, 5 scans, window 5: 0.3 ms against 8 ms
#: at 50, 0.2 s against 7 s at 1 000); the threshold is set where the dense route's arrays
#: reach hundreds of MB instead, so that the inputs of the tracking studies (tens of targets,
#: hundreds of tracks) keep the dense route and their results bit for bit.
SPARSE_MIN_PAIRS = 250_000

# The k-d tree is asked for a slightly larger radius than c, and its pairs are then kept by the
# dense route's own formula: a pair at c, or one a rounding away from it, is kept or left exactly
# as the dense route keeps or leaves it.
_RADIUS_SLACK = 1e-9


#: The sparse route solves each connected component of the pairs closer than the cut-off on
#: its own dense matrix (as the dense route solves the whole); a component with more (row,
#: column) entries than this goes to SciPy's LAPJVsp on its pairs instead, or, where the costs
#: underflow a double, is refused. On the ``"large"`` scenario's scenes (one target per
#: 200 m × 200 m, c = 100 m) the largest component has 32 tracks at N = 10 000 and 44 at
#: N = 100 000; a graph that percolates (a much denser scene, or a larger c) has one
#: component of most of the tracks.
DENSE_COMPONENT_MAX = 250_000


def _sparse_lsap(I: np.ndarray, J: np.ndarray, U: np.ndarray, r: int, s: int) -> np.ndarray:
    """Which pairs an optimal assignment of the ``r × s`` cost (``U`` at ``(I, J)``, 1
    elsewhere) uses, as a boolean mask over the pairs, by LAPJVsp on ``O(len(I) + r + s)``
    edges.

    The dense problem, ``min(r, s)`` pairs at cost ``U`` or 1, has its optimum at the partial
    matching of ``k`` of the given pairs that minimises ``sum U - k``. That is a full matching
    of rows (``r`` real, then ``s`` slots for unmatched columns) against columns (``s`` real,
    then ``r`` slots for unmatched rows): row ``i`` to its slot and column ``j`` to its slot at
    1, slot of ``j`` to slot of ``i`` at 1 for every given pair ``(i, j)`` (the textbook
    padding, only where a pair may need it), so that a full matching with ``k`` given pairs
    costs ``sum U + (r - k) + (s - k) + k``. LAPJVsp takes only non-zero weights: a cost of
    exactly 0 (two identical points) enters as the smallest subnormal, which only orders it
    below every positive cost. Its optimum is exact to the solver's absolute precision (about
    1e-16 of the cut-off's cost), less than the dense LSAP's on costs far below that (orders
    ``p`` in the hundreds, whose root ``1/p`` magnifies them), hence only for components
    above :data:`DENSE_COMPONENT_MAX`.
    """

    e = I.size
    rows = np.concatenate([I, np.arange(r), r + np.arange(s), r + J])
    cols = np.concatenate([J, s + np.arange(r), np.arange(s), s + I])
    w = np.concatenate([np.maximum(U, np.nextafter(0.0, 1.0)), np.ones(r + s + e)])
    graph = coo_matrix((w, (rows, cols)), shape=(r + s, r + s)).tocsr()
    rr, cc = min_weight_full_bipartite_matching(graph)
    real = (rr < r) & (cc < s)
    hit = np.zeros(e, dtype=bool)
    if real.any():
        key = I * s + J
        order = np.argsort(key)
        hit[order[np.searchsorted(key[order], rr[real] * s + cc[real])]] = True
    return hit


def _check_method(method: str) -> str:
    return check_choice(method, "method", ("auto", "dense", "sparse"))


def _base_distance(diff: np.ndarray, c: float, p: float, base: str):
    """Per-scan base distance ``s`` (units of ``c``, or of ``c^p`` for ``"lp"``) and its log
    ``g``, for differences ``(..., d)`` (the dense route's and the sparse route's: 7.1, A18)."""
    with np.errstate(over="ignore", under="ignore", divide="ignore"):
        if base == "euclidean":
            s = np.minimum(_norm(diff) / c, 1.0)  # min(c, ||x - y||) / c       (7.1)
            g = np.log(s)
        else:
            # min(c^p, sum_dims |x - y|^p) / c^p                                   (A18)
            q = np.abs(diff) / c
            s = np.minimum((q**p).sum(axis=-1), 1.0)
            g = np.minimum(0.0, _masked_logsumexp(np.moveaxis(p * np.log(q), -1, 0), True))
    return s, g


def _close_pairs(A: np.ndarray, B: np.ndarray, c: float, p: float, base: str):
    """The pairs ``(i, j)`` of rows of ``A`` and ``B`` whose base distance is below the
    cut-off (``s < 1``), found with a k-d tree, with ``s`` and ``g`` of each (int64, int64,
    float64, float64 arrays, sorted by ``(i, j)``)."""

    empty = (np.empty(0, np.int64), np.empty(0, np.int64), np.empty(0), np.empty(0))
    if A.shape[0] == 0 or B.shape[0] == 0:
        return empty
    # Both per-scan distances are below the cut-off only where the largest coordinate
    # difference is (a p-norm is at least the max-norm): the tree searches max-norm balls,
    # whose distance has no rounding of its own and no overflow for any order p.
    with np.errstate(over="ignore", invalid="ignore"):
        M = cKDTree(A).sparse_distance_matrix(cKDTree(B), c * (1.0 + _RADIUS_SLACK), p=np.inf,
                                              output_type="ndarray")
    i, j = M["i"].astype(np.int64), M["j"].astype(np.int64)
    with np.errstate(over="ignore"):
        s, g = _base_distance(A[i] - B[j], c, p, base)
    keep = s < 1.0
    i, j, s, g = i[keep], j[keep], s[keep], g[keep]
    order = np.lexsort((j, i))
    return i[order], j[order], s[order], g[order]


def _log_assignment_sum(L: np.ndarray) -> float:
    """``ln min_pi sum_i exp(L[i, pi(i)])`` for an ``(r, s)`` matrix of entries ``<= 0`` with
    ``r <= s``, exact for any entries (the dense route's rescaling by the bottleneck value)."""
    m = L.shape[0]
    shift = _bottleneck(L)
    if shift == -math.inf:  # a zero-cost matching exists
        return -math.inf
    with np.errstate(over="ignore", under="ignore"):
        S = np.exp(np.minimum(L - shift, math.log(2 * m + 2)))
    rows, cols = _linear_sum_assignment(S)
    total = float(S[rows, cols].sum())
    return shift + math.log(total) if total > 0 else -math.inf


def _component_assignment(I, J, U, L, log_mode: bool):
    """Optimal assignment of a sparse bipartite cost, one connected component at a time.

    ``(I, J)`` are the pairs below the cut-off, ``U`` their costs in units of the cut-off's
    cost (``< 1``) and ``L`` their logarithms; every other pair costs 1. A pair at the cut-off
    costs what leaving both sides unassigned costs, so the assignment decomposes over the
    connected components of the graph of the pairs below it. A component of one pair is one
    row and one column, matched at its cost; one of two pairs shares a row or a column, and
    the cheaper pair is matched (both done for all such components at once: at 10 000 targets
    they are most of them). Each larger component is solved on its own dense matrix (other
    entries 1) as the dense route solves the whole: by :func:`scipy.optimize.linear_sum_assignment`,
    or where the costs underflow (``log_mode``) in log space with the dense route's
    bottleneck rescaling; above :data:`DENSE_COMPONENT_MAX` entries by LAPJVsp
    (:func:`_sparse_lsap`), or refused in ``log_mode``.

    Returns ``(total, log_total, n_matched, kept)``: ``n_matched`` matched pairs of cost
    ``total`` in all, so that the optimum of the whole problem with ``small`` rows on its
    smaller side is ``total + (small - n_matched)`` (the other rows of the smaller side are
    matched at cost 1); ``log_total`` the logarithm of ``total`` (``log_mode`` only, else
    NaN); and a boolean mask of the pairs matched with cost below 1.
    """

    kept = np.zeros(I.size, dtype=bool)
    if I.size == 0:
        return 0.0, -math.inf, 0, kept
    # nodes: the rows that take part, then the columns
    ri, I_loc = np.unique(I, return_inverse=True)
    ci, J_loc = np.unique(J, return_inverse=True)
    nr = ri.size
    graph = coo_matrix((np.ones(I.size, np.int8), (I_loc, nr + J_loc)),
                       shape=(nr + ci.size, nr + ci.size))
    _, comp = connected_components(graph, directed=False)
    lab = comp[I_loc]

    def local(idx):
        # each pair's node index within its component: the rank of its node there
        o = np.lexsort((idx, lab))
        new_node = np.r_[True, (lab[o][1:] != lab[o][:-1]) | (idx[o][1:] != idx[o][:-1])]
        new_comp = np.r_[True, lab[o][1:] != lab[o][:-1]]
        rank = np.cumsum(new_node)
        rank -= np.maximum.accumulate(np.where(new_comp, rank, 0))
        out = np.empty_like(rank)
        out[o] = rank
        return out

    r_loc, c_loc = local(I_loc), local(J_loc)
    order = np.argsort(lab, kind="stable")
    lab_sorted = lab[order]
    starts = np.flatnonzero(np.r_[True, lab_sorted[1:] != lab_sorted[:-1]])
    sizes = np.diff(np.r_[starts, lab_sorted.size])
    single = order[starts[sizes == 1]]
    kept[single] = True
    first, second = order[starts[sizes == 2]], order[starts[sizes == 2] + 1]
    # compared as logarithms where the costs underflow (both may be 0 as they are)
    cheaper = L[second] < L[first] if log_mode else U[second] < U[first]
    take = np.where(cheaper, second, first)
    kept[take] = True
    n_matched = single.size + take.size
    parts_lin = [U[single], U[take]]
    parts_log = [L[single], L[take]]
    for st, sz in zip(starts[sizes > 2], sizes[sizes > 2], strict=True):
        e = order[st:st + sz]
        rl, cl = r_loc[e], c_loc[e]
        nrow, ncol = int(rl.max()) + 1, int(cl.max()) + 1
        if nrow * ncol > DENSE_COMPONENT_MAX:
            if log_mode:
                raise ValueError(
                    f"the sparse route cannot solve a connected component of {nrow} x {ncol} "
                    f"tracks whose costs (d/c)^p underflow a double (below "
                    f"exp({_EXP_SAFE:g})): use method='dense' or a smaller order p")
            hit = _sparse_lsap(rl, cl, U[e], nrow, ncol)
            kept[e] = hit
            n_matched += int(hit.sum())
            parts_lin.append(U[e][hit])
            continue
        C = np.ones((nrow, ncol))
        C[rl, cl] = U[e]
        if log_mode:
            G = np.zeros((nrow, ncol))  # ln 1 for the pairs at the cut-off
            G[rl, cl] = L[e]
            parts_log.append(np.array([_log_assignment_sum(G.T if nrow > ncol else G)]))
        rr, cc = _linear_sum_assignment(C)
        n_matched += rr.size
        parts_lin.append(C[rr, cc])
        # which pairs the assignment uses below the cut-off
        hit = np.zeros((nrow, ncol), dtype=bool)
        hit[rr, cc] = C[rr, cc] < 1.0
        kept[e] = hit[rl, cl]
    total = float(np.concatenate(parts_lin).sum())
    log_total = float(np.logaddexp.reduce(np.concatenate(parts_log))) if log_mode else math.nan
    return total, log_total, n_matched, kept


def _windows(K: int, N: int, r: float):
    """Per scan ``k``: the first scan ``lo`` of its window of ``N`` and the window's log-weights."""
    for k in range(K):
        lo = max(0, k - N + 1)
        # ln w_t = r ln(t - k + N) with 1-based t, k: the newest scan has weight N^r.
        yield k, lo, r * np.log((np.arange(lo, k + 1) - k + N).astype(np.float64))


def _ospa2_sparse(X, ex, Y, ey, c: float, p: float, N: int, r: float, base: str):
    """:func:`ospa2` by the sparse route: the same three arrays as the dense route."""
    K = X.shape[0]
    n_y = Y.shape[1]
    # per scan, the pairs that both exist and lie closer than c, keyed by i * n_y + j
    keys, s_at, g_at = [], [], []
    for t in range(K):
        xi, yj = np.flatnonzero(ex[t]), np.flatnonzero(ey[t])
        i, j, s, g = _close_pairs(X[t, xi], Y[t, yj], c, p, base)
        keys.append(xi[i] * n_y + yj[j])  # sorted: xi and yj are increasing
        s_at.append(s)
        g_at.append(g)
    value = np.empty(K)
    loc = np.empty(K)
    card = np.empty(K)
    for k, lo, lw in _windows(K, N, r):
        m = int(ex[lo : k + 1].any(axis=0).sum())
        n = int(ey[lo : k + 1].any(axis=0).sum())
        small, big = min(m, n), max(m, n)
        if big == 0:
            value[k] = loc[k] = card[k] = 0.0
            continue
        # a pair of tracks can have a time-averaged distance below c only if at some scan of
        # the window both exist closer than c: only those pairs are averaged (7.2)
        pk = np.unique(np.concatenate(keys[lo : k + 1]))
        I, J = pk // max(n_y, 1), pk % max(n_y, 1)
        W = k + 1 - lo
        s = np.ones((W, pk.size))
        g = np.zeros((W, pk.size))
        for t in range(lo, k + 1):
            pos = np.searchsorted(pk, keys[t])
            s[t - lo, pos] = s_at[t]
            g[t - lo, pos] = g_at[t]
        uw = ex[lo : k + 1][:, I] | ey[lo : k + 1][:, J]
        # the dense route's average (7.2), column by column
        lwb = np.where(uw, lw[:, None], -np.inf)
        lwb = lwb - lwb.max(axis=0, initial=-np.inf)
        with np.errstate(under="ignore"):
            w = np.exp(lwb)
            avg = (w * s).sum(axis=0) / w.sum(axis=0)
        A = _masked_logsumexp(lwb + g, uw) - _masked_logsumexp(lwb, uw)
        if base == "euclidean":
            with np.errstate(under="ignore"):
                U = avg**p
            L = p * A
        else:
            U, L = avg, A
        below = U < 1.0
        I, J, U, L = I[below], J[below], U[below], L[below]
        finite = L[np.isfinite(L)]
        log_mode = finite.size > 0 and finite.min() <= _EXP_SAFE
        total, log_total, n_matched, _ = _component_assignment(I, J, U, L, log_mode)
        # the rows of the smaller side left by every component's assignment go to columns
        # outside it, at the cut-off
        rest = small - n_matched
        if not log_mode:
            # d_p^(c) = c ((1/n) [min_pi sum (d/c)^p + (n - m)])^(1/p)   (spec 7.3)
            lsum = total + rest
            value[k] = min(c, c * ((lsum + (big - small)) / big) ** (1.0 / p))
            loc[k] = min(c, c * (lsum / big) ** (1.0 / p))
            card[k] = c * ((big - small) / big) ** (1.0 / p)
            continue
        log_loc = float(np.logaddexp(log_total, math.log(rest) if rest else -math.inf))
        log_card = math.log(big - small) if big > small else -math.inf
        log_all = float(np.logaddexp(log_loc, log_card))

        def scaled(log_sum, big=big):
            return min(c, c * math.exp((log_sum - math.log(big)) / p)) \
                if log_sum > -math.inf else 0.0

        value[k], loc[k], card[k] = scaled(log_all), scaled(log_loc), scaled(log_card)
    return OSPA2Result(value, loc, card)


def _gospa_sparse(A: np.ndarray, B: np.ndarray, c: float, p: float):
    """:func:`gospa`'s localisation sum (units of ``c^p``) and pairs by the sparse route."""
    i, j, u, _ = _close_pairs(A, B, c, 1.0, "euclidean")  # u = min(c, ||x - y||) / c < 1
    with np.errstate(under="ignore"):
        U = u**p
    _, _, _, kept = _component_assignment(i, j, U, np.zeros_like(U), False)
    return float(U[kept].sum()), int(kept.sum())

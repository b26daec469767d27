"""Multi-object performance metrics: OSPA and OSPA(2).

:func:`ospa` is the optimal sub-pattern assignment distance between two finite sets of points
(Schuhmacher, Vo & Vo 2008). :func:`ospa2` is OSPA(2), the OSPA distance between two sets of
*tracks* over a trailing time window (Beard, Vo & Vo 2018/2020), the metric of the paper's
tracking study (spec §7). :func:`tracks_to_array` turns a filter's labelled estimates into the
NaN-padded array :func:`ospa2` takes. :func:`track_coverage` tells, per true track, how much of
its life some estimate was near it: the diagnostic that shows a target lost for good, which a
mean OSPA(2) only averages in.

Track arrays have shape ``(n_scans, n_tracks, d)``: entry ``[k, f]`` is the state of track ``f``
at scan ``k``, all-NaN where the track does not exist.
"""

from __future__ import annotations

from collections.abc import Hashable, Mapping, Sequence
from typing import NamedTuple

import numpy as np

__all__ = ["OSPAResult", "OSPA2Result", "ospa", "ospa2", "tracks_to_array", "track_coverage"]


class OSPAResult(NamedTuple):
    """OSPA distance and its two components (all floats, in the units of the points)."""

    value: float
    localisation: float
    cardinality: float


class OSPA2Result(NamedTuple):
    """OSPA(2) per scan: arrays of shape ``(n_scans,)``."""

    value: np.ndarray
    localisation: np.ndarray
    cardinality: np.ndarray


# ---------------------------------------------------------------------------------- validation
def _check_cp(c, p) -> tuple[float, float]:
    try:
        c = float(c)
        p = float(p)
    except (TypeError, ValueError):
        raise TypeError(f"c and p must be real numbers, got c={c!r}, p={p!r}") from None
    if not np.isfinite(c) or c <= 0:
        raise ValueError(f"cut-off c must be a positive finite number, got {c}")
    if not np.isfinite(p) or p < 1:
        raise ValueError(f"order p must be a finite number >= 1, got {p}")
    return c, p


def _as_points(X, name: str) -> np.ndarray:
    try:
        a = np.asarray(X, dtype=np.float64)
    except (TypeError, ValueError):
        raise TypeError(f"{name} must be a numeric array of points") from None
    if a.ndim == 1 and a.size == 0:
        a = a.reshape(0, 0)
    if a.ndim != 2:
        raise ValueError(f"{name} must be 2-D with shape (n_points, d), got shape {a.shape}")
    if not np.isfinite(a).all():
        raise ValueError(f"{name} contains NaN or inf; every point must be finite")
    return a


def _ospa_from_matrix(D: np.ndarray, m: int, n: int, c: float, p: float) -> OSPAResult:
    """OSPA from an ``(m, n)`` matrix of cut-off base distances raised to the power ``p``."""
    if m == 0 and n == 0:
        return OSPAResult(0.0, 0.0, 0.0)
    big = max(m, n)
    if m and n:
        from scipy.optimize import linear_sum_assignment  # deferred: keeps the import light

        rows, cols = linear_sum_assignment(D)
        loc = float(D[rows, cols].sum())
    else:
        loc = 0.0
    card = c**p * abs(m - n)
    # d_p^(c)(X, Y) = ((1/n) [min_pi sum d^p + c^p (n - m)])^(1/p)   (spec 7.3)
    return OSPAResult(
        float(((loc + card) / big) ** (1.0 / p)),
        float((loc / big) ** (1.0 / p)),
        float((card / big) ** (1.0 / p)),
    )


# ---------------------------------------------------------------------------------- OSPA
def ospa(X, Y, c: float, p: float) -> OSPAResult:
    """OSPA distance between two finite sets of points.

    Parameters
    ----------
    X : array_like, shape (m, d)
        First set, one point per row (``m`` may be 0; an empty list is accepted).
    Y : array_like, shape (n, d)
        Second set.
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
        On non-finite points, mismatched dimensions, ``c <= 0`` or ``p < 1``.

    Notes
    -----
    With ``m <= n`` (swap otherwise) and ``d^(c)(x, y) = min(c, ||x - y||_2)``,

    ``d_p^(c)(X, Y) = ( (1/n) [ min_pi sum_i d^(c)(x_i, y_pi(i))^p + c^p (n - m) ] )^(1/p)``,

    ``0`` when both sets are empty. The assignment is solved with
    :func:`scipy.optimize.linear_sum_assignment`. OSPA is a metric on finite sets bounded by ``c``.

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
    """
    c, p = _check_cp(c, p)
    A = _as_points(X, "X")
    B = _as_points(Y, "Y")
    if A.shape[0] and B.shape[0] and A.shape[1] != B.shape[1]:
        raise ValueError(
            f"X and Y must have the same point dimension, got {A.shape[1]} and {B.shape[1]}"
        )
    if A.shape[0] > B.shape[0]:
        A, B = B, A
    m, n = A.shape[0], B.shape[0]
    if m and n:
        D = np.minimum(c, np.linalg.norm(A[:, None, :] - B[None, :, :], axis=-1)) ** p
    else:
        D = np.zeros((m, n))
    return _ospa_from_matrix(D, m, n, c, p)


# ---------------------------------------------------------------------------------- OSPA(2)
def _as_tracks(a, name: str) -> tuple[np.ndarray, np.ndarray]:
    try:
        arr = np.asarray(a, dtype=np.float64)
    except (TypeError, ValueError):
        raise TypeError(f"{name} must be a numeric array") from None
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

    Returns
    -------
    OSPA2Result
        ``value``, ``localisation``, ``cardinality``, each of shape ``(n_scans,)``.

    Raises
    ------
    ValueError
        On mismatched scan counts or dimensions, a partly-NaN state, ``c <= 0``, ``p < 1``,
        ``window < 1`` or an unknown ``base``.

    Notes
    -----
    Spec §7. With ``W_k = {max(1, k-N+1), ..., k}``, only tracks that exist somewhere in
    ``W_k`` take part. Per-scan base distance (7.1): ``d_t(f, g) = min(c, ||f(t) - g(t)||)`` if
    both exist, ``c`` if exactly one does; the time average (7.2) runs over the union of the two
    domains within the window with weights ``w_t``; the OSPA (7.3) over the two sets of tracks
    uses these averages as base distances (they are already ``<= c``). With ``window = 1`` this
    is OSPA at every scan. OSPA(2) is a metric on sets of tracks bounded by ``c``.

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
    """
    c, p = _check_cp(c, p)
    if isinstance(window, bool) or not isinstance(window, (int, np.integer)):
        raise TypeError(f"window must be an integer, got {type(window).__name__}")
    if window < 1:
        raise ValueError(f"window must be >= 1, got {window}")
    try:
        r = float(weight_power)
    except (TypeError, ValueError):
        raise TypeError(f"weight_power must be a real number, got {weight_power!r}") from None
    if not np.isfinite(r) or r < 0:
        raise ValueError(f"weight_power must be a finite number >= 0, got {weight_power}")
    if base not in ("euclidean", "lp"):
        raise ValueError(f"base must be 'euclidean' or 'lp', got {base!r}")
    X, ex, Y, ey = _as_track_pair(truth, estimates)
    K = X.shape[0]
    N = int(window)
    cp = c**p
    # Per-scan base distances between every truth and every estimate, shape (K, m, n).
    # Missing states are NaN, so the difference is NaN; replace by 0 and mask with existence.
    diff = np.nan_to_num(X[:, :, None, :] - Y[:, None, :, :])
    if base == "euclidean":
        step = np.minimum(c, np.linalg.norm(diff, axis=-1))
    else:
        step = np.minimum(cp, (np.abs(diff) ** p).sum(axis=-1))
        # "lp" works with d^p throughout; the one-exists penalty is c^p.
    penalty = c if base == "euclidean" else cp
    both = ex[:, :, None] & ey[:, None, :]
    one = ex[:, :, None] ^ ey[:, None, :]
    dt = np.where(both, step, 0.0) + np.where(one, penalty, 0.0)
    union = (both | one).astype(np.float64)

    value = np.empty(K)
    loc = np.empty(K)
    card = np.empty(K)
    for k in range(K):
        lo = max(0, k - N + 1)
        # w_t = (t - k + N)^r with 1-based t, k: the newest scan has weight N^r.
        wt = (np.arange(lo, k + 1) - k + N).astype(np.float64) ** r
        fx = ex[lo : k + 1].any(axis=0)
        fy = ey[lo : k + 1].any(axis=0)
        num = np.einsum("t,tmn->mn", wt, dt[lo : k + 1][:, fx][:, :, fy])
        den = np.einsum("t,tmn->mn", wt, union[lo : k + 1][:, fx][:, :, fy])
        m, n = int(fx.sum()), int(fy.sum())
        if m and n:
            avg = num / den  # den > 0: each track exists somewhere in the window (7.2)
            D = avg**p if base == "euclidean" else avg
        else:
            D = np.zeros((m, n))
        if m > n:
            D = D.T
            m, n = n, m
        res = _ospa_from_matrix(D, m, n, c, p)
        value[k], loc[k], card[k] = res
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
    order: dict[Hashable, int] = {}
    dim = None
    for scan in labelled_estimates:
        for lab, x in scan.items():
            v = np.asarray(x, dtype=np.float64).reshape(-1)
            if dim is None:
                dim = v.size
            elif v.size != dim:
                raise ValueError(
                    f"state of track {lab!r} has {v.size} components, expected {dim}"
                )
            order.setdefault(lab, len(order))
    dim = 0 if dim is None else dim
    idx = np.arange(dim) if dims is None else np.asarray(dims, dtype=np.int64).reshape(-1)
    if idx.size and (idx.min() < 0 or idx.max() >= max(dim, 1)) and dim:
        raise ValueError(f"dims {idx.tolist()} out of range for states of length {dim}")
    K = len(labelled_estimates)
    out = np.full((K, len(order), idx.size), np.nan)
    for k, scan in enumerate(labelled_estimates):
        for lab, x in scan.items():
            out[k, order[lab]] = np.asarray(x, dtype=np.float64).reshape(-1)[idx]
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
    try:
        radius = float(radius)
    except (TypeError, ValueError):
        raise TypeError(f"radius must be a real number, got {radius!r}") from None
    if not np.isfinite(radius) or radius <= 0:
        raise ValueError(f"radius must be a positive finite number, got {radius}")
    if isinstance(settle, bool) or not isinstance(settle, (int, np.integer)):
        raise TypeError(f"settle must be an integer, got {type(settle).__name__}")
    if settle < 0:
        raise ValueError(f"settle must be >= 0, got {settle}")
    # distance of every truth to every estimate per scan, (K, m, n); NaN where either is absent,
    # and NaN <= radius is False
    dist = np.linalg.norm(X[:, :, None, :] - Y[:, None, :, :], axis=-1)
    covered = (dist <= radius).any(axis=2)
    counted = x_exists & (np.cumsum(x_exists, axis=0) > settle)  # past each life's first scans
    n = counted.sum(axis=0)
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(n > 0, (covered & counted).sum(axis=0) / n, np.nan)
